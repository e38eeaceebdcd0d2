//! Ray queries: one ray or a batch, for every method.

use crate::detail::fail_at;
use crate::hf_result::{self, *};
use crate::occluder::{hf_occluder, mismatch, occluders_of};
use crate::ptr::Named;
use crate::{guard, hf_field, ptr, surface_of};
use hfcore::condition::{condition, condition_query_near, Local, Near};
use hfcore::horizon::{End, Horizon, Plan, Sighting, Start, MIN_GROUP};
use hfcore::march::MarchOptions;
use hfcore::march::Placed;
use hfcore::projective::{Mat4, Projective};
use hfcore::scene::RayClasses;
use hfcore::scene::{MethodKind, Shadows};
use hfcore::simd::Avx2;
use hfcore::{Flags, HeightField, Hit, Marcher, Query, Surface, Trace};
use std::ffi::c_void;
use std::ops::Range;

/// A ray: the points `origin + t * dir` for `t` in `[t_min, t_max]`, in grid space, or
/// in the field's world units when it has a transform (`hf_field_set_transform`).
/// `dir` need not be normalised (t is then in units of `|dir|`) but must be finite
/// and non-zero, also after conversion to grid space; `t_min` finite; `t_max ≥ t_min`,
/// `INFINITY` allowed. Grid space: x along sample columns i, y along rows j, z up, all
/// in sample spacings.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hf_ray {
    /// Origin (x, y, z) in grid units (world units with a transform).
    pub origin: [f32; 3],
    /// Direction (x, y, z), finite and non-zero.
    pub dir: [f32; 3],
    /// Start of the parameter range (finite).
    pub t_min: f32,
    /// End of the parameter range (`INFINITY` allowed).
    pub t_max: f32,
}

/// The answer to one query. On a miss `hit` is 0 and every field but `fetches`,
/// `flags` and `clearance` is 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hf_hit {
    /// 1 when the ray meets the surface in `[t_min, t_max]`, else 0.
    pub hit: u32,
    /// `HF_FLAG_*` bits: those of the hit (`ORIGIN_INSIDE`, `SIDE`, `WALL`) and of the
    /// trace (`BUDGET_EXHAUSTED`).
    pub flags: u32,
    /// Texture fetches used (one per texel read; a cell's four corners are four): the
    /// hardware-independent cost.
    pub fetches: u32,
    /// The cell (i, j) holding the hit: the unit square [i, i+1] × [j, j+1].
    pub cell: [u32; 2],
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point in grid space (world units with a transform).
    pub point: [f32; 3],
    /// Unit surface normal at the hit (a wall's normal for side and step hits).
    pub normal: [f32; 3],
    /// Smallest clearance (ray height − surface height, grid units; world height units
    /// with a transform) seen before the hit
    /// or along the whole ray for a miss; `INFINITY` when the ray never overlaps the
    /// field. Exact methods fill it; approximate ones report `INFINITY`.
    pub clearance: f32,
}

impl hf_hit {
    /// The core's hit this answer reports (the caller checked `hit` is 1).
    pub(crate) fn to_hit(self) -> Hit<f32> {
        Hit {
            t: self.t,
            point: self.point.into(),
            cell: self.cell,
            normal: self.normal.into(),
            flags: Flags(self.flags),
        }
    }
}

impl From<Trace<f32>> for hf_hit {
    fn from(tr: Trace<f32>) -> hf_hit {
        let mut out = hf_hit {
            flags: tr.flags.0,
            fetches: tr.fetches,
            clearance: tr.clearance,
            ..hf_hit::default()
        };
        if let Some(h) = tr.hit {
            out.hit = 1;
            out.flags |= h.flags.0;
            out.cell = h.cell;
            out.t = h.t;
            out.point = h.point.to_array();
            out.normal = h.normal.to_array();
        }
        out
    }
}

/// Checks a ray, converts it from the field's world units to grid space (in f64) and
/// conditions it for the f32 march (`hfcore::condition`: a far origin rebased near the
/// field, a tiny or huge direction scaled); an invalid ray's detail names it `ray`, or
/// `rays[index]` (and records `index`) in a batch.
pub(crate) fn query(
    hf: &HeightField,
    r: &hf_ray,
    index: Option<usize>,
) -> Result<Local, hf_result> {
    query_near(hf, &Near::of(hf), r, index)
}

/// [`query`] with the conditioning's test prepared ([`Near::of`] of `hf`): a batch's.
#[inline]
pub(crate) fn query_near(
    hf: &HeightField,
    near: &Near<f32>,
    r: &hf_ray,
    index: Option<usize>,
) -> Result<Local, hf_result> {
    let err = |e| ray_error(e, index);
    // The world ray's own faults first, named as such.
    let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max).map_err(err)?;
    let xf = hf.transform();
    if xf.is_identity() {
        return Ok(condition_query_near(hf, near, &q));
    }
    let o = xf.point_to_grid(r.origin.map(f64::from));
    let d = xf.dir_to_grid(r.dir.map(f64::from));
    condition(hf, o, d, r.t_min, r.t_max).map_err(err)
}

/// [`query`]'s checks alone (a batch's first pass): for a field without a transform,
/// the ray's own (conditioning a valid grid ray cannot fail).
pub(crate) fn check(hf: &HeightField, r: &hf_ray, index: Option<usize>) -> Result<(), hf_result> {
    if hf.transform().is_identity() {
        let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max);
        return q.map(|_| ()).map_err(|e| ray_error(e, index));
    }
    query(hf, r, index).map(|_| ())
}

/// The error of an invalid ray: its detail names it `ray`, or `rays[index]` (and
/// records `index`) in a batch.
pub(crate) fn ray_error(e: hfcore::RayError, index: Option<usize>) -> hf_result {
    match index {
        Some(k) => fail_at(HF_ERR_INVALID_RAY, index, format_args!("rays[{k}]: {e}")),
        None => fail_at(HF_ERR_INVALID_RAY, None, format_args!("ray: {e}")),
    }
}

/// A grid-space trace as the caller's `hf_hit`, in the field's world units.
pub(crate) fn answer(hf: &HeightField, tr: Trace<f32>) -> hf_hit {
    hf_hit::from(hf.transform().trace_to_world(tr))
}

/// How a trace runs: the surface, what the map must hold, the step budgets. Pass NULL
/// for the defaults, or start from `hf_trace_options_default` and change fields. Each
/// method reads the fields whose comment names it and ignores the others (a field it
/// ignores is still checked for a valid value: a known surface, a class set); a surface
/// it does not trace is `HF_ERR_INVALID_ARGUMENT`, and so is a non-zero `reserved`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct hf_trace_options {
    /// The surface to trace, an `hf_surface` (default `HF_SURFACE_TRIANGLES`). The
    /// safety-shape methods (safety, cc, radius) trace the triangle and view-linear
    /// surfaces, the cone family the triangle surface only, the others every surface.
    pub surface: u32,
    /// The ray classes (`HF_RAYS_*` bits) the map must hold (safety, cc): 0 (the
    /// default) accepts the classes its descriptor names; another set that differs
    /// from them is `HF_ERR_MAP_MISMATCH`.
    pub ray_classes: u32,
    /// The step budget, at least 1: linear steps (linear-binary, linear-secant),
    /// iterations (cone, qdm), cone steps (relaxed); for multires the one-texel distance
    /// in grid units (1 / the pixel angle; the CLI's default is 512). Default 64.
    pub steps: u32,
    /// Bisection steps (linear-binary, relaxed); default 8.
    pub binary_steps: u32,
    /// What a zero radius does (radius), an `hf_radius_zero`; default `HF_RADIUS_WALK`.
    pub radius_zero: u32,
    /// Threads `hf_trace_batch` traces on: 1 (the default) the calling thread, `n` up to
    /// `n` (at most the available cores), 0 one per available core, as the bakes. The
    /// answers do not depend on it. `hf_trace` (one ray) ignores it.
    pub threads: u32,
    /// Whether batches and cameras may use the CPU's SIMD lanes, an `hf_simd`: default
    /// `HF_SIMD_AUTO` (the maximum mipmap marches 16 rays at once in AVX-512, 8 in AVX2,
    /// where the CPU has them), `HF_SIMD_OFF` (one ray after another: for comparison).
    /// The answers do not depend on it.
    pub simd: u32,
    /// Whether a batch's or camera's rays from one eye share a horizon, an
    /// `hf_horizon`: default `HF_HORIZON_AUTO` (with the exact DDA and the exact maximum
    /// mipmap, a batch of at least `HF_HORIZON_MIN_GROUP` rays from one eye, and every
    /// camera of as many pixels, start each ray's march near its hit: docs/DESIGN.md,
    /// "Coherent batches"), `HF_HORIZON_OFF` (each ray from its own start: for
    /// comparison). The hits do not depend on it; `fetches` and `clearance` (a lower
    /// bound either way) do.
    pub horizon: u32,
    /// The occluders a safety or cylinder–cone map was baked over
    /// (`hf_bake_options::occluders`): the same list, in the same order, for every
    /// trace over such a map (else `HF_ERR_MAP_MISMATCH`), NULL and 0 (the default)
    /// for any other map. Read during the call only.
    pub occluders: *const hf_occluder,
    /// How many `occluders` there are, at most `HF_MAX_OCCLUDERS`.
    pub occluder_count: u32,
    /// Room for later options: must be 0 (else `HF_ERR_INVALID_ARGUMENT`).
    pub reserved: [u32; 5],
}

/// Whether a batch may use SIMD lanes (`hf_trace_options::simd`). Passed as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_simd {
    /// Lanes where the method has them and the CPU can (detected at run time).
    HF_SIMD_AUTO = 0,
    /// One ray after another.
    HF_SIMD_OFF = 1,
}

/// Whether rays from one eye share a horizon (`hf_trace_options::horizon`). Passed as
/// `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_horizon {
    /// A horizon where the method and the batch allow it.
    HF_HORIZON_AUTO = 0,
    /// Every ray marched from its own start.
    HF_HORIZON_OFF = 1,
}

/// Rays from one eye a batch needs before it shares a horizon among them
/// (`hf_trace_options::horizon`): fewer do not repay its pass over the field.
pub const HF_HORIZON_MIN_GROUP: u32 = 2048;
const _: () = assert!(HF_HORIZON_MIN_GROUP as usize == hfcore::horizon::MIN_GROUP);

impl Default for hf_trace_options {
    fn default() -> Self {
        // The core's defaults (the registry's step budgets), on the triangle surface.
        let m = MarchOptions::on(Surface::Triangles);
        hf_trace_options {
            surface: 0,
            ray_classes: 0,
            steps: m.steps,
            binary_steps: m.binary_steps,
            radius_zero: 0,
            threads: 1,
            simd: hf_simd::HF_SIMD_AUTO as u32,
            horizon: hf_horizon::HF_HORIZON_AUTO as u32,
            occluders: core::ptr::null(),
            occluder_count: 0,
            reserved: [0; 5],
        }
    }
}

/// Writes the default trace options to `*out_options` (what NULL options mean).
/// Thread safe.
///
/// # Safety
/// `out_options` is NULL (an error) or valid for writing one `hf_trace_options`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace_options_default(out_options: *mut hf_trace_options) -> hf_result {
    guard(|| {
        let out = ptr::out(out_options).named("out_options")?;
        // SAFETY: the caller promises `out_options` is writable.
        unsafe { out.set(hf_trace_options::default()) };
        Ok(())
    })
}

/// The trace options, checked for `method`: the core's march options, the ray classes
/// the map must hold and the batch's thread count.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TraceOptions {
    /// The surface and step budgets.
    pub march: MarchOptions,
    /// The ray classes the map must hold, when named.
    pub classes: Option<RayClasses>,
    /// The batch's thread count, as passed (0: one per core).
    pub threads: u32,
    /// The SIMD lanes a batch may use: the CPU's, unless the options turn them off.
    pub simd: Option<hfcore::simd::Avx2>,
    /// Whether rays from one eye may share a horizon.
    pub horizon: bool,
}

impl TraceOptions {
    /// Checks `o` for `method`.
    fn of(method: MethodKind, o: &hf_trace_options) -> Result<TraceOptions, hf_result> {
        use crate::detail::fail;
        if let Some(k) = o.reserved.iter().position(|&v| v != 0) {
            return Err(fail(
                HF_ERR_INVALID_ARGUMENT,
                format_args!("options.reserved[{k}]: must be 0"),
            ));
        }
        let info = method.info();
        let surface = surface_of(o.surface)?;
        if !info.surfaces.contains(&surface) {
            return Err(fail(
                HF_ERR_INVALID_ARGUMENT,
                format_args!(
                    "options.surface: {} does not trace the {} surface",
                    info.kind.name(),
                    surface.name()
                ),
            ));
        }
        if !info.steps.is_empty() && o.steps == 0 {
            return Err(fail(
                HF_ERR_INVALID_ARGUMENT,
                format_args!("options.steps: {} needs at least 1", info.kind.name()),
            ));
        }
        let radius_clamp = match o.radius_zero {
            0 | 1 => o.radius_zero == 1,
            _ => {
                let why = "options.radius_zero: not an hf_radius_zero";
                return Err(fail(HF_ERR_INVALID_ENUM, why));
            }
        };
        let classes = match o.ray_classes {
            0 => None,
            v => Some(crate::scene::classes_of(v)?),
        };
        let simd = match o.simd {
            0 => hfcore::detect_avx2!(),
            1 => None,
            _ => return Err(fail(HF_ERR_INVALID_ENUM, "options.simd: not an hf_simd")),
        };
        let horizon = match o.horizon {
            0 | 1 => o.horizon == 0,
            _ => {
                return Err(fail(
                    HF_ERR_INVALID_ENUM,
                    "options.horizon: not an hf_horizon",
                ))
            }
        };
        Ok(TraceOptions {
            march: MarchOptions {
                surface,
                steps: o.steps,
                binary_steps: o.binary_steps,
                radius_clamp,
            },
            classes,
            threads: o.threads,
            simd,
            horizon,
        })
    }
}

/// The marcher of `method` over the `map_len` elements at `map` (floats or bytes, as
/// the method's map is), its descriptor checked for `f`, with options `o`.
///
/// # Safety
/// `map` NULL or valid for reading `map_len` elements of the method's map.
pub(crate) unsafe fn marcher<'a>(
    f: &'a hf_field,
    method: u32,
    map: *const c_void,
    map_len: usize,
    options: *const hf_trace_options,
) -> Result<(Marcher<'a>, TraceOptions), hf_result> {
    let kind = crate::built_method_of(method)?;
    let o = match options.is_null() {
        true => hf_trace_options::default(),
        // SAFETY: the caller promises non-NULL options are readable.
        false => *unsafe { ptr::get(options) }.named("options")?,
    };
    // SAFETY: the caller promises the options' occluders are readable.
    let occluders = unsafe { occluders_of(o.occluders, o.occluder_count, "occluders") }?;
    let o = TraceOptions::of(kind, &o)?;
    // SAFETY: the caller's promise, passed on.
    let m = unsafe { crate::maps::marcher(kind, f, map, map_len, &o) }?;
    let m = m.with_occluders(f.view(), occluders).map_err(mismatch)?;
    Ok((m, o))
}

/// Traces one ray with `method` (an `hf_method`) over its baked `map` and writes the
/// answer to `*out_hit` (a miss is success with `hit = 0`): the one trace function of
/// every method. `map` is the buffer the method's bake filled for this field, of
/// `map_len` elements (floats for maxmip, cone, relaxed and qdm, bytes for safety, cc
/// and radius: as their `_len` query counts them); methods without a bake (exact,
/// linear-binary, linear-secant) take NULL and 0. `options` NULL means the defaults
/// (`hf_trace_options`). The map's descriptor is checked first: `HF_ERR_MAP_MISMATCH`
/// for a map of another method, field, size or class set, `HF_ERR_STALE_MAP` for one
/// baked before an update of this field (rebake it, or refresh a pyramid with
/// `hf_maxmip_update_rect`). A method left out of this build is `HF_ERR_NOT_BUILT`.
///
/// What each method answers, and costs (fetches: one per texel read, four per exact
/// cell test):
/// - exact: the first hit in `[t_min, t_max]` on `options->surface`, watertight in
///   `float`; four fetches per cell visited.
/// - maxmip (Tevs et al. 2008): exact, the hit of exact (the corner-planes surface is
///   traced by the exact traversal); one fetch per pyramid texel.
/// - safety, cc, radius (Baboud et al. 2011; Baboud & Décoret 2006): exact, the hit of
///   exact on the triangle surface, or with `HF_SURFACE_VIEW_LINEAR` on the
///   view-linear surface (Baboud et al. §7), from the same map, when the map was baked
///   exact (safety `positive = 0`, radius tolerance 0, `HF_RADIUS_WALK`); a ray of a
///   class the map does not hold walks cell by cell, still exact.
/// - cone, qdm: exact within `options->steps` iterations; when they run out the
///   current point is returned, flagged `HF_FLAG_BUDGET_EXHAUSTED`.
/// - linear-binary, linear-secant, relaxed: approximate (features thinner than a step
///   are missed), `options->steps` linear or cone steps then `binary_steps`
///   bisections (linear-secant: one secant step).
/// - multires (Qu et al. 2003, after Cohen-Or et al.): approximate, the exact walk on
///   coarser grids (every 2^l-th sample) where a pixel's footprint is wider than their
///   cells; `options->steps` is the one-texel distance `R` (grid units along the ray at
///   which a pixel covers one texel: 1 / the pixel angle): level `floor(log2(dist /
///   R))` at distance `dist`, full resolution under `2R`. Four fetches per cell of any
///   level.
///
/// Thread safe (reads the field and the map only).
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `map` NULL or valid for reading
/// `map_len` elements, not written during the call; `options` NULL or valid; `ray`
/// NULL (an error) or valid; `out_hit` NULL (an error) or valid for writing one
/// `hf_hit`.
#[no_mangle]
pub unsafe extern "C" fn hf_trace(
    field: *const hf_field,
    method: u32,
    map: *const c_void,
    map_len: usize,
    options: *const hf_trace_options,
    ray: *const hf_ray,
    out_hit: *mut hf_hit,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle and a valid ray (copied, so that
        // `out_hit` may even overlap it).
        let (f, r) = unsafe {
            (
                ptr::get(field).named("field")?,
                *ptr::get(ray).named("ray")?,
            )
        };
        let out = ptr::out(out_hit).named("out_hit")?;
        // SAFETY: the caller's promises, passed on.
        let (m, _) = unsafe { marcher(f, method, map, map_len, options) }?;
        let hf = f.view();
        let local = query(hf, &r, None)?;
        let hit = answer(hf, local.trace(|q| m.trace(hf, q)));
        // SAFETY: the caller promises `out_hit` is writable.
        unsafe { out.set(hit) };
        Ok(())
    })
}

/// The ray `r`'s line in grid space, in `f64`: what a horizon's eye and wedges are
/// measured in. (Inlined: returned through memory, its narrow stores stalled the
/// wide loads that read it, in the first pass over a batch.)
#[inline(always)]
pub(crate) fn grid_line(hf: &HeightField, r: &hf_ray) -> ([f64; 3], [f64; 3]) {
    let xf = hf.transform();
    if xf.is_identity() {
        (r.origin.map(f64::from), r.dir.map(f64::from))
    } else {
        (
            xf.point_to_grid(r.origin.map(f64::from)),
            xf.dir_to_grid(r.dir.map(f64::from)),
        )
    }
}

/// The surface of a horizon for `rays` rays traced by `m` with `o` (the one whose hits
/// `m`'s are): `None` unless the options allow one, `m`'s hits are the DDA's, and there
/// are enough rays to repay its pass over the field ([`MIN_GROUP`]; the batch's own
/// rays must share an origin too).
pub(crate) fn horizon_surface(m: &Marcher, o: &TraceOptions, rays: usize) -> Option<Surface> {
    m.dda_surface().filter(|_| o.horizon && rays >= MIN_GROUP)
}

/// Rays from which a batch checks its rays on its threads ([`checked_horizon`]): a
/// smaller batch's pass is shorter than starting them.
const PARALLEL_CHECK: usize = 1 << 15;

/// What the first pass over a batch found ([`checked_horizon`]).
pub(crate) struct Checked {
    /// The horizon its rays share ([`Marcher::horizon`]'s), if any.
    pub horizon: Option<Horizon>,
    /// Every ray is the caller's own query: a field without a transform, no ray
    /// needing conditioning ([`Near::holds`]); [`as_queries`] then views them.
    pub plain: bool,
}

/// Checks every ray of a batch ([`check`]: the first bad ray's error, its detail
/// recorded on the calling thread) and, in the same pass, sights the rays for the
/// horizon they can share ([`Plan::for_sightings`]; [`Marcher::horizon`]'s horizon,
/// `None` unless the options allow one, `m`'s hits are the DDA's and enough rays share
/// an origin) and sees whether they are all plain. A large batch's pass is split among
/// its threads.
pub(crate) fn checked_horizon(
    m: &Marcher,
    o: &TraceOptions,
    hf: &HeightField,
    rays: &[hf_ray],
) -> Result<Checked, hf_result> {
    let total = rays.len();
    let surface = horizon_surface(m, o, total);
    let eye = rays.first().map(|r| grid_line(hf, r).0);
    let identity = hf.transform().is_identity();
    let near = Near::of(hf);
    let lanes = o.simd.and_then(Avx2::avx512).filter(|_| identity);
    let sight = |part: Range<usize>| -> Result<(Sighting, bool), usize> {
        let mut seen = Sighting::new(total);
        let mut plain = identity;
        let mut from = part.start;
        // Runs of 64 rays in AVX-512 lanes (`Near::sight`: the same tests); from a run
        // that holds an invalid ray on, ray by ray, which finds the first.
        if let (Some(avx512), Some(r0)) = (lanes, rays.first()) {
            while from + RUN <= part.end {
                let run = &rays[from..from + RUN];
                let seen_run = near.sight(as_arrays(run), r0.origin, avx512);
                if !seen_run.valid {
                    break;
                }
                plain &= seen_run.plain;
                if surface.is_some() {
                    seen.add_run(from, RUN, seen_run.at_eye, |i| grid_line(hf, &run[i]).1);
                }
                from += RUN;
            }
        }
        let part = from..part.end;
        for (k, r) in part.clone().zip(&rays[part]) {
            if identity {
                let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max).map_err(|_| k)?;
                plain &= near.holds(&q);
            } else {
                check(hf, r, None).map_err(|_| k)?;
            }
            if surface.is_some() {
                let (origin, dir) = grid_line(hf, r);
                if Some(origin) == eye {
                    seen.add(k, dir);
                }
            }
        }
        Ok((seen, plain))
    };
    let parts = match u32::try_from(total) {
        Ok(n) if total >= PARALLEL_CHECK => crate::par::split(n, o.threads, |part| {
            sight(part.start as usize..part.end as usize)
        }),
        _ => vec![sight(0..total)],
    };
    let parts: Vec<(Sighting, bool)> = match parts.into_iter().collect() {
        Ok(parts) => parts,
        // Found on some thread: checked again on this one for its detail.
        Err(k) => return check(hf, &rays[k], Some(k)).and(Err(HF_ERR_INVALID_RAY)),
    };
    let plain = parts.iter().all(|p| p.1);
    let horizon = match (surface, eye) {
        (Some(surface), Some(eye)) => {
            let seen = parts.into_iter().map(|p| p.0);
            Plan::for_sightings(hf, surface, eye, seen, m.horizon_max_block())
                .map(|plan| build_horizon(plan, o.threads))
        }
        _ => None,
    };
    Ok(Checked { horizon, plain })
}

/// Rays [`checked_horizon`] checks at once in AVX-512 lanes.
const RUN: usize = 64;

/// The rays `rays` as arrays of their eight `f32` (origin, direction, `t_min`,
/// `t_max`), where they lie: what [`Near::sight`] reads.
fn as_arrays(rays: &[hf_ray]) -> &[[f32; 8]] {
    const {
        assert!(size_of::<hf_ray>() == size_of::<[f32; 8]>());
        assert!(align_of::<hf_ray>() == align_of::<[f32; 8]>());
    }
    // SAFETY: `hf_ray` is `repr(C)`, four arrays of `f32` (3 + 3 + 1 + 1), no padding
    // (the sizes are checked above): every `hf_ray` is eight initialized `f32`.
    unsafe { core::slice::from_raw_parts(rays.as_ptr().cast::<[f32; 8]>(), rays.len()) }
}

/// The rays of a batch that [`checked_horizon`] found plain, as the queries the marches
/// take, where they lie.
pub(crate) fn as_queries(rays: &[hf_ray]) -> &[Query<f32>] {
    const {
        assert!(size_of::<hf_ray>() == size_of::<Query<f32>>());
        assert!(align_of::<hf_ray>() == align_of::<Query<f32>>());
    }
    // SAFETY: `Query<f32>` is `repr(C)` with the fields of `hf_ray` in the same order
    // (both four arrays of `f32`; the sizes and alignments are checked above, the order
    // by `tests::rays_are_queries`), and every ray passed `Query::from_arrays`, so each
    // is a valid query.
    unsafe { core::slice::from_raw_parts(rays.as_ptr().cast::<Query<f32>>(), rays.len()) }
}

/// The horizon of `plan`, each pass over the field shared by the batch's `threads`
/// ([`crate::par::split`], [`Plan::build_by`]): the same horizon as one thread builds.
pub(crate) fn build_horizon(plan: Plan, threads: u32) -> Horizon {
    plan.build_by(|plan| {
        let parts = crate::par::split(plan.block_rows(), threads, |rows| plan.wedges(rows));
        plan.finish(parts)
    })
}

/// Where `horizon` places the ray `r` (`None`: it says nothing of it), `hint` the
/// band of the last ray asked ([`Horizon::start`]).
pub(crate) fn horizon_start(
    horizon: &Horizon,
    hf: &HeightField,
    r: &hf_ray,
    hint: &mut usize,
) -> Option<(Start<f64>, u32)> {
    let (o, d) = grid_line(hf, r);
    horizon.start(o, d, (f64::from(r.t_min), f64::from(r.t_max)), hint)
}

/// The hits of the conditioned queries `locals` into `out` (same lengths; `None`: a
/// miss that cost nothing), the answers those of one `hf_trace` each. A query with a
/// horizon's start in `starts` (empty, or one per query) marches from there
/// ([`Marcher::trace_started`]); the others are traced together by `m`
/// ([`Marcher::trace_each`]: in the SIMD lanes `o` allows where the method has them).
pub(crate) fn trace_locals(
    m: &Marcher,
    o: &TraceOptions,
    hf: &HeightField,
    locals: &[Option<Local>],
    starts: &[Option<(Start<f64>, u32)>],
    out: &mut [hf_hit],
) {
    let start = |k: usize| starts.get(k).copied().flatten();
    let rest = |k: &usize| locals[*k].is_some() && start(*k).is_none();
    let queries: Vec<Query<f32>> = (0..locals.len())
        .filter(rest)
        .filter_map(|k| locals[k].map(|l| l.query))
        .collect();
    let mut traces = vec![Trace::MISS; queries.len()];
    m.trace_each(hf, &queries, &mut traces, o.simd);
    let mut traces = traces.into_iter();
    for (k, (l, h)) in locals.iter().zip(out.iter_mut()).enumerate() {
        *h = match (l, start(k)) {
            (Some(local), Some(start)) => trace_from_start(m, hf, local, start),
            (Some(local), None) => {
                let trace = traces.next().expect("one trace per query");
                answer(hf, local.trace(|_| trace))
            }
            (None, _) => hf_hit::from(Trace::<f32>::miss(0, f32::INFINITY)),
        };
    }
}

/// The answer to the conditioned query `local` whose horizon placed it `start`
/// ([`Marcher::trace_started`]).
#[inline]
fn trace_from_start(
    m: &Marcher,
    hf: &HeightField,
    local: &Local,
    (start, probes): (Start<f64>, u32),
) -> hf_hit {
    match start {
        Start::At(t, before, _) => answer(
            hf,
            local.trace_from(Some(t), |q, t| {
                let t = t.expect("a start in local units");
                let whole = End::whole(q.t_max());
                m.trace_started(hf, q, (Start::At(t, before as f32, whole), probes))
            }),
        ),
        Start::Miss(clearance) => hf_hit::from(Trace::<f32>::miss(probes, clearance as f32)),
    }
}

/// A batch's rays and hits (the hits cut to the rays' count): NULLs, overlap and a short
/// output are errors.
///
/// # Safety
/// `rays` valid for reading `rays_len` rays and `out_hits` for writing `out_hits_len`
/// hits, or NULL (an error).
unsafe fn batch_io<'a>(
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> Result<(&'a [hf_ray], &'a mut [hf_hit]), hf_result> {
    // SAFETY: the caller promises `rays_len` valid rays and `out_hits` writable for its
    // length; the two are checked disjoint before the slices exist.
    let (rays, hits) = unsafe {
        ptr::slice_and_out(
            (rays, rays_len, "rays"),
            (out_hits, out_hits_len, "out_hits"),
        )
    }?;
    if hits.len() < rays.len() {
        return Err(crate::detail::fail(
            HF_ERR_BUFFER_TOO_SMALL,
            format_args!("out_hits: {} hits for {} rays", hits.len(), rays.len()),
        ));
    }
    let n = rays.len();
    Ok((rays, &mut hits[..n]))
}

/// Rays a thread of `hf_trace_batch` takes at a time (the bands of `par::bake_bands`)
/// in a batch of `n`: a sixteenth of the batch (so that threads share it evenly), and
/// 256 to 4,096. Long runs keep a laned march's lanes full: a set of lanes drains at
/// the end of each run (random rays over the Himalaya DEM: 256-ray bands cost about
/// 1.2× the time of 4,096-ray ones, in the maximum mipmap's lanes).
fn ray_band(n: u32) -> u32 {
    (n / 16).clamp(256, 4096)
}

/// `hf_trace` for `rays_len` rays on `options->threads` threads: `out_hits[k]` answers
/// `rays[k]`; `out_hits_len ≥
/// rays_len`. Everything is checked before any ray is traced, and an error writes
/// nothing: `out_hits` sharing a byte with `rays` (over their whole lengths) is
/// `HF_ERR_INVALID_ARGUMENT`; one bad ray fails the call (`HF_ERR_INVALID_RAY`;
/// `hf_last_error_index` gives the first bad ray). An empty batch (`rays_len` 0) is
/// `HF_OK` and writes nothing; its pointers must still be non-NULL. Thread safe.
///
/// # Safety
/// As `hf_trace`; `rays` is NULL (an error) or valid for reading `rays_len` rays;
/// `out_hits` NULL (an error) or valid for writing `out_hits_len` hits.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_trace_batch(
    field: *const hf_field,
    method: u32,
    map: *const c_void,
    map_len: usize,
    options: *const hf_trace_options,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle.
        let f = unsafe { ptr::get(field) }.named("field")?;
        // SAFETY: the caller's promises, passed on.
        let (rays, hits) = unsafe { batch_io(rays, rays_len, out_hits, out_hits_len) }?;
        // SAFETY: the caller's promises, passed on.
        let (m, o) = unsafe { marcher(f, method, map, map_len, options) }?;
        let hf = f.view();
        // Every ray is checked first; rays from one eye (a camera's) share a horizon,
        // built once for all threads.
        let Checked { horizon, plain } = checked_horizon(&m, &o, hf, rays)?;
        // The callers' own rays (no transform, no conditioning: the common case) go to
        // the marches where they lie.
        let queries = plain.then(|| as_queries(rays));
        // Bands of rays taken in turn by the threads; `u32` counts them.
        let n = u32::try_from(rays.len()).unwrap_or(u32::MAX);
        let threads = if n == u32::MAX { 1 } else { o.threads };
        let ray_band = ray_band(n);
        crate::par::bake_bands(n, 1, ray_band, threads, hits, |band, out| {
            // At most `ray_band` rays at a time, also when one thread takes them all as
            // one band: the per-ray buffers stay small and in cache (measured: one
            // buffer for a whole 640 × 512 batch cost 160 ns a ray in page faults and
            // misses, for rays that miss the box).
            let (mut hint, mut scratch) = (0, BandScratch::default());
            let near = Near::of(hf);
            let traced = Band {
                m: &m,
                o: &o,
                hf,
                near: &near,
            };
            for (c, out) in out.chunks_mut(ray_band as usize).enumerate() {
                let first = band.start as usize + c * ray_band as usize;
                let part = first..first + out.len();
                if let Some(queries) = queries {
                    let plain = (&queries[part], &mut scratch.traced);
                    trace_plain((&m, &o, hf), horizon.as_ref(), plain, &mut hint, out);
                } else {
                    let rays = (&rays[part], first);
                    traced.trace(horizon.as_ref(), rays, &mut hint, &mut scratch, out)?;
                }
            }
            Ok(())
        })
    })
}

/// What every band of an `hf_trace_batch` call is traced with.
struct Band<'a> {
    m: &'a Marcher<'a>,
    o: &'a TraceOptions,
    hf: &'a HeightField<'a>,
    /// The conditioning's test, prepared once.
    near: &'a Near<f32>,
}

/// The buffers a thread of `hf_trace_batch` reuses from band to band.
#[derive(Default)]
struct BandScratch {
    traced: PlainScratch,
    locals: Vec<Option<Local>>,
}

impl Band<'_> {
    /// The hits of `rays` (the first of them `rays[first]` of the batch) into `out`,
    /// those of one `hf_trace` each: marched from where `horizon` places them (`hint`:
    /// the last ray's band), else by the method itself, in lanes where it has them. The
    /// callers' own rays (no transform, no conditioning: the common case) go to the
    /// marches as they are; the others through their local form ([`query`]).
    fn trace(
        &self,
        horizon: Option<&Horizon>,
        (rays, first): (&[hf_ray], usize),
        hint: &mut usize,
        s: &mut BandScratch,
        out: &mut [hf_hit],
    ) -> Result<(), hf_result> {
        let Band { m, o, hf, near } = *self;
        if let Some(plain) = plain_queries(hf, near, rays) {
            let plain = (plain, &mut s.traced);
            trace_plain((m, o, hf), horizon, plain, hint, out);
            return Ok(());
        }
        match horizon {
            Some(h) => {
                for (k, (r, hit)) in rays.iter().zip(out.iter_mut()).enumerate() {
                    let local = query_near(hf, near, r, Some(first + k))?;
                    *hit = match horizon_start(h, hf, r, hint) {
                        Some(start) => trace_from_start(m, hf, &local, start),
                        None => answer(hf, local.trace(|q| m.trace(hf, q))),
                    };
                }
            }
            None => {
                s.locals.clear();
                for (k, r) in rays.iter().enumerate() {
                    s.locals
                        .push(Some(query_near(hf, near, r, Some(first + k))?));
                }
                trace_locals(m, o, hf, &s.locals, &[], out);
            }
        }
        Ok(())
    }
}

/// The buffers [`trace_plain`] reuses from call to call.
#[derive(Default)]
pub(crate) struct PlainScratch {
    traces: Vec<Trace<f32>>,
    placed: Placed,
}

/// The hits of `plain`, the callers' own rays as a march takes them
/// ([`plain_queries`]), into `out`, those of one `hf_trace` each: marched from where
/// `horizon` places them (`hint`: the last ray's band), else by the method itself, in
/// lanes where `o` allows them (`s`: scratch).
pub(crate) fn trace_plain(
    (m, o, hf): (&Marcher, &TraceOptions, &HeightField),
    horizon: Option<&Horizon>,
    (plain, s): (&[Query<f32>], &mut PlainScratch),
    hint: &mut usize,
    out: &mut [hf_hit],
) {
    if let Some(h) = horizon {
        // The answers written as hits where they go.
        m.trace_placed(hf, h, (plain, hint), out, o.simd, &mut s.placed);
        return;
    }
    let traces = &mut s.traces;
    traces.clear();
    traces.resize(plain.len(), Trace::MISS);
    m.trace_each(hf, plain, traces, o.simd);
    for (hit, tr) in out.iter_mut().zip(traces.iter()) {
        *hit = hf_hit::from(*tr);
    }
}

/// `rays` as the queries a march traces, where they lie ([`as_queries`]), when every
/// one is the caller's own ray: valid, on a field without a transform, needing no
/// conditioning (`near`, [`Near::holds`]). `None` otherwise: then [`query`] gives each
/// its local form, or its error.
pub(crate) fn plain_queries<'r>(
    hf: &HeightField,
    near: &Near<f32>,
    rays: &'r [hf_ray],
) -> Option<&'r [Query<f32>]> {
    let plain = hf.transform().is_identity()
        && rays.iter().all(|r| {
            let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max);
            q.is_ok_and(|q| near.holds(&q))
        });
    plain.then(|| as_queries(rays))
}

/// `hf_trace_batch` on a projective height field (Baboud & Décoret §4: a frustum, e.g.
/// reverse perspective): `matrix` is 16 doubles, row-major, the invertible map from
/// the caller's world points `[x, y, z, 1]` to homogeneous grid points of `field` (its
/// own transform is not applied). Each world ray is mapped to the grid line of the
/// part of it in front of the centre of projection (`w > 0`), traced there by `method`
/// over `map` as `hf_trace_batch` traces, and its hit mapped back: `t` on the world
/// ray, the point by the inverse map, the normal by the transpose, all in double
/// (docs/DESIGN.md, "Projective height fields"); a ray with no part in front is a
/// miss. `HF_ERR_INVALID_ARGUMENT` for a matrix with a NaN or infinite entry or a
/// singular one (no frustum); other checks and errors as `hf_trace_batch` (every ray
/// is checked, and mapped, before any is traced; an error writes nothing). Thread
/// safe.
///
/// # Safety
/// As `hf_trace_batch`; `matrix` NULL (an error) or valid for reading 16 doubles.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_projective_trace_batch(
    field: *const hf_field,
    matrix: *const f64,
    method: u32,
    map: *const c_void,
    map_len: usize,
    options: *const hf_trace_options,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle and 16 readable doubles.
        let (f, m) = unsafe {
            (
                ptr::get(field).named("field")?,
                ptr::slice(matrix, 16).named("matrix")?,
            )
        };
        let rows: Mat4 = core::array::from_fn(|r| core::array::from_fn(|c| m[4 * r + c]));
        let proj = Projective::new(rows).map_err(|e| fail_at(HF_ERR_INVALID_ARGUMENT, None, e))?;
        // SAFETY: the caller's promises, passed on.
        let (rays, hits) = unsafe { batch_io(rays, rays_len, out_hits, out_hits_len) }?;
        // SAFETY: the caller's promises, passed on.
        let (marcher, o) = unsafe { marcher(f, method, map, map_len, options) }?;
        let hf = f.view();
        let mapped = rays
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max)
                    .map_err(|e| ray_error(e, Some(k)))?;
                proj.map(hf, &q).map_err(|e| ray_error(e, Some(k)))
            })
            .collect::<Result<Vec<_>, hf_result>>()?;
        let n = u32::try_from(rays.len()).unwrap_or(u32::MAX);
        let threads = if n == u32::MAX { 1 } else { o.threads };
        crate::par::bake_bands(n, 1, ray_band(n), threads, hits, |band, out| {
            let first = band.start as usize;
            for (m, h) in mapped[first..first + out.len()].iter().zip(out.iter_mut()) {
                *h = hf_hit::from(match m {
                    Some(m) => proj.trace_to_world(m, marcher.trace(hf, &m.grid)),
                    None => Trace::MISS,
                });
            }
            Ok::<(), hf_result>(())
        })
    })
}

/// Qu et al.'s hybrid rasterization renderer on the CPU (`hfcast::hybrid`, Qu et al.
/// 2003 §4): its two passes for `rays_len` rays on the view-linear surface,
/// `out_hits[k]` answering `rays[k]` as `hf_trace` of `HF_METHOD_EXACT` on
/// `HF_SURFACE_VIEW_LINEAR` does (in world units when the field has a transform). The
/// reference a GPU implementation of the renderer is checked against, ray by ray (the
/// OSMesa and GLFW tests do). Pass 1 tests every cell boundary of the field per ray (W +
/// H), as a rasterizer covers them, so it is slow by design. Checks and errors as
/// `hf_trace_batch`. Thread safe.
///
/// # Safety
/// As `hf_trace_batch`.
#[no_mangle]
pub unsafe extern "C" fn hf_hybrid_trace_batch(
    field: *const hf_field,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle.
        let f = unsafe { ptr::get(field) }.named("field")?;
        // SAFETY: the caller's promises, passed on.
        let (rays, hits) = unsafe { batch_io(rays, rays_len, out_hits, out_hits_len) }?;
        let hf = f.view();
        let locals = rays
            .iter()
            .enumerate()
            .map(|(k, r)| query(hf, r, Some(k)))
            .collect::<Result<Vec<_>, _>>()?;
        for (local, h) in locals.iter().zip(hits.iter_mut()) {
            *h = answer(hf, local.trace(|q| hfcore::hybrid::trace(hf, q)));
        }
        Ok(())
    })
}

/// A shadow ray from `hit` (the answer `hf_trace` gave for `primary` on `surface`, an
/// `hf_surface` value, of `field`; in world units when the field has a transform)
/// towards a light in direction `to_light`, written to `*out_ray`: its origin is the
/// hit point lifted off the surface (along the normal by `64 · FLT_EPSILON · (1 + m)`
/// grid units, `m` the largest magnitude of the hit point's and the primary origin's
/// grid coordinates, then to at least that above the surface where it lies over the
/// field), `t` in `[0, INFINITY]`. A shadow ray started at the hit point itself often
/// reports `HF_FLAG_ORIGIN_INSIDE` (the point rounds into the solid); this one starts
/// outside. `HF_ERR_INVALID_ARGUMENT` when `hit->hit` is 0. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `primary`, `hit` and `to_light` (3
/// floats) are NULL (an error) or valid for reading; `out_ray` is NULL (an error) or
/// valid for writing one `hf_ray`.
#[no_mangle]
pub unsafe extern "C" fn hf_shadow_ray(
    field: *const hf_field,
    surface: u32,
    primary: *const hf_ray,
    hit: *const hf_hit,
    to_light: *const [f32; 3],
    out_ray: *mut hf_ray,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        shadow_ray_call(
            field,
            surface,
            primary,
            hit,
            to_light,
            out_ray,
            Shadows::FromSurface,
        )
    }
}

/// The shadow ray of `hf_shadow_ray` traced from the light's side, written to
/// `*out_ray`: the same points walked the other way, from a grid unit outside the
/// field's box down along `-to_light` to the same lifted start (origin that start,
/// direction `-to_light`, `t` in `[-T, 0]`). It meets the surface iff the ray of
/// `hf_shadow_ray` does, and it starts outside the box: a map baked for exterior rays
/// (`hf_bake_options::exterior`) takes its long steps along it, where the ray of
/// `hf_shadow_ray` walks cell by cell (`HF_SHADOWS_FROM_LIGHT`). Its hit, when in
/// shadow, is the one nearest the light. Errors as `hf_shadow_ray`. Thread safe.
///
/// # Safety
/// As `hf_shadow_ray`.
#[no_mangle]
pub unsafe extern "C" fn hf_shadow_ray_from_light(
    field: *const hf_field,
    surface: u32,
    primary: *const hf_ray,
    hit: *const hf_hit,
    to_light: *const [f32; 3],
    out_ray: *mut hf_ray,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        shadow_ray_call(
            field,
            surface,
            primary,
            hit,
            to_light,
            out_ray,
            Shadows::FromLight,
        )
    }
}

/// The ray `ray` of `field` (grid space, or world units when the field has a transform)
/// walked the other way, written to `*out_ray`: the origin kept, the direction
/// negated, `t` from a grid unit beyond where the ray leaves the field's box back to
/// `-t_min`. The same points, now entering from outside the box: how a shadow ray
/// towards a light becomes the light's ray to its point (`hf_shadow_ray_from_light`
/// is `hf_shadow_ray` then this). A ray that misses the box comes back as it is; one
/// that ends inside it is reversed over its own range. `HF_ERR_INVALID_RAY` for a ray
/// `hf_trace` refuses. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `ray` NULL (an error) or valid for
/// reading; `out_ray` NULL (an error) or valid for writing one `hf_ray` (it may be
/// `ray`).
#[no_mangle]
pub unsafe extern "C" fn hf_ray_walked_back(
    field: *const hf_field,
    ray: *const hf_ray,
    out_ray: *mut hf_ray,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle and a readable ray (copied first).
        let (f, r) = unsafe { (ptr::get(field)?, *ptr::get(ray)?) };
        let out = ptr::out(out_ray)?;
        let hf = f.view();
        let q = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max)
            .and_then(|q| hf.transform().walked_back(hf, &q))
            .map_err(|e| crate::detail::fail(HF_ERR_INVALID_RAY, e))?;
        // SAFETY: the caller promises `out_ray` is writable.
        unsafe { out.set(hf_ray::from(q)) };
        Ok(())
    })
}

/// `hf_shadow_ray` (`from` [`Shadows::FromSurface`]) or `hf_shadow_ray_from_light`.
///
/// # Safety
/// As `hf_shadow_ray`.
unsafe fn shadow_ray_call(
    field: *const hf_field,
    surface: u32,
    primary: *const hf_ray,
    hit: *const hf_hit,
    to_light: *const [f32; 3],
    out_ray: *mut hf_ray,
    from: Shadows,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle and readable inputs.
        let (f, p, h, l) = unsafe {
            (
                ptr::get(field)?,
                ptr::get(primary)?,
                ptr::get(hit)?,
                ptr::get(to_light)?,
            )
        };
        let out = ptr::out(out_ray)?;
        let ray = shadow_ray_of(f.view(), surface_of(surface)?, p, h, *l, from)?;
        // SAFETY: the caller promises `out_ray` is writable.
        unsafe { out.set(ray) };
        Ok(())
    })
}

/// The shadow ray of `hf_shadow_ray` (`from` [`Shadows::FromSurface`]) or of
/// `hf_shadow_ray_from_light` ([`Shadows::FromLight`]): from `hit` (the answer to
/// `primary` on `surface`) towards `to_light`, lifted off the surface;
/// `HF_ERR_INVALID_ARGUMENT` for a miss or a hit that is not finite. Also the camera's
/// shadow pass.
pub(crate) fn shadow_ray_of(
    hf: &HeightField,
    surface: Surface,
    primary: &hf_ray,
    hit: &hf_hit,
    to_light: [f32; 3],
    from: Shadows,
) -> Result<hf_ray, hf_result> {
    if hit.hit == 0 || !hit.point.iter().chain(&hit.normal).all(|v| v.is_finite()) {
        return Err(HF_ERR_INVALID_ARGUMENT);
    }
    let p = primary;
    let primary = Query::from_arrays(p.origin, p.dir, p.t_min, p.t_max)?;
    let (xf, h) = (hf.transform(), hit.to_hit());
    let q = match from {
        Shadows::FromLight => xf.shadow_query_from_light(hf, surface, &primary, &h, to_light),
        _ => xf.shadow_query(hf, surface, &primary, &h, to_light),
    }?;
    Ok(hf_ray::from(q))
}

impl From<Query<f32>> for hf_ray {
    fn from(q: Query<f32>) -> hf_ray {
        hf_ray {
            origin: q.origin(),
            dir: q.dir(),
            t_min: q.t_min(),
            t_max: q.t_max(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`as_queries`] reads each ray's fields as the query's own.
    #[test]
    fn rays_are_queries() {
        let rays = [
            hf_ray {
                origin: [1.0, 2.0, 3.0],
                dir: [4.0, 5.0, 6.0],
                t_min: 7.0,
                t_max: 8.0,
            },
            hf_ray {
                origin: [-1.5, 0.25, 9.0],
                dir: [0.0, -1.0, 0.5],
                t_min: 0.0,
                t_max: f32::INFINITY,
            },
        ];
        for (r, q) in rays.iter().zip(as_queries(&rays)) {
            let own = Query::from_arrays(r.origin, r.dir, r.t_min, r.t_max).unwrap();
            assert_eq!(*q, own);
            assert_eq!((q.origin(), q.dir()), (r.origin, r.dir));
            assert_eq!((q.t_min(), q.t_max()), (r.t_min, r.t_max));
        }
    }
}
