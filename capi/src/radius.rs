//! Safety radius (Baboud & Décoret 2006, §3.4–3.5): sizes, bake (whole, by rows,
//! threaded) and the march, for the triangle surface. The bake shares the strip bounds
//! of the safety distances (`hf_safety_prepare`).

use crate::hf_result::{self, *};
use crate::mapdesc::{bake_stamped, check, elems, stamp, Expect};
use crate::safety;
use crate::size_query;
use crate::trace::{batch, hf_hit, hf_ray, one};
use crate::{guard, hf_field, hf_surface, par, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::radius::{self, BakeOptions, Options, RadiusMap, Zero};
use hfcore::HeightField;

/// What the radius march does at a texel of radius zero. Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_radius_zero {
    /// Walk to the next centerline cell by cell with the exact test (exact).
    HF_RADIUS_WALK = 0,
    /// Jump one centerline as if the radius were 1: fewer fetches, **not exact** (a
    /// dip under the surface between two centerlines may be skipped).
    HF_RADIUS_CLAMP = 1,
}

/// What a radius bake computes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_radius_options {
    /// Error tolerance in grid units, finite and ≥ 0 (0: the exact radius; larger
    /// gives larger radii and rays may pass under the surface by up to that depth).
    pub tolerance: f32,
    /// Largest radius stored, 0..=255 (255 is the default; smaller is conservative).
    pub cap: u32,
}

/// Checks bake options.
fn options_of(o: &hf_radius_options) -> Result<BakeOptions, hf_result> {
    if !o.tolerance.is_finite() || o.tolerance < 0.0 {
        return Err(HF_ERR_INVALID_ARGUMENT);
    }
    let cap = u8::try_from(o.cap).map_err(|_| HF_ERR_INVALID_ARGUMENT)?;
    Ok(BakeOptions {
        tolerance: o.tolerance,
        cap,
    })
}

/// Checks a zero mode passed as `uint32_t`.
fn zero_of(v: u32) -> Result<Options, hf_result> {
    let zero = match v {
        0 => Zero::Walk,
        1 => Zero::Clamp,
        _ => return Err(crate::detail::fail(HF_ERR_INVALID_ENUM, "zero: not 0 or 1")),
    };
    Ok(Options {
        zero,
        ..Options::default()
    })
}

/// Writes the size in bytes of the radius map of a `width × height` field to
/// `*out_len`: `W * H`, one radius per texel at `map[j * W + i]` (an `R8UI` texture),
/// then `HF_MAP_DESC_BYTES` of descriptor (`hf_map_desc`). Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_radius_map_len(
    width: u32,
    height: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok(radius::map_len(width, height) + elems::<u8>())
        })
    }
}

/// Writes the number of floats of the scratch `hf_radius_prepare` fills and
/// `hf_radius_bake_rows` reads to `*out_len`: the strip bounds of the safety
/// distances, `hf_safety_scratch_len`. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_radius_scratch_len(
    width: u32,
    height: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe { safety::hf_safety_scratch_len(width, height, out_len) }
}

/// Fills `out_scratch` (`out_scratch_len ≥ hf_radius_scratch_len` floats) with the
/// strip bounds the row bakes of `field` share, whatever the options: what
/// `hf_safety_prepare` fills (one scratch serves both bakes). O(cells), one thread.
/// Thread safe for distinct buffers.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_scratch` NULL (an error) or valid
/// for writing `out_scratch_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_radius_prepare(
    field: *const hf_field,
    out_scratch: *mut f32,
    out_scratch_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { safety::hf_safety_prepare(field, out_scratch, out_scratch_len) }
}

/// Bakes the radii of texel rows `[row_begin, row_end)` (0 ≤ begin ≤ end ≤ H) of
/// `field` into `map`, the whole map buffer (`map_len ≥ hf_radius_map_len`), reading
/// `scratch` from `hf_radius_prepare`. Writes only those rows, so threads may bake
/// disjoint row ranges of one map at once, sharing one scratch.
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `scratch` NULL (an error) or valid for
/// reading `scratch_len` floats; `options` NULL (an error) or valid; `map` NULL (an
/// error) or valid for writing `map_len` bytes; concurrent calls must bake disjoint
/// rows.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_radius_bake_rows(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    options: *const hf_radius_options,
    row_begin: u32,
    row_end: u32,
    map: *mut u8,
    map_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, scratch, o) = unsafe {
            (
                ptr::get(field)?,
                ptr::slice(scratch, scratch_len)?,
                ptr::get(options)?,
            )
        };
        let map = par::RowsOut::new(map, map_len, row_begin, row_end)?;
        let opts = options_of(o)?;
        let hf = f.view();
        let needed = radius::map_len(hf.width(), hf.height());
        // SAFETY: `map` is writable for `map_len` bytes and the rows are this call's alone
        // (the caller's promises).
        let (rows, out, slot) = unsafe { map.rows(hf.height(), hf.width() as usize, needed) }?;
        radius::bake_rows(hf, scratch, rows, opts, out)?;
        if let Some(slot) = slot {
            stamp(f, desc_of(hf, &opts), needed, slot);
        }
        Ok(())
    })
}

/// Bakes the whole radius map of `field` into `out_map` (`out_map_len ≥
/// hf_radius_map_len` bytes) on `threads` threads (0: one per available core; 1: the
/// calling thread), allocating the scratch itself. Same result for any thread count.
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `options` NULL (an error) or valid;
/// `out_map` NULL (an error) or valid for writing `out_map_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hf_radius_bake(
    field: *const hf_field,
    options: *const hf_radius_options,
    threads: u32,
    out_map: *mut u8,
    out_map_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, o, out) = unsafe {
            (
                ptr::get(field)?,
                ptr::get(options)?,
                ptr::slice_mut(out_map, out_map_len)?,
            )
        };
        let opts = options_of(o)?;
        let hf = f.view();
        let needed = radius::map_len(hf.width(), hf.height());
        bake_stamped(f, desc_of(hf, &opts), needed, out, |out| {
            par::bake_map(
                hf.height(),
                hf.width() as usize,
                needed,
                threads,
                out,
                || safety::strip_scratch(hf),
                |scratch, rows, chunk| radius::bake_rows(hf, scratch, rows, opts, chunk),
            )
        })
    })
}

/// The radius map over `data`, its descriptor checked for `f`.
fn map_of<'a>(f: &hf_field, data: &'a [u8]) -> Result<RadiusMap<'a>, hf_result> {
    let hf = f.view();
    let n = radius::map_len(hf.width(), hf.height());
    check(f, Expect::map(MapKind::Radius), data, n)?;
    Ok(RadiusMap::new(hf, &data[..n])?)
}

/// The description of a radius map of `hf` baked with `opts`.
fn desc_of(hf: &HeightField, opts: &BakeOptions) -> Desc {
    Desc {
        cap: opts.cap,
        tolerance: opts.tolerance,
        ..Desc::new(MapKind::Radius, hf.width(), hf.height())
    }
}

/// The map slice and the march options of a trace call, checked behind the panic
/// boundary.
///
/// # Safety
/// `map` NULL or valid for reading `map_len` bytes.
unsafe fn trace_inputs<'a>(
    map: *const u8,
    map_len: usize,
    zero: u32,
    surface: u32,
) -> Result<(&'a [u8], Options), hf_result> {
    // SAFETY: the caller's promise.
    let (data, surface) = unsafe { safety::trace_inputs(map, map_len, surface) }?;
    Ok((
        data,
        Options {
            surface,
            ..zero_of(zero)?
        },
    ))
}

/// Traces one ray on the triangle surface with the radii `map` (baked for this field
/// by `hf_radius_bake`, `map_len ≥ hf_radius_map_len`); `zero` (an `hf_radius_zero`)
/// says what a zero radius does. Exact, the hit of `hf_trace_exact` with
/// `HF_SURFACE_TRIANGLES` (up to rounding on rays that graze the surface), when the
/// map was baked with tolerance 0 and `zero` is `HF_RADIUS_WALK`. Costs one fetch per
/// radius read, two per centerline clearance, four per cell walked. A map of another
/// field, or baked before an update, is refused (`HF_ERR_MAP_MISMATCH`,
/// `HF_ERR_STALE_MAP`: its descriptor). Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `map` NULL (an error) or valid for
/// reading `map_len` bytes; `ray` NULL (an error) or valid; `out_hit` NULL (an error)
/// or valid for writing one `hf_hit`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_radius(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    zero: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    let tri = hf_surface::HF_SURFACE_TRIANGLES as u32;
    // SAFETY: the caller's promises, passed on.
    unsafe { hf_trace_radius_on(field, map, map_len, zero, tri, ray, out_hit) }
}

/// `hf_trace_radius` finishing on `surface` (an `hf_surface`): `HF_SURFACE_TRIANGLES`,
/// or `HF_SURFACE_VIEW_LINEAR` (Baboud et al. 2011 §7), whose hit is then (exact map,
/// `HF_RADIUS_WALK`) that of `hf_trace_exact` on the view-linear surface, from the
/// same map. Other surfaces: `HF_ERR_INVALID_ARGUMENT`. Thread safe.
///
/// # Safety
/// As `hf_trace_radius`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_radius_on(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    zero: u32,
    surface: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    let (data, opts) = match unsafe { trace_inputs(map, map_len, zero, surface) } {
        Ok(v) => v,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        one(
            field,
            ray,
            out_hit,
            |f| map_of(f, data),
            |hf, m, q| radius::trace(m, hf, q, &opts),
        )
    }
}

/// `hf_trace_radius` for a batch, with the conventions of `hf_trace_exact_batch`
/// (every ray checked first; an error writes nothing). Thread safe.
///
/// # Safety
/// As `hf_trace_radius`; `rays` valid for reading `rays_len` rays, `out_hits` for
/// writing `out_hits_len` hits (overlap is an error).
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_radius_batch(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    zero: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let tri = hf_surface::HF_SURFACE_TRIANGLES as u32;
    // SAFETY: the caller's promises, passed on.
    unsafe {
        hf_trace_radius_on_batch(
            field,
            map,
            map_len,
            zero,
            tri,
            rays,
            rays_len,
            out_hits,
            out_hits_len,
        )
    }
}

/// `hf_trace_radius_on` for a batch, with the conventions of `hf_trace_exact_batch`.
/// Thread safe.
///
/// # Safety
/// As `hf_trace_radius_batch`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_radius_on_batch(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    zero: u32,
    surface: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    let (data, opts) = match unsafe { trace_inputs(map, map_len, zero, surface) } {
        Ok(v) => v,
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
            |f| map_of(f, data),
            |hf, m, q| radius::trace(m, hf, q, &opts),
        )
    }
}
