//! The random and near-degenerate light shapes of the fuzz (shared by
//! `light_fuzz.rs`, `one_shot.rs`, and `polygon_fuzz.rs` for the helpers): spherical triangles (random, nearly
//! coincident, nearly antipodal, nearly collinear vertices, points at scales
//! 1e-30 … 1e30) and spherical rectangles (observers 1e-6 … 1e-300 off the
//! plane, elongated, scales 1e-30 … 1e30), sphere lights (tiny cones,
//! observers next to the surface, scales 1e-30 … 1e30), and the values of `u`, `v` every
//! accepted shape is sampled at.
#![allow(dead_code)] // each test crate uses a part

use areawarp::shapes::{
    SphericalRectangle, SphericalRectangleVariant, SphericalTriangle, SphericalTriangleVariant,
};
use areawarp::{Real, Vec3, WarpError};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// A triangle case: vertex directions, or points and an observer.
#[derive(Clone, Debug)]
pub struct TriangleCase {
    pub kind: &'static str,
    pub v: [[f64; 3]; 3],
    /// `Some(o)`: the vertices are points seen from `o`.
    pub observer: Option<[f64; 3]>,
}

/// A rectangle case: corner, edges, observer.
#[derive(Clone, Debug)]
pub struct RectangleCase {
    pub kind: &'static str,
    pub s: [f64; 3],
    pub ex: [f64; 3],
    pub ey: [f64; 3],
    pub o: [f64; 3],
}

impl TriangleCase {
    /// The case's triangle in `T` with `variant`: of the vertex
    /// directions, or of the points seen from the observer.
    pub fn build<T: Real>(
        &self,
        variant: SphericalTriangleVariant,
    ) -> Result<SphericalTriangle<T>, WarpError> {
        let [a, b, c] = self.v.each_ref().map(|p| v3::<T>(p));
        match &self.observer {
            None => SphericalTriangle::new_with(a, b, c, variant),
            Some(o) => {
                SphericalTriangle::from_points(a, b, c, v3(o)).map(|w| w.with_variant(variant))
            }
        }
    }
}

impl RectangleCase {
    /// The case's rectangle in `T` with `variant`.
    pub fn build<T: Real>(
        &self,
        variant: SphericalRectangleVariant,
    ) -> Result<SphericalRectangle<T>, WarpError> {
        let [s, ex, ey, o] = [&self.s, &self.ex, &self.ey, &self.o].map(|x| v3::<T>(x));
        SphericalRectangle::new_with(s, ex, ey, o, variant)
    }
}

pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn scale(a: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// A direction (not normalized, not zero).
pub fn direction() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-1.0f64..1.0).prop_map(|a| {
        if a.iter().all(|x| x.abs() < 1e-3) {
            [1.0, a[1], a[2]]
        } else {
            a
        }
    })
}

/// `10^e` for `e` uniform in `[lo, hi]`.
pub fn power(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    (lo..hi).prop_map(|e| 10f64.powf(e))
}

pub fn triangle_case() -> impl Strategy<Value = TriangleCase> {
    let random = (direction(), direction(), direction()).prop_map(|(a, b, c)| TriangleCase {
        kind: "random",
        v: [a, b, c],
        observer: None,
    });
    // B and C within δ of A.
    let coincident =
        (direction(), direction(), direction(), power(-17.0, -1.0)).prop_map(|(a, db, dc, d)| {
            let a = normalize(a);
            TriangleCase {
                kind: "nearly coincident",
                v: [a, add(a, scale(db, d)), add(a, scale(dc, d * 0.7))],
                observer: None,
            }
        });
    // C within δ of −A (or of −B).
    let antipodal = (
        direction(),
        direction(),
        direction(),
        power(-17.0, -1.0),
        any::<bool>(),
    )
        .prop_map(|(a, b, dc, d, from_b)| {
            let a = normalize(a);
            let b = normalize(b);
            let base = if from_b { b } else { a };
            TriangleCase {
                kind: "nearly antipodal",
                v: [a, b, add(scale(base, -1.0), scale(dc, d))],
                observer: None,
            }
        });
    // C within δ of the great circle through A and B (or of their chord).
    let collinear = (
        direction(),
        direction(),
        -1.5f64..2.5,
        power(-17.0, -1.0),
        any::<bool>(),
    )
        .prop_map(|(a, b, t, d, chord)| {
            let a = normalize(a);
            let b = normalize(b);
            let n = normalize(cross(a, b));
            let on = add(scale(a, 1.0 - t), scale(b, t));
            let on = if chord { on } else { normalize(on) };
            TriangleCase {
                kind: "nearly collinear",
                v: [a, b, add(on, scale(n, d))],
                observer: None,
            }
        });
    // Points at scale 10^k seen from an observer at the same scale.
    let points = (
        direction(),
        direction(),
        direction(),
        direction(),
        power(-30.0, 30.0),
    )
        .prop_map(|(a, b, c, o, k)| TriangleCase {
            kind: "points at scale",
            v: [scale(a, k), scale(b, k), scale(c, k)],
            observer: Some(scale(o, k * 0.5)),
        });
    prop_oneof![random, coincident, antipodal, collinear, points]
}

pub fn rectangle_case() -> impl Strategy<Value = RectangleCase> {
    (
        direction(),
        direction(),
        direction(),
        (power(-2.0, 2.0), power(-2.0, 2.0)),
        (-1.0f64..2.0, -1.0f64..2.0),
        prop_oneof![power(-300.0, -6.0), power(-6.0, 1.0)],
        any::<bool>(),
        power(-30.0, 30.0),
    )
        .prop_map(|(c, n, t, (lx, ly), (fx, fy), h, below, k)| {
            let n = normalize(n);
            let t1 = normalize(cross(n, t));
            let t2 = cross(n, t1);
            let (ex, ey) = (scale(t1, lx * k), scale(t2, ly * k));
            let s = scale(c, k);
            let foot = add(add(s, scale(ex, fx)), scale(ey, fy));
            let h = if below { -h } else { h };
            RectangleCase {
                kind: if h.abs() < 1e-6 { "grazing" } else { "random" },
                s,
                ex,
                ey,
                o: add(foot, scale(n, h * k)),
            }
        })
}

/// A sphere-light case: centre, radius, observer.
#[derive(Clone, Debug)]
pub struct SphereCase {
    pub kind: &'static str,
    pub c: [f64; 3],
    pub r: f64,
    pub o: [f64; 3],
}

/// Sphere lights seen from outside: `sin θ_max = r/d` random, tiny
/// (10⁻³⁰ … 10⁻⁶: far away) or next to 1 (the observer 10⁻¹⁶ … 10⁻² of d
/// above the surface), `d` at scales 10⁻³⁰ … 10³⁰, the observer at the
/// origin or offset by up to 10⁴ d (the centre's rounding then dominates).
pub fn sphere_case() -> impl Strategy<Value = SphereCase> {
    (
        direction(),
        direction(),
        prop_oneof![
            (0.0f64..1.0).prop_map(|x| ("random", x)),
            power(-30.0, -6.0).prop_map(|x| ("far", x)),
            power(-16.0, -2.0).prop_map(|g| ("near the surface", 1.0 - g)),
        ],
        power(-30.0, 30.0),
        prop_oneof![Just(0.0), power(-3.0, 4.0)],
    )
        .prop_map(|(dir, at, (kind, sin_max), d, offset)| {
            let o = scale(normalize(at), offset * d);
            SphereCase {
                kind,
                c: add(o, scale(normalize(dir), d)),
                r: d * sin_max,
                o,
            }
        })
}

/// A runner with a fixed seed: the counts are reproducible. For an
/// exploratory campaign, `AREAWARP_FUZZ_SEED=N` (an integer) draws other
/// shapes from the seed `N` (its counts then differ from the quoted ones;
/// the assertions are the same).
pub fn runner(config: Config) -> TestRunner {
    let rng = match std::env::var("AREAWARP_FUZZ_SEED") {
        Ok(n) => {
            let n: u64 = n.parse().expect("AREAWARP_FUZZ_SEED: an integer");
            let mut seed = [0u8; 32];
            seed[..8].copy_from_slice(&n.to_le_bytes());
            TestRng::from_seed(RngAlgorithm::ChaCha, &seed)
        }
        Err(_) => TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    };
    TestRunner::new_with_rng(config, rng)
}

/// The six values of `u` and `v` every accepted shape is sampled at.
pub fn unit_values<T: Real>() -> [T; 6] {
    let subnormal = if T::precision() == 24 {
        f64::from(f32::from_bits(1))
    } else {
        f64::from_bits(1)
    };
    [
        T::zero(),
        T::from_f64(subnormal),
        T::from_f64(1e-7),
        T::from_ratio(1, 2),
        T::one() - &T::unit_roundoff(),
        T::one(),
    ]
}

/// `2^(−p/2)`, the library's on-shape tolerance for a shape of extent 1
/// (crate-private there): the relative tolerance of the fuzz's point
/// checks (a light sample's point on the triangle's plane, the rectangle
/// or the sphere), times the case's scale. Directions are judged by each
/// warp's own `on_shape_tolerance()`.
pub fn tolerance<T: Real>() -> T {
    T::exp2i(-((T::precision() / 2) as i32))
}

pub fn v3<T: Real>(a: &[f64; 3]) -> Vec3<T> {
    Vec3::new(T::from_f64(a[0]), T::from_f64(a[1]), T::from_f64(a[2]))
}

/// Whether a light sample agrees with itself (`None`) or how it does not:
/// its point lies along its direction at its distance from `observer`
/// ([`light_point_consistency`]), and its density in area is its density
/// in solid angle times `|cos θ_e|/distance²` ([`light_density_consistency`]).
pub fn light_consistency<T: Real>(
    s: &areawarp::LightSample<T>,
    observer: &Vec3<T>,
    normal: &Vec3<f64>,
    normal_error: f64,
    extent: f64,
) -> Option<String> {
    light_point_consistency(s, observer, extent)
        .or_else(|| light_density_consistency(s, normal, normal_error))
}

/// Whether the sample's point lies along its direction at its distance
/// from `observer`, within `64u` of `|point| + |observer| + distance +
/// extent` (`extent` the magnitude of the coordinates the point is formed
/// from: the rectangle's corner and edges, the sphere's centre and
/// radius); `None` if it does.
pub fn light_point_consistency<T: Real>(
    s: &areawarp::LightSample<T>,
    observer: &Vec3<T>,
    extent: f64,
) -> Option<String> {
    let u = T::unit_roundoff().to_f64();
    let d: Vec3<f64> = s.direction.convert();
    let p: Vec3<f64> = s.point.convert();
    let o: Vec3<f64> = observer.convert();
    let t = s.distance.to_f64();
    let gap = o.add(&d.scale(&t)).sub(&p).norm();
    let scale = p.norm() + o.norm() + t + extent;
    (!(gap <= 64.0 * u * scale))
        .then(|| format!("point {gap:e} from observer + distance·direction (scale {scale:e})"))
}

/// Whether the sample's density in area is its density in solid angle
/// times `|cos θ_e|/distance²`, with `θ_e` the angle at the emitter between
/// the direction and `normal` (the emitter's unit normal at the point, in
/// `f64`, known to `normal_error`), within [`density_factor`]` · u`
/// relatively, widened by `1/|cos θ_e|` for the errors of the rounded
/// direction and of `normal` in the cosine (the sample's own `|cos θ_e|³`
/// carries three times its cosine's relative error, and a plane seen at a
/// grazing angle its distance's); `None` if it is. A density of 0 is left
/// to the caller's own rule (the sphere's rim, the polygon's horizon), and
/// so is the density where the cosine is within `64` times those errors of
/// 0 (the reference cannot resolve it).
pub fn light_density_consistency<T: Real>(
    s: &areawarp::LightSample<T>,
    normal: &Vec3<f64>,
    normal_error: f64,
) -> Option<String> {
    let u = T::unit_roundoff().to_f64();
    let got = s.pdf_area.to_f64();
    if got == 0.0 {
        return None;
    }
    let d: Vec3<f64> = s.direction.convert();
    let t = s.distance.to_f64();
    let cos = d.dot(normal).abs();
    if !(cos > 64.0 * (u + normal_error)) {
        // The reference cannot resolve the cosine (a grazing ray, or a
        // normal not known to better than the cosine itself).
        return None;
    }
    let expect = s.pdf.to_f64() * cos / t / t;
    let rel = (got - expect).abs() / expect;
    let k = density_factor::<T>();
    (!(rel <= k * (u * (1.0 + 1.0 / cos) + normal_error / cos))).then(|| {
        format!(
            "density in area {got:e}, expected pdf·|cos θ_e|/t² = {expect:e} (|cos θ_e| = {cos:e})"
        )
    })
}

/// The factor of [`light_density_consistency`]'s tolerance, in units of
/// `u(1 + 1/|cos θ_e|)`.
///
/// For `T` narrower than `f64` (`f32`) the reference, evaluated in `f64`
/// from the sample's own direction, distance and density in solid angle
/// and a normal from the corners as `T` holds them, is exact to within
/// `2⁻²⁹` of `T`'s errors, so the factor bounds the library's own error:
/// the cosine `d·n̂` formed in `T` from a direction within a few units and a
/// rounded normal (about `8u/|cos|`), cubed (`24u/|cos|`), the distance
/// `t₀/|cos|` squared in the reference (`16u/|cos|`) and the products by
/// `1/t₀` (a few `u`): about `40`, taken as `64`. The light and polygon
/// fuzzes reach `8.4` (`light_fuzz` at fast sizes, seeds 1–40, grazing
/// rays with `|cos| ≈ 10⁻⁵`), `4.0` (its large sizes, seeds 1–41) and
/// `3.4` (`polygon_fuzz_large`, seeds 1–61). A density wrong by `10⁻⁵`
/// (`168u`) is caught on 283 of 2,023 robust `f32` triangles, 290 of 1,738
/// rectangles, 317 of 1,058 sphere lights and 47 of 460 polygons of seed
/// 1 (fast sizes), where a factor of `256` caught none.
///
/// In `f64` the reference's normal is no more accurate than the library's
/// (both in `f64`, from a fan of differences that cancel for a thin or far
/// emitter, which `normal_error` does not always cover): `256`, after `64`
/// was exceeded by 1.1–1.3× on two triangles of the large light fuzz
/// (seeds 98 and 108); the large fuzz reaches `38` on seeds 1–41 and the
/// large polygon fuzz `3.9` on seeds 1–61.
pub fn density_factor<T: Real>() -> f64 {
    if T::precision() < f64::MANTISSA_DIGITS {
        64.0
    } else {
        256.0
    }
}

/// The plane of a light's corners as `T` holds them, in `f64` relative to
/// the observer: from the differences `p − o` rounded to `T` (what
/// `from_points` builds the triangle and the polygon from, and their light
/// samples' plane), the normal of their fan of triangles.
pub struct EmitterPlane {
    /// The observer (rounded to `T`).
    pub observer: Vec3<f64>,
    /// The corners' centroid, relative to the observer.
    pub centroid: Vec3<f64>,
    /// The unit normal `Σ (Vᵢ − V₀) × (Vᵢ₊₁ − V₀)/|…|`.
    pub normal: Vec3<f64>,
}

impl EmitterPlane {
    /// How far the light sample's `point` lies from the plane, and the
    /// scale of the magnitudes it was formed from
    /// (`|point − observer| + |centroid| + |observer|`): each fuzz holds the
    /// ratio to its own tolerance.
    pub fn offset<T: Real>(&self, point: &Vec3<T>) -> (f64, f64) {
        let q = point.convert::<f64>().sub(&self.observer);
        let off = q.sub(&self.centroid).dot(&self.normal).abs();
        (off, q.norm() + self.centroid.norm() + self.observer.norm())
    }
}

/// [`EmitterPlane`] of the corners `points` seen from `observer`.
pub fn emitter_plane<T: Real>(points: &[[f64; 3]], observer: &[f64; 3]) -> EmitterPlane {
    let o = v3::<T>(observer);
    let rel: Vec<Vec3<f64>> = points
        .iter()
        .map(|p| v3::<T>(p).sub(&o).convert::<f64>())
        .collect();
    let mut normal = Vec3::zero();
    for k in 1..rel.len() - 1 {
        normal = normal.add(&rel[k].sub(&rel[0]).cross(&rel[k + 1].sub(&rel[0])));
    }
    let centroid = rel
        .iter()
        .fold(Vec3::zero(), |c, p| c.add(p))
        .scale(&(1.0 / rel.len() as f64));
    EmitterPlane {
        observer: o.convert(),
        centroid,
        normal: normal.scale(&(1.0 / normal.norm())),
    }
}
