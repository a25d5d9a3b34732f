//! Speeds and accelerations from noisy samples: a centred Savitzky-Golay filter on the
//! log's own (possibly uneven) time stamps.
//!
//! At sample i a polynomial p(s) = c0 + c1 s + ... + c_q s^q (degree q = 5 for angles,
//! 4 for speeds: [`crate::fit::ANGLE_DEGREE`]) is fitted by least squares to the 2h + 1
//! samples i - h ..= i + h, in s = (t_j - t_i) / T with T the largest |t_j - t_i| of the
//! window (so the normal matrix stays well scaled); then the value, first and second
//! derivative at t_i are c0, c1 / T and 2 c2 / T^2. On an even grid this is exactly the
//! Savitzky-Golay filter (Savitzky and Golay, Anal. Chem. 36 (1964) 1627); on uneven
//! stamps (timing jitter) it stays the least-squares local fit, where a fixed
//! convolution kernel would not.
//!
//! Bias (docs/identify.md, "Noise and bias"): the fit is exact for polynomials up to its
//! degree, so on an even grid with spacing dt and half-width h the leading error of the
//! acceleration is the next even term of the Taylor series:
//!
//! ```text
//! degree 2, 3: phi'' + phi^(4) dt^2 K4(h) / 12
//! degree 4, 5: phi'' + phi^(6) dt^4 K6(h) / 360
//! ```
//!
//! with K_k(h) the coefficient of j^2 when j^k is fitted by the even powers below k over
//! j = -h..=h ([`acceleration_bias_factor`]). Degree 5 is used: a wheel accelerated by a
//! voltage step decays as e^(-t/tau) (tau = 0.17 s for the DC motor of the tests), and
//! the cubic's bias dt^2 K4 / (12 tau^2) (2.7 % at h = 10, dt = 10 ms) showed as a 15 %
//! error of the small wheel inertia; the quintic's is (dt / tau)^4 K6 / 360 at
//! h = 15 (about 0.09 %). A step of the command (a jump of phi'') is still smeared over the window: rows
//! within h samples of a jump are left out of the fit ([`mod@crate::fit`]). The first and
//! last h rows of a run have no centred window and are left out too.

/// The value, first and second derivative of a local polynomial fit at each sample
/// (NaN for the h samples at each end, which have no centred window).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Derivatives {
    /// Smoothed value.
    pub value: Vec<f64>,
    /// First derivative (per s).
    pub d1: Vec<f64>,
    /// Second derivative (per s^2); NaN for degree < 2.
    pub d2: Vec<f64>,
    /// The variance of the samples about the local fits, the mean of RSS / (N - p) over
    /// the windows: an estimate of the measurement noise's variance (plus what the
    /// polynomial cannot follow).
    pub noise_var: f64,
}

/// Fits a polynomial of `degree` (1..=5) over the centred window of `half` samples on each
/// side of every sample of `y` taken at `t_s` (strictly increasing).
pub fn local_polynomial(t_s: &[f64], y: &[f64], half: usize, degree: usize) -> Derivatives {
    let n = t_s.len();
    let p = degree + 1;
    let mut out =
        Derivatives { value: vec![f64::NAN; n], d1: vec![f64::NAN; n], d2: vec![f64::NAN; n], noise_var: f64::NAN };
    if n < 2 * half + 1 {
        return out;
    }
    let (mut rss_sum, mut windows) = (0.0, 0usize);
    for i in half..n - half {
        let t0 = t_s[i];
        let scale = (t_s[i + half] - t0).max(t0 - t_s[i - half]);
        // Normal equations of the local fit: A^T A c = A^T y, A_jk = s_j^k.
        let mut ata = [[0.0f64; 6]; 6];
        let mut aty = [0.0f64; 6];
        for j in i - half..=i + half {
            let s = (t_s[j] - t0) / scale;
            let mut pow = [1.0f64; 11];
            for k in 1..11 {
                pow[k] = pow[k - 1] * s;
            }
            for a in 0..p {
                aty[a] += pow[a] * y[j];
                for b in 0..p {
                    ata[a][b] += pow[a + b];
                }
            }
        }
        let Some(c) = solve_small(&mut ata, &mut aty, p) else { continue };
        let mut rss = 0.0;
        for j in i - half..=i + half {
            let s = (t_s[j] - t0) / scale;
            let fit = c.iter().rev().fold(0.0, |acc, &ck| acc * s + ck);
            rss += (y[j] - fit).powi(2);
        }
        rss_sum += rss / (2 * half + 1 - p) as f64;
        windows += 1;
        out.value[i] = c[0];
        out.d1[i] = c[1] / scale;
        if degree >= 2 {
            out.d2[i] = 2.0 * c[2] / (scale * scale);
        }
    }
    out.noise_var = rss_sum / windows.max(1) as f64;
    out
}

/// K_k(h) of the module's bias formula: the coefficient of j^2 when j^k (k = 4 or 6) is
/// fitted by least squares by the even powers below k over j = -h..=h. The acceleration
/// of a centred window of half-width `half` samples is off by phi^(k) dt^(k-2) K_k(h) /
/// (k! / 2) to leading order (degree k - 2 or k - 1).
pub fn acceleration_bias_factor(half: usize, k: usize) -> f64 {
    let h = half as i64;
    let s = |p: usize| (-h..=h).map(|j| (j as f64).powi(p as i32)).sum::<f64>();
    let m = k / 2; // the even powers 0, 2, .., k - 2: m unknowns
    let mut a = [[0.0f64; 6]; 6];
    let mut b = [0.0f64; 6];
    for r in 0..m {
        for c in 0..m {
            a[r][c] = s(2 * r + 2 * c);
        }
        b[r] = s(2 * r + k);
    }
    solve_small(&mut a, &mut b, m).map_or(f64::NAN, |x| x[1])
}

/// Solves the `p` x `p` system by Gaussian elimination with partial pivoting; None if
/// singular.
fn solve_small(a: &mut [[f64; 6]; 6], b: &mut [f64; 6], p: usize) -> Option<[f64; 6]> {
    for col in 0..p {
        let piv = (col..p).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..p {
            let f = a[row][col] / a[col][col];
            for k in col..p {
                a[row][k] -= f * a[col][k];
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0f64; 6];
    for row in (0..p).rev() {
        let mut s = b[row];
        for k in row + 1..p {
            s -= a[row][k] * x[k];
        }
        x[row] = s / a[row][row];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cubic is fitted exactly by the degree-3 filter, on uneven stamps: the derivatives
    /// equal the closed forms.
    #[test]
    fn a_cubic_is_differentiated_exactly_on_uneven_stamps() {
        let t: Vec<f64> = (0..50).map(|i| 0.01 * i as f64 + 0.004 * ((i * 7 % 5) as f64) / 5.0).collect();
        let f = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + 0.5 * t * t * t;
        let y: Vec<f64> = t.iter().map(|&t| f(t)).collect();
        let d = local_polynomial(&t, &y, 5, 3);
        for i in 5..45 {
            let ti = t[i];
            assert!((d.value[i] - f(ti)).abs() < 1e-9);
            assert!((d.d1[i] - (2.0 - 6.0 * ti + 1.5 * ti * ti)).abs() < 1e-7, "{i}");
            assert!((d.d2[i] - (-6.0 + 3.0 * ti)).abs() < 1e-5, "{i}");
        }
        assert!(d.value[0].is_nan() && d.d2[49].is_nan());
    }

    /// On an even grid, the acceleration of sin(w t) carries the stated bias
    /// phi^(k) dt^(k-2) K_k(h) / (k! / 2) to leading order, for the cubic (k = 4) and the
    /// quintic (k = 6); and K_4 has its closed form (N S6 - S2 S4) / (N S4 - S2^2).
    #[test]
    fn the_acceleration_bias_is_the_stated_one() {
        let (dt, h, w) = (0.01, 15usize, 3.0);
        let t: Vec<f64> = (0..200).map(|i| dt * i as f64).collect();
        let y: Vec<f64> = t.iter().map(|&t| (w * t).sin()).collect();
        let i = 100;
        let sin = (w * t[i]).sin();
        for (degree, k, derivative, factorial_half) in [(3, 4, w.powi(4) * sin, 12.0), (5, 6, -w.powi(6) * sin, 360.0)]
        {
            let d = local_polynomial(&t, &y, h, degree);
            let predicted = derivative * dt.powi(k as i32 - 2) * acceleration_bias_factor(h, k) / factorial_half;
            let bias = d.d2[i] - (-w * w * sin);
            assert!(
                (bias - predicted).abs() < 0.05 * predicted.abs(),
                "degree {degree}: bias {bias} predicted {predicted}"
            );
        }
        let hh = h as i64;
        let s = |p: i32| (-hh..=hh).map(|j| (j as f64).powi(p)).sum::<f64>();
        let n = (2 * h + 1) as f64;
        let closed = (n * s(6) - s(2) * s(4)) / (n * s(4) - s(2) * s(2));
        assert!((acceleration_bias_factor(h, 4) - closed).abs() < 1e-9 * closed);
    }
}
