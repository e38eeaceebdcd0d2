//! Safety radius and robust binary search: the exact variant gives zero wrong rays
//! against the `f64` exact traversal (f32 and f64, every ray kind, grazing and upward
//! rays) and never stands past the oracle's hit; an independent brute-force check of
//! the bake (shown to fail on a bake inflated by one); row-range bakes, the relation to
//! the isotropic safety distance; and the approximate variants (zero radius clamped to
//! one, error-tolerant radii) measured, with their error bounds asserted.
#![cfg(feature = "safety")]

mod common;

use common::{
    assert_rows_rebake, breakpoints, check_bakes, class_axis, eps_f32, is_touch, march_fields,
    rays_with_grazing, rows_field, Field, Probe, RaySpec, Rng,
};
use hfcast::radius::{self, BakeOptions, Options, RadiusMap, Zero};
use hfcast::safety::{self, Variant, CLASSES};
use hfcast::{dda, Query, Real, Surface, Trace};

const TRI: Surface = Surface::Triangles;

/// The error tolerances (grid units) measured.
const TOLERANCES: [f32; 4] = [0.25, 0.5, 1.0, 2.0];

/// Synthetic fields: fractal, 1-texel walls, needles, checkerboard max/min, small ones;
/// smooth and convex, then flat-topped: large radii, long jumps.
fn fields() -> Vec<(String, Field)> {
    let dome = Field::from_fn(50, 44, 50, |i, j| {
        let (x, y) = (f64::from(i) - 24.5, f64::from(j) - 21.5);
        (12.0 - (x * x + y * y) / 60.0) as f32
    });
    let checker = ("checkerboard max/min 24x20", 5.0, -1.0);
    march_fields(0x4ad1, 11, checker, vec![("dome 50x44".into(), dome)], 8)
}

fn bake(field: &Field, opts: BakeOptions) -> Vec<u8> {
    let hf = field.hf();
    let mut scratch = vec![0f32; radius::scratch_len(field.w, field.h)];
    let mut out = vec![0u8; radius::map_len(field.w, field.h)];
    radius::bake(&hf, &mut scratch, opts, &mut out).unwrap();
    out
}

fn tolerant(e: f32) -> BakeOptions {
    BakeOptions {
        tolerance: e,
        ..BakeOptions::default()
    }
}

/// Rays of every kind and class, plus grazing rays (down and up) just above the surface.
fn rays(field: &Field, rng: &mut Rng, per_kind: usize) -> Vec<RaySpec> {
    rays_with_grazing(field, TRI, rng, per_kind)
}

/// Surface clearance of the ray at `t`.
fn clearance(field: &Field, q: &Query<f64>, t: f64) -> f64 {
    common::clearance(field, TRI, q, t)
}

/// How often `clearance + offset` changes sign on `[0, t_end]` (values within `tol`
/// of zero count as neither sign): exact, from the breakpoints.
fn crossings(field: &Field, q: &Query<f64>, t_end: f64, offset: f64, tol: f64) -> u32 {
    let mut sign = 0i8;
    let mut n = 0;
    for t in breakpoints(q, 0.0, t_end) {
        let c = clearance(field, q, t) + offset;
        let s = if c > tol {
            1
        } else if c < -tol {
            -1
        } else {
            0
        };
        if s != 0 && sign != 0 && s != sign {
            n += 1;
        }
        if s != 0 {
            sign = s;
        }
    }
    n
}

/// The ray's span over the footprint (`None` if it never overlaps it).
fn footprint_span(field: &Field, q: &Query<f64>) -> Option<(f64, f64)> {
    let (o, d) = (q.origin(), q.dir());
    let (mut a, mut b) = (q.t_min(), q.t_max());
    for (k, lim) in [(field.w - 1) as f64, (field.h - 1) as f64]
        .into_iter()
        .enumerate()
    {
        if d[k] == 0.0 {
            if o[k] < 0.0 || o[k] > lim {
                return None;
            }
        } else {
            let (p, r) = (-o[k] / d[k], (lim - o[k]) / d[k]);
            a = a.max(p.min(r));
            b = b.min(p.max(r));
        }
    }
    (a <= b && b.is_finite()).then_some((a, b))
}

/// Deepest the ray goes under the surface on `[t0, t1]` (exact, from the breakpoints).
fn max_depth(field: &Field, q: &Query<f64>, t0: f64, t1: f64) -> f64 {
    breakpoints(q, t0, t1)
        .into_iter()
        .map(|t| -clearance(field, q, t))
        .fold(0.0, f64::max)
}

/// Main-axis length of the stretch under the surface that starts at `t_hit`: from
/// `t_hit` to where the ray comes back above (or leaves the footprint).
fn chord_main(field: &Field, q: &Query<f64>, t_hit: f64, t_end: f64) -> f64 {
    let d = q.dir();
    let dm = d[0].abs().max(d[1].abs());
    let ts = breakpoints(q, t_hit, t_end);
    let mut prev = (t_hit, clearance(field, q, t_hit).min(0.0));
    for &t in &ts[1..] {
        let c = clearance(field, q, t);
        if c > 0.0 {
            let exit = prev.0 + (t - prev.0) * (-prev.1) / (c - prev.1);
            return (exit - t_hit) * dm;
        }
        prev = (t, c);
    }
    (t_end - t_hit) * dm
}

/// How a traced ray compares with the oracle.
enum Verdict {
    Ambiguous,
    Right,
    Wrong,
}

/// Judges one ray as docs/DESIGN.md says: hit/miss and position (1e-3 texel) against the
/// f64 exact traversal; grazing rays and touches are ambiguous.
fn judge<R: Real>(field: &Field, got: &Trace<R>, q: &Query<R>, oracle: &Trace<f64>) -> Verdict {
    let eps = eps_f32(field.z_scale());
    if oracle.clearance < eps {
        return Verdict::Ambiguous;
    }
    let right = match (oracle.hit, got.hit) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            common::dist(a.point.to_array(), common::p64::<R>(b.point)) <= 1e-3
                && a.flags == b.flags
        }
        _ => false,
    };
    if right {
        return Verdict::Right;
    }
    match oracle.hit {
        Some(hit) if is_touch(field, TRI, &q.cast(), hit.t, eps) => Verdict::Ambiguous,
        _ => Verdict::Wrong,
    }
}

#[test]
fn exact_zero_wrong_and_conservative() {
    let mut rng = Rng::new(42);
    let (mut wrong, mut overshoot, mut tried, mut steps) = (0u64, 0u64, 0u64, 0u64);
    for (name, field) in fields() {
        let hf = field.hf();
        let data = bake(&field, BakeOptions::default());
        let map = RadiusMap::new(&hf, &data).unwrap();
        let per_kind = if field.w * field.h > 200 { 160 } else { 40 };
        let specs = rays(&field, &mut rng, per_kind);
        let (mut w, mut amb, mut over) = (0, 0, 0);
        for s in &specs {
            let oracle = dda::trace(&hf, TRI, &s.q64());
            // Where the oracle hits, for the conservative check.
            let limit = oracle.hit.map(|h| {
                let d = s.d;
                h.t + 1e-4 / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
            });
            let ambiguous = oracle.clearance < eps_f32(field.z_scale());
            let mut check = |q32: bool| {
                let mut ts: Vec<f64> = Vec::new();
                let (verdict, desc) = if q32 {
                    let q = s.q32();
                    let got = radius::trace_steps(&map, &hf, &q, &Options::default(), &mut |t| {
                        ts.push(f64::from(t))
                    });
                    (judge(&field, &got, &q, &oracle), format!("{:?}", got.hit))
                } else {
                    let q = s.q64();
                    let got = radius::trace_steps(&map, &hf, &q, &Options::default(), &mut |t| {
                        ts.push(t)
                    });
                    (judge(&field, &got, &q, &oracle), format!("{:?}", got.hit))
                };
                steps += ts.len() as u64;
                if let (Some(lim), false) = (limit, ambiguous) {
                    if ts.iter().any(|&t| t > lim) {
                        over += 1;
                        println!(
                            "  overshoot {name} f32={q32}: {s:?} steps {ts:?} oracle {:?}",
                            oracle.hit
                        );
                    }
                }
                match verdict {
                    Verdict::Ambiguous => amb += 1,
                    Verdict::Right => {}
                    Verdict::Wrong => {
                        w += 1;
                        println!(
                            "  wrong {name} f32={q32}: {s:?} got {desc} oracle {:?}",
                            oracle.hit
                        );
                    }
                }
            };
            check(true);
            check(false);
        }
        let mean = data.iter().map(|&v| f64::from(v)).sum::<f64>() / data.len() as f64;
        println!(
            "{name:<36} rays {:>6} (f32 + f64)  wrong {w}  ambiguous {amb}  past the oracle \
             hit {over}  mean radius {mean:.2}",
            2 * specs.len()
        );
        tried += 2 * specs.len() as u64;
        wrong += w;
        overshoot += over;
    }
    println!("exact radius: {tried} rays, {wrong} wrong, {overshoot} standing past the hit, {steps} radius reads");
    assert_eq!(wrong, 0, "wrong rays");
    assert_eq!(overshoot, 0, "a step stood past the oracle's hit");
    assert!(steps > 10_000, "the march hardly ever read a radius");
}

/// For random texels and every class, dense rays from the segment above the texel,
/// rising or falling, aimed inside the square of radius `r + extra`, checked with the
/// exact piecewise-linear clearance: the ray (above the surface lowered by `e` at its
/// start) must cross that lowered surface at most once. Returns (rays, violations).
fn check_bake(field: &Field, data: &[u8], e: f64, extra: u32, rng: &mut Rng) -> (u64, u64) {
    let probe = Probe::new(field);
    let (w, h) = (field.w, field.h);
    let (mut tried, mut bad) = (0, 0);
    for _ in 0..200 {
        let (i, j) = (rng.below(w as usize) as u32, rng.below(h as usize) as u32);
        let r = u32::from(data[(j * w + i) as usize]);
        let k = r + extra;
        if k == 0 || r == 255 {
            continue;
        }
        for (ax, sg) in CLASSES.map(class_axis) {
            let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
            let lm = f64::from(if ax == 0 { w } else { h });
            let ln = f64::from(if ax == 0 { h } else { w });
            for q in 0..50 {
                let p = probe.start(rng, ax, [m, n], q);
                let y = p[1 - ax];
                let (dist, slope) = Probe::reach(rng, k, q);
                let mut tgt = [0.0; 3];
                tgt[ax] = f64::from(m) + sg * dist;
                tgt[1 - ax] = y + slope * dist;
                if tgt[1 - ax] < 0.0
                    || tgt[1 - ax] > ln - 1.0
                    || tgt[ax] < 0.0
                    || tgt[ax] > lm - 1.0
                {
                    continue;
                }
                // Mostly aimed at or under the surface ahead; every seventh rises.
                tgt[2] = if q % 7 == 0 {
                    p[2] + rng.range(0.0, 2.0) * dist
                } else {
                    TRI.height_at(&probe.hf, tgt[0], tgt[1]) - rng.range(-0.05, 0.5) * probe.relief
                };
                let dir = [tgt[0] - p[0], tgt[1] - p[1], tgt[2] - p[2]];
                let ray = Query::from_arrays(p, dir, 0.0, f64::INFINITY).unwrap();
                // Up to centerline m ± k, cut where the ray leaves the footprint.
                let mut t_end = f64::from(k) / dist;
                t_end = t_end.min(if sg > 0.0 { lm - 1.0 - p[ax] } else { p[ax] } / dist);
                if dir[1 - ax] != 0.0 {
                    let lim = if dir[1 - ax] > 0.0 { ln - 1.0 } else { 0.0 };
                    t_end = t_end.min((lim - y) / dir[1 - ax]);
                }
                if t_end <= 0.0 {
                    continue;
                }
                tried += 1;
                bad += u64::from(crossings(field, &ray, t_end, e, 1e-9 * probe.zs) > 1);
            }
        }
    }
    (tried, bad)
}

#[test]
fn bake_checked_independently() {
    check_bakes(9, fields(), |name, field, rng| {
        let mut inflated_bad = 0;
        for e in [0.0f32, 1.0] {
            let data = bake(field, tolerant(e));
            let (tried, bad) = check_bake(field, &data, f64::from(e), 0, rng);
            let (itried, ibad) = check_bake(field, &data, f64::from(e), 1, rng);
            println!(
                "{name:<36} e {e}: rays {tried:>6} crossing twice {bad}   (radius + 1: rays \
                 {itried:>6} crossing twice {ibad})"
            );
            assert_eq!(
                bad, 0,
                "{name} e {e}: a ray inside its radius crosses twice"
            );
            inflated_bad += ibad;
        }
        inflated_bad
    });
}

#[test]
fn rows_relation_and_monotone_tolerance() {
    let field = rows_field(3);
    let hf = field.hf();
    let mut scratch = vec![0f32; radius::scratch_len(23, 17)];
    radius::prepare(&hf, &mut scratch).unwrap();
    let mut prev = bake(&field, BakeOptions::default());
    // e = 0 is the isotropic safety distance.
    let mut sd = vec![0u8; safety::map_len(23, 17, Variant::Isotropic)];
    let sd_opts = safety::Options {
        variant: Variant::Isotropic,
        ..safety::Options::default()
    };
    safety::bake(&hf, &mut scratch, sd_opts, &mut sd).unwrap();
    assert_eq!(prev, sd);
    for e in TOLERANCES {
        let opts = tolerant(e);
        let whole = bake(&field, opts);
        assert_rows_rebake(&whole, 23, &[0..5, 5..6, 6..17], |r, out| {
            radius::bake_rows(&hf, &scratch, r, opts, out).unwrap()
        });
        for j in 0..17 {
            for i in 0..23 {
                let t = (j * 23 + i) as usize;
                assert_eq!(whole[t], radius::texel_radius(&hf, &scratch, opts, i, j));
                assert!(whole[t] >= prev[t], "radius shrank with a larger tolerance");
            }
        }
        prev = whole;
    }
    // Too short an output is refused.
    let mut short = vec![0u8; 10];
    assert!(radius::bake(&hf, &mut scratch, BakeOptions::default(), &mut short).is_err());
    assert!(RadiusMap::new(&hf, &short).is_err());
}

/// Measured accuracy of one approximate variant.
#[derive(Default)]
struct Measure {
    tried: u64,
    wrong: u64,
    ambiguous: u64,
    hit_to_miss: u64,
    miss_to_hit: u64,
    early: u64,
    compared: u64,
    sum_err: f64,
    max_err: f64,
    /// Largest depth under the surface skipped before the reported hit (wrong rays).
    max_depth: f64,
    /// Largest main-axis length of the first stretch under the surface skipped.
    max_chord: f64,
    fetches: u64,
}

#[test]
fn approximate_variants_measured() {
    let mut rng = Rng::new(77);
    let variants: Vec<(String, f32, Zero)> =
        std::iter::once(("clamp to 1".to_string(), 0.0, Zero::Clamp))
            .chain(
                TOLERANCES
                    .iter()
                    .map(|&e| (format!("tolerant e={e}"), e, Zero::Walk)),
            )
            .collect();
    let mut ms: Vec<Measure> = variants.iter().map(|_| Measure::default()).collect();
    let mut exact_fetches = 0u64;
    for (_, field) in fields() {
        let hf = field.hf();
        let zs = field.z_scale();
        let per_kind = if field.w * field.h > 200 { 120 } else { 30 };
        let specs = rays(&field, &mut rng, per_kind);
        let oracles: Vec<Trace<f64>> = specs
            .iter()
            .map(|s| dda::trace(&hf, TRI, &s.q64()))
            .collect();
        let exact = bake(&field, BakeOptions::default());
        let emap = RadiusMap::new(&hf, &exact).unwrap();
        for s in &specs {
            exact_fetches +=
                u64::from(radius::trace(&emap, &hf, &s.q32(), &Options::default()).fetches);
        }
        for ((_, e, zero), m) in variants.iter().zip(&mut ms) {
            let data = if *e == 0.0 {
                exact.clone()
            } else {
                bake(&field, tolerant(*e))
            };
            let map = RadiusMap::new(&hf, &data).unwrap();
            let opts = Options {
                zero: *zero,
                ..Options::default()
            };
            for (s, oracle) in specs.iter().zip(&oracles) {
                let q = s.q32();
                let q64 = s.q64();
                let got = radius::trace(&map, &hf, &q, &opts);
                m.tried += 1;
                m.fetches += u64::from(got.fetches);
                match judge(&field, &got, &q, oracle) {
                    Verdict::Ambiguous => m.ambiguous += 1,
                    Verdict::Right => {}
                    Verdict::Wrong => {
                        m.wrong += 1;
                        let Some(oh) = oracle.hit else {
                            m.miss_to_hit += 1;
                            continue;
                        };
                        let (_, t_end) = footprint_span(&field, &q64).unwrap_or((oh.t, oh.t));
                        let t_got = match got.hit {
                            Some(h) => {
                                let e =
                                    common::dist(oh.point.to_array(), common::p64::<f32>(h.point));
                                m.compared += 1;
                                m.sum_err += e;
                                m.max_err = m.max_err.max(e);
                                f64::from(h.t)
                            }
                            None => {
                                m.hit_to_miss += 1;
                                t_end.max(oh.t)
                            }
                        };
                        let d = q64.dir();
                        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                        if t_got < oh.t - 1e-4 / len {
                            m.early += 1;
                        }
                        let depth = max_depth(&field, &q64, oh.t, t_got.max(oh.t));
                        let chord = chord_main(&field, &q64, oh.t, t_end.max(oh.t));
                        m.max_depth = m.max_depth.max(depth - 1e-4 * zs);
                        m.max_chord = m.max_chord.max(chord);
                    }
                }
            }
        }
    }
    println!(
        "{:<16} {:>7} {:>6} {:>8} {:>6} {:>6} {:>10} {:>10} {:>9} {:>9} {:>9}",
        "variant",
        "rays",
        "wrong",
        "rate",
        "h->m",
        "m->h",
        "err mean",
        "err max",
        "depth",
        "chord",
        "fetch/ray"
    );
    println!(
        "{:<16} {:>7} {:>6} {:>8} {:>6} {:>6} {:>10} {:>10} {:>9} {:>9} {:>9.1}",
        "exact",
        ms[0].tried,
        0,
        "0",
        0,
        0,
        "-",
        "-",
        "-",
        "-",
        exact_fetches as f64 / ms[0].tried as f64
    );
    for ((name, e, zero), m) in variants.iter().zip(&ms) {
        let mean = if m.compared > 0 {
            m.sum_err / m.compared as f64
        } else {
            0.0
        };
        println!(
            "{name:<16} {:>7} {:>6} {:>7.3}% {:>6} {:>6} {:>10.3} {:>10.3} {:>9.4} {:>9.4} {:>9.1}",
            m.tried,
            m.wrong,
            100.0 * m.wrong as f64 / m.tried as f64,
            m.hit_to_miss,
            m.miss_to_hit,
            mean,
            m.max_err,
            m.max_depth,
            m.max_chord,
            m.fetches as f64 / m.tried as f64
        );
        // Never a hit before the oracle's, never a hit where the oracle misses.
        assert_eq!(m.early, 0, "{name}: a hit before the surface");
        assert_eq!(m.miss_to_hit, 0, "{name}: a hit where the oracle misses");
        match zero {
            // Jumping one centerline skips at most a dip between two centerlines.
            Zero::Clamp => assert!(
                m.max_chord <= 1.0 + 1e-6,
                "{name}: skipped more than one column"
            ),
            // Above `h` at both ends of a jump and never crossing `h − e` upwards:
            // never deeper than `e` under the surface before the reported hit.
            Zero::Walk => assert!(
                m.max_depth <= f64::from(*e) + 1e-4,
                "{name}: skipped solid deeper than e"
            ),
        }
        assert!(m.wrong * 10 < m.tried, "{name}: more than 10% wrong");
    }
    assert!(
        ms.iter().any(|m| m.wrong > 0),
        "no approximate variant ever erred: a vacuous test"
    );
}
