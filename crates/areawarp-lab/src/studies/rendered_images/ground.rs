//! The images of Ureña, Fajardo & King (2013, Fig. 4 and 6): the ground
//! in front of the standing rectangular light of the variance study.

use super::*;
use crate::estimator::{Method, Sampler};
use crate::studies::variance::VarianceConfig;
use areawarp::estimate::Heuristic;

/// The standing-light images.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundConfig {
    /// Width of the light (the variance study's).
    pub width: f64,
    /// Its height.
    pub height: f64,
    /// Its radiance.
    pub radiance: f64,
    /// The pixels on the ground.
    pub grid: PixelGrid,
    /// Samples per pixel of the images.
    pub spp: Vec<usize>,
    /// The light samplers, each rendered alone (Fig. 4) and with MIS
    /// (Fig. 6).
    pub samplers: Vec<Sampler>,
}

impl Default for GroundConfig {
    /// The variance study's light (1 × 0.5, radiance 1, standing on the
    /// ground along `x ∈ [−½, ½]` at `y = 0`) seen from above over
    /// `x ∈ [−1, 1]`, `y ∈ [0, 1]` (the light's foot is the bottom edge of
    /// the image) in 200 × 100 pixels; 1, 4 and 16 spp; the study's five
    /// light samplers.
    fn default() -> Self {
        let v = VarianceConfig::default();
        GroundConfig {
            width: v.width,
            height: v.height,
            radiance: v.radiance,
            grid: PixelGrid {
                x: (-1.0, 1.0),
                y: (0.0, 1.0),
                cols: 200,
                rows: 100,
            },
            spp: vec![1, 4, 16],
            samplers: Sampler::LIGHT.to_vec(),
        }
    }
}

/// The rendered standing-light images.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundImages {
    /// The grid.
    pub grid: PixelGrid,
    /// The exact irradiance.
    pub reference: Image,
    /// The methods alone, in [`GroundConfig::samplers`] order.
    pub plain: Vec<Method>,
    /// `plain_images[m][l]`: method `plain[m]` at `spp[l]`.
    pub plain_images: Vec<Vec<Image>>,
    /// The same samplers with MIS (balance heuristic).
    pub mis: Vec<Method>,
    /// `mis_images[m][l]`.
    pub mis_images: Vec<Vec<Image>>,
}

/// Renders the standing-light images (the reference, then every sampler
/// alone and with MIS at every spp; alone and with MIS in one pass, so
/// that both see the same light points).
///
/// # Errors
/// As [`setup::standing_rectangle`], [`reference_image`] and [`render`].
pub fn render_ground(config: &GroundConfig, seed: u64) -> Result<GroundImages, WarpError> {
    let scene = standing_light(config.width, config.height, config.radiance)?;
    let reference = reference_image(&scene, &config.grid)?;
    let plain: Vec<Method> = config.samplers.iter().map(|&s| Method::plain(s)).collect();
    let mis: Vec<Method> = config
        .samplers
        .iter()
        .map(|&s| Method::mis(s, Heuristic::Balance))
        .collect();
    let estimators: Vec<&dyn ReceiverEstimator> = plain
        .iter()
        .chain(&mis)
        .map(|m| m as &dyn ReceiverEstimator)
        .collect();
    let mut images = render(&scene, &config.grid, &estimators, &config.spp, seed)?;
    let mis_images = images.split_off(plain.len());
    Ok(GroundImages {
        grid: config.grid,
        reference,
        plain,
        plain_images: images,
        mis,
        mis_images,
    })
}
