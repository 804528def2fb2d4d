//! The map at a vertex on a lune's side meridian when an edge ending
//! there runs nearly along the meridian (small |n_z|): the edge's g summed
//! from its normal places its points with a relative error ~u/|n_z| in r²,
//! which at the vertex lies off the polygon (the map's intervals take g
//! from the vertex there: `EdgeSide::gv`, `build::vertex_g`). Polygons
//! found by `polygon_fuzz_large` with other seeds, each sampled on the
//! meridian of the vertex: a planar quad seen from the origin (seed 49;
//! edge with n_z = −1.7·10⁻⁶, the sample at u = 1 used to be 1.8·10⁻¹¹
//! off) and a nearly coincident hexagon (seed 12, 1.7·10⁻¹² off at u = 0),
//! both at an extremal vertex (the interval closes there); two triangles
//! whose interval at the vertex runs from the pole (seeds 144 and 304,
//! 1.9·10⁻¹³ and 2.1·10⁻¹⁴ off before g was taken from the vertex); a
//! pentagon next to the horizon (seed 1), where the edges' z² is what is
//! ill-conditioned; and one whose vertex lies beside its merged meridian,
//! so that g is *not* taken from it there (seed 135).

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
    let (w, exact) = f64_and_exact(&v);
    vertex_samples_on_polygon(&w, &exact, 0.0);
}

/// Random triangles with two vertices half a turn apart in azimuth, so that
/// their edge passes next to the pole: the interval at the vertex's
/// meridian runs from the pole to the vertex, and does not close there
/// (fuzz seeds 144 and 304: 1.9·10⁻¹³ off at u = 0 and 2.1·10⁻¹⁴ off at
/// u = 1 before g was taken from the vertex).
#[test]
fn triangles_with_an_edge_next_to_the_pole() {
    let seed_144 = [
        [
            -0.35271771026527954,
            -0.4054709408728772,
            0.8433169824999862,
        ],
        [0.5198492388886755, 0.5967307130616059, 0.6112848966855406],
        [-0.7346901829380994, 0.6675894929313941, 0.12064246359382036],
    ];
    let seed_304 = [
        [0.315077605688812, 0.6241919735370158, 0.7149199133926617],
        [-0.2792682236091571, -0.5412700039001451, 0.793117924498068],
        [0.8796775630653224, -0.4358372835855012, 0.1902977857891866],
    ];
    for (vertices, us) in [
        (seed_144, [0.0, 1e-7]),
        (seed_304, [1.0, 1.0 - f64::EPSILON]),
    ] {
        let v: Vec<Vec3<f64>> = vertices.map(Vec3::from).to_vec();
        let (w, exact) = f64_and_exact(&v);
        for u in us {
            vertex_samples_on_polygon(&w, &exact, u);
        }
    }
}

/// A small pentagon across the horizon (fuzz seed 1): at its last
/// meridian two edges meet at a vertex 2.2·10⁻⁵ above the horizon, where
/// z² carries the position and the edge's summed g has a relative error
/// ~u/|g| (|g| ≈ 7·10⁻⁸); g from the vertex only where r² is
/// ill-conditioned (an edge nearly along a meridian) left the sample at
/// u = 1, v = 1 388 u off.
#[test]
fn pentagon_next_to_the_horizon() {
    let v: Vec<Vec3<f64>> = [
        [-0.8287354314415155, 0.5596405848164114, 2.23559844345062e-5],
        [
            -0.8286808877065202,
            0.5597213444166619,
            5.4353824819976554e-5,
        ],
        [
            -0.8286469979310894,
            0.5597715176845418,
            -2.8441828210227925e-5,
        ],
        [
            -0.8286805966329976,
            0.5597217668691679,
            -0.00011161019628910785,
        ],
        [
            -0.8287352515481854,
            0.5596408459064188,
            -8.021542152051297e-5,
        ],
    ]
    .map(Vec3::from)
    .to_vec();
    let (w, exact) = f64_and_exact(&v);
    vertex_samples_on_polygon(&w, &exact, 1.0);
}

/// Two vertices 4·10⁻¹⁵ apart, whose azimuths are one merged meridian at
/// the lesser azimuth: the other vertex lies beside that meridian, so the
/// edge ending there keeps its own g (fuzz seed 135: g taken from that
/// vertex put the sample at u = 1, v = ½ 103 u off at 256 bits). Judged
/// at 256 bits only: f64's own `outside_by` reads up to 10 u there (its
/// distance to an arc between the two nearly coincident vertices).
#[test]
fn vertex_beside_its_merged_meridian() {
    let v: Vec<Vec3<f64>> = [
        [-0.3630152917421865, -0.11357786852791277, 0.924835101919251],
        [
            -0.36301529174218217,
            -0.11357786852791342,
            0.9248351019192518,
        ],
        [0.22959571326464404, 0.11630975064840314, 0.9663114665337494],
        [0.10476864491705701, 0.45267253753669845, 0.8855004826663448],
        [-0.2539503917601519, 0.5059101213926881, 0.8243568084253935],
        [
            -0.48784236008977366,
            0.22278491836038233,
            0.8440241180518465,
        ],
    ]
    .map(Vec3::from)
    .to_vec();
    let (w, exact) = f64_and_exact(&v);
    let tol = 4.0 * f64::EPSILON / 2.0;
    for v in [0.0, 0.25, 0.5, 1.0] {
        let p = w.map(&1.0, &v);
        let by_exact = exact.outside_by(&p.convert()).to_f64();
        assert!(
            by_exact <= tol,
            "v {v}: {p:?} is {by_exact:e} off at 256 bits"
        );
        assert!(w.inverse(&p).is_ok(), "v {v}: refused");
    }
}
