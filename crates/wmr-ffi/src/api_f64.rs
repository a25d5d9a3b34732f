//! The f64 entry points: `api_f32.rs` with every `f32` replaced by `f64`. Generated;
//! edit `api_f32.rs` and run `WMR_BLESS=1 cargo test -p wmr-ffi --test header`.

use crate::imp::{self, Lyapunov, Paper, PaperBidirectional, Polar};
use crate::*;

/// Fills `out` with the paper's robot: m = 5 kg, r = 0.1 m, R = 0.2 m, d = 0.25 m,
/// I_m = 0.002 kg m^2, I_p = 0.005 kg m^2, k_t = 0.1, no friction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_robot_params_f64_paper(out: *mut wmr_robot_params<f64>) -> wmr_status {
    imp::robot_params_paper(out)
}

/// Validates `params` into a robot. On error `err` (may be NULL) names the field.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_robot_f64_init(
    out: *mut wmr_robot_f64,
    params: *const wmr_robot_params<f64>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::robot_init(out, params, err)
}

/// Fills `out` with the defaults of drive `kind` (both kinds' fields are filled).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_drive_params_f64_default(kind: u32, out: *mut wmr_drive_params<f64>) -> wmr_status {
    imp::drive_params_default(kind, out)
}

/// Validates `params` for `robot` (its gear ratio) into a drive.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_drive_f64_init(
    out: *mut wmr_drive_f64,
    params: *const wmr_drive_params<f64>,
    robot: *const wmr_robot_f64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::drive_init(out, params, robot, err)
}

/// Fills `out` with the wheel stage defaults for the drive kind of `drive`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_wheel_stage_params_f64_default(
    drive: *const wmr_drive_params<f64>,
    out: *mut wmr_wheel_stage_params<f64>,
) -> wmr_status {
    imp::wheel_stage_params_default(drive, out)
}

/// Fills `out` with the paper's gains (section 4) and the default radii and hold.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_params_f64_default(out: *mut wmr_paper_params<f64>) -> wmr_status {
    imp::law_params_default::<f64, Paper>(out)
}

/// Fills `out` with the bidirectional paper law's defaults (Kp_theta 0, Ki_theta 1,
/// Kp_s 0, Ki_s 0.25, goal_radius 1 mm, hold_radius 5 mm, `WMR_HOLD_FREEZE`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_bidirectional_params_f64_default(
    out: *mut wmr_paper_bidirectional_params<f64>,
) -> wmr_status {
    imp::law_params_default::<f64, PaperBidirectional>(out)
}

/// Fills `out` with the polar law's defaults (k_rho 0.5, k_alpha 3, k_beta -1.2).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_polar_params_f64_default(out: *mut wmr_polar_params<f64>) -> wmr_status {
    imp::law_params_default::<f64, Polar>(out)
}

/// Fills `out` with the Lyapunov law's defaults (gamma 0.5, k 3, h 9).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_lyapunov_params_f64_default(out: *mut wmr_lyapunov_params<f64>) -> wmr_status {
    imp::law_params_default::<f64, Lyapunov>(out)
}

/// A plant at rest at `start` (m, m, rad), encoders at zero, no command held, on the
/// ground `world` (NULL: flat).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f64_init(
    out: *mut wmr_plant_f64,
    robot: *const wmr_robot_f64,
    drive: *const wmr_drive_f64,
    world: *const wmr_world_params<f64>,
    start: wmr_pose<f64>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::plant_init(out, robot, drive, world, start, err)
}

/// Holds `command` (per wheel: N m for the torque drive, V for the DC motor) until the
/// next call: the zero-order hold of a digital controller.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f64_apply(plant: *mut wmr_plant_f64, command: wmr_wheels<f64>) -> wmr_status {
    imp::plant_apply(plant, command)
}

/// One RK4 step of `dt` (s) from time `t` (s) under the held command. A state that is
/// not finite or leaves the 1 km box is refused (`WMR_DIVERGED_*`), the state unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f64_step(plant: *mut wmr_plant_f64, t: f64, dt: f64) -> wmr_status {
    imp::plant_step(plant, t, dt)
}

/// The plant's true state.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f64_state(plant: *const wmr_plant_f64, out: *mut wmr_state<f64>) -> wmr_status {
    imp::plant_state(plant, out)
}

/// The paper's sensor: the true pose and wheel state at the instant of the tick.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f64_init_perfect(out: *mut wmr_sensor_f64) -> wmr_status {
    imp::sensor_init_perfect::<f64>(out)
}

/// Fills `out` with the pose sensor's defaults (the perfect sensor, seed 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_params_f64_default(out: *mut wmr_sensor_params<f64>) -> wmr_status {
    imp::sensor_params_default(out)
}

/// The pose sensor for control period `control_dt` (s); `run` selects the noise stream
/// (with `params.seed`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f64_init_pose(
    out: *mut wmr_sensor_f64,
    params: *const wmr_sensor_params<f64>,
    control_dt: f64,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::sensor_init_pose::<f64>(out, params, control_dt, run, err)
}

/// What the sensor reports at time `t` (s) of the plant's state.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f64_measure(
    sensor: *mut wmr_sensor_f64,
    t: f64,
    plant: *const wmr_plant_f64,
    out: *mut wmr_measurement<f64>,
) -> wmr_status {
    imp::sensor_measure(sensor, t, plant, out)
}

/// Forgets the sensor's memory, as at t = 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f64_reset(sensor: *mut wmr_sensor_f64) -> wmr_status {
    imp::sensor_reset::<f64>(sensor)
}

/// The paper's law with its wheel stage, for the controller's robot model (r and R),
/// the drive it commands and the control period `control_dt` (s).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_controller_f64_init(
    out: *mut wmr_paper_controller_f64,
    params: *const wmr_paper_params<f64>,
    wheels: *const wmr_wheel_stage_params<f64>,
    model: *const wmr_robot_f64,
    drive: *const wmr_drive_f64,
    control_dt: f64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_init::<f64, Paper>(out, params, wheels, model, drive, control_dt, err)
}

/// One control tick at time `t` (s): drive commands and errors from the measurement and
/// the goal pose (m, m, rad), the reference at rest there (as `_update_reference` with
/// zero twist and acceleration). Non-finite inputs are refused (`WMR_NOT_FINITE`) and
/// leave the controller unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_controller_f64_update(
    ctrl: *mut wmr_paper_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    goal: wmr_pose<f64>,
    out: *mut wmr_control_output<f64>,
) -> wmr_status {
    imp::controller_update::<f64, Paper>(ctrl, t, measurement, goal, out)
}

/// One control tick at time `t` (s) following `reference`: the pose (m, m, rad), twist
/// (m/s, rad/s) and acceleration (m/s^2, rad/s^2) of the reference point at `t`.
/// Non-finite inputs are refused (`WMR_NOT_FINITE`; `err`, may be NULL, names the field,
/// as `reference.twist.v`) and leave the controller unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_controller_f64_update_reference(
    ctrl: *mut wmr_paper_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    reference: *const wmr_reference_state<f64>,
    out: *mut wmr_control_output<f64>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_update_reference::<f64, Paper>(ctrl, t, measurement, reference, out, err)
}

/// Clears the integrators and memories, as at t = 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_controller_f64_reset(ctrl: *mut wmr_paper_controller_f64) -> wmr_status {
    imp::controller_reset::<f64, Paper>(ctrl)
}

/// The paper's law repaired (`paper_bidirectional`: a position error that never feeds
/// back positively, gains for which the heading settles before the position) with its
/// wheel stage (see `wmr_paper_controller_f64_init`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_bidirectional_controller_f64_init(
    out: *mut wmr_paper_bidirectional_controller_f64,
    params: *const wmr_paper_bidirectional_params<f64>,
    wheels: *const wmr_wheel_stage_params<f64>,
    model: *const wmr_robot_f64,
    drive: *const wmr_drive_f64,
    control_dt: f64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_init::<f64, PaperBidirectional>(out, params, wheels, model, drive, control_dt, err)
}

/// One control tick (see `wmr_paper_controller_f64_update`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_bidirectional_controller_f64_update(
    ctrl: *mut wmr_paper_bidirectional_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    goal: wmr_pose<f64>,
    out: *mut wmr_control_output<f64>,
) -> wmr_status {
    imp::controller_update::<f64, PaperBidirectional>(ctrl, t, measurement, goal, out)
}

/// One control tick following a reference (see `wmr_paper_controller_f64_update_reference`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_bidirectional_controller_f64_update_reference(
    ctrl: *mut wmr_paper_bidirectional_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    reference: *const wmr_reference_state<f64>,
    out: *mut wmr_control_output<f64>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_update_reference::<f64, PaperBidirectional>(ctrl, t, measurement, reference, out, err)
}

/// Clears the integrators and memories, as at t = 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_paper_bidirectional_controller_f64_reset(
    ctrl: *mut wmr_paper_bidirectional_controller_f64,
) -> wmr_status {
    imp::controller_reset::<f64, PaperBidirectional>(ctrl)
}

/// Astolfi's polar law with its wheel stage (see `wmr_paper_controller_f64_init`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_polar_controller_f64_init(
    out: *mut wmr_polar_controller_f64,
    params: *const wmr_polar_params<f64>,
    wheels: *const wmr_wheel_stage_params<f64>,
    model: *const wmr_robot_f64,
    drive: *const wmr_drive_f64,
    control_dt: f64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_init::<f64, Polar>(out, params, wheels, model, drive, control_dt, err)
}

/// One control tick (see `wmr_paper_controller_f64_update`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_polar_controller_f64_update(
    ctrl: *mut wmr_polar_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    goal: wmr_pose<f64>,
    out: *mut wmr_control_output<f64>,
) -> wmr_status {
    imp::controller_update::<f64, Polar>(ctrl, t, measurement, goal, out)
}

/// One control tick following a reference (see `wmr_paper_controller_f64_update_reference`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_polar_controller_f64_update_reference(
    ctrl: *mut wmr_polar_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    reference: *const wmr_reference_state<f64>,
    out: *mut wmr_control_output<f64>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_update_reference::<f64, Polar>(ctrl, t, measurement, reference, out, err)
}

/// Clears the direction choice, the servos and the references, as at t = 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_polar_controller_f64_reset(ctrl: *mut wmr_polar_controller_f64) -> wmr_status {
    imp::controller_reset::<f64, Polar>(ctrl)
}

/// Aicardi et al.'s Lyapunov law with its wheel stage (see `wmr_paper_controller_f64_init`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_lyapunov_controller_f64_init(
    out: *mut wmr_lyapunov_controller_f64,
    params: *const wmr_lyapunov_params<f64>,
    wheels: *const wmr_wheel_stage_params<f64>,
    model: *const wmr_robot_f64,
    drive: *const wmr_drive_f64,
    control_dt: f64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_init::<f64, Lyapunov>(out, params, wheels, model, drive, control_dt, err)
}

/// One control tick (see `wmr_paper_controller_f64_update`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_lyapunov_controller_f64_update(
    ctrl: *mut wmr_lyapunov_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    goal: wmr_pose<f64>,
    out: *mut wmr_control_output<f64>,
) -> wmr_status {
    imp::controller_update::<f64, Lyapunov>(ctrl, t, measurement, goal, out)
}

/// One control tick following a reference (see `wmr_paper_controller_f64_update_reference`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_lyapunov_controller_f64_update_reference(
    ctrl: *mut wmr_lyapunov_controller_f64,
    t: f64,
    measurement: *const wmr_measurement<f64>,
    reference: *const wmr_reference_state<f64>,
    out: *mut wmr_control_output<f64>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_update_reference::<f64, Lyapunov>(ctrl, t, measurement, reference, out, err)
}

/// Clears the direction choice, the servos and the references, as at t = 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_lyapunov_controller_f64_reset(ctrl: *mut wmr_lyapunov_controller_f64) -> wmr_status {
    imp::controller_reset::<f64, Lyapunov>(ctrl)
}
