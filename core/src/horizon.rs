//! Rays from one eye: an exact lower bound, shared by all of them, on where each can
//! first meet the surface. The coherent path of the batch traces (issue 21): a camera's
//! primary rays start their exact march just before the band of their hit instead of at
//! the eye (docs/DESIGN.md, "Coherent batches").
//!
//! **The bound.** Every ray from the eye E lies in the vertical plane at its azimuth;
//! at horizontal distance `s` it is at height `E_z + m·s`, `m` its slope (`d_z / |d_xy|`).
//! It passes over a square block of cells whose surface lies under `H` (the block's
//! highest sample; on corner planes plus the samples' range, see `block_tops`)
//! wherever `m > g = max (H − E_z) / s` over the block's distances `s`. The horizon
//! splits the group's azimuths into wedges (bins of a pseudo-angle) and distance into
//! bands one block wide, keeps for each wedge and band the largest `g` of the blocks the
//! wedge meets whose nearest point is in the band, and its running maximum `P` along
//! the wedge. A ray of slope `m` in a wedge passes over every block nearer than the
//! first band where `P ≥ m`: it cannot meet the surface (nor a side wall, which lies on
//! a cell's edge) before that band; a ray whose wedge never reaches `m` misses.
//!
//! **Spans.** Past that band the ray also passes over every block of a band whose own
//! largest `g` is under `m` (a ridge crossed, the ground behind it out of reach; on a
//! field of needles, the ground between them). So a march from the start that has
//! walked some cells without a hit (most rays hit before) may stop past the next two
//! such bands in a row ([`Horizon::cut_query`], an [`End`]: `1.5` bands into the pair,
//! where the cell lies in a block of one of them), and [`Horizon::resume_query`] finds
//! the next band the wedge reaches after them (from the bands' own `g`, and their
//! maxima by chunks of 16 bands and from each chunk to the last: long clear runs in a
//! read, proved misses in one), where the next span starts; that span's end is looked
//! for at once. A march of the spans one after another, each to its end, finds the
//! ray's hit, or proves a miss. An end is looked for a few bands (4) on: a ray
//! whose wedge reaches further on marches on (it hits there, nearly always). In a
//! view of tall, sparse features over low ground (most wedges' bands in the shadow of
//! those before, [`Horizon::ends_at_start`]) a start looks for its span's end at once.
//!
//! **Exactness.** The walk that starts just before that band (a sixteenth of a cell
//! or so, far above the rounding of its first point: `before_band`) enters every
//! cell after its first through the same integer crossings as the walk from the eye,
//! so the hit is the same bit for bit ([`crate::dda::trace`]'s, which every exact
//! march returns). Its first cell lies in blocks whose nearest points are nearer than
//! the band (a block's band is its nearest point's), blocks the ray passes over; so it
//! is one the ray clears with a margin (heights are raised by [`MARGIN`] relative),
//! and no rounding of the `f32` march can find a hit there; so is
//! the cell where a span ends, so the march cut there finds what the whole walk finds
//! before it, and the next span's first cell is again one the ray clears. The
//! wedges are conservative: a block's pseudo-angle range is widened before binning, its
//! distance lowered before its band is taken.
//!
//! Cost: one pass over the field (f32, vectorized: about 4 ms at 1024² with blocks of 2
//! cells; in each block row only the run of blocks the group's wedges may meet, so a
//! telephoto's pass is a fraction of that; the blocks as coarse as the rays that come
//! into the field above its surface allow, [`block_for`]), then per ray a
//! pseudo-angle, a slope and a galloping search from the last ray's band, and the
//! march from the start; for a ray that walks on, a look at a few bands for an end,
//! and the next spans' searches and marches.

mod lanes;
mod sector;

use crate::field::HeightField;
use crate::math::Real;
use crate::ray::Query;
use crate::simd::Avx512;
use crate::surface::Surface;
use alloc::vec;
use alloc::vec::Vec;
use sector::Sector;

/// Relative margin by which a cell's bound is raised (of the heights and distances
/// involved): far above the `f32` march's rounding, far below a texel.
pub const MARGIN: f64 = 1e-5;

/// Widening of a cell's pseudo-angle range before binning, relative to the group's
/// range (at least 1): the build's pseudo-angles are `f32`, a few ulps off.
const ANGLE_SLACK: f64 = 1e-6;

/// Pseudo-angle of `(x, y)` in `(−2, 2]`: increasing counter-clockwise from the
/// negative x axis (−2) through +x (0) to the negative x axis again (2), and a half
/// turn apart for opposite vectors. NaN at the origin.
#[inline]
fn pseudo_angle(x: f64, y: f64) -> f64 {
    let r = y / (x.abs() + y.abs());
    if x >= 0.0 {
        r
    } else if y >= 0.0 {
        2.0 - r
    } else {
        -2.0 - r
    }
}

/// [`pseudo_angle`] in `f32`, without branches (the build's vectorized loop).
#[inline(always)]
fn pseudo_angle_f32(x: f32, y: f32) -> f32 {
    let r = y / (x.abs() + y.abs());
    if x >= 0.0 {
        r
    } else {
        2.0f32.copysign(y) - r
    }
}

/// The horizon of a field seen from one eye, for the azimuths of a group of rays (see
/// the module docs).
#[derive(Clone, Debug)]
pub struct Horizon {
    eye: [f64; 3],
    /// The group's mean horizontal direction (unit): pseudo-angles are measured from it.
    axis: [f64; 2],
    /// Pseudo-angle of bin 0's start, and bins per unit pseudo-angle.
    angle0: f64,
    per_angle: f64,
    bins: usize,
    /// Horizontal distance where band 0 begins (the eye's distance to the footprint).
    s0: f64,
    bands: usize,
    /// Band width (the block's side, in cells).
    width: f64,
    /// The running maximum `P` of bin `b` at band `k`: `running[k * bins + b]` (band
    /// by band, so that neighbouring rays, in neighbouring bins, read one cache line).
    running: Vec<f32>,
    /// The largest slope `g` of bin `b` at band `k` itself, laid out as `running`
    /// (neighbouring rays look at neighbouring bins): `slopes[k * bins + b]`; the bands
    /// past the first reached that a ray may still skip ([`Horizon::resume_query`]).
    slopes: Vec<f32>,
    /// The largest `g` of bin `b` over the [`CHUNK`] bands of chunk `c`, and over every
    /// band from there to the last: `chunks[c * bins + b]`, `ahead[c * bins + b]` (the
    /// resumes' skips over long runs of clear bands, and their proved misses).
    chunks: Vec<f32>,
    ahead: Vec<f32>,
    /// Whether a march from a start looks for its span's end at once
    /// ([`Horizon::ends_at_start`]).
    ends_at_start: bool,
}

/// Bands a chunk of [`Horizon`]'s `chunks` spans.
const CHUNK: usize = 16;

/// Bands a span's end is looked for in (the first of two clear bands in a row among
/// them; [`Horizon::cut_query`], [`Horizon::resume_query`]): a ray whose wedge reaches
/// further on marches on.
const RUN: usize = 4;

/// A wedge is in shadow when more than this share (in %) of its bands past the first
/// that holds a block lie under the largest slope of the bands before: the view of
/// tall, sparse features over low ground (needles, from a low eye), where a ray's span
/// from its start mostly ends in a long clear run.
const SHADOW_PERCENT: u64 = 95;

/// Where a ray of a [`Horizon`]'s group may first meet the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start<R> {
    /// Not before this `t` (at least the query's `t_min`, at most its `t_max`); the
    /// lower bound of its clearance before it that the horizon proves; and where the
    /// span that opens there ends (the ray cannot meet the surface from there to the
    /// next start, [`Horizon::resume_query`]): the query's end for a ray's first start,
    /// which [`Horizon::cut_query`] may cut once a march from it has walked on.
    At(R, R, End<R>),
    /// Never in `[t_min, t_max]`: the ray passes over the field (or its range ends
    /// before the start). The lower bound of its clearance the horizon proves.
    Miss(R),
}

impl Start<f64> {
    /// In the precision of the query `q`, within its range (the margin before a start,
    /// [`before_band`], and the half band past an end cover the rounding).
    #[inline(always)]
    fn rounded<R: Real>(self, q: &Query<R>) -> Start<R> {
        match self {
            Start::At(t, c, end) => {
                let t = R::from_f64(t).max(q.t_min()).min(q.t_max());
                let end = End {
                    t: R::from_f64(end.t).max(t).min(q.t_max()),
                    band: end.band,
                };
                Start::At(t, R::from_f64(c), end)
            }
            Start::Miss(c) => Start::Miss(R::from_f64(c)),
        }
    }
}

/// Where the span of a [`Start::At`] ends: past `t`, up to the next start, the ray
/// passes over the surface (the bands of its wedge there rise to no block it could
/// meet), so a march of the span alone, to `t`, finds the same hit as the march of the
/// whole ray when there is one in the span, and no hit otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct End<R> {
    /// The span's end (at most the query's `t_max`).
    pub t: R,
    /// The first of the two clear bands the end lies past; `u32::MAX` when the span
    /// runs to the query's `t_max`.
    band: u32,
}

/// A ray's wedge, slope `m` and horizontal length (`|d_xy|`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Aim {
    wedge: u32,
    m: f64,
    rho: f64,
}

impl<R> End<R> {
    /// A span to `t_max`: the horizon proves nothing past the start.
    pub fn whole(t_max: R) -> End<R> {
        End {
            t: t_max,
            band: u32::MAX,
        }
    }

    /// Whether the ray goes on past the span ([`Horizon::resume_query`] places its next
    /// start); false when the span runs to the query's `t_max`.
    pub fn goes_on(&self) -> bool {
        self.band != u32::MAX
    }
}

/// Where a group's wedges lie: its mean horizontal direction (unit), from which
/// pseudo-angles are measured, and the range of its rays' pseudo-angles.
#[derive(Clone, Copy, Debug)]
struct Frame {
    axis: [f64; 2],
    lo: f64,
    hi: f64,
}

/// Directions [`Horizon::new`] reads to place its wedges.
const FRAME_SAMPLES: usize = 4096;

/// Rays that must share an origin before a batch builds a [`Horizon`] for them
/// ([`Horizon::for_batch`]): fewer do not repay a pass over the field.
pub const MIN_GROUP: usize = 2048;

impl Horizon {
    /// The horizon of `hf` (as `surface` reconstructs it) seen from `eye`, in `bins`
    /// wedges spanning the azimuths of `dirs` (the group's directions), over square
    /// blocks of `block` cells (1: every cell; larger: fewer items to bin, a looser
    /// bound); `None` when no direction has a horizontal part.
    pub fn new(
        hf: &HeightField,
        surface: Surface,
        eye: [f64; 3],
        dirs: impl Iterator<Item = [f64; 3]> + Clone,
        bins: usize,
        block: u32,
    ) -> Option<Horizon> {
        let n = dirs.clone().count();
        let frame = frame(&Sighting::of(dirs, n))?;
        Some(Plan::new(hf, surface, eye, frame, bins, block).pass())
    }

    /// Whether a march from a start should have its span's end looked for at once
    /// ([`Horizon::start_aimed_query_ending`]), as a resumed span's is, rather than
    /// after [`crate::march`]'s first cells: when more than a quarter of the wedges
    /// are in shadow (95 % of their bands past the first that holds a block under the
    /// largest slope before them). Measured on the benchmark's cameras: the
    /// needles' filled 5° frame 0.70× the time, their 5° frame 0.84–0.91×; the
    /// terrain fields' frames, which do not qualify, took 1.04–1.17× when every start
    /// looked (most of their rays hit before an end; the look reads five bands).
    pub fn ends_at_start(&self) -> bool {
        self.ends_at_start
    }

    /// Bytes the horizon holds.
    pub fn size_bytes(&self) -> usize {
        (self.running.len() + self.slopes.len() + self.chunks.len() + self.ahead.len()) * 4
    }

    /// The eye the horizon is seen from.
    pub fn eye(&self) -> [f64; 3] {
        self.eye
    }

    /// The width of its bands in cells: the side of the blocks it is built over.
    pub fn band_width(&self) -> f64 {
        self.width
    }

    /// The horizon for the rays of a batch (`(origin, direction)` pairs in grid
    /// space, read once) that share the first one's origin, when there are at least
    /// [`MIN_GROUP`] of them and their blocks need be no coarser than `max_block`
    /// cells: sized by [`Horizon::sized`]. `None` otherwise. [`Plan::for_batch`], built.
    pub fn for_batch(
        hf: &HeightField,
        surface: Surface,
        rays: impl ExactSizeIterator<Item = ([f64; 3], [f64; 3])>,
        max_block: u32,
    ) -> Option<Horizon> {
        Plan::for_batch(hf, surface, rays, max_block).map(Plan::build)
    }

    /// [`Horizon::new`] for `n` rays from `eye`, whose directions' azimuths `dirs`
    /// span (all of them, or a camera image's border with a grid of its pixels inside):
    /// about 512 rays a wedge, and blocks of 2ᵏ cells sized for the rays that come
    /// into the field above its surface ([`block_for`], the share of `dirs` that do,
    /// of `n`); `None` when those would be coarser than `max_block` cells.
    /// [`Plan::sized`], built.
    pub fn sized(
        hf: &HeightField,
        surface: Surface,
        eye: [f64; 3],
        dirs: impl Iterator<Item = [f64; 3]> + Clone,
        n: usize,
        max_block: u32,
    ) -> Option<Horizon> {
        Plan::sized(hf, surface, eye, dirs, n, max_block).map(Plan::build)
    }

    /// [`Horizon::start`] of a query, in its precision.
    // Inlined with what it calls: the answer, a few dozen bytes, otherwise comes back
    // through memory in narrow stores that a wide load cannot forward from.
    #[inline(always)]
    pub fn start_query<R: Real>(&self, q: &Query<R>, hint: &mut usize) -> Option<(Start<R>, u32)> {
        self.start_aimed_query(q, self.aimed(q), hint)
    }

    /// The next start of the query `q` after its span that ended at `end` (of a start
    /// this horizon placed for `q`, which went on: [`End::goes_on`]), and the horizon
    /// texels read to say it: the first band after the end's two clear bands that the
    /// ray's wedge may reach, and its span; or a proved miss when none. `None` when the
    /// horizon says nothing of it (another origin, an end that does not go on).
    pub fn resume_query<R: Real>(&self, q: &Query<R>, end: End<R>) -> Option<(Start<R>, u32)> {
        if q.origin().map(R::to_f64) != self.eye || !end.goes_on() {
            return None;
        }
        // (The aim is found again: carried in every span's end, it made a resume about
        // 35 ns cheaper and the ends of all spans four times larger, for no gain
        // measured on terrain.)
        let aim = self.aim(q.dir().map(R::to_f64))?;
        let (start, probes) = self.resume(aim, q.t_max().to_f64(), end.band as usize);
        Some((start.rounded(q), probes))
    }

    /// The wedge, slope and horizontal length of the direction `d` of a ray from the
    /// eye: `None` for a vertical ray or an azimuth outside the group's.
    #[inline]
    fn aim(&self, d: [f64; 3]) -> Option<Aim> {
        let rho = norm(d[0], d[1]);
        if rho == 0.0 {
            return None;
        }
        let (ax, ay) = (self.axis[0], self.axis[1]);
        let a = pseudo_angle(d[0] * ax + d[1] * ay, d[1] * ax - d[0] * ay);
        let b = (a - self.angle0) * self.per_angle;
        if !(b >= 0.0 && b < self.bins as f64 + 1.0) {
            return None;
        }
        let wedge = (b as usize).min(self.bins - 1) as u32;
        Some(Aim {
            wedge,
            m: d[2] / rho,
            rho,
        })
    }

    /// The start of a span at band `band` (one the ray's wedge may reach, after only
    /// clear bands) for a ray of `aim`, range `(t_min, t_max)`, clearance `before`
    /// over what it skipped; the span runs to `t_max` ([`Horizon::end_after`] cuts it).
    #[inline(always)]
    fn span(&self, aim: Aim, band: usize, (t_min, t_max): (f64, f64), before: f64) -> Start<f64> {
        // Just before the band the ray may not pass over ([`before_band`]): every block
        // holding a point there has its nearest point (its band's measure) nearer,
        // in a band the ray passes over.
        let at = self.s0 + band as f64 * self.width;
        let t = (at - before_band(self.eye, at, self.width)) / aim.rho;
        if t > t_max {
            Start::Miss(0.0)
        } else if t <= t_min {
            Start::At(t_min, f64::INFINITY, End::whole(t_max))
        } else {
            Start::At(t, before, End::whole(t_max))
        }
    }

    /// [`Horizon::span`] with its end looked for at once ([`Horizon::end_after`]) from
    /// the band after `band` (which is not clear), as resumed spans have theirs: an end
    /// not past the start (one at the query's `t_min` may lie beyond it) counts as none.
    #[inline(always)]
    fn ended_span(
        &self,
        aim: Aim,
        band: usize,
        (t_min, t_max): (f64, f64),
        before: f64,
        probes: &mut u32,
    ) -> Start<f64> {
        match self.span(aim, band, (t_min, t_max), before) {
            Start::At(t, before, _) => {
                let end = self.end_after(aim, band + 1, t_max, probes);
                Start::At(t, before, if end.t > t { end } else { End::whole(t_max) })
            }
            miss => miss,
        }
    }

    /// The end of a span of a ray of `aim` (traced to `t_max`) past the first two
    /// clear bands `j`, `j + 1` with `j` in `from..from + RUN`, at `j + 1.5` bands: the
    /// cell there lies in a block of one of them (the argument of the starts), which
    /// no march finds a contact in. The whole range when there are none.
    fn end_after(&self, aim: Aim, from: usize, t_max: f64, probes: &mut u32) -> End<f64> {
        // The bands read all at once, one bit each (without branches: the pattern is
        // the terrain's), then the first pair of clear ones.
        let mut clear = 0u32;
        for i in 0..RUN + 1 {
            let k = from + i;
            let at = k * self.bins + aim.wedge as usize;
            let g = self.slopes.get(at).filter(|_| k < self.bands);
            clear |= u32::from(g.is_none_or(|&g| f64::from(g) < aim.m)) << i;
        }
        *probes += (RUN + 1).min(self.bands.saturating_sub(from)) as u32;
        let pairs = clear & (clear >> 1);
        if pairs == 0 {
            return End::whole(t_max);
        }
        let j = from + pairs.trailing_zeros() as usize;
        let end = (self.s0 + (j as f64 + 1.5) * self.width) / aim.rho;
        match u32::try_from(j) {
            Ok(band) if j + 1 < self.bands && end < t_max => End { t: end, band },
            _ => End::whole(t_max),
        }
    }

    /// Where a march of `q` that reached `t` without a hit (at the entry of a cell the
    /// ray passes above, from where the march may go on: the same hit) may stop and
    /// let the horizon place its next start ([`Horizon::resume_query`]): past the first
    /// two clear bands in a row from there, within a few bands; the query's end when
    /// there are none. And the horizon texels read. `None` when the horizon says
    /// nothing of the ray (another origin, a vertical ray, an azimuth outside the
    /// group's).
    pub fn cut_query<R: Real>(&self, q: &Query<R>, t: R) -> Option<(End<R>, u32)> {
        if q.origin().map(R::to_f64) != self.eye {
            return None;
        }
        let aim = self.aim(q.dir().map(R::to_f64))?;
        // The first band whose pair's end lies a quarter band past `t` at least (far
        // above the rounding of `t`): `j + 1.5 > u + 0.25`, `u` the band (in
        // fractions) at `t`.
        let u = (t.to_f64() * aim.rho - self.s0) / self.width;
        let from = libm::floor(u - 1.25).max(-1.0) as isize + 1;
        let mut probes = 0;
        let end = self.end_after(aim, from.max(0) as usize, q.t_max().to_f64(), &mut probes);
        let end = End {
            t: R::from_f64(end.t).max(t).min(q.t_max()),
            band: end.band,
        };
        Some((end, probes))
    }

    /// [`Horizon::resume_query`] for a ray of `aim` traced to `t_max`, from band
    /// `band` (the first of two clear bands) on.
    fn resume(&self, aim: Aim, t_max: f64, band: usize) -> (Start<f64>, u32) {
        let (b, m) = (aim.wedge as usize, aim.m);
        // `g < m` for an `f32` `g` is `g < m_up`, the least `f32` no less than `m`.
        let m_up = m as f32;
        let m_up = if f64::from(m_up) < m {
            m_up.next_up()
        } else {
            m_up
        };
        let mut probes = 0;
        // The clear bands skipped: the ray is over every block there by `m − g` times
        // its distance, at least `s0` (`g` their largest: none is NaN).
        let mut g = f32::NEG_INFINITY;
        let over = |g: f32| ((m - f64::from(g)) * self.s0).max(0.0) * (1.0 - 1e-6);
        let mut k = band;
        while k < self.bands {
            if k.is_multiple_of(CHUNK) {
                // A whole chunk at once, or all the rest.
                let at = (k / CHUNK) * self.bins + b;
                probes += 1;
                let rest = self.ahead[at];
                if rest < m_up {
                    return (Start::Miss(over(mx(g, rest))), probes);
                }
                if self.chunks[at] < m_up {
                    g = mx(g, self.chunks[at]);
                    k += CHUNK;
                    continue;
                }
            }
            // The band's own `g`: the ray passes over it when `g < m_up` (a NaN does
            // not let it pass).
            let here = self.slopes[k * self.bins + b];
            probes += 1;
            let passes = here < m_up;
            if !passes {
                let start = self.ended_span(aim, k, (0.0, t_max), over(g), &mut probes);
                return (start, probes);
            }
            g = mx(g, here);
            k += 1;
        }
        (Start::Miss(over(g)), probes)
    }

    /// Where the ray `origin + t · dir` (grid space), traced over `t_range`, may first
    /// meet the surface, and the horizon texels read to say it (its fetches): `None`
    /// when the horizon says nothing of it (another origin, a vertical ray, an azimuth
    /// outside the group's). `hint` is a band to search from, the last answer's for
    /// the best speed (neighbouring rays start near each other); it is updated.
    #[inline(always)]
    pub fn start(
        &self,
        origin: [f64; 3],
        d: [f64; 3],
        t_range: (f64, f64),
        hint: &mut usize,
    ) -> Option<(Start<f64>, u32)> {
        self.start_aimed::<false>(self.aim_from(origin, d)?, t_range, hint)
    }

    /// The aim of each query of `queries` into `out` (cleared first), for
    /// [`Horizon::start_aimed_query`]: a pass of square roots and divisions on its own,
    /// ahead of the searches, whose branches then do not wait on them; sixteen queries a
    /// step in AVX-512 lanes with `simd` (the same aims).
    pub fn aims(&self, queries: &[Query<f32>], out: &mut Vec<Aimed>, simd: Option<Avx512>) {
        out.clear();
        let laned = simd.map_or(0, |simd| lanes::aims_in_lanes(self, queries, out, simd));
        out.extend(queries[laned..].iter().map(|q| self.aimed(q)));
    }

    /// The aim of `q`: none for a ray from another origin, a vertical ray, or one
    /// outside the group's azimuths ([`Horizon::aim`]).
    #[inline(always)]
    fn aimed<R: Real>(&self, q: &Query<R>) -> Aimed {
        Aimed(self.aim_from(q.origin().map(R::to_f64), q.dir().map(R::to_f64)))
    }

    /// [`Horizon::aim`] of a ray from `origin` in direction `d`: none unless it leaves
    /// the eye.
    #[inline(always)]
    fn aim_from(&self, origin: [f64; 3], d: [f64; 3]) -> Option<Aim> {
        if origin != self.eye {
            return None;
        }
        self.aim(d)
    }

    /// [`Horizon::start_query`] of `q`, whose aim [`Horizon::aims`] found.
    #[inline(always)]
    pub fn start_aimed_query<R: Real>(
        &self,
        q: &Query<R>,
        aimed: Aimed,
        hint: &mut usize,
    ) -> Option<(Start<R>, u32)> {
        self.start_aimed_query_ending::<R, false>(q, aimed, hint)
    }

    /// [`Horizon::start_aimed_query`], and with `ENDS` the span's end looked for at
    /// once, past two clear bands in a row within a few bands after the one reached,
    /// as a resumed span's is (for a horizon that [`Horizon::ends_at_start`]); without,
    /// the span runs to the query's end.
    #[inline(always)]
    pub fn start_aimed_query_ending<R: Real, const ENDS: bool>(
        &self,
        q: &Query<R>,
        aimed: Aimed,
        hint: &mut usize,
    ) -> Option<(Start<R>, u32)> {
        let range = (q.t_min().to_f64(), q.t_max().to_f64());
        let (start, probes) = self.start_aimed::<ENDS>(aimed.0?, range, hint)?;
        Some((start.rounded(q), probes))
    }

    /// [`Horizon::start`] of a ray from the eye of `aim`; with `ENDS`, its span's end
    /// looked for ([`Horizon::start_aimed_query_ending`]).
    #[inline(always)]
    fn start_aimed<const ENDS: bool>(
        &self,
        aim: Aim,
        (t_min, t_max): (f64, f64),
        hint: &mut usize,
    ) -> Option<(Start<f64>, u32)> {
        let (b, m) = (aim.wedge as usize, aim.m);
        let mut probes = 0;
        let reaches = |k: usize| {
            probes += 1;
            f64::from(self.running[k * self.bins + b]) >= m
        };
        // Over every block of the bands before `k` by `m − P[k − 1]` times its
        // distance, at least `s0`: the clearance there.
        let over = |k: usize| match k {
            0 => f64::INFINITY,
            k => {
                let p = f64::from(self.running[(k - 1) * self.bins + b]);
                ((m - p) * self.s0).max(0.0) * (1.0 - 1e-6)
            }
        };
        let Some(band) = first_reaching(self.bands, reaches, hint) else {
            return Some((Start::Miss(over(self.bands)), probes));
        };
        let before = over(band);
        let range = (t_min, t_max);
        let start = if ENDS {
            self.ended_span(aim, band, range, before, &mut probes)
        } else {
            self.span(aim, band, range, before)
        };
        Some((start, probes))
    }
}

/// A ray's aim found ahead of its search ([`Horizon::aims`]): `None` inside where the
/// horizon says nothing of the ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aimed(Option<Aim>);

/// A horizon to build: its eye, wedges, bands and blocks ([`Plan::for_batch`],
/// [`Plan::sized`]).
/// [`Plan::build`] builds it in one pass over the field; [`Plan::wedges`] and
/// [`Plan::finish`] let threads share that pass.
#[derive(Clone, Copy, Debug)]
pub struct Plan<'a> {
    hf: HeightField<'a>,
    surface: Surface,
    eye: [f64; 3],
    frame: Frame,
    bins: usize,
    bands: usize,
    block: u32,
    s0: f64,
    width: f64,
    per_angle: f64,
}

impl<'a> Plan<'a> {
    /// The plan of [`Horizon::for_batch`].
    pub fn for_batch(
        hf: &HeightField<'a>,
        surface: Surface,
        rays: impl ExactSizeIterator<Item = ([f64; 3], [f64; 3])>,
        max_block: u32,
    ) -> Option<Plan<'a>> {
        let total = rays.len();
        if total < MIN_GROUP {
            return None;
        }
        let mut rays = rays.peekable();
        let eye = rays.peek()?.0;
        let mut seen = Sighting::new(total);
        for (k, (o, d)) in rays.enumerate() {
            if o == eye {
                seen.add(k, d);
            }
        }
        Plan::for_sightings(hf, surface, eye, [seen], max_block)
    }

    /// [`Plan::for_batch`] from its pass over the batch's rays made in parts: `parts`
    /// in order, each the [`Sighting`] (of the whole batch's size) of one range of the
    /// rays, of those among them that leave `eye` (the first ray's origin), numbered in
    /// the batch.
    pub fn for_sightings(
        hf: &HeightField<'a>,
        surface: Surface,
        eye: [f64; 3],
        parts: impl IntoIterator<Item = Sighting>,
        max_block: u32,
    ) -> Option<Plan<'a>> {
        let seen = Sighting::join(parts)?;
        let n = seen.count;
        let block = block_of(hf, surface, eye, &seen, n, max_block);
        let fits = n >= MIN_GROUP && block <= max_block;
        let frame = frame(&seen)?;
        fits.then(|| Plan::fitted(hf, surface, eye, frame, n, block))
    }

    /// The plan of [`Horizon::sized`].
    pub fn sized(
        hf: &HeightField<'a>,
        surface: Surface,
        eye: [f64; 3],
        dirs: impl Iterator<Item = [f64; 3]> + Clone,
        n: usize,
        max_block: u32,
    ) -> Option<Plan<'a>> {
        let seen = Sighting::of(dirs.clone(), dirs.count());
        let block = block_of(hf, surface, eye, &seen, n, max_block);
        if block > max_block {
            return None;
        }
        let frame = frame(&seen)?;
        Some(Plan::fitted(hf, surface, eye, frame, n, block))
    }

    /// The plan in `frame` for `n` rays over blocks of `block` cells: about 512 rays a
    /// wedge.
    fn fitted(
        hf: &HeightField<'a>,
        surface: Surface,
        eye: [f64; 3],
        frame: Frame,
        n: usize,
        block: u32,
    ) -> Plan<'a> {
        Plan::new(hf, surface, eye, frame, (n / 512).clamp(16, 4096), block)
    }

    /// The plan of [`Horizon::new`] in the wedges of `frame`: the group's axis and its
    /// range of pseudo-angles.
    fn new(
        hf: &HeightField<'a>,
        surface: Surface,
        eye: [f64; 3],
        frame: Frame,
        bins: usize,
        block: u32,
    ) -> Plan<'a> {
        let e = eye;
        let block = block.max(1);
        let (fx, fy) = (f64::from(hf.width() - 1), f64::from(hf.height() - 1));
        let gap = |v: f64, end: f64| (0.0 - v).max(v - end).max(0.0);
        let s0 = norm(gap(e[0], fx), gap(e[1], fy));
        let far = norm(
            e[0].abs().max((fx - e[0]).abs()),
            e[1].abs().max((fy - e[1]).abs()),
        );
        let width = f64::from(block);
        let bands = ((far - s0) / width) as usize + 2;
        let bins = bins.clamp(1, ((1usize << 24) / bands).max(1));
        let per_angle = bins as f64 / (frame.hi - frame.lo).max(1e-12);
        Plan {
            hf: *hf,
            surface,
            eye,
            frame,
            bins,
            bands,
            block,
            s0,
            width,
            per_angle,
        }
    }

    /// How many block rows the field has: the rows [`Plan::wedges`] takes.
    pub fn block_rows(&self) -> u32 {
        (self.hf.height() - 1).div_ceil(self.block)
    }

    /// The horizon from one pass over the whole field, and a second over blocks half
    /// as wide where the first calls for them ([`Plan::finer`]).
    pub fn build(self) -> Horizon {
        self.build_by(Plan::pass)
    }

    /// [`Plan::build`] with `pass` the pass over the field of a plan (its
    /// [`Plan::wedges`] in parts, which threads share, then [`Plan::finish`]): the same
    /// horizon however the passes are cut.
    pub fn build_by(self, pass: impl Fn(Plan<'a>) -> Horizon) -> Horizon {
        let built = pass(self);
        match self.finer(&built) {
            Some(finer) => pass(finer),
            None => built,
        }
    }

    /// The horizon from one pass over the whole field, over this plan's blocks.
    fn pass(self) -> Horizon {
        let all = self.wedges(0..self.block_rows());
        self.finish([all])
    }

    /// The plan to build again when `built`, this plan's horizon, ends its spans at
    /// the starts ([`Horizon::ends_at_start`]: tall, sparse features over low ground)
    /// over blocks of more than one cell: the same wedges over blocks half as wide.
    /// There a block's top is a feature's over cells around it the rays pass over:
    /// the needles' filled telephoto takes about 0.8× the time with blocks of 1 cell
    /// instead of 2, both passes included.
    pub fn finer(&self, built: &Horizon) -> Option<Plan<'a>> {
        let Plan {
            ref hf,
            surface,
            eye,
            frame,
            bins,
            block,
            ..
        } = *self;
        (built.ends_at_start() && block > 1)
            .then(|| Plan::new(hf, surface, eye, frame, bins, block / 2))
    }

    /// The largest slope `g` per wedge and band (`bins × bands` values, band by band)
    /// over the blocks of block rows `rows`: one part of the pass over the field, which
    /// threads can share (each a part, [`Plan::finish`] then joins them).
    pub fn wedges(&self, rows: core::ops::Range<u32>) -> Vec<f32> {
        self.wedges_reading(rows, true)
    }

    /// [`Plan::wedges`], reading in each row only the blocks the sector of the group's
    /// azimuths may meet ([`Sector::blocks_met`]) with `sector`, else every block: the
    /// same slopes.
    fn wedges_reading(&self, rows: core::ops::Range<u32>, sector: bool) -> Vec<f32> {
        let Plan {
            ref hf,
            surface,
            eye: e,
            frame: Frame { lo, hi, .. },
            bins,
            bands,
            block,
            s0,
            width,
            per_angle,
        } = *self;
        let axis = self.frame.axis;
        let (w, h) = (hf.width(), hf.height());
        let per_band = 1.0 / width;
        let mut g_rows = vec![f32::NEG_INFINITY; bins * bands];
        let bin_of =
            |a: f32| ((f64::from(a) - lo) * per_angle).clamp(0.0, (bins - 1) as f64) as usize;
        let raise = |g: &mut [f32], b0: usize, b1: usize, band: usize, slope: f32| {
            for v in &mut g[band * bins + b0..=band * bins + b1] {
                *v = mx(*v, slope);
            }
        };
        // Block row by block row, in f32 (the margins cover its rounding), each step a
        // loop over the row that the compiler vectorizes; only raising the wedges is
        // scalar. Block `i` of a row spans samples `edges[i]..=edges[i + 1]`.
        let edges = |n: u32| -> Vec<u32> {
            (0..n - 1)
                .step_by(block as usize)
                .chain(core::iter::once(n - 1))
                .collect()
        };
        let (ex, ey) = (edges(w), edges(h));
        let nx = ex.len() - 1;
        let span_of = |a: u32, b: u32, v: f64| {
            let (a, b) = (f64::from(a) - v, f64::from(b) - v);
            let near = if a > 0.0 {
                a
            } else if b < 0.0 {
                -b
            } else {
                0.0
            };
            (near as f32, a.abs().max(b.abs()) as f32)
        };
        let (near_x, far_x): (Vec<f32>, Vec<f32>) =
            ex.windows(2).map(|p| span_of(p[0], p[1], e[0])).unzip();
        let xs: Vec<f32> = ex.iter().map(|&i| (f64::from(i) - e[0]) as f32).collect();
        let (ax, ay) = (axis[0] as f32, axis[1] as f32);
        // The pseudo-angles of the block corners of sample row `j`, at `edges` (indices
        // into the block edges).
        let angles_of = |j: u32, out: &mut [f32], edges: core::ops::Range<usize>| {
            let y = (f64::from(j) - e[1]) as f32;
            for (a, &x) in out[edges.clone()].iter_mut().zip(&xs[edges]) {
                *a = pseudo_angle_f32(x * ax + y * ay, y * ax - x * ay);
            }
        };
        let (mut below, mut above) = (vec![0.0f32; nx + 1], vec![0.0f32; nx + 1]);
        let (mut top, mut col_hi, mut col_lo) = (
            vec![0.0f32; nx],
            vec![0.0f32; w as usize],
            vec![0.0f32; w as usize],
        );
        let (mut slope, mut dist) = (vec![0.0f32; nx], vec![0.0f32; nx]);
        let (mut band, mut first, mut last) = (vec![0u32; nx], vec![0u32; nx], vec![0u32; nx]);
        let (mut plain, mut maybe) = (vec![false; nx], vec![false; nx]);
        let ez = e[2] as f32;
        let slack = (ANGLE_SLACK * (hi - lo).max(1.0)) as f32;
        let (lo32, hi32, s0_32) = (lo as f32, hi as f32, s0 as f32);
        let (per_band32, per_angle32, top_bin, top_band) = (
            per_band as f32,
            per_angle as f32,
            (bins - 1) as f32,
            (bands - 1) as f32,
        );
        if rows.is_empty() {
            return g_rows;
        }
        let ey = &ey[rows.start as usize..=(rows.end as usize).min(ey.len() - 1)];
        if ey.len() < 2 {
            return g_rows;
        }
        // The blocks of each block row the sector of the group's azimuths may meet
        // (every block when it spans half a turn or more), and the corners they need.
        let sector = sector.then(|| Sector::new(e, axis, (lo, hi))).flatten();
        let met: Vec<core::ops::Range<usize>> = ey
            .windows(2)
            .map(|rows| match &sector {
                Some(sector) => sector.blocks_met((rows[0], rows[1]), block, nx),
                None => 0..nx,
            })
            .collect();
        let corners = |k: usize| met.get(k).map_or(0..0, |m| m.start..m.end + 1);
        let both = |a: core::ops::Range<usize>, b: core::ops::Range<usize>| {
            a.start.min(b.start)..a.end.max(b.end)
        };
        angles_of(ey[0], &mut above, corners(0));
        for (r, rows) in ey.windows(2).enumerate() {
            core::mem::swap(&mut below, &mut above);
            angles_of(rows[1], &mut above, both(corners(r), corners(r + 1)));
            let (near_y, far_y) = span_of(rows[0], rows[1], e[1]);
            // The blocks from the first to the last that may raise a wedge: the others
            // are provably outside the group's azimuths (`plain` false, and none of
            // the cases of the second loop below), so skipping them changes nothing.
            // A telephoto's wedges meet a small part of each row.
            // (`mx` and `mn` are `max` and `min` where no angle is NaN, the others
            // are never outside.) Each block's nearest distance is kept for the loops.
            let met = met[r].clone();
            // (Slices of the run's length, for the loop the compiler vectorizes.)
            let (at, len) = (met.start, met.len());
            let (near_x, low, high) = (
                &near_x[at..][..len],
                &below[at..][..len + 1],
                &above[at..][..len + 1],
            );
            let run = maybe[met.clone()].iter_mut().zip(&mut dist[met.clone()]);
            for (i, (maybe, dist)) in run.enumerate() {
                let s_min = (near_x[i] * near_x[i] + near_y * near_y).sqrt();
                *dist = s_min;
                let a = [low[i], low[i + 1], high[i], high[i + 1]];
                let ordered = !(a[0].is_nan() | a[1].is_nan() | a[2].is_nan() | a[3].is_nan());
                let a0 = mn(mn(a[0], a[1]), mn(a[2], a[3]));
                let a1 = mx(mx(a[0], a[1]), mx(a[2], a[3]));
                let away = (a1 + slack < lo32) | (a0 - slack > hi32);
                *maybe = !((s_min > 0.0) & ordered & (a1 - a0 <= 2.0) & away);
            }
            let Some(i0) = maybe[met.clone()].iter().position(|&m| m) else {
                continue;
            };
            let i0 = met.start + i0;
            let i1 = met.start
                + maybe[met.clone()]
                    .iter()
                    .rposition(|&m| m)
                    .map_or(0, |i| i + 1);
            block_tops(
                hf,
                surface,
                rows[0]..=rows[1],
                &ex[i0..=i1],
                (&mut col_hi, &mut col_lo),
                &mut top[i0..i1],
            );
            for i in i0..i1 {
                let s_min = dist[i];
                let s_max = (far_x[i] * far_x[i] + far_y * far_y).sqrt();
                let t = top[i];
                let rise = t - ez + MARGIN as f32 * (1.0 + t.abs() + ez.abs() + s_max);
                slope[i] = if rise >= 0.0 {
                    rise / s_min
                } else {
                    rise / s_max
                };
                // The band of the block's nearest point, rounded down (its distance
                // lowered by a few ulps first: a band too far would let rays start
                // past the block).
                let near = s_min * (1.0 - 1.0 / 524_288.0) - s0_32;
                band[i] = mn(mx(near * per_band32, 0.0), top_band) as i32 as u32;
                // (An angle is NaN only at the eye, where `s_min` is 0: not plain.)
                let a = [below[i], below[i + 1], above[i], above[i + 1]];
                let a0 = mn(mn(a[0], a[1]), mn(a[2], a[3])) - slack;
                let a1 = mx(mx(a[0], a[1]), mx(a[2], a[3])) + slack;
                let bin = |a: f32| mn(mx((a - lo32) * per_angle32, 0.0), top_bin) as i32 as u32;
                (first[i], last[i]) = (bin(a0), bin(a1));
                // Not over the eye, not across the cut, inside the group's range.
                plain[i] = (s_min > 0.0) & (a1 - a0 <= 2.0) & (a1 >= lo32) & (a0 <= hi32);
            }
            for i in i0..i1 {
                let (k, g) = (band[i] as usize, slope[i]);
                if plain[i] {
                    let (b0, b1) = (first[i] as usize, last[i] as usize);
                    let row = &mut g_rows[k * bins..(k + 1) * bins];
                    row[b0] = mx(row[b0], g);
                    row[b1] = mx(row[b1], g);
                    for v in row.iter_mut().take(b1).skip(b0 + 1) {
                        *v = mx(*v, g);
                    }
                    continue;
                }
                let (a0, a1) = {
                    let a = [below[i], below[i + 1], above[i], above[i + 1]];
                    (
                        a[0].min(a[1]).min(a[2].min(a[3])),
                        a[0].max(a[1]).max(a[2].max(a[3])),
                    )
                };
                if dist[i] == 0.0 {
                    // The eye is over the block (or on its edge): every azimuth meets
                    // it, and no ray passes over it unless it is lower than the eye.
                    let g = if g.is_nan() || g > 0.0 {
                        f32::INFINITY
                    } else {
                        g
                    };
                    raise(&mut g_rows, 0, bins - 1, k, g);
                } else if a1 - a0 > 2.0 {
                    // Across the cut behind the axis: [min of the positive ones, 2] and
                    // [−2, max of the negative ones].
                    let a = [below[i], below[i + 1], above[i], above[i + 1]];
                    let pos = a
                        .iter()
                        .copied()
                        .filter(|&v| v > 0.0)
                        .fold(2.0f32, f32::min);
                    let neg = a
                        .iter()
                        .copied()
                        .filter(|&v| v <= 0.0)
                        .fold(-2.0f32, f32::max);
                    if hi32 + slack >= pos {
                        raise(&mut g_rows, bin_of(pos - slack), bins - 1, k, g);
                    }
                    if lo32 - slack <= neg {
                        raise(&mut g_rows, 0, bin_of(neg + slack), k, g);
                    }
                } else if a1 + slack >= lo32 && a0 - slack <= hi32 {
                    // A range of nearly a half turn (the eye all but on the block's
                    // edge), which the widening took past it.
                    raise(&mut g_rows, bin_of(a0 - slack), bin_of(a1 + slack), k, g);
                }
            }
        }
        g_rows
    }

    /// The horizon from the parts of the pass over the field ([`Plan::wedges`]; together
    /// covering every block row): their largest slopes joined, then each wedge's running
    /// maximum. The same horizon however the rows were split.
    pub fn finish(self, parts: impl IntoIterator<Item = Vec<f32>>) -> Horizon {
        let Plan {
            eye,
            frame,
            bins,
            bands,
            s0,
            width,
            per_angle,
            ..
        } = self;
        let mut parts = parts.into_iter();
        let mut g = parts.next().unwrap_or_default();
        g.resize(bins * bands, f32::NEG_INFINITY);
        for part in parts {
            for (v, &p) in g.iter_mut().zip(&part) {
                *v = mx(*v, p);
            }
        }
        // In one pass over the bands: each wedge's running maximum, and each chunk's
        // maximum; then the maxima from each chunk on. The bands' own maxima stay.
        let slopes = g;
        let n_chunks = bands.div_ceil(CHUNK);
        let mut running = vec![f32::NEG_INFINITY; bins * bands];
        let mut chunks = vec![f32::NEG_INFINITY; n_chunks * bins];
        // Per wedge, its bands under the largest slope of those before, of those after
        // one that holds a block.
        let (mut shadowed, mut behind) = (vec![0u32; bins], vec![0u32; bins]);
        for (k, row) in slopes.chunks_exact(bins).enumerate() {
            let (done, rest) = running.split_at_mut(k * bins);
            let now = &mut rest[..bins];
            if k == 0 {
                now.copy_from_slice(row);
            } else {
                let before = &done[(k - 1) * bins..][..bins];
                for ((v, &g), &p) in now.iter_mut().zip(row).zip(before) {
                    *v = mx(g, p);
                }
                let counts = shadowed.iter_mut().zip(behind.iter_mut());
                for (((under, after), &g), &p) in counts.zip(row).zip(before) {
                    *under += u32::from(g < p);
                    *after += u32::from(p > f32::NEG_INFINITY);
                }
            }
            let at = &mut chunks[(k / CHUNK) * bins..][..bins];
            for (v, &g) in at.iter_mut().zip(row) {
                *v = mx(*v, g);
            }
        }
        let mut ahead = chunks.clone();
        for c in (0..n_chunks.saturating_sub(1)).rev() {
            let (this, after) = ahead.split_at_mut((c + 1) * bins);
            for (v, &later) in this[c * bins..].iter_mut().zip(&after[..bins]) {
                *v = mx(*v, later);
            }
        }
        let in_shadow = shadowed.iter().zip(&behind);
        let in_shadow = in_shadow
            .filter(|&(&under, &after)| u64::from(under) * 100 > u64::from(after) * SHADOW_PERCENT)
            .count();
        Horizon {
            eye,
            axis: frame.axis,
            angle0: frame.lo,
            per_angle,
            bins,
            s0,
            bands,
            width,
            running,
            slopes,
            chunks,
            ahead,
            ends_at_start: in_shadow * 4 > bins,
        }
    }
}

/// How far before a band's start (horizontal distance `at` from `eye`, bands `width`
/// cells wide) a span starts: `1/64` of a cell plus `2⁻¹⁶` of the magnitudes
/// involved, about 80 times the rounding of the `f32` march's first point (a few ulps
/// of its coordinates and of `t`), about a sixteenth of a cell over a field of 1024²;
/// never more than the half band the starts kept before (measured: camera frames
/// 0.97–1.0× the time, the same hits).
fn before_band(eye: [f64; 3], at: f64, width: f64) -> f64 {
    let scale = eye[0].abs() + eye[1].abs() + 2.0 * at.abs();
    (1.0 / 64.0 + scale / 65536.0).min(0.5 * width)
}

/// The side, in cells, of the blocks a horizon of `hf` serving `n` rays is built over:
/// the power of 2 (up to 64) nearest, as a ratio, to `1.6 ∛(cells / n)`. The pass over
/// the field costs as its blocks (`cells / B²`), each served ray's walk from its start
/// grows with the blocks' side (`n B`), and the sum is least near `∛(cells / n)`; the
/// factor is measured (640 × 512 cameras over the 1024² Himalaya DEM: blocks of 2 where
/// the terrain fills the frame, 4 for the whole field from 45°, 4 or 8 from 5°; 8 for
/// the report's 160 × 120 cameras). (The rays a horizon serves are those that come into
/// the field above its surface, [`Plan::for_sightings`]: a camera that shows the whole
/// field from afar sends most of its rays past it or into its sides.)
pub fn block_for(hf: &HeightField, n: usize) -> u32 {
    let cells = f64::from(hf.width() - 1) * f64::from(hf.height() - 1);
    let best = 1.6 * libm::cbrt(cells / n.max(1) as f64);
    let mut block = 1u32;
    while f64::from(block) * core::f64::consts::SQRT_2 <= best && block < 64 {
        block *= 2;
    }
    block
}

/// What a pass over a group's rays (or a part of them) gathers to place its wedges
/// and size its blocks: how many rays it saw, and the directions of about 4096 of the
/// whole group, picked by their number in it through a multiplicative hash so that no
/// stride of a batch (an image's columns) is missed. Parts of a batch
/// (consecutive ranges of its rays) can be sighted apart, on several threads, then
/// joined in order ([`Plan::for_sightings`]): the same sample as one pass takes.
#[derive(Clone, Debug)]
pub struct Sighting {
    /// The hash's threshold: `FRAME_SAMPLES / total` of its range.
    below: u64,
    count: usize,
    sample: Vec<[f64; 3]>,
}

impl Sighting {
    /// An empty sighting of a group of about `total` rays.
    pub fn new(total: usize) -> Sighting {
        let below = (FRAME_SAMPLES as f64 / total.max(1) as f64 * 18_446_744_073_709_551_616.0)
            .min(u64::MAX as f64) as u64;
        Sighting {
            below,
            count: 0,
            sample: Vec::new(),
        }
    }

    /// Sees ray number `k` of the group, its direction `d` (grid space).
    #[inline]
    pub fn add(&mut self, k: usize, d: [f64; 3]) {
        self.count += 1;
        if self.picked(k) {
            self.keep(d);
        }
    }

    /// Sees the rays `first..first + n` of a batch (`n` at most 64) that leave the
    /// group's eye, those whose bit is set in `at` (bit `i` for ray `first + i`),
    /// `dir(i)` the direction of ray `first + i` (grid space): as [`Sighting::add`] of
    /// each of them, in order.
    #[inline]
    pub fn add_run(&mut self, first: usize, n: usize, at: u64, dir: impl Fn(usize) -> [f64; 3]) {
        self.count += at.count_ones() as usize;
        for i in 0..n {
            if self.picked(first + i) && at >> i & 1 == 1 {
                self.keep(dir(i));
            }
        }
    }

    /// Whether ray number `k` of the group is in the sample.
    #[inline(always)]
    fn picked(&self, k: usize) -> bool {
        (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) <= self.below
    }

    /// Keeps a picked direction `d` in the sample, unless it has no horizontal part.
    fn keep(&mut self, d: [f64; 3]) {
        if d[0] != 0.0 || d[1] != 0.0 {
            self.sample.push(d);
        }
    }

    /// The sighting of the directions `dirs`, the whole group.
    fn of(dirs: impl Iterator<Item = [f64; 3]>, total: usize) -> Sighting {
        let mut s = Sighting::new(total);
        for (k, d) in dirs.enumerate() {
            s.add(k, d);
        }
        s
    }

    /// `parts` joined in order.
    fn join(parts: impl IntoIterator<Item = Sighting>) -> Option<Sighting> {
        parts.into_iter().reduce(|mut all, part| {
            all.count += part.count;
            all.sample.extend(part.sample);
            all
        })
    }
}

/// The blocks of a horizon for the `n` rays from `eye` whose directions `seen`
/// samples: sized for the rays it serves ([`served`], [`block_for`]), yet no coarser
/// than `max_block` where blocks sized for all `n` rays are no coarser either (a
/// method whose own march beats coarser horizons keeps its horizon).
fn block_of(
    hf: &HeightField,
    surface: Surface,
    eye: [f64; 3],
    seen: &Sighting,
    n: usize,
    max_block: u32,
) -> u32 {
    let all = block_for(hf, n);
    block_for(hf, served(hf, surface, eye, seen, n)).min(all.max(max_block))
}

/// How many of the `n` rays from `eye` whose directions `seen` samples the horizon
/// serves, estimated from the sample (all `n` when it is empty): the rays that come
/// into the box of the field's `surface` above the surface (through its top, through
/// a side over the surface there, or from an eye inside the box over the surface).
/// The others miss the box or meet a side under the surface, answered without a
/// start. Only the blocks' size depends on it (measured: blocks of 4 cells instead of
/// 2 make the whole field's frames from 45° and 5° 0.89× and 0.82× as long; a frame
/// the terrain fills keeps blocks of 2).
fn served(hf: &HeightField, surface: Surface, eye: [f64; 3], seen: &Sighting, n: usize) -> usize {
    let sample = &seen.sample;
    if sample.is_empty() {
        return n;
    }
    let origin = eye.map(|v| v as f32);
    let above = |d: &[f64; 3]| {
        let dir = d.map(|v| v as f32);
        let Ok(q) = Query::from_arrays(origin, dir, 0.0, f32::INFINITY) else {
            return false;
        };
        crate::dda::clip_surface(hf, surface, &q).is_some_and(|span| {
            let p = q.at(span.t0);
            p[2] > surface.height_at(hf, p[0], p[1])
        })
    };
    // A quarter of the sample is enough for the size of a block, and at most one ray
    // in 16 of the group (a small group's sample is all its rays: a box clip and a
    // height each would add about 25 ns a ray to 2048 of them).
    let looked = sample.iter().step_by(4.max(sample.len() * 16 / n.max(1)));
    let (len, hits) = (looked.len(), looked.filter(|d| above(d)).count());
    (n as u64 * hits as u64).div_ceil(len as u64) as usize
}

/// The unit mean horizontal direction of the sampled directions of `seen` (or +x when
/// they cancel) and the range of their pseudo-angles from it, widened by a hundredth
/// of itself on each side; `None` when no direction has a horizontal part. A ray
/// outside the range is traced without the horizon.
fn frame(seen: &Sighting) -> Option<Frame> {
    let sample = seen.sample.as_slice();
    let mut sum = [0.0f64; 2];
    for d in sample {
        let len = norm(d[0], d[1]);
        sum = [sum[0] + d[0] / len, sum[1] + d[1] / len];
    }
    let len = norm(sum[0], sum[1]);
    let axis = if len > 1e-9 {
        [sum[0] / len, sum[1] / len]
    } else {
        [1.0, 0.0]
    };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for d in sample {
        let a = pseudo_angle(
            d[0] * axis[0] + d[1] * axis[1],
            d[1] * axis[0] - d[0] * axis[1],
        );
        (lo, hi) = (lo.min(a), hi.max(a));
    }
    let pad = (hi - lo) / 100.0;
    let (lo, hi) = ((lo - pad).max(-2.0), (hi + pad).min(2.0));
    (lo <= hi).then_some(Frame { axis, lo, hi })
}

/// An upper bound of the surface over each block of one block row (or of a run of
/// its blocks): its highest sample, plus the samples' range on corner planes (whose
/// plane reaches `h10 + h01 − h00` at a cell's far corner). The blocks span sample
/// rows `rows` and sample columns `edges[i]..=edges[i + 1]`; `col_hi` and `col_lo`
/// are scratch of the field's width (each column's highest and lowest sample over
/// `rows`, for the columns of the blocks).
fn block_tops(
    hf: &HeightField,
    surface: Surface,
    rows: core::ops::RangeInclusive<u32>,
    edges: &[u32],
    (col_hi, col_lo): (&mut [f32], &mut [f32]),
    top: &mut [f32],
) {
    let n = top.len();
    let cols = edges[0] as usize..=edges[n] as usize;
    let first = &hf.row(*rows.start())[cols.clone()];
    col_hi[cols.clone()].copy_from_slice(first);
    col_lo[cols.clone()].copy_from_slice(first);
    for j in rows.skip(1) {
        let (hi, lo) = (&mut col_hi[cols.clone()], &mut col_lo[cols.clone()]);
        for ((hi, lo), &v) in hi
            .iter_mut()
            .zip(lo.iter_mut())
            .zip(&hf.row(j)[cols.clone()])
        {
            *hi = mx(*hi, v);
            *lo = mn(*lo, v);
        }
    }
    // Every block but the last spans `edges[1] − edges[0]` cells: its columns are
    // `edges[0] + i · block + o`, loops the compiler vectorizes.
    let block = (edges[1] - edges[0]) as usize;
    let span = |col: &[f32], init: f32, f: fn(f32, f32) -> f32, out: &mut [f32]| {
        out.fill(init);
        for o in 0..=block {
            let cols = col[edges[0] as usize + o..].iter().step_by(block);
            for (t, &v) in out[..n - 1].iter_mut().zip(cols) {
                *t = f(*t, v);
            }
        }
        let (a, b) = (edges[n - 1] as usize, edges[n] as usize);
        out[n - 1] = col[a..=b].iter().fold(init, |m, &v| f(m, v));
    };
    span(col_hi, f32::NEG_INFINITY, mx, top);
    if surface == Surface::CornerPlanes {
        let mut low = vec![0.0f32; n];
        span(col_lo, f32::INFINITY, mn, &mut low);
        for (t, l) in top.iter_mut().zip(&low) {
            *t += *t - l;
        }
    }
}

/// The larger of two values that are not NaN (one `maxss`, unlike `f32::max`).
#[inline(always)]
fn mx(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// The smaller of two values that are not NaN.
#[inline(always)]
fn mn(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `|(x, y)|` (of values far from overflow: f32 coordinates in f64).
#[inline]
fn norm(x: f64, y: f64) -> f64 {
    libm::sqrt(x * x + y * y)
}

/// The first of `0..len` that `reaches` (false, then true), searched outwards from
/// `*hint` (then set to it); `None` when none does.
#[inline]
fn first_reaching(
    len: usize,
    mut reaches: impl FnMut(usize) -> bool,
    hint: &mut usize,
) -> Option<usize> {
    let last = len - 1;
    if !reaches(last) {
        return None;
    }
    let k = (*hint).min(last);
    // Gallop to a bracket (lo, hi]: `lo` does not reach (or is −1), `hi` does.
    let (mut lo, mut hi) = if reaches(k) {
        let mut step = 1;
        let mut hi = k;
        loop {
            if hi < step {
                break (None, hi);
            }
            let probe = hi - step;
            if !reaches(probe) {
                break (Some(probe), hi);
            }
            hi = probe;
            step *= 2;
        }
    } else {
        let mut step = 1;
        let mut lo = k;
        loop {
            let probe = (lo + step).min(last);
            if reaches(probe) {
                break (Some(lo), probe);
            }
            lo = probe;
            step *= 2;
        }
    };
    // Bisect: the answer is in (lo, hi].
    while hi - lo.map_or(0, |l| l + 1) > 0 {
        let from = lo.map_or(0, |l| l + 1);
        let mid = from + (hi - from) / 2;
        if reaches(mid) {
            hi = mid;
        } else {
            lo = Some(mid);
        }
    }
    *hint = hi;
    Some(hi)
}
