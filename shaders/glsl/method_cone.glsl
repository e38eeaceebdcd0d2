// HF_METHOD_CONE: hf_trace is cone::trace, at most `hf_max_iter` iterations.
uniform uint hf_max_iter;

// The closure of `cone::trace_steps`: one fetch of the cell's texel, then `cone_step`.
int cone_march_step(uvec2 cell, vec3 p, vec3 d, out float dt, out uint fetches) {
    vec2 tex = cone_texel(cell[0], cell[1]);
    fetches = 1u;
    return cone_cone_step(p, d, tex[0], tex[1], dt);
}

Trace hf_trace(Query q) { return cone_march(q, hf_max_iter); }
