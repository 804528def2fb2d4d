//! The scalar layer: one trait, [`Real`], implemented by `f32`, `f64`,
//! `Mpfr<BITS>` (feature `mpfr`) and the forward-mode
//! dual numbers [`Dual2<T>`] used for exact partial derivatives.
//!
//! The trait is `Clone`-based (MPFR floats are heap values, not `Copy`), takes
//! `&self` in every method and supports arithmetic with a reference on the
//! right-hand side (`a.clone() * &b`). Constants are built *exactly*, from
//! integers, ratios and [`Real::pi`], never from decimal `f64` literals: a
//! literal such as `0.1` would silently cap a 256-bit computation at 53 bits.
//! Tolerances also come from the type ([`Real::unit_roundoff`]).

mod dual;
mod float;
#[cfg(feature = "mpfr")]
mod mpfr;
mod quarter_turns;

pub use dual::Dual2;
#[cfg(feature = "mpfr")]
pub use mpfr::{Mpfr, Mpfr128, Mpfr256};

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real scalar type: `f32`, `f64`, an MPFR float of fixed precision, or a
/// dual number over one of these.
///
/// Comparison operators compare values (for [`Dual2`], the real parts).
pub trait Real:
    Clone
    + Debug
    + Display
    + PartialEq
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + for<'a> Add<&'a Self, Output = Self>
    + for<'a> Sub<&'a Self, Output = Self>
    + for<'a> Mul<&'a Self, Output = Self>
    + for<'a> Div<&'a Self, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + for<'a> AddAssign<&'a Self>
    + for<'a> SubAssign<&'a Self>
    + for<'a> MulAssign<&'a Self>
    + for<'a> DivAssign<&'a Self>
{
    /// The scalar in which constructors take their decisions and compute
    /// the constants that cancellation would spoil: `f64` for `f32` and for
    /// `f64`, the type itself for MPFR, `Dual2<T::Wide>` for [`Dual2<T>`].
    ///
    /// A shape built in `f32` thereby accepts exactly what the `f64`
    /// constructor accepts on the same values, and its constants are the
    /// `f64` values correctly rounded to `f32`; the per-sample arithmetic
    /// stays in `Self`.
    type Wide: Real;
    /// `self` in [`Real::Wide`] (exact).
    fn widen(&self) -> Self::Wide;
    /// `w` rounded to the nearest value of `Self`.
    fn narrow(w: &Self::Wide) -> Self;

    /// A short name of the type for reports: `f32`, `f64`, `mpfr:256`, ….
    fn type_name() -> String;
    /// Number of significand bits `p` (24 for `f32`, 53 for `f64`, `BITS` for MPFR).
    fn precision() -> u32;
    /// The integer `n`, exactly (rounded only if `|n|` exceeds the precision).
    fn from_i64(n: i64) -> Self;
    /// The ratio `num / den`, correctly rounded.
    fn from_ratio(num: i64, den: i64) -> Self {
        Self::from_i64(num) / Self::from_i64(den)
    }
    /// Converts an `f64` *value* (data, e.g. a vertex read from input) to this
    /// type: exact for `f64` and MPFR, rounded to nearest for `f32`.
    /// Not for constants in generic code: use [`Real::from_ratio`].
    fn from_f64(x: f64) -> Self;
    /// Nearest `f64` (for dual numbers: of the real part).
    fn to_f64(&self) -> f64;
    /// Parses a decimal string directly in this precision (correctly rounded,
    /// as `str::parse::<f32>` does for `f32`).
    fn parse_decimal(s: &str) -> Option<Self>;
    /// A decimal string that parses back to exactly this value.
    fn to_roundtrip_string(&self) -> String;

    /// Zero.
    fn zero() -> Self {
        Self::from_i64(0)
    }
    /// One.
    fn one() -> Self {
        Self::from_i64(1)
    }
    /// π, correctly rounded.
    fn pi() -> Self;
    /// `2^e`, exactly.
    fn exp2i(e: i32) -> Self;
    /// The unit roundoff `u = 2^-p`: the relative error bound of one correctly
    /// rounded operation. Tolerances in generic code are multiples of it.
    fn unit_roundoff() -> Self {
        Self::exp2i(-(Self::precision() as i32))
    }
    /// Largest finite value.
    fn max_value() -> Self;
    /// `4 / max_value()`: about the smallest normal number (2^(emin + 1)
    /// for IEEE types), the floor under which products and quotients of
    /// small terms may turn subnormal.
    fn normal_floor() -> Self {
        Self::from_i64(4) / &Self::max_value()
    }

    /// `2^p / max` (`p` the precision): below it a value's own roundoff
    /// is lost to underflow (`f32`, `f64`; out of reach for MPFR).
    fn precision_floor() -> Self {
        Self::exp2i(Self::precision() as i32) / &Self::max_value()
    }

    /// `true` if neither infinite nor NaN.
    fn is_finite(&self) -> bool;
    /// `true` if NaN.
    fn is_nan(&self) -> bool;
    /// `lo < self < ∞` for a non-negative finite `lo` (not `-0`); `false`
    /// for NaN. The constructors' range tests ("positive and finite",
    /// "neither tiny nor infinite"): `f32` and `f64` answer with one integer
    /// comparison of the bits, where the two floating-point tests compile
    /// to a dozen instructions of classification.
    fn is_finite_above(&self, lo: &Self) -> bool {
        *self > *lo && self.is_finite()
    }
    /// `true` if the sign bit is set (including `-0`).
    fn is_sign_negative(&self) -> bool;

    /// Absolute value.
    fn abs(&self) -> Self;
    /// Square root.
    fn sqrt(&self) -> Self;
    /// Cube root.
    fn cbrt(&self) -> Self;
    /// `sqrt(self² + other²)` without undue overflow or underflow.
    fn hypot(&self, other: &Self) -> Self;
    /// Sine.
    fn sin(&self) -> Self;
    /// Cosine.
    fn cos(&self) -> Self;
    /// Sine and cosine together.
    fn sin_cos(&self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// For `self = 4v`, `v ∈ [0, 1]` (an angle in quarter turns): the
    /// integer `q` nearest `self` (ties to even), as a constant (for
    /// [`Dual2`] the derivative stays in `self − q`), and `q mod 4`.
    /// `self − q ∈ [−1/2, 1/2]` is then exact (Sterbenz).
    ///
    /// `f32` and `f64` add and subtract `1.5·2^(p−1)`, which rounds to an
    /// integer held in the low bits of the sum's significand (no `floor`
    /// call, no saturating float-to-integer conversion). The default does
    /// the same in `Self` for `p ≤ 53`, and otherwise goes through the
    /// `f64` nearest `self`, whose `q` may be one off the integer nearest
    /// `self` when `self` is within `2^-53` of a half-integer: `self − q`
    /// then lies just beyond ±1/2, which changes nothing (the same angle,
    /// sine and cosine well conditioned there). NaN gives a NaN `q` (the
    /// quadrant is then arbitrary).
    fn split_quarter_turns(&self) -> (Self, usize) {
        if Self::precision() <= 53 {
            let rounder = Self::from_i64(3) * &Self::exp2i(Self::precision() as i32 - 2);
            // q as a constant, through f64 (exact).
            let q = ((self.clone() + &rounder) - &rounder).to_f64();
            // A NaN q casts to 0.
            (Self::from_f64(q), (q as i64 & 3) as usize)
        } else {
            // 1.5·2^52.
            let rounder = (3u64 << 51) as f64;
            let shifted = self.to_f64() + rounder;
            (
                Self::from_f64(shifted - rounder),
                (shifted.to_bits() & 3) as usize,
            )
        }
    }
    /// The point `(a, b)` rotated by the angle `(π/2)·self`, for a reduced
    /// argument `|self| ≤ 1/2` (in quarter turns): `(a·c − b·s, a·s + b·c)`
    /// with `(s, c) = sin_cos((π/2)·self)`; `half_pi` is π/2 in this type.
    ///
    /// The default rounds the angle and calls [`Real::sin_cos`] (dual
    /// numbers carry the derivative of `self`, `a` and `b`). `f32` and `f64`
    /// evaluate minimax polynomials of the reduced argument instead (`f32`
    /// in `f64`, each coordinate rounded once; `f64` with its leading terms
    /// kept exact), more accurate than the library route and without its
    /// call and second range reduction (`real::quarter_turns`). Larger
    /// `|self|` is outside the contract (the polynomials lose accuracy
    /// there). NaN gives NaN.
    #[inline]
    fn rotate_quarter_turns(&self, a: &Self, b: &Self, half_pi: &Self) -> (Self, Self) {
        let (s, c) = (self.clone() * half_pi).sin_cos();
        (c.clone() * a - &(s.clone() * b), s * a + &(c * b))
    }
    /// `(r cos 2πv, r sin 2πv)` for `self = v ∈ [0, 1]` (an angle in turns),
    /// reduced exactly by quarter turns (`docs/quarter-turns.md`): `q` and
    /// `q mod 4` from [`Real::split_quarter_turns`] of `4v` (`4v` and
    /// `4v − q` are exact, the latter by Sterbenz's lemma), `r` times the exact cosine and
    /// sine of `qπ/2` (values in `{0, ±r}`), rotated by the reduced angle
    /// with [`Real::rotate_quarter_turns`]; `half_pi` is π/2 in this type.
    ///
    /// `f32` does the same in `f64` from the products `r·cos(qπ/2)`,
    /// `r·sin(qπ/2)` (exact in `f32` and in `f64`): the same values, bit for
    /// bit, without converting the quadrant's cosine and sine to `f32` and
    /// the products back. NaN `v` gives NaN coordinates.
    #[inline]
    fn polar_turns(&self, r: &Self, half_pi: &Self) -> (Self, Self) {
        // cos(qπ/2) and sin(qπ/2) by q mod 4.
        const COS_Q: [f64; 4] = [1.0, 0.0, -1.0, 0.0];
        const SIN_Q: [f64; 4] = [0.0, 1.0, 0.0, -1.0];
        let four_v = self.clone() * &Self::from_i64(4);
        let (q, quadrant) = four_v.split_quarter_turns();
        let reduced = four_v - &q;
        // r·i^q: exact.
        let rc = r.clone() * &Self::from_f64(COS_Q[quadrant]);
        let rs = r.clone() * &Self::from_f64(SIN_Q[quadrant]);
        // r (c + i s)·i^q: one of rc, rs is ±0, so each coordinate is one
        // rounded product (only the sign of a zero coordinate may differ
        // from a rotation by swaps and negations).
        reduced.rotate_quarter_turns(&rc, &rs, half_pi)
    }
    /// Tangent.
    fn tan(&self) -> Self;
    /// Arcsine.
    fn asin(&self) -> Self;
    /// Arccosine.
    fn acos(&self) -> Self;
    /// Arctangent.
    fn atan(&self) -> Self;
    /// Four-quadrant arctangent of `self / x`.
    fn atan2(&self, x: &Self) -> Self;
    /// `e^self`.
    fn exp(&self) -> Self;
    /// `e^self − 1`, accurate near zero.
    fn exp_m1(&self) -> Self;
    /// Natural logarithm.
    fn ln(&self) -> Self;
    /// `ln(1 + self)`, accurate near zero.
    fn ln_1p(&self) -> Self;
    /// `self^e`.
    fn powf(&self, e: &Self) -> Self;
    /// `self^n` for an integer `n`.
    fn powi(&self, n: i32) -> Self;
    /// Largest integer not greater than `self`.
    fn floor(&self) -> Self;
    /// `|self|` with the sign of `sign`.
    fn copysign(&self, sign: &Self) -> Self {
        let a = self.abs();
        if sign.is_sign_negative() { -a } else { a }
    }
    /// `self·a + b` (fused where the type supports it).
    fn mul_add(&self, a: &Self, b: &Self) -> Self {
        self.clone() * a + b
    }
    /// The smaller of two values (NaN-ignoring like `f64::min`).
    fn min(&self, other: &Self) -> Self {
        if other < self || self.is_nan() {
            other.clone()
        } else {
            self.clone()
        }
    }
    /// The larger of two values (NaN-ignoring like `f64::max`).
    fn max(&self, other: &Self) -> Self {
        if other > self || self.is_nan() {
            other.clone()
        } else {
            self.clone()
        }
    }
    /// `self` clamped to `[lo, hi]` (NaN maps to `lo`).
    fn clamp(&self, lo: &Self, hi: &Self) -> Self {
        if self.is_nan() || self < lo {
            lo.clone()
        } else if self > hi {
            hi.clone()
        } else {
            self.clone()
        }
    }
    /// `self²`.
    fn square(&self) -> Self {
        self.clone() * self
    }
    /// The value alone, as a constant: `self` for plain scalars, the real
    /// part with zero derivatives for [`Dual2`]. Lets a numerical inversion
    /// state its derivative (1/F' at the root it returns) instead of
    /// inheriting whatever its iterations carried.
    fn detached(&self) -> Self {
        self.clone()
    }
}

/// Scalars `Self` into which the constants of a shape stored as `T` can be
/// embedded: `T` itself, and [`Dual2<T>`] (a constant with zero derivative).
///
/// Generic recipe code written as `fn phi<S: Embed<T>>(&self, s: &S, t: &S)`
/// runs unchanged in `T` and in dual numbers, which is how
/// [`Parametrization::partials`](crate::recipe::Parametrization::partials)
/// gets exact derivatives.
pub trait Embed<T: Real>: Real {
    /// `x` as a value of `Self`.
    fn embed(x: &T) -> Self;
}

impl<T: Real> Embed<T> for T {
    #[inline]
    fn embed(x: &T) -> Self {
        x.clone()
    }
}
impl<T: Real> Embed<T> for Dual2<T> {
    fn embed(x: &T) -> Self {
        Dual2::constant(x.clone())
    }
}

/// Converts between two scalar types through their decimal round-trip
/// representations when needed; exact from `f32`/`f64` into `f64` or MPFR.
pub fn convert<A: Real, B: Real>(x: &A) -> B {
    if A::precision() <= 53 {
        B::from_f64(x.to_f64())
    } else {
        B::parse_decimal(&x.to_roundtrip_string()).unwrap_or_else(|| B::from_f64(x.to_f64()))
    }
}
