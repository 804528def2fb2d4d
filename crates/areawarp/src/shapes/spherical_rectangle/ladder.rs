//! The ladder of hard rectangles of issue 4, and a few ordinary ones.

use crate::vector::Vec3;

/// A point of the plane of the generic frame: `C + x·A + y·B + z·N` with
/// the orthonormal `A = (2, −1, 2)/3`, `B = (2, 2, −1)/3`, `N = A × B =
/// (−1, 2, 2)/3` (so no coordinate of the ladder is accidentally exact) and
/// the origin `C = (0.37, −1.21, 0.73)`.
fn world(x: f64, y: f64, z: f64) -> Vec3<f64> {
    let [a, b, n] = axes();
    Vec3::new(0.37, -1.21, 0.73)
        .add(&a.scale(&x))
        .add(&b.scale(&y))
        .add(&n.scale(&z))
}

/// The axes `A`, `B`, `N` of [`world`].
fn axes() -> [Vec3<f64>; 3] {
    [
        Vec3::new(2.0 / 3.0, -1.0 / 3.0, 2.0 / 3.0),
        Vec3::new(2.0 / 3.0, 2.0 / 3.0, -1.0 / 3.0),
        Vec3::new(-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0),
    ]
}

/// The rectangle `[0, lx] × [0, ly]` of the generic frame's plane and the
/// observer at height `h` above the in-plane point `(fx, fy)`, as
/// `[s, e_x, e_y, o]`.
fn placed(lx: f64, ly: f64, fx: f64, fy: f64, h: f64) -> [Vec3<f64>; 4] {
    let [a, b, _] = axes();
    [
        world(0.0, 0.0, 0.0),
        a.scale(&lx),
        b.scale(&ly),
        world(fx, fy, h),
    ]
}

/// The ladder of hard rectangles of issue 4, as `(label, [s, e_x, e_y, o])`
/// (corner, edges, observer), all but one in a generic orientation (edges
/// along `(2, −1, 2)/3` and `(2, 2, −1)/3`, corner `(0.37, −1.21, 0.73)`):
///
/// - `far 1e-8 sr oblique`: a 1 × 0.75 rectangle seen from about 7071 units
///   away at 45° (Ω ≈ 1.06e-8 sr); the corner has small coordinates and
///   the observer large ones, so the map must be accurate relative to the
///   rectangle, not to the distance;
/// - `far 1e-8 sr head-on`: the same rectangle 8660 units above its centre
///   (Ω ≈ 1.0e-8 sr);
/// - `above interior 1e-6`: the observer 1e-6 above the interior point
///   (0.3, 0.45) of a 1 × 0.75 rectangle (Ω ≈ 2π − 4e-6);
/// - `above corner 1e-3`: 1e-3 above the corner s (Ω ≈ π/2);
/// - `above corner 1e-3 axis-aligned`: the same in world axes, with the
///   observer's foot exactly on the corner (x₀ = y₀ = 0);
/// - `grazing 1e-9 side`, `1e-7`, `1e-5`: the observer that far above the
///   plane at (−0.4, 0.3), outside the rectangle beside the edge x = 0;
/// - `grazing 1e-9 diagonal`, `1e-7`, `1e-5`: at (−0.4, −0.3), outside
///   beside the corner;
/// - `elongated 1e3 x 1e-3`: a 1000 × 0.001 strip, observer 0.3 above
///   (400.3, 0.0021) (just beside the strip);
/// - `elongated 1e-3 x 1e3`: the same strip with the edges swapped.
///
/// # Example
/// ```
/// use areawarp::shapes::{hard_rectangles, SphericalRectangle};
/// for (name, [s, ex, ey, o]) in hard_rectangles() {
///     let r = SphericalRectangle::<f64>::new(s, ex, ey, o).unwrap();
///     assert!(r.solid_angle() > 0.0, "{name}");
/// }
/// ```
pub fn hard_rectangles() -> Vec<(String, [Vec3<f64>; 4])> {
    let mut out = vec![
        (
            "far 1e-8 sr oblique".to_string(),
            placed(1.0, 0.75, 4000.0, -3000.0, 5000.0),
        ),
        (
            "far 1e-8 sr head-on".to_string(),
            placed(1.0, 0.75, 0.5, 0.375, 8660.0),
        ),
        (
            "above interior 1e-6".to_string(),
            placed(1.0, 0.75, 0.3, 0.45, 1e-6),
        ),
        (
            "above corner 1e-3".to_string(),
            placed(1.0, 0.75, 0.0, 0.0, 1e-3),
        ),
        (
            "above corner 1e-3 axis-aligned".to_string(),
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 0.75, 0.0),
                Vec3::new(0.0, 0.0, 1e-3),
            ],
        ),
    ];
    for (kind, fy) in [("side", 0.3), ("diagonal", -0.3)] {
        for h in [1e-9, 1e-7, 1e-5] {
            out.push((
                format!("grazing {h:e} {kind}"),
                placed(1.0, 0.75, -0.4, fy, h),
            ));
        }
    }
    out.push((
        "elongated 1e3 x 1e-3".to_string(),
        placed(1e3, 1e-3, 400.3, 0.0021, 0.3),
    ));
    out.push((
        "elongated 1e-3 x 1e3".to_string(),
        placed(1e-3, 1e3, 0.0021, 400.3, 0.3),
    ));
    out
}

/// A few ordinary rectangles (solid angles 0.05 … 5 sr), as
/// `(label, [s, e_x, e_y, o])`: for the χ² tests and the speed benchmark.
///
/// - `unit square head-on`: world axes, 1 × 1 centred 1 below the observer;
/// - `oblique`: 1.3 × 0.7, observer 0.8 above (−0.6, 1.1), generic frame;
/// - `near inside`: 1 × 1, observer 0.25 above (0.2, 0.1), generic frame;
/// - `small far`: 0.3 × 0.2, observer 1.5 above (1.1, −0.4), generic frame.
pub fn ordinary_rectangles() -> Vec<(String, [Vec3<f64>; 4])> {
    vec![
        (
            "unit square head-on".to_string(),
            [
                Vec3::new(-0.5, -0.5, -1.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, 0.0, 0.0),
            ],
        ),
        ("oblique".to_string(), placed(1.3, 0.7, -0.6, 1.1, 0.8)),
        ("near inside".to_string(), placed(1.0, 1.0, 0.2, 0.1, 0.25)),
        ("small far".to_string(), placed(0.3, 0.2, 1.1, -0.4, 1.5)),
    ]
}
