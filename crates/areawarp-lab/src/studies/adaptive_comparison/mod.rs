//! Ureña (2000, §5): adaptive sampling of a triangle light against
//! stratified solid-angle sampling, at equal sample count, on a patterned
//! triangle light seen through occluders. A section of the variance study
//! ([`VarianceStudy::attach`](super::variance::VarianceStudy::attach)),
//! measured on the same engine ([`measure`]).
//!
//! # The experiment
//! The scene is [`setup::patterned_triangle`]: a vertical one-sided
//! triangle light with a checkerboard radiance pattern, a 3 × 2 array of
//! opaque horizontal squares between it and the ground, and a grid of
//! receivers on the ground. At each receiver the irradiance
//! `E = ∫ L V cos⁺θ dω` is estimated with `n` samples (*spp*) by
//!
//! | method | density (solid angle) | points |
//! |---|---|---|
//! | `stratified solid angle` | `1/σ`: Arvo's spherical-triangle map | jittered, `n_x × n_y` strata (6 × 6 at 36 spp, as the paper's Fig. 9) |
//! | `stratified cosine-weighted` | `cos θ/σ⊥`: the projected polygon (Arvo 2001) | jittered |
//! | `random cosine-weighted` | `cos θ/σ⊥` | independent uniform points: the ideal density `U₀` of Ureña's §3, unstratified |
//! | `adaptive K=…` ([`AdaptiveEstimator`]) | Ureña's adaptive density, `→ cos θ/σ⊥` as `K → 0` | its own: the recursive allocation of §4.1, random within each piece |
//!
//! with `K = ∞` (no split: unstratified solid-angle sampling, the paper's
//! first image of Fig. 9), `K = 0.1` and `K = 0.001` (the paper's values in
//! Fig. 7 and 9). All methods spend `n` samples (rays) per estimate.
//!
//! # Cost
//! [`AdaptiveComparisonConfig::cost`] times one whole estimate of every
//! method at every receiver and sample count (thread CPU time, cold: the
//! per-receiver work — for adaptive sampling the partition it builds —
//! included), for the efficiency `1/(RMS² · time)` relative to stratified
//! solid-angle sampling and Ureña's claims about cost (§5, last
//! paragraph); see [`AdaptiveComparison::equal_time_cell`] and
//! [`AdaptiveComparison::break_even_ns`].
//!
//! # References
//! The irradiance of the *unoccluded* patterned light is exact (Lambert's
//! formula per pattern cell, [`lambert::irradiance`]). The occluded part
//! `B = ∫ L (1 − V) cos⁺θ dω` is estimated with jittered solid-angle
//! samples (Arvo's map), whose estimator `σ L (1 − V) cos θ` is bounded,
//! in [`ReferenceConfig::replicas`] independent replicas of `side²`
//! samples; the reference is `E = E_free − B̂`, with the standard
//! error of `B̂` from the replicas' spread. Receivers that no occluder can
//! shadow (no occluder between them and the light's plane) have `B = 0`
//! exactly. The report states the references' largest relative standard
//! error next to the smallest RMS error it judges.
//!
//! # Randomness and determinism
//! The jittered methods use the engine's points; the adaptive sampler and
//! the random cosine-weighted method draw their own points from an rng
//! seeded with [`Batch::seed`] (derived from the job's stream by the
//! engine). Everything is a [`run_jobs`] job
//! with its own seed: the results are identical for any thread count.
//!
//! # Example
//! ```
//! use areawarp_lab::studies::adaptive_comparison::{
//!     AdaptiveComparisonConfig, ReferenceConfig, run,
//! };
//!
//! let mut config = AdaptiveComparisonConfig::quick();
//! config.receivers_per_side = 2;
//! config.spp = vec![4, 16];
//! config.runs = 2;
//! config.reference = ReferenceConfig { replicas: 2, side: 16 };
//! let section = run(&config)?;
//! assert!(section.markdown.contains("adaptive K=0.001"));
//! assert!(!section.claims.is_empty());
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use super::variance::{
    Batch, Claim, ExtraSection, MeasureSpec, Measurement, Method, PointSet, PreparedEstimator,
    ReceiverEstimator, Sampler, Subset, Verdict, measure,
};
use crate::jobs::run_jobs;
use crate::scene::setup::{self, Setup};
use crate::scene::{Quantity, Receiver, Scene, lambert, strategies};
use areawarp::adaptive::{AdaptiveTriangle, Allocation, SampleSet};
use areawarp::error::WarpError;
use areawarp::estimate::Strategy;
use areawarp::estimate::{Stats, job_rng};
use areawarp::sampling::jittered_iter;
use rand::RngExt;
use std::fmt::Write as _;
use std::time::Instant;

mod cost;
mod estimators;
mod output;
pub use self::cost::{AdaptiveCost, COST_BASELINE, CostConfig, EqualTimeCell};
pub use self::estimators::*;

#[cfg(test)]
mod tests;
// ---------------------------------------------------------------------------
// The comparison
// ---------------------------------------------------------------------------

/// The size and contents of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveComparisonConfig {
    /// Seed of the runs (the references use a seed derived from it).
    pub seed: u64,
    /// Pattern cells per side ([`setup::patterned_triangle`]).
    pub cells: usize,
    /// The pattern's high radiance.
    pub high: f64,
    /// Its low radiance.
    pub low: f64,
    /// Receivers per side of the grid.
    pub receivers_per_side: usize,
    /// Samples per receiver, increasing.
    pub spp: Vec<usize>,
    /// Independent runs per receiver.
    pub runs: usize,
    /// The thresholds `K` of the adaptive methods (`f64::INFINITY`:
    /// unstratified solid-angle sampling).
    pub thresholds: Vec<f64>,
    /// The adaptive allocation rule.
    pub allocation: Allocation,
    /// The references.
    pub reference: ReferenceConfig,
    /// Receivers at most this far from the light form the near subset.
    pub near_light: f64,
    /// Levels (the last ones) of the power-law fits.
    pub fit_levels: usize,
    /// Keep the 3 × 2 occluding squares. Ureña's Fig. 9 shows the
    /// irradiance "with the occluders removed": `false` is the paper's
    /// setup, `true` our extension (visibility discontinuities inside the
    /// light).
    pub occluders: bool,
    /// The equal-time measurement (CPU time per estimate of every
    /// method); `None` skips it.
    pub cost: Option<CostConfig>,
}

impl Default for AdaptiveComparisonConfig {
    /// The report's size: a 5 × 5 pattern (radiances 1 and 0.1), 7 × 7
    /// receivers, spp 4, 16, 36, 64, 256, 1024, 16 runs, K = ∞, 0.1, 0.001,
    /// references from 8 × 192² solid-angle samples; near the light =
    /// within 0.5. About 30 s on 2 cores in `--release` (adaptive
    /// sampling with K = 0.001 takes two thirds of it, the references 3 s).
    fn default() -> Self {
        AdaptiveComparisonConfig {
            seed: 0x5EED_2000,
            cells: 5,
            high: 1.0,
            low: 0.1,
            receivers_per_side: 7,
            spp: vec![4, 16, 36, 64, 256, 1024],
            runs: 16,
            thresholds: vec![f64::INFINITY, 0.1, 0.001],
            allocation: Allocation::default(),
            reference: ReferenceConfig {
                replicas: 8,
                side: 192,
            },
            near_light: 0.5,
            fit_levels: 3,
            occluders: false,
            cost: Some(CostConfig::default()),
        }
    }
}

impl AdaptiveComparisonConfig {
    /// Our extension of the default: the occluders kept, spp up to 256
    /// (the run without occluders is the paper's; this one asks whether
    /// its findings survive visibility discontinuities).
    pub fn with_occluders() -> Self {
        AdaptiveComparisonConfig {
            spp: vec![4, 16, 36, 64, 256],
            occluders: true,
            ..Self::default()
        }
    }

    /// A small configuration for tests (about a second in the test
    /// profile): 3 × 3 receivers, spp up to 256, 4 runs, references from
    /// 8 × 96² samples.
    pub fn quick() -> Self {
        AdaptiveComparisonConfig {
            receivers_per_side: 3,
            spp: vec![4, 16, 36, 64, 256],
            runs: 4,
            reference: ReferenceConfig {
                replicas: 8,
                side: 96,
            },
            cost: Some(CostConfig::quick()),
            ..Self::default()
        }
    }
}

/// Partitions with more pieces than this are not counted
/// ([`PartitionCounts::over_limit`]): a walk over the whole partition costs
/// about 1.5 µs per piece, and `K = 0.001` has millions.
pub const PIECE_LIMIT: usize = 10_000;

/// The sizes of the adaptive partitions of one threshold at the receivers
/// ([`AdaptiveTriangle::piece_count`]): how many pieces the samples are
/// spread over, which decides when the allocation stops stratifying.
#[derive(Clone, Debug, PartialEq)]
pub struct PartitionCounts {
    /// The threshold K.
    pub k: f64,
    /// Pieces at each receiver whose partition has at most
    /// [`PIECE_LIMIT`] pieces, in receiver order.
    pub counts: Vec<usize>,
    /// Receivers whose partition has more than [`PIECE_LIMIT`] pieces.
    pub over_limit: usize,
}

impl PartitionCounts {
    /// The smallest and largest count (`None` if none was counted).
    pub fn range(&self) -> Option<(usize, usize)> {
        let lo = self.counts.iter().copied().min()?;
        let hi = self.counts.iter().copied().max()?;
        Some((lo, hi))
    }
}

/// The partition sizes for each finite threshold.
///
/// # Errors
/// As [`AdaptiveTriangle::from_points`].
fn partition_counts(setup: &Setup, thresholds: &[f64]) -> Result<Vec<PartitionCounts>, WarpError> {
    let v = setup.scene.emitter().polygon().vertices();
    if v.len() != 3 {
        return Ok(Vec::new());
    }
    let finite: Vec<f64> = thresholds
        .iter()
        .copied()
        .filter(|k| k.is_finite())
        .collect();
    let nr = setup.receivers.len();
    let counts = run_jobs(finite.len() * nr, 0, |i, _| {
        let (k, r) = (finite[i / nr], &setup.receivers[i % nr]);
        AdaptiveTriangle::from_points([&v[0], &v[1], &v[2]], r.position(), r.normal(), k)
            .map(|t| t.piece_count(PIECE_LIMIT))
    });
    finite
        .iter()
        .enumerate()
        .map(|(j, &k)| {
            let mut out = PartitionCounts {
                k,
                counts: Vec::new(),
                over_limit: 0,
            };
            for c in &counts[j * nr..(j + 1) * nr] {
                match c.as_ref().map_err(Clone::clone)? {
                    Some(n) => out.counts.push(*n),
                    None => out.over_limit += 1,
                }
            }
            Ok(out)
        })
        .collect()
}

/// The result of [`run_comparison`].
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveComparison {
    /// The configuration.
    pub config: AdaptiveComparisonConfig,
    /// The reference at each receiver.
    pub references: Vec<ReferenceValue>,
    /// The measurement: methods in the order `stratified solid angle`,
    /// `stratified cosine-weighted`, `random cosine-weighted`, then one
    /// `adaptive K=…` per threshold.
    pub measurement: Measurement,
    /// The sizes of the adaptive partitions, per finite threshold.
    pub partitions: Vec<PartitionCounts>,
    /// The CPU time per estimate of every method, if measured.
    pub cost: Option<AdaptiveCost>,
    /// Wall-clock seconds of the references (not part of the results'
    /// determinism).
    pub reference_seconds: f64,
    /// Wall-clock seconds of the whole run.
    pub elapsed_seconds: f64,
}

/// Runs the comparison.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for a threshold that is not `> 0`, and
/// as [`setup::patterned_triangle`], [`references`] and [`measure`].
pub fn run_comparison(config: &AdaptiveComparisonConfig) -> Result<AdaptiveComparison, WarpError> {
    let start = Instant::now();
    if config.thresholds.iter().any(|k| !(*k > 0.0)) {
        return Err(WarpError::InvalidParameter {
            name: "thresholds",
            expected: "thresholds K > 0",
        });
    }
    let mut setup = setup::patterned_triangle(
        config.cells,
        config.high,
        config.low,
        config.receivers_per_side,
    )?;
    if !config.occluders {
        setup.scene = crate::scene::Scene::new(setup.scene.emitter().clone());
    }
    let refs = references(
        &setup,
        &config.reference,
        areawarp::estimate::job_seed(config.seed, u64::MAX),
    )?;
    let reference_seconds = start.elapsed().as_secs_f64();
    let partitions = partition_counts(&setup, &config.thresholds)?;
    let values: Vec<f64> = refs.iter().map(|r| r.value).collect();

    let solid = Named {
        name: STRATIFIED_SOLID_ANGLE,
        // For a triangle light the "pair" is the one spherical triangle.
        method: Method::plain(Sampler::TrianglePair),
    };
    let cosine = Named {
        name: STRATIFIED_COSINE,
        method: Method::plain(Sampler::ProjectedPolygon),
    };
    let random_cosine = RandomPoints(Named {
        name: RANDOM_COSINE,
        method: Method::plain(Sampler::ProjectedPolygon),
    });
    let adaptive: Vec<AdaptiveEstimator> = config
        .thresholds
        .iter()
        .map(|&k| AdaptiveEstimator::new(k).with_allocation(config.allocation))
        .collect();
    let mut estimators: Vec<&dyn ReceiverEstimator> = vec![&solid, &cosine, &random_cosine];
    estimators.extend(adaptive.iter().map(|a| a as &dyn ReceiverEstimator));
    let spec = MeasureSpec {
        setup: &setup,
        references: &values,
        estimators: &estimators,
        point_sets: &[PointSet::Jittered],
        spp: &config.spp,
        runs: config.runs,
        seed: config.seed,
        near_light: config.near_light,
    };
    let measurement = measure(&spec, config.fit_levels)?;
    // The jittered methods consume the engine's points; the others draw
    // their own inside the estimate.
    let mut uses_points = vec![true, true, false];
    uses_points.resize(estimators.len(), false);
    let cost = config
        .cost
        .as_ref()
        .map(|c| cost::measure_cost(&setup, &estimators, &uses_points, &config.spp, c));
    Ok(AdaptiveComparison {
        config: config.clone(),
        references: refs,
        measurement,
        partitions,
        cost,
        reference_seconds,
        elapsed_seconds: start.elapsed().as_secs_f64(),
    })
}

/// Runs the comparison and returns it as a section of the variance study
/// (title "Adaptive vs stratified (Ureña 2000)", slug `adaptive`: its
/// curves are written as `variance_adaptive_curves.csv` and
/// `variance_adaptive.svg`).
///
/// # Errors
/// As [`run_comparison`].
pub fn run(config: &AdaptiveComparisonConfig) -> Result<ExtraSection, WarpError> {
    Ok(run_comparison(config)?.section())
}

/// Formats an error value.
fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3e}")
    } else {
        "–".to_string()
    }
}

/// The paper's sample count in Fig. 9.
const PAPER_SPP: usize = 36;

/// Ureña's report.
const SOURCE: &str = "Ureña 2000, §5 / Fig. 9";
