//! The condition of a map: how far the *exact* map moves when one of its
//! inputs changes by one unit in the last place.
//!
//! A map evaluated in `f64` cannot be more accurate than its inputs allow:
//! the shape's parameters and `(u, v)` are themselves `f64` numbers, known
//! only to within half an ulp, and a map that amplifies a one-ulp change of
//! an input into a large move of its output is ill-conditioned there, no
//! matter how it is evaluated. The sensitivity
//!
//! `κ(x) = max_i max_± ‖ψ(x ± ulp(x_i)·e_i) − ψ(x)‖_∞ / extent`,
//!
//! over every input `x_i` (the shape's parameters, then `u`, then `v`) and both
//! directions, with `ψ` evaluated exactly (at 256 bits) and the perturbed
//! input the *neighbouring floating-point number* of `x_i` in the input format
//! (`f64` or `f32`), measures that limit in the units of the precision check
//! ([`precision`](super::precision)): absolute distance divided by the shape's
//! [`extent`](crate::warp::Warp::extent). A map is *as accurate as its inputs
//! allow* at `x` when its error in that format is at most
//! [`accuracy_bound`]`(κ, format)` `= 16 · max(u_T, κ)`, with `u_T = 2^-53`
//! for `f64` and `2^-24` for `f32`.
//!
//! Notes:
//! - Neighbours of `u` and `v` outside `[0, 1]` are skipped (the map is not
//!   defined there), so at `u = 1` only the step down counts.
//! - The neighbour of 0 is the smallest subnormal (`2^-1074` for `f64`), so a
//!   zero input contributes next to nothing.
//! - κ is absolute, not relative: `r = √u` near `u = 0` is *well*-conditioned
//!   in this sense (`ulp(u)/(2√u) ≈ 2^-54 √u`), whereas `√(1 − u)` near
//!   `u = 1` is not: at `u = 1 − 2^-53` one ulp moves it by `2^-26.5`.
//! - A perturbed parameter vector the builder rejects (a parameter on the
//!   boundary of its valid range) is skipped and counted in
//!   [`Sensitivity::skipped`].
//!
//! # Example
//! ```ignore
//! use areawarp::harness::sensitivity::{accuracy_bound, sensitivity, InputFormat};
//! use areawarp::real::Mpfr256;
//! // params = the 9 vertex coordinates of a triangle
//! let kappa = sensitivity(|p: &[Mpfr256]| build_triangle(p), &params, u, v)?;
//! assert!(err_f64 <= accuracy_bound(kappa, InputFormat::F64));
//! ```

use crate::error::WarpError;
use crate::real::Real;
use crate::vector::{Coords, Vec3};
use crate::warp::Warp;
#[cfg(feature = "mpfr")]
use crate::warp::WarpFamily;

/// The factor of the accuracy criterion `error ≤ 16 · max(u_T, κ)`.
pub const ACCURACY_FACTOR: f64 = 16.0;

/// The floating-point format whose ulps perturb the inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputFormat {
    /// IEEE single precision (24-bit significand): inputs are first rounded
    /// to `f32`, then moved to their `f32` neighbours.
    F32,
    /// IEEE double precision (53-bit significand): inputs are used as given
    /// and moved to their `f64` neighbours.
    F64,
}

impl InputFormat {
    /// The format of a scalar of `p` significand bits: `F32` for 24, `F64`
    /// for 53, `None` otherwise.
    pub fn for_precision(p: u32) -> Option<InputFormat> {
        match p {
            24 => Some(InputFormat::F32),
            53 => Some(InputFormat::F64),
            _ => None,
        }
    }
    /// `x` rounded to this format (nearest), returned as `f64`.
    pub fn round(self, x: f64) -> f64 {
        match self {
            InputFormat::F32 => f64::from(x as f32),
            InputFormat::F64 => x,
        }
    }
    /// The next larger number of this format after `round(x)`.
    pub fn next_up(self, x: f64) -> f64 {
        match self {
            InputFormat::F32 => f64::from((x as f32).next_up()),
            InputFormat::F64 => x.next_up(),
        }
    }
    /// The next smaller number of this format before `round(x)`.
    pub fn next_down(self, x: f64) -> f64 {
        match self {
            InputFormat::F32 => f64::from((x as f32).next_down()),
            InputFormat::F64 => x.next_down(),
        }
    }
    /// The unit roundoff `2^-p` of the format: `2^-24` or `2^-53`.
    pub fn unit_roundoff(self) -> f64 {
        match self {
            InputFormat::F32 => f64::from(f32::EPSILON) / 2.0,
            InputFormat::F64 => f64::EPSILON / 2.0,
        }
    }
}

/// `16 · max(u_T, κ)`: the largest error (in the units of κ: distance over
/// extent) a map evaluated in `format` may make at a point of sensitivity
/// `κ` and still count as accurate as its inputs allow.
pub fn accuracy_bound(kappa: f64, format: InputFormat) -> f64 {
    ACCURACY_FACTOR * format.unit_roundoff().max(kappa)
}

/// The sensitivity at one point, with where it comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// κ: the largest move of the exact map under a one-ulp change of one
    /// input, over the shape's extent.
    pub kappa: f64,
    /// The input responsible: `Some(i)` with `i < params.len()` a parameter,
    /// `params.len()` for `u` and `params.len() + 1` for `v`; `None` if no
    /// perturbation moved the map.
    pub worst_input: Option<usize>,
    /// Perturbations skipped because the builder rejected the perturbed
    /// parameters.
    pub skipped: usize,
}

/// κ of the map built by `build` from `params`, at `(u, v)`, with `f64`
/// inputs perturbed by one `f64` ulp and the map evaluated at 256 bits (see
/// the [module documentation](self)).
///
/// `build` receives the parameters converted exactly to
/// [`Mpfr256`](crate::real::Mpfr256) and builds the warp (any variant of it).
///
/// # Errors
/// The builder's error at the unperturbed parameters, or
/// [`WarpError::NonFinite`] if the exact map is not finite at an evaluated
/// point (a bug of the map, not a matter of conditioning).
#[cfg(feature = "mpfr")]
pub fn sensitivity<W, F>(build: F, params: &[f64], u: f64, v: f64) -> Result<f64, WarpError>
where
    W: Warp<crate::real::Mpfr256>,
    F: Fn(&[crate::real::Mpfr256]) -> Result<W, WarpError>,
{
    Ok(sensitivities_in(build, params, &[(u, v)], InputFormat::F64)?[0].kappa)
}

/// [`sensitivity`] for `f32` inputs: `params`, `u` and `v` are first rounded
/// to `f32` (the shape and point as `f32` sees them, as in the `f32`
/// precision check) and perturbed by one `f32` ulp.
///
/// # Errors
/// As [`sensitivity`].
#[cfg(feature = "mpfr")]
pub fn sensitivity_f32<W, F>(build: F, params: &[f64], u: f64, v: f64) -> Result<f64, WarpError>
where
    W: Warp<crate::real::Mpfr256>,
    F: Fn(&[crate::real::Mpfr256]) -> Result<W, WarpError>,
{
    Ok(sensitivities_in(build, params, &[(u, v)], InputFormat::F32)?[0].kappa)
}

/// The sensitivity at each of `points`, with the map evaluated in scalar `R`
/// (normally `Mpfr256`, feature `mpfr`; `f64` gives a rough estimate
/// without MPFR) and inputs perturbed in `format`.
///
/// Builds the shape `1 + 2·params.len()` times (once per perturbed
/// parameter vector), not once per point, so a whole grid costs little more
/// than one point.
///
/// # Errors
/// As `sensitivity` (feature `mpfr`).
pub fn sensitivities_in<R, W, F>(
    build: F,
    params: &[f64],
    points: &[(f64, f64)],
    format: InputFormat,
) -> Result<Vec<Sensitivity>, WarpError>
where
    R: Real,
    W: Warp<R>,
    F: Fn(&[R]) -> Result<W, WarpError>,
{
    let base_params: Vec<f64> = params.iter().map(|&x| format.round(x)).collect();
    let to_r = |xs: &[f64]| -> Vec<R> { xs.iter().map(|&x| R::from_f64(x)).collect() };
    let base = build(&to_r(&base_params))?;
    let extent = base.extent();
    let inputs: Vec<(R, R)> = points
        .iter()
        .map(|&(u, v)| (R::from_f64(format.round(u)), R::from_f64(format.round(v))))
        .collect();
    let reference: Vec<Vec3<R>> = inputs
        .iter()
        .map(|(u, v)| finite(base.map(u, v).to_vec3(), "map at the unperturbed inputs"))
        .collect::<Result<_, _>>()?;

    let mut out: Vec<(R, Option<usize>)> = vec![(R::zero(), None); points.len()];
    let mut skipped = 0;
    let mut record = |k: usize, moved: Vec3<R>, input: usize| -> Result<(), WarpError> {
        let moved = finite(moved, "map at a perturbed input")?;
        let d = moved.sub(&reference[k]).max_abs() / &extent;
        if d > out[k].0 {
            out[k] = (d, Some(input));
        }
        Ok(())
    };

    // Parameters: one rebuilt shape per perturbation, evaluated at every point.
    let mut perturbed = base_params.clone();
    for i in 0..base_params.len() {
        for x in [
            format.next_up(base_params[i]),
            format.next_down(base_params[i]),
        ] {
            if !x.is_finite() {
                continue;
            }
            perturbed[i] = x;
            let built = build(&to_r(&perturbed));
            perturbed[i] = base_params[i];
            let Ok(w) = built else {
                skipped += 1;
                continue;
            };
            for (k, (u, v)) in inputs.iter().enumerate() {
                record(k, w.map(u, v).to_vec3(), i)?;
            }
        }
    }

    // u and v: neighbours within [0, 1].
    for (k, &(u, v)) in points.iter().enumerate() {
        let (u, v) = (format.round(u), format.round(v));
        for x in [format.next_up(u), format.next_down(u)] {
            if (0.0..=1.0).contains(&x) {
                record(
                    k,
                    base.map(&R::from_f64(x), &inputs[k].1).to_vec3(),
                    params.len(),
                )?;
            }
        }
        for x in [format.next_up(v), format.next_down(v)] {
            if (0.0..=1.0).contains(&x) {
                record(
                    k,
                    base.map(&inputs[k].0, &R::from_f64(x)).to_vec3(),
                    params.len() + 1,
                )?;
            }
        }
    }

    Ok(out
        .into_iter()
        .map(|(kappa, worst_input)| Sensitivity {
            kappa: kappa.to_f64(),
            worst_input,
            skipped,
        })
        .collect())
}

/// The outcome of [`check_precision_conditioned`]: the precision check with
/// each point's error held to its own bound `16 · max(u_T, κ)`.
#[cfg(feature = "mpfr")]
#[derive(Clone, Debug)]
pub struct ConditionedReport {
    /// The warp's [`WarpFamily::name`].
    pub warp: String,
    /// The scalar under test, `f32` or `f64`.
    pub scalar: String,
    /// Number of points evaluated.
    pub points: usize,
    /// `max error / accuracy_bound(κ)` over the points where both
    /// evaluations are finite: at most 1 when the map is as accurate as its
    /// inputs allow.
    pub max_ratio: f64,
    /// The input `(u, v)` with the largest ratio.
    pub worst: Option<(f64, f64)>,
    /// The error (distance over extent) at [`ConditionedReport::worst`].
    pub worst_error: f64,
    /// κ at [`ConditionedReport::worst`].
    pub worst_kappa: f64,
    /// The largest error over all points (distance over extent).
    pub max_error: f64,
    /// The largest κ over all points.
    pub max_kappa: f64,
    /// Points where the map in `T` returned NaN or infinite coordinates.
    pub non_finite: usize,
    /// Points where the 256-bit reference was not finite.
    pub reference_non_finite: usize,
    /// Points whose [`Warp::outside_by`] (measured on the reference shape)
    /// exceeds their accuracy bound.
    pub outside: usize,
}

#[cfg(feature = "mpfr")]
impl ConditionedReport {
    /// `true` when every point is finite, none is outside beyond its bound,
    /// and every error is within its bound (`max_ratio ≤ 1`).
    pub fn passes(&self) -> bool {
        self.non_finite == 0
            && self.reference_non_finite == 0
            && self.outside == 0
            && self.max_ratio <= 1.0
    }
}

/// The precision check of [`precision`](super::precision) with a per-point
/// bound: at each of `points`, the error of `w` evaluated in `T` (`f32` or
/// `f64`) against the same shape as `T` sees it at 256 bits, in distance over
/// extent, divided by [`accuracy_bound`]`(κ)`, where κ is the sensitivity at
/// that point of the map `build` makes from `params` (the parameters of the
/// same shape, in `f64`) with `T`'s input format.
///
/// `w` and `build(params)` must describe the same shape and variant; the
/// error reference is `w.at::<T>()?.at::<Mpfr256>()`, as in
/// [`check_precision`](super::precision::check_precision).
///
/// # Errors
/// [`WarpError::InvalidParameter`] if `T` is neither `f32` nor `f64`; the
/// errors of [`WarpFamily::at`] and of [`sensitivities_in`].
///
/// # Example
/// ```ignore
/// let report = check_precision_conditioned::<f64, _, _, _>(
///     &triangle, |p: &[Mpfr256]| build_triangle(p), &params, &extremes_grid())?;
/// assert!(report.passes(), "{report:?}");
/// ```
#[cfg(feature = "mpfr")]
pub fn check_precision_conditioned<T, W, F, WR>(
    w: &W,
    build: F,
    params: &[f64],
    points: &[(f64, f64)],
) -> Result<ConditionedReport, WarpError>
where
    T: Real,
    W: WarpFamily<f64>,
    F: Fn(&[crate::real::Mpfr256]) -> Result<WR, WarpError>,
    WR: Warp<crate::real::Mpfr256>,
{
    use crate::real::{Mpfr256, convert};
    let format = InputFormat::for_precision(T::precision()).ok_or(WarpError::InvalidParameter {
        name: "T",
        expected: "f32 or f64",
    })?;
    let kappas = sensitivities_in(build, params, points, format)?;
    let wt = w.at::<T>()?;
    let wr = wt.at::<Mpfr256>()?;
    let extent = wr.extent();
    let mut report = ConditionedReport {
        warp: w.name(),
        scalar: T::type_name(),
        points: points.len(),
        max_ratio: 0.0,
        worst: None,
        worst_error: 0.0,
        worst_kappa: 0.0,
        max_error: 0.0,
        max_kappa: 0.0,
        non_finite: 0,
        reference_non_finite: 0,
        outside: 0,
    };
    for (&(u, v), s) in points.iter().zip(&kappas) {
        report.max_kappa = report.max_kappa.max(s.kappa);
        let (ut, vt) = (T::from_f64(u), T::from_f64(v));
        let (ur, vr): (Mpfr256, Mpfr256) = (convert(&ut), convert(&vt));
        let reference = wr.map(&ur, &vr).to_vec3();
        let pt = wt.map(&ut, &vt).to_vec3();
        if !reference.is_finite() {
            report.reference_non_finite += 1;
            continue;
        }
        if !pt.is_finite() {
            report.non_finite += 1;
            continue;
        }
        let p: Vec3<Mpfr256> = pt.convert();
        let bound = accuracy_bound(s.kappa, format);
        let err = (p.sub(&reference).max_abs() / &extent).to_f64();
        let out =
            (wr.outside_by(&<WR2<T, W> as Warp<Mpfr256>>::Point::from_vec3(p)) / &extent).to_f64();
        if out > bound {
            report.outside += 1;
        }
        report.max_error = report.max_error.max(err);
        let ratio = err / bound;
        if report.worst.is_none() || ratio > report.max_ratio {
            report.max_ratio = ratio;
            report.worst = Some((u, v));
            report.worst_error = err;
            report.worst_kappa = s.kappa;
        }
    }
    Ok(report)
}

/// The reference warp type of [`check_precision_conditioned`].
#[cfg(feature = "mpfr")]
type WR2<T, W> = <<W as WarpFamily<f64>>::At<T> as WarpFamily<T>>::At<crate::real::Mpfr256>;

fn finite<R: Real>(p: Vec3<R>, what: &'static str) -> Result<Vec3<R>, WarpError> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(WarpError::NonFinite { what })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::test_warps::{Parallelogram, TestDisk};
    use crate::warp::InverseError;

    fn parallelogram<R: Real>(p: &[R]) -> Result<Parallelogram<R>, WarpError> {
        let v = |i: usize| Vec3::new(p[i].clone(), p[i + 1].clone(), p[i + 2].clone());
        Parallelogram::new(v(0), v(3), v(6))
    }

    /// o = (1/2, 0, 0), e1 = (4, 0, 0), e2 = (0, 1, 0); extent 4.
    const PARAMS: [f64; 9] = [0.5, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 1.0, 0.0];

    #[test]
    fn linear_map_f32_inputs_with_f64_reference() {
        // f32 steps at u = 3/4 (all sums exact in f64): e1.x = 4 up by 2^-21
        // moves x by (3/4)·2^-21, more than o.x (2^-24), u (4·2^-24), v
        // (2^-24) or e2.y (2^-24): κ = 3·2^-23 / 4.
        let s = sensitivities_in::<f64, _, _>(
            parallelogram,
            &PARAMS,
            &[(0.75, 0.5), (0.125, 0.5)],
            InputFormat::F32,
        )
        .unwrap();
        assert_eq!(s[0].kappa, 3.0 * 2f64.powi(-25));
        assert_eq!(s[0].worst_input, Some(3));
        assert_eq!(s[0].skipped, 0);
        // At u = 1/8, e1.x, o.x, u, v and e2.y all move the point by 2^-24.
        assert_eq!(s[1].kappa, 2f64.powi(-26));
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn linear_map_at_256_bits_and_f32() {
        let k = sensitivity(parallelogram, &PARAMS, 0.75, 0.5).unwrap();
        assert_eq!(k, 3.0 * 2f64.powi(-54));
        // f32: ulp(4) up = 2^-21, times 3/4, over 4.
        let k32 = sensitivity_f32(parallelogram, &PARAMS, 0.75, 0.5).unwrap();
        assert_eq!(k32, 3.0 * 2f64.powi(-25));
        // 3·2^-54 > 2^-53: the bound is set by κ, not by the roundoff.
        assert_eq!(accuracy_bound(k, InputFormat::F64), 16.0 * k);
        assert_eq!(accuracy_bound(0.0, InputFormat::F64), 16.0 * 2f64.powi(-53));
        assert_eq!(accuracy_bound(k32, InputFormat::F32), 16.0 * k32);
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn sqrt_of_one_minus_u_is_ill_conditioned() {
        use crate::harness::test_warps::TestSphere;
        // Sphere: r = 2√(u(1 − u)). At u = 1 − 2^-53 the step up to u = 1
        // moves r from 2·2^-26.5·√(1 − 2^-53) to 0: κ ≈ 2^-25.5.
        let build = |_: &[crate::real::Mpfr256]| {
            Ok::<_, WarpError>(TestSphere::<crate::real::Mpfr256>::new(false))
        };
        let u = 1.0 - 2f64.powi(-53);
        let k = sensitivity(build, &[], u, 0.0).unwrap();
        let expected = 2f64.powf(-25.5);
        assert!((k / expected - 1.0).abs() < 1e-12, "{k:e} vs {expected:e}");
        // At u = 1 only the step down exists: r goes to 2√(2^-53 (1 − 2^-53)).
        let k1 = sensitivity(build, &[], 1.0, 0.0).unwrap();
        assert!((k1 / expected - 1.0).abs() < 1e-12, "{k1:e}");
        // The same map near u = 0 is well-conditioned in absolute terms.
        let k0 = sensitivity(build, &[], 2f64.powi(-60), 0.0).unwrap();
        assert!(k0 < 2f64.powi(-80), "{k0:e}");
        // f32: at u = 1 − 2^-24 (an f32), κ ≈ 2^-11.
        let k32 = sensitivity_f32(build, &[], 1.0 - 2f64.powi(-24), 0.0).unwrap();
        assert!((k32 / 2f64.powi(-11) - 1.0).abs() < 1e-6, "{k32:e}");
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn polar_disk_near_the_centre() {
        // r = √u at u = 2^-60, v = 0: the step up of u by 2^-112 moves r by
        // 2^-112 / (2 · 2^-30) = 2^-83; v's neighbours are 2^-1074 (nothing)
        // and −2^-1074 (outside [0, 1], skipped).
        let build = |_: &[crate::real::Mpfr256]| {
            Ok::<_, WarpError>(TestDisk::<crate::real::Mpfr256>::correct())
        };
        let s = sensitivities_in(build, &[], &[(2f64.powi(-60), 0.0)], InputFormat::F64).unwrap();
        assert!((s[0].kappa / 2f64.powi(-83) - 1.0).abs() < 1e-12, "{s:?}");
        assert_eq!(s[0].worst_input, Some(0));
        // At (1, 1/2) the step of v up (2^-53) rotates the rim point by 2π·2^-53.
        let k = sensitivity(build, &[], 1.0, 0.5).unwrap();
        let expected = 2.0 * core::f64::consts::PI * 2f64.powi(-53);
        assert!((k / expected - 1.0).abs() < 1e-12, "{k:e}");
        // At u = v = 0 nothing moves beyond the subnormal scale.
        let k0 = sensitivity(build, &[], 0.0, 0.0).unwrap();
        assert!(k0 < 1e-160, "{k0:e}");
    }

    #[test]
    fn rejected_perturbations_are_skipped_and_errors_reported() {
        // A builder that rejects any parameter other than exactly 1.
        let build = |p: &[f64]| {
            if p[0] == 1.0 {
                Ok(TestDisk::<f64>::correct())
            } else {
                Err(WarpError::InvalidParameter {
                    name: "p",
                    expected: "1",
                })
            }
        };
        let s = sensitivities_in(build, &[1.0], &[(0.5, 0.5)], InputFormat::F64).unwrap();
        assert_eq!(s[0].skipped, 2);
        assert_eq!(s[0].worst_input, Some(2));
        let e = sensitivities_in(build, &[2.0], &[(0.5, 0.5)], InputFormat::F64);
        assert!(e.is_err());

        // A map that is NaN at the point is an error, not a condition.
        #[derive(Clone, Debug)]
        struct Nan;
        impl Warp<f64> for Nan {
            type Point = crate::vector::Vec2<f64>;
            fn map(&self, u: &f64, _v: &f64) -> Self::Point {
                crate::vector::Vec2::new((u - 0.5).sqrt(), 0.0)
            }
            fn pdf_unchecked(&self, _p: &Self::Point) -> f64 {
                1.0
            }
            fn measure(&self) -> f64 {
                1.0
            }
            fn inverse(&self, _p: &Self::Point) -> Result<[f64; 2], InverseError> {
                Err(InverseError::NonFinite)
            }
            fn outside_by(&self, _p: &Self::Point) -> f64 {
                0.0
            }
        }
        let r = sensitivities_in(|_: &[f64]| Ok(Nan), &[], &[(0.25, 0.5)], InputFormat::F64);
        assert!(matches!(r, Err(WarpError::NonFinite { .. })));
        // At u = 1/2 the step down makes it NaN.
        let r = sensitivities_in(|_: &[f64]| Ok(Nan), &[], &[(0.5, 0.5)], InputFormat::F64);
        assert!(matches!(r, Err(WarpError::NonFinite { .. })));
    }

    /// The unit square's identity map, evaluated as `((u + 2^k) − 2^k, v)`:
    /// exact for `k = 0`, loses `k` bits of `u` otherwise.
    #[cfg(feature = "mpfr")]
    #[derive(Clone, Debug)]
    struct Lossy(i32);
    #[cfg(feature = "mpfr")]
    impl<T: Real> Warp<T> for Lossy {
        type Point = crate::vector::Vec2<T>;
        fn map(&self, u: &T, v: &T) -> Self::Point {
            let big = if self.0 == 0 {
                T::zero()
            } else {
                T::exp2i(self.0)
            };
            crate::vector::Vec2::new(u.clone() + &big - &big, v.clone())
        }
        fn pdf_unchecked(&self, _p: &Self::Point) -> T {
            T::one()
        }
        fn measure(&self) -> T {
            T::one()
        }
        fn inverse(&self, p: &Self::Point) -> Result<[T; 2], InverseError> {
            Ok([p.x.clone(), p.y.clone()])
        }
        fn outside_by(&self, p: &Self::Point) -> T {
            let zero = T::zero();
            (-p.x.clone()).max(&zero) + &(p.x.clone() - &T::one()).max(&zero)
        }
    }
    #[cfg(feature = "mpfr")]
    impl<T: Real> WarpFamily<T> for Lossy {
        type At<S: Real> = Lossy;
        fn at<S: Real>(&self) -> Result<Lossy, WarpError> {
            Ok(self.clone())
        }
        fn name(&self) -> String {
            format!("lossy({})", self.0)
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn conditioned_precision_check() {
        use crate::harness::extremes::{extremes_grid, random_points};
        use crate::harness::test_warps::TestSphere;
        use crate::real::Mpfr256;
        let mut points = extremes_grid();
        points.extend(random_points(50, 1));
        let sphere = |_: &[Mpfr256]| Ok::<_, WarpError>(TestSphere::<Mpfr256>::new(false));
        for r in [
            check_precision_conditioned::<f64, _, _, _>(
                &TestSphere::<f64>::new(false),
                sphere,
                &[],
                &points,
            )
            .unwrap(),
            check_precision_conditioned::<f32, _, _, _>(
                &TestSphere::<f64>::new(false),
                sphere,
                &[],
                &points,
            )
            .unwrap(),
        ] {
            assert!(r.passes(), "{r:?}");
            assert_eq!(r.points, 114);
            // u = 1 − 1e-12 is ill-conditioned in f64 (r = 2√(u(1 − u))).
            assert!(r.max_kappa > 1e-8, "{r:?}");
            assert!(r.max_error > 0.0);
        }
        let exact = check_precision_conditioned::<f32, _, _, _>(
            &Lossy(0),
            |_: &[Mpfr256]| Ok(Lossy(0)),
            &[],
            &points,
        )
        .unwrap();
        assert!(exact.passes() && exact.max_error == 0.0, "{exact:?}");
        // Losing 8 bits of u: errors up to 2^-17 where κ ≈ 2^-24.
        let lossy = check_precision_conditioned::<f32, _, _, _>(
            &Lossy(8),
            |_: &[Mpfr256]| Ok(Lossy(0)),
            &[],
            &points,
        )
        .unwrap();
        assert!(!lossy.passes());
        assert!(lossy.max_ratio > 2.0, "{lossy:?}");
        assert!(
            check_precision_conditioned::<Mpfr256, _, _, _>(
                &Lossy(0),
                |_: &[Mpfr256]| Ok(Lossy(0)),
                &[],
                &points,
            )
            .is_err()
        );
    }

    #[test]
    fn input_format_neighbours() {
        assert_eq!(InputFormat::F64.next_up(1.0), 1.0 + f64::EPSILON);
        assert_eq!(InputFormat::F64.next_down(1.0), 1.0 - f64::EPSILON / 2.0);
        assert_eq!(InputFormat::F32.next_up(1.0), 1.0 + f64::from(f32::EPSILON));
        assert_eq!(InputFormat::F32.round(0.1), f64::from(0.1f32));
        assert_eq!(InputFormat::F32.unit_roundoff(), 2f64.powi(-24));
        assert_eq!(InputFormat::F64.unit_roundoff(), 2f64.powi(-53));
        assert_eq!(InputFormat::F64.next_up(0.0), f64::from_bits(1));
    }
}
