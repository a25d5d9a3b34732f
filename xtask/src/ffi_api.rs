//! `crates/wmr-ffi/src/api_f32.rs` and `api_f64.rs`: the C API's exported entry points.
//! The robot, drive, wheel stage, plant, sensor and reference functions are written here
//! once; each law of the registry gets its `_params_*_default` and its controller's
//! `_init`, `_update`, `_update_reference`, `_update_on`, `_reset` and `_for_plant`, which
//! call `imp`'s generic functions with the law's marker type (`imp::c_laws!`). The f64
//! file is the f32 file with every `f32` replaced by `f64`.

use crate::registry::{self, LawRow};
use crate::{Generated, header};

/// A law as its C entry points name and describe it.
struct CLaw {
    /// The law in C names: `wmr_<c_name>_params_*`, `wmr_<c_name>_controller_*`.
    c_name: &'static str,
    /// Its marker type in `imp` (the registry's variant: `Paper`).
    marker: &'static str,
    /// What the law is, as the start of its `_init` doc.
    about: &'static str,
    /// What `_params_*_default` fills in (after "Fills `out` with ").
    defaults: String,
    /// What `_reset` clears.
    reset: &'static str,
}

impl CLaw {
    fn of(row: &LawRow) -> CLaw {
        CLaw {
            c_name: row.kind,
            marker: row.variant,
            about: row.about,
            defaults: format!("the default keys of `[controller] kind = \"{}\"` (docs/scenario.md)", row.kind),
            reset: "Clears the law's memories and the wheel servos, as at t = 0.",
        }
    }
}

/// The entry points before the laws' parameter defaults: robot, drive, wheel stage.
const API_ROBOT_DRIVE: &str = r#"/// Fills `out` with the paper's robot: m = 5 kg, r = 0.1 m, R = 0.2 m, d = 0.25 m,
/// I_m = 0.002 kg m^2, I_p = 0.005 kg m^2, k_t = 0.1, no friction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_robot_params_f32_paper(out: *mut wmr_robot_params<f32>) -> wmr_status {
    imp::robot_params_paper(out)
}

/// Validates `params` into a robot. On error `err` (may be NULL) names the field.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_robot_f32_init(
    out: *mut wmr_robot_f32,
    params: *const wmr_robot_params<f32>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::robot_init(out, params, err)
}

/// Fills `out` with the defaults of drive `kind` (both kinds' fields are filled).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_drive_params_f32_default(kind: u32, out: *mut wmr_drive_params<f32>) -> wmr_status {
    imp::drive_params_default(kind, out)
}

/// Validates `params` for `robot` (its gear ratio) into a drive.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_drive_f32_init(
    out: *mut wmr_drive_f32,
    params: *const wmr_drive_params<f32>,
    robot: *const wmr_robot_f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::drive_init(out, params, robot, err)
}

/// Fills `out` with the wheel stage defaults for `drive` on the controller's robot
/// `model` (its gear ratio): a DC motor's servo gains and speed limit follow its keys.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_wheel_stage_params_f32_default(
    drive: *const wmr_drive_params<f32>,
    model: *const wmr_robot_f32,
    out: *mut wmr_wheel_stage_params<f32>,
) -> wmr_status {
    imp::wheel_stage_params_default(drive, model, out)
}

/// Fills `out` with the disturbance observer's defaults (the keys of
/// `[controller.observer] kind = "disturbance"`: bandwidth 50 rad/s).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_disturbance_observer_params_f32_default(
    out: *mut wmr_disturbance_observer_params<f32>,
) -> wmr_status {
    imp::disturbance_observer_params_default(out)
}
"#;

/// The entry points between the laws' parameter defaults and their controllers: plant
/// and sensor.
const API_PLANT_SENSOR: &str = r#"/// A plant at rest at `start` (m, m, rad; finite, |x| and |y| <= 1000 m), encoders at
/// zero, no command held, on the ground `world` (NULL: flat).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f32_init(
    out: *mut wmr_plant_f32,
    robot: *const wmr_robot_f32,
    drive: *const wmr_drive_f32,
    world: *const wmr_world_params<f32>,
    start: wmr_pose<f32>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::plant_init(out, robot, drive, world, start, err)
}

/// Fills `out` with the slip plant's defaults with `traction = WMR_TRACTION_SLIP` (mu =
/// 0.8, caster 0.35 m ahead of C, G 0.1 m high, slip_speed 0.03 m/s, stiction_length
/// 1 mm).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_traction_params_f32_default(out: *mut wmr_traction_params<f32>) -> wmr_status {
    imp::traction_params_default(out)
}

/// As `wmr_plant_f32_init`, with the traction model `traction` (NULL or
/// `WMR_TRACTION_ROLLING`: the paper's rolling wheels; `WMR_TRACTION_SLIP`: wheels that
/// slip when the forces exceed mu times the normal loads). The slip plant splits a step
/// its contacts are too stiff for into RK4 sub-steps, as the CLI does
/// (`wmr_plant_f32_step` says so).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f32_init_traction(
    out: *mut wmr_plant_f32,
    robot: *const wmr_robot_f32,
    drive: *const wmr_drive_f32,
    world: *const wmr_world_params<f32>,
    traction: *const wmr_traction_params<f32>,
    start: wmr_pose<f32>,
    err: *mut wmr_error,
) -> wmr_status {
    imp::plant_init_traction(out, robot, drive, world, traction, start, err)
}

/// Holds `command` (per wheel: N m for the torque drive, V for the DC motor) until the
/// next call: the zero-order hold of a digital controller. A non-finite command is
/// refused (`WMR_NOT_FINITE`) and the held one kept.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f32_apply(plant: *mut wmr_plant_f32, command: wmr_wheels<f32>) -> wmr_status {
    imp::plant_apply(plant, command)
}

/// One RK4 step of `dt` (s) from time `t` (s) under the held command; a slip plant
/// takes n equal sub-steps, n = 1 while dt * stiffness < 2.785, else
/// ceil(dt * stiffness / (0.9 * 2.785)), the CLI's (`wmr-cli check` shows n). `t` must be
/// finite and `dt` finite, > 0 and below the plant's RK4 limit, for a slip plant within
/// 1000 sub-steps (`WMR_NOT_FINITE`, `WMR_NOT_POSITIVE`, `WMR_OUT_OF_RANGE`). A state
/// that is not finite or leaves the 1 km box is refused (`WMR_DIVERGED_*`), the state
/// unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f32_step(plant: *mut wmr_plant_f32, t: f32, dt: f32) -> wmr_status {
    imp::plant_step(plant, t, dt)
}

/// The plant's true state.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f32_state(plant: *const wmr_plant_f32, out: *mut wmr_state<f32>) -> wmr_status {
    imp::plant_state(plant, out)
}

/// Each wheel's own speed, rad/s: under slip it differs from the body's (v +- R omega) / r.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_plant_f32_wheel_speeds(plant: *const wmr_plant_f32, out: *mut wmr_wheels<f32>) -> wmr_status {
    imp::plant_wheel_speeds(plant, out)
}

/// The paper's sensor: the true pose and wheel state at the instant of the tick.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f32_init_perfect(out: *mut wmr_sensor_f32) -> wmr_status {
    imp::sensor_init_perfect::<f32>(out)
}

/// Fills `out` with the pose sensor's defaults (the perfect sensor, seed 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_params_f32_default(out: *mut wmr_sensor_params<f32>) -> wmr_status {
    imp::sensor_params_default(out)
}

/// The pose sensor for control period `control_dt` (s); `run` selects the noise stream
/// (with `params.seed`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f32_init_pose(
    out: *mut wmr_sensor_f32,
    params: *const wmr_sensor_params<f32>,
    control_dt: f32,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::sensor_init_pose::<f32>(out, params, control_dt, run, err)
}

/// Fills `out` with the odometry defaults with `pose = WMR_POSE_ODOMETRY`: no absolute
/// fixes (`fix_rate_hz` 0), `odometry_noise` 0.01 m^(1/2).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_odometry_params_f32_default(out: *mut wmr_odometry_params<f32>) -> wmr_status {
    imp::odometry_params_default(out)
}

/// The odometry sensor for control period `control_dt` (s): the pose dead-reckoned from
/// the encoders (`params.encoder_counts`) with the controller's `model` (its r and R),
/// fused by the EKF with absolute fixes at `odometry.fix_rate_hz` (`params`' noise and
/// latency; `params.rate_hz` must stay infinite); `run` selects the fixes' noise stream
/// (with `params.seed`). Here latency * fix_rate_hz must be below
/// `WMR_SENSOR_SAMPLES_IN_FLIGHT` - 1.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f32_init_odometry(
    out: *mut wmr_sensor_f32,
    params: *const wmr_sensor_params<f32>,
    odometry: *const wmr_odometry_params<f32>,
    model: *const wmr_robot_f32,
    control_dt: f32,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::sensor_init_odometry::<f32>(out, params, odometry, model, control_dt, run, err)
}

/// The odometry sensor's dead-reckoned pose and EKF covariance at its last tick;
/// `WMR_OUT_OF_RANGE` for another sensor or before the first measurement.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f32_odometry(sensor: *const wmr_sensor_f32, out: *mut wmr_odometry_estimate<f32>) -> wmr_status {
    imp::sensor_odometry::<f32>(sensor, out)
}

/// What the sensor reports at time `t` (s, finite) of the plant's state. A measurement
/// that comes out non-finite is refused (`WMR_NOT_FINITE`), the sensor unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f32_measure(
    sensor: *mut wmr_sensor_f32,
    t: f32,
    plant: *const wmr_plant_f32,
    out: *mut wmr_measurement<f32>,
) -> wmr_status {
    imp::sensor_measure(sensor, t, plant, out)
}

/// Forgets the sensor's memory, as at t = 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_sensor_f32_reset(sensor: *mut wmr_sensor_f32) -> wmr_status {
    imp::sensor_reset::<f32>(sensor)
}

/// A circle at constant speed (the `[reference] kind = "circle"` keys): centre (m, m;
/// theta unused), radius (m, > 0), speed (m/s, nonzero: > 0 counter-clockwise) and phase
/// (rad, the angle of C_ref - centre at t = 0). Checked like the scenario's keys, the
/// whole circle inside the 1 km box; `err` (may be NULL) names the field.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_reference_f32_init_circle(
    out: *mut wmr_reference_f32,
    center: wmr_pose<f32>,
    radius: f32,
    speed: f32,
    phase: f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::reference_init_circle::<f32>(out, center, radius, speed, phase, err)
}

/// A figure-eight (`kind = "figure_eight"`): centre (m, m; theta unused), width and
/// height (m, > 0) and period (s, > 0), the whole figure inside the 1 km box.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_reference_f32_init_figure_eight(
    out: *mut wmr_reference_f32,
    center: wmr_pose<f32>,
    width: f32,
    height: f32,
    period: f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::reference_init_figure_eight::<f32>(out, center, width, height, period, err)
}

/// A straight line (`kind = "line"`) from `start` (m, m, rad) along its heading at
/// `speed` (m/s, nonzero; < 0 backwards).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_reference_f32_init_line(
    out: *mut wmr_reference_f32,
    start: wmr_pose<f32>,
    speed: f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::reference_init_line::<f32>(out, start, speed, err)
}

/// A C2 spline through `n` waypoints (`kind = "waypoints"`; `points` is `n` pairs
/// (x, y) in m, 2 to `WMR_REFERENCE_MAX_POINTS`, the reference's own storage; a longer
/// path: `_init_waypoints_in`) with a speed profile from rest to rest, at most `speed`
/// (m/s, > 0) and |acceleration| at most `accel_max` (m/s^2, > 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_reference_f32_init_waypoints(
    out: *mut wmr_reference_f32,
    points: *const [f32; 2],
    n: usize,
    speed: f32,
    accel_max: f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::reference_init_waypoints::<f32>(out, points, n, speed, accel_max, err)
}

/// The numbers (each an `f32`) of storage `_init_waypoints_in` needs for `n` points:
/// 37 n - 28 (0 when that overflows a size_t).
#[unsafe(no_mangle)]
pub extern "C" fn wmr_reference_f32_waypoints_words(n: usize) -> usize {
    imp::waypoints_words(n)
}

/// As `_init_waypoints`, for a path of any length (a recorded one: thousands of points),
/// built in `storage`, `words` numbers the caller owns (at least
/// `wmr_reference_f32_waypoints_words(n)`, not overlapping `points`). The reference reads
/// them while it is in use: keep them alive and unchanged as long as the reference.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_reference_f32_init_waypoints_in(
    out: *mut wmr_reference_f32,
    points: *const [f32; 2],
    n: usize,
    speed: f32,
    accel_max: f32,
    storage: *mut f32,
    words: usize,
    err: *mut wmr_error,
) -> wmr_status {
    imp::reference_init_waypoints_in::<f32>(out, points, n, speed, accel_max, storage, words, err)
}

/// The state of the reference point at time `t` (s): pose (m, m, rad), twist (m/s,
/// rad/s) and acceleration (m/s^2, rad/s^2), what `_update_reference` takes: the same
/// bits as the scenario's x_ref ... omega_ref columns. A state that is not finite, or
/// whose pose is outside the 1 km box where C can be (a line at 1e300 m/s), is refused
/// (`WMR_NOT_FINITE`, `WMR_OUT_OF_RANGE`) and `out` left untouched.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_reference_f32_state_at(
    reference: *const wmr_reference_f32,
    t: f32,
    out: *mut wmr_reference_state<f32>,
) -> wmr_status {
    imp::reference_state_at::<f32>(reference, t, out)
}
"#;

/// `text` as `///` doc lines of at most 88 columns.
fn doc(text: &str) -> String {
    let mut out = String::new();
    let mut line = String::from("///");
    for word in text.split_whitespace() {
        if line.len() + 1 + word.len() > 88 && line != "///" {
            out.push_str(&line);
            out.push('\n');
            line = String::from("///");
        }
        line.push(' ');
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
    out
}

/// One exported function: its doc, name, arguments (`name: type`) and body.
fn entry_point(text: &str, name: &str, args: &[String], body: &str) -> String {
    let mut out = doc(text);
    out.push_str(&format!("#[unsafe(no_mangle)]\npub unsafe extern \"C\" fn {name}(\n"));
    for a in args {
        out.push_str(&format!("    {a},\n"));
    }
    out.push_str(&format!(") -> wmr_status {{\n    {body}\n}}\n"));
    out
}

/// `api_f32.rs` as it must be.
pub fn api_f32() -> String {
    let laws: Vec<CLaw> = registry::laws().iter().map(CLaw::of).collect();
    let first = laws.first().expect("a law").c_name;
    let markers: Vec<&str> = laws.iter().map(|l| l.marker).collect();
    let mut out = header("the C entry points (f32; api_f64.rs: the same in f64).");
    out.push_str(&format!(
        "//! The f32 entry points (`api_f64.rs`: the same in f64).\n\n\
         use crate::imp::{{self, {}}};\nuse crate::*;\n\n",
        markers.join(", ")
    ));
    out.push_str(API_ROBOT_DRIVE);
    for l in &laws {
        let (c, m) = (l.c_name, l.marker);
        out.push('\n');
        out.push_str(&entry_point(
            &format!("Fills `out` with {}.", l.defaults),
            &format!("wmr_{c}_params_f32_default"),
            &[format!("out: *mut wmr_{c}_params<f32>")],
            &format!("imp::law_params_default::<f32, {m}>(out)"),
        ));
    }
    out.push('\n');
    out.push_str(API_PLANT_SENSOR);
    for (i, l) in laws.iter().enumerate() {
        let (c, m) = (l.c_name, l.marker);
        let see = |what: &str| format!("(see `wmr_{first}_controller_f32_{what}`)");
        let update_on = if i == 0 {
            "One control tick at time `t` (s) following the reference object `reference` (a \
             `wmr_reference_*`): its state at `t` and, for the path-following law, its path, as a \
             scenario run steps the law. Refusals as for `_update_reference`; a path-following law \
             given a reference without a path (a goal) is refused naming `reference`."
                .to_owned()
        } else {
            format!("One control tick following a reference object {}.", see("update_on"))
        };
        let (init, update, update_reference) = if i == 0 {
            (
                format!(
                    "{} with its wheel stage, for the controller's robot model (r and R), the drive it commands \
                     and the control period `control_dt` (s).",
                    l.about
                ),
                "One control tick at time `t` (s): drive commands and errors from the measurement and the goal \
                 pose (m, m, rad), the reference at rest there (as `_update_reference` with zero twist and \
                 acceleration). Non-finite inputs, a measured pose or goal outside the 1 km box, and a tick \
                 whose output comes out non-finite (gains or inputs that overflow) are refused \
                 (`WMR_NOT_FINITE`, `WMR_OUT_OF_RANGE`) and leave the controller and `out` unchanged. A \
                 law that follows a path (`pure_pursuit`) is refused here (`WMR_OUT_OF_RANGE`): it steers \
                 by a reference's path, given through `_update_on`."
                    .to_owned(),
                "One control tick at time `t` (s) following `reference`: the pose (m, m, rad), twist (m/s, \
                 rad/s) and acceleration (m/s^2, rad/s^2) of the reference point at `t`. Non-finite inputs are \
                 refused (`WMR_NOT_FINITE`; `err`, may be NULL, names the field, as `reference.twist.v`, or the \
                 output, as `out.command.right`) and leave the controller unchanged. A law that follows a path \
                 is refused (`WMR_OUT_OF_RANGE` naming `reference`): use `_update_on`."
                    .to_owned(),
            )
        } else {
            (
                format!("{} with its wheel stage {}.", l.about, see("init")),
                format!("One control tick {}.", see("update")),
                format!("One control tick following a reference {}.", see("update_reference")),
            )
        };
        let ctrl = format!("ctrl: *mut wmr_{c}_controller_f32");
        out.push('\n');
        out.push_str(&entry_point(
            &init,
            &format!("wmr_{c}_controller_f32_init"),
            &[
                format!("out: *mut wmr_{c}_controller_f32"),
                format!("params: *const wmr_{c}_params<f32>"),
                "wheels: *const wmr_wheel_stage_params<f32>".into(),
                "model: *const wmr_robot_f32".into(),
                "drive: *const wmr_drive_f32".into(),
                "control_dt: f32".into(),
                "err: *mut wmr_error".into(),
            ],
            &format!("imp::controller_init::<f32, {m}>(out, params, wheels, model, drive, control_dt, err)"),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            &if i == 0 {
                "As `_init`, with the disturbance observer `observer` on the wheel stage \
                 (`[controller.observer] kind = \"disturbance\"`): each tick it estimates the \
                 disturbance torque at each wheel from the commanded torques and the measured wheel \
                 speeds and subtracts it from the command; `_disturbance` reads the estimate. `err` \
                 names `observer.bandwidth` for a bad bandwidth."
                    .to_owned()
            } else {
                format!("As `_init`, with a disturbance observer on the wheel stage {}.", see("init_observer"))
            },
            &format!("wmr_{c}_controller_f32_init_observer"),
            &[
                format!("out: *mut wmr_{c}_controller_f32"),
                format!("params: *const wmr_{c}_params<f32>"),
                "wheels: *const wmr_wheel_stage_params<f32>".into(),
                "observer: *const wmr_disturbance_observer_params<f32>".into(),
                "model: *const wmr_robot_f32".into(),
                "drive: *const wmr_drive_f32".into(),
                "control_dt: f32".into(),
                "err: *mut wmr_error".into(),
            ],
            &format!(
                "imp::controller_init_observer::<f32, {m}>(out, params, wheels, observer, model, drive, control_dt, err)"
            ),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            &if i == 0 {
                "The disturbance observer's estimate of the disturbance torque at each wheel at the \
                 last tick, N m (0 before the second tick); `WMR_OUT_OF_RANGE` for a controller \
                 initialised without an observer."
                    .to_owned()
            } else {
                format!("The disturbance observer's estimate, N m per wheel {}.", see("disturbance"))
            },
            &format!("wmr_{c}_controller_f32_disturbance"),
            &[format!("ctrl: *const wmr_{c}_controller_f32"), "out: *mut wmr_wheels<f32>".into()],
            &format!("imp::controller_disturbance::<f32, {m}>(ctrl, out)"),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            &update,
            &format!("wmr_{c}_controller_f32_update"),
            &[
                ctrl.clone(),
                "t: f32".into(),
                "measurement: *const wmr_measurement<f32>".into(),
                "goal: wmr_pose<f32>".into(),
                "out: *mut wmr_control_output<f32>".into(),
            ],
            &format!("imp::controller_update::<f32, {m}>(ctrl, t, measurement, goal, out)"),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            &update_reference,
            &format!("wmr_{c}_controller_f32_update_reference"),
            &[
                ctrl.clone(),
                "t: f32".into(),
                "measurement: *const wmr_measurement<f32>".into(),
                "reference: *const wmr_reference_state<f32>".into(),
                "out: *mut wmr_control_output<f32>".into(),
                "err: *mut wmr_error".into(),
            ],
            &format!("imp::controller_update_reference::<f32, {m}>(ctrl, t, measurement, reference, out, err)"),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            &update_on,
            &format!("wmr_{c}_controller_f32_update_on"),
            &[
                ctrl.clone(),
                "t: f32".into(),
                "measurement: *const wmr_measurement<f32>".into(),
                "reference: *const wmr_reference_f32".into(),
                "out: *mut wmr_control_output<f32>".into(),
                "err: *mut wmr_error".into(),
            ],
            &format!("imp::controller_update_on::<f32, {m}>(ctrl, t, measurement, reference, out, err)"),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            l.reset,
            &format!("wmr_{c}_controller_f32_reset"),
            std::slice::from_ref(&ctrl),
            &format!("imp::controller_reset::<f32, {m}>(ctrl)"),
        ));
        out.push('\n');
        out.push_str(&entry_point(
            &if i == 0 {
                "Fits the controller's wheel speed guard to the wheels of `plant`: on a plant whose \
                 wheels slip (`wmr_plant_f32_init_traction`) the guard acts on a wheel's own inertia \
                 I_m, as a scenario run sets it. Call it once after both inits; a controller that \
                 never sees it assumes rolling wheels."
                    .to_owned()
            } else {
                see("for_plant")
            },
            &format!("wmr_{c}_controller_f32_for_plant"),
            &[ctrl, "plant: *const wmr_plant_f32".into()],
            &format!("imp::controller_for_plant::<f32, {m}>(ctrl, plant)"),
        ));
    }
    out.push('\n');
    out.push_str(API_OBSTACLES_MPPI);
    out
}

/// MPPI's obstacles and run (its `obstacles` critic, its noise per run): written once.
const API_OBSTACLES_MPPI: &str = r#"/// An empty set of obstacles with the robot's footprint radius `footprint_radius` (m,
/// about C: a scenario's `[robot] footprint_radius`, nav2's `robot_radius`); `err` names
/// `footprint_radius` when it is negative or not finite.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_obstacles_f32_init(
    out: *mut wmr_obstacles_f32,
    footprint_radius: f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::obstacles_init::<f32>(out, footprint_radius, err)
}

/// Adds a circle (`[[world.obstacle]] kind = "circle"`): centre (`x`, `y`), m, world
/// frame, and `radius`, m (> 0). Circles come before polygons whatever the order of the
/// calls, as in a scenario (the numbering of its `collided ... with obstacle i`). A bad
/// value is refused naming `obstacle.center` or `obstacle.radius` (the value: the
/// obstacle's index), a 17th obstacle naming `obstacle`; `obstacles` is then unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_obstacles_f32_add_circle(
    obstacles: *mut wmr_obstacles_f32,
    x: f32,
    y: f32,
    radius: f32,
    err: *mut wmr_error,
) -> wmr_status {
    imp::obstacles_add_circle::<f32>(obstacles, x, y, radius, err)
}

/// Adds a polygon (`kind = "polygon"`): `n` vertices (x, y), m, world frame, in order,
/// at least 3 (32 in all, over every polygon). Refused naming `obstacle.points`, and
/// `obstacles` unchanged, for too few or too many vertices or one not finite.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_obstacles_f32_add_polygon(
    obstacles: *mut wmr_obstacles_f32,
    points: *const [f32; 2],
    n: usize,
    err: *mut wmr_error,
) -> wmr_status {
    imp::obstacles_add_polygon::<f32>(obstacles, points, n, err)
}

/// As `wmr_mppi_controller_f32_init`, knowing the obstacles on the controller's map
/// (`obstacles`, NULL: none; the `obstacles` critic scores the rollouts against them) and
/// drawing the noise of run `run` (0: the `seed` key's; k: the seed a scenario's run k
/// draws under, `wmr_core::LawContext::run`): the controller of a scenario's run `run`
/// with these `[[world.obstacle]]`, bit for bit.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn wmr_mppi_controller_f32_init_in(
    out: *mut wmr_mppi_controller_f32,
    params: *const wmr_mppi_params<f32>,
    wheels: *const wmr_wheel_stage_params<f32>,
    model: *const wmr_robot_f32,
    drive: *const wmr_drive_f32,
    control_dt: f32,
    obstacles: *const wmr_obstacles_f32,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    imp::controller_init_in::<f32, Mppi>(out, params, wheels, model, drive, control_dt, obstacles, run, err)
}
"#;

/// `api_f64.rs` as it must be: `api_f32.rs` with every `f32` replaced by `f64`.
pub fn api_f64() -> String {
    api_f32().replace("f32", "f64")
}

/// Both files.
pub fn generate() -> [Generated; 2] {
    [
        Generated { path: "crates/wmr-ffi/src/api_f32.rs".into(), text: api_f32() },
        Generated { path: "crates/wmr-ffi/src/api_f64.rs".into(), text: api_f64() },
    ]
}
