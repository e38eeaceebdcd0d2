//! The lane operations of one x86 vector width behind one trait, [`Wide`], so that the
//! maximum mipmap's step is written once for AVX2's eight lanes ([`Ymm`]) and
//! AVX-512's sixteen ([`Zmm`]).
//!
//! Every operation is `#[inline(always)]` and has no `#[target_feature]` of its own: it
//! is only ever inlined into a function that enables its width's instructions
//! (`run_avx2`, `run_avx512` in the parent module), which is also the only place the
//! zero-sized width tokens are made. Comparisons are false on NaN, as Rust's.

use core::arch::x86_64::*;

/// The operations of one vector width on `N` lanes of `f32` ([`Wide::F`]), `u32`
/// ([`Wide::I`], compared as `i32` by [`Wide::igt`]) and lane masks ([`Wide::M`]).
pub(super) trait Wide<const N: usize>: Copy {
    type F: Copy;
    type I: Copy;
    type M: Copy;
    fn fld(self, a: &[f32; N]) -> Self::F;
    fn fst(self, a: &mut [f32; N], v: Self::F);
    fn fsplat(self, x: f32) -> Self::F;
    fn fadd(self, a: Self::F, b: Self::F) -> Self::F;
    fn fsub(self, a: Self::F, b: Self::F) -> Self::F;
    fn fmul(self, a: Self::F, b: Self::F) -> Self::F;
    fn fdiv(self, a: Self::F, b: Self::F) -> Self::F;
    fn flt(self, a: Self::F, b: Self::F) -> Self::M;
    fn fgt(self, a: Self::F, b: Self::F) -> Self::M;
    fn fle(self, a: Self::F, b: Self::F) -> Self::M;
    fn feq(self, a: Self::F, b: Self::F) -> Self::M;
    /// `if m { a } else { b }` per lane.
    fn fpick(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F;
    /// `|a|`.
    fn fabs(self, a: Self::F) -> Self::F;
    /// Truncation towards zero.
    fn ftrunc(self, a: Self::F) -> Self::I;
    /// The bits of `a`.
    fn fbits(self, a: Self::F) -> Self::I;
    fn ild(self, a: &[u32; N]) -> Self::I;
    fn ist(self, a: &mut [u32; N], v: Self::I);
    fn isplat(self, x: u32) -> Self::I;
    fn iadd(self, a: Self::I, b: Self::I) -> Self::I;
    fn isub(self, a: Self::I, b: Self::I) -> Self::I;
    fn imul(self, a: Self::I, b: Self::I) -> Self::I;
    fn iand(self, a: Self::I, b: Self::I) -> Self::I;
    /// `a << n` and `a >> n` per lane (logical).
    fn ishl(self, a: Self::I, n: Self::I) -> Self::I;
    fn ishr(self, a: Self::I, n: Self::I) -> Self::I;
    /// Unsigned minimum and maximum.
    fn imin(self, a: Self::I, b: Self::I) -> Self::I;
    fn imax(self, a: Self::I, b: Self::I) -> Self::I;
    /// `a > b` as `i32`.
    fn igt(self, a: Self::I, b: Self::I) -> Self::M;
    fn ieq(self, a: Self::I, b: Self::I) -> Self::M;
    fn ipick(self, m: Self::M, a: Self::I, b: Self::I) -> Self::I;
    /// The value as `f32` (of `i32`).
    fn ifloat(self, a: Self::I) -> Self::F;
    /// A mask from lanes holding `0` or `u32::MAX`, and back.
    fn mld(self, a: &[u32; N]) -> Self::M;
    fn mst(self, a: &mut [u32; N], m: Self::M);
    fn mand(self, a: Self::M, b: Self::M) -> Self::M;
    fn mor(self, a: Self::M, b: Self::M) -> Self::M;
    /// `a && !b`.
    fn mandnot(self, a: Self::M, b: Self::M) -> Self::M;
    fn mpick(self, m: Self::M, a: Self::M, b: Self::M) -> Self::M;
    /// Bit `l` set for each lane `l` set.
    fn mbits(self, m: Self::M) -> u32;
    /// The mask of the lanes whose bit is set.
    fn mfrom(self, bits: u32) -> Self::M;
    /// `base[at]` per lane.
    ///
    /// # Safety
    /// Every index is inside the allocation `base` points into.
    unsafe fn fgather(self, base: *const f32, at: Self::I) -> Self::F;
    /// `table[at]` per lane, `at` below 16 (a permutation across the register, not
    /// a gather).
    fn itable(self, table: &[u32; 16], at: Self::I) -> Self::I;

    /// `Real::min(a, b)`: `b < a ? b : a`.
    #[inline(always)]
    fn rmin(self, a: Self::F, b: Self::F) -> Self::F {
        self.fpick(self.flt(b, a), b, a)
    }

    /// `Real::max(a, b)`: `b > a ? b : a`.
    #[inline(always)]
    fn rmax(self, a: Self::F, b: Self::F) -> Self::F {
        self.fpick(self.fgt(b, a), b, a)
    }

    /// Whether some lane of `m` is set.
    #[inline(always)]
    fn many(self, m: Self::M) -> bool {
        self.mbits(m) != 0
    }
}

/// AVX2's eight lanes; made only where AVX2 is enabled.
#[derive(Clone, Copy)]
pub(super) struct Ymm(pub(super) ());

/// AVX-512F's sixteen lanes; made only where AVX-512F is enabled.
#[derive(Clone, Copy)]
pub(super) struct Zmm(pub(super) ());

// SAFETY (every `unsafe` block below): the token exists only inside a function that
// enables the width's instructions (module docs), and the loads and stores read or
// write exactly one whole lane array.

impl Wide<8> for Ymm {
    type F = __m256;
    type I = __m256i;
    type M = __m256i;
    #[inline(always)]
    fn fld(self, a: &[f32; 8]) -> __m256 {
        unsafe { _mm256_loadu_ps(a.as_ptr()) }
    }
    #[inline(always)]
    fn fst(self, a: &mut [f32; 8], v: __m256) {
        unsafe { _mm256_storeu_ps(a.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn fsplat(self, x: f32) -> __m256 {
        unsafe { _mm256_set1_ps(x) }
    }
    #[inline(always)]
    fn fadd(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_add_ps(a, b) }
    }
    #[inline(always)]
    fn fsub(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_sub_ps(a, b) }
    }
    #[inline(always)]
    fn fmul(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_mul_ps(a, b) }
    }
    #[inline(always)]
    fn fdiv(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_div_ps(a, b) }
    }
    #[inline(always)]
    fn flt(self, a: __m256, b: __m256) -> __m256i {
        unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(a, b)) }
    }
    #[inline(always)]
    fn fgt(self, a: __m256, b: __m256) -> __m256i {
        unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(a, b)) }
    }
    #[inline(always)]
    fn fle(self, a: __m256, b: __m256) -> __m256i {
        unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(a, b)) }
    }
    #[inline(always)]
    fn feq(self, a: __m256, b: __m256) -> __m256i {
        unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_EQ_OQ>(a, b)) }
    }
    #[inline(always)]
    fn fpick(self, m: __m256i, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_blendv_ps(b, a, _mm256_castsi256_ps(m)) }
    }
    #[inline(always)]
    fn fabs(self, a: __m256) -> __m256 {
        unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), a) }
    }
    #[inline(always)]
    fn ftrunc(self, a: __m256) -> __m256i {
        unsafe { _mm256_cvttps_epi32(a) }
    }
    #[inline(always)]
    fn fbits(self, a: __m256) -> __m256i {
        unsafe { _mm256_castps_si256(a) }
    }
    #[inline(always)]
    fn ild(self, a: &[u32; 8]) -> __m256i {
        unsafe { _mm256_loadu_si256(a.as_ptr().cast()) }
    }
    #[inline(always)]
    fn ist(self, a: &mut [u32; 8], v: __m256i) {
        unsafe { _mm256_storeu_si256(a.as_mut_ptr().cast(), v) }
    }
    #[inline(always)]
    fn isplat(self, x: u32) -> __m256i {
        unsafe { _mm256_set1_epi32(x as i32) }
    }
    #[inline(always)]
    fn iadd(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_add_epi32(a, b) }
    }
    #[inline(always)]
    fn isub(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_sub_epi32(a, b) }
    }
    #[inline(always)]
    fn imul(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_mullo_epi32(a, b) }
    }
    #[inline(always)]
    fn iand(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_and_si256(a, b) }
    }
    #[inline(always)]
    fn ishl(self, a: __m256i, n: __m256i) -> __m256i {
        unsafe { _mm256_sllv_epi32(a, n) }
    }
    #[inline(always)]
    fn ishr(self, a: __m256i, n: __m256i) -> __m256i {
        unsafe { _mm256_srlv_epi32(a, n) }
    }
    #[inline(always)]
    fn imin(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_min_epu32(a, b) }
    }
    #[inline(always)]
    fn imax(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_max_epu32(a, b) }
    }
    #[inline(always)]
    fn igt(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_cmpgt_epi32(a, b) }
    }
    #[inline(always)]
    fn ieq(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_cmpeq_epi32(a, b) }
    }
    #[inline(always)]
    fn ipick(self, m: __m256i, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_blendv_epi8(b, a, m) }
    }
    #[inline(always)]
    fn ifloat(self, a: __m256i) -> __m256 {
        unsafe { _mm256_cvtepi32_ps(a) }
    }
    #[inline(always)]
    fn mld(self, a: &[u32; 8]) -> __m256i {
        self.ild(a)
    }
    #[inline(always)]
    fn mst(self, a: &mut [u32; 8], m: __m256i) {
        self.ist(a, m)
    }
    #[inline(always)]
    fn mand(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_and_si256(a, b) }
    }
    #[inline(always)]
    fn mor(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_or_si256(a, b) }
    }
    #[inline(always)]
    fn mandnot(self, a: __m256i, b: __m256i) -> __m256i {
        unsafe { _mm256_andnot_si256(b, a) }
    }
    #[inline(always)]
    fn mpick(self, m: __m256i, a: __m256i, b: __m256i) -> __m256i {
        self.ipick(m, a, b)
    }
    #[inline(always)]
    fn mbits(self, m: __m256i) -> u32 {
        unsafe { _mm256_movemask_ps(_mm256_castsi256_ps(m)) as u32 }
    }
    #[inline(always)]
    fn mfrom(self, bits: u32) -> __m256i {
        let bit = unsafe { _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128) };
        self.ieq(self.iand(self.isplat(bits), bit), bit)
    }
    #[inline(always)]
    unsafe fn fgather(self, base: *const f32, at: __m256i) -> __m256 {
        unsafe { _mm256_i32gather_ps::<4>(base, at) }
    }
    #[inline(always)]
    fn itable(self, table: &[u32; 16], at: __m256i) -> __m256i {
        // Each half of the table permuted by the low three bits, then the half chosen.
        let (low, high) = unsafe {
            let low = _mm256_loadu_si256(table.as_ptr().cast());
            let high = _mm256_loadu_si256(table[8..].as_ptr().cast());
            (
                _mm256_permutevar8x32_epi32(low, at),
                _mm256_permutevar8x32_epi32(high, at),
            )
        };
        self.ipick(self.igt(at, self.isplat(7)), high, low)
    }
}

impl Wide<16> for Zmm {
    type F = __m512;
    type I = __m512i;
    type M = __mmask16;
    #[inline(always)]
    fn fld(self, a: &[f32; 16]) -> __m512 {
        unsafe { _mm512_loadu_ps(a.as_ptr()) }
    }
    #[inline(always)]
    fn fst(self, a: &mut [f32; 16], v: __m512) {
        unsafe { _mm512_storeu_ps(a.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn fsplat(self, x: f32) -> __m512 {
        unsafe { _mm512_set1_ps(x) }
    }
    #[inline(always)]
    fn fadd(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_add_ps(a, b) }
    }
    #[inline(always)]
    fn fsub(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_sub_ps(a, b) }
    }
    #[inline(always)]
    fn fmul(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_mul_ps(a, b) }
    }
    #[inline(always)]
    fn fdiv(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_div_ps(a, b) }
    }
    #[inline(always)]
    fn flt(self, a: __m512, b: __m512) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_LT_OQ>(a, b) }
    }
    #[inline(always)]
    fn fgt(self, a: __m512, b: __m512) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(a, b) }
    }
    #[inline(always)]
    fn fle(self, a: __m512, b: __m512) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(a, b) }
    }
    #[inline(always)]
    fn feq(self, a: __m512, b: __m512) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(a, b) }
    }
    #[inline(always)]
    fn fpick(self, m: __mmask16, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_mask_blend_ps(m, b, a) }
    }
    #[inline(always)]
    fn fabs(self, a: __m512) -> __m512 {
        unsafe { _mm512_abs_ps(a) }
    }
    #[inline(always)]
    fn ftrunc(self, a: __m512) -> __m512i {
        unsafe { _mm512_cvttps_epi32(a) }
    }
    #[inline(always)]
    fn fbits(self, a: __m512) -> __m512i {
        unsafe { _mm512_castps_si512(a) }
    }
    #[inline(always)]
    fn ild(self, a: &[u32; 16]) -> __m512i {
        unsafe { _mm512_loadu_si512(a.as_ptr().cast()) }
    }
    #[inline(always)]
    fn ist(self, a: &mut [u32; 16], v: __m512i) {
        unsafe { _mm512_storeu_si512(a.as_mut_ptr().cast(), v) }
    }
    #[inline(always)]
    fn isplat(self, x: u32) -> __m512i {
        unsafe { _mm512_set1_epi32(x as i32) }
    }
    #[inline(always)]
    fn iadd(self, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_add_epi32(a, b) }
    }
    #[inline(always)]
    fn isub(self, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_sub_epi32(a, b) }
    }
    #[inline(always)]
    fn imul(self, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_mullo_epi32(a, b) }
    }
    #[inline(always)]
    fn iand(self, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_and_si512(a, b) }
    }
    #[inline(always)]
    fn ishl(self, a: __m512i, n: __m512i) -> __m512i {
        unsafe { _mm512_sllv_epi32(a, n) }
    }
    #[inline(always)]
    fn ishr(self, a: __m512i, n: __m512i) -> __m512i {
        unsafe { _mm512_srlv_epi32(a, n) }
    }
    #[inline(always)]
    fn imin(self, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_min_epu32(a, b) }
    }
    #[inline(always)]
    fn imax(self, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_max_epu32(a, b) }
    }
    #[inline(always)]
    fn igt(self, a: __m512i, b: __m512i) -> __mmask16 {
        unsafe { _mm512_cmpgt_epi32_mask(a, b) }
    }
    #[inline(always)]
    fn ieq(self, a: __m512i, b: __m512i) -> __mmask16 {
        unsafe { _mm512_cmpeq_epi32_mask(a, b) }
    }
    #[inline(always)]
    fn ipick(self, m: __mmask16, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_mask_blend_epi32(m, b, a) }
    }
    #[inline(always)]
    fn ifloat(self, a: __m512i) -> __m512 {
        unsafe { _mm512_cvtepi32_ps(a) }
    }
    #[inline(always)]
    fn mld(self, a: &[u32; 16]) -> __mmask16 {
        let v = self.ild(a);
        unsafe { _mm512_test_epi32_mask(v, v) }
    }
    #[inline(always)]
    fn mst(self, a: &mut [u32; 16], m: __mmask16) {
        let set = unsafe { _mm512_maskz_mov_epi32(m, _mm512_set1_epi32(-1)) };
        self.ist(a, set)
    }
    #[inline(always)]
    fn mand(self, a: __mmask16, b: __mmask16) -> __mmask16 {
        a & b
    }
    #[inline(always)]
    fn mor(self, a: __mmask16, b: __mmask16) -> __mmask16 {
        a | b
    }
    #[inline(always)]
    fn mandnot(self, a: __mmask16, b: __mmask16) -> __mmask16 {
        a & !b
    }
    #[inline(always)]
    fn mpick(self, m: __mmask16, a: __mmask16, b: __mmask16) -> __mmask16 {
        (m & a) | (!m & b)
    }
    #[inline(always)]
    fn mbits(self, m: __mmask16) -> u32 {
        m as u32
    }
    #[inline(always)]
    fn mfrom(self, bits: u32) -> __mmask16 {
        bits as __mmask16
    }
    #[inline(always)]
    unsafe fn fgather(self, base: *const f32, at: __m512i) -> __m512 {
        unsafe { _mm512_i32gather_ps::<4>(at, base) }
    }
    #[inline(always)]
    fn itable(self, table: &[u32; 16], at: __m512i) -> __m512i {
        unsafe { _mm512_permutexvar_epi32(at, _mm512_loadu_si512(table.as_ptr().cast())) }
    }
}
