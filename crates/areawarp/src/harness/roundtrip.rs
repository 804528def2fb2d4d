//! The round-trip check: `ψ⁻¹(ψ(u, v)) = (u, v)` in a scalar `T`.
//!
//! For each input rounded to `T`, the map and then its inverse are evaluated
//! in `T`, and the parameter error `max(|u − u'|, |v − v'|)` is measured
//! (absolute: the inputs live in `[0, 1]`). This checks that
//! [`Warp::inverse`] really inverts [`Warp::map`] — as used for MIS weights,
//! path guiding or re-projection of stored samples.
//!
//! The parameter error is not small everywhere, for legitimate reasons: where
//! the map is not injective (the whole edge `u = 0` of a polar map goes to the
//! centre, `v = 0` and `v = 1` meet at a seam) the inverse returns one of the
//! preimages, and where the map contracts strongly (`z = u^(1/(k+1))` for a
//! large Phong exponent near the pole) a point rounded to `T` no longer
//! determines `u` to `T`'s precision. The report therefore also gives the
//! *image* error `‖ψ(ψ⁻¹(p)) − p‖_∞ / extent / u_T` with `p = ψ(u, v)`, in
//! units of `T`'s roundoff, which is small for a correct inverse at every
//! point, seams and poles included.

use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Coords;
use crate::warp::{Warp, WarpFamily};

/// The outcome of a round-trip check.
#[derive(Clone, Debug)]
pub struct RoundTripReport {
    /// The warp's [`WarpFamily::name`].
    pub warp: String,
    /// The scalar the round trip was evaluated in.
    pub scalar: String,
    /// Number of points evaluated.
    pub points: usize,
    /// `max |(u, v) − ψ⁻¹(ψ(u, v))|_∞` over the points with a finite inverse.
    pub max_error: f64,
    /// The median of the same error.
    pub median_error: f64,
    /// The input `(u, v)` where the maximal parameter error occurs.
    pub worst: Option<(f64, f64)>,
    /// `max ‖ψ(ψ⁻¹(p)) − p‖_∞ / extent` in units of `T`'s roundoff, `p = ψ(u, v)`.
    pub max_image_ulps: f64,
    /// The median of the image error, in the same units.
    pub median_image_ulps: f64,
    /// The input `(u, v)` where the maximal image error occurs.
    pub worst_image: Option<(f64, f64)>,
    /// Points where the inverse refused the point or returned non-finite coordinates,
    /// or the map itself was not finite.
    pub failures: usize,
    /// The first such point, if any.
    pub first_failure: Option<(f64, f64)>,
}

impl RoundTripReport {
    /// `true` when no inverse failed, the maximal parameter error is at most
    /// `max_error` and the maximal image error at most `max_image_ulps`.
    pub fn passes(&self, max_error: f64, max_image_ulps: f64) -> bool {
        self.failures == 0 && self.max_error <= max_error && self.max_image_ulps <= max_image_ulps
    }
}

/// Evaluates `ψ⁻¹(ψ(u, v))` in `T` on `points` (see the
/// [module documentation](self)).
///
/// Inputs are rounded to `T`; the errors are measured against the rounded
/// inputs.
///
/// # Errors
/// The error of [`WarpFamily::at`] if the warp cannot be rebuilt in `T`.
///
/// # Example
/// ```
/// use areawarp::harness::{extremes::extremes_grid, roundtrip::check_roundtrip};
/// use areawarp::shapes::PolarDisk;
///
/// let report = check_roundtrip::<f64, _>(&PolarDisk::<f64>::new(), &extremes_grid())?;
/// assert_eq!(report.failures, 0);
/// assert!(report.max_image_ulps <= 16.0, "{report:?}");
/// // (0, v) all map to the centre: v cannot come back, the image does.
/// assert!(report.max_error > 0.5);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn check_roundtrip<T: Real, W: WarpFamily<f64>>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<RoundTripReport, WarpError> {
    let wt = w.at::<T>()?;
    let unit = T::unit_roundoff() * &wt.extent();
    let mut errors = Vec::with_capacity(points.len());
    let mut image_errors = Vec::with_capacity(points.len());
    let (mut max_err, mut worst) = (None::<T>, None);
    let (mut max_img, mut worst_image) = (None::<T>, None);
    let mut failures = 0;
    let mut first_failure = None;
    for &(u, v) in points {
        let (ut, vt) = (T::from_f64(u), T::from_f64(v));
        let p = wt.map(&ut, &vt);
        let p3 = p.to_vec3();
        let inverse = if p3.is_finite() {
            wt.inverse(&p).ok()
        } else {
            None
        };
        let (ui, vi) = match inverse {
            Some([a, b]) if a.is_finite() && b.is_finite() => (a, b),
            _ => {
                failures += 1;
                first_failure.get_or_insert((u, v));
                continue;
            }
        };
        let err = (ut - &ui).abs().max(&(vt - &vi).abs());
        let q = wt.map(&ui, &vi).to_vec3();
        // A non-finite re-evaluation yields a NaN image error, recorded as ∞.
        let img = q.sub(&p3).max_abs() / &unit;
        let img = if img.is_finite() { img } else { T::max_value() };
        errors.push(err.to_f64());
        image_errors.push(img.to_f64());
        if max_err.as_ref().is_none_or(|m| err > *m) {
            max_err = Some(err);
            worst = Some((u, v));
        }
        if max_img.as_ref().is_none_or(|m| img > *m) {
            max_img = Some(img);
            worst_image = Some((u, v));
        }
    }
    Ok(RoundTripReport {
        warp: w.name(),
        scalar: T::type_name(),
        points: points.len(),
        max_error: max_err.map_or(0.0, |m| m.to_f64()),
        median_error: super::median(&mut errors),
        worst,
        max_image_ulps: max_img.map_or(0.0, |m| m.to_f64()),
        median_image_ulps: super::median(&mut image_errors),
        worst_image,
        failures,
        first_failure,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::{extremes_grid, random_points};
    use crate::harness::test_warps::{Parallelogram, TestDisk, TestSphere};
    use crate::vector::Vec3;
    use crate::warp::InverseError;

    #[test]
    fn affine_round_trip_is_tight() {
        let w = Parallelogram::new(
            Vec3::<f64>::new(0.0, 0.0, 0.0),
            Vec3::<f64>::new(1.0, 0.0, 0.0),
            Vec3::<f64>::new(0.5, 1.0, 0.0),
        )
        .unwrap();
        let r = check_roundtrip::<f64, _>(&w, &random_points(200, 5)).unwrap();
        assert!(r.passes(1e-15, 4.0), "{r:?}");
        assert_eq!(r.points, 200);
    }

    #[test]
    fn polar_seams_show_in_parameters_not_in_image() {
        let w = TestDisk::<f64>::correct();
        let r = check_roundtrip::<f64, _>(&w, &extremes_grid()).unwrap();
        assert_eq!(r.failures, 0);
        // v = 1 comes back as v = 0 (or (0, v) as (0, 0)): parameter error ~1.
        assert!(r.max_error > 0.5, "{r:?}");
        assert!(r.max_image_ulps <= 8.0, "{r:?}");
        let s = check_roundtrip::<f32, _>(&TestSphere::<f64>::new(false), &random_points(100, 9))
            .unwrap();
        assert!(s.passes(1e-5, 16.0), "{s:?}");
    }

    #[test]
    fn wrong_inverse_is_detected() {
        // The disk map with the inverse of the wrong radial law.
        #[derive(Clone, Debug)]
        struct Mismatched;
        impl<T: Real> Warp<T> for Mismatched {
            type Point = crate::vector::Vec2<T>;
            fn map(&self, u: &T, v: &T) -> Self::Point {
                TestDisk::<T>::correct().map(u, v)
            }
            fn pdf_unchecked(&self, p: &Self::Point) -> T {
                TestDisk::<T>::correct().pdf(p)
            }
            fn measure(&self) -> T {
                T::pi()
            }
            fn inverse(&self, p: &Self::Point) -> Result<[T; 2], InverseError> {
                if p.x > T::zero() {
                    TestDisk::<T>::wrong().inverse(p)
                } else {
                    Err(InverseError::OffShape { distance: 0.0 })
                }
            }
            fn outside_by(&self, _p: &Self::Point) -> T {
                T::zero()
            }
        }
        impl<T: Real> WarpFamily<T> for Mismatched {
            type At<S: Real> = Mismatched;
            fn at<S: Real>(&self) -> Result<Mismatched, WarpError> {
                Ok(Mismatched)
            }
            fn name(&self) -> String {
                "mismatched".into()
            }
        }
        let r = check_roundtrip::<f64, _>(&Mismatched, &random_points(100, 4)).unwrap();
        assert!(r.failures > 20 && r.failures < 80, "{r:?}");
        assert!(r.first_failure.is_some());
        assert!(r.max_error > 0.1 && r.max_image_ulps > 1e6, "{r:?}");
    }
}
