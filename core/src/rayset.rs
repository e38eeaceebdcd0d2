//! Ray sets: which rays a baked map serves (exterior rays, a largest view angle,
//! rays that pass over static occluders; Baboud, Eisemann, Seidel 2011, §6.2). A map
//! baked for a set records it (its description, [`crate::ktx2::Desc::rays`]), and its
//! march checks every ray against it ([`Rays::holds`]): a ray outside the set marches
//! without the map's steps. The bakes' side, which triangles limit the rays of a set,
//! is in `safety::rays`.

use crate::field::HeightField;
use crate::math::Real;
use crate::ray::Query;

/// Which rays a map is baked for: its march reads the map for the rays of the set only
/// ([`Rays::holds`]); every other ray marches without the map's steps (the safety
/// shapes: cell by cell).
#[derive(Clone, Copy, Debug)]
pub struct Rays {
    /// Only rays that start outside the field's box: every camera outside it, shadow
    /// rays traced from a light outside it.
    pub exterior: bool,
    /// The largest angle between a ray and the downward vertical, in degrees, in
    /// `(0, 180]` (the scene's `max_view_angle_deg`): 90 = no ray rises, 180 = any.
    pub max_view_angle_deg: f32,
    /// Only rays whose line passes over every occluder of a caller's list (see
    /// [`Occluder`]): the list's [`fingerprint`], 0 for none. The triangles travel
    /// beside the set (`Rays` stays a small `Copy` value in descriptors, options and
    /// shaders); the bake and the guard take them and check them against it.
    pub occluders: u32,
}

/// Equal when every field is (the angle bit for bit: so `Eq` and `Hash` hold).
impl PartialEq for Rays {
    fn eq(&self, o: &Rays) -> bool {
        self.exterior == o.exterior
            && self.max_view_angle_deg.to_bits() == o.max_view_angle_deg.to_bits()
            && self.occluders == o.occluders
    }
}

impl Eq for Rays {}

impl core::hash::Hash for Rays {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        let key = (self.exterior, self.max_view_angle_deg.to_bits());
        (key, self.occluders).hash(h);
    }
}

/// A static occluder: the solid under a triangle (its corners `[x, y, z]` in grid
/// units, the field's frame), every point at or below the triangle over its
/// footprint (a wall's or a mountain's top standing around the field). A set with
/// occluders ([`Rays::occluders`]) holds only the rays whose line, up to where it
/// leaves the field's footprint, never dips under one: such rays cannot come from
/// behind it, so the surface behind an occluder no longer limits the bake (docs/
/// DESIGN.md, "Ray sets").
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C)]
pub struct Occluder {
    /// The triangle's corners, finite, with a footprint (`x`, `y`) of non-zero area.
    pub corners: [[f32; 3]; 3],
}

/// A set's occluders prepared for the guard on one field ([`Rays::holds_over`]): the
/// list, and what lets most rays pass without a test per occluder.
#[derive(Clone, Copy, Debug)]
pub struct Occluders<'a> {
    list: &'a [Occluder],
    /// The highest corner.
    top: f64,
    /// The largest magnitude of a corner's coordinate.
    size: f64,
    /// Whether every occluder's bounding box lies outside the field's open footprint.
    outside: bool,
}

impl<'a> Occluders<'a> {
    /// No occluders.
    pub const NONE: Occluders<'static> = Occluders {
        list: &[],
        top: f64::NEG_INFINITY,
        size: 0.0,
        outside: true,
    };

    /// `list` prepared for the field `hf` (not checked: [`Rays::check_occluders`]).
    pub fn prepare(hf: &HeightField, list: &'a [Occluder]) -> Occluders<'a> {
        let ends = [f64::from(hf.width() - 1), f64::from(hf.height() - 1)];
        let corners = || list.iter().flat_map(|o| o.corners_f64());
        Occluders {
            list,
            top: corners().fold(f64::NEG_INFINITY, |m, c| m.max(c[2])),
            size: corners().flatten().fold(0f64, |m, v| m.max(v.abs())),
            outside: list.iter().all(|o| o.outside(ends)),
        }
    }

    /// The list.
    pub fn list(&self) -> &'a [Occluder] {
        self.list
    }
}

/// Most occluders a set takes (the shaders' occluder texture is one row this wide).
pub const MAX_OCCLUDERS: usize = 64;

/// The fingerprint of an occluder list ([`Rays::occluders`]): 24 bits (FNV-1a of the
/// corners' bits, folded), never 0 for a non-empty list; 0 for the empty one.
pub fn fingerprint(occluders: &[Occluder]) -> u32 {
    if occluders.is_empty() {
        return 0;
    }
    let mut h: u32 = 0x811c_9dc5;
    for c in occluders.iter().flat_map(|o| o.corners.iter().flatten()) {
        for b in c.to_bits().to_le_bytes() {
            h = (h ^ u32::from(b)).wrapping_mul(0x0100_0193);
        }
    }
    ((h >> 24) ^ (h & 0x00ff_ffff)).max(1)
}

impl Occluder {
    /// The top of the rectangle `x × y` (grid units) as two occluders, its corners at
    /// the heights `top(x, y)`: a wall or a block standing around the field.
    pub fn rectangle(x: [f64; 2], y: [f64; 2], top: impl Fn(f64, f64) -> f64) -> [Occluder; 2] {
        let c = |x: f64, y: f64| [x as f32, y as f32, top(x, y) as f32];
        let [a, b, p, q] = [c(x[0], y[0]), c(x[1], y[0]), c(x[1], y[1]), c(x[0], y[1])];
        [
            Occluder { corners: [a, b, p] },
            Occluder { corners: [a, p, q] },
        ]
    }

    /// Whether the bounding box of the footprint lies outside the open footprint
    /// `(0, ends[0]) × (0, ends[1])` of a field.
    fn outside(&self, ends: [f64; 2]) -> bool {
        let c = self.corners_f64();
        let min = |k: usize| c.iter().fold(f64::INFINITY, |m, v| m.min(v[k]));
        let max = |k: usize| c.iter().fold(f64::NEG_INFINITY, |m, v| m.max(v[k]));
        max(0) <= 0.0 || min(0) >= ends[0] || max(1) <= 0.0 || min(1) >= ends[1]
    }

    /// The corners in `f64`.
    pub fn corners_f64(&self) -> [[f64; 3]; 3] {
        self.corners.map(|c| c.map(f64::from))
    }

    /// Twice the footprint's signed area (counter-clockwise positive).
    fn twice_area(&self) -> f64 {
        let [a, b, c] = self.corners_f64();
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    /// Whether the line `p + t·d`, for `t ≤ t_hi`, comes within the guard's margin of
    /// the solid under the triangle somewhere over its closed footprint: within
    /// `10⁻⁵·(1 + m)` of the triangle's height or under it, `m` the largest magnitude
    /// of the triangle's and `p`'s coordinates (so the shaders' `f32` check, with the
    /// same margin, agrees). In `f64`.
    pub fn dips_under(&self, p: [f64; 3], d: [f64; 3], t_hi: f64) -> bool {
        let big = self
            .corners_f64()
            .iter()
            .chain([&p])
            .flatten()
            .fold(0f64, |m, v| m.max(v.abs()));
        self.dips_under_by(p, d, t_hi, 1e-5 * (1.0 + big))
    }

    /// [`Occluder::dips_under`] with its `margin`.
    fn dips_under_by(&self, p: [f64; 3], d: [f64; 3], t_hi: f64, margin: f64) -> bool {
        let [a, b, c] = self.corners_f64();
        // Every corner strictly on one side of the line's footprint: it misses.
        let side = |v: [f64; 3]| d[0] * (v[1] - p[1]) - d[1] * (v[0] - p[0]);
        let (sa, sb, sc) = (side(a), side(b), side(c));
        if (sa > 0.0 && sb > 0.0 && sc > 0.0) || (sa < 0.0 && sb < 0.0 && sc < 0.0) {
            return false;
        }
        let area = self.twice_area();
        let orient = area.signum();
        // The footprint's edges as `α + β·t ≥ 0` along the line.
        let (mut lo, mut hi) = (f64::NEG_INFINITY, t_hi);
        for (e0, e1) in [(a, b), (b, c), (c, a)] {
            let (ex, ey) = (e1[0] - e0[0], e1[1] - e0[1]);
            let alpha = orient * (ex * (p[1] - e0[1]) - ey * (p[0] - e0[0]));
            let beta = orient * (ex * d[1] - ey * d[0]);
            if beta > 0.0 {
                lo = lo.max(-alpha / beta);
            } else if beta < 0.0 {
                hi = hi.min(-alpha / beta);
            } else if alpha < 0.0 {
                return false;
            }
        }
        if lo > hi {
            return false;
        }
        // The triangle's height over the line minus the line's: linear in `t`.
        let gx = ((b[2] - a[2]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[2] - a[2])) / area;
        let gy = ((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0])) / area;
        let depth0 = a[2] + gx * (p[0] - a[0]) + gy * (p[1] - a[1]) - p[2];
        let rate = gx * d[0] + gy * d[1] - d[2];
        // Linear: deepest at an end of the interval (towards `−∞` when it falls
        // with `t`, towards `+∞` when it rises, anywhere when flat).
        if rate == 0.0 {
            return depth0 > -margin;
        }
        let end = if rate < 0.0 { lo } else { hi };
        !end.is_finite() || depth0 + rate * end > -margin
    }
}

impl Default for Rays {
    fn default() -> Self {
        Rays::ALL
    }
}

/// Why a [`Rays`] is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RaysError {
    /// The view angle is NaN or outside `(0, 180]`.
    ViewAngle,
    /// An occluder is not finite or has a footprint of zero area, or there are more
    /// than [`MAX_OCCLUDERS`].
    Occluder,
    /// The occluders given are not those the set (or map) was baked for: their
    /// [`fingerprint`] differs from [`Rays::occluders`].
    OccludersDiffer,
    /// Not a set's text (`Rays`' `FromStr`).
    Unreadable,
}

impl core::fmt::Display for RaysError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            RaysError::ViewAngle => "max_view_angle_deg is NaN or outside (0, 180]",
            RaysError::Occluder => {
                "an occluder is not finite or has no footprint, or there are over 64"
            }
            RaysError::OccludersDiffer => "the occluders are not those the ray set was baked for",
            RaysError::Unreadable => {
                "not a ray set (all, or exterior, angle:A, occluders:F joined by commas)"
            }
        })
    }
}

impl Rays {
    /// Every ray.
    pub const ALL: Rays = Rays {
        exterior: false,
        max_view_angle_deg: 180.0,
        occluders: 0,
    };

    /// The exterior rays, any direction.
    pub const EXTERIOR: Rays = Rays {
        exterior: true,
        ..Rays::ALL
    };

    /// Checks the view angle.
    pub fn validate(self) -> Result<Self, RaysError> {
        let a = self.max_view_angle_deg;
        if a > 0.0 && a <= 180.0 {
            Ok(self)
        } else {
            Err(RaysError::ViewAngle)
        }
    }

    /// The same set, passing over `occluders` too (checked: finite, with footprints,
    /// at most [`MAX_OCCLUDERS`]; none gives the set without occluders).
    pub fn passing_over(self, occluders: &[Occluder]) -> Result<Self, RaysError> {
        check_occluders(occluders)?;
        Ok(Rays {
            occluders: fingerprint(occluders),
            ..self
        })
    }

    /// `occluders` if they are the set's ([`fingerprint`]), else
    /// [`RaysError::OccludersDiffer`].
    pub fn check_occluders(self, occluders: &[Occluder]) -> Result<(), RaysError> {
        check_occluders(occluders)?;
        if fingerprint(occluders) == self.occluders {
            Ok(())
        } else {
            Err(RaysError::OccludersDiffer)
        }
    }

    /// Whether the set is every ray.
    pub fn is_all(self) -> bool {
        !self.exterior && !self.limits_angle() && self.occluders == 0
    }

    /// Whether the set bounds the view angle.
    fn limits_angle(self) -> bool {
        self.max_view_angle_deg < 180.0
    }

    /// The largest rise of a ray of the set per unit of horizontal distance,
    /// `τ = −cot α` (`+∞` for any direction).
    pub fn rise_bound(self) -> f64 {
        if !self.limits_angle() {
            return f64::INFINITY;
        }
        let a = f64::from(self.max_view_angle_deg).to_radians();
        -libm::cos(a) / libm::sin(a)
    }

    /// Whether `q` is a ray of the set for the field `hf`: for an exterior set its
    /// start `q.at(t_min)` lies outside the closed box of the field's samples; for a
    /// view angle it rises at most [`Rays::rise_bound`] per unit of horizontal
    /// distance (checked in `f64` from the query's own values, a millionth tighter);
    /// for a set with occluders, `occluders` are the set's (else no ray is held) and
    /// the ray's line, up to where it leaves the field's footprint, dips under none
    /// ([`Occluder::dips_under`]).
    pub fn holds<R: Real>(self, hf: &HeightField, occluders: &[Occluder], q: &Query<R>) -> bool {
        self.holds_over(hf, &Occluders::prepare(hf, occluders), q)
    }

    /// [`Rays::holds`] with occluders prepared once for many rays (the marches'):
    /// most rays then pass without a test per occluder.
    pub fn holds_over<R: Real>(
        self,
        hf: &HeightField,
        occluders: &Occluders,
        q: &Query<R>,
    ) -> bool {
        if self.exterior {
            let p = q.at(q.t_min()).map(|c| c.to_f64());
            let (w, h) = (f64::from(hf.width() - 1), f64::from(hf.height() - 1));
            let (lo, hi) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
            // NaN compares false: such a start is not outside.
            let outside =
                p[0] < 0.0 || p[0] > w || p[1] < 0.0 || p[1] > h || p[2] < lo || p[2] > hi;
            if !outside {
                return false;
            }
        }
        if self.limits_angle() {
            let d = q.dir().map(|c| c.to_f64());
            let flat = libm::sqrt(d[0] * d[0] + d[1] * d[1]);
            let tau = self.rise_bound();
            let bound = tau * flat - 1e-6 * (tau.abs() * flat + d[2].abs());
            // A query's direction is finite: so is `bound`.
            if d[2] > bound {
                return false;
            }
        }
        if self.occluders != 0 {
            if occluders.list.is_empty() {
                return false;
            }
            let p = q.origin().map(|c| c.to_f64());
            let d = q.dir().map(|c| c.to_f64());
            let ends = [f64::from(hf.width() - 1), f64::from(hf.height() - 1)];
            let span = footprint_span(ends, p, d);
            let p_size = p.iter().fold(0f64, |m, v| m.max(v.abs()));
            // Over an occluder outside the field's open footprint the line can be only
            // before it enters the footprint (or after it leaves): the same answer as up
            // to the exit, for fewer points. A line that falls with `t` and is above
            // every corner by the margin where it enters passes over them all.
            let margin = 1e-5 * (1.0 + occluders.size.max(p_size));
            let entry_z = p[2] + span[0] * d[2];
            if occluders.outside && d[2] < 0.0 && entry_z > occluders.top + margin {
                return true;
            }
            for o in occluders.list {
                let c = o.corners_f64();
                let t_end = if o.outside(ends) { span[0] } else { span[1] };
                if t_end == f64::NEG_INFINITY {
                    continue;
                }
                // The same for this occluder alone (its own margin, as `dips_under`'s).
                let size = c.iter().flatten().fold(p_size, |m, v| m.max(v.abs()));
                let margin = 1e-5 * (1.0 + size);
                let top = c[0][2].max(c[1][2]).max(c[2][2]);
                let falls = d[2] < 0.0 && t_end.is_finite();
                if falls && p[2] + t_end * d[2] > top + margin {
                    continue;
                }
                // Every corner ahead of the range's end along the line: the line is
                // over the occluder only later.
                let along = |v: &[f64; 3]| (v[0] - p[0]) * d[0] + (v[1] - p[1]) * d[1];
                let end = t_end * (d[0] * d[0] + d[1] * d[1]);
                let beyond = end + 1e-9 * (1.0 + end.abs());
                if end.is_finite() && c.iter().all(|v| along(v) > beyond) {
                    continue;
                }
                if o.dips_under_by(p, d, t_end, margin) {
                    return false;
                }
            }
        }
        true
    }
}

/// Where the line `p + t·d` enters and leaves the field's footprint `[0, ends[0]] ×
/// [0, ends[1]]`, each a little late (so the rounding of the slabs never cuts a point
/// of the line inside); both `+∞` when it never meets it, the entry `−∞` when it never
/// leaves it backwards.
fn footprint_span(ends: [f64; 2], p: [f64; 3], d: [f64; 3]) -> [f64; 2] {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..2 {
        if d[a] != 0.0 {
            let (t0, t1) = ((0.0 - p[a]) / d[a], (ends[a] - p[a]) / d[a]);
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        } else if p[a] < 0.0 || p[a] > ends[a] {
            return [f64::INFINITY; 2];
        }
    }
    if lo > hi {
        return [f64::INFINITY; 2];
    }
    [lo, hi].map(|t| match t.is_finite() {
        true => t + 1e-9 * (1.0 + t.abs()),
        false => t,
    })
}

/// Refuses occluders that are not finite, have no footprint, or are too many.
fn check_occluders(occluders: &[Occluder]) -> Result<(), RaysError> {
    let bad = |o: &Occluder| {
        let area = o.twice_area();
        let size = o
            .corners
            .iter()
            .flatten()
            .fold(0f64, |m, c| m.max(f64::from(c.abs())));
        !o.corners.iter().flatten().all(|c| c.is_finite())
            || area.abs() <= 1e-9 * (1.0 + size * size)
    };
    if occluders.len() > MAX_OCCLUDERS || occluders.iter().any(bad) {
        return Err(RaysError::Occluder);
    }
    Ok(())
}

/// `all`, or `exterior`, `angle:A` and `occluders:F` joined by commas in that order
/// (`A` in degrees, as Rust prints an `f32`; `F` the occluders' [`fingerprint`] in 6
/// hexadecimal digits): the KTX 2 `hfcast.ray_set` of a safety or cylinder–cone map.
impl core::fmt::Display for Rays {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.is_all() {
            return f.write_str("all");
        }
        let mut sep = "";
        if self.exterior {
            f.write_str("exterior")?;
            sep = ",";
        }
        if self.limits_angle() {
            write!(f, "{sep}angle:{}", self.max_view_angle_deg)?;
            sep = ",";
        }
        if self.occluders != 0 {
            write!(f, "{sep}occluders:{:06x}", self.occluders)?;
        }
        Ok(())
    }
}

/// Reads what [`Rays`]' `Display` writes: `all`, or `exterior`, `angle:A` (`A` below
/// 180) and `occluders:F` (6 hexadecimal digits, not all 0), each at most once,
/// separated by commas.
impl core::str::FromStr for Rays {
    type Err = RaysError;

    fn from_str(s: &str) -> Result<Self, RaysError> {
        let mut rays = Rays::ALL;
        if s == "all" {
            return Ok(rays);
        }
        let mut seen = [false; 3];
        for part in s.split(',') {
            let angle = part
                .strip_prefix("angle:")
                .and_then(|a| a.parse::<f32>().ok());
            let occluders = part
                .strip_prefix("occluders:")
                .filter(|f| f.len() == 6 && f.bytes().all(|b| b.is_ascii_hexdigit()))
                .and_then(|f| u32::from_str_radix(f, 16).ok());
            match (part, angle, occluders) {
                ("exterior", _, _) if !seen[0] => {
                    rays.exterior = true;
                    seen[0] = true;
                }
                (_, Some(a), _) if !seen[1] && a < 180.0 => {
                    rays.max_view_angle_deg = a;
                    seen[1] = true;
                }
                (_, _, Some(f)) if !seen[2] && f != 0 => {
                    rays.occluders = f;
                    seen[2] = true;
                }
                _ => return Err(RaysError::Unreadable),
            }
        }
        rays.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_round_trips_and_refuses_the_rest() {
        for text in [
            "all",
            "exterior",
            "angle:45",
            "exterior,angle:120.5",
            "angle:90",
            "occluders:00ab12",
            "exterior,angle:45,occluders:ffffff",
        ] {
            let rays: Rays = text.parse().unwrap();
            let mut back = heapless::String::<64>::new();
            core::fmt::write(&mut back, format_args!("{rays}")).unwrap();
            assert_eq!(back.as_str(), text);
        }
        assert_eq!(
            "angle:45,exterior".parse::<Rays>().unwrap().to_owned_text(),
            "exterior,angle:45"
        );
        for bad in [
            "",
            "none",
            "exterior,",
            "exterior,exterior",
            "angle:180",
            "angle:0",
            "angle:-3",
            "angle:NaN",
            "angle:45,angle:60",
            "all,exterior",
            "Exterior",
            "occluders:000000",
            "occluders:abc",
            "occluders:1234567",
            "occluders:+12345",
            "occluders:00ab12,occluders:00ab12",
        ] {
            assert!(bad.parse::<Rays>().is_err(), "{bad:?}");
        }
        let nan = Rays {
            max_view_angle_deg: f32::NAN,
            ..Rays::ALL
        };
        assert_eq!(nan.validate(), Err(RaysError::ViewAngle));
        assert_eq!(nan, nan, "bitwise equality");
    }

    impl Rays {
        fn to_owned_text(self) -> heapless::String<64> {
            let mut s = heapless::String::new();
            core::fmt::write(&mut s, format_args!("{self}")).unwrap();
            s
        }
    }

    #[test]
    fn holds_checks_start_and_angle() {
        let s = [0.0f32, 1.0, 2.0, 3.0];
        let hf = HeightField::new(&s, 2, 2, 2).unwrap();
        let q = |o: [f64; 3], d: [f64; 3]| Query::from_arrays(o, d, 0.0, f64::INFINITY).unwrap();
        let down = [0.1, 0.0, -1.0];
        let ext = Rays::EXTERIOR;
        assert!(ext.holds(&hf, &[], &q([0.5, 0.5, 3.5], down)));
        assert!(
            !ext.holds(&hf, &[], &q([0.5, 0.5, 2.5], down)),
            "inside the box"
        );
        assert!(
            !ext.holds(&hf, &[], &q([0.5, 0.5, 3.0], down)),
            "on its top face"
        );
        assert!(ext.holds(&hf, &[], &q([-0.5, 0.5, 1.0], [1.0, 0.0, 0.0])));
        let a45 = Rays {
            max_view_angle_deg: 45.0,
            ..Rays::ALL
        };
        assert!(a45.holds(&hf, &[], &q([0.5, 0.5, 1.0], [0.5, 0.5, -1.0])));
        assert!(
            !a45.holds(&hf, &[], &q([0.5, 0.5, 1.0], [1.0, 0.0, -1.0])),
            "at 45°: the margin"
        );
        assert!(!a45.holds(&hf, &[], &q([0.5, 0.5, 1.0], [1.0, 0.0, -0.5])));
        assert!(Rays::ALL.holds(&hf, &[], &q([0.5, 0.5, 1.0], [1.0, 0.0, 1.0])));
    }

    #[test]
    fn occluders_are_checked_and_guard_their_set() {
        let s = [0.0f32; 16];
        let hf = HeightField::new(&s, 4, 4, 4).unwrap();
        // A wall's top west of the field: x in [-2, -1], y in [-1, 4], z = 5.
        let top = |a: [f32; 2], b: [f32; 2], c: [f32; 2]| Occluder {
            corners: [[a[0], a[1], 5.0], [b[0], b[1], 5.0], [c[0], c[1], 5.0]],
        };
        let wall = [
            top([-2.0, -1.0], [-1.0, -1.0], [-1.0, 4.0]),
            top([-2.0, -1.0], [-1.0, 4.0], [-2.0, 4.0]),
        ];
        let set = Rays::EXTERIOR.passing_over(&wall).unwrap();
        assert_ne!(set.occluders, 0);
        assert_eq!(set.check_occluders(&wall), Ok(()));
        assert_eq!(
            set.check_occluders(&wall[..1]),
            Err(RaysError::OccludersDiffer)
        );
        assert_eq!(Rays::EXTERIOR.passing_over(&[]).unwrap(), Rays::EXTERIOR);
        let q = |o: [f64; 3], d: [f64; 3]| Query::from_arrays(o, d, 0.0, f64::INFINITY).unwrap();
        // From the east, down to the west: its line behind stays east of the wall.
        assert!(set.holds(&hf, &wall, &q([8.0, 1.5, 4.0], [-1.0, 0.0, -0.5])));
        // From the west over the wall at z 5.5, then down: held.
        assert!(set.holds(&hf, &wall, &q([-3.0, 1.5, 6.0], [1.0, 0.0, -0.25])));
        // Through the wall (z 4 under its top 5 at x = -1.5): not held.
        assert!(!set.holds(&hf, &wall, &q([-3.0, 1.5, 4.5], [1.0, 0.0, -0.25])));
        // The line behind the origin dips under the wall: not held either.
        assert!(!set.holds(&hf, &wall, &q([-0.5, 1.5, 4.0], [1.0, 0.0, 0.0])));
        // Under the wall only beyond the field (after leaving it eastwards... here
        // westwards, ahead of the ray past the footprint): held.
        assert!(set.holds(&hf, &wall, &q([3.5, 1.5, 4.0], [-1.0, 0.0, -0.1])));
        // Vertical through the wall's footprint, and beside it.
        assert!(!set.holds(&hf, &wall, &q([-1.5, 1.5, 9.0], [0.0, 0.0, -1.0])));
        assert!(set.holds(&hf, &wall, &q([1.5, 1.5, 9.0], [0.0, 0.0, -1.0])));
        // Without its occluders the set holds no ray.
        assert!(!set.holds(&hf, &[], &q([8.0, 1.5, 4.0], [-1.0, 0.0, -0.5])));
        for bad in [
            [[0.0, 0.0, 1.0], [1.0, 1.0, 2.0], [2.0, 2.0, 3.0]],
            [[0.0, 0.0, f32::NAN], [1.0, 0.0, 2.0], [0.0, 1.0, 3.0]],
            [[0.0, 0.0, 1.0], [f32::INFINITY, 0.0, 2.0], [0.0, 1.0, 3.0]],
        ] {
            let o = [Occluder { corners: bad }];
            assert_eq!(Rays::EXTERIOR.passing_over(&o), Err(RaysError::Occluder));
        }
        let many = [wall[0]; MAX_OCCLUDERS + 1];
        assert_eq!(Rays::EXTERIOR.passing_over(&many), Err(RaysError::Occluder));
        assert!(Rays::EXTERIOR.passing_over(&many[1..]).is_ok());
    }
}
