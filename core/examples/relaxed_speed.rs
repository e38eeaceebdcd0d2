//! Bake times of the relaxed cone map (two threads, rows in bands) on the synthetic
//! field of `cones_bench`, the himalaya DEM downsampled to the size and centred crops
//! of the data maps (heights 0.1 × the full map's larger side, as in
//! `tools/tests/cones_maps.rs`), with the process's CPU seconds beside the wall clock
//! (the machine may be shared).
//!
//! `cargo run --release -p hfcast --example relaxed_speed -- [--sizes 64,128]
//! [--maps synth,himalaya,spike,FILE.png] [--threads 2] [--brute 1]` (a PNG of the data
//! folder gives its centred crop; `--brute 1` also runs the Θ(N⁴) oracle and checks
//! equality).

#[cfg(feature = "relaxed")]
mod common;

#[cfg(not(feature = "relaxed"))]
fn main() {
    eprintln!("needs the `relaxed` feature");
}

#[cfg(feature = "relaxed")]
use hfcast::{cone, relaxed, HeightField};
#[cfg(feature = "relaxed")]
use std::time::Instant;

#[cfg(feature = "relaxed")]
/// The `n × n` heights of map `name`, or `None` when its PNG is missing.
fn heights(name: &str, n: u32) -> Option<Vec<f32>> {
    match name {
        "synth" => Some(common::fractal_field(n)),
        "himalaya" => {
            let (raw, w, h) = common::load_png("dem_etopo5_himalaya_1024.png")?;
            let (v, nw, _) = common::downsample(&raw, w, h, (w / n).max(1));
            Some(
                (0..n * n)
                    .map(|k| v[((k / n) * nw + k % n) as usize])
                    .collect(),
            )
        }
        _ => {
            // A centred crop of a data map (`spike` for the game map).
            let file = if name == "spike" {
                "game_etr_i_like_spike_2_128x640.png"
            } else {
                name
            };
            let (raw, w, h) = common::load_png(file)?;
            let depth = 0.1 * w.max(h) as f32;
            let n = n.min(w).min(h);
            let (x0, y0) = ((w - n) / 2, (h - n) / 2);
            Some(
                (0..n * n)
                    .map(|k| {
                        let (i, j) = (x0 + k % n, y0 + k / n);
                        raw[(j * w + i) as usize] as f32 / 65535.0 * depth
                    })
                    .collect(),
            )
        }
    }
}

/// CPU seconds (user + system) of this process so far, from `/proc/self/stat` (0 where
/// it cannot be read): the bake's cost on a shared, busy machine.
#[cfg(feature = "relaxed")]
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<f64> = after
        .split_whitespace()
        .map(|v| v.parse().unwrap_or(0.0))
        .collect();
    f.get(11)
        .zip(f.get(12))
        .map_or(0.0, |(u, s)| (u + s) / 100.0)
}

#[cfg(feature = "relaxed")]
fn main() {
    let opts = common::options();
    let opt = |k: &str, d: &str| {
        opts.iter()
            .find(|(a, _)| a == k)
            .map_or(d.to_string(), |(_, v)| v.clone())
    };
    let sizes: Vec<u32> = opt("--sizes", "64,128")
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let maps = opt("--maps", "synth,himalaya,spike");
    let threads: u32 = opt("--threads", "2").parse().unwrap();
    let brute = opt("--brute", "0") == "1";
    println!("| map | size | relaxed bake s (wall) | CPU s | brute s | equal |");
    println!("|---|---|---|---|---|---|");
    for name in maps.split(',') {
        for &n in &sizes {
            let Some(s) = heights(name, n) else {
                println!("| {name} | {n}² | (missing) | | | |");
                continue;
            };
            let side = (s.len() as f64).sqrt() as u32;
            let hf = HeightField::new(&s, side, side, side as usize).unwrap();
            let mut scratch = vec![0.0; relaxed::scratch_len(side, side)];
            let (t0, c0) = (Instant::now(), cpu_s());
            hfcast::cone::prepare(&hf, &mut scratch).unwrap();
            let mut map = vec![0.0; relaxed::map_len(side, side)];
            common::in_bands(&mut map, side as usize, side, threads, |r, o| {
                cone::bake_rows::<relaxed::Relaxed>(&hf, &scratch, r, o).unwrap()
            });
            let (tr, cr) = (t0.elapsed().as_secs_f64(), cpu_s() - c0);
            let (tb, eq) = if brute {
                let t0 = Instant::now();
                let mut b = vec![0.0; relaxed::map_len(side, side)];
                relaxed::bake_brute(&hf, &mut b).unwrap();
                let same = b.iter().zip(&map).all(|(x, y)| x.to_bits() == y.to_bits());
                (
                    format!("{:.2}", t0.elapsed().as_secs_f64()),
                    same.to_string(),
                )
            } else {
                (String::new(), String::new())
            };
            let sum: f64 = map.iter().map(|&v| v as f64).sum();
            println!("| {name} | {side}² | {tr:.3} | {cr:.2} | {tb} | {eq} | (checksum {sum:.6e})");
        }
    }
}
