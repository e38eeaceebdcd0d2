//! Projective height fields in WGSL (`shaders/wgsl/projective.wgsl`, a mirror of
//! `core/src/projective.rs`) executed on a Vulkan device through wgpu (lavapipe in CI)
//! against the Rust core, ray by ray: on the bundled map and a synthetic field with
//! needles and thin walls, through a reverse-perspective frustum (projection centre
//! under the field, a sheared world), world rays traced with `hf_trace_projective` (the
//! map and its inverse as constants) and on the CPU with `Projective::trace` around the
//! same f32 march, for the exact DDA, the maximum mipmap and the cylinder–cone march,
//! each in the general source and the shader generated for its scene.
//!
//! The rays are aimed at grid points over the footprint (some grazing the surface)
//! from world points back along random directions; a fifth come from behind the centre
//! of projection (their range starts at w = 0). The shader maps in f32 where the core
//! maps in f64 (the file header of projective.wgsl), so a ray agrees when hit/miss is
//! the same and, for a hit, t and the world point are within [`REL_TOL`] of the ray's
//! magnitude and the unit normal within [`NORMAL_TOL`]; at least 99.9 % of each case's
//! rays must agree, the others are printed. A ray from behind the centre that is under
//! the surface where its range starts (the core flags `ORIGIN_INSIDE` or `SIDE`) hits
//! there, on the widened box, where its line comes in from infinity: which face is
//! ill-conditioned (f32 puts the entry on another face for about 1 % of them), so such
//! a ray agrees when the shader flags its hit so too; they are counted apart.

mod common;

use common::{
    load_bundled_map, run_kernel, Agreement, Case, Gpu, GpuHit, Kernel, Ray, Scene, SceneGpu,
};
use hfcast::projective::{Mat4, Projective};
use hfcast::rng::SplitMix as Rng;
use hfcast::scene::MethodKind;
use hfcast::{Flags, Query, Surface, Trace};
use std::fmt::Write as _;

/// Largest difference of an agreeing hit's t and world point components, relative to
/// the ray's magnitude.
const REL_TOL: f64 = 1e-4;
/// Largest difference of an agreeing hit's unit world normal components.
const NORMAL_TOL: f64 = 1e-3;

/// The reverse-perspective frustum of `core/tests/projective.rs` for a `w × h` field.
fn frustum(w: u32, h: u32) -> Projective {
    let (xm, ym) = (f64::from(w - 1), f64::from(h - 1));
    let f = 3.0 * (xm + ym);
    let (cx, cy) = (0.5 * xm, 0.4 * ym);
    let p: Mat4 = [
        [1.0, 0.0, cx / f, 0.0],
        [0.0, 1.0, cy / f, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0 / f, 1.0],
    ];
    let a: Mat4 = [
        [1.5, 0.2, 0.0, 0.0],
        [0.0, 0.8, 0.0, 0.0],
        [0.0, 0.0, 1.2, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let m: Mat4 =
        core::array::from_fn(|r| core::array::from_fn(|c| (0..4).map(|k| p[r][k] * a[k][c]).sum()));
    Projective::new(m).expect("an invertible frustum")
}

/// World rays of `scene` through `proj` (see the file's header).
fn world_rays(scene: &Scene, proj: &Projective, seed: u64, n: usize) -> Vec<Ray> {
    let hf = scene.hf();
    let (xm, ym) = (f64::from(scene.w - 1), f64::from(scene.h - 1));
    let (zlo, zhi) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let f = 3.0 * (xm + ym);
    let mut rng = Rng::new(seed);
    let mut rays = Vec::new();
    for k in 0..n {
        let (gx, gy) = (rng.range(0.0, xm), rng.range(0.0, ym));
        let near = if k % 3 == 0 {
            rng.range(0.0, 0.05)
        } else {
            0.0
        };
        let target = proj.to_world([gx, gy, Surface::Triangles.height_at(&hf, gx, gy) + near]);
        let az = rng.range(0.0, std::f64::consts::TAU);
        let from_below = k % 5 == 4;
        let el = if from_below {
            -rng.range(0.6, 1.4)
        } else {
            rng.range(0.02, 1.4)
        };
        let d = [-az.cos() * el.cos(), -az.sin() * el.cos(), -el.sin()];
        let back = if from_below {
            4.0 * f
        } else {
            rng.range(1.0, 2.0) * (xm + ym + zhi - zlo)
        };
        let o = [0, 1, 2].map(|c| (target[c] - back * d[c]) as f32);
        if let Ok(q) = Query::from_arrays(o, d.map(|v| v as f32), 0.0, f32::INFINITY) {
            rays.push(q);
        }
    }
    rays
}

/// Counts of one case over the scenes.
#[derive(Default)]
struct Tally {
    n: Agreement,
    /// Rays from behind the centre, under the surface where their range starts.
    under_at_start: u64,
    max_dp: f64,
    max_dn: f64,
}

impl Tally {
    fn add(&mut self, scene: &str, behind: bool, r: &Ray, cpu: &Trace<f32>, g: &GpuHit) {
        let o = r.origin().map(|v| f64::from(v).abs());
        let mag = o.into_iter().fold(1f64, f64::max);
        let under = Flags::ORIGIN_INSIDE.with(Flags::SIDE).0;
        let agree = match cpu.hit {
            None => !g.hit,
            Some(h) if behind && h.flags.0 & under != 0 => {
                self.under_at_start += 1;
                g.hit && g.flags & under != 0
            }
            Some(h) if g.hit => {
                let scale = mag.max(f64::from(h.t).abs());
                let dt = (f64::from(g.t) - f64::from(h.t)).abs() / scale;
                let (p, n) = (h.point.to_array(), h.normal.to_array());
                let (mut dp, mut dn) = (0f64, 0f64);
                for k in 0..3 {
                    dp = dp.max((f64::from(g.point[k]) - f64::from(p[k])).abs() / scale);
                    dn = dn.max((f64::from(g.normal[k]) - f64::from(n[k])).abs());
                }
                let ok = dt <= REL_TOL && dp <= REL_TOL && dn <= NORMAL_TOL;
                if ok {
                    self.n.hit(dt, g.cell != h.cell);
                    self.max_dp = self.max_dp.max(dp);
                    self.max_dn = self.max_dn.max(dn);
                }
                ok
            }
            Some(_) => false,
        };
        let wrong = || format!("{scene}: projective {}", common::describe(r, cpu, g));
        self.n.ray(agree, cpu.fetches != g.fetches, wrong);
    }
}

#[test]
fn wgsl_projective_rays_match_the_rust_core_ray_by_ray() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let (w, h, _, _, heights) = load_bundled_map();
    let scenes = [
        Scene::new("jacksboro 403x344", w, h, heights, false),
        Scene::spiky(7, 96, 80, false),
    ];
    let uploaded: Vec<SceneGpu> = scenes.iter().map(|s| SceneGpu::new(&gpu, s)).collect();
    let projs: Vec<Projective> = scenes.iter().map(|s| frustum(s.w, s.h)).collect();
    let rays: Vec<Vec<Ray>> = scenes
        .iter()
        .zip(&projs)
        .enumerate()
        .map(|(k, (s, p))| world_rays(s, p, 0x9e + k as u64, 3000))
        .collect();
    let methods = [
        (MethodKind::Exact, Surface::Triangles),
        (MethodKind::MaxMip, Surface::Triangles),
        (MethodKind::Cc, Surface::Triangles),
    ];
    let mut report = String::new();
    let mut failures = String::new();
    for (method, surface) in methods {
        for generated in [false, true] {
            let mut tally = Tally::default();
            let mut label = String::new();
            for (k, (scene, sg)) in scenes.iter().zip(&uploaded).enumerate() {
                let case = Case {
                    generated,
                    projective: Some(projs[k]),
                    ..Case::new(method, surface, [0; 4], true)
                };
                label = case.label();
                let kernel = Kernel::new(&gpu, &case);
                let got = run_kernel(&gpu, &kernel, sg, &case, &rays[k]);
                let want = case.cpu(scene, &rays[k]);
                for ((r, g), cpu) in rays[k].iter().zip(&got).zip(&want) {
                    let behind = projs[k].to_grid_h(r.origin().map(f64::from))[3] <= 0.0;
                    tally.add(&scene.name, behind, r, cpu, g);
                }
            }
            let _ = writeln!(
                report,
                "{label:<24} projective rays {:>6}  agree {:>6} ({:.4} %)  hits {:>6}  max rel |dt| \
                 {:.1e}  max rel |dp| {:.1e}  max |dn| {:.1e}  fetches differ {}  cell differ {}  \
                 from behind, under at the start {}",
                tally.n.rays,
                tally.n.agree,
                100.0 * tally.n.rate(),
                tally.n.hits,
                tally.n.max_dt,
                tally.max_dp,
                tally.max_dn,
                tally.n.fetches_differ,
                tally.n.cell_differ,
                tally.under_at_start,
            );
            for wr in &tally.n.wrong {
                let _ = writeln!(report, "    differs: {wr}");
            }
            if tally.n.rate() < 0.999 || tally.n.hits < tally.n.rays / 4 {
                let _ = writeln!(
                    failures,
                    "{label}: {} of {} projective rays differ ({} hits)",
                    tally.n.wrong.len(),
                    tally.n.rays,
                    tally.n.hits
                );
            }
        }
    }
    println!("{report}");
    assert!(failures.is_empty(), "WGSL projective fields:\n{failures}");
}
