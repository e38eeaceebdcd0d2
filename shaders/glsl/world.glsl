// Mirror of core/src/world.rs: world units, where a field's grid sits in the caller's
// frame. `Trace hf_trace_world(Query world)` takes a ray in world units and returns its
// hit in world units; `hf_trace` stays the grid-space entry (grid space is the marches'
// frame).
//
// The transform (`WorldTransform`, the C API's hf_transform from hf_field_get_transform)
// is two uniforms, the identity by default:
//   world = hf_world_offset + hf_world_scale * grid, componentwise, with
//   hf_world_offset = (origin[0], origin[1], height_offset),
//   hf_world_scale = (spacing[0], spacing[1], height_scale);
// spacings non-zero (negative flips an axis), height_scale positive, as
// `WorldTransform::new` checks. The ray parameter is the same in both frames: t, t_min,
// t_max and a hit's t need no conversion. The caller validates the world ray as for
// hf_trace; a transform so extreme that the grid ray overflows or its direction
// underflows to zero (a RayError on the CPU) is the caller's to avoid.
//
// What a shader can promise: the core converts in f64 and rounds once to f32; a shader
// has no f64, so it rounds the transform to f32 and converts in f32 (a subtraction and a
// division per component, GLSL's division within 2.5 ulp). The grid ray may then differ
// from the core's by a few ulps of the world coordinates (put the origin near the field
// and the camera, as for the core), so t, the hit point and the normal agree with
// `WorldTransform::trace` within rounding, and a ray grazing an edge may rarely fall on
// the other side of it. With the identity (the default) nothing is converted: the answers
// are `hf_trace`'s bit for bit.

uniform vec3 hf_world_offset = vec3(0.0);
uniform vec3 hf_world_scale = vec3(1.0);

// `WorldTransform::is_identity`.
bool world_is_identity() {
    return hf_world_offset == vec3(0.0) && hf_world_scale == vec3(1.0);
}

// `WorldTransform::query_to_grid` (`point_to_grid`, `dir_to_grid`); the identity returns
// the ray unchanged.
Query world_query_to_grid(Query world) {
    if (world_is_identity()) {
        return world;
    }
    vec3 o = (world.origin - hf_world_offset) / hf_world_scale;
    return Query(o, world.dir / hf_world_scale, world.t_min, world.t_max);
}

// `WorldTransform::normal_to_world`: the inverse transpose, renormalised.
vec3 world_normal_to_world(vec3 n) {
    vec3 m = n / hf_world_scale;
    float len = length(m);
    return len > 0.0 ? m / len : m;
}

// `WorldTransform::trace_to_world`: the hit point (`point_to_world`) and normal mapped
// to world space, the clearance scaled by the height scale; t, the cell, the flags and
// the fetches unchanged. The identity returns the trace unchanged.
Trace world_trace_to_world(Trace tr) {
    if (world_is_identity()) {
        return tr;
    }
    if (tr.has_hit) {
        tr.hit.point = hf_world_offset + hf_world_scale * tr.hit.point;
        tr.hit.normal = world_normal_to_world(tr.hit.normal);
    }
    if (real_is_finite(tr.clearance)) {
        tr.clearance = tr.clearance * hf_world_scale.z;
    }
    return tr;
}

// `WorldTransform::trace` with the method's march: a world ray in, its hit in world units
// out.
Trace hf_trace_world(Query world) {
    return world_trace_to_world(hf_trace(world_query_to_grid(world)));
}
