// Generated from shaders/wgsl/relaxed.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/relaxed.rs (the march; the bake stays on the CPU): relaxed cone
// stepping (Policarpo & Oliveira 2007), approximate: cone steps until the ray is under
// the surface, then a binary search between the last two points.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", relaxed cone): `hf_relaxed_map`.

uniform sampler2D hf_relaxed_map;

// The closure `above` of `trace_steps`: the ray's height over the surface at t.
float relaxed_above(Query q, float t, inout uint fetches) {
    vec3 p = query_at(q, t);
    fetches += 4u;
    return p[2] - surface_height_at(HF_SURFACE_TRIANGLES, p[0], p[1]);
}

// The closure `hit` of `trace_steps`.
Trace relaxed_hit(Query q, float t, uint fetches, uint flags) {
    vec3 p = query_at(q, t);
    float xm = float(field_width() - 1u);
    float ym = float(field_height() - 1u);
    float x = real_clamp_to(p[0], 0.0, xm);
    float y = real_clamp_to(p[1], 0.0, ym);
    uvec2 cell = uvec2(min(uint(floor(x)), field_width() - 2u), min(uint(floor(y)), field_height() - 2u));
    Trace tr = trace_hit(Hit(t, p, cell, surface_normal_at(HF_SURFACE_TRIANGLES, x, y), 0u), fetches, real_infinity());
    tr.flags = flags;
    return tr;
}

// `trace` (`trace_steps`): at most `cone_steps` cone steps, then `binary` bisections.
Trace relaxed_trace(Query q, uint cone_steps, uint binary) {
    Span span;
    if (!dda_clip(q, span)) {
        return trace_miss(0u, real_infinity());
    }
    vec3 d = q.dir;
    float hs = sqrt(d[0] * d[0] + d[1] * d[1]);
    uint w = field_width();
    float xm = float(w - 1u);
    float ym = float(field_height() - 1u);
    uint fetches = 0u;
    float t = span.t0;
    float dh = relaxed_above(q, t, fetches);
    if (dh <= 0.0) {
        return relaxed_hit(q, t, fetches, 0u);
    }
    float t_prev = t;
    uint n = 0u;
    while (dh > 0.0) {
        if (n == cone_steps) {
            return relaxed_hit(q, t, fetches, HF_FLAG_BUDGET_EXHAUSTED);
        }
        n += 1u;
        vec3 p = query_at(q, t);
        uint i = uint(floor(real_clamp_to(p[0], 0.0, xm) + 0.5));
        uint j = uint(floor(real_clamp_to(p[1], 0.0, ym) + 0.5));
        float r = texelFetch(hf_relaxed_map, ivec2(min(i, w - 1u), j), 0).r;
        fetches += 1u;
        float denom = ((hs == 0.0) ? (-d[2]) : (hs / r - d[2]));
        if (!(denom > 0.0)) {
            return trace_miss(fetches, real_infinity());
        }
        t_prev = t;
        t = t + dh / denom;
        if (!(t <= span.t1)) {
            return trace_miss(fetches, real_infinity());
        }
        dh = relaxed_above(q, t, fetches);
    }
    // Binary search between the last point above and the first one under.
    float lo = t_prev;
    float hi = t;
    for (uint k = 0u; k < binary; k++) {
        float mid = 0.5 * (lo + hi);
        if (relaxed_above(q, mid, fetches) > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return relaxed_hit(q, hi, fetches, 0u);
}
