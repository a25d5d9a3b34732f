//! Per-wheel speed saturation that keeps the curvature: both wheels scaled by one factor.
//!
//! Clipping each wheel on its own changes the ratio omega_r / omega_l and so the path's
//! curvature kappa = omega / v; instead, when the faster wheel exceeds the limit, both
//! wheel speeds are multiplied by the same factor:
//!
//! ```text
//! m = max(|omega_r|, |omega_l|)                       rad/s
//! s = 1 if m <= omega_max, else omega_max / m         (0 < s <= 1)
//! (omega_r, omega_l) <- s (omega_r, omega_l)
//! ```
//!
//! Since v = r (omega_r + omega_l) / 2 and omega = r (omega_r - omega_l) / (2 R) are
//! linear in the wheel speeds, (v, omega) are scaled by the same s, so omega / v (and the
//! sign of each) is unchanged: the robot follows the same path, only slower. The limit
//! `omega_max` is the scenario key `controller.wheel_speed_max` (rad/s at the wheel;
//! infinity turns it off, and then every value passes through bit for bit).
//!
//! For laws that command (v, omega) ([`super::PolarLaw`], [`super::LyapunovLaw`]) it
//! limits the wheel speed references. The paper's law commands wheel *angles*; for it,
//! [`WheelRateLimiter`] limits the speed at which the angle references move. Both are
//! applied by [`super::WheelStage`].

use crate::Real;
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use crate::math::Wheels;

/// Validates a wheel speed limit (rad/s): > 0, infinity allowed (off), not NaN.
pub(crate) fn check_wheel_speed_max<T: Real>(w_max: T) -> Result<T, ParamError> {
    check::positive_or_inf("wheel_speed_max", w_max)
}

/// The common factor s in (0, 1] that brings max(|w.right|, |w.left|) down to `w_max`
/// (rad/s); 1 when already within the limit or when the limit is infinite.
#[cfg_attr(target_os = "none", inline)]
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn wheel_speed_scale<L: Lane>(w: Wheels<L>, w_max: L) -> L {
    let m = w.right.abs().max(w.left.abs());
    L::select(w_max.lt(m), w_max / m, L::lit(1.0))
}

/// Wheel speeds (rad/s) scaled together so that neither exceeds `w_max` (rad/s); the
/// ratio between them, hence the curvature, is kept. Unchanged when within the limit.
#[cfg_attr(target_os = "none", inline)]
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn limit_wheel_speeds<L: Lane>(w: Wheels<L>, w_max: L) -> Wheels<L> {
    limit_wheel_speeds_masked(w, w_max).0
}

/// [`limit_wheel_speeds`] and where it scaled (the wheel stage's saturation signal).
#[inline(always)]
pub(crate) fn limit_wheel_speeds_masked<L: Lane>(w: Wheels<L>, w_max: L) -> (Wheels<L>, L::Mask) {
    let s = wheel_speed_scale(w, w_max);
    let scaled = s.lt(L::lit(1.0));
    (Wheels::new(L::select(scaled, w.right * s, w.right), L::select(scaled, w.left * s, w.left)), scaled)
}

/// Rate limiter for a pair of wheel angle references (rad): each control tick the
/// limited references move towards the targets by at most `w_max * dt` on the faster
/// wheel, both increments scaled by one factor (so the ratio of the increments, the
/// curvature of the commanded motion, is kept).
///
/// ```text
/// delta = target - phi_lim;  s = scale(delta / dt, w_max);  phi_lim <- phi_lim + s delta
/// ```
///
/// It starts from the measured wheel angles at the first tick after construction or
/// reset, so a step in the target (the paper law's first tick) is spread over time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelRateLimiter<T: Lane> {
    w_max: T::Scalar,
    dt: T::Scalar,
    /// The limited references of the last tick, rad, where `started`.
    phi_lim: Wheels<T>,
    started: T::Mask,
    /// Where the last tick held the references back from their targets.
    pub(crate) limited: T::Mask,
}

impl<T: Lane> WheelRateLimiter<T> {
    /// A limiter for speed `w_max` (rad/s, > 0, infinity allowed) and tick `dt` (s, > 0).
    pub fn new(w_max: T::Scalar, dt: T::Scalar) -> Result<Self, ParamError> {
        check_wheel_speed_max(w_max)?;
        check::positive("control_dt", dt)?;
        let no = T::Mask::splat(false);
        Ok(Self { w_max, dt, phi_lim: Wheels::default(), started: no, limited: no })
    }

    /// The speed limit, rad/s.
    pub fn w_max(&self) -> T::Scalar {
        self.w_max
    }

    /// The limited references (rad) for this tick, given the targets (rad) and the
    /// measured wheel angles (rad, used only on the first tick).
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn limit(&mut self, target: Wheels<T>, measured: Wheels<T>) -> Wheels<T> {
        let prev = Wheels::new(
            T::select(self.started, self.phi_lim.right, measured.right),
            T::select(self.started, self.phi_lim.left, measured.left),
        );
        let delta = Wheels::new(target.right - prev.right, target.left - prev.left);
        let dt = T::splat(self.dt);
        let rate = delta.map(|d| d / dt);
        let s = wheel_speed_scale(rate, T::splat(self.w_max));
        // Within the limit: take the target exactly (no rounding drift).
        let limited = s.lt(T::lit(1.0));
        let next = Wheels::new(
            T::select(limited, prev.right + delta.right * s, target.right),
            T::select(limited, prev.left + delta.left * s, target.left),
        );
        self.phi_lim = next;
        self.started = T::Mask::splat(true);
        self.limited = limited;
        next
    }

    /// Forgets the limited references: the next tick starts from the measured angles.
    pub fn reset(&mut self) {
        self.reset_lanes(T::Mask::splat(true));
    }

    /// [`WheelRateLimiter::reset`] of the runs in `lanes` only.
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.started = self.started & !lanes;
        self.limited = self.limited & !lanes;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_keeps_ratio_and_limit() {
        let w = limit_wheel_speeds(Wheels::new(30.0_f64, -10.0), 15.0);
        assert_eq!(w, Wheels::new(15.0, -5.0));
        let w = limit_wheel_speeds(Wheels::new(3.0_f64, -1.0), f64::INFINITY);
        assert_eq!(w, Wheels::new(3.0, -1.0));
    }

    #[test]
    fn rate_limiter_steps() {
        let mut l = WheelRateLimiter::new(10.0_f64, 0.1).unwrap();
        let z = Wheels::new(0.0, 0.0);
        // Target (4, 2): the right wheel may move 1 rad per tick, the left half of that.
        let a = l.limit(Wheels::new(4.0, 2.0), z);
        assert!((a.right - 1.0).abs() < 1e-15 && (a.left - 0.5).abs() < 1e-15);
        for _ in 0..3 {
            l.limit(Wheels::new(4.0, 2.0), z);
        }
        assert_eq!(l.limit(Wheels::new(4.0, 2.0), z), Wheels::new(4.0, 2.0));
    }
}
