//! Shirley–Chiu concentric map of the unit square onto the unit disk.
//! Derivation and numerical choices: `docs/disk.md`.

use super::turns::clamp01;
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec2;
use crate::warp::InverseError;
use crate::warp::{Warp, WarpFamily};

/// The concentric map of Shirley and Chiu (1997): concentric squares of
/// `[−1, 1]²` (after `(a, b) = (2u − 1, 2v − 1)`) go to concentric circles,
/// so strata stay compact and the map is continuous and bijective on the
/// closed square minus its boundary identifications — unlike the polar map
/// it does not squeeze strata towards the center.
///
/// For `|a| > |b|` (left and right triangles of the square):
/// ψ = a·(cos x, sin x) with x = (π/4)·(b/a);
/// otherwise (top and bottom triangles, and the center):
/// ψ = b·(sin x, cos x) with x = (π/4)·(a/b),
/// which is r(cos θ, sin θ) with r = b, θ = π/2 − x written without the
/// subtraction. The square's corners go to the diagonals of the disk, its
/// edges to the circle.
///
/// # Density
/// Uniform in area: `pdf(p) = 1/π`, `measure() = π`; in each of the four
/// triangles the map sends the area element `r dr dt` of a "square polar"
/// parametrization to `(π/4) r dr dt` of a wedge, so `|ψ_u × ψ_v| = π`
/// everywhere (also at the center, whose one-sided derivatives the map
/// returns for dual numbers: ψ = (π a/4, b) there).
///
/// # Recipe
/// The concentric map is *not* an instance of Arvo's recipe on `[0, 1]²`:
/// its radius `max(|a|, |b|)` depends on both `u` and `v`, so it is not of the
/// triangular form `(s, t) = (f(u), g(u, v))`. It is a piecewise composition
/// of two polar parametrizations (square triangle → wedge) and has no
/// `Recipe` specification here; it is checked directly (Jacobian, inverse).
///
/// # Example
/// ```
/// use areawarp::shapes::ConcentricDisk;
/// use areawarp::Warp;
///
/// let disk = ConcentricDisk::<f64>::new();
/// let p = disk.map(&1.0, &0.5); // the middle of the right edge
/// assert_eq!((p.x, p.y), (1.0, 0.0));
/// let q = disk.map(&0.75, &0.75); // a corner of the concentric square of radius 1/2
/// assert!((q.x - 0.5 * 0.5f64.sqrt()).abs() < 1e-16 && (q.y - q.x).abs() < 1e-16);
/// let [u, v] = disk.inverse(&q).unwrap();
/// assert!((u - 0.75).abs() < 1e-15 && (v - 0.75).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct ConcentricDisk<T> {
    quarter_pi: T,
    half_pi: T,
    four_over_pi: T,
    pi: T,
    inv_pi: T,
    /// Largest `outside_by` that [`Warp::inverse`] accepts.
    inverse_tolerance: T,
}

impl<T: Real> ConcentricDisk<T> {
    /// The unit disk centered at the origin (constants precomputed).
    pub fn new() -> Self {
        let pi = T::pi();
        ConcentricDisk {
            quarter_pi: pi.clone() / T::from_i64(4),
            half_pi: pi.clone() / T::from_i64(2),
            four_over_pi: T::from_i64(4) / &pi,
            inv_pi: T::one() / &pi,
            pi,
            inverse_tolerance: T::exp2i(6) * T::unit_roundoff(),
        }
    }
}

impl<T: Real> Default for ConcentricDisk<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Warp<T> for ConcentricDisk<T> {
    type Point = Vec2<T>;

    /// The concentric map; `u`, `v` clamped to `[0, 1]` (NaN counts as 0).
    /// `2u − 1` is exact for `u ≥ 1/4`; the angle `(π/4)·ratio` stays within
    /// `[−π/4, π/4]`, where sin and cos are well conditioned.
    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        let a = clamp01(u) * T::from_i64(2) - &T::one();
        let b = clamp01(v) * T::from_i64(2) - &T::one();
        let zero = T::zero();
        if a.abs() > b.abs() {
            // a·(cos x, sin x): (a, 0) rotated by x = (π/4)·(b/a), i.e. by
            // b/(2a) quarter turns (2a exact).
            let (x, y) = (b / &(a.clone() + &a)).rotate_quarter_turns(&a, &zero, &self.half_pi);
            Vec2::new(x, y)
        } else if b == zero {
            // The center (a = b = 0): (0, 0), written as the limit of the
            // second branch so that dual numbers carry its derivatives.
            Vec2::new(self.quarter_pi.clone() * &a, b)
        } else {
            // b·(sin x, cos x), x = (π/4)·(a/b): (b, 0) rotated by x,
            // coordinates swapped.
            let (y, x) = (a / &(b.clone() + &b)).rotate_quarter_turns(&b, &zero, &self.half_pi);
            Vec2::new(x, y)
        }
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

    /// The inverse map: with r = |p|, for `|x| ≥ |y|` `a = ±r` (sign of x) and
    /// `b = a·(4/π)·atan(y/x)`, otherwise `b = ±r` (sign of y) and
    /// `a = b·(4/π)·atan(x/y)`; then `(u, v) = ((a + 1)/2, (b + 1)/2)`,
    /// clamped to `[0, 1]`. The center gives `(1/2, 1/2)`. `None` if `p` is not
    /// finite or `|p| > 1 + 64u`.
    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &self.inverse_tolerance)?;
        let half = T::from_ratio(1, 2);
        let r = p.x.hypot(&p.y).min(&T::one());
        if r == T::zero() {
            return Ok([half.clone(), half]);
        }
        let (a, b) = if p.x.abs() >= p.y.abs() {
            let a = r.copysign(&p.x);
            let b = a.clone() * &self.four_over_pi * &(p.y.clone() / &p.x).atan();
            (a, b)
        } else {
            let b = r.copysign(&p.y);
            let a = b.clone() * &self.four_over_pi * &(p.x.clone() / &p.y).atan();
            (a, b)
        };
        let u = ((a + &T::one()) * &half).clamp(&T::zero(), &T::one());
        let v = ((b + &T::one()) * &half).clamp(&T::zero(), &T::one());
        Ok([u, v])
    }

    /// `max(0, |p| − 1)`; non-finite `p`: [`Real::max_value`].
    fn outside_by(&self, p: &Vec2<T>) -> T {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return T::max_value();
        }
        (p.x.hypot(&p.y) - &T::one()).max(&T::zero())
    }
}

crate::warp::distribution_for_floats!(ConcentricDisk, Vec2);

impl<T: Real> WarpFamily<T> for ConcentricDisk<T> {
    type At<S: Real> = ConcentricDisk<S>;
    /// The unit disk over `S` (never fails).
    fn at<S: Real>(&self) -> Result<ConcentricDisk<S>, WarpError> {
        Ok(ConcentricDisk::new())
    }
    /// `concentric-disk`.
    fn name(&self) -> String {
        "concentric-disk".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real::Dual2;

    /// u, v ∈ {0, 2^-60, 1e-12, 1e-6, 1/2, 1 − 1e-6, 1 − 2^-40, 1}, plus points
    /// next to the center.
    fn grid() -> Vec<f64> {
        vec![
            0.0,
            2f64.powi(-60),
            1e-12,
            1e-6,
            0.25,
            0.5 - 1e-9,
            0.5,
            0.5 + 2f64.powi(-40),
            0.8,
            1.0 - 1e-6,
            1.0 - 2f64.powi(-40),
            1.0,
        ]
    }

    #[test]
    fn grid_edges_corners_and_center() {
        let d = ConcentricDisk::<f64>::new();
        let ur = f64::EPSILON / 2.0;
        for u in grid() {
            for v in grid() {
                let p = d.map(&u, &v);
                assert!(p.x.is_finite() && p.y.is_finite(), "({u},{v})");
                assert!(d.outside_by(&p) <= 2.0 * ur);
                // |ψ| = max(|2u − 1|, |2v − 1|).
                let r = (2.0 * u - 1.0).abs().max((2.0 * v - 1.0).abs());
                assert!((p.norm() - r).abs() <= 4.0 * ur * r.max(ur), "({u},{v})");
            }
        }
        assert_eq!(d.map(&0.5, &0.5), Vec2::new(0.0, 0.0));
        let h = 0.5f64.sqrt();
        for (u, v, x, y) in [
            (1.0, 1.0, h, h),
            (0.0, 1.0, -h, h),
            (0.0, 0.0, -h, -h),
            (1.0, 0.0, h, -h),
        ] {
            let p = d.map(&u, &v);
            assert!(
                (p.x - x).abs() <= 2.0 * ur && (p.y - y).abs() <= 2.0 * ur,
                "corner {p:?}"
            );
        }
        assert_eq!(d.map(&1.0, &0.5), Vec2::new(1.0, 0.0));
        assert_eq!(d.map(&0.5, &1.0), Vec2::new(0.0, 1.0));
        assert_eq!(d.map(&0.0, &0.5), Vec2::new(-1.0, 0.0));
        assert_eq!(d.map(&0.5, &0.0), Vec2::new(0.0, -1.0));
    }

    #[test]
    fn round_trip_f64() {
        let d = ConcentricDisk::<f64>::new();
        for u in grid() {
            for v in grid() {
                let p = d.map(&u, &v);
                let [u2, v2] = d.inverse(&p).expect("on the disk");
                assert!((u - u2).abs() <= 1e-12, "({u},{v}) -> ({u2},{v2})");
                assert!((v - v2).abs() <= 1e-12, "({u},{v}) -> ({u2},{v2})");
            }
        }
        assert_eq!(d.inverse(&Vec2::new(0.0, 0.0)), Ok([0.5, 0.5]));
        assert_eq!(d.inverse(&Vec2::new(-0.0, -0.0)), Ok([0.5, 0.5]));
        assert!(d.inverse(&Vec2::new(1.0, 0.01)).is_err());
        assert!(d.inverse(&Vec2::new(f64::NAN, 0.0)).is_err());
    }

    #[test]
    fn jacobian_is_pi_everywhere_including_center() {
        let d = ConcentricDisk::<Dual2<f64>>::new();
        let pts = [0.0, 0.1, 0.3, 0.5, 0.7, 0.75, 0.9, 1.0];
        for u in pts {
            for v in pts {
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
        let d = ConcentricDisk::<f64>::new();
        assert_eq!(d.name(), "concentric-disk");
        assert_eq!(d.measure(), std::f64::consts::PI);
        assert_eq!(d.pdf(&Vec2::new(0.1, 0.2)), 1.0 / std::f64::consts::PI);
        let d32 = d.at::<f32>().unwrap();
        let p = d32.map(&0.9, &0.3);
        assert!((p.norm() - 0.8).abs() < 1e-6);
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn f64_map_is_accurate() {
        use crate::real::Mpfr256;
        let d = ConcentricDisk::<f64>::new();
        let d256 = ConcentricDisk::<Mpfr256>::new();
        for u in grid() {
            for v in grid() {
                let p = d.map(&u, &v);
                let q = d256.map(&Mpfr256::from_f64(u), &Mpfr256::from_f64(v));
                let err = (p.x - q.x.to_f64()).hypot(p.y - q.y.to_f64());
                assert!(err <= 4.0 * f64::EPSILON, "({u},{v}): {err:e}");
            }
        }
    }
}
