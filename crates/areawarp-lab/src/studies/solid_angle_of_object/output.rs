//! The study's Markdown, CSV files and figures.

use super::*;

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// A decimal string cut to `digits` significant characters, keeping its
/// exponent.
pub(crate) fn short_decimal(s: &str, digits: usize) -> String {
    match s.find(['e', 'E']) {
        Some(i) => format!("{}{}", &s[..i.min(digits + 2)], &s[i..]),
        None => s[..s.len().min(digits + 2)].to_string(),
    }
}

pub(crate) fn fmt_e(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.2e}")
    }
}

pub(crate) fn csv_write(path: &Path, header: &str, lines: &[String]) -> io::Result<PathBuf> {
    let mut s = String::from(header);
    s.push('\n');
    for l in lines {
        s.push_str(l);
        s.push('\n');
    }
    std::fs::write(path, s)?;
    Ok(path.to_path_buf())
}

impl SolidAngleStudy {
    pub(crate) fn row(&self, scene: &str, method: &Method, n: usize) -> Option<&ErrorRow> {
        let name = method.name();
        self.rows
            .iter()
            .find(|r| r.scene == scene && r.method == name && r.n == n)
    }

    /// The file names [`SolidAngleStudy::write_figures`] writes, in order.
    pub fn figure_files(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "solid_angle_samples.svg",
            "solid_angle_f32_error_uv.svg",
            "solid_angle_f32_error_uv.png",
            "solid_angle_f32_evaluation_uv.svg",
            "solid_angle_f32_pole_profile.svg",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for a in &self.axis_spread {
            v.push(format!("solid_angle_f32_world_{}.svg", a.axis));
        }
        for sc in &self.scenes {
            v.push(format!("solid_angle_error_vs_n_{}.svg", sc.name));
        }
        v
    }

    /// `rms(a) / rms(b)` on `scene` at the largest `n` where both were
    /// measured, with that `n`.
    pub fn error_ratio(&self, scene: &str, a: &Method, b: &Method) -> Option<(f64, usize)> {
        self.config.sample_counts.iter().rev().find_map(|&n| {
            Some((
                self.rms_error(scene, a, n)? / self.rms_error(scene, b, n)?,
                n,
            ))
        })
    }

    /// [`SolidAngleStudy::error_ratio`] with its standard error by the
    /// delta method (the methods' estimates are independent:
    /// `se(r)/r = √((se_a/rms_a)² + (se_b/rms_b)²)`): `(ratio, se, n)`.
    pub fn error_ratio_interval(
        &self,
        scene: &str,
        a: &Method,
        b: &Method,
    ) -> Option<(f64, f64, usize)> {
        self.config.sample_counts.iter().rev().find_map(|&n| {
            let (ra, rb) = (self.row(scene, a, n)?, self.row(scene, b, n)?);
            let r = ra.rms_relative_error / rb.rms_relative_error;
            let rel = ((ra.rms_std_error / ra.rms_relative_error).powi(2)
                + (rb.rms_std_error / rb.rms_relative_error).powi(2))
            .sqrt();
            Some((r, r * rel, n))
        })
    }

    /// The RMS relative error of `method` on `scene` at `n`, if measured.
    pub fn rms_error(&self, scene: &str, method: &Method, n: usize) -> Option<f64> {
        self.row(scene, method, n).map(|r| r.rms_relative_error)
    }

    /// The report section (Markdown): scenes with exact references, the
    /// error-vs-samples tables, slopes, headline ratios, the `f32` error
    /// profile and spread, and links to the figures (relative to the
    /// directory given to [`SolidAngleStudy::write_figures`]).
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let c = &self.config;
        let nmax = c.sample_counts.iter().copied().max().unwrap_or(0);
        let _ = writeln!(s, "## Solid angle of an object (Shao–Badler §3)\n");
        let _ = writeln!(
            s,
            "Ω̂ = |B| · (hits / n): directions uniform in the object's angular bounding box B in \
             cylinder coordinates (z, φ) — Archimedes' axial projection makes them uniform on the \
             sphere —, a Möller–Trumbore ray test per direction (inclusive edges), against the exact \
             Ω from Van Oosterom–Strackee per face ({}). {} estimates per cell, seed {:#x}.\n",
            self.f32_map.reference, c.repetitions, c.seed
        );
        let _ = writeln!(
            s,
            "| scene | faces | kind | Ω exact (sr) | f64 vs reference | box share of sphere (fixed axis) |\n|---|---|---|---|---|---|"
        );
        for sc in &self.scenes {
            let _ = writeln!(
                s,
                "| {} — {} | {} | {:?} | {} | {} | {} |",
                sc.name,
                sc.description,
                sc.faces,
                sc.kind,
                short_decimal(&sc.exact_reference, 20),
                fmt_e(sc.f64_relative_error),
                fmt_e(sc.fixed_box_fraction)
            );
        }
        for sc in &self.scenes {
            let _ = writeln!(
                s,
                "\n### RMS relative error — {}\n\n![error vs n](solid_angle_error_vs_n_{}.svg)\n\n\
                 Each cell: the RMS relative error over {} estimates ± the half-width of its 95% interval relative to it \
                 (delta method on the mean of the squared errors).\n",
                sc.name, sc.name, c.repetitions
            );
            let _ = write!(s, "| n |");
            for m in &c.methods {
                let _ = write!(s, " {} |", m.name());
            }
            let _ = write!(s, "\n|---|");
            for _ in &c.methods {
                let _ = write!(s, "---|");
            }
            s.push('\n');
            for &n in &c.sample_counts {
                let _ = write!(s, "| {n} |");
                for m in &c.methods {
                    match self.row(&sc.name, m, n) {
                        Some(r) if r.rms_relative_error > 0.0 => {
                            let _ = write!(
                                s,
                                " {} ±{:.0}% |",
                                fmt_e(r.rms_relative_error),
                                100.0 * crate::verdict::Z95 * r.rms_std_error
                                    / r.rms_relative_error
                            );
                        }
                        Some(r) => {
                            let _ = write!(s, " {} |", fmt_e(r.rms_relative_error));
                        }
                        None => s.push_str(" – |"),
                    }
                }
                s.push('\n');
            }
            let _ = write!(s, "| slope |");
            for m in &c.methods {
                let sl = self
                    .slopes
                    .iter()
                    .find(|r| r.scene == sc.name && r.method == m.name())
                    .map_or(f64::NAN, |r| r.slope);
                let _ = write!(s, " {sl:.2} |");
            }
            s.push('\n');
            let _ = write!(s, "| bias at n = {nmax} (± s.e.) |");
            for m in &c.methods {
                match self.row(&sc.name, m, nmax) {
                    Some(r) => {
                        let _ = write!(
                            s,
                            " {} ± {} |",
                            fmt_e(r.relative_bias),
                            fmt_e(r.bias_std_error)
                        );
                    }
                    None => s.push_str(" – |"),
                }
            }
            s.push('\n');
        }
        // Headlines.
        let _ = writeln!(
            s,
            "\n### Findings (RMS error ratios at the largest n measured for both)\n\n\
             Each ratio with its 95% interval: the delta method on the two RMS values, each with the standard error of a mean \
             of {} squared errors (the methods' estimates are independent).\n",
            self.config.repetitions
        );
        let std = Method::standard();
        let (rand_box, strat_box, strat_sphere, rand_axis, strat_axes, f32_fixed, f32_axes) =
            (std[0], std[1], std[2], std[3], std[4], std[5], std[6]);
        let ratio =
            |scene: &str, a: &Method, b: &Method| match self.error_ratio_interval(scene, a, b) {
                Some((r, se, n)) => {
                    let (lo, hi) = crate::verdict::interval(r, se);
                    format!(
                        "{} [95%: {}, {}] (n = {n})",
                        crate::verdict::sig3(r),
                        crate::verdict::sig3(lo.max(0.0)),
                        crate::verdict::sig3(hi)
                    )
                }
                None => "–".to_string(),
            };
        for sc in &self.scenes {
            let _ = writeln!(
                s,
                "- **{}**: stratified / random {}; stratified box / whole sphere {}; random axis \
                 / fixed axis: random sampling (axis per sample) {}, stratified (≈ n^(1/4) axes) {}.",
                sc.name,
                ratio(&sc.name, &strat_box, &rand_box),
                ratio(&sc.name, &strat_box, &strat_sphere),
                ratio(&sc.name, &rand_axis, &rand_box),
                ratio(&sc.name, &strat_axes, &strat_box),
            );
            if let (Some(a), Some(r)) = (
                self.row(&sc.name, &f32_fixed, nmax),
                self.row(&sc.name, &f32_axes, nmax),
            ) {
                let _ = writeln!(
                    s,
                    "  `f32` map at n = {nmax}: fixed axis bias {} ± {} (RMS {}), random axes \
                     bias {} ± {} (RMS {}).",
                    fmt_e(a.relative_bias),
                    fmt_e(a.bias_std_error),
                    fmt_e(a.rms_relative_error),
                    fmt_e(r.relative_bias),
                    fmt_e(r.bias_std_error),
                    fmt_e(r.rms_relative_error)
                );
            }
        }
        // f32 error.
        let m = &self.f32_map;
        let max_e2e = m.end_to_end_ulps.iter().copied().fold(0.0, f64::max);
        let max_eval = m.evaluation_ulps.iter().copied().fold(0.0, f64::max);
        let col_max = |i: usize| {
            (0..m.rows)
                .map(|j| m.end_to_end_ulps[j * m.cols + i])
                .fold(0.0, f64::max)
        };
        let mid = (m.cols / 4..3 * m.cols / 4)
            .map(col_max)
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "\n### Where the `f32` truncation error of the sphere map lives\n\n\
             ![f32 error over (u, v)](solid_angle_f32_error_uv.svg)\n\n\
             End-to-end error of `Sphere<f32>` (data (u, v) in f64, rounded to f32) against the \
             {} map at the data, max over {} points per cell of a {}×{} grid, in units of 2^-24: \
             max {:.1} overall; first column (u → 0, north pole) {:.1}; middle half \
             (|z| < 1/2) {:.1}; last column (u → 1, south pole) {:.1}. The evaluation alone \
             (inputs first rounded to f32) stays within {:.1} units everywhere \
             ([map](solid_angle_f32_evaluation_uv.svg)): the error is the quantization of u \
             near 1, amplified by dθ/dz = 1/sin θ.\n",
            m.reference,
            m.points_per_cell,
            m.cols,
            m.rows,
            max_e2e,
            col_max(0),
            mid,
            col_max(m.cols - 1),
            max_eval
        );
        let _ = writeln!(
            s,
            "![f32 error towards the poles](solid_angle_f32_pole_profile.svg)\n\n\
             | distance d from the pole | north, end-to-end | south, end-to-end | north, evaluation | south, evaluation |\n|---|---|---|---|---|"
        );
        for r in self
            .pole_profile
            .iter()
            .filter(|r| r.log2_distance % 4 == 0)
        {
            let _ = writeln!(
                s,
                "| 2^{} | {:.2} | {:.2} | {:.2} | {:.2} |",
                r.log2_distance,
                r.north_end_to_end,
                r.south_end_to_end,
                r.north_evaluation,
                r.south_evaluation
            );
        }
        let _ = writeln!(
            s,
            "\nWorld directions (caps |z| > 0.99 hold 1% of the sphere): \
             ![fixed axis](solid_angle_f32_world_fixed.svg) ![random axis](solid_angle_f32_world_random.svg)\n\n\
             | axis | samples | share of squared error in the caps | max, north cap | max, south cap | max elsewhere | RMS |\n|---|---|---|---|---|---|---|"
        );
        for a in &self.axis_spread {
            let _ = writeln!(
                s,
                "| {} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.2} |",
                a.axis,
                a.samples,
                a.cap_error_share,
                a.max_north_cap,
                a.max_south_cap,
                a.max_elsewhere,
                a.rms
            );
        }
        let _ = writeln!(s, "\n![samples over the object](solid_angle_samples.svg)\n");
        s
    }

    /// Writes the tables as CSV files into `dir` (created if needed):
    /// `solid_angle_scenes.csv`, `solid_angle_errors.csv`,
    /// `solid_angle_slopes.csv`, `solid_angle_f32_pole_profile.csv`,
    /// `solid_angle_f32_uv.csv`, `solid_angle_f32_axis_spread.csv`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        out.push(csv_write(
            &dir.join("solid_angle_scenes.csv"),
            "scene,faces,kind,exact_f64,exact_reference,f64_relative_error,fixed_box_fraction",
            &self
                .scenes
                .iter()
                .map(|s| {
                    format!(
                        "{},{},{:?},{:e},{},{:e},{:e}",
                        s.name,
                        s.faces,
                        s.kind,
                        s.exact_f64,
                        s.exact_reference,
                        s.f64_relative_error,
                        s.fixed_box_fraction
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_errors.csv"),
            "scene,method,n,repetitions,mean,rms_relative_error,rms_std_error,relative_bias,bias_std_error,box_fraction,random_prediction",
            &self
                .rows
                .iter()
                .map(|r| {
                    format!(
                        "{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                        r.scene,
                        r.method,
                        r.n,
                        r.repetitions,
                        r.mean,
                        r.rms_relative_error,
                        r.rms_std_error,
                        r.relative_bias,
                        r.bias_std_error,
                        r.box_fraction,
                        r.random_prediction
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_slopes.csv"),
            "scene,method,slope",
            &self
                .slopes
                .iter()
                .map(|r| format!("{},{},{:e}", r.scene, r.method, r.slope))
                .collect::<Vec<_>>(),
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_f32_pole_profile.csv"),
            "log2_distance,north_end_to_end,south_end_to_end,north_evaluation,south_evaluation",
            &self
                .pole_profile
                .iter()
                .map(|r| {
                    format!(
                        "{},{:e},{:e},{:e},{:e}",
                        r.log2_distance,
                        r.north_end_to_end,
                        r.south_end_to_end,
                        r.north_evaluation,
                        r.south_evaluation
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        let m = &self.f32_map;
        let mut lines = Vec::with_capacity(m.cols * m.rows);
        for j in 0..m.rows {
            for i in 0..m.cols {
                lines.push(format!(
                    "{},{},{:.4e},{:.4e}",
                    (i as f64 + 0.5) / m.cols as f64,
                    (j as f64 + 0.5) / m.rows as f64,
                    m.end_to_end_ulps[j * m.cols + i],
                    m.evaluation_ulps[j * m.cols + i]
                ));
            }
        }
        out.push(csv_write(
            &dir.join("solid_angle_f32_uv.csv"),
            "u_center,v_center,end_to_end_ulps,evaluation_ulps",
            &lines,
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_f32_axis_spread.csv"),
            "axis,samples,cap_error_share,max_north_cap,max_south_cap,max_elsewhere,rms",
            &self
                .axis_spread
                .iter()
                .map(|a| {
                    format!(
                        "{},{},{:e},{:e},{:e},{:e},{:e}",
                        a.axis,
                        a.samples,
                        a.cap_error_share,
                        a.max_north_cap,
                        a.max_south_cap,
                        a.max_elsewhere,
                        a.rms
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        Ok(out)
    }

    /// Writes the figures into `dir` (created if needed): per scene a
    /// log-log plot of RMS relative error against `n` for every method with
    /// `n^(−1/2)` and `n^(−3/4)` reference slopes
    /// (`solid_angle_error_vs_n_<scene>.svg`); the `f32` error heat maps
    /// over `(u, v)` (end-to-end as SVG and PNG, evaluation-only as SVG);
    /// the pole profile; the world-direction maps for the fixed and the
    /// random axis (same colour range); and the sample-distribution demo.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        // Samples over the object.
        let hits: Vec<(f64, f64)> = self
            .demo_points
            .iter()
            .filter(|p| p.2)
            .map(|p| (p.0, 1.0 - 2.0 * p.1))
            .collect();
        let misses: Vec<(f64, f64)> = self
            .demo_points
            .iter()
            .filter(|p| !p.2)
            .map(|p| (p.0, 1.0 - 2.0 * p.1))
            .collect();
        let name = self.scenes.first().map_or("", |s| s.name.as_str());
        out.push(figures::write_scatter_svg(
            &dir.join("solid_angle_samples.svg"),
            &Plot::new(
                &format!(
                    "{} stratified directions in the (z, φ) box of the {name} ({:.2}% of the sphere)",
                    self.demo_points.len(),
                    100.0 * self.demo_box.fraction()
                ),
                Axis::linear("φ / 2π (turns)"),
                Axis::linear("z"),
            )
            .series(Series::new("hit", hits))
            .series(Series::new("miss", misses))
            .point_radius(2.0),
        )?);
        // f32 maps over (u, v).
        let m = &self.f32_map;
        let uv_axes = |map: HeatMap| {
            map.axes(
                Axis::linear("u   (0: north pole, 1: south pole)").with_range(0.0, 1.0),
                Axis::linear("v = φ / 2π").with_range(0.0, 1.0),
            )
        };
        let e2e = uv_axes(HeatMap::new(
            &format!(
                "f32 sphere map, end-to-end error vs {} (units of 2^-24)",
                m.reference
            ),
            m.cols,
            m.rows,
            m.end_to_end_ulps.clone(),
        )?)
        .value_axis("max error / 2^-24 per cell", Scale::Log10);
        out.push(figures::write_heat_map_svg(
            &dir.join("solid_angle_f32_error_uv.svg"),
            &e2e,
        )?);
        out.push(figures::write_heat_map_png(
            &dir.join("solid_angle_f32_error_uv.png"),
            &e2e,
            (256 / m.cols.max(1)).max(1) as u32,
        )?);
        let mut eval = uv_axes(HeatMap::new(
            "f32 sphere map, evaluation error only (inputs rounded to f32 first)",
            m.cols,
            m.rows,
            m.evaluation_ulps.clone(),
        )?)
        .value_axis("max error / 2^-24 per cell", Scale::Log10);
        eval.value_range = Some((
            e2e.color_range().0.min(eval.color_range().0),
            e2e.color_range().1,
        ));
        out.push(figures::write_heat_map_svg(
            &dir.join("solid_angle_f32_evaluation_uv.svg"),
            &eval,
        )?);
        // Pole profile.
        let series = |f: fn(&PoleProfileRow) -> f64| -> Vec<(f64, f64)> {
            self.pole_profile
                .iter()
                .map(|r| (2f64.powi(r.log2_distance), f(r)))
                .collect()
        };
        out.push(figures::write_line_plot_svg(
            &dir.join("solid_angle_f32_pole_profile.svg"),
            &Plot::new(
                "f32 sphere map: error at distance d (in u) from each pole",
                Axis::log("d  (u = d at the north pole, u = 1 − d at the south pole)"),
                Axis::log("max error / 2^-24"),
            )
            .series(Series::new(
                "south, end-to-end",
                series(|r| r.south_end_to_end),
            ))
            .series(Series::new(
                "north, end-to-end",
                series(|r| r.north_end_to_end),
            ))
            .series(Series::new(
                "south, evaluation only",
                series(|r| r.south_evaluation),
            ))
            .series(Series::new(
                "north, evaluation only",
                series(|r| r.north_evaluation),
            )),
        )?);
        // World maps, one colour range.
        let range = self
            .axis_spread
            .iter()
            .flat_map(|a| a.cell_rms.iter().flatten().copied())
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        for a in &self.axis_spread {
            let mut map = HeatMap::new(
                &format!(
                    "f32 end-to-end error over world directions, {} axis (RMS per cell)",
                    a.axis
                ),
                a.cols,
                a.rows,
                a.cell_rms.iter().map(|c| c.unwrap_or(f64::NAN)).collect(),
            )?
            .axes(
                Axis::linear("u_world = (1 − z)/2").with_range(0.0, 1.0),
                Axis::linear("φ_world / 2π").with_range(0.0, 1.0),
            )
            .value_axis("RMS error / 2^-24", Scale::Log10);
            if range.0.is_finite() && range.1 > range.0 {
                map.value_range = Some(range);
            }
            out.push(figures::write_heat_map_svg(
                &dir.join(format!("solid_angle_f32_world_{}.svg", a.axis)),
                &map,
            )?);
        }
        // Error vs n per scene.
        for sc in &self.scenes {
            let mut plot = Plot::new(
                &format!("solid angle of the {}: RMS relative error", sc.name),
                Axis::log("samples n"),
                Axis::log("RMS relative error"),
            );
            for m in &self.config.methods {
                let pts: Vec<(f64, f64)> = self
                    .rows
                    .iter()
                    .filter(|r| r.scene == sc.name && r.method == m.name())
                    .map(|r| (r.n as f64, r.rms_relative_error))
                    .collect();
                plot = plot.series(Series::new(&m.name(), pts));
            }
            let nmin = self.config.sample_counts.iter().copied().min().unwrap_or(4) as f64;
            let nmax = self.config.sample_counts.iter().copied().max().unwrap_or(4) as f64;
            let anchor = |m: &Method| {
                self.rms_error(&sc.name, m, nmin as usize)
                    .filter(|v| *v > 0.0)
            };
            let std = Method::standard();
            if let Some(a) = anchor(&std[0]) {
                plot = plot.series(
                    Series::new(
                        "n^-1/2",
                        vec![(nmin, a), (nmax, a * (nmax / nmin).powf(-0.5))],
                    )
                    .reference()
                    .with_color(figures::Rgb(90, 90, 90)),
                );
            }
            if let Some(a) = anchor(&std[1]) {
                plot = plot.series(
                    Series::new(
                        "n^-3/4",
                        vec![(nmin, a), (nmax, a * (nmax / nmin).powf(-0.75))],
                    )
                    .reference()
                    .with_color(figures::Rgb(160, 160, 160)),
                );
            }
            out.push(figures::write_line_plot_svg(
                &dir.join(format!("solid_angle_error_vs_n_{}.svg", sc.name)),
                &plot,
            )?);
        }
        Ok(out)
    }
}
