// HF_METHOD_LINEAR_BINARY: hf_trace is search::linear_binary.
uniform uint hf_surface;
uniform uint hf_linear_steps;
uniform uint hf_binary_steps;

Trace hf_trace(Query q) { return search_linear_binary(hf_surface, q, hf_linear_steps, hf_binary_steps); }
