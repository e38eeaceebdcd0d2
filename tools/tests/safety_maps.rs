//! Safety distances on a centred window (at most 256 × 256) of every real map of
//! `../shared/data`, at depths 0.1 and 0.05 × max(W, H): zero wrong rays against the f64 exact DDA on the triangle surface, for
//! camera rays at 45° and 5° and random rays (all directions, upward included) inside
//! the box, directional and isotropic, marched in f32 and f64; and the same for the
//! cylinder–cone maps (exact and N-buffer slopes).

mod common;

use common::{
    ambiguity_eps, bake_halves, differs, maps, oracle_traces, test_rays, touch, touch_on, window,
};
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, MarchSurface, Options, SafetyMap, Variant};
use hfcast::{dda, HeightField, Query, Surface};
use hfcast_tools::maps::load_map;

const TRI: Surface = Surface::Triangles;

/// Bakes on two threads (row halves).
fn bake(hf: &HeightField, scratch: &[f32], variant: Variant) -> Vec<u8> {
    let opts = Options {
        variant,
        ..Options::default()
    };
    let mut out = vec![0u8; safety::map_len(hf.width(), hf.height(), variant)];
    let row = hf.width() as usize * variant.channels();
    bake_halves(&mut out, row, hf.height(), |rows, part| {
        safety::bake_rows(hf, scratch, rows, opts, part).unwrap()
    });
    out
}

/// Bakes a cylinder–cone map on two threads (row halves).
fn bake_cc(hf: &HeightField, scratch: &[f32], nb: &[f32], opts: CcOptions) -> Vec<u8> {
    let mut out = vec![0u8; cc::map_len(hf.width(), hf.height())];
    let row = hf.width() as usize * cc::BYTES_PER_TEXEL;
    bake_halves(&mut out, row, hf.height(), |rows, part| {
        cc::bake_rows(hf, scratch, nb, rows, opts, part).unwrap()
    });
    out
}

#[test]
fn safety_exact_on_every_map() {
    let mut total_wrong = 0;
    for info in &maps() {
        for depth_frac in [0.1f32, 0.05] {
            let depth = depth_frac * info.width.max(info.height) as f32;
            let map = load_map(&info.path, Some(depth)).expect("map loads");
            // Each map is checked on a centred window of at most 256 x 256 of its real
            // data (a view with the full row stride): whole-map bakes of the exact
            // cylinder-cone slope take seconds each and belong to the benchmark, which
            // also counts wrong rays on the full maps.
            let hf = window(&map);
            let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
            safety::prepare(&hf, &mut scratch).unwrap();
            let eps = ambiguity_eps(&hf);
            let rays = test_rays(&hf);
            let oracles = oracle_traces(&hf, &rays);
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

/// §7 on the real maps: the same maps marched to the view-linear surface (directional
/// SD, CC with N-buffer slopes) against the f64 exact DDA on that surface, depth 0.1.
#[test]
fn view_linear_exact_on_every_map() {
    let vl = Surface::ViewLinear;
    let mut total_wrong = 0;
    for info in &maps() {
        let depth = 0.1 * info.width.max(info.height) as f32;
        let map = load_map(&info.path, Some(depth)).expect("map loads");
        let hf = window(&map);
        let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
        safety::prepare(&hf, &mut scratch).unwrap();
        let cap = 16;
        let mut nb = vec![0f32; cc::nbuffer_len(hf.width(), hf.height(), cap)];
        cc::prepare_nbuffer(&hf, cap, &mut nb).unwrap();
        let sd_data = bake(&hf, &scratch, Variant::Directional);
        let sd = SafetyMap::new(&hf, &sd_data, Variant::Directional).unwrap();
        let opts = CcOptions {
            slope: Slope::NBuffer,
            cap,
        };
        let cc_data = bake_cc(&hf, &scratch, &nb, opts);
        let ccm = CcMap::new(&hf, &cc_data, cap).unwrap();
        let eps = ambiguity_eps(&hf);
        let rays = test_rays(&hf);
        let (mut wrong, mut ambiguous, mut differ_amb) = (0, 0, 0);
        for q in &rays {
            let q64 = q.cast::<f64>();
            let oracle = dda::trace(&hf, vl, &q64);
            let amb = oracle.clearance.abs() < eps || touch_on(&hf, vl, &q64, &oracle, eps);
            ambiguous += usize::from(amb);
            let m = MarchSurface::ViewLinear;
            let got = [
                safety::trace_on(&sd, &hf, m, q).hit.is_some(),
                cc::trace_on(&ccm, &hf, m, q).hit.is_some(),
            ];
            let bad = differs(&safety::trace_on(&sd, &hf, m, q), &oracle)
                || differs(&safety::trace_on(&sd, &hf, m, &q64), &oracle)
                || differs(&cc::trace_on(&ccm, &hf, m, q), &oracle)
                || differs(&cc::trace_on(&ccm, &hf, m, &q64), &oracle);
            differ_amb += usize::from(bad && amb);
            if bad && !amb {
                wrong += 1;
                if wrong <= 3 {
                    println!("    wrong: {q:?} got {got:?} oracle {:?}", oracle.hit);
                }
            }
        }
        println!(
            "{:<34} view-linear  tried {:>5}  wrong {wrong}  ambiguous {ambiguous} (differ \
             {differ_amb})",
            info.name,
            rays.len()
        );
        total_wrong += wrong;
    }
    assert_eq!(total_wrong, 0, "wrong rays on the view-linear surface");
}
