//! Multiple importance sampling: the multi-sample estimator of Veach and
//! Guibas (1995) as presented by Arvo (2001, ch. 2).

use super::{Estimate, Stats, Strategy, ratio};
use crate::error::WarpError;

/// How the samples of `k` strategies are weighted (Arvo 2001, §2.3).
///
/// Every heuristic computes the weights `w_i(x)` from the *weighted
/// densities* `q_j = N_j p_j(x)` (`N_j` the number of samples of strategy
/// `j`, i.e. Arvo's `c_j p_j(x)` with `c_j = N_j / N`), and every weight
/// vector is non-negative and sums to 1 at every `x` — the two conditions
/// (Arvo, eq. 2.6–2.7) that make the combined estimator unbiased whatever
/// the heuristic. Where all `q_j` vanish (no strategy can sample `x`) the
/// weights are `1/k` each, so that the sum is 1 there too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Heuristic {
    /// `w_i = q_i / Σ_j q_j` (Arvo, eq. 2.8): with `N_i ∝ c_i`, plain
    /// importance sampling from the mixture density (eq. 2.11). Its variance
    /// is within `I² (1/N_min − 1/N)` of that of any other weighting
    /// (Veach; Arvo, eq. 2.14).
    Balance,
    /// `w_i = q_i^β / Σ_j q_j^β` for an exponent `β > 0` (Veach's power
    /// heuristic; `β = 1` is the balance heuristic, `β → ∞` the maximum
    /// heuristic; Veach recommends `β = 2`). Arvo's eq. 2.13 writes
    /// `c_i p_i^m / Σ c_j p_j^m`, which is another valid weighting but not
    /// Veach's for unequal `N_i`; this is Veach's.
    Power(f64),
    /// `w_i = 1` for the strategy of largest `q_i`, 0 for the others (Arvo,
    /// eq. 2.12); ties share the weight equally.
    Maximum,
}

impl Heuristic {
    /// Checks the parameter: a finite exponent `β > 0`.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] for an invalid exponent.
    pub fn validate(&self) -> Result<(), WarpError> {
        match self {
            Heuristic::Power(b) if !(b.is_finite() && *b > 0.0) => {
                Err(WarpError::InvalidParameter {
                    name: "power heuristic exponent",
                    expected: "a finite exponent > 0",
                })
            }
            _ => Ok(()),
        }
    }

    /// A short name for reports: `balance`, `power(2)`, `maximum`.
    pub fn name(&self) -> String {
        match self {
            Heuristic::Balance => "balance".to_string(),
            Heuristic::Power(b) => format!("power({b})"),
            Heuristic::Maximum => "maximum".to_string(),
        }
    }

    /// The weight `w_i` of strategy `i` given the weighted densities
    /// `q_j = N_j p_j(x)` of all strategies at `x` (negative or NaN entries
    /// count as 0). O(k), no allocation. 0 for `i ≥ q.len()`.
    pub fn weight(&self, i: usize, q: &[f64]) -> f64 {
        let Some(&qi) = q.get(i) else {
            return 0.0;
        };
        let qi = clean(qi);
        let k = q.len() as f64;
        let max = q.iter().fold(0.0_f64, |m, &x| m.max(clean(x)));
        if max == 0.0 {
            return 1.0 / k;
        }
        if max == f64::INFINITY {
            // Only the infinite densities count, equally.
            let n_inf = q.iter().filter(|&&x| x == f64::INFINITY).count() as f64;
            return if qi == f64::INFINITY {
                1.0 / n_inf
            } else {
                0.0
            };
        }
        match *self {
            Heuristic::Balance => {
                // Scaled by the maximum so the sum cannot overflow.
                let total: f64 = q.iter().map(|&x| clean(x) / max).sum();
                (qi / max) / total
            }
            Heuristic::Power(beta) => {
                let total: f64 = q.iter().map(|&x| (clean(x) / max).powf(beta)).sum();
                (qi / max).powf(beta) / total
            }
            Heuristic::Maximum => {
                if qi == max {
                    1.0 / q.iter().filter(|&&x| clean(x) == max).count() as f64
                } else {
                    0.0
                }
            }
        }
    }

    /// All `k` weights at once (`out.len() = q.len()`), as [`Heuristic::weight`].
    pub fn weights(&self, q: &[f64], out: &mut [f64]) {
        for (i, w) in out.iter_mut().enumerate().take(q.len()) {
            *w = self.weight(i, q);
        }
    }
}

/// A density as a weight input: NaN and negative values count as 0.
#[inline]
fn clean(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}

/// The multi-sample MIS estimator of `k` strategies with `N_i` samples
/// each (Arvo 2001, eq. 2.4–2.5):
///
/// `F = Σ_i (1/N_i) Σ_{j ≤ N_i} w_i(X_ij) f(X_ij) / p_i(X_ij)`,
///
/// with `X_ij` the points of strategy `i` and the weights of a
/// [`Heuristic`] computed from `q_j = N_j p_j(x)`. Unbiased for any
/// heuristic as long as, wherever `f ≠ 0`, some strategy with `N_i > 0`
/// has `p_i > 0`. A strategy with `N_i = 0` takes no part (its `q_i = 0`).
///
/// All strategies must share the integral's measure (e.g. solid angle:
/// convert area densities with `r² / cos θ` first).
pub struct Mis<'a, P> {
    strategies: Vec<&'a dyn Strategy<Point = P>>,
    counts: Vec<usize>,
    heuristic: Heuristic,
}

impl<P> core::fmt::Debug for Mis<'_, P> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Mis")
            .field("strategies", &self.strategies.len())
            .field("counts", &self.counts)
            .field("heuristic", &self.heuristic)
            .finish()
    }
}

/// The result of [`Mis::estimate`].
#[derive(Clone, Debug, PartialEq)]
pub struct MisEstimate {
    /// The estimate `F` of the integral.
    pub value: f64,
    /// Its estimated variance, `Σ_i s_i² / N_i` with `s_i²` the sample
    /// variance of strategy `i`'s weighted primary estimates
    /// `w_i f / p_i` (NaN if some `N_i` is 1).
    pub variance: f64,
    /// Per strategy: the statistics of its weighted primary estimates
    /// (their mean is strategy `i`'s contribution to `value`).
    pub per_strategy: Vec<Stats>,
}

impl MisEstimate {
    /// `√variance`.
    pub fn std_error(&self) -> f64 {
        self.variance.sqrt()
    }

    /// As a plain [`Estimate`] (`samples` = total number of points).
    pub fn as_estimate(&self) -> Estimate {
        Estimate {
            value: self.value,
            variance: self.variance,
            samples: self.per_strategy.iter().map(Stats::count).sum(),
        }
    }
}

impl<'a, P> Mis<'a, P> {
    /// MIS of `strategies` with `counts[i]` samples from strategy `i`.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if there are no strategies, the
    /// lengths differ, all counts are zero, or the heuristic's exponent is
    /// invalid ([`Heuristic::validate`]).
    pub fn new(
        strategies: &[&'a dyn Strategy<Point = P>],
        counts: &[usize],
        heuristic: Heuristic,
    ) -> Result<Self, WarpError> {
        heuristic.validate()?;
        if strategies.is_empty() || strategies.len() != counts.len() {
            return Err(WarpError::InvalidParameter {
                name: "counts",
                expected: "one sample count per strategy",
            });
        }
        if counts.iter().all(|&n| n == 0) {
            return Err(WarpError::InvalidParameter {
                name: "counts",
                expected: "at least one strategy with samples",
            });
        }
        Ok(Mis {
            strategies: strategies.to_vec(),
            counts: counts.to_vec(),
            heuristic,
        })
    }

    /// The number of strategies `k`.
    pub fn len(&self) -> usize {
        self.strategies.len()
    }

    /// `true` if there are no strategies (never, for a constructed `Mis`).
    pub fn is_empty(&self) -> bool {
        self.strategies.is_empty()
    }

    /// The sample counts `N_i`.
    pub fn counts(&self) -> &[usize] {
        &self.counts
    }

    /// The heuristic.
    pub fn heuristic(&self) -> Heuristic {
        self.heuristic
    }

    /// The weights `w_i(x)` of all strategies at `x` into `out`
    /// (`out.len() = k`), from the strategies' [`Strategy::pdf`].
    pub fn weights_at(&self, x: &P, out: &mut [f64]) {
        let q: Vec<f64> = self
            .strategies
            .iter()
            .zip(&self.counts)
            .map(|(s, &n)| n as f64 * s.pdf(x))
            .collect();
        self.heuristic.weights(&q, out);
    }

    /// The estimate of `∫ f` from `N_i` points `(u, v)` per strategy:
    /// `points(i)` yields strategy `i`'s points (the first `N_i` are used).
    ///
    /// Allocates O(k) once per call, nothing per sample. The other
    /// strategies' densities are evaluated only where `f(x) ≠ 0`.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if `points(i)` yields fewer than
    /// `N_i` points (the estimate would be biased).
    pub fn estimate<F, G, I>(&self, mut f: F, mut points: G) -> Result<MisEstimate, WarpError>
    where
        F: FnMut(&P) -> f64,
        G: FnMut(usize) -> I,
        I: IntoIterator<Item = (f64, f64)>,
    {
        let k = self.strategies.len();
        let mut q = vec![0.0; k];
        let mut per_strategy = vec![Stats::new(); k];
        for (i, strategy) in self.strategies.iter().enumerate() {
            let n_i = self.counts[i];
            if n_i == 0 {
                continue;
            }
            let stats = &mut per_strategy[i];
            for (u, v) in points(i).into_iter().take(n_i) {
                let y = match strategy.sample(u, v) {
                    None => 0.0,
                    Some(s) => {
                        let fx = f(&s.point);
                        if fx == 0.0 {
                            0.0
                        } else {
                            for (j, other) in self.strategies.iter().enumerate() {
                                let p = if j == i { s.pdf } else { other.pdf(&s.point) };
                                q[j] = self.counts[j] as f64 * p;
                            }
                            self.heuristic.weight(i, &q) * ratio(fx, s.pdf)
                        }
                    }
                };
                stats.push(y);
            }
            if (stats.count() as usize) < n_i {
                return Err(WarpError::InvalidParameter {
                    name: "points",
                    expected: "at least N_i points (u, v) for strategy i",
                });
            }
        }
        let value = per_strategy.iter().map(Stats::mean).sum();
        let variance = per_strategy
            .iter()
            .filter(|s| s.count() > 0)
            .map(|s| s.variance() / s.count() as f64)
            .sum();
        Ok(MisEstimate {
            value,
            variance,
            per_strategy,
        })
    }
}
