//! MIS on a glossy receiver: the variance study's light samplers combined
//! with a sample of a Phong BRDF instead of the cosine.
//!
//! The diffuse rows of the study combine each light sampler with cosine
//! sampling, whose density is proportional to a diffuse receiver's
//! integrand apart from the light's extent; that is MIS's weakest case. On
//! a glossy (modified Phong) receiver the BRDF has a lobe about the mirror
//! direction that the light samplers ignore, and BRDF sampling
//! ([`strategies::brdf_sampling`]: the cosine lobe ∝ `k_d`, the Phong lobe
//! ∝ `k_s`) concentrates where the lobe is — the case MIS is made for.
//!
//! The receivers, runs, spp levels and jittered points are the study's;
//! the quantity is the reflected radiance toward a distant viewer on the
//! far side of the receivers, so that the mirror direction points at the
//! light. No closed form exists for a Phong lobe over a polygon here, so
//! the reference at each receiver is a converged estimate: MIS (balance)
//! of the spherical rectangle and BRDF sampling with
//! [`GlossyConfig::reference_samples`] jittered points each, in replicates
//! whose spread gives its relative standard error (reported beside the
//! table).

use super::tables::{error_table, table_levels};
use super::*;
use crate::scene::{Quantity, Reflectance, strategies};
use areawarp::estimate::{Mis, Strategy, job_rng, monte_carlo};
use areawarp::sampling::jittered;

/// The glossy receiver and the size of its measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct GlossyConfig {
    /// Diffuse coefficient `k_d`.
    pub diffuse: f64,
    /// Specular coefficient `k_s`.
    pub specular: f64,
    /// Phong exponent `n`.
    pub exponent: f64,
    /// The direction toward the viewer (normalized; receivers face `+z`).
    pub outgoing: Vec3<f64>,
    /// Jittered points per strategy of each receiver's reference (in 8
    /// replicates).
    pub reference_samples: usize,
    /// The light samplers (each alone and with MIS).
    pub samplers: Vec<Sampler>,
}

impl GlossyConfig {
    /// The tests' size.
    pub fn quick() -> Self {
        GlossyConfig {
            reference_samples: 1 << 12,
            ..Self::default()
        }
    }
}

impl Default for GlossyConfig {
    /// `k_d = 0.2`, `k_s = 0.8`, `n = 20`, the viewer at 45° on the far
    /// side (`ω_o ∝ (0, 1, 1)`: mirror direction toward the light),
    /// references with 2¹⁷ points per strategy; the rectangle, triangle
    /// pair, area and bilinear-cosine samplers.
    fn default() -> Self {
        GlossyConfig {
            diffuse: 0.2,
            specular: 0.8,
            exponent: 20.0,
            outgoing: Vec3::new(0.0, 1.0, 1.0),
            reference_samples: 1 << 17,
            samplers: vec![
                Sampler::Rectangle,
                Sampler::TrianglePair,
                Sampler::Area,
                Sampler::BilinearRectangle,
            ],
        }
    }
}

/// A method on the glossy receiver: a light sampler alone, BRDF sampling
/// alone (`sampler = None`), or both under the balance heuristic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlossyMethod {
    /// The light sampler (`None`: BRDF sampling alone).
    pub sampler: Option<Sampler>,
    /// Combined with BRDF sampling by MIS (balance heuristic).
    pub mis: bool,
    /// The BRDF.
    pub reflectance: Reflectance,
    /// Toward the viewer (unit).
    pub outgoing: Vec3<f64>,
}

struct PreparedGlossy<'s> {
    scene: &'s Scene,
    receiver: &'s Receiver,
    quantity: Quantity,
    light: Option<Box<dyn Strategy<Point = Vec3<f64>>>>,
    brdf: Option<Box<dyn Strategy<Point = Vec3<f64>>>>,
}

impl PreparedEstimator for PreparedGlossy<'_> {
    fn estimate(&mut self, batch: &Batch<'_>) -> Result<f64, WarpError> {
        let (scene, rx, q) = (self.scene, self.receiver, &self.quantity);
        let f = |d: &Vec3<f64>| scene.integrand(rx, q, d);
        match (&self.light, &self.brdf) {
            (Some(l), Some(b)) => {
                let s: [&dyn Strategy<Point = Vec3<f64>>; 2] = [&**l, &**b];
                let n = batch.light.len();
                let mis = Mis::new(&s, &[n, batch.partner.len().min(n)], Heuristic::Balance)?;
                let pts = [batch.light, batch.partner];
                Ok(mis.estimate(f, |i| pts[i].iter().copied())?.value)
            }
            (Some(only), None) | (None, Some(only)) => {
                Ok(monte_carlo(&**only, f, batch.light.iter().copied()).value)
            }
            (None, None) => Err(WarpError::InvalidParameter {
                name: "glossy method",
                expected: "a light sampler or BRDF sampling",
            }),
        }
    }
}

impl ReceiverEstimator for GlossyMethod {
    fn name(&self) -> String {
        match (self.sampler, self.mis) {
            (Some(s), true) => format!("{}+MIS(balance; BRDF)", s.name()),
            (Some(s), false) => s.name().to_string(),
            (None, _) => "BRDF (Phong) sampling".to_string(),
        }
    }

    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError> {
        let light = match self.sampler {
            Some(s) => Some(s.strategy(scene, receiver)?),
            None => None,
        };
        let brdf: Option<Box<dyn Strategy<Point = Vec3<f64>>>> =
            if self.mis || self.sampler.is_none() {
                Some(Box::new(strategies::brdf_sampling(
                    &self.reflectance,
                    receiver,
                    &self.outgoing,
                )?))
            } else {
                None
            };
        Ok(Box::new(PreparedGlossy {
            scene,
            receiver,
            quantity: Quantity::Radiance {
                reflectance: self.reflectance,
                outgoing: self.outgoing,
            },
            light,
            brdf,
        }))
    }
}

/// The glossy measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct GlossyStudy {
    /// Its configuration.
    pub config: GlossyConfig,
    /// The methods, in the measurement's order.
    pub methods: Vec<GlossyMethod>,
    /// The measurement (jittered points).
    pub measurement: Measurement,
    /// The largest estimated relative standard error of a reference.
    pub reference_rel_se: f64,
}

/// Runs the glossy measurement on the study's receivers, runs and spp.
///
/// # Errors
/// As [`Reflectance::phong`], the strategies and [`measure`].
pub fn run_glossy(study: &VarianceConfig, config: &GlossyConfig) -> Result<GlossyStudy, WarpError> {
    let reflectance = Reflectance::phong(config.diffuse, config.specular, config.exponent)?;
    let outgoing = config.outgoing.normalized().ok_or(WarpError::Degenerate {
        what: "viewer direction",
    })?;
    let setup = setup::standing_rectangle(
        study.width,
        study.height,
        study.radiance,
        study.near,
        study.far,
        study.rows,
        study.lateral,
    )?;
    let quantity = Quantity::Radiance {
        reflectance,
        outgoing,
    };
    // References: balance MIS of the rectangle and the BRDF, jittered, in
    // independent replicates (their spread is an honest error for
    // jittered points).
    const REPLICATES: usize = 8;
    let side = (((config.reference_samples / REPLICATES) as f64)
        .sqrt()
        .floor() as usize)
        .max(2);
    let refs = crate::jobs::run_jobs(setup.receivers.len(), study.seed ^ 0x6105_5EED, |i, _| {
        let r = &setup.receivers[i];
        let rect = Sampler::Rectangle.strategy(&setup.scene, r)?;
        let brdf = strategies::brdf_sampling(&reflectance, r, &outgoing)?;
        let s: [&dyn Strategy<Point = Vec3<f64>>; 2] = [&*rect, &brdf];
        let mis = Mis::new(&s, &[side * side; 2], Heuristic::Balance)?;
        let mut rng = job_rng(study.seed, i as u64);
        let mut values = [0.0; REPLICATES];
        for v in &mut values {
            *v = mis
                .estimate(
                    |d| setup.scene.integrand(r, &quantity, d),
                    |_| jittered::<f64, _>(side, side, &mut rng),
                )?
                .value;
        }
        let k = REPLICATES as f64;
        let mean = values.iter().sum::<f64>() / k;
        let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (k - 1.0);
        Ok::<_, WarpError>((mean, (var / k).sqrt() / mean))
    });
    // Receivers with a usable (positive) reference.
    let mut receivers = Vec::new();
    let mut references = Vec::new();
    let mut rel_se: f64 = 0.0;
    for (r, e) in setup.receivers.iter().zip(refs) {
        if let Ok((v, s)) = e
            && v > 0.0
            && v.is_finite()
        {
            receivers.push(r.clone());
            references.push(v);
            if s.is_finite() {
                rel_se = rel_se.max(s);
            }
        }
    }
    let mut methods = Vec::new();
    for &s in &config.samplers {
        methods.push(GlossyMethod {
            sampler: Some(s),
            mis: false,
            reflectance,
            outgoing,
        });
    }
    methods.push(GlossyMethod {
        sampler: None,
        mis: false,
        reflectance,
        outgoing,
    });
    for &s in &config.samplers {
        methods.push(GlossyMethod {
            sampler: Some(s),
            mis: true,
            reflectance,
            outgoing,
        });
    }
    let glossy_setup = Setup {
        scene: setup.scene.clone(),
        receivers,
    };
    let estimators: Vec<&dyn ReceiverEstimator> = methods
        .iter()
        .map(|m| m as &dyn ReceiverEstimator)
        .collect();
    let spp = study.spp();
    let spec = MeasureSpec {
        setup: &glossy_setup,
        references: &references,
        estimators: &estimators,
        point_sets: &[PointSet::Jittered],
        spp: &spp,
        runs: study.runs,
        seed: job_seed(study.seed, 0x6105),
        near_light: study.near_light,
    };
    let measurement = measure(&spec, study.fit_levels)?;
    Ok(GlossyStudy {
        config: config.clone(),
        methods,
        measurement,
        reference_rel_se: rel_se,
    })
}

impl GlossyStudy {
    /// The section to attach to the variance study (slug `glossy`): the
    /// error table and the MIS ratios with their intervals.
    pub fn to_section(&self) -> ExtraSection {
        ExtraSection {
            title: "MIS on a glossy (Phong) receiver: light sampling + BRDF sampling".to_string(),
            markdown: self.body_markdown(),
            slug: "glossy".to_string(),
            measurement: Some(self.measurement.clone()),
            claims: Vec::new(),
            claims_image: Vec::new(),
        }
    }

    /// RMS(light sampler + MIS) / RMS(light sampler alone) at the largest
    /// spp, with its jackknife standard error, per sampler.
    pub fn mis_ratios(&self) -> Vec<(Sampler, f64, f64)> {
        let ms = &self.measurement;
        let last = ms.spp.len().saturating_sub(1);
        self.config
            .samplers
            .iter()
            .filter_map(|&s| {
                let name = |mis| {
                    GlossyMethod {
                        sampler: Some(s),
                        mis,
                        ..self.methods[0]
                    }
                    .name()
                };
                let a = ms.method_index(&name(true))?;
                let b = ms.method_index(&name(false))?;
                let (r, se) = ms.error_ratio(Subset::All, a, b, 0, last);
                Some((s, r, se))
            })
            .collect()
    }

    /// The answer to our question "does combining each light sample with a
    /// BRDF sample by MIS lower the noise on the glossy receiver?" on the
    /// error measure `metric`, from [`GlossyStudy::mis_ratios`]: `yes`
    /// ([`Verdict::Reproduced`]) when every sampler's 95% interval of
    /// RMS(+MIS)/RMS(alone) lies below 1, `mixed` when some but not all
    /// do (MIS lowers the noise of some samplers only), direction only
    /// ([`Verdict::Qualitative`]) when every point is below 1 but no
    /// interval, `no` otherwise; with the ratios as text.
    pub fn mis_answer(&self, metric: Metric) -> (Verdict, String) {
        let study = GlossyStudy {
            measurement: self.measurement.with_metric(metric),
            ..self.clone()
        };
        let ratios = study.mis_ratios();
        let below = |r: f64, se: f64| crate::verdict::interval(r, se).1 < 1.0;
        let verdict = if ratios.is_empty() {
            Verdict::NotMeasured
        } else if ratios.iter().all(|x| below(x.1, x.2)) {
            Verdict::Reproduced
        } else if ratios.iter().any(|x| below(x.1, x.2)) {
            Verdict::Mixed
        } else if ratios.iter().all(|x| x.1 < 1.0) {
            Verdict::Qualitative
        } else {
            Verdict::NotReproduced
        };
        let text = ratios
            .iter()
            .map(|(s, r, se)| {
                format!(
                    "{} {} {}",
                    s.name(),
                    crate::verdict::sig3(*r),
                    crate::verdict::interval_text(*r, *se)
                )
            })
            .collect::<Vec<_>>()
            .join(", ");
        (verdict, text)
    }

    fn body_markdown(&self) -> String {
        let c = &self.config;
        let ms = &self.measurement;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "The study's receivers, runs, spp and jittered points, now glossy: modified Phong with k_d = {}, k_s = {}, n = {}, \
             seen by a distant viewer in direction ω_o ∝ ({}, {}, {}) (the mirror direction points at the light); the quantity is \
             the reflected radiance L_o = ∫ L f_r cos θ dω. MIS rows combine n light samples with n samples of the BRDF \
             (the cosine lobe with probability ∝ k_d, the Phong lobe about the mirror direction ∝ k_s) under the balance heuristic. \
             References: balance MIS of the spherical rectangle and the BRDF with {} jittered points each per receiver, \
             in 8 independent replicates (largest relative standard error over receivers, from the replicates' spread: {:.1e}). {} receivers \
             (those with a positive reference). Columns as in the diffuse error tables: the per-receiver relative RMS error \
             ± the half-width of its 95% interval (jackknife over runs), the fitted exponent α ± 95%, skipped receivers.\n",
            c.diffuse,
            c.specular,
            c.exponent,
            c.outgoing.x,
            c.outgoing.y,
            c.outgoing.z,
            c.reference_samples,
            self.reference_rel_se,
            ms.receivers.len(),
        );
        let ids: Vec<usize> = (0..ms.methods.len()).collect();
        error_table(&mut s, ms, &ids, 0, Subset::All, &table_levels(ms));
        let at = ms.spp.last().copied().unwrap_or(0);
        let _ = writeln!(
            s,
            "\n**What MIS with a BRDF sample does on the glossy receiver.** RMS error ratio, light sampler + MIS over the light \
             sampler alone, at {at} spp (light samples; MIS traces twice the rays), all receivers, ± 95% (jackknife over runs); \
             below 1: MIS lowers the error.\n\n| light sampler | RMS(+MIS) / RMS(alone) | 95% interval |\n|---|---:|---:|"
        );
        for (smp, r, se) in self.mis_ratios() {
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                smp.name(),
                crate::verdict::sig3(r),
                crate::verdict::interval_text(r, se)
            );
        }
        let _ = writeln!(
            s,
            "\n![Relative RMS error of the reflected radiance of a glossy receiver against spp, light samplers alone and with BRDF-sampling MIS, with 95% bands](variance_glossy.svg)\n"
        );
        s
    }
}
