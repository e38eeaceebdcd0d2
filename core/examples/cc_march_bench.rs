//! The cylinder–cone march on the CPU, one thread: himalaya 1024², depth 102.4, the
//! exact CC map (cached in `$TMPDIR/hfcast_cc_himalaya_rows.bin`: the bake takes seconds),
//! 640×512 camera rays at 45° and 5°, in scanline order or in 8×8 pixel tiles (the
//! order a tiled renderer uses); medians of ns/ray and mean fetches next to the DDA's,
//! and the march finishing on the view-linear surface.
//!
//! `cargo run --release -p hfcast --example cc_march_bench [-- --reps N --tiled 1 --dda 0]`

mod common;
use common::{camera_rays, downsample, load_png, options, run};
use hfcast::safety::cc::{self, CcMap, CcOptions};
use hfcast::safety::{self, MarchSurface};
use hfcast::{dda, HeightField, Surface};

fn main() {
    let (mut reps, mut tiles, mut with_dda) = (5, false, true);
    for (a, v) in options() {
        match a.as_str() {
            "--reps" => reps = v.parse().unwrap(),
            "--tiled" => tiles = v == "1",
            "--dda" => with_dda = v == "1",
            _ => panic!("unknown option {a}"),
        }
    }
    let (raw, w, h) = load_png("dem_etopo5_himalaya_1024.png").expect("himalaya map");
    let (v, w, h) = downsample(&raw, w, h, 1);
    let hf = HeightField::new(&v, w, h, w as usize).unwrap();
    let opts = CcOptions::default();
    let cache = std::env::temp_dir().join("hfcast_cc_himalaya_rows.bin");
    let data = match std::fs::read(&cache) {
        Ok(d) if d.len() == cc::map_len(w, h) => d,
        _ => {
            let mut scratch = vec![0f32; safety::scratch_len(w, h)];
            let mut nb = vec![0f32; cc::nbuffer_len(w, h, opts.cap)];
            let mut out = vec![0u8; cc::map_len(w, h)];
            cc::bake(&hf, &mut scratch, &mut nb, opts, &mut out).unwrap();
            std::fs::write(&cache, &out).unwrap();
            out
        }
    };
    let map = CcMap::new(&hf, &data, opts.cap).unwrap();
    for el in [45.0, 5.0] {
        let mut rays = camera_rays(&hf, el, 30.0, 640, 512);
        if tiles {
            rays = tiled(&rays, 640, 512, 8);
        }
        let dda_rays = if with_dda { &rays[..] } else { &rays[..1] };
        let d = run(dda_rays, reps, |q| dda::trace(&hf, Surface::Triangles, q));
        let c = run(&rays, reps, |q| cc::trace(&map, &hf, q));
        let vl = run(&rays, reps, |q| {
            cc::trace_on(&map, &hf, MarchSurface::ViewLinear, q)
        });
        println!(
            "{el}°: dda {:.0} ns/ray ({:.1} fetches), cc {:.0} ns/ray ({:.1} fetches, {:.2} Mrays/s), cc view-linear {:.0} ns/ray",
            d.ns, d.mean, c.ns, c.mean, 1e3 / c.ns, vl.ns
        );
    }
}

/// The rays of a `w × h` image in `t × t` pixel tiles (tile by tile, row by row
/// inside a tile): the order a tiled renderer traces them in.
fn tiled<T: Copy>(rays: &[T], w: usize, h: usize, t: usize) -> Vec<T> {
    let mut out = Vec::with_capacity(rays.len());
    for ty in (0..h).step_by(t) {
        for tx in (0..w).step_by(t) {
            for y in ty..(ty + t).min(h) {
                for x in tx..(tx + t).min(w) {
                    out.push(rays[y * w + x]);
                }
            }
        }
    }
    out
}
