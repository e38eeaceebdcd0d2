//! Coherent batches (issue 21): a horizon shared by the rays of one eye starts each
//! ray's march near its hit. Checked here: no hit precedes a start (against the f64
//! oracle), the coherent batch answers every query with the per-ray march's hit bit for
//! bit (the DDA and the maximum mipmap, every surface, cameras outside, inside, over and
//! under the field), the test would see a start placed too late, and the skipping DDA
//! it marches with equals the DDA.
#![cfg(feature = "maxmip")]

mod common;

use common::{
    eps_f32, fractal_field, is_ambiguous, kind_blocks, march_fields, Field, RayKind, Rng,
};
use hfcast::camera::Pinhole;
use hfcast::horizon::{End, Horizon, Plan, Sighting, Start};
use hfcast::march::Marcher;
use hfcast::maxmip::{self, MaxMip, Options};
use hfcast::{dda, HeightField, Query, Real, Surface, Trace};

/// A camera's eye and look-at point, in fractions of the field's box (x, y across the
/// footprint, z from the lowest sample (0) to the highest (1)), its vertical field of
/// view and image size.
struct Shot {
    name: &'static str,
    eye: [f64; 3],
    at: [f64; 3],
    fov: f64,
    size: (u32, u32),
}

/// Cameras of every kind the horizon meets: outside the box at several elevations (a
/// telephoto grazing across the field among them), far away, over the footprint
/// looking down (every azimuth), inside the box among the peaks, and under the
/// surface.
const SHOTS: [Shot; 8] = [
    shot("45 deg outside", [-0.6, -0.5, 1.8], [0.5, 0.5, 0.3], 40.0),
    shot("5 deg outside", [1.9, -0.7, 1.15], [0.4, 0.6, 0.5], 30.0),
    shot(
        "telephoto grazing",
        [-1.5, 0.4, 0.95],
        [1.0, 0.55, 0.45],
        3.0,
    ),
    shot("far away", [60.0, 45.0, 30.0], [0.5, 0.5, 0.5], 2.0),
    shot(
        "over, looking down",
        [0.45, 0.55, 2.5],
        [0.5, 0.5, 0.0],
        120.0,
    ),
    shot("inside the box", [0.3, 0.4, 0.8], [0.9, 0.7, 0.2], 70.0),
    shot("level, inside", [0.7, 0.2, 0.6], [0.1, 0.9, 0.6], 60.0),
    shot("under the surface", [0.5, 0.5, -0.5], [0.9, 0.1, 0.5], 60.0),
];

/// A shot of 48 × 40 pixels.
const fn shot(name: &'static str, eye: [f64; 3], at: [f64; 3], fov: f64) -> Shot {
    Shot {
        name,
        eye,
        at,
        fov,
        size: (48, 40),
    }
}

impl Shot {
    /// The primary rays of the shot over `field`.
    fn rays(&self, field: &Field) -> Vec<Query<f32>> {
        let (w, h) = field.far_corner();
        let (lo, hi) = field.range();
        let at = |f: [f64; 3]| [f[0] * w, f[1] * h, lo + f[2] * (hi - lo).max(1.0)];
        let (eye, target) = (at(self.eye), at(self.at));
        let forward = [0, 1, 2].map(|k| target[k] - eye[k]);
        let cam = Pinhole::new(
            eye,
            forward,
            [0.0, 0.0, 1.0],
            self.fov,
            self.size.0,
            self.size.1,
        )
        .or_else(|_| {
            Pinhole::new(
                eye,
                forward,
                [0.0, 1.0, 0.0],
                self.fov,
                self.size.0,
                self.size.1,
            )
        })
        .expect("a camera");
        let (cw, ch) = self.size;
        (0..ch)
            .flat_map(|y| (0..cw).map(move |x| (x, y)))
            .map(|(x, y)| cam.ray(x, y, f32::INFINITY).expect("a ray"))
            .collect()
    }
}

/// The fields: the march fields of the other suites and two larger fractals (cameras
/// see many cells a ray there).
fn fields() -> Vec<(String, Field)> {
    let mut rng = Rng::new(0x40_12_20);
    let extra = vec![
        (
            "fractal 160x120".to_string(),
            fractal_field(&mut rng, 160, 120, 160, 16.0),
        ),
        (
            "fractal 97x211 steep".to_string(),
            fractal_field(&mut rng, 97, 211, 101, 60.0),
        ),
    ];
    march_fields(0x40_12, 5, ("checkerboard 16x16", 0.0, 2.0), extra, 3)
}

fn pyramid(hf: &HeightField) -> Vec<f32> {
    let mut p = vec![f32::NAN; maxmip::pyramid_len(hf.width(), hf.height())];
    maxmip::bake(hf, &mut p).expect("bake");
    p
}

/// The horizon of `rays` (all from one eye), sized for them.
fn horizon_of(hf: &HeightField, surface: Surface, rays: &[Query<f32>]) -> Horizon {
    let eye = rays[0].origin().map(f64::from);
    let dirs = rays.iter().map(|q| q.dir().map(f64::from));
    Horizon::sized(hf, surface, eye, dirs, rays.len(), u32::MAX)
        .expect("rays with a horizontal part")
}

/// The hit of a trace, bit for bit (`Debug` shows every bit of the floats).
fn hit_bits(t: &Trace<f32>) -> String {
    format!("{:?}", t.hit)
}

/// A span: its start, the clearance bound over what was skipped before it, its end.
type Span = (f32, f32, End<f32>);

/// The spans of `q` the horizon places, span after span as if none held a hit (each
/// cut where [`Horizon::cut_query`] lets a march from its start stop, then
/// [`Horizon::resume_query`] after each that goes on): each `(t, before, end)` (the
/// bound of the clearance over what was skipped before `t`), and the clearance bound
/// of the proved miss after the last, if any.
fn spans_of(horizon: &Horizon, q: &Query<f32>, first: Start<f32>) -> (Vec<Span>, Option<f32>) {
    let mut spans = Vec::new();
    let mut start = first;
    loop {
        match start {
            Start::Miss(c) => return (spans, Some(c)),
            Start::At(t, before, end) => {
                let end = match horizon.cut_query(q, t) {
                    Some((cut, _)) if cut.goes_on() && !end.goes_on() => cut,
                    _ => end,
                };
                assert!(
                    end.t > t || !end.goes_on(),
                    "{q:?}: a span from {t} to {end:?}"
                );
                spans.push((t, before, end));
                if !end.goes_on() {
                    return (spans, None);
                }
                start = horizon.resume_query(q, end).expect("a resume").0;
            }
        }
    }
}

/// The starts of `rays` ([`Horizon::start_aimed_query_ending`]): with `ENDS`, each
/// first span's end looked for at once.
fn starts_of<const ENDS: bool>(horizon: &Horizon, rays: &[Query<f32>]) -> Vec<Option<Start<f32>>> {
    let mut aims = Vec::new();
    horizon.aims(rays, &mut aims, None);
    let mut hint = 0;
    let starts = rays.iter().zip(aims).map(|(q, aim)| {
        let start = horizon.start_aimed_query_ending::<_, ENDS>(q, aim, &mut hint);
        start.map(|s| s.0)
    });
    starts.collect()
}

/// No ray meets the surface before its start, nor between a span's end and the next
/// start: the f64 oracle's hit is in a span (nor is there one when the horizon says the
/// ray misses, at first or after a span), and the clearance bounds of the parts skipped
/// hold, on every field, surface and camera, unless the oracle calls the ray ambiguous;
/// also where the first span's end is looked for at its start
/// ([`Horizon::ends_at_start`]), which some of the needles' shots do.
#[test]
fn no_hit_precedes_a_start() {
    let (mut starts, mut misses, mut advanced, mut resumed) = (0usize, 0usize, 0usize, 0usize);
    let (mut ended, mut ending) = (0usize, 0usize);
    for (name, field) in fields() {
        let hf = field.hf();
        let eps = eps_f32(field.z_scale());
        for surface in Surface::ALL {
            for shot in &SHOTS {
                let rays = shot.rays(&field);
                let horizon = horizon_of(&hf, surface, &rays);
                ending += usize::from(horizon.ends_at_start());
                // The rays, and the rays from a later `t_min` (their starts there),
                // with and without ends looked for at the starts.
                let later: Vec<Query<f32>> = rays
                    .iter()
                    .map(|q| q.within(q.t_min() + 0.25 * hf.width() as f32, q.t_max()))
                    .collect();
                let mut placed = Vec::new();
                for rays in [&rays, &later] {
                    let both = starts_of::<false>(&horizon, rays)
                        .into_iter()
                        .zip(starts_of::<true>(&horizon, rays));
                    let both = rays.iter().zip(both);
                    placed.extend(both.flat_map(|(q, (a, b))| [(q, a), (q, b)]));
                }
                for (q, start) in placed {
                    let Some(start) = start else {
                        continue;
                    };
                    if let Start::At(_, _, end) = start {
                        ended += usize::from(end.goes_on());
                    }
                    let oracle = dda::trace(&hf, surface, &q.cast::<f64>());
                    if is_ambiguous(&oracle, eps) {
                        continue;
                    }
                    let o = q.cast::<f64>();
                    // The oracle's clearance over `[a, b]`.
                    let over = |a: f64, b: f64| {
                        let part = Query::from_arrays(o.origin(), o.dir(), a, b).unwrap();
                        dda::trace(&hf, surface, &part).clearance
                    };
                    match start {
                        Start::At(t, before, _) => {
                            starts += 1;
                            advanced += usize::from(t > q.t_min());
                            if t > q.t_min() {
                                let c = over(o.t_min(), f64::from(t));
                                assert!(
                                    f64::from(before) <= c,
                                    "{name} {surface:?}: {before} over {c}"
                                );
                            }
                            let (spans, miss) = spans_of(&horizon, q, start);
                            resumed += spans.len() - 1;
                            // The parts skipped: before the first span, between spans,
                            // after the last one that goes on.
                            let mut gaps = vec![(f64::from(q.t_min()), f64::from(t))];
                            for w in spans.windows(2) {
                                let (from, to) = (f64::from(w[0].2.t), f64::from(w[1].0));
                                gaps.push((from, to));
                                let c = over(from, to);
                                assert!(
                                    f64::from(w[1].1) <= c,
                                    "{name} {surface:?}: {} over {c} between spans",
                                    w[1].1
                                );
                            }
                            if let Some(c) = miss {
                                let last = f64::from(spans[spans.len() - 1].2.t);
                                gaps.push((last, f64::from(q.t_max())));
                                let over_rest = over(last, f64::from(q.t_max()));
                                assert!(f64::from(c) <= over_rest, "{name} {surface:?}");
                            }
                            if let Some(h) = oracle.hit {
                                for (a, b) in gaps {
                                    assert!(
                                        !(h.t >= a && h.t < b),
                                        "{name} {surface:?} {}: hit at {} skipped ({a}, {b})",
                                        shot.name,
                                        h.t
                                    );
                                }
                            }
                        }
                        Start::Miss(clearance) => {
                            misses += 1;
                            assert!(
                                oracle.hit.is_none(),
                                "{name} {surface:?} {}: a hit",
                                shot.name
                            );
                            assert!(
                                f64::from(clearance) <= oracle.clearance,
                                "{name} {surface:?}"
                            );
                        }
                    }
                }
            }
        }
    }
    println!(
        "{starts} starts ({advanced} past t_min, {resumed} spans resumed, {ended} ended at \
         once) and {misses} proved misses checked; {ending} horizons end spans at starts"
    );
    assert!(
        advanced > starts / 4 && misses > 1000 && resumed > 1000 && ended > 1000,
        "the horizon must place rays, resume spans and end them"
    );
    assert!(ending > 0, "some shot must end its spans at the starts");
}

/// The coherent batch ([`Marcher::trace_all_with`]) answers every query with the
/// per-ray march's hit bit for bit, for the DDA and the maximum mipmap, on every field,
/// surface and camera (spans ended at their starts on some, [`Horizon::ends_at_start`]),
/// and reads fewer texels doing so on the larger fields.
#[test]
fn coherent_hits_equal_the_per_ray_march() {
    let (mut compared, mut saved, mut ending) = (0usize, 0i64, 0usize);
    for (name, field) in fields() {
        let hf = field.hf();
        let pyramid = pyramid(&hf);
        let mip = MaxMip::new(&hf, &pyramid).expect("pyramid");
        for surface in Surface::ALL {
            let marchers = [
                Marcher::Exact(surface),
                Marcher::MaxMip(mip, surface, Options::default()),
            ];
            for m in &marchers {
                for shot in &SHOTS {
                    let shot_rays = shot.rays(&field);
                    let horizon = horizon_of(&hf, surface, &shot_rays);
                    ending += usize::from(horizon.ends_at_start());
                    // Also from a later `t_min` (the starts clamped there).
                    let mut rays = shot_rays.clone();
                    rays.extend(
                        shot_rays
                            .iter()
                            .map(|q| q.within(q.t_min() + 0.25 * hf.width() as f32, q.t_max())),
                    );
                    let mut got = vec![Trace::MISS; rays.len()];
                    m.trace_all_with(&hf, Some(&horizon), &rays, &mut got, hfcast::detect_avx2!());
                    for (q, g) in rays.iter().zip(&got) {
                        let want = m.trace(&hf, q);
                        let exact = dda::trace(&hf, surface, q);
                        assert_eq!(
                            hit_bits(g),
                            hit_bits(&want),
                            "{name} {surface:?} {:?} {}: {q:?}",
                            m.kind(),
                            shot.name
                        );
                        // A lower bound, to the rounding of the skipped cells' bound.
                        let slack = 1e-5 * (1.0 + exact.clearance.abs());
                        assert!(
                            g.clearance <= exact.clearance + slack,
                            "{name} {surface:?} {} {:?}: {g:?} {exact:?}",
                            shot.name,
                            m.kind()
                        );
                        if let Marcher::Exact(_) = m {
                            saved += i64::from(want.fetches) - i64::from(g.fetches);
                        }
                    }
                    compared += rays.len();
                }
            }
        }
    }
    println!(
        "{compared} coherent answers equal the per-ray march; the DDA read {saved} fewer texels"
    );
    assert!(compared > 100_000 && saved > 0 && ending > 0);
}

/// A batch's aims in AVX-512 lanes ([`Horizon::aims`] with the token) are the scalar
/// aims, on every shot's rays (the one looking down from over the field meets every
/// azimuth: rays behind the group's axis and on both sides of it) mixed with rays the
/// horizon says nothing of (another origin by an ulp, vertical, reversed, any
/// direction), in batches of every length around the lanes' group of sixteen.
#[test]
fn aims_in_lanes_are_the_scalar_aims() {
    let Some(avx512) = hfcast::detect_avx2!().and_then(|t| t.avx512()) else {
        println!("no AVX-512 on this CPU: the lanes do not run");
        return;
    };
    let (mut rng, mut compared) = (Rng::new(0xa1_35), 0usize);
    for (name, field) in fields() {
        let hf = field.hf();
        for shot in &SHOTS {
            let rays = shot.rays(&field);
            let horizon = horizon_of(&hf, Surface::Triangles, &rays);
            let mut queries = rays.clone();
            for q in rays.iter().step_by(5) {
                let (o, d) = (q.origin(), q.dir());
                let any = [0; 3].map(|_| rng.range(-1.0, 1.0) as f32);
                for (o, d) in [
                    ([o[0].next_up(), o[1], o[2]], d),
                    (o, [0.0, 0.0, -1.0]),
                    (o, [-d[0], -d[1], d[2]]),
                    (o, any),
                ] {
                    if let Ok(q) = Query::from_arrays(o, d, 0.0, f32::INFINITY) {
                        queries.push(q);
                    }
                }
            }
            for k in (1..queries.len()).rev() {
                queries.swap(k, rng.below(k + 1));
            }
            let n = queries.len();
            for len in [n, n - 1, n - 15, 33, 17, 16, 15, 1, 0] {
                let batch = &queries[..len];
                let (mut laned, mut scalar) = (Vec::new(), Vec::new());
                horizon.aims(batch, &mut laned, Some(avx512));
                horizon.aims(batch, &mut scalar, None);
                assert_eq!(laned, scalar, "{name} {}: {len} rays", shot.name);
                compared += len;
            }
        }
    }
    println!("{compared} aims in lanes equal the scalar aims");
    assert!(compared > 100_000);
}

/// A batch from one eye larger than [`hfcast::horizon::MIN_GROUP`] shares a horizon by
/// itself ([`Marcher::trace_all`]), with the same hits as one ray after another; and the
/// equality checks above would see a start placed too late (two bands further, some
/// ray's hit changes).
#[test]
fn batches_share_a_horizon_and_a_late_start_is_seen() {
    let mut rng = Rng::new(0x40_13);
    let field = fractal_field(&mut rng, 300, 260, 300, 30.0);
    let hf = field.hf();
    let shot = Shot {
        size: (64, 48),
        ..SHOTS[1]
    };
    let rays = shot.rays(&field);
    assert!(rays.len() >= hfcast::horizon::MIN_GROUP);
    let m = Marcher::Exact(Surface::Triangles);
    let mut got = vec![Trace::MISS; rays.len()];
    m.trace_all(&hf, &rays, &mut got, None);
    let mut plain = vec![Trace::MISS; rays.len()];
    m.trace_each(&hf, &rays, &mut plain, None);
    let fetched = |v: &[Trace<f32>]| v.iter().map(|t| u64::from(t.fetches)).sum::<u64>();
    for (g, p) in got.iter().zip(&plain) {
        assert_eq!(hit_bits(g), hit_bits(p));
    }
    println!(
        "fetches: {} per ray one by one, {} sharing a horizon",
        fetched(&plain) / rays.len() as u64,
        fetched(&got) / rays.len() as u64
    );
    assert!(
        fetched(&got) * 2 < fetched(&plain),
        "the horizon must save fetches"
    );

    // Two bands later than the start: some hit is lost, so the equality checks above
    // see a start placed past a hit.
    let horizon = horizon_of(&hf, Surface::Triangles, &rays);
    let late = 2.0 * horizon.band_width() as f32;
    let mut hint = 0;
    let late = rays
        .iter()
        .zip(&plain)
        .filter(|(q, p)| {
            let Some((Start::At(t, _, _), _)) = horizon.start_query(q, &mut hint) else {
                return false;
            };
            let d = q.dir();
            let t = (t + late / d[0].hypot(d[1])).min(q.t_max());
            hit_bits(&dda::trace_skipping(
                &hf,
                Surface::Triangles,
                &q.starting_at(t),
            )) != hit_bits(p)
        })
        .count();
    println!(
        "{late} of {} rays change their hit when started two bands late",
        rays.len()
    );
    assert!(late >= 10, "a late start must change some hit");
}

/// A horizon whose passes over the field are cut into parts (as threads share them)
/// is the one pass's: every ray of every field, surface and camera gets the same start.
#[test]
fn a_pass_in_parts_is_the_whole_pass() {
    let (mut compared, mut refined) = (0usize, 0usize);
    for (name, field) in fields() {
        let hf = field.hf();
        for surface in Surface::ALL {
            for shot in &SHOTS {
                let rays = shot.rays(&field);
                let eye = rays[0].origin().map(f64::from);
                let dirs = rays.iter().map(|q| q.dir().map(f64::from));
                let plan = Plan::sized(&hf, surface, eye, dirs, rays.len(), u32::MAX)
                    .expect("rays with a horizontal part");
                // Each pass in parts, as a batch's threads share it (capi's
                // `build_horizon`): the first, and the finer one it may call for.
                let in_parts = |plan: Plan| {
                    let rows = plan.block_rows();
                    let cuts = [0, 1, rows / 3, rows / 2, rows];
                    plan.finish(cuts.windows(2).map(|c| plan.wedges(c[0]..c[1])))
                };
                refined += usize::from(plan.finer(&in_parts(plan)).is_some());
                let (split, whole) = (plan.build_by(in_parts), plan.build());
                let (mut a, mut b) = (0, 0);
                for q in &rays {
                    let (x, y) = (whole.start_query(q, &mut a), split.start_query(q, &mut b));
                    assert_eq!(x, y, "{name} {surface:?} {}: {q:?}", shot.name);
                    compared += usize::from(x.is_some());
                }
            }
        }
    }
    println!("{compared} starts compared, {refined} horizons built again finer");
    assert!(compared > 100_000 && refined > 0);
}

/// A batch sighted in parts (as `hf_trace_batch`'s threads sight it: consecutive
/// ranges, some empty, some rays from another origin) places the wedges as one pass
/// ([`Plan::for_batch`]): every ray of every field and camera gets the same start.
#[test]
fn a_batch_sighted_in_parts_is_the_whole_batch() {
    let mut compared = 0usize;
    for (name, field) in fields() {
        let hf = field.hf();
        for shot in &SHOTS {
            let shot = Shot {
                size: (64, 48),
                ..*shot
            };
            let mut lines: Vec<([f64; 3], [f64; 3])> = shot
                .rays(&field)
                .iter()
                .map(|q| (q.origin().map(f64::from), q.dir().map(f64::from)))
                .collect();
            // Every seventh ray from elsewhere: not the batch's eye, not sighted.
            for line in lines.iter_mut().skip(3).step_by(7) {
                line.0[2] += 1.0;
            }
            let (n, eye) = (lines.len(), lines[0].0);
            let surface = Surface::Triangles;
            let whole = Plan::for_batch(&hf, surface, lines.iter().copied(), u32::MAX);
            let cuts = [0, 1, n / 3, n / 3, n / 2 + 5, n];
            let parts = cuts.windows(2).map(|c| {
                let mut seen = Sighting::new(n);
                for (k, line) in lines.iter().enumerate().take(c[1]).skip(c[0]) {
                    if line.0 == eye {
                        seen.add(k, line.1);
                    }
                }
                seen
            });
            let split = Plan::for_sightings(&hf, surface, eye, parts, u32::MAX);
            let (whole, split) = (
                whole.expect("a batch from one eye").build(),
                split.expect("the same batch").build(),
            );
            let (mut a, mut b) = (0, 0);
            for (o, d) in &lines {
                let range = (0.0, f64::INFINITY);
                let (x, y) = (
                    whole.start(*o, *d, range, &mut a),
                    split.start(*o, *d, range, &mut b),
                );
                assert_eq!(x, y, "{name} {}: {o:?} {d:?}", shot.name);
                compared += usize::from(x.is_some());
            }
        }
    }
    println!("{compared} starts compared");
    assert!(compared > 50_000);
}

/// [`dda::trace_skipping`] answers `q` with [`dda::trace`]'s hit bit for bit, its
/// fetches and a clearance no larger (to the rounding of the cells' bound).
fn skips_as_the_dda<R: Real>(hf: &HeightField, surface: Surface, q: &Query<R>, name: &str) {
    let (a, b) = (
        dda::trace(hf, surface, q),
        dda::trace_skipping(hf, surface, q),
    );
    let same = format!("{:?}", a.hit) == format!("{:?}", b.hit);
    assert!(same, "{name} {surface:?} {q:?}: {a:?} {b:?}");
    let slack = R::from_f64(1e-5) * (R::ONE + a.clearance.abs());
    assert!(
        b.clearance <= a.clearance + slack && b.fetches == a.fetches,
        "{a:?} {b:?}"
    );
}

/// [`dda::trace_skipping`] is [`dda::trace`] hit for hit, bit for bit, on every march
/// field, surface and ray kind, its clearance a lower bound, in `f32` and `f64`.
#[test]
fn the_skipping_dda_is_the_dda() {
    let mut rng = Rng::new(0x5c1b);
    let mut n = 0;
    for (name, field) in fields() {
        let hf = field.hf();
        for surface in Surface::ALL {
            for spec in kind_blocks(&mut rng, &field, surface, &RayKind::ALL, 12) {
                skips_as_the_dda(&hf, surface, &spec.q32(), &name);
                skips_as_the_dda(&hf, surface, &spec.q64(), &name);
                n += 2;
            }
        }
    }
    println!("{n} traces compared");
    assert!(n > 5000);
}

/// [`dda::trace_skipping_lanes`] answers each query with [`dda::trace_skipping_for`]'s
/// answer bit for bit (the hit, fetches and clearance, or the restart), on every field,
/// surface (only the triangle surface has lanes) and ray kind, for the cameras' rays
/// from their horizons' starts to where the horizon may cut them (the coherent batches'
/// march) and from their own `t_min`, with budgets from none to unlimited; fewer
/// queries than lanes and more; with the SIMD token and without.
#[test]
fn the_laned_dda_is_the_skipping_dda() {
    let mut rng = Rng::new(0x1a_2e5);
    let (mut compared, mut hits) = (0usize, 0usize);
    for (name, field) in fields() {
        let hf = field.hf();
        for surface in Surface::ALL {
            let mut sets: Vec<(String, Vec<Query<f32>>)> = Vec::new();
            for shot in &SHOTS {
                let rays = shot.rays(&field);
                let horizon = horizon_of(&hf, surface, &rays);
                let mut hint = 0;
                let started = rays
                    .iter()
                    .filter_map(|q| match horizon.start_query(q, &mut hint)?.0 {
                        // Cut where the horizon lets a walk from the start stop.
                        Start::At(t, _, _) => Some(q.within(t, horizon.cut_query(q, t)?.0.t)),
                        Start::Miss(_) => None,
                    })
                    .collect();
                sets.push((format!("{} over the first spans", shot.name), started));
                sets.push((shot.name.to_string(), rays));
            }
            let kinds = kind_blocks(&mut rng, &field, surface, &RayKind::ALL, 9);
            sets.push(("ray kinds".into(), kinds.iter().map(|s| s.q32()).collect()));
            for (set, queries) in &sets {
                for budget in [u32::MAX, 0, 3, 16] {
                    for n in [queries.len().min(3), queries.len()] {
                        let queries = &queries[..n];
                        let want: Vec<String> = queries
                            .iter()
                            .map(|q| {
                                format!("{:?}", dda::trace_skipping_for(&hf, surface, q, budget))
                            })
                            .collect();
                        for simd in [hfcast::detect_avx2!().and_then(|s| s.avx512()), None] {
                            let mut got = vec![Ok(Trace::MISS); n];
                            dda::trace_skipping_lanes(
                                &hf, surface, queries, budget, &mut got, simd,
                            );
                            for ((g, w), q) in got.iter().zip(&want).zip(queries) {
                                assert_eq!(
                                    &format!("{g:?}"),
                                    w,
                                    "{name} {surface:?} {set}, budget {budget}, {simd:?}: {q:?}"
                                );
                                hits += usize::from(matches!(g, Ok(t) if t.hit.is_some()));
                            }
                            compared += n;
                        }
                    }
                }
            }
        }
    }
    println!(
        "laned DDA ({:?}): {compared} answers equal the scalar walk's, {hits} of them hits",
        hfcast::detect_avx2!().and_then(|s| s.avx512())
    );
    assert!(compared > 500_000 && hits > 100_000);
}
