//! The study: configuration, rows, the replicated measurement, its Markdown;
//! the bias of the allocation rule.

use super::*;

/// What [`study`] measures.
#[derive(Clone, Debug)]
pub struct StudyConfig {
    /// The cases.
    pub cases: Vec<StudyCase>,
    /// The thresholds K (`f64::INFINITY` = no subdivision: Arvo's
    /// solid-angle sampling).
    pub thresholds: Vec<f64>,
    /// Samples per estimate `n`.
    pub samples: usize,
    /// Independent estimates per case and K.
    pub replicates: usize,
    /// Cosine-weighted samples for the references.
    pub reference_samples: usize,
    /// Largest partition counted ([`AdaptiveTriangle::piece_count`]).
    pub piece_limit: usize,
    /// The allocation rule.
    pub allocation: Allocation,
    /// The seed (every row and reference has its own stream).
    pub seed: u64,
}

impl StudyConfig {
    /// The report's configuration: [`standard_cases`], K ∈ {∞, 0.3, 0.1,
    /// 0.01, 0.001}, `n = 64`, 4000 estimates per row, 2²⁰ reference
    /// samples, [`Allocation::Systematic`], seed 2000.
    ///
    /// # Errors
    /// As [`standard_cases`].
    pub fn standard() -> Result<Self, WarpError> {
        Ok(StudyConfig {
            cases: standard_cases()?,
            thresholds: vec![f64::INFINITY, 0.3, 0.1, 0.01, 0.001],
            samples: 64,
            replicates: 4000,
            reference_samples: 1 << 20,
            piece_limit: 1 << 20,
            allocation: Allocation::Systematic,
            seed: 2000,
        })
    }
}

/// One row of the study: a case at one threshold K.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyRow {
    /// The case's name.
    pub case: String,
    /// Its integrand.
    pub integrand: StudyIntegrand,
    /// K.
    pub k_threshold: f64,
    /// The full partition's summary (`None` above the piece limit).
    pub partition: Option<PartitionSummary>,
    /// Mean number of pieces that received samples, per estimate.
    pub leaves_per_estimate: f64,
    /// Mean depth of the pieces that received samples.
    pub mean_depth: f64,
    /// The reference `I` and its standard error.
    pub reference: f64,
    /// The reference's standard error.
    pub reference_se: f64,
    /// The mean of the estimates.
    pub mean: f64,
    /// `(mean − I)/√(se² + se_ref²)`.
    pub z: f64,
    /// Per-sample second moment `U = E[(f w)²]` over `U₀` measured on the
    /// same samples as `E[σ⊥ f² w]` (paired ratio; `≤ 1 + K` sample by
    /// sample), and its standard error.
    pub u_ratio: f64,
    /// Standard error of [`StudyRow::u_ratio`].
    pub u_ratio_se: f64,
    /// `U` over the reference `U₀`, and its standard error.
    pub u_over_u0_ref: f64,
    /// Standard error of [`StudyRow::u_over_u0_ref`].
    pub u_over_u0_ref_se: f64,
    /// Effective second moment from the spread of the estimates,
    /// `n Var(Î) + I²`, over `U₀` (includes the gain of the stratified
    /// allocation), and its standard error.
    pub u_eff_ratio: f64,
    /// Standard error of [`StudyRow::u_eff_ratio`].
    pub u_eff_ratio_se: f64,
    /// The bound on [`StudyRow::u_ratio`]: `1 + K` plus the capped pieces'
    /// allowance `Σ_{i capped} σ⊥ f_i² w_i (k(R_i) − K) / Σ_i σ⊥ f_i² w_i`
    /// over the same samples (0 if no sample fell in a capped piece). The
    /// paired ratio is below it sample by sample, since
    /// `w ≤ σ⊥ (1 + k(R))` on every piece.
    pub bound: f64,
    /// The capped pieces' allowance alone (`bound − 1 − K`, 0 if no sample
    /// fell in a capped piece).
    pub capped_allowance: f64,
    /// `max_i w_i/σ⊥ − 1` over all samples (`< K` unless a capped piece
    /// was sampled).
    pub max_weight_excess: f64,
    /// Samples that fell in capped pieces.
    pub capped_samples: u64,
}

/// The results of [`study`].
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveStudy {
    /// Samples per estimate.
    pub samples: usize,
    /// Estimates per row.
    pub replicates: usize,
    /// The allocation rule.
    pub allocation: Allocation,
    /// The seed.
    pub seed: u64,
    /// Per case: name, integrand and its reference.
    pub references: Vec<(String, StudyIntegrand, Reference)>,
    /// The rows, case by case, K by K.
    pub rows: Vec<StudyRow>,
}

/// Per-estimate measurements.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Replicate {
    pub(crate) estimate: f64,
    /// `(1/n) Σ (f w)²`.
    pub(crate) u: f64,
    /// `(1/n) Σ σ⊥ f² w`.
    pub(crate) u0: f64,
    pub(crate) max_weight: f64,
    pub(crate) leaves: usize,
    pub(crate) depth_sum: f64,
    pub(crate) capped: u64,
    /// `(1/n) Σ_capped σ⊥ f² w (k − K)`.
    pub(crate) allowance: f64,
}

/// Runs the study: for every case and K, `replicates` independent
/// estimates of `n = samples` adaptive samples, each on its own random
/// stream (deterministic for a fixed seed, whatever the thread count).
///
/// # Errors
/// As [`StudyCase::reference`] and [`StudyCase::sampler`];
/// [`WarpError::InvalidParameter`] for fewer than 2 samples or replicates.
pub fn study(config: &StudyConfig) -> Result<AdaptiveStudy, WarpError> {
    if config.samples < 1 || config.replicates < 2 {
        return Err(WarpError::InvalidParameter {
            name: "study size",
            expected: "samples >= 1 and replicates >= 2",
        });
    }
    let mut references = Vec::new();
    let mut rows = Vec::new();
    let mut row_index = 0u64;
    for (ci, case) in config.cases.iter().enumerate() {
        let reference = case.reference(
            config.reference_samples,
            job_seed(config.seed, 1_000_000 + ci as u64),
        )?;
        for &k in &config.thresholds {
            let t = case.sampler(k)?.with_allocation(config.allocation);
            rows.push(measure_row(config, case, &t, &reference, row_index)?);
            row_index += 1;
        }
        references.push((case.name.clone(), case.integrand, reference));
    }
    Ok(AdaptiveStudy {
        samples: config.samples,
        replicates: config.replicates,
        allocation: config.allocation,
        seed: config.seed,
        references,
        rows,
    })
}

/// One row of [`study`].
pub(crate) fn measure_row(
    config: &StudyConfig,
    case: &StudyCase,
    t: &AdaptiveTriangle,
    reference: &Reference,
    row_index: u64,
) -> Result<StudyRow, WarpError> {
    let sp = t.projected_solid_angle();
    let k_threshold = t.threshold();
    let n = config.samples;
    let reps = run_jobs(
        config.replicates,
        job_seed(config.seed, row_index),
        |_, rng| {
            let set = t.generate(n, rng);
            let mut r = Replicate::default();
            for (i, d) in set.directions.iter().enumerate() {
                let w = set.weights[i];
                let f = case.f(d);
                if f != 0.0 {
                    r.estimate += f * w;
                    r.u += (f * w) * (f * w);
                    r.u0 += sp * f * f * w;
                    let leaf = &set.leaves[set.leaf[i] as usize];
                    if leaf.capped {
                        r.allowance += sp * f * f * w * (leaf.k - k_threshold).max(0.0);
                    }
                }
                r.max_weight = r.max_weight.max(w);
            }
            let nf = n as f64;
            r.estimate /= nf;
            r.u /= nf;
            r.u0 /= nf;
            r.allowance /= nf;
            r.leaves = set.leaves.len();
            for l in &set.leaves {
                r.depth_sum += l.depth as f64;
                if l.capped {
                    r.capped += l.count as u64;
                }
            }
            r
        },
    );
    let mut est = Stats::new();
    let mut u = Stats::new();
    let mut u0 = Stats::new();
    let mut leaves = 0usize;
    let mut depth_sum = 0.0;
    let mut capped = 0u64;
    let mut max_weight: f64 = 0.0;
    let mut allowance = 0.0;
    for r in &reps {
        est.push(r.estimate);
        u.push(r.u);
        u0.push(r.u0);
        leaves += r.leaves;
        depth_sum += r.depth_sum;
        capped += r.capped;
        max_weight = max_weight.max(r.max_weight);
        allowance += r.allowance;
    }
    let rn = reps.len() as f64;
    // Paired ratio U/U₀ = Ū/Ū₀, delta-method standard error over replicates.
    let ratio = u.mean() / u0.mean();
    let resid: Stats = reps.iter().map(|r| r.u - ratio * r.u0).collect();
    let ratio_se = resid.std_error() / u0.mean();
    // Effective U from the spread of the estimates.
    let var = est.variance();
    let m4 = reps
        .iter()
        .map(|r| (r.estimate - est.mean()).powi(4))
        .sum::<f64>()
        / rn;
    let var_se = ((m4 - var * var).max(0.0) / rn).sqrt();
    let i_ref = reference.value;
    let u_eff = n as f64 * var + i_ref * i_ref;
    let se = (var / rn + reference.value_se * reference.value_se).sqrt();
    let z = if se > 0.0 {
        (est.mean() - i_ref) / se
    } else if est.mean() == i_ref {
        0.0
    } else {
        f64::INFINITY.copysign(est.mean() - i_ref)
    };
    let partition = t.partition_summary(config.piece_limit);
    let allowance = if allowance > 0.0 {
        allowance / rn / u0.mean()
    } else {
        0.0
    };
    Ok(StudyRow {
        case: case.name.clone(),
        integrand: case.integrand,
        k_threshold: t.threshold(),
        partition,
        leaves_per_estimate: leaves as f64 / rn,
        mean_depth: depth_sum / leaves.max(1) as f64,
        reference: i_ref,
        reference_se: reference.value_se,
        mean: est.mean(),
        z,
        u_ratio: ratio,
        u_ratio_se: ratio_se,
        u_over_u0_ref: u.mean() / reference.u0,
        u_over_u0_ref_se: u.std_error() / reference.u0,
        u_eff_ratio: u_eff / reference.u0,
        u_eff_ratio_se: n as f64 * var_se / reference.u0,
        bound: 1.0 + k_threshold + allowance,
        capped_allowance: allowance,
        max_weight_excess: max_weight / sp - 1.0,
        capped_samples: capped,
    })
}

impl AdaptiveStudy {
    /// The results as Markdown: the references, then one table row per
    /// case and K.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Ureña (2000, §3.2) bounds the second moment U of the adaptive estimator by (1 + K) U₀, U₀ that of ideal \
             cosine-weighted sampling. Measured here on 5 triangles × 4 integrands and the scene of §5: n = {} samples per \
             estimate, {} estimates per row, allocation `{}`, seed {}.\n\n\
             Columns. First table: *σ*, *σ⊥* — solid angle and projected solid angle of the triangle; *I* — the integral \
             (± its standard error when estimated); *U₀* — the ideal second moment; *reference* — how I and U₀ were \
             obtained; *U₀ (cos-sampling)/U₀* — a check of U₀ by cosine-weighted sampling (should be 1). Second table: \
             *pieces* — pieces of the adaptive partition (\"> limit\": more than the piece limit); *leaves/est.* — distinct \
             pieces one n-sample estimate visits; *mean depth* — mean subdivision depth of the sampled pieces; \
             *U/U₀ − 1 (paired)* — the excess second moment against cosine-weighted sampling on the same random \
             numbers; *U/U₀ (ref.)* — against the reference U₀; *U_eff/U₀* — the same for the estimator as used \
             (stratified over pieces); *1 + K* — the bound; *capped allowance* — the part of the bound's allowance \
             spent on pieces capped by the piece limit; *max w/σ⊥ − 1* — the largest excess of a piece's sampling \
             weight over its projected solid angle; *z* — the estimator's bias in standard errors (|z| < 2 expected).\n",
            self.samples, self.replicates, self.allocation, self.seed
        );
        let _ = writeln!(
            s,
            "| case | f | σ | σ⊥ | I | U₀ | reference | U₀ (cos-sampling)/U₀ |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
        for (name, f, r) in &self.references {
            let _ = writeln!(
                s,
                "| {} | {} | {:.4e} | {:.4e} | {:.6e} ± {:.1e} | {:.6e} ± {:.1e} | {} | {:.5} ± {:.5} |",
                name,
                f.as_str(),
                r.solid_angle,
                r.projected_solid_angle,
                r.value,
                r.value_se,
                r.u0,
                r.u0_se,
                r.method,
                r.u0_cosine / r.u0,
                r.u0_cosine_se / r.u0
            );
        }
        let _ = writeln!(
            s,
            "\n| case | f | K | pieces | leaves/est. | mean depth | U/U₀ − 1 (paired) | U/U₀ (ref.) | U_eff/U₀ | 1 + K | capped allowance | max w/σ⊥ − 1 | z |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &self.rows {
            let k = if r.k_threshold.is_infinite() {
                "∞".to_string()
            } else {
                format!("{}", r.k_threshold)
            };
            let allowance = if r.capped_samples > 0 {
                format!("{:.1e} ({} samples)", r.capped_allowance, r.capped_samples)
            } else {
                "0".to_string()
            };
            let pieces = match &r.partition {
                Some(p) if p.capped > 0 => format!("{} ({} capped)", p.pieces, p.capped),
                Some(p) => p.pieces.to_string(),
                None => "> limit".to_string(),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1} | {:.2} | {:+.2e} ± {:.1e} | {:.5} ± {:.5} | {:.4} ± {:.4} | {:.3} | {} | {:.2e} | {:+.2} |",
                r.case,
                r.integrand.as_str(),
                k,
                pieces,
                r.leaves_per_estimate,
                r.mean_depth,
                r.u_ratio - 1.0,
                r.u_ratio_se,
                r.u_over_u0_ref,
                r.u_over_u0_ref_se,
                r.u_eff_ratio,
                r.u_eff_ratio_se,
                1.0 + r.k_threshold,
                allowance,
                r.max_weight_excess,
                r.z
            );
        }
        let finite: Vec<&StudyRow> = self
            .rows
            .iter()
            .filter(|r| r.k_threshold.is_finite())
            .collect();
        let within = finite
            .iter()
            .filter(|r| r.u_over_u0_ref <= 1.0 + r.k_threshold + 2.0 * r.u_over_u0_ref_se)
            .count();
        let unbiased = self.rows.iter().filter(|r| r.z.abs() < 3.0).count();
        let _ = writeln!(
            s,
            "\n**Conclusion.** U/U₀ (ref.) ≤ 1 + K within two standard errors in {within} of {} rows with finite K \
             (the bound of §3.2); the estimator's mean is within 3 standard errors of the reference in {unbiased} of {} rows.",
            finite.len(),
            self.rows.len()
        );
        s
    }
}

/// The study's triangles, receiver at the origin with normal `+z` (the
/// corners are given as points; their directions are what matters):
///
/// | name | corners | |
/// |---|---|---|
/// | small | about 0.003 sr at 37° from the normal | |
/// | large | about 1.1 sr, from 20° to 70° | |
/// | near-horizon | just above the horizon (z/|p| from 0.03 to 0.33) | |
/// | crossing | crosses the horizon (clipped to a quadrilateral) | |
/// | pole | around the normal | |
///
/// each with [`StudyIntegrand::Constant`], [`Pattern`](StudyIntegrand::Pattern),
/// [`Smooth`](StudyIntegrand::Smooth) and
/// [`PatternOccluded`](StudyIntegrand::PatternOccluded); then the scene of
/// Ureña (2000, §5) ([`setup::patterned_triangle`](crate::scene::setup::patterned_triangle)
/// with 6 × 6 cells, radiances 1 and 0.1, and its occluders) seen from
/// the receiver at `(0.3, 0.5, 0)`.
///
/// # Errors
/// Only if the built-in geometry were invalid.
pub fn standard_cases() -> Result<Vec<StudyCase>, WarpError> {
    let o = crate::scene::Receiver::new(Vec3::zero(), Vec3::new(0.0, 0.0, 1.0))?;
    let v = Vec3::new;
    let triangles: [(&str, [Vec3<f64>; 3]); 5] = [
        (
            "small",
            [
                v(0.59, 0.2, 0.81),
                v(0.53, 0.235, 0.81),
                v(0.53, 0.165, 0.82),
            ],
        ),
        (
            "large",
            [v(1.5, -1.2, 0.4), v(1.2, 1.4, 0.6), v(0.15, 0.0, 1.0)],
        ),
        (
            "near-horizon",
            [v(1.0, -0.4, 0.03), v(1.0, 0.4, 0.05), v(1.0, 0.0, 0.35)],
        ),
        (
            "crossing",
            [v(1.0, -0.6, -0.3), v(0.8, 0.7, 0.2), v(0.3, 0.0, 0.9)],
        ),
        (
            "pole",
            [v(0.6, 0.0, 1.0), v(-0.3, 0.5, 1.0), v(-0.3, -0.55, 1.05)],
        ),
    ];
    let mut cases = Vec::new();
    for (name, pts) in triangles {
        for f in [
            StudyIntegrand::Constant,
            StudyIntegrand::Pattern,
            StudyIntegrand::Smooth,
            StudyIntegrand::PatternOccluded,
        ] {
            cases.push(StudyCase::new(name, pts, o.clone(), f)?);
        }
    }
    let setup = crate::scene::setup::patterned_triangle(6, 1.0, 0.1, 1)?;
    let rx = Receiver::new(Vec3::new(0.3, 0.5, 0.0), Vec3::new(0.0, 0.0, 1.0))?;
    cases.push(StudyCase::from_scene("Ureña §5 scene", &setup.scene, rx)?);
    Ok(cases)
}

/// One row of [`allocation_bias`].
#[derive(Clone, Debug, PartialEq)]
pub struct AllocationBiasRow {
    /// The case's name.
    pub case: String,
    /// Its integrand.
    pub integrand: StudyIntegrand,
    /// K.
    pub k_threshold: f64,
    /// Samples per estimate.
    pub samples: usize,
    /// The allocation rule.
    pub allocation: Allocation,
    /// The reference `I` and its standard error.
    pub reference: f64,
    /// The reference's standard error.
    pub reference_se: f64,
    /// Mean of the estimates.
    pub mean: f64,
    /// Its standard error.
    pub mean_se: f64,
    /// `(mean − I)/I`.
    pub relative_bias: f64,
    /// `(mean − I)/√(se² + se_ref²)`.
    pub z: f64,
}

/// The bias of the three [`Allocation`] rules, measured: for each case,
/// each `n` in `samples` and each rule, the mean of `replicates`
/// independent `n`-sample estimates at threshold `k_threshold` against the
/// case's reference (with `reference_samples` cosine-weighted samples where
/// no exact value exists). The paper's [`Allocation::Successive`] is
/// biased for `n` small enough that two or more residual samples are
/// common and `f` is not constant.
///
/// # Errors
/// As [`study`].
pub fn allocation_bias(
    cases: &[StudyCase],
    k_threshold: f64,
    samples: &[usize],
    replicates: usize,
    reference_samples: usize,
    seed: u64,
) -> Result<Vec<AllocationBiasRow>, WarpError> {
    let mut rows = Vec::new();
    let mut index = 0u64;
    for (ci, case) in cases.iter().enumerate() {
        let reference = case.reference(reference_samples, job_seed(seed, 1_000_000 + ci as u64))?;
        let base = case.sampler(k_threshold)?;
        for &n in samples {
            for allocation in [
                Allocation::Successive,
                Allocation::Systematic,
                Allocation::Multinomial,
            ] {
                let t = base.clone().with_allocation(allocation);
                let est: Stats = run_jobs(replicates, job_seed(seed, index), |_, rng| {
                    t.generate(n, rng).estimate(|d| case.f(d))
                })
                .into_iter()
                .collect();
                index += 1;
                let i = reference.value;
                let se = (est.variance() / est.count() as f64
                    + reference.value_se * reference.value_se)
                    .sqrt();
                rows.push(AllocationBiasRow {
                    case: case.name.clone(),
                    integrand: case.integrand,
                    k_threshold,
                    samples: n,
                    allocation,
                    reference: i,
                    reference_se: reference.value_se,
                    mean: est.mean(),
                    mean_se: est.std_error(),
                    relative_bias: (est.mean() - i) / i,
                    z: (est.mean() - i) / se,
                });
            }
        }
    }
    Ok(rows)
}

/// The rows of [`allocation_bias`] as a Markdown table.
pub fn allocation_bias_markdown(rows: &[AllocationBiasRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| case | f | K | n | allocation | relative bias | ± (1 se) | z | p (two-sided) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:+.2e} | {:.1e} | {:+.2} | {:.2e} |",
            r.case,
            r.integrand.as_str(),
            r.k_threshold,
            r.samples,
            r.allocation,
            r.relative_bias,
            (r.mean_se * r.mean_se + r.reference_se * r.reference_se).sqrt() / r.reference,
            r.z,
            crate::verdict::normal_two_sided_p(r.z)
        );
    }
    s
}
