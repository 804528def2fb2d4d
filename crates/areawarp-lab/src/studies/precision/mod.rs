//! Study 1, *precision*: every warp × variant × {`f32`, `f64`} against the
//! exact map at 256 bits, on the extremes suite (the extremes grid plus
//! random points), over every shape of the warp's test set — for the
//! solid-angle maps, their ordinary shapes and the whole hard ladders
//! ([`hard_triangles`], [`hard_rectangles`]).
//!
//! For each warp, variant, shape and scalar `T` the study measures, at each
//! input point `(u, v)` rounded to `T`:
//!
//! - the **error** `‖ψ_T(u, v) − ψ_exact(u, v)‖_∞ / extent` in units of
//!   `T`'s unit roundoff `u_T` (`2⁻²⁴`, `2⁻⁵³`), where `ψ_exact` is the
//!   *exact* map of the shape as `T` sees it (parameters rounded to `T`),
//!   evaluated at 256 bits: the robust variant for the spherical triangle
//!   and rectangle, Newton to convergence for the projected polygon. For a
//!   literal variant or a truncated inversion this error includes what the
//!   variant gets wrong at any precision (the literal rectangle's cut-off,
//!   the cubic's bias); the column *own* isolates the rounding error by
//!   comparing with the variant's own map at 256 bits;
//! - the **NaN/∞** outputs, and the points **outside** the shape by more
//!   than [`OUTSIDE_TOLERANCE_ULPS`]` · u_T · extent`;
//! - the **κ-conditioned ratio** error / (16 · max(u_T, κ)), κ the move of
//!   the exact map under a one-ulp change of one input (the shape's
//!   parameters, `u`, `v`; [`sensitivities_in`]): at most 1 means the map is
//!   as accurate as its inputs allow (the criterion of
//!   [`check_precision_conditioned`](areawarp::harness::sensitivity::check_precision_conditioned));
//! - the **Jacobian deviation** `max |J · pdf − 1|` of the variant's map at
//!   256 bits with exact partials ([`check_jacobian`]) — independent of `T`;
//!   a literal variant or a truncated inversion that is not area-preserving
//!   shows here at any precision.
//!
//! Plus *where the `f32` error lives*: per warp, the `f32` error (in units of
//! `2⁻²⁴`) over a fine grid of nodes `(i/(n−1), j/(n−1))` of `[0, 1]²`,
//! written as heat maps ([`PrecisionStudy::write_figures`]).
//!
//! The study is deterministic: the cells are independent jobs run by
//! [`run_jobs`] and collected in job order, so the result is the same for
//! any number of threads.
//!
//! # Example
//! ```no_run
//! use areawarp_lab::studies::precision::{run, PrecisionConfig};
//! let study = run(&PrecisionConfig::quick())?;
//! println!("{}", study.to_markdown());
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use crate::figures::{Axis, Figure, HeatMap, Scale, write_heat_map_svg};
use crate::jobs::run_jobs;
use areawarp::error::WarpError;
use areawarp::harness::extremes::{extremes_grid, random_points};
use areawarp::harness::jacobian::check_jacobian;
use areawarp::harness::precision::OUTSIDE_TOLERANCE_ULPS;
use areawarp::harness::sensitivity::{InputFormat, accuracy_bound, sensitivities_in};
use areawarp::real::{Mpfr256, Real, convert};
use areawarp::shapes::{
    Beckmann, Bilinear, ConcentricDisk, Ggx, Hemisphere, MarginalInversion, PhongLobe,
    PlanarTriangle, PlanarTriangleVariant, PolarDisk, ProjectedPolygon, Sphere, SphereLight,
    SphericalLune, SphericalRectangle, SphericalRectangleVariant, SphericalTriangle,
    SphericalTriangleVariant, StdNormal, Tent, UniformCone, VonMisesFisher, hard_rectangles,
    hard_triangles, lune_catalogue, ordinary_rectangles, ordinary_triangles, sphere_light_ladder,
};
use areawarp::vector::{Coords, Vec3};
use areawarp::warp::{Warp, WarpFamily};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};
mod catalogue;
mod measure;
mod output;
pub use self::catalogue::*;
#[cfg(test)]
mod tests;
pub(crate) use self::measure::*;
pub(crate) use self::output::*;
/// The 256-bit reference scalar.
type M = Mpfr256;

// ---------------------------------------------------------------------------
// Configuration and results
// ---------------------------------------------------------------------------

/// The precision study's size.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionConfig {
    /// Seed of the random points.
    pub seed: u64,
    /// Random points added to the extremes grid (64 points) for every shape.
    pub random_points: usize,
    /// At most this many shapes per warp (ordinary shapes first); `None`:
    /// all, i.e. the whole hard ladders.
    pub max_shapes: Option<usize>,
    /// At most this many test polygons of the projected polygon (the most
    /// expensive shapes: κ rebuilds the polygon for every perturbed vertex
    /// coordinate); `None`: all of [`test_polygons`].
    pub max_polygons: Option<usize>,
    /// Nodes per side of the `f32` error maps (`n × n` nodes
    /// `(i/(n−1), j/(n−1))`), at least 2.
    pub heat_map_nodes: usize,
    /// Only these warps (labels of [`WARPS`]); `None`: all.
    pub warps: Option<Vec<String>>,
}

impl PrecisionConfig {
    /// The tests' size (a few seconds of CPU in the test profile): every
    /// shape of every ladder but only the first test polygon, on the
    /// extremes grid plus 4 random points, 12 × 12 error maps.
    pub fn quick() -> Self {
        PrecisionConfig {
            seed: 0x0005_EED5,
            random_points: 4,
            max_shapes: None,
            max_polygons: Some(1),
            heat_map_nodes: 12,
            warps: None,
        }
    }
}

impl Default for PrecisionConfig {
    /// The report's size: every shape on the extremes grid plus 64 random
    /// points, 64 × 64 error maps.
    fn default() -> Self {
        PrecisionConfig {
            random_points: 64,
            max_polygons: None,
            heat_map_nodes: 64,
            ..Self::quick()
        }
    }
}

impl PrecisionConfig {
    fn validate(&self) -> Result<(), WarpError> {
        if self.heat_map_nodes < 2 {
            return Err(WarpError::InvalidParameter {
                name: "heat_map_nodes",
                expected: "at least 2",
            });
        }
        if let Some(only) = &self.warps
            && (only.is_empty() || only.iter().any(|w| !WARPS.contains(&w.as_str())))
        {
            return Err(WarpError::InvalidParameter {
                name: "warps",
                expected: "labels of studies::precision::WARPS",
            });
        }
        if self.max_shapes == Some(0) || self.max_polygons == Some(0) {
            return Err(WarpError::InvalidParameter {
                name: "max_shapes/max_polygons",
                expected: "at least 1 (or None)",
            });
        }
        Ok(())
    }

    /// The input points of every shape: the extremes grid, then
    /// [`PrecisionConfig::random_points`] random points.
    pub fn points(&self) -> Vec<(f64, f64)> {
        let mut p = extremes_grid();
        p.extend(random_points(self.random_points, self.seed));
        p
    }
}

/// One warp × variant × shape × scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionCell {
    /// The warp (one of [`WARPS`]).
    pub warp: String,
    /// The variant (see [`warp_variants`]).
    pub variant: String,
    /// The shape.
    pub shape: String,
    /// `true` for a shape of a hard ladder.
    pub hard: bool,
    /// `f32` or `f64`.
    pub scalar: String,
    /// `true` if the constructor in this scalar rejects the shape (e.g. it
    /// rounds to a degenerate one); the other fields are then 0.
    pub rejected: bool,
    /// Number of points.
    pub points: usize,
    /// Max error against the exact map, units of `u_T · extent`, over the
    /// finite points.
    pub max_ulps: f64,
    /// Median of the same.
    pub median_ulps: f64,
    /// The input with the max error.
    pub worst: Option<(f64, f64)>,
    /// Max error against the variant's own map at 256 bits (the rounding
    /// error alone; equal to `max_ulps` for an exact variant).
    pub own_max_ulps: f64,
    /// Points where the map in this scalar returned NaN or ∞.
    pub non_finite: usize,
    /// Points where the 256-bit reference was not finite (a bug).
    pub reference_non_finite: usize,
    /// Points outside the shape by more than
    /// [`OUTSIDE_TOLERANCE_ULPS`]` · u_T · extent`.
    pub outside: usize,
    /// Max distance outside the shape, units of `u_T · extent`.
    pub max_outside_ulps: f64,
    /// Max over the points of error / (16 · max(u_T, κ)); `None` if κ
    /// could not be computed (see [`PrecisionCell::kappa_error`]).
    pub max_kappa_ratio: Option<f64>,
    /// The input with the largest ratio.
    pub worst_kappa_ratio: Option<(f64, f64)>,
    /// Max κ over the points, units of `u_T`.
    pub max_kappa_ulps: Option<f64>,
    /// Points outside the shape by more than their bound 16 · max(u_T, κ).
    pub outside_bound: usize,
    /// Why κ is missing, if it is.
    pub kappa_error: Option<String>,
    /// `max |J · pdf − 1|` of the variant's map at 256 bits (the same for
    /// both scalars).
    pub jacobian_max_dev: f64,
    /// Points where `J · pdf` was not finite even after the harness's nudge.
    pub jacobian_non_finite: usize,
}

/// One warp × variant × scalar, over all the warp's shapes.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionSummary {
    /// The warp.
    pub warp: String,
    /// The variant.
    pub variant: String,
    /// `f32` or `f64`.
    pub scalar: String,
    /// Shapes measured (accepted by the scalar).
    pub shapes: usize,
    /// Shapes the scalar's constructor rejects.
    pub rejected: usize,
    /// Points evaluated (over the accepted shapes).
    pub points: usize,
    /// Max error against the exact map, units of `u_T · extent`.
    pub max_ulps: f64,
    /// The shape and input of the max error.
    pub worst: Option<(String, (f64, f64))>,
    /// The median error over all points of all shapes.
    pub median_ulps: f64,
    /// Max error against the variant's own 256-bit map.
    pub own_max_ulps: f64,
    /// NaN/∞ outputs.
    pub non_finite: usize,
    /// Reference NaN/∞ (bugs).
    pub reference_non_finite: usize,
    /// Points outside by more than 4 `u_T · extent`.
    pub outside: usize,
    /// Points outside by more than their κ bound.
    pub outside_bound: usize,
    /// Max κ-conditioned ratio over the shapes with κ.
    pub max_kappa_ratio: Option<f64>,
    /// The shape of that ratio.
    pub worst_kappa_shape: Option<String>,
    /// Shapes whose κ could not be computed.
    pub kappa_failures: usize,
    /// Max 256-bit Jacobian deviation over the shapes.
    pub jacobian_max_dev: f64,
    /// Non-finite `J · pdf` points over the shapes.
    pub jacobian_non_finite: usize,
}

/// The `f32` error of one warp over a grid of `[0, 1]²`.
#[derive(Clone, Debug, PartialEq)]
pub struct F32ErrorMap {
    /// The warp.
    pub warp: String,
    /// The variant.
    pub variant: String,
    /// The shape.
    pub shape: String,
    /// Nodes per side `n`.
    pub nodes: usize,
    /// Error at node `(u_i, v_j) = (i/(n−1), j/(n−1))` in units of
    /// `2⁻²⁴ · extent`, at index `j · n + i`; NaN where the `f32` map is not
    /// finite.
    pub values: Vec<f64>,
    /// Max over the finite nodes.
    pub max_ulps: f64,
    /// The node of the max.
    pub worst: (f64, f64),
    /// Median over the finite nodes.
    pub median_ulps: f64,
    /// Fraction of the finite nodes with an error above 4 units.
    pub above_4: f64,
    /// Nodes where the `f32` map is not finite.
    pub non_finite: usize,
}

/// The results of the precision study.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionStudy {
    /// The configuration it ran with.
    pub config: PrecisionConfig,
    /// Points per shape.
    pub points_per_shape: usize,
    /// Every warp × variant × shape × scalar, in catalogue order (shape,
    /// then scalar `f32`, `f64`, then variant).
    pub cells: Vec<PrecisionCell>,
    /// Every warp × variant × scalar.
    pub summary: Vec<PrecisionSummary>,
    /// Where the `f32` error lives, per warp (exact variant) and for the
    /// literal variants.
    pub f32_maps: Vec<F32ErrorMap>,
}

/// The warps, variants and shapes whose `f32` error is mapped: each warp's
/// exact variant on its first shape, the literal variants of the
/// solid-angle maps and the bare cubic of the projected polygon.
fn heat_map_cases(shapes: &[ShapeEntry]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for warp in WARPS {
        let Some(k) = shapes.iter().position(|s| s.warp == warp) else {
            continue;
        };
        for (j, (label, _)) in shapes[k].variants.iter().enumerate() {
            if j == 0 || *label == "literal" || *label == "cubic" || *label == "tilted axis" {
                out.push((k, j));
            }
        }
    }
    out
}

enum JobOut {
    Jacobian(Vec<(f64, usize)>),
    Cells(Vec<(PrecisionCell, Vec<f64>)>),
    Map(F32ErrorMap),
}

/// Runs the study on rayon's current thread pool (sequentially without the
/// `studies` feature's rayon); the result does not depend on the number of
/// threads.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for an invalid configuration; the
/// errors of building a catalogue shape in `f64` or at 256 bits (none for
/// the shipped shapes).
pub fn run(config: &PrecisionConfig) -> Result<PrecisionStudy, WarpError> {
    config.validate()?;
    let mut shapes = catalogue(config.max_shapes, config.max_polygons)?;
    if let Some(only) = &config.warps {
        shapes.retain(|e| only.iter().any(|w| w == e.warp));
    }
    let points = config.points();
    let maps = heat_map_cases(&shapes);
    let n = config.heat_map_nodes;
    let grid: Vec<(f64, f64)> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64)))
        .collect();
    // The heat maps first (the longest jobs), then per shape its
    // Jacobians, its f32 cells and its f64 cells.
    let jobs = maps.len() + 3 * shapes.len();
    let results = run_jobs(jobs, config.seed, |i, _rng| -> Result<JobOut, WarpError> {
        if i < maps.len() {
            let (k, j) = maps[i];
            let e = &shapes[k];
            let (label, built) = &e.variants[j];
            let outcomes = with_warp!(built, |w| point_errors::<f32, _>(w, &grid))?;
            return Ok(JobOut::Map(error_map(e, label, n, &grid, &outcomes)));
        }
        let i = i - maps.len();
        let e = &shapes[i / 3];
        match i % 3 {
            0 => jacobians(e, &points).map(JobOut::Jacobian),
            1 => scalar_cells::<f32>(e, &points).map(JobOut::Cells),
            _ => scalar_cells::<f64>(e, &points).map(JobOut::Cells),
        }
    });
    let mut cells = Vec::new();
    let mut f32_maps = Vec::new();
    let mut jac = Vec::new();
    for r in results {
        match r? {
            JobOut::Jacobian(j) => jac = j,
            JobOut::Cells(c) => {
                // The variants of one scalar, in order: the Jacobian of
                // variant j belongs to cell j.
                for (j, (mut cell, errs)) in c.into_iter().enumerate() {
                    if let Some(&(dev, bad)) = jac.get(j) {
                        cell.jacobian_max_dev = dev;
                        cell.jacobian_non_finite = bad;
                    }
                    cells.push((cell, errs));
                }
            }
            JobOut::Map(m) => f32_maps.push(m),
        }
    }
    let summary = summarize(&cells);
    Ok(PrecisionStudy {
        config: config.clone(),
        points_per_shape: points.len(),
        cells: cells.into_iter().map(|(c, _)| c).collect(),
        summary,
        f32_maps,
    })
}
