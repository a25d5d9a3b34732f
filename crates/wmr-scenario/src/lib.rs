//! # wmr-scenario
//!
//! The scenario file of SPEC section 6, in one place for the CLI and the Python
//! bindings: parse (TOML, or JSON for a Python dict), fill the defaults, check every
//! key by building the core types once, then run.
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

mod controller;
mod error;
mod file;
mod locate;
mod output;
mod scenario;
mod sweep;

pub use controller::{
    BuiltController, CONTROLLER_KINDS, ControllerFile, ControllerSpec, HoldFile, LyapunovFile, ModeFile, PaperFile,
    PolarFile, build_controller,
};
pub use error::ScenarioError;
pub use file::{DcMotorFile, DriveFile, PoseFile, RobotFile, RunFile, ScenarioFile, SimFile, TorqueDriveFile};
pub use output::{CSV_COLUMNS, RunResult, SAMPLE_COLUMNS, Sink, SinkError, sample_values};
pub use scenario::{DEFAULT_LOG_DT_S, DEFAULT_T_END_S, MAX_STEPS, MAX_T_END_S, RunSpec, Scenario, SimSpec};
pub use sweep::{
    GridFile, LawSummary, MAX_SWEEP_RUNS, RandomFile, SWEEP_COLUMNS, Spread, StartsSource, SweepFile, SweepOutcome,
    SweepSpec, summarize, summary_table, sweep_row,
};
