//! The one error type of the core: which parameter is invalid, and why.

use core::fmt;

/// Why a parameter was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Reason {
    /// NaN or infinite where a finite number is needed.
    NotFinite,
    /// Must be strictly greater than zero.
    NotPositive,
    /// Must be zero or greater.
    Negative,
    /// Must be a whole multiple of the plant step `dt`.
    NotMultipleOfDt,
    /// NaN (infinity is allowed for this parameter).
    NaN,
    /// Outside the range the parameter's doc gives (the message says which).
    OutOfRange(&'static str),
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::NotFinite => f.write_str("must be a finite number"),
            Reason::NotPositive => f.write_str("must be > 0"),
            Reason::Negative => f.write_str("must be >= 0"),
            Reason::NotMultipleOfDt => f.write_str("must be a whole multiple of the plant step dt"),
            Reason::NaN => f.write_str("must not be NaN"),
            Reason::OutOfRange(why) => f.write_str(why),
        }
    }
}

/// An invalid parameter: the field (the core's own name, e.g. `mass`, `goal.x`,
/// `control_dt`), the reason and the offending value. `Copy` and alloc-free, so firmware
/// can use it too. Whoever knows where the value came from (a scenario file, a C struct)
/// adds the path: `robot.mass`, `run[2].goal.x`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ParamError {
    /// The field of the struct or argument that was checked, e.g. `"wheel_radius"`.
    pub field: &'static str,
    /// Why it was rejected.
    pub reason: Reason,
    /// The rejected value, widened to f64.
    pub value: f64,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {} (got ", self.field, self.reason)?;
        // Bounded width: exponent form when very large or small (`1e300`, not 301 digits).
        let a = self.value.abs();
        if self.value == 0.0 || !self.value.is_finite() || (1e-5..1e16).contains(&a) {
            write!(f, "{})", self.value)
        } else {
            write!(f, "{:e})", self.value)
        }
    }
}

impl core::error::Error for ParamError {}

/// Validation helpers shared by every parameter struct; each names the field it checks.
pub(crate) mod check {
    use super::{ParamError, Reason};
    use crate::Real;

    fn err<T: Real>(field: &'static str, reason: Reason, v: T) -> ParamError {
        ParamError { field, reason, value: v.to_f64_lossless() }
    }

    /// Finite and > 0.
    pub fn positive<T: Real>(field: &'static str, v: T) -> Result<T, ParamError> {
        if !v.is_finite() {
            Err(err(field, Reason::NotFinite, v))
        } else if v <= T::zero() {
            Err(err(field, Reason::NotPositive, v))
        } else {
            Ok(v)
        }
    }

    /// Finite and >= 0.
    pub fn non_negative<T: Real>(field: &'static str, v: T) -> Result<T, ParamError> {
        if !v.is_finite() {
            Err(err(field, Reason::NotFinite, v))
        } else if v < T::zero() {
            Err(err(field, Reason::Negative, v))
        } else {
            Ok(v)
        }
    }

    /// Finite, any sign.
    pub fn finite<T: Real>(field: &'static str, v: T) -> Result<T, ParamError> {
        if v.is_finite() { Ok(v) } else { Err(err(field, Reason::NotFinite, v)) }
    }

    /// > 0, +infinity allowed (a limit that may be switched off).
    pub fn positive_or_inf<T: Real>(field: &'static str, v: T) -> Result<T, ParamError> {
        if v.is_nan() {
            Err(err(field, Reason::NaN, v))
        } else if v <= T::zero() {
            Err(err(field, Reason::NotPositive, v))
        } else {
            Ok(v)
        }
    }

    /// A failed range check with its own explanation.
    pub fn out_of_range<T: Real>(field: &'static str, why: &'static str, v: T) -> ParamError {
        err(field, Reason::OutOfRange(why), v)
    }

    /// How many `dt` fit in `period`, if it is a whole multiple (relative tolerance 1e-9).
    pub fn whole_multiple<T: Real>(field: &'static str, period: T, dt: T) -> Result<u32, ParamError> {
        let ratio = (period / dt).round();
        let tol = T::lit(1e-9) * period.abs().max(T::min_positive_value());
        if ratio.is_nan() || ratio < T::one() || (ratio * dt - period).abs() > tol || ratio > T::lit(u32::MAX as f64) {
            return Err(err(field, Reason::NotMultipleOfDt, period));
        }
        ratio.to_u32().ok_or_else(|| err(field, Reason::NotMultipleOfDt, period))
    }
}
