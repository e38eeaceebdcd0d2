//! The GLSL and WGSL ports of the marches (crate `hfcast-shaders`), as source text the
//! caller compiles: a method's general GLSL source, or the shader generated for a scene.

use crate::hf_result::{self, *};
use crate::scene::{hf_scene, scene_of};
use crate::{built_method_of, guard, ptr};
use hfcast_shaders::{general, generate, GenError, Lang};
use hfcore::scene::MethodKind;
use std::ffi::c_char;

/// Shader language of `hf_shader_generate`: GLSL 3.30 core (no `#version` line).
pub const HF_SHADER_GLSL: u32 = 0;
/// Shader language of `hf_shader_generate`: WGSL.
pub const HF_SHADER_WGSL: u32 = 1;

/// The general GLSL source of `method`: its files concatenated (no `#version` line).
pub fn source(kind: MethodKind) -> String {
    general(kind, Lang::Glsl).expect("the GLSL port is complete")
}

/// The shader of `*scene` in language `lang` (an `HF_SHADER_*`).
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`.
unsafe fn generated(scene: *const hf_scene, lang: u32) -> Result<String, hf_result> {
    // SAFETY: the caller's promise.
    unsafe { generated_by(scene, lang, generate) }
}

/// The impostor shader of `*scene` in language `lang` (`hfcast_shaders::impostor`).
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`.
unsafe fn generated_impostor(scene: *const hf_scene, lang: u32) -> Result<String, hf_result> {
    // SAFETY: the caller's promise.
    unsafe { generated_by(scene, lang, hfcast_shaders::impostor) }
}

/// What the generator `gen` makes of `*scene` in language `lang`, its errors as C
/// error codes.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`.
unsafe fn generated_by(
    scene: *const hf_scene,
    lang: u32,
    gen: fn(&hfcore::scene::Scene, Lang) -> Result<String, GenError>,
) -> Result<String, hf_result> {
    // SAFETY: the caller's promise.
    let s = unsafe { ptr::get(scene) }?;
    let scene = scene_of(s)?;
    built_method_of(s.method)?;
    let lang = match lang {
        HF_SHADER_GLSL => Lang::Glsl,
        HF_SHADER_WGSL => Lang::Wgsl,
        _ => return Err(HF_ERR_INVALID_ENUM),
    };
    gen(&scene, lang).map_err(|e| match e {
        GenError::SurfaceNotSupported { .. } | GenError::Scene(_) => HF_ERR_INVALID_ARGUMENT,
        GenError::MissingFile { .. } | GenError::Source(_) => HF_ERR_NOT_BUILT,
    })
}

/// The source of the GPU bake `stem` (`bake_maxmip`, `bake_nbuffer`) in `lang` (an
/// `HF_SHADER_*`): WGSL, or a whole GLSL 4.30 compute shader (its `#version` line
/// included).
#[cfg(any(feature = "maxmip", feature = "safety"))]
pub(crate) fn gpu_bake_source(stem: &str, lang: u32) -> Result<String, hf_result> {
    let lang = match lang {
        HF_SHADER_GLSL => Lang::Glsl,
        HF_SHADER_WGSL => Lang::Wgsl,
        _ => return Err(HF_ERR_INVALID_ENUM),
    };
    hfcast_shaders::file(lang, stem)
        .map(String::from)
        .ok_or(HF_ERR_NOT_BUILT)
}

/// Writes the length of `text()` plus one (its NUL terminator) to `*out_len`, checked
/// first: the `*_len` query of `write_text`.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
pub(crate) unsafe fn write_len(
    out_len: *mut usize,
    text: impl FnOnce() -> Result<String, hf_result>,
) -> hf_result {
    guard(|| {
        let out = ptr::out(out_len)?;
        let n = text()?.len() + 1;
        // SAFETY: the caller promises `out_len` is writable.
        unsafe { out.set(n) };
        Ok(())
    })
}

/// Writes `text()` into `buf` as a NUL-terminated string and its length without the
/// NUL to `*out_written`, both checked first.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
pub(crate) unsafe fn write_text(
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
    text: impl FnOnce() -> Result<String, hf_result>,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    guard(|| unsafe { ptr::write_text(buf, buf_len, out_written, text) })
}

/// Writes the length in bytes of `hf_shader_source(method)`, including its NUL
/// terminator, to `*out_len`: the buffer size to pass. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_source_len(method: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise.
    unsafe { write_len(out_len, || Ok(source(built_method_of(method)?))) }
}

/// Writes the GLSL 3.30 source of `method` (an `hf_method`) into `buf` as a
/// NUL-terminated string and its length without the NUL to `*out_written`; `buf_len`
/// must be at least `hf_shader_source_len`. The source has no `#version` line: put
/// `#version 330 core` (or later) first, then this, then your `main`, which calls
/// `Trace hf_trace(Query q)` (a ray in grid space, as `hf_ray`; `Trace` mirrors
/// `hf_hit`). The functions mirror the Rust core one for one (`dda::trace` is
/// `dda_trace`, …) and give the same answers bit for bit on the rays tested. For rays
/// in world units call `Trace hf_trace_world(Query world)` instead, with the field's
/// `hf_transform` in the uniforms `hf_world_offset` = (origin x, origin y, height
/// offset) and `hf_world_scale` = (spacing x, spacing y, height scale) (default: the
/// identity; the conversion runs in `float`, so answers agree with the C API's
/// double-precision conversion within a few ulps). The uniforms it declares (the
/// textures' layouts: docs/DESIGN.md, "Texture layouts"): `hf_heights`, `hf_size` =
/// (W, H), `hf_height_range` = (min, max) from `hf_field_get_info`; `hf_surface` (every
/// method but the cone family, which traces the triangle surface); `hf_linear_steps`,
/// `hf_binary_steps` (search methods); multires: `hf_multires_range` (its one-texel
/// distance, `hf_trace_options::steps`); cone and QDM: `hf_max_iter`, `hf_cone_map` or
/// `hf_qdm_map`; relaxed: `hf_cone_steps`, `hf_binary_steps`, `hf_relaxed_map`;
/// maxmip: `hf_pyramid`, `hf_levels`, `hf_level_dims[]`, `hf_level_offset[]` (from
/// `hf_maxmip_levels`); safety: `hf_safety_map`, `hf_safety_variant`,
/// `hf_safety_classes`; cylinder–cone: `hf_cc_map`, `hf_cc_classes`, `hf_cc_cap`;
/// radius: `hf_radius_map`, `hf_radius_clamp`. `hf_safety_classes` and
/// `hf_cc_classes` (`HF_RAYS_*` bits, default `HF_RAYS_ALL`) are the ray classes the
/// map holds (its bake options' `ray_classes`); `hf_rays_exterior` (uint, default 0)
/// and `hf_rays_max_view_angle` (float degrees, default 180: any direction) the ray
/// set the safety or cylinder–cone map is baked for (its bake options' `exterior` and
/// `max_view_angle_deg`, 0 there being 180 here): a ray outside the set walks cell by
/// cell, as `hf_trace` does with the map. Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_source(
    method: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe {
        write_text(buf, buf_len, out_written, || {
            Ok(source(built_method_of(method)?))
        })
    }
}

/// Writes the length in bytes of `hf_shader_generate(scene, lang)`, including its NUL
/// terminator, to `*out_len`: the buffer size to pass. Errors as `hf_shader_generate`.
/// Thread safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`; `out_len` NULL (an
/// error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_generate_len(
    scene: *const hf_scene,
    lang: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe { write_len(out_len, || generated(scene, lang)) }
}

/// Writes the shader generated for `*scene` in `lang` (`HF_SHADER_GLSL`: GLSL 3.30 core
/// without a `#version` line; `HF_SHADER_WGSL`: WGSL) into `buf` as a NUL-terminated
/// string and its length without the NUL to `*out_written`; `buf_len` must be at least
/// `hf_shader_generate_len`. The shader holds only the code the scene uses: the
/// scene's surface and method, no branch for another surface, no upward-ray code
/// without shadows and with a view angle of at most 90°, and only the uniforms and
/// textures its march reads; `hf_surface`, `hf_safety_variant`, the map's ray
/// classes `hf_safety_classes` / `hf_cc_classes` and its ray set `hf_rays_exterior` /
/// `hf_rays_max_view_angle` are constants (safety: the layout `hf_bake_plan` picks,
/// isotropic for a single ray class, else directional; the classes: the scene's
/// `ray_classes`, so the maps are those baked with them as the options'
/// `ray_classes`; the set: `hf_bake_plan`'s, from the scene's `outside_only` and
/// `max_view_angle_deg`, every ray when it traces shadows). Such a shader serves the
/// scene's rays only. Its entry point and its remaining inputs are those of
/// `hf_shader_source` for the method, less what it does not read (a header comment
/// lists them): GLSL `hf_heights` (`R32F`; for `HF_HEIGHTS_U16` / `HF_HEIGHTS_U8` an
/// `R16UI` / `R8UI` texture of the samples and `hf_height_step` = depth / 65535 or
/// depth / 255), `hf_size`, `hf_height_range`, then the method's own (step counts,
/// maps); WGSL the fixed bindings of `hfcast_shared.wgsl` it uses. Errors:
/// `HF_ERR_INVALID_ENUM` (lang, or a field of the scene), `HF_ERR_INVALID_ARGUMENT` (an
/// invalid scene, a surface the method does not trace, LOD marching, which has no shader
/// port), `HF_ERR_NOT_BUILT` (a method left out of this build, or a file the language's
/// port lacks). Thread safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`; `buf` NULL (an error)
/// or valid for writing `buf_len` bytes; `out_written` NULL (an error) or valid for
/// writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_generate(
    scene: *const hf_scene,
    lang: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe { write_text(buf, buf_len, out_written, || generated(scene, lang)) }
}

/// Writes the length in bytes of `hf_shader_generate_impostor(scene, lang)`, including
/// its NUL terminator, to `*out_len`. Errors as `hf_shader_generate_impostor`. Thread
/// safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`; `out_len` NULL (an
/// error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_generate_impostor_len(
    scene: *const hf_scene,
    lang: u32,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe { write_len(out_len, || generated_impostor(scene, lang)) }
}

/// Writes the six-field impostor shader of `*scene` in `lang` into `buf` as
/// `hf_shader_generate` does (a NUL-terminated string; its length without the NUL to
/// `*out_written`; `buf_len` at least `hf_shader_generate_impostor_len`):
/// `ImpostorTrace hf_trace_impostor(Query world, uint combine)` (GLSL; WGSL the same),
/// the first point of a world ray in the impostor of six fields traced by the exact
/// march on the scene's surface, as `hf_impostor_trace_batch` traces it, and, only when
/// the scene has `depth_output`, `float hf_impostor_depth(vec3 p)`, the depth to write
/// for a hit at world point `p` under the uniform `hf_view_proj` (rows of the world to
/// clip matrix). The inputs (GLSL): `hf_heights` (R32F, the six `side × side` fields
/// stacked, face k's rows from `k·side`), `hf_size` = (side, side),
/// `hf_field_ranges[6]` (each field's min and max), `hf_impostor_maps[24]` and
/// `hf_impostor_inverses[24]` (row r of face k's `hf_impostor_face_map` and of its
/// inverse at 4k + r), `hf_impostor_cube` (centre, half side); the shader's header
/// comment lists them. Errors as `hf_shader_generate`, and `HF_ERR_INVALID_ARGUMENT`
/// for a scene whose method is not `HF_METHOD_EXACT` or whose heights are not
/// `HF_HEIGHTS_F32`. Thread safe.
///
/// # Safety
/// `scene` is NULL (an error) or valid for reading one `hf_scene`; `buf` NULL (an error)
/// or valid for writing `buf_len` bytes; `out_written` NULL (an error) or valid for
/// writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_generate_impostor(
    scene: *const hf_scene,
    lang: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe {
        write_text(buf, buf_len, out_written, || {
            generated_impostor(scene, lang)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::hf_scene_general;

    #[test]
    #[cfg(all(feature = "maxmip", feature = "safety"))]
    fn layout_numbers_agree_with_the_shaders() {
        assert_eq!(
            crate::HF_PYRAMID_TEX_WIDTH,
            hfcast_shaders::PYRAMID_TEX_WIDTH
        );
        assert_eq!(
            crate::maps::hf_safety_variant::HF_SAFETY_ISOTROPIC as u32,
            hfcast_shaders::SafetyVariant::Isotropic as u32
        );
    }

    #[test]
    fn every_method_has_a_source_with_hf_trace() {
        for m in MethodKind::ALL {
            let s = source(m);
            assert_eq!(
                s.matches("Trace hf_trace(Query q)").count(),
                1,
                "{}",
                m.name()
            );
            assert!(!s.contains("#version"));
        }
    }

    #[test]
    fn generate_sizes_then_writes_and_rejects_bad_input() {
        let mut scene = std::mem::MaybeUninit::<hf_scene>::uninit();
        // SAFETY: `scene` is writable.
        assert_eq!(unsafe { hf_scene_general(0, 0, scene.as_mut_ptr()) }, HF_OK);
        // SAFETY: written on HF_OK.
        let mut scene = unsafe { scene.assume_init() };
        scene.shadows = crate::scene::hf_shadows::HF_SHADOWS_NONE as u32;
        scene.max_view_angle_deg = 60.0;
        let mut len = 0usize;
        // SAFETY: valid pointers.
        let r = unsafe { hf_shader_generate_len(&scene, HF_SHADER_GLSL, &mut len) };
        assert_eq!(r, HF_OK);
        assert!(len > 100 && len < source(MethodKind::Exact).len());
        let mut buf = vec![0 as c_char; len];
        let mut written = 0usize;
        // SAFETY: `buf` holds `len` bytes.
        let r = unsafe {
            hf_shader_generate(&scene, HF_SHADER_GLSL, buf.as_mut_ptr(), len, &mut written)
        };
        assert_eq!((r, written + 1), (HF_OK, len));
        // SAFETY: one byte short.
        let r = unsafe {
            hf_shader_generate(
                &scene,
                HF_SHADER_GLSL,
                buf.as_mut_ptr(),
                len - 1,
                &mut written,
            )
        };
        assert_eq!(r, HF_ERR_BUFFER_TOO_SMALL);
        // SAFETY: valid pointers; bad language.
        assert_eq!(
            unsafe { hf_shader_generate_len(&scene, 2, &mut len) },
            HF_ERR_INVALID_ENUM
        );
        let cc_bilinear = hf_scene {
            method: 8,
            surface: 1,
            ..scene
        };
        // SAFETY: valid pointers; an unsupported surface (or, in a build without
        // cylinder–cone shapes, a method the build lacks).
        let expected = if cfg!(feature = "safety") {
            HF_ERR_INVALID_ARGUMENT
        } else {
            HF_ERR_NOT_BUILT
        };
        assert_eq!(
            unsafe { hf_shader_generate_len(&cc_bilinear, HF_SHADER_GLSL, &mut len) },
            expected
        );
        // SAFETY: a NULL scene is reported.
        assert_eq!(
            unsafe { hf_shader_generate_len(std::ptr::null(), HF_SHADER_GLSL, &mut len) },
            HF_ERR_NULL_POINTER
        );
    }

    #[test]
    fn the_impostor_shader_depends_on_depth_output_and_wants_the_exact_method() {
        let mut scene = std::mem::MaybeUninit::<hf_scene>::uninit();
        // SAFETY: `scene` is writable.
        assert_eq!(unsafe { hf_scene_general(0, 0, scene.as_mut_ptr()) }, HF_OK);
        // SAFETY: written on HF_OK.
        let scene = unsafe { scene.assume_init() };
        let text = |scene: &hf_scene| {
            let mut len = 0usize;
            // SAFETY: valid pointers.
            let r = unsafe { hf_shader_generate_impostor_len(scene, HF_SHADER_GLSL, &mut len) };
            if r != HF_OK {
                return Err(r);
            }
            let mut buf = vec![0 as c_char; len];
            let mut written = 0usize;
            // SAFETY: `buf` holds `len` bytes.
            let r = unsafe {
                hf_shader_generate_impostor(
                    scene,
                    HF_SHADER_GLSL,
                    buf.as_mut_ptr(),
                    len,
                    &mut written,
                )
            };
            assert_eq!((r, written + 1), (HF_OK, len));
            let bytes: Vec<u8> = buf[..written].iter().map(|&c| c as u8).collect();
            Ok(String::from_utf8(bytes).unwrap())
        };
        let with = text(&scene).unwrap();
        let without = text(&hf_scene {
            depth_output: 0,
            ..scene
        })
        .unwrap();
        let depth = "float hf_impostor_depth(vec3 p)";
        assert!(with.contains("hf_trace_impostor(Query world, uint combine)"));
        assert!(with.contains(depth) && !without.contains(depth));
        let maxmip = hf_scene { method: 3, ..scene };
        assert_eq!(text(&maxmip).unwrap_err(), HF_ERR_INVALID_ARGUMENT);
    }
}
