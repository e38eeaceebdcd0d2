//! What the benchmark examples share: timing medians, the command line, the shared
//! data folder and its maps, row bands on threads, the orbit camera's primary rays and
//! the fetch and time figures of a march (each example includes this file with
//! `mod common;`).
#![allow(dead_code)] // each example uses a different part

use hfcast::{HeightField, Query, Trace};
use std::hint::black_box;
use std::ops::Range;
use std::path::PathBuf;
use std::time::Instant;

/// Median of `v` (the upper middle for an even count).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Wall-clock seconds of `f`, median of `reps` runs.
pub fn wall(reps: usize, mut f: impl FnMut()) -> f64 {
    median(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

/// `../shared/data` beside the repository, or `$HFCAST_DATA`.
pub fn data_dir() -> PathBuf {
    std::env::var_os("HFCAST_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
        PathBuf::from,
    )
}

/// Primary rays of a pinhole camera (40° vertical field of view) at compass `azimuth`
/// and `elevation` (degrees), looking at the centre of the field's box from just far
/// enough that the box is in view.
pub fn camera_rays(
    hf: &HeightField,
    elevation: f64,
    azimuth: f64,
    w: u32,
    h: u32,
) -> Vec<Query<f32>> {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
    let size = [
        (hf.width() - 1) as f64,
        (hf.height() - 1) as f64,
        zmax - zmin,
    ];
    let centre = [size[0] / 2.0, size[1] / 2.0, zmin + size[2] / 2.0];
    let lens = Lens::new(elevation, azimuth, 20.0, w, h);
    let mut dist = 1e-3f64;
    for corner in 0..8 {
        let c = [0, 1, 2].map(|k| size[k] * (f64::from((corner >> k) & 1) - 0.5));
        let need_x = dot(c, lens.right).abs() / lens.tan[0] - dot(c, lens.fwd);
        let need_y = dot(c, lens.up).abs() / lens.tan[1] - dot(c, lens.fwd);
        dist = dist.max(need_x.max(need_y));
    }
    lens.rays(centre, 1.05 * dist, w, h)
}

/// Primary rays of a pinhole camera of `half_fov` degrees of half its vertical field
/// of view, at compass `azimuth` and `elevation` (degrees) over the plane `z = zref`,
/// framed so that the terrain fills the image: looking at the footprint's centre on
/// that plane, as far back as keeps the four corner rays' meetings with it inside the
/// footprint (shrunk by 1%). The filled cameras of `c_tests/embree_bench.c`.
pub fn filled_camera_rays(
    hf: &HeightField,
    (elevation, azimuth, half_fov): (f64, f64, f64),
    zref: f64,
    w: u32,
    h: u32,
) -> Vec<Query<f32>> {
    let size = [(hf.width() - 1) as f64, (hf.height() - 1) as f64];
    let lens = Lens::new(elevation, azimuth, half_fov, w, h);
    // Corner ray `c` meets the plane horizontally linearly in the distance: each side
    // of the footprint bounds it directly.
    let mut dist = f64::INFINITY;
    for corner in 0..4 {
        let sign = |bit: i32, v: f64| if corner & bit != 0 { v } else { -v };
        let c = [0, 1, 2].map(|k| {
            lens.fwd[k] + sign(1, lens.tan[0]) * lens.right[k] + sign(2, lens.tan[1]) * lens.up[k]
        });
        for k in 0..2 {
            let v = lens.to_eye[k] + lens.to_eye[2] / -c[2] * c[k];
            if v != 0.0 {
                dist = dist.min(0.99 * (size[k] / 2.0) / v.abs());
            }
        }
    }
    lens.rays([size[0] / 2.0, size[1] / 2.0, zref], dist, w, h)
}

/// A pinhole camera's orientation and lens: the unit vector to the eye, its frame and
/// the tangents of its half fields of view.
struct Lens {
    to_eye: [f64; 3],
    fwd: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    tan: [f64; 2],
}

impl Lens {
    fn new(elevation: f64, azimuth: f64, half_fov: f64, w: u32, h: u32) -> Lens {
        let dir = |az: f64, el: f64| {
            let (a, e) = (az.to_radians(), el.to_radians());
            [e.cos() * a.sin(), -e.cos() * a.cos(), e.sin()]
        };
        let tan_y = half_fov.to_radians().tan();
        let to_eye = dir(azimuth, elevation);
        let fwd = to_eye.map(|v| -v);
        let right = dir(azimuth + 270.0, 0.0);
        let up = [
            fwd[1] * right[2] - fwd[2] * right[1],
            fwd[2] * right[0] - fwd[0] * right[2],
            fwd[0] * right[1] - fwd[1] * right[0],
        ];
        Lens {
            to_eye,
            fwd,
            right,
            up,
            tan: [tan_y * w as f64 / h as f64, tan_y],
        }
    }

    /// The `w × h` image's rays from `dist` back from `target`.
    fn rays(&self, target: [f64; 3], dist: f64, w: u32, h: u32) -> Vec<Query<f32>> {
        let eye = [0, 1, 2].map(|k| (target[k] + dist * self.to_eye[k]) as f32);
        let mut rays = Vec::with_capacity((w * h) as usize);
        for py in 0..h {
            for px in 0..w {
                let sx = 2.0 * (px as f64 + 0.5) / w as f64 - 1.0;
                let sy = 1.0 - 2.0 * (py as f64 + 0.5) / h as f64;
                let d = [0, 1, 2].map(|k| {
                    (self.fwd[k] + sx * self.tan[0] * self.right[k] + sy * self.tan[1] * self.up[k])
                        as f32
                });
                rays.push(Query::from_arrays(eye, d, 0.0, f32::INFINITY).unwrap());
            }
        }
        rays
    }
}

/// The command line as `--option value` pairs (an option without its value panics).
pub fn options() -> Vec<(String, String)> {
    let mut args = std::env::args().skip(1);
    let mut pairs = Vec::new();
    while let Some(a) = args.next() {
        pairs.push((a, args.next().expect("option value")));
    }
    pairs
}

/// A `WxH` option value.
pub fn parse_size(v: &str) -> (u32, u32) {
    let (w, h) = v.split_once('x').expect("WxH");
    (w.parse().unwrap(), h.parse().unwrap())
}

/// A 16-bit grayscale PNG of the data folder as raw values, width, height.
pub fn load_png(name: &str) -> Option<(Vec<u16>, u32, u32)> {
    let file = std::fs::File::open(data_dir().join(name)).ok()?;
    let limits = png::Limits { bytes: 1 << 31 };
    let mut reader = png::Decoder::new_with_limits(std::io::BufReader::new(file), limits)
        .read_info()
        .ok()?;
    let mut buf = vec![0u8; reader.output_buffer_size()?];
    let frame = reader.next_frame(&mut buf).ok()?;
    assert_eq!(
        frame.bit_depth,
        png::BitDepth::Sixteen,
        "{name}: 16-bit expected"
    );
    let v = buf[..frame.buffer_size()]
        .chunks_exact(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect();
    Some((v, frame.width, frame.height))
}

/// Every `step`-th sample of `raw` (`w` wide), as heights `v / 65535 × 0.1 · side`.
pub fn downsample(raw: &[u16], w: u32, h: u32, step: u32) -> (Vec<f32>, u32, u32) {
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

/// Runs `f(rows, part)` over the `height` rows of `out` (`row_len` elements a row) in
/// bands of 8 rows taken in turn by `threads` threads, as the C API's threaded bakes
/// do (costly rows are uneven: one band per thread would leave a thread idle).
pub fn in_bands<T: Send>(
    out: &mut [T],
    row_len: usize,
    height: u32,
    threads: u32,
    f: impl Fn(Range<u32>, &mut [T]) + Sync,
) {
    const BAND: u32 = 8;
    let out = &mut out[..height as usize * row_len];
    let next = std::sync::Mutex::new(out.chunks_mut(BAND as usize * row_len).enumerate());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let item = next.lock().expect("a worker panicked").next();
                let Some((k, part)) = item else { break };
                let r0 = k as u32 * BAND;
                f(r0..(r0 + BAND).min(height), part);
            });
        }
    });
}

/// What one method did on one ray set.
pub struct Run {
    /// Fetches per ray: mean, 99th percentile and largest.
    pub mean: f64,
    pub p99: u32,
    pub max: u32,
    /// Nanoseconds per ray (median of the repetitions).
    pub ns: f64,
    /// The trace of every ray.
    pub traces: Vec<Trace<f32>>,
}

/// Traces every ray with `f` once (the traces and their fetches), then times `reps`
/// passes over all the rays ([`wall`]).
pub fn run(rays: &[Query<f32>], reps: usize, f: impl Fn(&Query<f32>) -> Trace<f32>) -> Run {
    let traces: Vec<Trace<f32>> = rays.iter().map(&f).collect();
    let secs = wall(reps, || {
        for q in rays {
            black_box(f(black_box(q)));
        }
    });
    let mut fetches: Vec<u32> = traces.iter().map(|t| t.fetches).collect();
    fetches.sort_unstable();
    Run {
        mean: fetches.iter().map(|&v| f64::from(v)).sum::<f64>() / rays.len() as f64,
        p99: fetches[(fetches.len() * 99 / 100).min(fetches.len() - 1)],
        max: *fetches.last().unwrap(),
        ns: secs * 1e9 / rays.len() as f64,
        traces,
    }
}

/// The synthetic fractal field of the cone-family benchmarks: an `n × n` sum of seven
/// sines (deterministic), heights in `[0, 0.1·n]` roughly.
pub fn fractal_field(n: u32) -> Vec<f32> {
    let mut v = Vec::with_capacity((n * n) as usize);
    let depth = 0.1 * n as f64;
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f64, j as f64);
            let mut s = 0.0;
            for k in 0..7 {
                let f = 0.02 * 1.9f64.powi(k);
                let a = k as f64 * 1.7;
                s += (f * (x * a.cos() + y * a.sin()) + k as f64).sin() / 1.8f64.powi(k);
            }
            v.push((depth * (0.5 + 0.25 * s)) as f32);
        }
    }
    v
}
