//! The resolved, checked scenario: parsing entry points, validation once, running (to
//! the end, stoppable, as a part of a larger batch) and the TOML dump. Its parts are
//! stored validated and read through accessors. The fast path of its runs is in
//! `fast.rs`, which builds on this one.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use toml::Value;
use wmr_core::rolling_traction::{RollingTraction, TractionWatch};
use wmr_core::{ControllerParams, Drive, OdometryParams, Pose2, Robot, RobotParams, Sample, SensorParams, WorldParams};

use crate::assemble::{self, Origin, RunLoop};

/// The `[robot]` keys that describe how a robot holds the ground: given any of them, a
/// rolling run's summary says when its wheels ask more than mu N ([`RollingTraction`]).
const TRACTION_KEYS: [&str; 3] = ["friction_coefficient", "caster_offset", "com_height"];
use crate::error::ScenarioError;
use crate::file::{RunFile, ScenarioFile, SimFile};
use crate::files::FileAccess;
use crate::keys::{fields_of, fields_read_by, join, to_table, toml_f64, write_keys, write_keys_noted};
use crate::output::{Columns, OdometryDrift, RunResult};
use crate::preset::{self, Origins};
use crate::reference::ReferenceSpec;
use crate::run::{RunSpec, short};
use crate::setup::{BuiltController, Setup, Tables};
use crate::sim::SimSpec;
use crate::sweep::{SweepSpec, SweepTracking};
use crate::{bounds, budget, controller, locate, read};

/// A complete, validated scenario: every default filled in, every key checked once.
/// Two scenarios are equal when they run the same: where a value came from (a preset,
/// the file: [`Scenario::origins`]) and which files it read ([`Scenario::inputs`]) are not
/// compared.
#[derive(Clone, Debug)]
pub struct Scenario {
    name: String,
    setup: Setup,
    sim: SimSpec,
    runs: Vec<RunSpec>,
    sweep: Option<SweepSpec>,
    tracking: Option<Tracking>,
    /// Where the given `[robot]` and `[drive]` values came from (the file, a preset).
    origins: Origins,
    /// The files read besides the scenario's own text (presets, reference CSVs).
    inputs: Vec<InputFile>,
}

/// A file a scenario read besides its own text: a robot preset or a reference CSV.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InputFile {
    /// The path as it was opened: the name written in the scenario joined to the
    /// scenario's folder (relative to the working directory when that folder is).
    pub path: PathBuf,
    /// The key that names it: `robot.from`, `reference.path`, `sweep.references[2].path`.
    pub key: String,
}

/// Adds the files of `read` not listed yet to `inputs`, named by `key`.
fn add_inputs(inputs: &mut Vec<InputFile>, seen: &mut HashSet<PathBuf>, read: Vec<PathBuf>, key: &str) {
    for path in read {
        if seen.insert(path.clone()) {
            inputs.push(InputFile { path, key: key.to_owned() });
        }
    }
}

impl PartialEq for Scenario {
    fn eq(&self, other: &Self) -> bool {
        let Self { name, setup, sim, runs, sweep, tracking, origins: _, inputs: _ } = self;
        (name, setup, sim, runs, sweep, tracking)
            == (&other.name, &other.setup, &other.sim, &other.runs, &other.sweep, &other.tracking)
    }
}

/// Plant steps of all the scenario's runs and sweep runs.
pub fn total_steps(scenario: &Scenario) -> u128 {
    budget::steps(scenario.sim(), scenario.all_runs())
}

/// The moving reference of a tracking scenario and the tolerance its runs are judged with.
#[derive(Clone, Debug, PartialEq)]
pub struct Tracking {
    /// `[reference]`, checked.
    pub reference: ReferenceSpec,
    /// `sim.tracking_tolerance`, m.
    pub tolerance: f64,
}

/// Default `sim.tracking_tolerance`, m.
pub const DEFAULT_TRACKING_TOLERANCE_M: f64 = 0.01;

impl ScenarioFile {
    /// [`ScenarioFile::resolve`] for a file in folder `dir` (where a `[reference]` of kind
    /// `file` finds its CSV, in that folder and below or a folder `access` allows).
    pub fn resolve_in(
        mut self,
        default_name: &str,
        dir: Option<&Path>,
        access: &FileAccess,
    ) -> Result<Scenario, ScenarioError> {
        let (mut inputs, mut seen) = (Vec::new(), HashSet::new());
        let reference = match self.reference.take() {
            Some(t) => {
                let (r, read) = read::recording(|| crate::reference::resolve(&t, dir, access));
                add_inputs(&mut inputs, &mut seen, read, "reference.path");
                Some(r?)
            }
            None => None,
        };
        let tolerance = self.sim.as_ref().and_then(|s| s.tracking_tolerance);
        let tolerance = match tolerance {
            None => DEFAULT_TRACKING_TOLERANCE_M,
            Some(v) if v.is_finite() && v > 0.0 => v,
            Some(v) => {
                return Err(ScenarioError::new(
                    "sim.tracking_tolerance",
                    format!("must be a finite number > 0 (got {v})"),
                ));
            }
        };
        // The references a [sweep] follows: its own list, else the scenario's [reference].
        let sweep_references = match self.sweep.as_mut().and_then(|sw| sw.references.take()) {
            Some(list) if list.is_empty() => {
                return Err(ScenarioError::new("sweep.references", "name at least one reference (or leave it out)"));
            }
            Some(list) => Some({
                // Counted before any is built; a file named by several is read once.
                crate::sweep::check_reference_count(self.sweep.as_ref().expect("a [sweep]"), list.len())?;
                let mut files = crate::reference::PointFiles::default();
                list.iter()
                    .enumerate()
                    .map(|(i, t)| {
                        let (r, read) =
                            read::recording(|| crate::reference::resolve_sharing(t, dir, access, &mut files));
                        add_inputs(&mut inputs, &mut seen, read, &format!("sweep.references[{i}].path"));
                        r.map_err(|e| ScenarioError {
                            key: e.key.replacen("reference", &format!("sweep.references[{i}]"), 1),
                            ..e
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?
            }),
            None if self.sweep.is_some() => reference.clone().map(|r| vec![r]),
            None => None,
        };
        if reference.is_none()
            && sweep_references.is_none()
            && self.sim.as_ref().is_some_and(|s| s.tracking_tolerance.is_some())
        {
            return Err(ScenarioError::new(
                "sim.tracking_tolerance",
                "only a scenario with a [reference] (or a [sweep] with references) tracks",
            ));
        }
        let sweep_tracking = sweep_references.map(|r| SweepTracking::named(r, tolerance));
        let mut runs = std::mem::take(&mut self.run);
        let mut starts_only = Vec::new();
        if reference.is_some() {
            // A tracking run gives its start only: the goal is the reference.
            for (i, r) in runs.iter_mut().enumerate() {
                if r.goal.is_some() {
                    return Err(ScenarioError::new(
                        format!("run[{i}].goal"),
                        "a run of a scenario with a [reference] gives its start only (the reference is the goal)",
                    ));
                }
                starts_only.push(i);
                r.goal = Some(crate::file::PoseFile::default());
            }
        }
        self.run = runs;
        let law_note = if reference.is_some() { self.default_law_for_reference() } else { None };
        let mut scenario = self.resolve_with(default_name, sweep_tracking)?;
        scenario.origins.law_note = law_note;
        if let Some(reference) = reference {
            let start = reference.built.start_pose();
            for i in starts_only {
                let run = &mut scenario.runs[i];
                let label_given = run.label != RunSpec::new(run.start, run.goal).label;
                run.goal = start;
                if !label_given {
                    run.label = format!(
                        "start ({}, {}, {} deg)",
                        short(run.start.x),
                        short(run.start.y),
                        short(run.start.theta.to_degrees())
                    );
                }
            }
            scenario.tracking = Some(Tracking { reference, tolerance });
        }
        scenario.check_references()?;
        crate::reference::check_law(
            &scenario.setup.controller.law,
            scenario.tracking.as_ref().map(|t| &t.reference),
            "controller",
        )?;
        scenario.check_runs()?;
        scenario.inputs = inputs;
        Ok(scenario)
    }

    /// A `[reference]` is followed by a law that follows it: where `[controller]` names no
    /// `kind` (and holds only keys that law reads), the first tracking law of the registry
    /// is written in; `paper`, the default without a reference, holds a point and would be
    /// refused. Returns the note `check` prints beside the kind.
    fn default_law_for_reference(&mut self) -> Option<String> {
        let kind = *crate::controller::tracking_law_kinds().first()?;
        let table = self.controller.get_or_insert_with(toml::Table::new);
        let accepted = crate::controller::controller_keys(kind);
        if table.contains_key("kind") || !table.keys().all(|k| accepted.contains(k)) {
            return None;
        }
        table.insert("kind".to_owned(), toml::Value::String(kind.to_owned()));
        Some("default with a [reference]: a law that follows it".to_owned())
    }

    /// Fills the defaults and checks everything by building the core types once.
    /// `default_name` is used when the file has no `name`.
    pub fn resolve(self, default_name: &str) -> Result<Scenario, ScenarioError> {
        self.resolve_with(default_name, None)
    }

    /// [`ScenarioFile::resolve`] with the references a `[sweep]` follows (checked).
    fn resolve_with(
        self,
        default_name: &str,
        sweep_tracking: Option<SweepTracking>,
    ) -> Result<Scenario, ScenarioError> {
        let tables = Tables {
            robot: self.robot.unwrap_or_default(),
            drive: self.drive.unwrap_or_default(),
            controller: self.controller.unwrap_or_default(),
            sensor: self.sensor,
            world: self.world.unwrap_or_default(),
        };
        let setup = Setup::resolve(&tables, "controller")?;

        let SimFile {
            t_end,
            dt,
            log_dt,
            stop_when_settled,
            early_arrival,
            tracking_tolerance: _,
            xy_goal_tolerance,
            yaw_goal_tolerance_deg,
        } = self.sim.unwrap_or_default();
        if early_arrival == Some(true) && stop_when_settled != Some(true) {
            return Err(ScenarioError::new(
                "sim.early_arrival",
                "is a shorter settle test: it needs stop_when_settled = true beside it",
            ));
        }
        let sim = SimSpec::resolve(t_end, dt, log_dt, setup.controller.control_dt)?
            .with_stop_when_settled(stop_when_settled.unwrap_or(false))
            .with_early_arrival(early_arrival.unwrap_or(false))
            .with_goal_tolerance(xy_goal_tolerance, yaw_goal_tolerance_deg)?;
        setup.check_step(sim.dt())?;

        let sweep = match &self.sweep {
            Some(sw) => Some(SweepSpec::resolve(sw, &tables, &sim, sweep_tracking)?),
            None => None,
        };
        if self.run.is_empty() && sweep.is_none() {
            return Err(ScenarioError::new("run", "at least one [[run]] with a goal is required"));
        }
        let mut runs = Vec::with_capacity(self.run.len());
        for (i, RunFile { label, start, goal }) in self.run.into_iter().enumerate() {
            let path = format!("run[{i}]");
            let start = start.unwrap_or_default().resolve(&join(&path, "start"))?;
            let goal = match goal {
                Some(g) => g.resolve(&join(&path, "goal"))?,
                None => return Err(ScenarioError::new(join(&path, "goal"), "missing: every [[run]] needs a goal")),
            };
            let mut run = RunSpec::new(start, goal);
            if let Some(label) = label {
                run.label = label;
            }
            runs.push(run);
        }
        let name = self.name.unwrap_or_else(|| default_name.to_owned());
        let scenario =
            Scenario { name, setup, sim, runs, sweep, tracking: None, origins: Origins::default(), inputs: Vec::new() };
        scenario.check_runs()?;
        Ok(scenario)
    }
}

impl Scenario {
    /// Parses and checks TOML text; `default_name` is used when it has no `name`.
    /// Errors name the key and, where it can be found, the line. A `[robot] from` path is
    /// relative to the current folder (see [`Scenario::from_toml_str_in`]).
    pub fn from_toml_str(text: &str, default_name: &str) -> Result<Self, ScenarioError> {
        Self::from_toml_str_in(text, default_name, Path::new(""))
    }

    /// [`Scenario::from_toml_str`] of the text of a file in folder `dir`: a `[robot] from`
    /// path (`robots/NAME.toml`) and a `[reference]` of kind `file` are relative to `dir`,
    /// and must lead into it or below (links followed; see [`Scenario::from_toml_str_with`]
    /// to allow other folders).
    pub fn from_toml_str_in(text: &str, default_name: &str, dir: &Path) -> Result<Self, ScenarioError> {
        Self::from_toml_str_with(text, default_name, dir, &FileAccess::default())
    }

    /// [`Scenario::from_toml_str_in`], the files the scenario names read from `dir` and
    /// below and from the folders `access` allows (issue 39 item 14): a file elsewhere is
    /// refused naming its key, before it is opened.
    pub fn from_toml_str_with(
        text: &str,
        default_name: &str,
        dir: &Path,
        access: &FileAccess,
    ) -> Result<Self, ScenarioError> {
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
        let mut file: ScenarioFile = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            locate::deser_error(&path, inner.message(), inner.span(), text)
        })?;
        // The keys the file gives, for `check`'s notes (`# scenario`, `# default`).
        let given: Vec<String> = [
            ("controller", &file.controller),
            ("sensor", &file.sensor),
            ("world", &file.world),
            ("reference", &file.reference),
        ]
        .into_iter()
        .flat_map(|(name, t)| t.iter().flat_map(|t| t.keys()).map(move |k| format!("{name}.{k}")))
        .collect();
        let (origins, presets) = read::recording(|| preset::expand(&mut file.robot, &mut file.drive, dir, access));
        // Kept to name a preset's line when one of its values is refused.
        let preset_origins = origins.as_ref().ok().filter(|o| o.preset.is_some()).cloned();
        origins
            .and_then(|origins| {
                let mut s = file.resolve_in(default_name, Some(dir), access)?;
                s.origins = Origins { given, law_note: s.origins.law_note.take(), ..origins };
                // The preset first, as it was read first.
                let mut inputs = Vec::new();
                add_inputs(&mut inputs, &mut HashSet::new(), presets, "robot.from");
                let own: Vec<InputFile> = std::mem::take(&mut s.inputs);
                let new = |f: &InputFile| !inputs.iter().any(|p: &InputFile| p.path == f.path);
                let own: Vec<InputFile> = own.into_iter().filter(new).collect();
                inputs.extend(own);
                s.inputs = inputs;
                Ok(s)
            })
            .map_err(|e| {
                // A preset's value: said so, at the scenario's `from` line.
                let (e, key) = match preset_origins.as_ref().and_then(|o| o.in_preset(&e)) {
                    Some(located) => (located, Some("robot.from")),
                    None => (e, None),
                };
                let key = key.unwrap_or(&e.key);
                let line = locate::span_of_key(text, key).map(|s| locate::line_of(text, s.start));
                e.at_line(line)
            })
    }

    /// Reads a TOML file (a regular file of at most [`read::MAX_FILE_BYTES`]); the
    /// name defaults to the file's stem. Read errors name the path. The files it names
    /// are read from its folder and below.
    pub fn from_path(path: impl AsRef<Path>) -> Result<Self, ScenarioError> {
        Self::from_path_with(path, &FileAccess::default())
    }

    /// [`Scenario::from_path`], the files it names read from its folder and below and
    /// from the folders `access` allows.
    pub fn from_path_with(path: impl AsRef<Path>, access: &FileAccess) -> Result<Self, ScenarioError> {
        let path = path.as_ref();
        let dir = path.parent().unwrap_or(Path::new(""));
        Self::from_toml_str_with(&read::read_text(path)?, &read::default_name(path), dir, access)
    }

    /// The same scenario with other runs, each checked (Python's batches of starts).
    pub fn with_runs(mut self, runs: Vec<RunSpec>) -> Result<Self, ScenarioError> {
        self.runs = runs;
        self.check_runs()?;
        Ok(self)
    }

    /// The limits every scenario is held to after it is resolved: poses in the box, total
    /// work at most [`budget::MAX_TOTAL_STEPS`].
    fn check_limits(&self) -> Result<(), ScenarioError> {
        bounds::check_runs(&self.runs)?;
        budget::check(&self.sim, self.all_runs(), self.weighted_runs())
    }

    /// [`Self::all_runs`], each weighed by its law's cost per step
    /// ([`wmr_core::LawParams::update_cost`]: an MPPI run at nav2's defaults weighs about
    /// 430 runs of the paper's law).
    fn weighted_runs(&self) -> f64 {
        let own = self.runs.len() as f64 * self.setup.controller.law.update_cost();
        let sweep = self.sweep.as_ref().map_or(0.0, |s| {
            let per_law = (s.len() / s.laws.len().max(1)) as f64;
            s.laws.iter().map(|(_, setup)| setup.controller.law.update_cost() * per_law).sum()
        });
        own + sweep
    }

    /// Runs of `[[run]]` and of `[sweep]` together.
    fn all_runs(&self) -> usize {
        self.runs.len() + self.sweep.as_ref().map_or(0, SweepSpec::len)
    }

    /// What each reference produces over a run (inside the box, finite), by the key
    /// that sets it.
    fn check_references(&self) -> Result<(), ScenarioError> {
        let t_end = self.sim.t_end();
        let is_file = |r: &ReferenceSpec| r.table.get("kind").and_then(Value::as_str) == Some("file");
        if let Some(t) = &self.tracking {
            bounds::check_reference("reference", &t.reference.built, is_file(&t.reference), t_end)?;
        }
        let sweep = self.sweep.as_ref().and_then(|s| s.tracking.as_ref());
        // A sweep without its own `references` follows the [reference] checked above.
        let inherited = |t: &&SweepTracking| matches!((&self.tracking, t.references.as_slice()), (Some(own), [(_, r)]) if *r == own.reference);
        for (i, (_, r)) in sweep.filter(|t| !inherited(t)).into_iter().flat_map(|t| t.references.iter()).enumerate() {
            bounds::check_reference(&format!("sweep.references[{i}]"), &r.built, is_file(r), t_end)?;
        }
        Ok(())
    }

    /// The limits first ([`Self::check_limits`]: building a loop runs the law's first
    /// update, which the step budget bounds), then every run's loop built once: the
    /// core's own checks are the truth.
    fn check_runs(&self) -> Result<(), ScenarioError> {
        self.check_limits()?;
        (0..self.runs.len()).try_for_each(|i| self.closed_loop(i).map(|_| ()))
    }

    /// Name (the `name` key, or the file's stem).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The validated configuration: robot, drive, world, sensor, controller and its model.
    pub fn setup(&self) -> &Setup {
        &self.setup
    }

    /// Where the given `[robot]` and `[drive]` values came from.
    pub fn origins(&self) -> &Origins {
        &self.origins
    }

    /// The files the scenario read besides its own text, each once and with the key that
    /// names it: the robot preset of `[robot] from` (not a built-in one), the CSV of each
    /// `[reference]` and `[sweep] references` entry of kind `file`. A command must not
    /// write over any of them.
    pub fn inputs(&self) -> &[InputFile] {
        &self.inputs
    }

    /// The validated robot (`[robot]`).
    pub fn robot(&self) -> &Robot<f64> {
        &self.setup.robot
    }

    /// The validated drive (`[drive]`).
    pub fn drive(&self) -> &Drive<f64> {
        &self.setup.drive
    }

    /// The controller's parameters (`[controller]`), every default filled in.
    pub fn controller(&self) -> &ControllerParams<f64> {
        &self.setup.controller
    }

    /// The controller built from them, at t = 0 (copy it to run it).
    pub fn built_controller(&self) -> &BuiltController {
        &self.setup.built
    }

    /// `[sim]`.
    pub fn sim(&self) -> &SimSpec {
        &self.sim
    }

    /// `[[run]]`: at least one, unless the file is a sweep.
    pub fn runs(&self) -> &[RunSpec] {
        &self.runs
    }

    /// `[sweep]`, when the file has one (`wmr-cli sweep`).
    pub fn sweep(&self) -> Option<&SweepSpec> {
        self.sweep.as_ref()
    }

    /// The closed loop of run `run_index`, at t = 0.
    pub fn closed_loop(&self, run_index: usize) -> Result<RunLoop, ScenarioError> {
        let run = self.runs.get(run_index).ok_or_else(|| {
            ScenarioError::new("run", format!("no run {run_index}: the scenario has {}", self.runs.len()))
        })?;
        let path = format!("run[{run_index}]");
        let origin = Origin { run: &path, controller: "controller" };
        self.loop_for(run_index as u64, run, origin)
    }

    /// The loop of `run` (noise stream `stream`): towards its goal, or following the
    /// `[reference]` of a tracking scenario.
    fn loop_for(&self, stream: u64, run: &RunSpec, origin: Origin<'_>) -> Result<RunLoop, ScenarioError> {
        match &self.tracking {
            Some(tr) => {
                assemble::closed_loop_to(&self.setup, stream, run.start, tr.reference.built.clone(), &self.sim, origin)
            }
            None => assemble::closed_loop(&self.setup, stream, run.start, run.goal, &self.sim, origin),
        }
    }

    /// The tracking reference and tolerance, for a scenario with a `[reference]`.
    pub fn tracking(&self) -> Option<&Tracking> {
        self.tracking.as_ref()
    }

    /// Runs `lp` to the end (stoppable): a plain run, or a tracking run with its
    /// tracking outcome.
    fn run_to_end<B>(
        &self,
        lp: &mut RunLoop,
        index: usize,
        label: String,
        sink: impl FnMut(&Sample<f64>) -> ControlFlow<B>,
        poll: impl FnMut() -> ControlFlow<B>,
    ) -> ControlFlow<B, RunResult> {
        let sim = self.sim();
        // A rolling run of a robot whose tyre, caster or centre-of-mass height is given
        // (by the scenario or its preset; wmr's defaults describe no real robot): what its
        // wheels ask of the ground, at every logged sample.
        let s = &self.setup;
        let described = TRACTION_KEYS.iter().any(|k| self.origins.of("robot", k) != "default");
        let rolling =
            (described && !lp.plant().slips()).then(|| RollingTraction::new(&s.truth, &s.world, &s.traction_params));
        let mut traction = TractionWatch::default();
        let mut sink = sink;
        let sink = |sample: &Sample<f64>| {
            if let Some(rt) = &rolling {
                traction.observe(sample.t, rt.ratio(&sample.state, sample.torque));
            }
            sink(sample)
        };
        let result = match &self.tracking {
            None => {
                lp.try_run(sim.n_steps(), sim.log_every(), sink, poll).map_continue(|o| RunResult::new(index, label, o))
            }
            Some(tr) => {
                let path = self.setup.controller.law.follows().follows_path();
                crate::tracking_run::run(lp, sim, tr.tolerance, path, sink, poll)
                    .map_continue(|(o, t)| RunResult::new(index, label, o).with_tracking(t))
            }
        };
        result.map_continue(|r| {
            let drift = OdometryDrift::of(lp, &r.outcome);
            r.with_odometry_drift(drift).with_traction(traction).with_collision(&s.obstacles)
        })
    }

    /// Simulates run `run_index` from t = 0 to t_end (or divergence), handing `sink`
    /// the sample at t = 0, every log_dt and the last one. The physics is the core's.
    pub fn run(&self, run_index: usize, sink: impl FnMut(&Sample<f64>)) -> Result<RunResult, ScenarioError> {
        let mut sink = sink;
        match self.try_run(
            run_index,
            |s| {
                sink(s);
                ControlFlow::<std::convert::Infallible>::Continue(())
            },
            || ControlFlow::Continue(()),
        )? {
            ControlFlow::Continue(r) => Ok(r),
            ControlFlow::Break(never) => match never {},
        }
    }

    /// [`Scenario::run`] that may be stopped part-way, by its output (a write failed, the
    /// disk is full) or from outside (Ctrl-C in Python), within about a millisecond of
    /// work ([`wmr_core::closed_loop::POLL_EVERY_STEPS`] plant steps) instead of at the
    /// end: `sink` gets the same samples and may answer [`ControlFlow::Break`]; `poll` is
    /// asked about every millisecond of work whether to go on. `Ok(Break(b))`: stopped with `b`, no result. Run to the end, the
    /// samples and the result are those of [`Scenario::run`], bit for bit.
    pub fn try_run<B>(
        &self,
        run_index: usize,
        sink: impl FnMut(&Sample<f64>) -> ControlFlow<B>,
        poll: impl FnMut() -> ControlFlow<B>,
    ) -> Result<ControlFlow<B, RunResult>, ScenarioError> {
        let mut lp = self.closed_loop(run_index)?;
        let label = self.runs().get(run_index).map(|r| r.label.clone()).unwrap_or_default();
        Ok(self.run_to_end(&mut lp, run_index, label, sink, poll))
    }

    /// [`Scenario::try_run`] of run `run_index` with the sensor noise of run `stream`: the
    /// run as it goes when it is run `stream` of a larger batch that was split into parts.
    /// `try_run_as(i, i as u64, ..)` is `try_run(i, ..)`, bit for bit. A run's result depends
    /// on its index only through the sensor's noise stream and MPPI's (its seed of run
    /// `stream`, [`Setup::controller_for`]), so a part that gives every run
    /// its stream in the whole puts together to the whole, bit for bit (tests/chunk.rs).
    pub fn try_run_as<B>(
        &self,
        run_index: usize,
        stream: u64,
        sink: impl FnMut(&Sample<f64>) -> ControlFlow<B>,
        poll: impl FnMut() -> ControlFlow<B>,
    ) -> Result<ControlFlow<B, RunResult>, ScenarioError> {
        let run = self.runs().get(run_index).ok_or_else(|| {
            ScenarioError::new("run", format!("no run {run_index}: the scenario has {}", self.runs().len()))
        })?;
        let path = format!("run[{run_index}]");
        let origin = Origin { run: &path, controller: "controller" };
        let mut lp = self.loop_for(stream, run, origin)?;
        Ok(self.run_to_end(&mut lp, run_index, run.label.clone(), sink, poll))
    }

    /// The scenario as TOML with every default filled in (`wmr-cli check`). Reading it
    /// back gives the same scenario.
    pub fn to_toml(&self) -> String {
        let mut o = String::new();
        let f = toml_f64;
        let _ = writeln!(o, "# Resolved scenario: every key with its value, defaults filled in.");
        let _ = writeln!(o, "name = {}", Value::String(self.name.clone()));
        let setup = &self.setup;
        // Each robot and drive value with where it came from: the file, a preset, a default.
        let _ = writeln!(o, "\n[robot]");
        // A value fitted by `wmr-cli identify` also shows its standard error and its log.
        let noted = |table: &'static str| {
            move |k: &str| {
                let origin = self.origins.of(table, k);
                Some(self.origins.fitted(table, k).map_or_else(|| origin.to_owned(), |f| format!("{origin}, {f}")))
            }
        };
        write_keys_noted(&mut o, &to_table(setup.robot.params()), fields_of::<RobotParams<f64>>(), noted("robot"));
        if setup.traction_params != wmr_core::TractionParams::default() {
            let order = fields_of::<wmr_core::TractionParams<f64>>();
            write_keys_noted(&mut o, &to_table(&setup.traction_params), order, noted("robot"));
        }
        if !setup.obstacles.is_empty() {
            let _ = writeln!(o, "{} = {}", crate::setup::FOOTPRINT_RADIUS, f(setup.obstacles.footprint_radius()));
        }
        let _ = writeln!(o, "\n[drive]");
        let drive = setup.drive.params();
        let mut order = vec!["kind"];
        order.extend(fields_read_by(|probe| drive.deserialize_variant(probe).map(|_| ())));
        write_keys_noted(&mut o, &to_table(&drive), &order, noted("drive"));
        let _ = writeln!(o, "\n[controller]");
        controller::write_noted(&setup.controller, &drive, setup.model.params(), &mut o, noted("controller"));
        if setup.model != setup.robot {
            let _ = writeln!(o, "\n[controller.model]");
            write_keys(&mut o, &to_table(setup.model.params()), fields_of::<RobotParams<f64>>());
        }
        if setup.has_sensor {
            let _ = writeln!(o, "\n[sensor]");
            write_keys_noted(&mut o, &to_table(&setup.sensor), fields_of::<SensorParams<f64>>(), noted("sensor"));
            write_keys_noted(&mut o, &to_table(&setup.pose), fields_of::<OdometryParams<f64>>(), noted("sensor"));
        }
        let _ = writeln!(o, "\n[world]");
        write_keys_noted(&mut o, &to_table(setup.world.params()), fields_of::<WorldParams<f64>>(), noted("world"));
        if setup.payload.is_some() {
            let _ = writeln!(o, "\n[world.payload]");
            write_keys(&mut o, &to_table(setup.payload.params()), fields_of::<wmr_core::PayloadParams<f64>>());
        }
        for p in setup.pushes.as_slice() {
            let _ = writeln!(
                o,
                "\n[[world.push]]\nt = {}\nduration = {}\nforce = {{ x = {}, y = {} }}\ntorque = {}",
                f(p.t),
                f(p.duration),
                f(p.force_x),
                f(p.force_y),
                f(p.torque)
            );
        }
        // Circles first, then polygons: the numbering of `collided ... with obstacle i`.
        for ob in setup.obstacles.iter() {
            let _ = match ob {
                wmr_core::Obstacle::Circle { center: (x, y), radius } => writeln!(
                    o,
                    "\n[[world.obstacle]]\nkind = \"circle\"\ncenter = {{ x = {}, y = {} }}\nradius = {}",
                    f(x),
                    f(y),
                    f(radius)
                ),
                wmr_core::Obstacle::Polygon(points) => {
                    let points: Vec<String> = points.iter().map(|&(x, y)| format!("[{}, {}]", f(x), f(y))).collect();
                    writeln!(o, "\n[[world.obstacle]]\nkind = \"polygon\"\npoints = [{}]", points.join(", "))
                }
            };
        }
        if let Some(tr) = &self.tracking {
            let _ = writeln!(o, "\n[reference]");
            let (table, order) = crate::reference::filled(&tr.reference);
            write_keys_noted(&mut o, &table, &order, noted("reference"));
        }
        let s = &self.sim;
        let _ = writeln!(
            o,
            "\n[sim]\nt_end = {}\ndt = {}\nlog_dt = {}\nstop_when_settled = {}",
            f(s.t_end()),
            f(s.dt()),
            f(s.log_dt()),
            s.stop_when_settled()
        );
        if s.early_arrival() {
            let _ = writeln!(o, "early_arrival = true");
        }
        if s.xy_goal_tolerance() != wmr_core::XY_GOAL_TOLERANCE_M {
            let _ = writeln!(o, "xy_goal_tolerance = {}", f(s.xy_goal_tolerance()));
        }
        if s.yaw_goal_tolerance_deg() != wmr_core::YAW_GOAL_TOLERANCE_DEG {
            let _ = writeln!(o, "yaw_goal_tolerance_deg = {}", f(s.yaw_goal_tolerance_deg()));
        }
        let tolerance = self
            .tracking
            .as_ref()
            .map(|t| t.tolerance)
            .or_else(|| self.sweep.as_ref().and_then(|s| s.tracking.as_ref()).map(|t| t.tolerance));
        if let Some(tol) = tolerance {
            let _ = writeln!(o, "tracking_tolerance = {}", f(tol));
        }
        let _ = writeln!(o, "# {} steps and {} samples per run", s.n_steps(), s.n_samples());
        if let Some((n, x)) = setup.slip_substeps(s.dt()) {
            // Derived, not a key: the slip plant splits each step its contacts are too
            // stiff for (wmr_core::Plant::substeps).
            let _ = writeln!(
                o,
                "# derived: the slip plant takes {n} RK4 sub-step{} per dt (dt * stiffness = {x:.3}; \
                 1 below 2.785, else ceil(dt * stiffness / (0.9 x 2.785)))",
                if n == 1 { "" } else { "s" }
            );
        }
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
            let _ = writeln!(o, "\n[[run]]\nlabel = {}", Value::String(run.label.clone()));
            let _ = writeln!(o, "start = {}", pose(&run.start));
            if self.tracking.is_none() {
                let _ = writeln!(o, "goal = {}", pose(&run.goal));
            }
        }
        if let Some(sweep) = &self.sweep {
            sweep.write_toml(&mut o);
        }
        o
    }
}

impl Columns {
    /// The columns of `scenario`'s runs. Here, not in `output`: the output layer knows
    /// the columns, not the scenario they are chosen from.
    pub fn of(scenario: &Scenario) -> Self {
        let setup = scenario.setup();
        Self {
            measured: setup.has_sensor,
            odometry: setup.odometry(),
            contact: setup.slips(),
            reference: scenario.tracking().map(|t| t.reference.built.clone()),
            command: scenario.controller().law.twist_demand(),
            disturbance: scenario.controller().observer.is_some(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 39 item 2: a sweep naming one reference CSV in many references read it once
    /// per use (1,000 uses of a 16 MiB file took a minute); now once per sweep.
    #[test]
    fn regression_39_2_a_reference_file_is_read_once_per_sweep() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("ref.csv"), "t,x,y\n0,0,0\n1,0.3,0\n2,0.6,0.1\n").unwrap();
        let uses = vec!["{ kind = \"file\", path = \"ref.csv\" }"; 50].join(", ");
        let text = format!(
            "[sim]\nt_end = 0.1\n[sweep]\ncontrollers = [{{ kind = \"kanayama\" }}]\nreferences = [{{ kind = \"circle\" }}, \
             {uses}]\nrandom = {{ n = 1, radius = 0.1 }}\n"
        );
        let (sc, read) = read::recording(|| Scenario::from_toml_str_in(&text, "s", dir.path()));
        let sc = sc.unwrap();
        assert_eq!(read, [dir.path().join("ref.csv")], "read once");
        let names: Vec<&str> =
            sc.sweep().unwrap().tracking.as_ref().unwrap().references.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names[..3], ["circle", "file", "file#2"]);
        assert_eq!(names[50], "file#50");
        assert_eq!(sc.inputs().len(), 1);
        assert_eq!(sc.inputs()[0].key, "sweep.references[1].path");
    }
}
