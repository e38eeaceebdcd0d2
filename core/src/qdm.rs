//! Quadratic displacement maps (after Kiglics, Valasek, Bálint, Bán): per cell a cone
//! `(a, b)` topped by a revolved parabola `c`, over the cell's top `h` — four channels
//! `[a, b, c, h]` ([`CHANNELS`]). The bake and the march side by side.
//!
//! **Bound.** With `ρ` the horizontal distance to the cell's footprint, the *radial
//! maximum function* `m(ρ)` is the highest surface point (above `h`) at distance `≤ ρ`;
//! the texel stores an upper bound `F(ρ) ≥ m(ρ)` that is concave and non-decreasing:
//! the cone `F = ρ / a` up to height `b` (the cone of [`crate::cone`], `a` its ratio),
//! then the parabola tangent to it, `F = b + x/a − c x²` with `x = ρ − a b`, up to its
//! top, then the plateau `b + 1 / (4 a² c)`. With `P = max − h` the height of the
//! field's top above the cell, `c = 1 / (4 a² (P − b))`, so the plateau is `P` and the
//! one free parameter is the *height ratio* `β = b / P`: the smallest `b` for which the
//! bound holds is baked (the parabolas inscribed between the cone line and the plateau
//! rise with `b`, so the bound is monotone in `b`). Empty space above `h + F(ρ)` is a
//! solid of revolution that opens up near the top of the field, where cones stay thin.
//!
//! **Bake.** `a` from [`crate::cone::ratio_search`]; then `b` by the pyramid search of
//! [`crate::cone::bnb_by`]: a node of height `M` at box distance `d` (directional lower
//! bound) needs `b ≥ M − h` or `F_b(d) ≥ M − h`; below `a b` the cone certifies every
//! point. The least such `b` per node comes from bisection in `f64`; `b` is rounded up,
//! `c` (from the rounded `b`) down: both only raise `F`. Both searches start from the
//! cells that set the previous texel ([`texel_search`]). [`bake_brute`] visits every
//! cell (the test oracle).
//!
//! **March** ([`trace`]). Above `h`, the ray may advance until it meets `h + F(ρ)`
//! around its current point: the first root of a line against the cone, then against
//! the parabola — a quadratic solved without cancellation ([`solve_stable`], the
//! paper's Algorithm 2; [`solve_textbook`] is kept to show why) — then against the
//! plateau. Otherwise, and for steps that stay in the cell, the exact cell test of
//! [`crate::cone::march`].

// `!(x > 0)` is meant: it is true for NaN too, which must not step.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use core::ops::Range;

use core::cell::Cell;

use crate::cone::{self, bnb_by, check, f32_down, f32_up, march, margin, BakeError, Step};
use crate::field::HeightField;
use crate::math::Real;
use crate::maxmip::MaxMip;
use crate::ray::{Query, Trace};
use crate::surface::stable_roots;

/// Channels per texel: `[a, b, c, h]`.
pub const CHANNELS: usize = 4;

/// Largest stored curvature (the plateau right at the cone's top).
pub const C_MAX: f32 = 1.0e30;

/// Length of a QDM for a `width × height` field.
pub fn map_len(width: u32, height: u32) -> usize {
    CHANNELS * cone::cell_count(width, height)
}

/// Length of the bake scratch (the max pyramid).
pub fn scratch_len(width: u32, height: u32) -> usize {
    cone::scratch_len(width, height)
}

/// The bound `F(ρ)` of a texel with cone ratio `a`, cone height `b`, curvature `c`.
pub fn bound(a: f64, b: f64, c: f64, rho: f64) -> f64 {
    if a <= 0.0 {
        return if rho > 0.0 {
            b + 0.25 / (a * a * c)
        } else {
            0.0
        };
    }
    let x = rho - a * b;
    if x <= 0.0 {
        return rho / a;
    }
    let xp = 0.5 / (a * c);
    if x >= xp {
        b + 0.25 / (a * a * c)
    } else {
        b + x / a - c * x * x
    }
}

/// `F_b(d)` for the bake: curvature from `b` and the plateau `p`.
fn bound_b(a: f64, p: f64, b: f64, d: f64) -> f64 {
    if b >= p {
        return (d / a).min(p);
    }
    // The plateau is `p` exactly (the closed form of `bound` rounds).
    let x = d - a * b;
    if x <= 0.0 {
        d / a
    } else if x >= 2.0 * a * (p - b) {
        p
    } else {
        b + x / a - 0.25 / (a * a * (p - b)) * x * x
    }
}

/// Least `b ∈ [0, e]` with `F_b(d) ≥ e` for cone ratio `a` and plateau `p` (`e` when
/// only `b ≥ e` works): what a region at box distance `d`, `e` above the top, needs.
pub fn required(a: f64, p: f64, d: f64, e: f64) -> f64 {
    if e <= 0.0 {
        return 0.0;
    }
    if a <= 0.0 || bound_b(a, p, e, d) < e {
        return e;
    }
    if bound_b(a, p, 0.0, d) >= e {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0f64, e);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if bound_b(a, p, mid, d) >= e {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The texel `[a, b, c, h]` of cell `c` from its cone ratio `a` (rounded) and `b`.
fn pack(hf: &HeightField, top: f32, a: f32, b: f64) -> [f32; 4] {
    let p = hf.max_height() as f64 - top as f64;
    let b32 = f32_up(b.min(p.max(0.0)));
    let rest = p - b32 as f64;
    let c = if a <= 0.0 || rest <= 0.0 {
        C_MAX
    } else {
        f32_down(0.25 / ((a as f64) * (a as f64) * rest)).min(C_MAX)
    };
    [a, b32, c, top]
}

/// The texel of cell `c`, searched over the pyramid.
pub fn texel(hf: &HeightField, mip: &MaxMip, c: [u32; 2]) -> [f32; 4] {
    texel_search(hf, mip, c, [c, c]).0
}

/// [`texel`] of cell `c`, and the cells that set its `a` and its `b` (for the next
/// texel's `hints`: any cells, a neighbour's are good guesses). `a` comes from
/// [`cone::ratio_search`]; `b` is the largest [`required`] height over the cells, and
/// the search starts from the `b` that cell `hints[1]` requires: one of the terms of
/// the maximum, so it changes no result. A node is skipped when it cannot raise `b`:
/// its excess `e = max − h` is at most `b` (a cell below needs at most its own excess),
/// or `F_b` already covers `e` at the node's distance (the pruning of the module notes,
/// unchanged). Nodes highest above the cone line `d / a` go first.
pub fn texel_search(
    hf: &HeightField,
    mip: &MaxMip,
    c: [u32; 2],
    hints: [[u32; 2]; 2],
) -> ([f32; 4], [[u32; 2]; 2]) {
    let top = mip.texel(0, c[0], c[1]);
    let (ratio, arg_a) = cone::ratio_search(hf, mip, c, hints[0]);
    let a = f32_down(ratio);
    let a64 = a as f64;
    let p = hf.max_height() as f64 - top as f64;
    let src = [
        c[0] as f64,
        c[0] as f64 + 1.0,
        c[1] as f64,
        c[1] as f64 + 1.0,
    ];
    let need = |d: f64, m: f32| required(a64, p, d, m as f64 - top as f64);
    let h = hints[1];
    let d = cone::box_dist(src, [h[0], h[0] + 1], [h[1], h[1] + 1]);
    let best = Cell::new(need(d, mip.texel(0, h[0], h[1])));
    let mut arg = h;
    let key = |d: f64, m: f32| {
        let (e, b) = (m as f64 - top as f64, best.get());
        if e <= b || (a > 0.0 && bound_b(a64, p, b, d) >= e) {
            f64::INFINITY
        } else if a > 0.0 {
            d / a64 - e
        } else {
            -e
        }
    };
    bnb_by(mip, src, key, |cell, d, m| {
        let r = need(d, m);
        if r > best.get() {
            best.set(r);
            arg = cell;
        }
    });
    (pack(hf, top, a, best.get()), [arg_a, arg])
}

/// Bakes the cone pyramid into `scratch` (see [`crate::cone::prepare`]).
pub fn prepare(hf: &HeightField, scratch: &mut [f32]) -> Result<(), BakeError> {
    cone::prepare(hf, scratch)
}

/// The QDM, one texel `[a, b, c, h]` per cell: its [`cone::Family`] member, baked by
/// [`cone::bake_rows`] and [`cone::bake`] from the pyramid [`prepare`] bakes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Qdm;

impl cone::Family for Qdm {
    const CHANNELS: usize = CHANNELS;

    fn texels(width: u32, height: u32) -> [u32; 2] {
        [width - 1, height - 1]
    }

    fn bake_texel_rows(hf: &HeightField, mip: &MaxMip, rows: Range<u32>, out: &mut [f32]) {
        let cw = hf.width() - 1;
        // Each search starts from the cells that set the previous texel.
        let mut hints = [[0, rows.start]; 2];
        for (r, j) in rows.enumerate() {
            for i in 0..cw {
                let k = CHANNELS * (r * cw as usize + i as usize);
                let (tex, arg) = texel_search(hf, mip, [i, j], hints);
                hints = arg;
                out[k..k + 4].copy_from_slice(&tex);
            }
        }
    }
}

/// The brute force (every cell against every cell; `a` from the cone map's brute
/// force): the test oracle of the bake.
pub fn bake_brute(hf: &HeightField, out: &mut [f32]) -> Result<(), BakeError> {
    let (cw, ch) = (hf.width() - 1, hf.height() - 1);
    check(map_len(hf.width(), hf.height()), out.len())?;
    for j in 0..ch {
        for i in 0..cw {
            let top = hf.cell_corners(i, j).into_iter().fold(f32::MIN, f32::max);
            let mut a = cone::RATIO_MAX as f64;
            for dj in 0..ch {
                for di in 0..cw {
                    a = a.min(cone::cell_bound(hf, [i, j], top, [di, dj]));
                }
            }
            let a = f32_down(a);
            let p = hf.max_height() as f64 - top as f64;
            let mut b = 0.0f64;
            for dj in 0..ch {
                for di in 0..cw {
                    let m = hf.cell_corners(di, dj).into_iter().fold(f32::MIN, f32::max);
                    let gx = cone::gap(i as f64, i as f64 + 1.0, di as f64, di as f64 + 1.0);
                    let gy = cone::gap(j as f64, j as f64 + 1.0, dj as f64, dj as f64 + 1.0);
                    let e = m as f64 - top as f64;
                    if e > b {
                        b = b.max(required(a as f64, p, cone::dist_lb(gx, gy), e));
                    }
                }
            }
            let k = CHANNELS * (j as usize * cw as usize + i as usize);
            out[k..k + 4].copy_from_slice(&pack(hf, top, a, b));
        }
    }
    Ok(())
}

/// A baked QDM: texels `[a, b, c, h]` (a [`cone::CellMap`] of [`CHANNELS`] floats).
pub type QdmMap<'a> = cone::CellMap<'a, CHANNELS>;

/// Smallest root `x ≥ 0` of `A x² + B x + C`, of the roots computed without
/// cancellation ([`stable_roots`]: the QDM paper's Algorithm 2).
pub fn solve_stable<R: Real>(qa: R, qb: R, qc: R) -> Option<R> {
    let ahead = |r: &R| r.is_finite() && *r >= R::ZERO;
    let roots = stable_roots(qa, qb, qc).into_iter().filter(ahead);
    roots.reduce(|a, b| if b < a { b } else { a })
}

/// Smallest root `x ≥ 0` of `A x² + B x + C` by the textbook formula
/// `(−B ± √D) / 2A`: loses the small root to cancellation when `4AC ≪ B²` (nearly
/// flat parabolas, grazing rays). Kept for the tests that show it.
pub fn solve_textbook<R: Real>(qa: R, qb: R, qc: R) -> Option<R> {
    let disc = qb * qb - R::from_f32(4.0) * qa * qc;
    if disc < R::ZERO {
        return None;
    }
    let sq = disc.sqrt();
    let two_a = R::from_f32(2.0) * qa;
    let mut best: Option<R> = None;
    for r in [(-qb - sq) / two_a, (-qb + sq) / two_a] {
        if r.is_finite() && r >= R::ZERO && best.is_none_or(|b| r < b) {
            best = Some(r);
        }
    }
    best
}

/// Horizontal distance `ρ` the ray (height `e0` above `h`, rise `g` per unit of
/// horizontal distance) may go before it meets `F(ρ)`; `None`: never.
pub fn free_distance<R: Real>(tex: [R; 4], e0: R, g: R) -> Option<R> {
    let [a, b, c, _] = tex;
    let inv_a = R::ONE / a;
    let k = inv_a - g;
    let ab = a * b;
    if k > R::ZERO {
        let rho = e0 / k;
        if rho <= ab {
            return Some(rho);
        }
    }
    let xp = R::HALF / (a * c);
    if let Some(x) = solve_stable(c, g - inv_a, e0 + g * ab - b) {
        if x <= xp {
            return Some(ab + x);
        }
    }
    let plateau = b + R::from_f32(0.25) / (a * a * c);
    if g < R::ZERO {
        Some((e0 - plateau) / -g)
    } else {
        None
    }
}

/// Traces `q` over the QDM with at most `max_iter` iterations.
pub fn trace<R: Real>(map: &QdmMap, hf: &HeightField, q: &Query<R>, max_iter: u32) -> Trace<R> {
    trace_steps(map, hf, q, max_iter, &mut |_| {})
}

/// [`trace`], reporting every new ray parameter to `on_step`.
pub fn trace_steps<R: Real>(
    map: &QdmMap,
    hf: &HeightField,
    q: &Query<R>,
    max_iter: u32,
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    let d = q.dir();
    let hs = (d[0] * d[0] + d[1] * d[1]).sqrt();
    march(
        hf,
        q,
        max_iter,
        |cell, p| {
            let tex = map.texel(cell[0], cell[1]).map(R::from_f32);
            let top = tex[3];
            let e0 = p[2] - top - margin(p[2], top);
            if !(e0 > R::ZERO) || !(tex[0] > R::ZERO) {
                return (Step::Cell, 1);
            }
            let shrink = R::ONE - R::from_f32(16.0) * R::EPSILON;
            if hs == R::ZERO {
                return if d[2] < R::ZERO {
                    (Step::Jump(e0 / -d[2] * shrink), 1)
                } else {
                    (Step::Miss, 1)
                };
            }
            match free_distance(tex, e0, d[2] / hs) {
                Some(rho) => (Step::Jump(rho / hs * shrink), 1),
                None => (Step::Miss, 1),
            }
        },
        on_step,
    )
}
