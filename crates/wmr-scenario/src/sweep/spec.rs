//! A checked sweep: the goal, every law with its configuration for every variant of
//! `vary`, the starts, and where run k of the sweep sits (law, variant, trial, start),
//! the order of every sweep output.

use toml::{Table, Value};
use wmr_core::{Obstacles, Pose2};

use super::outcome::SweepOutcome;
use super::starts::{StartsSource, grid_starts, random_starts, start_from};
use crate::assemble::{self, Origin};
use crate::bounds::check_in_box;
use crate::budget::{MAX_SWEEP_REFERENCES, MAX_SWEEP_RUNS};
use crate::controller::{stabilization_law_kinds, tracking_law_kinds};
use crate::error::ScenarioError;
use crate::file::{GridFile, SweepFile};
use crate::reference::{ReferenceSpec, check_law};
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
    /// Start poses of C: m, m, rad. In a sweep over references, the offsets from each
    /// reference's pose at t = 0 (x along its heading, y to its left, m; heading added,
    /// rad): [`SweepSpec::start_pose`] gives a run's start.
    pub starts: Vec<Pose2<f64>>,
    /// Where the starts come from, every default filled in (written back by `to_toml`).
    pub source: StartsSource,
    /// For a sweep over references (tracking, path following): the references and the
    /// tolerance the runs are judged with; `None` for a sweep towards `goal`.
    pub tracking: Option<SweepTracking>,
    /// Random starts whose footprint fell on an obstacle and were drawn again (0 without
    /// obstacles; `sweep.random`, docs/scenario.md).
    pub redrawn_starts: usize,
}

/// The references of a sweep over references and the tolerance its runs are judged with.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepTracking {
    /// The references, in file order: a unique name for each (`kind`, or `kind#2` ...)
    /// and the checked reference.
    pub references: Vec<(String, ReferenceSpec)>,
    /// `sim.tracking_tolerance`, m.
    pub tolerance: f64,
}

impl SweepTracking {
    /// Names each reference by its kind (`circle`, `circle#2` for a second circle).
    pub(crate) fn named(references: Vec<ReferenceSpec>, tolerance: f64) -> Self {
        let mut named: Vec<(String, ReferenceSpec)> = Vec::with_capacity(references.len());
        // How many of each kind came before: one look-up per reference (counting the
        // earlier names, a `format!` each, took 28 s for 20,000 circles).
        let mut seen: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
        for r in references {
            let kind = r.table.get("kind").and_then(Value::as_str).unwrap_or(r.built.kind()).to_owned();
            let same = seen.entry(kind.clone()).or_default();
            let name = if *same == 0 { kind } else { format!("{kind}#{}", *same + 1) };
            *same += 1;
            named.push((name, r));
        }
        Self { references: named, tolerance }
    }
}

/// Refuses a sweep over `n` references before any of them is built: more than
/// [`MAX_SWEEP_REFERENCES`], or more runs than [`MAX_SWEEP_RUNS`] counting the references,
/// starts, laws and trials as written (the variants, at least one, are counted later by
/// [`SweepSpec::resolve`]). The key is `sweep.references`.
pub(crate) fn check_reference_count(sw: &SweepFile, n: usize) -> Result<(), ScenarioError> {
    if n > MAX_SWEEP_REFERENCES {
        return Err(ScenarioError::new(
            "sweep.references",
            format!("{n} references, more than the limit of {MAX_SWEEP_REFERENCES}: split the sweep into files"),
        ));
    }
    let starts: u128 = match (&sw.grid, &sw.random) {
        (Some(g), None) => {
            u128::from(g.nx) * u128::from(g.ny) * g.theta_deg.as_ref().map_or(1, |t| t.len().max(1)) as u128
        }
        (None, Some(r)) => u128::from(r.n),
        // Refused by name later.
        _ => 1,
    };
    let laws = sw.controllers.as_ref().map_or(tracking_law_kinds().len(), Vec::len).max(1) as u128;
    let trials = u128::from(sw.trials.unwrap_or(1).max(1));
    let runs = n as u128 * starts.max(1) * laws * trials;
    if runs > MAX_SWEEP_RUNS as u128 {
        return Err(ScenarioError::new(
            "sweep.references",
            format!(
                "{n} references x {starts} starts x {laws} laws x {trials} trials is more than {MAX_SWEEP_RUNS} runs"
            ),
        ));
    }
    Ok(())
}

/// Two sweeps are equal when they run the same: the tables as written may differ.
impl PartialEq for SweepSpec {
    fn eq(&self, other: &Self) -> bool {
        (
            &self.goal,
            &self.laws,
            &self.variation,
            &self.variants,
            &self.setups,
            &self.starts,
            &self.source,
            &self.tracking,
        ) == (
            &other.goal,
            &other.laws,
            &other.variation,
            &other.variants,
            &other.setups,
            &other.starts,
            &other.source,
            &other.tracking,
        )
    }
}

impl SweepSpec {
    /// Checks a `[sweep]` table and draws the starts; every law is validated, for every
    /// variant, with the scenario's tables (`base`) and its own controller table, and its
    /// loop assembled towards the goal (towards each reference, for a sweep over
    /// references: `tracking`).
    pub(crate) fn resolve(
        sw: &SweepFile,
        base: &Tables,
        sim: &SimSpec,
        tracking: Option<SweepTracking>,
    ) -> Result<Self, ScenarioError> {
        if tracking.is_some() && sw.goal.is_some() {
            return Err(ScenarioError::new(
                "sweep.goal",
                "a sweep over a reference has no goal: the reference is the goal, and the starts are offsets from its \
                 pose at t = 0",
            ));
        }
        let goal = sw.goal.clone().unwrap_or_default().resolve("sweep.goal")?;
        check_in_box("sweep.goal", goal)?;
        let default_kinds = if tracking.is_some() { tracking_law_kinds() } else { stabilization_law_kinds() };
        let controllers: Vec<Table> = match &sw.controllers {
            Some(v) if v.is_empty() => return Err(ScenarioError::new("sweep.controllers", "name at least one law")),
            Some(v) => v.clone(),
            None => default_kinds
                .into_iter()
                .map(|k| Table::from_iter([("kind".to_owned(), Value::String(k.to_owned()))]))
                .collect(),
        };
        let n_references = tracking.as_ref().map_or(1, |t| t.references.len());
        let variation =
            Variation::resolve(sw.vary.as_deref().unwrap_or_default(), sw.seed.unwrap_or(0), sw.trials.unwrap_or(1))?;
        let variants = variation.variants();
        // The starts and the number of runs first: a sweep too large is refused before
        // any of its variants is checked (a list of a million values took 47 s and 3.9 GB).
        let (mut starts, source) = match (&sw.grid, &sw.random) {
            (Some(g), None) => {
                let g = GridFile { theta_deg: Some(g.theta_deg.clone().unwrap_or_else(|| vec![0.0])), ..g.clone() };
                (grid_starts(&g)?, StartsSource::Grid(g))
            }
            // Drawn again below, free of the obstacles, once the robot is known.
            (None, Some(r)) => (random_starts(r, goal, &Obstacles::default())?.0, StartsSource::Random(r.clone())),
            (Some(_), Some(_)) => {
                return Err(ScenarioError::new("sweep.random", "give either grid or random, not both"));
            }
            (None, None) => {
                return Err(ScenarioError::new("sweep", "missing the starts: give a grid or a random table"));
            }
        };
        let runs = starts
            .len()
            .saturating_mul(n_references)
            .saturating_mul(controllers.len())
            .saturating_mul(variants.len())
            .saturating_mul(variation.trials as usize);
        if runs > MAX_SWEEP_RUNS {
            return Err(ScenarioError::new(
                "sweep",
                format!(
                    "{} starts x {} references x {} laws x {} variants x {} trials is more than {MAX_SWEEP_RUNS} runs",
                    starts.len(),
                    n_references,
                    controllers.len(),
                    variants.len(),
                    variation.trials
                ),
            ));
        }
        let mut laws: Vec<(String, Setup)> = Vec::with_capacity(controllers.len());
        let mut tables = Vec::with_capacity(controllers.len());
        for (i, controller) in controllers.into_iter().enumerate() {
            let path = format!("sweep.controllers[{i}]");
            let mut t = Tables { controller, ..base.clone() };
            // A law without its own model takes the scenario's [controller.model].
            if let (None, Some(model)) = (t.controller.get("model"), base.controller.get("model")) {
                t.controller.insert("model".to_owned(), model.clone());
            }
            let law = Setup::resolve(&t, &path)?.controller.law;
            check_law(&law, tracking.as_ref().and_then(|tr| tr.references.first()).map(|(_, r)| r), &path)?;
            let setup = check_setup(&t, &path, sim, goal, None, tracking.as_ref())?;
            let kind = setup.controller.law.kind();
            let same = laws.iter().filter(|(_, s)| s.controller.law.kind() == kind).count();
            let name = if same == 0 { kind.to_owned() } else { format!("{kind}#{}", same + 1) };
            laws.push((name, setup));
            tables.push(t);
        }
        // Random starts towards the goal clear of the obstacles, for the nominal robot's
        // footprint (the first law's setup: the scenario's [robot] and [world]).
        let mut redrawn_starts = 0;
        if let (None, StartsSource::Random(r), Some((_, setup))) = (&tracking, &source, laws.first())
            && !setup.obstacles.is_empty()
        {
            (starts, redrawn_starts) = random_starts(r, goal, &setup.obstacles)?;
        }
        if let Some(tr) = &tracking {
            // Every start inside the box, from every reference.
            let key = match source {
                StartsSource::Grid(_) => "sweep.grid",
                StartsSource::Random(_) => "sweep.random",
            };
            for (_, r) in &tr.references {
                let origin = r.built.start_pose();
                starts.iter().try_for_each(|o| check_in_box(key, start_from(origin, *o)))?;
            }
        }
        let mut spec = SweepSpec {
            goal,
            laws,
            tables,
            variation,
            variants,
            setups: Vec::new(),
            starts,
            source,
            tracking,
            redrawn_starts,
        };
        // Every run's draws before the variants (whose setups hold run 0's draws), so a bad
        // draw is named as one.
        spec.check_draws(sim)?;
        let mut setups = Vec::with_capacity(spec.laws.len() * spec.variants.len());
        for (i, t) in spec.tables.iter().enumerate() {
            let path = format!("sweep.controllers[{i}]");
            for v in &spec.variants {
                let vt = with_settings(t, &spec.variation.settings(*v, 0))?;
                let blame =
                    v.map(|(k, x)| (format!("sweep.vary[{k}]"), format!("{} = {x}", spec.variation.keys[k].key)));
                setups.push(check_setup(&vt, &path, sim, goal, blame, spec.tracking.as_ref())?);
            }
        }
        spec.setups = setups;
        Ok(spec)
    }
}

/// `t` with every (key, value) of `settings` set.
pub(super) fn with_settings(t: &Tables, settings: &[(&str, Value)]) -> Result<Tables, ScenarioError> {
    let mut t = t.clone();
    for (k, v) in settings {
        t.set(k, v.clone())?;
    }
    Ok(t)
}

/// Resolves `t` and assembles its loop at the goal (on each reference of `tracking`), so
/// every check a run makes is made now. With `blame` (the `vary` entry's key path and the
/// value it set), an error names that entry, which is what the file says, and quotes the
/// key and reason inside.
fn check_setup(
    t: &Tables,
    path: &str,
    sim: &SimSpec,
    goal: Pose2<f64>,
    blame: Option<(String, String)>,
    tracking: Option<&SweepTracking>,
) -> Result<Setup, ScenarioError> {
    let prefix = |e: ScenarioError| match &blame {
        None => e,
        Some((key, what)) => ScenarioError::new(key, format!("{what}: {}: {}", e.key, e.message)),
    };
    let setup = Setup::resolve(t, path).map_err(prefix)?;
    setup.check_step(sim.dt()).map_err(prefix)?;
    let origin = Origin { run: "sweep", controller: path };
    match tracking {
        None => {
            assemble::closed_loop(&setup, 0, goal, goal, sim, origin).map_err(prefix)?;
        }
        Some(tr) => {
            for (_, r) in &tr.references {
                let start = r.built.start_pose();
                assemble::closed_loop_to(&setup, 0, start, r.built.clone(), sim, origin).map_err(prefix)?;
            }
        }
    }
    Ok(setup)
}

/// Where run k sits in a sweep: indices into [`SweepSpec::laws`], [`SweepSpec::variants`],
/// the trials and [`SweepSpec::starts`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RunIndex {
    pub law: usize,
    pub reference: usize,
    pub variant: usize,
    pub trial: usize,
    pub start: usize,
}

impl SweepSpec {
    /// Number of runs: laws x references x variants x trials x starts.
    pub fn len(&self) -> usize {
        self.laws.len() * self.n_references() * self.variants.len() * self.variation.trials as usize * self.starts.len()
    }

    /// The references of a sweep over references; 1 for a sweep towards a goal.
    pub fn n_references(&self) -> usize {
        self.tracking.as_ref().map_or(1, |t| t.references.len())
    }

    /// The name of (law, reference) in tables and plots: the law's name, with the
    /// reference's after it (`kanayama / circle`) when the sweep has several.
    pub fn case_name(&self, law: usize, reference: usize) -> String {
        match &self.tracking {
            Some(tr) if tr.references.len() > 1 => format!("{} / {}", self.laws[law].0, tr.references[reference].0),
            _ => self.laws[law].0.clone(),
        }
    }

    /// The start pose of C of a run from start `start` on reference `reference` (world
    /// frame; m, m, rad): the start itself, or in a sweep over references the offset
    /// from the reference's pose at t = 0.
    pub fn start_pose(&self, reference: usize, start: usize) -> Pose2<f64> {
        match &self.tracking {
            None => self.starts[start],
            Some(tr) => start_from(tr.references[reference].1.built.start_pose(), self.starts[start]),
        }
    }

    /// True when there is nothing to run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Which (law, reference, variant, trial, start) run `k` of the sweep is: law, then
    /// reference, variant, trial and start, the order of every sweep output.
    pub(crate) fn index_of(&self, k: usize) -> RunIndex {
        let n_starts = self.starts.len();
        let trials = self.variation.trials as usize;
        let n_variants = self.variants.len();
        let n_references = self.n_references();
        RunIndex {
            start: k % n_starts,
            trial: (k / n_starts) % trials,
            variant: (k / (n_starts * trials)) % n_variants,
            reference: (k / (n_starts * trials * n_variants)) % n_references,
            law: k / (n_starts * trials * n_variants * n_references),
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

    /// Checks every run's draws (when `vary` draws values per run) as the run will make
    /// them; the first bad run in run order is the error, naming the `vary`
    /// entry whose draw is refused (or `sweep.vary` when no single entry is to blame), the
    /// run, its law, trial and start, and the drawn values.
    fn check_draws(&self, sim: &SimSpec) -> Result<(), ScenarioError> {
        if !self.variation.has_draws() {
            return Ok(());
        }
        let check = |k: usize| -> Result<(), ScenarioError> {
            let i = self.index_of(k);
            let settings = self.variation.settings(self.variants[i.variant], k as u64);
            let path = self.law_path(i.law);
            let t = with_settings(&self.tables[i.law], &settings)?;
            check_setup(&t, &path, sim, self.goal, None, self.tracking.as_ref()).map(drop).map_err(|e| {
                let drawn: Vec<(usize, f64)> = self.variation.draws(k as u64);
                let shown: Vec<String> =
                    drawn.iter().map(|(j, v)| format!("{} = {v}", self.variation.keys[*j].key)).collect();
                // The entry whose key the error names (a law's errors say
                // `sweep.controllers[i].model.x` for `controller.model.x`); else the list.
                let culprit = drawn.iter().find(|(j, _)| {
                    let key = self.variation.keys[*j].key.as_str();
                    e.key.ends_with(key.strip_prefix("controller").unwrap_or(key))
                });
                let key = culprit.map_or("sweep.vary".to_owned(), |(j, _)| format!("sweep.vary[{j}]"));
                ScenarioError::new(
                    key,
                    format!(
                        "run {k} (law {}, trial {}, start {}) draws {}: {}: {}",
                        self.laws[i.law].0,
                        i.trial,
                        i.start,
                        shown.join(", "),
                        e.key,
                        e.message
                    ),
                )
            })
        };
        // In order on the calling thread, not on rayon's pool: a sweep part run by an
        // outside executor's forked worker (a process pool) must not touch a pool the
        // parent process started (its threads do not survive the fork: it would wait
        // forever). A draw costs one parameter check.
        match (0..self.len()).map(check).find(Result::is_err) {
            Some(Err(e)) => Err(e),
            _ => Ok(()),
        }
    }

    /// `sweep.controllers[law]`: where errors of a law's runs point.
    pub(crate) fn law_path(&self, law: usize) -> String {
        format!("sweep.controllers[{law}]")
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
