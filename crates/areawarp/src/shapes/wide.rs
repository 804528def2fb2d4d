//! Moving vectors between a scalar `T` and its wide type [`Real::Wide`],
//! and what the light shapes' constructors share around it: the finiteness
//! check of their inputs and the cheap normalization.
//!
//! The spherical lights take every decision of their constructors (is the
//! shape degenerate?) and compute every constant that cancellation would
//! spoil in `T::Wide` (`f64` for `f32`), then round the constants to `T`
//! for the per-sample path. An `f32` shape is thereby accepted exactly when
//! the `f64` constructor accepts the same values, and its constants are
//! correctly rounded.

use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;

/// `Err(NonFinite)` naming the first vector of `named` with a NaN or
/// infinite coordinate. One test for all of them in the common case: the
/// sum of the coordinates is finite only if each is (a finite sum that
/// overflows falls through to the per-vector tests, and passes them).
#[inline(always)]
pub(crate) fn check_finite<T: Real, const N: usize>(
    named: [(&Vec3<T>, &'static str); N],
) -> Result<(), WarpError> {
    // The vectors' sum first, then its coordinates: vector additions, where
    // a running sum of all coordinates would be one long scalar chain.
    let [(first, _), rest @ ..] = &named[..] else {
        return Ok(());
    };
    let v = rest.iter().fold((*first).clone(), |acc, (v, _)| acc.add(v));
    let sum = v.x + &v.y + &v.z;
    if sum.is_finite() {
        return Ok(());
    }
    first_non_finite(named)
}

/// The cold half of [`check_finite`]: `Err(NonFinite)` naming the first
/// vector of `named` with a NaN or infinite coordinate. Out of line, so
/// that the array of names is formed only on this path (inlined, it was
/// stored on the stack before every constructor's finiteness test).
#[cold]
#[inline(never)]
fn first_non_finite<T: Real, const N: usize>(
    named: [(&Vec3<T>, &'static str); N],
) -> Result<(), WarpError> {
    match named.iter().find(|(v, _)| !v.is_finite()) {
        Some(&(_, what)) => Err(WarpError::NonFinite { what }),
        None => Ok(()),
    }
}

/// Whether the sum of squares `sum` is neither tiny (above `u⁴`) nor
/// infinite, so that its square root needs no scaling: the fast path of
/// [`unit_vector`] and of the rectangle's lengths and frame.
#[inline(always)]
pub(crate) fn plain_root_is_safe<T: Real>(sum: &T) -> bool {
    sum.is_finite_above(&T::unit_roundoff().powi(4))
}

/// `v` in `T::Wide` (exact).
#[inline]
pub(crate) fn widen3<T: Real>(v: &Vec3<T>) -> Vec3<T::Wide> {
    Vec3::new(v.x.widen(), v.y.widen(), v.z.widen())
}

/// `v` rounded to `T` component by component.
#[inline]
pub(crate) fn narrow3<T: Real>(v: &Vec3<T::Wide>) -> Vec3<T> {
    Vec3::new(T::narrow(&v.x), T::narrow(&v.y), T::narrow(&v.z))
}

/// `⌊log₂ |x|⌋` of a finite non-zero `f64` (from the bits for normal
/// numbers, no libm call); `0` for zero or non-finite `x`.
#[inline]
pub(crate) fn floor_log2(x: f64) -> i32 {
    let a = x.abs();
    if !Real::is_finite_above(&a, &0.0) {
        return 0;
    }
    if a >= f64::MIN_POSITIVE {
        ((a.to_bits() >> 52) as i32) - 1023
    } else {
        a.log2().floor() as i32
    }
}

/// The larger of `a` and `b` by one comparison (`b` if `b > a`, else `a`):
/// for values known to be finite, where [`Real::max`]'s NaN handling costs
/// a dozen instructions per call.
#[inline(always)]
pub(crate) fn larger<T: Real>(a: T, b: T) -> T {
    if b > a { b } else { a }
}

/// The largest absolute coordinate of the finite vector `v`, by
/// comparisons ([`larger`]; `Vec3::max_abs` takes NaN-aware maxima).
#[inline]
pub(crate) fn largest_abs<T: Real>(v: &Vec3<T>) -> T {
    larger(larger(v.x.abs(), v.y.abs()), v.z.abs())
}

/// The exponent `e` such that `m·2^-e` is in `[1, 2)` (`m > 0`, given as
/// `f64`), clamped so that `2^±e` is representable in `T` (±120 in `f32`,
/// ±1016 in `f64`); 0 for a zero or non-finite `m` (no scaling). Scaling
/// by `2^-e` is exact, away from underflow: the shapes that take their
/// lengths to O(1) with it compute the same values at every scale.
#[inline]
pub(crate) fn scale_exponent<T: Real>(m: f64) -> i32 {
    let lim = T::max_value().to_f64().log2().min(1024.0) as i32 - 8;
    floor_log2(m).clamp(-lim, lim)
}

/// `v / |v|`, `None` for the zero vector (or a non-finite one).
///
/// One square root and one division when `|v|²` is neither tiny nor huge
/// (always, for `f32` data widened to `f64`); otherwise `v` is first
/// divided by its largest component, so that the result is free of overflow
/// and underflow for every finite non-zero `v`.
#[inline]
pub(crate) fn unit_vector<T: Real>(v: &Vec3<T>) -> Option<Vec3<T>> {
    let n2 = v.dot(v);
    if plain_root_is_safe(&n2) {
        // One division: each component is then within 1.5 ulps (not exact
        // for an axis-aligned vector of non-power-of-two length).
        let inv = T::one() / &n2.sqrt();
        return Some(Vec3::new(
            v.x.clone() * &inv,
            v.y.clone() * &inv,
            v.z.clone() * &inv,
        ));
    }
    let m = v.max_abs();
    if !m.is_finite_above(&T::zero()) {
        return None;
    }
    let w = Vec3::new(v.x.clone() / &m, v.y.clone() / &m, v.z.clone() / &m);
    let n = w.dot(&w).sqrt();
    Some(Vec3::new(w.x / &n, w.y / &n, w.z / &n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_vector_is_accurate_on_axes_and_scale_free() {
        for k in [1e-300, 1e-160, 1e-30, 1.0, 3.0, 1e30, 1e160, 1e300] {
            let e = unit_vector(&Vec3::new(k, 0.0, 0.0)).unwrap();
            assert!((e.x - 1.0).abs() <= f64::EPSILON && e.y == 0.0 && e.z == 0.0);
            let u = unit_vector(&Vec3::new(k, 2.0 * k, -2.0 * k)).unwrap();
            let want = Vec3::new(1.0 / 3.0, 2.0 / 3.0, -2.0 / 3.0);
            assert!(u.sub(&want).max_abs() <= 2.0 * f64::EPSILON, "{k}: {u:?}");
        }
        assert_eq!(unit_vector(&Vec3::<f64>::zero()), None);
        assert_eq!(unit_vector(&Vec3::new(f64::INFINITY, 0.0, 0.0)), None);
        let s = unit_vector(&Vec3::new(f64::from_bits(1), 0.0, f64::from_bits(1))).unwrap();
        assert!((s.x - core::f64::consts::FRAC_1_SQRT_2).abs() <= f64::EPSILON);
    }

    #[test]
    fn floor_log2_of_normal_and_subnormal_numbers() {
        for (x, e) in [
            (1.0, 0),
            (1.5, 0),
            (2.0, 1),
            (0.75, -1),
            (3e-320, -1062),
            (-8.0, 3),
        ] {
            assert_eq!(floor_log2(x), e, "{x}");
        }
        assert_eq!(floor_log2(0.0), 0);
        assert_eq!(f64::exp2i(-1074), f64::from_bits(1));
        assert_eq!(f32::exp2i(-126), f32::MIN_POSITIVE);
        assert_eq!(f64::exp2i(1023), 2f64.powi(1023));
        assert_eq!(f32::exp2i(-149), f32::from_bits(1));
    }

    #[test]
    fn widen_and_narrow() {
        let v = Vec3::new(0.1f32, -3.0, 1e-40);
        let w = widen3(&v);
        assert_eq!(w.x, f64::from(0.1f32));
        assert_eq!(narrow3::<f32>(&w), v);
        assert_eq!(
            narrow3::<f32>(&Vec3::new(0.1, 1e300, 1e-300)).y,
            f32::INFINITY
        );
    }
}
