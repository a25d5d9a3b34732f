//! `wmr-cli run FILE.toml --live [ADDR]`: the topics of [`crate::foxglove_topics`] served
//! over Foxglove's WebSocket protocol by the `foxglove` crate's server, paced at
//! simulated time / `--speed`, with the simulation time broadcast as the server's clock.
//!
//! Every run is simulated on its own thread and hands its samples over a bounded queue;
//! this thread merges them in time order (all runs share one clock), waits until each
//! sample is due, and sends the same bytes the MCAP file holds (optionally writing that
//! file at the same time). Streaming starts once a client has subscribed, so the start
//! of the runs is not lost while Foxglove connects. Ctrl-C stops the stream, closes the
//! server and leaves no output file.

use std::fs::File;
use std::net::SocketAddr;
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, sync_channel};
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result, anyhow};
use foxglove::websocket::{Capability, ChannelView, Client, ServerListener};
use foxglove::{Context, PartialMetadata, RawChannel, WebSocketServer};
use wmr_core::Sample;
use wmr_scenario::{RunResult, Scenario};

use crate::foxglove_topics::{Kind, LogClock, MESSAGE_ENCODING, RunEncoder, Schemas, topic};
use crate::mcap_sink::{McapFile, RunChannels};

/// The address `--live` serves on when none is given: loopback only.
pub const DEFAULT_ADDR: &str = "127.0.0.1:8765";

/// Runs streamed at once at most (one simulation thread each).
pub const MAX_LIVE_RUNS: usize = 256;

/// Samples a run's thread may be ahead of the stream.
const QUEUE_SAMPLES: usize = 512;

/// Least wall time between two broadcasts of the server clock: a broadcast per sample
/// fills a client's control queue at high speeds, and the server then drops the client.
const CLOCK_EVERY: Duration = Duration::from_millis(20);

/// Messages the server queues per client before dropping the oldest (the crate's default
/// is 1024, which a 30-run scenario fills in 0.2 s at speed 1).
const BACKLOG_MESSAGES: usize = 16 * 1024;

/// After the first subscription, time for the client's other subscriptions to arrive.
const SUBSCRIBE_GRACE: Duration = Duration::from_millis(300);

/// After the last message, the server stays up this long: stopping drops what is still
/// queued for a client.
const LINGER: Duration = Duration::from_secs(1);

/// Longest sleep between two checks of Ctrl-C.
const POLL: Duration = Duration::from_millis(20);

/// Set by the Ctrl-C handler of live mode.
static STOP: AtomicBool = AtomicBool::new(false);

/// Installs the Ctrl-C (SIGINT, SIGTERM) handler of live mode: the first stops the stream
/// (the server closes, no output is written); a second one exits at once.
pub fn install_interrupt_handler() -> Result<()> {
    ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            eprintln!("wmr-cli: interrupted twice, exiting");
            std::process::exit(130);
        }
    })
    .context("cannot install the Ctrl-C handler")
}

/// Ctrl-C was pressed.
#[derive(Debug)]
pub struct Interrupted;

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("interrupted, no output written")
    }
}

impl std::error::Error for Interrupted {}

/// Counts subscriptions.
#[derive(Default)]
struct Watch {
    subscriptions: AtomicU64,
}

impl ServerListener for Watch {
    fn on_subscribe(&self, _client: Client, _channel: ChannelView) {
        self.subscriptions.fetch_add(1, Ordering::SeqCst);
    }
}

/// What a live session did.
pub struct LiveReport {
    /// One result per run, in run order.
    pub results: Vec<RunResult>,
    /// Messages handed to the server.
    pub messages: u64,
    /// Wall time from the first to the last message, s.
    pub seconds: f64,
}

/// Sleeps until `due`, checking Ctrl-C.
fn wait_until(due: Instant) -> Result<()> {
    loop {
        if STOP.load(Ordering::SeqCst) {
            return Err(Interrupted.into());
        }
        let now = Instant::now();
        if now >= due {
            return Ok(());
        }
        std::thread::sleep((due - now).min(POLL));
    }
}

/// Serves `scenario`'s runs on `addr` at `speed` times real time, writing the MCAP file to
/// `mcap` as well when given. `announce` gets the `ws://` URL once the server listens.
pub fn serve(
    scenario: &Scenario,
    addr: SocketAddr,
    speed: f64,
    mcap: Option<File>,
    announce: impl FnOnce(&str),
) -> Result<LiveReport> {
    let runs = scenario.runs();
    let n = runs.len();
    if n > MAX_LIVE_RUNS {
        return Err(crate::errors::bad_input(format!(
            "--live streams at most {MAX_LIVE_RUNS} runs at once; this scenario has {n} [[run]] tables"
        )));
    }
    let measured = scenario.setup().has_sensor;
    let schemas = Schemas::new(measured);
    let ctx = Context::new();
    let mut channels: Vec<Vec<Option<Arc<RawChannel>>>> = Vec::with_capacity(n);
    for i in 0..n {
        let mut row = vec![None; Kind::ALL.len()];
        for kind in Kind::present(measured) {
            let ch = ctx
                .channel_builder(topic(i, kind))
                .message_encoding(MESSAGE_ENCODING)
                .schema(kind.schema(&schemas).clone())
                .build_raw()
                .map_err(|e| anyhow!("cannot create the channel {}: {e}", topic(i, kind)))?;
            row[kind as usize] = Some(ch);
        }
        channels.push(row);
    }
    let mut file = match mcap {
        Some(f) => {
            let mut m = McapFile::new(f, n, measured).map_err(|e| anyhow!(e))?;
            let ids = (0..n).map(|i| m.add_run(i)).collect::<Result<Vec<RunChannels>, _>>().map_err(|e| anyhow!(e))?;
            Some((m, ids))
        }
        None => None,
    };

    let watch = Arc::new(Watch::default());
    let server = WebSocketServer::new()
        .name(format!("wmr-cli {}", scenario.name()))
        .bind(addr.ip().to_string(), addr.port())
        .capabilities([Capability::Time])
        .message_backlog_size(BACKLOG_MESSAGES)
        .listener(watch.clone())
        .context(&ctx)
        .start_blocking()
        .map_err(|e| anyhow!("cannot serve on {addr}: {e}"))?;
    let url = match addr.ip() {
        std::net::IpAddr::V6(ip) => format!("ws://[{ip}]:{}", server.port()),
        std::net::IpAddr::V4(ip) => format!("ws://{ip}:{}", server.port()),
    };
    announce(&url);

    let outcome = (|| -> Result<LiveReport> {
        while watch.subscriptions.load(Ordering::SeqCst) == 0 {
            wait_until(Instant::now() + POLL)?;
        }
        wait_until(Instant::now() + SUBSCRIBE_GRACE)?;
        let report = stream(scenario, speed, &channels, &mut file, &server)?;
        wait_until(Instant::now() + LINGER)?;
        Ok(report)
    })();
    server.stop().wait_blocking();
    let report = outcome?;
    if let Some((m, _)) = file {
        m.finish().map_err(|e| anyhow!(e))?;
    }
    Ok(report)
}

/// Runs every run on its own thread and streams their samples in time order.
fn stream(
    scenario: &Scenario,
    speed: f64,
    channels: &[Vec<Option<Arc<RawChannel>>>],
    file: &mut Option<(McapFile, Vec<RunChannels>)>,
    server: &foxglove::WebSocketServerHandle,
) -> Result<LiveReport> {
    let runs = scenario.runs();
    let n = runs.len();
    let sim = scenario.sim();
    let clock = LogClock::new(sim.dt());
    let measured = scenario.setup().has_sensor;
    let robot = *scenario.robot().params();
    let closed = Arc::new(AtomicBool::new(false));

    std::thread::scope(|scope| -> Result<LiveReport> {
        let mut queues: Vec<Option<Receiver<Sample<f64>>>> = Vec::with_capacity(n);
        let mut workers = Vec::with_capacity(n);
        for (i, spec) in runs.iter().enumerate() {
            let (tx, rx) = sync_channel::<Sample<f64>>(QUEUE_SAMPLES);
            queues.push(Some(rx));
            let closed = closed.clone();
            workers.push(scope.spawn(move || -> Result<Option<RunResult>> {
                let mut lp = scenario.closed_loop(i)?;
                let sink = |s: &Sample<f64>| match tx.send(*s) {
                    Ok(()) => ControlFlow::Continue(()),
                    Err(_) => ControlFlow::Break(()),
                };
                let poll =
                    || if closed.load(Ordering::Relaxed) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
                Ok(match lp.try_run(sim.n_steps(), sim.log_every(), sink, poll) {
                    ControlFlow::Continue(outcome) => Some(RunResult::new(i, spec.label.clone(), outcome)),
                    ControlFlow::Break(()) => None,
                })
            }));
        }

        let mut encoders: Vec<RunEncoder> =
            runs.iter().enumerate().map(|(i, spec)| RunEncoder::new(i, spec, &robot, measured, clock)).collect();
        let mut heads: Vec<Option<Sample<f64>>> =
            queues.iter().map(|q| q.as_ref().and_then(|rx| rx.recv().ok())).collect();
        let mut last_t = vec![0.0; n];
        let mut messages = 0u64;
        // The last clock broadcast: simulation time (ns) and when.
        let mut last_broadcast: Option<(u64, Instant)> = None;
        let start = Instant::now();
        let mut first_message = None;
        let mut last_message = start;

        let streamed = (|| -> Result<()> {
            loop {
                // The run whose next sample is earliest (ties: the lower run index).
                let mut next: Option<(usize, f64)> = None;
                for (i, h) in heads.iter().enumerate() {
                    if let Some(s) = h
                        && next.is_none_or(|(_, t)| s.t < t)
                    {
                        next = Some((i, s.t));
                    }
                }
                let Some((i, t)) = next else { break };
                wait_until(start + Duration::from_secs_f64(t / speed))?;
                let ns = clock.nanos(t);
                if last_broadcast.is_none_or(|(b, at)| b != ns && at.elapsed() >= CLOCK_EVERY) {
                    server.broadcast_time(ns);
                    last_broadcast = Some((ns, Instant::now()));
                }
                let Some(s) = heads[i].take() else { break };
                last_t[i] = s.t;
                let mut emit = |kind: Kind, ns: u64, data: &[u8]| -> Result<(), mcap::McapError> {
                    if let Some(ch) = &channels[i][kind as usize] {
                        ch.log_with_meta(data, PartialMetadata::with_log_time(ns));
                    }
                    messages += 1;
                    if let Some((m, ids)) = file.as_mut() {
                        m.write(&ids[i], kind, ns, data)?;
                    }
                    Ok(())
                };
                encoders[i].sample(&s, &mut emit).map_err(|e| anyhow!("cannot write the MCAP file: {e}"))?;
                heads[i] = queues[i].as_ref().and_then(|rx| rx.recv().ok());
                if heads[i].is_none() {
                    queues[i] = None;
                    encoders[i].finish(last_t[i], &mut emit).map_err(|e| anyhow!("cannot write the MCAP file: {e}"))?;
                }
                first_message.get_or_insert_with(Instant::now);
                last_message = Instant::now();
            }
            // The clock ends at the last sample's time.
            let end = last_t.iter().copied().fold(0.0, f64::max);
            if last_broadcast.is_some_and(|(b, _)| b != clock.nanos(end)) {
                server.broadcast_time(clock.nanos(end));
            }
            Ok(())
        })();
        // Stop the simulations still running (after an error or Ctrl-C).
        closed.store(true, Ordering::Relaxed);
        drop(queues);
        let mut results = Vec::with_capacity(n);
        for w in workers {
            results.push(w.join().map_err(|_| anyhow!("a simulation thread panicked"))??);
        }
        streamed?;
        let results = results.into_iter().collect::<Option<Vec<_>>>().context("a run did not finish")?;
        let seconds = first_message.map_or(0.0, |f| (last_message - f).as_secs_f64());
        Ok(LiveReport { results, messages, seconds })
    })
}
