// HF_METHOD_QDM: hf_trace is qdm::trace, at most `hf_max_iter` iterations.
uniform uint hf_max_iter;

int cone_march_step(uvec2 cell, vec3 p, vec3 d, out float dt, out uint fetches) {
    return qdm_step(cell, p, d, dt, fetches);
}

Trace hf_trace(Query q) { return cone_march(q, hf_max_iter); }
