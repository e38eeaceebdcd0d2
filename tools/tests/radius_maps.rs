//! Safety radius on a centred window (at most 256 × 256) of every real map of
//! `../shared/data` (depth 0.1 × max(W, H)): zero wrong rays for the exact radius
//! against the f64 exact DDA on the triangle surface, for camera rays at 45° and 5°
//! and random rays (all directions, upward included) inside the box, marched in f32 and
//! f64; and, per map, the wrong-ray rate and position error of the approximate
//! variants (zero radius clamped to one; error-tolerant radii), which never hit before
//! the surface nor where the oracle misses.

mod common;

use common::{
    ambiguity_eps, bake_halves, differs, maps, oracle_traces, pos_err, test_rays, touch, window,
};
use hfcast::radius::{self, BakeOptions, Options, RadiusMap, Zero};
use hfcast::{dda, HeightField, Surface};
use hfcast_tools::maps::load_map;

const TRI: Surface = Surface::Triangles;

/// Bakes on two threads (row halves).
fn bake(hf: &HeightField, scratch: &[f32], opts: BakeOptions) -> Vec<u8> {
    let mut out = vec![0u8; radius::map_len(hf.width(), hf.height())];
    bake_halves(&mut out, hf.width() as usize, hf.height(), |rows, part| {
        radius::bake_rows(hf, scratch, rows, opts, part).unwrap()
    });
    out
}

#[test]
fn radius_on_every_map() {
    let variants: Vec<(String, f32, Zero)> = [
        ("exact".to_string(), 0.0, Zero::Walk),
        ("clamp to 1".to_string(), 0.0, Zero::Clamp),
    ]
    .into_iter()
    .chain([0.25f32, 0.5, 1.0, 2.0].map(|e| (format!("tolerant e={e}"), e, Zero::Walk)))
    .collect();
    let (mut exact_wrong, mut bad_approx) = (0, 0);
    for info in &maps() {
        let depth = 0.1 * info.width.max(info.height) as f32;
        let map = load_map(&info.path, Some(depth)).expect("map loads");
        let hf = window(&map);
        let (w, h) = (hf.width(), hf.height());
        let mut scratch = vec![0f32; radius::scratch_len(w, h)];
        radius::prepare(&hf, &mut scratch).unwrap();
        let eps = ambiguity_eps(&hf);
        let rays = test_rays(&hf);
        let oracles = oracle_traces(&hf, &rays);
        let f_dda = rays
            .iter()
            .map(|q| f64::from(dda::trace(&hf, TRI, q).fetches))
            .sum::<f64>()
            / rays.len() as f64;
        println!(
            "{} ({w}x{h} window, depth {depth}): {} rays, dda {f_dda:.1} fetches/ray",
            info.name,
            rays.len()
        );
        let mut last: Option<(f32, Vec<u8>)> = None;
        for (label, e, zero) in &variants {
            let data = match &last {
                Some((le, d)) if le == e => d.clone(),
                _ => bake(
                    &hf,
                    &scratch,
                    BakeOptions {
                        tolerance: *e,
                        ..BakeOptions::default()
                    },
                ),
            };
            let rm = RadiusMap::new(&hf, &data).unwrap();
            let opts = Options {
                zero: *zero,
                ..Options::default()
            };
            let exact = *e == 0.0 && *zero == Zero::Walk;
            let (mut wrong, mut amb, mut h2m, mut m2h, mut early) = (0, 0, 0, 0, 0);
            let (mut n_err, mut sum_err, mut max_err, mut fetches) = (0, 0.0, 0f64, 0u64);
            for (q, oracle) in rays.iter().zip(&oracles) {
                let q64 = q.cast::<f64>();
                let s32 = radius::trace(&rm, &hf, q, &opts);
                fetches += u64::from(s32.fetches);
                let mut bad = differs(&s32, oracle);
                if exact {
                    bad |= differs(&radius::trace(&rm, &hf, &q64, &opts), oracle);
                }
                if !bad {
                    continue;
                }
                if oracle.clearance.abs() < eps || touch(&hf, &q64, oracle, eps) {
                    amb += 1;
                    continue;
                }
                wrong += 1;
                if exact && wrong <= 3 {
                    println!("    wrong: {q:?} got {:?} oracle {:?}", s32.hit, oracle.hit);
                }
                match (s32.hit, oracle.hit) {
                    (Some(a), Some(b)) => {
                        let err = pos_err::<f32>(a.point, b.point);
                        n_err += 1;
                        sum_err += err;
                        max_err = max_err.max(err);
                        if f64::from(a.t) < b.t - 1e-4 {
                            early += 1;
                        }
                    }
                    (None, Some(_)) => h2m += 1,
                    (Some(_), None) => m2h += 1,
                    (None, None) => {}
                }
            }
            let mean_r = data.iter().map(|&v| f64::from(v)).sum::<f64>() / data.len() as f64;
            println!(
                "    {label:<16} wrong {wrong:>4} ({:.3}%)  ambiguous-differ {amb:>2}  hit->miss \
                 {h2m:>3}  pos err mean {:.2} max {max_err:.2}  mean radius {mean_r:.2}  \
                 fetches/ray {:.1}",
                100.0 * f64::from(wrong) / rays.len() as f64,
                sum_err / f64::from(n_err.max(1)),
                fetches as f64 / rays.len() as f64
            );
            if exact {
                exact_wrong += wrong;
            } else {
                bad_approx += m2h + early;
            }
            last = Some((*e, data));
        }
    }
    assert_eq!(exact_wrong, 0, "wrong rays (exact radius)");
    assert_eq!(
        bad_approx, 0,
        "an approximate variant hit before the surface or in the air"
    );
}
