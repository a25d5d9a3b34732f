//! The Foxglove parts of the command line: `wmr-cli layout`, `run --layout` and
//! `run --live [ADDR] [--speed X]`.

use std::io::Write as _;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context as _, Result};
use wmr_scenario::{Scenario, shown};

use crate::atomic::{AtomicOut, Target, target_of};
use crate::errors::{bad_input, note, say};
use crate::mcap_sink::Profile;
use crate::sinks::Format;
use crate::{format_of, layout, live};

/// `--live ADDR`: `IP:PORT` (port 0: any free port) of one host: a multicast or broadcast
/// address is refused (a server cannot accept connections there).
pub fn parse_addr(s: &str) -> Result<SocketAddr, String> {
    let addr: SocketAddr =
        s.parse().map_err(|_| format!("ADDR must be IP:PORT, e.g. {} (got {s:?})", live::DEFAULT_ADDR))?;
    let group = match addr.ip() {
        std::net::IpAddr::V4(ip) => ip.is_multicast() || ip.is_broadcast(),
        std::net::IpAddr::V6(ip) => ip.is_multicast(),
    };
    if group {
        return Err(format!(
            "{} is a multicast or broadcast address: a server listens on one host's address, e.g. {} or \
             0.0.0.0:8765 (got {s:?})",
            addr.ip(),
            live::DEFAULT_ADDR
        ));
    }
    Ok(addr)
}

/// `--speed X`: a number of simulated seconds per wall second in
/// [`live::MIN_SPEED`, `live::MAX_SPEED`].
pub fn parse_speed(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if (live::MIN_SPEED..=live::MAX_SPEED).contains(&v) => Ok(v),
        _ => Err(format!(
            "must be a number of simulated seconds per second from {:e} to {:e} (got {s:?})",
            live::MIN_SPEED,
            live::MAX_SPEED
        )),
    }
}

/// Exits with a usage error (one line `wmr-cli: error: MSG`, exit code 2) for flags that
/// do not go together.
pub fn usage_error(msg: &str) -> ! {
    note(&format!("wmr-cli: error: {msg}"));
    std::process::exit(i32::from(crate::errors::EXIT_BAD_INPUT))
}

/// Refuses, before any work, a LAYOUT path that cannot take the layout file (the rules of
/// OUT, except that LAYOUT must be a file) or that is OUT itself.
pub fn check_layout_path(layout: &Path, out: Option<&Path>) -> Result<()> {
    check_side_output("--layout", layout, out)
}

/// Refuses, before any work, a `path` that a flag (`--layout`, `--rosbag2`) writes beside
/// OUT when it cannot take the file (the rules of OUT, except that it must be a file) or
/// is OUT itself.
pub fn check_side_output(flag: &str, layout: &Path, out: Option<&Path>) -> Result<()> {
    let Target::File(real) = target_of(layout)? else {
        return Err(bad_input(format!("{flag} {} is not a regular file; give a file name", shown(layout))));
    };
    if let Some(Ok(Target::File(out))) = out.map(target_of) {
        let same = |p: &Path| std::fs::canonicalize(p).ok();
        if out == real || (same(&out).is_some() && same(&out) == same(&real)) {
            return Err(bad_input(format!("{flag} {} is OUT itself; give another file name", shown(layout))));
        }
    }
    Ok(())
}

/// Writes `scenario`'s layout to `path` (beside it under a temporary name, renamed when
/// complete; a path that cannot take a file is bad input, as for OUT).
pub fn write_layout(scenario: &Scenario, path: &Path, profile: Profile) -> Result<()> {
    let out = AtomicOut::create(path)?;
    let mut file = out.file()?;
    file.write_all(layout::layout_text(scenario, profile).as_bytes())
        .with_context(|| format!("cannot write {}", shown(path)))?;
    out.persist()
}

/// Writes `text` to `path`, replaced atomically when complete (as `layout` writes its file).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let out = AtomicOut::create(path)?;
    let mut file = out.file()?;
    file.write_all(text.as_bytes()).with_context(|| format!("cannot write {}", shown(path)))?;
    out.persist()
}

/// The layout of a live session, written before the server waits for a viewer and undone
/// when the session does not end well (a signal, a failure): the file it replaced is put
/// back (kept meanwhile as a hard link, or a copy, beside it), or the new one removed.
struct LiveLayout {
    /// The regular file written (links resolved); `None` for a stream (`/dev/null`, a FIFO).
    file: Option<PathBuf>,
    /// The file it replaced, kept beside it.
    kept: Option<PathBuf>,
}

impl LiveLayout {
    fn write(scenario: &Scenario, path: &Path) -> Result<Self> {
        let file = match target_of(path)? {
            Target::File(f) => Some(f),
            _ => None,
        };
        let mut kept = None;
        if let Some(f) = file.as_ref().filter(|f| f.is_file()) {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            let k = crate::atomic::parent_dir(f).join(format!(".{name}.{}.kept", std::process::id()));
            std::fs::hard_link(f, &k)
                .or_else(|_| std::fs::copy(f, &k).map(|_| ()))
                .with_context(|| format!("cannot keep {} while the session runs", shown(f)))?;
            kept = Some(k);
        }
        let layout = Self { file, kept };
        if let Err(e) = write_layout(scenario, path, Profile::Foxglove) {
            layout.undo();
            return Err(e);
        }
        Ok(layout)
    }

    /// Puts the replaced file back, or removes the new one.
    fn undo(self) {
        match (&self.file, &self.kept) {
            (Some(f), Some(k)) => {
                let _ = std::fs::rename(k, f);
            }
            (Some(f), None) => {
                let _ = std::fs::remove_file(f);
            }
            _ => {}
        }
    }

    /// The session ended well: the new layout stays.
    fn keep(self) {
        if let Some(k) = &self.kept {
            let _ = std::fs::remove_file(k);
        }
    }
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
    if let Some(o) = &output
        && format_of(o, format)? != Format::Mcap
    {
        usage_error("--live writes the MCAP file only: name OUT .mcap, or leave -o out");
    }
    if let Some(l) = &layout {
        check_layout_path(l, output.as_deref())?;
    }
    let start_after = live::start_after()?;
    // Bind first: an address that cannot be served is refused before anything is written.
    let server = live::serve(scenario, addr)?;
    let url = server.url().to_owned();
    let out = output.as_deref().map(AtomicOut::create).transpose()?;
    let file = out.as_ref().map(AtomicOut::file).transpose()?;
    let live_layout = match &layout {
        // Before serving, so it can be imported while the server waits for Foxglove.
        Some(l) => {
            let written = LiveLayout::write(scenario, l)?;
            note(&format!("wmr-cli: wrote {}", shown(l)));
            Some(written)
        }
        None => None,
    };
    if !addr.ip().is_loopback() {
        note(&format!(
            "wmr-cli: note: {addr} is not a loopback address: other machines can connect (at most {} clients at once)",
            live::MAX_CLIENTS
        ));
    }
    let started = Instant::now();
    note(&format!(
        "wmr-cli: live on {url} at {speed}x: in Foxglove, Open connection > Foxglove WebSocket > {url}; \
         streaming starts when a client subscribes (Ctrl-C stops)"
    ));
    let report = match server.run(scenario, speed, file, start_after) {
        Ok(r) => r,
        Err(e) => {
            // No output left: the MCAP file's temporary is removed, the layout undone.
            drop(out);
            if let Some(l) = live_layout {
                l.undo();
            }
            if let Some(i) = e.downcast_ref::<live::Interrupted>() {
                note("wmr-cli: interrupted, no output written");
                std::process::exit(128 + i.signal);
            }
            return Err(e);
        }
    };
    if let Some(l) = live_layout {
        l.keep();
    }
    if let (Some(out), Some(o)) = (out, &output) {
        out.persist()?;
        note(&format!("wmr-cli: wrote {}", shown(o)));
    }
    for r in &report.results {
        say(&r.summary_line())?;
    }
    let rate = if report.seconds > 0.0 { report.messages as f64 / report.seconds } else { 0.0 };
    let s = &report.stats;
    let mut clients = format!("{} client connection(s)", s.connections);
    if s.refused > 0 {
        clients += &format!(", {} refused (at most {} at once)", s.refused, live::MAX_CLIENTS);
    }
    if s.expired > 0 {
        clients += &format!(
            ", {} sent away (a handshake over {} s, no subscription within {} s, or a slot given to a new connection)",
            s.expired,
            live::HANDSHAKE_DEADLINE.as_secs(),
            live::IDLE_LIMIT.as_secs()
        );
    }
    if s.dropped > 0 {
        clients += &format!(
            ", {} queued message(s) dropped, oldest first, for clients reading slower than the stream",
            s.dropped
        );
    }
    note(&format!(
        "wmr-cli: live: {} messages in {:.2} s of streaming ({rate:.0} messages/s), {:.2} s in all; {clients}",
        report.messages,
        report.seconds,
        started.elapsed().as_secs_f64()
    ));
    Ok(())
}
