//! Rendered images: the papers' pictures re-made as false-colour
//! irradiance images of a ground plane, one receiver per pixel, with the
//! estimators the variance and adaptive studies measure
//! ([`ReceiverEstimator`]), so that each image is what the tables average.
//!
//! | figure | paper | scene | panels |
//! |---|---|---|---|
//! | `images_ufk13.png` | Ureña, Fajardo & King 2013, Fig. 4 | the variance study's standing rectangular light ([`setup::standing_rectangle`]) | the exact irradiance; per light sampler (area, triangle pair, spherical rectangle, projected polygon, bilinear-cosine rectangle) the image at 1, 4 and 16 spp and its signed error |
//! | `images_ufk13_mis.png` | the same, Fig. 6 | the same | the same with MIS (balance heuristic, `n` light + `n` cosine samples) |
//! | `images_urena2000.png` | Ureña 2000, Fig. 9 | the adaptive study's patterned triangle, occluders removed as in the paper ([`setup::patterned_triangle`]) | the exact irradiance; at 36 spp unstratified solid-angle sampling (`P ∝ σ`, the paper's top image), 6 × 6 stratified solid-angle sampling (middle), adaptive sampling with `K = 0.001` (bottom), and `K = 0.1` (ours), each with its signed error |
//!
//! # Rendering
//! A [`PixelGrid`] puts a receiver (normal `+z`) at the centre of each
//! pixel of a rectangle of the ground `z = 0`; the value of a pixel is the
//! estimate of the irradiance at that point (no pixel filter: the images
//! show the estimators' noise, not antialiasing). Every pixel is an
//! estimate of its own, with the study's point sets: `n` jittered points
//! (an `n_x × n_y` grid, [`PointSet::Jittered`]) for the method and `n` more
//! for an MIS partner; all methods at a pixel and spp see the *same*
//! points (common random numbers, as in the studies and the paper's "same
//! input set of samples"), and the adaptive sampler draws its own from the
//! batch's seed. One [`run_jobs`] job renders one row of pixels, so the
//! images are identical for any thread count.
//!
//! The references are exact: Lambert's formula for the constant light and
//! per pattern cell for the patterned triangle ([`Scene::exact`]) — neither
//! scene has occluders. The signed error `Ê − E` is drawn on a diverging
//! scale symmetric about 0 (white); its bound is the 99th percentile of
//! `|Ê − E|` over every error panel of the figure, so that the largest
//! errors (area sampling at the light's foot) saturate instead of washing
//! out the others. The Markdown gives, per panel, the image relative RMS
//! error `√(Σ (Ê − E)²) / √(Σ E²)` and the per-pixel one
//! `√(mean ((Ê − E)/E)²)`, the two metrics of the studies' tables.

use crate::estimator::{Batch, PointSet, PreparedEstimator, ReceiverEstimator};
use crate::jobs::run_jobs;
use crate::scene::setup;
use crate::scene::{Quantity, Receiver, Scene};
use areawarp::error::WarpError;
use areawarp::estimate::job_seed;
use areawarp::vector::Vec3;
use rand::Rng as _;
use std::time::Instant;

mod ground;
mod output;
mod triptych;
pub use self::ground::*;
pub use self::triptych::*;

#[cfg(test)]
mod tests;

/// A rectangle of the ground plane `z = 0` divided into pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelGrid {
    /// `x` range (left to right).
    pub x: (f64, f64),
    /// `y` range (bottom to top of the image).
    pub y: (f64, f64),
    /// Pixels along `x`.
    pub cols: usize,
    /// Pixels along `y`.
    pub rows: usize,
}

impl PixelGrid {
    /// The receiver at the centre of pixel `(i, j)` (column `i`, row `j`
    /// from the bottom), normal `+z`.
    ///
    /// # Errors
    /// As [`Receiver::new`] (non-finite ranges).
    pub fn receiver(&self, i: usize, j: usize) -> Result<Receiver, WarpError> {
        let x = self.x.0 + (self.x.1 - self.x.0) * (i as f64 + 0.5) / self.cols as f64;
        let y = self.y.0 + (self.y.1 - self.y.0) * (j as f64 + 0.5) / self.rows as f64;
        Receiver::new(Vec3::new(x, y, 0.0), Vec3::new(0.0, 0.0, 1.0))
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.cols * self.rows
    }

    /// `true` if the grid has no pixel.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn check(&self) -> Result<(), WarpError> {
        if self.is_empty() || !(self.x.0 < self.x.1 && self.y.0 < self.y.1) {
            return Err(WarpError::InvalidParameter {
                name: "pixel grid",
                expected: "at least one pixel over a rectangle with x0 < x1 and y0 < y1",
            });
        }
        Ok(())
    }
}

/// One rendered image: a value per pixel, row-major, bottom row first
/// (the layout of [`crate::figures::ImagePanel`]); `NaN` where the method
/// failed.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// What it shows (`rectangle, 4 spp`).
    pub label: String,
    /// A short title for its panel (`rectangle, 4 spp`, `stratified 6 × 6`).
    pub short: String,
    /// Samples per pixel (0 for a reference).
    pub spp: usize,
    /// The pixel values.
    pub values: Vec<f64>,
    /// Pixels where the method could not be built or gave a non-finite
    /// estimate (their value is `NaN`).
    pub failed: usize,
}

impl Image {
    /// The signed error `self − reference`, pixel by pixel.
    pub fn error(&self, reference: &Image) -> Vec<f64> {
        self.values
            .iter()
            .zip(&reference.values)
            .map(|(a, b)| a - b)
            .collect()
    }

    /// The image relative RMS error `√(Σ (Ê − E)²) / √(Σ E²)` and the
    /// per-pixel relative RMS error `√(mean ((Ê − E)/E)²)` against
    /// `reference`, over the pixels where both are finite (and `E > 0`
    /// for the second).
    pub fn rms_errors(&self, reference: &Image) -> (f64, f64) {
        let (mut num, mut den, mut rel, mut n) = (0.0, 0.0, 0.0, 0usize);
        for (a, e) in self.values.iter().zip(&reference.values) {
            if !(a.is_finite() && e.is_finite()) {
                continue;
            }
            num += (a - e) * (a - e);
            den += e * e;
            if *e > 0.0 {
                rel += ((a - e) / e).powi(2);
                n += 1;
            }
        }
        ((num / den).sqrt(), (rel / n as f64).sqrt())
    }
}

/// The exact irradiance at every pixel ([`Scene::exact`]).
///
/// # Errors
/// As [`PixelGrid::receiver`]; [`WarpError::InvalidParameter`] for a scene
/// without an exact irradiance (occluders).
pub fn reference_image(scene: &Scene, grid: &PixelGrid) -> Result<Image, WarpError> {
    grid.check()?;
    let mut values = Vec::with_capacity(grid.len());
    for j in 0..grid.rows {
        for i in 0..grid.cols {
            let rx = grid.receiver(i, j)?;
            values.push(scene.exact(&rx, &Quantity::Irradiance).ok_or(
                WarpError::InvalidParameter {
                    name: "scene",
                    expected: "a scene without occluders (exact irradiance)",
                },
            )?);
        }
    }
    Ok(Image {
        label: "reference (exact)".to_string(),
        short: "reference (exact)".to_string(),
        spp: 0,
        values,
        failed: 0,
    })
}

/// Renders `scene` on `grid` with every estimator at every spp in `spp`:
/// `result[m][l]` is estimator `m`'s image at `spp[l]` (see the module
/// docs for the points and the seeds).
///
/// # Errors
/// As [`PixelGrid::receiver`]; an estimator that fails at a pixel is not an
/// error (the pixel is `NaN` and counted in [`Image::failed`]).
pub fn render(
    scene: &Scene,
    grid: &PixelGrid,
    estimators: &[&dyn ReceiverEstimator],
    spp: &[usize],
    seed: u64,
) -> Result<Vec<Vec<Image>>, WarpError> {
    grid.check()?;
    let (nm, nl) = (estimators.len(), spp.len());
    let max_n = spp.iter().copied().max().unwrap_or(1);
    let set = PointSet::Jittered;
    // One job per pixel row: values[(m · nl + l) · cols + i].
    let rows = run_jobs(grid.rows, seed, |j, rng| {
        let mut values = vec![f64::NAN; nm * nl * grid.cols];
        let mut light = Vec::with_capacity(max_n);
        let mut partner = Vec::with_capacity(max_n);
        for i in 0..grid.cols {
            let rx = grid.receiver(i, j)?;
            let mut prepared: Vec<Option<Box<dyn PreparedEstimator + '_>>> = estimators
                .iter()
                .map(|e| e.prepare(scene, &rx).ok())
                .collect();
            for (l, &n) in spp.iter().enumerate() {
                set.fill(n, rng, &mut light);
                set.fill(n, rng, &mut partner);
                let level_seed = rng.next_u64();
                for (m, est) in prepared.iter_mut().enumerate() {
                    let Some(est) = est else { continue };
                    let batch = Batch {
                        light: &light,
                        partner: &partner,
                        point_set: set,
                        seed: job_seed(level_seed, m as u64),
                    };
                    if let Ok(v) = est.estimate(&batch)
                        && v.is_finite()
                    {
                        values[(m * nl + l) * grid.cols + i] = v;
                    }
                }
            }
        }
        Ok::<_, WarpError>(values)
    });
    let rows = rows.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok((0..nm)
        .map(|m| {
            (0..nl)
                .map(|l| {
                    let mut values = Vec::with_capacity(grid.len());
                    for row in &rows {
                        let k = (m * nl + l) * grid.cols;
                        values.extend_from_slice(&row[k..k + grid.cols]);
                    }
                    let failed = values.iter().filter(|v| v.is_nan()).count();
                    let label = format!("{}, {} spp", estimators[m].name(), spp[l]);
                    Image {
                        short: label.clone(),
                        label,
                        spp: spp[l],
                        values,
                        failed,
                    }
                })
                .collect()
        })
        .collect())
}

/// The size of the rendered images.
#[derive(Clone, Debug, PartialEq)]
pub struct ImagesConfig {
    /// Seed of the renders.
    pub seed: u64,
    /// The Ureña–Fajardo–King images.
    pub ground: GroundConfig,
    /// The Ureña 2000 triptych.
    pub triptych: TriptychConfig,
    /// Figure pixels per image pixel in the standing-light figures.
    pub ground_zoom: u32,
    /// Figure pixels per image pixel in the triptych.
    pub triptych_zoom: u32,
}

impl Default for ImagesConfig {
    /// The report's size: 200 × 100 pixels for the standing light (1, 4,
    /// 16 spp), 96 × 64 for the triptych (36 spp) drawn at 2 × 2 figure
    /// pixels per image pixel.
    fn default() -> Self {
        ImagesConfig {
            seed: 0x5EED_1A6E,
            ground: GroundConfig::default(),
            triptych: TriptychConfig::default(),
            ground_zoom: 1,
            triptych_zoom: 2,
        }
    }
}

impl ImagesConfig {
    /// A tiny size for tests and `report --quick`: 20 × 10 and 18 × 12
    /// pixels, 4 figure pixels per image pixel.
    pub fn quick() -> Self {
        let mut c = Self::default();
        c.ground.grid.cols = 20;
        c.ground.grid.rows = 10;
        c.triptych.grid.cols = 18;
        c.triptych.grid.rows = 12;
        c.ground_zoom = 4;
        c.triptych_zoom = 4;
        c
    }
}

/// The rendered images of both papers.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderedImages {
    /// The configuration.
    pub config: ImagesConfig,
    /// The standing light.
    pub ground: GroundImages,
    /// The triptych.
    pub triptych: Triptych,
    /// Wall-clock seconds of [`run`] (not part of the results).
    pub elapsed_seconds: f64,
}

/// Renders both sets of images.
///
/// # Errors
/// As [`render_ground`] and [`render_triptych`].
pub fn run(config: &ImagesConfig) -> Result<RenderedImages, WarpError> {
    let start = Instant::now();
    let ground = render_ground(&config.ground, job_seed(config.seed, 1))?;
    let triptych = render_triptych(&config.triptych, job_seed(config.seed, 2))?;
    Ok(RenderedImages {
        config: config.clone(),
        ground,
        triptych,
        elapsed_seconds: start.elapsed().as_secs_f64(),
    })
}

/// The standing-light scene of the variance study's default configuration.
fn standing_light(width: f64, height: f64, radiance: f64) -> Result<Scene, WarpError> {
    Ok(setup::standing_rectangle(width, height, radiance, 1.0, 1.0, 1, 1)?.scene)
}
