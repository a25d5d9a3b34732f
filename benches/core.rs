//! Criterion benches of the core's hot paths (issue 6), at both precisions where it matters:
//! one closed-loop step, the controller update alone, one RK4 step of the model, and a
//! whole 60 s Fig. 7 run, and one closed-loop step with wheels that roll and that slip
//! (the cost of the slip model), and one MPPI cycle at nav2's defaults on either motion
//! model. `cargo bench --bench core`; the C comparison is `benches/compare`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use wmr_core::integrator::rk4_step;
use wmr_core::{
    ClosedLoop, Controller, DriveParams, FixedGoal, Measurement, PaperLaw, PaperParams, Plant, Pose2, Real,
    ReferenceState, Robot, RobotParams, State, TractionKind, TractionParams, WheelStage, WheelStageParams, Wheels,
    World,
};

/// Fig. 7: (0, 0, 0) -> (1, 1, 120 deg), every default, dt = control_dt = 1 ms.
const FIG7_STEPS: u64 = 60_000;
/// Steps into the run where the per-step benches start: the robot is moving, not holding.
const WARM_STEPS: u64 = 5_000;

/// Fig. 7's goal: (1, 1, 120 deg).
fn fig7_goal<T: Real>() -> Pose2<T> {
    Pose2::new(T::lit(1.0), T::lit(1.0), T::lit(120f64.to_radians()))
}

/// The paper's law and the default wheel stage, composed directly (no `AnyLaw` dispatch).
fn fig7_loop<T: Real>() -> ClosedLoop<T, PaperLaw<T>> {
    fig7_loop_on(TractionKind::Rolling)
}

/// [`fig7_loop`] with wheels that roll or slip (`examples/slip.toml`'s geometry: the
/// caster 0.35 m ahead of C, G 0.1 m high, mu = 0.8).
fn fig7_loop_on<T: Real>(traction: TractionKind) -> ClosedLoop<T, PaperLaw<T>> {
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).expect("default drive is valid");
    let dt = T::lit(1e-3);
    let law = PaperLaw::new(PaperParams::paper(), robot.params(), dt).expect("paper gains are valid");
    let wheels = WheelStage::new(&WheelStageParams::default(), robot.params(), &drive, dt).expect("valid servos");
    let ctrl = Controller::new(law, wheels);
    let keys =
        TractionParams { traction, caster_offset: T::lit(0.35), com_height: T::lit(0.1), ..TractionParams::default() };
    let traction = keys.validate(&robot, &World::flat()).expect("valid traction keys");
    let plant = Plant::new(robot, drive, Pose2::default()).expect("finite start").with_traction(traction);
    ClosedLoop::new(plant, ctrl, FixedGoal::new(fig7_goal()).expect("finite goal"), dt).expect("dt divides control_dt")
}

/// The Fig. 7 loop `WARM_STEPS` into the run.
fn warm_loop<T: Real>() -> ClosedLoop<T, PaperLaw<T>> {
    let mut sim = fig7_loop::<T>();
    for _ in 0..WARM_STEPS {
        sim.step().expect("Fig. 7 does not diverge");
    }
    sim
}

fn closed_loop_step<T: Real>(c: &mut Criterion, name: &str) {
    let start = warm_loop::<T>();
    let mut sim = start.clone();
    c.bench_function(&format!("closed_loop_step/{name}"), |b| {
        b.iter(|| {
            // Stay inside the 60 s run: restart from the snapshot (one copy per 55 000 steps).
            if sim.steps() >= FIG7_STEPS {
                sim = start.clone();
            }
            black_box(sim.step()).ok();
        })
    });
}

/// One controller tick (law + wheel stage) on the measurement of the warm Fig. 7 state.
fn controller_update_at<T: Real>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
) {
    let sim = warm_loop::<T>();
    let s = *sim.state();
    let robot = *sim.plant().robot();
    let t = sim.time();
    let m =
        Measurement { t, pose: s.pose(), wheel_angles: s.wheel_angles(), wheel_speeds: s.wheel_speeds(robot.params()) };
    let r = ReferenceState::at_rest(fig7_goal::<T>());
    let mut ctrl = *sim.controller();
    group.bench_function(BenchmarkId::from_parameter(name), |b| {
        b.iter(|| ctrl.update(black_box(t), black_box(&m), black_box(&r)))
    });
}

fn controller_update(c: &mut Criterion) {
    let mut group = c.benchmark_group("controller_update");
    controller_update_at::<f64>(&mut group, "f64");
    controller_update_at::<f32>(&mut group, "f32");
    group.finish();
}

fn rk4_model<T: Real>(c: &mut Criterion, name: &str) {
    let robot = Robot::<T>::paper();
    let s = *warm_loop::<T>().state();
    let y = s.to_array();
    let tau = Wheels::new(T::lit(0.7), T::lit(-0.3));
    let dt = T::lit(1e-3);
    c.bench_function(&format!("rk4_step_model/{name}"), |b| {
        b.iter(|| {
            rk4_step(
                |_, y| robot.derivative(&State::from_array(*y), black_box(tau)).to_array(),
                T::zero(),
                black_box(&y),
                dt,
            )
        })
    });
}

fn fig7_run(c: &mut Criterion) {
    let mut group = c.benchmark_group("fig7_run_60s");
    group.sample_size(20).measurement_time(Duration::from_secs(4));
    group.bench_function("f64", |b| {
        b.iter(|| {
            fig7_loop::<f64>().run(black_box(FIG7_STEPS), u32::MAX, |s| {
                black_box(s);
            })
        })
    });
    group.bench_function("f32", |b| {
        b.iter(|| {
            fig7_loop::<f32>().run(black_box(FIG7_STEPS), u32::MAX, |s| {
                black_box(s);
            })
        })
    });
    group.finish();
}

/// One closed-loop step of Fig. 7 (f64) with wheels that roll (the paper's model) and that
/// slip: the slip model's cost per step against the rolling one.
fn traction_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("closed_loop_step_traction");
    for (name, kind) in [("rolling", TractionKind::Rolling), ("slip", TractionKind::Slip)] {
        let mut start = fig7_loop_on::<f64>(kind);
        for _ in 0..WARM_STEPS {
            start.step().expect("Fig. 7 does not diverge");
        }
        let mut sim = start.clone();
        group.bench_function(name, |b| {
            b.iter(|| {
                if sim.steps() >= FIG7_STEPS {
                    sim = start.clone();
                }
                black_box(sim.step()).ok();
            })
        });
    }
    group.finish();
}

/// One MPPI planning cycle at nav2's defaults (1000 samples x 56 steps of 0.05 s, one
/// iteration) on the paper's robot with a DC motor, moving at 0.3 m/s and 0.4 rad/s 0.8 m
/// from the goal: `update` with `control_dt` = `model_dt`, so that every call plans.
fn mppi_cycle(c: &mut Criterion) {
    use wmr_core::controller::MotionModel;
    use wmr_core::{DcMotorParams, Law, MppiLaw, MppiParams};
    let mut group = c.benchmark_group("mppi_cycle");
    let robot = RobotParams::<f64>::paper();
    let drive = DriveParams::DcMotor(DcMotorParams::default());
    let wheel_speed_max = WheelStageParams::for_drive(&drive, &robot).wheel_speed_max;
    let (v, omega) = (0.3, 0.4);
    let m = Measurement {
        t: 0.0,
        pose: Pose2::new(0.2, 0.1, 0.3),
        wheel_angles: Wheels::default(),
        wheel_speeds: Wheels {
            right: (v + robot.half_track * omega) / robot.wheel_radius,
            left: (v - robot.half_track * omega) / robot.wheel_radius,
        },
    };
    let r = ReferenceState::at_rest(Pose2::new(1.0, 0.2, 0.2));
    for (name, model) in [("dynamic", MotionModel::Dynamic), ("kinematic", MotionModel::Kinematic)] {
        let p = MppiParams::<f64> { motion_model: model, ..MppiParams::default() };
        let law = MppiLaw::<f64>::for_lanes(p, &robot, &drive, wheel_speed_max, p.model_dt).unwrap();
        group.bench_function(name, |b| {
            let mut law = law;
            b.iter(|| black_box(law.update(0.0, black_box(&m), &r)));
        });
    }
    group.finish();
}

fn per_step(c: &mut Criterion) {
    closed_loop_step::<f64>(c, "f64");
    closed_loop_step::<f32>(c, "f32");
    controller_update(c);
    rk4_model::<f64>(c, "f64");
    rk4_model::<f32>(c, "f32");
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = per_step, traction_step, fig7_run, mppi_cycle
}
criterion_main!(benches);
