// HF_METHOD_SAFETY: hf_trace is safety::trace_on on the surface `hf_surface`:
// triangles or view-linear (any other falls back to triangles: safety_march_surface).
override hf_surface: u32 = 0u;

// The closure of `safety::trace`: the texel's safety distance (no extra fetch).
fn safety_march_jump(l: SafetyLine, ray_class: u32, i: u32, j: u32, d: vec3<f32>) -> vec2<u32> {
    return vec2<u32>(safety_distance(ray_class, i, j), 0u);
}

fn hf_trace(q: Query) -> Trace { return safety_trace_on(hf_surface, q); }
