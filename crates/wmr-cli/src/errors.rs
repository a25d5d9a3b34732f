//! How a command ends: exit codes, the one error line, and printing that never panics.
//!
//! - 0: done (also when stdout's reader went away, e.g. `| head`: the command stops
//!   quietly, as Unix tools do; files already renamed into place are complete).
//! - 1: the work failed (a write error such as a full disk, a permission denied).
//! - 2: bad input: the command line, the scenario file, or an output path that cannot
//!   be used (missing directory, a directory, the input itself). Nothing is written.
//! - killed by SIGINT, SIGTERM or SIGHUP (a shell shows 130, 143, 129): see `atomic`.

use std::fmt;
use std::io::{self, Write as _};
use std::process::ExitCode;

use wmr_scenario::{ScenarioError, escape_controls};

/// Bad input that is not a scenario key: the command line or an output path. Exit 2.
#[derive(Debug)]
pub struct BadInput(pub String);

impl fmt::Display for BadInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// A [`BadInput`] error.
pub fn bad_input(message: impl Into<String>) -> anyhow::Error {
    anyhow::Error::new(BadInput(message.into()))
}

/// stdout's reader went away (broken pipe): the command ends quietly.
#[derive(Debug)]
pub struct StdoutClosed;

impl fmt::Display for StdoutClosed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("stdout was closed")
    }
}

impl std::error::Error for StdoutClosed {}

/// Exit code 2: bad input.
pub const EXIT_BAD_INPUT: u8 = 2;

/// True when `e` or an error below it is a broken pipe (also inside a CSV error).
pub fn is_broken_pipe_error(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut cur = Some(e);
    while let Some(err) = cur {
        let pipe = err.is::<StdoutClosed>()
            || err.downcast_ref::<io::Error>().is_some_and(|io| io.kind() == io::ErrorKind::BrokenPipe)
            || err
                .downcast_ref::<csv::Error>()
                .is_some_and(|c| matches!(c.kind(), csv::ErrorKind::Io(io) if io.kind() == io::ErrorKind::BrokenPipe));
        if pipe {
            return true;
        }
        cur = err.source();
    }
    false
}

/// True when an error of the chain of `e` is a broken pipe.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(is_broken_pipe_error)
}

/// Ends the command: prints the error (one line, control characters escaped) and
/// chooses the exit code.
pub fn finish(result: anyhow::Result<()>) -> ExitCode {
    let Err(e) = result else { return ExitCode::SUCCESS };
    if e.chain().any(|c| c.is::<StdoutClosed>()) {
        return ExitCode::SUCCESS;
    }
    note(&format!("wmr-cli: error: {e:#}"));
    let bad = e.chain().any(|c| c.is::<BadInput>() || c.is::<ScenarioError>());
    if bad { ExitCode::from(EXIT_BAD_INPUT) } else { ExitCode::FAILURE }
}

/// Writes `text` to stdout as it is. A closed pipe gives [`StdoutClosed`]; any other
/// failure (a full disk behind `> file`, `/dev/full`) is an error naming stdout.
pub fn say_raw(text: &str) -> anyhow::Result<()> {
    let mut out = io::stdout().lock();
    out.write_all(text.as_bytes()).and_then(|()| out.flush()).map_err(|e| {
        if e.kind() == io::ErrorKind::BrokenPipe {
            anyhow::Error::new(StdoutClosed)
        } else {
            anyhow::Error::new(e).context("cannot write to stdout")
        }
    })
}

/// Writes one line to stdout, control characters escaped (it may hold text from the
/// scenario file, such as a run's label); see [`say_raw`].
pub fn say(line: &str) -> anyhow::Result<()> {
    say_raw(&format!("{}\n", escape_controls(line)))
}

/// Writes one line to stderr, control characters escaped. Never fails: a closed or
/// full stderr loses the line, nothing more (no panic).
pub fn note(line: &str) {
    let _ = writeln!(io::stderr().lock(), "{}", escape_controls(line));
}

/// Ends the process for a command-line error of clap: help and `--version` print as clap
/// prints them (exit 0; help for a missing subcommand as clap does, exit 2); an error is
/// one line `wmr-cli: error: ...` on stderr (its tips in parentheses, the usage after a
/// semicolon), exit 2.
pub fn clap_exit(e: &clap::Error) -> ! {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit()
    }
    note(&format!("wmr-cli: error: {}", one_line(&e.render().to_string())));
    std::process::exit(i32::from(EXIT_BAD_INPUT))
}

/// Clap's rendered error (`error: ...`, items, tips, `Usage: ...`, `For more
/// information, try '--help'.`) as one line.
fn one_line(rendered: &str) -> String {
    let mut message = String::new();
    let (mut items, mut tips, mut usage) = (Vec::new(), Vec::new(), None);
    for line in rendered.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(rest) = line.strip_prefix("error:") {
            message = rest.trim().to_owned();
        } else if let Some(tip) = line.strip_prefix("tip:") {
            tips.push(tip.trim().to_owned());
        } else if let Some(u) = line.strip_prefix("Usage:") {
            usage = Some(u.trim().to_owned());
        } else if line.starts_with("For more information") {
        } else if usage.is_some() {
            // A usage of several lines (subcommands): the first one says enough.
        } else {
            items.push(line.to_owned());
        }
    }
    let mut s = message;
    if !items.is_empty() {
        s = format!("{} {}", s, items.join(", "));
    }
    if !tips.is_empty() {
        s = format!("{s} ({})", tips.join("; "));
    }
    if let Some(u) = usage {
        s = format!("{s}; usage: {u} (--help for more)");
    }
    s
}
