//! The start poses of a sweep: a grid, or random starts uniform over the annulus
//! `min_radius <= |C - goal| <= radius` with a uniform heading in [-180, 180) deg
//! (`[-max_heading_deg, max_heading_deg)` when given), drawn from `fastrand`'s generator
//! seeded with `seed` (the same file gives the same starts). Every start lies inside the
//! box a run may not leave. Random starts towards a goal whose footprint would touch an
//! obstacle (`[[world.obstacle]]`) are drawn again ([`random_starts`]); a grid's starts are
//! where the grid says (one on an obstacle ends `collided` at t = 0).
//!
//! In a sweep over references the same tables give offsets from each reference's pose at
//! t = 0 ([`start_from`]): x along the reference's heading, y to its left (m), the heading
//! added (so `random` draws starts around the reference's start, `grid` a grid in its
//! frame).

use wmr_core::plant::DIVERGENCE_BOX_M;
use wmr_core::{Obstacles, Pose2};

use crate::bounds::check_in_box;
use crate::budget::MAX_SWEEP_RUNS;
use crate::error::{ScenarioError, num};
use crate::file::{GridFile, RandomFile};

/// The `grid` or `random` table a sweep's starts were drawn from, defaults filled in.
#[derive(Clone, Debug, PartialEq)]
pub enum StartsSource {
    /// `grid = { ... }`.
    Grid(GridFile),
    /// `random = { ... }`.
    Random(RandomFile),
}

fn finite_key(key: &str, v: f64) -> Result<f64, ScenarioError> {
    if v.is_finite() { Ok(v) } else { Err(ScenarioError::new(key, format!("must be a finite number (got {v})"))) }
}

pub(super) fn grid_starts(g: &GridFile) -> Result<Vec<Pose2<f64>>, ScenarioError> {
    let x_min = finite_key("sweep.grid.x_min", g.x_min)?;
    let x_max = finite_key("sweep.grid.x_max", g.x_max)?;
    let y_min = finite_key("sweep.grid.y_min", g.y_min)?;
    let y_max = finite_key("sweep.grid.y_max", g.y_max)?;
    if g.nx == 0 {
        return Err(ScenarioError::new("sweep.grid.nx", "must be >= 1"));
    }
    if g.ny == 0 {
        return Err(ScenarioError::new("sweep.grid.ny", "must be >= 1"));
    }
    let thetas = g.theta_deg.clone().unwrap_or_else(|| vec![0.0]);
    if thetas.is_empty() {
        return Err(ScenarioError::new("sweep.grid.theta_deg", "give at least one heading"));
    }
    // Counted in u128: nx * ny * headings cannot wrap (each factor is below 2^32 or a
    // length), and nothing is allocated before the count is known to be allowed.
    let total = u128::from(g.nx) * u128::from(g.ny) * thetas.len() as u128;
    if total > MAX_SWEEP_RUNS as u128 {
        return Err(ScenarioError::new(
            "sweep.grid",
            format!(
                "nx x ny x headings = {} x {} x {} = {total} starts, more than the limit of {MAX_SWEEP_RUNS}",
                g.nx,
                g.ny,
                thetas.len()
            ),
        ));
    }
    if x_max < x_min {
        return Err(ScenarioError::new(
            "sweep.grid.x_max",
            format!("must be >= x_min = {} (got {})", num(x_min), num(x_max)),
        ));
    }
    if y_max < y_min {
        return Err(ScenarioError::new(
            "sweep.grid.y_max",
            format!("must be >= y_min = {} (got {})", num(y_min), num(y_max)),
        ));
    }
    // Every start inside the box (so hi - lo below cannot overflow either).
    for (key, v) in [("x_min", x_min), ("x_max", x_max), ("y_min", y_min), ("y_max", y_max)] {
        check_in_box("sweep.grid", Pose2::new(v, 0.0, 0.0))
            .map_err(|e| ScenarioError { key: format!("sweep.grid.{key}"), ..e })?;
    }
    for (i, t) in thetas.iter().enumerate() {
        finite_key(&format!("sweep.grid.theta_deg[{i}]"), *t)?;
    }
    let at = |lo: f64, hi: f64, n: u32, i: u32| {
        if n == 1 { 0.5 * (lo + hi) } else { lo + (hi - lo) * f64::from(i) / f64::from(n - 1) }
    };
    let mut starts = Vec::with_capacity(total as usize);
    for j in 0..g.ny {
        for i in 0..g.nx {
            for t in &thetas {
                starts.push(Pose2::new(at(x_min, x_max, g.nx, i), at(y_min, y_max, g.ny, j), t.to_radians()));
            }
        }
    }
    Ok(starts)
}

/// `r.n` random starts around `goal`, none whose footprint touches one of `obstacles`
/// (such a draw is drawn again, at most [`MAX_REDRAWS_PER_START`] times per start in
/// all), and how many were drawn again. Without obstacles: the draws as they always were.
pub(super) fn random_starts(
    r: &RandomFile,
    goal: Pose2<f64>,
    obstacles: &Obstacles<f64>,
) -> Result<(Vec<Pose2<f64>>, usize), ScenarioError> {
    let radius = finite_key("sweep.random.radius", r.radius)?;
    let min_radius = finite_key("sweep.random.min_radius", r.min_radius)?;
    if radius <= 0.0 {
        return Err(ScenarioError::new("sweep.random.radius", format!("must be > 0 (got {})", num(radius))));
    }
    if !(0.0..=radius).contains(&min_radius) {
        return Err(ScenarioError::new(
            "sweep.random.min_radius",
            format!("must be in [0, radius] (got {})", num(min_radius)),
        ));
    }
    if r.n == 0 || r.n as usize > MAX_SWEEP_RUNS {
        return Err(ScenarioError::new("sweep.random.n", format!("must be in 1..={MAX_SWEEP_RUNS} (got {})", r.n)));
    }
    // Every start inside the box: the circle of `radius` around the goal must be (this
    // also keeps radius^2 below from overflowing).
    let reach = goal.x.abs().max(goal.y.abs()) + radius;
    if reach > DIVERGENCE_BOX_M {
        return Err(ScenarioError::new(
            "sweep.random.radius",
            format!(
                "starts up to {} m from the goal ({}, {}) would lie outside the box a run may not leave \
                 (|x|, |y| <= {DIVERGENCE_BOX_M} m): at most {} m here",
                num(radius),
                num(goal.x),
                num(goal.y),
                num(DIVERGENCE_BOX_M - goal.x.abs().max(goal.y.abs()))
            ),
        ));
    }
    // The heading's half range as a factor of pi; none: the draw as it always was.
    let heading_scale = match r.max_heading_deg {
        None => None,
        Some(h) if h.is_finite() && (0.0..=180.0).contains(&h) => Some(h / 180.0),
        Some(h) => {
            return Err(ScenarioError::new(
                "sweep.random.max_heading_deg",
                format!("must be a number in [0, 180] (got {})", num(h)),
            ));
        }
    };
    let mut rng = fastrand::Rng::with_seed(r.seed);
    let tau = std::f64::consts::TAU;
    let (a2, b2) = (min_radius * min_radius, radius * radius);
    let mut draw = || {
        // Uniform over the annulus: r^2 uniform between the radii squared.
        let rho = (a2 + (b2 - a2) * rng.f64()).sqrt();
        let phi = tau * rng.f64();
        let theta = tau * rng.f64() - std::f64::consts::PI;
        let theta = heading_scale.map_or(theta, |k| theta * k);
        Pose2::new(goal.x + rho * phi.cos(), goal.y + rho * phi.sin(), theta)
    };
    if obstacles.is_empty() {
        return Ok(((0..r.n).map(|_| draw()).collect(), 0));
    }
    // A start whose footprint touches an obstacle (clearance <= 0, where a run would end
    // `collided` at t = 0) is drawn again from the same generator: the same file gives
    // the same starts, and the free ones stay uniform over the free part of the annulus.
    let n = r.n as usize;
    let limit = n.saturating_mul(MAX_REDRAWS_PER_START);
    let mut starts = Vec::with_capacity(n);
    let mut redrawn = 0usize;
    while starts.len() < n {
        let p = draw();
        if obstacles.clearance(p.x, p.y) > 0.0 {
            starts.push(p);
            continue;
        }
        redrawn += 1;
        if redrawn > limit {
            return Err(ScenarioError::new(
                "sweep.random",
                format!(
                    "{redrawn} draws put the robot's footprint (radius {} m) on an obstacle before {n} free starts \
                     were found ({} found): the free part of the annulus {} m <= |C - goal| <= {} m is too small \
                     (under 1 %); widen radius or min_radius, or move the obstacles",
                    num(obstacles.footprint_radius()),
                    starts.len(),
                    num(min_radius),
                    num(radius)
                ),
            ));
        }
    }
    Ok((starts, redrawn))
}

/// Draws a random sweep may take again per start before it gives up
/// ([`random_starts`]): 100, a free area of 1 % of the annulus.
const MAX_REDRAWS_PER_START: usize = 100;

/// The start of a run of a sweep over references: `offset` (x along the heading of the
/// reference's pose at t = 0, y to its left, m; heading added, rad) from `origin`, that pose.
pub(crate) fn start_from(origin: Pose2<f64>, offset: Pose2<f64>) -> Pose2<f64> {
    let (s, c) = origin.theta.sin_cos();
    Pose2::new(
        origin.x + c * offset.x - s * offset.y,
        origin.y + s * offset.x + c * offset.y,
        origin.theta + offset.theta,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_in_the_reference_frame() {
        // A reference heading +y at (1, 2): 1 m ahead is (1, 3), 1 m left is (0, 2).
        let origin = Pose2::new(1.0, 2.0, std::f64::consts::FRAC_PI_2);
        let ahead = start_from(origin, Pose2::new(1.0, 0.0, 0.0));
        let left = start_from(origin, Pose2::new(0.0, 1.0, 0.5));
        assert!((ahead.x - 1.0).abs() < 1e-15 && (ahead.y - 3.0).abs() < 1e-15);
        assert!((left.x - 0.0).abs() < 1e-15 && (left.y - 2.0).abs() < 1e-15);
        assert_eq!(left.theta, std::f64::consts::FRAC_PI_2 + 0.5);
    }

    #[test]
    fn max_heading_bounds_the_draw_and_none_keeps_the_old_draw() {
        let r = RandomFile { n: 500, seed: 3, radius: 1.0, min_radius: 0.0, max_heading_deg: Some(30.0) };
        let all = RandomFile { max_heading_deg: None, ..r.clone() };
        let none = Obstacles::default();
        let (bounded, _) = random_starts(&r, Pose2::default(), &none).unwrap();
        let (free, _) = random_starts(&all, Pose2::default(), &none).unwrap();
        assert!(bounded.iter().all(|p| p.theta.abs() <= 30f64.to_radians() + 1e-12));
        assert!(free.iter().any(|p| p.theta.abs() > 90f64.to_radians()));
        // Same positions; the heading is the old draw scaled by 30/180.
        for (b, f) in bounded.iter().zip(&free) {
            assert_eq!((b.x, b.y), (f.x, f.y));
            assert!((b.theta - f.theta / 6.0).abs() < 1e-15);
        }
        let bad = RandomFile { max_heading_deg: Some(200.0), ..r };
        assert_eq!(random_starts(&bad, Pose2::default(), &none).unwrap_err().key, "sweep.random.max_heading_deg");
    }
}
