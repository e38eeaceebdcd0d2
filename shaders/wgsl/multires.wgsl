// Mirror of core/src/multires.rs: the multiresolution walk (Qu et al. 2003, after
// Cohen-Or et al. 1996), approximate: the exact traversal's walk on coarser grids
// (level l: every 2^l-th sample, cells cut at the field's edge) as the ray goes
// farther, level floor(log2(dist / range)) at distance `dist`, 0 under 2 range.

// `u32::ilog2` (x > 0), by shifts: GLSL 3.30 has no findMSB.
fn multires_ilog2(x: u32) -> u32 {
    var n: u32 = 0u;
    for (var v: u32 = x; v > 1u; v = v >> 1u) {
        n += 1u;
    }
    return n;
}

// `level_at`: floor(log2(dist / range)), 0 under 2 range, at most `top`.
fn multires_level_at(dist: f32, range: f32, top: u32) -> u32 {
    let v: f32 = dist / range;
    if (v >= 2.0) {
        // 4294967040 is the largest f32 under 2^32 (the CPU saturates at u32::MAX).
        return min(multires_ilog2(u32(real_min(v, 4294967040.0))), top);
    }
    return 0u;
}

// `top_level`: the first level whose cell covers the longer axis (ceil(log2)).
fn multires_top_level(lim: vec2<u32>) -> u32 {
    let m: u32 = max(max(lim[0], lim[1]), 1u);
    let f: u32 = multires_ilog2(m);
    return select(f + 1u, f, (m & (m - 1u)) == 0u);
}

// `trace`: traces q on `surface` with the multiresolution walk for the one-texel
// distance `range_in` (0 is taken as 1). Four fetches per cell of any level.
fn multires_trace(surface: u32, q: Query, range_in: u32) -> Trace {
    var span: Span;
    if (!dda_clip_surface(surface, q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    let lim: vec2<u32> = vec2<u32>(field_width() - 1u, field_height() - 1u);
    let top: u32 = multires_top_level(lim);
    let len: f32 = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    let range: f32 = f32(max(range_in, 1u));
    let step: vec2<i32> = vec2<i32>(dda_step_of(d[0]), dda_step_of(d[1]));
    let p0: vec3<f32> = query_at(q, span.t0);
    var level: u32 = multires_level_at(real_max(span.t0, 0.0) * len, range, top);
    var cell: vec2<u32>;
    for (var k: i32 = 0; k < 2; k++) {
        let x: f32 = real_clamp_to(p0[k], 0.0, f32(lim[k]));
        cell[k] = dda_cell_index(x, d[k], lim[k]) >> level;
    }
    var ta: f32 = span.t0;
    var fetches: u32 = 0u;
    var clearance: f32 = real_infinity();
    var wall: vec3<f32> = vec3<f32>(0.0, 0.0, 1.0);
    if (span.entry == HF_ENTRY_SIDE) {
        wall = span.entry_normal;
    }
    loop {
        let size: u32 = 1u << level;
        let lo: vec2<u32> = vec2<u32>(cell[0] * size, cell[1] * size);
        let hi: vec2<u32> = vec2<u32>(min(lo[0] + size, lim[0]), min(lo[1] + size, lim[1]));
        // Where the ray leaves the cell along each axis.
        var exit: vec2<f32> = vec2<f32>(real_infinity());
        for (var k: i32 = 0; k < 2; k++) {
            if (step[k] == 1) {
                exit[k] = (f32(hi[k]) - o[k]) / d[k];
            } else if (step[k] == -1) {
                exit[k] = (f32(lo[k]) - o[k]) / d[k];
            }
        }
        let t_next: f32 = real_min(exit[0], exit[1]);
        var tb: f32 = span.t1;
        if (t_next < span.t1) {
            tb = real_max(t_next, ta);
        }
        let c: vec4<f32> = vec4<f32>(field_at(lo[0], lo[1]), field_at(hi[0], lo[1]), field_at(lo[0], hi[1]),
                                     field_at(hi[0], hi[1]));
        fetches += 4u;
        let extent: vec2<f32> = vec2<f32>(f32(hi[0] - lo[0]), f32(hi[1] - lo[1]));
        let pa: vec3<f32> = query_at(q, ta);
        let pb: vec3<f32> = query_at(q, tb);
        let a: vec3<f32> = vec3<f32>(real_clamp_to((pa[0] - f32(lo[0])) / extent[0], 0.0, 1.0),
                                     real_clamp_to((pa[1] - f32(lo[1])) / extent[1], 0.0, 1.0), pa[2]);
        let b: vec3<f32> = vec3<f32>(real_clamp_to((pb[0] - f32(lo[0])) / extent[0], 0.0, 1.0),
                                     real_clamp_to((pb[1] - f32(lo[1])) / extent[1], 0.0, 1.0), pb[2]);
        let ca: f32 = a[2] - surface_cell_height(surface, c, a[0], a[1]);
        if (ca <= 0.0) {
            // Under the surface where this cell's segment begins: at the span's start, as
            // the exact march flags it; later, a coarser cell rose over the ray.
            let g: vec2<f32> = surface_cell_gradient(surface, c, a[0], a[1]);
            var n: vec3<f32> = math_normal_from_gradient(g[0] / extent[0], g[1] / extent[1]);
            var flags: u32 = 0u;
            if (ta == span.t0 && span.entry == HF_ENTRY_SIDE) {
                n = span.entry_normal;
                flags = HF_FLAG_SIDE;
            } else if (ta == span.t0 && span.entry == HF_ENTRY_START) {
                flags = HF_FLAG_ORIGIN_INSIDE;
            }
            let fine: vec2<u32> = vec2<u32>(min(u32(real_max(pa[0], 0.0)), lim[0] - 1u),
                                            min(u32(real_max(pa[1], 0.0)), lim[1] - 1u));
            return trace_hit(Hit(ta, pa, fine, n, flags), fetches, real_min(clearance, -ca));
        }
        let cb: f32 = b[2] - surface_cell_height(surface, c, b[0], b[1]);
        let seg: SegmentHit = surface_segment_hit(surface, c, a, b, ca, cb, wall);
        clearance = real_min(clearance, seg.clearance);
        if (seg.has_hit) {
            let s: f32 = seg.s;
            let t: f32 = ta + s * (tb - ta);
            let p: vec3<f32> = query_at(q, t);
            let u: f32 = a[0] + s * (b[0] - a[0]);
            let v: f32 = a[1] + s * (b[1] - a[1]);
            var n: vec3<f32> = wall;
            if ((seg.flags & HF_FLAG_WALL) == 0u) {
                let g: vec2<f32> = surface_cell_gradient(surface, c, u, v);
                n = math_normal_from_gradient(g[0] / extent[0], g[1] / extent[1]);
            }
            let fine: vec2<u32> = vec2<u32>(min(u32(real_max(p[0], 0.0)), lim[0] - 1u),
                                            min(u32(real_max(p[1], 0.0)), lim[1] - 1u));
            return trace_hit(Hit(t, p, fine, n, seg.flags), fetches, clearance);
        }
        if (t_next >= span.t1) {
            break;
        }
        var leave: bool = false;
        for (var k: i32 = 0; k < 2; k++) {
            if (exit[k] <= t_next) {
                let next: i32 = i32(cell[k]) + step[k];
                if (next < 0 || u32(next) * size >= lim[k]) {
                    leave = true;
                    break;
                }
                cell[k] = u32(next);
            }
        }
        if (leave) {
            break;
        }
        // The face entered (x's when the ray passes exactly through a corner).
        let k: i32 = select(0, 1, exit[0] > t_next);
        wall = vec3<f32>(0.0);
        wall[k] = select(1.0, -1.0, step[k] > 0);
        ta = tb;
        let coarser: u32 = multires_level_at(real_max(tb, 0.0) * len, range, top);
        if (coarser > level) {
            cell = vec2<u32>(cell[0] >> (coarser - level), cell[1] >> (coarser - level));
            level = coarser;
        }
    }
    return trace_miss(fetches, clearance);
}
