//! The bake-free baselines (`search::linear` with either `search::Refine`, through
//! `hfcast::Method`) are approximate. This test asserts only what must hold, and prints
//! their wrong-ray rates against the oracle (the `f64` exact traversal on the same ray):
//!
//! - a baseline never reports a hit where the ray never goes under the surface (its
//!   bracket ends at a point with clearance ≤ 0), unless the ray is ambiguous;
//! - on a smooth field, with many steps, their error against the oracle is small, and
//!   it falls as the step count grows;
//! - a thin one-texel spike that the exact method hits is missed by a coarse linear
//!   search for at least one ray: the oracle catches their failures.
#![cfg(feature = "search")]

mod common;

use common::*;
use hfcast::{dda, Flags, Method, Query, SearchSteps, Surface};

/// Wrong-ray statistics of one method over `rays`.
fn measure(field: &Field, surface: Surface, method: Method, rays: &[Query<f32>]) -> (Tally, u64) {
    let hf = field.hf();
    let mut t = Tally::new(format!("{:?}", method));
    let mut impossible = 0;
    let eps = eps_f32(field.z_scale());
    for q in rays {
        let oracle = dda::trace(&hf, surface, &q.cast::<f64>());
        let got = method.trace(&hf, surface, q);
        if !t.ray(oracle.hit.is_some(), is_ambiguous(&oracle, eps)) {
            continue;
        }
        match (oracle.hit, got.hit) {
            (None, None) => {}
            (Some(o), Some(g)) => {
                if t.err_between(p64::<f64>(o.point), p64::<f32>(g.point)) > WRONG {
                    t.wrong += 1;
                }
            }
            (Some(_), None) => t.wrong += 1,
            (None, Some(g)) => {
                // A hit where the exact method finds none: impossible for a search whose
                // bracket ends under the surface.
                t.wrong += 1;
                impossible += 1;
                if impossible <= 3 {
                    println!("impossible hit {method:?} {q:?}: {g:?}");
                }
            }
        }
        assert!(!got.flags.contains(Flags::BUDGET_EXHAUSTED));
    }
    (t, impossible)
}

fn rate(t: &Tally) -> f64 {
    t.wrong as f64 / (t.tried - t.ambiguous).max(1) as f64
}

#[test]
fn baselines_converge_on_a_smooth_field() {
    let mut rng = Rng::new(0xBA5E);
    let field = fractal_field(&mut rng, 48, 48, 48, 3.0);
    // Rays from above the box at elevations of 5° to 35°, aimed into the field.
    let (lo, hi) = field.range();
    let rays: Vec<Query<f32>> = (0..1500)
        .map(|_| {
            let target = [
                rng.range(4.0, 43.0),
                rng.range(4.0, 43.0),
                rng.range(lo, hi),
            ];
            let (a, el) = (rng.range(0.0, std::f64::consts::TAU), -rng.range(0.08, 0.6));
            let d = [a.cos() * el.cos(), a.sin() * el.cos(), el.sin()];
            let back = (hi + 1.0 - target[2]) / -d[2];
            let o = [0, 1, 2].map(|k| target[k] - back * d[k]);
            Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .unwrap()
        })
        .collect();
    let mut out = String::from(
        "baselines vs the f64 oracle, smooth 48x48 field, 1500 rays at 5-35 degrees\n",
    );
    let mut checks = Vec::new();
    for surface in [Surface::Triangles, Surface::Bilinear] {
        let mut prev: Option<(Tally, Tally)> = None;
        let mut first = None;
        for n in [4u32, 8, 16, 32, 64, 128, 256, 512] {
            let (lb, i1) = measure(
                &field,
                surface,
                Method::LinearBinary(SearchSteps {
                    linear: n,
                    binary: 16,
                }),
                &rays,
            );
            let (ls, i2) = measure(&field, surface, Method::LinearSecant(n), &rays);
            out.push_str(&format!(
                "{:<12} {n:>4} steps: linear+binary(16) wrong {:>5.2}% ({}/{}) mean err {:.1e} | linear+secant wrong {:>5.2}% ({}/{}) mean err {:.1e}  (ambiguous {})\n",
                surface.name(),
                100.0 * rate(&lb),
                lb.wrong,
                lb.tried - lb.ambiguous,
                lb.sum_err / lb.compared_hits.max(1) as f64,
                100.0 * rate(&ls),
                ls.wrong,
                ls.tried - ls.ambiguous,
                ls.sum_err / ls.compared_hits.max(1) as f64,
                lb.ambiguous,
            ));
            checks.push((
                i1 + i2 == 0,
                format!("{n}: a baseline hit where the ray stays above"),
            ));
            let mean = |t: &Tally| t.sum_err / t.compared_hits.max(1) as f64;
            if let Some((plb, pls)) = &prev {
                // More steps never make them markedly worse; the secant's error falls
                // with every doubling.
                let what = format!("{surface:?} {n} steps vs half as many");
                checks.push((
                    lb.wrong <= plb.wrong + 2 && ls.wrong <= pls.wrong + 2,
                    what.clone(),
                ));
                checks.push((mean(&ls) < mean(pls), what));
            }
            if first.is_none() {
                first = Some((lb.wrong, ls.wrong, mean(&lb), mean(&ls)));
            }
            if n == 512 {
                // Fine searches: small error, far below the coarse ones'.
                let (w_lb, w_ls, m_lb, m_ls) = first.unwrap();
                let what = format!("{surface:?} at 512 steps");
                checks.push((rate(&lb) < 0.002 && rate(&ls) < 0.1, what.clone()));
                checks.push((mean(&lb) < 1e-4 && mean(&ls) < 1e-3, what.clone()));
                checks.push((
                    mean(&lb) * 100.0 < m_lb && mean(&ls) * 100.0 < m_ls,
                    what.clone(),
                ));
                checks.push((lb.wrong < w_lb && ls.wrong * 5 < w_ls, what));
            }
            prev = Some((lb, ls));
        }
    }
    println!("{out}");
    for (ok, what) in checks {
        assert!(ok, "{what}");
    }
}

#[test]
fn coarse_search_misses_a_thin_spike() {
    // Flat ground with one sample raised: on the triangle surface a pyramid two texels
    // wide. Nearly horizontal rays aimed under its upper part.
    let field = Field::from_fn(
        33,
        33,
        33,
        |i, j| if (i, j) == (16, 16) { 8.0 } else { 0.0 },
    );
    let hf = field.hf();
    let mut rng = Rng::new(0x5B1CE);
    let rays: Vec<Query<f32>> = (0..400)
        .map(|_| {
            // Aim at a point inside the pyramid's upper half, from 30 texels away.
            let (x, y) = (16.0 + rng.range(-0.2, 0.2), 16.0 + rng.range(-0.2, 0.2));
            let target = [
                x,
                y,
                Surface::Triangles.height_at(&hf, x, y) * rng.range(0.5, 0.95),
            ];
            let a = rng.range(0.0, std::f64::consts::TAU);
            let el = rng.range(-0.3, 0.0);
            let d = [a.cos() * el.cos(), a.sin() * el.cos(), el.sin()];
            let back = 30.0;
            let o = [
                target[0] - back * d[0],
                target[1] - back * d[1],
                target[2] - back * d[2],
            ];
            Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .unwrap()
        })
        .collect();
    let mut out =
        String::from("thin spike (33x33, one sample at 8), 400 rays aimed at its upper half\n");
    let mut exact_hits = 0;
    for q in &rays {
        assert!(
            dda::trace(&hf, Surface::Triangles, q).hit.is_some(),
            "exact misses {q:?}"
        );
        exact_hits += 1;
    }
    let mut coarse_misses = 0;
    for (method, name) in [
        (
            Method::LinearBinary(SearchSteps {
                linear: 8,
                binary: 8,
            }),
            "linear 8 + binary 8",
        ),
        (Method::LinearSecant(8), "linear 8 + secant"),
        (
            Method::LinearBinary(SearchSteps {
                linear: 32,
                binary: 8,
            }),
            "linear 32 + binary 8",
        ),
        (
            Method::LinearBinary(SearchSteps {
                linear: 256,
                binary: 8,
            }),
            "linear 256 + binary 8",
        ),
        (Method::Exact, "exact"),
    ] {
        let (t, impossible) = measure(&field, Surface::Triangles, method, &rays);
        let misses = rays
            .iter()
            .filter(|q| method.trace(&hf, Surface::Triangles, *q).hit.is_none())
            .count();
        if matches!(
            method,
            Method::LinearBinary(SearchSteps { linear: 8, .. }) | Method::LinearSecant(8)
        ) {
            coarse_misses += misses;
        }
        out.push_str(&format!(
            "{name:<24} wrong {:>3}/{} ({:.1}%), misses the spike {misses}\n",
            t.wrong,
            t.tried - t.ambiguous,
            100.0 * rate(&t),
        ));
        assert_eq!(impossible, 0);
        if method.is_exact() {
            assert_eq!(t.wrong, 0);
        }
    }
    println!("{out}");
    assert_eq!(exact_hits, rays.len());
    assert!(
        coarse_misses > 0,
        "a coarse linear search should miss the spike"
    );
}
