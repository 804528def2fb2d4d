//! The map at an extremal vertex (where a lune's interval closes) when one
//! of the two edges meeting there runs nearly along the meridian (small
//! |n_z|): that edge places its points with a relative error ~u/|n_z| in
//! r², which at the vertex lies off the polygon. Two polygons found by
//! `polygon_fuzz_large` with other seeds, each sampled on the meridian of
//! the vertex: a planar quad seen from the origin (seed 49; edge with
//! n_z = −1.7·10⁻⁶, the sample at u = 1 used to be 1.8·10⁻¹¹ off) and a
//! nearly coincident hexagon (seed 12, 1.7·10⁻¹² off at u = 0).

use super::*;
use crate::real::Mpfr256;

/// Samples at `u` (the vertex's meridian) are on the polygon in f64 and at
/// 256 bits and accepted by the inverse ([`assert_on_polygon`]).
fn vertex_samples_on_polygon(w: &ProjectedPolygon<f64>, exact: &ProjectedPolygon<Mpfr256>, u: f64) {
    for v in [0.0, 0.25, 0.5, 1.0] {
        assert_on_polygon(w, exact, &w.map(&u, &v), &format!("u {u}, v {v}"));
    }
}

#[test]
fn planar_quad_with_an_edge_along_a_meridian() {
    let pts: Vec<Vec3<f64>> = [
        [60559881164582.836, -54312975237491.42, 80855171537955.14],
        [81094034798689.73, -54312975237491.42, 80855171537955.14],
        [81094034798689.73, -41992483057027.28, 80855171537955.14],
        [60559881164582.836, -33778821603384.527, 80855171537955.14],
    ]
    .map(Vec3::from)
    .to_vec();
    let (o, n) = (
        Vec3::zero(),
        Vec3::from([-0.16881542697479143, -0.05064462809243743, 1.0]),
    );
    let w = ProjectedPolygon::from_points(&pts, &o, &n).unwrap();
    let wide: Vec<Vec3<Mpfr256>> = pts.iter().map(|p| p.convert()).collect();
    let exact = ProjectedPolygon::from_points(&wide, &o.convert(), &n.convert()).unwrap();
    // The case is what it says: an edge with |n_z| below 10⁻⁵.
    assert!(w.parts().edges.iter().any(|e| e.abs_nz < 1e-5));
    vertex_samples_on_polygon(&w, &exact, 1.0);
}

#[test]
fn nearly_coincident_hexagon_at_its_first_meridian() {
    let v: Vec<Vec3<f64>> = [
        [
            -0.8989547705151661,
            -0.25588855271284144,
            0.35552970221706154,
        ],
        [-0.8989547705523062, -0.25588855220532924, 0.355529702486615],
        [
            -0.9000085067134385,
            -0.2521537718784948,
            0.35553222522142036,
        ],
        [
            -0.9007732432874136,
            -0.25236812046717577,
            0.35343725885839933,
        ],
        [-0.900628743475265, -0.2543426851786896, 0.3523885141747094],
        [-0.8997195070891413, -0.2561029013015224, 0.3534347358540405],
    ]
    .map(Vec3::from)
    .to_vec();
    let w = ProjectedPolygon::new(&v).unwrap();
    let exact = ProjectedPolygon::new(&v.iter().map(|p| p.convert()).collect::<Vec<_>>()).unwrap();
    vertex_samples_on_polygon(&w, &exact, 0.0);
}
