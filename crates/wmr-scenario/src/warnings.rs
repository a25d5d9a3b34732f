//! What is valid but probably not meant, found in the text of a scenario and shown as
//! warnings: a heading `theta` (radians) of more than a full turn.

use toml::Value;

use crate::error::{ScenarioError, num};
use crate::locate;

/// Who wrote the scenario, so a hint is given in the words they can use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Writer {
    /// A TOML file: `theta_deg = 120`.
    Toml,
    /// Python, whose poses are dicts (`"theta_deg": 120`) or `(x, y, theta_rad)` tuples,
    /// where degrees cannot be written: `math.radians(120)`.
    Python,
}

/// Valid but probably not meant: a heading `theta` (radians) larger than a full turn,
/// which usually is a heading in degrees (`theta = 90`). One [`ScenarioError`] per
/// finding, with key and line, to be shown as a warning.
pub fn warnings(text: &str) -> Vec<ScenarioError> {
    warnings_for(text, Writer::Toml)
}

/// [`warnings`] with the hint in `writer`'s words.
pub fn warnings_for(text: &str, writer: Writer) -> Vec<ScenarioError> {
    let Ok(doc) = text.parse::<toml::Table>() else { return Vec::new() };
    let mut poses: Vec<(String, &Value)> = Vec::new();
    if let Some(Value::Array(runs)) = doc.get("run") {
        for (i, run) in runs.iter().enumerate() {
            for end in ["start", "goal"] {
                if let Some(p) = run.get(end) {
                    poses.push((format!("run[{i}].{end}"), p));
                }
            }
        }
    }
    if let Some(p) = doc.get("sweep").and_then(|s| s.get("goal")) {
        poses.push(("sweep.goal".to_owned(), p));
    }
    let mut found = Vec::new();
    for (path, pose) in poses {
        let theta = match pose.get("theta") {
            Some(Value::Float(f)) => *f,
            Some(Value::Integer(i)) => *i as f64,
            _ => continue,
        };
        if theta.abs() > std::f64::consts::TAU {
            let key = format!("{path}.theta");
            let line = locate::span_of_key(text, &key).map(|s| locate::line_of(text, s.start));
            let turns = theta.abs() / std::f64::consts::TAU;
            let message = match writer {
                Writer::Toml => format!(
                    "{} rad is {turns:.1} turns; theta is in radians: for degrees write theta_deg = {}",
                    num(theta),
                    num(theta)
                ),
                Writer::Python => format!(
                    "{} rad is {turns:.1} turns; a heading is in radians: if {} is degrees, give \
                     math.radians({}) = {:.6} (a tuple's third number is radians) or a dict with \"theta_deg\": {}",
                    num(theta),
                    num(theta),
                    num(theta),
                    theta.to_radians(),
                    num(theta)
                ),
            };
            found.push(ScenarioError::new(key, message).at_line(line));
        }
    }
    found
}
