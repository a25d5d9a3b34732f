//! `[reference]`: the moving reference of a tracking or path-following scenario, parsed
//! and checked into the core's [`AnyReference`]; the key table it accepts (one list, read
//! by the parser, `check` and the docs); which laws go with which reference.
//!
//! No `[reference]` table: each run's goal, at rest (point stabilization, as before).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use std::sync::Arc;
use toml::{Table, Value};
use wmr_core::reference::{Circle, FigureEight, Line, Waypoints};
use wmr_core::{AnyReference, LawParams, Pose2};

use crate::error::{ScenarioError, fixed};
use crate::files::FileAccess;

/// One key of `[reference]`: the kinds that read it, unit, default and what it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceKey {
    /// The key (`reference.<name>`).
    pub name: &'static str,
    /// The kinds that read it.
    pub kinds: &'static str,
    /// Unit (`""` for none).
    pub unit: &'static str,
    /// Default, as written in TOML (`""`: required).
    pub default: &'static str,
    /// What it is.
    pub doc: &'static str,
}

/// Every key of `[reference]`, in documentation order.
pub const REFERENCE_KEYS: &[ReferenceKey] = &[
    ReferenceKey {
        name: "kind",
        kinds: "all",
        unit: "",
        default: "",
        doc: "circle, figure_eight, line, waypoints or file",
    },
    ReferenceKey {
        name: "center",
        kinds: "circle, figure_eight",
        unit: "m",
        default: "{ x = 0.0, y = 0.0 }",
        doc: "center of the figure (world frame)",
    },
    ReferenceKey { name: "radius", kinds: "circle", unit: "m", default: "1.0", doc: "radius, > 0" },
    ReferenceKey {
        name: "speed",
        kinds: "circle, figure_eight, line, waypoints, file",
        unit: "m/s",
        default: "0.3",
        doc: "circle: > 0 counter-clockwise, < 0 clockwise; line: along the heading (< 0 backwards); waypoints, file: the peak speed, > 0; figure_eight: the peak speed pi sqrt(width^2 + 4 height^2) / period, > 0, instead of period (no default)",
    },
    ReferenceKey {
        name: "phase_deg",
        kinds: "circle",
        unit: "deg",
        default: "-90.0",
        doc: "angle of (C_ref - center) at t = 0",
    },
    ReferenceKey { name: "width", kinds: "figure_eight", unit: "m", default: "2.0", doc: "extent along x, > 0" },
    ReferenceKey { name: "height", kinds: "figure_eight", unit: "m", default: "1.0", doc: "extent along y, > 0" },
    ReferenceKey {
        name: "period",
        kinds: "figure_eight",
        unit: "s",
        default: "30.0",
        doc: "time for one figure, > 0; or give speed",
    },
    ReferenceKey {
        name: "start",
        kinds: "line",
        unit: "m, deg",
        default: "{ x = 0.0, y = 0.0, theta_deg = 0.0 }",
        doc: "pose at t = 0",
    },
    ReferenceKey {
        name: "points",
        kinds: "waypoints, file",
        unit: "m",
        default: "",
        doc: "[[x, y], ...], 2 to 1,000,000 points, none the same as the one before; file: the points read from path, \
              which a resolved scenario writes beside it so that it runs without the file (path is then not read)",
    },
    ReferenceKey {
        name: "accel_max",
        kinds: "waypoints, file",
        unit: "m/s^2",
        default: "0.5",
        doc: "bound on |acceleration| (tangential and centripetal together), > 0",
    },
    ReferenceKey {
        name: "path",
        kinds: "file",
        unit: "",
        default: "",
        doc: "CSV with columns t, x, y (a header line, t increasing), relative to the scenario file, in its folder or below",
    },
];

/// The values of `[reference] kind`: the core's moving kinds (its list,
/// [`AnyReference::KINDS`], but the goal at rest, which is no `[reference]`), and `file`,
/// a waypoints path read from a CSV.
pub fn kinds() -> Vec<&'static str> {
    let moving = RunReference::KINDS.iter().copied().filter(|&k| k != "goal");
    moving.chain(["file"]).collect()
}

/// The keys `kind` reads (besides `kind`).
fn keys_of(kind: &str) -> Vec<&'static str> {
    REFERENCE_KEYS
        .iter()
        .filter(|k| k.name != "kind" && k.kinds.split(", ").any(|c| c == kind))
        .map(|k| k.name)
        .collect()
}

/// A scenario's reference: a waypoints path of any length (up to [`MAX_PATH_POINTS`])
/// in shared storage, which a sweep's runs and a Python object's copies share.
pub type RunReference = AnyReference<f64, Arc<[f64]>>;

/// The most points a `waypoints` or `file` path holds (the core's own fixed storage,
/// and so the firmware and a trace, hold 64; here the storage is allocated): 1,000,000
/// points take 37 words each, 296 MB. A recorded path is usually far shorter (an hour at
/// 50 Hz is 180,000 poses).
pub const MAX_PATH_POINTS: usize = 1_000_000;

/// `[reference]`, checked.
#[derive(Clone, Debug)]
pub struct ReferenceSpec {
    /// The table as written (for the resolved-scenario dump), with a `file` reference's
    /// points as read (`points`), so that the dump runs without the file.
    pub table: Table,
    /// The reference.
    pub built: RunReference,
}

/// Two references are equal when they are the same reference: a table with its
/// defaults written out (`wmr-cli check`'s, a resolved scenario's) equals the table that
/// left them out.
impl PartialEq for ReferenceSpec {
    fn eq(&self, other: &Self) -> bool {
        self.built == other.built
    }
}

fn key(k: &str) -> String {
    format!("reference.{k}")
}

fn number(t: &Table, k: &str, default: f64) -> Result<f64, ScenarioError> {
    match t.get(k) {
        None => Ok(default),
        Some(v) => {
            let x = match v {
                Value::Float(f) => *f,
                Value::Integer(i) => *i as f64,
                other => {
                    return Err(ScenarioError::new(key(k), format!("must be a number (got {})", other.type_str())));
                }
            };
            if x.is_finite() {
                Ok(x)
            } else {
                Err(ScenarioError::new(key(k), format!("must be a finite number (got {x})")))
            }
        }
    }
}

/// `{ x = .., y = .. }` (and `theta_deg` where `with_theta`); missing parts are 0.
fn point(t: &Table, k: &str, with_theta: bool) -> Result<Pose2<f64>, ScenarioError> {
    let Some(v) = t.get(k) else { return Ok(Pose2::default()) };
    let Value::Table(p) = v else {
        return Err(ScenarioError::new(
            key(k),
            format!("must be a table like {{ x = 0.0, y = 0.0 }} (got {})", v.type_str()),
        ));
    };
    let allowed: &[&str] = if with_theta { &["x", "y", "theta_deg"] } else { &["x", "y"] };
    if let Some(bad) = p.keys().find(|n| !allowed.contains(&n.as_str())) {
        return Err(ScenarioError::new(
            format!("reference.{k}.{bad}"),
            format!("unknown key (expected one of {})", allowed.join(", ")),
        ));
    }
    let sub = |n: &str| number(p, n, 0.0).map_err(|e| ScenarioError::new(format!("reference.{k}.{n}"), e.message));
    Ok(Pose2::new(sub("x")?, sub("y")?, sub("theta_deg")?.to_radians()))
}

/// The core's error on a `[reference]` key, named in the scenario's terms.
fn core_error(e: &wmr_core::ParamError) -> ScenarioError {
    ScenarioError::from_param(e, &key(e.field))
}

/// The points of the `file` references read so far, by the path opened (or why it was
/// refused): a sweep naming one CSV in many references reads it once.
#[derive(Default)]
pub(crate) struct PointFiles(HashMap<PathBuf, Result<Vec<[f64; 2]>, ScenarioError>>);

/// Reads `[reference]`; `dir` is the scenario file's folder (where a `file` reference's
/// `path` is looked up; the working directory when `None`).
/// A `file` reference's CSV is read from that folder and below, and from the folders
/// `access` allows.
pub fn resolve(table: &Table, dir: Option<&Path>, access: &FileAccess) -> Result<ReferenceSpec, ScenarioError> {
    resolve_sharing(table, dir, access, &mut PointFiles::default())
}

/// [`resolve`], a `file` reference's points taken from `files` when its CSV was read
/// before (and added to it otherwise).
pub(crate) fn resolve_sharing(
    table: &Table,
    dir: Option<&Path>,
    access: &FileAccess,
    files: &mut PointFiles,
) -> Result<ReferenceSpec, ScenarioError> {
    let kinds = kinds();
    let kind = match table.get("kind") {
        Some(Value::String(s)) => s.as_str(),
        Some(v) => return Err(ScenarioError::new(key("kind"), format!("must be a string (got {})", v.type_str()))),
        None => return Err(ScenarioError::new(key("kind"), format!("missing: {}", one_of(&kinds)))),
    };
    if !kinds.contains(&kind) {
        return Err(ScenarioError::new(
            key("kind"),
            format!("unknown kind {kind:?} (expected one of {})", kinds.join(", ")),
        ));
    }
    let allowed = keys_of(kind);
    if let Some(bad) = table.keys().find(|k| *k != "kind" && !allowed.contains(&k.as_str())) {
        return Err(ScenarioError::new(
            key(bad),
            format!("unknown key for kind = {kind:?} (expected one of {})", allowed.join(", ")),
        ));
    }
    let mut stored = table.clone();
    let built = match kind {
        "circle" => {
            let c = point(table, "center", false)?;
            let phase = number(table, "phase_deg", -90.0)?.to_radians();
            let r = Circle::new(c.x, c.y, number(table, "radius", 1.0)?, number(table, "speed", 0.3)?, phase);
            AnyReference::Circle(r.map_err(|e| core_error(&e))?)
        }
        "figure_eight" => {
            let c = point(table, "center", false)?;
            let (width, height) = (number(table, "width", 2.0)?, number(table, "height", 1.0)?);
            let by_speed = table.contains_key("speed");
            let period = match (table.contains_key("period"), by_speed) {
                (true, true) => {
                    return Err(ScenarioError::new(
                        key("speed"),
                        "give period or speed, not both (the peak speed is pi sqrt(width^2 + 4 height^2) / period)",
                    ));
                }
                (false, true) => {
                    let speed = number(table, "speed", 0.0)?;
                    if speed <= 0.0 {
                        return Err(ScenarioError::new(key("speed"), format!("must be > 0 (got {speed})")));
                    }
                    figure_eight_period(width, height, speed)
                }
                _ => number(table, "period", 30.0)?,
            };
            let f = FigureEight::new(c.x, c.y, width, height, period).map_err(|e| {
                if by_speed && e.field == "period" {
                    ScenarioError::from_param(&e, &key("speed"))
                } else {
                    core_error(&e)
                }
            });
            AnyReference::FigureEight(f?)
        }
        "line" => {
            let start = point(table, "start", true)?;
            let l = Line::new(start, number(table, "speed", 0.3)?).map_err(|e| {
                let field = e.field.strip_prefix("start.").unwrap_or(e.field);
                ScenarioError::from_param(
                    &e,
                    &if e.field.starts_with("start.") { format!("reference.start.{field}") } else { key(e.field) },
                )
            })?;
            AnyReference::Line(l)
        }
        _ => {
            // A file reference's points, once read, are kept in its table: the resolved
            // scenario (`check`, Python's `scenario_toml`, an executor's parts) then holds
            // them and runs again anywhere, without the file.
            let from_file = kind == "file" && !table.contains_key("points");
            let points = if from_file { read_points_file(table, dir, access, files)? } else { points_of(table)? };
            let points_key = if from_file { "path" } else { "points" };
            if points.len() > MAX_PATH_POINTS {
                return Err(ScenarioError::new(
                    key(points_key),
                    format!(
                        "{} points, more than the limit of {MAX_PATH_POINTS}: thin the path (keep every k-th point; \
                         the spline through them is smooth)",
                        points.len()
                    ),
                ));
            }
            if from_file {
                let list = points.iter().map(|p| Value::Array(vec![Value::Float(p[0]), Value::Float(p[1])]));
                stored.insert("points".to_owned(), Value::Array(list.collect()));
            }
            let storage = vec![0.0; Waypoints::<f64, Vec<f64>>::words(points.len())];
            let w = Waypoints::new_in(&points, number(table, "speed", 0.3)?, number(table, "accel_max", 0.5)?, storage)
                .map_err(|e| {
                    if e.field == "points" { ScenarioError::from_param(&e, &key(points_key)) } else { core_error(&e) }
                })?;
            AnyReference::Waypoints(w.map_storage(Arc::from))
        }
    };
    Ok(ReferenceSpec { table: stored, built })
}

/// The period (s) of a figure-eight `width` x `height` (m) whose peak speed is `speed`
/// (m/s). With a = 2 pi / period, the speed is a sqrt((width/2)^2 cos^2(a t) + height^2
/// cos^2(2 a t)) (wmr_core::reference::FigureEight), largest at t = 0 where both cosines
/// are 1: pi sqrt(width^2 + 4 height^2) / period.
pub fn figure_eight_period(width: f64, height: f64, speed: f64) -> f64 {
    std::f64::consts::PI * width.hypot(2.0 * height) / speed
}

/// The table of `r` with every key its kind reads filled in (the given value, else the
/// default), and the keys in documentation order: what `wmr-cli check` prints. A
/// figure-eight keeps the one of `period` and `speed` it was given (`period` by default).
pub fn filled(r: &ReferenceSpec) -> (Table, Vec<&'static str>) {
    let kind = r.table.get("kind").and_then(Value::as_str).unwrap_or_default();
    let mut table = r.table.clone();
    let mut order = vec!["kind"];
    for k in REFERENCE_KEYS.iter().filter(|k| k.name != "kind" && k.kinds.split(", ").any(|c| c == kind)) {
        order.push(k.name);
        let other_given = |name: &str| r.table.contains_key(name);
        let skip = table.contains_key(k.name)
            || k.default.is_empty()
            || (kind == "figure_eight" && (k.name == "speed" || (k.name == "period" && other_given("speed"))));
        if skip {
            continue;
        }
        // The default as TOML text (`1.0`, `{ x = 0.0, y = 0.0 }`), read as a value.
        if let Ok(mut t) = format!("v = {}", k.default).parse::<Table>()
            && let Some(v) = t.remove("v")
        {
            table.insert(k.name.to_owned(), v);
        }
    }
    (table, order)
}

/// `points = [[x, y], ...]`.
fn points_of(table: &Table) -> Result<Vec<[f64; 2]>, ScenarioError> {
    let Some(v) = table.get("points") else {
        return Err(ScenarioError::new(key("points"), "missing: kind = \"waypoints\" needs points = [[x, y], ...]"));
    };
    let Value::Array(list) = v else {
        return Err(ScenarioError::new(key("points"), format!("must be an array of [x, y] (got {})", v.type_str())));
    };
    list.iter()
        .enumerate()
        .map(|(i, p)| {
            let bad = || ScenarioError::new(format!("reference.points[{i}]"), "must be [x, y], two finite numbers");
            let Value::Array(xy) = p else { return Err(bad()) };
            let n = |v: &Value| match v {
                Value::Float(f) if f.is_finite() => Some(*f),
                Value::Integer(k) => Some(*k as f64),
                _ => None,
            };
            match xy.as_slice() {
                [x, y] => Ok([n(x).ok_or_else(bad)?, n(y).ok_or_else(bad)?]),
                _ => Err(bad()),
            }
        })
        .collect()
}

/// The points of a `file` reference: CSV `t,x,y` with a header, t strictly increasing
/// (the timing is re-planned by the speed profile; t gives the order).
fn read_points_file(
    table: &Table,
    dir: Option<&Path>,
    access: &FileAccess,
    files: &mut PointFiles,
) -> Result<Vec<[f64; 2]>, ScenarioError> {
    let Some(Value::String(rel)) = table.get("path") else {
        return Err(ScenarioError::new(
            key("path"),
            "missing: kind = \"file\" needs path = \"ref.csv\" (columns t, x, y)",
        ));
    };
    let key = key("path");
    let (full, opened) = crate::files::check(&key, rel, dir.unwrap_or(Path::new("")), access)?;
    files.0.entry(full.clone()).or_insert_with(|| parse_points_file(&full, &opened)).clone()
}

/// The points of the CSV at `full`, refused at the first point past what a reference
/// holds (a long file is not parsed to its end).
fn parse_points_file(full: &Path, opened: &crate::files::Opened<'_>) -> Result<Vec<[f64; 2]>, ScenarioError> {
    let text = crate::read::read_text_within(full, Some(opened))
        .map_err(|e| if e.key.is_empty() { ScenarioError::new(key("path"), e.message) } else { e })?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    match lines.next() {
        Some((_, h)) if h.split(',').map(str::trim).eq(["t", "x", "y"]) => {}
        _ => {
            return Err(ScenarioError::new(
                key("path"),
                format!("{}: the first line must be the header t,x,y", full.display()),
            ));
        }
    }
    let mut points = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    for (i, line) in lines {
        let vals: Vec<f64> = line.split(',').map(|c| c.trim().parse::<f64>().unwrap_or(f64::NAN)).collect();
        let at = || format!("{} line {}", full.display(), i + 1);
        if vals.len() != 3 || vals.iter().any(|v| !v.is_finite()) {
            return Err(ScenarioError::new(key("path"), format!("{}: needs three finite numbers t,x,y", at())));
        }
        if vals[0] <= last_t {
            return Err(ScenarioError::new(
                key("path"),
                format!("{}: t must increase (got {} after {})", at(), vals[0], last_t),
            ));
        }
        last_t = vals[0];
        points.push([vals[1], vals[2]]);
        if points.len() > MAX_PATH_POINTS {
            return Err(ScenarioError::new(
                key("path"),
                format!(
                    "{}: more than {MAX_PATH_POINTS} points, the limit: thin the path (keep every k-th point; the \
                     spline through them is smooth)",
                    at()
                ),
            ));
        }
    }
    Ok(points)
}

/// `a, b or c`.
fn one_of(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// Refuses a stabilization law with a moving reference and a tracking law without one;
/// the error names `<controller>.kind`.
pub fn check_law(
    law: &LawParams<f64>,
    reference: Option<&ReferenceSpec>,
    controller: &str,
) -> Result<(), ScenarioError> {
    let k = format!("{controller}.kind");
    match (law.follows(), reference) {
        (f, None) if f.needs_reference() => Err(ScenarioError::new(
            k,
            format!("{:?} follows a moving reference: add a [reference] table ({})", law.kind(), kinds().join(", ")),
        )),
        (f, Some(r)) if !f.accepts_reference() => Err(ScenarioError::new(
            k,
            format!(
                "{:?} is a point-stabilization law and the [reference] ({}) moves: use {}",
                law.kind(),
                r.built.kind(),
                one_of(&crate::controller::reference_law_kinds())
            ),
        )),
        _ => Ok(()),
    }
}

/// One line describing the reference, for `wmr-cli check`.
pub fn describe(r: &ReferenceSpec) -> String {
    let p = r.built.start_pose();
    let extra = match &r.built {
        AnyReference::Waypoints(w) => {
            format!(", {} points, at rest again at t = {} s", w.len(), fixed(w.duration(), 3))
        }
        _ => String::new(),
    };
    format!(
        "reference: {} starting at ({}, {}, {} deg){extra}",
        r.table.get("kind").and_then(Value::as_str).unwrap_or(r.built.kind()),
        fixed(p.x, 4),
        fixed(p.y, 4),
        fixed(p.theta.to_degrees(), 2)
    )
}

#[cfg(test)]
mod tests {
    use super::{REFERENCE_KEYS, kinds};

    /// The key table names the kinds of the core's list and no other: a kind added to
    /// `wmr_core::reference::any` without its keys here (or a key for a kind that is
    /// gone) fails.
    #[test]
    fn the_key_table_covers_the_registered_kinds() {
        let kinds = kinds();
        let kind_doc = REFERENCE_KEYS.iter().find(|k| k.name == "kind").map(|k| k.doc).unwrap_or_default();
        assert_eq!(kind_doc, super::one_of(&kinds), "the doc of reference.kind lists the kinds");
        for k in REFERENCE_KEYS.iter().filter(|k| k.name != "kind") {
            for read_by in k.kinds.split(", ") {
                assert!(kinds.contains(&read_by), "reference.{} is read by {read_by:?}, no kind", k.name);
            }
        }
        for kind in &kinds {
            assert!(
                REFERENCE_KEYS.iter().any(|k| k.kinds.split(", ").any(|c| c == *kind)),
                "kind {kind:?} reads no key of REFERENCE_KEYS"
            );
        }
    }
}
