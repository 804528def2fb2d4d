//! Step 4 (inverters) against CDFs with known inverses.
//!
//! Errors are measured against the closed-form inverse evaluated at 512 bits.
//! The unit of error is u · scale(y) with
//! scale = max(|x_exact|, y / F'(x_exact), tiny): where the inverse is well
//! conditioned (y / F' ≤ x, e.g. x^n, convex CDFs) this is "units of roundoff
//! of x"; where F is flat (near y = 1 of a concave CDF) the computed F has an
//! absolute error of order u·y that no method evaluating F can beat, and the
//! unit widens by the condition number y / (x F'(x)).
//!
//! `cargo test --test inverters -- --nocapture` prints the tables.

use areawarp::real::Real;
use areawarp::recipe::{
    Bisection, Cdf1, ClosedForm, FittedCubic, Inversion, Inverter, Newton, Start, Tolerance,
    VandermondeCubic,
};

#[path = "support/known_cdfs.rs"]
mod known_cdfs;
use known_cdfs::*;

// ---------------------------------------------------------------------------
// Reference arithmetic at 512 bits.

#[cfg(feature = "mpfr")]
mod reference {
    use super::*;
    use areawarp::real::{Mpfr, Mpfr256};

    pub type R = Mpfr<512>;

    /// Exact conversion of the tested scalar to 512 bits.
    pub trait Lift: Real {
        fn lift(&self) -> R;
    }
    impl Lift for f64 {
        fn lift(&self) -> R {
            R::from_f64(*self)
        }
    }
    impl Lift for Mpfr256 {
        fn lift(&self) -> R {
            Mpfr(rug::Float::with_val(512, &self.0))
        }
    }

    /// Error of `x` as an inverse of F at `y`, in units of u_T · scale (see
    /// the module docs), and the absolute error.
    pub fn error_units<T: Lift>(fam: Family, y: &T, x: &T) -> (f64, R) {
        let yr = y.lift();
        let (xe, dfe) = with_cdf::<R, _>(fam, |c| {
            let xe = c.inverse_dyn(&yr).clamp(&R::zero(), &R::one());
            let d = c.pdf(&xe);
            (xe, d)
        });
        let err = (x.lift() - &xe).abs();
        let tiny = R::exp2i(-1000);
        let mut scale = xe.abs().max(&tiny);
        if dfe > R::zero() {
            scale = scale.max(&(yr / &dfe));
        }
        let u = T::unit_roundoff().lift();
        ((err.clone() / &(u * &scale)).to_f64(), err)
    }

    /// The condition number y / (x F'(x)) of the inverse at `y`.
    pub fn condition<T: Lift>(fam: Family, y: &T) -> f64 {
        let yr = y.lift();
        with_cdf::<R, _>(fam, |c| {
            let xe = c.inverse_dyn(&yr);
            let d = c.pdf(&xe);
            (yr.clone() / &(d * &xe)).to_f64()
        })
    }
}

// ---------------------------------------------------------------------------
// Honesty checks shared by all inverters.

/// x in the domain and finite, residual reported = |F(x) − y|, iterations
/// within `cap`.
fn check_report<T: Real, C: Cdf1<T> + ?Sized>(c: &C, y: &T, inv: &Inversion<T>, cap: u32) {
    assert!(inv.x.is_finite(), "x = {} not finite at y = {y}", inv.x);
    assert!(
        inv.x >= T::zero() && inv.x <= T::one(),
        "x = {} outside [0, 1]",
        inv.x
    );
    assert!(
        inv.iterations <= cap,
        "{} iterations > cap {cap}",
        inv.iterations
    );
    let r = (c.cdf(&inv.x) - y).abs();
    assert!(
        r == inv.residual,
        "reported residual {} != |F(x) - y| = {r} at y = {y}",
        inv.residual
    );
}

// ---------------------------------------------------------------------------
// Newton.

#[cfg(feature = "mpfr")]
fn newton_sweep<T: reference::Lift>(ys: &[T], label: &str) -> f64 {
    println!("\nsafeguarded Newton (default: Ulps(4), linear start) in {label}");
    println!(
        "{:<34} {:>14} {:>14} {:>10} {:>8}",
        "CDF", "max err/u·x", "max err/u·scl", "max |err|", "max it"
    );
    let newton = Newton::default();
    let mut worst = 0.0f64;
    for fam in Family::all() {
        let (mut pure, mut cond, mut abs_err, mut max_it) = (0.0f64, 0.0f64, 0.0f64, 0u32);
        with_cdf::<T, _>(fam, |c| {
            for y in ys {
                let inv = newton.invert(c, y);
                check_report(c, y, &inv, newton.max_iterations);
                assert!(inv.converged, "{}: not converged at y = {y}", fam.label());
                let (units, err) = reference::error_units(fam, y, &inv.x);
                // Pure units of roundoff of x where the inverse is well
                // conditioned (y / F'(x) ≤ x: the scale is |x|).
                let units_x = if reference::condition(fam, y) <= 1.0 {
                    units
                } else {
                    0.0
                };
                pure = pure.max(units_x);
                cond = cond.max(units);
                abs_err = abs_err.max(err.to_f64());
                max_it = max_it.max(inv.iterations);
            }
        });
        println!(
            "{:<34} {:>14.3} {:>14.3} {:>10.2e} {:>8}",
            fam.label(),
            pure,
            cond,
            abs_err,
            max_it
        );
        assert!(
            cond <= 4.0,
            "{}: error {cond} units of roundoff > 4",
            fam.label()
        );
        worst = worst.max(cond);
    }
    worst
}

#[cfg(feature = "mpfr")]
#[test]
fn newton_f64_within_4_units_of_roundoff() {
    let ys = ys_f64();
    let worst = newton_sweep::<f64>(&ys, "f64");
    println!("worst: {worst:.3} units");
}

#[cfg(feature = "mpfr")]
#[test]
fn newton_256_bits_within_2_pow_minus_200() {
    use areawarp::real::Mpfr256;
    let mut ys: Vec<Mpfr256> = ys_f64().iter().map(|&y| Mpfr256::from_f64(y)).collect();
    ys.extend((1..12).map(|k| Mpfr256::from_ratio(k, 13)));
    ys.push(Mpfr256::one() - &Mpfr256::exp2i(-100));
    ys.push(Mpfr256::exp2i(-200));
    let worst = newton_sweep::<Mpfr256>(&ys, "256 bits");
    println!("worst: {worst:.3} units");
    // And absolutely: ≤ 2^-200 everywhere.
    let bound = reference::R::exp2i(-200);
    for fam in Family::all() {
        with_cdf::<Mpfr256, _>(fam, |c| {
            for y in &ys {
                let inv = Newton::default().invert(c, y);
                let (_, err) = reference::error_units(fam, y, &inv.x);
                assert!(
                    err <= bound,
                    "{}: |x - x_exact| = {err} > 2^-200 at y = {y}",
                    fam.label()
                );
            }
        });
    }
}

#[cfg(feature = "mpfr")]
#[test]
fn newton_every_start_converges() {
    let ys = ys_f64();
    for start in [
        None,
        Some(Start::Midpoint),
        Some(Start::Linear),
        Some(Start::Cubic),
    ] {
        let newton = Newton {
            start,
            ..Newton::default()
        };
        for fam in Family::all() {
            with_cdf::<f64, _>(fam, |c| {
                for y in &ys {
                    let inv = newton.invert(c, y);
                    check_report(c, y, &inv, newton.max_iterations);
                    assert!(inv.converged, "{start:?} {}: y = {y}", fam.label());
                    let (units, _) = reference::error_units(fam, y, &inv.x);
                    assert!(
                        units <= 4.0,
                        "{start:?} {}: {units} units at y = {y}",
                        fam.label()
                    );
                }
            });
        }
    }
}

#[test]
fn newton_iteration_cap_is_respected_and_reported() {
    let c = ExpCdf::<f64>::new(20.0);
    for cap in [0, 1, 2, 3] {
        let newton = Newton {
            max_iterations: cap,
            ..Newton::default()
        };
        let inv = newton.invert(&c, &0.5);
        check_report(&c, &0.5, &inv, cap);
        assert!(
            !inv.converged,
            "cap {cap}: claims convergence with x = {}",
            inv.x
        );
    }
    let inv = Newton::default().invert(&c, &0.5);
    assert!(inv.converged && inv.iterations > 3);
    assert!(inv.residual <= 4.0 * f64::EPSILON);
}

// ---------------------------------------------------------------------------
// Bisection.

#[cfg(feature = "mpfr")]
#[test]
fn bisection_reaches_its_tolerance() {
    use areawarp::real::Mpfr256;
    // Relative tolerance in f64 (noise-limited like Newton, see module docs)...
    let bis = Bisection::default();
    let mut worst = 0.0f64;
    for fam in Family::all() {
        with_cdf::<f64, _>(fam, |c| {
            for y in &ys_f64() {
                let inv = bis.invert(c, y);
                check_report(c, y, &inv, bis.max_iterations);
                assert!(inv.converged, "{}: y = {y}", fam.label());
                let (units, _) = reference::error_units(fam, y, &inv.x);
                worst = worst.max(units);
                assert!(units <= 4.0, "{}: {units} units at y = {y}", fam.label());
            }
        });
    }
    println!("bisection Ulps(2) in f64: worst {worst:.3} units");
    // ...and absolute tolerances, exactly met at 256 bits.
    for e in [-10, -30, -100, -200] {
        let bis = Bisection {
            tolerance: Tolerance::Exp2(e),
            max_iterations: 4096,
        };
        let tol = reference::R::exp2i(e);
        let mut max_it = 0;
        for fam in Family::all() {
            with_cdf::<Mpfr256, _>(fam, |c| {
                for k in 0..=16 {
                    let y = Mpfr256::from_ratio(k, 16);
                    let inv = bis.invert(c, &y);
                    check_report(c, &y, &inv, bis.max_iterations);
                    assert!(inv.converged);
                    let (_, err) = reference::error_units(fam, &y, &inv.x);
                    assert!(err <= tol, "{}: err {err} > 2^{e} at y = {y}", fam.label());
                    max_it = max_it.max(inv.iterations);
                }
            });
        }
        // Bisection halves [0, 1] each step: about -e steps.
        assert!(max_it as i32 <= -e + 1, "2^{e}: {max_it} iterations");
        println!("bisection Exp2({e}) at 256 bits: ≤ {max_it} iterations, error ≤ 2^{e}");
    }
}

#[test]
fn bisection_iteration_cap() {
    let c = PowCdf { n: 3 };
    let bis = Bisection {
        tolerance: Tolerance::Ulps(2),
        max_iterations: 5,
    };
    let inv = bis.invert(&c, &0.3);
    check_report(&c, &0.3, &inv, 5);
    assert_eq!(inv.iterations, 5);
    assert!(!inv.converged);
}

// ---------------------------------------------------------------------------
// Vandermonde cubic + polish.

#[cfg(feature = "mpfr")]
#[test]
fn cubic_error_shrinks_with_each_polish_step() {
    use areawarp::real::Mpfr256;
    let ys: Vec<Mpfr256> = ys_f64().iter().map(|&y| Mpfr256::from_f64(y)).collect();
    println!("\nVandermonde cubic at 256 bits: max |x - x_exact| after k Newton polish steps");
    println!(
        "{:<34} {:>11} {:>11} {:>11} {:>11}",
        "CDF", "k = 0", "k = 1", "k = 2", "k = 3"
    );
    for fam in Family::all() {
        let errs: Vec<f64> = (0..4)
            .map(|k| {
                let inv = VandermondeCubic { polish: k };
                with_cdf::<Mpfr256, _>(fam, |c| {
                    ys.iter()
                        .map(|y| {
                            let r = inv.invert(c, y);
                            check_report(c, y, &r, k);
                            reference::error_units(fam, y, &r.x).1.to_f64()
                        })
                        .fold(0.0, f64::max)
                })
            })
            .collect();
        println!(
            "{:<34} {:>11.2e} {:>11.2e} {:>11.2e} {:>11.2e}",
            fam.label(),
            errs[0],
            errs[1],
            errs[2],
            errs[3]
        );
        // A polish step never increases the residual, and here never the
        // maximum error either.
        for k in 0..3 {
            assert!(
                errs[k + 1] <= errs[k],
                "{}: polish {} -> {} increased the error ({:e} -> {:e})",
                fam.label(),
                k,
                k + 1,
                errs[k],
                errs[k + 1]
            );
        }
        // Where the cubic is a good start (F' bounded away from 0 and
        // smooth: F_a with |a| ≤ 1), Newton converges quadratically: the
        // error strictly shrinks, by many orders of magnitude per step.
        let smooth = matches!(fam, Family::Exp(a) if a.abs() <= 1.0);
        if smooth {
            for k in 0..3 {
                assert!(
                    errs[k + 1] < errs[k] * 1e-2,
                    "{}: polish {} -> {}: {:e} -> {:e}",
                    fam.label(),
                    k,
                    k + 1,
                    errs[k],
                    errs[k + 1]
                );
            }
        }
        if matches!(fam, Family::Pow(1)) {
            // The inverse of x is linear: the cubic is exact.
            assert!(errs[0] < 1e-70);
        }
    }
}

#[test]
fn cubic_polish_never_increases_the_residual() {
    for fam in Family::all() {
        with_cdf::<f64, _>(fam, |c| {
            let fit = FittedCubic::fit(c);
            for y in &ys_f64() {
                let mut prev = f64::INFINITY;
                for k in 0..6 {
                    let r = fit.invert(c, y, k);
                    check_report(c, y, &r, k);
                    // The closing derivative-carrying update may move x by
                    // up to 4 units of roundoff, changing the residual by
                    // about 4u·|x|·F'(x) plus the noise of F (a few u|y|).
                    let u = f64::EPSILON / 2.0;
                    let noise = 4.0 * u * (r.x.abs() * c.pdf(&r.x) + 2.0 * y.abs());
                    assert!(
                        r.residual <= prev.max(noise),
                        "{} y = {y}: residual {} after {k} steps > {prev}",
                        fam.label(),
                        r.residual
                    );
                    prev = r.residual;
                }
            }
        });
    }
}

#[test]
fn fitted_cubic_interpolates_its_nodes() {
    let c = Sin2Cdf;
    let fit = FittedCubic::fit(&c);
    for i in 0..4 {
        let x = i as f64 / 3.0;
        let y: f64 = if i == 0 {
            0.0
        } else if i == 3 {
            1.0
        } else {
            c.cdf(&x)
        };
        assert!((fit.eval(&y) - x).abs() <= 4.0 * f64::EPSILON, "node {i}");
    }
}

// ---------------------------------------------------------------------------
// Ends, flat and steep CDFs: every inverter finite and in the domain.

fn all_inverters_on<C: Cdf1<f64>>(c: &C, label: &str) {
    let ys = ys_f64();
    let newtons = [
        Newton::default(),
        Newton {
            start: Some(Start::Midpoint),
            ..Newton::default()
        },
        Newton {
            start: Some(Start::Cubic),
            ..Newton::default()
        },
    ];
    for y in &ys {
        for n in &newtons {
            let inv = n.invert(c, y);
            check_report(c, y, &inv, n.max_iterations);
            assert!(inv.converged, "{label} {n:?} y = {y}: {inv:?}");
        }
        let inv = Bisection::default().invert(c, y);
        check_report(c, y, &inv, 4096);
        assert!(inv.converged, "{label} bisection y = {y}");
        for k in 0..4 {
            let inv = VandermondeCubic { polish: k }.invert(c, y);
            check_report(c, y, &inv, k);
        }
        let inv = ClosedForm.invert(c, y);
        check_report(c, y, &inv, 200);
    }
}

#[test]
fn inverters_are_finite_at_the_ends_and_on_flat_or_steep_cdfs() {
    for a in [-700.0, -200.0, -20.0, -1e-12, 1e-12, 20.0, 200.0, 700.0] {
        all_inverters_on(&ExpCdf::<f64>::new(a), &format!("exp a = {a}"));
    }
    for n in [1, 2, 10, 40] {
        all_inverters_on(&PowCdf { n }, &format!("x^{n}"));
    }
    all_inverters_on(&Sin2Cdf, "sin2");
    all_inverters_on(&FlatThenCubic, "flat then cubic");
    // The ends exactly.
    let c = PowCdf { n: 5 };
    assert_eq!(Newton::default().invert(&c, &0.0).x, 0.0);
    assert_eq!(Newton::default().invert(&c, &1.0).x, 1.0);
    assert_eq!(Bisection::default().invert(&c, &0.0).x, 0.0);
    assert_eq!(Bisection::default().invert(&c, &1.0).x, 1.0);
    // Out-of-range and NaN inputs still give a point of the domain.
    for y in [-1e-17, 1.0 + 1e-15, f64::NAN] {
        for inv in [
            Newton::default().invert(&c, &y),
            Bisection::default().invert(&c, &y),
            VandermondeCubic { polish: 3 }.invert(&c, &y),
        ] {
            assert!(
                inv.x.is_finite() && (0.0..=1.0).contains(&inv.x),
                "y = {y}: {inv:?}"
            );
        }
    }
}

#[test]
fn flat_region_is_handled() {
    let c = FlatThenCubic;
    // y = 0: any point of the flat part [0, 1/2] is a preimage.
    let inv = Newton::default().invert(&c, &0.0);
    assert!(inv.x <= 0.5 && inv.converged);
    // Interior: the root is right of the flat part; Newton from the midpoint
    // lands where F' = 0 and must bisect its way out.
    for y in [1e-12, 1e-3, 0.1, 0.5, 0.9] {
        let x_exact = Known::<f64>::inverse(&c, &y);
        for n in [
            Newton::default(),
            Newton {
                start: Some(Start::Midpoint),
                ..Newton::default()
            },
        ] {
            let inv = n.invert(&c, &y);
            assert!(inv.converged);
            assert!(
                (inv.x - x_exact).abs() <= 8.0 * f64::EPSILON,
                "y = {y}: {inv:?}"
            );
        }
    }
}

#[test]
fn closed_form_is_used_when_available_and_clamped() {
    let c = ExpCdf::<f64>::new(3.0);
    let inv = ClosedForm.invert(&c, &0.25);
    assert_eq!(inv.iterations, 0);
    assert_eq!(inv.x, Known::<f64>::inverse(&c, &0.25));
    // No closed form: falls back to Newton (iterations > 0).
    let inv = ClosedForm.invert(&PowCdf { n: 3 }, &0.25);
    assert!(inv.iterations > 0 && inv.converged);
    assert!((inv.x - 0.25f64.cbrt()).abs() <= 4.0 * f64::EPSILON);
}

// ---------------------------------------------------------------------------
// Derivatives through the inversion.

#[cfg(feature = "mpfr")]
fn check_dual_derivative<I: Inverter>(inv: &I, name: &str) {
    use areawarp::real::{Dual2, Mpfr256};
    type D = Dual2<Mpfr256>;
    let tol = reference::R::exp2i(-200);
    let mut worst = 0.0f64;
    let mut ys: Vec<f64> = vec![
        0.0,
        1e-12,
        1e-6,
        0.25,
        0.5,
        0.75,
        1.0 - 1e-6,
        1.0 - 1e-12,
        1.0,
    ];
    ys.extend((1..10).map(|k| k as f64 / 10.0));
    for fam in Family::all() {
        with_cdf::<D, _>(fam, |c| {
            for &y in &ys {
                let yd = D::seed_u(Mpfr256::from_f64(y));
                let r = inv.invert(c, &yd);
                // 1/F'(x_exact) at 512 bits; skip where F'(x) = 0 (the
                // inverse has an infinite derivative there).
                let yr = reference::R::from_f64(y);
                let dfe = with_cdf::<reference::R, _>(fam, |c| {
                    let xe = c
                        .inverse_dyn(&yr)
                        .clamp(&reference::R::zero(), &reference::R::one());
                    c.pdf(&xe)
                });
                if dfe <= reference::R::exp2i(-40) {
                    continue;
                }
                let expected = reference::R::one() / &dfe;
                let got = reference::Lift::lift(&r.x.du);
                let rel = (got - &expected).abs() / &expected;
                assert!(
                    rel <= tol,
                    "{name} {}: dx/dy = {} vs 1/F' = {expected} (rel {rel}) at y = {y}",
                    fam.label(),
                    r.x.du
                );
                assert!(r.x.dv == Mpfr256::zero());
                worst = worst.max(rel.to_f64());
            }
        });
    }
    println!("{name} over Dual2<Mpfr256>: max relative error of dx/dy vs 1/F'(x): {worst:.2e}");
}

#[cfg(feature = "mpfr")]
#[test]
fn newton_over_duals_gives_implicit_derivative() {
    check_dual_derivative(&Newton::default(), "Newton");
    check_dual_derivative(
        &Newton {
            start: Some(Start::Midpoint),
            ..Newton::default()
        },
        "Newton (midpoint start)",
    );
}

#[cfg(feature = "mpfr")]
#[test]
fn bisection_and_polished_cubic_over_duals_give_implicit_derivative() {
    check_dual_derivative(&Bisection::default(), "Bisection");
    // Four polish steps reach 256-bit accuracy from the cubic guess on these
    // CDFs only approximately; the derivative needs F(x) ≈ y to ~2^-200, so
    // use the converged Newton with a cubic start instead.
    check_dual_derivative(
        &Newton {
            start: Some(Start::Cubic),
            ..Newton::default()
        },
        "Newton (cubic start)",
    );
}

#[cfg(feature = "mpfr")]
#[test]
fn zero_density_at_the_root_gives_a_non_finite_derivative() {
    use areawarp::real::{Dual2, Mpfr256};
    type D = Dual2<Mpfr256>;
    // F = x² at y = 0 and sin²(πx/2) at y = 0 and 1: F'(x) = 0 there and
    // dx/dy = ∞. The value must be exact, the derivative non-finite (not a
    // silent 0, which would fake a degenerate Jacobian).
    let y0 = D::seed_u(Mpfr256::zero());
    let y1 = D::seed_u(Mpfr256::one());
    let cases: Vec<(Inversion<D>, Mpfr256)> = vec![
        (
            Newton::default().invert(&PowCdf { n: 2 }, &y0),
            Mpfr256::zero(),
        ),
        (
            Bisection::default().invert(&PowCdf { n: 2 }, &y0),
            Mpfr256::zero(),
        ),
        (Newton::default().invert(&Sin2Cdf, &y0), Mpfr256::zero()),
        (Newton::default().invert(&Sin2Cdf, &y1), Mpfr256::one()),
        (
            VandermondeCubic { polish: 1 }.invert(&Sin2Cdf, &y1),
            Mpfr256::one(),
        ),
    ];
    for (inv, x) in cases {
        assert!(inv.x.re == x, "{inv:?}");
        // (cos(π/2) rounds to ~1e-77, not 0, at 256 bits: then the
        // derivative is merely astronomically large.)
        let du = inv.x.du.clone();
        assert!(!du.is_finite() || du.abs() > Mpfr256::exp2i(200), "{inv:?}");
    }
    // In plain f64 the same paths return the exact ends.
    assert_eq!(Newton::default().invert(&PowCdf { n: 2 }, &0.0).x, 0.0);
    assert_eq!(Newton::default().invert(&Sin2Cdf, &1.0).x, 1.0);
}

/// Counts evaluations of F and F'.
struct Counting<C> {
    inner: C,
    cdf_calls: std::cell::Cell<u32>,
    pdf_calls: std::cell::Cell<u32>,
}

impl<C: Cdf1<f64>> Cdf1<f64> for Counting<C> {
    fn cdf(&self, x: &f64) -> f64 {
        self.cdf_calls.set(self.cdf_calls.get() + 1);
        self.inner.cdf(x)
    }
    fn pdf(&self, x: &f64) -> f64 {
        self.pdf_calls.set(self.pdf_calls.get() + 1);
        self.inner.pdf(x)
    }
}

#[test]
fn iteration_caps_bound_the_work() {
    // A CDF where Newton needs many steps (the root of x^7 at y = 1e-12
    // sits where F' is tiny), capped at k iterations: exactly k updates,
    // k + 1 evaluations of F (one for the start) and k of F'.
    for k in [0u32, 1, 5, 10] {
        let c = Counting {
            inner: PowCdf { n: 7 },
            cdf_calls: 0.into(),
            pdf_calls: 0.into(),
        };
        let newton = Newton {
            max_iterations: k,
            ..Newton::default()
        };
        let inv = newton.invert(&c, &1e-12);
        assert!(!inv.converged, "k = {k}: {inv:?}");
        assert_eq!(inv.iterations, k);
        assert_eq!(c.cdf_calls.get(), k + 1, "k = {k}");
        assert_eq!(c.pdf_calls.get(), k, "k = {k}");
        assert!(inv.x.is_finite() && (0.0..=1.0).contains(&inv.x));
    }
    // Bisection: k halvings, k + 1 evaluations of F (the last for the
    // reported residual), no F' when not converged.
    let c = Counting {
        inner: PowCdf { n: 7 },
        cdf_calls: 0.into(),
        pdf_calls: 0.into(),
    };
    let inv = Bisection {
        tolerance: Tolerance::Ulps(2),
        max_iterations: 7,
    }
    .invert(&c, &0.3);
    assert_eq!((inv.iterations, inv.converged), (7, false));
    assert_eq!((c.cdf_calls.get(), c.pdf_calls.get()), (8, 0));
    // The cubic: 4 evaluations of F to fit, then per polish step one F and
    // one F' (plus the first F at the guess and the closing F').
    let c = Counting {
        inner: ExpCdf::<f64>::new(1.0),
        cdf_calls: 0.into(),
        pdf_calls: 0.into(),
    };
    let fit = FittedCubic::fit(&c);
    assert_eq!(c.cdf_calls.get(), 4);
    let inv = fit.invert(&c, &0.3, 2);
    assert_eq!(inv.iterations, 2);
    assert!(c.cdf_calls.get() <= 4 + 1 + 2 + 1 && c.pdf_calls.get() <= 2 + 1);
}
