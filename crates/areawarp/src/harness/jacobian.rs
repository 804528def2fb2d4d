//! The Jacobian check: `|ψ_u × ψ_v| · pdf(ψ(u, v)) = 1`, evaluated with exact
//! partial derivatives (forward-mode dual numbers) at 256 bits.
//!
//! The density is the one the sample carries ([`Warp::map_with_pdf`], what
//! [`Warp::sample_uv`] returns and a renderer divides by); the contract test
//! ties it to [`Warp::pdf`] at the same point.
//!
//! A warp is area-preserving (measure-preserving, for weighted targets) exactly
//! when its area element `J = |ψ_u × ψ_v|` is the reciprocal of the density it
//! claims: `J · pdf = 1` at every point. Evaluating `ψ` over
//! [`Dual2<Mpfr256>`](crate::real::Dual2) gives `ψ` and both partials rounded
//! only at 256 bits, so for a correct map the deviation is of the order of
//! `2^-256 ≈ 10^-77` times a modest condition number, while a map with the
//! wrong radial law, a missing factor or a typo in a constant deviates by
//! `O(1)`. A loose bound such as `10^-60` therefore separates the two cases
//! with no ambiguity, which a finite-difference check in `f64` cannot do.
//!
//! For planar warps the point is embedded with `z = 0`, so `J = |det Dψ|`.
//!
//! # Singular edges
//! Closed forms have derivative singularities on edges of the square (`√u` at
//! `u = 0`, a pole at the end of `z = 1 − 2u`): there `J` or `pdf` is
//! infinite, zero or NaN and `J · pdf` is undefined. Such points are
//! re-evaluated nudged into the interior by `δ = 2^-(p/2)` in each coordinate
//! (towards `1/2`; `p` the precision, so `δ = 2^-128` at 256 bits) and counted
//! in [`JacobianReport::nudged`]. Points still not finite after the nudge are
//! counted in [`JacobianReport::non_finite`], a failure.

use crate::error::WarpError;
use crate::real::{Dual2, Real};
use crate::vector::{Coords, Vec3};
use crate::warp::{Warp, WarpFamily};

/// The outcome of a Jacobian check.
#[derive(Clone, Debug)]
pub struct JacobianReport {
    /// The warp's [`WarpFamily::name`].
    pub warp: String,
    /// The scalar the partials were computed in, e.g. `dual<mpfr:256>`.
    pub scalar: String,
    /// Number of points evaluated (including nudged and non-finite ones).
    pub points: usize,
    /// `max |J · pdf − 1|` over the points with a finite value.
    pub max_rel_deviation: f64,
    /// The input `(u, v)` (before any nudge) where the maximum occurs.
    pub worst: Option<(f64, f64)>,
    /// `J · pdf` at [`JacobianReport::worst`].
    pub worst_value: f64,
    /// Points whose value was not finite and that were re-evaluated nudged
    /// into the interior by [`JacobianReport::nudge`].
    pub nudged: usize,
    /// The nudge distance `2^-(p/2)` per coordinate.
    pub nudge: f64,
    /// Points whose value was still not finite after the nudge (failures).
    pub non_finite: usize,
    /// The first such point, if any.
    pub first_non_finite: Option<(f64, f64)>,
}

impl JacobianReport {
    /// `true` when every point gave a finite value and the maximal deviation
    /// is at most `bound`.
    pub fn passes(&self, bound: f64) -> bool {
        self.non_finite == 0 && self.max_rel_deviation <= bound
    }
}

/// Checks `|ψ_u × ψ_v| · pdf(ψ) = 1` at 256 bits on `points`
/// (see the [module documentation](self)).
///
/// Builds `w.at::<Dual2<Mpfr256>>()`; inputs are converted exactly.
///
/// # Errors
/// The error of [`WarpFamily::at`] if the warp cannot be rebuilt at 256 bits.
///
/// # Example
/// ```
/// use areawarp::harness::{extremes::extremes_grid, jacobian::check_jacobian};
/// use areawarp::shapes::PolarDisk;
///
/// let report = check_jacobian(&PolarDisk::<f64>::new(), &extremes_grid())?;
/// assert!(report.passes(1e-60), "{report:?}");
/// assert_eq!(report.nudged, 8); // the edge u = 0, where √u is singular
/// # Ok::<(), areawarp::WarpError>(())
/// ```
#[cfg(feature = "mpfr")]
pub fn check_jacobian<W: WarpFamily<f64>>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<JacobianReport, WarpError> {
    check_jacobian_in::<crate::real::Mpfr256, W>(w, points)
}

/// `check_jacobian` (feature `mpfr`) with the partials computed over `Dual2<R>` instead of
/// `Dual2<Mpfr256>`: e.g. `R = f64` without MPFR (deviations of a correct
/// map are then of the order of `f64`'s roundoff times the map's condition,
/// not `10^-77`).
///
/// Inputs are converted with [`Real::from_f64`] (exact for `f64` and MPFR,
/// rounded for `f32`); the nudge is `2^-(p/2)` with `p = R::precision()`.
///
/// # Errors
/// The error of [`WarpFamily::at`] if the warp cannot be rebuilt over `Dual2<R>`.
///
/// # Example
/// ```
/// use areawarp::harness::{extremes::random_points, jacobian::check_jacobian_in};
/// use areawarp::shapes::Sphere;
///
/// let report = check_jacobian_in::<f64, _>(&Sphere::<f64>::new(), &random_points(100, 1))?;
/// assert!(report.passes(1e-13), "{report:?}");
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn check_jacobian_in<R: Real, W: WarpFamily<f64>>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<JacobianReport, WarpError> {
    let wd = w.at::<Dual2<R>>()?;
    let delta = R::exp2i(-((R::precision() / 2) as i32));
    let half = R::from_ratio(1, 2);
    let towards_centre = |x: R| -> R { if x < half { x + &delta } else { x - &delta } };

    let mut max_dev: Option<R> = None;
    let mut worst = None;
    let mut worst_value = f64::NAN;
    let mut nudged = 0;
    let mut non_finite = 0;
    let mut first_non_finite = None;
    for &(u, v) in points {
        let (ur, vr) = (R::from_f64(u), R::from_f64(v));
        let value = match jacobian_times_pdf(&wd, &ur, &vr) {
            Some(x) => x,
            None => {
                nudged += 1;
                match jacobian_times_pdf(&wd, &towards_centre(ur), &towards_centre(vr)) {
                    Some(x) => x,
                    None => {
                        non_finite += 1;
                        first_non_finite.get_or_insert((u, v));
                        continue;
                    }
                }
            }
        };
        let dev = (value.clone() - &R::one()).abs();
        if max_dev.as_ref().is_none_or(|m| dev > *m) {
            max_dev = Some(dev);
            worst = Some((u, v));
            worst_value = value.to_f64();
        }
    }
    Ok(JacobianReport {
        warp: w.name(),
        scalar: Dual2::<R>::type_name(),
        points: points.len(),
        max_rel_deviation: max_dev.map_or(0.0, |m| m.to_f64()),
        worst,
        worst_value,
        nudged,
        nudge: delta.to_f64(),
        non_finite,
        first_non_finite,
    })
}

/// `|ψ_u × ψ_v| · pdf(ψ(u, v))` over dual numbers, or `None` if the point, its
/// partials or the product is not finite.
fn jacobian_times_pdf<R: Real, WD: Warp<Dual2<R>>>(wd: &WD, u: &R, v: &R) -> Option<R> {
    let (p, pdf) = wd.map_with_pdf(&Dual2::seed_u(u.clone()), &Dual2::seed_v(v.clone()));
    let q = p.to_vec3();
    if !q.is_finite() {
        return None;
    }
    let pu = Vec3::new(q.x.du.clone(), q.y.du.clone(), q.z.du.clone());
    let pv = Vec3::new(q.x.dv, q.y.dv, q.z.dv);
    let value = pu.cross(&pv).norm() * &pdf.re;
    value.is_finite().then_some(value)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::{extremes_grid, random_points};
    use crate::harness::test_warps::{Parallelogram, TestDisk, TestLobe, TestSphere};

    #[test]
    fn affine_map_has_constant_jacobian_in_f64() {
        let w = Parallelogram::new(
            Vec3::from_f64(1.0, 2.0, 3.0),
            Vec3::from_f64(2.0, 0.5, 0.0),
            Vec3::from_f64(-0.25, 3.0, 1.0),
        )
        .unwrap();
        let r = check_jacobian_in::<f64, _>(&w, &extremes_grid()).unwrap();
        assert_eq!(r.points, 64);
        assert_eq!(r.nudged, 0);
        assert!(r.passes(1e-14), "{r:?}");
        assert_eq!(r.scalar, "dual<f64>");
    }

    #[test]
    fn singular_edges_are_nudged_not_failed() {
        let w = TestDisk::<f64>::correct();
        let r = check_jacobian_in::<f64, _>(&w, &extremes_grid()).unwrap();
        // u = 0: √u has an infinite derivative; 8 such points.
        assert_eq!(r.nudged, 8, "{r:?}");
        assert_eq!(r.non_finite, 0);
        assert_eq!(r.nudge, 2f64.powi(-26));
        assert!(r.passes(1e-12), "{r:?}");
    }

    #[test]
    fn wrong_radial_law_fails() {
        // r = u instead of √u: J·pdf = 2u, far from 1 away from u = 1/2.
        let w = TestDisk::<f64>::wrong();
        let r = check_jacobian_in::<f64, _>(&w, &random_points(50, 1)).unwrap();
        assert!(!r.passes(1e-3), "{r:?}");
        assert!(r.max_rel_deviation > 0.5, "{r:?}");
        let (u, _) = r.worst.unwrap();
        assert!((r.worst_value - 2.0 * u).abs() < 1e-12, "{r:?}");
    }

    #[test]
    fn weighted_lobe_and_sphere_pass_in_f64() {
        for k in [0.0, 1.0, 7.5] {
            let w = TestLobe::new(k);
            let r = check_jacobian_in::<f64, _>(&w, &random_points(64, 2)).unwrap();
            assert!(r.passes(1e-12), "k = {k}: {r:?}");
        }
        let r = check_jacobian_in::<f64, _>(&TestSphere::new(false), &extremes_grid()).unwrap();
        assert!(r.non_finite == 0 && r.nudged > 0, "{r:?}");
        let bad = check_jacobian_in::<f64, _>(&TestSphere::new(true), &extremes_grid()).unwrap();
        assert!(!bad.passes(1e-3), "{bad:?}");
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn check_at_256_bits_is_exact_to_many_digits() {
        let w = TestDisk::<f64>::correct();
        let r = check_jacobian(&w, &extremes_grid()).unwrap();
        assert_eq!(r.scalar, "dual<mpfr:256>");
        assert_eq!(r.nudged, 8);
        assert!(r.passes(1e-70), "{r:?}");
        let s = check_jacobian(&TestSphere::new(false), &extremes_grid()).unwrap();
        assert!(s.passes(1e-70), "{s:?}");
        let bad = check_jacobian(&TestDisk::<f64>::wrong(), &extremes_grid()).unwrap();
        assert!(bad.max_rel_deviation > 0.9, "{bad:?}");
    }

    #[test]
    fn no_points_gives_an_empty_report() {
        let r = check_jacobian_in::<f64, _>(&TestDisk::<f64>::correct(), &[]).unwrap();
        assert_eq!(r.points, 0);
        assert!(r.worst.is_none());
        assert_eq!(r.max_rel_deviation, 0.0);
    }
}
