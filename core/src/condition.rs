//! Conditioning `f32` queries (issue 25): rays that start far from the field, or whose
//! direction is tiny or huge, made local before an `f32` march.
//!
//! An `f32` march computes every ray parameter from the origin: `(X − o) / d`. From an
//! origin 10⁶ texels away, `t` is 10⁶ and its rounding (an ulp of 0.06) is larger than a
//! cell's worth of precision near the field; from 1.8·10⁹ away the whole box is less
//! than one ulp of `t` and the ray misses; with `|d| ≤ 10⁻³⁷` every quotient
//! overflows and the ray misses with no fetch. [`condition`] fixes both in `f64`
//! before the march, by a reparametrisation of the same ray:
//!
//! - **Scale.** When the largest direction component lies outside `[2⁻³², 2³²]`, the
//!   direction is divided by the power of two `s` that brings it into `[1, 2)` and
//!   the range multiplied by it: exact (no bit of the direction changes but the
//!   exponent).
//! - **Rebase.** When the origin lies more than [`FAR`] field extents outside the
//!   field's box (the box of every surface, widened as for corner planes), the ray is
//!   clipped to that box in `f64`: a miss there is the answer (no march runs), and
//!   otherwise the origin moves along the ray to one grid unit before its entry, so
//!   the march sees coordinates of the field's size.
//!
//! [`Local::trace`] runs the march on the local query and maps the hit's `t` back
//! (`t = (shift + t_local) / s`, in `f64`); points, normals, cells and clearances are
//! the same in both parametrisations. A ray that needs neither is traced unchanged,
//! bit for bit. The GLSL and WGSL ports do not condition (a shader's rays start at a
//! camera near the field): what they promise is in the README ("World units").

use crate::dda;
use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Query, RayError, Trace};
use crate::surface::Surface;

mod lanes;
pub use lanes::Sighted;

/// How many field extents (one more than the largest of `W − 1`, `H − 1` and the height
/// range) an origin may lie outside the field's box before its ray is rebased.
pub const FAR: f64 = 2.0;

/// Direction magnitudes (largest component) outside `[SMALL, 1 / SMALL]` are scaled.
const SMALL: f64 = 1.0 / 4_294_967_296.0;

/// A query made local to a field, and how to map its answer back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// The query the march traces.
    pub query: Query<f32>,
    /// Ray parameter (in local units) of the local origin on the original ray.
    shift: f64,
    /// Local `t` per original `t` (the largest direction component, rounded down to a
    /// power of two): `t = (shift + t_local) / scale`.
    scale: f64,
    /// The ray misses the field's box: no march is needed.
    miss: bool,
}

impl Local {
    /// The caller's own query, traced as it is.
    fn unchanged(query: Query<f32>) -> Local {
        Local {
            query,
            shift: 0.0,
            scale: 1.0,
            miss: false,
        }
    }

    /// Whether the query is the caller's own (neither scaled nor rebased).
    pub fn is_unchanged(&self) -> bool {
        self.shift == 0.0 && self.scale == 1.0 && !self.miss
    }

    /// Runs `march` on the local query and maps its hit back to the caller's ray
    /// parameter. A ray that misses the box is [`Trace::MISS`] without a march. A hit
    /// whose `t` exceeds the `f32` range reports `t = f32::MAX` (its point is exact).
    pub fn trace(&self, march: impl FnOnce(&Query<f32>) -> Trace<f32>) -> Trace<f32> {
        self.trace_from(None, |q, _| march(q))
    }

    /// [`Local::trace`] of a ray whose start `t0` on the original ray is known (a
    /// [`crate::horizon::Horizon`]'s): `march` gets the local query and that start in
    /// local units, rounded and kept inside the local range (`None`: no start).
    pub fn trace_from(
        &self,
        t0: Option<f64>,
        march: impl FnOnce(&Query<f32>, Option<f32>) -> Trace<f32>,
    ) -> Trace<f32> {
        if self.miss {
            return Trace::MISS;
        }
        self.finish(march(&self.query, t0.map(|t| self.local_t(t))))
    }

    /// The parameter `t` of the original ray in local units, rounded and kept inside the
    /// local range.
    pub fn local_t(&self, t: f64) -> f32 {
        let q = &self.query;
        ((t * self.scale - self.shift) as f32).clamp(q.t_min(), q.t_max())
    }

    /// The answer of the local march `tr` on the original ray.
    fn finish(&self, mut tr: Trace<f32>) -> Trace<f32> {
        if self.shift != 0.0 || self.scale != 1.0 {
            if let Some(h) = tr.hit.as_mut() {
                let t = (self.shift + f64::from(h.t)) / self.scale;
                h.t = (t as f32).min(f32::MAX);
            }
        }
        tr
    }
}

/// The local query of the grid-space ray `origin + t·dir`, `t` in `[t_min, t_max]`
/// (origin and direction in `f64`: exact conversions of `f32` values, or a world ray
/// converted in `f64`), checked as [`Query::from_arrays`] checks the `f32` ray it
/// rounds to.
pub fn condition(
    hf: &HeightField,
    origin: [f64; 3],
    dir: [f64; 3],
    t_min: f32,
    t_max: f32,
) -> Result<Local, RayError> {
    let round = |v: [f64; 3]| v.map(|x| x as f32);
    // The caller's ray as the march would see it: its faults are reported as such.
    let plain = Query::from_arrays(round(origin), round(dir), t_min, t_max)?;
    Ok(match Near::of(hf).needs(origin, dir) {
        (false, false) => Local::unchanged(plain),
        need => localize(hf, origin, dir, plain, need),
    })
}

/// [`condition`] of a query already in `f32` (the fast path: a ray that needs no
/// conditioning costs a few `f32` compares).
#[inline]
pub fn condition_query(hf: &HeightField, q: &Query<f32>) -> Local {
    condition_query_near(hf, &Near::of(hf), q)
}

/// [`condition_query`] with its test prepared ([`Near::of`] of `hf`): what a batch
/// calls for each of its rays.
#[inline]
pub fn condition_query_near(hf: &HeightField, near: &Near<f32>, q: &Query<f32>) -> Local {
    let (o, d) = (q.origin(), q.dir());
    match near.needs(o, d) {
        (false, false) => Local::unchanged(*q),
        need => localize(hf, o.map(f64::from), d.map(f64::from), *q, need),
    }
}

/// What a ray needs to be conditioned, for one field, in precision `R`: its box (the
/// samples' footprint and height range), how far outside it an origin may lie, and the
/// direction magnitudes that need no scaling (the rules of the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Near<R> {
    lo: [R; 3],
    hi: [R; 3],
    /// [`FAR`] field extents.
    far: R,
    /// Smallest and largest direction magnitude left unscaled.
    small: R,
    big: R,
}

impl<R: Real> Near<R> {
    /// The test for rays of `hf`.
    pub fn of(hf: &HeightField) -> Near<R> {
        let lo = [R::ZERO, R::ZERO, R::from_f32(hf.min_height())];
        let hi = [
            R::from_u32(hf.width() - 1),
            R::from_u32(hf.height() - 1),
            R::from_f32(hf.max_height()),
        ];
        let extent = hi[0].max(hi[1]).max(hi[2] - lo[2]) + R::ONE;
        let small = R::from_f64(SMALL);
        Near {
            lo,
            hi,
            far: R::from_f64(FAR) * extent,
            small,
            big: R::ONE / small,
        }
    }

    /// Whether `q` needs no conditioning: [`condition_query`] would trace it as it is.
    #[inline]
    pub fn holds(&self, q: &Query<R>) -> bool {
        self.needs(q.origin(), q.dir()) == (false, false)
    }

    /// What the ray from `o` along `d` needs, evaluated in its own precision (the
    /// thresholds are not sharp): `(scale, far)`, whether its direction is to be scaled
    /// and whether its origin is far from the box.
    #[inline]
    fn needs(&self, o: [R; 3], d: [R; 3]) -> (bool, bool) {
        let m = d[0].abs().max(d[1].abs()).max(d[2].abs());
        let dist = (0..3).fold(R::ZERO, |m, k| {
            m.max(self.lo[k] - o[k]).max(o[k] - self.hi[k])
        });
        (!(m >= self.small && m <= self.big), dist > self.far)
    }
}

/// The local form of `plain`, the `f32` rounding of the ray `origin + t·dir`, given
/// what it needs ([`Near::needs`], not `(false, false)`).
fn localize(
    hf: &HeightField,
    origin: [f64; 3],
    dir: [f64; 3],
    plain: Query<f32>,
    (scaled, far): (bool, bool),
) -> Local {
    let miss = Local {
        miss: true,
        ..Local::unchanged(plain)
    };
    let largest = |v: [f64; 3]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = if scaled {
        libm::scalbn(1.0, libm::ilogb(largest(dir)))
    } else {
        1.0
    };
    let d = dir.map(|v| v / scale);
    let (t0, t1) = (
        f64::from(plain.t_min()) * scale,
        f64::from(plain.t_max()) * scale,
    );
    let shift = if far {
        let Ok(q) = Query::<f64>::from_arrays(origin, d, t0, t1) else {
            return miss;
        };
        match dda::clip_surface(hf, Surface::CornerPlanes, &q) {
            None => return miss,
            // One grid unit before the entry.
            Some(span) => span.t0 - 1.0 / largest(d),
        }
    } else {
        0.0
    };
    let o = [0, 1, 2].map(|k| (origin[k] + shift * d[k]) as f32);
    let (lo, hi) = ((t0 - shift) as f32, (t1 - shift) as f32);
    // A range that starts beyond what `f32` holds in local units reaches nothing.
    match Query::from_arrays(o, d.map(|v| v as f32), lo, hi) {
        Ok(query) => Local {
            query,
            shift,
            scale,
            miss: false,
        },
        Err(_) => miss,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dda;

    fn field() -> ([f32; 16], u32) {
        let mut h = [0.0f32; 16];
        for (k, v) in h.iter_mut().enumerate() {
            *v = (k % 3) as f32;
        }
        (h, 4)
    }

    #[test]
    fn near_rays_are_untouched() {
        let (h, n) = field();
        let hf = HeightField::new(&h, n, n, n as usize).unwrap();
        let l = condition(&hf, [1.5, 1.5, 5.0], [0.1, 0.2, -1.0], 0.0, f32::INFINITY).unwrap();
        assert!(l.is_unchanged());
    }

    #[test]
    fn a_far_horizontal_ray_hits() {
        // A needle at sample (2, 1) rising to 2 over a flat field; a level ray at z = 1
        // along y = 1 meets its flank at x = 1.5. From x = -1.8e9 the box is less than
        // one ulp of the f32 ray parameter (128) and the f32 march misses.
        let mut h = [0.0f32; 16];
        h[4 + 2] = 2.0;
        let hf = HeightField::new(&h, 4, 4, 4).unwrap();
        let (o, d) = ([-1.8e9f32, 1.0, 1.0], [1.0f32, 0.0, 0.0]);
        let q = Query::from_arrays(o, d, 0.0, f32::INFINITY).unwrap();
        assert!(dda::trace(&hf, Surface::Triangles, &q).hit.is_none());
        let l = condition(&hf, o.map(f64::from), d.map(f64::from), 0.0, f32::INFINITY).unwrap();
        assert!(!l.is_unchanged());
        let hit = l
            .trace(|q| dda::trace(&hf, Surface::Triangles, q))
            .hit
            .unwrap();
        assert_eq!(hit.point.to_array(), [1.5, 1.0, 1.0]);
        assert_eq!(hit.t, 1.8e9f32);
    }

    #[test]
    fn a_tiny_direction_is_scaled() {
        let h = [0.0f32, 1.0, 1.0, 2.0];
        let hf = HeightField::new(&h, 2, 2, 2).unwrap();
        let (o, d) = ([0.5f32, 0.5, 5.0], [0.0f32, 0.0, -1e-38]);
        let q = Query::from_arrays(o, d, 0.0, f32::INFINITY).unwrap();
        assert!(dda::trace(&hf, Surface::Triangles, &q).hit.is_none());
        let l = condition(&hf, o.map(f64::from), d.map(f64::from), 0.0, f32::INFINITY).unwrap();
        let hit = l
            .trace(|q| dda::trace(&hf, Surface::Triangles, q))
            .hit
            .unwrap();
        assert!((hit.point.z - 1.0).abs() < 1e-6);
        // t = 4 / 1e-38 overflows f32: the largest finite t, the point exact.
        assert_eq!(hit.t, f32::MAX);
    }
}
