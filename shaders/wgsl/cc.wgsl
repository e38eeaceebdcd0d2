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

@group(0) @binding(9) var hf_cc_map: texture_2d<u32>;
override hf_cc_classes: u32 = 15u;

//#wgsl
// A 4-byte uniform: WGSL and wgpu need no padding for a struct of one u32.
struct CcParams {
    cap: u32,
}

@group(0) @binding(10) var<uniform> hf_cc: CcParams;

// The bake's cap.
fn cc_cap() -> u32 { return hf_cc.cap; }
//#end
//#glsl
// uniform uint hf_cc_cap;
//
// // The bake's cap.
// uint cc_cap() { return hf_cc_cap; }
//#end

// `CcMap::texel`: the bytes [r, s] of texel (i, j) for `ray_class` ([0, HF_CC_NO_CONE],
// without a fetch, when the map does not hold it).
fn cc_texel(ray_class: u32, i: u32, j: u32) -> vec2<u32> {
    if (!safety_holds(hf_cc_classes, ray_class)) {
        return vec2<u32>(0u, HF_CC_NO_CONE);
    }
    return textureLoad(hf_cc_map, vec2<u32>(i, safety_class_row(hf_cc_classes, ray_class, j)), 0).rg;
}

// `decode_slope` (finite codes): `t |t| / 2048` with `t = code - 128`, exact in float.
fn cc_decode_slope(code: u32) -> f32 {
    let t: f32 = f32(i32(code) - 128);
    return t * abs(t) / 2048.0;
}

// `ConeStep::base`: the cone's base height over texel n of centerline m of axis ax (ln
// samples along the minor axis), the highest point of the surface on the texel's
// widened segment (half a sample spacing plus HF_SAFETY_SEG_PAD towards each
// neighbour, the one-sided slope at the field's border). Beyond the line's two samples
// it reads the third only inside the field (`if`, not `select`, which would load
// outside it).
fn cc_line_base(ax: i32, m: u32, n: u32, ln: u32) -> f32 {
    let h: f32 = safety_sample(ax, m, n);
    var lo: f32 = 0.0;
    if (n > 0u) {
        lo = safety_sample(ax, m, n - 1u);
    }
    var hi: f32 = 0.0;
    if (n + 1u < ln) {
        hi = safety_sample(ax, m, n + 1u);
    }
    let below: f32 = select(hi - h, h - lo, n > 0u);
    let above: f32 = select(h - lo, hi - h, n + 1u < ln);
    let w: f32 = 0.5 + HF_SAFETY_SEG_PAD;
    return real_max(real_max(h - below * w, h), h + above * w);
}

// `ConeStep::cone`: the step (centerlines) of a ray of rise `sd` per centerline (`sd_err`
// bounds its rounding) crossing the centerline `l` of axis ax above a texel of shape
// b = [r, s], and the fetches its base height took beyond the shape's (one inside the
// field, none at its border, none when no cone is tested).
fn cc_cone_step(b: vec2<u32>, ax: i32, l: SafetyLine, sd: f32, sd_err: f32) -> vec2<u32> {
    let r: u32 = b[0];
    let cap: u32 = cc_cap();
    if (b[1] == HF_CC_NO_CONE || r >= cap) {
        return vec2<u32>(r, 0u);
    }
    let n: u32 = l.texel;
    let ln: u32 = safety_extents(ax)[1];
    let zc: f32 = cc_line_base(ax, l.m, n, ln);
    let extra: u32 = select(0u, 1u, n > 0u && n + 1u < ln);
    let sc: f32 = cc_decode_slope(b[1]);
    // zc's own rounding: relative EPSILON of the heights.
    let zs: f32 = real_max(abs(field_min_height()), abs(field_max_height()));
    let zerr: f32 = 8.0 * REAL_EPSILON * (zs + abs(zc));
    let num: f32 = l.p[2] - zc - l.tol - l.tol - zerr;
    let above: bool = num > 0.0; // false for NaN too
    if (!above) {
        return vec2<u32>(r, extra);
    }
    let sd_lo: f32 = sd - sd_err;
    if (sd_lo >= sc) {
        return vec2<u32>(max(cap, r), extra);
    }
    let den: f32 = (sc - sd_lo) * (1.0 + 4.0 * REAL_EPSILON);
    let x: f32 = num / den * (1.0 - 4.0 * REAL_EPSILON);
    let short_step: bool = x < f32(cap); // false for NaN and +inf
    if (!short_step) {
        return vec2<u32>(max(cap, r), extra);
    }
    return vec2<u32>(max(u32(floor(x)), r), extra);
}

// The rise per centerline of the closure of `cc::trace`, and its rounding bound.
fn cc_rise(d: vec3<f32>) -> vec2<f32> {
    let ray_class: u32 = ray_class_of(d[0], d[1]);
    let ax: i32 = safety_axis_of(ray_class);
    let dm: f32 = abs(d[ax]);
    let sd: f32 = select(0.0, d[2] / dm, dm > 0.0);
    let sd_err: f32 = 2.0 * REAL_EPSILON * abs(sd);
    return vec2<f32>(sd, sd_err);
}

// `trace_on`: `trace` finishing on `surface` (HF_SURFACE_TRIANGLES or
// HF_SURFACE_VIEW_LINEAR; the same map bounds both, see safety_march_surface).
fn cc_trace_on(surface: u32, q: Query) -> Trace { return safety_march(surface, q, safety_rays_hold(q)); }

// `trace`: the safety march with cylinder-cone steps, on the triangle surface.
fn cc_trace(q: Query) -> Trace { return cc_trace_on(HF_SURFACE_TRIANGLES, q); }
