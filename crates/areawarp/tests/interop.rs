//! Round trips between `areawarp::{Vec2, Vec3}` and the vector/point types of
//! mint, glam and nalgebra (features `mint`, `glam`, `nalgebra`):
//!
//! ```text
//! cargo test -p areawarp --features mint,glam,nalgebra --test interop
//! ```
//!
//! Each conversion must keep every coordinate bit for bit, including `-0.0`,
//! subnormals and infinities, and map the right coordinate to the right field.

use areawarp::{Vec2, Vec3};

/// Coordinates that a field mix-up or a lossy conversion would show.
#[cfg(any(feature = "mint", feature = "glam", feature = "nalgebra"))]
fn v3_f32() -> Vec3<f32> {
    Vec3::new(-0.0, f32::MIN_POSITIVE / 8.0, 3.25e38)
}
fn v3_f64() -> Vec3<f64> {
    Vec3::new(1.0 + f64::EPSILON, -2.0e-310, f64::INFINITY)
}
fn v2_f32() -> Vec2<f32> {
    Vec2::new(1.0 + f32::EPSILON, -0.0)
}
#[cfg(any(feature = "mint", feature = "glam", feature = "nalgebra"))]
fn v2_f64() -> Vec2<f64> {
    Vec2::new(-7.25, 5e-324)
}

#[cfg(any(feature = "mint", feature = "glam", feature = "nalgebra"))]
fn bits3_f32(v: Vec3<f32>) -> [u32; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}
fn bits3_f64(v: Vec3<f64>) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}
fn bits2_f32(v: Vec2<f32>) -> [u32; 2] {
    [v.x.to_bits(), v.y.to_bits()]
}
#[cfg(any(feature = "mint", feature = "glam", feature = "nalgebra"))]
fn bits2_f64(v: Vec2<f64>) -> [u64; 2] {
    [v.x.to_bits(), v.y.to_bits()]
}

#[cfg(feature = "mint")]
#[test]
fn mint_round_trips() {
    let a = v3_f64();
    let m: mint::Vector3<f64> = a.into();
    assert_eq!([m.x, m.y, m.z].map(f64::to_bits), bits3_f64(a));
    assert_eq!(bits3_f64(Vec3::from(m)), bits3_f64(a));
    let p: mint::Point3<f64> = a.into();
    assert_eq!(p.z.to_bits(), a.z.to_bits());
    assert_eq!(bits3_f64(p.into()), bits3_f64(a));

    let b = v3_f32();
    let m: mint::Vector3<f32> = b.into();
    assert_eq!(bits3_f32(m.into()), bits3_f32(b));
    let p: mint::Point3<f32> = b.into();
    assert_eq!(bits3_f32(p.into()), bits3_f32(b));

    let c = v2_f32();
    let m: mint::Vector2<f32> = c.into();
    assert_eq!([m.x, m.y].map(f32::to_bits), bits2_f32(c));
    assert_eq!(bits2_f32(m.into()), bits2_f32(c));
    let p: mint::Point2<f32> = c.into();
    assert_eq!(bits2_f32(p.into()), bits2_f32(c));

    let d = v2_f64();
    let m: mint::Vector2<f64> = d.into();
    assert_eq!(bits2_f64(m.into()), bits2_f64(d));
    let p: mint::Point2<f64> = d.into();
    assert_eq!(bits2_f64(p.into()), bits2_f64(d));
}

#[cfg(feature = "glam")]
#[test]
fn glam_round_trips() {
    let a = v3_f32();
    let g: glam::Vec3 = a.into();
    assert_eq!(g.to_array().map(f32::to_bits), bits3_f32(a));
    assert_eq!(bits3_f32(g.into()), bits3_f32(a));
    let g: glam::Vec3A = a.into();
    assert_eq!(g.to_array().map(f32::to_bits), bits3_f32(a));
    assert_eq!(bits3_f32(g.into()), bits3_f32(a));

    let b = v3_f64();
    let g: glam::DVec3 = b.into();
    assert_eq!(g.to_array().map(f64::to_bits), bits3_f64(b));
    assert_eq!(bits3_f64(g.into()), bits3_f64(b));

    let c = v2_f32();
    let g: glam::Vec2 = c.into();
    assert_eq!(g.to_array().map(f32::to_bits), bits2_f32(c));
    assert_eq!(bits2_f32(g.into()), bits2_f32(c));

    let d = v2_f64();
    let g: glam::DVec2 = d.into();
    assert_eq!(g.to_array().map(f64::to_bits), bits2_f64(d));
    assert_eq!(bits2_f64(g.into()), bits2_f64(d));

    // A renderer's round trip: glam in, a warp's point out, glam again.
    use areawarp::Warp;
    use areawarp::shapes::PlanarTriangle;
    let tri = PlanarTriangle::new(
        glam::Vec3::new(0.0, 0.0, 0.0).into(),
        glam::Vec3::X.into(),
        glam::Vec3::Y.into(),
    )
    .expect("unit right triangle");
    let p: glam::Vec3 = tri.map(&0.25, &0.5).into();
    assert!(
        (p - glam::Vec3::new(0.25, 0.25, 0.0)).length() < 1e-6,
        "{p}"
    );
}

#[cfg(feature = "nalgebra")]
#[test]
fn nalgebra_round_trips() {
    let a = v3_f64();
    let n: nalgebra::Vector3<f64> = a.into();
    assert_eq!([n.x, n.y, n.z].map(f64::to_bits), bits3_f64(a));
    assert_eq!(bits3_f64(n.into()), bits3_f64(a));
    let p: nalgebra::Point3<f64> = a.into();
    assert_eq!([p.x, p.y, p.z].map(f64::to_bits), bits3_f64(a));
    assert_eq!(bits3_f64(p.into()), bits3_f64(a));

    let b = v3_f32();
    let n: nalgebra::Vector3<f32> = b.into();
    assert_eq!(bits3_f32(n.into()), bits3_f32(b));
    let p: nalgebra::Point3<f32> = b.into();
    assert_eq!(bits3_f32(p.into()), bits3_f32(b));

    let c = v2_f64();
    let n: nalgebra::Vector2<f64> = c.into();
    assert_eq!([n.x, n.y].map(f64::to_bits), bits2_f64(c));
    assert_eq!(bits2_f64(n.into()), bits2_f64(c));
    let p: nalgebra::Point2<f64> = c.into();
    assert_eq!(bits2_f64(p.into()), bits2_f64(c));

    let d = v2_f32();
    let n: nalgebra::Vector2<f32> = d.into();
    assert_eq!(bits2_f32(n.into()), bits2_f32(d));
    let p: nalgebra::Point2<f32> = d.into();
    assert_eq!(bits2_f32(p.into()), bits2_f32(d));
}

/// Non-`Copy` scalars cross too (nalgebra and mint are generic over the
/// scalar): dual numbers keep their derivative parts.
#[cfg(all(feature = "nalgebra", feature = "mint"))]
#[test]
fn generic_scalars_cross() {
    use areawarp::real::Dual2;
    let v = Vec3::new(
        Dual2::constant(1.0f64),
        Dual2::constant(-2.0),
        Dual2::constant(3.0),
    );
    let n: nalgebra::Vector3<Dual2<f64>> = v.clone().into();
    assert_eq!(Vec3::from(n), v);
    let m: mint::Point3<Dual2<f64>> = v.clone().into();
    assert_eq!(Vec3::from(m), v);
}

/// The default build has no interop types; arrays always convert.
#[test]
fn arrays_round_trip() {
    let a = v3_f64();
    let arr: [f64; 3] = a.into();
    assert_eq!(bits3_f64(Vec3::from(arr)), bits3_f64(a));
    let b = v2_f32();
    let arr: [f32; 2] = b.into();
    assert_eq!(bits2_f32(Vec2::from(arr)), bits2_f32(b));
}
