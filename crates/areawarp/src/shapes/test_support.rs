//! Test support for the shapes: χ² binnings whose cell probabilities are
//! integrated from a warp's claimed density (independently of its map), and
//! the harness runs that print the figures of the measurements.

use crate::harness::chi2::{BIN_TOLERANCE, Binning, ChiSquareOutcome, run_chi_square};
use crate::harness::extremes::{extremes_grid, random_points};
use crate::harness::roundtrip::{RoundTripReport, check_roundtrip};
use crate::vector::Vec3;
use crate::warp::{Warp, WarpFamily};

/// 5-point Gauss–Legendre nodes and weights on [−1, 1].
const GL5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// ∫_a^b f by composite 5-point Gauss–Legendre on `pieces` equal pieces.
pub(crate) fn integrate(f: &impl Fn(f64) -> f64, a: f64, b: f64, pieces: usize) -> f64 {
    let h = (b - a) / pieces as f64;
    (0..pieces)
        .map(|i| {
            let (lo, hi) = (a + h * i as f64, a + h * (i + 1) as f64);
            let (m, r) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
            GL5.iter().map(|&(x, w)| w * f(m + r * x)).sum::<f64>() * r
        })
        .sum()
}

/// ∫_a^b f over pieces of geometrically growing width from `a > 0` (the
/// densities here vary on the scale of `w` itself near the pole), or of
/// equal width from `a = 0`.
fn integrate_band(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    if a > 0.0 && b / a > 4.0 {
        let n = 512;
        let r = (b / a).powf(1.0 / n as f64);
        (0..n)
            .map(|k| {
                let lo = a * r.powi(k);
                let hi = if k + 1 == n { b } else { a * r.powi(k + 1) };
                integrate(f, lo, hi, 1)
            })
            .sum()
    } else {
        integrate(f, a, b, 64)
    }
}

/// Directions binned by `w = 1 − z` about an axis (bands with the given
/// edges `0 = w_0 < … < w_n ≤ 2`) times equal azimuth sectors of
/// `[0, span)`, measured from `e1` towards `e2`. Cell probabilities:
/// `(span/nphi) · ∫ pdf(w) dw` over the band (`dω = dw dφ`).
pub(crate) struct AxisBins {
    e1: Vec3<f64>,
    e2: Vec3<f64>,
    axis: Vec3<f64>,
    edges: Vec<f64>,
    span: f64,
    nphi: usize,
    probs: Vec<f64>,
}

impl AxisBins {
    pub(crate) fn new(
        frame: [Vec3<f64>; 3],
        edges: Vec<f64>,
        span: f64,
        nphi: usize,
        pdf_of_w: impl Fn(f64) -> f64,
    ) -> Self {
        let [e1, e2, axis] = frame;
        let mut probs = Vec::new();
        for band in edges.windows(2) {
            let p = integrate_band(&pdf_of_w, band[0], band[1]) * span / nphi as f64;
            probs.extend(std::iter::repeat_n(p, nphi));
        }
        AxisBins {
            e1,
            e2,
            axis,
            edges,
            span,
            nphi,
            probs,
        }
    }

    /// Band edges `0 = w_0 < … < w_n = w_max` at the quantiles `i/n` of the
    /// claimed density (`∫₀^w pdf`, integrated numerically and inverted by
    /// bisection): cells of equal probability, found without the map.
    pub(crate) fn quantile_edges(pdf_of_w: impl Fn(f64) -> f64, n: usize, w_max: f64) -> Vec<f64> {
        let tiny = 1e-15 * w_max;
        let mass = |w: f64| -> f64 {
            let w = w.clamp(0.0, w_max);
            if w <= tiny {
                integrate(&pdf_of_w, 0.0, w, 4)
            } else {
                integrate(&pdf_of_w, 0.0, tiny, 4) + integrate_band(&pdf_of_w, tiny, w)
            }
        };
        let total = mass(w_max);
        let mut edges = vec![0.0];
        for i in 1..n {
            let target = total * i as f64 / n as f64;
            let (mut lo, mut hi) = (tiny, w_max);
            for _ in 0..100 {
                // Bisection in log scale while the bracket is wide.
                let mid = if hi / lo > 4.0 {
                    (lo * hi).sqrt()
                } else {
                    0.5 * (lo + hi)
                };
                if mass(mid) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            edges.push(0.5 * (lo + hi));
        }
        edges.push(w_max);
        edges
    }
}

impl Binning for AxisBins {
    fn n_bins(&self) -> usize {
        self.probs.len()
    }
    fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
        let len = p.norm();
        if !((len - 1.0).abs() <= BIN_TOLERANCE) {
            return None;
        }
        let d = p.scale(&(1.0 / len));
        let (x, y, z) = (d.dot(&self.e1), d.dot(&self.e2), d.dot(&self.axis));
        let rho2 = x * x + y * y;
        let w = if z > 0.0 { rho2 / (1.0 + z) } else { 1.0 - z };
        let last = *self.edges.last()?;
        if w > last + BIN_TOLERANCE {
            return None;
        }
        let band = self
            .edges
            .partition_point(|&e| e <= w)
            .clamp(1, self.edges.len() - 1)
            - 1;
        let mut phi = y.atan2(x);
        if phi < -BIN_TOLERANCE {
            phi += 2.0 * std::f64::consts::PI;
        }
        if rho2 > 1e-20 && (phi < -BIN_TOLERANCE || phi > self.span + BIN_TOLERANCE) {
            return None;
        }
        let sector = ((phi.max(0.0) / self.span * self.nphi as f64) as usize).min(self.nphi - 1);
        Some(band * self.nphi + sector)
    }
    fn probability(&self, i: usize) -> f64 {
        self.probs[i]
    }
}

/// Planar points (embedded with `z = 0`) binned on a grid of cells given by
/// their `x` and `y` edges; probabilities by 2-D Gauss–Legendre of the pdf.
pub(crate) struct GridBins {
    xs: Vec<f64>,
    ys: Vec<f64>,
    probs: Vec<f64>,
}

impl GridBins {
    pub(crate) fn new(xs: Vec<f64>, ys: Vec<f64>, pdf: impl Fn(f64, f64) -> f64) -> Self {
        let mut probs = Vec::new();
        for bx in xs.windows(2) {
            for by in ys.windows(2) {
                let inner = |x: f64| integrate(&|y| pdf(x, y), by[0], by[1], 4);
                probs.push(integrate(&inner, bx[0], bx[1], 4));
            }
        }
        GridBins { xs, ys, probs }
    }
    pub(crate) fn uniform_edges(lo: f64, hi: f64, n: usize) -> Vec<f64> {
        (0..=n)
            .map(|i| lo + (hi - lo) * i as f64 / n as f64)
            .collect()
    }
}

fn slot(edges: &[f64], x: f64) -> Option<usize> {
    let (lo, hi) = (edges[0], *edges.last()?);
    if !(x >= lo - BIN_TOLERANCE && x <= hi + BIN_TOLERANCE) {
        return None;
    }
    Some(edges.partition_point(|&e| e <= x).clamp(1, edges.len() - 1) - 1)
}

impl Binning for GridBins {
    fn n_bins(&self) -> usize {
        self.probs.len()
    }
    fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
        if p.z != 0.0 {
            return None;
        }
        let i = slot(&self.xs, p.x)?;
        let j = slot(&self.ys, p.y)?;
        Some(i * (self.ys.len() - 1) + j)
    }
    fn probability(&self, i: usize) -> f64 {
        self.probs[i]
    }
}

/// χ² of `samples` f64 samples against `bins` at significance 0.01,
/// printed; asserts that it passes.
pub(crate) fn chi2_passes<W: Warp<f64>>(
    label: &str,
    w: &W,
    bins: &impl Binning,
    samples: usize,
) -> ChiSquareOutcome {
    let total: f64 = (0..bins.n_bins()).map(|i| bins.probability(i)).sum();
    assert!((total - 1.0).abs() < 1e-6, "{label}: cells sum to {total}");
    let out = run_chi_square(w, bins, samples, 7, 0.01, 1);
    println!(
        "chi2 {label}: p = {:.4} (dof {}, {} samples, outside {})",
        out.p_value, out.dof, samples, out.outside
    );
    assert!(out.passed, "{label}: {out:?}");
    out
}

/// The round trip in `T` on the extremes grid and 2000 random points,
/// printed; asserts no failure and an image error within `image_ulps`.
pub(crate) fn roundtrip_passes<T: crate::real::Real, W: WarpFamily<f64>>(
    label: &str,
    w: &W,
    image_ulps: f64,
) -> RoundTripReport {
    let mut pts = extremes_grid();
    pts.extend(random_points(2000, 3));
    let r = check_roundtrip::<T, W>(w, &pts).expect("rebuild");
    println!(
        "roundtrip {label} {}: image max {:.2} ulps (median {:.2}), param max {:.3e}, failures {}",
        r.scalar, r.max_image_ulps, r.median_image_ulps, r.max_error, r.failures
    );
    assert!(r.failures == 0, "{label}: {r:?}");
    assert!(r.max_image_ulps <= image_ulps, "{label}: {r:?}");
    r
}

/// Jacobian at 256 bits and f32/f64 precision against 256 bits on the
/// extremes grid plus random points, printed; asserts
/// `|J·pdf − 1| ≤ 1e-60` and errors within `ulps` units of roundoff
/// (`f64::INFINITY`: finite values only).
#[cfg(feature = "mpfr")]
pub(crate) fn harness_passes<W: WarpFamily<f64>>(label: &str, w: &W, ulps: f64) -> [f64; 3] {
    harness_passes_within(label, w, ulps, 1e-60)
}

/// [`harness_passes`] with another Jacobian bound.
#[cfg(feature = "mpfr")]
pub(crate) fn harness_passes_within<W: WarpFamily<f64>>(
    label: &str,
    w: &W,
    ulps: f64,
    jacobian_bound: f64,
) -> [f64; 3] {
    use crate::harness::jacobian::check_jacobian;
    use crate::harness::precision::check_precision;
    let mut pts = extremes_grid();
    pts.extend(random_points(200, 5));
    let j = check_jacobian(w, &pts).expect("rebuild at 256 bits");
    println!(
        "jacobian {label}: max |J·pdf − 1| = {:.2e} ({} points, {} nudged)",
        j.max_rel_deviation, j.points, j.nudged
    );
    assert!(j.passes(jacobian_bound), "{label}: {j:?}");
    let p32 = check_precision::<f32, _>(w, &pts).expect("f32");
    let p64 = check_precision::<f64, _>(w, &pts).expect("f64");
    for p in [&p32, &p64] {
        println!(
            "precision {label} {}: max {:.2} (median {:.2}) units of roundoff, worst {:?}, non-finite {}, outside {}",
            p.scalar, p.max_ulps, p.median_ulps, p.worst, p.non_finite, p.outside
        );
        if ulps.is_finite() {
            assert!(p.passes(ulps), "{label}: {p:?}");
        } else {
            // Ill-conditioned shapes: only finiteness here (their accuracy
            // is held to the κ bound elsewhere).
            assert!(p.non_finite + p.reference_non_finite == 0, "{label}: {p:?}");
        }
    }
    [j.max_rel_deviation, p32.max_ulps, p64.max_ulps]
}

/// The harness figures (precision against 256 bits, Jacobian) of the
/// simple warps of the `simple_warps` bench, printed with `--nocapture`:
/// the accuracy side of the speed comparison with the hand-written
/// baselines.
#[cfg(feature = "mpfr")]
#[test]
fn simple_warps_harness() {
    use crate::shapes::{ConcentricDisk, PhongLobe, PlanarTriangle, Sphere};
    use crate::vector::Vec3;
    let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    harness_passes("sphere", &Sphere::<f64>::new(), 4.0);
    harness_passes("cosine", &PhongLobe::<f64>::new(1.0).unwrap(), 4.0);
    harness_passes("concentric-disk", &ConcentricDisk::<f64>::new(), 4.0);
    let tri = PlanarTriangle::new(v(0.3, -0.2, 1.1), v(2.1, 0.4, 0.7), v(0.9, 1.7, 1.3)).unwrap();
    harness_passes("planar-triangle", &tri, 4.0);
}
