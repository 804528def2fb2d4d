//! Monte Carlo estimators over any sampler with a density: plain importance
//! sampling, multiple importance sampling (MIS) of several strategies
//! (Veach and Guibas 1995; Arvo 2001, ch. 2), and deterministic parallel
//! runs of independent estimator jobs.
//!
//! Everything here works in `f64`: the estimators are the consumers of the
//! warps, not warps themselves.
//!
//! # The model
//! An integral `I = ∫_D f(x) dμ(x)` over a domain `D` with a measure `μ`
//! (area, solid angle, length, …) is estimated from points drawn by a
//! [`Strategy`]: a map from the unit square to `D` that also reports the
//! density `p(x)` of the points it returns *with respect to the same
//! measure μ* as the integrand. Any [`Warp<f64>`](crate::warp::Warp) is a
//! strategy ([`WarpStrategy`]); [`Mixture`] picks one of several strategies
//! at random (the one-sample model, whose density is the mixture density).
//!
//! - [`monte_carlo`]: `⟨f(X)/p(X)⟩` over the given points (Arvo, eq. 2.3).
//! - [`Mis`]: `Σ_i (1/N_i) Σ_j w_i(X_ij) f(X_ij) / p_i(X_ij)` with `N_i`
//!   points from strategy `i` and the weights of a [`Heuristic`] (balance,
//!   power, maximum), non-negative and summing to 1 at every `x`, which is
//!   all unbiasedness needs (Arvo, eq. 2.4–2.7).
//! - [`run_jobs_sequential`]: `n` independent jobs, each with its own
//!   random stream derived from `(seed, job index)` ([`job_rng`]), results
//!   in job order; any parallel runner that hands job `i` the stream
//!   `job_rng(seed, i)` gets bit-identical results for any thread count.
//!
//! # Example
//! ```
//! use areawarp::estimate::{Heuristic, Mis, Strategy, WarpStrategy, monte_carlo};
//! use areawarp::sampling::hammersley;
//! use areawarp::shapes::{Hemisphere, PhongLobe};
//!
//! // ∫ cos²θ dω over the upper hemisphere = 2π/3.
//! let f = |d: &areawarp::Vec3<f64>| d.z * d.z;
//! let uniform = WarpStrategy::new(Hemisphere::<f64>::new());
//! let cosine = WarpStrategy::new(PhongLobe::<f64>::new(1.0).unwrap());
//! let points = hammersley::<f64>(4096);
//! let e = monte_carlo(&cosine, f, points.iter().cloned());
//! assert!((e.value - 2.0 * std::f64::consts::PI / 3.0).abs() < 1e-3);
//!
//! // The same integral by MIS of both strategies, 1024 points each.
//! let strategies: [&dyn Strategy<Point = _>; 2] = [&uniform, &cosine];
//! let mis = Mis::new(&strategies, &[1024, 1024], Heuristic::Balance).unwrap();
//! let e = mis.estimate(f, |_| hammersley::<f64>(1024)).unwrap();
//! assert!((e.value - 2.0 * std::f64::consts::PI / 3.0).abs() < 1e-2);
//! ```

mod jobs;
mod mis;

pub use jobs::{job_rng, job_seed, run_jobs_sequential};
pub use mis::{Heuristic, Mis, MisEstimate};

use crate::error::WarpError;
use crate::real::Real;
use crate::warp::Warp;

/// A point drawn by a [`Strategy`] and the density it was drawn with (in
/// the measure of the integral; finite and `> 0`): the warps' own
/// [`Sample`](crate::warp::Sample) with an `f64` density.
pub type Sample<P> = crate::warp::Sample<f64, P>;

/// A sampling strategy: a map from the unit square to the integration
/// domain with a known density.
///
/// Contract:
/// - [`Strategy::sample`] returns `None` only on a set of `(u, v)` of
///   measure zero (or where the strategy cannot place a point at all); a
///   returned sample has a finite density `pdf > 0`;
/// - [`Strategy::pdf`] is the density of the returned points with respect
///   to the integral's measure, **zero outside the strategy's support**
///   (MIS weights need the density of *other* strategies' points), and
///   equal to the `pdf` of a returned sample at that point within rounding.
pub trait Strategy {
    /// The points of the integration domain.
    type Point;
    /// The point for `(u, v) ∈ [0, 1]²` and its density.
    fn sample(&self, u: f64, v: f64) -> Option<Sample<Self::Point>>;
    /// The density of this strategy's points at `x` (0 outside its support).
    fn pdf(&self, x: &Self::Point) -> f64;
}

impl<S: Strategy + ?Sized> Strategy for &S {
    type Point = S::Point;
    fn sample(&self, u: f64, v: f64) -> Option<Sample<S::Point>> {
        (**self).sample(u, v)
    }
    fn pdf(&self, x: &S::Point) -> f64 {
        (**self).pdf(x)
    }
}

impl<S: Strategy + ?Sized> Strategy for Box<S> {
    type Point = S::Point;
    fn sample(&self, u: f64, v: f64) -> Option<Sample<S::Point>> {
        (**self).sample(u, v)
    }
    fn pdf(&self, x: &S::Point) -> f64 {
        (**self).pdf(x)
    }
}

/// `p` if it is a usable density (finite, `> 0`), else `None`.
fn usable(p: f64) -> Option<f64> {
    (p > 0.0 && p.is_finite()).then_some(p)
}

/// Any `f64` warp as a [`Strategy`]: `sample(u, v) = (ψ(u, v), pdf(ψ(u, v)))`
/// and `pdf = Warp::pdf`.
///
/// The warp's density must be zero outside its shape for use in [`Mis`]
/// (true of the weighted warps such as [`PhongLobe`](crate::shapes::PhongLobe),
/// not of the constant-density ones, whose `pdf` ignores its argument):
/// restrict those with [`WarpStrategy::with_support`].
#[derive(Clone, Debug)]
pub struct WarpStrategy<W, F = fn(&<W as Warp<f64>>::Point) -> bool>
where
    W: Warp<f64>,
{
    warp: W,
    support: Option<F>,
}

impl<W: Warp<f64>> WarpStrategy<W> {
    /// The warp's own density everywhere.
    pub fn new(warp: W) -> Self {
        WarpStrategy {
            warp,
            support: None,
        }
    }
}

impl<W: Warp<f64>, F: Fn(&W::Point) -> bool> WarpStrategy<W, F> {
    /// The warp with its density set to 0 where `inside(x)` is false
    /// (the shape's membership test, e.g. `SphericalTriangle::contains`).
    pub fn with_support(warp: W, inside: F) -> Self {
        WarpStrategy {
            warp,
            support: Some(inside),
        }
    }

    /// The wrapped warp.
    pub fn warp(&self) -> &W {
        &self.warp
    }
}

impl<W: Warp<f64>, F: Fn(&W::Point) -> bool> Strategy for WarpStrategy<W, F> {
    type Point = W::Point;

    fn sample(&self, u: f64, v: f64) -> Option<Sample<W::Point>> {
        let (point, pdf) = self.warp.map_with_pdf(&u, &v);
        let pdf = usable(pdf)?;
        Some(Sample { point, pdf })
    }

    fn pdf(&self, x: &W::Point) -> f64 {
        if let Some(inside) = &self.support
            && !inside(x)
        {
            return 0.0;
        }
        let p = self.warp.pdf(x);
        if p.is_nan() { 0.0 } else { p }
    }
}

/// A random choice among strategies: strategy `i` with probability `c_i`,
/// then its point. The density is the mixture `q(x) = Σ_j c_j p_j(x)`,
/// which makes [`monte_carlo`] with a mixture the *one-sample* balance
/// heuristic (Veach 1997, §9.2.4; Arvo 2001, eq. 2.8–2.11): e.g. a polygon
/// split into spherical triangles, each chosen with probability ∝ its solid
/// angle.
///
/// The choice uses `u`: with cumulative probabilities `C_i`, strategy `i`
/// gets `u ∈ [C_{i−1}, C_i)` and is fed `((u − C_{i−1}) / c_i, v)`, so
/// stratified `(u, v)` stay stratified within each part.
#[derive(Clone, Debug)]
pub struct Mixture<S> {
    parts: Vec<S>,
    probability: Vec<f64>,
    cumulative: Vec<f64>,
}

impl<S: Strategy> Mixture<S> {
    /// A mixture with probabilities proportional to `weights` (finite,
    /// `≥ 0`, not all zero).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] for no parts, a length mismatch, or
    /// invalid weights.
    pub fn new(parts: Vec<S>, weights: &[f64]) -> Result<Self, WarpError> {
        let invalid = WarpError::InvalidParameter {
            name: "weights",
            expected: "one finite weight >= 0 per part, not all zero",
        };
        if parts.is_empty() || parts.len() != weights.len() {
            return Err(invalid);
        }
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return Err(invalid);
        }
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return Err(invalid);
        }
        let probability: Vec<f64> = weights.iter().map(|w| w / total).collect();
        let mut cumulative = Vec::with_capacity(parts.len());
        let mut c = 0.0;
        for p in &probability {
            c += p;
            cumulative.push(c);
        }
        if let Some(last) = cumulative.last_mut() {
            *last = 1.0;
        }
        Ok(Mixture {
            parts,
            probability,
            cumulative,
        })
    }

    /// The parts.
    pub fn parts(&self) -> &[S] {
        &self.parts
    }

    /// The probabilities `c_i` (summing to 1).
    pub fn probabilities(&self) -> &[f64] {
        &self.probability
    }
}

impl<S: Strategy> Strategy for Mixture<S> {
    type Point = S::Point;

    fn sample(&self, u: f64, v: f64) -> Option<Sample<S::Point>> {
        let u = u.clamp(0.0, 1.0);
        // First part whose cumulative probability exceeds u (the last for u = 1),
        // skipping parts of probability 0.
        let mut i = self.cumulative.partition_point(|&c| c <= u);
        i = i.min(self.parts.len() - 1);
        while self.probability[i] == 0.0 && i > 0 {
            i -= 1;
        }
        let lo = if i == 0 { 0.0 } else { self.cumulative[i - 1] };
        let u_i = ((u - lo) / self.probability[i]).clamp(0.0, 1.0);
        let s = self.parts[i].sample(u_i, v)?;
        let mut pdf = self.probability[i] * s.pdf;
        for (j, part) in self.parts.iter().enumerate() {
            if j != i && self.probability[j] > 0.0 {
                pdf += self.probability[j] * part.pdf(&s.point);
            }
        }
        let pdf = usable(pdf)?;
        Some(Sample {
            point: s.point,
            pdf,
        })
    }

    fn pdf(&self, x: &S::Point) -> f64 {
        self.parts
            .iter()
            .zip(&self.probability)
            .filter(|(_, c)| **c > 0.0)
            .map(|(s, c)| c * s.pdf(x))
            .sum()
    }
}

/// Running count, mean and sum of squared deviations (Welford), mergeable
/// (Chan et al.): the statistics of a stream of primary estimates.
///
/// Merging is exact-order dependent in floating point: merge in a fixed
/// order (e.g. job order) for reproducible results.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    n: u64,
    mean: f64,
    m2: f64,
}

impl Stats {
    /// No values yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one value.
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }

    /// Adds all values of `other` (as if pushed after this one's).
    pub fn merge(&mut self, other: &Stats) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = *other;
            return;
        }
        let n = self.n + other.n;
        let d = other.mean - self.mean;
        let (na, nb) = (self.n as f64, other.n as f64);
        self.mean += d * nb / n as f64;
        self.m2 += other.m2 + d * d * na * nb / n as f64;
        self.n = n;
    }

    /// Number of values.
    pub fn count(&self) -> u64 {
        self.n
    }

    /// Their mean (0 for none).
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// The unbiased sample variance `Σ (x − x̄)² / (n − 1)`; NaN for fewer
    /// than two values.
    pub fn variance(&self) -> f64 {
        if self.n < 2 {
            f64::NAN
        } else {
            self.m2 / (self.n - 1) as f64
        }
    }

    /// The estimated standard error of the mean, `√(variance / n)`.
    pub fn std_error(&self) -> f64 {
        (self.variance() / self.n as f64).sqrt()
    }
}

impl Extend<f64> for Stats {
    fn extend<I: IntoIterator<Item = f64>>(&mut self, iter: I) {
        for x in iter {
            self.push(x);
        }
    }
}

impl FromIterator<f64> for Stats {
    fn from_iter<I: IntoIterator<Item = f64>>(iter: I) -> Self {
        let mut s = Stats::new();
        s.extend(iter);
        s
    }
}

/// An estimate of an integral with its estimated variance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// The estimate of the integral.
    pub value: f64,
    /// The estimated variance of `value` (sample variance of the primary
    /// estimates over their count; NaN for fewer than two). Valid for
    /// independent points; for stratified or low-discrepancy points it
    /// overestimates the true variance, which only repeated runs measure.
    pub variance: f64,
    /// Number of primary estimates (points used, including failed samples,
    /// which count as zeros).
    pub samples: u64,
}

impl Estimate {
    /// `√variance`: the estimated standard error.
    pub fn std_error(&self) -> f64 {
        self.variance.sqrt()
    }

    /// `(value − exact) / std_error`: about standard normal for an unbiased
    /// estimator of many independent samples.
    pub fn z_score(&self, exact: f64) -> f64 {
        (self.value - exact) / self.std_error()
    }

    /// The estimate from the statistics of its primary estimates.
    pub fn from_stats(s: &Stats) -> Self {
        Estimate {
            value: s.mean(),
            variance: s.variance() / s.count() as f64,
            samples: s.count(),
        }
    }
}

/// The primary estimate `f(x)/p(x)` of one sample; 0 where `f(x) = 0`
/// (even if `p` underflowed to 0 there).
#[inline]
fn ratio(f: f64, pdf: f64) -> f64 {
    if f == 0.0 { 0.0 } else { f / pdf }
}

/// Importance sampling: the mean of `f(x_k)/p(x_k)` over the points
/// `x_k = strategy.sample(u_k, v_k)` (Arvo, eq. 2.3). A `None` sample
/// counts as a zero.
///
/// `f` is the integrand in the strategy's measure. Unbiased for uniform
/// random `(u, v)`; for stratified or low-discrepancy points the value is
/// the (quasi-)Monte Carlo estimate, but [`Estimate::variance`] is then only
/// an upper-bound-like indicator.
pub fn monte_carlo<S, F, I>(strategy: &S, mut f: F, points: I) -> Estimate
where
    S: Strategy + ?Sized,
    F: FnMut(&S::Point) -> f64,
    I: IntoIterator<Item = (f64, f64)>,
{
    let mut stats = Stats::new();
    for (u, v) in points {
        let y = match strategy.sample(u, v) {
            Some(s) => ratio(f(&s.point), s.pdf),
            None => 0.0,
        };
        stats.push(y);
    }
    Estimate::from_stats(&stats)
}

/// The primary estimates `f(x_k)/p(x_k)` themselves (for callers that
/// combine them otherwise, e.g. per-stratum statistics).
pub fn primary_estimates<S, F, I>(strategy: &S, mut f: F, points: I) -> Vec<f64>
where
    S: Strategy + ?Sized,
    F: FnMut(&S::Point) -> f64,
    I: IntoIterator<Item = (f64, f64)>,
{
    points
        .into_iter()
        .map(|(u, v)| match strategy.sample(u, v) {
            Some(s) => ratio(f(&s.point), s.pdf),
            None => 0.0,
        })
        .collect()
}

/// Converts a generic-scalar point set (e.g. from [`crate::sampling`]) to
/// `f64` pairs.
pub fn to_f64_points<T: Real>(points: &[(T, T)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .map(|(u, v)| (u.to_f64(), v.to_f64()))
        .collect()
}

#[cfg(test)]
mod tests;
