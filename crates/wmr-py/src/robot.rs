//! `wmr_py.Robot`: the core's validated [`Robot`] with its equations of motion and RK4.

use numpy::ndarray::{Array1, Array2, ArrayView2};
use numpy::{IntoPyArray, PyArray1, PyUntypedArrayMethods, ToPyArray};
use pyo3::exceptions::PyFloatingPointError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use wmr_core::integrator::rk4_step;
use wmr_core::state::STATE_LEN;
use wmr_core::{Robot, RobotParams, State, Wheels};

use crate::alloc::{bytes_of, check_alloc, leading_rows, zeros2};
use crate::convert::{batch_arg, finite_array, finite_scalar, same_rows};
use crate::error::parameter_error;

/// Names of the state components, in order, for messages.
pub const STATE_NAMES: [&str; STATE_LEN] = ["x", "y", "theta", "v", "omega", "phi_r", "phi_l"];

/// A differential-drive robot (docs/model.md): physical parameters, SI units.
///
/// Robot(**params), params being the scenario's `[robot]` keys: mass=5.0,
/// wheel_radius=0.1, half_track=0.2, com_offset=0.25, wheel_inertia=0.002,
/// platform_inertia=0.005, gear_ratio=0.1, viscous_friction=0.0, coulomb_friction=0.0,
/// coulomb_speed=1e-3, static_friction=0.0.
///
/// Every keyword is optional and defaults to the paper's robot: mass m (kg), wheel
/// radius r (m), half track R (m, axle midpoint C to each wheel), com_offset d (m, C
/// forward to the centre of mass G), wheel_inertia I_m (kg m^2, one wheel plus rotor),
/// platform_inertia I_p (kg m^2, about G), gear_ratio k_t (wheel speed = k_t * motor
/// speed), viscous_friction b_v (N m s), coulomb_friction tau_c (N m) smoothed by
/// tanh(omega / coulomb_speed) (rad/s), static_friction tau_s (N m, stiction's breakaway
/// torque, 0: off).
///
/// The state is the 7-vector [x, y, theta, v, omega, phi_r, phi_l]: point C (m, world
/// frame), heading (rad), forward speed of C (m/s), yaw rate (rad/s), wheel angles (rad).
///
/// Raises ScenarioError (a ValueError) naming the key, e.g. ``robot.mass``, also for an
/// unknown keyword (``robot.mas``): the keys are parsed and checked by the scenario code.
#[pyclass(name = "Robot", module = "wmr_py", frozen)]
#[derive(Clone)]
pub struct PyRobot {
    pub(crate) inner: Robot<f64>,
}

impl From<Robot<f64>> for PyRobot {
    fn from(inner: Robot<f64>) -> Self {
        Self { inner }
    }
}

/// A one-run scenario dict `{robot, drive, controller, run = [{goal}]}` (tables left out
/// when None): how the building blocks reuse the scenario's parsing and checks.
pub fn one_run_scenario<'py>(
    py: Python<'py>,
    robot: Option<&Bound<'py, PyDict>>,
    drive: Option<&Bound<'py, PyAny>>,
    controller: Option<&Bound<'py, PyDict>>,
    goal: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    {
        let sc = PyDict::new(py);
        if let Some(r) = robot {
            sc.set_item("robot", r)?;
        }
        if let Some(d) = drive {
            sc.set_item("drive", d)?;
        }
        if let Some(c) = controller {
            sc.set_item("controller", c)?;
        }
        let run = PyDict::new(py);
        match goal {
            Some(g) => run.set_item("goal", g)?,
            None => run.set_item("goal", PyDict::new(py))?,
        }
        sc.set_item("run", vec![run])?;
        Ok(sc)
    }
}

/// A state argument as the core's [`State`], every component finite.
pub fn state_arg(obj: &Bound<'_, PyAny>, arg: &str) -> PyResult<State<f64>> {
    Ok(State::from_array(finite_array(obj, arg, STATE_NAMES)?))
}

/// A `(right, left)` pair argument, both finite.
pub fn wheels_arg(obj: &Bound<'_, PyAny>, arg: &str, names: [&str; 2]) -> PyResult<Wheels<f64>> {
    let [right, left] = finite_array(obj, arg, names)?;
    Ok(Wheels::new(right, left))
}

fn state_out<'py>(py: Python<'py>, s: &State<f64>, what: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
    if !s.is_finite() {
        return Err(PyFloatingPointError::new_err(format!(
            "{what} is not finite: {:?} (the state or torques are too large for the model)",
            s.to_array()
        )));
    }
    Ok(s.to_array().to_pyarray(py))
}

/// A quantity computed from a finite state, checked finite as [`state_out`] checks the
/// state after a step: a state too large for the model raises, never returns inf.
fn finite_out(values: &[f64], what: &str) -> PyResult<()> {
    if values.iter().all(|v| v.is_finite()) {
        return Ok(());
    }
    Err(PyFloatingPointError::new_err(format!(
        "{what} is not finite: {values:?} (the state is too large for the model)"
    )))
}

/// Row `i` of an (N, 7) state array.
fn state_row(a: &ArrayView2<'_, f64>, i: usize) -> State<f64> {
    State::from_array(std::array::from_fn(|j| a[[i, j]]))
}

/// An (N, 7) array of states out, every value finite (else `FloatingPointError` naming the row).
fn states_out<'py>(py: Python<'py>, out: Array2<f64>, what: &str) -> PyResult<Py<PyAny>> {
    if let Some(((i, _), _)) = out.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(PyFloatingPointError::new_err(format!(
            "{what} of robot {i} is not finite: {:?} (the state or torques are too large for the model)",
            out.row(i).to_vec()
        )));
    }
    Ok(out.into_pyarray(py).into_any().unbind())
}

/// Batched `state` (N, 7) and `tau` (N, 2) arguments, or `None` for single (1-D) ones.
type Batch<'py> = (numpy::PyReadonlyArray2<'py, f64>, numpy::PyReadonlyArray2<'py, f64>);

fn state_tau_batch<'py>(
    state: &Bound<'py, PyAny>,
    tau: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Option<Batch<'py>>> {
    // The (N, 7) result, checked before the arguments' values are read.
    if let Some(n) = leading_rows(state) {
        let bytes = bytes_of::<f64>(n).saturating_mul(STATE_LEN as u128);
        check_alloc(bytes, "state", || format!("the ({n}, {STATE_LEN}) array of {what}"))?;
    }
    let Some(s) = batch_arg(state, "state", STATE_NAMES)? else { return Ok(None) };
    let t = batch_arg(tau, "tau", ["tau_r", "tau_l"])?
        .ok_or_else(|| parameter_error("tau", "expected shape (N, 2) like state's (N, 7)"))?;
    same_rows(&t, "tau", s.shape()[0], "state")?;
    Ok(Some((s, t)))
}

#[pymethods]
impl PyRobot {
    #[new]
    #[pyo3(signature = (**params))]
    fn new(py: Python<'_>, params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        // The scenario's `[robot]` table: same keys, defaults and checks as a file.
        let sc = crate::scenario::scenario_arg(one_run_scenario(py, params, None, None, None)?.as_any())?;
        Ok((*sc.robot()).into())
    }

    /// Time derivative of the state, ndarray (7,): [x', y', theta', v', omega', phi_r', phi_l']
    /// in (m/s, m/s, rad/s, m/s^2, rad/s^2, rad/s, rad/s), under wheel torques
    /// tau = (tau_r, tau_l) in N m (the torques the drives put on the wheels), eq. (15).
    ///
    /// A batch: state (N, 7) and tau (N, 2) give an (N, 7) array, row i from row i.
    fn derivative<'py>(
        &self,
        py: Python<'py>,
        state: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        if let Some((s, t)) = state_tau_batch(state, tau, "derivatives")? {
            let (s, t) = (s.as_array(), t.as_array());
            let mut out = zeros2(s.nrows(), STATE_LEN, "state", "derivatives")?;
            for (i, mut row) in out.rows_mut().into_iter().enumerate() {
                let d = self.inner.derivative(&state_row(&s, i), Wheels::new(t[[i, 0]], t[[i, 1]])).to_array();
                row.iter_mut().zip(d).for_each(|(o, v)| *o = v);
            }
            return states_out(py, out, "the derivative");
        }
        let s = state_arg(state, "state")?;
        let tau = wheels_arg(tau, "tau", ["tau_r", "tau_l"])?;
        Ok(state_out(py, &self.inner.derivative(&s, tau), "the derivative")?.into_any().unbind())
    }

    /// The state after one classic RK4 step of dt seconds with the wheel torques
    /// tau = (tau_r, tau_l), N m, held constant over the step. Returns ndarray (7,).
    ///
    /// This is the core's integrator, the same arithmetic as the closed-loop simulation.
    /// A batch: state (N, 7) and tau (N, 2) give the (N, 7) states after the step.
    fn step<'py>(
        &self,
        py: Python<'py>,
        state: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        dt: &Bound<'py, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let batch = state_tau_batch(state, tau, "states after the step")?;
        let dt = finite_scalar(dt, "dt")?;
        if dt <= 0.0 {
            return Err(parameter_error("dt", format_args!("must be > 0 (got {dt})")));
        }
        let robot = &self.inner;
        let rk4 = |s: &State<f64>, tau: Wheels<f64>| {
            rk4_step(
                |_, y: &[f64; STATE_LEN]| robot.derivative(&State::from_array(*y), tau).to_array(),
                0.0,
                &s.to_array(),
                dt,
            )
        };
        if let Some((s, t)) = batch {
            let (s, t) = (s.as_array(), t.as_array());
            let mut out = zeros2(s.nrows(), STATE_LEN, "state", "states after the step")?;
            for (i, mut row) in out.rows_mut().into_iter().enumerate() {
                let next = rk4(&state_row(&s, i), Wheels::new(t[[i, 0]], t[[i, 1]]));
                row.iter_mut().zip(next).for_each(|(o, v)| *o = v);
            }
            return states_out(py, out, "the state after the step");
        }
        let s = state_arg(state, "state")?;
        let tau = wheels_arg(tau, "tau", ["tau_r", "tau_l"])?;
        let next = rk4_step(
            |_, y: &[f64; STATE_LEN]| robot.derivative(&State::from_array(*y), tau).to_array(),
            0.0,
            &s.to_array(),
            dt,
        );
        Ok(state_out(py, &State::from_array(next), "the state after the step")?.into_any().unbind())
    }

    /// Kinetic energy, J: 1/2 M11 v^2 + 1/2 M22 omega^2 (platform, wheels and rotors).
    /// A batch of states (N, 7) gives an (N,) array.
    fn kinetic_energy(&self, py: Python<'_>, state: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        if let Some(s) = batch_arg(state, "state", STATE_NAMES)? {
            let s = s.as_array();
            let mut out = zeros2(s.nrows(), 1, "state", "kinetic energies")?;
            for (i, e) in out.iter_mut().enumerate() {
                *e = self.inner.kinetic_energy(&state_row(&s, i));
            }
            let out: Array1<f64> = out.into_shape_with_order(s.nrows()).map_err(|e| parameter_error("state", e))?;
            if let Some(i) = out.iter().position(|v| !v.is_finite()) {
                finite_out(&[out[i]], &format!("the kinetic energy of robot {i}"))?;
            }
            return Ok(out.into_pyarray(py).into_any().unbind());
        }
        let s = state_arg(state, "state")?;
        let e = self.inner.kinetic_energy(&s);
        finite_out(&[e], "the kinetic energy")?;
        Ok(e.into_pyobject(py)?.into_any().unbind())
    }

    /// Wheel speeds (omega_r, omega_l), rad/s, of a state: ((v + R omega)/r, (v - R omega)/r).
    /// A batch of states (N, 7) gives an (N, 2) array.
    fn wheel_speeds(&self, py: Python<'_>, state: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        if let Some(s) = batch_arg(state, "state", STATE_NAMES)? {
            let s = s.as_array();
            let mut out = zeros2(s.nrows(), 2, "state", "wheel speeds")?;
            for (i, mut row) in out.rows_mut().into_iter().enumerate() {
                let w = state_row(&s, i).wheel_speeds(self.inner.params());
                finite_out(&[w.right, w.left], &format!("the wheel speeds of robot {i}"))?;
                row[0] = w.right;
                row[1] = w.left;
            }
            return Ok(out.into_pyarray(py).into_any().unbind());
        }
        let s = state_arg(state, "state")?;
        let w = s.wheel_speeds(self.inner.params());
        finite_out(&[w.right, w.left], "the wheel speeds")?;
        Ok((w.right, w.left).into_pyobject(py)?.into_any().unbind())
    }

    /// Diagonal of the reduced inertia matrix M_r of (15): (M11 in kg, M22 in kg m^2).
    #[getter]
    fn reduced_inertia(&self) -> (f64, f64) {
        self.inner.reduced_inertia()
    }

    /// m, total mass, kg.
    #[getter]
    fn mass(&self) -> f64 {
        self.inner.params().mass
    }
    /// r, wheel radius, m.
    #[getter]
    fn wheel_radius(&self) -> f64 {
        self.inner.params().wheel_radius
    }
    /// R, half the distance between the wheels (axle midpoint C to each wheel), m.
    #[getter]
    fn half_track(&self) -> f64 {
        self.inner.params().half_track
    }
    /// d, distance from C forward to the centre of mass G, m.
    #[getter]
    fn com_offset(&self) -> f64 {
        self.inner.params().com_offset
    }
    /// I_m, inertia of one wheel plus its motor rotor about the wheel axis, kg m^2.
    #[getter]
    fn wheel_inertia(&self) -> f64 {
        self.inner.params().wheel_inertia
    }
    /// I_p, platform inertia about G, kg m^2.
    #[getter]
    fn platform_inertia(&self) -> f64 {
        self.inner.params().platform_inertia
    }
    /// k_t, gear reduction: wheel speed = k_t * motor speed.
    #[getter]
    fn gear_ratio(&self) -> f64 {
        self.inner.params().gear_ratio
    }
    /// b_v, viscous friction at each wheel, N m s.
    #[getter]
    fn viscous_friction(&self) -> f64 {
        self.inner.params().viscous_friction
    }
    /// tau_c, Coulomb friction at each wheel, N m.
    #[getter]
    fn coulomb_friction(&self) -> f64 {
        self.inner.params().coulomb_friction
    }
    /// omega_eps, rad/s: Coulomb friction is tau_c tanh(omega / omega_eps).
    #[getter]
    fn coulomb_speed(&self) -> f64 {
        self.inner.params().coulomb_speed
    }
    /// tau_s, N m: stiction's breakaway torque at each wheel (0: off); the plant's step
    /// holds a wheel at rest below it (`derivative` and `step` are (15) without it).
    #[getter]
    fn static_friction(&self) -> f64 {
        self.inner.params().static_friction
    }

    /// The robot as a URDF (XML text), named `name`: the platform on `base_link` (mass and
    /// inertia at the centre of mass), the wheels on `wheel_left_joint` and
    /// `wheel_right_joint`, a caster; the file `wmr-cli urdf` writes for the same robot.
    #[pyo3(signature = (name = "wmr"))]
    fn urdf(&self, name: &str) -> String {
        wmr_scenario::urdf::urdf(self.inner.params(), name, "")
    }

    /// The parameters as a dict with the scenario's `[robot]` keys (SI units).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self.inner.params();
        let d = PyDict::new(py);
        for (k, v) in robot_items(p) {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let items: Vec<String> = robot_items(self.inner.params()).iter().map(|(k, v)| format!("{k}={v:?}")).collect();
        format!("Robot({})", items.join(", "))
    }

    /// Pickles as `wmr_py._make_robot(self.to_dict())`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let make = py.import("wmr_py")?.getattr("_make_robot")?;
        PyTuple::new(py, [make, PyTuple::new(py, [self.to_dict(py)?])?.into_any()])
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyRobot>().is_ok_and(|o| o.get().inner == self.inner)
    }
}

/// The `[robot]` keys and values.
pub fn robot_items(p: &RobotParams<f64>) -> [(&'static str, f64); 11] {
    [
        ("mass", p.mass),
        ("wheel_radius", p.wheel_radius),
        ("half_track", p.half_track),
        ("com_offset", p.com_offset),
        ("wheel_inertia", p.wheel_inertia),
        ("platform_inertia", p.platform_inertia),
        ("gear_ratio", p.gear_ratio),
        ("viscous_friction", p.viscous_friction),
        ("coulomb_friction", p.coulomb_friction),
        ("coulomb_speed", p.coulomb_speed),
        ("static_friction", p.static_friction),
    ]
}
