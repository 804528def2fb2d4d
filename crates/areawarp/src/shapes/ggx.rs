//! The GGX (Trowbridge–Reitz) microfacet normal distribution, sampled with
//! density D(m)·cos θ_m: `tan²θ = α² u/(1 − u)`. Derivation:
//! `docs/microfacet.md`.

use super::hemisphere::upper_hemisphere_outside_by;
use super::turns::{clamp_unit, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real, convert};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// Validates a microfacet roughness: finite and `> 0`.
pub(crate) fn check_roughness<T: Real>(alpha: &T) -> Result<(), WarpError> {
    if !alpha.is_finite() {
        return Err(WarpError::NonFinite {
            what: "roughness alpha",
        });
    }
    if *alpha <= T::zero() {
        return Err(WarpError::InvalidParameter {
            name: "alpha",
            expected: "a finite roughness > 0",
        });
    }
    Ok(())
}

/// Microfacet normals about `+z` with the isotropic GGX (Trowbridge–Reitz)
/// distribution of roughness α, sampled with density `D(m) cos θ_m` per
/// steradian (Walter et al. 2007; pbrt's `TrowbridgeReitzDistribution`,
/// visible-normal sampling aside):
///
/// D(m) = α² / (π cos⁴θ (α² + tan²θ)²).
///
/// The CDF of `tan²θ` is `tan²θ/(α² + tan²θ)`, so with `u` the CDF value
///
/// cos²θ = (1 − u)/((1 − u) + α²u),   sin²θ = α²u/((1 − u) + α²u),
///
/// `φ = 2πv`. `u = 0` is the normal `+z`, `u = 1` the horizon.
///
/// Numerics: `cos θ` and `sin θ` each come from their own quotient, with no
/// `1 − cos²θ` anywhere, so both keep full relative accuracy for every
/// roughness down to α = 10⁻⁴ (and below) and at both ends of `u`
/// (`1 − u` is exact for `u ≥ 1/2`). The density is evaluated as
/// `α² z |p|³/(π(α²z² + ρ²)²)` with `ρ² = x² + y²`: no `tan θ`, no overflow
/// at the horizon, where it tends to 0.
///
/// # Density
/// `D(m) cos θ_m` per steradian on the upper hemisphere (0 below);
/// `measure() = 1` (`∫ D cos θ dω = 1`).
///
/// # Example
/// ```
/// use areawarp::shapes::Ggx;
/// use areawarp::Warp;
///
/// let g = Ggx::new(1e-4f64).unwrap();
/// let m = g.map(&0.5, &0.0); // tan θ = α at the median
/// assert!((m.x / m.z - 1e-4).abs() < 1e-19);
/// let pole = g.pdf(&g.map(&0.0, &0.0));
/// assert!((pole * std::f64::consts::PI * 1e-8 - 1.0).abs() < 1e-14); // 1/(πα²)
/// ```
#[derive(Clone, Debug)]
pub struct Ggx<T> {
    alpha: T,
    alpha2: T,
    alpha2_over_pi: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> Ggx<T> {
    /// GGX of roughness `alpha > 0`.
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
    /// use areawarp::shapes::Ggx;
    /// assert!(Ggx::new(0.0f64).is_err());
    /// assert!(Ggx::new(0.3f32).is_ok());
    /// ```
    pub fn new(alpha: T) -> Result<Self, WarpError> {
        check_roughness(&alpha)?;
        let alpha2 = alpha.square();
        let pi = T::pi();
        Ok(Ggx {
            alpha2_over_pi: alpha2.clone() / &pi,
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

impl<T: Real> Warp<T> for Ggx<T> {
    type Point = Vec3<T>;

    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let u = clamp_unit(u);
        let one_minus_u = T::one() - &u;
        let a2u = self.alpha2.clone() * &u;
        let d = one_minus_u.clone() + &a2u;
        let cos_theta = (one_minus_u / &d).sqrt();
        let sin_theta = (a2u / &d).sqrt();
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        Vec3::new(x, y, cos_theta)
    }

    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() || p.z <= T::zero() {
            return T::zero();
        }
        let rho2 = p.x.square() + &p.y.square();
        let n2 = rho2.clone() + &p.z.square();
        let n = n2.sqrt();
        // Normalized: z/|p|, ρ²/|p|².
        let z = p.z.clone() / &n;
        let rho2 = rho2 / &n2;
        let q = self.alpha2.clone() * &z.square() + &rho2;
        self.alpha2_over_pi.clone() * &z / &q.square()
    }

    fn measure(&self) -> T {
        T::one()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let z = p.z.max(&T::zero());
        let rho2 = p.x.square() + &p.y.square();
        // u = tan²θ/(α² + tan²θ) = ρ²/(α²z² + ρ²).
        let a2z2 = self.alpha2.clone() * &z.square();
        let q = a2z2.clone() + &rho2;
        // Near the horizon 1 − u = α²z²/q is the accurate quantity (u is
        // rounded once from it, so that round trips reproduce u).
        let u = if !(q > T::zero()) {
            T::zero()
        } else if rho2 > a2z2 {
            T::one() - &(a2z2 / &q)
        } else {
            rho2 / &q
        };
        Ok([clamp_unit(&u), turns_of(&p.y, &p.x, &self.inv_two_pi)])
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

impl<T: Real> WarpFamily<T> for Ggx<T> {
    type At<S: Real> = Ggx<S>;
    fn at<S: Real>(&self) -> Result<Ggx<S>, WarpError> {
        Ggx::new(convert(&self.alpha))
    }
    fn name(&self) -> String {
        "ggx".to_string()
    }
}

crate::warp::distribution_for_floats!(Ggx, Vec3);

/// The polar parametrization of the upper hemisphere shared by the
/// microfacet recipes: φ(s, t) = (sin θ cos 2πt, sin θ sin 2πt, cos θ),
/// θ = πs/2, and its chart.
#[derive(Clone, Debug)]
pub(crate) struct PolarHemisphere<T> {
    half_pi: T,
    two_pi: T,
    two_over_pi: T,
    inv_two_pi: T,
}

impl<T: Real> PolarHemisphere<T> {
    pub(crate) fn new() -> Self {
        let pi = T::pi();
        PolarHemisphere {
            half_pi: pi.clone() / &T::from_i64(2),
            two_pi: pi.clone() * &T::from_i64(2),
            two_over_pi: T::from_i64(2) / &pi,
            inv_two_pi: T::one() / &(pi * &T::from_i64(2)),
        }
    }
    pub(crate) fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (sa, ca) = (S::embed(&self.half_pi) * s).sin_cos();
        let (sb, cb) = (S::embed(&self.two_pi) * t).sin_cos();
        Vec3::new(sa.clone() * &cb, sa * &sb, ca)
    }
    pub(crate) fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        let theta = p.x.hypot(&p.y).atan2(&p.z);
        Some((
            theta * &self.two_over_pi,
            turns_of(&p.y, &p.x, &self.inv_two_pi),
        ))
    }
    /// `(sin θ, cos θ)` at `s`.
    pub(crate) fn sin_cos(&self, s: &T) -> (T, T) {
        (self.half_pi.clone() * s).sin_cos()
    }
    /// `s` of the polar angle `θ`.
    pub(crate) fn s_of(&self, theta: &T) -> T {
        theta.clone() * &self.two_over_pi
    }
    /// `dθ/ds = π/2`.
    pub(crate) fn half_pi(&self) -> &T {
        &self.half_pi
    }
}

/// The recipe specification of [`Ggx`]: φ the polar hemisphere with
/// θ = πs/2, weight `D(m) cos θ_m` (measure 1),
/// `F(s) = sin²θ/(α² cos²θ + sin²θ)` (the CDF of tan²θ),
/// `F⁻¹(u) = (2/π) atan2(α√u, √(1 − u))`, `G_s(t) = t`.
///
/// # Density
/// As [`Ggx`].
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{Ggx, GgxRecipe};
/// use areawarp::Warp;
/// let spec = RecipeWarp::new(GgxRecipe::new(0.2f64).unwrap(), ClosedForm, ClosedForm);
/// let q = Ggx::new(0.2f64).unwrap().map(&0.3, &0.6);
/// assert!(spec.map(&0.3, &0.6).sub(&q).norm() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct GgxRecipe<T> {
    warp: Ggx<T>,
    polar: PolarHemisphere<T>,
}

impl<T: Real> GgxRecipe<T> {
    /// The recipe of [`Ggx::new`]`(alpha)`.
    ///
    /// # Errors
    /// As [`Ggx::new`].
    pub fn new(alpha: T) -> Result<Self, WarpError> {
        Ok(GgxRecipe {
            warp: Ggx::new(alpha)?,
            polar: PolarHemisphere::new(),
        })
    }
}

impl<T: Real> Parametrization<T> for GgxRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.polar.phi(s, t)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.polar.chart(p)
    }
}

impl<T: Real> AreaDensity<T> for GgxRecipe<T> {
    fn weight(&self, p: &Vec3<T>) -> T {
        self.warp.pdf(p)
    }
}

impl<T: Real> MarginalConditional<T> for GgxRecipe<T> {
    fn measure(&self) -> T {
        T::one()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        let (sn, cs) = self.polar.sin_cos(&clamp_unit(s));
        let s2 = sn.square();
        s2.clone() / &(self.warp.alpha2.clone() * &cs.square() + &s2)
    }
    fn marginal_pdf(&self, s: &T) -> T {
        // dF/dθ = 2α² sin θ cos θ/(α² cos²θ + sin²θ)², times dθ/ds.
        let (sn, cs) = self.polar.sin_cos(&clamp_unit(s));
        let q = self.warp.alpha2.clone() * &cs.square() + &sn.square();
        self.warp.alpha2.clone() * &T::from_i64(2) * &sn * &cs / &q.square() * self.polar.half_pi()
    }
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        let u = clamp_unit(u);
        let theta = (self.warp.alpha.clone() * &u.sqrt()).atan2(&(T::one() - &u).sqrt());
        Some(self.polar.s_of(&theta))
    }
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for GgxRecipe<T> {
    type At<S: Real> = GgxRecipe<S>;
    fn recast<S: Real>(&self) -> Result<GgxRecipe<S>, WarpError> {
        GgxRecipe::new(convert(&self.warp.alpha))
    }
    fn name(&self) -> String {
        "ggx".to_string()
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

    pub(crate) const ALPHAS: [f64; 5] = [1e-4, 1e-2, 0.3, 1.0, 3.0];

    fn d_cos_reference(alpha: f64, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        let t2 = (s / c) * (s / c);
        alpha * alpha / (std::f64::consts::PI * c.powi(4) * (alpha * alpha + t2).powi(2)) * c
    }

    #[test]
    fn ggx_errors_edges_and_density() {
        assert!(matches!(
            Ggx::new(f64::NAN),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(matches!(
            Ggx::new(-0.1f64),
            Err(WarpError::InvalidParameter { .. })
        ));
        for a in ALPHAS {
            let g = Ggx::new(a).unwrap();
            let g32 = Ggx::new(a as f32).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = g.map(&u, &v);
                    assert!(p.is_finite() && g.outside_by(&p) <= 4.0 * f64::EPSILON);
                    let q = g32.map(&(u as f32), &(v as f32));
                    assert!(q.is_finite() && g32.outside_by(&q) <= 4.0 * f32::EPSILON);
                    assert!(g.pdf(&p).is_finite());
                }
            }
            assert_eq!(g.map(&0.0, &0.0), Vec3::new(0.0, 0.0, 1.0));
            assert_eq!(g.map(&1.0, &0.0).z, 0.0);
            assert_eq!(g.pdf(&Vec3::new(1.0, 0.0, 0.0)), 0.0);
            for theta in [0.1, 0.7, 1.4] {
                let p = Vec3::new(theta.sin(), 0.0, theta.cos());
                let want = d_cos_reference(a, theta);
                assert!((g.pdf(&p) / want - 1.0).abs() < 1e-12, "{a} {theta}");
            }
        }
    }

    #[test]
    fn ggx_roundtrip_and_chi2() {
        for a in ALPHAS {
            let g = Ggx::new(a).unwrap();
            roundtrip_passes::<f64, _>(&format!("ggx {a}"), &g, 8.0);
            roundtrip_passes::<f32, _>(&format!("ggx {a}"), &g, 8.0);
            let axis = Vec3::new(0.0, 0.0, 1.0);
            let bins = AxisBins::new(
                [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), axis],
                AxisBins::quantile_edges(
                    |x| g.pdf(&Vec3::new((x * (2.0 - x)).max(0.0).sqrt(), 0.0, 1.0 - x)),
                    10,
                    1.0,
                ),
                2.0 * std::f64::consts::PI,
                12,
                |x| g.pdf(&Vec3::new((x * (2.0 - x)).max(0.0).sqrt(), 0.0, 1.0 - x)),
            );
            chi2_passes(&format!("ggx {a}"), &g, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn ggx_recipe_matches_direct_at_256_bits() {
        use crate::real::Mpfr256 as M;
        use crate::recipe::{ClosedForm, RecipeWarp};
        for a in ALPHAS {
            let a = M::from_f64(a);
            let spec = RecipeWarp::new(GgxRecipe::new(a.clone()).unwrap(), ClosedForm, ClosedForm);
            let direct = Ggx::new(a).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let (u, v) = (M::from_f64(u), M::from_f64(v));
                    let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                    assert!(d <= M::exp2i(-200), "{u} {v}: {d}");
                }
            }
            // F' = ∫σ dt / m, σ from dual numbers.
            let r = spec.recipe;
            for s in [
                M::from_ratio(1, 10),
                M::from_ratio(1, 2),
                M::from_ratio(9, 10),
            ] {
                let rel =
                    (r.sigma(&s, &M::from_ratio(1, 3)) / &r.marginal_pdf(&s) - &M::one()).abs();
                assert!(rel <= M::exp2i(-200), "{s}: {rel}");
            }
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn ggx_harness_at_extremes() {
        for a in ALPHAS {
            crate::shapes::test_support::harness_passes(
                &format!("ggx {a}"),
                &Ggx::new(a).unwrap(),
                4.0,
            );
        }
    }
}
