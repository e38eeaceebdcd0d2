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
const HF_IMPOSTOR_INTERSECTION: u32 = 0u;
const HF_IMPOSTOR_FACING_FIELD: u32 = 1u;
// Passes over the six fields before the intersection stops unsettled (MAX_ROUNDS).
const HF_IMPOSTOR_MAX_ROUNDS: u32 = 64u;
// `ImpostorTrace::face` of a miss.
const HF_IMPOSTOR_NO_FACE: u32 = 6u;

//#wgsl
struct ImpostorParams {
    maps: array<Mat4Rows, 6>,
    inverses: array<Mat4Rows, 6>,
    cube: vec4<f32>,
}

@group(0) @binding(21) var<uniform> hf_impostor: ImpostorParams;

fn impostor_map(k: u32) -> Mat4Rows { return hf_impostor.maps[k]; }
fn impostor_inverse(k: u32) -> Mat4Rows { return hf_impostor.inverses[k]; }
fn impostor_cube() -> vec4<f32> { return hf_impostor.cube; }
//#end
//#glsl
// uniform vec4 hf_impostor_maps[24];
// uniform vec4 hf_impostor_inverses[24];
// uniform vec4 hf_impostor_cube;
//
// Mat4Rows impostor_map(uint k) { return Mat4Rows(hf_impostor_maps[4u * k], hf_impostor_maps[4u * k + 1u], hf_impostor_maps[4u * k + 2u], hf_impostor_maps[4u * k + 3u]); }
// Mat4Rows impostor_inverse(uint k) { return Mat4Rows(hf_impostor_inverses[4u * k], hf_impostor_inverses[4u * k + 1u], hf_impostor_inverses[4u * k + 2u], hf_impostor_inverses[4u * k + 3u]); }
// vec4 impostor_cube() { return hf_impostor_cube; }
//#end

// `ImpostorTrace`: the hit in world space, the face whose field it is on
// (HF_IMPOSTOR_NO_FACE for a miss), the field traces made.
struct ImpostorTrace {
    trace: Trace,
    face: u32,
    traces: u32,
}

// `facing_face`: the face whose outward normal is most against `d` (the first axis of
// largest |d|).
fn impostor_facing_face(d: vec3<f32>) -> u32 {
    var a: u32 = 0u;
    if (abs(d.y) > abs(d.x)) {
        a = 1u;
    }
    if (abs(d.z) > abs(d[a])) {
        a = 2u;
    }
    return 2u * a + select(0u, 1u, d[a] > 0.0);
}

// The grid height under which no field's solid reaches (`FLOOR`).
const HF_IMPOSTOR_FLOOR: f32 = -0.5;

// Field k's trace of the world ray over [t, t_end] (`Impostor::field_trace`): the grid
// ray's range cut to where it is at or above HF_IMPOSTOR_FLOOR.
fn impostor_field_trace(k: u32, world: Query, t: f32, t_end: f32) -> Trace {
    hf_field_slot = k;
    let miss: Trace = trace_miss(0u, real_infinity());
    var pr: ProjectiveRay = projective_map(impostor_map(k), Query(world.origin, world.dir, t, t_end));
    if (!pr.ok) {
        return miss;
    }
    let oz: f32 = pr.grid.origin.z;
    let dz: f32 = pr.grid.dir.z;
    let at_floor: f32 = (HF_IMPOSTOR_FLOOR - oz) / dz;
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
fn hf_trace_impostor(world: Query, combine: u32) -> ImpostorTrace {
    var res: ImpostorTrace = ImpostorTrace(trace_miss(0u, real_infinity()), HF_IMPOSTOR_NO_FACE, 0u);
    // `Layout::clip`: the part of [t_min, t_max] inside the cube.
    let cube: vec4<f32> = impostor_cube();
    let x: vec2<f32> = dda_slab(world.origin.x, world.dir.x, cube.x - cube.w, cube.x + cube.w);
    let y: vec2<f32> = dda_slab(world.origin.y, world.dir.y, cube.y - cube.w, cube.y + cube.w);
    let z: vec2<f32> = dda_slab(world.origin.z, world.dir.z, cube.z - cube.w, cube.z + cube.w);
    var t: f32 = real_max(max(max(x.x, y.x), z.x), world.t_min);
    let t_end: f32 = real_min(min(min(x.y, y.y), z.y), world.t_max);
    if (!(t <= t_end)) {
        return res;
    }
    if (combine == HF_IMPOSTOR_FACING_FIELD) {
        let k: u32 = impostor_facing_face(world.dir);
        res.trace = impostor_field_trace(k, world, t, t_end);
        res.traces = 1u;
        if (res.trace.has_hit) {
            res.face = k;
        }
        return res;
    }
    // Bit k of `held`: field k held the ray's point at the current t (the core's
    // held[k] == Some(t); t only grows, so a larger t clears them all).
    var held: u32 = 0u;
    var best: Hit = hit_none();
    var best_face: u32 = HF_IMPOSTOR_NO_FACE;
    var fetches: u32 = 0u;
    loop {
        var k: u32 = 0u;
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
        let tr: Trace = impostor_field_trace(k, world, t, t_end);
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

//#wgsl
@group(0) @binding(22) var<uniform> hf_view_proj: Mat4Rows;

fn impostor_view_proj() -> Mat4Rows { return hf_view_proj; }
//#end
//#glsl
// uniform vec4 hf_view_proj[4];
//
// Mat4Rows impostor_view_proj() { return Mat4Rows(hf_view_proj[0], hf_view_proj[1], hf_view_proj[2], hf_view_proj[3]); }
//#end

// The fragment's depth at the world point `p` (a hit's point), for `@builtin(frag_depth)`
// (GLSL: gl_FragDepth): its normalized device z under hf_view_proj, WGSL's [0, 1] as it
// is, GLSL's [-1, 1] mapped to the default depth range [0, 1].
fn hf_impostor_depth(p: vec3<f32>) -> f32 {
    let clip: vec4<f32> = projective_mul(impostor_view_proj(), vec4<f32>(p, 1.0));
    let ndc: f32 = clip.z / clip.w;
//#wgsl
    return ndc;
//#end
//#glsl
    // return 0.5 * ndc + 0.5;
//#end
}
//#endif
