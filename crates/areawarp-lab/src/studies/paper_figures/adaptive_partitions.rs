//! Ureña 2000, Figs. 3 and 7: the adaptive partitions of a triangle's
//! projection `E` into the unit disk `C` for three thresholds K, and 900
//! samples on `C` from stratified solid-angle sampling and from adaptive
//! sampling with K = 0.1 and K = 0.001.

use super::{Row, describe, png_links};
use crate::figures::{Figure, PALETTE};
use crate::studies::sample_figures::experiments::{
    chi_square, great_arc, outline, subdivide, triangle_cell, unit, v3,
};
use crate::studies::sample_figures::output::{Drawing, Layer, OUTLINE, SAMPLES, SQUARE};
use crate::verdict::chi2_p_value;
use areawarp::adaptive::AdaptiveTriangle;
use areawarp::error::WarpError;
use areawarp::sampling::jittered;
use areawarp::shapes::SphericalTriangle;
use areawarp::shapes::polygon_measures::{projected_solid_angle, triangle_solid_angle};
use areawarp::vector::Vec3;
use areawarp::warp::Warp;
use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// The thresholds of Fig. 3.
pub const PARTITION_THRESHOLDS: [f64; 3] = [0.3, 0.15, 0.075];
/// The thresholds of Fig. 7's adaptive panels.
pub const PLACEMENT_THRESHOLDS: [f64; 2] = [0.1, 0.001];

/// The file stems written.
pub(crate) const STEMS: [&str; 6] = [
    "urena2000_fig3_partition_k0300",
    "urena2000_fig3_partition_k0150",
    "urena2000_fig3_partition_k0075",
    "urena2000_fig7_stratified_solid_angle",
    "urena2000_fig7_adaptive_k0100",
    "urena2000_fig7_adaptive_k0001",
];

/// Levels of midpoint subdivision of the measuring cells (16 cells).
const MEASURE_LEVELS: u32 = 2;
/// Most pieces drawn in a partition.
const PIECE_LIMIT: usize = 20_000;

/// One partition of Fig. 3.
#[derive(Clone, Debug, PartialEq)]
pub struct PartitionRow {
    /// The threshold K.
    pub threshold: f64,
    /// The pieces' unit vertices (receiver frame, normal `+z`).
    pub pieces: Vec<[Vec3<f64>; 3]>,
    /// The deepest piece.
    pub max_depth: u32,
    /// The largest k(R) = m(R)σ(R)/σ⊥(R) − 1 over the pieces.
    pub max_k: f64,
    /// Pieces stopped at the depth cap with k(R) ≥ K.
    pub capped: usize,
    /// Σ σ⊥(R) over the pieces.
    pub sigma_perp_sum: f64,
}

/// One sample set of Fig. 7.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacementRow {
    /// `"stratified P ∝ σ"` or `"adaptive K = …"`.
    pub method: String,
    /// The samples (unit directions, receiver frame).
    pub directions: Vec<Vec3<f64>>,
    /// χ² of the counts in the measuring sub-triangles against σ⊥.
    pub chi2_projected: f64,
    /// χ² of the same counts against σ.
    pub chi2_solid_angle: f64,
    /// Mean nearest-neighbour distance on C over `½ √(σ⊥(E)/n)` (≈ 1 for
    /// independent points of uniform density, larger when more even).
    pub nn_mean: f64,
    /// Coefficient of variation of the nearest-neighbour distances
    /// (≈ 0.52 for independent points, smaller when more regular).
    pub nn_cv: f64,
    /// The smallest nearest-neighbour distance over `½ √(σ⊥(E)/n)`.
    pub nn_min: f64,
}

/// Figs. 3 and 7.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptivePartitions {
    /// The triangle's unit vertices in the receiver's frame.
    pub vertices: [Vec3<f64>; 3],
    /// σ(E), sr.
    pub solid_angle: f64,
    /// σ⊥(E) by Lambert's formula.
    pub projected_solid_angle: f64,
    /// k(E) of the whole triangle.
    pub k_whole: f64,
    /// Fig. 3, one row per threshold of [`PARTITION_THRESHOLDS`].
    pub partitions: Vec<PartitionRow>,
    /// Fig. 7: stratified, then adaptive per [`PLACEMENT_THRESHOLDS`].
    pub placements: Vec<PlacementRow>,
    /// Cells of the uniformity measure.
    pub measure_cells: usize,
}

/// The example triangle: from the horizon towards the zenith, seen from a
/// receiver with normal `+z` (Ω ≈ 1.1 sr).
pub(crate) fn example_triangle() -> [Vec3<f64>; 3] {
    [
        unit(&v3(0.95, -0.55, 0.12)),
        unit(&v3(0.35, 0.95, 0.25)),
        unit(&v3(-0.1, -0.15, 1.0)),
    ]
}

/// Nearest-neighbour distances in the plane (brute force; n ≤ 10⁴).
fn nearest_neighbours(p: &[(f64, f64)]) -> Vec<f64> {
    p.iter()
        .enumerate()
        .map(|(i, a)| {
            p.iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, b)| (a.0 - b.0).hypot(a.1 - b.1))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

pub(crate) fn run(c: &super::PaperFiguresConfig) -> Result<AdaptivePartitions, WarpError> {
    let [a, b, cc] = example_triangle();
    let z = v3(0.0, 0.0, 1.0);
    let projected = projected_solid_angle(&[a, b, cc], &z).abs();
    let base = AdaptiveTriangle::new(a, b, cc, f64::INFINITY)?;
    let k_whole = base.roots().first().map(|r| r.1.k).unwrap_or(f64::NAN);
    let mut partitions = Vec::new();
    for &k in &PARTITION_THRESHOLDS {
        let t = base.clone().with_threshold(k)?;
        let pieces = t.pieces(PIECE_LIMIT)?;
        partitions.push(PartitionRow {
            threshold: k,
            max_depth: pieces.iter().map(|p| p.depth).max().unwrap_or(0),
            max_k: pieces.iter().map(|p| p.measures.k).fold(0.0, f64::max),
            capped: pieces.iter().filter(|p| p.capped).count(),
            sigma_perp_sum: pieces
                .iter()
                .map(|p| p.measures.projected_solid_angle)
                .sum(),
            pieces: pieces.into_iter().map(|p| p.vertices).collect(),
        });
    }

    let n = c.placement_samples;
    let side = (n as f64).sqrt().round() as usize;
    let mut sets = Vec::new();
    let tri = SphericalTriangle::<f64>::new(a, b, cc)?;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(c.seed ^ 0x0E7A_0007);
    sets.push((
        format!("stratified P ∝ σ ({side} × {side} jittered)"),
        jittered::<f64, _>(side, side, &mut rng)
            .iter()
            .map(|(u, v)| tri.map(u, v))
            .collect::<Vec<_>>(),
    ));
    for &k in &PLACEMENT_THRESHOLDS {
        let t = base.clone().with_threshold(k)?;
        sets.push((
            format!("adaptive K = {k}"),
            t.generate(n, &mut rng).directions,
        ));
    }
    let cells = subdivide([a, b, cc], MEASURE_LEVELS);
    let frac = |m: Vec<f64>| -> Vec<f64> {
        let t: f64 = m.iter().sum();
        m.into_iter().map(|x| x / t).collect()
    };
    let perp = frac(
        cells
            .iter()
            .map(|t| projected_solid_angle(t, &z).abs())
            .collect(),
    );
    let sigma = frac(
        cells
            .iter()
            .map(|[p, q, r]| triangle_solid_angle(p, q, r).abs())
            .collect(),
    );
    let scale = 0.5 * (projected / n as f64).sqrt();
    let placements = sets
        .into_iter()
        .map(|(method, directions)| {
            let mut counts = vec![0usize; cells.len()];
            for d in &directions {
                counts[triangle_cell(&cells, d)] += 1;
            }
            let flat: Vec<(f64, f64)> = directions.iter().map(|d| (d.x, d.y)).collect();
            let nn = nearest_neighbours(&flat);
            let mean = nn.iter().sum::<f64>() / nn.len() as f64;
            let var = nn.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / nn.len() as f64;
            PlacementRow {
                method,
                chi2_projected: chi_square(&counts, &perp),
                chi2_solid_angle: chi_square(&counts, &sigma),
                nn_mean: mean / scale,
                nn_cv: var.sqrt() / mean,
                nn_min: nn.iter().copied().fold(f64::INFINITY, f64::min) / scale,
                directions,
            }
        })
        .collect();
    Ok(AdaptivePartitions {
        vertices: [a, b, cc],
        solid_angle: tri.solid_angle(),
        projected_solid_angle: projected,
        k_whole,
        partitions,
        placements,
        measure_cells: cells.len(),
    })
}

impl AdaptivePartitions {
    /// The unit circle C and the outline of E in C.
    fn frame_lines(&self) -> Vec<Layer> {
        let circle: Vec<(f64, f64)> = (0..=256)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 256.0;
                (t.cos(), t.sin())
            })
            .collect();
        let e: Vec<(f64, f64)> = outline(&self.vertices, 128)
            .iter()
            .map(|d| (d.x, d.y))
            .collect();
        vec![
            ("unit circle C".into(), circle, PALETTE[7]),
            ("E".into(), e, OUTLINE),
        ]
    }

    pub(crate) fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        let mut out = Vec::new();
        let x = "x (vertical projection onto the receiver's plane)".to_string();
        let y = "y".to_string();
        for (row, stem) in self.partitions.iter().zip(&STEMS[..3]) {
            let mut lines = self.frame_lines();
            for (i, [p, q, r]) in row.pieces.iter().enumerate() {
                let mut l: Vec<(f64, f64)> = Vec::new();
                for (s, t) in [(p, q), (q, r), (r, p)] {
                    l.extend(great_arc(s, t, 12).iter().map(|d| (d.x, d.y)));
                }
                let label = if i == 0 {
                    "pieces".to_string()
                } else {
                    String::new()
                };
                lines.push((label, l, PALETTE[3]));
            }
            let d = Drawing {
                title: format!(
                    "adaptive partition of E for K = {}: {} pieces",
                    row.threshold,
                    row.pieces.len()
                ),
                x: x.clone(),
                y: y.clone(),
                size: SQUARE,
                lines,
                dots: Vec::new(),
            };
            out.extend(describe(
                d.write(dir, stem)?,
                &format!(
                    "Ureña 2000, Fig. 3 re-made: the partition of the projected triangle E in the unit disk C built \
                     by areawarp's adaptive sampler for K = {}: {} pieces (red), split at edge midpoints until \
                     every piece has k(R) < K, smallest near the horizon where the cosine varies most",
                    row.threshold,
                    row.pieces.len()
                ),
            ));
        }
        for (row, stem) in self.placements.iter().zip(&STEMS[3..]) {
            let d = Drawing {
                title: format!("{} samples on C: {}", row.directions.len(), row.method),
                x: x.clone(),
                y: y.clone(),
                size: SQUARE,
                lines: self.frame_lines(),
                dots: vec![(
                    String::new(),
                    row.directions.iter().map(|d| (d.x, d.y)).collect(),
                    SAMPLES,
                )],
            };
            let what = if row.method.starts_with("stratified") {
                "denser towards the circumference, since P ∝ σ ignores the cosine".to_string()
            } else {
                format!(
                    "even in area on C (χ² against σ⊥ {:.1} over {} cells), nearest-neighbour spread {:.2} \
                     (0.52 for independent points)",
                    row.chi2_projected, self.measure_cells, row.nn_cv
                )
            };
            out.extend(describe(
                d.write(dir, stem)?,
                &format!(
                    "Ureña 2000, Fig. 7 re-made: {} samples in the projected triangle E on the unit disk C from {}: {what}",
                    row.directions.len(),
                    row.method
                ),
            ));
        }
        Ok(out)
    }

    pub(crate) fn to_markdown(&self) -> String {
        let mut s = String::new();
        let cells = self.measure_cells;
        let _ = writeln!(
            s,
            "### The adaptive partitions and sample placements (Ureña 2000, Figs. 3 and 7)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** Fig. 3 shows the partitions of a triangle's projection E into the unit disk C for \
             K = 0.3, 0.15 and 0.075; Fig. 7 shows 900 samples on C from stratified sampling with P ∝ σ \
             (30 × 30 strata; \"clearly higher density near the circumference\"), adaptive sampling with K = 0.1 \
             (uniform in area on C, but with holes and clusters) and K = 0.001 (uniform, and even distances). \
             **Ours:** `AdaptiveTriangle` (systematic allocation) on a triangle from near the horizon to near the \
             zenith, seen from a receiver with normal +z: σ = {:.4} sr, σ⊥ = {:.4} (Lambert), k(E) = {:.3}. \
             The pieces are drawn in C; their edges are great arcs, i.e. arcs of ellipses in C.\n",
            self.solid_angle, self.projected_solid_angle, self.k_whole
        );
        s.push_str(&super::image_lines(&[
            ("partition K = 0.3", "urena2000_fig3_partition_k0300"),
            ("partition K = 0.15", "urena2000_fig3_partition_k0150"),
            ("partition K = 0.075", "urena2000_fig3_partition_k0075"),
        ]));
        let _ = writeln!(
            s,
            "| K | pieces | deepest | largest k(R) | pieces capped at the depth limit | Σσ⊥(R) / σ⊥(E) − 1 |\n\
             |---:|---:|---:|---:|---:|---:|"
        );
        for r in &self.partitions {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.4} | {} | {:.1e} |",
                r.threshold,
                r.pieces.len(),
                r.max_depth,
                r.max_k,
                r.capped,
                r.sigma_perp_sum / self.projected_solid_angle - 1.0
            );
        }
        let _ = writeln!(
            s,
            "\n*largest k(R)*: every piece meets the paper's stopping rule k(R) < K, which bounds the second \
             moment by (1 + K) U₀ (§3.2); the pieces' σ⊥ add up to Lambert's σ⊥(E) to rounding.\n"
        );
        s.push_str(&super::image_lines(&[
            (
                "stratified solid-angle samples on C",
                "urena2000_fig7_stratified_solid_angle",
            ),
            (
                "adaptive K = 0.1 samples on C",
                "urena2000_fig7_adaptive_k0100",
            ),
            (
                "adaptive K = 0.001 samples on C",
                "urena2000_fig7_adaptive_k0001",
            ),
        ]));
        let dof = (cells - 1) as f64;
        let _ = writeln!(
            s,
            "| {} samples | χ² vs σ⊥ ({cells} cells) | p | χ² vs σ | p | mean NN distance | NN spread (CV) | closest pair |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|",
            self.placements.first().map_or(0, |p| p.directions.len())
        );
        for r in &self.placements {
            let _ = writeln!(
                s,
                "| {} | {:.1} | {:.2e} | {:.1} | {:.2e} | {:.2} | {:.2} | {:.3} |",
                r.method,
                r.chi2_projected,
                chi2_p_value(r.chi2_projected, dof),
                r.chi2_solid_angle,
                chi2_p_value(r.chi2_solid_angle, dof),
                r.nn_mean,
                r.nn_cv,
                r.nn_min
            );
        }
        let _ = writeln!(
            s,
            "\n*χ² vs σ⊥ / vs σ*: counts in the {cells} sub-triangles of a {MEASURE_LEVELS}-level midpoint \
             subdivision of E against the expectations for samples uniform in area on C (σ⊥, Lambert's formula) \
             and uniform in solid angle (σ); *p* = P(χ² ≥ value) for independent samples (the adaptive sampler \
             splits at the same midpoints, so where its partition is deeper than {MEASURE_LEVELS} levels its \
             counts are stratified and χ² is small). *NN*: nearest-neighbour distances on C, in units of \
             ½√(σ⊥(E)/n), the mean distance of independent uniform points; *spread* is their coefficient of \
             variation (≈ 0.52 for independent points, smaller when distances are even; edge effects raise \
             both a little); *closest pair* in the same unit. The paper's reading holds when the stratified σ \
             samples fit σ but not σ⊥, K = 0.1 fits σ⊥ with an independent-like spread, and K = 0.001 fits σ⊥ \
             with a smaller spread. PNG: {}.\n",
            png_links(&STEMS)
        );
        s
    }

    pub(crate) fn rows(&self) -> Vec<Row> {
        let mut v: Vec<Row> = Vec::new();
        for r in &self.partitions {
            let f = "Urena 2000 Fig. 3";
            let k = r.threshold;
            v.push((
                f,
                format!("K = {k}: pieces"),
                r.pieces.len().to_string(),
                String::new(),
            ));
            v.push((
                f,
                format!("K = {k}: largest k(R); reference: K"),
                format!("{:.6}", r.max_k),
                k.to_string(),
            ));
            v.push((
                f,
                format!("K = {k}: sum of sigma_perp(R); reference: Lambert sigma_perp(E)"),
                format!("{:.12}", r.sigma_perp_sum),
                format!("{:.12}", self.projected_solid_angle),
            ));
        }
        for r in &self.placements {
            let f = "Urena 2000 Fig. 7";
            let m = &r.method;
            v.push((
                f,
                format!(
                    "{m}: chi2 vs sigma_perp over {} cells; reference: dof",
                    self.measure_cells
                ),
                format!("{:.3}", r.chi2_projected),
                (self.measure_cells - 1).to_string(),
            ));
            v.push((
                f,
                format!(
                    "{m}: chi2 vs sigma over {} cells; reference: dof",
                    self.measure_cells
                ),
                format!("{:.3}", r.chi2_solid_angle),
                (self.measure_cells - 1).to_string(),
            ));
            v.push((
                f,
                format!("{m}: nearest-neighbour CV; reference: independent points"),
                format!("{:.4}", r.nn_cv),
                "0.52".into(),
            ));
        }
        v
    }
}
