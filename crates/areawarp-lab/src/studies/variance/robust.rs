//! Area sampling's heavy-tailed error made readable: the mean-based RMS
//! curve beside a robust one (the median over runs of each run's error,
//! [`Measurement::rms_median_of_runs`]), each with its 95% band.

use super::*;
use crate::verdict::Z95;

/// The methods of the robust table: area sampling alone and with MIS, and
/// the spherical rectangle for contrast.
fn robust_methods() -> [Method; 3] {
    [
        Method::plain(Sampler::Area),
        Method::mis(Sampler::Area, Heuristic::Balance),
        Method::plain(Sampler::Rectangle),
    ]
}

impl VarianceStudy {
    /// The section "Area sampling's heavy tail": a table per subset (all
    /// receivers, near the light) of the mean-based RMS (± 95%, jackknife)
    /// and the median over runs [order-statistic 95% interval] at every
    /// level, for the jittered points, and its figure.
    pub fn robust_markdown(&self) -> String {
        let ms = &self.measurement;
        let Some(p) = self.primary_set() else {
            return String::new();
        };
        let (j, coverage) = order_statistic_interval(ms.runs);
        let mut s = String::new();
        let _ = writeln!(
            s,
            "### Area sampling's heavy tail: mean-based and median-of-runs error\n\n\
             Near the light, area sampling's f/p grows like 1/r², so a rare sample close to the light's edge dominates the mean \
             squared error: the mean-based RMS curve jumps with whichever run drew it (non-monotone, an equal-error ratio without \
             meaning). Beside it a robust estimator, the *median of means*: each of the {runs} independent runs gives one RMS over \
             all receivers of the subset, and the median over runs is reported with a distribution-free interval from order \
             statistics (from the {j}. smallest to the {j}. largest of the {runs} runs: coverage {cov:.1}% for the median{warn}). \
             The median estimates the *typical* run's error and is lower than the RMS when rare large errors dominate; read it for the \
             curve's shape and rate, the mean-based RMS for the expected squared error. {} points. Columns: *spp*; for each method \
             *RMS* — the mean-based per-receiver relative RMS ± the half-width of its 95% interval relative to it (jackknife over runs) \
             and *median of runs* — the robust value [its interval].\n",
            ms.point_sets[p].name(),
            runs = ms.runs,
            cov = 100.0 * coverage,
            warn = if coverage < 0.95 {
                ", below 95%: too few runs for a 95% interval"
            } else {
                ""
            },
        );
        let methods: Vec<(Method, usize)> = robust_methods()
            .into_iter()
            .filter_map(|m| Some((m, self.method(m)?)))
            .collect();
        for subset in [Subset::All, Subset::NearLight] {
            let count = ms
                .receivers
                .iter()
                .filter(|r| subset == Subset::All || r.near)
                .count();
            if count == 0 {
                continue;
            }
            let _ = writeln!(s, "\n**{} receivers ({count}).**\n", subset.name());
            let _ = write!(s, "| spp |");
            for (m, _) in &methods {
                let _ = write!(s, " {} RMS | {} median of runs |", m.name(), m.name());
            }
            let _ = write!(s, "\n|---:|");
            for _ in &methods {
                s.push_str("---:|---:|");
            }
            s.push('\n');
            for l in table_levels(ms) {
                let _ = write!(s, "| {} |", ms.spp[l]);
                for (_, i) in &methods {
                    let (e, se) = (ms.rms(subset, *i, p, l), ms.rms_std_error(subset, *i, p, l));
                    let (med, lo, hi, _) = ms.rms_median_of_runs(subset, *i, p, l);
                    let _ = write!(
                        s,
                        " {} ±{:.0}% | {} [{}, {}] |",
                        sci(e),
                        100.0 * Z95 * se / e,
                        sci(med),
                        sci(lo),
                        sci(hi)
                    );
                }
                s.push('\n');
            }
        }
        let _ = writeln!(
            s,
            "\n![Area sampling's relative RMS error against spp, mean-based with its jackknife band and median of runs with its order-statistic band, all receivers and near the light](variance_area_robust.svg)\n"
        );
        s
    }

    /// Writes `variance_area_robust.svg`: area sampling's mean-based RMS
    /// and median-of-runs curves, all receivers and near the light, each
    /// with its band.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_robust_figure(&self, dir: &Path) -> io::Result<Option<Figure>> {
        let ms = &self.measurement;
        let (Some(p), Some(i)) = (
            self.primary_set(),
            self.method(Method::plain(Sampler::Area)),
        ) else {
            return Ok(None);
        };
        let mut plot = Plot::new(
            "area sampling: mean-based RMS vs median of runs (jittered)",
            Axis::log("samples per receiver (spp)"),
            Axis::log("relative error (bands: 95% intervals)"),
        )
        .size(900, 580);
        for (k, subset) in [Subset::All, Subset::NearLight].into_iter().enumerate() {
            if subset == Subset::NearLight && !ms.receivers.iter().any(|r| r.near) {
                continue;
            }
            let levels = 0..ms.spp.len();
            let mean: Vec<(f64, f64, f64, f64)> = levels
                .clone()
                .map(|l| {
                    let (e, se) = (ms.rms(subset, i, p, l), ms.rms_std_error(subset, i, p, l));
                    let (lo, hi) = crate::verdict::interval(e, se);
                    (ms.spp[l] as f64, e, lo.max(e * 1e-3), hi)
                })
                .collect();
            let median: Vec<(f64, f64, f64, f64)> = levels
                .map(|l| {
                    let (m, lo, hi, _) = ms.rms_median_of_runs(subset, i, p, l);
                    (ms.spp[l] as f64, m, lo, hi)
                })
                .collect();
            for (name, curve, c, dashed) in [
                ("RMS (mean)", mean, PALETTE[2 * k], false),
                ("median of runs", median, PALETTE[2 * k + 1], true),
            ] {
                let mut series = Series::new(
                    &format!("{name}, {}", subset.name()),
                    curve.iter().map(|x| (x.0, x.1)).collect(),
                )
                .with_color(c)
                .with_band(curve.iter().map(|x| (x.0, x.2, x.3)).collect());
                series.dashed = dashed;
                plot = plot.series(series);
            }
        }
        Ok(Some(figures::write_line_plot_svg(
            &dir.join("variance_area_robust.svg"),
            &plot,
        )?))
    }
}
