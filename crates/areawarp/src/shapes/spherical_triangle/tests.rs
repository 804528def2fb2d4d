use super::*;
#[cfg(feature = "mpfr")]
use crate::harness::extremes::extremes_grid;
use crate::harness::extremes::random_points;
use SphericalTriangleVariant::{Literal as Lit, Robust as Rob};

fn tri(v: &[Vec3<f64>; 3]) -> Result<SphericalTriangle<f64>, WarpError> {
    SphericalTriangle::new(v[0], v[1], v[2])
}

fn all_shapes() -> Vec<(String, [Vec3<f64>; 3])> {
    let mut s = ordinary_triangles();
    s.extend(hard_triangles());
    s
}

/// The extremes grid plus 16 random points.
#[cfg(feature = "mpfr")]
fn points() -> Vec<(f64, f64)> {
    let mut p = extremes_grid();
    p.extend(random_points(16, 42));
    p
}

fn octant() -> SphericalTriangle<f64> {
    SphericalTriangle::new(
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    )
    .unwrap()
}

#[test]
fn constructor_rejects_bad_input() {
    let x = Vec3::new(1.0, 0.0, 0.0);
    let y = Vec3::new(0.0, 1.0, 0.0);
    let z = Vec3::new(0.0, 0.0, 1.0);
    let new = |a: &Vec3<f64>, b: &Vec3<f64>, c: &Vec3<f64>| SphericalTriangle::new(*a, *b, *c);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let v = Vec3::new(bad, 0.0, 1.0);
        assert_eq!(
            new(&v, &y, &z).unwrap_err(),
            WarpError::NonFinite { what: "vertex A" }
        );
        assert_eq!(
            new(&x, &y, &v).unwrap_err(),
            WarpError::NonFinite { what: "vertex C" }
        );
    }
    let zero = Vec3::zero();
    assert_eq!(
        new(&x, &zero, &z).unwrap_err(),
        WarpError::Degenerate {
            what: "zero vertex direction"
        }
    );
    // The same direction twice (also at another length).
    for b in [x, x.scale(&3.0)] {
        assert_eq!(
            new(&x, &b, &z).unwrap_err(),
            WarpError::Degenerate {
                what: "coincident vertices"
            }
        );
    }
    // Three directions on one great circle; antipodal vertices; a vertex
    // 1e-17 rad off the great circle of the two others (below the rounding
    // of the determinant).
    let on_circle = WarpError::Degenerate {
        what: "vertices on one great circle (or collinear)",
    };
    assert_eq!(
        new(&x, &y, &Vec3::new(-1.0, 1.0, 0.0)).unwrap_err(),
        on_circle
    );
    assert_eq!(new(&x, &x.neg(), &y).unwrap_err(), on_circle);
    assert_eq!(
        new(&x, &Vec3::new(0.0, 1.0, 1e-17), &Vec3::new(-1.0, 0.5, 0.0)).unwrap_err(),
        on_circle
    );
    // ... but 1e-12 rad off it is a valid (nearly hemispherical) triangle,
    // and so is a triangle of 1e-12 sr.
    let hemi = new(
        &x,
        &Vec3::new(-0.5, 0.8, 1e-12),
        &Vec3::new(-0.5, -0.8, 1e-12),
    )
    .unwrap();
    assert!(2.0 * core::f64::consts::PI - hemi.solid_angle() < 1e-10);
    let tiny = new(
        &Vec3::new(1.0, 0.0, 0.0),
        &Vec3::new(1.0, 1.5e-6, 0.0),
        &Vec3::new(1.0, 0.0, 1.5e-6),
    )
    .unwrap();
    assert!((tiny.solid_angle() / 1.125e-12 - 1.0).abs() < 1e-5);
    // Scale-free: vertex vectors of any length give the same triangle.
    for k in [1e-300, 1e-150, 1.0, 1e150, 1e300] {
        let t = new(&x.scale(&k), &y.scale(&k), &z.scale(&k)).unwrap();
        assert!((t.solid_angle() - octant().solid_angle()).abs() <= 4.0 * f64::EPSILON);
        assert!(t.a().sub(&x).max_abs() <= f64::EPSILON);
    }
    // The decisions are taken in f64: f32 accepts the 1e-6 rad sliver
    // (its f32 vertices are as valid as in f64).
    let (_, sliver) = &hard_triangles()[4];
    let s = tri(sliver).unwrap();
    assert!(s.at::<f32>().is_ok());
    // Nearly antipodal vertices: the arc between them is not determined.
    let antipodal = WarpError::Degenerate {
        what: "nearly antipodal vertices: the great arc between them is not determined",
    };
    for eps in [1e-7, 1e-9, 1e-12] {
        let near = Vec3::new(-1.0, eps, 0.0);
        assert_eq!(new(&x, &near, &z).unwrap_err(), antipodal, "{eps}");
    }
    assert!(new(&x, &Vec3::new(-1.0, 1e-5, 0.0), &z).is_ok());
    // What f32 cannot hold: a triangle of ~1e-90 sr is valid in f64 only.
    let (p, q, r) = (
        Vec3::new(1.0f32, 0.0, 0.0),
        Vec3::new(1.0f32, 1e-45, 0.0),
        Vec3::new(1.0f32, 0.0, 1e-45),
    );
    assert!(matches!(
        SphericalTriangle::new(p, q, r),
        Err(WarpError::Unrepresentable { .. })
    ));
    assert!(SphericalTriangle::<f64>::new(p.convert(), q.convert(), r.convert()).is_ok());
}

/// `from_points` (and its one-shot) names a non-finite input point or
/// observer before a difference `p − observer` that overflows, in `f64`
/// (where the difference of finite values can overflow) and `f32` (where,
/// formed in `f64`, it cannot).
#[test]
fn from_points_names_what_is_not_finite() {
    fn check<T: Real>() {
        let p = |x: f64, y: f64, z: f64| Vec3::<T>::from_f64(x, y, z);
        let (a, b, c, o) = (
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, 1.0),
            p(0.0, 0.0, 0.0),
        );
        let err = |a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>, o: &Vec3<T>| {
            let once =
                SphericalTriangle::sample_once_from_points(a, b, c, o, &T::zero(), &T::zero());
            let built = SphericalTriangle::from_points(a.clone(), b.clone(), c.clone(), o.clone());
            assert_eq!(once.clone().err(), built.err());
            once.err()
        };
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let v = p(bad, 0.0, 1.0);
            let named = |what| Some(WarpError::NonFinite { what });
            assert_eq!(err(&v, &b, &c, &o), named("point 0"));
            assert_eq!(err(&a, &b, &v, &o), named("point 2"));
            assert_eq!(err(&a, &b, &c, &v), named("observer"));
            // Both an input and the observer: the input is named first.
            assert_eq!(err(&a, &v, &c, &v), named("point 1"));
        }
        let big = T::max_value().to_f64();
        let far = p(big, 0.0, 0.0);
        let overflow = err(&far, &b, &c, &p(-big, 0.0, 0.0));
        if T::precision() == 53 {
            assert_eq!(overflow, Some(WarpError::NonFinite { what: "vertex A" }));
        } else {
            assert_ne!(overflow, Some(WarpError::NonFinite { what: "vertex A" }));
        }
    }
    check::<f64>();
    check::<f32>();
}

#[test]
fn from_points_and_variants() {
    let o = Vec3::new(1.0, 2.0, 3.0);
    let t = SphericalTriangle::from_points(
        Vec3::new(3.0, 2.0, 3.0),
        Vec3::new(1.0, 5.0, 3.0),
        Vec3::new(1.0, 2.0, 3.5),
        o,
    )
    .unwrap();
    assert_eq!(t.solid_angle(), octant().solid_angle());
    assert_eq!(t.b(), &Vec3::new(0.0, 1.0, 0.0));
    assert!(t.is_counter_clockwise());
    assert_eq!(
        SphericalTriangle::from_points(o, o.add(&Vec3::new(1.0, 0.0, 0.0)), Vec3::zero(), o)
            .unwrap_err(),
        WarpError::Degenerate {
            what: "zero vertex direction"
        }
    );
    assert_eq!(t.variant(), Rob);
    let l = t.clone().with_variant(Lit);
    assert_eq!(l.variant(), Lit);
    assert_eq!(l.at::<f32>().unwrap().variant(), Lit);
    assert_eq!(l.at::<f64>().unwrap().at::<f32>().unwrap().variant(), Lit);
    assert_eq!(l.name(), "spherical-triangle");
    assert_eq!(t.name(), "spherical-triangle");
    assert_eq!("literal".parse::<SphericalTriangleVariant>().unwrap(), Lit);
    assert_eq!(" Robust ".parse::<SphericalTriangleVariant>().unwrap(), Rob);
    assert!("exact".parse::<SphericalTriangleVariant>().is_err());
    assert_eq!(Lit.to_string(), "literal");
    assert_eq!(SphericalTriangleVariant::default(), Rob);
    let made = SphericalTriangle::new_with(*t.a(), *t.b(), *t.c(), Lit);
    assert_eq!(made.unwrap().variant(), Lit);
    // Both variants sample the same map on an ordinary triangle.
    for (u, v) in random_points(50, 3) {
        let d = t.map(&u, &v).sub(&l.map(&u, &v)).norm();
        assert!(d < 1e-12, "({u}, {v}): {d:e}");
    }
}

#[test]
fn corners_and_edges_are_exact() {
    for (name, shape) in all_shapes() {
        let t = tri(&shape).unwrap();
        for &x in &crate::harness::extremes::EXTREMES {
            // v = 0 is the vertex B, bit for bit.
            assert_eq!(t.map(&x, &0.0), *t.b(), "{name}");
        }
        // u = 0, v = 1 is A and u = 1, v = 1 is C, up to the final
        // renormalization (one unit of roundoff).
        let ur = f64::EPSILON;
        assert!(t.map(&0.0, &1.0).sub(t.a()).max_abs() <= ur, "{name}");
        assert!(t.map(&1.0, &1.0).sub(t.c()).max_abs() <= ur, "{name}");
        // u = 0 is the arc BA, u = 1 the arc BC: in the edge planes.
        for &v in &[1e-12, 1e-6, 0.5, 1.0 - 1e-6] {
            let p = t.map(&0.0, &v);
            assert!(t.normals()[0].dot(&p).abs() <= 2.0 * ur, "{name} u=0 v={v}");
            let q = t.map(&1.0, &v);
            assert!(t.normals()[1].dot(&q).abs() <= 2.0 * ur, "{name} u=1 v={v}");
        }
    }
}

/// No NaN, no infinity and nothing outside the triangle (beyond 4 units of
/// roundoff, measured on the exact shape) for the robust map in `T`, on the
/// whole ladder; for the literal map only the counts are returned.
#[cfg(feature = "mpfr")]
fn finite_and_inside<T: Real>() -> Vec<(String, usize, usize)> {
    use crate::real::Mpfr256;
    let mut literal = Vec::new();
    let tol = T::unit_roundoff().to_f64() * 4.0;
    for (name, shape) in all_shapes() {
        let Ok(t) = tri(&shape).unwrap().at::<T>() else {
            continue;
        };
        let exact = t.at::<Mpfr256>().unwrap();
        let (mut nan, mut out) = (0, 0);
        for variant in [Rob, Lit] {
            let w = t.clone().with_variant(variant);
            for &(u, v) in &points() {
                let p = w.map(&T::from_f64(u), &T::from_f64(v));
                let finite = p.is_finite();
                let outside = finite && exact.outside_by(&p.convert()).to_f64() > tol;
                if variant == Rob {
                    assert!(finite, "{name} ({u}, {v}) in {}: {p:?}", T::type_name());
                    assert!(!outside, "{name} ({u}, {v}) in {}: outside", T::type_name());
                } else {
                    nan += usize::from(!finite);
                    out += usize::from(outside);
                }
            }
        }
        literal.push((name, nan, out));
    }
    literal
}

#[cfg(feature = "mpfr")]
#[test]
fn robust_is_finite_and_inside_f64_literal_is_not() {
    let literal = finite_and_inside::<f64>();
    // The published algorithm produces NaN or leaves the triangle on the
    // hard ladder (this is what the robust variant is for).
    let bad: usize = literal.iter().map(|(_, n, o)| n + o).sum();
    assert!(bad > 100, "{literal:?}");
}

#[cfg(feature = "mpfr")]
#[test]
fn robust_is_finite_and_inside_f32() {
    finite_and_inside::<f32>();
}

#[test]
fn distribution_samples_lie_in_the_triangle() {
    use rand::SeedableRng;
    use rand::distr::Distribution;
    use rand::rngs::Xoshiro256PlusPlus;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    for (name, shape) in all_shapes() {
        let t = tri(&shape).unwrap();
        for _ in 0..200 {
            let p: Vec3<f64> = t.sample(&mut rng);
            assert!(t.outside_by(&p) <= 4.0 * f64::EPSILON, "{name}: {p:?}");
        }
        // The crate-wide adapter gives the same samples.
        let via = crate::sampling::WarpSampler::new(t.clone());
        let mut r1 = Xoshiro256PlusPlus::seed_from_u64(1);
        let mut r2 = Xoshiro256PlusPlus::seed_from_u64(1);
        for _ in 0..8 {
            let p: Vec3<f64> = via.sample(&mut r1);
            assert_eq!(p, t.sample(&mut r2), "{name}");
        }
        if let Ok(t32) = t.at::<f32>() {
            for _ in 0..200 {
                let p: Vec3<f32> = t32.sample(&mut rng);
                assert!(t32.outside_by(&p) <= 4.0 * f32::EPSILON, "{name}: {p:?}");
            }
        }
    }
}

#[test]
fn inverse_rejects_points_off_the_triangle() {
    let t = octant();
    assert!(t.inverse(&Vec3::new(-1.0, 0.1, 0.1)).is_err());
    assert!(t.inverse(&Vec3::new(f64::NAN, 0.1, 0.1)).is_err());
    assert!(t.inverse(&Vec3::zero()).is_err());
    assert_eq!(t.outside_by(&Vec3::zero()), f64::MAX);
    // Off the sphere: radial distance; outside an edge: the plane distance.
    assert!((t.outside_by(&Vec3::new(0.0, 0.0, 2.0)) - 1.0).abs() < 1e-15);
    let p = Vec3::new(0.6, 0.8, -0.1);
    assert!((t.outside_by(&p) - 0.1 / p.norm()).abs() < 1e-15);
    // Antipodal region: far outside.
    assert!(t.outside_by(&Vec3::new(-1.0, -1.0, -1.0)) > 0.5);
    // Non-unit points on the ray are accepted (within the tolerance) and
    // normalized; B itself gives (0, 0).
    let q = t.map(&0.3, &0.6);
    let [u, v] = t.inverse(&q.scale(&(1.0 + 1e-9))).unwrap();
    assert!((u - 0.3).abs() < 1e-14 && (v - 0.6).abs() < 1e-14);
    assert_eq!(t.inverse(t.b()), Ok([0.0, 0.0]));
    assert!(t.contains(&q) && !t.contains(&Vec3::new(0.0, 0.0, -1.0)));
}

#[test]
fn pdf_is_the_reciprocal_solid_angle() {
    for (name, shape) in all_shapes() {
        let t = tri(&shape).unwrap();
        for variant in [Rob, Lit] {
            let w = t.clone().with_variant(variant);
            let p = w.map(&0.3, &0.7);
            // The density of the returned direction, for both variants, is the
            // standalone 1/Ω of the Van Oosterom–Strackee solid angle (the
            // literal map's point may lie off a hard triangle, where `pdf`
            // is 0: its density is `pdf_unchecked`).
            assert_eq!(w.pdf_unchecked(&p), 1.0 / t.solid_angle(), "{name}");
            if variant == Rob {
                assert_eq!(w.pdf(&p), 1.0 / t.solid_angle(), "{name}");
            }
            assert_eq!(w.measure(), t.solid_angle(), "{name}");
        }
    }
    assert!((octant().solid_angle() - core::f64::consts::FRAC_PI_2).abs() <= 2e-16);
}

/// The one-shot solid angle's comparison (`omega_alone_in`) decides as the
/// constructor's test with 1/Ω (`omega_in`), with the same bits, on both
/// sides of its threshold `8/max` and at the ends of the range.
#[test]
fn omega_alone_decides_as_omega_in() {
    fn check<T: Real + core::fmt::Debug>(values: &[T::Wide]) {
        for w in values {
            let alone = build::omega_alone_in::<T>(w);
            let with_inverse = build::omega_in::<T>(w).map(|(omega, _)| omega);
            assert_eq!(alone, with_inverse, "{w:?}");
        }
    }
    let max32 = f64::from(f32::MAX);
    let mut wide = vec![
        0.0,
        -1.0,
        f64::NAN,
        f64::INFINITY,
        4.0 * core::f64::consts::PI,
    ];
    for k in [1.0, 2.0, 4.0, 7.999, 8.0, 8.001, 16.0] {
        wide.extend([k / max32, k / f64::MAX, k * f64::from(f32::MIN_POSITIVE)]);
    }
    wide.extend([f64::MIN_POSITIVE, f64::from_bits(1), 1e-300, 1e-40]);
    check::<f32>(&wide);
    check::<f64>(&wide);
}

#[cfg(feature = "mpfr")]
mod mpfr;

mod props {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        #[test]
        fn random_triangles_f64(
            a in prop::array::uniform3(-1.0f64..1.0),
            b in prop::array::uniform3(-1.0f64..1.0),
            c in prop::array::uniform3(-1.0f64..1.0),
            u in 0.0f64..=1.0,
            v in 0.0f64..=1.0,
        ) {
            let t = match SphericalTriangle::new(
                Vec3::new(a[0], a[1], a[2]), Vec3::new(b[0], b[1], b[2]), Vec3::new(c[0], c[1], c[2])) {
                Ok(t) => t,
                Err(e) => {
                    prop_assert!(matches!(e, WarpError::Degenerate { .. }), "unexpected {:?}", e);
                    return Err(TestCaseError::reject("degenerate"));
                }
            };
            prop_assume!(t.solid_angle() > 1e-6);
            let p = t.map(&u, &v);
            prop_assert!(p.is_finite());
            prop_assert!(t.outside_by(&p) <= 4.0 * f64::EPSILON, "outside by {:e}", t.outside_by(&p));
            let [u2, v2] = t.inverse(&p).expect("on the triangle");
            // Weighted by the local scale: √v·|Δu| and |Δv| (v = 0 is B).
            prop_assert!(v.sqrt() * (u - u2).abs() <= 1e-9, "u {} -> {}", u, u2);
            prop_assert!((v - v2).abs() <= 1e-9, "v {} -> {}", v, v2);
            prop_assert!((t.pdf(&p) * t.measure() - 1.0).abs() <= 2.0 * f64::EPSILON);
        }
    }
}
