//! What the marches may assume of the CPU's vector instructions. The core is `no_std`
//! and cannot ask the CPU (run-time detection needs `std`): the std-side crates detect
//! and hand the core a token; a march given none takes its portable path.

/// Proof that the running CPU executes AVX2 instructions: what the laned marches
/// ([`crate::maxmip::trace_lanes`]) need to take their SIMD path; it also says whether
/// the CPU executes AVX-512 ([`Avx2::avx512`]), which the laned DDA
/// ([`crate::dda::trace_skipping_lanes`]) needs and the maximum mipmap's lanes use
/// (sixteen a set instead of eight).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx2 {
    avx512: bool,
}

/// Proof that the running CPU executes the AVX-512 foundation instructions (AVX-512F),
/// made from an [`Avx2`] token that knows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx512(());

impl Avx2 {
    /// The token, on the caller's word.
    ///
    /// # Safety
    /// The CPU running the program supports AVX2 (with `std`, [`detect_avx2!`](crate::detect_avx2)
    /// makes the token after checking).
    #[allow(unsafe_code)]
    pub unsafe fn new_unchecked() -> Avx2 {
        Avx2 { avx512: false }
    }

    /// This token, also proving AVX-512F, on the caller's word.
    ///
    /// # Safety
    /// The CPU running the program supports AVX-512F.
    #[allow(unsafe_code)]
    pub unsafe fn with_avx512_unchecked(self) -> Avx2 {
        Avx2 { avx512: true }
    }

    /// The [`Avx512`] token, when this one knows the CPU has AVX-512F.
    pub fn avx512(self) -> Option<Avx512> {
        self.avx512.then_some(Avx512(()))
    }

    /// This token without its AVX-512 proof: the AVX2 paths only (for comparing them).
    pub fn without_avx512(self) -> Avx2 {
        Avx2 { avx512: false }
    }
}

/// The [`Avx2`] token when the running CPU has AVX2 (knowing whether it also has
/// AVX-512F), else `None`: run-time detection for the std-side crates (it expands to
/// `std::is_x86_feature_detected!` where it is used; the core itself has no `std`).
#[macro_export]
macro_rules! detect_avx2 {
    () => {{
        #[cfg(target_arch = "x86_64")]
        let avx2 = if ::std::is_x86_feature_detected!("avx2") {
            // SAFETY: just detected.
            let avx2 = unsafe { $crate::simd::Avx2::new_unchecked() };
            Some(if ::std::is_x86_feature_detected!("avx512f") {
                // SAFETY: just detected.
                unsafe { avx2.with_avx512_unchecked() }
            } else {
                avx2
            })
        } else {
            None
        };
        #[cfg(not(target_arch = "x86_64"))]
        let avx2: Option<$crate::simd::Avx2> = None;
        avx2
    }};
}
