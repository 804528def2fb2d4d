//! [`Real`] for MPFR floats of a fixed precision (feature `mpfr`).

use super::Real;
use core::cmp::Ordering;
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use rug::Float;
use rug::float::Constant;
use rug::ops::Pow;

/// An MPFR float with `BITS` significand bits, wrapping [`rug::Float`].
///
/// Every operation rounds to nearest at `BITS` bits, so the same generic code
/// that runs in `f64` runs here with `BITS`-bit accuracy.
///
/// # Example
/// ```
/// use areawarp::real::{Mpfr256, Real};
/// let third = Mpfr256::from_ratio(1, 3);
/// let back = third.clone() * &Mpfr256::from_i64(3);
/// assert!((back - &Mpfr256::one()).abs() <= Mpfr256::unit_roundoff());
/// ```
#[derive(Clone)]
pub struct Mpfr<const BITS: u32>(pub Float);

/// 128-bit MPFR float.
pub type Mpfr128 = Mpfr<128>;
/// 256-bit MPFR float: the reference precision of the checking harness.
pub type Mpfr256 = Mpfr<256>;

impl<const BITS: u32> Mpfr<BITS> {
    /// Wraps any value `rug` can convert, rounded to `BITS` bits.
    pub fn with_val<V>(v: V) -> Self
    where
        Float: rug::Assign<V>,
    {
        Mpfr(Float::with_val(BITS, v))
    }
}

impl<const BITS: u32> fmt::Debug for Mpfr<BITS> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Mpfr<{}>({})", BITS, self.0.to_string_radix(10, None))
    }
}

impl<const BITS: u32> fmt::Display for Mpfr<BITS> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

impl<const BITS: u32> PartialEq for Mpfr<BITS> {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl<const BITS: u32> PartialOrd for Mpfr<BITS> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.0.partial_cmp(&other.0)
    }
}

macro_rules! mpfr_binop {
    ($tr:ident, $m:ident, $tra:ident, $ma:ident) => {
        impl<const BITS: u32> $tr for Mpfr<BITS> {
            type Output = Self;
            #[inline]
            fn $m(self, rhs: Self) -> Self {
                Mpfr(self.0.$m(rhs.0))
            }
        }
        impl<'a, const BITS: u32> $tr<&'a Mpfr<BITS>> for Mpfr<BITS> {
            type Output = Self;
            #[inline]
            fn $m(self, rhs: &'a Self) -> Self {
                Mpfr(self.0.$m(&rhs.0))
            }
        }
        impl<const BITS: u32> $tra for Mpfr<BITS> {
            #[inline]
            fn $ma(&mut self, rhs: Self) {
                self.0.$ma(rhs.0)
            }
        }
        impl<'a, const BITS: u32> $tra<&'a Mpfr<BITS>> for Mpfr<BITS> {
            #[inline]
            fn $ma(&mut self, rhs: &'a Self) {
                self.0.$ma(&rhs.0)
            }
        }
    };
}
mpfr_binop!(Add, add, AddAssign, add_assign);
mpfr_binop!(Sub, sub, SubAssign, sub_assign);
mpfr_binop!(Mul, mul, MulAssign, mul_assign);
mpfr_binop!(Div, div, DivAssign, div_assign);

impl<const BITS: u32> Neg for Mpfr<BITS> {
    type Output = Self;
    fn neg(self) -> Self {
        Mpfr(-self.0)
    }
}

impl<const BITS: u32> Real for Mpfr<BITS> {
    type Wide = Self;
    fn widen(&self) -> Self {
        self.clone()
    }
    fn narrow(w: &Self) -> Self {
        w.clone()
    }
    fn type_name() -> String {
        format!("mpfr:{BITS}")
    }
    fn precision() -> u32 {
        BITS
    }
    fn from_i64(n: i64) -> Self {
        Mpfr(Float::with_val(BITS, n))
    }
    fn from_ratio(num: i64, den: i64) -> Self {
        Mpfr(Float::with_val(BITS, num) / Float::with_val(BITS, den))
    }
    fn from_f64(x: f64) -> Self {
        Mpfr(Float::with_val(BITS, x))
    }
    fn to_f64(&self) -> f64 {
        self.0.to_f64()
    }
    fn parse_decimal(s: &str) -> Option<Self> {
        Float::parse(s.trim())
            .ok()
            .map(|p| Mpfr(Float::with_val(BITS, p)))
    }
    fn to_roundtrip_string(&self) -> String {
        self.0.to_string_radix(10, None)
    }
    fn pi() -> Self {
        Mpfr(Float::with_val(BITS, Constant::Pi))
    }
    fn exp2i(e: i32) -> Self {
        Mpfr(Float::with_val(BITS, Float::i_exp(1, e)))
    }
    fn max_value() -> Self {
        // The largest finite MPFR value at this precision.
        let mut f = Float::with_val(BITS, 1);
        f.next_down();
        Mpfr(f * Float::with_val(BITS, Float::i_exp(1, rug::float::exp_max())))
    }
    fn is_finite(&self) -> bool {
        self.0.is_finite()
    }
    fn is_nan(&self) -> bool {
        self.0.is_nan()
    }
    fn is_sign_negative(&self) -> bool {
        self.0.is_sign_negative()
    }
    fn abs(&self) -> Self {
        Mpfr(self.0.clone().abs())
    }
    fn sqrt(&self) -> Self {
        Mpfr(self.0.clone().sqrt())
    }
    fn cbrt(&self) -> Self {
        Mpfr(self.0.clone().cbrt())
    }
    fn hypot(&self, other: &Self) -> Self {
        Mpfr(self.0.clone().hypot(&other.0))
    }
    fn sin(&self) -> Self {
        Mpfr(self.0.clone().sin())
    }
    fn cos(&self) -> Self {
        Mpfr(self.0.clone().cos())
    }
    fn sin_cos(&self) -> (Self, Self) {
        let (s, c) = self.0.clone().sin_cos(Float::new(BITS));
        (Mpfr(s), Mpfr(c))
    }
    fn tan(&self) -> Self {
        Mpfr(self.0.clone().tan())
    }
    fn asin(&self) -> Self {
        Mpfr(self.0.clone().asin())
    }
    fn acos(&self) -> Self {
        Mpfr(self.0.clone().acos())
    }
    fn atan(&self) -> Self {
        Mpfr(self.0.clone().atan())
    }
    fn atan2(&self, x: &Self) -> Self {
        Mpfr(self.0.clone().atan2(&x.0))
    }
    fn exp(&self) -> Self {
        Mpfr(self.0.clone().exp())
    }
    fn exp_m1(&self) -> Self {
        Mpfr(self.0.clone().exp_m1())
    }
    fn ln(&self) -> Self {
        Mpfr(self.0.clone().ln())
    }
    fn ln_1p(&self) -> Self {
        Mpfr(self.0.clone().ln_1p())
    }
    fn powf(&self, e: &Self) -> Self {
        Mpfr(self.0.clone().pow(&e.0))
    }
    fn powi(&self, n: i32) -> Self {
        Mpfr(self.0.clone().pow(n))
    }
    fn floor(&self) -> Self {
        Mpfr(self.0.clone().floor())
    }
    fn copysign(&self, sign: &Self) -> Self {
        Mpfr(self.0.clone().copysign(&sign.0))
    }
    fn mul_add(&self, a: &Self, b: &Self) -> Self {
        Mpfr(self.0.clone().mul_add(&a.0, &b.0))
    }
}
