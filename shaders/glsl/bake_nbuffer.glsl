// Generated from shaders/wgsl/bake_nbuffer.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// The N-buffers of the cylinder-cone bake on the GPU (issue 27; Baboud et al. 2011,
// §6.3.2): mirror of core/src/safety/cc.rs `NbufferStep::run`. A compute shader, not
// part of any march: one dispatch of `nbuffer_bake_pass` per step of
// `cc::nbuffer_steps`, in order, each over its rows x row_len elements in workgroups
// of 8 x 8 (x along the row, y across rows), into the storage buffer hf_nbuffer in
// the core's layout (`cc::nbuffer_len` floats). A step writes elements
// dst + r * row_len + y:
// - kind 0 (heights): the sample at main index r, minor index y of its axis;
// - kind 1 (double): the maximum of the level below (from src) at y and at
//   min(y + half, row_len - 1);
// - kind 2 (blocks): the maximum of the sample columns' level 0 (from src) over the
//   columns 8r ..= min(8r + 8, columns - 1), in that order.
// Maxima are the core's `a > b ? a : b`, so the floats equal the CPU's bit for bit.
// The GLSL 4.30 compute port (glsl/bake_nbuffer.glsl) is generated from this file.
#version 430 core

// One step (`cc::NbufferStep`). 32 bytes.
struct NbufferPass {
    // 0 heights, 1 double, 2 blocks.
    uint kind;
    // Main axis of the columns (0: x = r; 1: y = r).
    uint axis;
    // Rows written, elements per row.
    uint rows;
    uint row_len;
    // First element written, first element read.
    uint dst;
    uint src;
    // The doubling's offset (kind 1).
    uint half_window;
    // Sample columns of the axis (kind 2).
    uint columns;
};

uniform sampler2D hf_heights;
layout(std430, binding = 15) buffer HfNbuffer { float hf_nbuffer[]; };
layout(std140, binding = 16) uniform HfNbufferPass { NbufferPass hf_nbuffer_pass; };

// The block's columns: 8 cell columns, 9 sample columns (cc.rs `BLOCK`).
const uint NBUFFER_BLOCK = 8u;

// `mx`: the core's maximum, `a` when a > b, else `b`.
float nbuffer_mx(float a, float b) { return ((a > b) ? (a) : (b)); }

// Element (r, y) of the step `gid` addresses.
void nbuffer_bake_element(uvec3 gid) {
    NbufferPass p = hf_nbuffer_pass;
    uint y = gid.x;
    uint r = gid.y;
    if (y >= p.row_len || r >= p.rows) {
        return;
    }
    float v;
    if (p.kind == 0u) {
        uvec2 at = ((p.axis == 0u) ? (uvec2(r, y)) : (uvec2(y, r)));
        v = texelFetch(hf_heights, ivec2(at), 0).r;
    } else if (p.kind == 1u) {
        uint row = p.src + r * p.row_len;
        v = nbuffer_mx(hf_nbuffer[row + y], hf_nbuffer[row + min(y + p.half_window, p.row_len - 1u)]);
    } else {
        uint first = NBUFFER_BLOCK * r;
        uint last = min(first + NBUFFER_BLOCK, p.columns - 1u);
        v = hf_nbuffer[p.src + first * p.row_len + y];
        for (uint c = first + 1u; c <= last; c++) {
            v = nbuffer_mx(v, hf_nbuffer[p.src + c * p.row_len + y]);
        }
    }
    hf_nbuffer[p.dst + r * p.row_len + y] = v;
}

// The entry point: one invocation per element.
layout(local_size_x = 8, local_size_y = 8) in;
void main() {
    nbuffer_bake_element(gl_GlobalInvocationID);
}
