//! The N-buffers of the cylinder–cone bake on the GPU: the compute shader, its passes
//! and the buffer size (the CPU fills them in `hf_bake_prepare`).

use crate::detail::fail;
use crate::guard;
use crate::hf_result::{self, *};
use crate::ptr;
use std::ffi::c_char;

/// One dispatch of the GPU N-buffer bake (`hf_nbuffer_bake_passes`), a compute pass of
/// the shader of `hf_nbuffer_bake_shader`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct hf_nbuffer_pass {
    /// Workgroups along x (along a row of samples) and y (across rows), each 8 × 8.
    pub workgroups: [u32; 2],
    /// Its uniform `hf_nbuffer_pass` (`NbufferPass`, 32 bytes): kind (0 heights, 1
    /// doubling, 2 blocks), axis, rows, row length, first element written and first
    /// element read (counted from `bind_offset`), half window, sample columns.
    pub uniform: [u32; 8],
    /// The byte range of the N-buffer storage buffer the pass binds as
    /// `hf_nbuffer_out`: from `bind_offset` (a multiple of 256) …
    pub bind_offset: u64,
    /// … `bind_size` bytes (at most two levels of one axis).
    pub bind_size: u64,
}

/// The cone reach as the core takes it.
fn cap_of(cap: u32) -> Result<u8, hf_result> {
    u8::try_from(cap).map_err(|_| fail(HF_ERR_INVALID_ARGUMENT, "cap: must be 0 to 255"))
}

/// The passes of a `width × height` field and reach `cap`, checked.
fn passes(width: u32, height: u32, cap: u32) -> Result<Vec<hf_nbuffer_pass>, hf_result> {
    let passes = hfcast_shaders::bake::nbuffer_bake_passes(width, height, cap_of(cap)?)
        .ok_or(HF_ERR_INVALID_SIZE)?;
    Ok(passes
        .iter()
        .map(|p| hf_nbuffer_pass {
            workgroups: p.workgroups,
            uniform: p.uniform,
            bind_offset: p.bind_offset,
            bind_size: p.bind_size,
        })
        .collect())
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
/// `hf_nbuffer_out` (binding 15, `float`s, `hf_nbuffer_len` of them; each pass binds
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
    out_passes: *mut hf_nbuffer_pass,
    out_passes_len: usize,
    out_count: *mut u32,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `out_passes` is writable for its length.
        let out = unsafe { ptr::slice_mut(out_passes, out_passes_len) }?;
        let count = ptr::out(out_count)?;
        let passes = passes(width, height, cap)?;
        if out.len() < passes.len() {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        out[..passes.len()].copy_from_slice(&passes);
        // SAFETY: the caller promises `out_count` is writable.
        unsafe { count.set(passes.len() as u32) };
        Ok(())
    })
}

/// Most passes `hf_nbuffer_bake_passes` writes: per axis, the two level-0 passes and
/// one per level above (at most 10 levels).
pub const HF_NBUFFER_MAX_PASSES: u32 = 22;

#[cfg(test)]
mod tests {
    use super::*;

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
