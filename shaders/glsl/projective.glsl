// Generated from shaders/wgsl/projective.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/projective.rs in f32: projective height fields (Baboud & Décoret
// §4). `fn hf_trace_projective(m: Mat4Rows, m_inv: Mat4Rows, world: Query) -> Trace`
// maps a world ray to its grid line (the part with w > 0), traces it with the method's
// `hf_trace` and maps the hit back: t from the line's parameter, the point by `m_inv`,
// the normal by the transpose of `m` (docs/DESIGN.md, "Projective height fields"). The
// caller passes the map from world points [x, y, z, 1] to homogeneous grid points, and
// its inverse, by rows (from its own uniforms: the map is not a scene choice).
//
// What a shader can promise: the core maps in f64 and rounds the grid ray once; here
// the map is computed in f32, so the grid ray differs from the core's by rounding (a
// few ulps of the homogeneous coordinates), and a hit's t, point and normal agree with
// `Projective::trace` within that (shadertest/tests/wgsl_projective.rs: 1.7e-5 of the
// ray's magnitude). A ray from behind the centre of projection that is under the
// surface where its range starts hits there, where its line comes in from infinity:
// which face of the widened box that is can differ from the core's (ill-conditioned).

// A 4x4 matrix by rows (no matrix types: the file is translated to GLSL).
struct Mat4Rows {
    vec4 r0;
    vec4 r1;
    vec4 r2;
    vec4 r3;
};

// `m · v`.
vec4 projective_mul(Mat4Rows m, vec4 v) {
    return vec4(dot(m.r0, v), dot(m.r1, v), dot(m.r2, v), dot(m.r3, v));
}

// `Mapped`: the grid query and what maps its parameter back; `ok` false when the ray
// has no part in the field's space.
struct ProjectiveRay {
    Query grid;
    float t_b;
    float w_b;
    float b_w;
    bool ok;
};

// `Projective::map`.
ProjectiveRay projective_map(Mat4Rows m, Query world) {
    vec4 a = projective_mul(m, vec4(world.origin, 1.0));
    vec4 b = projective_mul(m, vec4(world.dir, 0.0));
    ProjectiveRay none = ProjectiveRay(world, 0.0, 1.0, 0.0, false);
    float t0 = world.t_min;
    float t1 = world.t_max;
    if (b.w == 0.0) {
        if (a.w <= 0.0) {
            return none;
        }
    } else {
        float root = -a.w / b.w;
        if (b.w > 0.0) {
            t0 = max(t0, root);
        } else {
            t1 = min(t1, root);
        }
    }
    if (t0 > t1) {
        return none;
    }
    // The base: the start unless w is tiny there, else where w is largest.
    float t_big = t0;
    if (b.w > 0.0) {
        t_big = ((real_is_finite(t1)) ? (t1) : (max(t0, -a.w / b.w + 1.0 / b.w)));
    }
    float t_b = t_big;
    if (a.w + t0 * b.w >= 1e-6 * (a.w + t_big * b.w)) {
        t_b = t0;
    }
    float w_b = a.w + t_b * b.w;
    if (!(w_b > 0.0 && real_is_finite(w_b))) {
        return none;
    }
    vec3 ab = a.xyz + t_b * b.xyz;
    vec3 g_b = ab / w_b;
    vec3 e = (b.xyz * w_b - ab * b.w) / (w_b * w_b);
    float inf = real_infinity();
    // sigma(t) at the ends: -inf / +inf at the root or at t = inf.
    float s0 = -inf;
    float w0 = a.w + t0 * b.w;
    if (real_is_finite(t0) && w0 > 0.0) {
        s0 = (t0 - t_b) * w_b / w0;
    }
    float s1 = inf;
    float w1 = a.w + t1 * b.w;
    if (real_is_finite(t1) && w1 > 0.0) {
        s1 = (t1 - t_b) * w_b / w1;
    }
    if (s0 == -inf) {
        // From where the line enters the box every surface lies in, widened by a unit.
        float zmin = field_min_height();
        float zmax = field_max_height();
        float range = zmax - zmin;
        vec2 x = dda_slab(g_b.x, e.x, -1.0, float(field_width()));
        vec2 y = dda_slab(g_b.y, e.y, -1.0, float(field_height()));
        vec2 z = dda_slab(g_b.z, e.z, zmin - range - 1.0, zmax + range + 1.0);
        s0 = max(max(x.x, y.x), z.x);
        float far = min(min(x.y, y.y), z.y);
        if (!(real_is_finite(s0) && s0 <= min(far, s1))) {
            return none;
        }
    }
    return ProjectiveRay(Query(g_b, e, s0, s1), t_b, w_b, b.w, true);
}

// `Projective::trace_to_world`: the trace `grid_trace` of `pr`'s grid query with its
// hit mapped back to the world ray.
Trace projective_to_world(Mat4Rows m, Mat4Rows m_inv, ProjectiveRay pr, Trace grid_trace) {
    Trace tr = grid_trace;
    if (tr.has_hit) {
        float s = tr.hit.t;
        tr.hit.t = pr.t_b + s * pr.w_b / (pr.w_b - s * pr.b_w);
        vec4 x = projective_mul(m_inv, vec4(tr.hit.point, 1.0));
        vec3 n = tr.hit.normal;
        vec4 plane = vec4(n, -dot(n, tr.hit.point));
        vec4 wn = plane.x * m.r0 + plane.y * m.r1 + plane.z * m.r2 + plane.w * m.r3;
        tr.hit.point = x.xyz / x.w;
        tr.hit.normal = normalize(wn.xyz);
    }
    return tr;
}

// `Projective::trace` with the method's march.
Trace hf_trace_projective(Mat4Rows m, Mat4Rows m_inv, Query world) {
    ProjectiveRay pr = projective_map(m, world);
    if (!pr.ok) {
        return trace_miss(0u, real_infinity());
    }
    return projective_to_world(m, m_inv, pr, hf_trace(pr.grid));
}
