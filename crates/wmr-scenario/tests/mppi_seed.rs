//! MPPI's sampling noise is seeded per run, like the sensor's (issue 41, "Seeded per run
//! like the sensor noise"): run k of a scenario or a sweep draws under its own seed, run 0
//! under the `seed` key, and the same run draws the same bits every time.

use wmr_scenario::Scenario;

/// Two runs from the same start to the same goal: only their index differs.
fn twin_runs(seed: u32) -> String {
    format!(
        r#"
[controller]
kind = "mppi"
motion_model = "kinematic"
batch_size = 24
time_steps = 12
seed = {seed}
[sim]
t_end = 1.5
log_dt = 0.05
[[run]]
start = {{ x = 0.0, y = 0.0, theta_deg = 0.0 }}
goal = {{ x = 0.8, y = 0.1, theta_deg = 0.0 }}
[[run]]
start = {{ x = 0.0, y = 0.0, theta_deg = 0.0 }}
goal = {{ x = 0.8, y = 0.1, theta_deg = 0.0 }}
"#
    )
}

fn samples(sc: &Scenario, run: usize) -> Vec<[f64; 5]> {
    let mut out = Vec::new();
    sc.run(run, |s| out.push([s.t, s.state.x, s.state.y, s.state.theta, s.torque.right])).expect("runs");
    out
}

/// SplitMix64's output function (Steele, Lea, Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014), written here from the paper's constants.
fn splitmix64_mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of run `k` as `MppiParams::build_in` documents it.
fn run_seed(seed: u32, k: u64) -> u32 {
    if k == 0 {
        return seed;
    }
    (splitmix64_mix(splitmix64_mix(u64::from(seed) ^ (0x52_554E << 40)) ^ k) >> 32) as u32
}

#[test]
fn each_run_draws_its_own_mppi_noise_and_a_rerun_the_same() {
    let sc = Scenario::from_toml_str(&twin_runs(3), "twins").expect("valid");
    let (run0, run1) = (samples(&sc, 0), samples(&sc, 1));
    assert_eq!(run0.len(), run1.len());
    assert_ne!(run0, run1, "the second run drew the first run's samples");
    // The same run again: the same bits.
    assert_eq!(samples(&sc, 1), run1);
    let again = Scenario::from_toml_str(&twin_runs(3), "twins").expect("valid");
    assert_eq!(samples(&again, 0), run0);
    assert_eq!(samples(&again, 1), run1);
}

#[test]
fn run_k_draws_under_the_documented_seed_and_run_0_under_the_key() {
    let sc = Scenario::from_toml_str(&twin_runs(3), "twins").expect("valid");
    // Run 1 is the first run of a scenario whose key is run 1's seed.
    let seed1 = run_seed(3, 1);
    assert_ne!(seed1, 3);
    let moved = Scenario::from_toml_str(&twin_runs(seed1), "moved").expect("valid");
    assert_eq!(samples(&sc, 1), samples(&moved, 0));
    // Run 0 keeps the key: a scenario of one run, as `wmr-cli run` of a single run gives.
    let one = twin_runs(3);
    let one = &one[..one.rfind("[[run]]").expect("two runs")];
    let single = Scenario::from_toml_str(one, "single").expect("valid");
    assert_eq!(single.runs().len(), 1);
    assert_eq!(samples(&sc, 0), samples(&single, 0));
}

const TRIALS: &str = r#"
[sim]
t_end = 1.5
[sweep]
goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
controllers = [{ kind = "mppi", motion_model = "kinematic", batch_size = 24, time_steps = 12 }]
random = { n = 2, seed = 9, radius = 0.8, min_radius = 0.5 }
trials = 2
"#;

#[test]
fn a_sweeps_trials_differ_in_noise_and_a_rerun_and_fast_are_the_same() {
    let sc = Scenario::from_toml_str(TRIALS, "trials").expect("valid");
    let spec = sc.sweep().expect("a sweep");
    let whole = spec.run(sc.sim(), &|| {}).expect("runs");
    assert_eq!(whole.len(), 4);
    // Trials 0 and 1 of each start: same start, other runs, other noise.
    for start in 0..2 {
        let of =
            |trial: u32| whole.iter().find(|o| o.start_index == start && o.trial == trial).expect("the run").outcome;
        assert_ne!(of(0), of(1), "start {start}: both trials drew the same noise");
    }
    assert_eq!(spec.run(sc.sim(), &|| {}).expect("runs"), whole);
    // The lanes share one controller: an MPPI sweep takes the exact path under --fast.
    assert_eq!(spec.run_fast(sc.sim(), &|| {}).expect("runs"), whole);
}
