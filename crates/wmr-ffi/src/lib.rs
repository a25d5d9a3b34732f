//! # wmr-ffi: the C API of wmr-core
//!
//! The header is `crates/wmr-ffi/include/wmr.h`, generated from this crate by cbindgen
//! (`cargo xtask gen` rewrites it; `cargo test -p xtask` fails when it is stale). Build the static library with
//!
//! ```text
//! cargo build -p wmr-ffi --release                       # host: target/release/libwmr_ffi.a
//! cargo build -p wmr-ffi --release --no-default-features \
//!     --target thumbv7em-none-eabihf                      # Cortex-M4F, no_std
//! ```
//!
//! Every entry point exists in an `_f32` and an `_f64` flavour. No function allocates:
//! each object (a validated robot, a drive, a plant, a sensor, a controller) lives in
//! storage the caller declares, a struct of `uint64_t` words whose size is given in the
//! header (`WMR_PLANT_F32_WORDS`, ...) and whose alignment is 8 (`WMR_STORAGE_ALIGN`).
//! An `*_init` function validates its inputs and fills the storage; the other functions
//! refuse storage that was not filled by the matching `*_init` (`WMR_NOT_INITIALIZED`).
//!
//! Errors: every function returns a [`wmr_status`]. Functions that validate parameters
//! also fill an optional [`wmr_error`] with the NUL-terminated name of the offending
//! field, as the core names it (`mass`, `servo_kp`, `control_dt`), the reason and the
//! value. No panic crosses the boundary: with the `std` feature (the host library) every
//! entry point runs under `catch_unwind` and a panic returns `WMR_PANIC`; the `no_std`
//! build for Cortex-M (feature `panic-handler`) traps instead (a HardFault), and
//! `firmware/check` shows that the only panic sites the entry points link are the core
//! pose sensor's two, in range by construction.
//!
//! Safety contract for C callers, once for all functions: every pointer argument is
//! either NULL (refused with `WMR_NULL_POINTER`), misaligned for its type (refused with
//! `WMR_MISALIGNED`, never dereferenced) or valid for reads (inputs) or writes (outputs)
//! of its type, and storage is not used from two threads at once. Every number passed
//! in is checked (finite, in range) and every number passed out is finite: a call
//! whose output would not be is refused (`WMR_NOT_FINITE`) and changes nothing.
//!
//! Laws: every law of the core's registry (`wmr_core::for_each_law!`) has a parameter
//! struct with defaults and `*_controller_*_init`, `_update`,
//! `_update_reference` and `_reset`. `_update_reference` follows a
//! [`wmr_reference_state`] (pose, twist, acceleration of the reference point);
//! `_update(..., goal, ...)` is the reference at rest at `goal`.
//!
//! Sensors: `wmr_sensor_*` is one storage type for every sensor model, created by a
//! per-model init function (`_init_perfect`: the paper's assumption; `_init_pose`: the
//! core's [`wmr_core::PoseSensor`] with rate, latency, noise and encoder counts;
//! `_init_odometry`: the core's [`wmr_core::OdometrySensor`], the pose dead-reckoned from
//! the encoders and fused by the EKF with absolute fixes) and used through the same
//! `measure`/`reset`; another model is one more init function.
//!
//! Plants: `wmr_plant_*_init` rolls (the paper's model); `_init_traction` takes a
//! [`wmr_traction_params`], with which the wheels slip when the forces exceed mu times
//! the normal loads. `wmr_plant_*_wheel_speeds` gives each wheel's own speed (under slip
//! it differs from the body's), which is what the sensors measure.
#![no_std]
// The C boundary dereferences raw pointers from C; every such place is in `imp`.
#![allow(unsafe_code)]
// C names: `wmr_pose_f32`, `WMR_OK`.
#![allow(non_camel_case_types)]
// One safety contract for every entry point, in the crate docs above.
#![allow(clippy::missing_safety_doc)]

#[cfg(feature = "std")]
extern crate std;

// Generated from the registry by `cargo xtask gen` (xtask/src/ffi_api.rs); laid out by
// the generator, not by rustfmt.
#[rustfmt::skip]
mod api_f32;
#[rustfmt::skip]
mod api_f64;
mod imp;
mod laws;

pub use api_f32::*;
pub use api_f64::*;
pub use laws::*;

use core::ffi::c_char;

/// Version of this C API: changes whenever a struct, a storage size or a signature does.
pub const WMR_ABI_VERSION: u32 = 8;

/// Alignment, bytes, of every storage struct (they are arrays of `uint64_t`).
pub const WMR_STORAGE_ALIGN: usize = 8;

/// Capacity of `wmr_error.field`, bytes, with the terminating NUL.
pub const WMR_FIELD_LEN: usize = 48;

/// Capacity of `wmr_error.reason`, bytes, with the terminating NUL.
pub const WMR_REASON_LEN: usize = 96;

/// `wmr_drive_params_*.kind`: ideal torque source with a motor torque limit.
pub const WMR_DRIVE_TORQUE: u32 = 0;
/// `wmr_drive_params_*.kind`: voltage-driven permanent-magnet DC motor.
pub const WMR_DRIVE_DC_MOTOR: u32 = 1;

/// Pose samples the C API's sensor holds in flight (the core's ring buffer length); the
/// odometry sensor holds as many absolute fixes.
pub const WMR_SENSOR_SAMPLES_IN_FLIGHT: usize = 16;

/// `wmr_odometry_params_*.pose`: the pose comes from the absolute pose sensor.
pub const WMR_POSE_ABSOLUTE: u32 = 0;
/// `wmr_odometry_params_*.pose`: the pose is dead-reckoned from the encoders, fused by
/// the EKF with absolute fixes at `fix_rate_hz` (if > 0).
pub const WMR_POSE_ODOMETRY: u32 = 1;

/// `wmr_traction_params_*.traction`: the paper's rolling wheels (no slip).
pub const WMR_TRACTION_ROLLING: u32 = 0;
/// `wmr_traction_params_*.traction`: wheels that slip, forces within mu times the loads.
pub const WMR_TRACTION_SLIP: u32 = 1;

/// `wmr_paper_params_*.mode`: reach (x, y, theta) (the paper's orientating control).
pub const WMR_PAPER_MODE_POSE: u32 = 0;
/// `wmr_paper_params_*.mode`: reach (x, y), heading free (positioning control).
pub const WMR_PAPER_MODE_POSITION: u32 = 1;

/// `wmr_paper_params_*.hold`: inside `hold_radius` the outer errors are zero.
pub const WMR_HOLD_ZERO_ERRORS: u32 = 0;
/// `wmr_paper_params_*.hold`: inside `hold_radius` the last wheel references are kept.
pub const WMR_HOLD_FREEZE: u32 = 1;
/// `wmr_paper_params_*.hold`: zero errors in pose mode, freeze in position mode (default).
pub const WMR_HOLD_AUTO: u32 = 2;

/// `wmr_paper_params_*.anti_windup`: the integrators run on while the wheels saturate
/// (the paper's law as printed; its default).
pub const WMR_ANTI_WINDUP_OFF: u32 = 0;
/// `wmr_paper_params_*.anti_windup`: conditional integration, the integrators hold while
/// the wheels saturate.
pub const WMR_ANTI_WINDUP_CONDITIONAL: u32 = 1;

/// `wmr_mppi_params_*.motion_model`: nav2's DiffDrive, the sampled twists within the
/// acceleration limits.
pub const WMR_MOTION_MODEL_KINEMATIC: u32 = 0;

/// `wmr_mppi_params_*.motion_model`: the controller's robot and drive (the default), the
/// accelerations what the drive can give.
pub const WMR_MOTION_MODEL_DYNAMIC: u32 = 1;

/// What a call did. `WMR_OK` is 0; every other value is an error.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum wmr_status {
    /// Success.
    WMR_OK = 0,
    /// A value is NaN or infinite where a finite number is needed.
    WMR_NOT_FINITE = 1,
    /// A value must be > 0.
    WMR_NOT_POSITIVE = 2,
    /// A value must be >= 0.
    WMR_NEGATIVE = 3,
    /// A period must be a whole multiple of the plant step.
    WMR_NOT_MULTIPLE_OF_DT = 4,
    /// A value is NaN (infinity is allowed there).
    WMR_NAN = 5,
    /// A value is outside its documented range (`wmr_error.reason` says which).
    WMR_OUT_OF_RANGE = 6,
    /// A pointer argument is NULL (`wmr_error.field` names the argument).
    WMR_NULL_POINTER = 7,
    /// The storage was not filled by the matching `*_init` function.
    WMR_NOT_INITIALIZED = 8,
    /// A plant step gave a state that is not finite; the state is unchanged.
    WMR_DIVERGED_NON_FINITE = 9,
    /// A plant step took point C out of the 1 km box; the state is unchanged.
    WMR_DIVERGED_LEFT_BOX = 10,
    /// A bug: Rust code panicked. The storage involved must be initialized again.
    WMR_PANIC = 11,
    /// A pointer argument is not aligned for its type (storage: `WMR_STORAGE_ALIGN`;
    /// `wmr_error.field` names the argument). Nothing was read or written through it.
    WMR_MISALIGNED = 12,
    /// The storage's tag is intact but its body fails the checks of the stored value (a
    /// stray write): initialize it again. Checked: a robot's parameters validate to it;
    /// a plant's robot, finite state inside the 1 km box and finite held command. Not
    /// detected: an overwrite of a drive, sensor or controller body that keeps the tag
    /// (a non-finite output is still refused, `WMR_NOT_FINITE`).
    WMR_CORRUPTED = 13,
}

/// Details of a refused call: the code, the field and the rejected value.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct wmr_error {
    /// The same code the function returned.
    pub code: wmr_status,
    /// The rejected value, widened to double (0 when there is none).
    pub value: f64,
    /// NUL-terminated name of the field, as the core names it (`mass`, `goal.x`,
    /// `control_dt`), or of the pointer argument for `WMR_NULL_POINTER`; empty on success.
    pub field: [c_char; WMR_FIELD_LEN],
    /// NUL-terminated reason in words (`must be > 0`); empty on success.
    pub reason: [c_char; WMR_REASON_LEN],
}

/// A planar pose of point C in the world frame: x, y in m, theta in rad (CCW from +x).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_pose<T> {
    /// x of C, m.
    pub x: T,
    /// y of C, m.
    pub y: T,
    /// Heading, rad.
    pub theta: T,
}

/// Body-frame velocity of a point: forward speed v in m/s, yaw rate omega in rad/s.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_twist<T> {
    /// Forward speed along the heading, m/s.
    pub v: T,
    /// Yaw rate, rad/s.
    pub omega: T,
}

/// The time derivative of a `wmr_twist`: v' in m/s^2, omega' in rad/s^2.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_accel<T> {
    /// Forward acceleration dv/dt, m/s^2.
    pub v: T,
    /// Yaw acceleration d(omega)/dt, rad/s^2.
    pub omega: T,
}

/// The reference point C_ref at one instant: what a law follows (the core's
/// `wmr_core::ReferenceState`). Point stabilization is the reference at rest: the goal
/// as `pose`, zero `twist` and `accel`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_reference_state<T> {
    /// Pose of C_ref in the world frame: x, y in m, theta in rad (CCW from +x).
    pub pose: wmr_pose<T>,
    /// Twist of C_ref: v in m/s along `pose.theta`, omega in rad/s.
    pub twist: wmr_twist<T>,
    /// Acceleration of C_ref: v' in m/s^2, omega' in rad/s^2.
    pub accel: wmr_accel<T>,
}

/// The disturbance observer's keys (`[controller.observer] kind = "disturbance"`,
/// `wmr_core::DisturbanceObserverParams` member for member: a test checks): a DOB on the
/// wheel dynamics whose estimate of the disturbance torque at each wheel the wheel stage
/// subtracts from its command, for any law (`wmr_<law>_controller_*_init_observer`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct wmr_disturbance_observer_params<T> {
    /// g, rad/s (> 0, finite): the bandwidth of the Q-filter g / (s + g); the estimate
    /// follows a step of the disturbance with time constant 1 / g.
    pub bandwidth: T,
    /// The driver deadband the controller believes, a fraction of the drive's largest
    /// command (in [0, 1); > 0 only with a finite drive limit; 0: off): a command that
    /// asks for motion is lifted to it (docs/model.md, "Disturbance observer").
    pub deadband: T,
    /// The breakaway torque at each wheel the controller believes, N m (>= 0, finite;
    /// 0: off): a command that asks for motion is lifted to the one giving it at rest.
    pub static_friction: T,
    /// b / c_min, in [0, 1] (default 0.5): commands within this fraction of the lift of
    /// zero pass unlifted, so a holding robot does not chatter.
    pub precompensation_band: T,
}

/// One value per driven wheel (angles, speeds, torques, commands).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_wheels<T> {
    /// Right wheel.
    pub right: T,
    /// Left wheel.
    pub left: T,
}

/// The robot's state: the core's `wmr_core::State` (`#[repr(C)]`; cbindgen reads its
/// declaration from the core's src/state.rs: xtask/src/ffi_header.rs).
/// cbindgen:ignore
pub type wmr_state<T> = wmr_core::State<T>;

/// What a controller sees at one control tick.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_measurement<T> {
    /// When the measurement was taken, s.
    pub t: T,
    /// Measured pose of C (m, m, rad).
    pub pose: wmr_pose<T>,
    /// Wheel angles from the encoders, rad.
    pub wheel_angles: wmr_wheels<T>,
    /// Wheel speeds, rad/s.
    pub wheel_speeds: wmr_wheels<T>,
}

/// What the odometry sensor knows beyond its measurement (whose pose is the EKF's mean).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_odometry_estimate<T> {
    /// The pose dead-reckoned from the encoders alone (world frame; m, m, rad).
    pub dead_reckoning: wmr_pose<T>,
    /// The EKF's covariance of (x, y, theta), row-major: m^2, m rad, rad^2.
    pub covariance: [T; 9],
}

/// One control update: the drive commands to hold until the next tick and the law's
/// logged errors.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_control_output<T> {
    /// Per-wheel drive command: wheel-torque demand (N m, torque drive) or voltage (V,
    /// DC motor).
    pub command: wmr_wheels<T>,
    /// The law's along-track error, m.
    pub e_s: T,
    /// The law's heading error, rad, in (-pi, pi].
    pub e_theta: T,
    /// The measured distance from C to the goal position, m.
    pub dl: T,
}

// The parameter structs the C API shares with the core: the core's own `#[repr(C)]`
// types (declared with `wmr_core::params!`). cbindgen does not see through the alias or
// the macro, so `cargo xtask gen` (xtask/src/ffi_header.rs) writes their C declarations from the core's field tables
// (`wmr_core::describe::Described::FIELDS`).
/// The robot (the `[robot]` keys): `wmr_core::RobotParams`.
/// cbindgen:ignore
pub type wmr_robot_params<T> = wmr_core::RobotParams<T>;
/// The ground (the `[world]` keys): `wmr_core::WorldParams`.
/// cbindgen:ignore
pub type wmr_world_params<T> = wmr_core::WorldParams<T>;
/// The pose sensor (the `[sensor]` keys): `wmr_core::SensorParams`.
/// cbindgen:ignore
pub type wmr_sensor_params<T> = wmr_core::SensorParams<T>;
/// The wheel stage: `wmr_core::WheelStageParams`.
/// cbindgen:ignore
pub type wmr_wheel_stage_params<T> = wmr_core::WheelStageParams<T>;
/// The odometry sensor's pose source (the `[sensor]` keys `pose`, `fix_rate_hz`,
/// `odometry_noise`): `wmr_core::OdometryParams`.
/// cbindgen:ignore
pub type wmr_odometry_params<T> = wmr_core::OdometryParams<T>;
/// The slip plant (the `[robot]` keys `traction`, ..., `stiction_length`):
/// `wmr_core::TractionParams`.
/// cbindgen:ignore
pub type wmr_traction_params<T> = wmr_core::TractionParams<T>;

// The C constants are the core enums' discriminants (`#[repr(u32)]`).
const _: () = {
    assert!(wmr_core::PaperMode::Pose as u32 == WMR_PAPER_MODE_POSE);
    assert!(wmr_core::PaperMode::Position as u32 == WMR_PAPER_MODE_POSITION);
    assert!(wmr_core::HoldMode::ZeroErrors as u32 == WMR_HOLD_ZERO_ERRORS);
    assert!(wmr_core::HoldMode::Freeze as u32 == WMR_HOLD_FREEZE);
    assert!(wmr_core::HoldMode::Auto as u32 == WMR_HOLD_AUTO);
    assert!(wmr_core::PoseSource::Absolute as u32 == WMR_POSE_ABSOLUTE);
    assert!(wmr_core::PoseSource::Odometry as u32 == WMR_POSE_ODOMETRY);
    assert!(wmr_core::TractionKind::Rolling as u32 == WMR_TRACTION_ROLLING);
    assert!(wmr_core::TractionKind::Slip as u32 == WMR_TRACTION_SLIP);
    assert!(wmr_core::MotionModel::Kinematic as u32 == WMR_MOTION_MODEL_KINEMATIC);
    assert!(wmr_core::MotionModel::Dynamic as u32 == WMR_MOTION_MODEL_DYNAMIC);
};

/// Drive parameters (the `[drive]` keys). `kind` selects which fields are read.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct wmr_drive_params<T> {
    /// `WMR_DRIVE_TORQUE` or `WMR_DRIVE_DC_MOTOR`.
    pub kind: u32,
    /// Torque drive: |motor torque| limit at the motor shaft, N m (> 0, infinity allowed).
    pub motor_torque_max: T,
    /// DC motor: supply voltage limit, V (> 0).
    pub voltage_max: T,
    /// DC motor: torque constant, N m/A (> 0).
    pub torque_constant: T,
    /// DC motor: back-EMF constant, V s/rad at the motor shaft (>= 0).
    pub back_emf_constant: T,
    /// DC motor: armature resistance, Ohm (> 0).
    pub armature_resistance: T,
    /// DC motor: armature current limit of the motor driver, A (> 0, infinity = none).
    pub current_max: T,
}

// The polar and Lyapunov laws' C structs are not the core's types: their `reverse` is a
// Rust `bool` (1 byte) and a `uint32_t` here, so an alias would change the C layout.
// tests/header.rs checks that their fields are the core's, in the core's order.

// Storage: cbindgen reads literal sizes, so each type is written out; `imp` checks at
// compile time that the Rust object it holds fits (size and alignment).
/// Words (8 bytes each) of a validated robot, `wmr_robot_f32`.
pub const WMR_ROBOT_F32_WORDS: usize = 12;
/// Words of a validated robot, `wmr_robot_f64`.
pub const WMR_ROBOT_F64_WORDS: usize = 20;
/// Words of a validated drive, `wmr_drive_f32`.
pub const WMR_DRIVE_F32_WORDS: usize = 8;
/// Words of a validated drive, `wmr_drive_f64`.
pub const WMR_DRIVE_F64_WORDS: usize = 12;
/// Words of a plant, `wmr_plant_f32`.
pub const WMR_PLANT_F32_WORDS: usize = 144;
/// Words of a plant, `wmr_plant_f64`.
pub const WMR_PLANT_F64_WORDS: usize = 256;
/// Words of a sensor, `wmr_sensor_f32` (perfect, pose or odometry sensor).
pub const WMR_SENSOR_F32_WORDS: usize = 144;
/// Words of a sensor, `wmr_sensor_f64` (perfect, pose or odometry sensor).
pub const WMR_SENSOR_F64_WORDS: usize = 208;
/// Points a `wmr_reference_*` of waypoints holds at most in its own storage (the core's
/// `MAX_POINTS`; the firmware's capacity too). A longer path: `_init_waypoints_in`, in
/// storage of `wmr_reference_<f32|f64>_waypoints_words(n)` numbers the caller owns.
pub const WMR_REFERENCE_MAX_POINTS: usize = 64;
/// Words of a reference, `wmr_reference_f32` (circle, figure-eight, line or waypoints:
/// 64 waypoints and their speed profile take 9.4 kB).
pub const WMR_REFERENCE_F32_WORDS: usize = 1280;
/// Words of a reference, `wmr_reference_f64` (circle, figure-eight, line or waypoints:
/// 64 waypoints and their speed profile take 18.8 kB).
pub const WMR_REFERENCE_F64_WORDS: usize = 2432;

/// A validated robot (f32): parameters and the reduced inertia matrix.
#[repr(C)]
pub struct wmr_robot_f32 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_ROBOT_F32_WORDS],
}
/// A validated robot (f64): parameters and the reduced inertia matrix.
#[repr(C)]
pub struct wmr_robot_f64 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_ROBOT_F64_WORDS],
}
/// A validated drive (f32).
#[repr(C)]
pub struct wmr_drive_f32 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_DRIVE_F32_WORDS],
}
/// A validated drive (f64).
#[repr(C)]
pub struct wmr_drive_f64 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_DRIVE_F64_WORDS],
}
/// The plant (f32): robot, drive and state, stepped by RK4 under a held command.
#[repr(C)]
pub struct wmr_plant_f32 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_PLANT_F32_WORDS],
}
/// The plant (f64): robot, drive and state, stepped by RK4 under a held command.
#[repr(C)]
pub struct wmr_plant_f64 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_PLANT_F64_WORDS],
}
/// A sensor (f32): turns the plant's true state into a measurement.
#[repr(C)]
pub struct wmr_sensor_f32 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_SENSOR_F32_WORDS],
}
/// A sensor (f64): turns the plant's true state into a measurement.
#[repr(C)]
pub struct wmr_sensor_f64 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_SENSOR_F64_WORDS],
}
/// Words of a set of obstacles, `wmr_obstacles_f32` (16 obstacles, 32 polygon vertices).
pub const WMR_OBSTACLES_F32_WORDS: usize = 72;
/// Words of a set of obstacles, `wmr_obstacles_f64` (16 obstacles, 32 polygon vertices).
pub const WMR_OBSTACLES_F64_WORDS: usize = 128;

/// Obstacles on the controller's map and the robot's footprint radius (f32; the core's
/// `wmr_core::Obstacles`, a scenario's `[[world.obstacle]]` and `[robot]
/// footprint_radius`): `wmr_obstacles_f32_init`, then `_add_circle`, `_add_polygon`;
/// MPPI's `_init_in` reads them (its `obstacles` critic).
#[repr(C)]
pub struct wmr_obstacles_f32 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_OBSTACLES_F32_WORDS],
}
/// Obstacles and the footprint radius (f64), as `wmr_obstacles_f32`.
#[repr(C)]
pub struct wmr_obstacles_f64 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_OBSTACLES_F64_WORDS],
}

/// A moving reference (f32): a circle, a figure-eight, a line or a spline through
/// waypoints (the core's `wmr_core::AnyReference`), with its state at any time and its
/// path for the path-following law.
#[repr(C)]
pub struct wmr_reference_f32 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_REFERENCE_F32_WORDS],
}
/// A moving reference (f64), as `wmr_reference_f32`.
#[repr(C)]
pub struct wmr_reference_f64 {
    /// Opaque: only the library reads or writes it.
    pub opaque: [u64; WMR_REFERENCE_F64_WORDS],
}

/// The version of the C API this library implements; compare it with the header's
/// `WMR_ABI_VERSION` at start-up.
#[unsafe(no_mangle)]
pub extern "C" fn wmr_abi_version() -> u32 {
    WMR_ABI_VERSION
}

/// A static NUL-terminated name for a status code (`"WMR_NOT_POSITIVE"`), or
/// `"WMR_UNKNOWN"` for a value that is not a `wmr_status`.
#[unsafe(no_mangle)]
pub extern "C" fn wmr_status_name(code: i32) -> *const c_char {
    imp::status_name(code).as_ptr()
}
