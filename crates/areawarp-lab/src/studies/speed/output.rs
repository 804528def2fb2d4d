//! The study's Markdown, CSV files and figures.

use super::*;

impl SpeedStudy {
    /// The recommended default per warp (in [`WARPS`] order), with the
    /// measured cost and error that justify it.
    pub fn recommendations(&self) -> &[Recommendation] {
        &self.recommendations
    }

    /// The row of `warp`, `variant`, `scalar`.
    pub fn row(&self, warp: &str, variant: &str, scalar: &str) -> Option<&SpeedRow> {
        self.rows
            .iter()
            .find(|r| r.warp == warp && r.variant == variant && r.scalar == scalar)
    }

    /// The Pareto-optimal rows of `warp`, fastest first.
    pub fn pareto(&self, warp: &str) -> Vec<&SpeedRow> {
        let mut v: Vec<&SpeedRow> = self
            .rows
            .iter()
            .filter(|r| r.warp == warp && r.pareto)
            .collect();
        v.sort_by(|a, b| a.map.median.total_cmp(&b.map.median));
        v
    }

    /// The study as a Markdown section: the full table, the Pareto set and
    /// the recommendations.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "## Speed–accuracy: every warp × variant × type\n");
        let c = &self.config;
        let _ = writeln!(
            s,
            "Time: ns per sample on the warp's first shape (*timed shape*), median of {} runs of {} samples \
             (MPFR: {} runs of {}), with the spread min–max and the interquartile range; *build + map* rebuilds \
             the shape from its f64 data for every sample ({} samples per run; MPFR {}). Error: max-norm \
             distance over extent to the exact map (robust / Newton) of the shape as the type sees it, at 512 \
             bits, over the extremes grid plus {} random points ({} per shape) on *all* the warp's shapes \
             (ladders included; `rej.` = shapes the type rejects), absolute and in units of the type's roundoff. \
             Inputs and outputs reach the reference exactly; the MPFR shapes' parameters pass through a decimal \
             round trip (½ ulp of the type). ★ = Pareto-optimal within the warp in (median map time, max error) \
             among the configurations without NaN/∞ — a configuration with an O(1) error is on the front only \
             by being the fastest. For the closed forms without per-shape constants *build + map* may come out \
             below *map* (code layout): their construction is free. Timings come from one run on a shared \
             machine (other processes inflate the upper quantiles): compare within the table.\n",
            c.repetitions,
            c.batch,
            c.mpfr_repetitions,
            c.mpfr_batch,
            c.build_batch,
            c.mpfr_batch,
            c.error_random_points,
            self.points_per_shape
        );
        let _ = writeln!(
            s,
            "| warp | variant | type | map ns (min–max; IQR) | build + map ns (min–max) | max error | [u] | worst shape | timed-shape error | NaN | shapes (rej.) | Pareto |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} ({}–{}; {}–{}) | {} ({}–{}) | {} | {} | {} | {} | {} | {} ({}) | {} |",
                r.warp,
                r.variant,
                r.scalar,
                fmt_num(r.map.median),
                fmt_num(r.map.min),
                fmt_num(r.map.max),
                fmt_num(r.map.q1),
                fmt_num(r.map.q3),
                fmt_num(r.build_and_map.median),
                fmt_num(r.build_and_map.min),
                fmt_num(r.build_and_map.max),
                fmt_num(r.max_error),
                fmt_num(r.max_error_ulps),
                r.worst_shape,
                fmt_num(r.timed_shape_error),
                r.non_finite,
                r.shapes,
                r.rejected,
                if r.pareto { "★" } else { "" }
            );
        }
        let _ = writeln!(s, "\n### Pareto set per warp (fastest first)\n");
        let _ = writeln!(s, "| warp | not dominated in (time, error) |");
        let _ = writeln!(s, "|---|---|");
        for warp in WARPS {
            let set: Vec<String> = self
                .pareto(warp)
                .iter()
                .map(|r| {
                    format!(
                        "{} {} ({} ns, {})",
                        r.variant,
                        r.scalar,
                        fmt_num(r.map.median),
                        fmt_num(r.max_error)
                    )
                })
                .collect();
            if !set.is_empty() {
                let _ = writeln!(s, "| {warp} | {} |", set.join(" → "));
            }
        }
        let _ = writeln!(
            s,
            "\n![speed–accuracy in f32 and f64](speed_pareto.svg)\n\n![speed–accuracy in MPFR](speed_pareto_mpfr.svg)\n\n![projected polygon: inversion settings](speed_pareto_projected-polygon.svg)\n"
        );
        let _ = writeln!(
            s,
            "### Recommended defaults\n\nPer warp, among the f64 configurations that never returned NaN/∞ and \
             whose max error over all shapes is within 4× the best f64 max error: the crate's default variant, \
             unless an alternative is clearly faster (median ≥ 10 % lower and the interquartile ranges do not \
             overlap), then the fastest such alternative.\n"
        );
        let _ = writeln!(
            s,
            "| warp | default | ns/sample | with construction | max error | why |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for r in &self.recommendations {
            let _ = writeln!(
                s,
                "| {} | {} {} | {} | {} | {} | {} |",
                r.warp,
                r.variant,
                r.scalar,
                fmt_num(r.ns_per_sample),
                fmt_num(r.ns_with_construction),
                fmt_num(r.max_error),
                r.reason
            );
        }
        s
    }

    /// Writes `speed_accuracy.csv` (every row) and
    /// `speed_recommendations.csv` into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut t = String::from(
            "warp,variant,type,timed_shape,map_ns_median,map_ns_min,map_ns_max,map_ns_q1,map_ns_q3,map_runs,map_samples,\
             build_ns_median,build_ns_min,build_ns_max,build_ns_q1,build_ns_q3,build_runs,build_samples,\
             max_error,max_error_ulps,worst_shape,timed_shape_error,non_finite,shapes,rejected,pareto\n",
        );
        for r in &self.rows {
            let _ = writeln!(
                t,
                "{},{},{},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:e},{:e},\"{}\",{:e},{},{},{},{}",
                r.warp,
                r.variant,
                r.scalar,
                r.timed_shape,
                r.map.median,
                r.map.min,
                r.map.max,
                r.map.q1,
                r.map.q3,
                r.map.runs,
                r.map.samples,
                r.build_and_map.median,
                r.build_and_map.min,
                r.build_and_map.max,
                r.build_and_map.q1,
                r.build_and_map.q3,
                r.build_and_map.runs,
                r.build_and_map.samples,
                r.max_error,
                r.max_error_ulps,
                r.worst_shape,
                r.timed_shape_error,
                r.non_finite,
                r.shapes,
                r.rejected,
                r.pareto
            );
        }
        let a = dir.join("speed_accuracy.csv");
        std::fs::write(&a, t)?;
        let mut t =
            String::from("warp,variant,type,ns_per_sample,ns_with_construction,max_error,reason\n");
        for r in &self.recommendations {
            let _ = writeln!(
                t,
                "{},{},{},{},{},{:e},\"{}\"",
                r.warp,
                r.variant,
                r.scalar,
                r.ns_per_sample,
                r.ns_with_construction,
                r.max_error,
                r.reason.replace('"', "\"\"")
            );
        }
        let b = dir.join("speed_recommendations.csv");
        std::fs::write(&b, t)?;
        Ok(vec![a, b])
    }

    /// Writes `speed_pareto.svg` (log-log: median ns per sample against max
    /// error in f32 and f64 only, per warp its Pareto front as a line and
    /// every configuration as a marker in the warp's colour, the marker's
    /// shape telling the type: triangle f32, disc f64),
    /// `speed_pareto_mpfr.svg` (the same for MPFR, square 128 bits, cross
    /// 256 bits) and `speed_pareto_projected-polygon.svg` (the
    /// polygon's inversion settings, one line per setting through the four
    /// types).
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let floor = |e: f64| e.max(1e-80);
        use crate::figures::Marker;
        let marker = |scalar: &str| match scalar {
            "f32" => Marker::Triangle,
            "f64" => Marker::Circle,
            "mpfr:128" => Marker::Square,
            _ => Marker::Cross,
        };
        // One plot per group of scalar types: f32/f64 (what a renderer
        // uses) and MPFR (errors down to 1e-77 would squeeze the first).
        let mut out = Vec::new();
        for (file, title, scalars) in [
            (
                "speed_pareto.svg",
                "speed–accuracy in f32 (triangles) and f64 (discs); lines: each warp's Pareto front",
                &["f32", "f64"][..],
            ),
            (
                "speed_pareto_mpfr.svg",
                "speed–accuracy in MPFR, 128 bits (squares) and 256 bits (crosses); lines: Pareto fronts",
                &["mpfr:128", "mpfr:256"][..],
            ),
        ] {
            let mut plot = Plot::new(
                title,
                Axis::log("ns per sample (median, shape built once)"),
                Axis::log("max error (distance / extent)"),
            )
            .size(980, 620);
            for (i, warp) in WARPS.iter().enumerate() {
                let color = crate::figures::PALETTE[i % crate::figures::PALETTE.len()];
                let rows: Vec<&SpeedRow> = self
                    .rows
                    .iter()
                    .filter(|r| {
                        r.warp == *warp && scalars.contains(&r.scalar.as_str()) && r.non_finite == 0
                    })
                    .collect();
                let dominated = |r: &SpeedRow| {
                    rows.iter().any(|o| {
                        o.map.median <= r.map.median
                            && o.max_error <= r.max_error
                            && (o.map.median < r.map.median || o.max_error < r.max_error)
                    })
                };
                let mut front: Vec<(f64, f64)> = rows
                    .iter()
                    .filter(|r| !dominated(r))
                    .map(|r| (r.map.median, floor(r.max_error)))
                    .collect();
                if front.is_empty() {
                    continue;
                }
                front.sort_by(|a, b| a.0.total_cmp(&b.0));
                let mut line = Series::new(warp, front).with_color(color);
                line.markers = false;
                plot = plot.series(line);
                for &t in scalars {
                    let pts: Vec<(f64, f64)> = rows
                        .iter()
                        .filter(|r| r.scalar == t)
                        .map(|r| (r.map.median, floor(r.max_error)))
                        .collect();
                    let mut dots = Series::new("", pts).with_color(color).marker(marker(t));
                    dots.points.sort_by(|a, b| a.0.total_cmp(&b.0));
                    // Markers only: a series of separate rows, not a curve.
                    let pts = std::mem::take(&mut dots.points);
                    for p in pts {
                        plot = plot
                            .series(Series::new("", vec![p]).with_color(color).marker(marker(t)));
                    }
                }
            }
            out.push(write_line_plot_svg(&dir.join(file), &plot)?);
        }

        // The polygon's inversion settings: one line per setting through
        // the scalars f32 → f64 → mpfr:128 → mpfr:256 (the cubic's error
        // stays at its bias, Newton's falls with the precision).
        let mut poly = Plot::new(
            "projected polygon: marginal inversion settings across types",
            Axis::log("ns per sample (median)"),
            Axis::log("max error (distance / extent)"),
        );
        for (label, _) in crate::studies::precision::POLYGON_SETTINGS {
            let pts: Vec<(f64, f64)> = SCALARS
                .iter()
                .filter_map(|t| self.row("projected-polygon", label, t))
                .map(|r| (r.map.median, floor(r.max_error)))
                .collect();
            if !pts.is_empty() {
                poly = poly.series(Series::new(label, pts));
            }
        }
        out.push(write_line_plot_svg(
            &dir.join(format!("speed_pareto_{}.svg", slug("projected-polygon"))),
            &poly,
        )?);
        Ok(out)
    }
}
