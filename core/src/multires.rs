//! Multiresolution traversal (Qu et al. 2003 §3, after Cohen-Or et al. 1996),
//! **approximate**: the grid walk of [`dda::trace`](crate::dda::trace) on coarser grids as
//! the ray goes farther, where a pixel's footprint is wider than their cells.
//!
//! Level `ℓ` is the field sampled every `2^ℓ` samples: its cells are the squares
//! `[i·2^ℓ, (i+1)·2^ℓ] × [j·2^ℓ, (j+1)·2^ℓ]` of the grid, the last of a row or column
//! cut at the field's edge, each with the surface of its four corner samples (no
//! filtering, no bake: a coarse cell reads the four samples at its corners). At distance
//! `dist` from the ray's origin the march uses level `⌊log₂(dist / R)⌋` (0 under `2R`,
//! capped where a cell spans the field), `R` being the distance at which one pixel's
//! footprint is one texel: the reciprocal of the pixel angle, in grid units. Coarse
//! cells nest in finer ones, so the walk only ever switches to a coarser level, at a cell
//! boundary, and keeps its integer cell indices (a finer index shifted right). With `R`
//! beyond every distance the march is the exact traversal's walk on level 0 (same hits up
//! to rounding, no robust finish).

use crate::dda::{cell_index, clip_surface, step_of, Entry};
use crate::field::HeightField;
use crate::math::{normal_from_gradient, Real};
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::Surface;

/// The level at distance `dist` for the one-texel distance `range`: `⌊log₂(dist /
/// range)⌋`, 0 under `2 · range`, at most `top`.
#[inline]
pub fn level_at<R: Real>(dist: R, range: R, top: u32) -> u32 {
    let v = (dist / range).to_f64();
    if v >= 2.0 {
        (v.min(f64::from(u32::MAX)) as u32).ilog2().min(top)
    } else {
        0
    }
}

/// The coarsest useful level of a field whose samples span `lim` grid units per axis: the
/// first whose cell covers the longer axis.
fn top_level(lim: [u32; 2]) -> u32 {
    lim[0].max(lim[1]).max(1).next_power_of_two().ilog2()
}

/// The grid coordinates `[lo, hi]` of cell `i` of level `size` (a power of two) along an
/// axis of `lim` grid units.
#[inline]
fn bounds(i: u32, size: u32, lim: u32) -> (u32, u32) {
    let lo = i * size;
    (lo, (lo + size).min(lim))
}

/// Traces `q` on `surface` with the multiresolution walk for the one-texel distance
/// `range` (grid units along the ray; 0 is taken as 1). Cost: four fetches (the
/// corners) per cell of any level.
pub fn trace<R: Real>(hf: &HeightField, surface: Surface, q: &Query<R>, range: u32) -> Trace<R> {
    let Some(span) = clip_surface(hf, surface, q) else {
        return Trace::MISS;
    };
    let (o, d) = (q.origin(), q.dir());
    let lim = [hf.width() - 1, hf.height() - 1];
    let top = top_level(lim);
    let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let range = R::from_u32(range.max(1));
    let level_of = |t: R| level_at(t.max(R::ZERO) * length, range, top);
    let step = [step_of(d[0]), step_of(d[1])];
    let p0 = q.at(span.t0);
    let mut level = level_of(span.t0);
    let mut cell = [0, 1].map(|k| {
        let x = p0[k].clamp_to(R::ZERO, R::from_u32(lim[k]));
        cell_index(x, d[k], lim[k]) >> level
    });
    let (mut ta, mut fetches, mut clearance) = (span.t0, 0u32, R::INFINITY);
    let mut wall = match span.entry {
        Entry::Side(n) => n,
        Entry::Start | Entry::Top => [R::ZERO, R::ZERO, R::ONE],
    };
    loop {
        let size = 1u32 << level;
        let b = [0, 1].map(|k| bounds(cell[k], size, lim[k]));
        // Where the ray leaves the cell along each axis.
        let exit = [0, 1].map(|k| match step[k] {
            1 => (R::from_u32(b[k].1) - o[k]) / d[k],
            -1 => (R::from_u32(b[k].0) - o[k]) / d[k],
            _ => R::INFINITY,
        });
        let t_next = exit[0].min(exit[1]);
        let tb = if t_next < span.t1 {
            t_next.max(ta)
        } else {
            span.t1
        };
        let c = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(x, y)| {
            let i = if x == 0 { b[0].0 } else { b[0].1 };
            let j = if y == 0 { b[1].0 } else { b[1].1 };
            R::from_f32(hf.at(i, j))
        });
        fetches += 4;
        let extent = [0, 1].map(|k| R::from_u32(b[k].1 - b[k].0));
        let local = |t: R| {
            let p = q.at(t);
            let uv = [0, 1]
                .map(|k| ((p[k] - R::from_u32(b[k].0)) / extent[k]).clamp_to(R::ZERO, R::ONE));
            [uv[0], uv[1], p[2]]
        };
        let (a, bb) = (local(ta), local(tb));
        let ca = a[2] - surface.cell_height(c, a[0], a[1]);
        // The normal at local (u, v): the cell's gradient scaled to grid units.
        let normal = |u: R, v: R| {
            let (gx, gy) = surface.cell_gradient(c, u, v);
            normal_from_gradient(gx / extent[0], gy / extent[1])
        };
        let fine = |p: [R; 3]| [0, 1].map(|k| (p[k].max(R::ZERO).to_f64() as u32).min(lim[k] - 1));
        if ca <= R::ZERO {
            // Under the surface where this cell's segment begins: at the span's start, as
            // the exact march flags it; later, a coarser cell rose over the ray.
            let p = q.at(ta);
            let (n, flags) = match (ta == span.t0, span.entry) {
                (true, Entry::Side(n)) => (n, Flags::SIDE),
                (true, Entry::Start) => (normal(a[0], a[1]), Flags::ORIGIN_INSIDE),
                _ => (normal(a[0], a[1]), Flags::default()),
            };
            let hit = Hit {
                t: ta,
                point: R::v3(p),
                cell: fine(p),
                normal: R::v3(n),
                flags,
            };
            return Trace::hit(hit, fetches, clearance.min(-ca));
        }
        let cb = bb[2] - surface.cell_height(c, bb[0], bb[1]);
        let seg = surface.segment_hit(c, a, bb, ca, cb, wall);
        clearance = clearance.min(seg.clearance);
        if let Some((s, _, flags)) = seg.hit {
            let t = ta + s * (tb - ta);
            let p = q.at(t);
            let u = a[0] + s * (bb[0] - a[0]);
            let v = a[1] + s * (bb[1] - a[1]);
            let n = if flags.contains(Flags::WALL) {
                wall
            } else {
                normal(u, v)
            };
            let hit = Hit {
                t,
                point: R::v3(p),
                cell: fine(p),
                normal: R::v3(n),
                flags,
            };
            return Trace::hit(hit, fetches, clearance);
        }
        if t_next >= span.t1 {
            return Trace::miss(fetches, clearance);
        }
        for k in 0..2 {
            if exit[k] <= t_next {
                let next = i64::from(cell[k]) + step[k];
                if next < 0 || next as u64 * u64::from(size) >= u64::from(lim[k]) {
                    return Trace::miss(fetches, clearance);
                }
                cell[k] = next as u32;
            }
        }
        // The face entered (x's when the ray passes exactly through a corner).
        let k = usize::from(exit[0] > t_next);
        wall = [R::ZERO; 3];
        wall[k] = if step[k] > 0 { -R::ONE } else { R::ONE };
        ta = tb;
        let coarser = level_of(tb);
        if coarser > level {
            cell = cell.map(|i| i >> (coarser - level));
            level = coarser;
        }
    }
}
