//! A test that needs what a machine may lack (root to mount a tmpfs, node with Foxglove's
//! npm packages) says so when it cannot run: it never passes silently.
//!
//! [`missing`] records the skip as one line `SKIP <test>: <reason>` on stderr (shown even
//! when the test passes) and, when `WMR_SKIP_LOG` names a file, appended to it
//! (`scripts/test` counts them at the end). Where `WMR_REQUIRE` lists the capability
//! (`WMR_REQUIRE=node,root,tmpfs`: what CI has), the lack is a failure instead.

use std::io::Write as _;

/// Records that the calling test cannot run (or runs a weaker check) for lack of
/// `capability`, then returns; panics instead when `WMR_REQUIRE` lists `capability`.
#[track_caller]
pub fn missing(capability: &str, reason: &str) {
    // libtest runs each test on a thread named after it.
    let test = format!("{}::{}", env!("CARGO_CRATE_NAME"), std::thread::current().name().unwrap_or("?"));
    // One line per skip (scripts/test counts lines), whatever the reason quotes: a
    // command's stderr may span several.
    let reason = reason.split_whitespace().collect::<Vec<_>>().join(" ");
    let require = std::env::var("WMR_REQUIRE").unwrap_or_default();
    assert!(
        !require.split(',').any(|c| c.trim() == capability),
        "{test}: {reason} (WMR_REQUIRE={require} requires {capability})"
    );
    let line = format!("SKIP {test}: {reason}\n");
    // Past libtest's capture (which takes `eprint!`), so a passing test shows it too.
    let _ = std::io::stderr().write_all(line.as_bytes());
    if let Some(log) = std::env::var_os("WMR_SKIP_LOG") {
        // One write of one short line to a file opened for appending: concurrent tests do
        // not interleave their lines.
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&log)
            .and_then(|mut f| f.write_all(line.as_bytes()))
            .unwrap_or_else(|e| panic!("cannot append to WMR_SKIP_LOG={}: {e}", log.to_string_lossy()));
    }
}
