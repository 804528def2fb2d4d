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
    let one = T::one();
    let two = T::from_i64(2);
    let num = u.clone() * &two - &one;
    let root = if *u < T::from_ratio(1, 2) {
        (u.clone() * &two).sqrt()
    } else {
        ((one.clone() - u) * &two).sqrt()
    };
    num / &(one + &root)
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
    /// `2⁻⁶⁴` from the edges `|x| = 1`, where the 256-bit coordinate carries
    /// `1 − |x|` (the density) to only 2⁻¹⁹² relative: the deviation there is
    /// ≈ 3·10⁻⁵⁹, a limit of the representation of the point, not of the map.
    #[cfg(feature = "mpfr")]
    #[test]
    fn tent_harness_at_extremes() {
        crate::shapes::test_support::harness_passes_within("tent", &Tent::<f64>::new(), 4.0, 1e-57);
    }
}
