//! The effects a real sensor has, one stage per file, in the order a measurement passes
//! through them at each control tick:
//!
//! 1. [`sampling`]: a pose sample is taken at its own rate (`rate_hz`, or `fix_rate_hz`
//!    for odometry's fixes);
//! 2. [`noise`]: Gaussian noise on x, y and theta of that sample (`position_noise`,
//!    `heading_noise_deg`; drawn in this order, so a seed gives the same numbers in every
//!    build);
//! 3. [`latency`]: the sample reaches the controller `latency` later (a fixed ring of
//!    samples in flight; odometry keeps a second one for the pose each fix was taken at);
//! 4. [`encoders`]: the wheel angles, quantized to whole counts (`encoder_counts`), and
//!    the speeds differenced from them.
//!
//! [`super::PoseSensor`] chains them; [`super::OdometrySensor`] adds dead reckoning and
//! the EKF on top. A new effect is a file here, its keys in [`super::SensorParams`]
//! and one line where the sensor chains the stages (CONTRIBUTING.md).

pub mod encoders;
pub mod latency;
pub mod noise;
pub mod sampling;

pub use encoders::Encoders;
pub use latency::DelayLine;
pub use noise::PoseNoise;
pub use sampling::Sampling;

use crate::Real;
use crate::error::ParamError;

/// Control ticks in `period` (s) at control period `dt` (s), both as written in `T` and
/// widened to f64: the whole number n >= 1 with |n dt - period| <= tol period, where tol
/// is 1e-9 or, in a precision coarser than that, 4 epsilons of `T`. In f32, 1 / 50 Hz
/// (0.0199999995...) is 20 ticks of 1 ms (0.00100000005...) although the two differ by
/// 2 parts in 1e8: each was rounded once to f32 where it was written, and the f64 check's
/// 1e-9 would refuse what f64 accepts. In f64 the tolerance is 1e-9,
/// the same as `ClosedLoop`'s check of control_dt against dt.
pub(crate) fn ticks_in<T: Real>(field: &'static str, period: f64, dt: f64) -> Result<u64, ParamError> {
    use num_traits::{Float, ToPrimitive as _};
    // Float's methods by name: no_std has no inherent f64::round.
    let ratio = Float::round(period / dt);
    let tol = 1e-9f64.max(4.0 * T::epsilon().to_f64_lossless()) * Float::abs(period).max(f64::MIN_POSITIVE);
    let refused = ParamError { field, reason: crate::Reason::NotMultipleOfDt, value: period };
    if ratio.is_nan() || ratio < 1.0 || Float::abs(ratio * dt - period) > tol || ratio > f64::from(u32::MAX) {
        return Err(refused);
    }
    ratio.to_u64().ok_or(refused)
}
