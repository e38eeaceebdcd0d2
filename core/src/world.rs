//! World units: where a field's grid sits in the caller's frame.
//!
//! Every march works in grid space (x along sample columns, y along rows, z up, all in
//! sample spacings). A [`WorldTransform`] places that grid in the caller's frame by a
//! per-axis scale and an offset:
//!
//! ```text
//! world = (origin_x + spacing_x · x,  origin_y + spacing_y · y,  height_offset + height_scale · z)
//! ```
//!
//! Such a map keeps straight lines straight and keeps the ray parameter: the world
//! ray `o + t·d` is the grid ray `(o − origin)/scale + t · d/scale`, so `t`, `t_min`
//! and `t_max` mean the same in both frames and a hit's `t` needs no conversion. A
//! triangle, bilinear patch or plane of grid space is one of the same kind in world
//! space, so every surface and every exact march stays exact on the converted ray.
//! Points map back by the formula above, normals by the inverse transpose
//! (`n / scale`, renormalised) and vertical clearances by `height_scale`.
//!
//! The conversion runs in `f64` and rounds once to the march's precision. The
//! identity transform converts nothing (bit-identical rays and hits). Precision: an
//! `f32` world coordinate far from `origin` (georeferenced metres, say) carries its
//! own rounding; put `origin` near the field and the camera.

use crate::math::Real;
use crate::ray::{Hit, Query, RayError, Trace};
use crate::{HeightField, Surface};
use core::fmt;

/// Why a transform was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransformError {
    /// A component is NaN or infinite.
    NotFinite,
    /// `spacing_x` or `spacing_y` is zero.
    ZeroSpacing,
    /// `height_scale` is not positive (up must stay up: the solid is below the surface).
    HeightScaleNotPositive,
}

impl fmt::Display for TransformError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TransformError::NotFinite => "a transform component is NaN or infinite",
            TransformError::ZeroSpacing => "a sample spacing is zero",
            TransformError::HeightScaleNotPositive => "the height scale must be positive",
        })
    }
}

/// The grid-to-world map of a field: origin of sample (0, 0) at height 0, x/y sample
/// spacing (negative flips the axis, e.g. y north for a north-up raster), height scale
/// and offset. See the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldTransform {
    /// World position of grid point (0, 0, 0): `[origin_x, origin_y, height_offset]`.
    offset: [f64; 3],
    /// World units per grid unit: `[spacing_x, spacing_y, height_scale]`.
    scale: [f64; 3],
}

impl Default for WorldTransform {
    fn default() -> Self {
        WorldTransform::IDENTITY
    }
}

impl WorldTransform {
    /// World space is grid space.
    pub const IDENTITY: WorldTransform = WorldTransform {
        offset: [0.0; 3],
        scale: [1.0; 3],
    };

    /// Checks and builds a transform: everything finite, spacings non-zero, height
    /// scale positive.
    pub fn new(
        origin: [f64; 2],
        spacing: [f64; 2],
        height_scale: f64,
        height_offset: f64,
    ) -> Result<WorldTransform, TransformError> {
        let all = [origin[0], origin[1], spacing[0], spacing[1]];
        if !all
            .iter()
            .chain(&[height_scale, height_offset])
            .all(|v| v.is_finite())
        {
            return Err(TransformError::NotFinite);
        }
        if spacing[0] == 0.0 || spacing[1] == 0.0 {
            return Err(TransformError::ZeroSpacing);
        }
        if height_scale <= 0.0 {
            return Err(TransformError::HeightScaleNotPositive);
        }
        Ok(WorldTransform {
            offset: [origin[0], origin[1], height_offset],
            scale: [spacing[0], spacing[1], height_scale],
        })
    }

    /// World position of sample (0, 0) at height 0 (x, y).
    pub fn origin(&self) -> [f64; 2] {
        [self.offset[0], self.offset[1]]
    }
    /// World units between neighbouring samples along x and y.
    pub fn spacing(&self) -> [f64; 2] {
        [self.scale[0], self.scale[1]]
    }
    /// World height units per grid height unit.
    pub fn height_scale(&self) -> f64 {
        self.scale[2]
    }
    /// World height of grid height 0.
    pub fn height_offset(&self) -> f64 {
        self.offset[2]
    }
    /// `true` for [`WorldTransform::IDENTITY`].
    #[inline]
    pub fn is_identity(&self) -> bool {
        *self == WorldTransform::IDENTITY
    }

    /// A world point in grid space.
    pub fn point_to_grid(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| (p[k] - self.offset[k]) / self.scale[k])
    }
    /// A grid point in world space.
    pub fn point_to_world(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| self.offset[k] + self.scale[k] * p[k])
    }
    /// A world direction in grid space (the same `t` advances both).
    pub fn dir_to_grid(&self, d: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| d[k] / self.scale[k])
    }
    /// A grid direction in world space.
    pub fn dir_to_world(&self, d: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| d[k] * self.scale[k])
    }
    /// A grid normal in world space: the inverse transpose, renormalised.
    pub fn normal_to_world(&self, n: [f64; 3]) -> [f64; 3] {
        let m = [0, 1, 2].map(|k| n[k] / self.scale[k]);
        let len = libm::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if len > 0.0 {
            m.map(|v| v / len)
        } else {
            m
        }
    }

    /// The grid-space query of a world ray, checked as [`Query::from_arrays`] checks
    /// (a ray whose converted origin or direction overflows or underflows to zero is a
    /// [`RayError`], never a silent miss). The identity returns the ray unchanged.
    pub fn query_to_grid<R: Real>(
        &self,
        origin: [R; 3],
        dir: [R; 3],
        t_min: R,
        t_max: R,
    ) -> Result<Query<R>, RayError> {
        if self.is_identity() {
            return Query::from_arrays(origin, dir, t_min, t_max);
        }
        // Check the world ray first, so its own faults are named as such.
        Query::from_arrays(origin, dir, t_min, t_max)?;
        let f64s = |v: [R; 3]| v.map(R::to_f64);
        let back = |v: [f64; 3]| v.map(R::from_f64);
        let o = back(self.point_to_grid(f64s(origin)));
        let d = back(self.dir_to_grid(f64s(dir)));
        Query::from_arrays(o, d, t_min, t_max)
    }

    /// A grid-space trace in world units: the hit point and normal mapped to world
    /// space, the clearance scaled by the height scale; `t`, the cell, the flags and
    /// the fetches unchanged. The identity returns the trace unchanged.
    pub fn trace_to_world<R: Real>(&self, mut tr: Trace<R>) -> Trace<R> {
        if self.is_identity() {
            return tr;
        }
        let f64s = |v: R::V3| R::xyz(v).map(R::to_f64);
        let back = |v: [f64; 3]| R::v3(v.map(R::from_f64));
        if let Some(h) = tr.hit.as_mut() {
            h.point = back(self.point_to_world(f64s(h.point)));
            h.normal = back(self.normal_to_world(f64s(h.normal)));
        }
        if tr.clearance.is_finite() {
            tr.clearance = R::from_f64(tr.clearance.to_f64() * self.scale[2]);
        }
        tr
    }

    /// [`Hit::shadow_query`] in world units: a shadow ray from `hit` (a world-space hit
    /// of `primary` on `surface` of `hf`, whose grid this transform places) towards
    /// `to_light` (a world direction), starting outside the solid. The lift is
    /// computed in grid space and the origin mapped back.
    pub fn shadow_query<R: Real>(
        &self,
        hf: &HeightField,
        surface: Surface,
        primary: &Query<R>,
        hit: &Hit<R>,
        to_light: [R; 3],
    ) -> Result<Query<R>, RayError> {
        let f64s = |v: [R; 3]| v.map(R::to_f64);
        let back = |v: [f64; 3]| v.map(R::from_f64);
        let mut grid = *hit;
        grid.point = R::v3(back(self.point_to_grid(f64s(R::xyz(hit.point)))));
        // The inverse of `normal_to_world`: n_grid ∝ n_world · scale.
        let n = self.dir_to_world(f64s(R::xyz(hit.normal)));
        let len = libm::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        grid.normal = R::v3(back(n.map(|v| if len > 0.0 { v / len } else { v })));
        let o = back(self.point_to_grid(f64s(primary.origin())));
        let m = o.iter().fold(R::ZERO, |m, v| m.max(v.abs()));
        let light = back(self.dir_to_grid(f64s(to_light)));
        let q = grid.shadow_query(hf, surface, light, m)?;
        let origin = back(self.point_to_world(f64s(q.origin())));
        Query::from_arrays(origin, to_light, R::ZERO, R::INFINITY)
    }

    /// [`Hit::shadow_query_from_light`] in world units: [`WorldTransform::shadow_query`]
    /// walked back from the light's side ([`WorldTransform::walked_back`]).
    pub fn shadow_query_from_light<R: Real>(
        &self,
        hf: &HeightField,
        surface: Surface,
        primary: &Query<R>,
        hit: &Hit<R>,
        to_light: [R; 3],
    ) -> Result<Query<R>, RayError> {
        let q = self.shadow_query(hf, surface, primary, hit, to_light)?;
        self.walked_back(hf, &q)
    }

    /// [`Query::walked_back`] of a world ray: `t` is the same in both spaces, so the
    /// range comes from the grid ray and the origin stays the world one.
    pub fn walked_back<R: Real>(
        &self,
        hf: &HeightField,
        world: &Query<R>,
    ) -> Result<Query<R>, RayError> {
        let (o, d) = (world.origin(), world.dir());
        let grid = self.query_to_grid(o, d, world.t_min(), world.t_max())?;
        match grid.walked_back_range(hf) {
            Some((t_min, t_max)) => Query::from_arrays(o, d.map(|v| -v), t_min, t_max),
            None => Ok(*world),
        }
    }

    /// Traces a world ray: converts it to grid space, runs `trace` (any march) and
    /// converts the answer back.
    pub fn trace<R: Real>(
        &self,
        world: &Query<R>,
        trace: impl FnOnce(&Query<R>) -> Trace<R>,
    ) -> Result<Trace<R>, RayError> {
        let q = self.query_to_grid(world.origin(), world.dir(), world.t_min(), world.t_max())?;
        Ok(self.trace_to_world(trace(&q)))
    }
}
