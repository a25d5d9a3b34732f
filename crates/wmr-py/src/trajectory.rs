//! `wmr_py.Reference`: the moving reference of a tracking or path-following run (circle,
//! figure_eight, line, waypoints, file), built from the scenario's `[reference]` keys by
//! the scenario code (`wmr_scenario::reference::resolve`): one description of the keys,
//! the one parser, the one set of checks and error names (`reference.radius`).

use numpy::IntoPyArray;
use numpy::ndarray::Ix1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use wmr_core::{Reference, ReferenceState};
use wmr_scenario::reference::{ReferenceSpec, RunReference, resolve};

use crate::alloc::zeros2;
use crate::convert::{finite_scalar, readonly_array, type_name};
use crate::error::{from_scenario, parameter_error, scenario_error};
use crate::scenario::to_toml;

/// A TOML value as the Python value a scenario dict would hold.
fn to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Array(a) => {
            PyList::new(py, a.iter().map(|x| to_py(py, x)).collect::<PyResult<Vec<_>>>()?)?.into_any()
        }
        toml::Value::Table(t) => table_to_py(py, t)?.into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
    })
}

fn table_to_py<'py>(py: Python<'py>, t: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, to_py(py, v)?)?;
    }
    Ok(d)
}

/// A reference state as the dict `update(reference=...)` takes: pose (x m, y m, theta
/// rad), twist (v m/s, omega rad/s), accel (v' m/s^2, omega' rad/s^2).
fn state_dict<'py>(py: Python<'py>, r: &ReferenceState<f64>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("pose", (r.pose.x, r.pose.y, r.pose.theta))?;
    d.set_item("twist", (r.twist.v, r.twist.omega))?;
    d.set_item("accel", (r.accel.v, r.accel.omega))?;
    Ok(d)
}

/// A moving reference (docs/scenario.md, `[reference]`; docs/model.md, "Tracking and path
/// following"): the reference point C_ref's pose, twist and acceleration at each time
/// and, for path following, its geometric path.
///
/// Reference(kind, **keys): kind "circle" (center, radius, speed, phase_deg),
/// "figure_eight" (center, width, height, period), "line" (start, speed), "waypoints"
/// (points, speed, accel_max) or "file" (path, speed, accel_max): the keys, units and
/// defaults of the scenario's `[reference]` table, read and checked by the scenario
/// code; a bad or unknown key raises ScenarioError naming it (``reference.radius``).
/// A `file` path is relative to the current folder (kept as an absolute path, so the
/// reference means the same file on an executor's workers); it may lead anywhere, as
/// `open`'s does (a scenario's own `path` keys stay in its folder: `allow_files_under`).
///
/// `simulate`, `run_batch` and the tracking laws' classes take a Reference or the same
/// keys as a dict (``{"kind": "circle", "radius": 1.0}``).
#[pyclass(name = "Reference", module = "wmr_py", frozen)]
#[derive(Clone)]
pub struct PyReference {
    pub(crate) spec: ReferenceSpec,
}

impl PyReference {
    /// The reference of a resolved scenario's `[reference]`.
    pub fn from_spec(spec: ReferenceSpec) -> Self {
        Self { spec }
    }

    /// The core's reference.
    pub fn built(&self) -> RunReference {
        self.spec.built.clone()
    }

    /// `[reference]` keys, as TOML, for a scenario built from Python.
    pub fn table(&self) -> &toml::Table {
        &self.spec.table
    }
}

/// The `reference=` argument of `simulate`, `run_batch` and the law classes: a
/// [`PyReference`] or a dict of `[reference]` keys, as a scenario dict's `reference` table.
pub fn reference_table<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    if let Ok(r) = obj.cast::<PyReference>() {
        return table_to_py(obj.py(), r.get().table());
    }
    match obj.cast::<PyDict>() {
        Ok(d) => Ok(d.clone()),
        Err(_) => Err(parameter_error(
            "reference",
            format_args!("expected a wmr_py.Reference or a dict of [reference] keys, got {}", type_name(obj)),
        )),
    }
}

#[pymethods]
impl PyReference {
    #[new]
    #[pyo3(signature = (kind, **keys))]
    fn new(py: Python<'_>, kind: &Bound<'_, PyAny>, keys: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let d = PyDict::new(py);
        if let Some(k) = keys {
            if k.contains("kind")? {
                return Err(parameter_error("reference.kind", "given twice (as the first argument and as a keyword)"));
            }
            d.update(k.as_mapping())?;
        }
        d.set_item("kind", kind)?;
        let Some(toml::Value::Table(mut table)) = to_toml(d.as_any(), "reference")? else {
            return Err(scenario_error("reference", None, "reference: expected keys".to_owned()));
        };
        // A relative `file` path is made absolute now: a worker process or a pickled copy
        // reads the same file whatever its current folder.
        if let Some(toml::Value::String(p)) = table.get("path")
            && std::path::Path::new(p).is_relative()
            && let Ok(cwd) = std::env::current_dir()
        {
            let full = cwd.join(p).to_string_lossy().into_owned();
            table.insert("path".to_owned(), toml::Value::String(full));
        }
        // The path is the caller's own (as for `open`), not one a scenario names: any file.
        let spec = resolve(&table, None, &wmr_scenario::FileAccess::anywhere()).map_err(|e| from_scenario(&e, None))?;
        Ok(Self { spec })
    }

    /// The kind: "circle", "figure_eight", "line", "waypoints" or "file".
    #[getter]
    fn kind(&self) -> String {
        self.spec.table.get("kind").and_then(toml::Value::as_str).unwrap_or(self.spec.built.kind()).to_owned()
    }

    /// The keys as given (with `kind`): a dict that `simulate(reference=...)` and a
    /// scenario's `[reference]` table take as they are.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        table_to_py(py, &self.spec.table)
    }

    /// Pose of C_ref at t = 0, (x_m, y_m, theta_rad): where a run that starts on the
    /// reference starts.
    #[getter]
    fn start_pose(&self) -> (f64, f64, f64) {
        let p = self.spec.built.start_pose();
        (p.x, p.y, p.theta)
    }

    /// The state of C_ref at time t_s (s): for a number, a dict {"pose": (x_m, y_m,
    /// theta_rad), "twist": (v m/s, omega rad/s), "accel": (v' m/s^2, omega' rad/s^2)}
    /// (what a controller's update(reference=...) takes); for a 1-D array of N times,
    /// an (N, 7) array of rows (x, y, theta, v, omega, v', omega'). The same numbers as
    /// the CSV's x_ref ... omega_ref columns at those times.
    fn state_at<'py>(&self, py: Python<'py>, t_s: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let r = &self.spec.built;
        if let Some(a) = readonly_array::<f64, Ix1>(t_s)? {
            let a = a.as_array();
            let mut out = zeros2(a.len(), 7, "t_s", "reference states")?;
            for (i, (mut row, &t)) in out.rows_mut().into_iter().zip(a.iter()).enumerate() {
                if !t.is_finite() {
                    return Err(parameter_error(
                        &format!("t_s[{i}]"),
                        format_args!("must be a finite number (got {t})"),
                    ));
                }
                let s = r.state_at(t);
                let v = [s.pose.x, s.pose.y, s.pose.theta, s.twist.v, s.twist.omega, s.accel.v, s.accel.omega];
                row.iter_mut().zip(v).for_each(|(o, v)| *o = v);
            }
            return Ok(out.into_pyarray(py).into_any());
        }
        let t = finite_scalar(t_s, "t_s")?;
        Ok(state_dict(py, &r.state_at(t))?.into_any())
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let mut parts = vec![format!("{:?}", self.kind())];
        for (k, v) in &self.spec.table {
            if k != "kind" {
                parts.push(format!("{k}={}", to_py(py, v)?.repr()?));
            }
        }
        Ok(format!("Reference({})", parts.join(", ")))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyReference>().is_ok_and(|o| o.get().spec == self.spec)
    }

    /// Pickles as `wmr_py._make_reference(self.to_dict())`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let make = py.import("wmr_py")?.getattr("_make_reference")?;
        PyTuple::new(py, [make, PyTuple::new(py, [self.to_dict(py)?])?.into_any()])
    }
}
