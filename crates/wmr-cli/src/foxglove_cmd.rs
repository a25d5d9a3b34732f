//! The Foxglove parts of the command line: `wmr-cli layout`, `run --layout` and
//! `run --live [ADDR] [--speed X]`.

use std::io::Write as _;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context as _, Result, anyhow, bail};
use clap::CommandFactory as _;
use wmr_scenario::Scenario;

use crate::atomic::AtomicOut;
use crate::{Cli, Format, format_of, layout, live};

/// `--live ADDR`: `IP:PORT` (port 0: any free port).
pub fn parse_addr(s: &str) -> Result<SocketAddr, String> {
    s.parse().map_err(|_| format!("ADDR must be IP:PORT, e.g. {} (got {s:?})", live::DEFAULT_ADDR))
}

/// `--speed X`: a positive finite number.
pub fn parse_speed(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("must be a positive number of simulated seconds per second (got {s:?})")),
    }
}

/// Exits with clap's usage error (exit code 2) for flags that do not go together.
pub fn usage_error(msg: &str) -> ! {
    Cli::command().error(clap::error::ErrorKind::ArgumentConflict, msg).exit()
}

/// Writes `scenario`'s layout to `path` (beside it under a temporary name, renamed when
/// complete).
pub fn write_layout(scenario: &Scenario, path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!("{} is a directory", path.display());
    }
    let out = AtomicOut::create(path)?;
    let mut file = out.file()?;
    file.write_all(layout::layout_text(scenario).as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))?;
    out.persist()
}

/// `run FILE --live ADDR [-o OUT.mcap] [--layout LAYOUT] [--speed X]`.
pub fn run_live(
    scenario: &Scenario,
    output: Option<PathBuf>,
    format: Option<Format>,
    layout: Option<PathBuf>,
    addr: SocketAddr,
    speed: f64,
) -> Result<()> {
    if let Some(o) = &output {
        if format_of(o, format)? != Format::Mcap {
            usage_error("--live writes the MCAP file only: name OUT .mcap, or leave -o out");
        }
        if o.is_dir() {
            bail!("{} is a directory", o.display());
        }
    }
    live::install_interrupt_handler()?;
    if let Some(l) = &layout {
        // First, so it can be imported while the server waits for Foxglove.
        write_layout(scenario, l)?;
        eprintln!("wmr-cli: wrote {}", l.display());
    }
    if !addr.ip().is_loopback() {
        eprintln!("wmr-cli: note: {addr} is not a loopback address: other machines can connect");
    }
    let out = output.as_deref().map(AtomicOut::create).transpose()?;
    let file = out.as_ref().map(AtomicOut::file).transpose()?;
    let started = Instant::now();
    let served = live::serve(scenario, addr, speed, file, |url| {
        eprintln!(
            "wmr-cli: live on {url} at {speed}x: in Foxglove, Open connection > Foxglove WebSocket > {url}; \
             streaming starts when a client subscribes (Ctrl-C stops)"
        );
    });
    let report = match served {
        Ok(r) => r,
        Err(e) if e.is::<live::Interrupted>() => {
            drop(out);
            eprintln!("wmr-cli: interrupted, no output written");
            std::process::exit(130);
        }
        Err(e) => return Err(e),
    };
    if let (Some(out), Some(o)) = (out, &output) {
        out.persist().map_err(|e| anyhow!(e))?;
        eprintln!("wmr-cli: wrote {}", o.display());
    }
    for r in &report.results {
        println!("{}", r.summary_line());
    }
    let rate = if report.seconds > 0.0 { report.messages as f64 / report.seconds } else { 0.0 };
    eprintln!(
        "wmr-cli: live: {} messages in {:.2} s of streaming ({rate:.0} messages/s), {:.2} s in all",
        report.messages,
        report.seconds,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
