//! The bake-free baselines every engine ships: fixed linear steps through the field's
//! box, then a refinement. Approximate: a feature thinner than a step is missed, and
//! the refined point is only as good as the refinement. Measured, never called exact.
//!
//! [`linear`] does the linear search, then refines the bracket it found ([`Refine`]):
//!
//! - [`Refine::Binary`]: binary search (Policarpo et al. 2005);
//! - [`Refine::Secant`]: one secant step on the last bracket, as in parallax occlusion
//!   mapping (Tatarchuk 2006).
//!
//! Cost: four fetches per height sample (the cell's corners).

use crate::dda::{clip_surface, Entry};
use crate::field::HeightField;
use crate::math::Real;
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::{locate, Surface};

/// Step counts of the search baselines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SearchSteps {
    /// Equal steps from the entry to the exit of the field's bounding box (≥ 1).
    pub linear: u32,
    /// Bisection steps after the linear search (ignored by the secant variant).
    pub binary: u32,
}

/// How [`linear`] refines the bracket its linear search found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refine {
    /// That many bisections of the bracket (Policarpo et al. 2005).
    Binary(u32),
    /// One secant step on the bracket: parallax occlusion mapping (Tatarchuk 2006).
    Secant,
}

/// Linear search with `linear_steps` equal steps (at least 1) through the field's box,
/// then `refine` on the first bracket that goes under the surface.
pub fn linear<R: Real>(
    hf: &HeightField,
    surface: Surface,
    q: &Query<R>,
    linear_steps: u32,
    refine: Refine,
) -> Trace<R> {
    let Some(span) = clip_surface(hf, surface, q) else {
        return Trace::MISS;
    };
    let mut fetches = 0u32;
    let mut clearance_at = |t: R| {
        fetches += 4;
        let p = q.at(t);
        p[2] - surface.height_at(hf, p[0], p[1])
    };
    let linear = linear_steps.max(1);
    let dt = (span.t1 - span.t0) / R::from_u32(linear);
    let mut prev = (span.t0, clearance_at(span.t0));
    let mut bracket = None;
    if prev.1 <= R::ZERO {
        bracket = Some((prev, prev));
    } else {
        for k in 1..=linear {
            let t = if k == linear {
                span.t1
            } else {
                span.t0 + dt * R::from_u32(k)
            };
            let c = clearance_at(t);
            if c <= R::ZERO {
                bracket = Some((prev, (t, c)));
                break;
            }
            prev = (t, c);
        }
    }
    let Some((mut above, mut under)) = bracket else {
        return Trace {
            fetches,
            ..Trace::MISS
        };
    };
    let t = if above.0 == under.0 {
        under.0
    } else {
        match refine {
            Refine::Binary(n) => {
                for _ in 0..n {
                    let mid = R::HALF * (above.0 + under.0);
                    let c = clearance_at(mid);
                    if c <= R::ZERO {
                        under = (mid, c);
                    } else {
                        above = (mid, c);
                    }
                }
                R::HALF * (above.0 + under.0)
            }
            Refine::Secant => above.0 + (under.0 - above.0) * above.1 / (above.1 - under.1),
        }
    };
    let p = q.at(t);
    let (c, u, v, cell) = locate(hf, p[0], p[1]);
    let flags = match span.entry {
        _ if t > span.t0 => Flags::default(),
        Entry::Start => Flags::ORIGIN_INSIDE,
        Entry::Side(_) => Flags::SIDE,
        Entry::Top => Flags::default(),
    };
    Trace::hit(
        Hit {
            t,
            point: R::v3(p),
            cell,
            normal: R::v3(surface.cell_normal(c, u, v)),
            flags,
        },
        fetches,
        R::INFINITY,
    )
}
