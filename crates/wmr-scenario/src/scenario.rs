//! The resolved, checked scenario: parsing entry points, validation and the TOML dump.

use std::fmt::Write as _;
use std::path::Path;

use wmr_core::{ClosedLoop, DriveParams, Pose2, RobotParams};

use crate::controller::{BuiltController, ControllerSpec};
use crate::file::{PoseFile, RunFile, ScenarioFile, SimFile};
use crate::locate;
use crate::sweep::SweepSpec;
use crate::{RunResult, ScenarioError};

/// Largest `sim.t_end` accepted, s (about 11.6 days of simulated time).
pub const MAX_T_END_S: f64 = 1e6;
/// Largest number of plant steps per run accepted (`t_end / dt`): about 15 min of CPU
/// per run at the core's ~1 us per step, so a typo like `dt = 1e-9` is caught.
pub const MAX_STEPS: u64 = 1_000_000_000;
/// Default `sim.t_end`, s.
pub const DEFAULT_T_END_S: f64 = 60.0;
/// Default `sim.log_dt`, s.
pub const DEFAULT_LOG_DT_S: f64 = 0.01;

/// `[sim]`, checked: t_end and log_dt are whole multiples of dt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimSpec {
    t_end: f64,
    dt: f64,
    log_dt: f64,
    n_steps: u64,
    log_every: u32,
}

/// How many `dt` fit in `period` if it is a whole multiple (relative tolerance 1e-9, as
/// the core's own check).
fn whole_multiple(period: f64, dt: f64) -> Option<u64> {
    let ratio = (period / dt).round();
    let tol = 1e-9 * period.abs();
    // ratio <= 2^53 keeps the u64 exact; `as` saturates and the range is checked first.
    ((1.0..=9.0e15).contains(&ratio) && (ratio * dt - period).abs() <= tol).then_some(ratio as u64)
}

fn positive(key: &str, v: f64) -> Result<f64, ScenarioError> {
    if !v.is_finite() {
        Err(ScenarioError::new(key, format!("must be a finite number (got {v})")))
    } else if v <= 0.0 {
        Err(ScenarioError::new(key, format!("must be > 0 (got {v})")))
    } else {
        Ok(v)
    }
}

impl SimSpec {
    /// Checks t_end (s), dt (s) and log_dt (s); errors name `sim.*`.
    pub fn new(t_end: f64, dt: f64, log_dt: f64) -> Result<Self, ScenarioError> {
        let dt = positive("sim.dt", dt)?;
        let t_end = positive("sim.t_end", t_end)?;
        let log_dt = positive("sim.log_dt", log_dt)?;
        if t_end > MAX_T_END_S {
            return Err(ScenarioError::new("sim.t_end", format!("must be <= {MAX_T_END_S:e} s (got {t_end})")));
        }
        let n_steps = whole_multiple(t_end, dt).ok_or_else(|| {
            ScenarioError::new("sim.t_end", format!("must be a whole multiple of sim.dt = {dt} (got {t_end})"))
        })?;
        if n_steps > MAX_STEPS {
            return Err(ScenarioError::new(
                "sim.t_end",
                format!("t_end / dt = {n_steps} steps per run, more than the limit of {MAX_STEPS}"),
            ));
        }
        let log_every = whole_multiple(log_dt, dt).and_then(|n| u32::try_from(n).ok()).ok_or_else(|| {
            ScenarioError::new("sim.log_dt", format!("must be a whole multiple of sim.dt = {dt} (got {log_dt})"))
        })?;
        Ok(Self { t_end, dt, log_dt, n_steps, log_every })
    }

    /// Simulated time per run, s.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// RK4 step, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Output sample period, s.
    pub fn log_dt(&self) -> f64 {
        self.log_dt
    }

    /// Plant steps per run, t_end / dt.
    pub fn n_steps(&self) -> u64 {
        self.n_steps
    }

    /// Plant steps per logged sample, log_dt / dt.
    pub fn log_every(&self) -> u32 {
        self.log_every
    }

    /// Samples a run that does not diverge hands to its sink: t = 0, every log_dt, and
    /// t_end when it is not on the log grid.
    pub fn n_samples(&self) -> u64 {
        let every = u64::from(self.log_every);
        self.n_steps / every + 1 + u64::from(!self.n_steps.is_multiple_of(every))
    }
}

/// One `[[run]]`, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Label for the summary (given, or built from start and goal).
    pub label: String,
    /// Start pose of C: m, m, rad.
    pub start: Pose2<f64>,
    /// Goal pose of C: m, m, rad.
    pub goal: Pose2<f64>,
}

/// A complete, validated scenario: every default filled in, every key checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Name (the `name` key, or the file's stem).
    pub name: String,
    /// `[robot]`.
    pub robot: RobotParams<f64>,
    /// `[drive]`.
    pub drive: DriveParams<f64>,
    /// `[controller]`.
    pub controller: ControllerSpec,
    /// `[sim]`.
    pub sim: SimSpec,
    /// `[[run]]`: at least one, unless the file is a sweep.
    pub runs: Vec<RunSpec>,
    /// `[sweep]`, when the file has one (`wmr-cli sweep`).
    pub sweep: Option<SweepSpec>,
}

/// A float as TOML: the shortest representation that reads back to the same f64.
pub(crate) fn toml_f64(v: f64) -> String {
    if v.is_nan() {
        "nan".to_owned()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".to_owned() } else { "-inf".to_owned() }
    } else {
        // Debug always has a '.' or an exponent, so TOML reads it as a float.
        format!("{v:?}")
    }
}

/// A short human number for labels: at most 4 decimals, trailing zeros dropped.
fn short(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { &s };
    if s == "-0" { "0".to_owned() } else { s.to_owned() }
}

fn default_label(start: &Pose2<f64>, goal: &Pose2<f64>) -> String {
    format!(
        "({}, {}, {} deg) -> ({}, {}, {} deg)",
        short(start.x),
        short(start.y),
        short(start.theta.to_degrees()),
        short(goal.x),
        short(goal.y),
        short(goal.theta.to_degrees())
    )
}

pub(crate) fn resolve_pose(prefix: &str, p: &PoseFile) -> Result<Pose2<f64>, ScenarioError> {
    let finite = |k: &str, v: Option<f64>| -> Result<f64, ScenarioError> {
        match v {
            None => Ok(0.0),
            Some(v) if v.is_finite() => Ok(v),
            Some(v) => Err(ScenarioError::new(format!("{prefix}.{k}"), format!("must be a finite number (got {v})"))),
        }
    };
    let x = finite("x", p.x)?;
    let y = finite("y", p.y)?;
    let theta = match (p.theta, p.theta_deg) {
        (Some(_), Some(_)) => {
            return Err(ScenarioError::new(
                format!("{prefix}.theta_deg"),
                "give the heading as theta (rad) or theta_deg (degrees), not both",
            ));
        }
        (_, Some(_)) => finite("theta_deg", p.theta_deg)?.to_radians(),
        (theta, None) => finite("theta", theta)?,
    };
    Ok(Pose2::new(x, y, theta))
}

impl ScenarioFile {
    /// Fills the defaults and checks everything by building the core types once.
    /// `default_name` is used when the file has no `name`.
    pub fn resolve(self, default_name: &str) -> Result<Scenario, ScenarioError> {
        let r = &self.robot;
        let d = RobotParams::<f64>::paper();
        let robot = RobotParams {
            mass: r.mass.unwrap_or(d.mass),
            wheel_radius: r.wheel_radius.unwrap_or(d.wheel_radius),
            half_track: r.half_track.unwrap_or(d.half_track),
            com_offset: r.com_offset.unwrap_or(d.com_offset),
            wheel_inertia: r.wheel_inertia.unwrap_or(d.wheel_inertia),
            platform_inertia: r.platform_inertia.unwrap_or(d.platform_inertia),
            gear_ratio: r.gear_ratio.unwrap_or(d.gear_ratio),
            viscous_friction: r.viscous_friction.unwrap_or(d.viscous_friction),
            coulomb_friction: r.coulomb_friction.unwrap_or(d.coulomb_friction),
            coulomb_speed: r.coulomb_speed.unwrap_or(d.coulomb_speed),
        };
        let same = |f: &str| f.to_owned();
        let checked_robot = robot.validate().map_err(|e| ScenarioError::from_param(e, same))?;
        let drive = self.drive.to_params();
        let checked_drive = drive.validate(&checked_robot).map_err(|e| ScenarioError::from_param(e, same))?;
        let controller = self.controller.to_spec(&drive);

        let SimFile { t_end, dt, log_dt } = self.sim;
        let sim = SimSpec::new(
            t_end.unwrap_or(DEFAULT_T_END_S),
            dt.unwrap_or(controller.control_dt()),
            log_dt.unwrap_or(DEFAULT_LOG_DT_S),
        )?;

        let sweep = match &self.sweep {
            Some(sw) => Some(sw.resolve(&drive, &robot, &sim)?),
            None => None,
        };
        if self.run.is_empty() && sweep.is_none() {
            return Err(ScenarioError::new("run", "at least one [[run]] with a goal is required"));
        }
        let mut runs = Vec::with_capacity(self.run.len());
        for (i, RunFile { label, start, goal }) in self.run.into_iter().enumerate() {
            let prefix = format!("run[{i}]");
            let start = resolve_pose(&format!("{prefix}.start"), &start.unwrap_or_default())?;
            let goal = match goal {
                Some(g) => resolve_pose(&format!("{prefix}.goal"), &g)?,
                None => {
                    return Err(ScenarioError::new(format!("{prefix}.goal"), "missing: every [[run]] needs a goal"));
                }
            };
            let rename = |f: &str| match f.strip_prefix("run.") {
                Some(rest) => format!("{prefix}.{rest}"),
                None => f.to_owned(),
            };
            // Build the controller and the loop once: the core's own checks are the truth.
            let ctrl = controller
                .build(&checked_robot, &checked_drive, goal)
                .map_err(|e| ScenarioError::from_param(e, rename))?;
            ClosedLoop::new(checked_robot, checked_drive, ctrl, start, sim.dt)
                .map_err(|e| ScenarioError::from_param(e, rename))?;
            let label = label.unwrap_or_else(|| default_label(&start, &goal));
            runs.push(RunSpec { label, start, goal });
        }
        let name = self.name.unwrap_or_else(|| default_name.to_owned());
        Ok(Scenario { name, robot, drive, controller, sim, runs, sweep })
    }
}

impl Scenario {
    /// Parses and checks TOML text; `default_name` is used when it has no `name`.
    /// Errors name the key and, where it can be found, the line.
    pub fn from_toml_str(text: &str, default_name: &str) -> Result<Self, ScenarioError> {
        let de = toml::de::Deserializer::parse(text).map_err(|e| {
            // A syntax error: toml gives the place; quote the line so the key shows.
            let line = e.span().map(|s| locate::line_of(text, s.start));
            let source = line.and_then(|l| text.lines().nth(l - 1)).map(str::trim).unwrap_or("");
            let quoted: String = source.chars().take(60).collect();
            let msg = if quoted.is_empty() {
                format!("bad TOML: {}", e.message().trim())
            } else {
                format!("bad TOML: {} (in `{quoted}`)", e.message().trim())
            };
            ScenarioError::new("", msg).at_line(line)
        })?;
        let file: ScenarioFile = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            locate::deser_error(&path, inner.message(), inner.span(), Some(text))
        })?;
        file.resolve(default_name).map_err(|e| {
            let line = locate::span_of_key(text, &e.key).map(|s| locate::line_of(text, s.start));
            e.at_line(line)
        })
    }

    /// Parses and checks JSON text (e.g. a Python dict), same keys as the TOML file.
    pub fn from_json_str(text: &str, default_name: &str) -> Result<Self, ScenarioError> {
        let mut de = serde_json::Deserializer::from_str(text);
        let file: ScenarioFile = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            // serde_json appends " at line L column C"; keep the message, drop the place.
            let msg = inner.to_string();
            let msg = msg.rsplit_once(" at line ").map_or(msg.as_str(), |(m, _)| m).to_owned();
            let mut err = locate::deser_error(&path, &msg, None, None);
            if inner.line() > 0 {
                err.line = Some(inner.line());
            }
            err
        })?;
        file.resolve(default_name)
    }

    /// Reads a TOML file; the name defaults to the file's stem. Read errors name the path.
    pub fn from_path(path: impl AsRef<Path>) -> Result<Self, ScenarioError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| ScenarioError::new("", format!("cannot read {}: {e}", path.display())))?;
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scenario".to_owned());
        Self::from_toml_str(&text, &stem)
    }

    /// The closed loop of run `run_index`, at t = 0.
    pub fn closed_loop(&self, run_index: usize) -> Result<ClosedLoop<f64, BuiltController>, ScenarioError> {
        let run = self.runs.get(run_index).ok_or_else(|| {
            ScenarioError::new("run", format!("no run {run_index}: the scenario has {}", self.runs.len()))
        })?;
        let same = |f: &str| f.to_owned();
        let robot = self.robot.validate().map_err(|e| ScenarioError::from_param(e, same))?;
        let drive = self.drive.validate(&robot).map_err(|e| ScenarioError::from_param(e, same))?;
        let rename = |f: &str| match f.strip_prefix("run.") {
            Some(rest) => format!("run[{run_index}].{rest}"),
            None => f.to_owned(),
        };
        let ctrl = self.controller.build(&robot, &drive, run.goal).map_err(|e| ScenarioError::from_param(e, rename))?;
        ClosedLoop::new(robot, drive, ctrl, run.start, self.sim.dt()).map_err(|e| ScenarioError::from_param(e, rename))
    }

    /// Simulates run `run_index` from t = 0 to t_end (or divergence), handing `sink`
    /// the sample at t = 0, every log_dt and the last one. The physics is the core's.
    pub fn run(&self, run_index: usize, sink: impl FnMut(&wmr_core::Sample<f64>)) -> Result<RunResult, ScenarioError> {
        let mut lp = self.closed_loop(run_index)?;
        let outcome = lp.run(self.sim.n_steps(), self.sim.log_every(), sink);
        let label = self.runs.get(run_index).map(|r| r.label.clone()).unwrap_or_default();
        Ok(RunResult::new(run_index, label, outcome))
    }

    /// The scenario as TOML with every default filled in (`wmr-cli check`). Reading it
    /// back gives the same scenario.
    pub fn to_toml(&self) -> String {
        let mut o = String::new();
        let f = toml_f64;
        let _ = writeln!(o, "# Resolved scenario: every key with its value, defaults filled in.");
        let _ = writeln!(o, "name = {}", toml::Value::String(self.name.clone()));
        let r = &self.robot;
        let _ = writeln!(o, "\n[robot]");
        for (k, v) in [
            ("mass", r.mass),
            ("wheel_radius", r.wheel_radius),
            ("half_track", r.half_track),
            ("com_offset", r.com_offset),
            ("wheel_inertia", r.wheel_inertia),
            ("platform_inertia", r.platform_inertia),
            ("gear_ratio", r.gear_ratio),
            ("viscous_friction", r.viscous_friction),
            ("coulomb_friction", r.coulomb_friction),
            ("coulomb_speed", r.coulomb_speed),
        ] {
            let _ = writeln!(o, "{k} = {}", f(v));
        }
        let _ = writeln!(o, "\n[drive]");
        match &self.drive {
            DriveParams::Torque(p) => {
                let _ = writeln!(o, "kind = \"torque\"\nmotor_torque_max = {}", f(p.motor_torque_max));
            }
            DriveParams::DcMotor(p) => {
                let _ = writeln!(
                    o,
                    "kind = \"dc_motor\"\nvoltage_max = {}\ntorque_constant = {}\nback_emf_constant = {}\narmature_resistance = {}",
                    f(p.voltage_max),
                    f(p.torque_constant),
                    f(p.back_emf_constant),
                    f(p.armature_resistance)
                );
            }
        }
        let _ = writeln!(o, "\n[controller]");
        crate::controller::write_toml(&self.controller, &mut o);
        let s = &self.sim;
        let _ = writeln!(o, "\n[sim]\nt_end = {}\ndt = {}\nlog_dt = {}", f(s.t_end), f(s.dt), f(s.log_dt));
        let _ = writeln!(o, "# {} steps and {} samples per run", s.n_steps, s.n_samples());
        for run in &self.runs {
            let pose = |p: &Pose2<f64>| {
                format!(
                    "{{ x = {}, y = {}, theta = {} }}  # {} deg",
                    f(p.x),
                    f(p.y),
                    f(p.theta),
                    short(p.theta.to_degrees())
                )
            };
            let _ = writeln!(o, "\n[[run]]\nlabel = {}", toml::Value::String(run.label.clone()));
            let _ = writeln!(o, "start = {}", pose(&run.start));
            let _ = writeln!(o, "goal = {}", pose(&run.goal));
        }
        if let Some(sweep) = &self.sweep {
            sweep.write_toml(&mut o);
        }
        o
    }
}
