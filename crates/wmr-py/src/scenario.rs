//! `run_scenario`, `run_batch` and `sweep`: scenarios parsed, checked and run by `wmr-scenario`,
//! columns handed to numpy without a copy, the GIL released while Rust runs.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use wmr_core::Pose2;
use wmr_core::plant::DIVERGENCE_BOX_M;
use wmr_core::{Outcome, Status, Termination};
use wmr_scenario::{
    RunResult, RunSpec, SAMPLE_COLUMNS, Scenario, ScenarioError, StartsSource, SweepOutcome, SweepSpec, executor,
    measured_values, sample_values,
};

use crate::convert::{is_real_number, type_name};
use crate::error::{from_scenario, parameter_error, scenario_error};
use crate::interrupt::{Progress, Stop, check_memory, interruptible, interruptible_with, try_vec};

/// Number of sample columns (the CSV columns after `run`).
const N_COLS: usize = SAMPLE_COLUMNS.len();

/// A `wmr_scenario::ScenarioError` as a Python exception (see [`from_scenario`]).
fn to_py(e: ScenarioError) -> PyErr {
    from_scenario(&e, None)
}

/// A str argument as Rust text; a str that is not valid Unicode (a lone surrogate such as
/// "\udcff", which cannot be encoded) is a `ScenarioError` naming `key`.
fn text_arg(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<String> {
    obj.extract::<String>().map_err(|_| {
        let shown = if key.is_empty() { "scenario" } else { key };
        scenario_error(shown, None, format!("{shown}: not valid Unicode text (it holds a lone surrogate)"))
    })
}

/// A Python value as TOML, for the scenario parser. `None` values are left out (the key
/// takes its default); keys must be strings; numbers, strings, bools, lists, tuples and
/// dicts are accepted. `key` is the dotted path for error messages.
fn to_toml(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<Option<toml::Value>> {
    if obj.is_none() {
        return Ok(None);
    }
    let named = if key.is_empty() { "scenario" } else { key };
    let bad = |what: String| scenario_error(named, None, format!("{named}: {what}"));
    let v = if obj.is_instance_of::<PyBool>() {
        toml::Value::Boolean(obj.extract::<bool>()?)
    } else if obj.is_instance_of::<PyInt>() {
        match obj.extract::<i64>() {
            Ok(i) => toml::Value::Integer(i),
            // Beyond i64: as a float when it is one, else too large for any key.
            Err(_) => match obj.extract::<f64>() {
                Ok(f) => toml::Value::Float(f),
                Err(_) => return Err(bad("the integer is too large (more than 1.8e308)".to_owned())),
            },
        }
    } else if obj.is_instance_of::<PyFloat>() {
        toml::Value::Float(obj.extract::<f64>()?)
    } else if obj.is_instance_of::<PyString>() {
        toml::Value::String(text_arg(obj, key)?)
    } else if let Ok(d) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            if !k.is_instance_of::<PyString>() {
                return Err(bad(format!("keys must be strings, got {}", type_name(&k))));
            }
            let k = text_arg(&k, key)?;
            let sub = if key.is_empty() { k.clone() } else { format!("{key}.{k}") };
            if let Some(v) = to_toml(&v, &sub)? {
                table.insert(k, v);
            }
        }
        toml::Value::Table(table)
    } else if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            if let Some(v) = to_toml(&item?, &format!("{key}[{i}]"))? {
                items.push(v);
            }
        }
        toml::Value::Array(items)
    } else if is_real_number(obj) {
        // numpy's real scalars (float64, int32, ...), not complex ones.
        match obj.extract::<f64>() {
            Ok(f) => toml::Value::Float(f),
            Err(_) => return Err(bad(format!("cannot read {} as a number", type_name(obj)))),
        }
    } else {
        return Err(bad(format!("unsupported value of type {}", type_name(obj))));
    };
    Ok(Some(v))
}

/// Where a scenario comes from.
enum Source {
    /// A TOML file.
    Path(PathBuf),
    /// TOML text given by the caller (its line numbers mean something to them).
    Text(String),
    /// TOML text made here from a dict (line numbers dropped from errors).
    Dict(String),
}

impl Source {
    /// A path (str or os.PathLike), TOML text, or a dict. A str is a path if such a file
    /// exists or it cannot be TOML text (no '=' and no newline); otherwise TOML text.
    fn from_py(obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        if obj.is_instance_of::<PyDict>() {
            let Some(toml::Value::Table(table)) = to_toml(obj, "")? else {
                return Err(scenario_error("scenario", None, "scenario: expected a dict".to_owned()));
            };
            let text = toml::to_string(&table).map_err(|e| {
                scenario_error("scenario", None, format!("scenario: cannot express the dict as a scenario: {e}"))
            })?;
            return Ok(Source::Dict(text));
        }
        if obj.is_instance_of::<PyString>() {
            let s = text_arg(obj, "scenario")?;
            let is_path = std::path::Path::new(&s).is_file() || !(s.contains('=') || s.contains('\n'));
            return Ok(if is_path { Source::Path(s.into()) } else { Source::Text(s) });
        }
        obj.extract::<PathBuf>().map(Source::Path).map_err(|_| {
            scenario_error(
                "scenario",
                None,
                format!("scenario: expected a path, TOML text or a dict, got {}", type_name(obj)),
            )
        })
    }

    /// Parses and checks the scenario (no Python involved: may run without the GIL), with
    /// the warnings about its text (a heading of 90 rad).
    fn parse(&self) -> Result<(Scenario, Vec<ScenarioError>), ScenarioError> {
        let (text, name) = match self {
            Source::Path(p) => (wmr_scenario::read_text(p)?, wmr_scenario::default_name(p)),
            Source::Text(t) | Source::Dict(t) => (t.clone(), "scenario".to_owned()),
        };
        let parsed = Scenario::from_toml_str(&text, &name);
        let (sc, warnings) = match self {
            Source::Dict(_) => (
                parsed.map_err(|e| e.at_line(None))?,
                wmr_scenario::warnings(&text).into_iter().map(|w| w.at_line(None)).collect(),
            ),
            _ => (parsed?, wmr_scenario::warnings(&text)),
        };
        Ok((sc, warnings))
    }

    /// The scenario's text: what a worker of an outside executor parses again.
    fn text(&self) -> Result<String, ScenarioError> {
        match self {
            Source::Path(p) => wmr_scenario::read_text(p),
            Source::Text(t) | Source::Dict(t) => Ok(t.clone()),
        }
    }

    /// The file, for an error about it.
    fn path(&self) -> Option<&std::path::Path> {
        match self {
            Source::Path(p) => Some(p),
            _ => None,
        }
    }
}

/// Parses a scenario from a path (str or os.PathLike), TOML text, or a dict; its
/// warnings become Python `UserWarning`s.
pub fn scenario_arg(obj: &Bound<'_, PyAny>) -> PyResult<Scenario> {
    let source = Source::from_py(obj)?;
    let (sc, warnings) = source.parse().map_err(|e| from_scenario(&e, source.path()))?;
    let py = obj.py();
    for w in warnings {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        let message = std::ffi::CString::new(w.key_first().replace('\0', "\\0")).unwrap_or_default();
        PyErr::warn(py, &category, &message, 1)?;
    }
    Ok(sc)
}

/// One run's columns, built once in Rust: the CSV columns and the measured pose.
struct Columns {
    cols: [Vec<f64>; N_COLS],
    measured: [Vec<f64>; 3],
}

impl Columns {
    /// Room for `n` samples in every column, or `MemoryError`.
    fn try_with_capacity(n: usize) -> PyResult<Self> {
        let mut cols = Self { cols: [(); N_COLS].map(|()| Vec::new()), measured: [(); 3].map(|()| Vec::new()) };
        for c in cols.cols.iter_mut().chain(cols.measured.iter_mut()) {
            *c = try_vec(n)?;
        }
        Ok(cols)
    }

    fn push(&mut self, s: &wmr_core::Sample<f64>) {
        for (col, v) in self.cols.iter_mut().zip(sample_values(s)) {
            col.push(v);
        }
        for (col, v) in self.measured.iter_mut().zip(measured_values(s)) {
            col.push(v);
        }
    }
}

/// Bytes of the columns of every run of `sc`: n_samples x (CSV columns + measured
/// pose) x 8, summed over the runs.
fn columns_bytes(sc: &Scenario) -> u128 {
    u128::from(sc.sim().n_samples()) * ((N_COLS + 3) * 8) as u128 * sc.runs().len() as u128
}

/// Refuses runs whose columns the memory cannot hold, naming `sim.log_dt` and the value
/// that would fit (before anything is allocated).
fn check_columns_memory(sc: &Scenario) -> PyResult<()> {
    let sim = sc.sim();
    check_memory(columns_bytes(sc), "sim.log_dt", |share| {
        let every = (f64::from(sim.log_every()) / share).ceil();
        format!("raise sim.log_dt to at least {:.3e} s (now {} s) or shorten sim.t_end", every * sim.dt(), sim.log_dt())
    })
}

/// Runs run `i` of `sc`, collecting its columns; `None` when `stop` ended it.
/// `done` counts the samples logged (progress).
fn run_one(sc: &Scenario, i: usize, stop: &Stop, done: &AtomicUsize) -> PyResult<Option<(RunResult, Columns)>> {
    let n = usize::try_from(sc.sim().n_samples()).unwrap_or(usize::MAX);
    let mut cols = Columns::try_with_capacity(n)?;
    let poll = || if stop.requested() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
    let flow = sc
        .try_run(
            i,
            |s| {
                cols.push(s);
                done.fetch_add(1, Ordering::Relaxed);
                ControlFlow::Continue(())
            },
            poll,
        )
        .map_err(to_py)?;
    Ok(match flow {
        ControlFlow::Continue(result) => Some((result, cols)),
        ControlFlow::Break(()) => None,
    })
}

/// One run of a scenario: every CSV column (docs/scenario.md) as a float64 ndarray, plus the
/// run's summary.
///
/// Columns (one value per logged sample): t (s), x, y (m, point C, world frame),
/// theta (rad), v (m/s), omega (rad/s), phi_r, phi_l (rad), omega_r, omega_l (rad/s),
/// tau_r, tau_l (N m, wheel torques applied from this sample on), e_s (m),
/// e_theta (rad), dl (m). `result["x"]` reads a column by name; `columns()` gives a dict
/// of all CSV columns (with `run`).
#[pyclass(name = "RunResult", module = "wmr_py", frozen)]
pub struct PyRunResult {
    /// 0-based index of the `[[run]]` (the CSV `run` column).
    #[pyo3(get)]
    run: usize,
    /// The run's label.
    #[pyo3(get)]
    label: String,
    /// `"converged"` (final dl < 1 cm, not diverged), `"diverged"` or `"unsettled"` (neither).
    #[pyo3(get)]
    status: &'static str,
    /// True when not diverged and the final dl < 1 cm.
    #[pyo3(get)]
    converged: bool,
    /// True when the state stopped being finite or C left the 1 km box.
    #[pyo3(get)]
    diverged: bool,
    /// First time (s) from which dl stays below 1 cm to the end; None if never.
    #[pyo3(get)]
    time_to_1cm: Option<f64>,
    /// Final distance from C to the goal position, m.
    #[pyo3(get)]
    final_dl: f64,
    /// Final heading error wrap(theta_d - theta), rad.
    #[pyo3(get)]
    final_heading_error: f64,
    /// Final heading error, degrees.
    #[pyo3(get)]
    final_heading_error_deg: f64,
    /// Time of the last state, s (t_end unless diverged).
    #[pyo3(get)]
    t_final: f64,
    /// Largest |wheel speed| seen, rad/s.
    #[pyo3(get)]
    peak_wheel_speed: f64,
    /// Path length of C, m.
    #[pyo3(get)]
    path_length: f64,
    /// Mechanical energy the drives put into the wheels, J.
    #[pyo3(get)]
    energy: f64,
    /// The summary line the CLI prints.
    #[pyo3(get)]
    summary: String,
    #[pyo3(get)]
    t: Py<PyArray1<f64>>,
    #[pyo3(get)]
    x: Py<PyArray1<f64>>,
    #[pyo3(get)]
    y: Py<PyArray1<f64>>,
    #[pyo3(get)]
    theta: Py<PyArray1<f64>>,
    #[pyo3(get)]
    v: Py<PyArray1<f64>>,
    #[pyo3(get)]
    omega: Py<PyArray1<f64>>,
    #[pyo3(get)]
    phi_r: Py<PyArray1<f64>>,
    #[pyo3(get)]
    phi_l: Py<PyArray1<f64>>,
    #[pyo3(get)]
    omega_r: Py<PyArray1<f64>>,
    #[pyo3(get)]
    omega_l: Py<PyArray1<f64>>,
    #[pyo3(get)]
    tau_r: Py<PyArray1<f64>>,
    #[pyo3(get)]
    tau_l: Py<PyArray1<f64>>,
    #[pyo3(get)]
    e_s: Py<PyArray1<f64>>,
    #[pyo3(get)]
    e_theta: Py<PyArray1<f64>>,
    #[pyo3(get)]
    dl: Py<PyArray1<f64>>,
    /// x of the pose the controller used at its last tick, m (= x without a `[sensor]`).
    #[pyo3(get)]
    x_meas: Py<PyArray1<f64>>,
    /// y of the pose the controller used, m.
    #[pyo3(get)]
    y_meas: Py<PyArray1<f64>>,
    /// theta of the pose the controller used, rad.
    #[pyo3(get)]
    theta_meas: Py<PyArray1<f64>>,
}

impl PyRunResult {
    fn new(py: Python<'_>, r: RunResult, cols: Columns) -> Self {
        // from_vec hands each Vec's buffer to numpy: no copy.
        let [t, x, y, theta, v, omega, phi_r, phi_l, omega_r, omega_l, tau_r, tau_l, e_s, e_theta, dl] =
            cols.cols.map(|c| PyArray1::from_vec(py, c).unbind());
        let [x_meas, y_meas, theta_meas] = cols.measured.map(|c| PyArray1::from_vec(py, c).unbind());
        let o = &r.outcome;
        Self {
            run: r.index,
            status: r.status().name(),
            converged: r.converged(),
            diverged: r.diverged(),
            time_to_1cm: o.time_to_arrival,
            final_dl: o.final_dl,
            final_heading_error: o.final_heading_error,
            final_heading_error_deg: o.final_heading_error.to_degrees(),
            t_final: o.t_final,
            peak_wheel_speed: o.peak_wheel_speed,
            path_length: o.path_length,
            energy: o.energy,
            summary: r.summary_line(),
            label: r.label,
            t,
            x,
            y,
            theta,
            v,
            omega,
            phi_r,
            phi_l,
            omega_r,
            omega_l,
            tau_r,
            tau_l,
            e_s,
            e_theta,
            dl,
            x_meas,
            y_meas,
            theta_meas,
        }
    }

    fn column(&self, name: &str) -> Option<&Py<PyArray1<f64>>> {
        Some(match name {
            "t" => &self.t,
            "x" => &self.x,
            "y" => &self.y,
            "theta" => &self.theta,
            "v" => &self.v,
            "omega" => &self.omega,
            "phi_r" => &self.phi_r,
            "phi_l" => &self.phi_l,
            "omega_r" => &self.omega_r,
            "omega_l" => &self.omega_l,
            "tau_r" => &self.tau_r,
            "tau_l" => &self.tau_l,
            "e_s" => &self.e_s,
            "e_theta" => &self.e_theta,
            "dl" => &self.dl,
            "x_meas" => &self.x_meas,
            "y_meas" => &self.y_meas,
            "theta_meas" => &self.theta_meas,
            _ => return None,
        })
    }
}

#[pymethods]
impl PyRunResult {
    /// Every field as a dict (scalars, `summary` and the columns as arrays): what pickling
    /// carries.
    fn __getstate__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("run", self.run)?;
        d.set_item("label", &self.label)?;
        d.set_item("status", self.status)?;
        d.set_item("converged", self.converged)?;
        d.set_item("diverged", self.diverged)?;
        d.set_item("time_to_1cm", self.time_to_1cm)?;
        d.set_item("final_dl", self.final_dl)?;
        d.set_item("final_heading_error", self.final_heading_error)?;
        d.set_item("final_heading_error_deg", self.final_heading_error_deg)?;
        d.set_item("t_final", self.t_final)?;
        d.set_item("peak_wheel_speed", self.peak_wheel_speed)?;
        d.set_item("path_length", self.path_length)?;
        d.set_item("energy", self.energy)?;
        d.set_item("summary", &self.summary)?;
        for name in RESULT_COLUMNS {
            if let Some(c) = self.column(name) {
                d.set_item(name, c.bind(py))?;
            }
        }
        Ok(d)
    }

    /// Pickles as `wmr_py._restore_run_result(state)`, state from `__getstate__`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let restore = py.import("wmr_py")?.getattr("_restore_run_result")?;
        PyTuple::new(py, [restore, PyTuple::new(py, [self.__getstate__(py)?])?.into_any()])
    }

    /// Every column (with `run` and `label`) as a pandas DataFrame, one row per logged
    /// sample. Needs pandas (ImportError naming it otherwise).
    fn to_pandas<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py().import("wmr_py._results")?.getattr("run_result_to_pandas")?.call1((slf,))
    }

    /// A column by its CSV name, e.g. result["omega_r"].
    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyArray1<f64>>> {
        self.column(name).map(|c| c.clone_ref(py)).ok_or_else(|| {
            pyo3::exceptions::PyKeyError::new_err(format!("no column {name:?}; columns are {:?}", SAMPLE_COLUMNS))
        })
    }

    /// Every CSV column of docs/scenario.md (`run` first, as float64 like the others), in order.
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let n = self.t.bind(py).len();
        d.set_item("run", PyArray1::from_vec(py, vec![self.run as f64; n]))?;
        for name in SAMPLE_COLUMNS {
            if let Some(c) = self.column(name) {
                d.set_item(name, c.bind(py))?;
            }
        }
        Ok(d)
    }

    /// Number of logged samples.
    fn __len__(&self, py: Python<'_>) -> usize {
        self.t.bind(py).len()
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "<RunResult run={} label={:?} samples={}: {}>",
            self.run,
            self.label,
            self.t.bind(py).len(),
            self.summary
        )
    }
}

/// Runs every `[[run]]` of a scenario and returns one RunResult per run, in run order.
///
/// `scenario`: a path (str or os.PathLike) to a TOML file, TOML text, or a dict with the
/// same keys (docs/scenario.md; None values take the default). Runs go in parallel with the
/// GIL released. Raises ScenarioError (a ValueError) naming the bad key. `progress`: None
/// or a callable given the number of samples logged so far (about every 50 ms) and the
/// total first, as `progress(-total)`.
#[pyfunction]
#[pyo3(signature = (scenario, progress=None))]
pub fn run_scenario(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<PyRunResult>> {
    let sc = scenario_arg(scenario)?;
    if sc.runs().is_empty() {
        return Err(scenario_error(
            "run",
            None,
            "run: the scenario has no [[run]] (it is a [sweep] file: run it with wmr_py.sweep)".to_owned(),
        ));
    }
    check_columns_memory(&sc)?;
    let done = AtomicUsize::new(0);
    if let Some(p) = progress {
        let total = sc.sim().n_samples() as i64 * sc.runs().len() as i64;
        p.call1((-total,))?;
    }
    let runs: PyResult<Vec<_>> =
        interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
            executor::map_ordered(sc.runs().len(), |i| run_one(&sc, i, stop, &done)).into_iter().collect()
        })?;
    // A run is `None` only when stopped, and then `interruptible` returned the signal's error.
    let runs: Vec<(RunResult, Columns)> = runs?.into_iter().flatten().collect();
    Ok(runs.into_iter().map(|(r, cols)| PyRunResult::new(py, r, cols)).collect())
}

/// Names of a RunResult's columns, in order: the CSV columns, then the measured pose.
const RESULT_COLUMNS: [&str; N_COLS + 3] = [
    "t",
    "x",
    "y",
    "theta",
    "v",
    "omega",
    "phi_r",
    "phi_l",
    "omega_r",
    "omega_l",
    "tau_r",
    "tau_l",
    "e_s",
    "e_theta",
    "dl",
    "x_meas",
    "y_meas",
    "theta_meas",
];

/// A RunResult from the state its `__getstate__` gave (unpickling); every field checked.
#[pyfunction(name = "_run_result_from_state")]
pub fn run_result_from_state(state: &Bound<'_, PyDict>) -> PyResult<PyRunResult> {
    let get = |k: &str| -> PyResult<Bound<'_, PyAny>> {
        state.get_item(k)?.ok_or_else(|| parameter_error("state", format_args!("no {k:?}")))
    };
    let status: String = get("status")?.extract()?;
    let status = Status::ALL
        .into_iter()
        .map(Status::name)
        .find(|n| *n == status)
        .ok_or_else(|| parameter_error("state.status", format_args!("unknown status {status:?}")))?;
    let mut cols: Vec<Py<PyArray1<f64>>> = Vec::with_capacity(RESULT_COLUMNS.len());
    for name in RESULT_COLUMNS {
        let a = get(name)?;
        let a = a.cast_into::<PyArray1<f64>>().map_err(|_| parameter_error(name, "expected a float64 array"))?;
        cols.push(a.unbind());
    }
    let mut it = cols.into_iter();
    let mut next = || it.next().ok_or_else(|| parameter_error("state", "too few columns"));
    Ok(PyRunResult {
        run: get("run")?.extract()?,
        label: get("label")?.extract()?,
        status,
        converged: get("converged")?.extract()?,
        diverged: get("diverged")?.extract()?,
        time_to_1cm: get("time_to_1cm")?.extract()?,
        final_dl: get("final_dl")?.extract()?,
        final_heading_error: get("final_heading_error")?.extract()?,
        final_heading_error_deg: get("final_heading_error_deg")?.extract()?,
        t_final: get("t_final")?.extract()?,
        peak_wheel_speed: get("peak_wheel_speed")?.extract()?,
        path_length: get("path_length")?.extract()?,
        energy: get("energy")?.extract()?,
        summary: get("summary")?.extract()?,
        t: next()?,
        x: next()?,
        y: next()?,
        theta: next()?,
        v: next()?,
        omega: next()?,
        phi_r: next()?,
        phi_l: next()?,
        omega_r: next()?,
        omega_l: next()?,
        tau_r: next()?,
        tau_l: next()?,
        e_s: next()?,
        e_theta: next()?,
        dl: next()?,
        x_meas: next()?,
        y_meas: next()?,
        theta_meas: next()?,
    })
}

/// Names of the run_batch outputs, in order.
const BATCH_FIELDS: [&str; 12] = [
    "final_x",
    "final_y",
    "final_theta",
    "final_dl",
    "final_heading_error",
    "time_to_1cm",
    "t_final",
    "peak_wheel_speed",
    "path_length",
    "energy",
    "converged",
    "diverged",
];

/// The per-run outcome arrays of `run_batch` and `sweep` ([`BATCH_FIELDS`]), one entry
/// per outcome, in order.
fn outcome_dict<'py, 'a>(
    py: Python<'py>,
    outcomes: impl ExactSizeIterator<Item = &'a wmr_core::Outcome<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = outcomes.len();
    let mut cols: [Vec<f64>; 10] = std::array::from_fn(|_| Vec::with_capacity(n));
    let mut converged = Vec::with_capacity(n);
    let mut diverged = Vec::with_capacity(n);
    for o in outcomes {
        let vals = [
            o.final_pose.x,
            o.final_pose.y,
            o.final_pose.theta,
            o.final_dl,
            o.final_heading_error,
            o.time_to_arrival.unwrap_or(f64::NAN),
            o.t_final,
            o.peak_wheel_speed,
            o.path_length,
            o.energy,
        ];
        for (c, v) in cols.iter_mut().zip(vals) {
            c.push(v);
        }
        converged.push(o.status() == Status::Converged);
        diverged.push(o.status() == Status::Diverged);
    }
    let d = PyDict::new(py);
    for (name, c) in BATCH_FIELDS.iter().zip(cols) {
        d.set_item(name, PyArray1::from_vec(py, c))?;
    }
    d.set_item(BATCH_FIELDS[10], PyArray1::from_vec(py, converged))?;
    d.set_item(BATCH_FIELDS[11], PyArray1::from_vec(py, diverged))?;
    Ok(d)
}

/// Runs the scenario `base` (a dict or path, validated like `run_scenario`; its runs give
/// the goal if `goals` is None) from every start in `starts` in parallel, GIL released.
///
/// `first`: the index of `starts[0]` in the whole batch when this is a part of it (an
/// outside executor's chunk): run i draws its sensor noise from stream `first + i`, as in
/// the whole. `threads = 1` runs the starts one after the other on one thread (a worker
/// of a process pool or Dask must not start a thread pool per process); 0: rayon's pool.
/// `progress`: as for `run_scenario`, counting runs.
#[pyfunction(name = "_run_batch")]
#[pyo3(signature = (base, starts, goals=None, first=0, threads=0, progress=None, fast=false))]
#[allow(clippy::too_many_arguments)]
pub fn run_batch_native<'py>(
    py: Python<'py>,
    base: &Bound<'py, PyAny>,
    starts: PyReadonlyArray2<'py, f64>,
    goals: Option<PyReadonlyArray2<'py, f64>>,
    first: usize,
    threads: usize,
    progress: Option<&Bound<'py, PyAny>>,
    fast: bool,
) -> PyResult<Bound<'py, PyDict>> {
    if threads > 1 {
        return Err(parameter_error("threads", format_args!("0 (rayon's pool) or 1, got {threads}")));
    }
    let sc = scenario_arg(base)?;
    let poses = |a: &PyReadonlyArray2<'py, f64>, arg: &str| -> PyResult<Vec<Pose2<f64>>> {
        let shape = a.shape();
        if shape.len() != 2 || shape[1] != 3 {
            return Err(parameter_error(
                arg,
                format_args!("expected shape (N, 3) of (x, y, theta_rad), got {shape:?}"),
            ));
        }
        let arr = a.as_array();
        let names = ["x", "y", "theta"];
        let mut out = Vec::with_capacity(shape[0]);
        for (i, row) in arr.rows().into_iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                if !v.is_finite() {
                    return Err(parameter_error(
                        &format!("{arg}[{i}, {j}]"),
                        format_args!("{} must be a finite number (got {v})", names[j]),
                    ));
                }
                if j < 2 && v.abs() > DIVERGENCE_BOX_M {
                    return Err(parameter_error(
                        &format!("{arg}[{i}, {j}]"),
                        format_args!(
                            "{} must be within {DIVERGENCE_BOX_M} m of the origin (got {v:e}): a run that leaves \
                             |x|, |y| <= {DIVERGENCE_BOX_M} m counts as diverged",
                            names[j]
                        ),
                    ));
                }
            }
            out.push(Pose2::new(row[0], row[1], row[2]));
        }
        Ok(out)
    };
    let starts = poses(&starts, "starts")?;
    // Every run's result is held until the arrays are made: refuse what memory cannot hold.
    let per_run = (std::mem::size_of::<RunSpec>() + std::mem::size_of::<Option<RunResult>>() + 32 + 12 * 8) as u128;
    let n = starts.len();
    check_memory(per_run * n as u128, "starts", |share| {
        format!("pass at most {} starts per call ({n} given)", (n as f64 * share).floor())
    })?;
    let default_goal = sc.runs().first().map(|r| r.goal).unwrap_or_default();
    let goals = match goals {
        Some(g) => {
            let g = poses(&g, "goals")?;
            if g.len() != starts.len() && g.len() != 1 {
                return Err(parameter_error(
                    "goals",
                    format_args!("expected 1 or {} rows (one per start), got {}", starts.len(), g.len()),
                ));
            }
            g
        }
        None => vec![default_goal],
    };
    let runs = starts
        .iter()
        .enumerate()
        .map(|(i, &start)| RunSpec { label: format!("start {i}"), start, goal: goals[i % goals.len()] })
        .collect();
    let sc = sc.with_runs(runs).map_err(to_py)?;
    let done = AtomicUsize::new(0);
    if let Some(p) = progress {
        p.call1((-(sc.runs().len() as i64),))?;
    }
    if fast {
        let count = || {
            done.fetch_add(1, Ordering::Relaxed);
        };
        let n = sc.runs().len();
        let outcomes = interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
            sc.run_fast(0..n, first as u64, threads != 1, &count, &|| stop.requested())
        })?
        .map_err(to_py)?;
        // `None` only when stopped, and then `interruptible` returned the signal's error.
        return outcome_dict(py, outcomes.unwrap_or_default().iter());
    }
    let results: Result<Vec<Option<RunResult>>, ScenarioError> =
        interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
            let poll = || if stop.requested() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
            let job = |i: usize| {
                let r = match sc.try_run_as(i, (first + i) as u64, |_| ControlFlow::Continue(()), poll)? {
                    ControlFlow::Continue(r) => Some(r),
                    ControlFlow::Break(()) => None,
                };
                done.fetch_add(1, Ordering::Relaxed);
                Ok(r)
            };
            if threads == 1 {
                (0..sc.runs().len()).map(job).collect()
            } else {
                executor::map_ordered(sc.runs().len(), job).into_iter().collect()
            }
        })?;
    // `None` only when stopped, and then `interruptible` returned the signal's error.
    let results: Vec<RunResult> = results.map_err(to_py)?.into_iter().flatten().collect();
    outcome_dict(py, results.iter().map(|r| &r.outcome))
}

/// Times run 0 of a scenario inside Rust, GIL released, `n` times; returns the best
/// wall time in seconds. The work is what `run_scenario` does in Rust (parse, run,
/// build the columns) without the numpy hand-over: the in-process Rust baseline of
/// bench_fig7.py.
#[pyfunction(name = "_time_run_rust")]
pub fn time_run_rust(py: Python<'_>, scenario: &Bound<'_, PyAny>, n: usize) -> PyResult<f64> {
    let source = Source::from_py(scenario)?;
    let best: PyResult<f64> = py.detach(|| {
        let mut best = f64::INFINITY;
        for _ in 0..n.max(1) {
            let t0 = Instant::now();
            let (sc, _) = source.parse().map_err(to_py)?;
            let (_r, cols) = run_one(&sc, 0, &Stop::new(), &AtomicUsize::new(0))?
                .ok_or_else(|| to_py(ScenarioError::new("", "stopped")))?;
            std::hint::black_box(&cols.cols);
            best = best.min(t0.elapsed().as_secs_f64());
        }
        Ok(best)
    });
    best
}

/// The parsed sweep of a scenario, or a `ScenarioError` naming `sweep`.
fn sweep_of(sc: &Scenario) -> PyResult<&SweepSpec> {
    sc.sweep().ok_or_else(|| scenario_error("sweep", None, "sweep: the scenario has no [sweep] table".to_owned()))
}

/// Runs a scenario's `[sweep]` (every law from every start, rayon, GIL released) and
/// returns one entry per (law, start), in law then start order: `law` (list of names),
/// `start` (int64), `x0`, `y0` (m), `theta0` (rad), the outcome arrays of `run_batch`
/// (`final_x` ... `energy`, `converged`, `diverged`), one array per varied key, and
/// `table`, the comparison `wmr-cli sweep` prints; `_meta`: the laws, the varied keys, the
/// resolved scenario (TOML) and the seeds. `progress`: as for `run_scenario`, counting runs.
#[pyfunction(name = "_sweep")]
#[pyo3(signature = (scenario, progress=None, fast=false))]
pub fn sweep<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    progress: Option<&Bound<'py, PyAny>>,
    fast: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let sc = scenario_arg(scenario)?;
    let spec = sweep_of(&sc)?;
    let done = AtomicUsize::new(0);
    if let Some(p) = progress {
        p.call1((-(spec.len() as i64),))?;
    }
    let count = || {
        done.fetch_add(1, Ordering::Relaxed);
    };
    let outcomes = interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
        if fast {
            spec.run_fast_until(sc.sim(), &count, &|| stop.requested())
        } else {
            spec.run_until(sc.sim(), &count, &|| stop.requested())
        }
    })?
    .map_err(to_py)?;
    // `None` only when stopped, and then `interruptible` returned the signal's error.
    sweep_dict(py, &sc, spec, &outcomes.unwrap_or_default())
}

/// Checks a sweep scenario for an outside executor: `(text, runs)`, the scenario's text
/// (each worker parses it again, so a file need not be on the workers' machines) and the
/// number of runs of the sweep.
#[pyfunction(name = "_sweep_plan")]
pub fn sweep_plan(scenario: &Bound<'_, PyAny>) -> PyResult<(String, usize)> {
    let source = Source::from_py(scenario)?;
    let sc = scenario_arg(scenario)?;
    let text = source.text().map_err(|e| from_scenario(&e, source.path()))?;
    Ok((text, sweep_of(&sc)?.len()))
}

/// Values per run in the rows of `_sweep_part` (see [`outcome_row`]).
const ROW_LEN: usize = 22;

/// One sweep outcome as floats (exact: indices below 2^53, f64 values as they are):
/// law, variant, trial, run, start index, start (3), diverged, t_final, final pose (3),
/// goal (3), final_dl, final heading error, time to 1 cm (NaN: never), peak wheel speed,
/// path length, energy.
fn outcome_row(o: &SweepOutcome) -> [f64; ROW_LEN] {
    let u = &o.outcome;
    let termination = match u.termination {
        Termination::Completed => 0.0,
        Termination::Settled => 1.0,
        Termination::NonFinite => 2.0,
        Termination::LeftBox => 3.0,
    };
    [
        o.law as f64,
        o.variant as f64,
        f64::from(o.trial),
        o.run as f64,
        o.start_index as f64,
        o.start.x,
        o.start.y,
        o.start.theta,
        termination,
        u.t_final,
        u.final_pose.x,
        u.final_pose.y,
        u.final_pose.theta,
        u.goal.x,
        u.goal.y,
        u.goal.theta,
        u.final_dl,
        u.final_heading_error,
        u.time_to_arrival.unwrap_or(f64::NAN),
        u.peak_wheel_speed,
        u.path_length,
        u.energy,
    ]
}

/// The outcome a row of [`outcome_row`] holds, or `None` for a row that is no outcome.
fn row_outcome(r: &[f64]) -> Option<SweepOutcome> {
    let index = |v: f64| (v >= 0.0 && v.fract() == 0.0 && v < 9.0e15).then_some(v as usize);
    let termination = match r[8] as u8 {
        0 => Termination::Completed,
        1 => Termination::Settled,
        2 => Termination::NonFinite,
        3 => Termination::LeftBox,
        _ => return None,
    };
    Some(SweepOutcome {
        law: index(r[0])?,
        variant: index(r[1])?,
        trial: u32::try_from(index(r[2])?).ok()?,
        run: index(r[3])? as u64,
        start_index: index(r[4])?,
        start: Pose2::new(r[5], r[6], r[7]),
        outcome: Outcome {
            termination,
            t_final: r[9],
            final_pose: Pose2::new(r[10], r[11], r[12]),
            goal: Pose2::new(r[13], r[14], r[15]),
            final_dl: r[16],
            final_heading_error: r[17],
            time_to_arrival: (!r[18].is_nan()).then_some(r[18]),
            peak_wheel_speed: r[19],
            path_length: r[20],
            energy: r[21],
        },
    })
}

/// Parses the text `_sweep_plan` gave (no warnings: the caller had them).
fn parse_text(text: &str) -> PyResult<Scenario> {
    Scenario::from_toml_str(text, "scenario").map_err(to_py)
}

/// Runs `first..last` of the sweep of `text` (from `_sweep_plan`) on one thread, GIL
/// released: the work of one outside executor's task. Returns an (n, 22) float64 array,
/// one row per run, which `_sweep_gather` puts together.
#[pyfunction(name = "_sweep_part")]
#[pyo3(signature = (text, first, last, fast=false))]
pub fn sweep_part<'py>(
    py: Python<'py>,
    text: &str,
    first: usize,
    last: usize,
    fast: bool,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let sc = parse_text(text)?;
    let spec = sweep_of(&sc)?;
    if first > last {
        return Err(parameter_error("first", format_args!("must be <= last ({first} > {last})")));
    }
    let flow = interruptible(py, |stop| {
        if fast {
            return spec
                .run_fast_range(sc.sim(), first..last, &|| stop.requested())
                .map(|o| o.map_or(ControlFlow::Break(()), ControlFlow::Continue));
        }
        spec.run_range(sc.sim(), first..last, || {
            if stop.requested() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        })
    })?
    .map_err(to_py)?;
    // Stopped only when `interruptible` returned the signal's error.
    let outcomes = match flow {
        ControlFlow::Continue(o) => o,
        ControlFlow::Break(()) => Vec::new(),
    };
    let mut rows = Array2::<f64>::zeros((outcomes.len(), ROW_LEN));
    for (mut row, o) in rows.rows_mut().into_iter().zip(&outcomes) {
        row.iter_mut().zip(outcome_row(o)).for_each(|(a, v)| *a = v);
    }
    Ok(rows.into_pyarray(py))
}

/// The result of `sweep` from the rows of every part (`_sweep_part`), in run order.
#[pyfunction(name = "_sweep_gather")]
pub fn sweep_gather<'py>(
    py: Python<'py>,
    text: &str,
    rows: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let sc = parse_text(text)?;
    let spec = sweep_of(&sc)?;
    let rows = rows.as_array();
    if rows.ncols() != ROW_LEN || rows.nrows() != spec.len() {
        return Err(parameter_error(
            "rows",
            format_args!("expected ({}, {ROW_LEN}) rows, got {:?}", spec.len(), rows.shape()),
        ));
    }
    let mut outcomes = Vec::with_capacity(rows.nrows());
    for (k, r) in rows.rows().into_iter().enumerate() {
        let r = r.to_vec();
        let o =
            row_outcome(&r).filter(|o| o.run == k as u64 && o.law < spec.laws.len() && o.variant < spec.variants.len());
        outcomes.push(o.ok_or_else(|| parameter_error(&format!("rows[{k}]"), "is not the outcome of run {k}"))?);
    }
    sweep_dict(py, &sc, spec, &outcomes)
}

/// The dict `sweep` returns (see there).
fn sweep_dict<'py>(
    py: Python<'py>,
    sc: &Scenario,
    spec: &SweepSpec,
    outcomes: &[SweepOutcome],
) -> PyResult<Bound<'py, PyDict>> {
    let d = outcome_dict(py, outcomes.iter().map(|o| &o.outcome))?;
    let law: Vec<String> = outcomes.iter().map(|o| spec.laws[o.law].0.clone()).collect();
    d.set_item("law", law)?;
    d.set_item("start", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start_index as i64).collect()))?;
    d.set_item("x0", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start.x).collect()))?;
    d.set_item("y0", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start.y).collect()))?;
    d.set_item("theta0", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start.theta).collect()))?;
    // One array per varied key of a robustness sweep (`vary`), the value each run used.
    let values: Vec<Vec<f64>> = outcomes.iter().map(|o| spec.varied_values(o)).collect();
    for (j, k) in spec.variation.keys.iter().enumerate() {
        d.set_item(k.key.as_str(), PyArray1::from_vec(py, values.iter().map(|v| v[j]).collect()))?;
    }
    d.set_item("table", wmr_scenario::summary_table(&wmr_scenario::summarize(spec, outcomes)))?;
    let meta = PyDict::new(py);
    meta.set_item("laws", spec.laws.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>())?;
    let varied = PyDict::new(py);
    for k in &spec.variation.keys {
        let kind = match k.spread {
            wmr_scenario::vary::Spread::Values(_) => "values",
            wmr_scenario::vary::Spread::Uniform(..) => "uniform",
            wmr_scenario::vary::Spread::Normal(..) => "normal",
        };
        varied.set_item(k.key.as_str(), kind)?;
    }
    meta.set_item("varied", varied)?;
    meta.set_item("trials", spec.variation.trials)?;
    meta.set_item("trial", PyArray1::from_vec(py, outcomes.iter().map(|o| i64::from(o.trial)).collect()))?;
    meta.set_item("scenario_toml", sc.to_toml())?;
    meta.set_item("seed", spec.variation.seed)?;
    let starts_seed = match &spec.source {
        StartsSource::Random(r) => Some(r.seed),
        StartsSource::Grid(_) => None,
    };
    meta.set_item("starts_seed", starts_seed)?;
    meta.set_item("goal", (spec.goal.x, spec.goal.y, spec.goal.theta))?;
    d.set_item("_meta", meta)?;
    Ok(d)
}
