// HF_METHOD_MAXMIP: hf_trace is maxmip::trace with exact options.
override hf_surface: u32 = 0u;

fn hf_trace(q: Query) -> Trace { return maxmip_trace(hf_surface, q); }
