//! Step 4: inverting one-dimensional CDFs.
//!
//! The *problem* is a [`Cdf1`] (what to invert); the *solvers* are the
//! [`Inverter`]s (how): [`ClosedForm`], safeguarded [`Newton`], [`Bisection`]
//! and the [`VandermondeCubic`] (a cubic fitted to the inverse at four nodes,
//! optionally polished by Newton steps). Inverters hold no scalar: their
//! tolerances are [`Tolerance`]s, exact in every precision.

use super::MarginalConditional;
use crate::real::Real;

/// A continuous, non-decreasing CDF on an interval `[lo, hi]`, with its density.
pub trait Cdf1<T: Real> {
    /// F(x), rising from 0 at `lo` to 1 at `hi`.
    fn cdf(&self, x: &T) -> T;
    /// F'(x).
    fn pdf(&self, x: &T) -> T;
    /// The support `[lo, hi]`; `[0, 1]` by default.
    fn domain(&self) -> (T, T) {
        (T::zero(), T::one())
    }
    /// F⁻¹(y) in closed form, if known.
    fn closed_form_inverse(&self, _y: &T) -> Option<T> {
        None
    }
}

/// The marginal F(s) of a step-3 distribution, as a [`Cdf1`].
pub struct Marginal<'a, D>(pub &'a D);

impl<T: Real, D: MarginalConditional<T>> Cdf1<T> for Marginal<'_, D> {
    fn cdf(&self, x: &T) -> T {
        self.0.marginal_cdf(x)
    }
    fn pdf(&self, x: &T) -> T {
        self.0.marginal_pdf(x)
    }
    fn closed_form_inverse(&self, y: &T) -> Option<T> {
        self.0.marginal_inverse(y)
    }
}

/// The conditional G_s(t) of a step-3 distribution at fixed `s`, as a [`Cdf1`].
pub struct Conditional<'a, D, T> {
    /// The distribution.
    pub dist: &'a D,
    /// The fixed first coordinate.
    pub s: T,
}

impl<T: Real, D: MarginalConditional<T>> Cdf1<T> for Conditional<'_, D, T> {
    fn cdf(&self, x: &T) -> T {
        self.dist.conditional_cdf(&self.s, x)
    }
    fn pdf(&self, x: &T) -> T {
        self.dist.conditional_pdf(&self.s, x)
    }
    fn closed_form_inverse(&self, y: &T) -> Option<T> {
        self.dist.conditional_inverse(&self.s, y)
    }
}

/// The result of an inversion: the abscissa and how it was reached.
#[derive(Clone, Debug)]
pub struct Inversion<T> {
    /// x with F(x) ≈ y, always inside the domain.
    pub x: T,
    /// Iterations spent (0 for closed forms).
    pub iterations: u32,
    /// |F(x) − y| at the returned x (zero when not evaluated, for closed forms).
    pub residual: T,
    /// Whether the stopping tolerance was met (closed forms: `true`).
    pub converged: bool,
}

/// A stopping tolerance on the step |Δx|, exact in every precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tolerance {
    /// |Δx| ≤ k · u · max(|x|, u · (hi − lo)), with u the unit roundoff of the
    /// scalar type: "converged to k units of roundoff".
    Ulps(u32),
    /// |Δx| ≤ 2^e (absolute).
    Exp2(i32),
}

impl Tolerance {
    fn bound<T: Real>(&self, x: &T, width: &T) -> T {
        match *self {
            Tolerance::Ulps(k) => {
                let u = T::unit_roundoff();
                T::from_i64(k as i64) * &u * &x.abs().max(&(u.clone() * width))
            }
            Tolerance::Exp2(e) => T::exp2i(e),
        }
    }
}

/// A method that inverts a [`Cdf1`].
pub trait Inverter {
    /// x in the domain with F(x) ≈ y, for `y ∈ [0, 1]`.
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T>;
}

/// Uses [`Cdf1::closed_form_inverse`] (clamped to the domain); falls back to
/// [`Newton::default`] when the CDF has no closed form.
#[derive(Clone, Copy, Debug, Default)]
pub struct ClosedForm;

impl Inverter for ClosedForm {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        match cdf.closed_form_inverse(y) {
            Some(x) if !x.is_nan() => {
                let (lo, hi) = cdf.domain();
                Inversion {
                    x: x.clamp(&lo, &hi),
                    iterations: 0,
                    residual: T::zero(),
                    converged: true,
                }
            }
            _ => Newton::default().invert(cdf, y),
        }
    }
}

/// Safeguarded Newton's method: keeps a bracket `[lo, hi]` with
/// F(lo) ≤ y ≤ F(hi), takes the Newton step when it stays inside the bracket
/// and the density is positive, and bisects otherwise. Stops when the step is
/// below [`Newton::tolerance`] or after [`Newton::max_iterations`].
///
/// The returned x always ends with a Newton (not a bisection) update when
/// one is possible, so that evaluated over dual numbers the derivative of x
/// is the implicit derivative 1/F'(x).
#[derive(Clone, Copy, Debug)]
pub struct Newton {
    /// Stopping tolerance on |Δx|.
    pub tolerance: Tolerance,
    /// Iteration cap.
    pub max_iterations: u32,
    /// Where to start: `None` for the bracket's midpoint.
    pub start: Option<Start>,
}

/// Starting point of a [`Newton`] iteration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// The midpoint of the domain.
    Midpoint,
    /// The linear interpolant x = lo + y (hi − lo).
    Linear,
    /// The Vandermonde cubic fitted to the inverse.
    Cubic,
}

impl Default for Newton {
    /// Converge to 4 units of roundoff, at most 200 iterations, starting from
    /// the linear guess.
    fn default() -> Self {
        Newton {
            tolerance: Tolerance::Ulps(4),
            max_iterations: 200,
            start: Some(Start::Linear),
        }
    }
}

impl Newton {
    /// Runs the safeguarded iteration from `x0`.
    pub fn solve_from<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T, x0: T) -> Inversion<T> {
        let (mut lo, mut hi) = cdf.domain();
        let width = hi.clone() - &lo;
        let mut x = x0.clamp(&lo, &hi);
        let mut iterations = 0;
        let mut converged = false;
        while iterations < self.max_iterations {
            iterations += 1;
            let f = cdf.cdf(&x) - y;
            if f.is_nan() {
                break;
            }
            if f < T::zero() {
                lo = x.clone();
            } else if f > T::zero() {
                hi = x.clone();
            }
            let d = cdf.pdf(&x);
            let newton = if d > T::zero() && d.is_finite() {
                Some(x.clone() - &(f.clone() / &d))
            } else {
                None
            };
            let next = match newton {
                Some(n) if n >= lo && n <= hi => n,
                _ => (lo.clone() + &hi) / T::from_i64(2),
            };
            let step = (next.clone() - &x).abs();
            x = next;
            if step <= self.tolerance.bound(&x, &width) {
                converged = true;
                break;
            }
        }
        let residual = (cdf.cdf(&x) - y).abs();
        Inversion {
            x,
            iterations,
            residual,
            converged,
        }
    }
}

impl Inverter for Newton {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        let (lo, hi) = cdf.domain();
        let x0 = match self.start.unwrap_or(Start::Midpoint) {
            Start::Midpoint => (lo.clone() + &hi) / T::from_i64(2),
            Start::Linear => lo.clone() + &(y.clone() * &(hi.clone() - &lo)),
            Start::Cubic => FittedCubic::fit(cdf).eval(y).clamp(&lo, &hi),
        };
        self.solve_from(cdf, y, x0)
    }
}

/// Bisection on the domain until the bracket is below the tolerance.
#[derive(Clone, Copy, Debug)]
pub struct Bisection {
    /// Stopping tolerance on the bracket width.
    pub tolerance: Tolerance,
    /// Iteration cap.
    pub max_iterations: u32,
}

impl Default for Bisection {
    fn default() -> Self {
        Bisection {
            tolerance: Tolerance::Ulps(2),
            max_iterations: 4096,
        }
    }
}

impl Inverter for Bisection {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        let (mut lo, mut hi) = cdf.domain();
        let width = hi.clone() - &lo;
        let two = T::from_i64(2);
        let mut iterations = 0;
        let mut converged = false;
        while iterations < self.max_iterations {
            iterations += 1;
            let mid = (lo.clone() + &hi) / &two;
            if mid <= lo || mid >= hi {
                converged = true;
                break;
            }
            if cdf.cdf(&mid) < *y {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi.clone() - &lo <= self.tolerance.bound(&lo, &width) {
                converged = true;
                break;
            }
        }
        let x = (lo + &hi) / &two;
        let residual = (cdf.cdf(&x) - y).abs();
        Inversion {
            x,
            iterations,
            residual,
            converged,
        }
    }
}

/// A cubic fitted to the inverse CDF at four nodes, optionally polished by
/// `polish` unsafeguarded-but-clamped Newton steps.
///
/// The nodes are x_i = lo + i (hi − lo)/3, i = 0…3, with y_i = F(x_i); the
/// cubic p interpolates (y_i, x_i) (Newton's divided differences, which solve
/// the Vandermonde system stably). Fitting costs four CDF evaluations: to
/// reuse a fit, call [`FittedCubic::fit`] once and [`FittedCubic::invert`] per
/// sample. As an [`Inverter`] it refits on every call.
#[derive(Clone, Copy, Debug, Default)]
pub struct VandermondeCubic {
    /// Newton steps after the cubic guess.
    pub polish: u32,
}

impl Inverter for VandermondeCubic {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        FittedCubic::fit(cdf).invert(cdf, y, self.polish)
    }
}

/// The cubic of [`VandermondeCubic`], fitted once.
#[derive(Clone, Debug)]
pub struct FittedCubic<T> {
    ys: [T; 4],
    coef: [T; 4],
    lo: T,
    hi: T,
}

impl<T: Real> FittedCubic<T> {
    /// Fits the cubic through the inverse of `cdf` at four equally spaced nodes.
    ///
    /// Coincident node values (a CDF flat over a third of its domain) make
    /// the divided differences degenerate; the fit then falls back to the
    /// linear interpolant between the end nodes.
    pub fn fit<C: Cdf1<T> + ?Sized>(cdf: &C) -> Self {
        let (lo, hi) = cdf.domain();
        let third = (hi.clone() - &lo) / T::from_i64(3);
        let xs: [T; 4] =
            core::array::from_fn(|i| lo.clone() + &(third.clone() * &T::from_i64(i as i64)));
        let mut ys: [T; 4] = core::array::from_fn(|i| cdf.cdf(&xs[i]));
        ys[0] = T::zero();
        ys[3] = T::one();
        let mut coef = xs.clone();
        let mut ok = true;
        for j in 1..4 {
            for i in (j..4).rev() {
                let dy = ys[i].clone() - &ys[i - j];
                if !(dy > T::zero()) {
                    ok = false;
                }
                coef[i] = (coef[i].clone() - &coef[i - 1]) / &dy;
            }
        }
        if !ok || coef.iter().any(|c| !c.is_finite()) {
            coef = [lo.clone(), hi.clone() - &lo, T::zero(), T::zero()];
            ys = [T::zero(), T::one(), T::one(), T::one()];
        }
        FittedCubic { ys, coef, lo, hi }
    }

    /// p(y), unclamped.
    pub fn eval(&self, y: &T) -> T {
        let mut acc = self.coef[3].clone();
        for i in (0..3).rev() {
            acc = acc * &(y.clone() - &self.ys[i]) + &self.coef[i];
        }
        acc
    }

    /// p(y) clamped to the domain, then `polish` Newton steps (each clamped).
    pub fn invert<C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T, polish: u32) -> Inversion<T> {
        let mut x = self.eval(y).clamp(&self.lo, &self.hi);
        for _ in 0..polish {
            let f = cdf.cdf(&x) - y;
            let d = cdf.pdf(&x);
            if d > T::zero() && d.is_finite() {
                x = (x - &(f / &d)).clamp(&self.lo, &self.hi);
            }
        }
        let residual = (cdf.cdf(&x) - y).abs();
        Inversion {
            x,
            iterations: polish,
            residual,
            converged: false,
        }
    }
}
