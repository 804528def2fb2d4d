//! Small numerical helpers shared by the spherical warps: the azimuth
//! `φ = 2πv` evaluated without losing accuracy at the ends of `[0, 1]`, its
//! inverse, `atan2` by libm's `atan` of the quotient ([`atan2_by_atan`],
//! [`atan2_nonneg`]), the clamps of `u`, `v` and of ratios to `[0, 1]`,
//! and the positivity test. (The on-shape tolerance is
//! `warp::on_shape_tolerance`, beside the trait that documents it.)

use crate::real::Real;

/// `(cos 2πv, sin 2πv)`, accurate to a few units of roundoff *relative to
/// each coordinate*, also for `v` near `1/4, 1/2, 3/4, 1`.
///
/// The naive `(2π·v).sin_cos()` rounds the angle `2πv` to an absolute error
/// of about `2π·u`, so `sin 2πv` for `v = 1 − 1e-12` (true value
/// `≈ −6.3e-12`) would carry a relative error near `1e-4`. Instead the
/// angle is measured in quarter turns: with `q` the integer nearest `4v` and
/// `r = 4v − q ∈ [−1/2, 1/2]` (both exact: `4v` is a power-of-two scaling
/// and `4v − q` is exact by Sterbenz's lemma), `2πv = (π/2)(q + r)`, and
/// only the reduced angle `(π/2)·r ∈ [−π/4, π/4]` goes through `sin_cos`;
/// the quadrant `q mod 4` rotates the result exactly.
///
/// Cost (see [`polar_turns`], which the maps call, and [`Real::polar_turns`],
/// whose `f32` route does the same in `f64`): `q` and `q mod 4` come
/// from [`Real::split_quarter_turns`] (a round-to-integer addition, no
/// `floor` call), the rotation by the quadrant is a product with its exact
/// cosine and sine, not a branch on the (random) quadrant, whose
/// mispredictions would cost more than the rest of a map, and the sine and
/// cosine of the reduced angle come from [`Real::rotate_quarter_turns`]
/// (for `f32`/`f64` polynomial kernels of `r` itself, no library call;
/// `docs/quarter-turns.md`).
///
/// `half_pi` is the caller's precomputed `π/2`. Dual numbers: `q` is an
/// integer constant, so `r` carries the full derivative `4·dv`. A NaN `v`
/// gives NaN coordinates.
#[cfg(test)]
pub(crate) fn cos_sin_turns<T: Real>(v: &T, half_pi: &T) -> (T, T) {
    polar_turns(&T::one(), v, half_pi)
}

/// `(r cos 2πv, r sin 2πv)`: [`Real::polar_turns`] with the arguments in
/// the maps' order, the steps [`cos_sin_turns`] describes with `r` entering
/// through the exact products `r·cos(qπ/2)`, `r·sin(qπ/2)` (two products
/// fewer than `r` times the unit point, the same roundings).
#[inline]
pub(crate) fn polar_turns<T: Real>(r: &T, v: &T, half_pi: &T) -> (T, T) {
    v.polar_turns(r, half_pi)
}

/// The azimuth of `(x, y)` in turns, in `[0, 1)`: `atan2(y, x) / 2π`, shifted
/// by one turn when negative. Returns `0` at the pole `x = y = 0`.
///
/// `inv_two_pi` is the caller's precomputed `1/(2π)`. A tiny negative angle
/// would round `1 + angle/2π` up to one; it is replaced by `1 − u`, the
/// largest value below one, so that points just below the `+x` axis keep
/// `v ≈ 1` (their neighbours), and `−0` becomes `+0`.
pub(crate) fn turns_of<T: Real>(y: &T, x: &T, inv_two_pi: &T) -> T {
    let mut v = y.atan2(x) * inv_two_pi;
    if v < T::zero() {
        v += &T::one();
    }
    (v + &T::zero()).min(&(T::one() - &T::unit_roundoff()))
}

/// `atan2(y, x)` for `y ≥ 0` (half a solid angle from its tangent): by
/// [`atan2_by_atan`] where `x > 0` (the angle below π/2), by libm's
/// `atan2` where `x ≤ 0`.
#[inline(always)]
pub(crate) fn atan2_nonneg<T: Real>(y: &T, x: &T) -> T {
    if *x > T::zero() {
        atan2_by_atan(y, x)
    } else {
        y.atan2(x)
    }
}

/// `atan2(y, x)` over the whole plane by libm's `atan` of the quotient,
/// which with the division costs about half of glibc's `atan2`:
/// - `atan(y/x)` when `x > 0` and the quotient is a normal number: one
///   more rounding, the quotient's ½ ulp, not amplified (the relative
///   condition number `t/((1 + t²)·atan t)` of atan is at most 1);
/// - `atan(y/x) ± π` (the sign of `y`, zeros included) when `x < 0` and the
///   quotient is finite: |result| ≥ π/2, so the roundings of π and of the
///   sum are about one unit of the result;
/// - libm's `atan2` otherwise (a zero or subnormal quotient with `x > 0`,
///   where the quotient would lose relative accuracy; `x = 0`;
///   infinities; NaN).
#[inline(always)]
pub(crate) fn atan2_by_atan<T: Real>(y: &T, x: &T) -> T {
    let ratio = y.clone() / x;
    if *x > T::zero() && ratio.abs() >= T::normal_floor() {
        ratio.atan()
    } else if *x < T::zero() && ratio.is_finite() {
        ratio.atan() + &T::pi().copysign(y)
    } else {
        y.atan2(x)
    }
}

/// `u` clamped to `[0, 1]`; NaN passes through unchanged (unlike
/// [`Real::clamp`], which would hide it).
#[inline]
pub(crate) fn clamp_unit<T: Real>(u: &T) -> T {
    if *u < T::zero() {
        T::zero()
    } else if *u > T::one() {
        T::one()
    } else {
        u.clone()
    }
}

/// `x` clamped to `[0, 1]`, NaN mapped to 0: for maps that promise a finite
/// point for any input.
#[inline]
pub(crate) fn clamp01<T: Real>(x: &T) -> T {
    x.clamp(&T::zero(), &T::one())
}

/// `x > 0`: `false` for zero, negative values and NaN, so that `!positive(x)`
/// reads as "zero, negative or NaN".
pub(crate) fn positive<T: Real>(x: &T) -> bool {
    *x > T::zero()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turns_exact_at_quarter_points() {
        let hp = f64::pi() / 2.0;
        assert_eq!(cos_sin_turns(&0.0, &hp), (1.0, 0.0));
        assert_eq!(cos_sin_turns(&0.25, &hp), (-0.0, 1.0));
        assert_eq!(cos_sin_turns(&0.5, &hp).0, -1.0);
        assert_eq!(cos_sin_turns(&0.5, &hp).1, 0.0);
        assert_eq!(cos_sin_turns(&0.75, &hp).1, -1.0);
        assert_eq!(cos_sin_turns(&1.0, &hp), (1.0, 0.0));
    }

    #[test]
    fn turns_relative_accuracy_near_one() {
        let hp = f64::pi() / 2.0;
        for d in [1e-6, 1e-12, 2f64.powi(-40)] {
            let v = 1.0 - d;
            let (c, s) = cos_sin_turns(&v, &hp);
            // sin 2πv = −sin(2π(1 − v)), and 1 − v is exact.
            let want = -(2.0 * std::f64::consts::PI * (1.0 - v)).sin();
            assert!(
                (s - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                "{s} {want}"
            );
            let want_c = (2.0 * std::f64::consts::PI * (1.0 - v)).cos();
            assert!((c - want_c).abs() <= 2.0 * f64::EPSILON);
        }
    }

    #[test]
    fn turns_agree_with_naive_in_the_middle() {
        let hp = f64::pi() / 2.0;
        for i in 0..=64 {
            let v = i as f64 / 64.0 + 0.001;
            let (c, s) = cos_sin_turns(&v, &hp);
            let a = 2.0 * std::f64::consts::PI * v;
            assert!((c - a.cos()).abs() < 1e-14 && (s - a.sin()).abs() < 1e-14);
        }
    }

    #[test]
    fn azimuth_inverse_in_unit_interval() {
        let i2p = 1.0 / (2.0 * f64::pi());
        let hp = f64::pi() / 2.0;
        assert_eq!(turns_of(&0.0, &0.0, &i2p), 0.0);
        assert!(turns_of(&-0.0, &1.0, &i2p).is_sign_positive());
        assert_eq!(turns_of(&-1e-300, &1.0, &i2p), 1.0 - f64::EPSILON / 2.0);
        for v in [0.0, 1e-12, 0.125, 0.25, 0.5, 0.7, 1.0 - 1e-12] {
            let (c, s) = cos_sin_turns(&v, &hp);
            let w = turns_of(&s, &c, &i2p);
            assert!((0.0..1.0).contains(&w));
            assert!((w - v).abs() <= 1e-15, "{v} {w}");
        }
    }

    #[test]
    fn clamp_keeps_nan() {
        assert!(clamp_unit(&f64::NAN).is_nan());
        assert_eq!(clamp_unit(&-1.0), 0.0);
        assert_eq!(clamp_unit(&2.0f32), 1.0);
    }
}
