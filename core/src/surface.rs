//! The six surface reconstructions of docs/DESIGN.md and their exact ray–cell tests.
//!
//! Everything here works in one cell's local coordinates: `u = x − i`, `v = y − j` in
//! `[0, 1]`, with the corners `c = [h00, h10, h01, h11]` (h10 at u = 1, h01 at v = 1).
//! A segment is the ray restricted to the cell, from local point `a` (s = 0) to `b`
//! (s = 1), each `[u, v, z]`.

use crate::field::HeightField;
use crate::math::{normal_from_gradient, Real};
use crate::ray::{Flags, Query};

named_enum! {
    /// How heights between samples are reconstructed.
    pub enum Surface: u32 {
        /// Two triangles per cell, split along the diagonal whose midpoint is lower, so the
        /// cell's height is the maximum of two planes (convex). The default.
        Triangles = 0 => "triangles" (true),
        /// Bilinear interpolation of the four corners.
        Bilinear = 1 => "bilinear" (true),
        /// Piecewise constant: the height of the nearest sample (ties go to the larger
        /// index). Steps between samples are vertical walls.
        HeightPlanes = 2 => "height-planes" (false),
        /// In cell (i, j) the plane through the samples (i, j), (i+1, j) and (i, j+1): the
        /// base sample and its forward differences. No paper defines it (Qu et al.'s linear
        /// approximation planes are the view-linear surface); not continuous across cells,
        /// steps are vertical walls.
        CornerPlanes = 3 => "corner-planes" (false),
        /// Baboud et al. §7, and Qu et al.'s linear approximation planes (eq. 1): linear
        /// along the ray between its centerline crossings, where it equals the edge
        /// interpolation of the samples. View dependent; shaded with the bilinear normal.
        ViewLinear = 4 => "view-linear" (true),
        /// Qu et al. 2003 §3.2: two triangles per cell split along the fixed diagonal
        /// from (i, j) to (i+1, j+1) in every cell, tested with their division-free
        /// inside test. Continuous, but its height is not convex over a cell (a ridge can
        /// run along the diagonal), so a segment clear at both ends can still meet it.
        QuTriangles = 5 => "qu-triangles" (true),
    }
    /// `true` when the surface is continuous, so its height on a cell edge is the linear
    /// interpolation of the edge's two samples, shared by both neighbouring cells.
    pub fn is_continuous(self) -> bool;
}

impl Default for Surface {
    /// [`Surface::Triangles`].
    fn default() -> Surface {
        Surface::Triangles
    }
}

/// Result of a segment test: where the segment first meets the surface (segment
/// parameter `s` in `[0, 1]`, unit normal, flags) and the smallest clearance seen on it
/// before that point.
#[derive(Clone, Copy, Debug)]
pub struct SegmentHit<R: Real> {
    /// `(s, normal, flags)` of the first contact, if any.
    pub hit: Option<(R, [R; 3], Flags)>,
    /// Smallest clearance (ray height − surface height) before the contact: over the
    /// whole segment when it stays clear; up to the start of the piece that holds the
    /// contact when it does not (the clearance falls to zero at the contact itself, so
    /// that piece adds only its starting value). A wall hit adds the depth of the ray
    /// under the wall's top edge there (`≥ 0`): how far the decision was from passing
    /// over it.
    pub clearance: R,
}

impl Surface {
    /// Height at grid point `(x, y)`, clamped into the footprint.
    pub fn height_at<R: Real>(self, hf: &HeightField, x: R, y: R) -> R {
        let (c, u, v, _) = locate(hf, x, y);
        self.cell_height(c, u, v)
    }

    /// Unit normal at grid point `(x, y)`, clamped into the footprint.
    pub fn normal_at<R: Real>(self, hf: &HeightField, x: R, y: R) -> [R; 3] {
        let (c, u, v, _) = locate(hf, x, y);
        let (gx, gy) = self.cell_gradient(c, u, v);
        normal_from_gradient(gx, gy)
    }

    /// Exact first intersection of `q`'s ray, restricted to `[ta, tb]`, with the surface
    /// over cell `(i, j)` (the caller clips `[ta, tb]` to the cell). Returns `(t, unit
    /// normal)`. A ray already under the surface at `ta` meets it at `ta`.
    pub fn intersect_cell<R: Real>(
        self,
        hf: &HeightField,
        cell: [u32; 2],
        q: &Query<R>,
        ta: R,
        tb: R,
    ) -> Option<(R, [R; 3])> {
        let c = corners(hf, cell[0], cell[1]);
        let local = |t: R| {
            let p = q.at(t);
            [
                (p[0] - R::from_u32(cell[0])).clamp_to(R::ZERO, R::ONE),
                (p[1] - R::from_u32(cell[1])).clamp_to(R::ZERO, R::ONE),
                p[2],
            ]
        };
        let (a, b) = (local(ta), local(tb));
        let ca = a[2] - self.cell_height(c, a[0], a[1]);
        if ca <= R::ZERO {
            return Some((ta, self.cell_normal(c, a[0], a[1])));
        }
        let cb = b[2] - self.cell_height(c, b[0], b[1]);
        let seg = self.segment_hit(c, a, b, ca, cb, [R::ZERO, R::ZERO, R::ONE]);
        seg.hit.map(|(s, n, _)| (ta + s * (tb - ta), n))
    }

    /// Height inside a cell at local `(u, v)`.
    #[inline]
    pub fn cell_height<R: Real>(self, c: [R; 4], u: R, v: R) -> R {
        match self {
            Surface::Triangles => {
                let [p, q] = triangle_planes(c);
                plane(p, u, v).max(plane(q, u, v))
            }
            Surface::Bilinear | Surface::ViewLinear => bilinear(c, u, v),
            Surface::HeightPlanes => c[nearest_corner(u, v)],
            Surface::CornerPlanes => plane(corner_plane(c), u, v),
            Surface::QuTriangles => plane(fixed_diagonal_planes(c)[usize::from(u < v)], u, v),
        }
    }

    /// Height gradient `(∂h/∂x, ∂h/∂y)` inside a cell at local `(u, v)`.
    #[inline]
    pub fn cell_gradient<R: Real>(self, c: [R; 4], u: R, v: R) -> (R, R) {
        match self {
            Surface::Triangles => {
                let [p, q] = triangle_planes(c);
                let top = if plane(p, u, v) >= plane(q, u, v) {
                    p
                } else {
                    q
                };
                (top[1], top[2])
            }
            Surface::Bilinear | Surface::ViewLinear => {
                let e = c[0] - c[1] - c[2] + c[3];
                (c[1] - c[0] + e * v, c[2] - c[0] + e * u)
            }
            Surface::HeightPlanes => (R::ZERO, R::ZERO),
            Surface::CornerPlanes => {
                let p = corner_plane(c);
                (p[1], p[2])
            }
            Surface::QuTriangles => {
                let p = fixed_diagonal_planes(c)[usize::from(u < v)];
                (p[1], p[2])
            }
        }
    }

    /// Unit normal inside a cell at local `(u, v)`.
    #[inline]
    pub fn cell_normal<R: Real>(self, c: [R; 4], u: R, v: R) -> [R; 3] {
        let (gx, gy) = self.cell_gradient(c, u, v);
        normal_from_gradient(gx, gy)
    }

    /// First contact of the segment `a → b` with the surface over one cell.
    ///
    /// `ca` and `cb` are the clearances at `a` and `b` as the caller computed them; for
    /// continuous surfaces the caller evaluates them once per centerline crossing and
    /// shares them with the neighbouring cell, which makes hit-or-miss watertight. The
    /// caller guarantees `ca > 0`. `entry_wall` is the normal of the face through which
    /// the segment entered the cell, used when a discontinuous surface stands above the
    /// ray right at `a`.
    #[inline]
    pub fn segment_hit<R: Real>(
        self,
        c: [R; 4],
        a: [R; 3],
        b: [R; 3],
        ca: R,
        cb: R,
        entry_wall: [R; 3],
    ) -> SegmentHit<R> {
        // Above at both ends, the ray stays above the triangle and the view-linear
        // surfaces over the cell (their clearance along the segment is concave, resp.
        // linear): no hit and the smaller end clearance, what their tests answer, here
        // without a call (most cells a march walks).
        if cb > R::ZERO && matches!(self, Surface::Triangles | Surface::ViewLinear) {
            return SegmentHit {
                hit: None,
                clearance: ca.min(cb),
            };
        }
        self.segment_contact(c, a, b, ca, cb, entry_wall)
    }

    /// [`Surface::segment_hit`] past its shortcut: the test of each surface (for the
    /// triangle and view-linear surfaces only segments that end on or under them,
    /// `cb ≤ 0`, get here).
    fn segment_contact<R: Real>(
        self,
        c: [R; 4],
        a: [R; 3],
        b: [R; 3],
        ca: R,
        cb: R,
        entry_wall: [R; 3],
    ) -> SegmentHit<R> {
        match self {
            Surface::Triangles => triangles_segment(c, a, b, ca),
            Surface::Bilinear => bilinear_segment(c, a, b, ca, cb),
            Surface::ViewLinear => {
                // Linear along the segment, from `ca > 0` to `cb ≤ 0`.
                let s = ca / (ca - cb);
                let (u, v) = (a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s);
                SegmentHit {
                    hit: Some((s, self.cell_normal(c, u, v), Flags::default())),
                    clearance: ca,
                }
            }
            Surface::CornerPlanes => {
                let p = corner_plane(c);
                let la = a[2] - plane(p, a[0], a[1]);
                let lb = b[2] - plane(p, b[0], b[1]);
                let n = normal_from_gradient(p[1], p[2]);
                let (hit, clearance) = if la <= R::ZERO {
                    (Some((R::ZERO, entry_wall, Flags::WALL)), -la)
                } else if lb <= R::ZERO {
                    (Some((la / (la - lb), n, Flags::default())), la)
                } else {
                    (None, la.min(lb))
                };
                SegmentHit { hit, clearance }
            }
            Surface::HeightPlanes => height_planes_segment(c, a, b, entry_wall),
            Surface::QuTriangles => qu_triangles_segment(c, a, b, ca, cb),
        }
    }
}

/// Corners of cell (i, j) in precision `R`.
#[inline]
pub fn corners<R: Real>(hf: &HeightField, i: u32, j: u32) -> [R; 4] {
    hf.cell_corners(i, j).map(R::from_f32)
}

/// Cell corners and local coordinates of grid point `(x, y)` (clamped into the footprint).
pub fn locate<R: Real>(hf: &HeightField, x: R, y: R) -> ([R; 4], R, R, [u32; 2]) {
    let x = x.clamp_to(R::ZERO, R::from_u32(hf.width() - 1));
    let y = y.clamp_to(R::ZERO, R::from_u32(hf.height() - 1));
    let i = (x.floor().to_f64() as u32).min(hf.width() - 2);
    let j = (y.floor().to_f64() as u32).min(hf.height() - 2);
    let c = corners(hf, i, j);
    (c, x - R::from_u32(i), y - R::from_u32(j), [i, j])
}

/// A plane `h0 + gu·u + gv·v` as `[h0, gu, gv]`.
#[inline]
pub(crate) fn plane<R: Real>(p: [R; 3], u: R, v: R) -> R {
    p[0] + p[1] * u + p[2] * v
}

/// Bilinear interpolation of the corners.
#[inline]
pub fn bilinear<R: Real>(c: [R; 4], u: R, v: R) -> R {
    R::lerp(R::lerp(c[0], c[1], u), R::lerp(c[2], c[3], u), v)
}

/// The two planes of the triangle split: the cell is cut along the diagonal whose
/// midpoint is lower, so the height is the maximum of the two planes.
#[inline]
pub fn triangle_planes<R: Real>(c: [R; 4]) -> [[R; 3]; 2] {
    let [h00, h10, h01, h11] = c;
    if h00 + h11 <= h10 + h01 {
        // Diagonal 00–11: triangles (00, 10, 11) and (00, 01, 11).
        fixed_diagonal_planes(c)
    } else {
        // Diagonal 10–01: triangles (00, 10, 01) and (10, 01, 11).
        [
            [h00, h10 - h00, h01 - h00],
            [h10 + h01 - h11, h11 - h01, h11 - h10],
        ]
    }
}

/// The two planes of the fixed split along the diagonal 00–11 ([`Surface::QuTriangles`]):
/// the triangle (00, 10, 11) where `u ≥ v`, then (00, 01, 11) where `u < v`.
#[inline]
pub fn fixed_diagonal_planes<R: Real>(c: [R; 4]) -> [[R; 3]; 2] {
    let [h00, h10, h01, h11] = c;
    [[h00, h10 - h00, h11 - h10], [h00, h11 - h01, h01 - h00]]
}

/// The corner-planes surface: the plane through h00, h10 and h01.
#[inline]
fn corner_plane<R: Real>(c: [R; 4]) -> [R; 3] {
    [c[0], c[1] - c[0], c[2] - c[0]]
}

/// Index into the corner array of the sample nearest to local `(u, v)`.
#[inline]
fn nearest_corner<R: Real>(u: R, v: R) -> usize {
    usize::from(u >= R::HALF) | (usize::from(v >= R::HALF) << 1)
}

/// Triangles: the clearance is the minimum of two linear functions, hence concave along
/// the segment, so the segment is clear iff both ends are ([`Surface::segment_hit`]
/// answers those); for one that ends on or under the surface (`cb ≤ 0`) the contact is
/// the first root of either plane's clearance.
fn triangles_segment<R: Real>(c: [R; 4], a: [R; 3], b: [R; 3], ca: R) -> SegmentHit<R> {
    let mut best: Option<(R, [R; 3])> = None;
    for p in triangle_planes(c) {
        let la = a[2] - plane(p, a[0], a[1]);
        let lb = b[2] - plane(p, b[0], b[1]);
        if lb <= R::ZERO {
            let s = if la <= R::ZERO {
                R::ZERO
            } else {
                la / (la - lb)
            };
            if best.is_none_or(|(bs, _)| s < bs) {
                best = Some((s, p));
            }
        }
    }
    // Rounding may leave both plane clearances just above zero while the shared edge
    // clearance `cb` is not: the contact is then at the end of the segment.
    let (s, p) = best.unwrap_or_else(|| {
        let [p, q] = triangle_planes(c);
        let top = if plane(p, b[0], b[1]) >= plane(q, b[0], b[1]) {
            p
        } else {
            q
        };
        (R::ONE, top)
    });
    SegmentHit {
        hit: Some((s, normal_from_gradient(p[1], p[2]), Flags::default())),
        clearance: ca,
    }
}

/// Qu et al.'s triangle test (§3.2) on the fixed diagonal `u = v`. The segment starts in
/// the triangle on `a`'s side of the diagonal (`u ≥ v` when `a` is on it and `b` is
/// not below it). If it stays there the clearance is linear, from `ca` to `cb`. If it
/// crosses, at `s_d = g_a / (g_a − g_b)` with `g = u − v`, the contact lies in the first
/// triangle iff its plane's clearance `l_b` at `b` satisfies `ca·|g_b| + l_b·|g_a| ≤ 0`:
/// their division-free comparison of the plane's root `ca / (ca − l_b)` with `s_d`
/// (products of offsets from the diagonal and heights over the plane; the left side is
/// `|g_a| + |g_b|` times the clearance where the segment crosses the diagonal). Past it,
/// the second triangle's clearance runs linearly from that crossing clearance to `cb`.
/// Only a hit (and the clearance of a crossing segment, reported as the smallest
/// clearance seen) takes a division.
fn qu_triangles_segment<R: Real>(c: [R; 4], a: [R; 3], b: [R; 3], ca: R, cb: R) -> SegmentHit<R> {
    let planes = fixed_diagonal_planes(c);
    let normal = |k: usize| normal_from_gradient(planes[k][1], planes[k][2]);
    let (ga, gb) = (a[0] - a[1], b[0] - b[1]);
    let first = usize::from(ga < R::ZERO || (ga == R::ZERO && gb < R::ZERO));
    let crosses = if first == 0 {
        gb < R::ZERO
    } else {
        gb > R::ZERO
    };
    if !crosses {
        let hit = (cb <= R::ZERO).then(|| (ca / (ca - cb), normal(first), Flags::default()));
        let clearance = if hit.is_some() { ca } else { ca.min(cb) };
        return SegmentHit { hit, clearance };
    }
    let (wa, wb) = (ga.abs(), gb.abs());
    let lb = b[2] - plane(planes[first], b[0], b[1]);
    let crossing = ca * wb + lb * wa;
    if crossing <= R::ZERO {
        return SegmentHit {
            hit: Some((ca / (ca - lb), normal(first), Flags::default())),
            clearance: ca,
        };
    }
    let cd = crossing / (wa + wb);
    let clearance = ca.min(cd);
    if cb > R::ZERO {
        return SegmentHit {
            hit: None,
            clearance: clearance.min(cb),
        };
    }
    let sd = wa / (wa + wb);
    // `cd` is 0 only when the product underflowed: the contact is then the crossing.
    let s = if cd > R::ZERO {
        sd + (R::ONE - sd) * (cd / (cd - cb))
    } else {
        sd
    };
    SegmentHit {
        hit: Some((s.min(R::ONE), normal(1 - first), Flags::default())),
        clearance,
    }
}

/// The roots of `A x² + B x + C` computed without cancellation: with
/// `q = −(B + sign(B)·√D) / 2` they are `q / A` and `C / q` (a double root at 0 when
/// `B = D = C = 0`, none when `D < 0` or `A = B = 0 ≠ C`). Right when `A` vanishes or is
/// tiny (`q / A` is then infinite or huge: callers keep the finite roots they want), for
/// a double root and for far-apart roots. Shared by the bilinear cell test and the QDM
/// march.
pub fn stable_roots<R: Real>(qa: R, qb: R, qc: R) -> heapless::Vec<R, 2> {
    let mut roots = heapless::Vec::new();
    let disc = qb * qb - R::from_f32(4.0) * qa * qc;
    if disc < R::ZERO {
        return roots;
    }
    let sq = disc.sqrt();
    let q = if qb >= R::ZERO {
        -R::HALF * (qb + sq)
    } else {
        -R::HALF * (qb - sq)
    };
    // Two pushes into room for two cannot fail.
    if q == R::ZERO {
        // B = 0 and D = 0: a double root at 0 when C = 0, or no root (A = B = 0, C ≠ 0).
        if qc == R::ZERO {
            let _ = roots.push(R::ZERO);
        }
    } else {
        let _ = roots.push(q / qa);
        let _ = roots.push(qc / q);
    }
    roots
}

/// Smallest root of `A s² + B s + C` in `[0, 1]` (within a few ulps, then clamped), of
/// the [`stable_roots`].
pub fn smallest_root_in_unit<R: Real>(qa: R, qb: R, qc: R) -> Option<R> {
    let tol = R::from_f32(64.0) * R::EPSILON;
    let inside = |r: &R| r.is_finite() && *r >= -tol && *r <= R::ONE + tol;
    let roots = stable_roots(qa, qb, qc).into_iter().filter(inside);
    roots
        .map(|r| r.clamp_to(R::ZERO, R::ONE))
        .reduce(|a, b| if b < a { b } else { a })
}

/// Bilinear: along the segment the clearance is `A s² + B s + C` with `C = ca` and
/// `A + B + C = cb` (the shared edge values), and `A = −e·Δu·Δv` from the twist
/// `e = h00 − h10 − h01 + h11`. A ray parallel to a cell edge has `A = 0` exactly.
fn bilinear_segment<R: Real>(c: [R; 4], a: [R; 3], b: [R; 3], ca: R, cb: R) -> SegmentHit<R> {
    let e = c[0] - c[1] - c[2] + c[3];
    let qa = -e * (b[0] - a[0]) * (b[1] - a[1]);
    let qc = ca;
    let qb = cb - ca - qa;
    let mut clearance = ca.min(cb);
    let mut s = None;
    if cb <= R::ZERO {
        // A sign change: a root in (0, 1] exists; fall back on bisection if rounding
        // pushed the discriminant below zero.
        s = Some(smallest_root_in_unit(qa, qb, qc).unwrap_or_else(|| bisect(qa, qb, qc)));
    } else if qa > R::ZERO {
        // Both ends clear: the ray can still dip under a saddle between them.
        let vertex = -qb / (R::from_f32(2.0) * qa);
        if vertex > R::ZERO && vertex < R::ONE {
            let lowest = qc - qb * qb / (R::from_f32(4.0) * qa);
            clearance = clearance.min(lowest);
            if lowest <= R::ZERO {
                s = Some(smallest_root_in_unit(qa, qb, qc).unwrap_or(vertex));
            }
        }
    }
    let hit = s.map(|s| {
        let (u, v) = (a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s);
        (s, Surface::Bilinear.cell_normal(c, u, v), Flags::default())
    });
    // Up to its first root the quadratic has no minimum below min(ca, 0): nothing but `ca`.
    if hit.is_some() {
        clearance = ca;
    }
    SegmentHit { hit, clearance }
}

/// First sign change of `A s² + B s + C` on `[0, 1]` by bisection, given `C > 0 ≥ A+B+C`.
fn bisect<R: Real>(qa: R, qb: R, qc: R) -> R {
    let (mut lo, mut hi) = (R::ZERO, R::ONE);
    for _ in 0..64 {
        let mid = R::HALF * (lo + hi);
        if (qa * mid + qb) * mid + qc > R::ZERO {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The bilinear cell test by search, approximate: `linear` equal steps from `a` to `b`
/// (sampling), then `bisect` bisections of the first step that ends under the surface.
/// Qu et al.'s bilinear method (§3.3), and Tevs et al.'s iterative test. It misses a
/// dip under a saddle between two samples, and places a hit to `1 / (linear · 2^bisect)`
/// of the segment.
pub fn bilinear_search_segment<R: Real>(
    c: [R; 4],
    a: [R; 3],
    b: [R; 3],
    ca: R,
    cb: R,
    (linear, bisect): (u32, u32),
) -> SegmentHit<R> {
    let at = |s: R| {
        let p = [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * s);
        p[2] - bilinear(c, p[0], p[1])
    };
    let n = linear.max(1);
    let (mut lo, mut clearance) = (R::ZERO, ca);
    for k in 1..=n {
        let s = R::from_u32(k) / R::from_u32(n);
        let cs = if k == n { cb } else { at(s) };
        if cs <= R::ZERO {
            let mut hi = s;
            for _ in 0..bisect {
                let mid = R::HALF * (lo + hi);
                if at(mid) <= R::ZERO {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let (u, v) = (a[0] + (b[0] - a[0]) * hi, a[1] + (b[1] - a[1]) * hi);
            let normal = Surface::Bilinear.cell_normal(c, u, v);
            return SegmentHit {
                hit: Some((hi, normal, Flags::default())),
                clearance,
            };
        }
        clearance = clearance.min(cs);
        lo = s;
    }
    SegmentHit {
        hit: None,
        clearance,
    }
}

/// Height planes: the cell holds four constant quarters; the segment is split where it
/// crosses u = ½ and v = ½ and each piece tested against its quarter's height. Entering
/// a taller quarter below its top is a wall hit.
fn height_planes_segment<R: Real>(
    c: [R; 4],
    a: [R; 3],
    b: [R; 3],
    entry_wall: [R; 3],
) -> SegmentHit<R> {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    // Split parameters where u or v crosses ½, with the wall normal met there.
    let mut cuts: heapless::Vec<(R, [R; 3]), 2> = heapless::Vec::new();
    for axis in 0..2 {
        if d[axis] != R::ZERO {
            let s = (R::HALF - a[axis]) / d[axis];
            if s > R::ZERO && s < R::ONE {
                let mut n = [R::ZERO; 3];
                n[axis] = if d[axis] > R::ZERO { -R::ONE } else { R::ONE };
                // Capacity 2, two axes: never full.
                let _ = cuts.push((s, n));
            }
        }
    }
    if cuts.len() == 2 && cuts[1].0 < cuts[0].0 {
        cuts.swap(0, 1);
    }
    let mut clearance = R::INFINITY;
    let mut start = (R::ZERO, entry_wall);
    let ends = cuts
        .iter()
        .copied()
        .chain(core::iter::once((R::ONE, entry_wall)));
    for (end, next_wall) in ends {
        let mid = R::HALF * (start.0 + end);
        let h = c[nearest_corner(a[0] + d[0] * mid, a[1] + d[1] * mid)];
        let c0 = a[2] + d[2] * start.0 - h;
        let c1 = a[2] + d[2] * end - h;
        if c0 <= R::ZERO {
            let n = start.1;
            return SegmentHit {
                hit: Some((start.0, n, Flags::WALL)),
                clearance: clearance.min(-c0),
            };
        }
        clearance = clearance.min(c0);
        if c1 <= R::ZERO {
            let s = start.0 + (end - start.0) * c0 / (c0 - c1);
            return SegmentHit {
                hit: Some((s, [R::ZERO, R::ZERO, R::ONE], Flags::default())),
                clearance,
            };
        }
        clearance = clearance.min(c1);
        start = (end, next_wall);
    }
    SegmentHit {
        hit: None,
        clearance,
    }
}
