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
//! use wmr_core::{ClosedLoop, PaperController, PaperParams, Pose2, DriveParams, Robot};
//!
//! let robot = Robot::<f64>::paper();
//! let drive = DriveParams::default().validate(&robot).unwrap();
//! let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
//! let ctrl = PaperController::new(PaperParams::paper(), &robot, &drive, goal).unwrap();
//! let mut sim = ClosedLoop::new(robot, drive, ctrl, Pose2::default(), 1e-3).unwrap();
//! let outcome = sim.run(60_000, 10, |_sample| {});
//! assert!(outcome.final_dl < 0.01);
//! ```
#![no_std]
#![warn(missing_docs)]

pub mod controller;
pub mod drive;
mod dynamics;
pub mod error;
pub mod integrator;
pub mod kinematics;
pub mod math;
pub mod metrics;
mod params;
mod real;
pub mod sim;
pub mod state;

pub use controller::{
    AnyController, ControllerKind, ControllerParams, LyapunovController, LyapunovParams, PaperSaturated,
    PolarController, PolarParams,
};
pub use controller::{
    ControlErrors, ControlOutput, Controller, HoldMode, Measurement, PaperController, PaperMode, PaperParams,
    ServoGains,
};
pub use drive::{DcMotorParams, Drive, DriveParams, TorqueDriveParams};
pub use error::{ParamError, Reason};
pub use math::{Pose2, Twist2, Wheels, wrap_angle};
pub use metrics::{Outcome, Termination};
pub use params::{Robot, RobotParams};
pub use real::Real;
pub use sim::{ClosedLoop, Sample};
pub use state::State;
