//! `[controller]`, tagged by `kind`. Adding a kind touches only this file: a variant in
//! [`ControllerFile`], [`ControllerSpec`] and [`BuiltController`], and one arm in each match.

use std::fmt::Write as _;

use serde::{Deserialize, Deserializer};
use wmr_core::controller::{ControlOutput, Controller, Measurement};
use wmr_core::{Drive, DriveParams, PaperController, PaperMode, PaperParams, ParamError, Pose2, Robot, ServoGains};

use crate::file::tagged;

/// `[controller]` as written. `kind` defaults to `"paper"`.
#[derive(Clone, Debug, PartialEq)]
pub enum ControllerFile {
    /// `kind = "paper"`: the paper's law (SPEC section 4).
    Paper(PaperFile),
}

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
            other => Err(tagged::unknown_kind::<D>(other, &["paper"])),
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
}

/// A resolved controller: every parameter filled in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControllerSpec {
    /// The paper's law.
    Paper(PaperParams<f64>),
}

impl ControllerFile {
    /// Fills the defaults; the servo defaults depend on the drive kind.
    pub fn to_spec(&self, drive: &DriveParams<f64>) -> ControllerSpec {
        match self {
            ControllerFile::Paper(f) => {
                let d = PaperParams::<f64>::paper();
                let servo_default = match drive {
                    DriveParams::Torque(_) => ServoGains::torque_default(),
                    DriveParams::DcMotor(_) => ServoGains::dc_motor_default(),
                };
                ControllerSpec::Paper(PaperParams {
                    mode: match f.mode {
                        None => d.mode,
                        Some(ModeFile::Pose) => PaperMode::Pose,
                        Some(ModeFile::Position) => PaperMode::Position,
                    },
                    kp_theta: f.kp_theta.unwrap_or(d.kp_theta),
                    ki_theta: f.ki_theta.unwrap_or(d.ki_theta),
                    kp_s: f.kp_s.unwrap_or(d.kp_s),
                    ki_s: f.ki_s.unwrap_or(d.ki_s),
                    servo: ServoGains {
                        kp: f.servo_kp.unwrap_or(servo_default.kp),
                        kd: f.servo_kd.unwrap_or(servo_default.kd),
                        ki: f.servo_ki.unwrap_or(servo_default.ki),
                    },
                    goal_radius: f.goal_radius.unwrap_or(d.goal_radius),
                    hold_radius: f.hold_radius.unwrap_or(d.hold_radius),
                    control_dt: f.control_dt.unwrap_or(d.control_dt),
                })
            }
        }
    }
}

impl ControllerSpec {
    /// The `kind` key.
    pub fn kind(&self) -> &'static str {
        match self {
            ControllerSpec::Paper(_) => "paper",
        }
    }

    /// Control period, s.
    pub fn control_dt(&self) -> f64 {
        match self {
            ControllerSpec::Paper(p) => p.control_dt,
        }
    }

    /// Builds (and so validates) the controller for a robot, drive and goal.
    pub fn build(
        &self,
        robot: &Robot<f64>,
        drive: &Drive<f64>,
        goal: Pose2<f64>,
    ) -> Result<BuiltController, ParamError> {
        match self {
            ControllerSpec::Paper(p) => PaperController::new(*p, robot, drive, goal).map(BuiltController::Paper),
        }
    }

    /// The `[controller]` table in TOML, every key written.
    pub(crate) fn write_toml(&self, out: &mut String) {
        match self {
            ControllerSpec::Paper(p) => {
                let mode = match p.mode {
                    PaperMode::Pose => "pose",
                    PaperMode::Position => "position",
                };
                let _ = writeln!(out, "kind = \"paper\"");
                let _ = writeln!(out, "mode = \"{mode}\"");
                for (k, v) in [
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
                ] {
                    let _ = writeln!(out, "{k} = {}", crate::scenario::toml_f64(v));
                }
            }
        }
    }
}

/// A built controller of any kind; implements [`Controller`] by dispatch.
#[derive(Clone, Debug)]
pub enum BuiltController {
    /// The paper's law.
    Paper(PaperController<f64>),
}

impl Controller<f64> for BuiltController {
    #[inline]
    fn update(&mut self, m: &Measurement<f64>) -> ControlOutput<f64> {
        match self {
            BuiltController::Paper(c) => c.update(m),
        }
    }

    fn reset(&mut self) {
        match self {
            BuiltController::Paper(c) => c.reset(),
        }
    }

    fn control_dt(&self) -> f64 {
        match self {
            BuiltController::Paper(c) => c.control_dt(),
        }
    }

    fn goal(&self) -> Pose2<f64> {
        match self {
            BuiltController::Paper(c) => c.goal(),
        }
    }
}
