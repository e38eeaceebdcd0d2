//! Cylinder–cone safety shapes (Baboud, Eisemann, Seidel 2011, §6.3): bake, packing
//! and march, on top of the safety distances of the parent module.
//!
//! **Shape.** Per texel and class ([`super::CLASSES`]), in the class's frame (forward
//! distance `u` from the texel's centerline, minor coordinate `y`, height `z`):
//! - the *cylinder* radius `r`: the safety distance ([`super::texel_distance`]), no
//!   limiting triangle in the columns `u ∈ [0, r)`;
//! - the *cone* `z ≤ z_c + s_c·u`: every limiting triangle ([`RaySet`]) in the
//!   columns `r ≤ u < cap`, over the part of it a ray from the segment can reach
//!   (`lo − u ≤ y ≤ hi + u`), lies under that line. `z_c` is the highest point of the
//!   surface on the (widened) segment; `s_c` the smallest slope that makes the line
//!   bound them (`−∞` when there is none: stored as the lowest code).
//!
//! **Step.** A ray crossing the texel's centerline above the surface at height `p_z`,
//! with *rise per centerline* `s_d = d_z / |d_main|` (negative for downward rays,
//! positive for upward/shadow rays), stays above that line for all
//! `u ≤ (p_z − z_c) / (s_c − s_d)` when `s_c > s_d`, and for all `u` when `s_d ≥ s_c`
//! and `p_z > z_c`. It cannot leave the solid where it is above every limiting
//! triangle, nor inside the cylinder, so it may skip
//! `i = max(r, min(cap, floor((p_z − z_c) / (s_c − s_d))))` centerlines
//! (`i = max(r, cap)` when `s_d ≥ s_c`, `i = r` when `p_z ≤ z_c`). `floor`, not
//! `ceil`: past `(p_z − z_c)/(s_c − s_d)` the ray may be under the line, where a
//! limiting triangle may be. The march ([`trace`]) evaluates the clearance at the
//! target and bisects when below, exactly like the SD march ([`super::trace`]); the
//! numerator loses twice the march's rounding bound, the denominator is rounded up.
//!
//! **Slopes.** [`Slope::Exact`] takes `s_c` over the limiting triangles only: each
//! triangle clipped to the reachable band (a convex polygon of at most five vertices);
//! `(plane − z_c)/u` is linear-fractional, so its maximum is at a vertex. A column's
//! maximum samples over its reachable range on its near side (`u = k`) and its far
//! side (`u = k + 1`) (from the N-buffer, two lookups each) bound the slope its
//! triangles can give; columns are scanned highest bound first (branch and bound: the
//! slope rises early, and a column is skipped once its bound cannot raise `s_c`); the
//! first pass stops when the field's maximum cannot.
//! [`Slope::NBuffer`] counts every triangle as limiting: per abscissa (the paper's
//! "maximum heights per abscissa"), the sample column at `u ≥ 1` bounds its samples'
//! slopes by its maximum over the band of column `u` (which holds column `u − 1`'s),
//! over `u`; column 0 (when `r = 0`) is taken exactly, like the exact slope does
//! (dividing by `u = 0` would leave no cone; its non-limiting triangles may be left
//! out there as anywhere, and testing them is cheaper than clipping them). The slope
//! is the largest of these bounds over the abscissas of the columns `max(r, 1) ≤ k`,
//! found block by block of `BLOCK` columns, highest block bound first, skipping the
//! blocks whose bound cannot raise it.
//!
//! **N-buffers** ([`nbuffer_len`], [`prepare_nbuffer`]): per axis, per sample column
//! and level `L`, the maximum over `2^L` consecutive samples along the cross axis; any
//! range is two lookups at level `⌊log₂ len⌋`. Levels up to the widest reachable
//! range, `2·cap + 5` samples. On each level, after the sample columns, the same per
//! block of `BLOCK` consecutive cell columns (the maximum over their `BLOCK + 1`
//! sample columns). [`nbuffer_steps`] fills them, on the CPU or as GPU passes.
//!
//! **Pruning.** Only the slope's code is stored, so the bake keeps the slope so far
//! rounded up to a code's value (`C(s)`, `code_ceiling`): `C` is monotone and
//! `C(max(a, C(b))) = C(max(a, b))`, so the result is the code of the maximum, and a
//! bound `≤ C(s)` cannot change it (a wider skip than `≤ s`). A skipped block or
//! column of the N-buffer slope only leaves out bounds that cannot exceed the slope
//! so far, and the slope is their maximum, so the order of visits does not change
//! it. The exact slope skips a cell when neither its highest sample (the N-buffer's
//! level 1) nor its highest corners on the near and far side (over `u = k` and
//! `u = k + 1`: a triangle's slope is largest at a corner) can raise the slope, or,
//! for a cell the band's edge cuts off but for a corner, no vertex of the part left
//! can (`Column::tip_under`), so its result does not depend on how the skipping is
//! organised either.
//!
//! **Packing** (the GPU layout: docs/DESIGN.md, "Texture layouts", cylinder–cone;
//! [`map_len`], [`texel_offset`]): `[r, s]`, two bytes per texel and class, each texel
//! row as one row per class. A ray reads one class only, so its texels lie side by side (a
//! quarter of the cache lines a texel-interleaved map needs: ~20% faster CPU marches
//! on the Himalaya benchmark), and row ranges stay contiguous for split bakes. A map
//! of fewer classes ([`bake_rows_classes`]) holds only their rows, `n` rows per texel
//! row for its `n` classes ([`super::ClassRows`]: texel `(i, n·j + slot)`, 2n bytes
//! per texel). `r` the safety distance (u8, exact, capped at 255 by the SD scan); `s`
//! the slope code, decoded `s_c = t·|t| / 2048` with `t = s − 128` (exact in `f32`;
//! ±1/1024 near 0, 1/16 near 2, up to 7.75), **rounded up** (the line only rises);
//! `s = 255` means "no cone" (`s_c > 7.75` saturates there: the step is then `r`, the
//! SD step; `s_c < −8` saturates to −8, which is larger, so safe). Rounding never
//! enlarges a shape: `r` is exact and `s_c` only grows, so the line only rises and the
//! step only shrinks.
//!
//! **Base height.** `z_c` is not stored: it is a function of the three samples of the
//! texel's centerline around it ([`base_height`]), which the march reads when the texel
//! has a cone (one fetch more than the line's two, none at the field's border). The map
//! is then half the size it would be with a 16-bit `z_c` beside each `[r, s]`, and
//! nothing but the slope is quantised. The march computes `z_c` in `R` and allows for
//! its rounding (`8·ε·(z_s + |z_c|)`, `z_s` the field's largest `|height|`, beside the
//! other rounding terms of the step), so it never uses a line lower than the bake's.

use core::ops::Range;

use super::{
    axis_of, band_cells, cell_tris, check_len, column_ahead, extents, march_with, sample, sigma_of,
    strides, texel_distance, tri_masks, AllRays, ClassRows, Jump, Line, MarchSurface, Occluder,
    Occluders, RaySet, Rays, RaysError, SafetyError, Sigma, Tri, Variant, CLASSES,
};
use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Query, RayClass, Trace};
use crate::scene::RayClasses;

/// Bytes per texel and class of the packed map (`[r, s]`).
pub const BYTES_PER_CLASS: usize = 2;

/// Bytes per texel of the packed map (two per class, four classes).
pub const BYTES_PER_TEXEL: usize = 4 * BYTES_PER_CLASS;

/// Slope code meaning "no cone": the step is the cylinder radius only.
pub const NO_CONE: u8 = 255;

/// Lowest slope a code stores (`t = −128`).
pub const S_MIN: f64 = -8.0;

/// Highest finite slope a code stores (`t = 126`).
pub const S_MAX: f64 = 126.0 * 126.0 / 2048.0;

/// How the cone slope is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Slope {
    /// Over the limiting triangles only, exactly.
    Exact,
    /// Every triangle limiting, the highest sample per abscissa from the N-buffers
    /// (conservative, faster).
    NBuffer,
}

/// What the bake computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CcOptions {
    /// How `s_c` is computed.
    pub slope: Slope,
    /// Longest cone step (centerlines); the bake scans that far. The march must use the
    /// same value ([`CcMap::new`]).
    pub cap: u8,
}

impl Default for CcOptions {
    fn default() -> Self {
        CcOptions {
            slope: Slope::Exact,
            cap: 64,
        }
    }
}

/// The packed bytes a class the map does not hold reads: radius 0 without a cone (a
/// zero jump, [`CcMap::with_classes`]).
const NOT_HELD: [u8; 2] = [0, NO_CONE];

/// Bytes of a whole packed map: `W · H · 8`.
pub fn map_len(width: u32, height: u32) -> usize {
    map_len_classes(width, height, RayClasses::ALL)
}

/// Bytes of a packed map holding the classes of `classes` ([`bake_rows_classes`]):
/// `W · H · 2n` for the set's `n` classes.
pub fn map_len_classes(width: u32, height: u32, classes: RayClasses) -> usize {
    width as usize * height as usize * BYTES_PER_CLASS * classes.count() as usize
}

/// Where `class`'s texels lie in a packed map `width` texels wide holding `classes`
/// (2 bytes from `2 ·` [`ClassRows::index`]); `None` when it does not hold `class`.
#[inline]
fn class_rows(width: u32, classes: RayClasses, class: RayClass) -> Option<ClassRows> {
    ClassRows::of(width, Variant::Directional, classes, class)
}

/// Offset in a whole packed map `width` texels wide of the two bytes of texel
/// `(i, j)` for `class` (see the module's **Packing**): `((j·4 + class)·W + i)·2`.
#[inline]
pub fn texel_offset(width: u32, class: RayClass, i: u32, j: u32) -> usize {
    class_rows(width, RayClasses::ALL, class).map_or(0, |at| at.index(i, j) * BYTES_PER_CLASS)
}

/// N-buffer levels for a cone reach `cap`.
fn levels(cap: u8) -> u32 {
    let span = 2 * u32::from(cap) + 6;
    32 - span.leading_zeros()
}

/// Cell columns per block of the block N-buffers.
const BLOCK: u32 = 8;

/// `f32` elements of the N-buffers for a `width × height` field and reach `cap`.
pub fn nbuffer_len(width: u32, height: u32, cap: u8) -> usize {
    let (w, h) = (width.max(2) as usize, height.max(2) as usize);
    let b = BLOCK as usize;
    let blocks = (w - 1).div_ceil(b) * h + (h - 1).div_ceil(b) * w;
    levels(cap) as usize * (2 * w * h + blocks)
}

/// Where the N-buffers of axis `ax` lie: their first element, elements per level (its
/// sample columns' then its blocks'), the sample columns' and the blocks' count.
/// Per axis, level by level, the `lm` sample columns then the blocks, `ln` elements
/// each: a level and the one below it are one contiguous range, what a GPU pass
/// binds.
fn nb_layout(width: u32, height: u32, cap: u8, ax: usize) -> NbLayout {
    let (lm, ln) = if ax == 0 {
        (width, height)
    } else {
        (height, width)
    };
    let blocks = (lm - 1).div_ceil(BLOCK);
    let level = (lm + blocks) as usize * ln as usize;
    let base = if ax == 0 {
        0
    } else {
        let blocks0 = (width - 1).div_ceil(BLOCK);
        levels(cap) as usize * (width + blocks0) as usize * height as usize
    };
    NbLayout {
        base,
        level,
        columns: lm,
        blocks,
        row_len: ln,
    }
}

/// [`nb_layout`]'s answer.
#[derive(Clone, Copy)]
struct NbLayout {
    base: usize,
    level: usize,
    columns: u32,
    blocks: u32,
    row_len: u32,
}

/// Fills the N-buffers ([`nbuffer_len`] elements): runs [`nbuffer_steps`] in order.
/// `O(cells · levels)`.
pub fn prepare_nbuffer(hf: &HeightField, cap: u8, nb: &mut [f32]) -> Result<(), SafetyError> {
    let needed = nbuffer_len(hf.width(), hf.height(), cap);
    crate::buffer::check("n-buffer", needed, nb.len())?;
    for step in nbuffer_steps(hf.width(), hf.height(), cap) {
        step.run(hf, &mut nb[..needed]);
    }
    Ok(())
}

/// What an [`NbufferStep`] writes into each element `(r, y)` of its rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NbufferKind {
    /// Level 0 of the sample columns: the sample at main index `r`, minor index `y`.
    Heights = 0,
    /// The next level of columns or blocks: the maximum of the level below at `y` and
    /// at `min(y + half, row_len − 1)`.
    Double = 1,
    /// Level 0 of the blocks: the maximum of level 0 of the block's sample columns
    /// `BLOCK·r ..= min(BLOCK·r + BLOCK, columns − 1)`, in that order.
    Blocks = 2,
}

/// One step of the N-buffer fill: `rows` rows of `row_len` elements (along the minor
/// axis of `axis`) written from element `dst` on, read from element `src` on (the
/// level below, or the sample columns' level 0); a GPU pass of `bake_nbuffer.wgsl`
/// each, as [`prepare_nbuffer`] runs them on the CPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NbufferStep {
    /// What it computes.
    pub kind: NbufferKind,
    /// Main axis of its columns (0: x = c, 1: y = c).
    pub axis: u32,
    /// Rows written: sample columns or blocks.
    pub rows: u32,
    /// Elements per row: samples along the minor axis.
    pub row_len: u32,
    /// First element written.
    pub dst: usize,
    /// First element read (unused by [`NbufferKind::Heights`]).
    pub src: usize,
    /// The doubling's offset ([`NbufferKind::Double`]; 0 else).
    pub half: u32,
    /// Sample columns of the axis (what [`NbufferKind::Blocks`] clamps to).
    pub columns: u32,
}

/// The steps that fill the N-buffers of a `width × height` field for reach `cap`, in
/// an order that reads only what an earlier step wrote: per axis, the sample columns'
/// level 0, the blocks' level 0, then each level above (columns and blocks together).
pub fn nbuffer_steps(width: u32, height: u32, cap: u8) -> impl Iterator<Item = NbufferStep> {
    let levels = levels(cap);
    (0..2u32).flat_map(move |axis| {
        let at = nb_layout(width, height, cap, axis as usize);
        let step = move |kind, rows: u32, dst, src, half| NbufferStep {
            kind,
            axis,
            rows,
            row_len: at.row_len,
            dst,
            src,
            half,
            columns: at.columns,
        };
        let blocks = at.base + at.columns as usize * at.row_len as usize;
        let level = move |l: u32| at.base + l as usize * at.level;
        [
            step(NbufferKind::Heights, at.columns, at.base, at.base, 0),
            step(NbufferKind::Blocks, at.blocks, blocks, at.base, 0),
        ]
        .into_iter()
        .chain((1..levels).map(move |l| {
            let rows = at.columns + at.blocks;
            step(
                NbufferKind::Double,
                rows,
                level(l),
                level(l - 1),
                1 << (l - 1),
            )
        }))
    })
}

impl NbufferStep {
    /// Runs the step on the CPU over `nb` (the whole N-buffers).
    pub fn run(&self, hf: &HeightField, nb: &mut [f32]) {
        let (ln, rows) = (self.row_len as usize, self.rows as usize);
        // Written and read parts never overlap: `src` lies below `dst`.
        let (below, out) = nb.split_at_mut(self.dst);
        let out = &mut out[..rows * ln];
        let ax = self.axis as usize;
        for (r, row) in out.chunks_exact_mut(ln).enumerate() {
            let from = self.src + r * ln;
            match self.kind {
                NbufferKind::Heights => {
                    for (y, v) in row.iter_mut().enumerate() {
                        *v = sample(hf, ax, r as u32, y as u32);
                    }
                }
                NbufferKind::Double => {
                    let half = self.half as usize;
                    for (y, v) in row.iter_mut().enumerate() {
                        *v = mx(below[from + y], below[from + (y + half).min(ln - 1)]);
                    }
                }
                NbufferKind::Blocks => {
                    let first = BLOCK as usize * r;
                    let last = (first + BLOCK as usize).min(self.columns as usize - 1);
                    for (y, v) in row.iter_mut().enumerate() {
                        let column = |c: usize| below[self.src + c * ln + y];
                        *v = (first + 1..=last).fold(column(first), |acc, c| mx(acc, column(c)));
                    }
                }
            }
        }
    }
}

/// The maximum of two finite values as the GPU bake takes it: `a` when `a > b`, else
/// `b` (so a tie of signed zeros keeps `b` on both).
#[inline(always)]
fn mx(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// The N-buffers of one axis, as [`range_max`] reads them (the offsets of their
/// levels and columns, computed once).
#[derive(Clone, Copy)]
struct NbView<'a> {
    nb: &'a [f32],
    /// Index of level 0, column 0, sample 0 of the axis.
    base: usize,
    /// Elements per level (the axis's columns and blocks, `(columns + blocks) · ln`).
    level: usize,
    /// Elements per column (`ln`).
    column: usize,
    /// Highest level.
    top: u32,
}

impl<'a> NbView<'a> {
    /// The N-buffers of axis `ax`: of its sample columns, or (`blocks`) of its blocks
    /// of [`BLOCK`] cell columns, stored after the columns' on each level (the maximum
    /// over the block's sample columns of their entries).
    fn new(hf: &HeightField, nb: &'a [f32], cap: u8, ax: usize, blocks: bool) -> Self {
        let at = nb_layout(hf.width(), hf.height(), cap, ax);
        let column = at.row_len as usize;
        NbView {
            nb,
            base: at.base
                + if blocks {
                    at.columns as usize * column
                } else {
                    0
                },
            level: at.level,
            column,
            top: levels(cap) - 1,
        }
    }
}

/// The views of both axes, `[columns, blocks]` per axis ([`NbView::new`]), as every
/// texel's search reads them: built once per bake.
type Views<'a> = [[NbView<'a>; 2]; 2];

fn views<'a>(hf: &HeightField, nb: &'a [f32], cap: u8) -> Views<'a> {
    [0, 1].map(|ax| [false, true].map(|blocks| NbView::new(hf, nb, cap, ax, blocks)))
}

/// Highest sample over cross samples `a..=b` of the view's sample column (or block)
/// whose level 0 starts at `at`.
#[inline]
fn range_max(v: &NbView, at: usize, a: u32, b: u32) -> f64 {
    let len = b - a + 1;
    let l = (31 - len.leading_zeros()).min(v.top);
    let w = 1usize << l;
    // Two windows of `w` from either end cover [a, b] when `len ≤ 2w` (always below
    // the top level, where `w ≤ len < 2w`); at the top level more may be needed.
    // `f32::max` as it compiles (a NaN test, then the first operand on ties), less
    // the NaN test: heights are finite.
    let max = |m: f32, y: f32| if y > m { y } else { m };
    let first = at + l as usize * v.level + a as usize;
    let last = first + len as usize - w;
    let mut m = max(v.nb[first], v.nb[last]);
    let mut y = first + w;
    while y < last {
        m = max(m, v.nb[y]);
        y += w;
    }
    f64::from(m)
}

/// The cell columns ahead of a texel `(m, n)` (main, minor indices of axis `ax`,
/// direction `sg`) as their bounds read the N-buffers: what [`cone_search`] computes
/// once per texel and class.
struct Ahead<'a> {
    cols: &'a NbView<'a>,
    blocks: &'a NbView<'a>,
    m: u32,
    n: u32,
    sg: i64,
    /// Samples across (`ln`).
    ln: u32,
    /// Where the level 0 of column `k = 0`'s near sample column (`m`, at `u = 0`)
    /// starts in `cols`, and how much further the next sample column's does (`±ln`;
    /// wrapping sums).
    at: usize,
    step: usize,
    zc: f64,
}

impl Ahead<'_> {
    /// The cell column `k` ahead.
    #[inline]
    fn column(&self, k: u32) -> u32 {
        column_ahead(self.m, self.sg, k)
    }

    /// The highest sample, less `z_c`, of the sample column or block of `v` whose
    /// level 0 starts at `at`, over the band column `k` reaches (`n − k − 2 ..= n + k +
    /// 2`, in the field).
    #[inline]
    fn top(&self, v: &NbView, at: usize, k: u32) -> f64 {
        let (a, b) = band_cells(self.n, k, self.ln);
        range_max(v, at, a, b + 1) - self.zc
    }

    /// The highest sample, less `z_c`, of the sample column at `u` ahead (column
    /// `k`'s near side is `u = k`, its far side `u = k + 1`) over the band column `k`
    /// reaches.
    #[inline]
    fn side_top(&self, u: u32, k: u32) -> f64 {
        let at = self.at.wrapping_add((u as usize).wrapping_mul(self.step));
        self.top(self.cols, at, k)
    }

    /// The bound of abscissa `u ≥ 1`, as the N-buffer slope takes it: its sample
    /// column's highest sample over the band of column `u` (which holds the band of
    /// column `u − 1`), over `u`. Column `k ≥ 1`'s [`Ahead::bound`] is at most the
    /// larger of abscissas `k` and `k + 1`'s (`f64` division is monotone).
    #[inline]
    fn abscissa(&self, u: u32) -> f64 {
        self.side_top(u, u) / f64::from(u)
    }

    /// Column `k`'s bound: the larger of its near side's highest reachable sample
    /// over `u = k` and its far side's over `u = k + 1` (a triangle's slope is largest
    /// at a corner). At `k = 0`, `+∞` when the near side reaches above `z_c`, else the
    /// far side's: along an edge from a corner at `u = 0` not above `z_c` to one at
    /// `u = 1`, `(z − z_c)/u` is at most the latter's.
    #[inline(always)]
    fn bound(&self, k: u32) -> f64 {
        let (top_near, top_far) = (self.side_top(k, k), self.side_top(k + 1, k));
        let kf = f64::from(k);
        let far_bound = top_far / (kf + 1.0);
        if k == 0 {
            if top_near > 0.0 {
                f64::INFINITY
            } else {
                far_bound
            }
        } else {
            // Not `max`: neither is NaN.
            let near_bound = top_near / kf;
            if near_bound > far_bound {
                near_bound
            } else {
                far_bound
            }
        }
    }

    /// The blocks of [`BLOCK`] cell columns (in the field's block grid) that hold the
    /// columns `k ∈ ks` (`k ≥ 1`), as [`Block`]s into `out`, those whose bound exceeds
    /// `s` only. `bound` is at least the bound of each of these columns and of the
    /// abscissas `ka..=kb` ([`Ahead::abscissa`]): the block's highest sample (its
    /// sample columns are those of its cell columns' two sides) over the band of `kb`
    /// (the widest) gives `top ≥` each side's `top` of each column; and (`f64`
    /// division being monotone in both operands) `top/ka ≥ top_k/k ≥ top_k/(k + 1)`
    /// when `top > 0` (a column's bound is then `≤ top/ka` whatever the signs),
    /// `top/(kb + 1) ≥ top_k/(k + 1) ≥ top_k/k` when `top ≤ 0`. Blocks go by
    /// increasing `k`; they stop once `(hmax − z_c)/ka ≤ s` with `hmax − z_c > 0`,
    /// which bounds every block further (then `s ≥ 0 ≥` the bound of a block under
    /// `z_c`).
    fn block_bounds(&self, ks: Range<u32>, (s, hmax): (f64, f64), out: &mut Blocks) {
        if ks.is_empty() {
            return;
        }
        let reach = hmax - self.zc;
        // The block of column `ka` and its far column; the next block is one further
        // (`step`), `BLOCK` columns on.
        let c = self.column(ks.start);
        let mut at = self.blocks.base + (c / BLOCK) as usize * self.blocks.column;
        let mut ka = ks.start;
        let mut far = ka
            + if self.sg > 0 {
                BLOCK - 1 - c % BLOCK
            } else {
                c % BLOCK
            };
        // At most 254 columns: 33 blocks.
        while ka < ks.end {
            if reach > 0.0 && reach / f64::from(ka) <= s {
                break;
            }
            let kb = far.min(ks.end - 1);
            let top = self.top(self.blocks, at, kb);
            let bound = if top > 0.0 {
                top / f64::from(ka)
            } else {
                top / (f64::from(kb) + 1.0)
            };
            if bound > s {
                out.push(Block { bound, top, ka, kb }).ok();
            }
            ka = far + 1;
            far += BLOCK;
            at = at.wrapping_add(self.step);
        }
    }
}

/// A block of columns as [`Ahead::block_bounds`] lists it.
#[derive(Clone, Copy)]
struct Block {
    bound: f64,
    /// The block's highest sample over the band of `kb`, less `z_c`.
    top: f64,
    /// The block's first and last columns.
    ka: u32,
    kb: u32,
}

impl Block {
    /// Whether a column or abscissa `k' ≥ k` of the block may have a bound above `s`:
    /// not when `0 < top/k ≤ s`, as its bound is then at most `top/k' ≤ top/k`
    /// ([`Ahead::block_bounds`]; `f64` division is monotone).
    #[inline]
    fn may_exceed(&self, k: u32, s: f64) -> bool {
        self.top <= 0.0 || self.top / f64::from(k) > s
    }
}

type Blocks = heapless::Vec<Block, 40>;

/// The edge of the band `lo − u ≤ y ≤ hi + u` (what a ray from the segment reaches)
/// that cuts cell `c` of column `k` (corners at `u ∈ {k, k + 1}`, `y ∈ {c, c + 1}`),
/// as the half-plane `a·u + b·y + d ≥ 0` it keeps; `None` when the band holds the
/// whole cell. With `lo = n − 9/16`, `hi = n + 9/16` and integer corners, the lower
/// edge keeps every corner iff `c + k ≥ n`, the upper one iff `c + 1 ≤ n + k`; both
/// fail together only when `2k < 1` and `n − 1 < c < n`, never. The sums are exact
/// in `f64`, here as in the clip's own test.
fn band_edge(sigma: &Sigma, k: f64, c: f64) -> Option<(f64, f64, f64)> {
    if c + k < sigma.n {
        Some((1.0, 1.0, -sigma.lo))
    } else if c + 1.0 > sigma.n + k {
        Some((1.0, -1.0, sigma.hi))
    } else {
        None
    }
}

/// Largest `(plane − zc) / u` over the part of `tri` a ray from the segment reaches
/// (the triangle clipped to `edge`, [`band_edge`] of its cell); `+∞` when that part
/// touches the centerline above `zc`.
///
/// Clipping to the band's other edge too would change nothing, so only `edge` is
/// clipped: that edge keeps the whole cell, and the points the clip adds lie in it and
/// are exact (`f` is exact, in sixteenths; it changes by `±1` or `±2` along an edge it
/// crosses, so `s` and the point are exact too). A clip that keeps every vertex keeps
/// the triangle as it is, so neither test nor clip is needed where `edge` is `None`.
/// Each point is taken as the clip makes it (a maximum does not depend on the order;
/// a `±0` tie gives the same code).
fn tri_slope(tri: &Tri, zc: f64, edge: Option<(f64, f64, f64)>) -> f64 {
    let tol = 1e-9 * (1.0 + zc.abs());
    let mut best = f64::NEG_INFINITY;
    let mut on_line_above = false;
    let mut take = |p: [f64; 2]| {
        let z = tri.height_on_line(p[1]) + tri.forward_slope * p[0];
        if p[0] <= 1e-9 {
            on_line_above |= z - zc > tol;
            return;
        }
        // Not `max`: `t` is never NaN here, and `>` is cheaper.
        let t = (z - zc) / p[0];
        if t > best {
            best = t;
        }
    };
    match edge {
        None => tri.verts.into_iter().for_each(take),
        Some((a, b, c)) => {
            // keep a·u + b·y + c ≥ 0
            let f = tri.verts.map(|p| a * p[0] + b * p[1] + c);
            for e in 0..3 {
                let q = (e + 1) % 3;
                let (p, fp, fq) = (tri.verts[e], f[e], f[q]);
                if fp >= 0.0 {
                    take(p);
                }
                if (fp >= 0.0) != (fq >= 0.0) {
                    let s = fp / (fp - fq);
                    let q = tri.verts[q];
                    take([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
                }
            }
        }
    }
    if on_line_above {
        f64::INFINITY
    } else {
        best
    }
}

/// The cone `(z_c, s_c)` of texel `(i, j)` for `class`, beyond the cylinder `r`, in
/// `f64`, `s_c` rounded up to the value of its code ([`encode_slope`]; at least
/// [`S_MIN`]; `+∞` when no cone is possible or the slope is past [`S_MAX`]). `nb` is
/// what [`prepare_nbuffer`] filled for `opts.cap`.
#[allow(clippy::too_many_arguments)]
pub fn texel_cone<S: RaySet>(
    hf: &HeightField,
    nb: &[f32],
    rays: &S,
    class: RayClass,
    i: u32,
    j: u32,
    r: u8,
    opts: CcOptions,
) -> (f64, f64) {
    let views = views(hf, nb, opts.cap);
    cone_search(hf, &views, rays, class, (i, j), r, opts, [None; 3]).0
}

/// A cell of the field as `(main, minor)` cell indices of a class's axis.
type Cell = Option<(u32, u32)>;

/// [`texel_cone`], first raising the slope over the cells `seeds` that lie ahead
/// (for the exact slope: the cells that set the slopes of the neighbours on the left,
/// above and above on the right, whose triangles often set this one's too, so that the search prunes
/// from the start; the result does not depend on them, see the module's **Pruning**).
/// Also returns the cell that set the slope, if any.
#[allow(clippy::too_many_arguments)]
fn cone_search<S: RaySet>(
    hf: &HeightField,
    views: &Views,
    rays: &S,
    class: RayClass,
    texel: (u32, u32),
    r: u8,
    opts: CcOptions,
    seeds: [Cell; 3],
) -> ((f64, f64), Cell) {
    // One instance per class: its axis and direction are then constants in the scans
    // (the same operations on the same values, fewer selects and spills).
    match class {
        RayClass::XPos => class_search::<S, 0, 1>(hf, views, rays, texel, r, opts, seeds),
        RayClass::XNeg => class_search::<S, 0, -1>(hf, views, rays, texel, r, opts, seeds),
        RayClass::YPos => class_search::<S, 1, 1>(hf, views, rays, texel, r, opts, seeds),
        RayClass::YNeg => class_search::<S, 1, -1>(hf, views, rays, texel, r, opts, seeds),
    }
}

/// [`cone_search`] for the class of main axis `AX` and direction `SG`.
#[allow(clippy::too_many_arguments)]
fn class_search<S: RaySet, const AX: usize, const SG: i64>(
    hf: &HeightField,
    views: &Views,
    rays: &S,
    (i, j): (u32, u32),
    r: u8,
    opts: CcOptions,
    seeds: [Cell; 3],
) -> ((f64, f64), Cell) {
    let (ax, sg) = (AX, SG);
    let (lm, ln) = extents(hf, ax);
    let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
    let sigma = sigma_of(hf, ax, sg, m, n);
    let zc = segment_top(&sigma);
    let hmax = f64::from(hf.max_height());
    let mut s = S_MIN;
    // A column's highest samples on its two sides, over its reachable band, bound the
    // slope its triangles can give (`(top − z_c)/u` is largest at a vertex): the exact
    // slope's pruning ([`Ahead::bound`]). The N-buffer slope is the largest bound of
    // the abscissas themselves (past column 0; [`Ahead::abscissa`]).
    let nbv = views[ax][0];
    // Columns `k < kend` lie in the field.
    let kend = u32::from(opts.cap).min(if sg > 0 { lm - 1 - m } else { m });
    let band = |k: u32| band_cells(n, k, ln);
    // Column `k`'s near side is sample column `m + k` ahead, `m − k` behind; its far
    // side the next one.
    let at = nbv.base + m as usize * nbv.column;
    let step = if sg > 0 {
        nbv.column
    } else {
        nbv.column.wrapping_neg()
    };
    let ahead = Ahead {
        cols: &nbv,
        blocks: &views[ax][1],
        m,
        n,
        sg,
        ln,
        at,
        step,
        zc,
    };
    let bound_of = |k: u32| ahead.bound(k);
    // Column `k` as its scans see it ([`Column`]).
    let column = |k: u32| Column::<S, AX, SG> {
        hf,
        nb: &nbv,
        rays,
        sigma: &sigma,
        cm: column_ahead(m, sg, k),
        kf: f64::from(k),
        zc,
    };
    // Raises `s` over the triangles of the cells of column `k` (exactly), noting in
    // `best` the cell that raised it last.
    let scan = |k: u32, s: &mut f64, best: &mut Cell| {
        let (l0, l1) = band(k);
        column(k).scan(l0, l1, s, best);
    };
    let mut best = None;
    // The blocks of columns `ks` whose bound exceeds `s` ([`Ahead::block_bounds`]).
    let blocks_above =
        |ks: Range<u32>, s: f64, out: &mut Blocks| ahead.block_bounds(ks, (s, hmax), out);
    let mut blocks = Blocks::new();
    let k0 = u32::from(r).max(1);
    if opts.slope == Slope::NBuffer {
        // The slope is the largest bound of the abscissas of the columns `k ≥
        // max(r, 1)`, `u ∈ k0..=kend` (the exact slope's stop on `hmax` below would
        // only leave out bounds `≤ s`); the order of visits does not change a
        // maximum: the nearest [`BLOCK`] abscissas (the likeliest maximum) and the
        // last one (no block's) first, then blocks of columns, highest bound first:
        // one whose bound does not exceed `s` is skipped with all its abscissas (the
        // rest are lower still). Then column 0. Not `max` below: bounds are never NaN,
        // and a `±0` tie gives the same code.
        let near = kend.min(k0 + BLOCK);
        let mut top = s;
        if k0 < kend {
            for u in (k0..near).chain([kend]) {
                let b = ahead.abscissa(u);
                if b > top {
                    top = b;
                }
            }
        }
        raise(&mut s, top);
        blocks_above(near..kend, s, &mut blocks);
        while let Some(block) = take_max(&mut blocks, |b| b.bound) {
            if block.bound <= s {
                break;
            }
            // The largest bound so far prunes the block's farther abscissas.
            let mut top = s;
            for u in block.ka..=block.kb {
                if !block.may_exceed(u, top) {
                    break;
                }
                let b = ahead.abscissa(u);
                if b > top {
                    top = b;
                }
            }
            raise(&mut s, top);
        }
        if r == 0 && kend > 0 && bound_of(0) > s {
            scan(0, &mut s, &mut best);
        }
        return ((zc, s), best);
    }
    // The exact slope scans the columns whose bound exceeds `S_MIN` (none when
    // `hmax − z_c ≤ S_MIN·cap`), after the seeds' cells, highest bound first, so that
    // the slope rises early and prunes the rest: a column whose bound does not exceed
    // `s` is skipped (or not even pushed). The
    // order is that of integer keys, the `f32` bound's order-preserving bits, then
    // `k`. They are taken largest first from a queue (with their bound) that starts
    // with column 0 and the blocks of [`Ahead::block_bounds`], keyed by their bound
    // above every column key of the same `f32` bound: a block pops before its columns
    // and is only then expanded into them (or dropped, when its bound does not exceed
    // `s`, as all its columns would be; those past [`Block::may_exceed`] are not even
    // bounded), so columns pop in exactly the key order. Once a popped `f32` bound is
    // below `f32(s)`, so are all the rest (rounding to `f32` is monotone) and none of
    // their bounds exceeds `s`: the scan stops.
    if u32::from(r) >= kend || hmax - zc <= S_MIN * f64::from(opts.cap) {
        return ((zc, s), None);
    }
    for (at, seed) in seeds.iter().enumerate() {
        // Each cell once.
        let Some((cm, c)) = seed.filter(|_| !seeds[..at].contains(seed)) else {
            continue;
        };
        let k = if sg > 0 {
            cm.wrapping_sub(m)
        } else {
            m.wrapping_sub(cm + 1)
        };
        let (l0, l1) = band(k.min(kend));
        if k >= u32::from(r) && k < kend && (l0..=l1).contains(&c) {
            column(k).scan_one(c, &mut s, &mut best);
        }
    }
    let key = |bound: f64, low: u32| {
        let b = (bound as f32).to_bits();
        let ordered = if b >> 31 == 1 { !b } else { b | 1 << 31 };
        u64::from(ordered) << 32 | u64::from(low)
    };
    blocks_above(k0..kend, s, &mut blocks);
    const BLOCK_KEY: u32 = 0xffff_ff00;
    let mut queue = Queue::new();
    if r == 0 {
        let b0 = bound_of(0);
        if b0 > s {
            enqueue(&mut queue, key(b0, 0), b0);
        }
    }
    for (idx, b) in blocks.iter().enumerate() {
        enqueue(&mut queue, key(b.bound, BLOCK_KEY | idx as u32), b.bound);
    }
    while let Some((top, bound)) = take_max(&mut queue, |e| e.0) {
        let low = top as u32;
        let block = (low >= BLOCK_KEY).then(|| blocks[(low - BLOCK_KEY) as usize]);
        if (bound as f32) < s as f32 {
            break;
        }
        if bound <= s {
            continue;
        }
        match block {
            Some(block) => {
                for k in block.ka..=block.kb {
                    if !block.may_exceed(k, s) {
                        break;
                    }
                    let b = bound_of(k);
                    if b > s {
                        enqueue(&mut queue, key(b, k), b);
                    }
                }
            }
            None => {
                scan(low, &mut s, &mut best);
                if s == f64::INFINITY {
                    return ((zc, s), best);
                }
            }
        }
    }
    ((zc, s), best)
}

/// The exact slope's queue of `(key, bound)`, in no order: [`take_max`] takes the
/// largest key, as a max-heap's pop would (the keys are distinct). It holds a few
/// entries (six on average when popped), most of them never popped: a scan per pop
/// costs less than keeping an order.
type Queue = heapless::Vec<(u64, f64), 320>;

#[inline]
fn enqueue(q: &mut Queue, key: u64, bound: f64) {
    // At most 255 columns and 33 blocks: it cannot fail.
    q.push((key, bound)).ok();
}

/// Takes the item of the largest `key` out of `v` (keys are never NaN).
#[inline]
fn take_max<T, K: PartialOrd, const N: usize>(
    v: &mut heapless::Vec<T, N>,
    key: impl Fn(&T) -> K,
) -> Option<T> {
    let (mut at, mut top) = (0, key(v.first()?));
    for (i, x) in v.iter().enumerate().skip(1) {
        let k = key(x);
        if k > top {
            (at, top) = (i, k);
        }
    }
    Some(v.swap_remove(at))
}

/// One column of cells ahead of a texel, as the exact slope scans it.
struct Column<'a, S: RaySet, const AX: usize, const SG: i64> {
    hf: &'a HeightField<'a>,
    nb: &'a NbView<'a>,
    rays: &'a S,
    sigma: &'a Sigma,
    cm: u32,
    kf: f64,
    zc: f64,
}

impl<S: RaySet, const AX: usize, const SG: i64> Column<'_, S, AX, SG> {
    /// [`Column::scan`] of the one cell `c` (a seed's): an instance of its own, where
    /// the scan's loop is a single step, so that a seed costs little more than its
    /// cell (inlining the whole scan here and there, and not this one, measured
    /// fewest instructions).
    #[inline(never)]
    fn scan_one(&self, c: u32, s: &mut f64, best: &mut Cell) {
        self.scan(c, c, s, best)
    }

    /// Raises `s` over the cells `c0..=c1` of the column, skipping every cell whose
    /// highest corners on the near and far sides (the N-buffer's level 1 of the two
    /// sample columns: two reads per cell, in two rows) cannot raise it.
    #[inline(always)]
    fn scan(&self, c0: u32, c1: u32, s: &mut f64, best: &mut Cell) {
        let (near, far) = if SG > 0 {
            (self.cm, self.cm + 1)
        } else {
            (self.cm + 1, self.cm)
        };
        let tops = |col: u32| {
            let row = self.nb.base + self.nb.level + col as usize * self.nb.column;
            &self.nb.nb[row + c0 as usize..=row + c1 as usize]
        };
        let mut bars = self.bars(*s);
        for (c, (&top_near, &top_far)) in (c0..).zip(tops(near).iter().zip(tops(far))) {
            if f64::from(top_near) - self.zc <= bars.near
                && f64::from(top_far) - self.zc <= bars.far
            {
                continue;
            }
            let h = super::cell_corners(self.hf, AX, self.cm, c);
            let under = bars.under(h, self.zc);
            if under == 0b1111 || self.tip_under(c, h, &bars) {
                continue;
            }
            // One raise by the larger slope of the two triangles: `C(max(a, C(b))) =
            // C(max(a, b))` (the module's **Pruning**), and neither slope depends on `s`.
            // A triangle with every corner under the line is left out: its slope does
            // not exceed `s` ([`Bars`]), so it changes neither whether `s` rises nor
            // the maximum it rises to.
            let edge = band_edge(self.sigma, self.kf, f64::from(c));
            let mut slope = f64::NEG_INFINITY;
            let tris = cell_tris(h, self.sigma, AX, SG, self.cm, c);
            for (tri, corners) in tris.iter().zip(tri_masks(h)) {
                if under & corners != corners && self.rays.limiting(self.sigma, tri) {
                    // Not `max`: neither is NaN (±0 tie: same code).
                    let t = tri_slope(tri, self.zc, edge);
                    if t > slope {
                        slope = t;
                    }
                }
            }
            if raise(s, slope) {
                *best = Some((self.cm, c));
                if *s == f64::INFINITY {
                    return;
                }
                bars = self.bars(*s);
            }
        }
    }

    /// The tests of [`Column::scan`] for the slope `s`.
    #[inline]
    fn bars(&self, s: f64) -> Bars {
        let (ln, lf) = (s * self.kf, s * (self.kf + 1.0));
        let margin = 1e-9 * (1.0 + self.zc.abs() + lf.abs());
        // Corner `i` of `h` ([`super::cell_corners`]) lies at `u = k + 1` when its
        // main-axis step (bit 0 of `i` for axis 0, bit 1 for axis 1) goes ahead.
        let lines = core::array::from_fn(|i| {
            let step = if AX == 0 { i & 1 } else { i >> 1 };
            if (step == 1) == (SG > 0) {
                lf - margin
            } else {
                ln - margin
            }
        });
        Bars {
            near: ln,
            far: lf,
            lines,
            s,
            margin,
        }
    }

    /// Whether cell `c` is one the band's edge cuts off but for a corner (`c = n − k −
    /// 2` or `c = n + k + 1`) and no point of the part left can raise `s`. That part
    /// (what a ray from the segment reaches, `lo − u ≤ y ≤ hi + u` with `lo = n −
    /// 9/16`, `hi = n + 9/16`) is the triangle of legs `9/16` at the cell's far corner
    /// on the band's side: the corner, the points `7/16` along the far side and along
    /// the side towards the band, and where the band's edge crosses the diagonal
    /// through the corner (`23/32` along it, when the cell is split there). The
    /// surface is linear on each piece the diagonal leaves, and `(z − z_c)/u` is
    /// largest at a vertex of a piece, so the cell's limiting triangles, clipped
    /// ([`tri_slope`]), cannot raise `s` when these four points lie under the line
    /// (less the margin of [`Bars`], far above the rounding of the interpolations
    /// here and of the clip's plane values).
    #[inline]
    fn tip_under(&self, c: u32, h: [f32; 4], bars: &Bars) -> bool {
        let (cf, n, k) = (f64::from(c), self.sigma.n, self.kf);
        // The corner's minor step: 1 below the band (its upper side), 0 above it.
        let b = if cf + k + 1.0 < n {
            1
        } else if cf > n + k {
            0
        } else {
            return false;
        };
        // Corner `(a, b)` of the cell: `u = k + a`, `y = c + b` ([`Column::bars`] on
        // the order of `h`).
        let z = |a: usize, b: usize| {
            let step = if SG > 0 { a } else { 1 - a };
            f64::from(h[if AX == 0 { step + 2 * b } else { b + 2 * step }])
        };
        let (tip, side, back, diag) = (z(1, b), z(1, 1 - b), z(0, b), z(0, 1 - b));
        [
            (tip, k + 1.0),
            (0.5625 * side + 0.4375 * tip, k + 1.0),
            (0.5625 * back + 0.4375 * tip, k + 0.4375),
            (0.28125 * diag + 0.71875 * tip, k + 0.71875),
        ]
        .iter()
        .all(|&(z, u)| z - self.zc <= bars.s * u - bars.margin)
    }
}

/// What [`Column::scan`] compares a cell with, for the slope so far `s` (the line
/// `z_c + s·u`).
struct Bars {
    /// The line's heights over `u = k` and `u = k + 1`, less `z_c`: a cell whose
    /// highest samples on those sides are no higher (less `z_c`) cannot raise `s` (at
    /// `k = 0`, corners not above `z_c` bound nothing: see [`Ahead::bound`]).
    near: f64,
    far: f64,
    /// Per corner of a cell (as [`super::cell_corners`] orders them), the line's height
    /// over it less `z_c`, lowered by a margin far above rounding.
    lines: [f64; 4],
    /// The slope and that margin.
    s: f64,
    margin: f64,
}

impl Bars {
    /// The corners of `h` under [`Bars::lines`], as a mask (bit `i` for `h[i]`). A
    /// triangle whose corners are all under cannot raise `s`: its slope is largest at a
    /// corner (along an edge `(z − z_c)/u` is monotone; a corner at `u = 0` under `z_c`
    /// only lowers the far one's). All four are under exactly when each side's highest
    /// corner is (the conversion and the subtraction are monotone).
    #[inline]
    fn under(&self, h: [f32; 4], zc: f64) -> u8 {
        (0..4).fold(0, |m, i| {
            m | u8::from(f64::from(h[i]) - zc <= self.lines[i]) << i
        })
    }
}

/// The smallest slope a code stands for that is `>= s` (`+∞` past [`S_MAX`]).
#[inline]
fn code_ceiling(s: f64) -> f64 {
    decode_slope(encode_slope(s))
}

/// Raises `s` (a [`code_ceiling`]) to `code_ceiling(max(s, t))`; whether it rose.
#[inline]
fn raise(s: &mut f64, t: f64) -> bool {
    let rises = t > *s;
    if rises {
        *s = code_ceiling(t);
    }
    rises
}

/// Slope code of `s` rounded up (`NO_CONE` above [`S_MAX`]).
pub fn encode_slope(s: f64) -> u8 {
    if s.is_nan() || s > S_MAX {
        return NO_CONE;
    }
    // Truncation is `floor` (and `ceil_small` is `ceil`) on these non-negative values.
    let mut t = if s >= 0.0 {
        ceil_small(libm::sqrt(2048.0 * s))
    } else {
        -(libm::sqrt(-2048.0 * s).min(128.0) as i32)
    };
    // `t` is the exact answer or one short: `2048·s` is exact and the square root is
    // correctly rounded (an error far below 1 at these sizes), so at most one `ceil`
    // or `floor` step is lost. (A single test: a loop here compiles to a vector block.)
    if t < 126 && decode_t(t) < s {
        t += 1;
    }
    if decode_t(t) < s {
        return NO_CONE;
    }
    (t + 128) as u8
}

/// `⌈x⌉` for `0 ≤ x ≤ 65535` (truncation, then one up when it dropped a fraction).
#[inline]
fn ceil_small(x: f64) -> i32 {
    let t = x as i32;
    t + i32::from(f64::from(t) < x)
}

#[inline]
const fn decode_t(t: i32) -> f64 {
    (t * t.abs()) as f64 / 2048.0
}

/// The slope a code stands for (`+∞` for [`NO_CONE`]).
#[inline]
pub fn decode_slope(code: u8) -> f64 {
    SLOPES[usize::from(code)]
}

/// The cone's base `z_c` of texel `(i, j)` for `class`, as the bake takes it: the
/// highest point of the surface on the texel's widened segment ([`Sigma`]), in `f64`.
/// Not stored: the march computes it from the same three samples.
pub fn base_height(hf: &HeightField, class: RayClass, i: u32, j: u32) -> f64 {
    let ax = axis_of(class);
    let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
    segment_top(&sigma_of(hf, ax, 1, m, n))
}

/// The highest point of the surface on the widened segment `sigma` (it is linear on
/// each side of the texel: the highest of its two ends and the middle).
#[inline]
fn segment_top(sigma: &Sigma) -> f64 {
    let [at_lo, at_hi] = sigma.end_heights();
    at_lo.max(sigma.h).max(at_hi)
}

/// The two packed bytes of a texel and class: `[r, s]`, "no cone" when `sc` saturates.
pub fn pack(r: u8, sc: f64) -> [u8; 2] {
    [r, encode_slope(sc)]
}

/// Bakes texel rows `rows` into `out` (`rows.len() · W · 8` bytes), for every ray.
/// `scratch` is what [`super::prepare`] filled, `nb` what [`prepare_nbuffer`] filled for
/// `opts.cap`. Rows are independent (any job system may split them).
pub fn bake_rows(
    hf: &HeightField,
    scratch: &[f32],
    nb: &[f32],
    rows: Range<u32>,
    opts: CcOptions,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    bake_rows_classes(hf, scratch, nb, RayClasses::ALL, rows, opts, out)
}

/// [`bake_rows`] for the ray classes of `classes` only (a scene's
/// [`BakePlan::classes`](crate::scene::BakePlan::classes)) into a map holding those
/// only (`rows.len() · W · 2n` bytes for the set's `n` classes, [`map_len_classes`]):
/// the others are never computed nor stored, the kept classes' bytes equal the full
/// bake's, each texel row stored as `n` rows in class order ([`super::ClassRows`]).
/// Read it with [`CcMap::with_classes`] for the same set: a ray of a class the map
/// does not hold then reads radius 0 without a cone (`[0, NO_CONE]`: a zero
/// jump, still exact).
pub fn bake_rows_classes(
    hf: &HeightField,
    scratch: &[f32],
    nb: &[f32],
    classes: RayClasses,
    rows: Range<u32>,
    opts: CcOptions,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    bake_rows_with(hf, scratch, nb, &AllRays, classes, rows, opts, out)
}

/// [`bake_rows_classes`] for the rays of `rays` (a [`Rays`] set's
/// [`Rays::on`]): both the radius and the slope count the triangles that limit those
/// rays only. Read it with [`CcMap::with_rays`] for the same set.
#[allow(clippy::too_many_arguments)]
pub fn bake_rows_with<S: RaySet>(
    hf: &HeightField,
    scratch: &[f32],
    nb: &[f32],
    rays: &S,
    classes: RayClasses,
    rows: Range<u32>,
    opts: CcOptions,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    let needed = super::scratch_len(hf.width(), hf.height());
    crate::buffer::check("scratch", needed, scratch.len())?;
    let needed = nbuffer_len(hf.width(), hf.height(), opts.cap);
    crate::buffer::check("n-buffer", needed, nb.len())?;
    if rows.end > hf.height() || rows.start > rows.end {
        return Err(SafetyError::BadRows);
    }
    let needed = (rows.end - rows.start) as usize * map_len_classes(hf.width(), 1, classes);
    crate::buffer::check("output", needed, out.len())?;
    let views = views(hf, nb, opts.cap);
    let rows_of = CLASSES.map(|class| class_rows(hf.width(), classes, class));
    // The rows are baked in chunks of `SEED_SPAN` texels, a class at a time, so that
    // the cells that set the slopes of a chunk's texels fit in a fixed array as seeds
    // for the texels below (a texel's seeds: the cells of its neighbours on the left,
    // above, above right), and the samples and N-buffer entries a chunk reads for a
    // class stay in cache over its rows.
    for i0 in (0..hf.width()).step_by(SEED_SPAN) {
        let i1 = (i0 + SEED_SPAN as u32).min(hf.width());
        for (c, class) in CLASSES.into_iter().enumerate() {
            let Some(at) = rows_of[c] else {
                continue;
            };
            // Per texel of the chunk, the cell that set the slope of the texel above
            // (the previous row of `rows`), then of the texel itself.
            let mut above: [Cell; SEED_SPAN + 1] = [None; SEED_SPAN + 1];
            for (row, j) in rows.clone().enumerate() {
                // The cell that set the slope of the texel on the left.
                let mut left: Cell = None;
                for i in i0..i1 {
                    let k = (i - i0) as usize;
                    let r = texel_distance(hf, scratch, rays, class, i, j, u8::MAX);
                    let sc = if r >= opts.cap {
                        f64::INFINITY
                    } else {
                        let seeds = [left, above[k], above[k + 1]];
                        let (cone, best) =
                            cone_search(hf, &views, rays, class, (i, j), r, opts, seeds);
                        left = best.or(left);
                        above[k] = best.or(above[k]);
                        cone.1
                    };
                    let at = at.index(i, row as u32) * BYTES_PER_CLASS;
                    out[at..at + BYTES_PER_CLASS].copy_from_slice(&pack(r, sc));
                }
            }
        }
    }
    Ok(())
}

/// Texels per chunk of the rows a bake walks ([`bake_rows_classes`]); 65 · 12 bytes
/// of seeds on the stack.
const SEED_SPAN: usize = 64;

/// Prepares both scratches and bakes the whole map, one thread.
pub fn bake(
    hf: &HeightField,
    scratch: &mut [f32],
    nb: &mut [f32],
    opts: CcOptions,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    super::prepare(hf, scratch)?;
    prepare_nbuffer(hf, opts.cap, nb)?;
    bake_rows(hf, scratch, nb, 0..hf.height(), opts, out)
}

/// A packed cylinder–cone map over caller-owned bytes.
#[derive(Clone, Copy, Debug)]
pub struct CcMap<'a> {
    data: &'a [u8],
    width: u32,
    classes: RayClasses,
    cap: u8,
    rays: Rays,
    occluders: Occluders<'a>,
}

/// One texel's shape for one class, decoded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Cylinder radius (centerlines).
    pub r: u32,
    /// Cone base height (`+∞` without a cone).
    pub zc: f64,
    /// Cone slope (`+∞` without a cone).
    pub sc: f64,
}

impl<'a> CcMap<'a> {
    /// Views `data` ([`map_len`] bytes, as [`bake`] wrote it with `opts.cap == cap`).
    pub fn new(hf: &HeightField, data: &'a [u8], cap: u8) -> Result<Self, SafetyError> {
        Self::with_classes(hf, data, cap, RayClasses::ALL)
    }

    /// Views a map holding the classes of `classes` ([`map_len_classes`] bytes, as
    /// [`bake_rows_classes`] wrote it for that set with `opts.cap == cap`): rays of
    /// the other classes read radius 0 without a cone (they walk cell by cell, still
    /// exact).
    pub fn with_classes(
        hf: &HeightField,
        data: &'a [u8],
        cap: u8,
        classes: RayClasses,
    ) -> Result<Self, SafetyError> {
        check_len(data, map_len_classes(hf.width(), hf.height(), classes))?;
        Ok(CcMap {
            data,
            width: hf.width(),
            classes,
            cap,
            rays: Rays::ALL,
            occluders: Occluders::NONE,
        })
    }

    /// The same map, baked for the rays of `rays` ([`bake_rows_with`]): the march
    /// reads it for those rays only ([`Rays::holds`]); any other ray walks cell by
    /// cell (exact).
    pub fn with_rays(self, rays: Rays) -> Self {
        CcMap { rays, ..self }
    }

    /// The rays the map is baked for.
    pub fn rays(&self) -> Rays {
        self.rays
    }

    /// The same map of `hf` with the occluders its set passes over
    /// ([`Rays::occluders`]; refused unless they are the set's). Without them a map
    /// baked for occluders holds no ray: every ray walks cell by cell (exact).
    pub fn with_occluders(
        self,
        hf: &HeightField,
        occluders: &'a [Occluder],
    ) -> Result<Self, RaysError> {
        self.rays.check_occluders(occluders)?;
        let occluders = Occluders::prepare(hf, occluders);
        Ok(CcMap { occluders, ..self })
    }

    /// The occluders given with [`CcMap::with_occluders`].
    pub fn occluders(&self) -> &'a [Occluder] {
        self.occluders.list()
    }

    /// Longest cone step.
    pub fn cap(&self) -> u8 {
        self.cap
    }

    /// The ray classes the map holds.
    pub fn classes(&self) -> RayClasses {
        self.classes
    }

    /// Where `class`'s texels lie (`None`: not held).
    #[inline]
    fn rows(&self, class: RayClass) -> Option<ClassRows> {
        class_rows(self.width, self.classes, class)
    }

    /// The packed bytes `[r, s]` of texel `(i, j)` for `class` (`[0, NO_CONE]`, radius
    /// 0 without a cone, when the map does not hold it).
    #[inline]
    pub fn texel(&self, class: RayClass, i: u32, j: u32) -> [u8; 2] {
        self.rows(class)
            .map_or(NOT_HELD, |at| texel_bytes(self.data, at, i, j))
    }

    /// The decoded shape of texel `(i, j)` for `class`, with its base height from
    /// `hf`, the field the map was baked for ([`base_height`]).
    pub fn shape(&self, hf: &HeightField, class: RayClass, i: u32, j: u32) -> Shape {
        let [r, s] = self.texel(class, i, j);
        let r = u32::from(r);
        if s == NO_CONE {
            return Shape {
                r,
                zc: f64::INFINITY,
                sc: f64::INFINITY,
            };
        }
        Shape {
            r,
            zc: base_height(hf, class, i, j),
            sc: decode_slope(s),
        }
    }
}

/// The two bytes of texel `(i, j)` in `data` at `at` (`2 ·` [`ClassRows::index`]).
#[inline]
fn texel_bytes(data: &[u8], at: ClassRows, i: u32, j: u32) -> [u8; 2] {
    let b = &data[at.index(i, j) * BYTES_PER_CLASS..][..BYTES_PER_CLASS];
    [b[0], b[1]]
}

/// The slope of every code, computed at compile time ([`decode_slope`] reads it: a
/// load instead of the arithmetic, also in the march).
const SLOPES: [f64; 256] = {
    let mut s = [f64::INFINITY; 256];
    let mut code = 0;
    while code < NO_CONE as usize {
        s[code] = decode_t(code as i32 - 128);
        code += 1;
    }
    s
};

/// The constants of a trace's cylinder–cone steps, in `R`: computed once the ray is
/// known to march ([`trace_on`]), not once per step.
struct ConeStep<'a, R> {
    /// The map's longest step.
    cap: u32,
    /// Lower bound of the ray's rise per centerline.
    sd_lo: R,
    /// The field's largest `|height|` (the scale of the base's rounding).
    zs: R,
    /// The field's samples, and their strides along the main and minor axis
    /// (`super::strides`).
    samples: &'a [f32],
    ms: usize,
    ns: usize,
    /// Samples along the minor axis.
    ln: u32,
}

impl<R: Real> ConeStep<'_, R> {
    /// The jump at the crossing `l` above a texel `[r, s]` with a cone (`s` not
    /// [`NO_CONE`], `r < cap`): the base ([`Self::base`]), then the closed-form step.
    #[inline]
    fn cone(&self, l: &Line<R>, [r, s]: [u8; 2]) -> Jump {
        let (zc, fetches) = self.base(l);
        let (r, sc) = (u32::from(r), R::from_f64(decode_slope(s)));
        let cap = self.cap;
        // zc's own rounding (a few operations on values of at most `zs`) and that of the
        // differences below: relative EPSILON of the terms, with room to spare.
        let zerr = R::from_f32(8.0) * R::EPSILON * (self.zs + zc.abs());
        let num = l.p[2] - zc - l.tol - l.tol - zerr;
        let above = num > R::ZERO; // false for NaN too
        let steps = if !above {
            r
        } else if self.sd_lo >= sc {
            cap.max(r)
        } else {
            let den = (sc - self.sd_lo) * (R::ONE + R::from_f32(4.0) * R::EPSILON);
            let x = num / den * (R::ONE - R::from_f32(4.0) * R::EPSILON);
            // `num > 0` and `den > 0` (`sc > sd_lo`, two distinct values), so
            // `0 ≤ x < cap` when short: truncation is the floor.
            let short = x < R::from_u32(cap); // false for NaN and +∞
            if short {
                (x.to_f64() as u32).max(r)
            } else {
                cap.max(r)
            }
        };
        Jump { steps, fetches }
    }

    /// [`base_height`] in `R` for the texel of the line `l`, from the three samples
    /// around it on the line's centerline (the same operations as [`sigma_of`] and
    /// [`segment_top`], rounded in `R`), and the fetches it makes beyond the line's two
    /// samples: the third, none at the field's border (where `sigma_of` reads two).
    #[inline]
    fn base(&self, l: &Line<R>) -> (R, u32) {
        let (n, ns, ln) = (l.texel, self.ns, self.ln);
        let at = l.m as usize * self.ms + n as usize * ns;
        let s = |k: usize| R::from_f32(self.samples[k]);
        let h = s(at);
        let below = if n > 0 {
            h - s(at - ns)
        } else {
            s(at + ns) - h
        };
        let above = if n + 1 < ln {
            s(at + ns) - h
        } else {
            h - s(at - ns)
        };
        let w = R::from_f64(0.5 + super::SEG_PAD);
        let zc = (h - below * w).max(h).max(h + above * w);
        (zc, u32::from(n > 0 && n + 1 < ln))
    }
}

/// Traces `q` on the triangle surface with the cylinder–cone map `map` (baked for
/// `hf`). Exact, like [`super::trace`], whose march it shares: one fetch per shape read
/// (`[r, s]` of the texel and class) and one for the third sample of a cone's base
/// (see [`base_height`]), two per centerline clearance, four per cell walked. Upward
/// rays use the same data. The step bound of the shared march flags
/// [`Flags::BUDGET_EXHAUSTED`](crate::ray::Flags::BUDGET_EXHAUSTED) (never expected).
pub fn trace<R: Real>(map: &CcMap, hf: &HeightField, q: &Query<R>) -> Trace<R> {
    trace_on(map, hf, MarchSurface::Triangles, q)
}

/// [`trace`] finishing on `surface` (the same map bounds the view-linear surface:
/// see [`MarchSurface`]).
pub fn trace_on<R: Real>(
    map: &CcMap,
    hf: &HeightField,
    surface: MarchSurface,
    q: &Query<R>,
) -> Trace<R> {
    let held = map.rays.holds_over(hf, &map.occluders, q);
    // The per-trace constants, once the ray is known to march.
    march_with(hf, surface, q, |class| {
        let d = q.dir();
        let ax = axis_of(class);
        let dm = d[ax].abs();
        let sd = if dm > R::ZERO { d[2] / dm } else { R::ZERO };
        let sd_err = R::from_f32(2.0) * R::EPSILON * sd.abs();
        let sd_lo = sd - sd_err;
        let (ms, ns) = strides(hf, ax);
        let step = ConeStep {
            cap: u32::from(map.cap),
            sd_lo,
            zs: R::from_f32(hf.min_height().abs().max(hf.max_height().abs())),
            samples: hf.samples(),
            ms,
            ns,
            ln: extents(hf, ax).1,
        };
        // A class the map does not hold, or a ray outside its set: radius 0 without a
        // cone (zero jumps, exact).
        let at = map.rows(class).filter(|_| held);
        // The step reads the bytes' slice directly, not through a reference to the map
        // (copied here, on the rays that march only).
        let data = map.data;
        move |l: &Line<R>, _, i, j| {
            let b = at.map_or(NOT_HELD, |at| texel_bytes(data, at, i, j));
            if b[1] == NO_CONE || u32::from(b[0]) >= step.cap {
                Jump::steps(u32::from(b[0]))
            } else {
                step.cone(l, b)
            }
        }
    })
}
