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
// The cylinder-cone map with N-buffer slopes (core/src/safety/cc.rs, `Slope::NBuffer`)
// is the entry point `cc_bake_pass` of the same file (GLSL: `#define HF_CC_BAKE` after
// the `#version` line): kind 0 as above, then
// - kind 2 (cylinder-cones): per texel and class `[r, s]` (bytes `2((4j + class) W +
//   i)` and the next) into hf_safety_out, r the safety distance (at most 255), s the
//   code of the cone slope for the reach `cap`: the largest bound of the abscissas of
//   the columns past the cylinder from the N-buffers in hf_nbuffer (filled before by
//   bake_nbuffer for the same cap), and at r = 0 the exact slope of the limiting
//   triangles of column 0; no cone (255) where r reaches `cap`.
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
@group(0) @binding(15) var<storage, read> hf_nbuffer: array<f32>;
@group(0) @binding(17) var<storage, read_write> hf_safety_scratch: array<f32>;
@group(0) @binding(18) var<storage, read_write> hf_safety_out: array<u32>;
@group(0) @binding(19) var<uniform> hf_safety_pass: SafetyBakePass;
//#end
//#glsl
// layout(std430, binding = 15) readonly buffer HfNbuffer { float hf_nbuffer[]; };
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

// One triangle in the frame of a class and a texel (`Tri`): its vertices (forward
// distance, minor coordinate), its plane's height `base` on the centerline at minor
// coordinate `at`, its minor and forward slopes.
struct SbTri {
    v0: vec2<f64>,
    v1: vec2<f64>,
    v2: vec2<f64>,
    base: f64,
    at: f64,
    minor_slope: f64,
    forward_slope: f64,
}

// The plane's height on the centerline at minor coordinate y (`Tri::height_on_line`).
fn sb_on_line(t: SbTri, y: f64) -> f64 {
    return t.base + t.minor_slope * (y - t.at);
}

// Whether triangle t limits some ray from the segment (`AllRays::limiting`).
fn sb_limiting(s: SbSigma, t: SbTri) -> bool {
    // The core starts from ±infinity: min(+inf, a) is a.
    var lo: f64 = sb_min(sb_min(t.v0.y - t.v0.x, t.v1.y - t.v1.x), t.v2.y - t.v2.x);
    var hi: f64 = sb_max(sb_max(t.v0.y + t.v0.x, t.v1.y + t.v1.x), t.v2.y + t.v2.x);
    lo = sb_max(lo, s.lo);
    hi = sb_min(hi, s.hi);
    if (lo > hi) {
        return false;
    }
    if (sb_on_line(t, lo) > sb_sigma_height(s, lo)) {
        return true;
    }
    if (sb_on_line(t, hi) > sb_sigma_height(s, hi)) {
        return true;
    }
    return lo < s.n && s.n < hi && sb_on_line(t, s.n) > sb_sigma_height(s, s.n);
}

// The two triangles of a cell in a texel's frame (`cell_tris`).
struct SbTris {
    t0: SbTri,
    t1: SbTri,
}

// The triangles of cell (cm, l) (main, minor indices of axis ax) for the texel of main
// index m and the class direction sg (`cell_tris`).
fn sb_cell_tris(ax: u32, sg: f64, m: u32, cm: u32, l: u32) -> SbTris {
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
        return SbTris(SbTri(p00, p10, p11, base0, lf, minor0, sg * main0), SbTri(p00, p01, p11, base1, lf, minor1, sg * main1));
    }
    return SbTris(SbTri(p00, p10, p01, base0, lf, minor0, sg * main0), SbTri(p10, p01, p11, base1, lf, minor1, sg * main1));
}

// Whether either triangle of cell (cm, l) limits (`cell_limits`).
fn sb_cell_limits(s: SbSigma, ax: u32, sg: f64, m: u32, cm: u32, l: u32) -> bool {
    let tris: SbTris = sb_cell_tris(ax, sg, m, cm, l);
    return sb_limiting(s, tris.t0) || sb_limiting(s, tris.t1);
}

// A texel and class in the class's frame: main axis, direction, samples along and
// across the main axis, the texel's main and minor indices, the surface over its
// segment and that surface's heights at the segment's ends (`Sigma::end_heights`).
struct SbTexel {
    ax: u32,
    forward: bool,
    sg: f64,
    lm: u32,
    ln: u32,
    m: u32,
    n: u32,
    sigma: SbSigma,
    at_lo: f64,
    at_hi: f64,
}

// Texel (i, j) for class `cls` (0 x+, 1 x-, 2 y+, 3 y-).
fn sb_texel(cls: u32, i: u32, j: u32) -> SbTexel {
    let ax: u32 = cls / 2u;
    let forward: bool = cls % 2u == 0u;
    var m: u32 = i;
    var n: u32 = j;
    if (ax == 1u) {
        m = j;
        n = i;
    }
    let s: SbSigma = sb_sigma_of(ax, m, n);
    let at_lo: f64 = s.h + s.below * (s.lo - s.n);
    let at_hi: f64 = s.h + s.above * (s.hi - s.n);
    return SbTexel(ax, forward, select(-1.0lf, 1.0lf, forward), sb_main_len(ax), sb_minor_len(ax), m, n, s, at_lo, at_hi);
}

// The safety distance of texel (i, j) for class `cls`, at most `cap`
// (`texel_distance` for `AllRays`).
fn sb_texel_distance(cls: u32, i: u32, j: u32, cap: u32) -> u32 {
    let t: SbTexel = sb_texel(cls, i, j);
    // The ray set lowers no plane (e = 0): `floor + (e - e * 2^-20)`.
    let lowest: f64 = sb_min(sb_min(t.at_lo, t.sigma.h), t.at_hi) + 0.0lf;
    let per_line: u32 = sb_strips(t.ax);
    var base: u32 = 0u;
    if (t.ax == 1u) {
        base = 3u * (hf_safety_pass.width - 1u) * sb_strips(0u);
    }
    let chan: u32 = select(2u, 1u, t.forward);
    let ahead: u32 = select(t.m, t.lm - 1u - t.m, t.forward);
    let columns: u32 = min(cap, ahead);
    for (var k: u32 = 0u; k < columns; k++) {
        let column: u32 = select(t.m - 1u - k, t.m + k, t.forward);
        // The band: cells l0..l1 (`band_cells`).
        let l0: u32 = select(0u, t.n - (k + 2u), t.n >= k + 2u);
        let l1: u32 = min(t.n + k + 1u, t.ln - 2u) + 1u;
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
                if (sb_cell_limits(t.sigma, t.ax, t.sg, t.m, column, l)) {
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

// ---- cylinder-cones (N-buffer slopes) ----

// floor(log2(v)) of v > 0.
//#wgsl
fn sb_log2(v: u32) -> u32 { return firstLeadingBit(v); }
//#end
//#glsl
// uint sb_log2(uint v) { return uint(findMSB(v)); }
//#end

// The N-buffer levels of the reach `cap` (cc.rs `levels`).
fn sb_levels(cap: u32) -> u32 {
    return sb_log2(2u * cap + 6u) + 1u;
}

// Where axis ax's N-buffers start, and their elements per level (`nb_layout`).
fn sb_nb_base(ax: u32, levels: u32) -> u32 {
    let w: u32 = hf_safety_pass.width;
    if (ax == 0u) {
        return 0u;
    }
    return levels * (w + (w - 1u + 7u) / 8u) * hf_safety_pass.height;
}
fn sb_nb_level(ax: u32) -> u32 {
    let lm: u32 = sb_main_len(ax);
    return (lm + (lm - 1u + 7u) / 8u) * sb_minor_len(ax);
}

// The highest sample over cross samples a..=b of the sample column whose level 0
// starts at `at` (`range_max`), for levels up to `top`, `level` elements apart.
fn sb_range_max(at: u32, a: u32, b: u32, level: u32, top: u32) -> f64 {
    let len: u32 = b - a + 1u;
    let l: u32 = min(sb_log2(len), top);
    let w: u32 = 1u << l;
    let first: u32 = at + l * level + a;
    let last: u32 = first + len - w;
    var m: f32 = select(hf_nbuffer[first], hf_nbuffer[last], hf_nbuffer[last] > hf_nbuffer[first]);
    for (var y: u32 = first + w; y < last; y += w) {
        m = select(m, hf_nbuffer[y], hf_nbuffer[y] > m);
    }
    return f64(m);
}

// The slope of a code's t (`decode_t`).
fn sb_decode_t(t: i32) -> f64 {
    return f64(t * abs(t)) / 2048.0lf;
}

// The slope code of s rounded up (`encode_slope`; 255 past S_MAX).
fn sb_encode_slope(s: f64) -> u32 {
    // S_MAX = 126 * 126 / 2048.
    if (s > 7.751953125lf) {
        return 255u;
    }
    var t: i32;
    if (s >= 0.0lf) {
        let x: f64 = sqrt(2048.0lf * s);
        t = i32(x);
        if (f64(t) < x) {
            t = t + 1;
        }
    } else {
        t = -i32(sb_min(sqrt(-2048.0lf * s), 128.0lf));
    }
    if (t < 126 && sb_decode_t(t) < s) {
        t = t + 1;
    }
    if (sb_decode_t(t) < s) {
        return 255u;
    }
    return u32(t + 128);
}

// The smallest slope a code stands for that is >= s (`code_ceiling`; +inf past S_MAX,
// returned as the flag `inf`).
struct SbSlope {
    s: f64,
    inf: bool,
}

fn sb_code_ceiling(s: f64) -> SbSlope {
    let code: u32 = sb_encode_slope(s);
    if (code == 255u) {
        return SbSlope(0.0lf, true);
    }
    return SbSlope(sb_decode_t(i32(code) - 128), false);
}

// `raise`: s to code_ceiling(max(s, t)).
fn sb_raise(s: SbSlope, t: f64) -> SbSlope {
    if (!s.inf && t > s.s) {
        return sb_code_ceiling(t);
    }
    return s;
}

// The edge of the band a ray from the segment reaches that cuts cell c of column k,
// as the half-plane a u + b y + d >= 0 it keeps (`band_edge`; xyz, w = 1 when there is
// one).
fn sb_band_edge(s: SbSigma, k: f64, c: f64) -> vec4<f64> {
    if (c + k < s.n) {
        return vec4<f64>(1.0lf, 1.0lf, -s.lo, 1.0lf);
    }
    if (c + 1.0lf > s.n + k) {
        return vec4<f64>(1.0lf, -1.0lf, s.hi, 1.0lf);
    }
    return vec4<f64>(0.0lf, 0.0lf, 0.0lf, 0.0lf);
}

// `tri_slope`'s running state: the best slope (once one is taken: the core starts
// from -inf), and whether a point on the centerline lies above z_c.
struct SbTake {
    best: f64,
    taken: bool,
    above: bool,
}

// `tri_slope`'s `take` of point p.
fn sb_take(st: SbTake, t: SbTri, zc: f64, p: vec2<f64>) -> SbTake {
    let z: f64 = sb_on_line(t, p.y) + t.forward_slope * p.x;
    let tol: f64 = 0.000000001lf * (1.0lf + abs(zc));
    if (p.x <= 0.000000001lf) {
        return SbTake(st.best, st.taken, st.above || z - zc > tol);
    }
    let slope: f64 = (z - zc) / p.x;
    if (!st.taken || slope > st.best) {
        return SbTake(slope, true, st.above);
    }
    return st;
}

// Vertex k of t.
fn sb_vertex(t: SbTri, k: u32) -> vec2<f64> {
    if (k == 0u) {
        return t.v0;
    }
    if (k == 1u) {
        return t.v1;
    }
    return t.v2;
}

// The largest (plane - zc) / u over the part of t a ray from the segment reaches (t
// clipped to `edge`, when its w is 1: `tri_slope`), as a raise of `s`.
fn sb_tri_slope(t: SbTri, zc: f64, edge: vec4<f64>, s: SbSlope) -> SbSlope {
    var st: SbTake = SbTake(0.0lf, false, false);
    for (var e: u32 = 0u; e < 3u; e++) {
        let p: vec2<f64> = sb_vertex(t, e);
        if (edge.w == 0.0lf) {
            st = sb_take(st, t, zc, p);
            continue;
        }
        let q: vec2<f64> = sb_vertex(t, (e + 1u) % 3u);
        let fp: f64 = edge.x * p.x + edge.y * p.y + edge.z;
        let fq: f64 = edge.x * q.x + edge.y * q.y + edge.z;
        if (fp >= 0.0lf) {
            st = sb_take(st, t, zc, p);
        }
        if ((fp >= 0.0lf) != (fq >= 0.0lf)) {
            let f: f64 = fp / (fp - fq);
            st = sb_take(st, t, zc, vec2<f64>(p.x + f * (q.x - p.x), p.y + f * (q.y - p.y)));
        }
    }
    if (st.above) {
        return SbSlope(0.0lf, true);
    }
    if (!st.taken) {
        return s;
    }
    return sb_raise(s, st.best);
}

// The cone slope code of texel (i, j) for class `cls` beyond the cylinder r
// (`class_search` with `Slope::NBuffer`), for the reach `cap`.
fn sb_cone_code(cls: u32, i: u32, j: u32, r: u32, cap: u32) -> u32 {
    let t: SbTexel = sb_texel(cls, i, j);
    let sig: SbSigma = t.sigma;
    let zc: f64 = sb_max(sb_max(t.at_lo, sig.h), t.at_hi);
    let levels: u32 = sb_levels(cap);
    let level: u32 = sb_nb_level(t.ax);
    // Sample column c's level 0 starts at axis + c ln.
    let axis: u32 = sb_nb_base(t.ax, levels);
    var s: SbSlope = SbSlope(-8.0lf, false);
    let kend: u32 = min(cap, select(t.m, t.lm - 1u - t.m, t.forward));
    let k0: u32 = max(r, 1u);
    // The largest bound of the abscissas u in k0..=kend: the highest sample of the
    // sample column u ahead over the band of column u, less z_c, over u.
    if (k0 < kend) {
        var top: f64 = -8.0lf;
        for (var u: u32 = k0; u <= kend; u++) {
            let a: u32 = select(0u, t.n - (u + 2u), t.n >= u + 2u);
            let b: u32 = min(t.n + u + 1u, t.ln - 2u) + 1u;
            let sample_column: u32 = select(t.m - u, t.m + u, t.forward);
            let bound: f64 = (sb_range_max(axis + sample_column * t.ln, a, b, level, levels - 1u) - zc) / f64(u);
            top = select(top, bound, bound > top);
        }
        s = sb_raise(s, top);
    }
    // Column 0, exactly, when the cylinder is empty: its bound (+inf when the near
    // side reaches above z_c), then its limiting triangles.
    if (r == 0u && kend > 0u) {
        let a: u32 = select(0u, t.n - 2u, t.n >= 2u);
        let b: u32 = min(t.n + 1u, t.ln - 2u) + 1u;
        let far_column: u32 = select(t.m - 1u, t.m + 1u, t.forward);
        let top_near: f64 = sb_range_max(axis + t.m * t.ln, a, b, level, levels - 1u) - zc;
        let top_far: f64 = sb_range_max(axis + far_column * t.ln, a, b, level, levels - 1u) - zc;
        if (top_near > 0.0lf || (!s.inf && top_far / 1.0lf > s.s)) {
            let cm: u32 = select(t.m - 1u, t.m, t.forward);
            for (var c: u32 = a; c < b && !s.inf; c++) {
                let tris: SbTris = sb_cell_tris(t.ax, t.sg, t.m, cm, c);
                let edge: vec4<f64> = sb_band_edge(sig, 0.0lf, f64(c));
                if (sb_limiting(sig, tris.t0)) {
                    s = sb_tri_slope(tris.t0, zc, edge, s);
                }
                if (!s.inf && sb_limiting(sig, tris.t1)) {
                    s = sb_tri_slope(tris.t1, zc, edge, s);
                }
            }
        }
    }
    if (s.inf) {
        return 255u;
    }
    return sb_encode_slope(s.s);
}

// The two bytes [r, s] of entry `e` of the cylinder-cone map (texel-class
// (4j + class) W + i).
fn sb_cc_entry(e: u32) -> u32 {
    let p: SafetyBakePass = hf_safety_pass;
    let i: u32 = e % p.width;
    let row: u32 = e / p.width;
    let cls: u32 = row % 4u;
    let j: u32 = row / 4u;
    let r: u32 = sb_texel_distance(cls, i, j, 255u);
    var code: u32 = 255u;
    if (r < p.cap) {
        code = sb_cone_code(cls, i, j, r, p.cap);
    }
    return r | (code << 8u);
}

// No item left for an invocation (`sb_word_item`).
const SB_DONE: u32 = 0xffffffffu;

// The item of invocation `gid`: a strip slot is baked here (kind 0); an output word's
// index is returned; SB_DONE when nothing is left to do.
fn sb_word_item(gid: vec3<u32>) -> u32 {
    let p: SafetyBakePass = hf_safety_pass;
    let item: u32 = gid.y * p.grid_width + gid.x;
    if (gid.x >= p.grid_width || item >= p.items) {
        return SB_DONE;
    }
    if (p.kind == 0u) {
        sb_strip_slot(item);
        return SB_DONE;
    }
    return item;
}

// Item `gid` of a pass of the safety bake: strip slots (kind 0), then the map's words,
// four bytes each (kind 1).
fn safety_bake_item(gid: vec3<u32>) {
    let p: SafetyBakePass = hf_safety_pass;
    let item: u32 = sb_word_item(gid);
    if (item == SB_DONE) {
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

// Item `gid` of a pass of the cylinder-cone bake: strip slots (kind 0), then the map's
// words, two entries each (kind 2).
fn cc_bake_item(gid: vec3<u32>) {
    let p: SafetyBakePass = hf_safety_pass;
    let item: u32 = sb_word_item(gid);
    if (item == SB_DONE) {
        return;
    }
    let entries: u32 = 4u * p.width * p.height;
    var word: u32 = sb_cc_entry(2u * item);
    if (2u * item + 1u < entries) {
        word = word | (sb_cc_entry(2u * item + 1u) << 16u);
    }
    hf_safety_out[item] = word;
}

// The entry points: one invocation per item.
//#wgsl
@compute @workgroup_size(8, 8)
fn safety_bake_pass(@builtin(global_invocation_id) gid: vec3<u32>) {
    safety_bake_item(gid);
}

@compute @workgroup_size(8, 8)
fn cc_bake_pass(@builtin(global_invocation_id) gid: vec3<u32>) {
    cc_bake_item(gid);
}
//#end
//#glsl
// layout(local_size_x = 8, local_size_y = 8) in;
// void main() {
// #ifdef HF_CC_BAKE
//     cc_bake_item(gl_GlobalInvocationID);
// #else
//     safety_bake_item(gl_GlobalInvocationID);
// #endif
// }
//#end
