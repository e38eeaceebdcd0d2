//! A batch's aims sixteen rays at a time in AVX-512 lanes ([`Horizon::aims`]).
//!
//! A ray's aim is a square root and two divisions in `f64` (its horizontal length, its
//! pseudo-angle, its slope): about a tenth of a terrain-filled camera frame one ray at
//! a time. The rays are read sixteen at a time, field by field
//! ([`crate::dda::lanes::queries_by_field`]: plain loads and a transpose; gathers of
//! their fields waited on every cache line of the group), and widened to `f64` eight
//! lanes a vector. Each lane does the scalar [`Horizon::aim`]'s operations on the same
//! values in the same order (IEEE products, sums, square root and quotients, no fused
//! forms; the branches as blends of the same comparisons), so every aim is the scalar
//! one (`core/tests/horizon.rs`, `aims_in_lanes_are_the_scalar_aims`).
#![allow(unsafe_code)]

use super::{Aimed, Horizon};
use crate::ray::Query;
use crate::simd::Avx512;
use alloc::vec::Vec;

/// Rays a step of [`aims_in_lanes`] reads.
const LANES: usize = crate::dda::LANES;

/// The aims of `queries` appended to `out`, [`LANES`] at a time with the AVX-512 token
/// `simd` (those past the last whole group are left to the caller); returns how many
/// it aimed.
pub(super) fn aims_in_lanes(
    h: &Horizon,
    queries: &[Query<f32>],
    out: &mut Vec<Aimed>,
    simd: Avx512,
) -> usize {
    let _ = simd;
    #[cfg(target_arch = "x86_64")]
    {
        let groups = queries.chunks_exact(LANES);
        let n = queries.len() - groups.remainder().len();
        out.reserve(n);
        for group in groups {
            let group: &[Query<f32>; LANES] = group.try_into().expect("a whole group");
            // SAFETY: the token proves the CPU executes AVX-512F.
            unsafe { avx512::group(h, group, out) };
        }
        n
    }
    #[cfg(not(target_arch = "x86_64"))]
    0
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::*;
    use crate::horizon::Aim;
    use core::arch::x86_64::*;

    /// The aims of a group of queries pushed to `out`, eight lanes of `f64` at a time.
    #[target_feature(enable = "avx512f")]
    pub(super) fn group(h: &Horizon, queries: &[Query<f32>; LANES], out: &mut Vec<Aimed>) {
        let fields = crate::dda::lanes::queries_by_field(queries);
        for half in [false, true] {
            let mut ray = [_mm512_setzero_pd(); 6];
            for (wide, &field) in ray.iter_mut().zip(&fields) {
                let field = _mm512_castps_pd(field);
                let eight = if half {
                    _mm512_extractf64x4_pd::<1>(field)
                } else {
                    _mm512_castpd512_pd256(field)
                };
                *wide = _mm512_cvtps_pd(_mm256_castpd_ps(eight));
            }
            eight(h, [ray[0], ray[1], ray[2]], [ray[3], ray[4], ray[5]], out);
        }
    }

    /// The aims of eight rays (origins `o` and directions `d`, lane by lane) pushed to
    /// `out`: [`Horizon::aimed`]'s, lane by lane.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn eight(h: &Horizon, o: [__m512d; 3], d: [__m512d; 3], out: &mut Vec<Aimed>) {
        let zero = _mm512_setzero_pd();
        let mut mine = 0xff;
        for (o, eye) in o.into_iter().zip(h.eye) {
            mine &= _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(o, _mm512_set1_pd(eye));
        }
        let rho = _mm512_sqrt_pd(_mm512_add_pd(
            _mm512_mul_pd(d[0], d[0]),
            _mm512_mul_pd(d[1], d[1]),
        ));
        let vertical = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(rho, zero);
        // `pseudo_angle` of the direction in the group's frame.
        let (ax, ay) = (_mm512_set1_pd(h.axis[0]), _mm512_set1_pd(h.axis[1]));
        let x = _mm512_add_pd(_mm512_mul_pd(d[0], ax), _mm512_mul_pd(d[1], ay));
        let y = _mm512_sub_pd(_mm512_mul_pd(d[1], ax), _mm512_mul_pd(d[0], ay));
        let r = _mm512_div_pd(y, _mm512_add_pd(_mm512_abs_pd(x), _mm512_abs_pd(y)));
        let ahead = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(x, zero);
        let left = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(y, zero);
        let behind = _mm512_mask_blend_pd(
            left,
            _mm512_sub_pd(_mm512_set1_pd(-2.0), r),
            _mm512_sub_pd(_mm512_set1_pd(2.0), r),
        );
        let a = _mm512_mask_blend_pd(ahead, behind, r);
        let b = _mm512_mul_pd(
            _mm512_sub_pd(a, _mm512_set1_pd(h.angle0)),
            _mm512_set1_pd(h.per_angle),
        );
        let inside = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(b, zero)
            & _mm512_cmp_pd_mask::<_CMP_LT_OQ>(b, _mm512_set1_pd(h.bins as f64 + 1.0));
        let aimed = mine & !vertical & inside;
        // `(b as usize).min(bins − 1)`, where `b` is in `[0, bins + 1)`.
        let last = u32::try_from(h.bins - 1).unwrap_or(u32::MAX);
        let wedge = _mm256_min_epu32(_mm512_cvttpd_epu32(b), _mm256_set1_epi32(last as i32));
        let m = _mm512_div_pd(d[2], rho);
        let (mut wedges, mut ms, mut rhos) = ([0u32; 8], [0f64; 8], [0f64; 8]);
        // SAFETY: eight lanes into arrays of eight.
        unsafe {
            _mm256_storeu_si256(wedges.as_mut_ptr().cast(), wedge);
            _mm512_storeu_pd(ms.as_mut_ptr(), m);
            _mm512_storeu_pd(rhos.as_mut_ptr(), rho);
        }
        for l in 0..8 {
            let aim = Aim {
                wedge: wedges[l],
                m: ms[l],
                rho: rhos[l],
            };
            out.push(Aimed((aimed >> l & 1 != 0).then_some(aim)));
        }
    }
}
