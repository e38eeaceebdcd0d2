//! Safety-distance benchmark: bake times (four classes; isotropic too) at 256², 512²,
//! 1024² (downsamples of the Himalaya map, depth 0.1 × side) and on the 4096×2048
//! world map; then fetches per ray (mean, p99, max) and rays per second, single
//! thread, of the SD march against the naive exact DDA on the same camera rays
//! (45° and 5° elevation), with wrong rays against the DDA. Medians of repetitions.
//!
//! Then the same for the cylinder–cone maps (exact and N-buffer slopes): bake times
//! and the march on the same rays, plus random rays inside the box (any direction).
//!
//! `cargo run --release -p hfcast --example safety_bench [-- --size WxH --reps N]`
//! (defaults 640x512, 5; `--maps K` keeps the first K maps, `--cc-only 1` skips the
//! SD bake table). Maps are read from `../shared/data` (or `$HFCAST_DATA`).

mod common;
use common::{camera_rays, data_dir, median, wall};
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, Options, SafetyMap, Variant};
use hfcast::{dda, HeightField, Query, Surface, Trace};
use std::hint::black_box;
use std::time::Instant;

/// A 16-bit PNG as raw values, width, height.
fn load_png(name: &str) -> Option<(Vec<u16>, u32, u32)> {
    let file = std::fs::File::open(data_dir().join(name)).ok()?;
    let limits = png::Limits { bytes: 1 << 31 };
    let mut reader = png::Decoder::new_with_limits(std::io::BufReader::new(file), limits)
        .read_info()
        .ok()?;
    let mut buf = vec![0u8; reader.output_buffer_size()?];
    let frame = reader.next_frame(&mut buf).ok()?;
    assert_eq!(frame.bit_depth, png::BitDepth::Sixteen, "16-bit expected");
    let v = buf[..frame.buffer_size()]
        .chunks_exact(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect();
    Some((v, frame.width, frame.height))
}

/// Every `step`-th sample of `raw` (`w` wide), as heights `v / 65535 × 0.1 · side`.
fn downsample(raw: &[u16], w: u32, h: u32, step: u32) -> (Vec<f32>, u32, u32) {
    let (nw, nh) = (w.div_ceil(step), h.div_ceil(step));
    let depth = 0.1 * nw.max(nh) as f32;
    let mut out = Vec::with_capacity((nw * nh) as usize);
    for j in 0..nh {
        for i in 0..nw {
            out.push(raw[(j * step * w + i * step) as usize] as f32 / 65535.0 * depth);
        }
    }
    (out, nw, nh)
}

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
    let band = hf.height().div_ceil(threads);
    std::thread::scope(|s| {
        for (k, chunk) in out.chunks_mut(band as usize * row).enumerate() {
            let r0 = k as u32 * band;
            let rows = r0..(r0 + band).min(hf.height());
            s.spawn(move || safety::bake_rows(hf, scratch, rows, opts, chunk).unwrap());
        }
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
    let t = Instant::now();
    safety::prepare(hf, scratch).unwrap();
    cc::prepare_nbuffer(hf, opts.cap, nb).unwrap();
    let tp = t.elapsed().as_secs_f64();
    let (scratch, nb) = (&*scratch, &*nb);
    let row = hf.width() as usize * cc::BYTES_PER_TEXEL;
    let band = hf.height().div_ceil(threads);
    let t = Instant::now();
    std::thread::scope(|s| {
        for (k, chunk) in out.chunks_mut(band as usize * row).enumerate() {
            let r0 = k as u32 * band;
            let rows = r0..(r0 + band).min(hf.height());
            s.spawn(move || cc::bake_rows(hf, scratch, nb, rows, opts, chunk).unwrap());
        }
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

/// Fetches (mean, p99, max), ns per ray (median of `reps`) and the traces.
fn run(
    rays: &[Query<f32>],
    reps: usize,
    f: impl Fn(&Query<f32>) -> Trace<f32>,
) -> (f64, u32, u32, f64, Vec<Trace<f32>>) {
    let traces: Vec<Trace<f32>> = rays.iter().map(&f).collect();
    let secs = wall(reps, || {
        for q in rays {
            black_box(f(black_box(q)));
        }
    });
    let mut fetches: Vec<u32> = traces.iter().map(|t| t.fetches).collect();
    fetches.sort_unstable();
    let mean = fetches.iter().map(|&v| v as f64).sum::<f64>() / rays.len() as f64;
    let p99 = fetches[(fetches.len() * 99 / 100).min(fetches.len() - 1)];
    let max = *fetches.last().unwrap();
    (mean, p99, max, secs * 1e9 / rays.len() as f64, traces)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut cam, mut reps) = ((640u32, 512u32), 5usize);
    let (mut nmaps, mut cc_only) = (4usize, false);
    while let Some(a) = args.next() {
        let v = args.next().expect("option value");
        match a.as_str() {
            "--size" => {
                let (w, h) = v.split_once('x').expect("WxH");
                cam = (w.parse().unwrap(), h.parse().unwrap());
            }
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
            let base = dda_r.3;
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
            ];
            let reference = &rows[0].1 .4;
            for (method, r) in &rows {
                let wrong = reference
                    .iter()
                    .zip(&r.4)
                    .filter(|(a, b)| match (a.hit, b.hit) {
                        (None, None) => false,
                        (Some(a), Some(b)) => (a.point - b.point).length() > 1e-3,
                        _ => true,
                    })
                    .count();
                println!(
                    "| {name} | {label} | {method} | {:.1} | {} | {} | {:.0} | {:.2} (×{:.1}) | {wrong} |",
                    r.0,
                    r.1,
                    r.2,
                    r.3,
                    1e3 / r.3,
                    base / r.3
                );
            }
        }
    }
}
