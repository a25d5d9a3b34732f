//! `wmr_py.PaperController`: the paper's law and its wheel stage (the core's
//! [`wmr_core::Controller`]) for loops closed in Python.

use pyo3::exceptions::PyFloatingPointError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::{ControlOutput, Measurement, Pose2};
use wmr_scenario::BuiltController;

use crate::convert::{finite_array, pose_table, type_name};
use crate::error::parameter_error;
use crate::robot::{PyRobot, one_run_scenario, wheels_arg};
use crate::scenario::scenario_arg;

/// The paper's point-stabilization controller (docs/model.md) with its two wheel servos.
///
/// PaperController(goal, robot=None, drive=None, **gains)
///
/// goal: the goal pose of C, (x_m, y_m, theta_rad) or a dict with x, y and theta (rad)
/// or theta_deg (degrees). robot: a Robot or a dict of `[robot]` keys (default: the
/// paper's). drive: a dict of `[drive]` keys (default: the torque drive); it sets the
/// servo's defaults and anti-windup bound. gains: the scenario's `[controller]` keys of
/// kind "paper": the law's mode ("pose" or "position"), kp_theta (rad/rad, 2), ki_theta
/// (1/s, 0.1), kp_s (m/m, 1), ki_s (1/s, 0.25), goal_radius (m, 0.001), hold_radius (m,
/// 0.005; 0 = off), hold ("auto", "zero_errors" or "freeze"); the wheel stage's servo_kp
/// (N m/rad, 14), servo_kd (N m s/rad, 1.4), servo_ki (N m/(rad s), 0), wheel_speed_max
/// (rad/s, inf); control_dt (s, 0.001). Parsed and checked by the scenario code: a bad or
/// unknown key raises ScenarioError naming it (``controller.kp_s``).
///
/// Call update() once every control_dt seconds and hold its output in between. With
/// the torque drive the output is the wheel torque demand (N m) before the drive's clamp
/// (|tau| <= motor_torque_max / gear_ratio, 2 N m by default); with dc_motor, volts.
#[pyclass(name = "PaperController", module = "wmr_py")]
pub struct PyPaperController {
    /// The paper's law with its wheel stage, as the scenario builds it.
    inner: BuiltController,
    goal: Pose2<f64>,
    /// Control ticks since construction or reset: the time of a tick is ticks * control_dt.
    ticks: u64,
    last: ControlOutput<f64>,
}

#[pymethods]
impl PyPaperController {
    #[new]
    #[pyo3(signature = (goal, robot=None, drive=None, **gains))]
    fn new(
        goal: &Bound<'_, PyAny>,
        robot: Option<&Bound<'_, PyAny>>,
        drive: Option<&Bound<'_, PyAny>>,
        gains: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let py = goal.py();
        let robot = match robot {
            None => None,
            Some(r) => match r.cast::<PyRobot>() {
                Ok(r) => Some(r.call_method0("to_dict")?.cast_into::<PyDict>()?),
                Err(_) => Some(
                    r.cast::<PyDict>()
                        .map_err(|_| {
                            parameter_error("robot", format_args!("expected a Robot or a dict, got {}", type_name(r)))
                        })?
                        .clone(),
                ),
            },
        };
        let goal = pose_table(goal, "goal")?;
        // A one-run scenario: the scenario code parses the keys, fills the defaults
        // (servo gains by drive kind) and checks everything, as for a file.
        let table = one_run_scenario(py, robot.as_ref(), drive, gains, Some(&goal))?;
        let sc = scenario_arg(table.as_any())?;
        let goal = sc.runs().first().map(|r| r.goal).unwrap_or_default();
        let inner = *sc.built_controller();
        if inner.law().kind() != "paper" {
            return Err(parameter_error("controller.kind", "PaperController needs kind = \"paper\""));
        }
        Ok(Self { inner, goal, ticks: 0, last: ControlOutput::default() })
    }

    /// One control tick: the wheel commands (tau_r, tau_l) in N m (the servos' wheel
    /// torque demands, before the drive's clamp) from the measured pose (x_m, y_m,
    /// theta_rad) of C, the wheel angles (phi_r, phi_l) in rad and the wheel speeds
    /// (omega_r, omega_l) in rad/s. Advances the integrators by control_dt.
    /// The errors of this tick are then in `errors`.
    fn update(
        &mut self,
        pose: &Bound<'_, PyAny>,
        wheel_angles: &Bound<'_, PyAny>,
        wheel_speeds: &Bound<'_, PyAny>,
    ) -> PyResult<(f64, f64)> {
        let [x, y, theta] = finite_array(pose, "pose", ["x", "y", "theta"])?;
        let t = self.ticks as f64 * self.inner.control_dt();
        let m = Measurement {
            t,
            pose: Pose2::new(x, y, theta),
            wheel_angles: wheels_arg(wheel_angles, "wheel_angles", ["phi_r", "phi_l"])?,
            wheel_speeds: wheels_arg(wheel_speeds, "wheel_speeds", ["omega_r", "omega_l"])?,
        };
        // A tick whose commands or errors are not finite (finite but huge inputs, such as
        // wheel angles of 1e308) is refused, and the controller stays as it was.
        let before = self.inner;
        let out = self.inner.update(t, &m, self.goal);
        let e = out.errors;
        if ![out.command.right, out.command.left, e.e_s, e.e_theta, e.dl].iter().all(|v| v.is_finite()) {
            self.inner = before;
            return Err(PyFloatingPointError::new_err(format!(
                "the wheel commands are not finite ({}, {}): the measurement is too large for the controller",
                out.command.right, out.command.left
            )));
        }
        self.last = out;
        self.ticks += 1;
        Ok((self.last.command.right, self.last.command.left))
    }

    /// Errors of the last update: (e_s in m, e_theta in rad, dl in m), eqs. (18), (21), (16).
    #[getter]
    fn errors(&self) -> (f64, f64, f64) {
        let e = self.last.errors;
        (e.e_s, e.e_theta, e.dl)
    }

    /// Clears the integrators and memories, as at t = 0.
    fn reset(&mut self) {
        self.inner.reset();
        self.ticks = 0;
        self.last = ControlOutput::default();
    }

    /// Control period, s: call update() this often.
    #[getter]
    fn control_dt(&self) -> f64 {
        self.inner.control_dt()
    }

    /// The goal (x_m, y_m, theta_rad) of C.
    #[getter]
    fn goal(&self) -> (f64, f64, f64) {
        let g = self.goal;
        (g.x, g.y, g.theta)
    }

    fn __repr__(&self) -> String {
        let g = self.goal;
        format!("PaperController(goal=({}, {}, {}))", g.x, g.y, g.theta)
    }
}
