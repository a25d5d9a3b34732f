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
