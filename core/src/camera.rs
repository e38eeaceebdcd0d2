//! A pinhole camera: one primary ray per pixel, and the order in which to trace them.
//!
//! Ray order decides coherence: neighbouring pixels' rays cross the same cells and read
//! the same map texels, so [`Pinhole::tiles`] hands pixels out in square tiles rather
//! than in image rows (the C API's `hf_trace_camera` traces in this order).

use crate::math::{cross3, dot3};
use crate::ray::{Query, RayError};
use core::ops::Range;

/// Why a camera is not one: what [`Pinhole::new`] refuses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraError {
    /// The eye, a direction or the field of view is NaN or infinite.
    NotFinite,
    /// The view direction is zero, or the up hint is zero or parallel to it.
    Degenerate,
    /// The vertical field of view is outside (0, 180) degrees.
    FieldOfView,
    /// The image has no pixel (width or height 0).
    Empty,
}

impl core::fmt::Display for CameraError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            CameraError::NotFinite => "the eye, a direction or the field of view is not finite",
            CameraError::Degenerate => {
                "the view direction is zero, or the up hint is zero or parallel to it"
            }
            CameraError::FieldOfView => "the vertical field of view is outside (0, 180) degrees",
            CameraError::Empty => "the image has no pixel",
        })
    }
}

/// The side of the square tiles [`Pinhole::tiles`] hands out, in pixels.
pub const TILE: u32 = 8;

/// A pinhole camera, in f64: the eye, the unit view direction, and the image's right
/// and up vectors scaled by the tangents of the half fields of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pinhole {
    /// Eye position.
    pub eye: [f64; 3],
    /// Unit view direction.
    pub forward: [f64; 3],
    /// Image right, scaled by tan(horizontal half field of view).
    pub right: [f64; 3],
    /// Image up, scaled by tan(vertical half field of view).
    pub up: [f64; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// `v` scaled to length `len`; `None` for a zero (or not finite) vector.
fn scaled(v: [f64; 3], len: f64) -> Option<[f64; 3]> {
    let n = libm::sqrt(dot3(v, v));
    (n > 0.0 && n.is_finite()).then(|| v.map(|c| c * len / n))
}

impl Pinhole {
    /// The camera at `eye` looking along `forward`, image up towards `up` (a hint: the
    /// image's up is the part of it square to `forward`), `fov_y_deg` degrees from the
    /// top row to the bottom one, `width × height` square pixels.
    pub fn new(
        eye: [f64; 3],
        forward: [f64; 3],
        up: [f64; 3],
        fov_y_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Pinhole, CameraError> {
        let finite = |v: [f64; 3]| v.iter().all(|c| c.is_finite());
        if !(finite(eye) && finite(forward) && finite(up) && fov_y_deg.is_finite()) {
            return Err(CameraError::NotFinite);
        }
        if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
            return Err(CameraError::FieldOfView);
        }
        if width == 0 || height == 0 {
            return Err(CameraError::Empty);
        }
        let tan_y = libm::tan(fov_y_deg.to_radians() / 2.0);
        let tan_x = tan_y * f64::from(width) / f64::from(height);
        let forward = scaled(forward, 1.0).ok_or(CameraError::Degenerate)?;
        let right = scaled(cross3(forward, up), tan_x).ok_or(CameraError::Degenerate)?;
        let up = scaled(cross3(right, forward), tan_y).ok_or(CameraError::Degenerate)?;
        // A hint within rounding of the view direction leaves no usable right vector.
        if dot3(right, right) < 1e-24 * tan_x * tan_x {
            return Err(CameraError::Degenerate);
        }
        Ok(Pinhole {
            eye,
            forward,
            right,
            up,
            width,
            height,
        })
    }

    /// The ray through the centre of pixel (`px`, `py`), row 0 at the top: from the
    /// eye, `t` in `[0, t_max]`, the direction `forward + sx·right + sy·up` (not unit;
    /// `sx`, `sy` in (−1, 1) across the image), rounded to f32 once; an error for an
    /// eye beyond the f32 range.
    #[inline]
    pub fn ray(&self, px: u32, py: u32, t_max: f32) -> Result<Query<f32>, RayError> {
        let sx = 2.0 * (f64::from(px) + 0.5) / f64::from(self.width) - 1.0;
        let sy = 1.0 - 2.0 * (f64::from(py) + 0.5) / f64::from(self.height);
        let d = [0, 1, 2].map(|k| (self.forward[k] + sx * self.right[k] + sy * self.up[k]) as f32);
        Query::from_arrays(self.eye.map(|v| v as f32), d, 0.0, t_max)
    }

    /// The [`TILE`] × [`TILE`] tiles of image rows `rows` in trace order (the last ones
    /// cut at the edges): tile rows from `rows.start`, each left to right; a tile's
    /// pixels go row by row. Each item is a tile's rows and columns.
    pub fn tiles(&self, rows: Range<u32>) -> impl Iterator<Item = (Range<u32>, Range<u32>)> {
        let (w, t) = (self.width, TILE);
        let end = rows.end;
        rows.step_by(t as usize).flat_map(move |y0| {
            let ys = y0..(y0 + t).min(end);
            (0..w)
                .step_by(t as usize)
                .map(move |x0| (ys.clone(), x0..(x0 + t).min(w)))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_ray_looks_forward_and_the_corners_span_the_field_of_view() {
        let cam = Pinhole::new([0.0; 3], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0], 90.0, 2, 2).unwrap();
        assert!((cam.forward[1] - 1.0).abs() < 1e-15);
        let d = cam.ray(1, 0, f32::INFINITY).unwrap().dir();
        // Pixel (1, 0): right and up of the centre, at half the half-angle tangents.
        assert!(
            (d[0] - 0.5).abs() < 1e-6 && (d[1] - 1.0).abs() < 1e-6 && (d[2] - 0.5).abs() < 1e-6
        );
    }

    #[test]
    fn bad_cameras_are_refused() {
        let ok =
            |f: [f64; 3], u: [f64; 3], fov: f64, w: u32| Pinhole::new([0.0; 3], f, u, fov, w, 4);
        assert_eq!(
            ok([0.0; 3], [0.0, 0.0, 1.0], 60.0, 4),
            Err(CameraError::Degenerate)
        );
        assert_eq!(
            ok([0.0, 0.0, 2.0], [0.0, 0.0, 1.0], 60.0, 4),
            Err(CameraError::Degenerate)
        );
        assert_eq!(
            ok([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 180.0, 4),
            Err(CameraError::FieldOfView)
        );
        assert_eq!(
            ok([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 60.0, 0),
            Err(CameraError::Empty)
        );
        assert_eq!(
            ok([f64::NAN, 0.0, 0.0], [0.0, 0.0, 1.0], 60.0, 4),
            Err(CameraError::NotFinite)
        );
    }

    #[test]
    fn tiles_visit_every_pixel_once() {
        let cam = Pinhole::new([0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 60.0, 19, 11).unwrap();
        let mut seen = [[0u8; 19]; 11];
        for (ys, xs) in cam.tiles(0..11) {
            assert!(ys.len() <= 8 && xs.len() <= 8);
            for y in ys {
                for x in xs.clone() {
                    seen[y as usize][x as usize] += 1;
                }
            }
        }
        assert!(seen.iter().flatten().all(|&n| n == 1));
        // Rows 3..11 are one tile row, cut at the right edge.
        let band: heapless::Vec<_, 4> = cam.tiles(3..11).take(4).collect();
        assert_eq!(&band[..], &[(3..11, 0..8), (3..11, 8..16), (3..11, 16..19)]);
    }
}
