use super::reference::{Moments, PlanarLight};
use super::*;
use crate::harness::chi2::{Binning, run_chi_square};
use crate::harness::extremes::{extremes_grid, random_points};
use crate::harness::roundtrip::check_roundtrip;
use crate::shapes::polygon_measures::{projected_solid_angle, solid_angle};
use crate::warp::{LightWarp, WarpFamily};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::f64::consts::PI;

/// The test lights: planar polygons in space seen from the origin (normal +z).
pub(super) fn lights() -> Vec<(&'static str, PlanarLight)> {
    let star = |n: usize, c: (f64, f64), ro: f64, ri: f64, z: f64| -> Vec<[f64; 3]> {
        (0..2 * n)
            .map(|i| {
                let a = PI * i as f64 / n as f64 + 0.1;
                let r = if i % 2 == 0 { ro } else { ri };
                [c.0 + r * a.cos(), c.1 + r * a.sin(), z]
            })
            .collect()
    };
    vec![
        (
            "convex",
            PlanarLight::new(&[
                [-0.3, 0.2, 1.0],
                [0.6, 0.1, 1.0],
                [0.7, 0.9, 1.0],
                [-0.2, 0.8, 1.0],
            ]),
        ),
        (
            "comb",
            PlanarLight::new(&[
                [0.3, -0.3, 1.0],
                [0.4, -0.3, 1.0],
                [0.4, 0.3, 1.0],
                [0.6, 0.3, 1.0],
                [0.6, -0.3, 1.0],
                [0.7, -0.3, 1.0],
                [0.7, 0.3, 1.0],
                [0.9, 0.3, 1.0],
                [0.9, -0.3, 1.0],
                [1.0, -0.3, 1.0],
                [1.0, 0.4, 1.0],
                [0.3, 0.4, 1.0],
            ]),
        ),
        (
            "around-pole",
            PlanarLight::new(
                &(0..5)
                    .map(|i| {
                        let a = 2.0 * PI * i as f64 / 5.0 + 0.3;
                        [0.1 + 0.7 * a.cos(), -0.05 + 0.7 * a.sin(), 1.0]
                    })
                    .collect::<Vec<_>>(),
            ),
        ),
        (
            "star-around-pole",
            PlanarLight::new(&star(6, (0.05, 0.1), 1.2, 0.5, 0.8)),
        ),
        (
            "horizon",
            PlanarLight::new(&[
                [1.0, -0.5, 0.6],
                [1.0, 0.5, 0.6],
                [1.0, 0.5, -0.4],
                [1.0, -0.5, -0.4],
            ]),
        ),
        (
            "horizon-split",
            // Asymmetric, so that u = 1/2 (an input of the precision
            // check) does not fall on the jump between the two pieces.
            PlanarLight::new(&[
                [1.0, -0.55, -0.5],
                [1.0, 0.6, -0.5],
                [1.0, 0.6, 0.7],
                [1.0, 0.3, 0.7],
                [1.0, 0.3, -0.2],
                [1.0, -0.3, -0.2],
                [1.0, -0.3, 0.7],
                [1.0, -0.55, 0.7],
            ]),
        ),
        (
            "pole-vertex",
            PlanarLight::new(&[[0.0, 0.0, 1.0], [0.8, 0.1, 1.0], [0.3, 0.7, 1.0]]),
        ),
        (
            "pole-edge",
            PlanarLight::new(&[[-0.5, 0.0, 1.0], [0.5, 0.0, 1.0], [0.0, 0.6, 1.0]]),
        ),
        (
            "horizon-vertex",
            PlanarLight::new(&[[1.0, -0.3, 0.0], [1.0, 0.4, 0.5], [0.6, 0.2, 0.9]]),
        ),
        (
            "horizon-edge",
            PlanarLight::new(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 1.0]]),
        ),
        (
            "wide-horizon",
            // Around the pole and below the horizon on one side: the
            // clipped boundary follows the horizon for more than a quarter
            // turn.
            PlanarLight::new(&[
                [-3.0, -1.0, 1.0],
                [3.0, -1.0, 1.0],
                [3.0, 1.0, -0.2],
                [-3.0, 1.0, -0.2],
            ]),
        ),
    ]
}

fn warp_of(light: &PlanarLight, inv: MarginalInversion) -> ProjectedPolygon<f64> {
    ProjectedPolygon::new_with(&light.points, inv).expect("valid test polygon")
}

const SETTINGS: [MarginalInversion; 4] = [
    MarginalInversion::Cubic,
    MarginalInversion::CubicNewton(1),
    MarginalInversion::CubicNewton(3),
    MarginalInversion::Newton,
];

fn finite_on_shape<T: Real>(name: &str, w: &ProjectedPolygon<T>) {
    let mut pts = extremes_grid();
    pts.extend(random_points(200, 11));
    let tol = T::unit_roundoff() * &T::from_i64(16);
    for (u, v) in pts {
        let p = w.map(&T::from_f64(u), &T::from_f64(v));
        assert!(p.is_finite(), "{name} {u} {v}: {p:?}");
        let out = w.outside_by(&p);
        assert!(out <= tol, "{name} {u} {v}: {p:?} outside by {out}");
        let d = w.pdf(&p);
        assert!(d.is_finite() && d >= T::zero(), "{name}: pdf {d}");
    }
    // Π as the constructor summed it (for f32 from the wide lunes,
    // `narrow_measure`) is the sum the sampled parts accumulate: the same
    // bits, which the cumulative areas of `select` rely on.
    let mut lunes = w.parts().lunes.clone();
    assert!(
        build::accumulate(&mut lunes) == w.measure(),
        "{name}: Π of the parts differs from the constructor's"
    );
}

#[test]
fn projected_polygon_finite_on_shape_f64_and_f32() {
    for (name, light) in lights() {
        for inv in SETTINGS {
            let w = warp_of(&light, inv);
            finite_on_shape(name, &w);
            finite_on_shape(name, &w.at::<f32>().unwrap());
        }
    }
}

#[test]
fn projected_polygon_constructor_errors() {
    let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    let is_degenerate = |r: Result<ProjectedPolygon<f64>, WarpError>| {
        matches!(r, Err(WarpError::Degenerate { .. }))
    };
    let tri = [v(0.2, 0.0, 1.0), v(0.0, 0.3, 1.0), v(-0.1, -0.1, 1.0)];
    assert!(ProjectedPolygon::new(&tri).is_ok());
    assert!(is_degenerate(ProjectedPolygon::new(&tri[..2])));
    // By points: fewer than three are refused, none included (the light's
    // plane, which reads the corners, must not be made before that).
    let (o, n) = (v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0));
    for k in 0..3 {
        assert!(is_degenerate(ProjectedPolygon::from_points(
            &tri[..k],
            &o,
            &n
        )));
    }
    assert!(ProjectedPolygon::from_points(&tri, &o, &n).is_ok());
    let mut nan = tri;
    nan[1].y = f64::NAN;
    assert!(matches!(
        ProjectedPolygon::new(&nan),
        Err(WarpError::NonFinite { .. })
    ));
    let mut inf = tri;
    inf[2].z = f64::INFINITY;
    assert!(matches!(
        ProjectedPolygon::new(&inf),
        Err(WarpError::NonFinite { .. })
    ));
    // Zero direction; coincident vertices (same direction, other length)
    // leaving two distinct directions (a repeated vertex of a polygon with
    // three distinct ones is dropped: `tests/coincident.rs`), and antipodal
    // consecutive vertices.
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(0.0, 0.0, 0.0),
        tri[1],
        tri[2]
    ])));
    assert!(is_degenerate(ProjectedPolygon::new(&[
        tri[0],
        tri[0].scale(&3.0),
        tri[1],
        tri[1].scale(&0.7)
    ])));
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(0.0, 0.0, 1.0),
        v(0.0, 0.0, -1.0),
        v(1.0, 0.0, 0.0)
    ])));
    // All below the horizon; touching it along an edge from below.
    let below: Vec<_> = tri.iter().map(|p| v(p.x, p.y, -p.z)).collect();
    assert!(is_degenerate(ProjectedPolygon::new(&below)));
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(1.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.5, 0.5, -1.0)
    ])));
    // A great circle: both sides have 2π.
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(1.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(-1.0, 0.0, 0.0),
        v(0.0, -1.0, 0.0)
    ])));
    // A spike folding straight back, and collinear vertices only.
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(0.0, 0.0, 1.0),
        v(0.5, 0.0, 1.0),
        v(0.2, 0.0, 1.0),
        v(0.2, 0.3, 1.0)
    ])));
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(0.0, 0.0, 1.0),
        v(0.5, 0.0, 1.0),
        v(0.8, 0.0, 1.0)
    ])));
    // A bow tie (self-intersecting quadrilateral).
    assert!(is_degenerate(ProjectedPolygon::new(&[
        v(0.1, 0.1, 1.0),
        v(0.6, 0.6, 1.0),
        v(0.6, 0.1, 1.0),
        v(0.1, 0.6, 1.0)
    ])));
    // from_points: zero or non-finite normal, non-finite observer.
    let o = v(0.0, 0.0, 0.0);
    assert!(is_degenerate(ProjectedPolygon::from_points(
        &tri,
        &o,
        &v(0.0, 0.0, 0.0)
    )));
    assert!(matches!(
        ProjectedPolygon::from_points(&tri, &o, &v(0.0, f64::NAN, 1.0)),
        Err(WarpError::NonFinite { .. })
    ));
    assert!(matches!(
        ProjectedPolygon::from_points(&tri, &v(f64::INFINITY, 0.0, 0.0), &v(0.0, 0.0, 1.0)),
        Err(WarpError::NonFinite { .. })
    ));
    // The observer in the polygon's plane: every direction is horizontal.
    assert!(is_degenerate(ProjectedPolygon::from_points(
        &tri,
        &v(0.0, 0.0, 1.0),
        &v(0.0, 0.0, 1.0)
    )));
}

/// The normalizations take the largest magnitude by comparisons, which pass
/// over a NaN in the second or third coordinate: a NaN, an infinity or the
/// zero vector still gives no unit vector, in every position.
#[test]
fn projected_polygon_normalizations_refuse_non_finite_and_zero() {
    use super::geometry::{scaled_unit, unit_direction};
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for k in 0..3 {
            let mut c = [0.5, -2.0, 1.0];
            c[k] = bad;
            let v = Vec3::new(c[0], c[1], c[2]);
            assert!(scaled_unit(&v).is_none(), "{v:?}");
            assert!(unit_direction(&v, "vertex").is_err(), "{v:?}");
        }
    }
    let zero = Vec3::new(0.0, 0.0, 0.0);
    assert!(scaled_unit(&zero).is_none());
    assert!(unit_direction(&zero, "vertex").is_err());
    for v in [
        Vec3::new(0.5, -2.0, 1.0),
        Vec3::new(-3.0, 1e-300, 0.0),
        Vec3::new(0.0, 0.0, -1e-310),
    ] {
        let (a, b) = (
            scaled_unit(&v).unwrap(),
            unit_direction(&v, "vertex").unwrap(),
        );
        for u in [a, b] {
            assert!((u.norm() - 1.0).abs() <= 2.0 * f64::EPSILON, "{v:?}: {u:?}");
            assert!(u.dot(&v) > 0.0, "{v:?}: {u:?}");
        }
    }
    // A polygon of subnormal directions is the polygon they point along
    // (its vertices' reciprocals overflow; the constructor used to call
    // them zero vectors). At 1e-322 (20 units of the smallest subnormal)
    // the scaled coordinates are whole units, so the directions are exact.
    let quad = [
        [-0.3, 0.2, 1.0],
        [0.6, 0.1, 1.0],
        [0.7, 0.9, 1.0],
        [-0.2, 0.8, 1.0],
    ];
    let at = |k: f64| quad.map(|p| Vec3::new(p[0] * k, p[1] * k, p[2] * k));
    let unit = ProjectedPolygon::<f64>::new(&at(1.0)).unwrap().measure();
    for k in [1e-300, 4e-309, 1e-310, 1e-322] {
        let tiny = ProjectedPolygon::<f64>::new(&at(k)).unwrap().measure();
        assert!(
            (tiny - unit).abs() <= 1e-12 * unit,
            "scale {k:e}: {tiny} against {unit}"
        );
    }
}

#[test]
fn projected_polygon_either_orientation_same_polygon() {
    for (name, light) in lights() {
        let w = warp_of(&light, MarginalInversion::Newton);
        let mut rev = light.points.clone();
        rev.reverse();
        let r = ProjectedPolygon::new(&rev).unwrap();
        assert!((w.measure() - r.measure()).abs() < 1e-14, "{name}");
        for (u, v) in random_points(20, 3) {
            let a = w.map(&u, &v);
            assert!(r.outside_by(&a) < 1e-14, "{name}");
        }
    }
}

/// Π against Lambert's formula (unclipped polygons) and against the
/// independent quadrature (all).
#[test]
fn projected_polygon_measure_matches_lambert_and_quadrature() {
    let up = Vec3::new(0.0, 0.0, 1.0);
    for (name, light) in lights() {
        let w = warp_of(&light, MarginalInversion::Newton);
        let reference = light.moments().area;
        assert!(
            (w.measure() - reference).abs() < 1e-12,
            "{name}: Π = {} vs quadrature {reference}",
            w.measure()
        );
        if light.points.iter().all(|p| p.z >= 0.0) {
            let lambert = projected_solid_angle(&light.points, &up).abs();
            assert!(
                (w.measure() - lambert).abs() < 1e-14,
                "{name}: Π = {} vs Lambert {lambert}",
                w.measure()
            );
            // Lambert against the quadrature: the formula itself.
            assert!((lambert - reference).abs() < 1e-12, "{name}");
        }
        let omega = solid_angle(&light.points);
        assert!((w.solid_angle() - omega).abs() < 1e-13, "{name}");
        assert!(w.measure() <= omega.min(PI) + 1e-15, "{name}");
    }
}

/// A non-planar polygon: a band ±10° about the horizon over three quarters
/// of a turn. Clipped, it keeps its upper half, whose boundary follows the
/// horizon for 270° (more than half a turn, split into pieces). Π against
/// Lambert's formula on the hand-clipped polygon (upper row, then the
/// horizon back in 45° steps).
#[test]
fn projected_polygon_band_along_the_horizon() {
    let el = 10f64.to_radians();
    let dir = |az_deg: f64, el: f64| {
        let a = az_deg.to_radians();
        Vec3::new(el.cos() * a.cos(), el.cos() * a.sin(), el.sin())
    };
    let upper: Vec<_> = (0..=6).map(|i| dir(45.0 * i as f64, el)).collect();
    let lower: Vec<_> = (0..=6).rev().map(|i| dir(45.0 * i as f64, -el)).collect();
    let band: Vec<_> = upper.iter().chain(lower.iter()).cloned().collect();
    let clipped: Vec<_> = upper
        .iter()
        .cloned()
        .chain((0..=6).rev().map(|i| dir(45.0 * i as f64, 0.0)))
        .collect();
    let lambert = projected_solid_angle(&clipped, &Vec3::new(0.0, 0.0, 1.0)).abs();
    for inv in SETTINGS {
        let w = ProjectedPolygon::new_with(&band, inv).unwrap();
        assert!(
            (w.measure() - lambert).abs() < 1e-14,
            "{} {lambert}",
            w.measure()
        );
        assert!(w.solid_angle() < 2.0 * PI);
        finite_on_shape("band", &w);
        finite_on_shape("band", &w.at::<f32>().unwrap());
    }
    let w = ProjectedPolygon::new(&band).unwrap();
    let rt = check_roundtrip::<f64, _>(&w, &random_points(300, 8)).unwrap();
    assert!(rt.failures == 0 && rt.median_error < 1e-12, "{rt:?}");
    for (u, v) in random_points(300, 9) {
        let p = w.map(&u, &v);
        // The great arcs between the upper vertices bulge poleward, to
        // tan(el_max) = tan(el) / cos(22.5°).
        let el_max = (el.tan() / 22.5f64.to_radians().cos()).atan();
        assert!(p.z >= 0.0 && p.z <= el_max.sin() + 1e-15, "{p:?}");
        let az = p.y.atan2(p.x).rem_euclid(2.0 * PI);
        assert!(az <= 1.5 * PI + 1e-12, "{az}");
    }
}

#[test]
fn projected_polygon_pdf_and_roundtrip() {
    for (name, light) in lights() {
        let w = warp_of(&light, MarginalInversion::Newton);
        let mut pts = extremes_grid();
        pts.extend(random_points(300, 5));
        for &(u, v) in &pts {
            let p = w.map(&u, &v);
            let want = p.z / p.norm() / w.measure();
            assert!((w.pdf(&p) - want).abs() <= 1e-15 * want.max(1.0), "{name}");
        }
        let rt = check_roundtrip::<f64, _>(&w, &pts).unwrap();
        assert_eq!(rt.failures, 0, "{name}: {rt:?}");
        assert!(rt.max_image_ulps < 1e4, "{name}: {rt:?}");
        // Away from the pole (where u is not defined), parameters come back.
        let inner = random_points(300, 6);
        let rt = check_roundtrip::<f64, _>(&w, &inner).unwrap();
        assert!(rt.median_error < 1e-13, "{name}: {rt:?}");
        let rt32 = check_roundtrip::<f32, _>(&w, &inner).unwrap();
        assert_eq!(rt32.failures, 0, "{name}: {rt32:?}");
        assert!(rt32.median_error < 1e-4, "{name}: {rt32:?}");
    }
    // Off the polygon: no inverse.
    let w = warp_of(&lights()[0].1, MarginalInversion::Newton);
    assert!(w.inverse(&Vec3::new(0.0, 0.0, -1.0)).is_err());
    assert!(w.inverse(&Vec3::new(-1.0, -1.0, 0.2)).is_err());
    assert!(w.inverse(&Vec3::new(f64::NAN, 0.0, 1.0)).is_err());
    assert!(w.outside_by(&Vec3::new(-1.0, -1.0, 0.2)) > 0.1);
}

#[test]
fn projected_polygon_from_points_frame() {
    // The same light seen from an observer at o on a tilted receiver: the
    // sampled world directions must follow the local-frame polygon.
    let light = &lights()[1].1;
    let o = Vec3::new(0.1, -0.2, 0.05);
    let n = Vec3::new(0.2, -0.1, 1.0);
    let w = ProjectedPolygon::from_points(&light.points, &o, &n).unwrap();
    let nn = n.normalized().unwrap();
    for (u, v) in random_points(200, 9) {
        let d = w.map(&u, &v);
        assert!((d.norm() - 1.0).abs() < 1e-15);
        assert!(w.outside_by(&d) < 1e-14);
        assert!(d.dot(&nn) >= 0.0);
        assert!((w.pdf(&d) - d.dot(&nn) / w.measure()).abs() < 1e-14);
        // The ray from o along d hits the light's plane inside the light.
        let shifted: Vec<[f64; 3]> = light
            .points
            .iter()
            .map(|p| {
                let q = p.sub(&o);
                [q.x, q.y, q.z]
            })
            .collect();
        assert!(PlanarLight::new(&shifted).inside(&d));
        let [u2, v2] = w.inverse(&d).unwrap();
        assert!((u2 - u).abs() < 1e-10 && (v2 - v).abs() < 1e-10);
    }
    let g = w.at::<f32>().unwrap();
    assert!((g.measure() as f64 - w.measure()).abs() < 1e-5);
}

/// A polygon given by points whose plane `f32` cannot hold is refused by
/// `from_points` (as the triangle's `from_points` refuses it), where it
/// used to be accepted with light samples on the unit sphere, off the
/// emitter; `f64` holds the same plane and places every sample on it.
/// Given as directions, the same polygon is accepted in `f32` and keeps
/// the documented unit-sphere point.
#[test]
fn projected_polygon_from_points_refuses_a_plane_the_type_cannot_hold() {
    let o = Vec3::new(0.0, 0.0, 0.0);
    let n = Vec3::new(0.0, 0.0, 1.0);
    // A square 10²² across, 10²⁸ away: its density in area, about 10⁻⁴⁴,
    // is below f32's normal range; its directions are ordinary.
    let (s, z) = (1e22, 1e28);
    let p64 = [
        Vec3::new(-s, -s, z),
        Vec3::new(s, -s, z),
        Vec3::new(s, s, z),
        Vec3::new(-s, s, z),
    ];
    let p32: Vec<Vec3<f32>> = p64.iter().map(|p| p.convert()).collect();
    assert!(matches!(
        ProjectedPolygon::<f32>::from_points(&p32, &o.convert(), &n.convert()),
        Err(WarpError::Unrepresentable { .. })
    ));
    let w = ProjectedPolygon::<f64>::from_points(&p64, &o, &n).unwrap();
    for (u, v) in random_points(64, 5) {
        let l = w.sample_light([u, v]);
        assert!((l.point.z - z).abs() <= 1e-14 * z, "{l:?}");
        assert!(l.point.x.abs() <= s * (1.0 + 1e-12) && l.point.y.abs() <= s * (1.0 + 1e-12));
        assert!(l.pdf_area > 0.0 && l.pdf_area < 1e-40, "{l:?}");
    }
    // The same corners as vertex directions: accepted in f32, the point on
    // the unit sphere (`new` is given no emitter to refuse).
    let w = ProjectedPolygon::<f32>::new(&p32).unwrap();
    let l = w.sample_light([0.3, 0.6]);
    assert_eq!((l.distance, l.point), (1.0, l.direction));
}

#[test]
fn projected_polygon_family_and_settings() {
    let light = &lights()[0].1;
    let w = warp_of(light, MarginalInversion::CubicNewton(2));
    assert_eq!(w.name(), "projected-polygon");
    assert_eq!(
        w.at::<f32>().unwrap().inversion(),
        MarginalInversion::CubicNewton(2)
    );
    assert_eq!(
        w.clone()
            .with_inversion(MarginalInversion::Cubic)
            .inversion(),
        MarginalInversion::Cubic
    );
    assert_eq!(MarginalInversion::default(), MarginalInversion::Newton);
    assert_eq!(w.lune_count(), 3);
    assert_eq!(w.max_edges_per_lune(), 2);
    let comb = warp_of(&lights()[1].1, MarginalInversion::Newton);
    assert_eq!(comb.max_edges_per_lune(), 6);
    let pole = warp_of(&lights()[2].1, MarginalInversion::Newton);
    assert_eq!(pole.max_edges_per_lune(), 1);
}

/// More Newton steps, smaller backward error; Newton converged to the
/// rounding level.
#[test]
fn projected_polygon_inversion_settings_converge() {
    for (name, light) in lights() {
        let w = warp_of(&light, MarginalInversion::Newton);
        let mut prev = f64::INFINITY;
        for inv in SETTINGS {
            let wi = w.clone().with_inversion(inv);
            let mut worst: f64 = 0.0;
            for (u, _) in random_points(200, 21) {
                let phi = wi.azimuth(&u);
                worst = worst.max((w.marginal_cdf(&phi) - u).abs());
            }
            assert!(worst <= prev.max(1e-15), "{name} {inv:?}: {worst} > {prev}");
            if inv == MarginalInversion::Newton {
                assert!(worst < 1e-14, "{name}: {worst}");
            }
            if inv == MarginalInversion::Cubic {
                assert!(worst < 2e-3, "{name}: {worst}");
            }
            println!("{name} {inv:?}: max |u − F(φ̂)| = {worst:.2e}");
            prev = worst;
        }
    }
}

/// Moments of a warp's samples: 16 independent jittered N×N replicas.
fn sample_moments(w: &ProjectedPolygon<f64>, n: usize, seed: u64) -> Vec<[f64; 5]> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..16)
        .map(|_| {
            let mut acc = [0.0; 5];
            for i in 0..n {
                for j in 0..n {
                    let u = (i as f64 + rng.random::<f64>()) / n as f64;
                    let v = (j as f64 + rng.random::<f64>()) / n as f64;
                    let p = w.map(&u, &v);
                    let f = [p.x, p.y, p.x * p.x, p.x * p.y, p.y * p.y];
                    for k in 0..5 {
                        acc[k] += f[k];
                    }
                }
            }
            acc.map(|a| a / (n * n) as f64)
        })
        .collect()
}

/// (mean − exact) / σ(mean) for the five moments, and the largest
/// |mean − exact| and σ(mean).
fn moment_z_scores(
    w: &ProjectedPolygon<f64>,
    m: &Moments,
    n: usize,
    seed: u64,
) -> ([f64; 5], f64, f64) {
    let reps = sample_moments(w, n, seed);
    let exact = [m.x, m.y, m.xx, m.xy, m.yy].map(|x| x / m.area);
    let mut z = [0.0; 5];
    let (mut dev, mut sig) = (0.0f64, 0.0f64);
    for k in 0..5 {
        let mean = reps.iter().map(|r| r[k]).sum::<f64>() / reps.len() as f64;
        let var = reps.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (reps.len() - 1) as f64;
        let sigma = (var / reps.len() as f64).sqrt().max(1e-13);
        z[k] = (mean - exact[k]) / sigma;
        dev = dev.max((mean - exact[k]).abs());
        sig = sig.max(sigma);
    }
    (z, dev, sig)
}

/// |z| < `bound` for the five moments of every test polygon. σ comes from
/// 16 replicas (Student's t with 15 degrees of freedom: P(|t| > 5) ≈ 1.6e-4
/// per moment, about 1 % for the 55 moments together). Each polygon gets its
/// own random stream, so that the z-scores are independent.
fn check_moments(n: usize, bound: f64) {
    for (seed, (name, light)) in lights().into_iter().enumerate() {
        let w = warp_of(&light, MarginalInversion::Newton);
        let m = light.moments();
        let (z, dev, sigma) = moment_z_scores(&w, &m, n, 1000 + seed as u64);
        println!("{name}: z-scores {z:.2?}, max |mean − exact| = {dev:.1e} (max σ = {sigma:.1e})");
        assert!(z.iter().all(|x| x.abs() < bound), "{name}: {z:?}");
    }
}

/// ~10⁵ stratified samples per polygon (16 replicas of 79²).
#[test]
fn projected_polygon_moments_match_exact() {
    check_moments(79, 5.0);
}

/// 10⁶ stratified samples per polygon (16 replicas of 250²).
#[test]
#[ignore]
fn projected_polygon_moments_match_exact_1e6() {
    check_moments(250, 5.0);
}

/// χ² bins: equal azimuth sectors × equal r² bins (the projected-area
/// measure is r dr dφ = ½ d(r²) dφ, so the cells are map-independent).
struct AzimuthRadiusBins {
    nphi: usize,
    ns: usize,
    probs: Vec<f64>,
}

impl Binning for AzimuthRadiusBins {
    fn n_bins(&self) -> usize {
        self.nphi * self.ns
    }
    fn bin(&self, p: &Vec3<f64>) -> Option<usize> {
        let d = p.normalized()?;
        if d.z < -1e-9 || (p.norm() - 1.0).abs() > 1e-9 {
            return None;
        }
        let mut a = d.y.atan2(d.x) / (2.0 * PI);
        if a < 0.0 {
            a += 1.0;
        }
        let i = ((a * self.nphi as f64) as usize).min(self.nphi - 1);
        let r2 = d.x * d.x + d.y * d.y;
        let j = ((r2 * self.ns as f64) as usize).min(self.ns - 1);
        Some(i * self.ns + j)
    }
    fn probability(&self, i: usize) -> f64 {
        self.probs[i]
    }
}

fn check_chi2(samples: usize) {
    let all = lights();
    for (name, light) in &all {
        let bins = AzimuthRadiusBins {
            nphi: 48,
            ns: 12,
            probs: light.cell_probabilities(48, 12),
        };
        let w = warp_of(light, MarginalInversion::Newton);
        let out = run_chi_square(&w, &bins, samples, 3, 0.01, all.len() as u32);
        println!(
            "{name}: χ² = {:.1}, dof = {}, p = {:.3}",
            out.statistic, out.dof, out.p_value
        );
        assert!(out.passed, "{name}: {out:?}");
    }
}

#[test]
fn projected_polygon_chi_square() {
    check_chi2(100_000);
}

#[test]
#[ignore]
fn projected_polygon_chi_square_1e6() {
    check_chi2(1_000_000);
}

/// Asserts that the direction `d` is within 4u of the polygon both at 256
/// bits (`exact`, the polygon rebuilt from the same input) and by the f64
/// polygon's own `outside_by`, and that `w.inverse` accepts it (`what`
/// names the case in the messages): the check of the regression tests
/// `extremal_vertex` and `horizon_sliver`.
/// The polygon of the directions `v` in f64 and, from the same values, at
/// 256 bits.
#[cfg(feature = "mpfr")]
fn f64_and_exact(
    v: &[Vec3<f64>],
) -> (
    ProjectedPolygon<f64>,
    ProjectedPolygon<crate::real::Mpfr256>,
) {
    let wide: Vec<Vec3<crate::real::Mpfr256>> = v.iter().map(|p| p.convert()).collect();
    (
        ProjectedPolygon::new(v).unwrap(),
        ProjectedPolygon::new(&wide).unwrap(),
    )
}

#[cfg(feature = "mpfr")]
fn assert_on_polygon(
    w: &ProjectedPolygon<f64>,
    exact: &ProjectedPolygon<crate::real::Mpfr256>,
    d: &Vec3<f64>,
    what: &str,
) {
    let tol = 4.0 * f64::EPSILON / 2.0;
    let (by_f64, by_exact) = (w.outside_by(d), exact.outside_by(&d.convert()).to_f64());
    assert!(
        by_exact <= tol,
        "{what}: {d:?} is {by_exact:e} off at 256 bits"
    );
    assert!(by_f64 <= tol, "{what}: {d:?} is {by_f64:e} off in f64");
    assert!(w.inverse(d).is_ok(), "{what}: {d:?} refused");
}

mod coincident;
#[cfg(feature = "mpfr")]
mod extremal_vertex;
#[cfg(feature = "mpfr")]
mod horizon_sliver;
#[cfg(feature = "mpfr")]
mod mpfr;
