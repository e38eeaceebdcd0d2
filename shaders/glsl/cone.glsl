// Generated from shaders/wgsl/cone.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/cone.rs (the march; the bake stays on the CPU): conservative cone
// step mapping for the triangle surface, and `cone::march`, the step-then-cell-test
// march that qdm.wgsl shares. The closure `step` of the Rust march is the function
// `cone_march_step`, defined by the method's file (method_cone.wgsl, method_qdm.wgsl).
//
// Texture layout (docs/DESIGN.md, "Texture layouts", cone): `hf_cone_map`.

uniform sampler2D hf_cone_map;

// `Step`: what a method's step function decides at a ray point above a cell.
const int CONE_STEP_JUMP = 0; // advance t by `dt` (> 0)
const int CONE_STEP_MISS = 1; // the rest of the ray cannot meet the surface
const int CONE_STEP_CELL = 2; // no safe step: run the exact cell test

// The closure `step(cell, point)` of `march` (`d` is the query's direction, which
// the Rust closures capture): returns the step (and `dt` for a jump) and the fetches
// it cost. Defined by the method's file:
// fn cone_march_step(cell: vec2<u32>, p: vec3<f32>, d: vec3<f32>, dt: ptr<function, f32>,
//                    fetches: ptr<function, u32>) -> i32
int cone_march_step(uvec2 cell, vec3 p, vec3 d, out float dt, out uint fetches);

// `ConeMap::texel`: [top, ratio] of cell (i, j).
vec2 cone_texel(uint i, uint j) { return texelFetch(hf_cone_map, ivec2(i, j), 0).rg; }

// `margin`: rounding margin on a clearance above a stored top.
float cone_margin(float z, float top) { return 64.0 * REAL_EPSILON * (1.0 + abs(z) + abs(top)); }

// The closure `locate` of `march`.
uvec2 cone_locate(vec3 p, vec3 d, uvec2 cells) {
    return uvec2(dda_cell_index(real_clamp_to(p[0], 0.0, float(cells[0])), d[0], cells[0]), dda_cell_index(real_clamp_to(p[1], 0.0, float(cells[1])), d[1], cells[1]));
}

// The closure `cell_exit` of `march`.
float cone_cell_exit(uvec2 cell, ivec2 dstep, Query q, float t1) {
    vec2 t_cross = dda_crossings(cell, dstep, q);
    return real_min(real_min(t_cross[0], t_cross[1]), t1);
}

// `march`: at each iteration the step either jumps, ends in a miss, or asks for the
// exact cell test of dda_trace.
Trace cone_march(Query q, uint max_iter) {
    Span span;
    if (!dda_clip(q, span)) {
        return trace_miss(0u, real_infinity());
    }
    vec3 d = q.dir;
    uvec2 cells = dda_cells();
    ivec2 dstep = ivec2(dda_step_of(d[0]), dda_step_of(d[1]));
    vec3 p0 = query_at(q, span.t0);
    vec2 start = vec2(real_clamp_to(p0[0], 0.0, float(cells[0])), real_clamp_to(p0[1], 0.0, float(cells[1])));
    uvec2 cell = cone_locate(p0, d, cells);
    vec4 c = surface_corners(cell[0], cell[1]);
    uint fetches = 4u;
    vec3 a;
    float ca = dda_local_clearance(HF_SURFACE_TRIANGLES, c, cell, vec3(start[0], start[1], p0[2]), dda_entry_on(HF_SURFACE_TRIANGLES, span), a);
    if (ca <= 0.0) {
        return trace_hit(dda_start_hit(HF_SURFACE_TRIANGLES, span, c, cell, a, p0), fetches, 0.0);
    }
    float clearance = ca;
    // `a, ca` valid for the current point; `have_c`: `c` holds the current cell's corners.
    bool have_ca = true;
    bool have_c = true;
    float t = span.t0;
    uint iter = 0u;
    for (;;) {
        vec3 p = query_at(q, t);
        if (iter >= max_iter) {
            Trace tr = trace_hit(Hit(t, p, cell, vec3(0.0, 0.0, 1.0), 0u), fetches, clearance);
            tr.flags = HF_FLAG_BUDGET_EXHAUSTED;
            return tr;
        }
        iter += 1u;
        float dt;
        uint f;
        int s = cone_march_step(cell, p, d, dt, f);
        fetches += f;
        if (s == CONE_STEP_MISS) {
            return trace_miss(fetches, clearance);
        }
        // A jump that stays in the cell would crawl: the cell test reaches its exit at once.
        if (s == CONE_STEP_JUMP && dt > 0.0 && t + dt >= cone_cell_exit(cell, dstep, q, span.t1)) {
            float tn = t + dt;
            if (!(tn < span.t1)) {
                return trace_miss(fetches, clearance);
            }
            t = tn;
            cell = cone_locate(query_at(q, t), d, cells);
            have_ca = false;
            have_c = false;
            continue;
        }
        // The exact cell test from t to the cell's exit.
        if (!have_c) {
            c = surface_corners(cell[0], cell[1]);
            fetches += 4u;
        }
        if (!have_ca) {
            ca = dda_local_clearance(HF_SURFACE_TRIANGLES, c, cell, p, ivec2(-1), a);
            clearance = real_min(clearance, ca);
            if (ca <= 0.0) {
                vec3 n = surface_cell_normal(HF_SURFACE_TRIANGLES, c, a[0], a[1]);
                return trace_hit(Hit(t, p, cell, n, 0u), fetches, clearance);
            }
        }
        vec2 t_cross = dda_crossings(cell, dstep, q);
        bvec2 cross;
        float tb = dda_exit(t_cross, t, span.t1, cross);
        ivec2 on = dda_exit_on(dstep, cross);
        vec3 b;
        float cb = dda_local_clearance(HF_SURFACE_TRIANGLES, c, cell, query_at(q, tb), on, b);
        SegmentHit seg = surface_segment_hit(HF_SURFACE_TRIANGLES, c, a, b, ca, cb, vec3(0.0, 0.0, 1.0));
        clearance = real_min(clearance, seg.clearance);
        if (seg.has_hit) {
            return trace_hit(dda_segment_point(seg, cell, a, b, t, tb), fetches, clearance);
        }
        if (!cross[0] && !cross[1]) {
            return trace_miss(fetches, clearance);
        }
        for (int k = 0; k < 2; k++) {
            if (cross[k]) {
                int next = int(cell[k]) + dstep[k];
                if (next < 0 || next >= int(cells[k])) {
                    return trace_miss(fetches, clearance);
                }
                cell[k] = uint(next);
            }
        }
        a = dda_next_entry(b, cross);
        ca = cb;
        t = tb;
        have_ca = true;
        have_c = false;
    }
    return trace_miss(fetches, clearance);
}

// `cone_step`: the cone step from ray point p with direction d over a texel [top, ratio].
int cone_cone_step(vec3 p, vec3 d, float top, float ratio, inout float dt) {
    dt = 0.0;
    float tol = cone_margin(p[2], top);
    float e = p[2] - top - tol;
    if (!(e > 0.0) || ratio <= 0.0) {
        return CONE_STEP_CELL;
    }
    float hs = sqrt(d[0] * d[0] + d[1] * d[1]);
    float denom = hs / ratio - d[2];
    if (!(denom > 0.0)) {
        return CONE_STEP_MISS;
    }
    dt = e / denom * (1.0 - 16.0 * REAL_EPSILON);
    return CONE_STEP_JUMP;
}
