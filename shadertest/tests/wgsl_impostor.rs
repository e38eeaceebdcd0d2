//! Six-field impostors in WGSL (`shaders/wgsl/impostor.wgsl`, a mirror of
//! `core/src/impostor.rs`, in the shader `hfcast_shaders::impostor` generates for the
//! exact method on the triangle surface) executed on a Vulkan device through wgpu
//! (lavapipe in CI) against the Rust core, ray by ray.
//!
//! The Stanford bunny (`data/`) and the core's procedural tower (48 segments), each
//! captured as six fields of 64² (`Layout::around`, `rasterize`, `pad_silhouettes`)
//! with orthographic and reverse-perspective (`Frustum::DEFAULT_REVERSE`) faces, the
//! six fields stacked in one R32Float texture; world rays of six pinhole cameras of
//! 24² pixels three half sides around the object (`hfcast_tools::impostor::six_views`), traced with both combinations by `hf_trace_impostor` and on the CPU by
//! `Impostor::trace` around the f32 DDA. The shader maps in f32 where the core maps in
//! f64 (impostor.wgsl's header), so a ray agrees when hit/miss is the same and, for a
//! hit, t (as a distance) and the world point are within [`REL_TOL`] of the cube's half
//! side, the unit normal within [`NORMAL_TOL`], and the face is the same, or else the
//! GPU's face's field's surface passes within [`TIE_TOL`] of the hit too (a tie: two
//! fields meet at the answer, as the tower's flat base does in several of them, and
//! which one sets t last is a matter of rounding; counted apart); at least
//! [`MIN_AGREE`] of each case's rays must agree, the others are printed. Measured on
//! lavapipe: every ray of the eight cases agrees, t and points within 1e-5 half sides,
//! normals within 1e-5; 47 of the tower's intersection hits are ties (within 1e-5 grid
//! units), none of the bunny's.

mod common;

use common::{
    bunny, describe, impostor_capture, impostor_layout0, impostor_uniforms, storage_entry, Gpu,
    GpuHit, MIN_AGREE,
};
use hfcast::impostor::{procedural_tower, Combine, Frustum, Impostor, ImpostorTrace, Layout, Mesh};
use hfcast::scene::{MethodKind, Scene};
use hfcast::{dda, HeightField, Query, Surface};
use hfcast_shaders::{wgsl_layout as binding, Lang};
use hfcast_tools::impostor::six_views;
use std::fmt::Write as _;

/// Largest difference of an agreeing hit's t (times the direction's length) and of its
/// world point, relative to the cube's half side.
const REL_TOL: f64 = 1e-4;
/// Largest difference of an agreeing hit's unit world normal components.
const NORMAL_TOL: f64 = 1e-3;
/// Largest distance (grid units) from the hit to the surface of the GPU's face's field
/// for a hit whose face differs but whose point and normal agree to count as a tie: both
/// fields' surfaces pass through the answer (coincident planes of the tower's flat
/// base), where which field sets t last is a matter of rounding.
const TIE_TOL: f64 = 1e-4;
/// The fields' side.
const SIDE: u32 = 64;
/// Pixels across each of the six cameras.
const PIXELS: u32 = 24;

/// The entry point appended to the impostor shader: one invocation per ray, traced by
/// `hf_trace_impostor` with `TEST_COMBINE`, written out as plain numbers.
const WRAPPER: &str = r#"
// ---- test entry point (shadertest/tests/wgsl_impostor.rs)
struct TestRay {
    origin: vec4<f32>, // xyz, t_min
    dir: vec4<f32>,    // xyz, t_max
}

struct TestOut {
    head: vec4<u32>,    // has_hit, flags (trace | hit), fetches, face
    point: vec4<f32>,   // hit.point, hit.t
    normal: vec4<f32>,  // hit.normal, clearance
    cell: vec4<u32>,    // hit.cell, traces, 0
}

@group(1) @binding(0) var<storage, read> test_rays: array<TestRay>;
@group(1) @binding(1) var<storage, read_write> test_out: array<TestOut>;

@compute @workgroup_size(64)
fn test_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= arrayLength(&test_rays)) {
        return;
    }
    let r = test_rays[k];
    let it = hf_trace_impostor(Query(r.origin.xyz, r.dir.xyz, r.origin.w, r.dir.w), TEST_COMBINE);
    let tr = it.trace;
    var flags = tr.flags;
    if (tr.has_hit) {
        flags |= tr.hit.flags;
    }
    test_out[k] = TestOut(vec4<u32>(u32(tr.has_hit), flags, tr.fetches, it.face),
                          vec4<f32>(tr.hit.point, tr.hit.t),
                          vec4<f32>(tr.hit.normal, tr.clearance),
                          vec4<u32>(tr.hit.cell, it.traces, 0u));
}
"#;

/// Rays of six pinhole cameras (`PIXELS²` each) three half sides from the centre,
/// looking at it from around the object (`hfcast_tools::impostor::six_views`).
fn camera_rays(layout: &Layout) -> Vec<Query<f32>> {
    let mut out = Vec::new();
    for cam in six_views(layout, PIXELS) {
        for j in 0..PIXELS {
            for i in 0..PIXELS {
                out.push(cam.ray(i, j, f32::INFINITY).expect("a camera ray"));
            }
        }
    }
    out
}

/// A compiled impostor kernel (one combination) and its bind group layouts.
struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout0: wgpu::BindGroupLayout,
    layout1: wgpu::BindGroupLayout,
}

impl Kernel {
    /// The impostor shader of the exact method on the triangle surface with the test
    /// entry point for `combine`, compiled (wgpu's message on a refusal).
    fn new(gpu: &Gpu, combine: Combine) -> Kernel {
        let scene = Scene {
            depth_output: false,
            ..Scene::general(MethodKind::Exact, Surface::Triangles)
        };
        let src = hfcast_shaders::impostor(&scene, Lang::Wgsl).expect("the impostor shader")
            + &format!("\nconst TEST_COMBINE: u32 = {}u;\n", combine as u32)
            + WRAPPER;
        let dev = &gpu.device;
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("impostor"),
            source: wgpu::ShaderSource::Wgsl(src.as_str().into()),
        });
        let layout0 = impostor_layout0(dev, wgpu::ShaderStages::COMPUTE, false);
        let layout1 = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[storage_entry(0, true), storage_entry(1, false)],
        });
        let pipeline_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout0), Some(&layout1)],
            immediate_size: 0,
        });
        let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("impostor"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("test_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("wgpu refused the impostor shader or pipeline: {e}");
        }
        Kernel {
            pipeline,
            layout0,
            layout1,
        }
    }

    /// Traces `rays` on the impostor `imp` whose fields are `stacked` (the host's
    /// inputs as impostor.wgsl's header asks) and reads the answers back, with each
    /// ray's face and field traces.
    fn run(
        &self,
        gpu: &Gpu,
        imp: &Impostor,
        stacked: &[f32],
        rays: &[Query<f32>],
    ) -> Vec<(GpuHit, u32, u32)> {
        let dev = &gpu.device;
        let heights = gpu.heights_texture(SIDE, 6 * SIDE, stacked);
        let [field, ranges, params] = impostor_uniforms(gpu, imp, SIDE);
        let group0 = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout0,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: binding::HEIGHTS,
                    resource: wgpu::BindingResource::TextureView(&heights),
                },
                wgpu::BindGroupEntry {
                    binding: binding::FIELD,
                    resource: field.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: binding::FIELD_RANGES,
                    resource: ranges.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: binding::IMPOSTOR,
                    resource: params.as_entire_binding(),
                },
            ],
        });
        gpu.dispatch_rays(&self.pipeline, &self.layout1, &group0, rays)
            .iter()
            .map(|w| (GpuHit::from_words(w), w[3], w[14]))
            .collect()
    }
}

/// How one case's rays compare.
#[derive(Default)]
struct Tally {
    rays: u64,
    agree: u64,
    hits: u64,
    /// Agreeing hits on another face whose field's surface also holds the hit.
    ties: u64,
    max_tie: f64,
    max_dt: f64,
    max_dp: f64,
    max_dn: f64,
    traces_differ: u64,
    fetches_differ: u64,
    wrong: Vec<String>,
}

impl Tally {
    /// Compares the GPU's answer `g` (its face and field traces) with the core's `cpu`
    /// for the ray `r` on `imp`.
    fn add(
        &mut self,
        r: &Query<f32>,
        imp: &Impostor,
        cpu: &ImpostorTrace<f32>,
        (g, face, traces): (GpuHit, u32, u32),
    ) {
        self.rays += 1;
        let half = imp.layout().half();
        let cpu_face = cpu.face.map_or(6, |f| f as u32);
        let agree = match cpu.trace.hit {
            None => !g.hit && face == 6,
            Some(h) if g.hit && face < 6 => {
                let len = r
                    .dir()
                    .iter()
                    .map(|v| f64::from(*v).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let dt = (f64::from(g.t) - f64::from(h.t)).abs() * len / half;
                let (p, n) = (h.point.to_array(), h.normal.to_array());
                let (mut dp, mut dn) = (0f64, 0f64);
                for k in 0..3 {
                    dp = dp.max((f64::from(g.point[k]) - f64::from(p[k])).abs() / half);
                    dn = dn.max((f64::from(g.normal[k]) - f64::from(n[k])).abs());
                }
                let mut ok = dt <= REL_TOL && dp <= REL_TOL && dn <= NORMAL_TOL;
                if ok && face != cpu_face {
                    let off = off_surface(imp, face as usize, p.map(f64::from));
                    ok = off <= TIE_TOL;
                    if ok {
                        self.ties += 1;
                        self.max_tie = self.max_tie.max(off);
                    }
                }
                if ok {
                    self.hits += 1;
                    self.max_dt = self.max_dt.max(dt);
                    self.max_dp = self.max_dp.max(dp);
                    self.max_dn = self.max_dn.max(dn);
                }
                ok
            }
            Some(_) => false,
        };
        if !agree {
            self.wrong.push(format!(
                "{}; cpu face {:?} traces {}, gpu face {face} traces {traces}",
                describe(r, &cpu.trace, &g),
                cpu.face,
                cpu.traces
            ));
            return;
        }
        self.agree += 1;
        self.traces_differ += u64::from(traces != cpu.traces);
        self.fetches_differ += u64::from(g.fetches != cpu.trace.fetches);
    }

    fn rate(&self) -> f64 {
        self.agree as f64 / self.rays.max(1) as f64
    }
}

/// How far (grid units) the world point `p` is from the surface of face `k`'s field
/// (infinite outside its footprint).
fn off_surface(imp: &Impostor, k: usize, p: [f64; 3]) -> f64 {
    let g = imp.map(k).to_grid_h(p);
    let (x, y, z) = (g[0] / g[3], g[1] / g[3], g[2] / g[3]);
    let hf = imp.field(k);
    let last = f64::from(hf.width() - 1);
    if !((0.0..=last).contains(&x) && (0.0..=last).contains(&y)) {
        return f64::INFINITY;
    }
    (z - Surface::Triangles.height_at(hf, x, y)).abs()
}

#[test]
fn wgsl_impostor_rays_match_the_rust_core_ray_by_ray() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let kernels = Combine::ALL.map(|c| (c, Kernel::new(&gpu, c)));
    let meshes = [("bunny", bunny()), ("tower", procedural_tower(48))];
    let mut report = String::new();
    let mut failures = String::new();
    for (name, (pos, tri)) in &meshes {
        let mesh = Mesh::new(pos, tri).expect("a mesh");
        for frustum in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
            let layout = Layout::around(&mesh, frustum).expect("a layout");
            let stacked = impostor_capture(&mesh, &layout, SIDE);
            let n = (SIDE * SIDE) as usize;
            let fields = core::array::from_fn(|k| {
                HeightField::new(&stacked[k * n..(k + 1) * n], SIDE, SIDE, SIDE as usize)
                    .expect("a field")
            });
            let imp = Impostor::new(layout, fields).expect("an impostor");
            let rays = camera_rays(&layout);
            for (combine, kernel) in &kernels {
                let got = kernel.run(&gpu, &imp, &stacked, &rays);
                let mut tally = Tally::default();
                for (r, g) in rays.iter().zip(got) {
                    let cpu = imp
                        .trace(*combine, r, |hf, q| dda::trace(hf, Surface::Triangles, q))
                        .expect("a valid world ray");
                    tally.add(r, &imp, &cpu, g);
                }
                let label = format!("{name} {frustum:?} {}", combine.name());
                let _ = writeln!(
                    report,
                    "{label:<48} rays {:>5}  agree {:>5} ({:.3} %)  hits {:>5} (ties {}, off \
                     {:.1e})  max |dt| {:.1e}  max |dp| {:.1e} (half sides)  max |dn| {:.1e}  \
                     traces differ {}  fetches differ {}",
                    tally.rays,
                    tally.agree,
                    100.0 * tally.rate(),
                    tally.hits,
                    tally.ties,
                    tally.max_tie,
                    tally.max_dt,
                    tally.max_dp,
                    tally.max_dn,
                    tally.traces_differ,
                    tally.fetches_differ,
                );
                for w in &tally.wrong {
                    let _ = writeln!(report, "    differs: {w}");
                }
                if tally.rate() < MIN_AGREE || tally.hits < tally.rays / 10 {
                    let _ = writeln!(
                        failures,
                        "{label}: {} of {} rays differ ({} hits)",
                        tally.wrong.len(),
                        tally.rays,
                        tally.hits
                    );
                }
            }
        }
    }
    println!("{report}");
    assert!(failures.is_empty(), "WGSL impostors:\n{failures}");
}
