// HF_METHOD_RELAXED: hf_trace is relaxed::trace with `hf_params.cone_steps` cone steps
// and `hf_params.binary_steps` bisections.

struct RelaxedParams {
    cone_steps: u32,
    binary_steps: u32,
}

@group(0) @binding(2) var<uniform> hf_params: RelaxedParams;

fn hf_trace(q: Query) -> Trace { return relaxed_trace(q, hf_params.cone_steps, hf_params.binary_steps); }
