//! Maximum mipmaps (Tevs, Ihrke, Seidel 2008): a pyramid of maximum heights, and the
//! hierarchical march over it.
//!
//! **Bake.** Level 0 holds one texel per cell, the maximum of the cell's four corners
//! (it bounds the triangle, bilinear, view-linear and height-plane surfaces); each
//! coarser level holds the maximum of its 2 × 2 children, down to a single texel. Any
//! W × H works: a level of odd size rounds up, and its last texel takes the maximum of
//! the children that exist. Levels lie one after the other in one caller-owned slice
//! ([`Layout`], [`pyramid_len`]); [`bake_rows`] bakes any rows of one level, so a job
//! system can split each level; [`update_rect`] refreshes what a changed rectangle of
//! samples touches.
//!
//! **March.** The ray walks the same integer cell indices as [`dda::trace`], one node of
//! some level at a time: when the ray stays above the node's maximum over the part of
//! the ray inside it, it jumps to the node's exit and ascends (one level, as in the
//! paper, or straight to the highest level whose boundary it just crossed: [`Ascent`]);
//! otherwise it descends, down to level 0 where the cell gets the exact per-cell test
//! of [`dda::trace`], with clearances computed on cell edges exactly as there, so
//! hit-or-miss stays watertight and the answer is the DDA's. Every crossing's `t` is
//! recomputed from its integer boundary; nothing is offset by an epsilon.
//!
//! Cost: one fetch per pyramid texel read, four per exact cell test (the corners).
//!
//! [`dda::trace`]: crate::dda::trace

use crate::dda::{
    self, cell_index, clip, entry_on, finish, local_clearance, segment_point, start_clearance,
    start_hit, step_of, Entry,
};
use crate::field::{HeightField, MAX_SIDE};
use crate::math::Real;
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::{bilinear_search_segment, corners, Surface};
use core::ops::Range;

mod lanes;
pub use lanes::{trace_lanes, LANES, LANES_AVX2};

/// Most levels a pyramid has: fewer than 2²⁴ cells per side need at most 25.
pub const MAX_LEVELS: usize = 25;

/// Where each level of the pyramid of a W × H field lies in its slice: level 0
/// ((W−1) × (H−1) texels) first, then each coarser level, row-major, to 1 × 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    levels: u32,
    dims: [[u32; 2]; MAX_LEVELS],
    offsets: [usize; MAX_LEVELS + 1],
}

impl Layout {
    /// The layout for a `width × height` field; `None` unless both are in
    /// `2..=MAX_SIDE` (what [`HeightField`] accepts).
    pub fn new(width: u32, height: u32) -> Option<Layout> {
        let ok = |n: u32| (2..=MAX_SIDE).contains(&n);
        if !ok(width) || !ok(height) {
            return None;
        }
        let mut layout = Layout {
            levels: 0,
            dims: [[0; 2]; MAX_LEVELS],
            offsets: [0; MAX_LEVELS + 1],
        };
        let mut dims = [width - 1, height - 1];
        loop {
            let l = layout.levels as usize;
            layout.dims[l] = dims;
            layout.offsets[l + 1] = layout.offsets[l] + dims[0] as usize * dims[1] as usize;
            layout.levels += 1;
            if dims == [1, 1] {
                return Some(layout);
            }
            dims = dims.map(|n| n.div_ceil(2));
        }
    }

    /// The layout for `hf`.
    pub fn of(hf: &HeightField) -> Layout {
        Layout::new(hf.width(), hf.height()).expect("a valid field has a valid size")
    }

    /// The texels of every level that depend on the samples `[x0, x1) × [y0, y1)`
    /// (a non-empty rectangle inside the field), finest level first: `(level, lo, hi)`,
    /// texels `[lo[0], hi[0]) × [lo[1], hi[1])` of that level. What [`update_rect`]
    /// rebakes, and what a GPU update dispatches over, level by level.
    pub fn update_ranges(
        &self,
        x0: u32,
        y0: u32,
        x1: u32,
        y1: u32,
    ) -> impl Iterator<Item = (u32, [u32; 2], [u32; 2])> {
        // Sample s is a corner of cells s − 1 and s: the cells touched, half-open.
        let cells = self.dims(0);
        let first = (
            0,
            [x0.saturating_sub(1), y0.saturating_sub(1)],
            [x1.min(cells[0]), y1.min(cells[1])],
        );
        let levels = self.levels;
        core::iter::successors(Some(first), move |&(level, lo, hi)| {
            (level + 1 < levels).then(|| {
                (
                    level + 1,
                    lo.map(|v| v >> 1),
                    hi.map(|v| ((v - 1) >> 1) + 1),
                )
            })
        })
    }

    /// Number of levels (level `levels − 1` is the single top texel).
    #[inline]
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// Texels of `level` along x and y.
    #[inline]
    pub fn dims(&self, level: u32) -> [u32; 2] {
        self.dims[level as usize]
    }

    /// Index of the first texel of `level` in the pyramid slice.
    #[inline]
    pub fn offset(&self, level: u32) -> usize {
        self.offsets[level as usize]
    }

    /// Texels of all levels together: the pyramid slice's length.
    #[inline]
    pub fn texel_count(&self) -> usize {
        self.offsets[self.levels as usize]
    }

    /// Splits a pyramid slice into the texels of `level − 1` (empty for level 0) and of
    /// `level`: what [`bake_rows`] reads and writes. `pyramid` must hold
    /// [`Layout::texel_count`] texels.
    pub fn split_level<'p>(
        &self,
        pyramid: &'p mut [f32],
        level: u32,
    ) -> (&'p [f32], &'p mut [f32]) {
        let (finer, rest) = pyramid.split_at_mut(self.offset(level));
        let finer = if level == 0 {
            &finer[..0]
        } else {
            &finer[self.offset(level - 1)..]
        };
        let len = self.offset(level + 1) - self.offset(level);
        (finer, &mut rest[..len])
    }
}

/// Length of the pyramid slice of a `width × height` field (0 for an invalid size).
pub fn pyramid_len(width: u32, height: u32) -> usize {
    Layout::new(width, height).map_or(0, |l| l.texel_count())
}

/// Why a pyramid view, bake or update refused its buffer or rectangle (the crate's
/// one [`BufferError`](crate::buffer::BufferError)).
pub type PyramidError = crate::buffer::BufferError;

/// Checks the pyramid slice length for `hf`.
fn check_len(layout: &Layout, len: usize) -> Result<(), PyramidError> {
    crate::buffer::check("pyramid", layout.texel_count(), len)
}

/// Maximum of two finite values (compiles to one `maxps`).
#[inline(always)]
fn mx(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// Level-0 texels `cols` of row `j` into `out`: the maximum of each cell's corners.
fn level0_row(hf: &HeightField, j: u32, cols: Range<u32>, out: &mut [f32]) {
    let (s, stride) = (hf.samples(), hf.stride());
    let (c0, n) = (cols.start as usize, out.len());
    let r0 = &s[j as usize * stride + c0..][..n + 1];
    let r1 = &s[(j as usize + 1) * stride + c0..][..n + 1];
    let (a0, a1, b0, b1) = (&r0[..n], &r0[1..], &r1[..n], &r1[1..]);
    for i in 0..n {
        out[i] = mx(mx(a0[i], a1[i]), mx(b0[i], b1[i]));
    }
}

/// Texels `cols` of row `j` of a coarser level into `out`, from `finer` (`fdims` texels):
/// the maximum of the 2 × 2 children, or of those that exist at an odd edge.
fn coarse_row(finer: &[f32], fdims: [u32; 2], j: u32, cols: Range<u32>, out: &mut [f32]) {
    let fw = fdims[0] as usize;
    let row = |r: u32| &finer[r.min(fdims[1] - 1) as usize * fw..][..fw];
    let (r0, r1) = (row(2 * j), row(2 * j + 1));
    let c0 = cols.start as usize;
    let pairs = (cols.end as usize).min(fw / 2).max(c0) - c0;
    let (a, b) = (&r0[2 * c0..2 * (c0 + pairs)], &r1[2 * c0..2 * (c0 + pairs)]);
    for ((o, a), b) in out.iter_mut().zip(a.chunks_exact(2)).zip(b.chunks_exact(2)) {
        *o = mx(mx(a[0], a[1]), mx(b[0], b[1]));
    }
    // At most one texel left: the last one of an odd-width level, with one child column.
    for o in &mut out[pairs..] {
        *o = mx(r0[fw - 1], r1[fw - 1]);
    }
}

/// Bakes rows `rows` of `level` of `hf`'s pyramid into `out`, which holds exactly those
/// rows (`rows.len() × dims(level)[0]` texels); `finer` is level `level − 1` (ignored for
/// level 0, which reads the samples). Levels must be baked finest first; the rows of one
/// level can be baked in any order or in parallel (see [`Layout::split_level`]).
///
/// Panics when `rows` or the slices do not fit the layout.
pub fn bake_rows(hf: &HeightField, level: u32, rows: Range<u32>, finer: &[f32], out: &mut [f32]) {
    let layout = Layout::of(hf);
    let w = layout.dims(level)[0];
    assert!(rows.end <= layout.dims(level)[1] && out.len() == rows.len() * w as usize);
    for (j, row) in rows.zip(out.chunks_exact_mut(w as usize)) {
        if level == 0 {
            level0_row(hf, j, 0..w, row);
        } else {
            coarse_row(finer, layout.dims(level - 1), j, 0..w, row);
        }
    }
}

/// Level-0 rows per band of [`bake`]: the first [`BAND_LEVELS`] levels of a band are
/// baked while its rows are still in cache.
const BAND_LEVELS: u32 = 4;

/// Bakes the whole pyramid of `hf` into `pyramid` (at least [`pyramid_len`] texels).
///
/// Single-threaded; the finest levels go in bands of 2⁴ level-0 rows, each band up to
/// level 4 before the next, which saves re-reading level 0 from memory.
pub fn bake(hf: &HeightField, pyramid: &mut [f32]) -> Result<(), PyramidError> {
    let layout = Layout::of(hf);
    check_len(&layout, pyramid.len())?;
    let banded = BAND_LEVELS.min(layout.levels() - 1);
    let band = 1u32 << banded;
    for j0 in (0..layout.dims(0)[1]).step_by(band as usize) {
        for level in 0..=banded {
            let [w, h] = layout.dims(level);
            let rows = (j0 >> level)..((j0 + band) >> level).min(h);
            let (finer, out) = layout.split_level(pyramid, level);
            let out = &mut out[(rows.start * w) as usize..(rows.end * w) as usize];
            bake_rows(hf, level, rows, finer, out);
        }
    }
    for level in banded + 1..layout.levels() {
        let (finer, out) = layout.split_level(pyramid, level);
        bake_rows(hf, level, 0..layout.dims(level)[1], finer, out);
    }
    Ok(())
}

/// Refreshes the texels of every level that depend on the samples `[x0, x1) × [y0, y1)`
/// of `hf`, after the caller changed them (`hf` being a view of the changed samples);
/// the result equals a full [`bake`]. An empty rectangle does nothing.
pub fn update_rect(
    hf: &HeightField,
    pyramid: &mut [f32],
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
) -> Result<(), PyramidError> {
    let layout = Layout::of(hf);
    check_len(&layout, pyramid.len())?;
    if x0 > x1 || y0 > y1 || x1 > hf.width() || y1 > hf.height() {
        return Err(PyramidError::BadRect);
    }
    if x0 == x1 || y0 == y1 {
        return Ok(());
    }
    for (level, lo, hi) in layout.update_ranges(x0, y0, x1, y1) {
        let w = layout.dims(level)[0] as usize;
        let (finer, out) = layout.split_level(pyramid, level);
        for j in lo[1]..hi[1] {
            let row = &mut out[j as usize * w..][lo[0] as usize..hi[0] as usize];
            if level == 0 {
                level0_row(hf, j, lo[0]..hi[0], row);
            } else {
                coarse_row(finer, layout.dims(level - 1), j, lo[0]..hi[0], row);
            }
        }
    }
    Ok(())
}

/// A baked pyramid for one height field: the read-only view the march uses.
#[derive(Clone, Copy, Debug)]
pub struct MaxMip<'a> {
    layout: Layout,
    texels: &'a [f32],
}

impl<'a> MaxMip<'a> {
    /// Views `texels` (baked by [`bake`] for `hf`, or for a field of the same size that
    /// `hf` has been updated from with [`update_rect`]) as `hf`'s pyramid.
    pub fn new(hf: &HeightField, texels: &'a [f32]) -> Result<MaxMip<'a>, PyramidError> {
        let layout = Layout::of(hf);
        check_len(&layout, texels.len())?;
        Ok(MaxMip { layout, texels })
    }

    /// The layout.
    #[inline]
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Texel `(i, j)` of `level`: the highest sample of that node's cells.
    #[inline]
    pub fn texel(&self, level: u32, i: u32, j: u32) -> f32 {
        let w = self.layout.dims(level)[0] as usize;
        self.texels[self.layout.offset(level) + j as usize * w + i as usize]
    }
}

/// Where the march goes after it leaves a node.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Ascent {
    /// One level up when the crossed boundary is also the parent's (the paper). The
    /// default: 2–5 % fewer fetches than [`Ascent::Highest`] on the maps measured, the
    /// same time within noise.
    #[default]
    OneLevel,
    /// Straight up to the highest level whose node boundary was crossed (the trailing
    /// zeros of the boundary's index): the first node there not yet tested.
    Highest,
}

/// How [`trace`] marches.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Options {
    /// Ascent after leaving a node.
    pub ascent: Ascent,
    /// Level of detail (the paper's §3.3), approximate: with factor `f`, the march stops
    /// descending at level `⌊log₂(f · distance)⌋` (distance from the ray origin, grid
    /// units) and takes that node's box, up to its maximum, for the surface. `f` is
    /// about the angle one pixel subtends, in radians. `None`: exact.
    pub lod: Option<f32>,
    /// Bilinear surface only, approximate: `Some((linear, bisect))` replaces the exact
    /// quadratic in a cell by `linear` equal steps then `bisect` bisections.
    pub iterative_bilinear: Option<(u32, u32)>,
}

impl Options {
    /// `true` when [`trace`] returns the exact answer of [`dda::trace`].
    pub fn is_exact(&self) -> bool {
        self.lod.is_none() && self.iterative_bilinear.is_none()
    }
}

/// Moves one axis to the cell the ray is in just after parameter `t`, when every
/// boundary it crosses at or before `t` has been crossed (the order of [`dda::trace`]),
/// from cell `i` inside the node's cells `[lo, hi)`. Also says whether the last boundary
/// crossed lies exactly at `t` (a corner crossing shared with the other axis).
///
/// [`dda::trace`]: crate::dda::trace
fn sync_axis<R: Real>(i: u32, step: i64, lo: u32, hi: u32, o: R, d: R, t: R) -> (u32, bool) {
    let at = |b: u32| (R::from_u32(b) - o) / d;
    // The estimate; x ≥ 0, so truncation is the floor.
    let x = (o + t * d).clamp_to(R::from_u32(lo), R::from_u32(hi - 1));
    let mut j = x.to_f64() as u32;
    if step > 0 {
        j = j.max(i);
        while j > i && at(j) > t {
            j -= 1;
        }
        while j + 1 < hi && at(j + 1) <= t {
            j += 1;
        }
        (j, j != i && at(j) == t)
    } else {
        j = j.min(i);
        while j < i && at(j + 1) > t {
            j += 1;
        }
        while j > lo && at(j) <= t {
            j -= 1;
        }
        (j, j != i && at(j + 1) == t)
    }
}

/// Level of detail at parameter `t`: the level the march stops descending at.
#[inline]
fn lod_level<R: Real>(per_t: Option<R>, t: R) -> u32 {
    match per_t {
        Some(k) => {
            let v = (k * t).to_f64();
            if v >= 2.0 {
                (v.min(u32::MAX as f64) as u32).ilog2()
            } else {
                0
            }
        }
        None => 0,
    }
}

/// Traces `q` over `hf` with its maximum mipmap `mip` and returns the first hit on
/// `surface`.
///
/// With exact [`Options`] the hit (t, point, cell, normal, flags) is the one of
/// [`dda::trace`] in the same precision, including its semantics for
/// rays that start under the surface ([`Flags::ORIGIN_INSIDE`]) or enter through a side
/// wall ([`Flags::SIDE`]); `clearance` is a lower bound of the DDA's (a skipped node
/// reports the ray's height above its maximum). Supports every surface bounded by its
/// cell's highest corner; [`Surface::CornerPlanes`] is not, and is traced by the DDA.
///
/// Cost: one fetch per pyramid texel read, four per exact cell test.
pub fn trace<R: Real>(
    hf: &HeightField,
    mip: &MaxMip,
    surface: Surface,
    q: &Query<R>,
    opts: &Options,
) -> Trace<R> {
    let march = March::new(hf, mip, surface, opts);
    let trace = match march.begin(q) {
        Ok(mut walk) => loop {
            if let Some(trace) = march.advance(&mut walk) {
                break trace;
            }
        },
        Err(trace) => trace,
    };
    march.finish(q, trace)
}

/// What every ray's march over one pyramid reads: the field, the pyramid, the surface
/// and the options, with what follows from them.
struct March<'m, 'a> {
    hf: &'m HeightField<'a>,
    mip: &'m MaxMip<'m>,
    surface: Surface,
    opts: &'m Options,
    cells: [u32; 2],
    top: u32,
    iterative: Option<(u32, u32)>,
}

/// One ray's march between two node visits ([`March::advance`]).
#[derive(Clone, Copy)]
struct Walk<R: Real> {
    q: Query<R>,
    span: dda::Span<R>,
    step: [i64; 2],
    /// Level-of-detail factor per unit `t` (`None`: exact).
    lod: Option<R>,
    cell: [u32; 2],
    level: u32,
    /// Where the ray entered the current node, and whether that is the span's start.
    t: R,
    p: [R; 3],
    start: bool,
    /// How the current cell was entered: `on[axis] = Some(far)` when through a
    /// centerline crossing on that axis, or a side of the footprint (see
    /// `local_clearance`, `entry_on`).
    on: [Option<bool>; 2],
    fetches: u32,
    clearance: R,
}

impl<'m, 'a> March<'m, 'a> {
    fn new(
        hf: &'m HeightField<'a>,
        mip: &'m MaxMip<'m>,
        surface: Surface,
        opts: &'m Options,
    ) -> Self {
        March {
            hf,
            mip,
            surface,
            opts,
            cells: [hf.width() - 1, hf.height() - 1],
            top: mip.layout().levels() - 1,
            iterative: opts
                .iterative_bilinear
                .filter(|_| surface == Surface::Bilinear),
        }
    }

    /// The exact answer gets the DDA's robust finish, the approximate ones keep theirs
    /// (the iterative bilinear search is approximate on the bilinear surface only).
    fn finish<R: Real>(&self, q: &Query<R>, trace: Trace<R>) -> Trace<R> {
        let opts = self.opts;
        if opts.lod.is_none()
            && (opts.iterative_bilinear.is_none() || self.surface != Surface::Bilinear)
        {
            finish(self.hf, self.surface, q, trace)
        } else {
            trace
        }
    }

    /// The walk of `q` at its first node, or its whole answer (before the finish) when
    /// it needs no march: a miss of the box, or the DDA on corner planes.
    fn begin<R: Real>(&self, q: &Query<R>) -> Result<Walk<R>, Trace<R>> {
        let (hf, surface, cells) = (self.hf, self.surface, self.cells);
        if surface == Surface::CornerPlanes {
            return Err(dda::trace(hf, surface, q));
        }
        let Some(span) = clip(hf, q) else {
            return Err(Trace::MISS);
        };
        let d = q.dir();
        let p = q.at(span.t0);
        let first = |k: usize| {
            cell_index(
                p[k].clamp_to(R::ZERO, R::from_u32(cells[k])),
                d[k],
                cells[k],
            )
        };
        // Start where nodes are a quarter to an eighth of the ray's horizontal reach over
        // the span: from higher up, nearly every ray pays a fetch per level only to
        // descend (measured: 15–45 % fewer fetches on the maps); the march ascends when
        // it pays.
        let reach = (d[0].abs().max(d[1].abs()) * (span.t1 - span.t0)).to_f64();
        let start_level = (reach.min(f64::from(1u32 << 30)) as u32 + 1)
            .ilog2()
            .saturating_sub(2);
        Ok(Walk {
            q: *q,
            step: [step_of(d[0]), step_of(d[1])],
            lod: self
                .opts
                .lod
                .map(|f| R::from_f32(f) * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()),
            cell: [first(0), first(1)],
            level: start_level.min(self.top),
            t: span.t0,
            p,
            start: true,
            on: entry_on(surface, &span.entry),
            span,
            fetches: 0,
            clearance: R::INFINITY,
        })
    }

    /// Visits the walk's current node: skips it, descends into it, or tests its cell;
    /// the answer (before the finish) once the ray hits or leaves the field.
    #[inline]
    fn advance<R: Real>(&self, w: &mut Walk<R>) -> Option<Trace<R>> {
        let node = self.node(w);
        let top_z = R::from_f32(self.mip.texel(
            w.level,
            w.cell[0] >> w.level,
            w.cell[1] >> w.level,
        ));
        w.fetches += 1;
        let low = w.p[2].min(node.pb[2]);
        if low > top_z {
            w.clearance = w.clearance.min(low - top_z);
        } else if w.level > lod_level(w.lod, w.t) {
            w.level -= 1;
            return None;
        } else if w.level > 0 {
            // Level of detail: the node's box up to its maximum is the surface.
            let (t, tb, lo, hi) = (w.t, node.tb, node.lo, node.hi);
            let hit = lod_hit(&w.q, &w.span, w.start, w.on, w.step, t, tb, top_z, lo, hi);
            return Some(Trace::hit(hit, w.fetches, w.clearance));
        } else if let Some(trace) = self.cell_test(w, &node) {
            return Some(trace);
        }
        self.leave(w, &node)
    }

    /// The walk's current node at its level: its cells, the boundary the ray leaves it
    /// through on each axis and when, and where the ray is then.
    #[inline]
    fn node<R: Real>(&self, w: &Walk<R>) -> Node<R> {
        let (o, d) = (w.q.origin(), w.q.dir());
        let mut n = Node {
            lo: [0; 2],
            hi: [0; 2],
            bound: [0; 2],
            t_out: [R::INFINITY; 2],
            t_next: R::INFINITY,
            crossing: false,
            tb: R::ZERO,
            pb: [R::ZERO; 3],
        };
        for k in 0..2 {
            n.lo[k] = (w.cell[k] >> w.level) << w.level;
            n.hi[k] = (n.lo[k] + (1 << w.level)).min(self.cells[k]);
            n.bound[k] = if w.step[k] > 0 { n.hi[k] } else { n.lo[k] };
            if w.step[k] != 0 {
                n.t_out[k] = (R::from_u32(n.bound[k]) - o[k]) / d[k];
            }
        }
        n.t_next = n.t_out[0].min(n.t_out[1]);
        n.crossing = n.t_next < w.span.t1;
        n.tb = if n.crossing {
            n.t_next.max(w.t)
        } else {
            w.span.t1
        };
        n.pb = w.q.at(n.tb);
        n
    }

    /// Level 0: the exact test of dda::trace on the walk's cell, on the same shared edge
    /// clearances; the hit, if the ray meets the surface in the cell. Always inlined:
    /// called out of line from the lanes' step, it took about 6 % more of a random
    /// ray's time there (its walk and corners passed through memory).
    #[inline(always)]
    fn cell_test<R: Real>(&self, w: &mut Walk<R>, node: &Node<R>) -> Option<Trace<R>> {
        let (surface, step) = (self.surface, w.step);
        let (cell, p, t, tb) = (w.cell, w.p, w.t, node.tb);
        let c: [R; 4] = corners(self.hf, cell[0], cell[1]);
        w.fetches += 4;
        // Read a side at a time, as they were written: read whole, the pair waits for
        // its two stores to retire (a failed store forward).
        let on = [w.on[0], w.on[1]];
        let (a, ca) = local_clearance(surface, c, cell, p, on);
        // Past the start a continuous surface leaves `ca > 0` unless rounding lifts an
        // edge above its node's maximum (discontinuous ones ignore `ca`).
        if ca <= R::ZERO && (w.start || surface.is_continuous()) {
            let hit = if w.start {
                start_hit(surface, &w.span, c, cell, a, p)
            } else {
                // A graze of the edge the ray came in through.
                Hit {
                    t,
                    point: R::v3(p),
                    cell,
                    normal: R::v3(surface.cell_normal(c, a[0], a[1])),
                    flags: Flags::default(),
                }
            };
            let clearance = match w.start {
                true => start_clearance(&w.span.entry, ca),
                false => w.clearance.min(ca),
            };
            return Some(Trace::hit(hit, w.fetches, clearance));
        }
        let exit =
            |k: usize| (node.crossing && node.t_out[k] <= node.t_next).then_some(step[k] > 0);
        let (b, cb) = local_clearance(surface, c, cell, node.pb, [exit(0), exit(1)]);
        let wall = entry_wall(on, step);
        let seg = match self.iterative {
            Some(steps) => bilinear_search_segment(c, a, b, ca, cb, steps),
            None => surface.segment_hit(c, a, b, ca, cb, wall),
        };
        w.clearance = w.clearance.min(seg.clearance);
        // As dda::trace (the iterative bilinear search's `s` included).
        seg.hit.map(|found| {
            Trace::hit(
                segment_point(cell, ((t, tb), (a, b)), found),
                w.fetches,
                w.clearance,
            )
        })
    }

    /// Leaves the node: steps over the crossed boundaries, brings the other axis up to
    /// date, ascends; the miss when the ray leaves the field.
    #[inline]
    fn leave<R: Real>(&self, w: &mut Walk<R>, node: &Node<R>) -> Option<Trace<R>> {
        let (cells, step, level) = (self.cells, w.step, w.level);
        if !node.crossing {
            return Some(Trace::miss(w.fetches, w.clearance));
        }
        let (o, d) = (w.q.origin(), w.q.dir());
        let mut crossed_level = level;
        for k in 0..2 {
            let bound = node.bound[k];
            if step[k] != 0 && node.t_out[k] <= node.t_next {
                if bound == if step[k] > 0 { cells[k] } else { 0 } {
                    return Some(Trace::miss(w.fetches, w.clearance));
                }
                w.cell[k] = if step[k] > 0 { bound } else { bound - 1 };
                w.on[k] = Some(step[k] < 0);
                crossed_level = crossed_level.max(bound.trailing_zeros());
            } else if step[k] != 0 && level > 0 {
                let (lo, hi) = (node.lo[k], node.hi[k]);
                let (i, exact) = sync_axis(w.cell[k], step[k], lo, hi, o[k], d[k], node.t_next);
                (w.cell[k], w.on[k]) = (i, exact.then_some(step[k] < 0));
            } else {
                w.on[k] = None;
            }
        }
        w.level = match self.opts.ascent {
            Ascent::OneLevel if crossed_level > level => level + 1,
            Ascent::OneLevel => level,
            Ascent::Highest => crossed_level,
        }
        .min(self.top);
        (w.t, w.p, w.start) = (node.tb, node.pb, false);
        None
    }
}

/// The node a walk is in ([`March::node`]).
#[derive(Clone, Copy)]
struct Node<R: Real> {
    lo: [u32; 2],
    hi: [u32; 2],
    bound: [u32; 2],
    t_out: [R; 2],
    t_next: R,
    crossing: bool,
    tb: R,
    pb: [R; 3],
}

/// Normal of the wall a cell was entered through (up at the start), as [`dda::trace`]
/// passes it to [`Surface::segment_hit`].
///
/// [`dda::trace`]: crate::dda::trace
#[inline]
fn entry_wall<R: Real>(on: [Option<bool>; 2], step: [i64; 2]) -> [R; 3] {
    let toward = |k: usize| if step[k] > 0 { -R::ONE } else { R::ONE };
    match on {
        [Some(_), _] => [toward(0), R::ZERO, R::ZERO],
        [None, Some(_)] => [R::ZERO, toward(1), R::ZERO],
        [None, None] => [R::ZERO, R::ZERO, R::ONE],
    }
}

/// The level-of-detail hit in the node `[lo, hi)` between `t` and `tb`, whose box up to
/// `top_z` the ray enters: at `t` through a wall when already below the top, else where
/// it comes down through the top.
#[allow(clippy::too_many_arguments)]
fn lod_hit<R: Real>(
    q: &Query<R>,
    span: &dda::Span<R>,
    start: bool,
    on: [Option<bool>; 2],
    step: [i64; 2],
    t: R,
    tb: R,
    top_z: R,
    lo: [u32; 2],
    hi: [u32; 2],
) -> Hit<R> {
    let (o, d) = (q.origin(), q.dir());
    let (th, normal, flags) = if q.at(t)[2] <= top_z {
        let flags = match span.entry {
            Entry::Start if start => Flags::ORIGIN_INSIDE,
            Entry::Side(_) if start => Flags::SIDE,
            _ => Flags::default(),
        };
        (t, entry_wall(on, step), flags)
    } else {
        let th = ((top_z - o[2]) / d[2]).clamp_to(t, tb);
        (th, [R::ZERO, R::ZERO, R::ONE], Flags::default())
    };
    let p = q.at(th);
    // Inside the node, x ≥ 0: truncation is the floor.
    let at = |k: usize| {
        p[k].clamp_to(R::from_u32(lo[k]), R::from_u32(hi[k] - 1))
            .to_f64() as u32
    };
    let cell = [at(0), at(1)];
    Hit {
        t: th,
        point: R::v3(p),
        cell,
        normal: R::v3(normal),
        flags,
    }
}
