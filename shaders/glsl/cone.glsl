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

// The closure `cell_exit` of `march`: where the ray leaves the walk's cell (or its span).
float cone_cell_exit(DdaWalk w, Query q) {
    vec2 t_cross = dda_next_crossings(w.cell, w.step, q);
    return real_min(real_min(t_cross[0], t_cross[1]), w.span.t1);
}

// `march`: at each iteration the step either jumps, ends in a miss, or asks for the
// exact cell test of dda_trace (the walk of dda.wgsl; `w.ta` is the march's t, and the
// closure `locate` is dda_cell_of).
Trace cone_march(Query q, uint max_iter) {
    DdaWalk w;
    if (!dda_walk_start(HF_SURFACE_TRIANGLES, HF_SURFACE_TRIANGLES, q, w)) {
        return trace_miss(0u, real_infinity());
    }
    if (w.ca <= 0.0) {
        return trace_hit(dda_walk_start_hit(w, q), w.fetches, 0.0);
    }
    // `w.a, w.ca` valid for the current point.
    bool have_ca = true;
    uint iter = 0u;
    for (;;) {
        vec3 p = query_at(q, w.ta);
        if (iter >= max_iter) {
            Trace tr = trace_hit(Hit(w.ta, p, w.cell, vec3(0.0, 0.0, 1.0), 0u), w.fetches, w.clearance);
            tr.flags = HF_FLAG_BUDGET_EXHAUSTED;
            return tr;
        }
        iter += 1u;
        float dt;
        uint f;
        int s = cone_march_step(w.cell, p, q.dir, dt, f);
        w.fetches += f;
        if (s == CONE_STEP_MISS) {
            return trace_miss(w.fetches, w.clearance);
        }
        // A jump that stays in the cell would crawl: the cell test reaches its exit at once.
        if (s == CONE_STEP_JUMP && dt > 0.0 && w.ta + dt >= cone_cell_exit(w, q)) {
            float tn = w.ta + dt;
            if (!(tn < w.span.t1)) {
                return trace_miss(w.fetches, w.clearance);
            }
            w.ta = tn;
            w.cell = dda_cell_of(query_at(q, tn), q.dir, w.cells);
            w.stale = true;
            have_ca = false;
            continue;
        }
        // The exact cell test from t to the cell's exit.
        dda_walk_corners(w);
        if (!have_ca) {
            vec3 a;
            w.ca = dda_local_clearance(HF_SURFACE_TRIANGLES, w.c, w.cell, p, ivec2(-1), a);
            w.a = a;
            w.clearance = real_min(w.clearance, w.ca);
            if (w.ca <= 0.0) {
                vec3 n = surface_cell_normal(HF_SURFACE_TRIANGLES, w.c, a[0], a[1]);
                return trace_hit(Hit(w.ta, p, w.cell, n, 0u), w.fetches, w.clearance);
            }
        }
        DdaExit ex = dda_walk_exit(w, q);
        Hit hit;
        if (dda_walk_test(w, ex, hit)) {
            return trace_hit(hit, w.fetches, w.clearance);
        }
        if (!dda_walk_next(w, ex)) {
            return trace_miss(w.fetches, w.clearance);
        }
        have_ca = true;
    }
    return trace_miss(w.fetches, w.clearance);
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
