//! parry3d's `HeightField` ray cast as a peer, on the same rays.
//!
//! parry3d's height field is y-up, centred on the origin and scaled to its size: sample
//! (row i, column j) of its `heights` array sits at `x = −½ + j / (ncols − 1)`,
//! `z = −½ + i / (nrows − 1)`, times `scale`. Our sample (i, j) (x = i, y = j) becomes
//! its row j, column i, with `scale = (W − 1, 1, H − 1)`; a ray is moved into that frame
//! by subtracting the footprint's centre in `f32` (as a user would) and swapping y and
//! z. Each cell is split into two triangles along a fixed diagonal (row i + 1 column j
//! to row i column j + 1) unless its status has `ZIGZAG_SUBDIVISION`, which takes the
//! other diagonal: setting that status where our lower-diagonal rule picks the 00–11
//! diagonal gives exactly our triangle surface ("split as ours"); leaving every status
//! empty gives parry3d's default ("fixed split").
//!
//! Semantics differ, and the report counts those rays apart: parry3d's height field is
//! a surface, not a solid (a ray starting under it does not hit at its origin, and one
//! entering a side of the box below the surface passes through and may hit a triangle
//! from below), and each triangle is tested on its own (no shared edge clearances).

use super::methods::{Caster, Out};
use hfcast::{dda, HeightField, Query};
use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};
use parry3d::shape::{HeightField as ParryField, HeightFieldCellStatus};
use parry3d::utils::Array2;

/// parry3d's height field of one of our fields, and the offset between the frames.
pub struct ParryCaster<'a> {
    field: ParryField,
    centre: [f32; 2],
    hf: HeightField<'a>,
    bytes: usize,
}

impl<'a> ParryCaster<'a> {
    /// Builds parry3d's field for `hf`; `matched` sets each cell's split to ours.
    pub fn new(hf: &HeightField<'a>, matched: bool) -> ParryCaster<'a> {
        let (w, h) = (hf.width() as usize, hf.height() as usize);
        let heights = Array2::from_fn(h, w, |i, j| hf.at(j as u32, i as u32));
        let scale = Vector::new((w - 1) as f32, 1.0, (h - 1) as f32);
        let mut field = ParryField::new(heights, scale);
        if matched {
            let status = field.cells_statuses_mut();
            for j in 0..h - 1 {
                for i in 0..w - 1 {
                    let [h00, h10, h01, h11] = hf.cell_corners(i as u32, j as u32);
                    if h00 + h11 <= h10 + h01 {
                        status[(j, i)] = HeightFieldCellStatus::ZIGZAG_SUBDIVISION;
                    }
                }
            }
        }
        ParryCaster {
            field,
            centre: [(w - 1) as f32 * 0.5, (h - 1) as f32 * 0.5],
            hf: *hf,
            // Heights (f32) and one status byte per cell.
            bytes: w * h * 4 + (w - 1) * (h - 1),
        }
    }

    /// Our ray in parry3d's frame.
    #[inline]
    fn ray(&self, q: &Query<f32>) -> Ray {
        let (o, d) = (q.origin(), q.dir());
        Ray::new(
            Vector::new(o[0] - self.centre[0], o[2], o[1] - self.centre[1]),
            Vector::new(d[0], d[2], d[1]),
        )
    }
}

impl Caster for ParryCaster<'_> {
    fn trace_all(&self, rays: &[Query<f32>], out: &mut [Out]) {
        for (o, q) in out.iter_mut().zip(rays) {
            let ray = self.ray(q);
            let max = if q.t_max().is_finite() {
                q.t_max()
            } else {
                f32::MAX
            };
            let toi = self.field.cast_local_ray(&ray, max, true);
            *o = Out {
                hit: toi.filter(|&t| t >= q.t_min()).map(|t| {
                    let p = ray.point_at(t);
                    [
                        f64::from(p.x) + f64::from(self.centre[0]),
                        f64::from(p.z) + f64::from(self.centre[1]),
                        f64::from(p.y),
                    ]
                }),
                fetches: 0,
                flags: 0,
            };
        }
    }

    fn baked_bytes(&self) -> usize {
        self.bytes
    }

    /// Estimated fetches: 4 per cell from the box entry to the hit (or the box exit).
    fn fill_fetches(&self, rays: &[Query<f32>], out: &mut [Out]) {
        for (o, q) in out.iter_mut().zip(rays) {
            let q = q.cast::<f64>();
            let Some(span) = dda::clip(&self.hf, &q) else {
                o.fetches = 0;
                continue;
            };
            let d = q.dir();
            let t_end = match o.hit {
                Some(p) => {
                    let k = (0..3).max_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()));
                    let k = k.unwrap_or(0);
                    ((p[k] - q.origin()[k]) / d[k]).clamp(span.t0, span.t1)
                }
                None => span.t1,
            };
            let (a, b) = (q.at(span.t0), q.at(t_end));
            let lim = [
                f64::from(self.hf.width() - 2),
                f64::from(self.hf.height() - 2),
            ];
            let cells: f64 = (0..2)
                .map(|k| (b[k].floor().clamp(0.0, lim[k]) - a[k].floor().clamp(0.0, lim[k])).abs())
                .sum();
            o.fetches = 4 * (1 + cells as u32);
        }
    }
}
