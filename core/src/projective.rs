//! Projective height fields (Baboud & Décoret 2006, §4): a field whose grid is the
//! image of a frustum under a 4×4 projective map, so that one field can hold the sides
//! of an object as well as its top (a *reverse-perspective* field). The orthographic
//! box (an affine map) is the special case.
//!
//! **Grid lines.** [`Projective`] maps a world point `X` to the homogeneous grid point
//! `G = M·[X, 1]`, the grid point `G.xyz / G.w`. A world ray `o + t·d` becomes
//! `G(t) = A + t·B` (`A = M·[o, 1]`, `B = M·[d, 0]`), and its grid points
//! `g(t) = g_b + σ(t)·e` lie on one line: from a base point `t_b` where
//! `w_b = w(t_b) > 0`, `e = (B.xyz·w_b − A_b.xyz·B.w) / w_b²` and
//! `σ(t) = (t − t_b)·w_b / (w_b + (t − t_b)·B.w)`, increasing wherever
//! `w(t) = A.w + t·B.w` stays positive. So every march runs
//! unchanged on the grid line, and a hit at `σ` is the world hit at
//! `t = t_b + σ·w_b / (w_b − σ·B.w)`.
//!
//! **Range** (the contract). Only points with `w > 0` are in the field's space (the
//! others are behind the centre of projection). A ray is traced over the part of
//! `[t_min, t_max]` where `w > 0`, as the grid range `[σ(start), σ(end)]`. Where that
//! part starts at `w = 0` the line starts at infinity; it is then traced from where it
//! enters the box every surface lies in (the footprint, heights from `min − range` to
//! `max + range`, as for [`crate::Query::walked_back`]) widened by a grid unit, and a
//! ray under the surface there hits there. An end at `w = 0` or at `t = ∞` may be
//! `σ = ∞`, which a march takes.
//!
//! **Exactness.** The map and the base point are computed in `f64` and the grid query
//! rounded once to `R`. The march is exact on that grid query (the same first hit as
//! the `f64` oracle on it, docs/DESIGN.md); the world `t` comes from its `σ`, the point
//! from the grid hit by `M⁻¹`, both in `f64`, and the world normal is the grid hit's
//! plane mapped by `Mᵀ` (a point `X` is on `[n, −n·p]` in grid space iff it is on
//! `Mᵀ·[n, −n·p]` in world space), on the same side of the world ray as the grid
//! normal is of the grid ray (`w > 0` keeps the sign). `core/tests/projective.rs`
//! holds the world point, mapped back, within 10⁻⁵ of the grid hit's magnitude
//! (measured: 7.6·10⁻⁸) and the normal orthogonal to the surface's world tangents
//! within 10⁻⁵ (measured: 4·10⁻⁸).

use crate::math::Real;
use crate::ray::{Hit, Query, RayError, Trace};
use crate::HeightField;

/// A 4×4 matrix, rows of `f64`.
pub type Mat4 = [[f64; 4]; 4];

/// Why a [`Projective`] map is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProjectiveError {
    /// An entry is NaN or infinite.
    NotFinite,
    /// The map is singular (or so near it that its inverse is not finite): no frustum.
    Singular,
}

impl core::fmt::Display for ProjectiveError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            ProjectiveError::NotFinite => "the projective map has a NaN or infinite entry",
            ProjectiveError::Singular => "the projective map is singular",
        })
    }
}

/// A projective map from world space to a field's grid space (homogeneous
/// coordinates), checked invertible; see the module's documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projective {
    m: Mat4,
    inv: Mat4,
}

/// A world ray on a projective field: its grid query and what maps a grid parameter
/// back to world `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mapped<R: Real> {
    /// The grid ray: the march's input.
    pub grid: Query<R>,
    /// The base point's world `t`.
    t_b: f64,
    /// `w` at the base point.
    w_b: f64,
    /// `B.w`: how `w` changes with `t`.
    b_w: f64,
}

impl<R: Real> Mapped<R> {
    /// The world `t` of the grid parameter `sigma`.
    pub fn world_t(&self, sigma: f64) -> f64 {
        self.t_b + sigma * self.w_b / (self.w_b - sigma * self.b_w)
    }
}

impl Projective {
    /// Checks `m` (rows; world `[x, y, z, 1]` to grid `[x, y, z, w]`): finite, and
    /// invertible with a finite inverse.
    pub fn new(m: Mat4) -> Result<Projective, ProjectiveError> {
        if !m.iter().flatten().all(|v| v.is_finite()) {
            return Err(ProjectiveError::NotFinite);
        }
        let inv = invert(&m).ok_or(ProjectiveError::Singular)?;
        Ok(Projective { m, inv })
    }

    /// The map of a frustum to the unit cube (`m_unit`: x and y in `[0, 1]` across the
    /// footprint, z in `[0, 1]` the height range) scaled to the grid of a `w × h`
    /// field whose heights span `depth` grid units: x·(w − 1), y·(h − 1), z·depth.
    pub fn from_unit_cube(
        m_unit: Mat4,
        w: u32,
        h: u32,
        depth: f64,
    ) -> Result<Projective, ProjectiveError> {
        let s = [f64::from(w.max(2) - 1), f64::from(h.max(2) - 1), depth, 1.0];
        let mut m = m_unit;
        for (row, k) in m.iter_mut().zip(s) {
            for v in row.iter_mut() {
                *v *= k;
            }
        }
        Projective::new(m)
    }

    /// The matrix (world to homogeneous grid).
    pub fn matrix(&self) -> &Mat4 {
        &self.m
    }

    /// The inverse matrix (homogeneous grid to world).
    pub fn inverse(&self) -> &Mat4 {
        &self.inv
    }

    /// The homogeneous grid point of the world point `p` (`M·[p, 1]`).
    pub fn to_grid_h(&self, p: [f64; 3]) -> [f64; 4] {
        mul(&self.m, [p[0], p[1], p[2], 1.0])
    }

    /// The world point of the grid point `g` (`M⁻¹·[g, 1]`, divided by its `w`).
    pub fn to_world(&self, g: [f64; 3]) -> [f64; 3] {
        let x = mul(&self.inv, [g[0], g[1], g[2], 1.0]);
        [x[0] / x[3], x[1] / x[3], x[2] / x[3]]
    }

    /// The world ray `world` as a grid query on `hf` (see the module's "Range");
    /// `Ok(None)` when no part of it with `w > 0` meets the field's box. Errors are the
    /// world ray's own (as [`Query::from_arrays`]).
    pub fn map<R: Real>(
        &self,
        hf: &HeightField,
        world: &Query<R>,
    ) -> Result<Option<Mapped<R>>, RayError> {
        let (o, d) = (world.origin().map(R::to_f64), world.dir().map(R::to_f64));
        let a = self.to_grid_h(o);
        let b = mul(&self.m, [d[0], d[1], d[2], 0.0]);
        // The part of [t_min, t_max] where w = a.w + t·b.w > 0.
        let (mut t0, mut t1) = (world.t_min().to_f64(), world.t_max().to_f64());
        if b[3] == 0.0 {
            if a[3] <= 0.0 {
                return Ok(None);
            }
        } else {
            let root = -a[3] / b[3];
            if b[3] > 0.0 {
                t0 = t0.max(root);
            } else {
                t1 = t1.min(root);
            }
        }
        if t0 > t1 {
            return Ok(None);
        }
        // A base point with w > 0 inside: the start, unless w is tiny there (the start
        // at the root, where the line is at infinity); then where w is largest (the
        // end, or where w = 1 for an endless range).
        let w = |t: f64| a[3] + t * b[3];
        let t_big = match (b[3] > 0.0, t1.is_finite()) {
            (true, true) => t1,
            (true, false) => t0.max(-a[3] / b[3] + 1.0 / b[3]),
            _ => t0,
        };
        let t_b = if w(t0) >= 1e-6 * w(t_big) { t0 } else { t_big };
        let w_b = w(t_b);
        if !(w_b > 0.0 && w_b.is_finite()) {
            return Ok(None);
        }
        let ab = [0, 1, 2].map(|k| a[k] + t_b * b[k]);
        let g_b = ab.map(|v| v / w_b);
        let e = [0, 1, 2].map(|k| (b[k] * w_b - ab[k] * b[3]) / (w_b * w_b));
        let sigma = |t: f64| {
            if t.is_infinite() || w(t) <= 0.0 {
                // The far end at infinity, or the root (w = 0): the line's end.
                if t >= t_b {
                    f64::INFINITY
                } else {
                    f64::NEG_INFINITY
                }
            } else {
                (t - t_b) * w_b / w(t)
            }
        };
        let (mut s0, s1) = (sigma(t0), sigma(t1));
        if s0 == f64::NEG_INFINITY {
            // The range starts at w = 0, where the line starts at infinity: from where
            // it enters the box every surface lies in, widened by a grid unit (so the
            // march still sees the entry), or a miss when it never does.
            let (lo, hi) = crate::ray::surface_box(hf, 1.0);
            let far;
            (s0, far) = crate::ray::slabs(g_b, e, lo, hi);
            if !(s0.is_finite() && s0 <= far.min(s1)) {
                return Ok(None);
            }
        }
        let r = |v: [f64; 3]| v.map(R::from_f64);
        let grid = Query::from_arrays(r(g_b), r(e), R::from_f64(s0), R::from_f64(s1))?;
        Ok(Some(Mapped {
            grid,
            t_b,
            w_b,
            b_w: b[3],
        }))
    }

    /// Traces the world ray `world` on `hf` with `march` (any march, on the grid
    /// query of [`Projective::map`]) and maps its answer back: the hit's world `t`,
    /// point and unit normal; its cell, flags, fetches and clearance (grid units) as
    /// the march gave them. A ray that [`Projective::map`] finds outside the field's
    /// space is a miss that cost nothing.
    pub fn trace<R: Real>(
        &self,
        hf: &HeightField,
        world: &Query<R>,
        march: impl FnOnce(&Query<R>) -> Trace<R>,
    ) -> Result<Trace<R>, RayError> {
        let Some(mapped) = self.map(hf, world)? else {
            return Ok(Trace::MISS);
        };
        Ok(self.trace_to_world(&mapped, march(&mapped.grid)))
    }

    /// The trace `tr` of `mapped`'s grid query with its hit mapped back to the world
    /// ray ([`Projective::trace`] after its march).
    pub fn trace_to_world<R: Real>(&self, mapped: &Mapped<R>, mut tr: Trace<R>) -> Trace<R> {
        if let Some(h) = tr.hit {
            tr.hit = Some(self.hit_to_world(mapped, &h));
        }
        tr
    }

    /// The world form of the grid hit `h` of `mapped`.
    fn hit_to_world<R: Real>(&self, mapped: &Mapped<R>, h: &Hit<R>) -> Hit<R> {
        let t = mapped.world_t(h.t.to_f64());
        let point = self.to_world(R::xyz(h.point).map(R::to_f64));
        // The grid plane [n, −n·p] through the hit, mapped by Mᵀ: its xyz is the world
        // normal, on the side where the grid normal points (w > 0 keeps the sign).
        let (n, p) = (
            R::xyz(h.normal).map(R::to_f64),
            R::xyz(h.point).map(R::to_f64),
        );
        let plane = [n[0], n[1], n[2], -(n[0] * p[0] + n[1] * p[1] + n[2] * p[2])];
        let mut wn = [0.0; 3];
        for (c, out) in wn.iter_mut().enumerate() {
            *out = (0..4).map(|r| self.m[r][c] * plane[r]).sum();
        }
        let len = libm::sqrt(wn.iter().map(|v| v * v).sum::<f64>());
        let wn = wn.map(|v| if len > 0.0 { v / len } else { v });
        let r = |v: [f64; 3]| R::v3(v.map(R::from_f64));
        Hit {
            t: R::from_f64(t),
            point: r(point),
            normal: r(wn),
            ..*h
        }
    }
}

/// `m·v`.
pub(crate) fn mul(m: &Mat4, v: [f64; 4]) -> [f64; 4] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2] + row[3] * v[3])
}

/// The inverse of `m` (Gauss–Jordan with partial pivoting); `None` when a pivot is
/// zero or under `1e-12` of the largest entry, or the inverse is not finite.
fn invert(m: &Mat4) -> Option<Mat4> {
    let scale = m.iter().flatten().fold(0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 {
        return None;
    }
    let mut a = *m;
    let mut inv = [[0.0; 4]; 4];
    for (k, row) in inv.iter_mut().enumerate() {
        row[k] = 1.0;
    }
    for c in 0..4 {
        let p = (c..4).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[p][c].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(c, p);
        inv.swap(c, p);
        let f = a[c][c];
        for k in 0..4 {
            a[c][k] /= f;
            inv[c][k] /= f;
        }
        for r in 0..4 {
            if r != c {
                let g = a[r][c];
                for k in 0..4 {
                    a[r][k] -= g * a[c][k];
                    inv[r][k] -= g * inv[c][k];
                }
            }
        }
    }
    inv.iter().flatten().all(|v| v.is_finite()).then_some(inv)
}
