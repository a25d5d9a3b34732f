//! `cargo xtask gen`: writes every generated file (this crate's generators, the C API's
//! entry points and header among them, then the docs key tables through wmr-cli's test
//! with `WMR_BLESS=1`). `cargo xtask check`: lists what is out of date
//! (this crate's files only; the others are checked by their crates' tests).

use std::process::{Command, ExitCode};

/// The tests that write the generated files of the crates that must compile first.
const BLESSED_TESTS: &[(&str, &str)] = &[("wmr-cli", "docs_tables")];

fn main() -> ExitCode {
    let root = xtask::repo_root();
    match std::env::args().nth(1).as_deref() {
        Some("gen") => {
            // Until nothing changes: the C header is read from the entry points on disk.
            for _ in 0..3 {
                let mut wrote = false;
                for g in xtask::generated() {
                    let path = root.join(&g.path);
                    if std::fs::read_to_string(&path).ok().as_deref() != Some(g.text.as_str()) {
                        if let Err(e) = std::fs::write(&path, &g.text) {
                            eprintln!("xtask: error: {}: {e}", g.path);
                            return ExitCode::from(1);
                        }
                        println!("wrote {}", g.path);
                        wrote = true;
                    }
                }
                if !wrote {
                    break;
                }
            }
            for stale in xtask::stale() {
                if let Err(e) = std::fs::remove_file(root.join(&stale)) {
                    eprintln!("xtask: error: {stale}: {e}");
                    return ExitCode::from(1);
                }
                println!("removed {stale}");
            }
            for (package, test) in BLESSED_TESTS {
                println!("WMR_BLESS=1 cargo test -p {package} --test {test}");
                let ok = Command::new(env!("CARGO"))
                    .args(["test", "-q", "--locked", "-p", package, "--test", test])
                    .env("WMR_BLESS", "1")
                    .current_dir(&root)
                    .status()
                    .is_ok_and(|s| s.success());
                if !ok {
                    eprintln!("xtask: error: WMR_BLESS=1 cargo test -p {package} --test {test} failed");
                    return ExitCode::from(1);
                }
            }
            ExitCode::SUCCESS
        }
        Some("check") => {
            let bad = xtask::out_of_date();
            if bad.is_empty() {
                println!("every generated file is up to date");
                ExitCode::SUCCESS
            } else {
                for b in &bad {
                    eprintln!("xtask: out of date: {b} (run `cargo xtask gen`)");
                }
                ExitCode::from(1)
            }
        }
        _ => {
            eprintln!("usage: cargo xtask gen | cargo xtask check");
            ExitCode::from(2)
        }
    }
}
