//! A disturbance observer (DOB) on the wheel dynamics with a first-order Q-filter
//! (`[controller.observer] kind = "disturbance"`): it estimates the lumped disturbance
//! torque at each wheel from the torque the controller commanded and the measured wheel
//! speeds, and the wheel stage subtracts the estimate from its command, whatever the law.
//!
//! # Derivation
//!
//! The nominal wheel dynamics are (15) of the controller's robot model written in the
//! wheel speeds w = (w_r, w_l): with v = r (w_r + w_l) / 2 and omega = r (w_r - w_l) / (2 R),
//! the kinetic energy 1/2 M_11 v^2 + 1/2 M_22 omega^2 is 1/2 w^T J w and the wheel
//! torques' power tau_r w_r + tau_l w_l is F v + M omega, so
//!
//! ```text
//! J w' = tau + d        J = [[J_s, J_x], [J_x, J_s]]       kg m^2
//! J_s = r^2/4 (M_11 + M_22 / R^2),   J_x = r^2/4 (M_11 - M_22 / R^2)
//! ```
//!
//! tau: the wheel torques the drive gives for the commands (N m), and d: everything this
//! linear model leaves out, per wheel (N m): the Coriolis terms of (15) when G is off C,
//! friction, a slope, a payload, pushes, the driver's deadband, stiction, and any
//! mismatch between the model and the robot. (A forward force F and a moment M about C
//! are the wheel torques r/2 (F + M / R, F - M / R).)
//!
//! Ohnishi's observer (Ohnishi, Shibata, Murakami 1996; Sariyildiz and Ohnishi, "A guide
//! to design disturbance observer", ASME J. Dyn. Sys. Meas. Control 136 (2014) 021011)
//! passes the model's disturbance d = J w' - tau through a low-pass Q-filter
//! Q(s) = g / (s + g), g the `bandwidth` (rad/s):
//!
//! ```text
//! d_hat = Q(s) (J s w - tau)
//! ```
//!
//! Against the true d (the model exact), d_hat' = g (d - d_hat): a first-order lag of
//! time constant 1 / g. A step of d at t0 is estimated as d (1 - exp(-g (t - t0))): within
//! 1 % after 5 / g (exp(-5) = 0.67 %).
//!
//! **Discrete form, at the control period h.** The controller holds its command over each
//! period, so between the ticks k - 1 and k the wheels feel the torque tau_(k-1) computed
//! at tick k - 1 and J (w_k - w_(k-1)) / h = tau_(k-1) + d_mean, d_mean the mean of d over the
//! period: exactly, for the linear model. The Q-filter, discretised exactly for a
//! piecewise-constant input, gives
//!
//! ```text
//! y_k     = J (w_k - w_(k-1)) / h - tau_(k-1)          the disturbance over the last period
//! d_hat_k = d_hat_(k-1) + (1 - exp(-g h)) (y_k - d_hat_(k-1))
//! ```
//!
//! so a step of d at a tick t0 is estimated at every later tick t_k as
//! d (1 - exp(-g (t_k - t0))), the continuous response sampled without error. The first
//! tick (and the first after a reset) has no previous speed: d_hat stays 0.
//!
//! **Compensation.** The wheel stage subtracts d_hat_k from the wheel torque of its
//! command ([`crate::Drive::command_for_wheel_torque`] is affine in the torque, so the
//! command moves by the command of -d_hat_k less the command of 0), before its speed
//! guard; tau_k is then the wheel torque the drive gives for the final command (its
//! limits included, so the observer does not wind up on a saturated drive).
//!
//! **Stability of the compensation.** Against a plant of inertia J' = J / rho (the model
//! wrong by a factor) the estimate's own pole is 1 - (1 - exp(-g h)) rho: inside the
//! unit circle for every g whenever 0 < rho < 2 (the robot heavier than the model, or less
//! than twice as light). The observer changes nothing when it is off (the default).
//!
//! # Deadband and stiction pre-compensation
//!
//! A driver deadband and stiction are not disturbances the filter can cancel: below the
//! deadband the wheel gets nothing whatever the command, and a wheel at rest stays there
//! until its torque passes the breakaway torque, so a small command does nothing and the
//! estimate (an integral of the command's shortfall) only builds up until it jumps. What a
//! user of a motor driver does instead is what its "minimum output" setting does (CTRE's
//! nominal output; a PWM driver's minimum duty): a command that asks for motion is lifted
//! to the smallest one that gives it. With the deadband fraction delta and the breakaway
//! torque tau_s the controller believes (`deadband`, `static_friction`: the plant's own
//! `[drive] deadband` and `[robot] static_friction`, as the controller knows them; 0: off),
//!
//! ```text
//! c_min = max(delta c_max, c(tau_s))       c_max: the drive's largest command
//! c'    = sign(c) max(|c|, c_min)   if |c| > b,     c' = c   otherwise
//! b     = beta c_min                        beta = `precompensation_band`
//! ```
//!
//! c(tau_s) the command that gives the wheel torque tau_s at rest (the torque drive:
//! tau_s; a DC motor: the voltage R_a k_t tau_s / k_tau). The plant's deadband passes a
//! command of magnitude delta c_max (it zeroes those below), so a lifted command reaches
//! the wheel; and a wheel at rest gets at least tau_s. The lift acts on the final command
//! (the law's, the servo's and the estimate's together), before the speed guard. The
//! observer then records the torque the believed drive gives: 0 for a command below the
//! believed deadband, so its estimate is not an integral of commands it knows are lost.
//!
//! **The band b.** Lifting every non-zero command makes the map discontinuous at 0: a
//! holding servo whose command hovers about 0 (sensor noise, a residual angle error)
//! would be kicked +-c_min each tick, and a lifted pulse that carries the wheel past its
//! reference is lifted back: a limit cycle. Commands within b of 0 pass unchanged (the
//! plant's deadband and stiction then hold the wheel), so the wheel rests where the
//! servo's command is within b: an angle error b / K_p. A pulse of c_min starting at
//! the edge of the lift (|c| just below c_min, an angle error c_min / K_p) stops by
//! friction alone once |c| < b, so it cannot be lifted back the other way when its
//! travel, at most (c_min - b) / K_p at a net torque c_min - tau_c, coasts less than the
//! band's width 2 b / K_p against the Coulomb friction tau_c:
//! (c_min - tau_c)(c_min - b) <= 2 b tau_c. The default beta = 0.5 is the middle of the
//! lift; it is chosen by measurement (examples/docking/README.md, "Pre-compensation").

use crate::drive::Drive;
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use crate::math::Wheels;
use crate::{Real, RobotParams};
use num_traits::Zero;

crate::params! {
    /// `[controller.observer] kind = "disturbance"` keys.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct DisturbanceObserverParams<T> {
        /// g, the Q-filter's bandwidth g / (s + g): the estimate follows a step with time constant 1 / g.
        pub bandwidth: T [unit = "rad/s", rule = "> 0, finite"],
        /// The driver deadband the controller believes, a fraction of the drive's largest command (as `[drive] deadband`): a command that asks for motion is lifted to it (module docs; 0: off).
        pub deadband: T [unit = "", rule = "in [0, 1); > 0 only with a finite drive limit"],
        /// The breakaway torque at each wheel the controller believes (as `[robot] static_friction`): a command that asks for motion is lifted to the one giving it at rest (module docs; 0: off).
        pub static_friction: T [unit = "N m", rule = ">= 0, finite"],
        /// b / c_min: commands within this fraction of the lift c_min of zero pass unlifted, so a holding robot does not chatter (module docs).
        pub precompensation_band: T [unit = "", rule = "in [0, 1]"],
    }
}

impl<T: Real> Default for DisturbanceObserverParams<T> {
    /// 50 rad/s: about 2.5 times the paper's wheel servo's natural frequency
    /// (sqrt(servo_kp / J_w) = sqrt(14 / 0.0328) = 21 rad/s), so the estimate settles
    /// (5 / g = 0.1 s) faster than the loop it serves; 0.05 per 1 ms control period.
    /// No pre-compensation (`deadband` and `static_friction` 0); its band, when on, is
    /// half the lift (module docs).
    fn default() -> Self {
        Self {
            bandwidth: T::lit(50.0),
            deadband: T::zero(),
            static_friction: T::zero(),
            precompensation_band: T::lit(0.5),
        }
    }
}

impl<T: Real> DisturbanceObserverParams<T> {
    /// The observer for the controller's robot `model` and `drive` at the control period
    /// `control_dt` (s); errors name the key as a scenario writes it
    /// (`observer.bandwidth`, ..., [`DisturbanceObserverParams::scenario_field`]) or a
    /// `model` key.
    pub fn validate<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        drive: &Drive<T>,
        control_dt: T,
    ) -> Result<DisturbanceObserver<L>, ParamError> {
        let named = |e: ParamError| ParamError { field: Self::scenario_field(e.field), ..e };
        let g = check::positive("bandwidth", self.bandwidth).map_err(named)?;
        let h = check::positive("control_dt", control_dt)?;
        let delta = crate::drive::check_deadband(self.deadband).map_err(named)?;
        let tau_s = check::non_negative("static_friction", self.static_friction).map_err(named)?;
        check::finite("static_friction", tau_s).map_err(named)?;
        let beta = check::non_negative("precompensation_band", self.precompensation_band).map_err(named)?;
        if beta > T::one() {
            return Err(named(check::out_of_range("precompensation_band", "must be <= 1", beta)));
        }
        let limit = drive.command_limit();
        if delta > T::zero() && limit.is_infinite() {
            return Err(named(check::out_of_range(
                "deadband",
                "must be 0 with a drive without a command limit (an infinite motor_torque_max)",
                delta,
            )));
        }
        let dead = if delta > T::zero() { delta * limit } else { T::zero() };
        let breakaway = if tau_s > T::zero() {
            drive.command_for_wheel_torque(tau_s, T::zero()) - drive.command_for_wheel_torque(T::zero(), T::zero())
        } else {
            T::zero()
        };
        let lift = dead.max(breakaway);
        let robot = model.validate()?;
        let (m11, m22) = robot.reduced_inertia();
        let (r, big_r) = (model.wheel_radius, model.half_track);
        let quarter = T::lit(0.25) * r * r;
        let rot = m22 / (big_r * big_r);
        Ok(DisturbanceObserver {
            params: *self,
            gain: T::one() - (-g * h).exp_libm(),
            inv_dt: h.recip(),
            j_same: quarter * (m11 + rot),
            j_cross: quarter * (m11 - rot),
            estimate: Wheels::default(),
            last_speeds: Wheels::default(),
            last_torques: Wheels::default(),
            primed: L::Mask::splat(false),
            lift,
            band: beta * lift,
            dead,
        })
    }

    /// `field` of these keys as a scenario names it under `[controller]`
    /// (`bandwidth` -> `observer.bandwidth`); any other field as it is.
    pub fn scenario_field(field: &'static str) -> &'static str {
        match field {
            "bandwidth" => "observer.bandwidth",
            "deadband" => "observer.deadband",
            "static_friction" => "observer.static_friction",
            "precompensation_band" => "observer.precompensation_band",
            other => other,
        }
    }
}

/// The observer's state (module docs), for one run or several side by side ([`crate::lane`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisturbanceObserver<L: Lane> {
    params: DisturbanceObserverParams<L::Scalar>,
    /// 1 - exp(-g h).
    gain: L::Scalar,
    /// 1 / h, 1/s.
    inv_dt: L::Scalar,
    /// J_s and J_x of the wheel-space inertia matrix, kg m^2.
    j_same: L::Scalar,
    j_cross: L::Scalar,
    /// d_hat, N m per wheel.
    estimate: Wheels<L>,
    /// w at the last tick, rad/s.
    last_speeds: Wheels<L>,
    /// The wheel torques held since the last tick, N m.
    last_torques: Wheels<L>,
    /// False until a tick has recorded its speeds and torques.
    primed: L::Mask,
    /// c_min, the pre-compensation's lift (command units, N m or V; 0: off).
    lift: L::Scalar,
    /// b, the band about 0 the lift leaves alone (command units).
    band: L::Scalar,
    /// The believed deadband delta c_max (command units; 0: none).
    dead: L::Scalar,
}

impl<L: Lane> DisturbanceObserver<L> {
    /// The parameters.
    pub fn params(&self) -> &DisturbanceObserverParams<L::Scalar> {
        &self.params
    }

    /// The wheel-space inertia matrix's (J_s, J_x), kg m^2 (module docs).
    pub fn wheel_inertia(&self) -> (L::Scalar, L::Scalar) {
        (self.j_same, self.j_cross)
    }

    /// The estimate of the last tick, d_hat (N m per wheel).
    pub fn estimate(&self) -> Wheels<L> {
        self.estimate
    }

    /// One tick: the estimate updated with the measured wheel speeds `w` (rad/s) and
    /// returned (d_hat_k of the module docs).
    #[inline(always)]
    pub fn update(&mut self, w: Wheels<L>) -> Wheels<L> {
        let inv_dt = L::splat(self.inv_dt);
        let (dr, dl) = ((w.right - self.last_speeds.right) * inv_dt, (w.left - self.last_speeds.left) * inv_dt);
        let (js, jx) = (L::splat(self.j_same), L::splat(self.j_cross));
        let y = Wheels::new(js * dr + jx * dl - self.last_torques.right, jx * dr + js * dl - self.last_torques.left);
        let g = L::splat(self.gain);
        let next = Wheels::new(
            self.estimate.right + g * (y.right - self.estimate.right),
            self.estimate.left + g * (y.left - self.estimate.left),
        );
        let p = self.primed;
        self.estimate =
            Wheels::new(L::select(p, next.right, self.estimate.right), L::select(p, next.left, self.estimate.left));
        self.last_speeds = w;
        self.estimate
    }

    /// Records the wheel torques `tau` (N m) the drive gives for this tick's commands,
    /// held until the next tick.
    #[inline(always)]
    pub fn record(&mut self, tau: Wheels<L>) {
        self.last_torques = tau;
        self.primed = L::Mask::splat(true);
    }

    /// c_min, the pre-compensation's lift (N m or V, the drive's command unit; 0: off),
    /// and b, the band about 0 it leaves alone (module docs).
    pub fn lift(&self) -> (L::Scalar, L::Scalar) {
        (self.lift, self.band)
    }

    /// True when the pre-compensation is on (a believed deadband or breakaway torque).
    #[inline(always)]
    pub fn precompensates(&self) -> bool {
        self.lift > L::Scalar::zero()
    }

    /// The drive commands `c` (N m or V per wheel) pre-compensated: each whose magnitude
    /// is above the band lifted to at least c_min in its own sign; the others, and every
    /// command when the pre-compensation is off, unchanged (module docs).
    #[inline(always)]
    pub fn precompensate(&self, c: Wheels<L>) -> Wheels<L> {
        if !self.precompensates() {
            return c;
        }
        let (lift, band) = (L::splat(self.lift), L::splat(self.band));
        // Written out, not a closure: the lanes' kernel holds no out-of-line call.
        Wheels::new(lifted(c.right, lift, band), lifted(c.left, lift, band))
    }

    /// The commands `c` as the believed drive passes them: 0 where the magnitude is below
    /// the believed deadband, the others unchanged (all when there is none).
    #[inline(always)]
    pub fn believed_passed(&self, c: Wheels<L>) -> Wheels<L> {
        if self.dead == L::Scalar::zero() {
            return c;
        }
        let (dead, zero) = (L::splat(self.dead), L::default());
        Wheels::new(L::select(c.right.abs().lt(dead), zero, c.right), L::select(c.left.abs().lt(dead), zero, c.left))
    }

    /// Forgets the runs in `lanes`, as at t = 0 (estimate 0, no previous speed).
    pub fn reset_lanes(&mut self, lanes: L::Mask) {
        let zero = L::default();
        let keep = |x: L| L::select(lanes, zero, x);
        self.estimate = self.estimate.map(keep);
        self.last_speeds = self.last_speeds.map(keep);
        self.last_torques = self.last_torques.map(keep);
        self.primed = self.primed & !lanes;
    }
}

/// `c` lifted to at least `lift` in its own sign where |c| > `band`, else `c` (NaN kept).
#[inline(always)]
fn lifted<L: Lane>(c: L, lift: L, band: L) -> L {
    let mag = c.abs();
    let up = mag.max(lift);
    L::select(band.lt(mag), L::select(c.lt(L::default()), -up, up), c)
}
