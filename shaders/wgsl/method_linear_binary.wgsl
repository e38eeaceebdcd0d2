// HF_METHOD_LINEAR_BINARY: hf_trace is search::linear with Refine::Binary.
override hf_surface: u32 = 0u;

struct LinearBinaryParams {
    linear_steps: u32,
    binary_steps: u32,
}

@group(0) @binding(2) var<uniform> hf_params: LinearBinaryParams;

fn hf_trace(q: Query) -> Trace {
    return search_linear_binary(hf_surface, q, hf_params.linear_steps, hf_params.binary_steps);
}
