//! The float trait every model is generic over, implemented for `f32` and `f64` only.

use core::fmt::{Debug, Display};
use num_traits::{Float, FloatConst};

/// A real number type usable by every wmr model: `f32` (firmware) or `f64` (analysis).
///
/// Built on [`num_traits::Float`] with `libm`, so it works without `std`.
pub trait Real: Float + FloatConst + Debug + Display + Default + Send + Sync + 'static {
    /// Converts an `f64` constant (a default, a literal in an equation) to this type.
    ///
    /// The only place where precision is chosen; `f64 -> f32` rounds to nearest.
    fn lit(x: f64) -> Self;

    /// Widens to `f64` for reporting (error messages, logs).
    fn to_f64_lossless(self) -> f64;

    // Transcendentals, always from the `libm` crate. Why not `Float::sin` & co.: num-traits
    // switches them to the platform's math library when any crate in the build turns on
    // its `std` feature (numpy and approx do), so the same run would differ in the last
    // bits between the CLI, the Python wheel and the firmware. These give one answer
    // everywhere. (sqrt, floor, abs, min, max are exact, so `Float`'s are fine.)

    /// (sin, cos) of an angle in rad.
    fn sin_cos_libm(self) -> (Self, Self);
    /// cos of an angle in rad.
    fn cos_libm(self) -> Self;
    /// atan2(self, x): the angle of (x, self) in (-pi, pi], rad.
    fn atan2_libm(self, x: Self) -> Self;
    /// sqrt(self^2 + y^2) without overflow.
    fn hypot_libm(self, y: Self) -> Self;
    /// Hyperbolic tangent.
    fn tanh_libm(self) -> Self;
    /// self^y.
    fn powf_libm(self, y: Self) -> Self;
    /// e^self (MPPI's softmax weights).
    fn exp_libm(self) -> Self;
}

impl Real for f32 {
    #[inline(always)]
    fn sin_cos_libm(self) -> (Self, Self) {
        libm::sincosf(self)
    }
    #[inline(always)]
    fn cos_libm(self) -> Self {
        libm::cosf(self)
    }
    #[inline(always)]
    fn atan2_libm(self, x: Self) -> Self {
        libm::atan2f(self, x)
    }
    #[inline(always)]
    fn hypot_libm(self, y: Self) -> Self {
        libm::hypotf(self, y)
    }
    #[inline(always)]
    fn tanh_libm(self) -> Self {
        libm::tanhf(self)
    }
    #[inline(always)]
    fn powf_libm(self, y: Self) -> Self {
        libm::powf(self, y)
    }
    #[inline(always)]
    fn exp_libm(self) -> Self {
        libm::expf(self)
    }
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64_lossless(self) -> f64 {
        f64::from(self)
    }
}

impl Real for f64 {
    #[inline(always)]
    fn sin_cos_libm(self) -> (Self, Self) {
        libm::sincos(self)
    }
    #[inline(always)]
    fn cos_libm(self) -> Self {
        libm::cos(self)
    }
    #[inline(always)]
    fn atan2_libm(self, x: Self) -> Self {
        libm::atan2(self, x)
    }
    #[inline(always)]
    fn hypot_libm(self, y: Self) -> Self {
        libm::hypot(self, y)
    }
    #[inline(always)]
    fn tanh_libm(self) -> Self {
        libm::tanh(self)
    }
    #[inline(always)]
    fn powf_libm(self, y: Self) -> Self {
        libm::pow(self, y)
    }
    #[inline(always)]
    fn exp_libm(self) -> Self {
        libm::exp(self)
    }
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64_lossless(self) -> f64 {
        self
    }
}
