//! The simple warps against the textbook formulas a renderer would otherwise
//! write by hand (pbrt-style, our own code below), in `f32` and `f64`, in
//! one run:
//!
//! | warp | areawarp | baseline |
//! |---|---|---|
//! | cosine hemisphere | `PhongLobe::new(1)`: z = √u, sin θ = √(1 − u), φ = 2πv | concentric disk + Malley: z = √(max(0, 1 − x² − y²)) |
//! | uniform sphere | `Sphere::new()`: z = 1 − 2u, sin θ = 2√(u(1 − u)) | z = 1 − 2u, r = √(max(0, 1 − z²)), φ = 2πv |
//! | planar triangle | `PlanarTriangle`: √u barycentrics anchored at A (B or C on u = 1) | b₀ = 1 − √u, b₁ = v√u, p = b₀p₀ + b₁p₁ + (1 − b₀ − b₁)p₂ |
//! | concentric disk | `ConcentricDisk` | Shirley–Chiu, θ = π/4·(b/a) or π/2 − π/4·(a/b) |
//!
//! Each measurement samples a fixed batch of 4096 `(u, v)` points (edges
//! included) and sums the coordinates and the density, so criterion's time
//! per batch / 4096 is the throughput cost of one sample *with its pdf*.
//! The areawarp warps are called by value, `warp.sample_uv([u, v])`, on
//! `f32`/`f64` data exactly as a renderer would; the baselines compute
//! their pdf the way pbrt does (cos θ/π, 1/4π, 1/area, 1/π).
//!
//! ```text
//! cargo bench -p areawarp --bench simple_warps -- --warm-up-time 1 --measurement-time 2
//! python3 scripts/criterion-ratios simple_warps
//! ```
//!
//! The second line prints the ratio areawarp / baseline per warp and scalar
//! from the run's `target/criterion/` estimates (a ratio ≤ 1 is parity or
//! better). Before the timings, every pair is checked to produce points on
//! the same shape (the same point where the two formulas are the same map).

use areawarp::shapes::{ConcentricDisk, PhongLobe, PlanarTriangle, Sphere};
use areawarp::{Vec3, Warp};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

#[path = "support/simple_warps_data.rs"]
mod data;
use data::{N, TRIANGLE, base_f32, base_f64, batch, run};

/// The benchmark for one scalar type.
macro_rules! bench_scalar {
    ($fn_name:ident, $t:ident, $base:ident) => {
        fn $fn_name(c: &mut Criterion) {
            let pts: Vec<($t, $t)> = batch()
                .into_iter()
                .map(|(u, v)| (u as $t, v as $t))
                .collect();
            let cosine = PhongLobe::<$t>::new(1.0).expect("k = 1");
            let sphere = Sphere::<$t>::new();
            let disk = ConcentricDisk::<$t>::new();
            let [a, b, cc] = TRIANGLE.map(|p| Vec3::<$t>::from(p.map(|x| x as $t)));
            let tri = PlanarTriangle::new(a, b, cc).expect("triangle");
            // Baseline vertex order (A, C, B): its b₁ = v√u weighs C and its
            // b₂ = √u(1 − v) weighs B, which is areawarp's map.
            let tri_base: [[$t; 3]; 3] = [a.into(), cc.into(), b.into()];
            let inv_area = 1.0 / tri.measure();
            // [x, y, z, pdf] and [x, y, pdf] from areawarp's by-value call.
            let s3 = |s: areawarp::Sample<$t, Vec3<$t>>| [s.point.x, s.point.y, s.point.z, s.pdf];
            let s2 = |s: areawarp::Sample<$t, areawarp::Vec2<$t>>| [s.point.x, s.point.y, s.pdf];

            // Same shapes (and the same points where the maps coincide).
            let eps = 64.0 * $t::EPSILON;
            for &(u, v) in &pts {
                let p = cosine.map(&u, &v);
                let q = $base::cosine_hemisphere(u, v);
                let (sa, sb) = (cosine.sample_uv([u, v]), $base::cosine_hemisphere_pdf(u, v));
                assert!((sa.pdf - sa.point.z * std::$t::consts::FRAC_1_PI).abs() < eps);
                assert!((sb[3] - q[2] * std::$t::consts::FRAC_1_PI).abs() < eps);
                let norm = |x: [$t; 3]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                assert!((norm(p.into()) - 1.0).abs() < eps && p.z >= 0.0);
                assert!((norm(q) - 1.0).abs() < eps && q[2] >= 0.0);
                let p: [$t; 3] = sphere.map(&u, &v).into();
                let q = $base::uniform_sphere(u, v);
                assert!(
                    p.iter().zip(q).all(|(x, y)| (x - y).abs() < eps),
                    "{p:?} {q:?}"
                );
                let p: [$t; 3] = tri.map(&u, &v).into();
                let q = $base::triangle(&tri_base, u, v);
                assert!(
                    p.iter().zip(q).all(|(x, y)| (x - y).abs() < 4.0 * eps),
                    "{p:?} {q:?}"
                );
                let p: [$t; 2] = disk.map(&u, &v).into();
                let q = $base::concentric_disk(u, v);
                assert!(
                    p.iter().zip(q).all(|(x, y)| (x - y).abs() < eps),
                    "{p:?} {q:?}"
                );
            }

            let ty = stringify!($t);
            let mut group = c.benchmark_group(format!("simple_warps/cosine_hemisphere_{ty}"));
            group.throughput(Throughput::Elements(N as u64));
            group.bench_function("areawarp", |b| {
                b.iter(|| run(&pts, |u, v| s3(cosine.sample_uv([u, v]))))
            });
            group.bench_function("baseline", |b| {
                b.iter(|| run(&pts, $base::cosine_hemisphere_pdf))
            });
            group.finish();

            let mut group = c.benchmark_group(format!("simple_warps/uniform_sphere_{ty}"));
            group.throughput(Throughput::Elements(N as u64));
            group.bench_function("areawarp", |b| {
                b.iter(|| run(&pts, |u, v| s3(sphere.sample_uv([u, v]))))
            });
            group.bench_function("baseline", |b| {
                b.iter(|| run(&pts, $base::uniform_sphere_pdf))
            });
            group.finish();

            let mut group = c.benchmark_group(format!("simple_warps/planar_triangle_{ty}"));
            group.throughput(Throughput::Elements(N as u64));
            group.bench_function("areawarp", |b| {
                b.iter(|| run(&pts, |u, v| s3(tri.sample_uv([u, v]))))
            });
            group.bench_function("baseline", |b| {
                b.iter(|| run(&pts, |u, v| $base::triangle_pdf(&tri_base, inv_area, u, v)))
            });
            group.finish();

            let mut group = c.benchmark_group(format!("simple_warps/concentric_disk_{ty}"));
            group.throughput(Throughput::Elements(N as u64));
            group.bench_function("areawarp", |b| {
                b.iter(|| run(&pts, |u, v| s2(disk.sample_uv([u, v]))))
            });
            group.bench_function("baseline", |b| {
                b.iter(|| run(&pts, $base::concentric_disk_pdf))
            });
            group.finish();
        }
    };
}
bench_scalar!(bench_f32, f32, base_f32);
bench_scalar!(bench_f64, f64, base_f64);

criterion_group!(benches, bench_f32, bench_f64);
criterion_main!(benches);
