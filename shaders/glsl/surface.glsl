// Generated from shaders/wgsl/surface.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/surface.rs: the six surface reconstructions and their exact
// segment tests, in one cell's local coordinates (u = x - i, v = y - j in [0, 1]) with
// the corners c = [h00, h10, h01, h11] (vec4). A segment runs from local point a
// (s = 0) to b (s = 1), each [u, v, z].

// `SegmentHit<f32>`; `has_hit` stands for `hit.is_some()`, `(s, normal, flags)` its value.
struct SegmentHit {
    bool has_hit;
    float s;
    vec3 normal;
    uint flags;
    float clearance;
};

SegmentHit segment_none(float clearance) { return SegmentHit(false, 0.0, vec3(0.0), 0u, clearance); }

SegmentHit segment_some(float s, vec3 normal, uint flags, float clearance) {
    return SegmentHit(true, s, normal, flags, clearance);
}

// `Surface::is_continuous`.
bool surface_is_continuous(uint surface) {
    return surface == HF_SURFACE_TRIANGLES || surface == HF_SURFACE_BILINEAR ||
           surface == HF_SURFACE_VIEW_LINEAR || surface == HF_SURFACE_QU_TRIANGLES;
}

// `plane`: `p[0] + p[1] u + p[2] v`.
float surface_plane(vec3 p, float u, float v) { return p[0] + p[1] * u + p[2] * v; }

// `bilinear`.
float surface_bilinear(vec4 c, float u, float v) {
    return real_lerp(real_lerp(c[0], c[1], u), real_lerp(c[2], c[3], u), v);
}

// `triangle_planes`: the two planes of the split along the lower diagonal.
void surface_triangle_planes(vec4 c, inout vec3 p, inout vec3 q) {
    float h00 = c[0];
    float h10 = c[1];
    float h01 = c[2];
    float h11 = c[3];
    if (h00 + h11 <= h10 + h01) {
        // Diagonal 00-11: triangles (00, 10, 11) and (00, 01, 11).
        p = vec3(h00, h10 - h00, h11 - h10);
        q = vec3(h00, h11 - h01, h01 - h00);
    } else {
        // Diagonal 10-01: triangles (00, 10, 01) and (10, 01, 11).
        p = vec3(h00, h10 - h00, h01 - h00);
        q = vec3(h10 + h01 - h11, h11 - h01, h11 - h10);
    }
}

// `fixed_diagonal_planes`: Qu's split along the diagonal 00-11, the triangle
// (00, 10, 11) where u >= v (index 0), then (00, 01, 11) where u < v (index 1).
vec3 surface_fixed_diagonal_plane(vec4 c, uint k) {
    if (k == 0u) {
        return vec3(c[0], c[1] - c[0], c[3] - c[1]);
    }
    return vec3(c[0], c[3] - c[2], c[2] - c[0]);
}

// `linear_plane`: the plane through h00, h10 and h01.
vec3 surface_linear_plane(vec4 c) { return vec3(c[0], c[1] - c[0], c[2] - c[0]); }

// `nearest_corner`: index into c of the sample nearest to (u, v).
int surface_nearest_corner(float u, float v) {
    return int(u >= 0.5) | (int(v >= 0.5) << 1u);
}

// `Surface::cell_height`.
float surface_cell_height(uint surface, vec4 c, float u, float v) {
//#if any_surface
    if (surface == HF_SURFACE_TRIANGLES) {
//#endif
//#if triangles
        vec3 p;
        vec3 q;
        surface_triangle_planes(c, p, q);
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
        return surface_plane(surface_fixed_diagonal_plane(c, uint(u < v)), u, v);
//#endif
//#if any_surface
    }
//#endif
//#if corner_planes
    return surface_plane(surface_linear_plane(c), u, v);
//#endif
}

// `Surface::cell_gradient`.
vec2 surface_cell_gradient(uint surface, vec4 c, float u, float v) {
//#if any_surface
    if (surface == HF_SURFACE_TRIANGLES) {
//#endif
//#if triangles
        vec3 p;
        vec3 q;
        surface_triangle_planes(c, p, q);
        vec3 top = ((surface_plane(p, u, v) >= surface_plane(q, u, v)) ? (p) : (q));
        return vec2(top[1], top[2]);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_BILINEAR || surface == HF_SURFACE_VIEW_LINEAR) {
//#endif
//#if bilinear|view_linear
        float e = c[0] - c[1] - c[2] + c[3];
        return vec2(c[1] - c[0] + e * v, c[2] - c[0] + e * u);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_HEIGHT_PLANES) {
//#endif
//#if height_planes
        return vec2(0.0, 0.0);
//#endif
//#if any_surface
    } else if (surface == HF_SURFACE_QU_TRIANGLES) {
//#endif
//#if qu_triangles
        vec3 p = surface_fixed_diagonal_plane(c, uint(u < v));
        return vec2(p[1], p[2]);
//#endif
//#if any_surface
    }
//#endif
//#if corner_planes
    vec3 p = surface_linear_plane(c);
    return vec2(p[1], p[2]);
//#endif
}

// `Surface::cell_normal`.
vec3 surface_cell_normal(uint surface, vec4 c, float u, float v) {
    vec2 g = surface_cell_gradient(surface, c, u, v);
    return math_normal_from_gradient(g.x, g.y);
}

// `corners`.
vec4 surface_corners(uint i, uint j) { return field_cell_corners(i, j); }

// `locate`'s tuple: the cell's corners, the local coordinates and the cell.
struct SurfaceLocal {
    vec4 c;
    float u;
    float v;
    uvec2 cell;
};

// `locate`: corners, local coordinates and cell of grid point (x, y), clamped into
// the footprint.
SurfaceLocal surface_locate(float x_in, float y_in) {
    float x = real_clamp_to(x_in, 0.0, float(field_width() - 1u));
    float y = real_clamp_to(y_in, 0.0, float(field_height() - 1u));
    uint i = min(uint(floor(x)), field_width() - 2u);
    uint j = min(uint(floor(y)), field_height() - 2u);
    return SurfaceLocal(surface_corners(i, j), x - float(i), y - float(j), uvec2(i, j));
}

// `Surface::height_at`.
float surface_height_at(uint surface, float x, float y) {
    SurfaceLocal l = surface_locate(x, y);
    return surface_cell_height(surface, l.c, l.u, l.v);
}

// `Surface::normal_at`.
vec3 surface_normal_at(uint surface, float x, float y) {
    SurfaceLocal l = surface_locate(x, y);
    vec2 g = surface_cell_gradient(surface, l.c, l.u, l.v);
    return math_normal_from_gradient(g.x, g.y);
}

// `triangles_segment`: the clearance is concave along the segment, so the segment is
// clear iff both ends are; the contact is the first root of either plane's clearance.
SegmentHit surface_triangles_segment(vec4 c, vec3 a, vec3 b, float ca, float cb) {
    float clearance = real_min(ca, cb);
    if (cb > 0.0) {
        return segment_none(clearance);
    }
    bool has_best = false;
    float best_s = 0.0;
    vec3 best_p = vec3(0.0);
    vec3 p0;
    vec3 p1;
    surface_triangle_planes(c, p0, p1);
    vec3[2] planes = vec3[2](p0, p1);
    for (int k = 0; k < 2; k++) {
        vec3 p = planes[k];
        float la = a[2] - surface_plane(p, a[0], a[1]);
        float lb = b[2] - surface_plane(p, b[0], b[1]);
        if (lb <= 0.0) {
            float s = ((la <= 0.0) ? (0.0) : (la / (la - lb)));
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
        vec3 top = ((surface_plane(planes[0], b[0], b[1]) >= surface_plane(planes[1], b[0], b[1])) ? (planes[0]) : (planes[1]));
        best_s = 1.0;
        best_p = top;
    }
    return segment_some(best_s, math_normal_from_gradient(best_p[1], best_p[2]), 0u, ca);
}

// `qu_triangles_segment`: Qu et al.'s division-free test on the fixed diagonal u = v.
// The segment starts in the triangle on a's side; if it crosses the diagonal, the
// contact is in that triangle iff ca |g_b| + l_b |g_a| <= 0 (g = u - v, l_b that
// triangle's plane clearance at b); past the crossing the clearance runs linearly to cb.
SegmentHit surface_qu_triangles_segment(vec4 c, vec3 a, vec3 b, float ca, float cb) {
    float ga = a[0] - a[1];
    float gb = b[0] - b[1];
    uint first = uint(ga < 0.0 || (ga == 0.0 && gb < 0.0));
    bool crosses = ((first == 0u) ? (gb < 0.0) : (gb > 0.0));
    vec3 p = surface_fixed_diagonal_plane(c, first);
    if (!crosses) {
        if (cb <= 0.0) {
            return segment_some(ca / (ca - cb), math_normal_from_gradient(p[1], p[2]), 0u, ca);
        }
        return segment_none(real_min(ca, cb));
    }
    float wa = abs(ga);
    float wb = abs(gb);
    float lb = b[2] - surface_plane(p, b[0], b[1]);
    float crossing = ca * wb + lb * wa;
    if (crossing <= 0.0) {
        return segment_some(ca / (ca - lb), math_normal_from_gradient(p[1], p[2]), 0u, ca);
    }
    float cd = crossing / (wa + wb);
    float clearance = real_min(ca, cd);
    if (cb > 0.0) {
        return segment_none(real_min(clearance, cb));
    }
    float sd = wa / (wa + wb);
    // `cd` is 0 only when the product underflowed: the contact is then the crossing.
    float s = sd;
    if (cd > 0.0) {
        s = sd + (1.0 - sd) * (cd / (cd - cb));
    }
    vec3 q = surface_fixed_diagonal_plane(c, 1u - first);
    return segment_some(real_min(s, 1.0), math_normal_from_gradient(q[1], q[2]), 0u, clearance);
}

// `stable_roots`: the roots of `A x^2 + B x + C` without cancellation (q / A and C / q
// with q = -(B + sign(B) sqrt(D)) / 2) into `roots`; returns how many (0 to 2).
int surface_stable_roots(float qa, float qb, float qc, inout float[2] roots) {
    float disc = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0) {
        return 0;
    }
    float sq = sqrt(disc);
    float q = ((qb >= 0.0) ? (-0.5 * (qb + sq)) : (-0.5 * (qb - sq)));
    if (q == 0.0) {
        // B = 0 and D = 0: a double root at 0 when C = 0, or no root (A = B = 0, C != 0).
        if (qc == 0.0) {
            (roots)[0] = 0.0;
            return 1;
        }
        return 0;
    }
    (roots)[0] = q / qa;
    (roots)[1] = qc / q;
    return 2;
}

// `smallest_root_in_unit`: smallest root of `A s^2 + B s + C` in [0, 1] (within a few
// ulps, then clamped), of the stable roots; `found` is false for none.
float surface_smallest_root_in_unit(float qa, float qb, float qc, inout bool found) {
    found = false;
    float best = 0.0;
    float tol = 64.0 * REAL_EPSILON;
    float[2] roots;
    int n = surface_stable_roots(qa, qb, qc, roots);
    for (int k = 0; k < n; k++) {
        float r = roots[k];
        if (real_is_finite(r) && r >= -tol && r <= 1.0 + tol) {
            r = real_clamp_to(r, 0.0, 1.0);
            if (!found || r < best) {
                found = true;
                best = r;
            }
        }
    }
    return best;
}

// `bisect`: first sign change of `A s^2 + B s + C` on [0, 1], given C > 0 >= A+B+C.
float surface_bisect(float qa, float qb, float qc) {
    float lo = 0.0;
    float hi = 1.0;
    for (int k = 0; k < 64; k++) {
        float mid = 0.5 * (lo + hi);
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
SegmentHit surface_bilinear_segment(vec4 c, vec3 a, vec3 b, float ca, float cb) {
    float e = c[0] - c[1] - c[2] + c[3];
    float qa = -e * (b[0] - a[0]) * (b[1] - a[1]);
    float qc = ca;
    float qb = cb - ca - qa;
    float clearance = real_min(ca, cb);
    bool has_s = false;
    float s = 0.0;
    if (cb <= 0.0) {
        // A sign change: a root in (0, 1] exists; fall back on bisection if rounding
        // pushed the discriminant below zero.
        bool found;
        float r = surface_smallest_root_in_unit(qa, qb, qc, found);
        has_s = true;
        if (found) {
            s = r;
        } else {
            s = surface_bisect(qa, qb, qc);
        }
    } else if (qa > 0.0) {
        // Both ends clear: the ray can still dip under a saddle between them.
        float vertex = -qb / (2.0 * qa);
        if (vertex > 0.0 && vertex < 1.0) {
            float lowest = qc - qb * qb / (4.0 * qa);
            clearance = real_min(clearance, lowest);
            if (lowest <= 0.0) {
                bool found;
                float r = surface_smallest_root_in_unit(qa, qb, qc, found);
                has_s = true;
                s = ((found) ? (r) : (vertex));
            }
        }
    }
    if (!has_s) {
        return segment_none(clearance);
    }
    float u = a[0] + (b[0] - a[0]) * s;
    float v = a[1] + (b[1] - a[1]) * s;
    // Up to its first root the quadratic has no minimum below min(ca, 0): nothing but `ca`.
    return segment_some(s, surface_cell_normal(HF_SURFACE_BILINEAR, c, u, v), 0u, ca);
}

// `height_planes_segment`: the cell holds four constant quarters; the segment is split
// where it crosses u = 1/2 and v = 1/2 and each piece tested against its quarter.
SegmentHit surface_height_planes_segment(vec4 c, vec3 a, vec3 b, vec3 entry_wall) {
    vec3 d = vec3(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    // Split parameters where u or v crosses 1/2, with the wall normal met there.
    float[2] cut_s;
    vec3[2] cut_n;
    int cuts = 0;
    for (int axis = 0; axis < 2; axis++) {
        if (d[axis] != 0.0) {
            float s = (0.5 - a[axis]) / d[axis];
            if (s > 0.0 && s < 1.0) {
                vec3 n = vec3(0.0);
                n[axis] = ((d[axis] > 0.0) ? (-1.0) : (1.0));
                cut_s[cuts] = s;
                cut_n[cuts] = n;
                cuts++;
            }
        }
    }
    if (cuts == 2 && cut_s[1] < cut_s[0]) {
        float ts = cut_s[0];
        cut_s[0] = cut_s[1];
        cut_s[1] = ts;
        vec3 tn = cut_n[0];
        cut_n[0] = cut_n[1];
        cut_n[1] = tn;
    }
    float clearance = real_infinity();
    float start_s = 0.0;
    vec3 start_n = entry_wall;
    for (int k = 0; k <= cuts; k++) {
        float end = 1.0;
        vec3 next_wall = entry_wall;
        if (k < cuts) {
            end = cut_s[k];
            next_wall = cut_n[k];
        }
        float mid = 0.5 * (start_s + end);
        float h = c[surface_nearest_corner(a[0] + d[0] * mid, a[1] + d[1] * mid)];
        float c0 = a[2] + d[2] * start_s - h;
        float c1 = a[2] + d[2] * end - h;
        if (c0 <= 0.0) {
            return segment_some(start_s, start_n, HF_FLAG_WALL, real_min(clearance, -c0));
        }
        clearance = real_min(clearance, c0);
        if (c1 <= 0.0) {
            float s = start_s + (end - start_s) * c0 / (c0 - c1);
            return segment_some(s, vec3(0.0, 0.0, 1.0), 0u, clearance);
        }
        clearance = real_min(clearance, c1);
        start_s = end;
        start_n = next_wall;
    }
    return segment_none(clearance);
}

// `Surface::segment_hit`: first contact of the segment a -> b with the surface over
// one cell, from the clearances ca > 0 and cb the caller computed at its ends.
SegmentHit surface_segment_hit(uint surface, vec4 c, vec3 a, vec3 b, float ca, float cb, vec3 entry_wall) {
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
            float s = ca / (ca - cb);
            float u = a[0] + (b[0] - a[0]) * s;
            float v = a[1] + (b[1] - a[1]) * s;
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
        vec3 p = surface_linear_plane(c);
        float la = a[2] - surface_plane(p, a[0], a[1]);
        float lb = b[2] - surface_plane(p, b[0], b[1]);
        vec3 n = math_normal_from_gradient(p[1], p[2]);
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
