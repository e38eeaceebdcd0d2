// HF_METHOD_RELAXED: hf_trace is relaxed::trace with `hf_cone_steps` cone steps and
// `hf_binary_steps` bisections.
uniform uint hf_cone_steps;
uniform uint hf_binary_steps;

Trace hf_trace(Query q) { return relaxed_trace(q, hf_cone_steps, hf_binary_steps); }
