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

mod allocation;
mod measures;
#[cfg(test)]
mod tests;
mod tree;

pub use allocation::*;
pub use measures::*;
use tree::*;

use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::SphericalTriangle;
use crate::vector::Frame;
use crate::vector::Vec3;
use crate::warp::Warp;
use rand::{Rng, RngExt};
use std::borrow::Cow;
use std::sync::OnceLock;

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
