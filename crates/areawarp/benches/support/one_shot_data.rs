//! The shading points, lights and `(u, v)` shared by `one_shot.rs` and
//! `one_shot_min.rs`. Whoever includes this module also includes
//! `textbook_one_shot.rs` as `mod textbook` (the textbook batches).

use areawarp::shapes::{SphereLight, SphericalRectangle, SphericalTriangle};
use areawarp::{LightWarp, Real, Vec3, Warp};
use std::hint::black_box;

/// Shading points (and samples) per batch.
pub const N: usize = 256;

/// A 64-bit LCG in [0, 1).
pub fn lcg(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `N` pairs `(u, v)` in [0, 1)².
pub fn batch<T: Real>() -> Vec<(T, T)> {
    let mut next = lcg(0x2545_F491_4F6C_DD1D);
    (0..N)
        .map(|_| (T::from_f64(next()), T::from_f64(next())))
        .collect()
}

/// Triangle lights (points) and shading points below them.
pub fn triangles<T: Real>() -> Vec<[Vec3<T>; 4]> {
    let mut next = lcg(7);
    (0..N)
        .map(|_| {
            let o = Vec3::from_f64(next() - 0.5, next() - 0.5, -1.0 - next());
            [
                Vec3::from_f64(1.0, 0.1, 0.0),
                Vec3::from_f64(0.2, 1.0, 0.1),
                Vec3::from_f64(0.0, 0.3, 1.0),
                o,
            ]
        })
        .collect()
}

/// A rectangle light and shading points below it.
pub fn rectangles<T: Real>() -> Vec<[Vec3<T>; 4]> {
    let mut next = lcg(11);
    (0..N)
        .map(|_| {
            [
                Vec3::from_f64(-0.5, -0.4, 1.0),
                Vec3::from_f64(1.0, 0.0, 0.0),
                Vec3::from_f64(0.0, 0.8, 0.0),
                Vec3::from_f64(2.0 * next() - 1.0, 2.0 * next() - 1.0, -next()),
            ]
        })
        .collect()
}

/// A sphere light (centre, radius) and shading points outside it, 1.25 to
/// 3.5 radii from the centre (cones of 0.26 to 2.5 sr).
pub fn spheres<T: Real>() -> Vec<(Vec3<T>, T, Vec3<T>)> {
    let mut next = lcg(13);
    (0..N)
        .map(|_| {
            (
                Vec3::from_f64(0.1, -0.2, 1.5),
                T::from_f64(0.5),
                Vec3::from_f64(next() - 0.5, next() - 0.5, 0.9 - next()),
            )
        })
        .collect()
}

#[inline]
pub fn fold<T: Real>(acc: T, p: &Vec3<T>, pdf: &T) -> T {
    acc + &p.x + &p.y + &p.z + pdf
}

/// One batch of the triangle `t` built once: `(direction, pdf)` per `(u, v)`.
#[inline(always)]
pub fn triangle_per_sample<T: Real>(t: &SphericalTriangle<T>, uv: &[(T, T)]) -> T {
    uv.iter().fold(T::zero(), |acc, (u, v)| {
        let (p, pdf) = t.map_with_pdf(black_box(u), black_box(v));
        fold(acc, &p, &pdf)
    })
}

/// One batch of one-shot samples: construct + one sample per shading point.
#[inline(always)]
pub fn triangle_one_shot<T: Real>(shapes: &[[Vec3<T>; 4]], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ([a, b, c, o], (u, v))| {
            let (p, pdf) =
                SphericalTriangle::sample_once_from_points(black_box(a), b, c, black_box(o), u, v)
                    .unwrap();
            fold(acc, &p, &pdf)
        })
}

/// One batch of the light `light` (a triangle built by `from_points`, a
/// rectangle, a sphere light) built once: a light sample (direction, point, distance,
/// both densities) per `(u, v)`.
#[inline(always)]
pub fn light_per_sample<T: Real, L: LightWarp<T>>(light: &L, uv: &[(T, T)]) -> T {
    uv.iter().fold(T::zero(), |acc, (u, v)| {
        fold_light(
            acc,
            &light.sample_light([black_box(u).clone(), black_box(v).clone()]),
        )
    })
}

/// One batch of one-shot light samples of the triangle
/// (`sample_light_once`: the plane of the points included).
#[inline(always)]
pub fn triangle_light_one_shot<T: Real>(shapes: &[[Vec3<T>; 4]], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ([a, b, c, o], (u, v))| {
            let smp = SphericalTriangle::sample_light_once(black_box(a), b, c, black_box(o), u, v)
                .unwrap();
            fold_light(acc, &smp)
        })
}

/// One batch of one-shot light samples of the rectangle.
#[inline(always)]
pub fn rectangle_one_shot<T: Real>(shapes: &[[Vec3<T>; 4]], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ([s, ex, ey, o], (u, v))| {
            let smp =
                SphericalRectangle::sample_once(black_box(s), ex, ey, black_box(o), u, v).unwrap();
            fold_light(acc, &smp)
        })
}

/// One batch of textbook one-shot triangle samples
/// (`textbook::textbook_triangle_sample`, unvalidated, in `T`) over the same
/// shading points and `(u, v)` as [`triangle_one_shot`], folding the same
/// outputs (direction, pdf). The vertex directions `p − o` are formed here,
/// as `sample_once_from_points` forms them.
#[inline(always)]
pub fn triangle_textbook_one_shot<T: Real>(shapes: &[[Vec3<T>; 4]], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ([a, b, c, o], (u, v))| {
            let o = black_box(o);
            let (p, pdf) = crate::textbook::textbook_triangle_sample(
                &black_box(a).sub(o),
                &b.sub(o),
                &c.sub(o),
                u,
                v,
            );
            fold(acc, &p, &pdf)
        })
}

/// One batch of textbook one-shot triangle light samples
/// (`textbook::textbook_triangle_light_sample`) over the same shading points
/// and `(u, v)` as [`triangle_light_one_shot`], folding the same outputs.
#[inline(always)]
pub fn triangle_light_textbook_one_shot<T: Real>(shapes: &[[Vec3<T>; 4]], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ([a, b, c, o], (u, v))| {
            let smp = crate::textbook::textbook_triangle_light_sample(
                black_box(a),
                b,
                c,
                black_box(o),
                u,
                v,
            );
            fold_light(acc, &smp)
        })
}

/// One batch of textbook one-shot rectangle samples
/// (`textbook::textbook_rectangle_sample`) over the same shading points and
/// `(u, v)` as [`rectangle_one_shot`], folding the same outputs
/// ([`fold_light`]): the textbook computes the distance and area pdf that
/// areawarp's `LightSample` carries, so both sides do the same work.
#[inline(always)]
pub fn rectangle_textbook_one_shot<T: Real>(shapes: &[[Vec3<T>; 4]], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ([s, ex, ey, o], (u, v))| {
            let smp = crate::textbook::textbook_rectangle_sample(
                black_box(s),
                ex,
                ey,
                black_box(o),
                u,
                v,
            );
            fold_light(acc, &smp)
        })
}

/// One light sample's outputs folded: direction, pdf, area pdf, point and
/// distance.
#[inline(always)]
fn fold_light<T: Real>(acc: T, smp: &areawarp::LightSample<T>) -> T {
    fold(acc, &smp.direction, &smp.pdf) + &smp.pdf_area + &smp.point.x + &smp.distance
}

/// One batch of one-shot light samples of the sphere light.
#[inline(always)]
pub fn sphere_one_shot<T: Real>(shapes: &[(Vec3<T>, T, Vec3<T>)], uv: &[(T, T)]) -> T {
    shapes
        .iter()
        .zip(uv)
        .fold(T::zero(), |acc, ((c, r, o), (u, v))| {
            let smp = SphereLight::sample_once(black_box(c), r, black_box(o), u, v).unwrap();
            fold_light(acc, &smp)
        })
}
