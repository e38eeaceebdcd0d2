// Generated from shaders/wgsl/safety.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/safety.rs (the march; the bake stays on the CPU): safety
// distances (Baboud, Eisemann, Seidel 2011) on the triangle surface, or (§7 of the
// paper, `MarchSurface`) on the view-linear surface from the same triangle-baked maps.
// The walk is the one of dda_trace up to the ray's first centerline of its main axis;
// then at each centerline m: fetch k, evaluate the clearance at m + k from the two
// samples on that centerline; above, jump; below, bisect on integer centerlines and
// finish with the exact cell test of the march's surface.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", safety): `hf_safety_map`, the overrides
// `hf_safety_variant` (directional or isotropic) and `hf_safety_classes` (the classes it
// holds; `SafetyMap::with_classes`). A ray of a class the map does not hold reads
// distance 0 without a fetch (it walks cell by cell, still exact).
//
// Ray sets (docs/DESIGN.md, "Ray sets"; `Rays`): the safety-distance or cylinder-cone
// map in use was baked for exterior rays only when `hf_rays_exterior` is 1, and for
// rays within `hf_rays_max_view_angle` degrees of the downward vertical (180: any
// direction), and over `hf_occluder_count` occluders (below). A ray outside the set
// reads distance 0 and no cone (one fetch counted, as for a class the map does not
// hold): it walks cell by cell, still exact.

uniform usampler2D hf_safety_map;
uniform uint hf_safety_variant = 0u;
uniform uint hf_safety_classes = 15u;
uniform uint hf_rays_exterior = 0u;
uniform float hf_rays_max_view_angle = 180.0;
//#if occluders

// Occluders (`Rays::occluders`, `Occluder`): a map baked over `hf_occluder_count` of
// them (0: none) serves only the rays whose line, up to where it leaves the field's
// footprint, passes over the solid under every triangle. Their corners (x, y, z) are
// texels (3k, 0), (3k + 1, 0) and (3k + 2, 0) of `hf_occluders`.
uniform sampler2D hf_occluders;
uniform uint hf_occluder_count = 0u;

// `footprint_exit`: where the line p + t d leaves the field's footprint
// [0, W - 1] x [0, H - 1], a little late; infinity when it never does or never meets it.
float safety_footprint_exit(vec3 p, vec3 d) {
    vec2 ends = vec2(float(field_width() - 1u), float(field_height() - 1u));
    float lo = -real_infinity();
    float hi = real_infinity();
    for (int a = 0; a < 2; a++) {
        if (d[a] != 0.0) {
            float t0 = (0.0 - p[a]) / d[a];
            float t1 = (ends[a] - p[a]) / d[a];
            lo = real_max(lo, real_min(t0, t1));
            hi = real_min(hi, real_max(t0, t1));
        } else if (p[a] < 0.0 || p[a] > ends[a]) {
            return real_infinity();
        }
    }
    if (lo > hi) {
        return real_infinity();
    }
    return hi + 1e-5 * (1.0 + abs(hi));
}

// `Occluder::dips_under`: whether the line p + t d, t <= t_hi, comes within the
// guard's margin of the solid under occluder k over its closed footprint. The core
// checks in f64 with the same margin, 1e-5 (1 + the largest coordinate of the
// triangle and of p): far above the difference.
bool safety_dips_under(uint k, vec3 p, vec3 d, float t_hi) {
    vec3 a = texelFetch(hf_occluders, ivec2(3u * k, 0u), 0).xyz;
    vec3 b = texelFetch(hf_occluders, ivec2(3u * k + 1u, 0u), 0).xyz;
    vec3 c = texelFetch(hf_occluders, ivec2(3u * k + 2u, 0u), 0).xyz;
    float area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    float orient = ((area > 0.0) ? (1.0) : (-1.0));
    float lo = -real_infinity();
    float hi = t_hi;
    for (uint e = 0u; e < 3u; e++) {
        vec3 e0 = ((e == 0u) ? (a) : (((e == 1u) ? (b) : (c))));
        vec3 e1 = ((e == 0u) ? (b) : (((e == 1u) ? (c) : (a))));
        float ex = e1[0] - e0[0];
        float ey = e1[1] - e0[1];
        float alpha = orient * (ex * (p[1] - e0[1]) - ey * (p[0] - e0[0]));
        float beta = orient * (ex * d[1] - ey * d[0]);
        if (beta > 0.0) {
            lo = real_max(lo, -alpha / beta);
        } else if (beta < 0.0) {
            hi = real_min(hi, -alpha / beta);
        } else if (alpha < 0.0) {
            return false;
        }
    }
    if (lo > hi) {
        return false;
    }
    float gx = ((b[2] - a[2]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[2] - a[2])) / area;
    float gy = ((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0])) / area;
    float depth0 = a[2] + gx * (p[0] - a[0]) + gy * (p[1] - a[1]) - p[2];
    float rate = gx * d[0] + gy * d[1] - d[2];
    vec3 big = max(max(abs(a), abs(b)), max(abs(c), abs(p)));
    float margin = 1e-5 * (1.0 + max(max(big[0], big[1]), big[2]));
    if (rate == 0.0) {
        return depth0 > -margin;
    }
    float end = ((rate < 0.0) ? (lo) : (hi));
    return !real_is_finite(end) || depth0 + rate * end > -margin;
}
//#endif

// `Rays::holds`: whether q is a ray of the map's set. The core checks in f64, here in
// f32; the set's margin (a millionth) is far above the difference.
bool safety_rays_hold(Query q) {
    if (hf_rays_exterior != 0u) {
        vec3 p = query_at(q, q.t_min);
        float w = float(field_width() - 1u);
        float h = float(field_height() - 1u);
        bool outside = p[0] < 0.0 || p[0] > w || p[1] < 0.0 || p[1] > h ||
                            p[2] < field_min_height() || p[2] > field_max_height();
        if (!outside) {
            return false;
        }
    }
    if (hf_rays_max_view_angle < 180.0) {
        // `Rays::rise_bound`: a rise of at most tau = -cot(angle) per unit of
        // horizontal distance.
        float a = hf_rays_max_view_angle * 0.017453292519943295;
        float tau = -cos(a) / sin(a);
        vec3 d = q.dir;
        float run = sqrt(d[0] * d[0] + d[1] * d[1]);
        float bound = tau * run - 1e-6 * (abs(tau) * run + abs(d[2]));
        if (d[2] > bound) {
            return false;
        }
    }
//#if occluders
    if (hf_occluder_count > 0u) {
        float t_hi = safety_footprint_exit(q.origin, q.dir);
        for (uint k = 0u; k < hf_occluder_count; k++) {
            if (safety_dips_under(k, q.origin, q.dir, t_hi)) {
                return false;
            }
        }
    }
//#endif
    return true;
}

// `RayClasses::contains`: whether the set `classes` (HF_RAYS_* bits) holds ray_class.
bool safety_holds(uint classes, uint ray_class) { return (classes & (1u << ray_class)) != 0u; }

// `RayClasses::count`: how many of the four classes `classes` holds (bit by bit:
// GLSL 3.30 has no bitCount).
uint safety_class_count(uint classes) {
    return (classes & 1u) + ((classes >> 1u) & 1u) + ((classes >> 2u) & 1u) + ((classes >> 3u) & 1u);
}

// `ClassRows::index` (the row): texel row j of a class-per-row map holding `classes`
// (HF_RAYS_* bits, which must hold ray_class) is row n j + slot for its n classes, slot
// = `RayClasses::slot(ray_class)`, the held classes before ray_class.
uint safety_class_row(uint classes, uint ray_class, uint j) {
    return safety_class_count(classes) * j + safety_class_count(classes & ((1u << ray_class) - 1u));
}

// `SafetyMap::distance`: safety distance of texel (i, j) for `ray_class` (0, without a
// fetch, when the map does not hold it).
uint safety_distance(uint ray_class, uint i, uint j) {
    if (!safety_holds(hf_safety_classes, ray_class)) {
        return 0u;
    }
//#if any_variant
    uint row = ((hf_safety_variant == HF_SAFETY_DIRECTIONAL) ? (safety_class_row(hf_safety_classes, ray_class, j)) : (j));
    return texelFetch(hf_safety_map, ivec2(i, row), 0).r;
//#else
//#if directional
    return texelFetch(hf_safety_map, ivec2(i, safety_class_row(hf_safety_classes, ray_class, j)), 0).r;
//#endif
//#if isotropic
    return texelFetch(hf_safety_map, ivec2(i, j), 0).r;
//#endif
//#endif
}

// `axis_of`: main axis (0 = x, 1 = y) of a ray_class.
int safety_axis_of(uint ray_class) {
    return ((ray_class == HF_RAY_CLASS_X_POS || ray_class == HF_RAY_CLASS_X_NEG) ? (0) : (1));
}

// `sample`: sample at main index m, minor index n of axis ax.
float safety_sample(int ax, uint m, uint n) {
    if (ax == 0) {
        return field_at(m, n);
    }
    return field_at(n, m);
}

// `extents`: samples along (main, minor) of axis ax.
uvec2 safety_extents(int ax) {
    return ((ax == 0) ? (uvec2(field_width(), field_height())) : (uvec2(field_height(), field_width())));
}

// `Line<f32>`: the ray where it crosses the main-axis centerline m.
struct SafetyLine {
    uint m;
    float t;
    vec3 p;
    float c;
    uint edge;
    uint texel;
    float tol;
};

// `line_at`: evaluates the crossing of centerline m of axis ax; two fetches.
SafetyLine safety_line_at(Query q, int ax, uint m) {
    vec3 o = q.origin;
    vec3 d = q.dir;
    int mi = 1 - ax;
    uint ln = safety_extents(ax)[1];
    float t = (float(m) - o[ax]) / d[ax];
    vec3 p = query_at(q, t);
    p[ax] = float(m);
    float y = real_clamp_to(p[mi], 0.0, float(ln - 1u));
    uint edge = min(uint(floor(y)), ln - 2u);
    float v = y - float(edge);
    float h0 = safety_sample(ax, m, edge);
    float h1 = safety_sample(ax, m, edge + 1u);
    float c = p[2] - real_lerp(h0, h1, v);
    uint texel = ((v < 0.5) ? (edge) : (edge + 1u));
    float ys = 1.0 + abs(o[mi]) + abs(p[mi]);
    float zs = 1.0 + abs(o[2]) + abs(p[2]) + abs(h0) + abs(h1 - h0) * ys;
    float rel = real_max(32.0 * REAL_EPSILON, 9.313225746154785e-10);
    float tol = ((8.0 * REAL_EPSILON * ys > HF_SAFETY_SEG_PAD) ? (real_infinity()) : (rel * zs));
    return SafetyLine(m, t, p, c, edge, texel, tol);
}

// `Step`: what one stretch of cell-by-cell walking came to.
const int SAFETY_STEP_HIT = 0;
const int SAFETY_STEP_LINE = 1;
const int SAFETY_STEP_END = 2;

// `March`: the state of the march, the cell walk of dda_trace on `surface`.
struct SafetyMarch {
    uint surface;
    Span span;
    int ax;
    ivec2 step;
    uvec2 cells;
    uvec2 ic;
    vec4 c;
    bool stale;
    vec3 a;
    float ca;
    float ta;
    vec3 wall;
    vec2 tn;
    uint fetches;
    float clearance;
};

// `March::line`: a centerline evaluation, counted.
SafetyLine safety_march_line(inout SafetyMarch mr, Query q, uint m) {
    (mr).fetches += 2u;
    SafetyLine l = safety_line_at(q, (mr).ax, m);
    if (l.c > 0.0) {
        (mr).clearance = real_min((mr).clearance, l.c);
    }
    return l;
}

// `March::wall_of`: normal of a wall facing the ray on `axis`.
vec3 safety_march_wall_of(SafetyMarch mr, int axis) {
    vec3 n = vec3(0.0);
    n[axis] = ((mr.step[axis] > 0) ? (-1.0) : (1.0));
    return n;
}

// `March::enter`: puts the walk just past the crossing l (above the surface).
void safety_march_enter(inout SafetyMarch mr, Query q, SafetyLine l) {
    int ax = (mr).ax;
    int mi = 1 - (mr).ax;
    vec3 o = q.origin;
    vec3 d = q.dir;
    (mr).ic[ax] = (((mr).step[ax] > 0) ? (l.m) : (l.m - 1u));
    float y = real_clamp_to(l.p[mi], 0.0, float((mr).cells[mi]));
    (mr).ic[mi] = dda_cell_index(y, d[mi], (mr).cells[mi]);
    (mr).a[ax] = (((mr).step[ax] > 0) ? (0.0) : (1.0));
    (mr).a[mi] = real_clamp_to(l.p[mi] - float((mr).ic[mi]), 0.0, 1.0);
    (mr).a[2] = l.p[2];
    (mr).ca = l.c;
    (mr).ta = l.t;
    (mr).wall = safety_march_wall_of(mr, ax);
    for (int k = 0; k < 2; k++) {
        (mr).tn[k] = dda_next_crossing((mr).ic[k], (mr).step[k], o[k], d[k]);
    }
    (mr).stale = true;
}

// `March::walk`: walks cell by cell, as dda_trace, up to the next main-axis
// centerline (SAFETY_STEP_LINE, `line`), the hit (SAFETY_STEP_HIT, `hit`), or the end.
int safety_march_walk(inout SafetyMarch mr, Query q, inout Hit hit, inout SafetyLine line) {
    int ax = (mr).ax;
    int mi = 1 - (mr).ax;
    vec3 o = q.origin;
    vec3 d = q.dir;
    hit = hit_none();
    line = SafetyLine(0u, 0.0, vec3(0.0), 0.0, 0u, 0u, 0.0);
    for (;;) {
        if ((mr).stale) {
            (mr).c = surface_corners((mr).ic[0], (mr).ic[1]);
            (mr).fetches += 4u;
            (mr).stale = false;
        }
        bvec2 cross;
        float tb = dda_exit((mr).tn, (mr).ta, (mr).span.t1, cross);
        ivec2 on = dda_exit_on((mr).step, cross);
        vec3 p = query_at(q, tb);
        vec3 b;
        float cb = dda_local_clearance((mr).surface, (mr).c, (mr).ic, p, on, b);
        bool has_line = false;
        if (cross[ax]) {
            // The clearance the jumps use at this centerline (same samples, same
            // arithmetic), so walking and jumping agree.
            uint m = (((mr).step[ax] > 0) ? ((mr).ic[ax] + 1u) : ((mr).ic[ax]));
            SafetyLine l = safety_line_at(q, ax, m);
            if (l.edge != (mr).ic[mi]) {
                (mr).fetches += 2u;
            }
            cb = l.c;
            line = l;
            has_line = true;
        }
        SegmentHit seg = surface_segment_hit((mr).surface, (mr).c, (mr).a, b, (mr).ca, cb, (mr).wall);
        (mr).clearance = real_min((mr).clearance, seg.clearance);
        if (seg.has_hit) {
            hit = dda_segment_point(seg, (mr).ic, (mr).a, b, (mr).ta, tb);
            return SAFETY_STEP_HIT;
        }
        if (!(cross[0] || cross[1])) {
            return SAFETY_STEP_END;
        }
        for (int k = 0; k < 2; k++) {
            if (cross[k]) {
                int next = int((mr).ic[k]) + (mr).step[k];
                if (next < 0 || next >= int((mr).cells[k])) {
                    return SAFETY_STEP_END;
                }
                (mr).ic[k] = uint(next);
                (mr).tn[k] = dda_next_crossing((mr).ic[k], (mr).step[k], o[k], d[k]);
            }
        }
        (mr).wall = safety_march_wall_of(mr, ((cross[0]) ? (0) : (1)));
        (mr).a = dda_next_entry(b, cross);
        (mr).ca = cb;
        (mr).ta = tb;
        (mr).stale = true;
        if (has_line) {
            return SAFETY_STEP_LINE;
        }
    }
    return SAFETY_STEP_END;
}

// `March::done`.
Trace safety_march_done(SafetyMarch mr, bool has_hit, Hit hit, uint flags) {
    return Trace(has_hit, hit, mr.fetches, mr.clearance, flags);
}

// `last_line`: last main-axis centerline the ray crosses strictly before t1 (false
// when there is none), with the crossing formula of the walk.
bool safety_last_line(Query q, int ax, int sg, float t1, inout uint last) {
    vec3 o = q.origin;
    vec3 d = q.dir;
    int lm = int(safety_extents(ax)[0]);
    float x1 = real_clamp_to(o[ax] + t1 * d[ax], 0.0, float(lm - 1));
    int m = int(floor(x1)) + int(sg < 0 && floor(x1) != x1);
    while (m >= 0 && m < lm && (float(uint(m)) - o[ax]) / d[ax] >= t1) {
        m -= sg;
    }
    while (m + sg >= 0 && m + sg < lm && (float(uint(m + sg)) - o[ax]) / d[ax] < t1) {
        m += sg;
    }
    last = uint(max(m, 0));
    return m >= 0 && m < lm;
}

// The closure `jump(line, class, i, j)` of `march`: reads the baked data of texel
// (i, j) (one fetch, counted by the march) and returns (x) how many centerlines the ray
// crossing `l` above that texel's segment may skip and (y) the fetches it took beyond
// that one (`d` is the query's direction, which the Rust closures capture). Defined by
// the method's file (method_safety.wgsl, method_cc.wgsl, method_radius.wgsl):
// fn safety_march_jump(l: SafetyLine, ray_class: u32, i: u32, j: u32, d: vec3<f32>) -> vec2<u32>
uvec2 safety_march_jump(SafetyLine l, uint ray_class, uint i, uint j, vec3 d);

// `MarchSurface::of(surface)` then `MarchSurface::surface`: the surface a safety-shape
// march finishes on, HF_SURFACE_TRIANGLES or HF_SURFACE_VIEW_LINEAR (the surfaces the
// triangle-baked maps bound). Any other surface (where Rust has no MarchSurface) falls
// back to the triangles; only a general shader's runtime `hf_surface` can ask for one,
// since a generated shader of another surface is refused (`supports`).
uint safety_march_surface(uint surface) {
//#if any_surface
    return ((surface == HF_SURFACE_VIEW_LINEAR) ? (HF_SURFACE_VIEW_LINEAR) : (HF_SURFACE_TRIANGLES));
//#else
    return surface;
//#endif
}

// `march`: the march shared by the safety-shape methods; the walk between jumps and
// the final test use `march_surface` (see safety_march_surface). `held`: whether the
// map's data serves q (safety_rays_hold); else every jump reads 0.
Trace safety_march(uint march_surface, Query q, bool held) {
    Span span;
    if (!dda_clip(q, span)) {
        return trace_miss(0u, real_infinity());
    }
    vec3 d = q.dir;
    uint ray_class = ray_class_of(d[0], d[1]);
    int ax = safety_axis_of(ray_class);
    uvec2 cells = dda_cells();
    vec3 p0 = query_at(q, span.t0);
    float x0 = real_clamp_to(p0[0], 0.0, float(cells[0]));
    float y0 = real_clamp_to(p0[1], 0.0, float(cells[1]));
    ivec2 step = ivec2(dda_step_of(d[0]), dda_step_of(d[1]));
    uvec2 ic = uvec2(dda_cell_index(x0, d[0], cells[0]), dda_cell_index(y0, d[1], cells[1]));
    vec4 c = surface_corners(ic[0], ic[1]);
    uint surface = safety_march_surface(march_surface);
    vec3 a;
    float ca = dda_local_clearance(surface, c, ic, vec3(x0, y0, p0[2]), dda_entry_on(surface, span), a);
    if (ca <= 0.0) {
        return trace_hit(dda_start_hit(surface, span, c, ic, a, p0), 4u, dda_start_clearance(span, ca));
    }
    SafetyMarch mr = SafetyMarch(surface, span, ax, step, cells, ic, c, false, a, ca, span.t0, vec3(0.0, 0.0, 1.0), dda_crossings(ic, step, q), 4u, ca);
    int sg = step[ax];
    uint last = 0u;
    bool has_last = sg != 0 && safety_last_line(q, ax, sg, span.t1, last);
    uint budget = safety_extents(ax)[0] + 8u;
    Hit hit;
    SafetyLine l;
    int st = safety_march_walk(mr, q, hit, l);
    for (;;) {
        if (st == SAFETY_STEP_HIT) {
            return safety_march_done(mr, true, hit, 0u);
        } else if (st == SAFETY_STEP_END) {
            return safety_march_done(mr, false, hit_none(), 0u);
        }
        if (budget == 0u) {
            return safety_march_done(mr, false, hit_none(), HF_FLAG_BUDGET_EXHAUSTED);
        }
        budget -= 1u;
        if (!has_last || last == l.m) {
            st = safety_march_walk(mr, q, hit, l);
            continue;
        }
        uint k = 0u;
        if (l.c > l.tol) {
            mr.fetches += 1u;
            if (held) {
                uvec2 ij = ((ax == 0) ? (uvec2(l.m, l.texel)) : (uvec2(l.texel, l.m)));
                uvec2 jump = safety_march_jump(l, ray_class, ij[0], ij[1], d);
                k = jump.x;
                mr.fetches += jump.y;
            }
        }
        if (k == 0u) {
            st = safety_march_walk(mr, q, hit, l);
            continue;
        }
        uint room = uint(abs(int(last) - int(l.m)));
        // `target` in Rust and GLSL, a reserved word in WGSL.
        uint goal = uint(int(l.m) + sg * int(min(k, room)));
        SafetyLine lt = safety_march_line(mr, q, goal);
        if (lt.c > 0.0) {
            safety_march_enter(mr, q, lt);
            l = lt;
            st = SAFETY_STEP_LINE;
            continue;
        }
        // Below at the target, above at m, and no exit in between: bisect.
        SafetyLine lo = l;
        uint hi = goal;
        while (abs(int(hi) - int(lo.m)) > 1) {
            uint mid = uint((int(hi) + int(lo.m)) / 2);
            SafetyLine lm = safety_march_line(mr, q, mid);
            if (lm.c > 0.0) {
                lo = lm;
            } else {
                hi = mid;
            }
        }
        safety_march_enter(mr, q, lo);
        st = safety_march_walk(mr, q, hit, l);
    }
    return safety_march_done(mr, false, hit_none(), 0u);
}

// `trace_on`: `trace` finishing on `surface` (HF_SURFACE_TRIANGLES or
// HF_SURFACE_VIEW_LINEAR; see safety_march_surface), from the same map.
Trace safety_trace_on(uint surface, Query q) { return safety_march(surface, q, safety_rays_hold(q)); }

// `trace`: traces q on the triangle surface with the safety distances.
Trace safety_trace(Query q) { return safety_trace_on(HF_SURFACE_TRIANGLES, q); }
