//! The approximate product sampling renderers use today (Hart, Pharr,
//! Müller, Lopes, McGuire & Shirley 2020; pbrt-v4's `SampleBilinear`): a
//! bilinear density over the unit square, fitted to the cosine at the four
//! corners of the spherical rectangle's parameter square, composed with
//! the spherical-rectangle map. The density in solid angle is
//! `bilinear(u′, v′) / Ω`, where `(u′, v′)` are the rectangle-map
//! coordinates of the direction.
//!
//! The one-dimensional pieces (our derivation of the standard formulas):
//! a linear density `p(x) ∝ (1 − x)a + x b` on `[0, 1]` has the CDF
//! `F(x) = x((2 − x)a + x b)/(a + b)`; its inverse is
//! `x = u(a + b)/(a + √((1 − u)a² + u b²))`, the root of the quadratic in a
//! form without cancellation. The bilinear density with corner weights
//! `w₀₀, w₁₀, w₀₁, w₁₁` has the marginal in `v` linear between `w₀₀ + w₁₀`
//! and `w₀₁ + w₁₁`, and the conditional in `u` linear between the
//! interpolated edge weights.

use super::Receiver;
use super::polygon::PlanarPolygon;
use super::strategies::{SolidAngleSampling, spherical_rectangle};
use areawarp::error::WarpError;
use areawarp::estimate::{Sample, Strategy};
use areawarp::shapes::SphericalRectangle;
use areawarp::vector::Vec3;
use areawarp::warp::Warp;

/// The smallest corner weight (pbrt-v4 uses the same floor): keeps the
/// density positive over the whole square where a corner's cosine is 0.
pub const MIN_WEIGHT: f64 = 0.01;

/// Samples the linear density between `a` (at 0) and `b` (at 1) by
/// inverting its CDF at `u`.
pub fn sample_linear(u: f64, a: f64, b: f64) -> f64 {
    if a + b <= 0.0 {
        return u;
    }
    let x = u * (a + b) / (a + ((1.0 - u) * a * a + u * b * b).sqrt());
    x.clamp(0.0, 1.0)
}

/// The CDF of the linear density between `a` and `b` at `x`: the inverse
/// of [`sample_linear`].
pub fn invert_linear(x: f64, a: f64, b: f64) -> f64 {
    if a + b <= 0.0 {
        return x;
    }
    (x * ((2.0 - x) * a + x * b) / (a + b)).clamp(0.0, 1.0)
}

/// The bilinear sample for `(u, v)` with corner weights `w = [w₀₀, w₁₀,
/// w₀₁, w₁₁]`.
pub fn sample_bilinear(u: f64, v: f64, w: &[f64; 4]) -> [f64; 2] {
    let y = sample_linear(v, w[0] + w[1], w[2] + w[3]);
    let x = sample_linear(u, (1.0 - y) * w[0] + y * w[2], (1.0 - y) * w[1] + y * w[3]);
    [x, y]
}

/// The `(u, v)` that [`sample_bilinear`] maps to `p`.
pub fn invert_bilinear(p: [f64; 2], w: &[f64; 4]) -> [f64; 2] {
    let [x, y] = p;
    [
        invert_linear(x, (1.0 - y) * w[0] + y * w[2], (1.0 - y) * w[1] + y * w[3]),
        invert_linear(y, w[0] + w[1], w[2] + w[3]),
    ]
}

/// The bilinear density at `p` (integrates to 1 over the unit square).
pub fn bilinear_pdf(p: [f64; 2], w: &[f64; 4]) -> f64 {
    let [x, y] = p;
    let sum = w[0] + w[1] + w[2] + w[3];
    if sum <= 0.0 {
        return 1.0;
    }
    4.0 * ((1.0 - x) * (1.0 - y) * w[0]
        + x * (1.0 - y) * w[1]
        + (1.0 - x) * y * w[2]
        + x * y * w[3])
        / sum
}

/// Bilinear-cosine sampling of a rectangular light from a receiver: the
/// spherical-rectangle map composed with a bilinear warp of the corner
/// cosines `max(cos⁺θ, 0.01)`.
#[derive(Clone, Debug)]
pub struct BilinearCosineRectangle {
    rect: SolidAngleSampling<SphericalRectangle<f64>>,
    weights: [f64; 4],
}

impl BilinearCosineRectangle {
    /// The strategy for `polygon` (a rectangle) seen from `receiver`.
    ///
    /// # Errors
    /// As [`spherical_rectangle`].
    pub fn new(polygon: &PlanarPolygon, receiver: &Receiver) -> Result<Self, WarpError> {
        let rect = spherical_rectangle(polygon, receiver.position())?;
        let n = receiver.normal();
        let mut weights = [MIN_WEIGHT; 4];
        for (k, (u, v)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .into_iter()
            .enumerate()
        {
            if let Some(s) = rect.sample(u, v) {
                weights[k] = s.point.dot(n).max(MIN_WEIGHT);
            }
        }
        Ok(BilinearCosineRectangle { rect, weights })
    }

    /// The corner weights `[w₀₀, w₁₀, w₀₁, w₁₁]`.
    pub fn weights(&self) -> [f64; 4] {
        self.weights
    }

    /// The unit-square point that [`Strategy::sample`] maps to direction
    /// `x` (an error where the rectangle map cannot invert it).
    ///
    /// # Errors
    /// The rectangle map's inverse error, as text.
    pub fn inverse(&self, x: &Vec3<f64>) -> Result<[f64; 2], String> {
        let p = self.rect.warp().inverse(x).map_err(|e| format!("{e:?}"))?;
        Ok(invert_bilinear(p, &self.weights))
    }
}

impl Strategy for BilinearCosineRectangle {
    type Point = Vec3<f64>;

    fn sample(&self, u: f64, v: f64) -> Option<Sample<Vec3<f64>>> {
        let p = sample_bilinear(u, v, &self.weights);
        let s = self.rect.sample(p[0], p[1])?;
        let pdf = s.pdf * bilinear_pdf(p, &self.weights);
        (pdf > 0.0 && pdf.is_finite()).then_some(Sample {
            point: s.point,
            pdf,
        })
    }

    fn pdf(&self, x: &Vec3<f64>) -> f64 {
        let base = self.rect.pdf(x);
        if !(base > 0.0) {
            return 0.0;
        }
        match self.rect.warp().inverse(x) {
            Ok(p) => base * bilinear_pdf(p, &self.weights),
            Err(_) => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_and_bilinear_round_trip_and_normalize() {
        let w = [0.3, 1.7, 0.01, 2.5];
        for i in 0..=20 {
            for j in 0..=20 {
                let (u, v) = (i as f64 / 20.0, j as f64 / 20.0);
                let p = sample_bilinear(u, v, &w);
                let back = invert_bilinear(p, &w);
                assert!(
                    (back[0] - u).abs() < 1e-12 && (back[1] - v).abs() < 1e-12,
                    "{u} {v} {back:?}"
                );
            }
        }
        // The density integrates to 1 (midpoint rule).
        let n = 400;
        let mut total = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                total += bilinear_pdf(p, &w);
            }
        }
        assert!((total / (n * n) as f64 - 1.0).abs() < 1e-9, "{total}");
        // The CDF's inverse is the CDF's inverse.
        for k in 0..=10 {
            let u = k as f64 / 10.0;
            assert!((invert_linear(sample_linear(u, 0.2, 3.0), 0.2, 3.0) - u).abs() < 1e-13);
        }
    }

    #[test]
    fn sampled_densities_match_the_pdf_and_the_inverse() {
        let light = PlanarPolygon::rectangle(
            Vec3::new(-0.5, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.5),
        )
        .unwrap();
        let rx = Receiver::new(Vec3::new(0.1, 0.3, 0.0), Vec3::new(0.0, 0.0, 1.0)).unwrap();
        let s = BilinearCosineRectangle::new(&light, &rx).unwrap();
        assert!(s.weights().iter().all(|w| *w >= MIN_WEIGHT));
        for i in 1..10 {
            for j in 1..10 {
                let (u, v) = (i as f64 / 10.0, j as f64 / 10.0);
                let x = s.sample(u, v).unwrap();
                let p = s.pdf(&x.point);
                assert!((p / x.pdf - 1.0).abs() < 1e-9, "{u} {v}: {p} vs {}", x.pdf);
                let back = s.inverse(&x.point).unwrap();
                assert!(
                    (back[0] - u).abs() < 1e-8 && (back[1] - v).abs() < 1e-8,
                    "{back:?}"
                );
            }
        }
        // Closer to cosine-proportional than the plain rectangle: the
        // density is higher where the cosine is higher.
        let hi = s.sample(0.5, 0.02).unwrap();
        let lo = s.sample(0.5, 0.98).unwrap();
        assert!(
            (hi.pdf / lo.pdf - 1.0) * (hi.point.dot(rx.normal()) / lo.point.dot(rx.normal()) - 1.0)
                > 0.0
        );
    }
}
