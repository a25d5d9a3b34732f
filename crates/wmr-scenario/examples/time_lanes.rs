//! CPU time per run-step of a sweep, exact path against lanes (benches/compare runs it):
//! `time_lanes [LAW] [N_STARTS] [T_END_S] [both|exact|fast]` prints `key=value` lines.
//! One thread; no settling, so every run is t_end / dt steps. `exact` or `fast` alone
//! (under `valgrind --tool=callgrind`: instructions per run-step, whatever the load).
//! Every mode prints `kernel=` (the vector unit the lanes run on, `WMR_FAST_KERNEL`
//! picks a narrower one); `time_lanes laws` prints the names of the laws the lanes run
//! (point stabilization: tracking laws follow a reference and take the exact path), one
//! a line.

use std::time::Instant;

use wmr_scenario::Scenario;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let law = args.get(1).map_or("paper", String::as_str);
    let n: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(64);
    let t_end: f64 = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(60.0);
    let which = args.get(4).map_or("both", String::as_str);
    if law == "laws" {
        for kind in wmr_scenario::stabilization_law_kinds() {
            println!("{kind}");
        }
        return;
    }
    println!("kernel={}", wmr_scenario::fast::Kernel::detect().expect("WMR_FAST_KERNEL").name());
    let text = format!(
        "[sim]\nt_end = {t_end}\n[sweep]\ngoal = {{ x = 0.0, y = 0.0 }}\ncontrollers = [{{ kind = \"{law}\" }}]\n\
         random = {{ n = {n}, seed = 2026, radius = 2.0 }}\n"
    );
    let s = Scenario::from_toml_str(&text, "time_lanes").expect("scenario");
    let spec = s.sweep().expect("sweep");
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool");
    let run_steps = (spec.len() as u64 * s.sim().n_steps()) as f64;
    if which != "both" {
        let t0 = Instant::now();
        let o =
            pool.install(|| if which == "fast" { spec.run_fast(s.sim(), &|| {}) } else { spec.run(s.sim(), &|| {}) });
        let secs = t0.elapsed().as_secs_f64();
        println!("{which}: runs={} ns_per_run_step={:.1}", o.expect("runs").len(), secs * 1e9 / run_steps);
        return;
    }
    let (exact, exact_s) = pool.install(|| {
        let t0 = Instant::now();
        let o = spec.run(s.sim(), &|| {}).expect("exact");
        (o, t0.elapsed().as_secs_f64())
    });
    let (fast, fast_s) = pool.install(|| {
        let t0 = Instant::now();
        let o = spec.run_fast(s.sim(), &|| {}).expect("fast");
        (o, t0.elapsed().as_secs_f64())
    });
    let mut worst = 0.0_f64;
    let mut same_status = 0;
    for (a, b) in exact.iter().zip(&fast) {
        let (p, q) = (a.outcome.final_pose, b.outcome.final_pose);
        for (u, v) in [(p.x, q.x), (p.y, q.y), (p.theta, q.theta)] {
            worst = worst.max((u - v).abs() / u.abs().max(1.0));
        }
        same_status += usize::from(a.status() == b.status());
    }
    println!("law={law} runs={} steps_per_run={}", spec.len(), s.sim().n_steps());
    println!("ns_per_run_step_exact={:.1}", exact_s * 1e9 / run_steps);
    println!("ns_per_run_step_fast={:.1}", fast_s * 1e9 / run_steps);
    println!("speedup={:.2}", exact_s / fast_s);
    println!("max_rel_diff_final_pose={worst:.1e} same_status={same_status}/{}", spec.len());
}
