//! Occluders at the boundary: `hf_occluder`, the triangles whose solids a safety or
//! cylinder–cone map's ray set passes over (`hf_bake_options::occluders`), given again
//! to every trace over such a map (`hf_trace_options::occluders`).

use hfcore::rayset::{Occluder, RaysError};

use crate::detail::fail;
use crate::hf_result::{self, *};
use crate::ptr;

/// A static occluder: the solid under a triangle, every point at or below it over its
/// footprint (a wall's or a mountain's top around the field). `corners` are `[x, y,
/// z]` in grid units (the field's frame, before any world transform), finite, with a
/// footprint (x, y) of non-zero area. A map baked over occluders serves only the rays
/// whose line, up to where it leaves the field's footprint, never dips under one;
/// every other ray walks cell by cell (exact). docs/DESIGN.md, "Ray sets".
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct hf_occluder {
    /// The triangle's corners `[x, y, z]`.
    pub corners: [[f32; 3]; 3],
}

/// The most occluders a map's ray set takes.
pub const HF_MAX_OCCLUDERS: u32 = 64;

// The core's type has the same layout: a list is read in place.
const _: () = {
    assert!(size_of::<hf_occluder>() == size_of::<Occluder>());
    assert!(align_of::<hf_occluder>() == align_of::<Occluder>());
    assert!(HF_MAX_OCCLUDERS as usize == hfcore::rayset::MAX_OCCLUDERS);
};

/// The `count` occluders at `p` (the option `name`), checked: none when `count` is 0
/// (then `p` is not read), else `p` must be a valid list of at most
/// `HF_MAX_OCCLUDERS` finite triangles with footprints.
///
/// # Safety
/// When `count > 0` and `p` is non-NULL and aligned, `p` is valid for reading `count`
/// occluders, not written while the slice lives.
pub(crate) unsafe fn occluders_of<'a>(
    p: *const hf_occluder,
    count: u32,
    name: &str,
) -> Result<&'a [Occluder], hf_result> {
    if count == 0 {
        return Ok(&[]);
    }
    if count > HF_MAX_OCCLUDERS {
        let why = format_args!("options.{name}: over {HF_MAX_OCCLUDERS} occluders");
        return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
    }
    // SAFETY: the caller's promise; `Occluder` has `hf_occluder`'s layout (asserted
    // above), both `repr(C)` arrays of floats.
    let list = unsafe { ptr::slice(p.cast::<Occluder>(), count as usize) }?;
    if let Err(e) = hfcore::rayset::Rays::ALL.passing_over(list) {
        return Err(fail(
            HF_ERR_INVALID_ARGUMENT,
            format_args!("options.{name}: {e}"),
        ));
    }
    Ok(list)
}

/// The error of occluders that are not a map's (`RaysError::OccludersDiffer`, else
/// an invalid occluder).
pub(crate) fn mismatch(e: RaysError) -> hf_result {
    match e {
        RaysError::OccludersDiffer => fail(
            HF_ERR_MAP_MISMATCH,
            "options.occluders: not the occluders the map was baked over (give the same \
             list, in the same order, or none for a map baked without)",
        ),
        e => fail(
            HF_ERR_INVALID_ARGUMENT,
            format_args!("options.occluders: {e}"),
        ),
    }
}
