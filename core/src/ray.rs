//! Rays, queries and their answers, shared by every method.

use crate::math::Real;
use crate::{HeightField, Surface};
use core::fmt;

/// Why a ray query was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayError {
    /// A component of the origin is NaN or infinite.
    OriginNotFinite,
    /// A component of the direction is NaN or infinite.
    DirectionNotFinite,
    /// The direction is (0, 0, 0).
    ZeroDirection,
    /// `t_min` is NaN or infinite, or `t_max` is NaN or −∞.
    RangeNotFinite,
    /// `t_min > t_max`.
    EmptyRange,
}

impl fmt::Display for RayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RayError::OriginNotFinite => "ray origin is NaN or infinite",
            RayError::DirectionNotFinite => "ray direction is NaN or infinite",
            RayError::ZeroDirection => "ray direction is zero",
            RayError::RangeNotFinite => "t_min must be finite and t_max not NaN or -inf",
            RayError::EmptyRange => "t_min is greater than t_max",
        })
    }
}

named_enum! {
    /// The four ray classes of the safety-shape methods, by the ray's main horizontal axis.
    pub enum RayClass: u8 {
        /// dx ≥ |dy|.
        XPos = 0 => "x+",
        /// −dx ≥ |dy|.
        XNeg = 1 => "x-",
        /// dy > |dx|.
        YPos = 2 => "y+",
        /// Every other direction (including vertical rays).
        YNeg = 3 => "y-",
    }
}

impl RayClass {
    /// The class of a direction (docs/DESIGN.md contract).
    pub fn of<R: Real>(dx: R, dy: R) -> RayClass {
        if dx >= dy.abs() && !(dx == R::ZERO && dy == R::ZERO) {
            RayClass::XPos
        } else if -dx >= dy.abs() && !(dx == R::ZERO && dy == R::ZERO) {
            RayClass::XNeg
        } else if dy > dx.abs() {
            RayClass::YPos
        } else {
            RayClass::YNeg
        }
    }
}

/// A validated ray query in grid space: `origin + t · dir` for `t` in `[t_min, t_max]`.
///
/// `dir` need not be normalised; `t_max` may be `+∞`. Laid out as C lays out
/// `{ R origin[3]; R dir[3]; R t_min; R t_max; }`: the C API marches its callers' rays,
/// once checked, where they lie.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Query<R: Real = f32> {
    origin: [R; 3],
    dir: [R; 3],
    t_min: R,
    t_max: R,
}

impl<R: Real> Query<R> {
    /// Checks and builds a query: finite origin and direction, non-zero direction,
    /// finite `t_min`, `t_max ≥ t_min` (`+∞` allowed).
    pub fn new(origin: R::V3, dir: R::V3, t_min: R, t_max: R) -> Result<Self, RayError> {
        Self::from_arrays(R::xyz(origin), R::xyz(dir), t_min, t_max)
    }

    /// [`Query::new`] from plain arrays.
    #[inline]
    pub fn from_arrays(origin: [R; 3], dir: [R; 3], t_min: R, t_max: R) -> Result<Self, RayError> {
        if !origin.iter().all(|v| v.is_finite()) {
            return Err(RayError::OriginNotFinite);
        }
        if !dir.iter().all(|v| v.is_finite()) {
            return Err(RayError::DirectionNotFinite);
        }
        if dir.iter().all(|&v| v == R::ZERO) {
            return Err(RayError::ZeroDirection);
        }
        let t_max_ok = t_max == R::INFINITY || t_max.is_finite();
        if !t_min.is_finite() || !t_max_ok {
            return Err(RayError::RangeNotFinite);
        }
        if t_min > t_max {
            return Err(RayError::EmptyRange);
        }
        Ok(Query {
            origin,
            dir,
            t_min,
            t_max,
        })
    }

    /// The same query from `t_min = t` on (`t` no less than its `t_min` and no more
    /// than its `t_max`: a start the caller has proved no hit precedes).
    #[inline]
    pub fn starting_at(&self, t: R) -> Query<R> {
        debug_assert!(t >= self.t_min && t <= self.t_max);
        // Copied whole, then changed: field by field, the copy of the three-element
        // arrays went through stores the CPU could not forward to the next read.
        let mut q = *self;
        q.t_min = t;
        q
    }

    /// The same query over `[t0, t1]`, a part of its range (a horizon's span, which
    /// the caller has proved no hit precedes).
    #[inline]
    pub fn within(&self, t0: R, t1: R) -> Query<R> {
        debug_assert!(self.t_min <= t0 && t0 <= t1 && t1 <= self.t_max);
        let mut q = *self;
        q.t_min = t0;
        q.t_max = t1;
        q
    }

    /// Origin in grid space.
    #[inline]
    pub fn origin(&self) -> [R; 3] {
        self.origin
    }
    /// Direction in grid space.
    #[inline]
    pub fn dir(&self) -> [R; 3] {
        self.dir
    }
    /// Start of the parameter range.
    #[inline]
    pub fn t_min(&self) -> R {
        self.t_min
    }
    /// End of the parameter range (may be `+∞`).
    #[inline]
    pub fn t_max(&self) -> R {
        self.t_max
    }
    /// `origin + t · dir`.
    #[inline]
    pub fn at(&self, t: R) -> [R; 3] {
        let (o, d) = (self.origin, self.dir);
        [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]]
    }
    /// The ray class of the direction.
    #[inline]
    pub fn class(&self) -> RayClass {
        RayClass::of(self.dir[0], self.dir[1])
    }
    /// The same query in another precision (f32 → f64 is exact: the oracle traces
    /// exactly the ray the fast path was given).
    pub fn cast<S: Real>(&self) -> Query<S> {
        let c = |v: [R; 3]| v.map(|x| S::from_f64(x.to_f64()));
        Query {
            origin: c(self.origin),
            dir: c(self.dir),
            t_min: S::from_f64(self.t_min.to_f64()),
            t_max: S::from_f64(self.t_max.to_f64()),
        }
    }

    /// The same points walked the other way: the origin kept, the direction negated,
    /// `t` from where the ray leaves the closed box every surface of `hf` lies in (a
    /// grid unit beyond it; the samples' height range widened by itself above and
    /// below, as the corner planes need) back to `−t_min`. A shadow ray from a surface
    /// point towards a light becomes the light's ray to that point
    /// ([`Hit::shadow_query_from_light`]): it starts outside the box, so an exterior
    /// map's set holds it
    /// ([`Rays::holds`](crate::rayset::Rays::holds)), and it meets the surface iff the
    /// original does (its first hit is the one nearest the light). The origin is not
    /// moved, so the end the original started at is computed without rounding. A ray
    /// that ends (`t_max`) inside the box is reversed over its own range; one that
    /// misses the box is returned as it is.
    pub fn walked_back(&self, hf: &HeightField) -> Query<R> {
        match self.walked_back_range(hf) {
            Some((t_min, t_max)) => Query {
                origin: self.origin,
                dir: self.dir.map(|v| -v),
                t_min,
                t_max,
            },
            None => *self,
        }
    }

    /// The `t` range of [`Query::walked_back`], `None` when the ray misses the box (it
    /// is returned as it is).
    pub fn walked_back_range(&self, hf: &HeightField) -> Option<(R, R)> {
        let (o, d) = (self.origin.map(R::to_f64), self.dir.map(R::to_f64));
        let (lo, hi) = surface_box(hf, 0.0);
        let (near, far) = slabs(o, d, lo, hi);
        let (t0, t1) = (self.t_min.to_f64(), self.t_max.to_f64());
        if far < near.max(t0) {
            return None;
        }
        let length = libm::sqrt(d.iter().map(|v| v * v).sum::<f64>());
        let end = if far < t1 {
            R::from_f64(far + 1.0 / length).min(self.t_max)
        } else {
            self.t_max
        };
        Some((-end, -self.t_min))
    }
}

/// The closed box every surface of `hf` lies in, grown by `margin` on every side: the
/// footprint, and the samples' height range widened by itself above and below (the
/// corner planes overshoot the samples by up to their range: `dda::clip_surface`).
pub(crate) fn surface_box(hf: &HeightField, margin: f64) -> ([f64; 3], [f64; 3]) {
    let (zmin, zmax) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let range = zmax - zmin;
    let lo = [-margin, -margin, zmin - range - margin];
    let hi = [
        f64::from(hf.width() - 1) + margin,
        f64::from(hf.height() - 1) + margin,
        zmax + range + margin,
    ];
    (lo, hi)
}

/// Where the line `o + t·d` is in the closed box `[lo, hi]`, as `(near, far)` (slabs;
/// `far < near` when never, `far = −∞` for a line parallel to a slab outside it).
pub(crate) fn slabs(o: [f64; 3], d: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> (f64, f64) {
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] != 0.0 {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        } else if o[k] < lo[k] || o[k] > hi[k] {
            far = f64::NEG_INFINITY;
        }
    }
    (near, far)
}

/// Bit flags describing a hit or a trace.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Flags(pub u32);

impl Flags {
    /// The ray starts under the surface: the hit is at `t_min`.
    pub const ORIGIN_INSIDE: Flags = Flags(1);
    /// The ray enters the footprint through a side wall below the surface; the hit is on
    /// that wall (the field is a solid: everything below the surface is inside).
    pub const SIDE: Flags = Flags(2);
    /// The hit is on a vertical step of a discontinuous surface (height or corner planes).
    pub const WALL: Flags = Flags(4);
    /// An approximate or iterative method ran out of its step budget; the answer is
    /// its best guess, not a converged one.
    pub const BUDGET_EXHAUSTED: Flags = Flags(8);

    /// `true` when every bit of `other` is set.
    #[inline]
    pub fn contains(self, other: Flags) -> bool {
        self.0 & other.0 == other.0
    }
    /// Both sets of bits.
    #[inline]
    pub fn with(self, other: Flags) -> Flags {
        Flags(self.0 | other.0)
    }
}

/// Where a ray meets the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<R: Real = f32> {
    /// Ray parameter of the hit.
    pub t: R,
    /// Hit point in grid space (`origin + t · dir`).
    pub point: R::V3,
    /// The cell (i, j) holding the hit: the unit square [i, i+1] × [j, j+1].
    pub cell: [u32; 2],
    /// Unit surface normal at the hit (a wall's normal for side and step hits).
    pub normal: R::V3,
    /// [`Flags::ORIGIN_INSIDE`], [`Flags::SIDE`], [`Flags::WALL`].
    pub flags: Flags,
}

impl<R: Real> Hit<R> {
    /// Units of `R`'s epsilon, times the coordinates' magnitude, that
    /// [`Hit::shadow_query`] lifts a shadow ray's origin off the surface: well above the
    /// few ulps by which a hit point computed as `origin + t · dir` can sit inside the
    /// solid.
    pub const SHADOW_LIFT_EPS: f32 = 64.0;

    /// A shadow ray from this grid-space hit on `surface` of `hf` towards a light in
    /// direction `to_light` (need not be normalised), starting outside the solid.
    ///
    /// The origin is the hit point moved `δ = SHADOW_LIFT_EPS · ε · (1 + m)` along the
    /// normal (off the hit's own plane, a wall included), then raised, where it lies
    /// over the footprint, to at least `δ` above the surface there (at a crease or a
    /// grid vertex the neighbouring cell can rise faster than the normal moves away);
    /// `m` is the largest magnitude of the hit point's coordinates and of `magnitude`
    /// (pass the primary ray's largest |origin| coordinate: the point's rounding grows
    /// with it). Starting at the hit point itself reports [`Flags::ORIGIN_INSIDE`] for
    /// a large share of hits (the point rounds into the solid).
    pub fn shadow_query(
        &self,
        hf: &HeightField,
        surface: Surface,
        to_light: [R; 3],
        magnitude: R,
    ) -> Result<Query<R>, RayError> {
        let (p, n) = (R::xyz(self.point), R::xyz(self.normal));
        let m = p.iter().fold(magnitude.abs(), |m, v| m.max(v.abs()));
        let lift = R::from_f32(Self::SHADOW_LIFT_EPS) * R::EPSILON * (R::ONE + m);
        let mut o = [0, 1, 2].map(|k| p[k] + lift * n[k]);
        let (xm, ym) = (R::from_u32(hf.width() - 1), R::from_u32(hf.height() - 1));
        let over = o[0] >= R::ZERO && o[0] <= xm && o[1] >= R::ZERO && o[1] <= ym;
        if over {
            o[2] = o[2].max(surface.height_at(hf, o[0], o[1]) + lift);
        }
        Query::from_arrays(o, to_light, R::ZERO, R::INFINITY)
    }

    /// [`Hit::shadow_query`] traced from the light's side ([`Query::walked_back`]):
    /// from outside the field's box, along `−to_light`, to the same lifted start. It
    /// meets the surface iff the shadow query does, and it is an exterior ray, so the
    /// safety shapes baked for exterior rays take their long steps along it
    /// ([`Shadows::FromLight`](crate::scene::Shadows::FromLight)).
    pub fn shadow_query_from_light(
        &self,
        hf: &HeightField,
        surface: Surface,
        to_light: [R; 3],
        magnitude: R,
    ) -> Result<Query<R>, RayError> {
        Ok(self
            .shadow_query(hf, surface, to_light, magnitude)?
            .walked_back(hf))
    }
}

/// The full answer to one query: the hit, if any, and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trace<R: Real = f32> {
    /// The first hit in `[t_min, t_max]`, or `None`.
    pub hit: Option<Hit<R>>,
    /// Texture fetches used: one per texel read of any texture (a cell's four corners
    /// are four fetches). The hardware-independent cost measure.
    pub fetches: u32,
    /// Smallest clearance (ray height − surface height) seen before the hit, or along
    /// the whole ray for a miss; `+∞` when the ray never overlaps the field. Exact
    /// traversals fill it; the oracle uses it to flag ambiguous rays. A hit right where
    /// the traced span begins reports the depth under the surface there (`≥ 0`: how far
    /// the decision was from a miss) when the ray starts under the surface or enters
    /// through a side below it, and `+∞` when it enters through the top of the box.
    pub clearance: R,
    /// [`Flags::BUDGET_EXHAUSTED`] when an iterative method stopped on its budget.
    pub flags: Flags,
}

impl<R: Real> Trace<R> {
    /// A miss that cost nothing.
    pub const MISS: Trace<R> = Trace {
        hit: None,
        fetches: 0,
        clearance: R::INFINITY,
        flags: Flags(0),
    };

    /// The trace of a march that found `hit` after `fetches` fetches, having seen
    /// `clearance` at least before it (no trace flags).
    #[inline]
    pub fn hit(hit: Hit<R>, fetches: u32, clearance: R) -> Trace<R> {
        Trace {
            hit: Some(hit),
            fetches,
            clearance,
            flags: Flags::default(),
        }
    }

    /// The trace of a march that missed after `fetches` fetches, having seen
    /// `clearance` at least along the ray (no trace flags).
    #[inline]
    pub fn miss(fetches: u32, clearance: R) -> Trace<R> {
        Trace {
            hit: None,
            fetches,
            clearance,
            flags: Flags::default(),
        }
    }
}
