//! The plant: the true robot and its drives, stepped by RK4 under held drive commands.
//!
//! This is the truth of a simulation; the controller never reads it directly (it sees a
//! [`crate::sensor::Measurement`]). Used on its own it is the model for
//! hardware-in-the-loop: apply a command, step, read the state.

use crate::drive::Drive;
use crate::dynamics::Model;
use crate::error::{ParamError, check};
use crate::integrator::{Rhs, rk4_step_of};
use crate::kinematics;
use crate::lane::Lane;
use crate::math::{Pose2, Wheels};
use crate::outcome::Termination;
use crate::push::Pushes;
use crate::state::{STATE_LEN, State};
use crate::traction::{Contact, SlipExtra, Traction};
use crate::world::World;
use crate::{Real, Robot};

/// Half-width of the box (m) point C must stay in; outside it the run has diverged.
pub const DIVERGENCE_BOX_M: f64 = 1000.0;

/// The most RK4 sub-steps a slip plant takes in one [`Plant::step`]
/// ([`Plant::substeps`]); a step that would need more is refused where it is checked
/// (`sim.dt`, the C API's `dt`).
pub const MAX_SLIP_SUBSTEPS: u32 = 1000;

/// The share of the RK4 stability limit a sub-step of a slip plant uses at most:
/// dt * stiffness / n <= 0.9 x 2.785 ([`Plant::substeps`]).
pub const SLIP_SUBSTEP_SHARE: f64 = 0.9;

/// The robot, its drive and its state, with a drive command held between control ticks.
#[derive(Clone, Copy, Debug)]
pub struct Plant<T> {
    robot: Robot<T>,
    /// The robot's equations with their constants precomputed once.
    model: Model<T>,
    drive: Drive<T>,
    state: State<T>,
    /// Per-wheel drive command held since the last [`Plant::apply`]: N m or V by drive.
    command: Wheels<T>,
    /// Wheel torques of the held command when they do not depend on speed, N m.
    held_torque: Wheels<T>,
    /// How the wheels hold the ground ([`crate::traction`]); rolling by default.
    traction: Traction<T>,
    /// The ground (a payload step rebuilds the model on it).
    world: World<T>,
    /// The slip plant's speeds beyond [`State`] (zero and unused when rolling).
    extra: SlipExtra<T>,
    /// A slip plant's [`Plant::stiffness`], 1/s, computed once for its sub-steps (zero
    /// when rolling).
    slip_stiffness: T,
    /// The pushes ([`crate::push`]); none by default.
    pushes: Pushes<T>,
    /// A payload that appears at a time ([`Plant::with_payload_at`]); none by default.
    payload_step: Option<PayloadStep<T>>,
}

/// The robot the plant swaps in at `t` (a payload put on it), and back before `t`.
#[derive(Clone, Copy, Debug)]
struct PayloadStep<T> {
    /// When the payload appears, s.
    t: T,
    /// The robot and its model not in use now: the one carrying the payload before `t`,
    /// the one without it from `t` on.
    other: Robot<T>,
    other_model: Model<T>,
    /// True from `t` on (the payload carried).
    carried: bool,
}

impl<T: Real> Plant<T> {
    /// At rest at `start` (x, y in m, theta in rad, world frame), encoders at zero, no
    /// command. Errors name `start.x`, `start.y` or `start.theta`.
    pub fn new(robot: Robot<T>, drive: Drive<T>, start: Pose2<T>) -> Result<Self, ParamError> {
        Self::on(robot, drive, World::flat(), start)
    }

    /// As [`Plant::new`], on `world`'s ground (a slope).
    pub fn on(robot: Robot<T>, drive: Drive<T>, world: World<T>, start: Pose2<T>) -> Result<Self, ParamError> {
        check::finite("start.x", start.x)?;
        check::finite("start.y", start.y)?;
        check::finite("start.theta", start.theta)?;
        Ok(Self {
            robot,
            model: Model::on(&robot, &world),
            drive,
            state: State::at_rest(start),
            command: Wheels::default(),
            held_torque: Wheels::default(),
            traction: Traction::Rolling,
            world,
            extra: SlipExtra::default(),
            slip_stiffness: T::zero(),
            pushes: Pushes::default(),
            payload_step: None,
        })
    }

    /// The same plant whose robot becomes `carrying` at time `t` (s): a payload put on
    /// it then (`[world.payload] t`, [`crate::Payload::carried_by`] of this plant's robot).
    /// Each step that starts at or after `t` uses the composite's mass, centre of mass and
    /// inertia (a step before `t`, the robot's own); the state is kept as it is (the
    /// payload arrives moving with the platform). Errors name `payload.t`: `t` negative or
    /// not finite, or a slip plant (its contact model is built for one robot).
    pub fn with_payload_at(mut self, t: T, carrying: Robot<T>) -> Result<Self, ParamError> {
        check::non_negative("payload.t", t)?;
        check::finite("payload.t", t)?;
        if self.slips() {
            return Err(check::out_of_range("payload.t", "the slip plant does not step a payload that appears", t));
        }
        let other_model = Model::on(&carrying, &self.world);
        self.payload_step = Some(PayloadStep { t, other: carrying, other_model, carried: false });
        Ok(self)
    }

    /// When a payload appears ([`Plant::with_payload_at`]), s; `None` without one.
    pub fn payload_time(&self) -> Option<T> {
        self.payload_step.map(|p| p.t)
    }

    /// The robot the step from `t` (s) uses: swapped for the other of a payload step
    /// when `t` crossed its time.
    #[inline(always)]
    fn carry_at(&mut self, t: T) {
        if let Some(p) = &mut self.payload_step {
            let carried = t >= p.t;
            if carried != p.carried {
                core::mem::swap(&mut self.robot, &mut p.other);
                core::mem::swap(&mut self.model, &mut p.other_model);
                p.carried = carried;
            }
        }
    }

    /// The same plant with `pushes` acting on it ([`crate::push`]).
    pub fn with_pushes(mut self, pushes: Pushes<T>) -> Self {
        self.pushes = pushes;
        self
    }

    /// The pushes.
    pub fn pushes(&self) -> &Pushes<T> {
        &self.pushes
    }

    /// The same plant with `traction` ([`crate::TractionParams::validate`], built for
    /// this plant's robot and world); a slip plant starts with its wheels at rest.
    pub fn with_traction(mut self, traction: Traction<T>) -> Self {
        self.traction = traction;
        self.slip_stiffness = if self.slips() { self.stiffness() } else { T::zero() };
        self
    }

    /// The traction model.
    pub fn traction(&self) -> &Traction<T> {
        &self.traction
    }

    /// True for a slip plant ([`Traction::Slip`]).
    pub fn slips(&self) -> bool {
        matches!(self.traction, Traction::Slip(_))
    }

    /// The slip plant's lateral velocity and wheel speeds (zero for a rolling plant).
    pub fn slip_extra(&self) -> &SlipExtra<T> {
        &self.extra
    }

    /// The contact of each wheel with the ground now: slip velocities, forces, loads
    /// (zero for a rolling plant, whose contact forces the model never needs).
    pub fn contact(&self) -> Contact<T> {
        match &self.traction {
            Traction::Slip(slip) => slip.contact_of(&self.state, &self.extra),
            Traction::Rolling => Contact::default(),
        }
    }

    /// The robot (the truth, which a controller's model may differ from).
    pub fn robot(&self) -> &Robot<T> {
        &self.robot
    }

    /// The drive.
    pub fn drive(&self) -> &Drive<T> {
        &self.drive
    }

    /// The current state.
    pub fn state(&self) -> &State<T> {
        &self.state
    }

    /// Puts the plant in state `s` (hardware-in-the-loop, tests): the held command stays;
    /// a slip plant's wheels are set rolling (no slip, no lateral velocity, contacts
    /// relaxed).
    pub fn set_state(&mut self, s: State<T>) {
        self.state = s;
        if self.slips() {
            self.extra = SlipExtra { wheel_speeds: s.wheel_speeds(self.robot.params()), ..SlipExtra::default() };
        }
    }

    /// Puts a slip plant in state (`s`, `extra`); on a rolling plant `extra` is ignored.
    pub fn set_slip_state(&mut self, s: State<T>, extra: SlipExtra<T>) {
        self.state = s;
        if self.slips() {
            self.extra = extra;
        }
    }

    /// The held drive command (N m or V per wheel).
    pub fn command(&self) -> Wheels<T> {
        self.command
    }

    /// Holds `command` (per wheel: wheel-torque demand in N m, or volts, by drive) until
    /// the next call: the zero-order hold of a digital controller. The drive's deadband
    /// (`[drive] deadband`) zeroes a small command here: [`Plant::command`] is what the
    /// motor driver passes on.
    #[inline(always)]
    pub fn apply(&mut self, command: Wheels<T>) {
        // The driver's deadband acts here, in the plant ([`Drive::deadband`]).
        let command = self.drive.deadband(command);
        self.command = command;
        if self.drive.is_speed_independent() {
            let d = self.drive;
            self.held_torque = command.map(|c| d.wheel_torque(c, T::zero()));
        }
    }

    /// The stiffness of the plant at rest, 1/s: the fastest decay rate lambda of its
    /// speeds, linearized at zero speed. Each wheel's friction and drive then act as a
    /// damper b = b_v + tau_c / omega_eps + (drive's speed damping), N m s/rad, and
    ///
    /// ```text
    /// v' = -2 b v / (r^2 M_r11),   omega' = -2 b R^2 omega / (r^2 M_r22)
    /// lambda = 2 b / r^2 * max(1 / M_r11, R^2 / M_r22)
    /// ```
    ///
    /// RK4 at step dt is stable for this plant exactly when dt lambda <
    /// [`crate::integrator::RK4_REAL_STABILITY_LIMIT`]; a Coulomb friction with a small
    /// `coulomb_speed` makes lambda large (tau_c = 0.075 N m and omega_eps = 1e-3 rad/s
    /// give 2,780 1/s on the paper's robot, the limit at dt = 1 ms).
    ///
    /// A slip plant's stiffness is [`crate::traction::Slip::stiffness`] with that b.
    pub fn stiffness(&self) -> T {
        let p = self.robot.params();
        let coulomb = if p.coulomb_friction > T::zero() { p.coulomb_friction / p.coulomb_speed } else { T::zero() };
        let b = p.viscous_friction + coulomb + self.drive.speed_damping();
        if let Traction::Slip(slip) = &self.traction {
            return slip.stiffness(b);
        }
        let (m11, m22) = self.robot.reduced_inertia();
        let r2 = p.wheel_radius * p.wheel_radius;
        let two = T::lit(2.0);
        (two * b / r2) * m11.recip().max(p.half_track * p.half_track / m22)
    }

    /// The largest plant step (s) one RK4 step integrates stably: limit /
    /// [`Plant::stiffness`] (infinite for a plant without damping).
    pub fn max_stable_dt(&self) -> T {
        T::lit(crate::integrator::RK4_REAL_STABILITY_LIMIT) / self.stiffness()
    }

    /// The RK4 sub-steps [`Plant::step`] takes for a step of `dt` (s), or `None` when it
    /// cannot take it stably.
    ///
    /// A rolling plant takes one step, stable while dt < [`Plant::max_stable_dt`]. A slip
    /// plant's contacts are stiffer than its step need be (a tyre that holds its force
    /// within a few per cent of slip: [`crate::TractionParams`]'s `slip_speed`), so it
    /// splits the step: one RK4 step while dt * stiffness < 2.785, as before, else
    ///
    /// ```text
    /// n = ceil(dt * stiffness / (0.9 * 2.785))      sub-steps of dt / n
    /// ```
    ///
    /// ([`SLIP_SUBSTEP_SHARE`]), each stable with a margin; `None` beyond
    /// [`MAX_SLIP_SUBSTEPS`]. The CLI's `check` shows n; the C API and the firmware step
    /// through this same function, so every surface takes the same sub-steps.
    pub fn substeps(&self, dt: T) -> Option<u32> {
        let limit = T::lit(crate::integrator::RK4_REAL_STABILITY_LIMIT);
        if !self.slips() {
            return (dt < self.max_stable_dt()).then_some(1);
        }
        let x = dt * self.slip_stiffness;
        if x < limit {
            return Some(1);
        }
        let n = (x / (T::lit(SLIP_SUBSTEP_SHARE) * limit)).ceil();
        (n <= T::lit(f64::from(MAX_SLIP_SUBSTEPS))).then(|| n.to_f64_lossless() as u32)
    }

    /// The largest plant step (s) [`Plant::step`] takes stably ([`Plant::substeps`]):
    /// [`Plant::max_stable_dt`] for a rolling plant, 1000 sub-steps at 90 % of it for a
    /// slip plant.
    pub fn max_step_dt(&self) -> T {
        if !self.slips() {
            return self.max_stable_dt();
        }
        let substeps = T::lit(f64::from(MAX_SLIP_SUBSTEPS) * SLIP_SUBSTEP_SHARE);
        substeps * T::lit(crate::integrator::RK4_REAL_STABILITY_LIMIT) / self.slip_stiffness
    }

    /// True wheel speeds, rad/s: each wheel's own speed (for a rolling plant, the
    /// speeds (v, omega) imply).
    #[inline(always)]
    pub fn wheel_speeds(&self) -> Wheels<T> {
        if self.slips() { self.extra.wheel_speeds } else { self.state.wheel_speeds(self.robot.params()) }
    }

    /// Wheel torques (N m) the held command gives at the current state.
    #[inline(always)]
    pub fn wheel_torque(&self) -> Wheels<T> {
        if self.slips() && !self.drive.is_speed_independent() {
            let (d, c, w) = (self.drive, self.command, self.extra.wheel_speeds);
            return Wheels::new(d.wheel_torque(c.right, w.right), d.wheel_torque(c.left, w.left));
        }
        self.wheel_torque_at(&self.state)
    }

    #[inline(always)]
    fn wheel_torque_at(&self, s: &State<T>) -> Wheels<T> {
        self.wheel_torque_lanes(s, self.command, self.held_torque)
    }

    /// The wheel torques (N m) the drive gives in state `s` under `command`, whose
    /// torque is `held_torque` when the drive does not depend on the wheel speed; for one
    /// run or several side by side ([`crate::lane`]).
    #[inline(always)]
    pub(crate) fn wheel_torque_lanes<L: Lane<Scalar = T>>(
        &self,
        s: &State<L>,
        command: Wheels<L>,
        held_torque: Wheels<L>,
    ) -> Wheels<L> {
        if self.drive.is_speed_independent() {
            held_torque
        } else {
            let w = kinematics::wheel_speeds_lanes(self.robot.params(), s.v, s.omega);
            Wheels::new(self.drive.wheel_torque(command.right, w.right), self.drive.wheel_torque(command.left, w.left))
        }
    }

    /// The torques (N m) `command` gives a speed-independent drive (the torque drive),
    /// held over a step; for one run or several side by side.
    #[inline(always)]
    pub(crate) fn held_torque_lanes<L: Lane<Scalar = T>>(&self, command: Wheels<L>) -> Wheels<L> {
        let d = self.drive;
        if d.is_speed_independent() {
            let zero = L::splat(T::zero());
            Wheels::new(d.wheel_torque(command.right, zero), d.wheel_torque(command.left, zero))
        } else {
            command
        }
    }

    /// One RK4 step of `dt` (s) from `state` at `t` (s) under `command` (held
    /// torque `held_torque`, see [`Plant::wheel_torque_lanes`]), not checked: for one run
    /// (`L = T`, what [`Plant::step`] does) or several side by side ([`crate::lane`]),
    /// the same operations in the same order.
    #[inline(always)]
    pub(crate) fn advance<L: Lane<Scalar = T>>(
        &self,
        state: &State<L>,
        command: Wheels<L>,
        held_torque: Wheels<L>,
        t: L,
        dt: L,
    ) -> State<L> {
        let mut f = PlantRhs { plant: self, command, held_torque };
        State::from_array(rk4_step_of(&mut f, t, &state.to_array(), dt))
    }

    /// Advances the state by one RK4 step of `dt` (s) from time `t` (s) under the held
    /// command; a slip plant whose contacts are too stiff for `dt` takes
    /// [`Plant::substeps`] equal steps instead (at most [`MAX_SLIP_SUBSTEPS`]). A result
    /// that is not finite or leaves the 1 km box is refused: the state stays at the last
    /// good one and the reason is returned.
    #[inline]
    pub fn step(&mut self, t: T, dt: T) -> Result<(), Termination> {
        if let Traction::Slip(mut slip) = self.traction {
            let n = self.substeps(dt).unwrap_or(MAX_SLIP_SUBSTEPS);
            if !self.pushes.is_empty() {
                // Each sub-step holds the pushes' mean over itself.
                let h = dt / T::lit(f64::from(n));
                for k in 0..n {
                    let t_k = t + T::lit(f64::from(k)) * h;
                    slip.set_load(self.pushes.mean_over(t_k, h));
                    self.step_slip(&slip, t_k, h)?;
                }
                return Ok(());
            }
            if n == 1 {
                return self.step_slip(&slip, t, dt);
            }
            // The sub-steps' times t + k h: each from t, so no rounding accumulates.
            let h = dt / T::lit(f64::from(n));
            for k in 0..n {
                self.step_slip(&slip, t + T::lit(f64::from(k)) * h, h)?;
            }
            return Ok(());
        }
        self.rk4_step(t, dt)
    }

    /// One RK4 step of `dt` (s) from `t` (s), never split ([`Plant::step`] splits a slip
    /// plant's step the contacts are too stiff for; this is what it does otherwise), with
    /// the same refusals.
    #[inline]
    pub fn rk4_step(&mut self, t: T, dt: T) -> Result<(), Termination> {
        if let Traction::Slip(mut slip) = self.traction {
            if !self.pushes.is_empty() {
                slip.set_load(self.pushes.mean_over(t, dt));
            }
            return self.step_slip(&slip, t, dt);
        }
        self.carry_at(t);
        if !self.pushes.is_empty() {
            self.model.set_load(self.pushes.mean_over(t, dt));
        }
        let next = if self.model.has_stiction() {
            self.advance_sticking(t, dt)
        } else {
            self.advance(&self.state, self.command, self.held_torque, t, dt)
        };
        let bound = T::lit(DIVERGENCE_BOX_M);
        if !all_finite(&next) {
            return Err(Termination::NonFinite);
        }
        if next.x.abs() > bound || next.y.abs() > bound {
            return Err(Termination::LeftBox);
        }
        self.state = next;
        Ok(())
    }
}

impl<T: Real> Plant<T> {
    /// One RK4 step of `dt` (s) from `t` (s) of a rolling plant with stiction: the wheels
    /// it holds are decided at the step's start ([`Model::stuck_wheels`]), set at rest,
    /// and kept so through the four stages (docs/model.md, "Stiction").
    fn advance_sticking(&self, t: T, dt: T) -> State<T> {
        let tau = self.wheel_torque_at(&self.state);
        let stuck = self.model.stuck_wheels(&self.state, tau);
        let start = self.model.at_rest(&self.state, stuck);
        let mut f = StuckRhs { plant: self, stuck };
        State::from_array(rk4_step_of(&mut f, t, &start.to_array(), dt))
    }

    /// [`Plant::step`] of a slip plant, with the same refusals.
    #[inline(never)]
    fn step_slip(&mut self, slip: &crate::traction::Slip<T>, t: T, dt: T) -> Result<(), Termination> {
        let (next, extra) = slip.step(&self.state, &self.extra, &self.drive, self.command, t, dt);
        let e = [extra.deflection_x.right, extra.deflection_x.left, extra.deflection_y.right, extra.deflection_y.left];
        let extra_finite = extra.v_lat.is_finite()
            && extra.wheel_speeds.right.is_finite()
            && extra.wheel_speeds.left.is_finite()
            && e.iter().all(|c| c.is_finite());
        if !next.is_finite() || !extra_finite {
            return Err(Termination::NonFinite);
        }
        let bound = T::lit(DIVERGENCE_BOX_M);
        if next.x.abs() > bound || next.y.abs() > bound {
            return Err(Termination::LeftBox);
        }
        self.state = next;
        self.extra = extra;
        Ok(())
    }
}

/// True (per lane) when every component of `s` is finite: the same test as
/// [`State::is_finite`], written branch-free for the hot path. 0 c is a zero for a finite
/// c and NaN for an infinite or NaN one, and a sum of zeros cannot overflow, so the sum is
/// zero exactly when all seven components are finite.
#[inline(always)]
pub(crate) fn all_finite<L: Lane>(s: &State<L>) -> L::Mask {
    let z = L::default();
    let sum = s.x * z + s.y * z + s.theta * z + s.v * z + s.omega * z + s.phi_r * z + s.phi_l * z;
    sum.eq(z)
}

/// The plant's right-hand side under a held command, for one run or several side by side.
struct PlantRhs<'a, T, L> {
    plant: &'a Plant<T>,
    command: Wheels<L>,
    held_torque: Wheels<L>,
}

impl<T: Real, L: Lane<Scalar = T>> Rhs<L, STATE_LEN> for PlantRhs<'_, T, L> {
    // Inlined into each RK4 stage on hosts (the lanes need it); a size-optimized firmware
    // keeps one copy.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn eval(&mut self, _t: L, y: &[L; STATE_LEN]) -> [L; STATE_LEN] {
        let s = State::from_array(*y);
        self.plant.derivative_under(&s, self.command, self.held_torque, s.theta.sin_cos()).to_array()
    }
}

/// [`PlantRhs`] of one run with stiction: the wheels in `stuck` held at rest.
struct StuckRhs<'a, T> {
    plant: &'a Plant<T>,
    stuck: Wheels<bool>,
}

impl<T: Real> Rhs<T, STATE_LEN> for StuckRhs<'_, T> {
    #[inline]
    fn eval(&mut self, _t: T, y: &[T; STATE_LEN]) -> [T; STATE_LEN] {
        let s = State::from_array(*y);
        let plant = self.plant;
        let tau = plant.wheel_torque_lanes(&s, plant.command, plant.held_torque);
        plant.model.derivative_stuck(&s, tau, self.stuck).to_array()
    }
}

/// The lanes' state with the heading's cosine and sine after it: [`STATE_LEN`] + 2.
pub(crate) const CARRIED_LEN: usize = STATE_LEN + 2;

/// [`PlantRhs`] with cos(theta) and sin(theta) as two more states, whose derivatives
/// are -omega sin(theta) and omega cos(theta): no stage computes a sine.
struct CarriedHeadingRhs<'a, T, L> {
    plant: &'a Plant<T>,
    command: Wheels<L>,
    held_torque: Wheels<L>,
}

impl<T: Real, L: Lane<Scalar = T>> Rhs<L, CARRIED_LEN> for CarriedHeadingRhs<'_, T, L> {
    #[inline(always)]
    fn eval(&mut self, _t: L, y: &[L; CARRIED_LEN]) -> [L; CARRIED_LEN] {
        // Written out, not `array::from_fn`: its closure is left as a call per element
        // in the AVX-512 build.
        let (s, (cos, sin)) = split_carried(y);
        let d = self.plant.derivative_under(&s, self.command, self.held_torque, (sin, cos));
        [d.x, d.y, d.theta, d.v, d.omega, d.phi_r, d.phi_l, -(s.omega * sin), s.omega * cos]
    }
}

/// The state and the (cos, sin) of a carried-heading vector ([`CARRIED_LEN`]).
#[inline(always)]
fn split_carried<L: Copy>(y: &[L; CARRIED_LEN]) -> (State<L>, (L, L)) {
    let [x, y, theta, v, omega, phi_r, phi_l, cos, sin] = *y;
    (State { x, y, theta, v, omega, phi_r, phi_l }, (cos, sin))
}

impl<T: Real> Plant<T> {
    /// The state's time derivative under `command` (held torque `held_torque`, see
    /// [`Plant::wheel_torque_lanes`]), with `heading` = (sin, cos) of `s.theta`.
    #[inline(always)]
    fn derivative_under<L: Lane<Scalar = T>>(
        &self,
        s: &State<L>,
        command: Wheels<L>,
        held_torque: Wheels<L>,
        heading: (L, L),
    ) -> State<L> {
        let model = &self.model;
        if self.drive.is_speed_independent() && !model.has_coulomb() && !model.is_sloped() {
            return model.derivative_at_heading::<L, false, false>(s, held_torque, heading);
        }
        let tau = self.wheel_torque_lanes(s, command, held_torque);
        match (model.has_coulomb(), model.is_sloped()) {
            (true, true) => model.derivative_at_heading::<L, true, true>(s, tau, heading),
            (true, false) => model.derivative_at_heading::<L, true, false>(s, tau, heading),
            (false, true) => model.derivative_at_heading::<L, false, true>(s, tau, heading),
            (false, false) => model.derivative_at_heading::<L, false, false>(s, tau, heading),
        }
    }

    /// [`Plant::advance`] for the lanes, with `heading` = (cos, sin) of the state's
    /// heading carried through the step as two more states (their derivatives
    /// -omega sin and omega cos); returns the next state and its (cos, sin).
    ///
    /// Why: the four stages' sin and cos were 29 % of the lanes' time on the
    /// million-start map (perf, AMD Zen 4); carried, they cost a stage two products and
    /// the step a few more sums.
    /// It is the same RK4 of the same equations, with (cos, sin) as states rather than
    /// functions of theta: the two agree to the steps' truncation and rounding, not bit
    /// for bit (over 100 s at 1 ms and 0.9 rad/s, within 1e-11; the test below).
    #[inline(always)]
    pub(crate) fn advance_carrying_heading<L: Lane<Scalar = T>>(
        &self,
        state: &State<L>,
        heading: (L, L),
        command: Wheels<L>,
        held_torque: Wheels<L>,
        dt: L,
    ) -> (State<L>, (L, L)) {
        let mut f = CarriedHeadingRhs { plant: self, command, held_torque };
        let State { x, y, theta, v, omega, phi_r, phi_l } = *state;
        let y = [x, y, theta, v, omega, phi_r, phi_l, heading.0, heading.1];
        split_carried(&rk4_step_of(&mut f, L::default(), &y, dt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DriveParams;

    /// Drives `plant` under fixed wheel torques for `t_s` seconds in steps of `dt` (s),
    /// once with theta's sin and cos at each stage and once with them carried; returns
    /// the largest |(cos, sin) carried - (cos, sin) of the carried run's theta| and the
    /// largest distance between the two runs' positions (m), over the run, and its
    /// turn rate at the end (rad/s).
    fn carried_against_computed(dt: f64, t_s: f64) -> (f64, f64, f64) {
        // The paper's robot with viscous friction, so that fixed torques give a steady
        // arc rather than a speed that grows without end.
        let robot = crate::RobotParams { viscous_friction: 0.05, ..crate::RobotParams::paper() }.validate().unwrap();
        let drive = DriveParams::default().validate(&robot).unwrap();
        let mut plant = Plant::new(robot, drive, Pose2::new(0.3, -0.2, 2.0)).unwrap();
        plant.apply(Wheels::new(1.5, 0.3));
        let (mut a, mut b) = (plant.state, plant.state);
        let (sin, cos) = b.theta.sin_cos_libm();
        let mut heading = (cos, sin);
        let (mut drift, mut apart) = (0.0f64, 0.0f64);
        for _ in 0..(t_s / dt).round() as usize {
            a = plant.advance(&a, plant.command, plant.held_torque, 0.0, dt);
            (b, heading) = plant.advance_carrying_heading(&b, heading, plant.command, plant.held_torque, dt);
            let (sin, cos) = b.theta.sin_cos_libm();
            drift = drift.max((heading.0 - cos).abs()).max((heading.1 - sin).abs());
            apart = apart.max((a.x - b.x).hypot(a.y - b.y));
        }
        (drift, apart, b.omega)
    }

    /// The carried (cos, sin) stays on theta's: at 1 ms, 100 s of turning at about
    /// 0.9 rad/s leave it within 1e-10 (7.7e-12 measured: the steps' rounding and
    /// truncation) and the two runs' positions within 1e-9 m (1.9e-11 measured); at steps
    /// long enough for the truncation to dominate (10 and 20 ms), the gap grows as dt^4,
    /// the order of RK4's global error: it is truncation, where wrong carried derivatives
    /// would leave a gap that does not shrink with dt.
    #[test]
    fn carried_heading_agrees_with_the_heading_to_the_step_error() {
        let (drift, apart, omega) = carried_against_computed(1e-3, 100.0);
        assert!(omega.abs() > 0.5, "the robot turns: {omega} rad/s");
        assert!(drift < 1e-10 && apart < 1e-9, "at 1 ms: drift {drift:e}, positions {apart:e} m apart");
        let (coarse, _, _) = carried_against_computed(20e-3, 100.0);
        let (fine, _, _) = carried_against_computed(10e-3, 100.0);
        let order = (coarse / fine).log2();
        assert!((3.5..4.5).contains(&order), "drift {fine:e} at 10 ms, {coarse:e} at 20 ms: order {order}");
    }
}
