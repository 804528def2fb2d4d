//! Tests of the spherical rectangle: validation, the ladder of hard shapes
//! (accuracy against 256 bits relative to the map's own sensitivity), the
//! recipe specification, the Jacobian, the inverse, the densities and χ².

use super::*;
use crate::harness::chi2::{Binning, run_chi_square};
use crate::harness::extremes::{extremes_grid, random_points};
use crate::vector::Vec3;

type V = SphericalRectangleVariant;

fn all_shapes() -> Vec<(String, [Vec3<f64>; 4])> {
    let mut v = hard_rectangles();
    v.extend(ordinary_rectangles());
    v
}

fn build<T: Real>(p: &[Vec3<f64>; 4], variant: V) -> Result<SphericalRectangle<T>, WarpError> {
    SphericalRectangle::<f64>::new_with(p[0], p[1], p[2], p[3], variant)?.at::<T>()
}

fn v3(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}

fn unit_square() -> [Vec3<f64>; 4] {
    [
        v3(-0.5, -0.5, -1.0),
        v3(1.0, 0.0, 0.0),
        v3(0.0, 1.0, 0.0),
        v3(0.0, 0.0, 0.0),
    ]
}

#[test]
fn spherical_rectangle_constructor_errors() {
    let [s, ex, ey, o] = unit_square();
    let new = |s: Vec3<f64>, ex: Vec3<f64>, ey: Vec3<f64>, o: Vec3<f64>| {
        SphericalRectangle::new(s, ex, ey, o)
    };
    assert!(new(s, ex, ey, o).is_ok());
    let nan = v3(f64::NAN, 0.0, 0.0);
    let inf = v3(0.0, f64::INFINITY, 0.0);
    for (i, bad) in [nan, inf].into_iter().enumerate() {
        let e = [
            new(bad, ex, ey, o),
            new(s, bad, ey, o),
            new(s, ex, bad, o),
            new(s, ex, ey, bad),
        ];
        for (j, r) in e.into_iter().enumerate() {
            assert!(
                matches!(r, Err(WarpError::NonFinite { .. })),
                "{i} {j}: {r:?}"
            );
        }
    }
    // Zero-length edges.
    let r = new(s, Vec3::zero(), ey, o);
    assert!(matches!(r, Err(WarpError::Degenerate { .. })), "{r:?}");
    let r = new(s, ex, Vec3::zero(), o);
    assert!(matches!(r, Err(WarpError::Degenerate { .. })), "{r:?}");
    // Perpendicularity: |cos| = 32 u accepted, 128 u rejected.
    let u = f64::EPSILON / 2.0;
    let ok = new(s, ex, v3(32.0 * u, 1.0, 0.0), o);
    assert!(ok.is_ok(), "{ok:?}");
    let skew = new(s, ex, v3(128.0 * u, 1.0, 0.0), o);
    assert!(
        matches!(skew, Err(WarpError::InvalidParameter { .. })),
        "{skew:?}"
    );
    let skew = new(s, ex, v3(0.5, 1.0, 0.0), o);
    assert!(matches!(skew, Err(WarpError::InvalidParameter { .. })));
    // The squared-up edge is exactly perpendicular.
    let r = ok.unwrap();
    assert_eq!(r.edge_y().x, 0.0);
    // Observer exactly in the plane (inside or outside the rectangle).
    for o in [v3(0.1, 0.2, -1.0), v3(3.0, -2.0, -1.0)] {
        let r = new(s, ex, ey, o);
        assert!(matches!(r, Err(WarpError::Degenerate { .. })), "{r:?}");
    }
    // A subnormal edge (either one, or both, long or short partners):
    // no such rectangle has a density in area the type can hold
    // (`subnormal_edge`); the overflowed frame used to fail the
    // perpendicularity test instead.
    for (a, b) in [
        (1e-310, 1e-310),
        (1e-310, 1.0),
        (1.0, 1e-310),
        (1e-320, 1e300),
    ] {
        let r = new(
            v3(0.0, 0.0, 0.0),
            v3(a, 0.0, 0.0),
            v3(0.0, b, 0.0),
            v3(0.0, 0.0, 1e-300),
        );
        let what = "density in area measure outside the scalar type's range";
        assert!(
            matches!(r, Err(WarpError::Unrepresentable { what: w }) if w == what),
            "{a:e} × {b:e}: {r:?}"
        );
    }
    // Zero solid angle: so far away that Ω underflows.
    let r = new(s, ex, ey, v3(0.0, 0.0, 1e200));
    assert!(matches!(r, Err(WarpError::Degenerate { .. })), "{r:?}");
    // The same errors at f32; a tiny but non-zero height is accepted while
    // h² stays a normal f32 number with 24 bits to spare (h ≥ 2^-51 times
    // the rectangle's scale), rejected as unrepresentable below.
    let r = SphericalRectangle::<f32>::new(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(-0.5, 0.5, 1e-15),
    );
    assert!(r.is_ok(), "{r:?}");
    for h in [1e-30f32, 1e-38] {
        let r = SphericalRectangle::<f32>::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-0.5, 0.5, h),
        );
        assert!(matches!(r, Err(WarpError::Unrepresentable { .. })), "{r:?}");
    }
    let r = SphericalRectangle::<f32>::new(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1e-3, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    );
    assert!(matches!(r, Err(WarpError::InvalidParameter { .. })));
}

#[test]
fn spherical_rectangle_variant_names() {
    assert_eq!(V::default(), V::Robust);
    assert_eq!("Literal".parse::<V>().unwrap(), V::Literal);
    assert_eq!(" robust ".parse::<V>().unwrap(), V::Robust);
    assert!("fast".parse::<V>().is_err());
    assert_eq!(V::Literal.to_string(), "literal");
    let [s, ex, ey, o] = unit_square();
    let r = SphericalRectangle::new_with(s, ex, ey, o, V::Literal).unwrap();
    assert_eq!(r.name(), "spherical-rectangle");
    assert_eq!(r.variant(), V::Literal);
    assert_eq!(r.at::<f32>().unwrap().variant(), V::Literal);
    assert_eq!(r.clone().with_variant(V::Robust).variant(), V::Robust);
}

#[test]
fn spherical_rectangle_head_on_square() {
    let [s, ex, ey, o] = unit_square();
    for variant in [V::Robust, V::Literal] {
        let r = SphericalRectangle::new_with(s, ex, ey, o, variant).unwrap();
        let omega = 4.0 * 0.2f64.asin();
        assert!((r.solid_angle() / omega - 1.0).abs() <= 2.0 * f64::EPSILON);
        assert!((r.girard_solid_angle() / omega - 1.0).abs() <= 1e-14);
        // The centre and the corners.
        let (p, d) = r.sample_point(&0.5, &0.5);
        assert!(
            p.x.hypot(p.y) < 1e-15 && p.z == -1.0 && (d.z + 1.0).abs() < 1e-15,
            "{variant}: {p:?}"
        );
        for (u, v, x, y) in [
            (0.0, 0.0, -0.5, -0.5),
            (1.0, 0.0, 0.5, -0.5),
            (0.0, 1.0, -0.5, 0.5),
            (1.0, 1.0, 0.5, 0.5),
        ] {
            let (p, _) = r.sample_point(&u, &v);
            assert!(
                (p.x - x).abs() < 1e-15 && (p.y - y).abs() < 1e-15,
                "{variant}: {p:?}"
            );
        }
    }
    // Robust: the edges exactly.
    let r = SphericalRectangle::new(s, ex, ey, o).unwrap();
    for t in [0.0, 1e-12, 0.3, 0.5, 0.9, 1.0] {
        assert_eq!(r.sample_point(&0.0, &t).0.x, -0.5);
        assert_eq!(r.sample_point(&1.0, &t).0.x, 0.5);
        assert_eq!(r.sample_point(&t, &0.0).0.y, -0.5);
        assert_eq!(r.sample_point(&t, &1.0).0.y, 0.5);
    }
}

#[cfg(feature = "mpfr")]
mod accuracy;

#[cfg(feature = "mpfr")]
mod exact {
    //! The recipe specification, the Jacobian and Ω at 256 bits.
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::harness::jacobian::check_jacobian;
    use crate::real::Mpfr256;
    use crate::recipe::{
        AreaDensity, ClosedForm, MarginalConditional, Newton, Parametrization, Recipe, RecipeWarp,
        Start, Tolerance,
    };

    type M = Mpfr256;

    fn recipe_at_256(shape: &[Vec3<f64>; 4]) -> SphericalRectangleRecipe<M> {
        SphericalRectangleRecipe::<f64>::new(shape[0], shape[1], shape[2], shape[3])
            .unwrap()
            .recast::<M>()
            .unwrap()
    }

    fn newton() -> Newton {
        Newton {
            tolerance: Tolerance::Ulps(4),
            max_iterations: 600,
            start: Some(Start::Linear),
        }
    }

    /// The robust map at 256 bits equals the recipe-composed map (Newton on
    /// F, the closed form for G) to 2⁻²⁰⁰ on the extremes grid.
    fn recipe_agrees(shapes: &[(String, [Vec3<f64>; 4])]) {
        let tol = M::exp2i(-200);
        for (name, shape) in shapes {
            let spec = RecipeWarp::new(recipe_at_256(shape), newton(), ClosedForm);
            let direct = build::<M>(shape, V::Robust).unwrap();
            let rel = (spec.measure() - &direct.solid_angle()).abs() / &direct.solid_angle();
            assert!(rel <= tol, "{name}: Ω {rel}");
            let mut worst = M::zero();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let (u, v) = (M::from_f64(u), M::from_f64(v));
                    let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                    if d > worst {
                        worst = d;
                    }
                }
            }
            println!(
                "{name:<34} recipe vs robust at 256 bits: {:.3e}",
                worst.to_f64()
            );
            assert!(worst <= tol, "{name}: {worst}");
        }
    }

    #[test]
    fn spherical_rectangle_recipe_matches_robust_ordinary() {
        recipe_agrees(&ordinary_rectangles());
    }

    #[test]
    fn spherical_rectangle_recipe_matches_robust_hard() {
        recipe_agrees(&hard_rectangles());
    }

    /// The paper's closed-form F⁻¹ (Appendix A) against Newton at 256 bits:
    /// 2⁻²⁰⁰ on ordinary rectangles; the loss on the hard ones is printed.
    #[test]
    fn spherical_rectangle_recipe_closed_form_marginal() {
        for (name, shape) in all_shapes() {
            let r = recipe_at_256(&shape);
            let mut worst = M::zero();
            for &u in &EXTREMES[1..7] {
                let u = M::from_f64(u);
                let closed = r.marginal_inverse(&u).unwrap();
                let numeric =
                    crate::recipe::Inverter::invert(&newton(), &crate::recipe::Marginal(&r), &u).x;
                let d = (closed - &numeric).abs();
                if d > worst {
                    worst = d;
                }
            }
            println!(
                "{name:<34} closed-form F⁻¹ vs Newton: {:.3e}",
                worst.to_f64()
            );
            if ordinary_rectangles().iter().any(|(n, _)| *n == name) {
                assert!(worst <= M::exp2i(-200), "{name}: {worst}");
            }
        }
    }

    /// σ (by dual numbers) is `h Lx Ly / r³`, F' and ∂G/∂t are the
    /// derivatives of F and G, and the CDFs run from 0 to 1.
    #[test]
    fn spherical_rectangle_recipe_steps_consistent() {
        for (name, shape) in ordinary_rectangles()
            .into_iter()
            .chain(hard_rectangles().into_iter().take(4))
        {
            let r = recipe_at_256(&shape);
            let g = &r.geometry;
            let tol = M::exp2i(-230);
            let hstep = M::exp2i(-80);
            for (sn, tn) in [(1, 3), (1, 2), (5, 7), (9, 10)] {
                let (s, t) = (M::from_ratio(sn, 10), M::from_ratio(tn, 10));
                let x = g.x0.clone() + &(s.clone() * &g.lx);
                let y = g.y0.clone() + &(t.clone() * &g.ly);
                let r3 = (x.square() + &y.square() + &g.h.square()).sqrt().powi(3);
                let closed = g.h.clone() * &g.lx * &g.ly / &r3;
                let sigma = r.sigma(&s, &t);
                assert!(
                    (sigma.clone() - &closed).abs() <= tol.clone() * &closed,
                    "{name}: σ"
                );
                let two_h = hstep.clone() * &M::from_i64(2);
                let fd = (r.marginal_cdf(&(s.clone() + &hstep))
                    - &r.marginal_cdf(&(s.clone() - &hstep)))
                    / &two_h;
                let fp = r.marginal_pdf(&s);
                assert!((fd - &fp).abs() <= M::exp2i(-120) * &fp, "{name}: F'");
                let gd = (r.conditional_cdf(&s, &(t.clone() + &hstep))
                    - &r.conditional_cdf(&s, &(t.clone() - &hstep)))
                    / &two_h;
                let gp = r.conditional_pdf(&s, &t);
                assert!((gd - &gp).abs() <= M::exp2i(-120) * &gp, "{name}: G'");
                // ∫σ dt over the column = m F'(s): σ/(m F') is the conditional density.
                let cond = sigma / &(r.measure() * &fp);
                assert!(
                    (cond - &gp).abs() <= M::exp2i(-200) * &gp,
                    "{name}: σ = m F' G'"
                );
            }
            assert!(r.marginal_cdf(&M::zero()).abs() <= tol);
            assert!((r.marginal_cdf(&M::one()) - &M::one()).abs() <= M::exp2i(-200));
            let s = M::from_ratio(1, 3);
            assert!(r.conditional_cdf(&s, &M::zero()).abs() <= tol);
            assert!((r.conditional_cdf(&s, &M::one()) - &M::one()).abs() <= tol);
            // The chart inverts φ.
            let (s2, t2) = r.chart(&r.phi(&s, &M::from_ratio(2, 3))).unwrap();
            assert!((s2 - &s).abs() <= M::exp2i(-200), "{name}: chart");
            assert!(
                (t2 - &M::from_ratio(2, 3)).abs() <= M::exp2i(-200),
                "{name}: chart"
            );
        }
    }

    /// `|ψ_u × ψ_v| · pdf = 1` at 256 bits on the extremes grid, for every
    /// shape of the ladder and the ordinary ones.
    #[test]
    fn spherical_rectangle_jacobian_256_bits() {
        for (name, shape) in all_shapes() {
            let w = build::<f64>(&shape, V::Robust).unwrap();
            let r = check_jacobian(&w, &extremes_grid()).unwrap();
            println!(
                "{name:<34} Jacobian: max |J·pdf − 1| = {:.3e}",
                r.max_rel_deviation
            );
            assert!(r.passes(1e-60), "{name}: {r:?}");
            assert_eq!(r.nudged, 0, "{name}: {r:?}");
        }
    }

    /// Van Oosterom–Strackee solid angle of the triangle `abc` seen from the
    /// origin.
    fn vos(a: &Vec3<M>, b: &Vec3<M>, c: &Vec3<M>) -> M {
        let det = a.dot(&b.cross(c)).abs();
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let den =
            la.clone() * &lb * &lc + &(a.dot(b) * &lc) + &(a.dot(c) * &lb) + &(b.dot(c) * &la);
        det.atan2(&den) * &M::from_i64(2)
    }

    /// Ω against an independent closed form (two triangles by Van
    /// Oosterom–Strackee, in world coordinates) at 256 bits; the f64 value
    /// within 16·max(2⁻⁵³, κ_Ω) of it, κ_Ω its sensitivity to one-ulp input
    /// changes.
    #[test]
    fn spherical_rectangle_solid_angle_independent() {
        let conv = |v: &Vec3<f64>| Vec3::new(M::from_f64(v.x), M::from_f64(v.y), M::from_f64(v.z));
        for (name, shape) in all_shapes() {
            let w = build::<M>(&shape, V::Robust).unwrap();
            let (s, ex, ey, o) = (
                w.corner().clone(),
                w.edge_x().clone(),
                w.edge_y().clone(),
                w.observer().clone(),
            );
            let a = s.sub(&o);
            let b = a.add(&ex);
            let c = b.add(&ey);
            let d = a.add(&ey);
            let omega = vos(&a, &b, &c) + &vos(&a, &c, &d);
            let rel = ((w.solid_angle() - &omega) / &omega).abs();
            assert!(rel <= M::exp2i(-200), "{name}: {rel}");
            // f64 against the same at 256 bits, and κ_Ω.
            let w64 = build::<f64>(&shape, V::Robust).unwrap();
            let err = ((M::from_f64(w64.solid_angle()) - &omega) / &omega)
                .abs()
                .to_f64();
            let mut kappa: f64 = 0.0;
            let mut p = shape;
            for i in 0..4 {
                for k in 0..3 {
                    let orig = p[i].to_array()[k];
                    for x in [orig.next_up(), orig.next_down()] {
                        let mut arr = p[i].to_array();
                        arr[k] = x;
                        p[i] = Vec3::new(arr[0], arr[1], arr[2]);
                        if let Ok(wp) = build::<M>(&p, V::Robust) {
                            let k = ((wp.solid_angle() - &omega) / &omega).abs().to_f64();
                            kappa = kappa.max(k);
                        }
                        arr[k] = orig;
                        p[i] = Vec3::new(arr[0], arr[1], arr[2]);
                    }
                }
            }
            let ulp = f64::EPSILON / 2.0;
            let girard = build::<f64>(&shape, V::Literal)
                .unwrap()
                .girard_solid_angle();
            let girard_err = ((M::from_f64(girard) - &omega) / &omega).abs().to_f64();
            println!(
                "{name:<34} Ω = {:.6e}: f64 {:.2} u (κ_Ω {:.2} u); Girard (literal) rel. error {:.2e}",
                omega.to_f64(),
                err / ulp,
                kappa / ulp,
                girard_err
            );
            assert!(
                err <= 16.0 * ulp.max(kappa),
                "{name}: {err:e} vs κ {kappa:e}"
            );
            let _ = conv;
        }
    }
}

/// The solid-angle density reported with each sample equals the standalone
/// density of its direction (both variants, every shape), and the area
/// density reported equals the standalone one at its point.
#[test]
fn spherical_rectangle_pdf_consistent() {
    let mut pts = extremes_grid();
    pts.extend(random_points(64, 11));
    let ordinary: Vec<String> = ordinary_rectangles().into_iter().map(|(n, _)| n).collect();
    for (name, shape) in all_shapes() {
        for variant in [V::Robust, V::Literal] {
            let w = build::<f64>(&shape, variant).unwrap();
            let mut worst_area: f64 = 0.0;
            for &(u, v) in &pts {
                let s = w.sample_light([u, v]);
                let pdf = w.pdf(&s.direction);
                assert!(
                    (pdf / s.pdf - 1.0).abs() <= 1e-12,
                    "{name} {variant} ({u}, {v}): {pdf} vs {}",
                    s.pdf
                );
                assert!(
                    (s.pdf * w.measure() - 1.0).abs() <= 2.0 * f64::EPSILON,
                    "{name}"
                );
                // The sampler's shortcut (no on-shape test) agrees with
                // the map and the standalone density.
                let (d, p) = w.map_with_pdf(&u, &v);
                assert_eq!(d, s.direction, "{name} {variant}");
                assert_eq!(p, pdf, "{name} {variant} ({u}, {v})");
                let area = w.pdf_area(&s.point);
                worst_area = worst_area.max((area / s.pdf_area - 1.0).abs());
            }
            if variant == V::Literal || ordinary.contains(&name) {
                assert!(worst_area <= 1e-12, "{name} {variant}: {worst_area:e}");
            }
        }
    }
}

/// pdf_area = cos θ / (Ω r²) by hand for the head-on square, and the two
/// densities integrate to 1 (a midpoint sum over the square).
#[test]
fn spherical_rectangle_area_density() {
    let [s, ex, ey, o] = unit_square();
    let w = SphericalRectangle::new(s, ex, ey, o).unwrap();
    let p = Vec3::new(0.3, -0.2, -1.0);
    let r2: f64 = 0.09 + 0.04 + 1.0;
    let want = (1.0 / r2.sqrt()) / (w.solid_angle() * r2);
    assert!((w.pdf_area(&p) / want - 1.0).abs() < 1e-14);
    let n = 200;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let x = -0.5 + (i as f64 + 0.5) / n as f64;
            let y = -0.5 + (j as f64 + 0.5) / n as f64;
            sum += w.pdf_area(&Vec3::new(x, y, -1.0));
        }
    }
    sum /= (n * n) as f64;
    assert!((sum - 1.0).abs() < 1e-4, "{sum}");
    // Off the rectangle: 0.
    assert_eq!(w.pdf_area(&Vec3::new(0.7, 0.0, -1.0)), 0.0);
    assert_eq!(w.pdf_area(&Vec3::new(0.0, 0.0, -0.9)), 0.0);
}

/// Directions and points off the shape are rejected by the inverses and
/// have density 0.
#[test]
fn spherical_rectangle_outside_rejected() {
    for (name, shape) in all_shapes() {
        let w = build::<f64>(&shape, V::Robust).unwrap();
        let (p, d) = w.sample_point(&0.3, &0.6);
        assert!(w.contains(&d) && w.outside_by(&d) <= 1e-15, "{name}");
        let away = d.neg();
        assert!(w.inverse(&away).is_err(), "{name}");
        assert_eq!(w.pdf(&away), 0.0, "{name}");
        assert!(w.outside_by(&away) > 1e-3, "{name}");
        // Beyond the edge e_x by 10 % of its length.
        let beyond = w
            .corner()
            .add(&w.edge_x().scale(&1.1))
            .add(&w.edge_y().scale(&0.5));
        assert!(w.inverse_point(&beyond).is_err(), "{name}");
        // Its direction is outside, but may be within the angular tolerance
        // 2^-26 when the observer grazes the plane.
        let dir = beyond.sub(w.observer());
        let dir = dir.scale(&(1.0 / dir.norm()));
        assert!(w.outside_by(&dir) > 0.0, "{name}");
        let near = w.outside_by(&dir) <= 2f64.powi(-26);
        assert_eq!(w.inverse(&dir).is_ok(), near, "{name}");
        assert_eq!(w.pdf(&dir) > 0.0, near, "{name}");
        if !name.starts_with("grazing") {
            assert!(!near, "{name}");
        }
        assert!(w.inverse_point(&p).is_ok(), "{name}");
        assert!(w.inverse(&Vec3::new(f64::NAN, 0.0, 1.0)).is_err());
        assert!(w.inverse(&Vec3::zero()).is_err());
        assert_eq!(w.outside_by(&Vec3::zero()), f64::MAX);
        assert!(
            w.inverse_point(&Vec3::new(f64::INFINITY, 0.0, 0.0))
                .is_err()
        );
    }
}

/// A χ² binning of a rectangle: an `n × n` grid of sub-rectangles, each
/// with its solid angle (two triangles by Van Oosterom–Strackee) as
/// expected probability; directions are binned by where the ray from the
/// observer hits the rectangle's plane. Independent of the map's code.
struct RectangleBins {
    o: Vec3<f64>,
    s: Vec3<f64>,
    ex: Vec3<f64>,
    ey: Vec3<f64>,
    n: usize,
    prob: Vec<f64>,
}

fn vos64(a: &Vec3<f64>, b: &Vec3<f64>, c: &Vec3<f64>) -> f64 {
    let det = a.dot(&b.cross(c)).abs();
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    2.0 * det.atan2(la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la)
}

impl RectangleBins {
    fn new(s: Vec3<f64>, ex: Vec3<f64>, ey: Vec3<f64>, o: Vec3<f64>, n: usize) -> Self {
        let mut prob = Vec::with_capacity(n * n);
        let corner = |i: usize, j: usize| {
            s.add(&ex.scale(&(i as f64 / n as f64)))
                .add(&ey.scale(&(j as f64 / n as f64)))
                .sub(&o)
        };
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (
                    corner(i, j),
                    corner(i + 1, j),
                    corner(i + 1, j + 1),
                    corner(i, j + 1),
                );
                prob.push(vos64(&a, &b, &c) + vos64(&a, &c, &d));
            }
        }
        let total: f64 = prob.iter().sum();
        prob.iter_mut().for_each(|p| *p /= total);
        RectangleBins {
            o,
            s,
            ex,
            ey,
            n,
            prob,
        }
    }
}

impl Binning for RectangleBins {
    fn n_bins(&self) -> usize {
        self.n * self.n
    }
    fn bin(&self, d: &Vec3<f64>) -> Option<usize> {
        let normal = self.ex.cross(&self.ey);
        let t = self.s.sub(&self.o).dot(&normal) / d.dot(&normal);
        if t.is_nan() || t <= 0.0 {
            return None;
        }
        let q = self.o.add(&d.scale(&t)).sub(&self.s);
        let xi = q.dot(&self.ex) / self.ex.norm_squared();
        let eta = q.dot(&self.ey) / self.ey.norm_squared();
        let tol = crate::harness::chi2::BIN_TOLERANCE;
        if !((-tol..=1.0 + tol).contains(&xi) && (-tol..=1.0 + tol).contains(&eta)) {
            return None;
        }
        let cell = |c: f64| ((c.clamp(0.0, 1.0) * self.n as f64) as usize).min(self.n - 1);
        Some(cell(xi) * self.n + cell(eta))
    }
    fn probability(&self, i: usize) -> f64 {
        self.prob[i]
    }
}

#[test]
fn spherical_rectangle_chi_square_both_variants() {
    let shapes = ordinary_rectangles();
    let tests = 2 * shapes.len() as u32;
    for (name, [s, ex, ey, o]) in shapes {
        let bins = RectangleBins::new(s, ex, ey, o, 8);
        for variant in [V::Robust, V::Literal] {
            let w = SphericalRectangle::new_with(s, ex, ey, o, variant).unwrap();
            let out = run_chi_square(&w, &bins, 100_000, 7, 0.01, tests);
            assert!(out.passed, "{name} {variant}: {out:?}");
        }
    }
    // The same test rejects area-uniform points (a wrong density).
    let [s, ex, ey, o] = ordinary_rectangles()[2].1;
    let bins = RectangleBins::new(s, ex, ey, o, 8);
    #[derive(Clone)]
    struct AreaUniform(SphericalRectangle<f64>);
    impl Warp<f64> for AreaUniform {
        type Point = Vec3<f64>;
        fn map(&self, u: &f64, v: &f64) -> Vec3<f64> {
            let p = self
                .0
                .corner()
                .add(&self.0.edge_x().scale(u))
                .add(&self.0.edge_y().scale(v));
            let d = p.sub(self.0.observer());
            d.scale(&(1.0 / d.norm()))
        }
        fn pdf_unchecked(&self, d: &Vec3<f64>) -> f64 {
            self.0.pdf(d)
        }
        fn measure(&self) -> f64 {
            self.0.measure()
        }
        fn inverse(&self, _d: &Vec3<f64>) -> Result<[f64; 2], InverseError> {
            Err(InverseError::NonFinite)
        }
        fn outside_by(&self, d: &Vec3<f64>) -> f64 {
            self.0.outside_by(d)
        }
    }
    let wrong = AreaUniform(SphericalRectangle::new(s, ex, ey, o).unwrap());
    let out = run_chi_square(&wrong, &bins, 100_000, 7, 0.01, 1);
    assert!(!out.passed, "{out:?}");
}

/// Samples through [`WarpSampler`](crate::sampling::WarpSampler), the
/// crate's `rand::distr::Distribution` adapter, in f32 and f64.
#[test]
fn spherical_rectangle_rand_distribution() {
    use crate::sampling::WarpSampler;
    use rand::SeedableRng;
    use rand::distr::Distribution;
    let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(5);
    for (name, shape) in all_shapes() {
        let w = build::<f64>(&shape, V::Robust).unwrap();
        let sampler = WarpSampler::new(w.clone());
        for d in (&sampler).sample_iter(&mut rng).take(64) {
            assert!(w.contains(&d), "{name}: {d:?}");
        }
        if let Ok(w32) = build::<f32>(&shape, V::Robust) {
            let sampler = WarpSampler::new(w32);
            let d: Vec3<f32> = sampler.sample(&mut rng);
            assert!(d.is_finite() && (d.norm() - 1.0).abs() < 1e-6, "{name}");
        }
    }
}

/// The products-only test of the area densities' range never accepts what
/// the exact test (square roots and divisions) rejects, over local lengths,
/// heights, solid angles and scales across both types' ranges; and it
/// accepts the ordinary cases (which `check_range` settles first, by
/// the three comparisons of `ordinary_density_range`).
fn area_density_fast_test_is_sound<T: Real<Wide = f64>>(max_log2_omega: i32) {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..200_000 {
        let exp = (next() * 300.0) as i32 - 150;
        let h = 2.0 * next() * 2f64.powi(-((next() * 80.0) as i32));
        let h = if i % 7 == 0 { 2.0 } else { h };
        let x0 = 8.0 * next() - 4.0;
        let y0 = 8.0 * next() - 4.0;
        let (lx, ly) = (2.0 * next(), 2.0 * next());
        let omega = 6.0 * 2f64.powi(-((next() * f64::from(max_log2_omega)) as i32)) * next();
        let local = [x0, y0, lx, ly, h];
        if area_density_in_range::<T>(&local, &omega, exp) {
            let exact = area_density_exact::<T>(&local, &omega, exp);
            assert!(exact, "{local:?} omega {omega:e} exp {exp}");
        }
    }
    // Ordinary rectangles (lengths within 2^±10 of one another, Ω above
    // 1e-6 sr, world scale within 2^±20) pass the products test too.
    for _ in 0..10_000 {
        let exp = (next() * 40.0) as i32 - 20;
        let h = 2f64.powi(-((next() * 10.0) as i32)) * (1.0 + next());
        let local = [
            4.0 * next() - 2.0,
            4.0 * next() - 2.0,
            1.0 + next(),
            next() + 1e-3,
            h,
        ];
        let omega = 1e-6 + 6.0 * next();
        assert!(
            area_density_in_range::<T>(&local, &omega, exp),
            "{local:?} {omega:e} {exp}"
        );
    }
    // The three comparisons of `ordinary_density_range` imply the products'
    // test, at its corners (h = 2^-16, Ω = 2^-32, |exp| = 16, with the
    // farthest point at (4, 4) (x0 = y0 = 2) or the square around the foot
    // (x0 = y0 = −2)) and at random points inside them.
    let implies = |local: [f64; 5], omega: f64, exp: i32| {
        let (th, tomega) = (T::from_f64(local[4]), T::from_f64(omega));
        if super::ordinary_density_range(&th, &tomega, exp) {
            assert!(
                area_density_in_range::<T>(&local, &omega, exp),
                "{local:?} {omega:e} {exp}"
            );
        }
    };
    for exp in [16, -16] {
        for corner in [2.0, -2.0] {
            implies(
                [corner, corner, 2.0, 2.0, 2f64.powi(-16)],
                2f64.powi(-32),
                exp,
            );
        }
    }
    for _ in 0..50_000 {
        let exp = (next() * 33.0) as i32 - 16;
        let h = 2f64.powi(-((next() * 17.0) as i32)) * (1.0 + next());
        let omega = 2f64.powi(-((next() * 33.0) as i32)) * (1.0 + 2.0 * next());
        let (x0, y0) = (4.0 * next() - 2.0, 4.0 * next() - 2.0);
        let (lx, ly) = (2.0 * next(), 2.0 * next());
        implies([x0, y0, lx, ly, h.min(2.0)], omega, exp);
    }
}

#[test]
fn area_density_fast_test_is_sound_f32() {
    area_density_fast_test_is_sound::<f32>(140);
}

#[test]
fn area_density_fast_test_is_sound_f64() {
    area_density_fast_test_is_sound::<f64>(1100);
}
