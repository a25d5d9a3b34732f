//! `wmr-cli run`: checks what the runs will cost, simulates them through the scenario's
//! ordered executor and hands them to a sink in run order, so the output does not depend
//! on the thread count. The first failed write stops the work.

use std::mem::size_of;
use std::ops::ControlFlow;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context as _, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use wmr_core::Sample;
use wmr_scenario::{RunResult, Scenario, Sink, SinkError, executor};

use crate::atomic::Output;
use crate::errors::{StdoutClosed, bad_input, is_broken_pipe, note, say};
use crate::mcap_sink;
use crate::sinks::{Format, SinkOptions};

/// Memory for samples between the simulation and the sink, bytes: what keeps `run`'s
/// memory flat whatever the run length (issue 15; `tests/memory.rs`). Short runs whose
/// samples fit, one per thread at least, are simulated in parallel batches and written in
/// order; longer runs stream: simulated in parallel, each handing its samples to the sink
/// in blocks through a bounded queue, written in run order ([`stream_runs`]).
const BUFFER_BUDGET_BYTES: u64 = 8 << 20;

/// Samples per block handed from a streamed run to the sink (144 KiB of samples).
const BLOCK_SAMPLES: usize = 1024;

/// The buffer budget: [`BUFFER_BUDGET_BYTES`], or `WMR_CLI_BUFFER_BYTES` when set (the
/// tests use it to exercise streaming and batching on small scenarios).
fn buffer_budget() -> u64 {
    std::env::var("WMR_CLI_BUFFER_BYTES").ok().and_then(|v| v.parse().ok()).unwrap_or(BUFFER_BUDGET_BYTES)
}

/// Plant steps (all runs) above which the work counts as long and gets a progress bar.
const LONG_WORK_STEPS: u64 = 2_000_000;

/// Plant steps above which the work is announced with an estimate of its duration
/// (about a minute and more).
pub const ANNOUNCE_WORK_STEPS: u128 = 100_000_000;

/// Plant steps per second of one core for logged runs and plots, roughly and on the slow
/// side (release build; the benches measure it): only for the announcement of long work.
const STEPS_PER_CORE_SECOND: f64 = 1e6;

/// Plant steps per second of one core in a sweep (no samples kept), on the slow side of
/// benches/README.md's figures: the exact path (about 150 ns per step) and the SIMD
/// lanes of `--fast` (about 45 ns per run-step with AVX2).
const SWEEP_STEPS_PER_CORE_SECOND: f64 = 5e6;
const FAST_SWEEP_STEPS_PER_CORE_SECOND: f64 = 1.5e7;

/// `bytes` for people: `281 GB`, `1.7 MB`.
pub fn human_bytes(bytes: f64) -> String {
    let units = ["bytes", "kB", "MB", "GB", "TB", "PB"];
    let mut v = bytes;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < units.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 { format!("{v:.0} {}", units[0]) } else { format!("{v:.1} {}", units[u]) }
}

/// Seconds for people: `42 s`, `17 min`, `5.8 h`, `3.1 days`.
pub fn human_seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86400.0)
    }
}

/// Announces long work (more than [`ANNOUNCE_WORK_STEPS`]) with a rough duration.
pub fn announce_work(steps: u128, what: &str) {
    announce(steps, what, STEPS_PER_CORE_SECOND, false);
}

/// [`announce_work`] for a sweep, stepped `fast` or not, whose steps cost `step_cost`
/// times a stabilization law's on average (`LawParams::update_cost`); where runs stop once
/// settled (`sim.stop_when_settled`), the steps and the time are upper bounds.
pub fn announce_sweep(steps: u128, what: &str, fast: bool, stops_early: bool, step_cost: f64) {
    let rate = if fast { FAST_SWEEP_STEPS_PER_CORE_SECOND } else { SWEEP_STEPS_PER_CORE_SECOND };
    announce(steps, what, rate / step_cost, stops_early);
}

fn announce(steps: u128, what: &str, steps_per_core_second: f64, at_most: bool) {
    if steps > ANNOUNCE_WORK_STEPS {
        let threads = rayon::current_num_threads().max(1) as f64;
        let secs = steps as f64 / steps_per_core_second / threads;
        let (up_to, roughly, why) =
            if at_most { ("up to ", "at most roughly", " (runs stop once settled)") } else { ("", "roughly", "") };
        note(&format!(
            "wmr-cli: {what}: {up_to}{steps:.2e} plant steps{why}, {roughly} {} on {threads} threads; Ctrl-C stops \
             it and leaves OUT as it was",
            human_seconds(secs)
        ));
    }
}

/// Refuses output that cannot fit in the free space where it goes: `samples` logged
/// samples of at least [`Format::bytes_per_sample`] each. The message says which key to change
/// and to what.
pub fn check_space(scenario: &Scenario, out: &Output, format: Format, samples: u128) -> Result<()> {
    let Some(free) = out.free_bytes() else { return Ok(()) };
    let (least_each, typical_each) = format.bytes_per_sample();
    let least = samples.saturating_mul(u128::from(least_each));
    if least <= u128::from(free) {
        return Ok(());
    }
    let sim = scenario.sim();
    let typical = samples as f64 * typical_each as f64;
    // log_dt (a whole multiple of dt) for which the typical size fits.
    let factor = typical / free.max(1) as f64;
    let steps = (f64::from(sim.log_every()) * factor).ceil();
    let log_dt = steps * sim.dt();
    let hint = if log_dt <= sim.t_end() {
        format!("raise sim.log_dt to at least {log_dt:.3e} s (now {} s), ", sim.log_dt())
    } else {
        String::new()
    };
    Err(bad_input(format!(
        "{} would take about {} ({samples} samples of ~{typical_each} bytes), at least {}, but only {} are free \
         there: {hint}shorten sim.t_end, or write elsewhere",
        out.shown(),
        human_bytes(typical),
        human_bytes(least as f64),
        human_bytes(free as f64)
    )))
}

/// Refuses a scenario without `[[run]]` (a sweep file) for a command that runs them.
pub fn require_runs(scenario: &Scenario, file: &Path) -> Result<()> {
    if scenario.runs().is_empty() {
        return Err(bad_input(format!(
            "{}: run: the file has no [[run]] (a [sweep] file runs with `wmr-cli sweep`)",
            wmr_scenario::shown(file)
        )));
    }
    Ok(())
}

/// `wmr-cli run FILE -o OUT [--format] [--layout LAYOUT]`.
pub fn run_command(
    scenario: &Scenario,
    file: &Path,
    output: &Path,
    format: Format,
    profile: mcap_sink::Profile,
    layout: Option<&Path>,
) -> Result<()> {
    require_runs(scenario, file)?;
    let started = Instant::now();
    let out = Output::create(output)?;
    let n_runs = scenario.runs().len();
    let samples = u128::from(scenario.sim().n_samples()) * n_runs as u128;
    check_space(scenario, &out, format, samples)?;
    announce_work(u128::from(scenario.sim().n_steps()) * n_runs as u128, &format!("{n_runs} run(s)"));
    let writer = out.writer()?;
    let mut sink = format.open(writer, scenario, &SinkOptions { profile }).map_err(sink_err).map_err(|e| {
        if out.is_stdout() && is_broken_pipe(&e) {
            anyhow::Error::new(StdoutClosed)
        } else {
            e.context(format!("cannot write {}", out.shown()))
        }
    })?;
    let show_bar = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let executed = execute(scenario, sink.as_mut(), show_bar);
    drop(sink);
    let (results, counts) = match executed {
        Ok(done) => done,
        Err(e) if out.is_stdout() && is_broken_pipe(&e) => return Err(anyhow::Error::new(StdoutClosed)),
        Err(e) => return Err(e.context(format!("cannot write {}", out.shown()))),
    };
    let to_stdout = out.is_stdout();
    out.finish()?;
    if let Some(layout) = layout {
        crate::foxglove_cmd::write_layout(scenario, layout, profile)?;
    }
    for r in &results {
        // With OUT on stdout the summary goes to stderr, so the data stays clean.
        if to_stdout { note(&r.summary_line()) } else { say(&r.summary_line())? }
    }
    let samples = if counts.iter().all(|&c| c == counts[0]) {
        format!("{} samples each", counts[0])
    } else {
        // Say why some runs wrote fewer: what actually ended them before t_end.
        let settled = results.iter().filter(|r| r.outcome.termination == wmr_core::Termination::Settled).count();
        let diverged = results.iter().filter(|r| r.diverged()).count();
        let why = match (settled, diverged) {
            (0, 0) => String::new(),
            (s, 0) => format!(" (fewer for the {s} run(s) that stopped once settled)"),
            (0, d) => format!(" (fewer for the {d} run(s) that diverged early)"),
            (s, d) => format!(" (fewer for the {s} run(s) that stopped once settled and the {d} that diverged)"),
        };
        format!("{} samples in all{why}", counts.iter().sum::<u64>())
    };
    note(&format!(
        "wmr-cli: wrote {} ({} run(s), {samples}, {:.2} s)",
        if to_stdout { "stdout".to_owned() } else { wmr_scenario::shown(output) },
        results.len(),
        started.elapsed().as_secs_f64()
    ));
    Ok(())
}

/// The sink of `run` without `-o`: the samples are dropped, the summaries stay.
struct SummaryOnly;

impl Sink for SummaryOnly {
    fn sample(&mut self, _index: usize, _sample: &Sample<f64>) -> Result<(), SinkError> {
        Ok(())
    }

    fn finish(&mut self) -> Result<(), SinkError> {
        Ok(())
    }
}

/// `wmr-cli run FILE` without `-o`: every run simulated and its summary line printed; no
/// file is written, and a note says how to write one.
pub fn run_summary(scenario: &Scenario, file: &Path) -> Result<()> {
    require_runs(scenario, file)?;
    let n_runs = scenario.runs().len();
    announce_work(u128::from(scenario.sim().n_steps()) * n_runs as u128, &format!("{n_runs} run(s)"));
    let show_bar = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let (results, _) = execute(scenario, &mut SummaryOnly, show_bar)?;
    for r in &results {
        say(&r.summary_line())?;
    }
    note("wmr-cli: no file written; -o OUT.mcap (for Foxglove) or -o OUT.csv writes the runs' samples");
    Ok(())
}

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

/// A sink error as an anyhow error; a broken pipe stays recognisable as one.
fn sink_err(e: SinkError) -> anyhow::Error {
    if crate::errors::is_broken_pipe_error(e.as_ref()) {
        anyhow::Error::new(std::io::Error::new(std::io::ErrorKind::BrokenPipe, e.to_string()))
    } else {
        anyhow::Error::from_boxed(e)
    }
}

/// Simulates every run into `sink` and finishes it; returns the results and the number
/// of samples each run wrote. The first failed write stops everything: streamed runs
/// within a block of samples of work, batched runs at the end of their batch (a few runs
/// per thread at most). `show_progress`: stderr is a terminal, so a bar may be drawn when the
/// work is long.
pub fn execute(scenario: &Scenario, sink: &mut dyn Sink, show_progress: bool) -> Result<(Vec<RunResult>, Vec<u64>)> {
    let bar = progress(scenario, show_progress);
    let step = u64::from(scenario.sim().log_every());
    let per_run = scenario.sim().n_samples().saturating_mul(size_of::<Sample<f64>>() as u64);
    let n = scenario.runs().len();
    let mut results = Vec::with_capacity(n);
    let mut counts = Vec::with_capacity(n);
    let budget = buffer_budget();

    let threads = rayon::current_num_threads().max(1);
    let by_memory = usize::try_from(budget / per_run.max(1)).unwrap_or(usize::MAX);
    if by_memory < n.min(threads).max(1) {
        // Streaming: runs too long to buffer one per thread, bounded memory.
        stream_runs(scenario, sink, &bar, budget, threads, &mut results, &mut counts)?;
    } else {
        // Batches of runs in parallel, their samples buffered, handed on in run order.
        // A batch holds at most a few runs per thread, so a failed write wastes little.
        let batch = by_memory.min(4 * threads);
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
            counts.push(samples.len() as u64);
            Ok(())
        })?;
    }
    sink.finish().map_err(sink_err)?;
    bar.finish_and_clear();
    Ok((results, counts))
}

/// What a streamed run hands to the sink: its samples in blocks, then its result.
enum Piece {
    Samples(Vec<Sample<f64>>),
    // Boxed: a run's result is ten times a batch handle, and one is sent per run.
    Done(Box<Result<RunResult>>),
}

/// Streams every run into `sink` in run order with memory bounded by `budget` (bytes of
/// samples in flight), whatever the run length: up to `threads` runs are simulated at once,
/// each on its own thread, handing its samples in blocks of [`BLOCK_SAMPLES`] through a
/// bounded queue; this thread writes the oldest run's blocks as they come, then the next
/// run's. A run ahead of the one being written waits when its queue is full. A failed write
/// drops the queues: every run stops at its next block.
fn stream_runs(
    scenario: &Scenario,
    sink: &mut dyn Sink,
    bar: &ProgressBar,
    budget: u64,
    threads: usize,
    results: &mut Vec<RunResult>,
    counts: &mut Vec<u64>,
) -> Result<()> {
    let n = scenario.runs().len();
    let step = u64::from(scenario.sim().log_every());
    let window = threads.min(n).max(1);
    let block_bytes = (BLOCK_SAMPLES * size_of::<Sample<f64>>()) as u64;
    // Blocks queued per run: enough to keep a run going while the sink is busy, within the
    // budget shared by the runs in flight (2 to 8: at most 1.2 MB of samples per run).
    let queued = usize::try_from(budget / (window as u64 * block_bytes)).unwrap_or(usize::MAX).clamp(2, 8);
    std::thread::scope(|scope| -> Result<()> {
        let start = |i: usize| {
            let (tx, rx) = std::sync::mpsc::sync_channel::<Piece>(queued);
            let bar = bar.clone();
            scope.spawn(move || {
                let mut block = Vec::with_capacity(BLOCK_SAMPLES);
                let flow = scenario.try_run(
                    i,
                    |s| {
                        bar.inc(step);
                        block.push(*s);
                        if block.len() < BLOCK_SAMPLES {
                            return ControlFlow::Continue(());
                        }
                        let full = std::mem::replace(&mut block, Vec::with_capacity(BLOCK_SAMPLES));
                        // An error: the writer has stopped (a failed write) and dropped the queue.
                        if tx.send(Piece::Samples(full)).is_err() {
                            ControlFlow::Break(())
                        } else {
                            ControlFlow::Continue(())
                        }
                    },
                    || ControlFlow::Continue(()),
                );
                let done = match flow {
                    Ok(ControlFlow::Continue(result)) => Ok(result),
                    Ok(ControlFlow::Break(())) => return,
                    Err(e) => Err(anyhow::Error::new(e)),
                };
                if !block.is_empty() && tx.send(Piece::Samples(block)).is_err() {
                    return;
                }
                let _ = tx.send(Piece::Done(Box::new(done)));
            });
            (i, rx)
        };
        let mut in_flight: std::collections::VecDeque<_> = (0..window).map(start).collect();
        let mut next = window;
        while let Some((i, rx)) = in_flight.pop_front() {
            sink.begin_run(i, &scenario.runs()[i]).map_err(sink_err)?;
            let mut count = 0u64;
            let result = loop {
                match rx.recv() {
                    Ok(Piece::Samples(block)) => {
                        for s in &block {
                            sink.sample(i, s).map_err(sink_err)?;
                        }
                        count += block.len() as u64;
                    }
                    Ok(Piece::Done(result)) => break (*result)?,
                    Err(_) => anyhow::bail!("run {i} stopped without a result"),
                }
            };
            sink.end_run(&result).map_err(sink_err)?;
            results.push(result);
            counts.push(count);
            if next < n {
                in_flight.push_back(start(next));
                next += 1;
            }
        }
        Ok(())
    })
}

/// Loads a scenario file: read (a regular file, size-capped), checked, its warnings
/// printed, and remembered as an input so no output replaces it.
pub fn load(file: &Path, access: &wmr_scenario::FileAccess) -> Result<Scenario> {
    let name = wmr_scenario::shown(file);
    let text = wmr_scenario::read_text(file).map_err(|e| anyhow::Error::new(e).context(name.clone()))?;
    crate::atomic::register_input(file);
    // Printed as "FILE: line L: KEY: what is wrong".
    // A `[robot] from = "robots/NAME.toml"` is relative to the scenario's folder, and
    // stays in it unless `access` allows another.
    let dir = file.parent().unwrap_or(Path::new(""));
    let scenario = Scenario::from_toml_str_with(&text, &wmr_scenario::default_name(file), dir, access)
        .map_err(|e| anyhow::Error::new(e).context(name.clone()))?;
    for w in wmr_scenario::warnings(&text) {
        note(&format!("wmr-cli: warning: {name}: {w}"));
    }
    Ok(scenario)
}

/// `wmr-cli check FILE`: the resolved scenario on stdout.
pub fn check_command(file: &Path, access: &wmr_scenario::FileAccess) -> Result<()> {
    let scenario = load(file, access)?;
    let total = wmr_scenario::total_steps(&scenario);
    let text = scenario.to_toml();
    // Labels and the name are TOML strings: control characters come out escaped by
    // TOML's rules; the bidirectional overrides TOML allows raw are escaped here too.
    let text: String =
        text.chars()
            .map(|c| {
                if wmr_scenario::is_unsafe_char(c) && c != '\n' {
                    format!("\\u{:04X}", c as u32)
                } else {
                    c.to_string()
                }
            })
            .collect();
    crate::errors::say_raw(&text)?;
    if let Some(tr) = scenario.tracking() {
        crate::errors::say_raw(&format!("# {}\n", wmr_scenario::reference::describe(&tr.reference)))?;
    }
    crate::errors::say_raw(&format!("# {total} plant steps in all\n")).context("cannot write to stdout")
}
