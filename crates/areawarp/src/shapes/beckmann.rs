//! The Beckmann microfacet normal distribution, sampled with density
//! D(m)·cos θ_m: `tan²θ = −α² ln(1 − u)`. Derivation: `docs/microfacet.md`.

use super::ggx::{PolarHemisphere, check_roughness};
use super::hemisphere::upper_hemisphere_outside_by;
use super::turns::{clamp_unit, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real, convert};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// Microfacet normals about `+z` with the isotropic Beckmann distribution of
/// roughness α, sampled with density `D(m) cos θ_m` per steradian
/// (Mitsuba's `square_to_beckmann`):
///
/// D(m) = exp(−tan²θ/α²) / (π α² cos⁴θ).
///
/// The CDF of `tan²θ` is `1 − exp(−tan²θ/α²)`, so with
/// `L = −ln(1 − u)`, `tan²θ = α² L` and `φ = 2πv`. `u = 0` is the normal
/// `+z`, `u = 1` the horizon (`L = ∞`).
///
/// Numerics: `L = −ln_1p(−u)` for `u < 1/2`, `−ln(1 − u)` (exact
/// difference) above; with `t = α√L`, `cos θ = 1/√(1 + t²)` and
/// `sin θ = t·cos θ` for `t ≤ 1`, and through `1/t` above, so that the
/// horizon `u = 1` (`t = ∞`) gives `(sin θ, cos θ) = (1, 0)` and no NaN.
/// Both keep full relative accuracy for every α down to 10⁻⁴. The density
/// is `exp(−tan²θ/α²)/(π α² cos³θ)`, evaluated as 0 once `tan²θ/α²`
/// exceeds the exponent range (no ∞·0).
///
/// # Density
/// `D(m) cos θ_m` per steradian on the upper hemisphere; `measure() = 1`.
///
/// # Example
/// ```
/// use areawarp::shapes::Beckmann;
/// use areawarp::Warp;
///
/// let b = Beckmann::new(0.1f64).unwrap();
/// let m = b.map(&(1.0 - (-1.0f64).exp()), &0.0); // tan²θ = α²
/// assert!((m.x / m.z - 0.1).abs() < 1e-15);
/// assert_eq!(b.map(&1.0, &0.0).z, 0.0); // the horizon, no NaN
/// ```
#[derive(Clone, Debug)]
pub struct Beckmann<T> {
    alpha: T,
    alpha2: T,
    inv_pi_alpha2: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> Beckmann<T> {
    /// Beckmann of roughness `alpha > 0`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for NaN/∞, [`WarpError::InvalidParameter`]
    /// for α ≤ 0.
    ///
    /// # Density
    /// `D(m) cos θ_m` per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Beckmann;
    /// assert!(Beckmann::new(-1.0f64).is_err());
    /// ```
    pub fn new(alpha: T) -> Result<Self, WarpError> {
        check_roughness(&alpha)?;
        let alpha2 = alpha.square();
        let pi = T::pi();
        Ok(Beckmann {
            inv_pi_alpha2: T::one() / &(pi.clone() * &alpha2),
            half_pi: pi.clone() / &T::from_i64(2),
            inv_two_pi: T::one() / &(pi * &T::from_i64(2)),
            alpha,
            alpha2,
        })
    }

    /// The roughness α.
    pub fn alpha(&self) -> &T {
        &self.alpha
    }
}

impl<T: Real> Warp<T> for Beckmann<T> {
    type Point = Vec3<T>;

    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let u = clamp_unit(u);
        let one = T::one();
        let l = if u < T::from_ratio(1, 2) {
            -(-u.clone()).ln_1p()
        } else {
            -(one.clone() - &u).ln()
        };
        let t = (self.alpha2.clone() * &l).sqrt();
        let (sin_theta, cos_theta) = if t <= one {
            let c = one.clone() / &(one + &t.square()).sqrt();
            (t * &c, c)
        } else {
            let r = one.clone() / &t;
            let s = one.clone() / &(one + &r.square()).sqrt();
            (s.clone(), r * &s)
        };
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        Vec3::new(x, y, cos_theta)
    }

    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() || p.z <= T::zero() {
            return T::zero();
        }
        let rho2 = p.x.square() + &p.y.square();
        let z2 = p.z.square();
        let tan2 = rho2.clone() / &z2;
        let x = tan2 / &self.alpha2;
        if !x.is_finite() {
            return T::zero();
        }
        // 1/cos³θ = (|p|/z)³.
        let sec2 = (rho2 + &z2) / &z2;
        let sec3 = sec2.clone() * &sec2.sqrt();
        let e = (-x).exp();
        if e == T::zero() {
            return T::zero();
        }
        e * &sec3 * &self.inv_pi_alpha2
    }

    fn measure(&self) -> T {
        T::one()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let z = p.z.max(&T::zero());
        let rho2 = p.x.square() + &p.y.square();
        // u = 1 − exp(−tan²θ/α²).
        let x = rho2 / &(self.alpha2.clone() * &z.square());
        let u = if x.is_finite() {
            -(-x).exp_m1()
        } else {
            T::one()
        };
        Ok([clamp_unit(&u), turns_of(&p.y, &p.x, &self.inv_two_pi)])
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

impl<T: Real> WarpFamily<T> for Beckmann<T> {
    type At<S: Real> = Beckmann<S>;
    fn at<S: Real>(&self) -> Result<Beckmann<S>, WarpError> {
        Beckmann::new(convert(&self.alpha))
    }
    fn name(&self) -> String {
        "beckmann".to_string()
    }
}

crate::warp::distribution_for_floats!(Beckmann, Vec3);

/// The recipe specification of [`Beckmann`]: φ the polar hemisphere with
/// θ = πs/2, weight `D(m) cos θ_m` (measure 1),
/// `F(s) = 1 − exp(−tan²θ/α²)`, `F⁻¹(u) = (2/π) atan(α√(−ln(1 − u)))`,
/// `G_s(t) = t`.
///
/// # Density
/// As [`Beckmann`].
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{Beckmann, BeckmannRecipe};
/// use areawarp::Warp;
/// let spec = RecipeWarp::new(BeckmannRecipe::new(0.2f64).unwrap(), ClosedForm, ClosedForm);
/// let q = Beckmann::new(0.2f64).unwrap().map(&0.3, &0.6);
/// assert!(spec.map(&0.3, &0.6).sub(&q).norm() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct BeckmannRecipe<T> {
    warp: Beckmann<T>,
    polar: PolarHemisphere<T>,
}

impl<T: Real> BeckmannRecipe<T> {
    /// The recipe of [`Beckmann::new`]`(alpha)`.
    ///
    /// # Errors
    /// As [`Beckmann::new`].
    pub fn new(alpha: T) -> Result<Self, WarpError> {
        Ok(BeckmannRecipe {
            warp: Beckmann::new(alpha)?,
            polar: PolarHemisphere::new(),
        })
    }

    /// `tan²θ/α²` at `s` (∞ at the horizon).
    fn x(&self, s: &T) -> T {
        let (sn, cs) = self.polar.sin_cos(&clamp_unit(s));
        sn.square() / &(cs.square() * &self.warp.alpha2)
    }
}

impl<T: Real> Parametrization<T> for BeckmannRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.polar.phi(s, t)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.polar.chart(p)
    }
}

impl<T: Real> AreaDensity<T> for BeckmannRecipe<T> {
    fn weight(&self, p: &Vec3<T>) -> T {
        self.warp.pdf(p)
    }
}

impl<T: Real> MarginalConditional<T> for BeckmannRecipe<T> {
    fn measure(&self) -> T {
        T::one()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        let x = self.x(s);
        if x.is_finite() {
            -(-x).exp_m1()
        } else {
            T::one()
        }
    }
    fn marginal_pdf(&self, s: &T) -> T {
        // dF/dθ = e^(−x)·2 tan θ sec²θ/α², times dθ/ds.
        let (sn, cs) = self.polar.sin_cos(&clamp_unit(s));
        let x = self.x(s);
        if !x.is_finite() || cs == T::zero() {
            return T::zero();
        }
        (-x).exp() * &T::from_i64(2) * &sn / &(cs.clone() * &cs * &cs * &self.warp.alpha2)
            * self.polar.half_pi()
    }
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        let u = clamp_unit(u);
        let l = if u < T::from_ratio(1, 2) {
            -(-u.clone()).ln_1p()
        } else {
            -(T::one() - &u).ln()
        };
        let t = (self.warp.alpha2.clone() * &l).sqrt();
        // atan of ∞ is π/2: the horizon.
        Some(self.polar.s_of(&t.atan2(&T::one())))
    }
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for BeckmannRecipe<T> {
    type At<S: Real> = BeckmannRecipe<S>;
    fn recast<S: Real>(&self) -> Result<BeckmannRecipe<S>, WarpError> {
        BeckmannRecipe::new(convert(&self.warp.alpha))
    }
    fn name(&self) -> String {
        "beckmann".to_string()
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{AxisBins, chi2_passes, roundtrip_passes};

    const ALPHAS: [f64; 5] = [1e-4, 1e-2, 0.3, 1.0, 3.0];

    #[test]
    fn beckmann_errors_edges_and_density() {
        assert!(matches!(
            Beckmann::new(f64::INFINITY),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(matches!(
            Beckmann::new(0.0f64),
            Err(WarpError::InvalidParameter { .. })
        ));
        for a in ALPHAS {
            let b = Beckmann::new(a).unwrap();
            let b32 = Beckmann::new(a as f32).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = b.map(&u, &v);
                    assert!(
                        p.is_finite() && b.outside_by(&p) <= 4.0 * f64::EPSILON,
                        "{a} {u} {v}"
                    );
                    let q = b32.map(&(u as f32), &(v as f32));
                    assert!(q.is_finite() && b32.outside_by(&q) <= 4.0 * f32::EPSILON);
                    assert!(b.pdf(&p).is_finite());
                }
            }
            assert_eq!(b.map(&0.0, &0.0), Vec3::new(0.0, 0.0, 1.0));
            for theta in [0.01, 0.3, 1.2] {
                let (s, c) = f64::sin_cos(theta);
                let t2 = (s / c) * (s / c);
                let want = (-t2 / (a * a)).exp() / (std::f64::consts::PI * a * a * c.powi(3));
                let got = b.pdf(&Vec3::new(s, 0.0, c));
                assert!(
                    (got - want).abs() <= 1e-12 * want.max(1e-300),
                    "{a} {theta}: {got} {want}"
                );
            }
        }
    }

    #[test]
    fn beckmann_roundtrip_and_chi2() {
        for a in ALPHAS {
            let b = Beckmann::new(a).unwrap();
            // Near the horizon exp(−tan²θ/α²) underflows: u rounds to 1.
            roundtrip_passes::<f64, _>(&format!("beckmann {a}"), &b, 16.0);
            roundtrip_passes::<f32, _>(&format!("beckmann {a}"), &b, 16.0);
            let axis = Vec3::new(0.0, 0.0, 1.0);
            let bins = AxisBins::new(
                [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), axis],
                AxisBins::quantile_edges(
                    |x| b.pdf(&Vec3::new((x * (2.0 - x)).max(0.0).sqrt(), 0.0, 1.0 - x)),
                    10,
                    1.0,
                ),
                2.0 * std::f64::consts::PI,
                12,
                |x| b.pdf(&Vec3::new((x * (2.0 - x)).max(0.0).sqrt(), 0.0, 1.0 - x)),
            );
            chi2_passes(&format!("beckmann {a}"), &b, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn beckmann_recipe_matches_direct_at_256_bits() {
        use crate::real::Mpfr256 as M;
        use crate::recipe::{ClosedForm, RecipeWarp};
        for a in ALPHAS {
            let a = M::from_f64(a);
            let spec = RecipeWarp::new(
                BeckmannRecipe::new(a.clone()).unwrap(),
                ClosedForm,
                ClosedForm,
            );
            let direct = Beckmann::new(a).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let (u, v) = (M::from_f64(u), M::from_f64(v));
                    let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                    assert!(d <= M::exp2i(-200), "{u} {v}: {d}");
                }
            }
            let r = spec.recipe;
            for s in [
                M::from_ratio(1, 10),
                M::from_ratio(1, 2),
                M::from_ratio(9, 10),
            ] {
                let (sig, fp) = (r.sigma(&s, &M::from_ratio(1, 3)), r.marginal_pdf(&s));
                assert!(
                    (sig.clone() - &fp).abs() <= M::exp2i(-200) * &sig.max(&M::exp2i(-1000)),
                    "{s}"
                );
            }
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn beckmann_harness_at_extremes() {
        for a in ALPHAS {
            crate::shapes::test_support::harness_passes(
                &format!("beckmann {a}"),
                &Beckmann::new(a).unwrap(),
                8.0,
            );
        }
    }
}
