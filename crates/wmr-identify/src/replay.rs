//! The replay: a robot file run open loop on a log's commands, against the log's wheel
//! speeds and poses (how a user judges a fit: docs/identify.md).

use wmr_core::{Drive, Robot, State, wrap_angle};

use crate::error::IdentifyError;
use crate::filter::local_polynomial;
use crate::fit::{ANGLE_DEGREE, SPEED_DEGREE};
use crate::log::{Log, WheelSignal};
use crate::sim::simulate_from;

/// Half-width of the filter that reads the logged wheel speeds (as the fit's default), s.
pub const REPLAY_HALF_WINDOW_S: f64 = 0.15;

/// The errors of one run (or of all, pooled).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunErrors {
    /// The run's index (`run` column).
    pub index: usize,
    /// Samples compared.
    pub samples: usize,
    /// RMS over both wheels of the simulated minus the logged wheel speed, rad/s.
    pub speed_rms_rad_s: f64,
    /// `speed_rms_rad_s` over the RMS of the logged wheel speeds (a fraction).
    pub speed_rms_relative: f64,
    /// The larger of the two wheels' speed errors at the last sample compared, rad/s.
    pub speed_final_rad_s: f64,
    /// RMS distance between the simulated and the logged position of C, m (logs with a pose).
    pub position_rms_m: Option<f64>,
    /// That distance at the last sample compared, m.
    pub position_final_m: Option<f64>,
    /// The heading error at the last sample compared, rad, in (-pi, pi].
    pub heading_final_rad: Option<f64>,
}

/// One run's compared samples, logged and replayed (what a plot of the replay draws),
/// and its error per second of log.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunTrace {
    /// The run's index (`run` column).
    pub index: usize,
    /// Time of each compared sample, s (the log's).
    pub t_s: Vec<f64>,
    /// The logged wheel speeds (right, left), rad/s, filtered as the fit filters them.
    pub logged_speed: [Vec<f64>; 2],
    /// The replayed wheel speeds (right, left), rad/s.
    pub replayed_speed: [Vec<f64>; 2],
    /// The logged pose of C (x m, y m, theta rad), if the log has one.
    pub logged_pose: Option<[Vec<f64>; 3]>,
    /// The replayed pose of C (x m, y m, theta rad).
    pub replayed_pose: [Vec<f64>; 3],
    /// RMS over both wheels of the wheel-speed error in each second of the run, rad/s:
    /// element k covers the samples with `t - t_first` in [k, k + 1) s, `t_first` the
    /// run's first compared sample.
    pub speed_rms_per_second_rad_s: Vec<f64>,
}

/// Per run, and pooled over all runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReplayReport {
    /// Each run.
    pub runs: Vec<RunErrors>,
    /// All runs' samples together (the finals are not pooled: 0 / None).
    pub total: RunErrors,
    /// Each run's samples and its error per second, in the order of `runs`.
    pub traces: Vec<RunTrace>,
}

/// Replays every run of `log` on `robot` with `drive`: from the first sample with a
/// centred filter window (the logged speeds there, filtered as the fit filters them; the
/// logged pose if any, else the origin; the logged wheel angles), holding each logged
/// command to the next stamp, compared at every stamp where the filtered log has a speed.
///
/// With `horizon_s` > 0 the replay starts again from the log's state every `horizon_s`
/// seconds of each run: an open-loop replay cannot follow a motion that is unstable
/// (a robot whose centre of mass is ahead of the axle, d > 0, driving backward: the
/// yaw rate grows as e^(m d |v| t / M_r22), so the smallest error of the starting yaw
/// rate ends in a spin), and a short horizon measures the model rather than that growth.
pub fn replay(log: &Log, robot: Robot<f64>, drive: Drive<f64>, horizon_s: f64) -> Result<ReplayReport, IdentifyError> {
    if !(horizon_s >= 0.0) {
        return Err(IdentifyError::BadSetting {
            key: "horizon".to_owned(),
            detail: format!("must be >= 0 (0: the whole run), got {horizon_s}"),
        });
    }
    let p = *robot.params();
    let mut report = ReplayReport::default();
    let (mut sum_e2, mut sum_s2, mut sum_p2, mut n_all, mut n_pose) = (0.0, 0.0, 0.0, 0usize, 0usize);
    for run in &log.runs {
        let n = run.t_s.len();
        let mut dts: Vec<f64> = run.t_s.windows(2).map(|w| w[1] - w[0]).collect();
        dts.sort_by(f64::total_cmp);
        let median_dt = dts.get(dts.len() / 2).copied().unwrap_or(f64::NAN);
        let half = ((REPLAY_HALF_WINDOW_S / median_dt).round() as usize).max(3);
        if n < 2 * half + 2 {
            return Err(IdentifyError::TooShort { run: run.index, rows: n, needed: 2 * half + 2 });
        }
        let speed: [Vec<f64>; 2] = std::array::from_fn(|w| match log.wheel {
            WheelSignal::Angle => local_polynomial(&run.t_s, &run.wheel[w], half, ANGLE_DEGREE).d1,
            WheelSignal::Speed => local_polynomial(&run.t_s, &run.wheel[w], half, SPEED_DEGREE).value,
        });
        let (first, last) = (half, n - half);
        let mut e = RunErrors { index: run.index, ..Default::default() };
        let mut trace = RunTrace { index: run.index, ..Default::default() };
        if run.pose.is_some() {
            trace.logged_pose = Some(Default::default());
        }
        // Per second of log: the sum of squared errors and the samples in it.
        let mut per_second: Vec<(f64, usize)> = Vec::new();
        let (mut e2, mut s2, mut p2, mut np) = (0.0, 0.0, 0.0, 0usize);
        let mut i0 = first;
        while i0 < last {
            // The segment [i0, i1): to the end of the run, or `horizon_s` long.
            let mut i1 = last;
            if horizon_s > 0.0 {
                i1 = (i0 + 1..last).find(|&i| run.t_s[i] - run.t_s[i0] >= horizon_s).unwrap_or(last);
            }
            let (wr, wl) = (speed[0][i0], speed[1][i0]);
            let (x, y, theta) = run.pose.as_ref().map_or((0.0, 0.0, 0.0), |q| (q[0][i0], q[1][i0], q[2][i0]));
            let (phi_r, phi_l) = match log.wheel {
                WheelSignal::Angle => (run.wheel[0][i0], run.wheel[1][i0]),
                WheelSignal::Speed => (0.0, 0.0),
            };
            let start = State {
                x,
                y,
                theta,
                v: p.wheel_radius * (wr + wl) / 2.0,
                omega: p.wheel_radius * (wr - wl) / (2.0 * p.half_track),
                phi_r,
                phi_l,
            };
            let sim = simulate_from(
                robot,
                drive,
                start,
                &run.t_s[i0..i1],
                [&run.command[0][i0..i1], &run.command[1][i0..i1]],
            )?;
            for k in 0..i1 - i0 {
                let i = i0 + k;
                let err = [sim.omega[0][k] - speed[0][i], sim.omega[1][k] - speed[1][i]];
                e2 += err[0] * err[0] + err[1] * err[1];
                let second = (run.t_s[i] - run.t_s[first]).floor().max(0.0) as usize;
                if per_second.len() <= second {
                    per_second.resize(second + 1, (0.0, 0));
                }
                per_second[second].0 += err[0] * err[0] + err[1] * err[1];
                per_second[second].1 += 1;
                trace.t_s.push(run.t_s[i]);
                for w in 0..2 {
                    trace.logged_speed[w].push(speed[w][i]);
                    trace.replayed_speed[w].push(sim.omega[w][k]);
                }
                for j in 0..3 {
                    trace.replayed_pose[j].push(sim.pose[j][k]);
                }
                if let (Some(q), Some(lp)) = (&run.pose, trace.logged_pose.as_mut()) {
                    for j in 0..3 {
                        lp[j].push(q[j][i]);
                    }
                }
                s2 += speed[0][i] * speed[0][i] + speed[1][i] * speed[1][i];
                e.speed_final_rad_s = err[0].abs().max(err[1].abs());
                if let Some(q) = &run.pose {
                    let d = (sim.pose[0][k] - q[0][i]).hypot(sim.pose[1][k] - q[1][i]);
                    p2 += d * d;
                    np += 1;
                    e.position_final_m = Some(d);
                    e.heading_final_rad = Some(wrap_angle(sim.pose[2][k] - q[2][i]));
                }
                e.samples += 1;
            }
            i0 = i1;
        }
        e.speed_rms_rad_s = (e2 / (2 * e.samples) as f64).sqrt();
        e.speed_rms_relative = (e2 / s2).sqrt();
        if np > 0 {
            e.position_rms_m = Some((p2 / np as f64).sqrt());
        }
        trace.speed_rms_per_second_rad_s =
            per_second.iter().map(|&(e2, n)| if n == 0 { f64::NAN } else { (e2 / (2 * n) as f64).sqrt() }).collect();
        report.traces.push(trace);
        sum_e2 += e2;
        sum_s2 += s2;
        sum_p2 += p2;
        n_all += e.samples;
        n_pose += np;
        report.runs.push(e);
    }
    report.total = RunErrors {
        index: 0,
        samples: n_all,
        speed_rms_rad_s: (sum_e2 / (2 * n_all).max(1) as f64).sqrt(),
        speed_rms_relative: (sum_e2 / sum_s2).sqrt(),
        speed_final_rad_s: 0.0,
        position_rms_m: (n_pose > 0).then(|| (sum_p2 / n_pose as f64).sqrt()),
        position_final_m: None,
        heading_final_rad: None,
    };
    Ok(report)
}
