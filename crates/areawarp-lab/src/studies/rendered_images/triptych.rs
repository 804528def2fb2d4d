//! Ureña (2000, Fig. 9): the irradiance of the patterned triangle on the
//! ground at 36 samples per pixel, occluders removed as in the paper.

use super::*;
use crate::estimator::{Method, Sampler};
use crate::studies::adaptive_comparison::{
    AdaptiveComparisonConfig, AdaptiveEstimator, STRATIFIED_SOLID_ANGLE,
};

/// The triptych.
#[derive(Clone, Debug, PartialEq)]
pub struct TriptychConfig {
    /// Pattern cells per side (the adaptive study's).
    pub cells: usize,
    /// The pattern's high radiance.
    pub high: f64,
    /// Its low radiance.
    pub low: f64,
    /// The pixels on the ground.
    pub grid: PixelGrid,
    /// Samples per pixel (the paper's 36).
    pub spp: usize,
    /// The adaptive thresholds after `K = ∞`: the paper's Fig. 9 shows
    /// `K = 0.001`; `K = 0.1` (its Fig. 7) is ours.
    pub thresholds: Vec<f64>,
}

impl Default for TriptychConfig {
    /// The adaptive study's scene (5 × 5 pattern, radiances 1 and 0.1)
    /// over its receivers' rectangle `x ∈ [−1.5, 1.5]`, `y ∈ [0.05, 2.05]`
    /// in 96 × 64 pixels, 36 spp, `K = 0.1` and `0.001`.
    fn default() -> Self {
        let a = AdaptiveComparisonConfig::default();
        TriptychConfig {
            cells: a.cells,
            high: a.high,
            low: a.low,
            grid: PixelGrid {
                x: (-1.5, 1.5),
                y: (0.05, 2.05),
                cols: 96,
                rows: 64,
            },
            spp: 36,
            thresholds: vec![0.1, 0.001],
        }
    }
}

/// The rendered triptych.
#[derive(Clone, Debug, PartialEq)]
pub struct Triptych {
    /// The grid.
    pub grid: PixelGrid,
    /// The exact irradiance (Lambert per pattern cell).
    pub reference: Image,
    /// In order: `P ∝ σ` without strata (adaptive `K = ∞`), stratified
    /// solid angle (`√n × √n` strata), adaptive at each threshold.
    pub images: Vec<Image>,
}

/// The label of the paper's first image.
pub const UNSTRATIFIED_SOLID_ANGLE: &str = "P ∝ σ, unstratified (K = ∞)";

/// Renders the triptych.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for a threshold that is not `> 0`; as
/// [`setup::patterned_triangle`], [`reference_image`] and [`render`].
pub fn render_triptych(config: &TriptychConfig, seed: u64) -> Result<Triptych, WarpError> {
    if config.thresholds.iter().any(|k| !(*k > 0.0)) {
        return Err(WarpError::InvalidParameter {
            name: "thresholds",
            expected: "thresholds K > 0",
        });
    }
    let with_occluders = setup::patterned_triangle(config.cells, config.high, config.low, 1)?;
    // The paper's Fig. 9: "with the occluders removed".
    let scene = Scene::new(with_occluders.scene.emitter().clone());
    let reference = reference_image(&scene, &config.grid)?;
    let unstratified = AdaptiveEstimator::new(f64::INFINITY);
    // For a triangle light the study's "pair" is the one spherical triangle.
    let stratified = Method::plain(Sampler::TrianglePair);
    let adaptive: Vec<AdaptiveEstimator> = config
        .thresholds
        .iter()
        .map(|&k| AdaptiveEstimator::new(k))
        .collect();
    let mut estimators: Vec<&dyn ReceiverEstimator> = vec![&unstratified, &stratified];
    estimators.extend(adaptive.iter().map(|a| a as &dyn ReceiverEstimator));
    let images = render(&scene, &config.grid, &estimators, &[config.spp], seed)?;
    let mut images: Vec<Image> = images.into_iter().flatten().collect();
    images[0].label = format!("{UNSTRATIFIED_SOLID_ANGLE}, {} spp", config.spp);
    images[0].short = "P ∝ σ, unstratified".to_string();
    images[1].label = format!("{STRATIFIED_SOLID_ANGLE}, {} spp", config.spp);
    let s = crate::estimator::grid_columns(config.spp);
    images[1].short = format!("stratified {s} × {} strata", config.spp / s.max(1));
    for (im, k) in images[2..].iter_mut().zip(&config.thresholds) {
        im.short = format!("adaptive K = {k}");
    }
    Ok(Triptych {
        grid: config.grid,
        reference,
        images,
    })
}
