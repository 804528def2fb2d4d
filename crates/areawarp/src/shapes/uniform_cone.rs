//! Uniform directions in a cone about `+z` (a spherical cap):
//! `1 − z = u·(1 − cos θ_max)`, `φ = 2πv`. Derivation: `docs/uniform-cone.md`.

use super::local_frame::{off_unit_sphere, one_minus_z};
use super::turns::{clamp_unit, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real, convert};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// Validates `cos θ_max` and returns `h = 1 − cos θ_max` (exact for
/// `cos θ_max ≥ 1/2`, Sterbenz).
fn cap_height<T: Real>(cos_theta_max: &T) -> Result<T, WarpError> {
    if !cos_theta_max.is_finite() {
        return Err(WarpError::NonFinite {
            what: "cos_theta_max",
        });
    }
    if *cos_theta_max < -T::one() || *cos_theta_max >= T::one() {
        return Err(WarpError::InvalidParameter {
            name: "cos_theta_max",
            expected: "a number in [-1, 1) (1 is an empty cone)",
        });
    }
    Ok(T::one() - cos_theta_max)
}

/// `max(0, w − h)` for a direction with `w = 1 − z`: how far (in `1 − z`)
/// it lies beyond the rim of a cap of height `h`, plus the distance of the
/// point from the unit sphere.
fn cap_outside_by<T: Real>(p: &Vec3<T>, h: &T) -> T {
    if !p.is_finite() {
        return T::max_value();
    }
    let radial = off_unit_sphere(p);
    if p.norm_squared() == T::zero() {
        return radial;
    }
    let (w, _) = one_minus_z(p);
    radial + &(w - h).max(&T::zero())
}

/// Uniform directions (in solid angle) in the cone of half-angle θ_max about
/// `+z`, i.e. on the spherical cap `{|p| = 1, z ≥ cos θ_max}` (Mitsuba's
/// `square_to_uniform_cone`, pbrt's `SampleUniformCone`):
///
/// ψ(u, v) = (sin θ cos 2πv, sin θ sin 2πv, 1 − u·h),   h = 1 − cos θ_max,
///
/// with `sin θ = √(u·h·(2 − u·h))`. `u = 0` is the axis, `u = 1` the rim.
/// `cos θ_max = 0` is the hemisphere, `−1` the whole sphere.
///
/// Numerics: the map works with `1 − z = u·h` (one rounding) and never forms
/// `1 − z²` from a rounded `z`, so tiny cones (θ_max = 10⁻⁶, `z` rounding
/// to 1) keep full relative accuracy in `sin θ`; `h = 1 − cos θ_max` is exact
/// for `cos θ_max ≥ 1/2`. The inverse takes `1 − z = ρ²/(1 + z)`.
///
/// # Density
/// `pdf = 1/(2πh)` per steradian on the cap (0 outside), `measure() = 2πh`.
///
/// # Example
/// ```
/// use areawarp::shapes::UniformCone;
/// use areawarp::Warp;
///
/// let cone = UniformCone::new(0.5f64).unwrap(); // θ_max = 60°
/// let p = cone.map(&1.0, &0.0);
/// assert!((p.z - 0.5).abs() < 1e-15); // the rim
/// assert!((cone.measure() - std::f64::consts::PI).abs() < 1e-15);
/// let [u, v] = cone.inverse(&cone.map(&0.3, &0.6)).unwrap();
/// assert!((u - 0.3).abs() < 1e-15 && (v - 0.6).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct UniformCone<T> {
    cos_theta_max: T,
    h: T,
    inv_measure: T,
    measure: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> UniformCone<T> {
    /// The cone of half-angle θ_max about `+z`, given `cos θ_max ∈ [−1, 1)`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for NaN/∞, [`WarpError::InvalidParameter`]
    /// outside `[−1, 1)` (`cos θ_max = 1` is the empty cone).
    ///
    /// # Density
    /// `1/(2π(1 − cos θ_max))` per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::UniformCone;
    /// assert!(UniformCone::new(1.0f64).is_err());
    /// assert!(UniformCone::new(-1.0f32).is_ok()); // the whole sphere
    /// ```
    pub fn new(cos_theta_max: T) -> Result<Self, WarpError> {
        let h = cap_height(&cos_theta_max)?;
        let pi = T::pi();
        let measure = pi.clone() * &h * &T::from_i64(2);
        Ok(UniformCone {
            cos_theta_max,
            inv_measure: T::one() / &measure,
            measure,
            h,
            half_pi: pi.clone() / &T::from_i64(2),
            inv_two_pi: T::one() / &(pi * &T::from_i64(2)),
        })
    }

    /// `cos θ_max`.
    pub fn cos_theta_max(&self) -> &T {
        &self.cos_theta_max
    }
}

impl<T: Real> Warp<T> for UniformCone<T> {
    type Point = Vec3<T>;

    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let w = clamp_unit(u) * &self.h;
        let sin_theta = (w.clone() * &(T::from_i64(2) - &w)).sqrt();
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        Vec3::new(x, y, T::one() - &w)
    }

    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        self.inv_measure.clone()
    }

    fn measure(&self) -> T {
        self.measure.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        Ok(cone_inverse(p, &self.h, &self.inv_two_pi))
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        cap_outside_by(p, &self.h)
    }
}

/// `[u, v]` of a direction (on the cap, checked by the caller) of a cap of
/// height `h` about `+z`.
fn cone_inverse<T: Real>(p: &Vec3<T>, h: &T, inv_two_pi: &T) -> [T; 2] {
    let (w, _) = one_minus_z(p);
    [clamp_unit(&(w / h)), turns_of(&p.y, &p.x, inv_two_pi)]
}

impl<T: Real> WarpFamily<T> for UniformCone<T> {
    type At<S: Real> = UniformCone<S>;
    fn at<S: Real>(&self) -> Result<UniformCone<S>, WarpError> {
        UniformCone::new(convert(&self.cos_theta_max))
    }
    fn name(&self) -> String {
        "uniform-cone".to_string()
    }
}

crate::warp::distribution_for_floats!(UniformCone, Vec3);

/// The recipe specification of [`UniformCone`], steps 1–4:
///
/// 1. φ(s, t) = (sin(θ_max s) cos 2πt, sin(θ_max s) sin 2πt, cos(θ_max s));
/// 2. σ(s, t) = 2πθ_max sin(θ_max s) (by dual numbers);
/// 3. m = 2πh, F(s) = (1 − cos θ_max s)/h = 2 sin²(θ_max s/2)/h, G_s(t) = t;
/// 4. F⁻¹(u) = (2/θ_max) arcsin √(u·h/2), G_s⁻¹(v) = v.
///
/// θ_max = 2 arcsin √(h/2) (no `arccos` near 1).
///
/// # Density
/// Uniform: `1/(2πh)` per steradian.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{UniformCone, UniformConeRecipe};
/// use areawarp::Warp;
/// let spec = RecipeWarp::new(UniformConeRecipe::new(0.25f64).unwrap(), ClosedForm, ClosedForm);
/// let q = UniformCone::new(0.25f64).unwrap().map(&0.3, &0.6);
/// assert!(spec.map(&0.3, &0.6).sub(&q).norm() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct UniformConeRecipe<T> {
    cone: UniformCone<T>,
    theta_max: T,
    two_pi: T,
}

impl<T: Real> UniformConeRecipe<T> {
    /// The recipe of [`UniformCone::new`]`(cos_theta_max)`.
    ///
    /// # Errors
    /// As [`UniformCone::new`].
    pub fn new(cos_theta_max: T) -> Result<Self, WarpError> {
        let cone = UniformCone::new(cos_theta_max)?;
        let theta_max = (cone.h.clone() / &T::from_i64(2)).sqrt().asin() * &T::from_i64(2);
        Ok(UniformConeRecipe {
            theta_max,
            two_pi: T::pi() * &T::from_i64(2),
            cone,
        })
    }
}

impl<T: Real> Parametrization<T> for UniformConeRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (sa, ca) = (S::embed(&self.theta_max) * s).sin_cos();
        let (sb, cb) = (S::embed(&self.two_pi) * t).sin_cos();
        Vec3::new(sa.clone() * &cb, sa * &sb, ca)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        let theta = p.x.hypot(&p.y).atan2(&p.z);
        Some((
            theta / &self.theta_max,
            turns_of(&p.y, &p.x, &self.cone.inv_two_pi),
        ))
    }
}

impl<T: Real> AreaDensity<T> for UniformConeRecipe<T> {}

impl<T: Real> MarginalConditional<T> for UniformConeRecipe<T> {
    fn measure(&self) -> T {
        self.cone.measure.clone()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        let h = (self.theta_max.clone() * s / &T::from_i64(2)).sin();
        h.square() * &T::from_i64(2) / &self.cone.h
    }
    fn marginal_pdf(&self, s: &T) -> T {
        (self.theta_max.clone() * s).sin() * &self.theta_max / &self.cone.h
    }
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        let half = clamp_unit(u) * &self.cone.h / &T::from_i64(2);
        Some(half.sqrt().asin() * &T::from_i64(2) / &self.theta_max)
    }
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for UniformConeRecipe<T> {
    type At<S: Real> = UniformConeRecipe<S>;
    fn recast<S: Real>(&self) -> Result<UniformConeRecipe<S>, WarpError> {
        UniformConeRecipe::new(convert(&self.cone.cos_theta_max))
    }
    fn name(&self) -> String {
        "uniform-cone".to_string()
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        cap_outside_by(p, &self.cone.h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{AxisBins, chi2_passes, roundtrip_passes};

    const CAPS: [f64; 5] = [0.5, 0.0, -1.0, 0.999_999, 1.0 - 1.0 / 1024.0 / 1024.0];

    #[test]
    fn cone_constructor_errors() {
        assert!(matches!(
            UniformCone::new(f64::NAN),
            Err(WarpError::NonFinite { .. })
        ));
        for bad in [1.0, 1.5, -1.0 - 1e-15] {
            assert!(matches!(
                UniformCone::new(bad),
                Err(WarpError::InvalidParameter { .. })
            ));
        }
    }

    #[test]
    fn cone_finite_on_cap_and_edges() {
        for c in CAPS {
            let w = UniformCone::new(c).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = w.map(&u, &v);
                    assert!(p.is_finite());
                    assert!(w.outside_by(&p) <= 4.0 * f64::EPSILON, "{c} {u} {v}");
                    assert!(w.pdf(&p) > 0.0);
                }
            }
            assert_eq!(w.map(&0.0, &0.3), Vec3::new(0.0, 0.0, 1.0));
            assert_eq!(w.map(&1.0, &0.0).z, c);
            assert_eq!(
                w.pdf(&Vec3::new(0.0, 0.0, -1.0)),
                if c == -1.0 {
                    w.pdf(&w.map(&1.0, &0.0))
                } else {
                    0.0
                }
            );
        }
        // A tiny cone: sin θ keeps its relative accuracy.
        let w = UniformCone::new(1.0 - 2f64.powi(-40)).unwrap();
        let p = w.map(&0.5, &0.0);
        let want = (2f64.powi(-41) * (2.0 - 2f64.powi(-41))).sqrt();
        assert!(
            (p.x / want - 1.0).abs() < 4.0 * f64::EPSILON,
            "{}",
            p.x / want - 1.0
        );
    }

    #[test]
    fn cone_roundtrip_and_chi2() {
        for c in CAPS {
            let w = UniformCone::new(c).unwrap();
            roundtrip_passes::<f64, _>(&format!("uniform-cone {c}"), &w, 8.0);
            roundtrip_passes::<f32, _>(&format!("uniform-cone {c}"), &w, 8.0);
            let axis = Vec3::new(0.0, 0.0, 1.0);
            let h = 1.0 - c;
            let edges = AxisBins::quantile_edges(|_| 1.0, 10, h);
            let bins = AxisBins::new(
                [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), axis],
                edges,
                2.0 * std::f64::consts::PI,
                12,
                |_| 1.0 / (2.0 * std::f64::consts::PI * h),
            );
            chi2_passes(&format!("uniform-cone {c}"), &w, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    mod mpfr {
        use super::*;
        use crate::real::Mpfr256;
        use crate::recipe::{ClosedForm, RecipeWarp};
        use crate::shapes::test_support::harness_passes;

        #[test]
        fn cone_harness_at_extremes() {
            for c in CAPS {
                harness_passes(
                    &format!("uniform-cone {c}"),
                    &UniformCone::new(c).unwrap(),
                    4.0,
                );
            }
        }

        #[test]
        fn cone_recipe_matches_direct_at_256_bits() {
            type M = Mpfr256;
            for c in CAPS {
                let c = M::from_f64(c);
                let spec = RecipeWarp::new(
                    UniformConeRecipe::new(c.clone()).unwrap(),
                    ClosedForm,
                    ClosedForm,
                );
                let direct = UniformCone::new(c).unwrap();
                for &u in &EXTREMES {
                    for &v in &EXTREMES {
                        let (u, v) = (M::from_f64(u), M::from_f64(v));
                        let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                        assert!(d <= M::exp2i(-230), "{u} {v}: {d}");
                    }
                }
                assert!((spec.measure() - &direct.measure()).abs() <= M::exp2i(-240));
            }
        }
    }
}
