//! The figures, tables and CSV of the rendered images.

use super::*;
use crate::estimator::{Method, Sampler};
use crate::figures::{self, Axis, ColorScale, Figure, ImageGrid, ImagePanel};
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// File names of the figures.
pub const GROUND_FIGURE: &str = "images_ufk13.png";
/// The MIS images.
pub const GROUND_MIS_FIGURE: &str = "images_ufk13_mis.png";
/// The triptych.
pub const TRIPTYCH_FIGURE: &str = "images_urena2000.png";
/// The CSV of the per-image errors.
pub const ERRORS_CSV: &str = "images_errors.csv";

/// A short sampler name for panel titles.
fn short(s: Sampler) -> &'static str {
    match s {
        Sampler::BilinearRectangle => "bilinear-cos. rect.",
        Sampler::ProjectedPolygon => "proj. polygon",
        other => other.name(),
    }
}

/// The symmetric bound of the error scale: the 99th percentile of `|e|`
/// over the finite errors (a positive fallback if all are 0).
pub fn error_bound<'a>(errors: impl Iterator<Item = &'a f64>, fallback: f64) -> f64 {
    let mut a: Vec<f64> = errors.filter(|e| e.is_finite()).map(|e| e.abs()).collect();
    if a.is_empty() {
        return fallback;
    }
    a.sort_by(f64::total_cmp);
    let q = a[((a.len() - 1) as f64 * 0.99).round() as usize];
    if q > 0.0 { q } else { fallback }
}

fn max_finite(v: &[f64]) -> f64 {
    v.iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max)
}

/// `1.23e-2`.
fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "–".to_string()
    }
}

fn panel(title: String, grid: &PixelGrid, values: Vec<f64>, scale: usize) -> ImagePanel {
    ImagePanel {
        title,
        cols: grid.cols,
        rows: grid.rows,
        values,
        scale,
    }
}

fn ground_axes() -> (Axis, Axis) {
    (
        Axis::linear("x (along the light)"),
        Axis::linear("y (from the light)"),
    )
}

impl RenderedImages {
    fn zoomed(grid: &PixelGrid, zoom: u32) -> (u32, u32) {
        let z = zoom.max(1);
        (grid.cols as u32 * z, grid.rows as u32 * z)
    }

    /// The standing-light figure for `methods` and their images (with or
    /// without MIS), and its error bound.
    fn ground_grid(
        &self,
        methods: &[Method],
        images: &[Vec<Image>],
        mis: bool,
    ) -> (ImageGrid, f64) {
        let g = &self.ground;
        let grid = &g.grid;
        let reference = &g.reference;
        let errors: Vec<Vec<Vec<f64>>> = images
            .iter()
            .map(|row| row.iter().map(|im| im.error(reference)).collect())
            .collect();
        let peak = max_finite(&reference.values);
        let bound = error_bound(errors.iter().flatten().flatten(), peak * 1e-3);
        let levels = images.first().map_or(0, Vec::len);
        let columns = 2 * levels.max(1);
        let mut panels = vec![None; columns];
        panels[0] = Some(panel(
            "reference (exact)".into(),
            grid,
            reference.values.clone(),
            0,
        ));
        for (m, method) in methods.iter().enumerate() {
            let name = short(method.sampler);
            for im in &images[m] {
                panels.push(Some(panel(
                    format!("{name}, {} spp", im.spp),
                    grid,
                    im.values.clone(),
                    0,
                )));
            }
            for (l, im) in images[m].iter().enumerate() {
                panels.push(Some(panel(
                    format!("{name}, {} spp: Ê − E", im.spp),
                    grid,
                    errors[m][l].clone(),
                    1,
                )));
            }
        }
        let (x, y) = ground_axes();
        let title = if mis {
            "Standing light, each light sample + one cosine sample by MIS (balance): irradiance and signed error"
        } else {
            "Standing light, light sampling alone: irradiance and signed error"
        };
        (
            ImageGrid {
                title: title.to_string(),
                x: x.with_range(grid.x.0, grid.x.1),
                y: y.with_range(grid.y.0, grid.y.1),
                columns,
                panels,
                scales: vec![
                    ColorScale::sequential("irradiance E", 0.0, peak.max(f64::MIN_POSITIVE)),
                    ColorScale::symmetric("signed error Ê − E", bound),
                ],
                panel_px: Self::zoomed(grid, self.config.ground_zoom),
            },
            bound,
        )
    }

    /// The triptych figure and its error bound.
    fn triptych_grid(&self) -> (ImageGrid, f64) {
        let t = &self.triptych;
        let grid = &t.grid;
        let errors: Vec<Vec<f64>> = t.images.iter().map(|im| im.error(&t.reference)).collect();
        let peak = max_finite(&t.reference.values);
        let bound = error_bound(errors.iter().flatten(), peak * 1e-3);
        let columns = 1 + t.images.len();
        let mut panels = vec![Some(panel(
            "reference (exact)".into(),
            grid,
            t.reference.values.clone(),
            0,
        ))];
        panels.extend(
            t.images
                .iter()
                .map(|im| Some(panel(im.short.clone(), grid, im.values.clone(), 0))),
        );
        panels.push(None);
        panels.extend(
            t.images
                .iter()
                .zip(errors)
                .map(|(im, e)| Some(panel(format!("Ê − E, {}", im.short), grid, e, 1))),
        );
        let (x, y) = ground_axes();
        (
            ImageGrid {
                title: format!(
                    "Patterned triangle light, occluders removed, {} samples per pixel: irradiance and signed error",
                    self.config.triptych.spp
                ),
                x: Axis {
                    label: "x".into(),
                    ..x
                }
                .with_range(grid.x.0, grid.x.1),
                y: Axis {
                    label: "y".into(),
                    ..y
                }
                .with_range(grid.y.0, grid.y.1),
                columns,
                panels,
                scales: vec![
                    ColorScale::sequential("irradiance E", 0.0, peak.max(f64::MIN_POSITIVE)),
                    ColorScale::symmetric("signed error Ê − E", bound),
                ],
                panel_px: Self::zoomed(grid, self.config.triptych_zoom),
            },
            bound,
        )
    }

    /// Writes `images_ufk13.png`, `images_ufk13_mis.png` and
    /// `images_urena2000.png` into `dir`; each [`Figure::title`] is the
    /// figure's caption (the report's alt text).
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        let g = &self.ground;
        let spp = spp_list(&self.config.ground.spp);
        let names = g
            .plain
            .iter()
            .map(|m| m.sampler.name())
            .collect::<Vec<_>>()
            .join(", ");
        let (gx, gy) = (g.grid.x, g.grid.y);
        let mut out = Vec::new();
        for (methods, images, mis, file, fig) in [
            (&g.plain, &g.plain_images, false, GROUND_FIGURE, "Fig. 4"),
            (&g.mis, &g.mis_images, true, GROUND_MIS_FIGURE, "Fig. 6"),
        ] {
            let (grid, bound) = self.ground_grid(methods, images, mis);
            let mut f = figures::write_image_grid_png(&dir.join(file), &grid)?;
            f.title = format!(
                "Rendered irradiance of the ground in front of the standing rectangular light, {how} \
                 (Ureña, Fajardo & King 2013, {fig} re-made as a top view of x ∈ {}…{}, y ∈ {}…{}, \
                 {}×{} pixels; the {w} × {h} light stands along the bottom edge, x ∈ {}…{}). \
                 Top left: the exact irradiance (Lambert's formula). Each further row one light sampler \
                 ({names}): its estimate at {spp} jittered samples per pixel on the same viridis scale, then the \
                 signed error Ê − E on a blue–white–red scale symmetric about 0 (±{}, the 99th percentile of \
                 |Ê − E| over the error panels; larger errors saturate){note}",
                gx.0,
                gx.1,
                gy.0,
                gy.1,
                g.grid.cols,
                g.grid.rows,
                -self.config.ground.width / 2.0,
                self.config.ground.width / 2.0,
                sci(bound),
                w = self.config.ground.width,
                h = self.config.ground.height,
                note = if mis {
                    ""
                } else {
                    ". Area sampling's errors concentrate at the light's foot; the projected polygon's \
                     estimate is exact up to rounding (a zero-variance estimator)"
                },
                how = if mis {
                    "each light sample combined with one cosine sample by MIS (balance heuristic)"
                } else {
                    "light sampling alone"
                },
            );
            out.push(f);
        }
        let (grid, bound) = self.triptych_grid();
        let t = &self.config.triptych;
        let mut f = figures::write_image_grid_png(&dir.join(TRIPTYCH_FIGURE), &grid)?;
        f.title = format!(
            "Ureña 2000, Fig. 9 re-made: irradiance on the ground under the vertical triangle light with a \
             {c} × {c} radiance pattern, occluders removed as in the paper, top view of x ∈ {}…{}, y ∈ {}…{} \
             ({}×{} pixels), at {n} samples per pixel. Top row: the exact irradiance, then unstratified \
             solid-angle sampling (P ∝ σ, the paper's top image), stratified solid-angle sampling with \
             {s} × {s} strata (middle), adaptive sampling with K = 0.1 (ours) and K = 0.001 (the paper's \
             bottom image), all on one viridis scale; bottom row: their signed errors Ê − E on one \
             blue–white–red scale symmetric about 0 (±{}, the 99th percentile of |Ê − E|)",
            self.triptych.grid.x.0,
            self.triptych.grid.x.1,
            self.triptych.grid.y.0,
            self.triptych.grid.y.1,
            self.triptych.grid.cols,
            self.triptych.grid.rows,
            sci(bound),
            c = t.cells,
            n = t.spp,
            s = crate::estimator::grid_columns(t.spp),
        );
        out.push(f);
        Ok(out)
    }

    /// Writes `images_errors.csv` (figure, method, spp, image and
    /// per-pixel relative RMS error, failed pixels) into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<std::path::PathBuf> {
        let mut t =
            String::from("figure,method,spp,image_relative_rms,pixel_relative_rms,failed_pixels\n");
        let g = &self.ground;
        for (file, methods, images) in [
            (GROUND_FIGURE, &g.plain, &g.plain_images),
            (GROUND_MIS_FIGURE, &g.mis, &g.mis_images),
        ] {
            for (m, row) in methods.iter().zip(images) {
                for im in row {
                    let (a, b) = im.rms_errors(&g.reference);
                    let _ = writeln!(
                        t,
                        "{file},{},{},{a:e},{b:e},{}",
                        m.name(),
                        im.spp,
                        im.failed
                    );
                }
            }
        }
        let tr = &self.triptych;
        for im in &tr.images {
            let (a, b) = im.rms_errors(&tr.reference);
            let name = im.label.rsplit_once(',').map_or(im.label.as_str(), |p| p.0);
            let _ = writeln!(
                t,
                "{TRIPTYCH_FIGURE},\"{name}\",{},{a:e},{b:e},{}",
                im.spp, im.failed
            );
        }
        std::fs::create_dir_all(dir)?;
        let path = dir.join(ERRORS_CSV);
        std::fs::write(&path, t)?;
        Ok(path)
    }

    /// The Ureña–Fajardo–King images as a Markdown subsection: what they
    /// show, the per-image error table (both metrics) and the two figures.
    pub fn ground_markdown(&self) -> String {
        let g = &self.ground;
        let c = &self.config.ground;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "### Rendered images (Ureña, Fajardo & King 2013, Fig. 4 and 6)\n\n\
             The scene of the tables above seen from above: {}×{} pixels over x ∈ {}…{}, y ∈ {}…{} of the ground, \
             one receiver at each pixel centre, the {w} × {h} light standing along the image's bottom edge. Each \
             pixel is one estimate with the study's estimators and jittered points ({spp} spp; MIS: as many cosine \
             samples again), all methods at a pixel seeing the same points; the reference is exact. The table gives \
             each image's error under the two metrics of the study: *image* √(Σ(Ê − E)²)/√(ΣE²) over the pixels, \
             and *per pixel* √(mean((Ê − E)/E)²) — the per-receiver metric of the tables above, over a uniform \
             grid instead of receivers concentrated at the light's foot. Errors per image: `{ERRORS_CSV}`; \
             rendered in {:.1} s together with the triptych of Ureña 2000.\n",
            g.grid.cols,
            g.grid.rows,
            g.grid.x.0,
            g.grid.x.1,
            g.grid.y.0,
            g.grid.y.1,
            self.elapsed_seconds,
            w = c.width,
            h = c.height,
            spp = spp_list(&c.spp),
        );
        let _ = write!(s, "| method |");
        for n in &c.spp {
            let _ = write!(s, " {n} spp: image | {n} spp: per pixel |");
        }
        let _ = writeln!(s);
        let _ = writeln!(s, "|---|{}", "---:|---:|".repeat(c.spp.len()));
        for (methods, images) in [(&g.plain, &g.plain_images), (&g.mis, &g.mis_images)] {
            for (m, row) in methods.iter().zip(images) {
                let _ = write!(s, "| {} |", m.name());
                for im in row {
                    let (a, b) = im.rms_errors(&g.reference);
                    let _ = write!(s, " {} | {} |", sci(a), sci(b));
                }
                let _ = writeln!(s);
            }
        }
        let failed: usize = g
            .plain_images
            .iter()
            .chain(&g.mis_images)
            .flatten()
            .map(|im| im.failed)
            .sum();
        if failed > 0 {
            let _ = writeln!(
                s,
                "\n{failed} pixel estimates failed (a method could not be built there); they are drawn grey."
            );
        }
        let _ = writeln!(
            s,
            "\n![Rendered images, light sampling alone]({GROUND_FIGURE})\n\n\
             ![Rendered images, light sampling with MIS]({GROUND_MIS_FIGURE})\n"
        );
        s
    }

    /// The Ureña 2000 triptych as a Markdown subsection: the error table
    /// at 36 spp and the figure.
    pub fn triptych_markdown(&self) -> String {
        let t = &self.triptych;
        let c = &self.config.triptych;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "### Rendered images at {n} spp (Ureña 2000, Fig. 9)\n\n\
             The paper's Fig. 9 shows the irradiance on the receiver \"as seen from the top, with the occluders \
             removed\" at {n} samples per pixel: P ∝ σ (top), stratified with 6 × 6 strata (middle), adaptive with \
             K = 0.001 (bottom). Re-made on the scene of the table above ({c} × {c} pattern, occluders removed), \
             {}×{} pixels over x ∈ {}…{}, y ∈ {}…{} (the rectangle of its receivers), with the study's estimators \
             and adaptive K = 0.1 added; the reference is exact (Lambert's formula per pattern cell). Errors of each \
             image, both metrics (as in the table above), and the ratio to stratified solid angle:\n",
            t.grid.cols,
            t.grid.rows,
            t.grid.x.0,
            t.grid.x.1,
            t.grid.y.0,
            t.grid.y.1,
            n = c.spp,
            c = c.cells,
        );
        let _ = writeln!(
            s,
            "| method | image rel. RMS | per-pixel rel. RMS | image / stratified | per pixel / stratified |\n|---|---:|---:|---:|---:|"
        );
        let errs: Vec<(f64, f64)> = t
            .images
            .iter()
            .map(|im| im.rms_errors(&t.reference))
            .collect();
        let base = errs.get(1).copied().unwrap_or((f64::NAN, f64::NAN));
        for (im, (a, b)) in t.images.iter().zip(&errs) {
            let name = im.label.rsplit_once(',').map_or(im.label.as_str(), |p| p.0);
            let _ = writeln!(
                s,
                "| {name} | {} | {} | {:.3} | {:.3} |",
                sci(*a),
                sci(*b),
                a / base.0,
                b / base.1
            );
        }
        let _ = writeln!(
            s,
            "\nOne image per method: the ratios are of one render each (about {} pixels), not averages over runs; the \
             table above gives the same comparison over 16 runs with intervals.\n\n\
             ![Ureña 2000, Fig. 9 re-made]({TRIPTYCH_FIGURE})\n",
            t.grid.len()
        );
        s
    }
}

/// `1, 4 and 16`.
fn spp_list(spp: &[usize]) -> String {
    let v: Vec<String> = spp.iter().map(|n| n.to_string()).collect();
    match v.len() {
        0 => String::new(),
        1 => v[0].clone(),
        k => format!("{} and {}", v[..k - 1].join(", "), v[k - 1]),
    }
}
