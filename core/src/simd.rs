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
    /// The CPU running the program supports AVX2 (with `std`, [`detect_avx2!`](crate::detect_avx2)
    /// makes the token after checking).
    #[allow(unsafe_code)]
    pub unsafe fn new_unchecked() -> Avx2 {
        Avx2(())
    }
}

/// The [`Avx2`] token when the running CPU has AVX2, else `None`: run-time detection
/// for the std-side crates (it expands to `std::is_x86_feature_detected!` where it is
/// used; the core itself has no `std`).
#[macro_export]
macro_rules! detect_avx2 {
    () => {{
        #[cfg(target_arch = "x86_64")]
        let avx2 = if ::std::is_x86_feature_detected!("avx2") {
            // SAFETY: just detected.
            Some(unsafe { $crate::simd::Avx2::new_unchecked() })
        } else {
            None
        };
        #[cfg(not(target_arch = "x86_64"))]
        let avx2: Option<$crate::simd::Avx2> = None;
        avx2
    }};
}
