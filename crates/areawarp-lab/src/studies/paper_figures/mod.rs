//! The papers' remaining figures, re-made from the library's own maps, each
//! with a number measured on the drawn data that the picture alone does not
//! give. Every figure is *computed*: the samples, partitions and curves come
//! from `areawarp`'s maps (and the lab's estimator pieces built on them),
//! not from re-drawn formulas.
//!
//! | figure | paper | ours | measured |
//! |---|---|---|---|
//! | the triangle-pair panel | Ureña, Fajardo & King 2013, Fig. 5 | the rectangle of [`sample_figures`](super::sample_figures)' Fig. 5 split into two spherical triangles ([`strategies::spherical_triangles`]: [`areawarp::estimate::Mixture`] of two [`SphericalTriangle`]s chosen ∝ Ω by `u`); the same Hammersley points, pulled back to the rectangle, with the pair's own equal-solid-angle grid, and over the spherical-rectangle map's grid | points per cell of the spherical-rectangle map's grid (1 each for that map; holes and doubles for the pair), against independent points |
//! | adaptive partitions | Ureña 2000, Fig. 3 | [`AdaptiveTriangle::pieces`] for K = 0.3, 0.15, 0.075, drawn in the unit disk C (vertical projection) | pieces, depth, largest k(R) against K, Σσ⊥(R) against Lambert's σ⊥(E) |
//! | sample distributions on C | Ureña 2000, Fig. 7 | 900 samples: 30 × 30 jittered through [`SphericalTriangle`] (P ∝ σ), [`AdaptiveTriangle::generate`] with K = 0.1 and K = 0.001 | χ² of counts in sub-triangles against σ⊥ and against σ; nearest-neighbour distances on C (holes and clusters) |
//! | the marginal CDF | Arvo 2001, Fig. 1.9 | [`ProjectedPolygon::marginal_cdf`] of the comb of Arvo's Fig. 1.11 (as in [`sample_figures`](super::sample_figures)), its vertex meridians, and Arvo's Vandermonde cubic inverse ([`MarginalInversion::Cubic`]) | lunes and breakpoints; F's deviation from its chords between breakpoints (the "fluctuations" Arvo exaggerated); the cubic's backward error |
//! | samples on a sphere | Shao & Badler 1996, Fig. 3 | [`Sphere`] (Archimedes' axial projection), independent and jittered `(u, v)`, orthographic view of the front hemisphere | χ² over the 80 cells of a subdivided icosahedron; the mean resultant length |
//! | samples on a spherical triangle | Shao & Badler 1996, Fig. 4 | [`Sphere`] restricted to the triangle's `(z, φ)` bounding box ([`angular_box`]), kept when the ray hits the triangle ([`ray_hits_triangle`]) | acceptance against Ω/|B|; χ² over sub-triangles |
//!
//! The report shows each figure in the section of its paper:
//! [`PaperFigures::ufk_markdown`], [`PaperFigures::urena_markdown`],
//! [`PaperFigures::arvo_markdown`], [`PaperFigures::shao_markdown`].
//!
//! [`strategies::spherical_triangles`]: crate::scene::strategies::spherical_triangles
//! [`angular_box`]: crate::studies::solid_angle_of_object::angular_box
//! [`ray_hits_triangle`]: crate::studies::solid_angle_of_object::ray_hits_triangle
//! [`SphericalTriangle`]: areawarp::shapes::SphericalTriangle
//! [`AdaptiveTriangle::pieces`]: areawarp::adaptive::AdaptiveTriangle::pieces
//! [`AdaptiveTriangle::generate`]: areawarp::adaptive::AdaptiveTriangle::generate
//! [`ProjectedPolygon::marginal_cdf`]: areawarp::shapes::ProjectedPolygon::marginal_cdf
//! [`MarginalInversion::Cubic`]: areawarp::shapes::MarginalInversion::Cubic
//! [`Sphere`]: areawarp::shapes::Sphere
//!
//! # Example
//! ```
//! use areawarp_lab::studies::paper_figures::{PaperFiguresConfig, run};
//!
//! let study = run(&PaperFiguresConfig::quick())?;
//! // Hammersley points through the spherical-rectangle map: one per cell
//! // of its equal-solid-angle grid; through the triangle pair: holes.
//! assert_eq!(study.triangle_pair.rectangle_cells, (1, 1));
//! assert!(study.triangle_pair.pair_empty_cells > 0);
//! assert!(study.ufk_markdown().contains("ufk2013_fig5_triangle_pair.svg"));
//! # Ok::<(), areawarp::WarpError>(())
//! ```

mod adaptive_partitions;
mod archimedes;
mod marginal_cdf;
#[cfg(test)]
mod tests;
mod triangle_pair;

pub use self::adaptive_partitions::{
    AdaptivePartitions, PARTITION_THRESHOLDS, PLACEMENT_THRESHOLDS, PartitionRow, PlacementRow,
};
pub use self::archimedes::{ArchimedesSamples, ArchimedesTriangle};
pub use self::marginal_cdf::MarginalCdf;
pub use self::triangle_pair::TrianglePairPanel;

use crate::figures::Figure;
use areawarp::error::WarpError;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// The study's sizes and seed.
#[derive(Clone, Debug, PartialEq)]
pub struct PaperFiguresConfig {
    /// Master seed of every random set.
    pub seed: u64,
    /// Hammersley points of the triangle-pair panel: a power of 4 (the
    /// paper's 256).
    pub hammersley_points: usize,
    /// Samples of Ureña's Fig. 7 panels: a square (the paper's 900 = 30²).
    pub placement_samples: usize,
    /// Strata per side of the drawn sphere samples (`k²` samples).
    pub sphere_strata: usize,
    /// Strata per side of the larger sets the uniformity measures use.
    pub measure_strata: usize,
    /// Points on the plotted marginal CDF.
    pub cdf_points: usize,
}

impl PaperFiguresConfig {
    /// A quick run (milliseconds): 64 Hammersley points, 900 samples on C,
    /// 16 × 16 sphere samples, 32 × 32 measured, 400 CDF points.
    pub fn quick() -> Self {
        PaperFiguresConfig {
            seed: 0xF16_5EED,
            hammersley_points: 64,
            placement_samples: 900,
            sphere_strata: 16,
            measure_strata: 32,
            cdf_points: 400,
        }
    }

    fn validate(&self) -> Result<(), WarpError> {
        let n = self.hammersley_points;
        if !(16..=1 << 12).contains(&n)
            || !n.is_power_of_two()
            || !n.trailing_zeros().is_multiple_of(2)
        {
            return Err(WarpError::InvalidParameter {
                name: "hammersley_points",
                expected: "a power of 4 from 16 to 4096",
            });
        }
        let r = (self.placement_samples as f64).sqrt().round() as usize;
        if !(4..=100).contains(&r) || r * r != self.placement_samples {
            return Err(WarpError::InvalidParameter {
                name: "placement_samples",
                expected: "a square from 16 to 10000",
            });
        }
        if !(4..=64).contains(&self.sphere_strata) || !(4..=256).contains(&self.measure_strata) {
            return Err(WarpError::InvalidParameter {
                name: "sphere_strata",
                expected: "4 to 64 strata drawn, 4 to 256 measured",
            });
        }
        if !(16..=100_000).contains(&self.cdf_points) {
            return Err(WarpError::InvalidParameter {
                name: "cdf_points",
                expected: "16 to 100000 points",
            });
        }
        Ok(())
    }
}

impl Default for PaperFiguresConfig {
    /// The report's size: the papers' 256 Hammersley points and 900
    /// samples, 32 × 32 sphere samples, 64 × 64 measured, 2000 CDF points.
    fn default() -> Self {
        PaperFiguresConfig {
            hammersley_points: 256,
            sphere_strata: 32,
            measure_strata: 64,
            cdf_points: 2000,
            ..Self::quick()
        }
    }
}

/// Everything [`run`] computed.
#[derive(Clone, Debug)]
pub struct PaperFigures {
    /// The configuration run.
    pub config: PaperFiguresConfig,
    /// Ureña, Fajardo & King 2013, Fig. 5, the triangle-pair panel.
    pub triangle_pair: TrianglePairPanel,
    /// Ureña 2000, Figs. 3 and 7.
    pub adaptive: AdaptivePartitions,
    /// Arvo 2001, Fig. 1.9.
    pub marginal: MarginalCdf,
    /// Shao & Badler 1996, Fig. 3.
    pub sphere: ArchimedesSamples,
    /// Shao & Badler 1996, Fig. 4.
    pub sphere_triangle: ArchimedesTriangle,
}

/// Runs the study.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for a configuration out of range (see
/// [`PaperFiguresConfig`]); the maps' constructors' errors (not expected:
/// the shapes are fixed and valid).
pub fn run(config: &PaperFiguresConfig) -> Result<PaperFigures, WarpError> {
    config.validate()?;
    Ok(PaperFigures {
        config: config.clone(),
        triangle_pair: triangle_pair::run(config)?,
        adaptive: adaptive_partitions::run(config)?,
        marginal: marginal_cdf::run(config)?,
        sphere: archimedes::run_sphere(config)?,
        sphere_triangle: archimedes::run_triangle(config)?,
    })
}

/// `[a.png](a.png), [b.png](b.png)`.
pub(crate) fn png_links(stems: &[&str]) -> String {
    stems
        .iter()
        .map(|st| format!("[{st}.png]({st}.png)"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Figures shown one per line (each then gets a numbered caption in the
/// report): `(alt, stem)` pairs, the SVG shown.
pub(crate) fn image_lines(items: &[(&str, &str)]) -> String {
    items
        .iter()
        .map(|(alt, stem)| format!("![{alt}]({stem}.svg)\n\n"))
        .collect()
}

/// Sets the title (the report's alt text and caption) of the SVG and PNG
/// versions of a drawing.
pub(crate) fn describe(mut figs: Vec<Figure>, alt: &str) -> Vec<Figure> {
    for f in &mut figs {
        f.title = alt.to_string();
    }
    figs
}

impl PaperFigures {
    /// Every file stem [`PaperFigures::write_figures`] writes (each as
    /// `.svg` and `.png`).
    pub fn figure_stems() -> Vec<&'static str> {
        let mut v = Vec::new();
        v.extend(triangle_pair::STEMS);
        v.extend(adaptive_partitions::STEMS);
        v.extend(marginal_cdf::STEMS);
        v.extend(archimedes::STEMS);
        v
    }

    /// Writes every figure into `dir` (created if needed), as SVG and PNG,
    /// each titled with its alt text. Names: [`PaperFigures::figure_stems`].
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = self.triangle_pair.write_figures(dir)?;
        out.extend(self.adaptive.write_figures(dir)?);
        out.extend(self.marginal.write_figures(dir)?);
        out.extend(self.sphere.write_figures(dir)?);
        out.extend(self.sphere_triangle.write_figures(dir)?);
        Ok(out)
    }

    /// The figures of Ureña, Fajardo & King 2013 (Markdown subsection).
    pub fn ufk_markdown(&self) -> String {
        self.triangle_pair.to_markdown()
    }

    /// The figures of Ureña 2000 (Markdown subsection).
    pub fn urena_markdown(&self) -> String {
        self.adaptive.to_markdown()
    }

    /// The figures of Arvo 2001 (Markdown subsection).
    pub fn arvo_markdown(&self) -> String {
        self.marginal.to_markdown()
    }

    /// The figures of Shao & Badler 1996 (Markdown subsection).
    pub fn shao_markdown(&self) -> String {
        let mut s = self.sphere.to_markdown();
        s.push_str(&self.sphere_triangle.to_markdown());
        s
    }

    /// Writes `paper_figures.csv` (figure, quantity, measured, reference).
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<PathBuf> {
        use crate::studies::sample_figures::output::csv_field;
        std::fs::create_dir_all(dir)?;
        let mut s = String::from("figure,quantity,measured,reference\n");
        let rows = self
            .triangle_pair
            .rows()
            .into_iter()
            .chain(self.adaptive.rows())
            .chain(self.marginal.rows())
            .chain(self.sphere.rows())
            .chain(self.sphere_triangle.rows());
        for (fig, q, m, r) in rows {
            let _ = writeln!(
                s,
                "{},{},{},{}",
                csv_field(fig),
                csv_field(&q),
                csv_field(&m),
                csv_field(&r)
            );
        }
        let path = dir.join("paper_figures.csv");
        std::fs::write(&path, s)?;
        Ok(path)
    }
}

/// One CSV row: figure, quantity, measured, reference (empty if none).
pub(crate) type Row = (&'static str, String, String, String);
