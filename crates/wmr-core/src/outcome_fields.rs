//! The figures of a run's outcome as every output names them: one table, read by the
//! sweep CSVs, Python's arrays and `RunResult` attributes, the CLI's help and the docs.
//!
//! A name carries its unit as a suffix (`final_dl_m`, `final_heading_error_deg`), the
//! one spelling of every output. A new figure is one row here (and, if it needs a new
//! accumulator, its field in [`crate::Outcome`] or [`crate::tracking::TrackingOutcome`]).

use crate::Outcome;
use crate::tracking::TrackingOutcome;

/// Where a figure belongs, which decides the outputs that carry it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldGroup {
    /// The final pose and time: Python's arrays and `RunResult` (a run's own CSV has them
    /// in its last row; a sweep CSV does not).
    Final,
    /// How close a run came to its goal: the sweep CSV of a run towards a goal, Python.
    Goal,
    /// How a tracking run followed its reference (none for a run towards a goal): the
    /// sweep CSV over references, Python.
    Tracking,
    /// What a tracking run was judged with: Python's `RunResult` only.
    TrackingSetting,
    /// What the drives did: every sweep CSV, Python.
    Drive,
}

/// How a figure is read from a run's outcome.
#[derive(Clone, Copy, Debug)]
pub enum Read {
    /// From the outcome every run has.
    Run(fn(&Outcome<f64>) -> Option<f64>),
    /// From a tracking run's outcome (none for a run towards a goal).
    Tracking(fn(&TrackingOutcome<f64>) -> Option<f64>),
}

/// One figure of a run's outcome.
#[derive(Clone, Copy, Debug)]
pub struct OutcomeField {
    /// The name with its unit suffix: the CSV column, the Python array and attribute.
    pub name: &'static str,
    /// Its unit as the help and docs print it.
    pub unit: &'static str,
    /// What it is, one line.
    pub doc: &'static str,
    /// Which outputs carry it.
    pub group: FieldGroup,
    /// Whether a run that has the figure's group may still have no value (a time never
    /// reached): an empty CSV field, NaN in an array, None as an attribute.
    pub may_be_none: bool,
    /// How it is read.
    pub read: Read,
}

impl OutcomeField {
    /// The figure of a run, in [`OutcomeField::unit`]; `None` where the run has none (a time
    /// never reached, a tracking figure of a run towards a goal).
    pub fn value(&self, outcome: &Outcome<f64>, tracking: Option<&TrackingOutcome<f64>>) -> Option<f64> {
        match self.read {
            Read::Run(get) => get(outcome),
            Read::Tracking(get) => tracking.and_then(get),
        }
    }

    /// Whether the sweep CSV of a run towards a goal (`tracking` false) or over
    /// references (`tracking` true) has a column of it.
    pub fn in_sweep_csv(&self, tracking: bool) -> bool {
        match self.group {
            FieldGroup::Goal => !tracking,
            FieldGroup::Tracking => tracking,
            FieldGroup::Drive => true,
            FieldGroup::Final | FieldGroup::TrackingSetting => false,
        }
    }
}

/// Every figure of an outcome, in the order of every output (the sweep CSVs take theirs
/// in this order, [`OutcomeField::in_sweep_csv`]).
pub const OUTCOME_FIELDS: [OutcomeField; 16] = [
    OutcomeField {
        name: "final_x_m",
        unit: "m",
        doc: "position x of C at the end of the run (world frame)",
        group: FieldGroup::Final,
        may_be_none: false,
        read: Read::Run(|o| Some(o.final_pose.x)),
    },
    OutcomeField {
        name: "final_y_m",
        unit: "m",
        doc: "position y of C at the end of the run (world frame)",
        group: FieldGroup::Final,
        may_be_none: false,
        read: Read::Run(|o| Some(o.final_pose.y)),
    },
    OutcomeField {
        name: "final_theta_deg",
        unit: "deg",
        doc: "heading at the end of the run (world frame, counter-clockwise from x)",
        group: FieldGroup::Final,
        may_be_none: false,
        read: Read::Run(|o| Some(o.final_pose.theta.to_degrees())),
    },
    OutcomeField {
        name: "t_final_s",
        unit: "s",
        doc: "time of the last state (t_end unless the run diverged or settled)",
        group: FieldGroup::Final,
        may_be_none: false,
        read: Read::Run(|o| Some(o.t_final)),
    },
    OutcomeField {
        name: "time_to_1cm_s",
        unit: "s",
        doc: "first time from which C stays within 1 cm of the goal to the end (none: never)",
        group: FieldGroup::Goal,
        may_be_none: true,
        read: Read::Run(|o| o.time_to_arrival),
    },
    OutcomeField {
        name: "final_dl_m",
        unit: "m",
        doc: "final distance from C to the goal position",
        group: FieldGroup::Goal,
        may_be_none: false,
        read: Read::Run(|o| Some(o.final_dl)),
    },
    OutcomeField {
        name: "final_heading_error_deg",
        unit: "deg",
        doc: "final heading error, wrap(theta_goal - theta)",
        group: FieldGroup::Goal,
        may_be_none: false,
        read: Read::Run(|o| Some(o.final_heading_error.to_degrees())),
    },
    OutcomeField {
        name: "docked",
        unit: "",
        doc: "1 if the run ended within sim.xy_goal_tolerance of the goal position and sim.yaw_goal_tolerance_deg of its heading (final state, not diverged), else 0",
        group: FieldGroup::Goal,
        may_be_none: false,
        read: Read::Run(|o| Some(if o.docked() { 1.0 } else { 0.0 })),
    },
    OutcomeField {
        name: "time_to_tolerance_s",
        unit: "s",
        doc: "time after which the tracking error stays below sim.tracking_tolerance (none: above at the end)",
        group: FieldGroup::Tracking,
        may_be_none: true,
        read: Read::Tracking(|t| t.time_to_tolerance),
    },
    OutcomeField {
        name: "rms_error_m",
        unit: "m",
        doc: "RMS tracking error over the last half of t_end",
        group: FieldGroup::Tracking,
        may_be_none: false,
        read: Read::Tracking(|t| Some(t.rms_last_half)),
    },
    OutcomeField {
        name: "max_error_m",
        unit: "m",
        doc: "largest tracking error over the last half of t_end",
        group: FieldGroup::Tracking,
        may_be_none: false,
        read: Read::Tracking(|t| Some(t.max_last_half)),
    },
    OutcomeField {
        name: "final_error_m",
        unit: "m",
        doc: "tracking error at the last step",
        group: FieldGroup::Tracking,
        may_be_none: false,
        read: Read::Tracking(|t| Some(t.final_error)),
    },
    OutcomeField {
        name: "tracking_tolerance_m",
        unit: "m",
        doc: "the tolerance the tracking run was judged with (sim.tracking_tolerance)",
        group: FieldGroup::TrackingSetting,
        may_be_none: false,
        read: Read::Tracking(|t| Some(t.tolerance)),
    },
    OutcomeField {
        name: "peak_wheel_speed_rad_s",
        unit: "rad/s",
        doc: "largest |wheel speed| of the run",
        group: FieldGroup::Drive,
        may_be_none: false,
        read: Read::Run(|o| Some(o.peak_wheel_speed)),
    },
    OutcomeField {
        name: "path_length_m",
        unit: "m",
        doc: "path length of C, int |v| dt",
        group: FieldGroup::Drive,
        may_be_none: false,
        read: Read::Run(|o| Some(o.path_length)),
    },
    OutcomeField {
        name: "abs_work_j",
        unit: "J",
        doc: "work of both drives on their wheels, int (|tau_r omega_r| + |tau_l omega_l|) dt (braking counts as positive work)",
        group: FieldGroup::Drive,
        may_be_none: false,
        read: Read::Run(|o| Some(o.abs_work)),
    },
];

/// The fields of `group`, in table order.
pub fn fields_of(group: FieldGroup) -> impl Iterator<Item = &'static OutcomeField> {
    OUTCOME_FIELDS.iter().filter(move |f| f.group == group)
}

/// The outcome columns of a sweep CSV, in order: of a run towards a goal (`tracking`
/// false) or over references.
pub fn sweep_csv_fields(tracking: bool) -> impl Iterator<Item = &'static OutcomeField> {
    OUTCOME_FIELDS.iter().filter(move |f| f.in_sweep_csv(tracking))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_end_in_their_unit() {
        for (i, f) in OUTCOME_FIELDS.iter().enumerate() {
            assert!(OUTCOME_FIELDS[..i].iter().all(|g| g.name != f.name), "{} twice", f.name);
            let suffix = match f.unit {
                "m" => "_m",
                "s" => "_s",
                "deg" => "_deg",
                "rad/s" => "_rad_s",
                "J" => "_j",
                // A flag (1 or 0) has no unit and no suffix.
                "" => "",
                u => panic!("{}: unit {u} has no suffix rule", f.name),
            };
            assert!(f.name.ends_with(suffix), "{} does not end in {suffix}", f.name);
        }
    }
}
