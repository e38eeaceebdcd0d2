//! Brute force over every cell, in `f64`: the oracle of the oracle, for small fields.
//!
//! Written independently of the traversal: no grid walk, no local coordinates, no
//! shared crossings. The solid under the triangle, corner-plane, height-plane and Qu
//! triangle surfaces is a union of convex pieces (a cell's, quarter's or half-cell's
//! column cut by one plane);
//! the first hit is the smallest entry parameter over all pieces. Bilinear cells solve
//! their quadratic in the global ray parameter. The view-linear surface, being defined
//! by the ray's own crossings, is checked by listing every crossing and sorting them.

use crate::dda::clip;
use crate::field::HeightField;
use crate::ray::Query;
use crate::surface::{fixed_diagonal_planes, smallest_root_in_unit, triangle_planes, Surface};

/// `[lo, hi]` of `t` with `lo_x ≤ o + t·d ≤ hi_x`, intersected with `range`.
///
/// A ray that does not move along this axis and lies exactly on `hi` belongs to the
/// next cell (or quarter), not this one, unless `keep_hi` (the footprint's far side):
/// on a step of a discontinuous surface ties go to the larger index, as in
/// `Surface::HeightPlanes` and the traversal's cell choice.
fn slab(o: f64, d: f64, lo: f64, hi: f64, keep_hi: bool, range: (f64, f64)) -> Option<(f64, f64)> {
    let (mut a, mut b) = range;
    if d == 0.0 {
        if o < lo || o > hi || (o == hi && !keep_hi) {
            return None;
        }
    } else {
        let (p, q) = ((lo - o) / d, (hi - o) / d);
        a = a.max(p.min(q));
        b = b.min(p.max(q));
    }
    (a <= b).then_some((a, b))
}

/// `[lo, hi]` with `g0 + g1·t ≤ 0`, intersected with `range`.
fn below(g0: f64, g1: f64, range: (f64, f64)) -> Option<(f64, f64)> {
    let (mut a, mut b) = range;
    if g1 == 0.0 {
        if g0 > 0.0 {
            return None;
        }
    } else if g1 > 0.0 {
        b = b.min(-g0 / g1);
    } else {
        a = a.max(-g0 / g1);
    }
    (a <= b).then_some((a, b))
}

/// First parameter at which the ray of `q` is inside the solid under `surface`, and
/// the cell holding it.
pub fn first_hit(hf: &HeightField, surface: Surface, q: &Query<f64>) -> Option<(f64, [u32; 2])> {
    if surface == Surface::ViewLinear {
        return view_linear_first_hit(hf, q);
    }
    let (o, d) = (q.origin(), q.dir());
    let mut best: Option<(f64, [u32; 2])> = None;
    let mut offer = |t: f64, cell: [u32; 2]| {
        if best.is_none_or(|(b, _)| t < b) {
            best = Some((t, cell));
        }
    };
    for j in 0..hf.height() - 1 {
        for i in 0..hf.width() - 1 {
            let (x0, y0) = (i as f64, j as f64);
            let (last_x, last_y) = (i + 2 == hf.width(), j + 2 == hf.height());
            let range = (q.t_min(), q.t_max());
            let Some(cell_range) = slab(o[0], d[0], x0, x0 + 1.0, last_x, range)
                .and_then(|r| slab(o[1], d[1], y0, y0 + 1.0, last_y, r))
            else {
                continue;
            };
            let c = hf.cell_corners(i, j).map(f64::from);
            // Clearance of a plane h0 + gu (x − x0) + gv (y − y0) as g0 + g1·t.
            let plane_clearance = |p: [f64; 3]| {
                let g0 = o[2] - p[0] - p[1] * (o[0] - x0) - p[2] * (o[1] - y0);
                let g1 = d[2] - p[1] * d[0] - p[2] * d[1];
                (g0, g1)
            };
            match surface {
                Surface::Triangles | Surface::CornerPlanes => {
                    let planes = if surface == Surface::Triangles {
                        triangle_planes(c)
                    } else {
                        [
                            [c[0], c[1] - c[0], c[2] - c[0]],
                            [c[0], c[1] - c[0], c[2] - c[0]],
                        ]
                    };
                    for p in planes {
                        let (g0, g1) = plane_clearance(p);
                        if let Some((t, _)) = below(g0, g1, cell_range) {
                            offer(t, [i, j]);
                        }
                    }
                }
                Surface::HeightPlanes => {
                    for (k, &h) in c.iter().enumerate() {
                        let (qx, qy) = (x0 + 0.5 * (k & 1) as f64, y0 + 0.5 * (k >> 1) as f64);
                        let r = slab(o[0], d[0], qx, qx + 0.5, k & 1 == 1, cell_range)
                            .and_then(|r| slab(o[1], d[1], qy, qy + 0.5, k >> 1 == 1, r))
                            .and_then(|r| below(o[2] - h, d[2], r));
                        if let Some((t, _)) = r {
                            offer(t, [i, j]);
                        }
                    }
                }
                Surface::QuTriangles => {
                    // The triangle (00, 10, 11) holds u − v ≥ 0, (00, 01, 11) u − v ≤ 0.
                    let g0 = (o[0] - x0) - (o[1] - y0);
                    let g1 = d[0] - d[1];
                    for (k, p) in fixed_diagonal_planes(c).into_iter().enumerate() {
                        let side = if k == 0 { -1.0 } else { 1.0 };
                        let (h0, h1) = plane_clearance(p);
                        let r =
                            below(side * g0, side * g1, cell_range).and_then(|r| below(h0, h1, r));
                        if let Some((t, _)) = r {
                            offer(t, [i, j]);
                        }
                    }
                }
                Surface::Bilinear => {
                    if let Some(t) = bilinear_cell(c, [o[0] - x0, o[1] - y0, o[2]], d, cell_range) {
                        offer(t, [i, j]);
                    }
                }
                Surface::ViewLinear => unreachable!("handled above"),
            }
        }
    }
    best
}

/// First `t` in `range` where the ray (origin `o` relative to the cell corner) is on or
/// under the bilinear patch `c`.
fn bilinear_cell(c: [f64; 4], o: [f64; 3], d: [f64; 3], range: (f64, f64)) -> Option<f64> {
    let (a, b, e) = (c[1] - c[0], c[2] - c[0], c[0] - c[1] - c[2] + c[3]);
    let g2 = -e * d[0] * d[1];
    let g1 = d[2] - a * d[0] - b * d[1] - e * (o[0] * d[1] + o[1] * d[0]);
    let g0 = o[2] - c[0] - a * o[0] - b * o[1] - e * o[0] * o[1];
    let g = |t: f64| (g2 * t + g1) * t + g0;
    let (lo, hi) = range;
    if g(lo) <= 0.0 {
        return Some(lo);
    }
    // Map [lo, hi] to [0, 1] (hi is finite unless the ray is vertical, where g2 = 0).
    if !hi.is_finite() {
        return below(g0, g1, range).map(|r| r.0);
    }
    let w = hi - lo;
    let (qa, qb, qc) = (g2 * w * w, (2.0 * g2 * lo + g1) * w, g(lo));
    smallest_root_in_unit(qa, qb, qc).map(|s| lo + s * w)
}

/// View-linear: clearances at every centerline crossing (found by enumerating integer
/// coordinates, not by walking cells), sorted by `t`, interpolated linearly.
fn view_linear_first_hit(hf: &HeightField, q: &Query<f64>) -> Option<(f64, [u32; 2])> {
    let span = clip(hf, q)?;
    let (o, d) = (q.origin(), q.dir());
    let mut ts = alloc::vec![span.t0, span.t1];
    for axis in 0..2 {
        if d[axis] == 0.0 {
            continue;
        }
        let n = if axis == 0 { hf.width() } else { hf.height() };
        for k in 0..n {
            let t = (k as f64 - o[axis]) / d[axis];
            if t > span.t0 && t < span.t1 {
                ts.push(t);
            }
        }
    }
    ts.sort_by(|a, b| a.total_cmp(b));
    let surf = Surface::Bilinear; // equal to view-linear on centerlines
    let clearance = |t: f64| {
        let p = q.at(t);
        p[2] - surf.height_at(hf, p[0], p[1])
    };
    let mut prev = (ts[0], clearance(ts[0]));
    let cell_at = |t: f64| {
        let p = q.at(t);
        crate::surface::locate(hf, p[0], p[1]).3
    };
    if prev.1 <= 0.0 {
        return Some((prev.0, cell_at(prev.0)));
    }
    for &t in &ts[1..] {
        let c = clearance(t);
        if c <= 0.0 {
            let th = prev.0 + (t - prev.0) * prev.1 / (prev.1 - c);
            return Some((th, cell_at(0.5 * (prev.0 + t))));
        }
        prev = (t, c);
    }
    None
}
