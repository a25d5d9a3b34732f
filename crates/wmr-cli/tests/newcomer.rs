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
