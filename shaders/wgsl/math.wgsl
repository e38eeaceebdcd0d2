// Mirror of core/src/math.rs for f32: the `Real` helpers the marches use. Min and max
// keep Rust's argument order (`a.min(b)` is `real_min(a, b)`), so ties and signed
// zeros resolve as on the CPU; lerp is written out, never `mix`.

// A run-time value: a WGSL const-expression may not be infinite.
fn real_infinity() -> f32 {
    var bits: u32 = 0x7F800000u;
    return bitcast<f32>(bits);
}

const REAL_EPSILON: f32 = 1.1920929e-07;

// WGSL has no isinf / isnan (and lets compilers assume finite comparisons): the
// exponent bits decide.
fn real_is_finite(v: f32) -> bool { return (bitcast<u32>(v) & 0x7F800000u) != 0x7F800000u; }

// `Real::min`: returns `a` when `b` is NaN.
fn real_min(a: f32, b: f32) -> f32 { return select(a, b, b < a); }

// `Real::max`: returns `a` when `b` is NaN.
fn real_max(a: f32, b: f32) -> f32 { return select(a, b, b > a); }

// `Real::clamp_to`.
fn real_clamp_to(x: f32, lo: f32, hi: f32) -> f32 { return real_min(real_max(x, lo), hi); }

// `Real::lerp`: `a (1 - f) + b f`, exact at f = 0 and f = 1.
fn real_lerp(a: f32, b: f32, f: f32) -> f32 { return a * (1.0 - f) + b * f; }

// `math::normal_from_gradient`: unit normal `(-gx, -gy, 1) / |...|`.
fn math_normal_from_gradient(gx: f32, gy: f32) -> vec3<f32> {
    let len: f32 = sqrt(gx * gx + gy * gy + 1.0);
    return vec3<f32>(-gx / len, -gy / len, 1.0 / len);
}
