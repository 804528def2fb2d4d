//! Forward-mode dual numbers with two derivative components.
//!
//! `Dual2 { re, du, dv }` carries a value and its partial derivatives with
//! respect to two seeded inputs. Because `Dual2<T>` is itself a [`Real`], any
//! generic warp evaluated at `u = Dual2::seed_u(u0)`, `v = Dual2::seed_v(v0)`
//! returns its point *and* the exact partials ∂ψ/∂u, ∂ψ/∂v, rounded only at
//! the precision of `T` — no finite differences.

use super::Real;
use core::cmp::Ordering;
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A value with two partial derivatives.
#[derive(Clone, Debug)]
pub struct Dual2<T> {
    /// The value.
    pub re: T,
    /// Partial derivative with respect to the first seeded input.
    pub du: T,
    /// Partial derivative with respect to the second seeded input.
    pub dv: T,
}

impl<T: Real> Dual2<T> {
    /// A constant: both derivatives zero.
    pub fn constant(re: T) -> Self {
        Dual2 {
            re,
            du: T::zero(),
            dv: T::zero(),
        }
    }
    /// The first independent variable at `re` (∂/∂u = 1).
    pub fn seed_u(re: T) -> Self {
        Dual2 {
            re,
            du: T::one(),
            dv: T::zero(),
        }
    }
    /// The second independent variable at `re` (∂/∂v = 1).
    pub fn seed_v(re: T) -> Self {
        Dual2 {
            re,
            du: T::zero(),
            dv: T::one(),
        }
    }
    /// Applies the chain rule: value `f` with derivative `df` (of the outer
    /// function at `self.re`).
    #[inline]
    fn chain(&self, f: T, df: T) -> Self {
        Dual2 {
            re: f,
            du: self.du.clone() * &df,
            dv: self.dv.clone() * &df,
        }
    }
}

impl<T: Real> fmt::Display for Dual2<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} [+ {} du + {} dv]", self.re, self.du, self.dv)
    }
}

impl<T: Real> PartialEq for Dual2<T> {
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}
impl<T: Real> PartialOrd for Dual2<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<T: Real> Add<&Dual2<T>> for Dual2<T> {
    type Output = Self;
    fn add(self, r: &Self) -> Self {
        Dual2 {
            re: self.re + &r.re,
            du: self.du + &r.du,
            dv: self.dv + &r.dv,
        }
    }
}
impl<T: Real> Sub<&Dual2<T>> for Dual2<T> {
    type Output = Self;
    fn sub(self, r: &Self) -> Self {
        Dual2 {
            re: self.re - &r.re,
            du: self.du - &r.du,
            dv: self.dv - &r.dv,
        }
    }
}
impl<T: Real> Mul<&Dual2<T>> for Dual2<T> {
    type Output = Self;
    fn mul(self, r: &Self) -> Self {
        Dual2 {
            du: self.du * &r.re + &(self.re.clone() * &r.du),
            dv: self.dv * &r.re + &(self.re.clone() * &r.dv),
            re: self.re * &r.re,
        }
    }
}
impl<T: Real> Div<&Dual2<T>> for Dual2<T> {
    type Output = Self;
    fn div(self, r: &Self) -> Self {
        let q = self.re / &r.re;
        Dual2 {
            du: (self.du - &(q.clone() * &r.du)) / &r.re,
            dv: (self.dv - &(q.clone() * &r.dv)) / &r.re,
            re: q,
        }
    }
}

macro_rules! dual_owned_ops {
    ($tr:ident, $m:ident, $tra:ident, $ma:ident) => {
        impl<T: Real> $tr for Dual2<T> {
            type Output = Self;
            #[inline]
            fn $m(self, r: Self) -> Self {
                $tr::$m(self, &r)
            }
        }
        impl<T: Real> $tra for Dual2<T> {
            #[inline]
            fn $ma(&mut self, r: Self) {
                *self = $tr::$m(self.clone(), &r);
            }
        }
        impl<'a, T: Real> $tra<&'a Dual2<T>> for Dual2<T> {
            #[inline]
            fn $ma(&mut self, r: &'a Self) {
                *self = $tr::$m(self.clone(), r);
            }
        }
    };
}
dual_owned_ops!(Add, add, AddAssign, add_assign);
dual_owned_ops!(Sub, sub, SubAssign, sub_assign);
dual_owned_ops!(Mul, mul, MulAssign, mul_assign);
dual_owned_ops!(Div, div, DivAssign, div_assign);

impl<T: Real> Neg for Dual2<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual2 {
            re: -self.re,
            du: -self.du,
            dv: -self.dv,
        }
    }
}

impl<T: Real> Real for Dual2<T> {
    type Wide = Dual2<T::Wide>;
    fn widen(&self) -> Dual2<T::Wide> {
        Dual2 {
            re: self.re.widen(),
            du: self.du.widen(),
            dv: self.dv.widen(),
        }
    }
    fn narrow(w: &Dual2<T::Wide>) -> Self {
        Dual2 {
            re: T::narrow(&w.re),
            du: T::narrow(&w.du),
            dv: T::narrow(&w.dv),
        }
    }
    fn type_name() -> String {
        format!("dual<{}>", T::type_name())
    }
    fn detached(&self) -> Self {
        Dual2::constant(self.re.clone())
    }
    fn precision() -> u32 {
        T::precision()
    }
    fn from_i64(n: i64) -> Self {
        Self::constant(T::from_i64(n))
    }
    fn from_ratio(num: i64, den: i64) -> Self {
        Self::constant(T::from_ratio(num, den))
    }
    fn from_f64(x: f64) -> Self {
        Self::constant(T::from_f64(x))
    }
    fn to_f64(&self) -> f64 {
        self.re.to_f64()
    }
    fn parse_decimal(s: &str) -> Option<Self> {
        T::parse_decimal(s).map(Self::constant)
    }
    fn to_roundtrip_string(&self) -> String {
        self.re.to_roundtrip_string()
    }
    fn pi() -> Self {
        Self::constant(T::pi())
    }
    fn exp2i(e: i32) -> Self {
        Self::constant(T::exp2i(e))
    }
    fn unit_roundoff() -> Self {
        Self::constant(T::unit_roundoff())
    }
    fn max_value() -> Self {
        Self::constant(T::max_value())
    }
    fn is_finite(&self) -> bool {
        self.re.is_finite() && self.du.is_finite() && self.dv.is_finite()
    }
    fn is_nan(&self) -> bool {
        self.re.is_nan()
    }
    fn is_sign_negative(&self) -> bool {
        self.re.is_sign_negative()
    }
    fn abs(&self) -> Self {
        if self.re.is_sign_negative() {
            -self.clone()
        } else {
            self.clone()
        }
    }
    fn sqrt(&self) -> Self {
        let r = self.re.sqrt();
        let d = T::one() / &(r.clone() + &r);
        self.chain(r, d)
    }
    fn cbrt(&self) -> Self {
        let r = self.re.cbrt();
        let d = T::one() / &(T::from_i64(3) * &r * &r);
        self.chain(r, d)
    }
    fn hypot(&self, other: &Self) -> Self {
        let h = self.re.hypot(&other.re);
        if h == T::zero() {
            // Not differentiable at the origin; use the one-sided directional
            // derivative |(ẋ, ẏ)| (zero for constants, never NaN).
            return Dual2 {
                re: h,
                du: self.du.hypot(&other.du),
                dv: self.dv.hypot(&other.dv),
            };
        }
        let a = self.re.clone() / &h;
        let b = other.re.clone() / &h;
        Dual2 {
            du: a.clone() * &self.du + &(b.clone() * &other.du),
            dv: a * &self.dv + &(b * &other.dv),
            re: h,
        }
    }
    fn sin(&self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(s, c)
    }
    fn cos(&self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(c, -s)
    }
    fn sin_cos(&self) -> (Self, Self) {
        let (s, c) = self.re.sin_cos();
        (self.chain(s.clone(), c.clone()), self.chain(c, -s))
    }
    fn tan(&self) -> Self {
        let t = self.re.tan();
        let d = T::one() + &t.square();
        self.chain(t, d)
    }
    fn asin(&self) -> Self {
        let d = T::one() / &(T::one() - &self.re.square()).sqrt();
        self.chain(self.re.asin(), d)
    }
    fn acos(&self) -> Self {
        let d = -(T::one() / &(T::one() - &self.re.square()).sqrt());
        self.chain(self.re.acos(), d)
    }
    fn atan(&self) -> Self {
        let d = T::one() / &(T::one() + &self.re.square());
        self.chain(self.re.atan(), d)
    }
    fn atan2(&self, x: &Self) -> Self {
        // d atan2(y, x) = (x dy − y dx) / (x² + y²)
        let r2 = x.re.square() + &self.re.square();
        let du = (x.re.clone() * &self.du - &(self.re.clone() * &x.du)) / &r2;
        let dv = (x.re.clone() * &self.dv - &(self.re.clone() * &x.dv)) / &r2;
        Dual2 {
            re: self.re.atan2(&x.re),
            du,
            dv,
        }
    }
    fn exp(&self) -> Self {
        let e = self.re.exp();
        self.chain(e.clone(), e)
    }
    fn exp_m1(&self) -> Self {
        let e = self.re.exp_m1();
        let d = e.clone() + &T::one();
        self.chain(e, d)
    }
    fn ln(&self) -> Self {
        let d = T::one() / &self.re;
        self.chain(self.re.ln(), d)
    }
    fn ln_1p(&self) -> Self {
        let d = T::one() / &(T::one() + &self.re);
        self.chain(self.re.ln_1p(), d)
    }
    fn powf(&self, e: &Self) -> Self {
        let p = self.re.powf(&e.re);
        // ∂/∂x x^e = e·x^(e−1); ∂/∂e x^e = x^e·ln x (only when e varies).
        let dx = e.re.clone() * &self.re.powf(&(e.re.clone() - &T::one()));
        let mut out = self.chain(p.clone(), dx);
        if e.du != T::zero() || e.dv != T::zero() {
            let l = p.clone() * &self.re.ln();
            out.du += &(l.clone() * &e.du);
            out.dv += &(l * &e.dv);
        }
        out
    }
    fn powi(&self, n: i32) -> Self {
        let d = if n == 0 {
            T::zero()
        } else {
            T::from_i64(n as i64) * &self.re.powi(n - 1)
        };
        self.chain(self.re.powi(n), d)
    }
    fn floor(&self) -> Self {
        Self::constant(self.re.floor())
    }
}
