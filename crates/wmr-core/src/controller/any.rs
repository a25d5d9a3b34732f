//! One controller type over every law, selected at run time by `controller.kind`
//! ("paper", "polar", "lyapunov"): an enum dispatched by `match` (no `dyn`, no alloc).
//!
//! Logged errors ([`super::ControlErrors`]) by law:
//!
//! | kind | dl | e_theta | e_s |
//! |---|---|---|---|
//! | paper | distance to goal (16) | wrap(theta_R - theta) (21), towards the false target | dl cos(theta_R - theta) (18) |
//! | polar, lyapunov | distance to goal | wrap(theta_d - theta), the final heading error | (x_d - x) cos(theta) + (y_d - y) sin(theta) |
//!
//! e_s of the polar-coordinate laws is the signed distance to the goal along the
//! heading (negative when the goal is behind).

use super::{
    ControlOutput, Controller, LyapunovController, LyapunovParams, Measurement, PaperController, PaperParams,
    PaperSaturated, PolarController, PolarParams,
};
use crate::drive::Drive;
use crate::math::Pose2;
use crate::{ParamError, Real, Robot};

/// The law named by `controller.kind`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ControllerKind {
    /// The paper's law, [`PaperController`] (`"paper"`).
    #[default]
    Paper,
    /// Astolfi's polar law, [`PolarController`] (`"polar"`).
    Polar,
    /// Aicardi et al.'s Lyapunov law, [`LyapunovController`] (`"lyapunov"`).
    Lyapunov,
}

impl ControllerKind {
    /// Every kind, in documentation order.
    pub const ALL: [ControllerKind; 3] = [ControllerKind::Paper, ControllerKind::Polar, ControllerKind::Lyapunov];

    /// The scenario name: "paper", "polar" or "lyapunov".
    pub fn name(self) -> &'static str {
        match self {
            ControllerKind::Paper => "paper",
            ControllerKind::Polar => "polar",
            ControllerKind::Lyapunov => "lyapunov",
        }
    }

    /// The kind of a scenario name, if it is one of [`ControllerKind::name`]'s.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// This kind's default parameters (torque-drive servo gains).
    pub fn default_params<T: Real>(self) -> ControllerParams<T> {
        match self {
            ControllerKind::Paper => {
                ControllerParams::Paper { params: PaperParams::paper(), wheel_speed_max: T::infinity() }
            }
            ControllerKind::Polar => ControllerParams::Polar(PolarParams::default()),
            ControllerKind::Lyapunov => ControllerParams::Lyapunov(LyapunovParams::default()),
        }
    }
}

/// `[controller]` parameters of any kind, before validation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControllerParams<T> {
    /// `kind = "paper"`.
    Paper {
        /// The paper law's parameters.
        params: PaperParams<T>,
        /// `wheel_speed_max`, rad/s: limit on the speed of the wheel angle references
        /// ([`PaperSaturated`]); infinity (the default) runs [`PaperController`] unchanged.
        wheel_speed_max: T,
    },
    /// `kind = "polar"`.
    Polar(PolarParams<T>),
    /// `kind = "lyapunov"`.
    Lyapunov(LyapunovParams<T>),
}

impl<T: Real> Default for ControllerParams<T> {
    /// The paper's law with the SPEC defaults and no wheel speed limit.
    fn default() -> Self {
        ControllerKind::Paper.default_params()
    }
}

impl<T: Real> ControllerParams<T> {
    /// Which law.
    pub fn kind(&self) -> ControllerKind {
        match self {
            ControllerParams::Paper { .. } => ControllerKind::Paper,
            ControllerParams::Polar(_) => ControllerKind::Polar,
            ControllerParams::Lyapunov(_) => ControllerKind::Lyapunov,
        }
    }

    /// The control period, s.
    pub fn control_dt(&self) -> T {
        match self {
            ControllerParams::Paper { params, .. } => params.control_dt,
            ControllerParams::Polar(p) => p.control_dt,
            ControllerParams::Lyapunov(p) => p.control_dt,
        }
    }

    /// The per-wheel speed limit, rad/s (infinite when off).
    pub fn wheel_speed_max(&self) -> T {
        match self {
            ControllerParams::Paper { wheel_speed_max, .. } => *wheel_speed_max,
            ControllerParams::Polar(p) => p.wheel_speed_max,
            ControllerParams::Lyapunov(p) => p.wheel_speed_max,
        }
    }

    /// Validates and builds the controller for this robot, drive and goal (m, m, rad).
    ///
    /// `Paper` with an infinite `wheel_speed_max` builds the plain [`PaperController`]
    /// (bit for bit the paper law); a finite one builds [`PaperSaturated`].
    pub fn build(self, robot: &Robot<T>, drive: &Drive<T>, goal: Pose2<T>) -> Result<AnyController<T>, ParamError> {
        Ok(match self {
            ControllerParams::Paper { params, wheel_speed_max } => {
                if wheel_speed_max == T::infinity() {
                    AnyController::Paper(PaperController::new(params, robot, drive, goal)?)
                } else {
                    AnyController::PaperSaturated(PaperSaturated::new(params, wheel_speed_max, robot, drive, goal)?)
                }
            }
            ControllerParams::Polar(p) => AnyController::Polar(PolarController::new(p, robot, drive, goal)?),
            ControllerParams::Lyapunov(p) => AnyController::Lyapunov(LyapunovController::new(p, robot, drive, goal)?),
        })
    }
}

/// Any of the laws, dispatched by `match`. Implements [`Controller`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyController<T> {
    /// The paper's law, no wheel speed limit.
    Paper(PaperController<T>),
    /// The paper's law with rate-limited wheel references.
    PaperSaturated(PaperSaturated<T>),
    /// Astolfi's polar law.
    Polar(PolarController<T>),
    /// Aicardi et al.'s Lyapunov law.
    Lyapunov(LyapunovController<T>),
}

impl<T: Real> AnyController<T> {
    /// Which law.
    pub fn kind(&self) -> ControllerKind {
        match self {
            AnyController::Paper(_) | AnyController::PaperSaturated(_) => ControllerKind::Paper,
            AnyController::Polar(_) => ControllerKind::Polar,
            AnyController::Lyapunov(_) => ControllerKind::Lyapunov,
        }
    }
}

impl<T: Real> Controller<T> for AnyController<T> {
    #[inline]
    fn update(&mut self, m: &Measurement<T>) -> ControlOutput<T> {
        match self {
            AnyController::Paper(c) => c.update(m),
            AnyController::PaperSaturated(c) => c.update(m),
            AnyController::Polar(c) => c.update(m),
            AnyController::Lyapunov(c) => c.update(m),
        }
    }

    fn reset(&mut self) {
        match self {
            AnyController::Paper(c) => c.reset(),
            AnyController::PaperSaturated(c) => c.reset(),
            AnyController::Polar(c) => c.reset(),
            AnyController::Lyapunov(c) => c.reset(),
        }
    }

    fn control_dt(&self) -> T {
        match self {
            AnyController::Paper(c) => c.control_dt(),
            AnyController::PaperSaturated(c) => c.control_dt(),
            AnyController::Polar(c) => c.control_dt(),
            AnyController::Lyapunov(c) => c.control_dt(),
        }
    }

    fn goal(&self) -> Pose2<T> {
        match self {
            AnyController::Paper(c) => c.goal(),
            AnyController::PaperSaturated(c) => c.goal(),
            AnyController::Polar(c) => c.goal(),
            AnyController::Lyapunov(c) => c.goal(),
        }
    }
}
