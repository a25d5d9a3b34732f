//! `wmr-cli plot` on a `[sweep]`: one figure per start with the path of every law
//! (`examples/paper/compare-paths.toml`), and a clear refusal for sweeps with many starts.

use std::path::PathBuf;
use std::process::Command;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("wmr-compare-paths-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn plot_draws_every_law_from_each_start_of_a_sweep() {
    let out = tmp_dir("ok");
    let status = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["plot", repo("examples/paper/compare-paths.toml").to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    for k in 0..2 {
        let svg = std::fs::read_to_string(out.join(format!("compare-start{k}.svg"))).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let curves = doc
            .descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .filter(|n| n.attribute("points").is_some_and(|p| p.split_whitespace().count() > 10))
            .count();
        assert_eq!(curves, 4, "one path per law from start {k}");
        for law in ["paper", "paper_bidirectional", "polar", "lyapunov"] {
            assert!(svg.contains(&format!(">{law}")), "{law} in the legend");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn plot_refuses_a_sweep_with_too_many_starts_naming_the_limit() {
    let dir = tmp_dir("many");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("many.toml");
    std::fs::write(&file, "[sim]\nt_end = 1.0\n[sweep]\nrandom = { n = 13, radius = 1.0 }\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["plot", file.to_str().unwrap(), "-o", dir.join("figs").to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("at most 12 starts"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
