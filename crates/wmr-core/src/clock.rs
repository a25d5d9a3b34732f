//! The one clock of a run: the time of plant step i is `i * dt`, counted, never summed,
//! so it does not drift. [`crate::ClosedLoop`], the lanes ([`crate::batch`]) and every
//! shell that steps a controller on its own (the Python controllers, at `control_dt`)
//! read time from it, so a law that reads `t` sees the same bits everywhere.

use crate::Real;
use crate::lane::{Lane, Lanes};

/// The time of step i, s: `i * dt`, exact for a short decimal `dt` in `f64` (see
/// [`crate::ClosedLoop::time`]).
#[derive(Clone, Copy, Debug)]
pub struct StepClock<T> {
    /// Plant step, s.
    pub dt: T,
    /// `dt` as an exact decimal `m / scale` (1 ms: m = 1, scale = 1e3), when it is one.
    decimal_dt: Option<(u64, f64)>,
}

impl<T: Real> StepClock<T> {
    /// The clock of steps of `dt` (s).
    pub fn new(dt: T) -> Self {
        Self { dt, decimal_dt: decimal(dt) }
    }

    /// The time of step `i`, s.
    #[inline(always)]
    pub fn time(&self, i: u64) -> T {
        match self.decimal_dt {
            // i * m < 2^53 is exact in f64, so one rounding: the division.
            Some((m, scale)) if i < (1u64 << 53) / m => T::lit((i * m) as f64 / scale),
            _ => T::lit(i as f64) * self.dt,
        }
    }
}

impl StepClock<f64> {
    /// [`StepClock::time`] of every lane's step, each given as a whole `f64` (exact below
    /// 2^53): the same operations on the same numbers, so the same bits, without a
    /// per-lane integer conversion.
    #[inline(always)]
    pub fn time_lanes<const N: usize>(&self, i: Lanes<N>) -> Lanes<N> {
        let plain = i * Lanes::splat(self.dt);
        match self.decimal_dt {
            Some((m, scale)) => {
                let decimal = i * Lanes::splat(m as f64) / Lanes::splat(scale);
                Lanes::select(i.lt(Lanes::splat(((1u64 << 53) / m) as f64)), decimal, plain)
            }
            None => plain,
        }
    }
}

/// `dt` as `m / 10^k` with a whole `m` of at most 1e6 and k <= 12, when that quotient,
/// rounded to `T`, is `dt` itself (1e-3 -> (1, 1e3); 2.5e-4 -> (25, 1e5)). Only for
/// `f64`: in `f32` (firmware) the time stays the plain product `steps * dt`, the formula
/// f32 traces replay tick for tick.
fn decimal<T: Real>(dt: T) -> Option<(u64, f64)> {
    // T is f64 exactly when it holds 0.1 as f64 does.
    if T::lit(0.1).to_f64_lossless() != 0.1 {
        return None;
    }
    let dt64 = dt.to_f64_lossless();
    let mut scale = 1.0_f64;
    for _ in 0..=12 {
        let m = num_traits::Float::round(dt64 * scale);
        if (1.0..=1e6).contains(&m) && <T as Real>::lit(m / scale) == dt {
            return Some((m as u64, scale));
        }
        scale *= 10.0;
    }
    None
}
