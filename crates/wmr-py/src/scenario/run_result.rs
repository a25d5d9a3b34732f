//! `wmr_py.RunResult`: one run's columns, built once in Rust and handed to numpy without
//! a copy, with the run's summary; pickled as its fields.

use numpy::{PyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use wmr_core::Status;
use wmr_core::{FieldGroup, OUTCOME_FIELDS};
use wmr_scenario::{ColumnGroup, MEASURED_COLUMNS, MEASURED_UNITS, RunResult, SAMPLE_COLUMNS, SAMPLE_UNITS};

use crate::error::parameter_error;
use crate::interrupt::try_vec;

/// Number of sample columns (the CSV columns after `run`).
const N_COLS: usize = SAMPLE_COLUMNS.len();

/// Number of a RunResult's columns: the sample columns, then the measured pose.
const N_ALL: usize = N_COLS + MEASURED_COLUMNS.len();

/// Names of a RunResult's columns, in order: wmr-scenario's [`SAMPLE_COLUMNS`], then its
/// [`MEASURED_COLUMNS`] (built from them, not copied).
pub const RESULT_COLUMNS: [&str; N_ALL] = {
    let mut out = [""; N_ALL];
    let mut i = 0;
    while i < N_ALL {
        out[i] = if i < N_COLS { SAMPLE_COLUMNS[i] } else { MEASURED_COLUMNS[i - N_COLS] };
        i += 1;
    }
    out
};

/// The unit of each of [`RESULT_COLUMNS`], in order.
pub const RESULT_UNITS: [&str; N_ALL] = {
    let mut out = [""; N_ALL];
    let mut i = 0;
    while i < N_ALL {
        out[i] = if i < N_COLS { SAMPLE_UNITS[i] } else { MEASURED_UNITS[i - N_COLS] };
        i += 1;
    }
    out
};

/// The column groups a RunResult may have after [`RESULT_COLUMNS`], in CSV order: each
/// only on the runs whose CSV has it ([`ColumnGroup::carried_by`]).
const OPTIONAL_GROUPS: [ColumnGroup; 5] = [
    ColumnGroup::Odometry,
    ColumnGroup::Contact,
    ColumnGroup::Reference,
    ColumnGroup::Command,
    ColumnGroup::Disturbance,
];

/// The optional group that has column `name`, if any.
fn optional_group(name: &str) -> Option<ColumnGroup> {
    OPTIONAL_GROUPS.into_iter().find(|g| g.names().contains(&name))
}

/// One run's columns, built once in Rust: those of the scenario's
/// [`wmr_scenario::Columns`] (the CSV's), with the measured pose always (the true pose
/// without a `[sensor]`), each with the CSV's values.
pub(super) struct Columns {
    shape: wmr_scenario::Columns,
    /// One per name of `shape`, in order.
    pub(super) cols: Vec<Vec<f64>>,
}

impl Columns {
    /// The shape of a RunResult of `scenario`: its CSV's columns, with the measured pose.
    pub(super) fn shape(scenario: &wmr_scenario::Scenario) -> wmr_scenario::Columns {
        wmr_scenario::Columns { measured: true, ..wmr_scenario::Columns::of(scenario) }
    }

    /// Room for `n` samples in every column of `shape`, or `MemoryError`.
    pub(super) fn try_with_capacity(n: usize, shape: wmr_scenario::Columns) -> PyResult<Self> {
        let cols = (0..shape.len()).map(|_| try_vec(n)).collect::<PyResult<_>>()?;
        Ok(Self { shape, cols })
    }

    pub(super) fn push(&mut self, s: &wmr_core::Sample<f64>) {
        for (col, v) in self.cols.iter_mut().zip(self.shape.values(s)) {
            col.push(v);
        }
    }
}

/// One run of a scenario: every CSV column (docs/scenario.md) as a float64 ndarray, plus the
/// run's summary.
///
/// Columns (one value per logged sample): `wmr_py.COLUMNS` (the CSV columns after `run`,
/// units in `wmr_py.COLUMN_UNITS`), then `wmr_py.MEASURED_COLUMNS`, each an attribute.
/// `result["x"]` reads a column by name; `columns()` gives a dict of all CSV columns
/// (with `run`).
#[pyclass(name = "RunResult", module = "wmr_py", frozen)]
pub struct PyRunResult {
    /// 0-based index of the `[[run]]` (the CSV `run` column).
    #[pyo3(get)]
    run: usize,
    /// The run's label.
    #[pyo3(get)]
    label: String,
    /// `"converged"` (final dl < 1 cm, not diverged; within 5 deg of the goal heading for a
    /// law built to reach it), `"diverged"`, `"unsettled"` (neither), `"collided"` (its
    /// footprint touched an obstacle) or, for a tracking run whose reference asks more than
    /// the robot can give, `"cannot_follow"`.
    #[pyo3(get)]
    status: &'static str,
    /// True when not diverged and the final dl < 1 cm.
    #[pyo3(get)]
    converged: bool,
    /// True when the state stopped being finite or C left the 1 km box.
    #[pyo3(get)]
    diverged: bool,
    /// True when the robot's footprint touched an obstacle (`[[world.obstacle]]`): the run
    /// stopped there.
    #[pyo3(get)]
    collided: bool,
    /// The summary line the CLI prints.
    #[pyo3(get)]
    summary: String,
    /// The columns, in [`RESULT_COLUMNS`] order; each is also an attribute of the class
    /// (a property that `add_column_properties` adds from the same list).
    cols: Vec<Py<PyArray1<f64>>>,
    /// The run's groups of [`OPTIONAL_GROUPS`] (those its CSV has), in order, each with
    /// its columns in the group's order.
    groups: Vec<(ColumnGroup, Vec<Py<PyArray1<f64>>>)>,
    /// The run's outcome, in [`OUTCOME_FIELDS`] order, each in its unit (`None` where the
    /// run has none: a time never reached, a tracking figure of a run towards a goal); each
    /// is also an attribute of the class (`add_outcome_properties`).
    fields: [Option<f64>; OUTCOME_FIELDS.len()],
}

impl PyRunResult {
    pub(super) fn new(py: Python<'_>, r: RunResult, cols: Columns) -> Self {
        // from_vec hands each Vec's buffer to numpy: no copy.
        let mut arrays = cols.cols.into_iter().map(|c| PyArray1::from_vec(py, c).unbind());
        let mut groups = Vec::new();
        let mut result_cols = Vec::with_capacity(N_ALL);
        for g in cols.shape.groups() {
            let group: Vec<_> = arrays.by_ref().take(g.names().len()).collect();
            match g {
                ColumnGroup::Sample | ColumnGroup::Measured => result_cols.extend(group),
                g => groups.push((g, group)),
            }
        }
        let cols = result_cols;
        let fields = OUTCOME_FIELDS.map(|f| f.value(&r.outcome, r.tracking.as_ref()));
        Self {
            run: r.index,
            status: r.status().name(),
            converged: r.converged(),
            diverged: r.diverged(),
            collided: r.status() == wmr_core::Status::Collided,
            summary: r.summary_line(),
            label: r.label,
            cols,
            groups,
            fields,
        }
    }

    fn column(&self, name: &str) -> Option<&Py<PyArray1<f64>>> {
        if let Some(i) = RESULT_COLUMNS.iter().position(|c| *c == name) {
            return Some(&self.cols[i]);
        }
        self.groups.iter().find_map(|(g, cols)| g.names().iter().position(|c| *c == name).map(|i| &cols[i]))
    }

    /// Whether the run has the columns of `group`.
    fn has(&self, group: ColumnGroup) -> bool {
        self.groups.iter().any(|(g, _)| *g == group)
    }

    /// The run's column names in CSV order: [`RESULT_COLUMNS`], then its optional groups'.
    fn names(&self) -> impl Iterator<Item = &'static str> + '_ {
        RESULT_COLUMNS.iter().copied().chain(self.groups.iter().flat_map(|(g, _)| g.names().iter().copied()))
    }

    fn len(&self, py: Python<'_>) -> usize {
        self.cols[0].bind(py).len()
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
        d.set_item("summary", &self.summary)?;
        for (f, v) in OUTCOME_FIELDS.iter().zip(self.fields) {
            d.set_item(f.name, v)?;
        }
        for name in self.names() {
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

    /// Every column as an xarray Dataset along `t` (s), each variable with its `units`;
    /// the summary (with a tracking run's rms_error, max_error, time_to_tolerance,
    /// final_error, tracking_tolerance) as attributes. Needs xarray.
    fn to_xarray<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py().import("wmr_py._results")?.getattr("run_result_to_xarray")?.call1((slf,))
    }

    /// Logs the run into a Rerun recording (`recording`, a `rerun.RecordingStream`; the
    /// current one by default) under `entity` (`wmr/runN`): its path, a tracking run's
    /// reference path, the robot's pose over time and every other column as a plot, on the
    /// timeline `timeline` (simulation time, s). Needs rerun-sdk (ImportError naming it).
    #[pyo3(signature = (recording = None, entity = None, timeline = "sim_time"))]
    fn log_rerun<'py>(
        slf: &Bound<'py, Self>,
        recording: Option<Bound<'py, PyAny>>,
        entity: Option<&str>,
        timeline: &str,
    ) -> PyResult<()> {
        slf.py().import("wmr_py._rerun")?.getattr("run_result_log_rerun")?.call1((slf, recording, entity, timeline))?;
        Ok(())
    }

    /// A column by its CSV name, e.g. result["omega_r"]; a tracking run's also
    /// result["x_ref"] ... result["omega_ref"], a run on odometry's result["x_odom"] ...,
    /// a run whose wheels slip result["slip_r"] ... result["n_l"].
    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyArray1<f64>>> {
        self.column(name).map(|c| c.clone_ref(py)).ok_or_else(|| {
            let why = if let Some(g) = optional_group(name) {
                format!("no column {name:?}: only {} has the {} columns", g.carried_by(), g.name())
            } else {
                format!("no column {name:?}; columns are {SAMPLE_COLUMNS:?}")
            };
            pyo3::exceptions::PyKeyError::new_err(why)
        })
    }

    /// Every CSV column of docs/scenario.md (`run` first, as float64 like the others), in
    /// order: the sample columns, then those of the run's odometry, contact and reference
    /// (x_ref ... omega_ref last), as in its CSV.
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let n = self.len(py);
        d.set_item("run", PyArray1::from_vec(py, vec![self.run as f64; n]))?;
        for name in self.names().filter(|n| !MEASURED_COLUMNS.contains(n)) {
            if let Some(c) = self.column(name) {
                d.set_item(name, c.bind(py))?;
            }
        }
        Ok(d)
    }

    /// The run's column names in CSV order: `wmr_py.COLUMNS`, `wmr_py.MEASURED_COLUMNS`,
    /// then a run on odometry's `ODOMETRY_COLUMNS`, a run whose wheels slip's
    /// `CONTACT_COLUMNS` and a tracking run's `REFERENCE_COLUMNS`.
    #[getter]
    fn column_names(&self) -> Vec<&'static str> {
        self.names().collect()
    }

    /// True for a tracking or path-following run (a scenario with a `[reference]`): it
    /// has the reference columns and the tracking summary.
    #[getter]
    fn tracking(&self) -> bool {
        self.has(ColumnGroup::Reference)
    }

    /// Number of logged samples.
    fn __len__(&self, py: Python<'_>) -> usize {
        self.len(py)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<RunResult run={} label={:?} samples={}: {}>", self.run, self.label, self.len(py), self.summary)
    }
}

/// Adds to `RunResult` one read-only property per column of [`RESULT_COLUMNS`]
/// (`result.x` is `result["x"]`, the same array object), with its unit as the doc; and
/// one per column of `OPTIONAL_GROUPS`, which a run without the group lacks
/// (AttributeError).
pub fn add_column_properties(cls: &Bound<'_, pyo3::types::PyType>) -> PyResult<()> {
    let py = cls.py();
    let property = py.import("builtins")?.getattr("property")?;
    let itemgetter = py.import("operator")?.getattr("itemgetter")?;
    for group in OPTIONAL_GROUPS {
        for (name, unit) in group.names().iter().zip(group.units()) {
            let name: &'static str = name;
            let get = pyo3::types::PyCFunction::new_closure(
                py,
                None,
                None,
                move |args: &Bound<'_, PyTuple>, _kw: Option<&Bound<'_, PyDict>>| -> PyResult<Py<PyArray1<f64>>> {
                    let r = args.get_item(0)?;
                    let r = r.cast::<PyRunResult>()?;
                    r.get().column(name).map(|c| c.clone_ref(args.py())).ok_or_else(|| {
                        pyo3::exceptions::PyAttributeError::new_err(format!(
                            "RunResult has no {name}: only {} has the {} columns",
                            group.carried_by(),
                            group.name()
                        ))
                    })
                },
            )?;
            let what = match group {
                ColumnGroup::Odometry => "the pose dead-reckoned from the encoders at the controller's last tick",
                ColumnGroup::Contact => "the wheels' contact with the ground",
                ColumnGroup::Command => "the twist the law demanded at its last tick (ROS 2's /cmd_vel)",
                ColumnGroup::Disturbance => {
                    "the disturbance observer's estimate of the disturbance torque at the wheel"
                }
                _ => "the reference at each sample's t",
            };
            let doc =
                format!("The {name} column of {}, {unit}: {what} (AttributeError otherwise).", group.carried_by());
            cls.setattr(name, property.call1((get, py.None(), py.None(), doc))?)?;
        }
    }
    for (name, unit) in RESULT_COLUMNS.iter().zip(RESULT_UNITS) {
        let doc = if MEASURED_COLUMNS.contains(name) {
            format!(
                "{name} of the pose the controller used at its last tick, {unit} (= {} without a [sensor]).",
                &name[..name.len() - 5]
            )
        } else {
            format!("The {name} column, {unit}, one value per logged sample.")
        };
        let prop = property.call1((itemgetter.call1((*name,))?, py.None(), py.None(), doc))?;
        cls.setattr(*name, prop)?;
    }
    Ok(())
}

/// Adds to `RunResult` one read-only property per outcome field ([`OUTCOME_FIELDS`]:
/// `result.final_dl_m`), with its unit and meaning as the doc: a float, or None where the
/// run has none (a time never reached; a tracking figure of a run towards a goal).
pub fn add_outcome_properties(cls: &Bound<'_, pyo3::types::PyType>) -> PyResult<()> {
    let py = cls.py();
    let property = py.import("builtins")?.getattr("property")?;
    for (i, f) in OUTCOME_FIELDS.iter().enumerate() {
        let get = pyo3::types::PyCFunction::new_closure(
            py,
            None,
            None,
            move |args: &Bound<'_, PyTuple>, _kw: Option<&Bound<'_, PyDict>>| -> PyResult<Option<f64>> {
                let r = args.get_item(0)?;
                Ok(r.cast::<PyRunResult>()?.get().fields[i])
            },
        )?;
        let when = match f.group {
            FieldGroup::Tracking | FieldGroup::TrackingSetting => " A tracking run's; None for a run towards a goal.",
            _ => "",
        };
        let doc = format!("{}, {}.{when}", capitalized(f.doc), f.unit);
        cls.setattr(f.name, property.call1((get, py.None(), py.None(), doc))?)?;
    }
    Ok(())
}

/// `text` with its first letter upper-case.
fn capitalized(text: &str) -> String {
    let mut c = text.chars();
    c.next().map(|first| first.to_uppercase().chain(c).collect()).unwrap_or_default()
}

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
    // Every column one sample per row, all of one length: a result with a short column
    // would index past its end (issue 25, item 13).
    let mut rows: Option<(usize, &str)> = None;
    for name in RESULT_COLUMNS {
        let a = get(name)?;
        let a = a.cast_into::<PyArray1<f64>>().map_err(|_| parameter_error(name, "expected a float64 array"))?;
        let len = a.len();
        match rows {
            None => rows = Some((len, name)),
            Some((n, first)) if n != len => {
                return Err(parameter_error(
                    &format!("state.{name}"),
                    format_args!("has {len} samples, {first} has {n}: every column has one value per sample"),
                ));
            }
            Some(_) => {}
        }
        cols.push(a.unbind());
    }
    // Each optional group's columns: all or none, each as long as the others.
    let mut groups = Vec::new();
    for group in OPTIONAL_GROUPS {
        let mut cols = Vec::new();
        for name in group.names() {
            let Some(a) = state.get_item(name)?.filter(|a| !a.is_none()) else { continue };
            let a = a.cast_into::<PyArray1<f64>>().map_err(|_| parameter_error(name, "expected a float64 array"))?;
            if let Some((n, first)) = rows
                && a.len() != n
            {
                return Err(parameter_error(
                    &format!("state.{name}"),
                    format_args!("has {} samples, {first} has {n}: every column has one value per sample", a.len()),
                ));
            }
            cols.push(a.unbind());
        }
        match cols.len() {
            0 => {}
            n if n == group.names().len() => groups.push((group, cols)),
            n => {
                return Err(parameter_error(
                    "state",
                    format_args!(
                        "has {n} of the {} {} columns: {} has all of them",
                        group.names().len(),
                        group.name(),
                        group.carried_by()
                    ),
                ));
            }
        }
    }
    Ok(PyRunResult {
        run: get("run")?.extract()?,
        label: get("label")?.extract()?,
        status,
        converged: get("converged")?.extract()?,
        diverged: get("diverged")?.extract()?,
        // Derived from the status (a pickle from before it had no such entry).
        collided: status == wmr_core::Status::Collided.name(),
        summary: get("summary")?.extract()?,
        fields: {
            let mut values = [None; OUTCOME_FIELDS.len()];
            for (v, f) in values.iter_mut().zip(&OUTCOME_FIELDS) {
                *v = get(f.name)?.extract()?;
            }
            values
        },
        groups,
        cols,
    })
}
