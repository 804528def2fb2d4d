//! Equal-time comparison of the light samplers of the variance study: the
//! error of each method against the CPU time it spends per receiver, and
//! its efficiency `1/(MSE · time)`, without and with occluders; and the
//! bias of cubic-only inversion of the projected polygon ([`inversion`]).
//!
//! The cost of a method is measured here, on the estimator the variance
//! study runs ([`timing`]: thread CPU time, methods interleaved in rounds,
//! minimum over rounds, the spread reported): per light sample the draw,
//! pdf, integrand and visibility tests and, for MIS, the cosine sample and
//! the balance weights' pdfs; plus the construction of the strategies once
//! per receiver. The light-cost table ("What a sample costs") times the
//! samplers in isolation (the map alone, and one estimator step without
//! MIS weights); its numbers answer a different question and are not used
//! here.

pub mod inversion;
mod output;
#[cfg(test)]
mod tests;
pub mod timing;

use self::inversion::{BiasConfig, InversionBias};
use self::timing::{MethodCost, time_methods};
use super::variance::{VarianceStudy, occluded_irradiance};
use crate::estimator::{Measurement, Method, PointSet, Sampler, Subset};
use crate::scene::{Receiver, Scene, setup};
use crate::verdict::interval;
use areawarp::error::WarpError;
use areawarp::estimate::Heuristic;

/// The size of the timing and of the bias test.
#[derive(Clone, Debug, PartialEq)]
pub struct EqualTimeConfig {
    /// Light samples per receiver in each timed batch.
    pub batch: usize,
    /// Timed rounds (after one warm-up round).
    pub rounds: usize,
    /// Seed of the timed points.
    pub seed: u64,
    /// The cubic-only bias test; `None` skips it.
    pub bias: Option<BiasConfig>,
}

impl EqualTimeConfig {
    /// The tests' size (milliseconds).
    pub fn quick() -> Self {
        EqualTimeConfig {
            batch: 64,
            rounds: 5,
            seed: 0xE0_7135,
            bias: Some(BiasConfig::quick()),
        }
    }
}

impl Default for EqualTimeConfig {
    /// The report's size: 256 samples per receiver, 15 rounds.
    fn default() -> Self {
        EqualTimeConfig {
            batch: 256,
            rounds: 15,
            bias: Some(BiasConfig::default()),
            ..Self::quick()
        }
    }
}

/// One method's row.
#[derive(Clone, Debug, PartialEq)]
pub struct EqualTimeRow {
    /// The method's name.
    pub method: String,
    /// Its measured cost.
    pub cost: MethodCost,
    /// The spp of the comparison.
    pub spp: usize,
    /// Relative RMS error at `spp` (per-receiver metric).
    pub rms: f64,
    /// Its jackknife standard error.
    pub rms_se: f64,
    /// CPU µs per receiver at `spp` (minima over rounds).
    pub micros: f64,
    /// Time per receiver over the baseline's, median of per-round ratios.
    pub time_ratio: f64,
    /// Standard error of the log of the time ratio (rounds).
    pub time_ratio_log_se: f64,
    /// Efficiency `1/(rms² · time)` relative to the baseline's.
    pub efficiency: f64,
    /// Its standard error: the two RMS values' (jackknife) and the time
    /// ratio's (rounds), added in quadrature.
    pub efficiency_se: f64,
    /// The error curve against µs per receiver: `(µs, rms, lo, hi)`.
    pub curve: Vec<(f64, f64, f64, f64)>,
}

/// One comparison (one scene).
#[derive(Clone, Debug, PartialEq)]
pub struct EqualTimeTable {
    /// What the scene is (`no occluders`, `3 occluders`).
    pub scene: String,
    /// The point set used.
    pub point_set: PointSet,
    /// Receivers timed.
    pub receivers: usize,
    /// The baseline of the ratios.
    pub baseline: String,
    /// The rows.
    pub rows: Vec<EqualTimeRow>,
}

/// The study's result.
#[derive(Clone, Debug, PartialEq)]
pub struct EqualTime {
    /// Its size.
    pub config: EqualTimeConfig,
    /// Without occluders (the variance study's main measurement).
    pub free: EqualTimeTable,
    /// With the occluded measurement's occluders, if it ran.
    pub occluded: Option<EqualTimeTable>,
    /// The bias of cubic-only inversion, if run.
    pub bias: Option<InversionBias>,
}

/// The methods compared: balance-heuristic MIS and the samplers alone.
fn compared(methods: &[Method]) -> Vec<Method> {
    let mut out: Vec<Method> = methods
        .iter()
        .filter(|m| !matches!(m.mis, Some(Heuristic::Power(_) | Heuristic::Maximum)))
        .copied()
        .collect();
    // The baseline (the spherical rectangle alone) first.
    let base = Method::plain(Sampler::Rectangle);
    if let Some(i) = out.iter().position(|m| *m == base) {
        let b = out.remove(i);
        out.insert(0, b);
    }
    out
}

/// The efficiency `1/(rms² · time)` of `row` relative to `base`, each
/// given as `(rms, its standard error, time)`, and its standard error: the
/// relative error of `1/rms²` (≈ 2·se/rms) of both, added in quadrature
/// although common random numbers correlate them (a conservative bound),
/// and `time_log_se`, the standard error of the log of the time ratio.
pub fn relative_efficiency(
    base: (f64, f64, f64),
    row: (f64, f64, f64),
    time_log_se: f64,
) -> (f64, f64) {
    let (rb, sb, tb) = base;
    let (r, s, t) = row;
    let e = (rb * rb * tb) / (r * r * t);
    let rel = (4.0 * (s / r).powi(2) + 4.0 * (sb / rb).powi(2) + time_log_se.powi(2)).sqrt();
    (e, e * rel)
}

fn table(
    scene_name: &str,
    ms: &Measurement,
    methods: &[Method],
    scene: &Scene,
    receivers: &[Receiver],
    config: &EqualTimeConfig,
) -> EqualTimeTable {
    let methods: Vec<Method> = compared(methods)
        .into_iter()
        .filter(|m| ms.method_index(&m.name()).is_some())
        .collect();
    let costs = time_methods(
        scene,
        receivers,
        &methods,
        config.batch,
        config.rounds,
        config.seed,
    );
    let p = ms.point_set_index(PointSet::Jittered).unwrap_or(0);
    let last = ms.spp.len().saturating_sub(1);
    let spp = ms.spp.get(last).copied().unwrap_or(1);
    let mut rows: Vec<EqualTimeRow> = Vec::new();
    for (m, cost) in methods.iter().zip(&costs) {
        let Some(i) = ms.method_index(&m.name()) else {
            continue;
        };
        let rms = ms.rms(Subset::All, i, p, last);
        let rms_se = ms.rms_std_error(Subset::All, i, p, last);
        let curve = (0..ms.spp.len())
            .map(|l| {
                let (e, se) = (
                    ms.rms(Subset::All, i, p, l),
                    ms.rms_std_error(Subset::All, i, p, l),
                );
                let (lo, hi) = interval(e, se);
                (cost.micros_per_receiver(ms.spp[l]), e, lo, hi)
            })
            .collect();
        let (time_ratio, time_ratio_log_se) = cost.ratio_to(&costs[0], spp);
        rows.push(EqualTimeRow {
            method: m.name(),
            cost: cost.clone(),
            spp,
            rms,
            rms_se,
            micros: cost.micros_per_receiver(spp),
            time_ratio,
            time_ratio_log_se,
            efficiency: f64::NAN,
            efficiency_se: f64::NAN,
            curve,
        });
    }
    if let Some(base) = rows.first().cloned() {
        for r in &mut rows {
            if !(r.rms > 1e-12) {
                // A zero-variance estimator: no finite efficiency.
                r.efficiency = f64::INFINITY;
                continue;
            }
            let (e, se) = relative_efficiency(
                (base.rms, base.rms_se, base.micros),
                (r.rms, r.rms_se, r.micros),
                r.time_ratio_log_se,
            );
            r.efficiency = e;
            r.efficiency_se = if r.method == base.method { 0.0 } else { se };
        }
    }
    EqualTimeTable {
        scene: scene_name.to_string(),
        point_set: ms.point_sets.get(p).copied().unwrap_or(PointSet::Jittered),
        receivers: receivers.len(),
        baseline: methods.first().map(|m| m.name()).unwrap_or_default(),
        rows,
    }
}

/// Builds the comparison from the variance study's measurements (jittered
/// points, all receivers), timing every method on the same scenes and
/// receivers, and runs the cubic-only bias test on the occluded scene.
///
/// # Errors
/// As [`setup::standing_rectangle`] and
/// [`OccluderRow::polygons`](super::variance::OccluderRow::polygons).
pub fn run(var: &VarianceStudy, config: &EqualTimeConfig) -> Result<EqualTime, WarpError> {
    let c = &var.config;
    let set = setup::standing_rectangle(
        c.width, c.height, c.radiance, c.near, c.far, c.rows, c.lateral,
    )?;
    let free = table(
        "no occluders",
        &var.measurement,
        &c.methods,
        &set.scene,
        &set.receivers,
        config,
    );
    let (mut occluded, mut bias) = (None, None);
    if let Some(o) = &var.occluded {
        let mut scene = set.scene.clone();
        for q in o.occluders.polygons()? {
            scene = scene.with_occluder(q);
        }
        // The occluded measurement's receivers: those with an exact
        // reference, in the same order.
        let receivers: Vec<Receiver> = set
            .receivers
            .iter()
            .filter(|r| {
                o.measurement
                    .receivers
                    .iter()
                    .any(|i| i.position == *r.position())
            })
            .cloned()
            .collect();
        let name = format!("{} occluders", o.occluders.centers.len());
        occluded = Some(table(
            &name,
            &o.measurement,
            &c.occluded_methods,
            &scene,
            &receivers,
            config,
        ));
        if let Some(bc) = &config.bias {
            // The receivers in partial shadow, with their exact values.
            let mut rx = Vec::new();
            let mut refs = Vec::new();
            for r in &receivers {
                let free_e = crate::scene::lambert::irradiance(set.scene.emitter(), r);
                if let Some(e) = occluded_irradiance(&scene, r)
                    && e > 0.0
                    && e < free_e * (1.0 - 1e-9)
                {
                    rx.push(r.clone());
                    refs.push(e);
                }
            }
            if !rx.is_empty() {
                bias = Some(inversion::run(&scene, &rx, &refs, bc)?);
            }
        }
    }
    Ok(EqualTime {
        config: config.clone(),
        free,
        occluded,
        bias,
    })
}
