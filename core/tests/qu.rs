//! Qu et al. 2003 as hfcast implements it: the fixed-diagonal triangles with their
//! division-free test (§3.2), against the adaptive triangles and the f64 oracles, and
//! their bilinear method (§3.3, sampling then bisection) against the exact bilinear
//! solution.

mod common;

use common::*;
use hfcast::{brute, dda, Query, Surface};

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

/// Every random ray kind, grazing rays included, on real-like and spiky fields: the
/// fixed-diagonal surface has zero wrong rays against brute force in f64 and f32 (the
/// oracle suite covers it too, as it covers every surface; this case draws rays for
/// it alone).
#[test]
fn qu_triangles_are_exact_against_brute_force() {
    let mut rng = Rng::new(0x0052);
    let mut all = Judged::new("qu-triangles, all fields");
    let mut out = String::new();
    let fields = [
        ("fractal 33x29", fractal_field(&mut rng, 33, 29, 35, 8.0)),
        ("needles", needles_field(7)),
        ("checkerboard", checkerboard_field(0.0, 5.0)),
        ("walls", random_walls_field(&mut rng)),
    ];
    for (name, field) in &fields {
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
