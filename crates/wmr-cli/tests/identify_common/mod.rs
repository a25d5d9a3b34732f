//! What the identification tests (`identify.rs`, `identify_mcap.rs`) share: running
//! wmr-cli in a folder and reading its outcome.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// wmr-cli run in `dir` with `args`.
pub fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli")).current_dir(dir).args(args).output().expect("spawn wmr-cli")
}

/// Its standard output, after asserting it succeeded.
pub fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Its standard error, after asserting it was refused as bad input (exit 2).
pub fn refused(o: &Output) -> String {
    assert_eq!(o.status.code(), Some(2), "stdout {}", String::from_utf8_lossy(&o.stdout));
    String::from_utf8_lossy(&o.stderr).into_owned()
}
