//! Cost of the projected spherical polygon map (cosine-weighted sampling of
//! polygonal lights, Arvo 2001 §1.4) per marginal inversion setting:
//! the fitted cubic alone, the cubic followed by 1, 2, 3 safeguarded Newton
//! steps, and Newton to convergence; in `f32` and `f64`, on four polygons
//! (convex off the pole, a non-convex comb, a pentagon around the pole, a
//! quadrilateral crossing the horizon). Also the construction cost, alone
//! and followed by one sample (`build`, `one_shot`; filter with
//! `-- projected_polygon/build` or `-- projected_polygon/one_shot`).
//!
//! Each measurement maps a fixed batch of 1024 `(u, v)` points (corners
//! included) with the polygon built once:
//!
//! ```text
//! cargo bench --bench projected_polygon -- --warm-up-time 1 --measurement-time 2
//! ```
//!
//! Criterion reports the time per batch and the throughput in samples per
//! second; ns/sample = batch time / 1024.

use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
use areawarp::{Real, Warp};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

const N: usize = 1024;

/// A fixed batch of `N` points in [0, 1]² (a 64-bit LCG), corners included.
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

#[path = "support/polygons.rs"]
mod polygons;
use polygons::{polygons, vertices};

const SETTINGS: [(&str, MarginalInversion); 5] = [
    ("cubic", MarginalInversion::Cubic),
    ("cubic+1", MarginalInversion::CubicNewton(1)),
    ("cubic+2", MarginalInversion::CubicNewton(2)),
    ("cubic+3", MarginalInversion::CubicNewton(3)),
    ("newton", MarginalInversion::Newton),
];

fn map_in<T: Real>(c: &mut Criterion) {
    let points = batch::<T>();
    for (name, v) in polygons() {
        let verts = vertices::<T>(&v);
        let mut group = c.benchmark_group(format!("projected_polygon/{name}/{}", T::type_name()));
        group.throughput(Throughput::Elements(N as u64));
        for (label, inv) in SETTINGS {
            let w = ProjectedPolygon::new_with(&verts, inv).expect("valid polygon");
            group.bench_with_input(BenchmarkId::from_parameter(label), &points, |b, pts| {
                b.iter(|| {
                    let mut acc = T::zero();
                    for (u, v) in pts {
                        let p = w.map(black_box(u), black_box(v));
                        acc = acc + &p.x + &p.y + &p.z;
                    }
                    acc
                })
            });
        }
        group.finish();
    }
}

/// Construction alone, and construction plus one sample (what a renderer
/// pays per shading point when it builds the sampler on the fly).
fn build_in<T: Real>(c: &mut Criterion) {
    let mut group = c.benchmark_group(format!("projected_polygon/build/{}", T::type_name()));
    for (name, v) in polygons() {
        let verts = vertices::<T>(&v);
        group.bench_with_input(BenchmarkId::from_parameter(name), &verts, |b, verts| {
            b.iter(|| ProjectedPolygon::new(black_box(verts)).map(|w| w.measure()))
        });
    }
    group.finish();
    let mut group = c.benchmark_group(format!("projected_polygon/one_shot/{}", T::type_name()));
    let (u, v) = (T::from_ratio(3, 10), T::from_ratio(7, 10));
    for (name, verts) in polygons() {
        let verts = vertices::<T>(&verts);
        group.bench_with_input(BenchmarkId::from_parameter(name), &verts, |b, verts| {
            b.iter(|| {
                ProjectedPolygon::new(black_box(verts)).map(|w| w.map(black_box(&u), black_box(&v)))
            })
        });
    }
    group.finish();
}

fn benches(c: &mut Criterion) {
    map_in::<f64>(c);
    map_in::<f32>(c);
    build_in::<f64>(c);
    build_in::<f32>(c);
}

criterion_group!(projected_polygon, benches);
criterion_main!(projected_polygon);
