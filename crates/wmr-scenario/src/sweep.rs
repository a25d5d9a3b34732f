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
//! Each entry of `controllers` takes the keys of `[controller]` for its kind; absent, every
//! law runs with its defaults. Random starts are uniform over the annulus
//! `min_radius <= |C - goal| <= radius` with a uniform heading in [-180, 180) deg, drawn
//! from `fastrand`'s generator seeded with `seed` (the same file gives the same starts).

use std::ops::{ControlFlow, Range};

use toml::{Table, Value};
use wmr_core::plant::DIVERGENCE_BOX_M;
use wmr_core::{Outcome, Pose2, Status};

use crate::assemble::{self, Origin};
use crate::bounds::check_in_box;
use crate::budget::MAX_SWEEP_RUNS;
use crate::controller::{self as controller_table, law_kinds};
use crate::error::{ScenarioError, num};
use crate::executor::map_ordered;
use crate::file::{GridFile, RandomFile, SweepFile};
use crate::setup::{Setup, Tables};
use crate::sim::SimSpec;
use crate::vary::{Variant, Variation};

/// A checked sweep: the goal, the laws (with their names) and every start.
#[derive(Clone, Debug)]
pub struct SweepSpec {
    /// Goal pose of C: m, m, rad.
    pub goal: Pose2<f64>,
    /// The laws, in file order: a unique name for each (`kind`, or `kind#2` ...) and its
    /// nominal configuration (the scenario's robot, drive, sensor and world, the law's
    /// controller table).
    pub laws: Vec<(String, Setup)>,
    /// Each law's tables, from which varied runs are resolved.
    pub tables: Vec<Tables>,
    /// The varied keys (`vary`), the trials and the seed of the draws.
    pub variation: Variation,
    /// The variants of [`Variation::variants`], in order.
    pub variants: Vec<Variant>,
    /// The configuration of each (law, variant), index law * variants + variant.
    pub setups: Vec<Setup>,
    /// Start poses of C: m, m, rad.
    pub starts: Vec<Pose2<f64>>,
    /// Where the starts come from, every default filled in (written back by `to_toml`).
    pub source: StartsSource,
}

/// Two sweeps are equal when they run the same: the tables as written may differ.
impl PartialEq for SweepSpec {
    fn eq(&self, other: &Self) -> bool {
        (&self.goal, &self.laws, &self.variation, &self.variants, &self.setups, &self.starts, &self.source)
            == (
                &other.goal,
                &other.laws,
                &other.variation,
                &other.variants,
                &other.setups,
                &other.starts,
                &other.source,
            )
    }
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

impl SweepSpec {
    /// Checks a `[sweep]` table and draws the starts; every law is validated, for every
    /// variant, with the scenario's tables (`base`) and its own controller table, and its
    /// loop assembled towards the goal.
    pub(crate) fn resolve(sw: &SweepFile, base: &Tables, sim: &SimSpec) -> Result<Self, ScenarioError> {
        let goal = sw.goal.clone().unwrap_or_default().resolve("sweep.goal")?;
        check_in_box("sweep.goal", goal)?;
        let controllers: Vec<Table> = match &sw.controllers {
            Some(v) if v.is_empty() => return Err(ScenarioError::new("sweep.controllers", "name at least one law")),
            Some(v) => v.clone(),
            None => law_kinds()
                .into_iter()
                .map(|k| Table::from_iter([("kind".to_owned(), Value::String(k.to_owned()))]))
                .collect(),
        };
        let variation =
            Variation::resolve(sw.vary.as_deref().unwrap_or_default(), sw.seed.unwrap_or(0), sw.trials.unwrap_or(1))?;
        let variants = variation.variants();
        let mut laws: Vec<(String, Setup)> = Vec::with_capacity(controllers.len());
        let mut tables = Vec::with_capacity(controllers.len());
        let mut setups = Vec::with_capacity(controllers.len() * variants.len());
        for (i, controller) in controllers.into_iter().enumerate() {
            let path = format!("sweep.controllers[{i}]");
            let mut t = Tables { controller, ..base.clone() };
            // A law without its own model takes the scenario's [controller.model].
            if let (None, Some(model)) = (t.controller.get("model"), base.controller.get("model")) {
                t.controller.insert("model".to_owned(), model.clone());
            }
            let setup = check_setup(&t, &path, sim, goal, None)?;
            for v in &variants {
                let vt = with_settings(&t, &variation.settings(*v, 0))?;
                let blame = v.map(|(k, x)| (format!("sweep.vary[{k}]"), format!("{} = {x}", variation.keys[k].key)));
                setups.push(check_setup(&vt, &path, sim, goal, blame)?);
            }
            if variation.has_draws() {
                // The draws of the first run, as a sample of what the distributions give.
                let blame = Some(("sweep.vary".to_owned(), "a drawn value".to_owned()));
                check_setup(&with_settings(&t, &variation.settings(None, 0))?, &path, sim, goal, blame)?;
            }
            let kind = setup.controller.law.kind();
            let same = laws.iter().filter(|(_, s)| s.controller.law.kind() == kind).count();
            let name = if same == 0 { kind.to_owned() } else { format!("{kind}#{}", same + 1) };
            laws.push((name, setup));
            tables.push(t);
        }
        let (starts, source) = match (&sw.grid, &sw.random) {
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
        let runs = starts
            .len()
            .saturating_mul(laws.len())
            .saturating_mul(variants.len())
            .saturating_mul(variation.trials as usize);
        if runs > MAX_SWEEP_RUNS {
            return Err(ScenarioError::new(
                "sweep",
                format!(
                    "{} starts x {} laws x {} variants x {} trials is more than {MAX_SWEEP_RUNS} runs",
                    starts.len(),
                    laws.len(),
                    variants.len(),
                    variation.trials
                ),
            ));
        }
        Ok(SweepSpec { goal, laws, tables, variation, variants, setups, starts, source })
    }
}

/// `t` with every (key, value) of `settings` set.
fn with_settings(t: &Tables, settings: &[(&str, Value)]) -> Result<Tables, ScenarioError> {
    let mut t = t.clone();
    for (k, v) in settings {
        t.set(k, v.clone())?;
    }
    Ok(t)
}

/// Resolves `t` and assembles its loop at the goal, so every check a run makes is made
/// now. With `blame` (the `vary` entry's key path and the value it set), an error names
/// that entry, which is what the file says, and quotes the key and reason inside.
fn check_setup(
    t: &Tables,
    path: &str,
    sim: &SimSpec,
    goal: Pose2<f64>,
    blame: Option<(String, String)>,
) -> Result<Setup, ScenarioError> {
    let prefix = |e: ScenarioError| match &blame {
        None => e,
        Some((key, what)) => ScenarioError::new(key, format!("{what}: {}: {}", e.key, e.message)),
    };
    let setup = Setup::resolve(t, path).map_err(prefix)?;
    setup.check_step(sim.dt()).map_err(prefix)?;
    assemble::closed_loop(&setup, 0, goal, goal, sim, Origin { run: "sweep", controller: path }).map_err(prefix)?;
    Ok(setup)
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
    let thetas = g.theta_deg.clone().unwrap_or_else(|| vec![0.0]);
    if thetas.is_empty() {
        return Err(ScenarioError::new("sweep.grid.theta_deg", "give at least one heading"));
    }
    // Counted in u128: nx * ny * headings cannot wrap (each factor is below 2^32 or a
    // length), and nothing is allocated before the count is known to be allowed.
    let total = u128::from(g.nx) * u128::from(g.ny) * thetas.len() as u128;
    if total > MAX_SWEEP_RUNS as u128 {
        return Err(ScenarioError::new(
            "sweep.grid",
            format!(
                "nx x ny x headings = {} x {} x {} = {total} starts, more than the limit of {MAX_SWEEP_RUNS}",
                g.nx,
                g.ny,
                thetas.len()
            ),
        ));
    }
    if x_max < x_min {
        return Err(ScenarioError::new(
            "sweep.grid.x_max",
            format!("must be >= x_min = {} (got {})", num(x_min), num(x_max)),
        ));
    }
    if y_max < y_min {
        return Err(ScenarioError::new(
            "sweep.grid.y_max",
            format!("must be >= y_min = {} (got {})", num(y_min), num(y_max)),
        ));
    }
    // Every start inside the box (so hi - lo below cannot overflow either).
    for (key, v) in [("x_min", x_min), ("x_max", x_max), ("y_min", y_min), ("y_max", y_max)] {
        check_in_box("sweep.grid", Pose2::new(v, 0.0, 0.0))
            .map_err(|e| ScenarioError { key: format!("sweep.grid.{key}"), ..e })?;
    }
    for (i, t) in thetas.iter().enumerate() {
        finite_key(&format!("sweep.grid.theta_deg[{i}]"), *t)?;
    }
    let at = |lo: f64, hi: f64, n: u32, i: u32| {
        if n == 1 { 0.5 * (lo + hi) } else { lo + (hi - lo) * f64::from(i) / f64::from(n - 1) }
    };
    let mut starts = Vec::with_capacity(total as usize);
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
        return Err(ScenarioError::new("sweep.random.radius", format!("must be > 0 (got {})", num(radius))));
    }
    if !(0.0..=radius).contains(&min_radius) {
        return Err(ScenarioError::new(
            "sweep.random.min_radius",
            format!("must be in [0, radius] (got {})", num(min_radius)),
        ));
    }
    if r.n == 0 || r.n as usize > MAX_SWEEP_RUNS {
        return Err(ScenarioError::new("sweep.random.n", format!("must be in 1..={MAX_SWEEP_RUNS} (got {})", r.n)));
    }
    // Every start inside the box: the circle of `radius` around the goal must be (this
    // also keeps radius^2 below from overflowing).
    let reach = goal.x.abs().max(goal.y.abs()) + radius;
    if reach > DIVERGENCE_BOX_M {
        return Err(ScenarioError::new(
            "sweep.random.radius",
            format!(
                "starts up to {} m from the goal ({}, {}) would lie outside the box a run may not leave \
                 (|x|, |y| <= {DIVERGENCE_BOX_M} m): at most {} m here",
                num(radius),
                num(goal.x),
                num(goal.y),
                num(DIVERGENCE_BOX_M - goal.x.abs().max(goal.y.abs()))
            ),
        ));
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
        let f = crate::keys::toml_f64;
        let g = &self.goal;
        let _ = writeln!(out, "\n[sweep]\ngoal = {{ x = {}, y = {}, theta = {} }}", f(g.x), f(g.y), f(g.theta));
        let _ = writeln!(out, "controllers = [");
        for (_, setup) in &self.laws {
            let mut table = String::new();
            controller_table::write(&setup.controller, &mut table);
            if setup.model != setup.robot {
                let mut model = String::new();
                crate::keys::write_keys(&mut model, &crate::keys::to_table(setup.model.params()), &[]);
                let _ = writeln!(table, "model = {{ {} }}", model.lines().collect::<Vec<_>>().join(", "));
            }
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
        let v = &self.variation;
        let _ = writeln!(out, "trials = {}\nseed = {}", v.trials, v.seed);
        if !v.keys.is_empty() {
            let _ = writeln!(out, "vary = [");
            for k in &v.keys {
                let spread = match &k.spread {
                    crate::vary::Spread::Values(x) => {
                        format!("values = [{}]", x.iter().map(|x| f(*x)).collect::<Vec<_>>().join(", "))
                    }
                    crate::vary::Spread::Uniform(lo, hi) => format!("uniform = [{}, {}]", f(*lo), f(*hi)),
                    crate::vary::Spread::Normal(m, sd) => format!("normal = [{}, {}]", f(*m), f(*sd)),
                };
                let _ = writeln!(out, "  {{ key = {}, {spread} }},", Value::String(k.key.clone()));
            }
            let _ = writeln!(out, "]");
        }
        let _ = writeln!(
            out,
            "# {} laws x {} variants x {} trials x {} starts = {} runs",
            self.laws.len(),
            self.variants.len(),
            v.trials,
            self.starts.len(),
            self.len()
        );
    }
}

/// The outcome of one (law, variant, trial, start) run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepOutcome {
    /// Index into [`SweepSpec::laws`].
    pub law: usize,
    /// Index into [`SweepSpec::variants`].
    pub variant: usize,
    /// 0-based trial.
    pub trial: u32,
    /// The run's index in the sweep (it selects the sensor noise and the draws).
    pub run: u64,
    /// Index into [`SweepSpec::starts`].
    pub start_index: usize,
    /// Start pose of C.
    pub start: Pose2<f64>,
    /// The core's outcome.
    pub outcome: Outcome<f64>,
}

impl SweepOutcome {
    /// Converged, diverged or unsettled (decided by the core).
    pub fn status(&self) -> Status {
        self.outcome.status()
    }
}

/// Where run k sits in a sweep: indices into [`SweepSpec::laws`], [`SweepSpec::variants`],
/// the trials and [`SweepSpec::starts`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RunIndex {
    pub law: usize,
    pub variant: usize,
    pub trial: usize,
    pub start: usize,
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
    /// Number of runs: laws x variants x trials x starts.
    pub fn len(&self) -> usize {
        self.laws.len() * self.variants.len() * self.variation.trials as usize * self.starts.len()
    }

    /// True when there is nothing to run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Runs every (law, variant, trial, start) in parallel with the scenario's `[sim]`;
    /// `done` is called once per finished run (from worker threads). Results are ordered
    /// by law, then variant, trial and start.
    pub fn run(&self, sim: &SimSpec, done: &(dyn Fn() + Sync)) -> Result<Vec<SweepOutcome>, ScenarioError> {
        Ok(self.run_until(sim, done, &|| false)?.unwrap_or_default())
    }

    /// [`SweepSpec::run`] that stops soon after `stop` answers true (every run asks it
    /// about every millisecond of work): `Ok(None)` then.
    pub fn run_until(
        &self,
        sim: &SimSpec,
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let poll = || if stop() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
        let runs: Result<Vec<Option<SweepOutcome>>, ScenarioError> = map_ordered(self.len(), |k| {
            let ControlFlow::Continue(outcome) = self.run_exact(sim, k, poll)? else {
                return Ok(None);
            };
            done();
            Ok(Some(outcome))
        })
        .into_iter()
        .collect();
        Ok(runs?.into_iter().collect())
    }

    /// Runs `k` of the sweep (numbered as [`SweepSpec::run_until`] numbers them: law, then
    /// variant, trial and start), one after the other on the calling thread. `poll` is
    /// asked about every millisecond of work whether to go on: `Ok(Break(()))` when it
    /// said stop. The outcomes are those `run_until` gives for the same indices, bit for
    /// bit (tests/chunk.rs): the draws of `vary` and the sensor noise take the run's index
    /// in the whole sweep, so parts put together are the whole. What one worker of an
    /// outside executor (a process pool, Dask) runs, without a thread pool of its own.
    pub fn run_range(
        &self,
        sim: &SimSpec,
        range: Range<usize>,
        mut poll: impl FnMut() -> ControlFlow<()>,
    ) -> Result<ControlFlow<(), Vec<SweepOutcome>>, ScenarioError> {
        if range.end > self.len() {
            return Err(ScenarioError::new(
                "sweep",
                format!("runs {}..{} asked of a sweep of {} runs", range.start, range.end, self.len()),
            ));
        }
        let mut out = Vec::with_capacity(range.len());
        for k in range {
            match self.run_exact(sim, k, &mut poll)? {
                ControlFlow::Continue(o) => out.push(o),
                ControlFlow::Break(()) => return Ok(ControlFlow::Break(())),
            }
        }
        Ok(ControlFlow::Continue(out))
    }

    /// Which (law, variant, trial, start) run `k` of the sweep is: law, then variant,
    /// trial and start, the order of every sweep output.
    pub(crate) fn index_of(&self, k: usize) -> RunIndex {
        let n_starts = self.starts.len();
        let trials = self.variation.trials as usize;
        let n_variants = self.variants.len();
        RunIndex {
            start: k % n_starts,
            trial: (k / n_starts) % trials,
            variant: (k / (n_starts * trials)) % n_variants,
            law: k / (n_starts * trials * n_variants),
        }
    }

    /// The setup of run `k`: its law's and variant's, or, when `vary` draws values per
    /// run, one resolved with the run's draws (`drawn` holds it).
    pub(crate) fn setup_of<'a>(
        &'a self,
        sim: &SimSpec,
        k: usize,
        drawn: &'a mut Option<Setup>,
    ) -> Result<&'a Setup, ScenarioError> {
        let i = self.index_of(k);
        if self.variation.has_draws() {
            let settings = self.variation.settings(self.variants[i.variant], k as u64);
            let setup = Setup::resolve(&with_settings(&self.tables[i.law], &settings)?, &self.law_path(i.law))?;
            setup.check_step(sim.dt())?;
            Ok(drawn.insert(setup))
        } else {
            Ok(&self.setups[i.law * self.variants.len() + i.variant])
        }
    }

    /// `sweep.controllers[law]`: where errors of a law's runs point.
    pub(crate) fn law_path(&self, law: usize) -> String {
        format!("sweep.controllers[{law}]")
    }

    /// Run `k` of the sweep through the exact closed loop, asking `poll` about every
    /// millisecond of work whether to go on.
    pub(crate) fn run_exact(
        &self,
        sim: &SimSpec,
        k: usize,
        poll: impl FnMut() -> ControlFlow<()>,
    ) -> Result<ControlFlow<(), SweepOutcome>, ScenarioError> {
        let i = self.index_of(k);
        let path = self.law_path(i.law);
        let origin = Origin { run: "sweep", controller: &path };
        let mut drawn = None;
        let setup = self.setup_of(sim, k, &mut drawn)?;
        let start = self.starts[i.start];
        let mut lp = assemble::closed_loop(setup, k as u64, start, self.goal, sim, origin)?;
        Ok(lp
            .try_run(sim.n_steps(), u32::MAX, |_| ControlFlow::Continue(()), poll)
            .map_continue(|outcome| self.outcome_of(k, outcome)))
    }

    /// Run `k`'s outcome with where it sits in the sweep.
    pub(crate) fn outcome_of(&self, k: usize, outcome: Outcome<f64>) -> SweepOutcome {
        let i = self.index_of(k);
        SweepOutcome {
            law: i.law,
            variant: i.variant,
            trial: i.trial as u32,
            run: k as u64,
            start_index: i.start,
            start: self.starts[i.start],
            outcome,
        }
    }

    /// One run of law `law` from start `start_index` (the first variant and trial, as the
    /// sweep runs it), handing `sink` every `sim.log_dt` sample: what `wmr-cli plot` draws
    /// to compare the laws from one start.
    pub fn run_one(
        &self,
        sim: &SimSpec,
        law: usize,
        start_index: usize,
        sink: impl FnMut(&wmr_core::Sample<f64>),
    ) -> Result<Outcome<f64>, ScenarioError> {
        let n_starts = self.starts.len();
        let trials = self.variation.trials as usize;
        let n_variants = self.variants.len();
        if law >= self.laws.len() || start_index >= n_starts {
            return Err(ScenarioError::new("sweep", format!("no run of law {law} from start {start_index}")));
        }
        // The run's index as `run_until` numbers it (variant 0, trial 0).
        let run = (law * n_variants * trials * n_starts + start_index) as u64;
        let path = format!("sweep.controllers[{law}]");
        let origin = Origin { run: "sweep", controller: &path };
        let drawn;
        let setup = if self.variation.has_draws() {
            let settings = self.variation.settings(self.variants[0], run);
            drawn = Setup::resolve(&with_settings(&self.tables[law], &settings)?, &path)?;
            drawn.check_step(sim.dt())?;
            &drawn
        } else {
            &self.setups[law * n_variants]
        };
        let mut lp = assemble::closed_loop(setup, run, self.starts[start_index], self.goal, sim, origin)?;
        Ok(lp.run(sim.n_steps(), sim.log_every(), sink))
    }

    /// The value of every varied key in a run (in `vary` order): its variant's axis value,
    /// its draw, or the nominal value.
    pub fn varied_values(&self, o: &SweepOutcome) -> Vec<f64> {
        let settings = self.variation.settings(self.variants[o.variant], o.run);
        let nominal = &self.laws[o.law].1;
        self.variation
            .keys
            .iter()
            .map(|k| {
                settings
                    .iter()
                    .find(|(key, _)| *key == k.key)
                    .and_then(|(_, v)| v.as_float())
                    .or_else(|| nominal.value_of(&k.key))
                    .unwrap_or(f64::NAN)
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
        o.status().name().to_owned(),
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
    /// Share of runs that diverged (0..1): the state stopped being finite or C left the box.
    pub diverged: f64,
    /// Share of runs that are unsettled (0..1): neither converged nor diverged at t_end.
    pub unsettled: f64,
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
            let ok: Vec<&SweepOutcome> = runs.iter().copied().filter(|o| o.status() == Status::Converged).collect();
            let n = runs.len().max(1) as f64;
            let share = |status: Status| runs.iter().filter(|o| o.status() == status).count() as f64 / n;
            let over = |f: fn(&Outcome<f64>) -> f64| spread(ok.iter().map(|o| f(&o.outcome)).collect());
            LawSummary {
                name: name.clone(),
                n: runs.len(),
                converged: ok.len() as f64 / n,
                diverged: share(Status::Diverged),
                unsettled: share(Status::Unsettled),
                time_to_1cm: over(|o| o.time_to_arrival.unwrap_or(f64::NAN)),
                heading_error_deg: over(|o| o.final_heading_error.to_degrees().abs()),
                peak_wheel_speed: over(|o| o.peak_wheel_speed),
                path_length: over(|o| o.path_length),
                energy: over(|o| o.energy),
            }
        })
        .collect()
}

/// The comparison table as aligned text, one line per law: the shares of the three
/// outcomes, then "median / worst" of the other figures over the converged runs.
pub fn summary_table(rows: &[LawSummary]) -> String {
    let fmt = |s: Spread, prec: usize| {
        if s.median.is_nan() { "-".to_owned() } else { format!("{:.p$} / {:.p$}", s.median, s.worst, p = prec) }
    };
    let w = rows.iter().map(|r| r.name.len()).max().unwrap_or(0).max(3);
    let mut out = format!(
        "{:<w$} {:>6} {:>10} {:>9} {:>10} {:>17} {:>15} {:>15} {:>13} {:>15}\n",
        "law",
        "runs",
        "converged",
        "diverged",
        "unsettled",
        "t_1cm s (med/max)",
        "|e_th| deg",
        "peak w rad/s",
        "path m",
        "energy J"
    );
    for r in rows {
        out.push_str(&format!(
            "{:<w$} {:>6} {:>9.1}% {:>8.1}% {:>9.1}% {:>17} {:>15} {:>15} {:>13} {:>15}\n",
            r.name,
            r.n,
            100.0 * r.converged,
            100.0 * r.diverged,
            100.0 * r.unsettled,
            fmt(r.time_to_1cm, 2),
            fmt(r.heading_error_deg, 2),
            fmt(r.peak_wheel_speed, 1),
            fmt(r.path_length, 2),
            fmt(r.energy, 1),
        ));
    }
    out
}
