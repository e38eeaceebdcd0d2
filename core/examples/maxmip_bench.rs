//! Maximum-mipmap benchmark: bake and update times, then fetches per ray and rays per
//! second (single thread) of the hierarchical march against the naive exact DDA, on the
//! same rays, for two map sizes. Medians of several repetitions.
//!
//! `cargo run --release -p hfcast --example maxmip_bench [-- --size WxH --random N --reps N]`
//! (defaults 640x512 camera rays, 100000 random rays, 5 repetitions; the DDA gets at
//! most 3). Maps are read from `../shared/data` (or `$HFCAST_DATA`).

mod common;
use common::{camera_rays, in_bands, load_png, median, options, parse_size, wall};
use hfcast::maxmip::{self, Ascent, Layout, MaxMip, Options};
use hfcast::rng::SplitMix;
use hfcast::{dda, HeightField, Query, Surface, Trace};
use std::hint::black_box;
use std::time::Instant;

/// CPU time of this thread in seconds (Linux: `/proc/thread-self/schedstat`), so that
/// other work on a shared machine does not count; `None` elsewhere.
fn thread_cpu() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

/// Seconds of one call of `f`: median of `reps` runs of at least 0.2 s each (repeating
/// `f`), in this thread's CPU time where available (the kernel updates it every few
/// milliseconds), else wall clock. Multi-threaded work is timed by [`wall`].
fn time(reps: usize, mut f: impl FnMut()) -> f64 {
    let t = Instant::now();
    f();
    let once = t.elapsed().as_secs_f64();
    let k = (0.2 / once.max(1e-9)).ceil().max(1.0) as usize;
    let now = || thread_cpu().unwrap_or_else(|| t.elapsed().as_secs_f64());
    median(
        (0..reps)
            .map(|_| {
                let t0 = now();
                for _ in 0..k {
                    f();
                }
                (now() - t0) / k as f64
            })
            .collect(),
    )
}

/// Heights, width and height of a map.
type Map = (Vec<f32>, u32, u32);

/// A 16-bit grayscale PNG as heights `png / 65535 × 0.1 · max(W, H)`.
fn load_heights(name: &str) -> Option<Map> {
    let (v, w, h) = load_png(name)?;
    let mut heights = vec![0f32; (w * h) as usize];
    let depth = 0.1 * w.max(h) as f32;
    HeightField::from_u16(&v, w, h, w as usize, depth, &mut heights).ok()?;
    Some((heights, w, h))
}

/// A synthetic `n × n` fractal-ish field: separable waves of falling amplitude plus
/// hashed noise, heights up to about 0.1 · n.
fn synthetic(n: u32) -> Vec<f32> {
    let mut rng = SplitMix::from_state(17);
    let waves: Vec<(Vec<f32>, Vec<f32>)> = (0..8)
        .map(|k| {
            let f = 0.004 * 2f64.powi(k);
            let (px, py) = (rng.range(0.0, 6.3), rng.range(0.0, 6.3));
            let a = 0.05 * n as f64 / 1.8f64.powi(k);
            let xs = (0..n)
                .map(|i| (a * (f * i as f64 + px).sin()) as f32)
                .collect();
            let ys = (0..n)
                .map(|j| (f * j as f64 * 1.3 + py).sin() as f32)
                .collect();
            (xs, ys)
        })
        .collect();
    let mut out = vec![0f32; (n * n) as usize];
    for (j, row) in out.chunks_exact_mut(n as usize).enumerate() {
        for (xs, ys) in &waves {
            for (o, x) in row.iter_mut().zip(xs) {
                *o += x * ys[j];
            }
        }
        for (i, o) in row.iter_mut().enumerate() {
            let hsh = (i as u32 ^ (j as u32).wrapping_mul(0x9E37_79B9)).wrapping_mul(0x85EB_CA6B);
            *o += 0.05 * n as f32 + (hsh >> 8) as f32 / (1 << 24) as f32;
        }
    }
    out
}

/// Bakes with `threads` threads, each level split into row bands ([`maxmip::bake`],
/// which bakes the finest levels band by band, for one thread).
fn bake_threads(hf: &HeightField, pyramid: &mut [f32], threads: u32) {
    if threads == 1 {
        return maxmip::bake(hf, pyramid).unwrap();
    }
    let layout = Layout::of(hf);
    for level in 0..layout.levels() {
        let [w, h] = layout.dims(level);
        let (finer, out) = layout.split_level(pyramid, level);
        if threads == 1 || h < 64 {
            maxmip::bake_rows(hf, level, 0..h, finer, out);
            continue;
        }
        in_bands(out, w as usize, h, threads, |rows, part| {
            maxmip::bake_rows(hf, level, rows, finer, part)
        });
    }
}

/// `n` rays with origins uniform in the field's box and directions uniform on the sphere.
fn random_rays(hf: &HeightField, n: usize) -> Vec<Query<f32>> {
    let mut rng = SplitMix::from_state(99);
    let (w, h) = ((hf.width() - 1) as f64, (hf.height() - 1) as f64);
    let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
    (0..n)
        .map(|_| {
            let o = [rng.range(0.0, w), rng.range(0.0, h), rng.range(zmin, zmax)];
            let z: f64 = rng.range(-1.0, 1.0);
            let a = rng.range(0.0, std::f64::consts::TAU);
            let r = (1.0 - z * z).sqrt();
            let d = [r * a.cos(), r * a.sin(), z];
            Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .unwrap()
        })
        .collect()
}

/// One method's figures on one ray set.
struct Row {
    fetches: f64,
    ns: f64,
    hits: usize,
    /// Against the reference (the DDA; the exact march for LOD): rays whose hit point
    /// is off by more than 1e-3 texel or whose hit/miss differs (docs/DESIGN.md's wrong
    /// rays), the hit/miss changes alone, and the mean and largest hit point error.
    wrong: usize,
    hit_miss: usize,
    err: (f64, f64),
    traces: Vec<Trace<f32>>,
}

fn run(
    rays: &[Query<f32>],
    reps: usize,
    reference: Option<&[Trace<f32>]>,
    f: impl Fn(&Query<f32>) -> Trace<f32>,
) -> Row {
    let traces: Vec<Trace<f32>> = rays.iter().map(&f).collect();
    let secs = time(reps, || {
        for q in rays {
            black_box(f(black_box(q)));
        }
    });
    let fetches = traces.iter().map(|t| t.fetches as f64).sum::<f64>() / rays.len() as f64;
    let (mut wrong, mut hit_miss, mut err, mut n) = (0, 0, (0.0, 0.0f64), 0);
    for (a, b) in reference.unwrap_or(&[]).iter().zip(&traces) {
        match (a.hit, b.hit) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                let e = f64::from((a.point - b.point).length());
                wrong += usize::from(e > 1e-3);
                (err.0, err.1, n) = (err.0 + e, err.1.max(e), n + 1);
            }
            _ => (wrong, hit_miss) = (wrong + 1, hit_miss + 1),
        }
    }
    err.0 /= n.max(1) as f64;
    Row {
        fetches,
        ns: secs * 1e9 / rays.len() as f64,
        hits: traces.iter().filter(|t| t.hit.is_some()).count(),
        wrong,
        hit_miss,
        err,
        traces,
    }
}

fn main() {
    let (mut cam, mut n_random, mut reps) = ((640u32, 512u32), 100_000usize, 5usize);
    for (a, v) in options() {
        match a.as_str() {
            "--size" => cam = parse_size(&v),
            "--random" => n_random = v.parse().unwrap(),
            "--reps" => reps = v.parse().unwrap(),
            _ => panic!("unknown option {a}"),
        }
    }
    let dda_reps = reps.min(3);
    println!("## maxmip_bench: medians of {reps} repetitions (DDA {dda_reps}), single thread unless noted\n");

    // Bake and update.
    println!("| bake | size | pyramid MiB | 1 thread ms | 2 threads ms |");
    println!("|---|---|---|---|---|");
    let n = 4096;
    let synth = synthetic(n);
    let world = load_heights("dem_etopo5_world_4096x2048.png");
    let mut bakes: Vec<(&str, &[f32], u32, u32)> = vec![("synthetic", &synth, n, n)];
    if let Some((h, w, hh)) = &world {
        bakes.push(("etopo5 world", h, *w, *hh));
    }
    for (name, samples, w, h) in &bakes {
        let hf = HeightField::new(samples, *w, *h, *w as usize).unwrap();
        let mut pyr = vec![0f32; maxmip::pyramid_len(*w, *h)];
        let t1 = wall(reps, || bake_threads(&hf, &mut pyr, 1));
        let t2 = wall(reps, || bake_threads(&hf, &mut pyr, 2));
        let mut check = vec![0f32; pyr.len()];
        maxmip::bake(&hf, &mut check).unwrap();
        assert_eq!(pyr, check);
        let mib = pyr.len() as f64 * 4.0 / (1 << 20) as f64;
        println!(
            "| {name} | {w}x{h} | {mib:.1} | {:.2} | {:.2} |",
            t1 * 1e3,
            t2 * 1e3
        );
    }
    {
        let mut samples = synth.clone();
        let hf = HeightField::new(&samples, n, n, n as usize).unwrap();
        let mut pyr = vec![0f32; maxmip::pyramid_len(n, n)];
        maxmip::bake(&hf, &mut pyr).unwrap();
        let mut rng = SplitMix::from_state(5);
        let rects: Vec<(u32, u32)> = (0..64)
            .map(|_| {
                (
                    rng.range(0.0, (n - 64) as f64) as u32,
                    rng.range(0.0, (n - 64) as f64) as u32,
                )
            })
            .collect();
        for &(x0, y0) in &rects {
            for j in y0..y0 + 64 {
                for i in x0..x0 + 64 {
                    samples[(j * n + i) as usize] += 3.0;
                }
            }
        }
        let hf = HeightField::new(&samples, n, n, n as usize).unwrap();
        let mut times = Vec::new();
        for &(x0, y0) in &rects {
            let t = Instant::now();
            maxmip::update_rect(&hf, &mut pyr, x0, y0, x0 + 64, y0 + 64).unwrap();
            times.push(t.elapsed().as_secs_f64());
        }
        let mut check = vec![0f32; pyr.len()];
        maxmip::bake(&hf, &mut check).unwrap();
        assert_eq!(pyr, check, "updates equal a re-bake");
        println!(
            "\nupdate_rect 64x64 in {n}x{n}: median {:.1} µs, max {:.1} µs (64 rectangles)",
            median(times.clone()) * 1e6,
            times.iter().cloned().fold(0.0, f64::max) * 1e6
        );
        // The new HeightField view the caller needs after changing samples validates
        // (and takes min/max of) every sample: for context.
        let t = wall(reps, || {
            black_box(HeightField::new(&samples, n, n, n as usize).unwrap());
        });
        println!(
            "(HeightField::new over {n}x{n}, re-reading every sample: {:.1} ms)",
            t * 1e3
        );
        // What a dynamic caller does instead: re-validate only the changed rectangle.
        let times: Vec<f64> = rects
            .iter()
            .map(|&(x0, y0)| {
                let t = Instant::now();
                let view = hf
                    .revalidate_rect(&samples, x0, y0, x0 + 64, y0 + 64)
                    .unwrap();
                maxmip::update_rect(&view, &mut pyr, x0, y0, x0 + 64, y0 + 64).unwrap();
                black_box(&view);
                t.elapsed().as_secs_f64()
            })
            .collect();
        println!(
            "revalidate_rect + update_rect 64x64 in {n}x{n}: median {:.1} µs, max {:.1} µs\n",
            median(times.clone()) * 1e6,
            times.iter().cloned().fold(0.0, f64::max) * 1e6
        );
    }

    // March.
    let himalaya = load_heights("dem_etopo5_himalaya_1024.png");
    let maps: Vec<(&str, &Map)> = [("himalaya", &himalaya), ("world", &world)]
        .into_iter()
        .filter_map(|(name, m)| m.as_ref().map(|m| (name, m)))
        .collect();
    println!("| map | rays | method | fetches/ray | ns/ray | Mrays/s | vs dda | hits | wrong | hit/miss | err mean / max |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, (samples, w, h)) in maps {
        let hf = HeightField::new(samples, *w, *h, *w as usize).unwrap();
        let mut pyr = vec![0f32; maxmip::pyramid_len(*w, *h)];
        maxmip::bake(&hf, &mut pyr).unwrap();
        let mip = MaxMip::new(&hf, &pyr).unwrap();
        let pixel_angle = (40f64.to_radians() / cam.1 as f64) as f32;
        let sets = [
            (
                format!("camera {}x{} 45°", cam.0, cam.1),
                camera_rays(&hf, 45.0, 200.0, cam.0, cam.1),
                true,
            ),
            (
                format!("camera {}x{} 5°", cam.0, cam.1),
                camera_rays(&hf, 5.0, 200.0, cam.0, cam.1),
                true,
            ),
            (
                format!("random {n_random} in box"),
                random_rays(&hf, n_random),
                false,
            ),
        ];
        for (set, rays, camera) in &sets {
            let s = Surface::Triangles;
            let dda = run(rays, dda_reps, None, |q| dda::trace(&hf, s, q));
            let print = |method: &str, r: &Row| {
                println!(
                    "| {name} {w}x{h} | {set} | {method} | {:.1} | {:.0} | {:.2} | {:.1}x | {} \
                     | {} | {} | {:.2} / {:.1} |",
                    r.fetches,
                    r.ns,
                    1e3 / r.ns,
                    dda.ns / r.ns,
                    r.hits,
                    r.wrong,
                    r.hit_miss,
                    r.err.0,
                    r.err.1,
                );
            };
            print("dda (naive exact)", &dda);
            let mut exact = None;
            for ascent in [Ascent::OneLevel, Ascent::Highest] {
                let opts = Options {
                    ascent,
                    ..Options::default()
                };
                let r = run(rays, reps, Some(&dda.traces), |q| {
                    maxmip::trace(&hf, &mip, s, q, &opts)
                });
                print(&format!("maxmip {ascent:?}"), &r);
                exact = Some(r);
            }
            if *camera {
                let exact = exact.unwrap();
                for k in [1.0f32, 4.0] {
                    let opts = Options {
                        lod: Some(k * pixel_angle),
                        ..Options::default()
                    };
                    let r = run(rays, reps, Some(&exact.traces), |q| {
                        maxmip::trace(&hf, &mip, s, q, &opts)
                    });
                    print(&format!("maxmip LOD {k}·pixel"), &r);
                }
            }
        }
    }
    println!(
        "\n`wrong`: hit/miss differs or the hit point is off by more than 1e-3 texel, \
         against the DDA (LOD rows: against the exact maxmip); `err` in texels."
    );
}
