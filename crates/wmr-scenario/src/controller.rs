//! `[controller]`, tagged by `kind` ("paper", "polar", "lyapunov"). Adding a kind touches
//! only this file and the core's `ControllerParams`: a variant in [`ControllerFile`] and
//! one arm in each match.

use std::fmt::Write as _;

use serde::{Deserialize, Deserializer};
use wmr_core::controller::{AnyController, ControllerParams, LyapunovParams, PolarParams};
use wmr_core::{Drive, DriveParams, HoldMode, PaperMode, PaperParams, ParamError, Pose2, Robot, ServoGains};

use crate::file::tagged;

/// `[controller]` as written. `kind` defaults to `"paper"`.
#[derive(Clone, Debug, PartialEq)]
pub enum ControllerFile {
    /// `kind = "paper"`: the paper's law (SPEC section 4).
    Paper(PaperFile),
    /// `kind = "polar"`: Astolfi's polar-coordinates law.
    Polar(PolarFile),
    /// `kind = "lyapunov"`: Aicardi et al.'s law, which also reaches the goal heading.
    Lyapunov(LyapunovFile),
}

/// The `kind` names, in documentation order.
pub const CONTROLLER_KINDS: [&str; 3] = ["paper", "polar", "lyapunov"];

impl Default for ControllerFile {
    fn default() -> Self {
        ControllerFile::Paper(PaperFile::default())
    }
}

impl<'de> Deserialize<'de> for ControllerFile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (kind, rest) = tagged::split::<D>(d, "paper")?;
        match kind.as_str() {
            "paper" => tagged::inner::<D, _>(rest).map(ControllerFile::Paper),
            "polar" => tagged::inner::<D, _>(rest).map(ControllerFile::Polar),
            "lyapunov" => tagged::inner::<D, _>(rest).map(ControllerFile::Lyapunov),
            other => Err(tagged::unknown_kind::<D>(other, &CONTROLLER_KINDS)),
        }
    }
}

/// `mode` of the paper controller.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ModeFile {
    /// Orientating control: reach (x_d, y_d, theta_d).
    Pose,
    /// Positioning control: reach (x_d, y_d), heading free.
    Position,
}

/// `hold` of the paper controller.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum HoldFile {
    /// SPEC section 4: errors taken as zero inside hold_radius (the default).
    ZeroErrors,
    /// Bumpless: keep the last wheel references.
    Freeze,
}

/// `[controller] kind = "paper"` keys (SPEC section 4). Missing keys take the SPEC defaults;
/// the servo defaults follow the drive (`ServoGains::torque_default` or `dc_motor_default`).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // each key is documented on `wmr_core::PaperParams` and in docs/scenario.md
pub struct PaperFile {
    pub mode: Option<ModeFile>,
    pub kp_theta: Option<f64>,
    pub ki_theta: Option<f64>,
    pub kp_s: Option<f64>,
    pub ki_s: Option<f64>,
    pub servo_kp: Option<f64>,
    pub servo_kd: Option<f64>,
    pub servo_ki: Option<f64>,
    pub goal_radius: Option<f64>,
    pub hold_radius: Option<f64>,
    pub control_dt: Option<f64>,
    /// rad/s: limit on the speed of the wheel angle references; absent = off.
    pub wheel_speed_max: Option<f64>,
    pub hold: Option<HoldFile>,
}

/// `[controller] kind = "polar"` keys (see `wmr_core::controller::PolarParams`).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // each key is documented on `wmr_core::controller::PolarParams` and in docs/scenario.md
pub struct PolarFile {
    pub k_rho: Option<f64>,
    pub k_alpha: Option<f64>,
    pub k_beta: Option<f64>,
    pub reverse: Option<bool>,
    pub reverse_hysteresis: Option<f64>,
    pub goal_radius: Option<f64>,
    pub wheel_speed_max: Option<f64>,
    pub servo_kp: Option<f64>,
    pub servo_kd: Option<f64>,
    pub servo_ki: Option<f64>,
    pub control_dt: Option<f64>,
}

/// `[controller] kind = "lyapunov"` keys (see `wmr_core::controller::LyapunovParams`).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // each key is documented on `wmr_core::controller::LyapunovParams` and in docs/scenario.md
pub struct LyapunovFile {
    pub gamma: Option<f64>,
    pub k: Option<f64>,
    pub h: Option<f64>,
    pub reverse: Option<bool>,
    pub reverse_hysteresis: Option<f64>,
    pub goal_radius: Option<f64>,
    pub wheel_speed_max: Option<f64>,
    pub servo_kp: Option<f64>,
    pub servo_kd: Option<f64>,
    pub servo_ki: Option<f64>,
    pub control_dt: Option<f64>,
}

/// A resolved controller, every parameter filled in: the core's parameters of any kind.
pub type ControllerSpec = ControllerParams<f64>;

/// A built controller of any kind; implements `Controller` by dispatch.
pub type BuiltController = AnyController<f64>;

/// Servo gains: the keys given, the drive's defaults for the rest.
fn servo(kp: Option<f64>, kd: Option<f64>, ki: Option<f64>, drive: &DriveParams<f64>) -> ServoGains<f64> {
    let d = match drive {
        DriveParams::Torque(_) => ServoGains::torque_default(),
        DriveParams::DcMotor(_) => ServoGains::dc_motor_default(),
    };
    ServoGains { kp: kp.unwrap_or(d.kp), kd: kd.unwrap_or(d.kd), ki: ki.unwrap_or(d.ki) }
}

impl ControllerFile {
    /// The file of a kind with every key absent (its defaults), if `kind` is known.
    pub fn default_of(kind: &str) -> Option<Self> {
        match kind {
            "paper" => Some(ControllerFile::Paper(PaperFile::default())),
            "polar" => Some(ControllerFile::Polar(PolarFile::default())),
            "lyapunov" => Some(ControllerFile::Lyapunov(LyapunovFile::default())),
            _ => None,
        }
    }

    /// Fills the defaults; the servo defaults depend on the drive kind.
    pub fn to_spec(&self, drive: &DriveParams<f64>) -> ControllerSpec {
        match self {
            ControllerFile::Paper(f) => {
                let d = PaperParams::<f64>::paper();
                let params = PaperParams {
                    mode: match f.mode {
                        None => d.mode,
                        Some(ModeFile::Pose) => PaperMode::Pose,
                        Some(ModeFile::Position) => PaperMode::Position,
                    },
                    kp_theta: f.kp_theta.unwrap_or(d.kp_theta),
                    ki_theta: f.ki_theta.unwrap_or(d.ki_theta),
                    kp_s: f.kp_s.unwrap_or(d.kp_s),
                    ki_s: f.ki_s.unwrap_or(d.ki_s),
                    servo: servo(f.servo_kp, f.servo_kd, f.servo_ki, drive),
                    goal_radius: f.goal_radius.unwrap_or(d.goal_radius),
                    hold_radius: f.hold_radius.unwrap_or(d.hold_radius),
                    hold: match f.hold {
                        None => d.hold,
                        Some(HoldFile::ZeroErrors) => HoldMode::ZeroErrors,
                        Some(HoldFile::Freeze) => HoldMode::Freeze,
                    },
                    control_dt: f.control_dt.unwrap_or(d.control_dt),
                };
                ControllerParams::Paper { params, wheel_speed_max: f.wheel_speed_max.unwrap_or(f64::INFINITY) }
            }
            ControllerFile::Polar(f) => {
                let d = PolarParams::<f64>::default();
                ControllerParams::Polar(PolarParams {
                    k_rho: f.k_rho.unwrap_or(d.k_rho),
                    k_alpha: f.k_alpha.unwrap_or(d.k_alpha),
                    k_beta: f.k_beta.unwrap_or(d.k_beta),
                    reverse: f.reverse.unwrap_or(d.reverse),
                    reverse_hysteresis: f.reverse_hysteresis.unwrap_or(d.reverse_hysteresis),
                    goal_radius: f.goal_radius.unwrap_or(d.goal_radius),
                    wheel_speed_max: f.wheel_speed_max.unwrap_or(d.wheel_speed_max),
                    servo: servo(f.servo_kp, f.servo_kd, f.servo_ki, drive),
                    control_dt: f.control_dt.unwrap_or(d.control_dt),
                })
            }
            ControllerFile::Lyapunov(f) => {
                let d = LyapunovParams::<f64>::default();
                ControllerParams::Lyapunov(LyapunovParams {
                    gamma: f.gamma.unwrap_or(d.gamma),
                    k: f.k.unwrap_or(d.k),
                    h: f.h.unwrap_or(d.h),
                    reverse: f.reverse.unwrap_or(d.reverse),
                    reverse_hysteresis: f.reverse_hysteresis.unwrap_or(d.reverse_hysteresis),
                    goal_radius: f.goal_radius.unwrap_or(d.goal_radius),
                    wheel_speed_max: f.wheel_speed_max.unwrap_or(d.wheel_speed_max),
                    servo: servo(f.servo_kp, f.servo_kd, f.servo_ki, drive),
                    control_dt: f.control_dt.unwrap_or(d.control_dt),
                })
            }
        }
    }
}

/// Builds (and so validates) a controller for a robot, drive and goal (m, m, rad).
pub fn build_controller(
    spec: &ControllerSpec,
    robot: &Robot<f64>,
    drive: &Drive<f64>,
    goal: Pose2<f64>,
) -> Result<BuiltController, ParamError> {
    spec.build(robot, drive, goal)
}

/// Writes the `[controller]` table in TOML, every key written.
pub(crate) fn write_toml(spec: &ControllerSpec, out: &mut String) {
    let _ = writeln!(out, "kind = \"{}\"", spec.kind().name());
    let body: Vec<(&str, f64)> = match spec {
        ControllerParams::Paper { params: p, wheel_speed_max } => {
            let mode = match p.mode {
                PaperMode::Pose => "pose",
                PaperMode::Position => "position",
            };
            let hold = match p.hold {
                HoldMode::ZeroErrors => "zero_errors",
                HoldMode::Freeze => "freeze",
            };
            let _ = writeln!(out, "mode = \"{mode}\"");
            let _ = writeln!(out, "hold = \"{hold}\"");
            vec![
                ("kp_theta", p.kp_theta),
                ("ki_theta", p.ki_theta),
                ("kp_s", p.kp_s),
                ("ki_s", p.ki_s),
                ("servo_kp", p.servo.kp),
                ("servo_kd", p.servo.kd),
                ("servo_ki", p.servo.ki),
                ("goal_radius", p.goal_radius),
                ("hold_radius", p.hold_radius),
                ("control_dt", p.control_dt),
                ("wheel_speed_max", *wheel_speed_max),
            ]
        }
        ControllerParams::Polar(p) => {
            let _ = writeln!(out, "reverse = {}", p.reverse);
            vec![
                ("k_rho", p.k_rho),
                ("k_alpha", p.k_alpha),
                ("k_beta", p.k_beta),
                ("reverse_hysteresis", p.reverse_hysteresis),
                ("goal_radius", p.goal_radius),
                ("wheel_speed_max", p.wheel_speed_max),
                ("servo_kp", p.servo.kp),
                ("servo_kd", p.servo.kd),
                ("servo_ki", p.servo.ki),
                ("control_dt", p.control_dt),
            ]
        }
        ControllerParams::Lyapunov(p) => {
            let _ = writeln!(out, "reverse = {}", p.reverse);
            vec![
                ("gamma", p.gamma),
                ("k", p.k),
                ("h", p.h),
                ("reverse_hysteresis", p.reverse_hysteresis),
                ("goal_radius", p.goal_radius),
                ("wheel_speed_max", p.wheel_speed_max),
                ("servo_kp", p.servo.kp),
                ("servo_kd", p.servo.kd),
                ("servo_ki", p.servo.ki),
                ("control_dt", p.control_dt),
            ]
        }
    };
    for (k, v) in body {
        let _ = writeln!(out, "{k} = {}", crate::scenario::toml_f64(v));
    }
}
