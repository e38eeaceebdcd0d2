//! The maximum-mipmap march on [`LANES`] rays at once in AVX2: [`trace_lanes`].
//!
//! The lanes' walks are held field by field (one array of [`LANES`] per field), and a
//! step is one pass of AVX2 code over all eight: the node's bounds, its two exit
//! parameters, the texel read, the skip-descend-test decision, leaving the node with
//! the other axis brought up to date (`sync_axis`) and the one-level ascent, every
//! branch of [`March::advance`] a blend. Only the exact cell test at level 0, the start
//! of a walk and its finish run per lane, on the scalar march's own code. Two sets of
//! lanes step in turn, and each step ends by prefetching its lanes' next texels: on
//! incoherent rays the texel read is a cache miss, and the other set's step hides it
//! (random rays over the Himalaya DEM: about 0.75× the time of one set). Every lane
//! operation is the scalar march's operation on the same values in the same order
//! (the same IEEE divisions, products and sums, no fused forms; `min`, `max` and the
//! comparisons as blends with [`Real`]'s NaN behaviour), so each answer is the scalar
//! answer bit for bit; `core/tests/maxmip.rs` checks it on every march field, surface
//! and ray kind.
//!
//! The core cannot ask the CPU what it supports (that needs `std`): the caller proves
//! AVX2 with an [`Avx2`] token, which the std-side crates make after run-time detection.
//! Without one, [`trace_lanes`] is the scalar march, query by query.
#![allow(unsafe_code)]

use super::{trace, Ascent, March, MaxMip, Node, Options, Walk, MAX_LEVELS};
use crate::dda::{Entry, Span};
use crate::field::HeightField;
use crate::ray::{Query, Trace};
use crate::simd::Avx2;
use crate::surface::Surface;

/// Rays [`trace_lanes`] marches side by side, one per lane.
pub const LANES: usize = 8;

/// One value per lane.
type Lane<T> = [T; LANES];

/// A lane mask's "true" (all bits set), as the blends read it.
const TRUE: u32 = u32::MAX;

/// [`super::trace`] of every query of `queries` into `out` (same lengths), the answers
/// bit for bit those of [`super::trace`], [`LANES`] rays at a time with `simd` (see the
/// module docs); without it, or for level of detail, [`Ascent::Highest`] or a pyramid
/// of 2³¹ texels or more, query by query. A lane that finishes takes the next query,
/// so coherent queries (a pixel tile's, in order) keep the lanes on neighbouring nodes.
///
/// Panics when the lengths differ.
pub fn trace_lanes(
    hf: &HeightField,
    mip: &MaxMip,
    surface: Surface,
    queries: &[Query<f32>],
    opts: &Options,
    out: &mut [Trace<f32>],
    simd: Option<Avx2>,
) {
    assert_eq!(queries.len(), out.len(), "one answer per query");
    let laned = opts.lod.is_none()
        && opts.ascent == Ascent::OneLevel
        && i32::try_from(mip.texels.len()).is_ok();
    let (true, Some(_avx2)) = (laned && cfg!(target_arch = "x86_64"), simd) else {
        for (o, q) in out.iter_mut().zip(queries) {
            *o = trace(hf, mip, surface, q, opts);
        }
        return;
    };
    let march = March::new(hf, mip, surface, opts);
    let tables = Tables::of(mip);
    // Two sets of lanes stepped in turn: each step asks for its next texels, which
    // arrive while the other set steps.
    let mut sets: [Lanes; SETS] = core::array::from_fn(|_| Lanes::idle());
    let mut next = 0;
    loop {
        for lanes in &mut sets {
            for l in 0..LANES {
                // An idle lane takes the next query that needs a march.
                while lanes.index[l].is_none() && next < queries.len() {
                    match march.begin(&queries[next]) {
                        Ok(walk) => lanes.load(l, next, &walk),
                        Err(trace) => out[next] = march.finish(&queries[next], trace),
                    }
                    next += 1;
                }
            }
        }
        let idle = |lanes: &Lanes| lanes.index.iter().all(Option::is_none);
        if sets.iter().all(idle) {
            return;
        }
        for lanes in &mut sets {
            if idle(lanes) {
                continue;
            }
            let mut ended = |k: usize, trace| out[k] = march.finish(&queries[k], trace);
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the token proves the CPU executes AVX2.
            unsafe {
                march.step_lanes(&tables, lanes, &mut ended)
            };
        }
    }
}

/// Sets of lanes [`trace_lanes`] steps in turn.
const SETS: usize = 2;

/// The pyramid's level table in `i32` (the gathers' indices).
struct Tables {
    offset: [i32; MAX_LEVELS],
    width: [i32; MAX_LEVELS],
}

impl Tables {
    fn of(mip: &MaxMip) -> Tables {
        let layout = mip.layout();
        let mut t = Tables {
            offset: [0; MAX_LEVELS],
            width: [0; MAX_LEVELS],
        };
        for level in 0..layout.levels() {
            // Both fit: the caller checked that the texel count does.
            t.offset[level as usize] = layout.offset(level) as i32;
            t.width[level as usize] = layout.dims(level)[0] as i32;
        }
        t
    }
}

/// How a lane's cell was entered on one axis (a [`Walk`]'s `on`, as a number the lanes
/// can blend): through no boundary, the near one, or the far one.
const ON_NONE: u32 = 0;
const ON_NEAR: u32 = 1;
const ON_FAR: u32 = 2;

fn on_code(on: Option<bool>) -> u32 {
    match on {
        None => ON_NONE,
        Some(false) => ON_NEAR,
        Some(true) => ON_FAR,
    }
}

fn on_of(code: u32) -> Option<bool> {
    (code != ON_NONE).then_some(code == ON_FAR)
}

/// [`LANES`] walks held field by field; `walk` keeps what only the per-lane code reads
/// (the query and its span). An idle lane (`index` `None`) holds a harmless walk.
struct Lanes {
    /// The query each lane marches (its position in the caller's slice).
    index: Lane<Option<usize>>,
    walk: Lane<Walk<f32>>,
    o: [Lane<f32>; 3],
    d: [Lane<f32>; 3],
    t1: Lane<f32>,
    /// Per axis, masks: the ray moves along it (`step ≠ 0`), towards `+` (`step > 0`).
    moving: [Lane<u32>; 2],
    up: [Lane<u32>; 2],
    cell: [Lane<u32>; 2],
    level: Lane<u32>,
    t: Lane<f32>,
    p: [Lane<f32>; 3],
    start: Lane<u32>,
    on: [Lane<u32>; 2],
    fetches: Lane<u32>,
    clearance: Lane<f32>,
}

impl Lanes {
    /// Every lane idle, on a walk that reads texel 0.
    fn idle() -> Self {
        let q = Query::from_arrays([0.0; 3], [1.0; 3], 0.0, 1.0).expect("a valid ray");
        let span = Span {
            t0: 0.0,
            t1: 0.0,
            entry: Entry::Start,
        };
        let walk = Walk {
            q,
            span,
            step: [1, 1],
            lod: None,
            cell: [0; 2],
            level: 0,
            t: 0.0,
            p: [0.0; 3],
            start: true,
            on: [None; 2],
            fetches: 0,
            clearance: f32::INFINITY,
        };
        let mut lanes = Lanes {
            index: [None; LANES],
            walk: [walk; LANES],
            o: [[0.0; LANES]; 3],
            d: [[1.0; LANES]; 3],
            t1: [0.0; LANES],
            moving: [[TRUE; LANES]; 2],
            up: [[TRUE; LANES]; 2],
            cell: [[0; LANES]; 2],
            level: [0; LANES],
            t: [0.0; LANES],
            p: [[0.0; LANES]; 3],
            start: [TRUE; LANES],
            on: [[ON_NONE; LANES]; 2],
            fetches: [0; LANES],
            clearance: [f32::INFINITY; LANES],
        };
        for l in 0..LANES {
            lanes.store(l, &walk);
        }
        lanes
    }

    /// Lane `l` takes query `k`'s walk.
    fn load(&mut self, l: usize, k: usize, w: &Walk<f32>) {
        self.index[l] = Some(k);
        self.store(l, w);
    }

    /// Lane `l`'s fields from `w`.
    fn store(&mut self, l: usize, w: &Walk<f32>) {
        self.walk[l] = *w;
        let (o, d) = (w.q.origin(), w.q.dir());
        let mask = |b: bool| if b { TRUE } else { 0 };
        for k in 0..3 {
            (self.o[k][l], self.d[k][l], self.p[k][l]) = (o[k], d[k], w.p[k]);
        }
        for k in 0..2 {
            (self.moving[k][l], self.up[k][l]) = (mask(w.step[k] != 0), mask(w.step[k] > 0));
            (self.cell[k][l], self.on[k][l]) = (w.cell[k], on_code(w.on[k]));
        }
        (self.t1[l], self.level[l], self.t[l]) = (w.span.t1, w.level, w.t);
        (self.start[l], self.fetches[l], self.clearance[l]) =
            (mask(w.start), w.fetches, w.clearance);
    }

    /// Lane `l`'s walk, its laned fields brought up to date.
    fn walk(&self, l: usize) -> Walk<f32> {
        let mut w = self.walk[l];
        w.cell = [self.cell[0][l], self.cell[1][l]];
        w.on = [on_of(self.on[0][l]), on_of(self.on[1][l])];
        w.p = [self.p[0][l], self.p[1][l], self.p[2][l]];
        (w.level, w.t, w.start) = (self.level[l], self.t[l], self.start[l] != 0);
        (w.fetches, w.clearance) = (self.fetches[l], self.clearance[l]);
        w
    }

    /// The lanes marching a query, as a mask.
    fn busy(&self) -> Lane<u32> {
        core::array::from_fn(|l| if self.index[l].is_some() { TRUE } else { 0 })
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::*;
    use core::arch::x86_64::*;

    // Loads and stores of whole lane arrays. SAFETY (every use): an array of eight
    // 4-byte values is exactly one unaligned 256-bit load or store.
    macro_rules! ld {
        (f, $a:expr) => {
            unsafe { _mm256_loadu_ps($a.as_ptr()) }
        };
        (i, $a:expr) => {
            unsafe { _mm256_loadu_si256($a.as_ptr() as *const __m256i) }
        };
    }
    macro_rules! st {
        (f, $a:expr, $v:expr) => {
            unsafe { _mm256_storeu_ps($a.as_mut_ptr(), $v) }
        };
        (i, $a:expr, $v:expr) => {
            unsafe { _mm256_storeu_si256($a.as_mut_ptr() as *mut __m256i, $v) }
        };
    }
    // `if m { a } else { b }` per lane, for floats and for integers.
    macro_rules! pick_f {
        ($m:expr, $a:expr, $b:expr) => {
            _mm256_blendv_ps($b, $a, _mm256_castsi256_ps($m))
        };
    }
    macro_rules! pick_i {
        ($m:expr, $a:expr, $b:expr) => {
            _mm256_blendv_epi8($b, $a, $m)
        };
    }
    // Comparisons as masks, false on NaN as Rust's.
    macro_rules! cmp {
        ($a:expr, $op:ident, $b:expr) => {
            _mm256_castps_si256(_mm256_cmp_ps::<$op>($a, $b))
        };
    }
    // `Real::min(a, b)` (`b < a ? b : a`) and `Real::max(a, b)` (`b > a ? b : a`).
    macro_rules! rmin {
        ($a:expr, $b:expr) => {{
            let (a, b) = ($a, $b);
            pick_f!(cmp!(b, _CMP_LT_OQ, a), b, a)
        }};
    }
    macro_rules! rmax {
        ($a:expr, $b:expr) => {{
            let (a, b) = ($a, $b);
            pick_f!(cmp!(b, _CMP_GT_OQ, a), b, a)
        }};
    }

    impl March<'_, '_> {
        /// One node visit of every busy lane ([`March::advance`] on each, exact options,
        /// one-level ascent); `ended(k, trace)` receives the answer (before the finish)
        /// of each query `k` that ends, and its lane goes idle.
        #[target_feature(enable = "avx2")]
        pub(super) fn step_lanes(
            &self,
            tables: &Tables,
            ln: &mut Lanes,
            ended: &mut impl FnMut(usize, Trace<f32>),
        ) {
            let zero = _mm256_setzero_si256();
            let one = _mm256_set1_epi32(1);
            let level = ld!(i, ln.level);
            let cell = [ld!(i, ln.cell[0]), ld!(i, ln.cell[1])];
            let up = [ld!(i, ln.up[0]), ld!(i, ln.up[1])];
            let moving = [ld!(i, ln.moving[0]), ld!(i, ln.moving[1])];
            let o = [ld!(f, ln.o[0]), ld!(f, ln.o[1]), ld!(f, ln.o[2])];
            let d = [ld!(f, ln.d[0]), ld!(f, ln.d[1]), ld!(f, ln.d[2])];
            let (t, t1) = (ld!(f, ln.t), ld!(f, ln.t1));
            // The node of each lane's cell at its level and where the ray leaves it.
            let mut lo = [zero; 2];
            let mut hi = [zero; 2];
            let mut bound = [zero; 2];
            let mut t_out = [_mm256_setzero_ps(); 2];
            for k in 0..2 {
                lo[k] = _mm256_sllv_epi32(_mm256_srlv_epi32(cell[k], level), level);
                let cells = _mm256_set1_epi32(self.cells[k] as i32);
                hi[k] = _mm256_min_epu32(
                    _mm256_add_epi32(lo[k], _mm256_sllv_epi32(one, level)),
                    cells,
                );
                bound[k] = pick_i!(up[k], hi[k], lo[k]);
                let tk = _mm256_div_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(bound[k]), o[k]), d[k]);
                t_out[k] = pick_f!(moving[k], tk, _mm256_set1_ps(f32::INFINITY));
            }
            let t_next = rmin!(t_out[0], t_out[1]);
            let crossing = cmp!(t_next, _CMP_LT_OQ, t1);
            let tb = pick_f!(crossing, rmax!(t_next, t), t1);
            let pb = [0, 1, 2].map(|k| _mm256_add_ps(o[k], _mm256_mul_ps(tb, d[k])));
            let texels = self.mip.texels;
            let at = texel_index(tables, texels.len(), level, cell);
            // SAFETY: every index is at most the last texel's.
            let top_z = unsafe { _mm256_i32gather_ps::<4>(texels.as_ptr(), at) };
            let fetches = ld!(i, ln.fetches);
            st!(i, ln.fetches, _mm256_add_epi32(fetches, one));
            let low = rmin!(ld!(f, ln.p[2]), pb[2]);
            let skip = cmp!(low, _CMP_GT_OQ, top_z);
            let clearance = ld!(f, ln.clearance);
            let skipped = rmin!(clearance, _mm256_sub_ps(low, top_z));
            st!(f, ln.clearance, pick_f!(skip, skipped, clearance));
            let above0 = _mm256_cmpgt_epi32(level, zero);
            let descend = _mm256_andnot_si256(skip, above0);
            // Level 0, not skipped: the exact cell test, per lane.
            let test = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_or_si256(skip, descend)));
            if test != 0xff {
                let mut a = [[0u32; LANES]; 6];
                let mut fl = [[0f32; LANES]; 7];
                for (k, v) in [lo[0], lo[1], hi[0], hi[1], bound[0], bound[1]]
                    .into_iter()
                    .enumerate()
                {
                    st!(i, a[k], v);
                }
                for (k, v) in [t_out[0], t_out[1], t_next, tb, pb[0], pb[1], pb[2]]
                    .into_iter()
                    .enumerate()
                {
                    st!(f, fl[k], v);
                }
                let mut due = !test & 0xff;
                while due != 0 {
                    let l = due.trailing_zeros() as usize;
                    due &= due - 1;
                    let Some(k) = ln.index[l] else { continue };
                    let mut w = ln.walk(l);
                    let node = Node {
                        lo: [a[0][l], a[1][l]],
                        hi: [a[2][l], a[3][l]],
                        bound: [a[4][l], a[5][l]],
                        t_out: [fl[0][l], fl[1][l]],
                        t_next: fl[2][l],
                        crossing: fl[2][l] < ln.t1[l],
                        tb: fl[3][l],
                        pb: [fl[4][l], fl[5][l], fl[6][l]],
                    };
                    match self.cell_test(&mut w, &node) {
                        Some(trace) => {
                            ended(k, trace);
                            ln.index[l] = None;
                        }
                        None => (ln.fetches[l], ln.clearance[l]) = (w.fetches, w.clearance),
                    }
                }
            }
            // Leaving the node (`March::leave`).
            let busy = ld!(i, ln.busy());
            let leaving = _mm256_andnot_si256(descend, busy);
            let mut ends = _mm256_andnot_si256(crossing, leaving);
            let mut coarser = zero;
            let parent = _mm256_sub_epi32(_mm256_sllv_epi32(_mm256_set1_epi32(2), level), one);
            let mut crossed = [zero; 2];
            for k in 0..2 {
                crossed[k] = _mm256_and_si256(moving[k], cmp!(t_out[k], _CMP_LE_OQ, t_next));
                let edge = pick_i!(up[k], _mm256_set1_epi32(self.cells[k] as i32), zero);
                let at_edge = _mm256_cmpeq_epi32(bound[k], edge);
                ends = _mm256_or_si256(ends, _mm256_and_si256(crossed[k], at_edge));
                // The boundary is also the parent's when it is a multiple of 2^(level+1).
                let aligned = _mm256_cmpeq_epi32(_mm256_and_si256(bound[k], parent), zero);
                coarser = _mm256_or_si256(coarser, _mm256_and_si256(crossed[k], aligned));
            }
            ends = _mm256_and_si256(ends, leaving);
            let moves = _mm256_andnot_si256(ends, leaving);
            let top = _mm256_set1_epi32(self.top as i32);
            let up_one =
                _mm256_min_epu32(pick_i!(coarser, _mm256_add_epi32(level, one), level), top);
            let level = pick_i!(
                descend,
                _mm256_sub_epi32(level, one),
                pick_i!(moves, up_one, level)
            );
            st!(i, ln.level, level);
            for k in 0..2 {
                let synced = _mm256_and_si256(moving[k], above0);
                let active = _mm256_and_si256(synced, moves);
                let (j, exact) =
                    sync_axis(active, cell[k], up[k], lo[k], hi[k], o[k], d[k], t_next);
                let far = pick_i!(
                    up[k],
                    _mm256_set1_epi32(ON_NEAR as i32),
                    _mm256_set1_epi32(ON_FAR as i32)
                );
                let stepped = pick_i!(up[k], bound[k], _mm256_sub_epi32(bound[k], one));
                let kept = pick_i!(synced, j, cell[k]);
                let on_kept = _mm256_and_si256(_mm256_and_si256(synced, exact), far);
                let cell_k = pick_i!(crossed[k], stepped, kept);
                let on_k = pick_i!(crossed[k], far, on_kept);
                st!(i, ln.cell[k], pick_i!(moves, cell_k, cell[k]));
                let on_was = ld!(i, ln.on[k]);
                st!(i, ln.on[k], pick_i!(moves, on_k, on_was));
            }
            for (p, pb) in ln.p.iter_mut().zip(pb) {
                let p_was = ld!(f, p);
                st!(f, p, pick_f!(moves, pb, p_was));
            }
            st!(f, ln.t, pick_f!(moves, tb, t));
            let start = ld!(i, ln.start);
            st!(i, ln.start, _mm256_andnot_si256(moves, start));
            // The next step's texels, asked for now: the other set's step hides the wait.
            let cell = [ld!(i, ln.cell[0]), ld!(i, ln.cell[1])];
            let mut ahead = [0u32; LANES];
            st!(i, ahead, texel_index(tables, texels.len(), level, cell));
            for at in ahead {
                // SAFETY: `texel_index` is at most the last texel's.
                _mm_prefetch::<_MM_HINT_T0>(unsafe { texels.as_ptr().add(at as usize) }.cast());
            }
            let mut ending = _mm256_movemask_ps(_mm256_castsi256_ps(ends));
            while ending != 0 {
                let l = ending.trailing_zeros() as usize;
                ending &= ending - 1;
                let k = ln.index[l].take().unwrap_or_default();
                ended(k, Trace::miss(ln.fetches[l], ln.clearance[l]));
            }
        }
    }

    /// The index of every lane's texel, the node of `cell` at `level`: the level's
    /// offset + row × width + column, at most `len − 1`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn texel_index(tables: &Tables, len: usize, level: __m256i, cell: [__m256i; 2]) -> __m256i {
        let offset = gather_i(&tables.offset, level);
        let width = gather_i(&tables.width, level);
        let row = _mm256_mullo_epi32(_mm256_srlv_epi32(cell[1], level), width);
        let at = _mm256_add_epi32(
            offset,
            _mm256_add_epi32(row, _mm256_srlv_epi32(cell[0], level)),
        );
        _mm256_min_epu32(at, _mm256_set1_epi32(len as i32 - 1))
    }

    /// `table[level]` per lane (`level` below [`MAX_LEVELS`]; clamped to it).
    #[target_feature(enable = "avx2")]
    fn gather_i(table: &[i32; MAX_LEVELS], level: __m256i) -> __m256i {
        let level = _mm256_min_epu32(level, _mm256_set1_epi32(MAX_LEVELS as i32 - 1));
        // SAFETY: every index is below the table's length.
        unsafe { _mm256_i32gather_epi32::<4>(table.as_ptr(), level) }
    }

    /// The scalar march's `sync_axis` on one axis of every lane at `t`: the cell after
    /// every boundary crossed at or before `t`, from cell `i` inside `[lo, hi)`, and
    /// whether the last boundary crossed lies exactly at `t`, for the `active` lanes
    /// (the others' answers are not used): the estimate, then the corrections while
    /// some active lane needs one.
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    fn sync_axis(
        active: __m256i,
        i: __m256i,
        up: __m256i,
        lo: __m256i,
        hi: __m256i,
        o: __m256,
        d: __m256,
        t: __m256,
    ) -> (__m256i, __m256i) {
        let one = _mm256_set1_epi32(1);
        let at = |b: __m256i| _mm256_div_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(b), o), d);
        let lo_x = _mm256_cvtepi32_ps(lo);
        let hi_x = _mm256_cvtepi32_ps(_mm256_sub_epi32(_mm256_max_epu32(hi, one), one));
        // The estimate, clamped to the node (`clamp_to`: max, then min); x ≥ 0, so
        // truncation is the floor.
        let x = _mm256_add_ps(o, _mm256_mul_ps(t, d));
        let j = _mm256_cvttps_epi32(rmin!(rmax!(x, lo_x), hi_x));
        let mut j = pick_i!(up, _mm256_max_epu32(j, i), _mm256_min_epu32(j, i));
        let back_step = pick_i!(up, _mm256_set1_epi32(-1), one);
        loop {
            let up_back = _mm256_and_si256(_mm256_cmpgt_epi32(j, i), cmp!(at(j), _CMP_GT_OQ, t));
            let next = _mm256_add_epi32(j, one);
            let down_back =
                _mm256_and_si256(_mm256_cmpgt_epi32(i, j), cmp!(at(next), _CMP_GT_OQ, t));
            let back = _mm256_and_si256(active, pick_i!(up, up_back, down_back));
            if _mm256_testz_si256(back, back) != 0 {
                break;
            }
            j = _mm256_add_epi32(j, _mm256_and_si256(back, back_step));
        }
        let zero = _mm256_setzero_si256();
        let on_step = _mm256_sub_epi32(zero, back_step);
        loop {
            let next = _mm256_add_epi32(j, one);
            let up_on =
                _mm256_and_si256(_mm256_cmpgt_epi32(hi, next), cmp!(at(next), _CMP_LE_OQ, t));
            let down_on = _mm256_and_si256(_mm256_cmpgt_epi32(j, lo), cmp!(at(j), _CMP_LE_OQ, t));
            let on = _mm256_and_si256(active, pick_i!(up, up_on, down_on));
            if _mm256_testz_si256(on, on) != 0 {
                break;
            }
            j = _mm256_add_epi32(j, _mm256_and_si256(on, on_step));
        }
        let moved = _mm256_andnot_si256(_mm256_cmpeq_epi32(j, i), _mm256_set1_epi32(-1));
        let last = pick_f!(up, at(j), at(_mm256_add_epi32(j, one)));
        let exact = _mm256_and_si256(moved, cmp!(last, _CMP_EQ_OQ, t));
        (j, exact)
    }
}
