// HF_METHOD_CC: hf_trace is safety::cc::trace_on on the surface `hf_surface`:
// triangles or view-linear (any other falls back to triangles: safety_march_surface).
override hf_surface: u32 = 0u;

// The closure of `cc::trace`: the texel's shape for the class, then `ConeStep::cone`
// (the step, and the fetches of the cone's base height).
fn safety_march_jump(l: SafetyLine, ray_class: u32, i: u32, j: u32, d: vec3<f32>) -> vec2<u32> {
    let rise: vec2<f32> = cc_rise(d);
    return cc_cone_step(cc_texel(ray_class, i, j), safety_axis_of(ray_class), l, rise[0], rise[1]);
}

fn hf_trace(q: Query) -> Trace { return cc_trace_on(hf_surface, q); }
