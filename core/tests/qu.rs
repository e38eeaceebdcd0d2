//! Qu et al. 2003 as hfcast implements it: the fixed-diagonal triangles with their
//! division-free test (§3.2), against the adaptive triangles and the f64 oracles, and
//! their bilinear method (§3.3, sampling then bisection) against the exact bilinear
//! solution.

mod common;

use common::*;
use hfcast::{brute, dda, hybrid, judge, multires, Query, Surface};

/// One cell with a ridge along the diagonal 00–11 (h00 = h11 = 1, h10 = h01 = 0). Qu's
/// fixed diagonal keeps the ridge; the triangle surface splits along the lower diagonal
/// 10–01 (a valley). A level ray at z = 0.9 from (0.9, 0.1) to (0.1, 0.9) is clear at
/// both ends (0.2 under it) and passes under the ridge's 1 at the crossing: the
/// division-free test must find it, and it must not hit the valley.
#[test]
fn qu_triangles_meet_a_ridge_between_clear_ends() {
    let field = Field::from_fn(2, 2, 2, |i, j| if i == j { 1.0 } else { 0.0 });
    let hf = field.hf();
    let q = Query::from_arrays([0.9f32, 0.1, 0.9], [-0.8, 0.8, 0.0], 0.0, 1.0).unwrap();
    let qu = dda::trace(&hf, Surface::QuTriangles, &q)
        .hit
        .expect("the ridge");
    // The ridge 1 − |u − v| reaches 0.9 at |u − v| = 0.1: u = 0.55, t = 0.4375.
    assert!((qu.t - 0.4375).abs() < 1e-6, "{qu:?}");
    assert!((qu.point[0] - 0.55).abs() < 1e-6 && (qu.point[2] - 0.9).abs() < 1e-6);
    let b = brute::first_hit(&hf, Surface::QuTriangles, &q.cast::<f64>()).expect("brute");
    assert!((b.0 - 0.4375).abs() < 1e-6, "{b:?}");
    assert!(dda::trace(&hf, Surface::Triangles, &q).hit.is_none());
    assert!(brute::first_hit(&hf, Surface::Triangles, &q.cast::<f64>()).is_none());
    // Lower, the first triangle holds the hit: from (0.9, 0.1) at z = 0.25 (0.05 over
    // the plane of (00, 10, 11), which rises by 1.6 per unit of t) it is met at
    // t = 1/32, before the diagonal.
    let low = Query::from_arrays([0.9f32, 0.1, 0.25], [-0.8, 0.8, 0.0], 0.0, 1.0).unwrap();
    let hit = dda::trace(&hf, Surface::QuTriangles, &low)
        .hit
        .expect("first triangle");
    assert!(
        hit.point[0] > hit.point[1] && (hit.t - 0.03125).abs() < 1e-6,
        "{hit:?}"
    );
}

/// Where every cell's lower diagonal is 00–11 the two triangle surfaces are one
/// surface: h = a(i) + b(j) − k·i·j has the mixed difference h00 + h11 − h10 − h01 = −k
/// in every cell. The division-free test must then find the triangle test's hits.
#[test]
fn qu_triangles_equal_triangles_where_the_lower_diagonal_is_00_11() {
    let mut rng = Rng::new(0x0051);
    let a: Vec<f32> = (0..40).map(|_| rng.range(0.0, 6.0) as f32).collect();
    let b: Vec<f32> = (0..36).map(|_| rng.range(0.0, 6.0) as f32).collect();
    let field = Field::from_fn(40, 36, 40, |i, j| {
        a[i as usize] + b[j as usize] - 0.25 * (i * j) as f32
    });
    let hf = field.hf();
    let (mut compared, mut hits) = (0, 0);
    for kind in RayKind::ALL {
        for _ in 0..300 {
            let q = random_ray(&mut rng, &field, Surface::Triangles, kind).q32();
            let tri = dda::trace(&hf, Surface::Triangles, &q);
            let qu = dda::trace(&hf, Surface::QuTriangles, &q);
            compared += 1;
            match (tri.hit, qu.hit) {
                (None, None) => {}
                (Some(x), Some(y)) => {
                    hits += 1;
                    let e = dist(p64::<f32>(x.point), p64::<f32>(y.point));
                    assert!(e < 1e-4, "{q:?}: triangles {x:?}, qu {y:?}");
                }
                (x, y) => {
                    // Only where f32 cannot tell: a touch or a graze.
                    let oracle = dda::trace(&hf, Surface::Triangles, &q.cast::<f64>());
                    assert!(
                        hfcast::judge::ambiguous(&hf, Surface::Triangles, &q.cast(), &oracle),
                        "{q:?}: triangles {x:?}, qu {y:?}"
                    );
                }
            }
        }
    }
    println!("qu = triangles: {compared} rays, {hits} hits");
    assert!(hits * 3 > compared);
}

/// The fields of the exactness tests here: fBm, one-texel needles, a checkerboard of
/// cliffs, random walls.
fn exactness_fields(rng: &mut Rng) -> [(&'static str, Field); 4] {
    [
        ("fractal 33x29", fractal_field(rng, 33, 29, 35, 8.0)),
        ("needles", needles_field(7)),
        ("checkerboard", checkerboard_field(0.0, 5.0)),
        ("walls", random_walls_field(rng)),
    ]
}

/// Every random ray kind, grazing rays included, on real-like and spiky fields: the
/// fixed-diagonal surface has zero wrong rays against brute force in f64 and f32 (the
/// oracle suite covers it too, as it covers every surface; this case draws rays for
/// it alone).
#[test]
fn qu_triangles_are_exact_against_brute_force() {
    let mut rng = Rng::new(0x0052);
    let mut all = Judged::new("qu-triangles, all fields");
    let mut out = String::new();
    for (name, field) in &exactness_fields(&mut rng) {
        let mut j = Judged::new(format!("qu-triangles {name}"));
        for spec in rays_with_grazing(field, Surface::QuTriangles, &mut rng, 150) {
            j.add(field, Surface::QuTriangles, &spec.q64());
            j.add(field, Surface::QuTriangles, &spec.q32());
        }
        j.report(&mut out);
        all.absorb(&j);
    }
    all.report(&mut out);
    println!("{out}");
    assert_eq!(all.tally.wrong, 0);
    assert!(all.tally.ambiguous * 7 < all.tally.tried);
}

/// Qu's bilinear method is approximate: on a saddle field it misses dips the exact
/// quadratic finds with one sample per cell, and its error falls as the samples and
/// bisections grow; with many it agrees with the exact solution on nearly every ray.
#[test]
fn qu_bilinear_search_error_falls_with_its_steps() {
    let mut rng = Rng::new(0x0053);
    let field = fractal_field(&mut rng, 48, 40, 48, 10.0);
    let hf = field.hf();
    let rays: Vec<Query<f32>> = (0..3000)
        .map(|k| {
            let kind = [RayKind::Down, RayKind::Grazing, RayKind::Horizontal][k % 3];
            random_ray(&mut rng, &field, Surface::Bilinear, kind).q32()
        })
        .collect();
    let exact: Vec<_> = rays
        .iter()
        .map(|q| dda::trace(&hf, Surface::Bilinear, q))
        .collect();
    let mut out = String::new();
    let mut wrong_of = Vec::new();
    for steps in [(1, 0), (2, 4), (8, 16), (32, 24)] {
        let (mut wrong, mut max_err) = (0, 0f64);
        for (q, e) in rays.iter().zip(&exact) {
            let s = dda::trace_bilinear_search(&hf, q, steps);
            let err = match (e.hit, s.hit) {
                (None, None) => 0.0,
                (Some(a), Some(b)) => dist(p64::<f32>(a.point), p64::<f32>(b.point)),
                _ => f64::INFINITY,
            };
            if err > WRONG {
                wrong += 1;
            } else {
                max_err = max_err.max(err);
            }
        }
        out.push_str(&format!(
            "qu bilinear {}:{}  wrong {wrong} of {}  max error of the rest {max_err:.1e}\n",
            steps.0,
            steps.1,
            rays.len()
        ));
        wrong_of.push(wrong);
    }
    println!("{out}");
    assert!(
        wrong_of[0] > 0,
        "one sample per cell must miss or misplace some hits"
    );
    assert!(wrong_of.windows(2).all(|w| w[1] <= w[0]), "{wrong_of:?}");
    assert!(wrong_of[3] * 200 < rays.len(), "{wrong_of:?}");
}

/// With a one-texel distance beyond every ray the multiresolution walk is the exact
/// walk on level 0: the same cells (fetches) and the same hits up to rounding, on every
/// surface and ray kind.
#[test]
fn multires_with_a_far_one_texel_distance_is_the_exact_walk() {
    let mut rng = Rng::new(0x0054);
    let field = fractal_field(&mut rng, 40, 33, 41, 8.0);
    let hf = field.hf();
    let (mut compared, mut ambiguous) = (0, 0);
    for surface in Surface::ALL {
        for kind in RayKind::ALL {
            for _ in 0..60 {
                let q = random_ray(&mut rng, &field, surface, kind).q32();
                let exact = dda::trace(&hf, surface, &q);
                let multi = multires::trace(&hf, surface, &q, u32::MAX);
                let q64 = q.cast::<f64>();
                let oracle = dda::trace(&hf, surface, &q64);
                let same = match (exact.hit, multi.hit) {
                    (None, None) => true,
                    (Some(x), Some(y)) => dist(p64::<f32>(x.point), p64::<f32>(y.point)) < WRONG,
                    _ => false,
                };
                if !same || exact.fetches != multi.fetches {
                    assert!(
                        judge::ambiguous(&hf, surface, &q64, &oracle)
                            || near_pinch(&field, surface, &q64, PINCH),
                        "{surface:?} {q:?}: exact {exact:?}, multires {multi:?}"
                    );
                    ambiguous += 1;
                }
                compared += 1;
            }
        }
    }
    println!("multires on level 0: {compared} rays, {ambiguous} ambiguous ones differ");
    assert!(ambiguous * 50 < compared);
}

/// The multiresolution walk on a 1024² fractal seen from a low camera (5° and 20°
/// above the horizon, 160 × 120, 40° field of view), the one-texel distance the
/// reciprocal of the pixel angle: its error against the exact walk in pixel footprints
/// (the pixel angle times the hit's distance), its hit/miss flips and its fetches. The
/// error is measured, not bounded; the test checks that coarse levels are used (fewer
/// fetches), that the median error of hits is under a footprint while some rays flip
/// (it is approximate), and that a finer one-texel distance (four times) errs less.
#[test]
fn multires_error_is_measured_per_pixel_footprint() {
    let mut rng = Rng::new(0x0055);
    let field = fractal_field(&mut rng, 1024, 1024, 1024, 60.0);
    let hf = field.hf();
    let (w, h, fov) = (160u32, 120u32, 40.0f64);
    let angle = fov.to_radians() / f64::from(h);
    let range = (1.0 / angle).round() as u32;
    let (mut out, mut checks) = (String::new(), Vec::new());
    for elevation in [5.0f64, 20.0] {
        let el = elevation.to_radians();
        let eye = [-60.0, 512.0, 70.0 + 300.0 * el.tan()];
        let forward = [el.cos(), 0.0, -el.sin()];
        let cam = hfcast::camera::Pinhole::new(eye, forward, [0.0, 0.0, 1.0], fov, w, h).unwrap();
        let mut medians = Vec::new();
        for r in [range, 4 * range] {
            let (mut errs, mut flips, mut hits) = (Vec::new(), 0usize, 0usize);
            let (mut fetch_exact, mut fetch_multi) = (0u64, 0u64);
            for py in 0..h {
                for px in 0..w {
                    let q = cam.ray(px, py, f32::INFINITY).unwrap();
                    let e = dda::trace(&hf, Surface::Triangles, &q);
                    let m = multires::trace(&hf, Surface::Triangles, &q, r);
                    fetch_exact += u64::from(e.fetches);
                    fetch_multi += u64::from(m.fetches);
                    match (e.hit, m.hit) {
                        (Some(a), Some(b)) => {
                            hits += 1;
                            let p = p64::<f32>(a.point);
                            let footprint = angle * dist(p, eye);
                            errs.push(dist(p, p64::<f32>(b.point)) / footprint);
                        }
                        (None, None) => {}
                        _ => flips += 1,
                    }
                }
            }
            errs.sort_by(f64::total_cmp);
            let q = |f: f64| errs[((errs.len() - 1) as f64 * f) as usize];
            out.push_str(&format!(
                "multires {elevation}° one-texel distance {r}: {hits} hits, error in footprints \
                 median {:.2} p90 {:.2} max {:.1}; {flips} hit/miss flips of {}; fetches {:.2}x \
                 the exact walk's\n",
                q(0.5),
                q(0.9),
                q(1.0),
                w * h,
                fetch_multi as f64 / fetch_exact as f64
            ));
            medians.push((
                q(0.5),
                q(0.9),
                flips,
                fetch_multi as f64 / fetch_exact as f64,
            ));
        }
        checks.push(medians);
    }
    println!("{out}");
    for m in checks {
        assert!(m[0].3 < 0.9, "coarse levels are used: {m:?}");
        assert!(m[0].0 < 1.0 && m[0].2 > 0, "{m:?}");
        assert!(
            m[1].1 <= m[0].1 && m[1].2 <= m[0].2,
            "finer errs less: {m:?}"
        );
    }
}

/// The hybrid renderer's two passes on the CPU answer as the exact walk on the
/// view-linear surface (both finished in f64): against brute force on every ray kind,
/// grazing rays included, zero wrong rays.
#[test]
fn hybrid_passes_are_the_view_linear_surface() {
    let mut rng = Rng::new(0x0056);
    let mut all = Judged::new("hybrid, all fields");
    let mut out = String::new();
    let mut same = 0;
    for (name, field) in &exactness_fields(&mut rng) {
        let hf = field.hf();
        let mut j = Judged::new(format!("hybrid {name}"));
        for spec in rays_with_grazing(field, Surface::ViewLinear, &mut rng, 120) {
            let q = spec.q32();
            let (hy, walk) = (
                hybrid::trace(&hf, &q),
                dda::trace(&hf, Surface::ViewLinear, &q),
            );
            let agree = match (hy.hit, walk.hit) {
                (None, None) => true,
                (Some(a), Some(b)) => dist(p64::<f32>(a.point), p64::<f32>(b.point)) < WRONG,
                _ => false,
            };
            same += usize::from(agree);
            j.add_trace(field, Surface::ViewLinear, &q, &hy);
        }
        j.report(&mut out);
        all.absorb(&j);
    }
    all.report(&mut out);
    println!(
        "{out}hybrid = exact walk on {same} of {} rays",
        all.tally.tried
    );
    assert_eq!(all.tally.wrong, 0);
    assert!(all.tally.ambiguous * 7 < all.tally.tried);
}
