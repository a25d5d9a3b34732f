//! What is valid but probably not meant, found in the text of a scenario and shown as
//! warnings: a heading `theta` (radians) of more than a full turn.

use toml::Value;

use crate::error::{ScenarioError, num};
use crate::locate;

/// Valid but probably not meant: a heading `theta` (radians) larger than a full turn,
/// which usually is a heading in degrees (`theta = 90`). One [`ScenarioError`] per
/// finding, with key and line, to be shown as a warning.
pub fn warnings(text: &str) -> Vec<ScenarioError> {
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
            found.push(
                ScenarioError::new(
                    key,
                    format!(
                        "{} rad is {:.1} turns; theta is in radians: for degrees write theta_deg = {}",
                        num(theta),
                        theta.abs() / std::f64::consts::TAU,
                        num(theta)
                    ),
                )
                .at_line(line),
            );
        }
    }
    found
}
