//! The precision check: how far the map evaluated in a hardware scalar `T`
//! (`f32`, `f64`) lands from the same map evaluated at 256 bits, in units of
//! `T`'s unit roundoff.
//!
//! The reference is `w.at::<T>()?.at::<Mpfr256>()`: the shape *exactly as `T`
//! sees it* (parameters first rounded to `T`), evaluated at the inputs rounded
//! to `T` and converted exactly. The measured error is therefore the error of
//! the evaluation alone, not of rounding the shape's parameters or the
//! inputs, and a well-conditioned, carefully written closed form stays within
//! a few units: the error is
//!
//! `‖ψ_T(u, v) − ψ_ref(u, v)‖_∞ / extent / u_T`,
//!
//! with `u_T = 2^-p` ([`Real::unit_roundoff`]) and `extent` the shape's
//! characteristic length ([`Warp::extent`]). A map that loses digits to
//! cancellation near an edge (`1 − z` for `z ≈ 1`, `√(1 − z²)` at a pole)
//! shows up as thousands or millions of units at the extreme inputs.
//!
//! The check also counts points where `T` produced NaN or infinity, and
//! points the reference shape reports as lying outside it
//! ([`Warp::outside_by`]) by more than [`OUTSIDE_TOLERANCE_ULPS`]` · u_T · extent`.

use crate::error::WarpError;
use crate::real::{Real, convert};
use crate::vector::{Coords, Vec3};
use crate::warp::{Warp, WarpFamily};

/// A point counts as outside the shape when [`Warp::outside_by`] exceeds this
/// many units of roundoff of `T`, times the shape's extent: the tolerance is
/// `4 · u_T · extent`. A correctly rounded evaluation misses the exact
/// surface by about `1/2` to `2` units in each coordinate.
pub const OUTSIDE_TOLERANCE_ULPS: f64 = 4.0;

/// The outcome of a precision check.
#[derive(Clone, Debug)]
pub struct PrecisionReport {
    /// The warp's [`WarpFamily::name`].
    pub warp: String,
    /// The scalar under test, e.g. `f32`.
    pub scalar: String,
    /// The reference scalar, e.g. `mpfr:256`.
    pub reference: String,
    /// Number of points evaluated.
    pub points: usize,
    /// Maximal error, in units of `T`'s roundoff (relative to the extent),
    /// over the points where both evaluations are finite.
    pub max_ulps: f64,
    /// Median error in the same units.
    pub median_ulps: f64,
    /// The input `(u, v)` with the maximal error.
    pub worst: Option<(f64, f64)>,
    /// Points where the map in `T` returned NaN or infinite coordinates.
    pub non_finite: usize,
    /// Points where the reference returned NaN or infinite coordinates (a
    /// bug of the map itself, not of `T`'s precision).
    pub reference_non_finite: usize,
    /// Points farther outside the shape than the tolerance
    /// ([`OUTSIDE_TOLERANCE_ULPS`]).
    pub outside: usize,
    /// Maximal [`Warp::outside_by`] over the points, in units of
    /// `u_T · extent`.
    pub max_outside_ulps: f64,
}

impl PrecisionReport {
    /// `true` when every point is finite (in `T` and the reference), none is
    /// outside the shape, and the maximal error is at most `max_ulps`.
    pub fn passes(&self, max_ulps: f64) -> bool {
        self.non_finite == 0
            && self.reference_non_finite == 0
            && self.outside == 0
            && self.max_ulps <= max_ulps
    }
}

/// Measures the map in `T` against 256 bits on `points` (see the
/// [module documentation](self)).
///
/// # Errors
/// The error of [`WarpFamily::at`] if the warp cannot be rebuilt in `T` or at
/// 256 bits.
///
/// # Example
/// ```
/// use areawarp::harness::{extremes::extremes_grid, precision::check_precision};
/// use areawarp::shapes::Sphere;
///
/// let report = check_precision::<f32, _>(&Sphere::<f64>::new(), &extremes_grid())?;
/// assert!(report.passes(16.0), "{report:?}");
/// # Ok::<(), areawarp::WarpError>(())
/// ```
#[cfg(feature = "mpfr")]
pub fn check_precision<T: Real, W: WarpFamily<f64>>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<PrecisionReport, WarpError> {
    check_precision_against::<T, crate::real::Mpfr256, W>(w, points)
}

/// `check_precision` (feature `mpfr`) with another reference scalar `R` (which should be
/// much more precise than `T`): e.g. `T = f32`, `R = f64` without MPFR.
///
/// # Errors
/// The error of [`WarpFamily::at`] if the warp cannot be rebuilt in `T` or `R`.
///
/// # Example
/// ```
/// use areawarp::harness::{extremes::extremes_grid, precision::check_precision_against};
/// use areawarp::shapes::ConcentricDisk;
///
/// let w = ConcentricDisk::<f64>::new();
/// let report = check_precision_against::<f32, f64, _>(&w, &extremes_grid())?;
/// assert!(report.passes(16.0), "{report:?}");
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn check_precision_against<T: Real, R: Real, W: WarpFamily<f64>>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<PrecisionReport, WarpError> {
    let wt = w.at::<T>()?;
    let wr = wt.at::<R>()?;
    let unit = R::exp2i(-(T::precision() as i32)) * &wr.extent();
    let mut errors = Vec::with_capacity(points.len());
    let mut max_err: Option<R> = None;
    let mut worst = None;
    let mut non_finite = 0;
    let mut reference_non_finite = 0;
    let mut outside = 0;
    let mut max_outside = R::zero();
    let tolerance = R::from_i64(OUTSIDE_TOLERANCE_ULPS as i64);
    for &(u, v) in points {
        let (ut, vt) = (T::from_f64(u), T::from_f64(v));
        let (ur, vr): (R, R) = (convert(&ut), convert(&vt));
        let reference = wr.map(&ur, &vr).to_vec3();
        let pt = wt.map(&ut, &vt).to_vec3();
        if !reference.is_finite() {
            reference_non_finite += 1;
            continue;
        }
        if !pt.is_finite() {
            non_finite += 1;
            continue;
        }
        let p: Vec3<R> = pt.convert();
        let err = p.sub(&reference).max_abs() / &unit;
        let out = outside_by(&wr, p) / &unit;
        if out > tolerance {
            outside += 1;
        }
        if out > max_outside {
            max_outside = out;
        }
        errors.push(err.to_f64());
        if max_err.as_ref().is_none_or(|m| err > *m) {
            max_err = Some(err);
            worst = Some((u, v));
        }
    }
    Ok(PrecisionReport {
        warp: w.name(),
        scalar: T::type_name(),
        reference: R::type_name(),
        points: points.len(),
        max_ulps: max_err.map_or(0.0, |m| m.to_f64()),
        median_ulps: super::median(&mut errors),
        worst,
        non_finite,
        reference_non_finite,
        outside,
        max_outside_ulps: max_outside.to_f64(),
    })
}

fn outside_by<R: Real, WR: Warp<R>>(wr: &WR, p: Vec3<R>) -> R {
    wr.outside_by(&<WR::Point as Coords<R>>::from_vec3(p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::{extremes_grid, random_points};
    use crate::harness::test_warps::{Parallelogram, TestDisk, TestLobe, TestSphere};
    use crate::warp::InverseError;

    #[test]
    fn f32_against_f64_reference() {
        let w = TestDisk::<f64>::correct();
        let r = check_precision_against::<f32, f64, _>(&w, &extremes_grid()).unwrap();
        assert_eq!((r.scalar.as_str(), r.reference.as_str()), ("f32", "f64"));
        assert_eq!(r.points, 64);
        // 2πv with π rounded to f32 costs a few units near v = 1.
        assert!(r.passes(8.0), "{r:?}");
        assert!(r.max_ulps > 0.0, "{r:?}");
    }

    #[test]
    fn parameters_are_rounded_before_the_reference() {
        // 0.1 is not an f32: the reference must use the f32 shape, so the
        // error stays at the level of the evaluation.
        let w = Parallelogram::new(
            Vec3::<f64>::new(0.1, 0.2, 0.3),
            Vec3::<f64>::new(1.1, 0.0, 0.0),
            Vec3::<f64>::new(0.0, 0.7, 0.3),
        )
        .unwrap();
        let r = check_precision_against::<f32, f64, _>(&w, &random_points(200, 3)).unwrap();
        assert!(r.passes(4.0), "{r:?}");
    }

    #[test]
    fn cancellation_is_detected() {
        // The lobe evaluates √(1 − z²) with z close to 1 at u → 1: f32
        // loses digits there. The sphere's closed form 2√(u(1−u)) does not.
        let lobe = TestLobe::new(3.0);
        let r = check_precision_against::<f32, f64, _>(&lobe, &extremes_grid()).unwrap();
        assert!(r.max_ulps > 100.0, "{r:?}");
        assert!(!r.passes(16.0));
        let sphere = TestSphere::<f64>::new(false);
        let s = check_precision_against::<f32, f64, _>(&sphere, &extremes_grid()).unwrap();
        assert!(s.passes(8.0), "{s:?}");
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn f64_against_256_bits() {
        let w = TestSphere::<f64>::new(false);
        let r = check_precision::<f64, _>(&w, &extremes_grid()).unwrap();
        assert_eq!(r.reference, "mpfr:256");
        assert!(r.passes(8.0), "{r:?}");
        assert_eq!(r.non_finite + r.reference_non_finite + r.outside, 0);
    }

    #[test]
    fn outside_points_are_counted() {
        /// The unit disk scaled by 1 + 2^-10: every rim point is outside.
        #[derive(Clone, Debug)]
        struct Bulging;
        impl<T: Real> Warp<T> for Bulging {
            type Point = crate::vector::Vec2<T>;
            fn map(&self, u: &T, v: &T) -> Self::Point {
                let p = TestDisk::<T>::correct().map(u, v);
                p.scale(&(T::one() + &T::exp2i(-10)))
            }
            fn pdf_unchecked(&self, _p: &Self::Point) -> T {
                T::one() / &T::pi()
            }
            fn measure(&self) -> T {
                T::pi()
            }
            fn inverse(&self, _p: &Self::Point) -> Result<[T; 2], InverseError> {
                Err(InverseError::NonFinite)
            }
            fn outside_by(&self, p: &Self::Point) -> T {
                TestDisk::<T>::correct().outside_by(p)
            }
        }
        impl<T: Real> WarpFamily<T> for Bulging {
            type At<S: Real> = Bulging;
            fn at<S: Real>(&self) -> Result<Bulging, WarpError> {
                Ok(Bulging)
            }
            fn name(&self) -> String {
                "bulging".into()
            }
        }
        let r = check_precision_against::<f32, f64, _>(&Bulging, &extremes_grid()).unwrap();
        // u = 1 and u = 1 − 1e-12 (= 1 in f32) and u = 1 − 1e-6: 24 points
        // lie farther than 4 units outside.
        assert_eq!(r.outside, 24, "{r:?}");
        assert!(!r.passes(1e9));
        assert!(r.max_outside_ulps > 1e4);
    }
}
