//! Where the robot should be: a [`Reference`] gives, at each time, the state of a
//! reference point C_ref ([`ReferenceState`]): its pose, its twist and its acceleration,
//! and, for path following, its geometric [`Path`].
//!
//! Point stabilization is the reference at rest ([`FixedGoal`]); a trajectory is a
//! reference that moves, and a law that tracks it reads the twist and the acceleration as
//! feedforward. The laws receive the whole state at every tick, so a new kind of reference
//! is one more file here plus one line in [`any`]'s list, and no law changes.
//!
//! - [`state`]: the contract ([`Reference`], [`ReferenceState`]).
//! - [`path`]: the geometric path and its searches ([`Path`], [`PathCursor`]).
//! - [`fixed`]: the goal at rest. [`circle`], [`figure_eight`], [`line`](mod@line): analytic
//!   trajectories. [`waypoints`]: a C2 spline through points with a speed profile.
//! - [`config`]: what builds each kind, as a trace carries it ([`config::KindConfig`]).
//! - [`any`]: every kind behind one enum ([`AnyReference`]) and what builds it ([`ReferenceConfig`]).

pub mod any;
pub mod circle;
pub mod config;
pub mod figure_eight;
pub mod fixed;
pub mod line;
pub mod path;
pub mod state;
pub mod waypoints;

pub use any::{AnyReference, ReferenceConfig};
pub use circle::Circle;
pub use figure_eight::{FigureEight, FigureEightParams};
pub use fixed::FixedGoal;
pub use line::{Line, LineParams};
pub use path::{Path, PathCursor};
pub use state::{Reference, ReferenceState};
pub use waypoints::{Waypoints, WaypointsConfig};
