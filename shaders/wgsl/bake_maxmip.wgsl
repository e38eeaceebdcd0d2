// The maximum mipmap baked on the GPU (issue 27; Tevs et al. 2008, §3.1): mirror of
// core/src/maxmip.rs `bake_rows` (a whole bake) and `update_rect` (a sub-rectangle of
// edited samples). A compute shader, not part of any march: one dispatch of
// `maxmip_bake_pass` per level, finest first, each over that level's texels
// [lo, hi) (the whole level for a bake, `Layout::update_ranges` for an update), in
// workgroups of 8 x 8 texels, into the pyramid buffer in the core's `Layout` (level l
// from texel `offset(l)`, row-major). Level 0 reads the heights: a cell's texel is the
// maximum of its four corners. A coarser level reads the finer one: the maximum of its
// 2 x 2 children, or of the last column's two at an odd width (rows clamp to the last
// at an odd height). The maxima are taken in the core's order with its
// `a > b ? a : b`, so the bytes equal the CPU bake's (signed zeros too; a GPU that
// flushes subnormal heights to zero may compare those as zero). The GLSL 4.30 compute
// port (glsl/bake_maxmip.glsl) is generated from this file; its `main` is the entry.
//#glsl
// #version 430 core
//#end

// One pass: the level, where it and the finer level lie in `hf_pyramid_out`, and the
// texels it writes. 48 bytes (WGSL rounds the uniform struct to 16).
struct MaxMipPass {
    // The level baked (0: from the heights).
    level: u32,
    // Its first texel in hf_pyramid_out, and its texels along x.
    offset: u32,
    width: u32,
    // The finer level's first texel (level > 0).
    finer_offset: u32,
    // The finer level's texels along x and y (level > 0).
    finer_dims: vec2<u32>,
    // The texels written: [lo, hi).
    lo: vec2<u32>,
    hi: vec2<u32>,
}

@group(0) @binding(0) var hf_heights: texture_2d<f32>;
//#wgsl
@group(0) @binding(13) var<storage, read_write> hf_pyramid_out: array<f32>;
@group(0) @binding(14) var<uniform> hf_maxmip_pass: MaxMipPass;
//#end
//#glsl
// layout(std430, binding = 13) buffer HfPyramidOut { float hf_pyramid_out[]; };
// layout(std140, binding = 14) uniform HfMaxMipPass { MaxMipPass hf_maxmip_pass; };
//#end

// `mx`: the core's maximum, `a` when a > b, else `b`.
fn bake_mx(a: f32, b: f32) -> f32 { return select(b, a, a > b); }

// Sample (i, j).
fn bake_height(i: u32, j: u32) -> f32 { return textureLoad(hf_heights, vec2<u32>(i, j), 0).r; }

// Texel (i, j) of the finer level.
fn bake_finer(i: u32, j: u32) -> f32 {
    let p: MaxMipPass = hf_maxmip_pass;
    return hf_pyramid_out[p.finer_offset + j * p.finer_dims.x + i];
}

// Texel `gid` of the pass's range.
fn maxmip_bake_texel(gid: vec3<u32>) {
    let p: MaxMipPass = hf_maxmip_pass;
    let i: u32 = p.lo.x + gid.x;
    let j: u32 = p.lo.y + gid.y;
    if (i >= p.hi.x || j >= p.hi.y) {
        return;
    }
    var v: f32;
    if (p.level == 0u) {
        // `level0_row`.
        v = bake_mx(bake_mx(bake_height(i, j), bake_height(i + 1u, j)),
                    bake_mx(bake_height(i, j + 1u), bake_height(i + 1u, j + 1u)));
    } else {
        // `coarse_row`.
        let r0: u32 = min(2u * j, p.finer_dims.y - 1u);
        let r1: u32 = min(2u * j + 1u, p.finer_dims.y - 1u);
        if (2u * i + 1u < p.finer_dims.x) {
            v = bake_mx(bake_mx(bake_finer(2u * i, r0), bake_finer(2u * i + 1u, r0)),
                        bake_mx(bake_finer(2u * i, r1), bake_finer(2u * i + 1u, r1)));
        } else {
            let c: u32 = p.finer_dims.x - 1u;
            v = bake_mx(bake_finer(c, r0), bake_finer(c, r1));
        }
    }
    hf_pyramid_out[p.offset + j * p.width + i] = v;
}

// The entry point: one invocation per texel.
//#wgsl
@compute @workgroup_size(8, 8)
fn maxmip_bake_pass(@builtin(global_invocation_id) gid: vec3<u32>) {
    maxmip_bake_texel(gid);
}
//#end
//#glsl
// layout(local_size_x = 8, local_size_y = 8) in;
// void main() {
//     maxmip_bake_texel(gl_GlobalInvocationID);
// }
//#end
