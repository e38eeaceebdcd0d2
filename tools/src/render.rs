//! A pinhole camera orbiting the field and a shaded, shadowed CPU renderer.
//!
//! Angles are compass angles in degrees: azimuth 0 = north (image top, −y), 90 = east
//! (+x); elevation above the horizon. The camera is built so that the picture is not
//! mirrored although grid y points south: image right is the camera's east-ish side.
//!
//! [`render`] works in the field's world units ([`HeightField::transform`]: a map's
//! metres and real spacing, see [`crate::maps`]): the camera frames the world box,
//! lights and normals are world vectors, and each primary ray is converted to grid
//! space once ([`Camera::grid_ray`]) for the march. [`Camera::orbit`] (the benchmarks'
//! and the report's camera) stays in grid space.

use crate::maps::Error;
use crate::trace::Tracer;
use crate::{par_chunks, MethodSpec};
use hfcast::camera::Pinhole;
use hfcast::rayset::Rays;
use hfcast::scene::MethodKind;
use hfcast::scene::{BakePlan, RayClasses};
use hfcast::{HeightField, Hit, Query, Surface, Trace, WorldTransform};
use std::io::BufWriter;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Vertical field of view of the camera, degrees.
pub const FOV_Y_DEG: f64 = 40.0;

/// Unit horizontal-and-up vector of a compass `azimuth` and `elevation` (degrees) in
/// grid space (x east, y south, z up).
pub fn compass_dir(azimuth_deg: f64, elevation_deg: f64) -> [f64; 3] {
    compass_dir_in(&WorldTransform::IDENTITY, azimuth_deg, elevation_deg)
}

/// [`compass_dir`] in the world frame of `xf`: east and north are the world images of
/// grid +x and −y (row 0 is north), unit length.
pub fn compass_dir_in(xf: &WorldTransform, azimuth_deg: f64, elevation_deg: f64) -> [f64; 3] {
    let unit = |v: [f64; 3]| scale(v, 1.0 / dot(v, v).sqrt());
    let east = unit(xf.dir_to_world([1.0, 0.0, 0.0]));
    let north = unit(xf.dir_to_world([0.0, -1.0, 0.0]));
    let (a, e) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    let (h, v) = (e.cos(), e.sin());
    [0, 1, 2].map(|k| h * a.sin() * east[k] + h * a.cos() * north[k] + if k == 2 { v } else { 0.0 })
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scale(v: [f64; 3], s: f64) -> [f64; 3] {
    v.map(|x| x * s)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A pinhole camera producing one primary ray per pixel, in the frame of
/// [`Camera::world`] (grid space for [`Camera::orbit`]).
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    /// The frame the camera lives in: its rays are in these world units.
    pub world: WorldTransform,
    /// The pinhole (the core's: eye, view direction, scaled right and up, pixels).
    pub pinhole: Pinhole,
}

impl Camera {
    /// A camera at compass `azimuth` and `elevation` (degrees) from the centre of the
    /// box `[0, W−1] × [0, H−1] × [zmin, zmax]`, looking at that centre, just far enough
    /// away that the whole box is in view (5 % margin).
    pub fn orbit(
        hf: &HeightField,
        elevation_deg: f64,
        azimuth_deg: f64,
        width: u32,
        height: u32,
    ) -> Camera {
        let zmin = f64::from(hf.min_height());
        let grid = WorldTransform::IDENTITY;
        Camera::framing_in(hf, &grid, zmin, elevation_deg, azimuth_deg, width, height)
    }

    /// [`Camera::orbit`] in the world frame of `xf`, framing the box down to `zmin`
    /// instead of the lowest sample: the world image of the grid box
    /// `[0, W−1] × [0, H−1] × [zmin, zmax]` framed, compass angles taken in that frame.
    pub fn framing_in(
        hf: &HeightField,
        xf: &WorldTransform,
        zmin: f64,
        elevation_deg: f64,
        azimuth_deg: f64,
        width: u32,
        height: u32,
    ) -> Camera {
        let lo = xf.point_to_world([0.0, 0.0, zmin]);
        let hi = xf.point_to_world([
            f64::from(hf.width() - 1),
            f64::from(hf.height() - 1),
            f64::from(hf.max_height()),
        ]);
        let size = [0, 1, 2].map(|k| (hi[k] - lo[k]).abs());
        let centre = [0, 1, 2].map(|k| lo[k].min(hi[k]) + size[k] / 2.0);
        let tan_y = (FOV_Y_DEG.to_radians() / 2.0).tan();
        let tan_x = tan_y * f64::from(width) / f64::from(height.max(1));
        let to_eye = compass_dir_in(xf, azimuth_deg, elevation_deg);
        let forward = scale(to_eye, -1.0);
        // Image right points at bearing azimuth + 270° (the camera faces azimuth + 180°);
        // taken from the azimuth so a straight-down view is still defined.
        let right = compass_dir_in(xf, azimuth_deg + 270.0, 0.0);
        // Grid space (x east, y south, z up) is left-handed, a north-up world frame
        // right-handed: the cross product that points up flips with the frame.
        let [sx, sy] = xf.spacing();
        let up = scale(cross(forward, right), (sx * sy).signum());
        // Distance at which every box corner c (relative to the centre) projects inside
        // the image: |c·right| ≤ tan_x (d + c·forward), the same for up.
        let mut dist = 1e-3;
        for corner in 0..8 {
            let c = [0, 1, 2].map(|k| size[k] * (f64::from((corner >> k) & 1) - 0.5));
            let need_x = dot(c, right).abs() / tan_x - dot(c, forward);
            let need_y = dot(c, up).abs() / tan_y - dot(c, forward);
            dist = f64::max(dist, need_x.max(need_y));
        }
        let eye = [0, 1, 2].map(|k| centre[k] + 1.05 * dist * to_eye[k]);
        let pinhole = Pinhole {
            eye,
            forward,
            right: scale(right, tan_x),
            up: scale(up, tan_y),
            width,
            height,
        };
        Camera {
            world: *xf,
            pinhole,
        }
    }

    /// The primary ray through the centre of pixel (`px`, `py`), row 0 at the top;
    /// `t` in `[0, ∞)`, direction not normalised.
    pub fn ray(&self, px: u32, py: u32) -> Query<f32> {
        (self.pinhole.ray(px, py, f32::INFINITY)).expect("camera rays are finite")
    }

    /// [`Camera::ray`] in grid space, for the march (`None` when the conversion
    /// overflows).
    pub fn grid_ray(&self, px: u32, py: u32) -> Option<Query<f32>> {
        let q = self.ray(px, py);
        self.world
            .query_to_grid(q.origin(), q.dir(), q.t_min(), q.t_max())
            .ok()
    }

    /// Every pixel's primary ray, row-major from the top row.
    pub fn rays(&self) -> Vec<Query<f32>> {
        let (w, h) = (self.pinhole.width, self.pinhole.height);
        (0..h)
            .flat_map(|py| (0..w).map(move |px| self.ray(px, py)))
            .collect()
    }
}

/// What to render and how.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Marching method, for primary and shadow rays (baked once per render).
    pub method: MethodSpec,
    /// Surface reconstruction.
    pub surface: Surface,
    /// Camera elevation, degrees.
    pub elevation: f64,
    /// Camera compass azimuth, degrees.
    pub azimuth: f64,
    /// Light (sun) elevation, degrees.
    pub light_elevation: f64,
    /// Light compass azimuth, degrees.
    pub light_azimuth: f64,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Worker threads.
    pub threads: usize,
    /// Print a percentage of rows done on stderr.
    pub progress: bool,
    /// The rays the safety-distance and cylinder–cone maps are baked for. For an
    /// exterior set the shadow rays are traced from the light's side
    /// ([`Hit::shadow_query_from_light`]), so that they are in it.
    pub rays: Rays,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            method: MethodSpec::of(MethodKind::Exact),
            surface: Surface::Triangles,
            elevation: 35.0,
            azimuth: 200.0,
            light_elevation: 30.0,
            light_azimuth: 315.0,
            width: 1024,
            height: 768,
            threads: crate::default_threads(),
            progress: false,
            rays: Rays::ALL,
        }
    }
}

/// An RGB8 image, rows from the top.
#[derive(Clone, Debug)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height × 3` bytes.
    pub rgb: Vec<u8>,
}

/// Counts and time of one render.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    /// Primary rays traced (one per pixel).
    pub primary: u64,
    /// Primary rays that hit the surface.
    pub hits: u64,
    /// Shadow rays traced (hits facing the light).
    pub shadow: u64,
    /// Texture fetches of all rays.
    pub fetches: u64,
    /// Texture fetches of the shadow rays.
    pub shadow_fetches: u64,
    /// Wall time of the whole render (the bake included).
    pub wall: Duration,
    /// Wall time of the method's bake (one thread).
    pub bake: Duration,
    /// Bytes of baked data.
    pub baked_bytes: usize,
}

impl RenderStats {
    /// A one-line summary with rays per second.
    pub fn summary(&self) -> String {
        let s = self.wall.as_secs_f64().max(1e-9);
        let rays = (s - self.bake.as_secs_f64()).max(1e-9);
        let rate = |n: u64| n as f64 / rays / 1e6;
        format!(
            "{:.3} s wall (bake {:.3} s, {} bytes); primary {} rays ({:.2} Mrays/s, {} hits), \
             shadow {} rays ({:.2} Mrays/s), total {:.2} Mrays/s; {:.1} fetches/ray \
             ({:.1} primary, {:.1} shadow)",
            s,
            self.bake.as_secs_f64(),
            self.baked_bytes,
            self.primary,
            rate(self.primary),
            self.hits,
            self.shadow,
            rate(self.shadow),
            rate(self.primary + self.shadow),
            self.fetches as f64 / (self.primary + self.shadow).max(1) as f64,
            (self.fetches - self.shadow_fetches) as f64 / self.primary.max(1) as f64,
            self.shadow_fetches as f64 / self.shadow.max(1) as f64,
        )
    }
}

fn lerp3(a: [f64; 3], b: [f64; 3], f: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * f.clamp(0.0, 1.0))
}

/// Albedo by normalised height `f` in [0, 1]: green, brown, snow.
fn albedo(f: f64) -> [f64; 3] {
    let (green, brown, snow) = ([0.30, 0.48, 0.22], [0.55, 0.44, 0.32], [0.93, 0.93, 0.96]);
    if f < 0.6 {
        lerp3(green, brown, f / 0.6)
    } else {
        lerp3(brown, snow, (f - 0.6) / 0.4)
    }
}

/// The part of `q` at or above the plane `z = base`, or `None`.
fn above_base(q: &Query<f32>, base: f32) -> Option<Query<f32>> {
    let (o, d) = (q.origin(), q.dir());
    let (mut t0, mut t1) = (q.t_min(), q.t_max());
    let t = (base - o[2]) / d[2];
    if d[2] < 0.0 {
        t1 = t1.min(t);
    } else if d[2] > 0.0 {
        t0 = t0.max(t);
    } else if o[2] < base {
        return None;
    }
    Query::from_arrays(o, d, t0, t1).ok()
}

/// The camera of a render, in the field's world units, and the grid height of the
/// slab base it shows the solid down to (15 % of the relief, at least 1 grid unit,
/// under the lowest sample).
pub fn render_camera(hf: &HeightField, opts: &RenderOptions) -> (Camera, f32) {
    let (zmin, zmax) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let base = zmin - f64::max(1.0, 0.15 * (zmax - zmin));
    let (el, az) = (opts.elevation, opts.azimuth);
    let cam = Camera::framing_in(hf, hf.transform(), base, el, az, opts.width, opts.height);
    (cam, base as f32)
}

/// The primary ray of pixel (`px`, `py`) as the render traces it, in grid space:
/// clipped to the half-space above the slab base (`None`: the pixel sees only the sky).
pub fn primary_ray(cam: &Camera, base: f32, px: u32, py: u32) -> Option<Query<f32>> {
    above_base(&cam.grid_ray(px, py)?, base)
}

/// The render's light: the unit direction towards it in world units and in grid
/// space (not unit there unless the transform is the identity).
#[derive(Clone, Copy, Debug)]
pub struct Light {
    /// Unit world direction (shading).
    pub world: [f64; 3],
    /// The same direction in grid space (shadow rays).
    pub grid: [f32; 3],
}

/// The render's light for `hf`'s world frame.
pub fn light_dir(hf: &HeightField, opts: &RenderOptions) -> Light {
    let xf = hf.transform();
    let world = compass_dir_in(xf, opts.light_azimuth, opts.light_elevation);
    let grid = xf.dir_to_grid(world).map(|v| v as f32);
    Light { world, grid }
}

/// The shadow ray (grid space) the render traces from a primary grid-space hit on
/// `surface` of `hf` towards `light`, with the Lambert factor of the hit (world
/// normal · world light); `None` when the hit faces away from the light (no shadow
/// ray). It starts off the surface by [`Hit::shadow_query`]'s documented lift, or,
/// `from_light`, walks the same points from the light's side
/// ([`Hit::shadow_query_from_light`]); `magnitude` is the primary ray's largest
/// |origin| coordinate.
pub fn shadow_ray(
    hf: &HeightField,
    surface: Surface,
    hit: &Hit<f32>,
    light: &Light,
    magnitude: f32,
    from_light: bool,
) -> Option<(Query<f32>, f64)> {
    let n = hf
        .transform()
        .normal_to_world(hit.normal.to_array().map(f64::from));
    let lambert = dot(n, light.world);
    if lambert <= 0.0 {
        return None;
    }
    let q = match from_light {
        true => hit.shadow_query_from_light(hf, surface, light.grid, magnitude),
        false => hit.shadow_query(hf, surface, light.grid, magnitude),
    };
    Some((q.ok()?, lambert))
}

/// The traces of the queries of `queries` that are there, as one batch
/// ([`Tracer::trace_all`]); `None` where there is none.
fn trace_some(tracer: &Tracer, queries: &[Option<Query<f32>>]) -> Vec<Option<Trace<f32>>> {
    let some: Vec<Query<f32>> = queries.iter().flatten().copied().collect();
    let mut out = vec![Trace::MISS; some.len()];
    tracer.trace_all(&some, &mut out);
    let mut traces = out.into_iter();
    queries
        .iter()
        .map(|q| q.and_then(|_| traces.next()))
        .collect()
}

/// The largest |origin| coordinate of `q`: the `magnitude` of [`shadow_ray`].
pub fn origin_magnitude(q: &Query<f32>) -> f32 {
    q.origin().iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The horizontal ray classes of a render's rays (in grid space): its primary rays'
/// and its light's (every shadow ray has the light's direction, or its opposite when
/// traced from the light). The classes its bake computes.
pub fn ray_classes(hf: &HeightField, opts: &RenderOptions) -> RayClasses {
    let (cam, _) = render_camera(hf, opts);
    let light = light_dir(hf, opts).grid;
    let sign = if opts.rays.exterior { -1.0 } else { 1.0 };
    let shadow = RayClasses::NONE.with(hfcast::RayClass::of(sign * light[0], sign * light[1]));
    (0..opts.height)
        .flat_map(|py| (0..opts.width).map(move |px| (px, py)))
        .filter_map(|(px, py)| cam.grid_ray(px, py))
        .fold(shadow, |set, q| set.with(q.class()))
}

/// A render: the picture and, per pixel, what the heat maps show.
#[derive(Clone, Debug)]
pub struct Frame {
    /// The shaded picture.
    pub image: Image,
    /// Per pixel (row-major from the top), the distance from the eye to the primary
    /// hit in world units (grid units without a transform), `None` for the sky.
    pub depth: Vec<Option<f32>>,
    /// Per pixel, the texture fetches of its primary and shadow rays together.
    pub fetches: Vec<u32>,
    /// Counts and times.
    pub stats: RenderStats,
    /// The core's bake plan the method was baked by (`hf_scene_bake_plan` of the same
    /// scene).
    pub plan: BakePlan,
}

/// One pixel's result.
#[derive(Clone, Copy, Debug, Default)]
struct Pixel {
    rgb: [u8; 3],
    depth: Option<f32>,
    fetches: u32,
    /// The shadow ray's share of `fetches`.
    shadow_fetches: u32,
    /// Primary hit, shadow ray traced.
    counts: [bool; 2],
}

/// Renders the field with `opts.method` (baked first, on `opts.threads`, for the
/// render's [`ray_classes`] and `opts.rays`): Lambert shading with a directional
/// light, a shadow ray from every lit hit (from the light's side for an exterior
/// set), a sky gradient for misses. Rows are shared out to the threads in bands.
/// Fails when the method does not trace the surface.
///
/// The core treats everything under the surface as solid, down to −∞; the picture
/// shows it as a slab whose base lies 15 % of the relief (at least 1) under the lowest
/// sample, by clipping primary rays to the half-space above the base.
pub fn render(hf: &HeightField, opts: &RenderOptions) -> Result<Frame, String> {
    let start = Instant::now();
    let classes = ray_classes(hf, opts);
    let tracer = Tracer::bake_for(
        *hf,
        opts.method,
        opts.surface,
        classes,
        opts.rays,
        opts.threads,
    )?;
    let (zmin, zmax) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let (cam, base) = render_camera(hf, opts);
    let light = light_dir(hf, opts);
    let (rows_done, shown) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let width = opts.width as usize;
    let band = 4;
    let mut pixels = vec![Pixel::default(); width * opts.height as usize];

    // A pixel from its world ray, its primary trace (none when the ray misses the slab)
    // and its shadow trace with the Lambert factor (none when the hit faces away).
    let shade = |world: &Query<f32>, tr: Option<Trace<f32>>, shadow: Option<(Trace<f32>, f64)>| {
        let mut px = Pixel {
            fetches: tr.map_or(0, |t| t.fetches),
            ..Pixel::default()
        };
        let Some(hit) = tr.and_then(|t: Trace<f32>| t.hit) else {
            let d = world.dir();
            let up = f64::from(d[2]) / f64::from(d[0].hypot(d[1]).hypot(d[2]));
            px.rgb = to_rgb(lerp3([0.78, 0.86, 0.95], [0.33, 0.52, 0.85], up));
            return px;
        };
        px.counts[0] = true;
        let d = world.dir();
        px.depth = Some(hit.t * d[0].hypot(d[1]).hypot(d[2]));
        let p = hit.point.to_array();
        let colour = if hit.flags.contains(hfcast::Flags::SIDE) {
            [0.42, 0.34, 0.26]
        } else {
            albedo((f64::from(p[2]) - zmin) / (zmax - zmin).max(1e-9))
        };
        let mut lit = 0.0;
        if let Some((st, lambert)) = shadow {
            px.counts[1] = true;
            px.fetches += st.fetches;
            px.shadow_fetches = st.fetches;
            if st.hit.is_none() {
                lit = lambert;
            }
        }
        px.rgb = to_rgb(colour.map(|c| c * (0.22 + 0.78 * lit)));
        px
    };

    // A band's primary rays are traced as one batch, then its shadow rays as another:
    // batches march in SIMD lanes where the method has them (`Tracer::trace_all`).
    par_chunks(&mut pixels, width * band, opts.threads, |first, chunk| {
        let at = |k: usize| (((first + k) % width) as u32, ((first + k) / width) as u32);
        let grid: Vec<Option<Query<f32>>> = (0..chunk.len())
            .map(|k| {
                let (px, py) = at(k);
                cam.grid_ray(px, py).and_then(|q| above_base(&q, base))
            })
            .collect();
        let primary = trace_some(&tracer, &grid);
        let shadows: Vec<Option<(Query<f32>, f64)>> = primary
            .iter()
            .zip(&grid)
            .map(|(tr, q)| {
                let hit = tr.as_ref()?.hit?;
                let magnitude = q.as_ref().map_or(0.0, origin_magnitude);
                shadow_ray(
                    hf,
                    opts.surface,
                    &hit,
                    &light,
                    magnitude,
                    opts.rays.exterior,
                )
            })
            .collect();
        let shadow_queries: Vec<Option<Query<f32>>> =
            shadows.iter().map(|s| s.map(|(q, _)| q)).collect();
        let shadow_traces = trace_some(&tracer, &shadow_queries);
        for (k, out) in chunk.iter_mut().enumerate() {
            let (px, py) = at(k);
            let shadow = shadow_traces[k].zip(shadows[k].map(|(_, l)| l));
            *out = shade(&cam.ray(px, py), primary[k], shadow);
        }
        let done =
            rows_done.fetch_add(chunk.len() / width, Ordering::Relaxed) + chunk.len() / width;
        // Every 5 %.
        let pct = done * 20 / opts.height.max(1) as usize * 5;
        if opts.progress && shown.fetch_max(pct, Ordering::Relaxed) < pct {
            eprint!("\rrender: {pct:3}%");
        }
    });
    if opts.progress {
        eprintln!();
    }
    let count = |k: usize| pixels.iter().filter(|p| p.counts[k]).count() as u64;
    let stats = RenderStats {
        primary: u64::from(opts.width) * u64::from(opts.height),
        hits: count(0),
        shadow: count(1),
        fetches: pixels.iter().map(|p| u64::from(p.fetches)).sum(),
        shadow_fetches: pixels.iter().map(|p| u64::from(p.shadow_fetches)).sum(),
        wall: start.elapsed(),
        bake: tracer.bake_time(),
        baked_bytes: tracer.bytes(),
    };
    let image = Image {
        width: opts.width,
        height: opts.height,
        rgb: pixels.iter().flat_map(|p| p.rgb).collect(),
    };
    Ok(Frame {
        image,
        depth: pixels.iter().map(|p| p.depth).collect(),
        fetches: pixels.iter().map(|p| p.fetches).collect(),
        stats,
        plan: *tracer.plan(),
    })
}

/// A colour in [0, 1] as RGB8.
fn to_rgb(c: [f64; 3]) -> [u8; 3] {
    c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// The heat maps' colour ramp, from low to high: dark blue, blue, cyan, green,
/// yellow, red (equal steps, linear between them).
pub const RAMP: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.35],
    [0.0, 0.2, 1.0],
    [0.0, 0.9, 1.0],
    [0.1, 0.85, 0.1],
    [1.0, 0.9, 0.0],
    [0.85, 0.0, 0.0],
];

/// The colour of `f` in [0, 1] on [`RAMP`] (clamped).
pub fn ramp(f: f64) -> [u8; 3] {
    let x = f.clamp(0.0, 1.0) * (RAMP.len() - 1) as f64;
    let k = (x as usize).min(RAMP.len() - 2);
    to_rgb(lerp3(RAMP[k], RAMP[k + 1], x - k as f64))
}

/// A heat map of `values` (row-major, `width × height`) on [`RAMP`] from `lo` (dark
/// blue) to `hi` (red); `None` pixels black.
pub fn heat_map(width: u32, height: u32, values: &[Option<f64>], lo: f64, hi: f64) -> Image {
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let rgb = values
        .iter()
        .flat_map(|v| v.map_or([0; 3], |v| ramp((v - lo) / span)))
        .collect();
    Image { width, height, rgb }
}

/// The depth and fetch-count heat maps of a frame (Tevs et al. 2008, Fig. 8), each
/// with the range its ramp spans: depth from the nearest to the farthest hit (sky
/// black), fetches per pixel from 0 to their 99th percentile (more is red too, so a
/// few costly pixels do not darken the rest).
pub fn heat_maps(frame: &Frame) -> [(Image, f64, f64); 2] {
    let (w, h) = (frame.image.width, frame.image.height);
    let depth: Vec<Option<f64>> = frame.depth.iter().map(|d| d.map(f64::from)).collect();
    let (lo, hi) = depth
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &d| {
            (a.min(d), b.max(d))
        });
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 0.0) };
    let fetches: Vec<Option<f64>> = frame.fetches.iter().map(|&f| Some(f64::from(f))).collect();
    let mut sorted = frame.fetches.clone();
    sorted.sort_unstable();
    let p99 = sorted
        .get(sorted.len().saturating_sub(1) * 99 / 100)
        .map_or(0.0, |&f| f64::from(f));
    [
        (heat_map(w, h, &depth, lo, hi), lo, hi),
        (heat_map(w, h, &fetches, 0.0, p99), 0.0, p99),
    ]
}

/// Writes an RGB8 PNG, creating the parent folder if needed.
pub fn write_png(path: impl AsRef<Path>, image: &Image) -> Result<(), Error> {
    let path = path.as_ref();
    let err = |e: &dyn std::fmt::Display| Error::at(path, e);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| err(&e))?;
    }
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let mut enc = png::Encoder::new(BufWriter::new(file), image.width, image.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| err(&e))?;
    writer.write_image_data(&image.rgb).map_err(|e| err(&e))?;
    writer.finish().map_err(|e| err(&e))
}
