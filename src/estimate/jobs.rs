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
/// nothing but `(seed, index)`, which is what makes [`run_jobs`]
/// independent of the thread count.
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

/// Runs `job(i, rng_i)` for `i = 0 … jobs − 1`, in parallel on rayon's
/// current thread pool (feature `studies`; sequentially without it), each
/// job with its own stream `rng_i = job_rng(seed, i)`; results in job order.
///
/// The result is bit-identical for any number of threads, and to
/// [`run_jobs_sequential`], as long as each job depends only on its index,
/// its stream and shared read-only data: reduce the returned vector in
/// order (e.g. [`Stats::merge`](super::Stats::merge) from the first job
/// to the last), never in completion order. Use
/// `rayon::ThreadPoolBuilder::new().num_threads(t).build()?.install(|| …)`
/// to choose the thread count.
///
/// # Example
/// ```
/// use areawarp::estimate::{Stats, run_jobs, run_jobs_sequential};
/// use rand::RngExt;
/// let job = |_i: usize, rng: &mut rand::rngs::Xoshiro256PlusPlus| {
///     (0..100).map(|_| rng.random::<f64>()).collect::<Stats>()
/// };
/// let mut total = Stats::new();
/// for s in run_jobs(8, 42, job) {
///     total.merge(&s);
/// }
/// let mut again = Stats::new();
/// for s in run_jobs_sequential(8, 42, job) {
///     again.merge(&s);
/// }
/// assert_eq!(total, again);
/// assert!((total.mean() - 0.5).abs() < 0.05);
/// ```
#[cfg(feature = "studies")]
pub fn run_jobs<R, F>(jobs: usize, seed: u64, job: F) -> Vec<R>
where
    R: Send,
    F: Fn(usize, &mut Xoshiro256PlusPlus) -> R + Sync,
{
    use rayon::prelude::*;
    let tracker = super::progress::Tracker::new(jobs);
    (0..jobs)
        .into_par_iter()
        .map(|i| {
            let r = job(i, &mut job_rng(seed, i as u64));
            if let Some(t) = &tracker {
                t.tick();
            }
            r
        })
        .collect()
}

/// Runs `job(i, rng_i)` for `i = 0 … jobs − 1` with `rng_i =
/// job_rng(seed, i)`, results in job order; sequential because the
/// `studies` feature (rayon) is off. Same results as with it.
#[cfg(not(feature = "studies"))]
pub fn run_jobs<R, F>(jobs: usize, seed: u64, job: F) -> Vec<R>
where
    R: Send,
    F: Fn(usize, &mut Xoshiro256PlusPlus) -> R + Sync,
{
    run_jobs_sequential(jobs, seed, job)
}
