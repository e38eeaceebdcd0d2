//! The one math shim: the scalar trait that lets every march run in `f32` (the fast
//! path, what shaders do) and in `f64` (the test oracle) from one source, with `libm`
//! supplying the functions `core` lacks.

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A floating-point scalar: `f32` or `f64`.
///
/// `V3` is the matching glam vector (`Vec3` or `DVec3`) used in public types.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Default
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + 'static
{
    /// The glam 3-vector of this precision.
    type V3: Copy + Debug + PartialEq + Default;
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 0.5.
    const HALF: Self;
    /// +∞.
    const INFINITY: Self;
    /// Machine epsilon.
    const EPSILON: Self;
    /// The largest finite value.
    const MAX: Self;

    /// Converts (exactly) from `f32`.
    fn from_f32(v: f32) -> Self;
    /// Converts from `f64` (rounding to nearest for `f32`).
    fn from_f64(v: f64) -> Self;
    /// Converts to `f64` (exact).
    fn to_f64(self) -> f64;
    /// Converts to `f32` (rounding to nearest for `f64`).
    fn to_f32(self) -> f32;
    /// Converts a grid index; exact for indices below 2²⁴.
    fn from_u32(v: u32) -> Self;
    /// Largest integer not above `self`.
    fn floor(self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// `true` unless NaN or infinite.
    fn is_finite(self) -> bool;

    /// Builds a glam vector.
    fn v3(v: [Self; 3]) -> Self::V3;
    /// Reads a glam vector.
    fn xyz(v: Self::V3) -> [Self; 3];

    /// Absolute value: the sign bit cleared (`−0.0` gives `+0.0`).
    fn abs(self) -> Self;
    /// Minimum; returns `self` when `other` is NaN.
    #[inline]
    fn min(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
    /// Maximum; returns `self` when `other` is NaN.
    #[inline]
    fn max(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    /// Clamps into `[lo, hi]`.
    #[inline]
    fn clamp_to(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
    /// `a (1 − f) + b f`: exact at f = 0 and f = 1.
    #[inline]
    fn lerp(a: Self, b: Self, f: Self) -> Self {
        a * (Self::ONE - f) + b * f
    }
}

macro_rules! impl_real {
    ($t:ty, $v3:ty, $int:ty, $sqrt:path) => {
        impl Real for $t {
            type V3 = $v3;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const HALF: Self = 0.5;
            const INFINITY: Self = <$t>::INFINITY;
            const EPSILON: Self = <$t>::EPSILON;
            const MAX: Self = <$t>::MAX;
            #[inline]
            fn from_f32(v: f32) -> Self {
                v as $t
            }
            #[inline]
            fn from_f64(v: f64) -> Self {
                v as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn to_f32(self) -> f32 {
                self as f32
            }
            #[inline]
            fn from_u32(v: u32) -> Self {
                v as $t
            }
            /// By truncation through an integer, without a call into `libm`; the
            /// same value as `libm`'s floor for every input: at and beyond
            /// `2^(mantissa bits)` every value is integral (returned as is, as are
            /// NaN and ±∞), below it truncation is exact; integral values (`−0.0`
            /// included) come back unchanged, negative others one lower.
            #[inline]
            fn floor(self) -> Self {
                const INTEGRAL: $t = (1u64 << (<$t>::MANTISSA_DIGITS - 1)) as $t;
                // NaN and ±∞ fail the test too.
                let small = self.abs() < INTEGRAL;
                if !small {
                    return self;
                }
                let t = self as $int as $t;
                if t == self {
                    self
                } else if self < 0.0 {
                    t - 1.0
                } else {
                    t
                }
            }
            #[inline]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            /// One mask of the bits (a compare and a negation cost several
            /// instructions, and `abs` is on every centerline of the march).
            #[inline]
            fn abs(self) -> Self {
                <$t>::from_bits(self.to_bits() & (!0 >> 1))
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline]
            fn v3(v: [Self; 3]) -> Self::V3 {
                <$v3>::new(v[0], v[1], v[2])
            }
            #[inline]
            fn xyz(v: Self::V3) -> [Self; 3] {
                [v.x, v.y, v.z]
            }
        }
    };
}

impl_real!(f32, glam::Vec3, i32, libm::sqrtf);
impl_real!(f64, glam::DVec3, i64, libm::sqrt);

/// Unit normal of the height function with gradient `(gx, gy)`: `(−gx, −gy, 1) / |…|`.
#[inline]
pub fn normal_from_gradient<R: Real>(gx: R, gy: R) -> [R; 3] {
    let len = (gx * gx + gy * gy + R::ONE).sqrt();
    [-gx / len, -gy / len, R::ONE / len]
}

/// `a − b` of two `f64` points (the geometry of cameras and meshes is `f64`).
#[inline]
pub fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · b` of two `f64` vectors.
#[inline]
pub fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b` of two `f64` vectors.
#[inline]
pub fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::Real;

    /// The shim's floor equals `libm`'s bit for bit: edge values and a sweep of bit
    /// patterns (every exponent, both signs, NaN and infinities included).
    #[test]
    fn floor_is_libm_floor() {
        let edges: [f32; 10] = [
            0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 1.5, -1.5, 8388607.5, -8388607.5,
        ];
        for v in edges {
            assert_eq!(
                <f32 as Real>::floor(v).to_bits(),
                libm::floorf(v).to_bits(),
                "{v}"
            );
            let d = f64::from(v);
            assert_eq!(
                <f64 as Real>::floor(d).to_bits(),
                libm::floor(d).to_bits(),
                "{d}"
            );
        }
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..2_000_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let f = f32::from_bits(x as u32);
            let a = Real::floor(f);
            let b = libm::floorf(f);
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{f:e}"
            );
            let d = f64::from_bits(x);
            let (a, b) = (Real::floor(d), libm::floor(d));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{d:e}"
            );
        }
    }
}
