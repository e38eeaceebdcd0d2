//! docs/DESIGN.md's judge, shared by the report, the tests and (mirrored in C) the fuzz
//! targets: when an answer is **wrong** against the `f64` oracle, and when a ray is
//! **ambiguous**, i.e. its exact answer is not resolved by what `f32` can represent.
//!
//! A ray is ambiguous when moving its origin by the `f32` resolution δ of the ray
//! ([`resolution`]) along any axis, either way, changes the oracle's answer by more than
//! the answer's own sensitivity to that move ([`agree`]). The measure is symmetric: a
//! near-touch before the hit (lowered, the ray hits there), a ridge the hit only clips
//! (lifted, the hit is gone), a touch exactly at a sample, a side entry at the edge's
//! height and a ray that skims the box's side all change the answer; and δ is scaled by
//! the coordinates the ray involves (its origin's distance included), so the threshold
//! is what `f32` resolves there rather than a fraction of the largest height. Moving
//! the origin sideways turns the surface's slope into a change of clearance, which is
//! how `f32`'s rounding of the crossing coordinates acts on it.

use crate::dda;
use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Query, Trace};
use crate::surface::Surface;

/// The "wrong" distance, texels: a hit farther than this (or than [`F32_ULPS`] ulps of
/// the coordinates, for `f32` answers) from the oracle's is wrong.
pub const WRONG: f64 = 1e-3;

/// Units of `f32`'s epsilon, times the coordinates' magnitude, of the wrong-ray
/// tolerance: a few roundings of `o + t · d` and of the crossing parameters
/// `(X − o) / d`, each half an ulp, with room.
pub const F32_ULPS: f64 = 8.0;

/// Largest magnitude of a point's coordinates.
fn inf_norm(v: [f64; 3]) -> f64 {
    v.iter().fold(0f64, |m, x| m.max(x.abs()))
}

/// The wrong-ray tolerance of a ray with origin `o` and oracle hit `p`: [`WRONG`], or
/// for `f32` methods `max(WRONG, F32_ULPS · ε32 · (|o|∞ + |p|∞))`.
pub fn tolerance(f64_method: bool, o: [f64; 3], p: [f64; 3]) -> f64 {
    if f64_method {
        return WRONG;
    }
    WRONG.max(F32_ULPS * f64::from(f32::EPSILON) * (inf_norm(o) + inf_norm(p)))
}

/// Units of `f32`'s epsilon, times the coordinates' magnitude, of the resolution δ
/// ([`resolution`]): a march's point `o + t · d` at a crossing `t = (X − o) / d` is off
/// by about one ulp of its coordinates (two roundings of half an ulp), which the slope
/// turns into a clearance error; the height interpolation adds about an ulp of the
/// heights. Two ulps of the larger of the two bound both.
pub const RESOLUTION_ULPS: f64 = 2.0;

/// The `f32` resolution δ of a ray with origin `o` over `hf`:
/// `RESOLUTION_ULPS · ε32 · (|o|∞ + E)`,
/// `E = max(W − 1, H − 1, |min height|, |max height|)`, the largest coordinate the
/// ray's points take over the field.
pub fn resolution(hf: &HeightField, o: [f64; 3]) -> f64 {
    let extent = f64::from(hf.width().max(hf.height()) - 1)
        .max(f64::from(hf.min_height()).abs())
        .max(f64::from(hf.max_height()).abs());
    RESOLUTION_ULPS * f64::from(f32::EPSILON) * (inf_norm(o) + extent)
}

/// Whether two oracle answers, one for the ray moved by `delta`, are the same answer:
/// both miss, or both hit within the tolerance plus the distance a hit moves when the
/// ray moves by `delta` (`delta · (1 + 1/|n · d̂|)` for normal `n`, unit direction `d̂`,
/// doubled; the cosine taken at least 1e-3: a hit that slides farther is not resolved).
pub fn agree(
    base: &Trace<f64>,
    moved: &Trace<f64>,
    o: [f64; 3],
    dir: [f64; 3],
    delta: f64,
) -> bool {
    match (base.hit, moved.hit) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            let (p, n) = (a.point.to_array(), a.normal.to_array());
            let len = Real::sqrt(dir.iter().map(|x| x * x).sum::<f64>());
            let cos = (n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]).abs() / len;
            let slide = 2.0 * delta * (1.0 + 1.0 / cos.max(1e-3));
            (a.point - b.point).length() <= tolerance(false, o, p) + slide
        }
        _ => false,
    }
}

/// The oracle's answers to `q` with its origin moved by ±δ ([`resolution`]) along each
/// axis: `+x, −x, +y, −y, +z, −z` (`None` where the moved ray is not a valid query).
pub fn moved(hf: &HeightField, surface: Surface, q: &Query<f64>) -> [Option<Trace<f64>>; 6] {
    let (o, d) = (q.origin(), q.dir());
    let delta = resolution(hf, o);
    core::array::from_fn(|k| {
        let mut moved = o;
        moved[k / 2] += if k % 2 == 0 { delta } else { -delta };
        let m = Query::from_arrays(moved, d, q.t_min(), q.t_max()).ok()?;
        Some(dda::trace(hf, surface, &m))
    })
}

/// Whether `q` is ambiguous on `surface` of `hf` (module doc), given the oracle's answer
/// `base` (`dda::trace` of `q`): six more oracle traces ([`moved`]).
pub fn ambiguous(hf: &HeightField, surface: Surface, q: &Query<f64>, base: &Trace<f64>) -> bool {
    let (o, d) = (q.origin(), q.dir());
    let delta = resolution(hf, o);
    moved(hf, surface, q)
        .iter()
        .any(|m| m.as_ref().is_none_or(|m| !agree(base, m, o, d, delta)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;

    fn samples(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Vec<f32> {
        (0..w * h).map(|k| f(k % w, k / w)).collect()
    }

    fn judge(hf: &HeightField, o: [f64; 3], d: [f64; 3]) -> bool {
        let q = Query::from_arrays(o, d, 0.0, f64::INFINITY).unwrap();
        ambiguous(
            hf,
            Surface::Triangles,
            &q,
            &dda::trace(hf, Surface::Triangles, &q),
        )
    }

    #[test]
    fn tolerance_grows_with_coordinates() {
        assert_eq!(tolerance(true, [1e5, 0.0, 0.0], [1.0; 3]), WRONG);
        assert_eq!(tolerance(false, [1.0, 2.0, 3.0], [1.0; 3]), WRONG);
        let far = tolerance(false, [1e5, 0.0, 0.0], [10.0, 0.0, 0.0]);
        let want = 8.0 * f64::from(f32::EPSILON) * (1e5 + 10.0);
        assert!((far - want).abs() < 1e-12, "{far}");
    }

    #[test]
    fn touches_and_clipped_ridges_are_ambiguous() {
        // A single peak of height 1 at (2, 2) on a flat 5 x 5 field.
        let s = samples(5, 5, |i, j| f32::from(u8::from(i == 2 && j == 2)));
        let hf = HeightField::new(&s, 5, 5, 5).unwrap();
        // Level through the peak's tip (a touch), just over it and just under it (the
        // hit clips the tip), and well under it.
        assert!(judge(&hf, [-3.0, 2.0, 1.0], [1.0, 0.0, 0.0]));
        assert!(judge(&hf, [-3.0, 2.0, 1.0 + 1e-9], [1.0, 0.0, 0.0]));
        assert!(judge(&hf, [-3.0, 2.0, 1.0 - 1e-9], [1.0, 0.0, 0.0]));
        assert!(!judge(&hf, [-3.0, 2.0, 0.5], [1.0, 0.0, 0.0]));
        assert!(!judge(&hf, [-3.0, 2.0, 1.5], [1.0, 0.0, 0.0]));
        // Straight down onto the slope: stable.
        assert!(!judge(&hf, [1.5, 2.0, 3.0], [0.0, 0.0, -1.0]));
        // The old rule (clearance before the hit under 2^-13) did not see the clipped
        // tip: the clearance it measured is the ray's height over the flat ground.
        let q = Query::from_arrays([-3.0, 2.0, 1.0 - 1e-9], [1.0, 0.0, 0.0], 0.0, f64::INFINITY);
        let before = dda::trace(&hf, Surface::Triangles, &q.unwrap()).clearance;
        assert!(before > 1.0 / 8192.0, "{before}");
    }

    #[test]
    fn threshold_follows_the_coordinates_not_the_largest_height() {
        // Heights around 1e5 with a relief of 1: the old rule's 2^-13 · 1e5 = 12.2
        // exceeded the relief; δ here is 2 · ε32 · (|o|∞ + E) = 2 · ε32 · 2e5 ≈ 0.048.
        let s = samples(9, 9, |i, j| 1e5 + ((i + j) % 2) as f32);
        let hf = HeightField::new(&s, 9, 9, 9).unwrap();
        let over = [4.3, 4.6, 1e5 + 2.0];
        assert!(!judge(&hf, over, [0.3, 0.1, -1.0]));
        // The old rule called it ambiguous: its clearance before the hit (at most the
        // relief plus the 2 above it) is under 2^-13 · 1e5.
        let q = Query::from_arrays(over, [0.3, 0.1, -1.0], 0.0, f64::INFINITY).unwrap();
        let old_rule = dda::trace(&hf, Surface::Triangles, &q).clearance < 1e5 / 8192.0;
        assert!(old_rule);
        let delta = resolution(&hf, over);
        assert!(delta < 0.05 && delta > 0.045, "{delta}");
    }
}
