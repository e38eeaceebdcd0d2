// Generated from shaders/wgsl/multires.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/multires.rs: the multiresolution walk (Qu et al. 2003, after
// Cohen-Or et al. 1996), approximate: the exact traversal's walk on coarser grids
// (level l: every 2^l-th sample, cells cut at the field's edge) as the ray goes
// farther, level floor(log2(dist / range)) at distance `dist`, 0 under 2 range.

// `u32::ilog2` (x > 0), by shifts: GLSL 3.30 has no findMSB.
uint multires_ilog2(uint x) {
    uint n = 0u;
    for (uint v = x; v > 1u; v = v >> 1u) {
        n += 1u;
    }
    return n;
}

// `level_at`: floor(log2(dist / range)), 0 under 2 range, at most `top`.
uint multires_level_at(float dist, float range, uint top) {
    float v = dist / range;
    if (v >= 2.0) {
        // 4294967040 is the largest f32 under 2^32 (the CPU saturates at u32::MAX).
        return min(multires_ilog2(uint(real_min(v, 4294967040.0))), top);
    }
    return 0u;
}

// `top_level`: the first level whose cell covers the longer axis (ceil(log2)).
uint multires_top_level(uvec2 lim) {
    uint m = max(max(lim[0], lim[1]), 1u);
    uint f = multires_ilog2(m);
    return (((m & (m - 1u)) == 0u) ? (f) : (f + 1u));
}

// `trace`: traces q on `surface` with the multiresolution walk for the one-texel
// distance `range_in` (0 is taken as 1). Four fetches per cell of any level.
Trace multires_trace(uint surface, Query q, uint range_in) {
    Span span;
    if (!dda_clip_surface(surface, q, span)) {
        return trace_miss(0u, real_infinity());
    }
    vec3 o = q.origin;
    vec3 d = q.dir;
    uvec2 lim = uvec2(field_width() - 1u, field_height() - 1u);
    uint top = multires_top_level(lim);
    float len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    float range = float(max(range_in, 1u));
    ivec2 step = ivec2(dda_step_of(d[0]), dda_step_of(d[1]));
    vec3 p0 = query_at(q, span.t0);
    uint level = multires_level_at(real_max(span.t0, 0.0) * len, range, top);
    uvec2 cell;
    for (int k = 0; k < 2; k++) {
        float x = real_clamp_to(p0[k], 0.0, float(lim[k]));
        cell[k] = dda_cell_index(x, d[k], lim[k]) >> level;
    }
    float ta = span.t0;
    uint fetches = 0u;
    float clearance = real_infinity();
    vec3 wall = vec3(0.0, 0.0, 1.0);
    if (span.entry == HF_ENTRY_SIDE) {
        wall = span.entry_normal;
    }
    for (;;) {
        uint size = 1u << level;
        uvec2 lo = uvec2(cell[0] * size, cell[1] * size);
        uvec2 hi = uvec2(min(lo[0] + size, lim[0]), min(lo[1] + size, lim[1]));
        // Where the ray leaves the cell along each axis.
        vec2 exit = vec2(real_infinity());
        for (int k = 0; k < 2; k++) {
            if (step[k] == 1) {
                exit[k] = (float(hi[k]) - o[k]) / d[k];
            } else if (step[k] == -1) {
                exit[k] = (float(lo[k]) - o[k]) / d[k];
            }
        }
        float t_next = real_min(exit[0], exit[1]);
        float tb = span.t1;
        if (t_next < span.t1) {
            tb = real_max(t_next, ta);
        }
        vec4 c = vec4(field_at(lo[0], lo[1]), field_at(hi[0], lo[1]), field_at(lo[0], hi[1]), field_at(hi[0], hi[1]));
        fetches += 4u;
        vec2 extent = vec2(float(hi[0] - lo[0]), float(hi[1] - lo[1]));
        vec3 pa = query_at(q, ta);
        vec3 pb = query_at(q, tb);
        vec3 a = vec3(real_clamp_to((pa[0] - float(lo[0])) / extent[0], 0.0, 1.0), real_clamp_to((pa[1] - float(lo[1])) / extent[1], 0.0, 1.0), pa[2]);
        vec3 b = vec3(real_clamp_to((pb[0] - float(lo[0])) / extent[0], 0.0, 1.0), real_clamp_to((pb[1] - float(lo[1])) / extent[1], 0.0, 1.0), pb[2]);
        float ca = a[2] - surface_cell_height(surface, c, a[0], a[1]);
        if (ca <= 0.0) {
            // Under the surface where this cell's segment begins: at the span's start, as
            // the exact march flags it; later, a coarser cell rose over the ray.
            vec2 g = surface_cell_gradient(surface, c, a[0], a[1]);
            vec3 n = math_normal_from_gradient(g[0] / extent[0], g[1] / extent[1]);
            uint flags = 0u;
            if (ta == span.t0 && span.entry == HF_ENTRY_SIDE) {
                n = span.entry_normal;
                flags = HF_FLAG_SIDE;
            } else if (ta == span.t0 && span.entry == HF_ENTRY_START) {
                flags = HF_FLAG_ORIGIN_INSIDE;
            }
            uvec2 fine = uvec2(min(uint(real_max(pa[0], 0.0)), lim[0] - 1u), min(uint(real_max(pa[1], 0.0)), lim[1] - 1u));
            return trace_hit(Hit(ta, pa, fine, n, flags), fetches, real_min(clearance, -ca));
        }
        float cb = b[2] - surface_cell_height(surface, c, b[0], b[1]);
        SegmentHit seg = surface_segment_hit(surface, c, a, b, ca, cb, wall);
        clearance = real_min(clearance, seg.clearance);
        if (seg.has_hit) {
            float s = seg.s;
            float t = ta + s * (tb - ta);
            vec3 p = query_at(q, t);
            float u = a[0] + s * (b[0] - a[0]);
            float v = a[1] + s * (b[1] - a[1]);
            vec3 n = wall;
            if ((seg.flags & HF_FLAG_WALL) == 0u) {
                vec2 g = surface_cell_gradient(surface, c, u, v);
                n = math_normal_from_gradient(g[0] / extent[0], g[1] / extent[1]);
            }
            uvec2 fine = uvec2(min(uint(real_max(p[0], 0.0)), lim[0] - 1u), min(uint(real_max(p[1], 0.0)), lim[1] - 1u));
            return trace_hit(Hit(t, p, fine, n, seg.flags), fetches, clearance);
        }
        if (t_next >= span.t1) {
            break;
        }
        bool leave = false;
        for (int k = 0; k < 2; k++) {
            if (exit[k] <= t_next) {
                int next = int(cell[k]) + step[k];
                if (next < 0 || uint(next) * size >= lim[k]) {
                    leave = true;
                    break;
                }
                cell[k] = uint(next);
            }
        }
        if (leave) {
            break;
        }
        // The face entered (x's when the ray passes exactly through a corner).
        int k = ((exit[0] > t_next) ? (1) : (0));
        wall = vec3(0.0);
        wall[k] = ((step[k] > 0) ? (-1.0) : (1.0));
        ta = tb;
        uint coarser = multires_level_at(real_max(tb, 0.0) * len, range, top);
        if (coarser > level) {
            cell = uvec2(cell[0] >> (coarser - level), cell[1] >> (coarser - level));
            level = coarser;
        }
    }
    return trace_miss(fetches, clearance);
}
