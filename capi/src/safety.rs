//! Safety distances (Baboud, Eisemann, Seidel 2011, §5.2.2 and §6.1): sizes, bake
//! (whole, by rows, threaded) and the march, for the triangle surface.

use crate::hf_result::{self, *};
use crate::mapdesc::{bake_stamped, check_layout, elems, stamp};
use crate::scene::bake_classes_of;
use crate::size_query;
use crate::trace::TraceOptions;
use crate::{guard, hf_field, par, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::safety::{self, AllRays, MarchSurface, Options, SafetyMap, Variant};
use hfcore::scene::RayClasses;
use hfcore::{HeightField, Marcher};

/// Layout of a safety-distance map. Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_safety_variant {
    /// One byte per texel and ray class, each texel row as one row per class the map
    /// holds (layout: docs/DESIGN.md, "Texture layouts", safety, directional).
    HF_SAFETY_DIRECTIONAL = 0,
    /// One byte per texel, the minimum over the classes the map holds (layout:
    /// docs/DESIGN.md, "Texture layouts", safety, isotropic).
    HF_SAFETY_ISOTROPIC = 1,
}

/// What a safety-distance bake computes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct hf_safety_options {
    /// An `hf_safety_variant`.
    pub variant: u32,
    /// 1: clamp every distance to at least 1 (the paper's "strictly positive" variant:
    /// fewer fetches, **not exact**, rays may miss silhouettes); 0: exact.
    pub positive: u32,
    /// Largest distance stored, 0..=255 (255 is the default; smaller is conservative).
    pub cap: u32,
    /// The ray classes to bake (`HF_RAYS_*` bits; 0: all four): a map of fewer classes
    /// is smaller and faster to bake (`hf_safety_bake_rows`).
    pub ray_classes: u32,
}

/// Checks a variant passed as `uint32_t`.
fn variant_of(v: u32) -> Result<Variant, hf_result> {
    match v {
        0 => Ok(Variant::Directional),
        1 => Ok(Variant::Isotropic),
        _ => Err(HF_ERR_INVALID_ENUM),
    }
}

/// Checks bake options: the core's, and the ray classes to bake.
fn options_of(o: &hf_safety_options) -> Result<(Options, RayClasses), hf_result> {
    let variant = variant_of(o.variant)?;
    if o.positive > 1 {
        return Err(HF_ERR_INVALID_ARGUMENT);
    }
    let cap = u8::try_from(o.cap).map_err(|_| HF_ERR_INVALID_ARGUMENT)?;
    let opts = Options {
        variant,
        positive: o.positive == 1,
        cap,
    };
    Ok((opts, bake_classes_of(o.ray_classes)?))
}
/// Writes the size in bytes of the safety-distance map of a `width × height` field
/// with `variant` (an `hf_safety_variant`) for the ray classes `ray_classes`
/// (`HF_RAYS_*` bits; 0: all four, as `hf_safety_options::ray_classes`) to `*out_len`:
/// `W * H * n` directional for its `n` classes (`W * H * 4` for all), `W * H`
/// isotropic, then `HF_MAP_DESC_BYTES` of descriptor (`hf_map_desc`; upload the bytes
/// before it). Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_map_len(
    width: u32,
    height: u32,
    variant: u32,
    ray_classes: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            let (variant, classes) = (variant_of(variant)?, bake_classes_of(ray_classes)?);
            Ok(safety::map_len_classes(width, height, variant, classes) + elems::<u8>())
        })
    }
}

/// Writes the number of floats of the scratch buffer `hf_safety_prepare` fills and
/// `hf_safety_bake_rows` reads (per-strip bounds, O(cells / 8)) to `*out_len`.
/// Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_scratch_len(
    width: u32,
    height: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok(safety::scratch_len(width, height))
        })
    }
}

/// Fills `out_scratch` (`out_scratch_len ≥ hf_safety_scratch_len` floats) with the
/// strip bounds the row bakes of `field` share. O(cells), one thread. Thread safe for
/// distinct buffers.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_scratch` NULL (an error) or valid
/// for writing `out_scratch_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_prepare(
    field: *const hf_field,
    out_scratch: *mut f32,
    out_scratch_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, scratch) = unsafe {
            (
                ptr::get(field)?,
                ptr::slice_mut(out_scratch, out_scratch_len)?,
            )
        };
        Ok(safety::prepare(f.view(), scratch)?)
    })
}

/// Bakes the safety distances of texel rows `[row_begin, row_end)` (0 ≤ begin ≤ end ≤
/// H) of `field` into `map`, the whole map buffer (`map_len ≥ hf_safety_map_len` of the
/// same variant and classes), reading `scratch` from `hf_safety_prepare`. Writes only
/// those rows, so threads may bake disjoint row ranges of one map at once, sharing one
/// scratch. The costly part of the bake. With `options->ray_classes` naming some of the
/// four classes (`hf_scene_bake_plan` gives a scene's), the other classes are neither
/// computed nor stored: directional, the kept classes' rows, equal to the full bake's,
/// `n` rows per texel row in class order (rows `row_begin..row_end` from byte
/// `row_begin * W * n`); isotropic, the minimum over the kept classes (larger
/// distances, valid for rays of those classes only). `hf_trace` reads the classes from
/// the map's descriptor.
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `scratch` NULL (an error) or valid for
/// reading `scratch_len` floats; `options` NULL (an error) or valid; `map` NULL (an
/// error) or valid for writing `map_len` bytes; concurrent calls must bake disjoint
/// rows.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_safety_bake_rows(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    options: *const hf_safety_options,
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
        let (opts, classes) = options_of(o)?;
        let hf = f.view();
        let row = safety::map_len_classes(hf.width(), 1, opts.variant, classes);
        let needed = safety::map_len_classes(hf.width(), hf.height(), opts.variant, classes);
        // SAFETY: `map` is writable for `map_len` bytes and the rows are this call's alone
        // (the caller's promises).
        let (rows, out, slot) = unsafe { map.rows(hf.height(), row, needed) }?;
        if scratch.len() < safety::scratch_len(hf.width(), hf.height()) {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        safety::bake_rows_classes(hf, scratch, &AllRays, classes, rows, opts, out)?;
        if let Some(slot) = slot {
            stamp(f, desc_of(hf, &opts, classes), needed, slot);
        }
        Ok(())
    })
}

/// Bakes the whole safety-distance map of `field` into `out_map` (`out_map_len ≥
/// hf_safety_map_len` bytes of the same variant and classes) on `threads` threads (0:
/// one per available core; 1: the calling thread), allocating the scratch itself, as
/// `hf_safety_bake_rows` (a scene that casts two of the four classes bakes in about
/// half the time into half the bytes). Same result for any thread count.
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `options` NULL (an error) or valid;
/// `out_map` NULL (an error) or valid for writing `out_map_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_bake(
    field: *const hf_field,
    options: *const hf_safety_options,
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
        let needed = safety::map_len_classes(hf.width(), hf.height(), opts.variant, classes);
        let desc = desc_of(hf, &opts, classes);
        bake_stamped(f, desc, needed, out, |out| {
            par::bake_map(
                hf.height(),
                safety::map_len_classes(hf.width(), 1, opts.variant, classes),
                needed,
                threads,
                out,
                || strip_scratch(hf),
                |scratch, rows, chunk| {
                    safety::bake_rows_classes(hf, scratch, &AllRays, classes, rows, opts, chunk)
                },
            )
        })
    })
}

/// The strip bounds of `hf` (`safety::prepare`) in a buffer of their own: the scratch
/// the whole-map bakes allocate.
pub(crate) fn strip_scratch(hf: &HeightField) -> Result<Vec<f32>, hf_result> {
    let mut scratch = par::zeroed(safety::scratch_len(hf.width(), hf.height()))?;
    safety::prepare(hf, &mut scratch)?;
    Ok(scratch)
}

/// The safety marcher over `data`: the map's variant and ray classes are its
/// descriptor's (checked against `o.classes` when named), the descriptor checked for
/// `f`.
pub(crate) fn marcher<'a>(
    f: &'a hf_field,
    data: &'a [u8],
    o: &TraceOptions,
) -> Result<Marcher<'a>, hf_result> {
    let hf = f.view();
    let kinds = [MapKind::Safety, MapKind::SafetyIsotropic];
    let variant = |kind| match kind {
        MapKind::Safety => Variant::Directional,
        _ => Variant::Isotropic,
    };
    let len =
        |kind, classes| safety::map_len_classes(hf.width(), hf.height(), variant(kind), classes);
    let (got, n) = check_layout(f, data, &kinds, o.classes, len)?;
    let (v, classes) = (variant(got.desc.map), got.desc.classes);
    let map = SafetyMap::with_classes(hf, &data[..n], v, classes)?;
    Ok(Marcher::Safety(map, march_surface(o.surface)))
}

/// The map kind of a safety variant.
fn kind_of(variant: Variant) -> MapKind {
    match variant {
        Variant::Directional => MapKind::Safety,
        Variant::Isotropic => MapKind::SafetyIsotropic,
    }
}

/// The description of a safety map of `hf` baked with `opts` for `classes`.
fn desc_of(hf: &HeightField, opts: &Options, classes: RayClasses) -> Desc {
    Desc {
        cap: opts.cap,
        classes,
        ..Desc::new(kind_of(opts.variant), hf.width(), hf.height())
    }
}

/// The march surface of a surface the registry lets the safety-shape methods trace
/// (`TraceOptions` checked it).
pub(crate) fn march_surface(surface: hfcore::Surface) -> MarchSurface {
    MarchSurface::of(surface).unwrap_or_default()
}
