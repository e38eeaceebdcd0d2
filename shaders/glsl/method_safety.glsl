// HF_METHOD_SAFETY: hf_trace is safety::trace (triangle surface only).

// The closure of `safety::trace`: the texel's safety distance.
uint safety_march_jump(SafetyLine l, uint ray_class, uint i, uint j, vec3 d) {
    return safety_distance(ray_class, i, j);
}

Trace hf_trace(Query q) { return safety_trace(q); }
