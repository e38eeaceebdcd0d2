//! `hfcast advise`: which exact method to trace a scene with, measured on the scene's
//! own rays.
//!
//! The rays are those `hfcast render` traces with the same options: every pixel's
//! primary ray (clipped to the slab above the base, [`render::primary_ray`]) and the
//! shadow ray from every hit that faces the light ([`render::shadow_ray`], from the
//! exact traversal's hits). Each exact method ([`MethodSpec::exact`] that traces the
//! surface) is baked once, one thread, for the scene's ray classes (the core's bake
//! plan, [`Tracer::plan`]) and traces the rays one thread, median of a few repetitions.
//!
//! The choice ([`Advice::choice`]): among the Pareto set of (bake time, ns/ray, baked
//! bytes), the least time for one frame, `bake + rays · ns/ray`; candidates within
//! [`TIE`] of that time count as tied and the one with the fewest bytes wins.

use crate::render::{self, RenderOptions};
use crate::report::measure::tolerance;
use crate::trace::Tracer;
use crate::MethodSpec;
use hfcast::scene::{BakePlan, MethodKind, Need, Product, RayClasses};
use hfcast::{HeightField, Query, Trace};
use std::fmt::Write;
use std::time::Instant;

/// Relative frame-time difference under which two candidates are tied (then the one
/// with fewer baked bytes is chosen).
pub const TIE: f64 = 0.05;

/// How much to measure.
#[derive(Clone, Copy, Debug)]
pub struct AdviseOptions {
    /// Timing repetitions (median).
    pub reps: usize,
    /// Measure on every `every`-th pixel only (row-major; 1: all), its primary and
    /// shadow rays, to measure faster; the frame's ray counts are then estimated as
    /// `every` times those measured.
    pub every: usize,
}

impl Default for AdviseOptions {
    fn default() -> Self {
        AdviseOptions { reps: 3, every: 1 }
    }
}

/// One exact method measured on the scene.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The method.
    pub method: MethodSpec,
    /// The core's bake plan it baked by.
    pub plan: BakePlan,
    /// Seconds of its bake, one thread.
    pub bake_s: f64,
    /// Bytes of baked data.
    pub bytes: usize,
    /// Median nanoseconds per ray, one thread.
    pub ns_per_ray: f64,
    /// Mean texture fetches per ray.
    pub fetches_per_ray: f64,
    /// Rays whose answer differs from the exact traversal's by more than `f32`
    /// rounding (the report's tolerance; grazing rays may).
    pub differ: usize,
    /// Whether no other candidate is at least as good in bake time, ns/ray and bytes
    /// and better in one.
    pub pareto: bool,
}

impl Candidate {
    /// Seconds of one frame of `rays` rays: the bake, then the rays.
    pub fn frame_s(&self, rays: usize) -> f64 {
        self.bake_s + rays as f64 * self.ns_per_ray * 1e-9
    }

    /// Whether `self` dominates `other`: no worse in every cost, better in one.
    fn dominates(&self, other: &Candidate) -> bool {
        let (a, b) = (self.costs(), other.costs());
        a.iter().zip(&b).all(|(x, y)| x <= y) && a.iter().zip(&b).any(|(x, y)| x < y)
    }

    /// Bake seconds, ns/ray, bytes.
    fn costs(&self) -> [f64; 3] {
        [self.bake_s, self.ns_per_ray, self.bytes as f64]
    }
}

/// What `advise` measured and chose.
#[derive(Clone, Debug)]
pub struct Advice {
    /// Primary rays of one frame (pixels whose ray reaches the slab); estimated when
    /// [`AdviseOptions::every`] is over 1.
    pub primary: usize,
    /// Shadow rays of one frame (likewise).
    pub shadow: usize,
    /// Rays measured.
    pub measured: usize,
    /// Every exact method that traces the surface, in [`MethodSpec::exact`] order.
    pub candidates: Vec<Candidate>,
    /// Index of the chosen one in [`Advice::candidates`].
    pub choice: usize,
}

impl Advice {
    /// Rays of one frame.
    pub fn rays(&self) -> usize {
        self.primary + self.shadow
    }

    /// The chosen candidate.
    pub fn chosen(&self) -> &Candidate {
        &self.candidates[self.choice]
    }
}

/// The rays of every `every`-th pixel (row-major) of a render with `opts`: primary rays
/// (those that reach the slab) and the shadow rays from the exact traversal's hits
/// that face the light.
pub fn scene_rays(
    hf: &HeightField,
    opts: &RenderOptions,
    every: usize,
) -> (Vec<Query<f32>>, Vec<Query<f32>>) {
    let (cam, base) = render::render_camera(hf, opts);
    let primary: Vec<Query<f32>> = (0..opts.height)
        .flat_map(|py| (0..opts.width).map(move |px| (px, py)))
        .step_by(every.max(1))
        .filter_map(|(px, py)| render::primary_ray(&cam, base, px, py))
        .collect();
    let light = render::light_dir(hf, opts);
    let exact = hfcast::Method::Exact;
    let shadow = primary
        .iter()
        .filter_map(|q| Some((exact.trace(hf, opts.surface, q).hit?, q)))
        .filter_map(|(hit, q)| {
            let m = render::origin_magnitude(q);
            render::shadow_ray(hf, opts.surface, &hit, &light, m, opts.rays.exterior)
                .map(|(s, _)| s)
        })
        .collect();
    (primary, shadow)
}

/// The classes of `rays`.
fn classes_of(rays: &[Query<f32>]) -> RayClasses {
    rays.iter()
        .fold(RayClasses::NONE, |set, q| set.with(q.class()))
}

/// Whether `got` answers `want`'s hit within `f32` rounding.
fn same(q: &Query<f32>, want: &Trace<f32>, got: &Trace<f32>) -> bool {
    match (want.hit, got.hit) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            let (a, b) = (a.point.to_array(), b.point.to_array());
            let p = a.map(f64::from);
            let e = (0..3)
                .map(|k| (p[k] - f64::from(b[k])).powi(2))
                .sum::<f64>();
            e.sqrt() <= tolerance(false, q.origin().map(f64::from), p)
        }
        _ => false,
    }
}

/// Median of `v` (not empty).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Measures one method on `rays` against the exact traversal's answers `want`.
fn measure(
    hf: HeightField,
    method: MethodSpec,
    opts: &RenderOptions,
    rays: &[Query<f32>],
    want: &[Trace<f32>],
    how: AdviseOptions,
) -> Result<Candidate, String> {
    let tracer = Tracer::bake(hf, method, opts.surface, classes_of(rays))?;
    let mut out = vec![Trace::MISS; rays.len()];
    tracer.trace_all(rays, &mut out);
    let differ = rays
        .iter()
        .zip(want.iter().zip(&out))
        .filter(|(q, (w, g))| !same(q, w, g))
        .count();
    let fetches = out.iter().map(|t| f64::from(t.fetches)).sum::<f64>();
    let times = (0..how.reps.max(1))
        .map(|_| {
            let start = Instant::now();
            tracer.trace_all(std::hint::black_box(rays), &mut out);
            std::hint::black_box(&out);
            start.elapsed().as_secs_f64()
        })
        .collect();
    Ok(Candidate {
        method,
        plan: *tracer.plan(),
        bake_s: tracer.bake_time().as_secs_f64(),
        bytes: tracer.bytes(),
        ns_per_ray: median(times) * 1e9 / rays.len().max(1) as f64,
        fetches_per_ray: fetches / rays.len().max(1) as f64,
        differ,
        pareto: false,
    })
}

/// Measures every exact method on the rays of a render with `opts` and chooses one
/// (see the module's documentation). `progress` is told each method before it is
/// measured.
pub fn advise(
    hf: &HeightField,
    opts: &RenderOptions,
    how: AdviseOptions,
    progress: impl Fn(MethodSpec),
) -> Result<Advice, String> {
    let every = how.every.max(1);
    let (primary, shadow) = scene_rays(hf, opts, every);
    let (n_primary, n_shadow) = (primary.len() * every, shadow.len() * every);
    let rays = [primary, shadow].concat();
    let exact = Tracer::bake(
        *hf,
        MethodSpec::of(MethodKind::Exact),
        opts.surface,
        RayClasses::ALL,
    )?;
    let mut want = vec![Trace::MISS; rays.len()];
    exact.trace_all(&rays, &mut want);
    let mut candidates = Vec::new();
    for method in MethodSpec::exact()
        .into_iter()
        .filter(|m| m.supports(opts.surface))
    {
        progress(method);
        candidates.push(measure(*hf, method, opts, &rays, &want, how)?);
    }
    for k in 0..candidates.len() {
        let dominated = candidates.iter().any(|c| c.dominates(&candidates[k]));
        candidates[k].pareto = !dominated;
    }
    let choice = choose(&candidates, n_primary + n_shadow);
    Ok(Advice {
        primary: n_primary,
        shadow: n_shadow,
        measured: rays.len(),
        candidates,
        choice,
    })
}

/// The index of the choice among `candidates` (not empty) for frames of `rays` rays:
/// of the Pareto set, the fewest bytes among those within [`TIE`] of the least frame
/// time.
pub fn choose(candidates: &[Candidate], rays: usize) -> usize {
    let pareto = || candidates.iter().enumerate().filter(|(_, c)| c.pareto);
    let best = pareto()
        .map(|(_, c)| c.frame_s(rays))
        .fold(f64::INFINITY, f64::min);
    pareto()
        .filter(|(_, c)| c.frame_s(rays) <= best * (1.0 + TIE))
        .min_by(|(_, a), (_, b)| {
            (a.bytes, a.frame_s(rays))
                .partial_cmp(&(b.bytes, b.frame_s(rays)))
                .expect("finite times")
        })
        .map_or(0, |(k, _)| k)
}

/// What a bake plan bakes, in one line: the products kept and those baked as scratch,
/// the ray classes and layout of the safety-shape maps.
pub fn plan_text(plan: &BakePlan) -> String {
    if plan.bakes_nothing() {
        return "bakes nothing".into();
    }
    let list = |need: Need| {
        Product::ALL
            .into_iter()
            .filter(|&p| plan.need(p) == need)
            .map(Product::name)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut s = format!("keeps {}", list(Need::Keep));
    let scratch = list(Need::Scratch);
    if !scratch.is_empty() {
        let _ = write!(s, "; scratch {scratch}");
    }
    if plan.classes != RayClasses::NONE {
        let names = ["x+", "x-", "y+", "y-"];
        let held: Vec<&str> = hfcast::safety::CLASSES
            .into_iter()
            .zip(names)
            .filter(|&(c, _)| plan.classes.contains(c))
            .map(|(_, n)| n)
            .collect();
        let _ = write!(s, "; ray classes {}", held.join(" "));
    }
    if plan.bakes(Product::SafetyMap) {
        s.push_str(if plan.isotropic {
            "; isotropic layout"
        } else {
            "; directional layout"
        });
    }
    s
}

/// The advice as Markdown: a table of the candidates, the choice with its numbers and
/// its bake plan.
pub fn markdown(advice: &Advice) -> String {
    let rays = advice.rays();
    let mut s = format!(
        "{} primary + {} shadow rays a frame; {} measured, one thread\n\n\
         | method | bake ms | baked bytes | ns/ray | fetches/ray | one frame ms | Pareto | differ |\n\
         |---|---:|---:|---:|---:|---:|---|---:|\n",
        advice.primary, advice.shadow, advice.measured
    );
    for c in &advice.candidates {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {} | {:.1} | {:.1} | {:.1} | {} | {} |",
            c.method.name(),
            c.bake_s * 1e3,
            c.bytes,
            c.ns_per_ray,
            c.fetches_per_ray,
            c.frame_s(rays) * 1e3,
            if c.pareto { "yes" } else { "" },
            c.differ
        );
    }
    let c = advice.chosen();
    let _ = write!(
        s,
        "\nchoice: {} (least one-frame time, bake + rays x ns/ray, of the Pareto set of \
         bake time, ns/ray and bytes; ties within {:.0} % by bytes): {:.1} ms a frame = \
         bake {:.1} ms + {rays} rays x {:.1} ns, {} bytes, {:.1} fetches/ray\n\
         bake plan: {}\n",
        c.method.name(),
        TIE * 100.0,
        c.frame_s(rays) * 1e3,
        c.bake_s * 1e3,
        c.ns_per_ray,
        c.bytes,
        c.fetches_per_ray,
        plan_text(&c.plan)
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use hfcast::scene::{MethodKind, Scene};
    use hfcast::Surface;

    fn candidate(method: MethodSpec, bake_s: f64, ns: f64, bytes: usize) -> Candidate {
        Candidate {
            method,
            plan: Scene::general(method.kind(), Surface::Triangles).bake_plan(),
            bake_s,
            bytes,
            ns_per_ray: ns,
            fetches_per_ray: 0.0,
            differ: 0,
            pareto: true,
        }
    }

    #[test]
    fn choice_is_the_fastest_frame_ties_by_bytes() {
        let [dda, mip, safety, cc, _] = MethodSpec::exact()[..] else {
            unreachable!("five exact methods")
        };
        let mut c = vec![
            candidate(dda, 0.0, 400.0, 0),
            candidate(mip, 0.01, 200.0, 1000),
            candidate(safety, 0.5, 150.0, 500),
            candidate(cc, 0.02, 201.0, 2000),
        ];
        // cc is dominated by the maximum mipmap.
        assert!(c[1].dominates(&c[3]) && !c[3].dominates(&c[1]));
        c[3].pareto = false;
        // A million rays: dda 0.4 s, maxmip 0.21 s, safety 0.65 s.
        assert_eq!(choose(&c, 1_000_000), 1);
        // Ten rays: the bake decides; dda and maxmip tie (within 5 %) and dda has 0 bytes.
        assert_eq!(choose(&c, 10), 0);
        // A billion rays: safety's 150 ns wins.
        assert_eq!(choose(&c, 1_000_000_000), 2);
    }

    #[test]
    fn plan_text_names_the_bakes() {
        let scene = Scene {
            ray_classes: RayClasses::NONE.with(hfcast::RayClass::XNeg),
            ..Scene::general(MethodKind::Safety, Surface::Triangles)
        };
        let text = plan_text(&scene.bake_plan());
        assert_eq!(
            text,
            "keeps safety map; scratch safety scratch; ray classes x-; isotropic layout"
        );
        let exact = Scene::general(MethodKind::Exact, Surface::Triangles).bake_plan();
        assert_eq!(plan_text(&exact), "bakes nothing");
    }
}
