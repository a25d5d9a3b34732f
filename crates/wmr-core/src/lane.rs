//! Numbers that may be several runs at once: the [`Lane`] trait the equations that run
//! in lanes are written against, for one run (`f32`, `f64`: every [`Real`]) and for
//! [`Lanes`]`<N>`, N runs side by side in `f64`.
//!
//! Why: a sweep runs thousands of independent runs of the same loop. Stepping N of them
//! in lockstep turns each arithmetic operation into one SIMD instruction over N runs.
//! The equations are written once, against this trait; a branch on the state becomes a
//! [`Lane::select`] (both sides computed, one kept per lane), a branch on a parameter
//! stays a branch. For a [`Real`] every operation is the scalar one, in the same order,
//! with the same `libm` transcendentals: the exact path is unchanged, bit for bit.
//!
//! [`Lanes`] has its own transcendentals (Cody-Waite reduction and Cephes polynomials,
//! branch-free so they vectorize), accurate to a few ulp rather than `libm`'s correctly
//! rounded-in-practice results: the fast path is close to the exact one, not identical.

// Index loops over fixed-size arrays: the form the compiler unrolls into SIMD lanes. The
// constants are written as their sources (fdlibm, Cephes) print them.
#![allow(clippy::needless_range_loop, clippy::excessive_precision)]

use core::fmt::Debug;
use core::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use crate::Real;

/// A boolean per lane: `bool` for one run, [`LaneMask`] for [`Lanes`].
pub trait Mask: Copy + Debug + PartialEq + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> {
    /// True in every lane.
    fn all(self) -> bool;
    /// True in at least one lane.
    fn any(self) -> bool;
    /// `b` in every lane.
    fn splat(b: bool) -> Self;
}

impl Mask for bool {
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn splat(b: bool) -> Self {
        b
    }
}

/// One run's number ([`Real`]) or several runs' ([`Lanes`]): what the lane-generic
/// equations compute with. Parameters stay [`Lane::Scalar`] (shared by every lane) and
/// enter through [`Lane::splat`].
pub trait Lane:
    Copy
    + Debug
    + Default
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
    + 'static
{
    /// The number of one lane.
    type Scalar: Real;
    /// A boolean per lane.
    type Mask: Mask;

    /// Every lane `x`.
    fn splat(x: Self::Scalar) -> Self;
    /// Every lane the `f64` constant `x` (rounded as [`Real::lit`]).
    #[inline(always)]
    fn lit(x: f64) -> Self {
        Self::splat(<Self::Scalar as Real>::lit(x))
    }
    /// Per lane: `if m { a } else { b }`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// `*self = select(m, new, *self)`, with a plain store where every lane takes `new`
    /// (the common case): the compiler turns a select into the place it reads from into
    /// a masked store, which costs more than the rest of a lanes' step on x86.
    #[inline(always)]
    fn assign_where(&mut self, m: Self::Mask, new: Self) {
        *self = if m.all() { new } else { Self::select(m, new, *self) };
    }
    /// self < o per lane.
    fn lt(self, o: Self) -> Self::Mask;
    /// self <= o per lane.
    fn le(self, o: Self) -> Self::Mask;
    /// self == o per lane.
    fn eq(self, o: Self) -> Self::Mask;
    /// |self|.
    fn abs(self) -> Self;
    /// The smaller of two (`Float::min` for one run).
    fn min(self, o: Self) -> Self;
    /// The larger of two (`Float::max` for one run).
    fn max(self, o: Self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Largest whole number <= self.
    fn floor(self) -> Self;
    /// self / d, where `inv_d` = 1 / d: one run divides (its bits are the exact path's);
    /// lanes multiply by the reciprocal (within 1 ulp of the quotient), since a vector
    /// division costs several products' time and sits on the plant's critical path.
    fn div_by(self, d: Self::Scalar, inv_d: Self::Scalar) -> Self;
    /// (sin, cos) of an angle in rad.
    fn sin_cos(self) -> (Self, Self);
    /// cos of an angle in rad.
    fn cos(self) -> Self;
    /// atan2(self, x), rad in (-pi, pi].
    fn atan2(self, x: Self) -> Self;
    /// sqrt(self^2 + y^2).
    fn hypot(self, y: Self) -> Self;
    /// Hyperbolic tangent.
    fn tanh(self) -> Self;
    /// self^y (`libm`'s pow in every lane: not vectorized; the graceful law's only).
    fn powf(self, y: Self) -> Self;
    /// Finite per lane (not NaN, not infinite).
    fn is_finite(self) -> Self::Mask;
    /// How many runs side by side: 1 for a [`Real`], N for [`Lanes`]`<N>`.
    const WIDTH: usize;
    /// Lane `i` (< [`Lane::WIDTH`]) alone: for a law that runs each lane's run by itself
    /// (MPPI, [`crate::controller::mppi`]).
    fn lane(self, i: usize) -> Self::Scalar;
    /// Sets lane `i` (< [`Lane::WIDTH`]) to `x`, the other lanes kept.
    fn set_lane(&mut self, i: usize, x: Self::Scalar);
}

impl<T: Real> Lane for T {
    type Scalar = T;
    type Mask = bool;

    #[inline(always)]
    fn splat(x: T) -> Self {
        x
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn le(self, o: Self) -> bool {
        self <= o
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self == o
    }
    #[inline(always)]
    fn abs(self) -> Self {
        num_traits::Float::abs(self)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        num_traits::Float::min(self, o)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        num_traits::Float::max(self, o)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        num_traits::Float::sqrt(self)
    }
    #[inline(always)]
    fn floor(self) -> Self {
        num_traits::Float::floor(self)
    }
    #[inline(always)]
    fn div_by(self, d: T, _inv_d: T) -> Self {
        self / d
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        self.sin_cos_libm()
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.cos_libm()
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        self.atan2_libm(x)
    }
    #[inline(always)]
    fn hypot(self, y: Self) -> Self {
        self.hypot_libm(y)
    }
    #[inline(always)]
    fn tanh(self) -> Self {
        self.tanh_libm()
    }
    #[inline(always)]
    fn powf(self, y: Self) -> Self {
        self.powf_libm(y)
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        num_traits::Float::is_finite(self)
    }
    const WIDTH: usize = 1;
    #[inline(always)]
    fn lane(self, _i: usize) -> T {
        self
    }
    #[inline(always)]
    fn set_lane(&mut self, _i: usize, x: T) {
        *self = x;
    }
}

/// N runs' `f64`s side by side. Every operation is a loop over the lanes that the
/// compiler turns into SIMD instructions (4 lanes per AVX2 register).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct Lanes<const N: usize>(pub [f64; N]);

/// A boolean per lane of [`Lanes`], stored as SIMD compare results are: all ones
/// (true) or all zeros (false) per 64-bit lane, so a select is a bitwise blend and a
/// compare is one instruction (a `[bool; N]` costs a conversion each way).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C, align(32))]
pub struct LaneMask<const N: usize>([u64; N]);

impl<const N: usize> LaneMask<N> {
    /// The mask of `bools`.
    #[inline(always)]
    pub fn from_bools(bools: [bool; N]) -> Self {
        let mut out = [0; N];
        for i in 0..N {
            out[i] = u64::from(bools[i]).wrapping_neg();
        }
        LaneMask(out)
    }

    /// True in lane `i` only.
    #[inline(always)]
    pub fn lane_only(i: usize) -> Self {
        let mut out = [0; N];
        out[i] = !0;
        LaneMask(out)
    }

    /// Lane `i`.
    #[inline(always)]
    pub fn lane(self, i: usize) -> bool {
        self.0[i] != 0
    }
}

impl<const N: usize> Default for Lanes<N> {
    fn default() -> Self {
        Lanes([0.0; N])
    }
}

// Plain loops over the lanes (not `array::from_fn`, which the compiler may leave as a
// call): each unrolls into SIMD instructions.
impl<const N: usize> Lanes<N> {
    /// ln x per lane for positive normal numbers (what a uniform draw in (0, 1] is; zero,
    /// negative, subnormal, infinite or NaN lanes give meaningless numbers): fdlibm's
    /// algorithm, branch-free, within 1 ulp of `libm::log`. MPPI's noise draws with it.
    #[inline(always)]
    pub fn ln(self) -> Self {
        self.map(ln_lane)
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        let mut out = [0.0; N];
        for i in 0..N {
            out[i] = f(self.0[i]);
        }
        Lanes(out)
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        let mut out = [0.0; N];
        for i in 0..N {
            out[i] = f(self.0[i], o.0[i]);
        }
        Lanes(out)
    }
    #[inline(always)]
    fn test(self, o: Self, f: impl Fn(f64, f64) -> bool) -> LaneMask<N> {
        let mut out = [0; N];
        for i in 0..N {
            out[i] = u64::from(f(self.0[i], o.0[i])).wrapping_neg();
        }
        LaneMask(out)
    }
}

macro_rules! lanes_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<const N: usize> $tr for Lanes<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
    };
}
lanes_op!(Add, add, +);
lanes_op!(Sub, sub, -);
lanes_op!(Mul, mul, *);
lanes_op!(Div, div, /);

impl<const N: usize> Neg for Lanes<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<const N: usize> BitAnd for LaneMask<N> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        let mut out = self.0;
        for i in 0..N {
            out[i] &= o.0[i];
        }
        LaneMask(out)
    }
}
impl<const N: usize> BitOr for LaneMask<N> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        let mut out = self.0;
        for i in 0..N {
            out[i] |= o.0[i];
        }
        LaneMask(out)
    }
}
impl<const N: usize> Not for LaneMask<N> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        let mut out = self.0;
        for i in 0..N {
            out[i] = !out[i];
        }
        LaneMask(out)
    }
}
impl<const N: usize> Mask for LaneMask<N> {
    #[inline(always)]
    fn all(self) -> bool {
        let mut acc = !0;
        for i in 0..N {
            acc &= self.0[i];
        }
        acc != 0
    }
    #[inline(always)]
    fn any(self) -> bool {
        let mut acc = 0;
        for i in 0..N {
            acc |= self.0[i];
        }
        acc != 0
    }
    #[inline(always)]
    fn splat(b: bool) -> Self {
        LaneMask([u64::from(b).wrapping_neg(); N])
    }
}

/// 1.5 * 2^52: x + ROUNDER - ROUNDER rounds |x| < 2^51 to the nearest whole number (ties
/// to even), and the low bits of x + ROUNDER hold that number.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// pi/2 in three parts (fdlibm's pio2_1, pio2_2, pio2_2t): j * PIO2_1 and j * PIO2_2
/// are exact for whole j < 2^20, so the reduction of an angle below about 1.6e6 rad
/// keeps full precision.
const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11;
const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;

/// sin on [-pi/4, pi/4]: x + x^3 P(x^2) (Cephes `sin.c`).
#[inline(always)]
fn sin_poly(r: f64, z: f64) -> f64 {
    const S: [f64; 6] = [
        1.589_623_015_765_465_680_60e-10,
        -2.505_074_776_285_780_728_66e-8,
        2.755_731_362_138_572_452_13e-6,
        -1.984_126_982_958_953_859_96e-4,
        8.333_333_333_322_118_588_78e-3,
        -1.666_666_666_666_663_072_95e-1,
    ];
    let p = ((((S[0] * z + S[1]) * z + S[2]) * z + S[3]) * z + S[4]) * z + S[5];
    r + r * z * p
}

/// cos on [-pi/4, pi/4]: 1 - x^2/2 + x^4 Q(x^2) (Cephes `sin.c`).
#[inline(always)]
fn cos_poly(z: f64) -> f64 {
    const C: [f64; 6] = [
        -1.135_853_652_138_768_173_00e-11,
        2.087_570_084_197_473_167_78e-9,
        -2.755_731_417_929_673_881_12e-7,
        2.480_158_728_885_170_453_48e-5,
        -1.388_888_888_887_305_641_16e-3,
        4.166_666_666_666_659_292_18e-2,
    ];
    let q = ((((C[0] * z + C[1]) * z + C[2]) * z + C[3]) * z + C[4]) * z + C[5];
    1.0 - 0.5 * z + z * z * q
}

/// atan(lo / hi) for 0 <= lo <= hi, with one division (fdlibm's `atan`, whose range
/// reduction divides again after the caller's lo / hi): below 7/16 the ratio itself;
/// below 11/16 atan(1/2) + atan((2 lo - hi) / (2 hi + lo)); above, pi/4 + atan((lo - hi)
/// / (lo + hi)); then fdlibm's polynomial in t^2, split in two for parallel products.
/// lo = hi = 0 gives 0. Whole-vector steps, each a loop the compiler vectorizes (a
/// per-lane function with branches did not).
#[inline(always)]
fn atan_ratio<const N: usize>(lo: Lanes<N>, hi: Lanes<N>) -> Lanes<N> {
    const AT: [f64; 11] = [
        3.333_333_333_333_293_180_27e-1,
        -1.999_999_999_987_648_324_76e-1,
        1.428_571_427_250_346_637_11e-1,
        -1.111_111_040_546_235_578_80e-1,
        9.090_887_133_436_506_561_96e-2,
        -7.691_876_205_044_829_994_95e-2,
        6.661_073_137_387_531_206_69e-2,
        -5.833_570_133_790_573_486_45e-2,
        4.976_877_994_615_932_360_17e-2,
        -3.653_157_274_421_691_552_70e-2,
        1.628_582_011_536_578_236_23e-2,
    ];
    /// atan(1/2) and atan(1) in two parts each (high, low).
    const HALF: (f64, f64) = (4.636_476_090_008_060_935_15e-1, 2.269_877_745_296_168_709_24e-17);
    const ONE: (f64, f64) = (core::f64::consts::FRAC_PI_4, 3.061_616_997_868_383_017_93e-17);
    let l = |x: f64| Lanes::<N>::splat(x);
    let zero = hi.eq(l(0.0));
    let small = lo.lt(l(0.4375) * hi) | zero;
    let middle = lo.lt(l(0.6875) * hi);
    let pick = |a: f64, b: f64, c: f64| Lanes::select(small, l(a), Lanes::select(middle, l(b), l(c)));
    let num = Lanes::select(small, lo, Lanes::select(middle, l(2.0) * lo - hi, lo - hi));
    let den = Lanes::select(small, hi, Lanes::select(middle, l(2.0) * hi + lo, lo + hi));
    let t = Lanes::select(zero, l(0.0), num / den);
    let (base, tail) = (pick(0.0, HALF.0, ONE.0), pick(0.0, HALF.1, ONE.1));
    let z = t * t;
    let w = z * z;
    let s1 = z * (l(AT[0]) + w * (l(AT[2]) + w * (l(AT[4]) + w * (l(AT[6]) + w * (l(AT[8]) + w * l(AT[10]))))));
    let s2 = w * (l(AT[1]) + w * (l(AT[3]) + w * (l(AT[5]) + w * (l(AT[7]) + w * l(AT[9])))));
    base - ((t * (s1 + s2) - tail) - t)
}

/// ln x for a positive normal x, fdlibm's `__ieee754_log` without its special cases: x =
/// 2^k (1 + f) with 1 + f in [sqrt(2)/2, sqrt(2)), s = f / (2 + f), and ln(1 + f) =
/// f - (f^2/2 - s (f^2/2 + R(s^2))) with fdlibm's degree-14 polynomial R; within 1 ulp
/// of `libm::log` (tests below). Branch-free, so it vectorizes.
#[inline(always)]
fn ln_lane(x: f64) -> f64 {
    const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
    const LG: [f64; 7] = [
        6.666_666_666_666_735_130e-1,
        3.999_999_999_940_941_908e-1,
        2.857_142_874_366_239_149e-1,
        2.222_219_843_214_978_396e-1,
        1.818_357_216_161_805_012e-1,
        1.531_383_769_920_937_332e-1,
        1.479_819_860_511_658_591e-1,
    ];
    let bits = x.to_bits();
    // fdlibm's reduction on the high word: shift the mantissa's range to start at sqrt(2)/2.
    let hx = (bits >> 32).wrapping_add(0x3ff0_0000 - 0x3fe6_a09e);
    let k = ((hx >> 20) as i64 - 0x3ff) as f64;
    let hx = (hx & 0x000f_ffff) + 0x3fe6_a09e;
    let m = f64::from_bits((hx << 32) | (bits & 0xffff_ffff));
    let f = m - 1.0;
    let hfsq = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG[1] + w * (LG[3] + w * LG[5]));
    let t2 = z * (LG[0] + w * (LG[2] + w * (LG[4] + w * LG[6])));
    let r = t2 + t1;
    k * LN2_HI - ((hfsq - (s * (hfsq + r) + k * LN2_LO)) - f)
}

/// e^x for |x| <= 708 (clamped beyond): x = n ln 2 + r, |r| <= ln2 / 2, a degree-13
/// Taylor polynomial of e^r, times 2^n built from its bits.
#[inline(always)]
fn exp_lane(x: f64) -> f64 {
    const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
    let x = x.clamp(-708.0, 708.0);
    let shifted = x * core::f64::consts::LOG2_E + ROUNDER;
    let n = shifted - ROUNDER;
    let r = (x - n * LN2_HI) - n * LN2_LO;
    let mut p = 1.0 / 6_227_020_800.0;
    for k in (1..13).rev() {
        p = p * r + 1.0 / FACTORIALS[k];
    }
    let e_r = p * r + 1.0;
    // The low bits of `shifted` hold n mod 2^11; n + 1023 is the biased exponent of 2^n.
    let biased = ((shifted.to_bits() & 0x7ff) + 1023) & 0x7ff;
    e_r * f64::from_bits(biased << 52)
}

/// The square root of each lane, correctly rounded (IEEE 754): the same bits as the
/// scalar `sqrt` of the exact path. On x86-64 through the SSE2 intrinsic, which the
/// compiler emits as a vector `vsqrtpd` in code compiled for AVX2 or AVX-512 (and merges
/// pairs into wider registers): the `libm` crate's `sqrt` is inline assembly, a scalar
/// legacy-SSE `sqrtsd` per lane, which the compiler can neither vectorize nor re-encode.
#[inline(always)]
fn sqrt_lanes<const N: usize>(x: [f64; N]) -> [f64; N] {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
    #[allow(unsafe_code)]
    {
        use core::arch::x86_64::{_mm_cvtsd_f64, _mm_set_pd, _mm_sqrt_pd, _mm_unpackhi_pd};
        let mut out = [0.0; N];
        let mut i = 0;
        while i < N {
            let hi = if i + 1 < N { x[i + 1] } else { 0.0 };
            // SAFETY: SSE2 is enabled for this build (the cfg above; every x86-64 has
            // it), and these intrinsics only compute on registers.
            let (lo, hi) = unsafe {
                let r = _mm_sqrt_pd(_mm_set_pd(hi, x[i]));
                (_mm_cvtsd_f64(r), _mm_cvtsd_f64(_mm_unpackhi_pd(r, r)))
            };
            out[i] = lo;
            if i + 1 < N {
                out[i + 1] = hi;
            }
            i += 2;
        }
        out
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
    {
        x.map(num_traits::Float::sqrt)
    }
}

/// k! for k = 0..13.
const FACTORIALS: [f64; 13] =
    [1.0, 1.0, 2.0, 6.0, 24.0, 120.0, 720.0, 5040.0, 40320.0, 362_880.0, 3_628_800.0, 39_916_800.0, 479_001_600.0];

impl<const N: usize> Lane for Lanes<N> {
    type Scalar = f64;
    type Mask = LaneMask<N>;
    const WIDTH: usize = N;

    #[inline(always)]
    fn lane(self, i: usize) -> f64 {
        self.0[i]
    }
    #[inline(always)]
    fn set_lane(&mut self, i: usize, x: f64) {
        self.0[i] = x;
    }

    #[inline(always)]
    fn splat(x: f64) -> Self {
        Lanes([x; N])
    }
    #[inline(always)]
    fn select(m: LaneMask<N>, a: Self, b: Self) -> Self {
        let mut out = [0.0; N];
        for i in 0..N {
            out[i] = f64::from_bits((a.0[i].to_bits() & m.0[i]) | (b.0[i].to_bits() & !m.0[i]));
        }
        Lanes(out)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> LaneMask<N> {
        self.test(o, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, o: Self) -> LaneMask<N> {
        self.test(o, |a, b| a <= b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> LaneMask<N> {
        self.test(o, |a, b| a == b)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        self.zip(o, f64::min)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.zip(o, f64::max)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Lanes(sqrt_lanes(self.0))
    }
    #[inline(always)]
    fn floor(self) -> Self {
        // Round |x| to nearest by adding and taking off 2^52, then down where that went
        // up: no library call, so it vectorizes. From 2^52 on every f64 is whole.
        const TWO_52: f64 = 4_503_599_627_370_496.0;
        self.map(|x| {
            let r = ((x.abs() + TWO_52) - TWO_52).copysign(x);
            let r = if r > x { r - 1.0 } else { r };
            if x.abs() < TWO_52 { r } else { x }
        })
    }
    #[inline(always)]
    fn div_by(self, _d: f64, inv_d: f64) -> Self {
        self * Lanes::splat(inv_d)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        // Quadrant j = round(x 2/pi) (ROUNDER), r = x - j pi/2 in [-pi/4, pi/4] (PIO2_*),
        // the two polynomials, then the quadrant's swap and signs, all without a branch;
        // written as whole-vector steps, each a loop the compiler turns into SIMD
        // instructions (a per-lane function returning a pair does not vectorize).
        let shifted = self.map(|x| x * core::f64::consts::FRAC_2_PI + ROUNDER);
        let j = shifted.map(|s| s - ROUNDER);
        let r = self.zip(j, |x, j| ((x - j * PIO2_1) - j * PIO2_2) - j * PIO2_2T);
        let z = r * r;
        let s = r.zip(z, sin_poly);
        let c = z.map(cos_poly);
        let (mut sin, mut cos) = ([0.0; N], [0.0; N]);
        for i in 0..N {
            let q = shifted.0[i].to_bits();
            // Odd quadrants swap sin and cos (a bitwise blend, so it vectorizes).
            let swap = (q & 1).wrapping_neg();
            let (s, c) = (s.0[i].to_bits(), c.0[i].to_bits());
            let (a, b) = ((c & swap) | (s & !swap), (s & swap) | (c & !swap));
            // Bit 1 of q (and of q + 1) is the sign of sin (cos): moved to the sign bit.
            sin[i] = f64::from_bits(a ^ ((q & 2) << 62));
            cos[i] = f64::from_bits(b ^ ((q.wrapping_add(1) & 2) << 62));
        }
        (Lanes(sin), Lanes(cos))
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.sin_cos().1
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        // atan of min/max of |y|, |x| (in [0, 1]), then the octant, as whole-vector steps.
        let (ay, ax) = (self.abs(), x.abs());
        let (hi, lo) = (ay.max(ax), ay.min(ax));
        let t = atan_ratio(lo, hi);
        let t = Lanes::select(ax.lt(ay), Lanes::splat(core::f64::consts::FRAC_PI_2) - t, t);
        let t = x.zip(t, |x, t| if x.is_sign_negative() { core::f64::consts::PI - t } else { t });
        self.zip(t, |y, t| if y.is_sign_negative() { -t } else { t })
    }
    #[inline(always)]
    fn hypot(self, y: Self) -> Self {
        (self * self + y * y).sqrt()
    }
    #[inline(always)]
    fn tanh(self) -> Self {
        // 1 - 2 / (e^(2x) + 1): -1 and 1 at the ends, no NaN.
        self.map(|a| 1.0 - 2.0 / (exp_lane(a + a) + 1.0))
    }
    #[inline(always)]
    fn powf(self, y: Self) -> Self {
        self.zip(y, libm::pow)
    }
    #[inline(always)]
    fn is_finite(self) -> LaneMask<N> {
        // 0 x is (+-)0 for a finite x and NaN for an infinite or NaN one.
        (self * Lanes::splat(0.0)).eq(Lanes::splat(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_is_within_an_ulp_of_libm() {
        // Uniform draws in (0, 1] as MPPI makes them, and a spread of magnitudes.
        let mut h: u64 = 0x1234_5678;
        let mut worst = 0.0f64;
        for k in 0..200_000u64 {
            h = h.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            let x = if k % 2 == 0 {
                ((h >> 11) + 1) as f64 * (1.0 / 9_007_199_254_740_992.0)
            } else {
                f64::from_bits(0x0010_0000_0000_0000 + (h >> 2) % 0x7fd0_0000_0000_0000)
            };
            let want = libm::log(x);
            let got = Lanes::<1>([x]).ln().0[0];
            let ulp = f64::from_bits(want.abs().to_bits() + 1) - want.abs();
            worst = worst.max((got - want).abs() / ulp);
        }
        assert!(worst <= 1.0, "worst error {worst} ulp");
    }

    /// Relative (or, near zero, absolute) distance in ulp-ish units of 1e-16.
    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1.0)
    }

    /// Each transcendental against `libm` over the angles and ratios a run meets, and
    /// far beyond: every quadrant, both signs, the octant edges of atan2.
    #[test]
    fn lane_transcendentals_match_libm() {
        let mut worst = [0.0_f64; 5];
        for k in -200_000..=200_000 {
            let x = f64::from(k) * 1.37e-4 + 1e-9 * f64::from(k % 7);
            let (s, c) = Lanes::<1>([x]).sin_cos();
            let (ls, lc) = libm::sincos(x);
            worst[0] = worst[0].max((s.0[0] - ls).abs());
            worst[1] = worst[1].max((c.0[0] - lc).abs());
            let y = f64::from(k % 1000) * 3.1e-3 - 1.5;
            let a = Lanes::<1>([y]).atan2(Lanes([x]));
            worst[2] = worst[2].max((a.0[0] - libm::atan2(y, x)).abs());
            let t = x * 0.05;
            let th = Lanes::<1>([t]).tanh();
            worst[3] = worst[3].max((th.0[0] - libm::tanh(t)).abs());
            let e = exp_lane(t);
            worst[4] = worst[4].max(((e - libm::exp(t)) / libm::exp(t)).abs());
        }
        // At most 2 ulp of the result: sin, cos, tanh within 1 of magnitude 1, atan2 up to pi.
        let bounds = [4.5e-16, 4.5e-16, 9e-16, 4.5e-16, 4.5e-16];
        for ((name, w), bound) in ["sin", "cos", "atan2", "tanh", "exp (rel)"].iter().zip(worst).zip(bounds) {
            assert!(w <= bound, "{name}: worst error {w:e}");
        }
        // Edges: zeros, exact quadrant angles, huge and tiny arguments of tanh.
        let atan2 = |y: f64, x: f64| Lanes::<1>([y]).atan2(Lanes([x])).0[0];
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert!(close(atan2(1.0, -1.0), 3.0 * core::f64::consts::FRAC_PI_4, 1e-16));
        assert!(close(atan2(-1.0, 0.0), -core::f64::consts::FRAC_PI_2, 1e-16));
        assert_eq!(Lanes::<1>([1e6]).tanh().0[0], 1.0);
        assert_eq!(Lanes::<1>([-1e6]).tanh().0[0], -1.0);
        assert!(close(Lanes::<1>([core::f64::consts::PI]).sin_cos().1.0[0], -1.0, 1e-16));
    }

    /// The lanes' square root (a vector instruction on x86-64) is `libm`'s, bit for bit,
    /// in every lane of an odd and an even width: correctly rounded both, including the
    /// edges (signed zero, subnormal, infinity, NaN for a negative).
    #[test]
    fn lane_sqrt_is_libm_sqrt_bit_for_bit() {
        let mut xs = [0.0, -0.0, 5e-324, 2.2e-308, 1e-300, 0.25, 2.0, 3.0, 1e300, f64::MAX, f64::INFINITY, -1.0];
        let bits = |x: f64| if x.is_nan() { u64::MAX } else { x.to_bits() };
        for k in 0..20_000_u32 {
            // The edges first, then each slot in turn takes new values.
            if k > 0 {
                xs[k as usize % 12] = f64::from(k) * 0.731 + 1e-7 * f64::from(k % 13);
            }
            let five = Lanes::<5>([xs[0], xs[1], xs[2], xs[3], xs[4]]).sqrt();
            let eight = Lanes::<8>(core::array::from_fn(|i| xs[i + 4])).sqrt();
            for (i, r) in five.0.iter().enumerate() {
                assert_eq!(bits(*r), bits(libm::sqrt(xs[i])), "sqrt({:e})", xs[i]);
            }
            for (i, r) in eight.0.iter().enumerate() {
                assert_eq!(bits(*r), bits(libm::sqrt(xs[i + 4])), "sqrt({:e})", xs[i + 4]);
            }
        }
        let h = Lanes::<3>([3.0, 1e-200, -0.0]).hypot(Lanes([4.0, 1e-200, 0.0]));
        assert_eq!(h.0, [5.0, libm::sqrt(1e-200 * 1e-200 + 1e-200 * 1e-200), 0.0]);
    }

    /// The scalar implementation is the plain arithmetic and `libm`: bit for bit.
    #[test]
    fn scalar_lanes_are_the_scalar_operations() {
        for x in [-3.0_f64, -0.2, 0.0, 0.7, 2.9, 1e3] {
            assert_eq!(Lane::sin_cos(x), libm::sincos(x));
            assert_eq!(Lane::atan2(x, 0.3), libm::atan2(x, 0.3));
            assert_eq!(Lane::tanh(x), libm::tanh(x));
            assert_eq!(Lane::hypot(x, 0.3), libm::hypot(x, 0.3));
        }
        assert_eq!(<f64 as Lane>::select(true, 1.0, 2.0), 1.0);
        for x in [
            -3.5,
            -3.0,
            -2.9999999999999996,
            -0.5,
            -0.0,
            0.0,
            0.5,
            0.9999999999999999,
            2.5,
            7.0,
            1e300,
            -1e300,
            4.5e15 + 0.5,
        ] {
            assert_eq!(Lanes::<1>([x]).floor().0[0], libm::floor(x), "floor({x})");
        }
        let m = Lanes([1.0, 5.0]).lt(Lanes([2.0, 2.0]));
        assert_eq!(Lanes::select(m, Lanes([10.0, 20.0]), Lanes([30.0, 40.0])), Lanes([10.0, 40.0]));
    }

    /// Masks: finiteness, a select that keeps every bit (signed zeros, NaN), the lane
    /// logic, and the conversions the batch uses.
    #[test]
    fn masks_per_lane() {
        let x = Lanes([0.0, -0.0, 1e308, -5e-324, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, -1.0]);
        let finite = x.is_finite();
        let expected = [true, true, true, true, false, false, false, true];
        assert_eq!(finite, LaneMask::from_bools(expected));
        for (i, e) in expected.iter().enumerate() {
            assert_eq!(finite.lane(i), *e, "lane {i}");
            assert_eq!(finite.lane(i), x.0[i].is_finite(), "lane {i}");
        }
        let picked = Lanes::select(finite, x, Lanes::splat(7.0));
        let bits = |l: Lanes<8>| l.0.map(f64::to_bits);
        let want = [0.0, -0.0, 1e308, -5e-324, 7.0, 7.0, 7.0, -1.0];
        assert_eq!(bits(picked), want.map(f64::to_bits));
        let nan_kept = Lanes::select(!finite, x, Lanes::splat(0.0));
        assert!(nan_kept.0[6].is_nan() && nan_kept.0[4] == f64::INFINITY && nan_kept.0[0] == 0.0);
        assert!(finite.any() && !finite.all() && (finite | !finite).all() && !(finite & !finite).any());
        assert_eq!(
            LaneMask::<8>::lane_only(4),
            LaneMask::from_bools([false, false, false, false, true, false, false, false])
        );
        assert!(LaneMask::<8>::splat(true).all() && !LaneMask::<8>::splat(false).any());
    }
}
