//! The planar triangle of `benches/simple_warps.rs` against its hand-written
//! baseline, measured so that a loaded machine does not blur the ratio: the
//! same batch of 4096 `(u, v)` points, areawarp and baseline batches timed
//! alternately, and the minimum over many repetitions of each (preemption
//! and frequency changes only ever add time).
//!
//! ```text
//! cargo bench -p areawarp --bench planar_triangle_min [-- REPS]
//! ```
//!
//! Prints ns per sample (batch / 4096) and the ratio areawarp / baseline.

use areawarp::shapes::PlanarTriangle;
use areawarp::{Vec3, Warp};
use std::hint::black_box;
use std::time::Instant;

const N: usize = 4096;

/// The triangle of `simple_warps.rs`.
const TRIANGLE: [[f64; 3]; 3] = [[0.3, -0.2, 1.1], [2.1, 0.4, 0.7], [0.9, 1.7, 1.3]];

/// The batch of `simple_warps.rs`: a 64-bit LCG, the corners included.
fn batch() -> Vec<(f64, f64)> {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut pts: Vec<(f64, f64)> = (0..N).map(|_| (next(), next())).collect();
    pts[..4].copy_from_slice(&[(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0)]);
    pts
}

macro_rules! measure {
    ($t:ident, $reps:expr) => {{
        let pts: Vec<($t, $t)> = batch()
            .into_iter()
            .map(|(u, v)| (u as $t, v as $t))
            .collect();
        let [a, b, c] = TRIANGLE.map(|p| Vec3::<$t>::from(p.map(|x| x as $t)));
        let tri = PlanarTriangle::new(a, b, c).expect("triangle");
        // Baseline vertex order (A, C, B), as in `simple_warps.rs`.
        let p: [[$t; 3]; 3] = [a.into(), c.into(), b.into()];
        let inv_area = 1.0 / tri.measure();
        let ours = || {
            let mut acc = 0.0f64;
            for &(u, v) in &pts {
                let s = tri.sample_uv([black_box(u), black_box(v)]);
                acc += f64::from(s.point.x)
                    + f64::from(s.point.y)
                    + f64::from(s.point.z)
                    + f64::from(s.pdf);
            }
            acc
        };
        let base = || {
            let mut acc = 0.0f64;
            for &(u, v) in &pts {
                let (u, v) = (black_box(u), black_box(v));
                let su = u.sqrt();
                let b0 = 1.0 - su;
                let b1 = v * su;
                let b2 = 1.0 - b0 - b1;
                let q = [
                    b0 * p[0][0] + b1 * p[1][0] + b2 * p[2][0],
                    b0 * p[0][1] + b1 * p[1][1] + b2 * p[2][1],
                    b0 * p[0][2] + b1 * p[1][2] + b2 * p[2][2],
                ];
                acc += f64::from(q[0]) + f64::from(q[1]) + f64::from(q[2]) + f64::from(inv_area);
            }
            acc
        };
        let (mut best_o, mut best_b, mut sink) = (f64::INFINITY, f64::INFINITY, 0.0);
        for _ in 0..$reps {
            let t = Instant::now();
            sink += ours();
            best_o = best_o.min(t.elapsed().as_nanos() as f64 / N as f64);
            let t = Instant::now();
            sink += base();
            best_b = best_b.min(t.elapsed().as_nanos() as f64 / N as f64);
        }
        black_box(sink);
        println!(
            "planar triangle {:3}  areawarp {best_o:6.3} ns  baseline {best_b:6.3} ns  ratio {:.3}",
            stringify!($t),
            best_o / best_b
        );
    }};
}

fn main() {
    let reps: usize = std::env::args()
        .filter_map(|a| a.parse().ok())
        .next()
        .unwrap_or(3000);
    measure!(f32, reps);
    measure!(f64, reps);
}
