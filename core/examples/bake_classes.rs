//! Bake time of the safety-distance and cylinder–cone maps when a scene casts only
//! some ray classes ([`Scene::bake_plan`](hfcast::scene::Scene::bake_plan)): every
//! class, two, one, and the bytes of each map (it holds the baked classes' rows only). One thread, median of `reps` runs, on a 512 × 512 fractal field
//! (sums of sines; no data files needed).
//!
//! `cargo run --release -p hfcast --example bake_classes [side] [reps]`

mod common;

use common::wall;
use hfcast::safety::cc::{self, CcOptions};
use hfcast::safety::{self, AllRays, Options, Variant};
use hfcast::scene::RayClasses;
use hfcast::{HeightField, RayClass};

fn main() {
    let mut args = std::env::args().skip(1);
    let side: u32 = args.next().map_or(512, |a| a.parse().expect("side"));
    let reps: usize = args.next().map_or(3, |a| a.parse().expect("reps"));
    let heights: Vec<f32> = (0..side * side)
        .map(|k| {
            let (x, y) = (f64::from(k % side), f64::from(k / side));
            let s: f64 = (0..6)
                .map(|o| {
                    let f = 0.013 * 2f64.powi(o);
                    (f * x + 1.3 * f64::from(o)).sin() * (0.8 * f * y + 0.7).cos() * 40.0
                        / 1.9f64.powi(o)
                })
                .sum();
            s as f32
        })
        .collect();
    let hf = HeightField::new(&heights, side, side, side as usize).expect("field");
    let mut scratch = vec![0.0; safety::scratch_len(side, side)];
    safety::prepare(&hf, &mut scratch).expect("prepare");
    let two = RayClasses::NONE.with(RayClass::XPos).with(RayClass::YNeg);
    let one = RayClasses::NONE.with(RayClass::XPos);
    println!("{side} x {side} field, one thread, median of {reps}");
    println!("| bake | classes | bytes | ms | vs all |");
    println!("|---|---|---:|---:|---:|");
    let sd = |name: &str, classes: RayClasses, variant: Variant, base: f64| -> f64 {
        let opts = Options {
            variant,
            ..Options::default()
        };
        let mut out = vec![0u8; safety::map_len_classes(side, side, variant, classes)];
        let s = wall(reps, || {
            safety::bake_rows_classes(&hf, &scratch, &AllRays, classes, 0..side, opts, &mut out)
                .expect("bake");
        });
        let base = if base > 0.0 { base } else { s };
        println!(
            "| {name} | {} | {} | {:.1} | {:.2} |",
            classes.count(),
            out.len(),
            s * 1e3,
            s / base
        );
        s
    };
    let all = sd("SD directional", RayClasses::ALL, Variant::Directional, 0.0);
    sd("SD directional", two, Variant::Directional, all);
    sd("SD isotropic", one, Variant::Isotropic, all);
    let opts = CcOptions::default();
    let mut nb = vec![0.0; cc::nbuffer_len(side, side, opts.cap)];
    cc::prepare_nbuffer(&hf, opts.cap, &mut nb).expect("n-buffer");
    let ccb = |classes: RayClasses, base: f64| -> f64 {
        let mut out = vec![0u8; cc::map_len_classes(side, side, classes)];
        let s = wall(reps, || {
            cc::bake_rows_classes(&hf, &scratch, &nb, classes, 0..side, opts, &mut out)
                .expect("bake");
        });
        let base = if base > 0.0 { base } else { s };
        println!(
            "| CC exact slope | {} | {} | {:.1} | {:.2} |",
            classes.count(),
            out.len(),
            s * 1e3,
            s / base
        );
        s
    };
    let all = ccb(RayClasses::ALL, 0.0);
    ccb(two, all);
    ccb(one, all);
}
