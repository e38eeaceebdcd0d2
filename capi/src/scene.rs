//! The scene description (`hfcast::scene::Scene`) as a C struct.

use crate::detail::fail;
use crate::hf_result::{self, *};
use crate::{guard, method_of, ptr, surface_of};
use hfcore::scene::{BakePlan, HeightFormat, Need, RayClasses, Scene, Shadows};
use std::ffi::c_char;

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

/// Which shadow rays a scene traces (`hf_scene::shadows`). Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_shadows {
    /// No shadow rays.
    HF_SHADOWS_NONE = 0,
    /// From each lit point up towards the light (`hf_shadow_ray`): they start inside
    /// the field's box and rise, so the safety shapes are baked for every ray.
    HF_SHADOWS_FROM_SURFACE = 1,
    /// From the light's side down to each lit point (`hf_shadow_ray_from_light`):
    /// exterior rays, so a scene of outside viewpoints keeps its exterior maps.
    HF_SHADOWS_FROM_LIGHT = 2,
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
    /// Which shadow rays are traced (`hf_shadows`).
    pub shadows: u32,
    /// 1 for level-of-detail marching (maximum mipmaps only; approximate), else 0.
    pub lod: u32,
    /// 1 when the shader writes the hit depth, else 0.
    pub depth_output: u32,
    /// The height texture's format (`hf_height_format`).
    pub height_format: u32,
    /// 1 when the safety-shape maps are baked over static occluders
    /// (`hf_bake_options::occluders`; `hf_scene_bake_plan` leaves the list to the
    /// caller): the shader keeps their guard (the uniform `hf_occluder_count` and the
    /// texture `hf_occluders`); else 0.
    pub occluders: u32,
}

/// Checks a ray-class set passed as `uint32_t`: `HF_RAYS_*` bits, not 0.
pub(crate) fn classes_of(v: u32) -> Result<RayClasses, hf_result> {
    if v == 0 || v > HF_RAYS_ALL {
        return Err(HF_ERR_INVALID_ARGUMENT);
    }
    Ok(RayClasses(v as u8))
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
    let method = method_of(s.method)?;
    let scene = Scene {
        surface: surface_of(s.surface)?,
        method,
        ray_classes: RayClasses(u8::try_from(s.ray_classes).unwrap_or(u8::MAX)),
        outside_only: flag(s.outside_only)?,
        max_view_angle_deg: s.max_view_angle_deg,
        shadows: Shadows::from_u32(s.shadows).ok_or(HF_ERR_INVALID_ARGUMENT)?,
        lod: flag(s.lod)?,
        depth_output: flag(s.depth_output)?,
        heights,
        occluders: flag(s.occluders)?,
    };
    scene
        .validate()
        .map_err(|e| fail(HF_ERR_INVALID_ARGUMENT, e))?;
    Ok(scene)
}

/// The C form of a core [`Scene`].
pub(crate) fn c_scene(s: &Scene) -> hf_scene {
    hf_scene {
        surface: s.surface as u32,
        method: s.method as u32,
        ray_classes: u32::from(s.ray_classes.0),
        outside_only: u32::from(s.outside_only),
        max_view_angle_deg: s.max_view_angle_deg,
        shadows: s.shadows as u32,
        lod: u32::from(s.lod),
        depth_output: u32::from(s.depth_output),
        height_format: s.heights as u32,
        occluders: u32::from(s.occluders),
    }
}

/// Writes the general scene of `method` on `surface` to `*out`: every ray class,
/// viewpoints anywhere, any direction, shadows from the surface, no LOD, depth output,
/// `F32` heights, occluders. Thread safe.
///
/// # Safety
/// `out` is NULL (an error) or valid for writing one `hf_scene`.
#[no_mangle]
pub unsafe extern "C" fn hf_scene_general(
    method: u32,
    surface: u32,
    out: *mut hf_scene,
) -> hf_result {
    let general = |()| {
        let m = method_of(method)?;
        Ok(c_scene(&Scene::general(m, surface_of(surface)?)))
    };
    // SAFETY: the caller's promise, passed on.
    unsafe { ptr::answer(|| Ok(()), out, general) }
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

/// How a scene needs one baked product (the fields of `hf_bake_plan`). Passed as
/// `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_need {
    /// Not baked: the scene's method never reads it (`hf_scene_bake_plan_skipped` says why).
    HF_NEED_SKIP = 0,
    /// Baked as the input of another bake only: free it once that bake is done.
    HF_NEED_SCRATCH = 1,
    /// Baked and read by the march: keep it (upload it).
    HF_NEED_KEEP = 2,
}

/// What to bake for a scene (`hf_scene_bake_plan`): an `hf_need` per product, the ray
/// classes and the ray set the safety-shape bakes compute for, and the safety map's
/// layout.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_bake_plan {
    /// The maximum-mipmap pyramid (`hf_bake` of `HF_METHOD_MAXMIP`): kept for maxmip;
    /// the scratch of the cone, relaxed-cone and QDM bakes (`hf_bake_prepare`).
    pub pyramid: u32,
    /// The strip bounds of the safety-shape bakes (their `hf_bake_prepare` scratch).
    pub safety_scratch: u32,
    /// The safety-distance map (`hf_bake` of `HF_METHOD_SAFETY`).
    pub safety_map: u32,
    /// The cylinder–cone map (`hf_bake` of `HF_METHOD_CC`).
    pub cc_map: u32,
    /// The N-buffers of the cylinder–cone bake (the second part of its `hf_bake_prepare`
    /// scratch), with either slope.
    pub nbuffer: u32,
    /// The conservative cone map (`hf_bake` of `HF_METHOD_CONE`).
    pub cone_map: u32,
    /// The relaxed cone map (`hf_bake` of `HF_METHOD_RELAXED`).
    pub relaxed_map: u32,
    /// The quadratic displacement map (`hf_bake` of `HF_METHOD_QDM`).
    pub qdm_map: u32,
    /// `HF_RAYS_*` bits of the classes the safety-distance and cylinder–cone bakes
    /// compute (pass them as `hf_bake_options::ray_classes` to `hf_map_len` and the
    /// bakes): the maps hold these classes' rows only, and `hf_trace`
    /// reads them from the maps. 0 when neither is baked.
    pub ray_classes: u32,
    /// The safety map's layout, an `hf_safety_variant`: `HF_SAFETY_ISOTROPIC` (one
    /// byte per texel, that class's distances exactly) when one ray class occurs,
    /// else `HF_SAFETY_DIRECTIONAL`.
    pub safety_variant: u32,
    /// The safety-radius map (`hf_bake` of `HF_METHOD_RADIUS`; its scratch is
    /// `safety_scratch`).
    pub radius_map: u32,
    /// The ray set the safety-distance and cylinder–cone bakes are for (pass it as
    /// `hf_bake_options::exterior`): 1 for exterior rays only when the scene's rays all
    /// start outside the box and it traces no shadows from the surface, else 0.
    pub exterior: u32,
    /// Likewise `hf_bake_options::max_view_angle_deg`: the scene's largest view angle
    /// when below 180° and it traces no shadows from the surface, else 0 (any
    /// direction).
    pub max_view_angle_deg: f32,
}

/// The C form of a `Need`.
fn need_of(n: Need) -> u32 {
    let v = match n {
        Need::Skip(_) => hf_need::HF_NEED_SKIP,
        Need::Scratch => hf_need::HF_NEED_SCRATCH,
        Need::Keep => hf_need::HF_NEED_KEEP,
    };
    v as u32
}

/// The C form of a core [`BakePlan`].
fn c_plan(p: &BakePlan) -> hf_bake_plan {
    let [pyramid, safety_scratch, safety_map, cc_map, nbuffer, cone_map, relaxed_map, qdm_map, radius_map] =
        p.needs.map(need_of);
    hf_bake_plan {
        pyramid,
        safety_scratch,
        safety_map,
        cc_map,
        nbuffer,
        cone_map,
        relaxed_map,
        qdm_map,
        ray_classes: u32::from(p.classes.0),
        safety_variant: u32::from(p.isotropic),
        radius_map,
        exterior: u32::from(p.rays.exterior),
        max_view_angle_deg: match p.rays.max_view_angle_deg {
            a if a < 180.0 => a,
            _ => 0.0,
        },
    }
}

/// Writes what to bake for `*scene` to `*out_plan`: only the data its method reads
/// (nothing for the exact and search methods), safety-shape channels only for the ray
/// classes that occur, for the scene's ray set. Any method, built or not (a plan is
/// data). A bad scene gives the code of `hf_scene_check`. Thread safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`; `out_plan` NULL (an
/// error) or valid for writing one `hf_bake_plan`.
#[no_mangle]
pub unsafe extern "C" fn hf_scene_bake_plan(
    scene: *const hf_scene,
    out_plan: *mut hf_bake_plan,
) -> hf_result {
    let plan = |s: &hf_scene| Ok(c_plan(&scene_of(s)?.bake_plan()));
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| ptr::get(scene), out_plan, plan) }
}

/// The text of `hf_scene_bake_plan_skipped`: one `item: reason` line per skipped item.
fn skipped_text(plan: &BakePlan) -> String {
    plan.skipped()
        .map(|(what, why)| format!("{what}: {why}\n"))
        .collect()
}

/// Writes what the bake plan of `*scene` leaves out, and why, into `buf` as a
/// NUL-terminated ASCII string of lines `item: reason\n` (empty when nothing is
/// skipped), and its length without the NUL to `*out_written`. 1024 bytes always
/// suffice; a smaller buffer that is too small is `HF_ERR_BUFFER_TOO_SMALL`. Thread
/// safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`; `buf` NULL (an
/// error) or valid for writing `buf_len` bytes; `out_written` NULL (an error) or valid
/// for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_scene_bake_plan_skipped(
    scene: *const hf_scene,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `scene` is readable, `buf` and `out_written`
        // writable.
        unsafe {
            let s = ptr::get(scene)?;
            let text = || Ok(skipped_text(&scene_of(s)?.bake_plan()));
            ptr::write_text(buf, buf_len, out_written, text)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hfcore::scene::MethodKind;

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
            hf_scene { shadows: 3, ..s },
            hf_scene { occluders: 2, ..s },
        ] {
            assert_eq!(scene_of(&bad), Err(HF_ERR_INVALID_ARGUMENT));
        }
        assert_eq!(
            scene_of(&hf_scene {
                method: crate::HF_METHOD_COUNT,
                ..s
            }),
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

    #[test]
    fn bake_plans_mirror_the_core() {
        for m in MethodKind::ALL {
            for classes in [HF_RAYS_ALL, HF_RAYS_X_POS | HF_RAYS_Y_NEG, HF_RAYS_Y_POS] {
                let mut s = std::mem::MaybeUninit::<hf_scene>::uninit();
                // SAFETY: `s` is writable.
                assert_eq!(
                    unsafe { hf_scene_general(m as u32, 0, s.as_mut_ptr()) },
                    HF_OK
                );
                // SAFETY: written on HF_OK.
                let s = hf_scene {
                    ray_classes: classes,
                    ..unsafe { s.assume_init() }
                };
                let core = scene_of(&s).unwrap().bake_plan();
                let mut plan = std::mem::MaybeUninit::<hf_bake_plan>::uninit();
                // SAFETY: valid pointers.
                assert_eq!(unsafe { hf_scene_bake_plan(&s, plan.as_mut_ptr()) }, HF_OK);
                // SAFETY: written on HF_OK.
                let plan = unsafe { plan.assume_init() };
                assert_eq!(plan, c_plan(&core));
                let needs = [
                    plan.pyramid,
                    plan.safety_scratch,
                    plan.safety_map,
                    plan.cc_map,
                    plan.nbuffer,
                    plan.cone_map,
                    plan.relaxed_map,
                    plan.qdm_map,
                    plan.radius_map,
                ];
                assert_eq!(needs, core.needs.map(need_of));
                let mut buf = [0 as c_char; 1024];
                let mut n = 0;
                // SAFETY: valid pointers and length.
                let r =
                    unsafe { hf_scene_bake_plan_skipped(&s, buf.as_mut_ptr(), buf.len(), &mut n) };
                assert_eq!(r, HF_OK);
                let text = skipped_text(&core);
                assert_eq!(n, text.len());
                assert!(text.is_ascii() && text.lines().count() == core.skipped().count());
                // SAFETY: a buffer one byte short is refused.
                let r = unsafe { hf_scene_bake_plan_skipped(&s, buf.as_mut_ptr(), n, &mut n) };
                assert_eq!(r, HF_ERR_BUFFER_TOO_SMALL);
            }
        }
        let mut plan = std::mem::MaybeUninit::<hf_bake_plan>::uninit();
        let bad = hf_scene {
            ray_classes: 0,
            ..c_scene(&Scene::general(MethodKind::Cc, hfcore::Surface::Triangles))
        };
        // SAFETY: valid pointers; the scene is invalid.
        let r = unsafe { hf_scene_bake_plan(&bad, plan.as_mut_ptr()) };
        assert_eq!(r, HF_ERR_INVALID_ARGUMENT);
    }
}
