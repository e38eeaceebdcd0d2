// Generated from shaders/wgsl/qdm.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/qdm.rs (the march; the bake stays on the CPU): quadratic
// displacement maps, per cell a cone (a, b) topped by a revolved parabola c over the
// cell's top h; steps by cone_march (cone.wgsl).
//
// Texture layout (docs/DESIGN.md, "Texture layouts", QDM): `hf_qdm_map`.

uniform sampler2D hf_qdm_map;

// `QdmMap::texel`: [a, b, c, h] of cell (i, j).
vec4 qdm_texel(uint i, uint j) { return texelFetch(hf_qdm_map, ivec2(i, j), 0); }

// `solve_stable`: smallest root x >= 0 of `A x^2 + B x + C` without cancellation;
// `found` false for none.
float qdm_solve_stable(float qa, float qb, float qc, inout bool found) {
    found = false;
    float best = 0.0;
    float[2] roots;
    int n = surface_stable_roots(qa, qb, qc, roots);
    for (int k = 0; k < n; k++) {
        float r = roots[k];
        if (real_is_finite(r) && r >= 0.0 && (!found || r < best)) {
            found = true;
            best = r;
        }
    }
    return best;
}

// `free_distance`: horizontal distance rho the ray (height e0 above h, rise g per unit
// of horizontal distance) may go before it meets F(rho); `found` false: never.
float qdm_free_distance(vec4 tex, float e0, float g, inout bool found) {
    found = true;
    float a = tex[0];
    float b = tex[1];
    float c = tex[2];
    float inv_a = 1.0 / a;
    float k = inv_a - g;
    float ab = a * b;
    if (k > 0.0) {
        float rho = e0 / k;
        if (rho <= ab) {
            return rho;
        }
    }
    float xp = 0.5 / (a * c);
    bool has_x;
    float x = qdm_solve_stable(c, g - inv_a, e0 + g * ab - b, has_x);
    if (has_x && x <= xp) {
        return ab + x;
    }
    float plateau = b + 0.25 / (a * a * c);
    if (g < 0.0) {
        return (e0 - plateau) / -g;
    }
    found = false;
    return 0.0;
}

// The closure of `qdm::trace_steps`: one fetch of the cell's texel, then the step.
int qdm_step(uvec2 cell, vec3 p, vec3 d, inout float dt, inout uint fetches) {
    dt = 0.0;
    fetches = 1u;
    float hs = sqrt(d[0] * d[0] + d[1] * d[1]);
    vec4 tex = qdm_texel(cell[0], cell[1]);
    float top = tex[3];
    float e0 = p[2] - top - cone_margin(p[2], top);
    if (!(e0 > 0.0) || !(tex[0] > 0.0)) {
        return CONE_STEP_CELL;
    }
    float shrink = 1.0 - 16.0 * REAL_EPSILON;
    if (hs == 0.0) {
        if (d[2] < 0.0) {
            dt = e0 / -d[2] * shrink;
            return CONE_STEP_JUMP;
        }
        return CONE_STEP_MISS;
    }
    bool found;
    float rho = qdm_free_distance(tex, e0, d[2] / hs, found);
    if (found) {
        dt = rho / hs * shrink;
        return CONE_STEP_JUMP;
    }
    return CONE_STEP_MISS;
}
