//! `wmr_py.identify`: the fit of `wmr-cli identify` (docs/identify.md), through the same
//! library code (`wmr_identify::file`), so the robot file is the CLI's bit for bit.

use std::path::PathBuf;

use pyo3::exceptions::PyFileNotFoundError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::{DriveParams, RobotParams};

use crate::error::parameter_error;
use crate::robot::{PyRobot, robot_items};
use wmr_identify::file::{FileError, base, command_kind, identify_table, read_table};

/// A robot identified from a log (`wmr_py.identify`): the fitted values with their
/// standard errors, the robot (`robot`, a `Robot`), the scenario tables (`to_dict()`) and
/// the robot file `wmr-cli identify` writes (`toml`).
#[pyclass(name = "IdentifiedRobot", module = "wmr_py", frozen)]
pub struct PyIdentified {
    robot: RobotParams<f64>,
    drive: DriveParams<f64>,
    /// (key, value, standard error or None when held, held, zeroed) per parameter.
    estimates: Vec<(&'static str, f64, f64, bool, bool)>,
    log: String,
    toml: String,
    rows_used: usize,
    rows_total: usize,
    condition: f64,
    rms_residual: f64,
}

#[pymethods]
impl PyIdentified {
    /// The fitted robot, a `Robot` (its `[robot]` keys).
    #[getter]
    fn robot(&self) -> PyResult<PyRobot> {
        let r = self.robot.validate().map_err(|e| parameter_error("robot", e))?;
        Ok(PyRobot::from(r))
    }
    /// The robot file `wmr-cli identify` writes, the same text bit for bit.
    #[getter]
    fn toml(&self) -> &str {
        &self.toml
    }
    /// The log the values came from, as given.
    #[getter]
    fn log(&self) -> &str {
        &self.log
    }
    /// Every parameter of the fit (fitted or held): key -> value, SI units.
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v, ..) in &self.estimates {
            d.set_item(*k, *v)?;
        }
        Ok(d)
    }
    /// The standard error of each fitted parameter (key -> value, its unit); the held ones
    /// are not in it.
    #[getter]
    fn std_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, _, se, held, _) in &self.estimates {
            if !held {
                d.set_item(*k, *se)?;
            }
        }
        Ok(d)
    }
    /// The keys of the parameters held rather than fitted.
    #[getter]
    fn held(&self) -> Vec<&'static str> {
        self.estimates.iter().filter(|e| e.3).map(|e| e.0).collect()
    }
    /// The keys of the parameters the fit put below zero within 3 standard errors (set to 0).
    #[getter]
    fn zeroed(&self) -> Vec<&'static str> {
        self.estimates.iter().filter(|e| e.4).map(|e| e.0).collect()
    }
    /// Rows of the log the fit used, and all its rows.
    #[getter]
    fn rows(&self) -> (usize, usize) {
        (self.rows_used, self.rows_total)
    }
    /// Condition number of the column-scaled regressor.
    #[getter]
    fn condition(&self) -> f64 {
        self.condition
    }
    /// RMS residual of the fit, N m (torque) or V (dc_motor).
    #[getter]
    fn rms_residual(&self) -> f64 {
        self.rms_residual
    }
    /// The scenario's `robot` and `drive` tables: `{**fitted.to_dict(), "run": [...]}` is a
    /// scenario of the fitted robot (as `[robot] from` the written file).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let robot = PyDict::new(py);
        for (k, v) in robot_items(&self.robot) {
            robot.set_item(k, v)?;
        }
        let drive = PyDict::new(py);
        match self.drive {
            DriveParams::Torque(p) => {
                drive.set_item("kind", "torque")?;
                drive.set_item("motor_torque_max", p.motor_torque_max)?;
                drive.set_item("deadband", p.deadband)?;
            }
            DriveParams::DcMotor(m) => {
                drive.set_item("kind", "dc_motor")?;
                drive.set_item("voltage_max", m.voltage_max)?;
                drive.set_item("torque_constant", m.torque_constant)?;
                drive.set_item("back_emf_constant", m.back_emf_constant)?;
                drive.set_item("armature_resistance", m.armature_resistance)?;
                drive.set_item("current_max", m.current_max)?;
                drive.set_item("deadband", m.deadband)?;
            }
            // `identify` gives a torque drive or a DC motor only.
            _ => {}
        }
        let d = PyDict::new(py);
        d.set_item("robot", robot)?;
        d.set_item("drive", drive)?;
        Ok(d)
    }
    fn __repr__(&self) -> String {
        let items: Vec<String> = self
            .estimates
            .iter()
            .map(
                |(k, v, se, held, _)| {
                    if *held { format!("{k}={v:?} (held)") } else { format!("{k}={v:?} +- {se:.3e}") }
                },
            )
            .collect();
        format!("IdentifiedRobot({}; from {})", items.join(", "), self.log)
    }
}

/// A refusal as a Python exception: a `ParameterError` whose `key` is the parameter the
/// log does not determine (`platform_inertia`) or the argument that is bad (`log`,
/// `robot`, `hold`, `namespace`).
fn to_py(e: FileError) -> PyErr {
    match e {
        FileError::Input { key, message } => parameter_error(key, message),
        FileError::Parameter { parameter, log, error } => {
            let message = error.to_string();
            let message = message.strip_prefix(&format!("{parameter}: ")).unwrap_or(&message);
            let message = message.replace(&format!("(--hold {parameter})"), &format!("(hold=[\"{parameter}\"])"));
            parameter_error(&parameter, format!("{message} (log {log})"))
        }
    }
}

/// Fits a robot to a log, as `wmr-cli identify LOG -o OUT` (docs/identify.md).
#[pyfunction]
#[pyo3(signature = (log, *, drive = "torque", robot = None, hold = None, namespace = None, allow_files_under = None))]
pub fn identify(
    py: Python<'_>,
    log: PathBuf,
    drive: &str,
    robot: Option<PathBuf>,
    hold: Option<Vec<String>>,
    namespace: Option<String>,
    allow_files_under: Option<Vec<PathBuf>>,
) -> PyResult<PyIdentified> {
    let dc_motor = match drive {
        "torque" => false,
        "dc_motor" => true,
        other => return Err(parameter_error("drive", format!("must be \"torque\" or \"dc_motor\", got {other:?}"))),
    };
    // A file that is not there raises as `open()` would.
    for p in std::iter::once(&log).chain(robot.as_ref()) {
        if !p.exists() {
            return Err(PyFileNotFoundError::new_err((2, "No such file or directory", p.display().to_string())));
        }
    }
    let access = crate::scenario::file_access(allow_files_under)?;
    let kind = command_kind(dc_motor);
    py.detach(|| {
        let base = base(robot.as_deref(), &access)?;
        let table = read_table(&log, namespace.as_deref(), kind)?;
        let shown = wmr_scenario::shown(&log);
        let id = identify_table(&table, &shown, &base, kind, hold.as_deref())?;
        let f = &id.fit;
        Ok(PyIdentified {
            robot: f.robot,
            drive: id.drive,
            estimates: f.estimates.iter().map(|e| (e.param.key(), e.value, e.std_err, e.held, e.zeroed)).collect(),
            log: shown,
            toml: id.text,
            rows_used: f.rows_used,
            rows_total: f.rows_total,
            condition: f.condition,
            rms_residual: f.rms_residual,
        })
    })
    .map_err(to_py)
}
