//! A live session: the topics of [`crate::foxglove_topics`] served by [`super::server`],
//! paced at simulated time / `--speed`, with the simulation time broadcast as the server's
//! clock.
//!
//! Every run is simulated on its own thread and hands its samples over a bounded queue;
//! this thread merges them in time order (all runs share one clock), waits until each
//! sample is due, and sends the same bytes the MCAP file holds (optionally writing that
//! file at the same time). Streaming starts once a client has subscribed, so the start
//! of the runs is not lost while Foxglove connects. The session ends when the runs end,
//! whatever the clients do; a signal ([`super::stop`]) ends it at any point within
//! [`super::stop::POLL`] or so, and no output file is left.

use std::fs::File;
use std::net::SocketAddr;
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, sync_channel};
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result, anyhow};
use wmr_core::Sample;
use wmr_scenario::{Columns, RunResult, Scenario};

use super::protocol::ChannelInfo;
use super::server::{Limits, Server, Stats};
use super::stop::{self, POLL};
use crate::foxglove_topics::{Kind, LogClock, MESSAGE_ENCODING, RunEncoder, Schemas, Views, topic};
use crate::mcap_sink::{McapFile, RunChannels};

/// The address `--live` serves on when none is given: loopback only.
pub const DEFAULT_ADDR: &str = "127.0.0.1:8765";

/// Runs streamed at once at most (one simulation thread each).
pub const MAX_LIVE_RUNS: usize = 256;

/// The range of `--speed` (simulated seconds per wall second): slower than 1/1000 a
/// session of the paper's 60 s takes more than 16 hours; faster than 1e6 every sample is
/// due at once anyway.
pub const MIN_SPEED: f64 = 1e-3;
/// See [`MIN_SPEED`].
pub const MAX_SPEED: f64 = 1e6;

/// Samples a run's thread may be ahead of the stream.
const QUEUE_SAMPLES: usize = 512;

/// Least wall time between two broadcasts of the server clock.
const CLOCK_EVERY: Duration = Duration::from_millis(20);

/// The environment variable that bounds the wait for a viewer: with
/// `WMR_LIVE_START_AFTER_S=S`, streaming starts when a client subscribes or after S
/// seconds, whichever comes first (the docs test runs the documented `--live` commands
/// so, with no viewer; unset, the session waits for one as long as it takes).
pub const START_AFTER_VAR: &str = "WMR_LIVE_START_AFTER_S";

/// The wait for a viewer [`START_AFTER_VAR`] asks for (`None`: unset, wait for one); a
/// value that is not a number of seconds from 0 to 1e6 is bad input naming the variable.
pub fn start_after() -> Result<Option<Duration>> {
    let Some(v) = std::env::var_os(START_AFTER_VAR) else { return Ok(None) };
    let text = v.to_string_lossy();
    match text.trim().parse::<f64>() {
        Ok(s) if (0.0..=1e6).contains(&s) => Ok(Some(Duration::from_secs_f64(s))),
        _ => Err(crate::errors::bad_input(format!(
            "{START_AFTER_VAR}: {text:?} is not a number of seconds from 0 to 1e6 (the longest wait for a viewer)"
        ))),
    }
}

/// After the first subscription, time for the client's other subscriptions to arrive.
const SUBSCRIBE_GRACE: Duration = Duration::from_millis(300);

/// After the last message, the server stays up until every client's queue is written
/// out, at most this long.
const LINGER: Duration = Duration::from_secs(1);

/// The id of run `run`'s channel of `kind`.
fn channel_id(run: usize, kind: Kind) -> u64 {
    (run * Kind::ALL.len() + kind as usize) as u64
}

/// A bound server, ready to serve a scenario's runs.
pub struct Live {
    server: Server,
    url: String,
}

/// What a live session did.
pub struct LiveReport {
    /// One result per run, in run order.
    pub results: Vec<RunResult>,
    /// Messages handed to the server.
    pub messages: u64,
    /// Wall time from the first to the last message, s.
    pub seconds: f64,
    /// What the server saw (clients, refusals, drops).
    pub stats: Stats,
}

/// Binds the server of `scenario`'s runs on `addr` (before anything is written: a bind
/// failure is bad input).
pub fn serve(scenario: &Scenario, addr: SocketAddr) -> Result<Live> {
    let n = scenario.runs().len();
    if n > MAX_LIVE_RUNS {
        return Err(crate::errors::bad_input(format!(
            "--live streams at most {MAX_LIVE_RUNS} runs at once; this scenario has {n} [[run]] tables"
        )));
    }
    let columns = Columns::of(scenario);
    // MPPI's plans go to `run -o FILE.mcap` only.
    let views = Views { mppi: false, ..Views::of(scenario) };
    let schemas = Schemas::new(&columns);
    let mut channels = Vec::new();
    for i in 0..n {
        for kind in Kind::present(&columns, views) {
            let s = kind.schema(&schemas);
            channels.push(ChannelInfo {
                id: channel_id(i, kind),
                topic: topic(i, kind),
                encoding: MESSAGE_ENCODING.to_owned(),
                schema_name: s.name.clone(),
                schema_encoding: s.encoding.clone(),
                schema: s.data.to_vec(),
            });
        }
    }
    let name = format!("wmr-cli {}", scenario.name());
    let server = Server::bind(addr, &name, &channels, Limits::default()).map_err(|e| {
        crate::errors::bad_input(format!("--live: cannot serve on {addr}: {e}; choose another address or port"))
    })?;
    let bound = server.local_addr();
    let url = match bound.ip() {
        std::net::IpAddr::V6(ip) => format!("ws://[{ip}]:{}", bound.port()),
        std::net::IpAddr::V4(ip) => format!("ws://{ip}:{}", bound.port()),
    };
    Ok(Live { server, url })
}

impl Live {
    /// `ws://IP:PORT`, the port the one bound.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// Serves `scenario`'s runs at `speed` times real time once a client subscribes (or
    /// once `start_after` has passed without one, when given: [`START_AFTER_VAR`]),
    /// writing the MCAP file to `mcap` as well when given. The server is closed when this
    /// returns, whatever happened.
    pub fn run(
        self,
        scenario: &Scenario,
        speed: f64,
        mcap: Option<File>,
        start_after: Option<Duration>,
    ) -> Result<LiveReport> {
        let n = scenario.runs().len();
        let mut file = match mcap {
            Some(f) => {
                let mut m = McapFile::new(f, n, Columns::of(scenario), Views { mppi: false, ..Views::of(scenario) })
                    .map_err(|e| anyhow!(e))?;
                let ids =
                    (0..n).map(|i| m.add_run(i)).collect::<Result<Vec<RunChannels>, _>>().map_err(|e| anyhow!(e))?;
                Some((m, ids))
            }
            None => None,
        };
        let server = self.server;
        let outcome = (|| -> Result<(Vec<RunResult>, u64, f64)> {
            let give_up = start_after.and_then(|d| Instant::now().checked_add(d));
            while !server.subscribed() && give_up.is_none_or(|g| Instant::now() < g) {
                stop::wait_for(POLL)?;
            }
            if server.subscribed() {
                stop::wait_for(SUBSCRIBE_GRACE)?;
            }
            let streamed = stream(scenario, speed, &mut file, &server)?;
            let until = Instant::now() + LINGER;
            while !server.drained() && Instant::now() < until {
                stop::wait_for(Duration::from_millis(5))?;
            }
            Ok(streamed)
        })();
        let stats = server.close();
        let (results, messages, seconds) = outcome?;
        if let Some((m, _)) = file {
            m.finish().map_err(|e| anyhow!(e))?;
        }
        Ok(LiveReport { results, messages, seconds, stats })
    }
}

/// The next sample of a run's queue (`None`: the run is over), giving up on a signal.
fn next(rx: &Receiver<Sample<f64>>) -> Result<Option<Sample<f64>>, stop::Interrupted> {
    loop {
        stop::check()?;
        match rx.recv_timeout(POLL) {
            Ok(s) => return Ok(Some(s)),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => return Ok(None),
        }
    }
}

/// When the sample of simulated time `t_s` is due: `t_s / speed` after `start` (`None`:
/// beyond what an `Instant` holds, never).
fn due(start: Instant, t_s: f64, speed: f64) -> Option<Instant> {
    Duration::try_from_secs_f64((t_s / speed).max(0.0)).ok().and_then(|d| start.checked_add(d))
}

/// Runs every run on its own thread and streams their samples in time order; returns the
/// results, the messages sent and the seconds from the first to the last.
fn stream(
    scenario: &Scenario,
    speed: f64,
    file: &mut Option<(McapFile, Vec<RunChannels>)>,
    server: &Server,
) -> Result<(Vec<RunResult>, u64, f64)> {
    let runs = scenario.runs();
    let n = runs.len();
    let sim = scenario.sim();
    let clock = LogClock::new(sim.dt());
    let columns = Columns::of(scenario);
    let robot = *scenario.robot().params();
    let closed = Arc::new(AtomicBool::new(false));

    std::thread::scope(|scope| -> Result<(Vec<RunResult>, u64, f64)> {
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
                // Asked every 1024 plant steps: a stop reaches a run between two samples.
                let poll =
                    || if closed.load(Ordering::Relaxed) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
                Ok(match lp.try_run(sim.n_steps(), sim.log_every(), sink, poll) {
                    ControlFlow::Continue(outcome) => Some(RunResult::new(i, spec.label.clone(), outcome)),
                    ControlFlow::Break(()) => None,
                })
            }));
        }

        let mut encoders: Vec<RunEncoder> = runs
            .iter()
            .enumerate()
            .map(|(i, spec)| {
                RunEncoder::new(i, spec, &robot, columns.clone(), sim).with_obstacles(&scenario.setup().obstacles)
            })
            .collect();
        let mut heads: Vec<Option<Sample<f64>>> = vec![None; n];
        let mut last_t = vec![0.0; n];
        let mut messages = 0u64;
        // The last clock broadcast: simulation time (ns) and when.
        let mut last_broadcast: Option<(u64, Instant)> = None;
        let mut first_message = None;
        let mut last_message = Instant::now();

        let streamed = (|| -> Result<()> {
            for (h, q) in heads.iter_mut().zip(&queues) {
                if let Some(rx) = q {
                    *h = next(rx)?;
                }
            }
            let start = Instant::now();
            loop {
                // The run whose next sample is earliest (ties: the lower run index).
                let mut earliest: Option<(usize, f64)> = None;
                for (i, h) in heads.iter().enumerate() {
                    if let Some(s) = h
                        && earliest.is_none_or(|(_, t)| s.t < t)
                    {
                        earliest = Some((i, s.t));
                    }
                }
                let Some((i, t)) = earliest else { break };
                stop::wait_until(due(start, t, speed))?;
                let ns = clock.nanos(t);
                if last_broadcast.is_none_or(|(b, at)| b != ns && at.elapsed() >= CLOCK_EVERY) {
                    server.broadcast_time(ns);
                    last_broadcast = Some((ns, Instant::now()));
                }
                let Some(s) = heads[i].take() else { break };
                last_t[i] = s.t;
                let mut emit = |kind: Kind, ns: u64, data: &[u8]| -> Result<(), mcap::McapError> {
                    server.log(channel_id(i, kind), ns, data);
                    messages += 1;
                    if let Some((m, ids)) = file.as_mut() {
                        m.write(&ids[i], kind, ns, data)?;
                    }
                    Ok(())
                };
                encoders[i].sample(&s, &mut emit).map_err(|e| anyhow!("cannot write the MCAP file: {e}"))?;
                heads[i] = match &queues[i] {
                    Some(rx) => next(rx)?,
                    None => None,
                };
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
        // Stop the simulations still running (after an error or a signal).
        closed.store(true, Ordering::Relaxed);
        drop(queues);
        let mut results = Vec::with_capacity(n);
        for w in workers {
            results.push(w.join().map_err(|_| anyhow!("a simulation thread panicked"))??);
        }
        streamed?;
        let results = results.into_iter().collect::<Option<Vec<_>>>().context("a run did not finish")?;
        let seconds = first_message.map_or(0.0, |f| (last_message - f).as_secs_f64());
        Ok((results, messages, seconds))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn due_times_never_panic() {
        let now = Instant::now();
        // What panicked before (issue 25 item 3): huge quotients; and the range's ends.
        for (t, speed) in [(60.0, 1e-300), (1.0, 5e-324), (1e6, 1e-21), (1e300, 1e-3), (0.0, 1.0)] {
            let _ = due(now, t, speed);
        }
        assert_eq!(due(now, 2.0, 4.0), Some(now + Duration::from_millis(500)));
        assert_eq!(due(now, 1e300, MIN_SPEED), None);
    }
}
