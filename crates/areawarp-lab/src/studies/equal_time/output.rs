//! The equal-time tables and figures.

use super::{EqualTime, EqualTimeTable};
use crate::figures::{self, Axis, Figure, PALETTE, Plot, Series};
use crate::verdict::{Z95, sig3};
use std::fmt::Write as _;
use std::io;
use std::path::Path;

impl EqualTimeTable {
    /// The file name of its figure.
    pub fn figure_name(&self) -> String {
        if self.scene == "no occluders" {
            "equal_time.svg".to_string()
        } else {
            "equal_time_occluded.svg".to_string()
        }
    }

    fn to_markdown(&self) -> String {
        let mut s = String::new();
        let spp = self.rows.first().map_or(0, |r| r.spp);
        let rounds = self.rows.first().map_or(0, |r| r.cost.per_sample.runs);
        let _ = writeln!(
            s,
            "#### Equal time, {}\n\n{} receivers, {} points; {} timed rounds. Columns: \
             *CPU ns/sample* — thread CPU time per light sample of the method's whole estimator, minimum over rounds \
             [median; interquartile range over rounds]; *build ns* — construction of its strategies per receiver (minimum); \
             *RMS at {spp} spp* — per-receiver relative RMS error ± 95% (jackknife over runs); \
             *µs/receiver* — build + {spp} × ns/sample; *time ratio* — µs/receiver over `{}`'s, median of the per-round ratios \
             [range over rounds]; *efficiency* — 1/(RMS² × µs/receiver) relative to `{}`, ± 95% from both RMS values and the \
             time ratio's spread. Higher is better: efficiency 2 means the same error in half the time.\n",
            self.scene,
            self.receivers,
            self.point_set.name(),
            rounds,
            self.baseline,
            self.baseline,
        );
        let _ = writeln!(
            s,
            "| method | CPU ns/sample [median; IQR] | build ns | RMS at {spp} spp | µs/receiver | time ratio [range] | efficiency ({} = 1) |\n\
             |---|---:|---:|---:|---:|---:|---:|",
            self.baseline
        );
        for r in &self.rows {
            let t = &r.cost.per_sample;
            let efficiency = if r.efficiency.is_infinite() {
                "∞ (zero variance: exact here)".to_string()
            } else if r.efficiency_se == 0.0 {
                sig3(r.efficiency)
            } else {
                format!("{} ± {}", sig3(r.efficiency), sig3(Z95 * r.efficiency_se))
            };
            let (lo, hi) = r
                .cost
                .rounds
                .iter()
                .zip(&self.rows[0].cost.rounds)
                .map(|(a, b)| (a.1 + r.spp as f64 * a.0) / (b.1 + r.spp as f64 * b.0))
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                });
            let rms = if r.rms > 1e-12 {
                format!("{:.3e} ± {:.0}%", r.rms, 100.0 * Z95 * r.rms_se / r.rms)
            } else {
                format!("{:.1e} (exact)", r.rms)
            };
            let _ = writeln!(
                s,
                "| {} | {:.1} [{:.1}; {:.1}–{:.1}] | {:.0} | {rms} | {:.1} | {:.2} [{:.2}–{:.2}] | {efficiency} |",
                r.method,
                t.min,
                t.median,
                t.q1,
                t.q3,
                r.cost.construction.min,
                r.micros,
                r.time_ratio,
                lo,
                hi,
            );
        }
        let _ = writeln!(
            s,
            "\n![Relative RMS error against CPU µs per receiver, {}, one curve per method with its 95% band]({})\n",
            self.scene,
            self.figure_name()
        );
        s
    }

    fn write_figure(&self, dir: &Path) -> io::Result<Figure> {
        let mut plot = Plot::new(
            &format!(
                "equal time, {}: relative RMS error against CPU time per receiver ({})",
                self.scene,
                self.point_set.name()
            ),
            Axis::log("CPU µs per receiver (build + spp × ns per sample, whole estimator)"),
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
        figures::write_line_plot_svg(&dir.join(self.figure_name()), &plot)
    }
}

impl EqualTime {
    /// The section: how the costs are measured, the tables, figures and
    /// the cubic-only bias test.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "### Equal time: error against the CPU time spent per receiver\n\n\
             The cost of each method is measured here on the estimator the variance study runs, at the same receivers: \
             per light sample the draw, the pdf, the irradiance integrand (ray–light test, radiance, cosine) with the scene's \
             visibility tests and, for MIS, the cosine sample and every pdf the balance weights need; the strategies' construction \
             is charged once per receiver; generating the points is not timed. \
             The clock is the thread's {}: waiting for a core another process holds is not counted. The methods are interleaved \
             within each round (rotating which goes first) after an untimed warm-up round, and the cost is the *minimum* over rounds — \
             load only adds time — with the median and quartiles beside it as the spread. \
             (The cost table \"What a sample costs\" times the samplers alone, without MIS weights: a different workload.)\n",
            if crate::timing::is_cpu_time() {
                "CPU time (`CLOCK_THREAD_CPUTIME_ID`)"
            } else {
                "wall time (no per-thread CPU clock on this platform)"
            }
        );
        s.push_str(&self.free.to_markdown());
        if let Some(o) = &self.occluded {
            s.push_str(&o.to_markdown());
        }
        if let Some(b) = &self.bias {
            s.push_str(&b.to_markdown());
        }
        s
    }

    /// Writes `equal_time.svg` and, with occluders, `equal_time_occluded.svg`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        let mut out = vec![self.free.write_figure(dir)?];
        if let Some(o) = &self.occluded {
            out.push(o.write_figure(dir)?);
        }
        Ok(out)
    }

    /// Writes `equal_time.csv`: one row per scene and method.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<std::path::PathBuf> {
        let mut t = String::from(
            "scene,method,spp,cpu_ns_per_sample_min,cpu_ns_per_sample_median,cpu_ns_per_sample_q1,cpu_ns_per_sample_q3,build_ns_min,rms,rms_std_error,us_per_receiver,time_ratio,time_ratio_log_std_error,efficiency,efficiency_std_error\n",
        );
        for tb in std::iter::once(&self.free).chain(self.occluded.as_ref()) {
            for r in &tb.rows {
                let c = &r.cost.per_sample;
                let _ = writeln!(
                    t,
                    "{},\"{}\",{},{},{},{},{},{},{:e},{:e},{},{},{},{},{}",
                    tb.scene,
                    r.method,
                    r.spp,
                    c.min,
                    c.median,
                    c.q1,
                    c.q3,
                    r.cost.construction.min,
                    r.rms,
                    r.rms_se,
                    r.micros,
                    r.time_ratio,
                    r.time_ratio_log_se,
                    r.efficiency,
                    r.efficiency_se
                );
            }
        }
        let path = dir.join("equal_time.csv");
        std::fs::write(&path, t)?;
        Ok(path)
    }
}
