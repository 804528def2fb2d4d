//! Grids of false-colour images (rendered irradiance, signed errors) with
//! shared colour scales: every panel framed by axes with ticks, titled, and
//! one colour bar per scale beside the grid. Drawn with plotters' bitmap
//! back end (each panel's pixels blitted as one [`BitMapElement`]) and
//! encoded by the `png` crate.

use super::draw::{FONT, color, err, register_font, render_png, tick_label, title_size};
use super::{Axis, Figure, MISSING, Rgb, invalid, viridis, write_file};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::io;
use std::path::Path;

/// ColorBrewer's RdBu control points, blue (negative) to red (positive)
/// through a near-white middle.
const DIVERGING: [(u8, u8, u8); 11] = [
    (5, 48, 97),
    (33, 102, 172),
    (67, 147, 195),
    (146, 197, 222),
    (209, 229, 240),
    (247, 247, 247),
    (253, 219, 199),
    (244, 165, 130),
    (214, 96, 77),
    (178, 24, 43),
    (103, 0, 31),
];

/// The diverging colour map at `t ∈ [0, 1]` (clamped; NaN gives
/// [`MISSING`]): dark blue at 0, near white at ½, dark red at 1, symmetric
/// in lightness about ½.
pub fn diverging(t: f64) -> Rgb {
    if t.is_nan() {
        return MISSING;
    }
    let t = t.clamp(0.0, 1.0) * 10.0;
    let i = (t.floor() as usize).min(9);
    let f = t - i as f64;
    let (a, b) = (DIVERGING[i], DIVERGING[i + 1]);
    let mix = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * f).round() as u8;
    Rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A colour map of an image panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorMap {
    /// [`viridis`]: for values (irradiance).
    Sequential,
    /// [`diverging`]: for signed values (errors); give it a range
    /// symmetric about 0 so that white means 0.
    Diverging,
}

/// A colour scale shared by several panels: a map, a fixed value range
/// (values outside are clamped to the ends) and the colour bar's label.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorScale {
    /// The colour bar's label.
    pub label: String,
    /// The colour map.
    pub map: ColorMap,
    /// `(low, high)`, `low < high`.
    pub range: (f64, f64),
}

impl ColorScale {
    /// A sequential scale over `[low, high]`.
    pub fn sequential(label: &str, low: f64, high: f64) -> Self {
        ColorScale {
            label: label.to_string(),
            map: ColorMap::Sequential,
            range: (low, high),
        }
    }

    /// A diverging scale over `[−bound, bound]`.
    pub fn symmetric(label: &str, bound: f64) -> Self {
        ColorScale {
            label: label.to_string(),
            map: ColorMap::Diverging,
            range: (-bound, bound),
        }
    }

    /// The colour of `v` (non-finite: [`MISSING`]).
    pub fn color_of(&self, v: f64) -> Rgb {
        if !v.is_finite() {
            return MISSING;
        }
        let (lo, hi) = self.range;
        let t = if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        match self.map {
            ColorMap::Sequential => viridis(t),
            ColorMap::Diverging => diverging(t),
        }
    }
}

/// One image of an [`ImageGrid`]: `cols × rows` values, row-major with the
/// *bottom* row first (as [`super::HeatMap`]), coloured by scale `scale`.
#[derive(Clone, Debug, PartialEq)]
pub struct ImagePanel {
    /// The panel's title (above it).
    pub title: String,
    /// Columns.
    pub cols: usize,
    /// Rows.
    pub rows: usize,
    /// The values, `values[j · cols + i]` at column `i`, row `j` from the bottom.
    pub values: Vec<f64>,
    /// Index into [`ImageGrid::scales`].
    pub scale: usize,
}

/// A grid of image panels sharing axes (every panel covers
/// `x.range × y.range`) and colour scales.
#[derive(Clone, Debug)]
pub struct ImageGrid {
    /// The figure's title.
    pub title: String,
    /// The horizontal axis of every panel (label and range).
    pub x: Axis,
    /// The vertical axis of every panel.
    pub y: Axis,
    /// Panels per row.
    pub columns: usize,
    /// The panels, row-major from the top-left; `None` leaves a cell blank.
    pub panels: Vec<Option<ImagePanel>>,
    /// The colour scales, one colour bar each (stacked at the right).
    pub scales: Vec<ColorScale>,
    /// The size of each panel's image area in pixels.
    pub panel_px: (u32, u32),
}

/// Pixels around each panel: tick labels on the left and below, the
/// panel title above.
const PANEL_LEFT: u32 = 44;
const PANEL_BOTTOM: u32 = 34;
const PANEL_TOP: u32 = 20;
const PANEL_RIGHT: u32 = 10;
const TITLE_BAND: u32 = 34;
const BAR_WIDTH: u32 = 120;

impl ImageGrid {
    /// The whole figure's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let rows = self.panels.len().div_ceil(self.columns.max(1)) as u32;
        let cw = self.panel_px.0 + PANEL_LEFT + PANEL_RIGHT;
        let ch = self.panel_px.1 + PANEL_TOP + PANEL_BOTTOM;
        (
            self.columns as u32 * cw + BAR_WIDTH,
            rows * ch + TITLE_BAND + 8,
        )
    }

    fn validate(&self) -> io::Result<()> {
        if self.columns == 0 || self.panels.iter().all(Option::is_none) {
            return Err(invalid("image grid needs columns and at least one panel"));
        }
        if self.panel_px.0 < 16 || self.panel_px.1 < 16 {
            return Err(invalid("image panels need at least 16 × 16 pixels"));
        }
        for p in self.panels.iter().flatten() {
            if p.cols == 0 || p.rows == 0 || p.values.len() != p.cols * p.rows {
                return Err(invalid("image panel needs cols · rows = values.len() > 0"));
            }
            if p.scale >= self.scales.len() {
                return Err(invalid("image panel refers to a missing colour scale"));
            }
        }
        if self
            .scales
            .iter()
            .any(|s| !(s.range.0 < s.range.1 && s.range.0.is_finite() && s.range.1.is_finite()))
        {
            return Err(invalid("colour scales need finite ranges low < high"));
        }
        let (w, h) = self.size();
        super::draw::check_size(w, h)
    }
}

/// The panel's values resampled (nearest cell) onto `w × h` pixels, RGB,
/// top row first.
fn raster(panel: &ImagePanel, scale: &ColorScale, w: u32, h: u32) -> Vec<u8> {
    let (w, h) = (w as usize, h as usize);
    let mut rgb = vec![0u8; w * h * 3];
    for py in 0..h {
        let j = panel.rows - 1 - (py * panel.rows / h).min(panel.rows - 1);
        for px in 0..w {
            let i = (px * panel.cols / w).min(panel.cols - 1);
            let c = scale.color_of(panel.values[j * panel.cols + i]);
            rgb[(py * w + px) * 3..(py * w + px) * 3 + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    }
    rgb
}

/// Draws one panel (image, frame, ticks, title) on `area`.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    grid: &ImageGrid,
    panel: &ImagePanel,
    title_px: u32,
    (first_column, last_row): (bool, bool),
) -> io::Result<()> {
    let (x0, x1) = grid.x.range.unwrap_or((0.0, 1.0));
    let (y0, y1) = grid.y.range.unwrap_or((0.0, 1.0));
    let titled = area.titled(&panel.title, (FONT, title_px)).map_err(err)?;
    let mut chart = ChartBuilder::on(&titled)
        .margin_right(PANEL_RIGHT)
        .x_label_area_size(PANEL_BOTTOM)
        .y_label_area_size(PANEL_LEFT)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let (w, h) = (
        (xs.end - xs.start).max(1) as u32,
        (ys.end - ys.start).max(1) as u32,
    );
    let scale = &grid.scales[panel.scale];
    let image = BitMapElement::with_owned_buffer((x0, y1), (w, h), raster(panel, scale, w, h))
        .ok_or_else(|| invalid("panel raster of the wrong size"))?;
    chart.plotting_area().draw(&image).map_err(err)?;
    let fmt = |v: &f64| tick_label(*v);
    let mut mesh = chart.configure_mesh();
    mesh.disable_mesh()
        .x_labels(4)
        .y_labels(4)
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .label_style((FONT, 10))
        .axis_desc_style((FONT, 11));
    if last_row {
        mesh.x_desc(grid.x.label.as_str());
    }
    if first_column {
        mesh.y_desc(grid.y.label.as_str());
    }
    mesh.draw().map_err(err)?;
    Ok(())
}

/// Draws the colour bar of `scale` on `area`: the strip and its value axis.
fn draw_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scale: &ColorScale,
) -> io::Result<()> {
    let (lo, hi) = scale.range;
    let inner = area.margin(14, 14, 6, 0);
    let mut c = ChartBuilder::on(&inner)
        .right_y_label_area_size(BAR_WIDTH - 50)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(err)?;
    // Ticks that should be 0 but are off by rounding print as 0.
    let fmt = |v: &f64| tick_label(if v.abs() < 1e-9 * (hi - lo) { 0.0 } else { *v });
    c.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(7)
        .y_label_formatter(&fmt)
        .label_style((FONT, 10))
        .draw()
        .map_err(err)?;
    let steps = 128;
    c.draw_series((0..steps).map(|k| {
        let (a, b) = (k as f64 / steps as f64, (k + 1) as f64 / steps as f64);
        let v = lo + (a + b) / 2.0 * (hi - lo);
        Rectangle::new(
            [(0.0, lo + a * (hi - lo)), (1.0, lo + b * (hi - lo))],
            color(scale.color_of(v)).filled(),
        )
    }))
    .map_err(err)?;
    if !scale.label.is_empty() {
        let (w, h) = area.dim_in_pixel();
        let style = TextStyle::from((FONT, 11).into_font())
            .transform(FontTransform::Rotate270)
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ));
        area.draw_text(&scale.label, &style, (w as i32 - 9, h as i32 / 2))
            .map_err(err)?;
    }
    Ok(())
}

/// Writes `grid` as a PNG: the title, the panels with their axes, ticks,
/// titles (axis labels on the left column and bottom row) and one colour
/// bar per scale at the right.
///
/// `marks` counts the image cells drawn (sum of `cols · rows` over panels).
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an empty grid, panels
/// inconsistent with their sizes or scales, a scale without a proper range,
/// or a figure outside 160×120 … 8192×8192 pixels.
pub fn write_image_grid_png(path: &Path, grid: &ImageGrid) -> io::Result<Figure> {
    grid.validate()?;
    let (w, h) = grid.size();
    let (png, marks) = render_png(w, h, |root| {
        register_font();
        root.fill(&WHITE).map_err(err)?;
        let titled = root
            .titled(&grid.title, (FONT, title_size(&grid.title, w)))
            .map_err(err)?;
        let (main, bars) = titled.split_horizontally(w - BAR_WIDTH);
        let rows = grid.panels.len().div_ceil(grid.columns);
        let cells = main.split_evenly((rows, grid.columns));
        // One title size for all panels: the largest that fits the longest.
        let cell_width = cells.first().map_or(w, |c| c.dim_in_pixel().0);
        let title_px = grid
            .panels
            .iter()
            .flatten()
            .map(|p| title_size(&p.title, cell_width))
            .min()
            .unwrap_or(12)
            .min(12);
        let mut marks = 0;
        for (k, (cell, panel)) in cells.iter().zip(&grid.panels).enumerate() {
            let Some(panel) = panel else { continue };
            let (r, c) = (k / grid.columns, k % grid.columns);
            // Axis labels where no panel lies to the left or below.
            let first_column = c == 0 || grid.panels[k - 1].is_none();
            let below = k + grid.columns;
            let last_row = r + 1 == rows || grid.panels.get(below).is_none_or(Option::is_none);
            draw_panel(cell, grid, panel, title_px, (first_column, last_row))?;
            marks += panel.cols * panel.rows;
        }
        let slots = bars.split_evenly((grid.scales.len().max(1), 1));
        for (slot, scale) in slots.iter().zip(&grid.scales) {
            draw_bar(slot, scale)?;
        }
        Ok(marks)
    })?;
    write_file(path, &png, marks, (w, h), &grid.title, grid.alt_text())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::verify_figure;

    #[test]
    fn diverging_is_white_in_the_middle_and_symmetric() {
        let mid = diverging(0.5);
        assert!(mid.0 > 240 && mid.1 > 240 && mid.2 > 240, "{mid:?}");
        let (lo, hi) = (diverging(0.0), diverging(1.0));
        assert!(lo.2 > lo.0 && hi.0 > hi.2, "blue below, red above");
        assert_eq!(diverging(f64::NAN), MISSING);
        let s = ColorScale::symmetric("e", 2.0);
        assert_eq!(s.color_of(0.0), mid);
        assert_eq!(s.color_of(-5.0), lo);
        assert_eq!(s.color_of(f64::INFINITY), MISSING);
    }

    #[test]
    fn grid_png_has_panels_axes_text_and_both_bars() {
        let dir = std::env::temp_dir().join(format!("areawarp-grid-{}", std::process::id()));
        let ramp: Vec<f64> = (0..64).map(|k| k as f64 / 63.0).collect();
        let signed: Vec<f64> = ramp.iter().map(|v| 2.0 * v - 1.0).collect();
        let panel = |title: &str, values: Vec<f64>, scale| ImagePanel {
            title: title.to_string(),
            cols: 8,
            rows: 8,
            values,
            scale,
        };
        let grid = ImageGrid {
            title: "test grid".to_string(),
            x: Axis::linear("x").with_range(-1.0, 1.0),
            y: Axis::linear("y").with_range(0.0, 2.0),
            columns: 2,
            panels: vec![
                Some(panel("values", ramp, 0)),
                None,
                Some(panel("errors", signed.clone(), 1)),
                Some(panel("errors again", signed, 1)),
            ],
            scales: vec![
                ColorScale::sequential("E", 0.0, 1.0),
                ColorScale::symmetric("Ê − E", 1.0),
            ],
            panel_px: (64, 64),
        };
        let f = write_image_grid_png(&dir.join("grid.png"), &grid).unwrap();
        assert_eq!(f.marks, 3 * 64);
        assert_eq!((f.width, f.height), grid.size());
        let check = verify_figure(&f.path).unwrap();
        assert!(check.distinct_colors > 50, "{check:?}");
        assert!(check.dark_pixels > 400, "{check:?}");
        // The blank cell (top right) stays white.
        let img = crate::figures::decode_png(&std::fs::read(&f.path).unwrap()).unwrap();
        let (cw, ch) = (64 + PANEL_LEFT + PANEL_RIGHT, 64 + PANEL_TOP + PANEL_BOTTOM);
        let p = img.pixel(cw + cw / 2, TITLE_BAND + ch / 2).unwrap();
        assert_eq!(p, Rgb(255, 255, 255));
        let mut bad = grid.clone();
        bad.panels[0].as_mut().unwrap().scale = 7;
        assert!(write_image_grid_png(&dir.join("bad.png"), &bad).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
