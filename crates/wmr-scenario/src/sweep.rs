//! Sweeps (`[sweep]`): many starts, several laws, one outcome per (law, start), run in
//! parallel (rayon, one run per task) with results in a fixed order.
//!
//! ```toml
//! [sweep]
//! goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
//! controllers = [{ kind = "paper" }, { kind = "polar" }, { kind = "lyapunov", h = 9.0 }]
//! # exactly one of:
//! grid = { x_min = -2.0, x_max = 2.0, nx = 21, y_min = -2.0, y_max = 2.0, ny = 21, theta_deg = [0.0] }
//! random = { n = 1000, seed = 1, radius = 2.0, min_radius = 0.1 }
//! ```
//!
//! Each entry of `controllers` takes the keys of `[controller]` for its kind; absent, all
//! three laws run with their defaults. Random starts are uniform over the annulus
//! `min_radius <= |C - goal| <= radius` with a uniform heading in [-180, 180) deg, drawn
//! from `fastrand`'s generator seeded with `seed` (the same file gives the same starts).

use rayon::prelude::*;
use serde::Deserialize;
use wmr_core::metrics::ARRIVAL_RADIUS_M;
use wmr_core::{ClosedLoop, DriveParams, Outcome, Pose2, Robot, RobotParams};

use crate::controller::{ControllerFile, ControllerSpec};
use crate::error::ScenarioError;
use crate::file::PoseFile;
use crate::scenario::{SimSpec, resolve_pose};

/// Most (law, start) runs one sweep may hold.
pub const MAX_SWEEP_RUNS: usize = 1_000_000;

/// `[sweep]` as written.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Goal pose of C; default (0, 0, 0).
    pub goal: Option<PoseFile>,
    /// The laws to compare; default: paper, polar and lyapunov with their defaults.
    pub controllers: Option<Vec<ControllerFile>>,
    /// A grid of starts.
    pub grid: Option<GridFile>,
    /// Seeded random starts.
    pub random: Option<RandomFile>,
}

/// `grid = { ... }`: starts on a rectangular grid, every heading in `theta_deg`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // documented in the module docs and docs/scenario.md
pub struct GridFile {
    pub x_min: f64,
    pub x_max: f64,
    pub nx: u32,
    pub y_min: f64,
    pub y_max: f64,
    pub ny: u32,
    #[serde(default)]
    pub theta_deg: Option<Vec<f64>>,
}

/// `random = { ... }`: seeded random starts around the goal.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // documented in the module docs and docs/scenario.md
pub struct RandomFile {
    pub n: u32,
    #[serde(default)]
    pub seed: u64,
    pub radius: f64,
    #[serde(default)]
    pub min_radius: f64,
}

/// A checked sweep: the goal, the laws (with their names) and every start.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// Goal pose of C: m, m, rad.
    pub goal: Pose2<f64>,
    /// The laws, in file order, and a unique name for each (`kind`, or `kind#2` ...).
    pub laws: Vec<(String, ControllerSpec)>,
    /// Start poses of C: m, m, rad.
    pub starts: Vec<Pose2<f64>>,
    /// Where the starts come from, every default filled in (written back by `to_toml`).
    pub source: StartsSource,
}

/// The `grid` or `random` table a sweep's starts were drawn from, defaults filled in.
#[derive(Clone, Debug, PartialEq)]
pub enum StartsSource {
    /// `grid = { ... }`.
    Grid(GridFile),
    /// `random = { ... }`.
    Random(RandomFile),
}

fn finite_key(key: &str, v: f64) -> Result<f64, ScenarioError> {
    if v.is_finite() { Ok(v) } else { Err(ScenarioError::new(key, format!("must be a finite number (got {v})"))) }
}

impl SweepFile {
    /// Checks the table and draws the starts; controllers are validated for the goal.
    pub(crate) fn resolve(
        &self,
        drive: &DriveParams<f64>,
        robot: &RobotParams<f64>,
        sim: &SimSpec,
    ) -> Result<SweepSpec, ScenarioError> {
        let goal = resolve_pose("sweep.goal", &self.goal.clone().unwrap_or_default())?;
        let files = match &self.controllers {
            Some(v) if v.is_empty() => return Err(ScenarioError::new("sweep.controllers", "name at least one law")),
            Some(v) => v.clone(),
            None => crate::controller::CONTROLLER_KINDS
                .iter()
                .map(|k| ControllerFile::default_of(k))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| ScenarioError::new("sweep.controllers", "internal: unknown default kind"))?,
        };
        let checked_robot = robot.validate().map_err(|e| ScenarioError::from_param(e, |f| f.to_owned()))?;
        let checked_drive =
            drive.validate(&checked_robot).map_err(|e| ScenarioError::from_param(e, |f| f.to_owned()))?;
        let mut laws: Vec<(String, ControllerSpec)> = Vec::with_capacity(files.len());
        for (i, f) in files.iter().enumerate() {
            let spec = f.to_spec(drive);
            let rename = |field: &str| match field.strip_prefix("controller.") {
                Some(rest) => format!("sweep.controllers[{i}].{rest}"),
                None => field.replacen("run.goal", "sweep.goal", 1),
            };
            let ctrl =
                spec.build(&checked_robot, &checked_drive, goal).map_err(|e| ScenarioError::from_param(e, rename))?;
            ClosedLoop::new(checked_robot, checked_drive, ctrl, goal, sim.dt())
                .map_err(|e| ScenarioError::from_param(e, rename))?;
            let kind = spec.kind().name();
            let same = laws.iter().filter(|(_, s)| s.kind().name() == kind).count();
            let name = if same == 0 { kind.to_owned() } else { format!("{kind}#{}", same + 1) };
            laws.push((name, spec));
        }
        let (starts, source) = match (&self.grid, &self.random) {
            (Some(g), None) => {
                let g = GridFile { theta_deg: Some(g.theta_deg.clone().unwrap_or_else(|| vec![0.0])), ..g.clone() };
                (grid_starts(&g)?, StartsSource::Grid(g))
            }
            (None, Some(r)) => (random_starts(r, goal)?, StartsSource::Random(r.clone())),
            (Some(_), Some(_)) => {
                return Err(ScenarioError::new("sweep.random", "give either grid or random, not both"));
            }
            (None, None) => {
                return Err(ScenarioError::new("sweep", "missing the starts: give a grid or a random table"));
            }
        };
        if starts.len().saturating_mul(laws.len()) > MAX_SWEEP_RUNS {
            return Err(ScenarioError::new(
                "sweep",
                format!("{} starts x {} laws is more than {MAX_SWEEP_RUNS} runs", starts.len(), laws.len()),
            ));
        }
        Ok(SweepSpec { goal, laws, starts, source })
    }
}

fn grid_starts(g: &GridFile) -> Result<Vec<Pose2<f64>>, ScenarioError> {
    let x_min = finite_key("sweep.grid.x_min", g.x_min)?;
    let x_max = finite_key("sweep.grid.x_max", g.x_max)?;
    let y_min = finite_key("sweep.grid.y_min", g.y_min)?;
    let y_max = finite_key("sweep.grid.y_max", g.y_max)?;
    if g.nx == 0 {
        return Err(ScenarioError::new("sweep.grid.nx", "must be >= 1"));
    }
    if g.ny == 0 {
        return Err(ScenarioError::new("sweep.grid.ny", "must be >= 1"));
    }
    if x_max < x_min {
        return Err(ScenarioError::new("sweep.grid.x_max", "must be >= x_min"));
    }
    if y_max < y_min {
        return Err(ScenarioError::new("sweep.grid.y_max", "must be >= y_min"));
    }
    let thetas = g.theta_deg.clone().unwrap_or_else(|| vec![0.0]);
    if thetas.is_empty() {
        return Err(ScenarioError::new("sweep.grid.theta_deg", "give at least one heading"));
    }
    for (i, t) in thetas.iter().enumerate() {
        finite_key(&format!("sweep.grid.theta_deg[{i}]"), *t)?;
    }
    let at = |lo: f64, hi: f64, n: u32, i: u32| {
        if n == 1 { 0.5 * (lo + hi) } else { lo + (hi - lo) * f64::from(i) / f64::from(n - 1) }
    };
    let total = u64::from(g.nx) * u64::from(g.ny) * thetas.len() as u64;
    if total > MAX_SWEEP_RUNS as u64 {
        return Err(ScenarioError::new("sweep.grid", format!("{total} starts is more than {MAX_SWEEP_RUNS}")));
    }
    let mut starts = Vec::new();
    for j in 0..g.ny {
        for i in 0..g.nx {
            for t in &thetas {
                starts.push(Pose2::new(at(x_min, x_max, g.nx, i), at(y_min, y_max, g.ny, j), t.to_radians()));
            }
        }
    }
    Ok(starts)
}

fn random_starts(r: &RandomFile, goal: Pose2<f64>) -> Result<Vec<Pose2<f64>>, ScenarioError> {
    let radius = finite_key("sweep.random.radius", r.radius)?;
    let min_radius = finite_key("sweep.random.min_radius", r.min_radius)?;
    if radius <= 0.0 {
        return Err(ScenarioError::new("sweep.random.radius", format!("must be > 0 (got {radius})")));
    }
    if !(0.0..=radius).contains(&min_radius) {
        return Err(ScenarioError::new(
            "sweep.random.min_radius",
            format!("must be in [0, radius] (got {min_radius})"),
        ));
    }
    if r.n == 0 || r.n as usize > MAX_SWEEP_RUNS {
        return Err(ScenarioError::new("sweep.random.n", format!("must be in 1..={MAX_SWEEP_RUNS} (got {})", r.n)));
    }
    let mut rng = fastrand::Rng::with_seed(r.seed);
    let tau = std::f64::consts::TAU;
    let (a2, b2) = (min_radius * min_radius, radius * radius);
    Ok((0..r.n)
        .map(|_| {
            // Uniform over the annulus: r^2 uniform between the radii squared.
            let rho = (a2 + (b2 - a2) * rng.f64()).sqrt();
            let phi = tau * rng.f64();
            let theta = tau * rng.f64() - std::f64::consts::PI;
            Pose2::new(goal.x + rho * phi.cos(), goal.y + rho * phi.sin(), theta)
        })
        .collect())
}

impl SweepSpec {
    /// The `[sweep]` table in TOML, every key written; reads back to the same sweep.
    pub(crate) fn write_toml(&self, out: &mut String) {
        use std::fmt::Write as _;
        let f = crate::scenario::toml_f64;
        let g = &self.goal;
        let _ = writeln!(out, "\n[sweep]\ngoal = {{ x = {}, y = {}, theta = {} }}", f(g.x), f(g.y), f(g.theta));
        let _ = writeln!(out, "controllers = [");
        for (_, spec) in &self.laws {
            let mut table = String::new();
            crate::controller::write_toml(spec, &mut table);
            let _ = writeln!(out, "  {{ {} }},", table.lines().collect::<Vec<_>>().join(", "));
        }
        let _ = writeln!(out, "]");
        match &self.source {
            StartsSource::Grid(g) => {
                let thetas: Vec<String> = g.theta_deg.iter().flatten().map(|t| f(*t)).collect();
                let _ = writeln!(
                    out,
                    "grid = {{ x_min = {}, x_max = {}, nx = {}, y_min = {}, y_max = {}, ny = {}, theta_deg = [{}] }}",
                    f(g.x_min),
                    f(g.x_max),
                    g.nx,
                    f(g.y_min),
                    f(g.y_max),
                    g.ny,
                    thetas.join(", ")
                );
            }
            StartsSource::Random(r) => {
                let _ = writeln!(
                    out,
                    "random = {{ n = {}, seed = {}, radius = {}, min_radius = {} }}",
                    r.n,
                    r.seed,
                    f(r.radius),
                    f(r.min_radius)
                );
            }
        }
        let _ = writeln!(out, "# {} laws x {} starts = {} runs", self.laws.len(), self.starts.len(), self.len());
    }
}

/// The outcome of one (law, start) run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepOutcome {
    /// Index into [`SweepSpec::laws`].
    pub law: usize,
    /// Index into [`SweepSpec::starts`].
    pub start_index: usize,
    /// Start pose of C.
    pub start: Pose2<f64>,
    /// The core's outcome.
    pub outcome: Outcome<f64>,
}

impl SweepOutcome {
    /// Not diverged and final dl below 1 cm (as [`crate::RunResult::converged`]).
    pub fn converged(&self) -> bool {
        !self.outcome.termination.diverged() && self.outcome.final_dl < ARRIVAL_RADIUS_M
    }

    /// `"converged"`, `"diverged"` or `"not converged"`.
    pub fn status(&self) -> &'static str {
        if self.outcome.termination.diverged() {
            "diverged"
        } else if self.converged() {
            "converged"
        } else {
            "not converged"
        }
    }
}

/// Columns of the sweep CSV, in order.
pub const SWEEP_COLUMNS: [&str; 12] = [
    "law",
    "start",
    "x0",
    "y0",
    "theta0_deg",
    "status",
    "time_to_1cm_s",
    "final_dl_m",
    "final_heading_error_deg",
    "peak_wheel_speed_rad_s",
    "path_length_m",
    "energy_j",
];

impl SweepSpec {
    /// Number of (law, start) runs.
    pub fn len(&self) -> usize {
        self.laws.len() * self.starts.len()
    }

    /// True when there is nothing to run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Runs every (law, start) pair in parallel; `done` is called once per finished run
    /// (from worker threads). Results are ordered by law, then start.
    pub fn run(
        &self,
        robot: &RobotParams<f64>,
        drive: &DriveParams<f64>,
        sim: &SimSpec,
        done: &(dyn Fn() + Sync),
    ) -> Result<Vec<SweepOutcome>, ScenarioError> {
        let same = |f: &str| f.to_owned();
        let robot: Robot<f64> = robot.validate().map_err(|e| ScenarioError::from_param(e, same))?;
        let drive = drive.validate(&robot).map_err(|e| ScenarioError::from_param(e, same))?;
        let n_starts = self.starts.len();
        (0..self.len())
            .into_par_iter()
            .map(|k| {
                let (law, start_index) = (k / n_starts, k % n_starts);
                let start = self.starts[start_index];
                let rename = |f: &str| f.to_owned();
                let ctrl = self.laws[law]
                    .1
                    .build(&robot, &drive, self.goal)
                    .map_err(|e| ScenarioError::from_param(e, rename))?;
                let mut sim_loop = ClosedLoop::new(robot, drive, ctrl, start, sim.dt())
                    .map_err(|e| ScenarioError::from_param(e, rename))?;
                let outcome = sim_loop.run(sim.n_steps(), u32::MAX, |_| {});
                done();
                Ok(SweepOutcome { law, start_index, start, outcome })
            })
            .collect()
    }
}

/// One CSV row of a sweep outcome, as strings in [`SWEEP_COLUMNS`] order.
pub fn sweep_row(spec: &SweepSpec, o: &SweepOutcome) -> [String; 12] {
    let out = &o.outcome;
    [
        spec.laws[o.law].0.clone(),
        o.start_index.to_string(),
        o.start.x.to_string(),
        o.start.y.to_string(),
        o.start.theta.to_degrees().to_string(),
        o.status().to_owned(),
        out.time_to_arrival.map(|t| t.to_string()).unwrap_or_default(),
        out.final_dl.to_string(),
        out.final_heading_error.to_degrees().to_string(),
        out.peak_wheel_speed.to_string(),
        out.path_length.to_string(),
        out.energy.to_string(),
    ]
}

/// Median and worst of one figure over a law's runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// Median (NaN when no run counts).
    pub median: f64,
    /// Worst: the largest value (NaN when no run counts).
    pub worst: f64,
}

fn spread(mut v: Vec<f64>) -> Spread {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return Spread { median: f64::NAN, worst: f64::NAN };
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) };
    Spread { median, worst: v[n - 1] }
}

/// Comparison of one law over all starts. Figures other than the shares are taken over
/// the converged runs only (a diverged run has no meaningful time or heading error).
#[derive(Clone, Debug, PartialEq)]
pub struct LawSummary {
    /// The law's name.
    pub name: String,
    /// Runs.
    pub n: usize,
    /// Share of runs that converged (0..1).
    pub converged: f64,
    /// Share of runs that diverged (0..1).
    pub diverged: f64,
    /// Time to 1 cm, s.
    pub time_to_1cm: Spread,
    /// |final heading error|, deg.
    pub heading_error_deg: Spread,
    /// Peak wheel speed, rad/s.
    pub peak_wheel_speed: Spread,
    /// Path length, m.
    pub path_length: Spread,
    /// Drive energy, J.
    pub energy: Spread,
}

/// Per-law comparison of sweep outcomes, in law order.
pub fn summarize(spec: &SweepSpec, outcomes: &[SweepOutcome]) -> Vec<LawSummary> {
    spec.laws
        .iter()
        .enumerate()
        .map(|(i, (name, _))| {
            let runs: Vec<&SweepOutcome> = outcomes.iter().filter(|o| o.law == i).collect();
            let ok: Vec<&SweepOutcome> = runs.iter().copied().filter(|o| o.converged()).collect();
            let n = runs.len().max(1) as f64;
            let over = |f: fn(&Outcome<f64>) -> f64| spread(ok.iter().map(|o| f(&o.outcome)).collect());
            LawSummary {
                name: name.clone(),
                n: runs.len(),
                converged: ok.len() as f64 / n,
                diverged: runs.iter().filter(|o| o.outcome.termination.diverged()).count() as f64 / n,
                time_to_1cm: over(|o| o.time_to_arrival.unwrap_or(f64::NAN)),
                heading_error_deg: over(|o| o.final_heading_error.to_degrees().abs()),
                peak_wheel_speed: over(|o| o.peak_wheel_speed),
                path_length: over(|o| o.path_length),
                energy: over(|o| o.energy),
            }
        })
        .collect()
}

/// The comparison table as aligned text, one line per law ("median / worst").
pub fn summary_table(rows: &[LawSummary]) -> String {
    let fmt = |s: Spread, prec: usize| {
        if s.median.is_nan() { "-".to_owned() } else { format!("{:.p$} / {:.p$}", s.median, s.worst, p = prec) }
    };
    let mut out = format!(
        "{:<12} {:>6} {:>10} {:>9} {:>17} {:>17} {:>17} {:>15} {:>17}\n",
        "law", "runs", "converged", "diverged", "t_1cm s (med/max)", "|e_th| deg", "peak w rad/s", "path m", "energy J"
    );
    for r in rows {
        out.push_str(&format!(
            "{:<12} {:>6} {:>9.1}% {:>8.1}% {:>17} {:>17} {:>17} {:>15} {:>17}\n",
            r.name,
            r.n,
            100.0 * r.converged,
            100.0 * r.diverged,
            fmt(r.time_to_1cm, 2),
            fmt(r.heading_error_deg, 2),
            fmt(r.peak_wheel_speed, 1),
            fmt(r.path_length, 2),
            fmt(r.energy, 1),
        ));
    }
    out
}
