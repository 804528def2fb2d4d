//! Keeps `examples/cosine_weighted_cap.rs` honest: a warp derived from φ and
//! w = cos θ alone has the cap's projected solid angle as its measure, a
//! conditional that depends on s, and the harness passes.
#![cfg(feature = "mpfr")]

#[allow(dead_code)]
#[path = "../examples/cosine_weighted_cap.rs"]
mod example;

use areawarp::WarpError;
use areawarp::harness::{extremes::extremes_grid, jacobian::check_jacobian};
use example::{CAPS, CosineCap, cosine_cap_warp, quick_checks};

#[test]
fn cosine_caps_pass_the_f64_checks() {
    for (theta_max, beta) in CAPS {
        let c = quick_checks(theta_max, beta).unwrap();
        assert!(c.measure_error < 1e-13, "{c:?}");
        assert!(c.jacobian_f64 < 1e-12, "{c:?}");
        assert_eq!(c.roundtrip.1, 0, "{c:?}");
        assert!(c.roundtrip.0 <= 16.0, "{c:?}");
        assert!(c.table.1 <= 1e-9, "{c:?}");
    }
    // The wider caps have a conditional that the table must follow in s.
    let wide = quick_checks(1.2, 0.3).unwrap();
    assert!(wide.table.0 > 1, "{wide:?}");
}

#[test]
fn caps_below_the_horizon_are_refused() {
    assert!(matches!(
        CosineCap::new(1.0, 0.6),
        Err(WarpError::InvalidParameter { .. })
    ));
    assert!(CosineCap::new(f64::NAN, 0.1).is_err());
}

#[test]
#[ignore = "the Jacobian at 256 bits (minutes)"]
fn cosine_cap_jacobian_at_256_bits() {
    let w = cosine_cap_warp(0.3, 0.6).unwrap();
    let r = check_jacobian(&w, &extremes_grid()).unwrap();
    println!("{r:?}");
    assert!(r.passes(1e-60), "{r:?}");
}
