//! The traction a rolling run asks of the ground: with rolling
//! wheels (the paper's model, the default) nothing stops a strong drive from pushing the
//! robot harder than its tyres could; this measures by how much.
//!
//! At a state s under wheel torques tau (the rolling plant's equations give v', omega'):
//!
//! ```text
//! longitudinal, per wheel:  F_x = (tau - tau_f(omega_w) - I_m omega_w') / r,  omega_w' = (v' +- R omega') / r
//! lateral, both wheels:     F_yr + F_yl = m (omega v + omega' d) - G_y      (v_y = 0: no side slip)
//! normal, per wheel:        N = (W (c - d) + h (F_xr + F_xl)) / (2 c),       W = m g cos(slope)
//! ratio, per wheel:         |(F_x, F_y / 2)| / (mu N)
//! ```
//!
//! with G_y the downhill pull along the body's y, c = `caster_offset`, h = `com_height`,
//! mu = `friction_coefficient` (the keys of the slip model, [`crate::traction`]: the same
//! normal loads, no lateral load transfer, the lateral force shared equally). A ratio
//! above 1 is a force the tyre cannot give: the rolling result is not physical there (a
//! wheel with no load, N <= 0, has an infinite ratio). The keys need not pass the slip
//! model's validation (`mu h <= |d|`): a rolling run only reads them.

use crate::dynamics::Model;
use crate::math::Wheels;
use crate::state::State;
use crate::traction::TractionParams;
use crate::world::{STANDARD_GRAVITY, World};
use crate::{Real, Robot};

/// What a rolling robot's wheels ask of the ground (module docs). No alloc.
#[derive(Clone, Copy, Debug)]
pub struct RollingTraction<T> {
    model: Model<T>,
    /// r, R, d, I_m, m: m, m, m, kg m^2, kg.
    r: T,
    big_r: T,
    d: T,
    wheel_inertia: T,
    mass: T,
    /// mu, c (m), h (m).
    mu: T,
    c: T,
    h: T,
    /// W = m g cos(slope), N.
    weight: T,
    /// Gravity along the plane, world x and y, N.
    downhill: (T, T),
}

impl<T: Real> RollingTraction<T> {
    /// For `robot` on `world`'s ground with the tyre and load keys of `traction`.
    pub fn new(robot: &Robot<T>, world: &World<T>, traction: &TractionParams<T>) -> Self {
        let p = robot.params();
        let per_degree = T::PI() / T::lit(180.0);
        let (_, cos_slope) = (world.params().slope_deg * per_degree).sin_cos_libm();
        Self {
            model: Model::on(robot, world),
            r: p.wheel_radius,
            big_r: p.half_track,
            d: p.com_offset,
            wheel_inertia: p.wheel_inertia,
            mass: p.mass,
            mu: traction.friction_coefficient,
            c: traction.caster_offset,
            h: traction.com_height,
            weight: p.mass * T::lit(STANDARD_GRAVITY) * cos_slope,
            downhill: world.downhill_force(p.mass),
        }
    }

    /// The larger of the two wheels' |F| / (mu N) at state `s` under wheel torques
    /// `torque` (N m): above 1, a force the tyre cannot give (module docs).
    pub fn ratio(&self, s: &State<T>, torque: Wheels<T>) -> T {
        let ds = self.model.derivative(s, torque);
        let (r, big_r) = (self.r, self.big_r);
        let wheel = |tau: T, sign: T| {
            let omega_w = (s.v + sign * big_r * s.omega) / r;
            let omega_w_dot = (ds.v + sign * big_r * ds.omega) / r;
            (tau - self.model.friction_torque(omega_w) - self.wheel_inertia * omega_w_dot) / r
        };
        let f_r = wheel(torque.right, T::one());
        let f_l = wheel(torque.left, -T::one());
        let (sin, cos) = s.theta.sin_cos_libm();
        let g_y = -self.downhill.0 * sin + self.downhill.1 * cos;
        let f_y = (self.mass * (s.omega * s.v + ds.omega * self.d) - g_y) / T::lit(2.0);
        let n = (self.weight * (self.c - self.d) + self.h * (f_r + f_l)) / (T::lit(2.0) * self.c);
        if n <= T::zero() {
            return T::infinity();
        }
        let limit = self.mu * n;
        (f_r.hypot_libm(f_y) / limit).max(f_l.hypot_libm(f_y) / limit)
    }
}

/// When a rolling run first asked more than its tyres can give, and its worst. No alloc.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TractionWatch<T> {
    /// First time (s) with a ratio above 1, and that ratio.
    pub first: Option<(T, T)>,
    /// Largest ratio seen (s, ratio) above 1.
    pub peak: Option<(T, T)>,
}

impl<T: Real> TractionWatch<T> {
    /// Adds the ratio `ratio` ([`RollingTraction::ratio`]) at time `t` (s).
    pub fn observe(&mut self, t: T, ratio: T) {
        if ratio.is_nan() || ratio <= T::one() {
            return;
        }
        if self.first.is_none() {
            self.first = Some((t, ratio));
        }
        if self.peak.is_none_or(|(_, p)| ratio > p) {
            self.peak = Some((t, ratio));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RobotParams;

    /// Straight ahead from rest under equal torques tau on flat ground, by hand: no yaw,
    /// v' = 2 tau / (r M_r11), each wheel pushes F = (tau - I_m v' / r) / r, the load is
    /// N = (W (c - d) + 2 h F) / (2 c), and the ratio is F / (mu N). Both precisions.
    fn straight_ahead<T: Real>(tol: f64) {
        let robot = RobotParams::<T>::paper().validate().unwrap();
        let p = *robot.params();
        let traction = TractionParams::<T>::default();
        let rt = RollingTraction::new(&robot, &World::flat(), &traction);
        let tau = 0.3;
        let ratio = rt.ratio(&State::zero(), Wheels::new(T::lit(tau), T::lit(tau))).to_f64().unwrap();
        let f = |x: T| x.to_f64().unwrap();
        let (m, r, d, i_m) = (f(p.mass), f(p.wheel_radius), f(p.com_offset), f(p.wheel_inertia));
        let (mu, c, h) = (f(traction.friction_coefficient), f(traction.caster_offset), f(traction.com_height));
        let m11 = m + 2.0 * i_m / (r * r);
        let v_dot = 2.0 * tau / (r * m11);
        let force = (tau - i_m * v_dot / r) / r;
        let w = m * STANDARD_GRAVITY;
        let n = (w * (c - d) + 2.0 * h * force) / (2.0 * c);
        let want = force / (mu * n);
        assert!((ratio - want).abs() <= tol * want, "{ratio} vs {want}");
        // Half the torque, about half the ratio (the load moves with the force): below 1
        // here, above 1 at 20 times the torque.
        assert!(ratio < 1.0);
        let big = rt.ratio(&State::zero(), Wheels::new(T::lit(20.0 * tau), T::lit(20.0 * tau)));
        assert!(big > T::one(), "{big:?}");
    }

    #[test]
    fn the_ratio_of_a_straight_push_is_the_hand_computed_one() {
        straight_ahead::<f64>(1e-12);
        straight_ahead::<f32>(1e-5);
    }

    /// A steady turn at speed: the torques that hold v and omega (v' = omega' = 0:
    /// tau_r + tau_l = -r m d omega^2, tau_r - tau_l = r m d v omega / R) leave each tyre
    /// the side force m omega v / 2 and its own push tau / r, by hand.
    #[test]
    fn a_steady_turn_asks_for_the_side_force_m_omega_v() {
        let robot = RobotParams::<f64>::paper().validate().unwrap();
        let p = *robot.params();
        let traction = TractionParams::default();
        let rt = RollingTraction::new(&robot, &World::flat(), &traction);
        let (v, omega) = (1.0, 2.0);
        let (m, r, big_r, d) = (p.mass, p.wheel_radius, p.half_track, p.com_offset);
        let sum = -r * m * d * omega * omega;
        let diff = r * m * d * v * omega / big_r;
        let tau = Wheels::new((sum + diff) / 2.0, (sum - diff) / 2.0);
        let mut s = State::zero();
        (s.v, s.omega) = (v, omega);
        let ds = robot.derivative(&s, tau);
        assert!(ds.v.abs() < 1e-12 && ds.omega.abs() < 1e-12, "{ds:?}");
        let f_y = m * omega * v / 2.0;
        let (f_r, f_l) = (tau.right / r, tau.left / r);
        let (c, h, mu) = (traction.caster_offset, traction.com_height, traction.friction_coefficient);
        let n = (m * STANDARD_GRAVITY * (c - d) + h * (f_r + f_l)) / (2.0 * c);
        let want = f_r.hypot(f_y).max(f_l.hypot(f_y)) / (mu * n);
        let ratio = rt.ratio(&s, tau);
        assert!((ratio - want).abs() < 1e-12 * want, "{ratio} vs {want}");
        // 5 N to the side and 8.75 N back at the inner wheel, against mu N of about 5.6 N.
        assert!(ratio > 1.0, "{ratio}");
    }

    #[test]
    fn the_watch_keeps_the_first_and_the_worst() {
        let mut w = TractionWatch::default();
        for (t, r) in [(0.0, 0.5), (0.1, 1.5), (0.2, 3.0), (0.3, 2.0)] {
            w.observe(t, r);
        }
        assert_eq!(w.first, Some((0.1, 1.5)));
        assert_eq!(w.peak, Some((0.2, 3.0)));
        let mut calm = TractionWatch::default();
        calm.observe(0.0, 0.99);
        assert_eq!(calm, TractionWatch::default());
    }
}
