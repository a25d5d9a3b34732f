//! Classic fourth-order Runge-Kutta with a fixed step, on a fixed-size array (no heap).

// Index loops over fixed-size arrays: the form the compiler unrolls into SIMD lanes.
#![allow(clippy::needless_range_loop)]

use crate::lane::Lane;

/// One classic RK4 step of `y' = f(t, y)` from `(t, y)` over `h`; returns y(t + h).
///
/// Local error O(h^5), global error O(h^4). `f` is called four times.
#[inline(always)]
pub fn rk4_step<T: Lane, const N: usize>(f: impl FnMut(T, &[T; N]) -> [T; N], t: T, y: &[T; N], h: T) -> [T; N] {
    rk4_step_of(&mut FnRhs(f), t, y, h)
}

/// The right-hand side f(t, y) of y' = f(t, y), for [`rk4_step_of`].
pub trait Rhs<T, const N: usize> {
    /// f(t, y).
    fn eval(&mut self, t: T, y: &[T; N]) -> [T; N];
}

/// A closure as a [`Rhs`].
struct FnRhs<F>(F);

impl<T, const N: usize, F: FnMut(T, &[T; N]) -> [T; N]> Rhs<T, N> for FnRhs<F> {
    #[inline(always)]
    fn eval(&mut self, t: T, y: &[T; N]) -> [T; N] {
        (self.0)(t, y)
    }
}

/// [`rk4_step`] of a [`Rhs`]: a type whose `eval` is `#[inline(always)]` is inlined into
/// the step for certain (a closure may be left as a call, which the lanes of
/// [`crate::batch`] cannot afford: a call is compiled without the caller's SIMD features).
#[inline(always)]
pub fn rk4_step_of<T: Lane, const N: usize>(f: &mut impl Rhs<T, N>, t: T, y: &[T; N], h: T) -> [T; N] {
    let two = T::lit(2.0);
    let half_h = h / two;
    let sixth_h = h / T::lit(6.0);
    // The four stages in a loop: `f` is inlined once, not four times (in the lanes'
    // kernels `f` is the plant's whole model: four copies were 39 % of each kernel's
    // unoptimized code). The same operations in the same order as the four written out.
    let mut k = [*y; 4];
    let (mut t_stage, mut y_stage) = (t, *y);
    for stage in 0..4 {
        k[stage] = f.eval(t_stage, &y_stage);
        if stage < 3 {
            let a = if stage == 2 { h } else { half_h };
            y_stage = axpy(y, a, &k[stage]);
            t_stage = t + a;
        }
    }
    let [k1, k2, k3, k4] = k;
    let mut next = *y;
    for i in 0..N {
        next[i] = y[i] + sixth_h * (k1[i] + two * (k2[i] + k3[i]) + k4[i]);
    }
    next
}

/// y + a k, component by component.
#[inline(always)]
fn axpy<T: Lane, const N: usize>(y: &[T; N], a: T, k: &[T; N]) -> [T; N] {
    let mut out = *y;
    for i in 0..N {
        out[i] = y[i] + a * k[i];
    }
    out
}

/// Where classic RK4's stability region meets the negative real axis: a decay
/// y' = -lambda y is integrated stably (and, since the amplification factor stays
/// positive there, without sign flips) exactly when h lambda < 2.785293563405282.
pub const RK4_REAL_STABILITY_LIMIT: f64 = 2.785_293_563_405_282;

/// The radius of the largest half-disk of the left half-plane inside classic RK4's
/// stability region (its boundary comes closest to the origin at 122.7 deg, at
/// 2.6155876882): an oscillation y'' + beta y' + omega^2 y = 0 with complex roots (modulus
/// omega) is integrated stably when h omega is below it.
pub const RK4_HALF_DISK_RADIUS: f64 = 2.615_587_688_235_293_8;

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
