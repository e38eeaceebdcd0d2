//! Bake times of cone maps, QDMs and relaxed cone maps at 256², 512², 1024² on a
//! synthetic fractal field (rows split over two threads), then fetches per ray and
//! position error against the iteration cap for cone vs QDM at 5°, 30° and 60°
//! elevation (medians over the rays that hit).
//!
//! `cargo run --release -p hfcast --example cones_bench [--relaxed-all]  (SIZES=256,512 to choose sizes)`

mod common;

use hfcast::{cone, dda, qdm, relaxed, HeightField, Query, Surface};
use std::time::Instant;

/// Bakes `rows` of a map with `texel` channels per row unit over two threads.
fn bake2(
    rows: u32,
    row_len: usize,
    out: &mut [f32],
    f: impl Fn(std::ops::Range<u32>, &mut [f32]) + Sync,
) {
    let mid = rows / 2;
    let (lo, hi) = out.split_at_mut(mid as usize * row_len);
    std::thread::scope(|s| {
        s.spawn(|| f(0..mid, lo));
        f(mid..rows, &mut hi[..(rows - mid) as usize * row_len]);
    });
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let relaxed_1024 = std::env::args().any(|a| a == "--relaxed-all");
    println!("| size | cone bake s | QDM bake s | relaxed bake s |");
    println!("|---|---|---|---|");
    let sizes: Vec<u32> = std::env::var("SIZES").map_or(vec![256, 512, 1024], |s| {
        s.split(',').map(|v| v.parse().unwrap()).collect()
    });
    for n in sizes {
        let s = common::fractal_field(n);
        let hf = HeightField::new(&s, n, n, n as usize).unwrap();
        let mut scratch = vec![0.0; cone::scratch_len(n, n)];
        cone::prepare(&hf, &mut scratch).unwrap();
        let cw = (n - 1) as usize;
        let t0 = Instant::now();
        let mut cm = vec![0.0; cone::map_len(n, n)];
        bake2(n - 1, cw * cone::CHANNELS, &mut cm, |r, o| {
            cone::bake_rows::<cone::Cone>(&hf, &scratch, r, o).unwrap()
        });
        let tc = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let mut qm = vec![0.0; qdm::map_len(n, n)];
        bake2(n - 1, cw * qdm::CHANNELS, &mut qm, |r, o| {
            cone::bake_rows::<qdm::Qdm>(&hf, &scratch, r, o).unwrap()
        });
        let tq = t0.elapsed().as_secs_f64();
        let tr = if n <= 128 || relaxed_1024 {
            let t0 = Instant::now();
            let mut rm = vec![0.0; relaxed::map_len(n, n)];
            bake2(n, n as usize, &mut rm, |r, o| {
                cone::bake_rows::<relaxed::Relaxed>(&hf, &scratch, r, o).unwrap()
            });
            format!("{:.2}", t0.elapsed().as_secs_f64())
        } else {
            "(skipped: --relaxed-all)".into()
        };
        println!("| {n}² | {tc:.2} | {tq:.2} | {tr} |");
        if n != 512 {
            continue;
        }
        // Fetches and error against the iteration cap, cone vs QDM.
        let cmap = cone::ConeMap::new(&hf, &cm).unwrap();
        let qmap = qdm::QdmMap::new(&hf, &qm).unwrap();
        println!(
            "\n512²: median fetches / median error (texels) / budget-exhausted %, by iteration cap"
        );
        println!("| elevation | cap | cone fetches | cone err | cone exh % | QDM fetches | QDM err | QDM exh % |");
        println!("|---|---|---|---|---|---|---|---|");
        for el in [5.0f64, 30.0, 60.0] {
            let e = el.to_radians();
            let rays: Vec<Query<f32>> = (0..2000)
                .map(|k| {
                    let az = k as f64 * 2.399;
                    let d = [e.cos() * az.cos(), e.cos() * az.sin(), -e.sin()];
                    let (x, y) = ((k * 37 % 491) as f64 + 10.0, (k * 91 % 487) as f64 + 12.0);
                    let z = hf.max_height() as f64 + 1.0;
                    let o = [x - d[0] * 5.0, y - d[1] * 5.0, z];
                    Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                        .unwrap()
                })
                .collect();
            let oracle: Vec<_> = rays
                .iter()
                .map(|q| dda::trace(&hf, Surface::Triangles, &q.cast::<f64>()))
                .collect();
            for cap in [4u32, 8, 16, 32, 64, 128, 1024] {
                let mut row = format!("| {el}° | {cap} |");
                for which in 0..2 {
                    let (mut f, mut err, mut exh) = (Vec::new(), Vec::new(), 0);
                    for (q, o) in rays.iter().zip(&oracle) {
                        let tr = if which == 0 {
                            cone::trace(&cmap, &hf, q, cap)
                        } else {
                            qdm::trace(&qmap, &hf, q, cap)
                        };
                        f.push(tr.fetches as f64);
                        if tr.flags.contains(hfcast::Flags::BUDGET_EXHAUSTED) {
                            exh += 1;
                        }
                        if let (Some(a), Some(b)) = (tr.hit, o.hit) {
                            let a = [a.point.x as f64, a.point.y as f64, a.point.z as f64];
                            let b = [b.point.x, b.point.y, b.point.z];
                            err.push(
                                ((a[0] - b[0]).powi(2)
                                    + (a[1] - b[1]).powi(2)
                                    + (a[2] - b[2]).powi(2))
                                .sqrt(),
                            );
                        }
                    }
                    row += &format!(
                        " {:.0} | {:.1e} | {:.1} |",
                        median(&mut f),
                        median(&mut err),
                        100.0 * exh as f64 / rays.len() as f64
                    );
                }
                println!("{row}");
            }
        }
        println!();
    }
}
