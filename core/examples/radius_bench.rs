//! Safety-radius benchmark: bake times (exact and error-tolerant radii, one byte per
//! texel) at 256², 512², 1024² (downsamples of the Himalaya map, depth 0.1 × side);
//! then, on the 1024² map, fetches per ray (mean, p99, max) and ns per ray, single
//! thread, of the radius variants against the naive exact DDA and the safety distances
//! on the same camera rays (45° and 5° elevation), with the error of each variant
//! against the f64 exact DDA: the error-vs-speed table of the tolerances. Medians of
//! repetitions.
//!
//! `cargo run --release -p hfcast --example radius_bench [-- --size WxH --reps N]`
//! (defaults 640x512, 5). Maps are read from `../shared/data` (or `$HFCAST_DATA`).

mod common;
use common::{camera_rays, downsample, in_bands, load_png, options, parse_size, run, wall, Run};
use hfcast::radius::{self, BakeOptions, Options as MarchOptions, RadiusMap, Zero};
use hfcast::safety::{self, SafetyMap, Variant};
use hfcast::{dda, HeightField, Surface, Trace};

/// The error tolerances (grid units) benchmarked.
const TOLERANCES: [f32; 4] = [0.25, 0.5, 1.0, 2.0];

/// Bakes radii with `threads` threads splitting the rows (`scratch` prepared).
fn bake_threads(
    hf: &HeightField,
    scratch: &[f32],
    opts: BakeOptions,
    out: &mut [u8],
    threads: u32,
) {
    let (w, h) = (hf.width() as usize, hf.height());
    in_bands(out, w, h, threads, |rows, part| {
        radius::bake_rows(hf, scratch, rows, opts, part).unwrap()
    });
}

/// Wrong rays against the f64 oracle (hit/miss or position by more than 1e-3 texel,
/// rays closer than docs/DESIGN.md's ambiguity threshold left out), and the mean and max
/// position error of the wrong rays that hit on both sides.
fn errors(traces: &[Trace<f32>], oracles: &[Trace<f64>], eps: f64) -> (usize, f64, f64) {
    let (mut wrong, mut n, mut sum, mut max) = (0, 0, 0.0, 0f64);
    for (t, o) in traces.iter().zip(oracles) {
        if o.clearance < eps {
            continue;
        }
        match (t.hit, o.hit) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                let e = (a.point.as_dvec3() - b.point).length();
                if e > 1e-3 {
                    wrong += 1;
                    n += 1;
                    sum += e;
                    max = max.max(e);
                }
            }
            _ => wrong += 1,
        }
    }
    (wrong, if n > 0 { sum / f64::from(n) } else { 0.0 }, max)
}

fn main() {
    let (mut cam, mut reps) = ((640u32, 512u32), 5usize);
    for (a, v) in options() {
        match a.as_str() {
            "--size" => cam = parse_size(&v),
            "--reps" => reps = v.parse().unwrap(),
            _ => panic!("unknown option {a}"),
        }
    }
    let (raw, rw, rh) = load_png("dem_etopo5_himalaya_1024.png").expect("himalaya map");
    let maps: Vec<(Vec<f32>, u32, u32)> = [4, 2, 1]
        .into_iter()
        .map(|s| downsample(&raw, rw, rh, s))
        .collect();
    let bakes: Vec<(String, f32)> = std::iter::once(("exact".to_string(), 0.0))
        .chain(TOLERANCES.map(|e| (format!("tolerant e={e}"), e)))
        .collect();

    println!(
        "## radius_bench: medians of {reps} repetitions (bakes: wall clock, 3 repetitions at \
         256², 1 from 512² on; 1 thread not run at 1024²)\n"
    );
    println!(
        "Bytes per texel: {}. Prepare = the strip bounds shared by every bake.\n",
        radius::BYTES_PER_TEXEL
    );
    println!(
        "| map | radius | prepare ms | 1 thread ms | 2 threads ms | mean radius | zero radii |"
    );
    println!("|---|---|---|---|---|---|---|");
    // The 1024² bakes, kept for the march.
    let mut radii: Vec<Vec<u8>> = Vec::new();
    for (v, w, h) in &maps {
        let hf = HeightField::new(v, *w, *h, *w as usize).unwrap();
        let mut scratch = vec![0f32; radius::scratch_len(*w, *h)];
        // The tolerant bakes take seconds from 512² on: fewer repetitions there.
        let big = w * h > 100_000;
        let r = if big { 1 } else { reps.min(3) };
        let tp = wall(reps, || radius::prepare(&hf, &mut scratch).unwrap());
        radii.clear();
        for (label, e) in &bakes {
            let opts = BakeOptions {
                tolerance: *e,
                ..BakeOptions::default()
            };
            let mut out = vec![0u8; radius::map_len(*w, *h)];
            let t1 = if w * h > 500_000 {
                f64::NAN
            } else {
                wall(r, || bake_threads(&hf, &scratch, opts, &mut out, 1))
            };
            let t2 = wall(r, || bake_threads(&hf, &scratch, opts, &mut out, 2));
            let mean = out.iter().map(|&v| f64::from(v)).sum::<f64>() / out.len() as f64;
            let zeros = out.iter().filter(|&&v| v == 0).count() as f64 / out.len() as f64;
            println!(
                "| himalaya {w}x{h} | {label} | {:.1} | {:.0} | {:.0} | {mean:.2} | {:.0}% |",
                tp * 1e3,
                t1 * 1e3,
                t2 * 1e3,
                zeros * 100.0
            );
            radii.push(out);
        }
    }

    let (v, w, h) = &maps[2];
    let hf = HeightField::new(v, *w, *h, *w as usize).unwrap();
    let mut scratch = vec![0f32; radius::scratch_len(*w, *h)];
    let maps_r: Vec<RadiusMap> = radii
        .iter()
        .map(|d| RadiusMap::new(&hf, d).unwrap())
        .collect();
    let mut sd = vec![0u8; safety::map_len(*w, *h, Variant::Directional)];
    safety::bake(&hf, &mut scratch, safety::Options::default(), &mut sd).unwrap();
    let sdm = SafetyMap::new(&hf, &sd, Variant::Directional).unwrap();
    let z = 1f64
        .max(hf.max_height().abs().into())
        .max(hf.min_height().abs().into());
    let eps = z / 8192.0;

    println!(
        "\n### March on himalaya {w}x{h}, camera {}x{}, single thread\n",
        cam.0, cam.1
    );
    println!(
        "| camera | method | fetches mean | p99 | max | ns/ray | speed-up vs dda | wrong | wrong rate | err mean | err max |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for el in [45.0, 5.0] {
        let rays = camera_rays(&hf, el, 200.0, cam.0, cam.1);
        let oracles: Vec<Trace<f64>> = rays
            .iter()
            .map(|q| dda::trace(&hf, Surface::Triangles, &q.cast::<f64>()))
            .collect();
        let mut rows: Vec<(String, Run)> = vec![
            (
                "dda (naive exact)".into(),
                run(&rays, reps, |q| dda::trace(&hf, Surface::Triangles, q)),
            ),
            (
                "SD directional (exact)".into(),
                run(&rays, reps, |q| safety::trace(&sdm, &hf, q)),
            ),
        ];
        for (k, (label, _)) in bakes.iter().enumerate() {
            let m = &maps_r[k];
            let zeros: &[Zero] = if k == 0 {
                &[Zero::Walk, Zero::Clamp]
            } else {
                &[Zero::Walk]
            };
            for &zero in zeros {
                let opts = MarchOptions {
                    zero,
                    ..MarchOptions::default()
                };
                let name = match zero {
                    Zero::Walk if k == 0 => "radius exact".to_string(),
                    Zero::Walk => format!("radius {label}"),
                    Zero::Clamp => "radius clamp to 1".to_string(),
                };
                rows.push((name, run(&rays, reps, |q| radius::trace(m, &hf, q, &opts))));
            }
        }
        let base = rows[0].1.ns;
        for (name, r) in &rows {
            let (wrong, mean, max) = errors(&r.traces, &oracles, eps);
            println!(
                "| {el}° | {name} | {:.1} | {} | {} | {:.0} | ×{:.2} | {wrong} | {:.3}% | {mean:.2} | {max:.2} |",
                r.mean,
                r.p99,
                r.max,
                r.ns,
                base / r.ns,
                100.0 * wrong as f64 / rays.len() as f64
            );
        }
    }
}
