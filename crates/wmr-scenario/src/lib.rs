//! # wmr-scenario
//!
//! The scenario file (`docs/scenario.md`), in one place for the CLI and the Python
//! bindings: parse TOML, fill the defaults, check every key by building the core types
//! once, then run.
//!
//! - [`keys`]: how `[robot]`, `[drive]` and `[controller]` are read through the core's
//!   own parameter types (every key a field name there, spelled once).
//! - `file`: the raw tables; `scenario`: the validated [`Scenario`]; `sweep`: `[sweep]`.
//! - `read`, `bounds`, `budget`: what a scenario may ask for, checked before any work
//!   starts (a file within [`MAX_FILE_BYTES`], poses in the box, [`MAX_TOTAL_STEPS`]).
//! - [`executor`]: the one ordered parallel runner (CLI, sweeps, Python).
//! - `output`: sample columns, the [`Sink`] trait and [`RunResult`].
//!
//! ```
//! let text = r#"
//! [sim]
//! t_end = 1.0
//! [[run]]
//! goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
//! "#;
//! let scenario = wmr_scenario::Scenario::from_toml_str(text, "demo").unwrap();
//! let mut rows = 0;
//! let result = scenario.run(0, |_sample| rows += 1).unwrap();
//! assert_eq!(rows, 101); // t = 0, 0.01, ..., 1.0
//! assert!(!result.diverged());
//!
//! let err = wmr_scenario::Scenario::from_toml_str("[robot]\nmass = -1.0\n[[run]]\ngoal = {}\n", "bad").unwrap_err();
//! assert_eq!(err.key, "robot.mass");
//! assert_eq!(err.line, Some(2));
//! ```
//!
//! Every error is a [`ScenarioError`] naming the key (`robot.mass`, `run[2].start.x`)
//! and, for TOML, the line.

mod assemble;
mod bounds;
mod budget;
mod controller;
mod error;
pub mod executor;
pub mod fast;
mod file;
mod files;
pub mod keys;
mod locate;
mod memory;
mod output;
pub mod preset;
mod read;
pub mod reference;
pub mod robustness;
mod run;
mod scenario;
pub mod schema;
mod setup;
mod sim;
mod sweep;
mod tracking_run;
pub mod urdf;
pub mod vary;
mod warnings;

pub use assemble::RunLoop;
pub use budget::{MAX_SWEEP_REFERENCES, MAX_SWEEP_RUNS, MAX_TOTAL_STEPS};
pub use controller::{controller_keys, law_kinds, stabilization_law_kinds, tracking_law_kinds};
pub use error::{ScenarioError, escape_controls, is_unsafe_char, shown};
pub use file::{GridFile, PoseFile, RandomFile, RunFile, ScenarioFile, SimFile, SweepFile};
pub use files::{AllowedBy, FileAccess};
pub use memory::{Headroom, available_memory_bytes, memory_headroom};
pub use output::{
    COMMAND_COLUMNS, COMMAND_UNITS, CONTACT_COLUMNS, CONTACT_UNITS, CSV_COLUMNS, ColumnGroup, Columns,
    DISTURBANCE_COLUMNS, DISTURBANCE_UNITS, MEASURED_COLUMNS, MEASURED_UNITS, ODOMETRY_COLUMNS, ODOMETRY_UNITS,
    OdometryDrift, REFERENCE_COLUMNS, REFERENCE_UNITS, RunResult, SAMPLE_COLUMNS, SAMPLE_UNITS, Sink, SinkError,
    command_values, contact_values, disturbance_values, measured_values, odometry_values, reference_values,
    sample_values,
};
pub use read::{MAX_FILE_BYTES, default_name, read_text};
pub use run::RunSpec;
pub use scenario::{DEFAULT_TRACKING_TOLERANCE_M, InputFile, Scenario, Tracking, total_steps};
pub use schema::{SchemaKey, schema};
pub use setup::{BuiltController, FOOTPRINT_RADIUS, Setup, Tables};
pub use sim::{DEFAULT_LOG_DT_S, DEFAULT_T_END_S, MAX_STEPS, MAX_T_END_S, SimSpec};
pub use sweep::{
    DockingSummary, LawSummary, Percentiles, Spread, StartsSource, SweepOutcome, SweepSpec, SweepTracking,
    TrackingSummary, docking_summary, docking_table, percentile, summarize, summary_table, sweep_columns, sweep_row,
    tracking_summary, tracking_summary_table, tracking_sweep_columns, tracking_sweep_row,
};
pub use warnings::{Writer, warnings, warnings_for};
