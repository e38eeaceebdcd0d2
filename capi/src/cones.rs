//! The cone family: conservative cone step mapping (`hfcast::cone`), relaxed cone
//! stepping (`hfcast::relaxed`) and quadratic displacement maps (`hfcast::qdm`). All
//! three bake from the maximum-mipmap pyramid (the scratch) into a float map, in rows.

use crate::hf_result::{self, *};
use crate::mapdesc::{bake_stamped, check, elems, stamp, Expect};
use crate::size_query;
use crate::trace::TraceOptions;
use crate::{guard, hf_field, ptr};
use hfcore::cone::{self, ConeMap};
use hfcore::ktx2::{Desc, MapKind};
#[cfg(feature = "qdm")]
use hfcore::qdm::{self, QdmMap};
#[cfg(feature = "relaxed")]
use hfcore::relaxed;
use hfcore::scene::MethodKind;
use hfcore::{HeightField, Marcher};

/// The core's row bake of one family.
type BakeRows = cone::RowBake;

/// What differs between the three bakes.
#[derive(Clone, Copy)]
struct Family {
    /// The map kind its descriptor names.
    kind: MapKind,
    /// Floats of the whole map's texels (its `_len` adds the descriptor).
    map_len: fn(u32, u32) -> usize,
    /// Rows the bake iterates: cell rows (H − 1) or sample rows (H).
    rows: fn(&HeightField) -> u32,
    /// Floats per row.
    row_len: fn(&HeightField) -> usize,
    /// The core's row bake.
    bake_rows: BakeRows,
}

fn cell_rows(hf: &HeightField) -> u32 {
    hf.height() - 1
}
#[cfg(feature = "relaxed")]
fn sample_rows(hf: &HeightField) -> u32 {
    hf.height()
}
fn cone_row(hf: &HeightField) -> usize {
    cone::CHANNELS * (hf.width() as usize - 1)
}
#[cfg(feature = "qdm")]
fn qdm_row(hf: &HeightField) -> usize {
    qdm::CHANNELS * (hf.width() as usize - 1)
}
#[cfg(feature = "relaxed")]
fn relaxed_row(hf: &HeightField) -> usize {
    hf.width() as usize
}

const CONE: Family = Family {
    kind: MapKind::Cone,
    map_len: cone::map_len,
    rows: cell_rows,
    row_len: cone_row,
    bake_rows: cone::bake_rows,
};
#[cfg(feature = "relaxed")]
const RELAXED: Family = Family {
    kind: MapKind::Relaxed,
    map_len: relaxed::map_len,
    rows: sample_rows,
    row_len: relaxed_row,
    bake_rows: relaxed::bake_rows,
};
#[cfg(feature = "qdm")]
const QDM: Family = Family {
    kind: MapKind::Qdm,
    map_len: qdm::map_len,
    rows: cell_rows,
    row_len: qdm_row,
    bake_rows: qdm::bake_rows,
};

/// Body of the `*_map_len` queries.
///
/// # Safety
/// `out_len` NULL or writable.
unsafe fn map_len(fam: Family, width: u32, height: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok((fam.map_len)(width, height) + elems::<f32>())
        })
    }
}

/// Body of the `*_bake_rows` functions.
///
/// # Safety
/// As `hf_cone_bake_rows`.
#[allow(clippy::too_many_arguments)]
unsafe fn bake_rows(
    fam: Family,
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    row_begin: u32,
    row_end: u32,
    map: *mut f32,
    map_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, scratch) = unsafe { (ptr::get(field)?, ptr::slice(scratch, scratch_len)?) };
        if map.is_null() {
            return Err(HF_ERR_NULL_POINTER);
        }
        let hf = f.view();
        let texels = (fam.map_len)(hf.width(), hf.height());
        if map_len < texels + elems::<f32>() {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        if scratch.len() < cone::scratch_len(hf.width(), hf.height()) {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        if row_begin > row_end || row_end > (fam.rows)(hf) {
            return Err(HF_ERR_INVALID_ARGUMENT);
        }
        let row = (fam.row_len)(hf);
        // Only the rows baked become a slice, so concurrent calls never alias.
        // SAFETY: inside the caller's buffer (length checked), this call's alone (the
        // documented contract).
        let out = unsafe {
            ptr::slice_mut(
                map.add(row_begin as usize * row),
                (row_end - row_begin) as usize * row,
            )
        }?;
        (fam.bake_rows)(hf, scratch, row_begin..row_end, out)?;
        if row_begin == 0 {
            // SAFETY: the descriptor follows the texels (length checked); only the call
            // whose rows start at 0 writes it.
            let slot = unsafe { ptr::slice_mut(map.add(texels), elems::<f32>()) }?;
            stamp(
                f,
                Desc::new(fam.kind, hf.width(), hf.height()),
                texels,
                slot,
            );
        }
        Ok(())
    })
}

/// Body of the whole-map bakes.
///
/// # Safety
/// As `hf_cone_bake`.
unsafe fn bake(
    fam: Family,
    field: *const hf_field,
    threads: u32,
    out_map: *mut f32,
    out_map_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, out) = unsafe { (ptr::get(field)?, ptr::slice_mut(out_map, out_map_len)?) };
        let hf = f.view();
        let texels = (fam.map_len)(hf.width(), hf.height());
        let desc = Desc::new(fam.kind, hf.width(), hf.height());
        bake_stamped(f, desc, texels, out, |out| bake_into(fam, hf, threads, out))
    })
}

/// The threaded bake of `fam`'s texels into `out`.
fn bake_into(
    fam: Family,
    hf: &HeightField,
    threads: u32,
    out: &mut [f32],
) -> Result<(), hf_result> {
    let n = cone::scratch_len(hf.width(), hf.height());
    let mut scratch = Vec::new();
    scratch
        .try_reserve_exact(n)
        .map_err(|_| HF_ERR_OUT_OF_MEMORY)?;
    scratch.resize(n, 0.0);
    cone::prepare(hf, &mut scratch)?;
    let rows = (fam.rows)(hf);
    let threads = crate::par::thread_count(threads, rows);
    let scratch = &scratch;
    Ok(crate::par::bake_bands(
        rows,
        (fam.row_len)(hf),
        8,
        threads,
        out,
        |r, chunk| (fam.bake_rows)(hf, scratch, r, chunk),
    )?)
}

/// The texels of a map of `fam`, its descriptor checked for `f`.
fn texels_of<'a>(fam: Family, f: &hf_field, map: &'a [f32]) -> Result<&'a [f32], hf_result> {
    let hf = f.view();
    let n = (fam.map_len)(hf.width(), hf.height());
    check(f, Expect::map(fam.kind), map, n)?;
    Ok(&map[..n])
}

/// Writes the number of floats of the bake scratch of a `width × height` field to
/// `*out_len`: the maximum-mipmap pyramid (`hf_maxmip_len`) the cone, relaxed-cone
/// and QDM bakes search. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cone_scratch_len(
    width: u32,
    height: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe {
        size_query(width, height, out_len, |width, height| {
            Ok(cone::scratch_len(width, height))
        })
    }
}

/// Fills `out_scratch` (`out_scratch_len ≥ hf_cone_scratch_len`) with what the row
/// bakes of the cone family (`hf_cone_bake_rows`, `hf_relaxed_bake_rows`,
/// `hf_qdm_bake_rows`) read: the maximum-mipmap pyramid of `field`. Thread safe for
/// distinct buffers.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_scratch` NULL (an error) or valid
/// for writing `out_scratch_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_cone_prepare(
    field: *const hf_field,
    out_scratch: *mut f32,
    out_scratch_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, s) = unsafe {
            (
                ptr::get(field)?,
                ptr::slice_mut(out_scratch, out_scratch_len)?,
            )
        };
        Ok(cone::prepare(f.view(), s)?)
    })
}

/// Writes the number of floats of the cone map of a `width × height` field to
/// `*out_len`: two per cell (layout: docs/DESIGN.md, "Texture layouts", cone), then
/// `HF_MAP_DESC_BYTES / 4` floats of descriptor (`hf_map_desc`), which stays on the
/// CPU. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cone_map_len(
    width: u32,
    height: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe { map_len(CONE, width, height, out_len) }
}

/// Bakes cell rows `[row_begin, row_end)` (0 ≤ begin ≤ end ≤ H − 1) of the
/// conservative cone map of `field` into `map` (the whole map buffer, `map_len ≥
/// hf_cone_map_len`), reading `scratch` from `hf_cone_prepare`. Writes only those
/// rows: threads may bake disjoint rows of one map at once, sharing one scratch.
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `scratch` NULL (an error) or valid for
/// reading `scratch_len` floats; `map` NULL (an error) or valid for writing `map_len`
/// floats; concurrent calls must bake disjoint rows.
#[no_mangle]
pub unsafe extern "C" fn hf_cone_bake_rows(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    row_begin: u32,
    row_end: u32,
    map: *mut f32,
    map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        bake_rows(
            CONE,
            field,
            scratch,
            scratch_len,
            row_begin,
            row_end,
            map,
            map_len,
        )
    }
}

/// Bakes the whole conservative cone map of `field` (cone step mapping made exact for
/// the triangle surface) into `out_map` (`out_map_len ≥ hf_cone_map_len`) on `threads`
/// threads (0: one per available core), allocating the scratch itself.
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_map` NULL (an error) or valid for
/// writing `out_map_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_cone_bake(
    field: *const hf_field,
    threads: u32,
    out_map: *mut f32,
    out_map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { bake(CONE, field, threads, out_map, out_map_len) }
}

#[cfg(feature = "relaxed")]
/// Writes the number of floats of the relaxed cone map of a `width × height` field to
/// `*out_len`: one ratio per sample (layout: docs/DESIGN.md, "Texture layouts",
/// relaxed cone), then `HF_MAP_DESC_BYTES / 4` floats of descriptor. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_relaxed_map_len(
    width: u32,
    height: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe { map_len(RELAXED, width, height, out_len) }
}

#[cfg(feature = "relaxed")]
/// Bakes sample rows `[row_begin, row_end)` (0 ≤ begin ≤ end ≤ H) of the relaxed cone
/// map (Policarpo & Oliveira 2007) into `map`, as `hf_cone_bake_rows`.
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// As `hf_cone_bake_rows`.
#[no_mangle]
pub unsafe extern "C" fn hf_relaxed_bake_rows(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    row_begin: u32,
    row_end: u32,
    map: *mut f32,
    map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        bake_rows(
            RELAXED,
            field,
            scratch,
            scratch_len,
            row_begin,
            row_end,
            map,
            map_len,
        )
    }
}

#[cfg(feature = "relaxed")]
/// Bakes the whole relaxed cone map of `field` into `out_map` (`out_map_len ≥
/// hf_relaxed_map_len`) on `threads` threads (0: one per available core).
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// As `hf_cone_bake`.
#[no_mangle]
pub unsafe extern "C" fn hf_relaxed_bake(
    field: *const hf_field,
    threads: u32,
    out_map: *mut f32,
    out_map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { bake(RELAXED, field, threads, out_map, out_map_len) }
}

#[cfg(feature = "qdm")]
/// Writes the number of floats of the quadratic displacement map of a `width ×
/// height` field to `*out_len`: four per cell (layout: docs/DESIGN.md, "Texture
/// layouts", QDM), then `HF_MAP_DESC_BYTES / 4` floats of descriptor. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_qdm_map_len(width: u32, height: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe { map_len(QDM, width, height, out_len) }
}

#[cfg(feature = "qdm")]
/// Bakes cell rows `[row_begin, row_end)` (0 ≤ begin ≤ end ≤ H − 1) of the quadratic
/// displacement map (after Kiglics et al.) into `map`, as `hf_cone_bake_rows`.
/// Thread safe (reads the field only) for disjoint rows of one map.
///
/// # Safety
/// As `hf_cone_bake_rows`.
#[no_mangle]
pub unsafe extern "C" fn hf_qdm_bake_rows(
    field: *const hf_field,
    scratch: *const f32,
    scratch_len: usize,
    row_begin: u32,
    row_end: u32,
    map: *mut f32,
    map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        bake_rows(
            QDM,
            field,
            scratch,
            scratch_len,
            row_begin,
            row_end,
            map,
            map_len,
        )
    }
}

#[cfg(feature = "qdm")]
/// Bakes the whole quadratic displacement map of `field` into `out_map` (`out_map_len
/// ≥ hf_qdm_map_len`) on `threads` threads (0: one per available core).
/// Thread safe for distinct output maps (reads the field only).
///
/// # Safety
/// As `hf_cone_bake`.
#[no_mangle]
pub unsafe extern "C" fn hf_qdm_bake(
    field: *const hf_field,
    threads: u32,
    out_map: *mut f32,
    out_map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { bake(QDM, field, threads, out_map, out_map_len) }
}

/// The marcher of `kind` (cone, relaxed or qdm) over `data`, its descriptor checked
/// for `f`, with the step budgets of `o`.
pub(crate) fn marcher<'a>(
    kind: MethodKind,
    f: &'a hf_field,
    data: &'a [f32],
    o: &TraceOptions,
) -> Result<Marcher<'a>, hf_result> {
    let hf = f.view();
    Ok(match kind {
        #[cfg(feature = "relaxed")]
        MethodKind::Relaxed => {
            let steps = relaxed::Steps {
                cone: o.steps,
                binary: o.binary_steps,
            };
            Marcher::Relaxed(texels_of(RELAXED, f, data)?, steps)
        }
        #[cfg(feature = "qdm")]
        MethodKind::Qdm => Marcher::Qdm(QdmMap::new(hf, texels_of(QDM, f, data)?)?, o.steps),
        MethodKind::Cone => Marcher::Cone(ConeMap::new(hf, texels_of(CONE, f, data)?)?, o.steps),
        _ => return Err(HF_ERR_NOT_BUILT),
    })
}
