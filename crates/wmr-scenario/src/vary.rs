//! Robustness sweeps: `[sweep] vary = [...]` changes keys of the plant, the controller's
//! model, the sensor and the world, over listed values or seeded distributions, with
//! `trials` runs per (law, start, value).
//!
//! ```toml
//! [sweep]
//! trials = 2     # runs per (law, start, value); each has its own sensor noise and draws
//! seed = 7       # the draws of run k are a function of (seed, k)
//! vary = [
//!   { key = "sensor.position_noise", values = [0.0, 0.01, 0.05] },  # one axis
//!   { key = "controller.model.wheel_radius", values = [0.09, 0.11] }, # another axis
//!   { key = "world.slope_deg", uniform = [0.0, 10.0] },                # drawn per run
//!   { key = "robot.mass", normal = [5.0, 0.25] },                      # mean, std
//! ]
//! ```
//!
//! Keys with `values` are varied one at a time: each value of each such key is one
//! variant, every other key at its nominal value (the scenario's), so the converged share
//! of each law can be read against each key. Keys with `uniform` or `normal` are drawn
//! for every run, jointly, on top of its variant. The controller's model stays nominal
//! unless a `controller.model.*` key is varied. An entry with `values` may set other keys
//! with each value (`with = { "sensor.pose" = "odometry" }`): the fix rate of odometry
//! means nothing on the absolute sensor.

use serde::Deserialize;
use toml::Value;
use wmr_core::sensor::gaussian::Gaussian;

use crate::error::ScenarioError;

/// One entry of `vary` as written: a dotted key and exactly one of its spreads.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VaryFile {
    /// The scenario key, e.g. `sensor.latency`, `controller.model.wheel_radius`.
    pub key: String,
    /// Values taken one at a time.
    pub values: Option<Vec<f64>>,
    /// `[low, high]`: drawn uniformly for every run (exactly two numbers; read as a list
    /// so that a third is refused, not dropped).
    pub uniform: Option<Vec<f64>>,
    /// `[mean, standard deviation]`: drawn for every run (exactly two numbers).
    pub normal: Option<Vec<f64>>,
    /// Keys set alongside each of `values` (dotted, e.g. `{ "sensor.pose" = "odometry" }`):
    /// what a value needs to mean anything (a fix rate needs the odometry).
    pub with: Option<toml::Table>,
}

/// How a varied key spreads.
#[derive(Clone, Debug, PartialEq)]
pub enum Spread {
    /// One variant per value.
    Values(Vec<f64>),
    /// Uniform on [low, high], per run.
    Uniform(f64, f64),
    /// Normal (mean, standard deviation), per run.
    Normal(f64, f64),
}

/// A varied key and its spread.
#[derive(Clone, Debug, PartialEq)]
pub struct Varied {
    /// The dotted scenario key.
    pub key: String,
    /// Its values or distribution.
    pub spread: Spread,
    /// Keys set alongside each value (`with`), in file order.
    pub with: Vec<(String, Value)>,
}

/// Every varied key of a sweep, with the seed of the draws and the trials per run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Variation {
    /// In file order.
    pub keys: Vec<Varied>,
    /// Seed of the per-run draws.
    pub seed: u64,
    /// Runs per (law, start, variant), at least 1.
    pub trials: u32,
}

/// One variant: which axis key is set to which value (`None`: every key nominal).
pub type Variant = Option<(usize, f64)>;

impl Variation {
    /// Checks the `vary` entries (values finite, one spread each, high >= low, std >= 0).
    pub fn resolve(files: &[VaryFile], seed: u64, trials: u32) -> Result<Self, ScenarioError> {
        if trials == 0 {
            return Err(ScenarioError::new("sweep.trials", "must be >= 1"));
        }
        let mut keys = Vec::with_capacity(files.len());
        for (i, f) in files.iter().enumerate() {
            let path = format!("sweep.vary[{i}]");
            let finite = |k: &str, v: f64| {
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(ScenarioError::new(format!("{path}.{k}"), format!("must be a finite number (got {v})")))
                }
            };
            let pair = |k: &str, v: &[f64], what: &str| -> Result<(f64, f64), ScenarioError> {
                match v {
                    [a, b] => Ok((finite(k, *a)?, finite(k, *b)?)),
                    _ => Err(ScenarioError::new(
                        format!("{path}.{k}"),
                        format!("give exactly two numbers {what} (got {} number(s))", v.len()),
                    )),
                }
            };
            let spread = match (&f.values, f.uniform.as_deref(), f.normal.as_deref()) {
                (Some(v), None, None) => {
                    if v.is_empty() {
                        return Err(ScenarioError::new(format!("{path}.values"), "give at least one value"));
                    }
                    // Counted before anything else: every value is a variant run from every
                    // start by every law, so more values than runs allowed cannot be run.
                    if v.len() > crate::budget::MAX_SWEEP_RUNS {
                        return Err(ScenarioError::new(
                            format!("{path}.values"),
                            format!(
                                "{} values: each is a variant of the sweep, more than the limit of {} runs",
                                v.len(),
                                crate::budget::MAX_SWEEP_RUNS
                            ),
                        ));
                    }
                    for x in v {
                        finite("values", *x)?;
                    }
                    Spread::Values(v.clone())
                }
                (None, Some(u), None) => {
                    let (lo, hi) = pair("uniform", u, "[low, high]")?;
                    if hi < lo {
                        return Err(ScenarioError::new(format!("{path}.uniform"), "give [low, high] with high >= low"));
                    }
                    Spread::Uniform(lo, hi)
                }
                (None, None, Some(n)) => {
                    let (mean, std) = pair("normal", n, "[mean, standard deviation]")?;
                    if std < 0.0 {
                        return Err(ScenarioError::new(
                            format!("{path}.normal"),
                            "the standard deviation must be >= 0",
                        ));
                    }
                    Spread::Normal(mean, std)
                }
                _ => {
                    return Err(ScenarioError::new(
                        path,
                        "give exactly one of values, uniform = [low, high], normal = [mean, std]",
                    ));
                }
            };
            if keys.iter().any(|k: &Varied| k.key == f.key) {
                return Err(ScenarioError::new(format!("{path}.key"), format!("{} is varied twice", f.key)));
            }
            let with: Vec<(String, Value)> = f.with.clone().unwrap_or_default().into_iter().collect();
            if !with.is_empty() && !matches!(spread, Spread::Values(_)) {
                return Err(ScenarioError::new(
                    format!("{path}.with"),
                    "only an entry with values can set keys with them",
                ));
            }
            if let Some((k, _)) = with.iter().find(|(k, _)| *k == f.key) {
                return Err(ScenarioError::new(format!("{path}.with"), format!("{k} is the varied key itself")));
            }
            keys.push(Varied { key: f.key.clone(), spread, with });
        }
        Ok(Self { keys, seed, trials })
    }

    /// The variants: one per value of each `values` key, or a single nominal one.
    pub fn variants(&self) -> Vec<Variant> {
        let axes: Vec<Variant> = self
            .keys
            .iter()
            .enumerate()
            .flat_map(|(i, k)| match &k.spread {
                Spread::Values(v) => v.iter().map(|&x| Some((i, x))).collect(),
                _ => Vec::new(),
            })
            .collect();
        if axes.is_empty() { vec![None] } else { axes }
    }

    /// True when some key is drawn per run.
    pub fn has_draws(&self) -> bool {
        self.keys.iter().any(|k| !matches!(k.spread, Spread::Values(_)))
    }

    /// The drawn value of every distribution key for run `run` (index into `keys`, value).
    pub fn draws(&self, run: u64) -> Vec<(usize, f64)> {
        let mut g = Gaussian::new(self.seed, run);
        self.keys
            .iter()
            .enumerate()
            .filter_map(|(i, k)| match k.spread {
                Spread::Values(_) => None,
                Spread::Uniform(lo, hi) => {
                    Some((i, lo + (hi - lo) * (g.uniform_open0() - f64::EPSILON / 2.0).max(0.0)))
                }
                Spread::Normal(mean, std) => Some((i, mean + std * g.next_normal())),
            })
            .collect()
    }

    /// The (key, value) pairs a run sets: its variant's axis value, then its draws.
    pub fn settings(&self, variant: Variant, run: u64) -> Vec<(&str, Value)> {
        let mut out: Vec<(&str, Value)> = Vec::new();
        if let Some((i, v)) = variant {
            out.push((self.keys[i].key.as_str(), Value::Float(v)));
            out.extend(self.keys[i].with.iter().map(|(k, w)| (k.as_str(), w.clone())));
        }
        out.extend(self.draws(run).into_iter().map(|(i, v)| (self.keys[i].key.as_str(), Value::Float(v))));
        out
    }
}
