//! DistributeSamples (Ureña 2000, §4.1): how many of n samples each piece
//! of a partition gets.

use super::*;
// ---------------------------------------------------------------------------
// DistributeSamples (§4.1).

/// How [`distribute_samples`] splits `n` samples among sub-triangles of
/// probabilities `p_i` (proportional to σ⊥).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Allocation {
    /// Ureña (2000) §4.1 and Fig. 5, as written: `n_i = ⌊p_i n⌋`, then,
    /// while `Σ n_i < n`, one more sample to a region chosen with
    /// probability `∝ q_i = max(0, p_i n − n_i)` (recomputed after each
    /// assignment, so a region gets at most one extra sample: successive
    /// sampling without replacement of the `r = n − Σ⌊p_i n⌋ ≤ 3`
    /// residual samples).
    ///
    /// Not exactly unbiased: the paper states that a region still receives
    /// a sample with probability `p_i`, i.e. `E[n_i] = p_i n`, which holds
    /// for `r ≤ 1` but not for `r ≥ 2`: successive sampling ∝ `q` includes
    /// region `i` with a probability other than its fractional part `q_i`
    /// (e.g. `p = (0.45, 0.45, 0.05, 0.05)`, `n = 2`:
    /// `E[n] = (0.8656, 0.8656, 0.1344, 0.1344)`, not `(0.9, 0.9, 0.1, 0.1)`;
    /// see [`expected_counts`]). The estimator's bias is
    /// `(1/n) Σ_i (E[n_i] − p_i n)(μ_i − I)` per split (`μ_i` the region's
    /// mean of `f/p`): zero for constant radiance, small otherwise
    /// (measured in `docs/adaptive-triangle.md`).
    Successive,
    /// The same floor, then the `r` residual samples by *systematic*
    /// sampling of the fractional parts `q_i` (one uniform `U`, region `i`
    /// gets one extra sample per point `U + j`, `j = 0 … r−1`, in its
    /// interval `[Σ_{l<i} q_l, Σ_{l≤i} q_l)`): the same support as §4.1 (each
    /// region gets `⌊p_i n⌋` or `⌊p_i n⌋ + 1`, total `n`) with
    /// `P(extra sample) = q_i` exactly, hence `E[n_i] = p_i n` and an
    /// exactly unbiased estimator. The default.
    #[default]
    Systematic,
    /// Each sample independently to region `i` with probability `p_i` (the
    /// "raw approach" of §4): i.i.d. samples from the adaptive density.
    Multinomial,
}

impl Allocation {
    /// `"successive"`, `"systematic"` or `"multinomial"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Allocation::Successive => "successive",
            Allocation::Systematic => "systematic",
            Allocation::Multinomial => "multinomial",
        }
    }
}

impl core::fmt::Display for Allocation {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The index `i` with `u` in `[C_{i−1}, C_i)` of the cumulative sums of
/// `weights` scaled to `total` (the last positive weight for `u` at or
/// beyond the end).
pub(super) fn pick(weights: &[f64], total: f64, u: f64) -> usize {
    let target = u * total;
    let mut c = 0.0;
    let mut last = 0;
    for (i, w) in weights.iter().enumerate() {
        if *w > 0.0 {
            c += w;
            last = i;
            if target < c {
                return i;
            }
        }
    }
    last
}

/// The floors `⌊p_i n⌋` into `counts`, their sum, and the fractional parts
/// into `frac` (`≥ 0`).
pub(super) fn floors(p: &[f64], n: usize, counts: &mut [usize], frac: &mut [f64]) -> usize {
    let nf = n as f64;
    let mut assigned = 0;
    for ((c, f), pi) in counts.iter_mut().zip(frac.iter_mut()).zip(p) {
        let x = ((*pi).max(0.0) * nf).min(nf);
        let fl = x.floor();
        *c = fl as usize;
        *f = (x - fl).max(0.0);
        assigned += *c;
    }
    // Rounding could only push Σ⌊p_i n⌋ above n if Σ p_i > 1 + 1/n.
    while assigned > n {
        let Some(i) = (0..counts.len()).max_by_key(|&i| counts[i]) else {
            break;
        };
        counts[i] -= 1;
        assigned -= 1;
    }
    assigned
}

/// [`distribute_samples`] without allocation: `p.len() ≤ 8`, counts into
/// `counts[..p.len()]`.
pub(super) fn distribute_into<R: Rng + ?Sized>(
    p: &[f64],
    n: usize,
    allocation: Allocation,
    rng: &mut R,
    counts: &mut [usize],
) {
    let len = p.len();
    let counts = &mut counts[..len];
    let total_p: f64 = p.iter().map(|x| (*x).max(0.0)).sum();
    if len == 0 || !(total_p > 0.0) || !total_p.is_finite() {
        counts.fill(0);
        if len > 0 {
            counts[0] = n;
        }
        return;
    }
    match allocation {
        Allocation::Multinomial => {
            counts.fill(0);
            for _ in 0..n {
                let u: f64 = rng.random();
                counts[pick(p, total_p, u)] += 1;
            }
        }
        Allocation::Successive => {
            let mut frac = [0.0f64; 8];
            let assigned = floors(p, n, counts, &mut frac[..len]);
            let nf = n as f64;
            for _ in assigned..n {
                let mut q = [0.0f64; 8];
                for i in 0..len {
                    q[i] = (p[i].max(0.0) * nf - counts[i] as f64).max(0.0);
                }
                let total: f64 = q[..len].iter().sum();
                let i = if total > 0.0 {
                    let u: f64 = rng.random();
                    pick(&q[..len], total, u)
                } else {
                    // Only reachable through rounding (Σ p_i < 1 − 1/n).
                    (0..len).max_by(|&x, &y| p[x].total_cmp(&p[y])).unwrap_or(0)
                };
                counts[i] += 1;
            }
        }
        Allocation::Systematic => {
            let mut frac = [0.0f64; 8];
            let assigned = floors(p, n, counts, &mut frac[..len]);
            let r = n - assigned;
            if r == 0 {
                return;
            }
            let total: f64 = frac[..len].iter().sum();
            if !(total > 0.0) {
                let i = (0..len).max_by(|&x, &y| p[x].total_cmp(&p[y])).unwrap_or(0);
                counts[i] += r;
                return;
            }
            let scale = r as f64 / total;
            let u: f64 = rng.random();
            let mut c_prev = 0.0f64;
            let mut given = 0usize;
            for i in 0..len {
                let c = if i + 1 == len {
                    r as f64
                } else {
                    c_prev + frac[i] * scale
                };
                // Points U + j in [c_prev, c): ⌈c − U⌉ − ⌈c_prev − U⌉.
                let hits = ((c - u).ceil() - (c_prev - u).ceil()).max(0.0) as usize;
                let hits = hits.min(r - given);
                counts[i] += hits;
                given += hits;
                c_prev = c;
            }
            if given < r {
                counts[len - 1] += r - given;
            }
        }
    }
}

/// DistributeSamples (Ureña 2000, §4.1, Fig. 5): how many of `n` samples
/// go to each of the regions of probabilities `p` (`p_i ≥ 0`, normalized
/// here), by the given [`Allocation`] rule. The counts sum to `n`; with
/// [`Allocation::Successive`] and [`Allocation::Systematic`] region `i`
/// gets `⌊p_i n⌋` or `⌊p_i n⌋ + 1`.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for no regions, more than 8, or
/// probabilities that are negative, non-finite or all zero.
///
/// # Example
/// ```
/// use areawarp::adaptive::{Allocation, distribute_samples};
/// use rand::SeedableRng;
/// let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(3);
/// let p = [0.5, 0.25, 0.125, 0.125];
/// // 8 samples: the floors already sum to 8, whatever the rule.
/// assert_eq!(distribute_samples(&p, 8, Allocation::Successive, &mut rng)?, vec![4, 2, 1, 1]);
/// // 7 samples: floors (3, 1, 0, 0), and 3 residual samples.
/// let c = distribute_samples(&p, 7, Allocation::Systematic, &mut rng)?;
/// assert_eq!(c.iter().sum::<usize>(), 7);
/// assert!(c[0] >= 3 && c[0] <= 4 && c[1] >= 1 && c[1] <= 2 && c[2] <= 1 && c[3] <= 1);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn distribute_samples<R: Rng + ?Sized>(
    p: &[f64],
    n: usize,
    allocation: Allocation,
    rng: &mut R,
) -> Result<Vec<usize>, WarpError> {
    let p = normalized_probabilities(p)?;
    let mut counts = vec![0usize; p.len()];
    distribute_into(&p, n, allocation, rng, &mut counts);
    Ok(counts)
}

/// `p / Σ p`, validated (1 to 8 finite non-negative entries, not all zero).
pub(super) fn normalized_probabilities(p: &[f64]) -> Result<Vec<f64>, WarpError> {
    let invalid = WarpError::InvalidParameter {
        name: "probabilities",
        expected: "1 to 8 finite values >= 0, not all zero",
    };
    if p.is_empty() || p.len() > 8 || p.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
        return Err(invalid);
    }
    let total: f64 = p.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(invalid);
    }
    Ok(p.iter().map(|x| x / total).collect())
}

/// The exact expected counts `E[n_i]` of [`distribute_samples`] (with the
/// same floating-point floors): `p_i n` for [`Allocation::Systematic`] and
/// [`Allocation::Multinomial`]; for [`Allocation::Successive`]
/// `⌊p_i n⌋ + π_i`, with `π_i` the probability that successive sampling
/// ∝ `q` picks region `i` among the `r` residual samples, by enumeration
/// of all ordered selections (`O(len^r)`, `r < len ≤ 8`).
///
/// # Errors
/// As [`distribute_samples`].
///
/// # Example
/// ```
/// use areawarp::adaptive::{Allocation, expected_counts};
/// let p = [0.45, 0.45, 0.05, 0.05];
/// let e = expected_counts(&p, 2, Allocation::Successive)?;
/// assert!((e[0] - 0.8656).abs() < 1e-4 && (e[2] - 0.1344).abs() < 1e-4);
/// let e = expected_counts(&p, 2, Allocation::Systematic)?;
/// assert!((e[0] - 0.9).abs() < 1e-12);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn expected_counts(p: &[f64], n: usize, allocation: Allocation) -> Result<Vec<f64>, WarpError> {
    let p = normalized_probabilities(p)?;
    let len = p.len();
    let nf = n as f64;
    match allocation {
        Allocation::Multinomial | Allocation::Systematic => {
            Ok(p.iter().map(|pi| pi * nf).collect())
        }
        Allocation::Successive => {
            let mut counts = vec![0usize; len];
            let mut frac = vec![0.0; len];
            let assigned = floors(&p, n, &mut counts, &mut frac);
            let r = n - assigned;
            let mut inclusion = vec![0.0; len];
            let mut taken = vec![false; len];
            successive_inclusion(&frac, r, 1.0, &mut taken, &mut inclusion);
            Ok(counts
                .iter()
                .zip(&inclusion)
                .map(|(c, pi)| *c as f64 + pi)
                .collect())
        }
    }
}

/// Adds to `inclusion[i]` the probability (times `weight`) that region `i`
/// is among the next `r` successive draws ∝ `frac` over the regions not
/// yet `taken`.
pub(super) fn successive_inclusion(
    frac: &[f64],
    r: usize,
    weight: f64,
    taken: &mut [bool],
    inclusion: &mut [f64],
) {
    if r == 0 || weight == 0.0 {
        return;
    }
    let total: f64 = (0..frac.len())
        .filter(|&i| !taken[i])
        .map(|i| frac[i])
        .sum();
    if !(total > 0.0) {
        return;
    }
    for i in 0..frac.len() {
        if taken[i] || frac[i] <= 0.0 {
            continue;
        }
        let w = weight * frac[i] / total;
        inclusion[i] += w;
        taken[i] = true;
        successive_inclusion(frac, r - 1, w, taken, inclusion);
        taken[i] = false;
    }
}
