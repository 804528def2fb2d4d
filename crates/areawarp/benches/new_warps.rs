//! Cost of the planar triangle's two maps: Arvo's √u map against Heitz's
//! (2019) low-distortion fold map (no square root), in `f32` and `f64`,
//! each over a fixed batch of 4096 `(u, v)` points, the triangle built once.
//!
//! ```text
//! cargo bench -p areawarp --bench new_warps -- --warm-up-time 1 --measurement-time 3
//! ```
//!
//! Criterion reports the time per batch of 4096; ns/sample = batch time / 4096.

use areawarp::shapes::{PlanarTriangle, PlanarTriangleVariant};
use areawarp::{Real, Vec3, Warp};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

const N: usize = 4096;

/// A fixed batch of `N` points in [0, 1]² (a 64-bit LCG).
fn batch<T: Real>() -> Vec<(T, T)> {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..N)
        .map(|_| (T::from_f64(next()), T::from_f64(next())))
        .collect()
}

fn triangle_in<T: Real>(c: &mut Criterion) {
    let points = batch::<T>();
    let mut group = c.benchmark_group(format!("planar-triangle/map/{}", T::type_name()));
    group.throughput(Throughput::Elements(N as u64));
    for variant in [
        PlanarTriangleVariant::SquareRoot,
        PlanarTriangleVariant::Fold,
    ] {
        let t = PlanarTriangle::new_with(
            Vec3::from_f64(1.0, 2.0, 3.0),
            Vec3::from_f64(-2.0, 0.5, 1.0),
            Vec3::from_f64(0.5, -1.0, 2.0),
            variant,
        )
        .expect("a valid triangle");
        // Points are written to a buffer: no loop-carried dependency, so the
        // time is the map's throughput, not the latency of an accumulator.
        let mut out = vec![Vec3::<T>::zero(); N];
        group.bench_function(BenchmarkId::from_parameter(variant), |b| {
            b.iter(|| {
                for ((u, v), slot) in black_box(&points).iter().zip(out.iter_mut()) {
                    *slot = t.map(u, v);
                }
                black_box(&out);
            })
        });
    }
    group.finish();
}

fn benches(c: &mut Criterion) {
    triangle_in::<f32>(c);
    triangle_in::<f64>(c);
}

criterion_group!(new_warps, benches);
criterion_main!(new_warps);
