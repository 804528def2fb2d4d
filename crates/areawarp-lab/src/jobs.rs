//! Parallel runs of independent estimator jobs: [`run_jobs`] spreads
//! `areawarp`'s reproducible job streams ([`job_rng`]) over rayon's thread
//! pool, with results bit-identical to [`run_jobs_sequential`] for any
//! thread count.

pub use areawarp::estimate::{job_rng, job_seed, run_jobs_sequential};
use rand::rngs::Xoshiro256PlusPlus;

/// Runs `job(i, rng_i)` for `i = 0 … jobs − 1`, in parallel on rayon's
/// current thread pool each
/// job with its own stream `rng_i = job_rng(seed, i)`; results in job order.
///
/// The result is bit-identical for any number of threads, and to
/// [`run_jobs_sequential`], as long as each job depends only on its index,
/// its stream and shared read-only data: reduce the returned vector in
/// order (e.g. [`Stats::merge`](areawarp::estimate::Stats::merge) from the first job
/// to the last), never in completion order. Use
/// `rayon::ThreadPoolBuilder::new().num_threads(t).build()?.install(|| …)`
/// to choose the thread count.
///
/// # Example
/// ```
/// use areawarp::estimate::{Stats, run_jobs_sequential};
/// use areawarp_lab::jobs::run_jobs;
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
pub fn run_jobs<R, F>(jobs: usize, seed: u64, job: F) -> Vec<R>
where
    R: Send,
    F: Fn(usize, &mut Xoshiro256PlusPlus) -> R + Sync,
{
    use rayon::prelude::*;
    let tracker = crate::progress::Tracker::new(jobs);
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
