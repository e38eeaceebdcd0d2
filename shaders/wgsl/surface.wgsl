// Mirror of core/src/surface.rs: the six surface reconstructions and their exact
// segment tests, in one cell's local coordinates (u = x - i, v = y - j in [0, 1]) with
// the corners c = [h00, h10, h01, h11] (vec4). A segment runs from local point a
// (s = 0) to b (s = 1), each [u, v, z].

// `SegmentHit<f32>`; `has_hit` stands for `hit.is_some()`, `(s, normal, flags)` its value.
struct SegmentHit {
    has_hit: bool,
    s: f32,
    normal: vec3<f32>,
    flags: u32,
    clearance: f32,
}

fn segment_none(clearance: f32) -> SegmentHit { return SegmentHit(false, 0.0, vec3<f32>(0.0), 0u, clearance); }

fn segment_some(s: f32, normal: vec3<f32>, flags: u32, clearance: f32) -> SegmentHit {
    return SegmentHit(true, s, normal, flags, clearance);
}

// `Surface::is_continuous`.
fn surface_is_continuous(surface: u32) -> bool {
    return surface == HF_SURFACE_TRIANGLES || surface == HF_SURFACE_BILINEAR ||
           surface == HF_SURFACE_VIEW_LINEAR || surface == HF_SURFACE_QU_TRIANGLES;
}

// `plane`: `p[0] + p[1] u + p[2] v`.
fn surface_plane(p: vec3<f32>, u: f32, v: f32) -> f32 { return p[0] + p[1] * u + p[2] * v; }

// `bilinear`.
fn surface_bilinear(c: vec4<f32>, u: f32, v: f32) -> f32 {
    return real_lerp(real_lerp(c[0], c[1], u), real_lerp(c[2], c[3], u), v);
}

// `triangle_planes`: the two planes of the split along the lower diagonal.
fn surface_triangle_planes(c: vec4<f32>, p: ptr<function, vec3<f32>>, q: ptr<function, vec3<f32>>) {
    let h00: f32 = c[0];
    let h10: f32 = c[1];
    let h01: f32 = c[2];
    let h11: f32 = c[3];
    if (h00 + h11 <= h10 + h01) {
        // Diagonal 00-11: triangles (00, 10, 11) and (00, 01, 11).
        *p = vec3<f32>(h00, h10 - h00, h11 - h10);
        *q = vec3<f32>(h00, h11 - h01, h01 - h00);
    } else {
        // Diagonal 10-01: triangles (00, 10, 01) and (10, 01, 11).
        *p = vec3<f32>(h00, h10 - h00, h01 - h00);
        *q = vec3<f32>(h10 + h01 - h11, h11 - h01, h11 - h10);
    }
}

// `fixed_diagonal_planes`: Qu's split along the diagonal 00-11, the triangle
// (00, 10, 11) where u >= v (index 0), then (00, 01, 11) where u < v (index 1).
fn surface_fixed_diagonal_plane(c: vec4<f32>, k: u32) -> vec3<f32> {
    if (k == 0u) {
        return vec3<f32>(c[0], c[1] - c[0], c[3] - c[1]);
    }
    return vec3<f32>(c[0], c[3] - c[2], c[2] - c[0]);
}

// `linear_plane`: the plane through h00, h10 and h01.
fn surface_linear_plane(c: vec4<f32>) -> vec3<f32> { return vec3<f32>(c[0], c[1] - c[0], c[2] - c[0]); }

// `nearest_corner`: index into c of the sample nearest to (u, v).
fn surface_nearest_corner(u: f32, v: f32) -> i32 {
    return i32(u >= 0.5) | (i32(v >= 0.5) << 1u);
}

// `Surface::cell_height`.
fn surface_cell_height(surface: u32, c: vec4<f32>, u: f32, v: f32) -> f32 {
//#if any_surface
    if (surface == HF_SURFACE_TRIANGLES) {
//#endif
//#if triangles
        var p: vec3<f32>;
        var q: vec3<f32>;
        surface_triangle_planes(c, &p, &q);
        return real_max(surface_plane(p, u, v), surface_plane(q, u, v));
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_BILINEAR || surface == HF_SURFACE_VIEW_LINEAR) {
//#endif
//#if bilinear|view_linear
        return surface_bilinear(c, u, v);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_HEIGHT_PLANES) {
//#endif
//#if height_planes
        return c[surface_nearest_corner(u, v)];
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_QU_TRIANGLES) {
//#endif
//#if qu_triangles
        return surface_plane(surface_fixed_diagonal_plane(c, u32(u < v)), u, v);
//#endif
//#if any_surface
    }
//#endif
//#if corner_planes
    return surface_plane(surface_linear_plane(c), u, v);
//#endif
}

// `Surface::cell_gradient`.
fn surface_cell_gradient(surface: u32, c: vec4<f32>, u: f32, v: f32) -> vec2<f32> {
//#if any_surface
    if (surface == HF_SURFACE_TRIANGLES) {
//#endif
//#if triangles
        var p: vec3<f32>;
        var q: vec3<f32>;
        surface_triangle_planes(c, &p, &q);
        let top: vec3<f32> = select(q, p, surface_plane(p, u, v) >= surface_plane(q, u, v));
        return vec2<f32>(top[1], top[2]);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_BILINEAR || surface == HF_SURFACE_VIEW_LINEAR) {
//#endif
//#if bilinear|view_linear
        let e: f32 = c[0] - c[1] - c[2] + c[3];
        return vec2<f32>(c[1] - c[0] + e * v, c[2] - c[0] + e * u);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_HEIGHT_PLANES) {
//#endif
//#if height_planes
        return vec2<f32>(0.0, 0.0);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_QU_TRIANGLES) {
//#endif
//#if qu_triangles
        let p: vec3<f32> = surface_fixed_diagonal_plane(c, u32(u < v));
        return vec2<f32>(p[1], p[2]);
//#endif
//#if any_surface
    }
//#endif
//#if corner_planes
    let p: vec3<f32> = surface_linear_plane(c);
    return vec2<f32>(p[1], p[2]);
//#endif
}

// `Surface::cell_normal`.
fn surface_cell_normal(surface: u32, c: vec4<f32>, u: f32, v: f32) -> vec3<f32> {
    let g: vec2<f32> = surface_cell_gradient(surface, c, u, v);
    return math_normal_from_gradient(g.x, g.y);
}

// `corners`.
fn surface_corners(i: u32, j: u32) -> vec4<f32> { return field_cell_corners(i, j); }

// `locate`'s tuple: the cell's corners, the local coordinates and the cell.
struct SurfaceLocal {
    c: vec4<f32>,
    u: f32,
    v: f32,
    cell: vec2<u32>,
}

// `locate`: corners, local coordinates and cell of grid point (x, y), clamped into
// the footprint.
fn surface_locate(x_in: f32, y_in: f32) -> SurfaceLocal {
    let x: f32 = real_clamp_to(x_in, 0.0, f32(field_width() - 1u));
    let y: f32 = real_clamp_to(y_in, 0.0, f32(field_height() - 1u));
    let i: u32 = min(u32(floor(x)), field_width() - 2u);
    let j: u32 = min(u32(floor(y)), field_height() - 2u);
    return SurfaceLocal(surface_corners(i, j), x - f32(i), y - f32(j), vec2<u32>(i, j));
}

// `Surface::height_at`.
fn surface_height_at(surface: u32, x: f32, y: f32) -> f32 {
    let l: SurfaceLocal = surface_locate(x, y);
    return surface_cell_height(surface, l.c, l.u, l.v);
}

// `Surface::normal_at`.
fn surface_normal_at(surface: u32, x: f32, y: f32) -> vec3<f32> {
    let l: SurfaceLocal = surface_locate(x, y);
    let g: vec2<f32> = surface_cell_gradient(surface, l.c, l.u, l.v);
    return math_normal_from_gradient(g.x, g.y);
}

// `triangles_segment`: the clearance is concave along the segment, so the segment is
// clear iff both ends are; the contact is the first root of either plane's clearance.
fn surface_triangles_segment(c: vec4<f32>, a: vec3<f32>, b: vec3<f32>, ca: f32, cb: f32) -> SegmentHit {
    let clearance: f32 = real_min(ca, cb);
    if (cb > 0.0) {
        return segment_none(clearance);
    }
    var has_best: bool = false;
    var best_s: f32 = 0.0;
    var best_p: vec3<f32> = vec3<f32>(0.0);
    var p0: vec3<f32>;
    var p1: vec3<f32>;
    surface_triangle_planes(c, &p0, &p1);
    var planes: array<vec3<f32>, 2> = array<vec3<f32>, 2>(p0, p1);
    for (var k: i32 = 0; k < 2; k++) {
        let p: vec3<f32> = planes[k];
        let la: f32 = a[2] - surface_plane(p, a[0], a[1]);
        let lb: f32 = b[2] - surface_plane(p, b[0], b[1]);
        if (lb <= 0.0) {
            let s: f32 = select(la / (la - lb), 0.0, la <= 0.0);
            if (!has_best || s < best_s) {
                has_best = true;
                best_s = s;
                best_p = p;
            }
        }
    }
    // Rounding may leave both plane clearances just above zero while the shared edge
    // clearance `cb` is not: the contact is then at the end of the segment.
    if (!has_best) {
        let top: vec3<f32> = select(planes[1], planes[0],
                         surface_plane(planes[0], b[0], b[1]) >= surface_plane(planes[1], b[0], b[1]));
        best_s = 1.0;
        best_p = top;
    }
    return segment_some(best_s, math_normal_from_gradient(best_p[1], best_p[2]), 0u, ca);
}

// `qu_triangles_segment`: Qu et al.'s division-free test on the fixed diagonal u = v.
// The segment starts in the triangle on a's side; if it crosses the diagonal, the
// contact is in that triangle iff ca |g_b| + l_b |g_a| <= 0 (g = u - v, l_b that
// triangle's plane clearance at b); past the crossing the clearance runs linearly to cb.
fn surface_qu_triangles_segment(c: vec4<f32>, a: vec3<f32>, b: vec3<f32>, ca: f32, cb: f32) -> SegmentHit {
    let ga: f32 = a[0] - a[1];
    let gb: f32 = b[0] - b[1];
    let first: u32 = u32(ga < 0.0 || (ga == 0.0 && gb < 0.0));
    let crosses: bool = select(gb > 0.0, gb < 0.0, first == 0u);
    let p: vec3<f32> = surface_fixed_diagonal_plane(c, first);
    if (!crosses) {
        if (cb <= 0.0) {
            return segment_some(ca / (ca - cb), math_normal_from_gradient(p[1], p[2]), 0u, ca);
        }
        return segment_none(real_min(ca, cb));
    }
    let wa: f32 = abs(ga);
    let wb: f32 = abs(gb);
    let lb: f32 = b[2] - surface_plane(p, b[0], b[1]);
    let crossing: f32 = ca * wb + lb * wa;
    if (crossing <= 0.0) {
        return segment_some(ca / (ca - lb), math_normal_from_gradient(p[1], p[2]), 0u, ca);
    }
    let cd: f32 = crossing / (wa + wb);
    let clearance: f32 = real_min(ca, cd);
    if (cb > 0.0) {
        return segment_none(real_min(clearance, cb));
    }
    let sd: f32 = wa / (wa + wb);
    // `cd` is 0 only when the product underflowed: the contact is then the crossing.
    var s: f32 = sd;
    if (cd > 0.0) {
        s = sd + (1.0 - sd) * (cd / (cd - cb));
    }
    let q: vec3<f32> = surface_fixed_diagonal_plane(c, 1u - first);
    return segment_some(real_min(s, 1.0), math_normal_from_gradient(q[1], q[2]), 0u, clearance);
}

// `stable_roots`: the roots of `A x^2 + B x + C` without cancellation (q / A and C / q
// with q = -(B + sign(B) sqrt(D)) / 2) into `roots`; returns how many (0 to 2).
fn surface_stable_roots(qa: f32, qb: f32, qc: f32, roots: ptr<function, array<f32, 2>>) -> i32 {
    let disc: f32 = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0) {
        return 0;
    }
    let sq: f32 = sqrt(disc);
    let q: f32 = select(-0.5 * (qb - sq), -0.5 * (qb + sq), qb >= 0.0);
    if (q == 0.0) {
        // B = 0 and D = 0: a double root at 0 when C = 0, or no root (A = B = 0, C != 0).
        if (qc == 0.0) {
            (*roots)[0] = 0.0;
            return 1;
        }
        return 0;
    }
    (*roots)[0] = q / qa;
    (*roots)[1] = qc / q;
    return 2;
}

// `smallest_root_in_unit`: smallest root of `A s^2 + B s + C` in [0, 1] (within a few
// ulps, then clamped), of the stable roots; `found` is false for none.
fn surface_smallest_root_in_unit(qa: f32, qb: f32, qc: f32, found: ptr<function, bool>) -> f32 {
    *found = false;
    var best: f32 = 0.0;
    let tol: f32 = 64.0 * REAL_EPSILON;
    var roots: array<f32, 2>;
    let n: i32 = surface_stable_roots(qa, qb, qc, &roots);
    for (var k: i32 = 0; k < n; k++) {
        var r: f32 = roots[k];
        if (real_is_finite(r) && r >= -tol && r <= 1.0 + tol) {
            r = real_clamp_to(r, 0.0, 1.0);
            if (!*found || r < best) {
                *found = true;
                best = r;
            }
        }
    }
    return best;
}

// `bisect`: first sign change of `A s^2 + B s + C` on [0, 1], given C > 0 >= A+B+C.
fn surface_bisect(qa: f32, qb: f32, qc: f32) -> f32 {
    var lo: f32 = 0.0;
    var hi: f32 = 1.0;
    for (var k: i32 = 0; k < 64; k++) {
        let mid: f32 = 0.5 * (lo + hi);
        if ((qa * mid + qb) * mid + qc > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return hi;
}

// `bilinear_segment`: the clearance along the segment is `A s^2 + B s + C` with
// C = ca, A + B + C = cb and A = -e du dv.
fn surface_bilinear_segment(c: vec4<f32>, a: vec3<f32>, b: vec3<f32>, ca: f32, cb: f32) -> SegmentHit {
    let e: f32 = c[0] - c[1] - c[2] + c[3];
    let qa: f32 = -e * (b[0] - a[0]) * (b[1] - a[1]);
    let qc: f32 = ca;
    let qb: f32 = cb - ca - qa;
    var clearance: f32 = real_min(ca, cb);
    var has_s: bool = false;
    var s: f32 = 0.0;
    if (cb <= 0.0) {
        // A sign change: a root in (0, 1] exists; fall back on bisection if rounding
        // pushed the discriminant below zero.
        var found: bool;
        let r: f32 = surface_smallest_root_in_unit(qa, qb, qc, &found);
        has_s = true;
        if (found) {
            s = r;
        } else {
            s = surface_bisect(qa, qb, qc);
        }
    } else if (qa > 0.0) {
        // Both ends clear: the ray can still dip under a saddle between them.
        let vertex: f32 = -qb / (2.0 * qa);
        if (vertex > 0.0 && vertex < 1.0) {
            let lowest: f32 = qc - qb * qb / (4.0 * qa);
            clearance = real_min(clearance, lowest);
            if (lowest <= 0.0) {
                var found: bool;
                let r: f32 = surface_smallest_root_in_unit(qa, qb, qc, &found);
                has_s = true;
                s = select(vertex, r, found);
            }
        }
    }
    if (!has_s) {
        return segment_none(clearance);
    }
    let u: f32 = a[0] + (b[0] - a[0]) * s;
    let v: f32 = a[1] + (b[1] - a[1]) * s;
    // Up to its first root the quadratic has no minimum below min(ca, 0): nothing but `ca`.
    return segment_some(s, surface_cell_normal(HF_SURFACE_BILINEAR, c, u, v), 0u, ca);
}

// `height_planes_segment`: the cell holds four constant quarters; the segment is split
// where it crosses u = 1/2 and v = 1/2 and each piece tested against its quarter.
fn surface_height_planes_segment(c: vec4<f32>, a: vec3<f32>, b: vec3<f32>, entry_wall: vec3<f32>) -> SegmentHit {
    let d: vec3<f32> = vec3<f32>(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    // Split parameters where u or v crosses 1/2, with the wall normal met there.
    var cut_s: array<f32, 2>;
    var cut_n: array<vec3<f32>, 2>;
    var cuts: i32 = 0;
    for (var axis: i32 = 0; axis < 2; axis++) {
        if (d[axis] != 0.0) {
            let s: f32 = (0.5 - a[axis]) / d[axis];
            if (s > 0.0 && s < 1.0) {
                var n: vec3<f32> = vec3<f32>(0.0);
                n[axis] = select(1.0, -1.0, d[axis] > 0.0);
                cut_s[cuts] = s;
                cut_n[cuts] = n;
                cuts++;
            }
        }
    }
    if (cuts == 2 && cut_s[1] < cut_s[0]) {
        let ts: f32 = cut_s[0];
        cut_s[0] = cut_s[1];
        cut_s[1] = ts;
        let tn: vec3<f32> = cut_n[0];
        cut_n[0] = cut_n[1];
        cut_n[1] = tn;
    }
    var clearance: f32 = real_infinity();
    var start_s: f32 = 0.0;
    var start_n: vec3<f32> = entry_wall;
    for (var k: i32 = 0; k <= cuts; k++) {
        var end: f32 = 1.0;
        var next_wall: vec3<f32> = entry_wall;
        if (k < cuts) {
            end = cut_s[k];
            next_wall = cut_n[k];
        }
        let mid: f32 = 0.5 * (start_s + end);
        let h: f32 = c[surface_nearest_corner(a[0] + d[0] * mid, a[1] + d[1] * mid)];
        let c0: f32 = a[2] + d[2] * start_s - h;
        let c1: f32 = a[2] + d[2] * end - h;
        if (c0 <= 0.0) {
            return segment_some(start_s, start_n, HF_FLAG_WALL, real_min(clearance, -c0));
        }
        clearance = real_min(clearance, c0);
        if (c1 <= 0.0) {
            let s: f32 = start_s + (end - start_s) * c0 / (c0 - c1);
            return segment_some(s, vec3<f32>(0.0, 0.0, 1.0), 0u, clearance);
        }
        clearance = real_min(clearance, c1);
        start_s = end;
        start_n = next_wall;
    }
    return segment_none(clearance);
}

// `Surface::segment_hit`: first contact of the segment a -> b with the surface over
// one cell, from the clearances ca > 0 and cb the caller computed at its ends.
fn surface_segment_hit(surface: u32, c: vec4<f32>, a: vec3<f32>, b: vec3<f32>, ca: f32, cb: f32,
                       entry_wall: vec3<f32>) -> SegmentHit {
//#if any_surface
    if (surface == HF_SURFACE_TRIANGLES) {
//#endif
//#if triangles
        return surface_triangles_segment(c, a, b, ca, cb);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_BILINEAR) {
//#endif
//#if bilinear
        return surface_bilinear_segment(c, a, b, ca, cb);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_VIEW_LINEAR) {
//#endif
//#if view_linear
        if (cb <= 0.0) {
            let s: f32 = ca / (ca - cb);
            let u: f32 = a[0] + (b[0] - a[0]) * s;
            let v: f32 = a[1] + (b[1] - a[1]) * s;
            return segment_some(s, surface_cell_normal(surface, c, u, v), 0u, ca);
        }
        return segment_none(real_min(ca, cb));
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_QU_TRIANGLES) {
//#endif
//#if qu_triangles
        return surface_qu_triangles_segment(c, a, b, ca, cb);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_CORNER_PLANES) {
//#endif
//#if corner_planes
        let p: vec3<f32> = surface_linear_plane(c);
        let la: f32 = a[2] - surface_plane(p, a[0], a[1]);
        let lb: f32 = b[2] - surface_plane(p, b[0], b[1]);
        let n: vec3<f32> = math_normal_from_gradient(p[1], p[2]);
        if (la <= 0.0) {
            return segment_some(0.0, entry_wall, HF_FLAG_WALL, -la);
        } else if (lb <= 0.0) {
            return segment_some(la / (la - lb), n, 0u, la);
        }
        return segment_none(real_min(la, lb));
//#endif
//#if any_surface
    }
//#endif
//#if height_planes
    return surface_height_planes_segment(c, a, b, entry_wall);
//#endif
}
