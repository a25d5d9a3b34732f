//! Early arrival (`[sim] early_arrival`, `wmr_core::arrival`) against full-length runs
//! and against the 1 s settle rule, on a reduced copy of the million-start map
//! `examples/paper/map-paper_bidirectional.toml` (the same square, the same law, a 20 x 20
//! grid: 400 starts; the full 1,000 x 1,000 with `WMR_LONG_TESTS=1` would take hours at
//! full length, so it is not offered here).
//!
//! Each early-stopped run must have the status and the time to 1 cm of the same run at
//! full length (100 s, no stop) and a final position within 1 cm of it; the test counts
//! how many final positions moved and by how much, and checks that the early test does
//! stop runs sooner than the settle rule (the point of it). The fast path and, on a few
//! starts, the exact path.

use wmr_core::{Status, Termination};
use wmr_scenario::{Scenario, SweepOutcome};

const MAP: &str = include_str!("../../../examples/paper/map-paper_bidirectional.toml");

/// The map with a `n` x `n` grid and `[sim]` as `sim` says.
fn map(n: usize, sim: &str) -> Scenario {
    let text = MAP
        .replace("nx = 1000", &format!("nx = {n}"))
        .replace("ny = 1000", &format!("ny = {n}"))
        .replace(
            "stop_when_settled = true   # end a run once it has settled (docs/scenario.md)\n\
             early_arrival = true       # as soon as the motion has died out for 0.1 s, not after 1 s (docs/scenario.md)\n",
            sim,
        );
    assert!(text.contains(sim), "the map's [sim] lines changed: update this test");
    Scenario::from_toml_str(&text, "map").unwrap()
}

const EARLY: &str = "stop_when_settled = true\nearly_arrival = true\n";
const SETTLE: &str = "stop_when_settled = true\n";
const FULL: &str = "stop_when_settled = false\n";

fn distance(a: &SweepOutcome, b: &SweepOutcome) -> f64 {
    let (p, q) = (a.outcome.final_pose, b.outcome.final_pose);
    (p.x - q.x).hypot(p.y - q.y)
}

/// Compares early-stopped runs with full-length ones; returns (runs stopped early,
/// final positions that moved, the largest move in m).
fn compare(early: &[SweepOutcome], full: &[SweepOutcome]) -> (usize, usize, f64) {
    assert_eq!(early.len(), full.len());
    let (mut stopped, mut moved, mut most) = (0, 0, 0.0_f64);
    for (e, f) in early.iter().zip(full) {
        assert_eq!(e.start, f.start);
        assert_eq!(e.status(), f.status(), "start {:?}: {e:?} against full length {f:?}", e.start);
        assert_eq!(e.outcome.time_to_arrival, f.outcome.time_to_arrival, "start {:?}", e.start);
        let d = distance(e, f);
        assert!(d < 0.01, "start {:?}: final positions {d} m apart", e.start);
        if e.outcome.termination == Termination::Settled {
            stopped += 1;
        }
        if d > 0.0 {
            moved += 1;
        }
        most = most.max(d);
    }
    (stopped, moved, most)
}

#[test]
fn early_arrival_keeps_every_status_of_full_length_runs_on_the_fast_path() {
    let (early, settle, full) = (map(20, EARLY), map(20, SETTLE), map(20, FULL));
    let run = |s: &Scenario| s.sweep().unwrap().run_fast(s.sim(), &|| {}).unwrap();
    let (e, st, f) = (run(&early), run(&settle), run(&full));
    let (stopped, moved, most) = compare(&e, &f);
    let converged = f.iter().filter(|o| o.status() == Status::Converged).count();
    eprintln!(
        "early arrival, fast path: {stopped} of {} runs stopped early ({converged} converged at full length); \
         {moved} final positions moved, by at most {most:.3e} m",
        e.len()
    );
    assert!(stopped > e.len() / 2, "the early test must stop most runs of this map: {stopped}");
    // Against the 1 s settle rule: the same statuses, and every stop sooner or as soon.
    let mut sooner = 0;
    for (a, b) in e.iter().zip(&st) {
        assert_eq!(a.status(), b.status());
        assert!(a.outcome.t_final <= b.outcome.t_final, "{a:?} {b:?}");
        if a.outcome.t_final < b.outcome.t_final {
            sooner += 1;
        }
    }
    let steps = |o: &[SweepOutcome]| o.iter().map(|o| o.outcome.t_final).sum::<f64>();
    eprintln!(
        "simulated time: early {:.0} s, settle rule {:.0} s, full length {:.0} s; {sooner} runs stopped sooner",
        steps(&e),
        steps(&st),
        steps(&f)
    );
    assert!(sooner > stopped / 2, "{sooner} of {stopped}");
}

#[test]
fn early_arrival_keeps_every_status_of_full_length_runs_on_the_exact_path() {
    let (early, full) = (map(4, EARLY), map(4, FULL));
    let run = |s: &Scenario| s.sweep().unwrap().run(s.sim(), &|| {}).unwrap();
    let (e, f) = (run(&early), run(&full));
    let (stopped, moved, most) = compare(&e, &f);
    eprintln!(
        "early arrival, exact path: {stopped} of {} stopped early; {moved} moved, by at most {most:.3e} m",
        e.len()
    );
    assert!(stopped > 0);
}

#[test]
fn early_arrival_needs_stop_when_settled() {
    let text = MAP.replace("stop_when_settled = true ", "stop_when_settled = false");
    let e = Scenario::from_toml_str(&text, "map").unwrap_err();
    assert_eq!(e.key, "sim.early_arrival", "{e:?}");
    assert!(e.message.contains("stop_when_settled"), "{e:?}");
}
