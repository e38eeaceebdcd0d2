//! Six-field impostors in a wgpu RENDER pipeline (lavapipe in CI): the cube proxy drawn,
//! each fragment tracing its pixel's world ray with `hf_trace_impostor`
//! (`hfcast_shaders::impostor` with `depth_output`), discarding a miss and writing
//! `@builtin(frag_depth) = hf_impostor_depth(hit.point)`, against the Rust core.
//!
//! The Stanford bunny (`data/`) captured as six fields of 64² with orthographic and
//! reverse-perspective (`Frustum::DEFAULT_REVERSE`) faces, both combinations, seen by
//! two of `hfcast_tools::impostor::six_views`' pinhole cameras at 64 × 64 pixels. The
//! vertex shader projects the layout's cube (36 vertices, back faces culled) by the
//! camera's view-projection (`view_proj`: clip x, y = the pinhole's sx, sy times the
//! forward distance w, so that the centre of pixel (x, y) is where the pinhole's ray
//! (x, y) crosses; z from [`NEAR`, `FAR`] half sides to [0, 1]), the same matrix the
//! library reads as `hf_view_proj`. The fragment shader builds the ray of its pixel
//! from `@builtin(position)` as `Pinhole::ray` does, in f32, and writes (point, t) to
//! an Rgba32Float target and the face to an R32Uint one; the depth target is
//! Depth32Float, compare Less, cleared to 1. A second pass of the proxy alone (no
//! discard, no frag_depth) writes its own depth: the proxy's coverage.
//!
//! Per case and pixel: (a) the CPU traces the same ray (built with the same f32
//! operations from the same f32 camera vectors) with `Impostor::trace` around the f32
//! DDA; a pixel agrees when hit/miss is the same and, for a hit, the point is within
//! [`REL_TOL`] of the cube's half side and (b) the depth buffer is within [`DEPTH_TOL`]
//! of the CPU point's depth under the same matrix, and for a miss the depth buffer is
//! still 1.0 and the colour targets untouched; at least [`MIN_AGREE`] of the pixels
//! must agree, the others are printed. (c) No GPU hit lies outside the proxy's
//! coverage, every hit lies at or behind the proxy's front face (back faces culled,
//! not front ones), there are covered pixels that stayed at depth 1.0 (the fragment
//! shader discarded them), and the coverage is the set of pixels whose ray meets the
//! cube (f64 slabs) but for at most 1 % of the pixels (centres on its silhouette).
//!
//! Measured on lavapipe (llvmpipe, LLVM 15, Mesa 22.3.6): all 8 × 4096 pixels agree
//! (hit/miss, 597 to 1092 hits a case, the same count on both sides); points within
//! 4.0e-6 half sides; depth buffer within 3.3e-7 of the CPU point's depth, 1.0 at
//! every miss; one hit of 6,297 on another face than the core's (orthographic,
//! intersection, view 4; its point agrees); the proxy covers 2507 and 2287 pixels of
//! the two views, exactly those whose ray meets the cube, of which 1195 to 1910 a
//! case were discarded; no hit outside the coverage or in front of the proxy. The
//! run takes about a second.

mod common;

use common::{bunny, impostor_capture, impostor_layout0, impostor_uniforms, mat4_rows, Gpu};
use hfcast::camera::Pinhole;
use hfcast::impostor::{Combine, Frustum, Impostor, Layout, Mesh};
use hfcast::projective::Mat4;
use hfcast::scene::{MethodKind, Scene};
use hfcast::{dda, HeightField, Query, Surface};
use hfcast_shaders::{wgsl_layout as binding, Lang};
use hfcast_tools::impostor::six_views;
use std::fmt::Write as _;

/// Largest difference of an agreeing hit's world point, relative to the cube's half
/// side.
const REL_TOL: f64 = 1e-4;
/// Largest difference of an agreeing hit's depth buffer value from the depth of the
/// CPU's hit point.
const DEPTH_TOL: f64 = 1e-5;
/// Least share of a case's pixels that must agree.
const MIN_AGREE: f64 = 0.999;
/// The fields' side.
const SIDE: u32 = 64;
/// Pixels across each camera.
const PIXELS: u32 = 64;
/// Which of `six_views` are drawn.
const VIEWS: [usize; 2] = [0, 4];
/// The near and far planes of the projection, in half sides from the eye (the cameras
/// are three half sides from the centre, the cube within √3 of it).
const NEAR: f64 = 0.5;
const FAR: f64 = 6.0;
/// The colour targets' clear values where no fragment wrote.
const CLEAR_FACE: u32 = 7;
const CLEAR_COVER: f64 = -1.0;

/// The entry points appended to the impostor shader: the proxy's vertices, the
/// tracing fragment and the coverage fragment.
const WRAPPER: &str = r#"
// ---- test entry points (shadertest/tests/wgsl_impostor_render.rs)
struct TestCamera {
    eye: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    size: vec4<f32>,      // width, height
    combine: vec4<u32>,   // x: the Combine
}

@group(1) @binding(0) var<uniform> test_camera: TestCamera;

// The cube's 36 corners (bit 0: +x, bit 1: +y, bit 2: +z), counter-clockwise seen
// from outside (TEST_CORNERS, filled in by the test).
@vertex
fn test_vertex(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    var corners = TEST_CORNERS;
    let c: u32 = corners[i];
    let s = vec3<f32>(f32(c & 1u), f32((c >> 1u) & 1u), f32((c >> 2u) & 1u)) * 2.0 - 1.0;
    let cube = impostor_cube();
    return projective_mul(impostor_view_proj(), vec4<f32>(cube.xyz + cube.w * s, 1.0));
}

struct TestFragment {
    @location(0) hit: vec4<f32>, // point, t
    @location(1) face: u32,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn test_fragment(@builtin(position) pos: vec4<f32>) -> TestFragment {
    let px = floor(pos.xy);
    let sx: f32 = 2.0 * (px.x + 0.5) / test_camera.size.x - 1.0;
    let sy: f32 = 1.0 - 2.0 * (px.y + 0.5) / test_camera.size.y;
    let dir = test_camera.forward.xyz + sx * test_camera.right.xyz + sy * test_camera.up.xyz;
    let it = hf_trace_impostor(Query(test_camera.eye.xyz, dir, 0.0, real_infinity()),
                               test_camera.combine.x);
    if (!it.trace.has_hit) {
        discard;
    }
    let p = it.trace.hit.point;
    return TestFragment(vec4<f32>(p, it.trace.hit.t), it.face, hf_impostor_depth(p));
}

@fragment
fn test_cover(@builtin(position) pos: vec4<f32>) -> @location(0) f32 {
    return pos.z;
}
"#;

/// The cube's 36 corner indices (bit k set: + on axis k), two triangles a face,
/// counter-clockwise seen from outside.
fn cube_corners() -> Vec<u32> {
    let mut out = Vec::new();
    for a in 0..3 {
        let (u, v) = (1 << ((a + 1) % 3), 1 << ((a + 2) % 3));
        for s in [0, 1 << a] {
            // e_u × e_v = e_a: this order is counter-clockwise seen from +a.
            let mut q = [s, s | u, s | u | v, s | v];
            if s == 0 {
                q.reverse();
            }
            out.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
        }
    }
    out
}

/// The world-to-clip matrix of `cam` for a cube of half side `half`: clip x, y = the
/// pinhole's sx, sy (the coordinates along right and up over the forward distance)
/// times w = the forward distance, z from [`NEAR`, `FAR`] half sides to [0, 1].
fn view_proj(cam: &Pinhole, half: f64) -> Mat4 {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let row = |v: [f64; 3], s: f64| {
        let r = v.map(|c| c * s);
        [r[0], r[1], r[2], -dot(r, cam.eye)]
    };
    let x = row(cam.right, 1.0 / dot(cam.right, cam.right));
    let y = row(cam.up, 1.0 / dot(cam.up, cam.up));
    let w = row(cam.forward, 1.0);
    let (n, f) = (NEAR * half, FAR * half);
    let a = f / (f - n);
    let z = [a * w[0], a * w[1], a * w[2], a * w[3] - a * n];
    [x, y, z, w]
}

/// `m` (rounded to f32, as the shader holds it) applied to the point `p`: its depth.
fn depth_of(m: &[f32; 16], p: [f32; 3]) -> f64 {
    let v = [f64::from(p[0]), f64::from(p[1]), f64::from(p[2]), 1.0];
    let r = |k: usize| (0..4).map(|j| f64::from(m[4 * k + j]) * v[j]).sum::<f64>();
    r(2) / r(3)
}

/// The f32 ray of pixel (x, y), the fragment shader's operations in the same order.
fn pixel_ray(cam: &Pinhole, x: u32, y: u32) -> Query<f32> {
    let f = |v: [f64; 3]| v.map(|c| c as f32);
    let (eye, fw, r, u) = (f(cam.eye), f(cam.forward), f(cam.right), f(cam.up));
    let sx = 2.0 * (x as f32 + 0.5) / cam.width as f32 - 1.0;
    let sy = 1.0 - 2.0 * (y as f32 + 0.5) / cam.height as f32;
    let d = [0, 1, 2].map(|k| fw[k] + sx * r[k] + sy * u[k]);
    Query::from_arrays(eye, d, 0.0, f32::INFINITY).expect("a pixel ray")
}

/// Whether the ray `r` meets the cube of `layout` (slabs in f64).
fn meets_cube(layout: &Layout, r: &Query<f32>) -> bool {
    let (o, d) = (r.origin(), r.dir());
    let (c, h) = (layout.center(), layout.half());
    let (mut t0, mut t1) = (0f64, f64::INFINITY);
    for k in 0..3 {
        let (o, d) = (f64::from(o[k]), f64::from(d[k]));
        let (a, b) = ((c[k] - h - o) / d, (c[k] + h - o) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

/// The render pipelines and their bind group layouts.
struct Renderer {
    trace: wgpu::RenderPipeline,
    cover: wgpu::RenderPipeline,
    layout0: wgpu::BindGroupLayout,
    layout1: wgpu::BindGroupLayout,
}

fn entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty,
        count: None,
    }
}

const UNIFORM: wgpu::BindingType = wgpu::BindingType::Buffer {
    ty: wgpu::BufferBindingType::Uniform,
    has_dynamic_offset: false,
    min_binding_size: None,
};

const HIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const FACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const COVER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

impl Renderer {
    fn new(gpu: &Gpu) -> Renderer {
        let scene = Scene {
            depth_output: true,
            ..Scene::general(MethodKind::Exact, Surface::Triangles)
        };
        let corners: Vec<String> = cube_corners().iter().map(|c| format!("{c}u")).collect();
        let src = hfcast_shaders::impostor(&scene, Lang::Wgsl).expect("the impostor shader")
            + &format!(
                "\nconst TEST_CORNERS = array<u32, 36>({});\n",
                corners.join(", ")
            )
            + WRAPPER;
        let dev = &gpu.device;
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("impostor render"),
            source: wgpu::ShaderSource::Wgsl(src.as_str().into()),
        });
        let layout0 = impostor_layout0(dev, wgpu::ShaderStages::VERTEX_FRAGMENT, true);
        let layout1 = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[entry(0, UNIFORM)],
        });
        let pipeline_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout0), Some(&layout1)],
            immediate_size: 0,
        });
        let pipeline = |fragment: &str, targets: &[Option<wgpu::ColorTargetState>], depth| {
            dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(fragment),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("test_vertex"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: Some(wgpu::Face::Back),
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: depth,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let trace = pipeline(
            "test_fragment",
            &[Some(HIT_FORMAT.into()), Some(FACE_FORMAT.into())],
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
        );
        let cover = pipeline("test_cover", &[Some(COVER_FORMAT.into())], None);
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("wgpu refused the impostor render shader or pipelines: {e}");
        }
        Renderer {
            trace,
            cover,
            layout0,
            layout1,
        }
    }
}

/// A `PIXELS²` render target of `format` that can be copied out.
fn target(gpu: &Gpu, format: wgpu::TextureFormat) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: extent(),
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

fn extent() -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: PIXELS,
        height: PIXELS,
        depth_or_array_layers: 1,
    }
}

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor::default())
}

fn clear_to(v: f64) -> wgpu::Operations<wgpu::Color> {
    wgpu::Operations {
        load: wgpu::LoadOp::Clear(wgpu::Color {
            r: v,
            g: v,
            b: v,
            a: v,
        }),
        store: wgpu::StoreOp::Store,
    }
}

/// The words of `tex` (`words` 32-bit words a pixel, row 0 at the top), read back.
fn read_texture(gpu: &Gpu, tex: &wgpu::Texture, words: u32) -> Vec<u32> {
    let row = 4 * words * PIXELS;
    assert_eq!(row % wgpu::COPY_BYTES_PER_ROW_ALIGNMENT, 0);
    let size = u64::from(row * PIXELS);
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: tex,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(PIXELS),
            },
        },
        extent(),
    );
    gpu.queue.submit([enc.finish()]);
    staging.map_async(wgpu::MapMode::Read, .., |r| r.expect("map the texture"));
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("wait for the GPU");
    let words: Vec<u32> = staging
        .get_mapped_range(..)
        .expect("mapped texture")
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    staging.unmap();
    words
}

/// The bind group entry of the buffer `b` at `binding`.
fn buffer(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

/// What one draw left: per pixel, (point, t), face, depth buffer, the proxy's depth
/// (the coverage pass; [`CLEAR_COVER`] where it drew nothing).
struct Frame {
    hit: Vec<[f32; 4]>,
    face: Vec<u32>,
    depth: Vec<f32>,
    cover: Vec<f32>,
}

impl Renderer {
    /// Draws the proxy of `imp` (fields `stacked`) seen by `cam` with `combine`, and
    /// the proxy alone, and reads the targets back.
    fn draw(
        &self,
        gpu: &Gpu,
        imp: &Impostor,
        stacked: &[f32],
        cam: &Pinhole,
        vp: &[f32; 16],
        combine: Combine,
    ) -> Frame {
        let dev = &gpu.device;
        let heights = gpu.heights_texture(SIDE, 6 * SIDE, stacked);
        let [field, ranges, params] = impostor_uniforms(gpu, imp, SIDE);
        let vp_buf = gpu.uniform(&common::f32_bytes(vp));
        let f = |v: [f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0];
        let mut camera: Vec<f32> = [cam.eye, cam.forward, cam.right, cam.up]
            .into_iter()
            .flat_map(f)
            .collect();
        camera.extend([cam.width as f32, cam.height as f32, 0.0, 0.0]);
        let mut camera = common::f32_bytes(&camera);
        camera.extend(common::u32_bytes(&[combine as u32, 0, 0, 0]));
        let camera = gpu.uniform(&camera);
        let group0 = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout0,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: binding::HEIGHTS,
                    resource: wgpu::BindingResource::TextureView(&heights),
                },
                buffer(binding::FIELD, &field),
                buffer(binding::FIELD_RANGES, &ranges),
                buffer(binding::IMPOSTOR, &params),
                buffer(binding::VIEW_PROJ, &vp_buf),
            ],
        });
        let group1 = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout1,
            entries: &[buffer(0, &camera)],
        });
        let (hit, face) = (target(gpu, HIT_FORMAT), target(gpu, FACE_FORMAT));
        let (depth, cover) = (target(gpu, DEPTH_FORMAT), target(gpu, COVER_FORMAT));
        let (hit_v, face_v, depth_v, cover_v) =
            (view(&hit), view(&face), view(&depth), view(&cover));
        let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("trace"),
                color_attachments: &[
                    Some(wgpu::RenderPassColorAttachment {
                        view: &hit_v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: clear_to(0.0),
                    }),
                    Some(wgpu::RenderPassColorAttachment {
                        view: &face_v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: clear_to(f64::from(CLEAR_FACE)),
                    }),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_v,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.trace);
            pass.set_bind_group(0, &group0, &[]);
            pass.set_bind_group(1, &group1, &[]);
            pass.draw(0..36, 0..1);
        }
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("cover"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &cover_v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: clear_to(CLEAR_COVER),
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.cover);
            pass.set_bind_group(0, &group0, &[]);
            pass.set_bind_group(1, &group1, &[]);
            pass.draw(0..36, 0..1);
        }
        gpu.queue.submit([enc.finish()]);
        let floats = |w: Vec<u32>| w.into_iter().map(f32::from_bits).collect::<Vec<f32>>();
        Frame {
            hit: floats(read_texture(gpu, &hit, 4))
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
            face: read_texture(gpu, &face, 1),
            depth: floats(read_texture(gpu, &depth, 1)),
            cover: floats(read_texture(gpu, &cover, 1)),
        }
    }
}

/// How one case's pixels compare.
#[derive(Default)]
struct Tally {
    pixels: u64,
    agree: u64,
    hits: u64,
    covered: u64,
    discarded: u64,
    outside: u64,
    in_front: u64,
    face_differs: u64,
    /// Pixels whose ray meets the cube (f64 slabs) where the proxy drew nothing, or
    /// the other way round (pixel centres on the silhouette's edge).
    cover_differs: u64,
    max_dp: f64,
    max_dz: f64,
    wrong: Vec<String>,
}

#[test]
fn wgsl_impostor_render_pipeline_matches_the_rust_core_pixel_by_pixel() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let renderer = Renderer::new(&gpu);
    let (pos, tri) = bunny();
    let mesh = Mesh::new(&pos, &tri).expect("a mesh");
    let mut report = String::new();
    let mut failures = String::new();
    for frustum in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
        let layout = Layout::around(&mesh, frustum).expect("a layout");
        let stacked = impostor_capture(&mesh, &layout, SIDE);
        let n = (SIDE * SIDE) as usize;
        let fields = core::array::from_fn(|k| {
            HeightField::new(&stacked[k * n..(k + 1) * n], SIDE, SIDE, SIDE as usize)
                .expect("a field")
        });
        let imp = Impostor::new(layout, fields).expect("an impostor");
        let half = layout.half();
        let cams = six_views(&layout, PIXELS);
        for combine in Combine::ALL {
            for &v in &VIEWS {
                let cam = &cams[v];
                let vp: Vec<f32> = mat4_rows(&view_proj(cam, half)).collect();
                let vp: [f32; 16] = vp.try_into().expect("16 entries");
                let frame = renderer.draw(&gpu, &imp, &stacked, cam, &vp, combine);
                let mut t = Tally::default();
                for y in 0..PIXELS {
                    for x in 0..PIXELS {
                        let k = (y * PIXELS + x) as usize;
                        let r = pixel_ray(cam, x, y);
                        let cpu = imp
                            .trace(combine, &r, |hf, q| dda::trace(hf, Surface::Triangles, q))
                            .expect("a valid world ray");
                        let (g, face, depth) = (frame.hit[k], frame.face[k], frame.depth[k]);
                        let covered = frame.cover[k] != CLEAR_COVER as f32;
                        let gpu_hit = face != CLEAR_FACE;
                        t.pixels += 1;
                        t.covered += u64::from(covered);
                        t.discarded += u64::from(covered && depth == 1.0);
                        t.outside += u64::from(gpu_hit && !covered);
                        t.in_front += u64::from(gpu_hit && covered && frame.cover[k] <= depth);
                        t.cover_differs += u64::from(meets_cube(&layout, &r) != covered);
                        let ok = match cpu.trace.hit {
                            None => !gpu_hit && depth == 1.0 && g == [0.0; 4],
                            Some(h) if gpu_hit && face < 6 => {
                                let p = h.point.to_array();
                                let dp = (0..3)
                                    .map(|i| (f64::from(g[i]) - f64::from(p[i])).abs() / half)
                                    .fold(0.0, f64::max);
                                let dz = (f64::from(depth) - depth_of(&vp, p)).abs();
                                let ok = dp <= REL_TOL && dz <= DEPTH_TOL;
                                if ok {
                                    t.hits += 1;
                                    t.max_dp = t.max_dp.max(dp);
                                    t.max_dz = t.max_dz.max(dz);
                                    t.face_differs +=
                                        u64::from(cpu.face.map_or(6, |f| f as u32) != face);
                                }
                                ok
                            }
                            Some(_) => false,
                        };
                        if ok {
                            t.agree += 1;
                        } else {
                            t.wrong.push(format!(
                                "pixel ({x}, {y}): cpu {:?} face {:?} depth {:?}; gpu {g:?} \
                                 face {face} depth {depth} covered {covered}",
                                cpu.trace.hit.map(|h| h.point.to_array()),
                                cpu.face,
                                cpu.trace.hit.map(|h| depth_of(&vp, h.point.to_array())),
                            ));
                        }
                    }
                }
                let gpu_hits = frame.face.iter().filter(|&&f| f != CLEAR_FACE).count() as u64;
                let rate = t.agree as f64 / t.pixels as f64;
                let label = format!("bunny {frustum:?} {} view {v}", combine.name());
                let _ = writeln!(
                    report,
                    "{label:<52} pixels {}  agree {} ({:.3} %)  hits {} (gpu {})  max |dp| \
                     {:.1e} (half sides)  max |ddepth| {:.1e}  faces differ {}  covered {} (differing \
                     from the rays' cube {})  discarded {}  hits outside {}  hits at or behind the proxy {}",
                    t.pixels,
                    t.agree,
                    100.0 * rate,
                    t.hits,
                    gpu_hits,
                    t.max_dp,
                    t.max_dz,
                    t.face_differs,
                    t.covered,
                    t.cover_differs,
                    t.discarded,
                    t.outside,
                    t.in_front,
                );
                for w in &t.wrong {
                    let _ = writeln!(report, "    differs: {w}");
                }
                if rate < MIN_AGREE
                    || t.hits < t.pixels / 20
                    || t.outside > 0
                    || t.discarded == 0
                    || t.in_front < gpu_hits
                    || t.cover_differs > t.pixels / 100
                {
                    let _ = writeln!(
                        failures,
                        "{label}: {} of {} pixels differ ({} hits), {} hits outside the \
                         proxy, {} discarded, {} of {gpu_hits} hits at or behind the proxy, coverage \
                         differs from the rays' cube on {}",
                        t.wrong.len(),
                        t.pixels,
                        t.hits,
                        t.outside,
                        t.discarded,
                        t.in_front,
                        t.cover_differs
                    );
                }
            }
        }
    }
    println!("{report}");
    assert!(failures.is_empty(), "WGSL impostor render:\n{failures}");
}
