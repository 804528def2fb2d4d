//! The tent (separable triangle) density on `[−1, 1]²`, density
//! `(1 − |x|)(1 − |y|)`. Derivation: `docs/planar-densities.md`.

use super::turns::clamp_unit;
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec2;
use crate::warp::{InverseError, Warp, WarpFamily};

/// The inverse CDF of the 1-D tent `1 − |x|` on [−1, 1]:
/// `x = −1 + √(2u)` for `u < 1/2`, `1 − √(2(1 − u))` above, evaluated as
/// `(2u − 1)/(1 + √(2u))` and `(2u − 1)/(1 + √(2(1 − u)))` (`2u − 1` is
/// exact near the centre, so `x ≈ 0` keeps its relative accuracy).
pub(crate) fn tent_inverse_cdf<T: Real>(u: &T) -> T {
    tent_inverse_cdf_with_density(u).0
}

/// [`tent_inverse_cdf`] and the 1-D density `1 − |x|` at its result, taken
/// from the square root itself (`1 − |x| = √(2u)` below the centre and
/// `√(2(1 − u))` above) rather than recomputed from `x`: next to the edges
/// `x` carries `1 − |x|` only to the absolute rounding of `x`, the root to
/// full relative accuracy.
pub(crate) fn tent_inverse_cdf_with_density<T: Real>(u: &T) -> (T, T) {
    let one = T::one();
    let two = T::from_i64(2);
    let num = u.clone() * &two - &one;
    let root = if *u < T::from_ratio(1, 2) {
        (u.clone() * &two).sqrt()
    } else {
        ((one.clone() - u) * &two).sqrt()
    };
    (num / &(one + &root), root)
}

/// The CDF of the 1-D tent: `(1 + x)²/2` for `x ≤ 0`, `1 − (1 − x)²/2` above.
pub(crate) fn tent_cdf<T: Real>(x: &T) -> T {
    let one = T::one();
    let two = T::from_i64(2);
    if *x <= T::zero() {
        (one + x).square() / &two
    } else {
        one.clone() - &((one - x).square() / &two)
    }
}

/// Points of `[−1, 1]²` with the tent density `(1 − |x|)(1 − |y|)`
/// (Mitsuba's `square_to_tent`): `x` from `u`, `y` from `v`, each by the
/// inverse CDF of the 1-D tent. `(1/2, 1/2)` is the centre, the edges of
/// the unit square map onto the edges of `[−1, 1]²`.
///
/// # Density
/// `(1 − |x|)(1 − |y|)` (area measure, 0 outside), `measure() = 1`.
///
/// # Example
/// ```
/// use areawarp::shapes::Tent;
/// use areawarp::{Vec2, Warp};
/// let t = Tent::<f64>::new();
/// assert_eq!(t.map(&0.5, &0.5), Vec2::new(0.0, 0.0));
/// assert_eq!(t.map(&0.0, &1.0), Vec2::new(-1.0, 1.0));
/// assert_eq!(t.pdf(&Vec2::new(0.5, 0.0)), 0.5);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Tent<T> {
    _scalar: core::marker::PhantomData<T>,
}

impl<T: Real> Tent<T> {
    /// The tent on `[−1, 1]²`.
    ///
    /// # Density
    /// `(1 − |x|)(1 − |y|)`.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Tent;
    /// use areawarp::Warp;
    /// assert_eq!(Tent::<f32>::new().measure(), 1.0);
    /// ```
    pub fn new() -> Self {
        Tent {
            _scalar: core::marker::PhantomData,
        }
    }
}

impl<T: Real> Warp<T> for Tent<T> {
    type Point = Vec2<T>;

    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        Vec2::new(
            tent_inverse_cdf(&clamp_unit(u)),
            tent_inverse_cdf(&clamp_unit(v)),
        )
    }

    /// The density from the two roots of the inverse CDFs (see
    /// `tent_inverse_cdf_with_density`): full relative accuracy next to
    /// the edges, where `pdf_unchecked(map(u, v))` keeps only the absolute
    /// accuracy of the point.
    fn map_with_pdf(&self, u: &T, v: &T) -> (Vec2<T>, T) {
        let (x, dx) = tent_inverse_cdf_with_density(&clamp_unit(u));
        let (y, dy) = tent_inverse_cdf_with_density(&clamp_unit(v));
        (Vec2::new(x, y), dx * &dy)
    }

    fn pdf_unchecked(&self, p: &Vec2<T>) -> T {
        let one = T::one();
        (one.clone() - &p.x.abs()) * &(one - &p.y.abs())
    }

    fn measure(&self) -> T {
        T::one()
    }

    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &(T::unit_roundoff() * &T::from_i64(4)))?;
        let one = T::one();
        let (x, y) = (
            p.x.clamp(&-one.clone(), &one),
            p.y.clamp(&-one.clone(), &one),
        );
        Ok([clamp_unit(&tent_cdf(&x)), clamp_unit(&tent_cdf(&y))])
    }

    fn outside_by(&self, p: &Vec2<T>) -> T {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return T::max_value();
        }
        let one = T::one();
        (p.x.abs() - &one).max(&(p.y.abs() - &one)).max(&T::zero())
    }
}

impl<T: Real> WarpFamily<T> for Tent<T> {
    type At<S: Real> = Tent<S>;
    fn at<S: Real>(&self) -> Result<Tent<S>, WarpError> {
        Ok(Tent::new())
    }
    fn name(&self) -> String {
        "tent".to_string()
    }
}

crate::warp::distribution_for_floats!(Tent, Vec2);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{GridBins, chi2_passes, roundtrip_passes};

    #[test]
    fn tent_edges_centre_and_chi2() {
        let t = Tent::<f64>::new();
        for &u in &EXTREMES {
            for &v in &EXTREMES {
                let p = t.map(&u, &v);
                assert!(t.outside_by(&p) == 0.0 && p.x.is_finite(), "{u} {v}");
            }
        }
        // Near the centre x ≈ u − 1/2 to full relative accuracy.
        let x = t.map(&(0.5 + 2f64.powi(-40)), &0.5).x;
        assert!((x / 2f64.powi(-40) - 1.0).abs() < 1e-11, "{x}");
        roundtrip_passes::<f64, _>("tent", &t, 8.0);
        roundtrip_passes::<f32, _>("tent", &t, 8.0);
        let e = GridBins::uniform_edges(-1.0, 1.0, 12);
        let bins = GridBins::new(e.clone(), e, |x, y| t.pdf(&Vec2::new(x, y)));
        chi2_passes("tent", &t, &bins, 200_000);
    }

    /// The Jacobian check nudges the corners by 2⁻¹²⁸, i.e. to points
    /// `2⁻⁶⁴` from the edges `|x| = 1`. There the 256-bit coordinate carries
    /// `1 − |x|` to only 2⁻¹⁹² relative (`pdf(map(u, v))` deviates by
    /// ≈ 3·10⁻⁵⁹), while the sample's own density, taken from the roots,
    /// keeps full precision: the check holds to 10⁻⁶⁰ like every other warp.
    #[cfg(feature = "mpfr")]
    #[test]
    fn tent_harness_at_extremes() {
        crate::shapes::test_support::harness_passes_within("tent", &Tent::<f64>::new(), 4.0, 1e-60);
    }

    #[test]
    fn tent_sample_density_agrees_with_pdf() {
        let t = Tent::<f64>::new();
        for &u in &EXTREMES {
            for &v in &EXTREMES {
                let (p, pdf) = t.map_with_pdf(&u, &v);
                assert_eq!(p, t.map(&u, &v));
                assert!((pdf - t.pdf(&p)).abs() <= 4.0 * f64::EPSILON, "{u} {v}");
            }
        }
        assert!(t.map_with_pdf(&f64::NAN, &0.5).1.is_nan());
    }
}
