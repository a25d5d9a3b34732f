//! `run_scenario`, `run_batch` and `sweep`: scenarios parsed, checked and run by `wmr-scenario`,
//! columns handed to numpy without a copy, the GIL released while Rust runs.
//!
//! - `source`: the scenario argument (a path, TOML text or a dict), parsed and checked;
//! - `run_result`: `RunResult`, one run's columns as numpy arrays, and its pickling;
//! - `run`: `run_scenario` (and the Rust timing of it for the benches);
//! - `outcomes`: the per-run outcome arrays that `run_batch` and `sweep` return;
//! - `batch`: `run_batch`, one scenario from many starts;
//! - `sweep_run`: `sweep`, every law from every start;
//! - `sweep_parts`: a sweep cut into parts for an outside executor, and put together.

mod batch;
mod outcomes;
mod run;
mod run_result;
mod source;
mod sweep_parts;
mod sweep_run;

pub use batch::run_batch_native;
pub use outcomes::{outcome_fields, tracking_fields};
pub use run::{run_scenario, time_run_rust};
pub use run_result::{
    PyRunResult, RESULT_COLUMNS, RESULT_UNITS, add_column_properties, add_outcome_properties, run_result_from_state,
};
pub(crate) use source::to_toml;
pub use source::{file_access, scenario_arg};
pub use sweep_parts::{SWEEP_ROW_LEN, sweep_gather, sweep_part, sweep_plan};
pub use sweep_run::sweep;
