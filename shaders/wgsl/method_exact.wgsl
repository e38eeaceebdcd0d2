// HF_METHOD_EXACT: hf_trace is dda::trace on the surface `hf_surface`.
override hf_surface: u32 = 0u;

fn hf_trace(q: Query) -> Trace { return dda_trace(hf_surface, q); }
