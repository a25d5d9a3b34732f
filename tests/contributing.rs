//! CONTRIBUTING.md, performed: in a scratch copy of the repository, a law is added
//! exactly as it says (a copy of Kanayama's law under a new name: its file, the `mod`
//! line, the registry line and its docs section), `cargo xtask gen` is run, and the CLI
//! (`check`, `run`, `trace`, `help keys`), the C header, the Python classes and the
//! firmware's law programs must all know it. A long check (a build of the workspace in
//! the copy): `WMR_LONG_TESTS=1` runs it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "../crates/wmr-cli/tests/skip/mod.rs"]
mod skip;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn write(p: &Path, text: &str) {
    std::fs::write(p, text).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn run(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The tracked files of the repository, copied into `to`.
fn copy_tracked(to: &Path) {
    let files = run(Command::new("git").args(["ls-files", "-z"]).current_dir(root()));
    for rel in files.stdout.split(|b| *b == 0).filter(|f| !f.is_empty()) {
        let rel = Path::new(std::str::from_utf8(rel).expect("a UTF-8 path"));
        let (src, dst) = (root().join(rel), to.join(rel));
        if !src.is_file() {
            continue;
        }
        std::fs::create_dir_all(dst.parent().expect("a file in a folder")).expect("mkdir");
        std::fs::copy(&src, &dst).unwrap_or_else(|e| panic!("{}: {e}", src.display()));
    }
}

#[test]
fn a_law_added_as_contributing_says_is_known_everywhere() {
    if std::env::var("WMR_LONG_TESTS").as_deref() != Ok("1") {
        skip::missing("long", "adds a law in a scratch copy and builds it there (WMR_LONG_TESTS=1 runs it)");
        return;
    }
    let scratch = std::env::temp_dir().join(format!("wmr-contributing-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    copy_tracked(&scratch);
    let controller = scratch.join("crates/wmr-core/src/controller");

    // 1. The law's file: Kanayama's, renamed.
    let law = read(&controller.join("kanayama.rs"))
        .replace("KanayamaParams", "KanayamaCopyParams")
        .replace("KanayamaLaw", "KanayamaCopyLaw");
    write(&controller.join("kanayama_copy.rs"), &law);
    // 2. The `mod` line.
    let m = read(&controller.join("mod.rs"));
    write(
        &controller.join("mod.rs"),
        &m.replacen("pub mod kanayama;\n", "pub mod kanayama;\npub mod kanayama_copy;\n", 1),
    );
    // 3. The registry line, after the last law.
    let reg_path = controller.join("registry.rs");
    let reg = read(&reg_path);
    let last = "follows Path;\n";
    let at = reg.rfind(last).expect("the registry's last line") + last.len();
    let mut reg = reg;
    reg.insert_str(
        at,
        "            /// A copy of Kanayama's law (CONTRIBUTING.md, performed by tests/contributing.rs).\n            \
         KanayamaCopy(KanayamaCopyParams, KanayamaCopyLaw) = kanayama_copy, code 7, follows Trajectory;\n",
    );
    write(&reg_path, &reg);
    // 4. The docs text the tests ask for: the law's section of docs/scenario.md (its keys
    // table between markers, filled by `cargo xtask gen`).
    let docs_path = scratch.join("docs/scenario.md");
    let docs = read(&docs_path);
    let a = docs.find("### `kind = \"kanayama\"`").expect("Kanayama's section");
    let b = a + 1 + docs[a + 1..].find("\n### ").expect("the next section") + 1;
    let section = docs[a..b]
        .replace(
            "### `kind = \"kanayama\"`: Kanayama et al.'s",
            "### `kind = \"kanayama_copy\"`: a copy of Kanayama et al.'s",
        )
        .replace("keys:controller.kanayama ", "keys:controller.kanayama_copy ");
    let mut docs = docs;
    docs.insert_str(b, &section);
    write(&docs_path, &docs);

    // Then `cargo xtask gen`, in a target folder kept between runs (a warm cache).
    let target = root().join("target/contributing-scratch");
    let cargo = || {
        let mut c = Command::new(env!("CARGO"));
        c.current_dir(&scratch).env("CARGO_TARGET_DIR", &target).env_remove("WMR_SKIP_LOG");
        c
    };
    run(cargo().args(["xtask", "gen"]));
    run(cargo().args(["xtask", "check"]));
    run(cargo().args(["build", "--locked", "-p", "wmr-cli", "-p", "wmr-ffi", "-p", "wmr-py"]));
    let cli = target.join("debug/wmr-cli");

    // The CLI: the help, check, run (the same bits as Kanayama's: the same law), trace.
    let help = run(Command::new(&cli).args(["help", "keys"]));
    assert!(String::from_utf8_lossy(&help.stdout).contains("kanayama_copy"), "help keys lacks the new law");
    let circle = read(&root().join("examples/tracking/circle.toml"));
    assert!(circle.contains("kind = \"kanayama\""), "examples/tracking/circle.toml runs Kanayama's law");
    let copy = circle.replace("kind = \"kanayama\"", "kind = \"kanayama_copy\"");
    write(&scratch.join("copy.toml"), &copy);
    write(&scratch.join("original.toml"), &circle);
    let check = run(Command::new(&cli).args(["check", "copy.toml"]).current_dir(&scratch));
    assert!(String::from_utf8_lossy(&check.stdout).contains("kanayama_copy"));
    for (toml, csv) in [("copy.toml", "copy.csv"), ("original.toml", "original.csv")] {
        run(Command::new(&cli).args(["run", toml, "-o", csv]).current_dir(&scratch));
    }
    assert_eq!(
        std::fs::read(scratch.join("copy.csv")).unwrap(),
        std::fs::read(scratch.join("original.csv")).unwrap(),
        "the copy of Kanayama's law must run as Kanayama's"
    );
    run(Command::new(&cli).args(["trace", "copy.toml", "-o", "copy.bin"]).current_dir(&scratch));
    let trace = std::fs::read(scratch.join("copy.bin")).unwrap();
    // Header (6 words), then the config: its first word is the law's code.
    assert_eq!(u32::from_le_bytes(trace[24..28].try_into().unwrap()), 7, "the trace's law code");

    // The C header, the Python classes and stubs, the firmware's cost program.
    let header = read(&scratch.join("crates/wmr-ffi/include/wmr.h"));
    for name in [
        "wmr_kanayama_copy_controller_f32_init",
        "wmr_kanayama_copy_controller_f64_update",
        "WMR_KANAYAMA_COPY_CONTROLLER_F32_WORDS",
    ] {
        assert!(header.contains(name), "wmr.h lacks {name}");
    }
    assert!(read(&scratch.join("crates/wmr-py/python/wmr_py/_laws.py")).contains("\"KanayamaCopyController\""));
    let stub = read(&scratch.join("crates/wmr-py/python/wmr_py/_native.pyi"));
    let class = &stub[stub.find("class KanayamaCopyController:").expect("the generated stub class")..];
    assert!(class[..class.find("# end of generated keys").unwrap()].contains("kx: float = 10.0"), "stub keywords");
    assert!(scratch.join("firmware/src/bin/cost-kanayama-copy.rs").is_file(), "the firmware's cost program");
    let _ = std::fs::remove_dir_all(&scratch);
}
