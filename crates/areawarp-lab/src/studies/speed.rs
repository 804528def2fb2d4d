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

/// The max error of one variant on one shape in one scalar.
#[derive(Clone, Debug)]
struct ErrorCell {
    rejected: bool,
    max_error: f64,
    non_finite: usize,
}

/// Max error of each variant of `e` in `T` against the exact map at 512
/// bits: each exact variant is its own reference (the sphere's two axes are
/// two maps), the others (literal, truncated inversions) share the
/// reference of the first, exact variant, evaluated once per point.
fn shape_errors<T: Real>(
    e: &ShapeEntry,
    points: &[(f64, f64)],
) -> Result<Vec<ErrorCell>, WarpError> {
    type Reference = Option<(Vec<Option<Vec3<R>>>, R)>;
    let first: Reference = with_warp!(&e.variants[0].1, |w| reference_points::<T, _>(w, points))?;
    let mut out = Vec::new();
    for (j, (_, built)) in e.variants.iter().enumerate() {
        let own: Option<Reference> = if j > 0 && with_warp!(built, |w| w.is_exact()) {
            Some(with_warp!(built, |w| reference_points::<T, _>(w, points))?)
        } else {
            None
        };
        let Some((refs, extent)) = own.as_ref().unwrap_or(&first) else {
            out.push(ErrorCell {
                rejected: true,
                max_error: 0.0,
                non_finite: 0,
            });
            continue;
        };
        let cell = with_warp!(built, |w| variant_error::<T, _>(w, points, refs, extent))?;
        out.push(cell);
    }
    Ok(out)
}

/// `x` converted exactly to the reference scalar: the sum of its leading
/// `f64` parts (`x = Σ x_i`, each `x_i` the `f64` nearest to the remainder;
/// exact for scalars of up to 512 bits, unlike a decimal round trip, whose
/// rounding the cancellation in `1 − u` would amplify).
fn widen<T: Real>(x: &T) -> R {
    let mut acc = R::zero();
    let mut rest = x.clone();
    for _ in 0..12 {
        let part = rest.to_f64();
        if part == 0.0 || !part.is_finite() {
            break;
        }
        acc += R::from_f64(part);
        rest -= T::from_f64(part);
    }
    acc
}

fn widen3<T: Real>(p: &Vec3<T>) -> Vec3<R> {
    Vec3::new(widen(&p.x), widen(&p.y), widen(&p.z))
}

/// The exact map of the shape as `T` sees it at 512 bits, at the points
/// rounded to `T` (`None` where not finite), and its extent; `None` if
/// `T` rejects the shape.
#[allow(clippy::type_complexity)]
fn reference_points<T: Real, W: StudyWarp>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<Option<(Vec<Option<Vec3<R>>>, R)>, WarpError> {
    let Ok(wt) = w.exact().at::<T>() else {
        return Ok(None);
    };
    let wr = wt.at::<R>()?;
    let refs = points
        .iter()
        .map(|&(u, v)| {
            let (ut, vt) = (T::from_f64(u), T::from_f64(v));
            let q = wr.map(&widen(&ut), &widen(&vt)).to_vec3();
            q.is_finite().then_some(q)
        })
        .collect();
    Ok(Some((refs, wr.extent())))
}

fn variant_error<T: Real, W: StudyWarp>(
    w: &W,
    points: &[(f64, f64)],
    refs: &[Option<Vec3<R>>],
    extent: &R,
) -> Result<ErrorCell, WarpError> {
    let Ok(wt) = w.at::<T>() else {
        return Ok(ErrorCell {
            rejected: true,
            max_error: 0.0,
            non_finite: 0,
        });
    };
    let mut cell = ErrorCell {
        rejected: false,
        max_error: 0.0,
        non_finite: 0,
    };
    for (&(u, v), q) in points.iter().zip(refs) {
        let Some(q) = q else { continue };
        let p = wt.map(&T::from_f64(u), &T::from_f64(v)).to_vec3();
        if !p.is_finite() {
            cell.non_finite += 1;
            continue;
        }
        let p: Vec3<R> = widen3(&p);
        let err = (p.sub(q).max_abs() / extent).to_f64();
        cell.max_error = cell.max_error.max(err);
    }
    Ok(cell)
}

/// ns per sample of `w.map` over `inputs`, `reps` timed runs after one
/// untimed run.
fn time_map<T: Real, W: Warp<T>>(w: &W, inputs: &[(T, T)], reps: usize) -> Timing {
    let run = || {
        let start = Instant::now();
        for (u, v) in inputs {
            black_box(w.map(black_box(u), black_box(v)));
        }
        start.elapsed().as_secs_f64() * 1e9 / inputs.len() as f64
    };
    run();
    Timing::of((0..reps).map(|_| run()).collect(), inputs.len())
}

/// ns per sample of rebuilding the shape in `T` from its `f64` data
/// ([`WarpFamily::at`]) and mapping one sample, over `inputs`.
fn time_build<T: Real, W: WarpFamily<f64>>(
    w: &W,
    inputs: &[(T, T)],
    reps: usize,
) -> Result<Timing, WarpError> {
    let run = || -> Result<f64, WarpError> {
        let start = Instant::now();
        for (u, v) in inputs {
            // Opaque, so that the map cannot be specialised to the
            // constants of a shape built in the loop.
            let wt = black_box(black_box(w).at::<T>()?);
            black_box(wt.map(black_box(u), black_box(v)));
        }
        Ok(start.elapsed().as_secs_f64() * 1e9 / inputs.len() as f64)
    };
    run()?;
    let runs = (0..reps).map(|_| run()).collect::<Result<Vec<f64>, _>>()?;
    Ok(Timing::of(runs, inputs.len()))
}

fn timings<T: Real, W: StudyWarp>(
    w: &W,
    config: &SpeedConfig,
) -> Result<(Timing, Timing), WarpError> {
    let mpfr = T::precision() > 53;
    let (batch, build_batch, reps) = if mpfr {
        (
            config.mpfr_batch,
            config.mpfr_batch,
            config.mpfr_repetitions,
        )
    } else {
        (config.batch, config.build_batch, config.repetitions)
    };
    let inputs: Vec<(T, T)> = random_points(batch.max(build_batch), config.seed ^ 0x7157)
        .into_iter()
        .map(|(u, v)| (T::from_f64(u), T::from_f64(v)))
        .collect();
    let wt = w.at::<T>()?;
    let map = time_map(&wt, &inputs[..batch], reps);
    let build = time_build(w, &inputs[..build_batch], reps)?;
    Ok((map, build))
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

/// Marks, per warp, the rows not dominated in (median map time, max
/// error): no other row of the warp is at least as fast and at least as
/// accurate and strictly better in one. Rows with NaN/∞ outputs count as
/// infinitely inaccurate.
fn mark_pareto(rows: &mut [SpeedRow]) {
    let key = |r: &SpeedRow| {
        let e = if r.non_finite > 0 {
            f64::INFINITY
        } else {
            r.max_error
        };
        (r.map.median, e)
    };
    let keys: Vec<(f64, f64)> = rows.iter().map(key).collect();
    for i in 0..rows.len() {
        let (ti, ei) = keys[i];
        let dominated = (0..rows.len()).any(|j| {
            let (tj, ej) = keys[j];
            j != i && rows[j].warp == rows[i].warp && tj <= ti && ej <= ei && (tj < ti || ej < ei)
        });
        rows[i].pareto = !dominated && ei.is_finite();
    }
}

/// `a` is clearly faster than `b`: a median at least 10 % lower and
/// interquartile ranges that do not overlap.
fn clearly_faster(a: &Timing, b: &Timing) -> bool {
    a.median < 0.9 * b.median && a.q3 < b.q1
}

/// Per warp, among the `f64` rows without NaN/∞ whose max error is within a
/// factor 4 of the smallest such `f64` max error (*qualifying*): the
/// crate's default variant (the first of [`warp_variants`]) if it
/// qualifies and no qualifying alternative is [clearly
/// faster](clearly_faster); else the fastest (median) clearly faster
/// alternative; else, if the default does not qualify, the fastest
/// qualifying row. The reason cites the alternatives.
///
/// [`warp_variants`]: super::precision::warp_variants
fn recommend(rows: &[SpeedRow]) -> Vec<Recommendation> {
    fn fastest<'a>(v: &[&'a SpeedRow]) -> Option<&'a SpeedRow> {
        v.iter()
            .copied()
            .min_by(|a, b| a.map.median.total_cmp(&b.map.median))
    }
    let mut out = Vec::new();
    for (warp, variants) in super::precision::warp_variants() {
        let f64_rows: Vec<&SpeedRow> = rows
            .iter()
            .filter(|r| r.warp == warp && r.scalar == "f64")
            .collect();
        let clean: Vec<&SpeedRow> = f64_rows
            .iter()
            .copied()
            .filter(|r| r.non_finite == 0)
            .collect();
        let Some(best_error) = clean.iter().map(|r| r.max_error).min_by(f64::total_cmp) else {
            continue;
        };
        let tolerance = 4.0 * best_error.max(f64::MIN_POSITIVE);
        let qualifying: Vec<&SpeedRow> = clean
            .iter()
            .copied()
            .filter(|r| r.max_error <= tolerance)
            .collect();
        let default = qualifying
            .iter()
            .copied()
            .find(|r| r.variant == variants[0]);
        let (pick, why) = match default {
            Some(d) => {
                let faster: Vec<&SpeedRow> = qualifying
                    .iter()
                    .copied()
                    .filter(|r| clearly_faster(&r.map, &d.map))
                    .collect();
                match fastest(&faster) {
                    Some(f) => (f, "clearly faster than the default, as accurate"),
                    None => (
                        d,
                        "the default: as accurate as the best, no alternative clearly faster",
                    ),
                }
            }
            None => match fastest(&qualifying) {
                Some(f) => (f, "the default is not accurate enough"),
                None => continue,
            },
        };
        let mut reason = format!(
            "{why} — f64 {}: {} ns/sample ({} with construction), max error {} ({} u) over {} shapes",
            pick.variant,
            fmt_num(pick.map.median),
            fmt_num(pick.build_and_map.median),
            fmt_num(pick.max_error),
            fmt_num(pick.max_error_ulps),
            pick.shapes
        );
        for r in &f64_rows {
            if r.variant == pick.variant {
                continue;
            }
            let _ = write!(
                reason,
                "; {}: {} ns/sample ({:.2}×), max error {}",
                r.variant,
                fmt_num(r.map.median),
                r.map.median / pick.map.median,
                fmt_num(r.max_error)
            );
            if r.non_finite > 0 {
                let _ = write!(reason, ", {} NaN/∞", r.non_finite);
            } else if r.max_error > tolerance {
                let _ = write!(
                    reason,
                    " ({}× the best)",
                    fmt_num(r.max_error / best_error.max(f64::MIN_POSITIVE))
                );
            }
        }
        if let Some(f32_row) = rows
            .iter()
            .find(|r| r.warp == warp && r.scalar == "f32" && r.variant == pick.variant)
        {
            let _ = write!(
                reason,
                "; in f32: {} ns/sample ({:.2}×), max error {}{}",
                fmt_num(f32_row.map.median),
                f32_row.map.median / pick.map.median,
                fmt_num(f32_row.max_error),
                if f32_row.non_finite > 0 {
                    format!(", {} NaN/∞", f32_row.non_finite)
                } else {
                    String::new()
                }
            );
        }
        out.push(Recommendation {
            warp: warp.to_string(),
            variant: pick.variant.clone(),
            scalar: pick.scalar.clone(),
            ns_per_sample: pick.map.median,
            ns_with_construction: pick.build_and_map.median,
            max_error: pick.max_error,
            reason,
        });
    }
    out
}

impl SpeedStudy {
    /// The recommended default per warp (in [`WARPS`] order), with the
    /// measured cost and error that justify it.
    pub fn recommendations(&self) -> &[Recommendation] {
        &self.recommendations
    }

    /// The row of `warp`, `variant`, `scalar`.
    pub fn row(&self, warp: &str, variant: &str, scalar: &str) -> Option<&SpeedRow> {
        self.rows
            .iter()
            .find(|r| r.warp == warp && r.variant == variant && r.scalar == scalar)
    }

    /// The Pareto-optimal rows of `warp`, fastest first.
    pub fn pareto(&self, warp: &str) -> Vec<&SpeedRow> {
        let mut v: Vec<&SpeedRow> = self
            .rows
            .iter()
            .filter(|r| r.warp == warp && r.pareto)
            .collect();
        v.sort_by(|a, b| a.map.median.total_cmp(&b.map.median));
        v
    }

    /// The study as a Markdown section: the full table, the Pareto set and
    /// the recommendations.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "## Speed–accuracy: every warp × variant × type\n");
        let c = &self.config;
        let _ = writeln!(
            s,
            "Time: ns per sample on the warp's first shape (*timed shape*), median of {} runs of {} samples \
             (MPFR: {} runs of {}), with the spread min–max and the interquartile range; *build + map* rebuilds \
             the shape from its f64 data for every sample ({} samples per run; MPFR {}). Error: max-norm \
             distance over extent to the exact map (robust / Newton) of the shape as the type sees it, at 512 \
             bits, over the extremes grid plus {} random points ({} per shape) on *all* the warp's shapes \
             (ladders included; `rej.` = shapes the type rejects), absolute and in units of the type's roundoff. \
             Inputs and outputs reach the reference exactly; the MPFR shapes' parameters pass through a decimal \
             round trip (½ ulp of the type). ★ = Pareto-optimal within the warp in (median map time, max error) \
             among the configurations without NaN/∞ — a configuration with an O(1) error is on the front only \
             by being the fastest. For the closed forms without per-shape constants *build + map* may come out \
             below *map* (code layout): their construction is free. Timings come from one run on a shared \
             machine (other processes inflate the upper quantiles): compare within the table.\n",
            c.repetitions,
            c.batch,
            c.mpfr_repetitions,
            c.mpfr_batch,
            c.build_batch,
            c.mpfr_batch,
            c.error_random_points,
            self.points_per_shape
        );
        let _ = writeln!(
            s,
            "| warp | variant | type | map ns (min–max; IQR) | build + map ns (min–max) | max error | [u] | worst shape | timed-shape error | NaN | shapes (rej.) | Pareto |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} ({}–{}; {}–{}) | {} ({}–{}) | {} | {} | {} | {} | {} | {} ({}) | {} |",
                r.warp,
                r.variant,
                r.scalar,
                fmt_num(r.map.median),
                fmt_num(r.map.min),
                fmt_num(r.map.max),
                fmt_num(r.map.q1),
                fmt_num(r.map.q3),
                fmt_num(r.build_and_map.median),
                fmt_num(r.build_and_map.min),
                fmt_num(r.build_and_map.max),
                fmt_num(r.max_error),
                fmt_num(r.max_error_ulps),
                r.worst_shape,
                fmt_num(r.timed_shape_error),
                r.non_finite,
                r.shapes,
                r.rejected,
                if r.pareto { "★" } else { "" }
            );
        }
        let _ = writeln!(s, "\n### Pareto set per warp (fastest first)\n");
        let _ = writeln!(s, "| warp | not dominated in (time, error) |");
        let _ = writeln!(s, "|---|---|");
        for warp in WARPS {
            let set: Vec<String> = self
                .pareto(warp)
                .iter()
                .map(|r| {
                    format!(
                        "{} {} ({} ns, {})",
                        r.variant,
                        r.scalar,
                        fmt_num(r.map.median),
                        fmt_num(r.max_error)
                    )
                })
                .collect();
            if !set.is_empty() {
                let _ = writeln!(s, "| {warp} | {} |", set.join(" → "));
            }
        }
        let _ = writeln!(
            s,
            "\n![speed–accuracy Pareto plot](speed_pareto.svg)\n\n![speed–accuracy in f32 and f64](speed_pareto_f32_f64.svg)\n\n![projected polygon: inversion settings](speed_pareto_projected-polygon.svg)\n"
        );
        let _ = writeln!(
            s,
            "### Recommended defaults\n\nPer warp, among the f64 configurations that never returned NaN/∞ and \
             whose max error over all shapes is within 4× the best f64 max error: the crate's default variant, \
             unless an alternative is clearly faster (median ≥ 10 % lower and the interquartile ranges do not \
             overlap), then the fastest such alternative.\n"
        );
        let _ = writeln!(
            s,
            "| warp | default | ns/sample | with construction | max error | why |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for r in &self.recommendations {
            let _ = writeln!(
                s,
                "| {} | {} {} | {} | {} | {} | {} |",
                r.warp,
                r.variant,
                r.scalar,
                fmt_num(r.ns_per_sample),
                fmt_num(r.ns_with_construction),
                fmt_num(r.max_error),
                r.reason
            );
        }
        s
    }

    /// Writes `speed_accuracy.csv` (every row) and
    /// `speed_recommendations.csv` into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut t = String::from(
            "warp,variant,type,timed_shape,map_ns_median,map_ns_min,map_ns_max,map_ns_q1,map_ns_q3,map_runs,map_samples,\
             build_ns_median,build_ns_min,build_ns_max,build_ns_q1,build_ns_q3,build_runs,build_samples,\
             max_error,max_error_ulps,worst_shape,timed_shape_error,non_finite,shapes,rejected,pareto\n",
        );
        for r in &self.rows {
            let _ = writeln!(
                t,
                "{},{},{},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:e},{:e},\"{}\",{:e},{},{},{},{}",
                r.warp,
                r.variant,
                r.scalar,
                r.timed_shape,
                r.map.median,
                r.map.min,
                r.map.max,
                r.map.q1,
                r.map.q3,
                r.map.runs,
                r.map.samples,
                r.build_and_map.median,
                r.build_and_map.min,
                r.build_and_map.max,
                r.build_and_map.q1,
                r.build_and_map.q3,
                r.build_and_map.runs,
                r.build_and_map.samples,
                r.max_error,
                r.max_error_ulps,
                r.worst_shape,
                r.timed_shape_error,
                r.non_finite,
                r.shapes,
                r.rejected,
                r.pareto
            );
        }
        let a = dir.join("speed_accuracy.csv");
        std::fs::write(&a, t)?;
        let mut t =
            String::from("warp,variant,type,ns_per_sample,ns_with_construction,max_error,reason\n");
        for r in &self.recommendations {
            let _ = writeln!(
                t,
                "{},{},{},{},{},{:e},\"{}\"",
                r.warp,
                r.variant,
                r.scalar,
                r.ns_per_sample,
                r.ns_with_construction,
                r.max_error,
                r.reason.replace('"', "\"\"")
            );
        }
        let b = dir.join("speed_recommendations.csv");
        std::fs::write(&b, t)?;
        Ok(vec![a, b])
    }

    /// Writes `speed_pareto.svg` (log-log: median ns per sample against max
    /// error, every configuration; per warp its Pareto front as a line and
    /// the dominated configurations as single markers in the same colour),
    /// `speed_pareto_f32_f64.svg` (the same for the hardware types alone,
    /// front within them) and `speed_pareto_projected-polygon.svg` (the
    /// polygon's inversion settings, one line per setting through the four
    /// types).
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let floor = |e: f64| e.max(1e-80);
        let mut plot = Plot::new(
            "speed–accuracy: every warp × variant × type",
            Axis::log("ns per sample (median, shape built once)"),
            Axis::log("max error (distance / extent)"),
        )
        .size(900, 620);
        for (i, warp) in WARPS.iter().enumerate() {
            let color = crate::figures::PALETTE[i % crate::figures::PALETTE.len()];
            let front: Vec<(f64, f64)> = self
                .pareto(warp)
                .iter()
                .map(|r| (r.map.median, floor(r.max_error)))
                .collect();
            if front.is_empty() {
                continue;
            }
            plot = plot.series(Series::new(warp, front).with_color(color));
            for r in self.rows.iter().filter(|r| r.warp == *warp && !r.pareto) {
                if r.non_finite == 0 {
                    plot = plot.series(
                        Series::new("", vec![(r.map.median, floor(r.max_error))]).with_color(color),
                    );
                }
            }
        }
        let mut out = vec![write_line_plot_svg(&dir.join("speed_pareto.svg"), &plot)?];

        // The hardware types alone: per warp the front within f32/f64.
        let mut hw = Plot::new(
            "speed–accuracy in f32 and f64",
            Axis::log("ns per sample (median, shape built once)"),
            Axis::log("max error (distance / extent)"),
        )
        .size(900, 620);
        for (i, warp) in WARPS.iter().enumerate() {
            let color = crate::figures::PALETTE[i % crate::figures::PALETTE.len()];
            let rows: Vec<&SpeedRow> = self
                .rows
                .iter()
                .filter(|r| {
                    r.warp == *warp && (r.scalar == "f32" || r.scalar == "f64") && r.non_finite == 0
                })
                .collect();
            let dominated = |r: &SpeedRow| {
                rows.iter().any(|o| {
                    o.map.median <= r.map.median
                        && o.max_error <= r.max_error
                        && (o.map.median < r.map.median || o.max_error < r.max_error)
                })
            };
            let mut front: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| !dominated(r))
                .map(|r| (r.map.median, floor(r.max_error)))
                .collect();
            if front.is_empty() {
                continue;
            }
            front.sort_by(|a, b| a.0.total_cmp(&b.0));
            hw = hw.series(Series::new(warp, front).with_color(color));
            for r in rows.iter().filter(|r| dominated(r)) {
                hw = hw.series(
                    Series::new("", vec![(r.map.median, floor(r.max_error))]).with_color(color),
                );
            }
        }
        out.push(write_line_plot_svg(
            &dir.join("speed_pareto_f32_f64.svg"),
            &hw,
        )?);

        // The polygon's inversion settings: one line per setting through
        // the scalars f32 → f64 → mpfr:128 → mpfr:256 (the cubic's error
        // stays at its bias, Newton's falls with the precision).
        let mut poly = Plot::new(
            "projected polygon: marginal inversion settings across types",
            Axis::log("ns per sample (median)"),
            Axis::log("max error (distance / extent)"),
        );
        for (label, _) in super::precision::POLYGON_SETTINGS {
            let pts: Vec<(f64, f64)> = SCALARS
                .iter()
                .filter_map(|t| self.row("projected-polygon", label, t))
                .map(|r| (r.map.median, floor(r.max_error)))
                .collect();
            if !pts.is_empty() {
                poly = poly.series(Series::new(label, pts));
            }
        }
        out.push(write_line_plot_svg(
            &dir.join(format!("speed_pareto_{}.svg", slug("projected-polygon"))),
            &poly,
        )?);
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::verify_figure;
    use crate::studies::precision::warp_variants;

    fn quick() -> &'static SpeedStudy {
        use std::sync::OnceLock;
        static STUDY: OnceLock<SpeedStudy> = OnceLock::new();
        STUDY.get_or_init(|| run(&SpeedConfig::quick()).expect("quick speed study"))
    }

    #[test]
    fn speed_table_covers_every_warp_variant_and_type() {
        let s = quick();
        let mut expected = 0;
        for (warp, variants) in warp_variants() {
            for variant in variants {
                for scalar in SCALARS {
                    expected += 1;
                    let r = s
                        .row(warp, variant, scalar)
                        .unwrap_or_else(|| panic!("{warp} {variant} {scalar} missing"));
                    assert!(
                        r.map.median > 0.0
                            && r.map.min <= r.map.median
                            && r.map.median <= r.map.max,
                        "{r:?}"
                    );
                    assert!(r.map.q1 <= r.map.q3, "{r:?}");
                    assert!(r.build_and_map.median > 0.0, "{r:?}");
                    assert!(r.shapes > 0 && r.max_error.is_finite(), "{r:?}");
                    assert_eq!(r.map.runs, if scalar.starts_with("mpfr") { 2 } else { 3 });
                }
            }
        }
        assert_eq!(s.rows.len(), expected);
        // Every inversion setting of the polygon, in every type.
        for inv in [
            "cubic",
            "cubic+1 Newton",
            "cubic+2 Newton",
            "cubic+3 Newton",
            "Newton",
        ] {
            assert!(s.row("projected-polygon", inv, "mpfr:128").is_some());
        }
        let md = s.to_markdown();
        assert!(md.contains("| projected-polygon | cubic+2 Newton | mpfr:256 |"));
    }

    /// The errors (not the timings) are identical for 1 and 2 threads.
    #[test]
    fn speed_errors_are_identical_for_one_and_two_threads() {
        let config = SpeedConfig {
            max_shapes: Some(2),
            ..SpeedConfig::quick()
        };
        let errors = |threads: usize| -> Vec<(String, f64, f64, usize, usize)> {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let study = pool.install(|| run(&config)).expect("runs");
            study
                .rows
                .iter()
                .map(|r| {
                    (
                        format!("{} {} {} {}", r.warp, r.variant, r.scalar, r.worst_shape),
                        r.max_error,
                        r.timed_shape_error,
                        r.non_finite,
                        r.rejected,
                    )
                })
                .collect()
        };
        assert_eq!(errors(1), errors(2));
    }

    #[test]
    fn speed_errors_order_the_scalars() {
        // Structure, not timing: the exact variants' errors shrink with the
        // precision, and the bare cubic is no better in f64 than its bias.
        let s = quick();
        let exact = ["closed form", "+z axis", "tilted axis", "robust", "Newton"];
        for (warp, variants) in warp_variants() {
            for v in variants.into_iter().filter(|v| exact.contains(v)) {
                let e: Vec<f64> = SCALARS
                    .iter()
                    .map(|t| s.row(warp, v, t).unwrap().max_error)
                    .collect();
                assert!(
                    e[0] > e[1] && e[1] > e[2] && e[2] > e[3],
                    "{warp} {v}: {e:?}"
                );
                assert!(
                    e[0] < 1e-5 && e[1] < 1e-12 && e[3] < 1e-70,
                    "{warp} {v}: {e:?}"
                );
            }
        }
        let cubic = s.row("projected-polygon", "cubic", "mpfr:256").unwrap();
        assert!(cubic.max_error > 1e-12, "{cubic:?}");
    }

    #[test]
    fn speed_pareto_and_recommendations_cover_every_warp() {
        let s = quick();
        for warp in WARPS {
            let front = s.pareto(warp);
            assert!(!front.is_empty(), "{warp}");
            // Along the front, slower means more accurate.
            for w in front.windows(2) {
                assert!(
                    w[0].map.median <= w[1].map.median && w[0].max_error >= w[1].max_error,
                    "{w:?}"
                );
            }
        }
        let rec = s.recommendations();
        assert_eq!(rec.len(), WARPS.len());
        for r in rec {
            assert_eq!(r.scalar, "f64");
            let row = s.row(&r.warp, &r.variant, "f64").unwrap();
            assert_eq!(row.non_finite, 0);
            assert_eq!(r.max_error, row.max_error);
            assert!(r.reason.contains("ns/sample"));
            // The rule, checked structurally (whatever the timings).
            let clean: Vec<&SpeedRow> = s
                .rows
                .iter()
                .filter(|x| x.warp == r.warp && x.scalar == "f64" && x.non_finite == 0)
                .collect();
            let best = clean
                .iter()
                .map(|x| x.max_error)
                .fold(f64::INFINITY, f64::min);
            let ok = |x: &SpeedRow| x.max_error <= 4.0 * best.max(f64::MIN_POSITIVE);
            assert!(ok(row), "{r:?}");
            let default_variant = warp_variants()
                .into_iter()
                .find(|(w, _)| *w == r.warp)
                .unwrap()
                .1[0];
            let default = s.row(&r.warp, default_variant, "f64").unwrap();
            let faster: Vec<&&SpeedRow> = clean
                .iter()
                .filter(|x| ok(x) && clearly_faster(&x.map, &default.map))
                .collect();
            if r.variant == default_variant {
                assert!(faster.is_empty(), "{r:?}: {faster:?}");
            } else if ok(default) {
                assert!(clearly_faster(&row.map, &default.map), "{r:?}");
                assert!(
                    faster.iter().all(|x| x.map.median >= row.map.median),
                    "{r:?}"
                );
            }
        }
        // The literal solid-angle maps are disqualified on the quick
        // shapes already (NaN/∞ or far from the robust error), so they are
        // never recommended.
        for warp in ["spherical-triangle", "spherical-rectangle"] {
            let lit = s.row(warp, "literal", "f64").unwrap();
            let rob = s.row(warp, "robust", "f64").unwrap();
            assert!(
                lit.non_finite > 0 || lit.max_error > 4.0 * rob.max_error,
                "{lit:?}"
            );
            let r = rec.iter().find(|r| r.warp == warp).unwrap();
            assert_eq!(r.variant, "robust", "{r:?}");
        }
    }

    #[test]
    fn speed_figures_and_csv_are_written() {
        let s = quick();
        let dir = std::env::temp_dir().join(format!("areawarp-speed-{}", std::process::id()));
        let figs = s.write_figures(&dir).unwrap();
        assert_eq!(figs.len(), 3);
        let all = verify_figure(&figs[0].path).unwrap();
        assert_eq!(
            all.marks,
            s.rows.iter().filter(|r| r.non_finite == 0).count(),
            "{all:?}"
        );
        let hw = verify_figure(&figs[1].path).unwrap();
        assert_eq!(
            hw.marks,
            s.rows
                .iter()
                .filter(|r| r.non_finite == 0 && !r.scalar.starts_with("mpfr"))
                .count(),
            "{hw:?}"
        );
        let poly = verify_figure(&figs[2].path).unwrap();
        assert_eq!(poly.marks, 20, "{poly:?}");
        let csv = s.write_csv(&dir).unwrap();
        let rows = std::fs::read_to_string(&csv[0]).unwrap();
        assert_eq!(rows.lines().count(), s.rows.len() + 1);
        std::fs::remove_dir_all(&dir).ok();
        assert!(
            run(&SpeedConfig {
                batch: 0,
                ..SpeedConfig::quick()
            })
            .is_err()
        );
    }

    /// The default sizes of both studies, timed, with their Markdown
    /// printed and files written to `target/studies-report`:
    /// `cargo test --release --lib studies::speed::tests::default_sizes -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn default_sizes() {
        use crate::studies::precision;
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/studies-report");
        let t0 = Instant::now();
        let p = precision::run(&precision::PrecisionConfig::default()).unwrap();
        let tp = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let s = run(&SpeedConfig::default()).unwrap();
        let ts = t1.elapsed().as_secs_f64();
        println!("{}\n{}", p.to_markdown(), s.to_markdown());
        p.write_csv(&dir).unwrap();
        p.write_figures(&dir).unwrap();
        s.write_csv(&dir).unwrap();
        s.write_figures(&dir).unwrap();
        println!("precision: {tp:.1} s, speed: {ts:.1} s");
    }

    #[test]
    fn widening_is_exact() {
        // 1 − 10⁻¹² as a 128-bit number: a decimal round trip (40 digits)
        // would move it by ~10⁻⁴⁰, i.e. 1 − u by 10⁻²⁸ relative.
        let u = 1.0 - 1e-12;
        assert_eq!(widen(&Mpfr128::from_f64(u)), R::from_f64(u));
        let third = Mpfr128::from_ratio(1, 3);
        let w = widen(&third);
        let e = (w.clone() * &R::from_i64(3) - &R::one()).abs();
        assert!(e > R::zero() && e <= R::exp2i(-127), "{e}");
        let back = w - &R::from_f64(third.to_f64());
        assert!(back.abs() <= R::exp2i(-54), "{back}");
        assert_eq!(widen(&0.1f32), R::from_f64(f64::from(0.1f32)));
        let third256 = Mpfr256::from_ratio(1, 3);
        let e = (widen(&third256) * &R::from_i64(3) - &R::one()).abs();
        assert!(e > R::zero() && e <= R::exp2i(-255), "{e}");
    }

    #[test]
    fn timing_quantiles() {
        let t = Timing::of(vec![4.0, 1.0, 3.0, 2.0, 5.0], 10);
        assert_eq!(
            (t.min, t.q1, t.median, t.q3, t.max),
            (1.0, 2.0, 3.0, 4.0, 5.0)
        );
        let t = Timing::of(vec![2.0, 1.0], 1);
        assert_eq!(t.median, 1.5);
    }
}
