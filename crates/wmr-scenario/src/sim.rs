//! `[sim]`, checked: run length, plant step and log period, whole multiples of each other.

use wmr_core::{Outcome, XY_GOAL_TOLERANCE_M, YAW_GOAL_TOLERANCE_DEG};

use crate::error::{ScenarioError, num};

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
    stop_when_settled: bool,
    /// With `stop_when_settled`: stop a run as soon as it has arrived (`wmr_core::arrival`).
    early_arrival: bool,
    /// `sim.xy_goal_tolerance`, m.
    xy_goal_tolerance: f64,
    /// `sim.yaw_goal_tolerance_deg`, deg.
    yaw_goal_tolerance_deg: f64,
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
        Err(ScenarioError::new(key, format!("must be > 0 (got {})", num(v))))
    } else {
        Ok(v)
    }
}

impl SimSpec {
    /// Checks t_end (s), dt (s) and log_dt (s), all given; errors name `sim.*`.
    pub fn new(t_end: f64, dt: f64, log_dt: f64) -> Result<Self, ScenarioError> {
        Self::resolve(Some(t_end), Some(dt), Some(log_dt), dt)
    }

    /// `[sim]` as written (`None`: the key is absent) with its defaults: t_end
    /// [`DEFAULT_T_END_S`], dt the controller's `control_dt` (s), log_dt
    /// [`DEFAULT_LOG_DT_S`]. An error names a key the file has: when t_end or log_dt is
    /// not a whole multiple of dt, the one of them that was written, else `sim.dt` if
    /// written, else `controller.control_dt` (where dt came from).
    pub fn resolve(
        t_end: Option<f64>,
        dt: Option<f64>,
        log_dt: Option<f64>,
        control_dt: f64,
    ) -> Result<Self, ScenarioError> {
        let dt_key = if dt.is_some() { "sim.dt" } else { "controller.control_dt" };
        let dt = positive(dt_key, dt.unwrap_or(control_dt))?;
        let t_end_given = t_end.is_some();
        let log_dt_given = log_dt.is_some();
        let t_end = positive("sim.t_end", t_end.unwrap_or(DEFAULT_T_END_S))?;
        let log_dt = positive("sim.log_dt", log_dt.unwrap_or(DEFAULT_LOG_DT_S))?;
        if t_end > MAX_T_END_S {
            return Err(ScenarioError::new("sim.t_end", format!("must be <= {MAX_T_END_S:e} s (got {})", num(t_end))));
        }
        // Which key to blame when `period` is not a whole multiple of dt.
        let blame = |given: bool, key: &str, period: f64| {
            if given {
                ScenarioError::new(
                    key,
                    format!("must be a whole multiple of sim.dt = {} (got {})", num(dt), num(period)),
                )
            } else {
                ScenarioError::new(
                    dt_key,
                    format!(
                        "{} s does not divide the default {key} = {} s: give a {} that divides it, or set {key}",
                        num(dt),
                        num(period),
                        if dt_key == "sim.dt" { "dt" } else { "control_dt" },
                    ),
                )
            }
        };
        let n_steps = whole_multiple(t_end, dt).ok_or_else(|| blame(t_end_given, "sim.t_end", t_end))?;
        if n_steps > MAX_STEPS {
            let key = if t_end_given { "sim.t_end" } else { dt_key };
            return Err(ScenarioError::new(
                key,
                format!(
                    "t_end / dt = {} s / {} s = {n_steps} steps per run, more than the limit of {MAX_STEPS}: \
                     shorten sim.t_end or raise sim.dt",
                    num(t_end),
                    num(dt)
                ),
            ));
        }
        let log_every = whole_multiple(log_dt, dt)
            .and_then(|n| u32::try_from(n).ok())
            .ok_or_else(|| blame(log_dt_given, "sim.log_dt", log_dt))?;
        Ok(Self {
            t_end,
            dt,
            log_dt,
            n_steps,
            log_every,
            stop_when_settled: false,
            early_arrival: false,
            xy_goal_tolerance: XY_GOAL_TOLERANCE_M,
            yaw_goal_tolerance_deg: YAW_GOAL_TOLERANCE_DEG,
        })
    }

    /// With the goal tolerances a run towards a goal is judged docked with
    /// (`wmr_core::Outcome::docked`), as written (`None`: the default):
    /// `sim.xy_goal_tolerance` (m, finite, > 0) and `sim.yaw_goal_tolerance_deg` (deg,
    /// finite, > 0 and <= 180); errors name the key.
    pub fn with_goal_tolerance(mut self, xy: Option<f64>, yaw_deg: Option<f64>) -> Result<Self, ScenarioError> {
        if let Some(v) = xy {
            self.xy_goal_tolerance = positive("sim.xy_goal_tolerance", v)?;
        }
        if let Some(v) = yaw_deg {
            let v = positive("sim.yaw_goal_tolerance_deg", v)?;
            if v > 180.0 {
                return Err(ScenarioError::new(
                    "sim.yaw_goal_tolerance_deg",
                    format!("must be <= 180 deg, the largest heading error (got {})", num(v)),
                ));
            }
            self.yaw_goal_tolerance_deg = v;
        }
        Ok(self)
    }

    /// `sim.xy_goal_tolerance`, m.
    pub fn xy_goal_tolerance(&self) -> f64 {
        self.xy_goal_tolerance
    }

    /// `sim.yaw_goal_tolerance_deg`, deg.
    pub fn yaw_goal_tolerance_deg(&self) -> f64 {
        self.yaw_goal_tolerance_deg
    }

    /// `outcome` judged with these goal tolerances (`wmr_core::Outcome::docked`).
    pub fn judged(&self, outcome: Outcome<f64>) -> Outcome<f64> {
        outcome.with_goal_tolerance(self.xy_goal_tolerance, self.yaw_goal_tolerance_deg.to_radians())
    }

    /// With `on`, each run stops once it has settled (`[sim] stop_when_settled`, the
    /// rule of `wmr_core::settle`); runs keep their full length otherwise.
    pub fn with_stop_when_settled(mut self, on: bool) -> Self {
        self.stop_when_settled = on;
        self
    }

    /// With `on` (and [`SimSpec::with_stop_when_settled`]), each run also stops as soon as
    /// it has arrived by the shorter test of `wmr_core::arrival` (`[sim] early_arrival`).
    pub fn with_early_arrival(mut self, on: bool) -> Self {
        self.early_arrival = on;
        self
    }

    /// Whether runs stop as soon as they have arrived (`wmr_core::arrival`).
    pub fn early_arrival(&self) -> bool {
        self.early_arrival
    }

    /// Whether runs stop once settled.
    pub fn stop_when_settled(&self) -> bool {
        self.stop_when_settled
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
