//! The study's Markdown, CSV files and figures.

use super::*;

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// `x` in a short scientific or fixed notation for tables.
pub(crate) fn fmt_num(x: f64) -> String {
    if x.is_nan() {
        "NaN".to_string()
    } else if x == 0.0 {
        "0".to_string()
    } else if x.abs() >= 1e4 || x.abs() < 1e-2 {
        format!("{x:.1e}")
    } else if x.abs() >= 100.0 {
        format!("{x:.0}")
    } else {
        format!("{x:.2}")
    }
}

pub(crate) fn fmt_opt(x: Option<f64>) -> String {
    x.map_or("–".to_string(), fmt_num)
}

pub(crate) fn fmt_uv(uv: (f64, f64)) -> String {
    let f = |x: f64| {
        if x == 0.0 || x == 1.0 || x == 0.5 {
            format!("{x}")
        } else if x < 1e-3 {
            format!("{x:.0e}")
        } else if x > 1.0 - 1e-3 {
            format!("1−{:.0e}", 1.0 - x)
        } else {
            format!("{x:.3}")
        }
    };
    format!("({}, {})", f(uv.0), f(uv.1))
}

/// A file-name-safe version of `s`.
pub(crate) fn slug(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('-') {
            out.push('-');
        }
    }
    out.trim_matches('-').to_string()
}

pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub(crate) fn opt_csv(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| format!("{v:e}"))
}

pub(crate) fn uv_csv(uv: Option<(f64, f64)>) -> (String, String) {
    uv.map_or((String::new(), String::new()), |(u, v)| {
        (format!("{u:e}"), format!("{v:e}"))
    })
}

impl PrecisionStudy {
    /// The summary row of `warp`, `variant`, `scalar`.
    pub fn summary_of(&self, warp: &str, variant: &str, scalar: &str) -> Option<&PrecisionSummary> {
        self.summary
            .iter()
            .find(|s| s.warp == warp && s.variant == variant && s.scalar == scalar)
    }

    /// The cell of `warp`, `variant`, `shape`, `scalar`.
    pub fn cell(
        &self,
        warp: &str,
        variant: &str,
        shape: &str,
        scalar: &str,
    ) -> Option<&PrecisionCell> {
        self.cells.iter().find(|c| {
            c.warp == warp && c.variant == variant && c.shape == shape && c.scalar == scalar
        })
    }

    /// The figure file name of an `f32` error map.
    pub fn map_file_name(m: &F32ErrorMap) -> String {
        format!(
            "precision_f32_map_{}_{}.svg",
            slug(&m.warp),
            slug(&m.variant)
        )
    }

    /// The study as a Markdown section: the summary over all shapes, the
    /// solid-angle maps' ladders shape by shape, the projected polygon's
    /// inversion settings per polygon, and the `f32` error maps.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "## Precision: every warp × variant × type against 256 bits\n"
        );
        let _ = writeln!(
            s,
            "Each shape is evaluated on the extremes grid (u, v ∈ {{0, 2⁻⁶⁰, 1e-12, 1e-6, ½, 1−1e-6, 1−1e-12, 1}}²) \
             plus {} random points ({} points per shape), for every shape of the warp's test set — for the \
             spherical triangle and rectangle their ordinary shapes and the whole hard ladders. *Error* is the \
             max-norm distance to the **exact** map (robust variant, Newton-converged inversion) of the shape as \
             the type sees it, at the same rounded inputs, evaluated at 256 bits, over the shape's extent, in \
             units of the type's roundoff (2⁻²⁴, 2⁻⁵³); *own* compares with the variant's own map at 256 bits \
             instead (rounding alone; NaN where that map itself is NaN). *κ-ratio* is max error / (16·max(u, κ)), κ the move of the exact map \
             under a one-ulp change of one input (parameters, u, v): ≤ 1 means as accurate as the inputs allow. \
             *Jacobian* is max |J·pdf − 1| of the variant's map at 256 bits with exact partials (same for both \
             types). *NaN* counts NaN/∞ outputs, *out* points off the shape by more than 4 units (by more than \
             the κ bound in parentheses).\n",
            self.config.random_points, self.points_per_shape
        );
        let _ = writeln!(
            s,
            "| warp | variant | type | shapes (rejected) | max error [u] | at shape (u, v) | median [u] | own max [u] | NaN | out (κ) | κ-ratio | Jacobian dev. |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &self.summary {
            let at = r.worst.as_ref().map_or("–".to_string(), |(sh, uv)| {
                format!("{sh} {}", fmt_uv(*uv))
            });
            let kappa = match (r.max_kappa_ratio, r.kappa_failures) {
                (Some(k), 0) => fmt_num(k),
                (Some(k), f) => format!("{} ({f} without κ)", fmt_num(k)),
                (None, _) => "–".to_string(),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} ({}) | {} | {:.1e}{} |",
                r.warp,
                r.variant,
                r.scalar,
                r.shapes,
                r.rejected,
                fmt_num(r.max_ulps),
                at,
                fmt_num(r.median_ulps),
                fmt_num(r.own_max_ulps),
                r.non_finite,
                r.outside,
                r.outside_bound,
                kappa,
                r.jacobian_max_dev,
                if r.jacobian_non_finite > 0 {
                    format!(" ({} non-finite)", r.jacobian_non_finite)
                } else {
                    String::new()
                }
            );
        }
        for warp in ["spherical-triangle", "spherical-rectangle"] {
            let shapes: Vec<&PrecisionCell> = self
                .cells
                .iter()
                .filter(|c| c.warp == warp && c.variant == "robust" && c.scalar == "f64")
                .collect();
            if shapes.is_empty() {
                continue;
            }
            let _ = writeln!(
                s,
                "\n### {warp}: shape by shape (max error [u] / κ-ratio / NaN; `rej.` = rejected by the type)\n"
            );
            let _ = writeln!(
                s,
                "| shape | f64 robust | f64 literal | f32 robust | f32 literal | Jacobian literal |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|");
            for c in shapes {
                let cell = |variant: &str, scalar: &str| -> String {
                    match self.cell(warp, variant, &c.shape, scalar) {
                        None => "–".to_string(),
                        Some(x) if x.rejected => "rej.".to_string(),
                        Some(x) => format!(
                            "{} / {} / {}",
                            fmt_num(x.max_ulps),
                            fmt_opt(x.max_kappa_ratio),
                            x.non_finite
                        ),
                    }
                };
                let jl = self
                    .cell(warp, "literal", &c.shape, "f64")
                    .map_or("–".to_string(), |x| format!("{:.1e}", x.jacobian_max_dev));
                let _ = writeln!(
                    s,
                    "| {}{} | {} | {} | {} | {} | {} |",
                    c.shape,
                    if c.hard { "" } else { " (ordinary)" },
                    cell("robust", "f64"),
                    cell("literal", "f64"),
                    cell("robust", "f32"),
                    cell("literal", "f32"),
                    jl
                );
            }
        }
        let polys: Vec<&PrecisionCell> = self
            .cells
            .iter()
            .filter(|c| c.warp == "projected-polygon" && c.variant == "Newton" && c.scalar == "f64")
            .collect();
        if !polys.is_empty() {
            let _ = writeln!(
                s,
                "\n### projected-polygon: inversion settings per polygon (f64 max error against the exact map [u]; 256-bit Jacobian deviation)\n"
            );
            let mut head = "| polygon |".to_string();
            let mut rule = "|---|".to_string();
            for (label, _) in POLYGON_SETTINGS {
                let _ = write!(head, " {label} |");
                rule.push_str("---|");
            }
            let _ = writeln!(s, "{head}\n{rule}");
            for c in polys {
                let mut row = format!("| {} |", c.shape);
                for (label, _) in POLYGON_SETTINGS {
                    let x = self.cell("projected-polygon", label, &c.shape, "f64");
                    let _ = write!(
                        row,
                        " {} |",
                        x.map_or("–".to_string(), |x| format!(
                            "{} ({:.0e})",
                            fmt_num(x.max_ulps),
                            x.jacobian_max_dev
                        ))
                    );
                }
                let _ = writeln!(s, "{row}");
            }
        }
        if !self.f32_maps.is_empty() {
            let n = self.config.heat_map_nodes;
            let _ = writeln!(
                s,
                "\n### Where the f32 error lives over [0, 1]²\n\n\
                 The f32 error (units of 2⁻²⁴ · extent, against the exact map at 256 bits) at the {n} × {n} nodes \
                 (i/{m}, j/{m}); log colour scale, grey = NaN/∞.\n",
                m = n - 1
            );
            let _ = writeln!(
                s,
                "| warp | variant | shape | max [u] | at (u, v) | median [u] | nodes > 4 u | NaN | figure |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
            for m in &self.f32_maps {
                let f = Self::map_file_name(m);
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {} | {:.1}% | {} | [{f}]({f}) |",
                    m.warp,
                    m.variant,
                    m.shape,
                    fmt_num(m.max_ulps),
                    fmt_uv(m.worst),
                    fmt_num(m.median_ulps),
                    100.0 * m.above_4,
                    m.non_finite
                );
            }
            s.push('\n');
            for m in &self.f32_maps {
                let f = Self::map_file_name(m);
                let _ = writeln!(s, "![{} {} f32 error]({f})", m.warp, m.variant);
            }
        }
        s
    }

    /// Writes `precision_cells.csv` (every warp × variant × shape × type),
    /// `precision_summary.csv` (every warp × variant × type) and
    /// `precision_f32_maps.csv` (the error maps' statistics) into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        let mut t = String::from(
            "warp,variant,shape,hard,type,rejected,points,max_ulps,median_ulps,worst_u,worst_v,own_max_ulps,\
             non_finite,reference_non_finite,outside,max_outside_ulps,max_kappa_ratio,worst_kappa_u,worst_kappa_v,\
             max_kappa_ulps,outside_kappa_bound,kappa_error,jacobian_max_dev,jacobian_non_finite\n",
        );
        for c in &self.cells {
            let (wu, wv) = uv_csv(c.worst);
            let (ku, kv) = uv_csv(c.worst_kappa_ratio);
            let _ = writeln!(
                t,
                "{},{},{},{},{},{},{},{:e},{:e},{wu},{wv},{:e},{},{},{},{:e},{},{ku},{kv},{},{},{},{:e},{}",
                csv_field(&c.warp),
                csv_field(&c.variant),
                csv_field(&c.shape),
                c.hard,
                c.scalar,
                c.rejected,
                c.points,
                c.max_ulps,
                c.median_ulps,
                c.own_max_ulps,
                c.non_finite,
                c.reference_non_finite,
                c.outside,
                c.max_outside_ulps,
                opt_csv(c.max_kappa_ratio),
                opt_csv(c.max_kappa_ulps),
                c.outside_bound,
                csv_field(c.kappa_error.as_deref().unwrap_or("")),
                c.jacobian_max_dev,
                c.jacobian_non_finite
            );
        }
        let p = dir.join("precision_cells.csv");
        std::fs::write(&p, t)?;
        out.push(p);

        let mut t = String::from(
            "warp,variant,type,shapes,rejected,points,max_ulps,worst_shape,worst_u,worst_v,median_ulps,own_max_ulps,\
             non_finite,reference_non_finite,outside,outside_kappa_bound,max_kappa_ratio,worst_kappa_shape,\
             kappa_failures,jacobian_max_dev,jacobian_non_finite\n",
        );
        for r in &self.summary {
            let (shape, (wu, wv)) = match &r.worst {
                Some((sh, uv)) => (sh.clone(), uv_csv(Some(*uv))),
                None => (String::new(), uv_csv(None)),
            };
            let _ = writeln!(
                t,
                "{},{},{},{},{},{},{:e},{},{wu},{wv},{:e},{:e},{},{},{},{},{},{},{},{:e},{}",
                csv_field(&r.warp),
                csv_field(&r.variant),
                r.scalar,
                r.shapes,
                r.rejected,
                r.points,
                r.max_ulps,
                csv_field(&shape),
                r.median_ulps,
                r.own_max_ulps,
                r.non_finite,
                r.reference_non_finite,
                r.outside,
                r.outside_bound,
                opt_csv(r.max_kappa_ratio),
                csv_field(r.worst_kappa_shape.as_deref().unwrap_or("")),
                r.kappa_failures,
                r.jacobian_max_dev,
                r.jacobian_non_finite
            );
        }
        let p = dir.join("precision_summary.csv");
        std::fs::write(&p, t)?;
        out.push(p);

        let mut t = String::from(
            "warp,variant,shape,nodes,max_ulps,worst_u,worst_v,median_ulps,fraction_above_4,non_finite,figure\n",
        );
        for m in &self.f32_maps {
            let _ = writeln!(
                t,
                "{},{},{},{},{:e},{:e},{:e},{:e},{},{},{}",
                csv_field(&m.warp),
                csv_field(&m.variant),
                csv_field(&m.shape),
                m.nodes,
                m.max_ulps,
                m.worst.0,
                m.worst.1,
                m.median_ulps,
                m.above_4,
                m.non_finite,
                Self::map_file_name(m)
            );
        }
        let p = dir.join("precision_f32_maps.csv");
        std::fs::write(&p, t)?;
        out.push(p);
        Ok(out)
    }

    /// Writes one SVG heat map per `f32` error map
    /// ([`PrecisionStudy::map_file_name`]): log colour scale from
    /// `1/16` unit (or the smallest error above it) to the map's max.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        for m in &self.f32_maps {
            let n = m.nodes;
            let half = 0.5 / (n - 1) as f64;
            let floor = 1.0 / 16.0;
            let values: Vec<f64> = m
                .values
                .iter()
                .map(|&x| if x.is_finite() { x.max(floor) } else { x })
                .collect();
            let hi = m.max_ulps.max(2.0 * floor);
            let mut map = HeatMap::new(
                &format!("{} ({}, {}): f32 error", m.warp, m.variant, m.shape),
                n,
                n,
                values,
            )?
            .axes(
                Axis::linear("u").with_range(-half, 1.0 + half),
                Axis::linear("v").with_range(-half, 1.0 + half),
            )
            .value_axis("error [units of 2^-24 · extent]", Scale::Log10);
            map.value_range = Some((floor, hi));
            out.push(write_heat_map_svg(&dir.join(Self::map_file_name(m)), &map)?);
        }
        Ok(out)
    }
}
