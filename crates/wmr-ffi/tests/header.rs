//! The checked-in C header and the entry points (`src/api_f32.rs`, `src/api_f64.rs`, from
//! the law list `c_laws!` in src/imp.rs) are generated: these tests fail when any is
//! stale. `WMR_BLESS=1 cargo test -p wmr-ffi --test header` rewrites them.

use std::path::{Path, PathBuf};

use wmr_core::describe::{Described, ParamField};
use wmr_core::{
    BacksteppingParams, KanayamaParams, LyapunovParams, OdometryParams, PaperBidirectionalParams, PaperParams,
    PolarParams, PurePursuitParams, RobotParams, SensorParams, TractionParams, WheelStageParams, WorldParams,
};

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bless() -> bool {
    std::env::var_os("WMR_BLESS").is_some_and(|v| v == "1")
}

/// Compares `fresh` with the file at `path`, or rewrites the file under `WMR_BLESS=1`.
fn check_or_bless(path: &Path, fresh: &str, how: &str) {
    if bless() {
        std::fs::write(path, fresh).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        // Blessing rewrites instead of comparing: said, so a blessed run is not read as a check.
        eprintln!("WMR_BLESS=1: rewrote {} instead of comparing it", path.display());
        return;
    }
    let current = std::fs::read_to_string(path).unwrap_or_default();
    if current != fresh {
        let line = current.lines().zip(fresh.lines()).position(|(a, b)| a != b).map_or(0, |i| i + 1);
        panic!("{} is stale (first difference near line {line}): {how}", path.display());
    }
}

// ---------------------------------------------------------------------------------------
// api_f32.rs and api_f64.rs: written from the law list (`wmr_ffi::C_LAWS`, from `c_laws!`
// in src/imp.rs) and the entry points below that every law shares. In f32; the f64 file
// is the same text with every `f32` replaced by `f64`.

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
fn api_f32() -> String {
    let laws = wmr_ffi::C_LAWS;
    let first = laws.first().expect("a law").c_name;
    let markers: Vec<&str> = laws.iter().map(|l| l.marker).collect();
    let mut out = format!(
        "// @generated by crates/wmr-ffi/tests/header.rs from the law list `c_laws!` in src/imp.rs:\n\
         // do not edit. Regenerate with WMR_BLESS=1 cargo test -p wmr-ffi --test header\n\
         //! The f32 entry points (`api_f64.rs`: the same in f64).\n\n\
         use crate::imp::{{self, {}}};\nuse crate::*;\n\n",
        markers.join(", ")
    );
    out.push_str(API_ROBOT_DRIVE);
    for l in laws {
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
             scenario run steps the law. Refusals as for `_update_reference`."
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
                 (`WMR_NOT_FINITE`, `WMR_OUT_OF_RANGE`) and leave the controller and `out` unchanged."
                    .to_owned(),
                "One control tick at time `t` (s) following `reference`: the pose (m, m, rad), twist (m/s, \
                 rad/s) and acceleration (m/s^2, rad/s^2) of the reference point at `t`. Non-finite inputs are \
                 refused (`WMR_NOT_FINITE`; `err`, may be NULL, names the field, as `reference.twist.v`, or the \
                 output, as `out.command.right`) and leave the controller unchanged."
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
    out
}

/// `api_f64.rs` as it must be: `api_f32.rs` with every `f32` replaced by `f64`.
fn api_f64() -> String {
    api_f32().replace("f32", "f64")
}

#[test]
fn api_files_are_generated_from_the_law_list() {
    let dir = crate_dir().join("src");
    let how = "run WMR_BLESS=1 cargo test -p wmr-ffi --test header";
    let f32_src = api_f32();
    assert!(f32_src.starts_with("// @generated"));
    for law in wmr_ffi::C_LAWS {
        for f in ["init", "update", "update_reference", "update_on", "reset"] {
            assert!(f32_src.contains(&format!("fn wmr_{}_controller_f32_{f}(", law.c_name)), "{} {f}", law.c_name);
        }
    }
    check_or_bless(&dir.join("api_f32.rs"), &f32_src, how);
    check_or_bless(&dir.join("api_f64.rs"), &api_f64(), how);
}

/// The core parameter structs the C API takes as they are (`pub type` aliases in
/// `src/lib.rs`): C name, doc, fields.
/// The C structs that are the core's `#[repr(C)]` parameter structs: the robot, world,
/// sensor and wheel stage, and each law's keys (from the registry) unless a flag makes
/// them a mirror struct (`laws.rs`, `cargo xtask gen`).
fn shared_structs() -> Vec<(String, String, &'static [ParamField])> {
    let mut out = vec![
        (
            "wmr_robot_params".to_owned(),
            "Physical robot parameters, SI units (the `[robot]` keys of a scenario).".to_owned(),
            RobotParams::<f64>::FIELDS,
        ),
        (
            "wmr_world_params".to_owned(),
            "The ground (the `[world]` keys): a plane tilted by `slope_deg`, descending towards `slope_direction_deg`.".to_owned(),
            WorldParams::<f64>::FIELDS,
        ),
        (
            "wmr_sensor_params".to_owned(),
            "The pose sensor (the `[sensor]` keys); every default: the perfect sensor, bit for bit. Here latency * rate_hz must be below `WMR_SENSOR_SAMPLES_IN_FLIGHT` - 1.".to_owned(),
            SensorParams::<f64>::FIELDS,
        ),
        (
            "wmr_wheel_stage_params".to_owned(),
            "The wheel stage: two wheel position servos and the curvature-keeping speed limit.".to_owned(),
            WheelStageParams::<f64>::FIELDS,
        ),
        (
            "wmr_odometry_params".to_owned(),
            "The odometry sensor's pose source (the `[sensor]` keys `pose`, `fix_rate_hz`, `odometry_noise`).".to_owned(),
            OdometryParams::<f64>::FIELDS,
        ),
        (
            "wmr_traction_params".to_owned(),
            "The traction model (the `[robot]` keys `traction` to `stiction_length`): rolling or slip.".to_owned(),
            TractionParams::<f64>::FIELDS,
        ),
    ];
    for law in wmr_core::LawParams::<f64>::defaults() {
        if law.fields().iter().all(|f| f.ty != "bool") {
            out.push((
                format!("wmr_{}_params", law.kind()),
                format!("{} (`[controller] kind = \"{}\"`).", law.about().trim_end_matches('.'), law.kind()),
                law.fields(),
            ));
        }
    }
    out
}

/// The C type and the C constants of a core field type that is not `T`: the core's
/// `#[repr(u32)]` enums are `uint32_t` codes in C.
fn c_type(ty: &'static str) -> (&'static str, &'static str) {
    match ty {
        "PaperMode" => ("u32", "`WMR_PAPER_MODE_POSE` or `WMR_PAPER_MODE_POSITION`"),
        "HoldMode" => ("u32", "`WMR_HOLD_AUTO`, `WMR_HOLD_ZERO_ERRORS` or `WMR_HOLD_FREEZE`"),
        "AntiWindup" => ("u32", "`WMR_ANTI_WINDUP_OFF` or `WMR_ANTI_WINDUP_CONDITIONAL`"),
        "PoseSource" => ("u32", "`WMR_POSE_ABSOLUTE` or `WMR_POSE_ODOMETRY`"),
        "TractionKind" => ("u32", "`WMR_TRACTION_ROLLING` or `WMR_TRACTION_SLIP`"),
        "MotionModel" => ("u32", "`WMR_MOTION_MODEL_KINEMATIC`"),
        other => (other, ""),
    }
}

/// Rust declarations of [`shared_structs`] for cbindgen (which cannot see through the
/// core's `params!` macro): the same fields, order and types, so the same C layout.
fn shared_structs_source() -> String {
    let mut out = String::new();
    for (name, doc, fields) in shared_structs() {
        out.push_str(&format!("/// {doc}\n#[repr(C)]\npub struct {name}<T> {{\n"));
        for f in fields {
            let unit = if f.unit.is_empty() { String::new() } else { format!(", {}", f.unit) };
            let (ty, constants) = c_type(f.ty);
            let rule = if constants.is_empty() { f.rule } else { constants };
            out.push_str(&format!(
                "    /// {}{unit} ({rule}).\n    pub {}: {ty},\n",
                f.doc.trim_end_matches('.'),
                f.name,
            ));
        }
        out.push_str("}\n\n");
    }
    out
}

#[test]
fn shared_structs_have_the_core_layout() {
    // The C declarations list the fields in declaration order; repr(C) lays them out so.
    // All-float structs: one float per declared field, nothing else.
    let floats = |fields: &[ParamField]| fields.len() * 4;
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_robot_params<f32>>(), floats(RobotParams::<f64>::FIELDS));
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_world_params<f32>>(), floats(WorldParams::<f64>::FIELDS));
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_wheel_stage_params<f32>>(), floats(WheelStageParams::<f64>::FIELDS));
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_sensor_params<f32>>(), 4 * 4 + 4 + 4 + 8);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_sensor_params<f64>, seed), 4 * 8 + 8);
    // The odometry and traction structs: a u32 code, then floats.
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_odometry_params<f32>>(), 3 * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_odometry_params<f64>, fix_rate_hz), 8);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_odometry_params<f64>>(), 3 * 8);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_traction_params<f32>>(), TractionParams::<f64>::FIELDS.len() * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_traction_params<f64>, friction_coefficient), 8);
    // The law structs: u32 codes and floats, in declaration order.
    let paper = PaperParams::<f64>::FIELDS;
    let offsets = [
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, mode),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, kp_theta),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, ki_theta),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, kp_s),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, ki_s),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, goal_radius),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, hold_radius),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, hold),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, anti_windup),
    ];
    assert_eq!(paper.len(), offsets.len());
    assert_eq!(offsets, [0, 8, 16, 24, 32, 40, 48, 56, 60]);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_params<f32>>(), 9 * 4);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_params<f64>>(), 64);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_bidirectional_params<f32>>(), 7 * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_paper_bidirectional_params<f64>, hold), 6 * 8);
    for (_, _, fields) in shared_structs() {
        assert!(fields.iter().all(|f| matches!(c_type(f.ty).0, "T" | "u32" | "u64")), "{fields:?}");
    }
}

/// The C struct `name`'s members as the generated header declares them, in order.
fn c_members(header: &str, name: &str) -> Vec<String> {
    let end = header.find(&format!("}} {name};")).unwrap_or_else(|| panic!("{name} is not in the header"));
    let start = header[..end].rfind("typedef struct {").expect("a typedef struct");
    header[start..end]
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//") && l.ends_with(';'))
        .map(|l| l.trim_end_matches(';').rsplit(' ').next().expect("a member").to_owned())
        .collect()
}

#[test]
fn every_law_struct_has_the_core_fields_in_order() {
    // The polar and Lyapunov structs are written out in src/lib.rs (their `bool`s are
    // `uint32_t` in C); the paper structs come from the core's tables. Either way the C
    // members must be the core's fields, in the core's order.
    let header = generate();
    let laws: [(&str, &[ParamField]); 7] = [
        ("wmr_paper_params_f64", PaperParams::<f64>::FIELDS),
        ("wmr_paper_bidirectional_params_f64", PaperBidirectionalParams::<f64>::FIELDS),
        ("wmr_polar_params_f64", PolarParams::<f64>::FIELDS),
        ("wmr_lyapunov_params_f64", LyapunovParams::<f64>::FIELDS),
        ("wmr_kanayama_params_f64", KanayamaParams::<f64>::FIELDS),
        ("wmr_backstepping_params_f64", BacksteppingParams::<f64>::FIELDS),
        ("wmr_pure_pursuit_params_f64", PurePursuitParams::<f64>::FIELDS),
    ];
    for (name, fields) in laws {
        let core: Vec<&str> = fields.iter().map(|f| f.name).collect();
        assert_eq!(c_members(&header, name), core, "{name}");
    }
}

/// The core's `#[repr(C)]` `State` (crates/wmr-core/src/state.rs), its declaration as
/// written there, named `wmr_state` for cbindgen (which does not follow the alias in
/// src/lib.rs).
fn core_state_source() -> String {
    let path = crate_dir().join("../wmr-core/src/state.rs");
    let src = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let decl = src.find("pub struct State<T> {").expect("the core's State");
    let start = src[..decl].rfind("\n\n").expect("a blank line before State's doc") + 2;
    let end = decl + src[decl..].find("\n}\n").expect("the end of State") + 3;
    src[start..end].replace("pub struct State<T>", "pub struct wmr_state<T>")
}

fn generate() -> String {
    let dir = crate_dir();
    // One file per call: tests run generate() on several threads at once.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let shared = std::env::temp_dir().join(format!("wmr-ffi-shared-{}-{call}.rs", std::process::id()));
    std::fs::write(&shared, shared_structs_source() + &core_state_source()).expect("temporary source");
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .with_src(&shared)
        .generate()
        .expect("cbindgen parses the crate");
    let _ = std::fs::remove_file(&shared);
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("UTF-8 header")
}

#[test]
fn header_is_current() {
    // The API files must be current first, or the header would be generated from stale
    // ones; under WMR_BLESS they are written first.
    let dir = crate_dir().join("src");
    for (file, fresh) in [("api_f32.rs", api_f32()), ("api_f64.rs", api_f64())] {
        let now = std::fs::read_to_string(dir.join(file)).unwrap_or_default();
        if bless() {
            // Only when changed, and whole (a rename): the other tests of this file parse
            // the crate with cbindgen at the same time and must never see half a file.
            if now != fresh {
                let tmp = dir.join(format!(".{file}.tmp"));
                std::fs::write(&tmp, &fresh).expect("write the API file");
                std::fs::rename(&tmp, dir.join(file)).expect("replace the API file");
            }
        } else {
            assert!(now == fresh, "{file} is stale: run WMR_BLESS=1 cargo test -p wmr-ffi --test header");
        }
    }
    let header = generate();
    for name in [
        "wmr_plant_f32_step",
        "wmr_plant_f64_step",
        "wmr_lyapunov_controller_f64_update",
        "wmr_paper_bidirectional_controller_f32_update",
        "WMR_PLANT_F32_WORDS",
    ] {
        assert!(header.contains(name), "the generated header lacks {name}");
    }
    check_or_bless(&crate_dir().join("include/wmr.h"), &header, "run WMR_BLESS=1 cargo test -p wmr-ffi --test header");
}
