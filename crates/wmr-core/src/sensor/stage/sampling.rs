//! When a pose sample is taken: at every control tick k that is a whole multiple of
//! P / dt_c, where P = 1 / `rate_hz` is the sample period; sample j is taken at j P.

use super::ticks_in;
use crate::Real;
use crate::error::{ParamError, check};

/// The sample clock of a sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling<T> {
    /// Control ticks per sample, P / dt_c (>= 1; at most u32::MAX, as `ticks_in` checks:
    /// stored in 32 bits, the C API's storage holds the sensor).
    ticks_per_sample: u32,
    /// The sample period P, s.
    period: T,
}

impl<T: Real> Sampling<T> {
    /// The clock of `rate_hz` samples per second (inf: every tick) at control period
    /// `control_dt` (s, > 0, checked by the caller). Errors name `rate_hz`: not > 0, or
    /// 1 / rate_hz not a whole multiple of control_dt.
    pub fn new(rate_hz: T, control_dt: T) -> Result<Self, ParamError> {
        if rate_hz.is_nan() || rate_hz <= T::zero() {
            return Err(check::out_of_range("rate_hz", "must be > 0 (inf: every control tick)", rate_hz));
        }
        let ticks_per_sample: u64 = if rate_hz.is_infinite() {
            1
        } else {
            ticks_in::<T>("rate_hz", 1.0 / rate_hz.to_f64_lossless(), control_dt.to_f64_lossless()).map_err(|e| {
                ParamError {
                    reason: crate::Reason::OutOfRange("1 / rate_hz must be a whole multiple of control_dt"),
                    ..e
                }
            })?
        };
        let period = T::lit(ticks_per_sample as f64) * control_dt;
        let ticks_per_sample = u32::try_from(ticks_per_sample).map_err(|_| ParamError {
            field: "rate_hz",
            reason: crate::Reason::NotMultipleOfDt,
            value: rate_hz.to_f64_lossless(),
        })?;
        Ok(Self { ticks_per_sample, period })
    }

    /// Control ticks per sample, P / dt_c (>= 1): sample j is taken at tick j times this.
    pub fn ticks_per_sample(&self) -> u64 {
        u64::from(self.ticks_per_sample)
    }

    /// The index j of the sample taken at control tick `tick`, if one is.
    #[inline]
    pub fn sample_at(&self, tick: u64) -> Option<u64> {
        // ticks_per_sample >= 1 by construction; checked_div leaves no division-by-zero
        // panic path on a Cortex-M (firmware/check).
        let tps = self.ticks_per_sample();
        if tick.is_multiple_of(tps) { tick.checked_div(tps) } else { None }
    }

    /// When sample `j` was taken, j P, s.
    #[inline]
    pub fn time_of(&self, j: u64) -> T {
        T::lit(j as f64) * self.period
    }
}
