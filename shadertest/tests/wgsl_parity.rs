//! The WGSL marches (`shaders/wgsl`) executed on a Vulkan device through wgpu
//! (lavapipe in CI: `mesa-vulkan-drivers`) against the Rust core's f32 marches, ray by
//! ray: for every method (exact on all five surfaces, linear-binary, linear-secant,
//! maxmip on triangles and bilinear, safety in both layouts, cc, cone, qdm, relaxed,
//! radius; safety, cc and radius also on the view-linear surface, §7) on
//! the bundled map, a synthetic field with needles and thin walls, and two small fields
//! where relaxed (a Θ(N⁴) bake) is baked too: a 64 × 64 crop of the map and a smaller
//! synthetic field; over 45° and 5° camera rays and random rays (upward,
//! grazing, axis-parallel, vertical, under the surface, finite ranges). Every case runs
//! twice: `hfcast-shaders`' general source (scene choices as `override`s), and the
//! shader it generates for the case's scene (constants, unused code left out). A few
//! cases read the heights as 16-bit samples (`field_int.wgsl`), which only generated
//! shaders do: both runs of those are generated (`generate`, then `generate_with`).
//! The safety (both layouts) and cc cases also run on compact maps of a ray-class
//! subset ({x+, y−} and {x−}: `bake_rows_classes`, W × nH textures, the set as
//! `hf_safety_classes` / `hf_cc_classes`, or the generated scene's `ray_classes`)
//! against `SafetyMap::with_classes` / `CcMap::with_classes`, on rays of every class:
//! those of a class the map does not hold read zero jumps and must agree too. The
//! safety (both layouts) and cc cases also run on maps baked for a ray set (exterior
//! rays within 60° of the downward vertical, `RAY_SET`; the set as `hf_rays_exterior`
//! and `hf_rays_max_view_angle`, or the generated scene's `outside_only` and
//! `max_view_angle_deg`) against `with_rays`: the rays outside the set (inside starts,
//! upward and grazing rays) walk cell by cell and must agree too; the generated
//! shaders of such a scene serve the scene's rays only, and are compared on those.
//!
//! A ray agrees when hit/miss is the same and, for a hit, |t_gpu − t_cpu| ≤ 1e-3 texel
//! (directions are unit). Every case must agree on at least 99.99 % of its rays; the
//! approximate methods (linear-binary, linear-secant, relaxed) are deterministic and
//! are held to the same rate. Differences in fetches, flags, cells and points are
//! counted and reported too. No Vulkan adapter is a failure, not a skip.

mod common;

use common::{
    describe, load_bundled_map, run_kernel, scene_rays, Agreement, Case, Gpu, GpuHit, Kernel, Ray,
    Scene, SceneGpu,
};
use std::fmt::Write as _;
use std::time::Instant;

/// Largest |t_gpu − t_cpu| (texels) of an agreeing hit.
const T_TOL: f64 = 1e-3;

/// Counts of one case over the scenes.
#[derive(Default)]
struct Tally {
    /// The counts both tests keep (`max_dt`: |t_gpu − t_cpu|).
    n: Agreement,
    /// Rays of a class the case's map does not hold.
    unheld: u64,
    /// Rays outside the ray set the case's map is baked for.
    outside: u64,
    flags_differ: u64,
    point_differ: u64,
    /// A few rays that agree but not bit for bit (t, fetches or flags differ).
    other: Vec<String>,
}

impl Tally {
    fn add(&mut self, scene: &str, r: &Ray, cpu: &hfcast::Trace<f32>, g: &GpuHit) {
        let cpu_flags = cpu.flags.0 | cpu.hit.map_or(0, |h| h.flags.0);
        let agree = match cpu.hit {
            None => !g.hit,
            Some(h) => {
                let dt = (f64::from(g.t) - f64::from(h.t)).abs();
                if g.hit && dt <= T_TOL {
                    self.n.hit(dt, g.cell != h.cell);
                    let p = h.point.to_array();
                    if (0..3).any(|k| f64::from((p[k] - g.point[k]).abs()) > T_TOL) {
                        self.point_differ += 1;
                    }
                    true
                } else {
                    false
                }
            }
        };
        let fetches = cpu.fetches != g.fetches;
        if !self.n.ray(agree, fetches, || {
            format!("{scene}: {}", describe(r, cpu, g))
        }) {
            return;
        }
        let flags = cpu_flags != g.flags;
        let inexact = cpu.hit.is_some_and(|h| h.t != g.t);
        self.flags_differ += u64::from(flags);
        if (fetches || flags || inexact) && self.other.len() < 3 {
            self.other.push(format!("{scene}: {}", describe(r, cpu, g)));
        }
    }
}

#[test]
fn wgsl_marches_match_the_rust_core_ray_by_ray() {
    let start = Instant::now();
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let (w, h, samples, depth, heights) = load_bundled_map();
    let scenes = [
        Scene::new("jacksboro 403x344", w, h, heights.clone(), false)
            .with_samples(samples.clone(), depth),
        Scene::new(
            "jacksboro crop 64x64",
            64,
            64,
            Scene::crop(&heights, w, 64, 64),
            true,
        )
        .with_samples(Scene::crop(&samples, w, 64, 64), depth),
        Scene::spiky(7, 96, 80, false),
        Scene::spiky(11, 40, 36, true),
    ];
    let uploaded: Vec<SceneGpu> = scenes.iter().map(|s| SceneGpu::new(&gpu, s)).collect();
    let rays = scene_rays(&scenes, 1000, 16, 800);
    println!(
        "scenes baked and uploaded in {:.1} s",
        start.elapsed().as_secs_f64()
    );

    let mut report = String::new();
    let mut failures = String::new();
    // HFCAST_WGSL_CASE=text runs only the cases whose label contains it (debugging).
    let only = std::env::var("HFCAST_WGSL_CASE").unwrap_or_default();
    for case in Case::all() {
        if !case.label().contains(&only) {
            continue;
        }
        let t0 = Instant::now();
        let kernel = Kernel::new(&gpu, &case);
        let compile_s = t0.elapsed().as_secs_f64();
        let mut tally = Tally::default();
        // Multires: rays whose CPU march used a coarse level (fetches unlike the exact
        // walk's), so that the parity covers the level switches.
        let multires = case.method == hfcast::scene::MethodKind::Multires;
        let mut coarse = 0u64;
        for ((scene, sg), rays) in scenes.iter().zip(&uploaded).zip(&rays) {
            let relaxed = case.method == hfcast::scene::MethodKind::Relaxed;
            if (relaxed && scene.relaxed.is_none()) || (case.int_heights && scene.samples.is_none())
            {
                continue;
            }
            let got = run_kernel(&gpu, &kernel, sg, &case, rays);
            let want = case.cpu(scene, rays);
            let hf = scene.hf();
            let (set, walls) = case.set_on(scene);
            for ((r, g), cpu) in rays.iter().zip(&got).zip(&want) {
                let outside = !set.holds(&hf, walls, r);
                tally.outside += u64::from(outside);
                // A generated shader serves its scene's rays only (an outside-only
                // scene's leaves out the start under the surface, a view angle's the
                // upward rays): the others are not compared.
                if outside && case.generated {
                    continue;
                }
                tally.add(&scene.name, r, cpu, g);
                if multires {
                    coarse +=
                        u64::from(hfcast::dda::trace(&hf, case.surface, r).fetches != cpu.fetches);
                }
                tally.unheld += u64::from(case.classes & (1 << r.class() as u8) == 0);
            }
        }
        let kind = if case.exact { "exact" } else { "approximate" };
        let _ = writeln!(
            report,
            "{:<26} {kind:<11} rays {:>6}  agree {:>6} ({:.4} %)  hits {:>6}  max |dt| {:.2e}  \
             fetches differ {}  flags differ {}  cell differ {}  point > 1e-3 {}{}{}  (compile {:.1} s, total {:.1} s)",
            case.label(),
            tally.n.rays,
            tally.n.agree,
            100.0 * tally.n.rate(),
            tally.n.hits,
            tally.n.max_dt,
            tally.n.fetches_differ,
            tally.flags_differ,
            tally.n.cell_differ,
            tally.point_differ,
            if case.classes == 15 {
                String::new()
            } else {
                format!("  rays of classes not held {}", tally.unheld)
            },
            if case.rays.is_all() {
                String::new()
            } else {
                let compared = if case.generated { " (not compared)" } else { "" };
                format!("  rays outside the set {}{compared}", tally.outside)
            },
            compile_s,
            t0.elapsed().as_secs_f64()
        );
        for o in &tally.other {
            let _ = writeln!(report, "    agrees, but not bit for bit: {o}");
        }
        if multires {
            let _ = writeln!(report, "    rays that reached a coarse level: {coarse}");
            if coarse == 0 {
                let _ = writeln!(failures, "{}: no ray reached a coarse level", case.label());
            }
        }
        if !tally.n.passes() {
            let _ = writeln!(
                failures,
                "{}: {} of {} rays differ:",
                case.label(),
                tally.n.wrong.len(),
                tally.n.rays
            );
            for wr in &tally.n.wrong {
                let _ = writeln!(failures, "    {wr}");
            }
        } else {
            for wr in &tally.n.wrong {
                let _ = writeln!(report, "    differs (within the allowed rate): {wr}");
            }
        }
    }
    println!("{report}");
    println!("total {:.1} s", start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "WGSL and Rust disagree:\n{failures}");
}
