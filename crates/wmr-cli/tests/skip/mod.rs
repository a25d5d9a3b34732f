//! A test that needs what a machine may lack (root to mount a tmpfs, node with Foxglove's
//! npm packages) says so when it cannot run: it never passes silently.
//!
//! [`missing`] records the skip as `SKIP <test>: <reason>` on stderr (shown even when the
//! test passes) and, when `WMR_SKIP_LOG` names a file, appended to it (`scripts/test`
//! counts the lines starting `SKIP ` at the end); a long reason (a list of the documented
//! commands not run) is wrapped at [`WIDTH`] columns, its further lines indented. Where
//! `WMR_REQUIRE` lists the capability (`WMR_REQUIRE=node,root,tmpfs,python-packages`: what CI has), the
//! lack is a failure instead.

use std::io::Write as _;

/// Records that the calling test cannot run (or runs a weaker check) for lack of
/// `capability`, then returns; panics instead when `WMR_REQUIRE` lists `capability`.
#[track_caller]
pub fn missing(capability: &str, reason: &str) {
    // libtest runs each test on a thread named after it: `file::test` in a crate's one
    // integration binary (tests/integration.rs), `test` in a binary of its own (a file
    // kept apart, tests/contributing.rs), named here after its file as well.
    let name = std::thread::current().name().unwrap_or("?").to_owned();
    let test = match env!("CARGO_CRATE_NAME") {
        "integration" => name,
        file => format!("{file}::{name}"),
    };
    // One `SKIP` line per skip (scripts/test counts them), whatever the reason quotes (a
    // command's stderr may span several lines): its words, wrapped.
    let reason = reason.split_whitespace().collect::<Vec<_>>().join(" ");
    let require = std::env::var("WMR_REQUIRE").unwrap_or_default();
    assert!(
        !require.split(',').any(|c| c.trim() == capability),
        "{test}: {reason} (WMR_REQUIRE={require} requires {capability})"
    );
    let line = entry(&test, &reason);
    // Past libtest's capture (which takes `eprint!`), so a passing test shows it too.
    let _ = std::io::stderr().write_all(line.as_bytes());
    if let Some(log) = std::env::var_os("WMR_SKIP_LOG") {
        // One write of the whole entry to a file opened for appending: concurrent tests
        // do not interleave their lines.
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&log)
            .and_then(|mut f| f.write_all(line.as_bytes()))
            .unwrap_or_else(|e| panic!("cannot append to WMR_SKIP_LOG={}: {e}", log.to_string_lossy()));
    }
}

/// Columns of a line of the skip report.
const WIDTH: usize = 100;

/// `SKIP <test>: <reason>`, the words wrapped at [`WIDTH`] columns (a word longer than a
/// line stays whole), the lines after the first indented by four spaces.
fn entry(test: &str, reason: &str) -> String {
    let mut out = String::new();
    let mut line = format!("SKIP {test}:");
    for word in reason.split(' ').filter(|w| !w.is_empty()) {
        if line.len() + 1 + word.len() > WIDTH && line.len() > 4 {
            out.push_str(&line);
            out.push('\n');
            line = String::from("   ");
        }
        line.push(' ');
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
    out
}
