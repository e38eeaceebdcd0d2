//! Cylinder–cone safety shapes (Baboud, Eisemann, Seidel 2011, §6.3): sizes, bake
//! (whole, by rows, threaded) and the march, for the triangle surface.

use crate::hf_result::{self, *};
use crate::mapdesc::{bake_stamped, check_layout, elems, stamp};
use crate::safety::march_surface;
use crate::scene::bake_classes_of;
use crate::trace::TraceOptions;
use crate::{check_size, size_query};
use crate::{guard, hf_field, par, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcore::safety::{self, SafetyError};
use hfcore::scene::RayClasses;
use hfcore::Marcher;

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
    /// Longest cone step in centerlines, 0..=255 (64 is the core's default); the map's
    /// descriptor records it for the march.
    pub cap: u32,
    /// The ray classes to bake (`HF_RAYS_*` bits; 0: all four): a map of fewer classes
    /// is smaller and faster to bake (`hf_cc_bake_rows`).
    pub ray_classes: u32,
}

/// Checks a cap passed as `uint32_t`.
fn cap_of(cap: u32) -> Result<u8, hf_result> {
    u8::try_from(cap).map_err(|_| HF_ERR_INVALID_ARGUMENT)
}

/// Checks bake options: the core's, and the ray classes to bake.
fn options_of(o: &hf_cc_options) -> Result<(CcOptions, RayClasses), hf_result> {
    let slope = match o.slope {
        0 => Slope::Exact,
        1 => Slope::NBuffer,
        _ => return Err(HF_ERR_INVALID_ENUM),
    };
    let opts = CcOptions {
        slope,
        cap: cap_of(o.cap)?,
    };
    Ok((opts, bake_classes_of(o.ray_classes)?))
}

/// Writes the size in bytes of the packed cylinder–cone map of a `width × height`
/// field for the ray classes `ray_classes` (`HF_RAYS_*` bits; 0: all four, as
/// `hf_cc_options::ray_classes`) to `*out_len`: `W * H * 2 * n` for its `n` classes
/// (layout: docs/DESIGN.md, "Texture layouts", cylinder–cone), then `HF_MAP_DESC_BYTES`
/// of descriptor (`hf_map_desc`), which stays on the CPU. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_map_len(
    width: u32,
    height: u32,
    ray_classes: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok(cc::map_len_classes(width, height, bake_classes_of(ray_classes)?) + elems::<u8>())
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
/// end ≤ H) into `map` (the whole map buffer, `map_len ≥ hf_cc_map_len` of the same
/// classes), reading `scratch` (from `hf_safety_prepare`) and `nbuffer` (from
/// `hf_cc_prepare_nbuffer` with `options->cap`). Writes only those rows: threads may
/// bake disjoint rows at once, sharing both scratches. With `options->ray_classes`
/// naming some of the four classes (`hf_scene_bake_plan` gives a scene's), the others
/// are neither computed nor stored (rows `row_begin..row_end` from byte
/// `row_begin * W * 2n`), the kept classes' bytes equal the full bake's; `hf_trace`
/// reads the classes from the map's descriptor.
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
        let (opts, classes) = options_of(o)?;
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
/// hf_cc_map_len` of the same classes) on `threads` threads (0: one per available
/// core), allocating both scratches itself, as `hf_cc_bake_rows` (a scene that casts
/// one class bakes a quarter of the texels into a quarter of the bytes). Same result
/// for any thread count.
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
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, o, out) = unsafe {
            (
                ptr::get(field)?,
                ptr::get(options)?,
                ptr::slice_mut(out_map, out_map_len)?,
            )
        };
        let (opts, classes) = options_of(o)?;
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

/// The cylinder–cone marcher over `data`: the map's ray classes and cap are its
/// descriptor's (the classes checked against `o.classes` when named), the descriptor
/// checked for `f`.
pub(crate) fn marcher<'a>(
    f: &'a hf_field,
    data: &'a [u8],
    o: &TraceOptions,
) -> Result<Marcher<'a>, hf_result> {
    let hf = f.view();
    let len = |_, classes| cc::map_len_classes(hf.width(), hf.height(), classes);
    let (got, n) = check_layout(f, data, &[MapKind::Cc], o.classes, len)?;
    let map = CcMap::with_classes(hf, &data[..n], got.desc.cap, got.desc.classes)?;
    Ok(Marcher::Cc(map, march_surface(o.surface)))
}

/// The description of a cylinder–cone map of `hf` baked with `cap` for `classes`.
fn desc_of(hf: &hfcore::HeightField, cap: u8, classes: RayClasses) -> Desc {
    Desc {
        cap,
        classes,
        ..Desc::new(MapKind::Cc, hf.width(), hf.height())
    }
}
