//! Equations of motion (15) of the paper, written at C (docs/model.md, "Dynamics").
//!
//! With M_r = diag(m + 2 I_m/r^2, I_p + 2 R^2 I_m/r^2 + m d^2):
//!
//! ```text
//! v'     = ((tau_r - f_r + tau_l - f_l)/r + m d omega^2) / M_r11
//! omega' = ((R/r)((tau_r - f_r) - (tau_l - f_l)) - m d v omega) / M_r22
//! ```
//!
//! The Coriolis terms C(v) = [-m d omega^2, m d v omega] do no work
//! (v * m d omega^2 - omega * m d v omega = 0), which the energy test relies on.

use crate::lane::Lane;
use crate::math::Wheels;
use crate::state::State;
use crate::world::World;
use crate::{Real, Robot};

impl<T: Real> Robot<T> {
    /// Friction torque at one wheel, N m: b_v omega + tau_c tanh(omega / omega_eps).
    #[inline(always)]
    pub fn friction_torque(&self, omega_wheel: T) -> T {
        Model::new(self).friction_torque(omega_wheel)
    }

    /// Time derivative of the state under wheel torques `tau_wheel` (N m, drive on wheel).
    ///
    /// For many calls with the same robot, [`crate::Plant`] keeps a precomputed
    /// model instead; both give the same bits.
    #[inline(always)]
    pub fn derivative(&self, s: &State<T>, tau_wheel: Wheels<T>) -> State<T> {
        Model::new(self).derivative(s, tau_wheel)
    }

    /// Kinetic energy, J: T = 1/2 M_r11 v^2 + 1/2 M_r22 omega^2 (platform, wheels, rotors).
    pub fn kinetic_energy(&self, s: &State<T>) -> T {
        let (m11, m22) = self.reduced_inertia();
        let half = T::lit(0.5);
        let energy = half * m11 * s.v * s.v + half * m22 * s.omega * s.omega;
        // The payload's coupling (crate::payload): - m b v omega.
        if self.com_lateral() == T::zero() { energy } else { energy + self.mass_coupling() * s.v * s.omega }
    }
}

/// The constants of (15) gathered for the hot path: built once per [`crate::Plant`],
/// so a step reloads no parameter struct and divides only where the equations divide.
///
/// Every field is a value [`Robot::derivative`] would otherwise compute on each call
/// (`R / r` was a division per call), computed by the same operations, so the results
/// are bit-identical to computing them inline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Model<T> {
    /// r, m.
    r: T,
    /// R, m.
    big_r: T,
    /// R / r.
    big_r_over_r: T,
    /// 1 / r, 1/m: the lanes multiply where one run divides ([`Lane::div_by`]).
    inv_r: T,
    /// 1 / M_r11, 1/kg.
    inv_m11: T,
    /// 1 / M_r22, 1/(kg m^2).
    inv_m22: T,
    /// m d, kg m.
    md: T,
    /// b_v, N m s.
    b_v: T,
    /// tau_c, N m.
    tau_c: T,
    /// omega_eps, rad/s.
    omega_eps: T,
    /// tau_s, N m: the breakaway torque of stiction (0: none, [`Robot::breakaway_torque`]).
    tau_s: T,
    /// d, m: C forward to G.
    d: T,
    /// Gravity along a tilted ground, world x and y components, N (zero when flat).
    downhill: (T, T),
    /// True when the ground is tilted.
    sloped: bool,
    /// b, m: G left of C (a payload off the centreline, [`crate::payload`]; 0 otherwise).
    b: T,
    /// The off-diagonal term of the inverse mass matrix, 1/(kg m) (0 when b = 0).
    inv_m12: T,
    /// True when b != 0: the forward and yaw equations are coupled.
    coupled: bool,
    /// The pushes' load held over the current step ([`crate::push`]), body frame.
    load: crate::push::Load<T>,
    /// True when `load` is not zero.
    pushed: bool,
}

impl<T: Real> Model<T> {
    /// The model on flat ground.
    #[inline(always)]
    pub(crate) fn new(robot: &Robot<T>) -> Self {
        Self::on(robot, &World::flat())
    }

    /// The model on `world`'s ground.
    #[inline(always)]
    pub(crate) fn on(robot: &Robot<T>, world: &World<T>) -> Self {
        let p = robot.params();
        let (inv_m11, inv_m22) = robot.inv_reduced_inertia();
        Self {
            r: p.wheel_radius,
            big_r: p.half_track,
            big_r_over_r: p.half_track / p.wheel_radius,
            inv_r: T::one() / p.wheel_radius,
            inv_m11,
            inv_m22,
            md: robot.mass_offset(),
            b_v: p.viscous_friction,
            tau_c: p.coulomb_friction,
            omega_eps: p.coulomb_speed,
            tau_s: robot.breakaway_torque(),
            d: p.com_offset,
            downhill: world.downhill_force(p.mass),
            sloped: world.is_sloped(),
            b: robot.com_lateral(),
            inv_m12: robot.inv_coupling(),
            coupled: robot.com_lateral() != T::zero(),
            load: crate::push::Load::default(),
            pushed: false,
        }
    }

    /// (v', omega') from the forward force and the moment about C (the right side of
    /// (15)): M_r^-1 times them, diagonal unless a payload couples them ([`crate::payload`]).
    #[inline(always)]
    fn accelerations<L: Lane<Scalar = T>>(&self, forward: L, moment: L) -> (L, L) {
        let (v_dot, omega_dot) = (forward * L::splat(self.inv_m11), moment * L::splat(self.inv_m22));
        if self.coupled {
            let k = L::splat(self.inv_m12);
            (v_dot + moment * k, omega_dot + forward * k)
        } else {
            (v_dot, omega_dot)
        }
    }

    /// Holds the pushes' `load` (body frame, at C) over the next step ([`crate::push`]).
    #[inline(always)]
    pub(crate) fn set_load(&mut self, load: crate::push::Load<T>) {
        let zero = T::zero();
        self.pushed = load.force_x != zero || load.force_y != zero || load.torque != zero;
        self.load = load;
    }

    /// The load held over the current step, if any.
    #[inline(always)]
    pub(crate) fn load(&self) -> Option<crate::push::Load<T>> {
        self.pushed.then_some(self.load)
    }

    /// True when gravity acts along the ground (a tilted plane).
    #[inline(always)]
    pub(crate) fn is_sloped(&self) -> bool {
        self.sloped
    }

    /// True when the Coulomb term tau_c tanh(omega / omega_eps) is present (tau_c > 0).
    #[inline(always)]
    pub(crate) fn has_coulomb(&self) -> bool {
        self.tau_c > T::zero()
    }

    /// See [`Robot::friction_torque`].
    #[inline(always)]
    pub(crate) fn friction_torque(&self, omega_wheel: T) -> T {
        if self.has_coulomb() {
            self.friction_torque_with::<T, true>(omega_wheel)
        } else {
            self.friction_torque_with::<T, false>(omega_wheel)
        }
    }

    /// Friction with the Coulomb term switched at compile time; `COULOMB` must equal
    /// [`Model::has_coulomb`].
    ///
    /// Why: tanh is the dearest call of the model (a third of a closed-loop step when it
    /// was always evaluated), and without Coulomb friction (the default) tau_c tanh(.) is
    /// a zero. Skipping it changes at most the sign of a zero result; a NaN or infinite
    /// omega still gives NaN through b_v omega (0 * inf = NaN). Deciding it once per step
    /// rather than per call keeps the four RK4 stages free of branches.
    #[inline(always)]
    pub(crate) fn friction_torque_with<L: Lane<Scalar = T>, const COULOMB: bool>(&self, omega_wheel: L) -> L {
        let viscous = L::splat(self.b_v) * omega_wheel;
        if COULOMB { viscous + L::splat(self.tau_c) * (omega_wheel / L::splat(self.omega_eps)).tanh() } else { viscous }
    }

    /// See [`Robot::derivative`]; on a tilted ground, with gravity along it.
    #[inline(always)]
    pub(crate) fn derivative(&self, s: &State<T>, tau_wheel: Wheels<T>) -> State<T> {
        match (self.has_coulomb(), self.is_sloped()) {
            (true, true) => self.derivative_with::<true, true>(s, tau_wheel),
            (true, false) => self.derivative_with::<true, false>(s, tau_wheel),
            (false, true) => self.derivative_with::<false, true>(s, tau_wheel),
            (false, false) => self.derivative_with::<false, false>(s, tau_wheel),
        }
    }

    /// [`Model::derivative`] with the Coulomb term and the slope decided by the caller;
    /// `COULOMB` must equal [`Model::has_coulomb`] and `SLOPE` [`Model::is_sloped`].
    ///
    /// On a slope, with (F_x, F_y) = F (cos psi, sin psi) the pull along the plane (see
    /// [`crate::world`]): forward force += F cos(psi - theta) = F_x cos(theta) + F_y sin(theta),
    /// moment about C += d F sin(psi - theta) = d (F_y cos(theta) - F_x sin(theta)).
    #[inline(always)]
    pub(crate) fn derivative_with<const COULOMB: bool, const SLOPE: bool>(
        &self,
        s: &State<T>,
        tau_wheel: Wheels<T>,
    ) -> State<T> {
        self.derivative_lanes::<T, COULOMB, SLOPE>(s, tau_wheel)
    }

    /// [`Model::derivative_with`] for one run (`L = T`) or several side by side
    /// ([`crate::lane`]): the same operations in the same order.
    #[inline(always)]
    pub(crate) fn derivative_lanes<L: Lane<Scalar = T>, const COULOMB: bool, const SLOPE: bool>(
        &self,
        s: &State<L>,
        tau_wheel: Wheels<L>,
    ) -> State<L> {
        self.derivative_at_heading::<L, COULOMB, SLOPE>(s, tau_wheel, s.theta.sin_cos())
    }

    /// [`Model::derivative_lanes`] with (sin, cos) of the heading `s.theta` given: the
    /// lanes carry them through their RK4 step rather than computing them at each stage
    /// ([`crate::plant`]'s `advance_carrying_heading`).
    #[inline(always)]
    pub(crate) fn derivative_at_heading<L: Lane<Scalar = T>, const COULOMB: bool, const SLOPE: bool>(
        &self,
        s: &State<L>,
        tau_wheel: Wheels<L>,
        (sin, cos): (L, L),
    ) -> State<L> {
        let big_r = L::splat(self.big_r);
        let md = L::splat(self.md);
        let w_r = (s.v + big_r * s.omega).div_by(self.r, self.inv_r);
        let w_l = (s.v - big_r * s.omega).div_by(self.r, self.inv_r);
        let net_r = tau_wheel.right - self.friction_torque_with::<L, COULOMB>(w_r);
        let net_l = tau_wheel.left - self.friction_torque_with::<L, COULOMB>(w_l);
        let mut forward = (net_r + net_l).div_by(self.r, self.inv_r) + md * s.omega * s.omega;
        let mut moment = L::splat(self.big_r_over_r) * (net_r - net_l) - md * s.v * s.omega;
        if SLOPE {
            let (f_x, f_y) = (L::splat(self.downhill.0), L::splat(self.downhill.1));
            forward = forward + (f_x * cos + f_y * sin);
            moment = moment + L::splat(self.d) * (f_y * cos - f_x * sin);
            if self.coupled {
                // The pull acts at G', b left of C: its forward part's moment -b f_x.
                moment = moment - L::splat(self.b) * (f_x * cos + f_y * sin);
            }
        }
        if self.pushed {
            // A push at C: F_x forward, tau about C; F_y is the constraint's (crate::push).
            forward = forward + L::splat(self.load.force_x);
            moment = moment + L::splat(self.load.torque);
        }
        let (v_dot, omega_dot) = self.accelerations(forward, moment);
        State { x: s.v * cos, y: s.v * sin, theta: s.omega, v: v_dot, omega: omega_dot, phi_r: w_r, phi_l: w_l }
    }
}

/// Stiction (docs/model.md, "Stiction"): a stick/slip switch decided once per plant step.
///
/// In wheel speeds (omega_r, omega_l), with a = 1 / (r M_r11), c = R^2 / (r M_r22),
/// net_i = tau_i - f_i the torque at wheel i less its friction, and (F, M) the forward
/// force and the moment of the Coriolis terms and the slope, (15) reads
///
/// ```text
/// r omega_r' = (a + c) net_r + (a - c) net_l + g_r,   g_r = F / M_r11 + R M / M_r22
/// r omega_l' = (a - c) net_r + (a + c) net_l + g_l,   g_l = F / M_r11 - R M / M_r22
/// ```
///
/// A stuck wheel's friction is whatever keeps its speed at zero: its row set to 0 and
/// solved for its net torque (both stuck: the 2 x 2 system, determinant 4 a c > 0). It
/// stays stuck while that friction, tau_i - net_i, is within +-tau_s.
impl<T: Real> Model<T> {
    /// True when stiction holds wheels at rest (tau_s > 0).
    #[inline(always)]
    pub(crate) fn has_stiction(&self) -> bool {
        self.tau_s > T::zero()
    }

    /// The wheel speeds (rad/s) of state `s`.
    #[inline(always)]
    fn wheel_speeds_of(&self, s: &State<T>) -> Wheels<T> {
        Wheels::new((s.v + self.big_r * s.omega) / self.r, (s.v - self.big_r * s.omega) / self.r)
    }

    /// `s` with the wheels in `stuck` at rest and the others at their speed (the
    /// static friction's impulse that stops a wheel within omega_eps of rest).
    pub(crate) fn at_rest(&self, s: &State<T>, stuck: Wheels<bool>) -> State<T> {
        if !stuck.right && !stuck.left {
            return *s;
        }
        let w = self.wheel_speeds_of(s);
        let w_r = if stuck.right { T::zero() } else { w.right };
        let w_l = if stuck.left { T::zero() } else { w.left };
        let half = T::lit(0.5);
        State { v: half * self.r * (w_r + w_l), omega: half * self.r * (w_r - w_l) / self.big_r, ..*s }
    }

    /// Each wheel's net torque tau - f (N m) in state `s` under wheel torques `tau`, the
    /// wheels in `stuck` held at rest by their static friction (the impl's docs);
    /// `heading` = (sin, cos) of `s.theta`.
    fn net_torques(&self, s: &State<T>, tau: Wheels<T>, stuck: Wheels<bool>, (sin, cos): (T, T)) -> Wheels<T> {
        let w = self.wheel_speeds_of(s);
        let mut net = Wheels::new(tau.right - self.friction_torque(w.right), tau.left - self.friction_torque(w.left));
        if !stuck.right && !stuck.left {
            return net;
        }
        let (mut f, mut m) = (self.md * s.omega * s.omega, -(self.md * s.v * s.omega));
        if self.sloped {
            let (f_x, f_y) = self.downhill;
            f = f + (f_x * cos + f_y * sin);
            m = m + self.d * (f_y * cos - f_x * sin);
            if self.coupled {
                m = m - self.b * (f_x * cos + f_y * sin);
            }
        }
        if self.pushed {
            f = f + self.load.force_x;
            m = m + self.load.torque;
        }
        let big_r = self.big_r;
        let a = self.inv_m11 * self.inv_r;
        let c = big_r * big_r * self.inv_m22 * self.inv_r;
        let (mut p_r, q) = (a + c, a - c);
        let mut p_l = p_r;
        let mut g_r = f * self.inv_m11 + big_r * m * self.inv_m22;
        let mut g_l = f * self.inv_m11 - big_r * m * self.inv_m22;
        if self.coupled {
            // With k = inv_m12 (crate::payload): r omega_r' gains k (R F + M) and
            // r omega_l' gains k (M - R F), F and M the forward force and moment; the
            // net torques' share of them adds +-2 R k / r to the diagonal.
            let k = self.inv_m12;
            let e = T::lit(2.0) * big_r * k * self.inv_r;
            p_r = p_r + e;
            p_l = p_l - e;
            g_r = g_r + k * (big_r * f + m);
            g_l = g_l + k * (m - big_r * f);
        }
        match (stuck.right, stuck.left) {
            (true, true) => {
                let det = p_r * p_l - q * q;
                net = Wheels::new((q * g_l - p_l * g_r) / det, (q * g_r - p_r * g_l) / det);
            }
            (true, false) => net.right = -(q * net.left + g_r) / p_r,
            (false, true) => net.left = -(q * net.right + g_l) / p_l,
            (false, false) => {}
        }
        net
    }

    /// Which wheels stiction holds over the next step from `s` under wheel torques `tau`
    /// (N m): those within omega_eps of rest whose holding friction is within +-tau_s;
    /// both if both can be held, else the one that can (the smaller hold if either can).
    pub(crate) fn stuck_wheels(&self, s: &State<T>, tau: Wheels<T>) -> Wheels<bool> {
        let w = self.wheel_speeds_of(s);
        let near = Wheels::new(w.right.abs() <= self.omega_eps, w.left.abs() <= self.omega_eps);
        let heading = s.theta.sin_cos_libm();
        // The friction each wheel of `stuck` needs, as a share of tau_s (> 1: slips).
        let share = |stuck: Wheels<bool>| {
            let net = self.net_torques(&self.at_rest(s, stuck), tau, stuck, heading);
            let hold = |on: bool, tau: T, net: T| if on { (tau - net).abs() / self.tau_s } else { T::zero() };
            hold(stuck.right, tau.right, net.right).max(hold(stuck.left, tau.left, net.left))
        };
        let one = T::one();
        let none = Wheels::new(false, false);
        if !near.right && !near.left {
            return none;
        }
        if share(near) <= one {
            return near;
        }
        if !(near.right && near.left) {
            return none;
        }
        let (right, left) = (Wheels::new(true, false), Wheels::new(false, true));
        let (s_r, s_l) = (share(right), share(left));
        match (s_r <= one, s_l <= one) {
            (true, true) => {
                if s_r <= s_l {
                    right
                } else {
                    left
                }
            }
            (true, false) => right,
            (false, true) => left,
            (false, false) => none,
        }
    }

    /// [`Model::derivative_at_heading`] with the wheels in `stuck` held at rest by
    /// static friction (their speeds' derivatives zero); the others as always.
    pub(crate) fn derivative_stuck(&self, s: &State<T>, tau: Wheels<T>, stuck: Wheels<bool>) -> State<T> {
        let (sin, cos) = s.theta.sin_cos_libm();
        let w = self.wheel_speeds_of(s);
        let base = State { x: s.v * cos, y: s.v * sin, theta: s.omega, phi_r: w.right, phi_l: w.left, ..*s };
        if stuck.right && stuck.left {
            return State { v: T::zero(), omega: T::zero(), ..base };
        }
        let net = self.net_torques(s, tau, stuck, (sin, cos));
        let md = self.md;
        let mut forward = (net.right + net.left) / self.r + md * s.omega * s.omega;
        let mut moment = self.big_r_over_r * (net.right - net.left) - md * s.v * s.omega;
        if self.sloped {
            let (f_x, f_y) = self.downhill;
            forward = forward + (f_x * cos + f_y * sin);
            moment = moment + self.d * (f_y * cos - f_x * sin);
            if self.coupled {
                moment = moment - self.b * (f_x * cos + f_y * sin);
            }
        }
        if self.pushed {
            forward = forward + self.load.force_x;
            moment = moment + self.load.torque;
        }
        let (v, omega) = self.accelerations(forward, moment);
        State { v, omega, ..base }
    }

    /// The slip plant's wheel `i` within omega_eps of rest is held over the next step
    /// when the friction that holds it, tau - r F_x (N m, F_x the contact's force), is
    /// within +-tau_s.
    pub(crate) fn holds(&self, omega_wheel: T, tau: T, contact_torque: T) -> bool {
        self.has_stiction() && omega_wheel.abs() <= self.omega_eps && (tau - contact_torque).abs() <= self.tau_s
    }
}
