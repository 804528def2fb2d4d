//! Uniform sampling of the unit upper hemisphere (Arvo 2001, §1.3.3,
//! eq. 1.26): `z = 1 − u`, `φ = 2πv`. Derivation: `docs/hemisphere.md`.

use super::turns::{clamp_unit, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// Uniform directions on the unit upper hemisphere `{|p| = 1, z ≥ 0}`
/// (Arvo 2001, eq. 1.26):
///
/// ψ(u, v) = (sin θ cos 2πv, sin θ sin 2πv, 1 − u),  sin θ = √(u (2 − u)).
///
/// `u` selects the height `z = 1 − u` (Archimedes: equal heights, equal
/// areas), `v` the azimuth. `u = 0` is the pole `+z`, `u = 1` the equator.
///
/// Numerics: `sin θ = √(1 − z²)` is computed as `√(u (2 − u))` (no
/// cancellation near the pole, where `1 − z² ≈ 2u`); the azimuth is reduced
/// by quarter turns so that `sin 2πv` keeps its relative accuracy for `v`
/// near 1/2 or 1. The inverse takes `u = (x² + y²)/(1 + z)` near the pole,
/// which keeps relative accuracy for tiny `u` where `1 − z` would not.
///
/// # Density
/// Uniform in solid angle: `pdf(p) = 1/(2π)` on the hemisphere (0 below the
/// horizon), `measure() = 2π`.
///
/// # Example
/// ```
/// use areawarp::shapes::Hemisphere;
/// use areawarp::Warp;
///
/// let h = Hemisphere::<f64>::new();
/// let p = h.map(&0.25, &0.5);
/// assert!((p.z - 0.75).abs() < 1e-15);
/// assert!((p.x * p.x + p.y * p.y + p.z * p.z - 1.0).abs() < 1e-15);
/// assert!((h.pdf(&p) * h.measure() - 1.0).abs() < 1e-15);
/// let [u, v] = h.inverse(&p).unwrap();
/// assert!((u - 0.25).abs() < 1e-15 && (v - 0.5).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct Hemisphere<T> {
    half_pi: T,
    inv_two_pi: T,
    two_pi: T,
}

impl<T: Real> Hemisphere<T> {
    /// The uniform hemisphere warp around `+z`.
    ///
    /// # Density
    /// `1/(2π)` per steradian on the upper hemisphere.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Hemisphere;
    /// use areawarp::Warp;
    /// let h = Hemisphere::<f32>::new();
    /// assert_eq!(h.map(&0.0, &0.3).z, 1.0); // u = 0 is the pole
    /// assert_eq!(h.map(&1.0, &0.3).z, 0.0); // u = 1 is the equator
    /// ```
    pub fn new() -> Self {
        let pi = T::pi();
        let two_pi = pi.clone() * &T::from_i64(2);
        Hemisphere {
            half_pi: pi / &T::from_i64(2),
            inv_two_pi: T::one() / &two_pi,
            two_pi,
        }
    }
}

impl<T: Real> Default for Hemisphere<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// `| |p| − 1 | + max(0, −z)`: distance-like measure of how far `p` is off
/// the unit upper hemisphere.
pub(crate) fn upper_hemisphere_outside_by<T: Real>(p: &Vec3<T>) -> T {
    let radial = (p.norm() - &T::one()).abs();
    if p.z < T::zero() {
        radial - &p.z
    } else {
        radial
    }
}

impl<T: Real> Warp<T> for Hemisphere<T> {
    type Point = Vec3<T>;

    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let u = clamp_unit(u);
        let one = T::one();
        let z = one.clone() - &u;
        let sin_theta = (u.clone() * &(T::from_i64(2) - &u)).sqrt();
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        Vec3::new(x, y, z)
    }

    #[inline]
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        if p.z < T::zero() {
            T::zero()
        } else {
            self.inv_two_pi.clone()
        }
    }

    fn measure(&self) -> T {
        self.two_pi.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let n = p.norm();
        let (x, y, z) = (p.x.clone() / &n, p.y.clone() / &n, p.z.clone() / &n);
        let one = T::one();
        // 1 − z = (x² + y²)/(1 + z) on the sphere; the quotient keeps the
        // relative accuracy of tiny u that the difference would lose.
        let u = if z > T::from_ratio(1, 2) {
            (x.square() + &y.square()) / &(one.clone() + &z)
        } else {
            one - &z
        };
        Ok([clamp_unit(&u), turns_of(&y, &x, &self.inv_two_pi)])
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

crate::warp::distribution_for_floats!(Hemisphere, Vec3);

impl<T: Real> WarpFamily<T> for Hemisphere<T> {
    type At<S: Real> = Hemisphere<S>;
    fn at<S: Real>(&self) -> Result<Hemisphere<S>, WarpError> {
        Ok(Hemisphere::new())
    }
    fn name(&self) -> String {
        "hemisphere".to_string()
    }
}

/// The recipe specification of [`Hemisphere`] (Arvo 2001, §1.3.3), steps 1–4:
///
/// 1. φ(s, t) = (sin(πs/2) cos 2πt, sin(πs/2) sin 2πt, cos(πs/2))  (eq. 1.24;
///    `s` is the polar angle in units of π/2, `t` the azimuth in turns);
/// 2. σ(s, t) = ‖φ_s × φ_t‖ = π² sin(πs/2)  (eq. 1.25; derived by dual numbers);
/// 3. m = 2π, F(s) = 1 − cos(πs/2) = 2 sin²(πs/4), G_s(t) = t;
/// 4. F⁻¹(u) = (2/π) arccos(1 − u) = (4/π) arcsin(√(u/2)), G_s⁻¹(v) = v.
///
/// The half-angle forms of F and F⁻¹ avoid the cancellation of `1 − cos` and
/// `arccos(1 − u)` for small arguments. Composed with
/// [`RecipeWarp`](crate::recipe::RecipeWarp) and
/// [`ClosedForm`](crate::recipe::ClosedForm) inverters it is the same map as
/// [`Hemisphere`], which the unit tests check at 256 bits.
///
/// # Density
/// Weight 1 (uniform): density `1/(2π)` per steradian, total measure 2π.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{Hemisphere, HemisphereRecipe};
/// use areawarp::Warp;
///
/// let spec = RecipeWarp::new(HemisphereRecipe::<f64>::new(), ClosedForm, ClosedForm);
/// let p = spec.map(&0.3, &0.6);
/// let q = Hemisphere::<f64>::new().map(&0.3, &0.6);
/// assert!(p.sub(&q).norm() < 1e-15);
/// assert!((spec.measure() - 2.0 * std::f64::consts::PI).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct HemisphereRecipe<T> {
    half_pi: T,
    quarter_pi: T,
    two_pi: T,
    inv_two_pi: T,
    two_over_pi: T,
    four_over_pi: T,
}

impl<T: Real> HemisphereRecipe<T> {
    /// The recipe of the uniform hemisphere around `+z`.
    ///
    /// # Density
    /// Uniform: σ(s, t) = π² sin(πs/2), total measure 2π.
    ///
    /// # Example
    /// ```
    /// use areawarp::recipe::MarginalConditional;
    /// use areawarp::shapes::HemisphereRecipe;
    /// let r = HemisphereRecipe::<f64>::new();
    /// assert!((r.marginal_cdf(&1.0) - 1.0).abs() < 1e-15);
    /// ```
    pub fn new() -> Self {
        let pi = T::pi();
        let two_pi = pi.clone() * &T::from_i64(2);
        HemisphereRecipe {
            half_pi: pi.clone() / &T::from_i64(2),
            quarter_pi: pi.clone() / &T::from_i64(4),
            inv_two_pi: T::one() / &two_pi,
            two_pi,
            two_over_pi: T::from_i64(2) / &pi,
            four_over_pi: T::from_i64(4) / &pi,
        }
    }
}

impl<T: Real> Default for HemisphereRecipe<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Parametrization<T> for HemisphereRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (sin_a, cos_a) = (S::embed(&self.half_pi) * s).sin_cos();
        let (sin_b, cos_b) = (S::embed(&self.two_pi) * t).sin_cos();
        Vec3::new(sin_a.clone() * &cos_b, sin_a * &sin_b, cos_a)
    }

    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        // Polar angle by atan2: accurate at the pole and at the equator.
        let theta = p.x.hypot(&p.y).atan2(&p.z);
        Some((
            theta * &self.two_over_pi,
            turns_of(&p.y, &p.x, &self.inv_two_pi),
        ))
    }
}

impl<T: Real> AreaDensity<T> for HemisphereRecipe<T> {}

impl<T: Real> MarginalConditional<T> for HemisphereRecipe<T> {
    fn measure(&self) -> T {
        self.two_pi.clone()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        let h = (self.quarter_pi.clone() * s).sin();
        h.square() * &T::from_i64(2)
    }
    fn marginal_pdf(&self, s: &T) -> T {
        (self.half_pi.clone() * s).sin() * &self.half_pi
    }
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        let half_u = clamp_unit(u) / &T::from_i64(2);
        Some(half_u.sqrt().asin() * &self.four_over_pi)
    }
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for HemisphereRecipe<T> {
    type At<S: Real> = HemisphereRecipe<S>;
    fn recast<S: Real>(&self) -> Result<HemisphereRecipe<S>, WarpError> {
        Ok(HemisphereRecipe::new())
    }
    fn name(&self) -> String {
        "hemisphere".to_string()
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The extreme parameters of the brief, as exact binary values.
    fn edges() -> [f64; 8] {
        [
            0.0,
            2f64.powi(-60),
            1e-12,
            1e-6,
            0.5,
            1.0 - 1e-6,
            1.0 - 1e-12,
            1.0,
        ]
    }

    fn finite_on_shape<T: Real>() {
        let h = Hemisphere::<T>::new();
        let tol = T::unit_roundoff() * &T::from_i64(4);
        for &u in &edges() {
            for &v in &edges() {
                let p = h.map(&T::from_f64(u), &T::from_f64(v));
                assert!(p.is_finite(), "{u} {v}: {p:?}");
                assert!(h.outside_by(&p) <= tol, "{u} {v}: {p:?}");
                assert!(h.pdf(&p).is_finite() && h.pdf(&p) > T::zero());
            }
        }
    }

    #[test]
    fn hemisphere_finite_on_shape_f32() {
        finite_on_shape::<f32>();
    }

    #[test]
    fn hemisphere_finite_on_shape_f64() {
        finite_on_shape::<f64>();
    }

    #[test]
    fn hemisphere_poles_and_equator() {
        let h = Hemisphere::<f64>::new();
        assert_eq!(h.map(&0.0, &0.7), Vec3::new(0.0, 0.0, 1.0));
        let e = h.map(&1.0, &0.25);
        assert_eq!(e.z, 0.0);
        assert!(e.x.abs() < 1e-300 && e.y == 1.0);
        // Tiny u: sin θ ≈ √(2u) to full relative accuracy.
        let u = 2f64.powi(-60);
        let p = h.map(&u, &0.0);
        assert!((p.x / (2.0 * u).sqrt() - 1.0).abs() < 4.0 * f64::EPSILON);
    }

    #[test]
    fn hemisphere_roundtrip_f64() {
        let h = Hemisphere::<f64>::new();
        for &u in &edges() {
            if u == 0.0 {
                continue; // the pole: v undefined
            }
            for &v in &edges() {
                if v == 1.0 {
                    continue; // same azimuth as v = 0
                }
                let [u2, v2] = h.inverse(&h.map(&u, &v)).unwrap();
                assert!((u2 - u).abs() <= 1e-12 * u, "{u} {v}: {u2}");
                assert!((v2 - v).abs() <= 1e-12, "{u} {v}: {v2}");
            }
        }
    }

    #[test]
    fn hemisphere_inverse_rejects_off_shape() {
        let h = Hemisphere::<f64>::new();
        assert!(h.inverse(&Vec3::new(0.0, 0.0, -1.0)).is_err());
        assert!(h.inverse(&Vec3::new(0.0, 0.0, 2.0)).is_err());
        assert!(h.inverse(&Vec3::new(f64::NAN, 0.0, 1.0)).is_err());
        assert!(h.inverse(&Vec3::zero()).is_err());
        assert_eq!(h.pdf(&Vec3::new(0.0, 0.6, -0.8)), 0.0);
        assert!(h.outside_by(&Vec3::new(0.0, 0.6, -0.8)) >= 0.8);
    }

    #[test]
    fn hemisphere_family() {
        let h = Hemisphere::<f32>::new();
        assert_eq!(h.name(), "hemisphere");
        let g = h.at::<f64>().unwrap();
        assert!((g.measure() - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    }

    #[cfg(feature = "mpfr")]
    mod mpfr {
        use super::*;
        use crate::real::{Dual2, Mpfr256};
        use crate::recipe::{ClosedForm, RecipeWarp};

        type M = Mpfr256;

        fn grid() -> Vec<M> {
            let one = M::one();
            vec![
                M::zero(),
                M::exp2i(-60),
                M::from_ratio(1, 2),
                one.clone() - &M::exp2i(-40),
                one,
            ]
        }

        #[test]
        fn hemisphere_recipe_matches_direct_at_256_bits() {
            let spec = RecipeWarp::new(HemisphereRecipe::<M>::new(), ClosedForm, ClosedForm);
            let direct = Hemisphere::<M>::new();
            let tol = M::exp2i(-230);
            for u in grid() {
                for v in grid() {
                    let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                    assert!(d <= tol, "u={u} v={v}: {d}");
                }
            }
            assert!((spec.measure() - &direct.measure()).abs() <= tol);
        }

        #[test]
        fn hemisphere_recipe_sigma_consistent_with_marginal() {
            let r = HemisphereRecipe::<M>::new();
            let tol = M::exp2i(-240);
            let h = M::exp2i(-70);
            for (n, d) in [(1, 10), (1, 4), (1, 2), (3, 4), (9, 10)] {
                let s = M::from_ratio(n, d);
                let sig0 = r.sigma(&s, &M::zero());
                // σ does not depend on t …
                for t in [M::from_ratio(1, 3), M::from_ratio(7, 10)] {
                    assert!((r.sigma(&s, &t) - &sig0).abs() <= tol.clone() * &sig0);
                }
                // … so ∫σ dt = σ, which must equal F'(s)·m.
                let fm = r.marginal_pdf(&s) * &r.measure();
                assert!((fm.clone() - &sig0).abs() <= tol.clone() * &sig0, "s={s}");
                // σ = π² sin(πs/2) (eq. 1.25).
                let closed = M::pi().square() * &(M::pi() * &s / &M::from_i64(2)).sin();
                assert!((closed - &sig0).abs() <= tol.clone() * &sig0);
                // F' is the derivative of F (central difference, error O(h²)).
                let fd = (r.marginal_cdf(&(s.clone() + &h)) - &r.marginal_cdf(&(s.clone() - &h)))
                    / &(h.clone() * &M::from_i64(2));
                assert!((fd - &r.marginal_pdf(&s)).abs() <= M::exp2i(-120));
                // F(F⁻¹(u)) = u.
                let u = s.clone();
                let back = r.marginal_cdf(&r.marginal_inverse(&u).unwrap());
                assert!((back - &u).abs() <= tol);
            }
            assert_eq!(r.marginal_cdf(&M::zero()), M::zero());
            assert!((r.marginal_cdf(&M::one()) - &M::one()).abs() <= tol);
        }

        /// f64 against 256 bits at the extremes, coordinate by coordinate,
        /// relative to each coordinate (exact zeros must stay zero).
        #[test]
        fn hemisphere_f64_accurate_at_extremes() {
            let w64 = Hemisphere::<f64>::new();
            let wm = w64.at::<M>().unwrap();
            for u in edges() {
                for v in edges() {
                    let a = w64.map(&u, &v);
                    let b = wm.map(&M::from_f64(u), &M::from_f64(v));
                    for (x, y) in a.to_array().iter().zip(b.to_array()) {
                        let err = (M::from_f64(*x) - &y).abs();
                        let ulps = (err / &y.abs().max(&M::exp2i(-1000))).to_f64() / f64::EPSILON;
                        assert!(ulps <= 4.0, "u={u} v={v}: {x} vs {y}: {ulps} ulps");
                    }
                }
            }
        }

        #[test]
        fn hemisphere_jacobian_constant_at_256_bits() {
            let w = Hemisphere::<M>::new().at::<Dual2<M>>().unwrap();
            let inner = Hemisphere::<M>::new();
            for ((un, ud), (vn, vd)) in [((1, 3), (1, 7)), ((1, 2), (1, 2)), ((9, 10), (5, 6))] {
                let (u, v) = (M::from_ratio(un, ud), M::from_ratio(vn, vd));
                let p = w.map(&Dual2::seed_u(u.clone()), &Dual2::seed_v(v.clone()));
                let pu = Vec3::new(p.x.du.clone(), p.y.du.clone(), p.z.du.clone());
                let pv = Vec3::new(p.x.dv.clone(), p.y.dv.clone(), p.z.dv.clone());
                let j = pu.cross(&pv).norm() * &inner.pdf(&inner.map(&u, &v));
                assert!((j - &M::one()).abs() <= M::exp2i(-240));
            }
        }
    }

    proptest! {
        #[test]
        fn hemisphere_prop_on_shape_and_roundtrip(u in 0.0f64..=1.0, v in 0.0f64..=1.0) {
            let h = Hemisphere::<f64>::new();
            let p = h.map(&u, &v);
            prop_assert!(p.is_finite());
            prop_assert!(h.outside_by(&p) <= 4.0 * f64::EPSILON);
            prop_assert!((h.pdf(&p) * h.measure() - 1.0).abs() <= 4.0 * f64::EPSILON);
            let [u2, v2] = h.inverse(&p).unwrap();
            prop_assert!((u2 - u).abs() <= 1e-12 * u);
            if u > 1e-6 {
                // Azimuth is periodic: compare on the circle.
                let dv = (v2 - v).abs();
                prop_assert!(dv.min(1.0 - dv) <= 1e-10, "{} {} {}", u, v, v2);
            }
            let pf = Hemisphere::<f32>::new().map(&(u as f32), &(v as f32));
            prop_assert!(pf.is_finite());
        }
    }
}
