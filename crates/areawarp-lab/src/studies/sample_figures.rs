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

// ---------------------------------------------------------------------------
// Geometry helpers (f64 data)
// ---------------------------------------------------------------------------

fn v3(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}

fn unit(v: &Vec3<f64>) -> Vec3<f64> {
    v.normalized().unwrap_or(*v)
}

fn det(a: &Vec3<f64>, b: &Vec3<f64>, c: &Vec3<f64>) -> f64 {
    a.dot(&b.cross(c))
}

/// The Lambert azimuthal equal-area projection about `c`, seen from the
/// centre of the sphere looking along `c`, with `e1` to the right.
#[derive(Clone, Debug)]
struct EqualArea {
    c: Vec3<f64>,
    e1: Vec3<f64>,
    e2: Vec3<f64>,
}

impl EqualArea {
    /// About the unit direction `c`, with the component of `right` normal
    /// to `c` pointing right.
    fn about(c: &Vec3<f64>, right: &Vec3<f64>) -> Self {
        let c = unit(c);
        let e1 = right
            .sub(&c.scale(&right.dot(&c)))
            .normalized()
            .or_else(|| {
                let h = if c.x.abs() < 0.9 {
                    v3(1.0, 0.0, 0.0)
                } else {
                    v3(0.0, 1.0, 0.0)
                };
                h.sub(&c.scale(&h.dot(&c))).normalized()
            })
            .unwrap_or_else(|| v3(1.0, 0.0, 0.0));
        // Screen up = e1 × c: (e1, e2) is right-handed seen from the centre.
        let e2 = e1.cross(&c);
        EqualArea { c, e1, e2 }
    }

    fn project(&self, d: &Vec3<f64>) -> (f64, f64) {
        let d = unit(d);
        let (x, y) = (d.dot(&self.e1), d.dot(&self.e2));
        let h = x.hypot(y);
        if h == 0.0 {
            return (0.0, 0.0);
        }
        let rho = d.sub(&self.c).norm();
        (rho * x / h, rho * y / h)
    }
}

/// `n + 1` points along the minor great arc from `a` to `b` (normalized
/// linear interpolation: the chord's central projection is the arc).
fn great_arc(a: &Vec3<f64>, b: &Vec3<f64>, n: usize) -> Vec<Vec3<f64>> {
    (0..=n)
        .map(|i| unit(&a.lerp(b, &(i as f64 / n as f64))))
        .collect()
}

/// The closed outline of a polygon with vertex directions `v`, `n` points
/// per edge.
fn outline(v: &[Vec3<f64>], n: usize) -> Vec<Vec3<f64>> {
    let mut out = Vec::with_capacity(v.len() * n + 1);
    for i in 0..v.len() {
        let arc = great_arc(&v[i], &v[(i + 1) % v.len()], n);
        out.extend(arc.into_iter().take(n));
    }
    if let Some(first) = out.first().cloned() {
        out.push(first);
    }
    out
}

/// The fewest and most of `counts`.
fn min_max(counts: &[usize]) -> (usize, usize) {
    (
        counts.iter().copied().min().unwrap_or(0),
        counts.iter().copied().max().unwrap_or(0),
    )
}

/// `"a-b"`: the smallest and largest expected count `N Ω_i / Σ Ω`, 1 decimal.
fn expected_range(omegas: &[f64], n: usize) -> String {
    let total: f64 = omegas.iter().sum();
    let e = |o: f64| n as f64 * o / total;
    let lo = omegas.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = omegas.iter().copied().fold(0.0, f64::max);
    format!("{:.1}-{:.1}", e(lo), e(hi))
}

/// Σ (n_i − N p_i)² / (N p_i) over the cells with p_i > 0.
fn chi_square(counts: &[usize], fractions: &[f64]) -> f64 {
    let n: usize = counts.iter().sum();
    counts
        .iter()
        .zip(fractions)
        .filter(|(_, p)| **p > 0.0)
        .map(|(&c, &p)| {
            let e = n as f64 * p;
            (c as f64 - e).powi(2) / e
        })
        .sum()
}

// ---------------------------------------------------------------------------
// Figure 1: spherical triangle
// ---------------------------------------------------------------------------

/// The four sample sets of a direction map: drawn uniform random (`k²`),
/// drawn `k × k` jittered, measured uniform random (`m²`) and measured
/// `m × m` jittered, each from its own seed.
struct SampleSets {
    random: Vec<Vec3<f64>>,
    jittered: Vec<Vec3<f64>>,
    measure_random: Vec<Vec3<f64>>,
    measure_jittered: Vec<Vec3<f64>>,
}

impl SampleSets {
    fn draw<W: Warp<f64, Point = Vec3<f64>>>(w: &W, k: usize, m: usize, seed: u64) -> Self {
        let random = |n: usize, s: u64| -> Vec<Vec3<f64>> {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(s);
            (0..n)
                .map(|_| {
                    let (u, v) = (rng.random::<f64>(), rng.random::<f64>());
                    w.map(&u, &v)
                })
                .collect()
        };
        let strat = |n: usize, s: u64| -> Vec<Vec3<f64>> {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(s);
            jittered::<f64, _>(n, n, &mut rng)
                .iter()
                .map(|(u, v)| w.map(u, v))
                .collect()
        };
        SampleSets {
            random: random(k * k, seed ^ 0x11),
            jittered: strat(k, seed ^ 0x12),
            measure_random: random(m * m, seed ^ 0x13),
            measure_jittered: strat(m, seed ^ 0x14),
        }
    }

    fn all(&self) -> impl Iterator<Item = &Vec3<f64>> {
        self.random
            .iter()
            .chain(&self.jittered)
            .chain(&self.measure_random)
            .chain(&self.measure_jittered)
    }
}

/// The triangle: vertices in the plane z = 1 (normalized), Ω ≈ 1 sr.
fn triangle_vertices() -> [Vec3<f64>; 3] {
    [
        unit(&v3(-0.95, -0.62, 1.0)),
        unit(&v3(0.98, -0.42, 1.0)),
        unit(&v3(-0.05, 0.98, 1.0)),
    ]
}

/// `4^levels` sub-triangles by midpoint subdivision.
fn subdivide(t: [Vec3<f64>; 3], levels: u32) -> Vec<[Vec3<f64>; 3]> {
    let mut cells = vec![t];
    for _ in 0..levels {
        let mut next = Vec::with_capacity(cells.len() * 4);
        for [a, b, c] in cells {
            let ab = unit(&a.add(&b));
            let bc = unit(&b.add(&c));
            let ca = unit(&c.add(&a));
            next.push([a, ab, ca]);
            next.push([ab, b, bc]);
            next.push([ca, bc, c]);
            next.push([ab, bc, ca]);
        }
        cells = next;
    }
    cells
}

/// The cell containing `d`: the one where `d` is deepest inside (largest
/// smallest edge-plane distance, signed by the orientation), so that points
/// on shared edges are counted once.
fn triangle_cell(cells: &[[Vec3<f64>; 3]], d: &Vec3<f64>) -> usize {
    let mut best = (f64::NEG_INFINITY, 0);
    for (i, [a, b, c]) in cells.iter().enumerate() {
        let s = det(a, b, c).signum();
        let depth = (s * det(a, b, d))
            .min(s * det(b, c, d))
            .min(s * det(c, a, d));
        if depth > best.0 {
            best = (depth, i);
        }
    }
    best.1
}

fn run_triangle(c: &SampleFiguresConfig) -> Result<TriangleSamples, WarpError> {
    let [a, b, cc] = triangle_vertices();
    let tri = SphericalTriangle::<f64>::new(a, b, cc)?;
    let sets = SampleSets::draw(&tri, c.strata, c.measure_strata, c.seed ^ 0x7100);
    let cells = subdivide([a, b, cc], c.triangle_levels);
    let omegas: Vec<f64> = cells
        .iter()
        .map(|[p, q, r]| triangle_solid_angle(p, q, r).abs())
        .collect();
    let total: f64 = omegas.iter().sum();
    let fractions: Vec<f64> = omegas.iter().map(|o| o / total).collect();
    let count = |d: &[Vec3<f64>]| {
        let mut k = vec![0usize; cells.len()];
        for p in d {
            k[triangle_cell(&cells, p)] += 1;
        }
        k
    };
    let random_counts = count(&sets.measure_random);
    let jittered_counts = count(&sets.measure_jittered);
    let max_outside_by = sets.all().map(|p| tri.outside_by(p)).fold(0.0, f64::max);
    Ok(TriangleSamples {
        centre: unit(&a.add(&b).add(&cc)),
        vertices: [a, b, cc],
        solid_angle: tri.solid_angle(),
        random_chi2: chi_square(&random_counts, &fractions),
        jittered_chi2: chi_square(&jittered_counts, &fractions),
        cell_solid_angles: omegas,
        random_counts,
        jittered_counts,
        measure_samples: sets.measure_random.len(),
        random: sets.random,
        jittered: sets.jittered,
        max_outside_by,
    })
}

// ---------------------------------------------------------------------------
// Figure 2: projected (cosine-weighted) non-convex polygon
// ---------------------------------------------------------------------------

/// A comb with three teeth pointing to −y, in the plane z = 1, reaching
/// down to 22° above the horizon (the middle tooth covers the pole).
fn comb() -> Vec<(f64, f64)> {
    vec![
        (-1.9, -1.5),
        (-1.1, -1.5),
        (-1.1, 0.1),
        (-0.4, 0.1),
        (-0.4, -1.5),
        (0.4, -1.5),
        (0.4, 0.1),
        (1.1, 0.1),
        (1.1, -1.5),
        (1.9, -1.5),
        (1.9, 1.7),
        (-1.9, 1.7),
    ]
}

/// Even–odd point-in-polygon test in the plane.
fn inside_polygon(poly: &[(f64, f64)], p: (f64, f64)) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.1 > p.1) != (b.1 > p.1) {
            let x = a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
            if p.0 < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Sutherland–Hodgman clip of `poly` to the box `[x0, x1] × [y0, y1]` (a
/// non-convex polygon may come out with zero-width bridges, which cancel in
/// the signed measures below).
fn clip_to_box(poly: &[(f64, f64)], x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<(f64, f64)> {
    type Inside = fn(&(f64, f64), f64) -> bool;
    type Cut = fn(&(f64, f64), &(f64, f64), f64) -> (f64, f64);
    let cut_x: Cut = |a, b, x| (x, a.1 + (x - a.0) / (b.0 - a.0) * (b.1 - a.1));
    let cut_y: Cut = |a, b, y| (a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0), y);
    let planes: [(Inside, Cut, f64); 4] = [
        (|p, x| p.0 >= x, cut_x, x0),
        (|p, x| p.0 <= x, cut_x, x1),
        (|p, y| p.1 >= y, cut_y, y0),
        (|p, y| p.1 <= y, cut_y, y1),
    ];
    let mut out = poly.to_vec();
    for (inside, cut, k) in planes {
        let input = std::mem::take(&mut out);
        for i in 0..input.len() {
            let (cur, prev) = (&input[i], &input[(i + input.len() - 1) % input.len()]);
            match (inside(cur, k), inside(prev, k)) {
                (true, true) => out.push(*cur),
                (true, false) => {
                    out.push(cut(prev, cur, k));
                    out.push(*cur);
                }
                (false, true) => out.push(cut(prev, cur, k)),
                (false, false) => {}
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// `(|Ω|, |Π|)` of a polygon in the plane z = 1 (signed triangle fan from
/// its first vertex and Lambert's formula; both additive, so zero-width
/// bridges cancel).
fn plane_measures(poly: &[(f64, f64)]) -> (f64, f64) {
    if poly.len() < 3 {
        return (0.0, 0.0);
    }
    let d: Vec<Vec3<f64>> = poly.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
    let omega: f64 = (1..d.len() - 1)
        .map(|i| triangle_solid_angle(&d[0], &d[i], &d[i + 1]))
        .sum();
    let pi = projected_solid_angle(&d, &v3(0.0, 0.0, 1.0));
    (omega.abs(), pi.abs())
}

fn run_polygon(c: &SampleFiguresConfig) -> Result<PolygonSamples, WarpError> {
    let poly = comb();
    let dirs: Vec<Vec3<f64>> = poly.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
    let warp = ProjectedPolygon::<f64>::new(&dirs)?;
    let sets = SampleSets::draw(&warp, c.strata, c.measure_strata, c.seed ^ 0x9000);
    let n = sets.measure_random.len();
    let plane = |d: &Vec3<f64>| (d.x / d.z, d.y / d.z);
    let inside = |s: &[Vec3<f64>]| {
        s.iter()
            .filter(|d| d.z > 0.0 && inside_polygon(&poly, plane(d)))
            .count()
    };
    // Cells of side `cell` from the polygon's lower-left corner.
    let (x0, y0) = poly.iter().fold((f64::INFINITY, f64::INFINITY), |a, p| {
        (a.0.min(p.0), a.1.min(p.1))
    });
    let (x1, y1) = poly
        .iter()
        .fold((f64::NEG_INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.max(p.0), a.1.max(p.1))
        });
    let cell = c.polygon_cell;
    let cols = (((x1 - x0) / cell).ceil() as usize).max(1);
    let rows = (((y1 - y0) / cell).ceil() as usize).max(1);
    let (omega_total, pi_total) = plane_measures(&poly);
    let mut measures = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            let (a, b) = (x0 + i as f64 * cell, y0 + j as f64 * cell);
            measures.push(plane_measures(&clip_to_box(
                &poly,
                a,
                a + cell,
                b,
                b + cell,
            )));
        }
    }
    // Pool the cells expecting fewer than 5 cosine-weighted samples.
    let pooled = measures.len();
    let slot: Vec<usize> = {
        let mut next = 0;
        measures
            .iter()
            .map(|&(_, p)| {
                if n as f64 * p / pi_total >= 5.0 {
                    next += 1;
                    next - 1
                } else {
                    pooled
                }
            })
            .collect()
    };
    let kept = slot.iter().filter(|&&s| s != pooled).count();
    let has_pool = kept < measures.len();
    let slots = kept + usize::from(has_pool);
    let slot_of = |k: usize| if slot[k] == pooled { kept } else { slot[k] };
    let mut cos_frac = vec![0.0; slots];
    let mut uni_frac = vec![0.0; slots];
    for (k, &(o, p)) in measures.iter().enumerate() {
        cos_frac[slot_of(k)] += p / pi_total;
        uni_frac[slot_of(k)] += o / omega_total;
    }
    let count = |s: &[Vec3<f64>]| {
        let mut counts = vec![0usize; slots];
        for d in s {
            let (x, y) = plane(d);
            let i = (((x - x0) / cell).floor().max(0.0) as usize).min(cols - 1);
            let j = (((y - y0) / cell).floor().max(0.0) as usize).min(rows - 1);
            counts[slot_of(j * cols + i)] += 1;
        }
        counts
    };
    let random_counts = count(&sets.measure_random);
    let jittered_counts = count(&sets.measure_jittered);
    let max_outside_by = sets.all().map(|p| warp.outside_by(p)).fold(0.0, f64::max);
    Ok(PolygonSamples {
        projected_solid_angle: warp.projected_solid_angle(),
        solid_angle: warp.solid_angle(),
        random_inside: inside(&sets.random),
        jittered_inside: inside(&sets.jittered),
        measure_samples: n,
        measure_inside: inside(&sets.measure_random) + inside(&sets.measure_jittered),
        max_outside_by,
        cell,
        random_chi2: chi_square(&random_counts, &cos_frac),
        jittered_chi2: chi_square(&jittered_counts, &cos_frac),
        jittered_chi2_uniform: chi_square(&jittered_counts, &uni_frac),
        cell_fractions: cos_frac,
        cell_fractions_uniform: uni_frac,
        random_counts,
        jittered_counts,
        random: sets.random,
        jittered: sets.jittered,
        vertices: poly,
    })
}

// ---------------------------------------------------------------------------
// Figure 3: spherical rectangle
// ---------------------------------------------------------------------------

/// The rectangle: 2 × 2 on the ground `z = 0`, seen from 0.5 above a point
/// 0.25 before its near edge.
fn rectangle_geometry() -> [Vec3<f64>; 4] {
    [
        v3(-1.0, 0.0, 0.0),
        v3(2.0, 0.0, 0.0),
        v3(0.0, 2.0, 0.0),
        v3(0.0, -0.25, 0.5),
    ]
}

/// Ω of the part `η ∈ [a, b]` of the rectangle (fractions of `e_y`) as two
/// triangles.
fn strip_solid_angle(g: &[Vec3<f64>; 4], a: f64, b: f64) -> f64 {
    let [s, ex, ey, o] = g;
    let p = |xi: f64, eta: f64| s.add(&ex.scale(&xi)).add(&ey.scale(&eta)).sub(o);
    let (p0, p1, p2, p3) = (p(0.0, a), p(1.0, a), p(1.0, b), p(0.0, b));
    triangle_solid_angle(&p0, &p1, &p2).abs() + triangle_solid_angle(&p0, &p2, &p3).abs()
}

fn run_rectangle(c: &SampleFiguresConfig) -> Result<RectangleSamples, WarpError> {
    let g = rectangle_geometry();
    let [s, ex, ey, o] = g;
    let rect = SphericalRectangle::<f64>::new(s, ex, ey, o)?;
    let n = c.hammersley_points;
    let k = 1usize << (n.trailing_zeros() / 2);
    let half = 0.5 / n as f64;
    let uv: Vec<(f64, f64)> = hammersley::<f64>(n)
        .into_iter()
        .map(|(u, v)| (u + half, v + half))
        .collect();
    let mut directions = Vec::with_capacity(n);
    let mut points = Vec::with_capacity(n);
    for (u, v) in &uv {
        let (p, d) = rect.sample_point(u, v);
        points.push(p);
        directions.push(d);
    }
    let area_points: Vec<Vec3<f64>> = uv
        .iter()
        .map(|(u, v)| s.add(&ex.scale(u)).add(&ey.scale(v)))
        .collect();
    // The grid of equal-solid-angle cells: images of u = i/k and v = j/k.
    let steps = 48;
    let mut grid_lines = Vec::with_capacity(2 * k + 2);
    for fixed_u in [true, false] {
        for i in 0..=k {
            let a = i as f64 / k as f64;
            grid_lines.push(
                (0..=steps)
                    .map(|t| {
                        let b = t as f64 / steps as f64;
                        let (u, v) = if fixed_u { (a, b) } else { (b, a) };
                        rect.sample_point(&u, &v).0
                    })
                    .collect(),
            );
        }
    }
    let cells = |pts: &[Vec3<f64>]| -> Vec<usize> {
        let mut counts = vec![0usize; k * k];
        for p in pts {
            if let Ok([u, v]) = rect.inverse(&unit(&p.sub(&o))) {
                let i = ((u * k as f64) as usize).min(k - 1);
                let j = ((v * k as f64) as usize).min(k - 1);
                counts[j * k + i] += 1;
            }
        }
        counts
    };
    let range = |v: &[usize]| {
        (
            v.iter().copied().min().unwrap_or(0),
            v.iter().copied().max().unwrap_or(0),
        )
    };
    let sa_cells = cells(&points);
    let area_cells = cells(&area_points);
    let near_depth = 0.25;
    let omega_tri = strip_solid_angle(&g, 0.0, 1.0);
    let yhat = unit(&ey);
    let eta = |p: &Vec3<f64>| p.sub(&s).dot(&yhat) / ey.norm();
    Ok(RectangleSamples {
        solid_angle: rect.solid_angle(),
        solid_angle_triangles: omega_tri,
        grid: k,
        solid_angle_cells: range(&sa_cells),
        area_cells: range(&area_cells),
        solid_angle_empty_cells: sa_cells.iter().filter(|&&x| x == 0).count(),
        area_empty_cells: area_cells.iter().filter(|&&x| x == 0).count(),
        near_depth,
        near_fraction_exact: strip_solid_angle(&g, 0.0, near_depth) / omega_tri,
        near_count: points.iter().filter(|p| eta(p) < near_depth).count(),
        area_near_count: area_points.iter().filter(|p| eta(p) < near_depth).count(),
        far_fraction_exact: strip_solid_angle(&g, 1.0 - near_depth, 1.0) / omega_tri,
        far_count: points.iter().filter(|p| eta(p) > 1.0 - near_depth).count(),
        area_far_count: area_points
            .iter()
            .filter(|p| eta(p) > 1.0 - near_depth)
            .count(),
        corner: s,
        edge_x: ex,
        edge_y: ey,
        observer: o,
        uv,
        directions,
        points,
        area_points,
        grid_lines,
    })
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

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

const OUTLINE: Rgb = Rgb(40, 40, 40);
const SAMPLES: Rgb = PALETTE[0];
/// A light red, so that the samples stay visible over the grid.
const GRID: Rgb = Rgb(236, 128, 128);
const SQUARE: (u32, u32) = (600, 600);
const WIDE: (u32, u32) = (760, 480);

/// A CSV field, quoted (with doubled quotes) if it holds a comma, a quote
/// or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A series of separate dots for [`figures::write_line_plot_svg`]: the
/// points separated by NaN, so that no line joins them.
fn dots(label: &str, pts: &[(f64, f64)], color: Rgb) -> Series {
    let mut v = Vec::with_capacity(2 * pts.len());
    for &p in pts {
        v.push(p);
        v.push((f64::NAN, f64::NAN));
    }
    Series::new(label, v).with_color(color)
}

/// A line (no markers).
fn line(label: &str, pts: Vec<(f64, f64)>, color: Rgb) -> Series {
    let mut s = Series::new(label, pts).with_color(color);
    s.markers = false;
    s
}

/// The points of a polyline at spacing at most `step` (for rasters, where
/// lines are drawn as dense dots).
fn densify(pts: &[(f64, f64)], step: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let k = ((len / step).ceil() as usize).clamp(1, 100_000);
        for i in 0..k {
            let t = i as f64 / k as f64;
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    if let Some(last) = pts.last() {
        out.push(*last);
    }
    out
}

/// A labelled set of points in one colour (a line or a set of dots).
type Layer = (String, Vec<(f64, f64)>, Rgb);

/// One drawing: lines (outline, grid) and dot sets, written as SVG (line
/// plot with separated markers, `size` pixels) and PNG (no text, 4/5 of
/// the size; dots as small discs, lines as dense dots).
struct Drawing {
    title: String,
    x: String,
    y: String,
    size: (u32, u32),
    lines: Vec<Layer>,
    dots: Vec<Layer>,
}

impl Drawing {
    fn write(&self, dir: &Path, stem: &str) -> io::Result<Vec<Figure>> {
        let mut plot = Plot::new(&self.title, Axis::linear(&self.x), Axis::linear(&self.y))
            .size(self.size.0, self.size.1)
            .equal_aspect()
            .point_radius(2.5);
        for (label, pts, color) in &self.lines {
            plot = plot.series(line(label, pts.clone(), *color));
        }
        for (label, pts, color) in &self.dots {
            plot = plot.series(dots(label, pts, *color));
        }
        let svg = figures::write_line_plot_svg(&dir.join(format!("{stem}.svg")), &plot)?;
        // Raster: data units per pixel (equal aspect, the axes' 4% padding).
        let (w, h) = (self.size.0 * 4 / 5, self.size.1 * 4 / 5);
        let all = self
            .lines
            .iter()
            .flat_map(|l| l.1.iter())
            .chain(self.dots.iter().flat_map(|d| d.1.iter()));
        let (lo, hi) = all.fold(
            (
                (f64::INFINITY, f64::INFINITY),
                (f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(lo, hi), p| {
                (
                    (lo.0.min(p.0), lo.1.min(p.1)),
                    (hi.0.max(p.0), hi.1.max(p.1)),
                )
            },
        );
        let per_px = ((hi.0 - lo.0) / (w as f64 - 16.0))
            .max((hi.1 - lo.1) / (h as f64 - 16.0))
            .max(f64::MIN_POSITIVE)
            * 1.08;
        let mut raster = Plot::new(&self.title, Axis::linear(""), Axis::linear(""))
            .size(w, h)
            .equal_aspect()
            .point_radius(0.8);
        // Lines: dots a third of a pixel apart.
        for (label, pts, color) in &self.lines {
            raster =
                raster.series(Series::new(label, densify(pts, per_px / 3.0)).with_color(*color));
        }
        // Samples: discs of radius ≈ 2 px, as 9 dots each.
        let r = 1.3 * per_px;
        let d = r / std::f64::consts::SQRT_2;
        for (label, pts, color) in &self.dots {
            let disc: Vec<(f64, f64)> = pts
                .iter()
                .flat_map(|&(x, y)| {
                    [
                        (0.0, 0.0),
                        (r, 0.0),
                        (-r, 0.0),
                        (0.0, r),
                        (0.0, -r),
                        (d, d),
                        (d, -d),
                        (-d, d),
                        (-d, -d),
                    ]
                    .map(|(dx, dy)| (x + dx, y + dy))
                })
                .collect();
            raster = raster.series(Series::new(label, disc).with_color(*color));
        }
        let png = figures::write_scatter_png(&dir.join(format!("{stem}.png")), &raster)?;
        Ok(vec![svg, png])
    }
}

impl SampleFigures {
    /// The file names [`SampleFigures::write_figures`] writes, in order
    /// (each as `.svg` and `.png`).
    pub fn figure_stems() -> [&'static str; 7] {
        [
            "samples_spherical_triangle_random",
            "samples_spherical_triangle_jittered",
            "samples_projected_polygon_random",
            "samples_projected_polygon_jittered",
            "samples_spherical_rectangle_directions",
            "samples_spherical_rectangle_points",
            "samples_spherical_rectangle_area",
        ]
    }

    /// Writes the figures into `dir` (created if needed), each as SVG (with
    /// axes) and PNG (no text): the triangle with random and with jittered
    /// samples (equal-area projection about its centroid direction), the
    /// comb polygon with random and jittered cosine-weighted samples (the
    /// receiver's plane), and the rectangle's Hammersley samples as
    /// directions (equal-area projection) and as points on the rectangle,
    /// with the equal-solid-angle grid, plus area sampling of the same
    /// points for contrast. Names: [`SampleFigures::figure_stems`].
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        let [s1, s2, s3, s4, s5, s6, s7] = Self::figure_stems();

        // 1. The triangle.
        let t = &self.triangle;
        let proj = EqualArea::about(&t.centre, &v3(1.0, 0.0, 0.0));
        let tri_outline: Vec<(f64, f64)> = outline(&t.vertices, 128)
            .iter()
            .map(|d| proj.project(d))
            .collect();
        let axis_x = "equal-area projection about the centroid direction, seen from the centre";
        let axis_y = "";
        for (stem, name, set) in [
            (s1, "uniform random", &t.random),
            (s2, "jittered", &t.jittered),
        ] {
            let pts: Vec<(f64, f64)> = set.iter().map(|d| proj.project(d)).collect();
            let d = Drawing {
                title: format!(
                    "{} {name} samples on a spherical triangle (Ω = {:.2} sr)",
                    set.len(),
                    t.solid_angle
                ),
                x: axis_x.into(),
                y: axis_y.into(),
                size: SQUARE,
                lines: vec![(String::new(), tri_outline.clone(), OUTLINE)],
                dots: vec![(String::new(), pts, SAMPLES)],
            };
            out.extend(d.write(dir, stem)?);
        }

        // 2. The polygon, in the receiver's plane.
        let p = &self.polygon;
        let corners: Vec<Vec3<f64>> = p.vertices.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
        let poly_outline: Vec<(f64, f64)> =
            outline(&corners, 128).iter().map(|d| (d.x, d.y)).collect();
        let horizon: Vec<(f64, f64)> = (0..=256)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 256.0;
                (a.cos(), a.sin())
            })
            .collect();
        for (stem, name, set) in [
            (s3, "uniform random", &p.random),
            (s4, "jittered", &p.jittered),
        ] {
            let pts: Vec<(f64, f64)> = set.iter().map(|d| (d.x, d.y)).collect();
            let d = Drawing {
                title: format!(
                    "{} {name} cosine-weighted samples in a non-convex polygon",
                    set.len()
                ),
                x: "x = sin θ cos φ (receiver's plane)".into(),
                y: "y = sin θ sin φ".into(),
                size: SQUARE,
                lines: vec![
                    ("horizon".into(), horizon.clone(), PALETTE[7]),
                    ("polygon".into(), poly_outline.clone(), OUTLINE),
                ],
                dots: vec![(String::new(), pts, SAMPLES)],
            };
            out.extend(d.write(dir, stem)?);
        }

        // 3. The rectangle: directions, points on it, area sampling.
        let r = &self.rectangle;
        let centre = r
            .corner
            .add(&r.edge_x.scale(&0.5))
            .add(&r.edge_y.scale(&0.5))
            .sub(&r.observer);
        let proj = EqualArea::about(&centre, &r.edge_x);
        let corners = [
            r.corner,
            r.corner.add(&r.edge_x),
            r.corner.add(&r.edge_x).add(&r.edge_y),
            r.corner.add(&r.edge_y),
        ];
        let rel: Vec<Vec3<f64>> = corners.iter().map(|c| c.sub(&r.observer)).collect();
        let dir_outline: Vec<(f64, f64)> =
            outline(&rel, 128).iter().map(|d| proj.project(d)).collect();
        let grid_label = format!("{0} × {0} cells of equal solid angle", r.grid);
        let grid_dirs: Vec<Layer> = r
            .grid_lines
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let label = if i == 0 {
                    grid_label.clone()
                } else {
                    String::new()
                };
                let pts = l
                    .iter()
                    .map(|p| proj.project(&p.sub(&r.observer)))
                    .collect();
                (label, pts, GRID)
            })
            .collect();
        // On the rectangle a legend would cover the observer's foot: the
        // axis label explains the colours instead.
        let grid_flat_label =
            format!("x along e_x    (red: {grid_label}; orange: the observer's foot)");
        let mut lines = grid_dirs;
        lines.push(("spherical rectangle".into(), dir_outline, OUTLINE));
        let d = Drawing {
            title: format!(
                "{} Hammersley points mapped to a spherical rectangle (Ω = {:.3} sr)",
                r.directions.len(),
                r.solid_angle
            ),
            x: "equal-area projection about the centre's direction, seen from the observer".into(),
            y: String::new(),
            size: WIDE,
            lines,
            dots: vec![(
                String::new(),
                r.directions.iter().map(|d| proj.project(d)).collect(),
                SAMPLES,
            )],
        };
        out.extend(d.write(dir, s5)?);
        let xhat = unit(&r.edge_x);
        let yhat = unit(&r.edge_y);
        let flat = |p: &Vec3<f64>| {
            let q = p.sub(&r.corner);
            (q.dot(&xhat), q.dot(&yhat))
        };
        let grid_flat: Vec<Layer> = r
            .grid_lines
            .iter()
            .map(|l| (String::new(), l.iter().map(flat).collect(), GRID))
            .collect();
        let foot = flat(&r.observer);
        for (stem, title, set) in [
            (
                s6,
                format!(
                    "{} Hammersley points, solid-angle sampling, pulled back to the rectangle",
                    r.points.len()
                ),
                &r.points,
            ),
            (
                s7,
                format!(
                    "the same {} points, area sampling, on the rectangle",
                    r.area_points.len()
                ),
                &r.area_points,
            ),
        ] {
            let d = Drawing {
                title,
                x: grid_flat_label.clone(),
                y: "y along e_y (away from the observer)".into(),
                size: SQUARE,
                lines: grid_flat.clone(),
                dots: vec![
                    (String::new(), set.iter().map(flat).collect(), SAMPLES),
                    (String::new(), vec![foot], PALETTE[1]),
                ],
            };
            out.extend(d.write(dir, stem)?);
        }
        Ok(out)
    }

    /// Writes `sample_figures.csv` (figure, quantity, measured, reference:
    /// the numbers of the Markdown tables) into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut s = String::from("figure,quantity,measured,reference\n");
        for (fig, q, m, r) in self.rows() {
            let _ = writeln!(
                s,
                "{},{},{},{}",
                csv_field(fig),
                csv_field(&q),
                csv_field(&m),
                csv_field(&r)
            );
        }
        let path = dir.join("sample_figures.csv");
        std::fs::write(&path, s)?;
        Ok(vec![path])
    }

    /// The measured numbers: (figure, quantity, measured, reference), the
    /// reference empty where there is none.
    fn rows(&self) -> Vec<(&'static str, String, String, String)> {
        let t = &self.triangle;
        let p = &self.polygon;
        let r = &self.rectangle;
        let g = |x: f64| format!("{x:.4}");
        let range = |(a, b): (usize, usize)| format!("{a}-{b}");
        let m_t = t.measure_samples;
        let m_p = p.measure_samples;
        let n_r = r.points.len() as f64;
        let tri_cells = t.cell_solid_angles.len();
        let poly_cells = p.cell_fractions.len();
        vec![
            (
                "triangle",
                "solid angle (sr); reference: sum over the sub-triangles".into(),
                g(t.solid_angle),
                g(t.cell_solid_angles.iter().sum()),
            ),
            (
                "triangle",
                format!("chi2 over {tri_cells} sub-triangles, {m_t} uniform random; reference: degrees of freedom"),
                g(t.random_chi2),
                (tri_cells - 1).to_string(),
            ),
            (
                "triangle",
                format!("chi2 over {tri_cells} sub-triangles, {m_t} jittered"),
                g(t.jittered_chi2),
                String::new(),
            ),
            (
                "triangle",
                "samples per sub-triangle (min-max), uniform random; reference: expected".into(),
                range(min_max(&t.random_counts)),
                expected_range(&t.cell_solid_angles, m_t),
            ),
            (
                "triangle",
                "samples per sub-triangle (min-max), jittered; reference: expected".into(),
                range(min_max(&t.jittered_counts)),
                expected_range(&t.cell_solid_angles, m_t),
            ),
            (
                "triangle",
                "largest outside_by".into(),
                format!("{:e}", t.max_outside_by),
                String::new(),
            ),
            (
                "polygon",
                "projected solid angle (sr); reference: Lambert's formula".into(),
                g(p.projected_solid_angle),
                g(plane_measures(&p.vertices).1),
            ),
            (
                "polygon",
                "drawn samples inside the polygon, uniform random".into(),
                p.random_inside.to_string(),
                p.random.len().to_string(),
            ),
            (
                "polygon",
                "drawn samples inside the polygon, jittered".into(),
                p.jittered_inside.to_string(),
                p.jittered.len().to_string(),
            ),
            (
                "polygon",
                "measured samples inside the polygon, both sets".into(),
                p.measure_inside.to_string(),
                (2 * m_p).to_string(),
            ),
            (
                "polygon",
                format!("chi2 over {poly_cells} cells vs cosine-weighted, {m_p} uniform random; reference: degrees of freedom"),
                g(p.random_chi2),
                (poly_cells - 1).to_string(),
            ),
            (
                "polygon",
                format!("chi2 over {poly_cells} cells vs cosine-weighted, {m_p} jittered"),
                g(p.jittered_chi2),
                String::new(),
            ),
            (
                "polygon",
                format!("chi2 over {poly_cells} cells vs uniform in solid angle, {m_p} jittered"),
                g(p.jittered_chi2_uniform),
                String::new(),
            ),
            (
                "polygon",
                "largest outside_by".into(),
                format!("{:e}", p.max_outside_by),
                String::new(),
            ),
            (
                "rectangle",
                "solid angle (sr); reference: two triangles".into(),
                g(r.solid_angle),
                g(r.solid_angle_triangles),
            ),
            (
                "rectangle",
                "samples per equal-solid-angle cell (min-max), solid-angle sampling".into(),
                range(r.solid_angle_cells),
                "1-1".into(),
            ),
            (
                "rectangle",
                "samples per equal-solid-angle cell (min-max), area sampling".into(),
                range(r.area_cells),
                "1-1".into(),
            ),
            (
                "rectangle",
                "empty equal-solid-angle cells, area sampling".into(),
                r.area_empty_cells.to_string(),
                "0".into(),
            ),
            (
                "rectangle",
                "samples in the near quarter, solid-angle sampling; reference: N x solid-angle fraction".into(),
                r.near_count.to_string(),
                g(r.near_fraction_exact * n_r),
            ),
            (
                "rectangle",
                "samples in the far quarter, solid-angle sampling; reference: N x solid-angle fraction".into(),
                r.far_count.to_string(),
                g(r.far_fraction_exact * n_r),
            ),
            (
                "rectangle",
                "samples in the near quarter, area sampling; reference: N x solid-angle fraction".into(),
                r.area_near_count.to_string(),
                g(r.near_fraction_exact * n_r),
            ),
            (
                "rectangle",
                "samples in the far quarter, area sampling; reference: N x solid-angle fraction".into(),
                r.area_far_count.to_string(),
                g(r.far_fraction_exact * n_r),
            ),
        ]
    }

    /// The report section (Markdown): per figure a caption (what the
    /// paper's figure showed, what ours shows), the SVG figures shown by
    /// file name (they sit beside the Markdown file, PNG versions linked)
    /// and the measured numbers.
    pub fn to_markdown(&self) -> String {
        let t = &self.triangle;
        let p = &self.polygon;
        let r = &self.rectangle;
        let mut s = String::new();
        let png_links = |stems: &[&str]| -> String {
            stems
                .iter()
                .map(|st| format!("[{st}.png]({st}.png)"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let _ = writeln!(
            s,
            "## Sample distributions: the papers' figures, re-made from our maps\n"
        );
        let _ = writeln!(
            s,
            "Each figure is drawn with the crate's maps in f64, and each comes with a number \
             that the picture alone does not give. Directions are shown either in the Lambert azimuthal \
             equal-area projection, which preserves area, so uniform directions look uniform, or, for \
             cosine-weighted samples, in the receiver's plane, where by Nusselt's analogy cosine-weighted \
             directions are uniform. Both views are as seen from the centre of the sphere. The triangle's and \
             the polygon's counting measures compare counts in cells of exactly known measure with their \
             expectations and do not use the map being tested; the rectangle's cells are the map's own \
             images of a grid, and its near and far quarters are checked against solid angles computed \
             independently. Data: `sample_figures.csv`.\n"
        );

        // 1.
        let k = self.config.strata;
        let n = t.random.len();
        let m = t.measure_samples;
        let cells = t.cell_solid_angles.len();
        let _ = writeln!(
            s,
            "### Uniform and jittered samples on a spherical triangle (Arvo 1995, Fig. 2; Arvo 2001, Fig. 1.1)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** samples of a spherical triangle from Arvo's area-preserving map. On the left, \
             independent uniform (u, v) give the pattern of rejection sampling, but every sample lies in the \
             triangle. On the right, jittered (u, v), one per cell of a grid on the unit square, give \
             visibly more even samples. **Ours:** the same experiment with `SphericalTriangle` (robust \
             variant) on a triangle of Ω = {omega:.3} sr, with {n} samples in each panel ({k} × {k} strata), \
             in the equal-area projection about the triangle's centroid direction. **Measured:** the \
             triangle is cut into {cells} sub-triangles by {levels} level(s) of midpoint subdivision, with \
             exact Ω_i (Van Oosterom–Strackee). Counts from {m} fresh samples of each kind are compared \
             with M Ω_i / Ω. For independent uniform samples χ² is about its {dof} degrees of freedom. \
             For jittered samples it is far smaller, because only the strata that a sub-triangle's edges \
             cut contribute.\n",
            omega = t.solid_angle,
            levels = self.config.triangle_levels,
            dof = cells - 1,
        );
        let _ = writeln!(
            s,
            "| uniform random | jittered |\n|---|---|\n\
             | ![uniform random samples on a spherical triangle](samples_spherical_triangle_random.svg) \
             | ![jittered samples on a spherical triangle](samples_spherical_triangle_jittered.svg) |\n"
        );
        let (rmin, rmax) = min_max(&t.random_counts);
        let (jmin, jmax) = min_max(&t.jittered_counts);
        let _ = writeln!(
            s,
            "| {m} samples | χ² over {cells} sub-triangles ({dof} d.o.f.) | samples per sub-triangle (expected {exp}) |\n\
             |---|---:|---:|\n\
             | uniform random | {:.2} | {rmin}–{rmax} |\n\
             | jittered | {:.2} | {jmin}–{jmax} |\n",
            t.random_chi2,
            t.jittered_chi2,
            dof = cells - 1,
            exp = expected_range(&t.cell_solid_angles, m).replace('-', "–"),
        );
        let _ = writeln!(
            s,
            "PNG: {}.\n",
            png_links(&[
                "samples_spherical_triangle_random",
                "samples_spherical_triangle_jittered"
            ])
        );

        // 2.
        let n = p.random.len();
        let m = p.measure_samples;
        let cells = p.cell_fractions.len();
        let _ = writeln!(
            s,
            "### Cosine-weighted samples in a non-convex polygon (Arvo 2001, Fig. 1.2 and 1.11)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** a projected spherical polygon with uniform and with stratified samples, which \
             crowd towards the pole and thin out towards the horizon, and a non-convex spherical polygon \
             with cosine-weighted samples from Arvo's map. **Ours:** `ProjectedPolygon` of a comb-shaped \
             light with three teeth in the plane z = 1. The receiver is at the origin with normal +z; \
             Π = {pi:.4} and Ω = {omega:.4} sr. Each panel shows {n} samples, from uniform random and \
             from jittered (u, v), in the receiver's plane (x, y of the direction), with the polygon's \
             outline (projected great arcs) and the horizon. **Measured:** every sample's ray meets the \
             light's plane inside the comb, by an even–odd test that does not use the map: {ri} and {ji} \
             of the {n} drawn samples, and {mi} of the {mm} measured samples. For uniformity, the light's \
             plane is cut into squares of side {cell}. Lines in that plane are great circles, so each \
             square's part of the comb is a spherical polygon with an exact Ω_i and, by Lambert's formula, \
             an exact Π_i. The counts of {m} fresh samples of each kind are compared with M Π_i / Π by \
             χ² over {cells} cells; cells expecting fewer than 5 samples are pooled. The same jittered \
             counts give χ² = {cu:.1} against the expectation for samples uniform in solid angle, \
             M Ω_i / Ω, so the measure does detect the cosine weighting.\n",
            pi = p.projected_solid_angle,
            omega = p.solid_angle,
            ri = p.random_inside,
            ji = p.jittered_inside,
            mi = p.measure_inside,
            mm = 2 * m,
            cell = p.cell,
            cu = p.jittered_chi2_uniform,
        );
        let _ = writeln!(
            s,
            "| uniform random | jittered |\n|---|---|\n\
             | ![uniform random cosine-weighted samples in a non-convex polygon](samples_projected_polygon_random.svg) \
             | ![jittered cosine-weighted samples in a non-convex polygon](samples_projected_polygon_jittered.svg) |\n"
        );
        let _ = writeln!(
            s,
            "| {m} samples | χ² vs cosine-weighted, M Π_i/Π ({dof} d.o.f.) | χ² vs uniform in solid angle, M Ω_i/Ω |\n\
             |---|---:|---:|\n\
             | uniform random | {:.2} | {:.1} |\n\
             | jittered | {:.2} | {:.1} |\n",
            p.random_chi2,
            chi_square(&p.random_counts, &p.cell_fractions_uniform),
            p.jittered_chi2,
            p.jittered_chi2_uniform,
            dof = cells - 1,
        );
        let _ = writeln!(
            s,
            "PNG: {}.\n",
            png_links(&[
                "samples_projected_polygon_random",
                "samples_projected_polygon_jittered"
            ])
        );

        // 3.
        let n = r.points.len();
        let _ = writeln!(
            s,
            "### Hammersley points on a spherical rectangle, and pulled back to the rectangle (Ureña, Fajardo & King 2013, Fig. 5)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** 256 Hammersley points mapped to a spherical rectangle by several mappings and \
             projected back onto the planar rectangle, with a superimposed red grid whose cells all subtend \
             the same solid angle. With the solid-angle map the points follow the grid, crowding towards \
             the observer. **Ours:** `SphericalRectangle` of a 2 × 2 rectangle on the ground, seen from \
             0.5 above a point 0.25 before its near edge (Ω = {omega:.4} sr; {omega2:.4} sr as two \
             triangles). The {n} Hammersley points are moved to the centres of their 1/{n} cells, which \
             keeps them a net. The panels show the {k} × {k} grid of equal-solid-angle cells (the images \
             of u = i/{k} and v = j/{k}), the directions (equal-area projection), the points pulled back to \
             the rectangle, and, for contrast, area sampling of the same points. **Measured:** the number \
             of samples per equal-solid-angle cell, and the samples in the near and the far quarter of \
             the rectangle against the exact solid-angle fractions, computed as two triangles each.\n",
            omega = r.solid_angle,
            omega2 = r.solid_angle_triangles,
            k = r.grid,
        );
        let _ = writeln!(
            s,
            "| directions | pulled back to the rectangle | area sampling |\n|---|---|---|\n\
             | ![Hammersley points on a spherical rectangle](samples_spherical_rectangle_directions.svg) \
             | ![the same points pulled back to the rectangle](samples_spherical_rectangle_points.svg) \
             | ![area sampling of the same points](samples_spherical_rectangle_area.svg) |\n"
        );
        let near = r.near_fraction_exact * n as f64;
        let far = r.far_fraction_exact * n as f64;
        let _ = writeln!(
            s,
            "| {n} Hammersley points | samples per cell (min–max) | empty cells | near quarter (exact {near:.1}) | far quarter (exact {far:.1}) |\n\
             |---|---:|---:|---:|---:|\n\
             | solid-angle sampling (ours) | {}–{} | {} | {} | {} |\n\
             | area sampling | {}–{} | {} | {} | {} |\n",
            r.solid_angle_cells.0,
            r.solid_angle_cells.1,
            r.solid_angle_empty_cells,
            r.near_count,
            r.far_count,
            r.area_cells.0,
            r.area_cells.1,
            r.area_empty_cells,
            r.area_near_count,
            r.area_far_count,
        );
        let _ = writeln!(
            s,
            "The near quarter of the rectangle subtends {:.1}% of the solid angle and the far quarter \
             {:.1}%. Solid-angle sampling puts {} and {} of the {n} points there; area sampling puts {} \
             and {}. PNG: {}.\n",
            100.0 * r.near_fraction_exact,
            100.0 * r.far_fraction_exact,
            r.near_count,
            r.far_count,
            r.area_near_count,
            r.area_far_count,
            png_links(&[
                "samples_spherical_rectangle_directions",
                "samples_spherical_rectangle_points",
                "samples_spherical_rectangle_area"
            ])
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::{FigureKind, verify_figure};

    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "areawarp-sample-figures-{tag}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn figures_are_written_and_non_trivial() {
        let study = run(&SampleFiguresConfig::quick()).unwrap();
        let dir = temp_dir("quick");
        let figs = study.write_figures(&dir).unwrap();
        assert_eq!(figs.len(), 14);
        let n = study.config.strata * study.config.strata;
        let h = study.config.hammersley_points;
        let samples = [n, n, n, n, h, h, h];
        for (k, stem) in SampleFigures::figure_stems().iter().enumerate() {
            let svg = &figs[2 * k];
            let png = &figs[2 * k + 1];
            assert_eq!(svg.path, dir.join(format!("{stem}.svg")));
            assert_eq!(png.path, dir.join(format!("{stem}.png")));
            let check = verify_figure(&svg.path).unwrap();
            assert_eq!(check.kind, FigureKind::Svg);
            assert_eq!(check.marks, svg.marks);
            // Every sample is drawn as a marker, plus the outline's vertices.
            let text = std::fs::read_to_string(&svg.path).unwrap();
            let circles = text.matches("<circle class=\"mark\"").count();
            let extra = usize::from(k >= 5); // the observer's foot
            assert_eq!(circles, samples[k] + extra, "{stem}");
            assert!(check.marks > circles + 100, "{stem}: {}", check.marks);
            let check = verify_figure(&png.path).unwrap();
            assert_eq!(check.kind, FigureKind::Png);
            assert_eq!((check.width, check.height), (png.width, png.height));
            assert!(png.width >= 480 && png.height >= 380);
            // White, the frame, the outline and the samples (at least).
            assert!(
                check.distinct_colors >= 4,
                "{stem}: {}",
                check.distinct_colors
            );
            let img = figures::decode_png(&std::fs::read(&png.path).unwrap()).unwrap();
            let blue = img
                .rgb
                .chunks_exact(3)
                .filter(|p| Rgb(p[0], p[1], p[2]) == SAMPLES)
                .count();
            assert!(blue >= samples[k], "{stem}: {blue} sample pixels");
        }
        let csv = study.write_csv(&dir).unwrap();
        let text = std::fs::read_to_string(&csv[0]).unwrap();
        assert_eq!(text.lines().count(), 1 + study.rows().len());
        // Four fields per line (commas inside quoted fields do not count).
        for line in text.lines() {
            let mut quoted = false;
            let mut commas = 0;
            for c in line.chars() {
                match c {
                    '"' => quoted = !quoted,
                    ',' if !quoted => commas += 1,
                    _ => {}
                }
            }
            assert_eq!((commas, quoted), (3, false), "{line}");
        }
        assert!(text.contains("\"chi2 over 4 sub-triangles, 256 uniform random;"));
        let md = study.to_markdown();
        for stem in SampleFigures::figure_stems() {
            assert!(md.contains(&format!("({stem}.svg)")), "{stem}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn jittered_triangle_samples_are_more_even_than_random() {
        for seed in [1u64, 2, 3] {
            let config = SampleFiguresConfig {
                seed,
                ..SampleFiguresConfig::default()
            };
            let t = run_triangle(&config).unwrap();
            let cells = t.cell_solid_angles.len();
            assert_eq!(cells, 16);
            assert_eq!((t.random.len(), t.jittered.len()), (256, 256));
            // The sub-triangles tile the triangle.
            let total: f64 = t.cell_solid_angles.iter().sum();
            assert!((total - t.solid_angle).abs() < 1e-12 * t.solid_angle);
            assert!((0.9..1.2).contains(&t.solid_angle), "{}", t.solid_angle);
            assert_eq!(t.measure_samples, 4096);
            assert_eq!(t.random_counts.iter().sum::<usize>(), 4096);
            assert_eq!(t.jittered_counts.iter().sum::<usize>(), 4096);
            assert!(t.max_outside_by < 1e-14);
            // Random: χ² of 15 degrees of freedom (99.9% below 37.7).
            assert!(t.random_chi2 < 37.7, "{seed}: {}", t.random_chi2);
            // Jittered: far below the random expectation (15), and below
            // the 1% quantile of χ²(15), 5.23.
            assert!(t.jittered_chi2 < 3.0, "{seed}: {}", t.jittered_chi2);
            assert!(t.jittered_chi2 < t.random_chi2 / 3.0);
        }
    }

    #[test]
    fn projected_polygon_samples_are_inside_and_cosine_weighted() {
        let config = SampleFiguresConfig::default();
        let p = run_polygon(&config).unwrap();
        let n = p.random.len();
        assert_eq!((n, p.jittered.len(), p.measure_samples), (256, 256, 4096));
        assert_eq!(p.random_inside, n);
        assert_eq!(p.jittered_inside, n);
        assert_eq!(p.measure_inside, 2 * 4096);
        assert_eq!(p.random_counts.iter().sum::<usize>(), 4096);
        assert_eq!(p.jittered_counts.iter().sum::<usize>(), 4096);
        assert!(p.max_outside_by < 1e-12, "{}", p.max_outside_by);
        // The cells' projected solid angles add up to Lambert's Π of the
        // whole comb, which is the map's measure.
        let sum: f64 = p.cell_fractions.iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
        let sum: f64 = p.cell_fractions_uniform.iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
        assert!((plane_measures(&p.vertices).1 - p.projected_solid_angle).abs() < 1e-12);
        let cells = p.cell_fractions.len();
        assert!(cells >= 20, "{cells}");
        let dof = (cells - 1) as f64;
        // Random: within the bulk of χ²(dof); jittered: far more even.
        assert!(
            p.random_chi2 < dof + 6.0 * (2.0 * dof).sqrt(),
            "{}",
            p.random_chi2
        );
        assert!(p.jittered_chi2 < dof / 2.0, "{} {dof}", p.jittered_chi2);
        // The same counts are far from uniform-in-solid-angle.
        assert!(
            p.jittered_chi2_uniform > dof + 6.0 * (2.0 * dof).sqrt(),
            "{} {dof}",
            p.jittered_chi2_uniform
        );
    }

    #[test]
    fn rectangle_samples_follow_the_solid_angle() {
        let config = SampleFiguresConfig::default();
        let r = run_rectangle(&config).unwrap();
        let n = r.points.len();
        assert_eq!((n, r.grid), (256, 16));
        assert!((r.solid_angle - r.solid_angle_triangles).abs() < 1e-13);
        // One solid-angle sample per equal-solid-angle cell; area sampling
        // leaves cells empty and crowds others.
        assert_eq!(r.solid_angle_cells, (1, 1));
        assert_eq!(r.solid_angle_empty_cells, 0);
        assert_eq!(r.area_cells.0, 0);
        assert!(r.area_cells.1 >= 4, "{:?}", r.area_cells);
        assert!(r.area_empty_cells > 50, "{}", r.area_empty_cells);
        // The near and far quarters: counts within the net's bound (the
        // number of grid cells a boundary curve can cross, 2k) of the exact
        // solid-angle fractions — and in fact within a few points.
        let near = r.near_fraction_exact * n as f64;
        let far = r.far_fraction_exact * n as f64;
        assert!(near > 100.0 && far < 20.0, "{near} {far}");
        let bound = 2.0 * r.grid as f64;
        assert!((r.near_count as f64 - near).abs() <= bound);
        assert!((r.far_count as f64 - far).abs() <= bound);
        assert!(
            (r.near_count as f64 - near).abs() <= 3.0,
            "{} {near}",
            r.near_count
        );
        assert!(
            (r.far_count as f64 - far).abs() <= 3.0,
            "{} {far}",
            r.far_count
        );
        // Area sampling puts exactly a quarter there, far off.
        assert_eq!((r.area_near_count, r.area_far_count), (n / 4, n / 4));
        // ... beyond the bound the solid-angle samples meet.
        assert!(near - r.area_near_count as f64 > bound);
        assert!(r.area_far_count as f64 - far > bound);
        // Points are on the rectangle, and each direction points at its point.
        for (p, d) in r.points.iter().zip(&r.directions) {
            let q = p.sub(&r.observer);
            assert!(q.cross(d).norm() < 1e-12 * q.norm());
            assert!(p.z.abs() < 1e-12);
        }
    }

    #[test]
    fn deterministic_for_a_fixed_seed() {
        let config = SampleFiguresConfig::quick();
        let a = run(&config).unwrap();
        let b = run(&config).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.to_markdown(), b.to_markdown());
        let other = run(&SampleFiguresConfig {
            seed: config.seed + 1,
            ..config.clone()
        })
        .unwrap();
        assert_ne!(a.triangle.random, other.triangle.random);
        assert_ne!(a.polygon.jittered, other.polygon.jittered);
        // Hammersley points do not depend on the seed.
        assert_eq!(a.rectangle, other.rectangle);
    }

    #[test]
    fn invalid_configurations_are_rejected() {
        let ok = SampleFiguresConfig::quick();
        for bad in [
            SampleFiguresConfig {
                strata: 1,
                ..ok.clone()
            },
            SampleFiguresConfig {
                hammersley_points: 128,
                ..ok.clone()
            },
            SampleFiguresConfig {
                hammersley_points: 2,
                ..ok.clone()
            },
            SampleFiguresConfig {
                triangle_levels: 0,
                ..ok.clone()
            },
            SampleFiguresConfig {
                polygon_cell: f64::NAN,
                ..ok.clone()
            },
        ] {
            assert!(matches!(run(&bad), Err(WarpError::InvalidParameter { .. })));
        }
    }

    #[test]
    fn helpers() {
        // Equal-area projection: radius 2 sin(θ/2), seen from the centre.
        let p = EqualArea::about(&v3(0.0, 0.0, 1.0), &v3(1.0, 0.0, 0.0));
        let (x, y) = p.project(&v3(1.0, 0.0, 0.0));
        assert!((x - 2f64.sqrt()).abs() < 1e-15 && y.abs() < 1e-15);
        let (x, y) = p.project(&v3(0.0, 1.0, 1.0));
        assert!(x.abs() < 1e-15 && (y + 2.0 * (std::f64::consts::PI / 8.0).sin()).abs() < 1e-15);
        // Clipping the comb to its bounding box changes nothing; to a box
        // across a gap between two teeth it keeps both pieces.
        let comb = comb();
        let (o, pi) = plane_measures(&comb);
        let (o2, pi2) = plane_measures(&clip_to_box(&comb, -2.0, 2.0, -2.0, 2.0));
        assert!((o - o2).abs() < 1e-15 && (pi - pi2).abs() < 1e-15);
        let piece = clip_to_box(&comb, -1.2, 1.2, -1.4, -1.0);
        let (_, p_two) = plane_measures(&piece);
        let (_, p_a) = plane_measures(&clip_to_box(&comb, -1.2, 0.0, -1.4, -1.0));
        let (_, p_b) = plane_measures(&clip_to_box(&comb, 0.0, 1.2, -1.4, -1.0));
        assert!((p_two - p_a - p_b).abs() < 1e-15);
        assert!(inside_polygon(&comb, (0.0, -1.0)) && !inside_polygon(&comb, (0.8, -1.0)));
        assert_eq!(densify(&[(0.0, 0.0), (1.0, 0.0)], 0.25).len(), 5);
    }
}
