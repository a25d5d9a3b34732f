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
}

impl Real for f32 {
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
    fn lit(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64_lossless(self) -> f64 {
        self
    }
}
