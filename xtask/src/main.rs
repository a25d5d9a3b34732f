//! `cargo xtask gen`: writes every generated file (the C API's entry points and header,
//! the Python classes and stubs, the firmware cost programs, the docs tables).
//! `cargo xtask check`: lists what is out of date.

use std::process::ExitCode;

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
