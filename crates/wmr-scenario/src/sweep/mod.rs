//! Sweeps (`[sweep]`): many starts, several laws, one outcome per (law, start), run in
//! parallel (rayon, one run per task) with results in a fixed order.
//!
//! ```toml
//! [sweep]
//! goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
//! controllers = [{ kind = "paper" }, { kind = "polar" }, { kind = "lyapunov", h = 9.0 }]
//! # exactly one of:
//! grid = { x_min = -2.0, x_max = 2.0, nx = 21, y_min = -2.0, y_max = 2.0, ny = 21, theta_deg = [0.0] }
//! random = { n = 1000, seed = 1, radius = 2.0, min_radius = 0.1 }
//! ```
//!
//! Each entry of `controllers` takes the keys of `[controller]` for its kind; absent, every
//! law runs with its defaults. How the starts are drawn: `starts`.
//!
//! - `spec`: the checked sweep ([`SweepSpec`]): laws, variants, where run k sits;
//! - `starts`: the start poses, from a grid or drawn at random;
//! - `exact`: running it on the exact path ([`SweepOutcome`] per run; the fast path is
//!   `crate::fast`);
//! - `outcome`: one run's outcome and where it sits;
//! - `row`: an outcome as a CSV row; `write`: the table written back as TOML;
//! - `summary`: the per-law comparison table; `tracking_summary`: the per (law,
//!   reference) one of a sweep over references.
//!
//! A sweep over references (`references = [{ kind = "circle" }, ...]`, or the scenario's
//! `[reference]`) runs every law on every reference, from starts that are offsets from
//! the reference's pose at t = 0, and judges each run by its tracking error.

mod exact;
mod outcome;
mod row;
mod spec;
mod starts;
mod summary;
mod tracking_summary;
mod write;

pub use outcome::SweepOutcome;
pub use row::{csv_num, sweep_columns, sweep_row, tracking_sweep_columns, tracking_sweep_row};
pub(crate) use spec::check_reference_count;
pub use spec::{SweepSpec, SweepTracking};
pub use starts::StartsSource;
pub use summary::{
    DockingSummary, LawSummary, Percentiles, Spread, docking_summary, docking_table, percentile, summarize,
    summary_table,
};
pub use tracking_summary::{TrackingSummary, tracking_summary, tracking_summary_table};
