//! The batch, the triangle, the hand-written baselines (pbrt-style, our
//! own code) and the summing loop shared by `simple_warps.rs` and
//! `simple_warps_min.rs`.

use std::hint::black_box;

/// Points per batch.
pub const N: usize = 4096;

/// A fixed batch of points in [0, 1]² (a 64-bit LCG), the corners included.
pub fn batch() -> Vec<(f64, f64)> {
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
        pub mod $m {
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

/// Sums each coordinate over the batch, so that no evaluation can be
/// optimized away: one accumulator per coordinate, so that the loop's own
/// dependent additions (one per sample and coordinate, 3 cycles each) do
/// not set a floor under the maps' throughput. With a single sum, four
/// dependent additions per sample (≈ 4.1 ns) hid the cost of maps below it
/// (2026-11-29, before `Real::clamp` became two selects: the planar
/// triangle `f32` measured 0.91–0.95 of its baseline with one sum and
/// 1.10–1.15 with one sum per coordinate).
#[inline]
pub fn run<T: Copy + Into<f64>, const D: usize>(pts: &[(T, T)], f: impl Fn(T, T) -> [T; D]) -> f64 {
    let mut acc = [0.0; D];
    for &(u, v) in pts {
        let p = f(black_box(u), black_box(v));
        for (a, x) in acc.iter_mut().zip(p) {
            *a += x.into();
        }
    }
    acc.iter().sum()
}

/// The triangle of the benchmark: arbitrary, off the origin, not axis-aligned.
pub const TRIANGLE: [[f64; 3]; 3] = [[0.3, -0.2, 1.1], [2.1, 0.4, 0.7], [0.9, 1.7, 1.3]];
