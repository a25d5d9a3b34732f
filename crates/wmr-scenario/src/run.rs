//! One run as the scenario describes it: where C starts, where it should go, its label.

use wmr_core::Pose2;

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

impl RunSpec {
    /// A run with the default label, "(x0, y0, th0 deg) -> (x, y, th deg)".
    pub fn new(start: Pose2<f64>, goal: Pose2<f64>) -> Self {
        Self { label: default_label(&start, &goal), start, goal }
    }
}

/// A short human number for labels: at most 4 decimals, trailing zeros dropped.
pub(crate) fn short(v: f64) -> String {
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
