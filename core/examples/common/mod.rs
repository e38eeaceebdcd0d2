//! What the benchmark examples share: timing medians, the shared data folder and the
//! orbit camera's primary rays (each example includes this file with `mod common;`).
#![allow(dead_code)] // each example uses a different part

use hfcast::{HeightField, Query};
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
    let dir = |az: f64, el: f64| {
        let (a, e) = (az.to_radians(), el.to_radians());
        [e.cos() * a.sin(), -e.cos() * a.cos(), e.sin()]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
    let size = [
        (hf.width() - 1) as f64,
        (hf.height() - 1) as f64,
        zmax - zmin,
    ];
    let centre = [size[0] / 2.0, size[1] / 2.0, zmin + size[2] / 2.0];
    let tan_y = 20f64.to_radians().tan();
    let tan_x = tan_y * w as f64 / h as f64;
    let to_eye = dir(azimuth, elevation);
    let fwd = to_eye.map(|v| -v);
    let right = dir(azimuth + 270.0, 0.0);
    let up = [
        fwd[1] * right[2] - fwd[2] * right[1],
        fwd[2] * right[0] - fwd[0] * right[2],
        fwd[0] * right[1] - fwd[1] * right[0],
    ];
    let mut dist = 1e-3f64;
    for corner in 0..8 {
        let c = [0, 1, 2].map(|k| size[k] * (f64::from((corner >> k) & 1) - 0.5));
        let need_x = dot(c, right).abs() / tan_x - dot(c, fwd);
        let need_y = dot(c, up).abs() / tan_y - dot(c, fwd);
        dist = dist.max(need_x.max(need_y));
    }
    let eye = [0, 1, 2].map(|k| (centre[k] + 1.05 * dist * to_eye[k]) as f32);
    let mut rays = Vec::with_capacity((w * h) as usize);
    for py in 0..h {
        for px in 0..w {
            let sx = 2.0 * (px as f64 + 0.5) / w as f64 - 1.0;
            let sy = 1.0 - 2.0 * (py as f64 + 0.5) / h as f64;
            let d = [0, 1, 2].map(|k| (fwd[k] + sx * tan_x * right[k] + sy * tan_y * up[k]) as f32);
            rays.push(Query::from_arrays(eye, d, 0.0, f32::INFINITY).unwrap());
        }
    }
    rays
}
