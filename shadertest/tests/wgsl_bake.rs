//! The GPU bakes (`shaders/wgsl/bake_*.wgsl`, issue 27) executed through wgpu
//! (lavapipe in CI) against the core's CPU bakes, byte for byte, on every map of
//! `../shared/data`, the bundled map and synthetic fields (one of odd sizes with
//! negative heights and signed zeros):
//! - the maximum mipmap, baked whole, then refreshed after edits of sub-rectangles (a
//!   crater over about 1 %, 10 % and 100 % of the field, and one sample at a corner;
//!   also on a 4096² fractal),
//!   each update dispatched over the texels that depend on the edit only
//!   (`hfcast_shaders::bake::maxmip_update_passes`);
//! - the N-buffers of the cylinder–cone bake, for a short and the longest cone reach;
//! - the safety distances for every ray, directional and isotropic (positive), and the
//!   cylinder–cone shapes with N-buffer slopes (on the GPU's own N-buffers), in 64-bit
//!   floats (the device must have SHADER_F64: lavapipe has).
//!
//! Output buffers start as NaN bits, so an element no pass writes shows. Times are
//! printed (lavapipe: software figures) beside the CPU's.

mod common;

use common::{spiky_fractal, Gpu};
use hfcast::maxmip;
use hfcast::safety;
use hfcast::safety::cc;
use hfcast::HeightField;
use hfcast_shaders::bake::{
    cc_bake_passes, maxmip_bake_passes, maxmip_update_passes, nbuffer_bake_passes,
    safety_bake_passes,
};
use hfcast_shaders::{wgsl_layout as binding, Lang};
use std::time::Instant;

/// Bits the pyramid buffer starts with: a NaN no bake writes.
const POISON: u32 = 0x7fc0_dead;

/// A bake pipeline, its bind group layout and its bindings (output, pass uniform).
struct Bake {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    out: u32,
    pass: u32,
}

/// One dispatch: the pass uniform's bytes, the workgroups along x and y, and the
/// part of the output it binds (byte offset and size; `None`: all of it).
type Dispatch = (Vec<u8>, [u32; 2], Option<(u64, u64)>);

impl Bake {
    /// The bake `stem` (`bake_maxmip`, …) with entry point `entry`, writing the storage
    /// buffer at binding `out`, reading its pass uniform at `pass`.
    fn new(gpu: &Gpu, stem: &str, entry: &str, out: u32, pass: u32) -> Bake {
        let dev = &gpu.device;
        let src = hfcast_shaders::file(Lang::Wgsl, stem).expect("a bake");
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(stem),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        let layout_entry = |b: u32, ty| wgpu::BindGroupLayoutEntry {
            binding: b,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[
                layout_entry(
                    binding::HEIGHTS,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                layout_entry(
                    out,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                layout_entry(
                    pass,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
            ],
        });
        let pipeline_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(stem),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("{stem}: wgpu refused the shader or pipeline: {e}");
        }
        Bake {
            pipeline,
            layout,
            out,
            pass,
        }
    }

    /// The maximum-mipmap bake.
    fn maxmip(gpu: &Gpu) -> Bake {
        let b = (binding::PYRAMID_OUT, binding::MAXMIP_PASS);
        Bake::new(gpu, "bake_maxmip", "maxmip_bake_pass", b.0, b.1)
    }

    /// The N-buffer bake.
    fn nbuffer(gpu: &Gpu) -> Bake {
        let b = (binding::NBUFFER, binding::NBUFFER_PASS);
        Bake::new(gpu, "bake_nbuffer", "nbuffer_bake_pass", b.0, b.1)
    }

    /// Runs `passes` over `heights` (a `w × h` texture) into `out`, one compute pass
    /// each, and waits for them.
    fn run(&self, gpu: &Gpu, heights: &wgpu::TextureView, out: &wgpu::Buffer, passes: &[Dispatch]) {
        let dev = &gpu.device;
        let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        for (bytes, workgroups, range) in passes {
            let uniform = gpu.uniform(bytes);
            let bound = match *range {
                None => out.as_entire_binding(),
                Some((offset, size)) => wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: out,
                    offset,
                    size: std::num::NonZeroU64::new(size),
                }),
            };
            let group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: binding::HEIGHTS,
                        resource: wgpu::BindingResource::TextureView(heights),
                    },
                    wgpu::BindGroupEntry {
                        binding: self.out,
                        resource: bound,
                    },
                    wgpu::BindGroupEntry {
                        binding: self.pass,
                        resource: uniform.as_entire_binding(),
                    },
                ],
            });
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(workgroups[0], workgroups[1], 1);
        }
        gpu.queue.submit([enc.finish()]);
        dev.poll(wgpu::PollType::wait_indefinitely())
            .expect("wait for the bake");
    }

    /// [`Bake::run`], timed; then the output's first difference from `want`, if any.
    fn run_and_compare(
        &self,
        gpu: &Gpu,
        heights: &wgpu::TextureView,
        out: &wgpu::Buffer,
        passes: &[Dispatch],
        want: &[f32],
    ) -> (f64, Option<String>) {
        let t0 = Instant::now();
        self.run(gpu, heights, out, passes);
        let ms = 1e3 * t0.elapsed().as_secs_f64();
        let got = gpu.read_u32(out, want.len());
        (ms, first_difference(&got, &bits(want)))
    }
}

/// The dispatches of maximum-mipmap passes.
fn dispatches(passes: &[hfcast_shaders::bake::MaxMipPass]) -> Vec<Dispatch> {
    passes
        .iter()
        .map(|p| (p.uniform_bytes(), p.workgroups, None))
        .collect()
}

/// A field to bake: name, size, heights.
struct Field {
    name: String,
    w: u32,
    h: u32,
    heights: Vec<f32>,
}

/// The fields: every map of ../shared/data, the bundled map, a spiky fractal and an
/// odd-sized field of negative heights and signed zeros.
fn fields() -> Vec<Field> {
    let mut out = Vec::new();
    let mut paths: Vec<_> = hfcast_tools::maps::list_maps()
        .into_iter()
        .map(|m| (m.name, m.path))
        .collect();
    paths.push(("bundled".into(), hfcast_tools::maps::bundled_map()));
    for (name, path) in paths {
        let map = hfcast_tools::maps::load_map(&path, None)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        out.push(Field {
            name,
            w: map.width,
            h: map.height,
            heights: map.heights,
        });
    }
    out.push(Field {
        name: "spiky fractal 301 x 173".into(),
        w: 301,
        h: 173,
        heights: spiky_fractal(5, 301, 173, 40.0),
    });
    let (w, h) = (37u32, 19u32);
    let signed: Vec<f32> = (0..w * h)
        .map(|k| match k % 7 {
            0 => 0.0,
            1 => -0.0,
            2 => -3.5,
            3 => f32::MIN_POSITIVE,
            _ => ((k * 37 % 101) as f32 - 50.0) * 0.25,
        })
        .collect();
    out.push(Field {
        name: "negative and signed zeros 37 x 19".into(),
        w,
        h,
        heights: signed,
    });
    out
}

/// The bits of `v`.
fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The first texel where `got` and `want` differ, as a message.
fn first_difference(got: &[u32], want: &[u32]) -> Option<String> {
    let k = got.iter().zip(want).position(|(a, b)| a != b)?;
    Some(format!(
        "texel {k} of {}: gpu {:#010x} ({}), cpu {:#010x} ({})",
        want.len(),
        got[k],
        f32::from_bits(got[k]),
        want[k],
        f32::from_bits(want[k])
    ))
}

/// `heights` with a crater of radius `r` (samples) at `(cx, cy)` sunk into it, and the
/// rectangle of samples it changed, `[x0, y0, x1, y1]`.
fn crater(f: &Field, heights: &mut [f32], cx: u32, cy: u32, r: u32) -> [u32; 4] {
    let rect = [
        cx.saturating_sub(r),
        cy.saturating_sub(r),
        (cx + r + 1).min(f.w),
        (cy + r + 1).min(f.h),
    ];
    for j in rect[1]..rect[3] {
        for i in rect[0]..rect[2] {
            let d = (f64::from(i) - f64::from(cx)).hypot(f64::from(j) - f64::from(cy));
            let k = (j * f.w + i) as usize;
            heights[k] -= (1.0 + f64::from(r) - d).max(0.0) as f32 * 0.5;
        }
    }
    rect
}

#[test]
fn gpu_maximum_mipmap_is_the_cpu_one_byte_for_byte() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let bake = Bake::maxmip(&gpu);
    let mut failures = Vec::new();
    // And a 4096² field: the update costs of the issue (1 %, 10 %, 100 % of it).
    let big = Field {
        name: "spiky fractal 4096 x 4096".into(),
        w: 4096,
        h: 4096,
        heights: spiky_fractal(9, 4096, 4096, 40.0),
    };
    for f in fields().into_iter().chain([big]) {
        let hf = HeightField::new(&f.heights, f.w, f.h, f.w as usize).expect("field");
        let n = maxmip::pyramid_len(f.w, f.h);
        let t0 = Instant::now();
        let mut want = vec![0f32; n];
        maxmip::bake(&hf, &mut want).expect("cpu bake");
        let cpu_ms = 1e3 * t0.elapsed().as_secs_f64();
        let pyramid = gpu.storage(&vec![POISON; n]);
        let tex = gpu.heights_texture(f.w, f.h, &f.heights);
        let passes = dispatches(&maxmip_bake_passes(f.w, f.h).expect("passes"));
        let (gpu_ms, whole) = bake.run_and_compare(&gpu, &tex, &pyramid, &passes, &want);
        println!(
            "{:<40} {:>5} x {:<5} {:>9} texels, {:>2} passes: cpu {cpu_ms:7.1} ms, gpu (software) {gpu_ms:7.1} ms  {}",
            f.name,
            f.w,
            f.h,
            n,
            passes.len(),
            whole.as_deref().unwrap_or("identical")
        );
        if let Some(d) = whole {
            failures.push(format!("{}: whole bake: {d}", f.name));
            continue;
        }
        // Edits: craters of about 1 %, 10 % and 100 % of the field, and one corner
        // sample; each refreshes the GPU pyramid in place from the edited texture.
        let mut heights = f.heights.clone();
        let side = f.w.min(f.h);
        let edits = [
            (f.w / 3, f.h / 2, side / 20),
            (2 * f.w / 3, f.h / 3, side / 6),
            (f.w / 2, f.h / 2, f.w.max(f.h)),
            (f.w - 1, f.h - 1, 0),
        ];
        for (cx, cy, r) in edits {
            let rect = crater(&f, &mut heights, cx, cy, r);
            let hf = HeightField::new(&heights, f.w, f.h, f.w as usize).expect("field");
            let [x0, y0, x1, y1] = rect;
            let t0 = Instant::now();
            maxmip::update_rect(&hf, &mut want, x0, y0, x1, y1).expect("cpu update");
            let cpu_ms = 1e3 * t0.elapsed().as_secs_f64();
            let tex = gpu.heights_texture(f.w, f.h, &heights);
            let update = maxmip_update_passes(f.w, f.h, rect).expect("update passes");
            let texels: u32 = update
                .iter()
                .map(|p| (p.uniform[8] - p.uniform[6]) * (p.uniform[9] - p.uniform[7]))
                .sum();
            let passes = dispatches(&update);
            let (gpu_ms, diff) = bake.run_and_compare(&gpu, &tex, &pyramid, &passes, &want);
            println!(
                "    update of {} x {} samples: {texels} texels rewritten ({:.1} % of the pyramid), cpu {cpu_ms:.2} ms, gpu (software) {gpu_ms:.1} ms  {}",
                x1 - x0,
                y1 - y0,
                100.0 * f64::from(texels) / n as f64,
                diff.as_deref().unwrap_or("identical")
            );
            if let Some(d) = diff {
                failures.push(format!("{}: update {rect:?}: {d}", f.name));
            }
        }
        // And the CPU update equals a whole CPU bake of the edited field.
        let hf = HeightField::new(&heights, f.w, f.h, f.w as usize).expect("field");
        let mut again = vec![0f32; n];
        maxmip::bake(&hf, &mut again).expect("cpu bake");
        if bits(&again) != bits(&want) {
            failures.push(format!("{}: cpu update differs from a whole bake", f.name));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn gpu_nbuffers_are_the_cpu_ones_byte_for_byte() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let bake = Bake::nbuffer(&gpu);
    let mut failures = Vec::new();
    let mut baked = 0;
    for f in fields() {
        let hf = HeightField::new(&f.heights, f.w, f.h, f.w as usize).expect("field");
        // A cone reach of 6 columns (4 levels) and the longest, 255 (10 levels).
        for cap in [6u8, 255] {
            let n = cc::nbuffer_len(f.w, f.h, cap);
            let t0 = Instant::now();
            let mut want = vec![0f32; n];
            cc::prepare_nbuffer(&hf, cap, &mut want).expect("cpu n-buffers");
            let cpu_ms = 1e3 * t0.elapsed().as_secs_f64();
            let out = gpu.storage(&vec![POISON; n]);
            let tex = gpu.heights_texture(f.w, f.h, &f.heights);
            let passes: Vec<Dispatch> = nbuffer_bake_passes(f.w, f.h, cap)
                .expect("passes")
                .iter()
                .map(|p| {
                    assert!(
                        p.bind_size <= limit,
                        "{}: a pass binds over {limit} bytes",
                        f.name
                    );
                    (
                        p.uniform_bytes(),
                        p.workgroups,
                        Some((p.bind_offset, p.bind_size)),
                    )
                })
                .collect();
            let (gpu_ms, diff) = bake.run_and_compare(&gpu, &tex, &out, &passes, &want);
            println!(
                "{:<40} {:>5} x {:<5} cap {cap:>3}: {n:>9} floats, {:>2} passes: cpu {cpu_ms:7.1} ms, gpu (software) {gpu_ms:7.1} ms  {}",
                f.name,
                f.w,
                f.h,
                passes.len(),
                diff.as_deref().unwrap_or("identical")
            );
            if let Some(d) = diff {
                failures.push(format!("{} cap {cap}: {d}", f.name));
            }
            baked += 1;
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(baked >= 20, "{baked} bakes");
}

/// The GPU safety-distance or cylinder–cone bake (two passes: strip bounds, then the
/// map) into `out` (the map's words), with its scratch; timed.
struct SafetyBake {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl SafetyBake {
    /// The entry point `entry` of bake_safety.wgsl (`safety_bake_pass`, `cc_bake_pass`).
    fn new(gpu: &Gpu, entry: &str) -> SafetyBake {
        let dev = &gpu.device;
        let src = hfcast_shaders::file(Lang::Wgsl, "bake_safety").expect("bake_safety.wgsl");
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("bake_safety"),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("bake_safety"),
            layout: None,
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("bake_safety: wgpu refused the shader or pipeline: {e}");
        }
        let layout = pipeline.get_bind_group_layout(0);
        SafetyBake { pipeline, layout }
    }

    /// Bakes `f` with `passes` (reading the N-buffers `nb`, for the cylinder–cone
    /// bake) and returns the map's bytes (`len` of them) and the time.
    fn run(
        &self,
        gpu: &Gpu,
        f: &Field,
        passes: &[hfcast_shaders::bake::BakePass],
        len: usize,
        nb: Option<&wgpu::Buffer>,
    ) -> (Vec<u8>, f64) {
        let dev = &gpu.device;
        let tex = gpu.heights_texture(f.w, f.h, &f.heights);
        let scratch = gpu.storage(&vec![POISON; (passes[0].bind_size / 4) as usize]);
        let words = (passes[1].bind_size / 4) as usize;
        let out = gpu.storage(&vec![POISON; words]);
        let t0 = Instant::now();
        let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        for p in passes {
            let uniform = gpu.uniform(&p.uniform_bytes());
            let mut entries = vec![
                wgpu::BindGroupEntry {
                    binding: binding::HEIGHTS,
                    resource: wgpu::BindingResource::TextureView(&tex),
                },
                wgpu::BindGroupEntry {
                    binding: binding::SAFETY_SCRATCH,
                    resource: scratch.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: binding::SAFETY_OUT,
                    resource: out.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: binding::SAFETY_PASS,
                    resource: uniform.as_entire_binding(),
                },
            ];
            if let Some(nb) = nb {
                entries.push(wgpu::BindGroupEntry {
                    binding: binding::NBUFFER,
                    resource: nb.as_entire_binding(),
                });
            }
            let group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.layout,
                entries: &entries,
            });
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(p.workgroups[0], p.workgroups[1], 1);
        }
        gpu.queue.submit([enc.finish()]);
        dev.poll(wgpu::PollType::wait_indefinitely())
            .expect("wait for the bake");
        let ms = 1e3 * t0.elapsed().as_secs_f64();
        let bytes: Vec<u8> = gpu
            .read_u32(&out, words)
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect();
        (bytes[..len].to_vec(), ms)
    }
}

#[test]
fn gpu_safety_distances_are_the_cpu_ones_byte_for_byte() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    assert!(
        gpu.device.features().contains(wgpu::Features::SHADER_F64),
        "the safety-distance bake needs 64-bit floats (SHADER_F64): lavapipe has them"
    );
    let bake = SafetyBake::new(&gpu, "safety_bake_pass");
    let mut failures = Vec::new();
    let mut baked = 0;
    let variants = [
        ("directional", safety::Variant::Directional, false),
        ("isotropic, positive", safety::Variant::Isotropic, true),
    ];
    for f in fields() {
        let hf = HeightField::new(&f.heights, f.w, f.h, f.w as usize).expect("field");
        for (name, variant, positive) in variants {
            let opts = safety::Options {
                variant,
                positive,
                cap: u8::MAX,
            };
            let t0 = Instant::now();
            let mut scratch = vec![0f32; safety::scratch_len(f.w, f.h)];
            let mut want = vec![0u8; safety::map_len(f.w, f.h, variant)];
            safety::bake(&hf, &mut scratch, opts, &mut want).expect("cpu bake");
            let cpu_ms = 1e3 * t0.elapsed().as_secs_f64();
            let iso = variant == safety::Variant::Isotropic;
            let passes = safety_bake_passes(f.w, f.h, iso, opts.cap, positive).expect("passes");
            let (got, gpu_ms) = bake.run(&gpu, &f, &passes, want.len(), None);
            let diff = got.iter().zip(&want).position(|(a, b)| a != b);
            println!(
                "{:<40} {:>5} x {:<5} {name:<20} {:>9} bytes: cpu {cpu_ms:8.1} ms, gpu (software) {gpu_ms:8.1} ms  {}",
                f.name,
                f.w,
                f.h,
                want.len(),
                diff.map_or("identical".to_string(), |k| format!(
                    "DIFFERS at byte {k} of {}: gpu {}, cpu {}",
                    want.len(),
                    got[k],
                    want[k]
                ))
            );
            if let Some(k) = diff {
                failures.push(format!("{} {name}: byte {k}", f.name));
            }
            baked += 1;
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(baked >= 20, "{baked} bakes");
}

#[test]
fn gpu_cylinder_cones_with_nbuffer_slopes_are_the_cpu_ones_byte_for_byte() {
    let gpu = Gpu::new();
    println!("{}", gpu.describe());
    assert!(
        gpu.device.features().contains(wgpu::Features::SHADER_F64),
        "the cylinder-cone bake needs 64-bit floats (SHADER_F64): lavapipe has them"
    );
    let nbuffers = Bake::nbuffer(&gpu);
    let bake = SafetyBake::new(&gpu, "cc_bake_pass");
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let mut failures = Vec::new();
    let mut baked = 0;
    for f in fields() {
        // The cc pass binds the N-buffers whole: a field whose N-buffers exceed the
        // device's binding limit (the world DEM on lavapipe's 128 MiB) is baked on its
        // largest top-left crop of half sides that fits.
        let fits = |f: &Field| 4 * cc::nbuffer_len(f.w, f.h, 64) as u64 <= limit;
        let mut f = f;
        while !fits(&f) {
            let (w, h) = (f.w / 2, f.h / 2);
            let heights = (0..h)
                .flat_map(|j| f.heights[(j * f.w) as usize..][..w as usize].to_vec())
                .collect();
            f = Field {
                name: format!("{} (crop {w} x {h})", f.name),
                w,
                h,
                heights,
            };
        }
        let hf = HeightField::new(&f.heights, f.w, f.h, f.w as usize).expect("field");
        for cap in [6u8, 64] {
            let n = cc::nbuffer_len(f.w, f.h, cap);
            let opts = cc::CcOptions {
                slope: cc::Slope::NBuffer,
                cap,
            };
            let t0 = Instant::now();
            let mut scratch = vec![0f32; safety::scratch_len(f.w, f.h)];
            let mut nb_cpu = vec![0f32; n];
            let mut want = vec![0u8; cc::map_len(f.w, f.h)];
            cc::bake(&hf, &mut scratch, &mut nb_cpu, opts, &mut want).expect("cpu bake");
            let cpu_ms = 1e3 * t0.elapsed().as_secs_f64();
            let t0 = Instant::now();
            let nb = gpu.storage(&vec![POISON; n]);
            let tex = gpu.heights_texture(f.w, f.h, &f.heights);
            let fill: Vec<Dispatch> = nbuffer_bake_passes(f.w, f.h, cap)
                .expect("n-buffer passes")
                .iter()
                .map(|p| {
                    (
                        p.uniform_bytes(),
                        p.workgroups,
                        Some((p.bind_offset, p.bind_size)),
                    )
                })
                .collect();
            nbuffers.run(&gpu, &tex, &nb, &fill);
            let passes = cc_bake_passes(f.w, f.h, cap).expect("passes");
            let (got, _) = bake.run(&gpu, &f, &passes, want.len(), Some(&nb));
            let gpu_ms = 1e3 * t0.elapsed().as_secs_f64();
            let diff = got.iter().zip(&want).position(|(a, b)| a != b);
            println!(
                "{:<40} {:>5} x {:<5} cap {cap:>3} {:>9} bytes: cpu {cpu_ms:8.1} ms, gpu (software) {gpu_ms:8.1} ms  {}",
                f.name,
                f.w,
                f.h,
                want.len(),
                diff.map_or("identical".to_string(), |k| format!(
                    "DIFFERS at byte {k} (texel-class {}, {}): gpu {}, cpu {}",
                    k / 2,
                    if k % 2 == 0 { "r" } else { "s" },
                    got[k],
                    want[k]
                ))
            );
            if let Some(k) = diff {
                failures.push(format!("{} cap {cap}: byte {k}", f.name));
            }
            baked += 1;
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(baked >= 24, "{baked} bakes");
}
