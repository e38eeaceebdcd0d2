//! Safety distances (Baboud, Eisemann, Seidel, "Precomputed Safety Shapes for
//! Efficient and Accurate Height-field Rendering", TVCG 2011, §5.2.2 and §6.1) for the
//! triangle surface: the bake and the march side by side.
//!
//! **Texels and classes.** A ray of class x± ([`RayClass`]) crosses every centerline
//! `x = m` once; where it crosses it at `y`, the texel is `(m, round(y))` and its
//! *segment* is `x = m, y ∈ [n − ½, n + ½]`. Classes y± swap the axes.
//!
//! **Bake.** For each texel and class the safety distance `k` is the number of
//! centerlines that any ray of the class, passing above the surface on the texel's
//! segment, may skip without leaving the solid (crossing the surface upwards): there
//! is no *limiting* triangle in the `k` columns of cells ahead of the segment. A
//! triangle is limiting for a ray set when some ray of the set crosses its plane
//! upwards inside it ([`RaySet`]). For all rays of a class ([`AllRays`]) that is:
//! some point of the segment sees the triangle inside the ±45° quadrant and lies below
//! the triangle's plane — tested exactly at three points (both ends of the part of the
//! segment that sees the triangle, and the middle sample). Columns are scanned by
//! increasing distance; strips of [`STRIP`] cells carry a conservative bound (highest
//! corner, fastest rise of a plane towards the segment) that skips most cells.
//!
//! **March.** Like [`dda::trace`] up to the ray's first centerline of its main axis;
//! then at each centerline `m`: fetch `k`, evaluate the clearance at `m + k` from the
//! two samples on that centerline; above, jump; below, bisect on integer centerlines
//! and finish with the exact cell test of [`dda::trace`] (at most two cells). `k = 0`
//! (and clearances too small for rounding to be ruled out) walk one centerline cell by
//! cell. Clearances at centerline crossings come from the edge's two samples only, as
//! in [`dda::trace`], so hit or miss stays watertight; start, side and
//! under-the-surface semantics and flags are those of [`dda::trace`].
//!
//! Exactness under rounding: a jump is taken only when the clearance exceeds a bound
//! on the march's rounding error ([`Line::tol`]); the bake widens each segment by
//! `1/16` texel, so that rounding of the crossing's coordinate cannot leave it.
//!
//! The cylinder–cone shapes of §6.3 (a cone above the cylinder, closed-form steps,
//! packed for GPUs) are in [`cc`]; they share this module's bake of `k` and its march.
//!
//! [`dda::trace`]: crate::dda::trace

use core::ops::Range;

use crate::dda::{
    cell_index, clip, entry_on, finish, local_clearance, next_crossing, segment_point,
    start_clearance, start_hit,
};
use crate::dda::{step_of, Span};
use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Flags, Hit, Query, RayClass, Trace};
use crate::scene::RayClasses;
use crate::surface::{corners, triangle_planes, Surface};

pub mod cc;
pub mod rays;

pub use crate::rayset::{Occluder, Occluders, Rays, RaysError};
pub use rays::{RaysOn, Witness};

/// Cells per strip of the bake's bound (along the minor axis of a class).
pub const STRIP: u32 = 8;

/// How far (texels) the bake widens each segment beyond `[n − ½, n + ½]`.
pub const SEG_PAD: f64 = 1.0 / 16.0;

/// The four classes in class order (the rows of a directional map, [`texel_offset`]).
pub const CLASSES: [RayClass; 4] = RayClass::ALL;

/// Main axis (0 = x, 1 = y) of a class.
#[inline]
fn axis_of(class: RayClass) -> usize {
    match class {
        RayClass::XPos | RayClass::XNeg => 0,
        RayClass::YPos | RayClass::YNeg => 1,
    }
}

/// Sample at main index `m`, minor index `n` of axis `ax`.
#[inline]
fn sample(hf: &HeightField, ax: usize, m: u32, n: u32) -> f32 {
    if ax == 0 {
        hf.at(m, n)
    } else {
        hf.at(n, m)
    }
}

/// Slice elements between consecutive samples along the main and the minor axis of
/// axis `ax`: `sample(hf, ax, m, n)` is element `m·ms + n·ns` of `hf.samples()`.
#[inline]
fn strides(hf: &HeightField, ax: usize) -> (usize, usize) {
    if ax == 0 {
        (1, hf.stride())
    } else {
        (hf.stride(), 1)
    }
}

/// Samples along `[x, y]` of axis `ax` as `(main, minor)`.
#[inline]
fn extents(hf: &HeightField, ax: usize) -> (u32, u32) {
    if ax == 0 {
        (hf.width(), hf.height())
    } else {
        (hf.height(), hf.width())
    }
}

/// How the baked distances are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// One byte per texel and class, each texel row as one row per class
    /// ([`texel_offset`], [`ClassRows`]; the layout: docs/DESIGN.md, "Texture layouts",
    /// safety, directional). A ray reads one class only, so its distances lie side by
    /// side; row ranges stay contiguous for split bakes. A map of fewer classes
    /// ([`bake_rows_classes`]) holds only their rows.
    Directional,
    /// One byte per texel, the minimum over the classes (docs/DESIGN.md, "Texture
    /// layouts", safety, isotropic).
    Isotropic,
}

impl Variant {
    /// Bytes per texel (all classes together).
    pub fn channels(self) -> usize {
        match self {
            Variant::Directional => 4,
            Variant::Isotropic => 1,
        }
    }
}

/// What the bake computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Options {
    /// Directional or isotropic.
    pub variant: Variant,
    /// Clamp every distance to at least 1 (the paper's "strictly positive" variant):
    /// fewer fetches, **not exact** (rays may miss silhouettes).
    pub positive: bool,
    /// Largest distance stored (the scan stops there; smaller is conservative).
    pub cap: u8,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            variant: Variant::Directional,
            positive: false,
            cap: u8::MAX,
        }
    }
}

/// Why a safety-shape bake or map view refused its buffers or rows (the crate's one
/// [`BufferError`](crate::buffer::BufferError)).
pub type SafetyError = crate::buffer::BufferError;

// ---------------------------------------------------------------------------------
// Bake
// ---------------------------------------------------------------------------------

/// Strips per cell column (x classes) and per cell row (y classes).
fn strips(hf: &HeightField) -> (usize, usize) {
    let (cx, cy) = (hf.width() as usize - 1, hf.height() as usize - 1);
    (cy.div_ceil(STRIP as usize), cx.div_ceil(STRIP as usize))
}

/// `f32` elements of the scratch that [`prepare`] fills and the bake reads: three per
/// strip (highest corner, fastest rise towards the segment for the two classes of the
/// strip's orientation).
pub fn scratch_len(width: u32, height: u32) -> usize {
    let (cx, cy) = (width.max(2) as usize - 1, height.max(2) as usize - 1);
    let s = STRIP as usize;
    3 * (cx * cy.div_ceil(s) + cy * cx.div_ceil(s))
}

/// Rounds up to `f32` (the bound must not shrink).
#[inline]
fn up(v: f64) -> f32 {
    let r = v as f32;
    if (r as f64) < v {
        f32::from_bits(if r >= 0.0 {
            r.to_bits() + 1
        } else {
            r.to_bits() - 1
        })
    } else {
        r
    }
}

/// Highest corner of a cell and, per class, the fastest rise of either of its planes
/// going back towards a segment within the class's quadrant (`−g·main + |g·minor|`).
fn cell_bound(hf: &HeightField, ci: u32, cj: u32) -> (f64, [f64; 4]) {
    let c: [f64; 4] = corners(hf, ci, cj);
    let top = c[0].max(c[1]).max(c[2]).max(c[3]);
    let mut beta = [f64::NEG_INFINITY; 4];
    for [_, gu, gv] in triangle_planes(c) {
        let b = [-gu + gv.abs(), gu + gv.abs(), -gv + gu.abs(), gv + gu.abs()];
        for k in 0..4 {
            beta[k] = beta[k].max(b[k]);
        }
    }
    (top, beta)
}

/// Fills the strip bounds the bake reads (`scratch_len(W, H)` elements). `O(cells)`.
pub fn prepare(hf: &HeightField, scratch: &mut [f32]) -> Result<(), SafetyError> {
    let needed = scratch_len(hf.width(), hf.height());
    crate::buffer::check("scratch", needed, scratch.len())?;
    let (cx, cy) = (hf.width() - 1, hf.height() - 1);
    let (sx, sy) = strips(hf);
    let (xs, ys) = scratch[..needed].split_at_mut(3 * cx as usize * sx);
    xs.fill(f32::NEG_INFINITY);
    ys.fill(f32::NEG_INFINITY);
    let s = STRIP as usize;
    for cj in 0..cy {
        for ci in 0..cx {
            let (top, beta) = cell_bound(hf, ci, cj);
            let k = 3 * (ci as usize * sx + cj as usize / s);
            let k2 = 3 * (cj as usize * sy + ci as usize / s);
            for (slot, v) in [(k, top), (k + 1, beta[0]), (k + 2, beta[1])] {
                xs[slot] = xs[slot].max(up(v));
            }
            for (slot, v) in [(k2, top), (k2 + 1, beta[2]), (k2 + 2, beta[3])] {
                ys[slot] = ys[slot].max(up(v));
            }
        }
    }
    Ok(())
}

/// The surface over a texel's segment, in its class's frame: the minor coordinate `y`
/// runs along the main-axis centerline `m`; the height there is `h` at `y = n`,
/// linear with `slope[0]` below `n` and `slope[1]` above (the edge interpolation of
/// the samples), over `[lo, hi]` (the segment widened by [`SEG_PAD`]).
#[derive(Clone, Copy, Debug)]
pub struct Sigma {
    /// Main axis of the class's frame (0 = x, 1 = y).
    pub ax: usize,
    /// Direction of the class along it (`1` or `−1`).
    pub sg: i64,
    /// Main-axis centerline.
    pub m: u32,
    /// Minor index of the texel.
    pub n: f64,
    /// Height at `y = n`.
    pub h: f64,
    /// Slopes below and above `n`.
    pub slope: [f64; 2],
    /// Lower end of the widened segment.
    pub lo: f64,
    /// Upper end of the widened segment.
    pub hi: f64,
}

impl Sigma {
    /// Surface height on the segment at minor coordinate `y`.
    #[inline]
    pub fn height(&self, y: f64) -> f64 {
        let s = if y < self.n {
            self.slope[0]
        } else {
            self.slope[1]
        };
        self.h + s * (y - self.n)
    }

    /// [`Sigma::height`] at the segment's ends `lo` and `hi` (`lo < n < hi`: no test).
    #[inline]
    pub fn end_heights(&self) -> [f64; 2] {
        [
            self.h + self.slope[0] * (self.lo - self.n),
            self.h + self.slope[1] * (self.hi - self.n),
        ]
    }
}

/// One triangle of the surface, in the frame of a class and a texel: its vertices as
/// `[distance ahead of the texel's centerline, minor coordinate]`, and its plane.
#[derive(Clone, Copy, Debug)]
pub struct Tri {
    /// Vertices `[forward distance, minor coordinate]`.
    pub verts: [[f64; 2]; 3],
    /// Height of the plane on the texel's centerline at minor coordinate `at`.
    pub base: f64,
    /// Minor coordinate where the plane's height on the centerline is `base`.
    pub at: f64,
    /// Plane slope along the minor axis.
    pub minor_slope: f64,
    /// Plane slope along the class's forward direction.
    pub forward_slope: f64,
}

impl Tri {
    /// Height of the plane (extended) on the texel's centerline at minor coordinate `y`.
    #[inline]
    pub fn height_on_line(&self, y: f64) -> f64 {
        self.base + self.minor_slope * (y - self.at)
    }
}

/// A set of rays, as the bake sees it: which triangles limit the rays of the set that
/// pass above a segment. A narrower set (exterior rays, a bounded downward angle) gives
/// fewer limiting triangles and larger distances.
pub trait RaySet {
    /// `true` when some ray of the set, of the class the frame belongs to, passing
    /// above `sigma`, may cross the plane of `tri` upwards inside `tri`. Must never
    /// answer `false` wrongly; `true` wrongly only costs speed.
    fn limiting(&self, sigma: &Sigma, tri: &Tri) -> bool;

    /// How far (`≥ 0`) the set lowers every plane before [`RaySet::limiting`] compares
    /// it with the surface: no triangle limits unless its plane, lowered by this much,
    /// rises above the surface somewhere on the segment. The bake's strip bound
    /// ([`texel_distance`]) subtracts it. Default `0` (always safe).
    fn lowering(&self) -> f64 {
        0.0
    }

    /// How fast (`−∞` to `+∞`) the plane of a limiting triangle must at least rise
    /// going back towards the segment along some direction of the class's quadrant
    /// (`−f + |g|` for forward and minor slopes `f`, `g`): a strip whose fastest rise
    /// is below it holds no limiting triangle (a view-angle set,
    /// [`Rays`]). Default `−∞` (always safe).
    fn least_rise_back(&self) -> f64 {
        f64::NEG_INFINITY
    }
}

/// Every ray of the class (any vertical angle, up or down).
#[derive(Clone, Copy, Debug, Default)]
pub struct AllRays;

impl RaySet for AllRays {
    #[inline]
    fn limiting(&self, sigma: &Sigma, tri: &Tri) -> bool {
        // A ray from P (above the segment) meets the triangle at Q iff Q lies in the
        // quadrant ahead of P: |Q.minor − P.minor| ≤ Q.distance. The points of the
        // segment that see the triangle form an interval (the triangle is convex).
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for [dist, y] in tri.verts {
            lo = lo.min(y - dist);
            hi = hi.max(y + dist);
        }
        let (lo, hi) = (lo.max(sigma.lo), hi.min(sigma.hi));
        if lo > hi {
            return false;
        }
        // The ray leaves the solid through the plane iff P is below the plane; P can be
        // as low as the surface, so: the plane above the surface somewhere on [lo, hi].
        // Both are linear on either side of n: ends and middle suffice.
        let above = |y: f64| tri.height_on_line(y) > sigma.height(y);
        above(lo) || above(hi) || (lo < sigma.n && sigma.n < hi && above(sigma.n))
    }
}

/// The surface over the segment of texel `(m, n)` (main, minor indices) of axis `ax`,
/// for the class of direction `sg` along it.
#[inline]
pub(crate) fn sigma_of(hf: &HeightField, ax: usize, sg: i64, m: u32, n: u32) -> Sigma {
    let (_, ln) = extents(hf, ax);
    let s = |k: u32| f64::from(sample(hf, ax, m, k));
    let h = s(n);
    let below = if n > 0 { h - s(n - 1) } else { s(n + 1) - h };
    let above = if n + 1 < ln {
        s(n + 1) - h
    } else {
        h - s(n - 1)
    };
    let nf = f64::from(n);
    Sigma {
        ax,
        sg,
        m,
        n: nf,
        h,
        slope: [below, above],
        lo: nf - 0.5 - SEG_PAD,
        hi: nf + 0.5 + SEG_PAD,
    }
}

/// The safety distance of texel `(i, j)` for `class` and the rays of `rays`: the first
/// column of cells ahead that holds a limiting triangle, at most `cap` (also when the
/// field ends first). `scratch` is what [`prepare`] filled.
pub fn texel_distance<S: RaySet>(
    hf: &HeightField,
    scratch: &[f32],
    rays: &S,
    class: RayClass,
    i: u32,
    j: u32,
    cap: u8,
) -> u8 {
    // One instance per class: its axis and direction are then constants in the scan
    // (the same operations on the same values, fewer selects).
    let texel = (i, j);
    match class {
        RayClass::XPos => class_distance::<S, 0, 1>(hf, scratch, rays, texel, cap),
        RayClass::XNeg => class_distance::<S, 0, -1>(hf, scratch, rays, texel, cap),
        RayClass::YPos => class_distance::<S, 1, 1>(hf, scratch, rays, texel, cap),
        RayClass::YNeg => class_distance::<S, 1, -1>(hf, scratch, rays, texel, cap),
    }
}

/// [`texel_distance`] for the class of main axis `AX` and direction `SG`.
fn class_distance<S: RaySet, const AX: usize, const SG: i64>(
    hf: &HeightField,
    scratch: &[f32],
    rays: &S,
    (i, j): (u32, u32),
    cap: u8,
) -> u8 {
    let (ax, sg) = (AX, SG);
    let (lm, ln) = extents(hf, ax);
    let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
    let sigma = sigma_of(hf, ax, sg, m, n);
    // The lowest surface point of the segment: an end or `n`.
    let [at_lo, at_hi] = sigma.end_heights();
    let floor = at_lo.min(sigma.h).min(at_hi);
    let (sx, sy) = strips(hf);
    let (per_line, base, chan) = if ax == 0 {
        (sx, 0, if sg > 0 { 1 } else { 2 })
    } else {
        let xlen = 3 * (hf.width() as usize - 1) * sx;
        (sy, xlen, if sg > 0 { 1 } else { 2 })
    };
    // A strip is skipped when no plane in it, lowered by `e`, rises above `floor`:
    // `top + rise ≤ floor + e`. The bound keeps `e·2⁻²⁰` back, far above the
    // rounding of the lowered planes' heights, so it skips only strips the ray set
    // itself would pass (`e = 0`: the plain bound).
    let e = rays.lowering();
    let floor = floor + (e - e * (1.0 / 1_048_576.0));
    let least = rays.least_rise_back();
    // Columns of cells ahead before the field ends.
    let ahead = if sg > 0 { lm - 1 - m } else { m };
    let columns = u32::from(cap).min(ahead);
    let column = |k: u32| column_ahead(m, sg, k);
    let st = STRIP as usize;
    // Whether strip `b` of column `k` holds no limiting plane (the bound above).
    let shut = |k: u32, b: usize| {
        let at = base + 3 * (column(k) as usize * per_line + b);
        let (top, beta) = (f64::from(scratch[at]), f64::from(scratch[at + chan]));
        let kf = f64::from(k);
        top + (beta * kf).max(beta * (kf + 1.0)) <= floor || beta < least
    };
    // The answer is the first column holding a limiting cell, whatever the order of
    // the cells tested inside it; so the cell of column 0 (where most scans end) that
    // limits most often may go first, and the scan then skips it (not tested when
    // its strip is shut: the scan skips that strip too). For all rays that is cell
    // `n` where the surface bends down at `n` (`slope[0] > slope[1]`: every such
    // texel of the checks' maps), cell `n + 1` elsewhere (two times in three). A
    // lowered ray set passes the planes that near the surface mostly: it keeps the
    // plain order.
    let first = n + u32::from(sigma.slope[0] <= sigma.slope[1]);
    // In the band of column 0, `[n − 2, n + 1]`; a cell of the field below `ln − 1`.
    let skip = if e == 0.0 && columns > 0 && first < ln - 1 {
        let l = first as usize;
        if !shut(0, l / st) && cell_limits(hf, rays, &sigma, ax, sg, column(0), first) {
            return 0;
        }
        l
    } else {
        usize::MAX
    };
    for k in 0..columns {
        let skip = if k == 0 { skip } else { usize::MAX };
        // The band, as cells `l0..l1`.
        let (l0, l1) = band_cells(n, k, ln);
        let (l0, l1) = (l0 as usize, l1 as usize + 1);
        for b in l0 / st..l1.div_ceil(st) {
            if shut(k, b) {
                continue;
            }
            for l in l0.max(b * st)..l1.min(b * st + st) {
                if l != skip && cell_limits(hf, rays, &sigma, ax, sg, column(k), l as u32) {
                    return k as u8;
                }
            }
        }
    }
    cap
}

/// The cell column `k` ahead of main index `m` in direction `sg`: `m + k` forward,
/// `m − 1 − k` back.
#[inline]
pub(crate) fn column_ahead(m: u32, sg: i64, k: u32) -> u32 {
    if sg > 0 {
        m + k
    } else {
        m - 1 - k
    }
}

/// The cells `l0..=l1` (minor indices) of column `k` ahead of a texel of minor index
/// `n` that a ray from its segment can reach, `n − k − 2 ..= n + k + 1`, in a field of
/// `ln` samples across.
#[inline]
pub(crate) fn band_cells(n: u32, k: u32, ln: u32) -> (u32, u32) {
    (n.saturating_sub(k + 2), (n + k + 1).min(ln - 2))
}

/// `true` when either triangle of cell `(cm, l)` (main, minor indices) limits.
/// Always inlined: [`texel_distance`] calls it twice, and a call in its scan would
/// recompute per cell what the scan keeps per column.
#[inline(always)]
fn cell_limits<S: RaySet>(
    hf: &HeightField,
    rays: &S,
    sigma: &Sigma,
    ax: usize,
    sg: i64,
    cm: u32,
    l: u32,
) -> bool {
    let h = cell_corners(hf, ax, cm, l);
    cell_tris(h, sigma, ax, sg, cm, l)
        .iter()
        .any(|t| rays.limiting(sigma, t))
}

/// The corners of cell `(cm, l)` (main, minor indices of axis `ax`), as
/// [`HeightField::cell_corners`] gives them.
#[inline]
pub(crate) fn cell_corners(hf: &HeightField, ax: usize, cm: u32, l: u32) -> [f32; 4] {
    let (i, j) = if ax == 0 { (cm, l) } else { (l, cm) };
    hf.cell_corners(i, j)
}

/// The corners of the two triangles of [`cell_tris`], as masks over `h` (bit `u + 2v`
/// for the corner `(u, v)`, [`cell_corners`]'s order): its split, on the same values.
#[inline]
pub(crate) fn tri_masks(h: [f32; 4]) -> [u8; 2] {
    let c = h.map(f64::from);
    if c[0] + c[3] <= c[1] + c[2] {
        [0b1011, 0b1101]
    } else {
        [0b0111, 0b1110]
    }
}

/// The two triangles of cell `(cm, l)` (main, minor indices), of corners `h`
/// ([`cell_corners`]), in the frame of `sigma`.
#[inline]
pub(crate) fn cell_tris(
    h: [f32; 4],
    sigma: &Sigma,
    ax: usize,
    sg: i64,
    cm: u32,
    l: u32,
) -> [Tri; 2] {
    let c = h.map(f64::from);
    let planes = triangle_planes(c);
    let (mf, lf, cmf) = (f64::from(sigma.m), f64::from(l), f64::from(cm));
    let sgf = sg as f64;
    // Corner (u, v) in the frame (exact: small integers).
    let fwd = [sgf * (cmf - mf), sgf * (cmf + 1.0 - mf)];
    let p = |u: usize, v: usize| {
        let (a, b) = if ax == 0 { (u, v) } else { (v, u) };
        [fwd[a], lf + b as f64]
    };
    let [p00, p10, p01, p11] = [p(0, 0), p(1, 0), p(0, 1), p(1, 1)];
    // The two triangles' vertices, as in `triangle_planes`.
    let verts = if c[0] + c[3] <= c[1] + c[2] {
        [[p00, p10, p11], [p00, p01, p11]]
    } else {
        [[p00, p10, p01], [p10, p01, p11]]
    };
    let tri = |k: usize| {
        let [h0, gu, gv] = planes[k];
        let (g_main, g_minor) = if ax == 0 { (gu, gv) } else { (gv, gu) };
        Tri {
            verts: verts[k],
            base: h0 + g_main * (mf - cmf),
            at: lf,
            minor_slope: g_minor,
            forward_slope: sgf * g_main,
        }
    };
    [tri(0), tri(1)]
}

/// Bakes texel rows `rows` into `out` (`rows.len() · W · channels` bytes, the rows'
/// part of the whole map, from byte `rows.start · W · channels` on), for every ray
/// ([`AllRays`]). Rows are independent: any job system may split a bake into row
/// ranges sharing one `scratch` from [`prepare`].
pub fn bake_rows(
    hf: &HeightField,
    scratch: &[f32],
    rows: Range<u32>,
    opts: Options,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    bake_rows_with(hf, scratch, &AllRays, rows, opts, out)
}

/// [`bake_rows`] for any ray set.
pub fn bake_rows_with<S: RaySet>(
    hf: &HeightField,
    scratch: &[f32],
    rays: &S,
    rows: Range<u32>,
    opts: Options,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    bake_rows_classes(hf, scratch, rays, RayClasses::ALL, rows, opts, out)
}

/// [`bake_rows_with`] for the ray classes of `classes` only (a scene's
/// [`BakePlan::classes`](crate::scene::BakePlan::classes)) into a map holding those
/// only ([`map_len_classes`]: `rows.len() · W · n` bytes directional for the set's `n`
/// classes, `rows.len() · W` isotropic); the others are never computed nor stored.
/// Directional: each texel row as `n` rows, the kept classes' in class order
/// ([`ClassRows`]), their distances equal to the full bake's. Isotropic: the minimum
/// over the kept classes only (with one class that class's distances exactly). Read
/// it with [`SafetyMap::with_classes`] for the same set: a ray of a class the map
/// does not hold then jumps 0 (exact, cell by cell). An empty set writes nothing
/// directional, 0 isotropic.
pub fn bake_rows_classes<S: RaySet>(
    hf: &HeightField,
    scratch: &[f32],
    rays: &S,
    classes: RayClasses,
    rows: Range<u32>,
    opts: Options,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    let w = hf.width();
    let per_texel = map_len_classes(1, 1, opts.variant, classes);
    check_rows(hf, scratch, &rows, per_texel, out)?;
    let floor = u8::from(opts.positive);
    let rows_of = CLASSES.map(|class| ClassRows::of(w, opts.variant, classes, class));
    for (r, j) in rows.enumerate() {
        for i in 0..w {
            match opts.variant {
                Variant::Directional => {
                    for (class, rows) in CLASSES.into_iter().zip(rows_of) {
                        if let Some(at) = rows {
                            out[at.index(i, r as u32)] =
                                texel_distance(hf, scratch, rays, class, i, j, opts.cap).max(floor);
                        }
                    }
                }
                Variant::Isotropic if classes.count() == 0 => out[r * w as usize + i as usize] = 0,
                Variant::Isotropic => {
                    let mut v = opts.cap;
                    for (class, rows) in CLASSES.into_iter().zip(rows_of) {
                        if v == 0 {
                            break;
                        }
                        if rows.is_some() {
                            v = texel_distance(hf, scratch, rays, class, i, j, v);
                        }
                    }
                    out[r * w as usize + i as usize] = v.max(floor);
                }
            }
        }
    }
    Ok(())
}

/// Bytes of a whole map: `W · H · channels`.
pub fn map_len(width: u32, height: u32, variant: Variant) -> usize {
    map_len_classes(width, height, variant, RayClasses::ALL)
}

/// Bytes of a whole map holding the classes of `classes` ([`bake_rows_classes`]):
/// directional `W · H · n` for the set's `n` classes, isotropic `W · H`.
pub fn map_len_classes(width: u32, height: u32, variant: Variant, classes: RayClasses) -> usize {
    let rows = match variant {
        Variant::Directional => classes.count() as usize,
        Variant::Isotropic => 1,
    };
    width as usize * height as usize * rows
}

/// Offset in a whole map `width` texels wide of the distance of texel `(i, j)` for
/// `class` (see [`Variant`]): directional `(j·4 + class)·W + i` (each texel row stored
/// as four rows, one per class), isotropic `j·W + i` (every class reads the same byte).
/// Maps of fewer classes: [`ClassRows`].
#[inline]
pub fn texel_offset(width: u32, variant: Variant, class: RayClass, i: u32, j: u32) -> usize {
    ClassRows::of(width, variant, RayClasses::ALL, class).map_or(0, |at| at.index(i, j))
}

/// Where one ray class's entries lie in a class-per-row map (the directional safety
/// map, the cylinder–cone map) holding the classes of a set: each texel row stored as
/// one row of `W` entries per class of the set, in class order, so texel `(i, j)` is
/// entry `(j·n + slot)·W + i` for the set's `n` classes and the class's `slot` among
/// them ([`RayClasses::slot`]). The isotropic map is the one-row case (slot 0 for
/// every held class). On the GPU: a texture of `W × nH` texels, texel
/// `(i, n·j + slot)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClassRows {
    /// Entries per texel row: `n·W`.
    stride: usize,
    /// The class's row in a texel row: `slot·W`.
    offset: usize,
}

impl ClassRows {
    /// The rows of `class` in a map `width` texels wide of `variant` holding `classes`;
    /// `None` when it does not hold `class`.
    #[inline]
    pub fn of(width: u32, variant: Variant, classes: RayClasses, class: RayClass) -> Option<Self> {
        let slot = classes.slot(class)? as usize;
        let (rows, slot) = match variant {
            Variant::Directional => (classes.count() as usize, slot),
            Variant::Isotropic => (1, 0),
        };
        Some(ClassRows {
            stride: rows * width as usize,
            offset: slot * width as usize,
        })
    }

    /// Entry of texel `(i, j)`: `(j·n + slot)·W + i`.
    #[inline]
    pub fn index(self, i: u32, j: u32) -> usize {
        j as usize * self.stride + self.offset + i as usize
    }
}

/// Prepares `scratch` and bakes the whole map into `out` ([`map_len`] bytes), one thread.
pub fn bake(
    hf: &HeightField,
    scratch: &mut [f32],
    opts: Options,
    out: &mut [u8],
) -> Result<(), SafetyError> {
    bake_whole(hf, scratch, opts, out, bake_rows)
}

/// Checks the buffers of a bake of texel rows `rows`, `bytes_per_texel` bytes a texel:
/// `scratch` holds [`scratch_len`] values, `rows` lie in the field and `out` holds
/// their bytes, whose count it returns. The checks of [`bake_rows_classes`] and of the
/// radius bake ([`crate::radius::bake_rows`]).
pub(crate) fn check_rows(
    hf: &HeightField,
    scratch: &[f32],
    rows: &Range<u32>,
    bytes_per_texel: usize,
    out: &[u8],
) -> Result<usize, SafetyError> {
    let needed = scratch_len(hf.width(), hf.height());
    crate::buffer::check("scratch", needed, scratch.len())?;
    if rows.end > hf.height() || rows.start > rows.end {
        return Err(SafetyError::BadRows);
    }
    let needed = (rows.end - rows.start) as usize * hf.width() as usize * bytes_per_texel;
    check_len(out, needed)?;
    Ok(needed)
}

/// `TooShort` unless `data` holds at least `needed` bytes: a bake's output or
/// the baked data a map views ([`SafetyMap::new`], [`crate::radius::RadiusMap::new`]).
pub(crate) fn check_len(data: &[u8], needed: usize) -> Result<(), SafetyError> {
    crate::buffer::check("output", needed, data.len())?;
    Ok(())
}

/// [`prepare`]s `scratch`, then bakes all the rows with `bake_rows` into `out`: the
/// one-thread whole-map bake of the safety distances ([`bake`]) and of the radii
/// ([`crate::radius::bake`]).
pub(crate) fn bake_whole<O>(
    hf: &HeightField,
    scratch: &mut [f32],
    opts: O,
    out: &mut [u8],
    bake_rows: impl FnOnce(&HeightField, &[f32], Range<u32>, O, &mut [u8]) -> Result<(), SafetyError>,
) -> Result<(), SafetyError> {
    prepare(hf, scratch)?;
    bake_rows(hf, scratch, 0..hf.height(), opts, out)
}

// ---------------------------------------------------------------------------------
// March
// ---------------------------------------------------------------------------------

/// Baked safety distances over caller-owned bytes.
#[derive(Clone, Copy, Debug)]
pub struct SafetyMap<'a> {
    data: &'a [u8],
    width: u32,
    variant: Variant,
    classes: RayClasses,
    rays: Rays,
    occluders: Occluders<'a>,
}

impl<'a> SafetyMap<'a> {
    /// Views `data` ([`map_len`] bytes, as [`bake`] wrote it) for `hf`.
    pub fn new(hf: &HeightField, data: &'a [u8], variant: Variant) -> Result<Self, SafetyError> {
        Self::with_classes(hf, data, variant, RayClasses::ALL)
    }

    /// Views a map holding the classes of `classes` ([`map_len_classes`] bytes, as
    /// [`bake_rows_classes`] wrote it for that set): rays of the other classes read
    /// distance 0 (they walk cell by cell, still exact).
    pub fn with_classes(
        hf: &HeightField,
        data: &'a [u8],
        variant: Variant,
        classes: RayClasses,
    ) -> Result<Self, SafetyError> {
        check_len(
            data,
            map_len_classes(hf.width(), hf.height(), variant, classes),
        )?;
        Ok(SafetyMap {
            data,
            width: hf.width(),
            variant,
            classes,
            rays: Rays::ALL,
            occluders: Occluders::NONE,
        })
    }

    /// The same map, baked for the rays of `rays` ([`bake_rows_classes`] with
    /// `rays.on(hf)`): the march reads it for those rays only ([`Rays::holds`]); any
    /// other ray walks cell by cell (exact).
    pub fn with_rays(self, rays: Rays) -> Self {
        SafetyMap { rays, ..self }
    }

    /// The rays the map is baked for.
    pub fn rays(&self) -> Rays {
        self.rays
    }

    /// The same map of `hf` with the occluders its set passes over
    /// ([`Rays::occluders`]; refused unless they are the set's). Without them a map
    /// baked for occluders holds no ray: every ray walks cell by cell (exact).
    pub fn with_occluders(
        self,
        hf: &HeightField,
        occluders: &'a [Occluder],
    ) -> Result<Self, RaysError> {
        self.rays.check_occluders(occluders)?;
        let occluders = Occluders::prepare(hf, occluders);
        Ok(SafetyMap { occluders, ..self })
    }

    /// The occluders given with [`SafetyMap::with_occluders`].
    pub fn occluders(&self) -> &'a [Occluder] {
        self.occluders.list()
    }

    /// The layout.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// The ray classes the map holds.
    pub fn classes(&self) -> RayClasses {
        self.classes
    }

    /// Where `class`'s distances lie (`None`: not held).
    #[inline]
    fn rows(&self, class: RayClass) -> Option<ClassRows> {
        ClassRows::of(self.width, self.variant, self.classes, class)
    }

    /// Safety distance of texel `(i, j)` for `class` (0 when the map does not hold it).
    #[inline]
    pub fn distance(&self, class: RayClass, i: u32, j: u32) -> u8 {
        self.rows(class).map_or(0, |at| self.data[at.index(i, j)])
    }
}

/// The ray where it crosses the main-axis centerline `m`.
#[derive(Clone, Copy, Debug)]
pub struct Line<R: Real> {
    /// The centerline.
    pub m: u32,
    /// Ray parameter of the crossing.
    pub t: R,
    /// Crossing point (main coordinate exactly `m`).
    pub p: [R; 3],
    /// Clearance from the two samples of the centerline edge under the point.
    pub c: R,
    /// Minor index of that edge's first sample.
    pub edge: u32,
    /// Minor index of the texel whose segment holds the point.
    pub texel: u32,
    /// Bound on the rounding error of `c` and of the minor coordinate (scaled): a
    /// jump is taken only when `c > tol`; `+∞` when the minor coordinate itself may be
    /// off by more than [`SEG_PAD`].
    pub tol: R,
}

/// The parts of [`Frame::line_at`] that depend only on the ray and its main axis,
/// split out of the query's arrays by axis so that the evaluation indexes nothing by
/// the (run-time) axis: the same operations on the same values as [`Query::at`].
#[derive(Clone, Copy, Debug)]
struct Frame<R: Real, const AX: usize> {
    /// Origin and direction on the main axis `AX`.
    om: R,
    dm: R,
    /// Origin and direction on the minor axis.
    on: R,
    dn: R,
    /// Origin and direction in height.
    oz: R,
    dz: R,
    /// Last minor sample index `ln − 1`, as `R`.
    top: R,
    /// Last first-sample index of a centerline edge, `ln − 2`.
    last_edge: u32,
    /// Slice elements between consecutive samples along the main and the minor axis.
    ms: usize,
    ns: usize,
    /// `1 + |o[minor]|`, the start of the minor coordinate's error scale.
    ys0: R,
    /// `1 + |o[2]|`, the start of the height's error scale.
    zs0: R,
}

impl<R: Real, const AX: usize> Frame<R, AX> {
    /// The constants of main axis `AX` for `q`.
    fn new(hf: &HeightField, q: &Query<R>) -> Self {
        let (o, d) = (q.origin(), q.dir());
        let (ax, mi) = (AX, 1 - AX);
        let ln = extents(hf, ax).1;
        let (ms, ns) = strides(hf, ax);
        Frame {
            om: o[ax],
            dm: d[ax],
            on: o[mi],
            dn: d[mi],
            oz: o[2],
            dz: d[2],
            top: R::from_u32(ln - 1),
            last_edge: ln - 2,
            ms,
            ns,
            ys0: R::ONE + o[mi].abs(),
            zs0: R::ONE + o[2].abs(),
        }
    }

    /// Evaluates the crossing of centerline `m` by the ray; two fetches.
    #[inline(always)]
    fn line_at(&self, hf: &HeightField, m: u32) -> Line<R> {
        self.line_through(hf, m, (R::from_u32(m) - self.om) / self.dm)
    }

    /// [`Frame::line_at`] with the ray parameter of the crossing, `t`, already
    /// computed (by the same formula).
    #[inline(always)]
    fn line_through(&self, hf: &HeightField, m: u32, t: R) -> Line<R> {
        let mr = R::from_u32(m);
        // The minor coordinate and the height of `q.at(t)`.
        let pn = self.on + t * self.dn;
        let pz = self.oz + t * self.dz;
        let y = pn.clamp_to(R::ZERO, self.top);
        // `y` is `≥ 0` (or NaN, read as 0 either way): truncation is its floor.
        let edge = (y.to_f64() as u32).min(self.last_edge);
        let v = y - R::from_u32(edge);
        let s0 = m as usize * self.ms + edge as usize * self.ns;
        let samples = hf.samples();
        let h0 = R::from_f32(samples[s0]);
        let h1 = R::from_f32(samples[s0 + self.ns]);
        let c = pz - R::lerp(h0, h1, v);
        let texel = if v < R::HALF { edge } else { edge + 1 };
        let ys = self.ys0 + pn.abs();
        let zs = self.zs0 + pz.abs() + h0.abs() + (h1 - h0).abs() * ys;
        let rel = (R::from_f32(32.0) * R::EPSILON).max(R::from_f64(1.0 / (1u64 << 30) as f64));
        // `8·ε·ys > SEG_PAD`, with the constants divided out (powers of two, and
        // `8·ε·ys` neither overflows nor underflows: the same test) for one compare.
        let tol = if ys > R::from_f64(SEG_PAD) / (R::from_f32(8.0) * R::EPSILON) {
            R::INFINITY
        } else {
            rel * zs
        };
        Line {
            m,
            t,
            p: if AX == 0 { [mr, pn, pz] } else { [pn, mr, pz] },
            c,
            edge,
            texel,
            tol,
        }
    }
}

/// What one stretch of cell-by-cell walking came to.
enum Step<R: Real> {
    /// The exact hit.
    Hit(Hit<R>),
    /// Crossed a main-axis centerline above the surface; the walk stands in the next cell.
    Line(Line<R>),
    /// Left the span or the field without a hit.
    End,
}

/// State of the march: the query, and the cell walk of [`dda::trace`](crate::dda::trace).
struct March<'a, R: Real, const AX: usize> {
    hf: &'a HeightField<'a>,
    surface: Surface,
    q: &'a Query<R>,
    span: Span<R>,
    frame: Frame<R, AX>,
    step: [i64; 2],
    cells: [u32; 2],
    ic: [u32; 2],
    c: [R; 4],
    stale: bool,
    a: [R; 3],
    ca: R,
    ta: R,
    tn: [R; 2],
    fetches: u32,
    clearance: R,
}

impl<R: Real, const AX: usize> March<'_, R, AX> {
    /// A centerline evaluation, counted.
    #[inline(always)]
    fn line(&mut self, m: u32) -> Line<R> {
        self.fetches += 2;
        let l = self.frame.line_at(self.hf, m);
        if l.c > R::ZERO {
            self.clearance = self.clearance.min(l.c);
        }
        l
    }

    /// Puts the walk just past the crossing `l` (above the surface).
    #[inline(always)]
    fn enter(&mut self, l: &Line<R>) {
        let (ax, mi) = (AX, 1 - AX);
        let (o, d) = (self.q.origin(), self.q.dir());
        self.ic[ax] = if self.step[ax] > 0 { l.m } else { l.m - 1 };
        let y = l.p[mi].clamp_to(R::ZERO, R::from_u32(self.cells[mi]));
        self.ic[mi] = cell_index(y, d[mi], self.cells[mi]);
        self.a[ax] = if self.step[ax] > 0 { R::ZERO } else { R::ONE };
        self.a[mi] = (l.p[mi] - R::from_u32(self.ic[mi])).clamp_to(R::ZERO, R::ONE);
        self.a[2] = l.p[2];
        self.ca = l.c;
        self.ta = l.t;
        for k in 0..2 {
            self.tn[k] = next_crossing(self.ic[k], self.step[k], o[k], d[k]);
        }
        self.stale = true;
    }

    /// Walks cell by cell, as [`dda::trace`](crate::dda::trace), up to the next
    /// main-axis centerline, the hit, or the end. Inlined into its one call site (left
    /// to the heuristics, a build that instantiates the march for both surfaces, as the
    /// C API's, kept it a call: ~30% slower).
    #[inline(always)]
    fn walk(&mut self) -> Step<R> {
        let (ax, mi) = (AX, 1 - AX);
        let (o, d) = (self.q.origin(), self.q.dir());
        loop {
            if self.stale {
                self.c = corners(self.hf, self.ic[0], self.ic[1]);
                self.fetches += 4;
                self.stale = false;
            }
            let t_next = self.tn[0].min(self.tn[1]);
            let (tb, cross) = if t_next < self.span.t1 {
                (
                    t_next.max(self.ta),
                    [self.tn[0] <= t_next, self.tn[1] <= t_next],
                )
            } else {
                (self.span.t1, [false; 2])
            };
            let on = [
                cross[0].then_some(self.step[0] > 0),
                cross[1].then_some(self.step[1] > 0),
            ];
            let p = self.q.at(tb);
            let (b, mut cb) = local_clearance(self.surface, self.c, self.ic, p, on);
            let mut line = None;
            if cross[ax] {
                // The clearance the jumps use at this centerline (same samples, same
                // arithmetic), so walking and jumping agree.
                let m = if self.step[ax] > 0 {
                    self.ic[ax] + 1
                } else {
                    self.ic[ax]
                };
                // `tn[ax]` is this crossing's parameter: [`next_crossing`] computes it
                // as `(m − o[ax]) / d[ax]`, exactly as [`Frame::line_at`] does.
                let l = self.frame.line_through(self.hf, m, self.tn[ax]);
                if l.edge != self.ic[mi] {
                    self.fetches += 2;
                }
                cb = l.c;
                line = Some(l);
            }
            // The entry wall is for the discontinuous surfaces: the two march surfaces
            // never read it, so no walk keeps track of it.
            let wall = [R::ZERO, R::ZERO, R::ONE];
            let seg = self
                .surface
                .segment_hit(self.c, self.a, b, self.ca, cb, wall);
            self.clearance = self.clearance.min(seg.clearance);
            if let Some(found) = seg.hit {
                let ends = ((self.ta, tb), (self.a, b));
                return Step::Hit(segment_point(self.ic, ends, found));
            }
            if !(cross[0] || cross[1]) {
                return Step::End;
            }
            for k in 0..2 {
                if cross[k] {
                    let next = i64::from(self.ic[k]) + self.step[k];
                    if next < 0 || next >= i64::from(self.cells[k]) {
                        return Step::End;
                    }
                    self.ic[k] = next as u32;
                    self.tn[k] = next_crossing(self.ic[k], self.step[k], o[k], d[k]);
                }
            }
            self.a = [
                if cross[0] { R::ONE - b[0] } else { b[0] },
                if cross[1] { R::ONE - b[1] } else { b[1] },
                b[2],
            ];
            self.ca = cb;
            self.ta = tb;
            self.stale = true;
            if let Some(l) = line {
                return Step::Line(l);
            }
        }
    }

    /// The answer once the march is over.
    fn done(&self, hit: Option<Hit<R>>, flags: Flags) -> Trace<R> {
        Trace {
            hit,
            fetches: self.fetches,
            clearance: self.clearance,
            flags,
        }
    }
}

/// Last main-axis centerline the ray crosses strictly before the end of the span
/// (`None` when there is none), computed with the crossing formula of the walk.
fn last_line<R: Real>(hf: &HeightField, q: &Query<R>, ax: usize, sg: i64, t1: R) -> Option<u32> {
    let (o, d) = (q.origin(), q.dir());
    let (lm, _) = extents(hf, ax);
    let t_of = |m: i64| (R::from_u32(m as u32) - o[ax]) / d[ax];
    let inside = |m: i64| m >= 0 && m < i64::from(lm);
    let x1 = (o[ax] + t1 * d[ax]).clamp_to(R::ZERO, R::from_u32(lm - 1));
    // `x1 >= 0` (or NaN, read as 0 either way): truncation is its floor.
    let below = x1.to_f64() as i64;
    let mut m = below + i64::from(sg < 0 && R::from_u32(below as u32) != x1);
    while inside(m) && t_of(m) >= t1 {
        m -= sg;
    }
    while inside(m + sg) && t_of(m + sg) < t1 {
        m += sg;
    }
    inside(m).then_some(m as u32)
}

/// Traces `q` on the triangle surface with the safety distances of `map` (baked for
/// `hf`). Exact: the same hit as [`dda::trace`](crate::dda::trace) with
/// [`Surface::Triangles`], up to rounding on rays that graze the surface.
///
/// Cost: one fetch per distance read, two per centerline clearance, four per cell
/// walked. [`Trace::clearance`] is the smallest clearance at the crossings evaluated
/// (not the whole ray's). The march takes at most one step per centerline; a step
/// bound guards it ([`Flags::BUDGET_EXHAUSTED`], never expected).
pub fn trace<R: Real>(map: &SafetyMap, hf: &HeightField, q: &Query<R>) -> Trace<R> {
    trace_on(map, hf, MarchSurface::Triangles, q)
}

/// [`trace`] finishing on `surface`: with [`MarchSurface::ViewLinear`], the same hit
/// as [`dda::trace`](crate::dda::trace) with [`Surface::ViewLinear`], from the same
/// map.
pub fn trace_on<R: Real>(
    map: &SafetyMap,
    hf: &HeightField,
    surface: MarchSurface,
    q: &Query<R>,
) -> Trace<R> {
    let held = map.rays.holds_over(hf, &map.occluders, q);
    march_with(hf, surface, q, |class| {
        // A class the map does not hold, or a ray outside its set: distance 0 (zero
        // jumps, exact).
        let at = map.rows(class).filter(|_| held);
        move |_: &Line<R>, _, i, j| {
            Jump::steps(at.map_or(0, |at| u32::from(map.data[at.index(i, j)])))
        }
    })
}

/// The surfaces a safety-shape march can finish on, from maps baked for the triangle
/// surface (§7 of the paper).
///
/// Why one map serves both: on every grid line the two surfaces have the same height
/// (the edge interpolation of its two samples), and between consecutive grid-line
/// crossings of a ray the view-linear surface is linear along the ray. A jump is
/// taken only when the baked shape says the ray, above the surface where it starts,
/// cannot leave the triangle solid before the target; above at both ends, it then
/// stays above the triangle surface all the way, so its clearance is positive at
/// every grid-line crossing in between, hence above the view-linear surface too. The
/// final test in the one or two cells left is then a segment intersection: the ray
/// and the surface are both linear between crossings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MarchSurface {
    /// The triangle surface ([`Surface::Triangles`]), for which the maps are baked.
    #[default]
    Triangles,
    /// The view-linear surface ([`Surface::ViewLinear`]).
    ViewLinear,
}

impl MarchSurface {
    /// The march surface for `surface`, `None` for a surface the maps do not bound.
    pub fn of(surface: Surface) -> Option<Self> {
        match surface {
            Surface::Triangles => Some(MarchSurface::Triangles),
            Surface::ViewLinear => Some(MarchSurface::ViewLinear),
            _ => None,
        }
    }

    /// The surface it is.
    pub fn surface(self) -> Surface {
        match self {
            MarchSurface::Triangles => Surface::Triangles,
            MarchSurface::ViewLinear => Surface::ViewLinear,
        }
    }
}

/// What a step function answers at a crossing: how many centerlines the ray may skip,
/// and the fetches it made beyond the read of the texel's baked data, which the march
/// counts itself (the cylinder–cone base's third sample, [`cc`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Jump {
    /// Centerlines the ray may skip.
    pub(crate) steps: u32,
    /// Fetches beyond the texel's data.
    pub(crate) fetches: u32,
}

impl Jump {
    /// `steps` centerlines, no fetch beyond the texel's data.
    #[inline]
    pub(crate) fn steps(steps: u32) -> Self {
        Jump { steps, fetches: 0 }
    }
}

/// The march shared by the safety-shape methods: `jump(line, class, i, j)` reads the
/// baked data of texel `(i, j)` (one fetch, counted here) and returns how many
/// centerlines the ray crossing `line` above that texel's segment may skip; the walk
/// between jumps and the final test use `surface`.
pub(crate) fn march<R: Real>(
    hf: &HeightField,
    surface: MarchSurface,
    q: &Query<R>,
    jump: impl Fn(&Line<R>, RayClass, u32, u32) -> u32,
) -> Trace<R> {
    march_with(hf, surface, q, |_| {
        move |l: &Line<R>, class, i, j| Jump::steps(jump(l, class, i, j))
    })
}

/// [`march`] with the step function built by `setup` for the ray's class, called once
/// the ray is known to march (it meets the field's box and starts above the surface):
/// the per-trace constants of a step function then cost nothing on the rays that miss
/// the box or start under the surface.
pub(crate) fn march_with<R: Real, J: Fn(&Line<R>, RayClass, u32, u32) -> Jump>(
    hf: &HeightField,
    surface: MarchSurface,
    q: &Query<R>,
    setup: impl FnOnce(RayClass) -> J,
) -> Trace<R> {
    let Some(span) = clip(hf, q) else {
        return Trace::MISS;
    };
    let d = q.dir();
    let cells = [hf.width() - 1, hf.height() - 1];
    let p0 = q.at(span.t0);
    let x0 = p0[0].clamp_to(R::ZERO, R::from_u32(cells[0]));
    let y0 = p0[1].clamp_to(R::ZERO, R::from_u32(cells[1]));
    let ic = [
        cell_index(x0, d[0], cells[0]),
        cell_index(y0, d[1], cells[1]),
    ];
    let c: [R; 4] = corners(hf, ic[0], ic[1]);
    let surface = surface.surface();
    let (a, ca) = local_clearance(
        surface,
        c,
        ic,
        [x0, y0, p0[2]],
        entry_on(surface, &span.entry),
    );
    if ca <= R::ZERO {
        return Trace::hit(
            start_hit(surface, &span, c, ic, a, p0),
            4,
            start_clearance(&span.entry, ca),
        );
    }
    let start = Start {
        span,
        cells,
        ic,
        c,
        a,
        ca,
    };
    finish(hf, surface, q, march_above(hf, surface, q, start, setup))
}

/// [`march_with`] for a ray that starts above the surface at `start`. Not inlined
/// there: the rays that miss the field or start under the surface, most rays of a
/// camera's image, then run a short function (and spill nothing for a march).
#[inline(never)]
fn march_above<R: Real, J: Fn(&Line<R>, RayClass, u32, u32) -> Jump>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    start: Start<R>,
    setup: impl FnOnce(RayClass) -> J,
) -> Trace<R> {
    let d = q.dir();
    let class = RayClass::of(d[0], d[1]);
    let jump = setup(class);
    // One instance of the rest per main axis, which indexes the walk's state on every
    // step: a constant there.
    if axis_of(class) == 0 {
        march_from::<R, J, 0>(hf, surface, q, class, start, jump)
    } else {
        march_from::<R, J, 1>(hf, surface, q, class, start, jump)
    }
}

/// Where the walk of a march begins: the span, the cell counts per axis, the first
/// cell (its corners `c`), the local start point `a` above the surface by `ca`.
struct Start<R: Real> {
    span: Span<R>,
    cells: [u32; 2],
    ic: [u32; 2],
    c: [R; 4],
    a: [R; 3],
    ca: R,
}

/// [`march_with`] from the start, for rays of main axis `AX` (of class `class`).
fn march_from<R: Real, J: Fn(&Line<R>, RayClass, u32, u32) -> Jump, const AX: usize>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    class: RayClass,
    start: Start<R>,
    jump: J,
) -> Trace<R> {
    let ax = AX;
    let (o, d) = (q.origin(), q.dir());
    let Start {
        span,
        cells,
        ic,
        c,
        a,
        ca,
    } = start;
    // Here rather than in [`march_with`]: the rays that start under the surface need none.
    let step = [step_of(d[0]), step_of(d[1])];
    let mut mr = March::<R, AX> {
        hf,
        surface,
        q,
        span,
        frame: Frame::new(hf, q),
        step,
        cells,
        ic,
        c,
        stale: false,
        a,
        ca,
        ta: span.t0,
        tn: [
            next_crossing(ic[0], step[0], o[0], d[0]),
            next_crossing(ic[1], step[1], o[1], d[1]),
        ],
        fetches: 4,
        clearance: ca,
    };
    let sg = step[ax];
    let last = if sg == 0 {
        None
    } else {
        last_line(hf, q, ax, sg, span.t1)
    };
    let mut budget = extents(hf, ax).0 + 8;
    // One call site of the walk (the outer loop), so that it inlines into the march;
    // the inner loop jumps from crossing to crossing while the data allows, and hands
    // back to the walk when it does not.
    loop {
        let mut l = match mr.walk() {
            Step::Hit(h) => return mr.done(Some(h), Flags::default()),
            Step::End => return mr.done(None, Flags::default()),
            Step::Line(l) => l,
        };
        // A jump landed on the crossing `l`, and the walk has not been put past it yet:
        // [`March::enter`] waits until a walk follows (the next jump needs none).
        let mut landed = false;
        loop {
            if budget == 0 {
                return mr.done(None, Flags::BUDGET_EXHAUSTED);
            }
            budget -= 1;
            let k = match last {
                Some(last) if last != l.m && l.c > l.tol => {
                    mr.fetches += 1;
                    let (i, j) = if ax == 0 {
                        (l.m, l.texel)
                    } else {
                        (l.texel, l.m)
                    };
                    let jump = jump(&l, class, i, j);
                    mr.fetches += jump.fetches;
                    // At most to the last centerline (`room > 0`: a zero step stays zero).
                    let room = (i64::from(last) - i64::from(l.m)).unsigned_abs() as u32;
                    jump.steps.min(room)
                }
                _ => 0,
            };
            if k == 0 {
                if landed {
                    mr.enter(&l);
                }
                break;
            }
            let target = (i64::from(l.m) + sg * i64::from(k)) as u32;
            let lt = mr.line(target);
            if lt.c > R::ZERO {
                l = lt;
                landed = true;
                continue;
            }
            // Below at the target, above at `m`, and no exit in between: bisect.
            let (mut lo, mut hi) = (l, target);
            while (i64::from(hi) - i64::from(lo.m)).abs() > 1 {
                let mid = ((i64::from(hi) + i64::from(lo.m)) / 2) as u32;
                let lm = mr.line(mid);
                if lm.c > R::ZERO {
                    lo = lm;
                } else {
                    hi = mid;
                }
            }
            mr.enter(&lo);
            break;
        }
    }
}
