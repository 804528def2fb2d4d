//! Cost of the solid-angle maps: `literal` (the published algorithms) against
//! `robust` (the same maps reformulated for accuracy), in `f32` and `f64`, for
//! the spherical triangle (Arvo 1995) and the spherical rectangle (Ureña,
//! Fajardo, King 2013).
//!
//! Two measurements per shape, precision and variant, each over a fixed batch
//! of 4096 `(u, v)` points (edges included):
//! - `map`: the shape built once, constants precomputed; the time per batch
//!   divided by 4096 is the cost of one sample;
//! - `build+map`: the shape rebuilt for every sample (a renderer that samples
//!   each emitter once per shading point), construction included.
//!
//! ```text
//! cargo bench --bench solid_angle -- --warm-up-time 1 --measurement-time 3
//! ```
//!
//! Criterion reports the time per batch of 4096 and the throughput in
//! samples per second; ns/sample = batch time / 4096.

use areawarp::shapes::{
    SphericalRectangle, SphericalRectangleVariant, SphericalTriangle, SphericalTriangleVariant,
    ordinary_rectangles,
};
use areawarp::{Real, Vec3, Warp};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

const N: usize = 4096;

/// A fixed batch of `N` points in [0, 1]² (a 64-bit LCG), with the corners
/// included.
fn batch<T: Real>() -> Vec<(T, T)> {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut pts: Vec<(f64, f64)> = (0..N).map(|_| (next(), next())).collect();
    pts[0] = (0.0, 0.0);
    pts[1] = (1.0, 1.0);
    pts[2] = (0.0, 1.0);
    pts[3] = (1.0, 0.0);
    pts.into_iter()
        .map(|(u, v)| (T::from_f64(u), T::from_f64(v)))
        .collect()
}

/// Sums the coordinates of a direction, so that no evaluation is dead code.
#[inline]
fn fold<T: Real>(acc: T, p: &Vec3<T>) -> T {
    acc + &p.x + &p.y + &p.z
}

// ---------------------------------------------------------------------------
// Spherical triangle.

/// An ordinary triangle of about 1.2 sr, no special coordinates.
fn triangle_vertices<T: Real>() -> [Vec3<T>; 3] {
    [
        Vec3::from_f64(1.0, 0.1, 0.0),
        Vec3::from_f64(0.2, 1.0, 0.1),
        Vec3::from_f64(0.0, 0.3, 1.0),
    ]
}

const TRIANGLE_VARIANTS: [SphericalTriangleVariant; 2] = [
    SphericalTriangleVariant::Literal,
    SphericalTriangleVariant::Robust,
];

fn triangle_in<T: Real>(c: &mut Criterion) {
    let points = batch::<T>();
    let [a, b, cc] = triangle_vertices::<T>();

    let mut group = c.benchmark_group(format!("triangle/map/{}", T::type_name()));
    group.throughput(Throughput::Elements(N as u64));
    for variant in TRIANGLE_VARIANTS {
        let t = SphericalTriangle::new_with(a.clone(), b.clone(), cc.clone(), variant)
            .expect("valid triangle");
        group.bench_with_input(BenchmarkId::from_parameter(variant), &t, |bench, t| {
            bench.iter(|| {
                points
                    .iter()
                    .fold(T::zero(), |acc, (u, v)| fold(acc, &t.map(u, v)))
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group(format!("triangle/build+map/{}", T::type_name()));
    group.throughput(Throughput::Elements(N as u64));
    for variant in TRIANGLE_VARIANTS {
        group.bench_function(BenchmarkId::from_parameter(variant), |bench| {
            bench.iter(|| {
                points.iter().fold(T::zero(), |acc, (u, v)| {
                    let t = SphericalTriangle::new_with(
                        black_box(&a).clone(),
                        black_box(&b).clone(),
                        black_box(&cc).clone(),
                        variant,
                    );
                    match t {
                        Ok(t) => fold(acc, &t.map(u, v)),
                        Err(_) => acc,
                    }
                })
            })
        });
    }
    group.finish();
}

fn triangle(c: &mut Criterion) {
    triangle_in::<f32>(c);
    triangle_in::<f64>(c);
}

// ---------------------------------------------------------------------------
// Spherical rectangle.

/// The crate's `oblique` ordinary rectangle (1.3 × 0.7, generic orientation,
/// observer off to the side): `[s, e_x, e_y, o]`.
fn rectangle_parameters<T: Real>() -> [Vec3<T>; 4] {
    let (_, [s, ex, ey, o]) = ordinary_rectangles()
        .into_iter()
        .find(|(name, _)| name == "oblique")
        .expect("the oblique rectangle");
    [s.convert(), ex.convert(), ey.convert(), o.convert()]
}

const RECTANGLE_VARIANTS: [SphericalRectangleVariant; 2] = [
    SphericalRectangleVariant::Literal,
    SphericalRectangleVariant::Robust,
];

/// Folds M(u, v) = (point, direction) into the accumulator.
#[inline]
fn fold_sample<T: Real>(acc: T, r: &SphericalRectangle<T>, u: &T, v: &T) -> T {
    let (point, direction) = r.sample_point(u, v);
    fold(fold(acc, &point), &direction)
}

fn rectangle_in<T: Real>(c: &mut Criterion) {
    let points = batch::<T>();
    let [s, ex, ey, o] = rectangle_parameters::<T>();

    let mut group = c.benchmark_group(format!("rectangle/map/{}", T::type_name()));
    group.throughput(Throughput::Elements(N as u64));
    for variant in RECTANGLE_VARIANTS {
        let r = SphericalRectangle::new_with(s.clone(), ex.clone(), ey.clone(), o.clone(), variant)
            .expect("valid rectangle");
        group.bench_with_input(BenchmarkId::from_parameter(variant), &r, |bench, r| {
            bench.iter(|| {
                points
                    .iter()
                    .fold(T::zero(), |acc, (u, v)| fold_sample(acc, r, u, v))
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group(format!("rectangle/build+map/{}", T::type_name()));
    group.throughput(Throughput::Elements(N as u64));
    for variant in RECTANGLE_VARIANTS {
        group.bench_function(BenchmarkId::from_parameter(variant), |bench| {
            bench.iter(|| {
                points.iter().fold(T::zero(), |acc, (u, v)| {
                    let r = SphericalRectangle::new_with(
                        black_box(&s).clone(),
                        black_box(&ex).clone(),
                        black_box(&ey).clone(),
                        black_box(&o).clone(),
                        variant,
                    );
                    match r {
                        Ok(r) => fold_sample(acc, &r, u, v),
                        Err(_) => acc,
                    }
                })
            })
        });
    }
    group.finish();
}

fn rectangle(c: &mut Criterion) {
    rectangle_in::<f32>(c);
    rectangle_in::<f64>(c);
}

criterion_group!(benches, triangle, rectangle);
criterion_main!(benches);
