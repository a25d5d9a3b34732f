//! Odometry as the controller's pose (wmr issue 24): the dead reckoning against the true
//! pose and against replays by hand (Euler, midpoint), a wrong wheel radius against the
//! geometry of the error, and the EKF's fused pose against the truth with 1 Hz fixes.
//! Issue: "Wheels that slip, motors from a datasheet, a robot that knows where it is
//! only from odometry" (issue 24, `issues show 24`).

use crate::common::{fig7, paper_controller};
use wmr_core::reference::Circle;
use wmr_core::sensor::ekf::is_symmetric_positive_definite;
use wmr_core::{
    AnyReference, ClosedLoop, ControllerParams, DriveParams, FixedGoal, KanayamaParams, LawParams, OdometryParams,
    OdometrySensor, PaperParams, Plant, Pose2, PoseSource, Real, Robot, RobotParams, SensorParams, State,
};

const DT: f64 = 1e-3;

fn odometry(fix_rate_hz: f64) -> OdometryParams<f64> {
    OdometryParams { pose: PoseSource::Odometry, fix_rate_hz, ..OdometryParams::default() }
}

/// Fig. 7 (60 s) with the controller on odometry from ideal encoders, every tick logged:
/// the true states and the dead-reckoned poses.
fn fig7_on_odometry<T: Real>(model: RobotParams<T>) -> Vec<(State<T>, Pose2<T>)> {
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let (start, goal) = fig7::<T>();
    let dt = T::lit(DT);
    let sensor =
        OdometrySensor::<T>::new(SensorParams::default(), odometry(0.0).cast(), &model, dt, 0).expect("valid sensor");
    let ctrl = paper_controller(PaperParams::paper(), &model, &drive, dt);
    let plant = Plant::new(robot, drive, start).unwrap();
    let mut lp = ClosedLoop::with_sensor(plant, sensor, ctrl, FixedGoal::new(goal).unwrap(), dt).unwrap();
    let mut out = Vec::new();
    lp.run(60_000, 1, |s| {
        // Without fixes the controller's pose is the dead reckoning itself.
        assert_eq!(s.odometry, Some(s.measured));
        out.push((s.state, s.odometry.unwrap()));
    });
    out
}

/// Largest position error (m) of `poses` against the true states.
fn max_error<T: Real>(run: &[(State<T>, Pose2<T>)], poses: impl Iterator<Item = Pose2<f64>>) -> f64 {
    run.iter()
        .zip(poses)
        .map(|((s, _), p)| (s.x.to_f64_lossless() - p.x).hypot(s.y.to_f64_lossless() - p.y))
        .fold(0.0, f64::max)
}

/// Replays the wheel angles of `run` by hand with one step rule (r, R of the paper's robot).
fn replay(run: &[(State<f64>, Pose2<f64>)], step: impl Fn(Pose2<f64>, f64, f64) -> Pose2<f64>) -> Vec<Pose2<f64>> {
    let p = RobotParams::<f64>::paper();
    let mut pose = run[0].0.pose();
    let mut out = vec![pose];
    for w in run.windows(2) {
        let (a, b) = (w[0].0, w[1].0);
        let (dr, dl) = (p.wheel_radius * (b.phi_r - a.phi_r), p.wheel_radius * (b.phi_l - a.phi_l));
        pose = step(pose, (dr + dl) / 2.0, (dr - dl) / (2.0 * p.half_track));
        out.push(pose);
    }
    out
}

/// Ideal encoders, no slip: the odometry equals the true pose over Fig. 7 within 1e-5 m.
/// An independent midpoint replay (x += ds cos(theta + dth/2)) agrees as closely; an
/// Euler replay (x += ds cos theta) of the same wheel angles is off by about 0.8 mm.
#[test]
fn ideal_odometry_equals_the_true_pose_over_fig7() {
    let run = fig7_on_odometry::<f64>(RobotParams::paper());
    let ours = max_error(&run, run.iter().map(|(_, p)| *p));
    let midpoint = replay(&run, |q, ds, dth| {
        let m = q.theta + dth / 2.0;
        Pose2::new(q.x + ds * m.cos(), q.y + ds * m.sin(), q.theta + dth)
    });
    let euler =
        replay(&run, |q, ds, dth| Pose2::new(q.x + ds * q.theta.cos(), q.y + ds * q.theta.sin(), q.theta + dth));
    let (midpoint, euler) = (max_error(&run, midpoint.into_iter()), max_error(&run, euler.into_iter()));
    let numbers = format!("arc {ours:.3e} m, midpoint by hand {midpoint:.3e} m, Euler by hand {euler:.3e} m");
    eprintln!("Fig. 7 dead reckoning, largest position error over 60 s at 1 ms: {numbers}");
    assert!(ours < 1e-5, "{numbers}");
    assert!(midpoint < 1e-5, "{numbers}");
    // The first-order rule is two orders of magnitude worse: the test can tell them apart.
    assert!(euler > 5e-4 && euler < 2e-3, "{numbers}");
    // The heading is exact up to rounding: dth is linear in the wheel angles.
    let heading = run.iter().map(|(s, p)| (s.theta - p.theta).abs()).fold(0.0, f64::max);
    assert!(heading < 1e-9, "heading error {heading:e}");
}

/// The same in f32: rounding over 60 000 ticks, not the rule, bounds the error.
#[test]
fn ideal_odometry_in_f32_stays_within_rounding() {
    let run = fig7_on_odometry::<f32>(RobotParams::paper());
    let err = max_error(&run, run.iter().map(|(_, p)| Pose2::new(f64::from(p.x), f64::from(p.y), 0.0)));
    eprintln!("f32: largest position error {err:.3e} m");
    assert!(err < 1e-3, "{err:e}");
}

/// r and R both 1 % too large in the model: every wheel travel and the track scale alike,
/// so the turns are right and the odometry is the true path scaled by 1.01 about the start
/// (the start is the origin): odo = 1.01 true, heading equal.
#[test]
fn model_scaled_by_one_percent_sees_the_path_scaled_by_one_percent() {
    let p = RobotParams::<f64>::paper();
    let model = RobotParams { wheel_radius: 1.01 * p.wheel_radius, half_track: 1.01 * p.half_track, ..p };
    let run = fig7_on_odometry::<f64>(model);
    let scaled = run.iter().map(|(_, o)| Pose2::new(o.x / 1.01, o.y / 1.01, o.theta));
    let err = max_error(&run, scaled);
    assert!(err < 1e-5, "odometry / 1.01 vs truth: {err:e} m");
    let (s, o) = run.last().unwrap();
    assert!((s.theta - o.theta).abs() < 1e-9);
    // And the controller, believing the odometry, stopped its own pose at the goal:
    // the true robot stopped short, at (1, 1) / 1.01.
    assert!((s.x - 1.0 / 1.01).abs() < 0.02 && (s.y - 1.0 / 1.01).abs() < 0.02, "{s:?}");
}

/// Drift (m) at the end and path length (m) of a straight 5 m run, the controller on
/// odometry with model wheel radius `scale` times the true one (R exact).
fn straight_drift(scale: f64) -> (f64, f64) {
    let robot = Robot::<f64>::paper();
    let p = *robot.params();
    let model = RobotParams { wheel_radius: scale * p.wheel_radius, ..p };
    let drive = DriveParams::default().validate(&robot).unwrap();
    let sensor = OdometrySensor::<f64>::new(SensorParams::default(), odometry(0.0), &model, DT, 0).unwrap();
    let ctrl = ControllerParams::with_law(LawParams::Polar(Default::default())).build(&model, &drive).unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    let goal = FixedGoal::new(Pose2::new(5.0, 0.0, 0.0)).unwrap();
    let mut lp = ClosedLoop::with_sensor(plant, sensor, ctrl, goal, DT).unwrap();
    let mut last = None;
    let out = lp.run(60_000, 100, |s| last = Some(*s));
    let s = last.unwrap();
    let o = s.odometry.unwrap();
    ((s.state.x - o.x).hypot(s.state.y - o.y), out.path_length)
}

/// A 1 % wheel-radius error in the controller's model: the odometry drifts about 1 % of
/// the distance travelled (every metre it counts is 0.99 m of ground).
#[test]
fn one_percent_wheel_radius_error_drifts_one_percent_of_the_distance() {
    let (drift, length) = straight_drift(1.01);
    let share = drift / length;
    eprintln!("1 % radius error: drift {drift:.4} m over {length:.3} m = {:.3} %", 100.0 * share);
    assert!((0.008..0.012).contains(&share), "drift {drift} m over {length} m");
    // The exact model does not drift (the independent baseline of the same run).
    let (drift0, _) = straight_drift(1.0);
    assert!(drift0 < 1e-5, "{drift0}");
}

/// Circles at 0.3 m/s for 120 s (36 m) on odometry with the model's wheel radius 1 % off
/// and noisy, late fixes (1 cm, 0.5 deg, 100 ms) at `fix_rate_hz`: the largest fused
/// position error after the first 5 s, the final odometry drift (m), and whether the
/// covariance was symmetric positive definite at every tick.
fn circles_with_fixes<T: Real>(fix_rate_hz: f64) -> (f64, f64, bool) {
    let robot = Robot::<T>::paper();
    let p = *robot.params();
    let model = RobotParams { wheel_radius: T::lit(1.01) * p.wheel_radius, ..p };
    let drive = DriveParams::default().validate(&robot).unwrap();
    let sensor_params = SensorParams {
        position_noise: T::lit(0.01),
        heading_noise_deg: T::lit(0.5),
        latency: T::lit(0.1),
        encoder_counts: 2048,
        seed: 7,
        ..SensorParams::default()
    };
    let dt = T::lit(DT);
    let sensor = OdometrySensor::<T>::new(sensor_params, odometry(fix_rate_hz).cast(), &model, dt, 0).unwrap();
    let law = LawParams::Kanayama(KanayamaParams::default());
    let ctrl = ControllerParams::with_law(law).build(&model, &drive).unwrap();
    let reference = AnyReference::<T>::Circle(
        Circle::new(T::zero(), T::zero(), T::one(), T::lit(0.3), T::lit(-0.5 * T::PI().to_f64_lossless())).unwrap(),
    );
    let plant = Plant::new(robot, drive, Pose2::new(T::one(), T::zero(), T::FRAC_PI_2())).unwrap();
    let mut lp = ClosedLoop::with_sensor(plant, sensor, ctrl, reference, dt).unwrap();
    let (mut worst, mut spd) = (0.0f64, true);
    for k in 0..120_000u32 {
        lp.step().unwrap();
        spd &= is_symmetric_positive_definite(&lp.sensor().covariance().unwrap());
        if k >= 5_000 {
            let (s, m) = (lp.state(), lp.last_tick().measurement.pose);
            worst = worst.max((s.x - m.x).to_f64_lossless().hypot((s.y - m.y).to_f64_lossless()));
        }
    }
    let (s, o) = (lp.state(), lp.sensor().dead_reckoning().unwrap());
    let drift = (s.x - o.x).to_f64_lossless().hypot((s.y - o.y).to_f64_lossless());
    (worst, drift, spd)
}

/// With 1 Hz absolute fixes the fused pose's error stays bounded (a few fix sigmas) while
/// the odometry alone drifts by about 1 % of the 36 m; the covariance stays symmetric
/// positive definite throughout, in f64 and f32.
#[test]
fn one_hertz_fixes_bound_the_fused_error_and_keep_the_covariance_positive_definite() {
    let (alone, drift_alone, _) = circles_with_fixes::<f64>(0.0);
    let (fused, drift, spd) = circles_with_fixes::<f64>(1.0);
    eprintln!(
        "f64: odometry alone: worst {alone:.3} m, drift {drift_alone:.3} m; with 1 Hz fixes: worst fused {fused:.4} m (odometry drift {drift:.3} m)"
    );
    assert!(spd, "covariance lost symmetry or definiteness");
    assert!(drift_alone > 0.2, "odometry alone should drift: {drift_alone}");
    assert!(drift > 0.2, "the dead reckoning is not reset by fixes: {drift}");
    assert!(fused < 0.05, "fused error {fused} m");
    assert!(fused < alone / 5.0);
    let (fused32, _, spd32) = circles_with_fixes::<f32>(1.0);
    eprintln!("f32: worst fused {fused32:.4} m");
    assert!(spd32 && fused32 < 0.05, "f32: {fused32} {spd32}");
}

/// Bad keys are refused by name.
#[test]
fn odometry_keys_are_checked() {
    let model = RobotParams::<f64>::paper();
    let bad = |s: SensorParams<f64>, o: OdometryParams<f64>| {
        OdometrySensor::<f64>::new(s, o, &model, DT, 0).unwrap_err().field
    };
    let ok = SensorParams::default();
    assert_eq!(bad(SensorParams { rate_hz: 10.0, ..ok }, odometry(0.0)), "rate_hz");
    assert_eq!(bad(ok, odometry(-1.0)), "fix_rate_hz");
    assert_eq!(bad(ok, odometry(f64::NAN)), "fix_rate_hz");
    assert_eq!(bad(ok, odometry(3.0)), "fix_rate_hz", "1/3 s is not a whole number of ms");
    assert_eq!(bad(ok, OdometryParams { odometry_noise: 2.0, ..odometry(0.0) }), "odometry_noise");
    assert_eq!(bad(ok, OdometryParams::default()), "pose");
    let any = |o: OdometryParams<f64>| wmr_core::AnySensor::new(ok, o, &model, DT, 0).map(|_| ()).map_err(|e| e.field);
    assert_eq!(any(OdometryParams { fix_rate_hz: 1.0, ..OdometryParams::default() }), Err("fix_rate_hz"));
    assert_eq!(any(OdometryParams::default()), Ok(()));
    assert_eq!(any(odometry(1.0)), Ok(()));
}
