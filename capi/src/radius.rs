//! Safety radius (Baboud & Décoret 2006, §3.4–3.5): sizes, bake (whole, by rows,
//! threaded) and the march, for the triangle surface. The bake shares the strip bounds
//! of the safety distances (`hf_safety_prepare`).

use crate::hf_result::{self, *};
use crate::mapdesc::{bake_stamped, check, elems, stamp, Expect};
use crate::safety;
use crate::size_query;
use crate::trace::TraceOptions;
use crate::{guard, hf_field, par, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::radius::{self, BakeOptions, Options, RadiusMap, Zero};
use hfcore::{HeightField, Marcher};

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
        _ => {
            return Err(crate::detail::fail(
                HF_ERR_INVALID_ENUM,
                "options.radius_zero: not an hf_radius_zero",
            ))
        }
    };
    Ok(Options {
        zero,
        ..Options::default()
    })
}

/// Writes the size in bytes of the radius map of a `width × height` field to
/// `*out_len`: `W * H`, one radius per texel (layout: docs/DESIGN.md, "Texture
/// layouts", safety radius), then `HF_MAP_DESC_BYTES` of descriptor (`hf_map_desc`).
/// Thread safe.
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

/// The radius marcher over `data`, its descriptor checked for `f`, with the zero mode
/// and surface of `o`.
pub(crate) fn marcher<'a>(
    f: &'a hf_field,
    data: &'a [u8],
    o: &TraceOptions,
) -> Result<Marcher<'a>, hf_result> {
    let hf = f.view();
    let n = radius::map_len(hf.width(), hf.height());
    check(f, Expect::map(MapKind::Radius), data, n)?;
    let opts = Options {
        surface: safety::march_surface(o.surface),
        ..zero_of(o.radius_zero)?
    };
    Ok(Marcher::Radius(RadiusMap::new(hf, &data[..n])?, opts))
}

/// The description of a radius map of `hf` baked with `opts`.
fn desc_of(hf: &HeightField, opts: &BakeOptions) -> Desc {
    Desc {
        cap: opts.cap,
        tolerance: opts.tolerance,
        ..Desc::new(MapKind::Radius, hf.width(), hf.height())
    }
}
