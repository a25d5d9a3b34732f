//! Issue 38 item 9: a waypoints path of any length in storage its caller owns
//! ([`Waypoints::new_in`]), no alloc in the core: a recorded path of 2,000 points, in f32
//! and f64; the same bits as the fixed storage for a path that fits both; the errors.

use wmr_core::reference::waypoints::{FIXED_WORDS, MAX_POINTS};
use wmr_core::reference::{Path, Waypoints};
use wmr_core::{AnyReference, Real, Reference};

/// 2,000 poses on three quarters of a circle of radius 2 m, from (2, 0) to (0, -2).
fn recorded<T: Real>() -> Vec<[T; 2]> {
    (0..2000)
        .map(|i| {
            let a = i as f64 * 1.5 * core::f64::consts::PI / 1999.0;
            [T::lit(2.0 * a.cos()), T::lit(2.0 * a.sin())]
        })
        .collect()
}

fn a_path_of_2000_points<T: Real + Into<f64>>(tol: f64) {
    let points = recorded::<T>();
    let words = Waypoints::<T, &mut [T]>::words(points.len());
    assert_eq!(words, 37 * 2000 - 28);
    let mut storage = vec![T::lit(7.0); words];
    let w = Waypoints::new_in(&points, T::lit(0.3), T::lit(0.5), &mut storage[..]).unwrap();
    assert_eq!(w.len(), 2000);
    // The arc is 3 pi m; at 0.3 m/s with |a| <= 0.5 m/s^2, the profile takes
    // 3 pi / 0.3 + 0.3 / (0.9 * 0.5 / sqrt 2) plus what the curvature (0.5 1/m) costs:
    // between 32 s and 33.5 s.
    let d: f64 = w.duration().into();
    assert!((32.0..33.5).contains(&d), "duration {d} s");
    let r = AnyReference::Waypoints(w);
    let end = r.state_at(T::lit(d + 1.0));
    let (x, y): (f64, f64) = (end.pose.x.into(), end.pose.y.into());
    assert!(x.abs() < tol && (y + 2.0).abs() < tol, "end ({x}, {y})");
    // On the circle at every time, at most 0.3 m/s.
    for k in 0..=330 {
        let s = r.state_at(T::lit(k as f64 * 0.1));
        let (x, y, v): (f64, f64, f64) = (s.pose.x.into(), s.pose.y.into(), s.twist.v.into());
        assert!((x.hypot(y) - 2.0).abs() < tol, "t = {} s: radius {}", k as f64 * 0.1, x.hypot(y));
        assert!(v <= 0.3 + tol, "t = {} s: v {v}", k as f64 * 0.1);
    }
    let path = r.path().unwrap();
    let len: f64 = path.remaining_length(T::zero()).into();
    assert!((len - 3.0 * core::f64::consts::PI).abs() < 1e-3 * len, "length {len}");
}

#[test]
fn regression_38_9_a_recorded_path_of_2000_points_f64() {
    a_path_of_2000_points::<f64>(1e-6);
}

#[test]
fn regression_38_9_a_recorded_path_of_2000_points_f32() {
    a_path_of_2000_points::<f32>(1e-3);
}

/// The storage changes nothing: 64 points in the fixed array, a slice and a Vec give
/// the same bits.
#[test]
fn the_storage_changes_no_bit() {
    let points: Vec<[f64; 2]> = recorded::<f64>().into_iter().step_by(31).take(MAX_POINTS).collect();
    assert_eq!(points.len(), 64);
    let fixed = Waypoints::new(&points, 0.3, 0.5).unwrap();
    let mut buf = vec![0.0; FIXED_WORDS];
    let slice = Waypoints::new_in(&points, 0.3, 0.5, &mut buf[..]).unwrap();
    let vec = Waypoints::new_in(&points, 0.3, 0.5, vec![1.0; FIXED_WORDS + 5]).unwrap();
    assert_eq!(fixed.duration().to_bits(), slice.duration().to_bits());
    for k in 0..2000 {
        let t = k as f64 * 0.0123;
        let (a, b, c) = (fixed.state_at(t), slice.state_at(t), vec.state_at(t));
        assert_eq!(a, b, "t = {t}");
        assert_eq!(a, c, "t = {t}");
        let s = k as f64 * 0.003;
        assert_eq!(fixed.pose_on_path(s), slice.pose_on_path(s));
        assert_eq!(fixed.remaining_length(s).to_bits(), vec.remaining_length(s).to_bits());
    }
}

#[test]
fn the_errors_say_what_to_do() {
    let points = recorded::<f64>();
    let e = Waypoints::new(&points[..65], 0.3, 0.5).unwrap_err();
    assert_eq!(e.field, "points");
    let msg = e.to_string();
    assert!(msg.contains("64") && msg.contains("new_in"), "{msg}");
    let mut short = vec![0.0; Waypoints::<f64, &mut [f64]>::words(100) - 1];
    let e = Waypoints::new_in(&points[..100], 0.3, 0.5, &mut short[..]).unwrap_err();
    assert_eq!(e.field, "storage");
    let mut one = [0.0; 64];
    assert_eq!(Waypoints::new_in(&points[..1], 0.3, 0.5, &mut one[..]).unwrap_err().field, "points");
}
