// Generated from shaders/wgsl/search.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/search.rs: the bake-free baselines, linear search through the
// field's box then a refinement (bisection, or one secant step as in parallax
// occlusion mapping). Approximate. Cost: four fetches per height sample.

// `search` (the closure `clearance_at` is `search_clearance_at`, counting fetches).
float search_clearance_at(uint surface, Query q, float t, inout uint fetches) {
    fetches += 4u;
    vec3 p = query_at(q, t);
    return p[2] - surface_height_at(surface, p[0], p[1]);
}

// `search`: `linear` equal steps, then `binary` bisections (`secant` false) or one
// secant step (`secant` true).
Trace search_search(uint surface, Query q, uint linear_in, bool secant, uint binary) {
    Span span;
    if (!dda_clip_surface(surface, q, span)) {
        return trace_miss(0u, real_infinity());
    }
    uint fetches = 0u;
    uint linear = max(linear_in, 1u);
    float dt = (span.t1 - span.t0) / float(linear);
    vec2 prev = vec2(span.t0, search_clearance_at(surface, q, span.t0, fetches));
    bool bracket = false;
    vec2 above = vec2(0.0);
    vec2 under = vec2(0.0);
    if (prev[1] <= 0.0) {
        bracket = true;
        above = prev;
        under = prev;
    } else {
        for (uint k = 1u; k <= linear; k++) {
            float t = ((k == linear) ? (span.t1) : (span.t0 + dt * float(k)));
            float c = search_clearance_at(surface, q, t, fetches);
            if (c <= 0.0) {
                bracket = true;
                above = prev;
                under = vec2(t, c);
                break;
            }
            prev = vec2(t, c);
        }
    }
    if (!bracket) {
        return trace_miss(fetches, real_infinity());
    }
    float t;
    if (above[0] == under[0]) {
        t = under[0];
    } else if (!secant) {
        for (uint n = 0u; n < binary; n++) {
            float mid = 0.5 * (above[0] + under[0]);
            float c = search_clearance_at(surface, q, mid, fetches);
            if (c <= 0.0) {
                under = vec2(mid, c);
            } else {
                above = vec2(mid, c);
            }
        }
        t = 0.5 * (above[0] + under[0]);
    } else {
        t = above[0] + (under[0] - above[0]) * above[1] / (above[1] - under[1]);
    }
    vec3 p = query_at(q, t);
    SurfaceLocal l = surface_locate(p[0], p[1]);
    uint flags = 0u;
    if (!(t > span.t0)) {
        if (span.entry == HF_ENTRY_START) {
            flags = HF_FLAG_ORIGIN_INSIDE;
        } else if (span.entry == HF_ENTRY_SIDE) {
            flags = HF_FLAG_SIDE;
        }
    }
    return trace_hit(Hit(t, p, l.cell, surface_cell_normal(surface, l.c, l.u, l.v), flags), fetches, real_infinity());
}

// `linear` with `Refine::Binary(binary)`.
Trace search_linear_binary(uint surface, Query q, uint linear, uint binary) {
    return search_search(surface, q, linear, false, binary);
}

// `linear` with `Refine::Secant`.
Trace search_linear_secant(uint surface, Query q, uint linear) {
    return search_search(surface, q, linear, true, 0u);
}
