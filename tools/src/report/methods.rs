//! The method settings of the report sweep: for each, how it bakes and how it traces.
//!
//! Adding a method is one entry in [`settings`]: a [`Setting`] whose `bake` returns a
//! [`Caster`] that traces a batch of rays. Everything else (judging, timing, tables,
//! plots, the summary) reads the list.

use hfcast::maxmip::{self, Ascent};
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, MarchSurface, SafetyMap, Variant};
use hfcast::search::SearchSteps;
use hfcast::{
    cone, dda, qdm, radius, relaxed, HeightField, Marcher, Method, Query, Real, Surface, Trace,
};
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
type Baked = (u64, Arc<Vec<f32>>, f64);

/// A core bake function `(field, scratch, out)`.
type BakeFn = fn(&HeightField, &mut [f32], &mut [f32]) -> Result<(), cone::BakeError>;

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
        bake: impl Fn(&HeightField) -> Vec<f32>,
    ) -> (Arc<Vec<f32>>, f64) {
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

/// How a setting views its baked map as the core's [`Marcher`].
type View<T> = Box<dyn for<'m> Fn(&HeightField, &'m [T]) -> Marcher<'m> + Sync>;

/// A [`Caster`] through the core's one march interface: the field, its baked map
/// (owned, or shared with other settings), how to view it, and the seconds of a shared
/// bake.
pub struct Marched<'a, T> {
    hf: HeightField<'a>,
    map: Arc<Vec<T>>,
    view: View<T>,
    shared_seconds: Option<f64>,
}

impl<T: Sync + Send> Caster for Marched<'_, T> {
    fn trace_all(&self, rays: &[Query<f32>], out: &mut [Out]) {
        let m = (self.view)(&self.hf, &self.map);
        each(rays, out, |q| Out::of(&m.trace(&self.hf, q)))
    }
    fn baked_bytes(&self) -> usize {
        self.map.len() * std::mem::size_of::<T>()
    }
    fn bake_seconds(&self) -> Option<f64> {
        self.shared_seconds
    }
}

/// The [`Marched`] caster of `map` on `hf`, viewed by `view`.
fn marched<'a, T: Sync + Send + 'a>(
    hf: &HeightField<'a>,
    map: impl Into<Arc<Vec<T>>>,
    shared_seconds: Option<f64>,
    view: impl for<'m> Fn(&HeightField, &'m [T]) -> Marcher<'m> + Sync + 'static,
) -> Box<dyn Caster + 'a> {
    Box::new(Marched {
        hf: *hf,
        map: map.into(),
        view: Box::new(view),
        shared_seconds,
    })
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
    /// Legend name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Dda => "exact DDA",
            Family::MaxMip => "max mipmap",
            Family::MaxMipApprox => "max mipmap, approx.",
            Family::Safety => "safety distance",
            Family::SafetyApprox => "safety dist., approx.",
            Family::Cc => "cylinder–cone",
            Family::Radius => "safety radius",
            Family::Cone => "cone step",
            Family::Qdm => "QDM",
            Family::Relaxed => "relaxed cone, approx.",
            Family::LinearBinary => "linear + binary",
            Family::Secant => "linear + secant",
            Family::Parry => "parry3d (peer)",
        }
    }

    /// `true` for the bake-free approximate baselines and peers the summary compares
    /// the fastest exact method against.
    pub fn is_baseline(self) -> bool {
        matches!(self, Family::LinearBinary | Family::Secant | Family::Parry)
    }

    /// RGB colour of the family's points.
    pub fn colour(self) -> (u8, u8, u8) {
        match self {
            Family::Dda => (0, 0, 0),
            Family::MaxMip => (31, 119, 180),
            Family::MaxMipApprox => (140, 190, 230),
            Family::Safety => (44, 160, 44),
            Family::SafetyApprox => (150, 215, 140),
            Family::Cc => (23, 190, 207),
            Family::Radius => (127, 127, 127),
            Family::Cone => (140, 86, 75),
            Family::Qdm => (227, 119, 194),
            Family::Relaxed => (188, 189, 34),
            Family::LinearBinary => (214, 39, 40),
            Family::Secant => (255, 127, 14),
            Family::Parry => (148, 103, 189),
        }
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
        }
    }
}

/// A bake-free [`Method`] of the core.
fn core_method(m: Method) -> Baker {
    baker(move |hf, surface| {
        let hf = *hf;
        Box::new(Batch(
            move |rays: &[Query<f32>], out: &mut [Out]| {
                each(rays, out, |q| Out::of(&m.trace(&hf, surface, q)))
            },
            0,
        ))
    })
}

/// The maximum mipmap with `opts`.
fn maxmip_setting(opts: maxmip::Options) -> Baker {
    baker(move |hf, surface| {
        let mut pyramid = vec![0f32; maxmip::pyramid_len(hf.width(), hf.height())];
        maxmip::bake(hf, &mut pyramid).expect("sized by pyramid_len");
        marched(hf, pyramid, None, move |hf, p| {
            let mip = maxmip::MaxMip::new(hf, p).expect("baked for hf");
            Marcher::MaxMip(mip, surface, opts)
        })
    })
}

/// Safety distances with `opts` (triangle surface).
fn safety_setting(opts: safety::Options) -> Baker {
    baker(move |hf, _surface| {
        let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
        let mut data = vec![0u8; safety::map_len(hf.width(), hf.height(), opts.variant)];
        safety::bake(hf, &mut scratch, opts, &mut data).expect("sized by the module");
        marched(hf, data, None, move |hf, d| {
            let map = SafetyMap::new(hf, d, opts.variant).expect("baked for hf");
            Marcher::Safety(map, MarchSurface::Triangles)
        })
    })
}

/// Cylinder–cone safety shapes with `opts` (triangle surface).
fn cc_setting(opts: CcOptions) -> Baker {
    baker(move |hf, _surface| {
        let (w, h) = (hf.width(), hf.height());
        let mut scratch = vec![0f32; safety::scratch_len(w, h)];
        let mut nb = vec![0f32; cc::nbuffer_len(w, h, opts.cap)];
        let mut data = vec![0u8; cc::map_len(w, h)];
        cc::bake(hf, &mut scratch, &mut nb, opts, &mut data).expect("sized by the module");
        marched(hf, data, None, move |hf, d| {
            let map = CcMap::new(hf, d, opts.cap).expect("baked for hf");
            Marcher::Cc(map, MarchSurface::Triangles)
        })
    })
}

/// Exact safety radii (triangle surface, zero radii walked).
fn radius_setting() -> Baker {
    baker(move |hf, _surface| {
        let (w, h) = (hf.width(), hf.height());
        let mut scratch = vec![0f32; radius::scratch_len(w, h)];
        let mut data = vec![0u8; radius::map_len(w, h)];
        radius::bake(hf, &mut scratch, radius::BakeOptions::default(), &mut data)
            .expect("sized by the module");
        marched(hf, data, None, |hf, d| {
            let map = radius::RadiusMap::new(hf, d).expect("baked for hf");
            Marcher::Radius(map, radius::Options::default())
        })
    })
}

/// Bakes `len` floats with `bake` (sized scratch of `scratch` floats), panicking on a
/// size error (the lengths come from the module).
fn bake_map(hf: &HeightField, scratch: usize, len: usize, bake: BakeFn) -> Vec<f32> {
    let mut s = vec![0f32; scratch];
    let mut out = vec![0f32; len];
    bake(hf, &mut s, &mut out).expect("sized by the module");
    out
}

/// A setting of the cone family: its bake (`scratch_len`, `map_len`, `bake`), shared
/// by the family's settings, and how it views the map.
fn cone_family(
    shared: Arc<SharedBake>,
    lens: [fn(u32, u32) -> usize; 2],
    bake: BakeFn,
    view: impl for<'m> Fn(&HeightField, &'m [f32]) -> Marcher<'m> + Sync + Copy + 'static,
) -> Baker {
    baker(move |hf, _surface| {
        let (w, h) = (hf.width(), hf.height());
        let (data, s) = shared.get(hf, |hf| bake_map(hf, lens[0](w, h), lens[1](w, h), bake));
        marched(hf, data, Some(s), view)
    })
}

/// Cone step mapping with at most `cap` iterations (triangle surface).
fn cone_setting(shared: Arc<SharedBake>, cap: u32) -> Baker {
    let lens = [cone::scratch_len, cone::map_len];
    cone_family(shared, lens, cone::bake, move |hf, d| {
        Marcher::Cone(cone::ConeMap::new(hf, d).expect("baked for hf"), cap)
    })
}

/// Quadratic displacement maps with at most `cap` iterations (triangle surface).
fn qdm_setting(shared: Arc<SharedBake>, cap: u32) -> Baker {
    let lens = [qdm::scratch_len, qdm::map_len];
    cone_family(shared, lens, qdm::bake, move |hf, d| {
        Marcher::Qdm(qdm::QdmMap::new(hf, d).expect("baked for hf"), cap)
    })
}

/// Relaxed cone stepping with `steps` (triangle surface).
fn relaxed_setting(shared: Arc<SharedBake>, steps: relaxed::Steps) -> Baker {
    let lens = [relaxed::scratch_len, relaxed::map_len];
    cone_family(shared, lens, relaxed::bake, move |_, d| {
        Marcher::Relaxed(d, steps)
    })
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
        Setting {
            f64: true,
            ..setting(
                Family::Dda,
                "dda f64 (the oracle)",
                true,
                ALL_SURFACES,
                baker(|hf, surface| {
                    let hf = *hf;
                    Box::new(Batch(
                        move |rays: &[Query<f32>], out: &mut [Out]| {
                            each(rays, out, |q| {
                                Out::of(&dda::trace(&hf, surface, &q.cast::<f64>()))
                            })
                        },
                        0,
                    ))
                }),
            )
        },
    ];
    for (ascent, name) in [
        (Ascent::OneLevel, "one-level"),
        (Ascent::Highest, "highest"),
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
            maxmip_setting(opts),
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
            maxmip_setting(opts),
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
            maxmip_setting(opts),
        ));
    }
    for (variant, name) in [
        (Variant::Directional, "4 classes"),
        (Variant::Isotropic, "isotropic"),
    ] {
        let opts = safety::Options {
            variant,
            ..Default::default()
        };
        v.push(setting(
            Family::Safety,
            format!("safety {name}"),
            true,
            TRIANGLES,
            safety_setting(opts),
        ));
    }
    let positive = safety::Options {
        positive: true,
        ..Default::default()
    };
    v.push(setting(
        Family::SafetyApprox,
        "safety 4 classes, positive",
        false,
        TRIANGLES,
        safety_setting(positive),
    ));
    for (slope, name) in [
        (Slope::Exact, "exact slope"),
        (Slope::NBuffer, "N-buffer slope"),
    ] {
        let opts = CcOptions {
            slope,
            ..Default::default()
        };
        v.push(Setting {
            max_texels: Some(sweep.cc_max_texels),
            ..setting(
                Family::Cc,
                format!("cc {name}"),
                true,
                TRIANGLES,
                cc_setting(opts),
            )
        });
    }
    v.push(setting(
        Family::Radius,
        "safety radius",
        true,
        TRIANGLES,
        radius_setting(),
    ));
    let (cone_bake, qdm_bake) = (Arc::<SharedBake>::default(), Arc::<SharedBake>::default());
    for (family, name) in [(Family::Cone, "cone"), (Family::Qdm, "qdm")] {
        for &cap in &sweep.cone_caps {
            let bake = if family == Family::Cone {
                cone_setting(Arc::clone(&cone_bake), cap)
            } else {
                qdm_setting(Arc::clone(&qdm_bake), cap)
            };
            v.push(Setting {
                max_texels: Some(sweep.cone_max_texels),
                ..setting(family, format!("{name} cap {cap}"), false, TRIANGLES, bake)
            });
        }
    }
    let relaxed_bake = Arc::<SharedBake>::default();
    for &(cone, binary) in &sweep.relaxed {
        let steps = relaxed::Steps { cone, binary };
        v.push(Setting {
            max_texels: Some(sweep.relaxed_max_texels),
            ..setting(
                Family::Relaxed,
                format!("relaxed {cone}:{binary}"),
                false,
                TRIANGLES,
                relaxed_setting(Arc::clone(&relaxed_bake), steps),
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
