//! Uniform sampling of the unit disk in polar coordinates: Arvo (2001),
//! §1.3.2, eq. (1.23). Derivation and numerical choices: `docs/disk.md`.

use super::turns::{clamp01, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::{Vec2, Vec3};
use crate::warp::InverseError;
use crate::warp::{Warp, WarpFamily};

/// The polar area-preserving map of the unit disk (Arvo 2001, eq. 1.23):
///
/// ψ(u, v) = √u·(cos 2πv, sin 2πv).
///
/// `u` is the fraction of the area inside the radius (r = √u), `v` the
/// fraction of a turn counter-clockwise from the +x axis. The map is smooth
/// but not bijective at the center (u = 0) and joins v = 0 to v = 1 along the
/// +x axis; it distorts strata near the center, which the
/// [`ConcentricDisk`](crate::shapes::ConcentricDisk) avoids.
///
/// # Density
/// Uniform in area: `pdf(p) = 1/π`, `measure() = π`, `|ψ_u × ψ_v| = π`.
///
/// # Evaluation
/// cos and sin of 2πv are evaluated after an exact reduction of `v` to
/// `|v − k/4| ≤ 1/8`, so the point keeps full relative accuracy in each
/// coordinate, including v → 1 (angle → 0⁻) and v → 1/2. The inverse uses
/// `u = x² + y²` and `v = atan2(y, x)/(2π)` in `[0, 1)`. See `docs/disk.md`.
///
/// # Example
/// ```
/// use areawarp::shapes::PolarDisk;
/// use areawarp::Warp;
///
/// let disk = PolarDisk::<f64>::new();
/// let p = disk.map(&0.25, &0.25); // r = 1/2, a quarter turn
/// assert!(p.x.abs() < 1e-16 && (p.y - 0.5).abs() < 1e-16);
/// let [u, v] = disk.inverse(&p).unwrap();
/// assert!((u - 0.25).abs() < 1e-15 && (v - 0.25).abs() < 1e-15);
/// assert!((disk.pdf(&p) - 1.0 / std::f64::consts::PI).abs() < 1e-16);
/// ```
#[derive(Clone, Debug)]
pub struct PolarDisk<T> {
    two_pi: T,
    half_pi: T,
    inv_two_pi: T,
    pi: T,
    inv_pi: T,
    /// Largest `outside_by` that [`Warp::inverse`] accepts.
    inverse_tolerance: T,
}

impl<T: Real> PolarDisk<T> {
    /// The unit disk centered at the origin (constants precomputed).
    pub fn new() -> Self {
        let pi = T::pi();
        let two_pi = pi.clone() * T::from_i64(2);
        PolarDisk {
            inv_two_pi: T::one() / &two_pi,
            half_pi: pi.clone() / T::from_i64(2),
            inv_pi: T::one() / &pi,
            two_pi,
            pi,
            inverse_tolerance: T::exp2i(6) * T::unit_roundoff(),
        }
    }

    /// The recipe specification of this map (steps 1–3).
    pub fn recipe(&self) -> PolarDiskRecipe<T> {
        PolarDiskRecipe::new()
    }
}

impl<T: Real> Default for PolarDisk<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Warp<T> for PolarDisk<T> {
    type Point = Vec2<T>;

    /// √u·(cos 2πv, sin 2πv); `u`, `v` clamped to `[0, 1]` (NaN counts as 0).
    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        let r = clamp01(u).sqrt();
        let (x, y) = polar_turns(&r, &clamp01(v), &self.half_pi);
        Vec2::new(x, y)
    }

    /// `1/π`, whatever `p` (not checked).
    #[inline]
    fn pdf_unchecked(&self, _p: &Vec2<T>) -> T {
        self.inv_pi.clone()
    }

    /// π.
    fn measure(&self) -> T {
        self.pi.clone()
    }

    /// `(u, v) = (min(x² + y², 1), atan2(y, x)/(2π) in [0, 1))`; the center
    /// maps to `(0, 0)`. `None` if `p` is not finite or `|p| > 1 + 64u`.
    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &self.inverse_tolerance)?;
        let u = (p.x.square() + &p.y.square()).min(&T::one());
        Ok([u, turns_of(&p.y, &p.x, &self.inv_two_pi)])
    }

    /// `max(0, |p| − 1)`; non-finite `p`: [`Real::max_value`].
    fn outside_by(&self, p: &Vec2<T>) -> T {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return T::max_value();
        }
        (p.x.hypot(&p.y) - &T::one()).max(&T::zero())
    }
}

crate::warp::distribution_for_floats!(PolarDisk, Vec2);

impl<T: Real> WarpFamily<T> for PolarDisk<T> {
    type At<S: Real> = PolarDisk<S>;
    /// The unit disk over `S` (never fails).
    fn at<S: Real>(&self) -> Result<PolarDisk<S>, WarpError> {
        Ok(PolarDisk::new())
    }
    /// `disk`.
    fn name(&self) -> String {
        "disk".to_string()
    }
}

/// Arvo's recipe for the unit disk (steps 1–3), the specification
/// [`PolarDisk`] is tested against.
///
/// 1. φ(s, t) = s·(cos 2πt, sin 2πt, 0) (polar; bijective except at s = 0).
/// 2. σ(s, t) = |det Dφ| = 2πs.
/// 3. F(s) = s², G_s(t) = t; inverses f(u) = √u, g(u, v) = v.
///
/// # Density
/// Uniform: weight 1, measure π; the composed map has density `1/π`.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{PolarDisk, PolarDiskRecipe};
/// use areawarp::Warp;
///
/// let composed = RecipeWarp::new(PolarDiskRecipe::<f64>::new(), ClosedForm, ClosedForm);
/// let p = composed.map(&0.5, &0.125); // a point in space, z = 0
/// let q = PolarDisk::new().map(&0.5, &0.125);
/// assert!((p.x - q.x).abs() < 1e-16 && (p.y - q.y).abs() < 1e-16 && p.z == 0.0);
/// ```
#[derive(Clone, Debug)]
pub struct PolarDiskRecipe<T> {
    disk: PolarDisk<T>,
}

impl<T: Real> PolarDiskRecipe<T> {
    /// The recipe of the unit disk.
    pub fn new() -> Self {
        PolarDiskRecipe {
            disk: PolarDisk::new(),
        }
    }
}

impl<T: Real> Default for PolarDiskRecipe<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Parametrization<T> for PolarDiskRecipe<T> {
    /// φ(s, t) = s·(cos 2πt, sin 2πt, 0), with the reduced evaluation of the
    /// angle of [`PolarDisk`].
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (x, y) = polar_turns(s, t, &S::embed(&self.disk.half_pi));
        Vec3::new(x, y, S::zero())
    }

    /// `(s, t) = (|p|, atan2(y, x)/(2π) in [0, 1))` of the point's `x`, `y`.
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        let s = p.x.hypot(&p.y);
        Some((s, turns_of(&p.y, &p.x, &self.disk.inv_two_pi)))
    }
}

impl<T: Real> AreaDensity<T> for PolarDiskRecipe<T> {
    /// σ(s, t) = 2πs.
    fn sigma(&self, s: &T, _t: &T) -> T {
        self.disk.two_pi.clone() * s
    }
}

impl<T: Real> MarginalConditional<T> for PolarDiskRecipe<T> {
    /// π.
    fn measure(&self) -> T {
        self.disk.pi.clone()
    }
    /// F(s) = s².
    fn marginal_cdf(&self, s: &T) -> T {
        s.square()
    }
    /// F'(s) = 2s.
    fn marginal_pdf(&self, s: &T) -> T {
        s.clone() * T::from_i64(2)
    }
    /// G_s(t) = t.
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    /// ∂G_s/∂t = 1.
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    /// f(u) = √u (u clamped at 0).
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        Some(u.max(&T::zero()).sqrt())
    }
    /// g(s, v) = v.
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for PolarDiskRecipe<T> {
    type At<S: Real> = PolarDiskRecipe<S>;
    fn recast<S: Real>(&self) -> Result<PolarDiskRecipe<S>, WarpError> {
        Ok(PolarDiskRecipe::new())
    }
    fn name(&self) -> String {
        "disk".to_string()
    }
    /// Distance off the plane z = 0 combined with `max(0, |(x, y)| − 1)`.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let radial = (p.x.hypot(&p.y) - &T::one()).max(&T::zero());
        radial.hypot(&p.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real::Dual2;

    /// u, v ∈ {0, 2^-60, 1e-12, 1e-6, 1/2, 1 − 1e-6, 1 − 2^-40, 1}.
    fn grid() -> Vec<f64> {
        vec![
            0.0,
            2f64.powi(-60),
            1e-12,
            1e-6,
            0.5,
            1.0 - 1e-6,
            1.0 - 2f64.powi(-40),
            1.0,
        ]
    }

    #[test]
    fn grid_maps_into_disk() {
        let d = PolarDisk::<f64>::new();
        let ur = f64::EPSILON / 2.0;
        for u in grid() {
            for v in grid() {
                let p = d.map(&u, &v);
                assert!(p.x.is_finite() && p.y.is_finite());
                assert!(d.outside_by(&p) <= 2.0 * ur, "({u},{v}) -> {p:?}");
                // Radius √u to a few ulps.
                assert!((p.norm() - u.sqrt()).abs() <= 4.0 * ur * u.sqrt().max(ur));
            }
        }
        assert_eq!(d.map(&0.0, &0.3), Vec2::new(0.0, 0.0));
        assert_eq!(d.map(&1.0, &0.0), Vec2::new(1.0, 0.0));
        assert_eq!(d.map(&1.0, &1.0), Vec2::new(1.0, -0.0));
        assert_eq!(d.map(&1.0, &0.5), Vec2::new(-1.0, -0.0));
        assert_eq!(d.outside_by(&Vec2::new(0.0, 2.0)), 1.0);
        assert_eq!(d.outside_by(&Vec2::new(f64::NAN, 0.0)), f64::MAX);
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn angles_keep_relative_accuracy() {
        use crate::real::Mpfr256;
        // Near v = 1, 1/2, 1/4, 3/4 one coordinate is tiny: it must still be
        // accurate relative to its own size (naive 2πv loses ~1e-4 here).
        let d = PolarDisk::<f64>::new();
        let d256 = PolarDisk::<Mpfr256>::new();
        let tiny = 2f64.powi(-40);
        for v in [
            tiny,
            1.0 - tiny,
            0.5 - tiny,
            0.5 + tiny,
            0.25 + tiny,
            0.75 - tiny,
            0.3,
            0.9,
        ] {
            let p = d.map(&1.0, &v);
            let q = d256.map(&Mpfr256::one(), &Mpfr256::from_f64(v));
            for (a, b) in [(p.x, q.x.to_f64()), (p.y, q.y.to_f64())] {
                assert!(
                    (a - b).abs() <= 4.0 * f64::EPSILON * b.abs(),
                    "v = {v}: {a:e} vs {b:e}"
                );
            }
        }
    }

    #[test]
    fn round_trip_f64() {
        let d = PolarDisk::<f64>::new();
        for u in grid() {
            for v in grid() {
                let p = d.map(&u, &v);
                let [u2, v2] = d.inverse(&p).expect("on the disk");
                assert!((0.0..=1.0).contains(&u2) && (0.0..1.0).contains(&v2));
                assert!((u - u2).abs() <= 1e-12, "u: ({u},{v}) -> ({u2},{v2})");
                if u == 0.0 {
                    continue; // the center: v is arbitrary
                }
                // v = 1 and v = 0 are the same ray: compare on the circle.
                let dv = (v - v2).abs();
                let dv = dv.min(1.0 - dv);
                assert!(u.sqrt() * dv <= 1e-12, "v: ({u},{v}) -> ({u2},{v2})");
                if u >= 1e-6 {
                    assert!(dv <= 1e-12);
                }
            }
        }
        assert_eq!(d.inverse(&Vec2::new(0.0, 0.0)), Ok([0.0, 0.0]));
        // Just below the +x axis: v rounds to the largest value below 1.
        let [_, v] = d.inverse(&Vec2::new(1.0, -1e-300)).unwrap();
        assert_eq!(v, 1.0 - f64::EPSILON / 2.0);
        let [_, v] = d.inverse(&Vec2::new(1.0, -0.0)).unwrap();
        assert!(v == 0.0 && v.is_sign_positive());
        assert!(d.inverse(&Vec2::new(0.8, 0.8)).is_err());
        assert!(d.inverse(&Vec2::new(f64::INFINITY, 0.0)).is_err());
    }

    #[test]
    fn jacobian_is_pi_in_duals() {
        let d = PolarDisk::<Dual2<f64>>::new();
        for u in [1e-6, 0.1, 0.5, 1.0] {
            for v in [0.0, 0.1, 0.3, 0.5, 0.7, 0.99, 1.0] {
                let p = d.map(&Dual2::seed_u(u), &Dual2::seed_v(v));
                let det = p.x.du * p.y.dv - p.x.dv * p.y.du;
                assert!(
                    (det - std::f64::consts::PI).abs() < 1e-13,
                    "({u},{v}): {det}"
                );
            }
        }
    }

    #[test]
    fn family_and_name() {
        let d = PolarDisk::<f64>::new();
        assert_eq!(d.name(), "disk");
        let d32 = d.at::<f32>().unwrap();
        assert_eq!(d32.measure(), std::f32::consts::PI);
        assert_eq!(d.measure(), std::f64::consts::PI);
        assert_eq!(d.extent(), 1.0);
    }

    #[test]
    fn recipe_sigma_integrates_to_pi() {
        let r = PolarDiskRecipe::<f64>::new();
        let m = r.measure();
        for s in [0.0, 0.3, 1.0] {
            for t in [0.0, 0.2, 0.6, 1.0] {
                let [_, ps, pt] = r.partials(&s, &t);
                let exact = ps.cross(&pt).norm();
                assert!((exact - r.sigma(&s, &t)).abs() <= 1e-14, "{s} {t}");
            }
        }
        assert_eq!(r.marginal_cdf(&1.0), 1.0);
        assert_eq!(r.conditional_cdf(&0.5, &1.0), 1.0);
        for s in [0.1, 0.5, 0.8] {
            let int = (r.sigma(&s, &0.0) + 4.0 * r.sigma(&s, &0.5) + r.sigma(&s, &1.0)) / 6.0;
            assert!((int / m - r.marginal_pdf(&s)).abs() < 1e-14);
        }
        let total = (r.sigma(&0.0, &0.5) + 4.0 * r.sigma(&0.5, &0.5) + r.sigma(&1.0, &0.5)) / 6.0;
        assert!((total - m).abs() < 1e-14 * m);
        // The recipe's chart and outside_by.
        let p = Vec3::new(0.0, -0.5, 0.0);
        let (s, t) = r.chart(&p).unwrap();
        assert!((s - 0.5).abs() < 1e-16 && (t - 0.75).abs() < 1e-16);
        assert_eq!(Recipe::outside_by(&r, &Vec3::new(0.0, 0.0, 0.5)), 0.5);
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn recipe_matches_direct_map_at_256_bits() {
        use crate::real::Mpfr256;
        use crate::recipe::{ClosedForm, RecipeWarp};
        let d = PolarDisk::<f64>::new().at::<Mpfr256>().unwrap();
        let w = RecipeWarp::new(d.recipe(), ClosedForm, ClosedForm)
            .at::<Mpfr256>()
            .unwrap();
        assert_eq!(w.name(), "recipe:disk");
        let one = Mpfr256::one();
        let xs = [
            Mpfr256::zero(),
            Mpfr256::exp2i(-60),
            Mpfr256::from_ratio(1, 2),
            one.clone() - Mpfr256::exp2i(-40),
            one,
        ];
        let tol = Mpfr256::exp2i(-240);
        for u in &xs {
            for v in &xs {
                let p = d.map(u, v).to_vec3();
                let q = w.map(u, v);
                let dist = p.sub(&q).norm();
                assert!(dist <= tol, "({u}, {v}): {dist}");
                if *u > Mpfr256::zero() {
                    let [u1, v1] = d.inverse(&d.map(u, v)).unwrap();
                    let [u2, v2] = w.inverse(&q).unwrap();
                    assert!((u1 - &u2).abs() <= tol.clone());
                    assert!((v1 - &v2).abs() <= tol.clone());
                }
            }
        }
    }
}
