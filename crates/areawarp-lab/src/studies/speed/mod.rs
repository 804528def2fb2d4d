//! Study 2, *speed–accuracy*: what each warp configuration costs per
//! sample against how accurate it is, for every warp × variant × scalar
//! type {`f32`, `f64`, `mpfr:128`, `mpfr:256`} and, for the projected
//! polygon, every marginal inversion setting (cubic only, cubic + 1/2/3
//! Newton steps, Newton to convergence).
//!
//! - **Time**: ns per sample of the map on the warp's first catalogue
//!   shape (an ordinary one), over a batch of random `(u, v)` in the
//!   scalar, repeated ([`SpeedConfig::repetitions`]); the median and the
//!   spread (min, max, interquartile range) of the runs. Twice: with the
//!   shape built once (*map*), and rebuilt from its `f64` data for every
//!   sample (*build + map*: the cost when every shading point sees a new
//!   shape, as for a light seen from a new receiver). MPFR is timed on
//!   fewer samples. `std::time::Instant` around batches, inputs and
//!   outputs through [`std::hint::black_box`]; the timings run one at a
//!   time on the calling thread.
//! - **Error**: the max over the extremes grid plus random points of
//!   `‖ψ_T(u, v) − ψ_exact(u, v)‖_∞ / extent` (absolute, so that scalars
//!   compare), `ψ_exact` the exact map (robust variant, Newton inversion) of
//!   the shape as `T` sees it at 512 bits; over *all* the warp's shapes
//!   (the ladders included) and, separately, on the timed shape.
//! - **Pareto**: per warp, the configurations not dominated in (median
//!   map time, max error); a log-log plot.
//! - **Recommendations**: per warp, the fastest `f64` configuration whose
//!   max error is within a factor 4 of the best `f64` error and that never
//!   returns NaN/∞, with the measured numbers that justify it
//!   ([`SpeedStudy::recommendations`]).
//!
//! Timings vary from run to run and machine to machine: compare within a
//! table. Errors are deterministic.

use super::precision::{Built, ShapeEntry, StudyWarp, WARPS, catalogue, fmt_num, slug, with_warp};
use crate::figures::{Axis, Figure, Plot, Series, write_line_plot_svg};
use crate::jobs::run_jobs;
use areawarp::error::WarpError;
use areawarp::harness::extremes::{extremes_grid, random_points};
use areawarp::real::{Mpfr, Mpfr128, Mpfr256, Real};
use areawarp::vector::{Coords, Vec3};
use areawarp::warp::{Warp, WarpFamily};
use std::fmt::Write as _;
use std::hint::black_box;
use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;
/// The reference scalar of the error measurements.
type R = Mpfr<512>;
mod measure;
mod output;
mod pareto;

#[cfg(test)]
mod tests;
use self::measure::*;
use self::pareto::*;

/// The scalar types of the study, in table order.
pub const SCALARS: [&str; 4] = ["f32", "f64", "mpfr:128", "mpfr:256"];

/// The speed–accuracy study's size.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedConfig {
    /// Seed of the timing inputs and of the error points.
    pub seed: u64,
    /// Samples per timing run for `f32` and `f64` (shape built once).
    pub batch: usize,
    /// Samples per timing run for `f32` and `f64` when the shape is rebuilt
    /// for every sample.
    pub build_batch: usize,
    /// Samples per timing run for MPFR (both modes).
    pub mpfr_batch: usize,
    /// Timing runs per configuration and mode for `f32`, `f64` (at least 1;
    /// one more untimed run warms up).
    pub repetitions: usize,
    /// Timing runs for MPFR.
    pub mpfr_repetitions: usize,
    /// Random points added to the extremes grid for the error.
    pub error_random_points: usize,
    /// At most this many shapes per warp for the error (`None`: all).
    pub max_shapes: Option<usize>,
}

impl SpeedConfig {
    /// The tests' size (well under a second of timing): small batches,
    /// 3 runs, the extremes grid plus 2 random points on up to 4 shapes per
    /// warp (the ordinary ones of the solid-angle maps).
    pub fn quick() -> Self {
        SpeedConfig {
            seed: 0x5EED_0002,
            batch: 256,
            build_batch: 64,
            mpfr_batch: 4,
            repetitions: 3,
            mpfr_repetitions: 2,
            error_random_points: 2,
            max_shapes: Some(4),
        }
    }
}

impl Default for SpeedConfig {
    /// The report's size: 4096 samples × 21 runs (`f32`, `f64`; 1024 with
    /// construction), 64 samples × 7 runs (MPFR); the error on every shape
    /// of every ladder, extremes grid plus 64 random points.
    fn default() -> Self {
        SpeedConfig {
            batch: 4096,
            build_batch: 1024,
            mpfr_batch: 64,
            repetitions: 21,
            mpfr_repetitions: 7,
            error_random_points: 64,
            max_shapes: None,
            ..Self::quick()
        }
    }
}

impl SpeedConfig {
    fn validate(&self) -> Result<(), WarpError> {
        if self.batch == 0
            || self.build_batch == 0
            || self.mpfr_batch == 0
            || self.repetitions == 0
            || self.mpfr_repetitions == 0
            || self.max_shapes == Some(0)
        {
            return Err(WarpError::InvalidParameter {
                name: "SpeedConfig",
                expected: "positive batches, repetitions and max_shapes",
            });
        }
        Ok(())
    }
}

/// Repeated timing runs: ns per sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    /// Median over the runs.
    pub median: f64,
    /// Fastest run.
    pub min: f64,
    /// Slowest run.
    pub max: f64,
    /// First quartile.
    pub q1: f64,
    /// Third quartile.
    pub q3: f64,
    /// Number of runs.
    pub runs: usize,
    /// Samples per run.
    pub samples: usize,
}

impl Timing {
    pub(crate) fn of(mut ns: Vec<f64>, samples: usize) -> Timing {
        ns.sort_by(f64::total_cmp);
        let q = |p: f64| -> f64 {
            // Linear interpolation between order statistics.
            let x = p * (ns.len() - 1) as f64;
            let (i, f) = (x.floor() as usize, x - x.floor());
            if i + 1 < ns.len() {
                ns[i] + f * (ns[i + 1] - ns[i])
            } else {
                ns[i]
            }
        };
        Timing {
            median: q(0.5),
            min: ns[0],
            max: ns[ns.len() - 1],
            q1: q(0.25),
            q3: q(0.75),
            runs: ns.len(),
            samples,
        }
    }
}

/// One warp × variant × scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedRow {
    /// The warp.
    pub warp: String,
    /// The variant (inversion setting for the projected polygon).
    pub variant: String,
    /// The scalar type.
    pub scalar: String,
    /// The shape the timings use.
    pub timed_shape: String,
    /// ns per sample, shape built once.
    pub map: Timing,
    /// ns per sample, shape rebuilt (from its `f64` data) for every sample.
    pub build_and_map: Timing,
    /// Max error (distance over extent, against the exact map at 512 bits)
    /// over all the warp's shapes and points.
    pub max_error: f64,
    /// The shape of that max.
    pub worst_shape: String,
    /// Max error on the timed shape.
    pub timed_shape_error: f64,
    /// `max_error` in units of the scalar's roundoff `2^-p`.
    pub max_error_ulps: f64,
    /// Shapes measured (accepted by the scalar).
    pub shapes: usize,
    /// Shapes the scalar's constructor rejects.
    pub rejected: usize,
    /// Points where the map returned NaN or ∞ (all shapes).
    pub non_finite: usize,
    /// Not dominated, within its warp, in (median map time, max error).
    pub pareto: bool,
}

/// The recommended default of one warp.
#[derive(Clone, Debug, PartialEq)]
pub struct Recommendation {
    /// The warp.
    pub warp: String,
    /// The recommended variant.
    pub variant: String,
    /// The recommended scalar.
    pub scalar: String,
    /// Its median ns per sample (shape built once).
    pub ns_per_sample: f64,
    /// Its median ns per sample with the shape rebuilt for every sample.
    pub ns_with_construction: f64,
    /// Its max error over all the warp's shapes.
    pub max_error: f64,
    /// The measurements that justify it, against the alternatives.
    pub reason: String,
}

/// The results of the speed–accuracy study.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedStudy {
    /// The configuration it ran with.
    pub config: SpeedConfig,
    /// Error points per shape.
    pub points_per_shape: usize,
    /// Every warp × variant × scalar, warps in [`WARPS`] order.
    pub rows: Vec<SpeedRow>,
    recommendations: Vec<Recommendation>,
}
/// Runs the study: the errors in parallel ([`run_jobs`] on rayon's current
/// pool), then the timings one at a time on the calling thread.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for an invalid configuration; the
/// errors of building a catalogue shape (none for the shipped shapes).
pub fn run(config: &SpeedConfig) -> Result<SpeedStudy, WarpError> {
    config.validate()?;
    let shapes = catalogue(config.max_shapes, None)?;
    let mut points = extremes_grid();
    points.extend(random_points(config.error_random_points, config.seed));

    // Errors: one job per shape × scalar.
    let jobs = shapes.len() * SCALARS.len();
    let errors = run_jobs(jobs, config.seed, |i, _rng| {
        let e = &shapes[i / SCALARS.len()];
        match i % SCALARS.len() {
            0 => shape_errors::<f32>(e, &points),
            1 => shape_errors::<f64>(e, &points),
            2 => shape_errors::<Mpfr128>(e, &points),
            _ => shape_errors::<Mpfr256>(e, &points),
        }
    })
    .into_iter()
    .collect::<Result<Vec<_>, _>>()?;

    let mut rows = Vec::new();
    for warp in WARPS {
        let mine: Vec<usize> = (0..shapes.len())
            .filter(|&k| shapes[k].warp == warp)
            .collect();
        let Some(&first) = mine.first() else { continue };
        let timed = &shapes[first];
        for (j, (variant, built)) in timed.variants.iter().enumerate() {
            for (si, scalar) in SCALARS.iter().enumerate() {
                let (map, build_and_map) = match si {
                    0 => with_warp!(built, |w| timings::<f32, _>(w, config)),
                    1 => with_warp!(built, |w| timings::<f64, _>(w, config)),
                    2 => with_warp!(built, |w| timings::<Mpfr128, _>(w, config)),
                    _ => with_warp!(built, |w| timings::<Mpfr256, _>(w, config)),
                }?;
                let p = [24, 53, 128, 256][si];
                let mut row = SpeedRow {
                    warp: warp.to_string(),
                    variant: variant.to_string(),
                    scalar: scalar.to_string(),
                    timed_shape: timed.shape.clone(),
                    map,
                    build_and_map,
                    max_error: 0.0,
                    worst_shape: String::new(),
                    timed_shape_error: 0.0,
                    max_error_ulps: 0.0,
                    shapes: 0,
                    rejected: 0,
                    non_finite: 0,
                    pareto: false,
                };
                for &k in &mine {
                    let c = &errors[k * SCALARS.len() + si][j];
                    if c.rejected {
                        row.rejected += 1;
                        continue;
                    }
                    row.shapes += 1;
                    row.non_finite += c.non_finite;
                    if k == first {
                        row.timed_shape_error = c.max_error;
                    }
                    if row.worst_shape.is_empty() || c.max_error > row.max_error {
                        row.max_error = c.max_error;
                        row.worst_shape = shapes[k].shape.clone();
                    }
                }
                row.max_error_ulps = row.max_error / 2f64.powi(-p);
                rows.push(row);
            }
        }
    }
    mark_pareto(&mut rows);
    let recommendations = recommend(&rows);
    Ok(SpeedStudy {
        config: config.clone(),
        points_per_shape: points.len(),
        rows,
        recommendations,
    })
}
