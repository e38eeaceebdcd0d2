//! Bakes of every method's map through one set of functions (meshoptimizer's shape:
//! size queries, caller-owned buffers): `hf_map_len`, `hf_bake_scratch_len`,
//! `hf_bake_row_count`, `hf_bake_prepare`, `hf_bake_rows` and `hf_bake`, all taking
//! the method and one `hf_bake_options`. The core's `bake::Spec` does the work.

use crate::detail::fail;
use crate::hf_result::{self, *};
use crate::mapdesc::{elems, room, stamp, Texel};
use crate::occluder::{hf_occluder, mismatch, occluders_of};
use crate::ptr::Named;
use crate::{guard, hf_field, ptr};
use hfcore::bake::{self, Spec};
use hfcore::ktx2::{DataMut, Desc, MapKind};
use hfcore::rayset::{Occluder, Rays};
use hfcore::scene::{MethodKind, RayClasses};
use hfcore::HeightField;
use std::ffi::c_void;
use std::ops::Range;

/// How a method's map is baked. Pass NULL for the method's defaults, or start from
/// `hf_bake_options_default` and change fields. Each bake reads the fields whose
/// comment names its method and ignores the others, which must still hold valid values
/// (a known variant, a class set, a cap up to 255); a non-zero `reserved` is
/// `HF_ERR_INVALID_ARGUMENT`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_bake_options {
    /// Safety distances: the layout, an `hf_safety_variant` (default directional).
    pub variant: u32,
    /// Safety distances: 1 clamps every distance to at least 1 (the paper's "strictly
    /// positive" variant: fewer fetches, **not exact**); 0 (the default): exact.
    pub positive: u32,
    /// Safety distances, cylinder–cone shapes, radii: the largest distance, cone step
    /// or radius stored, 0..=255 (defaults 255, 64, 255; smaller is conservative). The
    /// map's descriptor records it for the march.
    pub cap: u32,
    /// Cylinder–cone shapes: how the cone slope is computed, an `hf_cc_slope` (default
    /// exact).
    pub slope: u32,
    /// Safety distances, cylinder–cone shapes: the ray classes to bake (`HF_RAYS_*`
    /// bits; 0, the default: all four). A map of fewer classes is smaller and faster to
    /// bake (`hf_scene_bake_plan` gives a scene's); `hf_trace` reads the classes from
    /// the map's descriptor.
    pub ray_classes: u32,
    /// Radii: the error tolerance in grid units, finite and ≥ 0 (0, the default: the
    /// exact radius; larger gives larger radii and rays may pass under the surface by
    /// up to that depth).
    pub tolerance: f32,
    /// Threads `hf_bake` bakes on: 1 (the default) the calling thread, `n` up to `n`
    /// (at most the available cores), 0 one per available core. The map does not
    /// depend on it. The other bake functions ignore it.
    pub threads: u32,
    /// Safety distances, cylinder–cone shapes: 1 bakes for exterior rays only (rays
    /// that start outside the field's box: longer steps for them); 0 (the default):
    /// every ray. The map's descriptor records it, and `hf_trace` walks any other ray
    /// cell by cell (still exact).
    pub exterior: u32,
    /// Safety distances, cylinder–cone shapes: the largest angle, in degrees, between a
    /// ray the map serves and the downward vertical, in (0, 180] (45: the paper's
    /// φmax = −45°); 0 (the default) is 180, every direction. Recorded and guarded as
    /// `exterior`.
    pub max_view_angle_deg: f32,
    /// Safety distances, cylinder–cone shapes: how many `occluders` there are, at most
    /// `HF_MAX_OCCLUDERS` (0, the default: none).
    pub occluder_count: u32,
    /// Safety distances, cylinder–cone shapes: static occluders around the field (the
    /// solids under these triangles, `hf_occluder`): the map serves only the rays whose
    /// line passes over every one (longer steps for them), and the descriptor records
    /// the list's fingerprint. Every trace over the map must pass the same list
    /// (`hf_trace_options::occluders`); `hf_trace` walks any other ray cell by cell
    /// (still exact). NULL with a count of 0 (the default): none. Read during the
    /// call only.
    pub occluders: *const hf_occluder,
    /// Room for later options: must be 0.
    pub reserved: [u32; 4],
}

impl hf_bake_options {
    /// The defaults of `kind`'s bake.
    pub(crate) fn default_for(kind: MethodKind) -> hf_bake_options {
        hf_bake_options {
            variant: 0,
            positive: 0,
            cap: kind.info().map.map_or(0, MapKind::default_cap).into(),
            slope: 0,
            ray_classes: 0,
            tolerance: 0.0,
            threads: 1,
            exterior: 0,
            max_view_angle_deg: 0.0,
            occluder_count: 0,
            occluders: core::ptr::null(),
            reserved: [0; 4],
        }
    }
}

/// A checked bake: the core's spec and the thread count, or `None` for a method that
/// bakes no map.
pub(crate) struct Checked<'a> {
    pub(crate) spec: Option<Spec>,
    threads: u32,
    /// The options' occluders (their fingerprint is in the spec's ray set).
    occluders: &'a [Occluder],
}

/// A two-valued option (a flag or a two-variant enum): 0 or 1, else `code` with the
/// detail `options.{why}`.
fn binary(v: u32, code: hf_result, why: &str) -> Result<bool, hf_result> {
    match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(fail(code, format_args!("options.{why}"))),
    }
}

/// Checks `method`, the `width × height` size and the options (NULL: the method's
/// defaults).
///
/// # Safety
/// `options` NULL or valid for reading one `hf_bake_options`.
pub(crate) unsafe fn checked<'a>(
    method: u32,
    width: u32,
    height: u32,
    options: *const hf_bake_options,
) -> Result<Checked<'a>, hf_result> {
    let kind = crate::built_method_of(method)?;
    let o = match options.is_null() {
        true => hf_bake_options::default_for(kind),
        // SAFETY: the caller promises non-NULL options are readable.
        false => *unsafe { ptr::get(options) }.named("options")?,
    };
    if let Some(k) = o.reserved.iter().position(|&v| v != 0) {
        let why = format_args!("options.reserved[{k}]: must be 0");
        return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
    }
    let isotropic = binary(
        o.variant,
        HF_ERR_INVALID_ENUM,
        "variant: not an hf_safety_variant",
    )?;
    let nbuffer_slope = binary(o.slope, HF_ERR_INVALID_ENUM, "slope: not an hf_cc_slope")?;
    let positive = binary(
        o.positive,
        HF_ERR_INVALID_ARGUMENT,
        "positive: must be 0 or 1",
    )?;
    let cap = u8::try_from(o.cap)
        .map_err(|_| fail(HF_ERR_INVALID_ARGUMENT, "options.cap: must be 0 to 255"))?;
    let classes = match o.ray_classes {
        0 => RayClasses::ALL,
        v => crate::scene::classes_of(v)?,
    };
    let exterior = binary(
        o.exterior,
        HF_ERR_INVALID_ARGUMENT,
        "exterior: must be 0 or 1",
    )?;
    let rays = Rays {
        exterior,
        max_view_angle_deg: match o.max_view_angle_deg {
            0.0 => 180.0,
            a => a,
        },
        occluders: 0,
    }
    .validate()
    .map_err(|_| {
        let why = "options.max_view_angle_deg: must be 0 or in (0, 180]";
        fail(HF_ERR_INVALID_ARGUMENT, why)
    })?;
    // SAFETY: the caller promises the options' occluders are readable.
    let occluders = unsafe { occluders_of(o.occluders, o.occluder_count, "occluders") }?;
    let rays = rays.passing_over(occluders).map_err(mismatch)?;
    if !o.tolerance.is_finite() || o.tolerance < 0.0 {
        let why = "options.tolerance: must be finite and at least 0";
        return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
    }
    crate::check_size(width, height)?;
    let map = match kind.info().map {
        Some(MapKind::Safety) if isotropic => Some(MapKind::SafetyIsotropic),
        m => m,
    };
    let spec = map.map(|map| Spec {
        desc: Desc {
            cap,
            classes,
            tolerance: o.tolerance,
            rays,
            ..Desc::new(map, width, height)
        }
        .normalized(),
        positive,
        nbuffer_slope,
    });
    Ok(Checked {
        spec,
        threads: o.threads,
        occluders,
    })
}

impl From<bake::Error> for hf_result {
    fn from(e: bake::Error) -> Self {
        match e {
            bake::Error::Buffer(b) => b.into(),
            bake::Error::BadDesc | bake::Error::WrongField | bake::Error::WrongType => {
                HF_ERR_INVALID_ARGUMENT
            }
            bake::Error::NotBuilt(_) => HF_ERR_NOT_BUILT,
            bake::Error::Occluders(e) => mismatch(e),
        }
    }
}

/// Writes the default bake options of `method` to `*out_options` (what NULL options
/// mean for it). Thread safe.
///
/// # Safety
/// `out_options` is NULL (an error) or valid for writing one `hf_bake_options`.
#[no_mangle]
pub unsafe extern "C" fn hf_bake_options_default(
    method: u32,
    out_options: *mut hf_bake_options,
) -> hf_result {
    guard(|| {
        let kind = crate::built_method_of(method)?;
        let out = ptr::out(out_options).named("out_options")?;
        // SAFETY: the caller promises `out_options` is writable.
        unsafe { out.set(hf_bake_options::default_for(kind)) };
        Ok(())
    })
}

/// Writes the number of elements of `method`'s map of a `width × height` field baked
/// with `options` (NULL: the defaults) to `*out_len`: the size to allocate for
/// `hf_bake` and to pass to `hf_trace`. Floats for the maximum mipmap and the cone,
/// relaxed and QDM maps, bytes for the safety-distance, cylinder–cone and radius maps;
/// 0 for a method that bakes no map. The texels (layout: docs/DESIGN.md, "Texture
/// layouts") come first, then `HF_MAP_DESC_BYTES` of descriptor (`hf_map_desc`;
/// upload the texels only). Thread safe.
///
/// # Safety
/// `options` is NULL (the defaults) or valid for reading; `out_len` NULL (an error) or
/// valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_map_len(
    method: u32,
    width: u32,
    height: u32,
    options: *const hf_bake_options,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { size_query(method, width, height, options, out_len, map_elems) }
}

/// Writes the number of floats of the scratch `hf_bake_prepare` fills and
/// `hf_bake_rows` reads (0 for a method that needs none: the maximum mipmap and those
/// without a map) to `*out_len`. Thread safe.
///
/// # Safety
/// As `hf_map_len`.
#[no_mangle]
pub unsafe extern "C" fn hf_bake_scratch_len(
    method: u32,
    width: u32,
    height: u32,
    options: *const hf_bake_options,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        size_query(method, width, height, options, out_len, |s| {
            Ok(s.scratch_len())
        })
    }
}

/// Writes the number of rows `hf_bake_rows` bakes, numbered from 0, to `*out_rows`: H
/// (sample rows) for the safety-distance, cylinder–cone, radius and relaxed maps, H − 1
/// (cell rows) for the cone and QDM maps, 1 for the maximum mipmap (its levels depend
/// on each other: split it by level with `hf_maxmip_bake_rows`), 0 for a method that
/// bakes no map. Thread safe.
///
/// # Safety
/// `options` is NULL (the defaults) or valid for reading; `out_rows` NULL (an error)
/// or valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_bake_row_count(
    method: u32,
    width: u32,
    height: u32,
    options: *const hf_bake_options,
    out_rows: *mut u32,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { size_query(method, width, height, options, out_rows, |s| Ok(s.rows())) }
}

/// The elements of `spec`'s map, descriptor included.
fn map_elems(spec: &Spec) -> Result<usize, hf_result> {
    let n = spec.map_len()?;
    Ok(n + if spec.is_float() {
        elems::<f32>()
    } else {
        elems::<u8>()
    })
}

/// Body of the size queries: checks the arguments, writes `len(spec)` (0 for a
/// method without a map).
///
/// # Safety
/// `options` NULL or readable; `out` NULL or writable.
unsafe fn size_query<T: Default>(
    method: u32,
    width: u32,
    height: u32,
    options: *const hf_bake_options,
    out: *mut T,
    len: impl FnOnce(&Spec) -> Result<T, hf_result>,
) -> hf_result {
    guard(|| {
        let out = ptr::out(out)?;
        // SAFETY: the caller's promise, passed on.
        let c = unsafe { checked(method, width, height, options) }?;
        let n = match &c.spec {
            Some(spec) => len(spec)?,
            None => T::default(),
        };
        // SAFETY: the caller promises `out` is writable.
        unsafe { out.set(n) };
        Ok(())
    })
}

/// What one of the bake exports does with the checked bake of a field.
enum Job {
    /// `hf_bake_prepare`: fills the scratch (`scratch`, `scratch_len`).
    Prepare(*mut f32, usize),
    /// `hf_bake_rows`: bakes the rows into the map (`map`, `map_len`), reading the
    /// scratch (`scratch`, `scratch_len`).
    Rows {
        scratch: (*const f32, usize),
        rows: Range<u32>,
        map: (*mut c_void, usize),
    },
    /// `hf_bake`: bakes the whole map (`out_map`, `out_map_len`) on the options' threads.
    Whole(*mut c_void, usize),
}

/// Shared body of the bake exports: checks the field and `method`'s bake for it
/// (`options` NULL: the defaults), then does `job`, on maps of the bake's element type.
/// A method without a map does nothing (then the map's length must be 0).
///
/// # Safety
/// `field` NULL or live; `options` NULL or readable; the job's buffers as its export
/// documents.
unsafe fn bake_job(
    method: u32,
    field: *const hf_field,
    options: *const hf_bake_options,
    job: Job,
) -> hf_result {
    guard(|| {
        let map_len = match &job {
            Job::Prepare(..) => 0,
            Job::Rows { map, .. } => map.1,
            Job::Whole(_, len) => *len,
        };
        // SAFETY: the caller's promises.
        let f = unsafe { ptr::get(field) }.named("field")?;
        let hf = f.view();
        // SAFETY: the caller's promise, passed on.
        let c = unsafe { checked(method, hf.width(), hf.height(), options) }?;
        let spec = match c.spec {
            Some(spec) => spec,
            None if map_len == 0 => return Ok(()),
            None => {
                return Err(fail(
                    HF_ERR_INVALID_ARGUMENT,
                    "map_len: this method bakes no map; pass NULL and 0",
                ))
            }
        };
        // SAFETY: the caller's promises for the job's buffers, passed on.
        unsafe {
            match spec.is_float() {
                true => job.run::<f32>(f, &spec, c.threads, c.occluders),
                false => job.run::<u8>(f, &spec, c.threads, c.occluders),
            }
        }
    })
}

impl Job {
    /// Does the job for the checked bake `spec` of `f`, on maps of `T`.
    ///
    /// # Safety
    /// The job's buffers as its export documents.
    unsafe fn run<T: Out + Send>(
        self,
        f: &hf_field,
        spec: &Spec,
        threads: u32,
        occluders: &[Occluder],
    ) -> Result<(), hf_result> {
        match self {
            Job::Prepare(_, _) if spec.scratch_len() == 0 => Ok(()),
            Job::Prepare(scratch, scratch_len) => {
                // SAFETY: the caller's promise.
                let scratch = unsafe { ptr::slice_mut(scratch, scratch_len) }.named("scratch")?;
                Ok(spec.prepare(f.view(), scratch)?)
            }
            Job::Rows { scratch, rows, map } => {
                let scratch: &[f32] = match spec.scratch_len() {
                    0 => &[],
                    // SAFETY: the caller's promise.
                    _ => unsafe { ptr::slice(scratch.0, scratch.1) }.named("scratch")?,
                };
                // SAFETY: the caller's promises for `map`, passed on.
                unsafe { rows_of::<T>(f, spec, occluders, scratch, rows, map.0, map.1) }
            }
            // SAFETY: the caller's promises for the map, passed on.
            Job::Whole(map, map_len) => unsafe {
                whole::<T>(f, spec, (threads, occluders), map, map_len)
            },
        }
    }
}

/// Fills `scratch` (`scratch_len ≥ hf_bake_scratch_len` floats) with what the row
/// bakes of `method`'s map of `field` share: the strip bounds (safety distances,
/// radii), those and the N-buffers (cylinder–cone), the maximum pyramid (cone family).
/// O(cells), one thread. Nothing to do (and `scratch` may be NULL with length 0) for
/// the maximum mipmap and the methods without a map. Thread safe for distinct buffers.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `options` NULL (the defaults) or
/// valid; `scratch` NULL or valid for writing `scratch_len` floats.
#[no_mangle]
pub unsafe extern "C" fn hf_bake_prepare(
    method: u32,
    field: *const hf_field,
    options: *const hf_bake_options,
    scratch: *mut f32,
    scratch_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { bake_job(method, field, options, Job::Prepare(scratch, scratch_len)) }
}

/// Bakes rows `[row_begin, row_end)` (0 ≤ begin ≤ end ≤ `hf_bake_row_count`) of
/// `method`'s map of `field` into `map`, the whole map buffer (`map_len ≥ hf_map_len`
/// elements of the same options), reading `scratch` from `hf_bake_prepare`. Writes only
/// those rows, and the descriptor after the texels when `row_begin` is 0, so threads
/// may bake disjoint row ranges of one map at once, sharing one scratch: any job
/// system can split the costly part of a bake. Thread safe (reads the field only) for
/// disjoint rows of one map.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `options` NULL (the defaults) or
/// valid; `scratch` NULL or valid for reading `scratch_len` floats; `map` NULL (an
/// error) or valid for writing `map_len` elements of the method's map; concurrent
/// calls must bake disjoint rows.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_bake_rows(
    method: u32,
    field: *const hf_field,
    options: *const hf_bake_options,
    scratch: *const f32,
    scratch_len: usize,
    row_begin: u32,
    row_end: u32,
    map: *mut c_void,
    map_len: usize,
) -> hf_result {
    let job = Job::Rows {
        scratch: (scratch, scratch_len),
        rows: row_begin..row_end,
        map: (map, map_len),
    };
    // SAFETY: the caller's promises, passed on.
    unsafe { bake_job(method, field, options, job) }
}

/// The output of an element type for the core's bake.
trait Out: Texel {
    fn data(out: &mut [Self]) -> DataMut<'_>;
}

impl Out for f32 {
    fn data(out: &mut [f32]) -> DataMut<'_> {
        DataMut::F32(out)
    }
}

impl Out for u8 {
    fn data(out: &mut [u8]) -> DataMut<'_> {
        DataMut::U8(out)
    }
}

/// Body of `hf_bake_rows` for maps of `T`.
///
/// # Safety
/// `map` NULL or valid for writing `map_len` elements of `T`; the rows this call's alone.
unsafe fn rows_of<T: Out>(
    f: &hf_field,
    spec: &Spec,
    occluders: &[Occluder],
    scratch: &[f32],
    rows: Range<u32>,
    map: *mut c_void,
    map_len: usize,
) -> Result<(), hf_result> {
    let map = map.cast::<T>();
    // Checks NULL and alignment before any length.
    // SAFETY: an empty slice at the caller's pointer.
    unsafe { ptr::slice_mut(map, 0) }.named("map")?;
    let texels = spec.map_len()?;
    room::<T>(map_len, texels, "map_len")?;
    if rows.start > rows.end || rows.end > spec.rows() {
        let why = format_args!(
            "rows {}..{}: the map has {}",
            rows.start,
            rows.end,
            spec.rows()
        );
        return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
    }
    let row = spec.row_len()?;
    // Only the rows baked become a slice, so concurrent calls never alias.
    // SAFETY: inside the caller's buffer (length checked), this call's alone (the
    // documented contract).
    let out = unsafe { ptr::slice_mut(map.add(rows.start as usize * row), rows.len() * row) }?;
    spec.bake_rows_over(f.view(), occluders, scratch, rows.clone(), T::data(out))?;
    if rows.start == 0 {
        // SAFETY: the descriptor follows the texels (length checked); only the call
        // whose rows start at 0 writes it.
        let slot = unsafe { ptr::slice_mut(map.add(texels), elems::<T>()) }?;
        stamp(f, spec.desc, texels, slot);
    }
    Ok(())
}

/// Bakes `method`'s whole map of `field` into `out_map` (`out_map_len ≥ hf_map_len`
/// elements of the same options) on `options->threads` threads, allocating the scratch
/// itself: `hf_bake_prepare` then `hf_bake_rows` over every row (the maximum mipmap:
/// every level, each level's rows split among the threads). The same map for any
/// thread count. A method without a map bakes nothing (`out_map_len` 0). Thread safe
/// for distinct output maps (reads the field only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `options` NULL (the defaults) or
/// valid; `out_map` NULL (an error) or valid for writing `out_map_len` elements of the
/// method's map.
#[no_mangle]
pub unsafe extern "C" fn hf_bake(
    method: u32,
    field: *const hf_field,
    options: *const hf_bake_options,
    out_map: *mut c_void,
    out_map_len: usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { bake_job(method, field, options, Job::Whole(out_map, out_map_len)) }
}

/// Body of `hf_bake` for maps of `T`.
///
/// # Safety
/// `map` NULL or valid for writing `map_len` elements of `T`, exclusive.
unsafe fn whole<T: Out + Send>(
    f: &hf_field,
    spec: &Spec,
    (threads, occluders): (u32, &[Occluder]),
    map: *mut c_void,
    map_len: usize,
) -> Result<(), hf_result> {
    // SAFETY: the caller's promise.
    let out = unsafe { ptr::slice_mut(map.cast::<T>(), map_len) }.named("out_map")?;
    let texels = spec.map_len()?;
    room::<T>(map_len, texels, "map_len")?;
    let hf = f.view();
    let (texel_out, slot) = out.split_at_mut(texels);
    bake_threaded(hf, spec, (threads, occluders), texel_out)?;
    stamp(f, spec.desc, texels, slot);
    Ok(())
}

/// The whole bake of `spec` into `out` (its texels) on `threads` threads.
fn bake_threaded<T: Out + Send>(
    hf: &HeightField,
    spec: &Spec,
    (threads, occluders): (u32, &[Occluder]),
    out: &mut [T],
) -> Result<(), hf_result> {
    #[cfg(feature = "maxmip")]
    if spec.desc.map == MapKind::MaxMip {
        // A pyramid is floats (`Spec::is_float`).
        let DataMut::F32(p) = T::data(out) else {
            return Err(HF_ERR_INVALID_ARGUMENT);
        };
        crate::maxmip::bake_threaded(hf, &hfcore::maxmip::Layout::of(hf), threads, p);
        return Ok(());
    }
    let mut scratch = crate::par::zeroed(spec.scratch_len())?;
    spec.prepare(hf, &mut scratch)?;
    let scratch = &scratch;
    // Costly rows are uneven: bands of 8 rows taken in turn.
    crate::par::bake_bands(
        spec.rows(),
        spec.row_len()?,
        8,
        threads,
        out,
        |rows, chunk| spec.bake_rows_over(hf, occluders, scratch, rows, T::data(chunk)),
    )?;
    Ok(())
}
