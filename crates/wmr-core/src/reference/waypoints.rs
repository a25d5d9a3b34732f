//! A smooth path through points with a speed profile: `[reference] kind = "waypoints"`
//! (and `"file"`, the same from a CSV), no alloc: in its own storage of [`MAX_POINTS`]
//! points, or of any length in storage its caller owns ([`Waypoints::new_in`]).
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

use super::config::{Configured, KindConfig};
use super::path::Path;
use super::state::{Reference, ReferenceState};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2};

/// The most points a waypoints reference holds in its own, fixed storage
/// ([`Waypoints::new`]: what the firmware and the C API's `wmr_reference_*` hold). A path
/// of any length is built over storage its caller owns ([`Waypoints::new_in`]).
pub const MAX_POINTS: usize = 64;
/// Speed-profile samples per span of the spline.
pub const SUBSTEPS: usize = 8;
/// The words ([`Waypoints::words`]) of the fixed storage: [`MAX_POINTS`] points.
pub const FIXED_WORDS: usize = Layout::of(MAX_POINTS).words();

/// `[reference] kind = "waypoints"` (or `"file"`): the spline and its time law,
/// precomputed into the storage `S`, a slice of `T` of [`Waypoints::words`]`(n)` words:
/// its own array of [`MAX_POINTS`] points by default (about 19 kB in f64), or any
/// storage its caller owns (a `Vec`, a `&mut [T]`, memory given by C).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoints<T, S = [T; FIXED_WORDS]> {
    n: usize,
    /// Knots: u (m), x, y (m), and the spline's second derivatives d2x/du2, d2y/du2 (1/m),
    /// n words each; then the samples of the time law: u_j (m), t_j (s), u'_j (m/s per m
    /// of u: 1/s), arc length s_j (m), (n - 1) SUBSTEPS + 1 words each ([`Layout`]).
    buf: S,
    /// The largest speed, m/s, and acceleration bound, m/s^2, the profile was built for.
    speed: T,
    accel_max: T,
    /// Bounds of |p'(u)| (found at the samples, widened), for the path searches.
    rate: (T, T),
}

/// Where each array of a path of `n` points starts in its storage.
#[derive(Clone, Copy, Debug)]
struct Layout {
    n: usize,
    /// Samples of the time law.
    m: usize,
}

/// The arrays of the storage, in order.
#[derive(Clone, Copy)]
enum Arr {
    U,
    X,
    Y,
    Mx,
    My,
    Su,
    St,
    Sud,
    Sarc,
}

impl Layout {
    const fn of(n: usize) -> Self {
        Self { n, m: n.saturating_sub(1) * SUBSTEPS + 1 }
    }

    const fn words(self) -> usize {
        5 * self.n + 4 * self.m
    }

    /// The range of `a` in the storage.
    fn range(self, a: Arr) -> core::ops::Range<usize> {
        let (n, m) = (self.n, self.m);
        let start = match a {
            Arr::U => 0,
            Arr::X => n,
            Arr::Y => 2 * n,
            Arr::Mx => 3 * n,
            Arr::My => 4 * n,
            Arr::Su => 5 * n,
            Arr::St => 5 * n + m,
            Arr::Sud => 5 * n + 2 * m,
            Arr::Sarc => 5 * n + 3 * m,
        };
        let len = if matches!(a, Arr::U | Arr::X | Arr::Y | Arr::Mx | Arr::My) { n } else { m };
        start..start + len
    }
}

/// The array `a` of storage `buf` (empty if `buf` is short: never, by construction; no
/// index below can panic, for the firmware and C, where no panic path may be linked).
#[inline(always)]
fn arr<T>(buf: &[T], l: Layout, a: Arr) -> &[T] {
    buf.get(l.range(a)).unwrap_or(&[])
}

/// `s[i]`, or zero past its end (never, by construction).
#[inline(always)]
fn at<T: Real>(s: &[T], i: usize) -> T {
    s.get(i).copied().unwrap_or(T::zero())
}

/// Writes `v` to `buf`'s array `a` at `i`.
#[inline(always)]
fn set<T>(buf: &mut [T], l: Layout, a: Arr, i: usize, v: T) {
    if let Some(w) = buf.get_mut(l.range(a)).and_then(|s| s.get_mut(i)) {
        *w = v;
    }
}

/// The spline at u: position, first, second and third derivatives in u.
struct SplinePoint<T> {
    p: (T, T),
    d1: (T, T),
    d2: (T, T),
    d3: (T, T),
}

/// What builds a waypoints path in its own fixed storage: the first `n` of `points` and
/// the limits, as [`Waypoints::new`] takes them (the trace's words: n, speed, accel_max,
/// then x and y of each point; its spline and speed profile are rebuilt from them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaypointsConfig<T> {
    /// Points in use, 2 to [`MAX_POINTS`].
    pub n: usize,
    /// x, y in m (world frame); zeros past `n`.
    pub points: [[T; 2]; MAX_POINTS],
    /// Peak speed, m/s.
    pub speed: T,
    /// Acceleration bound, m/s^2.
    pub accel_max: T,
}

impl<T: Real> KindConfig<T> for WaypointsConfig<T> {
    type Built = Waypoints<T>;
    const WORDS: usize = 3 + 2 * MAX_POINTS;

    fn build(&self) -> Result<Self::Built, ParamError> {
        let points = self
            .points
            .get(..self.n)
            .ok_or_else(|| check::out_of_range("points", "holds at most 64 points", T::lit(self.n as f64)))?;
        Waypoints::new(points, self.speed, self.accel_max)
    }

    fn encode(&self, args: &mut [u32], real: &mut dyn FnMut(T) -> u32) {
        let mut words = args.iter_mut();
        let mut put = |v: u32| {
            if let Some(w) = words.next() {
                *w = v;
            }
        };
        put(self.n as u32);
        put(real(self.speed));
        put(real(self.accel_max));
        for p in self.points.iter().take(self.n) {
            put(real(p[0]));
            put(real(p[1]));
        }
    }

    fn decode(args: &[u32], real: &mut dyn FnMut(u32) -> T) -> Result<Self, &'static str> {
        let n = args.first().map_or(0, |&n| n as usize);
        if !(2..=MAX_POINTS).contains(&n) || args.len() < 3 + 2 * n {
            return Err("waypoints point count is not within 2..=64");
        }
        let mut points = [[T::zero(); 2]; MAX_POINTS];
        for (p, xy) in points.iter_mut().zip(args[3..].chunks_exact(2)).take(n) {
            *p = [real(xy[0]), real(xy[1])];
        }
        Ok(Self { n, points, speed: real(args[1]), accel_max: real(args[2]) })
    }
}

impl<T: Real, S: AsRef<[T]>> Configured<T> for Waypoints<T, S> {
    type Config = WaypointsConfig<T>;

    /// Errors name `points` for a path longer than the fixed storage (and a trace) holds,
    /// [`MAX_POINTS`].
    fn config(&self) -> Result<Self::Config, ParamError> {
        if self.len() > MAX_POINTS {
            return Err(check::out_of_range(
                "points",
                "a trace (and the firmware's fixed storage) holds at most 64 points: thin the path to 64",
                T::lit(self.len() as f64),
            ));
        }
        let mut points = [[T::zero(); 2]; MAX_POINTS];
        for (i, p) in points.iter_mut().enumerate().take(self.len()) {
            *p = self.point(i);
        }
        let (speed, accel_max) = self.limits();
        Ok(WaypointsConfig { n: self.len(), points, speed, accel_max })
    }
}

impl<T: Real> Waypoints<T> {
    /// Builds the spline through `points` (x, y in m, world frame) and its speed profile
    /// (peak `speed` m/s, |acceleration| within `accel_max` m/s^2) in its own fixed
    /// storage. Errors name `points` (fewer than 2, more than [`MAX_POINTS`]: then
    /// [`Waypoints::new_in`] with storage of [`Waypoints::words`]`(n)`; a point not
    /// finite, or the same as the one before it), `speed` and `accel_max` (> 0).
    pub fn new(points: &[[T; 2]], speed: T, accel_max: T) -> Result<Self, ParamError> {
        let n = points.len();
        if n > MAX_POINTS {
            return Err(check::out_of_range(
                "points",
                "holds at most 64 points in fixed storage (give more in storage of your own: Waypoints::new_in)",
                T::lit(n as f64),
            ));
        }
        Self::new_in(points, speed, accel_max, [T::zero(); FIXED_WORDS])
    }
}

impl<T: Real, S> Waypoints<T, S> {
    /// The words of storage (numbers of type `T`) a path of `n` points takes:
    /// 5 n + 4 ((n - 1) [`SUBSTEPS`] + 1), 37 n - 28 (1 m per 2.7 kB in f64 for points
    /// 1 cm apart).
    pub const fn words(n: usize) -> usize {
        Layout::of(n).words()
    }

    /// As [`Waypoints::new`], into `storage` (at least [`Waypoints::words`]`(n)` words;
    /// its contents are overwritten): a path of any length in memory its caller owns, no
    /// alloc. Also errors naming `storage` (too short).
    pub fn new_in(points: &[[T; 2]], speed: T, accel_max: T, mut storage: S) -> Result<Self, ParamError>
    where
        S: AsRef<[T]> + AsMut<[T]>,
    {
        let n = points.len();
        if n < 2 {
            return Err(check::out_of_range("points", "needs at least 2 points", T::lit(n as f64)));
        }
        let l = Layout::of(n);
        if storage.as_ref().len() < l.words() {
            return Err(check::out_of_range(
                "storage",
                "is shorter than Waypoints::words(points) numbers",
                T::lit(storage.as_ref().len() as f64),
            ));
        }
        check::positive("speed", speed)?;
        check::positive("accel_max", accel_max)?;
        let z = T::zero();
        let buf = storage.as_mut();
        // Caller storage holds anything: start from zeros (the fixed storage is zeros).
        for w in buf.iter_mut().take(l.words()) {
            *w = z;
        }
        let (mut px, mut py) = (z, z);
        for (i, p) in points.iter().enumerate() {
            check::finite("points", p[0])?;
            check::finite("points", p[1])?;
            set(buf, l, Arr::X, i, p[0]);
            set(buf, l, Arr::Y, i, p[1]);
            if i > 0 {
                let h = (p[0] - px).hypot_libm(p[1] - py);
                if h <= z {
                    return Err(check::out_of_range("points", "a point repeats the one before it", T::lit(i as f64)));
                }
                let u = at(arr(buf, l, Arr::U), i - 1) + h;
                set(buf, l, Arr::U, i, u);
            }
            (px, py) = (p[0], p[1]);
        }
        natural_second_derivatives(buf, l, Arr::X, Arr::Mx);
        natural_second_derivatives(buf, l, Arr::Y, Arr::My);
        let rate = build_profile(buf, l, speed, accel_max);
        Ok(Self { n, buf: storage, speed, accel_max, rate })
    }

    /// The same path in other storage: `f` takes this storage and returns storage with
    /// the same numbers (e.g. a `Vec` into an `Arc<[T]>`, which clones cheaply).
    pub fn map_storage<S2>(self, f: impl FnOnce(S) -> S2) -> Waypoints<T, S2> {
        Waypoints { n: self.n, buf: f(self.buf), speed: self.speed, accel_max: self.accel_max, rate: self.rate }
    }
}

impl<T: Real, S: AsRef<[T]>> Waypoints<T, S> {
    fn layout(&self) -> Layout {
        Layout::of(self.n)
    }

    fn arr(&self, a: Arr) -> &[T] {
        arr(self.buf.as_ref(), self.layout(), a)
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
        [at(self.arr(Arr::X), i), at(self.arr(Arr::Y), i)]
    }

    /// Time at which the reference comes to rest at the last point, s.
    pub fn duration(&self) -> T {
        at(self.arr(Arr::St), self.layout().m - 1)
    }

    /// Peak speed (m/s) and acceleration bound (m/s^2) the profile keeps.
    pub fn limits(&self) -> (T, T) {
        (self.speed, self.accel_max)
    }

    /// The spline at `u` (clamped into [0, u_end]).
    fn spline(&self, u: T) -> SplinePoint<T> {
        spline(self.buf.as_ref(), self.layout(), u)
    }

    /// u (m), u' (1/s) and u'' (1/s^2) at time t (s).
    fn time_law(&self, t: T) -> (T, T, T) {
        let n_s = self.layout().m;
        let (su, st, sud) = (self.arr(Arr::Su), self.arr(Arr::St), self.arr(Arr::Sud));
        if t <= T::zero() {
            return (T::zero(), T::zero(), T::zero());
        }
        if t >= at(st, n_s - 1) {
            return (at(su, n_s - 1), T::zero(), T::zero());
        }
        // The sample interval j with t_j <= t < t_{j+1} (the times increase).
        let j = st.get(1..n_s - 1).unwrap_or(&[]).partition_point(|&tj| tj <= t).min(n_s - 2);
        let du = at(su, j + 1) - at(su, j);
        let (w0, w1) = (at(sud, j), at(sud, j + 1));
        let acc = (w1 * w1 - w0 * w0) / (T::lit(2.0) * du);
        let tau = t - at(st, j);
        let u = (at(su, j) + w0 * tau + acc * tau * tau * T::lit(0.5)).min(at(su, j + 1));
        (u, (w0 + acc * tau).max(T::zero()), acc)
    }
}

/// The spline of storage `buf` at `u` (clamped into [0, u_end]).
fn spline<T: Real>(buf: &[T], l: Layout, u: T) -> SplinePoint<T> {
    let last = l.n.max(2) - 1;
    let (us, xs, ys) = (arr(buf, l, Arr::U), arr(buf, l, Arr::X), arr(buf, l, Arr::Y));
    let (mxs, mys) = (arr(buf, l, Arr::Mx), arr(buf, l, Arr::My));
    let u = u.max(T::zero()).min(at(us, last));
    // The span i with u_i <= u <= u_{i+1} (the knots increase): the knots inside
    // that are <= u.
    let i = us.get(1..last).unwrap_or(&[]).partition_point(|&k| k <= u).min(last - 1);
    let h = at(us, i + 1) - at(us, i);
    let a = (at(us, i + 1) - u) / h;
    let b = (u - at(us, i)) / h;
    let six = T::lit(6.0);
    let one = T::one();
    let three = T::lit(3.0);
    // One coordinate from its values (v0, v1) and second derivatives (m0, m1) at the
    // span's knots.
    let comp = |v0: T, v1: T, m0: T, m1: T| {
        let p = a * v0 + b * v1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / six;
        let d1 = (v1 - v0) / h - (three * a * a - one) / six * h * m0 + (three * b * b - one) / six * h * m1;
        let d2 = a * m0 + b * m1;
        let d3 = (m1 - m0) / h;
        (p, d1, d2, d3)
    };
    let (px, x1, x2, x3) = comp(at(xs, i), at(xs, i + 1), at(mxs, i), at(mxs, i + 1));
    let (py, y1, y2, y3) = comp(at(ys, i), at(ys, i + 1), at(mys, i), at(mys, i + 1));
    SplinePoint { p: (px, py), d1: (x1, y1), d2: (x2, y2), d3: (x3, y3) }
}

/// The speed profile into `buf`'s samples: sample limits, forward and backward passes,
/// then the times. Returns the bounds of |p'(u)| for the path searches.
fn build_profile<T: Real>(buf: &mut [T], l: Layout, speed: T, accel_max: T) -> (T, T) {
    let n_s = l.m;
    let last = l.n.max(2) - 1;
    let a = T::lit(0.9) * accel_max;
    let a_share = a * T::FRAC_1_SQRT_2();
    // v_j (m/s) is kept in the t_j array until the times are computed at the end.
    let mut prev = (T::zero(), T::zero());
    for j in 0..n_s {
        let span = (j / SUBSTEPS).min(last - 1);
        let k = j - span * SUBSTEPS;
        let us = arr(buf, l, Arr::U);
        let (u0, u1) = (at(us, span), at(us, span + 1));
        let u = u0 + (u1 - u0) * T::lit(k as f64 / SUBSTEPS as f64);
        let su = if j == n_s - 1 { at(us, last) } else { u };
        set(buf, l, Arr::Su, j, su);
        let sp = spline(buf, l, su);
        let g = sp.d1.0.hypot_libm(sp.d1.1);
        let kappa = (sp.d1.0 * sp.d2.1 - sp.d1.1 * sp.d2.0).abs() / (g * g * g);
        let v = if kappa > T::zero() { speed.min((a_share / kappa).sqrt()) } else { speed };
        set(buf, l, Arr::St, j, v);
        if j > 0 {
            let s = at(arr(buf, l, Arr::Sarc), j - 1) + (sp.p.0 - prev.0).hypot_libm(sp.p.1 - prev.1);
            set(buf, l, Arr::Sarc, j, s);
        }
        prev = sp.p;
        // Keep g for the conversion to u' below.
        set(buf, l, Arr::Sud, j, g);
    }
    let two = T::lit(2.0);
    set(buf, l, Arr::St, 0, T::zero());
    set(buf, l, Arr::St, n_s - 1, T::zero());
    for j in 0..n_s - 1 {
        let (v, sarc) = (arr(buf, l, Arr::St), arr(buf, l, Arr::Sarc));
        let ds = at(sarc, j + 1) - at(sarc, j);
        let (vj, vn) = (at(v, j), at(v, j + 1));
        set(buf, l, Arr::St, j + 1, vn.min((vj * vj + two * a_share * ds).sqrt()));
    }
    for j in (0..n_s - 1).rev() {
        let (v, sarc) = (arr(buf, l, Arr::St), arr(buf, l, Arr::Sarc));
        let ds = at(sarc, j + 1) - at(sarc, j);
        let (vj, vn) = (at(v, j), at(v, j + 1));
        set(buf, l, Arr::St, j, vj.min((vn * vn + two * a_share * ds).sqrt()));
    }
    // u' = v / g with g the largest |p'(u)| next to the sample (at it and at the
    // middles of the steps either side, 1 % up): v = g u' then stays within the
    // planned speed between samples too, where g moves a little.
    let g_mid = |buf: &[T], j: usize| {
        let su = arr(buf, l, Arr::Su);
        let sp = spline(buf, l, (at(su, j) + at(su, j + 1)) * T::lit(0.5));
        sp.d1.0.hypot_libm(sp.d1.1)
    };
    let (mut lo, mut hi) = (T::infinity(), T::zero());
    let mut mid_before = T::zero();
    for j in 0..n_s {
        let gj = at(arr(buf, l, Arr::Sud), j);
        lo = lo.min(gj);
        hi = hi.max(gj);
        let mut g = gj;
        if j > 0 {
            g = g.max(mid_before);
        }
        if j < n_s - 1 {
            mid_before = g_mid(buf, j);
            g = g.max(mid_before);
        }
        let v = at(arr(buf, l, Arr::St), j);
        set(buf, l, Arr::Sud, j, v / (g * T::lit(1.01)));
    }
    set(buf, l, Arr::St, 0, T::zero());
    for j in 0..n_s - 1 {
        let (su, sud, st) = (arr(buf, l, Arr::Su), arr(buf, l, Arr::Sud), arr(buf, l, Arr::St));
        let du = at(su, j + 1) - at(su, j);
        let t = at(st, j) + two * du / (at(sud, j) + at(sud, j + 1));
        set(buf, l, Arr::St, j + 1, t);
    }
    // |p'(u)| is 1 at the knots' chords on average; between samples it moves little.
    (lo * T::lit(0.8), hi * T::lit(1.25))
}

/// M_i of the natural cubic spline through (u_i, v_i), v the array `v` of `buf`, into
/// its array `m`: M_0 = M_{n-1} = 0 and, inside,
/// h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 ((v_{i+1} - v_i)/h_i - (v_i - v_{i-1})/h_{i-1}),
/// solved by the Thomas algorithm (the system is diagonally dominant). Its c' and d'
/// are kept in the (not yet used, longer) arrays t_j and u'_j of the samples.
fn natural_second_derivatives<T: Real>(buf: &mut [T], l: Layout, v: Arr, m: Arr) {
    let n = l.n;
    for i in 0..n {
        set(buf, l, m, i, T::zero());
    }
    if n < 3 {
        return;
    }
    let (cp, dp) = (Arr::St, Arr::Sud);
    let two = T::lit(2.0);
    let six = T::lit(6.0);
    for i in 1..n - 1 {
        let (us, vs) = (arr(buf, l, Arr::U), arr(buf, l, v));
        let h0 = at(us, i) - at(us, i - 1);
        let h1 = at(us, i + 1) - at(us, i);
        let rhs = six * ((at(vs, i + 1) - at(vs, i)) / h1 - (at(vs, i) - at(vs, i - 1)) / h0);
        let (a, b, c) = (h0, two * (h0 + h1), h1);
        // Row i of the interior system; row 1 has no a (M_0 = 0), row n-2 no c (M_{n-1} = 0).
        let (cp_prev, dp_prev) =
            if i == 1 { (T::zero(), T::zero()) } else { (at(arr(buf, l, cp), i - 1), at(arr(buf, l, dp), i - 1)) };
        let denom = b - a * cp_prev;
        set(buf, l, cp, i, c / denom);
        set(buf, l, dp, i, (rhs - a * dp_prev) / denom);
    }
    let d_last = at(arr(buf, l, dp), n - 2);
    set(buf, l, m, n - 2, d_last);
    for i in (1..n - 2).rev() {
        let mi = at(arr(buf, l, dp), i) - at(arr(buf, l, cp), i) * at(arr(buf, l, m), i + 1);
        set(buf, l, m, i, mi);
    }
}

impl<T: Real, S: AsRef<[T]>> Reference<T> for Waypoints<T, S> {
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

impl<T: Real, S: AsRef<[T]>> Path<T> for Waypoints<T, S> {
    /// s = the spline's chord-length parameter u, m.
    fn pose_on_path(&self, s: T) -> Pose2<T> {
        let sp = self.spline(s);
        Pose2::new(sp.p.0, sp.p.1, sp.d1.1.atan2_libm(sp.d1.0))
    }
    fn end(&self) -> Option<T> {
        Some(at(self.arr(Arr::U), self.n - 1))
    }
    fn point_on_path(&self, s: T) -> (T, T) {
        self.spline(s).p
    }
    fn rate_bounds(&self) -> (T, T) {
        self.rate
    }
    fn remaining_length(&self, s: T) -> T {
        // Arc length at the samples, interpolated linearly in u between them.
        let n_s = self.layout().m;
        let (su, sarc) = (self.arr(Arr::Su), self.arr(Arr::Sarc));
        let s = s.max(T::zero()).min(at(su, n_s - 1));
        // The sample interval lo with u_lo <= s <= u_hi, hi = lo + 1.
        let lo = su.get(1..n_s - 1).unwrap_or(&[]).partition_point(|&uj| uj <= s).min(n_s - 2);
        let hi = lo + 1;
        let f = (s - at(su, lo)) / (at(su, hi) - at(su, lo));
        let arc = at(sarc, lo) + f * (at(sarc, hi) - at(sarc, lo));
        at(sarc, n_s - 1) - arc
    }
}
