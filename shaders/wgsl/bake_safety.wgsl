// The safety distances for every ray (Baboud, Eisemann, Seidel 2011, §5.2.2 and §6.1)
// baked on the GPU (issue 27): mirror of core/src/safety.rs `prepare` and
// `texel_distance` for `AllRays`, in f64 as the core computes them (the device needs
// 64-bit floats: wgpu's SHADER_F64, OpenGL 4.0 doubles). A compute shader, not part of
// any march; two dispatches of `safety_bake_pass`, each finished before the next:
// - kind 0 (strips): the strip bounds into hf_safety_scratch (`safety::scratch_len`
//   floats): per strip of 8 cells of a cell column (x classes) or row (y classes), the
//   highest corner and the fastest rise back towards a segment of either class of the
//   strip's orientation, each rounded up to f32;
// - kind 1 (distances): the map into hf_safety_out, its bytes packed four to a u32
//   word (little-endian: byte 4w + b is bits 8b..8b+7 of word w), every class of every
//   texel: directional `((4j + class) W + i)`, isotropic `j W + i` (the least over the
//   classes), at least `least` (1 for the paper's positive variant), at most `cap`.
// Invocation (x, y) of the 8 x 8 workgroups handles item y * grid_width + x (a strip
// slot, or an output word). Every test is the core's, operation for operation, so the
// bytes equal the CPU bake's.
// The GLSL 4.30 compute port (glsl/bake_safety.glsl) is generated from this file.
//#glsl
// #version 430 core
//#end

// One pass. 32 bytes.
struct SafetyBakePass {
    // 0 strips, 1 distances.
    kind: u32,
    // Samples along x and y.
    width: u32,
    height: u32,
    // 0 directional, 1 isotropic.
    isotropic: u32,
    // Largest distance, least distance (1: the positive variant).
    cap: u32,
    least: u32,
    // Items of the pass (strip slots or output words) and invocations per grid row.
    items: u32,
    grid_width: u32,
}

@group(0) @binding(0) var hf_heights: texture_2d<f32>;
//#wgsl
@group(0) @binding(17) var<storage, read_write> hf_safety_scratch: array<f32>;
@group(0) @binding(18) var<storage, read_write> hf_safety_out: array<u32>;
@group(0) @binding(19) var<uniform> hf_safety_pass: SafetyBakePass;
//#end
//#glsl
// layout(std430, binding = 17) buffer HfSafetyScratch { float hf_safety_scratch[]; };
// layout(std430, binding = 18) buffer HfSafetyOut { uint hf_safety_out[]; };
// layout(std140, binding = 19) uniform HfSafetyPass { SafetyBakePass hf_safety_pass; };
//#end

// Cells per strip (safety.rs `STRIP`).
const SB_STRIP: u32 = 8u;

// Sample (i, j), exactly as f64.
fn sb_height(i: u32, j: u32) -> f64 {
    return f64(textureLoad(hf_heights, vec2<u32>(i, j), 0).r);
}

// Sample at main index m, minor index n of axis ax (`sample`).
fn sb_sample(ax: u32, m: u32, n: u32) -> f64 {
    if (ax == 0u) {
        return sb_height(m, n);
    }
    return sb_height(n, m);
}

// Samples along the main axis of axis ax (`extents().0`) and along its minor axis.
fn sb_main_len(ax: u32) -> u32 {
    return select(hf_safety_pass.height, hf_safety_pass.width, ax == 0u);
}
fn sb_minor_len(ax: u32) -> u32 {
    return select(hf_safety_pass.width, hf_safety_pass.height, ax == 0u);
}

// Strips per cell column (x classes, ax 0) or cell row (y classes, ax 1) (`strips`).
fn sb_strips(ax: u32) -> u32 {
    return (sb_minor_len(ax) - 1u + SB_STRIP - 1u) / SB_STRIP;
}

// `f64::max` / `min` of finite values.
fn sb_max(a: f64, b: f64) -> f64 { return select(b, a, a > b); }
fn sb_min(a: f64, b: f64) -> f64 { return select(b, a, a < b); }

// Rounds up to f32 (`up`: the bound must not shrink).
fn sb_up(v: f64) -> f32 {
    let r: f32 = f32(v);
    if (f64(r) < v) {
        let bits: u32 = bitcast<u32>(r);
        return bitcast<f32>(select(bits - 1u, bits + 1u, r >= 0.0));
    }
    return r;
}

// The corners of cell (i, j) in f64: h00, h10, h01, h11 (`HeightField::cell_corners`).
fn sb_corners(i: u32, j: u32) -> vec4<f64> {
    return vec4<f64>(sb_height(i, j), sb_height(i + 1u, j), sb_height(i, j + 1u), sb_height(i + 1u, j + 1u));
}

// The two triangles' planes [h0, gu, gv] of corners c (`triangle_planes`).
struct SbPlanes {
    p0: vec3<f64>,
    p1: vec3<f64>,
}

fn sb_planes(c: vec4<f64>) -> SbPlanes {
    if (c.x + c.w <= c.y + c.z) {
        return SbPlanes(vec3<f64>(c.x, c.y - c.x, c.w - c.y), vec3<f64>(c.x, c.w - c.z, c.z - c.x));
    }
    return SbPlanes(vec3<f64>(c.x, c.y - c.x, c.z - c.x), vec3<f64>(c.y + c.z - c.w, c.w - c.z, c.w - c.y));
}

// The fastest rise of plane p going back towards a segment of class k (`cell_bound`'s
// `-gu + |gv|`, `gu + |gv|`, `-gv + |gu|`, `gv + |gu|`).
fn sb_rise(p: vec3<f64>, k: u32) -> f64 {
    if (k == 0u) {
        return -p.y + abs(p.z);
    }
    if (k == 1u) {
        return p.y + abs(p.z);
    }
    if (k == 2u) {
        return -p.z + abs(p.y);
    }
    return p.z + abs(p.y);
}

// Strip slot `item` (kind 0): x strips first (cell column ci, strip b: cells
// (ci, 8b..8b+8)), then y strips (cell row cj, strip b: cells (8b..8b+8, cj)).
fn sb_strip_slot(item: u32) {
    let p: SafetyBakePass = hf_safety_pass;
    let cx: u32 = p.width - 1u;
    let cy: u32 = p.height - 1u;
    let sx: u32 = sb_strips(0u);
    let sy: u32 = sb_strips(1u);
    var ax: u32 = 0u;
    var strip_line: u32 = item / sx;
    var b: u32 = item % sx;
    // Both regions' slots are 3 floats, the y strips' after the x strips'.
    let at: u32 = 3u * item;
    var cells: u32 = cy;
    if (item >= cx * sx) {
        ax = 1u;
        strip_line = (item - cx * sx) / sy;
        b = (item - cx * sx) % sy;
        cells = cx;
    }
    let neg_inf: f32 = bitcast<f32>(0xff800000u);
    var top: f32 = neg_inf;
    var rise0: f32 = neg_inf;
    var rise1: f32 = neg_inf;
    for (var c: u32 = b * SB_STRIP; c < min(b * SB_STRIP + SB_STRIP, cells); c++) {
        var corners: vec4<f64>;
        if (ax == 0u) {
            corners = sb_corners(strip_line, c);
        } else {
            corners = sb_corners(c, strip_line);
        }
        let cell_top: f64 = sb_max(sb_max(sb_max(corners.x, corners.y), corners.z), corners.w);
        let planes: SbPlanes = sb_planes(corners);
        let k0: u32 = 2u * ax;
        let r0: f64 = sb_max(sb_rise(planes.p0, k0), sb_rise(planes.p1, k0));
        let r1: f64 = sb_max(sb_rise(planes.p0, k0 + 1u), sb_rise(planes.p1, k0 + 1u));
        let t: f32 = sb_up(cell_top);
        let u0: f32 = sb_up(r0);
        let u1: f32 = sb_up(r1);
        top = select(top, t, t > top);
        rise0 = select(rise0, u0, u0 > rise0);
        rise1 = select(rise1, u1, u1 > rise1);
    }
    hf_safety_scratch[at] = top;
    hf_safety_scratch[at + 1u] = rise0;
    hf_safety_scratch[at + 2u] = rise1;
}

// The surface over a texel's segment in its class's frame (`Sigma`).
struct SbSigma {
    // Minor index, height there, slopes below and above it.
    n: f64,
    h: f64,
    below: f64,
    above: f64,
    // The widened segment [lo, hi].
    lo: f64,
    hi: f64,
}

// The surface height on the segment at minor coordinate y (`Sigma::height`).
fn sb_sigma_height(s: SbSigma, y: f64) -> f64 {
    let slope: f64 = select(s.above, s.below, y < s.n);
    return s.h + slope * (y - s.n);
}

// `sigma_of` for texel (m, n) of axis ax.
fn sb_sigma_of(ax: u32, m: u32, n: u32) -> SbSigma {
    let ln: u32 = sb_minor_len(ax);
    let h: f64 = sb_sample(ax, m, n);
    var below: f64;
    if (n > 0u) {
        below = h - sb_sample(ax, m, n - 1u);
    } else {
        below = sb_sample(ax, m, n + 1u) - h;
    }
    var above: f64;
    if (n + 1u < ln) {
        above = sb_sample(ax, m, n + 1u) - h;
    } else {
        above = h - sb_sample(ax, m, n - 1u);
    }
    let nf: f64 = f64(n);
    // SEG_PAD = 1/16.
    return SbSigma(nf, h, below, above, nf - 0.5lf - 0.0625lf, nf + 0.5lf + 0.0625lf);
}

// Whether a triangle of vertices (forward distance, minor coordinate) v0, v1, v2 whose
// plane has height `base` at minor coordinate `at` on the centerline and minor slope
// `slope` limits some ray from the segment (`AllRays::limiting`).
fn sb_limiting(s: SbSigma, v0: vec2<f64>, v1: vec2<f64>, v2: vec2<f64>, base: f64, at: f64, slope: f64) -> bool {
    // The core starts from ±infinity: min(+inf, a) is a.
    var lo: f64 = sb_min(sb_min(v0.y - v0.x, v1.y - v1.x), v2.y - v2.x);
    var hi: f64 = sb_max(sb_max(v0.y + v0.x, v1.y + v1.x), v2.y + v2.x);
    lo = sb_max(lo, s.lo);
    hi = sb_min(hi, s.hi);
    if (lo > hi) {
        return false;
    }
    if (base + slope * (lo - at) > sb_sigma_height(s, lo)) {
        return true;
    }
    if (base + slope * (hi - at) > sb_sigma_height(s, hi)) {
        return true;
    }
    return lo < s.n && s.n < hi && base + slope * (s.n - at) > sb_sigma_height(s, s.n);
}

// Whether either triangle of cell (cm, l) (main, minor indices of axis ax) limits, for
// the texel of main index m and the class direction sg (`cell_limits`, `cell_tris`).
fn sb_cell_limits(s: SbSigma, ax: u32, sg: f64, m: u32, cm: u32, l: u32) -> bool {
    var c: vec4<f64>;
    if (ax == 0u) {
        c = sb_corners(cm, l);
    } else {
        c = sb_corners(l, cm);
    }
    let planes: SbPlanes = sb_planes(c);
    let mf: f64 = f64(m);
    let lf: f64 = f64(l);
    let cmf: f64 = f64(cm);
    let fwd0: f64 = sg * (cmf - mf);
    let fwd1: f64 = sg * (cmf + 1.0lf - mf);
    // Corner (u, v) in the frame: [fwd[a], lf + b] with (a, b) = (u, v) or (v, u).
    var p00: vec2<f64> = vec2<f64>(fwd0, lf);
    var p10: vec2<f64>;
    var p01: vec2<f64>;
    if (ax == 0u) {
        p10 = vec2<f64>(fwd1, lf);
        p01 = vec2<f64>(fwd0, lf + 1.0lf);
    } else {
        p10 = vec2<f64>(fwd0, lf + 1.0lf);
        p01 = vec2<f64>(fwd1, lf);
    }
    let p11: vec2<f64> = vec2<f64>(fwd1, lf + 1.0lf);
    // Each plane's main and minor slopes.
    var main0: f64 = planes.p0.y;
    var minor0: f64 = planes.p0.z;
    var main1: f64 = planes.p1.y;
    var minor1: f64 = planes.p1.z;
    if (ax == 1u) {
        main0 = planes.p0.z;
        minor0 = planes.p0.y;
        main1 = planes.p1.z;
        minor1 = planes.p1.y;
    }
    let base0: f64 = planes.p0.x + main0 * (mf - cmf);
    let base1: f64 = planes.p1.x + main1 * (mf - cmf);
    if (c.x + c.w <= c.y + c.z) {
        return sb_limiting(s, p00, p10, p11, base0, lf, minor0) || sb_limiting(s, p00, p01, p11, base1, lf, minor1);
    }
    return sb_limiting(s, p00, p10, p01, base0, lf, minor0) || sb_limiting(s, p10, p01, p11, base1, lf, minor1);
}

// The safety distance of texel (i, j) for class `cls` (0 x+, 1 x-, 2 y+, 3 y-), at most
// `cap` (`texel_distance` for `AllRays`).
fn sb_texel_distance(cls: u32, i: u32, j: u32, cap: u32) -> u32 {
    let ax: u32 = cls / 2u;
    let forward: bool = cls % 2u == 0u;
    let sg: f64 = select(-1.0lf, 1.0lf, forward);
    let lm: u32 = sb_main_len(ax);
    let ln: u32 = sb_minor_len(ax);
    var m: u32 = i;
    var n: u32 = j;
    if (ax == 1u) {
        m = j;
        n = i;
    }
    let s: SbSigma = sb_sigma_of(ax, m, n);
    let at_lo: f64 = s.h + s.below * (s.lo - s.n);
    let at_hi: f64 = s.h + s.above * (s.hi - s.n);
    // The ray set lowers no plane (e = 0): `floor + (e - e * 2^-20)`.
    let lowest: f64 = sb_min(sb_min(at_lo, s.h), at_hi) + 0.0lf;
    let per_line: u32 = sb_strips(ax);
    var base: u32 = 0u;
    if (ax == 1u) {
        base = 3u * (hf_safety_pass.width - 1u) * sb_strips(0u);
    }
    let chan: u32 = select(2u, 1u, forward);
    let ahead: u32 = select(m, lm - 1u - m, forward);
    let columns: u32 = min(cap, ahead);
    for (var k: u32 = 0u; k < columns; k++) {
        let column: u32 = select(m - 1u - k, m + k, forward);
        // The band: cells l0..l1 (`band_cells`).
        let l0: u32 = select(0u, n - (k + 2u), n >= k + 2u);
        let l1: u32 = min(n + k + 1u, ln - 2u) + 1u;
        for (var b: u32 = l0 / SB_STRIP; b < (l1 + SB_STRIP - 1u) / SB_STRIP; b++) {
            // A strip is skipped when no plane in it rises above the lowest point.
            let at: u32 = base + 3u * (column * per_line + b);
            let top: f64 = f64(hf_safety_scratch[at]);
            let beta: f64 = f64(hf_safety_scratch[at + chan]);
            let kf: f64 = f64(k);
            if (top + sb_max(beta * kf, beta * (kf + 1.0lf)) <= lowest) {
                continue;
            }
            for (var l: u32 = max(l0, b * SB_STRIP); l < min(l1, b * SB_STRIP + SB_STRIP); l++) {
                if (sb_cell_limits(s, ax, sg, m, column, l)) {
                    return k;
                }
            }
        }
    }
    return cap;
}

// Byte `index` of the map (kind 1).
fn sb_map_byte(index: u32) -> u32 {
    let p: SafetyBakePass = hf_safety_pass;
    let i: u32 = index % p.width;
    let row: u32 = index / p.width;
    if (p.isotropic == 0u) {
        return max(sb_texel_distance(row % 4u, i, row / 4u, p.cap), p.least);
    }
    var v: u32 = p.cap;
    for (var cls: u32 = 0u; cls < 4u && v != 0u; cls++) {
        v = sb_texel_distance(cls, i, row, v);
    }
    return max(v, p.least);
}

// Item `gid` of the pass.
fn safety_bake_item(gid: vec3<u32>) {
    let p: SafetyBakePass = hf_safety_pass;
    let item: u32 = gid.y * p.grid_width + gid.x;
    if (gid.x >= p.grid_width || item >= p.items) {
        return;
    }
    if (p.kind == 0u) {
        sb_strip_slot(item);
        return;
    }
    // Output word `item`: bytes 4 item .. 4 item + 3 of the map.
    var bytes: u32 = p.width * p.height;
    if (p.isotropic == 0u) {
        bytes = 4u * bytes;
    }
    var word: u32 = 0u;
    for (var b: u32 = 0u; b < 4u; b++) {
        let index: u32 = 4u * item + b;
        if (index < bytes) {
            word = word | (sb_map_byte(index) << (8u * b));
        }
    }
    hf_safety_out[item] = word;
}

// The entry point: one invocation per item.
//#wgsl
@compute @workgroup_size(8, 8)
fn safety_bake_pass(@builtin(global_invocation_id) gid: vec3<u32>) {
    safety_bake_item(gid);
}
//#end
//#glsl
// layout(local_size_x = 8, local_size_y = 8) in;
// void main() {
//     safety_bake_item(gl_GlobalInvocationID);
// }
//#end
