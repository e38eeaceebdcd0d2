// Generated from shaders/wgsl/math.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/math.rs for f32: the `Real` helpers the marches use. Min and max
// keep Rust's argument order (`a.min(b)` is `real_min(a, b)`), so ties and signed
// zeros resolve as on the CPU; lerp is written out, never `mix`.

// A run-time value: a WGSL const-expression may not be infinite.
float real_infinity() {
    uint bits = 0x7F800000u;
    return uintBitsToFloat(bits);
}

const float REAL_EPSILON = 1.1920929e-07;

// WGSL has no isinf / isnan (and lets compilers assume finite comparisons): the
// exponent bits decide.
bool real_is_finite(float v) { return (floatBitsToUint(v) & 0x7F800000u) != 0x7F800000u; }

// `Real::min`: returns `a` when `b` is NaN.
float real_min(float a, float b) { return ((b < a) ? (b) : (a)); }

// `Real::max`: returns `a` when `b` is NaN.
float real_max(float a, float b) { return ((b > a) ? (b) : (a)); }

// `Real::clamp_to`.
float real_clamp_to(float x, float lo, float hi) { return real_min(real_max(x, lo), hi); }

// `Real::lerp`: `a (1 - f) + b f`, exact at f = 0 and f = 1.
float real_lerp(float a, float b, float f) { return a * (1.0 - f) + b * f; }

// `math::normal_from_gradient`: unit normal `(-gx, -gy, 1) / |...|`.
vec3 math_normal_from_gradient(float gx, float gy) {
    float len = sqrt(gx * gx + gy * gy + 1.0);
    return vec3(-gx / len, -gy / len, 1.0 / len);
}
