//! Qu et al. 2003 §4, the hybrid rasterization renderer of the linear approximation
//! (view-linear) surface, as a CPU march: the reference of its GPU implementation
//! (`c_tests/hybrid.c`, OSMesa and GLFW), ray by ray the same two passes.
//!
//! Every cell boundary, the vertical planes `x = i` and `y = j` over the footprint, is
//! one rectangle. Pass 1 tests the ray against every rectangle (a rasterizer's fragments:
//! the ray's crossing with each plane inside the footprint) and keeps the nearest
//! crossing `P2` where the ray is on or under the boundary's height (its two samples
//! interpolated, as the exact walk's crossings); pass 2 finds `P1`, the crossing before
//! `P2` on either axis or where the ray's span begins, and interpolates the clearances
//! `d1 > 0 ≥ d2`: `I = P1 + d1 / (d1 − d2) · (P2 − P1)`, the first hit on the view-linear
//! surface — the exact walk's hit ([`dda::trace`] on
//! [`Surface::ViewLinear`]), finished the same way. Cost: `W + H` boundary tests per ray,
//! two fetches for each crossing inside the footprint (the fragments), four in pass 2.

use crate::dda::{self, clip_surface};
use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::Surface;

/// The height of boundary `line` of axis `a` (0: the plane `x = line`) at point `p` on
/// it: its two samples around `p`'s other coordinate, interpolated.
fn boundary_height<R: Real>(hf: &HeightField, a: usize, line: u32, p: [R; 3]) -> R {
    let b = 1 - a;
    let lim = if b == 0 {
        hf.width() - 1
    } else {
        hf.height() - 1
    };
    let j = (p[b].max(R::ZERO).to_f64() as u32).min(lim - 1);
    let f = (p[b] - R::from_u32(j)).clamp_to(R::ZERO, R::ONE);
    let at = |k: u32| match a {
        0 => hf.at(line, k),
        _ => hf.at(k, line),
    };
    R::lerp(R::from_f32(at(j)), R::from_f32(at(j + 1)), f)
}

/// Pass 1: the nearest crossing on or under its boundary, `(t, axis, line)`, and the
/// crossings tested inside the footprint.
fn nearest_under<R: Real>(hf: &HeightField, q: &Query<R>) -> (Option<(R, usize, u32)>, u32) {
    let (o, d) = (q.origin(), q.dir());
    let count = [hf.width(), hf.height()];
    let (mut best, mut tested) = (None::<(R, usize, u32)>, 0u32);
    for a in 0..2 {
        let b = 1 - a;
        let lim = R::from_u32(count[b] - 1);
        if d[a] == R::ZERO {
            continue;
        }
        for line in 0..count[a] {
            let t = (R::from_u32(line) - o[a]) / d[a];
            if !(t >= q.t_min() && t <= q.t_max()) {
                continue;
            }
            let p = q.at(t);
            if !(p[b] >= R::ZERO && p[b] <= lim) {
                continue;
            }
            tested += 1;
            let nearer = best.is_none_or(|(bt, _, _)| t < bt);
            if nearer && p[2] - boundary_height(hf, a, line, p) <= R::ZERO {
                best = Some((t, a, line));
            }
        }
    }
    (best, tested)
}

/// The last line of axis `b` the ray crosses before `t2` (`d[b] ≠ 0`), and its `t`.
fn line_before<R: Real>(o: R, d: R, t2: R) -> (R, R) {
    let x = o + t2 * d;
    let s = if d > R::ZERO { R::ONE } else { -R::ONE };
    // ⌈x⌉ − 1 going up (the shim has no ceil: ⌈x⌉ = −⌊−x⌋, exactly), ⌊x⌋ + 1 down.
    let mut m = if d > R::ZERO {
        -(-x).floor() - R::ONE
    } else {
        x.floor() + R::ONE
    };
    for _ in 0..2 {
        if (m + s - o) / d < t2 {
            m = m + s;
        }
    }
    for _ in 0..2 {
        if (m - o) / d >= t2 {
            m = m - s;
        }
    }
    (m, (m - o) / d)
}

/// Traces `q` with both passes: the first hit on the view-linear surface. Two cases no
/// boundary crossing shows are settled in pass 2 as the exact walk settles them: a ray
/// already under the surface where its span begins hits there, and one that goes under
/// without crossing a boundary (a steep ray inside a cell) takes the span's end as P2.
pub fn trace<R: Real>(hf: &HeightField, q: &Query<R>) -> Trace<R> {
    let (found, tested) = nearest_under(hf, q);
    let fetches = 2 * tested + 4;
    let Some(span) = clip_surface(hf, Surface::ViewLinear, q) else {
        return Trace::miss(2 * tested, R::INFINITY);
    };
    let (o, d) = (q.origin(), q.dir());
    let lim = [hf.width() - 1, hf.height() - 1];
    // The clearance at parameter t: on boundary `on` (axis, line), else bilinear.
    let clearance = |t: R, on: Option<(usize, u32)>| {
        let p = q.at(t);
        let h = match on {
            Some((axis, line)) => boundary_height(hf, axis, line, p),
            None => Surface::Bilinear.height_at(hf, p[0], p[1]),
        };
        p[2] - h
    };
    let hit = |t: R, (normal, flags): ([R; 3], Flags), c: R| {
        let p = q.at(t);
        let cell = [0, 1].map(|k| (p[k].max(R::ZERO).to_f64() as u32).min(lim[k] - 1));
        let hit = Hit {
            t,
            point: R::v3(p),
            cell,
            normal: R::v3(normal),
            flags,
        };
        dda::finish(hf, Surface::ViewLinear, q, Trace::hit(hit, fetches, c))
    };
    let shaded = |t: R| {
        let p = q.at(t);
        (
            Surface::ViewLinear.normal_at(hf, p[0], p[1]),
            Flags::default(),
        )
    };
    // Under the surface where the span begins (a side entry on that side's boundary).
    let start_on = match span.entry {
        dda::Entry::Side(n) => {
            let axis = usize::from(n[0] == R::ZERO);
            Some((axis, if n[axis] > R::ZERO { lim[axis] } else { 0 }))
        }
        _ => None,
    };
    let c0 = clearance(span.t0, start_on);
    if c0 <= R::ZERO {
        let flags = match span.entry {
            dda::Entry::Side(n) => (n, Flags::SIDE),
            dda::Entry::Start => (shaded(span.t0).0, Flags::ORIGIN_INSIDE),
            dda::Entry::Top => shaded(span.t0),
        };
        return hit(span.t0, flags, -c0);
    }
    // P2: pass 1's crossing, else the span's end when under the surface there.
    let (t2, on2) = match found {
        Some((t, a, line)) => (t, Some((a, line))),
        None if clearance(span.t1, None) <= R::ZERO => (span.t1, None),
        None => return Trace::miss(fetches, R::INFINITY),
    };
    // P1: the last crossing before P2 on either axis, or the span's start.
    let (mut t1, mut on1) = (span.t0, start_on);
    for axis in 0..2 {
        if d[axis] != R::ZERO {
            let (m, t) = line_before(o[axis], d[axis], t2);
            if t >= t1 && m >= R::ZERO && m <= R::from_u32(lim[axis]) {
                (t1, on1) = (t, Some((axis, m.to_f64() as u32)));
            }
        }
    }
    let (d1, d2) = (clearance(t1, on1), clearance(t2, on2));
    let t = t1 + (t2 - t1) * (d1 / (d1 - d2));
    hit(t, shaded(t), d1)
}
