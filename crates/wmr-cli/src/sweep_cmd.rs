//! `wmr-cli sweep`: every (law, start) of a `[sweep]` in parallel, outcomes to CSV, a
//! comparison table on stdout, and optionally one region-of-attraction SVG per law.

use std::io::Write as _;
use std::path::Path;

use anyhow::{Context as _, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use wmr_core::Status;
use wmr_plot::{CellOutcome, ShareSeries, SweepCell, region_svg, share_svg};
use wmr_scenario::robustness::{ShareCurve, share_curves, share_table, varied_columns, varied_row};
use wmr_scenario::{SWEEP_COLUMNS, Scenario, SweepOutcome, SweepSpec, summarize, summary_table, sweep_row};

use crate::atomic::AtomicOut;

/// Runs the sweep of `scenario`, writes the outcome CSV to `out` and, with `plots`, one
/// `region-<law>.svg` per law into that folder; prints the comparison table.
pub fn sweep(scenario: &Scenario, out: &Path, plots: Option<&Path>, show_progress: bool) -> Result<()> {
    let Some(spec) = &scenario.sweep() else {
        bail!("the scenario has no [sweep] table (see `wmr-cli --help` for its keys)");
    };
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
    let outcomes = spec.run(scenario.sim(), &|| bar.inc(1))?;
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();

    write_csv(spec, &outcomes, out)?;
    let curves = share_curves(spec, &outcomes);
    if let Some(dir) = plots {
        write_regions(spec, &outcomes, dir)?;
        write_share_curves(&curves, dir)?;
    }
    print!("{}", summary_table(&summarize(spec, &outcomes)));
    print!("{}", share_table(&curves));
    eprintln!(
        "wmr-cli: {} runs ({} laws x {} variants x {} trials x {} starts, {} s each) in {wall:.2} s; outcomes in {}",
        spec.len(),
        spec.laws.len(),
        spec.variants.len(),
        spec.variation.trials,
        spec.starts.len(),
        scenario.sim().t_end(),
        out.display()
    );
    Ok(())
}

fn write_csv(spec: &SweepSpec, outcomes: &[SweepOutcome], out: &Path) -> Result<()> {
    let tmp = AtomicOut::create(out)?;
    {
        let mut w = csv::Writer::from_writer(std::io::BufWriter::new(tmp.file()?));
        // One column per varied key after the outcome columns (none without `vary`).
        w.write_record(SWEEP_COLUMNS.iter().map(|c| c.to_string()).chain(varied_columns(spec)))?;
        for o in outcomes {
            w.write_record(sweep_row(spec, o).into_iter().chain(varied_row(spec, o)))?;
        }
        w.flush().with_context(|| format!("cannot write {}", out.display()))?;
    }
    tmp.persist()
}

/// The outcome of a sweep run as a map cell.
fn cell(o: &SweepOutcome) -> SweepCell {
    let outcome = match o.status() {
        Status::Diverged => CellOutcome::Diverged,
        Status::Converged => CellOutcome::Converged,
        Status::Unsettled => CellOutcome::Unsettled,
    };
    SweepCell { x: o.start.x, y: o.start.y, outcome }
}

fn write_regions(spec: &SweepSpec, outcomes: &[SweepOutcome], dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for (i, (name, _)) in spec.laws.iter().enumerate() {
        let cells: Vec<SweepCell> = outcomes.iter().filter(|o| o.law == i).map(cell).collect();
        let title = format!("{name}: outcome by start (goal at the cross)");
        let svg = region_svg(&title, &cells, spec.goal)?;
        write_text(&dir.join(format!("region-{}.svg", name.replace('#', "-"))), &svg)?;
    }
    Ok(())
}

/// One `share-<key>.svg` per varied key: each law's converged share against the key.
fn write_share_curves(curves: &[ShareCurve], dir: &Path) -> Result<()> {
    let mut keys: Vec<&str> = curves.iter().map(|c| c.key.as_str()).collect();
    keys.dedup();
    for key in keys {
        let series: Vec<ShareSeries<'_>> = curves
            .iter()
            .filter(|c| c.key == key)
            .map(|c| (c.law.as_str(), c.points.iter().map(|(x, s, _)| (*x, *s)).collect()))
            .collect();
        let svg = share_svg(&format!("Converged share against {key}"), key, &series)?;
        write_text(&dir.join(format!("share-{}.svg", key.replace('.', "-"))), &svg)?;
    }
    Ok(())
}

/// Writes a text file atomically.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let tmp = AtomicOut::create(path)?;
    let mut f = tmp.file()?;
    f.write_all(text.as_bytes()).with_context(|| format!("cannot write {}", path.display()))?;
    drop(f);
    tmp.persist()
}
