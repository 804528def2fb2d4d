//! The construction of the projected polygon (`ProjectedPolygon::new`, then
//! `measure()`), measured so that a loaded machine does not blur it: for
//! each polygon of `benches/projected_polygon.rs`, batches of 256 builds in
//! `f64` and in `f32` timed alternately, and the minimum over many
//! repetitions of each (preemption and frequency changes only ever add
//! time). Issue 10's target is a quadrilateral (`convex`) in at most 1 µs.
//!
//! ```text
//! cargo bench -p areawarp --bench projected_polygon_min [-- REPS]
//! ```
//!
//! Prints the minimum ns per build.

use areawarp::shapes::ProjectedPolygon;
use areawarp::{Real, Vec3, Warp};
use std::hint::black_box;
use std::time::Instant;

#[path = "support/polygons.rs"]
mod polygons;
use polygons::{polygons, vertices};

/// Builds per timed batch.
const BATCH: usize = 256;

/// One batch of builds; ns per build.
fn batch<T: Real>(verts: &[Vec3<T>]) -> f64 {
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..BATCH {
        if let Ok(w) = ProjectedPolygon::new(black_box(verts)) {
            acc += w.measure().to_f64();
        }
    }
    black_box(acc);
    t.elapsed().as_nanos() as f64 / BATCH as f64
}

fn main() {
    // `cargo bench` passes `--bench`; a number among the arguments sets the
    // repetitions.
    let reps: usize = std::env::args()
        .filter_map(|a| a.parse().ok())
        .next()
        .unwrap_or(2000);
    for (name, v) in polygons() {
        let (v64, v32) = (vertices::<f64>(&v), vertices::<f32>(&v));
        let (mut best64, mut best32) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..reps {
            best64 = best64.min(batch(&v64));
            best32 = best32.min(batch(&v32));
        }
        println!("build {name:12} f64 {best64:8.0} ns  f32 {best32:8.0} ns");
    }
}
