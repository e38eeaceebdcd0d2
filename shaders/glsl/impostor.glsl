// Generated from shaders/wgsl/impostor.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/impostor.rs in f32: six-field impostors (Baboud & Décoret §4.1-4.2),
// an object as six projective height fields on the faces of its bounding cube, each
// traced by `hf_trace_projective` (projective.wgsl) with the exact march.
// `fn hf_trace_impostor(world: Query, combine: u32) -> ImpostorTrace` is
// `Impostor::trace`: the first point of the world ray in the object inside the cube,
// for `combine` HF_IMPOSTOR_INTERSECTION (the intersection of the six solids) or
// HF_IMPOSTOR_FACING_FIELD (only the field of `facing_face(dir)`). Only the shaders
// hfcast_shaders::impostor generates hold this file (method exact).
//
// What the host sets (GLSL names first, then WGSL; the shader's header lists those it
// keeps):
// - the six fields, each W x W (a side W), stacked in one R32F texture `hf_heights` of
//   W x 6W texels (WGSL binding 0): field k's sample (i, j) at texel (i, j + kW), faces
//   in the order of hfcast::impostor::FACES (+x, -x, +y, -y, +z, -z), heights in grid
//   units as rasterize and pad_silhouettes write them; read with texelFetch only;
// - `hf_size` = (W, W) (WGSL: `hf_field.size`, binding 1, its other members unused);
// - `hf_field_ranges[k]` = (min, max) of field k's heights (WGSL: binding 20,
//   array<vec4<f32>, 6>, xy of element k), as the CPU's HeightField holds them;
// - `hf_impostor_maps[4k + r]` = row r of face k's map from world points [x, y, z, 1]
//   to homogeneous grid points, `Layout::face_map(k, W).matrix()` (the C API's
//   hf_impostor_face_map, row-major doubles), rounded to f32; `hf_impostor_inverses`
//   likewise the rows of its inverse (`Projective::inverse`, inverted in f64);
//   `hf_impostor_cube` = (centre x, y, z, half side) of the layout's cube (WGSL: the
//   uniform struct ImpostorParams `hf_impostor` at binding 21: maps[k].rN, then
//   inverses[k].rN, then cube, 784 bytes);
// - with depth output only: `hf_view_proj[r]` = row r of the host's world-to-clip
//   matrix (WGSL: `hf_view_proj`, a Mat4Rows at binding 22), read by
//   `hf_impostor_depth`.
// The heights and ranges are those of the core's fields exactly; the surface is the
// scene's (a constant), the march the exact DDA. A GLSL caller's main builds the world
// ray (a unit or any non-zero direction; t in [t_min, t_max]) and calls
// `ImpostorTrace hf_trace_impostor(Query world, uint combine)`; with depth output it
// writes `gl_FragDepth = hf_impostor_depth(tr.trace.hit.point)` for a hit.
//
// What a shader can promise: the core clips to the cube and maps each face in f64; here
// both are f32 (the maps rounded once, as in projective.wgsl), so each field's grid ray
// differs from the core's by a few ulps and a hit's t, point and normal agree with
// `Impostor::trace` within that (shadertest/tests/wgsl_impostor.rs: t and points within
// 1e-5 of the cube's half side, normals within 1e-5, on the bunny and a tower). Where
// two fields' surfaces meet at the answer the passes may settle on the other one of
// them (its face; its normal too where the surfaces cross: there, the tower's flat base
// is one plane in several fields), and a ray grazing a field's surface may fall on the
// other side of it, as for one projective field. The passes made (`traces`) may differ.

// How hf_trace_impostor combines the fields (hfcast::impostor::Combine).
const uint HF_IMPOSTOR_INTERSECTION = 0u;
const uint HF_IMPOSTOR_FACING_FIELD = 1u;
// Passes over the six fields before the intersection stops unsettled (MAX_ROUNDS).
const uint HF_IMPOSTOR_MAX_ROUNDS = 64u;
// `ImpostorTrace::face` of a miss.
const uint HF_IMPOSTOR_NO_FACE = 6u;

uniform vec4 hf_impostor_maps[24];
uniform vec4 hf_impostor_inverses[24];
uniform vec4 hf_impostor_cube;

Mat4Rows impostor_map(uint k) { return Mat4Rows(hf_impostor_maps[4u * k], hf_impostor_maps[4u * k + 1u], hf_impostor_maps[4u * k + 2u], hf_impostor_maps[4u * k + 3u]); }
Mat4Rows impostor_inverse(uint k) { return Mat4Rows(hf_impostor_inverses[4u * k], hf_impostor_inverses[4u * k + 1u], hf_impostor_inverses[4u * k + 2u], hf_impostor_inverses[4u * k + 3u]); }
vec4 impostor_cube() { return hf_impostor_cube; }

// `ImpostorTrace`: the hit in world space, the face whose field it is on
// (HF_IMPOSTOR_NO_FACE for a miss), the field traces made.
struct ImpostorTrace {
    Trace trace;
    uint face;
    uint traces;
};

// `facing_face`: the face whose outward normal is most against `d` (the first axis of
// largest |d|).
uint impostor_facing_face(vec3 d) {
    uint a = 0u;
    if (abs(d.y) > abs(d.x)) {
        a = 1u;
    }
    if (abs(d.z) > abs(d[a])) {
        a = 2u;
    }
    return 2u * a + ((d[a] > 0.0) ? (1u) : (0u));
}

// The grid height under which no field's solid reaches (`FLOOR`).
const float HF_IMPOSTOR_FLOOR = -0.5;

// Field k's trace of the world ray over [t, t_end] (`Impostor::field_trace`): the grid
// ray's range cut to where it is at or above HF_IMPOSTOR_FLOOR.
Trace impostor_field_trace(uint k, Query world, float t, float t_end) {
    hf_field_slot = k;
    Trace miss = trace_miss(0u, real_infinity());
    ProjectiveRay pr = projective_map(impostor_map(k), Query(world.origin, world.dir, t, t_end));
    if (!pr.ok) {
        return miss;
    }
    float oz = pr.grid.origin.z;
    float dz = pr.grid.dir.z;
    float at_floor = (HF_IMPOSTOR_FLOOR - oz) / dz;
    if (dz > 0.0) {
        pr.grid.t_min = real_max(pr.grid.t_min, at_floor);
    } else if (dz < 0.0) {
        pr.grid.t_max = real_min(pr.grid.t_max, at_floor);
    } else if (oz < HF_IMPOSTOR_FLOOR) {
        return miss;
    }
    if (!(pr.grid.t_min <= pr.grid.t_max)) {
        return miss;
    }
    return projective_to_world(impostor_map(k), impostor_inverse(k), pr, hf_trace(pr.grid));
}

// `Impostor::trace` with the exact march.
ImpostorTrace hf_trace_impostor(Query world, uint combine) {
    ImpostorTrace res = ImpostorTrace(trace_miss(0u, real_infinity()), HF_IMPOSTOR_NO_FACE, 0u);
    // `Layout::clip`: the part of [t_min, t_max] inside the cube.
    vec4 cube = impostor_cube();
    vec2 x = dda_slab(world.origin.x, world.dir.x, cube.x - cube.w, cube.x + cube.w);
    vec2 y = dda_slab(world.origin.y, world.dir.y, cube.y - cube.w, cube.y + cube.w);
    vec2 z = dda_slab(world.origin.z, world.dir.z, cube.z - cube.w, cube.z + cube.w);
    float t = real_max(max(max(x.x, y.x), z.x), world.t_min);
    float t_end = real_min(min(min(x.y, y.y), z.y), world.t_max);
    if (!(t <= t_end)) {
        return res;
    }
    if (combine == HF_IMPOSTOR_FACING_FIELD) {
        uint k = impostor_facing_face(world.dir);
        res.trace = impostor_field_trace(k, world, t, t_end);
        res.traces = 1u;
        if (res.trace.has_hit) {
            res.face = k;
        }
        return res;
    }
    // Bit k of `held`: field k held the ray's point at the current t (the core's
    // held[k] == Some(t); t only grows, so a larger t clears them all).
    uint held = 0u;
    Hit best = hit_none();
    uint best_face = HF_IMPOSTOR_NO_FACE;
    uint fetches = 0u;
    for (;;) {
        uint k = 0u;
        while (k < 6u && (held & (1u << k)) != 0u) {
            k++;
        }
        if (k == 6u) {
            break;
        }
        if (res.traces >= 6u * HF_IMPOSTOR_MAX_ROUNDS) {
            res.trace.flags = HF_FLAG_BUDGET_EXHAUSTED;
            break;
        }
        res.traces += 1u;
        Trace tr = impostor_field_trace(k, world, t, t_end);
        fetches += tr.fetches;
        if (!tr.has_hit) {
            res.trace.fetches = fetches;
            return res;
        }
        if (tr.hit.t > t || best_face == HF_IMPOSTOR_NO_FACE) {
            if (tr.hit.t > t) {
                held = 0u;
            }
            t = real_max(t, tr.hit.t);
            best = tr.hit;
            best_face = k;
        }
        held |= 1u << k;
    }
    best.t = t;
    res.trace = Trace(true, best, fetches, 0.0, res.trace.flags);
    res.face = best_face;
    return res;
}
//#if depth_output

uniform vec4 hf_view_proj[4];

Mat4Rows impostor_view_proj() { return Mat4Rows(hf_view_proj[0], hf_view_proj[1], hf_view_proj[2], hf_view_proj[3]); }

// The fragment's depth at the world point `p` (a hit's point), for `@builtin(frag_depth)`
// (GLSL: gl_FragDepth): its normalized device z under hf_view_proj, WGSL's [0, 1] as it
// is, GLSL's [-1, 1] mapped to the default depth range [0, 1].
float hf_impostor_depth(vec3 p) {
    vec4 clip = projective_mul(impostor_view_proj(), vec4(p, 1.0));
    float ndc = clip.z / clip.w;
    return 0.5 * ndc + 0.5;
}
//#endif
