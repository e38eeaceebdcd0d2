//! Where a camera ray's time goes on the coherent batches' path (issue 21): for the
//! four cameras of `scripts/embree_bench.sh` (640 × 512: the whole box from 45° and 5°,
//! the terrain filling the frame from 45° and in a 2° telephoto from 5°), the cost of
//! each stage per ray — the horizon's build, the start lookup, the box clip alone, the
//! march from the start with its finish, one ray after another and in AVX-512 lanes
//! (`dda::trace_skipping_lanes`, where the CPU has them) — then the march's cost
//! against the cells it visits (its part per ray, its part per cell), and the same
//! stages with finer horizons (blocks of one cell, four times the wedges). One thread;
//! medians.
//!
//! `cargo run --release -p hfcast --example horizon_cost [-- --map NAME --reps N]`
//! (default the Himalaya DEM of ../shared/data, `--map fractal` the core benchmarks'
//! sum of sines at 1024², not `embree_bench.c`'s fBm; 5 repetitions).

mod common;
use common::{camera_rays, filled_camera_rays, load_png, median, options, wall};
use hfcast::horizon::{Horizon, Start};
use hfcast::{dda, Flags, HeightField, Query, Surface, Trace};
use std::hint::black_box;
use std::time::Instant;

/// The cameras: name, elevation, half vertical field of view, whether the terrain fills
/// the frame (all at azimuth 30°).
const CAMERAS: [(&str, f64, f64, bool); 4] = [
    ("45deg", 45.0, 20.0, false),
    ("5deg", 5.0, 20.0, false),
    ("filled45deg", 45.0, 20.0, true),
    ("filled5deg", 5.0, 1.0, true),
];

const SURFACE: Surface = Surface::Triangles;

fn main() {
    let (mut map, mut reps) = ("dem_etopo5_himalaya_1024.png".to_string(), 5);
    for (k, v) in options() {
        match k.as_str() {
            "--map" => map = v,
            "--reps" => reps = v.parse().expect("--reps N"),
            _ => panic!("unknown option {k}"),
        }
    }
    let heights = if map == "fractal" {
        common::fractal_field(1024)
    } else {
        let (raw, w, h) = load_png(&map).expect("a 16-bit PNG of the data folder");
        let (v, vw, vh) = common::downsample(&raw, w, h, 1);
        assert_eq!((vw, vh), (w, h));
        v
    };
    let side = (heights.len() as f64).sqrt() as u32;
    let hf = HeightField::new(&heights, side, heights.len() as u32 / side, side as usize)
        .expect("a valid field");
    println!(
        "{map}: {} x {}, one thread, ns per ray (median of {reps})",
        hf.width(),
        hf.height()
    );
    for (name, elevation, half_fov, filled) in CAMERAS {
        let rays = match filled {
            false => camera_rays(&hf, elevation, 30.0, 640, 512),
            true => filled_rays(&hf, (elevation, 30.0, half_fov)),
        };
        println!("{name}:");
        let n = rays.len();
        let eye = rays[0].origin().map(f64::from);
        let dirs = || rays.iter().map(|q| q.dir().map(f64::from));
        let clip = wall(reps, || {
            for q in &rays {
                black_box(dda::clip(&hf, black_box(q)));
            }
        });
        println!("  box clip alone {:.1}", clip * 1e9 / n as f64);
        let sized = || Horizon::sized(&hf, SURFACE, eye, dirs(), n, u32::MAX);
        let finer = |per_wedge: usize, block: u32| {
            move || Horizon::new(&hf, SURFACE, eye, dirs(), n / per_wedge, block)
        };
        stages(&hf, &rays, reps, "sized (512 rays a wedge)", sized);
        stages(&hf, &rays, reps, "blocks of 1 cell", finer(512, 1));
        stages(&hf, &rays, reps, "4x the wedges", finer(128, 2));
    }
}

/// The filled camera of `c_tests/embree_bench.c`: framed on the lowest sample; when some
/// rays then enter the field's near side under the surface (a low telephoto), lifted
/// to the highest level (eight halvings of the relief) at which every ray still hits.
fn filled_rays(hf: &HeightField, view: (f64, f64, f64)) -> Vec<Query<f32>> {
    let (zmin, zmax) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let rays = |zref: f64| filled_camera_rays(hf, view, zref, 640, 512);
    let traced = |rays: &[Query<f32>]| -> Vec<Trace<f32>> {
        rays.iter().map(|q| dda::trace(hf, SURFACE, q)).collect()
    };
    let side = |t: &Trace<f32>| t.hit.is_some_and(|h| h.flags.contains(Flags::SIDE));
    if !traced(&rays(zmin)).iter().any(side) {
        return rays(zmin);
    }
    let (mut lo, mut hi) = (zmin, zmax);
    for _ in 0..8 {
        let mid = 0.5 * (lo + hi);
        let all_hit = traced(&rays(mid)).iter().all(|t| t.hit.is_some());
        *(if all_hit { &mut lo } else { &mut hi }) = mid;
    }
    rays(lo)
}

/// One horizon's stages on `rays`: its build, the start lookup, the march from the
/// start (`dda::trace_skipping`, the DDA's march after a horizon start), and the
/// march's time against the cells it visits.
fn stages(
    hf: &HeightField,
    rays: &[Query<f32>],
    reps: usize,
    what: &str,
    build: impl Fn() -> Option<Horizon>,
) {
    let n = rays.len() as f64;
    let ns = |secs: f64| secs * 1e9 / n;
    let build_s = wall(reps, || {
        black_box(build());
    });
    let horizon = build().expect("rays with a horizontal part");
    let lookup = |hint: &mut usize| -> Vec<Query<f32>> {
        let from = |q: &Query<f32>, hint: &mut usize| match horizon.start_query(q, hint) {
            Some((Start::At(t, _, _), _)) => Some(q.starting_at(t)),
            Some((Start::Miss(_), _)) => None,
            None => Some(*q),
        };
        rays.iter().filter_map(|q| from(q, hint)).collect()
    };
    let lookup_s = wall(reps, || {
        black_box(lookup(&mut 0));
    });
    let started = lookup(&mut 0);
    let march_s = wall(reps, || {
        for q in &started {
            black_box(dda::trace_skipping(hf, SURFACE, black_box(q)));
        }
    });
    let mut walked = vec![Ok(Trace::MISS); started.len()];
    let lanes_s = wall(reps, || {
        let simd = hfcast::detect_avx2!().and_then(|s| s.avx512());
        dda::trace_skipping_lanes(hf, SURFACE, &started, u32::MAX, &mut walked, simd);
        black_box(&walked);
    });
    let cells: f64 = started
        .iter()
        .map(|q| f64::from(dda::trace_skipping(hf, SURFACE, q).fetches / 4))
        .sum();
    println!(
        "  {what}: build {:.1}, lookup {:.1}, march {:.1}, in lanes {:.1} ({:.1} cells a \
         ray); {} KiB",
        ns(build_s),
        ns(lookup_s),
        ns(march_s),
        ns(lanes_s),
        cells / n,
        horizon.size_bytes() / 1024
    );
    // Each march timed alone, by the cells it visits; the clock's own cost (an empty
    // timed call) taken off.
    let timed = |f: &mut dyn FnMut()| {
        let t = Instant::now();
        f();
        t.elapsed().as_secs_f64() * 1e9
    };
    let clock = median((0..10_000).map(|_| timed(&mut || {})).collect());
    let mut by_cells: Vec<Vec<f64>> = vec![Vec::new(); 17];
    for _ in 0..reps.min(3) {
        for q in &started {
            let mut fetches = 0;
            let ns =
                timed(&mut || fetches = black_box(dda::trace_skipping(hf, SURFACE, q)).fetches);
            by_cells[(fetches as usize / 4).min(16)].push(ns - clock);
        }
    }
    let row: Vec<String> = [1, 2, 4, 8, 16]
        .iter()
        .filter(|&&k| by_cells[k].len() >= 100)
        .map(|&k| {
            format!(
                "{k}{}: {:.0}",
                if k == 16 { "+" } else { "" },
                median(by_cells[k].clone())
            )
        })
        .collect();
    println!("    march by cells visited: {}", row.join(", "));
}
