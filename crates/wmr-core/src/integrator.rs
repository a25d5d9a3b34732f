//! Classic fourth-order Runge-Kutta with a fixed step, on a fixed-size array (no heap).

use crate::Real;

/// One classic RK4 step of `y' = f(t, y)` from `(t, y)` over `h`; returns y(t + h).
///
/// Local error O(h^5), global error O(h^4). `f` is called four times.
#[inline(always)]
pub fn rk4_step<T: Real, const N: usize>(mut f: impl FnMut(T, &[T; N]) -> [T; N], t: T, y: &[T; N], h: T) -> [T; N] {
    let two = T::lit(2.0);
    let half_h = h / two;
    let sixth_h = h / T::lit(6.0);
    let k1 = f(t, y);
    let y2: [T; N] = core::array::from_fn(|i| y[i] + half_h * k1[i]);
    let k2 = f(t + half_h, &y2);
    let y3: [T; N] = core::array::from_fn(|i| y[i] + half_h * k2[i]);
    let k3 = f(t + half_h, &y3);
    let y4: [T; N] = core::array::from_fn(|i| y[i] + h * k3[i]);
    let k4 = f(t + h, &y4);
    core::array::from_fn(|i| y[i] + sixth_h * (k1[i] + two * (k2[i] + k3[i]) + k4[i]))
}

/// Where classic RK4's stability region meets the negative real axis: a decay
/// y' = -lambda y is integrated stably (and, since the amplification factor stays
/// positive there, without sign flips) exactly when h lambda < 2.785293563405282.
pub const RK4_REAL_STABILITY_LIMIT: f64 = 2.785_293_563_405_282;

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = y, y(0) = 1: RK4 with h = 0.1 matches the 4th-order Taylor polynomial per step.
    #[test]
    fn exponential_one_step_is_taylor_4() {
        let h = 0.1_f64;
        let y = rk4_step(|_, y: &[f64; 1]| [y[0]], 0.0, &[1.0], h);
        let taylor = 1.0 + h + h * h / 2.0 + h.powi(3) / 6.0 + h.powi(4) / 24.0;
        assert!((y[0] - taylor).abs() < 1e-15);
    }
}
