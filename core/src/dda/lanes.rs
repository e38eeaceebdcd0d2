//! The skipping DDA ([`super::trace_skipping_for`]) on [`LANES`] rays at once in
//! AVX-512: [`trace_skipping_lanes`].
//!
//! Sixteen queries at a time begin in lanes (the scalar `first_cell`: the box clip, the
//! start's cell, its corners and clearance); those with a walk are packed into a queue
//! ([`Begun`]), and idle lanes take them from it. A lane holds its walk field by field
//! (one array of [`LANES`] per field, one bit per lane for each flag), and a step is
//! one pass of AVX-512 code over all sixteen walks: the next crossing, the exit point,
//! the bound test that skips a cell the ray passes above, the clearances at the entry
//! and the exit (each edge's two samples at a crossing, the triangle surface's planes
//! elsewhere), the step to the next cell and the gather of its corners, every branch of
//! the scalar walk a blend. A lane leaves the lanes once, when its ray ends: a miss, a
//! budget spent ([`Restart`]), or the cell whose exit lies on or under the surface.
//! Those cells wait in [`Contacts`] until sixteen have come, then get their contact
//! test, hit point and robust finish together, the finish's Newton steps in `f64` eight
//! lanes at a time. Rays that begin under the surface get their hit in the begin pass
//! when they enter through a side of the box, else (rare) from the scalar walk.
//!
//! Each lane operation is the scalar code's on the same values in the same order (the
//! same IEEE divisions, square roots, products and sums, no fused forms; `min`, `max`
//! and the comparisons as blends with [`crate::math::Real`]'s NaN behaviour), so every
//! answer is the scalar answer bit for bit; `core/tests/horizon.rs` checks it on every
//! march field, camera and ray kind.
//!
//! Only the triangle surface has lanes (the surface of the coherent batches and of the
//! Embree comparison): on the others every segment that reaches the surface, not only
//! the last, needs its contact test. Without an [`Avx512`] token, on another surface,
//! or on a field of 2³¹ samples or more, [`trace_skipping_lanes`] is the scalar walk,
//! query by query. AVX2 lanes of eight were measured first: their step (about 500
//! instructions, a third of them spills of AVX2's sixteen registers) cost as much per
//! cell as the scalar walk's, and the hit's scalar tail stayed.
#![allow(unsafe_code)]

use super::{trace_skipping_for, Restart};
use crate::field::HeightField;
use crate::ray::{Query, Trace};
use crate::simd::Avx512;
use crate::surface::Surface;

/// Rays [`trace_skipping_lanes`] walks side by side, one per lane.
pub const LANES: usize = 16;

/// One value per lane.
type Lane<T> = [T; LANES];

/// Idle lanes that make the lanes take new walks: a refill (two dozen expanding loads)
/// costs about as much as a step, so it waits for half the lanes (measured on the
/// filled 45° frame: 91–93 ns a ray against 98–103 refilling every idle lane at once).
const REFILL: u32 = 8;

/// What [`super::trace_skipping_for`] answers: the trace, or where a march may go on.
pub type Walked = Result<Trace<f32>, Restart<f32>>;

/// [`super::trace_skipping_for`] of every query of `queries` for at most `budget`
/// cells into `out` (same lengths), each answer that of the scalar walk bit for bit,
/// [`LANES`] rays at a time with `simd` on the triangle surface (see the module docs);
/// otherwise query by query. A lane whose ray ends takes the next query, so coherent
/// queries (a pixel tile's, in order) keep the lanes on neighbouring cells.
///
/// Panics when the lengths differ.
pub fn trace_skipping_lanes(
    hf: &HeightField,
    surface: Surface,
    queries: &[Query<f32>],
    budget: u32,
    out: &mut [Walked],
    simd: Option<Avx512>,
) {
    assert_eq!(queries.len(), out.len(), "one answer per query");
    let laned = surface == Surface::Triangles && i32::try_from(hf.samples().len()).is_ok();
    let (true, Some(_avx512)) = (laned && cfg!(target_arch = "x86_64"), simd) else {
        for (o, q) in out.iter_mut().zip(queries) {
            *o = trace_skipping_for(hf, surface, q, budget);
        }
        return;
    };
    if u32::try_from(queries.len()).is_err() {
        return trace_skipping_lanes(hf, surface, queries, budget, out, None);
    }
    #[cfg(target_arch = "x86_64")]
    // SAFETY: the token proves the CPU executes AVX-512F.
    unsafe {
        avx512::walk_all(hf, queries, budget, out);
    }
}

/// [`LANES`] walks held field by field (a [`super::walk`]'s state, per axis `[x, y]`;
/// each flag a mask, one bit per lane). An idle lane holds a harmless walk.
struct Lanes {
    /// The lanes walking a query.
    busy: u16,
    /// The query each lane walks (its position in the caller's slice).
    index: Lane<u32>,
    o: [Lane<f32>; 3],
    d: [Lane<f32>; 3],
    /// The end of the span.
    t1: Lane<f32>,
    cell: [Lane<u32>; 2],
    /// The cell's corners.
    c: [Lane<f32>; 4],
    /// The next crossing along each axis.
    t_cross: [Lane<f32>; 2],
    /// Where the ray entered the cell: `t` and point, and its local point and
    /// clearance (the last cell's exit, seen from this one).
    ta: Lane<f32>,
    pa: [Lane<f32>; 3],
    a: [Lane<f32>; 3],
    ca: Lane<f32>,
    fetches: Lane<u32>,
    clearance: Lane<f32>,
}

impl Lanes {
    /// Every lane idle.
    fn idle() -> Self {
        Lanes {
            busy: 0,
            index: [0; LANES],
            o: [[0.0; LANES]; 3],
            d: [[1.0; LANES]; 3],
            t1: [0.0; LANES],
            cell: [[0; LANES]; 2],
            c: [[0.0; LANES]; 4],
            t_cross: [[1.0; LANES]; 2],
            ta: [0.0; LANES],
            pa: [[0.0; LANES]; 3],
            a: [[0.0; LANES]; 3],
            ca: [1.0; LANES],
            fetches: [0; LANES],
            clearance: [f32::INFINITY; LANES],
        }
    }
}

/// The first cells of up to [`LANES`] walks ([`super::first_cell`]'s state) waiting
/// for idle lanes, from `head` to `n`, field by field as [`Lanes`] holds them.
struct Begun {
    n: usize,
    head: usize,
    index: Lane<u32>,
    o: [Lane<f32>; 3],
    d: [Lane<f32>; 3],
    t1: Lane<f32>,
    cell: [Lane<u32>; 2],
    c: [Lane<f32>; 4],
    t_cross: [Lane<f32>; 2],
    t0: Lane<f32>,
    p0: [Lane<f32>; 3],
    a: [Lane<f32>; 3],
    ca: Lane<f32>,
}

impl Begun {
    /// None waiting.
    fn new() -> Self {
        Begun {
            n: 0,
            head: 0,
            index: [0; LANES],
            o: [[0.0; LANES]; 3],
            d: [[1.0; LANES]; 3],
            t1: [0.0; LANES],
            cell: [[0; LANES]; 2],
            c: [[0.0; LANES]; 4],
            t_cross: [[1.0; LANES]; 2],
            t0: [0.0; LANES],
            p0: [[0.0; LANES]; 3],
            a: [[0.0; LANES]; 3],
            ca: [1.0; LANES],
        }
    }
}

/// Also the horizon's aims' reading of their rays.
#[cfg(all(target_arch = "x86_64", feature = "alloc"))]
pub(crate) use avx512::queries_by_field;

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::*;
    use core::arch::x86_64::*;

    /// [`trace_skipping_lanes`]'s walks of `queries` in lanes: one function with the
    /// lanes' feature, whose loop the steps, begins, refills and finishes inline into.
    /// In the lanes' code, closures that the compiler did not inline (a call per use,
    /// arguments through memory) are loops, macros and functions of the feature
    /// instead: measured together, 0.94–0.99× the time of the camera frames.
    #[target_feature(enable = "avx512f")]
    pub(super) fn walk_all(
        hf: &HeightField,
        queries: &[Query<f32>],
        budget: u32,
        out: &mut [Walked],
    ) {
        let (mut lanes, mut begun, mut contacts) = (Lanes::idle(), Begun::new(), Contacts::new());
        let mut next = 0;
        loop {
            // Once half the lanes are idle they take the next walks, begun sixteen
            // queries at a time.
            while lanes.busy.count_zeros() >= REFILL
                && (begun.head < begun.n || next < queries.len())
            {
                if begun.head == begun.n {
                    next += begin(hf, (queries, next), budget, out, &mut begun);
                }
                refill(&mut lanes, &mut begun);
            }
            if contacts.n >= LANES || lanes.busy == 0 {
                finish_contacts(&mut contacts, out);
            }
            if lanes.busy == 0 {
                return;
            }
            step(hf, budget, &mut lanes, queries, (out, &mut contacts));
        }
    }

    // Loads and stores of whole lane arrays. SAFETY (every use): an array of sixteen
    // 4-byte values is exactly one unaligned 512-bit load or store.
    macro_rules! ld {
        (f, $a:expr) => {
            unsafe { _mm512_loadu_ps($a.as_ptr()) }
        };
        (i, $a:expr) => {
            unsafe { _mm512_loadu_si512($a.as_ptr() as *const __m512i) }
        };
    }
    macro_rules! st {
        (f, $a:expr, $v:expr) => {
            unsafe { _mm512_storeu_ps($a.as_mut_ptr(), $v) }
        };
        (i, $a:expr, $v:expr) => {
            unsafe { _mm512_storeu_si512($a.as_mut_ptr() as *mut __m512i, $v) }
        };
    }

    /// `if m { a } else { b }` per lane.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn pick(m: __mmask16, a: __m512, b: __m512) -> __m512 {
        _mm512_mask_blend_ps(m, b, a)
    }

    /// `if m { a } else { b }` per lane, on integers.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn pick_i(m: __mmask16, a: __m512i, b: __m512i) -> __m512i {
        _mm512_mask_blend_epi32(m, b, a)
    }

    /// `Real::min(a, b)`: `b < a ? b : a` (false on NaN, as Rust's comparisons).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn rmin(a: __m512, b: __m512) -> __m512 {
        pick(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(b, a), b, a)
    }

    /// `Real::max(a, b)`: `b > a ? b : a`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn rmax(a: __m512, b: __m512) -> __m512 {
        pick(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(b, a), b, a)
    }

    /// One cell of every busy lane's walk ([`super::super::walk`]'s loop body, with
    /// `SKIP`, on the triangle surface); the answer of each query that ends goes to
    /// `out`, and its lane goes idle.
    #[target_feature(enable = "avx512f")]
    fn step(
        hf: &HeightField,
        budget: u32,
        ln: &mut Lanes,
        queries: &[Query<f32>],
        (out, cs): (&mut [Walked], &mut Contacts),
    ) {
        let (zero, one) = (_mm512_setzero_ps(), _mm512_set1_ps(1.0));
        let one_i = _mm512_set1_epi32(1);
        let o = [ld!(f, ln.o[0]), ld!(f, ln.o[1]), ld!(f, ln.o[2])];
        let d = [ld!(f, ln.d[0]), ld!(f, ln.d[1]), ld!(f, ln.d[2])];
        let (up, moving) = (d.map(|d| positive(d)), d.map(|d| !level(d)));
        let cell = [ld!(i, ln.cell[0]), ld!(i, ln.cell[1])];
        let c = [0, 1, 2, 3].map(|k| ld!(f, ln.c[k]));
        let t_cross = [ld!(f, ln.t_cross[0]), ld!(f, ln.t_cross[1])];
        let (ta, t1) = (ld!(f, ln.ta), ld!(f, ln.t1));
        let pa = [ld!(f, ln.pa[0]), ld!(f, ln.pa[1]), ld!(f, ln.pa[2])];
        let fetches = ld!(i, ln.fetches);
        let clearance = ld!(f, ln.clearance);
        // The exit: the next crossing, or the span's end.
        let t_next = rmin(t_cross[0], t_cross[1]);
        let crossing = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(t_next, t1);
        let tb = pick(crossing, rmax(t_next, ta), t1);
        let cross = t_cross.map(|t| crossing & _mm512_cmp_ps_mask::<_CMP_LE_OQ>(t, t_next));
        let pb = [0, 1, 2].map(|k| _mm512_add_ps(o[k], _mm512_mul_ps(tb, d[k])));
        // The bound test (`passes_above` on triangles): above the highest corner by 16
        // ulps of the larger magnitude.
        let low = rmin(pa[2], pb[2]);
        let top = rmax(rmax(c[0], c[1]), rmax(c[2], c[3]));
        let above = _mm512_sub_ps(low, top);
        let margin = _mm512_mul_ps(
            _mm512_mul_ps(
                _mm512_add_ps(_mm512_abs_ps(top), _mm512_abs_ps(low)),
                _mm512_set1_ps(16.0),
            ),
            _mm512_set1_ps(f32::EPSILON),
        );
        let skip = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(above, margin);
        let most = _mm512_set1_epi32(budget.min(i32::MAX as u32) as i32);
        let spent = _mm512_cmpgt_epi32_mask(_mm512_srli_epi32::<2>(fetches), most);
        // The test of a cell not passed above: the entry's clearance (carried from the
        // last cell's exit, which every step computes: the scalar walk's fresh entry
        // after a skipped cell reads the same samples in the same order) and the exit's.
        let a = [0, 1, 2].map(|k| ld!(f, ln.a[k]));
        let ca = ld!(f, ln.ca);
        let (b, cb) = local_clearance(c, cell, pb, (cross, [cross[0] & up[0], cross[1] & up[1]]));
        let clear = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(cb, zero);
        let tested = rmin(clearance, rmin(ca, cb));
        let clearance_now = pick(skip, rmin(clearance, above), tested);
        // The next cell along each axis crossed, and whether the walk leaves the field.
        let cells = [hf.width() - 1, hf.height() - 1];
        let mut left = !(cross[0] | cross[1]);
        let mut cell_next = cell;
        let mut t_cross_next = t_cross;
        for k in 0..2 {
            let stepped = pick_i(
                up[k],
                _mm512_add_epi32(cell[k], one_i),
                _mm512_sub_epi32(cell[k], one_i),
            );
            // Past the last cell (moving up), or before the first (down from 0).
            let last = _mm512_set1_epi32(cells[k] as i32 - 1);
            let edge = pick_i(up[k], last, _mm512_setzero_si512());
            left |= cross[k] & _mm512_cmpeq_epi32_mask(cell[k], edge);
            cell_next[k] = pick_i(cross[k], stepped, cell[k]);
            let t = next_crossing(cell_next[k], (up[k], moving[k]), o[k], d[k]);
            t_cross_next[k] = pick(cross[k], t, t_cross[k]);
        }
        // The ends: a hit, a budget spent, or the walk leaving the span or the field.
        let busy = ln.busy;
        let hit = !(skip | clear) & busy;
        let restart = skip & spent & busy;
        let missed = left & busy & !(hit | restart);
        let ending = hit | restart | missed;
        if ending != 0 {
            let mut v = [[0f32; LANES]; 12];
            for (k, x) in [
                a[0],
                a[1],
                a[2],
                b[0],
                b[1],
                b[2],
                ca,
                cb,
                tb,
                ta,
                clearance,
                clearance_now,
            ]
            .into_iter()
            .enumerate()
            {
                st!(f, v[k], x);
            }
            let mut left = ending;
            while left != 0 {
                let l = left.trailing_zeros() as usize;
                left &= left - 1;
                let k = ln.index[l] as usize;
                let bit = 1 << l;
                if hit & bit != 0 {
                    // The contact test and the finish wait for more hits.
                    let (q, n) = (&queries[k], cs.n);
                    let (o, d) = (q.origin(), q.dir());
                    cs.index[n] = k;
                    for i in 0..3 {
                        (cs.a[i][n], cs.b[i][n]) = (v[i][l], v[3 + i][l]);
                        (cs.o[i][n], cs.d[i][n]) = (o[i], d[i]);
                    }
                    for i in 0..4 {
                        cs.c[i][n] = ln.c[i][l];
                    }
                    (cs.cell[0][n], cs.cell[1][n]) = (ln.cell[0][l], ln.cell[1][l]);
                    (cs.t[0][n], cs.t[1][n]) = (v[9][l], v[8][l]);
                    (cs.range[0][n], cs.range[1][n]) = (q.t_min(), q.t_max());
                    (cs.ca[n], cs.clearance[n]) = (v[6][l], v[10][l]);
                    cs.fetches[n] = ln.fetches[l];
                    cs.n += 1;
                    continue;
                }
                out[k] = if restart & bit != 0 {
                    let trace = Trace::miss(ln.fetches[l], v[10][l]);
                    Err(Restart { t: v[9][l], trace })
                } else {
                    Ok(Trace::miss(ln.fetches[l], v[11][l]))
                };
            }
            ln.busy &= !ending;
        }
        // On to the next cell: its corners (a lane that left the field reads its last
        // row or column; it is idle), and the exit becomes the entry.
        let corners = corners(hf, cell_next);
        for (k, corner) in corners.into_iter().enumerate() {
            st!(f, ln.c[k], corner);
        }
        for k in 0..2 {
            st!(i, ln.cell[k], cell_next[k]);
            st!(f, ln.t_cross[k], t_cross_next[k]);
        }
        for k in 0..3 {
            st!(f, ln.pa[k], pb[k]);
            // The next cell's entry: this one's exit, seen from there.
            let mirrored = if k < 2 {
                pick(cross[k], _mm512_sub_ps(one, b[k]), b[k])
            } else {
                b[k]
            };
            st!(f, ln.a[k], mirrored);
        }
        st!(f, ln.ca, cb);
        st!(f, ln.ta, tb);
        st!(f, ln.clearance, clearance_now);
        st!(
            i,
            ln.fetches,
            _mm512_add_epi32(fetches, _mm512_set1_epi32(4))
        );
    }

    /// The lanes where `a < b`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn lt(a: __m512, b: __m512) -> __mmask16 {
        _mm512_cmp_ps_mask::<_CMP_LT_OQ>(a, b)
    }

    /// The lanes where `a > b`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn gt(a: __m512, b: __m512) -> __mmask16 {
        _mm512_cmp_ps_mask::<_CMP_GT_OQ>(a, b)
    }

    /// The lanes where `d > 0`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn positive(d: __m512) -> __mmask16 {
        _mm512_cmp_ps_mask::<_CMP_GT_OQ>(d, _mm512_setzero_ps())
    }

    /// The lanes where `d = ±0` (a query's direction is never NaN).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn level(d: __m512) -> __mmask16 {
        let zero = _mm512_setzero_ps();
        !(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(d, zero) | _mm512_cmp_ps_mask::<_CMP_LT_OQ>(d, zero))
    }

    /// `next_crossing` of every lane: the crossing after `cell` along an axis the ray
    /// moves along (`up` and `moving`, masks), `+∞` along one it does not.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn next_crossing(
        cell: __m512i,
        (up, moving): (__mmask16, __mmask16),
        o: __m512,
        d: __m512,
    ) -> __m512 {
        let bound = pick_i(up, _mm512_add_epi32(cell, _mm512_set1_epi32(1)), cell);
        let t = _mm512_div_ps(_mm512_sub_ps(_mm512_cvtepi32_ps(bound), o), d);
        pick(moving, t, _mm512_set1_ps(f32::INFINITY))
    }

    /// The corners of every lane's cell, `[h00, h10, h01, h11]` (a cell past the last
    /// row or column reads the last one's).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn corners(hf: &HeightField, cell: [__m512i; 2]) -> [__m512; 4] {
        let last = [hf.width() - 2, hf.height() - 2];
        let at = [0, 1].map(|k| _mm512_min_epu32(cell[k], _mm512_set1_epi32(last[k] as i32)));
        let stride = hf.stride() as i32;
        let first = _mm512_add_epi32(_mm512_mullo_epi32(at[1], _mm512_set1_epi32(stride)), at[0]);
        let samples = hf.samples().as_ptr();
        let [h00, h10] = row_corners(samples, first);
        let [h01, h11] = row_corners(samples, _mm512_add_epi32(first, _mm512_set1_epi32(stride)));
        [h00, h10, h01, h11]
    }

    /// The samples at `at` and `at + 1` (indices into `samples`) of every lane: a
    /// cell row's two corners, adjacent, so each lane's pair is one 8-byte element of a
    /// gather (eight lanes a gather), split after into the left and the right corners:
    /// half the elements two 4-byte gathers load (measured: 0.93–0.96× the time of the
    /// DDA's camera frames).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn row_corners(samples: *const f32, at: __m512i) -> [__m512; 2] {
        let halves = [
            _mm512_castsi512_si256(at),
            _mm512_extracti64x4_epi64::<1>(at),
        ];
        // SAFETY (both halves): the caller's lanes index the first of two samples of a
        // row inside `samples` (a cell below the field's last row and column).
        let lo = unsafe { _mm512_i32gather_pd::<4>(halves[0], samples.cast()) };
        let hi = unsafe { _mm512_i32gather_pd::<4>(halves[1], samples.cast()) };
        let (lo, hi) = (_mm512_castpd_ps(lo), _mm512_castpd_ps(hi));
        let even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
        let odd = _mm512_add_epi32(even, _mm512_set1_epi32(1));
        [
            _mm512_permutex2var_ps(lo, even, hi),
            _mm512_permutex2var_ps(lo, odd, hi),
        ]
    }

    /// Sixteen queries field by field (`origin`, `dir`, `t_min`, `t_max`: eight
    /// vectors of a field's sixteen values), as an 8 × 8 transpose in each 256-bit
    /// half: queries `j` and `j + 8` side by side, then the two steps of unpacking and
    /// shuffling within 128-bit lanes, then the 128-bit blocks put in place. Scalar
    /// stores read back as vectors wait on store forwarding that fails (measured: a
    /// sixth of the begin pass).
    #[inline]
    #[target_feature(enable = "avx512f")]
    pub(crate) fn queries_by_field(queries: &[Query<f32>; LANES]) -> [__m512; 8] {
        // (Loops, not closures: a closure the compiler does not inline is a call per
        // use, its vectors passed through memory.)
        let mut s = [_mm512_setzero_ps(); 8];
        for (j, s) in s.iter_mut().enumerate() {
            // SAFETY: `Query<f32>` is `repr(C)`, eight `f32`: a query is one 256-bit
            // load.
            let (a, b) = unsafe {
                (
                    _mm256_loadu_ps((&raw const queries[j]).cast::<f32>()),
                    _mm256_loadu_ps((&raw const queries[j + 8]).cast::<f32>()),
                )
            };
            let low = _mm512_castps_pd(_mm512_castps256_ps512(a));
            *s = _mm512_castpd_ps(_mm512_insertf64x4::<1>(low, _mm256_castps_pd(b)));
        }
        // `u[h][f]`, block by block (128 bits): field `f`, then field `f + 4`, of queries
        // `4h..4h + 4`, then the same of queries `8 + 4h..12 + 4h`.
        let mut u = [[_mm512_setzero_ps(); 4]; 2];
        for (h, u) in u.iter_mut().enumerate() {
            let (a, b) = (s[4 * h], s[4 * h + 1]);
            let (c, d) = (s[4 * h + 2], s[4 * h + 3]);
            let t = [
                _mm512_unpacklo_ps(a, b),
                _mm512_unpackhi_ps(a, b),
                _mm512_unpacklo_ps(c, d),
                _mm512_unpackhi_ps(c, d),
            ];
            *u = [
                _mm512_shuffle_ps::<0x44>(t[0], t[2]),
                _mm512_shuffle_ps::<0xEE>(t[0], t[2]),
                _mm512_shuffle_ps::<0x44>(t[1], t[3]),
                _mm512_shuffle_ps::<0xEE>(t[1], t[3]),
            ];
        }
        // Field `f < 4` of the sixteen queries: the first block of each 256-bit half of
        // `u[0][f]` and of `u[1][f]`, in order; field `f + 4`: the second blocks.
        let low = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
        let high = _mm512_add_epi32(low, _mm512_set1_epi32(4));
        let mut fields = [_mm512_setzero_ps(); 8];
        for f in 0..4 {
            fields[f] = _mm512_permutex2var_ps(u[0][f], low, u[1][f]);
            fields[f + 4] = _mm512_permutex2var_ps(u[0][f], high, u[1][f]);
        }
        fields
    }

    /// [`super::super::first_cell`] of the next (up to) [`LANES`] queries from `next`,
    /// in lanes: the queries with a walk into `bg` (which must be empty), in order; the
    /// answers of the others into `out` (a miss of the box; a ray starting or entering
    /// under the surface, rare, by the scalar walk). Returns how many queries it took.
    #[target_feature(enable = "avx512f")]
    fn begin(
        hf: &HeightField,
        (queries, next): (&[Query<f32>], usize),
        budget: u32,
        out: &mut [Walked],
        bg: &mut Begun,
    ) -> usize {
        let count = (queries.len() - next).min(LANES);
        let valid = (u32::MAX >> (32 - count)) as u16;
        // The rays field by field; unused lanes hold a harmless one.
        let ray = match queries[next..].first_chunk::<LANES>() {
            Some(sixteen) => queries_by_field(sixteen),
            None => {
                let mut ray = [[0f32; LANES]; 8];
                #[allow(clippy::needless_range_loop)]
                for l in 0..LANES {
                    let (o, d, range) = match queries.get(next + l) {
                        Some(q) => (q.origin(), q.dir(), [q.t_min(), q.t_max()]),
                        None => ([0.0; 3], [1.0; 3], [0.0, 1.0]),
                    };
                    for k in 0..3 {
                        (ray[k][l], ray[3 + k][l]) = (o[k], d[k]);
                    }
                    (ray[6][l], ray[7][l]) = (range[0], range[1]);
                }
                ray.map(|field| ld!(f, field))
            }
        };
        let o = [ray[0], ray[1], ray[2]];
        let d = [ray[3], ray[4], ray[5]];
        let (t_min, t_max) = (ray[6], ray[7]);
        let zero = _mm512_setzero_ps();
        // `clip_surface` on the triangle surface: the top plane, the two slabs, then
        // the top or the bottom.
        let (zmin, zmax) = (hf.min_height(), hf.max_height());
        let top = _mm512_div_ps(_mm512_sub_ps(_mm512_set1_ps(zmax), o[2]), d[2]);
        let (rising, falling) = (positive(d[2]), lt(d[2], zero));
        let mut none = (level(d[2]) & gt(o[2], _mm512_set1_ps(zmax))) | (rising & lt(top, t_min));
        let lim = [hf.width() - 1, hf.height() - 1].map(|n| _mm512_set1_ps(n as f32));
        let (mut t0, mut t1) = (t_min, t_max);
        let mut side = [0u16; 2];
        for k in 0..2 {
            let (up, flat) = (positive(d[k]), level(d[k]));
            none |= flat & (lt(o[k], zero) | gt(o[k], lim[k]));
            let enter = pick(up, zero, lim[k]);
            let leave = pick(up, lim[k], zero);
            let near = _mm512_div_ps(_mm512_sub_ps(enter, o[k]), d[k]);
            let far = _mm512_div_ps(_mm512_sub_ps(leave, o[k]), d[k]);
            let later = !flat & gt(near, t0);
            t0 = pick(later, near, t0);
            side = [side[0] & !later, side[1] & !later];
            side[k] |= later;
            t1 = pick(flat, t1, rmin(t1, far));
        }
        none |= gt(t0, t1);
        t1 = pick(rising, rmin(t1, top), t1);
        let through_top = falling & gt(top, t0);
        t0 = pick(through_top, top, t0);
        side = side.map(|s| s & !through_top);
        none |= falling & gt(t0, t1);
        let margin = 1.0 + (zmax - zmin);
        let under = _mm512_div_ps(_mm512_sub_ps(_mm512_set1_ps(zmin - margin), o[2]), d[2]);
        let under = rmin(rmax(under, t0), _mm512_set1_ps(f32::MAX));
        t1 = pick(falling, rmin(t1, under), t1);
        let spans = valid
            & !none
            & _mm512_cmp_ps_mask::<_CMP_LE_OQ>(t0, t1)
            & gt(t0, _mm512_set1_ps(f32::NEG_INFINITY))
            & lt(t1, _mm512_set1_ps(f32::INFINITY));
        // The start's cell (`cell_index`) and clearance.
        let p0 = [0, 1, 2].map(|k| _mm512_add_ps(o[k], _mm512_mul_ps(t0, d[k])));
        let start = [0, 1].map(|k| rmin(rmax(p0[k], zero), lim[k]));
        // (A loop: the closure of an array's `map` here was not inlined.)
        let mut cell = [_mm512_setzero_si512(); 2];
        for (k, cell) in cell.iter_mut().enumerate() {
            let x = start[k];
            let nan = _mm512_cmp_ps_mask::<_CMP_UNORD_Q>(x, x);
            let i = _mm512_maskz_cvttps_epu32(!nan, x);
            let back = lt(d[k], zero)
                & _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(_mm512_cvtepu32_ps(i), x)
                & _mm512_cmpgt_epu32_mask(i, _mm512_setzero_si512());
            let i = _mm512_mask_sub_epi32(i, back, i, _mm512_set1_epi32(1));
            let cells = [hf.width() - 1, hf.height() - 1][k];
            *cell = _mm512_min_epu32(i, _mm512_set1_epi32(cells as i32 - 1));
        }
        let c = corners(hf, cell);
        let far = [side[0] & lt(d[0], zero), side[1] & lt(d[1], zero)];
        let (a, ca) = local_clearance(c, cell, [start[0], start[1], p0[2]], (side, far));
        let under = spans & _mm512_cmp_ps_mask::<_CMP_LE_OQ>(ca, zero);
        let walks = spans & !under;
        // The walks, packed in order.
        let index = _mm512_add_epi32(
            _mm512_set1_epi32(next as i32),
            _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
        );
        // (Macros, not closures: see `queries_by_field`.) SAFETY (every use): at most
        // `LANES` values into an array of `LANES`.
        macro_rules! pack {
            ($to:expr, $v:expr $(,)?) => {
                unsafe { _mm512_mask_compressstoreu_ps($to.as_mut_ptr(), walks, $v) }
            };
        }
        macro_rules! pack_i {
            ($to:expr, $v:expr $(,)?) => {
                unsafe { _mm512_mask_compressstoreu_epi32($to.as_mut_ptr() as *mut i32, walks, $v) }
            };
        }
        pack_i!(&mut bg.index, index);
        for k in 0..3 {
            pack!(&mut bg.o[k], o[k]);
            pack!(&mut bg.d[k], d[k]);
            pack!(&mut bg.p0[k], p0[k]);
            pack!(&mut bg.a[k], a[k]);
        }
        let moving = d.map(|d| !level(d));
        for k in 0..2 {
            pack_i!(&mut bg.cell[k], cell[k]);
            let up = positive(d[k]);
            pack!(
                &mut bg.t_cross[k],
                next_crossing(cell[k], (up, moving[k]), o[k], d[k]),
            );
        }
        for (to, v) in bg.c.iter_mut().zip(c) {
            pack!(to, v);
        }
        pack!(&mut bg.t1, t1);
        pack!(&mut bg.t0, t0);
        pack!(&mut bg.ca, ca);
        (bg.n, bg.head) = (walks.count_ones() as usize, 0);
        // The others' answers: a miss of the box; a hit where the ray enters a side
        // under the surface (`start_hit`: common in low views of the whole box); the
        // rare rays that start, or enter through the top, under it by the scalar walk.
        let sides = under & (side[0] | side[1]);
        let mut v = [[0f32; LANES]; 5];
        for (to, x) in v.iter_mut().zip([t0, p0[0], p0[1], p0[2], ca]) {
            st!(f, to, x);
        }
        let mut at = [[0u32; LANES]; 2];
        for (to, x) in at.iter_mut().zip(cell) {
            st!(i, to, x);
        }
        let mut done = valid & !walks;
        while done != 0 {
            let l = done.trailing_zeros() as usize;
            done &= done - 1;
            let (k, q) = (next + l, &queries[next + l]);
            let bit = 1 << l;
            out[k] = if under & bit == 0 {
                Ok(Trace::MISS)
            } else if sides & bit != 0 {
                let axis = usize::from(side[1] & bit != 0);
                let mut normal = [0.0; 3];
                normal[axis] = if q.dir()[axis] > 0.0 { -1.0 } else { 1.0 };
                let hit = crate::ray::Hit {
                    t: v[0][l],
                    point: glam::Vec3::new(v[1][l], v[2][l], v[3][l]),
                    cell: [at[0][l], at[1][l]],
                    normal: glam::Vec3::from_array(normal),
                    flags: crate::ray::Flags::SIDE,
                };
                Ok(Trace::hit(hit, 4, -v[4][l]))
            } else {
                trace_skipping_for(hf, Surface::Triangles, q, budget)
            };
        }
        count
    }

    /// The idle lanes (the lowest first) take the waiting walks of `bg` (the earliest
    /// first), as many as both have.
    #[target_feature(enable = "avx512f")]
    fn refill(ln: &mut Lanes, bg: &mut Begun) {
        let (mut idle, mut take) = (!ln.busy, 0u16);
        for _ in 0..(bg.n - bg.head).min(idle.count_ones() as usize) {
            take |= idle & idle.wrapping_neg();
            idle &= idle - 1;
        }
        let h = bg.head;
        // SAFETY (all): an expanding load reads one value per lane taken, at most the
        // `n − head` waiting from `head`.
        let mv = |to: &mut Lane<f32>, from: &Lane<f32>| {
            let was = ld!(f, to);
            let v = unsafe { _mm512_mask_expandloadu_ps(was, take, from[h..].as_ptr()) };
            st!(f, to, v);
        };
        let mv_i = |to: &mut Lane<u32>, from: &Lane<u32>| {
            let at = from[h..].as_ptr() as *const i32;
            let was = ld!(i, to);
            let v = unsafe { _mm512_mask_expandloadu_epi32(was, take, at) };
            st!(i, to, v);
        };
        mv_i(&mut ln.index, &bg.index);
        for k in 0..3 {
            mv(&mut ln.o[k], &bg.o[k]);
            mv(&mut ln.d[k], &bg.d[k]);
            mv(&mut ln.pa[k], &bg.p0[k]);
            mv(&mut ln.a[k], &bg.a[k]);
        }
        for k in 0..2 {
            mv_i(&mut ln.cell[k], &bg.cell[k]);
            mv(&mut ln.t_cross[k], &bg.t_cross[k]);
        }
        for k in 0..4 {
            mv(&mut ln.c[k], &bg.c[k]);
        }
        mv(&mut ln.t1, &bg.t1);
        mv(&mut ln.ta, &bg.t0);
        mv(&mut ln.ca, &bg.ca);
        mv(&mut ln.clearance, &bg.ca);
        let fetches = _mm512_mask_mov_epi32(ld!(i, ln.fetches), take, _mm512_set1_epi32(4));
        st!(i, ln.fetches, fetches);
        ln.busy |= take;
        bg.head += take.count_ones() as usize;
    }

    /// The hits of the waiting contacts into `out`, [`LANES`] at a time: the scalar
    /// walk's last steps on each (the contact test, the hit, the robust finish).
    #[target_feature(enable = "avx512f")]
    fn finish_contacts(cs: &mut Contacts, out: &mut [Walked]) {
        for at in (0..cs.n).step_by(LANES) {
            finish_sixteen(cs, at, out);
        }
        cs.n = 0;
    }

    /// The contacts from `at` (at most [`CONTACTS`] − [`LANES`]; lanes past `cs.n`
    /// compute harmless garbage) to their answers in `out`: the cell's contact test on the
    /// triangle surface ([`crate::surface::Surface::segment_hit`]), the hit's point
    /// ([`super::super::segment_point`]) and the robust finish
    /// ([`super::super::finish`], its `f64` Newton steps eight lanes at a time).
    #[target_feature(enable = "avx512f")]
    fn finish_sixteen(cs: &Contacts, at: usize, out: &mut [Walked]) {
        let one = _mm512_set1_ps(1.0);
        let f = |a: &[f32; CONTACTS]| ld!(f, a[at..]);
        let c = cs.c.each_ref().map(f);
        let (a, b) = (cs.a.each_ref().map(f), cs.b.each_ref().map(f));
        let cell = [0, 1].map(|k| _mm512_cvtepi32_ps(ld!(i, cs.cell[k][at..])));
        // The two planes, [h0, gu, gv] (`triangle_planes`), and each one's clearance at
        // both ends and root along the segment (`triangles_segment`).
        let planes = planes(c);
        let mut s = [_mm512_setzero_ps(); 2];
        let mut under = [0u16; 2];
        for k in 0..2 {
            let la = _mm512_sub_ps(a[2], plane_at(&planes[k], a[0], a[1]));
            let lb = _mm512_sub_ps(b[2], plane_at(&planes[k], b[0], b[1]));
            under[k] = _mm512_cmp_ps_mask::<_CMP_LE_OQ>(lb, _mm512_setzero_ps());
            let root = _mm512_div_ps(la, _mm512_sub_ps(la, lb));
            let started = _mm512_cmp_ps_mask::<_CMP_LE_OQ>(la, _mm512_setzero_ps());
            s[k] = pick(started, _mm512_setzero_ps(), root);
        }
        let second = under[1] & (!under[0] | _mm512_cmp_ps_mask::<_CMP_LT_OQ>(s[1], s[0]));
        let found = under[0] | under[1];
        // Neither root (rounding): the contact is at `b`, on the plane on top there.
        let first_on_top = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(
            plane_at(&planes[0], b[0], b[1]),
            plane_at(&planes[1], b[0], b[1]),
        );
        let upper = (found & second) | (!found & !first_on_top);
        let s = pick(found, pick(second, s[1], s[0]), one);
        let (gx, gy) = (
            pick(upper, planes[1][1], planes[0][1]),
            pick(upper, planes[1][2], planes[0][2]),
        );
        let len = _mm512_sqrt_ps(_mm512_add_ps(
            _mm512_add_ps(_mm512_mul_ps(gx, gx), _mm512_mul_ps(gy, gy)),
            one,
        ));
        // Negation flips the sign bit (`0 − x` would give `+0` for `x = 0`).
        let minus = |x: __m512| {
            let sign = _mm512_set1_epi32(i32::MIN);
            _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(x), sign))
        };
        let normal = [
            _mm512_div_ps(minus(gx), len),
            _mm512_div_ps(minus(gy), len),
            _mm512_div_ps(one, len),
        ];
        let along = |x: __m512, y: __m512| _mm512_add_ps(x, _mm512_mul_ps(s, _mm512_sub_ps(y, x)));
        let (ta, tb) = (f(&cs.t[0]), f(&cs.t[1]));
        let mut hit = [[0f32; LANES]; 7];
        let values = [
            along(ta, tb),
            _mm512_add_ps(cell[0], along(a[0], b[0])),
            _mm512_add_ps(cell[1], along(a[1], b[1])),
            along(a[2], b[2]),
            normal[0],
            normal[1],
            normal[2],
        ];
        for (h, v) in hit.iter_mut().zip(values) {
            st!(f, h, v);
        }
        for half in [0, LANES / 2] {
            refine_eight(cs, at + half, &mut hit, half);
        }
        let clearance = rmin(f(&cs.clearance), f(&cs.ca));
        let mut kept = [0f32; LANES];
        st!(f, kept, clearance);
        let n = (cs.n - at).min(LANES);
        for (l, &k) in cs.index[at..at + n].iter().enumerate() {
            let j = at + l;
            let hit = crate::ray::Hit {
                t: hit[0][l],
                point: glam::Vec3::new(hit[1][l], hit[2][l], hit[3][l]),
                cell: [cs.cell[0][j], cs.cell[1][j]],
                normal: glam::Vec3::new(hit[4][l], hit[5][l], hit[6][l]),
                flags: crate::ray::Flags::default(),
            };
            out[k] = Ok(Trace::hit(hit, cs.fetches[j], kept[l]));
        }
    }

    /// A plane `[h0, gu, gv]`'s height at local `(u, v)` per lane (`plane`:
    /// `h0 + gu·u + gv·v`, in that order).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn plane_at(p: &[__m512; 3], u: __m512, v: __m512) -> __m512 {
        _mm512_add_ps(
            _mm512_add_ps(p[0], _mm512_mul_ps(p[1], u)),
            _mm512_mul_ps(p[2], v),
        )
    }

    /// The triangle split's two planes (`triangle_planes`) per lane, `[h0, gu, gv]`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn planes(c: [__m512; 4]) -> [[__m512; 3]; 2] {
        let diagonal =
            _mm512_cmp_ps_mask::<_CMP_LE_OQ>(_mm512_add_ps(c[0], c[3]), _mm512_add_ps(c[1], c[2]));
        let p_v = pick(
            diagonal,
            _mm512_sub_ps(c[3], c[1]),
            _mm512_sub_ps(c[2], c[0]),
        );
        let q0 = pick(
            diagonal,
            c[0],
            _mm512_sub_ps(_mm512_add_ps(c[1], c[2]), c[3]),
        );
        let q_v = pick(
            diagonal,
            _mm512_sub_ps(c[2], c[0]),
            _mm512_sub_ps(c[3], c[1]),
        );
        [
            [c[0], _mm512_sub_ps(c[1], c[0]), p_v],
            [q0, _mm512_sub_ps(c[3], c[2]), q_v],
        ]
    }

    /// `refine` on the triangle surface for the eight contacts from `at`, whose hits
    /// (`t`, point) lie in `hit` from lane `lane`: Newton's steps in `f64` along the
    /// ray in the cell's frame, the refined `t` and point written back where they stay
    /// in the cell and in `[t_min, t_max]`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn refine_eight(cs: &Contacts, at: usize, hit: &mut [[f32; LANES]; 7], lane: usize) {
        // SAFETY (both): eight values from `at` (at most `CONTACTS − 8`), or from `lane`
        // (at most `LANES − 8`).
        let wide = |a: &[f32]| _mm512_cvtps_pd(unsafe { _mm256_loadu_ps(a[at..].as_ptr()) });
        let wide_hit = |hit: &[[f32; LANES]; 7], k: usize| {
            _mm512_cvtps_pd(unsafe { _mm256_loadu_ps(hit[k][lane..].as_ptr()) })
        };
        let corner = [0, 1].map(|k| {
            _mm512_cvtepu32_pd(unsafe {
                _mm256_loadu_si256(cs.cell[k][at..].as_ptr() as *const __m256i)
            })
        });
        let o = [
            _mm512_sub_pd(wide(&cs.o[0]), corner[0]),
            _mm512_sub_pd(wide(&cs.o[1]), corner[1]),
            wide(&cs.o[2]),
        ];
        let d = cs.d.each_ref().map(|x| wide(x));
        let c = cs.c.each_ref().map(|x| wide(x));
        let sel = |m: __mmask8, a: __m512d, b: __m512d| _mm512_mask_blend_pd(m, b, a);
        let diagonal =
            _mm512_cmp_pd_mask::<_CMP_LE_OQ>(_mm512_add_pd(c[0], c[3]), _mm512_add_pd(c[1], c[2]));
        let planes = [
            [
                c[0],
                _mm512_sub_pd(c[1], c[0]),
                sel(
                    diagonal,
                    _mm512_sub_pd(c[3], c[1]),
                    _mm512_sub_pd(c[2], c[0]),
                ),
            ],
            [
                sel(
                    diagonal,
                    c[0],
                    _mm512_sub_pd(_mm512_add_pd(c[1], c[2]), c[3]),
                ),
                _mm512_sub_pd(c[3], c[2]),
                sel(
                    diagonal,
                    _mm512_sub_pd(c[2], c[0]),
                    _mm512_sub_pd(c[3], c[1]),
                ),
            ],
        ];
        let at_t = |t: __m512d| [0, 1, 2].map(|k| _mm512_add_pd(o[k], _mm512_mul_pd(t, d[k])));
        let height = |k: usize, p: &[__m512d; 3]| {
            let pl = &planes[k];
            _mm512_add_pd(
                _mm512_add_pd(pl[0], _mm512_mul_pd(pl[1], p[0])),
                _mm512_mul_pd(pl[2], p[1]),
            )
        };
        // The upper plane at `p` (the first on a tie), its height, and one Newton step
        // on it from `t`; whether the step is defined (the ray not level with it).
        let newton = |t: __m512d, p: &[__m512d; 3]| {
            let (h0, h1) = (height(0, p), height(1, p));
            let upper = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(h1, h0);
            let h = sel(upper, h1, h0);
            let gx = sel(upper, planes[1][1], planes[0][1]);
            let gy = sel(upper, planes[1][2], planes[0][2]);
            let slope = _mm512_sub_pd(
                _mm512_sub_pd(d[2], _mm512_mul_pd(gx, d[0])),
                _mm512_mul_pd(gy, d[1]),
            );
            let defined = _mm512_cmp_pd_mask::<_CMP_NEQ_UQ>(slope, _mm512_setzero_pd());
            let t1 = _mm512_sub_pd(t, _mm512_div_pd(_mm512_sub_pd(p[2], h), slope));
            (upper, t1, defined)
        };
        let t = wide_hit(hit, 0);
        let (k, t1, ok) = newton(t, &at_t(t));
        let p1 = at_t(t1);
        let (k1, t2, ok2) = newton(t1, &p1);
        let again = k ^ k1;
        let t = sel(again, t2, t1);
        let ok = ok & (!again | ok2);
        let p = at_t(t);
        const SLACK: f64 = 1e-9;
        let inside = |x: __m512d| {
            _mm512_cmp_pd_mask::<_CMP_LE_OQ>(_mm512_set1_pd(-SLACK), x)
                & _mm512_cmp_pd_mask::<_CMP_LE_OQ>(x, _mm512_set1_pd(1.0 + SLACK))
        };
        let in_range = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(t, wide(&cs.range[0]))
            & _mm512_cmp_pd_mask::<_CMP_LE_OQ>(t, wide(&cs.range[1]));
        let kept = ok & inside(p[0]) & inside(p[1]) & in_range;
        let refined = [
            t,
            _mm512_add_pd(corner[0], p[0]),
            _mm512_add_pd(corner[1], p[1]),
            p[2],
        ];
        for (k, r) in refined.into_iter().enumerate() {
            // The `f32` hit through `f64` and back is itself.
            let now = _mm512_cvtpd_ps(sel(kept, r, wide_hit(hit, k)));
            // SAFETY: eight values from `lane`, at most `LANES − 8`.
            unsafe { _mm256_storeu_ps(hit[k][lane..].as_mut_ptr(), now) };
        }
    }

    /// [`super::super::local_clearance`] on the triangle surface for every lane: the
    /// local point and clearance of grid point `p` in `cell` (corners `c`), lying per
    /// axis on an edge of the cell (`on.0`), the far one (`on.1`).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn local_clearance(
        c: [__m512; 4],
        cell: [__m512i; 2],
        p: [__m512; 3],
        (on_edge, far): ([u16; 2], [u16; 2]),
    ) -> ([__m512; 3], __m512) {
        let (zero, one) = (_mm512_setzero_ps(), _mm512_set1_ps(1.0));
        let local = |k: usize| {
            let inside = rmin(
                rmax(_mm512_sub_ps(p[k], _mm512_cvtepi32_ps(cell[k])), zero),
                one,
            );
            pick(on_edge[k], pick(far[k], one, zero), inside)
        };
        let (u, v) = (local(0), local(1));
        let lerp = |a: __m512, b: __m512, f: __m512| {
            _mm512_add_ps(_mm512_mul_ps(a, _mm512_sub_ps(one, f)), _mm512_mul_ps(b, f))
        };
        // On the edge x = fx: its samples at v = 0 and 1; on y = fy: at u = 0 and 1.
        let x0 = pick(far[0], c[1], c[0]);
        let x1 = pick(far[0], c[3], c[2]);
        let y0 = pick(far[1], c[2], c[0]);
        let y1 = pick(far[1], c[3], c[1]);
        let on_corner = pick(far[1], x1, x0);
        let on_x = lerp(x0, x1, v);
        let on_y = lerp(y0, y1, u);
        // Inside: the higher of the triangle split's two planes (`triangle_planes`).
        let [first, second] = planes(c);
        let inner = rmax(plane_at(&first, u, v), plane_at(&second, u, v));
        let height = pick(
            on_edge[0],
            pick(on_edge[1], on_corner, on_x),
            pick(on_edge[1], on_y, inner),
        );
        ([u, v, p[2]], _mm512_sub_ps(p[2], height))
    }
}

/// Room for the hits waiting for their finish ([`Contacts`]): two steps' worth, so
/// that a step may add one per lane to fewer than [`LANES`] waiting.
const CONTACTS: usize = 2 * LANES;

/// The cells where lanes met the surface (the segment `a → b` ends on or under it),
/// field by field, with the walk's values there and the query's ray, waiting for
/// their contact test, hit and robust finish, done [`LANES`] at a time.
struct Contacts {
    n: usize,
    /// The query of each.
    index: [usize; CONTACTS],
    cell: [[u32; CONTACTS]; 2],
    c: [[f32; CONTACTS]; 4],
    a: [[f32; CONTACTS]; 3],
    b: [[f32; CONTACTS]; 3],
    ca: [f32; CONTACTS],
    /// The ray parameters of `a` and `b`.
    t: [[f32; CONTACTS]; 2],
    fetches: [u32; CONTACTS],
    clearance: [f32; CONTACTS],
    o: [[f32; CONTACTS]; 3],
    d: [[f32; CONTACTS]; 3],
    /// The query's `t_min` and `t_max`.
    range: [[f32; CONTACTS]; 2],
}

impl Contacts {
    /// None waiting.
    fn new() -> Self {
        Contacts {
            n: 0,
            index: [0; CONTACTS],
            cell: [[0; CONTACTS]; 2],
            c: [[0.0; CONTACTS]; 4],
            a: [[0.0; CONTACTS]; 3],
            b: [[0.0; CONTACTS]; 3],
            ca: [0.0; CONTACTS],
            t: [[0.0; CONTACTS]; 2],
            fetches: [0; CONTACTS],
            clearance: [0.0; CONTACTS],
            o: [[0.0; CONTACTS]; 3],
            d: [[1.0; CONTACTS]; 3],
            range: [[0.0; CONTACTS]; 2],
        }
    }
}
