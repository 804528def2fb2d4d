//! The one-shot light paths against the shapes they stand for, over the
//! random and near-degenerate shapes of the light fuzz (issue 10, item 4):
//! `SphericalTriangle::sample_once{,_from_points}` against
//! `new`/`from_points` + `map_with_pdf`,
//! `SphericalTriangle::sample_light_once` against `from_points` +
//! `sample_light`, `SphericalRectangle::sample_once`
//! against `new` + `sample_light`, and the one-shot solid angles against the
//! shapes' `solid_angle`, in `f32` and `f64`, at the fuzz's values of `u`
//! and `v`.
//!
//! The one-shot paths evaluate the same formulas as the shapes, so they must
//! agree bit for bit, and accept and reject exactly the same inputs (with
//! the same error).

use areawarp::shapes::{
    SphericalRectangle, SphericalRectangleVariant, SphericalTriangle, SphericalTriangleVariant,
};
use areawarp::warp::{LightSample, LightWarp};
use areawarp::{Real, Vec3, Warp, WarpError};
use proptest::test_runner::Config;
use std::cell::RefCell;
use std::fmt::Debug;

#[path = "support/light_cases.rs"]
mod light_cases;
use light_cases::*;

/// Shapes tried, accepted, and one-shot samples compared.
#[derive(Default, Debug)]
struct Counts {
    tried: usize,
    accepted: usize,
    samples: usize,
    /// One-shot samples of triangles `from_points` refuses for their
    /// plane alone (the one-shot returns no point or area density).
    plane_only: usize,
    /// Light samples of points compared
    /// (`SphericalTriangle::sample_light_once`).
    light_samples: usize,
}

fn same<T: Real>(a: &T, b: &T) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

fn same3<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> bool {
    same(&a.x, &b.x) && same(&a.y, &b.y) && same(&a.z, &b.z)
}

fn triangle<T: Real>(case: &TriangleCase, n: &mut Counts) {
    n.tried += 1;
    let [a, b, c] = [v3::<T>(&case.v[0]), v3(&case.v[1]), v3(&case.v[2])];
    let o = case.observer.map(|o| v3::<T>(&o));
    let built = case.build::<T>(SphericalTriangleVariant::Robust);
    let omega = match &o {
        None => SphericalTriangle::solid_angle_of(&a, &b, &c),
        Some(o) => SphericalTriangle::solid_angle_of(&a.sub(o), &b.sub(o), &c.sub(o)),
    };
    if let Ok(t) = &built {
        n.accepted += 1;
        // The one-shot solid angle of points is that of their differences
        // rounded to T, the shape's of the exact (wide) differences: equal
        // for directions, and for f64 points.
        if o.is_none() {
            assert_eq!(omega, Ok(t.solid_angle()), "{case:?}");
        }
    } else if o.is_none() {
        // The one-shot solid angle does not check the map's constants;
        // every other rejection is the constructor's, with the same reason.
        match &built {
            Err(e @ WarpError::Unrepresentable { .. }) => {
                assert!(
                    omega.is_ok() || omega == Err(e.clone()),
                    "{case:?}: {omega:?} {e:?}"
                )
            }
            Err(e) => assert_eq!(omega, Err(e.clone()), "{case:?}"),
            Ok(_) => unreachable!(),
        }
    }
    for u in &unit_values::<T>() {
        for v in &unit_values::<T>() {
            let once = match &o {
                None => SphericalTriangle::sample_once(&a, &b, &c, u, v),
                Some(o) => SphericalTriangle::sample_once_from_points(&a, &b, &c, o, u, v),
            };
            match (&built, once) {
                (Ok(t), Ok((p, pdf))) => {
                    let (q, qdf) = t.map_with_pdf(u, v);
                    assert!(
                        same3(&p, &q) && same(&pdf, &qdf),
                        "{case:?} at ({u}, {v}): one-shot {p:?} {pdf}, shape {q:?} {qdf}"
                    );
                    n.samples += 1;
                }
                (Err(e), Err(f)) => assert_eq!(*e, f, "{case:?}"),
                // `sample_once_from_points` does not check the plane of the
                // points (documented): the shape's only refusal may be it.
                (Err(WarpError::Unrepresentable { what }), Ok(_))
                    if o.is_some() && what.contains("plane") =>
                {
                    n.plane_only += 1
                }
                (built, once) => panic!(
                    "{case:?} at ({u}, {v}): shape {:?}, one-shot {:?}",
                    built.as_ref().err(),
                    once.err()
                ),
            }
            // The light sample of points checks the plane as the shape does.
            if let Some(o) = &o {
                let once = SphericalTriangle::sample_light_once(&a, &b, &c, o, u, v);
                if light_agrees(case, &built, once, u, v) {
                    n.light_samples += 1;
                }
            }
        }
    }
}

/// Bit for bit the same light sample (NaN equal to NaN).
fn same_light<T: Real>(a: &LightSample<T>, b: &LightSample<T>) -> bool {
    same3(&a.direction, &b.direction)
        && same3(&a.point, &b.point)
        && same(&a.distance, &b.distance)
        && same(&a.pdf, &b.pdf)
        && same(&a.pdf_area, &b.pdf_area)
}

/// The one-shot light sample `once` at `(u, v)` against the built shape's
/// `sample_light`: both accepted with the same bits, or both refused with
/// the same error; `true` if a sample was compared.
fn light_agrees<T: Real, L: LightWarp<T>>(
    case: &impl Debug,
    built: &Result<L, WarpError>,
    once: Result<LightSample<T>, WarpError>,
    u: &T,
    v: &T,
) -> bool {
    match (built, once) {
        (Ok(shape), Ok(a)) => {
            let b = shape.sample_light([u.clone(), v.clone()]);
            assert!(
                same_light(&a, &b),
                "{case:?} at ({u}, {v}): one-shot {a:?}, shape {b:?}"
            );
            true
        }
        (Err(e), Err(f)) => {
            assert_eq!(*e, f, "{case:?}");
            false
        }
        (built, once) => panic!(
            "{case:?} at ({u}, {v}): shape {:?}, light one-shot {:?}",
            built.as_ref().err(),
            once.err()
        ),
    }
}

fn rectangle<T: Real>(case: &RectangleCase, n: &mut Counts) {
    n.tried += 1;
    let [s, ex, ey, o] = [&case.s, &case.ex, &case.ey, &case.o].map(|x| v3::<T>(x));
    let built = case.build::<T>(SphericalRectangleVariant::Robust);
    let omega = SphericalRectangle::solid_angle_of(&s, &ex, &ey, &o);
    match &built {
        Ok(r) => {
            n.accepted += 1;
            assert_eq!(omega, Ok(r.solid_angle()), "{case:?}");
        }
        Err(e) => assert_eq!(omega.as_ref().err(), Some(e), "{case:?}"),
    }
    for u in &unit_values::<T>() {
        for v in &unit_values::<T>() {
            let once = SphericalRectangle::sample_once(&s, &ex, &ey, &o, u, v);
            if light_agrees(case, &built, once, u, v) {
                n.samples += 1;
            }
        }
    }
}

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

#[test]
fn one_shot_triangles_agree_with_the_shape() {
    let counts = RefCell::new([Counts::default(), Counts::default()]);
    runner(config(3000))
        .run(&triangle_case(), |case| {
            let mut n = counts.borrow_mut();
            triangle::<f32>(&case, &mut n[0]);
            triangle::<f64>(&case, &mut n[1]);
            Ok(())
        })
        .unwrap();
    let n = counts.into_inner();
    println!("triangles f32: {:?}\ntriangles f64: {:?}", n[0], n[1]);
    assert!(
        n.iter()
            .all(|c| c.accepted > 1000 && c.samples > 0 && c.light_samples > 0)
    );
}

#[test]
fn one_shot_rectangles_agree_with_the_shape() {
    let counts = RefCell::new([Counts::default(), Counts::default()]);
    runner(config(3000))
        .run(&rectangle_case(), |case| {
            let mut n = counts.borrow_mut();
            rectangle::<f32>(&case, &mut n[0]);
            rectangle::<f64>(&case, &mut n[1]);
            Ok(())
        })
        .unwrap();
    let n = counts.into_inner();
    println!("rectangles f32: {:?}\nrectangles f64: {:?}", n[0], n[1]);
    assert!(n.iter().all(|c| c.accepted > 1000 && c.samples > 0));
}

/// Triangles that `f32` can serve from one end of the arc AC and not from
/// the other (two vertices `10⁻³⁰` apart: `4/|V − B|²` of the anchor at that
/// end overflows `f32`; Ω ≈ 10⁻³⁰ does not): the constructor refuses them,
/// so the one-shot paths must refuse them for every `u`, with the same
/// error, and not sample the half of `u` whose end `f32` could hold. Their
/// `f64` versions are accepted and must agree bit for bit.
#[test]
fn one_shot_refuses_what_one_end_of_the_shape_cannot_hold() {
    let near = [1.0, 1e-30, 0.0];
    let cases = [
        // B and C close: the anchor at C fails.
        [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], near],
        // A and B close: the anchor at A fails.
        [near, [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    ];
    let (mut n32, mut n64) = (Counts::default(), Counts::default());
    for v in cases {
        for observer in [None, Some([0.0; 3])] {
            let case = TriangleCase {
                kind: "one end out of f32's range",
                v,
                observer,
            };
            let [a, b, c] = v.map(|p| v3::<f32>(&p));
            assert!(SphericalTriangle::new(a, b, c).is_err());
            for u in [0.25f32, 0.75] {
                assert!(SphericalTriangle::sample_once(&a, &b, &c, &u, &0.5).is_err());
            }
            triangle::<f32>(&case, &mut n32);
            triangle::<f64>(&case, &mut n64);
        }
    }
    assert_eq!((n32.tried, n32.accepted, n32.samples), (4, 0, 0));
    assert_eq!((n64.tried, n64.accepted, n64.samples), (4, 4, 4 * 36));
}

/// Points whose difference from the observer overflows `f64` (the one-shot
/// paths do not test the differences on their hot path; the validation
/// fails there and the constructor names the error): the one-shot paths
/// refuse them with the constructor's error.
#[test]
fn one_shot_refuses_an_overflowing_difference_as_the_constructor_does() {
    let big = f64::MAX * 0.75;
    let o = Vec3::new(-big, 0.0, 0.0);
    let (p0, p1, p2) = (
        Vec3::new(big, 0.0, 0.0),
        Vec3::new(-big, 1.0, 0.0),
        Vec3::new(-big, 0.0, 1.0),
    );
    refused_as_non_finite([p0, p1, p2, o]);
}

/// `from_points` refuses the points `p0`, `p1`, `p2` seen from `o` as not
/// finite, and both one-shot paths of points refuse them with the same
/// error, for `u` in either half.
fn refused_as_non_finite<T: Real>([p0, p1, p2, o]: [Vec3<T>; 4]) {
    let built =
        SphericalTriangle::from_points(p0.clone(), p1.clone(), p2.clone(), o.clone()).unwrap_err();
    assert!(matches!(built, WarpError::NonFinite { .. }), "{built:?}");
    let half = T::from_ratio(1, 2);
    for u in [T::from_ratio(1, 4), T::from_ratio(3, 4)] {
        let once = SphericalTriangle::sample_once_from_points(&p0, &p1, &p2, &o, &u, &half);
        assert_eq!(once.unwrap_err(), built);
        let light = SphericalTriangle::sample_light_once(&p0, &p1, &p2, &o, &u, &half);
        assert_eq!(light.unwrap_err(), built);
    }
}

/// Points or an observer that are not finite (the one-shot paths of points
/// do not test them on their hot path; the validation fails there and the
/// constructor names the error), and vertex directions that are not: the
/// one-shot paths refuse them with the constructor's error, in `f32` and
/// `f64`.
#[test]
fn one_shot_refuses_non_finite_points_as_the_constructor_does() {
    fn check<T: Real>() {
        let p = |x: f64, y: f64, z: f64| Vec3::new(T::from_f64(x), T::from_f64(y), T::from_f64(z));
        let (inf, nan) = (f64::INFINITY, f64::NAN);
        let cases = [
            [
                p(nan, 0.0, 1.0),
                p(1.0, 0.0, 1.0),
                p(0.0, 1.0, 1.0),
                p(0.0, 0.0, 0.0),
            ],
            [
                p(0.0, 0.0, 1.0),
                p(1.0, inf, 1.0),
                p(0.0, 1.0, 1.0),
                p(0.0, 0.0, 0.0),
            ],
            [
                p(0.0, 0.0, 1.0),
                p(1.0, 0.0, 1.0),
                p(0.0, 1.0, -inf),
                p(0.0, 0.0, 0.0),
            ],
            [
                p(0.0, 0.0, 1.0),
                p(1.0, 0.0, 1.0),
                p(0.0, 1.0, 1.0),
                p(inf, 0.0, 0.0),
            ],
            [
                p(0.0, 0.0, 1.0),
                p(1.0, 0.0, 1.0),
                p(0.0, 1.0, 1.0),
                p(0.0, nan, 0.0),
            ],
        ];
        for case in cases {
            refused_as_non_finite(case.clone());
            // The same vertices as directions (observer at the origin).
            let [a, b, c, o] = case;
            if o.is_finite() {
                directions_refused_as_non_finite([a, b, c]);
            }
        }
    }
    check::<f32>();
    check::<f64>();
}

/// `new` refuses the vertex directions `a`, `b`, `c` as not finite, and
/// the one-shot sample (for `u` in either half) and the one-shot solid
/// angle refuse them with the same error.
fn directions_refused_as_non_finite<T: Real>([a, b, c]: [Vec3<T>; 3]) {
    let built = SphericalTriangle::new(a.clone(), b.clone(), c.clone()).unwrap_err();
    assert!(matches!(built, WarpError::NonFinite { .. }), "{built:?}");
    let half = T::from_ratio(1, 2);
    for u in [T::from_ratio(1, 4), T::from_ratio(3, 4)] {
        let once = SphericalTriangle::sample_once(&a, &b, &c, &u, &half);
        assert_eq!(once.unwrap_err(), built);
    }
    assert_eq!(
        SphericalTriangle::solid_angle_of(&a, &b, &c).unwrap_err(),
        built
    );
}
