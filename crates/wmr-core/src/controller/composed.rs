//! The controller: an outer law composed with a wheel stage, run every `control_dt`.
//!
//! `update(t, measurement, reference)`: the law turns the measurement and the reference
//! state into a
//! [`super::WheelDemand`]; the wheel stage turns that into one drive command per wheel,
//! which the plant holds until the next tick.

use super::any::{AnyLaw, LawParams};
use super::law::{ControlErrors, Law, LawContext, WheelDemand};
use super::paper::PaperParams;
use super::wheel_stage::{WheelStage, WheelStageParams};
use crate::drive::Drive;
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use crate::math::{Twist2, Wheels};
use crate::obstacle::Obstacles;
use crate::reference::{Path, ReferenceState};
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

/// One control tick's result: the drive commands, held until the next tick, and the errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlOutput<T> {
    /// Per-wheel drive command: wheel torque demand (N m) or voltage (V), by drive kind.
    pub command: Wheels<T>,
    /// The law's errors, for logging.
    pub errors: ControlErrors<T>,
    /// The body twist the law demanded (v m/s, omega rad/s, before the wheel stage's
    /// limits), for logging (`/cmd_vel`); `None` for a law that demands wheel angles or
    /// torques ([`super::LawSpec::TWIST_DEMAND`]).
    pub twist_demand: Option<Twist2<T>>,
    /// The disturbance observer's estimate of the disturbance torque at each wheel (N m,
    /// [`super::observer`]), for logging; `None` without an observer.
    pub disturbance: Option<Wheels<T>>,
}

/// The twist of a law's demand, if it is one.
#[inline(always)]
fn twist_of<T: Copy>(demand: &WheelDemand<T>) -> Option<Twist2<T>> {
    match demand {
        WheelDemand::Twist(t) => Some(*t),
        _ => None,
    }
}

/// A law, a wheel stage and the control period: everything a `[controller]` table says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControllerParams<T> {
    /// The outer law and its keys.
    pub law: LawParams<T>,
    /// The wheel servos and the speed limit.
    pub wheels: WheelStageParams<T>,
    /// Control period, s (`control_dt`); a whole multiple of the plant step.
    pub control_dt: T,
    /// The disturbance observer on the wheels (`[controller.observer]`), for any law;
    /// `None` (the default): off.
    pub observer: Option<super::observer::DisturbanceObserverParams<T>>,
}

impl<T: Real> ControllerParams<T> {
    /// Default control period, s: 1 ms.
    pub fn default_control_dt() -> T {
        T::lit(1e-3)
    }

    /// The paper's law with the torque drive's wheel stage, 1 ms. For a DC-motor drive,
    /// set `wheels` to [`WheelStageParams::for_drive`] of it and the controller's model.
    pub fn paper() -> Self {
        Self::with_law(LawParams::Paper(PaperParams::paper()))
    }

    /// `law` with the torque drive's wheel stage defaults and the default period.
    pub fn with_law(law: LawParams<T>) -> Self {
        Self { law, wheels: WheelStageParams::default(), control_dt: Self::default_control_dt(), observer: None }
    }

    /// Validates everything and builds the controller for the controller's idea of the
    /// robot (`model`: r and R) and the drive it commands.
    pub fn build(&self, model: &RobotParams<T>, drive: &Drive<T>) -> Result<Controller<T, AnyLaw<T>>, ParamError> {
        self.build_lanes(model, drive)
    }

    /// [`ControllerParams::build`] for several runs side by side ([`crate::lane`]).
    pub fn build_lanes<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        drive: &Drive<T>,
    ) -> Result<Controller<L, AnyLaw<L>>, ParamError> {
        self.build_lanes_in(model, drive, &Obstacles::default())
    }

    /// [`ControllerParams::build_lanes`] with the obstacles on the controller's map (MPPI's
    /// `obstacles` critic reads them; the other laws do not).
    pub fn build_lanes_in<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        drive: &Drive<T>,
        obstacles: &Obstacles<T>,
    ) -> Result<Controller<L, AnyLaw<L>>, ParamError> {
        self.build_lanes_for_run(model, drive, obstacles, 0)
    }

    /// [`ControllerParams::build_lanes_in`] for run `run` ([`LawContext::run`]: the noise
    /// stream of a law that samples; run 0 is `build_lanes_in`'s).
    pub fn build_lanes_for_run<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        drive: &Drive<T>,
        obstacles: &Obstacles<T>,
        run: u64,
    ) -> Result<Controller<L, AnyLaw<L>>, ParamError> {
        let control_dt = check::positive("control_dt", self.control_dt)?;
        let ctx = LawContext {
            model,
            drive: &drive.params(),
            wheel_speed_max: self.wheels.wheel_speed_max,
            obstacles,
            control_dt,
            run,
        };
        let law = self.law.build_lanes_in(&ctx)?;
        let mut wheels = WheelStage::for_lanes(&self.wheels, model, drive, control_dt)?;
        if let Some(observer) = &self.observer {
            wheels = wheels.with_observer(observer.validate(model, drive, control_dt)?);
        }
        Ok(Controller::new(law, wheels))
    }
}

impl<T: Real> Default for ControllerParams<T> {
    fn default() -> Self {
        Self::paper()
    }
}

/// An outer law `L` and a wheel stage, run every `control_dt`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controller<T: Lane, L> {
    law: L,
    wheels: WheelStage<T>,
    control_dt: T::Scalar,
}

impl<T: Lane, L: Law<T>> Controller<T, L> {
    /// Composes a law and a wheel stage; the controller runs at the wheel stage's
    /// control period (build a law that integrates, like [`super::PaperLaw`], for the same).
    /// The wheel servos' anti-windup follows the law's ([`Law::anti_windup`]).
    pub fn new(law: L, wheels: WheelStage<T>) -> Self {
        let wheels = wheels.with_anti_windup(law.anti_windup());
        Self { law, control_dt: wheels.control_dt(), wheels }
    }

    /// One control tick at time `t` (s): drive commands (N m or V per wheel) from the
    /// measurement and the reference state at `t`, and the law's errors. `t` is now; the
    /// measurement's own time `m.t` is when it was taken (earlier, for a late sensor).
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn update(&mut self, t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> ControlOutput<T> {
        self.law.wheels_saturated(self.wheels.saturated());
        let out = self.law.update(t, m, r);
        let twist_demand = twist_of(&out.demand);
        let command = self.wheels.command(out.demand, m);
        ControlOutput { command, errors: out.errors, twist_demand, disturbance: self.wheels.disturbance_estimate() }
    }

    /// [`Controller::update`] with the reference's geometric path, for a path-following
    /// law ([`Law::update_on_path`]).
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn update_on_path(
        &mut self,
        t: T,
        m: &Measurement<T>,
        r: &ReferenceState<T>,
        path: &dyn Path<T>,
    ) -> ControlOutput<T> {
        self.law.wheels_saturated(self.wheels.saturated());
        let out = self.law.update_on_path(t, m, r, path);
        let twist_demand = twist_of(&out.demand);
        let command = self.wheels.command(out.demand, m);
        ControlOutput { command, errors: out.errors, twist_demand, disturbance: self.wheels.disturbance_estimate() }
    }

    /// [`Law::reaches_heading`] of the law: whether its runs are judged on the heading too.
    pub fn reaches_heading(&self) -> bool {
        self.law.reaches_heading()
    }

    /// The controller for a plant whose wheels slip (`on`) or roll: its wheel stage's
    /// speed guard then acts on a wheel's own inertia ([`WheelStage::with_slipping_wheels`]).
    pub fn with_slipping_wheels(mut self, on: bool) -> Self {
        self.wheels = self.wheels.with_slipping_wheels(on);
        self
    }

    /// Clears every integrator and memory, as at t = 0.
    pub fn reset(&mut self) {
        self.reset_lanes(T::Mask::splat(true));
    }

    /// [`Controller::reset`] of the runs in `lanes` only (several runs side by side).
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.law.reset_lanes(lanes);
        self.wheels.reset_lanes(lanes);
    }

    /// Control period, s.
    pub fn control_dt(&self) -> T::Scalar {
        self.control_dt
    }

    /// True when the law holds ([`Law::holding`]).
    pub fn holding(&self) -> T::Mask {
        self.law.holding()
    }

    /// What the wheel servos' integrators have yet to move each wheel, rad
    /// ([`WheelStage::integrator_travel`]).
    pub fn integrator_travel(&self) -> Wheels<T> {
        self.wheels.integrator_travel()
    }

    /// The outer law.
    pub fn law(&self) -> &L {
        &self.law
    }

    /// The wheel stage.
    pub fn wheels(&self) -> &WheelStage<T> {
        &self.wheels
    }
}
