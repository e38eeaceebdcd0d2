//! Cone step mapping, quadratic displacement maps and relaxed cones against the f64
//! exact traversal (`dda::trace` on `q.cast::<f64>()`): conservative methods never step
//! past the oracle's hit and either converge or report their budget; the fast bakes
//! equal their brute-force oracles; the stable quadratic solver beats the textbook one
//! on stiff cases; relaxed cones miss thin features and the oracle catches it.
#![cfg(all(feature = "cone", feature = "qdm", feature = "relaxed"))]

mod common;

use common::{
    add_counts, baked_floats, checkerboard_field, dist, eps_f32, fractal_fields, keep_example,
    kind_blocks, needles_field, plateau_field, random_ray, small_fields, Field, RayKind, Rng,
};
use hfcast::bake::Spec;
use hfcast::cone::{CellMap, Cone, Family};
use hfcast::ktx2::{Desc, MapKind};
use hfcast::qdm::Qdm;
use hfcast::relaxed::Relaxed;
use hfcast::{cone, dda, qdm, relaxed, HeightField, Query, Real, Surface, Trace};

const TRI: Surface = Surface::Triangles;

/// Synthetic fields: fractal, thin walls, needles, plateau, checkerboard, small random.
fn fields() -> Vec<(String, Field)> {
    let mut rng = Rng::new(0xc0de);
    let mut v = fractal_fields(&mut rng, "fractal 90x7 stride 95");
    v.push(("needles 45x38".into(), needles_field(7)));
    let walls = Field::from_fn(40, 40, 40, |i, j| {
        if i % 9 == 4 || j % 11 == 5 {
            6.0
        } else {
            0.0
        }
    });
    v.push(("walls 40x40".into(), walls));
    v.push(("checkerboard 24x20".into(), checkerboard_field(0.0, 1.0)));
    v.push(("plateau 33x29".into(), plateau_field()));
    v.extend(small_fields(&mut rng, 8));
    v
}

/// Per-case counts of a convergent method.
#[derive(Default, Debug)]
struct Counts {
    tried: u64,
    wrong: u64,
    ambiguous: u64,
    exhausted: u64,
    converged: u64,
    overstep: u64,
    examples: Vec<String>,
}

impl Counts {
    fn line(&self, name: &str) -> String {
        format!(
            "{name:<52} tried {:>6}  wrong {:>4}  ambiguous {:>4}  budget-exhausted {:>5}  converged {:>6}  overstep {:>3}",
            self.tried, self.wrong, self.ambiguous, self.exhausted, self.converged, self.overstep
        )
    }
}

/// Hit position of a trace as f64.
fn pos<R: Real>(t: &Trace<R>) -> Option<[f64; 3]> {
    t.hit.map(|h| R::xyz(h.point).map(|v| v.to_f64()))
}

/// Runs one conservative method in one precision over the rays and tallies it.
fn run_conservative<R: Real>(
    field: &Field,
    rays: &[Query<f32>],
    slack_texel: f64,
    mut trace: impl FnMut(&Query<R>, &mut dyn FnMut(R)) -> Trace<R>,
) -> Counts {
    let hf = field.hf();
    let eps = eps_f32(field.z_scale());
    let mut c = Counts::default();
    for q32 in rays {
        let q64 = q32.cast::<f64>();
        let oracle = dda::trace(&hf, TRI, &q64);
        let amb = oracle.clearance < eps;
        c.tried += 1;
        let d = q64.dir();
        let dlen = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let limit = oracle
            .hit
            .map_or(f64::INFINITY, |h| h.t + slack_texel / dlen);
        let mut over = false;
        let q = q32.cast::<R>();
        let got = trace(&q, &mut |t: R| over |= t.to_f64() > limit);
        if amb {
            c.ambiguous += 1;
            continue;
        }
        if over {
            c.overstep += 1;
            keep_example(&mut c.examples, 3, || format!("overstep {q32:?}"));
        }
        if got.flags.contains(hfcast::Flags::BUDGET_EXHAUSTED) {
            c.exhausted += 1;
            continue;
        }
        let ok = match (pos(&got), pos(&oracle)) {
            (None, None) => true,
            (Some(a), Some(b)) => dist(a, b) <= 1e-3,
            _ => false,
        };
        if ok {
            c.converged += 1;
        } else {
            c.wrong += 1;
            keep_example(&mut c.examples, 3, || {
                format!("wrong {q32:?} got {:?} oracle {:?}", got.hit, oracle.hit)
            });
        }
    }
    c
}

/// Random f32 rays of every kind for a field.
fn rays_for(field: &Field, rng: &mut Rng, per_kind: usize) -> Vec<Query<f32>> {
    let specs = kind_blocks(rng, field, TRI, &RayKind::ALL, per_kind);
    specs.iter().map(|s| s.q32()).collect()
}

/// A brute-force oracle of a bake `(field, out)`.
type Brute = fn(&HeightField, &mut [f32]) -> Result<(), cone::BakeError>;

/// One field's map baked by its module's bake (with the scratch it filled) and by the
/// brute-force oracle.
struct BakedTwice {
    name: String,
    field: Field,
    scratch: Vec<f32>,
    fast: Vec<f32>,
    brute: Vec<f32>,
}

/// The fields of at most `max_samples` samples, each with its `map` (of family member
/// `F`) baked by `cone::bake::<F>` and by `brute`.
fn baked_twice<F: Family>(map: MapKind, max_samples: u32, brute: Brute) -> Vec<BakedTwice> {
    let small = fields()
        .into_iter()
        .filter(|(_, f)| f.w * f.h <= max_samples);
    small
        .map(|(name, field)| {
            let spec = Spec::new(Desc::new(map, field.w, field.h));
            let mut scratch = vec![0.0; spec.scratch_len()];
            let mut fast = vec![0.0; spec.map_len().unwrap()];
            let mut oracle = fast.clone();
            cone::bake::<F>(&field.hf(), &mut scratch, &mut fast).unwrap();
            brute(&field.hf(), &mut oracle).unwrap();
            BakedTwice {
                name,
                field,
                scratch,
                fast,
                brute: oracle,
            }
        })
        .collect()
}

/// Calls `check(cell, p, d)` for every cell of `f` and every one of `n` points `p` of
/// its triangle surface (uniform over the footprint, drawn from a generator seeded with
/// `seed`), `d` the horizontal distance from the cell to `p`: the independent checks
/// that a cell's bound holds no surface.
fn cells_and_surface_points(
    f: &Field,
    seed: u64,
    n: usize,
    mut check: impl FnMut([u32; 2], [f64; 3], f64),
) {
    let hf = f.hf();
    let mut rng = Rng::new(seed);
    let pts: Vec<[f64; 3]> = (0..n)
        .map(|_| {
            let x = rng.range(0.0, (f.w - 1) as f64);
            let y = rng.range(0.0, (f.h - 1) as f64);
            [x, y, TRI.height_at(&hf, x, y)]
        })
        .collect();
    for j in 0..f.h - 1 {
        for i in 0..f.w - 1 {
            for &p in &pts {
                let gx = (i as f64 - p[0]).max(p[0] - (i + 1) as f64).max(0.0);
                let gy = (j as f64 - p[1]).max(p[1] - (j + 1) as f64).max(0.0);
                check([i, j], p, (gx * gx + gy * gy).sqrt());
            }
        }
    }
}

#[test]
fn cone_bake_equals_brute_force() {
    for m in baked_twice::<Cone>(MapKind::Cone, 2000, cone::bake_brute) {
        let (f, name) = (&m.field, &m.name);
        assert_eq!(
            m.fast.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            m.brute.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            "{name}"
        );
        // Row ranges give the same texels.
        let hf = f.hf();
        let mut rows = vec![0.0; m.fast.len()];
        let cw = (f.w - 1) as usize * cone::CHANNELS;
        let mid = (f.h - 1) / 2;
        let (lo, hi) = rows.split_at_mut(mid as usize * cw);
        cone::bake_rows::<Cone>(&hf, &m.scratch, 0..mid, lo).unwrap();
        cone::bake_rows::<Cone>(&hf, &m.scratch, mid..f.h - 1, hi).unwrap();
        assert_eq!(rows, m.fast, "{name} rows");
    }
}

/// The cone bake is checked independently: dense points of the surface stay outside
/// every cell's cone (apex anywhere on the cell's top).
#[test]
fn cones_contain_no_surface() {
    for (name, f) in fields().into_iter().take(6) {
        let hf = f.hf();
        let map = baked_floats(MapKind::Cone, &hf);
        let cm = cone::ConeMap::new(&hf, &map).unwrap();
        cells_and_surface_points(&f, 3, 3000, |[i, j], p, d| {
            let [top, r] = cm.texel(i, j);
            let inside = p[2] - top as f64 > 1e-9 && d < r as f64 * (p[2] - top as f64);
            assert!(!inside, "{name}: cell ({i},{j}) cone holds {p:?}");
        });
    }
}

/// A cone or QDM step trace over its cell map (`cone::trace_steps`, `qdm::trace_steps`)
/// in precision `R`.
type StepTrace<const N: usize, R> =
    fn(&CellMap<'_, N>, &HeightField<'_>, &Query<R>, u32, &mut dyn FnMut(R)) -> Trace<R>;

/// The march of `method` over its map (`map`, `N` floats a cell), traced in `f64`
/// (`trace64`) and `f32` (`trace32`) with 256 iterations on 40 rays of every kind per
/// field (from a generator seeded with `seed`), never steps past the oracle's hit and
/// converges to it unless its budget runs out; prints the per-field and total counts.
fn assert_conservative<const N: usize>(
    method: &str,
    seed: u64,
    map: MapKind,
    trace64: StepTrace<N, f64>,
    trace32: StepTrace<N, f32>,
) {
    let mut rng = Rng::new(seed);
    let mut report = String::new();
    let mut total = [Counts::default(), Counts::default()];
    for (name, f) in fields() {
        let hf = f.hf();
        let data = baked_floats(map, &hf);
        let cm = CellMap::<N>::new(&hf, &data).unwrap();
        let rays = rays_for(&f, &mut rng, 40);
        let c64 = run_conservative(&f, &rays, 1e-9, |q, cb| trace64(&cm, &hf, q, 256, cb));
        let c32 = run_conservative(&f, &rays, 1e-4, |q, cb| trace32(&cm, &hf, q, 256, cb));
        report += &format!(
            "{}\n{}\n",
            c64.line(&format!("{method} f64 {name}")),
            c32.line(&format!("{method} f32 {name}"))
        );
        for (t, c) in total.iter_mut().zip([&c64, &c32]) {
            for e in &c.examples {
                report += &format!("    e.g. {e}\n");
            }
            add_counts!(t, c, tried, wrong, ambiguous, exhausted, converged, overstep);
        }
    }
    println!(
        "{report}{}\n{}",
        total[0].line(&format!("{method} f64 TOTAL")),
        total[1].line(&format!("{method} f32 TOTAL"))
    );
    for t in &total {
        assert_eq!(t.overstep, 0);
        assert_eq!(t.wrong, 0);
    }
}

#[test]
fn cone_march_is_conservative() {
    assert_conservative(
        "cone",
        11,
        MapKind::Cone,
        cone::trace_steps,
        cone::trace_steps,
    );
}

#[test]
fn qdm_bake_matches_brute_force_and_bounds_the_surface() {
    for m in baked_twice::<Qdm>(MapKind::Qdm, 2000, qdm::bake_brute) {
        let name = &m.name;
        for (k, (a, b)) in m.fast.iter().zip(&m.brute).enumerate() {
            let tol = 1e-5 * (1.0 + a.abs().max(b.abs()));
            assert!((a - b).abs() <= tol, "{name} channel {k}: {a} vs {b}");
        }
        // Independent check: surface points stay under h + F(dist to the cell).
        let hf = m.field.hf();
        let qm = qdm::QdmMap::new(&hf, &m.fast).unwrap();
        cells_and_surface_points(&m.field, 5, 1500, |[i, j], p, rho| {
            let [a, b, c, h] = qm.texel(i, j).map(f64::from);
            let f_rho = qdm::bound(a, b, c, rho);
            assert!(
                p[2] - h <= f_rho + 1e-9,
                "{name}: cell ({i},{j}) [{a},{b},{c},{h}] below {p:?}"
            );
        });
    }
}

#[test]
fn qdm_march_is_conservative() {
    assert_conservative("qdm", 12, MapKind::Qdm, qdm::trace_steps, qdm::trace_steps);
}

/// Stiff quadratics: nearly flat parabolas (tiny A), grazing rays (B ≈ 0 against a
/// tiny C) and huge curvatures. In f32 the textbook formula loses the small root to
/// cancellation; the stable solver keeps it to a few ulps. Reference: f64 stable.
#[test]
fn stable_quadratic_beats_textbook_on_stiff_cases() {
    let cases: [(f32, f32, f32); 6] = [
        (1e-6, -1.0, 1e-3), // nearly flat parabola
        (1e-9, -0.5, 0.25), // flatter still
        (3e-5, -2.0, 1e-4), // grazing: small C, tiny A
        (1e-4, -1.0, 1e-7), // grazing at the start
        (1e12, -1e7, 1.0),  // huge curvature, root near 1e-7
        (1e8, -2e4, 0.5),   // huge curvature
    ];
    let mut worst = [0.0f64; 2];
    for (a, b, c) in cases {
        let exact = qdm::solve_stable(a as f64, b as f64, c as f64).unwrap();
        let s = qdm::solve_stable(a, b, c).map_or(f64::INFINITY, |r| r as f64);
        let t = qdm::solve_textbook(a, b, c).map_or(f64::INFINITY, |r| r as f64);
        let (es, et) = ((s - exact).abs() / exact, (t - exact).abs() / exact);
        println!(
            "A={a:e} B={b:e} C={c:e}: exact {exact:.9e}  stable {s:.9e} (rel {es:.1e})  textbook {t:.9e} (rel {et:.1e})"
        );
        worst[0] = worst[0].max(es);
        worst[1] = worst[1].max(et);
    }
    println!(
        "worst relative error: stable {:.1e}, textbook {:.1e}",
        worst[0], worst[1]
    );
    assert!(worst[0] < 1e-6, "stable solver lost accuracy");
    assert!(
        worst[1] > 1e-2,
        "textbook formula was expected to lose accuracy"
    );
}

#[test]
fn relaxed_bake_equals_brute_force() {
    for m in baked_twice::<Relaxed>(MapKind::Relaxed, 1200, relaxed::bake_brute) {
        assert_eq!(m.fast, m.brute, "{}", m.name);
    }
}

/// Relaxed cones are approximate: the oracle catches their wrong rays (a thin needle
/// or wall stepped over), which are counted and printed, not hidden.
#[test]
fn relaxed_wrong_rays_are_caught() {
    let mut rng = Rng::new(13);
    let mut report = String::new();
    let mut thin_wrong = 0;
    for (name, f) in fields() {
        let hf = f.hf();
        let eps = eps_f32(f.z_scale());
        let map = baked_floats(MapKind::Relaxed, &hf);
        let (mut tried, mut wrong, mut amb, mut exh, mut err_sum, mut err_max, mut nh) =
            (0, 0, 0, 0, 0.0, 0.0f64, 0);
        for _ in 0..400 {
            let q32 = random_ray(&mut rng, &f, TRI, RayKind::Down).q32();
            let q64 = q32.cast::<f64>();
            let oracle = dda::trace(&hf, TRI, &q64);
            tried += 1;
            if oracle.clearance < eps {
                amb += 1;
                continue;
            }
            let got = relaxed::trace(&map, &hf, &q32, relaxed::Steps::default());
            if got.flags.contains(hfcast::Flags::BUDGET_EXHAUSTED) {
                exh += 1;
            }
            match (pos(&got), pos(&oracle)) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    let e = dist(a, b);
                    err_sum += e;
                    err_max = err_max.max(e);
                    nh += 1;
                    if e > 1e-3 {
                        wrong += 1;
                    }
                }
                _ => wrong += 1,
            }
        }
        if name.starts_with("needles") || name.starts_with("walls") {
            thin_wrong += wrong;
        }
        report += &format!(
            "relaxed f32 {name:<40} tried {tried:>5}  wrong {wrong:>4}  ambiguous {amb:>4}  budget-exhausted {exh:>4}  err mean {:.1e} max {err_max:.1e}\n",
            err_sum / nh.max(1) as f64
        );
    }
    println!("{report}");
    assert!(
        thin_wrong > 0,
        "relaxed cones were expected to miss some thin features"
    );
}
