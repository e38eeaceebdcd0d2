//! The method settings of the report sweep: for each, how it bakes and how it traces.
//!
//! Adding a method is one entry in [`settings`]: a [`Setting`] whose `bake` returns a
//! [`Caster`] that traces a batch of rays. Everything else (judging, timing, tables,
//! plots, the summary) reads the list.

use hfcast::maxmip::{self, Ascent};
use hfcast::safety::{self, SafetyMap, Variant};
use hfcast::search::SearchSteps;
use hfcast::{dda, HeightField, Method, Query, Real, Surface, Trace};

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
        let hf = *hf;
        let mut pyramid = vec![0f32; maxmip::pyramid_len(hf.width(), hf.height())];
        maxmip::bake(&hf, &mut pyramid).expect("sized by pyramid_len");
        let bytes = pyramid.len() * 4;
        Box::new(Batch(
            move |rays: &[Query<f32>], out: &mut [Out]| {
                let mip = maxmip::MaxMip::new(&hf, &pyramid).expect("baked for hf");
                each(rays, out, |q| {
                    Out::of(&maxmip::trace(&hf, &mip, surface, q, &opts))
                })
            },
            bytes,
        ))
    })
}

/// Safety distances with `opts` (triangle surface).
fn safety_setting(opts: safety::Options) -> Baker {
    baker(move |hf, _surface| {
        let hf = *hf;
        let mut scratch = vec![0f32; safety::scratch_len(hf.width(), hf.height())];
        let mut data = vec![0u8; safety::map_len(hf.width(), hf.height(), opts.variant)];
        safety::bake(&hf, &mut scratch, opts, &mut data).expect("sized by the module");
        let bytes = data.len();
        Box::new(Batch(
            move |rays: &[Query<f32>], out: &mut [Out]| {
                let map = SafetyMap::new(&hf, &data, opts.variant).expect("baked for hf");
                each(rays, out, |q| Out::of(&safety::trace(&map, &hf, q)))
            },
            bytes,
        ))
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
