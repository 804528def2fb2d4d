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
use std::hint::black_box;

const N: usize = 4096;

/// A fixed batch of points in [0, 1]² (a 64-bit LCG), the corners included.
fn batch() -> Vec<(f64, f64)> {
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
    pts
}

/// The hand-written baselines, once per scalar type.
macro_rules! baselines {
    ($m:ident, $t:ident) => {
        mod $m {
            use std::$t::consts::{FRAC_PI_2, FRAC_PI_4, PI};

            /// Shirley–Chiu concentric map, as renderers write it.
            #[inline]
            pub fn concentric_disk(u: $t, v: $t) -> [$t; 2] {
                let a = 2.0 * u - 1.0;
                let b = 2.0 * v - 1.0;
                if a == 0.0 && b == 0.0 {
                    return [0.0, 0.0];
                }
                let (r, theta) = if a.abs() > b.abs() {
                    (a, FRAC_PI_4 * (b / a))
                } else {
                    (b, FRAC_PI_2 - FRAC_PI_4 * (a / b))
                };
                let (s, c) = theta.sin_cos();
                [r * c, r * s]
            }

            /// Malley's method: the concentric disk lifted to the hemisphere.
            #[inline]
            pub fn cosine_hemisphere(u: $t, v: $t) -> [$t; 3] {
                let [x, y] = concentric_disk(u, v);
                let z = (1.0 - x * x - y * y).max(0.0).sqrt();
                [x, y, z]
            }

            /// The samples with their pdf, as a renderer uses them.
            #[inline]
            pub fn cosine_hemisphere_pdf(u: $t, v: $t) -> [$t; 4] {
                let [x, y, z] = cosine_hemisphere(u, v);
                [x, y, z, z * std::$t::consts::FRAC_1_PI]
            }
            #[inline]
            pub fn uniform_sphere_pdf(u: $t, v: $t) -> [$t; 4] {
                let [x, y, z] = uniform_sphere(u, v);
                [x, y, z, 0.25 * std::$t::consts::FRAC_1_PI]
            }
            #[inline]
            pub fn triangle_pdf(p: &[[$t; 3]; 3], inv_area: $t, u: $t, v: $t) -> [$t; 4] {
                let [x, y, z] = triangle(p, u, v);
                [x, y, z, inv_area]
            }
            #[inline]
            pub fn concentric_disk_pdf(u: $t, v: $t) -> [$t; 3] {
                let [x, y] = concentric_disk(u, v);
                [x, y, std::$t::consts::FRAC_1_PI]
            }

            /// Archimedes: z = 1 − 2u, φ = 2πv.
            #[inline]
            pub fn uniform_sphere(u: $t, v: $t) -> [$t; 3] {
                let z = 1.0 - 2.0 * u;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let (s, c) = (2.0 * PI * v).sin_cos();
                [r * c, r * s, z]
            }

            /// √u barycentrics: b₀ = 1 − √u, b₁ = v√u, b₂ = 1 − b₀ − b₁.
            #[inline]
            pub fn triangle(p: &[[$t; 3]; 3], u: $t, v: $t) -> [$t; 3] {
                let su = u.sqrt();
                let b0 = 1.0 - su;
                let b1 = v * su;
                let b2 = 1.0 - b0 - b1;
                [
                    b0 * p[0][0] + b1 * p[1][0] + b2 * p[2][0],
                    b0 * p[0][1] + b1 * p[1][1] + b2 * p[2][1],
                    b0 * p[0][2] + b1 * p[1][2] + b2 * p[2][2],
                ]
            }
        }
    };
}
baselines!(base_f32, f32);
baselines!(base_f64, f64);

/// Sums the coordinates so that no evaluation can be optimized away.
#[inline]
fn run<T: Copy + Into<f64>, const D: usize>(pts: &[(T, T)], f: impl Fn(T, T) -> [T; D]) -> f64 {
    let mut acc = 0.0;
    for &(u, v) in pts {
        let p = f(black_box(u), black_box(v));
        for x in p {
            acc += x.into();
        }
    }
    acc
}

/// The triangle of the benchmark: arbitrary, off the origin, not axis-aligned.
const TRIANGLE: [[f64; 3]; 3] = [[0.3, -0.2, 1.1], [2.1, 0.4, 0.7], [0.9, 1.7, 1.3]];

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
