// Mirror of core/src/cone.rs (the march; the bake stays on the CPU): conservative cone
// step mapping for the triangle surface, and `cone::march`, the step-then-cell-test
// march that qdm.wgsl shares. The closure `step` of the Rust march is the function
// `cone_march_step`, defined by the method's file (method_cone.wgsl, method_qdm.wgsl).
//
// Texture layout (docs/DESIGN.md, "Texture layouts", cone): `hf_cone_map`.

@group(0) @binding(6) var hf_cone_map: texture_2d<f32>;

// `Step`: what a method's step function decides at a ray point above a cell.
const CONE_STEP_JUMP: i32 = 0; // advance t by `dt` (> 0)
const CONE_STEP_MISS: i32 = 1; // the rest of the ray cannot meet the surface
const CONE_STEP_CELL: i32 = 2; // no safe step: run the exact cell test

// The closure `step(cell, point)` of `march` (`d` is the query's direction, which
// the Rust closures capture): returns the step (and `dt` for a jump) and the fetches
// it cost. Defined by the method's file:
// fn cone_march_step(cell: vec2<u32>, p: vec3<f32>, d: vec3<f32>, dt: ptr<function, f32>,
//                    fetches: ptr<function, u32>) -> i32
//#glsl
// int cone_march_step(uvec2 cell, vec3 p, vec3 d, out float dt, out uint fetches);
//#end

// `ConeMap::texel`: [top, ratio] of cell (i, j).
fn cone_texel(i: u32, j: u32) -> vec2<f32> { return textureLoad(hf_cone_map, vec2<u32>(i, j), 0).rg; }

// `margin`: rounding margin on a clearance above a stored top.
fn cone_margin(z: f32, top: f32) -> f32 { return 64.0 * REAL_EPSILON * (1.0 + abs(z) + abs(top)); }

// The closure `cell_exit` of `march`: where the ray leaves the walk's cell (or its span).
fn cone_cell_exit(w: DdaWalk, q: Query) -> f32 {
    let t_cross: vec2<f32> = dda_next_crossings(w.cell, w.step, q);
    return real_min(real_min(t_cross[0], t_cross[1]), w.span.t1);
}

// `march`: at each iteration the step either jumps, ends in a miss, or asks for the
// exact cell test of dda_trace (the walk of dda.wgsl; `w.ta` is the march's t, and the
// closure `locate` is dda_cell_of).
fn cone_march(q: Query, max_iter: u32) -> Trace {
    var w: DdaWalk;
    if (!dda_walk_start(HF_SURFACE_TRIANGLES, HF_SURFACE_TRIANGLES, q, &w)) {
        return trace_miss(0u, real_infinity());
    }
    if (w.ca <= 0.0) {
        return trace_hit(dda_walk_start_hit(w, q), w.fetches, 0.0);
    }
    // `w.a, w.ca` valid for the current point.
    var have_ca: bool = true;
    var iter: u32 = 0u;
    loop {
        let p: vec3<f32> = query_at(q, w.ta);
        if (iter >= max_iter) {
            var tr: Trace = trace_hit(Hit(w.ta, p, w.cell, vec3<f32>(0.0, 0.0, 1.0), 0u), w.fetches, w.clearance);
            tr.flags = HF_FLAG_BUDGET_EXHAUSTED;
            return tr;
        }
        iter += 1u;
        var dt: f32;
        var f: u32;
        let s: i32 = cone_march_step(w.cell, p, q.dir, &dt, &f);
        w.fetches += f;
        if (s == CONE_STEP_MISS) {
            return trace_miss(w.fetches, w.clearance);
        }
        // A jump that stays in the cell would crawl: the cell test reaches its exit at once.
        if (s == CONE_STEP_JUMP && dt > 0.0 && w.ta + dt >= cone_cell_exit(w, q)) {
            let tn: f32 = w.ta + dt;
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
        dda_walk_corners(&w);
        if (!have_ca) {
            var a: vec3<f32>;
            w.ca = dda_local_clearance(HF_SURFACE_TRIANGLES, w.c, w.cell, p, vec2<i32>(-1), &a);
            w.a = a;
            w.clearance = real_min(w.clearance, w.ca);
            if (w.ca <= 0.0) {
                let n: vec3<f32> = surface_cell_normal(HF_SURFACE_TRIANGLES, w.c, a[0], a[1]);
                return trace_hit(Hit(w.ta, p, w.cell, n, 0u), w.fetches, w.clearance);
            }
        }
        let ex: DdaExit = dda_walk_exit(w, q);
        var hit: Hit;
        if (dda_walk_test(&w, ex, &hit)) {
            return trace_hit(hit, w.fetches, w.clearance);
        }
        if (!dda_walk_next(&w, ex)) {
            return trace_miss(w.fetches, w.clearance);
        }
        have_ca = true;
    }
    return trace_miss(w.fetches, w.clearance);
}

// `cone_step`: the cone step from ray point p with direction d over a texel [top, ratio].
fn cone_cone_step(p: vec3<f32>, d: vec3<f32>, top: f32, ratio: f32, dt: ptr<function, f32>) -> i32 {
    *dt = 0.0;
    let tol: f32 = cone_margin(p[2], top);
    let e: f32 = p[2] - top - tol;
    if (!(e > 0.0) || ratio <= 0.0) {
        return CONE_STEP_CELL;
    }
    let hs: f32 = sqrt(d[0] * d[0] + d[1] * d[1]);
    let denom: f32 = hs / ratio - d[2];
    if (!(denom > 0.0)) {
        return CONE_STEP_MISS;
    }
    *dt = e / denom * (1.0 - 16.0 * REAL_EPSILON);
    return CONE_STEP_JUMP;
}
