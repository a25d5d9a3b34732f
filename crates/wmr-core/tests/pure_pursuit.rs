//! Regulated pure pursuit against nav2 (wmr issue 38, items 3 and 4): the closest-point
//! search starts at the path's beginning and stays within `max_robot_pose_search_dist`
//! (a patrol route that ends near its start is driven, a figure-eight is joined on its
//! first branch), and the law's twist equals a port of nav2's own functions
//! (`regulated_pure_pursuit_controller.cpp`, `regulation_functions.hpp`, Jazzy), written
//! here from the C++ with its own path searches.

use wmr_core::reference::{FigureEight, Path, Waypoints};
use wmr_core::{
    AnyReference, ClosedLoop, ControllerParams, DriveParams, Law, LawParams, Measurement, Plant, Pose2, PurePursuitLaw,
    PurePursuitParams, Real, ReferenceState, Robot, Wheels,
};

/// The patrol route of issue 38: a 2 m x 1.5 m rectangle through five points (about
/// 7 m of spline) that ends 8 cm short of its start.
const PATROL: [[f64; 2]; 5] = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.5], [0.0, 1.5], [0.0, 0.08]];

/// Drives the patrol route from 5 cm beside its first point (3 cm from its end): returns
/// the length of C's path over 40 s (m) and the final distance to the route's end (m).
fn patrol<T: Real>() -> (f64, f64) {
    let route = Waypoints::<T>::new(&PATROL.map(|p| p.map(T::lit)), T::lit(0.3), T::lit(0.5)).unwrap();
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::new(T::zero(), T::lit(0.05), T::zero())).unwrap();
    let law = LawParams::PurePursuit(PurePursuitParams::<T>::default());
    let controller = ControllerParams::with_law(law).build(robot.params(), &drive).unwrap();
    let mut lp = ClosedLoop::new(plant, controller, AnyReference::Waypoints(route), T::lit(1e-3)).unwrap();
    let mut length = 0.0f64;
    let mut last = (0.0f64, 0.05f64);
    lp.run(40_000, 10, |s| {
        let p = (s.state.x.to_f64_lossless(), s.state.y.to_f64_lossless());
        length += (p.0 - last.0).hypot(p.1 - last.1);
        last = p;
    });
    (length, (last.0 - PATROL[4][0]).hypot(last.1 - PATROL[4][1]))
}

#[test]
fn a_patrol_route_that_ends_near_its_start_is_driven_f64() {
    // Before: the first search covered the whole route and took its end, 3 cm away: the
    // robot drove 6.7 cm and stopped, the run `converged`.
    let (length, to_end) = patrol::<f64>();
    assert!(length > 6.0, "C's path: {length} m (the route is about 7 m)");
    assert!(to_end < 0.05, "ends {to_end} m from the route's end");
}

#[test]
fn a_patrol_route_that_ends_near_its_start_is_driven_f32() {
    let (length, to_end) = patrol::<f32>();
    assert!(length > 6.0, "C's path: {length} m (the route is about 7 m)");
    assert!(to_end < 0.05, "ends {to_end} m from the route's end");
}

/// The figure-eight (2 m x 1 m, 30 s) crosses itself at its centre: at t = 0 heading
/// 45 deg (towards the lobe at x > 0), at t = 15 s heading 135 deg (towards x < 0). A
/// robot 3 cm from the centre along the second branch, heading along the first, is nearer
/// the second branch; nav2's search from the plan's beginning (1.5 m of path) finds the
/// first. Returns C's x after 4 s, m.
fn figure_eight_x_after_4_s<T: Real>() -> f64 {
    let eight = FigureEight::new(T::zero(), T::zero(), T::lit(2.0), T::lit(1.0), T::lit(30.0)).unwrap();
    let (s, c) = 135f64.to_radians().sin_cos();
    let start = Pose2::new(T::lit(0.03 * c), T::lit(0.03 * s), T::lit(45f64.to_radians()));
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, start).unwrap();
    let law = LawParams::PurePursuit(PurePursuitParams::<T>::default());
    let controller = ControllerParams::with_law(law).build(robot.params(), &drive).unwrap();
    let mut lp = ClosedLoop::new(plant, controller, AnyReference::<T>::FigureEight(eight), T::lit(1e-3)).unwrap();
    lp.run(4_000, 1000, |_| {});
    lp.state().x.to_f64_lossless()
}

#[test]
fn a_figure_eight_is_joined_on_its_first_branch() {
    // Before: the first search covered the whole lap and took the second branch (x < 0).
    for x in [figure_eight_x_after_4_s::<f64>(), figure_eight_x_after_4_s::<f32>()] {
        assert!(x > 0.5, "C at x = {x} m after 4 s: the first branch runs to x > 0");
    }
    // The law's own cursor, one tick: on the first branch; the whole lap scanned (the old
    // first search) finds the second.
    let eight = FigureEight::new(0.0, 0.0, 2.0, 1.0, 30.0).unwrap();
    let (s, c) = 135f64.to_radians().sin_cos();
    let pose = Pose2::new(0.03 * c, 0.03 * s, 45f64.to_radians());
    let mut law =
        PurePursuitLaw::<f64>::for_lanes(PurePursuitParams::default(), Robot::paper().params(), 0.01).unwrap();
    let m = Measurement { t: 0.0, pose, ..Default::default() };
    law.update_on_path(0.0, &m, &ReferenceState::default(), &eight);
    let t = law.cursor();
    assert!(t < 1.0, "the closest point found at t = {t} s of the figure (the second branch is at 15 s)");
    let lap = wmr_core::reference::path::closest(&eight, pose.x, pose.y, 0.0, 30.0, 0.06);
    assert!((lap - 15.0).abs() < 1.0, "the whole lap's closest point: t = {lap} s");
}

/// nav2's functions, ported from the C++ (Jazzy) as written there.
mod nav2 {
    /// `calculateCurvature`.
    pub fn calculate_curvature(x: f64, y: f64) -> f64 {
        let carrot_dist2 = x * x + y * y;
        if carrot_dist2 > 0.001 { 2.0 * y / carrot_dist2 } else { 0.0 }
    }

    /// `heuristics::curvatureConstraint`.
    pub fn curvature_constraint(raw_linear_vel: f64, curvature: f64, min_radius: f64) -> f64 {
        let radius = (1.0 / curvature).abs();
        if radius < min_radius {
            raw_linear_vel * (1.0 - ((radius - min_radius).abs() / min_radius))
        } else {
            raw_linear_vel
        }
    }

    /// `heuristics::approachVelocityScalingFactor`: the remaining path length and the
    /// path's last point in the robot frame.
    pub fn approach_velocity_scaling_factor(remaining: f64, last: (f64, f64), dist: f64) -> f64 {
        if remaining < dist { last.0.hypot(last.1) / dist } else { 1.0 }
    }

    /// `heuristics::approachVelocityConstraint`.
    pub fn approach_velocity_constraint(v: f64, factor: f64, min_approach_velocity: f64) -> f64 {
        let mut approach_vel = v * factor;
        if approach_vel < min_approach_velocity {
            approach_vel = min_approach_velocity;
        }
        v.min(approach_vel)
    }

    /// `rotateToHeading`: (linear, angular).
    pub fn rotate_to_heading(angle: f64, omega_now: f64, vel: f64, accel: f64, dt: f64) -> (f64, f64) {
        let sign = if angle > 0.0 { 1.0 } else { -1.0 };
        let mut angular = sign * vel;
        angular = angular.clamp(omega_now - accel * dt, omega_now + accel * dt);
        let max_vel_to_stop = (2.0 * accel * angle.abs()).sqrt();
        if angular.abs() > max_vel_to_stop {
            angular = sign * max_vel_to_stop;
        }
        (0.0, angular)
    }
}

/// The test's own searches on a path: a dense scan (1e-4 of s) refined by bisection.
fn dense_closest(path: &dyn Path<f64>, x: f64, y: f64, end: f64) -> f64 {
    let d = |s: f64| {
        let (px, py) = path.point_on_path(s);
        (px - x).hypot(py - y)
    };
    let n = (end / 1e-4) as usize;
    let mut best = 0.0;
    for k in 0..=n {
        let s = (k as f64 * 1e-4).min(end);
        if d(s) < d(best) {
            best = s;
        }
    }
    // Ternary search in the bracket either side.
    let (mut a, mut b) = ((best - 1e-4).max(0.0), (best + 1e-4).min(end));
    for _ in 0..100 {
        let (c, e) = (a + (b - a) / 3.0, b - (b - a) / 3.0);
        if d(c) < d(e) { b = e } else { a = c }
    }
    (a + b) / 2.0
}

fn dense_carrot(path: &dyn Path<f64>, x: f64, y: f64, from: f64, l: f64, end: f64) -> f64 {
    let d = |s: f64| {
        let (px, py) = path.point_on_path(s);
        (px - x).hypot(py - y)
    };
    if d(from) >= l {
        return from;
    }
    let mut s = from;
    while s < end {
        let next = (s + 1e-4).min(end);
        if d(next) >= l {
            let (mut lo, mut hi) = (s, next);
            for _ in 0..60 {
                let mid = (lo + hi) / 2.0;
                if d(mid) >= l { hi = mid } else { lo = mid }
            }
            return hi;
        }
        s = next;
    }
    end
}

/// The path length from `s` to `end`, m, as a dense polyline.
fn dense_remaining(path: &dyn Path<f64>, s: f64, end: f64) -> f64 {
    let n = ((end - s) / 1e-4).ceil().max(1.0) as usize;
    let mut length = 0.0;
    let mut p = path.point_on_path(s);
    for k in 1..=n {
        let q = path.point_on_path(s + (end - s) * k as f64 / n as f64);
        length += (q.0 - p.0).hypot(q.1 - p.1);
        p = q;
    }
    length
}

fn in_robot_frame(pose: &Pose2<f64>, p: (f64, f64)) -> (f64, f64) {
    let (s, c) = pose.theta.sin_cos();
    let (dx, dy) = (p.0 - pose.x, p.1 - pose.y);
    (c * dx + s * dy, -s * dx + c * dy)
}

/// Walks along a waypoints path (beside it, at varied headings and speeds) and compares
/// the law's twist at each tick with nav2's functions applied to the test's own closest
/// point, lookahead point and remaining length. Ticks within a hair of a switch (the
/// approach distance, the rotation angle, the small carrot, the goal tolerance) are
/// skipped: there the two searches' last digits could pick different branches.
fn matches_nav2(p: PurePursuitParams<f64>) -> (usize, usize, usize) {
    let path = Waypoints::new(&[[0.0, 0.0], [1.0, 0.0], [1.5, 0.8], [0.5, 1.5]], 0.3, 0.5).unwrap();
    let end = path.end().unwrap();
    let robot = Robot::<f64>::paper();
    let (r, big_r) = (robot.params().wheel_radius, robot.params().half_track);
    let dt = 0.01;
    let mut law = PurePursuitLaw::<f64>::for_lanes(p, robot.params(), dt).unwrap();
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut compared, mut rotating, mut approaching) = (0, 0, 0);
    let n = 600;
    for k in 0..=n {
        // From the start to 5 mm short of the end, 4 cm either side, headings within 1.4 rad.
        let s = (end - 0.01) * k as f64 / n as f64;
        let on = path.pose_on_path(s);
        let off = 0.04 * (2.0 * rnd() - 1.0);
        let pose =
            Pose2::new(on.x - on.theta.sin() * off, on.y + on.theta.cos() * off, on.theta + 1.4 * (2.0 * rnd() - 1.0));
        let (v_now, w_now) = (0.4 * rnd(), 2.0 * rnd() - 1.0);
        let wheels = Wheels::new((v_now + big_r * w_now) / r, (v_now - big_r * w_now) / r);
        let m = Measurement { t: 0.0, pose, wheel_speeds: wheels, ..Default::default() };
        let out = law.update_on_path(0.0, &m, &ReferenceState::default(), &path);
        let wmr_core::WheelDemand::Twist(got) = out.demand else { panic!("pure pursuit demands a twist") };

        // nav2, step by step (computeVelocityCommands).
        let s_c = dense_closest(&path, pose.x, pose.y, end);
        let v_meas = r * (wheels.right + wheels.left) / 2.0;
        let l = if p.use_velocity_scaled_lookahead_dist {
            (v_meas.abs() * p.lookahead_time).clamp(p.min_lookahead_dist, p.max_lookahead_dist)
        } else {
            p.lookahead_dist
        };
        let carrot = in_robot_frame(&pose, path.point_on_path(dense_carrot(&path, pose.x, pose.y, s_c, l, end)));
        let last = in_robot_frame(&pose, path.point_on_path(end));
        let remaining = dense_remaining(&path, s_c, end);
        let angle = carrot.1.atan2(carrot.0);
        let d2 = carrot.0 * carrot.0 + carrot.1 * carrot.1;
        let near_switch = (remaining - p.approach_velocity_scaling_dist).abs() < 1e-3
            || (angle.abs() - p.rotate_to_heading_min_angle).abs() < 1e-4
            || (d2 - 0.001).abs() < 1e-5
            || (last.0.hypot(last.1) - p.xy_goal_tolerance).abs() < 1e-4;
        if near_switch {
            continue;
        }
        let curvature = nav2::calculate_curvature(carrot.0, carrot.1);
        let w_meas = r * (wheels.right - wheels.left) / (2.0 * big_r);
        let (mut v, mut w) = if p.use_rotate_to_heading && angle.abs() > p.rotate_to_heading_min_angle {
            rotating += 1;
            nav2::rotate_to_heading(angle, w_meas, p.rotate_to_heading_angular_vel, p.max_angular_accel, dt)
        } else {
            let curvature_vel = nav2::curvature_constraint(p.speed, curvature, p.regulated_linear_scaling_min_radius);
            let mut v = curvature_vel.max(p.regulated_linear_scaling_min_speed);
            let factor = nav2::approach_velocity_scaling_factor(remaining, last, p.approach_velocity_scaling_dist);
            if factor < 1.0 {
                approaching += 1;
            }
            v = nav2::approach_velocity_constraint(v, factor, p.min_approach_linear_velocity);
            v = v.abs().clamp(0.0, p.speed);
            (v, v * curvature)
        };
        // wmr's stop at the end (nav2's goal checker's place; docs/model.md).
        if last.0.hypot(last.1) < p.xy_goal_tolerance && remaining < p.approach_velocity_scaling_dist {
            (v, w) = (0.0, 0.0);
        }
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 + 1e-5 * b.abs();
        assert!(
            close(got.v, v) && close(got.omega, w),
            "tick {k} (s = {s:.4}): wmr (v {}, omega {}), nav2 (v {v}, omega {w}); carrot {carrot:?}, remaining {remaining}",
            got.v,
            got.omega
        );
        compared += 1;
    }
    (compared, rotating, approaching)
}

#[test]
fn the_twist_is_nav2s_with_its_defaults() {
    let (compared, rotating, approaching) = matches_nav2(PurePursuitParams::default());
    eprintln!("{compared} ticks, {rotating} rotating, {approaching} approaching");
    assert!(
        compared > 500 && rotating > 20 && approaching > 20,
        "{compared} ticks, {rotating} rotating, {approaching} approaching"
    );
}

#[test]
fn the_twist_is_nav2s_with_a_velocity_scaled_lookahead_and_no_rotation() {
    let p = PurePursuitParams {
        use_velocity_scaled_lookahead_dist: true,
        use_rotate_to_heading: false,
        ..Default::default()
    };
    let (compared, rotating, approaching) = matches_nav2(p);
    assert!(compared > 500 && rotating == 0 && approaching > 20, "{compared} ticks, {approaching} approaching");
}

/// Issue 38 item 4: on a path that ends in a tight turn, nav2 slows to v_c |p_end| / d
/// (v_c the curvature-regulated speed, |p_end| the straight distance to the end); wmr
/// used speed * remaining_arc / d, up to 62 % faster. One tick, robot on the path 0.3 m
/// of arc before the end of a quarter circle of radius 0.25 m.
#[test]
fn the_approach_slow_down_uses_the_curvature_regulated_speed_and_the_straight_distance() {
    // A quarter circle of radius 0.25 m after a 1 m straight, as waypoints (dense, so the spline is the arc).
    let mut pts = vec![[-1.0, 0.0], [-0.5, 0.0]];
    for k in 0..=12 {
        let a = core::f64::consts::FRAC_PI_2 * k as f64 / 12.0;
        pts.push([0.25 * a.sin(), 0.25 - 0.25 * a.cos()]);
    }
    let path = Waypoints::new(&pts, 0.3, 0.5).unwrap();
    let end = path.end().unwrap();
    let p = PurePursuitParams { use_rotate_to_heading: false, ..Default::default() };
    let robot = Robot::<f64>::paper();
    let mut law = PurePursuitLaw::<f64>::for_lanes(p, robot.params(), 0.01).unwrap();
    // Walk the cursor along, then the tick 0.3 m of path before the end.
    let mut last = None;
    for k in 0..=100 {
        let s = (end - 0.3) * k as f64 / 100.0;
        let pose = path.pose_on_path(s);
        let m = Measurement { t: 0.0, pose, ..Default::default() };
        last = Some((law.update_on_path(0.0, &m, &ReferenceState::default(), &path), pose));
    }
    let (out, pose) = last.unwrap();
    let wmr_core::WheelDemand::Twist(got) = out.demand else { panic!() };
    let s_c = dense_closest(&path, pose.x, pose.y, end);
    let carrot = in_robot_frame(&pose, path.point_on_path(dense_carrot(&path, pose.x, pose.y, s_c, 0.6, end)));
    let last_pt = in_robot_frame(&pose, path.point_on_path(end));
    let remaining = dense_remaining(&path, s_c, end);
    let kappa = nav2::calculate_curvature(carrot.0, carrot.1);
    let v_c = nav2::curvature_constraint(0.3, kappa, 0.9).max(0.25);
    let factor = nav2::approach_velocity_scaling_factor(remaining, last_pt, 0.6);
    let want = nav2::approach_velocity_constraint(v_c, factor, 0.05).clamp(0.0, 0.3);
    // The old rule, for the record: speed * remaining / d, not below 0.05, not above v_c.
    let old = v_c.min((0.3 * remaining / 0.6).max(0.05));
    assert!(factor < 1.0 && (old - want).abs() > 0.01, "the two rules differ here: old {old}, nav2 {want}");
    eprintln!("old {old}, nav2 {want}, wmr {}", got.v);
    assert!((got.v - want).abs() < 1e-6, "wmr {} m/s, nav2 {want} m/s (the old rule: {old} m/s)", got.v);
}

/// Pure pursuit has nothing to follow without the reference's path, and its
/// `Law::update` (no path) is a zero twist: the lanes, which carry no path, refuse it on
/// any reference (before: they ran it, the robots stood still, and the runs were judged).
#[test]
fn pure_pursuit_in_lanes_is_refused() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    let params = wmr_core::ControllerParams::with_law(LawParams::PurePursuit(PurePursuitParams::default()));
    let eight: AnyReference<f64> = AnyReference::FigureEight(FigureEight::new(0.0, 0.0, 2.0, 1.0, 30.0).unwrap());
    let lanes = params.build_lanes::<wmr_core::lane::Lanes<4>>(robot.params(), &drive).unwrap();
    let Err(e) = wmr_core::batch::LaneBatch::<4, _, _>::new(plant, lanes, eight, 1e-3, 100, false) else {
        panic!("the lanes ran pure pursuit, which they carry no path for");
    };
    assert_eq!(e.field, "kind");
    assert!(e.to_string().contains("path"), "{e}");
}

/// MPPI follows the reference's path when it has one: the lanes, which would hand it the
/// reference's pose as a goal instead, refuse it there, and run it on a goal at rest.
#[test]
fn mppi_in_lanes_is_refused_on_a_reference_with_a_path() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    let mppi = wmr_core::MppiParams { batch_size: 8, time_steps: 4, ..Default::default() };
    let params = wmr_core::ControllerParams::with_law(LawParams::Mppi(mppi));
    let eight: AnyReference<f64> = AnyReference::FigureEight(FigureEight::new(0.0, 0.0, 2.0, 1.0, 30.0).unwrap());
    let lanes = params.build_lanes::<wmr_core::lane::Lanes<4>>(robot.params(), &drive).unwrap();
    let Err(e) = wmr_core::batch::LaneBatch::<4, _, _>::new(plant, lanes, eight, 1e-3, 100, false) else {
        panic!("the lanes ran MPPI on a reference with a path, which they do not carry");
    };
    assert_eq!(e.field, "kind");
    let goal: AnyReference<f64> = AnyReference::Goal(wmr_core::FixedGoal::new(Pose2::new(1.0, 1.0, 0.0)).unwrap());
    let lanes = params.build_lanes::<wmr_core::lane::Lanes<4>>(robot.params(), &drive).unwrap();
    assert!(wmr_core::batch::LaneBatch::<4, _, _>::new(plant, lanes, goal, 1e-3, 100, false).is_ok());
}
