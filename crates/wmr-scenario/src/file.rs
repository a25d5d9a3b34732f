//! The scenario file as written (SPEC section 6): every key optional except `[[run]]`,
//! unknown keys rejected. [`ScenarioFile::resolve`] turns it into a checked
//! [`Scenario`](crate::Scenario).

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};
use wmr_core::{DcMotorParams, DriveParams, TorqueDriveParams};

use crate::controller::ControllerFile;
use crate::sweep::SweepFile;

/// A scenario file, parsed but not yet checked. Keys exactly as SPEC section 6.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// Name of the scenario; default: the file's stem.
    pub name: Option<String>,
    /// `[robot]`.
    #[serde(default)]
    pub robot: RobotFile,
    /// `[drive]`.
    #[serde(default)]
    pub drive: DriveFile,
    /// `[controller]`.
    #[serde(default)]
    pub controller: ControllerFile,
    /// `[sim]`.
    #[serde(default)]
    pub sim: SimFile,
    /// `[[run]]`: one or more (an empty or missing list is an error at resolve time,
    /// unless the file has a `[sweep]`).
    #[serde(default)]
    pub run: Vec<RunFile>,
    /// `[sweep]`: many starts and several laws (`wmr-cli sweep`).
    pub sweep: Option<SweepFile>,
}

/// `[robot]` (SPEC section 1), SI units. A missing key takes the paper's value.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // each key is documented on `wmr_core::RobotParams`
pub struct RobotFile {
    pub mass: Option<f64>,
    pub wheel_radius: Option<f64>,
    pub half_track: Option<f64>,
    pub com_offset: Option<f64>,
    pub wheel_inertia: Option<f64>,
    pub platform_inertia: Option<f64>,
    pub gear_ratio: Option<f64>,
    pub viscous_friction: Option<f64>,
    pub coulomb_friction: Option<f64>,
    pub coulomb_speed: Option<f64>,
}

/// `[drive]` (SPEC section 3), tagged by `kind`; `kind` defaults to `"torque"`.
#[derive(Clone, Debug, PartialEq)]
pub enum DriveFile {
    /// `kind = "torque"`.
    Torque(TorqueDriveFile),
    /// `kind = "dc_motor"`.
    DcMotor(DcMotorFile),
}

impl Default for DriveFile {
    fn default() -> Self {
        DriveFile::Torque(TorqueDriveFile::default())
    }
}

/// `[drive] kind = "torque"`.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TorqueDriveFile {
    /// |tau_motor| limit at the motor shaft, N m; `inf` allowed. Default 0.2.
    pub motor_torque_max: Option<f64>,
}

/// `[drive] kind = "dc_motor"`: a permanent-magnet DC motor (defaults: maxon RE 40, 24 V).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DcMotorFile {
    /// u_max, supply voltage limit, V. Default 24.
    pub voltage_max: Option<f64>,
    /// k_tau, torque constant, N m/A. Default 0.0302.
    pub torque_constant: Option<f64>,
    /// k_e, back-EMF constant at the motor shaft, V s/rad. Default 0.0302.
    pub back_emf_constant: Option<f64>,
    /// R_a, armature resistance, Ohm. Default 0.299.
    pub armature_resistance: Option<f64>,
}

impl DriveFile {
    /// The core's drive parameters, defaults filled in.
    pub fn to_params(&self) -> DriveParams<f64> {
        match self {
            DriveFile::Torque(f) => {
                let d = TorqueDriveParams::<f64>::default();
                DriveParams::Torque(TorqueDriveParams {
                    motor_torque_max: f.motor_torque_max.unwrap_or(d.motor_torque_max),
                })
            }
            DriveFile::DcMotor(f) => {
                let d = DcMotorParams::<f64>::default();
                DriveParams::DcMotor(DcMotorParams {
                    voltage_max: f.voltage_max.unwrap_or(d.voltage_max),
                    torque_constant: f.torque_constant.unwrap_or(d.torque_constant),
                    back_emf_constant: f.back_emf_constant.unwrap_or(d.back_emf_constant),
                    armature_resistance: f.armature_resistance.unwrap_or(d.armature_resistance),
                })
            }
        }
    }
}

impl<'de> Deserialize<'de> for DriveFile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (kind, rest) = tagged::split::<D>(d, "torque")?;
        match kind.as_str() {
            "torque" => tagged::inner::<D, _>(rest).map(DriveFile::Torque),
            "dc_motor" => tagged::inner::<D, _>(rest).map(DriveFile::DcMotor),
            other => Err(tagged::unknown_kind::<D>(other, &["torque", "dc_motor"])),
        }
    }
}

/// `[sim]`.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimFile {
    /// Simulated time per run, s. Default 60.
    pub t_end: Option<f64>,
    /// RK4 step, s. Default: the controller's `control_dt`.
    pub dt: Option<f64>,
    /// Output sample period, s; a whole multiple of `dt`. Default 0.01.
    pub log_dt: Option<f64>,
}

/// One `[[run]]`.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RunFile {
    /// Free text for the summary; default built from start and goal.
    pub label: Option<String>,
    /// Start pose of C; default (0, 0, 0).
    pub start: Option<PoseFile>,
    /// Goal pose of C; required.
    pub goal: Option<PoseFile>,
}

/// `{ x = .., y = .., theta = .. }` or with `theta_deg` instead of `theta` (not both).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PoseFile {
    /// m, default 0.
    pub x: Option<f64>,
    /// m, default 0.
    pub y: Option<f64>,
    /// Heading, rad, default 0.
    pub theta: Option<f64>,
    /// Heading, degrees (instead of `theta`).
    pub theta_deg: Option<f64>,
}

/// Tables tagged by `kind` with a default kind: `kind` is taken out and the rest is
/// read by the kind's own `deny_unknown_fields` struct. Errors inside carry their key
/// as a `{key}` prefix that [`crate::locate`] folds into the full key.
pub(crate) mod tagged {
    use super::*;

    /// Marks an inner key in an error message: `KEY_MARK + key + KEY_MARK + message`.
    pub const KEY_MARK: char = '\u{1f}';

    pub fn split<'de, D: Deserializer<'de>>(d: D, default_kind: &str) -> Result<(String, toml::Table), D::Error> {
        let mut table = toml::Table::deserialize(d)?;
        let kind = match table.remove("kind") {
            None => default_kind.to_owned(),
            Some(toml::Value::String(s)) => s,
            Some(other) => {
                return Err(de::Error::custom(format!(
                    "{KEY_MARK}kind{KEY_MARK}expected a string, got {}",
                    other.type_str()
                )));
            }
        };
        Ok((kind, table))
    }

    pub fn inner<'de, D: Deserializer<'de>, T: de::DeserializeOwned>(rest: toml::Table) -> Result<T, D::Error> {
        serde_path_to_error::deserialize(toml::Value::Table(rest)).map_err(|e| {
            let path = e.path().to_string();
            let msg = e.into_inner().message().to_owned();
            match unknown_field(&msg) {
                Some(field) => {
                    de::Error::custom(format!("{KEY_MARK}{field}{KEY_MARK}unknown key for this kind; {msg}"))
                }
                None if path != "." => de::Error::custom(format!("{KEY_MARK}{path}{KEY_MARK}{msg}")),
                None => de::Error::custom(msg),
            }
        })
    }

    pub fn unknown_kind<'de, D: Deserializer<'de>>(kind: &str, known: &[&str]) -> D::Error {
        de::Error::custom(format!("{KEY_MARK}kind{KEY_MARK}unknown kind \"{kind}\", expected one of {known:?}"))
    }

    /// The field of serde's "unknown field `x`, expected ..." message.
    pub fn unknown_field(msg: &str) -> Option<&str> {
        let rest = msg.strip_prefix("unknown field `")?;
        rest.split('`').next()
    }
}
