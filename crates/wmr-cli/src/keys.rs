//! `wmr-cli help keys [TABLE]`: every scenario key with its unit, default and rule, the tables of the
//! core's parameters generated from their declarations (through [`wmr_scenario::schema()`]),
//! the MCAP topics from [`crate::foxglove_topics::Kind`]; docs/scenario.md has more.

use std::fmt::Write as _;

use wmr_core::OUTCOME_FIELDS;
use wmr_scenario::keys::{toml_scalar, toml_scalar_rounded};
use wmr_scenario::{ColumnGroup, SchemaKey, schema, sweep_columns, tracking_sweep_columns};

use crate::foxglove_topics::{Kind, Schemas};

/// Column at which a key's description starts.
const TEXT_COLUMN: usize = 31;
/// Lines are wrapped before this column.
const WIDTH: usize = 100;

/// The tables generated from the schema, each with its note for the header line.
const TABLES: [(&str, &str); 6] = [
    ("robot", "SI units"),
    ("drive", ""),
    (
        "controller",
        "an outer law (kind) and a wheel stage; each kind accepts only its own law keys plus the wheel-stage keys and control_dt",
    ),
    ("sensor", "what the controller sees; no table = perfect and instant"),
    ("world", "x and y lie in the ground plane"),
    // The note names the laws that need a reference, from the registry: `reference_note`.
    ("reference", ""),
];

/// The `[reference]` table's note: the laws that follow one, from the registry, and the
/// one a scenario gets when its `[controller]` names no `kind`.
fn reference_note() -> String {
    let kinds = wmr_scenario::tracking_law_kinds();
    format!(
        "a moving reference for {}; no table = each run's goal, at rest; with one, [controller] kind defaults \
         to {}",
        kinds.join(", "),
        kinds.first().copied().unwrap_or("?")
    )
}

const HEAD: &str = r#"SCENARIO FILE (TOML; every key optional except [[run]]; unknown keys are errors)

name = "fig7"                  scenario name (default: the file's stem)
"#;

/// The tables the core does not declare (`wmr-scenario`'s own file types).
const SIM: &str = r#"[sim]
  t_end = 60.0                 s per run; a whole multiple of dt; <= 1e6 s and <= 1e9 steps
  dt = 1e-3                    s, RK4 step (default: controller.control_dt)
  log_dt = 0.01                s, output sample period; a whole multiple of dt
  stop_when_settled = false    stop a run once settled: law holding, at rest within 1 cm
  early_arrival = false        with stop_when_settled: stop after 0.1 s of dying motion, not 1 s
  tracking_tolerance = 0.01    m; a tracking run converges when its error stays below this over the last 10 % of t_end
  xy_goal_tolerance = 0.01     m; a run towards a goal is docked when it ends with C within this of the goal (nav2's name)
  yaw_goal_tolerance_deg = 1.0 deg; ... and its heading within this of the goal's
"#;

const RUN: &str = r#"[[run]]                        one or more
  label = "..."                text for the summary (default: built from start and goal)
  start = { x = 0.0, y = 0.0, theta_deg = 0.0 }   m, m, and theta (rad) or theta_deg, not both; default 0
  goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }  required (refused with a [reference]); missing x, y, theta are 0
"#;

const SWEEP: &str = r#"[sweep]                        wmr-cli sweep: every law from every start ([[run]] optional)
  goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }    goal pose of C (default origin, 0)
  controllers = [{ kind = "paper" }, { kind = "paper_bidirectional" }, { kind = "polar" }, { kind = "lyapunov" }]
                               laws to compare, each with its [controller] keys (default: these)
  grid = { x_min = -2.0, x_max = 2.0, nx = 21, y_min = -2.0, y_max = 2.0, ny = 21, theta_deg = [0.0] }
  references = [{ kind = "circle", radius = 1.0, speed = 0.3 }, { kind = "figure_eight" }]
                               a sweep over references (each a [reference] table): every
                               tracking law on each; grid/random starts are offsets from its
                               start pose (x along its heading, y to its left); no goal
  random = { n = 1000, seed = 1, radius = 2.0, min_radius = 0.1, max_heading_deg = 180.0 }
  vary = [{ key = "sensor.latency", values = [0.0, 0.05] }, { key = "world.slope_deg", uniform = [0, 5] }]
                               robustness: vary keys of [robot], [drive], [controller] (and
                               controller.model), [sensor], [world]: values one at a time, or
                               uniform = [low, high] / normal = [mean, std] drawn per run
  trials = 1                   runs per (law, start, value), each with its own noise and draws
  seed = 0                     seed of the per-run draws
                               exactly one of grid (m, deg) and random (m; heading uniform)
"#;

const OUTPUTS_HEAD: &str = "OUTPUTS\n";

const OUTPUTS_SUMMARY: &str = r#"  Summary (stdout, one line per run): label, final dl (m), final heading error (deg),
        time from which dl < 1 cm (s or "never"), converged / diverged / unsettled.
        Converged = not diverged and final dl < 1 cm (and |heading error| <= 5 deg for
        lyapunov and paper_bidirectional); unsettled = neither by t_end; a tracking run
        whose reference asks more than the robot can give: cannot_follow.
"#;

const OUTPUTS_TAIL: &str = r#"  plot:  DIR/paths.svg, DIR/run<i>-wheel-speeds.svg, DIR/run<i>-errors.svg.

A diverged run (state not finite, or C outside a 1 km box) keeps its rows up to that
point, is reported as diverged, and the exit code stays 0. Bad input exits with 2 and
one message naming the key; no output file is written. A failed write (full disk) exits
with 1; SIGINT, SIGTERM and SIGHUP leave OUT as it was. OUT may be `-` (stdout), a device
or a FIFO (streamed); its directory must exist. Limits: 16 MiB per file, 1e11 plant steps
per scenario, starts and goals within 1000 m. Full reference: docs/scenario.md
"#;

/// The run CSV's columns, one line per group ([`ColumnGroup::ALL`]) with the runs that
/// carry it.
fn push_run_csv(out: &mut String) {
    out.push_str("  CSV:  one row per run and sample (t = 0, every log_dt, and the last); SI units, radians:\n");
    for g in ColumnGroup::ALL {
        let names =
            if g == ColumnGroup::Sample { format!("run, {}", g.names().join(", ")) } else { g.names().join(", ") };
        push_line(out, &format!("        {}", g.name()), &format!("{names} ({})", g.carried_by()));
    }
}

/// The sweep CSVs' columns and every outcome field with its unit and meaning, from the
/// table of outcome fields ([`OUTCOME_FIELDS`]).
fn push_sweep(out: &mut String) {
    push_line(out, "  sweep: CSV", &sweep_columns().join(", "));
    push_line(out, "        over references", &tracking_sweep_columns().join(", "));
    out.push_str(
        "        then one column per varied key; a comparison table on stdout; --plots DIR:\n        \
         region-<law>.svg per law; --fast: runs in SIMD lanes, not bit-identical\n        \
         (docs/scenario.md, \"The fast path\"). The outcome fields (also Python's):\n",
    );
    for f in &OUTCOME_FIELDS {
        push_line(out, &format!("        {}", f.name), f.doc);
    }
}

/// Appends `head` padded to [`TEXT_COLUMN`] and `text` wrapped at [`WIDTH`].
fn push_line(out: &mut String, head: &str, text: &str) {
    let mut line = head.to_owned();
    if text.is_empty() {
        out.push_str(line.trim_end());
        out.push('\n');
        return;
    }
    if line.len() + 1 > TEXT_COLUMN {
        out.push_str(&line);
        out.push('\n');
        line.clear();
    }
    let pad = |line: &mut String| line.extend(std::iter::repeat_n(' ', TEXT_COLUMN - line.len()));
    pad(&mut line);
    let mut first = true;
    for word in text.split(' ') {
        if !first && line.len() + 1 + word.len() > WIDTH {
            out.push_str(&line);
            out.push('\n');
            line.clear();
            pad(&mut line);
            first = true;
        }
        if !first {
            line.push(' ');
        }
        line.push_str(word);
        first = false;
    }
    out.push_str(&line);
    out.push('\n');
}

/// What a key is, its unit and its rule: `m, total mass, kg (> 0)`.
pub fn describe(k: &SchemaKey) -> String {
    let mut text = k.doc.trim_end_matches('.').to_owned();
    if !k.unit.is_empty() {
        let _ = write!(text, ", {}", k.unit);
    }
    let mut rule = k.rule.to_string();
    if let [(_, shown), others @ ..] = k.default_by_drive.as_slice() {
        for (kind, v) in others.iter().filter(|(_, v)| v != shown) {
            let _ = write!(rule, "; default {} with kind = \"{kind}\"", toml_scalar_rounded(v));
        }
    }
    if !rule.is_empty() {
        let _ = write!(text, " ({rule})");
    }
    text
}

/// The value shown after `key = `: the default, the first drive's where it follows the drive.
pub fn shown_default(k: &SchemaKey) -> Option<String> {
    k.default.as_ref().or(k.default_by_drive.first().map(|(_, v)| v)).map(toml_scalar)
}

/// The lines of one key at `indent`.
fn push_key(out: &mut String, indent: &str, k: &SchemaKey) {
    let head = match shown_default(k) {
        Some(v) => format!("{indent}{} = {v}", k.key),
        None => format!("{indent}{}", k.key),
    };
    push_line(out, &head, &describe(k));
}

/// One core table generated from the schema (`[robot]`, `[controller]`, ...), with its note.
fn table_section(table: &str, note: &str, keys: &[SchemaKey]) -> String {
    let mut out = String::new();
    let note = if table == "reference" { reference_note() } else { note.to_owned() };
    push_line(&mut out, &format!("[{table}]"), &note);
    let mut kind = None;
    let mut every_kind = false;
    for k in keys.iter().filter(|k| k.table == table) {
        if k.key == "model" {
            out.push('\n');
            push_line(&mut out, "[controller.model]", k.doc);
            continue;
        }
        if k.kind != kind {
            kind = k.kind;
            if let Some(name) = kind {
                let _ = writeln!(out, "  kind = \"{name}\":");
            }
        }
        let tagged = keys.iter().any(|o| o.table == table && o.kind.is_some());
        if tagged && kind.is_none() && k.key != "kind" && !every_kind {
            let _ = writeln!(out, "  every kind (the wheel stage):");
            every_kind = true;
        }
        let indent = if kind.is_some() || every_kind { "    " } else { "  " };
        push_key(&mut out, indent, k);
    }
    out
}

/// The MCAP topics, one line each, from [`Kind::ALL`] and the schemas the file carries.
fn push_topics(out: &mut String) {
    let schemas = Schemas::new(&wmr_scenario::Columns::default());
    out.push_str("  MCAP: per run N (0-based), log time = simulation time:\n");
    for kind in Kind::ALL {
        let head = format!("        /runN/{}", kind.name());
        push_line(out, &head, &format!("{}: {}", kind.schema(&schemas).name, kind.messages()));
    }
}

/// The sections of `wmr-cli help keys`, in order: the file's top level (`name`), each table
/// (`robot`, ..., `sweep`) and the outputs; `wmr-cli help keys TABLE` prints one.
pub fn sections() -> Vec<(&'static str, String)> {
    let keys = schema();
    let mut out = vec![("name", HEAD.to_owned())];
    out.extend(TABLES.iter().map(|(table, note)| (*table, table_section(table, note, &keys))));
    out.extend([("sim", SIM.to_owned()), ("run", RUN.to_owned()), ("sweep", SWEEP.to_owned())]);
    let mut outputs = String::from(OUTPUTS_HEAD);
    push_run_csv(&mut outputs);
    push_topics(&mut outputs);
    outputs.push_str(OUTPUTS_SUMMARY);
    push_sweep(&mut outputs);
    outputs.push_str(OUTPUTS_TAIL);
    out.push(("outputs", outputs));
    out
}

/// What `--help` says after the options: where the scenario file's keys are, and the
/// names `help keys` takes (from [`sections`]).
pub fn keys_hint() -> String {
    let names: Vec<&str> = sections().iter().map(|(n, _)| *n).collect();
    format!(
        "The scenario file's keys, with units and defaults: wmr-cli help keys [TABLE] (TABLE: {}); \
         docs/scenario.md has more.",
        names.join(", ")
    )
}

/// `wmr-cli help keys`: every section, a blank line between two.
pub fn keys_help() -> String {
    sections().into_iter().map(|(_, text)| text).collect::<Vec<_>>().join("\n")
}

/// `wmr-cli help keys [TABLE]`: every section, or the one named (`robot`, `[robot]`,
/// `run`, `[[run]]`); an unknown name is an error listing the names.
pub fn keys_help_of(table: Option<&str>) -> Result<String, String> {
    let Some(asked) = table else { return Ok(keys_help()) };
    let name = asked.trim_start_matches('[').trim_end_matches(']');
    let all = sections();
    match all.iter().find(|(n, _)| *n == name) {
        Some((_, text)) => Ok(text.clone()),
        None => {
            let names: Vec<&str> = all.iter().map(|(n, _)| *n).collect();
            Err(format!("help keys: no section {asked:?} (expected one of {})", names.join(", ")))
        }
    }
}
