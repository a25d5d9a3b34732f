//! Robot presets: `[robot] from = "robots/NAME.toml"` (a path relative to the scenario
//! file) or `from = "NAME"` (a preset built in from the repository's `robots/` folder)
//! brings a robot and its drive; keys written beside `from`, and in `[drive]`, override
//! it. [`Origins`] remembers where each given value came from, for `wmr-cli check`.

use std::path::Path;

use toml::{Table, Value};

use crate::error::ScenarioError;
use crate::files::FileAccess;
use crate::keys::unknown_key;
use crate::setup::robot_keys;

/// The built-in presets: name and the text of `robots/NAME.toml` (each file cites the
/// source of every number).
pub const BUILT_IN: [(&str, &str); 3] = [
    ("paper", include_str!("../../../robots/paper.toml")),
    ("turtlebot3_burger", include_str!("../../../robots/turtlebot3_burger.toml")),
    ("turtlebot3_waffle", include_str!("../../../robots/turtlebot3_waffle.toml")),
];

/// Where the given values of `[robot]` and `[drive]` came from: `(key, origin)`, origin
/// being `scenario` or the preset as written after `from`. A key not listed has its
/// default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Origins {
    /// `[robot]` keys.
    pub robot: Vec<(String, String)>,
    /// `[drive]` keys.
    pub drive: Vec<(String, String)>,
    /// The keys the file gives in the other tables (`[controller]`, `[sensor]`, `[world]`,
    /// `[reference]`), as `table.key`.
    pub given: Vec<String>,
    /// Why `[controller] kind` is what it is where the file does not give it and the
    /// default is not `paper`: a `[reference]` is followed by a law that follows it.
    pub law_note: Option<String>,
    /// The preset as written after `from` and its text, so that an error in one of its
    /// values can name the preset's line (issue 39 item 9).
    pub preset: Option<(String, String)>,
}

impl Origins {
    /// For a `[robot]` or `[drive]` key whose value a robot file written by `wmr-cli
    /// identify` gave (docs/identify.md): the fit's note of it in that file's comment,
    /// `fitted: +- 1.017e-5 (standard error), from log.csv` (or `fitted: below 0 ...`).
    /// `None` for a key held, given by the scenario, or of any other preset.
    pub fn fitted(&self, table: &str, key: &str) -> Option<&str> {
        let (label, text) = self.preset.as_ref()?;
        if self.of(table, key) != label.as_str() {
            return None;
        }
        let mut current = "";
        for line in text.lines().map(str::trim) {
            if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
                current = name.trim();
            } else if current == table
                && line.split('=').next().is_some_and(|k| k.trim() == key)
                && let Some((_, comment)) = line.split_once('#')
                && let Some(at) = comment.find("fitted:")
            {
                return Some(comment[at..].trim_end());
            }
        }
        None
    }

    /// The origin of `key` of `table`: for `robot` and `drive`, `scenario`, the preset or
    /// `default`; for the other tables, `scenario` or `default`.
    pub fn of(&self, table: &str, key: &str) -> &str {
        let list = match table {
            "robot" => &self.robot,
            "drive" => &self.drive,
            _ => {
                if table == "controller"
                    && key == "kind"
                    && let Some(n) = &self.law_note
                {
                    return n;
                }
                let given =
                    self.given.iter().any(|g| g.strip_prefix(table).and_then(|r| r.strip_prefix('.')) == Some(key));
                return if given { "scenario" } else { "default" };
            }
        };
        list.iter().find(|(k, _)| k == key).map_or("default", |(_, o)| o.as_str())
    }

    /// When `e` is about a `[robot]` or `[drive]` key whose value the preset gave: `e`
    /// saying so, with the preset's line (the caller puts it at the scenario's `from`
    /// line). `None` for every other error.
    pub(crate) fn in_preset(&self, e: &ScenarioError) -> Option<ScenarioError> {
        let (label, text) = self.preset.as_ref()?;
        let (table, rest) = e.key.split_once('.')?;
        let name = rest.split(['.', '[']).next().unwrap_or(rest);
        if !matches!(table, "robot" | "drive") || self.of(table, name) != label.as_str() {
            return None;
        }
        let built_in = if BUILT_IN.iter().any(|(n, _)| n == label) { " (built in)" } else { "" };
        let line = crate::locate::span_of_key(text, &e.key).map(|s| crate::locate::line_of(text, s.start));
        let at = line.map_or(String::new(), |l| format!(", line {l}"));
        let message = format!("{} (the value of the preset {label}{built_in}{at}, brought by robot.from)", e.message);
        Some(ScenarioError { message, ..e.clone() })
    }
}

fn from_error(reason: impl Into<String>) -> ScenarioError {
    ScenarioError::new("robot.from", reason)
}

/// The text of preset `from`: a built-in name, or a file relative to `dir`, in the
/// folders `access` allows.
fn preset_text(from: &str, dir: &Path, access: &FileAccess) -> Result<String, ScenarioError> {
    if let Some((_, text)) = BUILT_IN.iter().find(|(name, _)| *name == from) {
        return Ok((*text).to_owned());
    }
    let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
    if !from.ends_with(".toml") {
        return Err(from_error(format!(
            "no built-in robot \"{from}\"; the built-in ones are {}, or give a file (robots/NAME.toml, relative to the scenario)",
            names.join(", ")
        )));
    }
    let (path, opened) = crate::files::check("robot.from", from, dir, access)?;
    crate::read::read_text_within(&path, Some(&opened))
        .map_err(|e| if e.key.is_empty() { from_error(format!("{e}")) } else { e })
}

/// Replaces `[robot] from = ...` in `robot` and `drive` by the preset's keys under those
/// written beside it; returns where every given value came from. `dir`: the scenario's
/// folder (relative preset paths start there); a preset file is read from it and below,
/// and from the folders `access` allows.
pub fn expand(
    robot: &mut Option<Table>,
    drive: &mut Option<Table>,
    dir: &Path,
    access: &FileAccess,
) -> Result<Origins, ScenarioError> {
    let given = |t: &Option<Table>| -> Vec<(String, String)> {
        t.iter().flat_map(|t| t.keys()).filter(|k| *k != "from").map(|k| (k.clone(), "scenario".to_owned())).collect()
    };
    let mut origins = Origins { robot: given(robot), drive: given(drive), ..Origins::default() };
    let Some(from) = robot.as_mut().and_then(|t| t.remove("from")) else { return Ok(origins) };
    let Value::String(from) = from else {
        return Err(from_error(format!(
            "expected a string (a preset name or a robots/NAME.toml path), got {}",
            from.type_str()
        )));
    };
    let text = preset_text(&from, dir, access)?;
    origins.preset = Some((from.clone(), text.clone()));
    let mut preset: Table =
        toml::from_str(&text).map_err(|e| from_error(format!("{from}: bad TOML: {}", e.message().trim())))?;
    for key in preset.keys() {
        if key != "robot" && key != "drive" {
            return Err(from_error(format!("{from}: a preset holds [robot] and [drive] only, not {key}")));
        }
    }
    let mut table = |name: &str| -> Result<Table, ScenarioError> {
        match preset.remove(name) {
            None => Ok(Table::new()),
            Some(Value::Table(t)) => Ok(t),
            Some(v) => Err(from_error(format!("{from}: {name} must be a table, got {}", v.type_str()))),
        }
    };
    let (p_robot, p_drive) = (table("robot")?, table("drive")?);
    let fields = robot_keys(false);
    if let Some(k) = p_robot.keys().find(|k| !fields.contains(&k.as_str())) {
        let e = unknown_key("robot", k, fields);
        return Err(from_error(format!("{from}: {}: {}", e.key, e.message)));
    }
    let label = from.clone();
    // The robot: the preset's keys, then those of the scenario over them.
    let mut merged = p_robot.clone();
    merged.extend(robot.take().unwrap_or_default());
    for k in p_robot.keys() {
        if !origins.robot.iter().any(|(g, _)| g == k) {
            origins.robot.push((k.clone(), label.clone()));
        }
    }
    *robot = Some(merged);
    // The drive comes with the robot, unless the scenario picks another kind.
    let own = drive.take().unwrap_or_default();
    let kind = |t: &Table| t.get("kind").and_then(Value::as_str).unwrap_or("torque").to_owned();
    let same_kind = !own.contains_key("kind") || kind(&own) == kind(&p_drive);
    if same_kind && !p_drive.is_empty() {
        let mut merged = p_drive.clone();
        merged.extend(own);
        for k in p_drive.keys() {
            if !origins.drive.iter().any(|(g, _)| g == k) {
                origins.drive.push((k.clone(), label.clone()));
            }
        }
        *drive = Some(merged);
    } else {
        *drive = Some(own);
    }
    Ok(origins)
}
