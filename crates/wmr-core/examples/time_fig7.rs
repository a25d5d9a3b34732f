//! Timing binary for `benches/compare` (issue 6): the Fig. 7 run against the C baseline,
//! and a batch of runs on several threads for the parallel efficiency.
//!
//! ```text
//! time_fig7 fig7 [REPS] [f64|f32]   # final pose + median time of REPS whole 60 s runs
//! time_fig7 batch [RUNS] [THREADS]  # wall time of RUNS 60 s runs spread over THREADS
//! ```
//!
//! Output is one `key=value` line, the same keys as `benches/baseline.c`:
//! `impl=rust x=.. y=.. theta=.. steps=.. median_run_s=.. median_step_ns=.. reps=..`,
//! plus `median_run_api_s` (the same run through `ClosedLoop::run`, which also feeds
//! the per-step metrics). Build with `cargo build --release -p wmr-core --example time_fig7`.

use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use wmr_core::{
    ClosedLoop, Controller, DriveParams, FixedGoal, PaperLaw, PaperParams, Plant, Pose2, Real, Robot, WheelStage,
    WheelStageParams,
};

/// Fig. 7: (0, 0, 0) -> (1, 1, 120 deg), every default, 60 s at dt = control_dt = 1 ms.
const FIG7_STEPS: u64 = 60_000;

/// The paper's law and the default wheel stage, composed directly (no `AnyLaw` dispatch).
fn fig7_loop<T: Real>(goal_theta_deg: f64) -> ClosedLoop<T, PaperLaw<T>> {
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).expect("default drive is valid");
    let goal = Pose2::new(T::lit(1.0), T::lit(1.0), T::lit(goal_theta_deg.to_radians()));
    let dt = T::lit(1e-3);
    let law = PaperLaw::new(PaperParams::paper(), robot.params(), dt).expect("paper gains are valid");
    let wheels = WheelStage::new(&WheelStageParams::default(), robot.params(), &drive, dt).expect("valid servos");
    let ctrl = Controller::new(law, wheels);
    let plant = Plant::new(robot, drive, Pose2::default()).expect("finite start");
    ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).expect("finite goal"), dt).expect("dt divides control_dt")
}

/// The closed-loop step alone, `FIG7_STEPS` times; returns the final pose and steps taken.
fn run_steps<T: Real>(goal_theta_deg: f64) -> (Pose2<T>, u64) {
    let mut sim = fig7_loop::<T>(goal_theta_deg);
    for _ in 0..FIG7_STEPS {
        if sim.step().is_err() {
            break;
        }
    }
    (sim.state().pose(), sim.steps())
}

/// The same run through the public `run` API (samples + metrics every step, no logging).
fn run_api<T: Real>(goal_theta_deg: f64) -> Pose2<T> {
    let mut sim = fig7_loop::<T>(goal_theta_deg);
    sim.run(FIG7_STEPS, u32::MAX, |s| {
        black_box(s);
    })
    .final_pose
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

fn time_reps(reps: usize, mut f: impl FnMut()) -> f64 {
    f(); // warm-up
    median(
        (0..reps)
            .map(|_| {
                let t0 = Instant::now();
                f();
                t0.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

fn fig7<T: Real>(reps: usize) {
    let mut out = (Pose2::<T>::default(), 0);
    let step_s = time_reps(reps, || out = run_steps::<T>(black_box(120.0)));
    let api_s = time_reps(reps, || {
        black_box(run_api::<T>(black_box(120.0)));
    });
    let (pose, steps) = out;
    println!(
        "impl=rust x={:?} y={:?} theta={:?} steps={steps} median_run_s={step_s:.6e} median_step_ns={:.3} reps={reps} median_run_api_s={api_s:.6e}",
        pose.x.to_f64_lossless(),
        pose.y.to_f64_lossless(),
        pose.theta.to_f64_lossless(),
        step_s / steps as f64 * 1e9,
    );
}

/// `runs` Fig. 4-style runs (goal heading spread over a turn) on `threads` threads,
/// handed out one at a time so a short (diverged) run does not unbalance the threads.
fn batch(runs: usize, threads: usize) {
    let next = AtomicUsize::new(0);
    let t0 = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= runs {
                        break;
                    }
                    let theta_deg = -180.0 + 360.0 * i as f64 / runs as f64;
                    black_box(run_steps::<f64>(theta_deg));
                }
            });
        }
    });
    let wall = t0.elapsed().as_secs_f64();
    println!("impl=rust batch_runs={runs} threads={threads} wall_s={wall:.6e}");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    match args.first().map(String::as_str) {
        Some("batch") => batch(arg(1, 200), arg(2, 2)),
        Some("fig7") | None => match args.get(2).map(String::as_str) {
            Some("f32") => fig7::<f32>(arg(1, 5)),
            _ => fig7::<f64>(arg(1, 5)),
        },
        Some(other) => {
            eprintln!("unknown mode {other:?}: use `fig7 [REPS] [f64|f32]` or `batch [RUNS] [THREADS]`");
            std::process::exit(2);
        }
    }
}
