//! Independent estimator jobs with reproducible random streams.

use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;

/// The SplitMix64 output function (Steele, Lea and Flood 2014): a
/// bijective 64-bit mixer.
#[inline]
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of job `index` of a run seeded with `seed`:
/// `SplitMix64(seed ⊕ SplitMix64(index))`. Distinct indices give distinct
/// seeds for a fixed `seed` (both steps are bijections).
pub fn job_seed(seed: u64, index: u64) -> u64 {
    splitmix64(seed ^ splitmix64(index))
}

/// The random stream of job `index`: a Xoshiro256++ generator seeded with
/// [`job_seed`]`(seed, index)` (expanded by `seed_from_u64`). It depends on
/// nothing but `(seed, index)`, which is what makes a parallel run of
/// jobs independent of the thread count.
pub fn job_rng(seed: u64, index: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(job_seed(seed, index))
}

/// Runs `job(i, rng_i)` for `i = 0 … jobs − 1` on the current thread, each
/// with its own stream `rng_i = job_rng(seed, i)`; results in job order.
pub fn run_jobs_sequential<R, F>(jobs: usize, seed: u64, job: F) -> Vec<R>
where
    F: Fn(usize, &mut Xoshiro256PlusPlus) -> R,
{
    (0..jobs)
        .map(|i| job(i, &mut job_rng(seed, i as u64)))
        .collect()
}
