//! `wmr_py.PaperController`: the core's [`PaperController`] for loops closed in Python.

use pyo3::prelude::*;
use wmr_core::{
    ControlOutput, Controller, DriveParams, Measurement, PaperController, PaperMode, PaperParams, Pose2, Robot,
};

use crate::convert::finite_array;
use crate::error::{from_param, parameter_error};
use crate::robot::{PyRobot, wheels_arg};

/// The paper's point-stabilization controller (SPEC section 4) with its two wheel servos.
///
/// PaperController(goal, robot=None, *, mode="pose", kp_theta=2.0, ki_theta=0.1,
///                 kp_s=1.0, ki_s=0.25, servo_kp=14.0, servo_kd=1.4, servo_ki=0.0,
///                 goal_radius=1e-3, hold_radius=5e-3, control_dt=1e-3,
///                 motor_torque_max=0.2)
///
/// goal: (x_m, y_m, theta_rad) of point C. robot: a Robot (default: the paper's).
/// Gains as the scenario's `[controller]` keys: kp_theta (rad/rad), ki_theta (1/s),
/// kp_s (m/m), ki_s (1/s), servo_kp (N m/rad), servo_kd (N m s/rad), servo_ki
/// (N m/(rad s)); goal_radius and hold_radius in m (0 turns the hold off); control_dt in s.
/// motor_torque_max (N m at the motor, inf allowed) is the torque drive's limit, used only
/// as the servo's anti-windup bound: update() returns the unclamped demand.
///
/// Call update() once every control_dt seconds and hold its output in between.
#[pyclass(name = "PaperController", module = "wmr_py")]
pub struct PyPaperController {
    inner: PaperController<f64>,
    last: ControlOutput<f64>,
}

#[pymethods]
impl PyPaperController {
    #[new]
    #[pyo3(signature = (goal, robot=None, *, mode=None, kp_theta=None, ki_theta=None, kp_s=None,
        ki_s=None, servo_kp=None, servo_kd=None, servo_ki=None, goal_radius=None, hold_radius=None,
        control_dt=None, motor_torque_max=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        goal: &Bound<'_, PyAny>,
        robot: Option<PyRef<'_, PyRobot>>,
        mode: Option<&str>,
        kp_theta: Option<f64>,
        ki_theta: Option<f64>,
        kp_s: Option<f64>,
        ki_s: Option<f64>,
        servo_kp: Option<f64>,
        servo_kd: Option<f64>,
        servo_ki: Option<f64>,
        goal_radius: Option<f64>,
        hold_radius: Option<f64>,
        control_dt: Option<f64>,
        motor_torque_max: Option<f64>,
    ) -> PyResult<Self> {
        let [x, y, theta] = finite_array(goal, "goal", ["x", "y", "theta"])?;
        let robot: Robot<f64> = robot.map(|r| r.inner).unwrap_or_else(Robot::paper);
        let mut drive = wmr_core::TorqueDriveParams::<f64>::default();
        if let Some(m) = motor_torque_max {
            drive.motor_torque_max = m;
        }
        let drive = DriveParams::Torque(drive).validate(&robot).map_err(from_param)?;
        let d = PaperParams::<f64>::paper();
        let mode = match mode {
            None | Some("pose") => PaperMode::Pose,
            Some("position") => PaperMode::Position,
            Some(other) => {
                return Err(parameter_error(
                    "controller.mode",
                    format_args!("expected \"pose\" or \"position\", got {other:?}"),
                ));
            }
        };
        let params = PaperParams {
            mode,
            kp_theta: kp_theta.unwrap_or(d.kp_theta),
            ki_theta: ki_theta.unwrap_or(d.ki_theta),
            kp_s: kp_s.unwrap_or(d.kp_s),
            ki_s: ki_s.unwrap_or(d.ki_s),
            servo: wmr_core::ServoGains {
                kp: servo_kp.unwrap_or(d.servo.kp),
                kd: servo_kd.unwrap_or(d.servo.kd),
                ki: servo_ki.unwrap_or(d.servo.ki),
            },
            goal_radius: goal_radius.unwrap_or(d.goal_radius),
            hold_radius: hold_radius.unwrap_or(d.hold_radius),
            control_dt: control_dt.unwrap_or(d.control_dt),
        };
        let inner = PaperController::new(params, &robot, &drive, Pose2::new(x, y, theta)).map_err(from_param)?;
        Ok(Self { inner, last: ControlOutput::default() })
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
        let m = Measurement {
            pose: Pose2::new(x, y, theta),
            wheel_angles: wheels_arg(wheel_angles, "wheel_angles", ["phi_r", "phi_l"])?,
            wheel_speeds: wheels_arg(wheel_speeds, "wheel_speeds", ["omega_r", "omega_l"])?,
        };
        self.last = self.inner.update(&m);
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
        let g = self.inner.goal();
        (g.x, g.y, g.theta)
    }

    fn __repr__(&self) -> String {
        let g = self.inner.goal();
        format!("PaperController(goal=({}, {}, {}))", g.x, g.y, g.theta)
    }
}
