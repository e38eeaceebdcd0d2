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

// The closure `locate` of `march`.
fn cone_locate(p: vec3<f32>, d: vec3<f32>, cells: vec2<u32>) -> vec2<u32> {
    return vec2<u32>(dda_cell_index(real_clamp_to(p[0], 0.0, f32(cells[0])), d[0], cells[0]),
                     dda_cell_index(real_clamp_to(p[1], 0.0, f32(cells[1])), d[1], cells[1]));
}

// The closure `cell_exit` of `march`.
fn cone_cell_exit(cell: vec2<u32>, dstep: vec2<i32>, q: Query, t1: f32) -> f32 {
    let t_cross: vec2<f32> = dda_crossings(cell, dstep, q);
    return real_min(real_min(t_cross[0], t_cross[1]), t1);
}

// `march`: at each iteration the step either jumps, ends in a miss, or asks for the
// exact cell test of dda_trace.
fn cone_march(q: Query, max_iter: u32) -> Trace {
    var span: Span;
    if (!dda_clip(q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    let d: vec3<f32> = q.dir;
    let cells: vec2<u32> = dda_cells();
    let dstep: vec2<i32> = vec2<i32>(dda_step_of(d[0]), dda_step_of(d[1]));
    let p0: vec3<f32> = query_at(q, span.t0);
    let start: vec2<f32> = vec2<f32>(real_clamp_to(p0[0], 0.0, f32(cells[0])),
                          real_clamp_to(p0[1], 0.0, f32(cells[1])));
    var cell: vec2<u32> = cone_locate(p0, d, cells);
    var c: vec4<f32> = surface_corners(cell[0], cell[1]);
    var fetches: u32 = 4u;
    var a: vec3<f32>;
    var ca: f32 = dda_local_clearance(HF_SURFACE_TRIANGLES, c, cell, vec3<f32>(start[0], start[1], p0[2]),
                                 dda_entry_on(HF_SURFACE_TRIANGLES, span), &a);
    if (ca <= 0.0) {
        return trace_hit(dda_start_hit(HF_SURFACE_TRIANGLES, span, c, cell, a, p0), fetches, 0.0);
    }
    var clearance: f32 = ca;
    // `a, ca` valid for the current point; `have_c`: `c` holds the current cell's corners.
    var have_ca: bool = true;
    var have_c: bool = true;
    var t: f32 = span.t0;
    var iter: u32 = 0u;
    loop {
        let p: vec3<f32> = query_at(q, t);
        if (iter >= max_iter) {
            var tr: Trace = trace_hit(Hit(t, p, cell, vec3<f32>(0.0, 0.0, 1.0), 0u), fetches, clearance);
            tr.flags = HF_FLAG_BUDGET_EXHAUSTED;
            return tr;
        }
        iter += 1u;
        var dt: f32;
        var f: u32;
        let s: i32 = cone_march_step(cell, p, d, &dt, &f);
        fetches += f;
        if (s == CONE_STEP_MISS) {
            return trace_miss(fetches, clearance);
        }
        // A jump that stays in the cell would crawl: the cell test reaches its exit at once.
        if (s == CONE_STEP_JUMP && dt > 0.0 && t + dt >= cone_cell_exit(cell, dstep, q, span.t1)) {
            let tn: f32 = t + dt;
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
            ca = dda_local_clearance(HF_SURFACE_TRIANGLES, c, cell, p, vec2<i32>(-1), &a);
            clearance = real_min(clearance, ca);
            if (ca <= 0.0) {
                let n: vec3<f32> = surface_cell_normal(HF_SURFACE_TRIANGLES, c, a[0], a[1]);
                return trace_hit(Hit(t, p, cell, n, 0u), fetches, clearance);
            }
        }
        let t_cross: vec2<f32> = dda_crossings(cell, dstep, q);
        var cross: vec2<bool>;
        let tb: f32 = dda_exit(t_cross, t, span.t1, &cross);
        let on: vec2<i32> = dda_exit_on(dstep, cross);
        var b: vec3<f32>;
        let cb: f32 = dda_local_clearance(HF_SURFACE_TRIANGLES, c, cell, query_at(q, tb), on, &b);
        let seg: SegmentHit = surface_segment_hit(HF_SURFACE_TRIANGLES, c, a, b, ca, cb,
                                      vec3<f32>(0.0, 0.0, 1.0));
        clearance = real_min(clearance, seg.clearance);
        if (seg.has_hit) {
            return trace_hit(dda_segment_point(seg, cell, a, b, t, tb), fetches, clearance);
        }
        if (!cross[0] && !cross[1]) {
            return trace_miss(fetches, clearance);
        }
        for (var k: i32 = 0; k < 2; k++) {
            if (cross[k]) {
                let next: i32 = i32(cell[k]) + dstep[k];
                if (next < 0 || next >= i32(cells[k])) {
                    return trace_miss(fetches, clearance);
                }
                cell[k] = u32(next);
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
