//! A bilinear density on the unit square (pbrt's `SampleBilinear`):
//! x from its linear marginal, y from the linear conditional.
//! Derivation: `docs/planar-densities.md`.

use super::turns::clamp_unit;
use crate::error::WarpError;
use crate::real::{Embed, Real, convert};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::{Vec2, Vec3};
use crate::warp::{InverseError, Warp, WarpFamily};

/// Inverse CDF of the linear density `∝ (1 − x)a + xb` on [0, 1]
/// (`a, b ≥ 0`, not both 0): `x = u(a + b)/(a + √((1 − u)a² + ub²))`,
/// the conjugate form of the quadratic's root (no cancellation, also for
/// `a = b` and `a = 0`). Uniform (`x = u`) if `a + b = 0`.
fn sample_linear<T: Real>(u: &T, a: &T, b: &T) -> T {
    let s = a.clone() + b;
    if !(s > T::zero()) {
        return u.clone();
    }
    let one = T::one();
    let root = ((one - u) * &a.square() + &(u.clone() * &b.square())).sqrt();
    let den = a.clone() + &root;
    if den == T::zero() {
        // a = 0 and u = 0: the density is ∝ x, x = √u (value 0; for dual
        // numbers the infinite derivative of the exact map).
        return u.sqrt();
    }
    clamp_unit(&(u.clone() * &s / &den))
}

/// CDF of the same density: `x(a(2 − x) + bx)/(a + b)` (all terms ≥ 0);
/// for `x > 1/2` as `1 − (1 − x)(a(1 − x) + b(1 + x))/(a + b)`, so that
/// `1 − F` is accurate where the inverse CDF is steep and `F` is rounded
/// once from it (round trips reproduce `u` there).
fn linear_cdf<T: Real>(x: &T, a: &T, b: &T) -> T {
    let s = a.clone() + b;
    if !(s > T::zero()) {
        return x.clone();
    }
    let one = T::one();
    if *x > T::from_ratio(1, 2) {
        let y = one.clone() - x;
        let tail = y.clone() * &(a.clone() * &y + &(b.clone() * &(one.clone() + x))) / &s;
        return clamp_unit(&(one - &tail));
    }
    clamp_unit(&(x.clone() * &(a.clone() * &(T::from_i64(2) - x) + &(b.clone() * x)) / &s))
}

/// Points of the unit square `[0, 1]²` with the bilinear density
///
/// pdf(x, y) = ((1−x)(1−y)w₀₀ + x(1−y)w₁₀ + (1−x)y w₀₁ + xy w₁₁) / m,
/// m = (w₀₀ + w₁₀ + w₀₁ + w₁₁)/4,
///
/// (pbrt-v4's `SampleBilinear`, Mitsuba's `square_to_bilinear`): `x` from
/// its linear marginal `∝ (1 − x)(w₀₀ + w₀₁) + x(w₁₀ + w₁₁)` by `u`, then
/// `y` from the linear conditional `∝ (1 − y)a + y b`,
/// `a = (1−x)w₀₀ + x w₁₀`, `b = (1−x)w₀₁ + x w₁₁`, by `v`.
///
/// Each linear inversion uses the conjugate root form
/// `x = u(a + b)/(a + √((1 − u)a² + u b²))`, accurate for all weights
/// (including zeros); the weights are scaled by their maximum at
/// construction, so huge or tiny weights neither overflow nor underflow.
///
/// # Density
/// As above (area measure on the square, 0 outside); [`Warp::measure`] is
/// `m`, the integral of the (scaled) bilinear weight.
///
/// # Example
/// ```
/// use areawarp::shapes::Bilinear;
/// use areawarp::{Vec2, Warp};
///
/// let b = Bilinear::new([0.0f64, 1.0, 0.0, 1.0]).unwrap(); // density 2x
/// let p = b.map(&0.25, &0.7);
/// assert!((p.x - 0.5).abs() < 1e-15 && (p.y - 0.7).abs() < 1e-15); // x = √u
/// assert!((b.pdf(&Vec2::new(0.5, 0.3)) - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct Bilinear<T> {
    /// The weights as given: w₀₀, w₁₀, w₀₁, w₁₁.
    weights: [T; 4],
    /// The weights divided by their maximum.
    w: [T; 4],
    /// Marginal endpoints: w₀₀ + w₀₁ (x = 0) and w₁₀ + w₁₁ (x = 1).
    left: T,
    right: T,
    /// m of the scaled weights.
    measure: T,
}

impl<T: Real> Bilinear<T> {
    /// The bilinear density with corner weights `[w00, w10, w01, w11]`
    /// (at (0,0), (1,0), (0,1), (1,1)).
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a NaN/∞ weight,
    /// [`WarpError::InvalidParameter`] for a negative weight,
    /// [`WarpError::Degenerate`] if all are 0.
    ///
    /// # Density
    /// The normalized bilinear interpolation of the weights.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Bilinear;
    /// assert!(Bilinear::new([0.0f64; 4]).is_err());
    /// assert!(Bilinear::new([1.0f64, -1.0, 1.0, 1.0]).is_err());
    /// ```
    pub fn new(weights: [T; 4]) -> Result<Self, WarpError> {
        if weights.iter().any(|w| !w.is_finite()) {
            return Err(WarpError::NonFinite {
                what: "bilinear weight",
            });
        }
        if weights.iter().any(|w| *w < T::zero()) {
            return Err(WarpError::InvalidParameter {
                name: "weights",
                expected: "four finite weights >= 0, not all 0",
            });
        }
        let max = weights.iter().fold(T::zero(), |m, w| m.max(w));
        if !(max > T::zero()) {
            return Err(WarpError::Degenerate {
                what: "all bilinear weights are 0",
            });
        }
        let w = weights.clone().map(|x| x / &max);
        let left = w[0].clone() + &w[2];
        let right = w[1].clone() + &w[3];
        let measure = (left.clone() + &right) / &T::from_i64(4);
        Ok(Bilinear {
            weights,
            w,
            left,
            right,
            measure,
        })
    }

    /// The weights as given, `[w00, w10, w01, w11]`.
    pub fn weights(&self) -> &[T; 4] {
        &self.weights
    }

    /// The conditional's endpoints `(a, b)` at `x` (scaled weights).
    fn conditional_ends(&self, x: &T) -> (T, T) {
        let one_minus_x = T::one() - x;
        let a = one_minus_x.clone() * &self.w[0] + &(x.clone() * &self.w[1]);
        let b = one_minus_x * &self.w[2] + &(x.clone() * &self.w[3]);
        (a, b)
    }

    /// The (scaled) bilinear weight at `(x, y)`.
    fn weight_at(&self, x: &T, y: &T) -> T {
        let (a, b) = self.conditional_ends(x);
        (T::one() - y) * &a + &(y.clone() * &b)
    }
}

/// `max(0, −x, x − 1)`: how far `x` is outside [0, 1].
fn outside_unit<T: Real>(x: &T) -> T {
    (-x.clone()).max(&(x.clone() - &T::one())).max(&T::zero())
}

impl<T: Real> Warp<T> for Bilinear<T> {
    type Point = Vec2<T>;

    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        let x = sample_linear(&clamp_unit(u), &self.left, &self.right);
        let (a, b) = self.conditional_ends(&x);
        let y = sample_linear(&clamp_unit(v), &a, &b);
        Vec2::new(x, y)
    }

    fn pdf_unchecked(&self, p: &Vec2<T>) -> T {
        self.weight_at(&clamp_unit(&p.x), &clamp_unit(&p.y)) / &self.measure
    }

    fn measure(&self) -> T {
        self.measure.clone()
    }

    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &(T::unit_roundoff() * &T::from_i64(4)))?;
        let (x, y) = (clamp_unit(&p.x), clamp_unit(&p.y));
        let u = linear_cdf(&x, &self.left, &self.right);
        let (a, b) = self.conditional_ends(&x);
        Ok([u, linear_cdf(&y, &a, &b)])
    }

    fn outside_by(&self, p: &Vec2<T>) -> T {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return T::max_value();
        }
        outside_unit(&p.x).max(&outside_unit(&p.y))
    }
}

impl<T: Real> WarpFamily<T> for Bilinear<T> {
    type At<S: Real> = Bilinear<S>;
    fn at<S: Real>(&self) -> Result<Bilinear<S>, WarpError> {
        Bilinear::new(self.weights.clone().map(|w| convert(&w)))
    }
    fn name(&self) -> String {
        "bilinear".to_string()
    }
}

crate::warp::distribution_for_floats!(Bilinear, Vec2);

/// The recipe specification of [`Bilinear`]: φ(s, t) = (s, t), weight the
/// bilinear interpolation, F the linear marginal's CDF, G_s the linear
/// conditional's; closed-form inverses as in the map.
///
/// # Density
/// As [`Bilinear`].
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{Bilinear, BilinearRecipe};
/// use areawarp::Warp;
/// let w = [1.0f64, 2.0, 0.5, 3.0];
/// let spec = RecipeWarp::new(BilinearRecipe::new(w).unwrap(), ClosedForm, ClosedForm);
/// let p = Bilinear::new(w).unwrap().map(&0.3, &0.6);
/// let q = spec.map(&0.3, &0.6);
/// assert!((p.x - q.x).abs() < 1e-15 && (p.y - q.y).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct BilinearRecipe<T> {
    warp: Bilinear<T>,
}

impl<T: Real> BilinearRecipe<T> {
    /// The recipe of [`Bilinear::new`]`(weights)`.
    ///
    /// # Errors
    /// As [`Bilinear::new`].
    pub fn new(weights: [T; 4]) -> Result<Self, WarpError> {
        Ok(BilinearRecipe {
            warp: Bilinear::new(weights)?,
        })
    }
}

impl<T: Real> Parametrization<T> for BilinearRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        Vec3::new(s.clone(), t.clone(), S::zero())
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        p.is_finite().then(|| (p.x.clone(), p.y.clone()))
    }
}

impl<T: Real> AreaDensity<T> for BilinearRecipe<T> {
    fn weight(&self, p: &Vec3<T>) -> T {
        self.warp.weight_at(&p.x, &p.y)
    }
}

impl<T: Real> MarginalConditional<T> for BilinearRecipe<T> {
    fn measure(&self) -> T {
        self.warp.measure.clone()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        linear_cdf(s, &self.warp.left, &self.warp.right)
    }
    fn marginal_pdf(&self, s: &T) -> T {
        let w = &self.warp;
        ((T::one() - s) * &w.left + &(s.clone() * &w.right)) * &T::from_i64(2)
            / &(w.left.clone() + &w.right)
    }
    fn conditional_cdf(&self, s: &T, t: &T) -> T {
        let (a, b) = self.warp.conditional_ends(s);
        linear_cdf(t, &a, &b)
    }
    fn conditional_pdf(&self, s: &T, t: &T) -> T {
        let (a, b) = self.warp.conditional_ends(s);
        ((T::one() - t) * &a + &(t.clone() * &b)) * &T::from_i64(2) / &(a + &b)
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        Some(sample_linear(u, &self.warp.left, &self.warp.right))
    }
    fn conditional_inverse(&self, s: &T, v: &T) -> Option<T> {
        let (a, b) = self.warp.conditional_ends(s);
        Some(sample_linear(v, &a, &b))
    }
}

impl<T: Real> Recipe<T> for BilinearRecipe<T> {
    type At<S: Real> = BilinearRecipe<S>;
    fn recast<S: Real>(&self) -> Result<BilinearRecipe<S>, WarpError> {
        Ok(BilinearRecipe {
            warp: self.warp.at()?,
        })
    }
    fn name(&self) -> String {
        "bilinear".to_string()
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.warp.outside_by(&Vec2::new(p.x.clone(), p.y.clone())) + &p.z.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{GridBins, chi2_passes, roundtrip_passes};

    pub(crate) const WEIGHTS: [[f64; 4]; 4] = [
        [1.0, 1.0, 1.0, 1.0],
        [0.1, 2.0, 0.7, 3.0],
        [0.0, 1.0, 1.0, 0.0],
        [1e-300, 0.0, 0.0, 1e-300],
    ];

    #[test]
    fn bilinear_errors_and_edges() {
        assert!(matches!(
            Bilinear::new([f64::NAN, 1.0, 1.0, 1.0]),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(matches!(
            Bilinear::new([0.0f64; 4]),
            Err(WarpError::Degenerate { .. })
        ));
        for w in WEIGHTS {
            let b = Bilinear::new(w).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = b.map(&u, &v);
                    assert!(
                        p.x.is_finite() && p.y.is_finite() && b.outside_by(&p) == 0.0,
                        "{w:?} {u} {v}"
                    );
                }
            }
            assert_eq!(b.map(&0.0, &0.0), Vec2::new(0.0, 0.0));
            assert_eq!(b.map(&1.0, &1.0), Vec2::new(1.0, 1.0));
        }
    }

    #[test]
    fn bilinear_roundtrip_and_chi2() {
        for w in WEIGHTS {
            let b = Bilinear::new(w).unwrap();
            roundtrip_passes::<f64, _>(&format!("bilinear {w:?}"), &b, 8.0);
            if w[0] > 1e-100 || w[1] > 0.0 {
                roundtrip_passes::<f32, _>(&format!("bilinear {w:?}"), &b, 8.0);
            }
            let e = GridBins::uniform_edges(0.0, 1.0, 12);
            let bins = GridBins::new(e.clone(), e, |x, y| b.pdf(&Vec2::new(x, y)));
            chi2_passes(&format!("bilinear {w:?}"), &b, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn bilinear_harness_at_extremes() {
        for w in &WEIGHTS[..3] {
            crate::shapes::test_support::harness_passes(
                &format!("bilinear {w:?}"),
                &Bilinear::new(*w).unwrap(),
                4.0,
            );
        }
    }
}
