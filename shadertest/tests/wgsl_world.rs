//! World units in WGSL (`shaders/wgsl/world.wgsl`, a mirror of `core/src/world.rs`)
//! executed on a Vulkan device through wgpu (lavapipe in CI) against the Rust core, ray
//! by ray: on the bundled map and a synthetic field with needles and thin walls, under
//! a transform with unequal spacings, a negative y spacing, a height scale and offsets,
//! world rays traced with `hf_trace_world` (the transform as the `hf_world` uniform) and
//! on the CPU with `WorldTransform::trace` around the same f32 march, for the exact
//! DDA (triangles, bilinear) and two baked methods (maxmip, cylinder–cone), each in the
//! general source and the shader generated for its scene.
//!
//! The world rays are the parity test's camera and random rays mapped to world space
//! (same line and segment, unit world direction, so t is in world units). The shader
//! converts in f32 where the core converts in f64 (the file header of world.wgsl): the
//! grid rays differ by a few ulps of the world coordinates, a hit's t by that over the
//! cosine of incidence. So a world ray agrees when hit/miss is the same, the clearance
//! (scaled by the height scale) is within [`REL_TOL`] of the ray's magnitude
//! (max(|t|, |origin|, 1), componentwise largest, plus |clearance|) and, for a hit, t and
//! every component of the world point are within [`REL_TOL`] of it (plus |p| for the
//! point) and every component of the unit world normal within [`NORMAL_TOL`]; at least
//! 99.99 % of each case's rays must agree, the others are printed. With the identity transform `hf_trace_world` must give the plain `hf_trace`
//! answers bit for bit (every field, on the grid rays).

mod common;

use common::{
    describe, load_bundled_map, run_kernel, scene_rays, Agreement, Case, Gpu, GpuHit, Kernel, Ray,
    Scene, SceneGpu,
};
use hfcast::scene::MethodKind;
use hfcast::world::WorldTransform;
use hfcast::{Query, Surface, Trace};
use std::fmt::Write as _;

/// Largest difference of an agreeing ray's t, world point components and clearance,
/// relative to the ray's magnitude.
const REL_TOL: f64 = 1e-5;
/// Largest difference of an agreeing hit's unit world normal components.
const NORMAL_TOL: f64 = 1e-3;

/// Unequal spacings, y flipped (a north-up raster), heights scaled and offset: no
/// coefficient is 1 or 0. World coordinates stay within a few thousand units, where f32
/// keeps a grid ray within a few ulps of the core's f64-converted one.
fn transform() -> WorldTransform {
    WorldTransform::new([-310.5, 1250.25], [3.0, -2.5], 1.75, -42.0).expect("a valid transform")
}

/// The world ray of the grid ray `r` under `t`: the same line and segment, the direction
/// a unit vector in world space (its ranges scaled to match).
fn to_world(t: &WorldTransform, r: &Ray) -> Ray {
    let o = t.point_to_world(r.origin().map(f64::from));
    let d = t.dir_to_world(r.dir().map(f64::from));
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let range = |v: f32| (f64::from(v) * len) as f32;
    Query::from_arrays(
        o.map(|v| v as f32),
        d.map(|v| (v / len) as f32),
        range(r.t_min()),
        range(r.t_max()),
    )
    .expect("a valid world ray")
}

/// Whether two GPU answers are the same bit for bit.
fn same_bits(a: &GpuHit, b: &GpuHit) -> bool {
    let f = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
    let floats = |g: &GpuHit| {
        let mut v = vec![g.t, g.clearance];
        v.extend(g.point);
        v.extend(g.normal);
        f(&v)
    };
    (a.hit, a.flags, a.fetches, a.cell) == (b.hit, b.flags, b.fetches, b.cell)
        && floats(a) == floats(b)
}

/// Counts of one world case over the scenes.
#[derive(Default)]
struct Tally {
    /// The counts both tests keep (`max_dt`: the largest relative difference of t).
    n: Agreement,
    /// Largest relative differences of the agreeing hits' points, and of the normals'
    /// largest component difference.
    max_dp: f64,
    max_dn: f64,
    clearance_differ: u64,
}

impl Tally {
    fn add(&mut self, scene: &str, r: &Ray, cpu: &Trace<f32>, g: &GpuHit) {
        // The ray's magnitude: where the conversion's rounding is relative to.
        let o = r.origin().map(|v| f64::from(v).abs());
        let mag = o.into_iter().fold(1f64, f64::max);
        let (c, gc) = (f64::from(cpu.clearance), f64::from(g.clearance));
        let clearance_ok = if c.is_finite() {
            (gc - c).abs() <= REL_TOL * (mag + c.abs())
        } else {
            gc == c
        };
        self.clearance_differ += u64::from(!clearance_ok);
        let agree = clearance_ok
            && match cpu.hit {
                None => !g.hit,
                Some(h) if g.hit => {
                    let scale = mag.max(f64::from(h.t).abs());
                    let dt = (f64::from(g.t) - f64::from(h.t)).abs() / scale;
                    let (p, n) = (h.point.to_array(), h.normal.to_array());
                    let (mut dp, mut dn) = (0f64, 0f64);
                    for k in 0..3 {
                        let (pk, gk) = (f64::from(p[k]), f64::from(g.point[k]));
                        dp = dp.max((gk - pk).abs() / (scale + pk.abs()));
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
        let wrong = || format!("{scene}: world {}", describe(r, cpu, g));
        self.n.ray(agree, cpu.fetches != g.fetches, wrong);
    }
}

#[test]
fn wgsl_world_rays_match_the_rust_core_ray_by_ray() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let (w, h, _, _, heights) = load_bundled_map();
    let scenes = [
        Scene::new("jacksboro 403x344", w, h, heights, false),
        Scene::spiky(7, 96, 80, false),
    ];
    let uploaded: Vec<SceneGpu> = scenes.iter().map(|s| SceneGpu::new(&gpu, s)).collect();
    let world = transform();
    // The parity test's camera and random rays (upward, grazing, axis-parallel, vertical,
    // under the surface, finite ranges).
    let grid_rays = scene_rays(&scenes, 2000, 40, 3000);
    let world_rays: Vec<Vec<Ray>> = grid_rays
        .iter()
        .map(|rays| rays.iter().map(|r| to_world(&world, r)).collect())
        .collect();

    let methods = [
        (MethodKind::Exact, Surface::Triangles),
        (MethodKind::Exact, Surface::Bilinear),
        (MethodKind::MaxMip, Surface::Triangles),
        (MethodKind::Cc, Surface::Triangles),
    ];
    let mut report = String::new();
    let mut failures = String::new();
    for (method, surface) in methods {
        for generated in [false, true] {
            let plain = Case {
                generated,
                ..Case::new(method, surface, [0; 4], true)
            };
            let in_world = Case {
                world: Some(world),
                ..plain
            };
            let identity = Case {
                world: Some(WorldTransform::IDENTITY),
                ..plain
            };
            let label = plain.label();
            let kernels = [&plain, &in_world, &identity].map(|c| Kernel::new(&gpu, c));
            let mut tally = Tally::default();
            let (mut identity_rays, mut identity_differ) = (0, 0);
            for (k, (scene, sg)) in scenes.iter().zip(&uploaded).enumerate() {
                let grid = &grid_rays[k];
                let want = run_kernel(&gpu, &kernels[0], sg, &plain, grid);
                let got = run_kernel(&gpu, &kernels[2], sg, &identity, grid);
                identity_rays += grid.len();
                identity_differ += want
                    .iter()
                    .zip(&got)
                    .filter(|(a, b)| !same_bits(a, b))
                    .count();
                let rays = &world_rays[k];
                let got = run_kernel(&gpu, &kernels[1], sg, &in_world, rays);
                let want = in_world.cpu(scene, rays);
                for ((r, g), cpu) in rays.iter().zip(&got).zip(&want) {
                    tally.add(&scene.name, r, cpu, g);
                }
            }
            let _ = writeln!(
                report,
                "{label:<24} world rays {:>6}  agree {:>6} ({:.4} %)  hits {:>6}  max rel |dt| \
                 {:.1e}  max rel |dp| {:.1e}  max |dn| {:.1e}  fetches differ {}  cell differ {}  \
                 clearance differ {}  \
                 | identity: {identity_rays} rays, {identity_differ} not bit-identical to hf_trace",
                tally.n.rays,
                tally.n.agree,
                100.0 * tally.n.rate(),
                tally.n.hits,
                tally.n.max_dt,
                tally.max_dp,
                tally.max_dn,
                tally.n.fetches_differ,
                tally.n.cell_differ,
                tally.clearance_differ,
            );
            let verdict = if !tally.n.passes() {
                let _ = writeln!(
                    failures,
                    "{label}: {} of {} world rays differ",
                    tally.n.wrong.len(),
                    tally.n.rays
                );
                "differs"
            } else {
                "differs (within the allowed rate)"
            };
            for wr in &tally.n.wrong {
                let _ = writeln!(report, "    {verdict}: {wr}");
            }
            if identity_differ > 0 {
                let _ = writeln!(
                    failures,
                    "{label}: with the identity, {identity_differ} of {identity_rays} rays of \
                     hf_trace_world differ from hf_trace"
                );
            }
        }
    }
    println!("{report}");
    assert!(failures.is_empty(), "WGSL world units:\n{failures}");
}
