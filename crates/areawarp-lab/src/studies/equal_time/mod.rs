//! Equal-time comparison of the light samplers of the variance study: the
//! error of each method against the time it spends per receiver, and its
//! efficiency `1/(MSE · time)`, with one cost per map for the whole report.
//!
//! The cost of a sample is the light-cost study's *estimator* workload
//! (`light_cost::WORKLOADS[1]`: draw the sample, evaluate the pdf and the
//! irradiance integrand, no occluders), measured in the same run as every
//! other timing of the report; an MIS method pays its light sample plus a
//! cosine sample (the two estimators' costs added — the MIS weights' extra
//! pdf evaluations are not counted, which flatters MIS slightly). The map
//! alone (`WORKLOADS[0]`) and the warps-at-a-glance timings measure less
//! work and are not comparable with this one.

use super::light_cost::LightCost;
use super::variance::VarianceStudy;
use crate::estimator::{Method, PointSet, Sampler, Subset};
use crate::figures::{self, Axis, Figure, PALETTE, Plot, Series};
use crate::verdict::{Z95, interval, sig3};
use areawarp::estimate::Heuristic;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// One method's row.
#[derive(Clone, Debug, PartialEq)]
pub struct EqualTimeRow {
    /// The method's name.
    pub method: String,
    /// ns per sample (estimator workload; MIS: light + cosine).
    pub ns: f64,
    /// The spp of the comparison.
    pub spp: usize,
    /// Relative RMS error at `spp` (per-receiver metric).
    pub rms: f64,
    /// Its jackknife standard error.
    pub rms_se: f64,
    /// Efficiency `1/(rms² · spp · ns)` relative to the spherical
    /// rectangle's.
    pub efficiency: f64,
    /// Its standard error (from the two RMS values' only; timings are
    /// medians of one run).
    pub efficiency_se: f64,
    /// The error curve against µs per receiver: `(µs, rms, lo, hi)`.
    pub curve: Vec<(f64, f64, f64, f64)>,
}

/// The comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct EqualTime {
    /// The point set used (jittered).
    pub point_set: PointSet,
    /// The rows, in the variance study's method order.
    pub rows: Vec<EqualTimeRow>,
}

/// The estimator cost (ns per sample) of a method, if measured.
fn cost(lc: &LightCost, m: &Method) -> Option<f64> {
    let light = lc.row(m.sampler)?.per_sample.get(1)?.median;
    match m.mis {
        None => Some(light),
        // MIS's second strategy is cosine sampling of the hemisphere.
        Some(_) => Some(light + lc.row(Sampler::Cosine)?.per_sample.get(1)?.median),
    }
}

/// Builds the comparison from the variance study (jittered points, all
/// receivers, balance-heuristic MIS) and the light-cost timings.
pub fn run(var: &VarianceStudy, lc: &LightCost) -> EqualTime {
    let ms = &var.measurement;
    let p = ms.point_set_index(PointSet::Jittered).unwrap_or(0);
    let last = ms.spp.len().saturating_sub(1);
    let mut rows = Vec::new();
    for m in &var.config.methods {
        if matches!(m.mis, Some(Heuristic::Power(_) | Heuristic::Maximum)) {
            continue;
        }
        let (Some(i), Some(ns)) = (ms.method_index(&m.name()), cost(lc, m)) else {
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
                (ms.spp[l] as f64 * ns * 1e-3, e, lo, hi)
            })
            .collect();
        rows.push(EqualTimeRow {
            method: m.name(),
            ns,
            spp: ms.spp[last],
            rms,
            rms_se,
            efficiency: 1.0 / (rms * rms * ms.spp[last] as f64 * ns),
            efficiency_se: 0.0,
            curve,
        });
    }
    let base = rows
        .iter()
        .find(|r| r.method == Method::plain(Sampler::Rectangle).name())
        .map(|r| (r.efficiency, r.rms, r.rms_se));
    if let Some((e0, r0, s0)) = base {
        for r in &mut rows {
            r.efficiency /= e0;
            if !(r.rms > 1e-12) {
                // A zero-variance estimator: no finite efficiency.
                r.efficiency = f64::INFINITY;
                r.efficiency_se = f64::NAN;
                continue;
            }
            // Relative error of 1/rms² ≈ 2·se/rms, both rows' added in
            // quadrature (the rows are correlated: a conservative bound).
            let rel = 2.0 * ((r.rms_se / r.rms).powi(2) + (s0 / r0).powi(2)).sqrt();
            r.efficiency_se = if r.method == Method::plain(Sampler::Rectangle).name() {
                0.0
            } else {
                r.efficiency * rel
            };
        }
    }
    EqualTime {
        point_set: ms.point_sets.get(p).copied().unwrap_or(PointSet::Jittered),
        rows,
    }
}

impl EqualTime {
    /// The table, its column definitions and the figure's link.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let spp = self.rows.first().map_or(0, |r| r.spp);
        let _ = writeln!(
            s,
            "### Equal time: error against the time spent per receiver\n\n\
             One cost per map for the whole report: ns per sample of the *estimator* workload of the cost table (\"What a sample costs\") \
             (draw, pdf, integrand; no occluders), measured in this run; MIS pays a light and a cosine sample. Columns: \
             *ns/sample* — that cost; *RMS at {spp} spp* — per-receiver relative RMS error, {} points, all receivers, \
             ± 95% interval; *µs/receiver* — spp × ns/sample; *efficiency* — 1/(RMS² × time) relative to the spherical \
             rectangle, ± 95% from the RMS values only (the timings are medians of one run; their quartiles are in the cost \
             table). Higher is better: efficiency 2 means the same error in half the time.\n",
            self.point_set.name()
        );
        let _ = writeln!(
            s,
            "| method | ns/sample | RMS at {spp} spp | µs/receiver | efficiency (rectangle = 1) |\n|---|---:|---:|---:|---:|"
        );
        for r in &self.rows {
            let efficiency = if r.efficiency.is_infinite() {
                "∞ (zero variance: exact for this light)".to_string()
            } else {
                format!("{} ± {}", sig3(r.efficiency), sig3(Z95 * r.efficiency_se))
            };
            let _ = writeln!(
                s,
                "| {} | {:.1} | {:.3e} ± {:.0}% | {:.1} | {efficiency} |",
                r.method,
                r.ns,
                r.rms,
                100.0 * Z95 * r.rms_se / r.rms,
                r.spp as f64 * r.ns * 1e-3,
            );
        }
        let _ = writeln!(s, "\n![equal time](equal_time.svg)\n");
        s
    }

    /// Writes `equal_time.svg`: RMS error against µs per receiver, one
    /// curve per method with its 95% band.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        let mut plot = Plot::new(
            "equal time: relative RMS error against time per receiver (jittered, all receivers)",
            Axis::log("µs per receiver (spp × ns per sample, estimator workload)"),
            Axis::log("per-receiver relative RMS error (band: 95% interval)"),
        )
        .size(900, 580);
        for (i, r) in self.rows.iter().enumerate() {
            let pts: Vec<(f64, f64)> = r.curve.iter().map(|c| (c.0, c.1)).collect();
            if pts.iter().all(|p| !(p.1 > 1e-12)) {
                continue;
            }
            let band = r.curve.iter().map(|c| (c.0, c.2, c.3)).collect();
            let mut series = Series::new(&r.method, pts)
                .with_color(PALETTE[i % PALETTE.len()])
                .with_band(band);
            series.dashed = r.method.contains("MIS");
            plot = plot.series(series);
        }
        Ok(vec![figures::write_line_plot_svg(
            &dir.join("equal_time.svg"),
            &plot,
        )?])
    }
}
