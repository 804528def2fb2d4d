//! The input points the checks are run on: the extremes grid (edges, the
//! smallest inputs a sampler realistically produces, and their mirror images
//! near 1), a uniform grid including the edges, and deterministic random
//! points.
//!
//! All points are `(u, v)` pairs of `f64` in `[0, 1]²`. The checks convert
//! them *exactly* into 256-bit references and round them to the scalar under
//! test (`f32` sees `1 − 10⁻¹²` as `1`, and the reference sees the same
//! rounded value).

use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

/// `2^-60`, built from its bit pattern (exact).
const TWO_POW_M60: f64 = f64::from_bits((1023 - 60) << 52);

/// The extreme coordinates, used for both `u` and `v`:
/// `0, 2^-60, 10^-12, 10^-6, 1/2, 1 − 10^-6, 1 − 10^-12, 1`.
///
/// The edges 0 and 1 are where closed forms meet their singularities (`√u`
/// at `u = 0`, poles, seams); the tiny values probe cancellation
/// (`1 − z` for `z = 1 − u`), and `1 − ε` their mirror images.
pub const EXTREMES: [f64; 8] = [
    0.0,
    TWO_POW_M60,
    1e-12,
    1e-6,
    0.5,
    1.0 - 1e-6,
    1.0 - 1e-12,
    1.0,
];

/// The 64 points `(u, v)` with `u, v ∈` [`EXTREMES`], `u`-major.
pub fn extremes_grid() -> Vec<(f64, f64)> {
    EXTREMES
        .iter()
        .flat_map(|&u| EXTREMES.iter().map(move |&v| (u, v)))
        .collect()
}

/// The `n × n` grid `(i/(n−1), j/(n−1))`, `i, j = 0 … n−1`, edges included,
/// `u`-major. `n = 1` gives the centre `(1/2, 1/2)`; `n = 0` no points.
pub fn uniform_grid(n: usize) -> Vec<(f64, f64)> {
    let coord = |i: usize| -> f64 {
        if n == 1 {
            0.5
        } else {
            i as f64 / (n - 1) as f64
        }
    };
    (0..n)
        .flat_map(|i| (0..n).map(move |j| (coord(i), coord(j))))
        .collect()
}

/// `n` pseudo-random points, uniform in `[0, 1)²`, deterministic for a given
/// `seed` on every platform (xoshiro256++ seeded by
/// [`SeedableRng::seed_from_u64`], 53-bit floats).
pub fn random_points(n: usize, seed: u64) -> Vec<(f64, f64)> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..n)
        .map(|_| (rng.random::<f64>(), rng.random::<f64>()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extremes_are_sorted_and_in_unit_interval() {
        assert_eq!(EXTREMES[1], 2f64.powi(-60));
        assert!(EXTREMES.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(EXTREMES[0], 0.0);
        assert_eq!(EXTREMES[7], 1.0);
    }

    #[test]
    fn extremes_grid_is_the_product() {
        let g = extremes_grid();
        assert_eq!(g.len(), 64);
        assert_eq!(g[0], (0.0, 0.0));
        assert_eq!(g[1], (0.0, TWO_POW_M60));
        assert_eq!(g[63], (1.0, 1.0));
        for &u in &EXTREMES {
            for &v in &EXTREMES {
                assert!(g.contains(&(u, v)));
            }
        }
    }

    #[test]
    fn uniform_grid_includes_edges() {
        let g = uniform_grid(5);
        assert_eq!(g.len(), 25);
        assert_eq!(g[0], (0.0, 0.0));
        assert_eq!(g[4], (0.0, 1.0));
        assert_eq!(g[24], (1.0, 1.0));
        assert_eq!(g[12], (0.5, 0.5));
        assert_eq!(uniform_grid(1), vec![(0.5, 0.5)]);
        assert!(uniform_grid(0).is_empty());
    }

    #[test]
    fn random_points_are_deterministic_and_in_range() {
        let a = random_points(100, 7);
        let b = random_points(100, 7);
        let c = random_points(100, 8);
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert!(
            a.iter()
                .all(|&(u, v)| (0.0..1.0).contains(&u) && (0.0..1.0).contains(&v))
        );
    }
}
