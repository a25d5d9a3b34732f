//! `wmr-cli plot`: SVG figures of a scenario's runs (paths, the paper's Figs. 4-7; wheel
//! speeds, Fig. 8; errors, Fig. 9). Each run keeps at most [`MAX_PLOT_SAMPLES`] samples,
//! evenly spaced, so memory and file sizes stay small whatever `t_end / log_dt` is.

use std::path::{Path, PathBuf};

use anyhow::Result;
use wmr_core::{Pose2, Reference, Sample};
use wmr_plot::{Trace, errors_svg, paths_among_svg, wheel_speeds_svg};
use wmr_scenario::{Scenario, executor, shown};

use crate::atomic::{parent_dir, write_text};
use crate::errors::bad_input;
use crate::exec::announce_work;

/// Most samples drawn per run and curve: a figure a few hundred pixels wide shows no
/// more, and 4,000 points keep each SVG below about 200 kB.
pub const MAX_PLOT_SAMPLES: u64 = 4000;

/// Extensions of files, not folders: `plot -o x.svg` is a mistake, not a folder name.
const FILE_EXTENSIONS: [&str; 6] = ["svg", "csv", "mcap", "png", "pdf", "toml"];

/// A folder ready for a command's SVGs; one the command created is removed again when the
/// command fails ([`Prepared::abandon`]) or a signal ends it (left empty), so no empty or
/// half-filled new folder stays behind.
#[must_use]
pub struct Prepared {
    /// The folder, when this command created it.
    created: Option<PathBuf>,
}

impl Prepared {
    /// The command failed: a folder it created is removed with the files it wrote there
    /// (`written`, names inside it); an existing folder keeps what it held.
    pub fn abandon(self, written: &[String]) {
        if let Some(d) = &self.created {
            for name in written {
                let _ = std::fs::remove_file(d.join(name));
            }
            let _ = std::fs::remove_dir(d);
            crate::atomic::forget_new_dir(d);
        }
    }

    /// The command succeeded: the folder stays.
    pub fn done(self) {
        if let Some(d) = &self.created {
            crate::atomic::forget_new_dir(d);
        }
    }
}

/// Makes sure `dir` is a folder to write into: an existing directory, or a new one
/// created in an existing parent (wmr-cli creates the last level only, as for files).
pub fn prepare_dir(dir: &Path) -> Result<Prepared> {
    let name = shown(dir);
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => return Ok(Prepared { created: None }),
        Ok(_) => return Err(bad_input(format!("{name} exists and is not a directory; give a folder for the SVGs"))),
        Err(e) => {
            if let Some(bad) = crate::atomic::bad_path(&name, &e) {
                return Err(bad);
            }
            if dir.is_symlink() {
                return Err(bad_input(format!("{name} is a symbolic link to a missing folder; give a folder")));
            }
        }
    }
    let ext = dir.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if let Some(ext) = ext.filter(|e| FILE_EXTENSIONS.contains(&e.as_str())) {
        return Err(bad_input(format!(
            "{name} looks like a file (.{ext}), but SVGs are written into a folder: give a folder name"
        )));
    }
    let parent = parent_dir(dir);
    if !parent.is_dir() {
        return Err(bad_input(format!(
            "cannot create {name}: the directory {} does not exist (wmr-cli creates one level, not the ones above)",
            shown(&parent)
        )));
    }
    // Registered first: a signal right after the folder exists removes it.
    crate::atomic::register_new_dir(dir);
    std::fs::create_dir(dir).map_err(|e| {
        crate::atomic::forget_new_dir(dir);
        crate::atomic::bad_path(&name, &e)
            .unwrap_or_else(|| anyhow::Error::new(e).context(format!("cannot create {name}")))
    })?;
    Ok(Prepared { created: Some(dir.to_path_buf()) })
}

/// The samples of one run, thinned to at most [`MAX_PLOT_SAMPLES`]: every `stride`-th
/// logged sample and the last one (the final state, also of a run that diverged).
struct Thinned {
    stride: u64,
    seen: u64,
    kept: Vec<Sample<f64>>,
    last: Option<Sample<f64>>,
}

impl Thinned {
    fn new(n_samples: u64) -> Self {
        let stride = n_samples.div_ceil(MAX_PLOT_SAMPLES).max(1);
        Self { stride, seen: 0, kept: Vec::with_capacity(MAX_PLOT_SAMPLES as usize + 1), last: None }
    }

    fn push(&mut self, s: &Sample<f64>) {
        if self.seen.is_multiple_of(self.stride) {
            self.kept.push(*s);
            self.last = None;
        } else {
            self.last = Some(*s);
        }
        self.seen += 1;
    }

    fn finish(mut self) -> Vec<Sample<f64>> {
        self.kept.extend(self.last);
        self.kept
    }
}

/// Writes `paths.svg`, and `run<i>-wheel-speeds.svg` and `run<i>-errors.svg` per run,
/// into `dir`; returns the files written.
pub fn plot(scenario: &Scenario, file: &Path, dir: &Path) -> Result<Vec<String>> {
    if scenario.runs().is_empty() {
        if let Some(spec) = scenario.sweep()
            && spec.starts.len() <= MAX_COMPARED_STARTS
        {
            return plot_sweep(scenario, spec, dir);
        }
        return Err(bad_input(format!(
            "{}: run: the file has no [[run]] to plot, and plot compares the laws of a [sweep] only from at most \
             {MAX_COMPARED_STARTS} starts (for region maps, use `wmr-cli sweep --plots DIR`)",
            shown(file)
        )));
    }
    into_prepared(dir, |written| plot_runs(scenario, dir, written))
}

/// Runs `draw` into folder `dir` prepared for it ([`prepare_dir`]): the names of the
/// figures it wrote; when it fails, a folder this call created is removed with them.
fn into_prepared(dir: &Path, draw: impl FnOnce(&mut Vec<String>) -> Result<()>) -> Result<Vec<String>> {
    let prepared = prepare_dir(dir)?;
    let mut written = Vec::new();
    match draw(&mut written) {
        Ok(()) => {
            prepared.done();
            Ok(written)
        }
        Err(e) => {
            prepared.abandon(&written);
            Err(e)
        }
    }
}

/// The figures of [`plot`] into `dir`, each name pushed to `written` once written.
fn plot_runs(scenario: &Scenario, dir: &Path, written: &mut Vec<String>) -> Result<()> {
    let n_samples = scenario.sim().n_samples();
    announce_work(u128::from(scenario.sim().n_steps()) * scenario.runs().len() as u128, "plot");
    let samples: Vec<Vec<Sample<f64>>> = executor::map_ordered(scenario.runs().len(), |i| {
        let mut thin = Thinned::new(n_samples);
        scenario.run(i, |s| thin.push(s)).map(|_| thin.finish())
    })
    .into_iter()
    .collect::<Result<_, _>>()?;
    // A tracking run's reference pose at each sample's time, as the CSV's x_ref ... columns.
    let reference = scenario.tracking().map(|t| &t.reference.built);
    let refs: Vec<Vec<Pose2<f64>>> = samples
        .iter()
        .map(|s| reference.map_or_else(Vec::new, |r| s.iter().map(|x| Reference::state_at(r, x.t).pose).collect()))
        .collect();
    let traces: Vec<Trace<'_>> = scenario
        .runs()
        .iter()
        .zip(&samples)
        .zip(&refs)
        .map(|((r, s), reference)| Trace { label: &r.label, goal: r.goal, samples: s, reference })
        .collect();
    let mut put = |name: String, svg: String| -> Result<()> {
        write_text(&dir.join(&name), &svg)?;
        written.push(name);
        Ok(())
    };
    let obstacles = &scenario.setup().obstacles;
    put("paths.svg".into(), paths_among_svg(&format!("{}: paths of C", scenario.name()), &traces, obstacles)?)?;
    for (i, t) in traces.iter().enumerate() {
        put(format!("run{i}-wheel-speeds.svg"), wheel_speeds_svg(&format!("{}: wheel speeds", t.label), t)?)?;
        put(format!("run{i}-errors.svg"), errors_svg(&format!("{}: errors", t.label), t)?)?;
    }
    Ok(())
}

/// Most starts of a `[sweep]` that `plot` draws, one figure each.
pub const MAX_COMPARED_STARTS: usize = 12;

/// For a `[sweep]` (no `[[run]]`): `compare-start<k>.svg` per start, the path of every law
/// from that start (the sweep's first variant and trial), one colour per law.
fn plot_sweep(scenario: &Scenario, spec: &wmr_scenario::SweepSpec, dir: &Path) -> Result<Vec<String>> {
    into_prepared(dir, |written| plot_sweep_into(scenario, spec, dir, written))
}

/// The figures of [`plot_sweep`] into `dir`, each name pushed to `written` once written.
fn plot_sweep_into(
    scenario: &Scenario,
    spec: &wmr_scenario::SweepSpec,
    dir: &Path,
    written: &mut Vec<String>,
) -> Result<()> {
    let sim = scenario.sim();
    let (n_laws, n_starts) = (spec.laws.len(), spec.starts.len());
    announce_work(u128::from(sim.n_steps()) * (n_laws * n_starts) as u128, "plot");
    let samples: Vec<Vec<Sample<f64>>> = executor::map_ordered(n_laws * n_starts, |k| {
        let mut thin = Thinned::new(sim.n_samples());
        spec.run_one(sim, k % n_laws, k / n_laws, |s| thin.push(s)).map(|_| thin.finish())
    })
    .into_iter()
    .collect::<Result<_, _>>()?;
    for (k, start) in spec.starts.iter().enumerate() {
        let traces: Vec<Trace<'_>> = spec
            .laws
            .iter()
            .enumerate()
            .map(|(i, (name, _))| Trace {
                label: name,
                goal: spec.goal,
                samples: &samples[k * n_laws + i],
                reference: &[],
            })
            .collect();
        let title = format!(
            "{}: every law from ({}, {}, {} deg)",
            scenario.name(),
            round3(start.x),
            round3(start.y),
            round3(start.theta.to_degrees())
        );
        let name = format!("compare-start{k}.svg");
        write_text(&dir.join(&name), &paths_among_svg(&title, &traces, &scenario.setup().obstacles)?)?;
        written.push(name);
    }
    Ok(())
}

/// A number to at most three decimals, for titles.
fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64) -> Sample<f64> {
        Sample { t, ..Default::default() }
    }

    #[test]
    fn thinning_keeps_evenly_spaced_samples_and_the_last() {
        for n in [1, 2, 3999, 4000, 4001, 6001, 100_000, 1_000_001] {
            let mut thin = Thinned::new(n);
            for i in 0..n {
                thin.push(&sample(i as f64));
            }
            let kept = thin.finish();
            assert!(kept.len() as u64 <= MAX_PLOT_SAMPLES + 1, "{n}: {}", kept.len());
            assert!(kept.len() as u64 >= n.min(MAX_PLOT_SAMPLES / 2), "{n}: {}", kept.len());
            assert_eq!(kept[0].t, 0.0);
            assert_eq!(kept.last().unwrap().t, (n - 1) as f64, "{n}: the last sample is kept");
            assert!(kept.windows(2).all(|w| w[0].t < w[1].t));
        }
    }
}
