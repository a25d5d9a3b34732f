//! A figure-eight (a Lissajous curve 1:2), all derivatives analytic. With a = 2 pi / period:
//!
//! ```text
//! x = cx + (width/2) sin(a t)        x'  = (width/2) a cos(a t)     x''  = -(width/2) a^2 sin(a t)
//! y = cy + (height/2) sin(2 a t)     y'  = height a cos(2 a t)      y''  = -2 height a^2 sin(2 a t)
//!                                    x''' = -(width/2) a^3 cos(a t)   y''' = -4 height a^3 cos(2 a t)
//! theta_ref = atan2(y', x'),  v_ref = hypot(x', y'),  v_ref' = (x' x'' + y' y'') / v_ref
//! omega_ref = (x' y'' - y' x'') / v^2
//! omega_ref' = (x' y''' - y' x''') / v^2 - 2 (x' y'' - y' x'') (x' x'' + y' y'') / v^4
//! ```
//!
//! v never vanishes (where x' = 0, |y'| = height a), so theta_ref is defined everywhere;
//! it is atan2's value, in (-pi, pi]. The path parameter ([`super::Path`]) is the time, s.

use super::config::{Configured, config_by_words};
use super::path::Path;
use super::state::{Reference, ReferenceState};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2};

crate::params! {
    words;
    /// What builds a [`FigureEight`] ([`FigureEight::new`], the trace's words).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct FigureEightParams<T> {
        /// Center, world frame.
        pub center_x: T [unit = "m", rule = "finite"],
        /// Center, world frame.
        pub center_y: T [unit = "m", rule = "finite"],
        /// Extent along x.
        pub width: T [unit = "m", rule = "> 0"],
        /// Extent along y.
        pub height: T [unit = "m", rule = "> 0"],
        /// Time for one figure.
        pub period: T [unit = "s", rule = "> 0"],
    }
}

config_by_words!(FigureEightParams => FigureEight, |c| FigureEight::new(c.center_x, c.center_y, c.width, c.height, c.period));

impl<T: Real> Configured<T> for FigureEight<T> {
    type Config = FigureEightParams<T>;

    fn config(&self) -> Result<Self::Config, ParamError> {
        let (center_x, center_y, width, height, period) =
            (self.center_x, self.center_y, self.width, self.height, self.period);
        Ok(FigureEightParams { center_x, center_y, width, height, period })
    }
}

/// `[reference] kind = "figure_eight"`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FigureEight<T> {
    /// Center, world frame, m.
    pub center_x: T,
    /// Center, world frame, m.
    pub center_y: T,
    /// Extent along x, m.
    pub width: T,
    /// Extent along y, m.
    pub height: T,
    /// Time for one figure, s.
    pub period: T,
    /// Bounds of |d(x, y)/dt| over a period, m/s (found at construction).
    rate: (T, T),
}

/// Derivatives of (x, y) at t: first, second and third.
struct Derivs<T> {
    p: (T, T),
    d1: (T, T),
    d2: (T, T),
    d3: (T, T),
}

impl<T: Real> FigureEight<T> {
    /// Checks the keys: errors name `center.x`, `center.y`, `width`, `height` and
    /// `period` (all > 0 but the center).
    pub fn new(center_x: T, center_y: T, width: T, height: T, period: T) -> Result<Self, ParamError> {
        check::finite("center.x", center_x)?;
        check::finite("center.y", center_y)?;
        check::positive("width", width)?;
        check::positive("height", height)?;
        check::positive("period", period)?;
        let mut f = Self { center_x, center_y, width, height, period, rate: (T::one(), T::one()) };
        // The speed's bounds over one period, sampled; the minimum taken 10 % lower so
        // the path searches never underestimate the span a distance needs.
        // The same samples check what the figure produces: omega_ref divides by v^2 and
        // its rate by v^4, which underflow or overflow for valid-looking keys (a period of
        // 1e300 s gives 0/0). The figure is periodic, so a period's samples cover any run.
        let (mut lo, mut hi) = (T::infinity(), T::zero());
        for k in 0..1024 {
            let t = period * T::lit(f64::from(k) / 1024.0);
            let d = f.derivs(t);
            let v = d.d1.0.hypot_libm(d.d1.1);
            lo = lo.min(v);
            hi = hi.max(v);
            let s = f.state_at(t);
            let values = [s.pose.x, s.pose.y, s.pose.theta, s.twist.v, s.twist.omega, s.accel.v, s.accel.omega];
            if values.iter().any(|x| !x.is_finite()) {
                return Err(f.non_finite_error(hi));
            }
        }
        f.rate = (lo * T::lit(0.9), hi * T::lit(1.01));
        Ok(f)
    }

    /// The key to blame for a figure whose state is not finite, found by what the state
    /// computes: the angular rate a = 2 pi / period to the third power (the jerk) and
    /// squared (omega_ref's denominator), else the speed v ~ extent a, squared and
    /// squared again: too large (`hi`, the fastest speed seen, overflows) blames the larger
    /// extent, too small the smaller one.
    fn non_finite_error(&self, hi: T) -> ParamError {
        const WHY: &str = "gives a figure whose turn rate or acceleration is not a finite number (the \
                           speed, about width / period, is too small or too large to square twice): \
                           bring width, height and period nearer 1";
        let a = T::TAU() / self.period;
        let a2 = a * a;
        if !(a2 * a).is_finite() || a2 < T::min_positive_value() {
            return check::out_of_range("period", WHY, self.period);
        }
        let too_large = !(hi * hi * hi * hi).is_finite();
        let width_blamed = if too_large { self.width >= self.height } else { self.width <= self.height };
        if width_blamed {
            check::out_of_range("width", WHY, self.width)
        } else {
            check::out_of_range("height", WHY, self.height)
        }
    }

    #[inline(always)]
    fn derivs(&self, t: T) -> Derivs<T> {
        let a = T::TAU() / self.period;
        let hw = self.width * T::lit(0.5);
        let hh = self.height * T::lit(0.5);
        let (s1, c1) = (a * t).sin_cos_libm();
        let (s2, c2) = (T::lit(2.0) * a * t).sin_cos_libm();
        let a2 = a * a;
        let a3 = a2 * a;
        Derivs {
            p: (self.center_x + hw * s1, self.center_y + hh * s2),
            d1: (hw * a * c1, self.height * a * c2),
            d2: (-hw * a2 * s1, -T::lit(2.0) * self.height * a2 * s2),
            d3: (-hw * a3 * c1, -T::lit(4.0) * self.height * a3 * c2),
        }
    }
}

impl<T: Real> Reference<T> for FigureEight<T> {
    fn state_at(&self, t: T) -> ReferenceState<T> {
        let d = self.derivs(t);
        let (x1, y1) = d.d1;
        let (x2, y2) = d.d2;
        let (x3, y3) = d.d3;
        let v2 = x1 * x1 + y1 * y1;
        let v = x1.hypot_libm(y1);
        let cross = x1 * y2 - y1 * x2;
        let dot = x1 * x2 + y1 * y2;
        ReferenceState {
            pose: Pose2::new(d.p.0, d.p.1, y1.atan2_libm(x1)),
            twist: Twist2 { v, omega: cross / v2 },
            accel: Twist2 { v: dot / v, omega: (x1 * y3 - y1 * x3) / v2 - T::lit(2.0) * cross * dot / (v2 * v2) },
        }
    }

    fn path(&self) -> Option<&dyn Path<T>> {
        Some(self)
    }
}

impl<T: Real> Path<T> for FigureEight<T> {
    /// s = time, s.
    fn pose_on_path(&self, s: T) -> Pose2<T> {
        let d = self.derivs(s.max(T::zero()));
        Pose2::new(d.p.0, d.p.1, d.d1.1.atan2_libm(d.d1.0))
    }
    fn end(&self) -> Option<T> {
        None
    }
    fn rate_bounds(&self) -> (T, T) {
        self.rate
    }
    fn remaining_length(&self, _s: T) -> T {
        T::infinity()
    }
    fn point_on_path(&self, s: T) -> (T, T) {
        // `derivs`' position, with the same operations (so the same numbers).
        let t = s.max(T::zero());
        let a = T::TAU() / self.period;
        let (s1, _) = (a * t).sin_cos_libm();
        let (s2, _) = (T::lit(2.0) * a * t).sin_cos_libm();
        (self.center_x + self.width * T::lit(0.5) * s1, self.center_y + self.height * T::lit(0.5) * s2)
    }
}
