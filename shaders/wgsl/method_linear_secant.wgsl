// HF_METHOD_LINEAR_SECANT: hf_trace is search::linear with Refine::Secant.
override hf_surface: u32 = 0u;

struct LinearSecantParams {
    linear_steps: u32,
}

@group(0) @binding(2) var<uniform> hf_params: LinearSecantParams;

fn hf_trace(q: Query) -> Trace { return search_linear_secant(hf_surface, q, hf_params.linear_steps); }
