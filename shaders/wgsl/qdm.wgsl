// Mirror of core/src/qdm.rs (the march; the bake stays on the CPU): quadratic
// displacement maps, per cell a cone (a, b) topped by a revolved parabola c over the
// cell's top h; steps by cone_march (cone.wgsl).
//
// Texture layout (docs/DESIGN.md, "Texture layouts", QDM): `hf_qdm_map`.

@group(0) @binding(7) var hf_qdm_map: texture_2d<f32>;

// `QdmMap::texel`: [a, b, c, h] of cell (i, j).
fn qdm_texel(i: u32, j: u32) -> vec4<f32> { return textureLoad(hf_qdm_map, vec2<u32>(i, j), 0); }

// `solve_stable`: smallest root x >= 0 of `A x^2 + B x + C` without cancellation;
// `found` false for none.
fn qdm_solve_stable(qa: f32, qb: f32, qc: f32, found: ptr<function, bool>) -> f32 {
    *found = false;
    var best: f32 = 0.0;
    var roots: array<f32, 2>;
    let n: i32 = surface_stable_roots(qa, qb, qc, &roots);
    for (var k: i32 = 0; k < n; k++) {
        let r: f32 = roots[k];
        if (real_is_finite(r) && r >= 0.0 && (!*found || r < best)) {
            *found = true;
            best = r;
        }
    }
    return best;
}

// `free_distance`: horizontal distance rho the ray (height e0 above h, rise g per unit
// of horizontal distance) may go before it meets F(rho); `found` false: never.
fn qdm_free_distance(tex: vec4<f32>, e0: f32, g: f32, found: ptr<function, bool>) -> f32 {
    *found = true;
    let a: f32 = tex[0];
    let b: f32 = tex[1];
    let c: f32 = tex[2];
    let inv_a: f32 = 1.0 / a;
    let k: f32 = inv_a - g;
    let ab: f32 = a * b;
    if (k > 0.0) {
        let rho: f32 = e0 / k;
        if (rho <= ab) {
            return rho;
        }
    }
    let xp: f32 = 0.5 / (a * c);
    var has_x: bool;
    let x: f32 = qdm_solve_stable(c, g - inv_a, e0 + g * ab - b, &has_x);
    if (has_x && x <= xp) {
        return ab + x;
    }
    let plateau: f32 = b + 0.25 / (a * a * c);
    if (g < 0.0) {
        return (e0 - plateau) / -g;
    }
    *found = false;
    return 0.0;
}

// The closure of `qdm::trace_steps`: one fetch of the cell's texel, then the step.
fn qdm_step(cell: vec2<u32>, p: vec3<f32>, d: vec3<f32>, dt: ptr<function, f32>,
            fetches: ptr<function, u32>) -> i32 {
    *dt = 0.0;
    *fetches = 1u;
    let hs: f32 = sqrt(d[0] * d[0] + d[1] * d[1]);
    let tex: vec4<f32> = qdm_texel(cell[0], cell[1]);
    let top: f32 = tex[3];
    let e0: f32 = p[2] - top - cone_margin(p[2], top);
    if (!(e0 > 0.0) || !(tex[0] > 0.0)) {
        return CONE_STEP_CELL;
    }
    let shrink: f32 = 1.0 - 16.0 * REAL_EPSILON;
    if (hs == 0.0) {
        if (d[2] < 0.0) {
            *dt = e0 / -d[2] * shrink;
            return CONE_STEP_JUMP;
        }
        return CONE_STEP_MISS;
    }
    var found: bool;
    let rho: f32 = qdm_free_distance(tex, e0, d[2] / hs, &found);
    if (found) {
        *dt = rho / hs * shrink;
        return CONE_STEP_JUMP;
    }
    return CONE_STEP_MISS;
}
