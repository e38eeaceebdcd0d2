// Generated from shaders/wgsl/maxmip.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/maxmip.rs: the hierarchical march over the maximum mipmap
// (Tevs et al. 2008) with exact options (Ascent::OneLevel, no LOD, exact bilinear).
//
// Texture layout (docs/DESIGN.md, "Texture layouts", maxmip pyramid): `hf_pyramid`, the levels as the uniform
// `hf_maxmip` (WGSL: `levels`, `level[l]` = (width, height, offset, 0)) or `hf_levels`,
// `hf_level_dims`, `hf_level_offset` (GLSL).

uniform sampler2D hf_pyramid;

uniform int hf_levels;
uniform ivec2 hf_level_dims[HF_MAX_LEVELS];
uniform int hf_level_offset[HF_MAX_LEVELS];

// The level count, and level l's (width, height, offset, 0).
int maxmip_levels() { return hf_levels; }
ivec4 maxmip_level(uint level) { return ivec4(hf_level_dims[level], hf_level_offset[level], 0); }

// `u32::ilog2` (GLSL 3.30 has no findMSB); v >= 1.
uint maxmip_ilog2(uint v) {
    uint r = 0u;
    while (v > 1u) {
        v >>= 1u;
        r += 1u;
    }
    return r;
}

// `u32::trailing_zeros` (GLSL 3.30 has no findLSB).
uint maxmip_trailing_zeros(uint v) {
    uint r = 0u;
    while (r < 32u && (v & 1u) == 0u) {
        v >>= 1u;
        r += 1u;
    }
    return r;
}

// `MaxMip::texel`: texel (i, j) of `level`, the highest sample of that node's cells.
float maxmip_texel(uint level, uint i, uint j) {
    ivec4 l = maxmip_level(level);
    int k = l.z + int(j) * l.x + int(i);
    return texelFetch(hf_pyramid, ivec2(k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH), 0).r;
}

// `sync_axis`: moves one axis to the cell the ray is in just after parameter t, from
// cell i inside the node's cells [lo, hi); `exact` says whether the last boundary
// crossed lies exactly at t.
uint maxmip_sync_axis(uint i, int step, uint lo, uint hi, float o, float d, float t, inout bool exact) {
    // The estimate; x >= 0, so truncation is the floor.
    float x = real_clamp_to(o + t * d, float(lo), float(hi - 1u));
    uint j = uint(x);
    if (step > 0) {
        j = max(j, i);
        while (j > i && (float(j) - o) / d > t) {
            j -= 1u;
        }
        while (j + 1u < hi && (float(j + 1u) - o) / d <= t) {
            j += 1u;
        }
        exact = j != i && (float(j) - o) / d == t;
    } else {
        j = min(j, i);
        while (j < i && (float(j + 1u) - o) / d > t) {
            j += 1u;
        }
        while (j > lo && (float(j) - o) / d <= t) {
            j -= 1u;
        }
        exact = j != i && (float(j + 1u) - o) / d == t;
    }
    return j;
}

// `entry_wall`: normal of the wall a cell was entered through (up at the start).
vec3 maxmip_entry_wall(ivec2 on, ivec2 step) {
    if (on[0] >= 0) {
        return vec3(((step[0] > 0) ? (-1.0) : (1.0)), 0.0, 0.0);
    } else if (on[1] >= 0) {
        return vec3(0.0, ((step[1] > 0) ? (-1.0) : (1.0)), 0.0);
    }
    return vec3(0.0, 0.0, 1.0);
}

// `trace`: the first hit on `surface`, the one of dda_trace; corner planes are traced
// by dda_trace.
Trace maxmip_trace(uint surface, Query q) {
//#if any_surface
    if (surface == HF_SURFACE_CORNER_PLANES) {
//#endif
//#if corner_planes
        return dda_trace(surface, q);
//#endif
//#if any_surface
    }
//#endif
//#if triangles|bilinear|height_planes|view_linear|qu_triangles
    Span span;
    if (!dda_clip(q, span)) {
        return trace_miss(0u, real_infinity());
    }
    vec3 o = q.origin;
    vec3 d = q.dir;
    uvec2 cells = dda_cells();
    ivec2 step = ivec2(dda_step_of(d[0]), dda_step_of(d[1]));
    vec3 p = query_at(q, span.t0);
    uvec2 cell = uvec2(dda_cell_index(real_clamp_to(p[0], 0.0, float(cells[0])), d[0], cells[0]), dda_cell_index(real_clamp_to(p[1], 0.0, float(cells[1])), d[1], cells[1]));
    uint top = uint(maxmip_levels()) - 1u;
    // Start where nodes are a quarter to an eighth of the ray's horizontal reach.
    float reach = real_max(abs(d[0]), abs(d[1])) * (span.t1 - span.t0);
    uint msb = maxmip_ilog2(uint(real_min(reach, 1073741824.0)) + 1u);
    uint start_level = ((msb >= 2u) ? (msb - 2u) : (0u));
    uint level = min(start_level, top);
    float t = span.t0;
    bool start = true;
    // How the current cell was entered: on[axis] >= 0 through a centerline crossing or a
    // side of the footprint.
    ivec2 on = dda_entry_on(surface, span);
    uint fetches = 0u;
    float clearance = real_infinity();
    for (;;) {
        // The node holding the cell at this level, and where the ray leaves it.
        uvec2 lo;
        uvec2 hi;
        uvec2 bound;
        vec2 t_out = vec2(real_infinity());
        for (int k = 0; k < 2; k++) {
            lo[k] = (cell[k] >> level) << level;
            hi[k] = min(lo[k] + (1u << level), cells[k]);
            bound[k] = ((step[k] > 0) ? (hi[k]) : (lo[k]));
            if (step[k] != 0) {
                t_out[k] = (float(bound[k]) - o[k]) / d[k];
            }
        }
        float t_next = real_min(t_out[0], t_out[1]);
        bool crossing = t_next < span.t1;
        float tb = ((crossing) ? (real_max(t_next, t)) : (span.t1));
        vec3 pb = query_at(q, tb);
        float top_z = maxmip_texel(level, cell[0] >> level, cell[1] >> level);
        fetches += 1u;
        float low = real_min(p[2], pb[2]);
        if (low > top_z) {
            clearance = real_min(clearance, low - top_z);
        } else if (level > 0u) {
            level -= 1u;
            continue;
        } else {
            // Level 0: the exact test of dda_trace, on the same shared edge clearances.
            vec4 c = surface_corners(cell[0], cell[1]);
            fetches += 4u;
            vec3 a;
            float ca = dda_local_clearance(surface, c, cell, p, on, a);
            if (ca <= 0.0 && (start || surface_is_continuous(surface))) {
                Hit hit;
                if (start) {
                    hit = dda_start_hit(surface, span, c, cell, a, p);
                } else {
                    // A graze of the edge the ray came in through.
                    hit = Hit(t, p, cell, surface_cell_normal(surface, c, a[0], a[1]), 0u);
                }
                float cl;
                if (start) {
                    cl = dda_start_clearance(span, ca);
                } else {
                    cl = real_min(clearance, ca);
                }
                return trace_hit(hit, fetches, cl);
            }
            ivec2 exit_on = ivec2(((crossing && t_out[0] <= t_next) ? (int(step[0] > 0)) : (-1)), ((crossing && t_out[1] <= t_next) ? (int(step[1] > 0)) : (-1)));
            vec3 b;
            float cb = dda_local_clearance(surface, c, cell, pb, exit_on, b);
            vec3 wall = maxmip_entry_wall(on, step);
            SegmentHit seg = surface_segment_hit(surface, c, a, b, ca, cb, wall);
            clearance = real_min(clearance, seg.clearance);
            if (seg.has_hit) {
                return trace_hit(dda_segment_point(seg, cell, a, b, t, tb), fetches, clearance);
            }
        }
        // Leave the node: step over the crossed boundaries, bring the other axis up to
        // date, ascend.
        if (!crossing) {
            return trace_miss(fetches, clearance);
        }
        uint crossed_level = level;
        for (int k = 0; k < 2; k++) {
            if (step[k] != 0 && t_out[k] <= t_next) {
                if (bound[k] == ((step[k] > 0) ? (cells[k]) : (0u))) {
                    return trace_miss(fetches, clearance);
                }
                cell[k] = ((step[k] > 0) ? (bound[k]) : (bound[k] - 1u));
                on[k] = int(step[k] < 0);
                crossed_level = max(crossed_level, maxmip_trailing_zeros(bound[k]));
            } else if (step[k] != 0 && level > 0u) {
                bool exact;
                cell[k] = maxmip_sync_axis(cell[k], step[k], lo[k], hi[k], o[k], d[k], t_next, exact);
                on[k] = ((exact) ? (int(step[k] < 0)) : (-1));
            } else {
                on[k] = -1;
            }
        }
        level = min(((crossed_level > level) ? (level + 1u) : (level)), top);
        t = tb;
        p = pb;
        start = false;
    }
    return trace_miss(fetches, clearance);
//#endif
}
