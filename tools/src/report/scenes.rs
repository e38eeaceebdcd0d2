//! The scenes of the report (height fields with the depth and surface they are traced
//! with) and the ray sets traced over them (cameras, an inside viewpoint, shadow rays).

use crate::maps::{load_map, scan_maps, Error};
use crate::render::{compass_dir, Camera, FOV_Y_DEG};
use crate::Rng;
use hfcast::{dda, HeightField, Query, Surface};

/// One height field of the report, with the surface it is traced on.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Short name (file-name safe): map name and depth, or the synthetic kind.
    pub name: String,
    /// One line saying what the scene is (size, depth in grid units, source).
    pub about: String,
    /// Samples along x.
    pub width: u32,
    /// Samples along y.
    pub height: u32,
    /// `width × height` heights in grid units, row-major.
    pub heights: Vec<f32>,
    /// Surface reconstruction traced.
    pub surface: Surface,
}

impl Scene {
    /// The validated field over [`Scene::heights`].
    pub fn field(&self) -> HeightField<'_> {
        HeightField::new(&self.heights, self.width, self.height, self.width as usize)
            .expect("scene heights are finite")
    }

    /// `max(1, |z|)` of the ambiguity rule over the whole field (conservative).
    pub fn z_scale(&self) -> f64 {
        let hf = self.field();
        1f64.max(f64::from(hf.min_height()).abs())
            .max(f64::from(hf.max_height()).abs())
    }
}

/// The relief depths of the map scenes, as fractions of `max(W, H)`.
pub const DEPTHS: [f64; 2] = [0.05, 0.15];

/// Relief of the synthetic scenes, as a fraction of `max(W, H)`.
pub const SYNTHETIC_DEPTH: f64 = 0.1;

/// Every map of the shared data folder at each of [`DEPTHS`] (triangle surface) whose
/// scene name `keep` accepts, the others never read; with `crop`, each map's centre
/// `crop × crop` samples at most (the depth then relative to the crop). A map that
/// cannot be read is skipped: the second value says why, one line per map.
pub fn map_scenes(keep: impl Fn(&str) -> bool, crop: Option<u32>) -> (Vec<Scene>, Vec<String>) {
    let name = |map: &str, frac: f64| format!("{map}@{frac}");
    // A map is read when one of its scenes, or its bilinear copy, may be kept.
    let wanted = |n: &str| keep(n) || keep(&format!("{n}-bilinear"));
    let (maps, errors) = scan_maps(|map| DEPTHS.iter().any(|&f| wanted(&name(map, f))));
    let mut skipped: Vec<String> = errors.iter().map(ToString::to_string).collect();
    let mut out = Vec::new();
    for info in maps {
        let (cw, ch) = crop.map_or((info.width, info.height), |c| {
            (info.width.min(c), info.height.min(c))
        });
        for frac in DEPTHS.into_iter().filter(|&f| wanted(&name(&info.name, f))) {
            let depth = (frac * f64::from(cw.max(ch))) as f32;
            let map = match load_map(&info.path, Some(depth)) {
                Ok(map) => map,
                Err(e) => {
                    skipped.push(e.to_string());
                    break;
                }
            };
            let cropped = if (cw, ch) == (map.width, map.height) {
                String::new()
            } else {
                format!(", centre {cw} × {ch} samples")
            };
            out.push(Scene {
                name: name(&info.name, frac),
                about: format!(
                    "`{}.png` ({} × {}{cropped}), depth {frac} × max(W, H) = {depth} grid units",
                    info.name, map.width, map.height
                ),
                width: cw,
                height: ch,
                heights: centre(&map.heights, (map.width, map.height), (cw, ch)),
                surface: Surface::Triangles,
            });
        }
    }
    (out, skipped)
}

/// The centre `size` samples of a row-major field of `full` samples.
fn centre(heights: &[f32], full: (u32, u32), size: (u32, u32)) -> Vec<f32> {
    let (x0, y0) = ((full.0 - size.0) / 2, (full.1 - size.1) / 2);
    (y0..y0 + size.1)
        .flat_map(|j| {
            let row = (j * full.0 + x0) as usize;
            heights[row..row + size.0 as usize].iter().copied()
        })
        .collect()
}

/// Name of the [`bundled_scene`].
pub fn bundled_name() -> String {
    format!("bundled@{}", DEPTHS[0])
}

/// The bundled default map at the first depth: the fallback when the shared data
/// folder is missing.
pub fn bundled_scene() -> Result<Scene, Error> {
    let path = crate::maps::bundled_map();
    let map = load_map(&path, None)?;
    let frac = DEPTHS[0];
    let depth = (frac * f64::from(map.width.max(map.height))) as f32;
    let map = load_map(&path, Some(depth))?;
    Ok(Scene {
        name: bundled_name(),
        about: format!(
            "bundled `{}` ({} × {}), depth {depth} grid units",
            crate::maps::DEFAULT_MAP,
            map.width,
            map.height
        ),
        width: map.width,
        height: map.height,
        heights: map.heights,
        surface: Surface::Triangles,
    })
}

/// The synthetic kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Synthetic {
    /// Sum of sines with falling amplitudes plus value noise.
    Fractal,
    /// Flat ground crossed by 1-texel walls at full height (every 16th column, every
    /// 24th row, with random gaps).
    Walls,
    /// Flat ground with single-sample needles at full height (1 sample in 150).
    Needles,
    /// Samples alternately at 0 and full height: every cell a saddle.
    Checkerboard,
    /// Every sample at 0.
    Flat,
}

impl Synthetic {
    /// All kinds.
    pub const ALL: [Synthetic; 5] = [
        Synthetic::Fractal,
        Synthetic::Walls,
        Synthetic::Needles,
        Synthetic::Checkerboard,
        Synthetic::Flat,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Synthetic::Fractal => "fractal",
            Synthetic::Walls => "walls",
            Synthetic::Needles => "needles",
            Synthetic::Checkerboard => "checkerboard",
            Synthetic::Flat => "flat",
        }
    }

    /// A `size × size` field of this kind with relief `depth`, deterministic.
    pub fn heights(self, size: u32, depth: f64) -> Vec<f32> {
        let mut rng = Rng::new(0x5EED ^ self as u64);
        let n = size as usize;
        let mut h = vec![0f32; n * n];
        match self {
            Synthetic::Fractal => {
                let waves: Vec<[f64; 4]> = (0..9)
                    .map(|k| {
                        let f = 0.02 * 1.9f64.powi(k);
                        let a = rng.range(0.0, std::f64::consts::TAU);
                        let ph = rng.range(0.0, std::f64::consts::TAU);
                        [f * a.cos(), f * a.sin(), ph, 1.0 / 1.7f64.powi(k)]
                    })
                    .collect();
                let raw: Vec<f64> = (0..n * n)
                    .map(|k| {
                        let (x, y) = ((k % n) as f64, (k / n) as f64);
                        let s: f64 = waves
                            .iter()
                            .map(|[fx, fy, ph, a]| a * (fx * x + fy * y + ph).sin())
                            .sum();
                        s + rng.range(-0.03, 0.03)
                    })
                    .collect();
                let lo = raw.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = raw.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                for (o, r) in h.iter_mut().zip(raw) {
                    *o = ((r - lo) / (hi - lo) * depth) as f32;
                }
            }
            Synthetic::Walls => {
                for j in 0..n {
                    for i in 0..n {
                        let wall = (i % 16 == 8 && rng.unit() > 0.02)
                            || (j % 24 == 12 && rng.unit() > 0.02);
                        if wall {
                            h[j * n + i] = depth as f32;
                        }
                    }
                }
            }
            Synthetic::Needles => {
                for v in h.iter_mut() {
                    if rng.unit() < 1.0 / 150.0 {
                        *v = depth as f32;
                    }
                }
            }
            Synthetic::Checkerboard => {
                for j in 0..n {
                    for i in 0..n {
                        if (i + j) % 2 == 0 {
                            h[j * n + i] = depth as f32;
                        }
                    }
                }
            }
            Synthetic::Flat => {}
        }
        h
    }

    /// The scene of this kind, `size × size`, on `surface`.
    pub fn scene(self, size: u32, surface: Surface) -> Scene {
        let depth = (SYNTHETIC_DEPTH * f64::from(size)).round();
        let suffix = match surface {
            Surface::Triangles => String::new(),
            s => format!("-{}", s.name()),
        };
        Scene {
            name: format!("synthetic-{}{suffix}", self.name()),
            about: format!(
                "synthetic {} ({size} × {size}), relief {depth} grid units{}",
                self.name(),
                if suffix.is_empty() {
                    String::new()
                } else {
                    format!(", {} surface", surface.name())
                }
            ),
            width: size,
            height: size,
            heights: self.heights(size, depth),
            surface,
        }
    }
}

/// A named batch of rays traced together.
#[derive(Clone, Debug)]
pub struct RaySet {
    /// Short name.
    pub name: String,
    /// `true` when each ray is one pixel of a camera image.
    pub pixels: bool,
    /// The rays.
    pub rays: Vec<Query<f32>>,
}

/// Compass azimuth (degrees) of the orbit cameras.
pub const CAMERA_AZIMUTH: f64 = 200.0;
/// Elevations (degrees) of the orbit cameras.
pub const CAMERA_ELEVATIONS: [f64; 3] = [45.0, 15.0, 5.0];
/// Light direction of the shadow rays: compass azimuth and elevation, degrees.
pub const LIGHT: (f64, f64) = (315.0, 20.0);
/// Horizontal field of view of the inside camera, degrees.
pub const INSIDE_FOV_X_DEG: f64 = 90.0;

/// A camera at `eye` looking horizontally towards compass `azimuth`, with
/// [`INSIDE_FOV_X_DEG`] horizontally.
fn sideways(eye: [f64; 3], azimuth: f64, width: u32, height: u32) -> Camera {
    let tan_x = (INSIDE_FOV_X_DEG.to_radians() / 2.0).tan();
    let tan_y = tan_x * f64::from(height) / f64::from(width);
    let pinhole = hfcast::camera::Pinhole {
        eye,
        forward: compass_dir(azimuth, 0.0),
        right: compass_dir(azimuth + 90.0, 0.0).map(|v| v * tan_x),
        up: [0.0, 0.0, tan_y],
        width,
        height,
    };
    Camera {
        world: hfcast::WorldTransform::IDENTITY,
        pinhole,
    }
}

/// Where the inside camera stands: over the centre of the footprint, above the
/// surface there and at least 60 % up the height range.
pub fn inside_eye(hf: &HeightField, surface: Surface) -> [f64; 3] {
    let (x, y) = (
        f64::from(hf.width() - 1) * 0.5,
        f64::from(hf.height() - 1) * 0.5,
    );
    let (lo, hi) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let range = (hi - lo).max(1.0);
    let ground: f64 = surface.height_at(hf, x, y);
    [x, y, (lo + 0.6 * range).max(ground + 0.02 * range)]
}

/// The ray sets of a scene: the orbit cameras at [`CAMERA_ELEVATIONS`], the inside
/// camera, and shadow rays from the oracle's hits of the first camera towards
/// [`LIGHT`] (from the hit, lifted straight up by `lift`, for hits on the top surface
/// that face the light); cameras of `width × height` pixels.
pub fn ray_sets(
    hf: &HeightField,
    surface: Surface,
    width: u32,
    height: u32,
    lift: f64,
) -> Vec<RaySet> {
    let mut sets = Vec::new();
    for el in CAMERA_ELEVATIONS {
        let cam = Camera::orbit(hf, el, CAMERA_AZIMUTH, width, height);
        sets.push(RaySet {
            name: format!("camera {el}°"),
            pixels: true,
            rays: cam.rays(),
        });
    }
    let eye = inside_eye(hf, surface);
    sets.push(RaySet {
        name: "inside, sideways".into(),
        pixels: true,
        rays: sideways(eye, CAMERA_AZIMUTH + 180.0, width, height).rays(),
    });
    let light = compass_dir(LIGHT.0, LIGHT.1);
    let shadow = sets[0]
        .rays
        .iter()
        .filter_map(|q| {
            let hit = dda::trace(hf, surface, &q.cast::<f64>()).hit?;
            if hit.flags.0 != 0 {
                return None;
            }
            let (p, n) = (hit.point.to_array(), hit.normal.to_array());
            if (0..3).map(|k| n[k] * light[k]).sum::<f64>() <= 0.0 {
                return None;
            }
            let o = [p[0] as f32, p[1] as f32, (p[2] + lift) as f32];
            Query::from_arrays(o, light.map(|v| v as f32), 0.0, f32::INFINITY).ok()
        })
        .collect();
    sets.push(RaySet {
        name: "shadow rays".into(),
        pixels: false,
        rays: shadow,
    });
    sets
}

/// The level-of-detail factor of one pixel of the orbit cameras (radians per pixel).
pub fn pixel_angle(height: u32) -> f64 {
    FOV_Y_DEG.to_radians() / f64::from(height.max(1))
}
