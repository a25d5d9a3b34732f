//! The disturbance observer (`[controller.observer] kind = "disturbance"`, wmr issue 42,
//! item 2) against closed forms: the first-order response d (1 - exp(-g t)) of its
//! Q-filter to a constant disturbance, sampled at the ticks, on the exact wheel dynamics
//! and on the plant under a push; and the compensation rejecting the push.

use crate::common::assert_close;
use wmr_core::{
    ClosedLoop, ControllerParams, DisturbanceObserverParams, DriveParams, FixedGoal, Plant, Pose2, PushParams, Pushes,
    Real, RobotParams, Wheels,
};

fn f(v: impl Real) -> f64 {
    v.to_f64_lossless()
}

/// The default torque drive on the paper's robot.
fn paper_drive<T: Real>() -> wmr_core::Drive<T> {
    DriveParams::default().validate(&wmr_core::Robot::paper()).unwrap()
}

/// The paper's robot's wheel-space inertia matrix by hand (r = 0.1 m, R = 0.2 m,
/// m = 5 kg, d = 0.25 m, I_p = 0.005, I_m = 0.002 kg m^2):
/// M_11 = 5 + 2 * 0.002 / 0.01 = 5.4 kg, M_22 = 0.005 + 5 * 0.0625 + 2 * 0.04 * 0.002 / 0.01
/// = 0.3335 kg m^2; J_s = 0.01 / 4 (5.4 + 0.3335 / 0.04) = 0.034343750,
/// J_x = 0.01 / 4 (5.4 - 0.3335 / 0.04) = -0.007343750 kg m^2.
const J_S: f64 = 0.034343750;
const J_X: f64 = -0.007343750;

/// On the exact wheel dynamics J w' = tau + d (stepped in closed form: w gains
/// h J^-1 (tau + d) per period under a held torque) with an arbitrary torque sequence and
/// a constant disturbance from t = 0, the estimate at tick k is d (1 - exp(-g k h)): the
/// Q-filter's step response, whatever the torques; within 1 % of d after 5 / g.
fn constant_disturbance_is_the_first_order_response<T: Real>(tol: f64) {
    let (g, h) = (40.0, 1e-3);
    let mut obs = DisturbanceObserverParams { bandwidth: T::lit(g), ..Default::default() }
        .validate::<T>(&RobotParams::paper(), &paper_drive(), T::lit(h))
        .unwrap();
    let (js, jx) = obs.wheel_inertia();
    assert_close("J_s", f(js), J_S, tol, 0.0);
    assert_close("J_x", f(jx), J_X, tol, 0.0);
    let d = (0.31, -0.12);
    let det = J_S * J_S - J_X * J_X;
    let mut w = (1.5, -0.4);
    let mut at_5_over_g = None;
    for k in 0..=400 {
        let t = k as f64 * h;
        let est = obs.update(Wheels::new(T::lit(w.0), T::lit(w.1)));
        let closed = 1.0 - (-g * t).exp();
        assert_close("d_hat right", f(est.right), d.0 * closed, tol, tol * 0.31);
        assert_close("d_hat left", f(est.left), d.1 * closed, tol, tol * 0.31);
        if k == (5.0 / g / h).round() as usize {
            at_5_over_g = Some((f(est.right), f(est.left)));
        }
        // Any torques: the estimate does not depend on them.
        let tau = (0.8 * (7.0 * t).sin(), -0.5 + 0.3 * (3.0 * t).cos());
        obs.record(Wheels::new(T::lit(tau.0), T::lit(tau.1)));
        let (a, b) = (tau.0 + d.0, tau.1 + d.1);
        // w += h J^-1 (tau + d).
        w = (w.0 + h * (J_S * a - J_X * b) / det, w.1 + h * (-J_X * a + J_S * b) / det);
    }
    let (r, l) = at_5_over_g.unwrap();
    assert!((r - d.0).abs() < 0.01 * d.0.abs() && (l - d.1).abs() < 0.01 * d.1.abs(), "after 5/g: ({r}, {l})");
}

#[test]
fn constant_disturbance_is_the_first_order_response_f64() {
    constant_disturbance_is_the_first_order_response::<f64>(1e-9);
}

#[test]
fn constant_disturbance_is_the_first_order_response_f32() {
    constant_disturbance_is_the_first_order_response::<f32>(2e-4);
}

/// The paper's robot with G at C (linear dynamics, so the model's J is exact), holding
/// its goal under the paper's law with the observer, pushed from t0 = 0.3 s (a tick) on
/// with F forward and tau about the vertical: a step of the wheel torques
/// d = r/2 (F + tau / R, F - tau / R), estimated at every tick after t0 as
/// d (1 - exp(-g (t - t0))) (the law's own torques do not enter the estimate).
fn a_pushs_step_is_estimated_with_the_closed_form_response<T: Real>(tol: f64) {
    let (g, t0, fx, tau) = (60.0, 0.3, 6.0, 0.8);
    let robot = RobotParams::<T> { com_offset: T::zero(), ..RobotParams::paper() }.validate().unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let push = PushParams {
        t: T::lit(t0),
        duration: T::lit(5.0),
        force_x: T::lit(fx),
        force_y: T::zero(),
        torque: T::lit(tau),
    };
    let params = ControllerParams {
        observer: Some(DisturbanceObserverParams { bandwidth: T::lit(g), ..Default::default() }),
        ..ControllerParams::paper()
    };
    let ctrl = params.build(robot.params(), &drive).unwrap();
    let goal = Pose2::new(T::zero(), T::zero(), T::zero());
    let plant = Plant::new(robot, drive, goal).unwrap().with_pushes(Pushes::new(&[push]).unwrap());
    let mut lp = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), T::lit(1e-3)).unwrap();
    let (r, big_r) = (0.1, 0.2);
    let d = (r / 2.0 * (fx + tau / big_r), r / 2.0 * (fx - tau / big_r));
    let mut checked = 0;
    for _ in 0..800 {
        lp.step().unwrap();
        let tick = lp.last_tick();
        let t = f(tick.t);
        let est = tick.output.disturbance.expect("the observer's estimate");
        let closed = if t <= t0 { 0.0 } else { 1.0 - (-g * (t - t0)).exp() };
        assert_close("d_hat right", f(est.right), d.0 * closed, tol, tol * d.0.abs());
        assert_close("d_hat left", f(est.left), d.1 * closed, tol, tol * d.0.abs());
        checked += 1;
    }
    assert_eq!(checked, 800);
}

#[test]
fn a_pushs_step_is_estimated_with_the_closed_form_response_f64() {
    a_pushs_step_is_estimated_with_the_closed_form_response::<f64>(1e-9);
}

#[test]
fn a_pushs_step_is_estimated_with_the_closed_form_response_f32() {
    a_pushs_step_is_estimated_with_the_closed_form_response::<f32>(2e-3);
}

/// The estimate is fed forward: the robot holding its goal under a steady push is moved
/// (far) less with the observer than without; and on an undisturbed run of the linear
/// plant (G at C, the model exact) there is nothing to estimate: the observer leaves the
/// path as it is (to `tol` m after 2 s from 0.36 m away).
fn the_estimate_is_fed_forward<T: Real>(tol: f64) {
    let robot = RobotParams::<T> { com_offset: T::zero(), ..RobotParams::paper() }.validate().unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let push = PushParams {
        t: T::lit(0.2),
        duration: T::lit(10.0),
        force_x: T::lit(8.0),
        force_y: T::zero(),
        torque: T::lit(0.5),
    };
    let goal = Pose2::new(T::zero(), T::zero(), T::zero());
    let run = |observer: Option<DisturbanceObserverParams<T>>, pushes: &[PushParams<T>], start: Pose2<T>| {
        let params = ControllerParams { observer, ..ControllerParams::paper() };
        let ctrl = params.build(robot.params(), &drive).unwrap();
        let plant = Plant::new(robot, drive, start).unwrap().with_pushes(Pushes::new(pushes).unwrap());
        let mut lp = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), T::lit(1e-3)).unwrap();
        let mut worst = 0.0f64;
        for _ in 0..2000 {
            lp.step().unwrap();
            let s = lp.state();
            worst = worst.max(f(s.x).hypot(f(s.y)) + 0.2 * f(s.theta).abs());
        }
        (worst, *lp.state())
    };
    let on = Some(DisturbanceObserverParams::default());
    let (plain, with) = (run(None, &[push], goal).0, run(on, &[push], goal).0);
    assert!(with < 0.2 * plain, "pushed: {with} m with the observer, {plain} m without");
    eprintln!("pushed at the goal: worst displacement {with:.4e} m with the observer, {plain:.4e} m without");
    let start = Pose2::new(T::lit(0.3), T::lit(-0.2), T::lit(0.5));
    let (a, b) = (run(None, &[], start).1, run(on, &[], start).1);
    let gap = f(a.x - b.x).hypot(f(a.y - b.y));
    assert!(gap <= tol, "undisturbed: the observer moved the path by {gap} m");
    let moved = f(a.x - start.x).hypot(f(a.y - start.y));
    assert!(moved > 0.01, "the run moved {moved} m");
}

#[test]
fn the_estimate_is_fed_forward_f64() {
    the_estimate_is_fed_forward::<f64>(1e-9);
}

#[test]
fn the_estimate_is_fed_forward_f32() {
    the_estimate_is_fed_forward::<f32>(1e-3);
}

/// Bad keys are refused naming them, and an observer changes nothing when it is off.
#[test]
fn bad_bandwidths_name_the_key() {
    let robot = RobotParams::<f64>::paper().validate().unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    for g in [0.0, -3.0, f64::NAN, f64::INFINITY] {
        let params = ControllerParams {
            observer: Some(DisturbanceObserverParams { bandwidth: g, ..Default::default() }),
            ..ControllerParams::paper()
        };
        let e = params.build(robot.params(), &drive).unwrap_err();
        assert_eq!(e.field, "observer.bandwidth", "{g}: {e}");
    }
    assert!(ControllerParams::<f64>::paper().observer.is_none(), "off by default");
}

/// The deadband and stiction pre-compensation by hand (docs/model.md, "Disturbance
/// observer"): torque demands in, drive commands out of the wheel stage at its first tick
/// (the estimate still 0), the wheels at rest. The torque drive on the paper's robot gives
/// at most c_max = 0.2 / 0.1 = 2 N m at the wheel: a believed deadband of 5 % is 0.1 N m,
/// a breakaway torque of 0.04 N m is less, so c_min = 0.1 N m and the band b = 0.05 N m.
/// A DC motor (12 V; k_tau / (R_a k_t) = 0.03744 / (2.18 * 0.1) = 0.171743 N m/V at the
/// wheel): 5 % is 0.6 V, a breakaway torque of 0.2 N m needs 0.2 / 0.171743 = 1.164531 V,
/// so c_min = 1.164531 V and b = 0.582266 V.
/// (drive, deadband, static_friction, c_min, [(demand N m, command out)]).
type Case<'a, T> = (DriveParams<T>, f64, f64, f64, &'a [(f64, f64)]);

fn precompensation_lifts_by_hand<T: Real>(tol: f64) {
    use wmr_core::{DcMotorParams, Measurement, Robot, WheelDemand, WheelStage, WheelStageParams};
    let robot = Robot::<T>::paper();
    let at_rest = Measurement {
        t: T::zero(),
        pose: Pose2::default(),
        wheel_angles: Wheels::new(T::zero(), T::zero()),
        wheel_speeds: Wheels::new(T::zero(), T::zero()),
    };
    let lit = |x: f64| T::lit(x);
    let torque = DriveParams::default();
    let dc = DriveParams::DcMotor(DcMotorParams::default());
    let volts = 1.0 / 0.171743119266055;
    let cases: [Case<'_, T>; 5] = [
        // Off (the default): every demand passes as it is.
        (torque, 0.0, 0.0, 0.0, &[(0.07, 0.07), (-0.03, -0.03), (0.0, 0.0), (1e-6, 1e-6)]),
        // Deadband 5 %, breakaway 0.04 N m: c_min = 0.1, b = 0.05 N m.
        (
            torque,
            0.05,
            0.04,
            0.1,
            &[
                (0.07, 0.1),
                (-0.07, -0.1),
                (0.0501, 0.1),
                (0.05, 0.05),
                (0.03, 0.03),
                (-0.03, -0.03),
                (0.0, 0.0),
                (0.1, 0.1),
                (0.3, 0.3),
                (-1.2, -1.2),
            ],
        ),
        // Stiction alone, 0.15 N m: c_min = 0.15, b = 0.075 N m.
        (torque, 0.0, 0.15, 0.15, &[(0.1, 0.15), (-0.08, -0.15), (0.07, 0.07), (-0.07, -0.07), (0.2, 0.2)]),
        // The DC motor: c_min = 1.164531 V (the breakaway torque), b = 0.582266 V.
        (
            dc,
            0.05,
            0.2,
            0.2 * volts,
            &[(0.12, 0.2 * volts), (-0.15, -0.2 * volts), (0.05, 0.05 * volts), (0.3, 0.3 * volts), (0.0, 0.0)],
        ),
        // The DC motor, the deadband larger: c_min = 0.6 V, b = 0.3 V.
        (dc, 0.05, 0.04, 0.6, &[(0.07, 0.6), (-0.07, -0.6), (0.04, 0.04 * volts), (0.2, 0.2 * volts)]),
    ];
    for (params, deadband, static_friction, lift, io) in cases {
        let drive = params.validate(&robot).unwrap();
        let observer = DisturbanceObserverParams {
            deadband: lit(deadband),
            static_friction: lit(static_friction),
            ..Default::default()
        };
        let obs = observer.validate::<T>(robot.params(), &drive, lit(1e-3)).unwrap();
        assert_close("c_min", f(obs.lift().0), lift, tol, 0.0);
        assert_close("b", f(obs.lift().1), 0.5 * lift, tol, 0.0);
        assert_eq!(obs.precompensates(), lift > 0.0);
        let wheels = WheelStageParams::for_drive(&params, robot.params());
        let stage = WheelStage::new(&wheels, robot.params(), &drive, lit(1e-3)).unwrap().with_observer(obs);
        for &(demand, out) in io {
            let mut s = stage;
            let c = s.command(WheelDemand::Torques(Wheels::new(lit(demand), lit(-demand))), &at_rest);
            let what =
                format!("{} deadband {deadband} static_friction {static_friction} demand {demand}", params.kind());
            assert_close(&format!("{what}: right"), f(c.right), out, tol, tol * 1e-3);
            assert_close(&format!("{what}: left"), f(c.left), -out, tol, tol * 1e-3);
            assert_eq!(f(c.right) == 0.0, demand == 0.0, "{what}: zero in, zero out");
        }
    }
}

#[test]
fn precompensation_lifts_by_hand_f64() {
    precompensation_lifts_by_hand::<f64>(1e-12);
}

#[test]
fn precompensation_lifts_by_hand_f32() {
    precompensation_lifts_by_hand::<f32>(1e-5);
}

/// With a believed deadband the observer records the torque the believed drive gives: a
/// command within the band, below the deadband, gives 0, so a wheel that stays at rest
/// under it shows no disturbance (the estimate stays 0); believing stiction alone the
/// same command is recorded as given, and the wheel at rest shows its loss: the estimate
/// at the second tick is (1 - exp(-g h)) (0 - 0.03) N m.
#[test]
fn the_observer_records_the_believed_drive() {
    use wmr_core::{Measurement, Robot, WheelDemand, WheelStage, WheelStageParams};
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let at_rest = Measurement {
        t: 0.0,
        pose: Pose2::default(),
        wheel_angles: Wheels::new(0.0, 0.0),
        wheel_speeds: Wheels::new(0.0, 0.0),
    };
    let gain = 1.0 - (-50.0f64 * 1e-3).exp();
    for (deadband, static_friction, expected) in [(0.05, 0.04, 0.0), (0.0, 0.15, -gain * 0.03)] {
        let observer = DisturbanceObserverParams { deadband, static_friction, ..Default::default() };
        let obs = observer.validate::<f64>(robot.params(), &drive, 1e-3).unwrap();
        let wheels = WheelStageParams::for_drive(&DriveParams::default(), robot.params());
        let mut stage = WheelStage::new(&wheels, robot.params(), &drive, 1e-3).unwrap().with_observer(obs);
        let demand = WheelDemand::Torques(Wheels::new(0.03, 0.03));
        assert_eq!(stage.command(demand, &at_rest).right, 0.03, "within the band: unlifted");
        stage.command(demand, &at_rest);
        let d = stage.disturbance_estimate().unwrap();
        assert_close("estimate", d.right, expected, 1e-12, 1e-15);
    }
}

/// The pre-compensation's keys are refused naming them as the scenario writes them.
#[test]
fn bad_precompensation_keys_name_the_key() {
    let robot = RobotParams::<f64>::paper().validate().unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let base = DisturbanceObserverParams::<f64>::default();
    let cases = [
        ("observer.deadband", DisturbanceObserverParams { deadband: -0.1, ..base }),
        ("observer.deadband", DisturbanceObserverParams { deadband: 1.0, ..base }),
        ("observer.deadband", DisturbanceObserverParams { deadband: f64::NAN, ..base }),
        ("observer.static_friction", DisturbanceObserverParams { static_friction: -0.1, ..base }),
        ("observer.static_friction", DisturbanceObserverParams { static_friction: f64::INFINITY, ..base }),
        ("observer.precompensation_band", DisturbanceObserverParams { precompensation_band: 1.5, ..base }),
        ("observer.precompensation_band", DisturbanceObserverParams { precompensation_band: -0.5, ..base }),
    ];
    for (name, observer) in cases {
        let params = ControllerParams { observer: Some(observer), ..ControllerParams::paper() };
        let e = params.build(robot.params(), &drive).unwrap_err();
        assert_eq!(e.field, name, "{observer:?}: {e}");
    }
    // A deadband is a fraction of the drive's largest command: none without a limit.
    let unlimited = DriveParams::Torque(wmr_core::TorqueDriveParams { motor_torque_max: f64::INFINITY, deadband: 0.0 })
        .validate(&robot)
        .unwrap();
    let params = ControllerParams {
        observer: Some(DisturbanceObserverParams { deadband: 0.05, ..base }),
        ..ControllerParams::paper()
    };
    assert_eq!(params.build(robot.params(), &unlimited).unwrap_err().field, "observer.deadband");
    let params = ControllerParams {
        observer: Some(DisturbanceObserverParams { static_friction: 0.05, ..base }),
        ..ControllerParams::paper()
    };
    assert!(params.build(robot.params(), &unlimited).is_ok(), "stiction alone needs no limit");
}
