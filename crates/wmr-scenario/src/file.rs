//! The scenario file as written: the tables of the file's own layout (`[sim]`, `[[run]]`,
//! `[sweep]`, poses). `[robot]`, `[drive]` and `[controller]` stay raw tables here; the
//! core's parameter types read them ([`crate::keys`]). Unknown keys are rejected; the
//! key of any error comes from the path serde reports, never from its message text.

use serde::Deserialize;
use toml::Table;
use wmr_core::Pose2;

use crate::error::ScenarioError;
use crate::keys::join;

/// A scenario file, parsed but not yet checked.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// Name of the scenario; default: the file's stem.
    pub name: Option<String>,
    /// `[robot]`: keys of `wmr_core::RobotParams`.
    pub robot: Option<Table>,
    /// `[drive]`: `kind` and the keys of that drive's parameters.
    pub drive: Option<Table>,
    /// `[controller]`: `kind`, the law's keys, the wheel stage's keys, `control_dt`, and
    /// the `[controller.model]` subtable (keys of `[robot]`).
    pub controller: Option<Table>,
    /// `[sensor]`: keys of `wmr_core::SensorParams`.
    pub sensor: Option<Table>,
    /// `[world]`: keys of `wmr_core::WorldParams`.
    pub world: Option<Table>,
    /// `[reference]`: the moving reference of a tracking scenario (`reference.rs`).
    pub reference: Option<Table>,
    /// `[sim]`.
    pub sim: Option<SimFile>,
    /// `[[run]]`: one or more (none is an error, unless the file has a `[sweep]`).
    #[serde(default)]
    pub run: Vec<RunFile>,
    /// `[sweep]`: many starts and several laws (`wmr-cli sweep`).
    pub sweep: Option<SweepFile>,
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
    /// Stop each run once it has settled (`wmr_core::settle`). Default false.
    pub stop_when_settled: Option<bool>,
    /// With `stop_when_settled`, stop each run as soon as it has arrived by the shorter
    /// test of `wmr_core::arrival` (0.1 s of dying motion, not the 1 s window). Default false.
    pub early_arrival: Option<bool>,
    /// A tracking run converges when its error stays below this over the last 10 % of
    /// t_end, m. Default 0.01.
    pub tracking_tolerance: Option<f64>,
    /// A run towards a goal is docked when it ends with C within this of the goal
    /// position, m (nav2's `xy_goal_tolerance`). Default 0.01.
    pub xy_goal_tolerance: Option<f64>,
    /// ... and its |heading error| within this, deg (nav2's `yaw_goal_tolerance`, in
    /// deg). Default 1.
    pub yaw_goal_tolerance_deg: Option<f64>,
}

/// One `[[run]]`.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RunFile {
    /// Free text for the summary; default built from start and goal.
    pub label: Option<String>,
    /// Start pose of C; default (0, 0, 0).
    pub start: Option<PoseFile>,
    /// Goal pose of C; required, unless the scenario has a `[reference]` (then refused).
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

impl PoseFile {
    /// The pose (m, m, rad), every value finite; errors name `path.x` and so on.
    pub fn resolve(&self, path: &str) -> Result<Pose2<f64>, ScenarioError> {
        let finite = |k: &str, v: Option<f64>| -> Result<f64, ScenarioError> {
            match v {
                None => Ok(0.0),
                Some(v) if v.is_finite() => Ok(v),
                Some(v) => Err(ScenarioError::new(join(path, k), format!("must be a finite number (got {v})"))),
            }
        };
        let x = finite("x", self.x)?;
        let y = finite("y", self.y)?;
        let theta = match (self.theta, self.theta_deg) {
            (Some(_), Some(_)) => {
                return Err(ScenarioError::new(
                    join(path, "theta_deg"),
                    "give the heading as theta (rad) or theta_deg (degrees), not both",
                ));
            }
            (_, Some(_)) => finite("theta_deg", self.theta_deg)?.to_radians(),
            (theta, None) => finite("theta", theta)?,
        };
        Ok(Pose2::new(x, y, theta))
    }
}

/// `[sweep]` as written.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Goal pose of C; default (0, 0, 0). Refused in a sweep over references (the
    /// reference is the goal).
    pub goal: Option<PoseFile>,
    /// The references to follow, each a `[reference]` table: every law runs on every
    /// one, from starts given as offsets from its pose at t = 0. Default: the scenario's
    /// `[reference]`, when it has one; none (a goal at rest) otherwise.
    pub references: Option<Vec<Table>>,
    /// The laws to compare, each a `[controller]` table; default: every law with its defaults.
    pub controllers: Option<Vec<Table>>,
    /// A grid of starts.
    pub grid: Option<GridFile>,
    /// Seeded random starts.
    pub random: Option<RandomFile>,
    /// Keys of the plant, the controller's model, the sensor and the world to vary
    /// (see `vary.rs`).
    pub vary: Option<Vec<crate::vary::VaryFile>>,
    /// Runs per (law, start, variant); default 1.
    pub trials: Option<u32>,
    /// Seed of the per-run draws of `vary`; default 0.
    pub seed: Option<u64>,
}

/// `grid = { ... }`: starts on a rectangular grid, every heading in `theta_deg`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GridFile {
    /// Smallest x of C, m.
    pub x_min: f64,
    /// Largest x of C, m.
    pub x_max: f64,
    /// Points along x (>= 1).
    pub nx: u32,
    /// Smallest y of C, m.
    pub y_min: f64,
    /// Largest y of C, m.
    pub y_max: f64,
    /// Points along y (>= 1).
    pub ny: u32,
    /// Start headings, degrees; default `[0.0]`.
    #[serde(default)]
    pub theta_deg: Option<Vec<f64>>,
}

/// `random = { ... }`: seeded random starts around the goal.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RandomFile {
    /// Number of starts.
    pub n: u32,
    /// Seed of the generator; default 0.
    #[serde(default)]
    pub seed: u64,
    /// Largest distance from the goal, m.
    pub radius: f64,
    /// Smallest distance from the goal, m; default 0.
    #[serde(default)]
    pub min_radius: f64,
    /// Largest |heading| drawn, deg (the heading is uniform in [-max, max)); default 180
    /// (any heading). For a sweep over references, the heading offset from the reference's.
    #[serde(default)]
    pub max_heading_deg: Option<f64>,
}
