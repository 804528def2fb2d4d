//! The adaptive comparison at equal time: the CPU time of one whole
//! estimate of each method (cold: the per-receiver work included), its
//! efficiency `1/(RMS² · time)` relative to stratified solid-angle sampling,
//! the break-even cost of an evaluation of the integrand, and Ureña's
//! (2000, §5, last paragraph) claims about cost.
//!
//! The timing is [`time_estimates`] (thread CPU time, estimators
//! interleaved in rounds, minimum over rounds, spread reported), as the
//! equal-time study of the variance study's methods times its estimators;
//! unlike that study (build + n × per-sample cost) it times the estimate at
//! every measured sample count, since adaptive sampling's cost is not
//! linear in `n`: its partition is refined where the samples go.

use super::*;
use crate::figures::{self, Axis, Figure, PALETTE, Plot, Series};
use crate::studies::equal_time::relative_efficiency;
use crate::studies::equal_time::timing::{EstimateCost, time_estimates};
use crate::verdict::{Z95, interval, sig3};
use std::io;
use std::path::Path;

/// The size of the timing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CostConfig {
    /// Timed rounds (after one untimed warm-up round).
    pub rounds: usize,
    /// Seed of the timed estimates' points.
    pub seed: u64,
}

impl CostConfig {
    /// The tests' size: 3 rounds.
    pub fn quick() -> Self {
        CostConfig {
            rounds: 3,
            seed: 0xC057_2000,
        }
    }
}

impl Default for CostConfig {
    /// The report's size: 9 rounds.
    fn default() -> Self {
        CostConfig {
            rounds: 9,
            ..Self::quick()
        }
    }
}

/// The measured cost of every method of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveCost {
    /// Its size.
    pub config: CostConfig,
    /// Receivers timed (all the comparison's).
    pub receivers: usize,
    /// Per method, in the measurement's order.
    pub costs: Vec<EstimateCost>,
}

/// Times the comparison's estimators at every receiver and sample count.
pub(crate) fn measure_cost(
    setup: &Setup,
    estimators: &[&dyn ReceiverEstimator],
    uses_points: &[bool],
    spp: &[usize],
    config: &CostConfig,
) -> AdaptiveCost {
    let costs = time_estimates(
        &setup.scene,
        &setup.receivers,
        estimators,
        uses_points,
        spp,
        config.rounds,
        config.seed,
    );
    AdaptiveCost {
        config: *config,
        receivers: setup.receivers.len(),
        costs,
    }
}

/// One method at one sample count, at equal time against the baseline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EqualTimeCell {
    /// CPU µs per estimate (minimum over rounds).
    pub micros: f64,
    /// Time per estimate over the baseline's (median of per-round ratios).
    pub time_ratio: f64,
    /// Standard error of the log of the time ratio.
    pub time_ratio_log_se: f64,
    /// Relative RMS error and its jackknife standard error.
    pub rms: (f64, f64),
    /// Efficiency relative to the baseline and its standard error.
    pub efficiency: (f64, f64),
}

/// The baseline of the efficiencies.
pub const COST_BASELINE: &str = STRATIFIED_SOLID_ANGLE;

impl AdaptiveComparison {
    /// Method `m` at level `l` against [`COST_BASELINE`] (`None` without a
    /// timing or a baseline).
    pub fn equal_time_cell(&self, m: usize, l: usize) -> Option<EqualTimeCell> {
        let cost = self.cost.as_ref()?;
        let ms = &self.measurement;
        let b = self.index(COST_BASELINE)?;
        let (cm, cb) = (cost.costs.get(m)?, cost.costs.get(b)?);
        let rms = (
            ms.rms(Subset::All, m, 0, l),
            ms.rms_std_error(Subset::All, m, 0, l),
        );
        let base = (
            ms.rms(Subset::All, b, 0, l),
            ms.rms_std_error(Subset::All, b, 0, l),
        );
        let (time_ratio, log_se) = cm.ratio_to(cb, l);
        let efficiency = if m == b {
            (1.0, 0.0)
        } else {
            relative_efficiency(
                (base.0, base.1, cb.micros(l)),
                (rms.0, rms.1, cm.micros(l)),
                log_se,
            )
        };
        Some(EqualTimeCell {
            micros: cm.micros(l),
            time_ratio,
            time_ratio_log_se: if m == b { 0.0 } else { log_se },
            rms,
            efficiency,
        })
    }

    /// The extra CPU time per evaluation of the integrand (ns) above which
    /// adaptive sampling with threshold `k` becomes as efficient as the
    /// baseline at level `l`: with variance ratio `v = (RMS_a/RMS_s)²` and
    /// times `T_a`, `T_s` per estimate of `n` samples, adding `c` per
    /// sample to both gives equal efficiency when
    /// `v (T_a + n c) = T_s + n c`, i.e. `c* = (v T_a − T_s) / (n (1 − v))`.
    /// Returns `(c*, lo, hi)` with `[lo, hi]` from the 95% interval of the
    /// error ratio (jackknife; `hi = ∞` when that interval reaches 1, `c* =
    /// ∞` when adaptive sampling is not less noisy; `0` when it is already
    /// more efficient).
    pub fn break_even_ns(&self, k: f64, l: usize) -> Option<(f64, f64, f64)> {
        let cost = self.cost.as_ref()?;
        let (a, s) = (self.adaptive_index(k)?, self.index(COST_BASELINE)?);
        let ms = &self.measurement;
        let n = *ms.spp.get(l)? as f64;
        let (ta, ts) = (
            cost.costs.get(a)?.micros(l) * 1e3,
            cost.costs.get(s)?.micros(l) * 1e3,
        );
        let (r, se) = ms.error_ratio(Subset::All, a, s, 0, l);
        let c = |r: f64| {
            let v = r.max(0.0).powi(2);
            if v >= 1.0 {
                f64::INFINITY
            } else {
                ((v * ta - ts) / (n * (1.0 - v))).max(0.0)
            }
        };
        let (lo, hi) = interval(r, se);
        Some((c(r), c(lo), c(hi)))
    }

    /// The equal-time table and the break-even costs (Markdown, level-4
    /// heading), `None` without a timing.
    pub(crate) fn cost_markdown(&self) -> Option<String> {
        let cost = self.cost.as_ref()?;
        let ms = &self.measurement;
        let (pl, last) = (self.paper_level(), ms.spp.len().checked_sub(1)?);
        let (np, nl) = (ms.spp[pl], ms.spp[last]);
        let mut s = String::new();
        let _ = writeln!(
            s,
            "#### Equal time: cost per estimate and efficiency\n\n\
             The CPU time of one whole estimate at a receiver, measured *cold* as a renderer pays it for one pixel: the method \
             prepared at the receiver (for adaptive sampling, the root triangle; its partition is then built and memoized where \
             the samples go, within the timed estimate), the n sample directions drawn (jittered points generated for the \
             stratified methods; the adaptive allocation and its random points, and the independent points of `{RANDOM_COSINE}`, \
             inside their estimates), their pdfs, and the integrand (ray–light test, pattern radiance, cosine{}). \
             Thread CPU time (`CLOCK_THREAD_CPUTIME_ID`), the methods interleaved at each sample count within a round after an \
             untimed warm-up round, {} timed rounds over all {} receivers; the time is the *minimum* over rounds (load only \
             adds time). Columns: *CPU µs/estimate* — minimum [median; interquartile range over rounds]; *time ratio* — over \
             `{COST_BASELINE}`, median of the per-round ratios ± 95% (from the spread of their logs); *RMS* — per-receiver \
             relative RMS error ± 95% (jackknife over runs); *efficiency* — 1/(RMS² × µs/estimate) relative to \
             `{COST_BASELINE}` ± 95% (both RMS values and the time ratio, in quadrature, as in the equal-time study). Higher is \
             better: efficiency 2 means the same error in half the time.\n",
            if self.config.occluders {
                ", and the visibility tests against the 6 occluding squares"
            } else {
                ""
            },
            cost.config.rounds,
            cost.receivers,
        );
        let _ = writeln!(
            s,
            "| method | CPU µs/estimate at {np} spp [median; IQR] | time ratio at {np} spp | RMS at {np} spp | efficiency at {np} spp | CPU µs/estimate at {nl} spp | efficiency at {nl} spp |\n\
             |---|---:|---:|---:|---:|---:|---:|"
        );
        for (m, c) in cost.costs.iter().enumerate() {
            let (Some(p), Some(q)) = (self.equal_time_cell(m, pl), self.equal_time_cell(m, last))
            else {
                continue;
            };
            let t = &c.per_estimate[pl];
            let ratio = if p.time_ratio_log_se > 0.0 {
                let h = Z95 * p.time_ratio_log_se;
                format!(
                    "{} [{}, {}]",
                    sig3(p.time_ratio),
                    sig3(p.time_ratio * (-h).exp()),
                    sig3(p.time_ratio * h.exp())
                )
            } else {
                sig3(p.time_ratio)
            };
            let eff = |e: (f64, f64)| {
                if e.1 > 0.0 {
                    format!("{} ± {}", sig3(e.0), sig3(Z95 * e.1))
                } else {
                    sig3(e.0)
                }
            };
            let _ = writeln!(
                s,
                "| {} | {} [{}; {}–{}] | {ratio} | {} ± {:.0}% | {} | {} | {} |",
                c.method,
                sig3(p.micros),
                sig3(t.median * 1e-3),
                sig3(t.q1 * 1e-3),
                sig3(t.q3 * 1e-3),
                sci(p.rms.0),
                100.0 * Z95 * p.rms.1 / p.rms.0,
                eff(p.efficiency),
                sig3(q.micros),
                eff(q.efficiency),
            );
        }
        let parts: Vec<String> = self
            .config
            .thresholds
            .iter()
            .filter(|k| k.is_finite())
            .filter_map(|&k| {
                let (c, lo, hi) = self.break_even_ns(k, pl)?;
                let text = |x: f64| {
                    if x.is_finite() {
                        format!("{x:.0} ns")
                    } else {
                        "∞".to_string()
                    }
                };
                Some(format!(
                    "K = {}: {} (95% interval {} – {})",
                    k_label(k),
                    text(c),
                    text(lo),
                    text(hi)
                ))
            })
            .collect();
        let base_per_sample = cost.costs[self.index(COST_BASELINE)?].micros(pl) * 1e3 / np as f64;
        let _ = writeln!(
            s,
            "\n**When is adaptive sampling worth its cost?** Ureña (2000, §5) notes that adaptive sampling takes longer than \
             stratified sampling and is worth it when evaluating the integrand (visibility in a complex scene) dominates. \
             Adding a cost c to every evaluation of the integrand of both methods, adaptive sampling matches `{COST_BASELINE}`'s \
             efficiency at {np} spp once c exceeds c* = (v T_a − T_s)/(n (1 − v)), v the variance ratio at equal n, T the times per \
             estimate above (interval from the error ratio's; ∞: not less noisy at equal n): {}. For scale, `{COST_BASELINE}` \
             spends {base_per_sample:.0} ns per sample here, integrand included.\n",
            if parts.is_empty() {
                "no finite threshold measured".to_string()
            } else {
                parts.join("; ")
            }
        );
        let _ = writeln!(
            s,
            "![Relative RMS error against CPU µs per estimate on log–log axes, one curve per method through the measured sample counts, with 95% bands]({})\n",
            self.cost_figure_name()
        );
        Some(s)
    }

    /// `equal_time_adaptive.svg` or `equal_time_adaptive_occluded.svg`.
    pub fn cost_figure_name(&self) -> &'static str {
        if self.config.occluders {
            "equal_time_adaptive_occluded.svg"
        } else {
            "equal_time_adaptive.svg"
        }
    }

    /// Writes the equal-time figure (error against CPU µs per estimate,
    /// one curve per method with its 95% band); `None` without a timing.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_cost_figure(&self, dir: &Path) -> io::Result<Option<Figure>> {
        let Some(cost) = &self.cost else {
            return Ok(None);
        };
        let ms = &self.measurement;
        let mut plot = Plot::new(
            &format!(
                "Ureña 2000 comparison at equal time ({}): relative RMS error against CPU time per estimate",
                if self.config.occluders {
                    "occluders kept"
                } else {
                    "occluders removed"
                }
            ),
            Axis::log("CPU µs per estimate (cold: per-receiver work included)"),
            Axis::log("per-receiver relative RMS error (band: 95% interval)"),
        )
        .size(900, 580);
        for (m, c) in cost.costs.iter().enumerate() {
            let mut pts = Vec::new();
            let mut band = Vec::new();
            for l in 0..ms.spp.len().min(c.per_estimate.len()) {
                let (e, se) = (
                    ms.rms(Subset::All, m, 0, l),
                    ms.rms_std_error(Subset::All, m, 0, l),
                );
                let (lo, hi) = interval(e, se);
                pts.push((c.micros(l), e));
                band.push((c.micros(l), lo, hi));
            }
            let mut series = Series::new(&c.method, pts)
                .with_color(PALETTE[m % PALETTE.len()])
                .with_band(band);
            series.dashed = c.method.starts_with("adaptive");
            plot = plot.series(series);
        }
        figures::write_line_plot_svg(&dir.join(self.cost_figure_name()), &plot).map(Some)
    }

    /// Ureña's claims about cost (§5, last paragraph), judged on the
    /// timing: empty without one.
    pub(crate) fn cost_claims(&self) -> Vec<Claim> {
        let mut out = Vec::new();
        let (Some(cost), Some(s), Some(a)) = (
            &self.cost,
            self.index(COST_BASELINE),
            self.adaptive_index(0.001),
        ) else {
            return out;
        };
        let ms = &self.measurement;
        let pl = self.paper_level();
        let np = ms.spp[pl];
        let source = self.source("Ureña 2000, §5 (last paragraph)");
        // "The adaptive sampling algorithm usually takes longer than
        // stratified sampling": the time ratio's whole interval above 1.
        {
            let (r, lse) = cost.costs[a].ratio_to(&cost.costs[s], pl);
            let h = Z95 * lse;
            let others: Vec<String> = (0..ms.spp.len())
                .map(|l| {
                    let (r, _) = cost.costs[a].ratio_to(&cost.costs[s], l);
                    format!("{} spp {}", ms.spp[l], sig3(r))
                })
                .collect();
            out.push(Claim {
                source: source.clone(),
                statement: "adaptive sampling takes longer than stratified sampling at the same number of samples (the triangles must be split)".to_string(),
                measured: format!(
                    "CPU time per estimate (cold, per-receiver work included), adaptive K=0.001 / stratified solid angle at {np} spp: {} (95% interval [{}, {}], {} rounds); at every spp: {}",
                    sig3(r),
                    sig3(r * (-h).exp()),
                    sig3(r * h.exp()),
                    cost.config.rounds,
                    others.join(", ")
                ),
                verdict: crate::verdict::judge_exceeds(r.ln(), lse, 0.0, 0.0),
            });
        }
        // "In the case that evaluation of f is fast enough, stratified
        // sampling with an increased number of samples may be preferable":
        // our integrand is cheap; the efficiency of adaptive sampling
        // relative to stratified below 1.
        if let Some(c) = self.equal_time_cell(a, pl) {
            let (e, se) = c.efficiency;
            let (lo, hi) = interval(e, se);
            let last = ms.spp.len() - 1;
            let at_last = self
                .equal_time_cell(a, last)
                .map(|c| {
                    format!(
                        "; at {} spp {} [{}, {}]",
                        ms.spp[last],
                        sig3(c.efficiency.0),
                        sig3(interval(c.efficiency.0, c.efficiency.1).0),
                        sig3(interval(c.efficiency.0, c.efficiency.1).1)
                    )
                })
                .unwrap_or_default();
            let be = self
                .break_even_ns(0.001, pl)
                .map(|(c, _, _)| {
                    if c.is_finite() {
                        format!("; break-even extra cost per evaluation of f: {c:.0} ns")
                    } else {
                        "; no extra cost of f makes it break even (not less noisy at equal n)"
                            .to_string()
                    }
                })
                .unwrap_or_default();
            out.push(Claim {
                source,
                statement: "when the integrand is fast to evaluate, stratified sampling with more samples may be preferable to adaptive sampling (at equal time)".to_string(),
                measured: format!(
                    "cheap integrand (one ray–triangle test and the pattern{}): efficiency 1/(RMS² · time) of adaptive K=0.001 relative to stratified solid angle at {np} spp, {}: {} (95% interval [{}, {}]; below 1: stratified preferable){at_last}{be}",
                    if self.config.occluders { ", 6 occluder tests" } else { "" },
                    ms.metric.name(),
                    sig3(e),
                    sig3(lo),
                    sig3(hi)
                ),
                // No number claimed: reproduced when the whole interval is
                // below 1, direction holds when the point is.
                verdict: if hi < 1.0 {
                    Verdict::Reproduced
                } else if e < 1.0 {
                    Verdict::Qualitative
                } else {
                    Verdict::NotReproduced
                },
            });
        }
        out
    }
}
