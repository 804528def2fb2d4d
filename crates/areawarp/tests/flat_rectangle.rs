//! A spherical rectangle seen from nearly in its plane, whose cone is flat:
//! its four faces coincide to 10⁻¹⁴, and it subtends a sliver 10⁻¹⁵ sr
//! wide along an arc of 0.46 rad. The light fuzz found it at
//! `AREAWARP_FUZZ_SEED=132` (kind "grazing", at a scale of 10¹⁸): in `f32`
//! the sample at `(0, ½)`, 1.2·10⁻⁷ from the sliver by a 256-bit
//! evaluation, was judged 0.074 off the rectangle by `outside_by` and
//! refused by `inverse`, because no face's distance passed its sign tests
//! (`robust/cone.rs`, `Cone::outside_local`).

use areawarp::shapes::SphericalRectangle;
use areawarp::{Real, Warp};

#[path = "support/light_cases.rs"]
mod light_cases;
use light_cases::{unit_values, v3};

/// The rectangle of the fuzz case (corner, edges, observer).
fn rectangle<T: Real>() -> SphericalRectangle<T> {
    SphericalRectangle::new(
        v3(&[
            9.808279316793128e16,
            1.8625139445873542e17,
            -3.1670312939368545e18,
        ]),
        v3(&[
            1.2058203238242654e17,
            -1.9428118135015866e17,
            -5.0610371909660504e16,
        ]),
        v3(&[
            -1976913705970742.0,
            -2.934190524017652e16,
            1.0792648887001467e17,
        ]),
        v3(&[
            -2.1314089496084532e16,
            3.6953855459814106e17,
            -3.087007233459982e18,
        ]),
    )
    .expect("the fuzz case is accepted")
}

/// Every sample at the fuzz's values of `u`, `v` lies on the rectangle by
/// its own `outside_by` (within its `on_shape_tolerance`, 2^(−p/2)) and is
/// accepted by its inverse; a direction moved
/// off the sliver by δ (along the rectangle's normal, across the flat cone)
/// is judged δ away to 10 %, so the rounding slack of the face tests does
/// not hide a real distance.
fn check<T: Real>() {
    let w = rectangle::<T>();
    let n = w.normal().clone();
    for u in unit_values::<T>() {
        for v in unit_values::<T>() {
            let d = w.map(&u, &v);
            let off = w.outside_by(&d);
            assert!(
                off <= w.on_shape_tolerance(),
                "u = {u:?}, v = {v:?}: outside_by {off:?}"
            );
            assert!(
                w.inverse(&d).is_ok(),
                "u = {u:?}, v = {v:?}: refused by the inverse"
            );
            for delta in [T::exp2i(-10), T::exp2i(-6)] {
                let moved = d.add(&n.scale(&delta)).normalized().expect("a unit vector");
                let judged = w.outside_by(&moved) / &delta;
                assert!(
                    judged >= T::from_ratio(9, 10) && judged <= T::from_ratio(11, 10),
                    "u = {u:?}, v = {v:?}: moved by {delta:?}, judged {judged:?} times that"
                );
            }
        }
    }
}

#[test]
fn flat_rectangle_samples_are_on_it_in_f32() {
    check::<f32>();
}

#[test]
fn flat_rectangle_samples_are_on_it_in_f64() {
    check::<f64>();
}
