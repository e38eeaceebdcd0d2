//! The maximum-mipmap march on many rays at once: [`trace_lanes`], sixteen lanes in
//! AVX-512 ([`LANES`]) or eight in AVX2 ([`LANES_AVX2`]).
//!
//! The lanes' walks are held field by field (one array per field, a value per lane),
//! and a step is one pass of vector code over all of them: the node's bounds, its two
//! exit parameters, the texel read, the skip-descend-test decision, leaving the node
//! with the other axis brought up to date (`sync_axis`) and the one-level ascent, every
//! branch of [`March::advance`] a blend. The walks begin in lanes too, `N` queries at a
//! time (the box clip, the first cell and the starting level, without a branch on the
//! ray's direction: on incoherent rays the scalar start's branches were mispredicted),
//! and idle lanes take them from that queue. Only the exact cell test at level 0 and
//! the finish run per lane, on the scalar march's own code. Two sets of
//! lanes step in turn, and each step ends by prefetching its lanes' next texels, and
//! the two corner rows of each lane now at level 0, whose cell test may be next: on
//! incoherent rays those reads miss the cache, and the other set's step hides the wait
//! (random rays over the Himalaya DEM: about 0.75× the time of one set; the corner rows
//! 0.9× more on a needles-like field). Every lane
//! operation is the scalar march's operation on the same values in the same order
//! (the same IEEE divisions, products and sums, no fused forms; `min`, `max` and the
//! comparisons as blends with [`Real`]'s NaN behaviour), so each answer is the scalar
//! answer bit for bit; `core/tests/maxmip.rs` checks it on every march field, surface
//! and ray kind, at both widths.
//!
//! The step is written once, on the lane operations of [`wide::Wide`], and compiled
//! for each width inside a function that enables its instructions.
//!
//! The core cannot ask the CPU what it supports (that needs `std`): the caller proves
//! AVX2, and AVX-512F if it has it, with an [`Avx2`] token, which the std-side crates
//! make after run-time detection. Without one, [`trace_lanes`] is the scalar march,
//! query by query.
//!
//! [`Real`]: crate::math::Real
#![allow(unsafe_code)]
// Elsewhere the lanes are never made: `trace_lanes` is the scalar march.
#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]

use super::{trace, Ascent, March, MaxMip, Options, Walk};
use crate::dda::{entry_on, Entry, Span};
use crate::field::HeightField;
use crate::ray::{Query, Trace};
use crate::simd::Avx2;
use crate::surface::Surface;

#[cfg(target_arch = "x86_64")]
mod wide;

/// Rays one set of lanes marches side by side with AVX-512.
pub const LANES: usize = 16;

/// Rays one set of lanes marches side by side with AVX2 only.
pub const LANES_AVX2: usize = 8;

/// A lane mask's "true" (all bits set), as the masks are stored.
const TRUE: u32 = u32::MAX;

/// [`super::trace`] of every query of `queries` into `out` (same lengths), the answers
/// bit for bit those of [`super::trace`], [`LANES`] rays at a time with `simd` when it
/// knows AVX-512F, [`LANES_AVX2`] with AVX2 only (see the module docs); without it, or
/// for level of detail, [`Ascent::Highest`], the corner-plane surface (which the scalar
/// march hands to the DDA), a pyramid of 2³¹ texels or more or one of more than 16
/// levels (a side of more than 2¹⁵ cells), query by query. A lane that finishes takes
/// the next query, so coherent queries (a pixel tile's, in order) keep the lanes on
/// neighbouring nodes.
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
        && surface != Surface::CornerPlanes
        && i32::try_from(mip.texels.len()).is_ok()
        && mip.layout().levels() as usize <= TABLE_LEVELS;
    let (true, Some(avx2)) = (laned && cfg!(target_arch = "x86_64"), simd) else {
        for (o, q) in out.iter_mut().zip(queries) {
            *o = trace(hf, mip, surface, q, opts);
        }
        return;
    };
    #[cfg(target_arch = "x86_64")]
    {
        let march = March::new(hf, mip, surface, opts);
        let tables = Tables::of(mip);
        // SAFETY: the token proves the CPU executes AVX2, and AVX-512F when it says so.
        unsafe {
            match avx2.avx512() {
                Some(_) => x86::run_avx512(&march, &tables, queries, out),
                None => x86::run_avx2(&march, &tables, queries, out),
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = avx2;
}

/// Sets of lanes [`trace_lanes`] steps in turn.
const SETS: usize = 2;

/// The pyramid's level tables, each level's first texel and width, read by a permutation
/// across a register ([`wide::Wide::itable`]).
struct Tables {
    offset: [u32; TABLE_LEVELS],
    width: [u32; TABLE_LEVELS],
}

/// The levels [`Tables`] holds: what a register of sixteen lanes holds, for a lookup
/// by permutation (a pyramid of more levels, over a side of more than 2¹⁵ cells, is
/// marched query by query).
const TABLE_LEVELS: usize = 16;

impl Tables {
    fn of(mip: &MaxMip) -> Tables {
        let layout = mip.layout();
        let mut t = Tables {
            offset: [0; TABLE_LEVELS],
            width: [0; TABLE_LEVELS],
        };
        for level in 0..layout.levels() {
            // Both fit `i32`: the caller checked that the texel count does.
            t.offset[level as usize] = layout.offset(level) as u32;
            t.width[level as usize] = layout.dims(level)[0];
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

/// A harmless walk, at texel 0 (an idle lane's).
fn idle_walk() -> Walk<f32> {
    let q = Query::from_arrays([0.0; 3], [1.0; 3], 0.0, 1.0).expect("a valid ray");
    let span = Span {
        t0: 0.0,
        t1: 0.0,
        entry: Entry::Start,
    };
    Walk {
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
    }
}

/// Up to `N` walks begun together, from `head` to `n`, waiting for idle lanes, each
/// with its query's position in the caller's slice.
struct Begun<const N: usize> {
    walks: [(usize, Walk<f32>); N],
    head: usize,
    n: usize,
}

/// How a span begins ([`Entry`], as a number the lanes can blend): at the start,
/// through the side of the footprint whose outward normal is `−x`, `+x`, `−y` or `+y`,
/// or through the top.
const ENTRY_START: u32 = 0;
const ENTRY_SIDE: [[u32; 2]; 2] = [[1, 2], [3, 4]];
const ENTRY_TOP: u32 = 5;

fn entry_of(code: u32) -> Entry<f32> {
    let side = |k: usize, out: f32| {
        let mut n = [0.0; 3];
        n[k] = out;
        Entry::Side(n)
    };
    match code {
        1 => side(0, -1.0),
        2 => side(0, 1.0),
        3 => side(1, -1.0),
        4 => side(1, 1.0),
        ENTRY_TOP => Entry::Top,
        _ => Entry::Start,
    }
}

/// `N` walks held field by field; `walk` keeps what only the per-lane code reads (the
/// query and its span). An idle lane (its `busy` bit clear) keeps its last walk, which
/// reads inside the pyramid and is masked out. Masks are stored as `0` or [`TRUE`] per
/// lane.
struct Lanes<const N: usize> {
    /// The lanes marching a query, a bit each.
    busy: u32,
    /// The query each busy lane marches (its position in the caller's slice).
    index: [usize; N],
    walk: [Walk<f32>; N],
    o: [[f32; N]; 3],
    d: [[f32; N]; 3],
    t1: [f32; N],
    /// Per axis, masks: the ray moves along it (`step ≠ 0`), towards `+` (`step > 0`).
    moving: [[u32; N]; 2],
    up: [[u32; N]; 2],
    cell: [[u32; N]; 2],
    level: [u32; N],
    t: [f32; N],
    p: [[f32; N]; 3],
    start: [u32; N],
    on: [[u32; N]; 2],
    fetches: [u32; N],
    clearance: [f32; N],
}

impl<const N: usize> Lanes<N> {
    /// A bit for every lane.
    const ALL: u32 = u32::MAX >> (32 - N);

    /// Every lane idle, on a walk that reads texel 0.
    fn idle() -> Self {
        let walk = idle_walk();
        let mut lanes = Lanes {
            busy: 0,
            index: [0; N],
            walk: [walk; N],
            o: [[0.0; N]; 3],
            d: [[1.0; N]; 3],
            t1: [0.0; N],
            moving: [[TRUE; N]; 2],
            up: [[TRUE; N]; 2],
            cell: [[0; N]; 2],
            level: [0; N],
            t: [0.0; N],
            p: [[0.0; N]; 3],
            start: [TRUE; N],
            on: [[ON_NONE; N]; 2],
            fetches: [0; N],
            clearance: [f32::INFINITY; N],
        };
        for l in 0..N {
            lanes.store(l, &walk);
        }
        lanes
    }

    /// Lane `l` takes query `k`'s walk.
    fn load(&mut self, l: usize, k: usize, w: &Walk<f32>) {
        (self.busy, self.index[l]) = (self.busy | 1 << l, k);
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

    /// Lane `l` goes idle.
    fn end(&mut self, l: usize) {
        self.busy &= !(1 << l);
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::wide::{Wide, Ymm, Zmm};
    use super::*;
    use crate::maxmip::Node;
    use core::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};

    /// [`trace_lanes`]'s march in AVX2's eight lanes.
    #[target_feature(enable = "avx2")]
    pub(super) fn run_avx2(
        march: &March,
        tables: &Tables,
        queries: &[Query<f32>],
        out: &mut [Trace<f32>],
    ) {
        run(Ymm(()), march, tables, queries, out)
    }

    /// [`trace_lanes`]'s march in AVX-512's sixteen lanes.
    #[target_feature(enable = "avx512f")]
    pub(super) fn run_avx512(
        march: &March,
        tables: &Tables,
        queries: &[Query<f32>],
        out: &mut [Trace<f32>],
    ) {
        run(Zmm(()), march, tables, queries, out)
    }

    /// Every query of `queries` marched in [`SETS`] sets of `N` lanes of width `w`, the
    /// answers into `out`.
    #[inline(always)]
    fn run<const N: usize, W: Wide<N>>(
        w: W,
        march: &March,
        tables: &Tables,
        queries: &[Query<f32>],
        out: &mut [Trace<f32>],
    ) {
        // Two sets of lanes stepped in turn: each step asks for its next texels, which
        // arrive while the other set steps.
        let mut sets: [Lanes<N>; SETS] = core::array::from_fn(|_| Lanes::idle());
        let mut begun = Begun {
            walks: [(0, idle_walk()); N],
            head: 0,
            n: 0,
        };
        let mut next = 0;
        loop {
            for lanes in &mut sets {
                // The idle lanes take the next walks, the queries begun `N` at a time.
                let mut idle = !lanes.busy & Lanes::<N>::ALL;
                while idle != 0 {
                    if begun.head < begun.n {
                        let (k, walk) = &begun.walks[begun.head];
                        lanes.load(idle.trailing_zeros() as usize, *k, walk);
                        (begun.head, idle) = (begun.head + 1, idle & (idle - 1));
                    } else if next < queries.len() {
                        next = march.begin_lanes(w, (queries, next), out, &mut begun);
                    } else {
                        break;
                    }
                }
            }
            if sets.iter().all(|lanes| lanes.busy == 0) {
                return;
            }
            for lanes in &mut sets {
                if lanes.busy == 0 {
                    continue;
                }
                let mut ended = |k: usize, trace| out[k] = march.finish(&queries[k], trace);
                march.step_lanes(w, tables, lanes, &mut ended);
            }
        }
    }

    impl March<'_, '_> {
        /// [`March::begin`] of the queries from `next` on, `N` of them (fewer at the
        /// end) in lanes: the box clip, the first cell and the starting level, each the
        /// scalar code's operations on the same values in the same order. The walks go
        /// to `begun` (emptied first), in order; the queries that miss the box get
        /// their answer in `out`. Returns the position after the last query begun.
        #[inline(always)]
        fn begin_lanes<const N: usize, W: Wide<N>>(
            &self,
            w: W,
            (queries, next): (&[Query<f32>], usize),
            out: &mut [Trace<f32>],
            begun: &mut Begun<N>,
        ) -> usize {
            let n = (queries.len() - next).min(N);
            // The lanes past the last query repeat it; their answers are not used.
            let mut q = [[0f32; N]; 8];
            for l in 0..N {
                let query = &queries[next + l.min(n - 1)];
                let (o, d) = (query.origin(), query.dir());
                for k in 0..3 {
                    (q[k][l], q[3 + k][l]) = (o[k], d[k]);
                }
                (q[6][l], q[7][l]) = (query.t_min(), query.t_max());
            }
            let o = [w.fld(&q[0]), w.fld(&q[1]), w.fld(&q[2])];
            let d = [w.fld(&q[3]), w.fld(&q[4]), w.fld(&q[5])];
            let (mut t0, mut t1) = (w.fld(&q[6]), w.fld(&q[7]));
            let (zero, one) = (w.fsplat(0.0), w.fsplat(1.0));
            let (izero, ione) = (w.isplat(0), w.isplat(1));
            let (hf, cells) = (self.hf, self.cells);
            let (zmin, zmax) = (w.fsplat(hf.min_height()), w.fsplat(hf.max_height()));
            // `dda::clip_surface` (any surface but corner planes). A level or rising
            // ray above the box misses.
            let top = w.fdiv(w.fsub(zmax, o[2]), d[2]);
            let (rising, falling) = (w.fgt(d[2], zero), w.flt(d[2], zero));
            let level = w.feq(d[2], zero);
            let above = w.mand(level, w.fgt(o[2], zmax));
            let mut ok = w.mandnot(
                w.ieq(izero, izero),
                w.mor(above, w.mand(rising, w.flt(top, t0))),
            );
            let mut entry = w.isplat(ENTRY_START);
            let mut up = [ok; 2];
            let mut down = [ok; 2];
            for k in 0..2 {
                let lim = w.fsplat(cells[k] as f32);
                (up[k], down[k]) = (w.fgt(d[k], zero), w.flt(d[k], zero));
                let moving = w.mor(up[k], down[k]);
                // A level ray stays in or out of the slab.
                let outside = w.mor(w.flt(o[k], zero), w.fgt(o[k], lim));
                ok = w.mandnot(ok, w.mandnot(outside, moving));
                let (enter, leave) = (w.fpick(up[k], zero, lim), w.fpick(up[k], lim, zero));
                let near = w.fdiv(w.fsub(enter, o[k]), d[k]);
                let far = w.fdiv(w.fsub(leave, o[k]), d[k]);
                let later = w.mand(moving, w.fgt(near, t0));
                t0 = w.fpick(later, near, t0);
                let side = w.ipick(
                    up[k],
                    w.isplat(ENTRY_SIDE[k][0]),
                    w.isplat(ENTRY_SIDE[k][1]),
                );
                entry = w.ipick(later, side, entry);
                t1 = w.fpick(moving, w.rmin(t1, far), t1);
            }
            ok = w.mandnot(ok, w.fgt(t0, t1));
            t1 = w.fpick(rising, w.rmin(t1, top), t1);
            let later = w.mand(falling, w.fgt(top, t0));
            t0 = w.fpick(later, top, t0);
            entry = w.ipick(later, w.isplat(ENTRY_TOP), entry);
            ok = w.mandnot(ok, w.mand(falling, w.fgt(t0, t1)));
            // Well under the lowest sample the ray is inside the solid.
            let margin = w.fadd(one, w.fsub(zmax, zmin));
            let under = w.fdiv(w.fsub(w.fsub(zmin, margin), o[2]), d[2]);
            let solid = w.rmin(w.rmax(under, t0), w.fsplat(f32::MAX));
            t1 = w.fpick(falling, w.rmin(t1, solid), t1);
            let finite = w.mand(
                w.fgt(t0, w.fsplat(f32::NEG_INFINITY)),
                w.flt(t1, w.fsplat(f32::INFINITY)),
            );
            ok = w.mand(ok, w.mand(w.fle(t0, t1), finite));
            // The first cell: a point on a boundary belongs to the cell the ray moves
            // into (`cell_index`).
            let p = [
                w.fadd(o[0], w.fmul(t0, d[0])),
                w.fadd(o[1], w.fmul(t0, d[1])),
                w.fadd(o[2], w.fmul(t0, d[2])),
            ];
            let mut cell = [izero; 2];
            for k in 0..2 {
                let x = w.rmin(w.rmax(p[k], zero), w.fsplat(cells[k] as f32));
                let i = w.ftrunc(x);
                let boundary = w.mand(w.feq(w.ifloat(i), x), w.igt(i, izero));
                let i = w.ipick(w.mand(down[k], boundary), w.isub(i, ione), i);
                cell[k] = w.imin(i, w.isplat(cells[k] - 1));
            }
            // Where nodes are a quarter to an eighth of the ray's horizontal reach:
            // ilog2(reach + 1) − 2, the logarithm from the exponent of the value as
            // `f32`, one less where that rounded up to the next power of two.
            let reach = w.fmul(w.rmax(w.fabs(d[0]), w.fabs(d[1])), w.fsub(t1, t0));
            let v = w.iadd(w.ftrunc(w.rmin(reach, w.fsplat((1u32 << 30) as f32))), ione);
            let e = w.isub(w.ishr(w.fbits(w.ifloat(v)), w.isplat(23)), w.isplat(127));
            let e = w.ipick(w.igt(w.ishl(ione, e), v), w.isub(e, ione), e);
            let start = w.isub(w.imax(e, w.isplat(2)), w.isplat(2));
            let start = w.imin(start, w.isplat(self.top));
            let mut a = [[0u32; N]; 4];
            for (k, v) in [cell[0], cell[1], start, entry].into_iter().enumerate() {
                w.ist(&mut a[k], v);
            }
            let mut f = [[0f32; N]; 5];
            for (k, v) in [t0, t1, p[0], p[1], p[2]].into_iter().enumerate() {
                w.fst(&mut f[k], v);
            }
            let ok = w.mbits(ok);
            let up = [w.mbits(up[0]), w.mbits(up[1])];
            let down = [w.mbits(down[0]), w.mbits(down[1])];
            begun.head = 0;
            begun.n = 0;
            for l in 0..n {
                let (k, query) = (next + l, &queries[next + l]);
                if ok >> l & 1 == 0 {
                    out[k] = self.finish(query, Trace::MISS);
                    continue;
                }
                let step = |k: usize| i64::from(up[k] >> l & 1) - i64::from(down[k] >> l & 1);
                let span = Span {
                    t0: f[0][l],
                    t1: f[1][l],
                    entry: entry_of(a[3][l]),
                };
                begun.walks[begun.n] = (
                    k,
                    Walk {
                        q: *query,
                        step: [step(0), step(1)],
                        lod: None,
                        cell: [a[0][l], a[1][l]],
                        level: a[2][l],
                        t: span.t0,
                        p: [f[2][l], f[3][l], f[4][l]],
                        start: true,
                        on: entry_on(self.surface, &span.entry),
                        span,
                        fetches: 0,
                        clearance: f32::INFINITY,
                    },
                );
                begun.n += 1;
            }
            next + n
        }

        /// One node visit of every busy lane ([`March::advance`] on each, exact options,
        /// one-level ascent); `ended(k, trace)` receives the answer (before the finish)
        /// of each query `k` that ends, and its lane goes idle.
        #[inline(always)]
        fn step_lanes<const N: usize, W: Wide<N>>(
            &self,
            w: W,
            tables: &Tables,
            ln: &mut Lanes<N>,
            ended: &mut impl FnMut(usize, Trace<f32>),
        ) {
            let (zero, one) = (w.isplat(0), w.isplat(1));
            let level = w.ild(&ln.level);
            let cell = [w.ild(&ln.cell[0]), w.ild(&ln.cell[1])];
            let up = [w.mld(&ln.up[0]), w.mld(&ln.up[1])];
            let moving = [w.mld(&ln.moving[0]), w.mld(&ln.moving[1])];
            let o = [w.fld(&ln.o[0]), w.fld(&ln.o[1]), w.fld(&ln.o[2])];
            let d = [w.fld(&ln.d[0]), w.fld(&ln.d[1]), w.fld(&ln.d[2])];
            let (t, t1) = (w.fld(&ln.t), w.fld(&ln.t1));
            // The node of each lane's cell at its level and where the ray leaves it.
            let mut lo = [zero; 2];
            let mut hi = [zero; 2];
            let mut bound = [zero; 2];
            let mut t_out = [w.fsplat(0.0); 2];
            for k in 0..2 {
                lo[k] = w.ishl(w.ishr(cell[k], level), level);
                let cells = w.isplat(self.cells[k]);
                hi[k] = w.imin(w.iadd(lo[k], w.ishl(one, level)), cells);
                bound[k] = w.ipick(up[k], hi[k], lo[k]);
                let tk = w.fdiv(w.fsub(w.ifloat(bound[k]), o[k]), d[k]);
                t_out[k] = w.fpick(moving[k], tk, w.fsplat(f32::INFINITY));
            }
            let t_next = w.rmin(t_out[0], t_out[1]);
            let crossing = w.flt(t_next, t1);
            let tb = w.fpick(crossing, w.rmax(t_next, t), t1);
            // No closures in the lane code: one that is not inlined (one passed to
            // `array::map`, say) runs without the width's instructions.
            let pb = [
                w.fadd(o[0], w.fmul(tb, d[0])),
                w.fadd(o[1], w.fmul(tb, d[1])),
            ];
            let pb = [pb[0], pb[1], w.fadd(o[2], w.fmul(tb, d[2]))];
            let texels = self.mip.texels;
            let at = texel_index(w, tables, texels.len(), level, cell);
            // SAFETY: every index is at most the last texel's.
            let top_z = unsafe { w.fgather(texels.as_ptr(), at) };
            let fetches = w.ild(&ln.fetches);
            w.ist(&mut ln.fetches, w.iadd(fetches, one));
            let low = w.rmin(w.fld(&ln.p[2]), pb[2]);
            let skip = w.fgt(low, top_z);
            let clearance = w.fld(&ln.clearance);
            let skipped = w.rmin(clearance, w.fsub(low, top_z));
            w.fst(&mut ln.clearance, w.fpick(skip, skipped, clearance));
            let above0 = w.igt(level, zero);
            let descend = w.mandnot(above0, skip);
            // Level 0, not skipped: the exact cell test, per lane.
            let test = w.mbits(w.mor(skip, descend));
            if test & ln.busy != ln.busy {
                let mut a = [[0u32; N]; 6];
                let mut fl = [[0f32; N]; 7];
                for (k, v) in [lo[0], lo[1], hi[0], hi[1], bound[0], bound[1]]
                    .into_iter()
                    .enumerate()
                {
                    w.ist(&mut a[k], v);
                }
                for (k, v) in [t_out[0], t_out[1], t_next, tb, pb[0], pb[1], pb[2]]
                    .into_iter()
                    .enumerate()
                {
                    w.fst(&mut fl[k], v);
                }
                let mut due = !test & ln.busy;
                while due != 0 {
                    let l = due.trailing_zeros() as usize;
                    due &= due - 1;
                    let k = ln.index[l];
                    let mut walk = ln.walk(l);
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
                    match self.cell_test(&mut walk, &node) {
                        Some(trace) => {
                            ended(k, trace);
                            ln.end(l);
                        }
                        None => (ln.fetches[l], ln.clearance[l]) = (walk.fetches, walk.clearance),
                    }
                }
            }
            // Leaving the node (`March::leave`).
            let leaving = w.mandnot(w.mfrom(ln.busy), descend);
            let mut ends = w.mandnot(leaving, crossing);
            let parent = w.isub(w.ishl(w.isplat(2), level), one);
            let mut crossed = [w.ieq(zero, one); 2];
            let mut aligned = crossed;
            for k in 0..2 {
                crossed[k] = w.mand(moving[k], w.fle(t_out[k], t_next));
                let edge = w.ipick(up[k], w.isplat(self.cells[k]), zero);
                let at_edge = w.ieq(bound[k], edge);
                ends = w.mor(ends, w.mand(crossed[k], at_edge));
                // The boundary is also the parent's when it is a multiple of 2^(level+1).
                aligned[k] = w.mand(crossed[k], w.ieq(w.iand(bound[k], parent), zero));
            }
            let coarser = w.mor(aligned[0], aligned[1]);
            let ends = w.mand(ends, leaving);
            let moves = w.mandnot(leaving, ends);
            let up_one = w.imin(
                w.ipick(coarser, w.iadd(level, one), level),
                w.isplat(self.top),
            );
            let level = w.ipick(descend, w.isub(level, one), w.ipick(moves, up_one, level));
            w.ist(&mut ln.level, level);
            for k in 0..2 {
                let synced = w.mand(moving[k], above0);
                let active = w.mand(synced, moves);
                let (j, exact) = sync_axis(
                    w,
                    active,
                    (cell[k], up[k]),
                    (lo[k], hi[k]),
                    o[k],
                    d[k],
                    t_next,
                );
                let far = w.ipick(up[k], w.isplat(ON_NEAR), w.isplat(ON_FAR));
                let stepped = w.ipick(up[k], bound[k], w.isub(bound[k], one));
                let kept = w.ipick(synced, j, cell[k]);
                let on_kept = w.ipick(w.mand(synced, exact), far, zero);
                let cell_k = w.ipick(crossed[k], stepped, kept);
                let on_k = w.ipick(crossed[k], far, on_kept);
                w.ist(&mut ln.cell[k], w.ipick(moves, cell_k, cell[k]));
                let on_was = w.ild(&ln.on[k]);
                w.ist(&mut ln.on[k], w.ipick(moves, on_k, on_was));
            }
            for (p, pb) in ln.p.iter_mut().zip(pb) {
                let p_was = w.fld(p);
                w.fst(p, w.fpick(moves, pb, p_was));
            }
            w.fst(&mut ln.t, w.fpick(moves, tb, t));
            let start = w.mld(&ln.start);
            w.mst(&mut ln.start, w.mandnot(start, moves));
            // The next step's texels, asked for now: the other set's step hides the wait.
            let cell = [w.ild(&ln.cell[0]), w.ild(&ln.cell[1])];
            let mut ahead = [0u32; N];
            w.ist(
                &mut ahead,
                texel_index(w, tables, texels.len(), level, cell),
            );
            for at in ahead {
                // SAFETY: `texel_index` is at most the last texel's; a prefetch is
                // SSE, which every x86-64 CPU executes.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(texels.as_ptr().add(at as usize).cast()) };
            }
            // The corners of the lanes now at level 0, whose cell test may be next: its
            // two rows (random rays: about 0.9x the time on the needles-like field).
            let (samples, stride) = (self.hf.samples().as_ptr(), self.hf.stride());
            let mut testing = w.mbits(w.mand(w.mfrom(ln.busy), w.ieq(level, zero)));
            while testing != 0 {
                let l = testing.trailing_zeros() as usize;
                testing &= testing - 1;
                let at = ln.cell[1][l] as usize * stride + ln.cell[0][l] as usize;
                // SAFETY: a prefetch reads nothing and cannot fault; `wrapping_add`
                // keeps the pointer arithmetic defined whatever the lane holds.
                unsafe {
                    _mm_prefetch::<_MM_HINT_T0>(samples.wrapping_add(at).cast());
                    _mm_prefetch::<_MM_HINT_T0>(samples.wrapping_add(at + stride).cast());
                }
            }
            let mut ending = w.mbits(ends);
            while ending != 0 {
                let l = ending.trailing_zeros() as usize;
                ending &= ending - 1;
                ln.end(l);
                ended(ln.index[l], Trace::miss(ln.fetches[l], ln.clearance[l]));
            }
        }
    }

    /// The index of every lane's texel, the node of `cell` at `level`: the level's
    /// offset + row × width + column, at most `len − 1`.
    #[inline(always)]
    fn texel_index<const N: usize, W: Wide<N>>(
        w: W,
        tables: &Tables,
        len: usize,
        level: W::I,
        cell: [W::I; 2],
    ) -> W::I {
        // `table[level]` (a level is below the tables' length: the caller checked).
        let (offset, width) = (
            w.itable(&tables.offset, level),
            w.itable(&tables.width, level),
        );
        let row = w.imul(w.ishr(cell[1], level), width);
        let at = w.iadd(offset, w.iadd(row, w.ishr(cell[0], level)));
        w.imin(at, w.isplat(len as u32 - 1))
    }

    /// Where the ray crosses boundary `b` (`(b − o) / d`).
    #[inline(always)]
    fn crossing<const N: usize, W: Wide<N>>(w: W, b: W::I, o: W::F, d: W::F) -> W::F {
        w.fdiv(w.fsub(w.ifloat(b), o), d)
    }

    /// Where the ray crosses boundaries `j` and `j + 1`.
    #[inline(always)]
    fn across<const N: usize, W: Wide<N>>(w: W, j: W::I, o: W::F, d: W::F) -> [W::F; 2] {
        [
            crossing(w, j, o, d),
            crossing(w, w.iadd(j, w.isplat(1)), o, d),
        ]
    }

    /// The scalar march's `sync_axis` on one axis of every lane at `t`: the cell after
    /// every boundary crossed at or before `t`, from cell `i` inside `[lo, hi)` moving
    /// `up` (a mask) or down, and whether the last boundary crossed lies exactly at
    /// `t`, for the `active` lanes (the others' answers are not used): the estimate,
    /// then the corrections while some active lane needs one.
    #[inline(always)]
    fn sync_axis<const N: usize, W: Wide<N>>(
        w: W,
        active: W::M,
        (i, up): (W::I, W::M),
        (lo, hi): (W::I, W::I),
        o: W::F,
        d: W::F,
        t: W::F,
    ) -> (W::I, W::M) {
        let one = w.isplat(1);
        let lo_x = w.ifloat(lo);
        let hi_x = w.ifloat(w.isub(w.imax(hi, one), one));
        // The estimate, clamped to the node (`clamp_to`: max, then min); x ≥ 0, so
        // truncation is the floor.
        let x = w.fadd(o, w.fmul(t, d));
        let j = w.ftrunc(w.rmin(w.rmax(x, lo_x), hi_x));
        let mut j = w.ipick(up, w.imax(j, i), w.imin(j, i));
        let (minus_one, plus_one) = (w.isplat(u32::MAX), one);
        // Where the ray crosses the lanes' boundaries `j` and `j + 1`, divided again only
        // when a correction moves `j` (the divisions are most of the step's time).
        let mut at = across(w, j, o, d);
        let back_step = w.ipick(up, minus_one, plus_one);
        loop {
            let up_back = w.mand(w.igt(j, i), w.fgt(at[0], t));
            let down_back = w.mand(w.igt(i, j), w.fgt(at[1], t));
            let back = w.mand(active, w.mpick(up, up_back, down_back));
            if !w.many(back) {
                break;
            }
            j = w.ipick(back, w.iadd(j, back_step), j);
            at = across(w, j, o, d);
        }
        let on_step = w.ipick(up, plus_one, minus_one);
        loop {
            let up_on = w.mand(w.igt(hi, w.iadd(j, one)), w.fle(at[1], t));
            let down_on = w.mand(w.igt(j, lo), w.fle(at[0], t));
            let on = w.mand(active, w.mpick(up, up_on, down_on));
            if !w.many(on) {
                break;
            }
            j = w.ipick(on, w.iadd(j, on_step), j);
            at = across(w, j, o, d);
        }
        let last = w.fpick(up, at[0], at[1]);
        let exact = w.mandnot(w.feq(last, t), w.ieq(j, i));
        (j, exact)
    }
}
