// Mirror of core/src/search.rs: the bake-free baselines, linear search through the
// field's box then a refinement (bisection, or one secant step as in parallax
// occlusion mapping). Approximate. Cost: four fetches per height sample.

// `search` (the closure `clearance_at` is `search_clearance_at`, counting fetches).
fn search_clearance_at(surface: u32, q: Query, t: f32, fetches: ptr<function, u32>) -> f32 {
    *fetches += 4u;
    let p: vec3<f32> = query_at(q, t);
    return p[2] - surface_height_at(surface, p[0], p[1]);
}

// `search`: `linear` equal steps, then `binary` bisections (`secant` false) or one
// secant step (`secant` true).
fn search_search(surface: u32, q: Query, linear_in: u32, secant: bool, binary: u32) -> Trace {
    var span: Span;
    if (!dda_clip_surface(surface, q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    var fetches: u32 = 0u;
    let linear: u32 = max(linear_in, 1u);
    let dt: f32 = (span.t1 - span.t0) / f32(linear);
    var prev: vec2<f32> = vec2<f32>(span.t0, search_clearance_at(surface, q, span.t0, &fetches));
    var bracket: bool = false;
    var above: vec2<f32> = vec2<f32>(0.0);
    var under: vec2<f32> = vec2<f32>(0.0);
    if (prev[1] <= 0.0) {
        bracket = true;
        above = prev;
        under = prev;
    } else {
        for (var k: u32 = 1u; k <= linear; k++) {
            let t: f32 = select(span.t0 + dt * f32(k), span.t1, k == linear);
            let c: f32 = search_clearance_at(surface, q, t, &fetches);
            if (c <= 0.0) {
                bracket = true;
                above = prev;
                under = vec2<f32>(t, c);
                break;
            }
            prev = vec2<f32>(t, c);
        }
    }
    if (!bracket) {
        return trace_miss(fetches, real_infinity());
    }
    var t: f32;
    if (above[0] == under[0]) {
        t = under[0];
    } else if (!secant) {
        for (var n: u32 = 0u; n < binary; n++) {
            let mid: f32 = 0.5 * (above[0] + under[0]);
            let c: f32 = search_clearance_at(surface, q, mid, &fetches);
            if (c <= 0.0) {
                under = vec2<f32>(mid, c);
            } else {
                above = vec2<f32>(mid, c);
            }
        }
        t = 0.5 * (above[0] + under[0]);
    } else {
        t = above[0] + (under[0] - above[0]) * above[1] / (above[1] - under[1]);
    }
    let p: vec3<f32> = query_at(q, t);
    let l: SurfaceLocal = surface_locate(p[0], p[1]);
    var flags: u32 = 0u;
    if (!(t > span.t0)) {
        if (span.entry == HF_ENTRY_START) {
            flags = HF_FLAG_ORIGIN_INSIDE;
        } else if (span.entry == HF_ENTRY_SIDE) {
            flags = HF_FLAG_SIDE;
        }
    }
    return trace_hit(Hit(t, p, l.cell, surface_cell_normal(surface, l.c, l.u, l.v), flags), fetches,
                     real_infinity());
}

// `linear` with `Refine::Binary(binary)`.
fn search_linear_binary(surface: u32, q: Query, linear: u32, binary: u32) -> Trace {
    return search_search(surface, q, linear, false, binary);
}

// `linear` with `Refine::Secant`.
fn search_linear_secant(surface: u32, q: Query, linear: u32) -> Trace {
    return search_search(surface, q, linear, true, 0u);
}
