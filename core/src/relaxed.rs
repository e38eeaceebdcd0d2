//! Relaxed cone stepping (Policarpo & Oliveira, GPU Gems 3, ch. 18): the published
//! preprocess and march, side by side. **Approximate**: a relaxed cone lets a ray
//! cross the surface once, so the final binary search can pick the wrong crossing or
//! miss a thin peak altogether; the tests measure how often.
//!
//! **Bake** (the book's listing, one texel per sample, ratio = horizontal/vertical).
//! For sample T and each destination sample D, the ray from the top of the field above
//! T (`z = max`, raised by a hair so that it is never horizontal) through D's surface
//! point is continued past D in [`SEARCH_STEPS`] equal steps down to the field's
//! bottom while it stays under the surface; the first point E out of it bounds the
//! ratio by `|E − T| / (z_E − h_T)` when E is above T. The ratio is the minimum over D.
//! The book loops over every D (Θ(N⁴)); here ([`texel_search`]) the result is the same
//! bit for bit ([`bake_brute`] is the oracle), from far fewer pairs and steps:
//! - the ratio along the ray never decreases past D, also as computed in f64, so the
//!   ratio at D bounds the pair's from below and a march stops as soon as its ratio
//!   reaches the best so far ([`pair_ratio_below`]);
//! - the max pyramid skips whole regions whose bound `dist(T, node) / (max − h_T)`
//!   cannot lower the ratio (E lies beyond D and not above it);
//! - the search starts from an upper bound: the pairs that won for the left and upper
//!   neighbours, moved along with T ([`Relaxed`]).
//!
//! **March** ([`trace`]): cone steps `Δt = Δh / (|d_xy| / r + |d_z|)` with `Δh` the
//! ray's height over the surface at its point and `r` the ratio of the nearest sample,
//! until the ray is under the surface (or the step budget runs out), then a binary
//! search between the last two points.

// `!(x > 0)` is meant: it is true for NaN too, which must not step.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use core::ops::Range;

use crate::cone::{check, f32_down, BakeError, RATIO_MAX};
use crate::dda::clip;
use crate::field::HeightField;
use crate::math::Real;
use crate::maxmip::MaxMip;
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::{plane, triangle_planes, Surface};

const TRI: Surface = Surface::Triangles;

/// Steps of the bake's search past each destination (the book's `search_steps`).
pub const SEARCH_STEPS: u32 = 128;

/// Length of a relaxed cone map (one ratio per sample).
pub fn map_len(width: u32, height: u32) -> usize {
    width as usize * height as usize
}

/// Length of the bake scratch (the max pyramid).
pub fn scratch_len(width: u32, height: u32) -> usize {
    crate::cone::scratch_len(width, height)
}

/// The ratio bound destination sample `dst` puts on source sample `src`.
pub fn pair_ratio(hf: &HeightField, src: [u32; 2], dst: [u32; 2]) -> f64 {
    let ht = hf.at(src[0], src[1]) as f64;
    let hd = hf.at(dst[0], dst[1]) as f64;
    if hd <= ht || src == dst {
        return f64::INFINITY;
    }
    let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
    let top = zmax + 1e-3 * (zmax - zmin) + 1e-6;
    let t = [src[0] as f64, src[1] as f64];
    let dpt = [dst[0] as f64, dst[1] as f64, hd];
    // Ray from (T, top) through D, scaled to reach the bottom from D.
    let v = [dpt[0] - t[0], dpt[1] - t[1], hd - top];
    let scale = (hd - zmin) / (top - hd) / SEARCH_STEPS as f64;
    let step = [v[0] * scale, v[1] * scale, v[2] * scale];
    let mut p = [dpt[0] + step[0], dpt[1] + step[1], dpt[2] + step[2]];
    for _ in 1..SEARCH_STEPS {
        if TRI.height_at(hf, p[0], p[1]) >= p[2] {
            p = [p[0] + step[0], p[1] + step[1], p[2] + step[2]];
        } else {
            break;
        }
    }
    if p[2] <= ht {
        return f64::INFINITY;
    }
    let (dx, dy) = (p[0] - t[0], p[1] - t[1]);
    libm::sqrt(dx * dx + dy * dy) / (p[2] - ht)
}

/// A source sample `T` and what all its pairs share.
struct Source<'h, 'a> {
    hf: &'h HeightField<'a>,
    /// `T`'s coordinates and height.
    t: [f64; 2],
    ht: f64,
    /// The ray's start height above every `T` and the field's bottom.
    top: f64,
    zmin: f64,
}

impl<'h, 'a> Source<'h, 'a> {
    fn new(hf: &'h HeightField<'a>, src: [u32; 2]) -> Self {
        let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
        Source {
            hf,
            t: [src[0] as f64, src[1] as f64],
            ht: hf.at(src[0], src[1]) as f64,
            top: zmax + 1e-3 * (zmax - zmin) + 1e-6,
            zmin,
        }
    }

    /// [`pair_ratio`]'s final formula at point `p` (`z > h_T`).
    #[inline]
    fn ratio(&self, p: [f64; 3]) -> f64 {
        let (dx, dy) = (p[0] - self.t[0], p[1] - self.t[1]);
        libm::sqrt(dx * dx + dy * dy) / (p[2] - self.ht)
    }

    /// [`pair_ratio_below`] from this source.
    fn below(&self, dst: [u32; 2], best: f64) -> f64 {
        let (hf, ht, top) = (self.hf, self.ht, self.top);
        let hd = hf.at(dst[0], dst[1]) as f64;
        if hd <= ht {
            return f64::INFINITY;
        }
        // Exactly `pair_ratio`'s march, stopped once `best` is out of reach.
        let v = [
            dst[0] as f64 - self.t[0],
            dst[1] as f64 - self.t[1],
            hd - top,
        ];
        let scale = (hd - self.zmin) / (top - hd) / SEARCH_STEPS as f64;
        let step = [v[0] * scale, v[1] * scale, v[2] * scale];
        // The first step whose exact ratio reaches `best`, `1 + (λ* − 1) / scale`
        // (a guess: it only says where the ratio is first evaluated).
        let a = libm::sqrt(v[0] * v[0] + v[1] * v[1]);
        let guess = (best * (hd - ht) - a) / ((a + best * (top - hd)) * scale);
        let mut check = if guess < (SEARCH_STEPS - 1) as f64 {
            guess.max(0.0) as u32 + 1
        } else {
            SEARCH_STEPS
        };
        let mut surf = TriCell::new(hf);
        let mut p = [
            dst[0] as f64 + step[0],
            dst[1] as f64 + step[1],
            hd + step[2],
        ];
        let mut k = 1;
        loop {
            // Up to step `check`, only the surface test (`k < check ≤ SEARCH_STEPS`).
            while k < check {
                if !(surf.height(p[0], p[1]) >= p[2]) {
                    return self.end(p);
                }
                p = [p[0] + step[0], p[1] + step[1], p[2] + step[2]];
                k += 1;
            }
            let r = self.end(p);
            if r >= best || k == SEARCH_STEPS {
                return r;
            }
            check += 1;
        }
    }

    /// The pair's ratio if the march ends at `p`.
    #[inline]
    fn end(&self, p: [f64; 3]) -> f64 {
        if p[2] <= self.ht {
            f64::INFINITY
        } else {
            self.ratio(p)
        }
    }
}

/// [`Surface::height_at`] of [`Surface::Triangles`] in f64 from the same steps
/// (`clamp_to`, `locate`'s cell, `triangle_planes`, the larger plane: the same bits),
/// keeping the last cell and its planes: consecutive steps of a march often stay in one cell (about half of them on
/// the test maps), which is then found by comparing the point with the cell's bounds
/// instead of converting it.
struct TriCell<'h, 'a> {
    hf: &'h HeightField<'a>,
    /// The cell's low corner, and the bounds below which a point is still in it.
    lo: [f64; 2],
    hi: [f64; 2],
    planes: [[f64; 3]; 2],
}

impl<'h, 'a> TriCell<'h, 'a> {
    fn new(hf: &'h HeightField<'a>) -> Self {
        TriCell {
            hf,
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
            planes: [[0.0; 3]; 2],
        }
    }

    #[inline]
    fn height(&mut self, x: f64, y: f64) -> f64 {
        let (w, h) = (self.hf.width(), self.hf.height());
        let x = x.clamp_to(0.0, (w - 1) as f64);
        let y = y.clamp_to(0.0, (h - 1) as f64);
        if !(x >= self.lo[0] && x < self.hi[0] && y >= self.lo[1] && y < self.hi[1]) {
            // `locate`'s cell: `floor` (the values are ≥ 0, so truncation is floor),
            // the last cell taking the far edge.
            let cell = [(x as u32).min(w - 2), (y as u32).min(h - 2)];
            let hi = |c: u32, n: u32| {
                if c + 2 < n {
                    (c + 1) as f64
                } else {
                    f64::INFINITY
                }
            };
            self.lo = [cell[0] as f64, cell[1] as f64];
            self.hi = [hi(cell[0], w), hi(cell[1], h)];
            let c = self.hf.cell_corners(cell[0], cell[1]).map(f64::from);
            self.planes = triangle_planes(c);
        }
        let (u, v) = (x - self.lo[0], y - self.lo[1]);
        let [p, q] = self.planes;
        // `Surface::cell_height` of the triangles.
        Real::max(plane(p, u, v), plane(q, u, v))
    }
}

/// [`pair_ratio`] when it is below `best`; otherwise some value `≥ best` (often
/// without the whole march). The minimum of `best` and the result is therefore the
/// minimum of `best` and [`pair_ratio`], bit for bit.
///
/// **Why stopping early is exact.** The march computes the points `p_k` (`k ≥ 1`) by
/// repeated rounded additions of a fixed `step` to `p_0 = D`, and [`pair_ratio`] is
/// `r(p_K) = fl(√fl(dx² + dy²) / fl(z − h_T))` at its final point `p_K` (`+∞` when
/// `z ≤ h_T`). Every operation is a correctly rounded IEEE operation, hence monotone in
/// each argument, so the computed `r(p_k)` never decreases with `k`:
/// - `step` has the signs of `D − T` in x and y and is negative in z (`h_D > h_T ≥
///   z_min`, `top > h_D`); `fl(a + step)` lies on the step's side of `a`, so each
///   coordinate of `p_k` moves monotonically away from `T` in x and y and down in z
///   (`p_0 = D` included: its offsets from `T` are exact integers);
/// - hence `|fl(p_x − t_x)|`, `|fl(p_y − t_y)|` (same sign as `D − T` throughout), the
///   squares, their sum and the square root never decrease, `fl(z − h_T)` never
///   increases, and so neither does the quotient once `z > h_T`; a `z ≤ h_T` stays so.
///
/// Thus `r(p_K) ≥ r(p_k)` for every `k ≤ K`, and the march can stop as soon as
/// `r(p_k) ≥ best` (or `z ≤ h_T`); `k = 0` is the per-destination test
/// `|D − T| / (h_D − h_T) ≥ best`. In exact arithmetic `r(p_k) < best` iff
/// `λ_k = 1 + k·scale < λ* = best·b / (a + best·c)` with `a = |D − T|`, `b = top − h_T`,
/// `c = top − h_D` (the point is `(T, top) + λ·(D − (T, top))`), so the first step that
/// may reach `best`, `1 + ⌊(λ* − 1) / scale⌋ = 1 + ⌊(best·(h_D − h_T) − a) / ((a +
/// best·c)·scale)⌋`, is computed in closed form; the march only tests the surface up
/// to it, and evaluates the ratio there (and at each following step should rounding
/// have made the guess short). The guess only decides where the ratio is evaluated,
/// never the result. The surface
/// heights are [`Surface::height_at`]'s, bit for bit (`TriCell`).
pub fn pair_ratio_below(hf: &HeightField, src: [u32; 2], dst: [u32; 2], best: f64) -> f64 {
    if src == dst {
        return f64::INFINITY;
    }
    Source::new(hf, src).below(dst, best)
}

/// Safety factor of the node test: a node is skipped only when its bound exceeds
/// `best` by far more than the rounding of the bound and of the ratio at `D`
/// (a few units in the last place).
const NODE_SAFETY: f64 = 1.0 + 1e-12;

/// Columns whose upper neighbour's destination seeds the search (a 32 KiB array on the
/// stack of [`Relaxed`]'s row bake; wider fields go without that seed past it).
const ABOVE: usize = 4096;

/// Pyramid level whose nodes the search enumerates sample by sample.
const LEAF_LEVEL: u32 = 2;

/// The ratio of sample `s`, searched over the pyramid.
pub fn texel_ratio(hf: &HeightField, mip: &MaxMip, s: [u32; 2]) -> f64 {
    texel_search(hf, mip, s, &[]).0
}

/// The ratio of sample `s` and the destination that gives it (`None` when no pair is
/// below [`RATIO_MAX`]), trying the destinations `seeds` first: any pair's ratio bounds
/// the minimum from above, so a good seed lets the search skip most of the field.
///
/// The search visits the pyramid depth first, the child nearest T first, down to
/// `LEAF_LEVEL`, whose nodes' samples it tries one by one. A node's bound
/// `dist(T, node) / (max − h_T)` is a lower bound of the ratio `|D − T| / (h_D − h_T)`
/// at every sample `D` of the node, itself a lower bound of the pair's ratio (see
/// [`pair_ratio_below`]); a node or a sample whose bound is at least the best ratio so
/// far (with `NODE_SAFETY` for the rounding; squares are compared) cannot lower it.
/// Every pair
/// that may lower it is evaluated by [`pair_ratio_below`], which returns the exact
/// [`pair_ratio`] whenever it is below the best so far: the result is the minimum over
/// all pairs, bit for bit as in [`bake_brute`], whatever the seeds and the order.
pub fn texel_search(
    hf: &HeightField,
    mip: &MaxMip,
    s: [u32; 2],
    seeds: &[[u32; 2]],
) -> (f64, Option<[u32; 2]>) {
    let (w, h) = (hf.width(), hf.height());
    let src = Source::new(hf, s);
    let htf = hf.at(s[0], s[1]);
    let mut best = RATIO_MAX as f64;
    let mut win = None;
    let (sx, sy) = (s[0] as f64, s[1] as f64);
    // Evaluates the pair unless the ratio at D, `|D − T| / (h_D − h_T)`, is surely at
    // least `best` (squares compared, with the node test's margin).
    let mut try_pair = |d: [u32; 2], best: &mut f64| {
        let dz = hf.at(d[0], d[1]) as f64 - src.ht;
        let (dx, dy) = (d[0] as f64 - sx, d[1] as f64 - sy);
        let lim = *best * NODE_SAFETY * dz;
        if dz > 0.0 && dx * dx + dy * dy < lim * lim {
            let r = src.below(d, *best);
            if r < *best {
                *best = r;
                win = Some(d);
            }
        }
    };
    for &d in seeds {
        if d[0] < w && d[1] < h {
            try_pair(d, &mut best);
        }
    }
    let layout = mip.layout();
    let cells = layout.dims(0);
    // The squared bound of node (l, i, j), `+∞` when no sample in it is above T.
    let key = |l: u32, i: u32, j: u32| {
        let m = mip.texel(l, i, j);
        if m <= htf {
            return f64::INFINITY;
        }
        let sz = 1u32 << l;
        let (x0, y0) = (i * sz, j * sz);
        let (x1, y1) = ((x0 + sz).min(cells[0]), (y0 + sz).min(cells[1]));
        let gx = (x0 as f64 - sx).max(sx - x1 as f64).max(0.0);
        let gy = (y0 as f64 - sy).max(sy - y1 as f64).max(0.0);
        let dz = m as f64 - src.ht;
        (gx * gx + gy * gy) / (dz * dz)
    };
    let limit = |best: f64| (best * NODE_SAFETY) * (best * NODE_SAFETY);
    let top = layout.levels() - 1;
    let mut stack: heapless::Vec<(f64, u32, u32, u32), 128> = heapless::Vec::new();
    let _ = stack.push((key(top, 0, 0), top, 0, 0));
    while let Some((k, l, i, j)) = stack.pop() {
        if k >= limit(best) {
            continue;
        }
        if l <= LEAF_LEVEL {
            // The node's samples: its cells' low corners, and the far ones on the last
            // row/column.
            let sz = 1u32 << l;
            let x1 = ((i + 1) * sz).min(cells[0]);
            let y1 = ((j + 1) * sz).min(cells[1]);
            for y in j * sz..y1 + u32::from(y1 == cells[1]) {
                for x in i * sz..x1 + u32::from(x1 == cells[0]) {
                    try_pair([x, y], &mut best);
                }
            }
            continue;
        }
        let dims = layout.dims(l - 1);
        let lim = limit(best);
        // Children farthest first, so the one nearest T pops first.
        let half = 1u32 << (l - 1);
        let qx = u32::from(sx >= ((2 * i + 1) * half) as f64);
        let qy = u32::from(sy >= ((2 * j + 1) * half) as f64);
        for (a, b) in [(1, 1), (0, 1), (1, 0), (0, 0)] {
            let (ci, cj) = (2 * i + (a ^ qx), 2 * j + (b ^ qy));
            if ci < dims[0] && cj < dims[1] {
                let k = key(l - 1, ci, cj);
                if k < lim {
                    let _ = stack.push((k, l - 1, ci, cj));
                }
            }
        }
    }
    (best, win)
}

/// The relaxed cone map, one ratio per sample: its [`crate::cone::Family`] member,
/// baked by [`crate::cone::bake_rows`] and [`crate::cone::bake`] from the pyramid
/// [`crate::cone::prepare`] bakes. Rows are independent: the destinations that won for
/// the left and upper neighbours seed each texel's search ([`texel_search`]), which
/// changes its speed, never its result.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Relaxed;

impl crate::cone::Family for Relaxed {
    const CHANNELS: usize = 1;

    fn texels(width: u32, height: u32) -> [u32; 2] {
        [width, height]
    }

    fn bake_texel_rows(hf: &HeightField, mip: &MaxMip, rows: Range<u32>, out: &mut [f32]) {
        let w = hf.width();
        // Seeds: the left and upper neighbours' destinations, as are and moved along.
        let mut above = [[u32::MAX; 2]; ABOVE];
        for (r, j) in rows.enumerate() {
            let mut left = [u32::MAX; 2];
            for i in 0..w {
                let mut seeds: heapless::Vec<[u32; 2], 4> = heapless::Vec::new();
                if left[0] != u32::MAX {
                    let _ = seeds.push(left);
                    let _ = seeds.push([left[0] + 1, left[1]]);
                }
                if let Some(&d) = above.get(i as usize) {
                    if d[0] != u32::MAX && d != left {
                        let _ = seeds.push(d);
                        let _ = seeds.push([d[0], d[1] + 1]);
                    }
                }
                let (best, win) = texel_search(hf, mip, [i, j], &seeds);
                left = win.unwrap_or([u32::MAX; 2]);
                if let Some(a) = above.get_mut(i as usize) {
                    *a = left;
                }
                out[r * w as usize + i as usize] = f32_down(best);
            }
        }
    }
}

/// The book's Θ(N⁴) loop over every pair: the test oracle of the bake.
pub fn bake_brute(hf: &HeightField, out: &mut [f32]) -> Result<(), BakeError> {
    let (w, h) = (hf.width(), hf.height());
    check(map_len(w, h), out.len())?;
    for j in 0..h {
        for i in 0..w {
            let mut best = RATIO_MAX as f64;
            for dj in 0..h {
                for di in 0..w {
                    best = best.min(pair_ratio(hf, [i, j], [di, dj]));
                }
            }
            out[j as usize * w as usize + i as usize] = f32_down(best);
        }
    }
    Ok(())
}

/// Step budget of the march.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Steps {
    /// Most cone steps.
    pub cone: u32,
    /// Binary-search steps after the first point under the surface.
    pub binary: u32,
}

impl Default for Steps {
    fn default() -> Self {
        Steps {
            cone: 64,
            binary: 8,
        }
    }
}

/// Traces `q` (approximate). Fetches: four per surface height, one per ratio.
pub fn trace<R: Real>(map: &[f32], hf: &HeightField, q: &Query<R>, steps: Steps) -> Trace<R> {
    trace_steps(map, hf, q, steps, &mut |_| {})
}

/// [`trace`], reporting every new ray parameter to `on_step`.
pub fn trace_steps<R: Real>(
    map: &[f32],
    hf: &HeightField,
    q: &Query<R>,
    steps: Steps,
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    let Some(span) = clip(hf, q) else {
        return Trace::MISS;
    };
    let d = q.dir();
    let hs = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let w = hf.width();
    let (xm, ym) = (R::from_u32(w - 1), R::from_u32(hf.height() - 1));
    let mut fetches = 0u32;
    let above = |t: R, fetches: &mut u32| {
        let p = q.at(t);
        *fetches += 4;
        p[2] - TRI.height_at(hf, p[0], p[1])
    };
    let hit = |t: R, fetches: u32, flags: Flags| {
        let p = q.at(t);
        let x = p[0].clamp_to(R::ZERO, xm);
        let y = p[1].clamp_to(R::ZERO, ym);
        let cell = [
            (x.floor().to_f64() as u32).min(w - 2),
            (y.floor().to_f64() as u32).min(hf.height() - 2),
        ];
        Trace {
            hit: Some(Hit {
                t,
                point: R::v3(p),
                cell,
                normal: R::v3(TRI.normal_at(hf, x, y)),
                flags: Flags::default(),
            }),
            fetches,
            clearance: R::INFINITY,
            flags,
        }
    };
    let mut t = span.t0;
    let mut dh = above(t, &mut fetches);
    if dh <= R::ZERO {
        return hit(t, fetches, Flags::default());
    }
    let mut t_prev = t;
    let mut n = 0;
    while dh > R::ZERO {
        if n == steps.cone {
            return hit(t, fetches, Flags::BUDGET_EXHAUSTED);
        }
        n += 1;
        let p = q.at(t);
        let i = (p[0].clamp_to(R::ZERO, xm) + R::HALF).floor().to_f64() as u32;
        let j = (p[1].clamp_to(R::ZERO, ym) + R::HALF).floor().to_f64() as u32;
        let r = R::from_f32(map[j as usize * w as usize + i.min(w - 1) as usize]);
        fetches += 1;
        let denom = if hs == R::ZERO { -d[2] } else { hs / r - d[2] };
        if !(denom > R::ZERO) {
            return Trace {
                fetches,
                ..Trace::MISS
            };
        }
        t_prev = t;
        t = t + dh / denom;
        if !(t <= span.t1) {
            return Trace {
                fetches,
                ..Trace::MISS
            };
        }
        on_step(t);
        dh = above(t, &mut fetches);
    }
    // Binary search between the last point above and the first one under.
    let (mut lo, mut hi) = (t_prev, t);
    for _ in 0..steps.binary {
        let mid = R::HALF * (lo + hi);
        if above(mid, &mut fetches) > R::ZERO {
            lo = mid;
        } else {
            hi = mid;
        }
        on_step(hi);
    }
    hit(hi, fetches, Flags::default())
}
