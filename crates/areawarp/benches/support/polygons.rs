//! The polygons of `projected_polygon.rs` and `projected_polygon_min.rs`.

use areawarp::{Real, Vec3};

/// The benchmark polygons (planar lights seen from the origin, receiver
/// normal +z), as in the unit tests.
pub fn polygons() -> Vec<(&'static str, Vec<[f64; 3]>)> {
    let pentagon = (0..5)
        .map(|i| {
            let a = 2.0 * std::f64::consts::PI * i as f64 / 5.0 + 0.3;
            [0.1 + 0.7 * a.cos(), -0.05 + 0.7 * a.sin(), 1.0]
        })
        .collect();
    vec![
        (
            "convex",
            vec![
                [-0.3, 0.2, 1.0],
                [0.6, 0.1, 1.0],
                [0.7, 0.9, 1.0],
                [-0.2, 0.8, 1.0],
            ],
        ),
        (
            "comb",
            vec![
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
            ],
        ),
        ("around-pole", pentagon),
        (
            "horizon",
            vec![
                [1.0, -0.5, 0.6],
                [1.0, 0.5, 0.6],
                [1.0, 0.5, -0.4],
                [1.0, -0.5, -0.4],
            ],
        ),
    ]
}

pub fn vertices<T: Real>(v: &[[f64; 3]]) -> Vec<Vec3<T>> {
    v.iter().map(|p| Vec3::from_f64(p[0], p[1], p[2])).collect()
}
