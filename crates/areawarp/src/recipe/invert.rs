//! Step 4: inverting one-dimensional CDFs.
//!
//! The *problem* is a [`Cdf1`] (what to invert); the *solvers* are the
//! [`Inverter`]s (how): [`ClosedForm`], safeguarded [`Newton`], [`Bisection`]
//! and the [`VandermondeCubic`] (a cubic fitted to the inverse at four nodes,
//! optionally polished by Newton steps). Inverters hold no scalar: their
//! tolerances are [`Tolerance`]s, exact in every precision.
//!
//! # Accuracy and conditioning
//! Where the computed F carries an absolute error of about u·|y| (u the unit
//! roundoff), no method that evaluates F can place x closer to the exact
//! inverse than about u·|y| / F'(x). This exceeds u·|x| where F is flat (near
//! y = 1 for a concave CDF, the condition number y / (x F'(x)) being large).
//! [`Tolerance::Ulps`] is therefore measured on the scale
//! max(|x|, |y| / F'(x)) wherever F' is known: pure units of roundoff of x
//! where the inverse is well conditioned, the rounding floor of the problem
//! where it is not.
//!
//! # Derivatives
//! [`Newton`], [`Bisection`] and the polished [`VandermondeCubic`] return an x
//! produced by a Newton update x − (F(x) − y)/F'(x). Evaluated over dual
//! numbers ([`Dual2`](crate::real::Dual2)) with `y` seeded, such an update
//! carries dx/dy = 1/F'(x) + O(F(x) − y) whatever the derivative of the
//! previous iterate, so the composed warp has exact partials even where the
//! inversion is numerical. Where F'(x) = 0 at the returned x (dx/dy = ∞,
//! e.g. y = 0 at a pole where F ~ x²) the derivative parts come out
//! non-finite rather than zero, with the value unchanged.

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
    /// x with F(x) ≈ y, always inside the domain (finite when the domain is).
    pub x: T,
    /// Iterations spent: Newton or bisection updates, each costing one
    /// evaluation of F and at most one of F' (0 for closed forms).
    pub iterations: u32,
    /// |F(x) − y| at the returned x, as computed (NaN if F is NaN there).
    pub residual: T,
    /// Whether the stopping tolerance was met (closed forms: `true`; the
    /// cubic: see [`FittedCubic::invert`]).
    pub converged: bool,
}

/// A stopping tolerance on the step |Δx| (or the bracket width), exact in
/// every precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tolerance {
    /// |Δx| ≤ k · u · |x|, with u the unit roundoff of the scalar type:
    /// "converged to k units of roundoff". Where F is flat the computed F
    /// is noise on a scale u·|y|/F'(x) wider than that, and the
    /// safeguarded solvers get there by bisecting the noisy bracket down
    /// (about log₂ of the condition number extra steps; see the module docs).
    /// [`Bisection`] measures it as k · u · max(|lo|, |hi|).
    Ulps(u32),
    /// |Δx| ≤ 2^e (absolute).
    Exp2(i32),
}

impl Tolerance {
    /// The bound at `x`; `floor` is the problem scale |y| / F'(x) (or 0).
    fn bound<T: Real>(&self, x: &T, floor: &T) -> T {
        match *self {
            Tolerance::Ulps(k) => T::from_i64(k as i64) * &T::unit_roundoff() * &x.abs().max(floor),
            Tolerance::Exp2(e) => T::exp2i(e),
        }
    }
}

/// |y| / d when the density d is positive and finite, else 0: the width of
/// the set of x whose F is within a unit roundoff (relative) of y.
fn noise_scale<T: Real>(y: &T, d: &T) -> T {
    if d.is_finite_above(&T::zero()) {
        let s = y.abs() / d;
        if s.is_finite() {
            return s;
        }
    }
    T::zero()
}

/// A method that inverts a [`Cdf1`].
pub trait Inverter {
    /// x in the domain with F(x) ≈ y, for `y ∈ [0, 1]`. Any other `y`
    /// (including NaN) still gives a point of the domain.
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T>;
}

/// Uses [`Cdf1::closed_form_inverse`] (clamped to the domain); falls back to
/// [`Newton::default`] when the CDF has no closed form or it returns NaN.
///
/// The residual is evaluated (one CDF evaluation), for an honest report;
/// code that needs only x can call [`Cdf1::closed_form_inverse`] directly.
#[derive(Clone, Copy, Debug, Default)]
pub struct ClosedForm;

impl Inverter for ClosedForm {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        match cdf.closed_form_inverse(y) {
            Some(x) if !x.is_nan() => {
                let (lo, hi) = cdf.domain();
                let x = x.clamp(&lo, &hi);
                let residual = (cdf.cdf(&x) - y).abs();
                Inversion {
                    x,
                    iterations: 0,
                    residual,
                    converged: true,
                }
            }
            _ => Newton::default().invert(cdf, y),
        }
    }
}

/// Safeguarded Newton's method (after `rtsafe`): keeps a bracket
/// `[lo, hi]` with F(lo) ≤ y ≤ F(hi), takes the Newton step when it stays
/// inside the bracket, the density is positive and the step is at most half
/// the step before last, and bisects otherwise. It therefore converges at
/// least about as fast as bisection also where F' vanishes or the computed F
/// is noisy (flat or steep CDFs), and quadratically near simple roots.
///
/// Stops when the last step, or the bracket, is below
/// [`Newton::tolerance`], when F(x) = y exactly, when the iterate stops
/// moving, or after [`Newton::max_iterations`] updates. `y ≤ 0` (or NaN)
/// returns `lo` and `y ≥ 1` returns `hi` without iterating (F is 0 and 1
/// there by the [`Cdf1`] contract; over dual numbers they carry 1/F' too).
/// The returned x is always inside the domain.
///
/// # Derivatives
/// If the iteration converged after a bisection (or at an exact root), one
/// more Newton update is applied (not counted in [`Inversion::iterations`]),
/// so that over dual numbers x carries dx/dy = 1/F'(x) (module docs). It is
/// accepted inside the bracket, or outside it if it moves x by at most 4
/// units of roundoff (rounding noise), and never outside the domain.
///
/// # Example
/// ```
/// use areawarp::recipe::{Cdf1, Inverter, Newton};
///
/// /// F(x) = x³ on [0, 1].
/// struct Cube;
/// impl Cdf1<f64> for Cube {
///     fn cdf(&self, x: &f64) -> f64 {
///         x * x * x
///     }
///     fn pdf(&self, x: &f64) -> f64 {
///         3.0 * x * x
///     }
/// }
///
/// let r = Newton::default().invert(&Cube, &0.125);
/// assert!(r.converged && r.iterations < 20);
/// assert!((r.x - 0.5).abs() <= 4.0 * f64::EPSILON / 2.0 * 0.5);
/// assert_eq!(Newton::default().invert(&Cube, &1.0).x, 1.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Newton {
    /// Stopping tolerance on |Δx| (and on the bracket width).
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
    /// The Vandermonde cubic fitted to the inverse, with the bracket between
    /// the two fitting nodes around y (four extra CDF evaluations per call).
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

/// Narrows `[lo, hi]` to keep the root of `f` bracketed, given f = F(x) − y.
fn update_bracket<T: Real>(x: &T, f: &T, lo: &mut T, hi: &mut T) {
    if *f < T::zero() {
        *lo = x.clone();
    } else if *f > T::zero() {
        *hi = x.clone();
    }
}

/// The Newton update `x − f/d`, if the density is usable and the result is
/// finite.
fn newton_point<T: Real>(x: &T, f: &T, d: &T) -> Option<T> {
    if !d.is_finite_above(&T::zero()) {
        return None;
    }
    let n = x.clone() - &(f.clone() / d);
    if n.is_finite() { Some(n) } else { None }
}

/// `lo ≤ x ≤ hi`.
fn within<T: Real>(x: &T, lo: &T, hi: &T) -> bool {
    *x >= *lo && *x <= *hi
}

/// |f| ≤ 4 u |y|: the residual is at the rounding level of y.
fn at_noise_level<T: Real>(y: &T, f: &T) -> bool {
    f.abs() <= T::from_i64(4) * &T::unit_roundoff() * &y.abs()
}

/// If `x` did not come from a Newton update, applies one (so that dual
/// numbers carry dx/dy = 1/F'(x)) and refreshes `f`.
///
/// The update is accepted inside the bracket `[lo, hi]`, or if it moves x by
/// at most 4 units of roundoff: once the bracket is at the rounding level
/// the computed F is noise, and the Newton point may land a few units
/// outside. When the solver `converged` (x is then next to the root, so
/// F'(x) is trustworthy), the units of roundoff are those of the problem,
/// max(|x|, |y|/F'(x)) (see the module docs). Never outside the domain
/// `[dlo, dhi]`.
fn finish_with_newton<T: Real, C: Cdf1<T> + ?Sized>(
    cdf: &C,
    y: &T,
    x: &mut T,
    f: &mut T,
    (lo, hi): (&T, &T),
    (dlo, dhi): (&T, &T),
    converged: bool,
) {
    if f.is_nan() {
        return;
    }
    let d = cdf.pdf(x);
    let Some(n) = newton_point(x, f, &d) else {
        if *f == T::zero() && d == T::zero() {
            // An exact root where F' = 0 (a pole of the parametrization,
            // F ~ x² at the end of the domain): dx/dy is infinite. Adding
            // √|F(x) − y| leaves the value unchanged (√0 = 0) and, over dual
            // numbers, makes the derivatives non-finite instead of silently
            // zero, so that a Jacobian check sees the singularity.
            *x = x.clone() + &f.abs().sqrt();
        }
        return;
    };
    let floor = if converged {
        noise_scale(y, &d)
    } else {
        T::zero()
    };
    let close = (n.clone() - &*x).abs() <= Tolerance::Ulps(4).bound(x, &floor);
    if within(&n, dlo, dhi) && (within(&n, lo, hi) || close) {
        // At an exact root the value is unchanged (only derivatives move):
        // no re-evaluation needed.
        if *f != T::zero() {
            *f = cdf.cdf(&n) - y;
        }
        *x = n;
    }
}

/// The inverse at an end of the domain, for `y ≤ 0` (or NaN: `lo`, with
/// `end_value = 0`) and `y ≥ 1` (`hi`, `end_value = 1`), without iterating.
///
/// By the [`Cdf1`] contract F(end) = end_value exactly, so the residual is
/// f = end_value − y, with no rounding from evaluating F. One Newton update
/// end − f/F'(end), kept only if it stays in the domain (it does exactly when
/// y = end_value: its value is then `end` itself), gives dual numbers the
/// derivative 1/F'(end); where F'(end) = 0 they get a non-finite one (see
/// the module docs) and the value stays `end`.
fn invert_at_end<T: Real, C: Cdf1<T> + ?Sized>(
    cdf: &C,
    y: &T,
    end: T,
    end_value: T,
) -> Inversion<T> {
    let (dlo, dhi) = cdf.domain();
    let f = end_value - y;
    let d = cdf.pdf(&end);
    let mut x = end;
    match newton_point(&x, &f, &d) {
        Some(n) if within(&n, &dlo, &dhi) => x = n,
        Some(_) => {}
        None => {
            if f == T::zero() && d == T::zero() {
                x = x.clone() + &f.abs().sqrt();
            }
        }
    }
    let residual = (cdf.cdf(&x) - y).abs();
    Inversion {
        x,
        iterations: 0,
        converged: !y.is_nan(),
        residual,
    }
}

/// `Some(inversion)` when `y` is at or beyond an end of [0, 1] (or NaN).
fn end_case<T: Real, C: Cdf1<T> + ?Sized>(cdf: &C, y: &T) -> Option<Inversion<T>> {
    let (lo, hi) = cdf.domain();
    if y.is_nan() || *y <= T::zero() {
        Some(invert_at_end(cdf, y, lo, T::zero()))
    } else if *y >= T::one() {
        Some(invert_at_end(cdf, y, hi, T::one()))
    } else {
        None
    }
}

impl Newton {
    /// Runs the safeguarded iteration from `x0` (clamped to the domain),
    /// with the whole domain as the initial bracket.
    pub fn solve_from<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T, x0: T) -> Inversion<T> {
        let (lo, hi) = cdf.domain();
        self.solve_in(cdf, y, x0, lo, hi)
    }

    /// Runs the safeguarded iteration from `x0` inside the bracket
    /// `[lo, hi]`, which must satisfy F(lo) ≤ y ≤ F(hi) and lie in the domain.
    pub fn solve_in<T: Real, C: Cdf1<T> + ?Sized>(
        &self,
        cdf: &C,
        y: &T,
        x0: T,
        mut lo: T,
        mut hi: T,
    ) -> Inversion<T> {
        let (dlo, dhi) = cdf.domain();
        let two = T::from_i64(2);
        let mut x = x0.clamp(&lo, &hi);
        let mut f = cdf.cdf(&x) - y;
        update_bracket(&x, &f, &mut lo, &mut hi);
        let mut iterations = 0;
        let mut converged = false;
        let mut newton_last = false;
        // The last two step lengths (rtsafe's dx and dxold).
        let mut step_last = hi.clone() - &lo;
        let mut step_before = step_last.clone();
        loop {
            if f.is_nan() {
                break;
            }
            if f == T::zero() {
                // An exact root: the value is final, but over dual numbers
                // a preceding Newton step left dx/dy off by the residual it
                // started from; the closing update (which does not move the
                // value) makes it 1/F'(x).
                converged = true;
                newton_last = false;
                break;
            }
            if iterations >= self.max_iterations {
                break;
            }
            iterations += 1;
            let d = cdf.pdf(&x);
            let newton = newton_point(&x, &f, &d)
                .filter(|n| within(n, &lo, &hi) && (n.clone() - &x).abs() * &two <= step_before);
            newton_last = newton.is_some();
            let next = newton.unwrap_or_else(|| (lo.clone() + &hi) / &two);
            let step = (next.clone() - &x).abs();
            step_before = core::mem::replace(&mut step_last, step.clone());
            x = next;
            f = cdf.cdf(&x) - y;
            update_bracket(&x, &f, &mut lo, &mut hi);
            let tol = self.tolerance.bound(&x, &T::zero());
            if step <= tol || hi.clone() - &lo <= tol || step == T::zero() {
                converged = !f.is_nan();
                break;
            }
        }
        // Only a converged x gets the closing update: at the iteration cap
        // the caller gets exactly `max_iterations` updates, no more.
        if converged && !newton_last {
            finish_with_newton(cdf, y, &mut x, &mut f, (&lo, &hi), (&dlo, &dhi), true);
        }
        Inversion {
            x,
            iterations,
            residual: f.abs(),
            converged,
        }
    }
}

impl Inverter for Newton {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        if let Some(end) = end_case(cdf, y) {
            return end;
        }
        let (lo, hi) = cdf.domain();
        match self.start.unwrap_or(Start::Midpoint) {
            Start::Midpoint => {
                let x0 = (lo.clone() + &hi) / T::from_i64(2);
                self.solve_in(cdf, y, x0, lo, hi)
            }
            Start::Linear => {
                let x0 = lo.clone() + &(y.clone() * &(hi.clone() - &lo));
                self.solve_in(cdf, y, x0, lo, hi)
            }
            Start::Cubic => {
                let fit = FittedCubic::fit(cdf);
                let (blo, bhi) = fit.bracket(y);
                let x0 = fit.eval(y);
                self.solve_in(cdf, y, x0, blo, bhi)
            }
        }
    }
}

/// Bisection until the bracket is below the tolerance.
///
/// `y ≤ 0` (or NaN) returns `lo` and `y ≥ 1` returns `hi`, as [`Newton`]
/// does. Otherwise the root
/// is kept in `[lo, hi]` until `hi − lo` is below [`Bisection::tolerance`]
/// (k · u · max(|lo|, |hi|) for [`Tolerance::Ulps`]) or the two ends are
/// adjacent floats. x is then the midpoint, moved (if converged) by one
/// Newton update (not counted in [`Inversion::iterations`]) if that stays
/// inside the bracket or within 4 units of roundoff of x, so that x keeps
/// the bracket's accuracy and, over dual numbers, carries dx/dy = 1/F'(x).
#[derive(Clone, Copy, Debug)]
pub struct Bisection {
    /// Stopping tolerance on the bracket width.
    pub tolerance: Tolerance,
    /// Iteration cap.
    pub max_iterations: u32,
}

impl Default for Bisection {
    /// Two units of roundoff, at most 4096 halvings (enough for relative
    /// accuracy down to f64's underflow threshold).
    fn default() -> Self {
        Bisection {
            tolerance: Tolerance::Ulps(2),
            max_iterations: 4096,
        }
    }
}

impl Inverter for Bisection {
    fn invert<T: Real, C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T) -> Inversion<T> {
        if let Some(end) = end_case(cdf, y) {
            return end;
        }
        let (dlo, dhi) = cdf.domain();
        let (mut lo, mut hi) = (dlo.clone(), dhi.clone());
        let two = T::from_i64(2);
        let zero = T::zero();
        let mut iterations = 0;
        let mut converged = false;
        loop {
            let size = lo.abs().max(&hi.abs());
            if hi.clone() - &lo <= self.tolerance.bound(&size, &zero) {
                converged = true;
                break;
            }
            let mid = (lo.clone() + &hi) / &two;
            if mid <= lo || mid >= hi {
                converged = true;
                break;
            }
            if iterations >= self.max_iterations {
                break;
            }
            iterations += 1;
            let f = cdf.cdf(&mid) - y;
            if f.is_nan() {
                break;
            }
            if f < T::zero() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let mut x = (lo.clone() + &hi) / &two;
        let mut f = cdf.cdf(&x) - y;
        if converged {
            finish_with_newton(cdf, y, &mut x, &mut f, (&lo, &hi), (&dlo, &dhi), true);
        }
        Inversion {
            x,
            iterations,
            residual: f.abs(),
            converged,
        }
    }
}

/// A cubic fitted to the inverse CDF at four nodes, then `polish` safeguarded
/// Newton steps.
///
/// The nodes are x_i = lo + i (hi − lo)/3, i = 0…3, with y_i = F(x_i); the
/// cubic p interpolates (y_i, x_i) (Newton's divided differences, which solve
/// the Vandermonde system stably). The nodes also bracket the root: y lies
/// between y_i and y_{i+1}, so each polish step is a Newton step kept inside
/// that (shrinking) bracket, or a bisection when Newton would leave it, and
/// never increases the residual (see [`FittedCubic::invert`]).
/// Fitting costs four CDF evaluations: to reuse a fit, call
/// [`FittedCubic::fit`] once and [`FittedCubic::invert`] per sample. As an
/// [`Inverter`] it refits on every call.
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
    /// The fitting nodes x_i.
    xs: [T; 4],
    /// F at the nodes (0 and 1 at the ends).
    fs: [T; 4],
    /// Interpolation nodes of the cubic (equal to `fs` unless degenerate).
    ys: [T; 4],
    /// Divided-difference coefficients.
    coef: [T; 4],
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
        let mut xs: [T; 4] =
            core::array::from_fn(|i| lo.clone() + &(third.clone() * &T::from_i64(i as i64)));
        xs[3] = hi.clone();
        let mut fs: [T; 4] = core::array::from_fn(|i| cdf.cdf(&xs[i]));
        fs[0] = T::zero();
        fs[3] = T::one();
        let mut ys = fs.clone();
        let mut coef = xs.clone();
        let mut ok = true;
        for j in 1..4 {
            for i in (j..4).rev() {
                let dy = ys[i].clone() - &ys[i - j];
                if dy.is_nan() || dy <= T::zero() {
                    ok = false;
                }
                coef[i] = (coef[i].clone() - &coef[i - 1]) / &dy;
            }
        }
        if !ok || coef.iter().any(|c| !c.is_finite()) {
            coef = [lo.clone(), hi.clone() - &lo, T::zero(), T::zero()];
            ys = [T::zero(), T::one(), T::one(), T::one()];
        }
        FittedCubic { xs, fs, ys, coef }
    }

    /// p(y), unclamped.
    pub fn eval(&self, y: &T) -> T {
        let mut acc = self.coef[3].clone();
        for i in (0..3).rev() {
            acc = acc * &(y.clone() - &self.ys[i]) + &self.coef[i];
        }
        acc
    }

    /// The node interval `[x_i, x_{i+1}]` with F(x_i) ≤ y ≤ F(x_{i+1})
    /// (for a non-decreasing F and y ∈ [0, 1]).
    pub fn bracket(&self, y: &T) -> (T, T) {
        let mut i = 0;
        for k in 1..3 {
            if self.fs[k] <= *y {
                i = k;
            }
        }
        (self.xs[i].clone(), self.xs[i + 1].clone())
    }

    /// p(y) clamped to the node bracket around y ([`FittedCubic::bracket`]),
    /// then up to `polish` safeguarded Newton steps.
    ///
    /// Each step tries the Newton update if it falls strictly inside the
    /// bracket (narrowed by every evaluation), else the bracket's midpoint,
    /// and keeps the trial only if it does not increase |F(x) − y|: a polish
    /// step never makes the residual worse, even from a poor cubic guess on a
    /// steep or flat CDF (where it may then stall: prefer [`Newton`] with
    /// [`Start::Cubic`] there). Stops early at an exact root or where F is
    /// NaN. With `polish > 0`, `y ≤ 0` and `y ≥ 1` return the ends as
    /// [`Newton`] does, and an x that did not come from a Newton update
    /// gets one more if that moves it by at most 4 units of roundoff (as in
    /// [`Newton`]; the residual may then change at the rounding level,
    /// ≤ 4u|y|), so that dual numbers carry dx/dy = 1/F'(x); the bare cubic
    /// (`polish = 0`) carries p'(y), an approximation.
    ///
    /// [`Inversion::iterations`] counts the polish steps taken (each costing
    /// one evaluation of F and F'); [`Inversion::converged`] tells whether
    /// the residual reached the rounding level, |F(x) − y| ≤ 4u|y| (always
    /// `false` without polish: the bare cubic tests nothing).
    pub fn invert<C: Cdf1<T> + ?Sized>(&self, cdf: &C, y: &T, polish: u32) -> Inversion<T> {
        if polish > 0
            && let Some(end) = end_case(cdf, y)
        {
            return end;
        }
        let (dlo, dhi) = cdf.domain();
        let (mut lo, mut hi) = self.bracket(y);
        let two = T::from_i64(2);
        let mut x = self.eval(y).clamp(&lo, &hi);
        let mut f = cdf.cdf(&x) - y;
        let mut iterations = 0;
        let mut from_newton = false;
        while iterations < polish && !f.is_nan() && f != T::zero() {
            update_bracket(&x, &f, &mut lo, &mut hi);
            iterations += 1;
            let d = cdf.pdf(&x);
            let newton = newton_point(&x, &f, &d).filter(|n| *n > lo && *n < hi);
            let is_newton = newton.is_some();
            let trial = newton.unwrap_or_else(|| (lo.clone() + &hi) / &two);
            let ft = cdf.cdf(&trial) - y;
            if ft.is_nan() {
                break;
            }
            if ft.abs() <= f.abs() {
                x = trial;
                f = ft;
                from_newton = is_newton;
            } else {
                // Rejected, but it still narrows the bracket (and a rejected
                // Newton point, now a bracket end, is not tried again).
                update_bracket(&trial, &ft, &mut lo, &mut hi);
            }
        }
        // An exact root reached by a Newton step also gets the closing
        // update: over dual numbers that step's derivative is off by the
        // residual it started from; at f = 0 the update moves only the
        // derivative.
        if polish > 0 && (!from_newton || f == T::zero()) {
            // Only a move at the rounding level: the polish bracket may be
            // wide, and a Newton point inside it need not be better than x.
            let here = x.clone();
            finish_with_newton(cdf, y, &mut x, &mut f, (&here, &here), (&dlo, &dhi), false);
        }
        let converged = polish > 0 && at_noise_level(y, &f);
        Inversion {
            x,
            iterations,
            residual: f.abs(),
            converged,
        }
    }
}
