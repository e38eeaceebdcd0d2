// HF_METHOD_RADIUS: hf_trace is radius::trace on the surface `hf_surface` (the
// `surface` of radius::Options): triangles or view-linear (any other falls back to
// triangles: safety_march_surface). `hf_params.clamp` is 1 for Zero::Clamp (a zero
// radius jumps one centerline), 0 for Zero::Walk.
override hf_surface: u32 = 0u;

struct RadiusParams {
    clamp: u32,
}

@group(0) @binding(2) var<uniform> hf_params: RadiusParams;

// The closure of `radius::trace_steps`: the texel's radius, at least `floor` (no extra
// fetch).
fn safety_march_jump(l: SafetyLine, ray_class: u32, i: u32, j: u32, d: vec3<f32>) -> vec2<u32> {
    let floor_: u32 = select(0u, 1u, hf_params.clamp == 1u);
    return vec2<u32>(max(radius_at(i, j), floor_), 0u);
}

fn hf_trace(q: Query) -> Trace { return safety_march(hf_surface, q, true); }
