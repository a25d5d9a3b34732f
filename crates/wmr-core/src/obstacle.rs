//! Obstacles (`[[world.obstacle]]`): circles and polygons on the ground, and the robot's
//! footprint, a circle of `footprint_radius` about C (nav2's `robot_radius`).
//!
//! A run whose footprint touches an obstacle ends there, [`crate::Termination::Collided`]
//! ([`crate::ClosedLoop`], [`crate::batch`]); MPPI's `obstacles` critic scores its
//! rollouts by their clearance. Both read [`Obstacles::clearance`]: the distance from the
//! footprint's edge to the nearest obstacle (m, negative when they overlap):
//!
//! ```text
//! circle (c, rho):    |p - c| - rho
//! polygon (q_0..q_n): min over edges of |p - nearest point of the edge|, negated inside
//!                     (the even-odd rule: a point is inside when a ray from it crosses
//!                     the boundary an odd number of times)
//! clearance(p)        = min over obstacles - footprint_radius
//! ```
//!
//! Fixed capacity, no allocation: at most [`MAX_OBSTACLES`] circles and polygons, with
//! [`MAX_POLYGON_POINTS`] vertices in all.

use crate::Real;
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};

/// The most obstacles a world holds.
pub const MAX_OBSTACLES: usize = 16;

/// The most polygon vertices a world holds, over all its polygons.
pub const MAX_POLYGON_POINTS: usize = 32;

/// One obstacle, as a scenario gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Obstacle<'a, T> {
    /// A disc: its centre (x, y) in m (world frame) and its radius in m.
    Circle {
        /// (x, y), m, world frame.
        center: (T, T),
        /// m, > 0.
        radius: T,
    },
    /// A simple polygon: its vertices (x, y) in m (world frame), in order, at least 3.
    Polygon(&'a [(T, T)]),
}

/// Where an obstacle's vertices lie in the shared pool.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Span {
    start: u8,
    len: u8,
}

/// A world's obstacles and the footprint radius that collides with them (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obstacles<T> {
    /// Circles: (x, y, radius), m.
    circles: [(T, T, T); MAX_OBSTACLES],
    n_circles: usize,
    /// Polygons: their spans in `points`.
    polygons: [Span; MAX_OBSTACLES],
    n_polygons: usize,
    points: [(T, T); MAX_POLYGON_POINTS],
    /// The footprint's radius about C, m.
    footprint_radius: T,
}

impl<T: Real> Default for Obstacles<T> {
    /// None (no run collides).
    fn default() -> Self {
        Self {
            circles: [(T::zero(), T::zero(), T::zero()); MAX_OBSTACLES],
            n_circles: 0,
            polygons: [Span::default(); MAX_OBSTACLES],
            n_polygons: 0,
            points: [(T::zero(), T::zero()); MAX_POLYGON_POINTS],
            footprint_radius: T::zero(),
        }
    }
}

impl<T: Real> Obstacles<T> {
    /// The obstacles `list` and the footprint radius (m) about C. Errors name
    /// `obstacle.center`, `obstacle.radius`, `obstacle.points` (with the obstacle's index
    /// in `ParamError::value`) or `footprint_radius`: a value not finite, a radius not
    /// above 0, a polygon of fewer than 3 vertices, more than [`MAX_OBSTACLES`]
    /// obstacles or [`MAX_POLYGON_POINTS`] vertices.
    pub fn new(list: &[Obstacle<'_, T>], footprint_radius: T) -> Result<Self, ParamError> {
        check::finite("footprint_radius", footprint_radius)?;
        let mut o =
            Self { footprint_radius: check::non_negative("footprint_radius", footprint_radius)?, ..Self::default() };
        if list.len() > MAX_OBSTACLES {
            return Err(check::out_of_range(
                "obstacle",
                "at most 16 obstacles (MAX_OBSTACLES)",
                T::lit(list.len() as f64),
            ));
        }
        let index = |i: usize| T::lit(i as f64);
        for (i, ob) in list.iter().enumerate() {
            match *ob {
                Obstacle::Circle { center, radius } => {
                    if !(center.0.is_finite() && center.1.is_finite()) {
                        return Err(check::out_of_range(
                            "obstacle.center",
                            "must be finite (obstacle index)",
                            index(i),
                        ));
                    }
                    if !(radius.is_finite() && radius > T::zero()) {
                        return Err(check::out_of_range(
                            "obstacle.radius",
                            "must be finite and > 0 (obstacle index)",
                            index(i),
                        ));
                    }
                    if let Some(slot) = o.circles.get_mut(o.n_circles) {
                        *slot = (center.0, center.1, radius);
                        o.n_circles += 1;
                    }
                }
                Obstacle::Polygon(points) => {
                    if points.len() < 3 {
                        return Err(check::out_of_range(
                            "obstacle.points",
                            "needs at least 3 vertices (obstacle index)",
                            index(i),
                        ));
                    }
                    if points.iter().any(|p| !(p.0.is_finite() && p.1.is_finite())) {
                        return Err(check::out_of_range(
                            "obstacle.points",
                            "must be finite (obstacle index)",
                            index(i),
                        ));
                    }
                    let start = o.polygons.iter().take(o.n_polygons).map(|s| usize::from(s.len)).sum::<usize>();
                    if start + points.len() > MAX_POLYGON_POINTS {
                        return Err(check::out_of_range(
                            "obstacle.points",
                            "at most 32 polygon vertices in all (MAX_POLYGON_POINTS; obstacle index)",
                            index(i),
                        ));
                    }
                    for (slot, &p) in o.points.iter_mut().skip(start).zip(points) {
                        *slot = p;
                    }
                    if let Some(span) = o.polygons.get_mut(o.n_polygons) {
                        // Both below 256: bounded by MAX_POLYGON_POINTS above.
                        *span = Span { start: start as u8, len: points.len() as u8 };
                        o.n_polygons += 1;
                    }
                }
            }
        }
        Ok(o)
    }

    /// The same obstacles in another precision (each number through `f64`).
    pub fn cast<U: Real>(&self) -> Obstacles<U> {
        let c = |x: T| U::lit(x.to_f64_lossless());
        Obstacles {
            circles: self.circles.map(|(x, y, r)| (c(x), c(y), c(r))),
            n_circles: self.n_circles,
            polygons: self.polygons,
            n_polygons: self.n_polygons,
            points: self.points.map(|(x, y)| (c(x), c(y))),
            footprint_radius: c(self.footprint_radius),
        }
    }

    /// True when there is no obstacle.
    pub fn is_empty(&self) -> bool {
        self.n_circles == 0 && self.n_polygons == 0
    }

    /// The footprint's radius about C, m.
    pub fn footprint_radius(&self) -> T {
        self.footprint_radius
    }

    /// The obstacles, circles first, then polygons, each in the order given.
    pub fn iter(&self) -> impl Iterator<Item = Obstacle<'_, T>> {
        let circles =
            self.circles.iter().take(self.n_circles).map(|&(x, y, r)| Obstacle::Circle { center: (x, y), radius: r });
        let polygons = self.polygons.iter().take(self.n_polygons).map(|s| {
            let (a, b) = (usize::from(s.start), usize::from(s.start) + usize::from(s.len));
            Obstacle::Polygon(self.points.get(a..b).unwrap_or(&[]))
        });
        circles.chain(polygons)
    }

    /// The signed distance (m) from C at (`x`, `y`) (world frame) to obstacle `ob`:
    /// positive outside, negative inside; for one run or several side by side.
    #[inline(always)]
    pub fn distance_to<L: Lane<Scalar = T>>(ob: &Obstacle<'_, T>, x: L, y: L) -> L {
        match *ob {
            Obstacle::Circle { center, radius } => {
                (x - L::splat(center.0)).hypot(y - L::splat(center.1)) - L::splat(radius)
            }
            Obstacle::Polygon(points) => polygon_distance(points, x, y),
        }
    }

    /// The clearance (m) of the footprint about C at (`x`, `y`): the distance from its
    /// edge to the nearest obstacle, negative when they overlap; infinite without
    /// obstacles. For one run or several side by side.
    #[inline(always)]
    pub fn clearance<L: Lane<Scalar = T>>(&self, x: L, y: L) -> L {
        let mut d = L::splat(T::infinity());
        for ob in self.iter() {
            d = d.min(Self::distance_to(&ob, x, y));
        }
        d - L::splat(self.footprint_radius)
    }

    /// The index (in [`Obstacles::iter`]'s order) of the obstacle nearest to C at
    /// (`x`, `y`) and the footprint's clearance to it (m); `None` without obstacles.
    pub fn nearest(&self, x: T, y: T) -> Option<(usize, T)> {
        let mut best: Option<(usize, T)> = None;
        for (i, ob) in self.iter().enumerate() {
            let d = Self::distance_to(&ob, x, y) - self.footprint_radius;
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((i, d));
            }
        }
        best
    }
}

/// The signed distance from (x, y) to a polygon: the nearest edge's distance, negated
/// inside (even-odd rule); branch-free per lane.
#[inline(always)]
fn polygon_distance<L: Lane>(points: &[(L::Scalar, L::Scalar)], x: L, y: L) -> L {
    let zero = L::splat(<L::Scalar as num_traits::Zero>::zero());
    let one = L::splat(<L::Scalar as num_traits::One>::one());
    let mut d2 = L::splat(<L::Scalar as num_traits::Float>::infinity());
    let mut inside = L::Mask::splat(false);
    let Some(&last) = points.last() else { return L::splat(<L::Scalar as num_traits::Float>::infinity()) };
    let mut prev = last;
    for &q in points {
        let (ax, ay, bx, by) = (L::splat(prev.0), L::splat(prev.1), L::splat(q.0), L::splat(q.1));
        let (ex, ey) = (bx - ax, by - ay);
        let (px, py) = (x - ax, y - ay);
        let len2 = ex * ex + ey * ey;
        // The nearest point of the edge: its parameter in [0, 1] (a zero-length edge: its end).
        let t = L::select(zero.lt(len2), (px * ex + py * ey) / len2, zero).max(zero).min(one);
        let (dx, dy) = (px - t * ex, py - t * ey);
        d2 = d2.min(dx * dx + dy * dy);
        // The ray to +x from (x, y) crosses this edge when y lies between its ends' y
        // (one end inclusive) and the crossing lies right of x.
        let straddles = (ay.le(y) & y.lt(by)) | (by.le(y) & y.lt(ay));
        let x_cross = ax + (y - ay) * ex / L::select(ey.eq(zero), one, ey);
        let crosses = straddles & x.lt(x_cross);
        inside = (inside & !crosses) | (!inside & crosses);
        prev = q;
    }
    let d = d2.sqrt();
    L::select(inside, -d, d)
}
