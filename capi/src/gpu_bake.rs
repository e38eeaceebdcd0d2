//! The GPU bakes of the safety-distance family (feature `safety`): the N-buffers, the
//! safety distances for every ray and the cylinder–cone shapes with N-buffer slopes.
//! Their compute shaders, passes and buffer sizes; the maximum mipmap's are in
//! `maxmip`.

use crate::bake::hf_bake_options;
use crate::detail::fail;
use crate::hf_result::{self, *};
use crate::{guard, ptr};
use hfcore::bake::Spec;
use hfcore::ktx2::MapKind;
use hfcore::scene::{MethodKind, RayClasses};
use std::ffi::c_char;

/// One dispatch of a GPU bake of `hf_nbuffer_bake_passes` or `hf_safety_bake_passes`,
/// a compute pass of its shader.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct hf_bake_pass {
    /// Workgroups along x and y, each 8 × 8 invocations.
    pub workgroups: [u32; 2],
    /// Its 32-byte uniform (`hf_nbuffer_pass`, `NbufferPass`: kind (0 heights, 1
    /// doubling, 2 blocks), axis, rows, row length, first element written and first
    /// element read (counted from `bind_offset`), half window, sample columns;
    /// `hf_safety_pass`, `SafetyBakePass`: kind (0 strip bounds, 1 distances), width,
    /// height, isotropic, cap, least distance, items, invocations per grid row).
    pub uniform: [u32; 8],
    /// The byte range of the buffer the pass writes that it binds (the N-buffers: at
    /// most two levels of one axis; the safety bake: all of the scratch, then all of
    /// the map): from `bind_offset` (a multiple of 256) …
    pub bind_offset: u64,
    /// … `bind_size` bytes.
    pub bind_size: u64,
}

impl From<&hfcast_shaders::bake::BakePass> for hf_bake_pass {
    fn from(p: &hfcast_shaders::bake::BakePass) -> Self {
        hf_bake_pass {
            workgroups: p.workgroups,
            uniform: p.uniform,
            bind_offset: p.bind_offset,
            bind_size: p.bind_size,
        }
    }
}

/// Writes `passes` to `out` and their count to `count`, or `HF_ERR_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `out` is NULL (an error) or valid for writing `out_len` passes; `count` NULL (an
/// error) or valid for writing one `uint32_t`.
unsafe fn write_passes(
    passes: &[hf_bake_pass],
    out: *mut hf_bake_pass,
    out_len: usize,
    count: *mut u32,
) -> Result<(), hf_result> {
    // SAFETY: the caller promises `out` is writable for its length.
    let out = unsafe { ptr::slice_mut(out, out_len) }?;
    let count = ptr::out(count)?;
    if out.len() < passes.len() {
        return Err(HF_ERR_BUFFER_TOO_SMALL);
    }
    out[..passes.len()].copy_from_slice(passes);
    // SAFETY: the caller promises `count` is writable.
    unsafe { count.set(passes.len() as u32) };
    Ok(())
}

/// The passes of the GPU bake of `method`'s map of a `width × height` field with
/// `options` (checked as `hf_bake` checks them) into `out` (passes, their room, the
/// count): `serves` says whether the GPU bake computes that map (else
/// `HF_ERR_INVALID_ARGUMENT` with the detail `why`), `passes` makes them (`None`: the
/// size is too large for the shader).
///
/// # Safety
/// `options` is NULL or valid for reading one `hf_bake_options`; the outputs as
/// `write_passes` takes them.
unsafe fn map_passes(
    method: MethodKind,
    (width, height): (u32, u32),
    options: *const hf_bake_options,
    (serves, why): (impl Fn(&Spec) -> bool, &str),
    passes: impl Fn(&Spec) -> Option<Vec<hfcast_shaders::bake::BakePass>>,
    (out, out_len, count): (*mut hf_bake_pass, usize, *mut u32),
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `options` is NULL or readable.
        let checked = unsafe { crate::bake::checked(method as u32, width, height, options) }?;
        let spec = checked.spec.ok_or(HF_ERR_INVALID_ARGUMENT)?;
        if !serves(&spec) {
            return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
        }
        let passes = passes(&spec).ok_or(HF_ERR_INVALID_SIZE)?;
        let passes: Vec<hf_bake_pass> = passes.iter().map(hf_bake_pass::from).collect();
        // SAFETY: the caller's promises, passed on.
        unsafe { write_passes(&passes, out, out_len, count) }
    })
}

/// The cone reach as the core takes it.
fn cap_of(cap: u32) -> Result<u8, hf_result> {
    u8::try_from(cap).map_err(|_| fail(HF_ERR_INVALID_ARGUMENT, "cap: must be 0 to 255"))
}

/// The passes of a `width × height` field and reach `cap`, checked.
fn passes(width: u32, height: u32, cap: u32) -> Result<Vec<hf_bake_pass>, hf_result> {
    let passes = hfcast_shaders::bake::nbuffer_bake_passes(width, height, cap_of(cap)?)
        .ok_or(HF_ERR_INVALID_SIZE)?;
    Ok(passes.iter().map(hf_bake_pass::from).collect())
}

/// Writes the floats of the N-buffers of a `width × height` field for the cone reach
/// `cap` (the `hf_bake_options.cap` of `HF_METHOD_CC`) to `*out_len`: the size of the
/// storage buffer the GPU bake fills, and the last part of `hf_bake_prepare`'s scratch
/// for `HF_METHOD_CC` (after the strip bounds), in the same layout.
/// `HF_ERR_INVALID_SIZE` for a size no field has, `HF_ERR_INVALID_ARGUMENT` for a cap
/// over 255. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_nbuffer_len(
    width: u32,
    height: u32,
    cap: u32,
    out_len: *mut usize,
) -> hf_result {
    guard(|| {
        let out = ptr::out(out_len)?;
        let cap = cap_of(cap)?;
        let side = |n: u32| (2..=hfcore::field::MAX_SIDE).contains(&n);
        if !side(width) || !side(height) {
            return Err(HF_ERR_INVALID_SIZE);
        }
        // SAFETY: the caller promises `out_len` is writable.
        unsafe { out.set(hfcore::safety::cc::nbuffer_len(width, height, cap)) };
        Ok(())
    })
}

/// Writes the length in bytes of `hf_nbuffer_bake_shader(lang)`, including its NUL
/// terminator, to `*out_len`. Errors as `hf_nbuffer_bake_shader`. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_nbuffer_bake_shader_len(lang: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise.
    unsafe {
        crate::shader::write_len(out_len, || {
            crate::shader::gpu_bake_source("bake_nbuffer", lang)
        })
    }
}

/// Writes the compute shader that fills the N-buffers on the GPU in `lang` into `buf`
/// as a NUL-terminated string and its length without the NUL to `*out_written`
/// (`buf_len` at least `hf_nbuffer_bake_shader_len`). Its entry point (WGSL
/// `nbuffer_bake_pass`, GLSL `main`) writes one pass's elements into the storage buffer
/// `hf_nbuffer` (binding 15, `float`s, `hf_nbuffer_len` of them; each pass binds
/// the byte range of its `bind_offset` and `bind_size`) from the heights texture
/// `hf_heights` (binding 0 / texture unit 0, R32F W × H) or the levels below, reading
/// its `hf_nbuffer_pass` uniform (binding 16, a uniform block in GLSL); dispatch
/// `hf_nbuffer_bake_passes` in order, each finished before the next (in OpenGL
/// `glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT)` between them). The result equals
/// the N-buffers `hf_bake_prepare` writes for `HF_METHOD_CC` byte for byte.
/// `HF_SHADER_WGSL` or `HF_SHADER_GLSL` (a whole GLSL 4.30 compute shader, its
/// `#version` line included); another value is `HF_ERR_INVALID_ENUM`. Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_nbuffer_bake_shader(
    lang: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe {
        crate::shader::write_text(buf, buf_len, out_written, || {
            crate::shader::gpu_bake_source("bake_nbuffer", lang)
        })
    }
}

/// Writes the passes of the GPU N-buffer bake of a `width × height` field for the cone
/// reach `cap` to `out_passes` and their count to `*out_count`
/// (`HF_NBUFFER_MAX_PASSES` always suffice). `HF_ERR_INVALID_SIZE` for a size no field
/// has or N-buffers of 2³² floats or more (the shader's offsets are 32-bit),
/// `HF_ERR_INVALID_ARGUMENT` for a cap over 255, `HF_ERR_BUFFER_TOO_SMALL` when
/// `out_passes_len` is below the count. Nothing is written on an error. Thread safe.
///
/// # Safety
/// `out_passes` is NULL (an error) or valid for writing `out_passes_len` passes;
/// `out_count` NULL (an error) or valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_nbuffer_bake_passes(
    width: u32,
    height: u32,
    cap: u32,
    out_passes: *mut hf_bake_pass,
    out_passes_len: usize,
    out_count: *mut u32,
) -> hf_result {
    guard(|| {
        let passes = passes(width, height, cap)?;
        // SAFETY: the caller's promises, passed on.
        unsafe { write_passes(&passes, out_passes, out_passes_len, out_count) }
    })
}

/// Writes the length in bytes of `hf_safety_bake_shader(lang)`, including its NUL
/// terminator, to `*out_len`. Errors as `hf_safety_bake_shader`. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_bake_shader_len(lang: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise.
    unsafe {
        crate::shader::write_len(out_len, || {
            crate::shader::gpu_bake_source("bake_safety", lang)
        })
    }
}

/// Writes the compute shader that bakes the safety distances for every ray on the GPU
/// in `lang` into `buf` as a NUL-terminated string and its length without the NUL to
/// `*out_written` (`buf_len` at least `hf_safety_bake_shader_len`). It computes in
/// 64-bit floats, as the CPU bake: the device needs them (wgpu `SHADER_F64`, Vulkan
/// `shaderFloat64`; OpenGL 4.0 has doubles). Its entry point (WGSL `safety_bake_pass`,
/// GLSL `main`) reads the heights texture `hf_heights` (binding 0 / texture unit 0,
/// R32F W × H) and its `hf_safety_pass` uniform (binding 19, a uniform block in GLSL);
/// the first pass writes the strip bounds into the storage buffer `hf_safety_scratch`
/// (binding 17, `float`s, as many as `hf_bake_scratch_len` of `HF_METHOD_SAFETY`), the
/// second reads them and writes the map into `hf_safety_out` (binding 18, `uint`s: the
/// map's bytes four to a word, little-endian). Dispatch `hf_safety_bake_passes` in
/// order, the first finished before the second (`glMemoryBarrier` in OpenGL). The
/// bytes equal the texels of `hf_bake`'s map of `HF_METHOD_SAFETY` (without its
/// descriptor). `HF_SHADER_WGSL` or `HF_SHADER_GLSL` (a whole GLSL 4.30 compute
/// shader, its `#version` line included); another value is `HF_ERR_INVALID_ENUM`.
/// Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_bake_shader(
    lang: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe {
        crate::shader::write_text(buf, buf_len, out_written, || {
            crate::shader::gpu_bake_source("bake_safety", lang)
        })
    }
}

/// Writes the two passes of the GPU safety-distance bake of a `width × height` field
/// with `options` (NULL: the defaults of `HF_METHOD_SAFETY`; checked as `hf_bake`
/// checks them) to `out_passes` (`out_passes_len` at least 2) and their count to
/// `*out_count`. The GPU bake serves every ray of every class: `ray_classes` must be 0
/// or `HF_RAYS_ALL`, `exterior` 0 and `max_view_angle_deg` 0, else
/// `HF_ERR_INVALID_ARGUMENT` (bake those maps with `hf_bake`). `variant`, `positive`
/// and `cap` are honoured. `HF_ERR_INVALID_SIZE` for a size no field has, or a map of
/// 2³² bytes or more; `HF_ERR_BUFFER_TOO_SMALL` for room for fewer than 2 passes.
/// Nothing is written on an error. Thread safe.
///
/// # Safety
/// `options` is NULL or valid for reading one `hf_bake_options`; `out_passes` NULL (an
/// error) or valid for writing `out_passes_len` passes; `out_count` NULL (an error) or
/// valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_safety_bake_passes(
    width: u32,
    height: u32,
    options: *const hf_bake_options,
    out_passes: *mut hf_bake_pass,
    out_passes_len: usize,
    out_count: *mut u32,
) -> hf_result {
    let serves = |spec: &Spec| spec.desc.classes == RayClasses::ALL && spec.desc.rays.is_all();
    let passes = |spec: &Spec| {
        let isotropic = spec.desc.map == MapKind::SafetyIsotropic;
        hfcast_shaders::bake::safety_bake_passes(
            width,
            height,
            isotropic,
            spec.desc.cap,
            spec.positive,
        )
    };
    let why = "options: the GPU safety bake serves every ray of every class (ray_classes 0, exterior 0, max_view_angle_deg 0)";
    let out = (out_passes, out_passes_len, out_count);
    // SAFETY: the caller's promises, passed on.
    unsafe {
        map_passes(
            MethodKind::Safety,
            (width, height),
            options,
            (serves, why),
            passes,
            out,
        )
    }
}

/// Most passes `hf_nbuffer_bake_passes` writes: per axis, the two level-0 passes and
/// one per level above (at most 10 levels).
pub const HF_NBUFFER_MAX_PASSES: u32 = 22;

/// The cylinder–cone bake's source in `lang`.
fn cc_source(lang: u32) -> Result<String, hf_result> {
    let lang = match lang {
        crate::shader::HF_SHADER_GLSL => hfcast_shaders::Lang::Glsl,
        crate::shader::HF_SHADER_WGSL => hfcast_shaders::Lang::Wgsl,
        _ => return Err(HF_ERR_INVALID_ENUM),
    };
    hfcast_shaders::bake::cc_bake_source(lang).ok_or(HF_ERR_NOT_BUILT)
}

/// Writes the length in bytes of `hf_cc_bake_shader(lang)`, including its NUL
/// terminator, to `*out_len`. Errors as `hf_cc_bake_shader`. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_bake_shader_len(lang: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise.
    unsafe { crate::shader::write_len(out_len, || cc_source(lang)) }
}

/// Writes the compute shader that bakes the cylinder–cone shapes with N-buffer slopes
/// (`HF_CC_SLOPE_NBUFFER`) for every ray on the GPU in `lang` into `buf` as a
/// NUL-terminated string and its length without the NUL to `*out_written` (`buf_len`
/// at least `hf_cc_bake_shader_len`): the shader of `hf_safety_bake_shader` with the
/// entry point `cc_bake_pass` (WGSL), or with `HF_CC_BAKE` defined, which makes that
/// entry `main` (GLSL). 64-bit floats, as that bake. Its bindings are those of
/// `hf_safety_bake_shader`, plus the N-buffers `hf_nbuffer` (binding 15, read-only,
/// bound whole), filled first by the passes of `hf_nbuffer_bake_passes` for the same
/// cap. Dispatch `hf_cc_bake_passes` in order after those: the strip bounds, then the
/// map, `[r, s]` per texel and class, two to a word of `hf_safety_out`. The bytes
/// equal the texels of `hf_bake`'s map of `HF_METHOD_CC` with the N-buffer slope.
/// `HF_SHADER_WGSL` or `HF_SHADER_GLSL`; another value is `HF_ERR_INVALID_ENUM`.
/// Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_bake_shader(
    lang: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe { crate::shader::write_text(buf, buf_len, out_written, || cc_source(lang)) }
}

/// Writes the two passes of the GPU cylinder–cone bake of a `width × height` field
/// with `options` (NULL: the defaults of `HF_METHOD_CC`, whose slope is exact: an
/// error here; checked as `hf_bake` checks them) to `out_passes` (`out_passes_len` at
/// least 2) and their count to `*out_count`. The GPU bake computes N-buffer slopes for
/// every ray of every class: `slope` must be `HF_CC_SLOPE_NBUFFER`, `ray_classes` 0 or
/// `HF_RAYS_ALL`, `exterior` 0 and `max_view_angle_deg` 0, else
/// `HF_ERR_INVALID_ARGUMENT` (bake the others with `hf_bake`). `HF_ERR_INVALID_SIZE`
/// for a size no field has, or a map or N-buffers of 2³² bytes or floats or more;
/// `HF_ERR_BUFFER_TOO_SMALL` for room for fewer than 2 passes. Nothing is written on
/// an error. Thread safe.
///
/// # Safety
/// `options` is NULL or valid for reading one `hf_bake_options`; `out_passes` NULL (an
/// error) or valid for writing `out_passes_len` passes; `out_count` NULL (an error) or
/// valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_cc_bake_passes(
    width: u32,
    height: u32,
    options: *const hf_bake_options,
    out_passes: *mut hf_bake_pass,
    out_passes_len: usize,
    out_count: *mut u32,
) -> hf_result {
    let serves = |spec: &Spec| {
        spec.nbuffer_slope && spec.desc.classes == RayClasses::ALL && spec.desc.rays.is_all()
    };
    let passes = |spec: &Spec| hfcast_shaders::bake::cc_bake_passes(width, height, spec.desc.cap);
    let why = "options: the GPU cylinder-cone bake computes N-buffer slopes (slope HF_CC_SLOPE_NBUFFER) for every ray of every class (ray_classes 0, exterior 0, max_view_angle_deg 0)";
    let out = (out_passes, out_passes_len, out_count);
    // SAFETY: the caller's promises, passed on.
    unsafe {
        map_passes(
            MethodKind::Cc,
            (width, height),
            options,
            (serves, why),
            passes,
            out,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn safety_passes_need_every_ray() {
        let mut n = 0u32;
        let mut out = [hf_bake_pass::default(); 2];
        let ok = |o: &hf_bake_options, out: &mut [hf_bake_pass; 2], n: &mut u32| unsafe {
            hf_safety_bake_passes(13, 6, o, out.as_mut_ptr(), 2, n)
        };
        let mut o = hf_bake_options::default_for(MethodKind::Safety);
        assert_eq!(ok(&o, &mut out, &mut n), HF_OK);
        assert_eq!((n, out[1].uniform[3], out[1].uniform[4]), (2, 0, 255));
        o.exterior = 1;
        assert_eq!(ok(&o, &mut out, &mut n), HF_ERR_INVALID_ARGUMENT);
        o.exterior = 0;
        o.ray_classes = 1;
        assert_eq!(ok(&o, &mut out, &mut n), HF_ERR_INVALID_ARGUMENT);
        o.ray_classes = 15;
        o.variant = 1;
        o.cap = 7;
        assert_eq!(ok(&o, &mut out, &mut n), HF_OK);
        assert_eq!((out[1].uniform[3], out[1].uniform[4]), (1, 7));
    }

    #[test]
    fn max_passes_bound_every_cap() {
        for cap in 0..=255 {
            let n = passes(5, 3, cap).unwrap().len();
            assert!(n as u32 <= HF_NBUFFER_MAX_PASSES, "cap {cap}: {n}");
        }
        assert_eq!(
            passes(5, 3, 255).unwrap().len() as u32,
            HF_NBUFFER_MAX_PASSES
        );
        assert_eq!(passes(5, 3, 256), Err(HF_ERR_INVALID_ARGUMENT));
        assert_eq!(passes(1, 3, 6), Err(HF_ERR_INVALID_SIZE));
    }
}
