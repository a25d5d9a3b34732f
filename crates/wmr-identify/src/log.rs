//! A checked log: runs of time-stamped wheel commands and wheel measurements.

use crate::error::IdentifyError;
use crate::table::Table;

/// What the logged command is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommandKind {
    /// The wheel torque, N m (`[drive] kind = "torque"`; a wmr run's `tau_r`, `tau_l`).
    Torque,
    /// The motor voltage, V (`[drive] kind = "dc_motor"`; columns `u_r`, `u_l`).
    Voltage,
}

/// The column names a log is read with; each slot takes the first name present.
///
/// A wmr run's CSV (`wmr-cli run ... -o run.csv`) has all of them (`t`, `tau_r`,
/// `tau_l`, `phi_r`, `phi_l`, `omega_r`, `omega_l`, `x`, `y`, `theta`, `run`).
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnNames {
    /// Time, s.
    pub time: &'static [&'static str],
    /// Run index (optional): each run is filtered on its own.
    pub run: &'static [&'static str],
    /// Right, left wheel torque, N m.
    pub torque: [&'static [&'static str]; 2],
    /// Right, left motor voltage, V.
    pub voltage: [&'static [&'static str]; 2],
    /// Right, left wheel angle, rad (preferred: the encoders themselves).
    pub angle: [&'static [&'static str]; 2],
    /// Right, left wheel speed, rad/s (used when there are no angles).
    pub speed: [&'static [&'static str]; 2],
    /// Pose of C in the world frame (optional): x, y (m), theta (rad).
    pub pose: [&'static [&'static str]; 3],
}

impl Default for ColumnNames {
    fn default() -> Self {
        Self {
            time: &["t", "t_s", "time"],
            run: &["run"],
            torque: [&["tau_r", "effort_r"], &["tau_l", "effort_l"]],
            voltage: [&["u_r", "voltage_r"], &["u_l", "voltage_l"]],
            angle: [&["phi_r", "position_r"], &["phi_l", "position_l"]],
            speed: [&["omega_r", "velocity_r"], &["omega_l", "velocity_l"]],
            pose: [&["x"], &["y"], &["theta"]],
        }
    }
}

/// How the wheels were measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WheelSignal {
    /// Wheel angles, rad: speeds and accelerations are their first and second derivatives.
    Angle,
    /// Wheel speeds, rad/s: accelerations are their derivative.
    Speed,
}

/// One run of a log: samples at increasing times, with the command held from each
/// sample to the next (a digital controller's zero-order hold).
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// The run's index in the log.
    pub index: usize,
    /// Sample times, s, strictly increasing.
    pub t_s: Vec<f64>,
    /// Right, left command (N m or V, [`Log::command`]) held from each sample on.
    pub command: [Vec<f64>; 2],
    /// Right, left wheel angle (rad) or speed (rad/s), [`Log::wheel`].
    pub wheel: [Vec<f64>; 2],
    /// x, y (m), theta (rad) of C in the world frame, if logged.
    pub pose: Option<[Vec<f64>; 3]>,
}

/// A checked log: every value finite, time increasing within each run.
#[derive(Clone, Debug, PartialEq)]
pub struct Log {
    /// What the command columns are.
    pub command: CommandKind,
    /// What the wheel columns are.
    pub wheel: WheelSignal,
    /// The names of the columns read, for messages and provenance: time, commands, wheels.
    pub columns_used: Vec<String>,
    /// The runs, in order of appearance.
    pub runs: Vec<Run>,
}

fn find<'a>(table: &'a Table, names: &[&'static str]) -> Option<(&'static str, &'a [f64])> {
    names.iter().find_map(|n| table.column(n).map(|c| (*n, c)))
}

fn need<'a>(table: &'a Table, names: &[&'static str]) -> Result<(&'static str, &'a [f64]), IdentifyError> {
    find(table, names).ok_or_else(|| IdentifyError::MissingColumn { column: names.join(" or ") })
}

impl Log {
    /// Reads `table` with `names`: the commands of `kind`, the wheel angles (or else the
    /// speeds), the pose if present. Refuses a missing column, a value that is not finite
    /// (naming its column and time) and a time that does not increase within a run.
    pub fn from_table(table: &Table, names: &ColumnNames, kind: CommandKind) -> Result<Self, IdentifyError> {
        let (t_name, t) = need(table, names.time)?;
        let cmd_names = match kind {
            CommandKind::Torque => names.torque,
            CommandKind::Voltage => names.voltage,
        };
        let cmd = [need(table, cmd_names[0])?, need(table, cmd_names[1])?];
        let (wheel, signal) = match (find(table, names.angle[0]), find(table, names.angle[1])) {
            (Some(r), Some(l)) => ([r, l], WheelSignal::Angle),
            _ => {
                let r = find(table, names.speed[0]);
                let l = find(table, names.speed[1]);
                match (r, l) {
                    (Some(r), Some(l)) => ([r, l], WheelSignal::Speed),
                    _ => {
                        // Name the wheel whose measurement is missing: the other angle if
                        // one angle is there, else the missing speed.
                        let side = match (find(table, names.angle[0]), find(table, names.angle[1]), r) {
                            (Some(_), None, _) => 1,
                            (None, Some(_), _) => 0,
                            (_, _, None) => 0,
                            _ => 1,
                        };
                        return Err(IdentifyError::MissingColumn {
                            column: format!(
                                "{} (or {})",
                                names.angle[side].join(" or "),
                                names.speed[side].join(" or ")
                            ),
                        });
                    }
                }
            }
        };
        let pose = match (find(table, names.pose[0]), find(table, names.pose[1]), find(table, names.pose[2])) {
            (Some(x), Some(y), Some(th)) => Some([x, y, th]),
            _ => None,
        };
        let run_col = find(table, names.run);
        let n = table.rows();
        // Every value the fit uses must be finite: name the first bad one with its time.
        for i in 0..n {
            if !t[i].is_finite() {
                return Err(IdentifyError::NotFinite { column: t_name.to_owned(), t_s: t[i], row: i + 1 });
            }
            let mut checked: Vec<(&str, &[f64])> = vec![cmd[0], cmd[1], wheel[0], wheel[1]];
            if let Some(p) = &pose {
                checked.extend_from_slice(p);
            }
            if let Some(r) = run_col {
                checked.push(r);
            }
            for (name, col) in checked {
                if !col[i].is_finite() {
                    return Err(IdentifyError::NotFinite { column: name.to_owned(), t_s: t[i], row: i + 1 });
                }
            }
        }
        let mut runs: Vec<Run> = Vec::new();
        let mut prev_run: Option<f64> = None;
        for i in 0..n {
            let run_id = run_col.map_or(0.0, |(_, c)| c[i]);
            if prev_run != Some(run_id) {
                let index = if run_id >= 0.0 && run_id.fract() == 0.0 { run_id as usize } else { runs.len() };
                runs.push(Run {
                    index,
                    t_s: Vec::new(),
                    command: [Vec::new(), Vec::new()],
                    wheel: [Vec::new(), Vec::new()],
                    pose: pose.map(|_| [Vec::new(), Vec::new(), Vec::new()]),
                });
                prev_run = Some(run_id);
            }
            let run = runs.last_mut().expect("pushed above");
            if let Some(&prev) = run.t_s.last()
                && t[i] <= prev
            {
                return Err(IdentifyError::NonMonotonicTime {
                    column: t_name.to_owned(),
                    t_s: t[i],
                    t_prev_s: prev,
                    row: i + 1,
                });
            }
            run.t_s.push(t[i]);
            for w in 0..2 {
                run.command[w].push(cmd[w].1[i]);
                run.wheel[w].push(wheel[w].1[i]);
            }
            if let (Some(p), Some(rp)) = (&pose, run.pose.as_mut()) {
                for k in 0..3 {
                    rp[k].push(p[k].1[i]);
                }
            }
        }
        if n == 0 {
            return Err(IdentifyError::Read { detail: "the table has no rows".to_owned() });
        }
        let mut columns_used = vec![t_name.to_owned(), cmd[0].0.to_owned(), cmd[1].0.to_owned()];
        columns_used.extend([wheel[0].0.to_owned(), wheel[1].0.to_owned()]);
        Ok(Log { command: kind, wheel: signal, columns_used, runs })
    }

    /// Number of samples over all runs.
    pub fn samples(&self) -> usize {
        self.runs.iter().map(|r| r.t_s.len()).sum()
    }
}
