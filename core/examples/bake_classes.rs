//! Bake time of the safety-distance and cylinder–cone maps when a scene casts only
//! some ray classes ([`Scene::bake_plan`](hfcast::scene::Scene::bake_plan)): every
//! class, two, one, and the bytes of each map (it holds the baked classes' rows only). One thread, median of `reps` runs, on a 512 × 512 fractal field
//! (sums of sines; no data files needed).
//!
//! `cargo run --release -p hfcast --example bake_classes [side] [reps]`

mod common;

use common::wall;
use hfcast::bake::Spec;
use hfcast::ktx2::{DataMut, Desc, MapKind};
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
    let two = RayClasses::NONE.with(RayClass::XPos).with(RayClass::YNeg);
    let one = RayClasses::NONE.with(RayClass::XPos);
    println!("{side} x {side} field, one thread, median of {reps}");
    println!("| bake | classes | bytes | ms | vs all |");
    println!("|---|---|---:|---:|---:|");
    // Times the row bake of the map `map` holding `classes` only (its scratch filled
    // beforehand) and prints its line; `base` is the time of the bake of every class
    // (0: this one).
    let bake = |name: &str, map: MapKind, classes: RayClasses, base: f64| -> f64 {
        let spec = Spec::new(Desc {
            classes,
            ..Desc::new(map, side, side)
        });
        let mut scratch = vec![0.0; spec.scratch_len()];
        spec.prepare(&hf, &mut scratch).expect("prepare");
        let mut out = vec![0u8; spec.map_len().expect("map size")];
        let s = wall(reps, || {
            let rows = 0..spec.rows();
            spec.bake_rows(&hf, &scratch, rows, DataMut::U8(&mut out))
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
    let all = bake("SD directional", MapKind::Safety, RayClasses::ALL, 0.0);
    bake("SD directional", MapKind::Safety, two, all);
    bake("SD isotropic", MapKind::SafetyIsotropic, one, all);
    let all = bake("CC exact slope", MapKind::Cc, RayClasses::ALL, 0.0);
    bake("CC exact slope", MapKind::Cc, two, all);
    bake("CC exact slope", MapKind::Cc, one, all);
}
