//! Ray sets: which rays a baked map serves (exterior rays, a largest view angle;
//! Baboud, Eisemann, Seidel 2011, §6.2). A map baked for a set records it (its
//! description, [`crate::ktx2::Desc::rays`]), and its march checks every ray against
//! it ([`Rays::holds`]): a ray outside the set marches without the map's steps. The
//! bakes' side, which triangles limit the rays of a set, is in `safety::rays`.

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
}

/// Equal when both fields are (the angle bit for bit: so `Eq` and `Hash` hold).
impl PartialEq for Rays {
    fn eq(&self, o: &Rays) -> bool {
        self.exterior == o.exterior
            && self.max_view_angle_deg.to_bits() == o.max_view_angle_deg.to_bits()
    }
}

impl Eq for Rays {}

impl core::hash::Hash for Rays {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        (self.exterior, self.max_view_angle_deg.to_bits()).hash(h);
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
    /// Not a set's text (`Rays`' `FromStr`).
    Unreadable,
}

impl core::fmt::Display for RaysError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            RaysError::ViewAngle => "max_view_angle_deg is NaN or outside (0, 180]",
            RaysError::Unreadable => "not a ray set (all, exterior, angle:A, exterior,angle:A)",
        })
    }
}

impl Rays {
    /// Every ray.
    pub const ALL: Rays = Rays {
        exterior: false,
        max_view_angle_deg: 180.0,
    };

    /// The exterior rays, any direction.
    pub const EXTERIOR: Rays = Rays {
        exterior: true,
        max_view_angle_deg: 180.0,
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

    /// Whether the set is every ray.
    pub fn is_all(self) -> bool {
        !self.exterior && !self.limits_angle()
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
    /// distance (checked in `f64` from the query's own values, a millionth tighter).
    pub fn holds<R: Real>(self, hf: &HeightField, q: &Query<R>) -> bool {
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
        true
    }
}

/// `all`, `exterior`, `angle:A` or `exterior,angle:A` (`A` in degrees, as Rust prints
/// an `f32`): the KTX 2 `hfcast.ray_set` of a safety or cylinder–cone map.
impl core::fmt::Display for Rays {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match (self.exterior, self.limits_angle()) {
            (false, false) => f.write_str("all"),
            (true, false) => f.write_str("exterior"),
            (false, true) => write!(f, "angle:{}", self.max_view_angle_deg),
            (true, true) => write!(f, "exterior,angle:{}", self.max_view_angle_deg),
        }
    }
}

/// Reads what [`Rays`]' `Display` writes: `all`, or `exterior` and `angle:A` (`A`
/// below 180), each at most once, separated by a comma.
impl core::str::FromStr for Rays {
    type Err = RaysError;

    fn from_str(s: &str) -> Result<Self, RaysError> {
        let mut rays = Rays::ALL;
        if s == "all" {
            return Ok(rays);
        }
        for part in s.split(',') {
            let angle = part
                .strip_prefix("angle:")
                .and_then(|a| a.parse::<f32>().ok());
            match (part, angle) {
                ("exterior", _) if !rays.exterior => rays.exterior = true,
                (_, Some(a)) if !rays.limits_angle() && a < 180.0 => {
                    rays.max_view_angle_deg = a;
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
        ] {
            let rays: Rays = text.parse().unwrap();
            let mut back = heapless::String::<32>::new();
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
        ] {
            assert!(bad.parse::<Rays>().is_err(), "{bad:?}");
        }
        let nan = Rays {
            exterior: false,
            max_view_angle_deg: f32::NAN,
        };
        assert_eq!(nan.validate(), Err(RaysError::ViewAngle));
        assert_eq!(nan, nan, "bitwise equality");
    }

    impl Rays {
        fn to_owned_text(self) -> heapless::String<32> {
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
        assert!(ext.holds(&hf, &q([0.5, 0.5, 3.5], down)));
        assert!(!ext.holds(&hf, &q([0.5, 0.5, 2.5], down)), "inside the box");
        assert!(
            !ext.holds(&hf, &q([0.5, 0.5, 3.0], down)),
            "on its top face"
        );
        assert!(ext.holds(&hf, &q([-0.5, 0.5, 1.0], [1.0, 0.0, 0.0])));
        let a45 = Rays {
            exterior: false,
            max_view_angle_deg: 45.0,
        };
        assert!(a45.holds(&hf, &q([0.5, 0.5, 1.0], [0.5, 0.5, -1.0])));
        assert!(
            !a45.holds(&hf, &q([0.5, 0.5, 1.0], [1.0, 0.0, -1.0])),
            "at 45°: the margin"
        );
        assert!(!a45.holds(&hf, &q([0.5, 0.5, 1.0], [1.0, 0.0, -0.5])));
        assert!(Rays::ALL.holds(&hf, &q([0.5, 0.5, 1.0], [1.0, 0.0, 1.0])));
    }
}
