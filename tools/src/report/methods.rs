//! The method settings of the report sweep: for each, how it bakes and how it traces.
//!
//! Adding a method is one entry in [`settings`]: a [`Setting`] whose `bake` returns a
//! [`Caster`] that traces a batch of rays. Everything else (judging, timing, tables,
//! plots, the summary) reads the list.

use hfcast::bake::{Spec, Texels};
use hfcast::ktx2::{Desc, MapKind};
use hfcast::march::MarchOptions;
use hfcast::maxmip::{self, Ascent};
use hfcast::rayset::{Occluder, Rays};
use hfcast::scene::MethodKind;
use hfcast::search::SearchSteps;
use hfcast::{dda, HeightField, Marcher, Method, Query, Real, Surface, Trace};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// What the report keeps of one traced ray.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Out {
    /// Hit point in grid space (`f64`), or `None` for a miss.
    pub hit: Option<[f64; 3]>,
    /// Texture fetches (for parry3d: an estimate, see [`Family::Parry`]).
    pub fetches: u32,
    /// Hit flags and trace flags together (bits of [`hfcast::Flags`]).
    pub flags: u32,
}

impl Out {
    /// From a trace of any precision.
    #[inline]
    pub fn of<R: Real>(t: &Trace<R>) -> Out {
        Out {
            hit: t.hit.map(|h| R::xyz(h.point).map(R::to_f64)),
            fetches: t.fetches,
            flags: t.flags.0 | t.hit.map_or(0, |h| h.flags.0),
        }
    }
}

/// Traces batches of rays with baked data it owns (or borrows from the field).
pub trait Caster: Sync {
    /// Traces `rays[k]` into `out[k]` (same lengths), single-threaded.
    fn trace_all(&self, rays: &[Query<f32>], out: &mut [Out]);
    /// Bytes of baked data.
    fn baked_bytes(&self) -> usize;
    /// Fills in `out[k].fetches` after an untimed [`Caster::trace_all`] when the method
    /// cannot count them itself (an estimate; nothing by default).
    fn fill_fetches(&self, _rays: &[Query<f32>], _out: &mut [Out]) {}
    /// Seconds of the bake this caster's data came from, when it shares a bake with
    /// other settings ([`SharedBake`]) and so its own bake call only fetched it.
    fn bake_seconds(&self) -> Option<f64> {
        None
    }
}

/// The last bake of a family whose settings differ only in how they trace (iteration
/// caps): the first setting on a field bakes, the others reuse it. Keyed by the field's
/// size and samples; holds one map at a time.
#[derive(Default)]
pub struct SharedBake {
    slot: Mutex<Option<Baked>>,
}

/// A shared bake: field key, map, seconds.
type Baked = (u64, Arc<Texels>, f64);

/// FNV-1a of the field's size and sample bits.
fn field_key(hf: &HeightField) -> u64 {
    let mut k = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |v: u32| {
        k ^= u64::from(v);
        k = k.wrapping_mul(0x100_0000_01b3);
    };
    eat(hf.width());
    eat(hf.height());
    for j in 0..hf.height() {
        for i in 0..hf.width() {
            eat(hf.at(i, j).to_bits());
        }
    }
    k
}

impl SharedBake {
    /// The map of `hf` (baking it with `bake` unless the last call was for the same
    /// field) and the seconds its bake took.
    pub fn get(
        &self,
        hf: &HeightField,
        bake: impl Fn(&HeightField) -> Texels,
    ) -> (Arc<Texels>, f64) {
        let key = field_key(hf);
        let mut slot = self.slot.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((k, data, s)) = slot.as_ref() {
            if *k == key {
                return (Arc::clone(data), *s);
            }
        }
        *slot = None;
        let start = Instant::now();
        let data = Arc::new(bake(hf));
        let s = start.elapsed().as_secs_f64();
        *slot = Some((key, Arc::clone(&data), s));
        (data, s)
    }
}

/// A [`Caster`] from a batch function and its baked byte count.
pub struct Batch<F>(pub F, pub usize);

impl<F: Fn(&[Query<f32>], &mut [Out]) + Sync> Caster for Batch<F> {
    fn trace_all(&self, rays: &[Query<f32>], out: &mut [Out]) {
        (self.0)(rays, out)
    }
    fn baked_bytes(&self) -> usize {
        self.1
    }
}

/// A [`Caster`] through the core's one march interface: the field, the method, its
/// baked map (owned, or shared with other settings), the march options, the maximum
/// mipmap's options, and the seconds of a shared bake.
pub struct Marched<'a> {
    hf: HeightField<'a>,
    kind: MethodKind,
    desc: Desc,
    /// The occluders the map's ray set passes over (none for most settings).
    walls: Vec<Occluder>,
    map: Arc<Texels>,
    opts: MarchOptions,
    maxmip: Option<maxmip::Options>,
    batching: Batching,
    shared_seconds: Option<f64>,
}

/// How a setting hands its rays to the core ([`Marcher::trace_all`] and its parts):
/// the report's scalar, packet and stream settings of a method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Batching {
    /// One ray after another, each from its own start.
    Scalar,
    /// In SIMD lanes where the method has them (the maximum mipmap's), each ray from
    /// its own start ([`Marcher::trace_each`]).
    Lanes,
    /// A camera's rays sharing a horizon that starts each near its hit, where the
    /// method's hits are the DDA's ([`Marcher::trace_all`]), else in lanes.
    Horizon,
}

impl Caster for Marched<'_> {
    fn trace_all(&self, rays: &[Query<f32>], out: &mut [Out]) {
        let data = Some(self.map.data());
        let m = Marcher::of(self.kind, &self.hf, &self.desc, data, &self.opts);
        let m = m
            .expect("baked for hf")
            .with_occluders(&self.hf, &self.walls);
        let m = match (m.expect("the map's occluders"), self.maxmip) {
            (Marcher::MaxMip(mip, surface, _), Some(o)) => Marcher::MaxMip(mip, surface, o),
            (m, _) => m,
        };
        // As the setting batches, so that the report's wrong-ray counts cover the laned
        // and the horizon's marches on every scene.
        let mut traces = vec![Trace::MISS; rays.len()];
        let simd = hfcast::detect_avx2!();
        match self.batching {
            Batching::Scalar => m.trace_each(&self.hf, rays, &mut traces, None),
            Batching::Lanes => m.trace_each(&self.hf, rays, &mut traces, simd),
            Batching::Horizon => m.trace_all(&self.hf, rays, &mut traces, simd),
        }
        for (o, t) in out.iter_mut().zip(&traces) {
            *o = Out::of(t);
        }
    }
    fn baked_bytes(&self) -> usize {
        self.map.bytes()
    }
    fn bake_seconds(&self) -> Option<f64> {
        self.shared_seconds
    }
}

/// How a setting over a baked map bakes and marches: the method, the map's bake (the
/// default `Spec` of the method's map changed by `spec`), the step budgets, the
/// maximum mipmap's options, how it batches its rays, and the bake it shares with
/// other settings (`None`: its own).
struct MapSetting {
    kind: MethodKind,
    spec: fn(&mut Spec),
    steps: [u32; 2],
    maxmip: Option<maxmip::Options>,
    batching: Batching,
    shared: Option<Arc<SharedBake>>,
    /// Bakes the map's ray set over walls around the field
    /// ([`walls_around`](crate::maps::walls_around)).
    walls: bool,
}

impl MapSetting {
    /// The method's default bake and march.
    fn of(kind: MethodKind) -> MapSetting {
        let o = MarchOptions::on(Surface::Triangles);
        MapSetting {
            kind,
            spec: |_| {},
            steps: [o.steps, o.binary_steps],
            maxmip: None,
            batching: Batching::Lanes,
            shared: None,
            walls: false,
        }
    }

    /// The setting's baker.
    fn baker(self) -> Baker {
        baker(move |hf, surface| {
            let map = self.kind.info().map.expect("a method with a map");
            let mut spec = Spec::new(Desc::new(map, hf.width(), hf.height()));
            (self.spec)(&mut spec);
            let walls = match self.walls {
                true => crate::maps::walls_around(hf),
                false => Vec::new(),
            };
            spec.desc.rays = spec.desc.rays.passing_over(&walls).expect("walls");
            let bake =
                |hf: &HeightField| spec.bake_owned_over(hf, &walls).expect("sized by the spec");
            let (map, shared_seconds) = match &self.shared {
                Some(shared) => {
                    let (m, s) = shared.get(hf, bake);
                    (m, Some(s))
                }
                None => (Arc::new(bake(hf)), None),
            };
            let opts = MarchOptions {
                steps: self.steps[0],
                binary_steps: self.steps[1],
                ..MarchOptions::on(surface)
            };
            Box::new(Marched {
                hf: *hf,
                kind: self.kind,
                desc: spec.desc,
                walls,
                map,
                opts,
                maxmip: self.maxmip,
                batching: self.batching,
                shared_seconds,
            })
        })
    }
}

/// Runs `f` on every ray: the inner loop every caster shares.
#[inline(always)]
pub fn each(rays: &[Query<f32>], out: &mut [Out], f: impl Fn(&Query<f32>) -> Out) {
    for (o, q) in out.iter_mut().zip(rays) {
        *o = f(q);
    }
}

/// Method families: colours and legend entries of the plots, groups of the tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// Exact grid traversal, `f32` and `f64`.
    Dda,
    /// Maximum mipmaps, exact settings.
    MaxMip,
    /// Maximum mipmaps with level of detail or iterative bilinear: approximate.
    MaxMipApprox,
    /// Safety distances, exact settings.
    Safety,
    /// Safety distances, approximate settings (strictly positive distances).
    SafetyApprox,
    /// Cylinder–cone safety shapes (exact and N-buffer slopes: both exact marches).
    Cc,
    /// Safety radius (Baboud & Décoret), exact bake and march.
    Radius,
    /// Cone step mapping, conservative (never passes the first hit) but iterative: a
    /// ray that runs out of its iteration cap returns its current point as a guess.
    Cone,
    /// Quadratic displacement maps: conservative and iterative like [`Family::Cone`].
    Qdm,
    /// Relaxed cone stepping then binary search: approximate.
    Relaxed,
    /// Qu et al.'s bilinear method: the exact traversal's cells, each searched by
    /// sampling then bisection (approximate).
    QuBilinear,
    /// Qu et al.'s multiresolution traversal: coarser grids where a pixel's footprint
    /// is wider than their cells (approximate).
    Multires,
    /// Qu et al.'s hybrid rasterization renderer's two passes on the CPU (every cell
    /// boundary per ray), view-linear surface, exact.
    Hybrid,
    /// Linear then binary search (baseline).
    LinearBinary,
    /// Linear search then a secant step, parallax-occlusion style (baseline).
    Secant,
    /// parry3d's `HeightField` ray cast (peer library, `f32`). Its fetches are an
    /// estimate: 4 per cell it visits (its loop reads the cell's four heights), the
    /// cells from the box entry to its hit or the box exit.
    Parry,
}

impl Family {
    /// Legend name and RGB colour of the family's points.
    fn style(self) -> (&'static str, (u8, u8, u8)) {
        match self {
            Family::Dda => ("exact DDA", (0, 0, 0)),
            Family::MaxMip => ("max mipmap", (31, 119, 180)),
            Family::MaxMipApprox => ("max mipmap, approx.", (140, 190, 230)),
            Family::Safety => ("safety distance", (44, 160, 44)),
            Family::SafetyApprox => ("safety dist., approx.", (150, 215, 140)),
            Family::Cc => ("cylinder–cone", (23, 190, 207)),
            Family::Radius => ("safety radius", (127, 127, 127)),
            Family::Cone => ("cone step", (140, 86, 75)),
            Family::Qdm => ("QDM", (227, 119, 194)),
            Family::Relaxed => ("relaxed cone, approx.", (188, 189, 34)),
            Family::QuBilinear => ("Qu bilinear search, approx.", (255, 187, 120)),
            Family::Multires => ("multires, approx.", (196, 156, 148)),
            Family::Hybrid => ("Qu hybrid passes (CPU)", (247, 182, 210)),
            Family::LinearBinary => ("linear + binary", (214, 39, 40)),
            Family::Secant => ("linear + secant", (255, 127, 14)),
            Family::Parry => ("parry3d (peer)", (148, 103, 189)),
        }
    }

    /// Legend name.
    pub fn name(self) -> &'static str {
        self.style().0
    }

    /// `true` for the bake-free approximate baselines and peers the summary compares
    /// the fastest exact method against.
    pub fn is_baseline(self) -> bool {
        matches!(self, Family::LinearBinary | Family::Secant | Family::Parry)
    }

    /// RGB colour of the family's points.
    pub fn colour(self) -> (u8, u8, u8) {
        self.style().1
    }
}

/// The baked form of a setting for one field.
pub type Baker = Box<dyn for<'a> Fn(&HeightField<'a>, Surface) -> Box<dyn Caster + 'a> + Sync>;

/// One point of the sweep.
pub struct Setting {
    /// Family (colour, group).
    pub family: Family,
    /// Name in tables and plots.
    pub label: String,
    /// Claims exactness: every wrong ray is a bug (ambiguous ones aside).
    pub exact: bool,
    /// Traces in `f64` (its wrong-ray tolerance is 1e-3 flat).
    pub f64: bool,
    /// Surfaces the setting traces (others skip it).
    pub surfaces: &'static [Surface],
    /// Bakes (possibly nothing) and returns the caster.
    pub bake: Baker,
    /// Largest field (samples) the setting is measured on: its bake is too slow for
    /// bigger ones (`None`: every size).
    pub max_texels: Option<usize>,
}

impl Setting {
    /// `false` when a `width × height` field is over [`Setting::max_texels`].
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.max_texels
            .is_none_or(|m| width as usize * height as usize <= m)
    }
}

/// Every surface the core traces.
const ALL_SURFACES: &[Surface] = &Surface::ALL;
/// The triangle surface only.
const TRIANGLES: &[Surface] = &[Surface::Triangles];
/// The bilinear surface only.
const BILINEAR: &[Surface] = &[Surface::Bilinear];
/// The view-linear surface only.
const VIEW_LINEAR: &[Surface] = &[Surface::ViewLinear];

/// Boxes a bake function (pins down its higher-ranked signature).
pub fn baker<F>(f: F) -> Baker
where
    F: for<'a> Fn(&HeightField<'a>, Surface) -> Box<dyn Caster + 'a> + Sync + 'static,
{
    Box::new(f)
}

fn setting(
    family: Family,
    label: impl Into<String>,
    exact: bool,
    surfaces: &'static [Surface],
    bake: Baker,
) -> Setting {
    Setting {
        family,
        label: label.into(),
        exact,
        f64: false,
        surfaces,
        bake,
        max_texels: None,
    }
}

/// Parameters of the sweep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// Linear step counts of the search baselines.
    pub linear: Vec<u32>,
    /// Bisection counts of linear + binary.
    pub binary: Vec<u32>,
    /// Level-of-detail pixel factors of the maximum mipmap (times the pixel angle).
    pub lod_pixels: Vec<f32>,
    /// Radians per pixel of the report's cameras.
    pub pixel_angle: f32,
    /// `(linear, bisect)` settings of the maximum mipmap's iterative bilinear test.
    pub iterative: Vec<(u32, u32)>,
    /// Iteration caps of cone step mapping and QDM.
    pub cone_caps: Vec<u32>,
    /// `(cone, binary)` steps of relaxed cone stepping.
    pub relaxed: Vec<(u32, u32)>,
    /// Largest field (samples) cone step mapping and QDM bake on.
    pub cone_max_texels: usize,
    /// Largest field (samples) relaxed cone stepping bakes on (the book's Θ(N⁴)
    /// preprocess, pruned: about a second at 300,000 samples).
    pub relaxed_max_texels: usize,
    /// Largest field (samples) the cylinder–cone shapes bake on (the exact slope takes
    /// about 7 s at 1024², one thread: every 1024² map, not the 4096 × 2048 one).
    pub cc_max_texels: usize,
    /// Largest field (samples) the ray-set settings (exterior, φmax) of the safety
    /// distances and cylinder–cone shapes bake on: one thread takes 23–110 s per map at
    /// 1024² (`docs/report/table1.md` has them there, on 2 cores).
    pub rayset_max_texels: usize,
    /// Largest field (samples) the occluder settings bake on: cutting the candidate
    /// lines by every wall makes their bakes about 7× the exterior ones'.
    pub occluder_max_texels: usize,
}

impl Sweep {
    /// The full sweep.
    pub fn full(pixel_angle: f32) -> Sweep {
        Sweep {
            linear: vec![8, 16, 32, 64, 128, 256],
            binary: vec![4, 8, 16],
            lod_pixels: vec![1.0, 4.0],
            pixel_angle,
            iterative: vec![(2, 4), (4, 8), (8, 16)],
            cone_caps: vec![16, 64, 256],
            relaxed: vec![(32, 8), (64, 8)],
            cone_max_texels: 300_000,
            relaxed_max_texels: 300_000,
            cc_max_texels: 1_100_000,
            rayset_max_texels: 300_000,
            occluder_max_texels: 100_000,
        }
    }

    /// The `--quick` sweep.
    pub fn quick(pixel_angle: f32) -> Sweep {
        Sweep {
            linear: vec![8, 32, 128],
            binary: vec![4, 8],
            lod_pixels: vec![1.0, 4.0],
            pixel_angle,
            iterative: vec![(2, 4), (8, 16)],
            cone_caps: vec![64],
            relaxed: vec![(32, 8)],
            cone_max_texels: 5_000,
            relaxed_max_texels: 5_000,
            cc_max_texels: 5_000,
            // Every `--quick` scene (128² crops and fields).
            rayset_max_texels: 20_000,
            // None of the `--quick` scenes: minutes of CI; the tests cover them.
            occluder_max_texels: 5_000,
        }
    }
}

/// A bake-free march `f`, ray after ray: `f(field, surface, query)`, in `f32` or `f64`.
fn per_ray<R: Real>(
    f: impl Fn(&HeightField, Surface, &Query<f32>) -> Trace<R> + Copy + Sync + 'static,
) -> Baker {
    baker(move |hf, surface| {
        let hf = *hf;
        Box::new(Batch(
            move |rays: &[Query<f32>], out: &mut [Out]| {
                each(rays, out, |q| Out::of(&f(&hf, surface, q)))
            },
            0,
        ))
    })
}

/// A bake-free setting tracing a whole ray set at once with `f` (into core traces).
fn batched(
    f: impl Fn(&HeightField, Surface, &[Query<f32>], &mut [Trace<f32>]) + Copy + Sync + 'static,
) -> Baker {
    baker(move |hf, surface| {
        let hf = *hf;
        Box::new(Batch(
            move |rays: &[Query<f32>], out: &mut [Out]| {
                let mut traces = vec![Trace::MISS; rays.len()];
                f(&hf, surface, rays, &mut traces);
                for (o, t) in out.iter_mut().zip(&traces) {
                    *o = Out::of(t);
                }
            },
            0,
        ))
    })
}

/// A bake-free [`Method`] of the core.
fn core_method(m: Method) -> Baker {
    per_ray(move |hf, surface, q| m.trace(hf, surface, q))
}

/// The maximum mipmap with `opts`, its rays batched as `batching` says.
fn maxmip_setting(opts: maxmip::Options, batching: Batching) -> Baker {
    MapSetting {
        maxmip: Some(opts),
        batching,
        ..MapSetting::of(MethodKind::MaxMip)
    }
    .baker()
}

/// Rays within 45° of the downward vertical (the paper's φmax = −45°).
const PHI45: Rays = Rays {
    max_view_angle_deg: 45.0,
    ..Rays::ALL
};

/// Exterior rays within 45° of the downward vertical.
const EXTERIOR_PHI45: Rays = Rays {
    max_view_angle_deg: 45.0,
    ..Rays::EXTERIOR
};

/// A setting of the cone family (`kind`) with step budgets `steps`, sharing `shared`.
fn cone_family(kind: MethodKind, shared: &Arc<SharedBake>, steps: [u32; 2]) -> Baker {
    MapSetting {
        steps,
        shared: Some(Arc::clone(shared)),
        ..MapSetting::of(kind)
    }
    .baker()
}

/// Every setting of `sweep`, in table order.
pub fn settings(sweep: &Sweep) -> Vec<Setting> {
    let mut v = vec![
        setting(
            Family::Dda,
            "dda f32",
            true,
            ALL_SURFACES,
            core_method(Method::Exact),
        ),
        setting(
            Family::Dda,
            "dda f32 horizon",
            true,
            ALL_SURFACES,
            batched(|hf, surface, rays, traces| {
                Marcher::Exact(surface).trace_all(hf, rays, traces, None)
            }),
        ),
        Setting {
            f64: true,
            ..setting(
                Family::Dda,
                "dda f64 (the oracle)",
                true,
                ALL_SURFACES,
                per_ray(|hf, surface, q| dda::trace(hf, surface, &q.cast::<f64>())),
            )
        },
    ];
    // One-level ascent in SIMD lanes (AVX-512 or AVX2, where the CPU has them), one ray after another
    // and sharing a camera's horizon; the highest ascent is not laned.
    for (ascent, name, batching) in [
        (Ascent::OneLevel, "one-level", Batching::Lanes),
        (Ascent::OneLevel, "one-level scalar", Batching::Scalar),
        (Ascent::OneLevel, "one-level horizon", Batching::Horizon),
        (Ascent::Highest, "highest", Batching::Lanes),
    ] {
        let opts = maxmip::Options {
            ascent,
            ..Default::default()
        };
        v.push(setting(
            Family::MaxMip,
            format!("maxmip {name}"),
            true,
            ALL_SURFACES,
            maxmip_setting(opts, batching),
        ));
    }
    for &px in &sweep.lod_pixels {
        let opts = maxmip::Options {
            lod: Some(px * sweep.pixel_angle),
            ..Default::default()
        };
        v.push(setting(
            Family::MaxMipApprox,
            format!("maxmip lod {px}px"),
            false,
            ALL_SURFACES,
            maxmip_setting(opts, Batching::Lanes),
        ));
    }
    v.push(setting(
        Family::Hybrid,
        "qu hybrid passes",
        true,
        VIEW_LINEAR,
        per_ray(|hf, _, q| hfcast::hybrid::trace(hf, q)),
    ));
    // The multiresolution walk at the same footprints as the maximum mipmap's level of
    // detail: coarse levels where a cell is narrower than `px` pixels.
    for &px in &sweep.lod_pixels {
        let range = (1.0 / (px * sweep.pixel_angle)).round().max(1.0) as u32;
        v.push(setting(
            Family::Multires,
            format!("multires {px}px"),
            false,
            ALL_SURFACES,
            core_method(Method::Multires(range)),
        ));
    }
    for &(linear, bisect) in &sweep.iterative {
        let opts = maxmip::Options {
            iterative_bilinear: Some((linear, bisect)),
            ..Default::default()
        };
        v.push(setting(
            Family::MaxMipApprox,
            format!("maxmip iter {linear}:{bisect}"),
            false,
            BILINEAR,
            maxmip_setting(opts, Batching::Lanes),
        ));
        v.push(setting(
            Family::QuBilinear,
            format!("qu bilinear {linear}:{bisect}"),
            false,
            BILINEAR,
            per_ray(move |hf, _, q| dda::trace_bilinear_search(hf, q, (linear, bisect))),
        ));
    }
    let safety: [(_, _, fn(&mut Spec)); 7] = [
        (Family::Safety, "safety 4 classes", |_| {}),
        (Family::Safety, "safety isotropic", |s| {
            s.desc.map = MapKind::SafetyIsotropic
        }),
        // Narrower ray sets: the scene's rays outside them walk cell by cell.
        (Family::Safety, "safety exterior", |s| {
            s.desc.rays = Rays::EXTERIOR
        }),
        (Family::Safety, "safety phi45", |s| s.desc.rays = PHI45),
        (Family::Safety, "safety exterior phi45", |s| {
            s.desc.rays = EXTERIOR_PHI45
        }),
        // The exterior set over walls around the field: rays whose line dips under
        // a wall walk cell by cell too.
        (Family::Safety, "safety exterior occluder", |s| {
            s.desc.rays = Rays::EXTERIOR
        }),
        (Family::SafetyApprox, "safety 4 classes, positive", |s| {
            s.positive = true
        }),
    ];
    // A ray-set setting's bake: [`Sweep::rayset_max_texels`]; an occluder one's
    // [`Sweep::occluder_max_texels`].
    let rays_limit = |name: &str| match name {
        n if n.contains("occluder") => Some(sweep.occluder_max_texels),
        n if n.contains("exterior") || n.contains("phi") => Some(sweep.rayset_max_texels),
        _ => None,
    };
    for (family, name, spec) in safety {
        let bake = MapSetting {
            spec,
            walls: name.contains("occluder"),
            ..MapSetting::of(MethodKind::Safety)
        };
        let exact = family == Family::Safety;
        v.push(Setting {
            max_texels: rays_limit(name),
            ..setting(family, name, exact, TRIANGLES, bake.baker())
        });
    }
    let cc: [(_, fn(&mut Spec)); 5] = [
        ("cc exact slope", |_| {}),
        ("cc N-buffer slope", |s| s.nbuffer_slope = true),
        ("cc exterior", |s| s.desc.rays = Rays::EXTERIOR),
        ("cc exterior phi45", |s| s.desc.rays = EXTERIOR_PHI45),
        ("cc exterior occluder", |s| s.desc.rays = Rays::EXTERIOR),
    ];
    for (name, spec) in cc {
        let bake = MapSetting {
            spec,
            walls: name.contains("occluder"),
            ..MapSetting::of(MethodKind::Cc)
        };
        let limit = rays_limit(name).map_or(sweep.cc_max_texels, |r| r.min(sweep.cc_max_texels));
        v.push(Setting {
            max_texels: Some(limit),
            ..setting(Family::Cc, name, true, TRIANGLES, bake.baker())
        });
    }
    let radius = MapSetting::of(MethodKind::Radius).baker();
    v.push(setting(
        Family::Radius,
        "safety radius",
        true,
        TRIANGLES,
        radius,
    ));
    let (cone_bake, qdm_bake) = (Arc::<SharedBake>::default(), Arc::<SharedBake>::default());
    for (family, name) in [(Family::Cone, "cone"), (Family::Qdm, "qdm")] {
        for &cap in &sweep.cone_caps {
            let bake = match family {
                Family::Cone => cone_family(MethodKind::Cone, &cone_bake, [cap, 0]),
                _ => cone_family(MethodKind::Qdm, &qdm_bake, [cap, 0]),
            };
            v.push(Setting {
                max_texels: Some(sweep.cone_max_texels),
                ..setting(family, format!("{name} cap {cap}"), false, TRIANGLES, bake)
            });
        }
    }
    let relaxed_bake = Arc::<SharedBake>::default();
    for &(cone, binary) in &sweep.relaxed {
        v.push(Setting {
            max_texels: Some(sweep.relaxed_max_texels),
            ..setting(
                Family::Relaxed,
                format!("relaxed {cone}:{binary}"),
                false,
                TRIANGLES,
                cone_family(MethodKind::Relaxed, &relaxed_bake, [cone, binary]),
            )
        });
    }
    for &linear in &sweep.linear {
        for &binary in &sweep.binary {
            let m = Method::LinearBinary(SearchSteps { linear, binary });
            v.push(setting(
                Family::LinearBinary,
                format!("linear-binary {linear}:{binary}"),
                false,
                ALL_SURFACES,
                core_method(m),
            ));
        }
    }
    for &linear in &sweep.linear {
        v.push(setting(
            Family::Secant,
            format!("secant {linear}"),
            false,
            ALL_SURFACES,
            core_method(Method::LinearSecant(linear)),
        ));
    }
    for (matched, name) in [(true, "split as ours"), (false, "fixed split")] {
        v.push(setting(
            Family::Parry,
            format!("parry3d, {name}"),
            false,
            TRIANGLES,
            baker(move |hf, _| Box::new(super::parry::ParryCaster::new(hf, matched))),
        ));
    }
    v
}
