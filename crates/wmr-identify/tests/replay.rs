//! Issue 44, "Replay": the error per second of log, and the samples a plot draws.

use wmr_core::{DriveParams, TorqueDriveParams};
use wmr_identify::excite::Test;
use wmr_identify::replay::replay;

use crate::common::{NOISE, robot, torque_log_of};

/// Each run's per-second RMS pools back to its RMS (the mean square over the run is the
/// sample-weighted mean of the seconds' mean squares), every second of the run has one,
/// and the traces are the samples compared.
#[test]
fn issue_44_replay_error_per_second_pools_to_the_run_rms() {
    let tests: Vec<Test> = Test::all().into_iter().take(4).collect();
    let log = torque_log_of(robot(), &tests, NOISE);
    // A wrong robot (10 % heavier), so that the errors are not noise only.
    let mut wrong = robot();
    wrong.mass *= 1.1;
    let r = wrong.validate().unwrap();
    let drive =
        DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY, deadband: 0.0 }).validate(&r).unwrap();
    let report = replay(&log, r, drive, 0.0).unwrap();
    assert_eq!(report.traces.len(), report.runs.len());
    for (run, tr) in report.runs.iter().zip(&report.traces) {
        assert_eq!(tr.t_s.len(), run.samples);
        assert!(tr.logged_pose.is_some());
        let t0 = tr.t_s[0];
        let seconds = (tr.t_s.last().unwrap() - t0).floor() as usize + 1;
        assert_eq!(tr.speed_rms_per_second_rad_s.len(), seconds);
        let mut counts = vec![0usize; seconds];
        for t in &tr.t_s {
            counts[(t - t0).floor() as usize] += 1;
        }
        let pooled: f64 =
            tr.speed_rms_per_second_rad_s.iter().zip(&counts).map(|(r, &n)| r * r * n as f64).sum::<f64>()
                / run.samples as f64;
        assert!(
            (pooled.sqrt() - run.speed_rms_rad_s).abs() <= 1e-12 * run.speed_rms_rad_s,
            "run {}: {} against {}",
            run.index,
            pooled.sqrt(),
            run.speed_rms_rad_s
        );
        // The traces give the same error.
        let e2: f64 = (0..tr.t_s.len())
            .map(|i| (0..2).map(|w| (tr.replayed_speed[w][i] - tr.logged_speed[w][i]).powi(2)).sum::<f64>())
            .sum();
        assert!(((e2 / (2 * run.samples) as f64).sqrt() - run.speed_rms_rad_s).abs() <= 1e-12 * run.speed_rms_rad_s);
        assert!(run.speed_rms_relative > 0.01, "the wrong robot shows: {}", run.speed_rms_relative);
    }
}
