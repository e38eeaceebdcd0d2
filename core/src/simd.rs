//! What the marches may assume of the CPU's vector instructions. The core is `no_std`
//! and cannot ask the CPU (run-time detection needs `std`): the std-side crates detect
//! and hand the core a token; a march given none takes its portable path.

/// Proof that the running CPU executes AVX2 instructions: what the laned marches
/// ([`crate::maxmip::trace_lanes`]) need to take their SIMD path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx2(());

impl Avx2 {
    /// The token, on the caller's word.
    ///
    /// # Safety
    /// The CPU running the program supports AVX2 (with `std`:
    /// `is_x86_feature_detected!("avx2")`).
    #[allow(unsafe_code)]
    pub unsafe fn new_unchecked() -> Avx2 {
        Avx2(())
    }
}
