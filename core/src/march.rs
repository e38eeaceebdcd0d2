//! One march interface over every method: a [`Marcher`] holds what one method's march
//! reads (its baked map, its surface and options) and [`Marcher::trace`] runs it. The
//! C API's traces, the report and the tools go through it, so a new method is one more
//! variant here and one more row of the registry ([`MethodKind::info`]).

#[cfg(feature = "cone")]
use crate::cone::{self, ConeMap};
#[cfg(feature = "maxmip")]
use crate::maxmip::{self, MaxMip};
#[cfg(feature = "qdm")]
use crate::qdm::{self, QdmMap};
#[cfg(feature = "safety")]
use crate::radius::{self, RadiusMap};
#[cfg(feature = "relaxed")]
use crate::relaxed;
#[cfg(feature = "safety")]
use crate::safety::{self, cc, cc::CcMap, MarchSurface, SafetyMap};
use crate::scene::MethodKind;
#[cfg(feature = "search")]
use crate::search::{self, SearchSteps};
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
    /// Linear search then bisection ([`search::linear_binary`]).
    #[cfg(feature = "search")]
    LinearBinary(Surface, SearchSteps),
    /// Linear search then a secant step ([`search::linear_secant`]): the linear steps.
    #[cfg(feature = "search")]
    LinearSecant(Surface, u32),
    /// Maximum mipmaps ([`maxmip::trace`]).
    #[cfg(feature = "maxmip")]
    MaxMip(MaxMip<'a>, Surface, maxmip::Options),
    /// Safety distances ([`safety::trace_on`]).
    #[cfg(feature = "safety")]
    Safety(SafetyMap<'a>, MarchSurface),
    /// Cylinder–cone safety shapes ([`cc::trace_on`]).
    #[cfg(feature = "safety")]
    Cc(CcMap<'a>, MarchSurface),
    /// Safety radii ([`radius::trace`]).
    #[cfg(feature = "safety")]
    Radius(RadiusMap<'a>, radius::Options),
    /// Conservative cone steps ([`cone::trace`]): the iteration budget.
    #[cfg(feature = "cone")]
    Cone(ConeMap<'a>, u32),
    /// Relaxed cone steps ([`relaxed::trace`]) over the map's texels.
    #[cfg(feature = "relaxed")]
    Relaxed(&'a [f32], relaxed::Steps),
    /// Quadratic displacement steps ([`qdm::trace`]): the iteration budget.
    #[cfg(feature = "qdm")]
    Qdm(QdmMap<'a>, u32),
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
            Marcher::LinearBinary(surface, steps) => search::linear_binary(hf, surface, q, steps),
            #[cfg(feature = "search")]
            Marcher::LinearSecant(surface, n) => search::linear_secant(hf, surface, q, n),
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(ref mip, surface, ref opts) => maxmip::trace(hf, mip, surface, q, opts),
            #[cfg(feature = "safety")]
            Marcher::Safety(ref map, surface) => safety::trace_on(map, hf, surface, q),
            #[cfg(feature = "safety")]
            Marcher::Cc(ref map, surface) => cc::trace_on(map, hf, surface, q),
            #[cfg(feature = "safety")]
            Marcher::Radius(ref map, ref opts) => radius::trace(map, hf, q, opts),
            #[cfg(feature = "cone")]
            Marcher::Cone(ref map, n) => cone::trace(map, hf, q, n),
            #[cfg(feature = "relaxed")]
            Marcher::Relaxed(map, steps) => relaxed::trace(map, hf, q, steps),
            #[cfg(feature = "qdm")]
            Marcher::Qdm(ref map, n) => qdm::trace(map, hf, q, n),
            Marcher::Unbuilt(never, _) => match never {},
        }
    }
}
