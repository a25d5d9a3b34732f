//! # wmr-py
//!
//! Python bindings of wmr, import name `wmr_py` (the native part is `wmr_py._native`;
//! the pure-Python package in `python/wmr_py` re-exports it with `.pyi` stubs).
//! One `PyX` wrapper per core type, errors converted in [`error`] only, the scenario
//! parsing and running left to `wmr-scenario`. See the crate's README.md.

pub mod alloc;
pub mod controller;
pub mod convert;
pub mod error;
pub mod identify;
pub mod interrupt;
pub mod reference;
pub mod robot;
pub mod ros2_log;
pub mod scenario;
pub mod trajectory;

/// Native part of wmr_py: models, controller and scenario runner of a differential-drive robot.
#[pyo3::pymodule]
mod _native {
    #[pymodule_export]
    use crate::controller::controller_from_toml;
    #[pymodule_export]
    use crate::error::{ParameterError, ScenarioError};
    #[pymodule_export]
    use crate::identify::{PyIdentified, identify};
    #[pymodule_export]
    use crate::robot::PyRobot;
    #[pymodule_export]
    use crate::ros2_log::read_log;
    #[pymodule_export]
    use crate::scenario::{
        PyRunResult, run_batch_native, run_result_from_state, run_scenario, sweep, sweep_gather, sweep_part,
        sweep_plan, time_run_rust,
    };
    #[pymodule_export]
    use crate::trajectory::PyReference;

    /// Loads NumPy's C API now, while importing: loaded lazily, the first array made
    /// after a run that Ctrl-C interrupted would import numpy with a KeyboardInterrupt
    /// pending, and rust-numpy panics when that import fails.
    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        use pyo3::types::{PyModuleMethods as _, PyTuple};
        // The version of wmr: the workspace's, which `wmr-cli --version` prints.
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        // The column and outcome names, each from its one list (wmr-scenario's output
        // module, wmr-core's arrival radius): `_results.py` and the tests read them here.
        m.add("COLUMNS", PyTuple::new(m.py(), wmr_scenario::SAMPLE_COLUMNS)?)?;
        // Values per run in an outside executor's sweep rows (`_sweep_part`).
        m.add("_SWEEP_ROW_LEN", crate::scenario::SWEEP_ROW_LEN)?;
        m.add("COLUMN_UNITS", PyTuple::new(m.py(), wmr_scenario::SAMPLE_UNITS)?)?;
        m.add("CSV_COLUMNS", PyTuple::new(m.py(), wmr_scenario::CSV_COLUMNS)?)?;
        m.add("MEASURED_COLUMNS", PyTuple::new(m.py(), wmr_scenario::MEASURED_COLUMNS)?)?;
        m.add("OUTCOME_FIELDS", PyTuple::new(m.py(), crate::scenario::outcome_fields().collect::<Vec<_>>())?)?;
        m.add("ODOMETRY_COLUMNS", PyTuple::new(m.py(), wmr_scenario::ODOMETRY_COLUMNS)?)?;
        m.add("ODOMETRY_UNITS", PyTuple::new(m.py(), wmr_scenario::ODOMETRY_UNITS)?)?;
        m.add("CONTACT_COLUMNS", PyTuple::new(m.py(), wmr_scenario::CONTACT_COLUMNS)?)?;
        m.add("CONTACT_UNITS", PyTuple::new(m.py(), wmr_scenario::CONTACT_UNITS)?)?;
        m.add("REFERENCE_COLUMNS", PyTuple::new(m.py(), wmr_scenario::REFERENCE_COLUMNS)?)?;
        m.add("REFERENCE_UNITS", PyTuple::new(m.py(), wmr_scenario::REFERENCE_UNITS)?)?;
        m.add("TRACKING_FIELDS", PyTuple::new(m.py(), crate::scenario::tracking_fields().collect::<Vec<_>>())?)?;
        m.add("ARRIVAL_RADIUS_M", wmr_core::ARRIVAL_RADIUS_M)?;
        crate::scenario::add_column_properties(&m.py().get_type::<crate::scenario::PyRunResult>())?;
        crate::scenario::add_outcome_properties(&m.py().get_type::<crate::scenario::PyRunResult>())?;
        // One class per law of the registry (`wmr_core::for_each_law!`).
        crate::controller::add_law_classes(m)?;
        crate::interrupt::load_numpy_api(m.py())
    }
}
