//! The path searches of path following (wmr issue 23, pure pursuit's cost): the cursor's
//! incremental search from the last closest point against the brute-force windowed scan
//! ([`closest`]), and a count of path evaluations per tick, in f32 and f64.

use std::cell::Cell;

use wmr_core::Pose2;
use wmr_core::Real;
use wmr_core::reference::path::{PathCursor, closest};
use wmr_core::reference::{Circle, FigureEight, Path, Waypoints};

/// A path that counts its evaluations.
struct Counting<'a, T: Real> {
    inner: &'a dyn Path<T>,
    calls: Cell<u64>,
}

impl<T: Real> Path<T> for Counting<'_, T> {
    fn pose_on_path(&self, s: T) -> Pose2<T> {
        self.calls.set(self.calls.get() + 1);
        self.inner.pose_on_path(s)
    }
    fn point_on_path(&self, s: T) -> (T, T) {
        self.calls.set(self.calls.get() + 1);
        self.inner.point_on_path(s)
    }
    fn end(&self) -> Option<T> {
        self.inner.end()
    }
    fn rate_bounds(&self) -> (T, T) {
        self.inner.rate_bounds()
    }
    fn remaining_length(&self, s: T) -> T {
        self.inner.remaining_length(s)
    }
}

/// The paths of the examples: a 1 m circle, the default figure-eight, five waypoints.
fn paths<T: Real>() -> Vec<(&'static str, Box<dyn Path<T>>)> {
    let l = |v: f64| T::lit(v);
    let pts = [[0.0, 0.0], [1.0, 0.0], [1.5, 0.8], [0.5, 1.5], [-0.5, 1.0]].map(|[x, y]| [l(x), l(y)]);
    vec![
        ("circle", Box::new(Circle::new(l(0.0), l(0.0), l(1.0), l(0.3), l(-core::f64::consts::FRAC_PI_2)).unwrap())),
        ("figure_eight", Box::new(FigureEight::new(l(0.0), l(0.0), l(2.0), l(1.0), l(30.0)).unwrap())),
        ("waypoints", Box::new(Waypoints::new(&pts, l(0.3), l(0.5)).unwrap())),
    ]
}

/// A robot weaving along `path`: at tick k the point at parameter s_k (advancing by a
/// rate-bounded step) moved `lateral` m along the path's normal, lateral = `amplitude_m`
/// x a slow sine. Yields (x, y) per tick.
fn weave<T: Real>(path: &dyn Path<T>, ticks: usize, amplitude_m: f64) -> Vec<(T, T)> {
    let (_, rate_max) = path.rate_bounds();
    let end = path.end().unwrap_or(T::lit(1e9));
    let ds = T::lit(0.003) / rate_max; // 3 mm of path per tick: 0.3 m/s at 100 Hz
    (0..ticks)
        .map(|k| {
            let s = (ds * T::lit(k as f64)).min(end);
            let p = path.pose_on_path(s);
            let e = T::lit(amplitude_m) * (T::lit(k as f64) * T::lit(0.01)).sin_cos_libm().0;
            let (sn, c) = p.theta.sin_cos_libm();
            (p.x - sn * e, p.y + c * e)
        })
        .collect()
}

fn incremental_matches_brute_force<T: Real>(tol_m: f64) {
    let window = T::lit(0.9); // m: pure pursuit's max_lookahead_dist
    let ds = T::lit(0.06); // m: its search step
    // 0.1 m: near the path; 0.4 m: beyond the figure-eight's radius of curvature at its
    // lobes (0.33 m), where the distance along the window has several minima (a search
    // that always stopped at its first minimum stuck behind the robot there).
    for (name, path, amplitude) in
        [0.1, 0.4].into_iter().flat_map(|a| paths::<T>().into_iter().map(move |(n, p)| (n, p, a)))
    {
        let path = path.as_ref();
        let (rate_min, _) = path.rate_bounds();
        let mut cursor = PathCursor::<T>::default();
        let mut brute_from = T::zero();
        for (k, (x, y)) in weave(path, 4000, amplitude).into_iter().enumerate() {
            let s_inc = cursor.advance(path, x, y, window, ds);
            // The brute force: the whole window scanned, from the same last point.
            let s_brute = closest(path, x, y, brute_from, window / rate_min, ds);
            brute_from = s_brute;
            let d = |s: T| {
                let (px, py) = path.point_on_path(s);
                (px - x).hypot_libm(py - y).to_f64().unwrap()
            };
            assert!(
                (d(s_inc) - d(s_brute)).abs() <= tol_m,
                "{name} (weave {amplitude} m) tick {k}: incremental {} m at s = {:?}, brute force {} m at s = {:?}",
                d(s_inc),
                s_inc,
                d(s_brute),
                s_brute
            );
        }
    }
}

#[test]
fn the_incremental_search_finds_the_brute_force_closest_point_f64() {
    incremental_matches_brute_force::<f64>(1e-9);
}

#[test]
fn the_incremental_search_finds_the_brute_force_closest_point_f32() {
    incremental_matches_brute_force::<f32>(2e-5);
}

/// Path evaluations per tick of the cursor after its first search, for pure pursuit's
/// window (0.9 m, 6 cm steps): the old full-window scan with two evaluations per golden
/// step took 66 on the circle and 86 on the figure-eight; the incremental search a few
/// steps plus 25 for the refinement.
fn evaluations_per_tick<T: Real>() {
    for (name, path) in paths::<T>() {
        let counting = Counting { inner: path.as_ref(), calls: Cell::new(0) };
        let mut cursor = PathCursor::<T>::default();
        let ticks = weave(path.as_ref(), 2001, 0.1);
        cursor.advance(&counting, ticks[0].0, ticks[0].1, T::lit(0.9), T::lit(0.06));
        counting.calls.set(0);
        for &(x, y) in &ticks[1..] {
            cursor.advance(&counting, x, y, T::lit(0.9), T::lit(0.06));
        }
        let per_tick = counting.calls.get() as f64 / 2000.0;
        assert!(per_tick <= 32.0, "{name}: {per_tick} path evaluations per tick");
    }
}

#[test]
fn a_tick_evaluates_the_path_a_few_times_f64() {
    evaluations_per_tick::<f64>();
}

#[test]
fn a_tick_evaluates_the_path_a_few_times_f32() {
    evaluations_per_tick::<f32>();
}

#[test]
fn point_on_path_is_the_poses_position() {
    for (name, path) in paths::<f64>() {
        for k in 0..500 {
            let s = 0.037 * f64::from(k);
            let p = path.pose_on_path(s);
            assert_eq!(path.point_on_path(s), (p.x, p.y), "{name} at s = {s}");
        }
    }
}
