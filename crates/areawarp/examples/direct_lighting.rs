//! Direct lighting at one shading point, the way a renderer does it, in
//! `f32`: a triangle light and a rectangle light sampled by solid angle
//! (`LightWarp::sample_light`: direction, point on the light, distance for
//! the shadow ray, pdf in solid angle and in area), combined by multiple
//! importance sampling with cosine-weighted hemisphere sampling, whose
//! directions are tested against the lights with `pdf` (0 off the light)
//! and mapped back to the light's unit square with `inverse`; and the
//! one-shot light samples (`sample_light_once`, `sample_once`) a renderer
//! calls when it draws one sample per light and shading point.
//!
//! ```sh
//! cargo run --release -p areawarp --example direct_lighting
//! ```
//!
//! The irradiance of each (unit-radiance) light is compared with the exact
//! value, the projected solid angle of the light polygon.

use areawarp::estimate::Heuristic;
use areawarp::shapes::polygon_measures::projected_solid_angle;
use areawarp::shapes::{PhongLobe, SphericalRectangle, SphericalTriangle};
use areawarp::{LightWarp, Vec3, Warp};

/// A shading point and its normal (here: the origin, facing +z).
const ORIGIN: [f32; 3] = [0.0, 0.0, 0.0];
/// Samples per technique, on a 32 × 32 jittered grid.
const SIDE: usize = 32;

/// A small deterministic generator (a renderer would use its own sampler).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }
}

/// Jittered points on [0, 1)².
fn jittered(rng: &mut Lcg) -> Vec<[f32; 2]> {
    let mut out = Vec::with_capacity(SIDE * SIDE);
    for i in 0..SIDE {
        for j in 0..SIDE {
            let u = (i as f32 + rng.next()) / SIDE as f32;
            let v = (j as f32 + rng.next()) / SIDE as f32;
            out.push([u.min(1.0), v.min(1.0)]);
        }
    }
    out
}

/// Irradiance at the shading point from a unit-radiance light sampled by
/// `light`, MIS-combined (balance heuristic) with cosine sampling.
fn irradiance<L: LightWarp<f32>>(light: &L, rng: &mut Lcg) -> f32 {
    let cosine = PhongLobe::<f32>::new(1.0).expect("k = 1 is a valid exponent");
    let n = (SIDE * SIDE) as f32;
    let mut sum = 0.0f32;
    // Light sampling: every sample hits the light; the shadow ray would run
    // from the shading point to `s.point`, `s.distance` long.
    for uv in jittered(rng) {
        let s = light.sample_light(uv);
        let cos_theta = s.direction.z.max(0.0);
        let p_bsdf = cosine.pdf(&s.direction);
        let w = Heuristic::Balance.weight(0, &[f64::from(s.pdf), f64::from(p_bsdf)]) as f32;
        sum += w * cos_theta / s.pdf;
    }
    // Cosine sampling: `light.pdf` is 0 for directions that miss the light.
    for uv in jittered(rng) {
        let b = cosine.sample_uv(uv);
        let p_light = light.pdf(&b.point);
        if p_light > 0.0 {
            // The direction hit the light: its (u, v) on the light's square,
            // e.g. for a path guide or to look up the light sample's stratum.
            let [lu, lv] = light
                .inverse(&b.point)
                .expect("a direction with a nonzero pdf is on the light");
            assert!((0.0..=1.0).contains(&lu) && (0.0..=1.0).contains(&lv));
            let w = Heuristic::Balance.weight(1, &[f64::from(p_light), f64::from(b.pdf)]) as f32;
            sum += w * b.point.z / b.pdf;
        }
    }
    sum / n
}

fn main() {
    let o = Vec3::from(ORIGIN);
    let normal = Vec3::new(0.0f32, 0.0, 1.0);
    let mut rng = Lcg(2024);

    // A triangle light above and to the side.
    let tri = [
        Vec3::new(0.5f32, -0.2, 1.0),
        Vec3::new(1.5, 0.3, 1.2),
        Vec3::new(0.4, 0.9, 0.8),
    ];
    let triangle = SphericalTriangle::from_points(tri[0], tri[1], tri[2], o)
        .expect("a non-degenerate triangle seen from off its plane");
    let e_tri = irradiance(&triangle, &mut rng);
    let exact_tri = projected_solid_angle(&tri.map(|p| p - o), &normal);

    // A rectangle light: corner, two perpendicular edges.
    let (corner, ex, ey) = (
        Vec3::new(-1.0f32, -0.5, 1.5),
        Vec3::new(0.8f32, 0.0, 0.0),
        Vec3::new(0.0f32, 1.2, 0.0),
    );
    let rectangle =
        SphericalRectangle::new(corner, ex, ey, o).expect("a rectangle seen from off its plane");
    let quad = [corner, corner + ex, corner + ex + ey, corner + ey];
    let e_rect = irradiance(&rectangle, &mut rng);
    let exact_rect = projected_solid_angle(&quad.map(|p| p - o), &normal);

    // One light sample, as a renderer would use it.
    let s = rectangle.sample_light([0.25, 0.75]);
    println!(
        "rectangle sample: direction {:?}, point {:?}, distance {:.4}, pdf {:.4}/sr = {:.4}/m²",
        s.direction, s.point, s.distance, s.pdf, s.pdf_area
    );
    // A renderer that draws one sample per light and shading point builds
    // no shape: the one-shot paths compute what that sample needs, with the
    // same bits.
    let once = SphericalTriangle::sample_light_once(&tri[0], &tri[1], &tri[2], &o, &0.25, &0.75)
        .expect("the triangle above");
    assert_eq!(once, triangle.sample_light([0.25, 0.75]));
    let once = SphericalRectangle::sample_once(&corner, &ex, &ey, &o, &0.25, &0.75)
        .expect("the rectangle above");
    assert_eq!(once, s);
    println!(
        "triangle:  irradiance {e_tri:.5} (exact {exact_tri:.5}, relative error {:.1e})",
        (e_tri / exact_tri - 1.0).abs()
    );
    println!(
        "rectangle: irradiance {e_rect:.5} (exact {exact_rect:.5}, relative error {:.1e})",
        (e_rect / exact_rect - 1.0).abs()
    );
    assert!((e_tri / exact_tri - 1.0).abs() < 1e-2);
    assert!((e_rect / exact_rect - 1.0).abs() < 1e-2);
}
