// Generated from shaders/wgsl/bake_maxmip.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
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
#version 430 core

// One pass: the level, where it and the finer level lie in `hf_pyramid_out`, and the
// texels it writes. 48 bytes (WGSL rounds the uniform struct to 16).
struct MaxMipPass {
    // The level baked (0: from the heights).
    uint level;
    // Its first texel in hf_pyramid_out, and its texels along x.
    uint offset;
    uint width;
    // The finer level's first texel (level > 0).
    uint finer_offset;
    // The finer level's texels along x and y (level > 0).
    uvec2 finer_dims;
    // The texels written: [lo, hi).
    uvec2 lo;
    uvec2 hi;
};

uniform sampler2D hf_heights;
layout(std430, binding = 13) buffer HfPyramidOut { float hf_pyramid_out[]; };
layout(std140, binding = 14) uniform HfMaxMipPass { MaxMipPass hf_maxmip_pass; };

// `mx`: the core's maximum, `a` when a > b, else `b`.
float bake_mx(float a, float b) { return ((a > b) ? (a) : (b)); }

// Sample (i, j).
float bake_height(uint i, uint j) { return texelFetch(hf_heights, ivec2(i, j), 0).r; }

// Texel (i, j) of the finer level.
float bake_finer(uint i, uint j) {
    MaxMipPass p = hf_maxmip_pass;
    return hf_pyramid_out[p.finer_offset + j * p.finer_dims.x + i];
}

// Texel `gid` of the pass's range.
void maxmip_bake_texel(uvec3 gid) {
    MaxMipPass p = hf_maxmip_pass;
    uint i = p.lo.x + gid.x;
    uint j = p.lo.y + gid.y;
    if (i >= p.hi.x || j >= p.hi.y) {
        return;
    }
    float v;
    if (p.level == 0u) {
        // `level0_row`.
        v = bake_mx(bake_mx(bake_height(i, j), bake_height(i + 1u, j)), bake_mx(bake_height(i, j + 1u), bake_height(i + 1u, j + 1u)));
    } else {
        // `coarse_row`.
        uint r0 = min(2u * j, p.finer_dims.y - 1u);
        uint r1 = min(2u * j + 1u, p.finer_dims.y - 1u);
        if (2u * i + 1u < p.finer_dims.x) {
            v = bake_mx(bake_mx(bake_finer(2u * i, r0), bake_finer(2u * i + 1u, r0)), bake_mx(bake_finer(2u * i, r1), bake_finer(2u * i + 1u, r1)));
        } else {
            uint c = p.finer_dims.x - 1u;
            v = bake_mx(bake_finer(c, r0), bake_finer(c, r1));
        }
    }
    hf_pyramid_out[p.offset + j * p.width + i] = v;
}

// The entry point: one invocation per texel.
layout(local_size_x = 8, local_size_y = 8) in;
void main() {
    maxmip_bake_texel(gl_GlobalInvocationID);
}
