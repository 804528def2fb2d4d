//! The estimators compared (adaptive sampling as a receiver estimator,
//! stratified and random baselines) and the per-receiver references.

use super::*;

// ---------------------------------------------------------------------------
// Estimators
// ---------------------------------------------------------------------------

/// Ureña's (2000) adaptive sampling of the scene's triangle light at a
/// receiver ([`AdaptiveTriangle`]), as a [`ReceiverEstimator`].
///
/// [`ReceiverEstimator::prepare`] builds the sampler for the receiver once
/// (its partition is then built lazily and memoized where samples go);
/// each estimate draws `n = batch.light.len()` samples.
///
/// The estimator ignores the batch's points: the adaptive scheme places its
/// samples jointly (a piece gets `⌊P n⌋` or `⌊P n⌋ + 1` of them) and draws
/// them with its *own* randomness, from an rng seeded with
/// [`Batch::seed`], which keeps it deterministic. It reuses one
/// [`SampleSet`] per prepared receiver; the subdivision below the
/// sampler's cache depth is recomputed per call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveEstimator {
    /// The threshold `K` (`> 0`; `f64::INFINITY` never splits: plain,
    /// unstratified solid-angle sampling).
    pub k: f64,
    /// How samples are distributed among sub-triangles.
    pub allocation: Allocation,
}

impl AdaptiveEstimator {
    /// Threshold `k` with the default allocation ([`Allocation::Systematic`],
    /// exactly unbiased).
    pub fn new(k: f64) -> Self {
        AdaptiveEstimator {
            k,
            allocation: Allocation::default(),
        }
    }

    /// The same estimator with another allocation rule.
    pub fn with_allocation(mut self, allocation: Allocation) -> Self {
        self.allocation = allocation;
        self
    }
}

/// `0.1`, `0.001`, `∞`.
pub(crate) fn k_label(k: f64) -> String {
    if k.is_infinite() {
        "∞".to_string()
    } else {
        format!("{k}")
    }
}

impl ReceiverEstimator for AdaptiveEstimator {
    /// `adaptive K=0.1`, `adaptive K=∞`; the allocation is appended unless
    /// it is the default (`adaptive K=0.1 (successive)`).
    fn name(&self) -> String {
        let base = format!("adaptive K={}", k_label(self.k));
        if self.allocation == Allocation::default() {
            base
        } else {
            format!("{base} ({})", self.allocation)
        }
    }

    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError> {
        let v = scene.emitter().polygon().vertices();
        if v.len() != 3 {
            return Err(WarpError::InvalidParameter {
                name: "scene",
                expected: "a triangular emitter for adaptive sampling",
            });
        }
        let sampler = AdaptiveTriangle::from_points(
            [&v[0], &v[1], &v[2]],
            receiver.position(),
            receiver.normal(),
            self.k,
        )?
        .with_allocation(self.allocation);
        Ok(Box::new(PreparedAdaptive {
            scene,
            receiver,
            sampler,
            samples: SampleSet::default(),
        }))
    }
}

/// An [`AdaptiveEstimator`] at a receiver.
pub(crate) struct PreparedAdaptive<'s> {
    pub(crate) scene: &'s Scene,
    pub(crate) receiver: &'s Receiver,
    pub(crate) sampler: AdaptiveTriangle,
    pub(crate) samples: SampleSet,
}

impl PreparedEstimator for PreparedAdaptive<'_> {
    fn estimate(&mut self, batch: &Batch<'_>) -> Result<f64, WarpError> {
        let mut rng = job_rng(batch.seed, 0);
        self.sampler
            .generate_into(batch.light.len(), &mut rng, &mut self.samples);
        let (scene, rx) = (self.scene, self.receiver);
        // Σ g/p with g = L V cos⁺θ, the integrand of the other methods.
        Ok(self
            .samples
            .estimate_solid_angle(|d| scene.integrand(rx, &Quantity::Irradiance, d)))
    }
}

/// A [`Method`] of the variance study under another name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Named {
    pub(crate) name: &'static str,
    pub(crate) method: Method,
}

impl ReceiverEstimator for Named {
    fn name(&self) -> String {
        self.name.to_string()
    }

    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError> {
        ReceiverEstimator::prepare(&self.method, scene, receiver)
    }
}

/// A [`Method`] fed independent uniform points of its own (from
/// [`Batch::seed`]) instead of the batch's stratified ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RandomPoints(pub(crate) Named);

pub(crate) struct PreparedRandom<'s> {
    pub(crate) inner: Box<dyn PreparedEstimator + 's>,
    pub(crate) points: Vec<(f64, f64)>,
}

impl ReceiverEstimator for RandomPoints {
    fn name(&self) -> String {
        self.0.name()
    }

    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError> {
        Ok(Box::new(PreparedRandom {
            inner: self.0.prepare(scene, receiver)?,
            points: Vec::new(),
        }))
    }
}

impl PreparedEstimator for PreparedRandom<'_> {
    fn estimate(&mut self, batch: &Batch<'_>) -> Result<f64, WarpError> {
        let mut rng = job_rng(batch.seed, 0);
        self.points.clear();
        self.points
            .extend((0..batch.light.len()).map(|_| (rng.random::<f64>(), rng.random::<f64>())));
        self.inner.estimate(&Batch {
            light: &self.points,
            partner: &[],
            point_set: batch.point_set,
            seed: batch.seed,
        })
    }
}

/// Name of stratified solid-angle sampling (spherical triangle, jittered).
pub const STRATIFIED_SOLID_ANGLE: &str = "stratified solid angle";
/// Name of stratified cosine-weighted sampling (projected polygon, jittered).
pub const STRATIFIED_COSINE: &str = "stratified cosine-weighted";
/// Name of cosine-weighted sampling with independent points.
pub const RANDOM_COSINE: &str = "random cosine-weighted";

// ---------------------------------------------------------------------------
// References
// ---------------------------------------------------------------------------

/// How the converged references are computed (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceConfig {
    /// Independent replicas of the occluded-part estimate (≥ 2).
    pub replicas: usize,
    /// Each replica uses `side × side` jittered solid-angle samples.
    pub side: usize,
}

/// The reference irradiance at a receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceValue {
    /// `E = E_free − B̂`.
    pub value: f64,
    /// The standard error of `value` (that of `B̂`; 0 where no occluder
    /// can shadow the receiver).
    pub std_error: f64,
    /// `E_free`: the unoccluded irradiance, exact (Lambert per cell).
    pub unoccluded: f64,
    /// `B̂`: the estimated occluded part.
    pub blocked: f64,
}

impl ReferenceValue {
    /// `std_error / value`.
    pub fn relative_std_error(&self) -> f64 {
        self.std_error / self.value
    }
}

/// `true` if some occluder of the scene lies (partly) strictly between the
/// receiver and the light's plane, so that it may shadow the receiver.
pub(crate) fn may_be_shadowed(scene: &Scene, receiver: &Receiver) -> bool {
    let light = scene.emitter().polygon();
    let dx = light.signed_distance(receiver.position());
    scene.occluders().iter().any(|o| {
        let (lo, hi) = o.vertices().iter().fold((f64::MAX, f64::MIN), |(a, b), v| {
            let d = light.signed_distance(v) * dx.signum();
            (a.min(d), b.max(d))
        });
        lo < dx.abs() && hi > 0.0
    })
}

/// The references at every receiver of `setup` (see the module docs);
/// deterministic for any thread count.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for fewer than 2 replicas or a side
/// below 2; as [`strategies::spherical_triangles`] at a receiver that may
/// be shadowed.
pub fn references(
    setup: &Setup,
    config: &ReferenceConfig,
    seed: u64,
) -> Result<Vec<ReferenceValue>, WarpError> {
    if config.replicas < 2 || config.side < 2 {
        return Err(WarpError::InvalidParameter {
            name: "reference",
            expected: "at least 2 replicas of at least 2 x 2 samples",
        });
    }
    let scene = &setup.scene;
    let emitter = scene.emitter();
    let light = emitter.polygon();
    let shadowed: Vec<bool> = setup
        .receivers
        .iter()
        .map(|r| may_be_shadowed(scene, r))
        .collect();
    let k = config.replicas;
    let side = config.side;
    let blocked = run_jobs(setup.receivers.len() * k, seed, |i, rng| {
        let r = i / k;
        if !shadowed[r] {
            return Ok(0.0);
        }
        let rx = &setup.receivers[r];
        let x = rx.position();
        let map = strategies::spherical_triangles(light, x)?;
        let mut sum = 0.0;
        for (u, v) in jittered_iter::<f64, _>(side, side, rng) {
            let Some(s) = map.sample(u, v) else { continue };
            let d = &s.point;
            let cos = rx.normal().dot(d);
            if cos > 0.0
                && let Some(hit) = light.intersect(x, d)
                && scene.occluded(x, d, hit.t)
            {
                sum += emitter.emitted(&hit.point, &d.neg()) * cos / s.pdf;
            }
        }
        Ok(sum / (side * side) as f64)
    });
    setup
        .receivers
        .iter()
        .enumerate()
        .map(|(r, rx)| {
            let mut stats = Stats::new();
            for b in &blocked[r * k..(r + 1) * k] {
                stats.push(*b.as_ref().map_err(Clone::clone)?);
            }
            let free = lambert::irradiance(emitter, rx);
            let (b, se) = if shadowed[r] {
                (stats.mean(), stats.std_error())
            } else {
                (0.0, 0.0)
            };
            Ok(ReferenceValue {
                value: free - b,
                std_error: se,
                unoccluded: free,
                blocked: b,
            })
        })
        .collect()
}
