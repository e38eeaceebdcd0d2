// Mirror of core/src/safety.rs (the march; the bake stays on the CPU): safety
// distances (Baboud, Eisemann, Seidel 2011) on the triangle surface, or (§7 of the
// paper, `MarchSurface`) on the view-linear surface from the same triangle-baked maps.
// The walk is the one of dda_trace up to the ray's first centerline of its main axis;
// then at each centerline m: fetch k, evaluate the clearance at m + k from the two
// samples on that centerline; above, jump; below, bisect on integer centerlines and
// finish with the exact cell test of the march's surface.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", safety): `hf_safety_map`, the overrides
// `hf_safety_variant` (directional or isotropic) and `hf_safety_classes` (the classes it
// holds; `SafetyMap::with_classes`). A ray of a class the map does not hold reads
// distance 0 without a fetch (it walks cell by cell, still exact).
//
// Ray sets (docs/DESIGN.md, "Ray sets"; `Rays`): the safety-distance or cylinder-cone
// map in use was baked for exterior rays only when `hf_rays_exterior` is 1, and for
// rays within `hf_rays_max_view_angle` degrees of the downward vertical (180: any
// direction), and over `hf_occluder_count` occluders (below). A ray outside the set
// reads distance 0 and no cone (one fetch counted, as for a class the map does not
// hold): it walks cell by cell, still exact.

@group(0) @binding(5) var hf_safety_map: texture_2d<u32>;
override hf_safety_variant: u32 = 0u;
override hf_safety_classes: u32 = 15u;
override hf_rays_exterior: u32 = 0u;
override hf_rays_max_view_angle: f32 = 180.0;
//#if occluders

// Occluders (`Rays::occluders`, `Occluder`): a map baked over `hf_occluder_count` of
// them (0: none) serves only the rays whose line, up to where it leaves the field's
// footprint, passes over the solid under every triangle. Their corners (x, y, z) are
// texels (3k, 0), (3k + 1, 0) and (3k + 2, 0) of `hf_occluders`.
@group(0) @binding(23) var hf_occluders: texture_2d<f32>;
override hf_occluder_count: u32 = 0u;

// `footprint_exit`: where the line p + t d leaves the field's footprint
// [0, W - 1] x [0, H - 1], a little late; infinity when it never does or never meets it.
fn safety_footprint_exit(p: vec3<f32>, d: vec3<f32>) -> f32 {
    let ends: vec2<f32> = vec2<f32>(f32(field_width() - 1u), f32(field_height() - 1u));
    var lo: f32 = -real_infinity();
    var hi: f32 = real_infinity();
    for (var a: i32 = 0; a < 2; a++) {
        if (d[a] != 0.0) {
            let t0: f32 = (0.0 - p[a]) / d[a];
            let t1: f32 = (ends[a] - p[a]) / d[a];
            lo = real_max(lo, real_min(t0, t1));
            hi = real_min(hi, real_max(t0, t1));
        } else if (p[a] < 0.0 || p[a] > ends[a]) {
            return real_infinity();
        }
    }
    if (lo > hi) {
        return real_infinity();
    }
    return hi + 1e-5 * (1.0 + abs(hi));
}

// `Occluder::dips_under`: whether the line p + t d, t <= t_hi, comes within the
// guard's margin of the solid under occluder k over its closed footprint. The core
// checks in f64 with the same margin, 1e-5 (1 + the largest coordinate of the
// triangle and of p): far above the difference.
fn safety_dips_under(k: u32, p: vec3<f32>, d: vec3<f32>, t_hi: f32) -> bool {
    let a: vec3<f32> = textureLoad(hf_occluders, vec2<u32>(3u * k, 0u), 0).xyz;
    let b: vec3<f32> = textureLoad(hf_occluders, vec2<u32>(3u * k + 1u, 0u), 0).xyz;
    let c: vec3<f32> = textureLoad(hf_occluders, vec2<u32>(3u * k + 2u, 0u), 0).xyz;
    let area: f32 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let orient: f32 = select(-1.0, 1.0, area > 0.0);
    var lo: f32 = -real_infinity();
    var hi: f32 = t_hi;
    for (var e: u32 = 0u; e < 3u; e++) {
        let e0: vec3<f32> = select(select(c, b, e == 1u), a, e == 0u);
        let e1: vec3<f32> = select(select(a, c, e == 1u), b, e == 0u);
        let ex: f32 = e1[0] - e0[0];
        let ey: f32 = e1[1] - e0[1];
        let alpha: f32 = orient * (ex * (p[1] - e0[1]) - ey * (p[0] - e0[0]));
        let beta: f32 = orient * (ex * d[1] - ey * d[0]);
        if (beta > 0.0) {
            lo = real_max(lo, -alpha / beta);
        } else if (beta < 0.0) {
            hi = real_min(hi, -alpha / beta);
        } else if (alpha < 0.0) {
            return false;
        }
    }
    if (lo > hi) {
        return false;
    }
    let gx: f32 = ((b[2] - a[2]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[2] - a[2])) / area;
    let gy: f32 = ((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0])) / area;
    let depth0: f32 = a[2] + gx * (p[0] - a[0]) + gy * (p[1] - a[1]) - p[2];
    let rate: f32 = gx * d[0] + gy * d[1] - d[2];
    let big: vec3<f32> = max(max(abs(a), abs(b)), max(abs(c), abs(p)));
    let margin: f32 = 1e-5 * (1.0 + max(max(big[0], big[1]), big[2]));
    if (rate == 0.0) {
        return depth0 > -margin;
    }
    let end: f32 = select(hi, lo, rate < 0.0);
    return !real_is_finite(end) || depth0 + rate * end > -margin;
}
//#endif

// `Rays::holds`: whether q is a ray of the map's set. The core checks in f64, here in
// f32; the set's margin (a millionth) is far above the difference.
fn safety_rays_hold(q: Query) -> bool {
    if (hf_rays_exterior != 0u) {
        let p: vec3<f32> = query_at(q, q.t_min);
        let w: f32 = f32(field_width() - 1u);
        let h: f32 = f32(field_height() - 1u);
        let outside: bool = p[0] < 0.0 || p[0] > w || p[1] < 0.0 || p[1] > h ||
                            p[2] < field_min_height() || p[2] > field_max_height();
        if (!outside) {
            return false;
        }
    }
    if (hf_rays_max_view_angle < 180.0) {
        // `Rays::rise_bound`: a rise of at most tau = -cot(angle) per unit of
        // horizontal distance.
        let a: f32 = hf_rays_max_view_angle * 0.017453292519943295;
        let tau: f32 = -cos(a) / sin(a);
        let d: vec3<f32> = q.dir;
        let run: f32 = sqrt(d[0] * d[0] + d[1] * d[1]);
        let bound: f32 = tau * run - 1e-6 * (abs(tau) * run + abs(d[2]));
        if (d[2] > bound) {
            return false;
        }
    }
//#if occluders
    if (hf_occluder_count > 0u) {
        let t_hi: f32 = safety_footprint_exit(q.origin, q.dir);
        for (var k: u32 = 0u; k < hf_occluder_count; k++) {
            if (safety_dips_under(k, q.origin, q.dir, t_hi)) {
                return false;
            }
        }
    }
//#endif
    return true;
}

// `RayClasses::contains`: whether the set `classes` (HF_RAYS_* bits) holds ray_class.
fn safety_holds(classes: u32, ray_class: u32) -> bool { return (classes & (1u << ray_class)) != 0u; }

// `RayClasses::count`: how many of the four classes `classes` holds (bit by bit:
// GLSL 3.30 has no bitCount).
fn safety_class_count(classes: u32) -> u32 {
    return (classes & 1u) + ((classes >> 1u) & 1u) + ((classes >> 2u) & 1u) + ((classes >> 3u) & 1u);
}

// `ClassRows::index` (the row): texel row j of a class-per-row map holding `classes`
// (HF_RAYS_* bits, which must hold ray_class) is row n j + slot for its n classes, slot
// = `RayClasses::slot(ray_class)`, the held classes before ray_class.
fn safety_class_row(classes: u32, ray_class: u32, j: u32) -> u32 {
    return safety_class_count(classes) * j + safety_class_count(classes & ((1u << ray_class) - 1u));
}

// `SafetyMap::distance`: safety distance of texel (i, j) for `ray_class` (0, without a
// fetch, when the map does not hold it).
fn safety_distance(ray_class: u32, i: u32, j: u32) -> u32 {
    if (!safety_holds(hf_safety_classes, ray_class)) {
        return 0u;
    }
//#if any_variant
    let row: u32 = select(j, safety_class_row(hf_safety_classes, ray_class, j),
                     hf_safety_variant == HF_SAFETY_DIRECTIONAL);
    return textureLoad(hf_safety_map, vec2<u32>(i, row), 0).r;
//#else
//#if directional
    return textureLoad(hf_safety_map, vec2<u32>(i, safety_class_row(hf_safety_classes, ray_class, j)), 0).r;
//#endif
//#if isotropic
    return textureLoad(hf_safety_map, vec2<u32>(i, j), 0).r;
//#endif
//#endif
}

// `axis_of`: main axis (0 = x, 1 = y) of a ray_class.
fn safety_axis_of(ray_class: u32) -> i32 {
    return select(1, 0, ray_class == HF_RAY_CLASS_X_POS || ray_class == HF_RAY_CLASS_X_NEG);
}

// `sample`: sample at main index m, minor index n of axis ax.
fn safety_sample(ax: i32, m: u32, n: u32) -> f32 {
    if (ax == 0) {
        return field_at(m, n);
    }
    return field_at(n, m);
}

// `extents`: samples along (main, minor) of axis ax.
fn safety_extents(ax: i32) -> vec2<u32> {
    return select(vec2<u32>(field_height(), field_width()), vec2<u32>(field_width(), field_height()),
                  ax == 0);
}

// `Line<f32>`: the ray where it crosses the main-axis centerline m.
struct SafetyLine {
    m: u32,
    t: f32,
    p: vec3<f32>,
    c: f32,
    edge: u32,
    texel: u32,
    tol: f32,
}

// `line_at`: evaluates the crossing of centerline m of axis ax; two fetches.
fn safety_line_at(q: Query, ax: i32, m: u32) -> SafetyLine {
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    let mi: i32 = 1 - ax;
    let ln: u32 = safety_extents(ax)[1];
    let t: f32 = (f32(m) - o[ax]) / d[ax];
    var p: vec3<f32> = query_at(q, t);
    p[ax] = f32(m);
    let y: f32 = real_clamp_to(p[mi], 0.0, f32(ln - 1u));
    let edge: u32 = min(u32(floor(y)), ln - 2u);
    let v: f32 = y - f32(edge);
    let h0: f32 = safety_sample(ax, m, edge);
    let h1: f32 = safety_sample(ax, m, edge + 1u);
    let c: f32 = p[2] - real_lerp(h0, h1, v);
    let texel: u32 = select(edge + 1u, edge, v < 0.5);
    let ys: f32 = 1.0 + abs(o[mi]) + abs(p[mi]);
    let zs: f32 = 1.0 + abs(o[2]) + abs(p[2]) + abs(h0) + abs(h1 - h0) * ys;
    let rel: f32 = real_max(32.0 * REAL_EPSILON, 9.313225746154785e-10);
    let tol: f32 = select(rel * zs, real_infinity(), 8.0 * REAL_EPSILON * ys > HF_SAFETY_SEG_PAD);
    return SafetyLine(m, t, p, c, edge, texel, tol);
}

// `Step`: what one stretch of cell-by-cell walking came to.
const SAFETY_STEP_HIT: i32 = 0;
const SAFETY_STEP_LINE: i32 = 1;
const SAFETY_STEP_END: i32 = 2;

// `March`: the state of the march, the cell walk of dda_trace on `surface`.
struct SafetyMarch {
    surface: u32,
    span: Span,
    ax: i32,
    step: vec2<i32>,
    cells: vec2<u32>,
    ic: vec2<u32>,
    c: vec4<f32>,
    stale: bool,
    a: vec3<f32>,
    ca: f32,
    ta: f32,
    wall: vec3<f32>,
    tn: vec2<f32>,
    fetches: u32,
    clearance: f32,
}

// `March::line`: a centerline evaluation, counted.
fn safety_march_line(mr: ptr<function, SafetyMarch>, q: Query, m: u32) -> SafetyLine {
    (*mr).fetches += 2u;
    let l: SafetyLine = safety_line_at(q, (*mr).ax, m);
    if (l.c > 0.0) {
        (*mr).clearance = real_min((*mr).clearance, l.c);
    }
    return l;
}

// `March::wall_of`: normal of a wall facing the ray on `axis`.
fn safety_march_wall_of(mr: SafetyMarch, axis: i32) -> vec3<f32> {
    var n: vec3<f32> = vec3<f32>(0.0);
    n[axis] = select(1.0, -1.0, mr.step[axis] > 0);
    return n;
}

// `March::enter`: puts the walk just past the crossing l (above the surface).
fn safety_march_enter(mr: ptr<function, SafetyMarch>, q: Query, l: SafetyLine) {
    let ax: i32 = (*mr).ax;
    let mi: i32 = 1 - (*mr).ax;
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    (*mr).ic[ax] = select(l.m - 1u, l.m, (*mr).step[ax] > 0);
    let y: f32 = real_clamp_to(l.p[mi], 0.0, f32((*mr).cells[mi]));
    (*mr).ic[mi] = dda_cell_index(y, d[mi], (*mr).cells[mi]);
    (*mr).a[ax] = select(1.0, 0.0, (*mr).step[ax] > 0);
    (*mr).a[mi] = real_clamp_to(l.p[mi] - f32((*mr).ic[mi]), 0.0, 1.0);
    (*mr).a[2] = l.p[2];
    (*mr).ca = l.c;
    (*mr).ta = l.t;
    (*mr).wall = safety_march_wall_of(*mr, ax);
    for (var k: i32 = 0; k < 2; k++) {
        (*mr).tn[k] = dda_next_crossing((*mr).ic[k], (*mr).step[k], o[k], d[k]);
    }
    (*mr).stale = true;
}

// `March::walk`: walks cell by cell, as dda_trace, up to the next main-axis
// centerline (SAFETY_STEP_LINE, `line`), the hit (SAFETY_STEP_HIT, `hit`), or the end.
fn safety_march_walk(mr: ptr<function, SafetyMarch>, q: Query, hit: ptr<function, Hit>,
                     line: ptr<function, SafetyLine>) -> i32 {
    let ax: i32 = (*mr).ax;
    let mi: i32 = 1 - (*mr).ax;
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    *hit = hit_none();
    *line = SafetyLine(0u, 0.0, vec3<f32>(0.0), 0.0, 0u, 0u, 0.0);
    loop {
        if ((*mr).stale) {
            (*mr).c = surface_corners((*mr).ic[0], (*mr).ic[1]);
            (*mr).fetches += 4u;
            (*mr).stale = false;
        }
        var cross: vec2<bool>;
        let tb: f32 = dda_exit((*mr).tn, (*mr).ta, (*mr).span.t1, &cross);
        let on: vec2<i32> = dda_exit_on((*mr).step, cross);
        let p: vec3<f32> = query_at(q, tb);
        var b: vec3<f32>;
        var cb: f32 = dda_local_clearance((*mr).surface, (*mr).c, (*mr).ic, p, on, &b);
        var has_line: bool = false;
        if (cross[ax]) {
            // The clearance the jumps use at this centerline (same samples, same
            // arithmetic), so walking and jumping agree.
            let m: u32 = select((*mr).ic[ax], (*mr).ic[ax] + 1u, (*mr).step[ax] > 0);
            let l: SafetyLine = safety_line_at(q, ax, m);
            if (l.edge != (*mr).ic[mi]) {
                (*mr).fetches += 2u;
            }
            cb = l.c;
            *line = l;
            has_line = true;
        }
        let seg: SegmentHit = surface_segment_hit((*mr).surface, (*mr).c, (*mr).a, b, (*mr).ca, cb, (*mr).wall);
        (*mr).clearance = real_min((*mr).clearance, seg.clearance);
        if (seg.has_hit) {
            *hit = dda_segment_point(seg, (*mr).ic, (*mr).a, b, (*mr).ta, tb);
            return SAFETY_STEP_HIT;
        }
        if (!(cross[0] || cross[1])) {
            return SAFETY_STEP_END;
        }
        for (var k: i32 = 0; k < 2; k++) {
            if (cross[k]) {
                let next: i32 = i32((*mr).ic[k]) + (*mr).step[k];
                if (next < 0 || next >= i32((*mr).cells[k])) {
                    return SAFETY_STEP_END;
                }
                (*mr).ic[k] = u32(next);
                (*mr).tn[k] = dda_next_crossing((*mr).ic[k], (*mr).step[k], o[k], d[k]);
            }
        }
        (*mr).wall = safety_march_wall_of(*mr, select(1, 0, cross[0]));
        (*mr).a = dda_next_entry(b, cross);
        (*mr).ca = cb;
        (*mr).ta = tb;
        (*mr).stale = true;
        if (has_line) {
            return SAFETY_STEP_LINE;
        }
    }
    return SAFETY_STEP_END;
}

// `March::done`.
fn safety_march_done(mr: SafetyMarch, has_hit: bool, hit: Hit, flags: u32) -> Trace {
    return Trace(has_hit, hit, mr.fetches, mr.clearance, flags);
}

// `last_line`: last main-axis centerline the ray crosses strictly before t1 (false
// when there is none), with the crossing formula of the walk.
fn safety_last_line(q: Query, ax: i32, sg: i32, t1: f32, last: ptr<function, u32>) -> bool {
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    let lm: i32 = i32(safety_extents(ax)[0]);
    let x1: f32 = real_clamp_to(o[ax] + t1 * d[ax], 0.0, f32(lm - 1));
    var m: i32 = i32(floor(x1)) + i32(sg < 0 && floor(x1) != x1);
    while (m >= 0 && m < lm && (f32(u32(m)) - o[ax]) / d[ax] >= t1) {
        m -= sg;
    }
    while (m + sg >= 0 && m + sg < lm && (f32(u32(m + sg)) - o[ax]) / d[ax] < t1) {
        m += sg;
    }
    *last = u32(max(m, 0));
    return m >= 0 && m < lm;
}

// The closure `jump(line, class, i, j)` of `march`: reads the baked data of texel
// (i, j) (one fetch, counted by the march) and returns (x) how many centerlines the ray
// crossing `l` above that texel's segment may skip and (y) the fetches it took beyond
// that one (`d` is the query's direction, which the Rust closures capture). Defined by
// the method's file (method_safety.wgsl, method_cc.wgsl, method_radius.wgsl):
// fn safety_march_jump(l: SafetyLine, ray_class: u32, i: u32, j: u32, d: vec3<f32>) -> vec2<u32>
//#glsl
// uvec2 safety_march_jump(SafetyLine l, uint ray_class, uint i, uint j, vec3 d);
//#end

// `MarchSurface::of(surface)` then `MarchSurface::surface`: the surface a safety-shape
// march finishes on, HF_SURFACE_TRIANGLES or HF_SURFACE_VIEW_LINEAR (the surfaces the
// triangle-baked maps bound). Any other surface (where Rust has no MarchSurface) falls
// back to the triangles; only a general shader's runtime `hf_surface` can ask for one,
// since a generated shader of another surface is refused (`supports`).
fn safety_march_surface(surface: u32) -> u32 {
//#if any_surface
    return select(HF_SURFACE_TRIANGLES, HF_SURFACE_VIEW_LINEAR, surface == HF_SURFACE_VIEW_LINEAR);
//#else
    return surface;
//#endif
}

// `march`: the march shared by the safety-shape methods; the walk between jumps and
// the final test use `march_surface` (see safety_march_surface). `held`: whether the
// map's data serves q (safety_rays_hold); else every jump reads 0.
fn safety_march(march_surface: u32, q: Query, held: bool) -> Trace {
    var span: Span;
    if (!dda_clip(q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    let d: vec3<f32> = q.dir;
    let ray_class: u32 = ray_class_of(d[0], d[1]);
    let ax: i32 = safety_axis_of(ray_class);
    let cells: vec2<u32> = dda_cells();
    let p0: vec3<f32> = query_at(q, span.t0);
    let x0: f32 = real_clamp_to(p0[0], 0.0, f32(cells[0]));
    let y0: f32 = real_clamp_to(p0[1], 0.0, f32(cells[1]));
    let step: vec2<i32> = vec2<i32>(dda_step_of(d[0]), dda_step_of(d[1]));
    let ic: vec2<u32> = vec2<u32>(dda_cell_index(x0, d[0], cells[0]), dda_cell_index(y0, d[1], cells[1]));
    let c: vec4<f32> = surface_corners(ic[0], ic[1]);
    let surface: u32 = safety_march_surface(march_surface);
    var a: vec3<f32>;
    let ca: f32 = dda_local_clearance(surface, c, ic, vec3<f32>(x0, y0, p0[2]), dda_entry_on(surface, span), &a);
    if (ca <= 0.0) {
        return trace_hit(dda_start_hit(surface, span, c, ic, a, p0), 4u,
                         dda_start_clearance(span, ca));
    }
    var mr: SafetyMarch = SafetyMarch(surface, span, ax, step, cells, ic, c, false, a, ca, span.t0,
                         vec3<f32>(0.0, 0.0, 1.0),
                         dda_crossings(ic, step, q),
                         4u, ca);
    let sg: i32 = step[ax];
    var last: u32 = 0u;
    let has_last: bool = sg != 0 && safety_last_line(q, ax, sg, span.t1, &last);
    var budget: u32 = safety_extents(ax)[0] + 8u;
    var hit: Hit;
    var l: SafetyLine;
    var st: i32 = safety_march_walk(&mr, q, &hit, &l);
    loop {
        if (st == SAFETY_STEP_HIT) {
            return safety_march_done(mr, true, hit, 0u);
        } else if (st == SAFETY_STEP_END) {
            return safety_march_done(mr, false, hit_none(), 0u);
        }
        if (budget == 0u) {
            return safety_march_done(mr, false, hit_none(), HF_FLAG_BUDGET_EXHAUSTED);
        }
        budget -= 1u;
        if (!has_last || last == l.m) {
            st = safety_march_walk(&mr, q, &hit, &l);
            continue;
        }
        var k: u32 = 0u;
        if (l.c > l.tol) {
            mr.fetches += 1u;
            if (held) {
                let ij: vec2<u32> = select(vec2<u32>(l.texel, l.m), vec2<u32>(l.m, l.texel), ax == 0);
                let jump: vec2<u32> = safety_march_jump(l, ray_class, ij[0], ij[1], d);
                k = jump.x;
                mr.fetches += jump.y;
            }
        }
        if (k == 0u) {
            st = safety_march_walk(&mr, q, &hit, &l);
            continue;
        }
        let room: u32 = u32(abs(i32(last) - i32(l.m)));
        // `target` in Rust and GLSL, a reserved word in WGSL.
        let goal: u32 = u32(i32(l.m) + sg * i32(min(k, room)));
        let lt: SafetyLine = safety_march_line(&mr, q, goal);
        if (lt.c > 0.0) {
            safety_march_enter(&mr, q, lt);
            l = lt;
            st = SAFETY_STEP_LINE;
            continue;
        }
        // Below at the target, above at m, and no exit in between: bisect.
        var lo: SafetyLine = l;
        var hi: u32 = goal;
        while (abs(i32(hi) - i32(lo.m)) > 1) {
            let mid: u32 = u32((i32(hi) + i32(lo.m)) / 2);
            let lm: SafetyLine = safety_march_line(&mr, q, mid);
            if (lm.c > 0.0) {
                lo = lm;
            } else {
                hi = mid;
            }
        }
        safety_march_enter(&mr, q, lo);
        st = safety_march_walk(&mr, q, &hit, &l);
    }
    return safety_march_done(mr, false, hit_none(), 0u);
}

// `trace_on`: `trace` finishing on `surface` (HF_SURFACE_TRIANGLES or
// HF_SURFACE_VIEW_LINEAR; see safety_march_surface), from the same map.
fn safety_trace_on(surface: u32, q: Query) -> Trace { return safety_march(surface, q, safety_rays_hold(q)); }

// `trace`: traces q on the triangle surface with the safety distances.
fn safety_trace(q: Query) -> Trace { return safety_trace_on(HF_SURFACE_TRIANGLES, q); }
