//! Safety radius and robust binary search (Baboud & Décoret, "Rendering Geometry with
//! Relief Textures", GI 2006, §3.4–3.5) for the triangle surface: the bake and the
//! march side by side.
//!
//! **Radius.** One byte per texel ([`BYTES_PER_TEXEL`]): the discrete radius `n` of a
//! `2n × 2n` square centred on the texel (sides on centerlines) inside which every ray
//! that crosses the texel above the surface meets it at most once going forward, in any
//! direction, up or down: it goes down at most once and never comes back up. Along a
//! ray of class x± (y±) the square ends `n` centerlines ahead on the main axis, so the
//! march may skip `n` centerlines and learn from the clearance there alone whether it
//! passed the surface.
//!
//! **Relation to the safety distance.** "Meets the surface at most once after passing
//! above the texel" is "never crosses it upwards", which is the question the safety
//! distances of [`crate::safety`] answer per class with the exact limiting-triangle
//! test ([`RaySet`]); the radius is their minimum over the four classes, for every ray
//! ([`AllRays`]): exactly the isotropic safety distance, from the same per-class scan
//! ([`safety::texel_distance`], [`texel_radius`]). The paper's symmetric square (rays
//! meeting the surface once behind the texel and once ahead count twice there) gives
//! smaller radii and buys the march nothing, so the forward condition is the one
//! baked. Near-tangent rays make it small: on a convex
//! bump a ray grazing just above a texel enters and leaves the bump arbitrarily soon,
//! so the exact radius is 0 on every curved patch of a terrain (flat and planar
//! regions, walls' faces keep it) — hence the error-tolerant radius.
//!
//! **Error-tolerant radius** (the paper's Fig. 12: allowing an error gives larger
//! radii). With tolerance `e` (grid units) the bake asks the same question of the
//! surface lowered by `e` ([`Lowered`]): a ray passing above the texel never crosses
//! `h − e` upwards within the radius. A ray that is above `h` at both ends of a jump
//! therefore never went more than `e` under the surface in between: what the march
//! may skip is solid that the ray grazes at depth `≤ e` (thin silhouettes, ridge tips).
//! The radius only grows with `e` (a lowered plane limits less), and `e = 0` is exact.
//!
//! **March** ([`trace`]). As [`dda::trace`] up to the ray's first main-axis
//! centerline; then at each centerline above the surface, fetch the radius `n` of the
//! texel under the crossing and evaluate the clearance `n` centerlines ahead: above,
//! jump there; below, bisect on integer centerlines (the clearance changes sign once
//! inside the square), and finish with the exact cell test of [`dda::trace`]. A zero
//! radius walks one centerline cell by cell ([`Zero::Walk`], exact) or is treated as
//! one ([`Zero::Clamp`]: fewer fetches, not exact: a ray may skip a dip under the
//! surface that lies between two centerlines). The march is the one the safety
//! distances use (`safety::march`): start, side and under-the-surface semantics, flags,
//! rounding guards and watertight clearances are those of [`dda::trace`].
//!
//! [`dda::trace`]: crate::dda::trace

use core::cell::RefCell;
use core::ops::Range;

use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Query, Trace};
use crate::safety::{self, AllRays, MarchSurface, RaySet, SafetyError, Sigma, Tri};

/// Bytes of baked data per texel: one radius.
pub const BYTES_PER_TEXEL: usize = 1;

/// The rays of every class and vertical angle, meeting the surface lowered by `e`
/// (grid units, `e ≥ 0`): a triangle limits when such a ray, passing above the real
/// surface over the segment, may cross the triangle's plane lowered by `e` upwards
/// inside it. `Lowered(0.0)` is [`AllRays`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lowered(pub f64);

impl RaySet for Lowered {
    #[inline]
    fn limiting(&self, sigma: &Sigma, tri: &Tri) -> bool {
        let lowered = Tri {
            base: tri.base - self.0,
            ..*tri
        };
        AllRays.limiting(sigma, &lowered)
    }

    #[inline]
    fn lowering(&self) -> f64 {
        self.0
    }
}

/// What the bake computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BakeOptions {
    /// Error tolerance `e` in grid units (`0` = exact radius; negative or NaN is
    /// read as `0`).
    pub tolerance: f32,
    /// Largest radius stored (the scan stops there; smaller is conservative).
    pub cap: u8,
}

impl Default for BakeOptions {
    fn default() -> Self {
        BakeOptions {
            tolerance: 0.0,
            cap: u8::MAX,
        }
    }
}

impl BakeOptions {
    /// The ray set the bake scans with.
    fn rays(&self) -> Lowered {
        Lowered(f64::from(self.tolerance.max(0.0)))
    }
}

/// Bytes of a whole map: `W · H`.
pub fn map_len(width: u32, height: u32) -> usize {
    width as usize * height as usize * BYTES_PER_TEXEL
}

/// `f32` elements of the scratch the bake reads (the strip bounds of
/// [`safety::prepare`]).
pub fn scratch_len(width: u32, height: u32) -> usize {
    safety::scratch_len(width, height)
}

/// Fills the scratch the bake reads (`scratch_len(W, H)` elements); `O(cells)`, once
/// per field whatever the options.
pub fn prepare(hf: &HeightField, scratch: &mut [f32]) -> Result<(), SafetyError> {
    safety::prepare(hf, scratch)
}

/// The radius of texel `(i, j)`; `scratch` is what [`prepare`] filled: the minimum
/// over the four classes of their safety distances for the bake's ray set (each class
/// scanned only up to the minimum so far), i.e. the isotropic safety distance.
/// Cost `O(r²)` cell tests per class for a class scanned to reach `r`.
pub fn texel_radius(hf: &HeightField, scratch: &[f32], opts: BakeOptions, i: u32, j: u32) -> u8 {
    let rays = opts.rays();
    let mut v = opts.cap;
    for class in safety::CLASSES {
        if v == 0 {
            break;
        }
        v = safety::texel_distance(hf, scratch, &rays, class, i, j, v);
    }
    v
}

/// Bakes texel rows `rows` into `out` (`rows.len() · W` bytes, the rows' part of the
/// whole map). Rows are independent: any job system may split a bake into row ranges
/// sharing one `scratch` from [`prepare`].
pub fn bake_rows(
    hf: &HeightField,
    scratch: &[f32],
    rows: Range<u32>,
    opts: BakeOptions,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    let needed = safety::check_rows(hf, scratch, &rows, BYTES_PER_TEXEL, out)?;
    let w = hf.width() as usize;
    for (row, j) in out[..needed].chunks_exact_mut(w).zip(rows) {
        for (v, i) in row.iter_mut().zip(0..) {
            *v = texel_radius(hf, scratch, opts, i, j);
        }
    }
    Ok(())
}

/// Prepares `scratch` and bakes the whole map into `out` ([`map_len`] bytes), one thread.
pub fn bake(
    hf: &HeightField,
    scratch: &mut [f32],
    opts: BakeOptions,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    safety::bake_whole(hf, scratch, opts, out, bake_rows)
}

/// Baked radii over caller-owned bytes.
#[derive(Clone, Copy, Debug)]
pub struct RadiusMap<'a> {
    data: &'a [u8],
    width: u32,
}

impl<'a> RadiusMap<'a> {
    /// Views `data` ([`map_len`] bytes, as [`bake`] wrote it) for `hf`.
    pub fn new(hf: &HeightField, data: &'a [u8]) -> Result<Self, SafetyError> {
        safety::check_len(data, map_len(hf.width(), hf.height()))?;
        Ok(RadiusMap {
            data,
            width: hf.width(),
        })
    }

    /// Radius of texel `(i, j)`.
    #[inline]
    pub fn radius(&self, i: u32, j: u32) -> u8 {
        self.data[j as usize * self.width as usize + i as usize]
    }
}

/// What the march does at a texel of radius zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Zero {
    /// Walk to the next centerline cell by cell with the exact test (exact).
    #[default]
    Walk,
    /// Jump one centerline as if the radius were one (approximate: a dip under the
    /// surface between two centerlines may be skipped).
    Clamp,
}

/// March options.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Options {
    /// Zero radii.
    pub zero: Zero,
    /// The surface the march finishes on (the radii bound both; see [`MarchSurface`]).
    pub surface: MarchSurface,
}

/// Traces `q` on the triangle surface with the radii of `map` (baked for `hf`).
/// With an exact bake and [`Zero::Walk`]: the same hit as
/// [`dda::trace`](crate::dda::trace) with [`Surface::Triangles`](crate::Surface),
/// up to rounding on rays that graze the surface.
///
/// Cost: one fetch per radius read, two per centerline clearance, four per cell
/// walked. [`Trace::clearance`] is the smallest clearance at the crossings evaluated.
pub fn trace<R: Real>(map: &RadiusMap, hf: &HeightField, q: &Query<R>, opts: &Options) -> Trace<R> {
    trace_steps(map, hf, q, opts, &mut |_| {})
}

/// [`trace`], reporting to `on_step` the ray parameter of every centerline crossing
/// where the march reads a radius (it stands above the surface there; for tests).
pub fn trace_steps<R: Real>(
    map: &RadiusMap,
    hf: &HeightField,
    q: &Query<R>,
    opts: &Options,
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    let floor = u32::from(opts.zero == Zero::Clamp);
    let on_step = RefCell::new(on_step);
    safety::march(hf, opts.surface, q, |l, _, i, j| {
        (on_step.borrow_mut())(l.t);
        u32::from(map.radius(i, j)).max(floor)
    })
}
