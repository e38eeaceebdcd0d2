//! The first pass of a batch over its rays, two rays a 512-bit vector: [`Near::sight`].
//!
//! A ray laid out as the C API's `hf_ray` (origin, direction, `t_min`, `t_max`: eight
//! `f32`) fills half a vector, so every test of [`Query::from_arrays`] and
//! [`Near::holds`] is a compare of each lane against that lane's bound, and a ray's
//! answer is the bits of its eight lanes in the compare masks. The compares are the
//! scalar tests' on the same values (`lo − o` and `o − hi` rounded alike), so a ray is
//! plain here exactly when [`Near::holds`] says so, and one that [`Query::from_arrays`]
//! refuses is never passed as valid.
#![allow(unsafe_code)]

use super::Near;
use crate::simd::Avx512;

/// What [`Near::sight`] finds of a run of at most 64 rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sighted {
    /// Whether every ray is valid ([`crate::Query::from_arrays`] accepts it).
    pub valid: bool,
    /// Whether every ray needs no conditioning ([`Near::holds`]); meaningful when
    /// `valid`.
    pub plain: bool,
    /// Bit `k` set when ray `k` leaves the eye (its origin equals it, as `f32`
    /// values compare).
    pub at_eye: u64,
}

impl Near<f32> {
    /// Checks the rays `rays` (at most 64, each `[origin, dir, t_min, t_max]`, the C
    /// API's `hf_ray`) as [`crate::Query::from_arrays`] and [`Near::holds`] do, and
    /// finds those that leave `eye`, two rays a vector. Panics with more than 64 rays.
    pub fn sight(&self, rays: &[[f32; 8]], eye: [f32; 3], _avx512: Avx512) -> Sighted {
        assert!(rays.len() <= 64, "at most 64 rays a run");
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the token proves the CPU executes AVX-512F.
        unsafe {
            avx512::sight(self, rays, eye)
        }
        // (A token made on another CPU, on a caller's false word: the same tests, one
        // ray at a time.)
        #[cfg(not(target_arch = "x86_64"))]
        {
            let mut seen = Sighted {
                valid: true,
                plain: true,
                at_eye: 0,
            };
            for (k, r) in rays.iter().enumerate() {
                let (o, d) = ([r[0], r[1], r[2]], [r[3], r[4], r[5]]);
                match crate::Query::from_arrays(o, d, r[6], r[7]) {
                    Ok(q) => seen.plain &= self.holds(&q),
                    Err(_) => seen.valid = false,
                }
                seen.at_eye |= u64::from(o == eye) << k;
            }
            seen
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::*;
    use core::arch::x86_64::*;

    /// Lanes of one ray (of the two a vector holds) by what they hold.
    const ORIGIN: u16 = 0b0000_0111;
    const DIR: u16 = 0b0011_1000;
    const T_MIN: u16 = 0b0100_0000;
    const T_MAX: u16 = 0b1000_0000;

    /// Both rays' lanes of a one-ray lane set.
    const fn both(m: u16) -> u16 {
        m | m << 8
    }

    /// Whether each of the two rays has every lane of `set` in `m` (bit 0: the first
    /// ray, bit 1: the second).
    #[inline(always)]
    fn all(m: u16, set: u16) -> u32 {
        u32::from(m & set == set) | u32::from(m >> 8 & set == set) << 1
    }

    /// Whether each of the two rays has some lane of `set` in `m`.
    #[inline(always)]
    fn any(m: u16, set: u16) -> u32 {
        u32::from(m & set != 0) | u32::from(m >> 8 & set != 0) << 1
    }

    /// [`Near::sight`], the AVX-512 body.
    #[target_feature(enable = "avx512f")]
    pub(super) unsafe fn sight(near: &Near<f32>, rays: &[[f32; 8]], eye: [f32; 3]) -> Sighted {
        // A bound of the origin lanes, for both rays (a ray's lanes are origin (3),
        // direction (3), t_min, t_max; the other lanes' bounds are unused).
        let per_ray = |o: [f32; 3]| {
            let half = [o[0], o[1], o[2], 0.0, 0.0, 0.0, 0.0, 0.0];
            let mut v = [0.0f32; 16];
            v[..8].copy_from_slice(&half);
            v[8..].copy_from_slice(&half);
            // SAFETY: sixteen `f32` are one unaligned 512-bit load.
            unsafe { _mm512_loadu_ps(v.as_ptr()) }
        };
        let inf = _mm512_set1_ps(f32::INFINITY);
        let zero = _mm512_setzero_ps();
        let lo = per_ray(near.lo);
        let hi = per_ray(near.hi);
        let far = _mm512_set1_ps(near.far);
        let small = _mm512_set1_ps(near.small);
        let big = _mm512_set1_ps(near.big);
        let at = per_ray(eye);
        // Lane 6 (t_min) compared with lane 7 (t_max) of the same ray.
        let t_max_at_t_min = _mm512_set_epi32(15, 15, 13, 12, 11, 10, 9, 8, 7, 7, 5, 4, 3, 2, 1, 0);
        let (mut valid, mut plain, mut at_eye) = (true, true, 0u64);
        for (k, pair) in rays.chunks(2).enumerate() {
            let v = match pair {
                // SAFETY: two rays, sixteen `f32`, one unaligned 512-bit load.
                [_, _] => unsafe { _mm512_loadu_ps(pair.as_ptr().cast::<f32>()) },
                // The last odd ray twice.
                _ => {
                    let mut two = [0.0f32; 16];
                    two[..8].copy_from_slice(&pair[0]);
                    two[8..].copy_from_slice(&pair[0]);
                    // SAFETY: sixteen `f32`, one unaligned 512-bit load.
                    unsafe { _mm512_loadu_ps(two.as_ptr()) }
                }
            };
            let a = _mm512_abs_ps(v);
            // Finite origin, direction and t_min; t_max finite or +∞.
            let finite = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(a, inf);
            let up = _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(v, inf);
            let ranged = finite | up & both(T_MAX);
            // A direction not all zeros; t_min no more than t_max.
            let zero_dir = _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(v, zero);
            let t_max = _mm512_permutexvar_ps(t_max_at_t_min, v);
            let reversed = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(v, t_max);
            let ok = all(ranged, 0xff) & !all(zero_dir, DIR) & !any(reversed, T_MIN);
            // Plain: the largest direction magnitude in [small, big] (one lane at
            // least `small`, all at most `big`); the origin within `far` of the box.
            let at_least = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(a, small);
            let at_most = _mm512_cmp_ps_mask::<_CMP_LE_OQ>(a, big);
            let below = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(_mm512_sub_ps(lo, v), far);
            let above = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(_mm512_sub_ps(v, hi), far);
            let held = any(at_least, DIR) & all(at_most, DIR) & !any(below | above, ORIGIN);
            let eye_bits = all(_mm512_cmp_ps_mask::<_CMP_EQ_OQ>(v, at), ORIGIN);
            let rays_here = if pair.len() == 2 { 0b11 } else { 0b01 };
            valid &= (ok & rays_here) == rays_here;
            plain &= (held & rays_here) == rays_here;
            at_eye |= u64::from(eye_bits & rays_here) << (2 * k);
        }
        Sighted {
            valid,
            plain,
            at_eye,
        }
    }
}
