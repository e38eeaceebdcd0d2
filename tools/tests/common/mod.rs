//! Shared helpers of the real-map tests: the maps and their test windows, the ray set,
//! docs/DESIGN.md's ambiguity threshold and touch rule, the comparison with the f64 exact
//! DDA, two-thread bakes, and runs of the `hfcast` binary (each test includes this file
//! with `mod common;`).
#![allow(dead_code)] // every test binary uses a different part of this module

use std::io::Write;
use std::ops::Range;
use std::path::Path;
use std::process::{Command, Stdio};

use hfcast::{dda, HeightField, Query, Real, Surface, Trace};
use hfcast_tools::bench::random_rays;
use hfcast_tools::maps::{list_maps, Map, MapInfo};
use hfcast_tools::render::Camera;

/// Largest side of the window of each map that the tests bake.
pub const WINDOW: u32 = 256;

/// The maps of the shared data folder (none, said on stdout, when there are none).
pub fn maps() -> Vec<MapInfo> {
    let maps = list_maps();
    if maps.is_empty() {
        println!("no maps found in the shared data folder: nothing to check");
    }
    maps
}

/// The centred window of at most [`WINDOW`] × [`WINDOW`] samples of `map` (a view with
/// the full row stride).
pub fn window(map: &Map) -> HeightField<'_> {
    let (w, h) = (map.width.min(WINDOW), map.height.min(WINDOW));
    let (x0, y0) = ((map.width - w) as usize / 2, (map.height - h) as usize / 2);
    let stride = map.width as usize;
    HeightField::new(&map.heights[y0 * stride + x0..], w, h, stride).expect("window")
}

/// docs/DESIGN.md's ambiguity threshold 2⁻¹³ · max(1, |z|), |z| over the whole field.
pub fn ambiguity_eps(hf: &HeightField) -> f64 {
    let z = 1f64
        .max(hf.max_height().abs().into())
        .max(hf.min_height().abs().into());
    z / 8192.0
}

/// The rays of the tests: 40 × 32 camera rays at 45° and at 5° elevation, then 1500
/// random rays inside the box (all directions, upward included).
pub fn test_rays(hf: &HeightField) -> Vec<Query<f32>> {
    let mut rays: Vec<Query<f32>> = Vec::new();
    for elevation in [45.0, 5.0] {
        rays.extend(Camera::orbit(hf, elevation, 200.0, 40, 32).rays());
    }
    rays.extend(random_rays(hf, 1500, 11));
    rays
}

/// The oracle of each ray: the f64 exact DDA on the triangle surface.
pub fn oracle_traces(hf: &HeightField, rays: &[Query<f32>]) -> Vec<Trace<f64>> {
    rays.iter()
        .map(|q| dda::trace(hf, Surface::Triangles, &q.cast::<f64>()))
        .collect()
}

/// Distance between a hit point and the oracle's.
pub fn pos_err<R: Real>(p: R::V3, o: <f64 as Real>::V3) -> f64 {
    let p = R::xyz(p).map(|v| v.to_f64());
    let o = f64::xyz(o);
    let d = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Wrong: hit/miss, flags or the hit point (by more than 1e-3 texel) differ.
pub fn differs<R: Real>(a: &Trace<R>, oracle: &Trace<f64>) -> bool {
    match (&a.hit, &oracle.hit) {
        (None, None) => false,
        (Some(a), Some(b)) => pos_err::<R>(a.point, b.point) > 1e-3 || a.flags != b.flags,
        _ => true,
    }
}

/// The oracle's hit is a touch: the ray meets the triangle surface without going
/// under it.
pub fn touch(hf: &HeightField, q: &Query<f64>, oracle: &Trace<f64>, eps: f64) -> bool {
    touch_on(hf, Surface::Triangles, q, oracle, eps)
}

/// [`touch`] on `surface`.
pub fn touch_on(
    hf: &HeightField,
    surface: Surface,
    q: &Query<f64>,
    oracle: &Trace<f64>,
    eps: f64,
) -> bool {
    let Some(hit) = oracle.hit else {
        return false;
    };
    let d = q.dir();
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [1e-4, 1e-3, 1e-2].iter().all(|s| {
        let p = q.at(hit.t + s / len);
        p[2] - surface.height_at(hf, p[0], p[1]) >= -eps
    })
}

/// A bake on two threads: `bake_rows(rows, part)` for each half of the `height` rows
/// of `out` (`row_len` bytes a row), the second half on this thread.
pub fn bake_halves(
    out: &mut [u8],
    row_len: usize,
    height: u32,
    bake_rows: impl Fn(Range<u32>, &mut [u8]) + Sync,
) {
    let half = height / 2;
    let (a, b) = out.split_at_mut(half as usize * row_len);
    let bake_rows = &bake_rows;
    std::thread::scope(|s| {
        s.spawn(move || bake_rows(0..half, a));
        bake_rows(half..height, b);
    });
}

/// What a run of the `hfcast` binary answered.
pub struct Run {
    /// It exited with success.
    pub ok: bool,
    /// Its standard output.
    pub stdout: String,
    /// Its standard error.
    pub stderr: String,
    /// All of the input reached it (a command that refuses its arguments exits before
    /// it reads, and may have closed the pipe first).
    pub fed: bool,
}

/// Runs the `hfcast` binary with `args` in `dir` (the test's own when `None`), `stdin`
/// on its standard input.
pub fn run_hfcast(dir: Option<&Path>, args: &[&str], stdin: &str) -> Run {
    let mut command = Command::new(env!("CARGO_BIN_EXE_hfcast"));
    command
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if let Some(dir) = dir {
        command.current_dir(dir);
    }
    let mut child = command.spawn().unwrap();
    let fed = child
        .stdin
        .take()
        .unwrap()
        .write_all(stdin.as_bytes())
        .is_ok();
    let out = child.wait_with_output().unwrap();
    Run {
        ok: out.status.success(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        fed,
    }
}
