//! The small dense linear algebra of the fit: symmetric eigenvalues (Jacobi) and a
//! symmetric solve, for the few (at most 8) parameters of a robot.

/// A p x p matrix, row-major.
pub type Square = Vec<Vec<f64>>;

/// Eigenvalues and eigenvectors (columns of the second result) of the symmetric `a`, by
/// cyclic Jacobi rotations (Golub and Van Loan, "Matrix Computations", section 8.5):
/// exact to rounding for the small, well-scaled Gram matrices of the fit.
pub fn symmetric_eigen(a: &Square) -> (Vec<f64>, Square) {
    let p = a.len();
    let mut a = a.clone();
    let mut v: Square = (0..p).map(|i| (0..p).map(|j| if i == j { 1.0 } else { 0.0 }).collect()).collect();
    for _sweep in 0..100 {
        let off: f64 = (0..p)
            .flat_map(|i| (0..p).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let diag: f64 = (0..p).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-30 * diag.max(1e-300) {
            break;
        }
        for i in 0..p {
            for j in i + 1..p {
                if a[i][j] == 0.0 {
                    continue;
                }
                // The rotation that zeroes a[i][j]: tan(2 phi) = 2 a_ij / (a_jj - a_ii).
                let theta = (a[j][j] - a[i][i]) / (2.0 * a[i][j]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..p {
                    let (aki, akj) = (a[k][i], a[k][j]);
                    a[k][i] = c * aki - s * akj;
                    a[k][j] = s * aki + c * akj;
                }
                for k in 0..p {
                    let (aik, ajk) = (a[i][k], a[j][k]);
                    a[i][k] = c * aik - s * ajk;
                    a[j][k] = s * aik + c * ajk;
                }
                for k in 0..p {
                    let (vki, vkj) = (v[k][i], v[k][j]);
                    v[k][i] = c * vki - s * vkj;
                    v[k][j] = s * vki + c * vkj;
                }
            }
        }
    }
    ((0..p).map(|i| a[i][i]).collect(), v)
}

/// The inverse of the symmetric positive definite `a` from its eigen-decomposition
/// (all eigenvalues > 0, checked by the caller through the condition number).
pub fn spd_inverse(values: &[f64], vectors: &Square) -> Square {
    let p = values.len();
    (0..p).map(|i| (0..p).map(|j| (0..p).map(|k| vectors[i][k] * vectors[j][k] / values[k]).sum()).collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A V D V^T built from known eigenpairs gives them back, and the inverse times the
    /// matrix is the identity.
    #[test]
    fn eigen_of_a_known_matrix() {
        let a = vec![vec![4.0, 1.0, 0.5], vec![1.0, 3.0, 0.25], vec![0.5, 0.25, 2.0]];
        let (vals, vecs) = symmetric_eigen(&a);
        for k in 0..3 {
            for i in 0..3 {
                let av: f64 = (0..3).map(|j| a[i][j] * vecs[j][k]).sum();
                assert!((av - vals[k] * vecs[i][k]).abs() < 1e-12);
            }
        }
        let trace: f64 = vals.iter().sum();
        assert!((trace - 9.0).abs() < 1e-12);
        let inv = spd_inverse(&vals, &vecs);
        for i in 0..3 {
            for j in 0..3 {
                let e: f64 = (0..3).map(|k| inv[i][k] * a[k][j]).sum();
                assert!((e - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
    }
}
