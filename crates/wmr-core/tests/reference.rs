//! A reference that moves: the loop hands every law the reference state at the tick's
//! own time, in one run ([`ClosedLoop`]) and in lanes ([`LaneBatch`], each lane at its
//! own run's time), and judges runs against the reference pose of the moment.

use wmr_core::batch::LaneBatch;
use wmr_core::controller::{ControlErrors, LawOutput, PolarLaw};
use wmr_core::lane::{Lane, Lanes};
use wmr_core::{
    ClosedLoop, Controller, ControllerParams, DriveParams, Law, LawParams, Measurement, Plant, PolarParams, Pose2,
    Reference, ReferenceState, Robot, Twist2, WheelDemand, WheelStage, WheelStageParams,
};

/// C_ref moving along +x at `v` m/s from (x0, y0), heading 0, accelerating at `a` m/s^2.
#[derive(Clone, Copy, Debug)]
struct Drifting {
    x0: f64,
    y0: f64,
    v: f64,
    a: f64,
}

impl Reference<f64> for Drifting {
    fn state_at(&self, t: f64) -> ReferenceState<f64> {
        ReferenceState {
            pose: Pose2::new(self.x0 + (self.v + 0.5 * self.a * t) * t, self.y0, 0.0),
            twist: Twist2 { v: self.v + self.a * t, omega: 0.0 },
            accel: Twist2 { v: self.a, omega: 0.0 },
        }
    }
}

/// A law that checks it is given the reference at time `t` (every lane at its own `t`)
/// and drives the reference's twist open loop.
#[derive(Clone, Copy, Debug)]
struct Spy {
    reference: Drifting,
    ticks: u64,
}

impl<L: Lane<Scalar = f64>> Law<L> for Spy {
    fn update(&mut self, t: L, _m: &Measurement<L>, r: &ReferenceState<L>) -> LawOutput<L> {
        let Drifting { x0, y0, v, a } = self.reference;
        // The same operations as Drifting::state_at, in the same order: the same bits.
        let want_x = L::splat(x0) + (L::splat(v) + L::splat(0.5) * L::splat(a) * t) * t;
        assert_eq!(r.pose.x, want_x, "tick {}: reference x at t", self.ticks);
        assert_eq!(r.pose.y, L::splat(y0));
        assert_eq!(r.twist.v, L::splat(v) + L::splat(a) * t, "tick {}: reference speed at t", self.ticks);
        assert_eq!(r.accel.v, L::splat(a));
        self.ticks += 1;
        LawOutput { demand: WheelDemand::Twist(r.twist), errors: ControlErrors::default() }
    }

    fn reset_lanes(&mut self, _lanes: L::Mask) {}
}

const DRIFT: Drifting = Drifting { x0: 0.5, y0: -0.25, v: 0.2, a: 0.01 };

fn wheel_stage<L: Lane<Scalar = f64>>(robot: &Robot<f64>) -> WheelStage<L> {
    let drive = DriveParams::default().validate(robot).unwrap();
    WheelStage::for_lanes(&WheelStageParams::default(), robot.params(), &drive, 1e-3).unwrap()
}

#[test]
fn one_run_gets_the_reference_at_each_tick_and_is_judged_against_it() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    let controller = Controller::new(Spy { reference: DRIFT, ticks: 0 }, wheel_stage(&robot));
    let mut sim = ClosedLoop::new(plant, controller, DRIFT, 1e-3).unwrap().stop_when_settled(true);
    let outcome = sim.run(5_000, 100, |_| {});
    assert_eq!(sim.controller().law().ticks, 5_001, "a tick at t = 0 and after each step");
    // Never stopped as settled: the reference moves.
    assert_eq!(outcome.t_final, 5.0);
    assert_eq!(outcome.goal, DRIFT.pose_at(5.0), "judged against the reference of the last moment");
    let tick = sim.last_tick();
    assert_eq!(tick.reference, DRIFT.state_at(tick.t));
}

#[test]
fn lanes_get_each_lane_s_reference_at_its_own_time() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    let controller = Controller::new(Spy { reference: DRIFT, ticks: 0 }, wheel_stage::<Lanes<4>>(&robot));
    // Runs of 2 s: 6 runs on 4 lanes, so lanes restart at different times and their
    // clocks differ.
    let mut batch = LaneBatch::<4, _, _>::new(plant, controller, DRIFT, 1e-3, 2_000, true).unwrap();
    let starts = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5];
    let mut next = starts.iter().enumerate().map(|(i, &y)| (i as u64, Pose2::new(0.0, y, 0.0)));
    let mut outcomes = Vec::new();
    batch.run_all(|| next.next(), |tag, o| outcomes.push((tag, o)));
    assert_eq!(outcomes.len(), 6);
    for (tag, o) in outcomes {
        assert_eq!(o.t_final, 2.0, "run {tag} ran its full length (no settling on a moving reference)");
        assert_eq!(o.goal, DRIFT.pose_at(2.0), "run {tag} judged against the reference at its own end");
    }
}

/// The polar law chasing a drifting goal, one run against the same run in lanes: the
/// same loop, so the same outcome up to the lanes' last-bit differences in sin/cos/atan2.
#[test]
fn a_law_chasing_a_moving_reference_agrees_between_one_run_and_lanes() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let params = ControllerParams::with_law(LawParams::Polar(PolarParams::default()));
    let start = Pose2::new(-0.5, 0.5, 0.3);
    let plant = Plant::new(robot, drive, start).unwrap();
    let one = params.build(robot.params(), &drive).unwrap();
    let mut sim = ClosedLoop::new(plant, one, DRIFT, 1e-3).unwrap();
    let exact = sim.run(10_000, 1000, |_| {});

    // The polar law itself in lanes, not `params.build_lanes` (every law behind one enum
    // is several times this test's build time); the same law and wheel stage.
    let lanes = Controller::new(PolarLaw::for_lanes(PolarParams::default()).unwrap(), wheel_stage::<Lanes<4>>(&robot));
    let mut batch = LaneBatch::<4, _, _>::new(plant, lanes, DRIFT, 1e-3, 10_000, false).unwrap();
    let mut given = Some((0, start));
    let mut fast = None;
    batch.run_all(|| given.take(), |_, o| fast = Some(o));
    let fast = fast.unwrap();
    assert_eq!(fast.goal, exact.goal);
    let d = (fast.final_pose.x - exact.final_pose.x).hypot(fast.final_pose.y - exact.final_pose.y);
    assert!(d < 1e-9, "lanes and one run differ by {d} m");
    // A proportional stabilization law chases a moving goal with a lag: v = k_rho rho, so
    // rho -> v_ref / k_rho = 0.3 / 0.5 = 0.6 m at t = 10 s (the reference moved 2.5 m).
    let lag = DRIFT.state_at(10.0).twist.v / 0.5;
    assert!((exact.final_dl - lag).abs() < 0.1 * lag, "final dl {} against the lag {lag}", exact.final_dl);
}
