//! Ray queries: one ray or a batch, for every method.

use crate::detail::fail_at;
use crate::hf_result::{self, *};
use crate::ptr::Named;
use crate::{guard, hf_field, ptr, surface_of};
use hfcore::condition::{condition, condition_query, Local};
#[cfg(feature = "maxmip")]
use hfcore::maxmip::{self, MaxMip};
#[cfg(feature = "search")]
use hfcore::search::{self, SearchSteps};
#[cfg(feature = "maxmip")]
use hfcore::Surface;
use hfcore::{dda, Flags, HeightField, Hit, Query, Trace};

/// A ray: the points `origin + t * dir` for `t` in `[t_min, t_max]`, in grid space, or
/// in the field's world units when it has a transform (`hf_field_set_transform`).
/// `dir` need not be normalised (t is then in units of `|dir|`) but must be finite
/// and non-zero, also after conversion to grid space; `t_min` finite; `t_max ≥ t_min`,
/// `INFINITY` allowed. Grid space: x along sample columns i, y along rows j, z up, all
/// in sample spacings.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hf_ray {
    /// Origin (x, y, z) in grid units (world units with a transform).
    pub origin: [f32; 3],
    /// Direction (x, y, z), finite and non-zero.
    pub dir: [f32; 3],
    /// Start of the parameter range (finite).
    pub t_min: f32,
    /// End of the parameter range (`INFINITY` allowed).
    pub t_max: f32,
}

/// The answer to one query. On a miss `hit` is 0 and every field but `fetches`,
/// `flags` and `clearance` is 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hf_hit {
    /// 1 when the ray meets the surface in `[t_min, t_max]`, else 0.
    pub hit: u32,
    /// `HF_FLAG_*` bits: those of the hit (`ORIGIN_INSIDE`, `SIDE`, `WALL`) and of the
    /// trace (`BUDGET_EXHAUSTED`).
    pub flags: u32,
    /// Texture fetches used (one per texel read; a cell's four corners are four): the
    /// hardware-independent cost.
    pub fetches: u32,
    /// The cell (i, j) holding the hit: the unit square [i, i+1] × [j, j+1].
    pub cell: [u32; 2],
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point in grid space (world units with a transform).
    pub point: [f32; 3],
    /// Unit surface normal at the hit (a wall's normal for side and step hits).
    pub normal: [f32; 3],
    /// Smallest clearance (ray height − surface height, grid units; world height units
    /// with a transform) seen before the hit
    /// or along the whole ray for a miss; `INFINITY` when the ray never overlaps the
    /// field. Exact methods fill it; approximate ones report `INFINITY`.
    pub clearance: f32,
}

impl From<Trace<f32>> for hf_hit {
    fn from(tr: Trace<f32>) -> hf_hit {
        let mut out = hf_hit {
            flags: tr.flags.0,
            fetches: tr.fetches,
            clearance: tr.clearance,
            ..hf_hit::default()
        };
        if let Some(h) = tr.hit {
            out.hit = 1;
            out.flags |= h.flags.0;
            out.cell = h.cell;
            out.t = h.t;
            out.point = h.point.to_array();
            out.normal = h.normal.to_array();
        }
        out
    }
}

/// Checks a ray, converts it from the field's world units to grid space (in f64) and
/// conditions it for the f32 march (`hfcore::condition`: a far origin rebased near the
/// field, a tiny or huge direction scaled); an invalid ray's detail names it `ray`, or
/// `rays[index]` (and records `index`) in a batch.
fn query(hf: &HeightField, r: &hf_ray, index: Option<usize>) -> Result<Local, hf_result> {
    let err = |e| ray_error(e, index);
    // The world ray's own faults first, named as such.
    let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max).map_err(err)?;
    let xf = hf.transform();
    if xf.is_identity() {
        return Ok(condition_query(hf, &q));
    }
    let o = xf.point_to_grid(r.origin.map(f64::from));
    let d = xf.dir_to_grid(r.dir.map(f64::from));
    condition(hf, o, d, r.t_min, r.t_max).map_err(err)
}

/// [`query`]'s checks alone (a batch's first pass): for a field without a transform,
/// the ray's own (conditioning a valid grid ray cannot fail).
fn check(hf: &HeightField, r: &hf_ray, index: Option<usize>) -> Result<(), hf_result> {
    if hf.transform().is_identity() {
        let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max);
        return q.map(|_| ()).map_err(|e| ray_error(e, index));
    }
    query(hf, r, index).map(|_| ())
}

/// The error of an invalid ray: its detail names it `ray`, or `rays[index]` (and
/// records `index`) in a batch.
fn ray_error(e: hfcore::RayError, index: Option<usize>) -> hf_result {
    match index {
        Some(k) => fail_at(HF_ERR_INVALID_RAY, index, format_args!("rays[{k}]: {e}")),
        None => fail_at(HF_ERR_INVALID_RAY, None, format_args!("ray: {e}")),
    }
}

/// A grid-space trace as the caller's `hf_hit`, in the field's world units.
fn answer(hf: &HeightField, tr: Trace<f32>) -> hf_hit {
    hf_hit::from(hf.transform().trace_to_world(tr))
}

/// Shared body of the single-ray functions: checks the pointers, prepares what the
/// method reads (its map, checked against the field, once), traces, writes.
///
/// # Safety
/// `field` NULL or live; `ray` NULL or valid; `out_hit` NULL or writable.
pub(crate) unsafe fn one<P>(
    field: *const hf_field,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
    prepare: impl FnOnce(&hf_field) -> Result<P, hf_result>,
    trace: impl Fn(&HeightField, &P, &Query<f32>) -> Trace<f32>,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle and a valid ray (copied, so that
        // `out_hit` may even overlap it).
        let (f, r) = unsafe {
            (
                ptr::get(field).named("field")?,
                *ptr::get(ray).named("ray")?,
            )
        };
        let out = ptr::out(out_hit).named("out_hit")?;
        let hf = f.view();
        let prepared = prepare(f)?;
        let local = query(hf, &r, None)?;
        let hit = answer(hf, local.trace(|q| trace(hf, &prepared, q)));
        // SAFETY: the caller promises `out_hit` is writable.
        unsafe { out.set(hit) };
        Ok(())
    })
}

/// Shared body of the batch functions: checks everything (the pointers, that `rays`
/// and `out_hits` share no byte, the output's length, every ray) first and prepares
/// what the method reads once, then traces into the output, so an error writes
/// nothing. An empty batch (`rays_len` 0) passes the same checks and writes nothing.
///
/// # Safety
/// `field` NULL or live; `rays` NULL or valid for `rays_len`; `out_hits` NULL or
/// writable for `out_hits_len`.
pub(crate) unsafe fn batch<P>(
    field: *const hf_field,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
    prepare: impl FnOnce(&hf_field) -> Result<P, hf_result>,
    trace: impl Fn(&HeightField, &P, &Query<f32>) -> Trace<f32>,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle.
        let f = unsafe { ptr::get(field) }.named("field")?;
        // SAFETY: the caller promises `rays_len` valid rays and `out_hits` writable for
        // its length; the two are checked disjoint before the slices exist.
        let (rays, hits) = unsafe {
            ptr::slice_and_out(
                (rays, rays_len, "rays"),
                (out_hits, out_hits_len, "out_hits"),
            )
        }?;
        if hits.len() < rays.len() {
            return Err(crate::detail::fail(
                HF_ERR_BUFFER_TOO_SMALL,
                format_args!("out_hits: {} hits for {} rays", hits.len(), rays.len()),
            ));
        }
        let hf = f.view();
        let prepared = prepare(f)?;
        for (k, r) in rays.iter().enumerate() {
            check(hf, r, Some(k))?;
        }
        for (k, (r, h)) in rays.iter().zip(hits.iter_mut()).enumerate() {
            let local = query(hf, r, Some(k))?;
            *h = answer(hf, local.trace(|q| trace(hf, &prepared, q)));
        }
        Ok(())
    })
}

/// A shadow ray from `hit` (the answer `hf_trace_*` gave for `primary` on `surface`, an
/// `hf_surface` value, of `field`; in world units when the field has a transform)
/// towards a light in direction `to_light`, written to `*out_ray`: its origin is the
/// hit point lifted off the surface (along the normal by `64 · FLT_EPSILON · (1 + m)`
/// grid units, `m` the largest magnitude of the hit point's and the primary origin's
/// grid coordinates, then to at least that above the surface where it lies over the
/// field), `t` in `[0, INFINITY]`. A shadow ray started at the hit point itself often
/// reports `HF_FLAG_ORIGIN_INSIDE` (the point rounds into the solid); this one starts
/// outside. `HF_ERR_INVALID_ARGUMENT` when `hit->hit` is 0. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `primary`, `hit` and `to_light` (3
/// floats) are NULL (an error) or valid for reading; `out_ray` is NULL (an error) or
/// valid for writing one `hf_ray`.
#[no_mangle]
pub unsafe extern "C" fn hf_shadow_ray(
    field: *const hf_field,
    surface: u32,
    primary: *const hf_ray,
    hit: *const hf_hit,
    to_light: *const [f32; 3],
    out_ray: *mut hf_ray,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle and readable inputs.
        let (f, p, h, l) = unsafe {
            (
                ptr::get(field)?,
                ptr::get(primary)?,
                ptr::get(hit)?,
                ptr::get(to_light)?,
            )
        };
        let out = ptr::out(out_ray)?;
        let surface = surface_of(surface)?;
        let hf = f.view();
        if h.hit == 0 || !h.point.iter().chain(&h.normal).all(|v| v.is_finite()) {
            return Err(HF_ERR_INVALID_ARGUMENT);
        }
        let primary = Query::from_arrays(p.origin, p.dir, p.t_min, p.t_max)?;
        let world_hit = Hit {
            t: h.t,
            point: h.point.into(),
            cell: h.cell,
            normal: h.normal.into(),
            flags: Flags(h.flags),
        };
        let q = hf
            .transform()
            .shadow_query(hf, surface, &primary, &world_hit, *l)?;
        let ray = hf_ray {
            origin: q.origin(),
            dir: q.dir(),
            t_min: q.t_min(),
            t_max: q.t_max(),
        };
        // SAFETY: the caller promises `out_ray` is writable.
        unsafe { out.set(ray) };
        Ok(())
    })
}

#[cfg(feature = "search")]
/// The search step counts, checked.
fn steps(linear: u32, binary: u32) -> Result<SearchSteps, hf_result> {
    if linear == 0 {
        return Err(crate::detail::fail(
            HF_ERR_INVALID_ARGUMENT,
            "linear_steps: must be at least 1",
        ));
    }
    Ok(SearchSteps { linear, binary })
}

/// Traces one ray with the exact method (grid traversal with the exact per-cell test
/// of `surface`, an `hf_surface` value): the first hit in `[t_min, t_max]`, watertight
/// in `float`. Writes `*out_hit` (a miss is success with `hit = 0`). Costs four
/// fetches per cell visited. Thread safe (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `ray` is NULL (an error) or valid;
/// `out_hit` is NULL (an error) or valid for writing one `hf_hit`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_exact(
    field: *const hf_field,
    surface: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    let surface = match surface_of(surface) {
        Ok(s) => s,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        one(
            field,
            ray,
            out_hit,
            |_| Ok(()),
            |hf, _, q| dda::trace(hf, surface, q),
        )
    }
}

/// `hf_trace_exact` for `rays_len` rays: `out_hits[k]` answers `rays[k]`;
/// `out_hits_len ≥ rays_len`. Everything is checked before any ray is traced, and an
/// error writes nothing: `out_hits` sharing a byte with `rays` (over their whole
/// lengths) is `HF_ERR_INVALID_ARGUMENT`; one bad ray fails the call
/// (`HF_ERR_INVALID_RAY`; `hf_last_error_index` gives the first bad ray). An empty
/// batch (`rays_len` 0) is `HF_OK` and writes nothing; its pointers must still be
/// non-NULL. Thread safe.
///
/// # Safety
/// `rays` is NULL (an error) or valid for reading `rays_len` rays; `out_hits` NULL (an
/// error) or valid for writing `out_hits_len` hits.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_exact_batch(
    field: *const hf_field,
    surface: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let surface = match surface_of(surface) {
        Ok(s) => s,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        batch(
            field,
            rays,
            rays_len,
            out_hits,
            out_hits_len,
            |_| Ok(()),
            |hf, _, q| dda::trace(hf, surface, q),
        )
    }
}

#[cfg(feature = "search")]
/// Traces one ray with linear search then bisection (Policarpo et al. 2005):
/// `linear_steps ≥ 1` equal steps through the field's bounding box, then
/// `binary_steps` bisections of the first step that ends under `surface`.
/// Approximate: features thinner than a step are missed. Costs four fetches per
/// height sample. Thread safe.
///
/// # Safety
/// As `hf_trace_exact`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_linear_binary(
    field: *const hf_field,
    surface: u32,
    linear_steps: u32,
    binary_steps: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    let (surface, steps) = match (surface_of(surface), steps(linear_steps, binary_steps)) {
        (Ok(s), Ok(n)) => (s, n),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        one(
            field,
            ray,
            out_hit,
            |_| Ok(()),
            |hf, _, q| search::linear_binary(hf, surface, q, steps),
        )
    }
}

#[cfg(feature = "search")]
/// `hf_trace_linear_binary` for a batch, with the conventions of
/// `hf_trace_exact_batch`. Thread safe.
///
/// # Safety
/// As `hf_trace_exact_batch`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_linear_binary_batch(
    field: *const hf_field,
    surface: u32,
    linear_steps: u32,
    binary_steps: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let (surface, steps) = match (surface_of(surface), steps(linear_steps, binary_steps)) {
        (Ok(s), Ok(n)) => (s, n),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        batch(
            field,
            rays,
            rays_len,
            out_hits,
            out_hits_len,
            |_| Ok(()),
            |hf, _, q| search::linear_binary(hf, surface, q, steps),
        )
    }
}

#[cfg(feature = "search")]
/// Traces one ray with linear search then one secant step (parallax occlusion
/// mapping): `linear_steps ≥ 1` equal steps, then the secant of the bracketing step.
/// Approximate. Costs four fetches per height sample. Thread safe.
///
/// # Safety
/// As `hf_trace_exact`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_linear_secant(
    field: *const hf_field,
    surface: u32,
    linear_steps: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    let (surface, steps) = match (surface_of(surface), steps(linear_steps, 0)) {
        (Ok(s), Ok(n)) => (s, n),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        one(
            field,
            ray,
            out_hit,
            |_| Ok(()),
            |hf, _, q| search::linear_secant(hf, surface, q, steps.linear),
        )
    }
}

#[cfg(feature = "search")]
/// `hf_trace_linear_secant` for a batch, with the conventions of
/// `hf_trace_exact_batch`. Thread safe.
///
/// # Safety
/// As `hf_trace_exact_batch`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_linear_secant_batch(
    field: *const hf_field,
    surface: u32,
    linear_steps: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let (surface, steps) = match (surface_of(surface), steps(linear_steps, 0)) {
        (Ok(s), Ok(n)) => (s, n),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        batch(
            field,
            rays,
            rays_len,
            out_hits,
            out_hits_len,
            |_| Ok(()),
            |hf, _, q| search::linear_secant(hf, surface, q, steps.linear),
        )
    }
}

#[cfg(feature = "maxmip")]
/// Traces one ray with maximum mipmaps (Tevs et al. 2008) over `pyramid`, the buffer
/// `hf_maxmip_bake` filled for this field (`pyramid_len ≥ hf_maxmip_len`): exact, the
/// same hit as `hf_trace_exact` (the linear-planes surface is traced by the exact
/// method). The pyramid's descriptor is checked first: `HF_ERR_MAP_MISMATCH` for a
/// pyramid of another field or size, `HF_ERR_STALE_MAP` for one baked before an
/// update of this field (refresh it with `hf_maxmip_update_rect`). Costs one fetch per
/// pyramid texel, four per exact cell test. Thread safe.
///
/// # Safety
/// As `hf_trace_exact`; `pyramid` is NULL (an error) or valid for reading
/// `pyramid_len` floats, not written during the call.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_maxmip(
    field: *const hf_field,
    pyramid: *const f32,
    pyramid_len: usize,
    surface: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    let surface = match surface_of(surface) {
        Ok(s) => s,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    let texels = match unsafe { pyramid_slice(pyramid, pyramid_len) } {
        Ok(t) => t,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        one(
            field,
            ray,
            out_hit,
            |f| mip_of(f, texels),
            |hf, mip, q| trace_mip(hf, mip, surface, q),
        )
    }
}

#[cfg(feature = "maxmip")]
/// `hf_trace_maxmip` for a batch, with the conventions of `hf_trace_exact_batch`.
/// Thread safe.
///
/// # Safety
/// As `hf_trace_exact_batch` and `hf_trace_maxmip`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_maxmip_batch(
    field: *const hf_field,
    pyramid: *const f32,
    pyramid_len: usize,
    surface: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let surface = match surface_of(surface) {
        Ok(s) => s,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    let texels = match unsafe { pyramid_slice(pyramid, pyramid_len) } {
        Ok(t) => t,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        batch(
            field,
            rays,
            rays_len,
            out_hits,
            out_hits_len,
            |f| mip_of(f, texels),
            |hf, mip, q| trace_mip(hf, mip, surface, q),
        )
    }
}

#[cfg(any(feature = "maxmip", feature = "cone", feature = "safety"))]
/// A baked buffer (pyramid or map) as a slice, checked behind the panic boundary.
///
/// # Safety
/// `p` NULL or valid for reading `len` floats.
pub(crate) unsafe fn pyramid_slice<'a, T>(p: *const T, len: usize) -> Result<&'a [T], hf_result> {
    let mut out = Err(HF_ERR_PANIC);
    let r = guard(|| {
        // SAFETY: the caller's promise.
        out = Ok(unsafe { ptr::slice(p, len) }?);
        Ok(())
    });
    if r != HF_OK {
        return Err(r);
    }
    out
}

#[cfg(feature = "maxmip")]
/// The pyramid over `texels`, its descriptor checked for `f`.
fn mip_of<'a>(f: &hf_field, texels: &'a [f32]) -> Result<MaxMip<'a>, hf_result> {
    let n = maxmip::Layout::of(f.view()).texel_count();
    let want = crate::mapdesc::Expect::map(hfcore::ktx2::MapKind::MaxMip);
    crate::mapdesc::check(f, want, texels, n)?;
    Ok(MaxMip::new(f.view(), &texels[..n])?)
}

#[cfg(feature = "maxmip")]
/// One maxmip trace with exact options.
fn trace_mip(hf: &HeightField, mip: &MaxMip, surface: Surface, q: &Query<f32>) -> Trace<f32> {
    maxmip::trace(hf, mip, surface, q, &maxmip::Options::default())
}
