//! The standard bivariate normal distribution by the Box–Muller transform
//! as a warp of the square: `r = √(−2 ln(1 − u))`, `φ = 2πv`.
//! Derivation: `docs/planar-densities.md`.

use super::turns::{clamp_unit, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec2;
use crate::warp::{InverseError, Warp, WarpFamily};

/// Points of the plane with the standard normal density (Box–Muller, as a
/// warp of the square with an inverse; Mitsuba's `square_to_std_normal`):
///
/// ψ(u, v) = r (cos 2πv, sin 2πv),   r = √(−2 ln(1 − u)).
///
/// `u = 0` is the origin. The exact map sends `u = 1` to infinity; so that
/// every `(u, v)` of the closed square gives a finite point, `1 − u = 0`
/// is replaced by `2⁻¹²⁰` (`r = √(240 ln 2) ≈ 12.9`, a radius whose tail
/// probability is 2⁻¹²⁰). Every other input, in every precision, is mapped
/// exactly; `1 − u ≥ 2⁻ᵖ` for `u < 1` in a `p`-bit type. The substitution
/// keeps the derivative `d(1 − u)/du = −1`, so the Jacobian identity
/// `|ψ_u × ψ_v|·pdf = 1` holds there too.
///
/// Numerics: `−ln(1 − u) = −ln_1p(−u)` for `u < 1/2` (relative accuracy of
/// small radii), `−ln(1 − u)` with the exact difference above; the azimuth
/// by quarter turns.
///
/// # Density
/// `pdf = e^(−r²/2)/(2π)` (area measure); [`Warp::measure`] is the weighted
/// measure `∫ e^(−r²/2) = 2π`.
///
/// # Example
/// ```
/// use areawarp::shapes::StdNormal;
/// use areawarp::{Vec2, Warp};
/// let n = StdNormal::<f64>::new();
/// let p = n.map(&(1.0 - (-0.5f64).exp()), &0.0); // r = 1
/// assert!((p.x - 1.0).abs() < 1e-15);
/// let q = n.map(&1.0, &0.0);
/// assert!(q.x.is_finite() && q.x > 12.0);
/// let [u, v] = n.inverse(&Vec2::new(0.3, -0.4)).unwrap();
/// assert!((n.map(&u, &v).x - 0.3).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct StdNormal<T> {
    half_pi: T,
    inv_two_pi: T,
    two_pi: T,
}

impl<T: Real> StdNormal<T> {
    /// The standard normal distribution on the plane.
    ///
    /// # Density
    /// `e^(−r²/2)/(2π)`.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::StdNormal;
    /// use areawarp::Warp;
    /// assert_eq!(StdNormal::<f64>::new().map(&0.0, &0.3).x, 0.0);
    /// ```
    pub fn new() -> Self {
        let pi = T::pi();
        let two_pi = pi.clone() * &T::from_i64(2);
        StdNormal {
            half_pi: pi / &T::from_i64(2),
            inv_two_pi: T::one() / &two_pi,
            two_pi,
        }
    }
}

impl<T: Real> Default for StdNormal<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Warp<T> for StdNormal<T> {
    type Point = Vec2<T>;

    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        let u = clamp_unit(u);
        let mut q = T::one() - &u;
        if q == T::zero() {
            q += &T::exp2i(-120);
        }
        let l = if u < T::from_ratio(1, 2) {
            -(-u).ln_1p()
        } else {
            -q.ln()
        };
        let r = (l * &T::from_i64(2)).sqrt();
        let (x, y) = polar_turns(&r, &clamp_unit(v), &self.half_pi);
        Vec2::new(x, y)
    }

    fn pdf_unchecked(&self, p: &Vec2<T>) -> T {
        let r2 = p.x.square() + &p.y.square();
        (-(r2 / &T::from_i64(2))).exp() * &self.inv_two_pi
    }

    fn measure(&self) -> T {
        self.two_pi.clone()
    }

    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &T::zero())?;
        let half_r2 = (p.x.square() + &p.y.square()) / &T::from_i64(2);
        let u = -(-half_r2).exp_m1();
        Ok([clamp_unit(&u), turns_of(&p.y, &p.x, &self.inv_two_pi)])
    }

    fn outside_by(&self, p: &Vec2<T>) -> T {
        if p.x.is_finite() && p.y.is_finite() {
            T::zero()
        } else {
            T::max_value()
        }
    }
}

impl<T: Real> WarpFamily<T> for StdNormal<T> {
    type At<S: Real> = StdNormal<S>;
    fn at<S: Real>(&self) -> Result<StdNormal<S>, WarpError> {
        Ok(StdNormal::new())
    }
    fn name(&self) -> String {
        "std-normal".to_string()
    }
}

crate::warp::distribution_for_floats!(StdNormal, Vec2);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::chi2::{BIN_TOLERANCE, Binning};
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{chi2_passes, roundtrip_passes};
    use crate::vector::Vec3;

    /// Annuli of equal normal probability (`P(r ≤ R) = 1 − e^(−R²/2)`, the
    /// last one unbounded) times equal sectors.
    struct RadialBins {
        nr: usize,
        nphi: usize,
    }

    impl Binning for RadialBins {
        fn n_bins(&self) -> usize {
            self.nr * self.nphi
        }
        fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
            if p.z.abs() > BIN_TOLERANCE || !p.is_finite() {
                return None;
            }
            let c = -(-(p.x * p.x + p.y * p.y) / 2.0).exp_m1();
            let i = ((c * self.nr as f64) as usize).min(self.nr - 1);
            let mut t = p.y.atan2(p.x) / (2.0 * std::f64::consts::PI);
            if t < 0.0 {
                t += 1.0;
            }
            let j = ((t * self.nphi as f64) as usize).min(self.nphi - 1);
            Some(i * self.nphi + j)
        }
        fn probability(&self, _i: usize) -> f64 {
            1.0 / self.n_bins() as f64
        }
    }

    #[test]
    fn std_normal_edges_moments_and_chi2() {
        let n = StdNormal::<f64>::new();
        let n32 = StdNormal::<f32>::new();
        for &u in &EXTREMES {
            for &v in &EXTREMES {
                let p = n.map(&u, &v);
                assert!(p.x.is_finite() && p.y.is_finite());
                let q = n32.map(&(u as f32), &(v as f32));
                assert!(q.x.is_finite() && q.y.is_finite());
            }
        }
        let rmax = n.map(&1.0, &0.0).x;
        assert!((rmax - (240.0 * 2f64.ln()).sqrt()).abs() < 1e-14, "{rmax}");
        assert!((n32.map(&1.0, &0.0).x as f64 - rmax).abs() < 1e-5);
        // One ulp of the recovered u moves r by ulp(u)/((1 − u) r): up to
        // ~20 units of roundoff at r ≈ 3.
        roundtrip_passes::<f64, _>("std-normal", &n, 32.0);
        roundtrip_passes::<f32, _>("std-normal", &n, 32.0);
        chi2_passes("std-normal", &n, &RadialBins { nr: 12, nphi: 12 }, 200_000);
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn std_normal_harness_at_extremes() {
        crate::shapes::test_support::harness_passes("std-normal", &StdNormal::<f64>::new(), 16.0);
    }
}
