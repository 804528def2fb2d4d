//! Phong-lobe sampling of the upper hemisphere, density ∝ cos^k θ about `+z`
//! (Arvo 2001, §1.3.4, eq. 1.28): `z = u^(1/(k+1))`, `φ = 2πv`.
//! Derivation: `docs/phong.md`.

use super::hemisphere::upper_hemisphere_outside_by;
use super::turns::{clamp_unit, polar_turns, positive, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real, convert};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// Which formula evaluates `z = u^(1/(k+1))`: the exact special cases
/// `k = 0` (`z = u`) and `k = 1` (`z = √u`), or the logarithmic general form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Uniform,
    Cosine,
    General,
}

impl Kind {
    fn of<T: Real>(k: &T) -> Kind {
        if *k == T::zero() {
            Kind::Uniform
        } else if *k == T::one() {
            Kind::Cosine
        } else {
            Kind::General
        }
    }
}

/// Validates a Phong exponent: finite and `≥ 0`.
fn check_exponent<T: Real>(k: &T) -> Result<(), WarpError> {
    if !k.is_finite() {
        return Err(WarpError::NonFinite {
            what: "Phong exponent",
        });
    }
    if *k < T::zero() {
        return Err(WarpError::InvalidParameter {
            name: "exponent",
            expected: "a finite number k >= 0",
        });
    }
    Ok(())
}

/// `ln cos²θ` of the direction with `ρ² = x² + y²` and height `z ≥ 0`
/// (`−∞` at the horizon), accurate near the pole: there
/// `cos²θ = 1 − ρ²/(ρ² + z²)` and `ln_1p` keeps the small `ρ²`.
fn ln_cos_squared<T: Real>(rho2: &T, z: &T) -> T {
    let n2 = rho2.clone() + &z.square();
    if rho2.clone() * &T::from_i64(2) <= n2 {
        (-(rho2.clone() / &n2)).ln_1p()
    } else {
        (z.square() / &n2).ln()
    }
}

/// `cos^k θ` of the direction `p` (`0` below the horizon or at the origin),
/// without overflow or NaN for huge `k`: `exp((k/2)·ln cos²θ)` underflows
/// to `0` gracefully.
fn cos_power<T: Real>(p: &Vec3<T>, kind: Kind, half_k: &T) -> T {
    let rho2 = p.x.square() + &p.y.square();
    let n2 = rho2.clone() + &p.z.square();
    if p.z < T::zero() || !positive(&n2) {
        return T::zero();
    }
    match kind {
        Kind::Uniform => T::one(),
        Kind::Cosine => p.z.clone() / &n2.sqrt(),
        Kind::General => (half_k.clone() * &ln_cos_squared(&rho2, &p.z)).exp(),
    }
}

/// Directions on the upper hemisphere distributed like a Phong lobe,
/// density ∝ cos^k θ about `+z` (Arvo 2001, eq. 1.28):
///
/// ψ(u, v) = (sin θ cos 2πv, sin θ sin 2πv, z),  z = cos θ = u^(1/(k+1)).
///
/// `k = 0` is the uniform hemisphere (with `z = u`, mirrored with respect to
/// [`Hemisphere`](super::Hemisphere)'s `z = 1 − u`), `k = 1` the
/// cosine-weighted hemisphere (`z = √u`). `u = 0` is the horizon (`z = 0`
/// exactly), `u = 1` the pole.
///
/// Numerics, for every `k` up to `10⁶` and beyond: with
/// `L = ln(u)/(k+1)`, `z = exp(L)` and `sin θ = √(1 − z²) = √(−expm1(2L))`,
/// which never cancels, even when `z` rounds to 1 (`k = 10⁶`,
/// `u = 1 − 10⁻¹²` gives `sin θ ≈ 1.4·10⁻⁹` to full relative accuracy).
/// `k = 0` and `k = 1` use the exact forms `z = u`, `sin θ = √((1−u)(1+u))`
/// and `z = √u`, `sin θ = √(1 − u)`. The density is evaluated as
/// `exp((k/2)·ln cos²θ)` with `ln cos²θ = ln_1p(−ρ²/|p|²)` near the pole, so
/// huge `k` underflow to 0 instead of producing NaN or losing all digits
/// to the rounding of `z`. `1/(k+1)`, `(k+1)/(2π)` etc. are computed once.
///
/// # Density
/// `pdf(p) = (k+1)/(2π) · cos^k θ` per steradian on the upper hemisphere
/// (0 below the horizon); `measure() = ∫ cos^k θ dω = 2π/(k+1)`, the
/// *weighted* measure, so that `|ψ_u × ψ_v| · pdf(ψ) = 1`.
///
/// # Example
/// ```
/// use areawarp::shapes::PhongLobe;
/// use areawarp::Warp;
///
/// let cosine = PhongLobe::<f64>::new(1.0).unwrap();
/// let p = cosine.map(&0.25, &0.0);
/// assert!((p.z - 0.5).abs() < 1e-15); // z = √u
/// let pi = std::f64::consts::PI;
/// assert!((cosine.pdf(&p) - 0.5 / pi).abs() < 1e-15); // cos θ / π
///
/// // A very sharp lobe stays accurate next to the pole.
/// let sharp = PhongLobe::<f64>::new(1e6).unwrap();
/// let u = 1.0 - 1e-12;
/// let q = sharp.map(&u, &0.0);
/// // sin²θ = 1 − u^(2/(k+1)) ≈ 2(1 − u)/(k+1); the naive
/// // (1.0 - u.powf(2.0 / (k + 1.0))).sqrt() returns 0 here.
/// let want = (2.0 * (1.0 - u) / (1e6 + 1.0)).sqrt();
/// assert!((q.x / want - 1.0).abs() < 1e-9);
/// ```
#[derive(Clone, Debug)]
pub struct PhongLobe<T> {
    exponent: T,
    kind: Kind,
    inv_k1: T,
    half_k: T,
    half_k1: T,
    norm: T,
    measure: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> PhongLobe<T> {
    /// The lobe cos^k θ about `+z` with exponent `k ≥ 0`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] if `k` is NaN or infinite,
    /// [`WarpError::InvalidParameter`] if `k < 0`.
    ///
    /// # Density
    /// `(k+1)/(2π) · cos^k θ` per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::PhongLobe;
    /// use areawarp::{Warp, WarpError};
    /// let lobe = PhongLobe::new(20.0f32).unwrap();
    /// assert!((lobe.measure() - 2.0 * std::f32::consts::PI / 21.0).abs() < 1e-6);
    /// assert!(matches!(PhongLobe::new(-1.0f64), Err(WarpError::InvalidParameter { .. })));
    /// assert!(matches!(PhongLobe::new(f64::NAN), Err(WarpError::NonFinite { .. })));
    /// ```
    pub fn new(exponent: T) -> Result<Self, WarpError> {
        check_exponent(&exponent)?;
        let two = T::from_i64(2);
        let pi = T::pi();
        let two_pi = pi.clone() * &two;
        let k1 = exponent.clone() + &T::one();
        Ok(PhongLobe {
            kind: Kind::of(&exponent),
            inv_k1: T::one() / &k1,
            half_k: exponent.clone() / &two,
            half_k1: k1.clone() / &two,
            norm: k1.clone() / &two_pi,
            measure: two_pi.clone() / &k1,
            half_pi: pi / &two,
            inv_two_pi: T::one() / &two_pi,
            exponent,
        })
    }

    /// The Phong exponent `k`.
    ///
    /// # Density
    /// The density is ∝ cos^k θ.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::PhongLobe;
    /// assert_eq!(*PhongLobe::new(3.0f64).unwrap().exponent(), 3.0);
    /// ```
    pub fn exponent(&self) -> &T {
        &self.exponent
    }

    /// `(z, sin θ)` for `u ∈ [0, 1]`, without cancellation.
    #[inline]
    fn height_and_radius(&self, u: &T) -> (T, T) {
        let one = T::one();
        match self.kind {
            Kind::Uniform => {
                let s2 = (one.clone() - u) * &(one + u);
                (u.clone(), s2.sqrt())
            }
            Kind::Cosine => (u.sqrt(), (one - u).sqrt()),
            Kind::General => {
                // At u = 0, ln u = −∞ and the IEEE/MPFR limits give the
                // horizon exactly: z = e^−∞ = 0, sin θ = √(−expm1(−∞)) = 1.
                // (No special case: with dual numbers the infinite
                // derivative dz/du = ∞ must show as non-finite, not as 0.)
                let l = u.ln() * &self.inv_k1;
                let two_l = l.clone() + &l;
                (l.exp(), (-two_l.exp_m1()).sqrt())
            }
        }
    }
}

impl<T: Real> Warp<T> for PhongLobe<T> {
    type Point = Vec3<T>;

    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let (z, sin_theta) = self.height_and_radius(&clamp_unit(u));
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        Vec3::new(x, y, z)
    }

    #[inline]
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        cos_power(p, self.kind, &self.half_k) * &self.norm
    }

    /// The point and its density from the map's own `z = cos θ` for `k = 0`
    /// and `k = 1` (`(k+1)/(2π)·z^k`: no normalization of the point, which
    /// is on the sphere to rounding), [`Warp::pdf_unchecked`] otherwise.
    #[inline]
    fn map_with_pdf(&self, u: &T, v: &T) -> (Vec3<T>, T) {
        let p = self.map(u, v);
        let pdf = match self.kind {
            Kind::Uniform => self.norm.clone(),
            Kind::Cosine => p.z.clone() * &self.norm,
            Kind::General => self.pdf_unchecked(&p),
        };
        (p, pdf)
    }

    fn measure(&self) -> T {
        self.measure.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let z = p.z.max(&T::zero());
        let rho2 = p.x.square() + &p.y.square();
        let n2 = rho2.clone() + &z.square();
        // u = cos^(k+1) θ. Near the pole (u → 1) the exact forms go through
        // 1 − u, computed from ρ² = sin²θ·|p|², so that u is rounded once
        // from an accurate 1 − u: the round trip then reproduces u exactly
        // where ψ is steep (sin θ = √(1 − u) for k = 1).
        let near_pole = rho2.clone() * &T::from_i64(2) <= n2;
        let u = match self.kind {
            Kind::Uniform if near_pole => {
                // 1 − cos θ = sin²θ / (1 + cos θ)
                let n = n2.sqrt();
                T::one() - &((rho2 / &n2) / &(T::one() + &(z / &n)))
            }
            Kind::Uniform => z / &n2.sqrt(),
            Kind::Cosine if near_pole => T::one() - &(rho2 / &n2),
            Kind::Cosine => z.square() / &n2,
            Kind::General => (self.half_k1.clone() * &ln_cos_squared(&rho2, &z)).exp(),
        };
        Ok([clamp_unit(&u), turns_of(&p.y, &p.x, &self.inv_two_pi)])
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

crate::warp::distribution_for_floats!(PhongLobe, Vec3);

impl<T: Real> WarpFamily<T> for PhongLobe<T> {
    type At<S: Real> = PhongLobe<S>;
    fn at<S: Real>(&self) -> Result<PhongLobe<S>, WarpError> {
        PhongLobe::new(convert(&self.exponent))
    }
    fn name(&self) -> String {
        "phong".to_string()
    }
}

/// The recipe specification of [`PhongLobe`] (Arvo 2001, §1.3.4), steps 1–4,
/// with `s` the *elevation* in units of π/2 so that F is an increasing CDF
/// that reproduces eq. 1.28 exactly:
///
/// 1. φ(s, t) = (cos(πs/2) cos 2πt, cos(πs/2) sin 2πt, sin(πs/2))
///    (eq. 1.24 with the polar angle π(1 − s)/2);
/// 2. weight w = cos^k θ = z^k, σ(s, t) = π² cos(πs/2) sin^k(πs/2)
///    (eq. 1.27 in the elevation variable; derived by dual numbers);
/// 3. m = 2π/(k+1), F(s) = sin^(k+1)(πs/2), G_s(t) = t;
/// 4. F⁻¹(u) = (2/π) arcsin(u^(1/(k+1))), evaluated as
///    (2/π) atan2(e^L, √(−expm1(2L))) with L = ln(u)/(k+1); G_s⁻¹(v) = v.
///
/// Arvo's printed `F(s) = cos^(k+1)(πs/2)` (in the polar variable) decreases
/// from 1 to 0: it is the complementary CDF, and using it directly amounts
/// to the substitution u → 1 − u, which leaves the distribution unchanged.
/// F is evaluated as `exp((k+1)·ln sin(πs/2))` with
/// `ln sin(πs/2) = ln_1p(−2 sin²(π(1−s)/4))` for `s > 1/2`, which keeps its
/// digits near the pole for huge `k`.
///
/// Near the pole (`s → 1`, which the orientation of eq. 1.28 forces) the
/// specification is limited by the absolute resolution of the float `s`:
/// composed at 256 bits, its Jacobian deviates from constant by
/// ≈ 2^-256/θ at an angle θ from the pole (≈ 10⁻⁵⁸ at θ ≈ 2⁻⁶⁴), where
/// [`PhongLobe`], which never forms `s`, stays at the 2^-256 level.
///
/// # Density
/// Weighted by cos^k θ: density `(k+1)/(2π) · cos^k θ` per steradian, total
/// weighted measure `2π/(k+1)`.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{PhongLobe, PhongRecipe};
/// use areawarp::Warp;
///
/// let spec = RecipeWarp::new(PhongRecipe::new(8.0f64).unwrap(), ClosedForm, ClosedForm);
/// let p = spec.map(&0.3, &0.6);
/// let q = PhongLobe::new(8.0f64).unwrap().map(&0.3, &0.6);
/// assert!(p.sub(&q).norm() < 1e-14);
/// assert!((spec.pdf(&p) * spec.measure() - p.z.powi(8)).abs() < 1e-14);
/// ```
#[derive(Clone, Debug)]
pub struct PhongRecipe<T> {
    exponent: T,
    kind: Kind,
    k1: T,
    inv_k1: T,
    half_k: T,
    measure: T,
    half_pi: T,
    quarter_pi: T,
    two_pi: T,
    inv_two_pi: T,
    two_over_pi: T,
}

impl<T: Real> PhongRecipe<T> {
    /// The recipe of the lobe cos^k θ about `+z`, `k ≥ 0`.
    ///
    /// # Errors
    /// As [`PhongLobe::new`].
    ///
    /// # Density
    /// σ(s, t) = π² cos(πs/2) sin^k(πs/2), total weighted measure 2π/(k+1).
    ///
    /// # Example
    /// ```
    /// use areawarp::recipe::MarginalConditional;
    /// use areawarp::shapes::PhongRecipe;
    /// let r = PhongRecipe::new(1.0f64).unwrap();
    /// assert!((r.measure() - std::f64::consts::PI).abs() < 1e-15);
    /// assert!((r.marginal_cdf(&(1.0 / 3.0)) - 0.25).abs() < 1e-15); // sin²(π/6)
    /// assert!(PhongRecipe::new(-0.5f64).is_err());
    /// ```
    pub fn new(exponent: T) -> Result<Self, WarpError> {
        check_exponent(&exponent)?;
        let two = T::from_i64(2);
        let pi = T::pi();
        let two_pi = pi.clone() * &two;
        let k1 = exponent.clone() + &T::one();
        Ok(PhongRecipe {
            kind: Kind::of(&exponent),
            inv_k1: T::one() / &k1,
            half_k: exponent.clone() / &two,
            measure: two_pi.clone() / &k1,
            k1,
            half_pi: pi.clone() / &two,
            quarter_pi: pi.clone() / &T::from_i64(4),
            inv_two_pi: T::one() / &two_pi,
            two_pi,
            two_over_pi: two / &pi,
            exponent,
        })
    }

    /// `ln sin(πs/2)` for `s ∈ [0, 1]`, accurate near `s = 1`.
    fn ln_sin(&self, s: &T) -> T {
        if *s > T::from_ratio(1, 2) {
            let h = (self.quarter_pi.clone() * &(T::one() - s)).sin();
            (-(h.square() * &T::from_i64(2))).ln_1p()
        } else {
            (self.half_pi.clone() * s).sin().ln()
        }
    }
}

impl<T: Real> Parametrization<T> for PhongRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (sin_a, cos_a) = (S::embed(&self.half_pi) * s).sin_cos();
        let (sin_b, cos_b) = (S::embed(&self.two_pi) * t).sin_cos();
        Vec3::new(cos_a.clone() * &cos_b, cos_a * &sin_b, sin_a)
    }

    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        let elevation = p.z.atan2(&p.x.hypot(&p.y));
        Some((
            elevation * &self.two_over_pi,
            turns_of(&p.y, &p.x, &self.inv_two_pi),
        ))
    }
}

impl<T: Real> AreaDensity<T> for PhongRecipe<T> {
    fn weight(&self, p: &Vec3<T>) -> T {
        cos_power(p, self.kind, &self.half_k)
    }
}

impl<T: Real> MarginalConditional<T> for PhongRecipe<T> {
    fn measure(&self) -> T {
        self.measure.clone()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        let s = clamp_unit(s);
        if !positive(&s) {
            return T::zero();
        }
        (self.k1.clone() * &self.ln_sin(&s)).exp()
    }
    fn marginal_pdf(&self, s: &T) -> T {
        let s = clamp_unit(s);
        // cos(πs/2) = sin(π(1 − s)/2): no cancellation near s = 1.
        let cos_a = (self.half_pi.clone() * &(T::one() - &s)).sin();
        let sin_pow_k = if self.kind == Kind::Uniform {
            T::one()
        } else if !positive(&s) {
            T::zero()
        } else {
            (self.exponent.clone() * &self.ln_sin(&s)).exp()
        };
        self.k1.clone() * &self.half_pi * &sin_pow_k * &cos_a
    }
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        // u = 0 needs no special case: ln 0 = −∞ gives z = 0, sin θ = 1, s = 0.
        let u = clamp_unit(u);
        let l = u.ln() * &self.inv_k1;
        let two_l = l.clone() + &l;
        let z = l.exp();
        let sin_theta = (-two_l.exp_m1()).sqrt();
        Some(z.atan2(&sin_theta) * &self.two_over_pi)
    }
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for PhongRecipe<T> {
    type At<S: Real> = PhongRecipe<S>;
    fn recast<S: Real>(&self) -> Result<PhongRecipe<S>, WarpError> {
        PhongRecipe::new(convert(&self.exponent))
    }
    fn name(&self) -> String {
        "phong".to_string()
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        upper_hemisphere_outside_by(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const EXPONENTS: [f64; 4] = [0.0, 1.0, 1000.0, 1e6];

    fn us() -> [f64; 5] {
        [0.0, 2f64.powi(-60), 1e-12, 1.0 - 1e-12, 1.0]
    }

    fn vs() -> [f64; 6] {
        [0.0, 2f64.powi(-60), 1e-12, 0.5, 1.0 - 1e-12, 1.0]
    }

    fn finite_on_shape<T: Real>() {
        let tol = T::unit_roundoff() * &T::from_i64(4);
        for k in EXPONENTS {
            let w = PhongLobe::<T>::new(T::from_f64(k)).unwrap();
            for u in us() {
                for v in vs() {
                    let p = w.map(&T::from_f64(u), &T::from_f64(v));
                    assert!(p.is_finite(), "k={k} u={u} v={v}: {p:?}");
                    assert!(w.outside_by(&p) <= tol, "k={k} u={u} v={v}: {p:?}");
                    assert!(p.z >= T::zero());
                    let d = w.pdf(&p);
                    assert!(d.is_finite() && d >= T::zero(), "k={k} u={u}: pdf {d}");
                }
            }
            // u = 0 is the horizon, exactly; u = 1 the pole.
            assert_eq!(w.map(&T::zero(), &T::zero()).z, T::zero());
            assert_eq!(w.map(&T::one(), &T::zero()).z, T::one());
        }
    }

    #[test]
    fn phong_finite_on_shape_f32() {
        finite_on_shape::<f32>();
    }

    #[test]
    fn phong_finite_on_shape_f64() {
        finite_on_shape::<f64>();
    }

    #[test]
    fn phong_constructor_errors() {
        assert_eq!(
            PhongLobe::new(f64::NAN).unwrap_err(),
            WarpError::NonFinite {
                what: "Phong exponent"
            }
        );
        assert!(matches!(
            PhongLobe::new(f64::INFINITY),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(matches!(
            PhongLobe::new(-1e-300f64),
            Err(WarpError::InvalidParameter { .. })
        ));
        assert!(matches!(
            PhongLobe::new(f32::NEG_INFINITY),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(PhongRecipe::new(-2.0f64).is_err());
        assert!(PhongLobe::new(0.0f64).is_ok());
    }

    #[test]
    fn phong_measure_and_pdf() {
        let pi = std::f64::consts::PI;
        for k in EXPONENTS {
            let w = PhongLobe::new(k).unwrap();
            assert!((w.measure() - 2.0 * pi / (k + 1.0)).abs() <= 1e-15 * w.measure());
            // pdf at the pole: (k+1)/(2π).
            let pole = w.pdf(&Vec3::new(0.0, 0.0, 1.0));
            assert!((pole * w.measure() - 1.0).abs() < 1e-15);
            assert_eq!(w.pdf(&Vec3::new(0.6, 0.0, -0.8)), 0.0);
        }
        // Huge k: underflow, no NaN, and the pole neighbourhood is accurate.
        let w = PhongLobe::new(1e6).unwrap();
        assert_eq!(w.pdf(&Vec3::new(1.0, 0.0, 0.0)), 0.0);
        assert_eq!(w.pdf(&Vec3::new(0.6, 0.0, 0.8)), 0.0);
        let p = w.map(&0.5, &0.25);
        let want = 0.5f64.powf(1e6 / (1e6 + 1.0)) * (1e6 + 1.0) / (2.0 * pi); // cos^k θ = u^(k/(k+1))
        let got = w.pdf(&p);
        assert!((got / want - 1.0).abs() < 1e-14, "{got} {want}");
        // Cosine lobe: pdf = cos θ/π.
        let c = PhongLobe::new(1.0).unwrap();
        assert!((c.pdf(&Vec3::new(0.6, 0.0, 0.8)) - 0.8 / pi).abs() < 1e-15);
    }

    #[test]
    fn phong_roundtrip_f64() {
        for k in EXPONENTS {
            let w = PhongLobe::new(k).unwrap();
            for u in [2f64.powi(-60), 1e-12, 1e-6, 0.5, 1.0 - 1e-6] {
                for v in [0.0, 1e-12, 0.3, 0.5, 1.0 - 1e-12] {
                    let [u2, v2] = w.inverse(&w.map(&u, &v)).unwrap();
                    assert!((u2 - u).abs() <= 1e-12 * u, "k={k} u={u} v={v}: {u2}");
                    assert!((v2 - v).abs() <= 1e-12, "k={k} u={u} v={v}: {v2}");
                }
            }
        }
    }

    /// Near the pole ψ is steep in u (sin θ ∝ √(1 − u)), so a round trip
    /// that is off by one ulp of u moves the image by ~1e-10; the inverse
    /// goes through an accurate 1 − u and reproduces u exactly.
    #[test]
    fn phong_roundtrip_exact_near_pole() {
        for k in EXPONENTS {
            let w = PhongLobe::new(k).unwrap();
            for u in [1.0 - 1e-6, 1.0 - 1e-12, 1.0 - 2f64.powi(-40)] {
                let [u2, _] = w.inverse(&w.map(&u, &0.3)).unwrap();
                if k <= 1.0 {
                    assert_eq!(u2, u, "k={k}");
                } else {
                    assert!((u2 - u).abs() <= 2.0 * f64::EPSILON, "k={k} u={u}: {u2}");
                }
            }
        }
    }

    /// With dual numbers the horizon u = 0 must not fake a zero derivative:
    /// dz/du is infinite there (for k > 0), and the Jacobian check relies on
    /// seeing a non-finite value to step inside.
    #[test]
    fn phong_horizon_derivative_not_faked() {
        use crate::real::Dual2;
        for k in [0.5, 7.0, 1000.0] {
            let w = PhongLobe::new(k).unwrap().at::<Dual2<f64>>().unwrap();
            let p = w.map(&Dual2::seed_u(0.0), &Dual2::seed_v(0.3));
            assert_eq!(p.z.re, 0.0);
            assert!(!p.z.du.is_finite() || p.z.du > 1e300, "k={k}: {:?}", p.z);
        }
    }

    #[test]
    fn phong_family() {
        let w = PhongLobe::new(1000.0f32).unwrap();
        assert_eq!(w.name(), "phong");
        let g = w.at::<f64>().unwrap();
        assert_eq!(*g.exponent(), 1000.0);
        assert_eq!(PhongRecipe::new(2.0f64).unwrap().name(), "phong");
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
        fn phong_recipe_matches_direct_at_256_bits() {
            let tol = M::exp2i(-230);
            for k in EXPONENTS {
                let k = M::from_f64(k);
                let spec =
                    RecipeWarp::new(PhongRecipe::new(k.clone()).unwrap(), ClosedForm, ClosedForm);
                let direct = PhongLobe::new(k.clone()).unwrap();
                for u in grid() {
                    for v in grid() {
                        let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                        assert!(d <= tol, "k={k} u={u} v={v}: {d}");
                    }
                }
                let p = direct.map(&M::from_ratio(1, 3), &M::from_ratio(1, 5));
                let rel = (spec.pdf(&p) / &direct.pdf(&p) - &M::one()).abs();
                assert!(rel <= tol, "k={k}: pdf {rel}");
            }
        }

        #[test]
        fn phong_recipe_sigma_consistent_with_marginal() {
            let rel_tol = M::exp2i(-200);
            let h = M::exp2i(-80);
            for k in EXPONENTS {
                let r = PhongRecipe::new(M::from_f64(k)).unwrap();
                let s_values = [
                    M::from_ratio(1, 10),
                    M::from_ratio(1, 2),
                    M::from_ratio(9, 10),
                    M::one() - &M::exp2i(-30),
                ];
                for s in s_values {
                    let sig0 = r.sigma(&s, &M::zero());
                    assert!(sig0 > M::zero(), "k={k} s={s}");
                    for t in [M::from_ratio(1, 3), M::from_ratio(7, 10)] {
                        let rel = (r.sigma(&s, &t) / &sig0 - &M::one()).abs();
                        assert!(rel <= rel_tol, "k={k} s={s}: σ depends on t");
                    }
                    let fm = r.marginal_pdf(&s) * &r.measure();
                    let rel = (fm / &sig0 - &M::one()).abs();
                    assert!(rel <= rel_tol, "k={k} s={s}: F'·m vs σ: {rel}");
                    let fd = (r.marginal_cdf(&(s.clone() + &h))
                        - &r.marginal_cdf(&(s.clone() - &h)))
                        / &(h.clone() * &M::from_i64(2));
                    let rel = (fd / &r.marginal_pdf(&s) - &M::one()).abs();
                    assert!(rel <= M::exp2i(-90), "k={k} s={s}: F' vs ΔF: {rel}");
                }
                for u in [
                    M::exp2i(-60),
                    M::from_ratio(1, 3),
                    M::one() - &M::exp2i(-40),
                ] {
                    let back = r.marginal_cdf(&r.marginal_inverse(&u).unwrap());
                    assert!((back / &u - &M::one()).abs() <= rel_tol, "k={k} u={u}");
                }
                assert_eq!(r.marginal_cdf(&M::zero()), M::zero());
                assert_eq!(r.marginal_cdf(&M::one()), M::one());
            }
        }

        #[test]
        fn phong_jacobian_constant_at_256_bits() {
            for k in EXPONENTS {
                let inner = PhongLobe::new(M::from_f64(k)).unwrap();
                let w = inner.at::<Dual2<M>>().unwrap();
                for (u, v) in [
                    (M::from_ratio(1, 3), M::from_ratio(1, 7)),
                    (M::from_ratio(9, 10), M::from_ratio(5, 6)),
                ] {
                    let p = w.map(&Dual2::seed_u(u.clone()), &Dual2::seed_v(v.clone()));
                    let pu = Vec3::new(p.x.du.clone(), p.y.du.clone(), p.z.du.clone());
                    let pv = Vec3::new(p.x.dv.clone(), p.y.dv.clone(), p.z.dv.clone());
                    let j = pu.cross(&pv).norm() * &inner.pdf(&inner.map(&u, &v));
                    assert!((j - &M::one()).abs() <= M::exp2i(-200), "k={k} u={u}");
                }
            }
        }

        /// f64 against 256 bits at the extremes, coordinate by coordinate,
        /// relative to each coordinate (absolute for exact zeros).
        #[test]
        fn phong_f64_accurate_at_extremes() {
            for k in EXPONENTS {
                let w64 = PhongLobe::new(k).unwrap();
                let wm = w64.at::<M>().unwrap();
                for u in us() {
                    for v in vs() {
                        let a = w64.map(&u, &v);
                        let b = wm.map(&M::from_f64(u), &M::from_f64(v));
                        for (x, y) in a.to_array().iter().zip(b.to_array()) {
                            let err = (M::from_f64(*x) - &y).abs();
                            let scale = y.abs().max(&M::exp2i(-1000));
                            let ulps = (err / &scale).to_f64() / f64::EPSILON;
                            assert!(ulps <= 8.0, "k={k} u={u} v={v}: {x} vs {y}: {ulps} ulps");
                        }
                    }
                }
            }
        }
    }

    proptest! {
        #[test]
        fn phong_prop_on_shape_and_roundtrip(
            u in 0.0f64..=1.0,
            v in 0.0f64..=1.0,
            k in prop_oneof![0.0f64..4.0, 4.0f64..1e6],
        ) {
            let w = PhongLobe::new(k).unwrap();
            let p = w.map(&u, &v);
            prop_assert!(p.is_finite());
            prop_assert!(w.outside_by(&p) <= 4.0 * f64::EPSILON);
            let d = w.pdf(&p);
            prop_assert!(d.is_finite() && d >= 0.0);
            // The density is the normalized weight: pdf·m = cos^k θ = u^(k/(k+1)).
            let want = u.powf(k / (k + 1.0));
            prop_assert!((d * w.measure() - want).abs() <= 1e-9 * want.max(1e-300), "{} {}", d, want);
            if u > 1e-300 && u < 1.0 {
                let [u2, v2] = w.inverse(&p).unwrap();
                prop_assert!((u2 - u).abs() <= 1e-11 * u, "k={} u={} u2={}", k, u, u2);
                let dv = (v2 - v).abs();
                prop_assert!(dv.min(1.0 - dv) <= 1e-9, "k={} u={} v={} v2={}", k, u, v, v2);
            }
            let pf = PhongLobe::new(k as f32).unwrap().map(&(u as f32), &(v as f32));
            prop_assert!(pf.is_finite());
        }
    }
}
