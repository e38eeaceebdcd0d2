// Mirror of core/src/dda.rs: the exact Amanatides-Woo traversal over cells with the
// exact per-cell test of the surface. Watertight as on the CPU: the clearance at each
// centerline crossing comes from that edge's two samples only and is shared by the
// cells on both sides; cell indices are integers and every crossing's t is recomputed
// from them.
//
// `Option<bool>` (the `on` vectors) is an i32: -1 = None, 0 = Some(false), 1 = Some(true).

// `Span<f32>`; `entry` is HF_ENTRY_START, HF_ENTRY_SIDE (normal in `entry_normal`) or
// HF_ENTRY_TOP.
struct Span {
    t0: f32,
    t1: f32,
    entry: u32,
    entry_normal: vec3<f32>,
}

// `clip_surface`: clips a query to the box that holds `surface` over the field; false
// when the ray misses it.
fn dda_clip_surface(surface: u32, q: Query, span: ptr<function, Span>) -> bool {
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    let lim: vec2<f32> = vec2<f32>(f32(field_width() - 1u), f32(field_height() - 1u));
    var t0: f32 = q.t_min;
    var t1: f32 = q.t_max;
    var entry: u32 = HF_ENTRY_START;
    var entry_normal: vec3<f32> = vec3<f32>(0.0);
    *span = Span(0.0, 0.0, HF_ENTRY_START, vec3<f32>(0.0));
    for (var axis: i32 = 0; axis < 2; axis++) {
        if (d[axis] == 0.0) {
            if (o[axis] < 0.0 || o[axis] > lim[axis]) {
                return false;
            }
            continue;
        }
        let a: f32 = (0.0 - o[axis]) / d[axis];
        let b: f32 = (lim[axis] - o[axis]) / d[axis];
        let near: f32 = select(b, a, d[axis] > 0.0);
        let far: f32 = select(a, b, d[axis] > 0.0);
        if (near > t0) {
            t0 = near;
            var n: vec3<f32> = vec3<f32>(0.0);
            n[axis] = select(1.0, -1.0, d[axis] > 0.0);
            entry = HF_ENTRY_SIDE;
            entry_normal = n;
        }
        t1 = real_min(t1, far);
    }
    var zmin: f32 = field_min_height();
    var zmax: f32 = field_max_height();
//#if corner_planes
    if (surface == HF_SURFACE_CORNER_PLANES) {
        let range: f32 = zmax - zmin;
        let lo: f32 = zmin - range;
        let hi: f32 = zmax + range;
        zmin = lo;
        zmax = hi;
    }
//#endif
    if (d[2] == 0.0) {
        if (o[2] > zmax) {
            return false;
        }
//#if upward
    } else if (d[2] > 0.0) {
        t1 = real_min(t1, (zmax - o[2]) / d[2]);
//#endif
    } else {
        let top: f32 = (zmax - o[2]) / d[2];
        if (top > t0) {
            t0 = top;
            entry = HF_ENTRY_TOP;
        }
        // Well under the lowest sample the ray is inside the solid: the hit comes first.
        let margin: f32 = 1.0 + (zmax - zmin);
        t1 = real_min(t1, real_max((zmin - margin - o[2]) / d[2], t0));
    }
    *span = Span(t0, t1, entry, entry_normal);
    return t0 <= t1 && real_is_finite(t0) && real_is_finite(t1);
}

// One slab of `query_walked_back`: where `o + t d` is within [lo, hi], as (near, far)
// (far < near when never).
fn dda_slab(o: f32, d: f32, lo: f32, hi: f32) -> vec2<f32> {
    if (d != 0.0) {
        let a: f32 = (lo - o) / d;
        let b: f32 = (hi - o) / d;
        return vec2<f32>(min(a, b), max(a, b));
    }
    let inf: f32 = real_infinity();
    return select(vec2<f32>(-inf, inf), vec2<f32>(inf, -inf), o < lo || o > hi);
}

// `Query::walked_back` (core/src/ray.rs), in f32: the same points walked from a grid
// unit beyond where the ray leaves the box every surface lies in back to its start
// (origin kept, direction negated, t in [-end, -t_min]); a ray that misses the box as
// it is. How a shadow ray towards a light becomes the light's ray, an exterior one.
// The range may differ from the core's f64 one by rounding: its start is outside the
// box either way, and the march clips to the box.
fn query_walked_back(q: Query) -> Query {
    let zmin: f32 = field_min_height();
    let zmax: f32 = field_max_height();
    let range: f32 = zmax - zmin;
    let x: vec2<f32> = dda_slab(q.origin.x, q.dir.x, 0.0, f32(field_width() - 1u));
    let y: vec2<f32> = dda_slab(q.origin.y, q.dir.y, 0.0, f32(field_height() - 1u));
    let z: vec2<f32> = dda_slab(q.origin.z, q.dir.z, zmin - range, zmax + range);
    let near: f32 = max(max(x.x, y.x), z.x);
    let far: f32 = min(min(x.y, y.y), z.y);
    if (far < max(near, q.t_min)) {
        return q;
    }
    var end: f32 = q.t_max;
    if (far < q.t_max) {
        end = min(far + 1.0 / length(q.dir), q.t_max);
    }
    return Query(q.origin, -q.dir, -end, -q.t_min);
}

// `clip`: the box of the triangle surface (the sample range in z).
fn dda_clip(q: Query, span: ptr<function, Span>) -> bool { return dda_clip_surface(HF_SURFACE_TRIANGLES, q, span); }

// `cell_index`: first cell index along one axis for coordinate x in [0, cells] moving
// with direction d; a point on a cell boundary belongs to the cell the ray moves into.
fn dda_cell_index(x: f32, d: f32, cells: u32) -> u32 {
    let f: f32 = floor(x);
    var i: u32 = u32(f);
    if (d < 0.0 && f == x && i > 0u) {
        i -= 1u;
    }
    return min(i, cells - 1u);
}

// `step_of`.
fn dda_step_of(d: f32) -> i32 {
    if (d > 0.0) {
        return 1;
    } else if (d < 0.0) {
        return -1;
    }
    return 0;
}

// `next_crossing`: parameter of the next centerline crossing along one axis after cell i.
fn dda_next_crossing(i: u32, step: i32, o: f32, d: f32) -> f32 {
    if (step == 1) {
        return (f32(i + 1u) - o) / d;
    } else if (step == -1) {
        return (f32(i) - o) / d;
    }
    return real_infinity();
}

// `local_clearance`: local point (written to `b`) and clearance of the grid point p in
// `cell`; on a centerline crossing (`on[axis] >= 0`) the height comes from that edge's
// two samples only, so both cells sharing the edge compute the same clearance.
fn dda_local_clearance(surface: u32, c: vec4<f32>, cell: vec2<u32>, p: vec3<f32>, on: vec2<i32>,
                       b: ptr<function, vec3<f32>>) -> f32 {
    var lx: f32 = real_clamp_to(p[0] - f32(cell[0]), 0.0, 1.0);
    if (on[0] >= 0) {
        lx = f32(on[0]);
    }
    var ly: f32 = real_clamp_to(p[1] - f32(cell[1]), 0.0, 1.0);
    if (on[1] >= 0) {
        ly = f32(on[1]);
    }
    *b = vec3<f32>(lx, ly, p[2]);
    var height: f32;
    if (on[0] >= 0 && on[1] >= 0) {
        height = c[on[0] | (on[1] << 1u)];
    } else if (on[0] >= 0) {
        height = real_lerp(c[on[0]], c[on[0] + 2], (*b)[1]);
    } else if (on[1] >= 0) {
        let k: i32 = on[1] << 1u;
        height = real_lerp(c[k], c[k + 1], (*b)[0]);
    } else {
        height = surface_cell_height(surface, c, (*b)[0], (*b)[1]);
    }
    return (*b)[2] - height;
}

// `entry_on`: how the span's first point lies on its cell's edges (a side entry of a
// continuous surface: on that side's edge).
fn dda_entry_on(surface: u32, span: Span) -> vec2<i32> {
//#if any_surface
    if (!surface_is_continuous(surface)) {
        return vec2<i32>(-1);
    }
//#endif
//#if triangles|bilinear|view_linear|qu_triangles
    if (span.entry == HF_ENTRY_SIDE) {
        let n: vec3<f32> = span.entry_normal;
        return vec2<i32>(select(-1, i32(n[0] > 0.0), n[0] != 0.0),
                         select(-1, i32(n[1] > 0.0), n[1] != 0.0));
    }
//#endif
    return vec2<i32>(-1);
}

// `start_clearance`: `Trace::clearance` of a hit where the span begins.
fn dda_start_clearance(span: Span, ca: f32) -> f32 {
    return select(-ca, real_infinity(), span.entry == HF_ENTRY_TOP);
}

// `start_hit`: the hit of a ray already under the surface where its span begins.
fn dda_start_hit(surface: u32, span: Span, c: vec4<f32>, cell: vec2<u32>, a: vec3<f32>, p0: vec3<f32>) -> Hit {
    var normal: vec3<f32>;
    var flags: u32;
    if (span.entry == HF_ENTRY_SIDE) {
        normal = span.entry_normal;
        flags = HF_FLAG_SIDE;
    } else if (span.entry == HF_ENTRY_START) {
        normal = surface_cell_normal(surface, c, a[0], a[1]);
        flags = HF_FLAG_ORIGIN_INSIDE;
    } else {
        normal = surface_cell_normal(surface, c, a[0], a[1]);
        flags = 0u;
    }
    return Hit(span.t0, p0, cell, normal, flags);
}

// `grid_cells`: the field's cells per axis (samples − 1).
fn dda_cells() -> vec2<u32> {
    return vec2<u32>(field_width() - 1u, field_height() - 1u);
}

// `next_crossings`: the ray parameters of the next centerline crossing on each axis
// out of `cell` (infinity on an axis the ray does not move along).
fn dda_crossings(cell: vec2<u32>, step: vec2<i32>, q: Query) -> vec2<f32> {
    return vec2<f32>(dda_next_crossing(cell[0], step[0], q.origin[0], q.dir[0]),
                     dda_next_crossing(cell[1], step[1], q.origin[1], q.dir[1]));
}

// `exit_of`: where the ray leaves the cell whose next centerline crossings are
// `t_cross` (entered at `ta`): tb, clamped to [ta, t1], and the axes it crosses
// there (none when the span ends first).
fn dda_exit(t_cross: vec2<f32>, ta: f32, t1: f32, cross: ptr<function, vec2<bool>>) -> f32 {
    let t_next: f32 = real_min(t_cross[0], t_cross[1]);
    if (t_next < t1) {
        *cross = vec2<bool>(t_cross[0] <= t_next, t_cross[1] <= t_next);
        return real_max(t_next, ta);
    }
    *cross = vec2<bool>(false);
    return t1;
}

// `exit_on`: how a cell's exit point lies on the centerline crossings `cross` (the
// `on` vector of local_clearance).
fn dda_exit_on(step: vec2<i32>, cross: vec2<bool>) -> vec2<i32> {
    return vec2<i32>(select(-1, i32(step[0] > 0), cross[0]), select(-1, i32(step[1] > 0), cross[1]));
}

// `next_entry`: the exit point `b` in the local coordinates of the next cell, entered
// across `cross`.
fn dda_next_entry(b: vec3<f32>, cross: vec2<bool>) -> vec3<f32> {
    return vec3<f32>(select(b[0], 1.0 - b[0], cross[0]), select(b[1], 1.0 - b[1], cross[1]), b[2]);
}

// `segment_point`: the hit of `seg` on the segment a→b (local coordinates) of `cell`,
// from ta to tb: the point from the cell's integer corner plus local coordinates.
fn dda_segment_point(seg: SegmentHit, cell: vec2<u32>, a: vec3<f32>, b: vec3<f32>, ta: f32, tb: f32) -> Hit {
    let s: f32 = seg.s;
    let point: vec3<f32> = vec3<f32>(f32(cell[0]) + (a[0] + s * (b[0] - a[0])),
                          f32(cell[1]) + (a[1] + s * (b[1] - a[1])),
                          a[2] + s * (b[2] - a[2]));
    return Hit(ta + s * (tb - ta), point, cell, seg.normal, seg.flags);
}

// `trace`: traces q cell by cell and returns the exact first hit on `surface`.
// Cost: four fetches (the corners) per cell visited.
fn dda_trace(surface: u32, q: Query) -> Trace {
    var span: Span;
    if (!dda_clip_surface(surface, q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    // Per-axis state, index 0 = x, 1 = y.
    let cells: vec2<u32> = dda_cells();
    let p0: vec3<f32> = query_at(q, span.t0);
    let start: vec2<f32> = vec2<f32>(real_clamp_to(p0[0], 0.0, f32(cells[0])),
                          real_clamp_to(p0[1], 0.0, f32(cells[1])));
    var cell: vec2<u32> = vec2<u32>(dda_cell_index(start[0], d[0], cells[0]),
                         dda_cell_index(start[1], d[1], cells[1]));
    let step: vec2<i32> = vec2<i32>(dda_step_of(d[0]), dda_step_of(d[1]));
    var c: vec4<f32> = surface_corners(cell[0], cell[1]);
    var fetches: u32 = 4u;
    var a: vec3<f32>;
    var ca: f32 = dda_local_clearance(surface, c, cell, vec3<f32>(start[0], start[1], p0[2]), dda_entry_on(surface, span),
                                 &a);

    if (ca <= 0.0) {
        return trace_hit(dda_start_hit(surface, span, c, cell, a, p0), fetches,
                         dda_start_clearance(span, ca));
    }

    var clearance: f32 = ca;
    var ta: f32 = span.t0;
    var wall: vec3<f32> = vec3<f32>(0.0, 0.0, 1.0);
    var t_cross: vec2<f32> = dda_crossings(cell, step, q);
    loop {
        var cross: vec2<bool>;
        let tb: f32 = dda_exit(t_cross, ta, span.t1, &cross);
        // Clearance at the exit point; on a centerline, from that edge's two samples only.
        let on: vec2<i32> = dda_exit_on(step, cross);
        var b: vec3<f32>;
        let cb: f32 = dda_local_clearance(surface, c, cell, query_at(q, tb), on, &b);
        let seg: SegmentHit = surface_segment_hit(surface, c, a, b, ca, cb, wall);
        clearance = real_min(clearance, seg.clearance);
        if (seg.has_hit) {
            return trace_hit(dda_segment_point(seg, cell, a, b, ta, tb), fetches, clearance);
        }
        if (!cross[0] && !cross[1]) {
            break;
        }
        var leave: bool = false;
        for (var k: i32 = 0; k < 2; k++) {
            if (cross[k]) {
                let next: i32 = i32(cell[k]) + step[k];
                if (next < 0 || next >= i32(cells[k])) {
                    leave = true;
                    break;
                }
                cell[k] = u32(next);
                t_cross[k] = dda_next_crossing(cell[k], step[k], o[k], d[k]);
            }
        }
        if (leave) {
            break;
        }
        // The face entered (x's when the ray passes exactly through a corner).
        let k: i32 = select(1, 0, cross[0]);
        wall = vec3<f32>(0.0);
        wall[k] = select(1.0, -1.0, step[k] > 0);
        c = surface_corners(cell[0], cell[1]);
        fetches += 4u;
        a = dda_next_entry(b, cross);
        ca = cb;
        ta = tb;
    }
    return trace_miss(fetches, clearance);
}
