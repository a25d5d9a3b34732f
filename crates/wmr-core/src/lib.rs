//! # wmr-core
//!
//! Models, integrator and controllers of a two-wheeled differential-drive robot, after
//! "Dynamic Modeling and Stabilization of Wheeled Mobile Robot": the kinematic model
//! (1)-(9), the dynamic model (15) with wheel and motor inertia and friction, drives,
//! a classic RK4 integrator, the paper's point-stabilization controller and a
//! closed-loop stepper.
//!
//! `#![no_std]`, no `alloc`, generic over `f32` and `f64` (see [`Real`]): the same
//! code runs in a notebook, the CLI and Cortex-M firmware. SI units and radians
//! throughout; frames are named where they matter (world frame XOY, body frame of C).
//!
//! ```
//! use wmr_core::{ClosedLoop, ControllerParams, DriveParams, FixedGoal, Plant, Pose2, Robot};
//!
//! let robot = Robot::<f64>::paper();
//! let drive = DriveParams::default().validate(&robot).unwrap();
//! let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
//! let controller = ControllerParams::paper().build(robot.params(), &drive).unwrap();
//! let goal = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians())).unwrap();
//! let mut sim = ClosedLoop::new(plant, controller, goal, 1e-3).unwrap();
//! let outcome = sim.run(60_000, 10, |_sample| {});
//! assert!(outcome.final_dl < 0.01);
//! ```
//!
//! The loop is made of parts, each its own module: [`plant`] (the truth: robot, drive,
//! RK4), [`sensor`] (what the controller sees), [`reference`](mod@reference) (the
//! reference's pose, twist and acceleration over time), [`controller`] (an outer law and
//! a wheel stage), [`closed_loop`] (the one stepping function: ties them together on one
//! [`clock`] and logs [`Sample`]s), [`batch`] (the same loop over SIMD lanes) and
//! [`outcome`] (how the run went, from the true state against the reference).
//! Every parameter type is declared once ([`describe`]): its field table gives the
//! scenario schema, `--help`, the docs tables and the C header; [`trace`] is the f32
//! tick record the firmware replays.
//!
//! **Stability** (0.x: a minor version may break the API): the equations and their
//! results, the parameter types and their field names, [`ParamError`]'s field names and
//! the loop's entry points ([`Plant`], [`Controller`], [`ClosedLoop`], [`Law`],
//! [`Sensor`], [`Reference`]) are meant to stay; the laws' helper modules, the fields of
//! [`Sample`], [`Outcome`] and [`Measurement`], and the `nalgebra` feature's nalgebra
//! version may still change. Optional features: `serde`, `nalgebra`
//! (`nalgebra_interop`). The crate's README says more.
#![no_std]
#![warn(missing_docs)]

pub mod arrival;
pub mod batch;
pub mod clock;
pub mod closed_loop;
pub mod controller;
pub mod describe;
pub mod drive;
mod dynamics;
pub mod error;
pub mod integrator;
pub mod kinematics;
pub mod lane;
pub mod math;
#[cfg(feature = "nalgebra")]
pub mod nalgebra_interop;
pub mod obstacle;
pub mod outcome;
pub mod outcome_fields;
mod params;
pub mod payload;
pub mod plant;
pub mod push;
mod real;
pub mod reference;
pub mod rolling_traction;
pub mod sample;
pub mod sensor;
pub mod settle;
pub mod state;
pub mod trace;
pub mod tracking;
pub mod traction;
pub mod world;

pub use clock::StepClock;
pub use closed_loop::{ClosedLoop, Diverged, Tick};
pub use controller::{
    AntiWindup, AnyLaw, ControlErrors, ControlOutput, Controller, ControllerParams, Follows, HoldMode, Law, LawParams,
    LawSpec, MotionModel, PaperMode, ServoGains, WheelDemand, WheelStage, WheelStageParams,
};
/// Each law's keys and law at the root (`wmr_core::KanayamaParams`), from the registry.
macro_rules! root_law_exports {
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
        pub use controller::{$($params, $law),+};
    };
}
for_each_law!(root_law_exports);
pub use controller::{DisturbanceObserver, DisturbanceObserverParams};
pub use drive::{DcMotorParams, Drive, DriveParams, TorqueDriveParams};
pub use error::{ParamError, Reason};
pub use math::{Pose2, Twist2, Wheels, wrap_angle};
pub use obstacle::{Obstacle, Obstacles};
pub use outcome::{
    ARRIVAL_HEADING_RAD, ARRIVAL_RADIUS_M, Outcome, Status, Termination, XY_GOAL_TOLERANCE_M, YAW_GOAL_TOLERANCE_DEG,
};
pub use outcome_fields::{FieldGroup, OUTCOME_FIELDS, OutcomeField};
pub use params::{Robot, RobotParams};
pub use payload::{Payload, PayloadParams};
pub use plant::Plant;
pub use push::{PushParams, Pushes};
pub use real::Real;
pub use reference::{AnyReference, FixedGoal, Path, Reference, ReferenceState};
pub use sample::Sample;
pub use sensor::{
    AnySensor, Measurement, OdometryParams, OdometrySensor, PerfectSensor, PoseSensor, PoseSource, Sensor, SensorParams,
};
pub use state::State;
pub use traction::{Contact, SlipExtra, Traction, TractionKind, TractionParams};
pub use world::{World, WorldParams};
