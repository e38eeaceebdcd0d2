//! Maximum mipmaps: sizes, layout, bake (whole, by rows, threaded) and update.

use crate::hf_result::{self, *};
use crate::mapdesc::{check_refresh, elems, stamp};
use crate::{guard, hf_field, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::maxmip::{self, Layout};
use hfcore::HeightField;
use std::ffi::c_char;

/// One level of a maximum-mipmap pyramid: its texels lie at
/// `pyramid[offset + j * width + i]`, row-major.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct hf_level {
    /// Texels along x (level 0: W − 1, one per cell; then halved, rounding up).
    pub width: u32,
    /// Texels along y (level 0: H − 1).
    pub height: u32,
    /// Index of the level's first texel in the pyramid buffer.
    pub offset: usize,
}

/// The layout of a `width × height` field, checked.
fn layout(width: u32, height: u32) -> Result<Layout, hf_result> {
    Layout::new(width, height).ok_or(HF_ERR_INVALID_SIZE)
}

/// Writes the pyramid levels of a `width × height` field, finest (level 0, one texel
/// per cell: the maximum of its four corners) to coarsest (1 × 1), into `out_levels`
/// (`out_levels_len ≥` the level count; `HF_MAX_LEVELS` always suffices) and their
/// count to `*out_count`. The GLSL port takes these as the uniforms
/// `hf_level_dims` / `hf_level_offset`. Thread safe.
///
/// # Safety
/// `out_levels` is NULL (an error) or valid for writing `out_levels_len` levels;
/// `out_count` NULL (an error) or valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_maxmip_levels(
    width: u32,
    height: u32,
    out_levels: *mut hf_level,
    out_levels_len: usize,
    out_count: *mut u32,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `out_levels` is writable for its length.
        let levels = unsafe { ptr::slice_mut(out_levels, out_levels_len) }?;
        let count = ptr::out(out_count)?;
        let l = layout(width, height)?;
        if levels.len() < l.levels() as usize {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        for (k, out) in levels.iter_mut().take(l.levels() as usize).enumerate() {
            let [w, h] = l.dims(k as u32);
            *out = hf_level {
                width: w,
                height: h,
                offset: l.offset(k as u32),
            };
        }
        // SAFETY: the caller promises `out_count` is writable.
        unsafe { count.set(l.levels()) };
        Ok(())
    })
}

/// The field and the pyramid as a mutable slice of at least the pyramid's length.
///
/// # Safety
/// `field` NULL or live; `pyramid` NULL or valid for `pyramid_len` floats, exclusive.
unsafe fn field_and_pyramid<'a>(
    field: *const hf_field,
    pyramid: *mut f32,
    pyramid_len: usize,
) -> Result<(&'a hf_field, &'a mut [f32], Layout), hf_result> {
    // SAFETY: the caller's promises.
    let (f, p) = unsafe { (ptr::get(field)?, ptr::slice_mut(pyramid, pyramid_len)?) };
    let l = Layout::of(f.view());
    if p.len() < l.texel_count() + elems::<f32>() {
        return Err(HF_ERR_BUFFER_TOO_SMALL);
    }
    Ok((f, p, l))
}

/// The description of the pyramid of `hf`.
fn desc_of(hf: &HeightField) -> Desc {
    Desc::new(MapKind::MaxMip, hf.width(), hf.height())
}

/// Writes the descriptor after the pyramid's texels.
fn stamp_pyramid(f: &hf_field, l: &Layout, p: &mut [f32]) {
    let n = l.texel_count();
    stamp(f, desc_of(f.view()), n, &mut p[n..]);
}

/// Bakes rows `[row_begin, row_end)` of pyramid level `level` into `pyramid` (the
/// whole pyramid buffer, `pyramid_len ≥ hf_map_len(HF_METHOD_MAXMIP, W, H)`), reading level
/// `level − 1` from the same buffer (level 0 reads the field). Levels must be baked
/// finest first; the rows of one level may be baked by several threads at once, each
/// with its own disjoint row range (this call touches only the level's rows it bakes
/// and the finer level it reads), so any job system can split the work.
/// Thread safe (reads the field only) for disjoint rows of one level.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `pyramid` is NULL (an error) or valid
/// for reading and writing `pyramid_len` floats; concurrent calls must bake disjoint
/// rows of the same level.
#[no_mangle]
pub unsafe extern "C" fn hf_maxmip_bake_rows(
    field: *const hf_field,
    level: u32,
    row_begin: u32,
    row_end: u32,
    pyramid: *mut f32,
    pyramid_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle.
        let f = unsafe { ptr::get(field) }?;
        if pyramid.is_null() {
            return Err(HF_ERR_NULL_POINTER);
        }
        let hf = f.view();
        let l = Layout::of(hf);
        if pyramid_len < l.texel_count() + elems::<f32>() {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        if level >= l.levels() {
            return Err(HF_ERR_INVALID_ARGUMENT);
        }
        let [w, h] = l.dims(level);
        if row_begin > row_end || row_end > h {
            return Err(HF_ERR_INVALID_ARGUMENT);
        }
        let finer_range = match level {
            0 => 0..0,
            _ => l.offset(level - 1)..l.offset(level),
        };
        let start = l.offset(level) + row_begin as usize * w as usize;
        let len = (row_end - row_begin) as usize * w as usize;
        // Only the finer level (read) and the rows baked (written) become slices, so
        // concurrent calls on disjoint rows never alias.
        // SAFETY: both ranges lie inside the caller's buffer (length checked), the
        // finer level is not written during this level's bake (the documented order),
        // and the rows are this call's alone (the documented contract).
        let (finer, out) = unsafe {
            (
                ptr::slice(pyramid.add(finer_range.start), finer_range.len())?,
                ptr::slice_mut(pyramid.add(start), len)?,
            )
        };
        maxmip::bake_rows(hf, level, row_begin..row_end, finer, out);
        if level + 1 == l.levels() && row_begin < row_end {
            // The top level (one texel) is baked last, by one call: it writes the
            // descriptor after the texels.
            let n = l.texel_count();
            // SAFETY: inside the caller's buffer (length checked), this call's alone.
            let slot = unsafe { ptr::slice_mut(pyramid.add(n), elems::<f32>()) }?;
            stamp(f, desc_of(hf), n, slot);
        }
        Ok(())
    })
}

/// Bakes every level, splitting the rows of levels large enough among `threads` (0:
/// one per core; capped by `par::thread_count`, a thread refused is done without).
pub(crate) fn bake_threaded(hf: &HeightField, l: &Layout, threads: u32, pyramid: &mut [f32]) {
    /// Below this many texels a level is baked on the calling thread.
    const SERIAL: usize = 1 << 14;
    for level in 0..l.levels() {
        let [w, h] = l.dims(level);
        let (finer, out) = l.split_level(pyramid, level);
        let n = match out.len() {
            n if n < SERIAL => 1,
            _ => crate::par::thread_count(threads, h),
        };
        let done = crate::par::bake_bands(h, w as usize, h.div_ceil(n), n, out, |r, chunk| {
            maxmip::bake_rows(hf, level, r, finer, chunk);
            Ok::<(), core::convert::Infallible>(())
        });
        done.unwrap_or_else(|never| match never {});
    }
}

/// Refreshes the texels of `pyramid` (baked for `field` before the change) that
/// depend on the samples `[x0, x1) × [y0, y1)`, after `hf_field_update_rect` changed
/// them; the result equals a full bake, descriptor included. `pyramid_len ≥
/// hf_map_len(HF_METHOD_MAXMIP, W, H)`. The pyramid's descriptor must name the field's heights now or
/// before updates that all lie inside the rectangle (the field remembers its last 16
/// updates): `HF_ERR_STALE_MAP` when an update since the bake lies outside it
/// (`hf_last_error_detail` names it), `HF_ERR_MAP_MISMATCH` for a pyramid of other
/// heights or older than those 16 updates (rebake it). An empty rectangle (x0 = x1 or
/// y0 = y1) is `HF_OK` and changes nothing, as for `hf_field_update_rect`; a reversed
/// one or one outside the field is `HF_ERR_INVALID_RECT`. Thread safe for distinct
/// pyramids (reads the field only); needs exclusive access to `pyramid`: no trace may
/// read it meanwhile.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `pyramid` is NULL (an error) or valid
/// for reading and writing `pyramid_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_maxmip_update_rect(
    field: *const hf_field,
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    pyramid: *mut f32,
    pyramid_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promises.
        let (f, p, l) = unsafe { field_and_pyramid(field, pyramid, pyramid_len) }?;
        let hf = f.view();
        if !crate::field::rect_in(hf, [x0, y0, x1, y1])? {
            return Ok(());
        }
        let n = l.texel_count();
        check_refresh(f, p, n, [x0, y0, x1, y1])?;
        maxmip::update_rect(hf, &mut p[..n], x0, y0, x1, y1)?;
        stamp_pyramid(f, &l, p);
        Ok(())
    })
}

/// One dispatch of the GPU maximum-mipmap bake (`hf_maxmip_bake_passes`), a compute
/// pass of `maxmip_bake_pass` in the shader of `hf_maxmip_bake_shader`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct hf_maxmip_pass {
    /// The level it writes (passes come finest first).
    pub level: u32,
    /// Workgroups along x and y (each 8 × 8 texels).
    pub workgroups: [u32; 2],
    /// Its uniform `hf_maxmip_pass` (`MaxMipPass`, 48 bytes): level, the level's first
    /// texel in the pyramid buffer, its width, the finer level's first texel, width and
    /// height, the texels written `lo` (x, y) and `hi` (x, y, exclusive), then 2 zeros.
    pub uniform: [u32; 12],
}

/// The GPU bake's source in `lang`, or why not.
fn bake_source(lang: u32) -> Result<String, hf_result> {
    crate::shader::gpu_bake_source("bake_maxmip", lang)
}

/// Writes the length in bytes of `hf_maxmip_bake_shader(lang)`, including its NUL
/// terminator, to `*out_len`. Errors as `hf_maxmip_bake_shader`. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_maxmip_bake_shader_len(lang: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise.
    unsafe { crate::shader::write_len(out_len, || bake_source(lang)) }
}

/// Writes the compute shader that bakes the maximum mipmap on the GPU in `lang` into
/// `buf` as a NUL-terminated string and its length without the NUL to
/// `*out_written` (`buf_len` at least `hf_maxmip_bake_shader_len`). Its entry point
/// (WGSL `maxmip_bake_pass`, GLSL `main`) writes one level's texels (or those an edit
/// touches) into the storage buffer `hf_pyramid_out` (binding 13, `hf_maxmip_levels`'
/// layout, `float`s) from the heights texture `hf_heights` (binding 0 / texture unit 0,
/// R32F W × H) or the finer level, reading its `hf_maxmip_pass` uniform (binding 14, a
/// uniform block in GLSL); dispatch `hf_maxmip_bake_passes` in order, each finished
/// before the next (in OpenGL `glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT)` between
/// them). The result equals `hf_bake` of `HF_METHOD_MAXMIP` (and `hf_maxmip_update` for
/// an edit) byte for byte. `HF_SHADER_WGSL` or `HF_SHADER_GLSL` (a whole GLSL 4.30
/// compute shader, its `#version` line included); another value is
/// `HF_ERR_INVALID_ENUM`. Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_maxmip_bake_shader(
    lang: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises.
    unsafe { crate::shader::write_text(buf, buf_len, out_written, || bake_source(lang)) }
}

/// Writes the passes of the GPU maximum-mipmap bake of a `width × height` field to
/// `out_passes` and their count to `*out_count`: with `rect` NULL the whole pyramid
/// (one pass per level, `hf_maxmip_levels`' count; `HF_MAX_LEVELS` passes always
/// suffice), else the refresh after the samples `[rect[0], rect[2]) × [rect[1],
/// rect[3])` changed: each level's pass over the texels that depend on them only (none
/// for an empty rectangle; `HF_ERR_INVALID_RECT` for one outside the field).
/// `HF_ERR_INVALID_SIZE` for a size no field has, or a pyramid of 2³² texels or more
/// (the shader's offsets are 32-bit). Nothing is written on an error. Thread safe.
///
/// # Safety
/// `rect` is NULL or valid for reading 4 `uint32_t`s; `out_passes` NULL (an error) or
/// valid for writing `out_passes_len` passes; `out_count` NULL (an error) or valid for
/// writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_maxmip_bake_passes(
    width: u32,
    height: u32,
    rect: *const u32,
    out_passes: *mut hf_maxmip_pass,
    out_passes_len: usize,
    out_count: *mut u32,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `out_passes` is writable for its length.
        let out = unsafe { ptr::slice_mut(out_passes, out_passes_len) }?;
        let count = ptr::out(out_count)?;
        // A size the shader cannot index (2³² texels or more) is invalid too; a valid
        // one makes `None` below a bad rectangle.
        let whole =
            hfcast_shaders::bake::maxmip_bake_passes(width, height).ok_or(HF_ERR_INVALID_SIZE)?;
        let passes = if rect.is_null() {
            whole
        } else {
            // SAFETY: the caller promises `rect` is readable for 4 words.
            let r = unsafe { ptr::slice(rect, 4) }?;
            hfcast_shaders::bake::maxmip_update_passes(width, height, [r[0], r[1], r[2], r[3]])
                .ok_or(HF_ERR_INVALID_RECT)?
        };
        if out.len() < passes.len() {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        for (o, p) in out.iter_mut().zip(&passes) {
            *o = hf_maxmip_pass {
                level: p.level,
                workgroups: p.workgroups,
                uniform: p.uniform,
            };
        }
        // SAFETY: the caller promises `out_count` is writable.
        unsafe { count.set(passes.len() as u32) };
        Ok(())
    })
}
