//! Safety-distance benchmark: bake times (four classes; isotropic too) at 256², 512²,
//! 1024² (downsamples of the Himalaya map, depth 0.1 × side) and on the 4096×2048
//! world map; then fetches per ray (mean, p99, max) and rays per second, single
//! thread, of the SD march against the naive exact DDA on the same camera rays
//! (45° and 5° elevation), with wrong rays against the DDA. Medians of repetitions.
//!
//! Then the same for the cylinder–cone maps (exact and N-buffer slopes): bake times
//! and the march on the same rays, plus random rays inside the box (any direction).
//! For each camera also the exact-slope map of the ray classes its rays use only
//! (what a scene of that camera bakes, [`Scene::bake_plan`](hfcast::scene::Scene)),
//! with its bytes.
//!
//! `cargo run --release -p hfcast --example safety_bench [-- --size WxH --reps N]`
//! (defaults 640x512, 5; `--maps K` keeps the first K maps, `--cc-only 1` skips the
//! SD bake table). Maps are read from `../shared/data` (or `$HFCAST_DATA`).

mod common;
use common::{camera_rays, downsample, in_bands, load_png, median, options, parse_size, run, wall};
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, Options, SafetyMap, Variant};
use hfcast::scene::RayClasses;
use hfcast::{dda, HeightField, Query, RayClass, Surface};
use std::time::Instant;

/// Bakes with `threads` threads splitting the rows.
fn bake_threads(
    hf: &HeightField,
    scratch: &mut [f32],
    opts: Options,
    out: &mut [u8],
    threads: u32,
) {
    safety::prepare(hf, scratch).unwrap();
    let scratch = &*scratch;
    let row = hf.width() as usize * opts.variant.channels();
    in_bands(out, row, hf.height(), threads, |rows, part| {
        safety::bake_rows(hf, scratch, rows, opts, part).unwrap()
    });
}

/// Bakes a cylinder–cone map with `threads` threads (both scratches prepared first,
/// one thread); returns (prepare seconds, bake seconds).
fn bake_cc_threads(
    hf: &HeightField,
    scratch: &mut [f32],
    nb: &mut [f32],
    opts: CcOptions,
    out: &mut [u8],
    threads: u32,
) -> (f64, f64) {
    bake_cc_classes(hf, scratch, nb, opts, RayClasses::ALL, out, threads)
}

/// [`bake_cc_threads`] for a map of the ray classes `classes` only.
fn bake_cc_classes(
    hf: &HeightField,
    scratch: &mut [f32],
    nb: &mut [f32],
    opts: CcOptions,
    classes: RayClasses,
    out: &mut [u8],
    threads: u32,
) -> (f64, f64) {
    let t = Instant::now();
    safety::prepare(hf, scratch).unwrap();
    cc::prepare_nbuffer(hf, opts.cap, nb).unwrap();
    let tp = t.elapsed().as_secs_f64();
    let (scratch, nb) = (&*scratch, &*nb);
    let row = cc::map_len_classes(hf.width(), 1, classes);
    let t = Instant::now();
    in_bands(out, row, hf.height(), threads, |rows, part| {
        cc::bake_rows_classes(hf, scratch, nb, classes, rows, opts, part).unwrap()
    });
    (tp, t.elapsed().as_secs_f64())
}

/// `n` random rays: origins uniform in the field's box, directions uniform on the
/// sphere (upward ones included).
fn random_rays(hf: &HeightField, n: usize, seed: u64) -> Vec<Query<f32>> {
    let mut x = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
    (0..n)
        .map(|_| {
            let o = [
                next() * (hf.width() - 1) as f64,
                next() * (hf.height() - 1) as f64,
                zmin + next() * (zmax - zmin),
            ];
            let z = 2.0 * next() - 1.0;
            let a = next() * std::f64::consts::TAU;
            let s = (1.0 - z * z).sqrt();
            let d = [s * a.cos(), s * a.sin(), z];
            Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .unwrap()
        })
        .collect()
}

fn main() {
    let (mut cam, mut reps) = ((640u32, 512u32), 5usize);
    let (mut nmaps, mut cc_only) = (4usize, false);
    for (a, v) in options() {
        match a.as_str() {
            "--size" => cam = parse_size(&v),
            "--reps" => reps = v.parse().unwrap(),
            "--maps" => nmaps = v.parse().unwrap(),
            "--cc-only" => cc_only = v == "1",
            _ => panic!("unknown option {a}"),
        }
    }
    let (raw, rw, rh) = load_png("dem_etopo5_himalaya_1024.png").expect("himalaya map");
    let mut maps: Vec<(String, Vec<f32>, u32, u32)> = [4, 2, 1]
        .into_iter()
        .map(|s| {
            let (v, w, h) = downsample(&raw, rw, rh, s);
            (format!("himalaya {w}x{h}"), v, w, h)
        })
        .collect();
    if nmaps > 3 {
        if let Some((raw, w, h)) = load_png("dem_etopo5_world_4096x2048.png") {
            let (v, w, h) = downsample(&raw, w, h, 1);
            maps.push((format!("world {w}x{h}"), v, w, h));
        }
    }
    maps.truncate(nmaps);

    println!("## safety_bench: medians of {reps} repetitions (bake: wall clock)\n");
    println!("| map | variant | bytes/texel | prepare ms | 1 thread ms | 2 threads ms | mean SD |");
    println!("|---|---|---|---|---|---|---|");
    for (name, v, w, h) in maps.iter().filter(|_| !cc_only) {
        let hf = HeightField::new(v, *w, *h, *w as usize).unwrap();
        let mut scratch = vec![0f32; safety::scratch_len(*w, *h)];
        let big = w * h > 2_000_000;
        let r = if big { reps.min(2) } else { reps };
        let tp = wall(r, || safety::prepare(&hf, &mut scratch).unwrap());
        for variant in [Variant::Directional, Variant::Isotropic] {
            let opts = Options {
                variant,
                ..Options::default()
            };
            let mut out = vec![0u8; safety::map_len(*w, *h, variant)];
            let t1 = if big {
                f64::NAN
            } else {
                wall(r, || bake_threads(&hf, &mut scratch, opts, &mut out, 1))
            };
            let t2 = wall(r, || bake_threads(&hf, &mut scratch, opts, &mut out, 2));
            let mean = out.iter().map(|&v| v as f64).sum::<f64>() / out.len() as f64;
            println!(
                "| {name} | {variant:?} | {} | {:.1} | {:.0} | {:.0} | {mean:.1} |",
                variant.channels(),
                tp * 1e3,
                t1 * 1e3,
                t2 * 1e3
            );
        }
    }

    let cap = CcOptions::default().cap;
    println!("\n### Cylinder–cone bake (cap {cap}; includes the SD radius; 2 threads)\n");
    println!("| map | slope | bytes/texel | prepare ms | 2 threads ms | cone share | mean r |");
    println!("|---|---|---|---|---|---|---|");
    for (name, v, w, h) in &maps {
        let hf = HeightField::new(v, *w, *h, *w as usize).unwrap();
        let mut scratch = vec![0f32; safety::scratch_len(*w, *h)];
        let mut nb = vec![0f32; cc::nbuffer_len(*w, *h, cap)];
        let mut out = vec![0u8; cc::map_len(*w, *h)];
        let r = if w * h > 2_000_000 { 1 } else { reps.min(3) };
        for slope in [Slope::Exact, Slope::NBuffer] {
            let opts = CcOptions { slope, cap };
            let mut times = Vec::new();
            for _ in 0..r {
                times.push(bake_cc_threads(
                    &hf,
                    &mut scratch,
                    &mut nb,
                    opts,
                    &mut out,
                    2,
                ));
            }
            let tp = median(times.iter().map(|t| t.0).collect());
            let tb = median(times.iter().map(|t| t.1).collect());
            let cones = out.chunks(4).filter(|b| b[1] != cc::NO_CONE).count();
            let mean_r = out.chunks(4).map(|b| b[0] as f64).sum::<f64>() / (out.len() / 4) as f64;
            println!(
                "| {name} | {slope:?} | {} | {:.0} | {:.0} | {:.2} | {mean_r:.2} |",
                cc::BYTES_PER_TEXEL,
                tp * 1e3,
                tb * 1e3,
                cones as f64 / (out.len() / 4) as f64
            );
        }
    }

    println!(
        "\n| map | rays | method | fetches mean | p99 | max | ns/ray | Mrays/s | wrong vs dda |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (name, v, w, h) in maps.iter().skip(2) {
        let hf = HeightField::new(v, *w, *h, *w as usize).unwrap();
        let mut scratch = vec![0f32; safety::scratch_len(*w, *h)];
        let dir_opts = Options::default();
        let iso_opts = Options {
            variant: Variant::Isotropic,
            ..Options::default()
        };
        let mut dir = vec![0u8; safety::map_len(*w, *h, Variant::Directional)];
        let mut iso = vec![0u8; safety::map_len(*w, *h, Variant::Isotropic)];
        bake_threads(&hf, &mut scratch, dir_opts, &mut dir, 2);
        bake_threads(&hf, &mut scratch, iso_opts, &mut iso, 2);
        let dmap = SafetyMap::new(&hf, &dir, Variant::Directional).unwrap();
        let imap = SafetyMap::new(&hf, &iso, Variant::Isotropic).unwrap();
        let mut nb = vec![0f32; cc::nbuffer_len(*w, *h, cap)];
        let mut cce = vec![0u8; cc::map_len(*w, *h)];
        let mut ccn = vec![0u8; cc::map_len(*w, *h)];
        let exact = CcOptions {
            slope: Slope::Exact,
            cap,
        };
        let nbuf = CcOptions {
            slope: Slope::NBuffer,
            cap,
        };
        bake_cc_threads(&hf, &mut scratch, &mut nb, exact, &mut cce, 2);
        bake_cc_threads(&hf, &mut scratch, &mut nb, nbuf, &mut ccn, 2);
        let emap = CcMap::new(&hf, &cce, cap).unwrap();
        let nmap = CcMap::new(&hf, &ccn, cap).unwrap();
        let n_random = (cam.0 * cam.1) as usize / 4;
        for el in [45.0, 5.0, -1.0] {
            let (rays, label) = if el < 0.0 {
                (
                    random_rays(&hf, n_random, 7),
                    format!("random {n_random} (inside box, any direction)"),
                )
            } else {
                (
                    camera_rays(&hf, el, 200.0, cam.0, cam.1),
                    format!("camera {}x{} {el}°", cam.0, cam.1),
                )
            };
            let dda_r = run(&rays, reps.min(3), |q| {
                dda::trace(&hf, Surface::Triangles, q)
            });
            let base = dda_r.ns;
            // The map a scene of these rays bakes: their classes only.
            let classes = rays.iter().fold(RayClasses::NONE, |set, q| {
                set.with(RayClass::of(q.dir()[0], q.dir()[1]))
            });
            let mut part = vec![0u8; cc::map_len_classes(*w, *h, classes)];
            let (_, tb) = bake_cc_classes(&hf, &mut scratch, &mut nb, exact, classes, &mut part, 2);
            let pmap = CcMap::with_classes(&hf, &part, cap, classes).unwrap();
            let mb = |bytes: usize| bytes as f64 / (1 << 20) as f64;
            let part_name = format!(
                "CC exact slope, {} class map ({:.1} MiB, baked in {:.2} s; all: {:.1}; heights {:.1})",
                classes.count(),
                mb(part.len()),
                tb,
                mb(cce.len()),
                mb(v.len() * 4)
            );
            let rows = [
                ("dda (naive exact)", dda_r),
                (
                    "SD directional",
                    run(&rays, reps, |q| safety::trace(&dmap, &hf, q)),
                ),
                (
                    "SD isotropic",
                    run(&rays, reps, |q| safety::trace(&imap, &hf, q)),
                ),
                (
                    "CC exact slope",
                    run(&rays, reps, |q| cc::trace(&emap, &hf, q)),
                ),
                (
                    "CC N-buffer slope",
                    run(&rays, reps, |q| cc::trace(&nmap, &hf, q)),
                ),
                (
                    part_name.as_str(),
                    run(&rays, reps, |q| cc::trace(&pmap, &hf, q)),
                ),
            ];
            let reference = &rows[0].1.traces;
            for (method, r) in &rows {
                let wrong = reference
                    .iter()
                    .zip(&r.traces)
                    .filter(|(a, b)| match (a.hit, b.hit) {
                        (None, None) => false,
                        (Some(a), Some(b)) => (a.point - b.point).length() > 1e-3,
                        _ => true,
                    })
                    .count();
                println!(
                    "| {name} | {label} | {method} | {:.1} | {} | {} | {:.0} | {:.2} (×{:.1}) | {wrong} |",
                    r.mean,
                    r.p99,
                    r.max,
                    r.ns,
                    1e3 / r.ns,
                    base / r.ns
                );
            }
        }
    }
}
