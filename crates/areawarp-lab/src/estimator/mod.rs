//! The estimator pieces the variance experiments share: the light-sampling
//! strategies ([`Sampler`]), methods (a strategy alone or with MIS,
//! [`Method`]), point sets ([`PointSet`]: independent, jittered, Sobol),
//! the estimator interface ([`ReceiverEstimator`], [`PreparedEstimator`],
//! [`Batch`]) and the measurement engine ([`measure`]: relative RMS error
//! against spp per receiver subset, fitted rates, samples at equal error,
//! failures). The variance study, the adaptive comparison of Ureña 2000
//! and the equal-time tables all measure through it.

use crate::jobs::run_jobs;
use crate::scene::setup::Setup;
use crate::scene::{PlanarPolygon, Quantity, Receiver, Scene, strategies};
use areawarp::error::WarpError;
use areawarp::estimate::{Heuristic, Mis, Strategy, job_seed, monte_carlo};
use areawarp::sampling::{Sobol2, jittered_iter};
use areawarp::vector::Vec3;
use rand::Rng;
use rand::rngs::Xoshiro256PlusPlus;

mod measure;
pub use self::measure::*;

// ---------------------------------------------------------------------------
// Samplers, methods, point sets
// ---------------------------------------------------------------------------

/// A sampling strategy for the light at a receiver (all densities in solid
/// angle; see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampler {
    /// Uniform area sampling of the light ([`strategies::AreaSampling`]).
    Area,
    /// Two spherical triangles (the rectangle's triangulation), one chosen
    /// with probability ∝ its solid angle ([`strategies::spherical_triangles`]).
    TrianglePair,
    /// The spherical rectangle of Ureña et al. ([`strategies::spherical_rectangle`]).
    Rectangle,
    /// The projected (cosine-weighted) polygon ([`strategies::projected_polygon`]),
    /// its marginal inverted to convergence (Newton from Arvo's cubic).
    ProjectedPolygon,
    /// The same map with the marginal inverted by Arvo's fitted cubic alone
    /// ([`MarginalInversion::Cubic`](areawarp::shapes::MarginalInversion::Cubic)):
    /// cheaper, but its samples are not exactly distributed as the density it
    /// reports (Arvo 2001 deems Newton's refinement "not warranted").
    ProjectedPolygonCubic,
    /// Cosine-weighted directions about the receiver's normal
    /// ([`strategies::cosine_sampling`]); the MIS partner of the others.
    Cosine,
    /// The modern baseline: the spherical rectangle composed with a
    /// bilinear warp of the corner cosines (Hart et al. 2020, pbrt-v4's
    /// `SampleBilinear`; [`crate::scene::bilinear`]).
    BilinearRectangle,
}

impl Sampler {
    /// The light samplers of the study, in table order.
    pub const LIGHT: [Sampler; 5] = [
        Sampler::Area,
        Sampler::TrianglePair,
        Sampler::Rectangle,
        Sampler::ProjectedPolygon,
        Sampler::BilinearRectangle,
    ];

    /// A short name: `area`, `triangle pair`, `rectangle`, `projected polygon`, `cosine`.
    pub fn name(&self) -> &'static str {
        match self {
            Sampler::Area => "area",
            Sampler::TrianglePair => "triangle pair",
            Sampler::Rectangle => "rectangle",
            Sampler::ProjectedPolygon => "projected polygon",
            Sampler::ProjectedPolygonCubic => "projected polygon (cubic only)",
            Sampler::Cosine => "cosine",
            Sampler::BilinearRectangle => "bilinear-cosine rectangle",
        }
    }

    /// The strategy at `receiver` for the light of `scene`.
    ///
    /// # Errors
    /// As the strategy's constructor.
    pub fn strategy(
        &self,
        scene: &Scene,
        receiver: &Receiver,
    ) -> Result<Box<dyn Strategy<Point = Vec3<f64>>>, WarpError> {
        let light = scene.emitter().polygon();
        let x = receiver.position();
        Ok(match self {
            Sampler::Area => Box::new(strategies::AreaSampling::new(light, x)?),
            Sampler::TrianglePair => Box::new(strategies::spherical_triangles(light, x)?),
            Sampler::Rectangle => Box::new(strategies::spherical_rectangle(light, x)?),
            Sampler::ProjectedPolygon => Box::new(strategies::projected_polygon(light, receiver)?),
            Sampler::ProjectedPolygonCubic => Box::new(strategies::projected_polygon_with(
                light,
                receiver,
                areawarp::shapes::MarginalInversion::Cubic,
            )?),
            Sampler::Cosine => Box::new(strategies::cosine_sampling(receiver)?),
            Sampler::BilinearRectangle => Box::new(
                crate::scene::bilinear::BilinearCosineRectangle::new(light, receiver)?,
            ),
        })
    }
}

/// A method of the study: a sampler alone, or combined by MIS with cosine
/// sampling (`n` samples of each) under a heuristic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Method {
    /// The light sampler.
    pub sampler: Sampler,
    /// `Some(h)`: MIS with cosine sampling under heuristic `h`.
    pub mis: Option<Heuristic>,
}

impl Method {
    /// The sampler alone.
    pub fn plain(sampler: Sampler) -> Self {
        Method { sampler, mis: None }
    }

    /// The sampler and cosine sampling under `heuristic`.
    pub fn mis(sampler: Sampler, heuristic: Heuristic) -> Self {
        Method {
            sampler,
            mis: Some(heuristic),
        }
    }

    /// `rectangle`, `rectangle+MIS(balance)`, `area+MIS(power(2))`, …
    pub fn name(&self) -> String {
        match self.mis {
            None => self.sampler.name().to_string(),
            Some(h) => format!("{}+MIS({})", self.sampler.name(), h.name()),
        }
    }

    /// The study's standard list: the four light samplers and cosine
    /// sampling alone, the four light samplers with the balance heuristic,
    /// and for each of `heuristic_samplers` the power (β = 2) and maximum
    /// heuristics.
    pub fn standard(heuristic_samplers: &[Sampler]) -> Vec<Method> {
        let mut out: Vec<Method> = Sampler::LIGHT.iter().map(|&s| Method::plain(s)).collect();
        out.push(Method::plain(Sampler::Cosine));
        out.extend(
            Sampler::LIGHT
                .iter()
                .map(|&s| Method::mis(s, Heuristic::Balance)),
        );
        for &s in heuristic_samplers {
            out.push(Method::mis(s, Heuristic::Power(2.0)));
            out.push(Method::mis(s, Heuristic::Maximum));
        }
        out
    }
}

/// The points on `[0, 1]²` fed to the maps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointSet {
    /// Jittered (stratified): one uniform point per cell of an `n_x × n_y`
    /// grid, `n_x` the smallest divisor of `n` with `n_x² ≥ n`.
    Jittered,
    /// The first `n` points of the Owen-scrambled Sobol sequence, a fresh
    /// scramble for every estimate ([`Sobol2::scrambled`]).
    Sobol,
    /// `n` independent uniform points: plain Monte Carlo, the setting of
    /// Veach's bound on the balance heuristic.
    Independent,
}

impl PointSet {
    /// `jittered`, `sobol` or `independent`.
    pub fn name(&self) -> &'static str {
        match self {
            PointSet::Jittered => "jittered",
            PointSet::Sobol => "sobol",
            PointSet::Independent => "independent",
        }
    }

    /// Replaces `out` by `n` points of this set, randomized from `rng`.
    pub fn fill<R: Rng + ?Sized>(&self, n: usize, rng: &mut R, out: &mut Vec<(f64, f64)>) {
        out.clear();
        match self {
            PointSet::Jittered => {
                let nx = grid_columns(n);
                let ny = n.checked_div(nx).unwrap_or(0);
                out.extend(jittered_iter::<f64, _>(nx, ny, rng));
            }
            PointSet::Sobol => {
                out.extend(Sobol2::<f64>::scrambled(rng.next_u64()).take(n));
            }
            PointSet::Independent => {
                use rand::RngExt as _;
                out.extend((0..n).map(|_| (rng.random::<f64>(), rng.random::<f64>())));
            }
        }
    }
}

/// The smallest divisor `d` of `n` with `d² ≥ n` (`2^⌈m/2⌉` for `n = 2^m`).
pub(crate) fn grid_columns(n: usize) -> usize {
    if n == 0 {
        return 0;
    }
    (1..=n)
        .find(|d| n.is_multiple_of(*d) && d * d >= n)
        .unwrap_or(n)
}

// ---------------------------------------------------------------------------
// The estimator interface (also the hook for other studies)
// ---------------------------------------------------------------------------

/// The points of one estimate: `light` for the method's main strategy and
/// an independent set `partner` of the same size for a second strategy
/// (the MIS partner), plus a seed for methods that draw their own
/// randomness (e.g. adaptive sampling).
#[derive(Clone, Copy, Debug)]
pub struct Batch<'a> {
    /// The points of the main strategy (`n` = the spp).
    pub light: &'a [(f64, f64)],
    /// Independent points of the same set, for a second strategy.
    pub partner: &'a [(f64, f64)],
    /// The point set both come from.
    pub point_set: PointSet,
    /// A seed for this estimate and method (derived from the job's stream).
    pub seed: u64,
}

/// An estimator of the irradiance at one receiver, prepared once per
/// receiver and run ([`ReceiverEstimator::prepare`]).
pub trait PreparedEstimator {
    /// The estimate from the batch's points.
    ///
    /// # Errors
    /// Whatever makes the estimate impossible; the study counts and
    /// reports it.
    fn estimate(&mut self, batch: &Batch<'_>) -> Result<f64, WarpError>;
}

/// A method measured by [`measure`]: anything that can estimate the
/// irradiance at a receiver from a [`Batch`] of points. The study's own
/// [`Method`]s implement it; so can other samplers (the hook for the
/// adaptive sampling of Ureña 2000).
pub trait ReceiverEstimator: Sync {
    /// The name in tables and figures (no commas).
    fn name(&self) -> String;

    /// The estimator at `receiver` (called once per receiver and run).
    ///
    /// # Errors
    /// If the method cannot be used at this receiver: the receiver is then
    /// skipped for this method, and the failure counted and reported.
    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError>;
}

/// A [`Method`] prepared at a receiver.
pub(crate) struct PreparedMethod<'s> {
    pub(crate) scene: &'s Scene,
    pub(crate) receiver: &'s Receiver,
    pub(crate) light: Box<dyn Strategy<Point = Vec3<f64>>>,
    pub(crate) cosine: Option<Box<dyn Strategy<Point = Vec3<f64>>>>,
    pub(crate) heuristic: Option<Heuristic>,
}

impl PreparedEstimator for PreparedMethod<'_> {
    fn estimate(&mut self, batch: &Batch<'_>) -> Result<f64, WarpError> {
        let (scene, rx) = (self.scene, self.receiver);
        let f = |d: &Vec3<f64>| scene.integrand(rx, &Quantity::Irradiance, d);
        match (&self.cosine, self.heuristic) {
            (Some(cosine), Some(h)) => {
                let s: [&dyn Strategy<Point = Vec3<f64>>; 2] = [&*self.light, &**cosine];
                let n = batch.light.len();
                let mis = Mis::new(&s, &[n, batch.partner.len().min(n)], h)?;
                let pts = [batch.light, batch.partner];
                Ok(mis.estimate(f, |i| pts[i].iter().copied())?.value)
            }
            _ => Ok(monte_carlo(&*self.light, f, batch.light.iter().copied()).value),
        }
    }
}

impl ReceiverEstimator for Method {
    fn name(&self) -> String {
        Method::name(self)
    }

    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError> {
        let light = self.sampler.strategy(scene, receiver)?;
        let cosine = match self.mis {
            Some(_) => Some(Sampler::Cosine.strategy(scene, receiver)?),
            None => None,
        };
        Ok(Box::new(PreparedMethod {
            scene,
            receiver,
            light,
            cosine,
            heuristic: self.mis,
        }))
    }
}
