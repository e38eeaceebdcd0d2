//! Cylinder–cone safety shapes (Baboud, Eisemann, Seidel 2011, §6.3): sizes, bake
//! (whole, by rows, threaded) and the march, for the triangle surface.

use crate::hf_result::{self, *};
use crate::mapdesc::{bake_stamped, check, elems, stamp, Expect};
use crate::safety::trace_inputs;
use crate::scene::{classes_of, HF_RAYS_ALL};
use crate::trace::{batch, hf_hit, hf_ray, one};
use crate::{check_size, size_query};
use crate::{guard, hf_field, hf_surface, par, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcore::safety::{self, SafetyError};
use hfcore::scene::RayClasses;

/// How the cone slope of a cylinder–cone bake is computed. Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_cc_slope {
    /// Over the limiting triangles only, exactly (larger steps, slower bake).
    HF_CC_SLOPE_EXACT = 0,
    /// Every triangle limiting, the highest sample per abscissa from the N-buffers
    /// (conservative, faster).
    HF_CC_SLOPE_NBUFFER = 1,
}

/// What a cylinder–cone bake computes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct hf_cc_options {
    /// An `hf_cc_slope`.
    pub slope: u32,
    /// Longest cone step in centerlines, 0..=255 (64 is the core's default); the march
    /// must be given the same value (the map's descriptor records it; another is
    /// `HF_ERR_MAP_MISMATCH`).
    pub cap: u32,
}

/// Checks a cap passed as `uint32_t`.
fn cap_of(cap: u32) -> Result<u8, hf_result> {
    u8::try_from(cap).map_err(|_| HF_ERR_INVALID_ARGUMENT)
}

/// Checks bake options.
fn options_of(o: &hf_cc_options) -> Result<CcOptions, hf_result> {
    let slope = match o.slope {
        0 => Slope::Exact,
        1 => Slope::NBuffer,
        _ => return Err(HF_ERR_INVALID_ENUM),
    };
    Ok(CcOptions {
        slope,
        cap: cap_of(o.cap)?,
    })
}

/// Writes the size in bytes of the packed cylinder–cone map of a `width × height`
/// field to `*out_len`: 8 per texel, two per ray class, `[r, s]` (cylinder radius,
/// slope code; the cone's base height is not stored: the march computes it from the
/// heights), each texel row stored as four rows of W, one per class in class order
/// (x+, x−, y+, y−): the bytes of texel (i, j) for class c start at
/// `((j * 4 + c) * W + i) * 2`; upload as an `RG8UI` texture of W × 4H texels, texel
/// (i, 4 j + class); then `HF_MAP_DESC_BYTES` of descriptor (`hf_map_desc`), which
/// stays on the CPU. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_map_len(width: u32, height: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok(cc::map_len(width, height) + elems::<u8>())
        })
    }
}

/// `hf_cc_map_len` for a map of the ray classes `ray_classes` only (`HF_RAYS_*` bits,
/// not 0; `hf_cc_bake_classes`): `W * H * 2 * n` for its `n` classes, each texel row
/// stored as `n` rows in class order (the bytes of texel (i, j) for class c at
/// `((j * n + slot) * W + i) * 2`, `slot` the number of its classes before c; an
/// `RG8UI` texture of W × nH texels, texel (i, n j + slot)), then `HF_MAP_DESC_BYTES`
/// of descriptor. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_map_len_classes(
    width: u32,
    height: u32,
    ray_classes: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok(cc::map_len_classes(width, height, classes_of(ray_classes)?) + elems::<u8>())
        })
    }
}

/// Writes the number of floats of the N-buffers of a `width × height` field for cone
/// reach `cap` (0..=255) to `*out_len`. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_nbuffer_len(
    width: u32,
    height: u32,
    cap: u32,
    out_len: *mut usize,
) -> hf_result {
    guard(|| {
        let out = ptr::out(out_len)?;
        check_size(width, height)?;
        let cap = cap_of(cap)?;
        // SAFETY: the caller promises `out_len` is writable.
        unsafe { out.set(cc::nbuffer_len(width, height, cap)) };
        Ok(())
    })
}

/// Fills `out_nbuffer` (`out_nbuffer_len ≥ hf_cc_nbuffer_len(W, H, cap)` floats) with
/// the N-buffers the cone slopes of `hf_cc_bake_rows` read. O(cells · levels), one
/// thread.
/// Thread safe for distinct output buffers (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_nbuffer` NULL (an error) or valid
/// for writing `out_nbuffer_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_prepare_nbuffer(
    field: *const hf_field,
    cap: u32,
    out_nbuffer: *mut f32,
    out_nbuffer_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, nb) = unsafe {
            (
                ptr::get(field)?,
                ptr::slice_mut(out_nbuffer, out_nbuffer_len)?,
            )
        };
        let cap = cap_of(cap)?;
        Ok(cc::prepare_nbuffer(f.view(), cap, nb)?)
    })
}

/// Bakes the cylinder–cone shapes of texel rows `[row_begin, row_end)` (0 ≤ begin ≤
/// end ≤ H) into `map` (the whole map buffer, `map_len ≥ hf_cc_map_len`), reading
/// `scratch` (from `hf_safety_prepare`) and `nbuffer` (from `hf_cc_prepare_nbuffer`
/// with `options->cap`). Writes only those rows: threads may bake disjoint rows at
/// once, sharing both scratches.
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `scratch`, `nbuffer` NULL (an error)
/// or valid for reading their lengths in floats; `options` NULL (an error) or valid;
/// `map` NULL (an error) or valid for writing `map_len` bytes; concurrent calls must
/// bake disjoint rows.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_cc_bake_rows(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    nbuffer: *const f32,
    nbuffer_len: usize,
    options: *const hf_cc_options,
    row_begin: u32,
    row_end: u32,
    map: *mut u8,
    map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        hf_cc_bake_rows_classes(
            field,
            scratch,
            scratch_len,
            nbuffer,
            nbuffer_len,
            options,
            HF_RAYS_ALL,
            row_begin,
            row_end,
            map,
            map_len,
        )
    }
}

/// `hf_cc_bake_rows` for the ray classes `ray_classes` only (`HF_RAYS_*` bits, not 0;
/// `hf_scene_bake_plan` gives a scene's) into a map of those classes only
/// (`hf_cc_map_len_classes` bytes; rows `row_begin..row_end` from byte `row_begin * W *
/// 4n`): the other classes are neither computed nor stored, the kept classes' bytes
/// equal the full bake's. Trace with the same `ray_classes` (`hf_trace_cc_on`).
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// As `hf_cc_bake_rows`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_cc_bake_rows_classes(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    nbuffer: *const f32,
    nbuffer_len: usize,
    options: *const hf_cc_options,
    ray_classes: u32,
    row_begin: u32,
    row_end: u32,
    map: *mut u8,
    map_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, scratch, nb, o) = unsafe {
            (
                ptr::get(field)?,
                ptr::slice(scratch, scratch_len)?,
                ptr::slice(nbuffer, nbuffer_len)?,
                ptr::get(options)?,
            )
        };
        let map = par::RowsOut::new(map, map_len, row_begin, row_end)?;
        let (opts, classes) = (options_of(o)?, classes_of(ray_classes)?);
        let hf = f.view();
        let row = cc::map_len_classes(hf.width(), 1, classes);
        let needed = cc::map_len_classes(hf.width(), hf.height(), classes);
        // SAFETY: `map` is writable for `map_len` bytes and the rows are this call's alone
        // (the caller's promises).
        let (rows, out, slot) = unsafe { map.rows(hf.height(), row, needed) }?;
        cc::bake_rows_classes(hf, scratch, nb, classes, rows, opts, out)?;
        if let Some(slot) = slot {
            stamp(f, desc_of(hf, opts.cap, classes), needed, slot);
        }
        Ok(())
    })
}

/// Bakes the whole cylinder–cone map of `field` into `out_map` (`out_map_len ≥
/// hf_cc_map_len`) on `threads` threads (0: one per available core), allocating both
/// scratches itself. Same result for any thread count.
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `options` NULL (an error) or valid;
/// `out_map` NULL (an error) or valid for writing `out_map_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_bake(
    field: *const hf_field,
    options: *const hf_cc_options,
    threads: u32,
    out_map: *mut u8,
    out_map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { hf_cc_bake_classes(field, options, HF_RAYS_ALL, threads, out_map, out_map_len) }
}

/// `hf_cc_bake` for the ray classes `ray_classes` only (`HF_RAYS_*` bits, not 0) into
/// `out_map` (`out_map_len ≥ hf_cc_map_len_classes` bytes), as
/// `hf_cc_bake_rows_classes`: a scene that casts one class bakes a quarter of the
/// texels into a quarter of the bytes.
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// As `hf_cc_bake`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_bake_classes(
    field: *const hf_field,
    options: *const hf_cc_options,
    ray_classes: u32,
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
        let (opts, classes) = (options_of(o)?, classes_of(ray_classes)?);
        let hf = f.view();
        let needed = cc::map_len_classes(hf.width(), hf.height(), classes);
        let desc = desc_of(hf, opts.cap, classes);
        bake_stamped(f, desc, needed, out, |out| {
            par::bake_map(
                hf.height(),
                cc::map_len_classes(hf.width(), 1, classes),
                needed,
                threads,
                out,
                || {
                    let mut scratch = par::zeroed(safety::scratch_len(hf.width(), hf.height()))?;
                    let mut nb = par::zeroed(cc::nbuffer_len(hf.width(), hf.height(), opts.cap))?;
                    safety::prepare(hf, &mut scratch)?;
                    cc::prepare_nbuffer(hf, opts.cap, &mut nb)?;
                    Ok((scratch, nb))
                },
                |(scratch, nb), rows, chunk| -> Result<(), SafetyError> {
                    cc::bake_rows_classes(hf, scratch, nb, classes, rows, opts, chunk)
                },
            )
        })
    })
}

/// Traces one ray on the triangle surface with the cylinder–cone map `map` (from
/// `hf_cc_bake` with the same `cap`, checked against the map's descriptor): exact, the
/// hit of `hf_trace_exact` with `HF_SURFACE_TRIANGLES` (up to rounding on grazing
/// rays). Costs one fetch per shape read and one for the third height sample of a
/// cone's base, two per centerline clearance, four per cell walked. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `map` NULL (an error) or valid for
/// reading `map_len` bytes; `ray` NULL (an error) or valid; `out_hit` NULL (an error)
/// or valid for writing one `hf_hit`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_cc(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    cap: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    let tri = hf_surface::HF_SURFACE_TRIANGLES as u32;
    // SAFETY: the caller's promises, passed on.
    unsafe { hf_trace_cc_on(field, map, map_len, cap, HF_RAYS_ALL, tri, ray, out_hit) }
}

/// `hf_trace_cc` with a map of the ray classes `ray_classes` (`HF_RAYS_*` bits, not 0;
/// `HF_RAYS_ALL` for `hf_cc_bake`'s, those passed to `hf_cc_bake_classes` otherwise;
/// `map_len ≥ hf_cc_map_len_classes`), finishing on `surface` (an `hf_surface`):
/// `HF_SURFACE_TRIANGLES`, or `HF_SURFACE_VIEW_LINEAR` (Baboud et al. §7), whose hit is
/// then that of `hf_trace_exact` on the view-linear surface, from the same map. Other
/// surfaces: `HF_ERR_INVALID_ARGUMENT`. A ray of a class the map does not hold reads
/// radius 0 without a cone (it walks cell by cell, still exact). Thread safe.
///
/// # Safety
/// As `hf_trace_cc`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_cc_on(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    cap: u32,
    ray_classes: u32,
    surface: u32,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    let (data, surface) = match unsafe { trace_inputs(map, map_len, surface) } {
        Ok(v) => v,
        Err(e) => return e,
    };
    // SAFETY: the caller's promises, passed on.
    unsafe {
        one(
            field,
            ray,
            out_hit,
            |f| map_of(f, data, cap, ray_classes),
            |hf, m, q| cc::trace_on(m, hf, surface, q),
        )
    }
}

/// `hf_trace_cc` for a batch, with the conventions of `hf_trace_exact_batch`.
/// Thread safe.
///
/// # Safety
/// As `hf_trace_cc`; `rays` valid for reading `rays_len` rays, `out_hits` for writing
/// `out_hits_len` hits (overlap is an error).
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_cc_batch(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    cap: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    let tri = hf_surface::HF_SURFACE_TRIANGLES as u32;
    // SAFETY: the caller's promises, passed on.
    unsafe {
        hf_trace_cc_on_batch(
            field,
            map,
            map_len,
            cap,
            HF_RAYS_ALL,
            tri,
            rays,
            rays_len,
            out_hits,
            out_hits_len,
        )
    }
}

/// `hf_trace_cc_on` for a batch, with the conventions of `hf_trace_exact_batch`.
/// Thread safe.
///
/// # Safety
/// As `hf_trace_cc_batch`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_cc_on_batch(
    field: *const hf_field,
    map: *const u8,
    map_len: usize,
    cap: u32,
    ray_classes: u32,
    surface: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    let (data, surface) = match unsafe { trace_inputs(map, map_len, surface) } {
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
            |f| map_of(f, data, cap, ray_classes),
            |hf, m, q| cc::trace_on(m, hf, surface, q),
        )
    }
}

/// The map's view (a map of the classes `ray_classes`, cone reach `cap`), its
/// descriptor checked for `f`.
fn map_of<'a>(
    f: &hf_field,
    data: &'a [u8],
    cap: u32,
    ray_classes: u32,
) -> Result<CcMap<'a>, hf_result> {
    let (cap, classes) = (cap_of(cap)?, classes_of(ray_classes)?);
    let hf = f.view();
    let n = cc::map_len_classes(hf.width(), hf.height(), classes);
    let want = Expect {
        map: MapKind::Cc,
        cap: Some(cap),
        classes: Some(classes),
    };
    check(f, want, data, n)?;
    Ok(CcMap::with_classes(hf, &data[..n], cap, classes)?)
}

/// The description of a cylinder–cone map of `hf` baked with `cap` for `classes`.
fn desc_of(hf: &hfcore::HeightField, cap: u8, classes: RayClasses) -> Desc {
    Desc {
        cap,
        classes,
        ..Desc::new(MapKind::Cc, hf.width(), hf.height())
    }
}
