//! The simple warps of `benches/simple_warps.rs` against the same
//! hand-written baselines, measured so that a loaded machine does not blur
//! the ratios: the same batch of 4096 `(u, v)` points, areawarp and
//! baseline batches timed alternately, and the minimum over many
//! repetitions of each (preemption and frequency changes only ever add
//! time).
//!
//! ```text
//! cargo bench -p areawarp --bench simple_warps_min [-- REPS]
//! ```
//!
//! Prints ns per sample (batch / 4096) and the ratio areawarp / baseline.

use areawarp::shapes::{ConcentricDisk, PhongLobe, PlanarTriangle, Sphere};
use areawarp::{Vec3, Warp};
use std::hint::black_box;
use std::time::Instant;

#[path = "support/simple_warps_data.rs"]
mod data;
use data::{N, TRIANGLE, base_f32, base_f64, batch, run};

/// Minimum ns per sample of `ours` and `base`, timed alternately `reps`
/// times; prints them with their ratio.
fn report(what: &str, reps: usize, ours: impl Fn() -> f64, base: impl Fn() -> f64) {
    let (mut best_o, mut best_b, mut sink) = (f64::INFINITY, f64::INFINITY, 0.0);
    for _ in 0..reps {
        let t = Instant::now();
        sink += ours();
        best_o = best_o.min(t.elapsed().as_nanos() as f64 / N as f64);
        let t = Instant::now();
        sink += base();
        best_b = best_b.min(t.elapsed().as_nanos() as f64 / N as f64);
    }
    black_box(sink);
    println!(
        "{what:22} areawarp {best_o:6.3} ns  baseline {best_b:6.3} ns  ratio {:.3}",
        best_o / best_b
    );
}

macro_rules! measure {
    ($t:ident, $base:ident, $reps:expr) => {{
        let reps = $reps;
        let ty = stringify!($t);
        let pts: Vec<($t, $t)> = batch()
            .into_iter()
            .map(|(u, v)| (u as $t, v as $t))
            .collect();
        let cosine = PhongLobe::<$t>::new(1.0).expect("k = 1");
        let sphere = Sphere::<$t>::new();
        let disk = ConcentricDisk::<$t>::new();
        let [a, b, c] = TRIANGLE.map(|p| Vec3::<$t>::from(p.map(|x| x as $t)));
        let tri = PlanarTriangle::new(a, b, c).expect("triangle");
        // Baseline vertex order (A, C, B), as in `simple_warps.rs`.
        let tri_base: [[$t; 3]; 3] = [a.into(), c.into(), b.into()];
        let inv_area = 1.0 / tri.measure();
        let s3 = |s: areawarp::Sample<$t, Vec3<$t>>| [s.point.x, s.point.y, s.point.z, s.pdf];
        let s2 = |s: areawarp::Sample<$t, areawarp::Vec2<$t>>| [s.point.x, s.point.y, s.pdf];
        report(
            &format!("cosine hemisphere {ty}"),
            reps,
            || run(&pts, |u, v| s3(cosine.sample_uv([u, v]))),
            || run(&pts, $base::cosine_hemisphere_pdf),
        );
        report(
            &format!("uniform sphere {ty}"),
            reps,
            || run(&pts, |u, v| s3(sphere.sample_uv([u, v]))),
            || run(&pts, $base::uniform_sphere_pdf),
        );
        report(
            &format!("planar triangle {ty}"),
            reps,
            || run(&pts, |u, v| s3(tri.sample_uv([u, v]))),
            || run(&pts, |u, v| $base::triangle_pdf(&tri_base, inv_area, u, v)),
        );
        report(
            &format!("concentric disk {ty}"),
            reps,
            || run(&pts, |u, v| s2(disk.sample_uv([u, v]))),
            || run(&pts, $base::concentric_disk_pdf),
        );
    }};
}

fn main() {
    // `cargo bench` passes `--bench`; a number among the arguments sets the
    // repetitions.
    let reps: usize = std::env::args()
        .filter_map(|a| a.parse().ok())
        .next()
        .unwrap_or(3000);
    measure!(f32, base_f32, reps);
    measure!(f64, base_f64, reps);
}
