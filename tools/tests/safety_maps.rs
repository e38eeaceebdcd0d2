//! Safety distances on a centred window (at most 256 × 256) of every real map of
//! `../shared/data`, at depths 0.1 and 0.05 × max(W, H): zero wrong rays against the f64 exact DDA on the triangle surface, for
//! camera rays at 45° and 5° and random rays (all directions, upward included) inside
//! the box, directional and isotropic, marched in f32 and f64; and the same for the
//! cylinder–cone maps (exact and N-buffer slopes).

use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, Options, SafetyMap, Variant};
use hfcast::{dda, HeightField, Query, Real, Surface, Trace};
use hfcast_tools::bench::random_rays;
use hfcast_tools::maps::{list_maps, load_map};
use hfcast_tools::render::Camera;

const TRI: Surface = Surface::Triangles;

/// Largest side of the window of each map that the test bakes.
const WINDOW: u32 = 256;

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

/// Bakes a cylinder–cone map on two threads (row halves).
fn bake_cc(hf: &HeightField, scratch: &[f32], nb: &[f32], opts: CcOptions) -> Vec<u8> {
    let mut out = vec![0u8; cc::map_len(hf.width(), hf.height())];
    let row = hf.width() as usize * cc::BYTES_PER_TEXEL;
    let half = hf.height() / 2;
    let (a, b) = out.split_at_mut(half as usize * row);
    std::thread::scope(|s| {
        s.spawn(|| cc::bake_rows(hf, scratch, nb, 0..half, opts, a).unwrap());
        cc::bake_rows(hf, scratch, nb, half..hf.height(), opts, b).unwrap();
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
        for depth_frac in [0.1f32, 0.05] {
            let depth = depth_frac * info.width.max(info.height) as f32;
            let map = load_map(&info.path, Some(depth)).expect("map loads");
            // Each map is checked on a centred window of at most 256 x 256 of its real
            // data (a view with the full row stride): whole-map bakes of the exact
            // cylinder-cone slope take seconds each and belong to the benchmark, which
            // also counts wrong rays on the full maps.
            let (w, h) = (map.width.min(WINDOW), map.height.min(WINDOW));
            let (x0, y0) = ((map.width - w) as usize / 2, (map.height - h) as usize / 2);
            let stride = map.width as usize;
            let hf =
                HeightField::new(&map.heights[y0 * stride + x0..], w, h, stride).expect("window");
            let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
            safety::prepare(&hf, &mut scratch).unwrap();
            let z = 1f64
                .max(hf.max_height().abs().into())
                .max(hf.min_height().abs().into());
            let eps = z / 8192.0;
            let mut rays: Vec<Query<f32>> = Vec::new();
            let (cw, ch, nr) = (40, 32, 1500);
            for elevation in [45.0, 5.0] {
                rays.extend(Camera::orbit(&hf, elevation, 200.0, cw, ch).rays());
            }
            rays.extend(random_rays(&hf, nr, 11));
            let oracles: Vec<Trace<f64>> = rays
                .iter()
                .map(|q| dda::trace(&hf, TRI, &q.cast::<f64>()))
                .collect();
            // A short cone reach keeps the test's bake time down (the march is exact
            // for any reach; the benchmark uses the default).
            let cap = 16;
            let mut nb = vec![0f32; cc::nbuffer_len(hf.width(), hf.height(), cap)];
            cc::prepare_nbuffer(&hf, cap, &mut nb).unwrap();
            let variants = [
                Some(Variant::Directional),
                Some(Variant::Isotropic),
                None,
                None,
            ];
            for (vi, variant) in variants.into_iter().enumerate() {
                let slope = if vi == 2 {
                    Slope::Exact
                } else {
                    Slope::NBuffer
                };
                let opts = CcOptions { slope, cap };
                let (data, cdata) = match variant {
                    Some(v) => (bake(&hf, &scratch, v), Vec::new()),
                    None => (Vec::new(), bake_cc(&hf, &scratch, &nb, opts)),
                };
                let sd = variant.map(|v| SafetyMap::new(&hf, &data, v).unwrap());
                let ccm = CcMap::new(&hf, &cdata, cap).ok();
                let label = match variant {
                    Some(v) => format!("{v:?}"),
                    None => format!("CC {slope:?}"),
                };
                let tr32 = |q: &Query<f32>| match (&sd, &ccm) {
                    (Some(m), _) => safety::trace(m, &hf, q),
                    (None, Some(m)) => cc::trace(m, &hf, q),
                    _ => unreachable!(),
                };
                let tr64 = |q: &Query<f64>| match (&sd, &ccm) {
                    (Some(m), _) => safety::trace(m, &hf, q),
                    (None, Some(m)) => cc::trace(m, &hf, q),
                    _ => unreachable!(),
                };
                let mean_sd = if variant.is_some() {
                    data.iter().map(|&v| f64::from(v)).sum::<f64>() / data.len() as f64
                } else {
                    cdata.chunks(4).map(|b| f64::from(b[0])).sum::<f64>() / (cdata.len() / 4) as f64
                };
                let (mut wrong, mut ambiguous, mut differ_amb, mut hits) = (0, 0, 0, 0);
                let (mut f_dda, mut f_sd) = (0u64, 0u64);
                for (q, oracle) in rays.iter().zip(&oracles) {
                    let q64 = q.cast::<f64>();
                    let amb = oracle.clearance.abs() < eps || touch(&hf, &q64, oracle, eps);
                    ambiguous += usize::from(amb);
                    hits += usize::from(oracle.hit.is_some());
                    f_dda += u64::from(dda::trace(&hf, TRI, q).fetches);
                    let s32 = tr32(q);
                    let s64 = tr64(&q64);
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
                    "{:<34} depth {depth_frac:<4} {label:<11} tried {:>5}  wrong {wrong}  \
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
