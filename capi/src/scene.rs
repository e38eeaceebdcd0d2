//! The scene description (`hfcast::scene::Scene`) as a C struct.

use crate::hf_result::{self, *};
use crate::{guard, method_of, ptr, surface_of};
use hfcore::scene::{HeightFormat, MethodKind, RayClasses, Scene};

/// Ray-class bit of `hf_scene::ray_classes`: rays with dx ≥ |dy|.
pub const HF_RAYS_X_POS: u32 = 1;
/// Ray-class bit: rays with −dx ≥ |dy|.
pub const HF_RAYS_X_NEG: u32 = 2;
/// Ray-class bit: rays with dy > |dx|.
pub const HF_RAYS_Y_POS: u32 = 4;
/// Ray-class bit: every other direction (vertical rays included).
pub const HF_RAYS_Y_NEG: u32 = 8;
/// Every ray class.
pub const HF_RAYS_ALL: u32 = 15;

/// Height texture formats (`hf_scene::height_format`). Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_height_format {
    /// 32-bit float heights in grid units (`R32F`).
    HF_HEIGHTS_F32 = 0,
    /// 16-bit unsigned normalised samples times a depth scale (`R16`).
    HF_HEIGHTS_U16 = 1,
    /// 8-bit unsigned normalised samples times a depth scale (`R8`).
    HF_HEIGHTS_U8 = 2,
}

/// What a scene uses; shader generation and bakes leave out everything else. Fill it
/// with `hf_scene_general`, then narrow it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_scene {
    /// The one surface (`hf_surface`).
    pub surface: u32,
    /// The one method (`hf_method`).
    pub method: u32,
    /// The ray classes that occur: `HF_RAYS_*` bits, not zero.
    pub ray_classes: u32,
    /// 1 when every ray origin stays outside the field's bounding box, else 0.
    pub outside_only: u32,
    /// The largest angle between a primary ray and the downward vertical, in degrees,
    /// in (0, 180]: 90 = horizontal at most, 180 = any direction.
    pub max_view_angle_deg: f32,
    /// 1 when shadow rays (upward, towards a light) are traced, else 0.
    pub shadows: u32,
    /// 1 for level-of-detail marching (maximum mipmaps only; approximate), else 0.
    pub lod: u32,
    /// 1 when the shader writes the hit depth, else 0.
    pub depth_output: u32,
    /// The height texture's format (`hf_height_format`).
    pub height_format: u32,
}

/// Checks an `hf_scene` and turns it into the core's [`Scene`].
pub(crate) fn scene_of(s: &hf_scene) -> Result<Scene, hf_result> {
    let flag = |v: u32| match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(HF_ERR_INVALID_ARGUMENT),
    };
    let heights = match s.height_format {
        0 => HeightFormat::F32,
        1 => HeightFormat::U16,
        2 => HeightFormat::U8,
        _ => return Err(HF_ERR_INVALID_ENUM),
    };
    if s.ray_classes == 0 || s.ray_classes > HF_RAYS_ALL {
        return Err(HF_ERR_INVALID_ARGUMENT);
    }
    let angle = s.max_view_angle_deg;
    if !(angle > 0.0 && angle <= 180.0) {
        return Err(HF_ERR_INVALID_ARGUMENT);
    }
    let method = method_of(s.method)?;
    Ok(Scene {
        surface: surface_of(s.surface)?,
        method: MethodKind::from_u32(method as u32).ok_or(HF_ERR_INVALID_ENUM)?,
        ray_classes: RayClasses(s.ray_classes as u8),
        outside_only: flag(s.outside_only)?,
        max_view_angle_deg: angle,
        shadows: flag(s.shadows)?,
        lod: flag(s.lod)?,
        depth_output: flag(s.depth_output)?,
        heights,
    })
}

/// The C form of a core [`Scene`].
pub(crate) fn c_scene(s: &Scene) -> hf_scene {
    hf_scene {
        surface: s.surface as u32,
        method: s.method as u32,
        ray_classes: u32::from(s.ray_classes.0),
        outside_only: u32::from(s.outside_only),
        max_view_angle_deg: s.max_view_angle_deg,
        shadows: u32::from(s.shadows),
        lod: u32::from(s.lod),
        depth_output: u32::from(s.depth_output),
        height_format: s.heights as u32,
    }
}

/// Writes the general scene of `method` on `surface` to `*out`: every ray class,
/// viewpoints anywhere, any direction, shadows, no LOD, depth output, `F32` heights.
/// Thread safe.
///
/// # Safety
/// `out` is NULL (an error) or valid for writing one `hf_scene`.
#[no_mangle]
pub unsafe extern "C" fn hf_scene_general(
    method: u32,
    surface: u32,
    out: *mut hf_scene,
) -> hf_result {
    guard(|| {
        let out = ptr::out(out)?;
        let m = MethodKind::from_u32(method_of(method)? as u32).ok_or(HF_ERR_INVALID_ENUM)?;
        let scene = Scene::general(m, surface_of(surface)?);
        // SAFETY: the caller promises `out` is writable.
        unsafe { out.set(c_scene(&scene)) };
        Ok(())
    })
}

/// Checks `*scene`: `HF_OK` when every field is valid, else the code the first bad
/// field gives (`HF_ERR_INVALID_ENUM` for an unknown surface, method or format,
/// `HF_ERR_INVALID_ARGUMENT` for an empty or unknown ray-class set, an angle outside
/// (0, 180] or a flag other than 0 and 1). Thread safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`.
#[no_mangle]
pub unsafe extern "C" fn hf_scene_check(scene: *const hf_scene) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `scene` is readable.
        let s = unsafe { ptr::get(scene) }?;
        scene_of(s).map(|_| ())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn general_scene_round_trips_and_bad_fields_are_rejected() {
        let mut s = std::mem::MaybeUninit::<hf_scene>::uninit();
        // SAFETY: `s` is writable.
        assert_eq!(unsafe { hf_scene_general(8, 1, s.as_mut_ptr()) }, HF_OK);
        // SAFETY: written on HF_OK.
        let s = unsafe { s.assume_init() };
        let core = scene_of(&s).unwrap();
        assert_eq!(
            core,
            Scene::general(MethodKind::Cc, hfcore::Surface::Bilinear)
        );
        assert_eq!(c_scene(&core), s);
        for bad in [
            hf_scene {
                ray_classes: 0,
                ..s
            },
            hf_scene {
                ray_classes: 16,
                ..s
            },
            hf_scene {
                max_view_angle_deg: f32::NAN,
                ..s
            },
            hf_scene {
                max_view_angle_deg: 0.0,
                ..s
            },
            hf_scene { shadows: 2, ..s },
        ] {
            assert_eq!(scene_of(&bad), Err(HF_ERR_INVALID_ARGUMENT));
        }
        assert_eq!(
            scene_of(&hf_scene { method: 9, ..s }),
            Err(HF_ERR_INVALID_ENUM)
        );
        assert_eq!(
            scene_of(&hf_scene {
                height_format: 3,
                ..s
            }),
            Err(HF_ERR_INVALID_ENUM)
        );
        // SAFETY: a NULL output is reported, not written.
        assert_eq!(
            unsafe { hf_scene_general(0, 0, std::ptr::null_mut()) },
            HF_ERR_NULL_POINTER
        );
    }
}
