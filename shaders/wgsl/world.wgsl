// Mirror of core/src/world.rs: world units, where a field's grid sits in the caller's
// frame. `fn hf_trace_world(world: Query) -> Trace` takes a ray in world units and
// returns its hit in world units; `hf_trace` stays the grid-space entry (grid space is
// the marches' frame).
//
// The transform (`WorldTransform`, the C API's hf_transform from hf_field_get_transform)
// is the uniform `hf_world` (32 bytes: `offset` at byte 0, `scale` at byte 16):
//   world = hf_world.offset + hf_world.scale * grid, componentwise, with
//   offset = (origin[0], origin[1], height_offset),
//   scale = (spacing[0], spacing[1], height_scale);
// spacings non-zero (negative flips an axis), height_scale positive, as
// `WorldTransform::new` checks. A WGSL uniform has no default: a caller of
// hf_trace_world binds one, the identity offset (0, 0, 0) and scale (1, 1, 1) for grid
// space; a caller of hf_trace alone binds nothing (the binding is used only by
// hf_trace_world). The ray parameter is the same in both frames: t, t_min, t_max and a
// hit's t need no conversion. The caller validates the world ray as for hf_trace; a
// transform so extreme that the grid ray overflows or its direction underflows to zero
// (a RayError on the CPU) is the caller's to avoid.
//
// What a shader can promise: the core converts in f64 and rounds once to f32; a shader
// has no f64, so it rounds the transform to f32 and converts in f32 (a subtraction and a
// division per component, the division within 2.5 ulp on Vulkan). The grid ray may then
// differ from the core's by a few ulps of the world coordinates (put the origin near the
// field and the camera, as for the core), so t, the hit point and the normal agree with
// `WorldTransform::trace` within rounding, and a ray grazing an edge may rarely fall on
// the other side of it. With the identity nothing is converted: the answers are
// `hf_trace`'s bit for bit.

struct WorldParams {
    offset: vec3<f32>,
    scale: vec3<f32>,
}

@group(0) @binding(12) var<uniform> hf_world: WorldParams;

// `WorldTransform::is_identity`.
fn world_is_identity() -> bool {
    return all(hf_world.offset == vec3<f32>(0.0)) && all(hf_world.scale == vec3<f32>(1.0));
}

// `WorldTransform::query_to_grid` (`point_to_grid`, `dir_to_grid`); the identity returns
// the ray unchanged.
fn world_query_to_grid(world: Query) -> Query {
    if (world_is_identity()) {
        return world;
    }
    let o: vec3<f32> = (world.origin - hf_world.offset) / hf_world.scale;
    return Query(o, world.dir / hf_world.scale, world.t_min, world.t_max);
}

// `WorldTransform::normal_to_world`: the inverse transpose, renormalised.
fn world_normal_to_world(n: vec3<f32>) -> vec3<f32> {
    let m: vec3<f32> = n / hf_world.scale;
    let len: f32 = length(m);
    return select(m, m / len, len > 0.0);
}

// `WorldTransform::trace_to_world`: the hit point (`point_to_world`) and normal mapped
// to world space, the clearance scaled by the height scale; t, the cell, the flags and
// the fetches unchanged. The identity returns the trace unchanged.
fn world_trace_to_world(tr: Trace) -> Trace {
    if (world_is_identity()) {
        return tr;
    }
    var out: Trace = tr;
    if (tr.has_hit) {
        out.hit.point = hf_world.offset + hf_world.scale * tr.hit.point;
        out.hit.normal = world_normal_to_world(tr.hit.normal);
    }
    if (real_is_finite(tr.clearance)) {
        out.clearance = tr.clearance * hf_world.scale.z;
    }
    return out;
}

// `WorldTransform::trace` with the method's march: a world ray in, its hit in world units
// out.
fn hf_trace_world(world: Query) -> Trace {
    return world_trace_to_world(hf_trace(world_query_to_grid(world)));
}
