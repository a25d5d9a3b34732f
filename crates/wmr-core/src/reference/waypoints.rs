//! A smooth path through points with a speed profile: `[reference] kind = "waypoints"`
//! (and `"file"`, the same from a CSV), in fixed capacity, no alloc.
//!
//! **Path.** A natural cubic spline through the points, x(u) and y(u), over the
//! cumulative chord length u (u_0 = 0, u_{i+1} = u_i + |p_{i+1} - p_i|): C2 (position,
//! tangent and curvature continuous), with zero second derivative at both ends. The
//! second derivatives M_i at the knots solve the usual tridiagonal system
//! (h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (slope_i - slope_{i-1})),
//! solved once at construction (Thomas algorithm).
//!
//! **Speed profile.** Each span is cut into [`SUBSTEPS`] equal steps of u; at each
//! sample j the speed limit is v_lim = min(speed, sqrt(a_n / kappa_j)), kappa the
//! curvature and a_n = a / sqrt(2) the centripetal share of a = 0.9 accel_max. A forward
//! pass from rest (v_{j+1}^2 <= v_j^2 + 2 a_t ds_j, a_t = a / sqrt(2)) and a backward
//! pass to rest at the end bound the tangential acceleration, so the total
//! sqrt(a_t^2 + a_n^2) stays within 0.9 accel_max at the samples (the 10 % is the margin
//! for what happens between them; the tests check accel_max on a fine grid). Between
//! two samples u'^2 is linear in u (a constant u''), which gives u(t) in closed form and
//! the time of each sample: tau_j = 2 du / (u'_j + u'_{j+1}); u'_j = v_j / g_j with g_j
//! the largest |p'(u)| next to the sample, 1 % up, so v = g u' stays below `speed`.
//!
//! **State at t.** u, u' and u'' from the sample interval holding t (binary search),
//! then with g = |p'(u)|: v = g u', theta = atan2(y', x'), omega = (x' y'' - y' x'') u' / g^2,
//! v' = g u'' + (p'.p''/g) u'^2, omega' = d/dt of omega (written out in `state_at`).
//! Before t = 0 and after the end the reference is at rest at the first or last point.
//! The path parameter ([`super::Path`]) is u, m.

// Index loops over the parallel sample arrays: the profile reads several at each index.
#![allow(clippy::needless_range_loop)]

use super::path::Path;
use super::state::{Reference, ReferenceState};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2};

/// The most points a waypoints reference holds.
pub const MAX_POINTS: usize = 64;
/// Speed-profile samples per span of the spline.
pub const SUBSTEPS: usize = 8;
/// Samples of the profile at full capacity.
const MAX_SAMPLES: usize = (MAX_POINTS - 1) * SUBSTEPS + 1;

/// `[reference] kind = "waypoints"` (or `"file"`): the spline and its time law,
/// precomputed (about 15 kB in f64 at full capacity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoints<T> {
    n: usize,
    /// Knots: u (m), x, y (m), and the spline's second derivatives d2x/du2, d2y/du2 (1/m).
    u: [T; MAX_POINTS],
    x: [T; MAX_POINTS],
    y: [T; MAX_POINTS],
    mx: [T; MAX_POINTS],
    my: [T; MAX_POINTS],
    /// Samples of the time law: u_j (m), t_j (s), u'_j (m/s per m of u: 1/s), arc length s_j (m).
    su: [T; MAX_SAMPLES],
    st: [T; MAX_SAMPLES],
    sud: [T; MAX_SAMPLES],
    sarc: [T; MAX_SAMPLES],
    /// The largest speed, m/s, and acceleration bound, m/s^2, the profile was built for.
    speed: T,
    accel_max: T,
    /// Bounds of |p'(u)| (found at the samples, widened), for the path searches.
    rate: (T, T),
}

/// The spline at u: position, first, second and third derivatives in u.
struct SplinePoint<T> {
    p: (T, T),
    d1: (T, T),
    d2: (T, T),
    d3: (T, T),
}

impl<T: Real> Waypoints<T> {
    /// Builds the spline through `points` (x, y in m, world frame) and its speed profile
    /// (peak `speed` m/s, |acceleration| within `accel_max` m/s^2). Errors name
    /// `points` (fewer than 2, more than [`MAX_POINTS`], a point not finite, or the same
    /// as the one before it), `speed` and `accel_max` (> 0).
    pub fn new(points: &[[T; 2]], speed: T, accel_max: T) -> Result<Self, ParamError> {
        let n = points.len();
        if n < 2 {
            return Err(check::out_of_range("points", "needs at least 2 points", T::lit(n as f64)));
        }
        if n > MAX_POINTS {
            return Err(check::out_of_range("points", "holds at most 64 points", T::lit(n as f64)));
        }
        check::positive("speed", speed)?;
        check::positive("accel_max", accel_max)?;
        let z = T::zero();
        let mut w = Self {
            n,
            u: [z; MAX_POINTS],
            x: [z; MAX_POINTS],
            y: [z; MAX_POINTS],
            mx: [z; MAX_POINTS],
            my: [z; MAX_POINTS],
            su: [z; MAX_SAMPLES],
            st: [z; MAX_SAMPLES],
            sud: [z; MAX_SAMPLES],
            sarc: [z; MAX_SAMPLES],
            speed,
            accel_max,
            rate: (T::one(), T::one()),
        };
        for (i, p) in points.iter().enumerate() {
            check::finite("points", p[0])?;
            check::finite("points", p[1])?;
            w.x[i] = p[0];
            w.y[i] = p[1];
            if i > 0 {
                let h = (p[0] - w.x[i - 1]).hypot_libm(p[1] - w.y[i - 1]);
                if h <= z {
                    return Err(check::out_of_range("points", "a point repeats the one before it", T::lit(i as f64)));
                }
                w.u[i] = w.u[i - 1] + h;
            }
        }
        w.mx = natural_second_derivatives(&w.u, &w.x, n);
        w.my = natural_second_derivatives(&w.u, &w.y, n);
        w.build_profile();
        Ok(w)
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a waypoints reference has at least 2 points.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The points, x and y in m.
    pub fn point(&self, i: usize) -> [T; 2] {
        [self.x[i], self.y[i]]
    }

    /// Time at which the reference comes to rest at the last point, s.
    pub fn duration(&self) -> T {
        self.st[self.samples() - 1]
    }

    /// Peak speed (m/s) and acceleration bound (m/s^2) the profile keeps.
    pub fn limits(&self) -> (T, T) {
        (self.speed, self.accel_max)
    }

    /// The last point's index. `n` is within 2..=MAX_POINTS by construction; clamped here
    /// so the compiler sees every index below in range too (no panic path is linked into
    /// the firmware: firmware/check disassembles it).
    fn last(&self) -> usize {
        self.n.clamp(2, MAX_POINTS) - 1
    }

    fn samples(&self) -> usize {
        self.last() * SUBSTEPS + 1
    }

    /// The spline at `u` (clamped into [0, u_end]).
    fn spline(&self, u: T) -> SplinePoint<T> {
        let last = self.last();
        let u = u.max(T::zero()).min(self.u[last]);
        // The span i with u_i <= u <= u_{i+1} (the knots increase): the knots inside
        // that are <= u.
        let i = self.u[1..last].partition_point(|&k| k <= u).min(last - 1);
        let h = self.u[i + 1] - self.u[i];
        let a = (self.u[i + 1] - u) / h;
        let b = (u - self.u[i]) / h;
        let six = T::lit(6.0);
        let one = T::one();
        let three = T::lit(3.0);
        // One coordinate from its values (v0, v1) and second derivatives (m0, m1) at the
        // span's knots (read here, where i is known to be in range).
        let comp = |v0: T, v1: T, m0: T, m1: T| {
            let p = a * v0 + b * v1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / six;
            let d1 = (v1 - v0) / h - (three * a * a - one) / six * h * m0 + (three * b * b - one) / six * h * m1;
            let d2 = a * m0 + b * m1;
            let d3 = (m1 - m0) / h;
            (p, d1, d2, d3)
        };
        let (px, x1, x2, x3) = comp(self.x[i], self.x[i + 1], self.mx[i], self.mx[i + 1]);
        let (py, y1, y2, y3) = comp(self.y[i], self.y[i + 1], self.my[i], self.my[i + 1]);
        SplinePoint { p: (px, py), d1: (x1, y1), d2: (x2, y2), d3: (x3, y3) }
    }

    /// The speed profile: sample limits, forward and backward passes, then the times.
    fn build_profile(&mut self) {
        let n_s = self.samples();
        let a = T::lit(0.9) * self.accel_max;
        let a_share = a * T::FRAC_1_SQRT_2();
        let mut v = [T::zero(); MAX_SAMPLES];
        let mut prev = (T::zero(), T::zero());
        for j in 0..n_s {
            let span = (j / SUBSTEPS).min(self.last() - 1);
            let k = j - span * SUBSTEPS;
            let (u0, u1) = (self.u[span], self.u[span + 1]);
            let u = u0 + (u1 - u0) * T::lit(k as f64 / SUBSTEPS as f64);
            self.su[j] = if j == n_s - 1 { self.u[self.last()] } else { u };
            let sp = self.spline(self.su[j]);
            let g = sp.d1.0.hypot_libm(sp.d1.1);
            let kappa = (sp.d1.0 * sp.d2.1 - sp.d1.1 * sp.d2.0).abs() / (g * g * g);
            v[j] = if kappa > T::zero() { self.speed.min((a_share / kappa).sqrt()) } else { self.speed };
            if j > 0 {
                self.sarc[j] = self.sarc[j - 1] + (sp.p.0 - prev.0).hypot_libm(sp.p.1 - prev.1);
            }
            prev = sp.p;
            // Keep g for the conversion to u' below.
            self.sud[j] = g;
        }
        let two = T::lit(2.0);
        v[0] = T::zero();
        v[n_s - 1] = T::zero();
        for j in 0..n_s - 1 {
            let ds = self.sarc[j + 1] - self.sarc[j];
            v[j + 1] = v[j + 1].min((v[j] * v[j] + two * a_share * ds).sqrt());
        }
        for j in (0..n_s - 1).rev() {
            let ds = self.sarc[j + 1] - self.sarc[j];
            v[j] = v[j].min((v[j + 1] * v[j + 1] + two * a_share * ds).sqrt());
        }
        // u' = v / g with g the largest |p'(u)| next to the sample (at it and at the
        // middles of the steps either side, 1 % up): v = g u' then stays within the
        // planned speed between samples too, where g moves a little.
        let mut g_mid = [T::zero(); MAX_SAMPLES];
        for j in 0..n_s - 1 {
            let sp = self.spline((self.su[j] + self.su[j + 1]) * T::lit(0.5));
            g_mid[j] = sp.d1.0.hypot_libm(sp.d1.1);
        }
        let (mut lo, mut hi) = (T::infinity(), T::zero());
        for j in 0..n_s {
            lo = lo.min(self.sud[j]);
            hi = hi.max(self.sud[j]);
            let mut g = self.sud[j];
            if j > 0 {
                g = g.max(g_mid[j - 1]);
            }
            if j < n_s - 1 {
                g = g.max(g_mid[j]);
            }
            self.sud[j] = v[j] / (g * T::lit(1.01));
        }
        // |p'(u)| is 1 at the knots' chords on average; between samples it moves little.
        self.rate = (lo * T::lit(0.8), hi * T::lit(1.25));
        self.st[0] = T::zero();
        for j in 0..n_s - 1 {
            let du = self.su[j + 1] - self.su[j];
            self.st[j + 1] = self.st[j] + two * du / (self.sud[j] + self.sud[j + 1]);
        }
    }

    /// u (m), u' (1/s) and u'' (1/s^2) at time t (s).
    fn time_law(&self, t: T) -> (T, T, T) {
        let n_s = self.samples();
        if t <= T::zero() {
            return (T::zero(), T::zero(), T::zero());
        }
        if t >= self.st[n_s - 1] {
            return (self.su[n_s - 1], T::zero(), T::zero());
        }
        // The sample interval j with t_j <= t < t_{j+1} (the times increase).
        let j = self.st[1..n_s - 1].partition_point(|&tj| tj <= t).min(n_s - 2);
        let du = self.su[j + 1] - self.su[j];
        let (w0, w1) = (self.sud[j], self.sud[j + 1]);
        let acc = (w1 * w1 - w0 * w0) / (T::lit(2.0) * du);
        let tau = t - self.st[j];
        let u = (self.su[j] + w0 * tau + acc * tau * tau * T::lit(0.5)).min(self.su[j + 1]);
        (u, (w0 + acc * tau).max(T::zero()), acc)
    }
}

/// M_i of the natural cubic spline through (u_i, v_i): M_0 = M_{n-1} = 0 and, inside,
/// h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 ((v_{i+1} - v_i)/h_i - (v_i - v_{i-1})/h_{i-1}),
/// solved by the Thomas algorithm (the system is diagonally dominant).
fn natural_second_derivatives<T: Real>(u: &[T; MAX_POINTS], v: &[T; MAX_POINTS], n: usize) -> [T; MAX_POINTS] {
    let n = n.min(MAX_POINTS);
    let mut m = [T::zero(); MAX_POINTS];
    if n < 3 {
        return m;
    }
    let mut c_prime = [T::zero(); MAX_POINTS];
    let mut d_prime = [T::zero(); MAX_POINTS];
    let two = T::lit(2.0);
    let six = T::lit(6.0);
    for i in 1..n - 1 {
        let h0 = u[i] - u[i - 1];
        let h1 = u[i + 1] - u[i];
        let rhs = six * ((v[i + 1] - v[i]) / h1 - (v[i] - v[i - 1]) / h0);
        let (a, b, c) = (h0, two * (h0 + h1), h1);
        // Row i of the interior system; row 1 has no a (M_0 = 0), row n-2 no c (M_{n-1} = 0).
        let (cp_prev, dp_prev) = if i == 1 { (T::zero(), T::zero()) } else { (c_prime[i - 1], d_prime[i - 1]) };
        let denom = b - a * cp_prev;
        c_prime[i] = c / denom;
        d_prime[i] = (rhs - a * dp_prev) / denom;
    }
    m[n - 2] = d_prime[n - 2];
    for i in (1..n - 2).rev() {
        m[i] = d_prime[i] - c_prime[i] * m[i + 1];
    }
    m
}

impl<T: Real> Reference<T> for Waypoints<T> {
    fn state_at(&self, t: T) -> ReferenceState<T> {
        let (u, ud, udd) = self.time_law(t);
        let sp = self.spline(u);
        let (x1, y1) = sp.d1;
        let (x2, y2) = sp.d2;
        let (x3, y3) = sp.d3;
        let g2 = x1 * x1 + y1 * y1;
        let g = g2.sqrt();
        let cross = x1 * y2 - y1 * x2;
        let dot = x1 * x2 + y1 * y2;
        // theta' = (cross / g^2) u';  d/du (cross / g^2) = (x' y''' - y' x''') / g^2 - 2 cross dot / g^4.
        let k = cross / g2;
        let dk = (x1 * y3 - y1 * x3) / g2 - T::lit(2.0) * cross * dot / (g2 * g2);
        ReferenceState {
            pose: Pose2::new(sp.p.0, sp.p.1, y1.atan2_libm(x1)),
            twist: Twist2 { v: g * ud, omega: k * ud },
            accel: Twist2 { v: g * udd + dot / g * ud * ud, omega: dk * ud * ud + k * udd },
        }
    }

    fn path(&self) -> Option<&dyn Path<T>> {
        Some(self)
    }
}

impl<T: Real> Path<T> for Waypoints<T> {
    /// s = the spline's chord-length parameter u, m.
    fn pose_on_path(&self, s: T) -> Pose2<T> {
        let sp = self.spline(s);
        Pose2::new(sp.p.0, sp.p.1, sp.d1.1.atan2_libm(sp.d1.0))
    }
    fn end(&self) -> Option<T> {
        Some(self.u[self.last()])
    }
    fn point_on_path(&self, s: T) -> (T, T) {
        self.spline(s).p
    }
    fn rate_bounds(&self) -> (T, T) {
        self.rate
    }
    fn remaining_length(&self, s: T) -> T {
        // Arc length at the samples, interpolated linearly in u between them.
        let n_s = self.samples();
        let s = s.max(T::zero()).min(self.su[n_s - 1]);
        // The sample interval lo with u_lo <= s <= u_hi, hi = lo + 1.
        let lo = self.su[1..n_s - 1].partition_point(|&uj| uj <= s).min(n_s - 2);
        let hi = lo + 1;
        let f = (s - self.su[lo]) / (self.su[hi] - self.su[lo]);
        let arc = self.sarc[lo] + f * (self.sarc[hi] - self.sarc[lo]);
        self.sarc[n_s - 1] - arc
    }
}
