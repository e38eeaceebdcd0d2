//! The blocks of a row that a group's azimuths may meet ([`Sector::blocks_met`]), so
//! that the pass over the field ([`super::Plan::wedges`]) reads only those: a
//! telephoto's wedges meet a few percent of each row.
//!
//! The group's azimuths, seen from the eye, form a sector of the plane: a cone with its
//! apex at the eye, bounded by the rays at the least and greatest pseudo-angle. Where it
//! spans less than a half turn it is convex, so its part in a row of blocks (the strip
//! between two sample rows) is a convex polygon whose vertices lie on the strip's two
//! lines or at the eye; the blocks it meets are those whose columns meet the polygon's
//! extent in x. The sector is widened far past the pass's own rounding (its
//! pseudo-angles are `f32`, a few ulps off), and the blocks found by a block more on
//! each side: every block the pass would raise a wedge with is among them, so the
//! horizon is the same as from whole rows.

/// Widening of the group's pseudo-angle range (at each end) before it bounds the blocks
/// the pass reads: about 0.006°, a thousand times the pass's own slack and rounding.
const MARGIN: f64 = 1e-4;

/// The group's azimuths as a cone from the eye: its apex and boundary directions,
/// counter-clockwise from `lo` to `hi` (grid space).
#[derive(Clone, Copy, Debug)]
pub(super) struct Sector {
    eye: [f64; 2],
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Sector {
    /// The pseudo-angles `lo..=hi` about `axis` (unit) from `eye`, widened by
    /// [`MARGIN`]; `None` when that spans half a turn or more, or reaches the cut behind
    /// the axis (then every block of a row is read).
    pub(super) fn new(eye: [f64; 3], axis: [f64; 2], (lo, hi): (f64, f64)) -> Option<Sector> {
        let (lo, hi) = (lo - MARGIN, hi + MARGIN);
        let fits = lo > -2.0 && hi < 2.0 && hi - lo < 2.0 - MARGIN;
        fits.then(|| Sector {
            eye: [eye[0], eye[1]],
            lo: direction(lo, axis),
            hi: direction(hi, axis),
        })
    }

    /// The blocks `i` of `0..blocks` (block `i` spanning sample columns
    /// `i · block ..= (i + 1) · block`, the last one to the field's edge) whose part of
    /// the strip between sample rows `y0 ≤ y1` the sector may meet: a range, empty when
    /// it meets none.
    pub(super) fn blocks_met(
        &self,
        (y0, y1): (u32, u32),
        block: u32,
        blocks: usize,
    ) -> core::ops::Range<usize> {
        let Some((x0, x1)) = self.x_extent(f64::from(y0), f64::from(y1)) else {
            return 0..0;
        };
        let per = f64::from(block);
        let first = (libm::floor(x0 / per) - 1.0).clamp(0.0, blocks as f64) as usize;
        let last = (libm::ceil(x1 / per) + 1.0).clamp(0.0, blocks as f64) as usize;
        first..last.max(first)
    }

    /// The least and greatest `x` of the sector's points with `y` in `[y0, y1]`
    /// (infinite where the sector runs along the strip); `None` when it has none.
    fn x_extent(&self, y0: f64, y1: f64) -> Option<(f64, f64)> {
        let [ex, ey] = self.eye;
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |x: f64| (x0, x1) = (x0.min(x), x1.max(x));
        if y0 <= ey && ey <= y1 {
            take(ex);
        }
        for y in [y0, y1] {
            let dy = y - ey;
            if dy == 0.0 {
                // The line through the eye: the sector's part of it may run either way.
                return Some((f64::NEG_INFINITY, f64::INFINITY));
            }
            // The directions that reach the line (`d_y` of the sign of `dy`) form one
            // arc of the sector, along which `x` is monotone; where the sector leaves
            // them, it runs off to infinity along the line (ccw: to `+x` above the eye
            // on entering, to `−x` on leaving; below the eye the other way).
            let reaches = |u: [f64; 2]| u[1] * dy > 0.0;
            let at = |u: [f64; 2]| ex + dy * u[0] / u[1];
            let up = dy > 0.0;
            match (reaches(self.lo), reaches(self.hi)) {
                (true, true) => {
                    take(at(self.lo));
                    take(at(self.hi));
                }
                (true, false) => {
                    take(at(self.lo));
                    take(if up { f64::NEG_INFINITY } else { f64::INFINITY });
                }
                (false, true) => {
                    take(at(self.hi));
                    take(if up { f64::INFINITY } else { f64::NEG_INFINITY });
                }
                // An arc of less than a half turn that starts and ends outside the
                // half-plane never enters it.
                (false, false) => {}
            }
        }
        (x0 <= x1).then_some((x0, x1))
    }
}

/// A direction (grid space) whose pseudo-angle about `axis` is `p` (in `[−2, 2]`).
fn direction(p: f64, axis: [f64; 2]) -> [f64; 2] {
    // In the axis's frame: on the unit diamond, `|x| + |y| = 1`.
    let (x, y) = if p.abs() <= 1.0 {
        (1.0 - p.abs(), p)
    } else {
        let r = if p > 0.0 { 2.0 - p } else { -2.0 - p };
        (r.abs() - 1.0, r)
    };
    [x * axis[0] - y * axis[1], x * axis[1] + y * axis[0]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_have_their_pseudo_angles() {
        let axis = [0.6, 0.8];
        for k in -20..=20 {
            let p = f64::from(k) / 10.0;
            let [x, y] = direction(p, axis);
            let a =
                super::super::pseudo_angle(x * axis[0] + y * axis[1], y * axis[0] - x * axis[1]);
            let same = (a - p).abs() < 1e-12 || (a.abs() == 2.0 && p.abs() == 2.0);
            assert!(same, "p {p}: {a}");
        }
    }

    /// Every grid point whose pseudo-angle lies in the range, from eyes on and off the
    /// lattice, lies in the extent found for its row's strip.
    #[test]
    fn the_extent_holds_every_point_of_the_sector() {
        let eyes = [
            [10.0, 10.0, 5.0],
            [10.5, -3.25, 5.0],
            [-7.5, 20.0, 5.0],
            [33.0, 12.5, 1.0],
        ];
        let axes = [[1.0, 0.0], [0.6, 0.8], [-0.8, 0.6], [0.0, -1.0]];
        let mut met = 0;
        for eye in eyes {
            for axis in axes {
                for (lo, hi) in [(-0.1, 0.1), (-0.9, 0.3), (0.5, 1.9), (-1.95, -1.5)] {
                    let sector = Sector::new(eye, axis, (lo, hi)).expect("under a half turn");
                    for y in 0u32..40 {
                        let extent = sector.x_extent(f64::from(y), f64::from(y + 1));
                        let points =
                            (-20i32..100).flat_map(|x| [0.0, 0.25, 0.5, 1.0].map(|f| (x, f)));
                        for (x, f) in points {
                            let (x, py) = (f64::from(x) / 2.0, f64::from(y) + f);
                            let (dx, dy) = (x - eye[0], py - eye[1]);
                            let a = super::super::pseudo_angle(
                                dx * axis[0] + dy * axis[1],
                                dy * axis[0] - dx * axis[1],
                            );
                            if !(a >= lo && a <= hi) {
                                continue;
                            }
                            met += 1;
                            let (x0, x1) = extent.expect("a point of the strip");
                            assert!(x0 <= x && x <= x1, "{eye:?} {axis:?} {py} {x}");
                        }
                    }
                }
            }
        }
        assert!(met > 1000, "{met}");
    }

    #[test]
    fn half_turns_and_the_cut_read_whole_rows() {
        let eye = [0.0, 0.0, 1.0];
        assert!(Sector::new(eye, [1.0, 0.0], (-1.0, 1.0)).is_none());
        assert!(Sector::new(eye, [1.0, 0.0], (1.5, 2.0)).is_none());
        assert!(Sector::new(eye, [1.0, 0.0], (-2.0, -1.5)).is_none());
        assert!(Sector::new(eye, [1.0, 0.0], (-0.9, 0.9)).is_some());
    }
}

#[cfg(test)]
mod pass {
    use super::super::{Frame, Plan};
    use crate::field::HeightField;
    use crate::surface::Surface;
    use alloc::vec::Vec;

    /// The pass over the sector's blocks gives the slopes of the pass over whole rows,
    /// bit for bit, from eyes in, over and off the field (on the lattice and off it),
    /// for narrow and wide groups, on blocks of 1, 2 and 4 cells, and reads fewer
    /// blocks where the group is narrow.
    #[test]
    fn the_sectors_pass_is_the_whole_pass() {
        let n = 97u32;
        let heights: Vec<f32> = (0..n * n)
            .map(|k| {
                let (x, y) = (f64::from(k % n), f64::from(k / n));
                (8.0 * libm::sin(x * 0.37) * libm::cos(y * 0.23) + 0.05 * x) as f32
            })
            .collect();
        let hf = HeightField::new(&heights, n, n, n as usize).expect("a field");
        let eyes = [
            [48.0, 48.0, 30.0],
            [-20.5, 40.25, 12.0],
            [120.0, -15.0, 4.0],
            [30.0, 200.0, 40.0],
            [96.0, 0.0, 9.0],
            [40.5, 50.5, 30.0],
            [60.25, 20.75, 12.0],
        ];
        let mut compared = 0;
        for eye in eyes {
            let to_center = [48.0 - eye[0], 48.0 - eye[1]];
            let len = libm::sqrt(to_center[0] * to_center[0] + to_center[1] * to_center[1]);
            let axis = if len > 0.0 {
                [to_center[0] / len, to_center[1] / len]
            } else {
                [0.6, 0.8]
            };
            for (lo, hi) in [(-0.02, 0.02), (-0.3, 0.1), (-0.9, 0.9), (-1.7, 1.7)] {
                for block in [1, 2, 4] {
                    let frame = Frame { axis, lo, hi };
                    let plan = Plan::new(&hf, Surface::Triangles, eye, frame, 64, block);
                    let rows = 0..plan.block_rows();
                    let whole = plan.wedges_reading(rows.clone(), false);
                    let sector = plan.wedges_reading(rows, true);
                    let same = whole
                        .iter()
                        .zip(&sector)
                        .all(|(a, b)| a.to_bits() == b.to_bits());
                    assert!(
                        same && whole.len() == sector.len(),
                        "{eye:?} {lo} {hi} {block}"
                    );
                    compared += whole.iter().filter(|g| **g > f32::NEG_INFINITY).count();
                }
            }
        }
        assert!(compared > 10_000, "{compared}");
        // A narrow group seen from off the field reads a small part of its rows.
        let sector = super::Sector::new([-20.5, 40.25, 12.0], [1.0, 0.0], (-0.02, 0.02));
        let sector = sector.expect("a narrow sector");
        let read: usize = (0..n - 1)
            .map(|y| sector.blocks_met((y, y + 1), 1, n as usize - 1).len())
            .sum();
        assert!(read > 0 && read * 10 < (n as usize - 1).pow(2), "{read}");
    }
}
