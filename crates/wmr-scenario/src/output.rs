//! What a run produces: the sample columns (one definition for CSV, MCAP and Python),
//! the [`Sink`] trait and the per-run [`RunResult`] with its summary line.

use std::error::Error;

use crate::reference::RunReference;
use wmr_core::rolling_traction::TractionWatch;
use wmr_core::tracking::TrackingOutcome;
use wmr_core::{Outcome, Reference, ReferenceState, Sample, Status};

use crate::error::{fixed, millimetres, num};
use crate::run::RunSpec;

/// The CSV header, in order: `run`, then [`SAMPLE_COLUMNS`] (built from it, not copied).
pub const CSV_COLUMNS: [&str; 1 + SAMPLE_COLUMNS.len()] = {
    let mut out = ["run"; 1 + SAMPLE_COLUMNS.len()];
    let mut i = 0;
    while i < SAMPLE_COLUMNS.len() {
        out[i + 1] = SAMPLE_COLUMNS[i];
        i += 1;
    }
    out
};

/// The columns of one sample, the values of [`sample_values`] (CSV columns after `run`):
/// the one list of sample column names that the CSV, the MCAP and Python use.
pub const SAMPLE_COLUMNS: [&str; 15] = [
    "t", "x", "y", "theta", "v", "omega", "phi_r", "phi_l", "omega_r", "omega_l", "tau_r", "tau_l", "e_s", "e_theta",
    "dl",
];

/// The unit of each of [`SAMPLE_COLUMNS`], in order.
pub const SAMPLE_UNITS: [&str; SAMPLE_COLUMNS.len()] =
    ["s", "m", "m", "rad", "m/s", "rad/s", "rad", "rad", "rad/s", "rad/s", "N m", "N m", "m", "rad", "m"];

/// A sample's values in [`SAMPLE_COLUMNS`] order: t (s), x, y (m), theta (rad),
/// v (m/s), omega (rad/s), phi_r, phi_l (rad), omega_r, omega_l (rad/s),
/// tau_r, tau_l (N m), e_s (m), e_theta (rad), dl (m).
#[inline]
pub fn sample_values(s: &Sample<f64>) -> [f64; 15] {
    let st = &s.state;
    [
        s.t,
        st.x,
        st.y,
        st.theta,
        st.v,
        st.omega,
        st.phi_r,
        st.phi_l,
        s.wheel_speeds.right,
        s.wheel_speeds.left,
        s.torque.right,
        s.torque.left,
        s.errors.e_s,
        s.errors.e_theta,
        s.errors.dl,
    ]
}

/// The columns a run with a `[sensor]` table adds after [`CSV_COLUMNS`]: the pose the
/// controller used at its last tick (m, m, rad).
pub const MEASURED_COLUMNS: [&str; 3] = ["x_meas", "y_meas", "theta_meas"];

/// The unit of each of [`MEASURED_COLUMNS`], in order.
pub const MEASURED_UNITS: [&str; MEASURED_COLUMNS.len()] = ["m", "m", "rad"];

/// A sample's values in [`MEASURED_COLUMNS`] order.
#[inline]
pub fn measured_values(s: &Sample<f64>) -> [f64; 3] {
    [s.measured.x, s.measured.y, s.measured.theta]
}

/// The columns a run whose wheels slip (`robot.traction = "slip"`) adds after
/// [`MEASURED_COLUMNS`]' place: each wheel's longitudinal slip velocity (r omega_w minus
/// the ground speed under it, m/s), the lateral velocity of C (body frame, left +, m/s),
/// the ground's longitudinal and lateral forces on each wheel (body frame, N) and each
/// wheel's normal load (N). Rolling runs never carry them, so their outputs are unchanged.
pub const CONTACT_COLUMNS: [&str; 9] = ["slip_r", "slip_l", "v_lat", "fx_r", "fx_l", "fy_r", "fy_l", "n_r", "n_l"];

/// The unit of each of [`CONTACT_COLUMNS`], in order.
pub const CONTACT_UNITS: [&str; CONTACT_COLUMNS.len()] = ["m/s", "m/s", "m/s", "N", "N", "N", "N", "N", "N"];

/// A sample's values in [`CONTACT_COLUMNS`] order.
#[inline]
pub fn contact_values(s: &Sample<f64>) -> [f64; 9] {
    let c = &s.contact;
    [
        c.slip.right,
        c.slip.left,
        c.v_lat,
        c.force_x.right,
        c.force_x.left,
        c.force_y.right,
        c.force_y.left,
        c.normal.right,
        c.normal.left,
    ]
}

/// The columns a run on odometry (`[sensor] pose = "odometry"`) adds after
/// [`MEASURED_COLUMNS`] (which are then the fused pose the controller used): the pose
/// dead-reckoned from the encoders at the last tick (m, m, rad). The true pose is `x, y, theta`.
pub const ODOMETRY_COLUMNS: [&str; 3] = ["x_odom", "y_odom", "theta_odom"];

/// The unit of each of [`ODOMETRY_COLUMNS`], in order.
pub const ODOMETRY_UNITS: [&str; ODOMETRY_COLUMNS.len()] = ["m", "m", "rad"];

/// A sample's values in [`ODOMETRY_COLUMNS`] order (NaN for a sample without odometry,
/// which a run on odometry never hands out).
#[inline]
pub fn odometry_values(s: &Sample<f64>) -> [f64; 3] {
    s.odometry.map_or([f64::NAN; 3], |p| [p.x, p.y, p.theta])
}

/// How far the odometry drifted from the true pose by the end of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometryDrift {
    /// Distance between the dead-reckoned and the true position of C at the end, m.
    pub drift_m: f64,
    /// Path length of C, m (the outcome's `path_length`).
    pub distance_m: f64,
}

impl OdometryDrift {
    /// The drift of the loop `lp` at its end, whose `outcome` gives the distance
    /// travelled: the dead reckoning at the last tick against the true pose; `None` for a
    /// loop whose sensor keeps no odometry.
    pub fn of<L, R>(
        lp: &wmr_core::ClosedLoop<f64, L, wmr_core::AnySensor<f64>, R>,
        outcome: &Outcome<f64>,
    ) -> Option<Self>
    where
        L: wmr_core::Law<f64>,
        R: wmr_core::Reference<f64>,
    {
        let odo = wmr_core::Sensor::odometry(lp.sensor())?;
        Some(Self { drift_m: (odo.x - lp.state().x).hypot(odo.y - lp.state().y), distance_m: outcome.path_length })
    }

    /// The drift in % of the distance travelled; `None` for a run that did not move.
    pub fn percent(&self) -> Option<f64> {
        (self.distance_m > 0.0).then(|| 100.0 * self.drift_m / self.distance_m)
    }

    /// `odometry drift 0.0123 m (1.02 % of 1.206 m travelled)`.
    pub fn describe(&self) -> String {
        match self.percent() {
            Some(p) => format!(
                "odometry drift {} m ({} % of {} m travelled)",
                fixed(self.drift_m, 4),
                fixed(p, 2),
                fixed(self.distance_m, 3)
            ),
            None => format!("odometry drift {} m (no distance travelled)", fixed(self.drift_m, 4)),
        }
    }
}

/// The columns a tracking run adds after the others: the reference at the sample's t
/// (m, m, rad, m/s, rad/s).
pub const REFERENCE_COLUMNS: [&str; 5] = ["x_ref", "y_ref", "theta_ref", "v_ref", "omega_ref"];

/// The unit of each of [`REFERENCE_COLUMNS`], in order.
pub const REFERENCE_UNITS: [&str; REFERENCE_COLUMNS.len()] = ["m", "m", "rad", "m/s", "rad/s"];

/// A reference state's values in [`REFERENCE_COLUMNS`] order.
#[inline]
pub fn reference_values(r: &ReferenceState<f64>) -> [f64; 5] {
    [r.pose.x, r.pose.y, r.pose.theta, r.twist.v, r.twist.omega]
}

/// The columns a run whose law demands a body twist adds after the others
/// ([`wmr_core::LawSpec::TWIST_DEMAND`]: every law but `paper`, `paper_bidirectional` and
/// `backstepping`): the twist the law demanded at its last tick, before the wheel stage's
/// limits (m/s, rad/s; ROS 2's `/cmd_vel`).
pub const COMMAND_COLUMNS: [&str; 2] = ["v_cmd", "omega_cmd"];

/// The unit of each of [`COMMAND_COLUMNS`], in order.
pub const COMMAND_UNITS: [&str; COMMAND_COLUMNS.len()] = ["m/s", "rad/s"];

/// A sample's values in [`COMMAND_COLUMNS`] order (NaN for a sample without a twist
/// demand, which a run carrying the group never hands out).
#[inline]
pub fn command_values(s: &Sample<f64>) -> [f64; 2] {
    s.twist_demand.map_or([f64::NAN; 2], |t| [t.v, t.omega])
}

/// The columns a run with a disturbance observer (`[controller.observer]`) adds after
/// the others: its estimate of the disturbance torque at each wheel at the last control
/// tick (N m, `wmr_core::controller::observer`).
pub const DISTURBANCE_COLUMNS: [&str; 2] = ["tau_dist_r", "tau_dist_l"];

/// The unit of each of [`DISTURBANCE_COLUMNS`], in order.
pub const DISTURBANCE_UNITS: [&str; DISTURBANCE_COLUMNS.len()] = ["N m", "N m"];

/// A sample's values in [`DISTURBANCE_COLUMNS`] order (NaN for a sample without an
/// estimate, which a run carrying the group never hands out).
#[inline]
pub fn disturbance_values(s: &Sample<f64>) -> [f64; 2] {
    s.disturbance.map_or([f64::NAN; 2], |d| [d.right, d.left])
}

/// One group of columns a run's output may carry; [`ColumnGroup::ALL`] is their order in
/// the CSV (and so in `wmr.Sample` and Python's tables).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColumnGroup {
    /// [`SAMPLE_COLUMNS`]: every run.
    Sample,
    /// [`MEASURED_COLUMNS`]: runs with a `[sensor]` (the fused pose on odometry).
    Measured,
    /// [`ODOMETRY_COLUMNS`]: runs with `[sensor] pose = "odometry"`.
    Odometry,
    /// [`CONTACT_COLUMNS`]: runs with `[robot] traction = "slip"`.
    Contact,
    /// [`REFERENCE_COLUMNS`]: runs with a `[reference]` (tracking and path following).
    Reference,
    /// [`COMMAND_COLUMNS`]: runs whose law demands a twist.
    Command,
    /// [`DISTURBANCE_COLUMNS`]: runs with a disturbance observer.
    Disturbance,
}

impl ColumnGroup {
    /// Every group, in CSV order.
    pub const ALL: [Self; 7] = [
        Self::Sample,
        Self::Measured,
        Self::Odometry,
        Self::Contact,
        Self::Reference,
        Self::Command,
        Self::Disturbance,
    ];

    /// The group's column names, in order.
    pub fn names(self) -> &'static [&'static str] {
        match self {
            Self::Sample => &SAMPLE_COLUMNS,
            Self::Measured => &MEASURED_COLUMNS,
            Self::Odometry => &ODOMETRY_COLUMNS,
            Self::Contact => &CONTACT_COLUMNS,
            Self::Reference => &REFERENCE_COLUMNS,
            Self::Command => &COMMAND_COLUMNS,
            Self::Disturbance => &DISTURBANCE_COLUMNS,
        }
    }

    /// The unit of each of [`ColumnGroup::names`], in order.
    pub fn units(self) -> &'static [&'static str] {
        match self {
            Self::Sample => &SAMPLE_UNITS,
            Self::Measured => &MEASURED_UNITS,
            Self::Odometry => &ODOMETRY_UNITS,
            Self::Contact => &CONTACT_UNITS,
            Self::Reference => &REFERENCE_UNITS,
            Self::Command => &COMMAND_UNITS,
            Self::Disturbance => &DISTURBANCE_UNITS,
        }
    }

    /// The group's name, for messages: `odometry` (the odometry columns).
    pub fn name(self) -> &'static str {
        match self {
            Self::Sample => "sample",
            Self::Measured => "measured",
            Self::Odometry => "odometry",
            Self::Contact => "contact",
            Self::Reference => "reference",
            Self::Command => "command",
            Self::Disturbance => "disturbance",
        }
    }

    /// Which runs carry the group, for messages: "a run on odometry (...)".
    pub fn carried_by(self) -> &'static str {
        match self {
            Self::Sample => "every run",
            Self::Measured => "a run with a [sensor]",
            Self::Odometry => "a run on odometry ([sensor] pose = \"odometry\")",
            Self::Contact => "a run whose wheels slip ([robot] traction = \"slip\")",
            Self::Reference => "a tracking run (a scenario with a [reference])",
            Self::Command => "a run whose law demands a twist (not paper, paper_bidirectional, backstepping)",
            Self::Disturbance => "a run with a disturbance observer ([controller.observer])",
        }
    }
}

/// The columns every run of a scenario carries after `run`, decided once from the
/// scenario (`Columns::of`, beside the scenario, which this module does not know): the CSV writes them, `wmr.Sample` has one field per column and Python one
/// array, all in this order ([`ColumnGroup::ALL`]) with the same f64. The default is
/// the sample columns alone.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Columns {
    /// The measured pose ([`MEASURED_COLUMNS`]).
    pub measured: bool,
    /// The dead-reckoned pose ([`ODOMETRY_COLUMNS`]).
    pub odometry: bool,
    /// The wheels' contact ([`CONTACT_COLUMNS`]).
    pub contact: bool,
    /// The reference whose state at each sample's t fills [`REFERENCE_COLUMNS`].
    pub reference: Option<RunReference>,
    /// The law's twist demand ([`COMMAND_COLUMNS`]).
    pub command: bool,
    /// The disturbance observer's estimate ([`DISTURBANCE_COLUMNS`]).
    pub disturbance: bool,
}

impl Columns {
    /// Whether the runs carry `group`.
    pub fn has(&self, group: ColumnGroup) -> bool {
        match group {
            ColumnGroup::Sample => true,
            ColumnGroup::Measured => self.measured,
            ColumnGroup::Odometry => self.odometry,
            ColumnGroup::Contact => self.contact,
            ColumnGroup::Reference => self.reference.is_some(),
            ColumnGroup::Command => self.command,
            ColumnGroup::Disturbance => self.disturbance,
        }
    }

    /// The groups carried, in order.
    pub fn groups(&self) -> impl Iterator<Item = ColumnGroup> + '_ {
        ColumnGroup::ALL.into_iter().filter(|g| self.has(*g))
    }

    /// The column names, in order (the CSV header after `run`).
    pub fn names(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.groups().flat_map(|g| g.names().iter().copied())
    }

    /// The number of columns.
    pub fn len(&self) -> usize {
        self.groups().map(|g| g.names().len()).sum()
    }

    /// Never: every run has the sample columns.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Sample `s`'s values, one per [`Columns::names`], in order.
    #[inline]
    pub fn values(&self, s: &Sample<f64>) -> impl Iterator<Item = f64> {
        let group = |on: bool, v: fn(&Sample<f64>) -> [f64; 3]| on.then(|| v(s)).into_iter().flatten();
        sample_values(s)
            .into_iter()
            .chain(group(self.measured, measured_values))
            .chain(group(self.odometry, odometry_values))
            .chain(self.contact.then(|| contact_values(s)).into_iter().flatten())
            .chain(self.reference.as_ref().map(|r| reference_values(&r.state_at(s.t))).into_iter().flatten())
            .chain(self.command.then(|| command_values(s)).into_iter().flatten())
            .chain(self.disturbance.then(|| disturbance_values(s)).into_iter().flatten())
    }
}

/// The error a sink reports (I/O, encoding, ...).
pub type SinkError = Box<dyn Error + Send + Sync + 'static>;

/// An output format: takes the samples of each run in order, then finishes.
///
/// Runs arrive one after the other, in run order, each as `begin_run`, its samples,
/// `end_run`. A new format is a new sink; nothing else changes.
pub trait Sink {
    /// Called before the first sample of run `index`.
    fn begin_run(&mut self, index: usize, run: &RunSpec) -> Result<(), SinkError> {
        let _ = (index, run);
        Ok(())
    }

    /// One logged sample of run `index`.
    fn sample(&mut self, index: usize, sample: &Sample<f64>) -> Result<(), SinkError>;

    /// Called after the last sample of a run.
    fn end_run(&mut self, result: &RunResult) -> Result<(), SinkError> {
        let _ = result;
        Ok(())
    }

    /// Completes the output (flush, write indexes) after the last run.
    fn finish(&mut self) -> Result<(), SinkError>;
}

/// Summary of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// 0-based index of the `[[run]]`.
    pub index: usize,
    /// The run's label.
    pub label: String,
    /// The core's outcome (final pose, final dl, heading error, time to arrival, ...).
    pub outcome: Outcome<f64>,
    /// For a tracking run, how the tracking error went (`wmr_core::tracking`).
    pub tracking: Option<TrackingOutcome<f64>>,
    /// For a run on odometry, its drift at the end.
    pub odometry_drift: Option<OdometryDrift>,
    /// For a rolling run, when its wheels first asked more than mu N of the ground and
    /// its worst ratio ([`wmr_core::rolling_traction`], at the logged samples); empty
    /// when they never did, and for a slipping run.
    pub traction: TractionWatch<f64>,
    /// For a run that collided, the index of the obstacle it touched (in
    /// `[[world.obstacle]]` order, circles first: `wmr_core::Obstacles::iter`).
    pub collided_with: Option<usize>,
}

impl RunResult {
    /// Wraps a core outcome.
    pub fn new(index: usize, label: String, outcome: Outcome<f64>) -> Self {
        Self {
            index,
            label,
            outcome,
            tracking: None,
            odometry_drift: None,
            traction: TractionWatch::default(),
            collided_with: None,
        }
    }

    /// The same run with the obstacle it touched (a run that collided).
    pub fn with_collision(mut self, obstacles: &wmr_core::Obstacles<f64>) -> Self {
        if self.outcome.termination == wmr_core::Termination::Collided {
            let p = self.outcome.final_pose;
            self.collided_with = obstacles.nearest(p.x, p.y).map(|(i, _)| i);
        }
        self
    }

    /// ", collided at t = T s with obstacle I" for a run that collided, ", diverged at t = T s" style stop
    /// otherwise: what follows the status word.
    fn stop_note(&self) -> String {
        let t = fixed(self.outcome.t_final, 3);
        match (self.status(), self.collided_with) {
            (Status::Diverged, _) => format!(" at t = {t} s"),
            (Status::Collided, Some(i)) => format!(" at t = {t} s with obstacle {i}"),
            (Status::Collided, None) => format!(" at t = {t} s"),
            _ => String::new(),
        }
    }

    /// The same run with what its rolling wheels asked of the ground.
    pub fn with_traction(mut self, traction: TractionWatch<f64>) -> Self {
        self.traction = traction;
        self
    }

    /// The same run with its final odometry drift (a run on odometry).
    pub fn with_odometry_drift(mut self, drift: Option<OdometryDrift>) -> Self {
        self.odometry_drift = drift;
        self
    }

    /// The same run with its tracking outcome (a tracking run).
    pub fn with_tracking(mut self, tracking: TrackingOutcome<f64>) -> Self {
        self.tracking = Some(tracking);
        self
    }

    /// Converged, diverged, unsettled or (a tracking run) cannot_follow, decided by the
    /// core from the true state. A tracking run converges when its tracking error stays
    /// below `sim.tracking_tolerance` over the last 10 % of t_end.
    pub fn status(&self) -> Status {
        crate::tracking_run::status(&self.outcome, self.tracking.as_ref())
    }

    /// The state stopped being finite or C left the 1 km box.
    pub fn diverged(&self) -> bool {
        self.status() == Status::Diverged
    }

    /// Not diverged and the final distance to the goal is below 1 cm.
    pub fn converged(&self) -> bool {
        self.status() == Status::Converged
    }

    /// The summary line: label, final dl (m), final heading error (deg),
    /// time to dl < 1 cm (s or "never"), status.
    /// A run on odometry adds its drift at the end ([`OdometryDrift::describe`]).
    pub fn summary_line(&self) -> String {
        let line = match &self.odometry_drift {
            Some(d) => format!("{}, {}", self.plain_summary_line(), d.describe()),
            None => self.plain_summary_line(),
        };
        match (self.traction.first, self.traction.peak) {
            (Some((t0, r0)), Some((tp, rp))) => format!(
                "{line}; traction exceeded: from t = {t0:.3} s the rolling wheels ask {r0:.2} x mu N of the ground \
                 (worst {rp:.2} x at t = {tp:.3} s), so the rolling result is not physical there \
                 (robot.traction = \"slip\" simulates it)"
            ),
            _ => line,
        }
    }

    fn plain_summary_line(&self) -> String {
        let o = &self.outcome;
        if let Some(tr) = &self.tracking {
            // The tolerance as written, in mm (0.01 m: `10 mm`), rounded to the nanometre.
            let tol = format!("{} mm", num((tr.tolerance * 1e9).round() / 1e6));
            let settle = match tr.time_to_tolerance {
                Some(t) => format!("within {tol} after {} s", fixed(t, 3)),
                None => format!("never within {tol}"),
            };
            let stop = self.stop_note();
            return format!(
                "run {} [{}]: tracking error over the last half RMS {}, max {}, final {}, {settle}, {}{}",
                self.index,
                self.label,
                millimetres(tr.rms_last_half),
                millimetres(tr.max_last_half),
                millimetres(tr.final_error),
                self.status().name(),
                match self.status() {
                    Status::CannotFollow => cannot_follow_reason(tr),
                    Status::Unsettled if tr.within_tolerance() => stalled_reason(tr),
                    _ => stop,
                }
            );
        }
        let arrival = match o.time_to_arrival {
            Some(t) => format!("{} s", fixed(t, 3)),
            None => "never".to_owned(),
        };
        let stop = self.stop_note();
        format!(
            "run {} [{}]: final dl {} m, final heading error {} deg, time to dl < 1 cm {}, {}{}",
            self.index,
            self.label,
            fixed(o.final_dl, 6),
            fixed(o.final_heading_error.to_degrees(), 3),
            arrival,
            self.status().name(),
            stop
        )
    }
}

/// Why a path-following run close to its path is `unsettled`: it stopped on the path
/// ([`TrackingOutcome::stalled`]), for its summary line.
fn stalled_reason(tr: &TrackingOutcome<f64>) -> String {
    let end = if tr.final_distance_to_path_end.is_nan() {
        String::new()
    } else {
        format!(", {} m from the path's end", fixed(tr.final_distance_to_path_end, 3))
    };
    format!(" (stopped on the path: {} m along it over the last tenth of t_end{end})", fixed(tr.progress_last_tenth, 3))
}

/// Why a tracking run is `cannot_follow`, for its summary line: the wheel speeds the
/// reference asks against the limit, or the growth of the error.
fn cannot_follow_reason(tr: &TrackingOutcome<f64>) -> String {
    match tr.over_limit_at {
        Some(t) => format!(
            " (the reference asks wheel speeds up to {:.1} rad/s, above wheel_speed_max = {:.1} rad/s from t = {t:.3} s)",
            tr.reference_wheel_speed, tr.wheel_speed_limit
        ),
        None => format!(
            " (the error grew: mean {:.6} m over the first tenth of t_end, {:.6} m over the last)",
            tr.mean_first_tenth, tr.mean_last_tenth
        ),
    }
}
