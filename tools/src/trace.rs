//! Tracing with any method of the command line ([`Tracer`]: the method's bake, once
//! per field, then one ray at a time), and the text format of `hfcast trace`: one ray
//! per line in, one answer per line out.
//!
//! In: `ox oy oz dx dy dz [t_min t_max]` (whitespace separated, grid space; `t_min`
//! defaults to 0, `t_max` to `inf`); `#` starts a comment. Out:
//! `hit t x y z cell_i cell_j nx ny nz fetches flags` (flags as the bit value of
//! [`hfcast::Flags`]), `miss fetches`, or `error <message>`.

use crate::MethodSpec;
use hfcast::maxmip::{self, MaxMip};
use hfcast::safety::cc::{self, CcMap, CcOptions};
use hfcast::safety::{self, MarchSurface, SafetyMap, Variant};
use hfcast::scene::{BakePlan, RayClasses, Scene};
use hfcast::{cone, qdm, radius, relaxed, HeightField, Marcher, Method, Query, Surface, Trace};
use std::time::{Duration, Instant};

/// What a bake produced.
enum Baked {
    /// Nothing (the bake-free methods).
    Nothing,
    /// A map of floats (pyramid, cone, relaxed and QDM maps).
    Floats(Vec<f32>),
    /// A map of bytes (safety, cylinder–cone and radius maps).
    Bytes(Vec<u8>),
}

/// A method baked for one field and surface: traces one ray at a time.
pub struct Tracer<'a> {
    hf: HeightField<'a>,
    method: MethodSpec,
    surface: Surface,
    plan: BakePlan,
    data: Baked,
    bake_time: Duration,
}

/// A core bake of a float map: `(field, scratch, out)`.
type FloatBake = fn(&HeightField, &mut [f32], &mut [f32]) -> Result<(), cone::BakeError>;

/// A bake error as text.
fn bake_err(e: impl std::fmt::Display) -> String {
    format!("bake failed: {e}")
}

impl<'a> Tracer<'a> {
    /// Bakes `method` for `hf` and `surface` (one thread), for rays of the horizontal
    /// classes `classes` (the safety-shape maps hold only those; rays of other classes
    /// are still exact, cell by cell). What is baked is the core's bake plan of the
    /// scene ([`Scene::bake_plan`], [`Tracer::plan`]). Fails when the method does not
    /// trace `surface` ([`MethodSpec::supports`]).
    pub fn bake(
        hf: HeightField<'a>,
        method: MethodSpec,
        surface: Surface,
        classes: RayClasses,
    ) -> Result<Tracer<'a>, String> {
        if !method.supports(surface) {
            return Err(format!(
                "method {} does not trace the {} surface",
                method.name(),
                surface.name()
            ));
        }
        let scene = Scene {
            ray_classes: classes,
            ..Scene::general(method.kind(), surface)
        };
        let plan = scene.bake_plan();
        let start = Instant::now();
        let data = bake_data(&hf, method, &plan)?;
        Ok(Tracer {
            hf,
            method,
            surface,
            plan,
            data,
            bake_time: start.elapsed(),
        })
    }

    /// The method.
    pub fn method(&self) -> MethodSpec {
        self.method
    }

    /// The core's bake plan this tracer baked by (the one `hf_scene_bake_plan` gives for
    /// the same scene).
    pub fn plan(&self) -> &BakePlan {
        &self.plan
    }

    /// Wall time of the bake.
    pub fn bake_time(&self) -> Duration {
        self.bake_time
    }

    /// Bytes of baked data kept for the march.
    pub fn bytes(&self) -> usize {
        match &self.data {
            Baked::Nothing => 0,
            Baked::Floats(v) => v.len() * 4,
            Baked::Bytes(v) => v.len(),
        }
    }

    /// Traces one ray.
    pub fn trace(&self, q: &Query<f32>) -> Trace<f32> {
        self.with_march(|march| march(q))
    }

    /// Traces `rays[k]` into `out[k]` (same lengths), one thread.
    pub fn trace_all(&self, rays: &[Query<f32>], out: &mut [Trace<f32>]) {
        self.with_march(|march| {
            for (o, q) in out.iter_mut().zip(rays) {
                *o = march(q);
            }
        })
    }

    /// Runs `f` with the method's march over the baked data (the map views built once).
    fn with_march<T>(&self, f: impl FnOnce(&dyn Fn(&Query<f32>) -> Trace<f32>) -> T) -> T {
        let m = self.marcher();
        f(&|q| m.trace(&self.hf, q))
    }

    /// The core's marcher of the method over the baked data.
    fn marcher(&self) -> Marcher<'_> {
        const BAKED: &str = "baked for this field";
        let (hf, surface) = (&self.hf, self.surface);
        let ms = MarchSurface::of(surface).unwrap_or_default();
        let classes = self.plan.classes;
        match (self.method, &self.data) {
            (MethodSpec::Plain(Method::Exact), _) => Marcher::Exact(surface),
            (MethodSpec::Plain(Method::LinearBinary(steps)), _) => {
                Marcher::LinearBinary(surface, steps)
            }
            (MethodSpec::Plain(Method::LinearSecant(n)), _) => Marcher::LinearSecant(surface, n),
            (MethodSpec::MaxMip, Baked::Floats(d)) => {
                let mip = MaxMip::new(hf, d).expect(BAKED);
                Marcher::MaxMip(mip, surface, maxmip::Options::default())
            }
            (MethodSpec::Safety, Baked::Bytes(d)) => {
                let variant = safety_variant(&self.plan);
                let map = SafetyMap::with_classes(hf, d, variant, classes).expect(BAKED);
                Marcher::Safety(map, ms)
            }
            (MethodSpec::Cc, Baked::Bytes(d)) => {
                let cap = CcOptions::default().cap;
                Marcher::Cc(CcMap::with_classes(hf, d, cap, classes).expect(BAKED), ms)
            }
            (MethodSpec::Radius, Baked::Bytes(d)) => {
                let opts = radius::Options {
                    surface: ms,
                    ..Default::default()
                };
                Marcher::Radius(radius::RadiusMap::new(hf, d).expect(BAKED), opts)
            }
            (MethodSpec::Cone(cap), Baked::Floats(d)) => {
                Marcher::Cone(cone::ConeMap::new(hf, d).expect(BAKED), cap)
            }
            (MethodSpec::Qdm(cap), Baked::Floats(d)) => {
                Marcher::Qdm(qdm::QdmMap::new(hf, d).expect(BAKED), cap)
            }
            (MethodSpec::Relaxed(steps), Baked::Floats(d)) => Marcher::Relaxed(d, steps),
            _ => unreachable!("bake_data bakes each method's kind of data"),
        }
    }
}

/// The safety map's layout in `plan`.
fn safety_variant(plan: &BakePlan) -> Variant {
    if plan.isotropic {
        Variant::Isotropic
    } else {
        Variant::Directional
    }
}

/// Bakes what `plan` keeps for `method`, one thread.
fn bake_data(hf: &HeightField, method: MethodSpec, plan: &BakePlan) -> Result<Baked, String> {
    let (w, h) = (hf.width(), hf.height());
    let floats = |scratch: usize, len: usize, bake: FloatBake| {
        let (mut s, mut out) = (vec![0f32; scratch], vec![0f32; len]);
        bake(hf, &mut s, &mut out).map_err(bake_err)?;
        Ok(Baked::Floats(out))
    };
    let safety_scratch = || -> Result<Vec<f32>, String> {
        let mut s = vec![0f32; safety::scratch_len(w, h)];
        safety::prepare(hf, &mut s).map_err(bake_err)?;
        Ok(s)
    };
    match method {
        MethodSpec::Plain(_) => Ok(Baked::Nothing),
        MethodSpec::MaxMip => {
            let mut pyramid = vec![0f32; maxmip::pyramid_len(w, h)];
            maxmip::bake(hf, &mut pyramid).map_err(bake_err)?;
            Ok(Baked::Floats(pyramid))
        }
        MethodSpec::Safety => {
            let scratch = safety_scratch()?;
            let opts = safety::Options {
                variant: safety_variant(plan),
                ..Default::default()
            };
            let mut out = vec![0u8; safety::map_len_classes(w, h, opts.variant, plan.classes)];
            let rays = &safety::AllRays;
            safety::bake_rows_classes(hf, &scratch, rays, plan.classes, 0..h, opts, &mut out)
                .map_err(bake_err)?;
            Ok(Baked::Bytes(out))
        }
        MethodSpec::Cc => {
            let scratch = safety_scratch()?;
            let opts = CcOptions::default();
            let mut nb = vec![0f32; cc::nbuffer_len(w, h, opts.cap)];
            cc::prepare_nbuffer(hf, opts.cap, &mut nb).map_err(bake_err)?;
            let mut out = vec![0u8; cc::map_len_classes(w, h, plan.classes)];
            cc::bake_rows_classes(hf, &scratch, &nb, plan.classes, 0..h, opts, &mut out)
                .map_err(bake_err)?;
            Ok(Baked::Bytes(out))
        }
        MethodSpec::Radius => {
            let mut scratch = vec![0f32; radius::scratch_len(w, h)];
            let mut out = vec![0u8; radius::map_len(w, h)];
            radius::bake(hf, &mut scratch, radius::BakeOptions::default(), &mut out)
                .map_err(bake_err)?;
            Ok(Baked::Bytes(out))
        }
        MethodSpec::Cone(_) => floats(cone::scratch_len(w, h), cone::map_len(w, h), cone::bake),
        MethodSpec::Qdm(_) => floats(qdm::scratch_len(w, h), qdm::map_len(w, h), qdm::bake),
        MethodSpec::Relaxed(_) => floats(
            relaxed::scratch_len(w, h),
            relaxed::map_len(w, h),
            relaxed::bake,
        ),
    }
}

/// Parses one input line; `Ok(None)` for a blank or comment-only line.
pub fn parse_ray(line: &str) -> Result<Option<Query<f32>>, String> {
    let text = line.split('#').next().unwrap_or("");
    let fields: Vec<&str> = text.split_whitespace().collect();
    if fields.is_empty() {
        return Ok(None);
    }
    parse_fields(&fields).map(Some)
}

/// Parses `ox oy oz dx dy dz [t_min t_max]` from separate words.
pub fn parse_fields(fields: &[&str]) -> Result<Query<f32>, String> {
    if fields.len() != 6 && fields.len() != 8 {
        return Err(format!(
            "expected 6 or 8 numbers (ox oy oz dx dy dz [t_min t_max]), got {}",
            fields.len()
        ));
    }
    let mut v = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, f32::INFINITY];
    for (slot, word) in v.iter_mut().zip(fields) {
        *slot = word
            .parse()
            .map_err(|_| format!("not a number: {word:?}"))?;
    }
    Query::from_arrays([v[0], v[1], v[2]], [v[3], v[4], v[5]], v[6], v[7])
        .map_err(|e| e.to_string())
}

/// Formats a trace as one output line (without the newline).
pub fn format_trace(tr: &Trace<f32>) -> String {
    match tr.hit {
        Some(h) => format!(
            "hit {} {} {} {} {} {} {} {} {} {} {}",
            h.t,
            h.point.x,
            h.point.y,
            h.point.z,
            h.cell[0],
            h.cell[1],
            h.normal.x,
            h.normal.y,
            h.normal.z,
            tr.fetches,
            h.flags.0
        ),
        None => format!("miss {}", tr.fetches),
    }
}

/// Answers one input line: `None` for blank and comment lines, else the output line
/// and whether it is an error.
pub fn answer_line(tracer: &Tracer, line: &str) -> Option<(String, bool)> {
    match parse_ray(line) {
        Ok(None) => None,
        Ok(Some(q)) => Some((format_trace(&tracer.trace(&q)), false)),
        Err(e) => Some((format!("error {e}"), true)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines() {
        let h = [0.0f32, 1.0, 1.0, 2.0];
        let hf = HeightField::new(&h, 2, 2, 2).unwrap();
        let exact = MethodSpec::Plain(hfcast::Method::Exact);
        let tracer = Tracer::bake(hf, exact, Surface::Triangles, RayClasses::ALL).unwrap();
        let ask = |l: &str| answer_line(&tracer, l);
        assert_eq!(ask("  # nothing"), None);
        assert_eq!(ask(""), None);
        let (out, err) = ask("0.5 0.5 5 0 0 -1 # down").unwrap();
        assert!(!err && out.starts_with("hit 4 0.5 0.5 1 0 0 "), "{out}");
        assert_eq!(ask("5 5 5 0 0 1").unwrap(), ("miss 0".into(), false));
        assert!(ask("0 0 0 0 0 0").unwrap().1);
        assert!(ask("0 0 0 1 0").unwrap().1);
        assert!(ask("0 0 0 1 0 x").unwrap().1);
        assert!(ask("0 0 0 1 0 0 2 1").unwrap().1);
    }
}
