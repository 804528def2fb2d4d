//! Keeps `examples/define_your_own_warp.rs` honest: the spherical cap defined
//! by φ alone, its CDFs derived by quadrature and inverted numerically,
//! passes the harness at 256 bits, and the checks it passes have teeth.
#![cfg(feature = "mpfr")]

#[allow(dead_code)]
#[path = "../examples/define_your_own_warp.rs"]
mod example;

use areawarp::harness::extremes::extremes_grid;
use areawarp::harness::jacobian::check_jacobian;
use areawarp::real::Real;
use areawarp::recipe::{AreaDensity, Bisection, DerivedRecipe, DerivedWarp, RecipeWarp, Tolerance};
use areawarp::{Warp, WarpError};
use example::{Cap, JACOBIAN_BOUND, THETAS, cap_warp, check_cap};

#[test]
fn cap_example_passes_every_check() {
    for theta in THETAS {
        let c = check_cap(theta).expect("valid cap");
        assert!(c.passes(), "theta_max = {theta}: {c:#?}");
        // Far below the bound: exact to ~256 bits.
        assert!(c.jacobian.max_rel_deviation < 1e-70, "{:?}", c.jacobian);
        // Only the pole u = 0 (8 grid points) is singular (at θ_max = π the
        // antipode is one too, but sin(π) rounds to a tiny positive value:
        // σ stays positive there and the check needs no nudge).
        assert_eq!(c.jacobian.nudged, 8, "{:?}", c.jacobian);
        assert_eq!(c.jacobian.points, 64);
        assert_eq!(c.precision.non_finite + c.precision.outside, 0);
    }
}

#[test]
fn cap_points_lie_on_the_cap_with_the_right_area() {
    let theta: f64 = 1.0;
    let w = cap_warp(theta).unwrap();
    let area = 2.0 * std::f64::consts::PI * (1.0 - theta.cos());
    assert!((w.measure() - area).abs() < 1e-14);
    for &(u, v) in &extremes_grid() {
        let p = w.map(&u, &v);
        assert!((p.norm() - 1.0).abs() < 1e-15, "{p:?}");
        assert!(p.z >= theta.cos() - 1e-15, "({u}, {v}) -> {p:?}");
        assert!((w.pdf(&p) * area - 1.0).abs() < 1e-14);
    }
    // u selects the polar angle: u = 1 is the rim, u = 0 the pole.
    assert!((w.map(&1.0, &0.3).z - theta.cos()).abs() < 1e-15);
    assert_eq!(w.map(&0.0, &0.3).z, 1.0);
    // The area density of step 2 (derived by dual numbers) is 2π θ sin(θ s).
    let r = Cap::new(theta).unwrap();
    let s = 0.4;
    let sigma = 2.0 * std::f64::consts::PI * theta * (theta * s).sin();
    assert!((r.sigma(&s, &0.7) - sigma).abs() < 1e-14);
}

#[test]
fn invalid_angles_are_rejected() {
    for bad in [0.0, -1.0, 3.2] {
        assert!(
            matches!(Cap::new(bad), Err(WarpError::InvalidParameter { .. })),
            "{bad}"
        );
    }
    assert!(matches!(
        Cap::new(f64::NAN),
        Err(WarpError::NonFinite { .. })
    ));
    assert!(Cap::new(std::f64::consts::PI).is_ok());
}

#[test]
fn jacobian_check_sees_an_inaccurate_inversion() {
    // The same recipe inverted only to 2^-20: the map is then not exactly
    // area-preserving, and the 256-bit check must say so.
    let coarse = Bisection {
        tolerance: Tolerance::Exp2(-20),
        max_iterations: 100,
    };
    let recipe = DerivedRecipe::new(Cap::new(1.0).unwrap()).unwrap();
    let w = RecipeWarp::new(recipe, coarse, coarse);
    let r = check_jacobian(&w, &extremes_grid()).unwrap();
    assert!(!r.passes(JACOBIAN_BOUND), "{r:?}");
    assert!(r.max_rel_deviation > 1e-12, "{r:?}");
    // And the f64 warp is generic: the same code runs in f32.
    let w32 = DerivedWarp::new(Cap::<f32>::new(1.0).unwrap()).unwrap();
    let p = w32.map(&0.5, &0.25);
    assert!(p.is_finite() && (p.norm() - 1.0).abs() < 4.0 * f32::unit_roundoff());
}
