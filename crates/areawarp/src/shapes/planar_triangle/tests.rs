use super::*;
use crate::real::Dual2;
use proptest::prelude::*;

fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Result<PlanarTriangle<f64>, WarpError> {
    PlanarTriangle::new(
        Vec3::from_f64(a[0], a[1], a[2]),
        Vec3::from_f64(b[0], b[1], b[2]),
        Vec3::from_f64(c[0], c[1], c[2]),
    )
}

fn sample() -> PlanarTriangle<f64> {
    tri([0.3, -1.2, 2.0], [2.5, 0.7, -0.4], [-1.1, 1.9, 0.8]).unwrap()
}

/// u, v ∈ {0, 2^-60, 1e-12, 1e-6, 1/2, 1 − 1e-6, 1 − 2^-40, 1}.
fn grid() -> Vec<f64> {
    vec![
        0.0,
        2f64.powi(-60),
        1e-12,
        1e-6,
        0.5,
        1.0 - 1e-6,
        1.0 - 2f64.powi(-40),
        1.0,
    ]
}

#[test]
fn corners_are_exact_vertices() {
    let t = sample();
    for v in grid() {
        assert_eq!(t.map(&0.0, &v), *t.a());
    }
    assert_eq!(t.map(&1.0, &0.0), *t.b());
    assert_eq!(t.map(&1.0, &1.0), *t.c());
}

#[test]
fn edges_and_grid_map_onto_triangle() {
    let t = sample();
    let u_r = f64::EPSILON / 2.0;
    for u in grid() {
        for v in grid() {
            let p = t.map(&u, &v);
            assert!(p.is_finite(), "({u}, {v}) -> {p:?}");
            let out = t.outside_by(&p);
            assert!(out <= 8.0 * u_r * t.extent(), "({u},{v}): {out:e}");
        }
    }
    // A point clearly off the plane and one outside an edge.
    let off = t.map(&0.3, &0.3).add(&t.normal().scale(&0.5));
    assert!((t.outside_by(&off) - 0.5).abs() < 1e-12);
    let beyond = t.b().add(&t.b().sub(t.a()).scale(&0.25));
    let d = t.outside_by(&beyond);
    assert!((d - 0.25 * t.b().sub(t.a()).norm()).abs() < 1e-12, "{d}");
    assert!(t.inverse(&off).is_err());
    assert!(t.inverse(&beyond).is_err());
}

#[test]
fn side_of_square_maps_onto_edge() {
    // Shifted triangle: v = 0 lands exactly on AB and v = 1 exactly on AC
    // (a zero weight is an exact zero), u = 1 on BC.
    let t = tri(
        [1e3, 1e3, 0.0],
        [1e3 + 1.0, 1e3, 0.0],
        [1e3, 1e3 + 3.0, 0.0],
    )
    .unwrap();
    for x in grid() {
        let (la, _, _) = t.barycentric(&t.map(&1.0, &x));
        assert!(la.abs() <= 1e-12, "u = 1 is BC: λ_A = {la:e}");
        let p = t.map(&x, &0.0);
        assert_eq!(p.y, 1e3, "v = 0 is AB");
        let q = t.map(&x, &1.0);
        assert_eq!(q.x, 1e3, "v = 1 is AC");
    }
}

#[test]
fn round_trip_f64() {
    let t = sample();
    for u in grid() {
        for v in grid() {
            let p = t.map(&u, &v);
            let [u2, v2] = t.inverse(&p).expect("on the triangle");
            assert!((0.0..=1.0).contains(&u2) && (0.0..=1.0).contains(&v2));
            assert!((u - u2).abs() <= 1e-12, "u: ({u},{v}) -> ({u2},{v2})");
            // v is singular at u = 0: compare it weighted by s = √u.
            assert!(
                u.sqrt() * (v - v2).abs() <= 1e-12,
                "v: ({u},{v}) -> ({u2},{v2})"
            );
            if u >= 1e-6 {
                assert!((v - v2).abs() <= 1e-12, "v: ({u},{v}) -> ({u2},{v2})");
            }
        }
    }
    // The apex: s = 0 gives t = 0, not NaN.
    assert_eq!(t.inverse(t.a()), Ok([0.0, 0.0]));
    assert_eq!(t.inverse(t.c()), Ok([1.0, 1.0]));
    assert!(t.inverse(&Vec3::new(f64::NAN, 0.0, 0.0)).is_err());
}

#[test]
fn constructor_rejects_bad_input() {
    let ok = [1.0, 0.0, 0.0];
    let o = [0.0, 0.0, 0.0];
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(matches!(
            tri([bad, 0.0, 0.0], ok, [0.0, 1.0, 0.0]),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(matches!(
            tri(o, ok, [0.0, 0.0, bad]),
            Err(WarpError::NonFinite { .. })
        ));
    }
    // Overflowing edge.
    assert!(matches!(
        tri([-1e308, 0.0, 0.0], [1e308, 0.0, 0.0], [0.0, 1.0, 0.0]),
        Err(WarpError::NonFinite { .. })
    ));
    assert_eq!(
        tri(o, o, ok).unwrap_err(),
        WarpError::Degenerate {
            what: "coincident vertices"
        }
    );
    assert_eq!(
        tri(o, ok, ok).unwrap_err(),
        WarpError::Degenerate {
            what: "coincident vertices"
        }
    );
    assert_eq!(
        tri(o, [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]).unwrap_err(),
        WarpError::Degenerate {
            what: "collinear vertices"
        }
    );
    // Exactly collinear far from the origin: the computed sine is rounding noise.
    let far = 1e9;
    assert!(matches!(
        tri(
            [far, far, far],
            [far + 1.0, far + 2.0, far + 3.0],
            [far + 2.0, far + 4.0, far + 6.0]
        ),
        Err(WarpError::Degenerate { .. })
    ));
    // Rotated collinear data (not axis-aligned, inexact unit vectors).
    assert!(tri([0.1, 0.7, -0.3], [0.4, 1.3, 0.6], [1.0, 2.5, 2.4]).is_err());
    // Scale invariance: the same shapes at 1e-150 and 1e150 are accepted.
    for k in [1e-150, 1.0, 1e150] {
        let t = tri([0.0; 3], [k, 0.0, 0.0], [0.0, k, 0.0]).unwrap();
        assert!((t.area() / (0.5 * k * k) - 1.0).abs() < 1e-15);
        assert!(tri([0.0; 3], [k, k, k], [2.0 * k, 2.0 * k, 2.0 * k]).is_err());
    }
    // A thin but well-defined needle (right angle at B) is accepted,
    // a cap whose largest angle has sin θ ≈ 1e-15 is not.
    assert!(tri(o, ok, [1.0, 1e-12, 0.0]).is_ok());
    assert!(tri(o, [2.0, 0.0, 0.0], [1.0, 5e-16, 5e-16]).is_err());
}

#[test]
fn f32_rebuild_and_name() {
    let t = sample();
    assert_eq!(t.name(), "planar-triangle");
    let t32 = t.at::<f32>().unwrap();
    assert!((t32.measure() as f64 - t.measure()).abs() < 1e-6 * t.measure());
    let p = t32.map(&1.0, &1.0);
    assert_eq!(p, t.c().convert::<f32>());
    // Vertices out of f32 range.
    let big = tri([0.0; 3], [1e100, 0.0, 0.0], [0.0, 1e100, 0.0]).unwrap();
    assert!(matches!(big.at::<f32>(), Err(WarpError::NonFinite { .. })));
}

#[test]
fn jacobian_is_area_in_duals() {
    // Includes a vertex at the origin and axis-aligned edges (zero
    // coordinates in the constant dual numbers of the construction).
    let axis = tri([0.0; 3], [0.0, 0.0, 2.0], [0.0, 3.0, 0.0]).unwrap();
    for t in [sample(), axis] {
        let d = t.at::<Dual2<f64>>().unwrap();
        for u in [1e-6, 0.1, 0.25, 0.5, 0.9, 1.0] {
            for v in [0.0, 0.3, 0.5, 0.99, 1.0] {
                let p = d.map(&Dual2::seed_u(u), &Dual2::seed_v(v));
                let pu = Vec3::new(p.x.du, p.y.du, p.z.du);
                let pv = Vec3::new(p.x.dv, p.y.dv, p.z.dv);
                let j = pu.cross(&pv).norm() * t.pdf(&t.map(&u, &v));
                assert!((j - 1.0).abs() < 1e-13, "({u},{v}): {j}");
            }
        }
    }
}

#[test]
fn recipe_sigma_integrates_to_area() {
    let r = sample().recipe();
    let m = r.measure();
    // σ from exact dual partials matches the closed form 2·area·s.
    for s in [0.0, 0.2, 0.5, 1.0] {
        for t in [0.0, 0.4, 1.0] {
            let [_, ps, pt] = r.partials(&s, &t);
            let exact = ps.cross(&pt).norm();
            assert!((exact - r.sigma(&s, &t)).abs() <= 1e-14 * m, "{s} {t}");
        }
    }
    // F(0) = 0, F(1) = 1, G_s(1) = 1, and F'(s) = ∫₀¹ σ(s, t) dt / m
    // (Simpson, exact for σ's degree).
    assert_eq!(r.marginal_cdf(&0.0), 0.0);
    assert_eq!(r.marginal_cdf(&1.0), 1.0);
    assert_eq!(r.conditional_cdf(&0.3, &1.0), 1.0);
    for s in [0.1, 0.5, 0.8] {
        let int = (r.sigma(&s, &0.0) + 4.0 * r.sigma(&s, &0.5) + r.sigma(&s, &1.0)) / 6.0;
        assert!((int / m - r.marginal_pdf(&s)).abs() < 1e-14);
    }
    // ∫∫σ = area (Simpson in s, exact for a linear integrand).
    let total = (r.sigma(&0.0, &0.5) + 4.0 * r.sigma(&0.5, &0.5) + r.sigma(&1.0, &0.5)) / 6.0;
    assert!((total - m).abs() < 1e-14 * m);
    assert!((m - sample().area()).abs() == 0.0);
}

#[cfg(feature = "mpfr")]
#[test]
fn recipe_matches_direct_map_at_256_bits() {
    use crate::real::Mpfr256;
    use crate::recipe::{ClosedForm, RecipeWarp};
    let t = sample().at::<Mpfr256>().unwrap();
    let w = RecipeWarp::new(t.recipe(), ClosedForm, ClosedForm);
    assert_eq!(w.name(), "recipe:planar-triangle");
    let one = Mpfr256::one();
    let xs = [
        Mpfr256::zero(),
        Mpfr256::exp2i(-60),
        Mpfr256::from_ratio(1, 2),
        one.clone() - Mpfr256::exp2i(-40),
        one,
    ];
    let tol = Mpfr256::exp2i(-240) * t.extent();
    for u in &xs {
        for v in &xs {
            let p = t.map(u, v);
            let q = w.map(u, v);
            let d = p.sub(&q).norm();
            assert!(d <= tol, "({u}, {v}): {d}");
            // The composed inverse agrees too.
            if let (Ok([u1, v1]), Ok([u2, v2])) = (t.inverse(&p), w.inverse(&p)) {
                assert!((u1 - &u2).abs() <= Mpfr256::exp2i(-240));
                assert!((v1 - &v2).abs() <= Mpfr256::exp2i(-240));
            } else {
                panic!("inverse failed at ({u}, {v})");
            }
        }
    }
    // The recipe rebuilt through `recast` is the same recipe.
    let r64 = sample().recipe();
    let r256 = r64.recast::<Mpfr256>().unwrap();
    let rel = r256.triangle().area().to_f64() / sample().area() - 1.0;
    assert!(rel.abs() < 1e-15, "{rel:e}");
}

#[cfg(feature = "mpfr")]
#[test]
fn f64_map_is_accurate() {
    use crate::real::Mpfr256;
    // Against the same triangle at 256 bits (f64 vertices convert exactly):
    // a general triangle, one far from the origin and small, and one with
    // an obtuse angle. The bound is in units of roundoff times the extent.
    let tris = [
        sample(),
        tri(
            [1e3, 1e3, 1e3],
            [1e3 + 1e-3, 1e3, 1e3 + 3e-4],
            [1e3, 1e3 - 7e-4, 1e3 + 2e-4],
        )
        .unwrap(),
        tri([-1.0, 0.1, 0.0], [1.0, 0.0, 0.2], [0.05, 0.3, 0.1]).unwrap(),
    ];
    let ur = f64::EPSILON / 2.0;
    for t in tris {
        let t256 = t.at::<Mpfr256>().unwrap();
        for u in grid().into_iter().chain([0.1, 0.37, 0.81]) {
            for v in grid().into_iter().chain([0.2, 0.66]) {
                let p = t.map(&u, &v);
                let q = t256.map(&Mpfr256::from_f64(u), &Mpfr256::from_f64(v));
                let q = Vec3::new(q.x.to_f64(), q.y.to_f64(), q.z.to_f64());
                let err = p.sub(&q).norm() / (ur * t.extent());
                assert!(err <= 4.0, "({u},{v}): {err} units of roundoff");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn random_triangles(
        a in prop::array::uniform3(-100.0f64..100.0),
        b in prop::array::uniform3(-100.0f64..100.0),
        c in prop::array::uniform3(-100.0f64..100.0),
        u in 0.0f64..=1.0,
        v in 0.0f64..=1.0,
    ) {
        let t = match tri(a, b, c) {
            Ok(t) => t,
            Err(e) => {
                prop_assert!(matches!(e, WarpError::Degenerate { .. }), "unexpected {:?}", e);
                return Err(TestCaseError::reject("degenerate"));
            }
        };
        let longest = t.l_ab.max(t.l_bc).max(t.l_ca);
        // Conditioning of barycentric coordinates: extent · longest / (2·area).
        let kappa = t.extent() * longest / (2.0 * t.area());
        prop_assume!(kappa < 1e6);
        let ur = f64::EPSILON / 2.0;
        let p = t.map(&u, &v);
        prop_assert!(p.is_finite());
        let out = t.outside_by(&p);
        prop_assert!(out <= 16.0 * ur * t.extent(), "outside_by = {:e}", out);
        let [u2, v2] = t.inverse(&p).expect("mapped point is on the triangle");
        let tol = 256.0 * ur * kappa;
        prop_assert!((u - u2).abs() <= tol, "u {} -> {}", u, u2);
        prop_assert!(u.sqrt() * (v - v2).abs() <= tol, "v {} -> {}", v, v2);
    }
}

#[cfg(feature = "mpfr")]
#[test]
/// The map's error against 256 bits over 200 random triangles × 200 random
/// `(u, v)`, in units of `u·extent`: unit-size triangles at the origin and
/// triangles of size 10⁻³ around (1000, 1000, 1000). Prints the maximum and
/// mean (`docs/planar-triangle.md` quotes them):
/// `cargo test --release -p areawarp --features mpfr --lib -- f64_map_error_survey --nocapture`
fn f64_map_error_survey() {
    use crate::real::Mpfr256;
    let mut state: u64 = 12345;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let ur = f64::EPSILON / 2.0;
    for (scale, off) in [(1.0, 0.0), (1e-3, 1000.0)] {
        let (mut worst, mut sum, mut n) = (0.0f64, 0.0, 0u32);
        for _ in 0..200 {
            let mut p = || {
                [
                    off + scale * (next() - 0.5),
                    off + scale * (next() - 0.5),
                    off + scale * (next() - 0.5),
                ]
            };
            let (a, b, c) = (p(), p(), p());
            let Ok(t) = tri(a, b, c) else { continue };
            let t256 = t.at::<Mpfr256>().unwrap();
            for _ in 0..200 {
                let (u, v) = (next(), next());
                let p = t.map(&u, &v);
                let q = t256.map(&Mpfr256::from_f64(u), &Mpfr256::from_f64(v));
                let q = Vec3::new(q.x.to_f64(), q.y.to_f64(), q.z.to_f64());
                let err = p.sub(&q).norm() / (ur * t.extent());
                worst = worst.max(err);
                sum += err;
                n += 1;
            }
        }
        let mean = sum / f64::from(n);
        println!("size {scale:e} at {off}: max {worst:.2} mean {mean:.3} ({n} samples)");
        assert!(worst <= 4.0 && mean <= 1.0, "{worst} {mean}");
    }
}
