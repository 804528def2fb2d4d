//! Study 3 — variance: the experiment of Ureña, Fajardo and King (2013,
//! Fig. 4 and 7), measured at receivers instead of pixels.
//!
//! # The experiment
//! A double-sided rectangular light stands perpendicular on a ground plane
//! ([`setup::standing_rectangle`]); receivers lie on the ground in front of
//! it, spaced geometrically so that they are dense near its foot, where the
//! `1/r²` of area sampling makes its estimator's variance explode (its
//! relative variance grows like `1/d²` at distance `d` from the light's
//! bottom edge). At each receiver the irradiance `E = ∫ L cos⁺θ dω` is
//! estimated with `n = 1, 2, 4, …, 1024` samples per receiver (*spp*) by
//!
//! | sampler ([`Sampler`]) | density (solid angle) | `f/p` |
//! |---|---|---|
//! | area sampling | `r² / (A cos θ_e)` | `L A cos θ cos θ_e / r²` (unbounded near the light) |
//! | two spherical triangles, chosen ∝ solid angle | `1/Ω` | `L Ω cos θ` |
//! | the spherical rectangle | `1/Ω` | `L Ω cos θ` |
//! | the projected polygon (Arvo 2001, §1.4) | `cos θ / Π` | `L Π`: constant, a zero-variance estimator |
//! | cosine sampling (the MIS partner, alone) | `cos θ / π` | `π L · [hit]` |
//!
//! each alone and combined by multiple importance sampling
//! ([`Mis`](areawarp::estimate::Mis)) with
//! cosine (BRDF) sampling: `n` light samples plus `n` cosine samples, as in
//! the paper's Fig. 6 ("each light sample with an additional BRDF sample"),
//! so an MIS estimate at `n` spp traces `2n` rays. The balance heuristic is
//! used throughout; the power (β = 2) and maximum heuristics are compared
//! on the configurations of [`VarianceConfig::heuristic_samplers`].
//!
//! The points on `[0, 1]²` are jittered (an `n_x × n_y` grid with
//! `n_x = 2^⌈m/2⌉`, `n_y = 2^⌊m/2⌋` for `n = 2^m`) or Owen-scrambled Sobol
//! ([`PointSet`]). All methods at a receiver, run and spp see the *same*
//! points (common random numbers, as in the paper: "the same input set of
//! samples"), which makes the differences between methods sharper than
//! their errors.
//!
//! # Error measure
//! The exact irradiance at each receiver is Lambert's formula
//! ([`lambert::irradiance`]; no occluders). With `Ê_{r,k}` the estimate at
//! receiver `r` in run `k`, the *relative RMS error* of a method at `n` spp
//! is `√( mean_{r,k} ((Ê_{r,k} − E_r)/E_r)² )` over all receivers and runs
//! (every receiver weighs the same; near-light receivers are many). The
//! CSV also has the image-style `√(Σ (Ê − E)²) / √(Σ E²)`. The runs are
//! independent jobs of [`run_jobs`](crate::jobs::run_jobs) (one per
//! receiver and run, its own seed)
//! reduced in job order: bit-identical results for any thread count.
//!
//! # Samples at equal error
//! Near the largest `n`, `ε(n) ≈ c n^(−α)` is fitted to each curve by least
//! squares on the last [`VarianceConfig::fit_levels`] levels in log–log.
//! For methods `a` and `b` the sample ratio at equal error is
//! `n_b / n_max` with `ε_b(n_b) = ε_a(n_max)`: how many times the samples of
//! `a` that `b` needs (the paper: the triangle pair needs `1/0.85 ≈ 1.18`
//! times the rectangle's samples at 1024 spp, i.e. the rectangle needs
//! ~15% fewer). Its standard error is a jackknife over runs.
//!
//! # With occluders
//! The paper's scene has three spheres on the ground whose shadows put
//! visibility discontinuities inside the light's solid angle, which caps
//! every stratified estimator's rate; our unoccluded receivers have a smooth
//! integrand. A second measurement ([`VarianceConfig::occluders`]) adds a
//! row of opaque squares ([`OccluderRow`]) between the light and the far
//! receivers, with exact references from Lambert's formula applied to the
//! light minus the occluders' central projections ([`occluded_irradiance`]).
//!
//! # Claims
//! [`VarianceStudy::claims`] checks each claim of the papers on the
//! jittered points: *reproduced* when the effect is there, significant
//! (beyond 2 jackknife standard errors where one exists) and consistent
//! within 2 standard errors with the claimed size (a factor 2 either way for
//! "15% / 9% fewer samples", `√2` for "about twice", ≥ 100 for "orders of
//! magnitude", ≥ 10 for "tremendous", RMS within 10% of the best for
//! "nearly optimal"); *qualitatively* when only the direction holds; with
//! the numbers in every case.
//!
//! # Failures
//! A method that cannot be built at a receiver (e.g.
//! [`ProjectedPolygon::from_points`](areawarp::shapes::ProjectedPolygon::from_points)
//! rejecting a light edge lying exactly on the receiver's horizon) or
//! returns a non-finite estimate is skipped *there*, counted, and listed in
//! the report ([`Measurement::failures`]); its curves are then over fewer
//! receivers (column `skipped`).
//!
//! # The hook for Ureña (2000)
//! The adaptive comparison of Ureña (2000) (patterned triangle with
//! occluders, solid-angle stratified vs adaptive with K = 0.1 and 0.001) is
//! not run here. It plugs in through the same engine: implement
//! [`ReceiverEstimator`] for the adaptive sampler, call [`measure`] with
//! [`setup::patterned_triangle`] and converged references
//! ([`Scene::reference`]), and attach the result with
//! [`VarianceStudy::attach`] as an [`ExtraSection`]: its curves, claims,
//! Markdown, CSV and figures then appear with this study's.
//!
//! # Example
//! ```
//! use areawarp_lab::studies::variance::{VarianceConfig, run};
//!
//! let mut config = VarianceConfig::quick();
//! config.max_log2_spp = 4;
//! config.runs = 2;
//! let study = run(&config)?;
//! let md = study.to_markdown();
//! assert!(md.contains("spherical rectangle") || md.contains("rectangle"));
//! assert!(!study.claims().is_empty());
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use crate::figures::{self, Axis, Figure, PALETTE, Plot, Series};
use crate::scene::setup::{self, Setup};
use crate::scene::{PlanarPolygon, Receiver, Scene, lambert};
use areawarp::error::WarpError;
use areawarp::estimate::{Heuristic, job_seed};
use areawarp::vector::Vec3;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;
mod claims;
mod glossy;
mod occluded;
mod output;
mod robust;
mod tables;
pub use self::glossy::*;
pub use self::occluded::*;
pub use crate::estimator::*;
pub use crate::verdict::{Claim, Verdict};
#[cfg(test)]
mod tests;
use self::tables::*;

/// The size and contents of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct VarianceConfig {
    /// Seed of the runs.
    pub seed: u64,
    /// Width of the standing light (along `x`).
    pub width: f64,
    /// Its height (along `z`).
    pub height: f64,
    /// Its radiance (constant).
    pub radiance: f64,
    /// Distance of the nearest receiver row from the light's plane.
    pub near: f64,
    /// Distance of the farthest row.
    pub far: f64,
    /// Receiver rows (geometric spacing between `near` and `far`).
    pub rows: usize,
    /// Receivers per row (`x` from `−width` to `width`, cell centres).
    pub lateral: usize,
    /// spp = 1, 2, 4, …, `2^max_log2_spp`.
    pub max_log2_spp: u32,
    /// Independent runs per receiver.
    pub runs: usize,
    /// The point sets.
    pub point_sets: Vec<PointSet>,
    /// The methods ([`Method::standard`]).
    pub methods: Vec<Method>,
    /// The samplers on which the balance, power and maximum heuristics are
    /// compared (their methods must be in `methods`).
    pub heuristic_samplers: Vec<Sampler>,
    /// Receivers at most this far from the light form the near-light subset.
    pub near_light: f64,
    /// Levels (the last ones) used by the power-law fits.
    pub fit_levels: usize,
    /// A second measurement with these occluders in the scene (exact
    /// references by [`occluded_irradiance`]); `None` skips it.
    pub occluders: Option<OccluderRow>,
    /// The methods of the occluded measurement.
    pub occluded_methods: Vec<Method>,
}

impl Default for VarianceConfig {
    /// The report's size: a 1 × 0.5 light, 24 rows × 4 receivers from 0.01
    /// to 4 away, spp up to 1024, 16 runs, jittered and Sobol points, all
    /// methods; near light = within 0.05; the occluded measurement with
    /// [`OccluderRow::standard`] for the rectangle and the triangle pair,
    /// alone and with MIS. About a minute on 2 cores in `--release`.
    fn default() -> Self {
        let heuristic_samplers = vec![Sampler::Area, Sampler::Rectangle];
        VarianceConfig {
            seed: 0x5EED_2013,
            width: 1.0,
            height: 0.5,
            radiance: 1.0,
            near: 0.01,
            far: 4.0,
            rows: 24,
            lateral: 4,
            max_log2_spp: 10,
            runs: 16,
            point_sets: vec![PointSet::Jittered, PointSet::Sobol, PointSet::Independent],
            methods: Method::standard(&heuristic_samplers),
            heuristic_samplers,
            near_light: 0.05,
            fit_levels: 5,
            occluders: Some(OccluderRow::standard()),
            occluded_methods: vec![
                Method::plain(Sampler::Rectangle),
                Method::plain(Sampler::TrianglePair),
                Method::mis(Sampler::Rectangle, Heuristic::Balance),
                Method::mis(Sampler::TrianglePair, Heuristic::Balance),
                Method::plain(Sampler::Area),
                Method::plain(Sampler::ProjectedPolygon),
                Method::plain(Sampler::ProjectedPolygonCubic),
                Method::plain(Sampler::BilinearRectangle),
            ],
        }
    }
}

impl VarianceConfig {
    /// A small configuration for tests (well under a second): 6 rows × 2
    /// receivers (at `x = ±width/2`, the light's side edges, where the
    /// bottom edge lies on the horizon), spp up to 256, 4 runs.
    pub fn quick() -> Self {
        VarianceConfig {
            rows: 6,
            lateral: 2,
            far: 2.0,
            max_log2_spp: 8,
            runs: 4,
            heuristic_samplers: vec![Sampler::Area],
            methods: Method::standard(&[Sampler::Area]),
            ..Self::default()
        }
    }

    /// The spp levels `1, 2, …, 2^max_log2_spp`.
    pub fn spp(&self) -> Vec<usize> {
        (0..=self.max_log2_spp.min(30))
            .map(|m| 1usize << m)
            .collect()
    }
}

/// A section contributed by another measurement on the same engine (the
/// hook for the adaptive comparison of Ureña 2000): shown after this
/// study's own sections, its claims listed with this study's.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtraSection {
    /// Section title (Markdown heading text).
    pub title: String,
    /// Markdown body (tables, notes).
    pub markdown: String,
    /// File-name stem for its CSV and figures (`[a-z0-9_]`).
    pub slug: String,
    /// Its measurement, if any: written as curves (CSV, figure).
    pub measurement: Option<Measurement>,
    /// Its claims (per-receiver relative RMS).
    pub claims: Vec<Claim>,
    /// The same claims judged on the image-style relative RMS
    /// ([`crate::estimator::Metric::Image`]); empty if the section has no
    /// second metric.
    pub claims_image: Vec<Claim>,
}

/// The measurement with occluders ([`VarianceConfig::occluders`]).
#[derive(Clone, Debug, PartialEq)]
pub struct OccludedPart {
    /// The occluders.
    pub occluders: OccluderRow,
    /// The measurement, over the receivers with an exact reference.
    pub measurement: Measurement,
    /// Receivers left out because [`occluded_irradiance`] does not apply
    /// there (an occluder straddling their distance to the light).
    pub dropped: usize,
    /// Receivers partly in shadow (reference below the unoccluded value).
    pub shadowed: usize,
}

/// The result of [`run`].
#[derive(Clone, Debug, PartialEq)]
pub struct VarianceStudy {
    /// The configuration.
    pub config: VarianceConfig,
    /// The measurement.
    pub measurement: Measurement,
    /// The measurement with occluders, if configured.
    pub occluded: Option<OccludedPart>,
    /// Wall-clock time of [`run`] in seconds (not part of the results'
    /// determinism).
    pub elapsed_seconds: f64,
    /// Sections attached with [`VarianceStudy::attach`].
    pub extra: Vec<ExtraSection>,
    /// Slugs of attached sections shown elsewhere in the report.
    pub detached: Vec<String>,
}

/// Runs the study.
///
/// # Errors
/// As [`setup::standing_rectangle`] and [`measure`]; a method whose
/// sampler fails at *every* receiver is not an error (it is reported).
pub fn run(config: &VarianceConfig) -> Result<VarianceStudy, WarpError> {
    let start = Instant::now();
    let setup = setup::standing_rectangle(
        config.width,
        config.height,
        config.radiance,
        config.near,
        config.far,
        config.rows,
        config.lateral,
    )?;
    let references: Vec<f64> = setup
        .receivers
        .iter()
        .map(|r| lambert::irradiance(setup.scene.emitter(), r))
        .collect();
    let estimators: Vec<&dyn ReceiverEstimator> = config
        .methods
        .iter()
        .map(|m| m as &dyn ReceiverEstimator)
        .collect();
    let spp = config.spp();
    let spec = MeasureSpec {
        setup: &setup,
        references: &references,
        estimators: &estimators,
        point_sets: &config.point_sets,
        spp: &spp,
        runs: config.runs,
        seed: config.seed,
        near_light: config.near_light,
    };
    let measurement = measure(&spec, config.fit_levels)?;
    let occluded = match &config.occluders {
        Some(row) if !config.occluded_methods.is_empty() => {
            let mut scene = setup.scene.clone();
            for o in row.polygons()? {
                scene = scene.with_occluder(o);
            }
            let mut receivers = Vec::new();
            let mut refs = Vec::new();
            let mut dropped = 0;
            let mut shadowed = 0;
            for (r, free) in setup.receivers.iter().zip(&references) {
                match occluded_irradiance(&scene, r) {
                    Some(e) if e > 0.0 && e.is_finite() => {
                        if e < *free * (1.0 - 1e-12) {
                            shadowed += 1;
                        }
                        receivers.push(r.clone());
                        refs.push(e);
                    }
                    _ => dropped += 1,
                }
            }
            let occluded_setup = Setup { scene, receivers };
            let estimators: Vec<&dyn ReceiverEstimator> = config
                .occluded_methods
                .iter()
                .map(|m| m as &dyn ReceiverEstimator)
                .collect();
            let spec = MeasureSpec {
                setup: &occluded_setup,
                references: &refs,
                estimators: &estimators,
                seed: job_seed(config.seed, u64::MAX),
                ..spec
            };
            Some(OccludedPart {
                occluders: row.clone(),
                measurement: measure(&spec, config.fit_levels)?,
                dropped,
                shadowed,
            })
        }
        _ => None,
    };
    Ok(VarianceStudy {
        config: config.clone(),
        measurement,
        occluded,
        elapsed_seconds: start.elapsed().as_secs_f64(),
        extra: Vec::new(),
        detached: Vec::new(),
    })
}

/// Formats an error value.
fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3e}")
    } else {
        "–".to_string()
    }
}

/// Formats a ratio: fixed for ordinary sizes, scientific otherwise.
fn num(x: f64) -> String {
    if x.is_finite() && (x == 0.0 || (1e-3..1e4).contains(&x.abs())) {
        format!("{x:.3}")
    } else {
        sci(x)
    }
}

/// Quotes a CSV field if needed.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}
