//! The checking harness: the checks the crate runs on its own warps, public so
//! that users run them on theirs.
//!
//! Every check takes any warp `w: W` with `W: WarpFamily<f64>` and a list of
//! input points `(u, v) ∈ [0, 1]²` ([`extremes`]), rebuilds the warp at the
//! precision it needs with [`WarpFamily::at`](crate::warp::WarpFamily::at),
//! and returns a report (plain data with public fields, `Debug`, `Clone`)
//! rather than panicking; each report has a `passes(..)` helper for asserts.
//! The checks that need 256-bit arithmetic are behind the `mpfr` feature;
//! each has a variant generic over the reference scalar that works without it.
//!
//! | check | proves | needs |
//! |---|---|---|
//! | `jacobian::check_jacobian` (feature `mpfr`) | the map is area-preserving: `|ψ_u × ψ_v| · pdf(ψ) = 1` at every point, with exact partials at 256 bits | `mpfr` ([`jacobian::check_jacobian_in`] without) |
//! | `precision::check_precision` (feature `mpfr`) | the `f32`/`f64` evaluation stays within a few units of roundoff of the 256-bit map, finite and on the shape | `mpfr` ([`precision::check_precision_against`] without) |
//! | [`roundtrip::check_roundtrip`] | [`Warp::inverse`](crate::warp::Warp::inverse) inverts the map | — |
//! | `sensitivity::sensitivity` (feature `mpfr`) | the map's own condition κ (move of the exact map under a one-ulp input change), for the criterion error ≤ 16·max(u_T, κ) | `mpfr` ([`sensitivity::sensitivities_in`] without) |
//! | [`chi2::run_chi_square`] | the samples the `f64` code actually produces follow the claimed density (statistically, in shape-intrinsic bins) | — |
//!
//! What each check proves, and what it does not:
//!
//! - **Jacobian** ([`jacobian`]). `J · pdf = 1` pointwise, with `J` computed
//!   by forward-mode dual numbers (no finite differences) in 256-bit MPFR, so
//!   a correct map deviates by ~`10^-75` and any error in the radial law, a
//!   constant or the density shows as a deviation of order 1. It is a local
//!   identity: it does not see a map that covers only part of the shape, or
//!   covers it twice (the χ² test does), and it tests the formulas at the
//!   given points, not the rounding of the hardware evaluation (the precision
//!   check does). Points on singular edges (`√u` at `u = 0`) are nudged into
//!   the interior by `2^-128` and counted.
//! - **Precision** ([`precision`]). The error of the map in `T` against the
//!   *same shape as `T` sees it* evaluated at 256 bits, in units of `T`'s
//!   unit roundoff relative to the shape's extent; plus NaN/∞ counts and
//!   points off the shape. On the extremes grid it exposes cancellation near
//!   edges and poles, which random testing almost never hits.
//! - **Round trip** ([`roundtrip`]). `ψ⁻¹(ψ(u, v))` against `(u, v)`, and the
//!   image error `ψ(ψ⁻¹(p)) − p`, which is the meaningful one at seams and
//!   poles where the parameters are not unique.
//! - **χ²** ([`chi2`]). Pearson's test, Mitsuba-style (pooling of small
//!   cells, Šidák correction for many tests), of `f64` samples against
//!   equal-measure binnings built from the shape's geometry
//!   ([`chi2::ZPhiBins`], [`chi2::DiskBins`], [`chi2::TriangleBins`]), plus a
//!   hard failure for samples outside the shape. It detects global errors
//!   (wrong coverage, wrong weight) but only statistically, to the
//!   resolution of the bins and the sample count.
//! - **Sensitivity** ([`sensitivity`]). Not a pass/fail check of the map but
//!   the yardstick for the precision check where the problem itself is
//!   ill-conditioned (e.g. `√(1 − u)` at `u = 1 − 2^-53`): a map is as
//!   accurate as its inputs allow when its error is within
//!   [`sensitivity::accuracy_bound`] of the condition κ.
//!
//! A warp that passes the first four at the extremes grid is area-preserving to
//! 256-bit accuracy, accurate in the hardware precisions, invertible and
//! samples its target distribution.
//!
//! # Example
//! ```
//! use areawarp::harness::chi2::{run_chi_square, ZPhiBins};
//! use areawarp::harness::extremes::extremes_grid;
//! use areawarp::harness::roundtrip::check_roundtrip;
//! use areawarp::shapes::Hemisphere;
//!
//! let warp = Hemisphere::<f64>::new();
//! let grid = extremes_grid();
//! #[cfg(feature = "mpfr")]
//! {
//!     use areawarp::harness::{jacobian::check_jacobian, precision::check_precision};
//!     let jacobian = check_jacobian(&warp, &grid)?;
//!     assert!(jacobian.passes(1e-60), "{jacobian:?}");
//!     let f32_error = check_precision::<f32, _>(&warp, &grid)?;
//!     assert!(f32_error.passes(16.0), "{f32_error:?}");
//! }
//! let round_trip = check_roundtrip::<f64, _>(&warp, &grid)?;
//! assert_eq!(round_trip.failures, 0);
//! let chi2 = run_chi_square(&warp, &ZPhiBins::hemisphere(8, 16)?, 20_000, 1, 0.01, 1);
//! assert!(chi2.passed, "{chi2:?}");
//! # Ok::<(), areawarp::WarpError>(())
//! ```

pub mod chi2;
pub mod extremes;
pub mod jacobian;
pub mod precision;
pub mod roundtrip;
pub mod sensitivity;

#[cfg(test)]
pub(crate) mod test_warps;

/// The median of `values` (sorted in place); 0 for an empty slice.
fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let m = values.len() / 2;
    if values.len() % 2 == 1 {
        values[m]
    } else {
        (values[m - 1] + values[m]) / 2.0
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_of_odd_even_and_empty() {
        assert_eq!(super::median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(super::median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(super::median(&mut []), 0.0);
    }
}
