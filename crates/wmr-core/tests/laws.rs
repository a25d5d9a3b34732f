//! The stabilization laws of issue 7 (polar, Lyapunov, curvature-keeping saturation) on
//! the full dynamic robot: `Robot::paper()`, default torque drive, dt = control_dt = 1 ms.
//!
//! Each check is against something independent of the code under test: the geometry of
//! the goal, the law's own Lyapunov function recomputed here from the pose, the inverse
//! kinematics (1) written out by hand, or the validation rules of the literature.

use core::f64::consts::{FRAC_PI_2, PI};

use proptest::prelude::*;
use wmr_core::controller::polar_frame::Direction;
use wmr_core::controller::{ServoGains, WheelServo, limit_wheel_speeds};
use wmr_core::kinematics::{twist_from_wheels, wheel_speeds};
use wmr_core::sensor::{PerfectSensor, Sensor};
use wmr_core::{
    ARRIVAL_RADIUS_M, AnyLaw, ClosedLoop, Controller, ControllerParams, DriveParams, FixedGoal, Law, LawParams,
    LyapunovLaw, LyapunovParams, Outcome, PaperLaw, PaperParams, ParamError, Plant, PolarLaw, PolarParams, Pose2, Real,
    Reason, ReferenceState, Robot, RobotParams, Sample, Status, Termination, Twist2, WheelDemand, WheelStage,
    WheelStageParams, Wheels, wrap_angle,
};

const DT: f64 = 1e-3;

fn deg(x: f64) -> f64 {
    x.to_radians()
}

fn pose<T: Real>(x: f64, y: f64, theta_deg: f64) -> Pose2<T> {
    Pose2::new(T::lit(x), T::lit(y), T::lit(theta_deg.to_radians()))
}

/// A loop with the paper's robot and default drive around `ctrl`, from `start` to a fixed `goal`.
fn closed<T: Real, L: Law<T>>(ctrl: Controller<T, L>, start: Pose2<T>, goal: Pose2<T>) -> ClosedLoop<T, L> {
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, start).unwrap();
    ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), T::lit(DT)).unwrap()
}

/// Any law by its keys, with the default wheel stage and control period.
fn build<T: Real>(law: LawParams<T>) -> Controller<T, AnyLaw<T>> {
    build_with(ControllerParams::with_law(law))
}

fn build_with<T: Real>(params: ControllerParams<T>) -> Controller<T, AnyLaw<T>> {
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    params.build(robot.params(), &drive).unwrap()
}

/// `law` with the torque-drive wheel stage, limited to `wheel_speed_max` rad/s (inf = off).
fn with_wheels<T: Real, L: Law<T>>(law: L, wheel_speed_max: T) -> Controller<T, L> {
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let dt = T::lit(DT);
    let wheels = WheelStageParams { wheel_speed_max, ..WheelStageParams::default() };
    Controller::new(law, WheelStage::new(&wheels, robot.params(), &drive, dt).unwrap())
}

fn polar<T: Real>(p: PolarParams<T>) -> Controller<T, PolarLaw<T>> {
    with_wheels(PolarLaw::<T>::new(p).unwrap(), T::infinity())
}

fn lyapunov<T: Real>(p: LyapunovParams<T>) -> Controller<T, LyapunovLaw<T>> {
    with_wheels(LyapunovLaw::<T>::new(p).unwrap(), T::infinity())
}

/// The two polar-coordinate laws with their default keys.
fn polar_laws<T: Real>() -> [LawParams<T>; 2] {
    [LawParams::Polar(PolarParams::default()), LawParams::Lyapunov(LyapunovParams::default())]
}

/// Tracks the first time from which dl stays below 1 cm (as `Outcome::time_to_arrival`).
fn track_arrival(since: &mut Option<f64>, t: f64, dl: f64) {
    if dl < 0.01 {
        since.get_or_insert(t);
    } else {
        *since = None;
    }
}

fn steps(t_s: f64) -> u64 {
    (t_s / DT).round() as u64
}

/// Distance (m) and heading error (rad, wrapped) of a pose from the goal, computed here.
fn miss(p: Pose2<f64>, goal: Pose2<f64>) -> (f64, f64) {
    let e = goal.theta - p.theta;
    ((goal.x - p.x).hypot(goal.y - p.y), e.sin().atan2(e.cos()))
}

/// Asserts a converged run: arrived (dl < 1 cm for good) before `t_max_s`, final
/// distance within `dl_max` m, final |heading error| below `head_max_deg`.
#[track_caller]
fn assert_converged(what: &str, o: &Outcome<f64>, goal: Pose2<f64>, t_max_s: f64, dl_max: f64, head_max_deg: f64) {
    assert!(!o.termination.diverged(), "{what}: diverged {o:?}");
    let t = o.time_to_arrival.unwrap_or_else(|| panic!("{what}: never arrived {o:?}"));
    let (dl, head) = miss(o.final_pose, goal);
    eprintln!("{what}: arrival {t:.2} s, final dl {dl:.2e} m, heading error {:.4} deg", head.to_degrees());
    assert!(t < t_max_s, "{what}: arrival at {t} s, not before {t_max_s} s");
    assert!(dl <= dl_max, "{what}: final dl {dl} m > {dl_max} m");
    assert!(head.abs() < deg(head_max_deg), "{what}: heading error {} deg", head.to_degrees());
    assert_eq!((o.status(), o.goal), (Status::Converged, goal), "{what}");
}

// The anchors' scenarios (Corke's RVC drive-to-pose and PythonRobotics move_to_pose).
fn anchor_1() -> (Pose2<f64>, Pose2<f64>) {
    (pose(5.0, 5.0, 0.0), pose(1.0, 4.0, 0.0))
}
fn anchor_2() -> (Pose2<f64>, Pose2<f64>) {
    (pose(5.0, 9.0, 0.0), pose(5.0, 5.0, 90.0))
}

// ---------------------------------------------------------------------------------------
// Convergence on the dynamic robot.

/// Polar law, (5, 5, 0) -> (1, 4, 0): measured arrival 12.2 s, heading error 0.4 deg
/// (the polar law's heading settles more slowly than its distance; see its docs).
#[test]
fn polar_anchor_1_converges() {
    let (start, goal) = anchor_1();
    let mut sim = closed(polar(PolarParams::default()), start, goal);
    let o = sim.run(steps(30.0), 10, |_| {});
    assert_converged("polar (5,5,0)->(1,4,0)", &o, goal, 15.0, 1.01e-3, 1.0);
    // The goal direction (-4, -1) is behind the heading (1, 0): the robot reverses.
    assert_eq!(sim.controller().law().direction(), Some(Direction::Backward));
}

/// Polar law, (5, 9, 0) -> (5, 5, 90 deg): measured arrival 15.1 s, heading error 2.5 deg.
/// The goal lies exactly abeam (alpha = -pi/2, the edge of I1), so the law starts
/// backwards; the robot's yaw overshoots on the torque-limited start and the direction
/// switches once (hysteresis), then never again.
#[test]
fn polar_anchor_2_converges() {
    let (start, goal) = anchor_2();
    let mut sim = closed(polar(PolarParams::default()), start, goal);
    let mut switches = 0;
    let mut last = sim.controller().law().direction();
    let mut arrived = None;
    for _ in 0..steps(30.0) {
        sim.step().unwrap();
        let d = sim.controller().law().direction();
        if d != last {
            switches += 1;
            last = d;
        }
        track_arrival(&mut arrived, sim.time(), miss(sim.state().pose(), goal).0);
    }
    assert!(switches <= 1, "direction switched {switches} times");
    assert!(arrived.is_some_and(|t| t < 18.0), "arrival {arrived:?}");
    let (dl, head) = miss(sim.state().pose(), goal);
    assert!(dl <= 1.01e-3 && head.abs() < deg(3.0), "dl {dl}, heading error {} deg", head.to_degrees());
}

/// Lyapunov law, (5, 5, 0) -> (1, 4, 0): measured arrival 12.3 s, heading error < 1e-3 deg.
#[test]
fn lyapunov_anchor_1_reaches_heading() {
    let (start, goal) = anchor_1();
    let mut sim = closed(lyapunov(LyapunovParams::default()), start, goal);
    let o = sim.run(steps(30.0), 10, |_| {});
    assert_converged("lyapunov (5,5,0)->(1,4,0)", &o, goal, 15.0, 1.01e-3, 1.0);
}

/// Lyapunov law, (5, 9, 0) -> (5, 5, 90 deg): measured arrival 13.1 s, heading error < 1e-3 deg.
#[test]
fn lyapunov_anchor_2_reaches_heading() {
    let (start, goal) = anchor_2();
    let mut sim = closed(lyapunov(LyapunovParams::default()), start, goal);
    let o = sim.run(steps(30.0), 10, |_| {});
    assert_converged("lyapunov (5,9,0)->(5,5,90)", &o, goal, 15.0, 1.01e-3, 1.0);
}

/// The exact-heading law from the paper's Fig. 7 scenario (the paper's own law leaves 5
/// to 16 deg there, docs/model.md): measured arrival 12.1 s, heading error < 1e-3 deg.
#[test]
fn lyapunov_fig7_reaches_heading() {
    let (start, goal) = (pose(0.0, 0.0, 0.0), pose(1.0, 1.0, 120.0));
    let mut sim = closed(lyapunov(LyapunovParams::default()), start, goal);
    let o = sim.run(steps(30.0), 10, |_| {});
    assert_converged("lyapunov (0,0,0)->(1,1,120)", &o, goal, 15.0, 1.01e-3, 0.1);
}

/// Goal right behind the robot: start (0, 0, 0), goal (-1, 0, 0). Both laws back straight
/// up: the geometry's answer is a 1 m straight line with the heading unchanged.
#[test]
fn goal_behind_backs_up_straight() {
    let (start, goal) = (pose(0.0, 0.0, 0.0), pose(-1.0, 0.0, 0.0));
    for law in polar_laws() {
        let mut sim = closed(build(law), start, goal);
        let (mut max_v, mut max_lateral, mut max_turn) = (0.0_f64, 0.0_f64, 0.0_f64);
        let o = sim.run(steps(20.0), 1, |s| {
            max_v = max_v.max(s.state.v);
            max_lateral = max_lateral.max(s.state.y.abs());
            max_turn = max_turn.max(s.state.theta.abs());
        });
        let what = law.kind();
        // Measured: arrival 9.2 s for both.
        assert_converged(what, &o, goal, 12.0, 1.01e-3, 1e-6);
        // Up to the stop's settling (measured 6e-5 m/s once held at the goal).
        assert!(max_v <= 1e-4, "{what}: drove forward at {max_v} m/s");
        assert!(max_lateral < 1e-12 && max_turn < 1e-12, "{what}: left the line ({max_lateral} m, {max_turn} rad)");
        assert!((o.path_length - 1.0).abs() < 2e-3, "{what}: path {} m, not 1 m", o.path_length);
    }
}

/// A goal ahead is reached driving forward (v >= 0 all along, up to the servo's ripple).
#[test]
fn goal_ahead_drives_forward() {
    let (start, goal) = (pose(0.0, 0.0, 0.0), pose(1.0, 1.0, 120.0));
    for law in polar_laws() {
        let mut sim = closed(build(law), start, goal);
        let mut min_v = 0.0_f64;
        let o = sim.run(steps(20.0), 1, |s| min_v = min_v.min(s.state.v));
        assert!(o.time_to_arrival.is_some(), "{}: {o:?}", law.kind());
        assert!(min_v > -1e-3, "{}: backed up at {min_v} m/s", law.kind());
    }
}

/// Aicardi et al.'s W = alpha^2 + h theta_A^2 is non-increasing along the kinematic closed
/// loop (V' = -lambda gamma cos^2(alpha) e^2 - k alpha^2 for every lambda > 0). On the
/// dynamic robot the torque-limited wheels lag the references at the start, so W may rise
/// a little in the first 2 s; after that it must not rise (beyond 1e-6 W(0), sampled every
/// 10 ms) and it must end many orders of magnitude below W(0).
#[test]
fn lyapunov_function_decreases_on_dynamic_robot() {
    let h = LyapunovParams::<f64>::default().h;
    for (start, goal) in [anchor_1(), anchor_2(), (pose(0.0, 0.0, 0.0), pose(1.0, 1.0, 120.0))] {
        let mut sim = closed(lyapunov(LyapunovParams::default()), start, goal);
        sim.step().unwrap();
        let dir = sim.controller().law().direction().unwrap();
        // W recomputed here from the pose: in the driving frame, alpha = wrap(phi - theta)
        // and theta_A = wrap(phi - theta_d), with both headings turned by pi when reversing.
        let flip = if dir == Direction::Backward { PI } else { 0.0 };
        let wrap = |a: f64| a.sin().atan2(a.cos());
        let w_of = |p: Pose2<f64>| {
            let phi = (goal.y - p.y).atan2(goal.x - p.x);
            let alpha = wrap(phi - p.theta - flip);
            let theta_a = wrap(phi - goal.theta - flip);
            alpha * alpha + h * theta_a * theta_a
        };
        let w0 = w_of(sim.state().pose());
        let (mut w_prev, mut early_rise, mut worst_rise, mut worst_at) = (w0, 0.0_f64, 0.0_f64, 0.0);
        let mut held_from = None;
        for i in 0..steps(30.0) {
            sim.step().unwrap();
            let p = sim.state().pose();
            let dl = (goal.x - p.x).hypot(goal.y - p.y);
            if dl < 2e-3 {
                held_from.get_or_insert(i);
                break; // Near the stop the angles are ill-conditioned; the law has stopped.
            }
            if i % 10 == 0 {
                let w = w_of(p);
                // The law's own W agrees with the one written out here.
                let w_law = sim.controller().law().angular_lyapunov(p, goal, dir);
                assert!((w_law - w).abs() <= 1e-9 * w0, "W {w} here, {w_law} by the law");
                let rise = (w - w_prev) / w0;
                if sim.time() < 2.0 {
                    early_rise = early_rise.max(rise);
                } else if rise > worst_rise {
                    (worst_rise, worst_at) = (rise, sim.time());
                }
                w_prev = w;
            }
        }
        eprintln!(
            "from {start:?}: W(0) = {w0:.3}, rise in the first 2 s {early_rise:.2e} W(0), later {worst_rise:.2e} W(0) at {worst_at:.2} s, last {w_prev:.2e}"
        );
        assert!(held_from.is_some(), "did not get near the goal from {start:?}");
        // Measured: at most 3.1 % in the first 2 s, 8.5e-8 later, final W below 1e-12 W(0).
        assert!(early_rise < 0.05, "W rose by {early_rise} of W(0) in the first 2 s from {start:?}");
        assert!(worst_rise < 1e-6, "W rose by {worst_rise} of W(0) at {worst_at} s from {start:?}");
        assert!(w_prev < 1e-9 * w0, "W only fell from {w0} to {w_prev}");
    }
}

/// Reset-safety: a controller that has run, once reset, repeats the run bit for bit.
#[test]
fn reset_repeats_the_run() {
    let (start, goal) = anchor_1();
    for law in polar_laws() {
        let fresh = build(law);
        let mut sim = closed(fresh, start, goal);
        let first = sim.run(steps(5.0), 10, |_| {});
        let mut used = *sim.controller();
        assert_ne!(used, fresh, "{}: the run left no memory to reset", law.kind());
        used.reset();
        let mut again = closed(used, start, goal);
        let second = again.run(steps(5.0), 10, |_| {});
        assert_eq!(first, second, "{}", law.kind());
    }
}

/// f32 runs of both laws: anchor 1's relative geometry, moved so the goal is the origin.
///
/// Not at the anchor's own coordinates: with f32 and dt = 1 ms the plant's position
/// increments near the goal (|v| dt ~ 1e-7 m) fall below half an ulp of y = 4 m
/// (2.4e-7 m), so y stops integrating, the lateral error cannot be removed and the
/// polar law turns in place (measured: 18 deg heading error at (1, 4)). Near the origin
/// the ulp is small. Measured here: arrival 12.2 / 12.3 s, final dl 1.3 / 1.9 mm (the
/// wheel angles, tens of rad, stall the same way below about 4e-3 rad/s), heading error
/// 0.45 / 0.006 deg.
#[test]
fn laws_converge_in_f32() {
    let start = pose::<f32>(4.0, 1.0, 0.0);
    let goal = pose::<f32>(0.0, 0.0, 0.0);
    for law in polar_laws::<f32>() {
        let mut sim = closed(build::<f32>(law), start, goal);
        let o = sim.run(steps(30.0), 10, |_| {});
        let p = o.final_pose;
        let p64 = Pose2::new(f64::from(p.x), f64::from(p.y), f64::from(p.theta));
        let g64 = Pose2::new(f64::from(goal.x), f64::from(goal.y), f64::from(goal.theta));
        let (dl, head) = miss(p64, g64);
        eprintln!(
            "f32 {}: arrival {:?} s, dl {dl:.2e} m, heading {:.4} deg",
            law.kind(),
            o.time_to_arrival,
            head.to_degrees()
        );
        assert!(o.time_to_arrival.is_some_and(|t| t < 16.0), "{}: {o:?}", law.kind());
        assert!(dl < 2.5e-3, "{}: dl {dl}", law.kind());
        let head_max = if matches!(law, LawParams::Lyapunov(_)) { 1.0 } else { 3.0 };
        assert!(head.abs() < deg(head_max), "{}: heading error {} deg", law.kind(), head.to_degrees());
    }
}

// ---------------------------------------------------------------------------------------
// Curvature-keeping saturation.

/// Wheel speeds of a twist by (1) inverted, written out here: (v +- R omega) / r.
fn wheels_by_hand(p: &RobotParams<f64>, t: Twist2<f64>) -> (f64, f64) {
    ((t.v + p.half_track * t.omega) / p.wheel_radius, (t.v - p.half_track * t.omega) / p.wheel_radius)
}

/// The controller's wheel stage limited to `w_max` rad/s, around `law`.
fn limited(law: LawParams<f64>, w_max: f64) -> Controller<f64, AnyLaw<f64>> {
    let wheels = WheelStageParams { wheel_speed_max: w_max, ..WheelStageParams::default() };
    build_with(ControllerParams { wheels, ..ControllerParams::with_law(law) })
}

proptest! {
    /// A twist limited through its wheel speeds (the inverse of (1), `limit_wheel_speeds`,
    /// then (1) back): omega / v is kept (as the cross product v_s omega - omega_s v = 0),
    /// the faster wheel ends exactly at the limit, and nothing changes within the limit.
    #[test]
    fn limited_wheel_speeds_keep_the_twist_curvature(v in -5.0f64..5.0, omega in -20.0f64..20.0, w_max in 0.5f64..50.0) {
        let p = RobotParams::<f64>::paper();
        let t = Twist2 { v, omega };
        let w = limit_wheel_speeds(wheel_speeds(&p, t), w_max);
        let s = twist_from_wheels(&p, w);
        let (wr, wl) = wheels_by_hand(&p, t);
        let (sr, sl) = wheels_by_hand(&p, s);
        let peak = wr.abs().max(wl.abs());
        if peak <= w_max {
            prop_assert_eq!(w, Wheels::new(wr, wl));
            prop_assert!((s.v - v).abs() <= 1e-12 * (v.abs() + 1.0) && (s.omega - omega).abs() <= 1e-12 * (omega.abs() + 1.0));
        } else {
            prop_assert!((sr.abs().max(sl.abs()) - w_max).abs() <= 1e-12 * w_max);
            prop_assert!((s.v * omega - s.omega * v).abs() <= 1e-12 * (v.abs() + 1.0) * (omega.abs() + 1.0));
            prop_assert!(s.v * v >= 0.0 && s.omega * omega >= 0.0);
        }
        // At the wheels: same ratio r/l, peak within the limit.
        prop_assert!((w.right * wl - w.left * wr).abs() <= 1e-9 * (wr.abs() + 1.0) * (wl.abs() + 1.0));
        prop_assert!(w.right.abs().max(w.left.abs()) <= w_max * (1.0 + 1e-12));
    }
}

#[test]
fn infinite_limit_passes_everything_through() {
    let p = RobotParams::<f64>::paper();
    let w = wheel_speeds(&p, Twist2 { v: 1e6, omega: -3e7 });
    assert_eq!(limit_wheel_speeds(w, f64::INFINITY), w);
    let huge = Wheels::new(f64::MAX, -f64::INFINITY);
    assert_eq!(limit_wheel_speeds(huge, f64::INFINITY), huge);
}

/// Along a run with the limit active: at every control tick the wheel speed references
/// give the same omega / v as the law's unsaturated twist, and neither exceeds the limit.
/// The law's twist is recomputed here by a copy of the law from the measurement it saw.
#[test]
fn saturation_keeps_curvature_along_runs() {
    let w_max = 10.0;
    let robot = Robot::<f64>::paper();
    let p = *robot.params();
    let (start, goal) = anchor_1();
    for law in polar_laws() {
        let what = law.kind();
        let mut sim = closed(limited(law, w_max), start, goal);
        assert_eq!(sim.controller().wheels().wheel_speed_max(), w_max);
        let (mut limited_ticks, mut peak_wheel, mut arrived) = (0, 0.0_f64, None);
        for _ in 0..steps(30.0) {
            let mut replay = *sim.controller().law();
            sim.step().unwrap();
            track_arrival(&mut arrived, sim.time(), miss(sim.state().pose(), goal).0);
            // dt = control_dt: every step ends with a control tick on the new state.
            let m = PerfectSensor.measure(sim.time(), sim.state(), robot.params());
            let out = replay.update(sim.time(), &m, &ReferenceState::at_rest(goal));
            let s = sim.sample();
            assert_eq!(out.errors, s.errors, "{what}: the replay is out of step");
            let WheelDemand::Twist(asked) = out.demand else { panic!("{what}: not a twist demand") };
            let refs = sim.controller().wheels().last_refs();
            let (wr, wl) = wheels_by_hand(&p, asked);
            if wr.abs().max(wl.abs()) > w_max {
                limited_ticks += 1;
            }
            assert!(refs.right.abs().max(refs.left.abs()) <= w_max * (1.0 + 1e-12), "{what}: {refs:?}");
            // Twist of the references by (1), by hand; curvature equal as a cross product.
            let v = p.wheel_radius * (refs.right + refs.left) / 2.0;
            let omega = p.wheel_radius * (refs.right - refs.left) / (2.0 * p.half_track);
            let scale = (asked.v.abs() + asked.omega.abs()) * (v.abs() + omega.abs());
            assert!((v * asked.omega - omega * asked.v).abs() <= 1e-12 * scale.max(1e-300), "{what}: ratio changed");
            peak_wheel = peak_wheel.max(s.wheel_speeds.right.abs().max(s.wheel_speeds.left.abs()));
        }
        assert!(limited_ticks > 100, "{what}: the limit was active for only {limited_ticks} ticks");
        // The wheels follow the limited references (measured peak 11.1 rad/s).
        assert!(peak_wheel < 1.2 * w_max, "{what}: wheel reached {peak_wheel} rad/s");
        // Slower than unlimited (12.2 / 12.3 s); measured 12.9 / 13.0 s.
        eprintln!("{what} limited to {w_max} rad/s: arrival {arrived:?} s, peak wheel {peak_wheel:.2} rad/s");
        assert!(arrived.is_some_and(|t| t < 16.0), "{what}: arrival {arrived:?}");
    }
}

/// The paper law with a finite limit: each tick the servo references move by at most
/// w_max dt on the faster wheel, parallel to the law's own step (same ratio, so the same
/// commanded curvature), and the run still converges (measured arrival 41.2 s at 10 rad/s).
#[test]
fn paper_saturation_limits_reference_speed() {
    let w_max = 10.0;
    let (start, goal) = (pose(0.0, 0.0, 0.0), pose(1.0, 1.0, 120.0));
    let mut sim = closed(limited(LawParams::Paper(PaperParams::paper()), w_max), start, goal);
    assert_eq!(sim.controller().wheels().wheel_speed_max(), w_max);
    let mut prev = sim.controller().wheels().last_refs();
    let (mut limited_ticks, mut arrived) = (0, None);
    for _ in 0..steps(60.0) {
        // The law's own target for the next tick, from a copy of it.
        let AnyLaw::Paper(mut law) = *sim.controller().law() else { panic!("expected the paper law") };
        let before = sim.steps();
        sim.step().unwrap();
        if sim.steps() == before {
            continue;
        }
        let (target, _) = law.references(sim.state().pose(), goal);
        let now = sim.controller().wheels().last_refs();
        let step = (now.right - prev.right, now.left - prev.left);
        let want = (target.right - prev.right, target.left - prev.left);
        assert!(step.0.abs().max(step.1.abs()) <= w_max * DT * (1.0 + 1e-9), "step {step:?}");
        if want.0.abs().max(want.1.abs()) > w_max * DT {
            limited_ticks += 1;
            let cross = step.0 * want.1 - step.1 * want.0;
            assert!(cross.abs() <= 1e-9 * want.0.abs().max(want.1.abs()).powi(2), "not parallel: {step:?} {want:?}");
        } else {
            assert_eq!(now, target);
        }
        prev = now;
        track_arrival(&mut arrived, sim.time(), miss(sim.state().pose(), goal).0);
    }
    assert!(limited_ticks > 100);
    assert!(arrived.is_some_and(|t| t < 50.0), "arrival {arrived:?}");
}

/// With the limit off (the default), `kind = "paper"` runs the paper's law bit for bit: the
/// same samples and outcome as the loop written out here from a bare `PaperLaw`, two
/// `WheelServo::update` calls (the paper's PD servos) and the plant, without the wheel
/// stage (whose rate limiter must pass the references through unchanged) or `ClosedLoop`.
#[test]
fn paper_default_is_unchanged() {
    let (start, goal) = (pose(0.0, 0.0, 0.0), pose(1.0, 1.0, 120.0));
    let n = steps(10.0);
    let any = build_with(ControllerParams::<f64>::default());
    assert!(matches!(any.law(), AnyLaw::Paper(_)));
    assert_eq!(any.wheels().wheel_speed_max(), f64::INFINITY);
    let mut a = closed(any, start, goal);
    let mut la = Vec::new();
    let oa = a.run(n, 1, |s| la.push(*s));

    // The same run by hand: measure, law, servos, hold, RK4 step; the outcome's sums too.
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let mut law = PaperLaw::new(PaperParams::paper(), robot.params(), DT).unwrap();
    let servo = WheelServo::new(ServoGains::torque_default(), drive.command_limit()).unwrap();
    let (mut servo_r, mut servo_l) = (servo, servo);
    let mut plant = Plant::new(robot, drive, start).unwrap();
    let mut lb = Vec::new();
    let (mut path, mut abs_work, mut peak, mut arrived) = (0.0_f64, 0.0_f64, 0.0_f64, None);
    for k in 0..=n {
        let t = k as f64 / 1e3; // ClosedLoop::time in f64: k ms exactly rounded (DT = 1 ms)
        let s = *plant.state();
        let w = s.wheel_speeds(robot.params());
        let (refs, errors) = law.references(s.pose(), goal);
        let command = Wheels::new(
            servo_r.update(refs.right, s.phi_r, w.right, DT),
            servo_l.update(refs.left, s.phi_l, w.left, DT),
        );
        plant.apply(command);
        let torque = plant.wheel_torque();
        lb.push(Sample {
            t,
            state: s,
            wheel_speeds: w,
            torque,
            errors,
            measured: s.pose(),
            contact: Default::default(),
            odometry: None,
            twist_demand: None,
            pose_covariance: None,
            disturbance: None,
        });
        let dl = (goal.x - s.x).hypot_libm(goal.y - s.y);
        if dl < ARRIVAL_RADIUS_M {
            arrived.get_or_insert(t);
        } else {
            arrived = None;
        }
        peak = peak.max(w.right.abs().max(w.left.abs()));
        if k == n {
            break;
        }
        path += s.v.abs() * DT;
        abs_work += ((torque.right * w.right).abs() + (torque.left * w.left).abs()) * DT;
        plant.step(t, DT).unwrap();
    }
    assert_eq!(la.len(), lb.len());
    for (sa, sb) in la.iter().zip(&lb) {
        assert_eq!(sa, sb, "at t = {}", sb.t);
    }
    let last = lb.last().unwrap();
    let expected = Outcome {
        termination: Termination::Completed,
        t_final: last.t,
        final_pose: last.state.pose(),
        goal,
        final_dl: (goal.x - last.state.x).hypot_libm(goal.y - last.state.y),
        final_heading_error: wrap_angle(goal.theta - last.state.theta),
        heading_tolerance: f64::INFINITY,
        time_to_arrival: arrived,
        peak_wheel_speed: peak,
        xy_goal_tolerance: 0.01,
        yaw_goal_tolerance: 1f64.to_radians(),
        path_length: path,
        abs_work,
    };
    assert_eq!(oa, expected);

    // The law composed directly (no AnyLaw) runs the same.
    let direct = with_wheels(PaperLaw::new(PaperParams::paper(), robot.params(), DT).unwrap(), f64::INFINITY);
    let mut b = closed(direct, start, goal);
    let mut lc = Vec::new();
    assert_eq!(b.run(n, 1, |s| lc.push(*s)), oa);
    assert_eq!(lc, la);
}

// ---------------------------------------------------------------------------------------
// Validation and selection.

fn robot_and_drive() -> (Robot<f64>, wmr_core::Drive<f64>) {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    (robot, drive)
}

/// The error of building a controller around the polar law with keys `p`; the law alone
/// gives the same one.
fn polar_err(p: PolarParams<f64>) -> ParamError {
    let (robot, drive) = robot_and_drive();
    let e = ControllerParams::with_law(LawParams::Polar(p)).build(robot.params(), &drive).unwrap_err();
    let alone = PolarLaw::new(p).unwrap_err();
    assert_eq!((alone.field, alone.reason), (e.field, e.reason));
    e
}

fn lyapunov_err(p: LyapunovParams<f64>) -> ParamError {
    let (robot, drive) = robot_and_drive();
    let e = ControllerParams::with_law(LawParams::Lyapunov(p)).build(robot.params(), &drive).unwrap_err();
    let alone = LyapunovLaw::new(p).unwrap_err();
    assert_eq!((alone.field, alone.reason), (e.field, e.reason));
    e
}

#[test]
fn polar_rejects_bad_gains_naming_the_key() {
    let d = PolarParams::<f64>::default();
    assert_eq!(polar_err(PolarParams { k_rho: 0.0, ..d }).field, "k_rho");
    assert_eq!(polar_err(PolarParams { k_rho: f64::NAN, ..d }).field, "k_rho");
    assert_eq!(polar_err(PolarParams { k_beta: 0.0, ..d }).field, "k_beta");
    assert_eq!(polar_err(PolarParams { k_beta: 0.3, ..d }).field, "k_beta");
    // k_alpha - k_rho must be > 0.
    let e = polar_err(PolarParams { k_rho: 3.0, k_alpha: 3.0, k_beta: -0.1, ..d });
    assert_eq!((e.field, e.reason), ("k_alpha", Reason::OutOfRange("must be > k_rho")));
    // Locally stable (k_alpha > k_rho, k_beta < 0) but not strongly: 1 - 5/3 1.2 - 2/pi 0.5 < 0.
    let e = polar_err(PolarParams { k_rho: 0.5, k_alpha: 1.0, k_beta: -1.2, ..d });
    assert_eq!(e.field, "k_alpha");
    assert!(e.to_string().contains("strong stability"), "{e}");
    // Siegwart's example gains pass: k = (3, 8, -1.5).
    let (robot, drive) = robot_and_drive();
    let ok = PolarParams { k_rho: 3.0, k_alpha: 8.0, k_beta: -1.5, ..d };
    assert!(PolarLaw::new(ok).is_ok());
    assert!(ControllerParams::with_law(LawParams::Polar(ok)).build(robot.params(), &drive).is_ok());
    assert_eq!(polar_err(PolarParams { reverse_hysteresis: FRAC_PI_2, ..d }).field, "reverse_hysteresis");
    assert_eq!(polar_err(PolarParams { goal_radius: -1.0, ..d }).field, "goal_radius");
    let bad_period = ControllerParams { control_dt: 0.0, ..ControllerParams::with_law(LawParams::Polar(d)) };
    assert_eq!(bad_period.build(robot.params(), &drive).unwrap_err().field, "control_dt");
}

#[test]
fn lyapunov_rejects_bad_gains_naming_the_key() {
    let d = LyapunovParams::<f64>::default();
    assert_eq!(lyapunov_err(LyapunovParams { gamma: 0.0, ..d }).field, "gamma");
    assert_eq!(lyapunov_err(LyapunovParams { k: -1.0, ..d }).field, "k");
    assert_eq!(lyapunov_err(LyapunovParams { h: 0.0, ..d }).field, "h");
    assert_eq!(lyapunov_err(LyapunovParams { h: f64::INFINITY, ..d }).field, "h");
}

#[test]
fn wheel_speed_max_validation() {
    let (robot, drive) = robot_and_drive();
    for bad in [0.0, -1.0, f64::NAN] {
        for law in LawParams::<f64>::defaults() {
            let wheels = WheelStageParams { wheel_speed_max: bad, ..WheelStageParams::default() };
            let p = ControllerParams { wheels, ..ControllerParams::with_law(law) };
            let e = p.build(robot.params(), &drive).unwrap_err();
            assert_eq!(e.field, "wheel_speed_max", "{bad} for {:?}", law.kind());
        }
    }
    for law in LawParams::<f64>::defaults() {
        let p = ControllerParams::with_law(law);
        assert_eq!(p.wheels.wheel_speed_max, f64::INFINITY);
        let ctrl = p.build(robot.params(), &drive).unwrap();
        assert_eq!(ctrl.wheels().wheel_speed_max(), f64::INFINITY);
    }
    // The defaults follow the drive: with a DC motor, the torque drive's 14 N m/rad and
    // 1.4 N m s/rad at the wheel (less the back-EMF's damping) and the no-load speed at the
    // wheel as the limit, by hand from the Pololu 37D's constants through k_t = 0.1.
    let m = wmr_core::DcMotorParams::<f64>::default();
    let dc = WheelStageParams::<f64>::for_drive(&DriveParams::DcMotor(m), &RobotParams::paper());
    let b = m.torque_constant / (m.armature_resistance * 0.1); // N m/V at the wheel
    let emf = m.back_emf_constant / 0.1; // V per rad/s of the wheel
    assert!((dc.servo_kp - 14.0 / b).abs() < 1e-12 && (dc.servo_kp - 81.5).abs() < 0.05, "{dc:?}");
    assert!((dc.servo_kd - (1.4 - b * emf) / b).abs() < 1e-12 && (dc.servo_kd - 7.58).abs() < 0.01, "{dc:?}");
    assert_eq!(dc.servo_ki, 0.0);
    // 12 V / 0.573 V s/rad = 20.94 rad/s: the datasheet's 200 rpm free-running at the output.
    assert!((dc.wheel_speed_max - 12.0 / emf).abs() < 1e-12, "{dc:?}");
    assert!((dc.wheel_speed_max - 200.0 * std::f64::consts::TAU / 60.0).abs() < 0.01, "{dc:?}");
    // A motor without back-EMF has no no-load speed: no limit.
    let no_emf = DriveParams::DcMotor(wmr_core::DcMotorParams { back_emf_constant: 0.0, ..m });
    assert_eq!(WheelStageParams::<f64>::for_drive(&no_emf, &RobotParams::paper()).wheel_speed_max, f64::INFINITY);
    assert_eq!(WheelStageParams::<f64>::default().servo(), ServoGains::torque_default());
    let bad_goal = Pose2::new(f64::NAN, 0.0, 0.0);
    assert_eq!(FixedGoal::new(bad_goal).unwrap_err().field, "goal.x");
}

/// The documented laws' `kind` names, in documentation order (a law added to the registry
/// comes after them); the built law and controller keep it. (Choosing a law by its name is
/// the scenario reader's job: it matches these names.)
#[test]
fn kinds_by_name() {
    let (robot, drive) = robot_and_drive();
    assert_eq!(
        LawParams::<f64>::defaults().map(|p| p.kind())[..9],
        [
            "paper",
            "paper_bidirectional",
            "polar",
            "lyapunov",
            "graceful",
            "mppi",
            "kanayama",
            "backstepping",
            "pure_pursuit"
        ]
    );
    for p in LawParams::<f64>::defaults() {
        assert_eq!(p.build(robot.params(), DT).unwrap().kind(), p.kind());
        assert_eq!(ControllerParams::with_law(p).build(robot.params(), &drive).unwrap().law().kind(), p.kind());
    }
    assert_eq!(LawParams::<f64>::default().kind(), "paper");
    assert_eq!(ControllerParams::<f64>::default().law.kind(), "paper");
}

/// AnyLaw dispatches to the same numbers as the law it holds.
#[test]
fn any_law_matches_direct() {
    let (start, goal) = anchor_2();
    let model = RobotParams::<f64>::paper();
    let mut a = closed(build(LawParams::Lyapunov(LyapunovParams::default())), start, goal);
    let mut b = closed(lyapunov(LyapunovParams::default()), start, goal);
    assert_eq!(a.run(steps(3.0), 10, |_| {}), b.run(steps(3.0), 10, |_| {}));
    let mut a = closed(build(LawParams::Polar(PolarParams::default())), start, goal);
    let mut b = closed(polar(PolarParams::default()), start, goal);
    assert_eq!(a.run(steps(3.0), 10, |_| {}), b.run(steps(3.0), 10, |_| {}));
    let mut a = closed(build(LawParams::Paper(PaperParams::paper())), start, goal);
    let mut b =
        closed(with_wheels(PaperLaw::new(PaperParams::paper(), &model, DT).unwrap(), f64::INFINITY), start, goal);
    assert_eq!(a.run(steps(3.0), 10, |_| {}), b.run(steps(3.0), 10, |_| {}));
}

/// The logged errors of the polar-coordinate laws: dl is the distance, e_theta the heading
/// error theta_d - theta, e_s the goal's signed distance along the heading.
#[test]
fn polar_laws_log_errors() {
    let (start, goal) = anchor_1();
    let mut sim = closed(build(LawParams::Polar(PolarParams::default())), start, goal);
    let mut n = 0;
    sim.run(steps(5.0), 100, |s| {
        let p = s.state.pose();
        // Errors are from the last control tick, which is this sample's time (dt = control_dt).
        let (dl, head) = miss(p, goal);
        let along = (goal.x - p.x) * p.theta.cos() + (goal.y - p.y) * p.theta.sin();
        assert!((s.errors.dl - dl).abs() < 1e-12 && (s.errors.e_theta - head).abs() < 1e-12);
        assert!((s.errors.e_s - along).abs() < 1e-12);
        n += 1;
    });
    assert!(n > 10);
}

/// The laws' closed loops allocate nothing (the core is alloc-free; this guards the enum
/// dispatch, the wheel stage's twist path and, for the paper law limited to 10 rad/s,
/// its rate limiter), at both precisions.
#[test]
fn laws_allocate_nothing() {
    fn count<T: Real>(law: LawParams<T>) -> u64 {
        let goal = pose::<T>(1.0, 1.0, 120.0);
        let mut p = ControllerParams::with_law(law);
        if let LawParams::Paper(_) = law {
            p.wheels.wheel_speed_max = T::lit(10.0);
        }
        let mut sim = closed(build_with(p), pose::<T>(0.0, 0.0, 0.0), goal);
        let mut checksum = T::zero();
        let info = allocation_counter::measure(|| {
            let o = sim.run(20_000, 10, |s| checksum = checksum + s.state.x);
            checksum = checksum + o.final_dl;
        });
        assert!(checksum.is_finite());
        info.count_total
    }
    for (l64, l32) in LawParams::<f64>::defaults().into_iter().zip(LawParams::<f32>::defaults()) {
        assert_eq!(count::<f64>(l64), 0, "{}", l64.kind());
        assert_eq!(count::<f32>(l32), 0, "{}", l32.kind());
    }
}

/// The direction rule on its own: decided from the sign of cos(alpha) at the first tick;
/// later, alpha wobbling around pi/2 does not switch it, only an overshoot past
/// pi/2 + hysteresis does, and then the new frame sees |alpha| < pi/2 - hysteresis.
#[test]
fn direction_switches_only_with_hysteresis() {
    use wmr_core::controller::DirectionSelector;
    let h = deg(30.0);
    let goal = pose::<f64>(0.0, 0.0, 0.0);
    // The robot 1 m east of the goal with heading psi: phi = pi, alpha = wrap(pi - psi).
    let at = |alpha: f64| Pose2::new(1.0, 0.0, PI - alpha);
    // `select` answers "backward?" (per lane; one run here).
    let mut sel = DirectionSelector::<f64>::new(true, h);
    assert!(!sel.select(at(deg(80.0)), goal).0);
    for a in [85.0, 95.0, 100.0, 119.0, 91.0, 110.0] {
        let (d, c) = sel.select(at(deg(a)), goal);
        assert!(!d, "switched at alpha = {a} deg");
        assert!((c.alpha - deg(a)).abs() < 1e-12);
    }
    let (d, c) = sel.select(at(deg(121.0)), goal);
    assert!(d);
    assert_eq!(sel.current(), Some(Direction::Backward));
    assert!((c.alpha - deg(121.0 - 180.0)).abs() < 1e-12 && c.alpha.abs() < FRAC_PI_2 - h);
    // Goal behind at the first tick: backwards at once; forward-only never reverses.
    let mut sel = DirectionSelector::<f64>::new(true, h);
    assert!(sel.select(at(deg(100.0)), goal).0);
    let mut fwd = DirectionSelector::<f64>::new(false, h);
    assert!(!fwd.select(at(deg(179.0)), goal).0);
    sel.reset();
    assert_eq!(sel.current(), None);
}

/// The paper's law with `anti_windup = "conditional"`: after a tick at which the wheel
/// stage saturated its integrators hold, so for a fixed measured pose the wheel references
/// stay where they are; without the key (the paper's law as printed, the default) they
/// move on by Ki e dt / r per tick. Both checked against the PI sums written out here.
#[test]
fn paper_anti_windup_holds_the_integrators_while_saturated() {
    use wmr_core::AntiWindup;
    let model = RobotParams::<f64>::paper();
    let (pose_now, goal) = (pose::<f64>(0.0, 0.0, 0.0), pose::<f64>(3.0, 0.0, 0.0));
    for (aw, holds) in [(AntiWindup::Off, false), (AntiWindup::Conditional, true)] {
        let params = PaperParams { anti_windup: aw, ..PaperParams::paper() };
        let mut law = PaperLaw::new(params, &model, DT).unwrap();
        assert_eq!(law.anti_windup(), holds);
        let (first, errors) = law.references(pose_now, goal);
        // Straight ahead: e_theta = 0, e_s = 3 m; u_s = Kp_s e_s + Ki_s e_s dt.
        assert_eq!((errors.e_s, errors.e_theta), (3.0, 0.0));
        let u_s = |ticks: f64| params.kp_s * 3.0 + params.ki_s * 3.0 * DT * ticks;
        assert!((first.right - u_s(1.0) / model.wheel_radius).abs() < 1e-12);
        law.wheels_saturated(true);
        let mut last = first;
        for tick in 2..=50 {
            let (refs, _) = law.references(pose_now, goal);
            let want = if holds { u_s(1.0) } else { u_s(f64::from(tick)) };
            assert!((refs.right - want / model.wheel_radius).abs() < 1e-12, "{aw:?} tick {tick}: {refs:?}");
            assert_eq!(refs.left, refs.right);
            last = refs;
        }
        // Released: the sums move on from where they held.
        law.wheels_saturated(false);
        let (refs, _) = law.references(pose_now, goal);
        assert!(refs.right > last.right, "{aw:?}");
    }
}

/// The default servo gains follow the robot's inertia at the wheel (issue 38, item 8):
/// the paper's robot keeps exactly 14 and 1.4 (f64 and f32, bit for bit); a 120 kg robot
/// gets the same bandwidth sqrt(Kp / J_w) and damping ratio Kd / (2 sqrt(Kp J_w)), from
/// J_w worked out here by hand (the old gains gave it the 5 kg robot's 14 N m/rad).
#[test]
fn servo_defaults_scale_with_the_inertia_at_the_wheel() {
    let torque = DriveParams::<f64>::default();
    let paper = WheelStageParams::<f64>::for_drive(&torque, &RobotParams::paper());
    assert_eq!((paper.servo_kp.to_bits(), paper.servo_kd.to_bits()), (14.0f64.to_bits(), 1.4f64.to_bits()));
    let paper32 = WheelStageParams::<f32>::for_drive(&DriveParams::default(), &RobotParams::paper());
    assert_eq!((paper32.servo_kp.to_bits(), paper32.servo_kd.to_bits()), (14.0f32.to_bits(), 1.4f32.to_bits()));
    // J_w = r^2 / (1 / M11 + R^2 / M22) by hand.
    let j_w = |p: &RobotParams<f64>| {
        let m11 = p.mass + 2.0 * p.wheel_inertia / (p.wheel_radius * p.wheel_radius);
        let m22 = p.platform_inertia
            + p.mass * p.com_offset * p.com_offset
            + 2.0 * p.half_track * p.half_track * p.wheel_inertia / (p.wheel_radius * p.wheel_radius);
        p.wheel_radius * p.wheel_radius / (1.0 / m11 + p.half_track * p.half_track / m22)
    };
    let j_paper = j_w(&RobotParams::paper());
    assert!((j_paper - 0.03277).abs() < 1e-5, "{j_paper}");
    let heavy = RobotParams {
        mass: 120.0,
        half_track: 0.25,
        com_offset: 0.05,
        wheel_inertia: 0.05,
        platform_inertia: 6.0,
        gear_ratio: 0.05,
        ..RobotParams::paper()
    };
    let g = WheelStageParams::<f64>::for_drive(&torque, &heavy);
    let j = j_w(&heavy);
    assert!(j > 10.0 * j_paper, "{j}");
    let bandwidth = |kp: f64, j: f64| (kp / j).sqrt();
    assert!((bandwidth(g.servo_kp, j) - bandwidth(14.0, j_paper)).abs() < 1e-9, "{g:?}");
    let zeta = |kp: f64, kd: f64, j: f64| kd / (2.0 * (kp * j).sqrt());
    assert!((zeta(g.servo_kp, g.servo_kd, j) - zeta(14.0, 1.4, j_paper)).abs() < 1e-12, "{g:?}");
    // Through a DC motor: the same stiffness at the wheel, b Kp = Kp_torque.
    let m = wmr_core::DcMotorParams::<f64>::default();
    let dc = WheelStageParams::<f64>::for_drive(&DriveParams::DcMotor(m), &heavy);
    let b = m.torque_constant / (m.armature_resistance * heavy.gear_ratio);
    assert!((dc.servo_kp * b - g.servo_kp).abs() < 1e-9, "{dc:?}");
}

/// Issue 43 item 1: a loop's samples carry the twist its law demanded at the last tick
/// (`/cmd_vel`): the law's own `WheelDemand::Twist`, asked of a second copy of the law
/// with the same measurements, for every law that demands a twist; `None` for the laws
/// that demand wheel angles or torques, as `LawParams::twist_demand` says. f64 and f32.
fn samples_carry_the_law_twist_demand<T: Real>() {
    let goal = pose::<T>(0.4, 0.3, 30.0);
    let robot = Robot::<T>::paper();
    let mut twist_laws = 0;
    for p in LawParams::<T>::defaults() {
        let ctrl = build(p);
        let mut lp = closed(ctrl, pose::<T>(0.0, 0.0, 0.0), goal);
        let mut law = p.build(robot.params(), T::lit(DT)).unwrap();
        // The law's own answers to the ticks the loop ran (control_dt = dt: every step).
        let check = |lp: &ClosedLoop<T, AnyLaw<T>>, law: &mut AnyLaw<T>| {
            let tick = *lp.last_tick();
            let out = law.update(tick.t, &tick.measurement, &tick.reference);
            let want = match out.demand {
                WheelDemand::Twist(t) => Some(t),
                _ => None,
            };
            assert_eq!(lp.sample().twist_demand, want, "{}", p.kind());
            assert_eq!(want.is_some(), p.twist_demand(), "{}", p.kind());
        };
        check(&lp, &mut law);
        for _ in 0..50 {
            lp.step().unwrap();
            law.wheels_saturated(lp.controller().wheels().saturated());
            check(&lp, &mut law);
        }
        twist_laws += usize::from(p.twist_demand());
        // A path-following law without a path (a fixed goal) stands still.
        if p.twist_demand() && p.follows() != wmr_core::controller::Follows::Path {
            let d = lp.sample().twist_demand.unwrap();
            assert!(d.v != T::lit(0.0) || d.omega != T::lit(0.0), "{}: a demand that moves", p.kind());
        }
    }
    assert_eq!(twist_laws, LawParams::<T>::defaults().len() - 3, "all but paper, paper_bidirectional, backstepping");
}

#[test]
fn samples_carry_the_law_twist_demand_f64() {
    samples_carry_the_law_twist_demand::<f64>();
}

#[test]
fn samples_carry_the_law_twist_demand_f32() {
    samples_carry_the_law_twist_demand::<f32>();
}
