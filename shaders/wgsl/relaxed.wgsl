// Mirror of core/src/relaxed.rs (the march; the bake stays on the CPU): relaxed cone
// stepping (Policarpo & Oliveira 2007), approximate: cone steps until the ray is under
// the surface, then a binary search between the last two points.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", relaxed cone): `hf_relaxed_map`.

@group(0) @binding(8) var hf_relaxed_map: texture_2d<f32>;

// The closure `above` of `trace_steps`: the ray's height over the surface at t.
fn relaxed_above(q: Query, t: f32, fetches: ptr<function, u32>) -> f32 {
    let p: vec3<f32> = query_at(q, t);
    *fetches += 4u;
    return p[2] - surface_height_at(HF_SURFACE_TRIANGLES, p[0], p[1]);
}

// The closure `hit` of `trace_steps`.
fn relaxed_hit(q: Query, t: f32, fetches: u32, flags: u32) -> Trace {
    let p: vec3<f32> = query_at(q, t);
    let xm: f32 = f32(field_width() - 1u);
    let ym: f32 = f32(field_height() - 1u);
    let x: f32 = real_clamp_to(p[0], 0.0, xm);
    let y: f32 = real_clamp_to(p[1], 0.0, ym);
    let cell: vec2<u32> = vec2<u32>(min(u32(floor(x)), field_width() - 2u),
                         min(u32(floor(y)), field_height() - 2u));
    var tr: Trace = trace_hit(Hit(t, p, cell, surface_normal_at(HF_SURFACE_TRIANGLES, x, y), 0u),
                       fetches, real_infinity());
    tr.flags = flags;
    return tr;
}

// `trace` (`trace_steps`): at most `cone_steps` cone steps, then `binary` bisections.
fn relaxed_trace(q: Query, cone_steps: u32, binary: u32) -> Trace {
    var span: Span;
    if (!dda_clip(q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    let d: vec3<f32> = q.dir;
    let hs: f32 = sqrt(d[0] * d[0] + d[1] * d[1]);
    let w: u32 = field_width();
    let xm: f32 = f32(w - 1u);
    let ym: f32 = f32(field_height() - 1u);
    var fetches: u32 = 0u;
    var t: f32 = span.t0;
    var dh: f32 = relaxed_above(q, t, &fetches);
    if (dh <= 0.0) {
        return relaxed_hit(q, t, fetches, 0u);
    }
    var t_prev: f32 = t;
    var n: u32 = 0u;
    while (dh > 0.0) {
        if (n == cone_steps) {
            return relaxed_hit(q, t, fetches, HF_FLAG_BUDGET_EXHAUSTED);
        }
        n += 1u;
        let p: vec3<f32> = query_at(q, t);
        let i: u32 = u32(floor(real_clamp_to(p[0], 0.0, xm) + 0.5));
        let j: u32 = u32(floor(real_clamp_to(p[1], 0.0, ym) + 0.5));
        let r: f32 = textureLoad(hf_relaxed_map, vec2<u32>(min(i, w - 1u), j), 0).r;
        fetches += 1u;
        let denom: f32 = select(hs / r - d[2], -d[2], hs == 0.0);
        if (!(denom > 0.0)) {
            return trace_miss(fetches, real_infinity());
        }
        t_prev = t;
        t = t + dh / denom;
        if (!(t <= span.t1)) {
            return trace_miss(fetches, real_infinity());
        }
        dh = relaxed_above(q, t, &fetches);
    }
    // Binary search between the last point above and the first one under.
    var lo: f32 = t_prev;
    var hi: f32 = t;
    for (var k: u32 = 0u; k < binary; k++) {
        let mid: f32 = 0.5 * (lo + hi);
        if (relaxed_above(q, mid, &fetches) > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return relaxed_hit(q, hi, fetches, 0u);
}
