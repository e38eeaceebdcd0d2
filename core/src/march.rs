//! One march interface over every method: a [`Marcher`] holds what one method's march
//! reads (its baked map, its surface and options) and [`Marcher::trace`] runs it. The
//! C API's traces, the report and the tools go through it, so a new method is one more
//! variant here and one more row of the registry ([`MethodKind::info`]).

use crate::bake::Error;
use crate::ktx2::{Data, Desc, MapKind};
use crate::scene::MethodKind;
use crate::{dda, HeightField, Query, Real, Surface, Trace};

/// What a march reads besides its map: the surface and the step budgets (the C API's
/// `hf_trace_options`). Each method reads the fields its registry row names
/// ([`MethodKind::info`]`.steps`) and ignores the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MarchOptions {
    /// The surface traced.
    pub surface: Surface,
    /// The first step budget: linear steps (searches), iterations (cone, QDM), cone
    /// steps (relaxed).
    pub steps: u32,
    /// Bisection steps (linear-binary, relaxed).
    pub binary_steps: u32,
    /// Radius: jump zero radii as one (**not exact**) instead of walking them.
    pub radius_clamp: bool,
}

impl MarchOptions {
    /// The defaults on `surface`: the registry's step budgets (64 steps, 8 bisections),
    /// zero radii walked.
    pub fn on(surface: Surface) -> MarchOptions {
        let steps = MethodKind::LinearBinary.info().steps;
        MarchOptions {
            surface,
            steps: steps[0].default,
            binary_steps: steps[1].default,
            radius_clamp: false,
        }
    }
}

/// Cells the maximum mipmap walks cell by cell after a horizon's start before its own
/// march takes over ([`Marcher::trace_started`]).
#[cfg(all(feature = "alloc", feature = "maxmip"))]
const DDA_CELLS: u32 = 16;

/// Cells the DDA walks from a horizon's start, or from the start of a span, before
/// the horizon may cut the walk ([`Marcher::trace_placed`]): most rays hit before and
/// never look for a cut (looking for one at every start cost terrain frames 8–10 %).
#[cfg(feature = "alloc")]
const SPAN_CELLS: u32 = 64;

/// A query placed at a start: its position in the batch, a bound of its clearance
/// before the start, texels read before it, and where its span ends.
#[cfg(feature = "alloc")]
type Pending = (usize, f32, u32, crate::horizon::End<f32>);

/// The buffers [`Marcher::trace_placed`] reuses from call to call.
#[cfg(feature = "alloc")]
#[derive(Clone, Debug, Default)]
pub struct Placed {
    /// The queries placed at a start: their positions, bounds of their clearance
    /// before the start, texels read before it, and where their spans end.
    which: alloc::vec::Vec<Pending>,
    /// Those queries over their spans.
    from: alloc::vec::Vec<Query<f32>>,
    /// The queries placed at their next spans, and those spans, for the next pass.
    which_next: alloc::vec::Vec<Pending>,
    from_next: alloc::vec::Vec<Query<f32>>,
    /// Their walks.
    walked: alloc::vec::Vec<dda::Walked>,
    /// The walks still running: from where they stopped, which they are, and their
    /// answers by this method's march.
    again: alloc::vec::Vec<Query<f32>>,
    restarts: alloc::vec::Vec<usize>,
    went_on: alloc::vec::Vec<Trace<f32>>,
    /// The queries' aims, found ahead of their searches.
    aims: alloc::vec::Vec<crate::horizon::Aimed>,
}

/// The start of the span after the one of `q` that ended at `end` without a hit
/// ([`crate::horizon::Horizon::resume_query`]), and the texels read: `fetches` so far
/// and the resume's. Where the horizon does not place it (it always does for a span it
/// ended), the rest of the query's range from `end`, where the ray passes over the
/// surface.
#[cfg(feature = "alloc")]
fn next_span(
    horizon: &crate::horizon::Horizon,
    q: &Query<f32>,
    end: crate::horizon::End<f32>,
    fetches: u32,
) -> (crate::horizon::Start<f32>, u32) {
    use crate::horizon::{End, Start};
    match horizon.resume_query(q, end) {
        Some((start, probes)) => (start, fetches + probes),
        None => (
            Start::At(end.t, f32::INFINITY, End::whole(q.t_max())),
            fetches,
        ),
    }
}

/// The answer of a walk that stopped at `restart` and went on to `trace`: the fetches
/// of both, the least clearance of both.
#[cfg(feature = "alloc")]
fn joined(restart: &dda::Restart<f32>, mut trace: Trace<f32>) -> Trace<f32> {
    trace.fetches += restart.trace.fetches;
    trace.clearance = trace.clearance.min(restart.trace.clearance);
    trace
}

/// A method ready to march: its map (borrowed), surface and options. Built by the
/// caller from a bake it has checked; [`Marcher::trace`] traces one query.
#[derive(Clone, Copy, Debug)]
// The maxmip view holds its level table (about 460 bytes): a marcher is built once per
// batch, not per ray, and a no_std core has no box to move it into.
#[allow(clippy::large_enum_variant)]
pub enum Marcher<'a> {
    /// The exact traversal on a surface ([`dda::trace`]).
    Exact(Surface),
    /// Linear search then bisection ([`crate::search::linear`], [`Refine::Binary`](crate::search::Refine::Binary)).
    #[cfg(feature = "search")]
    LinearBinary(Surface, crate::search::SearchSteps),
    /// Linear search then a secant step ([`crate::search::linear`],
    /// [`Refine::Secant`](crate::search::Refine::Secant)): the linear steps.
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
    /// The multiresolution walk ([`crate::multires::trace`]): the one-texel distance.
    Multires(Surface, u32),
    /// Never built: holds the lifetime in a build without baked methods.
    #[doc(hidden)]
    Unbuilt(core::convert::Infallible, core::marker::PhantomData<&'a ()>),
}

impl<'a> Marcher<'a> {
    /// The marcher of `kind` over `map`, the texels of the map `desc` describes, baked
    /// for `hf` (`None` for a method without a map), with `o`. The caller has checked
    /// that the map belongs to `hf` (the C API by its descriptor); the views check its
    /// length. `Error::BadDesc` when `desc` is not `kind`'s map, `Error::WrongType` for
    /// texels of the other element type, `Error::NotBuilt` for a method this build
    /// lacks.
    pub fn of(
        kind: MethodKind,
        hf: &HeightField,
        desc: &Desc,
        map: Option<Data<'a>>,
        o: &MarchOptions,
    ) -> Result<Marcher<'a>, Error> {
        let _ = (hf, desc, &map);
        let want = kind.info().map;
        let fits = match want {
            Some(MapKind::Safety) => matches!(desc.map, MapKind::Safety | MapKind::SafetyIsotropic),
            Some(m) => desc.map == m,
            None => true,
        };
        if !fits || want.is_some() != map.is_some() {
            return Err(Error::BadDesc);
        }
        let floats = || match map {
            Some(Data::F32(d)) => Ok(d),
            _ => Err(Error::WrongType),
        };
        #[cfg(feature = "safety")]
        let bytes = || match map {
            Some(Data::U8(d)) => Ok(d),
            _ => Err(Error::WrongType),
        };
        #[cfg(feature = "safety")]
        let surface = crate::safety::MarchSurface::of(o.surface).unwrap_or_default();
        Ok(match kind {
            MethodKind::Exact => Marcher::Exact(o.surface),
            MethodKind::Multires => Marcher::Multires(o.surface, o.steps),
            #[cfg(feature = "search")]
            MethodKind::LinearBinary => {
                let steps = crate::search::SearchSteps {
                    linear: o.steps,
                    binary: o.binary_steps,
                };
                Marcher::LinearBinary(o.surface, steps)
            }
            #[cfg(feature = "search")]
            MethodKind::LinearSecant => Marcher::LinearSecant(o.surface, o.steps),
            #[cfg(feature = "maxmip")]
            MethodKind::MaxMip => {
                let mip = crate::maxmip::MaxMip::new(hf, floats()?)?;
                Marcher::MaxMip(mip, o.surface, crate::maxmip::Options::default())
            }
            #[cfg(feature = "safety")]
            MethodKind::Safety => {
                use crate::safety::{SafetyMap, Variant};
                let variant = match desc.map {
                    MapKind::Safety => Variant::Directional,
                    _ => Variant::Isotropic,
                };
                let map = SafetyMap::with_classes(hf, bytes()?, variant, desc.classes)?;
                Marcher::Safety(map.with_rays(desc.rays), surface)
            }
            #[cfg(feature = "safety")]
            MethodKind::Cc => {
                let map =
                    crate::safety::cc::CcMap::with_classes(hf, bytes()?, desc.cap, desc.classes)?;
                Marcher::Cc(map.with_rays(desc.rays), surface)
            }
            #[cfg(feature = "safety")]
            MethodKind::Radius => {
                use crate::radius::{Options, RadiusMap, Zero};
                let zero = match o.radius_clamp {
                    true => Zero::Clamp,
                    false => Zero::Walk,
                };
                Marcher::Radius(RadiusMap::new(hf, bytes()?)?, Options { zero, surface })
            }
            #[cfg(feature = "cone")]
            MethodKind::Cone => Marcher::Cone(crate::cone::ConeMap::new(hf, floats()?)?, o.steps),
            #[cfg(feature = "qdm")]
            MethodKind::Qdm => Marcher::Qdm(crate::qdm::QdmMap::new(hf, floats()?)?, o.steps),
            #[cfg(feature = "relaxed")]
            MethodKind::Relaxed => {
                let steps = crate::relaxed::Steps {
                    cone: o.steps,
                    binary: o.binary_steps,
                };
                Marcher::Relaxed(floats()?, steps)
            }
            #[allow(unreachable_patterns)]
            k => {
                let _ = floats;
                return Err(Error::NotBuilt(k.info().map.unwrap_or(MapKind::Heights)));
            }
        })
    }

    /// The method it marches.
    pub fn kind(&self) -> MethodKind {
        match self {
            Marcher::Exact(_) => MethodKind::Exact,
            Marcher::Multires(..) => MethodKind::Multires,
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

    /// The rays its map is baked for ([`Rays::ALL`](crate::rayset::Rays::ALL) for a
    /// method without a ray set): callers that can choose how a ray runs (shadow rays,
    /// [`Hit::shadow_query_from_light`](crate::Hit::shadow_query_from_light)) keep it
    /// in the set.
    pub fn rays(&self) -> crate::rayset::Rays {
        match self {
            #[cfg(feature = "safety")]
            Marcher::Safety(map, _) => map.rays(),
            #[cfg(feature = "safety")]
            Marcher::Cc(map, _) => map.rays(),
            _ => crate::rayset::Rays::ALL,
        }
    }

    /// The same marcher of `hf` with the occluders its map's ray set passes over
    /// ([`SafetyMap::with_occluders`](crate::safety::SafetyMap::with_occluders); refused
    /// unless they are the set's). Methods without a ray set take none.
    pub fn with_occluders(
        self,
        hf: &HeightField,
        occluders: &'a [crate::rayset::Occluder],
    ) -> Result<Self, crate::rayset::RaysError> {
        let _ = hf;
        Ok(match self {
            #[cfg(feature = "safety")]
            Marcher::Safety(map, s) => Marcher::Safety(map.with_occluders(hf, occluders)?, s),
            #[cfg(feature = "safety")]
            Marcher::Cc(map, s) => Marcher::Cc(map.with_occluders(hf, occluders)?, s),
            other => {
                crate::rayset::Rays::ALL.check_occluders(occluders)?;
                other
            }
        })
    }

    /// The surface whose [`dda::trace`] this marcher's hits equal bit for bit (the
    /// exact DDA, and the maximum mipmap with exact options): the marches a coherent
    /// batch may replace, after its horizon's start, by [`dda::trace_skipping`].
    /// `None` for the others.
    pub fn dda_surface(&self) -> Option<Surface> {
        match *self {
            Marcher::Exact(surface) => Some(surface),
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(_, surface, ref opts) if opts.is_exact() => Some(surface),
            _ => None,
        }
    }

    /// The horizon that [`Marcher::trace_all_with`] can share among `queries` (those
    /// of them from one eye: [`Horizon::for_batch`](crate::horizon::Horizon::for_batch)),
    /// when this method's hits are the DDA's ([`Marcher::dda_surface`]) and the group
    /// is large enough; `None` otherwise.
    #[cfg(feature = "alloc")]
    pub fn horizon<R: Real>(
        &self,
        hf: &HeightField,
        queries: &[Query<R>],
    ) -> Option<crate::horizon::Horizon> {
        let rays = queries
            .iter()
            .map(|q| (q.origin().map(R::to_f64), q.dir().map(R::to_f64)));
        let max_block = self.horizon_max_block();
        crate::horizon::Horizon::for_batch(hf, self.dda_surface()?, rays, max_block)
    }

    /// The coarsest blocks (in cells) a horizon may have and still beat this method's
    /// own march ([`crate::horizon::block_for`]): 4 for the maximum mipmap, which a
    /// coarser horizon's longer walks lose to (measured: 287 against 192 ns a ray on
    /// the report's 160 × 120 cameras over the 1024² Himalaya DEM, blocks of 8); any
    /// for the DDA, which any horizon beats.
    pub fn horizon_max_block(&self) -> u32 {
        match self {
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(..) => 4,
            _ => u32::MAX,
        }
    }

    /// [`Marcher::trace`] of `q`, a ray the horizon placed `start`: from there to the
    /// query's end when this method's hits are the DDA's (by [`dda::trace_skipping`],
    /// the maximum mipmap taking over long walks; the walk from a start finds the same
    /// hit whether its span ends or not), else (a start this marcher cannot use) from
    /// its `t_min`; a miss when the horizon proved one.
    /// The clearance takes the horizon's bound before the start; `fetches` adds the
    /// horizon's `probes`.
    #[cfg(feature = "alloc")]
    pub fn trace_started(
        &self,
        hf: &HeightField,
        q: &Query<f32>,
        (start, probes): (crate::horizon::Start<f32>, u32),
    ) -> Trace<f32> {
        use crate::horizon::Start;
        let mut trace = match (start, self.dda_surface()) {
            (Start::At(t, before, _), Some(surface)) => {
                let mut trace = self.march_from(hf, surface, &q.starting_at(t));
                trace.clearance = trace.clearance.min(before);
                trace
            }
            (Start::Miss(clearance), Some(_)) => Trace::miss(0, clearance),
            (_, None) => self.trace(hf, q),
        };
        trace.fetches += probes;
        trace
    }

    /// The march of `q` from its start (a horizon's): [`dda::trace_skipping`], which
    /// costs least near a hit; the maximum mipmap hands a walk still running after
    /// [`DDA_CELLS`] cells to its own march, which crosses empty space by whole nodes
    /// (from the entry of a cell the ray passes above: the same hit).
    #[cfg(feature = "alloc")]
    fn march_from(&self, hf: &HeightField, surface: Surface, q: &Query<f32>) -> Trace<f32> {
        let walked = dda::trace_skipping_for(hf, surface, q, self.walk_budget());
        self.went_on(hf, q, walked)
    }

    /// The cells [`Marcher::march_from`] walks before this method takes over.
    #[cfg(feature = "alloc")]
    fn walk_budget(&self) -> u32 {
        match self {
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(..) => DDA_CELLS,
            _ => u32::MAX,
        }
    }

    /// The answer of `q` from its walk's ([`dda::trace_skipping_for`] for
    /// [`Marcher::walk_budget`] cells): a walk still running goes on by this method's
    /// march (only the maximum mipmap's walks stop early).
    #[cfg(feature = "alloc")]
    fn went_on(&self, hf: &HeightField, q: &Query<f32>, walked: dda::Walked) -> Trace<f32> {
        match walked {
            Ok(trace) => trace,
            Err(restart) => joined(&restart, self.trace(hf, &q.starting_at(restart.t))),
        }
    }

    /// [`Marcher::trace_started`] of the queries `queries` that `horizon` places
    /// (`hint`: the band of the last query asked), the others by [`Marcher::trace`],
    /// into `out` (same lengths; each answer as an `O`, e.g. a C API's hit written
    /// where the caller wants it): the walks from the starts in SIMD lanes with `simd`
    /// ([`dda::trace_skipping_lanes`]), the answers the same bit for bit. `scratch`
    /// keeps its buffers from call to call.
    #[cfg(feature = "alloc")]
    pub fn trace_placed<O: From<Trace<f32>>>(
        &self,
        hf: &HeightField,
        horizon: &crate::horizon::Horizon,
        (queries, hint): (&[Query<f32>], &mut usize),
        out: &mut [O],
        simd: Option<crate::simd::Avx2>,
        scratch: &mut Placed,
    ) {
        use crate::horizon::Start;
        assert_eq!(queries.len(), out.len(), "one answer per query");
        let Some(surface) = self.dda_surface() else {
            for (o, q) in out.iter_mut().zip(queries) {
                *o = self.trace(hf, q).into();
            }
            return;
        };
        let Placed {
            which,
            from,
            which_next,
            from_next,
            walked,
            again,
            restarts,
            went_on,
            aims,
        } = scratch;
        which.clear();
        from.clear();
        horizon.aims(queries, aims, simd.and_then(crate::simd::Avx2::avx512));
        let placed = (queries, aims.as_slice(), hint);
        if horizon.ends_at_start() {
            self.place::<_, true>(hf, horizon, placed, out, (which, from));
        } else {
            self.place::<_, false>(hf, horizon, placed, out, (which, from));
        }
        // Pass after pass: the spans walked together for a few cells; then the walks
        // still running cut where the horizon lets them stop (and go on together to
        // there), or go on by this method's march; and the next spans of the rays
        // that passed over theirs.
        while !from.is_empty() {
            walked.clear();
            walked.resize(from.len(), Ok(Trace::MISS));
            let avx512 = simd.and_then(crate::simd::Avx2::avx512);
            dda::trace_skipping_lanes(hf, surface, from, self.span_budget(), walked, avx512);
            which_next.clear();
            from_next.clear();
            again.clear();
            restarts.clear();
            // The DDA's walks are cut into spans; the maximum mipmap's own march goes
            // on faster than spans would (measured on the needles).
            let cuts = self.walk_budget() == u32::MAX;
            for (i, (&(k, before, probes, _), w)) in which.iter().zip(walked.iter()).enumerate() {
                let Err(restart) = w else { continue };
                let q = &queries[k];
                let cut = cuts.then(|| horizon.cut_query(q, restart.t)).flatten();
                match cut {
                    Some((end, cut)) if end.goes_on() => {
                        let clearance = before.min(restart.trace.clearance);
                        let fetches = probes + restart.trace.fetches + cut;
                        which_next.push((k, clearance, fetches, end));
                        from_next.push(q.within(restart.t, end.t));
                    }
                    _ => {
                        again.push(from[i].starting_at(restart.t));
                        restarts.push(i);
                    }
                }
            }
            went_on.clear();
            went_on.resize(again.len(), Trace::MISS);
            self.go_on(hf, surface, again, went_on, simd);
            for (&i, trace) in restarts.iter().zip(went_on.iter()) {
                if let Err(restart) = walked[i] {
                    walked[i] = Ok(joined(&restart, *trace));
                }
            }
            for (&(k, before, probes, end), w) in which.iter().zip(walked.iter()) {
                // (A walk still stopped was cut: its next span is queued.)
                let Ok(mut trace) = *w else { continue };
                trace.clearance = trace.clearance.min(before);
                trace.fetches += probes;
                if trace.hit.is_none() && end.goes_on() {
                    let q = &queries[k];
                    match next_span(horizon, q, end, trace.fetches) {
                        (Start::At(t, before, end), fetches) => {
                            let before = before.min(trace.clearance);
                            which_next.push((k, before, fetches, end));
                            from_next.push(q.within(t, end.t));
                            continue;
                        }
                        (Start::Miss(c), fetches) => {
                            trace = Trace::miss(fetches, trace.clearance.min(c));
                        }
                    }
                }
                out[k] = trace.into();
            }
            core::mem::swap(which, which_next);
            core::mem::swap(from, from_next);
        }
    }

    /// The first pass of [`Marcher::trace_placed`]: the answers of the queries the
    /// horizon does not place at a start into `out`, the others (their numbers,
    /// clearance before the start, texels read, span's end) into `which` and their
    /// spans into `from`; with `ENDS`, each span's end looked for at once
    /// ([`crate::horizon::Horizon::start_aimed_query_ending`]).
    #[cfg(feature = "alloc")]
    #[inline(always)]
    fn place<O: From<Trace<f32>>, const ENDS: bool>(
        &self,
        hf: &HeightField,
        horizon: &crate::horizon::Horizon,
        (queries, aims, hint): (&[Query<f32>], &[crate::horizon::Aimed], &mut usize),
        out: &mut [O],
        (which, from): (
            &mut alloc::vec::Vec<Pending>,
            &mut alloc::vec::Vec<Query<f32>>,
        ),
    ) {
        use crate::horizon::Start;
        for (k, ((o, q), &aim)) in out.iter_mut().zip(queries).zip(aims).enumerate() {
            match horizon.start_aimed_query_ending::<_, ENDS>(q, aim, hint) {
                Some((Start::At(t, before, end), probes)) => {
                    which.push((k, before, probes, end));
                    from.push(q.within(t, end.t));
                }
                Some((Start::Miss(clearance), probes)) => {
                    *o = Trace::miss(probes, clearance).into()
                }
                None => *o = self.trace(hf, q).into(),
            }
        }
    }

    /// The cells a walk of a span takes before the horizon may cut it (the few rays
    /// that walk on past a field's first ridge; most hit before): for the maximum
    /// mipmap, the cells before its own march takes over.
    #[cfg(feature = "alloc")]
    fn span_budget(&self) -> u32 {
        match self {
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(..) => DDA_CELLS,
            _ => SPAN_CELLS,
        }
    }

    /// The rest of the walks `again` (each from a cell its ray passes above) into
    /// `out`: by this method's march (the maximum mipmap's, in lanes), or the DDA's
    /// walk in lanes.
    #[cfg(feature = "alloc")]
    fn go_on(
        &self,
        hf: &HeightField,
        surface: Surface,
        again: &[Query<f32>],
        out: &mut [Trace<f32>],
        simd: Option<crate::simd::Avx2>,
    ) {
        if self.walk_budget() != u32::MAX {
            return self.trace_each(hf, again, out, simd);
        }
        let mut walked = alloc::vec![Ok(Trace::MISS); again.len()];
        let avx512 = simd.and_then(crate::simd::Avx2::avx512);
        dda::trace_skipping_lanes(hf, surface, again, u32::MAX, &mut walked, avx512);
        for (o, w) in out.iter_mut().zip(walked) {
            *o = match w {
                Ok(trace) | Err(dda::Restart { trace, .. }) => trace,
            };
        }
    }

    /// [`Marcher::trace_all`] with the horizon of a group of the queries (built once,
    /// e.g. for a whole camera batch that threads then share; see
    /// [`Marcher::horizon`]). A query the horizon knows marches from the horizon's
    /// start ([`Marcher::trace_started`]): its hit (t, point, cell, normal, flags) is
    /// bit for bit the one of [`Marcher::trace`]; `fetches` counts the horizon texels
    /// read and the march's from the start, `clearance` is a lower bound of the
    /// march's. The other queries are traced one by one ([`Marcher::trace`]); without
    /// a horizon, every query goes through [`Marcher::trace_each`].
    #[cfg(feature = "alloc")]
    pub fn trace_all_with(
        &self,
        hf: &HeightField,
        horizon: Option<&crate::horizon::Horizon>,
        queries: &[Query<f32>],
        out: &mut [Trace<f32>],
        simd: Option<crate::simd::Avx2>,
    ) {
        assert_eq!(queries.len(), out.len(), "one answer per query");
        let (Some(horizon), Some(_)) = (horizon, self.dda_surface()) else {
            return self.trace_each(hf, queries, out, simd);
        };
        let placed = (queries, &mut 0);
        self.trace_placed(hf, horizon, placed, out, simd, &mut Placed::default());
    }

    /// [`Marcher::trace`] of every query of `queries` into `out` (same lengths), the
    /// hits bit for bit the same: a large group of queries from one eye (a camera's)
    /// shares a horizon that starts each ray's march near its hit
    /// ([`Marcher::trace_all_with`]); with `simd`, the methods with a laned march
    /// ([`crate::maxmip::trace_lanes`]) march several rays at once; the others, and
    /// every method without `simd`, trace one ray after another.
    pub fn trace_all(
        &self,
        hf: &HeightField,
        queries: &[Query<f32>],
        out: &mut [Trace<f32>],
        simd: Option<crate::simd::Avx2>,
    ) {
        #[cfg(feature = "alloc")]
        if let Some(horizon) = self.horizon(hf, queries) {
            return self.trace_all_with(hf, Some(&horizon), queries, out, simd);
        }
        self.trace_each(hf, queries, out, simd)
    }

    /// [`Marcher::trace_all`] without a horizon: in SIMD lanes where the method has
    /// them (with `simd`), else one ray after another.
    pub fn trace_each(
        &self,
        hf: &HeightField,
        queries: &[Query<f32>],
        out: &mut [Trace<f32>],
        simd: Option<crate::simd::Avx2>,
    ) {
        assert_eq!(queries.len(), out.len(), "one answer per query");
        match *self {
            #[cfg(feature = "maxmip")]
            Marcher::MaxMip(ref mip, surface, ref opts) => {
                crate::maxmip::trace_lanes(hf, mip, surface, queries, opts, out, simd)
            }
            _ => {
                let _ = simd;
                for (o, q) in out.iter_mut().zip(queries) {
                    *o = self.trace(hf, q);
                }
            }
        }
    }

    /// Traces `q` on `hf`, the field the map was baked for.
    pub fn trace<R: Real>(&self, hf: &HeightField, q: &Query<R>) -> Trace<R> {
        match *self {
            Marcher::Exact(surface) => dda::trace(hf, surface, q),
            Marcher::Multires(surface, range) => crate::multires::trace(hf, surface, q, range),
            #[cfg(feature = "search")]
            Marcher::LinearBinary(surface, steps) => crate::search::linear(
                hf,
                surface,
                q,
                steps.linear,
                crate::search::Refine::Binary(steps.binary),
            ),
            #[cfg(feature = "search")]
            Marcher::LinearSecant(surface, n) => {
                crate::search::linear(hf, surface, q, n, crate::search::Refine::Secant)
            }
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
