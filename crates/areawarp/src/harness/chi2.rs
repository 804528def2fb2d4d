//! Pearson's χ² goodness-of-fit test of a warp's samples against its claimed
//! distribution, in the style of Mitsuba 3's `ChiSquareTest`.
//!
//! The Jacobian check proves the *local* identity `J · pdf = 1`; the χ² test
//! checks the *global* behaviour of the code that actually runs, in `f64`:
//! uniform random `(u, v)` are mapped, the points are counted in the bins of
//! a [`Binning`] of the shape, and the counts are compared with the expected
//! counts `samples · P(bin)`. The binnings here are built from the shape's
//! geometry (equal-area or equal-weight cells in `z` and `φ`, annuli and
//! sectors, sub-triangles), independently of any warp's own parametrization,
//! so a map that is bijective but not measure-preserving, that misses part
//! of the shape, or that leaves it, fails.
//!
//! [`chi_square_test`] follows Mitsuba: cells are sorted by expected count,
//! the cells with expected count below `min_expected` (5) are pooled into one
//! (the pool keeps absorbing the next cells until it reaches `min_expected`,
//! and is dropped if it never does), the statistic
//! `χ² = Σ (O − E)² / E` has `dof = cells − 1` degrees of freedom, and the
//! p-value `Q(dof/2, χ²/2)` (the regularized upper incomplete gamma
//! function, [`regularized_gamma_q`]) is compared with the Šidák-corrected
//! significance `α' = 1 − (1 − α)^(1/num_tests)`, so that a suite of
//! `num_tests` tests rejects a correct warp with probability `α` overall.
//! A sample in a cell of expected count 0, or outside every cell
//! ([`run_chi_square`]), fails the test outright.

use crate::error::WarpError;
use crate::vector::{Coords, Vec2, Vec3};
use crate::warp::Warp;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::f64::consts::PI;

/// Why a χ² test failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChiSquareFailure {
    /// `observed` and `expected` have different lengths.
    LengthMismatch,
    /// An expected count is negative or not finite.
    InvalidExpected,
    /// A cell with expected count 0 received samples.
    ZeroExpectedHit,
    /// Samples fell outside every cell of the binning.
    Outside,
    /// Fewer than two cells remain after pooling.
    TooFewCells,
    /// The p-value is below the corrected significance level (or not finite).
    Rejected,
}

/// The outcome of a χ² test.
#[derive(Clone, Debug)]
pub struct ChiSquareOutcome {
    /// The statistic `Σ (O − E)² / E` over the cells kept (the pool counting
    /// as one cell).
    pub statistic: f64,
    /// Degrees of freedom: cells kept − 1.
    pub dof: usize,
    /// `Q(dof/2, χ²/2)`: the probability of a statistic at least this large
    /// if the samples follow the expected distribution.
    pub p_value: f64,
    /// The Šidák-corrected significance level `α'` the p-value is compared with.
    pub significance: f64,
    /// Number of cells given.
    pub cells: usize,
    /// Number of cells pooled together because of a small expected count.
    pub pooled_cells: usize,
    /// The expected count of the pool.
    pub pooled_expected: f64,
    /// Whether the pool was dropped (its expected count stayed below the minimum).
    pub pool_dropped: bool,
    /// Total of the observed counts (samples inside the binning).
    pub observed_total: u64,
    /// Total of the expected counts.
    pub expected_total: f64,
    /// Cells of expected count 0 that received samples.
    pub zero_expected_hits: usize,
    /// Samples that fell outside every cell (set by [`run_chi_square`]; 0 from
    /// [`chi_square_test`]).
    pub outside: u64,
    /// Whether the test passed.
    pub passed: bool,
    /// The first reason for failure, `None` if passed.
    pub failure: Option<ChiSquareFailure>,
}

impl ChiSquareOutcome {
    fn fail(&mut self, why: ChiSquareFailure) {
        self.passed = false;
        if self.failure.is_none() {
            self.failure = Some(why);
        }
    }
}

/// The default minimal expected count of a cell (smaller cells are pooled).
pub const MIN_EXPECTED: f64 = 5.0;

/// Pearson's χ² test of `observed` counts against `expected` counts (see the
/// [module documentation](self)), at significance `significance` (e.g. 0.01)
/// Šidák-corrected for `num_tests` tests (0 is treated as 1).
pub fn chi_square_test(
    observed: &[u64],
    expected: &[f64],
    min_expected: f64,
    significance: f64,
    num_tests: u32,
) -> ChiSquareOutcome {
    let n = num_tests.max(1) as f64;
    // 1 − (1 − α)^(1/n), without cancellation for small α.
    let corrected = -((-significance).ln_1p() / n).exp_m1();
    let mut out = ChiSquareOutcome {
        statistic: 0.0,
        dof: 0,
        p_value: f64::NAN,
        significance: corrected,
        cells: expected.len(),
        pooled_cells: 0,
        pooled_expected: 0.0,
        pool_dropped: false,
        observed_total: observed.iter().sum(),
        expected_total: expected.iter().sum(),
        zero_expected_hits: 0,
        outside: 0,
        passed: true,
        failure: None,
    };
    if observed.len() != expected.len() {
        out.fail(ChiSquareFailure::LengthMismatch);
        return out;
    }
    if expected.iter().any(|e| !(e.is_finite() && *e >= 0.0)) {
        out.fail(ChiSquareFailure::InvalidExpected);
        return out;
    }
    out.zero_expected_hits = expected
        .iter()
        .zip(observed)
        .filter(|&(&e, &o)| e == 0.0 && o > 0)
        .count();
    if out.zero_expected_hits > 0 {
        out.fail(ChiSquareFailure::ZeroExpectedHit);
    }

    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    let mut kept = 0usize;
    let mut statistic = 0.0;
    for i in order {
        let (o, e) = (observed[i] as f64, expected[i]);
        if e < min_expected || (pool_exp > 0.0 && pool_exp < min_expected) {
            pool_obs += o;
            pool_exp += e;
            out.pooled_cells += 1;
        } else {
            statistic += (o - e) * (o - e) / e;
            kept += 1;
        }
    }
    out.pooled_expected = pool_exp;
    if out.pooled_cells > 0 {
        if pool_exp >= min_expected && pool_exp > 0.0 {
            statistic += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
            kept += 1;
        } else {
            out.pool_dropped = true;
        }
    }
    out.statistic = statistic;
    if kept < 2 {
        out.fail(ChiSquareFailure::TooFewCells);
        return out;
    }
    out.dof = kept - 1;
    out.p_value = regularized_gamma_q(out.dof as f64 / 2.0, statistic / 2.0);
    if !at_most(corrected, out.p_value) {
        out.fail(ChiSquareFailure::Rejected);
    }
    out
}

/// A partition of a shape (in space, `f64`) into cells of known probability.
pub trait Binning {
    /// Number of cells.
    fn n_bins(&self) -> usize;
    /// The cell containing `p`, or `None` if `p` is not on the shape (beyond
    /// [`BIN_TOLERANCE`]).
    fn bin(&self, p: &Vec3<f64>) -> Option<usize>;
    /// The probability of cell `i` under the target distribution.
    fn probability(&self, i: usize) -> f64;
}

/// Points farther than this from the binned shape (relative to its size)
/// fall outside every cell: `2^-30 ≈ 9.3·10⁻¹⁰`. Far above `f64` rounding,
/// far below the size of any cell; the precision check measures closeness
/// to the shape much more finely.
pub const BIN_TOLERANCE: f64 = 1.0 / (1u64 << 30) as f64;

/// `a ≤ b`, false if either is NaN.
fn at_most(a: f64, b: f64) -> bool {
    a <= b
}

fn invalid(name: &'static str, expected: &'static str) -> WarpError {
    WarpError::InvalidParameter { name, expected }
}

fn check_count(n: usize, name: &'static str) -> Result<(), WarpError> {
    if n == 0 {
        Err(invalid(name, "at least 1"))
    } else {
        Ok(())
    }
}

/// `floor(c · n)` for `c ∈ [0, 1]`, clamped to `0 … n−1`.
fn slot(c: f64, n: usize) -> usize {
    ((c.clamp(0.0, 1.0) * n as f64) as usize).min(n - 1)
}

/// The sector of the angle `atan2(y, x)` among `n` equal sectors of `[0, 2π)`.
fn sector(y: f64, x: f64, n: usize) -> usize {
    let mut t = y.atan2(x) / (2.0 * PI);
    if t < 0.0 {
        t += 1.0;
    }
    slot(t, n)
}

/// The measure on directions binned by [`ZPhiBins`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ZPhiMeasure {
    /// Uniform on the whole sphere: cdf in `z` is `(1 + z)/2`.
    Sphere,
    /// Uniform on the hemisphere `z ≥ 0`: cdf `z`.
    Hemisphere,
    /// The Phong lobe `cos^k θ` on the hemisphere: cdf `z^(k+1)`.
    Phong(f64),
}

/// Directions binned into `nz` bands of `z` (the cosine to an axis, +z by
/// default) of equal measure, times `nphi` equal sectors of the azimuth φ:
/// `nz · nphi` cells of equal probability.
///
/// Uniform measure on the sphere or hemisphere gives equal-width `z` bands
/// (Archimedes); the Phong lobe `cos^k θ` (solid-angle density ∝ `z^k`) gives
/// bands with edges `(i/nz)^(1/(k+1))`. Points are normalized before binning;
/// a point whose length differs from 1 by more than [`BIN_TOLERANCE`], or
/// that lies below the hemisphere, is outside.
#[derive(Clone, Debug)]
pub struct ZPhiBins {
    measure: ZPhiMeasure,
    nz: usize,
    nphi: usize,
    /// Orthonormal frame: tangent, bitangent, axis.
    frame: [Vec3<f64>; 3],
}

impl ZPhiBins {
    fn new(measure: ZPhiMeasure, nz: usize, nphi: usize) -> Result<Self, WarpError> {
        check_count(nz, "nz")?;
        check_count(nphi, "nphi")?;
        Ok(ZPhiBins {
            measure,
            nz,
            nphi,
            frame: [
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
            ],
        })
    }
    /// Equal-area cells of the unit sphere.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if `nz` or `nphi` is 0.
    pub fn sphere(nz: usize, nphi: usize) -> Result<Self, WarpError> {
        Self::new(ZPhiMeasure::Sphere, nz, nphi)
    }
    /// Equal-area cells of the unit hemisphere `z ≥ 0`.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if `nz` or `nphi` is 0.
    pub fn hemisphere(nz: usize, nphi: usize) -> Result<Self, WarpError> {
        Self::new(ZPhiMeasure::Hemisphere, nz, nphi)
    }
    /// Cells of equal `cos^k θ`-weighted solid angle on the hemisphere
    /// (`k = 0`: the uniform hemisphere, `k = 1`: cosine-weighted).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if `k` is negative or not finite, or
    /// `nz` or `nphi` is 0.
    pub fn phong(k: f64, nz: usize, nphi: usize) -> Result<Self, WarpError> {
        if !(k.is_finite() && k >= 0.0) {
            return Err(invalid("k", "a finite exponent ≥ 0"));
        }
        Self::new(ZPhiMeasure::Phong(k), nz, nphi)
    }
    /// The same cells about another axis (normalized here; the azimuth origin
    /// is an arbitrary direction perpendicular to it).
    ///
    /// # Errors
    /// [`WarpError::Degenerate`] for a zero or non-finite axis.
    pub fn with_axis(mut self, axis: Vec3<f64>) -> Result<Self, WarpError> {
        let n = axis
            .normalized()
            .ok_or(WarpError::Degenerate { what: "axis" })?;
        // Any unit vector not parallel to n, made perpendicular.
        let helper = if n.x.abs() < 0.5 {
            Vec3::new(1.0, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 1.0, 0.0)
        };
        let t = n
            .cross(&helper)
            .normalized()
            .ok_or(WarpError::Degenerate { what: "axis" })?;
        let b = n.cross(&t);
        self.frame = [t, b, n];
        Ok(self)
    }
    /// The measure the cells are equal in.
    pub fn measure(&self) -> ZPhiMeasure {
        self.measure
    }
}

impl Binning for ZPhiBins {
    fn n_bins(&self) -> usize {
        self.nz * self.nphi
    }
    fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
        let len = p.norm();
        if !at_most((len - 1.0).abs(), BIN_TOLERANCE) {
            return None;
        }
        let d = p.scale(&(1.0 / len));
        let [t, b, n] = &self.frame;
        let (x, y, z) = (d.dot(t), d.dot(b), d.dot(n));
        let c = match self.measure {
            ZPhiMeasure::Sphere => (1.0 + z) / 2.0,
            ZPhiMeasure::Hemisphere | ZPhiMeasure::Phong(_) if z < -BIN_TOLERANCE => return None,
            ZPhiMeasure::Hemisphere => z,
            ZPhiMeasure::Phong(k) => z.max(0.0).powf(k + 1.0),
        };
        Some(slot(c, self.nz) * self.nphi + sector(y, x, self.nphi))
    }
    fn probability(&self, _i: usize) -> f64 {
        1.0 / self.n_bins() as f64
    }
}

/// A planar disk (points embedded with `z = 0`) cut into `nr` annuli of equal
/// area (edges at radii `R √(i/nr)`) times `nphi` equal sectors.
///
/// Points off the plane or outside the disk by more than [`BIN_TOLERANCE`]
/// (relative to the radius) are outside.
#[derive(Clone, Debug)]
pub struct DiskBins {
    center: Vec2<f64>,
    radius: f64,
    nr: usize,
    nphi: usize,
}

impl DiskBins {
    /// The unit disk about the origin.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if `nr` or `nphi` is 0.
    pub fn unit(nr: usize, nphi: usize) -> Result<Self, WarpError> {
        Self::new(Vec2::new(0.0, 0.0), 1.0, nr, nphi)
    }
    /// The disk of the given centre and radius in the plane `z = 0`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a non-finite centre,
    /// [`WarpError::InvalidParameter`] for a radius that is not positive and
    /// finite or a zero count.
    pub fn new(center: Vec2<f64>, radius: f64, nr: usize, nphi: usize) -> Result<Self, WarpError> {
        if !(center.x.is_finite() && center.y.is_finite()) {
            return Err(WarpError::NonFinite { what: "center" });
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(invalid("radius", "finite and > 0"));
        }
        check_count(nr, "nr")?;
        check_count(nphi, "nphi")?;
        Ok(DiskBins {
            center,
            radius,
            nr,
            nphi,
        })
    }
}

impl Binning for DiskBins {
    fn n_bins(&self) -> usize {
        self.nr * self.nphi
    }
    fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
        if !at_most(p.z.abs(), BIN_TOLERANCE * self.radius) {
            return None;
        }
        let x = (p.x - self.center.x) / self.radius;
        let y = (p.y - self.center.y) / self.radius;
        let r2 = x * x + y * y;
        if !at_most(r2, 1.0 + BIN_TOLERANCE) {
            return None;
        }
        Some(slot(r2, self.nr) * self.nphi + sector(y, x, self.nphi))
    }
    fn probability(&self, _i: usize) -> f64 {
        1.0 / self.n_bins() as f64
    }
}

/// A triangle (in space) cut into `n²` congruent sub-triangles: the lines
/// `β = i/n`, `γ = j/n`, `α = k/n` of the barycentric coordinates. Every cell
/// has exactly `1/n²` of the area.
///
/// Points off the triangle's plane or outside it by more than
/// [`BIN_TOLERANCE`] (relative to the longest edge, resp. in barycentric
/// coordinates) are outside.
#[derive(Clone, Debug)]
pub struct TriangleBins {
    a: Vec3<f64>,
    e1: Vec3<f64>,
    e2: Vec3<f64>,
    /// Gram matrix entries and determinant of (e1, e2).
    g11: f64,
    g12: f64,
    g22: f64,
    det: f64,
    extent: f64,
    n: usize,
}

impl TriangleBins {
    /// The triangle `abc`, `n` subdivisions per edge.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for non-finite vertices,
    /// [`WarpError::Degenerate`] for collinear vertices,
    /// [`WarpError::InvalidParameter`] for `n = 0`.
    pub fn new(a: Vec3<f64>, b: Vec3<f64>, c: Vec3<f64>, n: usize) -> Result<Self, WarpError> {
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            return Err(WarpError::NonFinite { what: "vertex" });
        }
        check_count(n, "n")?;
        let (e1, e2) = (b.sub(&a), c.sub(&a));
        let (g11, g12, g22) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
        let det = g11 * g22 - g12 * g12;
        let extent = g11.max(g22).max(c.sub(&b).norm_squared()).sqrt();
        // |e1 × e2|² = det: relative to the edges, a sliver is degenerate.
        if !(det > 0.0 && e1.cross(&e2).norm() > BIN_TOLERANCE * extent * extent) {
            return Err(WarpError::Degenerate {
                what: "collinear vertices",
            });
        }
        Ok(TriangleBins {
            a,
            e1,
            e2,
            g11,
            g12,
            g22,
            det,
            extent,
            n,
        })
    }

    /// Index of the "upright" cell `(i, j)`, `i + j ≤ n − 1`, and of the
    /// "inverted" cell `(i, j)`, `i + j ≤ n − 2` (after all upright ones).
    fn cell(&self, i: usize, j: usize, upright: bool) -> usize {
        let n = self.n;
        if upright {
            i * n - i * i.saturating_sub(1) / 2 + j
        } else {
            n * (n + 1) / 2 + i * (n - 1) - i * i.saturating_sub(1) / 2 + j
        }
    }
}

impl Binning for TriangleBins {
    fn n_bins(&self) -> usize {
        self.n * self.n
    }
    fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
        let d = p.sub(&self.a);
        let (p1, p2) = (d.dot(&self.e1), d.dot(&self.e2));
        let beta = (self.g22 * p1 - self.g12 * p2) / self.det;
        let gamma = (self.g11 * p2 - self.g12 * p1) / self.det;
        let alpha = 1.0 - beta - gamma;
        let off_plane = d.sub(&self.e1.scale(&beta)).sub(&self.e2.scale(&gamma));
        if !at_most(off_plane.norm(), BIN_TOLERANCE * self.extent)
            || !at_most(-BIN_TOLERANCE, alpha.min(beta).min(gamma))
        {
            return None;
        }
        let n = self.n;
        let (x, y) = (beta.max(0.0) * n as f64, gamma.max(0.0) * n as f64);
        let i = (x as usize).min(n - 1);
        let j = (y as usize).min(n - 1 - i);
        let (fx, fy) = (x - i as f64, y - j as f64);
        let upright = fx + fy <= 1.0 || i + j + 1 >= n;
        Some(self.cell(i, j, upright))
    }
    fn probability(&self, _i: usize) -> f64 {
        1.0 / self.n_bins() as f64
    }
}

/// Observed counts of a warp's samples in the cells of a binning.
#[derive(Clone, Debug)]
pub struct Histogram {
    /// Samples per cell.
    pub counts: Vec<u64>,
    /// Samples outside every cell.
    pub outside: u64,
}

/// Maps `samples` uniform random `(u, v) ∈ [0, 1)²` (xoshiro256++ seeded
/// with `seed`, as [`random_points`](super::extremes::random_points)) and
/// counts them in the cells of `binning`.
pub fn histogram<W: Warp<f64>>(
    w: &W,
    binning: &impl Binning,
    samples: usize,
    seed: u64,
) -> Histogram {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut counts = vec![0u64; binning.n_bins()];
    let mut outside = 0;
    for _ in 0..samples {
        let (u, v): (f64, f64) = (rng.random(), rng.random());
        let p = w.map(&u, &v).to_vec3();
        match binning.bin(&p).and_then(|i| counts.get_mut(i)) {
            Some(c) => *c += 1,
            None => outside += 1,
        }
    }
    Histogram { counts, outside }
}

/// The expected counts `samples · P(cell)` of a binning.
pub fn expected_counts(binning: &impl Binning, samples: usize) -> Vec<f64> {
    (0..binning.n_bins())
        .map(|i| binning.probability(i) * samples as f64)
        .collect()
}

/// Samples the warp ([`histogram`]) and runs [`chi_square_test`] against the
/// binning's probabilities (minimal expected count [`MIN_EXPECTED`]); fails
/// if any sample fell outside every cell.
///
/// # Example
/// ```
/// use areawarp::harness::chi2::{run_chi_square, ZPhiBins};
/// use areawarp::shapes::PhongLobe;
///
/// let cosine = PhongLobe::new(1.0)?;
/// let outcome = run_chi_square(&cosine, &ZPhiBins::phong(1.0, 8, 16)?, 20_000, 1, 0.01, 1);
/// assert!(outcome.passed, "{outcome:?}");
/// // The same samples are not uniform on the hemisphere.
/// let wrong = run_chi_square(&cosine, &ZPhiBins::hemisphere(8, 16)?, 20_000, 1, 0.01, 1);
/// assert!(!wrong.passed);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn run_chi_square<W: Warp<f64>>(
    w: &W,
    binning: &impl Binning,
    samples: usize,
    seed: u64,
    significance: f64,
    num_tests: u32,
) -> ChiSquareOutcome {
    let h = histogram(w, binning, samples, seed);
    let expected = expected_counts(binning, samples);
    let mut out = chi_square_test(&h.counts, &expected, MIN_EXPECTED, significance, num_tests);
    out.outside = h.outside;
    if h.outside > 0 {
        // The more fundamental reason: reported even if the counts were also rejected.
        out.passed = false;
        out.failure = Some(ChiSquareFailure::Outside);
    }
    out
}

/// `ln Γ(x)` for `x > 0` (Lanczos, g = 7, 9 terms; relative accuracy ~10⁻¹⁵).
pub fn ln_gamma(x: f64) -> f64 {
    #[allow(clippy::excessive_precision)]
    const C: [f64; 9] = [
        0.999_999_999_999_809_93,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_13,
        -176.615_029_162_140_59,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_571_6e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x) Γ(1 − x) = π / sin(πx).
        return (PI / (PI * x).sin().abs()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = C
        .iter()
        .enumerate()
        .skip(1)
        .fold(C[0], |acc, (i, c)| acc + c / (x + i as f64));
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// The regularized upper incomplete gamma function
/// `Q(a, x) = Γ(a, x) / Γ(a) = 1 − P(a, x)`, for `a > 0`, `x ≥ 0` (NaN
/// otherwise). The χ² p-value of statistic `s` with `d` degrees of freedom is
/// `Q(d/2, s/2)`.
///
/// Series for `P` when `x < a + 1`, Lentz's continued fraction for `Q`
/// otherwise (Numerical Recipes §6.2); about 14 correct digits.
pub fn regularized_gamma_q(a: f64, x: f64) -> f64 {
    if !(a > 0.0 && x >= 0.0) || a.is_infinite() {
        return f64::NAN;
    }
    if x == 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    let eps = f64::EPSILON;
    let prefactor = (a * x.ln() - x - ln_gamma(a)).exp();
    let max_iter = 100_000 + (10.0 * a.sqrt()) as usize;
    if x < a + 1.0 {
        // P(a, x) = x^a e^-x / Γ(a) · Σ x^n / (a (a+1) … (a+n)).
        let (mut ap, mut term) = (a, 1.0 / a);
        let mut sum = term;
        for _ in 0..max_iter {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * eps {
                break;
            }
        }
        (1.0 - sum * prefactor).clamp(0.0, 1.0)
    } else {
        // Q(a, x) = x^a e^-x / Γ(a) · 1/(x+1−a− 1·(1−a)/(x+3−a− 2·(2−a)/(x+5−a− …))).
        let tiny = f64::MIN_POSITIVE / eps;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..max_iter {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < eps {
                break;
            }
        }
        (prefactor * h).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests;
