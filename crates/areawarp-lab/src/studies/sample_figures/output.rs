//! The figures, CSV file and Markdown of the sample-distribution study.

use super::*;
use crate::verdict::chi2_p_value;

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

pub(crate) const OUTLINE: Rgb = Rgb(40, 40, 40);
pub(crate) const SAMPLES: Rgb = PALETTE[0];
/// A light red, so that the samples stay visible over the grid.
pub(crate) const GRID: Rgb = Rgb(236, 128, 128);
pub(crate) const SQUARE: (u32, u32) = (600, 600);
pub(crate) const WIDE: (u32, u32) = (760, 480);

/// A CSV field, quoted (with doubled quotes) if it holds a comma, a quote
/// or a line break.
pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A series of separate dots for [`figures::write_line_plot_svg`]: the
/// points separated by NaN, so that no line joins them.
pub(crate) fn dots(label: &str, pts: &[(f64, f64)], color: Rgb) -> Series {
    let mut v = Vec::with_capacity(2 * pts.len());
    for &p in pts {
        v.push(p);
        v.push((f64::NAN, f64::NAN));
    }
    Series::new(label, v).with_color(color)
}

/// A line (no markers).
pub(crate) fn line(label: &str, pts: Vec<(f64, f64)>, color: Rgb) -> Series {
    let mut s = Series::new(label, pts).with_color(color);
    s.markers = false;
    s
}

/// The points of a polyline at spacing at most `step` (for rasters, where
/// lines are drawn as dense dots).
pub(crate) fn densify(pts: &[(f64, f64)], step: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let k = ((len / step).ceil() as usize).clamp(1, 100_000);
        for i in 0..k {
            let t = i as f64 / k as f64;
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    if let Some(last) = pts.last() {
        out.push(*last);
    }
    out
}

/// A labelled set of points in one colour (a line or a set of dots).
pub(crate) type Layer = (String, Vec<(f64, f64)>, Rgb);

/// One drawing: lines (outline, grid) and dot sets, written as SVG (line
/// plot with separated markers, `size` pixels) and PNG (no text, 4/5 of
/// the size; dots as small discs, lines as dense dots).
pub(crate) struct Drawing {
    pub(crate) title: String,
    pub(crate) x: String,
    pub(crate) y: String,
    pub(crate) size: (u32, u32),
    pub(crate) lines: Vec<Layer>,
    pub(crate) dots: Vec<Layer>,
}

impl Drawing {
    pub(crate) fn write(&self, dir: &Path, stem: &str) -> io::Result<Vec<Figure>> {
        let mut plot = Plot::new(&self.title, Axis::linear(&self.x), Axis::linear(&self.y))
            .size(self.size.0, self.size.1)
            .equal_aspect()
            .point_radius(2.5);
        for (label, pts, color) in &self.lines {
            plot = plot.series(line(label, pts.clone(), *color));
        }
        for (label, pts, color) in &self.dots {
            plot = plot.series(dots(label, pts, *color));
        }
        let svg = figures::write_line_plot_svg(&dir.join(format!("{stem}.svg")), &plot)?;
        // Raster: data units per pixel (equal aspect, the axes' 4% padding).
        let (w, h) = (self.size.0 * 4 / 5, self.size.1 * 4 / 5);
        let all = self
            .lines
            .iter()
            .flat_map(|l| l.1.iter())
            .chain(self.dots.iter().flat_map(|d| d.1.iter()));
        let (lo, hi) = all.fold(
            (
                (f64::INFINITY, f64::INFINITY),
                (f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(lo, hi), p| {
                (
                    (lo.0.min(p.0), lo.1.min(p.1)),
                    (hi.0.max(p.0), hi.1.max(p.1)),
                )
            },
        );
        let per_px = ((hi.0 - lo.0) / (w as f64 - 16.0))
            .max((hi.1 - lo.1) / (h as f64 - 16.0))
            .max(f64::MIN_POSITIVE)
            * 1.08;
        let mut raster = Plot::new(&self.title, Axis::linear(""), Axis::linear(""))
            .size(w, h)
            .equal_aspect()
            .point_radius(0.8);
        // Lines: dots a third of a pixel apart.
        for (label, pts, color) in &self.lines {
            raster =
                raster.series(Series::new(label, densify(pts, per_px / 3.0)).with_color(*color));
        }
        // Samples: discs of radius ≈ 2 px, as 9 dots each.
        let r = 1.3 * per_px;
        let d = r / std::f64::consts::SQRT_2;
        for (label, pts, color) in &self.dots {
            let disc: Vec<(f64, f64)> = pts
                .iter()
                .flat_map(|&(x, y)| {
                    [
                        (0.0, 0.0),
                        (r, 0.0),
                        (-r, 0.0),
                        (0.0, r),
                        (0.0, -r),
                        (d, d),
                        (d, -d),
                        (-d, d),
                        (-d, -d),
                    ]
                    .map(|(dx, dy)| (x + dx, y + dy))
                })
                .collect();
            raster = raster.series(Series::new(label, disc).with_color(*color));
        }
        let png = figures::write_scatter_png(&dir.join(format!("{stem}.png")), &raster)?;
        Ok(vec![svg, png])
    }
}

impl SampleFigures {
    /// The file names [`SampleFigures::write_figures`] writes, in order
    /// (each as `.svg` and `.png`).
    pub fn figure_stems() -> [&'static str; 7] {
        [
            "samples_spherical_triangle_random",
            "samples_spherical_triangle_jittered",
            "samples_projected_polygon_random",
            "samples_projected_polygon_jittered",
            "samples_spherical_rectangle_directions",
            "samples_spherical_rectangle_points",
            "samples_spherical_rectangle_area",
        ]
    }

    /// Writes the figures into `dir` (created if needed), each as SVG (with
    /// axes) and PNG (no text): the triangle with random and with jittered
    /// samples (equal-area projection about its centroid direction), the
    /// comb polygon with random and jittered cosine-weighted samples (the
    /// receiver's plane), and the rectangle's Hammersley samples as
    /// directions (equal-area projection) and as points on the rectangle,
    /// with the equal-solid-angle grid, plus area sampling of the same
    /// points for contrast. Names: [`SampleFigures::figure_stems`].
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        let [s1, s2, s3, s4, s5, s6, s7] = Self::figure_stems();

        // 1. The triangle.
        let t = &self.triangle;
        let proj = EqualArea::about(&t.centre, &v3(1.0, 0.0, 0.0));
        let tri_outline: Vec<(f64, f64)> = outline(&t.vertices, 128)
            .iter()
            .map(|d| proj.project(d))
            .collect();
        let axis_x = "equal-area projection about the centroid direction, seen from the centre";
        let axis_y = "";
        for (stem, name, set) in [
            (s1, "uniform random", &t.random),
            (s2, "jittered", &t.jittered),
        ] {
            let pts: Vec<(f64, f64)> = set.iter().map(|d| proj.project(d)).collect();
            let d = Drawing {
                title: format!(
                    "{} {name} samples on a spherical triangle (Ω = {:.2} sr)",
                    set.len(),
                    t.solid_angle
                ),
                x: axis_x.into(),
                y: axis_y.into(),
                size: SQUARE,
                lines: vec![(String::new(), tri_outline.clone(), OUTLINE)],
                dots: vec![(String::new(), pts, SAMPLES)],
            };
            out.extend(d.write(dir, stem)?);
        }

        // 2. The polygon, in the receiver's plane.
        let p = &self.polygon;
        let corners: Vec<Vec3<f64>> = p.vertices.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
        let poly_outline: Vec<(f64, f64)> =
            outline(&corners, 128).iter().map(|d| (d.x, d.y)).collect();
        let horizon: Vec<(f64, f64)> = (0..=256)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 256.0;
                (a.cos(), a.sin())
            })
            .collect();
        for (stem, name, set) in [
            (s3, "uniform random", &p.random),
            (s4, "jittered", &p.jittered),
        ] {
            let pts: Vec<(f64, f64)> = set.iter().map(|d| (d.x, d.y)).collect();
            let d = Drawing {
                title: format!(
                    "{} {name} cosine-weighted samples in a non-convex polygon",
                    set.len()
                ),
                x: "x = sin θ cos φ (receiver's plane)".into(),
                y: "y = sin θ sin φ".into(),
                size: SQUARE,
                lines: vec![
                    ("horizon".into(), horizon.clone(), PALETTE[7]),
                    ("polygon".into(), poly_outline.clone(), OUTLINE),
                ],
                dots: vec![(String::new(), pts, SAMPLES)],
            };
            out.extend(d.write(dir, stem)?);
        }

        // 3. The rectangle: directions, points on it, area sampling.
        let r = &self.rectangle;
        let centre = r
            .corner
            .add(&r.edge_x.scale(&0.5))
            .add(&r.edge_y.scale(&0.5))
            .sub(&r.observer);
        let proj = EqualArea::about(&centre, &r.edge_x);
        let corners = [
            r.corner,
            r.corner.add(&r.edge_x),
            r.corner.add(&r.edge_x).add(&r.edge_y),
            r.corner.add(&r.edge_y),
        ];
        let rel: Vec<Vec3<f64>> = corners.iter().map(|c| c.sub(&r.observer)).collect();
        let dir_outline: Vec<(f64, f64)> =
            outline(&rel, 128).iter().map(|d| proj.project(d)).collect();
        let grid_label = format!("{0} × {0} cells of equal solid angle", r.grid);
        let grid_dirs: Vec<Layer> = r
            .grid_lines
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let label = if i == 0 {
                    grid_label.clone()
                } else {
                    String::new()
                };
                let pts = l
                    .iter()
                    .map(|p| proj.project(&p.sub(&r.observer)))
                    .collect();
                (label, pts, GRID)
            })
            .collect();
        // On the rectangle a legend would cover the observer's foot: the
        // axis label explains the colours instead.
        let grid_flat_label =
            format!("x along e_x    (red: {grid_label}; orange: the observer's foot)");
        let mut lines = grid_dirs;
        lines.push(("spherical rectangle".into(), dir_outline, OUTLINE));
        let d = Drawing {
            title: format!(
                "{} Hammersley points mapped to a spherical rectangle (Ω = {:.3} sr)",
                r.directions.len(),
                r.solid_angle
            ),
            x: "equal-area projection about the centre's direction, seen from the observer".into(),
            y: String::new(),
            size: WIDE,
            lines,
            dots: vec![(
                String::new(),
                r.directions.iter().map(|d| proj.project(d)).collect(),
                SAMPLES,
            )],
        };
        out.extend(d.write(dir, s5)?);
        let xhat = unit(&r.edge_x);
        let yhat = unit(&r.edge_y);
        let flat = |p: &Vec3<f64>| {
            let q = p.sub(&r.corner);
            (q.dot(&xhat), q.dot(&yhat))
        };
        let grid_flat: Vec<Layer> = r
            .grid_lines
            .iter()
            .map(|l| (String::new(), l.iter().map(flat).collect(), GRID))
            .collect();
        let foot = flat(&r.observer);
        for (stem, title, set) in [
            (
                s6,
                format!(
                    "{} Hammersley points, solid-angle sampling, pulled back to the rectangle",
                    r.points.len()
                ),
                &r.points,
            ),
            (
                s7,
                format!(
                    "the same {} points, area sampling, on the rectangle",
                    r.area_points.len()
                ),
                &r.area_points,
            ),
        ] {
            let d = Drawing {
                title,
                x: grid_flat_label.clone(),
                y: "y along e_y (away from the observer)".into(),
                size: SQUARE,
                lines: grid_flat.clone(),
                dots: vec![
                    (String::new(), set.iter().map(flat).collect(), SAMPLES),
                    (String::new(), vec![foot], PALETTE[1]),
                ],
            };
            out.extend(d.write(dir, stem)?);
        }
        Ok(out)
    }

    /// Writes `sample_figures.csv` (figure, quantity, measured, reference:
    /// the numbers of the Markdown tables) into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut s = String::from("figure,quantity,measured,reference\n");
        for (fig, q, m, r) in self.rows() {
            let _ = writeln!(
                s,
                "{},{},{},{}",
                csv_field(fig),
                csv_field(&q),
                csv_field(&m),
                csv_field(&r)
            );
        }
        let path = dir.join("sample_figures.csv");
        std::fs::write(&path, s)?;
        Ok(vec![path])
    }

    /// The measured numbers: (figure, quantity, measured, reference), the
    /// reference empty where there is none.
    pub(crate) fn rows(&self) -> Vec<(&'static str, String, String, String)> {
        let t = &self.triangle;
        let p = &self.polygon;
        let r = &self.rectangle;
        let g = |x: f64| format!("{x:.4}");
        let range = |(a, b): (usize, usize)| format!("{a}-{b}");
        let m_t = t.measure_samples;
        let m_p = p.measure_samples;
        let n_r = r.points.len() as f64;
        let tri_cells = t.cell_solid_angles.len();
        let poly_cells = p.cell_fractions.len();
        vec![
            (
                "triangle",
                "solid angle (sr); reference: sum over the sub-triangles".into(),
                g(t.solid_angle),
                g(t.cell_solid_angles.iter().sum()),
            ),
            (
                "triangle",
                format!("chi2 over {tri_cells} sub-triangles, {m_t} uniform random; reference: degrees of freedom"),
                g(t.random_chi2),
                (tri_cells - 1).to_string(),
            ),
            (
                "triangle",
                format!("chi2 over {tri_cells} sub-triangles, {m_t} jittered"),
                g(t.jittered_chi2),
                String::new(),
            ),
            (
                "triangle",
                "samples per sub-triangle (min-max), uniform random; reference: expected".into(),
                range(min_max(&t.random_counts)),
                expected_range(&t.cell_solid_angles, m_t),
            ),
            (
                "triangle",
                "samples per sub-triangle (min-max), jittered; reference: expected".into(),
                range(min_max(&t.jittered_counts)),
                expected_range(&t.cell_solid_angles, m_t),
            ),
            (
                "triangle",
                "largest outside_by".into(),
                format!("{:e}", t.max_outside_by),
                String::new(),
            ),
            (
                "polygon",
                "projected solid angle (sr); reference: Lambert's formula".into(),
                g(p.projected_solid_angle),
                g(plane_measures(&p.vertices).1),
            ),
            (
                "polygon",
                "drawn samples inside the polygon, uniform random".into(),
                p.random_inside.to_string(),
                p.random.len().to_string(),
            ),
            (
                "polygon",
                "drawn samples inside the polygon, jittered".into(),
                p.jittered_inside.to_string(),
                p.jittered.len().to_string(),
            ),
            (
                "polygon",
                "measured samples inside the polygon, both sets".into(),
                p.measure_inside.to_string(),
                (2 * m_p).to_string(),
            ),
            (
                "polygon",
                format!("chi2 over {poly_cells} cells vs cosine-weighted, {m_p} uniform random; reference: degrees of freedom"),
                g(p.random_chi2),
                (poly_cells - 1).to_string(),
            ),
            (
                "polygon",
                format!("chi2 over {poly_cells} cells vs cosine-weighted, {m_p} jittered"),
                g(p.jittered_chi2),
                String::new(),
            ),
            (
                "polygon",
                format!("chi2 over {poly_cells} cells vs uniform in solid angle, {m_p} jittered"),
                g(p.jittered_chi2_uniform),
                String::new(),
            ),
            (
                "polygon",
                "largest outside_by".into(),
                format!("{:e}", p.max_outside_by),
                String::new(),
            ),
            (
                "rectangle",
                "solid angle (sr); reference: two triangles".into(),
                g(r.solid_angle),
                g(r.solid_angle_triangles),
            ),
            (
                "rectangle",
                "samples per equal-solid-angle cell (min-max), solid-angle sampling".into(),
                range(r.solid_angle_cells),
                "1-1".into(),
            ),
            (
                "rectangle",
                "samples per equal-solid-angle cell (min-max), area sampling".into(),
                range(r.area_cells),
                "1-1".into(),
            ),
            (
                "rectangle",
                "empty equal-solid-angle cells, area sampling".into(),
                r.area_empty_cells.to_string(),
                "0".into(),
            ),
            (
                "rectangle",
                "samples in the near quarter, solid-angle sampling; reference: N x solid-angle fraction".into(),
                r.near_count.to_string(),
                g(r.near_fraction_exact * n_r),
            ),
            (
                "rectangle",
                "samples in the far quarter, solid-angle sampling; reference: N x solid-angle fraction".into(),
                r.far_count.to_string(),
                g(r.far_fraction_exact * n_r),
            ),
            (
                "rectangle",
                "samples in the near quarter, area sampling; reference: N x solid-angle fraction".into(),
                r.area_near_count.to_string(),
                g(r.near_fraction_exact * n_r),
            ),
            (
                "rectangle",
                "samples in the far quarter, area sampling; reference: N x solid-angle fraction".into(),
                r.area_far_count.to_string(),
                g(r.far_fraction_exact * n_r),
            ),
        ]
    }

    /// The report section (Markdown): per figure a caption (what the
    /// paper's figure showed, what ours shows), the SVG figures shown by
    /// file name (they sit beside the Markdown file, PNG versions linked)
    /// and the measured numbers.
    pub fn to_markdown(&self) -> String {
        let (first, rectangle) = self.markdown_parts();
        first + &rectangle
    }

    /// [`SampleFigures::to_markdown`] in two parts: the introduction with
    /// the triangle's and the polygon's figures (Arvo 1995, 2001), and the
    /// rectangle's figure (Ureña, Fajardo & King 2013, Fig. 5), which the
    /// report shows in that paper's section.
    pub fn markdown_parts(&self) -> (String, String) {
        let t = &self.triangle;
        let p = &self.polygon;
        let r = &self.rectangle;
        let mut s = String::new();
        let png_links = |stems: &[&str]| -> String {
            stems
                .iter()
                .map(|st| format!("[{st}.png]({st}.png)"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let _ = writeln!(
            s,
            "## Sample distributions: the papers' figures, re-made from our maps\n"
        );
        let _ = writeln!(
            s,
            "Each figure is drawn with the crate's maps in f64, and each comes with a number \
             that the picture alone does not give. Directions are shown either in the Lambert azimuthal \
             equal-area projection, which preserves area, so uniform directions look uniform, or, for \
             cosine-weighted samples, in the receiver's plane, where by Nusselt's analogy cosine-weighted \
             directions are uniform. Both views are as seen from the centre of the sphere. The triangle's and \
             the polygon's counting measures compare counts in cells of exactly known measure with their \
             expectations and do not use the map being tested; the rectangle's cells are the map's own \
             images of a grid, and its near and far quarters are checked against solid angles computed \
             independently. Data: `sample_figures.csv`.\n"
        );

        // 1.
        let k = self.config.strata;
        let n = t.random.len();
        let m = t.measure_samples;
        let cells = t.cell_solid_angles.len();
        let _ = writeln!(
            s,
            "### Uniform and jittered samples on a spherical triangle (Arvo 1995, Fig. 2; Arvo 2001, Fig. 1.1)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** samples of a spherical triangle from Arvo's area-preserving map. On the left, \
             independent uniform (u, v) give the pattern of rejection sampling, but every sample lies in the \
             triangle. On the right, jittered (u, v), one per cell of a grid on the unit square, give \
             visibly more even samples. **Ours:** the same experiment with `SphericalTriangle` (robust \
             variant) on a triangle of Ω = {omega:.3} sr, with {n} samples in each panel ({k} × {k} strata), \
             in the equal-area projection about the triangle's centroid direction. **Measured:** the \
             triangle is cut into {cells} sub-triangles by {levels} level(s) of midpoint subdivision, with \
             exact Ω_i (Van Oosterom–Strackee). Counts from {m} fresh samples of each kind are compared \
             with M Ω_i / Ω. For independent uniform samples χ² is about its {dof} degrees of freedom. \
             For jittered samples it is far smaller, because only the strata that a sub-triangle's edges \
             cut contribute.\n",
            omega = t.solid_angle,
            levels = self.config.triangle_levels,
            dof = cells - 1,
        );
        let _ = writeln!(
            s,
            "| uniform random | jittered |\n|---|---|\n\
             | ![uniform random samples on a spherical triangle](samples_spherical_triangle_random.svg) \
             | ![jittered samples on a spherical triangle](samples_spherical_triangle_jittered.svg) |\n"
        );
        let (rmin, rmax) = min_max(&t.random_counts);
        let (jmin, jmax) = min_max(&t.jittered_counts);
        let _ = writeln!(
            s,
            "| {m} samples | χ² over {cells} sub-triangles ({dof} d.o.f.) | p = P(χ² ≥ value) | P(χ² ≤ value) | samples per sub-triangle (expected {exp}) |\n\
             |---|---:|---:|---:|---:|\n\
             | uniform random | {:.2} | {:.3} | {:.3} | {rmin}–{rmax} |\n\
             | jittered | {:.2} | {:.3} | {:.1e} | {jmin}–{jmax} |\n\n\
             *p*: the probability of a χ² at least this large if the samples were independent and uniform (small p: \
             not uniform); *P(χ² ≤ value)*: the probability of one at most this small (tiny for jittered samples: \
             more even than independent ones, as stratification makes them).\n",
            t.random_chi2,
            chi2_p_value(t.random_chi2, (cells - 1) as f64),
            1.0 - chi2_p_value(t.random_chi2, (cells - 1) as f64),
            t.jittered_chi2,
            chi2_p_value(t.jittered_chi2, (cells - 1) as f64),
            1.0 - chi2_p_value(t.jittered_chi2, (cells - 1) as f64),
            dof = cells - 1,
            exp = expected_range(&t.cell_solid_angles, m).replace('-', "–"),
        );
        let _ = writeln!(
            s,
            "PNG: {}.\n",
            png_links(&[
                "samples_spherical_triangle_random",
                "samples_spherical_triangle_jittered"
            ])
        );

        // 2.
        let n = p.random.len();
        let m = p.measure_samples;
        let cells = p.cell_fractions.len();
        let _ = writeln!(
            s,
            "### Cosine-weighted samples in a non-convex polygon (Arvo 2001, Fig. 1.2 and 1.11)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** a projected spherical polygon with uniform and with stratified samples, which \
             crowd towards the pole and thin out towards the horizon, and a non-convex spherical polygon \
             with cosine-weighted samples from Arvo's map. **Ours:** `ProjectedPolygon` of a comb-shaped \
             light with three teeth in the plane z = 1. The receiver is at the origin with normal +z; \
             Π = {pi:.4} and Ω = {omega:.4} sr. Each panel shows {n} samples, from uniform random and \
             from jittered (u, v), in the receiver's plane (x, y of the direction), with the polygon's \
             outline (projected great arcs) and the horizon. **Measured:** every sample's ray meets the \
             light's plane inside the comb, by an even–odd test that does not use the map: {ri} and {ji} \
             of the {n} drawn samples, and {mi} of the {mm} measured samples. For uniformity, the light's \
             plane is cut into squares of side {cell}. Lines in that plane are great circles, so each \
             square's part of the comb is a spherical polygon with an exact Ω_i and, by Lambert's formula, \
             an exact Π_i. The counts of {m} fresh samples of each kind are compared with M Π_i / Π by \
             χ² over {cells} cells; cells expecting fewer than 5 samples are pooled. The same jittered \
             counts give χ² = {cu:.1} against the expectation for samples uniform in solid angle, \
             M Ω_i / Ω, so the measure does detect the cosine weighting.\n",
            pi = p.projected_solid_angle,
            omega = p.solid_angle,
            ri = p.random_inside,
            ji = p.jittered_inside,
            mi = p.measure_inside,
            mm = 2 * m,
            cell = p.cell,
            cu = p.jittered_chi2_uniform,
        );
        let _ = writeln!(
            s,
            "| uniform random | jittered |\n|---|---|\n\
             | ![uniform random cosine-weighted samples in a non-convex polygon](samples_projected_polygon_random.svg) \
             | ![jittered cosine-weighted samples in a non-convex polygon](samples_projected_polygon_jittered.svg) |\n"
        );
        let _ = writeln!(
            s,
            "| {m} samples | χ² vs cosine-weighted, M Π_i/Π ({dof} d.o.f.) | p = P(χ² ≥ value) | χ² vs uniform in solid angle, M Ω_i/Ω | its p |\n\
             |---|---:|---:|---:|---:|\n\
             | uniform random | {:.2} | {:.3} | {:.1} | {:.1e} |\n\
             | jittered | {:.2} | {:.3} | {:.1} | {:.1e} |\n",
            p.random_chi2,
            chi2_p_value(p.random_chi2, (cells - 1) as f64),
            chi_square(&p.random_counts, &p.cell_fractions_uniform),
            chi2_p_value(
                chi_square(&p.random_counts, &p.cell_fractions_uniform),
                (cells - 1) as f64
            ),
            p.jittered_chi2,
            chi2_p_value(p.jittered_chi2, (cells - 1) as f64),
            p.jittered_chi2_uniform,
            chi2_p_value(p.jittered_chi2_uniform, (cells - 1) as f64),
            dof = cells - 1,
        );
        let _ = writeln!(
            s,
            "PNG: {}.\n",
            png_links(&[
                "samples_projected_polygon_random",
                "samples_projected_polygon_jittered"
            ])
        );

        // 3.
        let first = std::mem::take(&mut s);
        let n = r.points.len();
        let _ = writeln!(
            s,
            "### Hammersley points on a spherical rectangle, and pulled back to the rectangle (Ureña, Fajardo & King 2013, Fig. 5)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** 256 Hammersley points mapped to a spherical rectangle by several mappings and \
             projected back onto the planar rectangle, with a superimposed red grid whose cells all subtend \
             the same solid angle. With the solid-angle map the points follow the grid, crowding towards \
             the observer. **Ours:** `SphericalRectangle` of a 2 × 2 rectangle on the ground, seen from \
             0.5 above a point 0.25 before its near edge (Ω = {omega:.4} sr; {omega2:.4} sr as two \
             triangles). The {n} Hammersley points are moved to the centres of their 1/{n} cells, which \
             keeps them a net. The panels show the {k} × {k} grid of equal-solid-angle cells (the images \
             of u = i/{k} and v = j/{k}), the directions (equal-area projection), the points pulled back to \
             the rectangle, and, for contrast, area sampling of the same points. **Measured:** the number \
             of samples per equal-solid-angle cell, and the samples in the near and the far quarter of \
             the rectangle against the exact solid-angle fractions, computed as two triangles each.\n",
            omega = r.solid_angle,
            omega2 = r.solid_angle_triangles,
            k = r.grid,
        );
        let _ = writeln!(
            s,
            "| directions | pulled back to the rectangle | area sampling |\n|---|---|---|\n\
             | ![Hammersley points on a spherical rectangle](samples_spherical_rectangle_directions.svg) \
             | ![the same points pulled back to the rectangle](samples_spherical_rectangle_points.svg) \
             | ![area sampling of the same points](samples_spherical_rectangle_area.svg) |\n"
        );
        let near = r.near_fraction_exact * n as f64;
        let far = r.far_fraction_exact * n as f64;
        let _ = writeln!(
            s,
            "| {n} Hammersley points | samples per cell (min–max) | empty cells | near quarter (exact {near:.1}) | far quarter (exact {far:.1}) |\n\
             |---|---:|---:|---:|---:|\n\
             | solid-angle sampling (ours) | {}–{} | {} | {} | {} |\n\
             | area sampling | {}–{} | {} | {} | {} |\n",
            r.solid_angle_cells.0,
            r.solid_angle_cells.1,
            r.solid_angle_empty_cells,
            r.near_count,
            r.far_count,
            r.area_cells.0,
            r.area_cells.1,
            r.area_empty_cells,
            r.area_near_count,
            r.area_far_count,
        );
        let _ = writeln!(
            s,
            "The near quarter of the rectangle subtends {:.1}% of the solid angle and the far quarter \
             {:.1}%. Solid-angle sampling puts {} and {} of the {n} points there; area sampling puts {} \
             and {}. PNG: {}.\n",
            100.0 * r.near_fraction_exact,
            100.0 * r.far_fraction_exact,
            r.near_count,
            r.far_count,
            r.area_near_count,
            r.area_far_count,
            png_links(&[
                "samples_spherical_rectangle_directions",
                "samples_spherical_rectangle_points",
                "samples_spherical_rectangle_area"
            ])
        );
        (first, s)
    }
}
