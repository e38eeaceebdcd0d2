//! A pinhole camera's rays generated and traced by the library, in tile order
//! (`hfcast::camera`): ray order decides how many rays in a row share cells and map
//! texels, so the library orders them rather than leave it to each caller.

use crate::detail::{fail, Named};
use crate::hf_result::{self, *};
use crate::trace::{
    build_horizon, check, grid_line, hf_hit, hf_ray, hf_trace_options, horizon_start,
    horizon_surface, marcher, plain_queries, query_near, shadow_ray_of, trace_locals, trace_plain,
    PlainScratch,
};
use crate::{guard, hf_field, ptr, surface_of};
use hfcore::camera::{Pinhole, TILE};
use hfcore::condition::Near;
use hfcore::horizon::Plan;
use hfcore::scene::Shadows;
use hfcore::Marcher;
use std::ffi::c_void;

/// The side, in pixels, of the square tiles `hf_trace_camera` traces pixels in.
pub const HF_CAMERA_TILE: u32 = 8;
const _: () = assert!(HF_CAMERA_TILE == hfcore::camera::TILE);

/// A pinhole camera in the field's world units (grid units for a field without a
/// transform): pixel (x, y), row 0 at the top, sees along
/// `forward + sx * right + sy * up` from `eye`, `sx`, `sy` in (−1, 1) across the image,
/// `right` and `up` square to `forward` and scaled by the half fields of view.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_camera {
    /// Eye position, finite.
    pub eye: [f32; 3],
    /// View direction, finite and non-zero.
    pub forward: [f32; 3],
    /// Up hint: the image's up is its part square to `forward` (not zero, not parallel
    /// to `forward`).
    pub up: [f32; 3],
    /// Vertical field of view, degrees, in (0, 180).
    pub fov_y_deg: f32,
    /// Image width, pixels (≥ 1).
    pub width: u32,
    /// Image height, pixels (≥ 1).
    pub height: u32,
    /// End of every primary ray's parameter range (`INFINITY` allowed; > 0).
    pub t_max: f32,
}

/// The camera `c`, checked: `HF_ERR_INVALID_ARGUMENT` (with a detail) for a
/// degenerate one.
fn pinhole_of(c: &hf_camera) -> Result<Pinhole, hf_result> {
    let v = |a: [f32; 3]| a.map(f64::from);
    let p = Pinhole::new(
        v(c.eye),
        v(c.forward),
        v(c.up),
        f64::from(c.fov_y_deg),
        c.width,
        c.height,
    )
    .map_err(|e| fail(HF_ERR_INVALID_ARGUMENT, format_args!("camera: {e}")))?;
    if c.t_max.is_nan() || c.t_max <= 0.0 {
        return Err(fail(HF_ERR_INVALID_ARGUMENT, "camera: t_max must be > 0"));
    }
    Ok(p)
}

/// The primary ray of pixel (x, y) of `p` as an `hf_ray` (inlined: returned through
/// memory, its narrow stores stall the wide loads that read it back).
#[inline(always)]
fn pixel_ray(p: &Pinhole, t_max: f32, x: u32, y: u32) -> Result<hf_ray, hf_result> {
    let q = p
        .ray(x, y, t_max)
        .map_err(|e| fail(HF_ERR_INVALID_ARGUMENT, format_args!("camera: {e}")))?;
    Ok(hf_ray::from(q))
}

/// Writes the primary ray of pixel (`x`, `y`) of `*camera` to `*out_ray`: the ray
/// `hf_trace_camera` traces for that pixel, bit for bit. `HF_ERR_INVALID_ARGUMENT`
/// for a degenerate camera or a pixel outside the image. Thread safe.
///
/// # Safety
/// `camera` is NULL (an error) or valid for reading; `out_ray` NULL (an error) or
/// valid for writing one `hf_ray`.
#[no_mangle]
pub unsafe extern "C" fn hf_camera_ray(
    camera: *const hf_camera,
    x: u32,
    y: u32,
    out_ray: *mut hf_ray,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `camera` is readable.
        let c = unsafe { ptr::get(camera) }.named("camera")?;
        let out = ptr::out(out_ray).named("out_ray")?;
        let p = pinhole_of(c)?;
        if x >= c.width || y >= c.height {
            return Err(fail(
                HF_ERR_INVALID_ARGUMENT,
                format_args!(
                    "pixel ({x}, {y}): outside the {} x {} image",
                    c.width, c.height
                ),
            ));
        }
        let r = pixel_ray(&p, c.t_max, x, y)?;
        // SAFETY: the caller promises `out_ray` is writable.
        unsafe { out.set(r) };
        Ok(())
    })
}

/// What both camera passes trace: their exports' first arguments (`field`, `method`,
/// `map`, `map_len`, `options`, `camera`), as they take them.
type Pass = (
    *const hf_field,
    u32,
    *const c_void,
    usize,
    *const hf_trace_options,
    *const hf_camera,
);

/// Shared body of the camera passes: checks the camera and the output (`width ×
/// height` hits), builds the method's marcher, checks the pixels' rays (`ray(p, x, y)`,
/// `None` for a pixel traced as a miss; with `every_pixel` each one, else the corners',
/// which bound a pinhole's) before tracing any, then traces them in
/// tile order (`hfcast::camera::TILE`-pixel squares, bands of tile rows over
/// `options->threads` threads) into `out[y * width + x]`.
///
/// # Safety
/// As `hf_trace_camera`.
unsafe fn trace_pixels<PixelRay>(
    pass: Pass,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
    ray: &PixelRay,
    every_pixel: bool,
) -> hf_result
where
    PixelRay: Fn(&Pinhole, &Marcher, f32, u32, u32) -> Result<Option<hf_ray>, hf_result> + Sync,
{
    let (field, method, map, map_len, options, camera) = pass;
    guard(|| {
        // SAFETY: the caller promises a live handle and a readable camera.
        let (f, c) = unsafe {
            (
                ptr::get(field).named("field")?,
                ptr::get(camera).named("camera")?,
            )
        };
        // SAFETY: the caller promises `out_hits` is writable for its length.
        let out = unsafe { ptr::slice_mut(out_hits, out_hits_len) }.named("out_hits")?;
        let p = pinhole_of(c)?;
        let pixels = c.width as usize * c.height as usize;
        if out.len() < pixels {
            return Err(fail(
                HF_ERR_BUFFER_TOO_SMALL,
                format_args!("out_hits: {} hits for {pixels} pixels", out.len()),
            ));
        }
        // SAFETY: the caller's promises, passed on.
        let (m, o) = unsafe { marcher(f, method, map, map_len, options) }?;
        let hf = f.view();
        // Every pixel's ray is checked before any is traced (an error writes nothing);
        // primary rays need only the four corners': every other direction is a convex
        // combination of theirs from the same eye, finite and non-zero when they are.
        let (w, h) = (c.width, c.height);
        let corners = [(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)];
        let check_at = |(x, y): (u32, u32)| -> Result<(), hf_result> {
            match ray(&p, &m, c.t_max, x, y)? {
                Some(r) => check(hf, &r, Some(y as usize * w as usize + x as usize)),
                None => Ok(()),
            }
        };
        match every_pixel {
            true => p.tiles(0..h).try_for_each(|(ys, xs)| {
                ys.flat_map(|y| xs.clone().map(move |x| (x, y)))
                    .try_for_each(check_at)
            })?,
            false => corners.into_iter().try_for_each(check_at)?,
        }
        // Primary rays share the eye: a horizon placed by the image's border rays (an
        // azimuth inside the image is one of the border's; the others are traced
        // without it), its blocks sized by those and a grid of the pixels inside (how
        // many rays come into the field above its surface).
        let horizon = match every_pixel {
            true => None,
            false => {
                let inside = (0..h)
                    .step_by(16)
                    .flat_map(|y| (0..w).step_by(16).map(move |x| (x, y)));
                let border = (0..w)
                    .flat_map(|x| [(x, 0), (x, h - 1)])
                    .chain((0..h).flat_map(|y| [(0, y), (w - 1, y)]))
                    .chain(inside);
                let lines = border
                    .map(|(x, y)| ray(&p, &m, c.t_max, x, y))
                    .collect::<Result<Vec<_>, _>>()?;
                let lines: Vec<_> = lines.iter().flatten().map(|r| grid_line(hf, r)).collect();
                match (horizon_surface(&m, &o, pixels), lines.first()) {
                    (Some(surface), Some(&(eye, _))) => {
                        let dirs = lines.iter().map(|l| l.1);
                        let max_block = m.horizon_max_block();
                        Plan::sized(hf, surface, eye, dirs, pixels, max_block)
                            .map(|plan| build_horizon(plan, o.threads))
                    }
                    _ => None,
                }
            }
        };
        let out = &mut out[..pixels];
        crate::par::bake_bands(
            c.height,
            c.width as usize,
            TILE,
            o.threads,
            out,
            |rows, band| {
                // A row of tiles is traced at once, its rays in tile order: a laned
                // march's lanes drain at the end of each call (measured, the maximum
                // mipmap on the Himalaya DEM: 198 ns a ray at 45° and 175 at 5° with a
                // call a tile, 178 and 146 with a call a row of tiles). Its hits
                // gather in `local`, then go to the image a tile row at a time:
                // stores scattered over eight image rows cost more than the traces of
                // cheap rays (measured: 190 against 105 ns a ray that misses the box).
                let (first, width) = (rows.start as usize * c.width as usize, c.width as usize);
                let (mut rays, mut flat, mut local) = (Vec::new(), Vec::new(), Vec::new());
                let (mut queries, mut starts) = (Vec::new(), Vec::new());
                let mut traced = PlainScratch::default();
                let (mut hint, near) = (0, Near::of(hf));
                for y0 in rows.clone().step_by(TILE as usize) {
                    let tiles: Vec<_> = p.tiles(y0..(y0 + TILE).min(rows.end)).collect();
                    let pixels = || {
                        tiles.iter().flat_map(|(ys, xs)| {
                            ys.clone()
                                .flat_map(move |y| xs.clone().map(move |x| (x, y)))
                        })
                    };
                    rays.clear();
                    flat.clear();
                    for (x, y) in pixels() {
                        let r = ray(&p, &m, c.t_max, x, y)?;
                        flat.extend(r);
                        rays.push(r);
                    }
                    let n = rays.len();
                    local.clear();
                    local.resize(n, hf_hit::default());
                    let plain = (flat.len() == n).then(|| plain_queries(hf, &near, &flat));
                    if let Some(plain) = plain.flatten() {
                        // Every pixel has a ray that needs no conditioning: traced as
                        // the batches trace theirs.
                        let plain = (plain, &mut traced);
                        trace_plain((&m, &o, hf), horizon.as_ref(), plain, &mut hint, &mut local);
                    } else {
                        queries.clear();
                        starts.clear();
                        for ((x, y), r) in pixels().zip(&rays) {
                            let k = y as usize * width + x as usize;
                            queries.push(match r {
                                Some(r) => Some(query_near(hf, &near, r, Some(k))?),
                                None => None,
                            });
                            starts.push(match (&horizon, r) {
                                (Some(h), Some(r)) => horizon_start(h, hf, r, &mut hint),
                                _ => None,
                            });
                        }
                        trace_locals(&m, &o, hf, &queries, &starts, &mut local);
                    }
                    let mut hits = local.as_slice();
                    for (ys, xs) in &tiles {
                        let (tile, rest) = hits.split_at(ys.len() * xs.len());
                        for (dy, row) in tile.chunks(xs.len()).enumerate() {
                            let k = (ys.start as usize + dy) * width + xs.start as usize - first;
                            band[k..k + xs.len()].copy_from_slice(row);
                        }
                        hits = rest;
                    }
                }
                Ok(())
            },
        )
    })
}

/// Traces every pixel's primary ray of `*camera` (`hf_camera_ray`) with `method` over
/// its `map`, as `hf_trace_batch` does (the same options, `options->threads` threads;
/// NULL: the defaults) into `out_hits[y * width + x]` (`out_hits_len ≥ width *
/// height`). The rays are generated by the library and traced in tiles of
/// `HF_CAMERA_TILE` × `HF_CAMERA_TILE` pixels, neighbours in turn, so that successive
/// rays share cells and map texels; the hits equal `hf_trace_batch`'s on the same rays
/// bit for bit. With the exact DDA and maximum mipmap, a camera of at least
/// `HF_HORIZON_MIN_GROUP` pixels shares a horizon placed by its border rays
/// (`hf_trace_options::horizon`): the hits are the same, `fetches` and `clearance` may
/// differ from the batch's. Everything is checked first; an error writes nothing.
/// Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `map` as `hf_trace`; `options` NULL or
/// valid; `camera` NULL (an error) or valid; `out_hits` NULL (an error) or valid for
/// writing `out_hits_len` hits.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_camera(
    field: *const hf_field,
    method: u32,
    map: *const c_void,
    map_len: usize,
    options: *const hf_trace_options,
    camera: *const hf_camera,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let pass = (field, method, map, map_len, options, camera);
    let primary =
        |p: &Pinhole, _: &Marcher, t_max: f32, x: u32, y: u32| pixel_ray(p, t_max, x, y).map(Some);
    // SAFETY: the caller's promises, passed on.
    unsafe { trace_pixels(pass, out_hits, out_hits_len, &primary, false) }
}

/// The shadow pass of `hf_trace_camera`: for every pixel whose primary hit `hits[y *
/// width + x]` (from `hf_trace_camera` with the same camera and `options->surface`,
/// `hits_len ≥ width * height`) is a hit, the shadow ray `hf_shadow_ray` makes from it
/// towards `to_light` (a direction in the field's world units), traced with `method`
/// over its `map` in the same tile order into `out_shadows[y * width + x]` (hit 1: the
/// point is in shadow); a pixel whose primary ray missed gets a miss without a trace.
/// Over a map baked for exterior rays the ray is `hf_shadow_ray_from_light`'s instead
/// (the same points from the light's side, in the map's set: the map's steps serve
/// it). The answers equal that ray's `hf_trace` per pixel, bit for bit.
/// Everything is checked first; an error writes nothing. Thread safe.
///
/// # Safety
/// As `hf_trace_camera`; `hits` NULL (an error) or valid for reading `hits_len` hits;
/// `to_light` NULL (an error) or valid for reading 3 floats; `out_shadows` may not
/// overlap `hits`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_camera_shadows(
    field: *const hf_field,
    method: u32,
    map: *const c_void,
    map_len: usize,
    options: *const hf_trace_options,
    camera: *const hf_camera,
    hits: *const hf_hit,
    hits_len: usize,
    to_light: *const [f32; 3],
    out_shadows: *mut hf_hit,
    out_shadows_len: usize,
) -> hf_result {
    let mut pre = Err(HF_ERR_PANIC);
    let code = guard(|| {
        // SAFETY: the caller promises readable inputs; `out_shadows` is checked not to
        // overlap `hits` by the slices' byte ranges.
        let (f, c, l) = unsafe {
            (
                ptr::get(field).named("field")?,
                ptr::get(camera).named("camera")?,
                *ptr::get(to_light).named("to_light")?,
            )
        };
        // SAFETY: as above.
        let (primary, _) = unsafe {
            ptr::slice_and_out(
                (hits, hits_len, "hits"),
                (out_shadows, out_shadows_len, "out_shadows"),
            )
        }?;
        let pixels = c.width as usize * c.height as usize;
        if primary.len() < pixels {
            return Err(fail(
                HF_ERR_BUFFER_TOO_SMALL,
                format_args!("hits: {} hits for {pixels} pixels", primary.len()),
            ));
        }
        let surface = match options.is_null() {
            true => hfcore::Surface::Triangles,
            // SAFETY: the caller promises non-NULL options are readable.
            false => surface_of(unsafe { ptr::get(options) }?.surface)?,
        };
        pre = Ok((f, surface, l, primary));
        Ok(())
    });
    let Ok((f, surface, l, primary)) = pre else {
        return code;
    };
    let hf = f.view();
    let shadow = |p: &Pinhole, m: &Marcher, t_max: f32, x: u32, y: u32| {
        let h = &primary[y as usize * p.width as usize + x as usize];
        if h.hit == 0 {
            return Ok(None);
        }
        let r = pixel_ray(p, t_max, x, y)?;
        let from = match m.rays().exterior {
            true => Shadows::FromLight,
            false => Shadows::FromSurface,
        };
        shadow_ray_of(hf, surface, &r, h, l, from).map(Some)
    };
    let pass = (field, method, map, map_len, options, camera);
    // SAFETY: the caller's promises, passed on.
    unsafe { trace_pixels(pass, out_shadows, out_shadows_len, &shadow, true) }
}
