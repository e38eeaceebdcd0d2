// Generated from shaders/wgsl/dda.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/dda.rs: the exact Amanatides-Woo traversal over cells with the
// exact per-cell test of the surface. Watertight as on the CPU: the clearance at each
// centerline crossing comes from that edge's two samples only and is shared by the
// cells on both sides; cell indices are integers and every crossing's t is recomputed
// from them.
//
// `Option<bool>` (the `on` vectors) is an i32: -1 = None, 0 = Some(false), 1 = Some(true).

// `Span<f32>`; `entry` is HF_ENTRY_START, HF_ENTRY_SIDE (normal in `entry_normal`) or
// HF_ENTRY_TOP.
struct Span {
    float t0;
    float t1;
    uint entry;
    vec3 entry_normal;
};

// `clip_surface`: clips a query to the box that holds `surface` over the field; false
// when the ray misses it.
bool dda_clip_surface(uint surface, Query q, inout Span span) {
    vec3 o = q.origin;
    vec3 d = q.dir;
    vec2 lim = vec2(float(field_width() - 1u), float(field_height() - 1u));
    float t0 = q.t_min;
    float t1 = q.t_max;
    uint entry = HF_ENTRY_START;
    vec3 entry_normal = vec3(0.0);
    span = Span(0.0, 0.0, HF_ENTRY_START, vec3(0.0));
    for (int axis = 0; axis < 2; axis++) {
        if (d[axis] == 0.0) {
            if (o[axis] < 0.0 || o[axis] > lim[axis]) {
                return false;
            }
            continue;
        }
        float a = (0.0 - o[axis]) / d[axis];
        float b = (lim[axis] - o[axis]) / d[axis];
        float near = ((d[axis] > 0.0) ? (a) : (b));
        float far = ((d[axis] > 0.0) ? (b) : (a));
        if (near > t0) {
            t0 = near;
            vec3 n = vec3(0.0);
            n[axis] = ((d[axis] > 0.0) ? (-1.0) : (1.0));
            entry = HF_ENTRY_SIDE;
            entry_normal = n;
        }
        t1 = real_min(t1, far);
    }
    float zmin = field_min_height();
    float zmax = field_max_height();
//#if corner_planes
    if (surface == HF_SURFACE_CORNER_PLANES) {
        float range = zmax - zmin;
        float lo = zmin - range;
        float hi = zmax + range;
        zmin = lo;
        zmax = hi;
    }
//#endif
    if (d[2] == 0.0) {
        if (o[2] > zmax) {
            return false;
        }
//#if upward
    } else if (d[2] > 0.0) {
        t1 = real_min(t1, (zmax - o[2]) / d[2]);
//#endif
    } else {
        float top = (zmax - o[2]) / d[2];
        if (top > t0) {
            t0 = top;
            entry = HF_ENTRY_TOP;
        }
        // Well under the lowest sample the ray is inside the solid: the hit comes first.
        float margin = 1.0 + (zmax - zmin);
        t1 = real_min(t1, real_max((zmin - margin - o[2]) / d[2], t0));
    }
    span = Span(t0, t1, entry, entry_normal);
    return t0 <= t1 && real_is_finite(t0) && real_is_finite(t1);
}

// One slab of `query_walked_back`: where `o + t d` is within [lo, hi], as (near, far)
// (far < near when never).
vec2 dda_slab(float o, float d, float lo, float hi) {
    if (d != 0.0) {
        float a = (lo - o) / d;
        float b = (hi - o) / d;
        return vec2(min(a, b), max(a, b));
    }
    float inf = real_infinity();
    return ((o < lo || o > hi) ? (vec2(inf, -inf)) : (vec2(-inf, inf)));
}

// `Query::walked_back` (core/src/ray.rs), in f32: the same points walked from a grid
// unit beyond where the ray leaves the box every surface lies in back to its start
// (origin kept, direction negated, t in [-end, -t_min]); a ray that misses the box as
// it is. How a shadow ray towards a light becomes the light's ray, an exterior one.
// The range may differ from the core's f64 one by rounding: its start is outside the
// box either way, and the march clips to the box.
Query query_walked_back(Query q) {
    float zmin = field_min_height();
    float zmax = field_max_height();
    float range = zmax - zmin;
    vec2 x = dda_slab(q.origin.x, q.dir.x, 0.0, float(field_width() - 1u));
    vec2 y = dda_slab(q.origin.y, q.dir.y, 0.0, float(field_height() - 1u));
    vec2 z = dda_slab(q.origin.z, q.dir.z, zmin - range, zmax + range);
    float near = max(max(x.x, y.x), z.x);
    float far = min(min(x.y, y.y), z.y);
    if (far < max(near, q.t_min)) {
        return q;
    }
    float end = q.t_max;
    if (far < q.t_max) {
        end = min(far + 1.0 / length(q.dir), q.t_max);
    }
    return Query(q.origin, -q.dir, -end, -q.t_min);
}

// `clip`: the box of the triangle surface (the sample range in z).
bool dda_clip(Query q, inout Span span) { return dda_clip_surface(HF_SURFACE_TRIANGLES, q, span); }

// `cell_index`: first cell index along one axis for coordinate x in [0, cells] moving
// with direction d; a point on a cell boundary belongs to the cell the ray moves into.
uint dda_cell_index(float x, float d, uint cells) {
    float f = floor(x);
    uint i = uint(f);
    if (d < 0.0 && f == x && i > 0u) {
        i -= 1u;
    }
    return min(i, cells - 1u);
}

// `step_of`.
int dda_step_of(float d) {
    if (d > 0.0) {
        return 1;
    } else if (d < 0.0) {
        return -1;
    }
    return 0;
}

// `next_crossing`: parameter of the next centerline crossing along one axis after cell i.
float dda_next_crossing(uint i, int step, float o, float d) {
    if (step == 1) {
        return (float(i + 1u) - o) / d;
    } else if (step == -1) {
        return (float(i) - o) / d;
    }
    return real_infinity();
}

// `local_clearance`: local point (written to `b`) and clearance of the grid point p in
// `cell`; on a centerline crossing (`on[axis] >= 0`) the height comes from that edge's
// two samples only, so both cells sharing the edge compute the same clearance.
float dda_local_clearance(uint surface, vec4 c, uvec2 cell, vec3 p, ivec2 on, inout vec3 b) {
    float lx = real_clamp_to(p[0] - float(cell[0]), 0.0, 1.0);
    if (on[0] >= 0) {
        lx = float(on[0]);
    }
    float ly = real_clamp_to(p[1] - float(cell[1]), 0.0, 1.0);
    if (on[1] >= 0) {
        ly = float(on[1]);
    }
    b = vec3(lx, ly, p[2]);
    float height;
    if (on[0] >= 0 && on[1] >= 0) {
        height = c[on[0] | (on[1] << 1u)];
    } else if (on[0] >= 0) {
        height = real_lerp(c[on[0]], c[on[0] + 2], (b)[1]);
    } else if (on[1] >= 0) {
        int k = on[1] << 1u;
        height = real_lerp(c[k], c[k + 1], (b)[0]);
    } else {
        height = surface_cell_height(surface, c, (b)[0], (b)[1]);
    }
    return (b)[2] - height;
}

// `entry_on`: how the span's first point lies on its cell's edges (a side entry of a
// continuous surface: on that side's edge).
ivec2 dda_entry_on(uint surface, Span span) {
//#if any_surface
    if (!surface_is_continuous(surface)) {
        return ivec2(-1);
    }
//#endif
//#if triangles|bilinear|view_linear|qu_triangles
    if (span.entry == HF_ENTRY_SIDE) {
        vec3 n = span.entry_normal;
        return ivec2(((n[0] != 0.0) ? (int(n[0] > 0.0)) : (-1)), ((n[1] != 0.0) ? (int(n[1] > 0.0)) : (-1)));
    }
//#endif
    return ivec2(-1);
}

// `start_clearance`: `Trace::clearance` of a hit where the span begins.
float dda_start_clearance(Span span, float ca) {
    return ((span.entry == HF_ENTRY_TOP) ? (real_infinity()) : (-ca));
}

// `start_hit`: the hit of a ray already under the surface where its span begins.
Hit dda_start_hit(uint surface, Span span, vec4 c, uvec2 cell, vec3 a, vec3 p0) {
    vec3 normal;
    uint flags;
    if (span.entry == HF_ENTRY_SIDE) {
        normal = span.entry_normal;
        flags = HF_FLAG_SIDE;
    } else if (span.entry == HF_ENTRY_START) {
        normal = surface_cell_normal(surface, c, a[0], a[1]);
        flags = HF_FLAG_ORIGIN_INSIDE;
    } else {
        normal = surface_cell_normal(surface, c, a[0], a[1]);
        flags = 0u;
    }
    return Hit(span.t0, p0, cell, normal, flags);
}

// `grid_cells`: the field's cells per axis (samples − 1).
uvec2 dda_cells() {
    return uvec2(field_width() - 1u, field_height() - 1u);
}

// `next_crossings`: the ray parameters of the next centerline crossing on each axis
// out of `cell` (infinity on an axis the ray does not move along).
vec2 dda_crossings(uvec2 cell, ivec2 step, Query q) {
    return vec2(dda_next_crossing(cell[0], step[0], q.origin[0], q.dir[0]), dda_next_crossing(cell[1], step[1], q.origin[1], q.dir[1]));
}

// `exit_of`: where the ray leaves the cell whose next centerline crossings are
// `t_cross` (entered at `ta`): tb, clamped to [ta, t1], and the axes it crosses
// there (none when the span ends first).
float dda_exit(vec2 t_cross, float ta, float t1, inout bvec2 cross) {
    float t_next = real_min(t_cross[0], t_cross[1]);
    if (t_next < t1) {
        cross = bvec2(t_cross[0] <= t_next, t_cross[1] <= t_next);
        return real_max(t_next, ta);
    }
    cross = bvec2(false);
    return t1;
}

// `exit_on`: how a cell's exit point lies on the centerline crossings `cross` (the
// `on` vector of local_clearance).
ivec2 dda_exit_on(ivec2 step, bvec2 cross) {
    return ivec2(((cross[0]) ? (int(step[0] > 0)) : (-1)), ((cross[1]) ? (int(step[1] > 0)) : (-1)));
}

// `next_entry`: the exit point `b` in the local coordinates of the next cell, entered
// across `cross`.
vec3 dda_next_entry(vec3 b, bvec2 cross) {
    return vec3(((cross[0]) ? (1.0 - b[0]) : (b[0])), ((cross[1]) ? (1.0 - b[1]) : (b[1])), b[2]);
}

// `segment_point`: the hit of `seg` on the segment a→b (local coordinates) of `cell`,
// from ta to tb: the point from the cell's integer corner plus local coordinates.
Hit dda_segment_point(SegmentHit seg, uvec2 cell, vec3 a, vec3 b, float ta, float tb) {
    float s = seg.s;
    vec3 point = vec3(float(cell[0]) + (a[0] + s * (b[0] - a[0])), float(cell[1]) + (a[1] + s * (b[1] - a[1])), a[2] + s * (b[2] - a[2]));
    return Hit(ta + s * (tb - ta), point, cell, seg.normal, seg.flags);
}

// `trace`: traces q cell by cell and returns the exact first hit on `surface`.
// Cost: four fetches (the corners) per cell visited.
Trace dda_trace(uint surface, Query q) {
    Span span;
    if (!dda_clip_surface(surface, q, span)) {
        return trace_miss(0u, real_infinity());
    }
    vec3 o = q.origin;
    vec3 d = q.dir;
    // Per-axis state, index 0 = x, 1 = y.
    uvec2 cells = dda_cells();
    vec3 p0 = query_at(q, span.t0);
    vec2 start = vec2(real_clamp_to(p0[0], 0.0, float(cells[0])), real_clamp_to(p0[1], 0.0, float(cells[1])));
    uvec2 cell = uvec2(dda_cell_index(start[0], d[0], cells[0]), dda_cell_index(start[1], d[1], cells[1]));
    ivec2 step = ivec2(dda_step_of(d[0]), dda_step_of(d[1]));
    vec4 c = surface_corners(cell[0], cell[1]);
    uint fetches = 4u;
    vec3 a;
    float ca = dda_local_clearance(surface, c, cell, vec3(start[0], start[1], p0[2]), dda_entry_on(surface, span), a);

    if (ca <= 0.0) {
        return trace_hit(dda_start_hit(surface, span, c, cell, a, p0), fetches, dda_start_clearance(span, ca));
    }

    float clearance = ca;
    float ta = span.t0;
    vec3 wall = vec3(0.0, 0.0, 1.0);
    vec2 t_cross = dda_crossings(cell, step, q);
    for (;;) {
        bvec2 cross;
        float tb = dda_exit(t_cross, ta, span.t1, cross);
        // Clearance at the exit point; on a centerline, from that edge's two samples only.
        ivec2 on = dda_exit_on(step, cross);
        vec3 b;
        float cb = dda_local_clearance(surface, c, cell, query_at(q, tb), on, b);
        SegmentHit seg = surface_segment_hit(surface, c, a, b, ca, cb, wall);
        clearance = real_min(clearance, seg.clearance);
        if (seg.has_hit) {
            return trace_hit(dda_segment_point(seg, cell, a, b, ta, tb), fetches, clearance);
        }
        if (!cross[0] && !cross[1]) {
            break;
        }
        bool leave = false;
        for (int k = 0; k < 2; k++) {
            if (cross[k]) {
                int next = int(cell[k]) + step[k];
                if (next < 0 || next >= int(cells[k])) {
                    leave = true;
                    break;
                }
                cell[k] = uint(next);
                t_cross[k] = dda_next_crossing(cell[k], step[k], o[k], d[k]);
            }
        }
        if (leave) {
            break;
        }
        // The face entered (x's when the ray passes exactly through a corner).
        int k = ((cross[0]) ? (0) : (1));
        wall = vec3(0.0);
        wall[k] = ((step[k] > 0) ? (-1.0) : (1.0));
        c = surface_corners(cell[0], cell[1]);
        fetches += 4u;
        a = dda_next_entry(b, cross);
        ca = cb;
        ta = tb;
    }
    return trace_miss(fetches, clearance);
}
