//! Runs a scenario's runs through the scenario's ordered executor and hands them to a
//! sink in run order, so the output does not depend on the thread count.

use std::mem::size_of;

use anyhow::{Result, anyhow};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use wmr_core::Sample;
use wmr_scenario::{RunResult, Scenario, Sink, SinkError, executor};

/// Memory for buffered samples at once (bytes). Runs whose samples fit are simulated in
/// parallel batches and written in order; a run larger than this streams straight to
/// the sink on one thread.
const BUFFER_BUDGET_BYTES: u64 = 256 << 20;

/// The buffer budget: [`BUFFER_BUDGET_BYTES`], or `WMR_CLI_BUFFER_BYTES` when set (the
/// tests use it to exercise streaming and batching on small scenarios).
fn buffer_budget() -> u64 {
    std::env::var("WMR_CLI_BUFFER_BYTES").ok().and_then(|v| v.parse().ok()).unwrap_or(BUFFER_BUDGET_BYTES)
}

/// Plant steps (all runs) above which the work counts as long and gets a progress bar.
const LONG_WORK_STEPS: u64 = 2_000_000;

fn progress(scenario: &Scenario, show: bool) -> ProgressBar {
    let total = scenario.sim().n_steps().saturating_mul(scenario.runs().len() as u64);
    if !show || total < LONG_WORK_STEPS {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{spinner} {msg} [{elapsed_precise}] {wide_bar} {percent}% (eta {eta})")
    {
        bar.set_style(style);
    }
    bar.set_message(format!("{} run(s)", scenario.runs().len()));
    bar
}

fn sink_err(e: SinkError) -> anyhow::Error {
    anyhow!(e)
}

/// Simulates every run into `sink` and finishes it. `show_progress`: stderr is a
/// terminal, so a bar may be drawn when the work is long.
pub fn execute(scenario: &Scenario, sink: &mut dyn Sink, show_progress: bool) -> Result<Vec<RunResult>> {
    let bar = progress(scenario, show_progress);
    let step = u64::from(scenario.sim().log_every());
    let per_run = scenario.sim().n_samples().saturating_mul(size_of::<Sample<f64>>() as u64);
    let n = scenario.runs().len();
    let mut results = Vec::with_capacity(n);
    let budget = buffer_budget();

    if per_run > budget {
        // Streaming: one run at a time on this thread, bounded memory.
        for (i, spec) in scenario.runs().iter().enumerate() {
            sink.begin_run(i, spec).map_err(sink_err)?;
            let mut failed: Option<SinkError> = None;
            let result = scenario.run(i, |s| {
                if failed.is_none()
                    && let Err(e) = sink.sample(i, s)
                {
                    failed = Some(e);
                }
                bar.inc(step);
            })?;
            if let Some(e) = failed {
                return Err(sink_err(e));
            }
            sink.end_run(&result).map_err(sink_err)?;
            results.push(result);
        }
    } else {
        // Batches of runs in parallel, their samples buffered, handed on in run order.
        let batch = usize::try_from((budget / per_run.max(1)).max(1)).unwrap_or(usize::MAX);
        let capacity = usize::try_from(scenario.sim().n_samples()).unwrap_or(0);
        let job = |i: usize| {
            let mut samples = Vec::with_capacity(capacity);
            let result = scenario.run(i, |s| {
                samples.push(*s);
                bar.inc(step);
            });
            result.map(|r| (samples, r))
        };
        executor::for_each_ordered(n, batch, job, |i, item| -> Result<()> {
            let (samples, result) = item?;
            sink.begin_run(i, &scenario.runs()[i]).map_err(sink_err)?;
            for s in &samples {
                sink.sample(i, s).map_err(sink_err)?;
            }
            sink.end_run(&result).map_err(sink_err)?;
            results.push(result);
            Ok(())
        })?;
    }
    sink.finish().map_err(sink_err)?;
    bar.finish_and_clear();
    Ok(results)
}
