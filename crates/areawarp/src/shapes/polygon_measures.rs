//! Analytic measures of spherical polygons, used as references by the tests
//! of [`ProjectedPolygon`](super::ProjectedPolygon) and useful on their own:
//! the solid angle (Gauss–Bonnet, Van Oosterom–Strackee) and the projected
//! solid angle (Lambert's formula: π × the point-to-polygon form factor).
//!
//! A spherical polygon is given by its vertex *directions* `v_0 … v_{n−1}`
//! (any positive scale; each is normalized), joined by minor great arcs.
//! Orientation convention: the polygon is *positively oriented* when its
//! interior lies to the left of each edge seen from outside the sphere, i.e.
//! `(v_i × v_{i+1}) · p > 0` for interior points `p` next to edge `i`
//! (counter-clockwise seen from outside, clockwise seen from the origin).
//!
//! None of these functions allocate or fail: degenerate input (zero or
//! non-finite vertices, fewer than three vertices) gives a NaN or zero
//! result, as documented on each function.

use crate::real::Real;
use crate::vector::Vec3;

/// The unit vector of `v`, or NaN coordinates for zero / non-finite input.
fn unit<T: Real>(v: &Vec3<T>) -> Vec3<T> {
    v.normalized().unwrap_or_else(|| {
        let nan = T::zero() / T::zero();
        Vec3::new(nan.clone(), nan.clone(), nan)
    })
}

/// The angle between two directions, `atan2(|a × b|, a · b)` (accurate for
/// tiny and for nearly antipodal pairs, unlike `acos`), in `[0, π]`.
///
/// # Example
/// ```
/// use areawarp::shapes::polygon_measures::arc_angle;
/// use areawarp::Vec3;
/// let a = arc_angle(&Vec3::new(1.0, 0.0, 0.0), &Vec3::new(0.0, 2.0, 0.0));
/// assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// ```
pub fn arc_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    a.cross(b).norm().atan2(&a.dot(b))
}

/// The signed solid angle of the spherical triangle `(a, b, c)` (minor arcs)
/// by Van Oosterom and Strackee's formula
///
/// tan(Ω/2) = det(a, b, c) / (1 + a·b + b·c + c·a)   (unit a, b, c),
///
/// in `(−2π, 2π)`: positive for a positively oriented triangle.
///
/// # Example
/// ```
/// use areawarp::shapes::polygon_measures::triangle_solid_angle;
/// use areawarp::Vec3;
/// // The octant: a right spherical triangle of area 4π/8.
/// let o = triangle_solid_angle(
///     &Vec3::new(1.0, 0.0, 0.0),
///     &Vec3::new(0.0, 1.0, 0.0),
///     &Vec3::new(0.0, 0.0, 1.0),
/// );
/// assert!((o - std::f64::consts::PI / 2.0).abs() < 1e-15);
/// ```
pub fn triangle_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    unit_triangle_solid_angle(&unit(a), &unit(b), &unit(c))
}

/// [`triangle_solid_angle`] of unit vectors (not normalized again).
fn unit_triangle_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    // det(a, b, c) = a · ((b − a) × (c − a)): the differences keep the
    // relative accuracy of tiny triangles, where a · (b × c) would lose it.
    let det = a.dot(&b.sub(a).cross(&c.sub(a)));
    let den = T::one() + &a.dot(b) + &b.dot(c) + &c.dot(a);
    det.atan2(&den) * &T::from_i64(2)
}

/// The solid angle of the region to the *left* of the closed polygon
/// `v_0 → v_1 → … → v_0` (see the module docs), in `(0, 4π)` for a simple
/// polygon; the other side of the boundary has `4π − Ω`.
///
/// Computed as the fan Σ_i Ω(v_a, v_i, v_{i+1}) of signed triangles
/// ([`triangle_solid_angle`], accurate also for tiny polygons) from the
/// vertex v_a farthest from all antipodes of vertices, which is the answer
/// modulo 4π; the multiple of 4π is taken from the Gauss–Bonnet
/// theorem, Ω = 2π − Σ τ_i with τ_i the signed turning angle at vertex i
/// (accurate to far better than 4π, but not to the relative accuracy of a
/// small Ω, which is 2π minus a sum of angles). A vertex where the boundary
/// folds straight back (τ = ±π) makes the result ambiguous by 2π.
/// NaN for fewer than three or for zero / non-finite vertices.
///
/// # Example
/// ```
/// use areawarp::shapes::polygon_measures::oriented_solid_angle;
/// use areawarp::Vec3;
/// let octant = [
///     Vec3::new(1.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
///     Vec3::new(0.0, 0.0, 1.0),
/// ];
/// let pi = std::f64::consts::PI;
/// assert!((oriented_solid_angle(&octant) - pi / 2.0).abs() < 1e-14);
/// let mut reversed = octant.clone();
/// reversed.reverse();
/// assert!((oriented_solid_angle(&reversed) - 3.5 * pi).abs() < 1e-14);
/// ```
pub fn oriented_solid_angle<T: Real>(vertices: &[Vec3<T>]) -> T {
    let n = vertices.len();
    if n < 3 {
        return T::zero() / T::zero();
    }
    let v: Vec<Vec3<T>> = vertices.iter().map(unit).collect();
    oriented_solid_angle_of_units(&v)
}

/// [`oriented_solid_angle`] of unit vectors (not normalized again).
///
/// The Gauss–Bonnet estimate only picks the multiple of 4π, so it may be
/// off by far more than rounding: its turning angles are taken in `f32`
/// by a polynomial ([`rough_atan2`], error ≤ 2·10⁻⁵ each, against a margin
/// of 2π for the sum of n of them), which keeps the cost at what the fan's
/// accurate `atan2`s cost. The fan skips the two
/// triangles that contain the apex twice (zero solid angle).
pub(crate) fn oriented_solid_angle_of_units<T: Real>(v: &[Vec3<T>]) -> T {
    let n = v.len();
    if n < 3 {
        return T::zero() / T::zero();
    }
    let mut turning = 0.0f64;
    for i in 0..n {
        let (a, b, c) = (&v[(i + n - 1) % n], &v[i], &v[(i + 1) % n]);
        let (sin_part, cos_part) = turning_parts(a, b, c);
        turning += rough_angle(&sin_part, &cos_part);
    }
    oriented_solid_angle_with_turning(v, turning)
}

/// [`oriented_solid_angle_of_units`] given the sum of the turning angles
/// ([`rough_angle`] of each vertex's [`turning_parts`]), for a caller that
/// computed the parts already.
pub(crate) fn oriented_solid_angle_with_turning<T: Real>(v: &[Vec3<T>], turning: f64) -> T {
    let n = v.len();
    if n < 3 {
        return T::zero() / T::zero();
    }
    let gauss_bonnet = 2.0 * core::f64::consts::PI - turning;
    // The fan's apex: the vertex farthest from every vertex's antipode (a
    // diagonal to an antipodal vertex would be undefined).
    let mut apex = 0;
    let mut best: Option<T> = None;
    for (j, a) in v.iter().enumerate() {
        let worst = v
            .iter()
            .map(|b| T::one() + &a.dot(b))
            .fold(T::max_value(), |m, x| m.min(&x));
        if best.as_ref().is_none_or(|b| worst > *b) {
            best = Some(worst);
            apex = j;
        }
    }
    let mut fan = T::zero();
    for i in 0..n {
        let next = (i + 1) % n;
        if i != apex && next != apex {
            fan += &unit_triangle_solid_angle(&v[apex], &v[i], &v[next]);
        }
    }
    let four_pi = T::pi() * &T::from_i64(4);
    let k = ((gauss_bonnet - fan.to_f64()) / (4.0 * core::f64::consts::PI) + 0.5).floor();
    if k.is_nan() {
        return T::zero() / T::zero();
    }
    fan + &(T::from_i64(k as i64) * &four_pi)
}

/// `atan2(sin_part, cos_part)` to within 2·10⁻⁵ radians, in `f64` after
/// scaling the pair by its larger magnitude (no underflow for wide types).
/// The sign of a zero or tiny sine is kept, so ±π stay apart. NaN for NaN
/// input, 0 for (0, 0).
pub(crate) fn rough_angle<T: Real>(sin_part: &T, cos_part: &T) -> f64 {
    if sin_part.is_nan() || cos_part.is_nan() {
        return f64::NAN;
    }
    let (y, x) = (sin_part.to_f64(), cos_part.to_f64());
    let big = y.abs().max(x.abs());
    if big > f64::MIN_POSITIVE && big < f64::MAX {
        // Normal in f64 (always for f32/f64): the angle is scale-free.
        return rough_atan2(y, x);
    }
    let m = sin_part.abs().max(&cos_part.abs());
    if !(m > T::zero()) {
        return 0.0;
    }
    let y = (sin_part.clone() / &m).to_f64();
    let x = (cos_part.clone() / &m).to_f64();
    rough_atan2(y, x)
}

/// `atan2(y, x)` by octant reduction and the odd polynomial of Abramowitz
/// & Stegun 4.4.49 for `atan t`, `t ∈ [0, 1]` (absolute error ≤ 10⁻⁵),
/// without a library call: the Gauss–Bonnet sum needs the angles to far
/// better than 2π in total, not to the last digit.
fn rough_atan2(y: f64, x: f64) -> f64 {
    use core::f64::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if !(hi > 0.0) {
        return 0.0;
    }
    let t = lo / hi;
    let t2 = t * t;
    let mut r = t
        * (0.999_866
            + t2 * (-0.330_299_5 + t2 * (0.180_141 + t2 * (-0.085_133 + t2 * 0.020_835_1))));
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    if y.is_sign_negative() { -r } else { r }
}

/// `|n₁||n₂|` times the sine and cosine of the signed turning angle at `b`
/// of the path `a → b → c` (unit vectors; positive for a left turn seen
/// from outside the sphere), with n₁ = a × b, n₂ = b × c computed from
/// differences (accurate for short edges).
pub(crate) fn turning_parts<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> (T, T) {
    turning_from_normals(&edge_cross(a, b), &edge_cross(b, c), b)
}

/// `a × (b − a)`, the normal of the edge `a → b` that [`turning_parts`]
/// uses (from the difference: accurate for short edges).
pub(crate) fn edge_cross<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    a.cross(&b.sub(a))
}

/// [`turning_parts`] at `b` from the normals `n1`, `n2` ([`edge_cross`])
/// of the edges into and out of `b`, for a caller that walks the boundary
/// and computes each edge's normal once.
pub(crate) fn turning_from_normals<T: Real>(n1: &Vec3<T>, n2: &Vec3<T>, b: &Vec3<T>) -> (T, T) {
    (n1.cross(n2).dot(b), n1.dot(n2))
}

/// The solid angle of a simple spherical polygon, whatever its orientation:
/// the smaller of the two regions its boundary separates,
/// `min(Ω, 4π − Ω)` with Ω from [`oriented_solid_angle`].
///
/// # Example
/// ```
/// use areawarp::shapes::polygon_measures::solid_angle;
/// use areawarp::Vec3;
/// // A small square of side 0.02 at distance 1: about 4·10⁻⁴ sr.
/// let sq: [Vec3<f64>; 4] = [
///     Vec3::new(-0.01, -0.01, 1.0),
///     Vec3::new(-0.01, 0.01, 1.0),
///     Vec3::new(0.01, 0.01, 1.0),
///     Vec3::new(0.01, -0.01, 1.0),
/// ];
/// assert!((solid_angle(&sq) - 4e-4).abs() < 1e-7);
/// ```
pub fn solid_angle<T: Real>(vertices: &[Vec3<T>]) -> T {
    let o = oriented_solid_angle(vertices);
    let four_pi = T::pi() * &T::from_i64(4);
    o.clone().min(&(four_pi - &o))
}

/// Lambert's formula for the projected solid angle of a polygon lying in
/// the closed hemisphere `{p · N ≥ 0}` (N = `normal`, normalized here):
///
/// Π = ½ Σ_i θ_i (n̂_i · N),  θ_i = ∠(v_i, v_{i+1}),  n̂_i = (v_i × v_{i+1}) / |v_i × v_{i+1}|,
///
/// i.e. π times the form factor from a differential area with normal N at
/// the origin to the polygon (the irradiance of a unit-radiance polygonal
/// luminaire). Signed: positive for a positively oriented polygon (module
/// docs), negative for the reverse order; take the absolute value if the
/// orientation is unknown. The formula counts parts of the polygon below
/// the horizon `p · N < 0` *negatively*: clip first (as
/// [`ProjectedPolygon`](super::ProjectedPolygon) does) for polygons that
/// cross it. Edges with coincident ends contribute 0; NaN for a zero normal.
///
/// # Example
/// ```
/// use areawarp::shapes::polygon_measures::projected_solid_angle;
/// use areawarp::Vec3;
/// // The octant x, y, z ≥ 0 seen with normal +z: a quarter of the unit
/// // disk, π/4.
/// let octant = [
///     Vec3::new(1.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
///     Vec3::new(0.0, 0.0, 1.0),
/// ];
/// let p = projected_solid_angle(&octant, &Vec3::new(0.0, 0.0, 1.0));
/// assert!((p - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
/// ```
pub fn projected_solid_angle<T: Real>(vertices: &[Vec3<T>], normal: &Vec3<T>) -> T {
    let n_hat = unit(normal);
    let n = vertices.len();
    let mut sum = T::zero();
    for i in 0..n {
        let (a, b) = (unit(&vertices[i]), unit(&vertices[(i + 1) % n]));
        let c = a.cross(&b);
        let s = c.norm();
        if s > T::zero() {
            sum += &(s.atan2(&a.dot(&b)) * &c.dot(&n_hat) / &s);
        }
    }
    sum / &T::from_i64(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rough_atan2_within_its_bound() {
        let mut worst = 0.0f64;
        for i in 0..=720 {
            let a = -std::f64::consts::PI + i as f64 * std::f64::consts::PI / 360.0;
            for r in [1e-300, 1.0, 1e300] {
                let (y, x) = (r * a.sin(), r * a.cos());
                worst = worst.max((rough_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst <= 2e-5, "{worst}");
        // ±π stay apart; the axes are exact enough.
        assert!(rough_atan2(-0.0, -1.0) < -3.0 && rough_atan2(0.0, -1.0) > 3.0);
        assert!(rough_atan2(-1e-300, -1.0) < -3.0);
        assert_eq!(rough_atan2(0.0, 0.0), 0.0);
        assert!(rough_angle(&f64::NAN, &1.0).is_nan());
        assert!((rough_angle(&-1e-310f64, &-1e-310) + 0.75 * std::f64::consts::PI).abs() < 2e-5);
    }
    use std::f64::consts::PI;

    fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
        Vec3::new(x, y, z)
    }

    /// A spherical cap polygon: n vertices at polar angle `theta` about +z,
    /// counter-clockwise seen from above (positively oriented).
    fn cap(n: usize, theta: f64) -> Vec<Vec3<f64>> {
        (0..n)
            .map(|i| {
                let p = 2.0 * PI * i as f64 / n as f64;
                v(theta.sin() * p.cos(), theta.sin() * p.sin(), theta.cos())
            })
            .collect()
    }

    #[test]
    fn polygon_measures_octant() {
        let o = [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)];
        assert!((oriented_solid_angle(&o) - PI / 2.0).abs() < 1e-14);
        assert!((solid_angle(&o) - PI / 2.0).abs() < 1e-14);
        assert!((triangle_solid_angle(&o[0], &o[1], &o[2]) - PI / 2.0).abs() < 1e-15);
        assert!((triangle_solid_angle(&o[0], &o[2], &o[1]) + PI / 2.0).abs() < 1e-15);
        // Seen with normal +x or +y as well: by symmetry π/4 each.
        for n in [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 3.0)] {
            assert!((projected_solid_angle(&o, &n) - PI / 4.0).abs() < 1e-15);
        }
        let r = [o[2], o[1], o[0]];
        assert!((projected_solid_angle(&r, &v(0.0, 0.0, 1.0)) + PI / 4.0).abs() < 1e-15);
    }

    /// Regular polygon inscribed in a cap, against the triangle fan and the
    /// closed forms of the polygon's area (n triangles from the pole).
    #[test]
    fn polygon_measures_regular_polygon_around_the_pole() {
        for n in [3usize, 5, 8] {
            for theta in [0.1, 0.7, 1.4] {
                let p = cap(n, theta);
                let pole = v(0.0, 0.0, 1.0);
                let fan: f64 = (0..n)
                    .map(|i| triangle_solid_angle(&pole, &p[i], &p[(i + 1) % n]))
                    .sum();
                let gb = oriented_solid_angle(&p);
                assert!((gb - fan).abs() < 1e-13, "{n} {theta}: {gb} {fan}");
                // Projected: the polygon projects onto a regular planar
                // n-gon? No: edges project to ellipse arcs. Compare with the
                // fan of polar triangles, each contributing ½ θ_e |n_z|.
                let lam = projected_solid_angle(&p, &pole);
                let mut want = 0.0;
                for i in 0..n {
                    let (a, b) = (&p[i], &p[(i + 1) % n]);
                    let c = a.cross(b);
                    want += 0.5 * arc_angle(a, b) * c.z / c.norm();
                }
                assert!((lam - want).abs() < 1e-15);
                assert!(lam > 0.0 && lam < gb.min(PI));
            }
        }
    }

    /// A tiny polygon: Ω ≈ planar area / d², Π ≈ Ω cos θ.
    #[test]
    fn polygon_measures_small_polygon_limits() {
        let h = 1e-4;
        let c = v(0.3, -0.2, 1.0);
        let d = c.norm();
        let sq = [
            c.add(&v(-h, -h, 0.0)),
            c.add(&v(h, -h, 0.0)),
            c.add(&v(h, h, 0.0)),
            c.add(&v(-h, h, 0.0)),
        ];
        // Planar area 4h² in the plane z = 1, seen at cos α = 1/d.
        let omega = 4.0 * h * h / (d * d) / d;
        let s = solid_angle(&sq);
        assert!((s / omega - 1.0).abs() < 1e-6, "{s} {omega}");
        let p = projected_solid_angle(&sq, &v(0.0, 0.0, 1.0)).abs();
        assert!((p / (omega / d) - 1.0).abs() < 1e-6, "{p}");
    }

    /// A band ±10° about the equator over 270° of azimuth: vertex 0 is
    /// antipodal to one of the lower vertices (a fan from it would fail).
    /// Against the area integrated in azimuth between the great arcs.
    #[test]
    fn polygon_measures_band_with_antipodal_vertices() {
        let el = 10f64.to_radians();
        let dir = |az: f64, e: f64| {
            let a = az.to_radians();
            v(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
        };
        let mut band: Vec<_> = (0..=6).map(|i| dir(45.0 * i as f64, el)).collect();
        band.extend((0..=6).rev().map(|i| dir(45.0 * i as f64, -el)));
        assert!((band[0].dot(&band[9]) + 1.0).abs() < 1e-15);
        // ∫ (sin el_top − sin el_bottom) dφ, el of a great arc at azimuth φ
        // from its normal: tan el = −(n_x cos φ + n_y sin φ) / n_z.
        let mut want = 0.0;
        for k in 0..6 {
            let (a, b) = (dir(45.0 * k as f64, el), dir(45.0 * (k + 1) as f64, el));
            let n = a.cross(&b);
            let m = 2000;
            let h = PI / 4.0 / m as f64;
            for j in 0..m {
                let phi = (45.0 * k as f64).to_radians() + (j as f64 + 0.5) * h;
                let t = -(n.x * phi.cos() + n.y * phi.sin()) / n.z;
                // Both rows are mirror images: twice the upper half.
                want += 2.0 * h * (t / (1.0 + t * t).sqrt());
            }
        }
        let o = oriented_solid_angle(&band);
        assert!((o - (4.0 * PI - want)).abs() < 1e-6, "{o} {want}");
        assert!((solid_angle(&band) - want).abs() < 1e-6);
        band.reverse();
        assert!((oriented_solid_angle(&band) - want).abs() < 1e-6);
    }

    #[test]
    fn polygon_measures_degenerate_input() {
        assert!(oriented_solid_angle(&[v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]).is_nan());
        let z = [v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)];
        assert!(oriented_solid_angle(&z).is_nan());
        let o = [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)];
        assert!(projected_solid_angle(&o, &v(0.0, 0.0, 0.0)).is_nan());
    }
}
