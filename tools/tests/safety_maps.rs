//! Safety distances on every real map of `../shared/data`, at depths 0.1 and 0.05 ×
//! max(W, H): zero wrong rays against the f64 exact DDA on the triangle surface, for
//! camera rays at 45° and 5° and random rays (all directions, upward included) inside
//! the box, directional and isotropic, marched in f32 and f64.

use hfcast::safety::{self, Options, SafetyMap, Variant};
use hfcast::{dda, HeightField, Query, Real, Surface, Trace};
use hfcast_tools::bench::random_rays;
use hfcast_tools::maps::{list_maps, load_map};
use hfcast_tools::render::Camera;

const TRI: Surface = Surface::Triangles;

/// Wrong: hit/miss, flags or the hit point (by more than 1e-3 texel) differ.
fn differs<R: Real>(a: &Trace<R>, oracle: &Trace<f64>) -> bool {
    match (&a.hit, &oracle.hit) {
        (None, None) => false,
        (Some(a), Some(b)) => {
            let p = R::xyz(a.point).map(|v| v.to_f64());
            let d = [0, 1, 2].map(|k| p[k] - [b.point.x, b.point.y, b.point.z][k]);
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() > 1e-3 || a.flags != b.flags
        }
        _ => true,
    }
}

/// The oracle's hit is a touch: the ray meets the surface without going under it.
fn touch(hf: &HeightField, q: &Query<f64>, oracle: &Trace<f64>, eps: f64) -> bool {
    let Some(hit) = oracle.hit else {
        return false;
    };
    let d = q.dir();
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [1e-4, 1e-3, 1e-2].iter().all(|s| {
        let p = q.at(hit.t + s / len);
        p[2] - TRI.height_at(hf, p[0], p[1]) >= -eps
    })
}

/// Bakes on two threads (row halves).
fn bake(hf: &HeightField, scratch: &[f32], variant: Variant) -> Vec<u8> {
    let opts = Options {
        variant,
        ..Options::default()
    };
    let mut out = vec![0u8; safety::map_len(hf.width(), hf.height(), variant)];
    let row = hf.width() as usize * variant.channels();
    let half = hf.height() / 2;
    let (a, b) = out.split_at_mut(half as usize * row);
    std::thread::scope(|s| {
        s.spawn(|| safety::bake_rows(hf, scratch, 0..half, opts, a).unwrap());
        safety::bake_rows(hf, scratch, half..hf.height(), opts, b).unwrap();
    });
    out
}

#[test]
fn safety_exact_on_every_map() {
    let maps = list_maps();
    if maps.is_empty() {
        println!("no maps found in the shared data folder: nothing to check");
        return;
    }
    let mut total_wrong = 0;
    for info in &maps {
        let big = info.width * info.height > 4_000_000;
        for depth_frac in [0.1f32, 0.05] {
            let depth = depth_frac * info.width.max(info.height) as f32;
            let map = load_map(&info.path, Some(depth)).expect("map loads");
            let hf: HeightField = map.field();
            let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
            safety::prepare(&hf, &mut scratch).unwrap();
            let z = 1f64
                .max(hf.max_height().abs().into())
                .max(hf.min_height().abs().into());
            let eps = z / 8192.0;
            let mut rays: Vec<Query<f32>> = Vec::new();
            let (cw, ch, nr) = if big { (24, 20, 600) } else { (40, 32, 1500) };
            for elevation in [45.0, 5.0] {
                rays.extend(Camera::orbit(&hf, elevation, 200.0, cw, ch).rays());
            }
            rays.extend(random_rays(&hf, nr, 11));
            let oracles: Vec<Trace<f64>> = rays
                .iter()
                .map(|q| dda::trace(&hf, TRI, &q.cast::<f64>()))
                .collect();
            for variant in [Variant::Directional, Variant::Isotropic] {
                let data = bake(&hf, &scratch, variant);
                let sd = SafetyMap::new(&hf, &data, variant).unwrap();
                let mean_sd = data.iter().map(|&v| f64::from(v)).sum::<f64>() / data.len() as f64;
                let (mut wrong, mut ambiguous, mut differ_amb, mut hits) = (0, 0, 0, 0);
                let (mut f_dda, mut f_sd) = (0u64, 0u64);
                for (q, oracle) in rays.iter().zip(&oracles) {
                    let q64 = q.cast::<f64>();
                    let amb = oracle.clearance.abs() < eps || touch(&hf, &q64, oracle, eps);
                    ambiguous += usize::from(amb);
                    hits += usize::from(oracle.hit.is_some());
                    f_dda += u64::from(dda::trace(&hf, TRI, q).fetches);
                    let s32 = safety::trace(&sd, &hf, q);
                    let s64 = safety::trace(&sd, &hf, &q64);
                    f_sd += u64::from(s32.fetches);
                    let bad = differs(&s32, oracle) || differs(&s64, oracle);
                    if bad && amb {
                        differ_amb += 1;
                    } else if bad {
                        wrong += 1;
                        if wrong <= 3 {
                            println!("    wrong: {q:?} got {:?} oracle {:?}", s32.hit, oracle.hit);
                        }
                    }
                }
                println!(
                    "{:<34} depth {depth_frac:<4} {variant:<11?} tried {:>5}  wrong {wrong}  \
                     ambiguous {ambiguous:>2} (differ {differ_amb})  hits {hits:>5}  mean SD \
                     {mean_sd:.2}  fetches/ray dda {:.1} sd {:.1}",
                    info.name,
                    rays.len(),
                    f_dda as f64 / rays.len() as f64,
                    f_sd as f64 / rays.len() as f64
                );
                total_wrong += wrong;
            }
        }
    }
    assert_eq!(total_wrong, 0, "wrong rays");
}
