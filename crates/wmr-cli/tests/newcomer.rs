//! What a new user meets past the first hour (issue 40), one test per stumble.

use std::process::{Command, Output};

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().expect("spawn wmr-cli")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// `--help` and each subcommand's fit on a screen or two with their options; the
/// schema (every table's keys) is not repeated after them but named.
#[test]
fn help_is_short_and_names_help_keys() {
    for args in [&["--help"][..], &["run", "--help"], &["sweep", "--help"], &["check", "--help"], &["help"]] {
        let o = cli(args);
        assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
        let help = text(&o.stdout);
        assert!(help.lines().count() < 80, "{args:?}: {} lines", help.lines().count());
        assert!(!help.contains("\n[robot]"), "{args:?} repeats the schema");
    }
    let help = text(&cli(&["--help"]).stdout);
    assert!(help.contains("wmr-cli help keys"), "{help}");
    // `help SUB` is `SUB --help`.
    assert_eq!(cli(&["help", "run"]).stdout, cli(&["run", "--help"]).stdout);
}

/// `help keys` prints every table, `help keys TABLE` one, `help keys NOPE` is one line
/// naming the choices, exit 2.
#[test]
fn help_keys_prints_the_schema_or_one_table() {
    let all = cli(&["help", "keys"]);
    assert!(all.status.success());
    let all = text(&all.stdout);
    for table in
        ["[robot]", "[drive]", "[controller]", "[sensor]", "[world]", "[reference]", "[sim]", "[[run]]", "[sweep]"]
    {
        assert!(all.contains(&format!("\n{table}")), "help keys lacks {table}");
    }
    for asked in ["robot", "[robot]"] {
        let one = cli(&["help", "keys", asked]);
        assert!(one.status.success(), "{}", text(&one.stderr));
        let one = text(&one.stdout);
        assert!(one.starts_with("[robot]"), "{one}");
        assert!(one.contains("wheel_radius = 0.1") && !one.contains("[drive]"), "{one}");
        assert!(all.contains(&one), "help keys robot is a part of help keys");
    }
    let sweep = text(&cli(&["help", "keys", "sweep"]).stdout);
    assert!(sweep.starts_with("[sweep]") && sweep.contains("references = ") && !sweep.contains("[sim]"), "{sweep}");
    // The [reference] note names the law a scenario with a reference gets by default.
    let reference = text(&cli(&["help", "keys", "reference"]).stdout).split_whitespace().collect::<Vec<_>>().join(" ");
    let default = wmr_scenario::tracking_law_kinds()[0];
    assert!(reference.contains(&format!("[controller] kind defaults to {default}")), "{reference}");
    let bad = cli(&["help", "keys", "robt"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = text(&bad.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("robt") && err.contains("robot, drive"), "{err}");
}

fn repo(rel: &str) -> String {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel).to_str().unwrap().to_owned()
}

/// `run FILE` without `-o`: the summary lines a run with `-o` prints, and a note saying
/// how to write a file; no file written.
#[test]
fn run_without_output_prints_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let fig7 = repo("examples/paper/fig7.toml");
    let out = dir.path().join("fig7.csv");
    let with = cli(&["run", &fig7, "-o", out.to_str().unwrap()]);
    assert!(with.status.success(), "{}", text(&with.stderr));
    let without =
        Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(["run", &fig7]).current_dir(dir.path()).output().unwrap();
    assert!(without.status.success(), "{}", text(&without.stderr));
    assert_eq!(text(&without.stdout), text(&with.stdout));
    assert!(text(&without.stdout).contains("converged"), "{}", text(&without.stdout));
    assert!(text(&without.stderr).contains("-o OUT.csv"), "{}", text(&without.stderr));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "only the -o run's file");
    // --format and --layout describe a file: without -o, a usage error.
    let o = cli(&["run", &fig7, "--format", "csv"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
}

/// A sweep over references says the product with them: 1 law x 2 references x 1
/// variants x 1 trials x 2 starts = 4 runs (it said "1 laws x 1 variants x ...").
#[test]
fn a_sweep_over_references_counts_them() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("refs.toml");
    std::fs::write(
        &file,
        "[sim]\nt_end = 1.0\n[sweep]\ncontrollers = [{ kind = \"kanayama\" }]\n\
         references = [{ kind = \"circle\" }, { kind = \"figure_eight\" }]\n\
         random = { n = 2, seed = 1, radius = 0.2, max_heading_deg = 10.0 }\n",
    )
    .unwrap();
    let out = dir.path().join("refs.csv");
    let o = cli(&["sweep", file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(err.contains("4 runs (1 laws x 2 references x 1 variants x 1 trials x 2 starts"), "{err}");
}

use crate::skip;

/// The long reason of a skip (docs_commands lists the documented commands it did not
/// run: about 4,000 characters on one line) is wrapped: one `SKIP` line, then indented
/// lines, none wider than 100 columns, every word kept in order. Recorded by this test
/// binary run again as a child with its own WMR_SKIP_LOG.
#[test]
fn a_long_skip_reason_is_wrapped() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("skipped.txt");
    let o = Command::new(std::env::current_exe().unwrap())
        .args(["--ignored", "--exact", "newcomer::records_a_long_skip", "--test-threads=1"])
        .env("WMR_SKIP_LOG", &log)
        .env("WMR_SKIP_SELFTEST", "1")
        .env_remove("WMR_REQUIRE")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
    let report = std::fs::read_to_string(&log).unwrap();
    assert_eq!(report.lines().filter(|l| l.starts_with("SKIP ")).count(), 1, "{report}");
    assert!(report.lines().count() > 10, "{report}");
    for line in report.lines() {
        assert!(line.len() <= 100, "a line of {} characters: {line}", line.len());
        assert!(line.starts_with("SKIP ") || line.starts_with("    "), "{line:?}");
    }
    let words: Vec<&str> = report.split_whitespace().collect();
    assert_eq!(words[..2], ["SKIP", "newcomer::records_a_long_skip:"]);
    assert_eq!(words[2..].join(" "), long_reason());
}

fn long_reason() -> String {
    let commands: Vec<String> = (0..60)
        .map(|i| format!("README.md:{} `wmr-cli sweep examples/compare.toml -o compare.csv`", 100 + i))
        .collect();
    format!("60 documented command(s) marked long not run (WMR_LONG_TESTS=1 runs them): {}", commands.join("; "))
}

/// The skip [`a_long_skip_reason_is_wrapped`] reads back; nothing outside it.
#[test]
#[ignore = "run by a_long_skip_reason_is_wrapped, with its own WMR_SKIP_LOG"]
fn records_a_long_skip() {
    if std::env::var_os("WMR_SKIP_SELFTEST").is_some() {
        skip::missing("selftest", &long_reason());
    }
}
