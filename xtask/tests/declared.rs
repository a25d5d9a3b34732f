//! Every test file is compiled: with `autotests = false` (each crate's integration tests
//! are one binary, `tests/integration.rs`), a file of a crate's `tests/` that neither its
//! `integration.rs` declares (`mod name;`) nor its Cargo.toml names (`[[test]]` `path`)
//! would never build nor run, silently.

use std::path::Path;

/// The `tests/*.rs` files of every package that are not declared.
fn undeclared(root: &Path) -> Vec<String> {
    let mut missing = Vec::new();
    let mut packages: Vec<_> = ["crates", "."]
        .iter()
        .flat_map(|d| std::fs::read_dir(root.join(d)).into_iter().flatten().flatten())
        .map(|e| e.path())
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    packages.push(root.join("xtask"));
    packages.sort();
    packages.dedup();
    for package in packages {
        let manifest = std::fs::read_to_string(package.join("Cargo.toml")).unwrap_or_default();
        if !manifest.contains("autotests = false") {
            continue; // cargo finds each file itself
        }
        let integration = std::fs::read_to_string(package.join("tests/integration.rs")).unwrap_or_default();
        let Ok(files) = std::fs::read_dir(package.join("tests")) else { continue };
        for file in files.flatten().map(|e| e.path()) {
            let (Some(stem), Some("rs")) =
                (file.file_stem().and_then(|s| s.to_str()), file.extension().and_then(|e| e.to_str()))
            else {
                continue;
            };
            let declared = stem == "integration"
                || integration.lines().any(|l| l.trim() == format!("mod {stem};"))
                || manifest.contains(&format!("path = \"tests/{stem}.rs\""));
            if !declared {
                missing.push(format!("{}", file.strip_prefix(root).unwrap_or(&file).display()));
            }
        }
    }
    missing
}

#[test]
fn every_test_file_is_declared() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let missing = undeclared(&root);
    assert!(
        missing.is_empty(),
        "test files no test target builds: {missing:?}; add `mod <name>;` to their crate's tests/integration.rs"
    );
}
