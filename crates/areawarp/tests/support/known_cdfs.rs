//! CDFs with known inverses, generic over the scalar, and the points y
//! the inverters are tested at (for `tests/inverters.rs`).

use areawarp::real::Real;
use areawarp::recipe::Cdf1;

// ---------------------------------------------------------------------------
// CDFs with known inverses, generic over the scalar.

/// F_a(x) = expm1(a x) / expm1(a) on [0, 1]; inverse ln_1p(y expm1(a)) / a.
#[derive(Clone, Debug)]
pub struct ExpCdf<T> {
    a: T,
    em1a: T,
}

impl<T: Real> ExpCdf<T> {
    pub fn new(a: f64) -> Self {
        let a = T::from_f64(a);
        let em1a = a.exp_m1();
        ExpCdf { a, em1a }
    }
}

/// F(x) = x^n on [0, 1]; inverse y^(1/n).
#[derive(Clone, Debug)]
pub struct PowCdf {
    pub n: i32,
}

/// F(x) = sin²(πx/2) on [0, 1]; inverse (2/π) asin(√y).
#[derive(Clone, Debug)]
pub struct Sin2Cdf;

/// A CDF with a known inverse (the test oracle).
pub trait Known<T: Real>: Cdf1<T> {
    fn inverse(&self, y: &T) -> T;
}

impl<T: Real> Cdf1<T> for ExpCdf<T> {
    fn cdf(&self, x: &T) -> T {
        (self.a.clone() * x).exp_m1() / &self.em1a
    }
    fn pdf(&self, x: &T) -> T {
        self.a.clone() * &(self.a.clone() * x).exp() / &self.em1a
    }
    fn closed_form_inverse(&self, y: &T) -> Option<T> {
        Some(self.inverse(y))
    }
}
impl<T: Real> Known<T> for ExpCdf<T> {
    fn inverse(&self, y: &T) -> T {
        (y.clone() * &self.em1a).ln_1p() / &self.a
    }
}

impl<T: Real> Cdf1<T> for PowCdf {
    fn cdf(&self, x: &T) -> T {
        x.powi(self.n)
    }
    fn pdf(&self, x: &T) -> T {
        T::from_i64(self.n as i64) * &x.powi(self.n - 1)
    }
}
impl<T: Real> Known<T> for PowCdf {
    fn inverse(&self, y: &T) -> T {
        y.powf(&T::from_ratio(1, self.n as i64))
    }
}

impl<T: Real> Cdf1<T> for Sin2Cdf {
    fn cdf(&self, x: &T) -> T {
        (T::pi() * x / T::from_i64(2)).sin().square()
    }
    fn pdf(&self, x: &T) -> T {
        let (s, c) = (T::pi() * x / T::from_i64(2)).sin_cos();
        T::pi() * &s * &c
    }
}
impl<T: Real> Known<T> for Sin2Cdf {
    fn inverse(&self, y: &T) -> T {
        y.sqrt().asin() * &T::from_i64(2) / &T::pi()
    }
}

/// A CDF flat on [0, 1/2]: F = 0 there, then ((2x − 1))³. Its fitted cubic
/// is degenerate and F' vanishes on half the domain.
#[derive(Clone, Debug)]
pub struct FlatThenCubic;

impl<T: Real> Cdf1<T> for FlatThenCubic {
    fn cdf(&self, x: &T) -> T {
        let z = (T::from_i64(2) * x - T::one()).max(&T::zero());
        z.powi(3)
    }
    fn pdf(&self, x: &T) -> T {
        let z = (T::from_i64(2) * x - T::one()).max(&T::zero());
        T::from_i64(6) * &z.square()
    }
}
impl<T: Real> Known<T> for FlatThenCubic {
    fn inverse(&self, y: &T) -> T {
        // Smallest preimage for y = 0 is any point of [0, 1/2]: the oracle
        // returns 1/2, and the tests accept the whole flat interval at y = 0.
        (y.cbrt() + T::one()) / T::from_i64(2)
    }
}

pub const EXP_A: [f64; 9] = [-20.0, -5.0, -1.0, -1e-3, 1e-3, 0.5, 1.0, 5.0, 20.0];
pub const POW_N: [i32; 4] = [1, 2, 3, 7];

/// A CDF family member, built at any precision.
#[derive(Clone, Copy, Debug)]
pub enum Family {
    Exp(f64),
    Pow(i32),
    Sin2,
}

impl Family {
    pub fn all() -> Vec<Family> {
        let mut v: Vec<Family> = EXP_A.iter().map(|&a| Family::Exp(a)).collect();
        v.extend(POW_N.iter().map(|&n| Family::Pow(n)));
        v.push(Family::Sin2);
        v
    }
    pub fn label(&self) -> String {
        match self {
            Family::Exp(a) => format!("expm1(a x)/expm1(a), a = {a}"),
            Family::Pow(n) => format!("x^{n}"),
            Family::Sin2 => "sin²(πx/2)".to_string(),
        }
    }
}

/// Runs `f` with the family member built over `T`.
pub fn with_cdf<T: Real, R>(fam: Family, f: impl FnOnce(&dyn KnownDyn<T>) -> R) -> R {
    match fam {
        Family::Exp(a) => f(&ExpCdf::<T>::new(a)),
        Family::Pow(n) => f(&PowCdf { n }),
        Family::Sin2 => f(&Sin2Cdf),
    }
}

/// Object-safe view of [`Known`] so families can be looped over.
#[cfg_attr(not(feature = "mpfr"), allow(dead_code))]
pub trait KnownDyn<T: Real>: Cdf1<T> {
    fn inverse_dyn(&self, y: &T) -> T;
}
impl<T: Real, C: Known<T>> KnownDyn<T> for C {
    fn inverse_dyn(&self, y: &T) -> T {
        self.inverse(y)
    }
}

// ---------------------------------------------------------------------------
// Sample points y.

/// y values: the ends, extremes, and a dense interior sweep.
pub fn ys_f64() -> Vec<f64> {
    let mut ys = vec![
        0.0,
        2f64.powi(-60),
        1e-30,
        1e-12,
        1e-6,
        1e-3,
        1.0 - 1e-3,
        1.0 - 1e-6,
        1.0 - 1e-12,
        1.0 - f64::EPSILON / 2.0,
        1.0,
    ];
    ys.extend((1..128).map(|k| k as f64 / 128.0));
    ys.extend((1..40).map(|k| (k as f64 * 0.6180339887498949) % 1.0));
    ys
}
