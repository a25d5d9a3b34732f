//! Docs as tests (issue 27): every shell command shown in README.md, docs/*.md and every
//! README.md under examples/, benches/, firmware/ and crates/ runs here, in a fresh copy
//! of the repository's tracked files (a temporary folder: no `out/`, no build output),
//! and what the doc says it prints is compared.
//!
//! What counts as a command, found anew in every run (a section someone adds tomorrow is
//! picked up without touching this file):
//! - each line of a fenced block tagged `sh` (a trailing ` # comment` is prose, a line
//!   ending in `\` continues on the next); it must exit 0;
//! - each `$ ` line of a fenced block tagged `console`; the lines under it, up to the next
//!   `$ ` line, are what it prints (stdout, then stderr) and are compared: a line `...`
//!   stands for any number of lines, `[..]` within a line for any text; a first line
//!   `? N` is the exit code it must end with (0 otherwise);
//! - each inline code span that is a whole `wmr-cli` command: it starts with `wmr-cli `,
//!   names a `.toml` file of the repository and no placeholder (`FILE`, `OUT`, `DIR`...).
//!   Inline `wmr-cli sweep` spans are long (below); other inline spans run in every test.
//!
//! A block that needs a long run or hardware says so, visibly in the Markdown source, with
//! a comment on the line before its fence: `<!-- docs-test: long -->` (minutes of CPU,
//! or a build from scratch), `<!-- docs-test: hardware -->` (tools beyond the test command's,
//! e.g. qemu-system-arm). Those run under `WMR_LONG_TESTS=1` only; without it the test
//! records the skip (`skip::missing("long", ...)`), never passes them silently.
//!
//! Commands of one document run in order in one copy and share it (a `cd firmware` or a
//! venv's `. .venv/bin/activate` holds for the block's next commands, as in one terminal;
//! files written by one are there for the next). The copy is a git repository of the
//! tracked files (not committed), as a clone is. `target`
//! in the copy is this workspace's target folder, so a documented `cargo build` reuses what
//! is built. The `wmr-cli` first on `PATH` is this test's build (a debug one under `cargo
//! test`) in the normal set; under `WMR_LONG_TESTS=1` it is a release build, made once by
//! the test (`cargo build --release -p wmr-cli --locked` into that target folder, then
//! `target/release` first on `PATH`): the long commands' sweeps and maps are timed in
//! the docs with a release build and take several times as long with a debug one.
//!
//! Run: `cargo test -p wmr-cli --test integration docs_commands::` (`-- --nocapture` lists
//! every command with its time); all, long ones too: `WMR_LONG_TESTS=1 cargo test -p wmr-cli
//! --test integration docs_commands:: -- --nocapture`. `WMR_DOCS_ONLY=examples/paper,firmware` runs the documents
//! whose path starts with one of the given prefixes only (to finish a long run in parts),
//! `WMR_DOCS_ONLY=README.md:233` the block that holds that line; the others are counted as
//! skipped, never passed.

use crate::skip;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// What a documented command must do.
#[derive(Debug)]
struct DocCommand {
    /// `FILE:LINE` of the command in its document.
    at: String,
    /// The command as a shell would read it (continuations joined, comment dropped).
    text: String,
    /// Needs `WMR_LONG_TESTS=1`: marked long or hardware in the doc, or an inline sweep.
    long: bool,
    /// Lines the doc says it prints (console blocks); `None`: not compared.
    expected: Option<Vec<String>>,
    /// Exit code the doc says it ends with.
    code: i32,
    /// The line of the block's fence (of the span, inline): a `cd` lasts for its block.
    block: usize,
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

/// The documents: README.md, docs/*.md, and every README.md under examples/, benches/,
/// firmware/ and crates/ (tracked by git, so node_modules and build output are not read).
fn documents(root: &Path) -> Vec<PathBuf> {
    let out = Command::new("git").arg("-C").arg(root).args(["ls-files", "-z", "*.md"]).output().expect("run git");
    assert!(out.status.success(), "git ls-files: {}", String::from_utf8_lossy(&out.stderr));
    let mut docs: Vec<PathBuf> = String::from_utf8(out.stdout)
        .unwrap()
        .split('\0')
        .filter(|p| !p.is_empty())
        .filter(|p| {
            *p == "README.md"
                || (p.starts_with("docs/") && !p["docs/".len()..].contains('/'))
                || (["examples/", "benches/", "firmware/", "crates/"].iter().any(|d| p.starts_with(d))
                    && p.ends_with("/README.md"))
        })
        .map(PathBuf::from)
        .collect();
    docs.sort();
    docs
}

/// `line` without a trailing ` # comment` (a `#` outside quotes after whitespace).
fn strip_comment(line: &str) -> &str {
    let (mut single, mut double) = (false, false);
    let bytes = line.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b'\'' if !double => single = !single,
            b'"' if !single => double = !double,
            b'#' if !single && !double && (i == 0 || bytes[i - 1].is_ascii_whitespace()) => return &line[..i],
            _ => {}
        }
    }
    line
}

/// Placeholders the docs write for "your file": a span naming one is not a whole command.
const PLACEHOLDERS: [&str; 7] = ["FILE", "OUT", "DIR", "LAYOUT", "ADDR", "STEM", "..."];

/// The inline `wmr-cli` commands of `text` outside fenced blocks, with their line.
fn inline_commands(doc: &str, text: &str, root: &Path, out: &mut Vec<DocCommand>) {
    // Spans may wrap over a line break: walk the text, not the lines.
    let mut line = 1;
    let mut in_fence = false;
    let mut rest = text;
    while let Some(i) = rest.find(['`', '\n']) {
        let (c, after) = (rest.as_bytes()[i], &rest[i + 1..]);
        if c == b'\n' {
            line += 1;
            if after.trim_start().starts_with("```") {
                in_fence = !in_fence;
            }
            rest = after;
            continue;
        }
        if let Some(tail) = after.strip_prefix("``") {
            rest = tail; // a fence's backticks, not a span
            continue;
        }
        let Some(end) = after.find('`') else { break };
        let span = &after[..end];
        let start_line = line;
        line += span.matches('\n').count();
        rest = &after[end + 1..];
        if in_fence {
            continue;
        }
        let span = span.split_whitespace().collect::<Vec<_>>().join(" ");
        let words: Vec<&str> = span.split(' ').collect();
        let whole = words.first() == Some(&"wmr-cli")
            && words.iter().any(|w| w.ends_with(".toml") && root.join(w).is_file())
            && !words.iter().any(|w| PLACEHOLDERS.iter().any(|p| w.contains(p)) || w.contains('|'));
        if whole {
            out.push(DocCommand {
                at: format!("{doc}:{start_line}"),
                long: words.get(1) == Some(&"sweep"),
                text: span,
                expected: None,
                code: 0,
                block: start_line,
            });
        }
    }
}

/// Every command of document `doc` (path relative to `root`).
fn commands(doc: &str, text: &str, root: &Path) -> Vec<DocCommand> {
    let mut out = Vec::new();
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    let mut marked = false;
    while i < lines.len() {
        let l = lines[i].trim();
        if l.starts_with("<!-- docs-test:") {
            let what = l.trim_start_matches("<!-- docs-test:").trim_end_matches("-->");
            assert!(
                what.split(',').all(|w| matches!(w.trim(), "long" | "hardware")),
                "{doc}:{}: unknown docs-test marker {l:?} (long, hardware)",
                i + 1
            );
            marked = true;
            i += 1;
            continue;
        }
        let Some(tag) = l.strip_prefix("```") else {
            if !l.is_empty() {
                marked = false;
            }
            i += 1;
            continue;
        };
        let tag = tag.trim().to_string();
        let fence = i;
        i += 1;
        let mut body = Vec::new();
        while i < lines.len() && !lines[i].trim().starts_with("```") {
            body.push((i + 1, lines[i]));
            i += 1;
        }
        i += 1; // the closing fence
        let long = std::mem::take(&mut marked);
        match tag.as_str() {
            "sh" | "bash" | "shell" => {
                let mut pending: Option<(usize, String)> = None;
                for (n, raw) in body {
                    let l = strip_comment(raw).trim_end();
                    let (start, mut text) = pending.take().unwrap_or((n, String::new()));
                    if let Some(head) = l.strip_suffix('\\') {
                        text.push_str(head);
                        pending = Some((start, text));
                        continue;
                    }
                    text.push_str(l);
                    let text = text.trim().to_string();
                    if !text.is_empty() {
                        out.push(DocCommand {
                            at: format!("{doc}:{start}"),
                            text,
                            long,
                            expected: None,
                            code: 0,
                            block: fence,
                        });
                    }
                }
                assert!(pending.is_none(), "{doc}:{}: the block ends in a continued line", fence + 1);
            }
            "console" => {
                for (n, raw) in body {
                    if let Some(cmd) = raw.strip_prefix("$ ") {
                        out.push(DocCommand {
                            at: format!("{doc}:{n}"),
                            text: strip_comment(cmd).trim().to_string(),
                            long,
                            expected: Some(Vec::new()),
                            code: 0,
                            block: fence,
                        });
                    } else {
                        let last = out.last_mut().filter(|c| c.expected.is_some());
                        let last = last.unwrap_or_else(|| panic!("{doc}:{n}: a console block opens with `$ `"));
                        let lines = last.expected.as_mut().unwrap();
                        match raw.strip_prefix("? ") {
                            Some(code) if lines.is_empty() => {
                                last.code = code.trim().parse().unwrap_or_else(|_| panic!("{doc}:{n}: `? N`"))
                            }
                            _ => lines.push(raw.to_string()),
                        }
                    }
                }
            }
            _ => {}
        }
    }
    inline_commands(doc, text, root, &mut out);
    out
}

/// Whether `actual` matches the `pattern` line (`[..]`: any text).
fn line_matches(pattern: &str, actual: &str) -> bool {
    let mut parts = pattern.split("[..]");
    let first = parts.next().unwrap();
    let Some(mut rest) = actual.strip_prefix(first) else { return false };
    let parts: Vec<&str> = parts.collect();
    for (k, part) in parts.iter().enumerate() {
        if k + 1 == parts.len() {
            return rest.ends_with(part);
        }
        match rest.find(part) {
            Some(p) => rest = &rest[p + part.len()..],
            None => return false,
        }
    }
    rest.is_empty()
}

/// Whether `actual` matches the `expected` lines (`...`: any number of lines).
fn lines_match(expected: &[String], actual: &[&str]) -> bool {
    match expected.split_first() {
        None => actual.is_empty(),
        Some((e, rest)) if e.trim() == "..." => (0..=actual.len()).any(|k| lines_match(rest, &actual[k..])),
        Some((e, rest)) => actual
            .split_first()
            .is_some_and(|(a, tail)| line_matches(e.trim_end(), a.trim_end()) && lines_match(rest, tail)),
    }
}

/// The workspace's target folder: a documented `cargo build` and the release `wmr-cli` of
/// the long run reuse what is built there.
fn target_dir(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from)
}

/// Builds the release `wmr-cli` into the workspace's target folder; returns the folder
/// that holds it, `target/release`.
fn release_wmr_cli(root: &Path) -> PathBuf {
    let target = target_dir(root);
    let start = Instant::now();
    let status = Command::new(env!("CARGO"))
        .args(["build", "--release", "-p", "wmr-cli", "--locked", "--target-dir"])
        .arg(&target)
        .current_dir(root)
        .status()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", env!("CARGO")));
    assert!(status.success(), "cargo build --release -p wmr-cli --locked: {status}");
    eprintln!("{:>7.2} s  (the release wmr-cli for the long commands)", start.elapsed().as_secs_f64());
    target.join("release")
}

/// A fresh copy of the tracked files of `root` (as they are in the working tree) in a
/// temporary folder, with `target` linked to the workspace's target folder.
fn fresh_copy(root: &Path) -> tempfile::TempDir {
    let dir = tempfile::Builder::new().prefix("wmr-docs-").tempdir().unwrap();
    let out = Command::new("git").arg("-C").arg(root).args(["ls-files", "-z"]).output().unwrap();
    for rel in String::from_utf8(out.stdout).unwrap().split('\0').filter(|p| !p.is_empty()) {
        let (from, to) = (root.join(rel), dir.path().join(rel));
        if !from.is_file() {
            continue; // deleted in the working tree
        }
        fs::create_dir_all(to.parent().unwrap()).unwrap();
        fs::copy(&from, &to).unwrap();
        // The original's modification time: cargo judges the shared target folder's
        // artifacts by the sources' times, and a copy dated now made every documented
        // `cargo build` or `cargo run` rebuild the workspace (3 to 7 minutes each).
        let modified = fs::metadata(&from).and_then(|m| m.modified()).unwrap();
        fs::File::options().write(true).open(&to).and_then(|f| f.set_modified(modified)).unwrap();
    }
    std::os::unix::fs::symlink(target_dir(root), dir.path().join("target")).unwrap();
    // A git repository of those files, as a clone is: documented tests that list the
    // tracked files (`git ls-files`) see the same list (not committed: nothing needs it).
    for args in [&["init", "-q"][..], &["add", "-A"]] {
        let st = Command::new("git").args(args).current_dir(dir.path()).stdout(Stdio::null()).status().unwrap();
        assert!(st.success(), "git {args:?} in the fresh copy: {st}");
    }
    dir
}

/// Runs `cmd` with bash in `cwd`, `bin` first on PATH; returns (exit code, stdout then
/// stderr, the folder the command ended in).
///
/// Each line runs in a bash of its own, but what a block's earlier lines left behind
/// lasts as it would in one terminal: the folder (`cd`) and the exported variables (a
/// venv's `. .venv/bin/activate`), kept in `state`'s two files; [`forget`] ends them
/// when the block changes.
fn run(cmd: &str, cwd: &Path, bin: &Path, state: &Path, timeout_s: u32) -> (i32, String, PathBuf) {
    let (pwd, env) = (state.with_extension("pwd"), state.with_extension("env"));
    let script = format!(
        "[ -f '{env}' ] && . '{env}'\nset -o pipefail\n{cmd}\nrc=$?\npwd > '{pwd}'\nexport -p > '{env}'\nexit $rc",
        env = env.display(),
        pwd = pwd.display()
    );
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let out = Command::new("timeout")
        .args([format!("{timeout_s}"), "bash".into(), "-c".into(), script])
        .current_dir(cwd)
        .env("PATH", path)
        // A documented `./scripts/test` runs this harness again: the normal set only.
        .env_remove("WMR_LONG_TESTS")
        // A documented `--live` command has no viewer here: it streams after 1 s without
        // one and so ends by itself (docs/scenario.md, "Live view").
        .env("WMR_LIVE_START_AFTER_S", "1")
        .output()
        .expect("spawn bash");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let end = fs::read_to_string(&pwd).map_or_else(|_| cwd.to_path_buf(), |s| PathBuf::from(s.trim()));
    let _ = fs::remove_file(&pwd);
    (out.status.code().unwrap_or(-1), text, end)
}

/// Ends what a block's lines carried over to the next ([`run`]): at a new block.
fn forget(state: &Path) {
    let _ = fs::remove_file(state.with_extension("env"));
}

/// Writes what a failed command printed to `target/docs-commands/<doc>-<line>.log`
/// under the workspace's target folder; returns the path.
fn keep_output(root: &Path, at: &str, output: &str) -> PathBuf {
    let dir = target_dir(root).join("docs-commands");
    fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{}.log", at.replace(['/', ':'], "-")));
    fs::write(&path, output).unwrap();
    path
}

/// The failure of `c`, or None when it did what its doc says.
fn check(c: &DocCommand, code: i32, output: &str) -> Option<String> {
    let lines: Vec<&str> = output.lines().collect();
    let printed = || {
        let tail = &lines[lines.len().saturating_sub(40)..];
        format!("it printed (last {} lines):\n{}", tail.len(), tail.join("\n"))
    };
    if code == 124 {
        return Some(format!("{}: `{}` timed out; {}", c.at, c.text, printed()));
    }
    if code != c.code {
        return Some(format!("{}: `{}` exited with {code}, the doc says {}; {}", c.at, c.text, c.code, printed()));
    }
    let expected = c.expected.as_ref()?;
    (!lines_match(expected, &lines)).then(|| {
        format!(
            "{}: `{}` printed something else than the doc says.\nthe doc:\n{}\n{}",
            c.at,
            c.text,
            expected.join("\n"),
            printed()
        )
    })
}

#[test]
fn every_documented_command_does_what_its_doc_says() {
    let root = repo();
    let long = std::env::var_os("WMR_LONG_TESTS").is_some_and(|v| v == "1");
    // The folder first on PATH, with the `wmr-cli` the documented commands run (module doc).
    let debug = tempfile::tempdir().unwrap();
    let bin = if long {
        release_wmr_cli(&root)
    } else {
        std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_wmr-cli"), debug.path().join("wmr-cli")).unwrap();
        debug.path().to_path_buf()
    };
    let only: Option<Vec<String>> =
        std::env::var("WMR_DOCS_ONLY").ok().map(|v| v.split(',').map(|s| s.trim().to_string()).collect());
    // The documents' commands, each document in its own copy: several documents at once
    // on the executor the sweeps use (the long commands, whole builds among them, one
    // document at a time), reported in the documents' order.
    let docs = documents(&root);
    let job = |i: usize| run_document(&root, &docs[i], only.as_deref(), long, &bin);
    let results: Vec<DocResult> =
        if long { (0..docs.len()).map(job).collect() } else { wmr_scenario::executor::map_ordered(docs.len(), job) };
    let (mut ran, mut skipped, mut failures, mut not_selected) = (0, Vec::new(), Vec::new(), Vec::new());
    for r in results {
        eprint!("{}", r.log);
        ran += r.ran;
        skipped.extend(r.skipped);
        failures.extend(r.failures);
        not_selected.extend(r.not_selected);
    }
    eprintln!("docs_commands: ran {ran} documented command(s), {} long or hardware ones not run", skipped.len());
    if !not_selected.is_empty() {
        skip::missing(
            "WMR_DOCS_ONLY",
            &format!(
                "{} document(s) or command(s) not selected by WMR_DOCS_ONLY: {}",
                not_selected.len(),
                not_selected.join(", ")
            ),
        );
    }
    if !skipped.is_empty() {
        skip::missing(
            "long",
            &format!(
                "{} documented command(s) marked long or hardware not run (WMR_LONG_TESTS=1 runs them): {}",
                skipped.len(),
                skipped.join("; ")
            ),
        );
    }
    assert!(failures.is_empty(), "{} documented command(s) fail:\n\n{}", failures.len(), failures.join("\n\n"));
}

/// What one document's commands did.
#[derive(Default)]
struct DocResult {
    /// Commands run.
    ran: usize,
    /// `doc:line `command`` of the long or hardware commands not run.
    skipped: Vec<String>,
    /// What each failed command's check said.
    failures: Vec<String>,
    /// Documents or commands `WMR_DOCS_ONLY` left out.
    not_selected: Vec<String>,
    /// The time and text of each command run, as printed.
    log: String,
}

/// Runs the commands of `doc` (selected by `WMR_DOCS_ONLY`'s entries `only`) in a fresh
/// copy of the repository, with the `wmr-cli` of `bin`.
fn run_document(root: &Path, doc: &Path, only: Option<&[String]>, long: bool, bin: &Path) -> DocResult {
    let mut r = DocResult::default();
    let name = doc.to_string_lossy().into_owned();
    if let Some(only) = only
        && !only.iter().any(|o| !o.is_empty() && name.starts_with(o.split(':').next().unwrap_or_default()))
    {
        r.not_selected.push(name);
        return r;
    }
    let text = fs::read_to_string(root.join(doc)).unwrap();
    let mut cmds = commands(&name, &text, root);
    // `doc:line` entries select the blocks holding those lines (whole: a block's lines
    // share their folder and variables).
    let lines: Vec<&String> = only
        .iter()
        .flat_map(|o| o.iter())
        .filter(|o| o.contains(':') && name == o.split(':').next().unwrap_or_default())
        .collect();
    if !lines.is_empty() {
        let blocks: Vec<usize> = cmds.iter().filter(|c| lines.contains(&&c.at)).map(|c| c.block).collect();
        let (keep, drop): (Vec<_>, Vec<_>) = cmds.into_iter().partition(|c| blocks.contains(&c.block));
        r.not_selected.extend(drop.iter().map(|c| c.at.clone()));
        cmds = keep;
    }
    if cmds.is_empty() {
        return r;
    }
    let copy = fresh_copy(root);
    // Outside the copy: a documented `git status` or `ls` must not see it.
    let state_dir = tempfile::tempdir().unwrap();
    let state = state_dir.path().join("carried");
    // `cd` and exports last for the rest of their block ([`run`]).
    let mut cwd = copy.path().to_path_buf();
    let mut block = usize::MAX;
    for c in &cmds {
        if !c.long || long {
            if c.block != block {
                (block, cwd) = (c.block, copy.path().to_path_buf());
                forget(&state);
            }
            let start = Instant::now();
            let (code, output, end) = run(&c.text, &cwd, bin, &state, if c.long { 3600 } else { 300 });
            r.log += &format!("{:>7.2} s  {}  {}\n", start.elapsed().as_secs_f64(), c.at, c.text);
            r.ran += 1;
            if let Some(f) = check(c, code, &output) {
                // Said at once too: a long run stopped part-way still tells what failed.
                // The whole output is kept (the message shows its last 40 lines, and a
                // documented `./scripts/test` says what failed far above them).
                let log = keep_output(root, &c.at, &output);
                eprintln!("FAILED  {}  {}  (all it printed: {})", c.at, c.text, log.display());
                r.failures.push(format!("{f}\n(all it printed: {})", log.display()));
            }
            cwd = end;
        } else {
            r.skipped.push(format!("{} `{}`", c.at, c.text));
        }
    }
    r
}

/// The matcher itself: wildcards match what they say and nothing more.
#[test]
fn output_patterns_match_what_they_say() {
    let e = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert!(lines_match(&e(&["a [..] c"]), &["a b c"]));
    assert!(!lines_match(&e(&["a [..] c"]), &["a b d"]));
    assert!(lines_match(&e(&["a", "...", "z"]), &["a", "b", "c", "z"]));
    assert!(lines_match(&e(&["a", "...", "z"]), &["a", "z"]));
    assert!(!lines_match(&e(&["a", "z"]), &["a", "b", "z"]));
    assert!(!lines_match(&e(&["a"]), &["a", "b"]));
    assert_eq!(strip_comment("wmr-cli run f.toml -o x.csv   # CSV: run,t"), "wmr-cli run f.toml -o x.csv   ");
    assert_eq!(strip_comment("echo '# not a comment'"), "echo '# not a comment'");
}

/// A block's lines share what one terminal would: the folder and exported variables;
/// a new block starts afresh.
#[test]
fn a_blocks_lines_share_folder_and_exports() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("sub")).unwrap();
    let state = dir.path().join("carried");
    let bin = dir.path();
    let (code, _, end) = run("cd sub && export WMR_DOCS_PROBE=venv", dir.path(), bin, &state, 10);
    assert_eq!((code, end.file_name().unwrap().to_str().unwrap()), (0, "sub"));
    let (_, out, _) = run("echo \"[$WMR_DOCS_PROBE]\"", &end, bin, &state, 10);
    assert_eq!(out.trim(), "[venv]");
    forget(&state);
    let (_, out, _) = run("echo \"[$WMR_DOCS_PROBE]\"", &end, bin, &state, 10);
    assert_eq!(out.trim(), "[]");
}
