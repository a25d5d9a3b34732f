//! What one scenario may ask for, checked before any work starts, so that a file (typed
//! by hand, downloaded, or mutated by a fuzzer) gets one clear error instead of an
//! exhausted memory, a disk filled for hours or a process that never ends:
//!
//! - the file: a regular file of at most [`MAX_FILE_BYTES`], UTF-8 text;
//! - every start and goal inside the box a run may not leave
//!   ([`wmr_core::plant::DIVERGENCE_BOX_M`]);
//! - the work: at most [`MAX_TOTAL_STEPS`] plant steps over all runs of one scenario
//!   (with [`crate::MAX_STEPS`] per run and [`crate::MAX_SWEEP_RUNS`] per sweep);
//! - warnings for what is valid but probably not meant (a heading of 90 rad).

use std::fs::File;
use std::io::{self, Read as _};
use std::path::Path;

use toml::Value;
use wmr_core::Pose2;
use wmr_core::plant::DIVERGENCE_BOX_M;

use crate::error::{ScenarioError, escape_controls, num};
use crate::locate;
use crate::run::RunSpec;
use crate::scenario::Scenario;

/// Largest scenario file read, bytes (16 MiB: a million `[[run]]`s fit).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// Most plant steps (all runs together, or all (law, start) runs of a sweep) one
/// scenario may ask for: 1e11, about 28 hours of one core at the core's ~1 us per step.
/// Larger studies are split into several files.
pub const MAX_TOTAL_STEPS: u64 = 100_000_000_000;

/// A path as it may be shown in a message: control characters escaped.
pub fn shown(path: &Path) -> String {
    escape_controls(&path.display().to_string())
}

/// The scenario name a file gets when it has no `name`: its stem (`fig7` for
/// `examples/paper/fig7.toml`), or `scenario`.
pub fn default_name(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scenario".to_owned())
}

/// Reads a scenario file: a regular file (not a FIFO, a device or a directory, which
/// could block or never end) of at most [`MAX_FILE_BYTES`], UTF-8 text. Errors name the
/// path; for a file that cannot be opened, [`ScenarioError::io`] holds the reason.
pub fn read_text(path: &Path) -> Result<String, ScenarioError> {
    let name = shown(path);
    let io_err = |e: io::Error| ScenarioError::unreadable(e.kind(), format!("cannot read {name}: {e}"));
    let meta = std::fs::metadata(path).map_err(io_err)?;
    if meta.is_dir() {
        return Err(ScenarioError::unreadable(
            io::ErrorKind::IsADirectory,
            format!("cannot read {name}: it is a directory, not a scenario file"),
        ));
    }
    if !meta.is_file() {
        return Err(ScenarioError::unreadable(
            io::ErrorKind::InvalidInput,
            format!("cannot read {name}: not a regular file (a FIFO, a device or a socket); give a scenario file"),
        ));
    }
    let too_big = |len: u64| {
        ScenarioError::new(
            "",
            format!("{name} is {len} bytes: a scenario file may be at most {} MiB", MAX_FILE_BYTES >> 20),
        )
    };
    if meta.len() > MAX_FILE_BYTES {
        return Err(too_big(meta.len()));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    // The file may grow while it is read: never read more than the limit.
    File::open(path).and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)).map_err(io_err)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_big(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        ScenarioError::new("", format!("{name} is not UTF-8 text (a bad byte at offset {at})")).at_line(Some(line))
    })
}

/// Checks that a pose of C lies inside the box a run may not leave; `key` is the pose's
/// path (`run[0].start`).
pub(crate) fn check_in_box(key: &str, pose: Pose2<f64>) -> Result<(), ScenarioError> {
    for (axis, v) in [("x", pose.x), ("y", pose.y)] {
        if !v.is_finite() {
            return Err(ScenarioError::new(
                format!("{key}.{axis}"),
                format!("must be a finite number (got {})", num(v)),
            ));
        }
        if v.abs() > DIVERGENCE_BOX_M {
            return Err(ScenarioError::new(
                format!("{key}.{axis}"),
                format!(
                    "must be within {DIVERGENCE_BOX_M} m of the origin (got {}): a run whose |x| or |y| \
                     passes {DIVERGENCE_BOX_M} m counts as diverged",
                    num(v)
                ),
            ));
        }
    }
    Ok(())
}

/// Every run's start and goal inside the box.
pub(crate) fn check_runs(runs: &[RunSpec]) -> Result<(), ScenarioError> {
    for (i, run) in runs.iter().enumerate() {
        check_in_box(&format!("run[{i}].start"), run.start)?;
        check_in_box(&format!("run[{i}].goal"), run.goal)?;
    }
    Ok(())
}

/// Plant steps of all the scenario's runs and sweep runs.
pub fn total_steps(scenario: &Scenario) -> u128 {
    let per_run = u128::from(scenario.sim().n_steps());
    let runs = scenario.runs().len() as u128 + scenario.sweep().map_or(0, |s| s.len() as u128);
    per_run * runs
}

/// The limits every scenario is held to after it is resolved: poses in the box, total
/// work at most [`MAX_TOTAL_STEPS`].
pub(crate) fn check(scenario: &Scenario) -> Result<(), ScenarioError> {
    check_runs(scenario.runs())?;
    let total = total_steps(scenario);
    if total > u128::from(MAX_TOTAL_STEPS) {
        let sim = scenario.sim();
        let runs = scenario.runs().len() + scenario.sweep().map_or(0, |s| s.len());
        let most = MAX_TOTAL_STEPS / sim.n_steps().max(1);
        return Err(ScenarioError::new(
            "sim.t_end",
            format!(
                "{runs} runs x {} steps (t_end / dt) = {total:.3e} plant steps, more than the limit of {:.0e} \
                 (about a day of CPU): shorten sim.t_end, raise sim.dt, or split the {runs} runs into files \
                 of at most {most}",
                sim.n_steps(),
                MAX_TOTAL_STEPS as f64,
            ),
        ));
    }
    Ok(())
}

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

/// Memory the operating system says a new allocation can get without swapping, bytes
/// (`MemAvailable` of `/proc/meminfo`); `None` where that is not known.
pub fn available_memory_bytes() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}
