// Mirror of core/src/safety/cc.rs (the march; the bake stays on the CPU): cylinder-cone
// safety shapes (Baboud, Eisemann, Seidel 2011, section 6.3) on the triangle surface,
// or the view-linear one from the same map, stepping with the safety march of
// safety.wgsl.
//
// Texture layout: the map of hf_cc_bake as `hf_cc_map`, an RGBA8Uint texture of
// W x nH texels for the n ray classes it holds, the override `hf_cc_classes` (HF_RAYS_*
// bits, HF_RAYS_ALL for a whole map; `CcMap::with_classes`): texel (i, n j + slot) =
// [r, s, z_lo, z_hi] of texel (i, j) for the ray class of that slot (each texel row as
// n rows, one per held class in class order x+, x-, y+, y-; slot = how many held
// classes come before it; a whole map: W x 4H, texel (i, 4 j + class)). A ray of a
// class the map does not hold reads [0, HF_CC_NO_CONE, 0, 0] without a fetch (radius
// 0, no cone: it walks cell by cell, still exact). `hf_cc.cap` is the bake's cap;
// `hf_cc.zmin`, `hf_cc.zstep`, `hf_cc.zspan` the frame of the base heights
// (hf_cc_frame).

struct CcParams {
    cap: u32,
    zmin: f32,
    zstep: f32,
    zspan: f32,
}

@group(0) @binding(9) var hf_cc_map: texture_2d<u32>;
@group(0) @binding(10) var<uniform> hf_cc: CcParams;
override hf_cc_classes: u32 = 15u;

// `CcMap::texel`: the packed bytes of texel (i, j) for `ray_class` ([0, HF_CC_NO_CONE,
// 0, 0], without a fetch, when the map does not hold it).
fn cc_texel(ray_class: u32, i: u32, j: u32) -> vec4<u32> {
    if (!safety_holds(hf_cc_classes, ray_class)) {
        return vec4<u32>(0u, HF_CC_NO_CONE, 0u, 0u);
    }
    return textureLoad(hf_cc_map, vec2<u32>(i, safety_class_row(hf_cc_classes, ray_class, j)), 0);
}

// `decode_slope` (finite codes): `t |t| / 2048` with `t = code - 128`, exact in float.
fn cc_decode_slope(code: u32) -> f32 {
    let t = f32(i32(code) - 128);
    return t * abs(t) / 2048.0;
}

// `cone_step`: the step (centerlines) of a ray of rise `sd` per centerline (`sd_err`
// bounds its rounding) crossing the centerline at height `pz` (within `tol`) above a
// texel of shape b = [r, s, z0, z1].
fn cc_cone_step(b: vec4<u32>, pz: f32, tol: f32, sd: f32, sd_err: f32) -> u32 {
    let r = b[0];
    let cap = hf_cc.cap;
    if (b[1] == HF_CC_NO_CONE || r >= cap) {
        return r;
    }
    let zc = hf_cc.zmin + f32(b[2] | (b[3] << 8u)) * hf_cc.zstep;
    let sc = cc_decode_slope(b[1]);
    // zc's own rounding: relative EPSILON of the terms.
    let zerr = 4.0 * REAL_EPSILON * (abs(hf_cc.zmin) + hf_cc.zspan + abs(zc));
    let num = pz - zc - tol - tol - zerr;
    let above = num > 0.0; // false for NaN too
    if (!above) {
        return r;
    }
    let sd_lo = sd - sd_err;
    if (sd_lo >= sc) {
        return max(cap, r);
    }
    let den = (sc - sd_lo) * (1.0 + 4.0 * REAL_EPSILON);
    let x = num / den * (1.0 - 4.0 * REAL_EPSILON);
    let short_step = x < f32(cap); // false for NaN and +inf
    if (!short_step) {
        return max(cap, r);
    }
    return max(u32(floor(x)), r);
}

// The rise per centerline of the closure of `cc::trace`, and its rounding bound.
fn cc_rise(d: vec3<f32>) -> vec2<f32> {
    let ray_class = ray_class_of(d[0], d[1]);
    let ax = safety_axis_of(ray_class);
    let dm = abs(d[ax]);
    let sd = select(0.0, d[2] / dm, dm > 0.0);
    let sd_err = 2.0 * REAL_EPSILON * abs(sd);
    return vec2<f32>(sd, sd_err);
}

// `trace_on`: `trace` finishing on `surface` (HF_SURFACE_TRIANGLES or
// HF_SURFACE_VIEW_LINEAR; the same map bounds both, see safety_march_surface).
fn cc_trace_on(surface: u32, q: Query) -> Trace { return safety_march(surface, q); }

// `trace`: the safety march with cylinder-cone steps, on the triangle surface.
fn cc_trace(q: Query) -> Trace { return cc_trace_on(HF_SURFACE_TRIANGLES, q); }
