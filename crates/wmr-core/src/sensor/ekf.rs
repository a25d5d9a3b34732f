//! The pose EKF: an extended Kalman filter on the pose of C that predicts with wheel
//! odometry and corrects with occasional absolute pose fixes (docs/model.md, "Odometry").
//!
//! State: the estimated pose (x, y, theta) of C in the world frame, with covariance P
//! (3x3; m^2, m rad, rad^2). At each control tick, with wheel travels d_r, d_l (m) and
//! the arc of [`super::dead_reckoning`] (ds, dth, theta_m = theta + dth / 2):
//!
//! ```text
//! predict:  x <- arc_step(x, d)
//!           F = [[1, 0, -ds sin theta_m], [0, 1, ds cos theta_m], [0, 0, 1]]      d x+/d x
//!           G = [[c/2 - ds s/(4R), c/2 + ds s/(4R)],                           d x+/d (d_r, d_l)
//!                [s/2 + ds c/(4R), s/2 - ds c/(4R)],     c, s = cos, sin theta_m
//!                [1/(2R),          -1/(2R)        ]]
//!           Q = diag(var_r, var_l),  var_w = (r q)^2 / 12 min(1, |d_w| / (r q)) + k^2 |d_w|
//!           P <- F P F^T + G Q G^T
//! update:   z = a pose fix (H = I), R_z = diag(sigma_p^2, sigma_p^2, sigma_th^2)
//!           nu = z - x (heading wrapped),  S = P + R_z,  K = P S^-1
//!           x <- x + K nu,  P <- (I - K) P (I - K)^T + K R_z K^T   (Joseph form)
//! ```
//!
//! q is the encoder quantum (rad): each reading is rounded, with an error uniform in a
//! quantum (variance (r q)^2 / 12 in travel) that changes only when a count boundary is
//! crossed, so a tick adds a fresh rounding error in proportion to the counts crossed
//! (at most one) and a wheel at rest adds none. k is the slip and radius term
//! (`odometry_noise`, m^(1/2): the standard deviation of a wheel's travel error grows
//! as k sqrt(distance)). The Joseph form keeps P symmetric positive definite in
//! rounding; P is also symmetrized after each step.

use crate::Real;
use crate::math::{Pose2, Wheels, wrap_angle};

use super::dead_reckoning::arc_step;

/// A 3x3 matrix, row-major.
pub type Mat3<T> = [[T; 3]; 3];

fn zero3<T: Real>() -> Mat3<T> {
    [[T::zero(); 3]; 3]
}

fn mul<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let mut c = zero3();
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cij) in row.iter_mut().enumerate() {
            *cij = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

fn transpose<T: Real>(a: &Mat3<T>) -> Mat3<T> {
    core::array::from_fn(|i| core::array::from_fn(|j| a[j][i]))
}

fn add<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    core::array::from_fn(|i| core::array::from_fn(|j| a[i][j] + b[i][j]))
}

/// (A + A^T) / 2.
fn symmetrize<T: Real>(a: &Mat3<T>) -> Mat3<T> {
    let half = T::lit(0.5);
    core::array::from_fn(|i| core::array::from_fn(|j| half * (a[i][j] + a[j][i])))
}

/// The inverse of a 3x3 matrix by its adjugate; `None` when singular.
fn inverse<T: Real>(a: &Mat3<T>) -> Option<Mat3<T>> {
    let cof = |r0: usize, r1: usize, c0: usize, c1: usize| a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0];
    let adj = [
        [cof(1, 2, 1, 2), -cof(0, 2, 1, 2), cof(0, 1, 1, 2)],
        [-cof(1, 2, 0, 2), cof(0, 2, 0, 2), -cof(0, 1, 0, 2)],
        [cof(1, 2, 0, 1), -cof(0, 2, 0, 1), cof(0, 1, 0, 1)],
    ];
    let det = a[0][0] * adj[0][0] + a[0][1] * adj[1][0] + a[0][2] * adj[2][0];
    if !det.is_finite() || det == T::zero() {
        return None;
    }
    Some(core::array::from_fn(|i| core::array::from_fn(|j| adj[i][j] / det)))
}

/// diag(a, b, c).
pub fn diag<T: Real>(a: T, b: T, c: T) -> Mat3<T> {
    let z = T::zero();
    [[a, z, z], [z, b, z], [z, z, c]]
}

/// The pose EKF of the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseEkf<T> {
    /// The estimated pose of C, world frame.
    mean: Pose2<T>,
    /// Its covariance P (x, y in m, theta in rad).
    cov: Mat3<T>,
}

impl<T: Real> PoseEkf<T> {
    /// Starts at `mean` with covariance `cov` (symmetric positive definite).
    pub fn new(mean: Pose2<T>, cov: Mat3<T>) -> Self {
        Self { mean, cov }
    }

    /// The estimated pose of C, world frame.
    pub fn mean(&self) -> Pose2<T> {
        self.mean
    }

    /// Its covariance P (row-major; m^2, m rad, rad^2).
    pub fn covariance(&self) -> &Mat3<T> {
        &self.cov
    }

    /// The prediction over one tick: the wheels travelled `travel_m` (m), each with
    /// error variance `variance_m2` (m^2), on a robot of half track `half_track` (R, m).
    pub fn predict(&mut self, travel_m: Wheels<T>, variance_m2: Wheels<T>, half_track: T) {
        let two = T::lit(2.0);
        let ds = (travel_m.right + travel_m.left) / two;
        let dtheta = (travel_m.right - travel_m.left) / (two * half_track);
        let (s, c) = (self.mean.theta + dtheta / two).sin_cos_libm();
        let (z, one) = (T::zero(), T::one());
        let f = [[one, z, -ds * s], [z, one, ds * c], [z, z, one]];
        let k = ds / (T::lit(4.0) * half_track);
        let inv_2r = one / (two * half_track);
        let g = [[c / two - k * s, c / two + k * s], [s / two + k * c, s / two - k * c], [inv_2r, -inv_2r]];
        // G Q G^T with Q = diag(var_r, var_l).
        let gqg: Mat3<T> = core::array::from_fn(|i| {
            core::array::from_fn(|j| g[i][0] * variance_m2.right * g[j][0] + g[i][1] * variance_m2.left * g[j][1])
        });
        self.cov = symmetrize(&add(&mul(&mul(&f, &self.cov), &transpose(&f)), &gqg));
        self.mean = arc_step(self.mean, travel_m, half_track);
    }

    /// The correction by an absolute fix `z` of the pose (H = I) with noise covariance
    /// `noise` (positive definite). The heading of the estimate stays continuous (the
    /// innovation's heading is wrapped). Returns false, changing nothing, when the
    /// innovation covariance cannot be inverted (it can only with a non-finite input).
    pub fn update(&mut self, z: Pose2<T>, noise: &Mat3<T>) -> bool {
        let s = add(&self.cov, noise);
        let Some(s_inv) = inverse(&s) else { return false };
        let k = mul(&self.cov, &s_inv);
        let nu = [z.x - self.mean.x, z.y - self.mean.y, wrap_angle(z.theta - self.mean.theta)];
        let dx: [T; 3] = core::array::from_fn(|i| k[i][0] * nu[0] + k[i][1] * nu[1] + k[i][2] * nu[2]);
        let i_k: Mat3<T> =
            core::array::from_fn(|i| core::array::from_fn(|j| if i == j { T::one() } else { T::zero() } - k[i][j]));
        let joseph = add(&mul(&mul(&i_k, &self.cov), &transpose(&i_k)), &mul(&mul(&k, noise), &transpose(&k)));
        self.cov = symmetrize(&joseph);
        self.mean = Pose2::new(self.mean.x + dx[0], self.mean.y + dx[1], self.mean.theta + dx[2]);
        true
    }
}

/// True when `a` is symmetric (exactly) and positive definite (Sylvester's criterion:
/// every leading principal minor > 0).
pub fn is_symmetric_positive_definite<T: Real>(a: &Mat3<T>) -> bool {
    let symmetric = a[0][1] == a[1][0] && a[0][2] == a[2][0] && a[1][2] == a[2][1];
    let m1 = a[0][0];
    let m2 = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let m3 = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    symmetric && m1 > T::zero() && m2 > T::zero() && m3 > T::zero()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_times_matrix_is_identity() {
        let a: Mat3<f64> = [[4.0, 1.0, 0.5], [1.0, 3.0, -0.2], [0.5, -0.2, 2.0]];
        let b = mul(&a, &inverse(&a).unwrap());
        for (i, row) in b.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                assert!((v - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14, "{b:?}");
            }
        }
        assert!(inverse(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0f64]]).is_none());
    }

    /// A scalar check of the update: with P = p I and R = r I the gain is p / (p + r)
    /// per axis (the textbook Kalman gain), and the posterior variance p r / (p + r).
    fn scalar_gain<T: Real>(tol: T) {
        let (p, r) = (T::lit(0.04), T::lit(0.01));
        let mut ekf = PoseEkf::new(Pose2::default(), diag(p, p, p));
        assert!(ekf.update(Pose2::new(T::one(), T::lit(-2.0), T::lit(0.5)), &diag(r, r, r)));
        let gain = p / (p + r);
        let m = ekf.mean();
        assert!((m.x - gain).abs() < tol && (m.y + T::lit(2.0) * gain).abs() < tol);
        assert!((m.theta - T::lit(0.5) * gain).abs() < tol);
        let post = p * r / (p + r);
        for i in 0..3 {
            assert!((ekf.covariance()[i][i] - post).abs() < tol);
        }
        assert!(is_symmetric_positive_definite(ekf.covariance()));
    }

    #[test]
    fn update_has_the_textbook_gain_f64_and_f32() {
        scalar_gain::<f64>(1e-14);
        scalar_gain::<f32>(1e-6);
    }

    /// The prediction's linearization against finite differences of the arc itself.
    #[test]
    fn prediction_jacobians_match_finite_differences() {
        let big_r = 0.2f64;
        let x0 = Pose2::new(0.3f64, -0.1, 0.8);
        let d = Wheels::new(0.011, 0.007);
        let h = 1e-7;
        // With P = e_i e_i^T (tiny) and Q = 0, F P F^T = F e_i (F e_i)^T: column i of F.
        let mut ekf = PoseEkf::<f64>::new(x0, zero3());
        ekf.predict(d, Wheels::new(1.0, 0.0), big_r);
        // G Q G^T with Q = diag(1, 0): column 0 of G outer itself.
        let a = arc_step(x0, d, big_r);
        let b = arc_step(x0, Wheels::new(d.right + h, d.left), big_r);
        let g0 = [(b.x - a.x) / h, (b.y - a.y) / h, (b.theta - a.theta) / h];
        for i in 0..3 {
            // The Jacobian uses the midpoint form of the arc (sinc = 1): within 1e-4 here.
            assert!((ekf.covariance()[i][i] - g0[i] * g0[i]).abs() < 1e-4, "{i}: {:?} {g0:?}", ekf.covariance());
        }
        let mut ekf = PoseEkf::<f64>::new(x0, diag(1.0, 0.0, 0.0));
        ekf.predict(d, Wheels::new(0.0, 0.0), big_r);
        assert!((ekf.covariance()[0][0] - 1.0).abs() < 1e-15 && ekf.covariance()[1][1].abs() < 1e-15);
        let mut ekf = PoseEkf::<f64>::new(x0, diag(0.0, 0.0, 1.0));
        ekf.predict(d, Wheels::new(0.0, 0.0), big_r);
        let a2 = arc_step(Pose2::new(x0.x, x0.y, x0.theta + h), d, big_r);
        let f2 = [(a2.x - a.x) / h, (a2.y - a.y) / h];
        assert!((ekf.covariance()[0][0] - f2[0] * f2[0]).abs() < 1e-6, "{:?} {f2:?}", ekf.covariance());
        assert!((ekf.covariance()[1][1] - f2[1] * f2[1]).abs() < 1e-6);
    }
}
