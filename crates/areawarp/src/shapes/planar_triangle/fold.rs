//! Heitz's (2019) low-distortion fold map of the planar triangle, the
//! second variant of [`PlanarTriangle`](super::PlanarTriangle).
//! Derivation: `docs/planar-triangle.md`.

use super::{PlanarTriangle, anchored};
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::turns::clamp01;
use crate::vector::Vec3;

/// Which area-preserving map of the triangle a
/// [`PlanarTriangle`](super::PlanarTriangle) evaluates. Both are uniform in
/// area; they are different maps (different images of strata).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PlanarTriangleVariant {
    /// Arvo's (2001) eq. 1.20, `(1 − √u)A + √u(1 − v)B + √u·v·C`.
    #[default]
    SquareRoot,
    /// Heitz's (2019) low-distortion fold map, "A Low-Distortion Map
    /// Between Triangle and Square" (pbrt-v4's `SampleUniformTriangle`):
    /// the square is cut along its diagonal and each half sheared onto
    /// half of the triangle; no square root, piecewise linear:
    ///
    /// ```text
    /// u ≥ v:  λ_B = u − v/2,  λ_C = v/2
    /// u < v:  λ_B = u/2,      λ_C = v − u/2,     λ_A = 1 − max(u, v),
    /// i.e.    λ_B = u − min(u, v)/2,  λ_C = v − min(u, v)/2.
    /// ```
    ///
    /// `(0, 0)` is A, `(1, 0)` B, `(0, 1)` C, `(1, 1)` the midpoint of BC.
    Fold,
}

impl PlanarTriangleVariant {
    /// `"sqrt"` or `"fold"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            PlanarTriangleVariant::SquareRoot => "sqrt",
            PlanarTriangleVariant::Fold => "fold",
        }
    }
}

impl core::fmt::Display for PlanarTriangleVariant {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::str::FromStr for PlanarTriangleVariant {
    type Err = WarpError;
    /// Parses `sqrt` or `fold` (ASCII case-insensitive).
    fn from_str(s: &str) -> Result<Self, WarpError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "sqrt" => Ok(PlanarTriangleVariant::SquareRoot),
            "fold" => Ok(PlanarTriangleVariant::Fold),
            _ => Err(WarpError::InvalidParameter {
                name: "variant",
                expected: "sqrt or fold",
            }),
        }
    }
}

/// The fold map: barycentric weights as in [`PlanarTriangleVariant::Fold`],
/// the point as `A + (λ_B (B − A) + λ_C (C − A))` with the edge vectors
/// precomputed. Anchoring at A always (the √u map switches to B or C on
/// its side u = 1) and writing both halves as
/// `λ_B = u − min(u, v)/2`, `λ_C = v − min(u, v)/2` keep the map free of
/// data-dependent branches; the absolute error stays within
/// a few units of roundoff of the triangle's extent, and A is reproduced
/// exactly (B and C to within the rounding of the edge vectors).
pub(super) fn map<T: Real>(t: &PlanarTriangle<T>, u: &T, v: &T) -> Vec3<T> {
    let (u, v) = (clamp01(u), clamp01(v));
    // Both halves at once: λ_B = u − min(u, v)/2, λ_C = v − min(u, v)/2.
    let half_min = u.min(&v) / &T::from_i64(2);
    let lb = u - &half_min;
    let lc = v - &half_min;
    anchored(&t.a, &lb, &t.e_ab, &lc, &t.e_ca)
}

/// The inverse of the fold map (pbrt-v4's `InvertUniformTriangleSample`):
/// `(λ_B + λ_C, 2λ_C)` if `λ_B ≥ λ_C`, else `(2λ_B, λ_B + λ_C)`, from the
/// clamped barycentric coordinates of the projection of `p`.
pub(super) fn inverse<T: Real>(t: &PlanarTriangle<T>, p: &Vec3<T>) -> [T; 2] {
    let (_, lb, lc) = t.barycentric(p);
    let (lb, lc) = (lb.max(&T::zero()), lc.max(&T::zero()));
    let sum = clamp01(&(lb.clone() + &lc));
    let two = T::from_i64(2);
    if lb >= lc {
        [sum, clamp01(&(lc * &two))]
    } else {
        [clamp01(&(lb * &two)), sum]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::chi2::TriangleBins;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{chi2_passes, roundtrip_passes};
    use crate::warp::{Warp, WarpFamily};

    fn tris() -> Vec<PlanarTriangle<f64>> {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        [
            [v(1.0, 2.0, 3.0), v(-2.0, 0.5, 1.0), v(0.5, -1.0, 2.0)],
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.25, 1.0, 0.0)],
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.5, 1e-3, 0.0)],
        ]
        .into_iter()
        .map(|[a, b, c]| PlanarTriangle::new_with(a, b, c, PlanarTriangleVariant::Fold).unwrap())
        .collect()
    }

    #[test]
    fn fold_corners_variant_and_parse() {
        for t in tris() {
            assert_eq!(t.variant(), PlanarTriangleVariant::Fold);
            assert_eq!(
                t.at::<f32>().unwrap().variant(),
                PlanarTriangleVariant::Fold
            );
            assert_eq!(t.map(&0.0, &0.0), *t.a());
            let tol = 2.0 * f64::EPSILON * t.extent();
            assert!(t.map(&1.0, &0.0).sub(t.b()).max_abs() <= tol);
            assert!(t.map(&0.0, &1.0).sub(t.c()).max_abs() <= tol);
            let mid = t.b().add(t.c()).scale(&0.5);
            assert!(t.map(&1.0, &1.0).sub(&mid).norm() <= 4.0 * f64::EPSILON * t.extent());
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = t.map(&u, &v);
                    assert!(t.outside_by(&p) <= 8.0 * f64::EPSILON * t.extent());
                }
            }
        }
        assert_eq!("fold".parse(), Ok(PlanarTriangleVariant::Fold));
        assert_eq!(" SQRT".parse(), Ok(PlanarTriangleVariant::SquareRoot));
        assert!("arvo".parse::<PlanarTriangleVariant>().is_err());
        assert_eq!(PlanarTriangleVariant::Fold.to_string(), "fold");
    }

    #[test]
    fn fold_roundtrip_and_chi2() {
        for (i, t) in tris().into_iter().enumerate() {
            roundtrip_passes::<f64, _>(&format!("planar-triangle fold {i}"), &t, 8.0);
            roundtrip_passes::<f32, _>(&format!("planar-triangle fold {i}"), &t, 8.0);
            let bins = TriangleBins::new(*t.a(), *t.b(), *t.c(), 12).unwrap();
            chi2_passes(&format!("planar-triangle fold {i}"), &t, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn fold_harness_at_extremes() {
        for (i, t) in tris().into_iter().enumerate() {
            crate::shapes::test_support::harness_passes(
                &format!("planar-triangle fold {i}"),
                &t,
                4.0,
            );
        }
    }
}
