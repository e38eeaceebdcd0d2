//! The naive exact method: Amanatides–Woo grid traversal over cells with the exact
//! per-cell test of the chosen surface. In `f64` it is the test oracle; in `f32` the
//! fast path every accelerated method must beat.
//!
//! Watertight by construction: the clearance at each centerline crossing is computed
//! once, from the edge's two samples, and shared by the cells on both sides; for the
//! triangle surface hit-or-miss is decided from those values alone. Cell indices are
//! integers and every crossing's `t` is recomputed from them (`(X − o) / d`), so
//! nothing accumulates over long rays.

use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::{
    bilinear, bilinear_search_segment, corners, plane, triangle_planes, SegmentHit, Surface,
};

pub(crate) mod lanes;
pub use lanes::{trace_skipping_lanes, Walked, LANES};

/// How the traced part of a ray begins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Entry<R: Real> {
    /// At `t_min`, with the origin over (or under) the footprint.
    Start,
    /// Through a side of the footprint; the side's outward normal.
    Side([R; 3]),
    /// Through the top plane `z = max height`.
    Top,
}

/// The part of a ray worth tracing: `[t0, t1]` (always finite) where it is over the
/// footprint and not above the highest sample, ending early on downward rays once it
/// is certainly under the lowest sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span<R: Real> {
    /// First parameter to trace.
    pub t0: R,
    /// Last parameter to trace.
    pub t1: R,
    /// How the span begins.
    pub entry: Entry<R>,
}

/// Clips a query to the field's bounding box, `z` spanning the sample range (which
/// bounds every surface but corner planes: see [`clip_surface`]); `None` when the ray
/// misses it.
#[inline]
pub fn clip<R: Real>(hf: &HeightField, q: &Query<R>) -> Option<Span<R>> {
    clip_surface(hf, Surface::Triangles, q)
}

/// Clips a query to the box that holds `surface` over the field: the sample range in
/// `z`, widened for corner planes, whose plane reaches `h10 + h01 − h00` at a cell's far
/// corner and so may leave the sample range by up to its width; `None` when the ray
/// misses it. Inlined at every march's entry (the C API, which instantiates every
/// march, otherwise kept it a call).
#[inline(always)]
pub fn clip_surface<R: Real>(hf: &HeightField, surface: Surface, q: &Query<R>) -> Option<Span<R>> {
    let (o, d) = (q.origin(), q.dir());
    let (mut zmin, mut zmax) = (R::from_f32(hf.min_height()), R::from_f32(hf.max_height()));
    if surface == Surface::CornerPlanes {
        let range = zmax - zmin;
        (zmin, zmax) = (zmin - range, zmax + range);
    }
    // Where the ray crosses the top plane. A level or rising ray above the box (that
    // crosses it before `t_min`) misses whatever its footprint says: told first.
    let top = (zmax - o[2]) / d[2];
    if d[2] == R::ZERO && o[2] > zmax || d[2] > R::ZERO && top < q.t_min() {
        return None;
    }
    let lim = [R::from_u32(hf.width() - 1), R::from_u32(hf.height() - 1)];
    let (mut t0, mut t1, mut entry) = (q.t_min(), q.t_max(), Entry::Start);
    // The two axes in turn, written out (a loop over them indexes the arrays on the
    // stack).
    let mut slab = |axis: usize| {
        // The faces the ray enters and leaves the slab through, and the entry face's
        // outward normal, chosen before the two divisions (the same quotients as
        // dividing first, without a swap after). Level (`±0`; a query's direction is
        // never NaN), the ray stays in or out of the slab.
        let (enter, leave, out) = if d[axis] > R::ZERO {
            (R::ZERO, lim[axis], -R::ONE)
        } else if d[axis] < R::ZERO {
            (lim[axis], R::ZERO, R::ONE)
        } else {
            return !(o[axis] < R::ZERO || o[axis] > lim[axis]);
        };
        let near = (enter - o[axis]) / d[axis];
        let far = (leave - o[axis]) / d[axis];
        if near > t0 {
            t0 = near;
            let mut n = [R::ZERO; 3];
            n[axis] = out;
            entry = Entry::Side(n);
        }
        t1 = t1.min(far);
        true
    };
    // Past the footprint already: what follows only raises `t0` and lowers `t1` (never
    // NaN: a NaN bound moves neither), so the last test would fail too.
    if !(slab(0) && slab(1)) || t0 > t1 {
        return None;
    }
    if d[2] > R::ZERO {
        t1 = t1.min(top);
    } else if d[2] < R::ZERO {
        if top > t0 {
            t0 = top;
            entry = Entry::Top;
        }
        // Over the footprint only above the box: a miss, as the last test would say.
        if t0 > t1 {
            return None;
        }
        // Well under the lowest sample the ray is inside the solid: the hit comes first
        // (at `t0` when the ray already starts or enters the footprint down there).
        // With heights near ±10³⁸ the margin or the quotient overflows: the bound is
        // then the largest finite `t` (the footprint or the hit ends the ray before),
        // never `+∞`, which would leave a vertical ray into the solid untraceable.
        let margin = R::ONE + (zmax - zmin);
        t1 = t1.min(((zmin - margin - o[2]) / d[2]).max(t0).min(R::MAX));
    }
    // Both ends finite (a direction so small that the box lies beyond the largest
    // representable `t` cannot be traced in this precision: a miss); with `t0 ≤ t1`,
    // `t0 > −∞` and `t1 < +∞` say it in two compares.
    (t0 <= t1 && t0 > -R::INFINITY && t1 < R::INFINITY).then_some(Span { t0, t1, entry })
}

/// First cell index along one axis for coordinate `x` in `[0, cells]` moving with
/// direction `d`: a point on a cell boundary belongs to the cell the ray moves into.
#[inline]
pub(crate) fn cell_index<R: Real>(x: R, d: R, cells: u32) -> u32 {
    // Truncation is the floor for `x >= 0`; below, NaN included, both give 0. `x` lies
    // on a boundary (`floor(x) == x`) when it is the integer `i`, for `x < 2^32`;
    // beyond, `i` saturates and either way ends as `cells − 1`.
    let mut i = x.to_f64() as u32;
    if d < R::ZERO && R::from_u32(i) == x && i > 0 {
        i -= 1;
    }
    i.min(cells - 1)
}

/// Sign of a direction component as a cell step.
#[inline]
pub(crate) fn step_of<R: Real>(d: R) -> i64 {
    if d > R::ZERO {
        1
    } else if d < R::ZERO {
        -1
    } else {
        0
    }
}

/// Parameter of the next centerline crossing along one axis after cell `i`.
#[inline]
pub(crate) fn next_crossing<R: Real>(i: u32, step: i64, o: R, d: R) -> R {
    match step {
        1 => (R::from_u32(i + 1) - o) / d,
        -1 => (R::from_u32(i) - o) / d,
        _ => R::INFINITY,
    }
}

/// Local point `[u, v, z]` and clearance of the ray point `p` (grid space) in `cell`
/// with corners `c`. `on[axis] = Some(far)` when `p` is a centerline crossing on the
/// cell's edge at `u = 1` (`far`) or `u = 0` of that axis: the coordinate is then exact
/// and the height comes from that edge's two samples only (one at a corner), so both
/// cells sharing the edge compute the same clearance (watertight). Elsewhere the
/// surface's own cell height is used.
#[inline(always)]
pub(crate) fn local_clearance<R: Real>(
    surface: Surface,
    c: [R; 4],
    cell: [u32; 2],
    p: [R; 3],
    on: [Option<bool>; 2],
) -> ([R; 3], R) {
    let local = |axis: usize| match on[axis] {
        Some(far) => R::from_u32(u32::from(far)),
        None => (p[axis] - R::from_u32(cell[axis])).clamp_to(R::ZERO, R::ONE),
    };
    let b = [local(0), local(1), p[2]];
    // The samples of the edge x = fx at v = 0 and 1, of the edge y = fy at u = 0 and
    // 1, chosen without indexing `c` by a run-time value: that would keep the corners
    // in memory, copied there through a store the next read cannot forward from (14 %
    // of a 5° camera's march in the maximum mipmap's lanes).
    let x_edge = |fx: bool| if fx { (c[1], c[3]) } else { (c[0], c[2]) };
    let y_edge = |fy: bool| if fy { (c[2], c[3]) } else { (c[0], c[1]) };
    let height = match on {
        [Some(fx), Some(fy)] => {
            let (at_v0, at_v1) = x_edge(fx);
            if fy {
                at_v1
            } else {
                at_v0
            }
        }
        [Some(fx), None] => {
            let (at_v0, at_v1) = x_edge(fx);
            R::lerp(at_v0, at_v1, b[1])
        }
        [None, Some(fy)] => {
            let (at_u0, at_u1) = y_edge(fy);
            R::lerp(at_u0, at_u1, b[0])
        }
        [None, None] => surface.cell_height(c, b[0], b[1]),
    };
    (b, b[2] - height)
}

/// How the first point of `entry`'s span lies on its cell's edges, as
/// [`local_clearance`] takes it: through a side of the footprint the point is on that
/// side's edge (`u = 0` or `1` of that axis), so on a continuous surface its height
/// comes from the edge's two samples, as at every crossing; elsewhere, and on the
/// discontinuous surfaces (whose height at an edge is not the edge's interpolation),
/// from the cell's surface. At a side entry the cell's planes evaluated at a corner can
/// cancel catastrophically (heights near ±10³⁸ whose sum is a few units), where the
/// edge's two samples cannot.
#[inline]
pub(crate) fn entry_on<R: Real>(surface: Surface, entry: &Entry<R>) -> [Option<bool>; 2] {
    match entry {
        Entry::Side(n) if surface.is_continuous() => {
            [0, 1].map(|k| (n[k] != R::ZERO).then_some(n[k] > R::ZERO))
        }
        _ => [None; 2],
    }
}

/// [`Trace::clearance`] of a hit where the span begins, from the clearance `ca ≤ 0`
/// there: the depth `−ca` under the surface (how far the decision was from a miss)
/// when the ray starts or enters through a side down there; `+∞` when it enters
/// through the top of the box, having passed nothing before.
pub(crate) fn start_clearance<R: Real>(entry: &Entry<R>, ca: R) -> R {
    match entry {
        Entry::Top => R::INFINITY,
        Entry::Start | Entry::Side(_) => -ca,
    }
}

/// The hit of a ray already under the surface where its span begins (local point `a`
/// with clearance `≤ 0` in `cell`, grid point `p0`): at `t0`, flagged by how the span
/// begins.
#[inline]
pub(crate) fn start_hit<R: Real>(
    surface: Surface,
    span: &Span<R>,
    c: [R; 4],
    cell: [u32; 2],
    a: [R; 3],
    p0: [R; 3],
) -> Hit<R> {
    let (normal, flags) = match span.entry {
        Entry::Side(n) => (n, Flags::SIDE),
        Entry::Start => (surface.cell_normal(c, a[0], a[1]), Flags::ORIGIN_INSIDE),
        Entry::Top => (surface.cell_normal(c, a[0], a[1]), Flags::default()),
    };
    Hit {
        t: span.t0,
        point: R::v3(p0),
        cell,
        normal: R::v3(normal),
        flags,
    }
}

/// The hit at segment parameter `s` of `found` on `a → b` in `cell` (ray parameters
/// `ta`, `tb`), in the march's precision: the point from the cell's integer corner plus
/// local coordinates, as exact as `R` allows far from the origin, where `o + t · d`
/// loses an ulp of `t`.
#[inline(always)]
pub(crate) fn segment_point<R: Real>(
    cell: [u32; 2],
    ((ta, tb), (a, b)): ((R, R), ([R; 3], [R; 3])),
    (s, normal, flags): (R, [R; 3], Flags),
) -> Hit<R> {
    let local = |k: usize| a[k] + s * (b[k] - a[k]);
    Hit {
        t: ta + s * (tb - ta),
        point: R::v3([
            R::from_u32(cell[0]) + local(0),
            R::from_u32(cell[1]) + local(1),
            local(2),
        ]),
        cell,
        normal: R::v3(normal),
        flags,
    }
}

/// The robust finish of a trace in `R` (nothing to do in `f64`): the hit recomputed by
/// Newton's method on the clearance along the `f64` ray, `f(t) = z(t) − h(x(t), y(t))`
/// on the hit's cell, from the `R` hit ([`refine`]). Where the `R` march found the
/// right cell the point is then the `f64` oracle's, whatever the march's rounding of
/// its crossings (`f32` coordinates of ~1000 texels round to ~6e-5, which a slope of
/// 51 turns into 3e-3 of height), at the cost of one division per step, once per ray.
/// Every exact march ends here, so marches that reach the same `R` hit (the DDA and the
/// maximum mipmap) still agree bit for bit. The view-linear surface, whose height along
/// the ray is not a function of the point, is refined by its own definition instead:
/// the clearance is linear between the ends of the walk's segment in the cell, taken in
/// `f64`. Kept as found: hits where the span begins (origin inside, side entries),
/// walls (their `t` is a quotient `(X − o) / d` already), approximate hits (a budget
/// ran out), and a refinement that would leave the cell or `[t_min, t_max]` (a
/// near-touch the `R` march resolved differently from `f64`: an ambiguous ray by
/// docs/DESIGN.md's rule).
#[inline(always)]
pub(crate) fn finish<R: Real>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    mut trace: Trace<R>,
) -> Trace<R> {
    const KEPT: u32 =
        Flags::ORIGIN_INSIDE.0 | Flags::SIDE.0 | Flags::WALL.0 | Flags::BUDGET_EXHAUSTED.0;
    let Some(hit) = trace.hit.as_mut() else {
        return trace;
    };
    if R::EPSILON.to_f64() <= f64::EPSILON || (hit.flags.0 | trace.flags.0) & KEPT != 0 {
        return trace;
    }
    let c = corners(hf, hit.cell[0], hit.cell[1]);
    if let Some((t, point)) = refine(hf, surface, q, (hit.cell, c), hit.t) {
        (hit.t, hit.point) = (t, R::v3(point));
    }
    trace
}

/// [`finish`] past its early returns: Newton's steps in `f64` on `cell` (corners `c`)
/// from `t`, in the cell's frame (its corner at the origin), and the refined `t` and
/// point back in `R`; `None` when a step finds the ray level with the surface or the
/// result leaves the cell or `[t_min, t_max]`. A plane (a triangle, a linear or
/// height plane's top) takes one step, and the triangle surface a second only when the
/// upper of its two planes changed on the way; the bilinear patch takes two. Kept out
/// of line: once per ray, off every march's loop.
#[inline(never)]
fn refine<R: Real>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    (cell, c): ([u32; 2], [R; 4]),
    t: R,
) -> Option<(R, [R; 3])> {
    let corner = [f64::from(cell[0]), f64::from(cell[1])];
    let (o, d) = (q.origin().map(R::to_f64), q.dir().map(R::to_f64));
    let o = [o[0] - corner[0], o[1] - corner[1], o[2]];
    let c = c.map(R::to_f64);
    let at = |t: f64| [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
    // One step from `t`, where the clearance is `f` and the surface's gradient
    // `(gx, gy)`.
    let step = |t: f64, f: f64, (gx, gy): (f64, f64)| {
        let slope = d[2] - gx * d[0] - gy * d[1];
        (slope != 0.0).then(|| t - f / slope)
    };
    let t = t.to_f64();
    let t = match surface {
        Surface::Triangles => {
            let planes = triangle_planes(c);
            // The upper plane at `p` (the first on a tie, as `cell_gradient`) and the
            // two planes' heights there.
            let upper = |p: [f64; 3]| {
                let h = planes.map(|pl| plane(pl, p[0], p[1]));
                (usize::from(h[1] > h[0]), h)
            };
            let on = |k: usize, t: f64, p: [f64; 3], h: [f64; 2]| {
                step(t, p[2] - h[k], (planes[k][1], planes[k][2]))
            };
            let p = at(t);
            let (k, h) = upper(p);
            let t1 = on(k, t, p, h)?;
            let p1 = at(t1);
            match upper(p1) {
                (k1, h1) if k1 != k => on(k1, t1, p1, h1)?,
                _ => t1,
            }
        }
        Surface::ViewLinear => {
            // The walk's segment in the cell: the cell's crossings, clipped to the span
            // (the ray's own definition of the surface), its clearances in `f64`.
            let span = clip_surface(hf, surface, &q.cast::<f64>())?;
            let (mut ta, mut tb) = (span.t0, span.t1);
            for k in 0..2 {
                if d[k] != 0.0 {
                    let (t0, t1) = (-o[k] / d[k], (1.0 - o[k]) / d[k]);
                    (ta, tb) = (ta.max(t0.min(t1)), tb.min(t0.max(t1)));
                }
            }
            let clearance = |t: f64| {
                let p = at(t);
                p[2] - bilinear(c, p[0].clamp(0.0, 1.0), p[1].clamp(0.0, 1.0))
            };
            let (ca, cb) = (clearance(ta), clearance(tb));
            if !(ca > 0.0 && cb <= 0.0) {
                return None;
            }
            ta + (tb - ta) * (ca / (ca - cb))
        }
        _ => {
            let tangent = |t: f64| {
                let p = at(t);
                let f = p[2] - surface.cell_height(c, p[0], p[1]);
                step(t, f, surface.cell_gradient(c, p[0], p[1]))
            };
            let t1 = tangent(t)?;
            // The bilinear patch is curved; a step on Qu's triangles may land in the
            // cell's other triangle.
            match surface {
                Surface::Bilinear | Surface::QuTriangles => tangent(t1)?,
                _ => t1,
            }
        }
    };
    let p = at(t);
    // In the cell up to rounding of the local coordinates, and in `[t_min, t_max]`.
    const SLACK: f64 = 1e-9;
    let inside = |x: f64| (-SLACK..=1.0 + SLACK).contains(&x);
    let kept = inside(p[0]) && inside(p[1]) && t >= q.t_min().to_f64() && t <= q.t_max().to_f64();
    let point = [corner[0] + p[0], corner[1] + p[1], p[2]].map(R::from_f64);
    kept.then(|| (R::from_f64(t), point))
}

/// Traces `q` cell by cell and returns the exact first hit on `surface`.
///
/// Cost: four fetches (the corners) per cell visited.
pub fn trace<R: Real>(hf: &HeightField, surface: Surface, q: &Query<R>) -> Trace<R> {
    let test = |c, a, b, ca, cb, wall| surface.segment_hit(c, a, b, ca, cb, wall);
    let walked = walk::<R, false>(hf, surface, q, u32::MAX, test);
    finish(hf, surface, q, walked.expect("no budget"))
}

/// [`trace`] with a bound test first in each cell: a cell the ray passes over, above
/// its highest corner by a margin of rounding, is stepped over without its exact test.
/// The hit (t, point, cell, normal, flags) is [`trace`]'s bit for bit: a tested cell
/// gets the same entry point and clearance as there (both come from the crossing's
/// edge samples, shared by the cells on both sides), and a skipped one has no contact.
/// `clearance` is a lower bound of [`trace`]'s (a skipped cell reports the ray's
/// height above its highest corner). The coherent batches' march after their shared
/// start ([`crate::horizon`]).
///
/// Cost: four fetches (the corners) per cell visited.
pub fn trace_skipping<R: Real>(hf: &HeightField, surface: Surface, q: &Query<R>) -> Trace<R> {
    match trace_skipping_for(hf, surface, q, u32::MAX) {
        Ok(trace) | Err(Restart { trace, .. }) => trace,
    }
}

/// Where [`trace_skipping_for`] stopped without an answer: a `t` from which a march
/// (any exact one) has the same hit — the entry of a cell the ray passes above — and
/// what was spent before it (its fetches and the least clearance seen, a miss).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restart<R: Real> {
    /// The entry of the cell passed above.
    pub t: R,
    /// Fetches and clearance up to it.
    pub trace: Trace<R>,
}

/// [`trace_skipping`] for at most `cells` cells: when the walk passes above its cell
/// number `cells` still without an answer, where a march may go on from
/// ([`Restart`]; the maximum mipmap does, over long stretches of empty space).
pub fn trace_skipping_for<R: Real>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    cells: u32,
) -> Result<Trace<R>, Restart<R>> {
    let test = |c, a, b, ca, cb, wall| surface.segment_hit(c, a, b, ca, cb, wall);
    walk::<R, true>(hf, surface, q, cells, test).map(|trace| finish(hf, surface, q, trace))
}

/// How far a ray whose lowest height over a cell with corners `c` is `low` passes
/// above `surface` there, when it does by more than the rounding of the cell's exact
/// test: above its highest corner (corner planes reach `h10 + h01 − h00` at the far
/// corner, under the highest corner plus the corners' range) by 16 ulps of the larger
/// magnitude.
#[inline(always)]
fn passes_above<R: Real>(surface: Surface, c: [R; 4], low: R) -> Option<R> {
    let hi = c[0].max(c[1]).max(c[2].max(c[3]));
    let top = if surface == Surface::CornerPlanes {
        let lo = c[0].min(c[1]).min(c[2].min(c[3]));
        hi + (hi - lo)
    } else {
        hi
    };
    let above = low - top;
    (above > (top.abs() + low.abs()) * R::from_f32(16.0) * R::EPSILON).then_some(above)
}

/// Qu et al.'s bilinear method (§3.3), **approximate**: the cells of [`trace`] on the
/// bilinear surface, each tested by sampling and bisection
/// ([`bilinear_search_segment`]: `linear` samples, then `bisect` bisections) instead of
/// solving its quadratic. No robust finish: the hit is the search's.
pub fn trace_bilinear_search<R: Real>(
    hf: &HeightField,
    q: &Query<R>,
    (linear, bisect): (u32, u32),
) -> Trace<R> {
    let test = |c, a, b, ca, cb, _| bilinear_search_segment(c, a, b, ca, cb, (linear, bisect));
    walk::<R, false>(hf, Surface::Bilinear, q, u32::MAX, test).expect("no budget")
}

/// A walk's first cell, where its span begins (per-axis arrays: index 0 = x, 1 = y).
#[derive(Clone, Copy, Debug)]
pub(crate) struct First<R: Real> {
    /// The ray's span over the field.
    pub span: Span<R>,
    /// The ray's point at the span's start.
    pub p0: [R; 3],
    /// The cell holding it.
    pub cell: [u32; 2],
    /// The ray's cell steps ([`step_of`]).
    pub step: [i64; 2],
    /// The cell's corners.
    pub c: [R; 4],
    /// How the start lies on the cell's edges ([`entry_on`]).
    pub on: [Option<bool>; 2],
    /// The start's local point and clearance (`ca > 0`).
    pub a: [R; 3],
    /// See `a`.
    pub ca: R,
}

/// The first cell of `q`'s walk (four fetches), or the answer when there is no walk:
/// a miss of the box, or a hit where the span begins (the ray starts or enters under
/// the surface).
#[inline(always)]
pub(crate) fn first_cell<R: Real>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
) -> Result<First<R>, Trace<R>> {
    let Some(span) = clip_surface(hf, surface, q) else {
        return Err(Trace::MISS);
    };
    let d = q.dir();
    let cells = [hf.width() - 1, hf.height() - 1];
    let p0 = q.at(span.t0);
    let start = [0, 1].map(|k| p0[k].clamp_to(R::ZERO, R::from_u32(cells[k])));
    let cell = [0, 1].map(|k| cell_index(start[k], d[k], cells[k]));
    let step = [step_of(d[0]), step_of(d[1])];
    let c: [R; 4] = corners(hf, cell[0], cell[1]);
    let on = entry_on(surface, &span.entry);
    let (a, ca) = local_clearance(surface, c, cell, [start[0], start[1], p0[2]], on);
    if ca <= R::ZERO {
        return Err(Trace::hit(
            start_hit(surface, &span, c, cell, a, p0),
            4,
            start_clearance(&span.entry, ca),
        ));
    }
    Ok(First {
        span,
        p0,
        cell,
        step,
        c,
        on,
        a,
        ca,
    })
}

/// [`trace`] before the robust finish, with the cell test `test` (the arguments of
/// [`Surface::segment_hit`]); with `SKIP`, [`trace_skipping_for`]'s, stopping after
/// `budget` cells (only on a cell passed above).
#[inline(always)]
fn walk<R: Real, const SKIP: bool>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    budget: u32,
    test: impl Fn([R; 4], [R; 3], [R; 3], R, R, [R; 3]) -> SegmentHit<R>,
) -> Result<Trace<R>, Restart<R>> {
    let First {
        span,
        p0,
        mut cell,
        step,
        mut c,
        on,
        mut a,
        mut ca,
    } = match first_cell(hf, surface, q) {
        Ok(first) => first,
        Err(answer) => return Ok(answer),
    };
    let (o, d) = (q.origin(), q.dir());
    let cells = [hf.width() - 1, hf.height() - 1];
    let mut fetches = 4u32;
    let mut clearance = ca;
    let mut ta = span.t0;
    let mut wall = [R::ZERO, R::ZERO, R::ONE];
    let mut t_cross = [0, 1].map(|k| next_crossing(cell[k], step[k], o[k], d[k]));
    // Skipping: the point where the ray entered the cell, and how (`a` and `ca` are
    // then computed only for a cell that gets its exact test).
    let (mut pa, mut entered, mut fresh) = (p0, on, true);
    'walk: loop {
        let t_next = t_cross[0].min(t_cross[1]);
        let (tb, cross) = if t_next < span.t1 {
            (t_next.max(ta), t_cross.map(|t| t <= t_next))
        } else {
            (span.t1, [false; 2])
        };
        let pb = q.at(tb);
        // Clearance at the exit point; on a centerline, from that edge's two samples only.
        let on = [0, 1].map(|k| cross[k].then_some(step[k] > 0));
        let low = pa[2].min(pb[2]);
        let above = if SKIP {
            passes_above(surface, c, low)
        } else {
            None
        };
        let b = if let Some(above) = above {
            if fetches / 4 > budget {
                let trace = Trace::miss(fetches, clearance);
                return Err(Restart { t: ta, trace });
            }
            clearance = clearance.min(above);
            fresh = false;
            pb
        } else {
            if !fresh {
                (a, ca) = local_clearance(surface, c, cell, pa, entered);
            }
            let (b, cb) = local_clearance(surface, c, cell, pb, on);
            let seg = test(c, a, b, ca, cb, wall);
            clearance = clearance.min(seg.clearance);
            if let Some(found) = seg.hit {
                return Ok(Trace::hit(
                    segment_point(cell, ((ta, tb), (a, b)), found),
                    fetches,
                    clearance,
                ));
            }
            // The next cell's entry: this one's exit, seen from there.
            a = [0, 1, 2].map(|k| {
                if k < 2 && cross[k] {
                    R::ONE - b[k]
                } else {
                    b[k]
                }
            });
            (ca, fresh) = (cb, true);
            pb
        };
        if cross == [false; 2] {
            break;
        }
        for k in 0..2 {
            if cross[k] {
                let next = cell[k] as i64 + step[k];
                if next < 0 || next >= cells[k] as i64 {
                    break 'walk;
                }
                cell[k] = next as u32;
                t_cross[k] = next_crossing(cell[k], step[k], o[k], d[k]);
            }
        }
        // The face entered (x's when the ray passes exactly through a corner).
        let k = usize::from(!cross[0]);
        wall = [R::ZERO; 3];
        wall[k] = if step[k] > 0 { -R::ONE } else { R::ONE };
        c = corners(hf, cell[0], cell[1]);
        fetches += 4;
        (pa, entered, ta) = (b, [0, 1].map(|k| cross[k].then_some(step[k] < 0)), tb);
    }
    Ok(Trace::miss(fetches, clearance))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::maxmip::{self, MaxMip, Options};
    use alloc::vec;

    /// The fuzz finding `maxmip_side_wall` rebuilt: a 2 × 5 field whose sample (1, 3)
    /// is −1.7·10³⁸, the others near −24 and −5. A ray in the plane x = 0 enters
    /// through the side y = 4 at t = 6, 18 units above the corner (0, 4); evaluated
    /// from the cell's planes there, −1.7·10³⁸ cancelled into a wall (both precisions
    /// answered a side hit at t = 6), while the side's edge samples give −24.22. The
    /// real hit is on the edge x = 0 of cell (0, 2), at y = 42.84 / 19.92.
    #[test]
    fn side_entry_takes_its_height_from_the_edge_samples() {
        let heights = vec![
            -5.0,
            -5.0,
            -5.0,
            -5.0,
            -5.0,
            -5.0,
            -23.92,
            -1.701_463_5e38,
            -24.22,
            -23.92,
        ];
        let hf = HeightField::new(&heights, 2, 5, 2).unwrap();
        let want_y = 42.84 / 19.92;
        let want_t = 10.0 - want_y;
        let q = Query::<f64>::from_arrays([0.0, 10.0, 0.0], [0.0, -1.0, -1.0], 4.5, f64::INFINITY)
            .unwrap();
        for tr in [
            trace(&hf, Surface::Triangles, &q),
            trace(&hf, Surface::Bilinear, &q),
        ] {
            let h = tr.hit.expect("hits the edge x = 0");
            assert!(!h.flags.contains(Flags::SIDE), "{h:?}");
            assert!((h.t - want_t).abs() < 1e-3, "{h:?}");
        }
        let q32 = q.cast::<f32>();
        let mut pyramid = vec![0f32; maxmip::pyramid_len(2, 5)];
        maxmip::bake(&hf, &mut pyramid).unwrap();
        let mip = MaxMip::new(&hf, &pyramid).unwrap();
        for h in [
            trace(&hf, Surface::Triangles, &q32).hit,
            maxmip::trace(&hf, &mip, Surface::Triangles, &q32, &Options::default()).hit,
        ] {
            let h = h.expect("hits the edge x = 0");
            assert!(!h.flags.contains(Flags::SIDE), "{h:?}");
            assert!((f64::from(h.t) - want_t).abs() < 1e-3, "{h:?}");
        }
    }
}
