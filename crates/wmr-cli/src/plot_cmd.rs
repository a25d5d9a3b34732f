//! `wmr-cli plot`: SVG figures of a scenario's runs (paths, the paper's Figs. 4-7; wheel
//! speeds, Fig. 8; errors, Fig. 9) and, for a `[sweep]`, region maps per law.

use std::path::Path;

use anyhow::{Context as _, Result, bail};
use wmr_core::Sample;
use wmr_plot::{Trace, errors_svg, paths_svg, wheel_speeds_svg};
use wmr_scenario::{Scenario, executor};

use crate::sweep_cmd::write_text;

/// Writes `paths.svg`, and `run<i>-wheel-speeds.svg` and `run<i>-errors.svg` per run,
/// into `dir`; returns the files written.
pub fn plot(scenario: &Scenario, dir: &Path) -> Result<Vec<String>> {
    if scenario.runs().is_empty() {
        bail!("the scenario has no [[run]] to plot (for a [sweep], use `wmr-cli sweep --plots DIR`)");
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let samples: Vec<Vec<Sample<f64>>> = executor::map_ordered(scenario.runs().len(), |i| {
        let mut v = Vec::with_capacity(scenario.sim().n_samples() as usize);
        scenario.run(i, |s| v.push(*s)).map(|_| v)
    })
    .into_iter()
    .collect::<Result<_, _>>()?;
    let traces: Vec<Trace<'_>> = scenario
        .runs()
        .iter()
        .zip(&samples)
        .map(|(r, s)| Trace { label: &r.label, goal: r.goal, samples: s })
        .collect();
    let mut written = Vec::new();
    let mut put = |name: String, svg: String| -> Result<()> {
        write_text(&dir.join(&name), &svg)?;
        written.push(name);
        Ok(())
    };
    put("paths.svg".into(), paths_svg(&format!("{}: paths of C", scenario.name()), &traces)?)?;
    for (i, t) in traces.iter().enumerate() {
        put(format!("run{i}-wheel-speeds.svg"), wheel_speeds_svg(&format!("{}: wheel speeds", t.label), t)?)?;
        put(format!("run{i}-errors.svg"), errors_svg(&format!("{}: errors", t.label), t)?)?;
    }
    Ok(written)
}
