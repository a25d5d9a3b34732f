//! README.md tells what the header has: every `wmr_*` name and `WMR_*` constant it shows
//! is declared in `include/wmr.h`, and every sensor model the header can initialise is
//! named in its "Sensors" section (issue 40: it once named only the perfect sensor while
//! the header declared `wmr_sensor_f32_init_pose`).

use std::collections::BTreeSet;
use std::path::PathBuf;

fn read(rel: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The identifiers of `text` that start with `prefix` (`wmr_` or `WMR_`).
fn names(text: &str, prefix: &str) -> BTreeSet<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with(prefix) && w.len() > prefix.len())
        .map(str::to_owned)
        .collect()
}

#[test]
fn every_name_the_readme_shows_is_in_the_header() {
    let (readme, header) = (read("README.md"), read("include/wmr.h"));
    let tests: String = std::fs::read_dir(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests"))
        .unwrap()
        .filter_map(|e| std::fs::read_to_string(e.unwrap().path()).ok())
        .collect();
    for prefix in ["wmr_", "WMR_"] {
        let declared = names(&header, prefix);
        // `wmr_<kind>_controller_*` splits into `wmr_` and a name ending in `_`: patterns.
        // `WMR_FUZZ_SEED` and the like are the tests' environment variables, read as "NAME".
        let missing: Vec<_> = names(&readme, prefix)
            .into_iter()
            .filter(|n| !n.ends_with('_') && !declared.contains(n) && !tests.contains(&format!("\"{n}\"")))
            .collect();
        assert!(missing.is_empty(), "README.md names what include/wmr.h does not declare: {missing:?}");
    }
}

#[test]
fn every_sensor_model_of_the_header_is_in_the_readme() {
    let (readme, header) = (read("README.md"), read("include/wmr.h"));
    let section = &readme[readme.find("\n## Sensors").expect("a Sensors section")..];
    let section = &section[..section[1..].find("\n## ").map_or(section.len(), |i| i + 1)];
    let inits: Vec<String> =
        names(&header, "wmr_sensor_f32_init_").into_iter().chain(names(&header, "wmr_sensor_f32_odometry")).collect();
    assert!(inits.len() >= 3, "{inits:?}");
    for name in &inits {
        assert!(section.contains(name.as_str()), "README.md's Sensors section does not name {name}");
    }
}
