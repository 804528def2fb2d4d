//! The papers' sample-distribution figures, re-made from our maps, each
//! with a number measured on the drawn samples that a picture alone cannot
//! show.
//!
//! | figure | paper | ours | measured |
//! |---|---|---|---|
//! | uniform vs jittered samples on a spherical triangle | Arvo 1995, Fig. 2; Arvo 2001, Fig. 1.1 | [`SphericalTriangle`], `N = k²` independent uniform `(u, v)` and `k × k` jittered `(u, v)`, Lambert equal-area projection about the triangle's centroid direction | χ² of the counts in the `4^L` sub-triangles of a midpoint subdivision against `N Ω_i / Ω`; smallest angular distance between two samples |
//! | cosine-weighted samples in a non-convex polygon | Arvo 2001, Fig. 1.2 and 1.11 | [`ProjectedPolygon`] of a comb-shaped light in the plane `z = 1`, drawn in the receiver's plane `(x, y)` of the direction (Nusselt: cosine-weighted samples are uniform there) | samples inside the polygon (an independent point-in-polygon test in the light's plane); χ² of the counts in light-plane cells against the exact projected solid angles (Lambert's formula) and, for contrast, against the solid angles |
//! | Hammersley points on a spherical rectangle, and pulled back to the rectangle | Ureña, Fajardo & King 2013, Fig. 5 | [`SphericalRectangle`] of a rectangle on the ground seen from close above its near edge: the directions (equal-area projection) and the points on the rectangle, with the grid of equal-solid-angle cells; area sampling of the same points for contrast | samples per equal-solid-angle cell (exactly 1 vs. a wide spread for area sampling); the fraction of samples in the near quarter against the exact solid-angle fraction |
//!
//! The projections: the *Lambert azimuthal equal-area projection* about a
//! unit direction `c` sends the unit direction `d` at angle θ from `c` to
//! the point at radius `2 sin(θ/2) = |d − c|` in the direction of `d`'s
//! component perpendicular to `c`; it preserves area, so uniform directions
//! are uniform in the plot. Both views are as seen from the centre of the
//! sphere (the observer), looking along `c`. The receiver-plane view of the
//! polygon is the orthographic projection `(x, y)` of the direction (normal
//! `+z`), in which cosine-weighted directions are uniform.
//!
//! # Example
//! ```
//! use areawarp_lab::studies::sample_figures::{SampleFiguresConfig, run};
//!
//! let study = run(&SampleFiguresConfig::quick())?;
//! // Every cosine-weighted sample lies inside the non-convex polygon.
//! assert_eq!(study.polygon.jittered_inside, study.polygon.jittered.len());
//! // Hammersley points through the spherical rectangle map: one per
//! // equal-solid-angle cell.
//! assert_eq!(study.rectangle.solid_angle_cells, (1, 1));
//! assert!(study.to_markdown().contains("samples_spherical_triangle_jittered.svg"));
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use crate::figures::{self, Axis, Figure, PALETTE, Plot, Rgb, Series};
use areawarp::error::WarpError;
use areawarp::sampling::{hammersley, jittered};
use areawarp::shapes::polygon_measures::{projected_solid_angle, triangle_solid_angle};
use areawarp::shapes::{ProjectedPolygon, SphericalRectangle, SphericalTriangle};
use areawarp::vector::Vec3;
use areawarp::warp::Warp;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};
pub(crate) mod experiments;
pub(crate) mod output;
#[cfg(test)]
mod tests;
use self::experiments::*;
// ---------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------

/// The study's sizes and seed.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleFiguresConfig {
    /// Master seed of the random and jittered sets.
    pub seed: u64,
    /// Strata per side `k` of the jittered sets of the triangle and polygon
    /// figures (`N = k²` samples; the uniform random sets have the same `N`).
    pub strata: usize,
    /// Strata per side `m` of the larger sets the triangle's and polygon's
    /// uniformity measures are taken on (`m²` uniform random and `m × m`
    /// jittered samples from the same maps; the figures show `k²`).
    pub measure_strata: usize,
    /// Hammersley points of the rectangle figure: a power of 4, `4^m`, so
    /// that the grid of equal-solid-angle cells has `2^m × 2^m` cells (one
    /// per point: the set is a `(0, 2m, 2)`-net in base 2).
    pub hammersley_points: usize,
    /// Levels `L` of midpoint subdivision of the triangle for its uniformity
    /// measure (`4^L` sub-triangles), 1 to 4.
    pub triangle_levels: u32,
    /// Side of the square cells in the polygon's plane (`z = 1`) for its
    /// uniformity measure; cells expecting fewer than 5 samples are pooled.
    pub polygon_cell: f64,
}

impl SampleFiguresConfig {
    /// A quick run (milliseconds): 8 × 8 strata drawn, 16 × 16 measured, 64
    /// Hammersley points,
    /// 4 sub-triangles, polygon cells of side 0.9.
    pub fn quick() -> Self {
        SampleFiguresConfig {
            seed: 0x5A3D_F16E,
            strata: 8,
            measure_strata: 16,
            hammersley_points: 64,
            triangle_levels: 1,
            polygon_cell: 0.9,
        }
    }

    fn validate(&self) -> Result<(), WarpError> {
        if !(2..=64).contains(&self.strata) {
            return Err(WarpError::InvalidParameter {
                name: "strata",
                expected: "2 to 64 strata per side",
            });
        }
        if !(2..=256).contains(&self.measure_strata) {
            return Err(WarpError::InvalidParameter {
                name: "measure_strata",
                expected: "2 to 256 strata per side",
            });
        }
        let n = self.hammersley_points;
        if !(4..=1 << 16).contains(&n)
            || !n.is_power_of_two()
            || !n.trailing_zeros().is_multiple_of(2)
        {
            return Err(WarpError::InvalidParameter {
                name: "hammersley_points",
                expected: "a power of 4 from 4 to 65536",
            });
        }
        if !(1..=4).contains(&self.triangle_levels) {
            return Err(WarpError::InvalidParameter {
                name: "triangle_levels",
                expected: "1 to 4 subdivision levels",
            });
        }
        if !(self.polygon_cell.is_finite() && self.polygon_cell >= 0.05 && self.polygon_cell <= 2.0)
        {
            return Err(WarpError::InvalidParameter {
                name: "polygon_cell",
                expected: "a cell side from 0.05 to 2",
            });
        }
        Ok(())
    }
}

impl Default for SampleFiguresConfig {
    /// The report's size, the papers' 256 samples: 16 × 16 strata drawn,
    /// 64 × 64 measured, 256 Hammersley points, 16 sub-triangles, polygon cells of side 0.6.
    fn default() -> Self {
        SampleFiguresConfig {
            strata: 16,
            measure_strata: 64,
            hammersley_points: 256,
            triangle_levels: 2,
            polygon_cell: 0.6,
            ..Self::quick()
        }
    }
}

// ---------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------

/// Figure 1: uniform and jittered samples on a spherical triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleSamples {
    /// The unit vertices A, B, C.
    pub vertices: [Vec3<f64>; 3],
    /// The solid angle Ω (sr).
    pub solid_angle: f64,
    /// The unit centroid direction `(A + B + C)/|A + B + C|`, the centre of
    /// the projection.
    pub centre: Vec3<f64>,
    /// `N` directions from independent uniform `(u, v)`.
    pub random: Vec<Vec3<f64>>,
    /// `N` directions from `k × k` jittered `(u, v)`.
    pub jittered: Vec<Vec3<f64>>,
    /// `M = m²`, the size of each of the two measured sets (uniform random
    /// and `m × m` jittered, drawn afresh from the same map).
    pub measure_samples: usize,
    /// The solid angles Ω_i of the `4^L` sub-triangles of the midpoint
    /// subdivision (Van Oosterom–Strackee), summing to Ω.
    pub cell_solid_angles: Vec<f64>,
    /// Samples of the measured random set in each sub-triangle.
    pub random_counts: Vec<usize>,
    /// Samples of the measured jittered set in each sub-triangle.
    pub jittered_counts: Vec<usize>,
    /// `Σ (n_i − M Ω_i/Ω)² / (M Ω_i/Ω)` for the measured random set (expected ≈ the
    /// number of cells − 1 for independent uniform samples).
    pub random_chi2: f64,
    /// The same for the jittered set.
    pub jittered_chi2: f64,
    /// The largest [`Warp::outside_by`] over all samples (drawn and
    /// measured).
    pub max_outside_by: f64,
}

/// Figure 2: cosine-weighted samples in a non-convex polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct PolygonSamples {
    /// The polygon's vertices in the light's plane `z = 1` (the receiver at
    /// the origin, normal `+z`).
    pub vertices: Vec<(f64, f64)>,
    /// Its projected solid angle Π (Lambert).
    pub projected_solid_angle: f64,
    /// Its solid angle Ω.
    pub solid_angle: f64,
    /// `N` directions from independent uniform `(u, v)`.
    pub random: Vec<Vec3<f64>>,
    /// `N` directions from `k × k` jittered `(u, v)`.
    pub jittered: Vec<Vec3<f64>>,
    /// Drawn random samples whose ray meets the light's plane inside the
    /// polygon (even–odd test, independent of the map).
    pub random_inside: usize,
    /// Drawn jittered samples inside the polygon.
    pub jittered_inside: usize,
    /// `M = m²`, the size of each of the two measured sets.
    pub measure_samples: usize,
    /// Samples of the two measured sets (`2M`) inside the polygon.
    pub measure_inside: usize,
    /// The largest [`Warp::outside_by`] over all samples (drawn and
    /// measured).
    pub max_outside_by: f64,
    /// The cell side in the light's plane.
    pub cell: f64,
    /// The exact expected fraction of cosine-weighted samples per (pooled)
    /// cell, `Π_i / Π`; the last entry pools the cells expecting fewer than
    /// 5 samples (absent if there are none).
    pub cell_fractions: Vec<f64>,
    /// The fraction of *uniform* (solid-angle) samples per pooled cell,
    /// `Ω_i / Ω`, for contrast.
    pub cell_fractions_uniform: Vec<f64>,
    /// Measured random samples per pooled cell.
    pub random_counts: Vec<usize>,
    /// Measured jittered samples per pooled cell.
    pub jittered_counts: Vec<usize>,
    /// χ² of the random counts against `M Π_i / Π`.
    pub random_chi2: f64,
    /// χ² of the jittered counts against `M Π_i / Π`.
    pub jittered_chi2: f64,
    /// χ² of the jittered counts against `M Ω_i / Ω` (uniform in solid
    /// angle): large, showing that the measure tells the two densities apart.
    pub jittered_chi2_uniform: f64,
}

/// Figure 3: Hammersley points on a spherical rectangle and on the
/// rectangle.
#[derive(Clone, Debug, PartialEq)]
pub struct RectangleSamples {
    /// The corner `s`.
    pub corner: Vec3<f64>,
    /// The edge `e_x`.
    pub edge_x: Vec3<f64>,
    /// The edge `e_y` (away from the observer's foot).
    pub edge_y: Vec3<f64>,
    /// The observer.
    pub observer: Vec3<f64>,
    /// The solid angle Ω (the map's).
    pub solid_angle: f64,
    /// Ω as the sum of the solid angles of the two triangles `s, s+e_x,
    /// s+e_x+e_y` and `s, s+e_x+e_y, s+e_y` (Van Oosterom–Strackee).
    pub solid_angle_triangles: f64,
    /// Cells per side `k` of the equal-solid-angle grid (`k² = N`).
    pub grid: usize,
    /// The `(u, v)` points: Hammersley `(i/N, φ₂(i))` moved to the centres
    /// of their `1/N × 1/N` cells (still a net, and off every cell border).
    pub uv: Vec<(f64, f64)>,
    /// The directions M(u, v) (solid-angle sampling).
    pub directions: Vec<Vec3<f64>>,
    /// The same samples pulled back to the rectangle: points M(u, v) on it.
    pub points: Vec<Vec3<f64>>,
    /// Area sampling of the same `(u, v)`: `s + u e_x + v e_y`.
    pub area_points: Vec<Vec3<f64>>,
    /// The grid lines: images of `u = i/k` (first `k + 1` lines) and of
    /// `v = j/k` (next `k + 1`), as points on the rectangle.
    pub grid_lines: Vec<Vec<Vec3<f64>>>,
    /// Fewest and most solid-angle samples in an equal-solid-angle cell.
    pub solid_angle_cells: (usize, usize),
    /// Equal-solid-angle cells without a solid-angle sample.
    pub solid_angle_empty_cells: usize,
    /// Fewest and most area samples in an equal-solid-angle cell.
    pub area_cells: (usize, usize),
    /// Equal-solid-angle cells without an area sample.
    pub area_empty_cells: usize,
    /// The near part of the rectangle: `η < near_depth` (fraction of `e_y`).
    pub near_depth: f64,
    /// Exact fraction of Ω subtended by the near part (two triangles).
    pub near_fraction_exact: f64,
    /// Solid-angle samples in the near part.
    pub near_count: usize,
    /// Area samples in the near part.
    pub area_near_count: usize,
    /// Exact fraction of Ω subtended by the far part `η > 1 − near_depth`.
    pub far_fraction_exact: f64,
    /// Solid-angle samples in the far part.
    pub far_count: usize,
    /// Area samples in the far part.
    pub area_far_count: usize,
}

/// Everything [`run`] measured.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleFigures {
    /// The configuration run.
    pub config: SampleFiguresConfig,
    /// Figure 1.
    pub triangle: TriangleSamples,
    /// Figure 2.
    pub polygon: PolygonSamples,
    /// Figure 3.
    pub rectangle: RectangleSamples,
}

/// Runs the study: the three sample sets and their measures.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for a configuration out of range (see
/// [`SampleFiguresConfig`]); the shapes' constructors' errors (not expected:
/// the shapes are fixed and valid).
pub fn run(config: &SampleFiguresConfig) -> Result<SampleFigures, WarpError> {
    config.validate()?;
    Ok(SampleFigures {
        config: config.clone(),
        triangle: run_triangle(config)?,
        polygon: run_polygon(config)?,
        rectangle: run_rectangle(config)?,
    })
}
