//! Adaptive sampling of a spherical triangle for cosine-weighted integrals:
//! Ureña (2000), *Computation of irradiance from triangles by adaptive
//! sampling* (LSI-2000-1). Derivations, the variance bound and the measured
//! results: `docs/adaptive-triangle.md`.
//!
//! # The problem
//! A triangle seen from a receiver (normal `+z`) is a spherical triangle `S`;
//! its vertical projection `E` into the unit disk has area
//! `σ⊥(E) = ∫_S cos θ dω`, the projected solid angle. The integrals of
//! interest are `I = ∫_E f dσ⊥ = ∫_S f(ω) cos θ dω` (irradiance for
//! `f = L_i`). The ideal sampler, density `1/σ⊥(E)` per unit of `σ⊥`, has
//! the smallest second moment of all `f`-independent samplers,
//! `U₀ = σ⊥(E) ∫_E f² dσ⊥`; Arvo's map ([`SphericalTriangle`]) only gives
//! density `1/σ(E)` per steradian.
//!
//! # The algorithm
//! Split `E` into 4 sub-triangles at its edges' (normalized) midpoints,
//! recursively, until every piece `R` has
//! `k(R) = m(R)·σ(R)/σ⊥(R) − 1 < K`, with `m(R)` the largest `cos θ` over
//! `R` ([`max_cosine`]); give each piece a share of the `n` samples
//! proportional to its `σ⊥` ([`distribute_samples`], §4.1), and sample
//! each piece uniformly in solid angle with Arvo's map. A sample in piece
//! `R` has density (per steradian)
//!
//! `p(ω) = P(R)/σ(R)`,  `P(R) = Π` over the splits of `σ⊥(child)/Σ σ⊥(children)`
//!
//! (`P(R) = σ⊥(R)/σ⊥(E)` up to rounding), i.e. the paper's eq. (4),
//! `p⊥(u) = σ⊥(R)/(σ⊥(E) σ(R) cos u)` per unit of `σ⊥`. Since
//! `cos ≤ m(R)` on `R`, the estimator's per-sample weight
//! `w = cos θ / p(ω) = 1/p⊥` satisfies `w ≤ σ⊥(E)(1 + k(R)) < σ⊥(E)(1 + K)`
//! at every sample, which gives the paper's bound on the second moment,
//! `U = ∫ f²/p⊥ dσ⊥ ≤ (1 + K) U₀`.
//!
//! # Why this is not a [`Warp`]
//! The paper's method places the `n` samples *jointly*: a piece receives
//! `⌊P n⌋` or `⌊P n⌋ + 1` of them, drawn by the allocation rule, so the
//! k-th sample is not a function of one point of the unit square, and the
//! set depends on `n`. The partition is also built lazily, only where
//! samples go (it can have 10⁵–10⁶ pieces for small `K`). The density of
//! the samples *is* well defined, and [`AdaptiveTriangle::pdf`] evaluates
//! it at any direction (for multiple importance sampling), but the sampler
//! is a generator of sample sets ([`AdaptiveTriangle::generate`] →
//! [`SampleSet`]), not a map.
//!
//! # Example
//! ```
//! use areawarp::adaptive::AdaptiveTriangle;
//! use areawarp::shapes::polygon_measures::projected_solid_angle;
//! use areawarp::Vec3;
//! use rand::SeedableRng;
//!
//! let (a, b, c) = (
//!     Vec3::new(1.0, -0.5, 0.3),
//!     Vec3::new(1.0, 0.6, 0.4),
//!     Vec3::new(0.2, 0.0, 1.0),
//! );
//! let t = AdaptiveTriangle::new(a.clone(), b.clone(), c.clone(), 0.01)?;
//! let exact = projected_solid_angle(&[a, b, c], &Vec3::new(0.0, 0.0, 1.0)).abs();
//! assert!((t.projected_solid_angle() - exact).abs() < 1e-14);
//!
//! let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(1);
//! let set = t.generate(64, &mut rng);
//! assert_eq!(set.len(), 64);
//! // Irradiance from a unit radiance: every weight is within 1 + K of σ⊥.
//! let e = set.estimate(|_| 1.0);
//! assert!((e / exact - 1.0).abs() < 0.01);
//! assert!(set.weights.iter().all(|w| *w <= exact * (1.0 + 0.01) * (1.0 + 1e-12)));
//! # Ok::<(), areawarp::WarpError>(())
//! ```

#[cfg(test)]
mod tests;

use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::SphericalTriangle;
use crate::vector::Frame;
use crate::vector::Vec3;
use crate::warp::Warp;
use rand::{Rng, RngExt};
use std::borrow::Cow;
use std::sync::OnceLock;

// ---------------------------------------------------------------------------
// Measures of one spherical triangle (generic).

/// The largest `z` (`cos θ` about the receiver's normal `+z`) on the minor
/// great arc from `a` to `b` (directions, normalized here).
///
/// On the great circle with normal `n = a × b` the highest point is
/// `p = (ẑ − n̂_z n̂)/√(1 − n̂_z²)`, of height `√(1 − n̂_z²) = |n_xy|/|n|`;
/// it is on the arc iff it lies between `a` and `b`, i.e.
/// `(a × p)·n ≥ 0` and `(p × b)·n ≥ 0`. Otherwise `z` is monotone along
/// the arc and the maximum is at an end (Ureña 2000, §4.3, Fig. 6). An
/// arc on the horizon (`n ∥ ẑ`) has `z = 0` throughout.
///
/// # Example
/// ```
/// use areawarp::adaptive::arc_max_cosine;
/// use areawarp::Vec3;
/// // A meridian arc over the pole: its maximum is the pole.
/// let a = Vec3::<f64>::new(1.0, 0.0, 1.0);
/// let b = Vec3::<f64>::new(-1.0, 0.0, 1.0);
/// assert!((arc_max_cosine(&a, &b) - 1.0).abs() < 1e-15);
/// // An arc peaking between its ends, at (1, 0, 1)/√2 by symmetry.
/// let m = arc_max_cosine(&Vec3::<f64>::new(1.0, -1.0, 1.0), &Vec3::new(1.0, 1.0, 1.0));
/// assert!((m - 0.5f64.sqrt()).abs() < 1e-15);
/// ```
pub fn arc_max_cosine<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    let (a, b) = (unit_or_nan(a), unit_or_nan(b));
    let mut m = a.z.clone().max(&b.z);
    let n = a.cross(&b);
    let s2 = n.x.square() + &n.y.square();
    if s2 > T::zero() {
        // p ∝ ẑ |n|² − n_z n (height s2 > 0), unnormalized.
        let p = Vec3::new(-(n.z.clone() * &n.x), -(n.z.clone() * &n.y), s2.clone());
        if a.cross(&p).dot(&n) >= T::zero() && p.cross(&b).dot(&n) >= T::zero() {
            let top = s2.sqrt() / &n.norm();
            m = m.max(&top);
        }
    }
    m
}

/// `m(E)`: the largest `z = cos θ` over the spherical triangle `a b c`
/// (directions, normalized here; minor arcs), Ureña (2000) §4.3.
///
/// `z` is the height function on the sphere; restricted to a spherical
/// triangle (a geodesically convex region smaller than a hemisphere) its
/// maximum is either the pole `ẑ`, if the triangle contains it (then
/// `m = 1`), or on the boundary — a local maximum of `z` inside a region
/// that does not contain the pole would be a critical point of `z` on the
/// sphere other than ±ẑ, and there is none. On the boundary it is the
/// largest of the three arc maxima ([`arc_max_cosine`]). The pole is in
/// the triangle iff it is on the inner side of all three edges, i.e. the
/// `z` components of the edge normals `v_i × v_{i+1}` all have the
/// orientation's sign (§4.3).
///
/// # Example
/// ```
/// use areawarp::adaptive::max_cosine;
/// use areawarp::Vec3;
/// // Around the pole: m = 1.
/// let r = 0.5f64;
/// let (a, b, c) = (
///     Vec3::new(r, 0.0, 1.0),
///     Vec3::new(-r / 2.0, r * 0.75f64.sqrt(), 1.0),
///     Vec3::new(-r / 2.0, -r * 0.75f64.sqrt(), 1.0),
/// );
/// assert_eq!(max_cosine(&a, &b, &c), 1.0);
/// // Off the pole, at the highest vertex.
/// let (a, b, c) = (Vec3::new(1.0, 0.0, 0.1), Vec3::new(0.0, 1.0, 0.1), Vec3::new(1.0, 1.0, 1.0));
/// assert!((max_cosine(&a, &b, &c) - 1.0 / 3f64.sqrt()).abs() < 1e-15);
/// ```
pub fn max_cosine<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    let (a, b, c) = (unit_or_nan(a), unit_or_nan(b), unit_or_nan(c));
    // Orientation from differences (accurate for small triangles).
    let det = a.dot(&b.sub(&a).cross(&c.sub(&a)));
    let zero = T::zero();
    let (nab, nbc, nca) = (a.cross(&b).z, b.cross(&c).z, c.cross(&a).z);
    let inside = if det > zero {
        nab >= zero && nbc >= zero && nca >= zero
    } else if det < zero {
        nab <= zero && nbc <= zero && nca <= zero
    } else {
        false
    };
    if inside {
        return T::one();
    }
    arc_max_cosine(&a, &b)
        .max(&arc_max_cosine(&b, &c))
        .max(&arc_max_cosine(&c, &a))
}

/// `v/|v|`, NaN coordinates for a zero or non-finite `v`.
fn unit_or_nan<T: Real>(v: &Vec3<T>) -> Vec3<T> {
    v.normalized().unwrap_or_else(|| {
        let nan = T::zero() / T::zero();
        Vec3::new(nan.clone(), nan.clone(), nan)
    })
}

/// Lambert's formula for the projected solid angle (receiver normal `+z`)
/// of the spherical triangle with *unit* vertices `a`, `b`, `c`:
///
/// `σ⊥ = ½ |Σ_i θ_i n̂_i·ẑ|`, `θ_i = ∠(v_i, v_{i+1})`, `n̂_i = v_i × v_{i+1}/|v_i × v_{i+1}|`
///
/// (π × the point-to-polygon form factor; Ureña 2000 §4.2, whose `n_i`
/// must be normalized). Each edge normal is formed as `v_i × (v_{i+1} − v_i)`
/// (the same vector, without the cancellation of `v_i × v_{i+1}` for short
/// edges), so that each term has full relative accuracy; the sum of the
/// three `O(size)` terms to an `O(size²)` result still costs a relative
/// error of about `u/size` (`u` the unit roundoff). Edges of zero length
/// contribute 0.
fn lambert<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    let zero = T::zero();
    let mut sum = zero.clone();
    for (x, y) in [(a, b), (b, c), (c, a)] {
        let n = x.cross(&y.sub(x));
        let s = n.norm();
        if s > zero {
            sum += &(s.atan2(&x.dot(y)) * &n.z / &s);
        }
    }
    (sum / &T::from_i64(2)).abs()
}

/// The solid angle of the triangle with unit vertices `a`, `b`, `c` by the
/// evaluation of [`SphericalTriangle::new`] (Van Oosterom–Strackee,
/// `Ω = 2 atan2(|det|, 1 + a·b + b·c + c·a)`, with `det(a, b, c)` from the
/// cross product of the two shortest chords at the vertex opposite the
/// longest, and `1 + a·b = |a + b|²/2`), and `true` if the triangle passes
/// that constructor's non-degeneracy test `|det| > 256 u ℓ₁ℓ₂` with a
/// 16-fold margin (so that [`SphericalTriangle::new`] accepts it too).
fn robust_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> (T, bool) {
    let ab = b.sub(a);
    let bc = c.sub(b);
    let ca = a.sub(c);
    let (l_ab, l_bc, l_ca) = (ab.norm(), bc.norm(), ca.norm());
    let (det, l1, l2) = if l_bc >= l_ab && l_bc >= l_ca {
        (a.dot(&ab.cross(&ca.neg())), &l_ab, &l_ca)
    } else if l_ca >= l_ab {
        (b.dot(&bc.cross(&ab.neg())), &l_ab, &l_bc)
    } else {
        (c.dot(&ca.cross(&bc.neg())), &l_bc, &l_ca)
    };
    let two = T::from_i64(2);
    let a_plus_b = a.add(b);
    let den = a_plus_b.dot(&a_plus_b) / &two + &c.dot(&a_plus_b);
    let omega = det.abs().atan2(&den) * &two;
    let threshold = T::from_i64(4096) * &T::unit_roundoff() * l1 * l2;
    let ok = det.abs() > threshold
        && omega > T::zero()
        && (T::one() / &omega).is_finite()
        && l1.clone() > T::zero();
    (omega, ok)
}

/// σ, σ⊥, m and k of one spherical triangle above the receiver's horizon
/// (receiver normal `+z`), the quantities that drive the subdivision.
///
/// - `σ` ([`solid_angle`](Self::solid_angle)): the solid angle, by the
///   robust Van Oosterom–Strackee evaluation of [`SphericalTriangle`]
///   (not Girard's `Σβ − π` of the paper's §4.2, which cancels for small
///   triangles);
/// - `σ⊥` ([`projected_solid_angle`](Self::projected_solid_angle)):
///   Lambert's formula `½ |Σ θ_i n̂_i·ẑ|`, with edge normals formed from
///   differences (relative error about `u/size`);
/// - `m` ([`max_cosine`](Self::max_cosine)): [`max_cosine`];
/// - `k = m σ/σ⊥ − 1` ([`k`](Self::k), eq. 5): `≥ 0` since
///   `σ⊥ = ∫ cos dσ ≤ m σ` (to rounding); `+∞` when `σ⊥ = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMeasures<T> {
    /// σ, in steradians.
    pub solid_angle: T,
    /// σ⊥ = ∫ cos θ dω.
    pub projected_solid_angle: T,
    /// m = max cos θ over the triangle.
    pub max_cosine: T,
    /// k = m σ / σ⊥ − 1.
    pub k: T,
}

impl<T: Real> TriangleMeasures<T> {
    /// The measures of the triangle with vertex directions `a`, `b`, `c`.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`] (non-finite, zero, coincident or
    /// collinear vertices), and [`WarpError::InvalidParameter`] if a vertex
    /// is below the horizon (`z < 0`: clip first, as
    /// [`AdaptiveTriangle::new`] does).
    ///
    /// # Example
    /// ```
    /// use areawarp::adaptive::TriangleMeasures;
    /// use areawarp::Vec3;
    /// // The octant: σ = π/2, σ⊥ = π/4, m = 1 (the pole is a vertex), k = 1.
    /// let m = TriangleMeasures::<f64>::new(
    ///     Vec3::new(1.0, 0.0, 0.0),
    ///     Vec3::new(0.0, 1.0, 0.0),
    ///     Vec3::new(0.0, 0.0, 1.0),
    /// )?;
    /// assert!((m.k - 1.0).abs() < 1e-15);
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn new(a: Vec3<T>, b: Vec3<T>, c: Vec3<T>) -> Result<Self, WarpError> {
        Self::of(&SphericalTriangle::new(a, b, c)?)
    }

    /// The measures of an existing [`SphericalTriangle`] (σ is its
    /// [`solid_angle`](SphericalTriangle::solid_angle)).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if a vertex is below the horizon.
    pub fn of(tri: &SphericalTriangle<T>) -> Result<Self, WarpError> {
        let zero = T::zero();
        let (a, b, c) = (tri.a(), tri.b(), tri.c());
        if a.z < zero || b.z < zero || c.z < zero {
            return Err(WarpError::InvalidParameter {
                name: "vertices",
                expected: "directions with z >= 0 (clip against the horizon first)",
            });
        }
        Ok(Self::with_solid_angle(a, b, c, tri.solid_angle().clone()))
    }

    /// The measures of the triangle with unit vertices `a b c` (z ≥ 0) and
    /// solid angle `sigma`.
    fn with_solid_angle(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>, sigma: T) -> Self {
        let zero = T::zero();
        let sigma_perp = lambert(a, b, c);
        let m = max_cosine(a, b, c);
        let k = if sigma_perp > zero {
            m.clone() * &sigma / &sigma_perp - &T::one()
        } else {
            T::one() / T::zero()
        };
        TriangleMeasures {
            solid_angle: sigma,
            projected_solid_angle: sigma_perp,
            max_cosine: m,
            k,
        }
    }
}

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
fn pick(weights: &[f64], total: f64, u: f64) -> usize {
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
fn floors(p: &[f64], n: usize, counts: &mut [usize], frac: &mut [f64]) -> usize {
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
fn distribute_into<R: Rng + ?Sized>(
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
fn normalized_probabilities(p: &[f64]) -> Result<Vec<f64>, WarpError> {
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
fn successive_inclusion(
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

// ---------------------------------------------------------------------------
// The subdivision tree.

/// One spherical triangle of the subdivision. Only its vertices and σ⊥
/// (needed to share samples among siblings) are computed when it is
/// created; σ, m, k (needed once samples reach it), its solid-angle sampler
/// (once it is a leaf with samples) and its children (memoized near the
/// root) are computed on first use.
#[derive(Clone, Debug)]
struct Node {
    /// Unit vertices.
    v: [Vec3<f64>; 3],
    sigma_perp: f64,
    depth: u32,
    /// `root · 4^depth + Σ digit · 4^…` (see [`Piece::code`]).
    code: u64,
    measures: OnceLock<TriangleMeasures<f64>>,
    sampler: OnceLock<Option<SphericalTriangle<f64>>>,
    children: OnceLock<Option<Box<[Node; 4]>>>,
}

impl Node {
    /// The node with unit vertices `v`, if it is not degenerate in `f64`
    /// (see [`robust_solid_angle`]).
    fn new(v: [Vec3<f64>; 3], depth: u32, code: u64) -> Option<Self> {
        let (sigma, ok) = robust_solid_angle(&v[0], &v[1], &v[2]);
        if !ok || v.iter().any(|p| !(p.z >= 0.0)) {
            return None;
        }
        let sigma_perp = lambert(&v[0], &v[1], &v[2]);
        let measures = OnceLock::new();
        // Roots compute everything at once; children lazily.
        if depth == 0 {
            let _ = measures.set(TriangleMeasures::with_solid_angle(
                &v[0], &v[1], &v[2], sigma,
            ));
        }
        Some(Node {
            v,
            sigma_perp,
            depth,
            code,
            measures,
            sampler: OnceLock::new(),
            children: OnceLock::new(),
        })
    }

    fn measures(&self) -> &TriangleMeasures<f64> {
        self.measures.get_or_init(|| {
            let [a, b, c] = &self.v;
            let (sigma, _) = robust_solid_angle(a, b, c);
            TriangleMeasures::with_solid_angle(a, b, c, sigma)
        })
    }

    /// Arvo's map for this triangle (`None` only if [`SphericalTriangle::new`]
    /// rejected a triangle [`Node::new`] accepted, which its margin rules out).
    fn sampler(&self) -> Option<&SphericalTriangle<f64>> {
        self.sampler
            .get_or_init(|| {
                let [a, b, c] = &self.v;
                SphericalTriangle::new(*a, *b, *c).ok()
            })
            .as_ref()
    }

    /// The four children at the normalized edge midpoints (Fig. 2): the
    /// corners at the first, second and third vertex, then the middle
    /// triangle; `None` if a child is degenerate in `f64`.
    fn split(&self) -> Option<Box<[Node; 4]>> {
        let [a, b, c] = &self.v;
        let mab = a.add(b).normalized()?;
        let mbc = b.add(c).normalized()?;
        let mca = c.add(a).normalized()?;
        let d = self.depth + 1;
        let code = self.code * 4;
        Some(Box::new([
            Node::new([*a, mab, mca], d, code)?,
            Node::new([mab, *b, mbc], d, code + 1)?,
            Node::new([mca, mbc, *c], d, code + 2)?,
            Node::new([mab, mbc, mca], d, code + 3)?,
        ]))
    }
}

/// The shares `σ⊥(D_i)/Σ_j σ⊥(D_j)` of `nodes` (by solid angle if all
/// σ⊥ vanish).
fn shares(nodes: &[Node], out: &mut [f64]) {
    let total: f64 = nodes.iter().map(|d| d.sigma_perp).sum();
    if total > 0.0 && total.is_finite() {
        for (o, d) in out.iter_mut().zip(nodes) {
            *o = d.sigma_perp / total;
        }
    } else {
        let total: f64 = nodes.iter().map(|d| d.measures().solid_angle).sum();
        for (o, d) in out.iter_mut().zip(nodes) {
            *o = d.measures().solid_angle / total;
        }
    }
}

/// One piece of the adaptive partition (a leaf of the subdivision).
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// The unit vertex directions (receiver frame, normal `+z`).
    pub vertices: [Vec3<f64>; 3],
    /// σ, σ⊥, m and k of the piece.
    pub measures: TriangleMeasures<f64>,
    /// The subdivision depth (0 for the input triangle, or for each of the
    /// two triangles of a clipped quadrilateral).
    pub depth: u32,
    /// The piece's identifier: the root index followed by the child digits
    /// (0, 1, 2 = corner at the parent's first, second, third vertex,
    /// 3 = middle), in base 4.
    pub code: u64,
    /// The probability `P` that a sample falls in the piece (product of the
    /// σ⊥ shares along its path; `σ⊥(piece)/σ⊥(E)` up to rounding).
    pub probability: f64,
    /// `true` if the piece was not split although `k ≥ K`, because it
    /// reached the maximum depth or a child would be degenerate in `f64`.
    pub capped: bool,
}

/// Summary of an adaptive partition ([`AdaptiveTriangle::partition_summary`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PartitionSummary {
    /// The number of pieces.
    pub pieces: usize,
    /// The deepest piece's depth.
    pub max_depth: u32,
    /// The number of capped pieces ([`Piece::capped`]).
    pub capped: usize,
    /// Their total probability.
    pub capped_probability: f64,
    /// `Σ_capped (k(R) − K) P(R)`.
    pub capped_excess: f64,
}

/// A piece that received samples in one [`AdaptiveTriangle::generate`]
/// call.
#[derive(Clone, Debug, PartialEq)]
pub struct LeafVisit {
    /// The piece's identifier ([`Piece::code`]) and depth.
    pub code: u64,
    /// The piece's depth.
    pub depth: u32,
    /// Its probability `P` ([`Piece::probability`]).
    pub probability: f64,
    /// Its `k`.
    pub k: f64,
    /// Whether it is a capped piece ([`Piece::capped`]).
    pub capped: bool,
    /// The number of samples it received.
    pub count: usize,
}

/// The samples of one [`AdaptiveTriangle::generate`] call, in the order
/// they were generated (piece by piece, depth first), with everything an
/// estimator needs.
///
/// The estimator of `I = ∫ f(ω) cos⁺θ dω` (the paper's eq. 2, divided by
/// `n`) is `Î = (1/n) Σ_i f(ω_i) w_i` with `w_i = cos θ_i / p(ω_i)`
/// ([`SampleSet::estimate`]); that of `∫ g dω` for an integrand in solid
/// angle is `(1/n) Σ g(ω_i)/p(ω_i)` ([`SampleSet::estimate_solid_angle`]).
/// Both are unbiased with [`Allocation::Systematic`] and
/// [`Allocation::Multinomial`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleSet {
    /// The unit directions (world frame for
    /// [`AdaptiveTriangle::from_points`], else the receiver frame).
    pub directions: Vec<Vec3<f64>>,
    /// `cos θ_i` (clamped to `≥ 0`).
    pub cosines: Vec<f64>,
    /// The density `p(ω_i) = P(R)/σ(R)` per steradian.
    pub pdfs: Vec<f64>,
    /// The weights `w_i = cos θ_i / p(ω_i) = cos θ_i σ(R)/P(R)`, the
    /// reciprocal of the paper's probability `p⊥` (eq. 4).
    pub weights: Vec<f64>,
    /// For each sample, the index of its piece in [`SampleSet::leaves`].
    pub leaf: Vec<u32>,
    /// The pieces that received samples, in generation order.
    pub leaves: Vec<LeafVisit>,
}

impl SampleSet {
    /// The number of samples.
    pub fn len(&self) -> usize {
        self.directions.len()
    }

    /// `true` if there are no samples.
    pub fn is_empty(&self) -> bool {
        self.directions.is_empty()
    }

    /// Removes all samples (keeps the buffers).
    pub fn clear(&mut self) {
        self.directions.clear();
        self.cosines.clear();
        self.pdfs.clear();
        self.weights.clear();
        self.leaf.clear();
        self.leaves.clear();
    }

    /// `(1/n) Σ f(ω_i) w_i`: the estimate of `∫ f(ω) cos⁺θ dω` (e.g. the
    /// irradiance for `f` = incident radiance); 0 for no samples.
    pub fn estimate<F: FnMut(&Vec3<f64>) -> f64>(&self, mut f: F) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let s: f64 = self
            .directions
            .iter()
            .zip(&self.weights)
            .map(|(d, w)| {
                let v = f(d);
                if v == 0.0 { 0.0 } else { v * w }
            })
            .sum();
        s / self.len() as f64
    }

    /// `(1/n) Σ g(ω_i)/p(ω_i)`: the estimate of `∫ g(ω) dω` for an
    /// integrand `g` in solid angle (e.g. `L cos⁺θ`); 0 for no samples.
    pub fn estimate_solid_angle<F: FnMut(&Vec3<f64>) -> f64>(&self, mut g: F) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let s: f64 = self
            .directions
            .iter()
            .zip(&self.pdfs)
            .map(|(d, p)| {
                let v = g(d);
                if v == 0.0 { 0.0 } else { v / p }
            })
            .sum();
        s / self.len() as f64
    }
}

/// The default maximum subdivision depth (see [`AdaptiveTriangle`]).
pub const DEFAULT_MAX_DEPTH: u32 = 16;

/// The default depth down to which children are memoized.
pub const DEFAULT_CACHE_DEPTH: u32 = 8;

/// Adaptive cosine-weighted sampling of a triangle (Ureña 2000): a
/// generator of sample sets whose density approaches `cos θ/σ⊥` with the
/// second-moment bound `U ≤ (1 + K) U₀` (module docs,
/// `docs/adaptive-triangle.md`).
///
/// # Input
/// Vertex directions seen from the receiver, normal `+z`
/// ([`AdaptiveTriangle::new`]), or points in space with an observer and a
/// normal ([`AdaptiveTriangle::from_points`]). As in the paper (§2.1) the
/// part below the horizon is clipped away (it has `σ⊥ = 0`): a triangle
/// crossing the horizon becomes a triangle or a quadrilateral, the latter
/// split into two triangles that start the subdivision side by side
/// (depth 0, chosen with probability ∝ σ⊥ like any split).
///
/// # Termination
/// A piece is split while `k ≥ K`. The paper's termination argument ("k
/// approaches zero as the region shrinks") fails for pieces touching the
/// horizon: there `cos θ` falls to 0 and `k` stays near 1 or 2 at any
/// size. Splitting therefore also stops at a maximum depth
/// ([`DEFAULT_MAX_DEPTH`], [`AdaptiveTriangle::with_max_depth`]) or where a
/// child would be degenerate in `f64`; such pieces are flagged
/// ([`Piece::capped`]). For them the bound becomes
/// `U ≤ (1 + K) U₀ + σ⊥(E) Σ_capped (k(R) − K) ∫_R f² dσ⊥`, and the capped
/// pieces' total probability shrinks like `8^−depth` along a horizon edge
/// ([`AdaptiveTriangle::capped_excess`] computes the constant-`f` excess).
///
/// # Cost
/// The partition depends on the geometry and `K` only. It is built lazily
/// where samples go; the children of the pieces above
/// [`DEFAULT_CACHE_DEPTH`] are memoized (thread-safely) on first use, the
/// deeper ones recomputed per call. A split costs three normalizations and
/// four Lambert sums (the σ⊥ shares); σ, m and k are computed for the
/// children that samples reach, and one [`SphericalTriangle`] per piece that
/// receives samples. Measured (release, `n = 64`): about 50 ns per sample
/// for `K = ∞` or a triangle that needs no split, 0.1–0.2 µs at `K = 0.1`,
/// up to 2 µs at `K = 0.01` and 6 µs at `K = 0.001` for large or low
/// triangles (`docs/adaptive-triangle.md`).
#[derive(Clone, Debug)]
pub struct AdaptiveTriangle {
    threshold: f64,
    max_depth: u32,
    cache_depth: u32,
    allocation: Allocation,
    roots: Vec<Node>,
    root_shares: Vec<f64>,
    projected_solid_angle: f64,
    solid_angle: f64,
    frame: Option<Frame>,
}

/// The part of the triangle `v` with `z ≥ 0` (Sutherland–Hodgman against
/// the horizon great circle): 0, 3 or 4 unit vertices, all with `z ≥ 0`
/// exactly (crossing points have `z = 0` exactly).
fn clip_to_horizon(v: &[Vec3<f64>; 3]) -> Vec<Vec3<f64>> {
    let mut out = Vec::with_capacity(4);
    for i in 0..3 {
        let (p, q) = (&v[i], &v[(i + 1) % 3]);
        if p.z >= 0.0 {
            out.push(*p);
        }
        if (p.z > 0.0 && q.z < 0.0) || (p.z < 0.0 && q.z > 0.0) {
            // p_z q − q_z p: a combination of p and q with z = 0 exactly;
            // positive coefficients (the minor arc's point) when p_z > 0.
            let x = q.scale(&p.z).sub(&p.scale(&q.z));
            let x = if p.z > 0.0 { x } else { x.neg() };
            if let Some(u) = x.normalized() {
                out.push(Vec3::new(u.x, u.y, 0.0));
            }
        }
    }
    out
}

impl AdaptiveTriangle {
    /// The triangle with vertex directions `a`, `b`, `c` (any positive
    /// length; minor arcs) seen from a receiver with normal `+z`, threshold
    /// `k_threshold` = K, the default [`Allocation::Systematic`] and
    /// maximum depth [`DEFAULT_MAX_DEPTH`].
    ///
    /// `K = +∞` never splits (plain solid-angle sampling, Arvo 1995).
    ///
    /// # Errors
    /// - [`WarpError::InvalidParameter`] unless `K > 0` (not NaN);
    /// - as [`SphericalTriangle::new`] for the triangle;
    /// - [`WarpError::Degenerate`] if nothing of positive projected solid
    ///   angle is left above the horizon.
    pub fn new(
        a: Vec3<f64>,
        b: Vec3<f64>,
        c: Vec3<f64>,
        k_threshold: f64,
    ) -> Result<Self, WarpError> {
        if k_threshold.is_nan() || k_threshold <= 0.0 {
            return Err(WarpError::InvalidParameter {
                name: "K",
                expected: "a threshold K > 0",
            });
        }
        let whole = SphericalTriangle::new(a, b, c)?;
        let v = [*whole.a(), *whole.b(), *whole.c()];
        let clipped = clip_to_horizon(&v);
        let below = WarpError::Degenerate {
            what: "triangle below the receiver's horizon (nothing left after clipping)",
        };
        // A root must pass both Node::new and SphericalTriangle::new.
        let root = |i: usize, j: usize, k: usize, code: u64| {
            let v = [clipped[i], clipped[j], clipped[k]];
            let node = Node::new(v, 0, code)?;
            node.sampler()?;
            Some(node)
        };
        let roots: Vec<Node> = match clipped.len() {
            3 => vec![root(0, 1, 2, 0).ok_or(below.clone())?],
            4 => match (root(0, 1, 2, 0), root(0, 2, 3, 1)) {
                (Some(x), Some(y)) => vec![x, y],
                _ => match (root(1, 2, 3, 0), root(1, 3, 0, 1)) {
                    (Some(x), Some(y)) => vec![x, y],
                    (Some(x), None) => vec![x],
                    (None, Some(mut y)) => {
                        y.code = 0;
                        vec![y]
                    }
                    _ => return Err(below),
                },
            },
            _ => return Err(below),
        };
        let projected_solid_angle: f64 = roots.iter().map(|r| r.sigma_perp).sum();
        let solid_angle: f64 = roots.iter().map(|r| r.measures().solid_angle).sum();
        if !(projected_solid_angle > 0.0) || !projected_solid_angle.is_finite() {
            return Err(below);
        }
        let mut root_shares = vec![0.0; roots.len()];
        shares(&roots, &mut root_shares);
        Ok(AdaptiveTriangle {
            threshold: k_threshold,
            max_depth: DEFAULT_MAX_DEPTH,
            cache_depth: DEFAULT_CACHE_DEPTH,
            allocation: Allocation::default(),
            roots,
            root_shares,
            projected_solid_angle,
            solid_angle,
            frame: None,
        })
    }

    /// The triangle with corners `a`, `b`, `c` in space seen from
    /// `observer` on a receiver with normal `normal` (any positive length):
    /// directions `p − observer` in a frame with `normal` as `+z`
    /// ([`Frame::from_normal`]). The generated directions and
    /// [`AdaptiveTriangle::pdf`] are in world coordinates; [`pieces`]
    /// stay in the receiver's frame.
    ///
    /// [`pieces`]: AdaptiveTriangle::pieces
    ///
    /// # Errors
    /// As [`AdaptiveTriangle::new`]; [`WarpError::NonFinite`] for a
    /// non-finite point or observer, as [`Frame::from_normal`] for the
    /// normal.
    pub fn from_points(
        points: [&Vec3<f64>; 3],
        observer: &Vec3<f64>,
        normal: &Vec3<f64>,
        k_threshold: f64,
    ) -> Result<Self, WarpError> {
        if !observer.is_finite() {
            return Err(WarpError::NonFinite { what: "observer" });
        }
        let frame = Frame::from_normal(normal)?;
        let [a, b, c] = points.map(|p| frame.to_local(&p.sub(observer)));
        let mut t = Self::new(a, b, c, k_threshold)?;
        t.frame = Some(frame);
        Ok(t)
    }

    /// The same triangle with another allocation rule.
    pub fn with_allocation(mut self, allocation: Allocation) -> Self {
        self.allocation = allocation;
        self
    }

    /// The same triangle with another threshold `K` (memoized children are
    /// kept: the subdivision's geometry does not depend on `K`).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] unless `K > 0`.
    pub fn with_threshold(mut self, k_threshold: f64) -> Result<Self, WarpError> {
        if k_threshold.is_nan() || k_threshold <= 0.0 {
            return Err(WarpError::InvalidParameter {
                name: "K",
                expected: "a threshold K > 0",
            });
        }
        self.threshold = k_threshold;
        Ok(self)
    }

    /// The same triangle with another maximum depth (1 ≤ `depth` ≤ 30).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] outside that range.
    pub fn with_max_depth(mut self, depth: u32) -> Result<Self, WarpError> {
        if !(1..=30).contains(&depth) {
            return Err(WarpError::InvalidParameter {
                name: "max_depth",
                expected: "1 <= max_depth <= 30",
            });
        }
        self.max_depth = depth;
        Ok(self)
    }

    /// The same triangle memoizing children down to `depth` (0 disables
    /// the cache; memory is up to about 200 bytes × 4^depth per root, plus
    /// 600 bytes per memoized piece that received samples).
    pub fn with_cache_depth(mut self, depth: u32) -> Self {
        self.cache_depth = depth.min(30);
        self
    }

    /// The threshold K.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// The allocation rule.
    pub fn allocation(&self) -> Allocation {
        self.allocation
    }

    /// The maximum depth.
    pub fn max_depth(&self) -> u32 {
        self.max_depth
    }

    /// σ⊥(E): the projected solid angle of the clipped triangle (Lambert),
    /// the irradiance from a unit radiance.
    pub fn projected_solid_angle(&self) -> f64 {
        self.projected_solid_angle
    }

    /// σ(E): the solid angle of the clipped triangle.
    pub fn solid_angle(&self) -> f64 {
        self.solid_angle
    }

    /// The starting triangles (one, or two for a clipped quadrilateral):
    /// unit vertices in the receiver's frame and their measures.
    pub fn roots(&self) -> Vec<([Vec3<f64>; 3], TriangleMeasures<f64>)> {
        self.roots
            .iter()
            .map(|r| (r.v, r.measures().clone()))
            .collect()
    }

    /// The solid-angle samplers of the starting triangles with their
    /// probabilities (σ⊥ shares): e.g. for quadrature references.
    pub fn root_triangles(&self) -> Vec<(SphericalTriangle<f64>, f64)> {
        self.roots
            .iter()
            .zip(&self.root_shares)
            .filter_map(|(r, p)| Some((r.sampler()?.clone(), *p)))
            .collect()
    }

    /// The frame of [`AdaptiveTriangle::from_points`], if any.
    pub fn frame(&self) -> Option<&Frame> {
        self.frame.as_ref()
    }

    /// The children of `node`: none if it is a piece of the partition
    /// (converged, at the depth cap, or with a degenerate child).
    fn kids<'a>(&self, node: &'a Node) -> Kids<'a> {
        if node.measures().k < self.threshold || node.depth >= self.max_depth {
            return Kids::Leaf;
        }
        if node.depth < self.cache_depth {
            match node.children.get_or_init(|| node.split()).as_deref() {
                Some(k) => Kids::Memo(k),
                None => Kids::Leaf,
            }
        } else {
            match node.split() {
                Some(k) => Kids::Fresh(k),
                None => Kids::Leaf,
            }
        }
    }

    /// The adaptive partition: every piece (leaf of the subdivision) with
    /// its measures and probability, depth first.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if there are more than `limit`
    /// pieces (the partition can be large for small `K`: about `10⁵` pieces
    /// for a 1 sr triangle at `K = 10⁻³`).
    pub fn pieces(&self, limit: usize) -> Result<Vec<Piece>, WarpError> {
        let mut out = Vec::new();
        let mut ok = true;
        for (root, p) in self.roots.iter().zip(&self.root_shares) {
            self.walk(root, *p, &mut |piece| {
                if out.len() >= limit {
                    ok = false;
                    return false;
                }
                out.push(piece);
                true
            });
            if !ok {
                return Err(WarpError::InvalidParameter {
                    name: "limit",
                    expected: "at least as many pieces as the partition has",
                });
            }
        }
        Ok(out)
    }

    /// Counts and capped-piece statistics of the partition, if it has at
    /// most `limit` pieces (one walk, no storage).
    pub fn partition_summary(&self, limit: usize) -> Option<PartitionSummary> {
        let mut sum = PartitionSummary::default();
        let k_threshold = self.threshold;
        for (root, p) in self.roots.iter().zip(&self.root_shares) {
            let going = self.walk(root, *p, &mut |piece| {
                if sum.pieces >= limit {
                    return false;
                }
                sum.pieces += 1;
                sum.max_depth = sum.max_depth.max(piece.depth);
                if piece.capped {
                    sum.capped += 1;
                    sum.capped_probability += piece.probability;
                    sum.capped_excess +=
                        (piece.measures.k - k_threshold).max(0.0) * piece.probability;
                }
                true
            });
            if !going {
                return None;
            }
        }
        Some(sum)
    }

    /// The number of pieces of the partition, if at most `limit`.
    pub fn piece_count(&self, limit: usize) -> Option<usize> {
        self.partition_summary(limit).map(|s| s.pieces)
    }

    /// `Σ_capped (k(R) − K) P(R)` over the capped pieces (0 if none): the
    /// excess of `U/U₀` over `1 + K` allowed by the bound for constant `f`
    /// (`None` if the partition has more than `limit` pieces).
    pub fn capped_excess(&self, limit: usize) -> Option<f64> {
        self.partition_summary(limit).map(|s| s.capped_excess)
    }

    /// Depth-first walk over the leaves below `node` (probability `prob`);
    /// stops when `visit` returns `false`. Returns `false` if stopped.
    fn walk<F: FnMut(Piece) -> bool>(&self, node: &Node, prob: f64, visit: &mut F) -> bool {
        let kids = self.kids(node);
        match kids.as_ref() {
            Some(kids) => {
                let mut p = [0.0; 4];
                shares(kids, &mut p);
                for (kid, pk) in kids.iter().zip(p) {
                    if !self.walk(kid, prob * pk, visit) {
                        return false;
                    }
                }
                true
            }
            None => visit(Piece {
                vertices: node.v,
                measures: node.measures().clone(),
                depth: node.depth,
                code: node.code,
                probability: prob,
                capped: !(node.measures().k < self.threshold),
            }),
        }
    }

    /// `n` samples with their densities and weights (Ureña 2000, Fig. 4):
    /// AdaptiveSampling with DistributeSamples by the configured
    /// [`Allocation`], and `n_R` independent uniform points of the unit
    /// square carried by Arvo's map onto each piece `R`.
    pub fn generate<R: Rng + ?Sized>(&self, n: usize, rng: &mut R) -> SampleSet {
        let mut out = SampleSet::default();
        self.generate_into(n, rng, &mut out);
        out
    }

    /// As [`AdaptiveTriangle::generate`], into `out` (cleared first;
    /// reuses its buffers).
    pub fn generate_into<R: Rng + ?Sized>(&self, n: usize, rng: &mut R, out: &mut SampleSet) {
        out.clear();
        out.directions.reserve(n);
        out.cosines.reserve(n);
        out.pdfs.reserve(n);
        out.weights.reserve(n);
        out.leaf.reserve(n);
        let mut counts = [0usize; 8];
        distribute_into(&self.root_shares, n, self.allocation, rng, &mut counts);
        for (i, root) in self.roots.iter().enumerate() {
            self.visit(root, counts[i], self.root_shares[i], rng, out);
        }
    }

    /// AdaptiveSampling(node, n, K) with the probability `prob` of reaching
    /// `node`.
    fn visit<R: Rng + ?Sized>(
        &self,
        node: &Node,
        n: usize,
        prob: f64,
        rng: &mut R,
        out: &mut SampleSet,
    ) {
        if n == 0 {
            return;
        }
        let kids = self.kids(node);
        if let Some(kids) = kids.as_ref() {
            let mut p = [0.0; 4];
            shares(kids, &mut p);
            let mut counts = [0usize; 8];
            distribute_into(&p, n, self.allocation, rng, &mut counts);
            for i in 0..4 {
                self.visit(&kids[i], counts[i], prob * p[i], rng, out);
            }
            return;
        }
        // A leaf: n uniform points in solid angle (Arvo's map), density
        // P/Ω with Ω the map's own solid angle.
        let measures = node.measures();
        let tri = node.sampler();
        let sigma = match tri {
            Some(t) => t.solid_angle(),
            None => measures.solid_angle,
        };
        let pdf = prob / sigma;
        let index = out.leaves.len() as u32;
        out.leaves.push(LeafVisit {
            code: node.code,
            depth: node.depth,
            probability: prob,
            k: measures.k,
            capped: !(measures.k < self.threshold),
            count: n,
        });
        // (Unreachable fallback, see Node::sampler: the centroid direction.)
        let centroid = node.v[0]
            .add(&node.v[1])
            .add(&node.v[2])
            .normalized()
            .unwrap_or_else(|| node.v[0]);
        for _ in 0..n {
            let u: f64 = rng.random();
            let v: f64 = rng.random();
            let d = match tri {
                Some(t) => t.map(&u, &v),
                None => centroid,
            };
            let cos = d.z.max(0.0);
            let w = cos * sigma / prob;
            let d = match &self.frame {
                Some(f) => f.to_world(&d),
                None => d,
            };
            out.directions.push(d);
            out.cosines.push(cos);
            out.pdfs.push(pdf);
            out.weights.push(w);
            out.leaf.push(index);
        }
    }

    /// The density `p(ω) = P(R)/σ(R)` per steradian of the generated
    /// directions at the direction `direction` (world frame for
    /// [`AdaptiveTriangle::from_points`]; any positive length): the piece
    /// `R` containing it is found by descending the subdivision. 0 outside
    /// the clipped triangle. For multiple importance sampling.
    pub fn pdf(&self, direction: &Vec3<f64>) -> f64 {
        let local = match &self.frame {
            Some(f) => f.to_local(direction),
            None => *direction,
        };
        let Some(d) = local.normalized() else {
            return 0.0;
        };
        if !(d.z >= 0.0) {
            return 0.0;
        }
        let Some(i) = self.roots.iter().position(|r| inside(r, &d)) else {
            return 0.0;
        };
        let mut prob = self.root_shares[i];
        let mut node: Cow<'_, Node> = Cow::Borrowed(&self.roots[i]);
        loop {
            let next = match node {
                Cow::Borrowed(r) => match self.kids(r) {
                    Kids::Leaf => return prob / leaf_solid_angle(r),
                    Kids::Memo(k) => {
                        let (j, pj) = locate(k, &d);
                        prob *= pj;
                        Cow::Borrowed(&k[j])
                    }
                    Kids::Fresh(k) => {
                        let (j, pj) = locate(&k, &d);
                        prob *= pj;
                        Cow::Owned(take(*k, j))
                    }
                },
                Cow::Owned(o) => match self.kids(&o) {
                    Kids::Leaf => return prob / leaf_solid_angle(&o),
                    Kids::Memo(k) => {
                        let (j, pj) = locate(k, &d);
                        prob *= pj;
                        Cow::Owned(k[j].clone())
                    }
                    Kids::Fresh(k) => {
                        let (j, pj) = locate(&k, &d);
                        prob *= pj;
                        Cow::Owned(take(*k, j))
                    }
                },
            };
            node = next;
        }
    }
}

/// The children of a node, memoized or freshly computed.
enum Kids<'a> {
    Leaf,
    Memo(&'a [Node; 4]),
    Fresh(Box<[Node; 4]>),
}

impl Kids<'_> {
    fn as_ref(&self) -> Option<&[Node; 4]> {
        match self {
            Kids::Leaf => None,
            Kids::Memo(k) => Some(k),
            Kids::Fresh(k) => Some(k),
        }
    }
}

/// `det(e1, e2, p) = p · (e1 × e2)`: the side of the great circle through
/// `e1`, `e2` that `p` is on.
fn side(e1: &Vec3<f64>, e2: &Vec3<f64>, p: &Vec3<f64>) -> f64 {
    p.dot(&e1.cross(e2))
}

/// `true` if the unit direction `d` is in the spherical triangle of `node`
/// (boundary included), by the signs of the three edge determinants.
fn inside(node: &Node, d: &Vec3<f64>) -> bool {
    let [a, b, c] = &node.v;
    let s = if side(a, b, c) > 0.0 { 1.0 } else { -1.0 };
    s * side(a, b, d) >= 0.0 && s * side(b, c, d) >= 0.0 && s * side(c, a, d) >= 0.0
}

/// The child of `kids` containing the unit direction `d` (a direction of
/// the parent) and its σ⊥ share: corner child `i` if `d` is strictly on its
/// corner's side of its inner edge (the arc between the two midpoints),
/// else the middle child.
fn locate(kids: &[Node; 4], d: &Vec3<f64>) -> (usize, f64) {
    let mut p = [0.0; 4];
    shares(kids, &mut p);
    let corner = |i: usize| {
        let [a, b, c] = &kids[i].v;
        let (x, e1, e2) = match i {
            0 => (a, b, c),
            1 => (b, c, a),
            _ => (c, a, b),
        };
        let sd = side(e1, e2, d);
        let sx = side(e1, e2, x);
        (sd > 0.0 && sx > 0.0) || (sd < 0.0 && sx < 0.0)
    };
    let j = (0..3).find(|&i| corner(i)).unwrap_or(3);
    (j, p[j])
}

/// The solid angle in a leaf's density: its sampler's Ω.
fn leaf_solid_angle(node: &Node) -> f64 {
    match node.sampler() {
        Some(t) => t.solid_angle(),
        None => node.measures().solid_angle,
    }
}

/// Child `j` of an owned set of children.
fn take(kids: [Node; 4], j: usize) -> Node {
    let [a, b, c, d] = kids;
    match j {
        0 => a,
        1 => b,
        2 => c,
        _ => d,
    }
}
