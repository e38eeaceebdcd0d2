//! The marchers over baked maps: a map handed to `hf_trace` is checked by its
//! descriptor (kind, size, classes, heights) and viewed as the core's map type; and
//! the enums that name a map's variant or a march's mode.

use crate::detail::fail;
use crate::hf_result::{self, *};
use crate::mapdesc::{check_layout, Texel};
use crate::ptr::Named;
use crate::trace::TraceOptions;
use crate::{hf_field, ptr};
use hfcore::bake::Spec;
use hfcore::ktx2::{Data, Desc, MapKind};
use hfcore::mapdesc::MapDescriptor;
use hfcore::scene::MethodKind;
use hfcore::Marcher;
use std::ffi::c_void;

#[cfg(feature = "safety")]
/// Layout of a safety-distance map (`hf_bake_options::variant`). Passed as `uint32_t`.
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

#[cfg(feature = "safety")]
/// How the cone slope of a cylinder–cone bake is computed (`hf_bake_options::slope`).
/// Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_cc_slope {
    /// Over the limiting triangles only, exactly (larger steps, slower bake).
    HF_CC_SLOPE_EXACT = 0,
    /// Every triangle limiting, the highest sample per abscissa from the N-buffers
    /// (conservative, faster).
    HF_CC_SLOPE_NBUFFER = 1,
}

#[cfg(feature = "safety")]
/// What the radius march does at a texel of radius zero (`hf_trace_options::
/// radius_zero`). Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_radius_zero {
    /// Walk to the next centerline cell by cell with the exact test (exact).
    HF_RADIUS_WALK = 0,
    /// Jump one centerline as if the radius were 1: fewer fetches, **not exact** (a
    /// dip under the surface between two centerlines may be skipped).
    HF_RADIUS_CLAMP = 1,
}

/// The marcher of `kind` over the `map_len` elements at `map` (none for a method
/// without a map: then `map_len` must be 0), its descriptor checked for `f` (and for
/// the ray classes `o` names), with options `o`.
///
/// # Safety
/// `map` NULL or valid for reading `map_len` elements of the method's map.
pub(crate) unsafe fn marcher<'a>(
    kind: MethodKind,
    f: &'a hf_field,
    map: *const c_void,
    map_len: usize,
    o: &TraceOptions,
) -> Result<Marcher<'a>, hf_result> {
    let hf = f.view();
    let data = match kind.info().map {
        None if map_len != 0 => {
            let why = format_args!("map_len: {} reads no map; pass NULL and 0", kind.name());
            return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
        }
        None => None,
        Some(m) if m.format().is_float() => {
            // SAFETY: the caller's promise, for the method's element type.
            let (got, d) = unsafe { texels::<f32>(kind, f, map, map_len, o) }?;
            Some((got, Data::F32(d)))
        }
        Some(_) => {
            // SAFETY: the caller's promise, for the method's element type.
            let (got, d) = unsafe { texels::<u8>(kind, f, map, map_len, o) }?;
            Some((got, Data::U8(d)))
        }
    };
    let desc = data.map_or(Desc::new(MapKind::Heights, hf.width(), hf.height()), |d| {
        d.0.desc
    });
    Ok(Marcher::of(kind, hf, &desc, data.map(|d| d.1), &o.march)?)
}

/// The map `kind`'s march reads, checked by its descriptor for `f` (and for the ray
/// classes `o` names): the descriptor and the texels.
///
/// # Safety
/// `map` NULL or valid for reading `map_len` elements of `T`.
unsafe fn texels<'a, T: Texel>(
    kind: MethodKind,
    f: &hf_field,
    map: *const c_void,
    map_len: usize,
    o: &TraceOptions,
) -> Result<(MapDescriptor, &'a [T]), hf_result> {
    // SAFETY: the caller's promise.
    let data = unsafe { ptr::slice(map.cast::<T>(), map_len) }.named("map")?;
    let hf = f.view();
    let maps: &[MapKind] = match kind {
        MethodKind::Safety => &[MapKind::Safety, MapKind::SafetyIsotropic],
        _ => kind.info().map.as_slice(),
    };
    let len = |map, classes| {
        let desc = Desc {
            classes,
            ..Desc::new(map, hf.width(), hf.height())
        };
        Spec::new(desc.normalized()).map_len().unwrap_or(0)
    };
    let classes = o.classes.filter(|_| maps[0].has_rays());
    let (got, n) = check_layout(f, data, maps, classes, len)?;
    Ok((got, &data[..n]))
}
