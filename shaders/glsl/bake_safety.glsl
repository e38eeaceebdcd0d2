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
layout(std430, binding = 15) readonly buffer HfNbuffer { float hf_nbuffer[]; };
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

// One triangle in the frame of a class and a texel (`Tri`): its vertices (forward
// distance, minor coordinate), its plane's height `base` on the centerline at minor
// coordinate `at`, its minor and forward slopes.
struct SbTri {
    dvec2 v0;
    dvec2 v1;
    dvec2 v2;
    double base;
    double at;
    double minor_slope;
    double forward_slope;
};

// The plane's height on the centerline at minor coordinate y (`Tri::height_on_line`).
double sb_on_line(SbTri t, double y) {
    return t.base + t.minor_slope * (y - t.at);
}

// Whether triangle t limits some ray from the segment (`AllRays::limiting`).
bool sb_limiting(SbSigma s, SbTri t) {
    // The core starts from ±infinity: min(+inf, a) is a.
    double lo = sb_min(sb_min(t.v0.y - t.v0.x, t.v1.y - t.v1.x), t.v2.y - t.v2.x);
    double hi = sb_max(sb_max(t.v0.y + t.v0.x, t.v1.y + t.v1.x), t.v2.y + t.v2.x);
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
    SbTri t0;
    SbTri t1;
};

// The triangles of cell (cm, l) (main, minor indices of axis ax) for the texel of main
// index m and the class direction sg (`cell_tris`).
SbTris sb_cell_tris(uint ax, double sg, uint m, uint cm, uint l) {
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
        return SbTris(SbTri(p00, p10, p11, base0, lf, minor0, sg * main0), SbTri(p00, p01, p11, base1, lf, minor1, sg * main1));
    }
    return SbTris(SbTri(p00, p10, p01, base0, lf, minor0, sg * main0), SbTri(p10, p01, p11, base1, lf, minor1, sg * main1));
}

// Whether either triangle of cell (cm, l) limits (`cell_limits`).
bool sb_cell_limits(SbSigma s, uint ax, double sg, uint m, uint cm, uint l) {
    SbTris tris = sb_cell_tris(ax, sg, m, cm, l);
    return sb_limiting(s, tris.t0) || sb_limiting(s, tris.t1);
}

// A texel and class in the class's frame: main axis, direction, samples along and
// across the main axis, the texel's main and minor indices, the surface over its
// segment and that surface's heights at the segment's ends (`Sigma::end_heights`).
struct SbTexel {
    uint ax;
    bool forward;
    double sg;
    uint lm;
    uint ln;
    uint m;
    uint n;
    SbSigma sigma;
    double at_lo;
    double at_hi;
};

// Texel (i, j) for class `cls` (0 x+, 1 x-, 2 y+, 3 y-).
SbTexel sb_texel(uint cls, uint i, uint j) {
    uint ax = cls / 2u;
    bool forward = cls % 2u == 0u;
    uint m = i;
    uint n = j;
    if (ax == 1u) {
        m = j;
        n = i;
    }
    SbSigma s = sb_sigma_of(ax, m, n);
    double at_lo = s.h + s.below * (s.lo - s.n);
    double at_hi = s.h + s.above * (s.hi - s.n);
    return SbTexel(ax, forward, ((forward) ? (1.0lf) : (-1.0lf)), sb_main_len(ax), sb_minor_len(ax), m, n, s, at_lo, at_hi);
}

// The safety distance of texel (i, j) for class `cls`, at most `cap`
// (`texel_distance` for `AllRays`).
uint sb_texel_distance(uint cls, uint i, uint j, uint cap) {
    SbTexel t = sb_texel(cls, i, j);
    // The ray set lowers no plane (e = 0): `floor + (e - e * 2^-20)`.
    double lowest = sb_min(sb_min(t.at_lo, t.sigma.h), t.at_hi) + 0.0lf;
    uint per_line = sb_strips(t.ax);
    uint base = 0u;
    if (t.ax == 1u) {
        base = 3u * (hf_safety_pass.width - 1u) * sb_strips(0u);
    }
    uint chan = ((t.forward) ? (1u) : (2u));
    uint ahead = ((t.forward) ? (t.lm - 1u - t.m) : (t.m));
    uint columns = min(cap, ahead);
    for (uint k = 0u; k < columns; k++) {
        uint column = ((t.forward) ? (t.m + k) : (t.m - 1u - k));
        // The band: cells l0..l1 (`band_cells`).
        uint l0 = ((t.n >= k + 2u) ? (t.n - (k + 2u)) : (0u));
        uint l1 = min(t.n + k + 1u, t.ln - 2u) + 1u;
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
                if (sb_cell_limits(t.sigma, t.ax, t.sg, t.m, column, l)) {
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

// ---- cylinder-cones (N-buffer slopes) ----

// floor(log2(v)) of v > 0.
uint sb_log2(uint v) { return uint(findMSB(v)); }

// The N-buffer levels of the reach `cap` (cc.rs `levels`).
uint sb_levels(uint cap) {
    return sb_log2(2u * cap + 6u) + 1u;
}

// Where axis ax's N-buffers start, and their elements per level (`nb_layout`).
uint sb_nb_base(uint ax, uint levels) {
    uint w = hf_safety_pass.width;
    if (ax == 0u) {
        return 0u;
    }
    return levels * (w + (w - 1u + 7u) / 8u) * hf_safety_pass.height;
}
uint sb_nb_level(uint ax) {
    uint lm = sb_main_len(ax);
    return (lm + (lm - 1u + 7u) / 8u) * sb_minor_len(ax);
}

// The highest sample over cross samples a..=b of the sample column whose level 0
// starts at `at` (`range_max`), for levels up to `top`, `level` elements apart.
double sb_range_max(uint at, uint a, uint b, uint level, uint top) {
    uint len = b - a + 1u;
    uint l = min(sb_log2(len), top);
    uint w = 1u << l;
    uint first = at + l * level + a;
    uint last = first + len - w;
    float m = ((hf_nbuffer[last] > hf_nbuffer[first]) ? (hf_nbuffer[last]) : (hf_nbuffer[first]));
    for (uint y = first + w; y < last; y += w) {
        m = ((hf_nbuffer[y] > m) ? (hf_nbuffer[y]) : (m));
    }
    return double(m);
}

// The slope of a code's t (`decode_t`).
double sb_decode_t(int t) {
    return double(t * abs(t)) / 2048.0lf;
}

// The slope code of s rounded up (`encode_slope`; 255 past S_MAX).
uint sb_encode_slope(double s) {
    // S_MAX = 126 * 126 / 2048.
    if (s > 7.751953125lf) {
        return 255u;
    }
    int t;
    if (s >= 0.0lf) {
        double x = sqrt(2048.0lf * s);
        t = int(x);
        if (double(t) < x) {
            t = t + 1;
        }
    } else {
        t = -int(sb_min(sqrt(-2048.0lf * s), 128.0lf));
    }
    if (t < 126 && sb_decode_t(t) < s) {
        t = t + 1;
    }
    if (sb_decode_t(t) < s) {
        return 255u;
    }
    return uint(t + 128);
}

// The smallest slope a code stands for that is >= s (`code_ceiling`; +inf past S_MAX,
// returned as the flag `inf`).
struct SbSlope {
    double s;
    bool inf;
};

SbSlope sb_code_ceiling(double s) {
    uint code = sb_encode_slope(s);
    if (code == 255u) {
        return SbSlope(0.0lf, true);
    }
    return SbSlope(sb_decode_t(int(code) - 128), false);
}

// `raise`: s to code_ceiling(max(s, t)).
SbSlope sb_raise(SbSlope s, double t) {
    if (!s.inf && t > s.s) {
        return sb_code_ceiling(t);
    }
    return s;
}

// The edge of the band a ray from the segment reaches that cuts cell c of column k,
// as the half-plane a u + b y + d >= 0 it keeps (`band_edge`; xyz, w = 1 when there is
// one).
dvec4 sb_band_edge(SbSigma s, double k, double c) {
    if (c + k < s.n) {
        return dvec4(1.0lf, 1.0lf, -s.lo, 1.0lf);
    }
    if (c + 1.0lf > s.n + k) {
        return dvec4(1.0lf, -1.0lf, s.hi, 1.0lf);
    }
    return dvec4(0.0lf, 0.0lf, 0.0lf, 0.0lf);
}

// `tri_slope`'s running state: the best slope (once one is taken: the core starts
// from -inf), and whether a point on the centerline lies above z_c.
struct SbTake {
    double best;
    bool taken;
    bool above;
};

// `tri_slope`'s `take` of point p.
SbTake sb_take(SbTake st, SbTri t, double zc, dvec2 p) {
    double z = sb_on_line(t, p.y) + t.forward_slope * p.x;
    double tol = 0.000000001lf * (1.0lf + abs(zc));
    if (p.x <= 0.000000001lf) {
        return SbTake(st.best, st.taken, st.above || z - zc > tol);
    }
    double slope = (z - zc) / p.x;
    if (!st.taken || slope > st.best) {
        return SbTake(slope, true, st.above);
    }
    return st;
}

// Vertex k of t.
dvec2 sb_vertex(SbTri t, uint k) {
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
SbSlope sb_tri_slope(SbTri t, double zc, dvec4 edge, SbSlope s) {
    SbTake st = SbTake(0.0lf, false, false);
    for (uint e = 0u; e < 3u; e++) {
        dvec2 p = sb_vertex(t, e);
        if (edge.w == 0.0lf) {
            st = sb_take(st, t, zc, p);
            continue;
        }
        dvec2 q = sb_vertex(t, (e + 1u) % 3u);
        double fp = edge.x * p.x + edge.y * p.y + edge.z;
        double fq = edge.x * q.x + edge.y * q.y + edge.z;
        if (fp >= 0.0lf) {
            st = sb_take(st, t, zc, p);
        }
        if ((fp >= 0.0lf) != (fq >= 0.0lf)) {
            double f = fp / (fp - fq);
            st = sb_take(st, t, zc, dvec2(p.x + f * (q.x - p.x), p.y + f * (q.y - p.y)));
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
uint sb_cone_code(uint cls, uint i, uint j, uint r, uint cap) {
    SbTexel t = sb_texel(cls, i, j);
    SbSigma sig = t.sigma;
    double zc = sb_max(sb_max(t.at_lo, sig.h), t.at_hi);
    uint levels = sb_levels(cap);
    uint level = sb_nb_level(t.ax);
    // Sample column c's level 0 starts at axis + c ln.
    uint axis = sb_nb_base(t.ax, levels);
    SbSlope s = SbSlope(-8.0lf, false);
    uint kend = min(cap, ((t.forward) ? (t.lm - 1u - t.m) : (t.m)));
    uint k0 = max(r, 1u);
    // The largest bound of the abscissas u in k0..=kend: the highest sample of the
    // sample column u ahead over the band of column u, less z_c, over u.
    if (k0 < kend) {
        double top = -8.0lf;
        for (uint u = k0; u <= kend; u++) {
            uint a = ((t.n >= u + 2u) ? (t.n - (u + 2u)) : (0u));
            uint b = min(t.n + u + 1u, t.ln - 2u) + 1u;
            uint sample_column = ((t.forward) ? (t.m + u) : (t.m - u));
            double bound = (sb_range_max(axis + sample_column * t.ln, a, b, level, levels - 1u) - zc) / double(u);
            top = ((bound > top) ? (bound) : (top));
        }
        s = sb_raise(s, top);
    }
    // Column 0, exactly, when the cylinder is empty: its bound (+inf when the near
    // side reaches above z_c), then its limiting triangles.
    if (r == 0u && kend > 0u) {
        uint a = ((t.n >= 2u) ? (t.n - 2u) : (0u));
        uint b = min(t.n + 1u, t.ln - 2u) + 1u;
        uint far_column = ((t.forward) ? (t.m + 1u) : (t.m - 1u));
        double top_near = sb_range_max(axis + t.m * t.ln, a, b, level, levels - 1u) - zc;
        double top_far = sb_range_max(axis + far_column * t.ln, a, b, level, levels - 1u) - zc;
        if (top_near > 0.0lf || (!s.inf && top_far / 1.0lf > s.s)) {
            uint cm = ((t.forward) ? (t.m) : (t.m - 1u));
            for (uint c = a; c < b && !s.inf; c++) {
                SbTris tris = sb_cell_tris(t.ax, t.sg, t.m, cm, c);
                dvec4 edge = sb_band_edge(sig, 0.0lf, double(c));
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
uint sb_cc_entry(uint e) {
    SafetyBakePass p = hf_safety_pass;
    uint i = e % p.width;
    uint row = e / p.width;
    uint cls = row % 4u;
    uint j = row / 4u;
    uint r = sb_texel_distance(cls, i, j, 255u);
    uint code = 255u;
    if (r < p.cap) {
        code = sb_cone_code(cls, i, j, r, p.cap);
    }
    return r | (code << 8u);
}

// No item left for an invocation (`sb_word_item`).
const uint SB_DONE = 0xffffffffu;

// The item of invocation `gid`: a strip slot is baked here (kind 0); an output word's
// index is returned; SB_DONE when nothing is left to do.
uint sb_word_item(uvec3 gid) {
    SafetyBakePass p = hf_safety_pass;
    uint item = gid.y * p.grid_width + gid.x;
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
void safety_bake_item(uvec3 gid) {
    SafetyBakePass p = hf_safety_pass;
    uint item = sb_word_item(gid);
    if (item == SB_DONE) {
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

// Item `gid` of a pass of the cylinder-cone bake: strip slots (kind 0), then the map's
// words, two entries each (kind 2).
void cc_bake_item(uvec3 gid) {
    SafetyBakePass p = hf_safety_pass;
    uint item = sb_word_item(gid);
    if (item == SB_DONE) {
        return;
    }
    uint entries = 4u * p.width * p.height;
    uint word = sb_cc_entry(2u * item);
    if (2u * item + 1u < entries) {
        word = word | (sb_cc_entry(2u * item + 1u) << 16u);
    }
    hf_safety_out[item] = word;
}

// The entry points: one invocation per item.
layout(local_size_x = 8, local_size_y = 8) in;
void main() {
#ifdef HF_CC_BAKE
    cc_bake_item(gl_GlobalInvocationID);
#else
    safety_bake_item(gl_GlobalInvocationID);
#endif
}
