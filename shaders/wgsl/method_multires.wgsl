// HF_METHOD_MULTIRES: hf_trace is multires::trace on the surface `hf_surface` with the
// one-texel distance `hf_params.range` (grid units: 1 / the pixel angle).
override hf_surface: u32 = 0u;

struct MultiresParams {
    range: u32,
}

@group(0) @binding(2) var<uniform> hf_params: MultiresParams;

fn hf_trace(q: Query) -> Trace { return multires_trace(hf_surface, q, hf_params.range); }
