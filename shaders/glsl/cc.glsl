// Generated from shaders/wgsl/cc.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/safety/cc.rs (the march; the bake stays on the CPU): cylinder-cone
// safety shapes (Baboud, Eisemann, Seidel 2011, section 6.3) on the triangle surface,
// or the view-linear one from the same map, stepping with the safety march of
// safety.wgsl.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", cylinder-cone): `hf_cc_map`, the
// override `hf_cc_classes` (the classes it holds; `CcMap::with_classes`) and the bake's
// cap `hf_cc.cap` (GLSL: `hf_cc_cap`). A ray of a class the map does not hold reads [0, HF_CC_NO_CONE]
// without a fetch (radius 0, no cone: it walks cell by cell, still exact). The cone's
// base height is not stored: the march computes it from the heights (cc_line_base).

uniform usampler2D hf_cc_map;
uniform uint hf_cc_classes = 15u;

uniform uint hf_cc_cap;

// The bake's cap.
uint cc_cap() { return hf_cc_cap; }

// `CcMap::texel`: the bytes [r, s] of texel (i, j) for `ray_class` ([0, HF_CC_NO_CONE],
// without a fetch, when the map does not hold it).
uvec2 cc_texel(uint ray_class, uint i, uint j) {
    if (!safety_holds(hf_cc_classes, ray_class)) {
        return uvec2(0u, HF_CC_NO_CONE);
    }
    return texelFetch(hf_cc_map, ivec2(i, safety_class_row(hf_cc_classes, ray_class, j)), 0).rg;
}

// `decode_slope` (finite codes): `t |t| / 2048` with `t = code - 128`, exact in float.
float cc_decode_slope(uint code) {
    float t = float(int(code) - 128);
    return t * abs(t) / 2048.0;
}

// `ConeStep::base`: the cone's base height over texel n of centerline m of axis ax (ln
// samples along the minor axis), the highest point of the surface on the texel's
// widened segment (half a sample spacing plus HF_SAFETY_SEG_PAD towards each
// neighbour, the one-sided slope at the field's border). Beyond the line's two samples
// it reads the third only inside the field (`if`, not `select`, which would load
// outside it).
float cc_line_base(int ax, uint m, uint n, uint ln) {
    float h = safety_sample(ax, m, n);
    float lo = 0.0;
    if (n > 0u) {
        lo = safety_sample(ax, m, n - 1u);
    }
    float hi = 0.0;
    if (n + 1u < ln) {
        hi = safety_sample(ax, m, n + 1u);
    }
    float below = ((n > 0u) ? (h - lo) : (hi - h));
    float above = ((n + 1u < ln) ? (hi - h) : (h - lo));
    float w = 0.5 + HF_SAFETY_SEG_PAD;
    return real_max(real_max(h - below * w, h), h + above * w);
}

// `ConeStep::cone`: the step (centerlines) of a ray of rise `sd` per centerline (`sd_err`
// bounds its rounding) crossing the centerline `l` of axis ax above a texel of shape
// b = [r, s], and the fetches its base height took beyond the shape's (one inside the
// field, none at its border, none when no cone is tested).
uvec2 cc_cone_step(uvec2 b, int ax, SafetyLine l, float sd, float sd_err) {
    uint r = b[0];
    uint cap = cc_cap();
    if (b[1] == HF_CC_NO_CONE || r >= cap) {
        return uvec2(r, 0u);
    }
    uint n = l.texel;
    uint ln = safety_extents(ax)[1];
    float zc = cc_line_base(ax, l.m, n, ln);
    uint extra = ((n > 0u && n + 1u < ln) ? (1u) : (0u));
    float sc = cc_decode_slope(b[1]);
    // zc's own rounding: relative EPSILON of the heights.
    float zs = real_max(abs(field_min_height()), abs(field_max_height()));
    float zerr = 8.0 * REAL_EPSILON * (zs + abs(zc));
    float num = l.p[2] - zc - l.tol - l.tol - zerr;
    bool above = num > 0.0; // false for NaN too
    if (!above) {
        return uvec2(r, extra);
    }
    float sd_lo = sd - sd_err;
    if (sd_lo >= sc) {
        return uvec2(max(cap, r), extra);
    }
    float den = (sc - sd_lo) * (1.0 + 4.0 * REAL_EPSILON);
    float x = num / den * (1.0 - 4.0 * REAL_EPSILON);
    bool short_step = x < float(cap); // false for NaN and +inf
    if (!short_step) {
        return uvec2(max(cap, r), extra);
    }
    return uvec2(max(uint(floor(x)), r), extra);
}

// The rise per centerline of the closure of `cc::trace`, and its rounding bound.
vec2 cc_rise(vec3 d) {
    uint ray_class = ray_class_of(d[0], d[1]);
    int ax = safety_axis_of(ray_class);
    float dm = abs(d[ax]);
    float sd = ((dm > 0.0) ? (d[2] / dm) : (0.0));
    float sd_err = 2.0 * REAL_EPSILON * abs(sd);
    return vec2(sd, sd_err);
}

// `trace_on`: `trace` finishing on `surface` (HF_SURFACE_TRIANGLES or
// HF_SURFACE_VIEW_LINEAR; the same map bounds both, see safety_march_surface).
Trace cc_trace_on(uint surface, Query q) { return safety_march(surface, q, safety_rays_hold(q)); }

// `trace`: the safety march with cylinder-cone steps, on the triangle surface.
Trace cc_trace(Query q) { return cc_trace_on(HF_SURFACE_TRIANGLES, q); }
