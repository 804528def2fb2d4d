//! Does genericity cost anything? The generic `Hemisphere::<f64>` and
//! `PhongLobe::<f64>` maps against hand-written plain-`f64` functions that
//! evaluate the same formulas in the same order (clamping, the quarter-turn
//! azimuth reduction, the cancellation-free radii), over a fixed batch of
//! 4096 `(u, v)` points.
//!
//! ```text
//! cargo bench --bench generic_vs_plain -- --warm-up-time 1 --measurement-time 3
//! ```
//!
//! The ratio generic / plain should be 1 within noise: `Real` for `f64`
//! forwards every method to the inherent `f64` one with `#[inline]`, and the
//! `Clone`-based arithmetic (`a.clone() * &b`) compiles to plain copies.

use areawarp::Warp;
use areawarp::shapes::{Hemisphere, PhongLobe};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::f64::consts::FRAC_PI_2;
use std::hint::black_box;

const N: usize = 4096;

/// A fixed batch of points in [0, 1]² (a 64-bit LCG; no `rand` needed),
/// with the edges included.
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
    pts
}

// ---------------------------------------------------------------------------
// Plain f64: the shapes' formulas, written by hand.

/// `u` clamped to [0, 1], NaN passing through (as `shapes::turns::clamp_unit`,
/// written the same way rather than as `f64::clamp`).
#[inline]
#[allow(clippy::manual_clamp)]
fn clamp_unit(u: f64) -> f64 {
    if u < 0.0 {
        0.0
    } else if u > 1.0 {
        1.0
    } else {
        u
    }
}

/// `(r cos 2πv, r sin 2πv)` by quarter turns (as `shapes::turns::polar_turns`):
/// q = rint(4v) by the 1.5·2^52 rounder, r·i^q exactly, then one product
/// per coordinate.
#[inline]
fn polar_turns(radius: f64, v: f64) -> (f64, f64) {
    const ROUNDER: f64 = 6_755_399_441_055_744.0;
    const COS_Q: [f64; 4] = [1.0, 0.0, -1.0, 0.0];
    const SIN_Q: [f64; 4] = [0.0, 1.0, 0.0, -1.0];
    let shifted = v * 4.0 + ROUNDER;
    let quadrant = (shifted.to_bits() & 3) as usize;
    let reduced = v * 4.0 - (shifted - ROUNDER);
    let (rc, rs) = (radius * COS_Q[quadrant], radius * SIN_Q[quadrant]);
    let (s, c) = (reduced * FRAC_PI_2).sin_cos();
    (c * rc - s * rs, s * rc + c * rs)
}

/// Uniform hemisphere: z = 1 − u, sin θ = √(u (2 − u)).
#[inline]
fn plain_hemisphere(u: f64, v: f64) -> [f64; 3] {
    let u = clamp_unit(u);
    let z = 1.0 - u;
    let sin_theta = (u * (2.0 - u)).sqrt();
    let (x, y) = polar_turns(sin_theta, clamp_unit(v));
    [x, y, z]
}

/// Cosine lobe (k = 1): z = √u, sin θ = √(1 − u).
#[inline]
fn plain_cosine(u: f64, v: f64) -> [f64; 3] {
    let u = clamp_unit(u);
    let (z, sin_theta) = (u.sqrt(), (1.0 - u).sqrt());
    let (x, y) = polar_turns(sin_theta, clamp_unit(v));
    [x, y, z]
}

/// General Phong lobe: l = ln(u)/(k+1), z = e^l, sin θ = √(−expm1(2l)).
#[inline]
fn plain_phong(inv_k1: f64, u: f64, v: f64) -> [f64; 3] {
    let u = clamp_unit(u);
    let l = u.ln() * inv_k1;
    let two_l = l + l;
    let (z, sin_theta) = (l.exp(), (-two_l.exp_m1()).sqrt());
    let (x, y) = polar_turns(sin_theta, clamp_unit(v));
    [x, y, z]
}

// ---------------------------------------------------------------------------

/// Sums the coordinates so that no evaluation can be optimized away.
#[inline]
fn run(pts: &[(f64, f64)], f: impl Fn(f64, f64) -> [f64; 3]) -> f64 {
    let mut acc = 0.0;
    for &(u, v) in pts {
        let p = f(black_box(u), black_box(v));
        acc += p[0] + p[1] + p[2];
    }
    acc
}

fn bench(c: &mut Criterion) {
    let pts = batch();

    // Sanity: the plain functions are the same maps (a benchmark of a
    // different formula would prove nothing).
    let hemi = Hemisphere::<f64>::new();
    let cosine = PhongLobe::<f64>::new(1.0).expect("k = 1");
    let sharp = PhongLobe::<f64>::new(1000.0).expect("k = 1000");
    // Opaque, like the generic lobe's stored 1/(k+1): no constant folding.
    let inv_k1 = black_box(1.0 / 1001.0);
    for &(u, v) in &pts {
        let g = [hemi.map(&u, &v), cosine.map(&u, &v), sharp.map(&u, &v)];
        let p = [
            plain_hemisphere(u, v),
            plain_cosine(u, v),
            plain_phong(inv_k1, u, v),
        ];
        for (g, p) in g.iter().zip(&p) {
            assert!(
                g.x == p[0] && g.y == p[1] && g.z == p[2],
                "plain and generic maps differ at ({u}, {v}): {g:?} vs {p:?}"
            );
        }
    }
    let mut group = c.benchmark_group("map_4096");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("hemisphere/generic", |b| {
        b.iter(|| {
            run(&pts, |u, v| {
                let p = hemi.map(&u, &v);
                [p.x, p.y, p.z]
            })
        })
    });
    group.bench_function("hemisphere/plain", |b| {
        b.iter(|| run(&pts, plain_hemisphere))
    });
    group.bench_function("phong_k1/generic", |b| {
        b.iter(|| {
            run(&pts, |u, v| {
                let p = cosine.map(&u, &v);
                [p.x, p.y, p.z]
            })
        })
    });
    group.bench_function("phong_k1/plain", |b| b.iter(|| run(&pts, plain_cosine)));
    group.bench_function("phong_k1000/generic", |b| {
        b.iter(|| {
            run(&pts, |u, v| {
                let p = sharp.map(&u, &v);
                [p.x, p.y, p.z]
            })
        })
    });
    group.bench_function("phong_k1000/plain", |b| {
        b.iter(|| run(&pts, |u, v| plain_phong(inv_k1, u, v)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
