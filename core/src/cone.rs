//! Cone step mapping (Dummer 2006), made conservative for the continuous triangle
//! surface (the concern of Bán et al., "Robust cone step mapping", EGSR 2024): the bake
//! and the march side by side, plus the machinery [`crate::qdm`] and [`crate::relaxed`]
//! share (the pyramid-bounded search of the bake, the step-then-cell-test march).
//!
//! **Texels.** One texel per cell (i, j) (the unit square `[i, i+1] × [j, j+1]`), two
//! channels `[top, ratio]` ([`CHANNELS`]): `top` is the cell's highest corner (the apex
//! height) and `ratio` the cone's horizontal/vertical opening. The cone's apex may sit
//! anywhere in the cell's footprint, not only at its centre: the empty region is
//! `z ≥ top + dist(q, cell) / ratio`, where `dist` is the horizontal distance from `q`
//! to the square. So a ray point anywhere above the cell's top may step inside the cone
//! with its apex right under it (plain cone maps, built for texel centres, are not
//! conservative under interpolation).
//!
//! **Bake.** `ratio(C) = min over cells D, corners v of D with h(v) > top(C)` of a lower
//! bound of `dist(q, C) / (h(q) − top(C))` over D: on each triangle of D the height is
//! linear, and for D in C's row or column band the distance is linear (`L`, exact), so
//! `L / (h − top)` (linear-fractional) is smallest at a corner. For diagonal D the
//! distance to C's nearest corner P is bounded below by `u_k · (q − P)` for the nine
//! unit vectors `u_k` of the quadrant ([`DIRS`]); each is linear, so
//! `max_k min_v u_k·(v − P) / (h(v) − top)` is a lower bound — within `cos(π/32)` of
//! the exact cone (rounded down to `f32`). The search ([`ratio_search`]) visits the
//! max pyramid of [`crate::maxmip`] from the top, each node's children lowest bound
//! first ([`bnb_by`]), and skips a node whose bound `fl(d_lb / (max − top))` cannot
//! lower the ratio found so far; the same directional bound on the node's box distance
//! keeps it a true lower bound of every leaf below, rounding included, so the result
//! equals the brute force [`bake_brute`] (Θ(N⁴), the test oracle) bit for bit. The
//! search starts from the bound of the cell that limited the previous texel's cone (a
//! term of the minimum, so it changes nothing but the pruning), and a leaf's bound is
//! abandoned as soon as one of its directions shows it cannot lower the ratio. Rows of
//! the map bake independently ([`bake_rows`], generic over the cone [`Family`]).
//!
//! **March** ([`trace`]). At the ray point, fetch the texel of the cell under it (one
//! fetch). Above `top`: step to where the ray leaves the cone, shortened by a rounding
//! margin — the step never passes the first intersection — unless that step stays in
//! the cell (near a wall cone steps shrink geometrically). At or below `top`, or for
//! such a short step: the exact
//! cell test of [`crate::dda::trace`] (four corner fetches; clearances at centerline
//! crossings from the edge's two samples, shared by neighbours), which either finds
//! the exact hit or moves to the next cell. Every iteration (cone step or cell test)
//! counts against `max_iter`; when it runs out the trace returns the current point as
//! its guess, flagged [`Flags::BUDGET_EXHAUSTED`].

// `!(x > 0)` is meant: it is true for NaN too, which must not step.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use core::ops::Range;

use crate::buffer::BufferError;

use crate::dda::{
    cell_index, clip, entry_on, finish, local_clearance, next_crossing, segment_point, start_hit,
    step_of,
};
use crate::field::HeightField;
use crate::math::Real;
use crate::maxmip::{self, MaxMip};
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::{corners, Surface};

const TRI: Surface = Surface::Triangles;

/// Channels per texel: `[top, ratio]`.
pub const CHANNELS: usize = 2;

/// Largest stored ratio (a cell whose top no other surface point exceeds).
pub const RATIO_MAX: f32 = 1048576.0;

/// The nine unit vectors `(cos θ_k, sin θ_k)`, `θ_k = k · π/16`, of the diagonal bound
/// (exact at both ends, so a zero gap gives the exact axis distance).
pub const DIRS: [(f64, f64); 9] = [
    (1.0, 0.0),
    (0.980_785_280_403_230_4, 0.195_090_322_016_128_26),
    (0.923_879_532_511_286_7, 0.382_683_432_365_089_8),
    (0.831_469_612_302_545_2, 0.555_570_233_019_602_2),
    (
        core::f64::consts::FRAC_1_SQRT_2,
        core::f64::consts::FRAC_1_SQRT_2,
    ),
    (0.555_570_233_019_602_2, 0.831_469_612_302_545_2),
    (0.382_683_432_365_089_8, 0.923_879_532_511_286_7),
    (0.195_090_322_016_128_26, 0.980_785_280_403_230_4),
    (0.0, 1.0),
];

/// Why a cone-family bake or map view refused its buffers (the crate's one
/// [`BufferError`]).
pub type BakeError = BufferError;

/// Checks `len ≥ needed` for a slice.
pub(crate) fn check(needed: usize, given: usize) -> Result<(), BakeError> {
    crate::buffer::check("slice", needed, given)
}

/// Cells of a `width × height` field.
#[inline]
pub(crate) fn cell_count(width: u32, height: u32) -> usize {
    (width as usize - 1) * (height as usize - 1)
}

/// Length of a cone map for a `width × height` field.
pub fn map_len(width: u32, height: u32) -> usize {
    CHANNELS * cell_count(width, height)
}

/// Length of the bake scratch (the max pyramid of [`crate::maxmip`]).
pub fn scratch_len(width: u32, height: u32) -> usize {
    maxmip::pyramid_len(width, height)
}

/// Bakes the scratch pyramid every [`bake_rows`] call of the [`Family`] reads.
pub fn prepare(hf: &HeightField, scratch: &mut [f32]) -> Result<(), BakeError> {
    check(scratch_len(hf.width(), hf.height()), scratch.len())?;
    maxmip::bake(hf, scratch).map_err(|_| BakeError::TooShort {
        what: "scratch",
        needed: scratch_len(hf.width(), hf.height()),
        given: scratch.len(),
    })
}

/// Largest `f32` not above `v` (`v ≥ 0`).
#[inline]
pub fn f32_down(v: f64) -> f32 {
    let r = v as f32;
    if (r as f64) > v && r > 0.0 {
        f32::from_bits(r.to_bits() - 1)
    } else {
        r
    }
}

/// Smallest `f32` not below `v` (`v ≥ 0`).
#[inline]
pub fn f32_up(v: f64) -> f32 {
    let r = v as f32;
    if (r as f64) < v && r.is_finite() {
        f32::from_bits(r.to_bits() + 1)
    } else {
        r
    }
}

/// Directional lower bound of the distance from a box to a point or box whose gaps
/// along x and y are `gx, gy ≥ 0`: `max_k (cos θ_k gx + sin θ_k gy)`.
///
/// Only three directions are evaluated, with the same result: with `θ` the angle of
/// `(gx, gy)`, `k0 = round(8 gy / (gx + gy))` is within 0.87 of `16 θ / π`
/// (`|8 sin θ / (sin θ + cos θ) − 16 θ / π| ≤ 0.37`), so every direction within half a
/// step of `θ` (the nearest, and its rival in a near tie) is among `k0 − 1 ..= k0 + 1`;
/// the others are at least 1.13 steps away, their exact values ≥ 1.9 % below the
/// maximum, far beyond the rounding of a sum of two non-negative products.
#[inline]
pub fn dist_lb(gx: f64, gy: f64) -> f64 {
    if gx == 0.0 || gy == 0.0 {
        return gx + gy;
    }
    let k0 = ((8.0 * gy / (gx + gy) + 0.5) as usize).min(8);
    [k0.saturating_sub(1), k0, (k0 + 1).min(8)]
        .map(|k| DIRS[k].0 * gx + DIRS[k].1 * gy)
        .into_iter()
        .fold(0.0, f64::max)
}

/// Gap from the interval `[a0, a1]` to `[b0, b1]` (0 when they overlap).
#[inline]
pub fn gap(a0: f64, a1: f64, b0: f64, b1: f64) -> f64 {
    (b0 - a1).max(a0 - b1).max(0.0)
}

/// The cone bound contributed by cell `d` to the cell `c` whose apex height is `top`:
/// a lower bound of `dist(q, c) / (h(q) − top)` over `d` where `h > top` (`+∞` when
/// no corner of `d` is above `top`). See the module notes.
pub fn cell_bound(hf: &HeightField, c: [u32; 2], top: f32, d: [u32; 2]) -> f64 {
    cell_bound_below(hf, c, top, d, f64::INFINITY)
}

/// [`cell_bound`] when it is below `cut`, else some value `≥ cut` (for a search that
/// only needs to know that the cell cannot lower `cut`). The diagonal bound is the
/// largest of nine directional minima, so the first of them that reaches `cut` settles
/// it; the direction nearest the cell's offset goes first. Below `cut`, all nine are
/// taken and their maximum (exact, order-free) is [`cell_bound`]'s.
fn cell_bound_below(hf: &HeightField, c: [u32; 2], top: f32, d: [u32; 2], cut: f64) -> f64 {
    let hs = hf.cell_corners(d[0], d[1]);
    let top = top as f64;
    // Axis offset (≥ 0) of the grid line `v` from the source square's `[ci, ci + 1]`.
    let axis = |ci: u32, v: u32| gap(ci as f64, ci as f64 + 1.0, v as f64, v as f64);
    let ox = [axis(c[0], d[0]), axis(c[0], d[0] + 1)];
    let oy = [axis(c[1], d[1]), axis(c[1], d[1] + 1)];
    // Axis offsets of each corner above `top` (order (0,0), (1,0), (0,1), (1,1)), and
    // its excess height.
    let mut off = [(0.0f64, 0.0f64, 0.0f64); 4];
    let mut n = 0;
    for (k, &h) in hs.iter().enumerate() {
        let h = h as f64;
        if h > top {
            off[n] = (ox[k & 1], oy[k >> 1], h - top);
            n += 1;
        }
    }
    if n == 0 {
        return f64::INFINITY;
    }
    let off = &off[..n];
    if d[0] == c[0] || d[1] == c[1] {
        // Same column or row band: the distance is one axis gap, linear on the cell.
        return off
            .iter()
            .map(|&(x, y, e)| (x + y) / e)
            .fold(f64::INFINITY, f64::min);
    }
    // Index of the direction nearest the cell's gaps, give or take one (0 for 0 / 0).
    let (gx, gy) = (ox[0].min(ox[1]), oy[0].min(oy[1]));
    let k0 = (8.0 * gy / (gx + gy) + 0.5) as usize;
    let mut v = 0.0f64;
    for n in 0..DIRS.len() {
        let (cs, sn) = DIRS[(k0 + n) % DIRS.len()];
        let g = off
            .iter()
            .map(|&(x, y, e)| (cs * x + sn * y) / e)
            .fold(f64::INFINITY, f64::min);
        if g >= cut {
            return g;
        }
        v = v.max(g);
    }
    v
}

/// [`dist_lb`] from the box `src` to the cells `[x0, x1) × [y0, y1)`.
#[inline]
pub fn box_dist(src: [f64; 4], x: [u32; 2], y: [u32; 2]) -> f64 {
    let gx = gap(src[0], src[1], x[0] as f64, x[1] as f64);
    let gy = gap(src[2], src[3], y[0] as f64, y[1] as f64);
    dist_lb(gx, gy)
}

/// Branch and bound over the max pyramid, best first within each node: from the top,
/// depth first, a node's children in increasing `key(d_lb, max)` (`d_lb` the
/// [`dist_lb`] of the gaps between the box `src` = `[x0, x1] × [y0, y1]` (grid units)
/// and the node's cells, `max` the node's highest sample); `leaf(cell,
/// d_lb, max)` sees the leaves reached. A key of `+∞` skips the node (and everything
/// below it); it is asked again when the node's turn comes, so a key that reads the
/// search's best value so far prunes with the latest one.
pub fn bnb_by(
    mip: &MaxMip,
    src: [f64; 4],
    key: impl Fn(f64, f32) -> f64,
    mut leaf: impl FnMut([u32; 2], f64, f32),
) {
    let layout = mip.layout();
    let cells = layout.dims(0);
    // Depth-first stack of nodes (key, d_lb, max, level, i, j): at most 4 per level.
    let mut stack: heapless::Vec<(f64, f64, f32, u32, u32, u32), 112> = heapless::Vec::new();
    let top = layout.levels() - 1;
    let _ = stack.push((
        0.0,
        box_dist(src, [0, cells[0]], [0, cells[1]]),
        mip.texel(top, 0, 0),
        top,
        0,
        0,
    ));
    while let Some((_, d, m, l, i, j)) = stack.pop() {
        if key(d, m) == f64::INFINITY {
            continue;
        }
        if l == 0 {
            leaf([i, j], d, m);
            continue;
        }
        let (s, dims) = (1u32 << (l - 1), layout.dims(l - 1));
        let base = stack.len();
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let (ci, cj) = (2 * i + di, 2 * j + dj);
            if ci >= dims[0] || cj >= dims[1] {
                continue;
            }
            let x = [ci * s, (ci * s + s).min(cells[0])];
            let y = [cj * s, (cj * s + s).min(cells[1])];
            let (cd, cm) = (box_dist(src, x, y), mip.texel(l - 1, ci, cj));
            let k = key(cd, cm);
            if k == f64::INFINITY {
                continue;
            }
            // Insertion: the children above `base` stay sorted, lowest key on top.
            let _ = stack.push((k, cd, cm, l - 1, ci, cj));
            let mut n = stack.len() - 1;
            while n > base && stack[n - 1].0 < k {
                stack.swap(n - 1, n);
                n -= 1;
            }
        }
    }
}

/// The cone ratio (in `f64`, before rounding) of cell `c`, searched over the pyramid.
pub fn texel_ratio(hf: &HeightField, mip: &MaxMip, c: [u32; 2]) -> f64 {
    ratio_search(hf, mip, c, c).0
}

/// [`texel_ratio`] of cell `c`, and the cell whose bound gives it (`hint` when none
/// is below the hint's bound and [`RATIO_MAX`]). The search starts from the bound of
/// cell `hint` (any cell; a neighbour's result is a good guess): one of the terms of
/// the minimum, so it changes no result and prunes from the start.
///
/// Pruning is exact: a node of maximum `M` whose box is at `d = dist_lb(g)` (gaps `g`)
/// is skipped when `fl(d / (M − top)) ≥ best`. Every term of every cell below is
/// `fl(fl(u·o) / e)` with `o ≥ g` componentwise (the cell's corners lie in the box),
/// `e ≤ M − top`, `u` one of [`DIRS`] (or the axis sum in a band, where the box's gap
/// across the band is 0 and `dist_lb` is the other gap, and the axis direction of a
/// diagonal cell's bound reproduces it exactly); rounding is monotone, so each cell's
/// bound is `≥ fl(d / (M − top)) ≥ best` and cannot lower the minimum. Nodes go
/// lowest bound first.
pub fn ratio_search(
    hf: &HeightField,
    mip: &MaxMip,
    c: [u32; 2],
    hint: [u32; 2],
) -> (f64, [u32; 2]) {
    let top = mip.texel(0, c[0], c[1]);
    let src = [
        c[0] as f64,
        c[0] as f64 + 1.0,
        c[1] as f64,
        c[1] as f64 + 1.0,
    ];
    let best = core::cell::Cell::new((RATIO_MAX as f64).min(cell_bound(hf, c, top, hint)));
    let mut arg = hint;
    let key = |d: f64, m: f32| {
        let k = d / (m as f64 - top as f64);
        if m <= top || k >= best.get() {
            f64::INFINITY
        } else {
            k
        }
    };
    bnb_by(mip, src, key, |cell, _, _| {
        let b = cell_bound_below(hf, c, top, cell, best.get());
        if b < best.get() {
            best.set(b);
            arg = cell;
        }
    });
    (best.get(), arg)
}

/// A map of the cone family, baked row by row from the max pyramid [`prepare`] bakes
/// into the scratch: the cone map ([`Cone`]), the QDM (`crate::qdm::Qdm`) and the relaxed
/// cone map (`crate::relaxed::Relaxed`). [`bake_rows`] and [`bake`] bake any of them.
pub trait Family {
    /// Floats per texel.
    const CHANNELS: usize;

    /// Texels per row and rows of the map of a `width × height` field.
    fn texels(width: u32, height: u32) -> [u32; 2];

    /// Bakes texel rows `rows` (rows of the map) into `out` (at least those rows'
    /// floats), searching `mip`: what [`bake_rows`] runs once it checked the buffers.
    fn bake_texel_rows(hf: &HeightField, mip: &MaxMip, rows: Range<u32>, out: &mut [f32]);
}

/// The cone map, one texel `[top, ratio]` per cell: the [`Family`] member of this
/// module.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cone;

impl Family for Cone {
    const CHANNELS: usize = CHANNELS;

    fn texels(width: u32, height: u32) -> [u32; 2] {
        [width - 1, height - 1]
    }

    fn bake_texel_rows(hf: &HeightField, mip: &MaxMip, rows: Range<u32>, out: &mut [f32]) {
        let cw = hf.width() - 1;
        // Each search starts from the cell that limited the previous texel's cone.
        let mut hint = [0, rows.start];
        for (r, j) in rows.enumerate() {
            for i in 0..cw {
                let k = CHANNELS * (r * cw as usize + i as usize);
                let (ratio, arg) = ratio_search(hf, mip, [i, j], hint);
                hint = arg;
                out[k] = mip.texel(0, i, j);
                out[k + 1] = f32_down(ratio);
            }
        }
    }
}

/// Bakes texel rows `rows` of `F`'s map into `out` (`rows.len()` rows of
/// [`Family::texels`] texels, [`Family::CHANNELS`] floats each: the rows' part of the
/// whole map), reading the pyramid [`prepare`] baked into `scratch`. Rows are
/// independent: split them over threads as you like.
pub fn bake_rows<F: Family>(
    hf: &HeightField,
    scratch: &[f32],
    rows: Range<u32>,
    out: &mut [f32],
) -> Result<(), BakeError> {
    let mip = scratch_pyramid(hf, scratch)?;
    let [row_texels, map_rows] = F::texels(hf.width(), hf.height());
    if rows.end > map_rows || rows.start > rows.end {
        return Err(BakeError::BadRows);
    }
    check(F::CHANNELS * rows.len() * row_texels as usize, out.len())?;
    F::bake_texel_rows(hf, &mip, rows, out);
    Ok(())
}

/// Bakes the whole map of `F` into `out`: [`prepare`] into `scratch`, then
/// [`bake_rows`] over every row.
pub fn bake<F: Family>(
    hf: &HeightField,
    scratch: &mut [f32],
    out: &mut [f32],
) -> Result<(), BakeError> {
    prepare(hf, scratch)?;
    let map_rows = F::texels(hf.width(), hf.height())[1];
    bake_rows::<F>(hf, scratch, 0..map_rows, out)
}

/// The pyramid [`prepare`] baked into `scratch`, the row bakes' search structure.
fn scratch_pyramid<'a>(hf: &HeightField, scratch: &'a [f32]) -> Result<MaxMip<'a>, BakeError> {
    MaxMip::new(hf, scratch).map_err(|_| BakeError::TooShort {
        what: "scratch",
        needed: scratch_len(hf.width(), hf.height()),
        given: scratch.len(),
    })
}

/// The Θ(N⁴) brute force (every cell against every cell): the test oracle of the bake.
pub fn bake_brute(hf: &HeightField, out: &mut [f32]) -> Result<(), BakeError> {
    let (cw, ch) = (hf.width() - 1, hf.height() - 1);
    check(map_len(hf.width(), hf.height()), out.len())?;
    for j in 0..ch {
        for i in 0..cw {
            let c = hf.cell_corners(i, j);
            let top = c.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            let mut best = RATIO_MAX as f64;
            for dj in 0..ch {
                for di in 0..cw {
                    best = best.min(cell_bound(hf, [i, j], top, [di, dj]));
                }
            }
            let k = CHANNELS * (j as usize * cw as usize + i as usize);
            out[k] = top;
            out[k + 1] = f32_down(best);
        }
    }
    Ok(())
}

/// A baked map of `N` floats per cell (the cone map, `N` = [`CHANNELS`]; the QDM,
/// `crate::qdm::QdmMap`): the read-only view the march uses.
#[derive(Clone, Copy, Debug)]
pub struct CellMap<'a, const N: usize> {
    data: &'a [f32],
    cells_w: u32,
}

/// A baked cone map: texels `[top, ratio]`.
pub type ConeMap<'a> = CellMap<'a, CHANNELS>;

impl<'a, const N: usize> CellMap<'a, N> {
    /// Views `data` (baked for `hf` by [`bake`] of [`Cone`] or `crate::qdm::Qdm`) as `hf`'s
    /// map.
    pub fn new(hf: &HeightField, data: &'a [f32]) -> Result<Self, BakeError> {
        check(N * cell_count(hf.width(), hf.height()), data.len())?;
        Ok(CellMap {
            data,
            cells_w: hf.width() - 1,
        })
    }

    /// The texel of cell (i, j).
    #[inline]
    pub fn texel(&self, i: u32, j: u32) -> [f32; N] {
        let k = N * (j as usize * self.cells_w as usize + i as usize);
        let mut t = [0.0; N];
        t.copy_from_slice(&self.data[k..k + N]);
        t
    }
}

/// What a method's step function decides at a ray point above a cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step<R: Real> {
    /// Advance `t` by this much (`> 0`); the ray stays above the surface meanwhile.
    Jump(R),
    /// The rest of the ray cannot meet the surface.
    Miss,
    /// No safe step: run the exact cell test.
    Cell,
}

/// Rounding margin on a clearance above a stored top: `64 ε (1 + |z| + |top|)`.
#[inline]
pub(crate) fn margin<R: Real>(z: R, top: R) -> R {
    R::from_f32(64.0) * R::EPSILON * (R::ONE + z.abs() + top.abs())
}

/// The shared march: at each iteration, `step(cell, point)` (returning the step and
/// the fetches it cost) either jumps, ends in a miss, or asks for the exact cell test of
/// [`crate::dda::trace`]. `on_step(t)` sees every new `t` (jumps, cell exits and the
/// hit). Start, side and under-the-surface semantics are those of `dda::trace`.
pub fn march<R: Real>(
    hf: &HeightField,
    q: &Query<R>,
    max_iter: u32,
    step: impl FnMut([u32; 2], [R; 3]) -> (Step<R>, u32),
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    finish(hf, TRI, q, march_cells(hf, q, max_iter, step, on_step))
}

/// [`march`] before the robust finish.
fn march_cells<R: Real>(
    hf: &HeightField,
    q: &Query<R>,
    max_iter: u32,
    mut step: impl FnMut([u32; 2], [R; 3]) -> (Step<R>, u32),
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    let Some(span) = clip(hf, q) else {
        return Trace::MISS;
    };
    let (o, d) = (q.origin(), q.dir());
    let cells = [hf.width() - 1, hf.height() - 1];
    let dstep = [step_of(d[0]), step_of(d[1])];
    let locate = |p: [R; 3]| {
        [0, 1].map(|k| {
            cell_index(
                p[k].clamp_to(R::ZERO, R::from_u32(cells[k])),
                d[k],
                cells[k],
            )
        })
    };
    let p0 = q.at(span.t0);
    let start = [0, 1].map(|k| p0[k].clamp_to(R::ZERO, R::from_u32(cells[k])));
    let mut cell = locate(p0);
    let mut c: [R; 4] = corners(hf, cell[0], cell[1]);
    let mut fetches = 4u32;
    let on = entry_on(TRI, &span.entry);
    let (mut a, mut ca) = local_clearance(TRI, c, cell, [start[0], start[1], p0[2]], on);
    if ca <= R::ZERO {
        return Trace::hit(start_hit(TRI, &span, c, cell, a, p0), fetches, R::ZERO);
    }
    let mut clearance = ca;
    // `a, ca` valid for the current point; `have_c`: `c` holds the current cell's corners.
    let (mut have_ca, mut have_c) = (true, true);
    let mut t = span.t0;
    let mut iter = 0u32;
    let cell_exit = |cell: [u32; 2]| {
        let t_cross = [0, 1].map(|k| next_crossing(cell[k], dstep[k], o[k], d[k]));
        t_cross[0].min(t_cross[1]).min(span.t1)
    };
    loop {
        let p = q.at(t);
        if iter >= max_iter {
            return Trace {
                hit: Some(Hit {
                    t,
                    point: R::v3(p),
                    cell,
                    normal: R::v3([R::ZERO, R::ZERO, R::ONE]),
                    flags: Flags::default(),
                }),
                fetches,
                clearance,
                flags: Flags::BUDGET_EXHAUSTED,
            };
        }
        iter += 1;
        let (s, f) = step(cell, p);
        fetches += f;
        match s {
            Step::Miss => return Trace::miss(fetches, clearance),
            // A jump that stays in the cell would crawl (cone steps converge only
            // geometrically near a wall): the cell test reaches its exit at once.
            Step::Jump(dt) if dt > R::ZERO && t + dt >= cell_exit(cell) => {
                let tn = t + dt;
                if !(tn < span.t1) {
                    return Trace::miss(fetches, clearance);
                }
                t = tn;
                on_step(t);
                cell = locate(q.at(t));
                have_ca = false;
                have_c = false;
                continue;
            }
            _ => {}
        }
        // The exact cell test from `t` to the cell's exit.
        if !have_c {
            c = corners(hf, cell[0], cell[1]);
            fetches += 4;
        }
        if !have_ca {
            (a, ca) = local_clearance(TRI, c, cell, p, [None; 2]);
            clearance = clearance.min(ca);
            if ca <= R::ZERO {
                return Trace::hit(
                    Hit {
                        t,
                        point: R::v3(p),
                        cell,
                        normal: R::v3(TRI.cell_normal(c, a[0], a[1])),
                        flags: Flags::default(),
                    },
                    fetches,
                    clearance,
                );
            }
        }
        let t_cross = [0, 1].map(|k| next_crossing(cell[k], dstep[k], o[k], d[k]));
        let t_next = t_cross[0].min(t_cross[1]);
        let (tb, cross) = if t_next < span.t1 {
            (t_next.max(t), t_cross.map(|x| x <= t_next))
        } else {
            (span.t1, [false; 2])
        };
        let on = [0, 1].map(|k| cross[k].then_some(dstep[k] > 0));
        let (b, cb) = local_clearance(TRI, c, cell, q.at(tb), on);
        let seg = TRI.segment_hit(c, a, b, ca, cb, [R::ZERO, R::ZERO, R::ONE]);
        clearance = clearance.min(seg.clearance);
        if let Some(found) = seg.hit {
            on_step(t + found.0 * (tb - t));
            return Trace::hit(
                segment_point(cell, ((t, tb), (a, b)), found),
                fetches,
                clearance,
            );
        }
        if cross == [false; 2] {
            return Trace::miss(fetches, clearance);
        }
        for k in 0..2 {
            if cross[k] {
                let next = cell[k] as i64 + dstep[k];
                if next < 0 || next >= cells[k] as i64 {
                    return Trace::miss(fetches, clearance);
                }
                cell[k] = next as u32;
            }
        }
        a = [0, 1, 2].map(|k| {
            if k < 2 && cross[k] {
                R::ONE - b[k]
            } else {
                b[k]
            }
        });
        ca = cb;
        t = tb;
        on_step(t);
        have_ca = true;
        have_c = false;
    }
}

/// The cone step from ray point `p` with direction `d` over a texel `[top, ratio]`.
#[inline]
pub(crate) fn cone_step<R: Real>(p: [R; 3], d: [R; 3], top: R, ratio: R) -> Step<R> {
    let tol = margin(p[2], top);
    let e = p[2] - top - tol;
    if !(e > R::ZERO) || ratio <= R::ZERO {
        return Step::Cell;
    }
    let hs = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let denom = hs / ratio - d[2];
    if !(denom > R::ZERO) {
        return Step::Miss;
    }
    Step::Jump(e / denom * (R::ONE - R::from_f32(16.0) * R::EPSILON))
}

/// Traces `q` over the cone map with at most `max_iter` iterations.
pub fn trace<R: Real>(map: &ConeMap, hf: &HeightField, q: &Query<R>, max_iter: u32) -> Trace<R> {
    trace_steps(map, hf, q, max_iter, &mut |_| {})
}

/// [`trace`], reporting every new ray parameter to `on_step` (for tests and plots).
pub fn trace_steps<R: Real>(
    map: &ConeMap,
    hf: &HeightField,
    q: &Query<R>,
    max_iter: u32,
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    let d = q.dir();
    march(
        hf,
        q,
        max_iter,
        |cell, p| {
            let [top, ratio] = map.texel(cell[0], cell[1]);
            (cone_step(p, d, R::from_f32(top), R::from_f32(ratio)), 1)
        },
        on_step,
    )
}
