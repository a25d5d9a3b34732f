//! `wmr-cli sweep`: every (law, start) of a `[sweep]` in parallel, outcomes to CSV, a
//! comparison table on stdout, and optionally one region-of-attraction SVG per law.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use wmr_plot::{ShareSeries, SweepCell, region_svg, share_svg};
use wmr_scenario::robustness::{
    ShareCurve, drift_curves, drift_table, share_curves, share_table, varied_columns, varied_row,
};
use wmr_scenario::{
    Scenario, SweepOutcome, SweepSpec, docking_summary, docking_table, shown, summarize, summary_table, sweep_columns,
    sweep_row, tracking_summary, tracking_summary_table, tracking_sweep_columns, tracking_sweep_row,
};

use crate::atomic::{Output, write_text};
use crate::errors::{bad_input, is_broken_pipe, note, say_raw};
use crate::exec::announce_sweep;

/// Output bytes per sweep CSV row below which no row is written (a row holds a law
/// name, ten numbers and a status): the free-space check refuses only what surely
/// cannot fit.
const MIN_BYTES_PER_ROW: u64 = 60;

/// A file name made from `stem`: letters, digits, `.`, `_` and `-` kept, anything else
/// (path separators, spaces, control characters) `_`, no leading dot; `scenario` when
/// nothing is left. A file therefore never chooses where its default outputs go.
pub fn safe_file_stem(stem: &str) -> String {
    let s: String =
        stem.chars().map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) { c } else { '_' }).collect();
    let s = s.trim_start_matches('.');
    if s.is_empty() { "scenario".to_owned() } else { s.chars().take(100).collect() }
}

/// The default outcome CSV of `file`: `<stem>-sweep.csv` in the current folder, from the
/// file's name (never from the scenario's `name`, which the file's author chooses).
pub fn default_output(file: &Path) -> PathBuf {
    PathBuf::from(format!("{}-sweep.csv", safe_file_stem(&wmr_scenario::default_name(file))))
}

/// Runs the sweep of `scenario`, writes the outcome CSV to `out` and, with `plots`, one
/// `region-<law>.svg` per law into that folder; prints the comparison table. With `fast`,
/// the runs are stepped in SIMD lanes (`wmr_scenario::fast`).
pub fn sweep(
    scenario: &Scenario,
    file: &Path,
    out: &Path,
    plots: Option<&Path>,
    fast: bool,
    show_progress: bool,
) -> Result<()> {
    let Some(spec) = &scenario.sweep() else {
        return Err(bad_input(format!(
            "{}: sweep: the file has no [sweep] table (see `wmr-cli help keys sweep` for its keys; [[run]]s run with \
             `wmr-cli run`)",
            shown(file)
        )));
    };
    // The kernel `WMR_FAST_KERNEL` asks for is checked before any output is opened.
    let kernel = if fast { Some(wmr_scenario::fast::Kernel::detect()?) } else { None };
    // Every output is checked before the work: a bad path costs nothing.
    let output = Output::create(out)?;
    if let Some(free) = output.free_bytes() {
        let least = spec.len() as u128 * u128::from(MIN_BYTES_PER_ROW);
        if least > u128::from(free) {
            return Err(bad_input(format!(
                "{} would take at least {least} bytes ({} rows) but only {free} bytes are free there; write elsewhere",
                output.shown(),
                spec.len()
            )));
        }
    }
    let prepared = plots.map(crate::plot_cmd::prepare_dir).transpose()?;
    let what = match &spec.tracking {
        None => format!("{} laws x {} starts", spec.laws.len(), spec.starts.len()),
        Some(tr) => {
            format!("{} laws x {} references x {} starts", spec.laws.len(), tr.references.len(), spec.starts.len())
        }
    };
    // A sweep the lanes cannot run goes the exact way, and says so (no silent fallback).
    let refusal = if fast { spec.fast_refusal() } else { None };
    let fast = fast && refusal.is_none();
    if let Some(why) = refusal {
        note(&format!("wmr-cli: --fast: {why}"));
    }
    if spec.redrawn_starts > 0 {
        note(&format!(
            "wmr-cli: sweep.random: {} draws put the footprint on an obstacle and were drawn again",
            spec.redrawn_starts
        ));
    }
    announce_sweep(
        u128::from(scenario.sim().n_steps()) * spec.len() as u128,
        &what,
        fast,
        scenario.sim().stop_when_settled(),
        // Every law runs the same number of runs.
        spec.laws.iter().map(|(_, setup)| setup.controller.law.update_cost()).sum::<f64>()
            / spec.laws.len().max(1) as f64,
    );
    if let Some(kernel) = kernel {
        // Which vector unit the lanes run on: a figure measured here is not another CPU's.
        note(&format!("wmr-cli: --fast: {}", kernel.describe()));
    }
    let bar = if show_progress && spec.len() > 50 {
        let bar = ProgressBar::with_draw_target(Some(spec.len() as u64), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template("{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})")
        {
            bar.set_style(style);
        }
        bar.set_message(format!("{} runs", spec.len()));
        bar
    } else {
        ProgressBar::hidden()
    };
    let started = std::time::Instant::now();
    let outcomes =
        if fast { spec.run_fast(scenario.sim(), &|| bar.inc(1))? } else { spec.run(scenario.sim(), &|| bar.inc(1))? };
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();

    let to_stdout = output.is_stdout();
    let shown_out = output.shown().to_owned();
    // The CSV is written, then the figures, and only then renamed into place: a sweep
    // whose figures fail (a full disk) leaves OUT as it was, and no new folder.
    let output = write_csv(spec, &outcomes, output)?;
    let curves = share_curves(spec, &outcomes);
    if let (Some(dir), Some(prepared)) = (plots, prepared) {
        let mut written = Vec::new();
        let figures = write_regions(spec, &outcomes, dir, &mut written)
            .and_then(|()| write_share_curves(&curves, dir, &mut written))
            .and_then(|()| output.finish());
        match figures {
            Ok(()) => prepared.done(),
            Err(e) => {
                prepared.abandon(&written);
                return Err(e);
            }
        }
    } else {
        output.finish()?;
    }
    let summary = match &spec.tracking {
        None => summary_table(&summarize(spec, &outcomes)),
        Some(tr) => tracking_summary_table(&tracking_summary(spec, &outcomes), tr.tolerance),
    };
    // A sweep on odometry also shows how far the odometry drifted (nothing otherwise).
    let drift = drift_table(&drift_curves(spec, &outcomes));
    // A sweep towards a goal also shows how each law docked (nothing over references).
    let docking = docking_table(
        &docking_summary(spec, &outcomes),
        scenario.sim().xy_goal_tolerance(),
        scenario.sim().yaw_goal_tolerance_deg(),
    );
    let table = format!("{summary}{}{drift}{docking}", share_table(&curves));
    // With the CSV on stdout, the tables go to stderr.
    if to_stdout {
        table.lines().for_each(note);
    } else {
        say_raw(&table)?;
    }
    // The factors multiply to the number of runs: the references too, in a sweep over them.
    let references =
        spec.tracking.as_ref().map(|tr| format!(" x {} references", tr.references.len())).unwrap_or_default();
    note(&format!(
        "wmr-cli: {} runs ({} laws{references} x {} variants x {} trials x {} starts, {} s each) in {wall:.2} s; \
         outcomes in {shown_out}",
        spec.len(),
        spec.laws.len(),
        spec.variants.len(),
        spec.variation.trials,
        spec.starts.len(),
        scenario.sim().t_end(),
    ));
    Ok(())
}

/// Writes the outcome CSV to `out` and returns it, to be finished (renamed into place)
/// by the caller once everything else is written.
fn write_csv(spec: &SweepSpec, outcomes: &[SweepOutcome], out: Output) -> Result<Output> {
    let name = out.shown().to_owned();
    let to_stdout = out.is_stdout();
    let written = (|| -> Result<()> {
        let mut w = csv::Writer::from_writer(std::io::BufWriter::new(out.writer()?));
        // One column per varied key after the outcome columns (none without `vary`).
        if spec.tracking.is_some() {
            w.write_record(tracking_sweep_columns().into_iter().map(|c| c.to_string()).chain(varied_columns(spec)))?;
            for o in outcomes {
                let row = tracking_sweep_row(spec, o)
                    .context("a run of a sweep over references without its tracking outcome")?;
                w.write_record(row.into_iter().chain(varied_row(spec, o)))?;
            }
        } else {
            w.write_record(sweep_columns().into_iter().map(|c| c.to_string()).chain(varied_columns(spec)))?;
            for o in outcomes {
                w.write_record(sweep_row(spec, o).into_iter().chain(varied_row(spec, o)))?;
            }
        }
        w.flush()?;
        Ok(())
    })();
    match written {
        Err(e) if to_stdout && is_broken_pipe(&e) => Err(anyhow::Error::new(crate::errors::StdoutClosed)),
        Err(e) => Err(e.context(format!("cannot write {name}"))),
        Ok(()) => Ok(out),
    }
}

/// The outcome of a sweep run as a map cell: its start pose and the core's status.
fn cell(o: &SweepOutcome) -> SweepCell {
    SweepCell { x: o.start.x, y: o.start.y, theta: o.start.theta, outcome: o.status() }
}

/// One `region-<law>.svg` per law (per law and reference, `region-<law>-<reference>.svg`,
/// in a sweep over references: each start drawn at its offset from the reference's pose
/// at t = 0, the origin of the map).
fn write_regions(spec: &SweepSpec, outcomes: &[SweepOutcome], dir: &Path, written: &mut Vec<String>) -> Result<()> {
    for (i, (name, _)) in spec.laws.iter().enumerate() {
        let Some(tr) = &spec.tracking else {
            let cells: Vec<SweepCell> = outcomes.iter().filter(|o| o.law == i).map(cell).collect();
            let title = format!("{name}: how the run from each start ended");
            let svg = region_svg(&title, &cells, spec.goal)?;
            let file = format!("region-{}.svg", safe_file_stem(&name.replace('#', "-")));
            write_text(&dir.join(&file), &svg).with_context(|| format!("cannot write the region map of {name}"))?;
            written.push(file);
            continue;
        };
        for (r, (reference, _)) in tr.references.iter().enumerate() {
            let cells: Vec<SweepCell> = outcomes
                .iter()
                .filter(|o| o.law == i && o.reference == r)
                .map(|o| {
                    let offset = spec.starts[o.start_index];
                    SweepCell { x: offset.x, y: offset.y, theta: offset.theta, outcome: o.status() }
                })
                .collect();
            let title = format!("{name} on {reference}: outcome by start offset (reference frame at t = 0)");
            let svg = region_svg(&title, &cells, wmr_core::Pose2::default())?;
            let stem = safe_file_stem(&format!("{name}-{reference}").replace('#', "-"));
            write_text(&dir.join(format!("region-{stem}.svg")), &svg)
                .with_context(|| format!("cannot write the region map of {name} on {reference}"))?;
            written.push(format!("region-{stem}.svg"));
        }
    }
    Ok(())
}

/// The unit of a varied scenario key (`sensor.position_noise`: m;
/// `controller.model.wheel_radius`: the robot key's), from the schema `--help` shows;
/// `None` for a key without one (a count, a ratio).
fn unit_of(key: &str) -> Option<&'static str> {
    let (table, rest) = key.split_once('.')?;
    let (table, name) = match rest.strip_prefix("model.") {
        Some(name) if table == "controller" => ("robot", name),
        _ => (table, rest),
    };
    wmr_scenario::schema()
        .into_iter()
        .find(|k| k.table == table && k.key == name)
        .map(|k| k.unit)
        .filter(|u| !u.is_empty())
}

/// One `share-<key>.svg` per varied key: each law's converged share against the key.
fn write_share_curves(curves: &[ShareCurve], dir: &Path, written: &mut Vec<String>) -> Result<()> {
    let mut keys: Vec<&str> = curves.iter().map(|c| c.key.as_str()).collect();
    keys.dedup();
    for key in keys {
        let series: Vec<ShareSeries<'_>> = curves
            .iter()
            .filter(|c| c.key == key)
            .map(|c| (c.law.as_str(), c.points.iter().map(|(x, s, _)| (*x, *s)).collect()))
            .collect();
        // Every axis names its unit (issue 27): a key without one is a pure number (a
        // friction coefficient, a gear ratio, a seed).
        let axis = format!("{key} ({})", unit_of(key).unwrap_or("dimensionless"));
        let svg = share_svg(&format!("Converged share against {key}"), &axis, &series)?;
        let file = format!("share-{}.svg", safe_file_stem(&key.replace('.', "-")));
        write_text(&dir.join(&file), &svg)?;
        written.push(file);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn varied_keys_have_their_schema_units() {
        assert_eq!(unit_of("sensor.position_noise"), Some("m"));
        assert_eq!(unit_of("controller.model.wheel_radius"), unit_of("robot.wheel_radius"));
        assert_eq!(unit_of("robot.gear_ratio"), None, "a pure number");
        assert!(wmr_scenario::schema().iter().any(|k| k.table == "robot" && k.key == "gear_ratio"));
    }

    #[test]
    fn default_names_stay_in_the_working_directory() {
        assert_eq!(default_output(Path::new("examples/compare.toml")), PathBuf::from("compare-sweep.csv"));
        assert_eq!(safe_file_stem("/etc/wmr-evil"), "_etc_wmr-evil");
        assert_eq!(safe_file_stem("../../x"), "_.._x");
        assert_eq!(safe_file_stem("..."), "scenario");
        assert_eq!(safe_file_stem("a\u{1b}[31mb c"), "a_[31mb_c".replace('[', "_"));
    }
}
