//! Identify a robot's parameters from a log (docs/identify.md): mass, inertias, friction
//! and a DC motor's constants, by linear least squares on the model's own equations (15).
//!
//! A log is a [`Table`] of named, time-stamped columns (read from CSV, or from a ROS 2
//! MCAP by [`ros2::log`]), checked into a [`Log`], and fitted by [`fit()`]. [`file`](mod@file) is
//! the whole of `wmr-cli identify` short of its arguments: a log file in, a robot file
//! (and a C header) out, in a library so that a Python `identify` can give the same file
//! bit for bit.
//!
//! Its own crate (std, alloc) rather than part of wmr-core (no_std, no alloc: a fit needs
//! the whole log in memory) or of wmr-scenario (the scenario file): the CLI and the Python
//! module both call it, and the core stays what the firmware runs.

// Matrix and column code reads best with indices (as in the core's integrator), and a
// refusal of NaN is written `!(x > 0.0)`, which a NaN fails.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

pub mod error;
pub mod excite;
pub mod file;
pub mod filter;
pub mod fit;
pub mod linalg;
pub mod log;
pub mod replay;
pub mod sim;
pub mod table;

/// CDR and the ROS 2 log reader (`wmr-ros2`), under the path the identification reads
/// ROS 2 logs by.
pub use wmr_ros2 as ros2;

pub use error::IdentifyError;
pub use fit::{Estimate, Fit, FitSettings, Param, fit};
pub use log::{ColumnNames, CommandKind, Log, Run, WheelSignal};
pub use table::Table;
