// HF_METHOD_CC: hf_trace is safety::cc::trace_on on the surface `hf_surface`:
// triangles or view-linear (any other falls back to triangles: safety_march_surface).
uniform uint hf_surface;

// The closure of `cc::trace`: the texel's shape for the class, then `ConeStep::cone`
// (the step, and the fetches of the cone's base height).
uvec2 safety_march_jump(SafetyLine l, uint ray_class, uint i, uint j, vec3 d) {
    vec2 rise = cc_rise(d);
    return cc_cone_step(cc_texel(ray_class, i, j), safety_axis_of(ray_class), l, rise[0], rise[1]);
}

Trace hf_trace(Query q) { return cc_trace_on(hf_surface, q); }
