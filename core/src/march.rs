//! One march interface over every method: a [`Marcher`] holds what one method's march
//! reads (its baked map, its surface and options) and [`Marcher::trace`] runs it. The
//! C API's traces, the report and the tools go through it, so a new method is one more
//! variant here and one more row of the registry ([`MethodKind::info`]).

use crate::scene::MethodKind;
use crate::{dda, HeightField, Query, Real, Surface, Trace};

/// A method ready to march: its map (borrowed), surface and options. Built by the
/// caller from a bake it has checked; [`Marcher::trace`] traces one query.
#[derive(Clone, Copy, Debug)]
// The maxmip view holds its level table (about 460 bytes): a marcher is built once per
// batch, not per ray, and a no_std core has no box to move it into.
#[allow(clippy::large_enum_variant)]
pub enum Marcher<'a> {
    /// The exact traversal on a surface ([`dda::trace`]).
    Exact(Surface),
    /// Linear search then bisection ([`crate::search::linear_binary`]).
    #[cfg(feature = "search")]
    LinearBinary(Surface, crate::search::SearchSteps),
    /// Linear search then a secant step ([`crate::search::linear_secant`]): the linear steps.
    #[cfg(feature = "search")]
    LinearSecant(Surface, u32),
    /// Maximum mipmaps ([`crate::maxmip::trace`]).
    #[cfg(feature = "maxmip")]
    MaxMip(crate::maxmip::MaxMip<'a>, Surface, crate::maxmip::Options),
    /// Safety distances ([`crate::safety::trace_on`]).
    #[cfg(feature = "safety")]
    Safety(crate::safety::SafetyMap<'a>, crate::safety::MarchSurface),
    /// Cylinder–cone safety shapes ([`crate::safety::cc::trace_on`]).
    #[cfg(feature = "safety")]
    Cc(crate::safety::cc::CcMap<'a>, crate::safety::MarchSurface),
    /// Safety radii ([`crate::radius::trace`]).
    #[cfg(feature = "safety")]
    Radius(crate::radius::RadiusMap<'a>, crate::radius::Options),
    /// Conservative cone steps ([`crate::cone::trace`]): the iteration budget.
    #[cfg(feature = "cone")]
    Cone(crate::cone::ConeMap<'a>, u32),
    /// Relaxed cone steps ([`crate::relaxed::trace`]) over the map's texels.
    #[cfg(feature = "relaxed")]
    Relaxed(&'a [f32], crate::relaxed::Steps),
    /// Quadratic displacement steps ([`crate::qdm::trace`]): the iteration budget.
    #[cfg(feature = "qdm")]
    Qdm(crate::qdm::QdmMap<'a>, u32),
    /// Never built: holds the lifetime in a build without baked methods.
    #[doc(hidden)]
    Unbuilt(core::convert::Infallible, core::marker::PhantomData<&'a ()>),
}

impl Marcher<'_> {
    /// The method it marches.
    pub fn kind(&self) -> MethodKind {
        match self {
            Marcher::Exact(_) => MethodKind::Exact,
            #[cfg(feature = "search")]
            Marcher::LinearBinary(..) => MethodKind::LinearBinary,
            #[cfg(feature = "search")]
            Marcher::LinearSecant(..) => MethodKind::LinearSecant,
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(..) => MethodKind::MaxMip,
            #[cfg(feature = "safety")]
            Marcher::Safety(..) => MethodKind::Safety,
            #[cfg(feature = "safety")]
            Marcher::Cc(..) => MethodKind::Cc,
            #[cfg(feature = "safety")]
            Marcher::Radius(..) => MethodKind::Radius,
            #[cfg(feature = "cone")]
            Marcher::Cone(..) => MethodKind::Cone,
            #[cfg(feature = "relaxed")]
            Marcher::Relaxed(..) => MethodKind::Relaxed,
            #[cfg(feature = "qdm")]
            Marcher::Qdm(..) => MethodKind::Qdm,
            Marcher::Unbuilt(never, _) => match *never {},
        }
    }

    /// Traces `q` on `hf`, the field the map was baked for.
    pub fn trace<R: Real>(&self, hf: &HeightField, q: &Query<R>) -> Trace<R> {
        match *self {
            Marcher::Exact(surface) => dda::trace(hf, surface, q),
            #[cfg(feature = "search")]
            Marcher::LinearBinary(surface, steps) => {
                crate::search::linear_binary(hf, surface, q, steps)
            }
            #[cfg(feature = "search")]
            Marcher::LinearSecant(surface, n) => crate::search::linear_secant(hf, surface, q, n),
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(ref mip, surface, ref opts) => {
                crate::maxmip::trace(hf, mip, surface, q, opts)
            }
            #[cfg(feature = "safety")]
            Marcher::Safety(ref map, surface) => crate::safety::trace_on(map, hf, surface, q),
            #[cfg(feature = "safety")]
            Marcher::Cc(ref map, surface) => crate::safety::cc::trace_on(map, hf, surface, q),
            #[cfg(feature = "safety")]
            Marcher::Radius(ref map, ref opts) => crate::radius::trace(map, hf, q, opts),
            #[cfg(feature = "cone")]
            Marcher::Cone(ref map, n) => crate::cone::trace(map, hf, q, n),
            #[cfg(feature = "relaxed")]
            Marcher::Relaxed(map, steps) => crate::relaxed::trace(map, hf, q, steps),
            #[cfg(feature = "qdm")]
            Marcher::Qdm(ref map, n) => crate::qdm::trace(map, hf, q, n),
            Marcher::Unbuilt(never, _) => match never {},
        }
    }
}
