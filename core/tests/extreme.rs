//! The stiff and extreme case suite (issue 7): every method on the cases that break
//! ray casters, against the `f64` exact traversal (`dda::trace` on the same ray).
//!
//! Methods: the exact DDA (`f32`, `f64`), maximum mipmaps (exact: one-level and highest
//! ascent, `f32` and `f64`; approximate: level of detail, iterative bilinear), safety
//! distances (exact: four classes and isotropic, `f32` and `f64`; approximate:
//! strictly positive distances), linear + binary search and linear + secant; on fields
//! small enough for their slow bakes, cone step mapping and QDM (conservative and
//! iterative: a trace that does not run out of iterations is exact, one that does is
//! flagged and never past the first hit; a cap of 4 exercises the budget) and relaxed
//! cone stepping (approximate: only its step bound is asserted).
//!
//! Cases: grazing rays down to 1e-4 rad; axis-parallel and exactly vertical rays at
//! integer and half-integer coordinates; origins on cell corners and centerlines and
//! under the surface; long rays across 8193 × 64 and 16384 × 16 fields; origins 1e5
//! grid units away; height ranges 1e-6 and 1e6; all-equal heights; 2 × 2, 2 × 4096 and
//! 4096 × 2 fields; needles and 1-texel walls at full height; NaN and infinities in
//! heights and rays, and finite values whose arithmetic overflows.
//!
//! The `f64` DDA is the oracle; brute force over all cells checks it (and the `f32`
//! DDA) on every case, on every ray of small fields and a few of large ones.
//!
//! Rules (docs/DESIGN.md): a ray is **ambiguous** when the oracle's clearance is under
//! 2⁻¹³ · max(1, |z|) (`f32` traces; 1e-9 · max(1, |z|) for `f64` traces): counted on
//! its own, never as right. An `f32` ray is **wrong** when hit/miss differs from the
//! oracle or the hit is farther than `max(1e-3, 8 · eps32 · (|o|∞ + |p|∞))` texels from
//! the oracle's (`o` the origin, `p` the oracle's hit: 1e-3 near the field, a few ulps
//! of the coordinates far from it, where `f32` cannot resolve 1e-3); an `f64` trace is
//! wrong past `1e-9 ·` the scene's length scale. Exact methods: zero wrong rays.
//! Approximate methods: their errors are printed, and the one-sided bound each one has
//! is asserted (a search hit has the true hit at most one linear step later; a level
//! of detail box is never entered after the surface; an iterative or strictly positive
//! march only reports points on or under the surface, so the true hit is never later).
//!
//! Step bounds: every trace's fetch count is checked against a bound from W + H (and
//! the pyramid's levels) or the step counts; exact traces never set
//! `BUDGET_EXHAUSTED`. Numerics: the stable quadratic against the textbook formula,
//! ray–plane tests with nearly parallel rays, and drift over 10⁴ cells.
#![cfg(all(
    feature = "safety",
    feature = "search",
    feature = "qdm",
    feature = "relaxed"
))]

mod common;

use common::*;
use hfcast::maxmip::{self, Ascent, Layout, MaxMip};
use hfcast::safety::{self, SafetyMap, Variant};
use hfcast::search::{self, Refine};
use hfcast::surface::smallest_root_in_unit;
use hfcast::{cone, cone::Cone, qdm, qdm::Qdm, relaxed, relaxed::Relaxed};
use hfcast::{
    dda, FieldError, Flags, HeightField, Query, RayError, Real, SearchSteps, Surface, Trace,
};

// ---------------------------------------------------------------------------------
// Methods
// ---------------------------------------------------------------------------------

/// How a method is run.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Dda,
    MaxMip(maxmip::Options),
    Safety(safety::Options),
    LinearBinary(SearchSteps),
    Secant(u32),
    /// Cone step mapping with an iteration cap.
    Cone(u32),
    /// Quadratic displacement maps with an iteration cap.
    Qdm(u32),
    Relaxed(relaxed::Steps),
}

/// Largest fields (samples) the cone and QDM bakes run on here.
const CONE_MAX_SAMPLES: usize = 70_000;
/// Largest fields (samples) the relaxed cone bake (Θ(N⁴)) runs on here.
const RELAXED_MAX_SAMPLES: usize = 1_000;

/// What an approximate method guarantees, asserted on every non-ambiguous ray.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Bound {
    /// Exact: the oracle's answer.
    Exact,
    /// A hit has the oracle's hit at most one linear step (of the clipped span) later.
    Search(u32),
    /// Conservative (a box over the surface): the oracle hitting implies a hit no later.
    Conservative,
    /// Only points on or under the surface are reported: a hit implies the oracle's hit,
    /// no later.
    RealPoint,
    /// Iterative and conservative (cone steps, QDM): the oracle's answer unless the
    /// trace is flagged `BUDGET_EXHAUSTED`, and then a guess no later than the oracle's
    /// hit.
    Capped,
    /// No one-sided bound (relaxed cone stepping): only the step bound is checked.
    Free,
}

struct Def {
    name: &'static str,
    kind: Kind,
    bound: Bound,
}

fn defs() -> Vec<Def> {
    let mm = |ascent, lod, iterative_bilinear| {
        Kind::MaxMip(maxmip::Options {
            ascent,
            lod,
            iterative_bilinear,
        })
    };
    let sd = |variant, positive| {
        Kind::Safety(safety::Options {
            variant,
            positive,
            ..Default::default()
        })
    };
    vec![
        Def {
            name: "dda",
            kind: Kind::Dda,
            bound: Bound::Exact,
        },
        Def {
            name: "maxmip one-level",
            kind: mm(Ascent::OneLevel, None, None),
            bound: Bound::Exact,
        },
        Def {
            name: "maxmip highest",
            kind: mm(Ascent::Highest, None, None),
            bound: Bound::Exact,
        },
        Def {
            name: "safety 4 classes",
            kind: sd(Variant::Directional, false),
            bound: Bound::Exact,
        },
        Def {
            name: "safety isotropic",
            kind: sd(Variant::Isotropic, false),
            bound: Bound::Exact,
        },
        Def {
            name: "maxmip lod 1/256",
            kind: mm(Ascent::OneLevel, Some(1.0 / 256.0), None),
            bound: Bound::Conservative,
        },
        Def {
            name: "maxmip iterative 4:8",
            kind: mm(Ascent::OneLevel, None, Some((4, 8))),
            bound: Bound::RealPoint,
        },
        Def {
            name: "safety positive",
            kind: sd(Variant::Directional, true),
            bound: Bound::RealPoint,
        },
        Def {
            name: "linear-binary 32:8",
            kind: Kind::LinearBinary(SearchSteps {
                linear: 32,
                binary: 8,
            }),
            bound: Bound::Search(32),
        },
        Def {
            name: "linear-binary 256:16",
            kind: Kind::LinearBinary(SearchSteps {
                linear: 256,
                binary: 16,
            }),
            bound: Bound::Search(256),
        },
        Def {
            name: "secant 64",
            kind: Kind::Secant(64),
            bound: Bound::Search(64),
        },
        Def {
            name: "cone cap 4",
            kind: Kind::Cone(4),
            bound: Bound::Capped,
        },
        Def {
            name: "cone cap 256",
            kind: Kind::Cone(256),
            bound: Bound::Capped,
        },
        Def {
            name: "qdm cap 4",
            kind: Kind::Qdm(4),
            bound: Bound::Capped,
        },
        Def {
            name: "qdm cap 256",
            kind: Kind::Qdm(256),
            bound: Bound::Capped,
        },
        Def {
            name: "relaxed 64:8",
            kind: Kind::Relaxed(relaxed::Steps {
                cone: 64,
                binary: 8,
            }),
            bound: Bound::Free,
        },
    ]
}

impl Def {
    fn exact(&self) -> bool {
        self.bound == Bound::Exact
    }
    /// Surfaces the method traces here: safety distances are for triangles; the
    /// iterative cell test is a bilinear option.
    fn supports(&self, surface: Surface) -> bool {
        match self.kind {
            Kind::Safety(_) | Kind::Cone(_) | Kind::Qdm(_) | Kind::Relaxed(_) => {
                surface == Surface::Triangles
            }
            Kind::MaxMip(o) if o.iterative_bilinear.is_some() => surface == Surface::Bilinear,
            _ => true,
        }
    }
}

/// Everything baked for one field.
struct Baked {
    pyramid: Vec<f32>,
    safety: Vec<(safety::Options, Vec<u8>)>,
    levels: u32,
    /// Cone map, QDM and relaxed cone map, where the field is small enough.
    cone: Option<Vec<f32>>,
    qdm: Option<Vec<f32>>,
    relaxed: Option<Vec<f32>>,
}

impl Baked {
    fn new(hf: &HeightField) -> Baked {
        Baked::with_limits(hf, CONE_MAX_SAMPLES, RELAXED_MAX_SAMPLES)
    }

    /// Bakes the cone and QDM maps only on fields of at most `cone_max` samples, the
    /// relaxed cone map on at most `relaxed_max`.
    fn with_limits(hf: &HeightField, cone_max: usize, relaxed_max: usize) -> Baked {
        let mut pyramid = vec![f32::NAN; maxmip::pyramid_len(hf.width(), hf.height())];
        maxmip::bake(hf, &mut pyramid).expect("sized");
        let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
        let safety = defs()
            .into_iter()
            .filter_map(|d| match d.kind {
                Kind::Safety(o) => Some(o),
                _ => None,
            })
            .map(|o| {
                let mut data = vec![0u8; safety::map_len(hf.width(), hf.height(), o.variant)];
                safety::bake(hf, &mut scratch, o, &mut data).expect("sized");
                (o, data)
            })
            .collect();
        let (w, h) = (hf.width(), hf.height());
        let samples = w as usize * h as usize;
        // The cone family's bakes all search the pyramid in the same scratch.
        let map = |len: usize, bake: BakeFn| {
            let mut s = vec![0f32; cone::scratch_len(w, h)];
            let mut out = vec![f32::NAN; len];
            bake(hf, &mut s, &mut out).expect("sized");
            out
        };
        let small = samples <= cone_max;
        Baked {
            pyramid,
            safety,
            levels: Layout::of(hf).levels(),
            cone: small.then(|| map(cone::map_len(w, h), cone::bake::<Cone>)),
            qdm: small.then(|| map(qdm::map_len(w, h), cone::bake::<Qdm>)),
            relaxed: (samples <= relaxed_max)
                .then(|| map(relaxed::map_len(w, h), cone::bake::<Relaxed>)),
        }
    }

    /// `false` for a method whose map was not baked (the field is too big for it).
    fn has(&self, def: &Def) -> bool {
        match def.kind {
            Kind::Cone(_) => self.cone.is_some(),
            Kind::Qdm(_) => self.qdm.is_some(),
            Kind::Relaxed(_) => self.relaxed.is_some(),
            _ => true,
        }
    }
}

/// A core bake function `(field, scratch, out)`.
type BakeFn = fn(&HeightField, &mut [f32], &mut [f32]) -> Result<(), cone::BakeError>;

fn run<R: Real>(def: &Def, b: &Baked, hf: &HeightField, s: Surface, q: &Query<R>) -> Trace<R> {
    match def.kind {
        Kind::Dda => dda::trace(hf, s, q),
        Kind::MaxMip(o) => {
            let mip = MaxMip::new(hf, &b.pyramid).expect("baked");
            maxmip::trace(hf, &mip, s, q, &o)
        }
        Kind::Safety(o) => {
            let data = &b.safety.iter().find(|(k, _)| *k == o).expect("baked").1;
            let map = SafetyMap::new(hf, data, o.variant).expect("baked");
            safety::trace(&map, hf, q)
        }
        Kind::LinearBinary(st) => search::linear(hf, s, q, st.linear, Refine::Binary(st.binary)),
        Kind::Secant(n) => search::linear(hf, s, q, n, Refine::Secant),
        Kind::Cone(cap) => {
            let map = cone::ConeMap::new(hf, b.cone.as_ref().expect("baked")).expect("baked");
            cone::trace(&map, hf, q, cap)
        }
        Kind::Qdm(cap) => {
            let map = qdm::QdmMap::new(hf, b.qdm.as_ref().expect("baked")).expect("baked");
            qdm::trace(&map, hf, q, cap)
        }
        Kind::Relaxed(st) => relaxed::trace(b.relaxed.as_ref().expect("baked"), hf, q, st),
    }
}

/// The largest fetch count a trace of `def` may take on a `W × H` field.
///
/// - DDA: 4 per cell, at most W + H − 3 cells on a ray.
/// - Maximum mipmap: each node of each level is read at most once along a ray (the
///   march never re-enters a node it left), at most `(W + H) / 2ˡ + 2` nodes of level
///   `l` lie on a ray, plus 4 corners per level-0 cell: `6 (W + H) + 2 · levels`.
/// - Safety distances: per main-axis centerline at most one distance and two
///   clearances, and the cell walk's 4 per cell: `7 (W + H)` (and the march's guard).
/// - Searches: 4 per height sample, `linear + 1` samples and `binary` bisections.
/// - Cone steps, QDM: 4 at the start, then per iteration at most a texel and a cell
///   test (4): `5 · cap + 4` (with a margin).
/// - Relaxed cone steps: 4 per surface height and 1 per ratio, for the start, each cone
///   step and each bisection.
fn fetch_bound(def: &Def, hf: &HeightField, levels: u32) -> u64 {
    let wh = u64::from(hf.width()) + u64::from(hf.height());
    match def.kind {
        Kind::Dda => 4 * wh,
        Kind::MaxMip(_) => 6 * wh + 2 * u64::from(levels) + 8,
        Kind::Safety(_) => 7 * wh + 16,
        Kind::LinearBinary(s) => 4 * u64::from(s.linear + 1 + s.binary),
        Kind::Secant(n) => 4 * u64::from(n + 1),
        Kind::Cone(cap) | Kind::Qdm(cap) => 5 * u64::from(cap) + 8,
        Kind::Relaxed(st) => 5 * u64::from(st.cone + 1) + 4 * u64::from(st.binary + 1) + 8,
    }
}

// ---------------------------------------------------------------------------------
// Judging
// ---------------------------------------------------------------------------------

/// Counts of one method on one case.
#[derive(Clone, Debug, Default)]
struct Stat {
    tried: u64,
    wrong: u64,
    ambiguous: u64,
    hits: u64,
    err_n: u64,
    err_sum: f64,
    err_max: f64,
    /// Largest fetches / bound.
    fetch_ratio: f64,
    /// Fetch bound or budget flag violations.
    over_budget: u64,
    /// One-sided bound violations of an approximate method.
    bound_broken: u64,
    examples: Vec<String>,
}

impl Stat {
    fn note(&mut self, what: String) {
        if self.examples.len() < 3 {
            self.examples.push(what);
        }
    }
}

/// One case: per method (and precision) counts, plus brute-force checks of the `f64`
/// oracle itself on small fields.
struct Case {
    name: String,
    rows: Vec<(String, bool, Stat)>,
    brute: Judged,
    brute_used: bool,
}

impl Case {
    fn new(name: impl Into<String>) -> Case {
        let name = name.into();
        let mut rows = Vec::new();
        for d in defs() {
            rows.push((format!("{} f32", d.name), d.exact(), Stat::default()));
            // The f64 DDA is the oracle itself: brute force checks it (the case's last line).
            if d.exact() && !matches!(d.kind, Kind::Dda) {
                rows.push((format!("{} f64", d.name), true, Stat::default()));
            }
        }
        Case {
            brute: Judged::new(format!("{name}: f64/f32 DDA vs brute force")),
            name,
            rows,
            brute_used: false,
        }
    }

    fn row(&mut self, name: &str) -> &mut Stat {
        &mut self.rows.iter_mut().find(|r| r.0 == name).expect("row").2
    }

    /// Wrong rays of exact methods, over-budget traces, broken bounds.
    fn failures(&self) -> u64 {
        self.rows
            .iter()
            .map(|(_, exact, s)| s.over_budget + s.bound_broken + if *exact { s.wrong } else { 0 })
            .sum::<u64>()
            + self.brute.tally.wrong
    }

    fn print(&self) -> String {
        let mut out = format!("== {}\n", self.name);
        for (name, exact, s) in &self.rows {
            if s.tried == 0 {
                continue;
            }
            let mean = s.err_sum / s.err_n.max(1) as f64;
            out.push_str(&format!(
                "  {name:<28}{} tried {:>6}  wrong {:>5}  ambiguous {:>4}  hits {:>6}  err mean \
                 {mean:.1e} max {:.1e}  fetches/bound max {:.2}{}{}\n",
                if *exact { " (exact)" } else { "        " },
                s.tried,
                s.wrong,
                s.ambiguous,
                s.hits,
                s.err_max,
                s.fetch_ratio,
                if s.over_budget > 0 {
                    format!("  OVER BUDGET {}", s.over_budget)
                } else {
                    String::new()
                },
                if s.bound_broken > 0 {
                    format!("  BOUND BROKEN {}", s.bound_broken)
                } else {
                    String::new()
                },
            ));
            if *exact && s.wrong > 0 || s.over_budget + s.bound_broken > 0 {
                for e in &s.examples {
                    out.push_str(&format!("      e.g. {e}\n"));
                }
            }
        }
        if self.brute_used {
            self.brute.report(&mut out);
        }
        out
    }
}

/// The wrong-ray tolerance of an `f32` trace (texels).
fn tol32(o: [f64; 3], p: [f64; 3]) -> f64 {
    let inf = |v: [f64; 3]| v.iter().fold(0f64, |m, x| m.max(x.abs()));
    WRONG.max(8.0 * f64::from(f32::EPSILON) * (inf(o) + inf(p)))
}

/// One method on one field and surface, as [`trace_all`] runs it: its maps and fetch
/// bound.
#[derive(Clone, Copy)]
struct Judging<'a> {
    def: &'a Def,
    baked: &'a Baked,
    hf: &'a HeightField<'a>,
    surface: Surface,
    bound: u64,
}

impl Judging<'_> {
    /// Traces `q` and judges the trace against `oracle`, the oracle of the same ray;
    /// counts it in the case's row of the method in `precision` ("f32", "f64"). The
    /// ray is ambiguous when the oracle's clearance is under `amb_eps`; a hit is wrong
    /// farther than `tol(oracle's hit)` from the oracle's.
    fn judge<R: Real>(
        self,
        case: &mut Case,
        precision: &str,
        q: &Query<R>,
        oracle: &Trace<f64>,
        amb_eps: f64,
        tol: impl Fn([f64; 3]) -> f64,
    ) {
        let got = run(self.def, self.baked, self.hf, self.surface, q);
        let st = case.row(&format!("{} {precision}", self.def.name));
        judge_one(st, self, q, &got, oracle, amb_eps, tol);
    }
}

/// Judges one trace of `j`'s method against the oracle of the same ray; updates `st`.
fn judge_one<R: Real>(
    st: &mut Stat,
    j: Judging,
    q: &Query<R>,
    got: &Trace<R>,
    oracle: &Trace<f64>,
    amb_eps: f64,
    tol: impl Fn([f64; 3]) -> f64,
) {
    let Judging {
        def,
        hf,
        surface,
        bound,
        ..
    } = j;
    st.tried += 1;
    let f = u64::from(got.fetches);
    st.fetch_ratio = st.fetch_ratio.max(f as f64 / bound as f64);
    if f > bound || (def.exact() && got.flags.contains(Flags::BUDGET_EXHAUSTED)) {
        st.over_budget += 1;
        st.note(format!("fetches {f} > bound {bound} or budget flag: {q:?}"));
    }
    if got.hit.is_some() {
        st.hits += 1;
    }
    if oracle.clearance < amb_eps {
        st.ambiguous += 1;
        return;
    }
    let q64 = q.cast::<f64>();
    let d = q64.dir();
    let dlen = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let (differs, err) = match (oracle.hit, got.hit) {
        (None, None) => (false, None),
        (Some(o), Some(g)) => {
            let (po, pg) = (p64::<f64>(o.point), p64::<R>(g.point));
            let e = dist(po, pg);
            (e > tol(po), Some(e))
        }
        _ => (true, None),
    };
    if let Some(e) = err {
        st.err_n += 1;
        st.err_sum += e;
        st.err_max = st.err_max.max(e);
    }
    let t_tol = |p: [f64; 3]| tol(p) / dlen;
    match def.bound {
        Bound::Exact => {
            if differs {
                st.wrong += 1;
                st.note(format!(
                    "{surface:?} {q:?}: got {:?}, oracle {:?}",
                    got.hit.map(|h| p64::<R>(h.point)),
                    oracle.hit.map(|h| p64::<f64>(h.point))
                ));
            }
        }
        b => {
            st.wrong += u64::from(differs);
            let ok = match (b, oracle.hit, got.hit) {
                (Bound::Search(n), o, Some(g)) => {
                    let span = dda::clip_surface(hf, surface, &q64).map(|s| s.t1 - s.t0);
                    let step = span.unwrap_or(0.0) / f64::from(n);
                    o.is_some_and(|o| o.t <= g.t.to_f64() + step + t_tol(p64::<f64>(o.point)))
                }
                (Bound::Conservative, Some(o), g) => {
                    g.is_some_and(|g| g.t.to_f64() <= o.t + t_tol(p64::<f64>(o.point)))
                }
                (Bound::RealPoint, o, Some(g)) => {
                    o.is_some_and(|o| o.t <= g.t.to_f64() + t_tol(p64::<f64>(o.point)))
                }
                (Bound::Capped, o, g) => {
                    if got.flags.contains(Flags::BUDGET_EXHAUSTED) {
                        match (o, g) {
                            (Some(o), g) => {
                                g.is_some_and(|g| g.t.to_f64() <= o.t + t_tol(p64::<f64>(o.point)))
                            }
                            (None, _) => true,
                        }
                    } else {
                        !differs
                    }
                }
                _ => true,
            };
            if !ok {
                st.bound_broken += 1;
                st.note(format!(
                    "{surface:?} {q:?}: got {:?}, oracle {:?}",
                    got.hit.map(|h| (h.t, p64::<R>(h.point))),
                    oracle.hit.map(|h| (h.t, p64::<f64>(h.point)))
                ));
            }
        }
    }
}

/// Runs every method on `spec` over `field`: the `f32` ray (every method) against the
/// oracle of that very ray, and the `f64` ray (exact methods) against the `f64` oracle.
fn trace_all(case: &mut Case, field: &Field, baked: &Baked, surface: Surface, spec: &RaySpec) {
    let hf = field.hf();
    let zs = field.z_scale();
    let q32 = spec.q32();
    let q64 = spec.q64();
    let oracle32 = dda::trace(&hf, surface, &q32.cast::<f64>());
    let oracle64 = dda::trace(&hf, surface, &q64);
    let o64 = q64.origin();
    let (lo, hi) = field.range();
    let len_scale = 1f64
        .max(f64::from(field.w + field.h))
        .max(hi - lo)
        .max(o64.iter().fold(0f64, |m, v| m.max(v.abs())));
    let o32 = q32.cast::<f64>().origin();
    for def in defs() {
        if !def.supports(surface) || !baked.has(&def) {
            continue;
        }
        let j = Judging {
            def: &def,
            baked,
            hf: &hf,
            surface,
            bound: fetch_bound(&def, &hf, baked.levels),
        };
        j.judge(case, "f32", &q32, &oracle32, eps_f32(zs), |p| tol32(o32, p));
        if def.exact() && !matches!(def.kind, Kind::Dda) {
            j.judge(case, "f64", &q64, &oracle64, TOL64 * zs, |_| {
                TOL64 * len_scale
            });
        }
    }
}

/// Runs a case: every ray `rays` draws (from one generator seeded with `seed`) on
/// every surface given; brute force checks the oracle
/// itself (every ray on small fields, the first 8 per field and surface on large ones;
/// the `f64` ray, and the `f32` ray at docs/DESIGN.md's 1e-3
/// unless `far`: heights or origins so large that `f32` coordinates are coarser than
/// that, where the `f32` traces are judged against the oracle with the documented
/// bound instead).
fn run_case(
    name: &str,
    far: bool,
    fields: &[Field],
    surfaces: &[Surface],
    seed: u64,
    mut rays: impl FnMut(&mut Rng, &Field, Surface) -> Vec<RaySpec>,
) -> Case {
    let mut rng = Rng::new(seed);
    let mut case = Case::new(name);
    for field in fields {
        let baked = Baked::new(&field.hf());
        // Brute force is O(cells) per ray: every ray on small fields, a few on big ones.
        let small = u64::from(field.w) * u64::from(field.h) <= 4096;
        for &surface in surfaces {
            for (k, spec) in rays(&mut rng, field, surface).iter().enumerate() {
                trace_all(&mut case, field, &baked, surface, spec);
                if small || k < 8 {
                    case.brute_used = true;
                    case.brute.add(field, surface, &spec.q64());
                    if !far {
                        case.brute.add(field, surface, &spec.q32());
                    }
                }
            }
        }
    }
    case
}

/// Prints the cases and asserts there is no failure.
fn finish(cases: &[Case]) {
    let mut out = String::new();
    let mut failures = 0;
    for c in cases {
        out.push_str(&c.print());
        failures += c.failures();
    }
    println!("{out}");
    assert_eq!(
        failures, 0,
        "wrong rays of exact methods, budgets or bounds broken"
    );
}

const CONTINUOUS: [Surface; 2] = [Surface::Triangles, Surface::Bilinear];

// ---------------------------------------------------------------------------------
// Fields and rays
// ---------------------------------------------------------------------------------

/// Flat ground at 0 with single-sample needles at `top` (one sample in `every`).
fn needles(rng: &mut Rng, w: u32, h: u32, top: f32, every: usize) -> Field {
    Field::from_fn(w, h, w as usize, |_, _| {
        if rng.below(every) == 0 {
            top
        } else {
            0.0
        }
    })
}

/// Flat ground at 0 crossed by 1-texel walls at `top` (every 8th column and 6th row).
fn walls(w: u32, h: u32, top: f32) -> Field {
    Field::from_fn(w, h, w as usize + 1, |i, j| {
        if i % 8 == 4 || j % 6 == 3 {
            top
        } else {
            0.0
        }
    })
}

/// Long rays from beyond one end of `f` to the other (nearly horizontal, 60), then
/// grazing ones and random ones going down, along x and from outside.
fn end_to_end(r: &mut Rng, f: &Field, s: Surface) -> Vec<RaySpec> {
    let (xm, ym) = f.far_corner();
    let (lo, hi) = f.range();
    let mut v: Vec<RaySpec> = (0..60)
        .map(|k| {
            let back = k % 2 == 1;
            let x0 = if back {
                xm + r.range(0.5, 50.0)
            } else {
                -r.range(0.5, 50.0)
            };
            let y0 = r.range(0.0, ym);
            let y1 = r.range(0.0, ym);
            let x1 = if back { 0.0 } else { xm };
            let z0 = r.range(lo, hi + 1.0);
            let z1 = r.range(lo - 0.5, hi + 0.5);
            let d = [x1 - x0, y1 - y0, z1 - z0].map(|c| c / (x1 - x0).abs());
            RaySpec::whole([x0, y0, z0], d)
        })
        .collect();
    v.extend(grazing(r, f, s, 20, 1e-4));
    v.extend(of_kinds(
        r,
        f,
        s,
        &[RayKind::Down, RayKind::AxisX, RayKind::Outside],
        10,
    ));
    v
}

/// Rays from 1e5 texels away from `f` (on every side, and above) aimed at random
/// points of its box (80).
fn from_far(r: &mut Rng, f: &Field) -> Vec<RaySpec> {
    let (xm, ym) = f.far_corner();
    let (lo, hi) = f.range();
    (0..80)
        .map(|k| {
            let far = 1e5 * r.range(1.0, 1.3);
            let o = match k % 5 {
                0 => [-far, r.range(0.0, ym), r.range(lo, hi + 2e3)],
                1 => [xm + far, r.range(0.0, ym), r.range(lo, hi + 2e3)],
                2 => [r.range(0.0, xm), -far, r.range(lo, hi + 2e3)],
                3 => [far, far, hi + r.range(0.0, far)],
                _ => [r.range(0.0, xm), r.range(0.0, ym), far],
            };
            let p = [r.range(0.0, xm), r.range(0.0, ym), r.range(lo, hi)];
            RaySpec::whole(o, [p[0] - o[0], p[1] - o[1], p[2] - o[2]])
        })
        .collect()
}

/// The rays that cost most on `f`: corner-to-corner diagonals, nearly axis-parallel
/// rays across it (40), then grazing ones.
fn costly(r: &mut Rng, f: &Field, s: Surface) -> Vec<RaySpec> {
    let (xm, ym) = f.far_corner();
    let (lo, hi) = f.range();
    let mut v: Vec<RaySpec> = (0..40)
        .map(|k| {
            let z = if k % 2 == 0 {
                hi + 1e-3
            } else {
                r.range(lo, hi)
            };
            let (o, d) = match k % 4 {
                0 => ([-0.5, -0.5, z], [1.0, ym / xm, 0.0]),
                1 => ([xm + 0.5, -0.5, z], [-1.0, ym / xm, -1e-4]),
                2 => ([-1.0, r.range(0.0, ym), z], [1.0, 1e-3, 0.0]),
                _ => (
                    [r.range(0.0, xm), -1.0, z],
                    [r.range(-0.01, 0.01), 1.0, 1e-5],
                ),
            };
            RaySpec::whole(o, d)
        })
        .collect();
    v.extend(grazing(r, f, s, 20, 1e-4));
    v
}

// ---------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------

/// Grazing, axis-parallel, vertical, corner / centerline and under-the-surface rays
/// on a fractal field, needles and walls at full height, and a tilted plane.
#[test]
fn extreme_rays() {
    let mut rng = Rng::new(0xE7_0001);
    let fields = vec![
        fractal_field(&mut rng, 40, 30, 43, 6.0),
        needles(&mut rng, 33, 29, 20.0, 12),
        walls(31, 27, 20.0),
        Field::from_fn(25, 19, 25, |i, j| 0.25 * i as f32 + 0.125 * j as f32),
    ];
    type Gen = fn(&mut Rng, &Field, Surface) -> Vec<RaySpec>;
    let gens: [(&str, Gen); 5] = [
        ("grazing 1e-4 … 3e-2 rad", |r, f, s| {
            let mut v = grazing(r, f, s, 30, 1e-4);
            v.extend(grazing(r, f, s, 15, 1e-3));
            v.extend(of_kinds(r, f, s, &[RayKind::Grazing], 15));
            v
        }),
        ("axis-parallel, integer / half-integer", |r, f, s| {
            of_kinds(
                r,
                f,
                s,
                &[RayKind::AxisX, RayKind::AxisY, RayKind::Horizontal],
                15,
            )
        }),
        ("vertical, integer / half-integer xy", |r, f, s| {
            of_kinds(r, f, s, &[RayKind::VerticalInt, RayKind::VerticalHalf], 20)
        }),
        ("origin on a corner / centerline / diagonal", |r, f, s| {
            of_kinds(
                r,
                f,
                s,
                &[
                    RayKind::CornerOrigin,
                    RayKind::CenterlineOrigin,
                    RayKind::Diagonal,
                ],
                15,
            )
        }),
        ("origin under the surface", |r, f, s| {
            of_kinds(r, f, s, &[RayKind::Inside], 40)
        }),
    ];
    let mut cases = Vec::new();
    for (name, gen) in gens {
        let seed = name.len() as u64;
        cases.push(run_case(name, false, &fields, &CONTINUOUS, seed, gen));
    }
    finish(&cases);
}

/// Height ranges 1e-6 and 1e6, all-equal heights, 2 × 2, 2 × 4096 and 4096 × 2 fields,
/// needles and walls at full height over a large range.
#[test]
fn extreme_fields() {
    let mut rng = Rng::new(0xE7_0002);
    let all = [
        RayKind::Down,
        RayKind::Up,
        RayKind::Grazing,
        RayKind::AxisX,
        RayKind::VerticalHalf,
        RayKind::Inside,
        RayKind::CornerOrigin,
        RayKind::Outside,
    ];
    let tiny = Field::from_fn(9, 7, 9, |_, _| (rng.unit() * 1e-6) as f32);
    let huge = Field::from_fn(9, 7, 9, |_, _| (rng.unit() * 1e6) as f32);
    let flats: Vec<Field> = [0.0f32, -3.0, 2.5, 1e6]
        .iter()
        .map(|&v| Field::from_fn(7, 6, 8, move |_, _| v))
        .collect();
    let twos: Vec<Field> = (0..40)
        .map(|k| {
            Field::from_fn(2, 2, 2 + k % 3, |_, _| {
                if k % 2 == 0 {
                    rng.int(0, 2) as f32
                } else {
                    rng.range(-1.0, 1.0) as f32
                }
            })
        })
        .collect();
    let thin = vec![
        fractal_field(&mut rng, 2, 4096, 2, 3.0),
        fractal_field(&mut rng, 4096, 2, 4097, 3.0),
    ];
    let spiky = vec![needles(&mut rng, 48, 40, 5000.0, 40), walls(40, 36, 5000.0)];
    // (name, far, fields, seed of the rays, rays of each kind)
    let table: [(&str, bool, Vec<Field>, u64, usize); 6] = [
        ("height range 1e-6", false, vec![tiny], 7, 12),
        ("height range 1e6", true, vec![huge], 7, 12),
        ("all-equal heights (0, -3, 2.5, 1e6)", true, flats, 8, 6),
        ("2 x 2 fields", false, twos, 9, 2),
        ("2 x 4096 and 4096 x 2", false, thin, 10, 5),
        ("needles and walls 5000 high", true, spiky, 11, 8),
    ];
    let cases: Vec<Case> = table
        .into_iter()
        .map(|(name, far, fields, seed, n)| {
            run_case(name, far, &fields, &CONTINUOUS, seed, |r, f, s| {
                of_kinds(r, f, s, &all, n)
            })
        })
        .collect();
    finish(&cases);
}

/// Long rays across 8193 × 64 and 16384 × 16 fields: from beyond one end to the other,
/// nearly horizontal and grazing, plus random ones.
#[test]
fn long_rays() {
    let mut rng = Rng::new(0xE7_0003);
    let mut cases = Vec::new();
    for (w, h) in [(8193u32, 64u32), (16384, 16)] {
        let field = fractal_field(&mut rng, w, h, w as usize, 4.0);
        let name = format!("long rays across {w} x {h}");
        let surfaces = [Surface::Triangles];
        cases.push(run_case(
            &name,
            false,
            &[field],
            &surfaces,
            u64::from(w),
            end_to_end,
        ));
    }
    finish(&cases);
}

/// Origins 1e5 grid units from the field (on every side, and above): `f32` spacing
/// there is 2⁻⁷ ≈ 0.008, so `f32` traces cannot be within 1e-3 texel; they are held to
/// the documented bound `8 · eps32 · (|o|∞ + |p|∞)` (≈ 0.1 texel here) and their error
/// is printed. The `f64` paths are held to 1e-9 of the length scale, the DDA against
/// brute force too.
#[test]
fn far_origins() {
    let mut rng = Rng::new(0xE7_0004);
    let fields = vec![fractal_field(&mut rng, 48, 40, 48, 5.0), walls(33, 25, 8.0)];
    let case = run_case(
        "origins 1e5 away",
        true,
        &fields,
        &CONTINUOUS,
        12,
        |r, f, _| from_far(r, f),
    );
    let dda32 = &case.rows.iter().find(|r| r.0 == "dda f32").unwrap().2;
    println!(
        "far origins: f32 DDA hit error max {:.2e} texel (1e-3 is not reachable at 1e5: \
         f32 spacing there is 2^-7 = {:.1e})",
        dda32.err_max,
        f64::from(f32::EPSILON) * 65536.0
    );
    finish(&[case]);
}

/// NaN and infinities in heights, depth scales and rays are refused with a clear
/// error; finite heights and rays whose arithmetic overflows trace without a panic and
/// within the step bounds, and every method stops.
#[test]
fn non_finite_input() {
    let mut report = String::from("non-finite input\n");
    // Heights.
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut h = vec![1.0f32; 12];
        h[7] = bad;
        let e = HeightField::new(&h, 4, 3, 4).unwrap_err();
        assert_eq!(e, FieldError::NotFinite { index: 7 });
        report.push_str(&format!("  height {bad}: {e}\n"));
        let mut out = [0f32; 12];
        let e = HeightField::from_u16(&[1u16; 12], 4, 3, 4, bad, &mut out).unwrap_err();
        assert_eq!(e, FieldError::NotFinite { index: 0 });
        report.push_str(&format!("  depth scale {bad}: {e}\n"));
    }
    // Rays.
    type BadRay = ([f32; 3], [f32; 3], f32, f32, RayError);
    let cases: [BadRay; 6] = [
        (
            [f32::NAN, 0.0, 0.0],
            [0.0, 0.0, -1.0],
            0.0,
            1.0,
            RayError::OriginNotFinite,
        ),
        (
            [0.0, f32::INFINITY, 0.0],
            [0.0, 0.0, -1.0],
            0.0,
            1.0,
            RayError::OriginNotFinite,
        ),
        (
            [0.0; 3],
            [0.0, f32::NAN, -1.0],
            0.0,
            1.0,
            RayError::DirectionNotFinite,
        ),
        (
            [0.0; 3],
            [f32::NEG_INFINITY, 0.0, 0.0],
            0.0,
            1.0,
            RayError::DirectionNotFinite,
        ),
        (
            [0.0; 3],
            [0.0, 0.0, -1.0],
            f32::NAN,
            1.0,
            RayError::RangeNotFinite,
        ),
        (
            [0.0; 3],
            [0.0, 0.0, -1.0],
            0.0,
            f32::NAN,
            RayError::RangeNotFinite,
        ),
    ];
    for (o, d, a, b, want) in cases {
        let e = Query::from_arrays(o, d, a, b).unwrap_err();
        assert_eq!(e, want);
        report.push_str(&format!("  ray {o:?} {d:?} [{a}, {b}]: {e}\n"));
    }
    assert_eq!(
        Query::from_arrays([0f32; 3], [0.0; 3], 0.0, 1.0).unwrap_err(),
        RayError::ZeroDirection
    );
    assert!(Query::from_arrays([0f32; 3], [0.0, 0.0, 1.0], 0.0, f32::INFINITY).is_ok());

    // Finite heights whose sums overflow (±3.4e38), and huge, tiny and subnormal rays:
    // every method must return, within its fetch bound.
    let big = f32::MAX;
    let fields = vec![
        Field::from_fn(5, 4, 5, |i, j| if (i + j) % 2 == 0 { big } else { -big }),
        Field::from_fn(6, 3, 6, |i, _| if i == 2 { big } else { 0.0 }),
        Field::from_fn(4, 4, 4, |_, _| -big),
    ];
    let mut traced = 0;
    let mut hits = 0;
    for field in &fields {
        let hf = field.hf();
        let baked = Baked::new(&hf);
        for scale in [1e-40f32, 1e-20, 1.0, 1e20, 1e38] {
            for d in [
                [1.0f32, 0.3, -0.5],
                [0.0, 0.0, -1.0],
                [1.0, 0.0, 0.0],
                [-0.7, 1.0, 0.2],
            ] {
                for o in [
                    [2.0f32, 1.5, 10.0],
                    [-3.0, 1.0, 1e38],
                    [1.5, 1.5, -1e38],
                    [1e30, -1e30, 0.0],
                ] {
                    let Ok(q) = Query::from_arrays(o, d.map(|v| v * scale), 0.0, f32::INFINITY)
                    else {
                        continue;
                    };
                    for surface in CONTINUOUS {
                        for def in defs()
                            .iter()
                            .filter(|d| d.supports(surface) && baked.has(d))
                        {
                            let t = run(def, &baked, &hf, surface, &q);
                            let t64 = run(def, &baked, &hf, surface, &q.cast::<f64>());
                            let bound = fetch_bound(def, &hf, baked.levels);
                            assert!(
                                u64::from(t.fetches) <= bound && u64::from(t64.fetches) <= bound,
                                "{}: {} / {} fetches > {bound}",
                                def.name,
                                t.fetches,
                                t64.fetches
                            );
                            traced += 2;
                            hits += usize::from(t.hit.is_some()) + usize::from(t64.hit.is_some());
                        }
                    }
                }
            }
        }
    }
    report.push_str(&format!(
        "  overflowing heights (±3.4e38) and huge / subnormal rays: {traced} traces, \
         {hits} hits, every one within its fetch bound, none panicked\n"
    ));
    println!("{report}");
}

/// The stable quadratic (`smallest_root_in_unit`) against the textbook formula
/// `(−B − √(B² − 4AC)) / 2A`: with a small `A` the textbook root cancels
/// catastrophically; the stable one stays within a few ulps. Then through the
/// bilinear cell test: nearly flat twisted cells in `f32` against the `f64` oracle.
#[test]
fn quadratic_textbook_vs_stable() {
    fn textbook<R: Real>(a: R, b: R, c: R) -> R {
        (-b - (b * b - R::from_f32(4.0) * a * c).sqrt()) / (R::from_f32(2.0) * a)
    }
    let mut rng = Rng::new(0xE7_0005);
    let mut worst = [(0f64, 0f64); 2]; // (textbook, stable) relative errors: f32, f64
    for _ in 0..2000 {
        // Roots r (in [0.05, 0.95]) and R far away: A = k, B = −k (r + R), C = k r R.
        let r = rng.range(0.05, 0.95);
        let far = 10f64.powf(rng.range(3.0, 7.0));
        let k = 1.0 / far;
        let (a, b, c) = (k, -k * (r + far), k * r * far);
        // f64 reference: the exact small root is r (to f64 rounding of the coefficients).
        let r_ref = {
            let q = -0.5 * (b - (b * b - 4.0 * a * c).sqrt());
            c / q
        };
        let t32 = textbook(a as f32, b as f32, c as f32) as f64;
        let s32 = smallest_root_in_unit(a as f32, b as f32, c as f32).unwrap() as f64;
        let t64 = textbook(a, b, c);
        let s64 = smallest_root_in_unit(a, b, c).unwrap();
        // The f32 coefficients are rounded: compare with their exact root.
        let (a3, b3, c3) = (a as f32 as f64, b as f32 as f64, c as f32 as f64);
        let r32 = {
            let q = -0.5 * (b3 - (b3 * b3 - 4.0 * a3 * c3).sqrt());
            c3 / q
        };
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs();
        worst[0].0 = worst[0].0.max(rel(t32, r32));
        worst[0].1 = worst[0].1.max(rel(s32, r32));
        worst[1].0 = worst[1].0.max(rel(t64, r_ref));
        worst[1].1 = worst[1].1.max(rel(s64, r_ref));
    }
    println!(
        "small root, A = 1e-3 … 1e-7 (far root 1e3 … 1e7 away), 2000 quadratics:\n  \
         f32: textbook rel. error max {:.1e}, stable {:.1e}\n  \
         f64: textbook rel. error max {:.1e}, stable {:.1e}",
        worst[0].0, worst[0].1, worst[1].0, worst[1].1
    );
    assert!(worst[0].1 < 1e-6, "stable f32 root: {:.1e}", worst[0].1);
    assert!(worst[1].1 < 1e-14, "stable f64 root: {:.1e}", worst[1].1);
    assert!(
        worst[0].0 > 1e3 * worst[0].1,
        "the textbook formula should lose in f32"
    );
    assert!(
        worst[1].0 > 1e3 * worst[1].1,
        "the textbook formula should lose in f64"
    );

    // Nearly flat twisted bilinear cells (twist 1e-4 … 1e-7): diagonal rays make A tiny.
    let mut case = Case::new("bilinear cells with a tiny twist (A → 0)");
    for k in 0..6 {
        let e = 10f32.powi(-(k + 2));
        let field = Field::from_fn(9, 9, 9, |i, j| {
            0.3 * i as f32 + 0.2 * j as f32 + if (i + j) % 2 == 0 { e } else { 0.0 }
        });
        let baked = Baked::new(&field.hf());
        let mut r = Rng::new(k as u64);
        for spec in of_kinds(
            &mut r,
            &field,
            Surface::Bilinear,
            &[RayKind::Diagonal, RayKind::Down, RayKind::Grazing],
            30,
        ) {
            trace_all(&mut case, &field, &baked, Surface::Bilinear, &spec);
            case.brute_used = true;
            case.brute.add(&field, Surface::Bilinear, &spec.q32());
        }
    }
    finish(&[case]);
}

/// Ray–plane tests with nearly parallel rays: a field that is one exact plane
/// (`h = x/4 + y/8`), rays running along it at heights δ above and below, tilted by
/// ε towards it (hit far away, at a known place) or away from it. Also rays nearly
/// parallel to the box's top plane (`dz = ±1e-30 … ±1e-10`) against `dz = 0`.
#[test]
fn nearly_parallel_planes() {
    let field = Field::from_fn(257, 33, 257, |i, j| i as f32 / 4.0 + j as f32 / 8.0);
    let hf = field.hf();
    // No cone or QDM map here: this is already the suite's longest test, and their
    // bake on a tilted plane prunes little (extreme_rays traces them on a plane).
    let baked = Baked::with_limits(&hf, 0, RELAXED_MAX_SAMPLES);
    let mut case = Case::new("rays nearly parallel to a plane");
    let mut analytic = Stat::default();
    let mut rng = Rng::new(0xE7_0006);
    for _ in 0..120 {
        let (x, y) = (rng.range(0.0, 40.0), rng.range(0.0, 32.0));
        let delta = [1e-1, 1e-2, -1e-2][rng.below(3)];
        // Along the plane: d = (1, s, 1/4 + s/8) rises exactly as the plane does.
        let s = rng.range(-0.1, 0.1);
        let eps = [0.0, -1e-3, -1e-4, 1e-4][rng.below(4)];
        let d = [1.0, s, 0.25 + s / 8.0 + eps];
        let z = x / 4.0 + y / 8.0 + delta;
        let spec = RaySpec::whole([x, y, z], d);
        trace_all(&mut case, &field, &baked, Surface::Triangles, &spec);
        // Where the f32 ray meets the plane, in f64 from its own (rounded) numbers.
        let q = spec.q32().cast::<f64>();
        let (o, d) = (q.origin(), q.dir());
        let above = o[2] - (o[0] / 4.0 + o[1] / 8.0);
        let gap = d[2] - (d[0] / 4.0 + d[1] / 8.0);
        let t = -above / gap;
        let p = q.at(t);
        let inside = t >= 0.0 && (0.0..=256.0).contains(&p[0]) && (0.0..=32.0).contains(&p[1]);
        let expect = if above <= 0.0 {
            Some(o)
        } else {
            (inside && gap < 0.0).then_some(p)
        };
        let got = dda::trace(&hf, Surface::Triangles, &spec.q32());
        analytic.tried += 1;
        match (expect, got.hit) {
            (None, None) => {}
            (Some(e), Some(h)) => {
                let err = dist(e, p64::<f32>(h.point));
                analytic.err_max = analytic.err_max.max(err);
                // The hit is as good as the conditioning allows: an ulp of the heights
                // over the angle between ray and plane.
                let cond =
                    8.0 * f64::from(f32::EPSILON) * (1.0 + e[2].abs()) / gap.abs().max(1e-300);
                if err > WRONG.max(cond) {
                    analytic.wrong += 1;
                    analytic.note(format!("{spec:?}: {err:.2e} > {cond:.2e}"));
                }
            }
            (e, g) => {
                // Both near the edge of the footprint or the plane: ambiguous.
                if f64::from(got.clearance) >= eps_f32(field.z_scale()) {
                    analytic.wrong += 1;
                    analytic.note(format!("{spec:?}: expected {e:?}, got {g:?}"));
                } else {
                    analytic.ambiguous += 1;
                }
            }
        }
    }
    // Nearly parallel to the top plane of the box.
    let mut top = Case::new("rays nearly parallel to the box's top plane");
    let zmax = f64::from(hf.max_height());
    for dz in [0.0, 1e-30, -1e-30, 1e-20, -1e-20, 1e-10, -1e-10] {
        for z in [zmax + 1.0, zmax, zmax - 1e-3, zmax - 5.0, 3.0] {
            for (o, d) in [
                ([-5.0, 7.3, z], [1.0, 0.01, dz]),
                ([300.0, 2.5, z], [-1.0, 0.0, dz]),
            ] {
                let spec = RaySpec::whole(o, d);
                trace_all(&mut top, &field, &baked, Surface::Triangles, &spec);
            }
        }
    }
    println!(
        "nearly parallel rays vs the analytic plane hit (f32 DDA): tried {}  wrong {}  \
         ambiguous {}  err max {:.1e}",
        analytic.tried, analytic.wrong, analytic.ambiguous, analytic.err_max
    );
    for e in &analytic.examples {
        println!("    e.g. {e}");
    }
    assert_eq!(analytic.wrong, 0);
    finish(&[case, top]);
}

/// Drift over 10⁴ cells: a wall across a 16384 × 16 field at x = 12000.5 … 12001, met by
/// nearly horizontal rays from x < 0 after more than 10⁴ cells. The traversal recomputes
/// every crossing from integer cell indices, so its hit is as good after 12000 cells as
/// after one; a walk that adds `Δt` per cell in `f32` (shown for comparison) drifts.
#[test]
fn dda_drift_over_1e4_cells() {
    let field = Field::from_fn(16384, 16, 16384, |i, _| if i >= 12001 { 10.0 } else { 0.0 });
    let hf = field.hf();
    let baked = Baked::new(&hf);
    let mut case = Case::new("1e4 cells, then a ramp (exact far hit)");
    let mut rng = Rng::new(0xE7_0007);
    let mut worst = [0f64; 2]; // ours, accumulated
    let mut exact_cells = 0u64;
    for _ in 0..40 {
        let z = rng.range(0.5, 9.5);
        let (x0, y0) = (-rng.range(0.1, 30.0), rng.range(1.0, 14.0));
        // y stays inside the footprint up to the ramp.
        let dy = (rng.range(1.0, 14.0) - y0) / (12050.0 - x0);
        let spec = RaySpec::whole([x0, y0, z], [1.0, dy, 0.0]);
        trace_all(&mut case, &field, &baked, Surface::Triangles, &spec);
        let q = spec.q32();
        let q64 = q.cast::<f64>();
        // Triangles: between x = 12000 and 12001 the height rises 0 → 10 (flat in y).
        let x_hit = 12000.0 + q64.origin()[2] / 10.0;
        let t_hit = (x_hit - q64.origin()[0]) / q64.dir()[0];
        let p = q64.at(t_hit);
        let got = dda::trace(&hf, Surface::Triangles, &q);
        let h = got.hit.expect("the ramp is hit");
        worst[0] = worst[0].max(dist(p, p64::<f32>(h.point)));
        // Cells visited: every x and y centerline crossed from x = 0 to the hit, + 1.
        let y_at = |x: f64| q64.origin()[1] + (x - q64.origin()[0]) * q64.dir()[1];
        let cells = 12000 + 1 + (y_at(0.0).floor() - y_at(x_hit).floor()).abs() as u64;
        if u64::from(got.fetches) == 4 * cells {
            exact_cells += 1;
        }
        // The naive walk: t_next += Δt in f32, 12000 times.
        let (o, d) = (q.origin(), q.dir());
        let mut t = (0.0 - o[0]) / d[0];
        let dt = 1.0 / d[0];
        for _ in 0..12000 {
            t += dt;
        }
        let x_naive = o[0] + t * d[0];
        worst[1] = worst[1].max((f64::from(x_naive) - 12000.0).abs());
    }
    println!(
        "drift after 12000 cells: our f32 hit error max {:.1e} texel; an f32 walk adding Δt \
         per cell is {:.1e} texel off at x = 12000; cells visited exactly as counted on {} of 40 rays",
        worst[0], worst[1], exact_cells
    );
    assert!(worst[0] <= WRONG, "{}", worst[0]);
    assert_eq!(exact_cells, 40);
    finish(&[case]);
}

/// The fetch bounds on the rays that cost most: diagonal and grazing rays across
/// whole fields of needles and of a fractal, every method. (Every trace in this file
/// is checked against its bound; this case prints how close the worst come.)
#[test]
fn step_bounds() {
    let mut rng = Rng::new(0xE7_0008);
    let spikes = needles(&mut rng, 300, 200, 3.0, 50);
    let fractal = fractal_field(&mut rng, 257, 257, 257, 20.0);
    let name = "costly rays (diagonals, grazing, long)";
    finish(&[run_case(
        name,
        false,
        &[spikes, fractal],
        &CONTINUOUS,
        13,
        costly,
    )]);
}

/// The oracle's own ground: on a few random small fields with extreme ray kinds, the
/// `f64` and `f32` DDA agree with brute force over all cells.
#[test]
fn oracle_on_small_fields() {
    let mut rng = Rng::new(0xE7_0009);
    let mut j = Judged::new("small random fields: DDA vs brute force, extreme kinds");
    let kinds = [
        RayKind::Grazing,
        RayKind::VerticalHalf,
        RayKind::CornerOrigin,
        RayKind::Inside,
    ];
    for _ in 0..30 {
        let field = small_field(&mut rng);
        for surface in CONTINUOUS {
            for spec in kind_blocks(&mut rng, &field, surface, &kinds, 4) {
                j.add(&field, surface, &spec.q64());
                j.add(&field, surface, &spec.q32());
            }
        }
    }
    let mut out = String::new();
    j.report(&mut out);
    println!("{out}");
    assert_eq!(j.tally.wrong, 0);
}
