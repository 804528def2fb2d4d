//! The ladder of hard spherical triangles of issue 4, and a few ordinary ones.

use crate::vector::Vec3;

/// An orthonormal frame `(n, t₁, t₂)` in a generic orientation (no vertex
/// coordinate of the ladder is zero or exactly representable by accident).
fn frame() -> (Vec3<f64>, Vec3<f64>, Vec3<f64>) {
    // 0.36² + 0.48² + 0.8² = 1.
    let n = Vec3::new(0.36, -0.48, 0.8);
    let t1 = n
        .cross(&Vec3::new(0.0, 0.0, 1.0))
        .normalized()
        .unwrap_or(Vec3::new(1.0, 0.0, 0.0));
    let t2 = n.cross(&t1);
    (n, t1, t2)
}

/// The direction at angular distance `theta` from `n`, in the direction of
/// azimuth `phi` in the tangent plane (t₁, t₂).
fn at(theta: f64, phi: f64) -> Vec3<f64> {
    let (n, t1, t2) = frame();
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    n.scale(&ct)
        .add(&t1.scale(&(st * cp)).add(&t2.scale(&(st * sp))))
}

/// The three cyclic rotations of the vertex roles: `(x, y, z)` as
/// `(A, B, C)`, `(z, x, y)` and `(y, z, x)`, so that `x` is at A, B, C in turn.
fn rotations(
    name: &str,
    x: Vec3<f64>,
    y: Vec3<f64>,
    z: Vec3<f64>,
) -> Vec<(String, [Vec3<f64>; 3])> {
    vec![
        (format!("{name}@A"), [x, y, z]),
        (format!("{name}@B"), [z, x, y]),
        (format!("{name}@C"), [y, z, x]),
    ]
}

/// A triangle of about `omega` steradians (small: nearly equilateral, a
/// little irregular), centred on the frame's axis.
fn small(omega: f64) -> [Vec3<f64>; 3] {
    // Planar equilateral: Ω ≈ (√3/4)·side², circumradius side/√3.
    let side = (4.0 * omega / 3f64.sqrt()).sqrt();
    let r = side / 3f64.sqrt();
    [at(r, 0.1), at(r, 2.2), at(r * 0.9, 4.1)]
}

/// Three directions `δ` above a great circle, 120° apart, with `δ` chosen so
/// that the triangle containing the pole has Ω = 2π − ε.
fn near_hemisphere(eps: f64) -> [Vec3<f64>; 3] {
    // det = (3√3/2)·x(1 − x²), −(1 + A·B + B·C + C·A) = 1/2 − (9/2)x² with
    // x = sin δ, and 2π − Ω = 2·atan(det / −den): solve for x by Newton.
    let k = (eps / 2.0).tan();
    let s3 = 3f64.sqrt();
    let mut x = k / (3.0 * s3);
    for _ in 0..8 {
        let f = 1.5 * s3 * x * (1.0 - x * x) - k * (0.5 - 4.5 * x * x);
        let df = 1.5 * s3 * (1.0 - 3.0 * x * x) + 9.0 * k * x;
        x -= f / df;
    }
    let theta = std::f64::consts::FRAC_PI_2 - x.asin();
    let third = 2.0 * std::f64::consts::PI / 3.0;
    [
        at(theta, 0.25),
        at(theta, 0.25 + third),
        at(theta, 0.25 + 2.0 * third),
    ]
}

/// The ladder of hard spherical triangles of issue 4, as vertex directions
/// (not normalized exactly: the constructor normalizes), with a label.
///
/// All are placed in a generic orientation (axis `(0.36, −0.48, 0.8)`):
/// - `area 1e-2`, `area 1e-6`, `area 1e-10`, `area 1e-12`: nearly
///   equilateral triangles of about that many steradians;
/// - `sliver@V`: arcs of 1 rad and 0.8 rad from V meeting at an angle of
///   1e-6 rad at V, for V = A, B, C;
/// - `needle@V`: arcs of 1e-3 and 0.9e-3 rad from V meeting at 1e-6 rad
///   (a needle 1e-3 long and 1e-9 wide, about 5e-13 sr), for V = A, B, C;
/// - `obtuse@V`: the other two vertices 90° apart, V 1e-6 rad off the
///   midpoint of their arc (the angle at V is π − 4e-6 rad), for V = A, B, C;
/// - `hemi 2pi-ε`: three directions 120° apart just above a great circle,
///   Ω = 2π − ε for ε = 1e-2, 1e-4, 1e-6, 1e-7.
///
/// # Example
/// ```
/// use areawarp::shapes::{hard_triangles, SphericalTriangle};
/// for (name, [a, b, c]) in hard_triangles() {
///     let t = SphericalTriangle::<f64>::new(a, b, c).unwrap();
///     assert!(t.solid_angle() > 0.0, "{name}");
/// }
/// ```
pub fn hard_triangles() -> Vec<(String, [Vec3<f64>; 3])> {
    let mut out = Vec::new();
    for (name, omega) in [
        ("area 1e-2", 1e-2),
        ("area 1e-6", 1e-6),
        ("area 1e-10", 1e-10),
        ("area 1e-12", 1e-12),
    ] {
        out.push((name.to_string(), small(omega)));
    }
    out.extend(rotations(
        "sliver",
        at(0.0, 0.0),
        at(1.0, 0.3),
        at(0.8, 0.3 + 1e-6),
    ));
    out.extend(rotations(
        "needle",
        at(0.0, 0.0),
        at(1e-3, 0.7),
        at(0.9e-3, 0.7 + 1e-6),
    ));
    let half_pi = std::f64::consts::FRAC_PI_2;
    // Apex 1e-6 off the midpoint (the frame's axis) of a 90° arc.
    out.extend(rotations(
        "obtuse",
        at(1e-6, half_pi),
        at(half_pi / 2.0, 0.0),
        at(half_pi / 2.0, std::f64::consts::PI),
    ));
    for (name, eps) in [
        ("hemi 2pi-1e-2", 1e-2),
        ("hemi 2pi-1e-4", 1e-4),
        ("hemi 2pi-1e-6", 1e-6),
        ("hemi 2pi-1e-7", 1e-7),
    ] {
        out.push((name.to_string(), near_hemisphere(eps)));
    }
    out
}

/// A few ordinary triangles (0.05 to 3 sr, both orientations) for the χ²
/// tests and examples.
pub fn ordinary_triangles() -> Vec<(String, [Vec3<f64>; 3])> {
    vec![
        (
            "octant".to_string(),
            [
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
            ],
        ),
        (
            "generic".to_string(),
            [
                Vec3::new(1.0, 0.1, 0.0),
                Vec3::new(0.2, 1.0, 0.1),
                Vec3::new(0.0, 0.3, 1.0),
            ],
        ),
        (
            "clockwise".to_string(),
            [at(0.3, 0.0), at(0.25, -2.0), at(0.35, -4.0)],
        ),
        (
            "large obtuse".to_string(),
            [at(1.2, 0.0), at(1.3, 2.5), at(1.1, 3.9)],
        ),
    ]
}
