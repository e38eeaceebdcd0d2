// HF_METHOD_EXACT: hf_trace is dda::trace on the surface `hf_surface`.
uniform uint hf_surface;

Trace hf_trace(Query q) { return dda_trace(hf_surface, q); }
