// Mirror of core/src/safety/cc.rs (the march; the bake stays on the CPU): cylinder-cone
// safety shapes (Baboud, Eisemann, Seidel 2011, section 6.3) on the triangle surface,
// or the view-linear one from the same map, stepping with the safety march of
// safety.glsl.
//
// Texture layout: the map of hf_cc_bake as `hf_cc_map`, an RGBA8UI texture of W x nH
// texels for the n ray classes it holds, `hf_cc_classes` (HF_RAYS_* bits, HF_RAYS_ALL
// for a whole map; `CcMap::with_classes`): texel (i, n j + slot) = [r, s, z_lo, z_hi]
// of texel (i, j) for the ray class of that slot (each texel row as n rows, one per
// held class in class order x+, x-, y+, y-; slot = how many held classes come before
// it; a whole map: W x 4H, texel (i, 4 j + class)). A ray of a class the map does not
// hold reads [0, HF_CC_NO_CONE, 0, 0] without a fetch (radius 0, no cone: it walks
// cell by cell, still exact). `hf_cc_cap` is the bake's cap; `hf_cc_zmin`,
// `hf_cc_zstep`, `hf_cc_zspan` the frame of the base heights (hf_cc_frame).

uniform usampler2D hf_cc_map;
uniform uint hf_cc_classes = 15u;
uniform uint hf_cc_cap;
uniform float hf_cc_zmin;
uniform float hf_cc_zstep;
uniform float hf_cc_zspan;

// `CcMap::texel`: the packed bytes of texel (i, j) for `ray_class` ([0, HF_CC_NO_CONE,
// 0, 0], without a fetch, when the map does not hold it).
uvec4 cc_texel(uint ray_class, uint i, uint j) {
    if (!safety_holds(hf_cc_classes, ray_class)) {
        return uvec4(0u, HF_CC_NO_CONE, 0u, 0u);
    }
    return texelFetch(hf_cc_map, ivec2(i, safety_class_row(hf_cc_classes, ray_class, j)), 0);
}

// `decode_slope` (finite codes): `t |t| / 2048` with `t = code - 128`, exact in float.
float cc_decode_slope(uint code) {
    float t = float(int(code) - 128);
    return t * abs(t) / 2048.0;
}

// `cone_step`: the step (centerlines) of a ray of rise `sd` per centerline (`sd_err`
// bounds its rounding) crossing the centerline at height `pz` (within `tol`) above a
// texel of shape b = [r, s, z0, z1].
uint cc_cone_step(uvec4 b, float pz, float tol, float sd, float sd_err) {
    uint r = b[0];
    uint cap = hf_cc_cap;
    if (b[1] == HF_CC_NO_CONE || r >= cap) {
        return r;
    }
    float zc = hf_cc_zmin + float(b[2] | (b[3] << 8)) * hf_cc_zstep;
    float sc = cc_decode_slope(b[1]);
    // zc's own rounding: relative EPSILON of the terms.
    float zerr = 4.0 * REAL_EPSILON * (abs(hf_cc_zmin) + hf_cc_zspan + abs(zc));
    float num = pz - zc - tol - tol - zerr;
    bool above = num > 0.0; // false for NaN too
    if (!above) {
        return r;
    }
    float sd_lo = sd - sd_err;
    if (sd_lo >= sc) {
        return max(cap, r);
    }
    float den = (sc - sd_lo) * (1.0 + 4.0 * REAL_EPSILON);
    float x = num / den * (1.0 - 4.0 * REAL_EPSILON);
    bool short_step = x < float(cap); // false for NaN and +inf
    if (!short_step) {
        return max(cap, r);
    }
    return max(uint(floor(x)), r);
}

// The rise per centerline of the closure of `cc::trace`, and its rounding bound.
vec2 cc_rise(vec3 d) {
    uint ray_class = ray_class_of(d[0], d[1]);
    int ax = safety_axis_of(ray_class);
    float dm = abs(d[ax]);
    float sd = dm > 0.0 ? d[2] / dm : 0.0;
    float sd_err = 2.0 * REAL_EPSILON * abs(sd);
    return vec2(sd, sd_err);
}

// `trace_on`: `trace` finishing on `surface` (HF_SURFACE_TRIANGLES or
// HF_SURFACE_VIEW_LINEAR; the same map bounds both, see safety_march_surface).
Trace cc_trace_on(uint surface, Query q) { return safety_march(surface, q); }

// `trace`: the safety march with cylinder-cone steps, on the triangle surface.
Trace cc_trace(Query q) { return cc_trace_on(HF_SURFACE_TRIANGLES, q); }
