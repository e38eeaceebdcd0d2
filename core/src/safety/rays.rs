//! Ray sets narrower than every ray: exterior rays, a largest view angle and rays
//! over static occluders (Baboud, Eisemann, Seidel 2011, §6.2), for both safety-shape
//! bakes (the distances of the parent module, the cylinder–cone slopes of
//! [`super::cc`]) and their marches. Occluders cut the candidate lines as the
//! surface's blockers do ([`Rays::on_over`]; docs/DESIGN.md, "Ray sets", says why).
//!
//! **What a map holds** ([`Rays`]): a bake for a ray set is exact for the rays of the
//! set only, so a map carries its set, and the march checks every ray against it
//! ([`Rays::holds`]). A ray outside the set reads distance 0 (and no cone) at every
//! texel: it walks cell by cell, exact like [`dda::trace`](crate::dda::trace). That is
//! the guard; `core/tests/exterior.rs` shows a ray it saves.
//!
//! **Why a triangle limits** (the test of [`RaysOn::limiting`]). Let a ray `r` of the
//! set pass above the surface at `P` on a texel's segment and cross the plane `P_T` of
//! a triangle `T` upwards at `Q` in `T`. Lift it into the plane: `L` is the line of
//! `P_T` through `Q` with the same horizontal direction (through `P' = (P, P_T(P))`,
//! above `P` since `r` is under `P_T` before `Q`). Behind `Q`, `L` is above `r`, and
//! the further back the more. So:
//! - *exterior* (the ray starts outside the field's box): `r` is above the surface
//!   everywhere behind `P` in the field (it came from outside, and a ray under the
//!   surface would have hit it), hence so is `L`. `T` cannot limit unless some line of
//!   `P_T` through `T`, over the segment at `P'` (not under the surface there), in the
//!   class's quadrant, stays above the surface behind the segment. (The issue that
//!   asked for this, #20, put the blockers between the segment and `T`; there `r` is
//!   *under* `L`, and a line of the plane through a ridge between them says nothing
//!   about `r`, which dives into that ridge and out through `T`. The blockers are the
//!   surface *behind* the segment.)
//! - *largest view angle* `α` from the downward vertical (the scene's
//!   `max_view_angle_deg`): `r` rises at most `τ = −cot α` per unit of horizontal
//!   distance; crossing `P_T` upwards, it rises faster than the plane along its
//!   direction, so the plane's slope along `PQ` is below `τ`.
//!
//! Lines of `P_T` are the horizontal lines under it, so everything is 2-D, in the
//! class's frame (forward `u` from the texel's centerline, minor `v`): a line is
//! `v = y₀ + s·u`, the point `(y₀, s)` of the *dual* plane, `|s| ≤ 1` in the class's
//! quadrant. The candidate lines start as one box per half of the segment (where
//! `P_T ≥ σ`), cut by the view-angle half-plane (linear in `s`, after bounding
//! `√(1 + s²)`), less the lines that pass all vertices of `T` on one side. Then, for
//! an exterior set, the columns of cells behind the segment are scanned by increasing
//! distance: in every triangle `Δ` where the surface is above `P_T` (a convex part
//! `K` of `Δ`: the surface minus the plane is linear there), the lines through the
//! open `K` are below the surface, and subtracting them from a convex dual polygon
//! leaves two (the lines with every vertex of `K` on one side, and on the other).
//! Every point of the surface is on a triangle, so this is the whole surface behind,
//! exactly; only the cells a remaining line crosses are visited. `T` is limiting when
//! a line remains once the scan leaves the field, or rises above the field's highest
//! sample for good; not limiting when none remains.
//!
//! **Rounding** (every test may only keep more lines): all sets are closed and grown
//! by [`EPS`] (dual coordinates) or [`tol`](RaysOn) (heights); a blocker is the part
//! of `Δ` where the surface is above the plane by twice the height tolerance. Dual
//! polygons are clipped in `f64`; a clip that would overflow a polygon's vertex array
//! keeps the polygon unclipped, a scan that would overflow the polygon list, or run
//! past [`MAX_BEHIND`] columns, answers "limiting". All of that can only make
//! distances smaller (slower), never a ray wrong.

use core::cell::RefCell;

use heapless::Vec;

use super::{cell_corners, tri_masks, AllRays, RaySet, Sigma, Tri};
use crate::field::HeightField;
use crate::ray::{Query, RayClass};
use crate::rayset::{Occluder, Rays, RaysError};

impl Rays {
    /// The set as the bake tests it, for the field `hf`, without occluders: for a set
    /// with occluders this bakes the set without them (larger, so the map is safe for
    /// it too, only less tight); [`Rays::on_over`] gives them.
    pub fn on<'a>(self, hf: &'a HeightField<'a>) -> RaysOn<'a> {
        let top = f64::from(hf.max_height());
        let low = f64::from(hf.min_height());
        let tau = self.rise_bound();
        let rise = if tau < 0.0 {
            tau
        } else {
            tau * core::f64::consts::SQRT_2
        };
        RaysOn {
            hf,
            rays: self,
            tau: tau + 1e-6 * (1.0 + tau.abs()),
            rise: rise + 1e-6 * (1.0 + rise.abs()),
            top,
            tol: 1e-7 * (1.0 + top.abs().max(low.abs())),
            sliver: 1e-12 * (1.0 + top.abs().max(low.abs())),
            occluders: &[],
            occluder_tol: 0.0,
            scan: RefCell::new(Scan::new()),
        }
    }

    /// The set as the bake tests it, for the field `hf`, with the set's occluders
    /// (refused unless they are the set's, [`Rays::check_occluders`]).
    pub fn on_over<'a>(
        self,
        hf: &'a HeightField<'a>,
        occluders: &'a [Occluder],
    ) -> Result<RaysOn<'a>, RaysError> {
        self.check_occluders(occluders)?;
        let size = occluders
            .iter()
            .flat_map(|o| o.corners.iter().flatten())
            .fold(0f64, |m, c| m.max(f64::from(c.abs())));
        let on = self.on(hf);
        Ok(RaysOn {
            occluders,
            occluder_tol: on.tol + 1e-7 * size,
            ..on
        })
    }
}

/// What [`RaysOn::witness`] finds in a column of cells ahead of a texel.
#[derive(Clone, Copy, Debug)]
pub enum Witness {
    /// An explicit ray of the set that leaves the solid in the column.
    Ray(Query<f64>),
    /// A triangle of the column limits only because the scan gave up (too many
    /// polygons, or [`MAX_BEHIND`] columns behind) or by the growth of its sets (a
    /// line that meets the triangle on the centerline only): no ray to show.
    NoRay,
    /// No triangle of the column limits.
    None,
}

/// A [`Rays`] set bound to its field: the [`RaySet`] both bakes scan with. It holds
/// the scan's buffers (tens of kilobytes), so make one per thread and bake many
/// texels with it.
#[derive(Debug)]
pub struct RaysOn<'a> {
    hf: &'a HeightField<'a>,
    rays: Rays,
    /// [`Rays::rise_bound`] grown a millionth (`+∞` for any direction).
    tau: f64,
    /// The largest rise along a quadrant direction (per unit of its length) of the
    /// plane of a triangle that a ray of the set may cross upwards: [`Rays::rise_bound`]
    /// `τ` (for `τ < 0`; `τ·√2` else) grown a millionth; `+∞` for any direction. The
    /// plane's rise along `(1, s)` is `(f + g·s)/√(1 + s²)`, and `√(1 + s²) ∈ [1, √2]`.
    rise: f64,
    /// The field's highest sample.
    top: f64,
    /// Height tolerance: larger than any rounding of a plane's height in the field.
    tol: f64,
    /// How far a plane must rise above the surface on the segment for a ray to pass
    /// between them, `10⁻¹²·(1 + max |h|)`: a thousand times the rounding of the
    /// comparison in `f64`, far below the grazing threshold under which docs/DESIGN.md
    /// calls a ray ambiguous (a ray closer to the surface than that is a touch).
    /// Where the segment lies on the triangle's own edge, the plane *is* the surface
    /// there, and only touching rays lie between.
    sliver: f64,
    /// The set's occluders ([`Rays::on_over`]; none for [`Rays::on`]).
    occluders: &'a [Occluder],
    /// Height tolerance at the occluders: [`RaysOn::tol`](RaysOn) grown by their
    /// coordinates' size (a plane's height far from the field rounds more).
    occluder_tol: f64,
    /// The buffers of [`RaySet::limiting`]'s scan, reused by every triangle tested:
    /// clearing new ones per triangle cost a tenth of the bake.
    scan: RefCell<Scan>,
}

/// The buffers of one triangle's scan.
#[derive(Debug)]
struct Scan {
    /// The candidate lines ([`RaysOn::candidates`]).
    pieces: Pieces,
    /// The polygons [`RaysOn::survives`] has still to take through the columns behind.
    stack: Stack,
}

impl Scan {
    const fn new() -> Self {
        Scan {
            pieces: Pieces::new(),
            stack: Vec::new(),
        }
    }
}

/// Growth of every dual set (dual coordinates are minor coordinates and slopes: far
/// above their rounding in fields of up to 2²⁰ samples across).
pub const EPS: f64 = 1e-7;

/// Columns behind a segment the exterior scan visits before it gives up ("limiting").
pub const MAX_BEHIND: u32 = 16;

/// Vertices of a dual polygon.
const VERTS: usize = 16;

/// Dual polygons a scan holds at once.
const PIECES: usize = 48;

/// A point of the dual plane: the line `v = y₀ + s·u`, as `[y₀, s]`.
type Dual = [f64; 2];

/// A convex polygon of the dual plane, its vertices in order.
type Poly = Vec<Dual, VERTS>;

/// A closed half-plane of the dual plane, `a·y₀ + b·s + c ≥ 0`.
type Half = [f64; 3];

/// The lines above (or through) the point `(u, v)` of the frame, grown by [`EPS`]:
/// `y₀ + s·u − v ≥ −EPS`.
#[inline]
fn above(u: f64, v: f64) -> Half {
    [1.0, u, EPS - v]
}

/// The lines below (or through) `(u, v)`, grown by [`EPS`].
#[inline]
fn below(u: f64, v: f64) -> Half {
    [-1.0, -u, EPS + v]
}

#[inline]
fn side(h: &Half, p: &Dual) -> f64 {
    h[0] * p[0] + h[1] * p[1] + h[2]
}

/// `p` ∩ `h` (Sutherland–Hodgman); `p` itself when the result would not fit.
fn clip(p: &Poly, h: &Half) -> Poly {
    let mut out = Poly::new();
    clip_into(p, h, &mut out);
    out
}

/// [`clip`] into `out` (a polygon is hundreds of bytes: written in place, not moved).
fn clip_into(p: &Poly, h: &Half, out: &mut Poly) {
    out.clear();
    let n = p.len();
    for k in 0..n {
        let (a, b) = (p[k], p[(k + 1) % n]);
        let (sa, sb) = (side(h, &a), side(h, &b));
        if sa >= 0.0 && out.push(a).is_err() {
            out.clone_from(p);
            return;
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            let t = sa / (sa - sb);
            let x = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            if out.push(x).is_err() {
                out.clone_from(p);
                return;
            }
        }
    }
}

/// `p` ∩ every half-plane of `hs`, clipping back and forth between two polygons.
fn clip_all(p: &Poly, hs: &[Half]) -> Poly {
    let (mut a, mut b) = (p.clone(), Poly::new());
    let mut in_a = true;
    for h in hs {
        if in_a {
            clip_into(&a, h, &mut b);
        } else {
            clip_into(&b, h, &mut a);
        }
        in_a = !in_a;
        if (if in_a { &a } else { &b }).is_empty() {
            break;
        }
    }
    if in_a {
        a
    } else {
        b
    }
}

/// A polygon, the column behind the segment it is in, and the first blocker of that
/// column (`2·cell + triangle`) it has still to pass.
type Stack = Vec<(Poly, u32, u32), PIECES>;

/// The polygons a scan holds; `Err` once they would not fit (the caller then answers
/// "limiting"). Two lists that take turns ([`Pieces::keep_meeting`] reads one and
/// fills the other): a list is kilobytes, so it is filled and read in place, never
/// moved or returned (moving them was half of an exterior bake's time).
#[derive(Debug)]
struct Pieces {
    lists: [Vec<Poly, PIECES>; 2],
    /// Which list holds the polygons.
    live: usize,
}

/// The list overflowed.
struct Full;

/// Appends `p` to `list` unless it is empty (fewer than 3 vertices).
fn add(list: &mut Vec<Poly, PIECES>, p: Poly) -> Result<(), Full> {
    if p.len() < 3 {
        return Ok(());
    }
    list.push(p).map_err(|_| Full)
}

impl Pieces {
    const fn new() -> Self {
        Pieces {
            lists: [Vec::new(), Vec::new()],
            live: 0,
        }
    }

    /// Empties both lists.
    fn clear(&mut self) {
        self.lists.iter_mut().for_each(Vec::clear);
        self.live = 0;
    }

    /// The polygons.
    fn polys(&self) -> &[Poly] {
        &self.lists[self.live]
    }

    fn add(&mut self, p: Poly) -> Result<(), Full> {
        add(&mut self.lists[self.live], p)
    }

    /// Removes the lines through the open convex hull of `pts` ([`split`]), in place:
    /// the polygons on one side stay where they are (copying them was a fifth of a
    /// bake over occluders).
    fn remove_through(&mut self, pts: &[[f64; 2]]) -> Result<(), Full> {
        let list = &mut self.lists[self.live];
        for k in 0..list.len() {
            if let Some([x, y]) = split(&list[k], pts) {
                list[k] = x;
                add(list, y)?;
            }
        }
        list.retain(|p| p.len() >= 3);
        Ok(())
    }

    /// Keeps the lines that meet the closed triangle `verts` (grown by [`EPS`]): the
    /// lines not strictly above all of its vertices nor strictly below all of them.
    fn keep_meeting(&mut self, verts: &[[f64; 2]; 3]) -> Result<(), Full> {
        for dir in [below as fn(f64, f64) -> Half, above] {
            let [a, b] = &mut self.lists;
            let (old, new) = if self.live == 0 { (a, b) } else { (b, a) };
            new.clear();
            self.live ^= 1;
            for p in old.iter() {
                // Through or on this side of a vertex, the first such vertex being
                // `k` (the parts are disjoint but for their common edges).
                let mut rest = p.clone();
                for (k, &[u, v]) in verts.iter().enumerate() {
                    let h = dir(u, v);
                    add(new, clip(&rest, &h))?;
                    if k == 2 {
                        break;
                    }
                    let not = [-h[0], -h[1], -h[2]];
                    rest = clip(&rest, &not);
                    if rest.len() < 3 {
                        break;
                    }
                }
            }
        }
        Ok(())
    }
}

impl RaysOn<'_> {
    /// The set this bake scans with.
    pub fn rays(&self) -> Rays {
        self.rays
    }

    /// Height of `tri`'s plane at frame point `(u, v)`.
    #[inline]
    fn plane(tri: &Tri, u: f64, v: f64) -> f64 {
        tri.height_on_line(v) + tri.forward_slope * u
    }

    /// The candidate lines: over the segment where the plane is not under the surface
    /// (per half of the segment), in the quadrant, within the view angle, meeting `T`.
    fn candidates(&self, sigma: &Sigma, tri: &Tri, pieces: &mut Pieces) -> Result<(), Full> {
        let s_lim = 1.0 + EPS;
        for (a, b) in [(sigma.lo, sigma.n), (sigma.n, sigma.hi)] {
            // `P_T − σ` is linear on the half: where it is above `sliver` (a ray between
            // the surface and the plane needs room there; see [`RaysOn::sliver`]).
            let g = |y: f64| tri.height_on_line(y) - sigma.height(y);
            let (ga, gb) = (g(a), g(b));
            let t = self.sliver;
            let (lo, hi) = match (ga >= t, gb >= t) {
                (true, true) => (a, b),
                (false, false) => continue,
                (true, false) => (a, a + (b - a) * ((ga - t) / (ga - gb))),
                (false, true) => (a + (b - a) * ((ga - t) / (ga - gb)), b),
            };
            let (lo, hi) = (lo - EPS, hi + EPS);
            let mut p = Poly::new();
            for x in [[lo, -s_lim], [hi, -s_lim], [hi, s_lim], [lo, s_lim]] {
                let _ = p.push(x);
            }
            if self.tau.is_finite() {
                // The plane's rise along (1, s) per unit length at most `τ`: one or two
                // intervals of slopes ([`slopes_below`]).
                for (sa, sb) in slopes_below(tri.forward_slope, tri.minor_slope, self.tau) {
                    let q = clip(&p, &[0.0, 1.0, EPS - sa]);
                    pieces.add(clip(&q, &[0.0, -1.0, sb + EPS]))?;
                }
                continue;
            }
            pieces.add(p)?;
        }
        pieces.keep_meeting(&tri.verts)?;
        for o in self.occluders {
            let k = self.occluder_blocker(sigma, tri, o);
            if k.len() >= 2 {
                pieces.remove_through(&k)?;
            }
        }
        Ok(())
    }

    /// Where the solid under occluder `o` rises above `tri`'s plane by twice the
    /// tolerance behind the segment (`u ≤ 0`), in the frame: a line of the plane
    /// through it dips under the occluder before the segment, and so does every ray of
    /// the set that it lifts (it is under the line there), which the set excludes.
    fn occluder_blocker(&self, sigma: &Sigma, tri: &Tri, o: &Occluder) -> Poly {
        let vs: Vec<(f64, f64, f64), 3> = o
            .corners_f64()
            .iter()
            .map(|c| {
                let (main, minor) = if sigma.ax == 0 {
                    (c[0], c[1])
                } else {
                    (c[1], c[0])
                };
                let u = (sigma.sg as f64) * (main - f64::from(sigma.m));
                (u, minor, c[2] - Self::plane(tri, u, minor))
            })
            .collect();
        let mut k = Poly::new();
        for x in blocker(&vs, 2.0 * self.occluder_tol) {
            let _ = k.push(x);
        }
        // Behind the segment: `−u ≥ 0` (the points are primal `[u, v]` here).
        clip(&k, &[-1.0, 0.0, 0.0])
    }

    /// Whether a line of `pieces` survives the surface behind the segment (exterior):
    /// depth first, one polygon at a time through the columns behind, so that the
    /// first line found clear ends the search. That line is the answer: a vertex that
    /// got clear; for a `witness`, the centre of a polygon that crossed every column
    /// behind (inside every set kept: clear with a margin), with no column limit.
    fn survives(
        &self,
        sigma: &Sigma,
        tri: &Tri,
        pieces: &Pieces,
        stack: &mut Stack,
        witness: bool,
    ) -> Result<Option<Dual>, Full> {
        let hf = self.hf;
        let (ax, sg) = (sigma.ax, sigma.sg);
        let (lm, ln) = super::extents(hf, ax);
        let m = sigma.m;
        // Cell columns behind the segment before the field ends (a scan that would
        // go further gives up: "limiting").
        let behind = if sg > 0 { m } else { lm - 1 - m };
        let last = if witness {
            behind
        } else {
            behind.min(MAX_BEHIND)
        };
        let top_v = f64::from(ln - 1);
        let lim = 2.0 * self.tol;
        stack.clear();
        for p in pieces.polys() {
            stack.push((p.clone(), 1, 0)).map_err(|_| Full)?;
        }
        let mut best: Option<Poly> = None;
        'jobs: while let Some((mut p, mut j, mut from)) = stack.pop() {
            loop {
                if j > last {
                    // Past the field's end (clear), or given up. A witness keeps the
                    // widest polygon that gets through.
                    if last < behind {
                        return Err(Full);
                    }
                    if !witness {
                        return Ok(Some(centre(&p)));
                    }
                    if best.as_ref().is_none_or(|b| area(b) < area(&p)) {
                        best = Some(p);
                    }
                    continue 'jobs;
                }
                // The column of cells between `u = −j` and `u = −(j − 1)`.
                let cm = if sg > 0 { m - j } else { m + j - 1 };
                let (u0, u1) = (-f64::from(j), -f64::from(j - 1));
                // The minor range the polygon's lines cross there.
                let (mut vmin, mut vmax) = (f64::INFINITY, f64::NEG_INFINITY);
                for &[y0, s] in &p {
                    for u in [u0, u1] {
                        let v = y0 + s * u;
                        vmin = vmin.min(v);
                        vmax = vmax.max(v);
                    }
                }
                if vmax >= 0.0 && vmin <= top_v {
                    let c0 = libm::floor(vmin.max(0.0)) as u32;
                    let c1 = (libm::floor(vmax.min(top_v)) as u32).min(ln - 2);
                    for l in c0..=c1 {
                        if 2 * l + 1 < from {
                            continue;
                        }
                        let h = cell_corners(hf, ax, cm, l);
                        // Corner `q` (bit 0 along x, bit 1 along y) in the frame, and
                        // the surface's height above the plane there.
                        let corner = |q: usize| {
                            let (a, b) = if ax == 0 {
                                (q & 1, q >> 1)
                            } else {
                                (q >> 1, q & 1)
                            };
                            let u = (sg as f64) * (f64::from(cm) + a as f64 - f64::from(m));
                            let v = f64::from(l) + b as f64;
                            (u, v, f64::from(h[q]) - Self::plane(tri, u, v))
                        };
                        let cs: [(f64, f64, f64); 4] = core::array::from_fn(corner);
                        if cs.iter().all(|c| c.2 < lim) {
                            continue;
                        }
                        for (t, mask) in (0u32..).zip(tri_masks(h)) {
                            let key = 2 * l + t;
                            if key < from {
                                continue;
                            }
                            let vs: Vec<(f64, f64, f64), 3> = (0..4)
                                .filter(|q| mask >> q & 1 == 1)
                                .map(|q| cs[q])
                                .collect();
                            let k = blocker(&vs, lim);
                            if k.len() < 2 {
                                continue;
                            }
                            let Some([a, b]) = split(&p, &k) else {
                                continue;
                            };
                            match (a.len() >= 3, b.len() >= 3) {
                                (false, false) => continue 'jobs,
                                (true, false) => p = a,
                                (false, true) => p = b,
                                (true, true) => {
                                    stack.push((b, j, key + 1)).map_err(|_| Full)?;
                                    p = a;
                                }
                            }
                        }
                    }
                }
                // A line that leaves the field sideways, or rises above its highest
                // sample for good, is clear all the way: exterior.
                for &x @ [y0, s] in p.iter().filter(|_| !witness) {
                    let v = y0 + s * u0;
                    let rising_back = -(tri.forward_slope + tri.minor_slope * s) >= 0.0;
                    if v < 0.0
                        || v > top_v
                        || rising_back && Self::plane(tri, u0, v) > self.top + lim
                    {
                        return Ok(Some(x));
                    }
                }
                j += 1;
                from = 0;
            }
        }
        Ok(best.map(|p| centre(&p)))
    }

    /// A line of `tri`'s plane that limits the segment `sigma` for the set
    /// ([`RaySet::limiting`]'s witness): `Some(None)` when the answer "limiting" has
    /// no line to show (a scan that gave up), `None` when not limiting.
    fn witness_line(&self, sigma: &Sigma, tri: &Tri) -> Option<Option<Dual>> {
        if tri.forward_slope - tri.minor_slope.abs() > self.rise || !AllRays.limiting(sigma, tri) {
            return None;
        }
        let Scan { pieces, stack } = &mut *self.scan.borrow_mut();
        pieces.clear();
        if self.candidates(sigma, tri, pieces).is_err() {
            return Some(None);
        }
        let widest = pieces
            .polys()
            .iter()
            .max_by(|a, b| area(a).total_cmp(&area(b)))?;
        if !self.rays.exterior {
            return Some(Some(centre(widest)));
        }
        match self.survives(sigma, tri, pieces, stack, true) {
            Ok(line) => line.map(Some),
            Err(Full) => Some(None),
        }
    }

    /// An explicit ray of the set that shows why texel `(i, j)` of `class` has no
    /// safety distance above `k`: from outside the field's box (for an exterior set),
    /// through the texel's segment above the surface, into the solid and out through
    /// a triangle of the `k`-th column of cells ahead. It is the bake's witness line,
    /// lowered under its plane at the segment by `lower` (in `(0, 1)`) times the
    /// plane's height above the surface there (less where the view angle needs). For
    /// checking the bake against an oracle: a witness that is not in the set, or does
    /// not dip, counts against the bake's tightness, never against its safety.
    pub fn witness(&self, class: RayClass, i: u32, j: u32, k: u32, lower: f64) -> Witness {
        let hf = self.hf;
        let ax = super::axis_of(class);
        let sg: i64 = if matches!(class, RayClass::XPos | RayClass::YPos) {
            1
        } else {
            -1
        };
        let (lm, ln) = super::extents(hf, ax);
        let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
        let ahead = if sg > 0 { lm - 1 - m } else { m };
        if k >= ahead {
            return Witness::None;
        }
        let mut given_up = false;
        let sigma = super::sigma_of(hf, ax, sg, m, n);
        let cm = super::column_ahead(m, sg, k);
        let (l0, l1) = super::band_cells(n, k, ln);
        for l in l0..=l1 {
            let h = cell_corners(hf, ax, cm, l);
            for tri in super::cell_tris(h, &sigma, ax, sg, cm, l) {
                let [y0, s] = match self.witness_line(&sigma, &tri) {
                    Some(Some(line)) => line,
                    Some(None) => {
                        given_up = true;
                        continue;
                    }
                    // Limiting for the bake only because its scan gave up.
                    None => {
                        given_up |= self.limiting(&sigma, &tri);
                        continue;
                    }
                };
                // Where the line crosses the triangle: the middle of its part inside.
                let mut seg = Poly::new();
                for v in tri.verts {
                    let _ = seg.push(v);
                }
                let (mut u_lo, mut u_hi) = (f64::INFINITY, f64::NEG_INFINITY);
                let nv = seg.len();
                for e in 0..nv {
                    let (a, b) = (seg[e], seg[(e + 1) % nv]);
                    let (fa, fb) = (a[1] - y0 - s * a[0], b[1] - y0 - s * b[0]);
                    if (fa <= 0.0) != (fb <= 0.0) || fa == 0.0 {
                        let t = if fa == fb { 0.0 } else { fa / (fa - fb) };
                        let u = a[0] + t * (b[0] - a[0]);
                        u_lo = u_lo.min(u);
                        u_hi = u_hi.max(u);
                    }
                }
                // A line kept by the growth only: through its nearest vertex instead.
                let uq = if u_lo <= u_hi {
                    0.5 * (u_lo + u_hi)
                } else {
                    let off = |v: &[f64; 2]| (v[1] - y0 - s * v[0]).abs();
                    let near = tri.verts.iter().min_by(|a, b| off(a).total_cmp(&off(b)));
                    near.map_or(0.0, |v| v[0])
                };
                let zq = Self::plane(&tri, uq, y0 + s * uq);
                // Lowered by a thousandth of the gap to the surface (staying close to
                // the line, which is clear), and by at most half what keeps its slope
                // within the view angle.
                let zp = Self::plane(&tri, 0.0, y0);
                let flat = libm::sqrt(uq * uq + (s * uq) * (s * uq));
                let rise = (zq - zp) / flat;
                let mut drop = lower * (zp - sigma.height(y0)).max(0.0);
                if self.tau.is_finite() {
                    drop = drop.min(0.5 * (self.tau - rise) * flat).max(0.0);
                }
                let zp = zp - drop;
                // Frame to field: main `m + sg·u`, minor `v`.
                let to_field = |u: f64, v: f64, z: f64| {
                    let main = f64::from(m) + sg as f64 * u;
                    if ax == 0 {
                        [main, v, z]
                    } else {
                        [v, main, z]
                    }
                };
                let p = to_field(0.0, y0, zp);
                let q = to_field(uq, y0 + s * uq, zq);
                let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
                // For an exterior set back from the segment far enough to start outside
                // the box; else on the segment.
                let (w, hh) = (f64::from(hf.width()), f64::from(hf.height()));
                let span = w + hh + f64::from(hf.max_height() - hf.min_height()) + 2.0;
                let flat = libm::sqrt(d[0] * d[0] + d[1] * d[1]).max(1e-300);
                let back = if self.rays.exterior { span / flat } else { 0.0 };
                let o = [0, 1, 2].map(|c| p[c] - back * d[c]);
                match Query::from_arrays(o, d, 0.0, f64::INFINITY) {
                    Ok(q) if uq > 0.0 => return Witness::Ray(q),
                    // A line that meets the triangle on the centerline only (kept by
                    // the growth of the sets): no ray to show.
                    _ => given_up = true,
                }
            }
        }
        if given_up {
            Witness::NoRay
        } else {
            Witness::None
        }
    }
}

/// The slopes `s ∈ [−1, 1]` along which a plane of forward and minor slopes `f`,
/// `g` rises at most `τ` per unit length, `F(s) = f + g·s − τ·√(1 + s²) ≤ 0`, as at
/// most two intervals, grown a little. `F` is convex for `τ < 0` (one interval around
/// its minimum) and concave for `τ ≥ 0` (the ends outside an interval around its
/// maximum); the extremum is where `s/√(1 + s²) = g/τ`, the ends are found by
/// bisection (60 halvings: far below [`EPS`]).
fn slopes_below(f: f64, g: f64, tau: f64) -> Vec<(f64, f64), 2> {
    let big = |s: f64| f + g * s - tau * libm::sqrt(1.0 + s * s);
    let slack = 1e-9 * (1.0 + f.abs() + g.abs() + tau.abs());
    let feasible = |s: f64| big(s) <= slack;
    let r = g / tau;
    let mid = if r.abs() < 1.0 {
        (r / libm::sqrt(1.0 - r * r)).clamp(-1.0, 1.0)
    } else if (big(-1.0) <= big(1.0)) == (tau < 0.0) {
        -1.0
    } else {
        1.0
    };
    // Between `from` and `to`, where feasibility changes once: the last point on
    // `from`'s side.
    let edge = |from: f64, to: f64| {
        let (mut a, mut b) = (from, to);
        for _ in 0..60 {
            let c = 0.5 * (a + b);
            if feasible(c) == feasible(from) {
                a = c;
            } else {
                b = c;
            }
        }
        if feasible(from) {
            b
        } else {
            a
        }
    };
    let mut out = Vec::new();
    if tau < 0.0 {
        if feasible(mid) {
            let lo = if feasible(-1.0) {
                -1.0
            } else {
                edge(mid, -1.0)
            };
            let hi = if feasible(1.0) { 1.0 } else { edge(mid, 1.0) };
            let _ = out.push((lo, hi));
        }
    } else if feasible(mid) {
        let _ = out.push((-1.0, 1.0));
    } else {
        if feasible(-1.0) {
            let _ = out.push((-1.0, edge(-1.0, mid)));
        }
        if feasible(1.0) {
            let _ = out.push((edge(1.0, mid), 1.0));
        }
    }
    out
}

/// The area of a polygon.
fn area(p: &Poly) -> f64 {
    let n = p.len();
    let twice: f64 = (0..n)
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    0.5 * twice.abs()
}

/// The mean of a polygon's vertices (inside it: it is convex).
fn centre(p: &Poly) -> Dual {
    let n = p.len().max(1) as f64;
    let (a, b) = p.iter().fold((0.0, 0.0), |(a, b), x| (a + x[0], b + x[1]));
    [a / n, b / n]
}

/// `p` less the lines through the open convex hull of `pts` (grown by [`EPS`]): the
/// lines weakly on one side of every point (all above, or all below), as two polygons;
/// `None` when `p` lies on one side already.
fn split(p: &Poly, pts: &[[f64; 2]]) -> Option<[Poly; 2]> {
    let mut ups: Vec<Half, 6> = Vec::new();
    let mut downs: Vec<Half, 6> = Vec::new();
    for &[u, v] in pts {
        let _ = ups.push(above(u, v));
        let _ = downs.push(below(u, v));
    }
    let all = |hs: &[Half]| hs.iter().all(|h| p.iter().all(|x| side(h, x) >= 0.0));
    if all(&ups) || all(&downs) {
        return None;
    }
    Some([clip_all(p, &ups), clip_all(p, &downs)])
}

/// The part of a triangle (its vertices `(u, v, d)`, `d` the surface's height above
/// the plane) where `d ≥ lim`: its vertices `(u, v)` (linear `d`: a convex polygon).
fn blocker(vs: &[(f64, f64, f64)], lim: f64) -> Vec<[f64; 2], 4> {
    let mut out = Vec::new();
    let n = vs.len();
    for k in 0..n {
        let (a, b) = (vs[k], vs[(k + 1) % n]);
        if a.2 >= lim {
            let _ = out.push([a.0, a.1]);
        }
        if (a.2 >= lim) != (b.2 >= lim) {
            // The crossing at `d = 2·lim` seen from the side above: inside the part.
            let t = (a.2 - lim) / (a.2 - b.2);
            let t = if a.2 >= lim {
                t * (1.0 - 1e-9)
            } else {
                1.0 - (1.0 - t) * (1.0 - 1e-9)
            };
            let _ = out.push([a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)]);
        }
    }
    out
}

impl RaySet for RaysOn<'_> {
    fn least_rise_back(&self) -> f64 {
        -self.rise
    }

    fn limiting(&self, sigma: &Sigma, tri: &Tri) -> bool {
        // The plane's rise along the quadrant's directions is least, `f − |g|`, at
        // `s = ±1`: above `rise` no ray of the set crosses it upwards.
        if tri.forward_slope - tri.minor_slope.abs() > self.rise {
            return false;
        }
        if !AllRays.limiting(sigma, tri) {
            return false;
        }
        if self.rays.is_all() {
            return true;
        }
        let Scan { pieces, stack } = &mut *self.scan.borrow_mut();
        pieces.clear();
        if self.candidates(sigma, tri, pieces).is_err() {
            return true;
        }
        if pieces.polys().is_empty() {
            return false;
        }
        if !self.rays.exterior {
            return true;
        }
        !matches!(self.survives(sigma, tri, pieces, stack, false), Ok(None))
    }
}
