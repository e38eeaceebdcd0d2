// HF_METHOD_MAXMIP: hf_trace is maxmip::trace with exact options.
uniform uint hf_surface;

Trace hf_trace(Query q) { return maxmip_trace(hf_surface, q); }
