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
//#glsl
// #version 430 core
//#end

// One step (`cc::NbufferStep`). 32 bytes.
struct NbufferPass {
    // 0 heights, 1 double, 2 blocks.
    kind: u32,
    // Main axis of the columns (0: x = r; 1: y = r).
    axis: u32,
    // Rows written, elements per row.
    rows: u32,
    row_len: u32,
    // First element written, first element read.
    dst: u32,
    src: u32,
    // The doubling's offset (kind 1).
    half_window: u32,
    // Sample columns of the axis (kind 2).
    columns: u32,
}

@group(0) @binding(0) var hf_heights: texture_2d<f32>;
//#wgsl
@group(0) @binding(15) var<storage, read_write> hf_nbuffer: array<f32>;
@group(0) @binding(16) var<uniform> hf_nbuffer_pass: NbufferPass;
//#end
//#glsl
// layout(std430, binding = 15) buffer HfNbuffer { float hf_nbuffer[]; };
// layout(std140, binding = 16) uniform HfNbufferPass { NbufferPass hf_nbuffer_pass; };
//#end

// The block's columns: 8 cell columns, 9 sample columns (cc.rs `BLOCK`).
const NBUFFER_BLOCK: u32 = 8u;

// `mx`: the core's maximum, `a` when a > b, else `b`.
fn nbuffer_mx(a: f32, b: f32) -> f32 { return select(b, a, a > b); }

// Element (r, y) of the step `gid` addresses.
fn nbuffer_bake_element(gid: vec3<u32>) {
    let p: NbufferPass = hf_nbuffer_pass;
    let y: u32 = gid.x;
    let r: u32 = gid.y;
    if (y >= p.row_len || r >= p.rows) {
        return;
    }
    var v: f32;
    if (p.kind == 0u) {
        let at: vec2<u32> = select(vec2<u32>(y, r), vec2<u32>(r, y), p.axis == 0u);
        v = textureLoad(hf_heights, at, 0).r;
    } else if (p.kind == 1u) {
        let row: u32 = p.src + r * p.row_len;
        v = nbuffer_mx(hf_nbuffer[row + y], hf_nbuffer[row + min(y + p.half_window, p.row_len - 1u)]);
    } else {
        let first: u32 = NBUFFER_BLOCK * r;
        let last: u32 = min(first + NBUFFER_BLOCK, p.columns - 1u);
        v = hf_nbuffer[p.src + first * p.row_len + y];
        for (var c: u32 = first + 1u; c <= last; c++) {
            v = nbuffer_mx(v, hf_nbuffer[p.src + c * p.row_len + y]);
        }
    }
    hf_nbuffer[p.dst + r * p.row_len + y] = v;
}

// The entry point: one invocation per element.
//#wgsl
@compute @workgroup_size(8, 8)
fn nbuffer_bake_pass(@builtin(global_invocation_id) gid: vec3<u32>) {
    nbuffer_bake_element(gid);
}
//#end
//#glsl
// layout(local_size_x = 8, local_size_y = 8) in;
// void main() {
//     nbuffer_bake_element(gl_GlobalInvocationID);
// }
//#end
