//! Obstacles and collisions (wmr issue 41) against computations they were not made by:
//! - the signed distance to a polygon against a dense sampling of its boundary and the
//!   winding number (the sum of the angles its edges subtend), not the even-odd rule;
//! - the lanes against one run at a time;
//! - a run driven into a wall ends `collided` at the first plant step whose state an
//!   independent distance puts in contact, and not before.

use wmr_core::lane::{Lane, Lanes};
use wmr_core::obstacle::{MAX_OBSTACLES, Obstacle};
use wmr_core::{
    ClosedLoop, ControllerParams, DriveParams, FixedGoal, LawParams, Obstacles, Plant, Pose2, Robot, Status,
    Termination,
};

/// A concave L-shaped polygon (counter-clockwise).
const ELL: [(f64, f64); 6] = [(0.0, 0.0), (2.0, 0.0), (2.0, 0.5), (0.5, 0.5), (0.5, 2.0), (0.0, 2.0)];

/// The distance from p to the polygon's boundary by sampling it every 0.1 mm, and the
/// winding number of the boundary about p.
fn brute(points: &[(f64, f64)], p: (f64, f64)) -> (f64, bool) {
    let mut best = f64::INFINITY;
    let mut angle = 0.0;
    for i in 0..points.len() {
        let a = points[i];
        let b = points[(i + 1) % points.len()];
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let n = (len / 1e-4).ceil() as usize;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            let q = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            best = best.min((q.0 - p.0).hypot(q.1 - p.1));
        }
        let (ua, ub) = ((a.0 - p.0, a.1 - p.1), (b.0 - p.0, b.1 - p.1));
        angle += (ua.0 * ub.1 - ua.1 * ub.0).atan2(ua.0 * ub.0 + ua.1 * ub.1);
    }
    (best, (angle / std::f64::consts::TAU).round() != 0.0)
}

#[test]
fn the_signed_distance_is_the_sampled_boundarys_with_the_winding_numbers_sign() {
    let ob = Obstacle::Polygon(&ELL);
    let mut checked = 0;
    for i in 0..=26 {
        for j in 0..=26 {
            // A grid around the L, off its vertices' coordinates.
            let p = (-0.6 + 0.1037 * f64::from(i), -0.6 + 0.1029 * f64::from(j));
            let got = Obstacles::<f64>::distance_to(&ob, p.0, p.1);
            let (dist, inside) = brute(&ELL, p);
            let want = if inside { -dist } else { dist };
            assert!((got - want).abs() < 1e-4, "at {p:?}: {got} against {want}");
            checked += usize::from(inside);
        }
    }
    assert!(checked > 20, "only {checked} points inside");
    let circle = Obstacle::Circle { center: (1.0, -2.0), radius: 0.3 };
    let d = Obstacles::<f64>::distance_to(&circle, 1.0 + 0.6, -2.0 - 0.8);
    assert!((d - 0.7).abs() < 1e-15, "{d}");
}

#[test]
fn the_lanes_agree_with_one_run_at_a_time() {
    let obstacles =
        Obstacles::new(&[Obstacle::Polygon(&ELL), Obstacle::Circle { center: (3.0, 1.0), radius: 0.4 }], 0.15).unwrap();
    let xs = [-0.5, 0.25, 1.0, 2.6, 3.2, 0.4, 1.9, 5.0];
    let ys = [0.3, 0.25, 1.0, 1.0, 1.1, 1.7, 0.45, -3.0];
    let lanes = obstacles.clearance(Lanes(xs), Lanes(ys));
    for i in 0..8 {
        let one = obstacles.clearance(xs[i], ys[i]);
        assert!((lanes.lane(i) - one).abs() < 1e-12, "lane {i}: {} against {one}", lanes.lane(i));
    }
    assert_eq!(obstacles.nearest(3.0, 1.5).map(|(i, _)| i), Some(0), "circles come first");
    assert_eq!(Obstacles::<f64>::default().clearance(0.0, 0.0), f64::INFINITY);
}

#[test]
fn bad_obstacles_are_refused_naming_the_key() {
    let bad = [
        (vec![Obstacle::Circle { center: (f64::NAN, 0.0), radius: 1.0 }], 0.1, "obstacle.center"),
        (vec![Obstacle::Circle { center: (0.0, 0.0), radius: 0.0 }], 0.1, "obstacle.radius"),
        (vec![Obstacle::Polygon(&[(0.0, 0.0), (1.0, 0.0)])], 0.1, "obstacle.points"),
        (vec![Obstacle::Polygon(&[(0.0, 0.0), (1.0, f64::INFINITY), (0.0, 1.0)])], 0.1, "obstacle.points"),
        (vec![], -0.1, "footprint_radius"),
        (vec![Obstacle::Circle { center: (0.0, 0.0), radius: 1.0 }; MAX_OBSTACLES + 1], 0.1, "obstacle"),
    ];
    for (list, footprint, key) in bad {
        let e = Obstacles::new(&list, footprint).unwrap_err();
        assert_eq!(e.field, key, "{e}");
    }
}

/// The paper's robot sent to a goal beyond a wall: the run ends collided, at the first
/// plant step whose state is in contact by the brute-force distance.
#[test]
fn a_run_into_a_wall_ends_collided_at_the_contact() {
    let wall = [(0.6, -1.0), (0.7, -1.0), (0.7, 1.0), (0.6, 1.0)];
    let footprint = 0.12;
    let obstacles = Obstacles::new(&[Obstacle::Polygon(&wall)], footprint).unwrap();
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::new(0.0, 0.0, 0.0)).unwrap();
    let controller =
        ControllerParams::with_law(LawParams::Polar(Default::default())).build(robot.params(), &drive).unwrap();
    let goal = FixedGoal::new(Pose2::new(1.5, 0.0, 0.0)).unwrap();
    let mut lp = ClosedLoop::new(plant, controller, goal, 1e-3).unwrap().with_obstacles(obstacles);
    let mut clearances = Vec::new();
    let outcome = lp.run(20_000, 1, |s| clearances.push((s.t, brute(&wall, (s.state.x, s.state.y)).0 - footprint)));
    assert_eq!(outcome.termination, Termination::Collided);
    assert_eq!(outcome.status(), Status::Collided);
    let first_contact = clearances.iter().position(|&(_, c)| c <= 1e-4).expect("a contact");
    assert_eq!(first_contact, clearances.len() - 1, "the run went on after the contact");
    assert!(clearances[first_contact - 1].1 > -1e-4, "the step before was already in contact");
    assert!((outcome.t_final - clearances[first_contact].0).abs() < 1e-12);
    // Without the wall, the same run arrives.
    let plant = Plant::new(robot, drive, Pose2::new(0.0, 0.0, 0.0)).unwrap();
    let controller =
        ControllerParams::with_law(LawParams::Polar(Default::default())).build(robot.params(), &drive).unwrap();
    let mut free = ClosedLoop::new(plant, controller, goal, 1e-3).unwrap();
    assert_ne!(free.run(20_000, 0, |_| {}).termination, Termination::Collided);
}
