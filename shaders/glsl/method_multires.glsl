// HF_METHOD_MULTIRES: hf_trace is multires::trace.
uniform uint hf_surface;
uniform uint hf_multires_range;

Trace hf_trace(Query q) { return multires_trace(hf_surface, q, hf_multires_range); }
