// HF_METHOD_RADIUS: hf_trace is radius::trace on the surface `hf_surface` (the
// `surface` of radius::Options): triangles or view-linear (any other falls back to
// triangles: safety_march_surface). `hf_radius_clamp` is 1 for Zero::Clamp (a zero
// radius jumps one centerline), 0 for Zero::Walk.
uniform uint hf_surface;
uniform uint hf_radius_clamp;

// The closure of `radius::trace_steps`: the texel's radius, at least `floor` (no extra
// fetch).
uvec2 safety_march_jump(SafetyLine l, uint ray_class, uint i, uint j, vec3 d) {
    uint floor_ = hf_radius_clamp == 1u ? 1u : 0u;
    return uvec2(max(radius_at(i, j), floor_), 0u);
}

Trace hf_trace(Query q) { return safety_march(hf_surface, q, true); }
