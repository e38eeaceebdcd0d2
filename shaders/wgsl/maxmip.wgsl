// Mirror of core/src/maxmip.rs: the hierarchical march over the maximum mipmap
// (Tevs et al. 2008) with exact options (Ascent::OneLevel, no LOD, exact bilinear).
//
// Texture layout (docs/DESIGN.md, "Texture layouts", maxmip pyramid): `hf_pyramid`, the levels as the uniform
// `hf_maxmip` (WGSL: `levels`, `level[l]` = (width, height, offset, 0)) or `hf_levels`,
// `hf_level_dims`, `hf_level_offset` (GLSL).

@group(0) @binding(3) var hf_pyramid: texture_2d<f32>;

//#wgsl
struct MaxMipParams {
    levels: i32,
    level: array<vec4<i32>, HF_MAX_LEVELS>,
}

@group(0) @binding(4) var<uniform> hf_maxmip: MaxMipParams;

// The level count, and level l's (width, height, offset, 0).
fn maxmip_levels() -> i32 { return hf_maxmip.levels; }
fn maxmip_level(level: u32) -> vec4<i32> { return hf_maxmip.level[level]; }

// `u32::ilog2`; v >= 1.
fn maxmip_ilog2(v: u32) -> u32 { return firstLeadingBit(v); }

// `u32::trailing_zeros` (32 for 0).
fn maxmip_trailing_zeros(v: u32) -> u32 { return countTrailingZeros(v); }
//#end
//#glsl
// uniform int hf_levels;
// uniform ivec2 hf_level_dims[HF_MAX_LEVELS];
// uniform int hf_level_offset[HF_MAX_LEVELS];
//
// // The level count, and level l's (width, height, offset, 0).
// int maxmip_levels() { return hf_levels; }
// ivec4 maxmip_level(uint level) { return ivec4(hf_level_dims[level], hf_level_offset[level], 0); }
//
// // `u32::ilog2` (GLSL 3.30 has no findMSB); v >= 1.
// uint maxmip_ilog2(uint v) {
//     uint r = 0u;
//     while (v > 1u) {
//         v >>= 1u;
//         r += 1u;
//     }
//     return r;
// }
//
// // `u32::trailing_zeros` (GLSL 3.30 has no findLSB).
// uint maxmip_trailing_zeros(uint v) {
//     uint r = 0u;
//     while (r < 32u && (v & 1u) == 0u) {
//         v >>= 1u;
//         r += 1u;
//     }
//     return r;
// }
//#end

// `MaxMip::texel`: texel (i, j) of `level`, the highest sample of that node's cells.
fn maxmip_texel(level: u32, i: u32, j: u32) -> f32 {
    let l: vec4<i32> = maxmip_level(level);
    let k: i32 = l.z + i32(j) * l.x + i32(i);
    return textureLoad(hf_pyramid, vec2<i32>(k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH), 0).r;
}

// `sync_axis`: moves one axis to the cell the ray is in just after parameter t, from
// cell i inside the node's cells [lo, hi); `exact` says whether the last boundary
// crossed lies exactly at t.
fn maxmip_sync_axis(i: u32, step: i32, lo: u32, hi: u32, o: f32, d: f32, t: f32,
                    exact: ptr<function, bool>) -> u32 {
    // The estimate; x >= 0, so truncation is the floor.
    let x: f32 = real_clamp_to(o + t * d, f32(lo), f32(hi - 1u));
    var j: u32 = u32(x);
    if (step > 0) {
        j = max(j, i);
        while (j > i && (f32(j) - o) / d > t) {
            j -= 1u;
        }
        while (j + 1u < hi && (f32(j + 1u) - o) / d <= t) {
            j += 1u;
        }
        *exact = j != i && (f32(j) - o) / d == t;
    } else {
        j = min(j, i);
        while (j < i && (f32(j + 1u) - o) / d > t) {
            j += 1u;
        }
        while (j > lo && (f32(j) - o) / d <= t) {
            j -= 1u;
        }
        *exact = j != i && (f32(j + 1u) - o) / d == t;
    }
    return j;
}

// `entry_wall`: normal of the wall a cell was entered through (up at the start).
fn maxmip_entry_wall(on: vec2<i32>, step: vec2<i32>) -> vec3<f32> {
    if (on[0] >= 0) {
        return vec3<f32>(select(1.0, -1.0, step[0] > 0), 0.0, 0.0);
    } else if (on[1] >= 0) {
        return vec3<f32>(0.0, select(1.0, -1.0, step[1] > 0), 0.0);
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}

// `trace`: the first hit on `surface`, the one of dda_trace; corner planes are traced
// by dda_trace.
fn maxmip_trace(surface: u32, q: Query) -> Trace {
//#if any_surface
    if (surface == HF_SURFACE_CORNER_PLANES) {
//#endif
//#if corner_planes
        return dda_trace(surface, q);
//#endif
//#if any_surface
    }
//#endif
//#if triangles|bilinear|height_planes|view_linear|qu_triangles
    var span: Span;
    if (!dda_clip(q, &span)) {
        return trace_miss(0u, real_infinity());
    }
    let o: vec3<f32> = q.origin;
    let d: vec3<f32> = q.dir;
    let cells: vec2<u32> = dda_cells();
    let step: vec2<i32> = vec2<i32>(dda_step_of(d[0]), dda_step_of(d[1]));
    var p: vec3<f32> = query_at(q, span.t0);
    var cell: vec2<u32> = vec2<u32>(dda_cell_index(real_clamp_to(p[0], 0.0, f32(cells[0])), d[0], cells[0]),
                         dda_cell_index(real_clamp_to(p[1], 0.0, f32(cells[1])), d[1], cells[1]));
    let top: u32 = u32(maxmip_levels()) - 1u;
    // Start where nodes are a quarter to an eighth of the ray's horizontal reach.
    let reach: f32 = real_max(abs(d[0]), abs(d[1])) * (span.t1 - span.t0);
    let msb: u32 = maxmip_ilog2(u32(real_min(reach, 1073741824.0)) + 1u);
    let start_level: u32 = select(0u, msb - 2u, msb >= 2u);
    var level: u32 = min(start_level, top);
    var t: f32 = span.t0;
    var start: bool = true;
    // How the current cell was entered: on[axis] >= 0 through a centerline crossing or a
    // side of the footprint.
    var on: vec2<i32> = dda_entry_on(surface, span);
    var fetches: u32 = 0u;
    var clearance: f32 = real_infinity();
    loop {
        // The node holding the cell at this level, and where the ray leaves it.
        var lo: vec2<u32>;
        var hi: vec2<u32>;
        var bound: vec2<u32>;
        var t_out: vec2<f32> = vec2<f32>(real_infinity());
        for (var k: i32 = 0; k < 2; k++) {
            lo[k] = (cell[k] >> level) << level;
            hi[k] = min(lo[k] + (1u << level), cells[k]);
            bound[k] = select(lo[k], hi[k], step[k] > 0);
            if (step[k] != 0) {
                t_out[k] = (f32(bound[k]) - o[k]) / d[k];
            }
        }
        let t_next: f32 = real_min(t_out[0], t_out[1]);
        let crossing: bool = t_next < span.t1;
        let tb: f32 = select(span.t1, real_max(t_next, t), crossing);
        let pb: vec3<f32> = query_at(q, tb);
        let top_z: f32 = maxmip_texel(level, cell[0] >> level, cell[1] >> level);
        fetches += 1u;
        let low: f32 = real_min(p[2], pb[2]);
        if (low > top_z) {
            clearance = real_min(clearance, low - top_z);
        } else if (level > 0u) {
            level -= 1u;
            continue;
        } else {
            // Level 0: the exact test of dda_trace, on the same shared edge clearances.
            let c: vec4<f32> = surface_corners(cell[0], cell[1]);
            fetches += 4u;
            var a: vec3<f32>;
            let ca: f32 = dda_local_clearance(surface, c, cell, p, on, &a);
            if (ca <= 0.0 && (start || surface_is_continuous(surface))) {
                var hit: Hit;
                if (start) {
                    hit = dda_start_hit(surface, span, c, cell, a, p);
                } else {
                    // A graze of the edge the ray came in through.
                    hit = Hit(t, p, cell, surface_cell_normal(surface, c, a[0], a[1]), 0u);
                }
                var cl: f32;
                if (start) {
                    cl = dda_start_clearance(span, ca);
                } else {
                    cl = real_min(clearance, ca);
                }
                return trace_hit(hit, fetches, cl);
            }
            let exit_on: vec2<i32> = vec2<i32>(select(-1, i32(step[0] > 0), crossing && t_out[0] <= t_next),
                                    select(-1, i32(step[1] > 0), crossing && t_out[1] <= t_next));
            var b: vec3<f32>;
            let cb: f32 = dda_local_clearance(surface, c, cell, pb, exit_on, &b);
            let wall: vec3<f32> = maxmip_entry_wall(on, step);
            let seg: SegmentHit = surface_segment_hit(surface, c, a, b, ca, cb, wall);
            clearance = real_min(clearance, seg.clearance);
            if (seg.has_hit) {
                return trace_hit(dda_segment_point(seg, cell, a, b, t, tb), fetches, clearance);
            }
        }
        // Leave the node: step over the crossed boundaries, bring the other axis up to
        // date, ascend.
        if (!crossing) {
            return trace_miss(fetches, clearance);
        }
        var crossed_level: u32 = level;
        for (var k: i32 = 0; k < 2; k++) {
            if (step[k] != 0 && t_out[k] <= t_next) {
                if (bound[k] == select(0u, cells[k], step[k] > 0)) {
                    return trace_miss(fetches, clearance);
                }
                cell[k] = select(bound[k] - 1u, bound[k], step[k] > 0);
                on[k] = i32(step[k] < 0);
                crossed_level = max(crossed_level, maxmip_trailing_zeros(bound[k]));
            } else if (step[k] != 0 && level > 0u) {
                var exact: bool;
                cell[k] = maxmip_sync_axis(cell[k], step[k], lo[k], hi[k], o[k], d[k], t_next,
                                           &exact);
                on[k] = select(-1, i32(step[k] < 0), exact);
            } else {
                on[k] = -1;
            }
        }
        level = min(select(level, level + 1u, crossed_level > level), top);
        t = tb;
        p = pb;
        start = false;
    }
    return trace_miss(fetches, clearance);
//#endif
}
