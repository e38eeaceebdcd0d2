// HF_METHOD_CONE: hf_trace is cone::trace, at most `hf_params.max_iter` iterations.

struct ConeParams {
    max_iter: u32,
}

@group(0) @binding(2) var<uniform> hf_params: ConeParams;

// The closure of `cone::trace_steps`: one fetch of the cell's texel, then `cone_step`.
fn cone_march_step(cell: vec2<u32>, p: vec3<f32>, d: vec3<f32>, dt: ptr<function, f32>,
                   fetches: ptr<function, u32>) -> i32 {
    let tex: vec2<f32> = cone_texel(cell[0], cell[1]);
    *fetches = 1u;
    return cone_cone_step(p, d, tex[0], tex[1], dt);
}

fn hf_trace(q: Query) -> Trace { return cone_march(q, hf_params.max_iter); }
