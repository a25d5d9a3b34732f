//! Issue 12: mutated scenario text through `check`, `run` and `sweep`. Every outcome is
//! exit 0, or exit 2 with one line that names the key (or, for text that is not TOML, the
//! line), with no control character; never a panic, an abort or a hang; `check` agrees
//! with the library. Seeded: `WMR_FUZZ_CASES` (default 2,000) and `WMR_FUZZ_SEED`
//! (default 12) choose how many and which.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use wmr_scenario::Scenario;

/// xorshift64*: a small seeded generator, enough to pick mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

/// splitmix64: spreads a case number into a generator state.
fn splitmix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The seed texts: every example scenario and the bad-input corpus, and small ones.
fn seeds() -> Vec<String> {
    let mut files = Vec::new();
    for dir in ["examples", "examples/paper", "crates/wmr-cli/tests/bad"] {
        for e in std::fs::read_dir(repo().join(dir)).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "toml") {
                files.push(e.path());
            }
        }
    }
    files.sort();
    let mut texts: Vec<String> = files.iter().map(|f| std::fs::read_to_string(f).unwrap()).collect();
    // The same files with little work (t_end = 0.05 s, few starts), so that `run` and
    // `sweep` take them too.
    let small: Vec<String> = texts
        .iter()
        .filter(|t| t.contains("t_end"))
        .map(|t| {
            let t = t.replace("n = 1000", "n = 3").replace("n = 40,", "n = 3,").replace("nx = 21", "nx = 2");
            t.lines()
                .map(|l| if l.trim_start().starts_with("t_end") { "t_end = 0.05" } else { l })
                .collect::<Vec<_>>()
                .join("\n")
        })
        .collect();
    texts.extend(small);
    texts.push(
        "[sim]\nt_end = 0.05\n[[run]]\nstart = { x = 0.1, theta_deg = 10 }\ngoal = { x = 1.0, y = 1.0 }\n".into(),
    );
    texts.push(
        "[sim]\nt_end = 0.05\n[sweep]\ngoal = { x = 0.5 }\ncontrollers = [{ kind = \"paper\" }, { kind = \"polar\" }]\n\
         grid = { x_min = -1.0, x_max = 1.0, nx = 2, y_min = -1.0, y_max = 1.0, ny = 2, theta_deg = [0.0, 90.0] }\n"
            .into(),
    );
    texts
}

const VALUES: [&str; 22] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1.7e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "99999999999999999999",
    "4294967296",
    "2147483648",
    "-0.0",
    "\"text\"",
    "true",
    "[1, 2, 3]",
    "{ x = 1 }",
    "[]",
    "{}",
    "\"\\u001b[31m\\u202e\"",
    "1e6",
    "0.003",
];

/// One mutation of `text`.
fn mutate(text: &str, rng: &mut Rng) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    match rng.below(11) {
        // A number (or the value after `=`) replaced.
        0..=3 => {
            let places: Vec<usize> = text
                .match_indices("= ")
                .map(|(i, _)| i + 2)
                .chain(text.match_indices(['0', '1', '2', '5'].as_slice()).map(|(i, _)| i))
                .collect();
            if let Some(&at) = places.get(rng.below(places.len())) {
                let end = text[at..].find([',', '}', '\n', ' ', ']']).map_or(text.len(), |e| at + e);
                let mut out = text[..at].to_owned();
                let v: &str = VALUES[rng.below(VALUES.len())];
                out.push_str(v);
                out.push_str(&text[end..]);
                bytes = out.into_bytes();
            }
        }
        // A key renamed: a character dropped or doubled.
        4 => {
            if !bytes.is_empty() {
                let at = rng.below(bytes.len());
                if rng.below(2) == 0 {
                    bytes.remove(at);
                } else {
                    bytes.insert(at, bytes[at]);
                }
            }
        }
        // Truncated at a random offset.
        5 => bytes.truncate(rng.below(bytes.len() + 1)),
        // Random bytes (control characters, invalid UTF-8) inserted.
        6 => {
            let at = rng.below(bytes.len() + 1);
            let n = 1 + rng.below(8);
            let junk: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
            bytes.splice(at..at, junk);
        }
        // Deep nesting.
        7 => {
            let depth = 1 + rng.below(3000);
            let nest = if rng.below(2) == 0 {
                format!("{}1{}", "[".repeat(depth), "]".repeat(depth))
            } else {
                format!("{}1{}", "{ a = ".repeat(depth), " }".repeat(depth))
            };
            bytes = format!("{text}\nname = {nest}\n").into_bytes();
        }
        // Many runs.
        8 => {
            let n = 1 + rng.below(500);
            let mut out = text.to_owned();
            for i in 0..n {
                out.push_str(&format!("[[run]]\ngoal = {{ x = {} }}\n", (i % 7) as f64 * 0.1));
            }
            bytes = out.into_bytes();
        }
        // `[[run]]` as `[run]`, tables duplicated.
        9 => bytes = text.replacen("[[run]]", "[run]", 1).into_bytes(),
        _ => {
            let lines: Vec<&str> = text.lines().collect();
            if !lines.is_empty() {
                let l = lines[rng.below(lines.len())];
                bytes = format!("{text}\n{l}\n").into_bytes();
            }
        }
    }
    bytes
}

/// Plant steps the CLI would run for this text, if it is a valid scenario.
fn work(text: &[u8]) -> Option<u128> {
    let text = std::str::from_utf8(text).ok()?;
    let sc = Scenario::from_toml_str(text, "fuzz").ok()?;
    Some(wmr_scenario::total_steps(&sc))
}

/// One CLI call: exit 0 or exit 2 with one clean line; `Err` describes anything else.
fn call(dir: &Path, args: &[&str]) -> Result<Output, String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let started = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            return Err(format!("{args:?}: still running after 60 s"));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let o = child.wait_with_output().map_err(|e| e.to_string())?;
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    match o.status.code() {
        Some(0) => {}
        Some(2) => {
            let lines: Vec<&str> = err.lines().filter(|l| !l.starts_with("wmr-cli: warning: ")).collect();
            if lines.len() != 1 {
                return Err(format!("{args:?}: not one line: {err:?}"));
            }
            let line = lines[0];
            if !line.starts_with("wmr-cli: error: ") {
                return Err(format!("{args:?}: {err:?}"));
            }
            if line.chars().any(|c| c.is_control() || ('\u{202a}'..='\u{202e}').contains(&c)) {
                return Err(format!("{args:?}: raw control character: {err:?}"));
            }
            // `FILE: [line L: ]KEY: reason`, or a file or syntax error without a key.
            let after = line.split_once("case.toml: ").map(|(_, r)| r).unwrap_or("");
            let after = after.split_once(": ").filter(|(l, _)| l.starts_with("line ")).map_or(after, |(_, r)| r);
            let names_key = after.split_once(": ").is_some_and(|(k, _)| {
                !k.is_empty() && k.chars().all(|c| c.is_ascii_alphanumeric() || "_.[]#-".contains(c))
            });
            let keyless = after.starts_with("bad TOML: ") || after.contains("is not UTF-8 text");
            if !(names_key || keyless) {
                return Err(format!("{args:?}: names no key: {err:?}"));
            }
        }
        code => return Err(format!("{args:?}: exit {code:?} (signal?): {err:?}")),
    }
    if err.contains("panicked") {
        return Err(format!("{args:?}: panic: {err}"));
    }
    Ok(o)
}

#[test]
fn mutated_scenarios_exit_0_or_2_with_one_line_naming_the_key() {
    let cases: usize = std::env::var("WMR_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(2000);
    let seed: u64 = std::env::var("WMR_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(12);
    let seeds = seeds();
    let next = AtomicUsize::new(0);
    let started = Instant::now();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).min(4);
    let failures: Vec<String> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let dir = tempfile::tempdir().unwrap();
                    let mut found = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= cases {
                            break;
                        }
                        let mut rng = Rng(splitmix(seed ^ splitmix(i as u64)) | 1);
                        let base = rng.pick(&seeds).clone();
                        let mut text = mutate(&base, &mut rng);
                        if rng.below(3) == 0 {
                            text = mutate(&String::from_utf8_lossy(&text), &mut rng);
                        }
                        let t0 = Instant::now();
                        let file = dir.path().join("case.toml");
                        std::fs::write(&file, &text).unwrap();
                        let lib_ok = work(&text);
                        let mut fail = |what: String| found.push(format!("case {i} (seed {seed}): {what}"));
                        match call(dir.path(), &["check", "case.toml"]) {
                            Ok(o) => {
                                if lib_ok.is_some() != o.status.success() {
                                    fail(format!("check exit {:?} but the library says {lib_ok:?}", o.status.code()));
                                }
                            }
                            Err(e) => fail(e),
                        }
                        // Small work only: run and sweep what takes at most 20,000 plant steps.
                        if lib_ok.is_some_and(|w| w <= 20_000) {
                            for args in [["run", "case.toml", "-o", "out.csv"], ["sweep", "case.toml", "-o", "out.csv"]]
                            {
                                if let Err(e) = call(dir.path(), &args) {
                                    fail(e);
                                }
                            }
                        }
                        let left: Vec<String> = std::fs::read_dir(dir.path())
                            .unwrap()
                            .flatten()
                            .map(|e| e.file_name().to_string_lossy().into_owned())
                            .filter(|n| n.ends_with(".tmp"))
                            .collect();
                        if !left.is_empty() {
                            fail(format!("temporary files left: {left:?}"));
                        }
                        if std::env::var("WMR_FUZZ_SLOW").is_ok() && t0.elapsed() > Duration::from_millis(150) {
                            eprintln!(
                                "slow case {i}: {:?} {:?}",
                                t0.elapsed(),
                                String::from_utf8_lossy(&text[..text.len().min(120)])
                            );
                        }
                        if !found.is_empty() && found.len() < 3 {
                            let keep = dir.path().join(format!("failed-{i}.toml"));
                            let _ = std::fs::copy(&file, keep);
                        }
                    }
                    found
                })
            })
            .collect();
        workers.into_iter().flat_map(|w| w.join().unwrap()).collect()
    });
    eprintln!("{cases} cases in {:.1} s", started.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
