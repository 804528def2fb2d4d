//! [`Real`] for the hardware floats `f32` and `f64`.

use super::Real;

/// `2^e` for an exponent outside the normal range (subnormal, zero or
/// infinite result): the rare case of [`Real::exp2i`], kept out of line.
/// Below the normal range, the product of two (normal, or recursively
/// formed) powers of two `2^⌈e/2⌉·2^⌊e/2⌋`: exact where `2^e` is
/// representable, correctly rounded to zero below (`powi` computes
/// `1/2^|e|`, which overflows to zero for `e < −max_exp`).
#[cold]
#[inline(never)]
fn exp2i_outside_normal<T: Real>(e: i32) -> T {
    if e > 0 {
        return T::from_i64(2).powi(e);
    }
    let half = e / 2;
    T::exp2i(half) * &T::exp2i(e - half)
}

macro_rules! impl_real_for_float {
    ($t:ident, $bits:expr, $u:ty $(, rotate: $rotate:path)? $(, polar: $polar:path)?) => {
        impl Real for $t {
            type Wide = f64;
            #[inline]
            fn widen(&self) -> f64 {
                *self as f64
            }
            #[inline]
            fn narrow(w: &f64) -> Self {
                *w as $t
            }
            fn type_name() -> String {
                stringify!($t).to_string()
            }
            #[inline]
            fn precision() -> u32 {
                $bits
            }
            #[inline]
            fn from_i64(n: i64) -> Self {
                n as $t
            }
            #[inline]
            fn from_ratio(num: i64, den: i64) -> Self {
                // Correctly rounded when both integers are exact in the type,
                // which is the case for every constant the crate uses.
                (num as $t) / (den as $t)
            }
            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn to_f64(&self) -> f64 {
                *self as f64
            }
            fn parse_decimal(s: &str) -> Option<Self> {
                s.trim().parse::<$t>().ok()
            }
            fn to_roundtrip_string(&self) -> String {
                // `{:e}` without precision prints the shortest digits that
                // read back to the same value.
                format!("{:e}", self)
            }
            #[inline]
            fn zero() -> Self {
                0.0
            }
            #[inline]
            fn one() -> Self {
                1.0
            }
            #[inline]
            fn pi() -> Self {
                core::$t::consts::PI
            }
            #[inline]
            fn exp2i(e: i32) -> Self {
                // Normal powers of two straight from the bits (no powi call).
                const BIAS: i32 = $t::MAX_EXP - 1;
                if ($t::MIN_EXP - 1..=BIAS).contains(&e) {
                    $t::from_bits(((e + BIAS) as $u) << ($t::MANTISSA_DIGITS - 1))
                } else {
                    // Out of line: LLVM treats `powi` as speculatable and
                    // would otherwise call it on every path, then discard it.
                    exp2i_outside_normal::<$t>(e)
                }
            }
            #[inline]
            fn unit_roundoff() -> Self {
                $t::EPSILON / 2.0
            }
            #[inline]
            fn max_value() -> Self {
                $t::MAX
            }
            #[inline]
            fn is_finite(&self) -> bool {
                $t::is_finite(*self)
            }
            #[inline]
            fn is_nan(&self) -> bool {
                $t::is_nan(*self)
            }
            #[inline]
            fn is_finite_above(&self, lo: &Self) -> bool {
                // For values with the sign bit clear the order of the bits
                // is the order of the values, and every negative value or
                // NaN has bits above +∞'s: `lo < self < ∞` is
                // `bits(lo) < bits(self) < bits(∞)`, one unsigned comparison
                // after the shift by `bits(lo) + 1`.
                let inf = $t::INFINITY.to_bits();
                let lo = lo.to_bits();
                debug_assert!(lo < inf, "is_finite_above: lo must be finite and non-negative");
                self.to_bits().wrapping_sub(lo).wrapping_sub(1) < (inf - lo).wrapping_sub(1)
            }
            #[inline]
            fn is_sign_negative(&self) -> bool {
                $t::is_sign_negative(*self)
            }
            #[inline]
            fn abs(&self) -> Self {
                $t::abs(*self)
            }
            #[inline]
            fn sqrt(&self) -> Self {
                $t::sqrt(*self)
            }
            #[inline]
            fn cbrt(&self) -> Self {
                $t::cbrt(*self)
            }
            #[inline]
            fn hypot(&self, other: &Self) -> Self {
                $t::hypot(*self, *other)
            }
            #[inline]
            fn sin(&self) -> Self {
                $t::sin(*self)
            }
            #[inline]
            fn cos(&self) -> Self {
                $t::cos(*self)
            }
            #[inline]
            fn sin_cos(&self) -> (Self, Self) {
                $t::sin_cos(*self)
            }
            #[inline]
            fn split_quarter_turns(&self) -> (Self, usize) {
                // 1.5·2^(p−1): the sum with 4v ∈ [0, 4] has unit spacing,
                // so it is rounded to an integer, whose low bits are those
                // of the significand.
                let rounder = ((3 as $u) << ($bits - 2)) as $t;
                let shifted = *self + rounder;
                (shifted - rounder, (shifted.to_bits() & 3) as usize)
            }
            $(
                #[inline]
                fn rotate_quarter_turns(&self, a: &Self, b: &Self, _half_pi: &Self) -> (Self, Self) {
                    $rotate(*self, *a, *b)
                }
            )?
            $(
                #[inline]
                fn polar_turns(&self, r: &Self, _half_pi: &Self) -> (Self, Self) {
                    $polar(*self, *r)
                }
            )?
            #[inline]
            fn tan(&self) -> Self {
                $t::tan(*self)
            }
            #[inline]
            fn asin(&self) -> Self {
                $t::asin(*self)
            }
            #[inline]
            fn acos(&self) -> Self {
                $t::acos(*self)
            }
            #[inline]
            fn atan(&self) -> Self {
                $t::atan(*self)
            }
            #[inline]
            fn atan2(&self, x: &Self) -> Self {
                $t::atan2(*self, *x)
            }
            #[inline]
            fn exp(&self) -> Self {
                $t::exp(*self)
            }
            #[inline]
            fn exp_m1(&self) -> Self {
                $t::exp_m1(*self)
            }
            #[inline]
            fn ln(&self) -> Self {
                $t::ln(*self)
            }
            #[inline]
            fn ln_1p(&self) -> Self {
                $t::ln_1p(*self)
            }
            #[inline]
            fn powf(&self, e: &Self) -> Self {
                $t::powf(*self, *e)
            }
            #[inline]
            fn powi(&self, n: i32) -> Self {
                $t::powi(*self, n)
            }
            #[inline]
            fn floor(&self) -> Self {
                $t::floor(*self)
            }
            #[inline]
            fn copysign(&self, sign: &Self) -> Self {
                $t::copysign(*self, *sign)
            }
            #[inline]
            fn mul_add(&self, a: &Self, b: &Self) -> Self {
                // Plain multiply-add: `f64::mul_add` is a slow libm call on
                // targets without FMA, which would tax every sample.
                *self * *a + *b
            }
            #[inline]
            fn min(&self, other: &Self) -> Self {
                $t::min(*self, *other)
            }
            #[inline]
            fn max(&self, other: &Self) -> Self {
                $t::max(*self, *other)
            }
            #[inline]
            fn clamp(&self, lo: &Self, hi: &Self) -> Self {
                // Two selects, each one `maxss`/`minss` (NaN `self` fails
                // `>` and maps to `lo`), where `max`/`min` are NaN-aware
                // sequences of about four instructions each; the same
                // values, but `-0.0` clamped at `lo = 0` is `+0.0`.
                let x = if *self > *lo { *self } else { *lo };
                if x < *hi { x } else { *hi }
            }
            #[inline]
            fn square(&self) -> Self {
                *self * *self
            }
        }
    };
}

impl_real_for_float!(
    f32,
    24,
    u32,
    rotate: super::quarter_turns::rotate_f32,
    polar: super::quarter_turns::polar_turns_f32
);
impl_real_for_float!(f64, 53, u64, rotate: super::quarter_turns::rotate_f64);

#[cfg(test)]
mod tests {
    use crate::real::Real;

    /// The branch-free `clamp` of `f32`/`f64` agrees with the trait's
    /// default (NaN to `lo`, infinities to the bounds; the sign of a zero
    /// may differ).
    #[test]
    fn float_clamp_matches_the_default() {
        fn default_clamp(x: f64, lo: f64, hi: f64) -> f64 {
            if x.is_nan() || x < lo {
                lo
            } else if x > hi {
                hi
            } else {
                x
            }
        }
        let xs = [
            f64::NAN,
            f64::NEG_INFINITY,
            -1.0,
            -0.0,
            0.0,
            f64::from_bits(1),
            0.5,
            1.0 - f64::EPSILON / 2.0,
            1.0,
            1.5,
            f64::INFINITY,
        ];
        for x in xs {
            let want = default_clamp(x, 0.0, 1.0);
            let got = Real::clamp(&x, &0.0, &1.0);
            assert_eq!(got, want, "f64 {x}");
            let got32 = Real::clamp(&(x as f32), &0.0, &1.0);
            assert_eq!(got32, want as f32, "f32 {x}");
        }
    }

    /// The bit comparison of `is_finite_above` answers `lo < x < ∞` for
    /// every `x` (NaN of either sign, infinities, zeros, subnormals, the
    /// extremes) and every non-negative finite `lo` among them.
    #[test]
    fn is_finite_above_matches_the_comparisons() {
        let xs = [
            f64::NAN,
            -f64::NAN,
            f64::NEG_INFINITY,
            -f64::MAX,
            -1.0,
            -f64::from_bits(1),
            -0.0,
            0.0,
            f64::from_bits(1),
            f64::MIN_POSITIVE,
            f64::EPSILON,
            0.5,
            1.0,
            f64::MAX,
            f64::INFINITY,
        ];
        let los = [0.0, f64::from_bits(1), f64::EPSILON.powi(4), 1.0, f64::MAX];
        for lo in los {
            for x in xs {
                let want = x > lo && x.is_finite();
                assert_eq!(Real::is_finite_above(&x, &lo), want, "f64 {x} above {lo}");
                let (x32, lo32) = (x as f32, (lo as f32).min(f32::MAX));
                let want32 = x32 > lo32 && x32.is_finite();
                assert_eq!(
                    Real::is_finite_above(&x32, &lo32),
                    want32,
                    "f32 {x32} above {lo32}"
                );
            }
        }
    }
}
