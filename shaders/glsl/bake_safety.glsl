// Generated from shaders/wgsl/bake_safety.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
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
#version 430 core

// One pass. 32 bytes.
struct SafetyBakePass {
    // 0 strips, 1 distances.
    uint kind;
    // Samples along x and y.
    uint width;
    uint height;
    // 0 directional, 1 isotropic.
    uint isotropic;
    // Largest distance, least distance (1: the positive variant).
    uint cap;
    uint least;
    // Items of the pass (strip slots or output words) and invocations per grid row.
    uint items;
    uint grid_width;
};

uniform sampler2D hf_heights;
layout(std430, binding = 17) buffer HfSafetyScratch { float hf_safety_scratch[]; };
layout(std430, binding = 18) buffer HfSafetyOut { uint hf_safety_out[]; };
layout(std140, binding = 19) uniform HfSafetyPass { SafetyBakePass hf_safety_pass; };

// Cells per strip (safety.rs `STRIP`).
const uint SB_STRIP = 8u;

// Sample (i, j), exactly as f64.
double sb_height(uint i, uint j) {
    return double(texelFetch(hf_heights, ivec2(i, j), 0).r);
}

// Sample at main index m, minor index n of axis ax (`sample`).
double sb_sample(uint ax, uint m, uint n) {
    if (ax == 0u) {
        return sb_height(m, n);
    }
    return sb_height(n, m);
}

// Samples along the main axis of axis ax (`extents().0`) and along its minor axis.
uint sb_main_len(uint ax) {
    return ((ax == 0u) ? (hf_safety_pass.width) : (hf_safety_pass.height));
}
uint sb_minor_len(uint ax) {
    return ((ax == 0u) ? (hf_safety_pass.height) : (hf_safety_pass.width));
}

// Strips per cell column (x classes, ax 0) or cell row (y classes, ax 1) (`strips`).
uint sb_strips(uint ax) {
    return (sb_minor_len(ax) - 1u + SB_STRIP - 1u) / SB_STRIP;
}

// `f64::max` / `min` of finite values.
double sb_max(double a, double b) { return ((a > b) ? (a) : (b)); }
double sb_min(double a, double b) { return ((a < b) ? (a) : (b)); }

// Rounds up to f32 (`up`: the bound must not shrink).
float sb_up(double v) {
    float r = float(v);
    if (double(r) < v) {
        uint bits = floatBitsToUint(r);
        return uintBitsToFloat(((r >= 0.0) ? (bits + 1u) : (bits - 1u)));
    }
    return r;
}

// The corners of cell (i, j) in f64: h00, h10, h01, h11 (`HeightField::cell_corners`).
dvec4 sb_corners(uint i, uint j) {
    return dvec4(sb_height(i, j), sb_height(i + 1u, j), sb_height(i, j + 1u), sb_height(i + 1u, j + 1u));
}

// The two triangles' planes [h0, gu, gv] of corners c (`triangle_planes`).
struct SbPlanes {
    dvec3 p0;
    dvec3 p1;
};

SbPlanes sb_planes(dvec4 c) {
    if (c.x + c.w <= c.y + c.z) {
        return SbPlanes(dvec3(c.x, c.y - c.x, c.w - c.y), dvec3(c.x, c.w - c.z, c.z - c.x));
    }
    return SbPlanes(dvec3(c.x, c.y - c.x, c.z - c.x), dvec3(c.y + c.z - c.w, c.w - c.z, c.w - c.y));
}

// The fastest rise of plane p going back towards a segment of class k (`cell_bound`'s
// `-gu + |gv|`, `gu + |gv|`, `-gv + |gu|`, `gv + |gu|`).
double sb_rise(dvec3 p, uint k) {
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
void sb_strip_slot(uint item) {
    SafetyBakePass p = hf_safety_pass;
    uint cx = p.width - 1u;
    uint cy = p.height - 1u;
    uint sx = sb_strips(0u);
    uint sy = sb_strips(1u);
    uint ax = 0u;
    uint strip_line = item / sx;
    uint b = item % sx;
    // Both regions' slots are 3 floats, the y strips' after the x strips'.
    uint at = 3u * item;
    uint cells = cy;
    if (item >= cx * sx) {
        ax = 1u;
        strip_line = (item - cx * sx) / sy;
        b = (item - cx * sx) % sy;
        cells = cx;
    }
    float neg_inf = uintBitsToFloat(0xff800000u);
    float top = neg_inf;
    float rise0 = neg_inf;
    float rise1 = neg_inf;
    for (uint c = b * SB_STRIP; c < min(b * SB_STRIP + SB_STRIP, cells); c++) {
        dvec4 corners;
        if (ax == 0u) {
            corners = sb_corners(strip_line, c);
        } else {
            corners = sb_corners(c, strip_line);
        }
        double cell_top = sb_max(sb_max(sb_max(corners.x, corners.y), corners.z), corners.w);
        SbPlanes planes = sb_planes(corners);
        uint k0 = 2u * ax;
        double r0 = sb_max(sb_rise(planes.p0, k0), sb_rise(planes.p1, k0));
        double r1 = sb_max(sb_rise(planes.p0, k0 + 1u), sb_rise(planes.p1, k0 + 1u));
        float t = sb_up(cell_top);
        float u0 = sb_up(r0);
        float u1 = sb_up(r1);
        top = ((t > top) ? (t) : (top));
        rise0 = ((u0 > rise0) ? (u0) : (rise0));
        rise1 = ((u1 > rise1) ? (u1) : (rise1));
    }
    hf_safety_scratch[at] = top;
    hf_safety_scratch[at + 1u] = rise0;
    hf_safety_scratch[at + 2u] = rise1;
}

// The surface over a texel's segment in its class's frame (`Sigma`).
struct SbSigma {
    // Minor index, height there, slopes below and above it.
    double n;
    double h;
    double below;
    double above;
    // The widened segment [lo, hi].
    double lo;
    double hi;
};

// The surface height on the segment at minor coordinate y (`Sigma::height`).
double sb_sigma_height(SbSigma s, double y) {
    double slope = ((y < s.n) ? (s.below) : (s.above));
    return s.h + slope * (y - s.n);
}

// `sigma_of` for texel (m, n) of axis ax.
SbSigma sb_sigma_of(uint ax, uint m, uint n) {
    uint ln = sb_minor_len(ax);
    double h = sb_sample(ax, m, n);
    double below;
    if (n > 0u) {
        below = h - sb_sample(ax, m, n - 1u);
    } else {
        below = sb_sample(ax, m, n + 1u) - h;
    }
    double above;
    if (n + 1u < ln) {
        above = sb_sample(ax, m, n + 1u) - h;
    } else {
        above = h - sb_sample(ax, m, n - 1u);
    }
    double nf = double(n);
    // SEG_PAD = 1/16.
    return SbSigma(nf, h, below, above, nf - 0.5lf - 0.0625lf, nf + 0.5lf + 0.0625lf);
}

// Whether a triangle of vertices (forward distance, minor coordinate) v0, v1, v2 whose
// plane has height `base` at minor coordinate `at` on the centerline and minor slope
// `slope` limits some ray from the segment (`AllRays::limiting`).
bool sb_limiting(SbSigma s, dvec2 v0, dvec2 v1, dvec2 v2, double base, double at, double slope) {
    // The core starts from ±infinity: min(+inf, a) is a.
    double lo = sb_min(sb_min(v0.y - v0.x, v1.y - v1.x), v2.y - v2.x);
    double hi = sb_max(sb_max(v0.y + v0.x, v1.y + v1.x), v2.y + v2.x);
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
bool sb_cell_limits(SbSigma s, uint ax, double sg, uint m, uint cm, uint l) {
    dvec4 c;
    if (ax == 0u) {
        c = sb_corners(cm, l);
    } else {
        c = sb_corners(l, cm);
    }
    SbPlanes planes = sb_planes(c);
    double mf = double(m);
    double lf = double(l);
    double cmf = double(cm);
    double fwd0 = sg * (cmf - mf);
    double fwd1 = sg * (cmf + 1.0lf - mf);
    // Corner (u, v) in the frame: [fwd[a], lf + b] with (a, b) = (u, v) or (v, u).
    dvec2 p00 = dvec2(fwd0, lf);
    dvec2 p10;
    dvec2 p01;
    if (ax == 0u) {
        p10 = dvec2(fwd1, lf);
        p01 = dvec2(fwd0, lf + 1.0lf);
    } else {
        p10 = dvec2(fwd0, lf + 1.0lf);
        p01 = dvec2(fwd1, lf);
    }
    dvec2 p11 = dvec2(fwd1, lf + 1.0lf);
    // Each plane's main and minor slopes.
    double main0 = planes.p0.y;
    double minor0 = planes.p0.z;
    double main1 = planes.p1.y;
    double minor1 = planes.p1.z;
    if (ax == 1u) {
        main0 = planes.p0.z;
        minor0 = planes.p0.y;
        main1 = planes.p1.z;
        minor1 = planes.p1.y;
    }
    double base0 = planes.p0.x + main0 * (mf - cmf);
    double base1 = planes.p1.x + main1 * (mf - cmf);
    if (c.x + c.w <= c.y + c.z) {
        return sb_limiting(s, p00, p10, p11, base0, lf, minor0) || sb_limiting(s, p00, p01, p11, base1, lf, minor1);
    }
    return sb_limiting(s, p00, p10, p01, base0, lf, minor0) || sb_limiting(s, p10, p01, p11, base1, lf, minor1);
}

// The safety distance of texel (i, j) for class `cls` (0 x+, 1 x-, 2 y+, 3 y-), at most
// `cap` (`texel_distance` for `AllRays`).
uint sb_texel_distance(uint cls, uint i, uint j, uint cap) {
    uint ax = cls / 2u;
    bool forward = cls % 2u == 0u;
    double sg = ((forward) ? (1.0lf) : (-1.0lf));
    uint lm = sb_main_len(ax);
    uint ln = sb_minor_len(ax);
    uint m = i;
    uint n = j;
    if (ax == 1u) {
        m = j;
        n = i;
    }
    SbSigma s = sb_sigma_of(ax, m, n);
    double at_lo = s.h + s.below * (s.lo - s.n);
    double at_hi = s.h + s.above * (s.hi - s.n);
    // The ray set lowers no plane (e = 0): `floor + (e - e * 2^-20)`.
    double lowest = sb_min(sb_min(at_lo, s.h), at_hi) + 0.0lf;
    uint per_line = sb_strips(ax);
    uint base = 0u;
    if (ax == 1u) {
        base = 3u * (hf_safety_pass.width - 1u) * sb_strips(0u);
    }
    uint chan = ((forward) ? (1u) : (2u));
    uint ahead = ((forward) ? (lm - 1u - m) : (m));
    uint columns = min(cap, ahead);
    for (uint k = 0u; k < columns; k++) {
        uint column = ((forward) ? (m + k) : (m - 1u - k));
        // The band: cells l0..l1 (`band_cells`).
        uint l0 = ((n >= k + 2u) ? (n - (k + 2u)) : (0u));
        uint l1 = min(n + k + 1u, ln - 2u) + 1u;
        for (uint b = l0 / SB_STRIP; b < (l1 + SB_STRIP - 1u) / SB_STRIP; b++) {
            // A strip is skipped when no plane in it rises above the lowest point.
            uint at = base + 3u * (column * per_line + b);
            double top = double(hf_safety_scratch[at]);
            double beta = double(hf_safety_scratch[at + chan]);
            double kf = double(k);
            if (top + sb_max(beta * kf, beta * (kf + 1.0lf)) <= lowest) {
                continue;
            }
            for (uint l = max(l0, b * SB_STRIP); l < min(l1, b * SB_STRIP + SB_STRIP); l++) {
                if (sb_cell_limits(s, ax, sg, m, column, l)) {
                    return k;
                }
            }
        }
    }
    return cap;
}

// Byte `index` of the map (kind 1).
uint sb_map_byte(uint index) {
    SafetyBakePass p = hf_safety_pass;
    uint i = index % p.width;
    uint row = index / p.width;
    if (p.isotropic == 0u) {
        return max(sb_texel_distance(row % 4u, i, row / 4u, p.cap), p.least);
    }
    uint v = p.cap;
    for (uint cls = 0u; cls < 4u && v != 0u; cls++) {
        v = sb_texel_distance(cls, i, row, v);
    }
    return max(v, p.least);
}

// Item `gid` of the pass.
void safety_bake_item(uvec3 gid) {
    SafetyBakePass p = hf_safety_pass;
    uint item = gid.y * p.grid_width + gid.x;
    if (gid.x >= p.grid_width || item >= p.items) {
        return;
    }
    if (p.kind == 0u) {
        sb_strip_slot(item);
        return;
    }
    // Output word `item`: bytes 4 item .. 4 item + 3 of the map.
    uint bytes = p.width * p.height;
    if (p.isotropic == 0u) {
        bytes = 4u * bytes;
    }
    uint word = 0u;
    for (uint b = 0u; b < 4u; b++) {
        uint index = 4u * item + b;
        if (index < bytes) {
            word = word | (sb_map_byte(index) << (8u * b));
        }
    }
    hf_safety_out[item] = word;
}

// The entry point: one invocation per item.
layout(local_size_x = 8, local_size_y = 8) in;
void main() {
    safety_bake_item(gl_GlobalInvocationID);
}
