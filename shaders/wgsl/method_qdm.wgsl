// HF_METHOD_QDM: hf_trace is qdm::trace, at most `hf_params.max_iter` iterations.

struct QdmParams {
    max_iter: u32,
}

@group(0) @binding(2) var<uniform> hf_params: QdmParams;

fn cone_march_step(cell: vec2<u32>, p: vec3<f32>, d: vec3<f32>, dt: ptr<function, f32>,
                   fetches: ptr<function, u32>) -> i32 {
    return qdm_step(cell, p, d, dt, fetches);
}

fn hf_trace(q: Query) -> Trace { return cone_march(q, hf_params.max_iter); }
