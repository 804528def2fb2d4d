//! Quasi-Monte Carlo through area-preserving maps: the crate's point sets
//! (`areawarp::sampling`) drive two warps, and the integration error of
//! each set is compared at equal sample counts.
//!
//! ```text
//! cargo run --release -p areawarp --example qmc_point_sets
//! ```
//!
//! Because a warp has a constant Jacobian, the estimate `(1/N) Σ f(ψ(uᵢ))`
//! of the mean of `f` over the shape is exactly the equal-weight cubature
//! of `f∘ψ` over the square: whatever makes a point set good on the square
//! (one point per stratum, low discrepancy) carries over to the shape.
//!
//! Two integrands with closed-form means:
//! - the uniform sphere about a tilted axis, `f = e^z`: mean `sinh 1`
//!   (`(1/2)∫₋₁¹ e^z dz`, Archimedes);
//! - the cosine-weighted hemisphere (`PhongLobe` with k = 1), `L = e^x`:
//!   mean `2 I₁(1)` (`(1/π)∫ e^x cos θ dω = 2∫₀¹ r I₀(r) dr`).
//!
//! Randomized sets (independent, jittered, Owen-scrambled Sobol) report the
//! RMS error over 32 randomizations; deterministic ones (Hammersley, plain
//! Sobol) their one error. Expect roughly N^(-1/2) for independent points,
//! N^(-1) or better for the stratified and low-discrepancy sets on these
//! smooth integrands.

use areawarp::sampling::{Sobol2, WarpSampler, hammersley, jittered};
use areawarp::shapes::{PhongLobe, Sphere};
use areawarp::{Vec3, Warp};
use rand::SeedableRng;
use rand::distr::{Distribution, StandardUniform};
use rand::rngs::Xoshiro256PlusPlus;

const RANDOMIZATIONS: u64 = 32;

/// The mean of `f` over `points` carried by `warp`.
fn estimate<W: Warp<f64, Point = Vec3<f64>>>(
    warp: &W,
    points: &[(f64, f64)],
    f: impl Fn(&Vec3<f64>) -> f64,
) -> f64 {
    points.iter().map(|(u, v)| f(&warp.map(u, v))).sum::<f64>() / points.len() as f64
}

/// RMS error over randomizations (`points(seed)` for seeds `0..reps`).
fn rms(reps: u64, exact: f64, mut trial: impl FnMut(u64) -> f64) -> f64 {
    let sum: f64 = (0..reps).map(|s| (trial(s) - exact).powi(2)).sum();
    (sum / reps as f64).sqrt()
}

/// One table: error of every point set at N = 4^k.
fn table<W: Warp<f64, Point = Vec3<f64>> + Clone>(
    title: &str,
    warp: &W,
    exact: f64,
    f: impl Fn(&Vec3<f64>) -> f64 + Copy,
) {
    println!("\n{title} (exact mean {exact:.12})");
    println!(
        "{:>6}  {:>11}  {:>11}  {:>11}  {:>11}  {:>11}",
        "N", "independent", "jittered", "Sobol+Owen", "Hammersley", "Sobol"
    );
    for k in 3..=6 {
        let side = 1usize << k; // N = side²
        let n = side * side;
        // Independent points, through `rand` (the warp as a distribution
        // would do the same: `WarpSampler`).
        let independent = rms(RANDOMIZATIONS, exact, |s| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(s);
            let pts: Vec<(f64, f64)> = (0..n)
                .map(|_| {
                    (
                        StandardUniform.sample(&mut rng),
                        StandardUniform.sample(&mut rng),
                    )
                })
                .collect();
            estimate(warp, &pts, f)
        });
        let jittered_err = rms(RANDOMIZATIONS, exact, |s| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(1000 + s);
            estimate(warp, &jittered(side, side, &mut rng), f)
        });
        let owen = rms(RANDOMIZATIONS, exact, |s| {
            let pts: Vec<(f64, f64)> = Sobol2::scrambled(s).take(n).collect();
            estimate(warp, &pts, f)
        });
        let hammersley_err = (estimate(warp, &hammersley(n), f) - exact).abs();
        let sobol: Vec<(f64, f64)> = Sobol2::new().take(n).collect();
        let sobol_err = (estimate(warp, &sobol, f) - exact).abs();
        println!(
            "{n:>6}  {independent:>11.3e}  {jittered_err:>11.3e}  {owen:>11.3e}  {hammersley_err:>11.3e}  {sobol_err:>11.3e}"
        );
    }
}

/// I₁(1) = Σ_k (1/2)^(2k+1) / (k! (k+1)!).
fn bessel_i1_at_1() -> f64 {
    let mut term = 0.5; // k = 0
    let mut sum = term;
    for k in 1..20 {
        term *= 0.25 / (k as f64 * (k + 1) as f64);
        sum += term;
    }
    sum
}

fn main() {
    // The sphere about a tilted axis, so that e^z depends on both u and v.
    let sphere = Sphere::<f64>::with_axis(Vec3::new(1.0, 2.0, 3.0)).expect("non-zero axis");
    table(
        "Uniform sphere (tilted axis), f = e^z",
        &sphere,
        1f64.sinh(),
        |p| p.z.exp(),
    );

    let cosine = PhongLobe::<f64>::new(1.0).expect("k = 1");
    table(
        "Cosine-weighted hemisphere, L = e^x",
        &cosine,
        2.0 * bessel_i1_at_1(),
        |p| p.x.exp(),
    );

    // The same warp as a `rand` distribution, for renderers that draw
    // independent samples.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let draws = WarpSampler::new(cosine);
    let mean_z: f64 = (0..4096).map(|_| draws.sample(&mut rng).z).sum::<f64>() / 4096.0;
    println!("\nWarpSampler (independent draws): mean cos θ = {mean_z:.4} (exact 2/3)");
}
