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
    r0: vec4<f32>,
    r1: vec4<f32>,
    r2: vec4<f32>,
    r3: vec4<f32>,
}

// `m · v`.
fn projective_mul(m: Mat4Rows, v: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(dot(m.r0, v), dot(m.r1, v), dot(m.r2, v), dot(m.r3, v));
}

// `Mapped`: the grid query and what maps its parameter back; `ok` false when the ray
// has no part in the field's space.
struct ProjectiveRay {
    grid: Query,
    t_b: f32,
    w_b: f32,
    b_w: f32,
    ok: bool,
}

// `Projective::map`.
fn projective_map(m: Mat4Rows, world: Query) -> ProjectiveRay {
    let a: vec4<f32> = projective_mul(m, vec4<f32>(world.origin, 1.0));
    let b: vec4<f32> = projective_mul(m, vec4<f32>(world.dir, 0.0));
    var none: ProjectiveRay = ProjectiveRay(world, 0.0, 1.0, 0.0, false);
    var t0: f32 = world.t_min;
    var t1: f32 = world.t_max;
    if (b.w == 0.0) {
        if (a.w <= 0.0) {
            return none;
        }
    } else {
        let root: f32 = -a.w / b.w;
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
    var t_big: f32 = t0;
    if (b.w > 0.0) {
        t_big = select(max(t0, -a.w / b.w + 1.0 / b.w), t1, real_is_finite(t1));
    }
    var t_b: f32 = t_big;
    if (a.w + t0 * b.w >= 1e-6 * (a.w + t_big * b.w)) {
        t_b = t0;
    }
    let w_b: f32 = a.w + t_b * b.w;
    if (!(w_b > 0.0 && real_is_finite(w_b))) {
        return none;
    }
    let ab: vec3<f32> = a.xyz + t_b * b.xyz;
    let g_b: vec3<f32> = ab / w_b;
    let e: vec3<f32> = (b.xyz * w_b - ab * b.w) / (w_b * w_b);
    let inf: f32 = real_infinity();
    // sigma(t) at the ends: -inf / +inf at the root or at t = inf.
    var s0: f32 = -inf;
    let w0: f32 = a.w + t0 * b.w;
    if (real_is_finite(t0) && w0 > 0.0) {
        s0 = (t0 - t_b) * w_b / w0;
    }
    var s1: f32 = inf;
    let w1: f32 = a.w + t1 * b.w;
    if (real_is_finite(t1) && w1 > 0.0) {
        s1 = (t1 - t_b) * w_b / w1;
    }
    if (s0 == -inf) {
        // From where the line enters the box every surface lies in, widened by a unit.
        let zmin: f32 = field_min_height();
        let zmax: f32 = field_max_height();
        let range: f32 = zmax - zmin;
        let x: vec2<f32> = dda_slab(g_b.x, e.x, -1.0, f32(field_width()));
        let y: vec2<f32> = dda_slab(g_b.y, e.y, -1.0, f32(field_height()));
        let z: vec2<f32> = dda_slab(g_b.z, e.z, zmin - range - 1.0, zmax + range + 1.0);
        s0 = max(max(x.x, y.x), z.x);
        let far: f32 = min(min(x.y, y.y), z.y);
        if (!(real_is_finite(s0) && s0 <= min(far, s1))) {
            return none;
        }
    }
    return ProjectiveRay(Query(g_b, e, s0, s1), t_b, w_b, b.w, true);
}

// `Projective::trace_to_world`: the trace `grid_trace` of `pr`'s grid query with its
// hit mapped back to the world ray.
fn projective_to_world(m: Mat4Rows, m_inv: Mat4Rows, pr: ProjectiveRay, grid_trace: Trace) -> Trace {
    var tr: Trace = grid_trace;
    if (tr.has_hit) {
        let s: f32 = tr.hit.t;
        tr.hit.t = pr.t_b + s * pr.w_b / (pr.w_b - s * pr.b_w);
        let x: vec4<f32> = projective_mul(m_inv, vec4<f32>(tr.hit.point, 1.0));
        let n: vec3<f32> = tr.hit.normal;
        let plane: vec4<f32> = vec4<f32>(n, -dot(n, tr.hit.point));
        let wn: vec4<f32> = plane.x * m.r0 + plane.y * m.r1 + plane.z * m.r2 + plane.w * m.r3;
        tr.hit.point = x.xyz / x.w;
        tr.hit.normal = normalize(wn.xyz);
    }
    return tr;
}

// `Projective::trace` with the method's march.
fn hf_trace_projective(m: Mat4Rows, m_inv: Mat4Rows, world: Query) -> Trace {
    let pr: ProjectiveRay = projective_map(m, world);
    if (!pr.ok) {
        return trace_miss(0u, real_infinity());
    }
    return projective_to_world(m, m_inv, pr, hf_trace(pr.grid));
}
