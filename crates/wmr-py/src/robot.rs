//! `wmr_py.Robot`: the core's validated [`Robot`] with its equations of motion and RK4.

use numpy::{PyArray1, ToPyArray};
use pyo3::exceptions::PyFloatingPointError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::integrator::rk4_step;
use wmr_core::state::STATE_LEN;
use wmr_core::{Robot, RobotParams, State, Wheels};

use crate::convert::{finite_array, finite_scalar};
use crate::error::parameter_error;

/// Names of the state components, in order, for messages.
pub const STATE_NAMES: [&str; STATE_LEN] = ["x", "y", "theta", "v", "omega", "phi_r", "phi_l"];

/// A differential-drive robot (docs/model.md): physical parameters, SI units.
///
/// Robot(**params), params being the scenario's `[robot]` keys: mass=5.0,
/// wheel_radius=0.1, half_track=0.2, com_offset=0.25, wheel_inertia=0.002,
/// platform_inertia=0.005, gear_ratio=0.1, viscous_friction=0.0, coulomb_friction=0.0,
/// coulomb_speed=1e-3.
///
/// Every keyword is optional and defaults to the paper's robot: mass m (kg), wheel
/// radius r (m), half track R (m, axle midpoint C to each wheel), com_offset d (m, C
/// forward to the centre of mass G), wheel_inertia I_m (kg m^2, one wheel plus rotor),
/// platform_inertia I_p (kg m^2, about G), gear_ratio k_t (wheel speed = k_t * motor
/// speed), viscous_friction b_v (N m s), coulomb_friction tau_c (N m) smoothed by
/// tanh(omega / coulomb_speed) (rad/s).
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
    fn derivative<'py>(
        &self,
        py: Python<'py>,
        state: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let s = state_arg(state, "state")?;
        let tau = wheels_arg(tau, "tau", ["tau_r", "tau_l"])?;
        state_out(py, &self.inner.derivative(&s, tau), "the derivative")
    }

    /// The state after one classic RK4 step of dt seconds with the wheel torques
    /// tau = (tau_r, tau_l), N m, held constant over the step. Returns ndarray (7,).
    ///
    /// This is the core's integrator, the same arithmetic as the closed-loop simulation.
    fn step<'py>(
        &self,
        py: Python<'py>,
        state: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        dt: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let s = state_arg(state, "state")?;
        let tau = wheels_arg(tau, "tau", ["tau_r", "tau_l"])?;
        let dt = finite_scalar(dt, "dt")?;
        if dt <= 0.0 {
            return Err(parameter_error("dt", format_args!("must be > 0 (got {dt})")));
        }
        let robot = &self.inner;
        let next = rk4_step(
            |_, y: &[f64; STATE_LEN]| robot.derivative(&State::from_array(*y), tau).to_array(),
            0.0,
            &s.to_array(),
            dt,
        );
        state_out(py, &State::from_array(next), "the state after the step")
    }

    /// Kinetic energy, J: 1/2 M11 v^2 + 1/2 M22 omega^2 (platform, wheels and rotors).
    fn kinetic_energy(&self, state: &Bound<'_, PyAny>) -> PyResult<f64> {
        let s = state_arg(state, "state")?;
        Ok(self.inner.kinetic_energy(&s))
    }

    /// Wheel speeds (omega_r, omega_l), rad/s, of a state: ((v + R omega)/r, (v - R omega)/r).
    fn wheel_speeds(&self, state: &Bound<'_, PyAny>) -> PyResult<(f64, f64)> {
        let s = state_arg(state, "state")?;
        let w = s.wheel_speeds(self.inner.params());
        Ok((w.right, w.left))
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

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyRobot>().is_ok_and(|o| o.get().inner == self.inner)
    }
}

/// The `[robot]` keys and values.
pub fn robot_items(p: &RobotParams<f64>) -> [(&'static str, f64); 10] {
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
    ]
}
