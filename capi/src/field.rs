//! `hf_field`: a height field that owns a copy of its samples.

use crate::hf_result::{self, *};
use crate::{guard, ptr};
use core::ptr::NonNull;
use hfcore::field::MAX_SIDE;
use hfcore::mapdesc;
use hfcore::{HeightField, TransformError, WorldTransform};
use std::collections::VecDeque;

/// A height field: W × H heights in grid units, owned by the library (the constructors
/// copy the caller's samples, so the caller's buffer may be freed at once). Sample
/// (i, j) sits at grid point (x = i, y = j); the surface covers [0, W−1] × [0, H−1].
///
/// A field may carry an [`hf_transform`] (`hf_field_set_transform`): then every
/// trace (`hf_trace`, `hf_trace_batch`) takes rays and returns hits in world units.
///
/// Thread safety, a readers–writer protocol: functions taking a `const hf_field *`
/// (traces, bakes, size and info queries) only read it and may run concurrently from
/// any number of threads, on the field and on the maps baked from it;
/// `hf_field_update_rect`, `hf_field_set_transform` and `hf_field_destroy` need
/// exclusive access to the field, and `hf_maxmip_update_rect` (like any bake into a
/// buffer) exclusive access to the pyramid it refreshes. A program that changes a
/// field other threads trace holds a lock in write mode around the change and the map
/// refreshes, and in read mode around each trace (`c_tests/test_concurrency.c` does
/// so with a `pthread_rwlock_t`). Nothing detects a broken protocol: a trace racing
/// an update is a data race (undefined behaviour; in practice an answer from a mix of
/// old and new heights).
pub struct hf_field {
    /// The samples (W × H, stride W), allocated by `Box<[f32]>` and freed on drop.
    samples: NonNull<[f32]>,
    /// The validated view over `samples`; `'static` stands for "until this handle is
    /// dropped": it never leaves the handle with that lifetime.
    view: HeightField<'static>,
    /// `hfcore::mapdesc::fingerprint` of the samples, kept current by `update_rect`.
    fingerprint: u64,
    /// Updates of a non-empty rectangle so far.
    generation: u64,
    /// The last [`HISTORY`] updates, oldest first.
    history: VecDeque<Update>,
}

/// Updates a field remembers, so that a map refresh can tell whether its rectangle
/// covers every update since the map's bake (`hf_maxmip_update_rect`).
pub(crate) const HISTORY: usize = 16;

/// One `hf_field_update_rect`: its rectangle and the fingerprint before it (only
/// read by the map checks, which a build without methods leaves out).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(feature = "maxmip"), allow(dead_code))]
pub(crate) struct Update {
    /// `[x0, y0, x1, y1]`, sample indices, half-open.
    pub rect: [u32; 4],
    /// The field's fingerprint before the update.
    pub before: u64,
    /// The generation the update made.
    pub generation: u64,
}

impl hf_field {
    /// Takes ownership of `samples` (W × H, stride W), validating them.
    fn new(samples: Vec<f32>, width: u32, height: u32) -> Result<hf_field, hf_result> {
        let samples = NonNull::from(Box::leak(samples.into_boxed_slice()));
        // SAFETY: `samples` is a live allocation we own; it is only written by
        // `update_rect`, which replaces `view` right after, and freed in `drop`.
        let shared: &'static [f32] = unsafe { samples.as_ref() };
        match HeightField::new(shared, width, height, width as usize) {
            Ok(view) => Ok(hf_field {
                samples,
                view,
                fingerprint: mapdesc::fingerprint(shared),
                generation: 0,
                history: VecDeque::new(),
            }),
            Err(e) => {
                // SAFETY: from `Box::leak` above; `shared` is not used again.
                drop(unsafe { Box::from_raw(samples.as_ptr()) });
                Err(e.into())
            }
        }
    }

    /// The validated view, borrowed from the handle.
    pub fn view(&self) -> &HeightField<'_> {
        &self.view
    }

    /// The fingerprint of the current heights (what maps' descriptors must name).
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }

    /// Updates of a non-empty rectangle so far.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The remembered updates since the heights had fingerprint `fp` (the newest
    /// stretch that starts there), or `None` when none starts there.
    pub(crate) fn updates_since(&self, fp: u64) -> Option<&[Update]> {
        // `remember` keeps the deque contiguous, so the first slice is all of it.
        let all = self.history.as_slices().0;
        debug_assert_eq!(all.len(), self.history.len());
        let k = all.iter().rposition(|u| u.before == fp)?;
        Some(&all[k..])
    }

    /// Records an update of `rect` that changed the fingerprint from `before`.
    fn remember(&mut self, rect: [u32; 4], before: u64) {
        self.generation += 1;
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(Update {
            rect,
            before,
            generation: self.generation,
        });
        self.history.make_contiguous();
    }
}

impl Drop for hf_field {
    fn drop(&mut self) {
        // SAFETY: `samples` came from `Box::leak` in `new` and is freed only here.
        drop(unsafe { Box::from_raw(self.samples.as_ptr()) });
    }
}

/// Width, height and height bounds of a field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hf_field_info {
    /// Samples along x (W ≥ 2).
    pub width: u32,
    /// Samples along y (H ≥ 2).
    pub height: u32,
    /// Lowest height (grid units); after `hf_field_update_rect` a lower bound.
    pub min_height: f32,
    /// Highest height (grid units); after `hf_field_update_rect` an upper bound.
    pub max_height: f32,
}

/// Where a field's grid sits in world units: `world = (origin[0] + spacing[0]·x,
/// origin[1] + spacing[1]·y, height_offset + height_scale·z)` for grid point (x, y, z)
/// (x = sample column, y = sample row, z = height in grid units). A world ray
/// `o + t·d` is traced as the grid ray `(o − offset)/scale + t·d/scale`: `t`, `t_min`
/// and `t_max` mean the same in both frames. Hit points come back in world units,
/// normals by the inverse transpose (unit length), clearances times `height_scale`;
/// `cell` stays the grid cell. The conversion runs in double precision; keep `origin`
/// near the scene (float world coordinates far from it carry their own rounding).
/// The identity (origin 0, spacing 1, height scale 1, offset 0) is the default and
/// changes no bit of any answer.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_transform {
    /// World (x, y) of sample (0, 0).
    pub origin: [f64; 2],
    /// World units between neighbouring samples along x and y: non-zero (negative
    /// flips the axis, e.g. a north-up raster's rows).
    pub spacing: [f64; 2],
    /// World height units per grid height unit: positive.
    pub height_scale: f64,
    /// World height of grid height 0.
    pub height_offset: f64,
}

impl From<WorldTransform> for hf_transform {
    fn from(t: WorldTransform) -> Self {
        hf_transform {
            origin: t.origin(),
            spacing: t.spacing(),
            height_scale: t.height_scale(),
            height_offset: t.height_offset(),
        }
    }
}

impl From<TransformError> for hf_result {
    fn from(e: TransformError) -> Self {
        match e {
            TransformError::NotFinite => HF_ERR_NOT_FINITE,
            TransformError::ZeroSpacing | TransformError::HeightScaleNotPositive => {
                HF_ERR_INVALID_ARGUMENT
            }
        }
    }
}

/// Checks the size arguments of a constructor and returns (samples needed in the input,
/// W × H).
fn sizes(width: u32, height: u32, stride: usize) -> Result<(usize, usize), hf_result> {
    if !(2..=MAX_SIDE).contains(&width) || !(2..=MAX_SIDE).contains(&height) {
        return Err(HF_ERR_INVALID_SIZE);
    }
    if stride < width as usize {
        return Err(HF_ERR_INVALID_SIZE);
    }
    let needed = stride
        .checked_mul(height as usize - 1)
        .and_then(|n| n.checked_add(width as usize))
        .ok_or(HF_ERR_INVALID_SIZE)?;
    let count = (width as usize)
        .checked_mul(height as usize)
        .filter(|&n| n <= isize::MAX as usize / 4)
        .ok_or(HF_ERR_INVALID_SIZE)?;
    Ok((needed, count))
}

/// A zeroed vector of `n` floats, or `HF_ERR_OUT_OF_MEMORY`.
fn alloc(n: usize) -> Result<Vec<f32>, hf_result> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| HF_ERR_OUT_OF_MEMORY)?;
    v.resize(n, 0.0);
    Ok(v)
}

/// Shared body of the constructors: checks, copies/converts, validates, boxes.
///
/// # Safety
/// As the constructors: `samples` valid for `samples_len` elements, `out_field` for one
/// pointer.
unsafe fn create<S: Copy>(
    samples: *const S,
    samples_len: usize,
    width: u32,
    height: u32,
    stride: usize,
    out_field: *mut *mut hf_field,
    convert: impl FnOnce(&[S], &mut [f32]) -> Result<(), hfcore::FieldError>,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `samples` is valid for `samples_len` elements.
        let samples = unsafe { ptr::slice(samples, samples_len) }?;
        let out = ptr::out(out_field)?;
        let (needed, count) = sizes(width, height, stride)?;
        if samples.len() < needed {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        let mut heights = alloc(count)?;
        convert(samples, &mut heights)?;
        let field = Box::new(hf_field::new(heights, width, height)?);
        // SAFETY: the caller promises `out_field` is valid for one pointer.
        unsafe { out.set(Box::into_raw(field)) };
        Ok(())
    })
}

/// Creates a field from `float` heights in grid units (one grid unit = one sample
/// spacing): sample (i, j) is `heights[j * stride + i]`, for i < `width`, j < `height`.
/// The samples are copied. `heights_len` is the number of floats readable at
/// `heights`, at least `stride * (height - 1) + width`. Every height must be finite
/// (`HF_ERR_NOT_FINITE` otherwise). Sizes: 2 ≤ width, height ≤ `HF_MAX_SIDE`,
/// stride ≥ width. On success `*out_field` receives a handle to free with
/// `hf_field_destroy`. Thread safe.
///
/// # Safety
/// `heights` is NULL (an error) or valid for reading `heights_len` floats;
/// `out_field` is NULL (an error) or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn hf_field_create_f32(
    heights: *const f32,
    heights_len: usize,
    width: u32,
    height: u32,
    stride: usize,
    out_field: *mut *mut hf_field,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        create(
            heights,
            heights_len,
            width,
            height,
            stride,
            out_field,
            |s, out| {
                let w = width as usize;
                for (j, row) in out.chunks_exact_mut(w).enumerate() {
                    row.copy_from_slice(&s[j * stride..j * stride + w]);
                }
                Ok(())
            },
        )
    }
}

/// Creates a field from 8-bit samples: height = `sample / 255 * depth` grid units (the
/// core's `HeightField::from_u8`). Layout and sizes as `hf_field_create_f32`; `depth`
/// must be finite. Thread safe.
///
/// # Safety
/// `samples` is NULL (an error) or valid for reading `samples_len` bytes; `out_field`
/// is NULL (an error) or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn hf_field_create_u8(
    samples: *const u8,
    samples_len: usize,
    width: u32,
    height: u32,
    stride: usize,
    depth: f32,
    out_field: *mut *mut hf_field,
) -> hf_result {
    if !depth.is_finite() {
        return HF_ERR_NOT_FINITE;
    }
    // SAFETY: the caller's promises, passed on.
    unsafe {
        create(
            samples,
            samples_len,
            width,
            height,
            stride,
            out_field,
            |s, out| HeightField::from_u8(s, width, height, stride, depth, out).map(|_| ()),
        )
    }
}

/// Creates a field from 16-bit samples: height = `sample / 65535 * depth` grid units
/// (the core's `HeightField::from_u16`, the convention of the PNG maps in
/// `shared/data`). Layout and sizes as `hf_field_create_f32` (`samples_len` counts
/// `uint16_t` elements); `depth` must be finite. Thread safe.
///
/// # Safety
/// `samples` is NULL (an error) or valid for reading `samples_len` `uint16_t`s;
/// `out_field` is NULL (an error) or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn hf_field_create_u16(
    samples: *const u16,
    samples_len: usize,
    width: u32,
    height: u32,
    stride: usize,
    depth: f32,
    out_field: *mut *mut hf_field,
) -> hf_result {
    if !depth.is_finite() {
        return HF_ERR_NOT_FINITE;
    }
    // SAFETY: the caller's promises, passed on.
    unsafe {
        create(
            samples,
            samples_len,
            width,
            height,
            stride,
            out_field,
            |s, out| HeightField::from_u16(s, width, height, stride, depth, out).map(|_| ()),
        )
    }
}

/// Frees a field. NULL is allowed and does nothing. Needs exclusive access to the
/// field: no other thread may be using it (nor use it afterwards).
///
/// # Safety
/// `field` is NULL or a handle from an `hf_field_create_*` function not yet destroyed.
#[no_mangle]
pub unsafe extern "C" fn hf_field_destroy(field: *mut hf_field) {
    if field.is_null() {
        return;
    }
    let _ = guard(|| {
        // SAFETY: the caller promises a live handle from `Box::into_raw`.
        drop(unsafe { Box::from_raw(field) });
        Ok(())
    });
}

/// Writes the field's width, height and height bounds to `*out_info`. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_info` is NULL (an error) or valid
/// for writing one `hf_field_info`.
#[no_mangle]
pub unsafe extern "C" fn hf_field_get_info(
    field: *const hf_field,
    out_info: *mut hf_field_info,
) -> hf_result {
    let info = |f: &hf_field| {
        let v = f.view();
        Ok(hf_field_info {
            width: v.width(),
            height: v.height(),
            min_height: v.min_height(),
            max_height: v.max_height(),
        })
    };
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| ptr::get(field), out_info, info) }
}

/// Copies the field's W × H heights (grid units, row-major, stride W: what to upload
/// as the `R32F` height texture of the GLSL ports) into `out_heights`, which holds
/// `out_heights_len ≥ W * H` floats. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_heights` is NULL (an error) or
/// valid for writing `out_heights_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_field_copy_heights(
    field: *const hf_field,
    out_heights: *mut f32,
    out_heights_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle.
        let f = unsafe { ptr::get(field) }?;
        // SAFETY: the caller promises `out_heights` is writable for its length.
        let out = unsafe { ptr::slice_mut(out_heights, out_heights_len) }?;
        let s = f.view().samples();
        if out.len() < s.len() {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        out[..s.len()].copy_from_slice(s);
        Ok(())
    })
}

/// Checks a rectangle of samples `[x0, y0, x1, y1]` (half-open) given to an update:
/// `HF_ERR_INVALID_RECT` when reversed or outside `hf`; `false` when empty (the
/// update is then `HF_OK` and changes nothing).
pub(crate) fn rect_in(hf: &HeightField, [x0, y0, x1, y1]: [u32; 4]) -> Result<bool, hf_result> {
    if x0 > x1 || y0 > y1 || x1 > hf.width() || y1 > hf.height() {
        return Err(crate::detail::fail(
            HF_ERR_INVALID_RECT,
            format_args!(
                "[{x0}, {x1}) x [{y0}, {y1}) is reversed or outside the {} x {} field",
                hf.width(),
                hf.height()
            ),
        ));
    }
    Ok(x0 < x1 && y0 < y1)
}

/// Replaces the samples in the rectangle `[x0, x1) × [y0, y1)` (sample indices) by
/// `values`: sample (x0 + i, y0 + j) becomes `values[j * values_stride + i]`.
/// `values_len` is the number of floats readable at `values`, at least
/// `values_stride * (y1 - y0 - 1) + (x1 - x0)`; `values_stride ≥ x1 − x0`. Only the
/// rectangle is re-validated (every value must be finite; the height bounds widen to
/// cover them and never shrink). Then refresh a baked pyramid with
/// `hf_maxmip_update_rect` on the same rectangle. An empty rectangle (x0 = x1 or
/// y0 = y1, inside the field) is `HF_OK` and changes nothing, as for
/// `hf_maxmip_update_rect` (`values` must still be non-NULL); a reversed one or one
/// outside the field is `HF_ERR_INVALID_RECT`. On error the field is unchanged.
/// Needs exclusive access to the field.
///
/// # Safety
/// `field` is NULL (an error) or a live handle not used by another thread during the
/// call; `values` is NULL (an error) or valid for reading `values_len` floats.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_field_update_rect(
    field: *mut hf_field,
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    values: *const f32,
    values_len: usize,
    values_stride: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle used by no one else meanwhile.
        let f = unsafe { ptr::get_mut(field) }?;
        // SAFETY: the caller promises `values` is readable for its length.
        let values = unsafe { ptr::slice(values, values_len) }?;
        let old = f.view;
        if !rect_in(&old, [x0, y0, x1, y1])? {
            return Ok(());
        }
        let (cols, rows) = ((x1 - x0) as usize, (y1 - y0) as usize);
        if values_stride < cols {
            return Err(HF_ERR_INVALID_SIZE);
        }
        let needed = values_stride
            .checked_mul(rows - 1)
            .and_then(|n| n.checked_add(cols))
            .ok_or(HF_ERR_INVALID_SIZE)?;
        if values.len() < needed {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        let row = |j: usize| &values[j * values_stride..j * values_stride + cols];
        if !(0..rows).all(|j| row(j).iter().all(|v| v.is_finite())) {
            return Err(HF_ERR_NOT_FINITE);
        }
        let w = old.width() as usize;
        let before = f.fingerprint;
        let mut fp = before;
        {
            // SAFETY: we own the allocation and hold `&mut hf_field`; `f.view`'s shared
            // slice is not used again before it is replaced below (`old` only lends its
            // width, height and bounds to `revalidate_rect`).
            let samples = unsafe { f.samples.as_mut() };
            for j in 0..rows {
                let start = (y0 as usize + j) * w + x0 as usize;
                let dst = &mut samples[start..start + cols];
                for (i, (d, &v)) in dst.iter_mut().zip(row(j)).enumerate() {
                    fp = fp
                        .wrapping_sub(mapdesc::sample_term(start + i, *d))
                        .wrapping_add(mapdesc::sample_term(start + i, v));
                    *d = v;
                }
            }
        }

        // SAFETY: the allocation is live until drop; the mutable borrow above ended.
        let shared: &'static [f32] = unsafe { f.samples.as_ref() };
        f.view = old.revalidate_rect(shared, x0, y0, x1, y1)?;
        f.fingerprint = fp;
        f.remember([x0, y0, x1, y1], before);
        Ok(())
    })
}

/// Places the field in world units (see [`hf_transform`]); from then on every
/// `hf_trace` call on it takes world rays and returns world hits. Bakes and baked
/// maps are unaffected (they live in grid space). `HF_ERR_NOT_FINITE` for a NaN or
/// infinite component, `HF_ERR_INVALID_ARGUMENT` for a zero spacing or a height scale
/// that is not positive; on error the field keeps its transform. Needs exclusive
/// access to the field.
///
/// # Safety
/// `field` is NULL (an error) or a live handle not used by another thread during the
/// call; `transform` is NULL (an error) or valid for reading one `hf_transform`.
#[no_mangle]
pub unsafe extern "C" fn hf_field_set_transform(
    field: *mut hf_field,
    transform: *const hf_transform,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle used by no one else meanwhile.
        let f = unsafe { ptr::get_mut(field) }?;
        // SAFETY: the caller promises a readable transform.
        let t = unsafe { ptr::get(transform) }?;
        let xf = WorldTransform::new(t.origin, t.spacing, t.height_scale, t.height_offset)?;
        f.view = f.view.with_transform(xf);
        Ok(())
    })
}

/// Writes the field's transform (the identity unless `hf_field_set_transform` set
/// one) to `*out_transform`. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_transform` is NULL (an error) or
/// valid for writing one `hf_transform`.
#[no_mangle]
pub unsafe extern "C" fn hf_field_get_transform(
    field: *const hf_field,
    out_transform: *mut hf_transform,
) -> hf_result {
    let transform = |f: &hf_field| Ok(hf_transform::from(*f.view().transform()));
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| ptr::get(field), out_transform, transform) }
}
