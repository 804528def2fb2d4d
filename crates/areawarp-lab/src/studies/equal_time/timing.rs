//! The cost side of the equal-time comparison: per-thread CPU time of each
//! method's whole estimator, in interleaved rounds.
//!
//! What is timed, per method and receiver: the estimator the variance study
//! runs ([`ReceiverEstimator::prepare`] then [`PreparedEstimator::estimate`]
//! on a batch of jittered points), i.e. per light sample the draw, the pdf,
//! the irradiance integrand (ray–light test, radiance, cosine, and the
//! visibility tests against the scene's occluders) and, for MIS, the cosine
//! sample with its integrand and every pdf the balance weights need.
//! Construction (the strategies built at the receiver) is timed separately
//! and charged once per receiver. Point generation is not timed.
//!
//! Robustness on a shared machine: the clock is the thread's CPU time
//! ([`crate::timing::thread_cpu_ns`]), the methods are interleaved within
//! every round (rotating which goes first), one untimed round warms up, and
//! the cost used is the minimum over rounds (the least disturbed; load only
//! adds time), with the median, quartiles and per-round ratios to the
//! baseline reported as the spread.

use crate::estimator::{Batch, Method, PointSet, PreparedEstimator, ReceiverEstimator};
use crate::scene::{Receiver, Scene};
use crate::studies::speed::Timing;
use crate::timing::thread_cpu_ns;
use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;
use std::hint::black_box;

/// One method's measured cost.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodCost {
    /// The method's name.
    pub method: String,
    /// CPU ns per light sample of the estimator, over rounds.
    pub per_sample: Timing,
    /// CPU ns per receiver of the construction, over rounds.
    pub construction: Timing,
    /// Per round: (CPU ns per light sample, CPU ns per construction), in
    /// round order (the rounds of all methods interleave).
    pub rounds: Vec<(f64, f64)>,
    /// Receivers at which the method could not be prepared (not timed).
    pub skipped: usize,
}

impl MethodCost {
    /// CPU µs per receiver at `spp` light samples: construction plus `spp`
    /// samples, from the minima over rounds.
    pub fn micros_per_receiver(&self, spp: usize) -> f64 {
        (self.construction.min + spp as f64 * self.per_sample.min) * 1e-3
    }

    /// The time per receiver at `spp` over `base`'s, per round (same round,
    /// so that load drifting between rounds affects both alike): the
    /// median over rounds, and the standard error of the log-ratio's mean
    /// (the spread of the per-round log-ratios over √rounds).
    pub fn ratio_to(&self, base: &MethodCost, spp: usize) -> (f64, f64) {
        let n = spp as f64;
        ratio_spread(
            self.rounds
                .iter()
                .zip(&base.rounds)
                .map(|(a, b)| (a.1 + n * a.0) / (b.1 + n * b.0)),
        )
    }
}

/// The median of per-round time ratios and the standard error of the mean
/// of their logs (their spread over √rounds); non-positive or non-finite
/// ratios are dropped (NaN if none is left, NaN error for one).
pub fn ratio_spread(ratios: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut r: Vec<f64> = ratios.filter(|x| *x > 0.0 && x.is_finite()).collect();
    if r.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    r.sort_by(f64::total_cmp);
    let k = r.len();
    let median = if k % 2 == 1 {
        r[k / 2]
    } else {
        (r[k / 2 - 1] + r[k / 2]) / 2.0
    };
    if k < 2 {
        return (median, f64::NAN);
    }
    let logs: Vec<f64> = r.iter().map(|x| x.ln()).collect();
    let mean = logs.iter().sum::<f64>() / k as f64;
    let var = logs.iter().map(|l| (l - mean) * (l - mean)).sum::<f64>() / (k - 1) as f64;
    (median, (var / k as f64).sqrt())
}

/// Times `methods` at `receivers` of `scene`: `batch` light samples per
/// receiver, `rounds` timed rounds (at least one) after one untimed
/// warm-up round.
/// Single-threaded (call it outside rayon's pool work).
pub fn time_methods(
    scene: &Scene,
    receivers: &[Receiver],
    methods: &[Method],
    batch: usize,
    rounds: usize,
    seed: u64,
) -> Vec<MethodCost> {
    let nm = methods.len();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let (mut light, mut partner) = (Vec::new(), Vec::new());
    PointSet::Jittered.fill(batch.max(1), &mut rng, &mut light);
    PointSet::Jittered.fill(batch.max(1), &mut rng, &mut partner);
    let points = Batch {
        light: &light,
        partner: &partner,
        point_set: PointSet::Jittered,
        seed,
    };
    let mut prepared: Vec<Vec<Box<dyn PreparedEstimator + '_>>> = Vec::with_capacity(nm);
    let mut skipped = vec![0; nm];
    for (i, m) in methods.iter().enumerate() {
        let mut row = Vec::with_capacity(receivers.len());
        for r in receivers {
            match m.prepare(scene, r) {
                Ok(p) => row.push(p),
                Err(_) => skipped[i] += 1,
            }
        }
        prepared.push(row);
    }
    // [method][round]
    let mut sample_ns = vec![Vec::with_capacity(rounds); nm];
    let mut build_ns = vec![Vec::with_capacity(rounds); nm];
    let rounds = rounds.max(1);
    for round in 0..=rounds {
        for k in 0..nm {
            let i = (k + round) % nm;
            let t = thread_cpu_ns();
            for r in receivers {
                if let Ok(p) = methods[i].prepare(black_box(scene), black_box(r)) {
                    black_box(&p);
                }
            }
            let build = thread_cpu_ns().saturating_sub(t) as f64;
            let t = thread_cpu_ns();
            let mut acc = 0.0;
            for p in prepared[i].iter_mut() {
                if let Ok(v) = p.estimate(black_box(&points)) {
                    acc += v;
                }
            }
            black_box(acc);
            let sample = thread_cpu_ns().saturating_sub(t) as f64;
            if round > 0 {
                let done = prepared[i].len().max(1) as f64;
                sample_ns[i].push(sample / (done * batch.max(1) as f64));
                build_ns[i].push(build / receivers.len().max(1) as f64);
            }
        }
    }
    (0..nm)
        .map(|i| MethodCost {
            method: methods[i].name(),
            per_sample: Timing::of(sample_ns[i].clone(), batch * prepared[i].len()),
            construction: Timing::of(build_ns[i].clone(), receivers.len()),
            rounds: sample_ns[i]
                .iter()
                .copied()
                .zip(build_ns[i].iter().copied())
                .collect(),
            skipped: skipped[i],
        })
        .collect()
}

/// One estimator's cost per estimate at each sample count, measured cold
/// ([`time_estimates`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EstimateCost {
    /// The estimator's name.
    pub method: String,
    /// The sample counts timed.
    pub spp: Vec<usize>,
    /// Per sample count: CPU ns per estimate (mean over the receivers of
    /// one round), over rounds.
    pub per_estimate: Vec<Timing>,
    /// Per sample count, per round: CPU ns per estimate, in round order
    /// (the rounds of all estimators interleave).
    pub rounds: Vec<Vec<f64>>,
    /// Receivers at which the estimator could not be prepared (timed up
    /// to the failure, not counted in the mean).
    pub skipped: usize,
}

impl EstimateCost {
    /// CPU µs per estimate at level `l` (the minimum over rounds).
    pub fn micros(&self, l: usize) -> f64 {
        self.per_estimate.get(l).map_or(f64::NAN, |t| t.min * 1e-3)
    }

    /// The time per estimate at level `l` over `base`'s: the median of the
    /// per-round ratios and the standard error of their log
    /// ([`ratio_spread`]).
    pub fn ratio_to(&self, base: &EstimateCost, l: usize) -> (f64, f64) {
        match (self.rounds.get(l), base.rounds.get(l)) {
            (Some(a), Some(b)) => ratio_spread(a.iter().zip(b).map(|(x, y)| x / y)),
            _ => (f64::NAN, f64::NAN),
        }
    }
}

/// Times whole estimates of `estimators` at `receivers` of `scene`, *cold*:
/// per receiver and sample count `n`, the estimator is prepared anew and
/// one `n`-sample estimate made, so that all its per-receiver work (for
/// adaptive sampling, the partition it builds and memoizes while placing
/// the samples) is charged to that one estimate, as in a renderer that
/// makes one estimate per pixel. For the estimators flagged in
/// `uses_points`, generating their `n` jittered points is timed too
/// (estimators that draw their own points do it inside their estimate).
/// The partner points (used by MIS only) are generated untimed.
///
/// `rounds` timed rounds (at least one) follow one untimed warm-up round;
/// within a round, each sample count times every estimator in turn,
/// rotating which goes first. Single-threaded (call it outside rayon's
/// pool work).
///
/// # Panics
/// If `uses_points` and `estimators` differ in length.
pub fn time_estimates(
    scene: &Scene,
    receivers: &[Receiver],
    estimators: &[&dyn ReceiverEstimator],
    uses_points: &[bool],
    spp: &[usize],
    rounds: usize,
    seed: u64,
) -> Vec<EstimateCost> {
    assert_eq!(estimators.len(), uses_points.len());
    let nm = estimators.len();
    let rounds = rounds.max(1);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let max_n = spp.iter().copied().max().unwrap_or(1).max(1);
    let (mut light, mut partner) = (Vec::with_capacity(max_n), Vec::with_capacity(max_n));
    let mut skipped = vec![0; nm];
    // [method][level][round]
    let mut ns = vec![vec![Vec::with_capacity(rounds); spp.len()]; nm];
    for round in 0..=rounds {
        for (l, &n) in spp.iter().enumerate() {
            let n = n.max(1);
            PointSet::Jittered.fill(n, &mut rng, &mut partner);
            for k in 0..nm {
                let i = (k + round + l) % nm;
                let (mut done, mut acc) = (0usize, 0.0);
                let t = thread_cpu_ns();
                for (j, r) in receivers.iter().enumerate() {
                    if uses_points[i] {
                        PointSet::Jittered.fill(n, &mut rng, &mut light);
                    }
                    let batch = Batch {
                        light: if uses_points[i] { &light } else { &partner },
                        partner: &partner,
                        point_set: PointSet::Jittered,
                        seed: areawarp::estimate::job_seed(
                            seed,
                            (round * spp.len() + l) as u64 * 1_000_003 + j as u64,
                        ),
                    };
                    match estimators[i].prepare(black_box(scene), black_box(r)) {
                        Ok(mut p) => {
                            if let Ok(v) = p.estimate(black_box(&batch)) {
                                acc += v;
                            }
                            done += 1;
                        }
                        Err(_) => {
                            if round == 0 && l == 0 {
                                skipped[i] += 1;
                            }
                        }
                    }
                }
                black_box(acc);
                let elapsed = thread_cpu_ns().saturating_sub(t) as f64;
                if round > 0 {
                    ns[i][l].push(elapsed / done.max(1) as f64);
                }
            }
        }
    }
    (0..nm)
        .map(|i| EstimateCost {
            method: estimators[i].name(),
            spp: spp.to_vec(),
            per_estimate: ns[i]
                .iter()
                .map(|v| Timing::of(v.clone(), receivers.len()))
                .collect(),
            rounds: ns[i].clone(),
            skipped: skipped[i],
        })
        .collect()
}
