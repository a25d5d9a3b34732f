//! `firmware/src/bin/cost-<kind>.rs`: one cost program per law (its flash size alone,
//! and under QEMU its instructions and stack per update; `firmware/measure`).

use crate::registry::laws;
use crate::{Generated, repo_root};

fn path_of(kind: &str) -> String {
    format!("firmware/src/bin/cost-{}.rs", kind.replace('_', "-"))
}

/// The cost programs' texts.
pub fn generate() -> Vec<Generated> {
    laws()
        .into_iter()
        .map(|law| {
            let what = if !law.follows.needs_reference() {
                "Fig. 7 (start (0, 0, 0), goal (1, 1, 120 deg))"
            } else {
                "the figure-eight of examples/tracking"
            };
            let text = format!(
                "{}//! Cost program: the law `{}` with its wheel stage, the plant and the perfect sensor,\n\
                 //! on {what} in f32. Plain build: its flash size; `--features qemu`:\n\
                 //! instructions and stack per control update and plant step (firmware/measure).\n\
                 #![no_std]\n#![no_main]\n\n#[cortex_m_rt::entry]\nfn main() -> ! {{\n    \
                 wmr_firmware::cost_main::<wmr_core::{}<f32>>()\n}}\n",
                crate::header("the cost program of one law."),
                law.kind,
                law.law
            );
            Generated { path: path_of(law.kind), text }
        })
        .collect()
}

/// Cost programs of laws no longer in the registry (`cost-plant.rs`, `cost-none.rs` and
/// `cost-observer.rs` are written by hand: they measure no law of their own).
pub fn stale(generated: &[Generated]) -> Vec<String> {
    let dir = repo_root().join("firmware/src/bin");
    let Ok(entries) = std::fs::read_dir(&dir) else { return Vec::new() };
    let mut out: Vec<String> = entries
        .filter_map(|e| e.ok())
        .map(|e| format!("firmware/src/bin/{}", e.file_name().to_string_lossy()))
        .filter(|p| {
            p.contains("/cost-")
                && !p.ends_with("cost-plant.rs")
                && !p.ends_with("cost-none.rs")
                && !p.ends_with("cost-observer.rs")
        })
        .filter(|p| !generated.iter().any(|g| &g.path == p))
        .collect();
    out.sort();
    out
}
