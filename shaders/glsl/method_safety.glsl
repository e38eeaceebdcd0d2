// HF_METHOD_SAFETY: hf_trace is safety::trace_on on the surface `hf_surface`:
// triangles or view-linear (any other falls back to triangles: safety_march_surface).
uniform uint hf_surface;

// The closure of `safety::trace`: the texel's safety distance (no extra fetch).
uvec2 safety_march_jump(SafetyLine l, uint ray_class, uint i, uint j, vec3 d) {
    return uvec2(safety_distance(ray_class, i, j), 0u);
}

Trace hf_trace(Query q) { return safety_trace_on(hf_surface, q); }
