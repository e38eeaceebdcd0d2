// HF_METHOD_LINEAR_SECANT: hf_trace is search::linear_secant.
uniform uint hf_surface;
uniform uint hf_linear_steps;

Trace hf_trace(Query q) { return search_linear_secant(hf_surface, q, hf_linear_steps); }
