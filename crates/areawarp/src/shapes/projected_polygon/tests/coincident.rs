//! Repeated and nearly repeated vertices (`coincident.rs`): a vertex whose
//! direction coincides with its predecessor's is dropped while three
//! distinct directions remain; the polygon is then the one without it.

use super::*;

fn v(p: [f64; 3]) -> Vec3<f64> {
    Vec3::new(p[0], p[1], p[2])
}

/// A triangle light off the pole (plane z = 1), with coordinates of few
/// bits: their multiples by 3 and by 0.75 are exact (the same directions).
const TRI: [[f64; 3]; 3] = [[-0.375, 0.25, 1.0], [0.625, 0.125, 1.0], [0.75, 0.875, 1.0]];

fn tri() -> [Vec3<f64>; 3] {
    TRI.map(v)
}

/// Whether `a` and `b` have exactly the same direction, from error-free
/// products (`f64` input of moderate exponents): every component of
/// `a × b` is exactly zero and `a · b > 0`.
fn exactly_parallel(a: &Vec3<f64>, b: &Vec3<f64>) -> bool {
    let zero_diff = |p: f64, q: f64, r: f64, s: f64| {
        // p·q − r·s = 0 exactly?
        let (x, y) = (p * q, r * s);
        x == y && p.mul_add(q, -x) == r.mul_add(s, -y)
    };
    zero_diff(a.y, b.z, a.z, b.y)
        && zero_diff(a.z, b.x, a.x, b.z)
        && zero_diff(a.x, b.y, a.y, b.x)
        && a.dot(b) > 0.0
}

/// The grid the comparisons sample: the extremes and random points.
fn points() -> Vec<(f64, f64)> {
    let mut pts = extremes_grid();
    pts.extend(random_points(64, 21));
    pts
}

/// `q` is the polygon `t` (the same map within `tol` per sample, the same
/// measure and solid angle to `tol` relative, and for `tol = 0` the same
/// lunes), and passes the contract:
/// samples on its own shape, accepted by its own inverse, finite density.
fn same_polygon<T: Real>(name: &str, q: &ProjectedPolygon<T>, t: &ProjectedPolygon<T>, tol: f64) {
    let rel = |a: T, b: T| ((a.clone() - &b).abs() / &b).to_f64();
    assert!(rel(q.measure(), t.measure()) <= tol, "{name}: measure");
    assert!(rel(q.solid_angle(), t.solid_angle()) <= tol, "{name}: Ω");
    if tol == 0.0 {
        assert_eq!(q.lune_count(), t.lune_count(), "{name}");
    }
    finite_on_shape(name, q);
    for (u, w) in points() {
        let (u, w) = (T::from_f64(u), T::from_f64(w));
        let (p, r) = (q.map(&u, &w), t.map(&u, &w));
        let d = p.sub(&r).norm().to_f64();
        assert!(d <= tol, "{name} at {u:?}, {w:?}: {p:?} vs {r:?} ({d:e})");
        assert!(q.inverse(&p).is_ok(), "{name}: inverse refuses {p:?}");
        assert!(rel(q.pdf(&p), t.pdf(&r)) <= tol.max(1e-15), "{name}: pdf");
    }
}

#[test]
fn quad_with_a_repeated_vertex_is_the_triangle() {
    let [a, b, c] = tri();
    let t = ProjectedPolygon::new(&tri()).unwrap();
    // Kept: the first vertex of each run, cyclically; the same unit
    // vertices in the same order as the triangle's, hence the same bits.
    for (name, quad) in [
        ("a a b c", vec![a, a, b, c]),
        ("a b b c", vec![a, b, b, c]),
        ("a b c c", vec![a, b, c, c]),
        ("a b c a (first = last)", vec![a, b, c, a]),
        ("a a a b c a", vec![a, a, a, b, c, a]),
        ("a 3a b c (other length)", vec![a, a.scale(&3.0), b, c]),
        ("a b 0.75c c", vec![a, b, c.scale(&0.75), c]),
    ] {
        let q = ProjectedPolygon::new(&quad).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        same_polygon(name, &q, &t, 0.0);
        // f32: decided on the same values in f64.
        let (q32, t32) = (q.at::<f32>().unwrap(), t.at::<f32>().unwrap());
        same_polygon(name, &q32, &t32, 0.0);
    }
    // Starting elsewhere on the boundary: the triangle from another vertex,
    // the same polygon up to the rounding of its construction.
    let q = ProjectedPolygon::new(&[b, c, a, a]).unwrap();
    same_polygon("b c a a", &q, &t, 1e-13);
}

#[test]
fn points_with_a_repeated_corner_or_on_one_ray_from_the_observer() {
    let o = Vec3::new(0.25, 0.5, 0.0);
    let n = Vec3::new(0.1, -0.2, 1.0);
    let [a, b, c] = [[0.0, 0.0, 2.0], [0.75, 1.5, 2.0], [0.0, 1.0, 2.5]].map(v);
    let t = ProjectedPolygon::from_points(&[a, b, c], &o, &n).unwrap();
    // b repeated; then b' = o + 3 (b − o) (exact), another corner on the
    // ray from the observer through b: the same direction.
    let b3 = o.add(&b.sub(&o).scale(&3.0));
    assert_eq!(b3.sub(&o), b.sub(&o).scale(&3.0));
    for (name, quad) in [
        ("a b b c", [a, b, b, c]),
        ("a b b' c", [a, b, b3, c]),
        ("a b c a", [a, b, c, a]),
    ] {
        let q = ProjectedPolygon::from_points(&quad, &o, &n)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        same_polygon(name, &q, &t, 0.0);
        same_polygon(name, &q.at::<f32>().unwrap(), &t.at::<f32>().unwrap(), 0.0);
    }
}

#[test]
fn fewer_than_three_distinct_directions_is_an_error() {
    let [a, b, _] = tri();
    let fewer = |r: Result<ProjectedPolygon<f64>, WarpError>| matches!(r, Err(WarpError::Degenerate { what }) if what.contains("fewer than 3 distinct"));
    assert!(fewer(ProjectedPolygon::new(&[a, a, a, a])));
    assert!(fewer(ProjectedPolygon::new(&[
        a,
        a.scale(&2.0),
        a.scale(&0.3)
    ])));
    assert!(fewer(ProjectedPolygon::new(&[a, a, b, b])));
    assert!(fewer(ProjectedPolygon::new(&[a, b, b, a])));
    let o = Vec3::new(0.0, 0.0, 0.0);
    let n = Vec3::new(0.0, 0.0, 1.0);
    assert!(fewer(ProjectedPolygon::from_points(&[a, a, b, b], &o, &n)));
    // f32: the same decision.
    let (a32, b32): (Vec3<f32>, Vec3<f32>) = (a.convert(), b.convert());
    assert!(matches!(
        ProjectedPolygon::new(&[a32, b32, b32, a32]),
        Err(WarpError::Degenerate { .. })
    ));
    // A repeated vertex next to its antipode: the edge is undefined.
    assert!(matches!(
        ProjectedPolygon::new(&[a, a, a.neg(), b]),
        Err(WarpError::Degenerate { what }) if what.contains("antipodal")
    ));
}

#[test]
fn nearly_coincident_distinct_directions() {
    let [_, b, c] = tri();
    // fl(s a) for an `a` whose multiple by s is not exact: a direction
    // distinct from a's (exactly), ~10⁻¹⁷ rad away. Where the unit vectors
    // do not resolve the two (their cross product rounds to zero: the first
    // two) the second is dropped; where they do (the third: unit vectors one
    // ulp apart), the quadrilateral keeps an edge of ~10⁻¹⁷ rad. Either way
    // it is accepted, passes the contract, and is the triangle to rounding.
    for (a, s) in [
        ([-0.2239, 0.2088, 1.0], 3.0),
        ([-0.3, 0.2327, 1.0], 0.1),
        ([-0.3, 0.2, 1.0], 3.0),
    ] {
        let a = v(a);
        let close = a.scale(&s);
        assert!(!exactly_parallel(&a, &close), "{a:?} {s}");
        let name = format!("{a:?}, fl({s} a)");
        let q =
            ProjectedPolygon::new(&[a, close, b, c]).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let t = ProjectedPolygon::new(&[a, b, c]).unwrap();
        same_polygon(&name, &q, &t, 1e-15);
        // In f32 the rounded values are ~10⁻⁸ rad apart, resolved: a
        // quadrilateral with a short edge.
        same_polygon(
            &name,
            &q.at::<f32>().unwrap(),
            &t.at::<f32>().unwrap(),
            1e-6,
        );
    }
    // 10⁻⁹ rad apart: resolved, a quadrilateral with a short edge, which
    // passes the contract and differs from the triangle by ~10⁻⁹.
    let [a, b, c] = tri();
    let t = ProjectedPolygon::new(&tri()).unwrap();
    let nudged = a.add(&Vec3::new(1e-9, -1e-9, 0.0));
    let q = ProjectedPolygon::new(&[a, nudged, b, c]).unwrap();
    finite_on_shape("1e-9", &q);
    let rel = (q.measure() - t.measure()).abs() / t.measure();
    assert!(rel < 1e-8 && rel > 0.0, "{rel:e}");
    finite_on_shape("1e-9 f32", &q.at::<f32>().unwrap());
}
