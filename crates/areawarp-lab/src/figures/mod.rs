//! The studies' figures, drawn with [`plotters`]: line plots (linear or log
//! axes, several series with markers, dashed reference lines and confidence
//! bands, a legend beside the plot, never over it), scatter plots (optionally
//! with equal units on both axes) and heat maps of a scalar over a rectangle
//! with a colour bar, and grids of false-colour images sharing colour
//! scales ([`ImageGrid`]: rendered irradiance and signed-error maps). Every figure can be written as SVG (plotters' SVG back
//! end) or as PNG (plotters' bitmap back end, encoded by the [`png`] crate),
//! both with axes, ticks, labels and a title: text in the bitmaps uses DejaVu
//! Sans from the `dejavu` crate, so no system font is needed.
//!
//! Every writer returns a [`Figure`] (path, size in bytes, number of data
//! *marks* drawn: points, line vertices, heat-map cells) so that a test can
//! assert a figure is non-trivial; [`verify_figure`] re-reads a written
//! file and checks it independently of the writer: an SVG must be well
//! formed and its coloured marks are counted; a PNG must decode and its
//! colours are counted.
//!
//! # Example
//! ```
//! use areawarp_lab::figures::{Axis, Plot, Series, write_line_plot_svg, verify_figure};
//!
//! let dir = std::env::temp_dir().join("areawarp-figures-doc");
//! std::fs::create_dir_all(&dir)?;
//! let n = [16.0, 64.0, 256.0, 1024.0];
//! let plot = Plot::new("error vs samples", Axis::log("samples"), Axis::log("relative error"))
//!     .series(Series::new("random", n.iter().map(|&n| (n, 1.0 / f64::sqrt(n))).collect()))
//!     .series(Series::new("stratified", n.iter().map(|&n| (n, n.powf(-0.75))).collect()));
//! let figure = write_line_plot_svg(&dir.join("error.svg"), &plot)?;
//! assert_eq!(figure.marks, 8);
//! let check = verify_figure(&figure.path).map_err(std::io::Error::other)?;
//! assert!(check.marks >= 8 && check.texts >= 6);
//! # Ok::<(), std::io::Error>(())
//! ```

mod alt;
mod check;
mod draw;
mod grid;
mod heat_map;
#[cfg(test)]
mod tests;

pub use check::{
    FigureCheck, FigureKind, PngImage, SvgSummary, decode_png, encode_png, inspect_svg,
    verify_figure,
};
pub use draw::{write_line_plot_png, write_line_plot_svg, write_scatter_png, write_scatter_svg};
pub use grid::{ColorMap, ColorScale, ImageGrid, ImagePanel, diverging, write_image_grid_png};
pub use heat_map::{write_heat_map_png, write_heat_map_svg};

use std::io;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------
// Colours
// ---------------------------------------------------------------------------

/// An 8-bit sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// `#rrggbb`.
    pub fn hex(&self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// The series colours, in order (Tableau 10).
pub const PALETTE: [Rgb; 10] = [
    Rgb(31, 119, 180),
    Rgb(255, 127, 14),
    Rgb(44, 160, 44),
    Rgb(214, 39, 40),
    Rgb(148, 103, 189),
    Rgb(140, 86, 75),
    Rgb(227, 119, 194),
    Rgb(127, 127, 127),
    Rgb(188, 189, 34),
    Rgb(23, 190, 207),
];

/// The colour of missing (non-finite) heat-map values.
pub const MISSING: Rgb = Rgb(200, 200, 200);

/// Viridis control points (every eighth of the range).
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// The viridis colour map (piecewise linear through 9 control points) at
/// `t ∈ [0, 1]` (clamped; NaN gives [`MISSING`]): dark violet at 0, yellow at 1,
/// monotone in lightness.
pub fn viridis(t: f64) -> Rgb {
    if t.is_nan() {
        return MISSING;
    }
    let t = t.clamp(0.0, 1.0) * 8.0;
    let i = (t.floor() as usize).min(7);
    let f = t - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * f).round() as u8;
    Rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

// ---------------------------------------------------------------------------
// Plot description
// ---------------------------------------------------------------------------

/// An axis scale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    #[default]
    Linear,
    /// Base-10 logarithmic (non-positive values are not drawn).
    Log10,
}

/// An axis: label, scale and optional fixed range (otherwise the data's).
#[derive(Clone, Debug, Default)]
pub struct Axis {
    /// The axis label.
    pub label: String,
    /// Linear or logarithmic.
    pub scale: Scale,
    /// A fixed `(low, high)` range; `None` fits the data.
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// A linear axis fitted to the data.
    pub fn linear(label: &str) -> Self {
        Axis {
            label: label.to_string(),
            scale: Scale::Linear,
            range: None,
        }
    }
    /// A base-10 logarithmic axis fitted to the data.
    pub fn log(label: &str) -> Self {
        Axis {
            label: label.to_string(),
            scale: Scale::Log10,
            range: None,
        }
    }
    /// The same axis with the fixed range `[low, high]`.
    pub fn with_range(mut self, low: f64, high: f64) -> Self {
        self.range = Some((low, high));
        self
    }
}

/// One data series of a [`Plot`].
#[derive(Clone, Debug)]
pub struct Series {
    /// The legend entry (empty: not listed).
    pub label: String,
    /// The data points `(x, y)`; non-finite points (and non-positive ones on
    /// a log axis) are skipped and break a line.
    pub points: Vec<(f64, f64)>,
    /// A fixed colour; `None` takes the next [`PALETTE`] colour.
    pub color: Option<Rgb>,
    /// Draw the line dashed (line plots), e.g. for reference slopes.
    pub dashed: bool,
    /// Draw a marker at each point of a line plot.
    pub markers: bool,
    /// The marker's shape.
    pub marker: Marker,
    /// A confidence band `(x, low, high)` drawn as a translucent area in
    /// the series' colour behind its line (line plots).
    pub band: Vec<(f64, f64, f64)>,
}

/// The shape of a series' markers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Marker {
    /// A filled disc.
    #[default]
    Circle,
    /// A filled square.
    Square,
    /// A filled upward triangle.
    Triangle,
    /// A diagonal cross.
    Cross,
}

impl Series {
    /// A series with markers, solid line, palette colour.
    pub fn new(label: &str, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.to_string(),
            points,
            color: None,
            dashed: false,
            markers: true,
            marker: Marker::Circle,
            band: Vec::new(),
        }
    }
    /// The same series with markers of shape `m`.
    pub fn marker(mut self, m: Marker) -> Self {
        self.marker = m;
        self
    }
    /// The same series with a confidence band: `(x, low, high)` per point.
    pub fn with_band(mut self, band: Vec<(f64, f64, f64)>) -> Self {
        self.band = band;
        self
    }
    /// The same series drawn dashed and without markers (a reference line).
    pub fn reference(mut self) -> Self {
        self.dashed = true;
        self.markers = false;
        self
    }
    /// The same series in colour `c`.
    pub fn with_color(mut self, c: Rgb) -> Self {
        self.color = Some(c);
        self
    }
}

/// A 2-D plot: title, axes and series, drawn by [`write_line_plot_svg`],
/// [`write_line_plot_png`], [`write_scatter_svg`] or [`write_scatter_png`].
#[derive(Clone, Debug)]
pub struct Plot {
    /// Title above the plot.
    pub title: String,
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// The data.
    pub series: Vec<Series>,
    /// Width of the image in pixels.
    pub width: u32,
    /// Height of the image in pixels.
    pub height: u32,
    /// Equal units per pixel on both axes (linear axes only): the narrower
    /// data range is widened about its centre.
    pub equal_aspect: bool,
    /// Radius of scatter points and markers, in pixels.
    pub point_radius: f64,
}

impl Plot {
    /// A 720 × 480 plot with no series.
    pub fn new(title: &str, x: Axis, y: Axis) -> Self {
        Plot {
            title: title.to_string(),
            x,
            y,
            series: Vec::new(),
            width: 720,
            height: 480,
            equal_aspect: false,
            point_radius: 2.5,
        }
    }
    /// Adds a series.
    pub fn series(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
    /// Sets the image size.
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.width = width;
        self.height = height;
        self
    }
    /// Requests equal units per pixel on both axes.
    pub fn equal_aspect(mut self) -> Self {
        self.equal_aspect = true;
        self
    }
    /// Sets the radius of points and markers.
    pub fn point_radius(mut self, r: f64) -> Self {
        self.point_radius = r;
        self
    }
}

/// A scalar field sampled on a `cols × rows` grid of cells over the
/// rectangle `x.range × y.range` (default `[0, 1]²`): cell `(i, j)` (column
/// `i` from the left, row `j` from the *bottom*) covers
/// `[x0 + i·Δx, x0 + (i+1)·Δx] × [y0 + j·Δy, y0 + (j+1)·Δy]` and has the value
/// `values[j · cols + i]`.
#[derive(Clone, Debug)]
pub struct HeatMap {
    /// Title above the map.
    pub title: String,
    /// Horizontal axis (label, range; the scale is ignored: cells are linear).
    pub x: Axis,
    /// Vertical axis (label, range).
    pub y: Axis,
    /// The label of the colour bar.
    pub value_label: String,
    /// Linear or logarithmic colour scale (non-positive values on a log
    /// scale are drawn with the lowest colour).
    pub value_scale: Scale,
    /// A fixed colour range; `None` fits the finite values.
    pub value_range: Option<(f64, f64)>,
    /// Number of columns.
    pub cols: usize,
    /// Number of rows.
    pub rows: usize,
    /// Row-major values, bottom row first; non-finite values are drawn as
    /// [`MISSING`].
    pub values: Vec<f64>,
}

impl HeatMap {
    /// A heat map over `[0, 1]²` with a linear colour scale.
    ///
    /// # Errors
    /// [`io::ErrorKind::InvalidInput`] if `values.len() != cols · rows` or
    /// the grid is empty.
    pub fn new(title: &str, cols: usize, rows: usize, values: Vec<f64>) -> io::Result<Self> {
        if cols == 0 || rows == 0 || values.len() != cols * rows {
            return Err(invalid("heat map needs cols · rows = values.len() > 0"));
        }
        Ok(HeatMap {
            title: title.to_string(),
            x: Axis::linear("u").with_range(0.0, 1.0),
            y: Axis::linear("v").with_range(0.0, 1.0),
            value_label: String::new(),
            value_scale: Scale::Linear,
            value_range: None,
            cols,
            rows,
            values,
        })
    }
    /// Sets the axes.
    pub fn axes(mut self, x: Axis, y: Axis) -> Self {
        self.x = x;
        self.y = y;
        self
    }
    /// Sets the colour bar's label and scale.
    pub fn value_axis(mut self, label: &str, scale: Scale) -> Self {
        self.value_label = label.to_string();
        self.value_scale = scale;
        self
    }

    /// The colour range actually used: the fixed range, or the finite
    /// (positive, on a log scale) values' range; `(0, 1)` if there are none.
    pub fn color_range(&self) -> (f64, f64) {
        if let Some(r) = self.value_range {
            return r;
        }
        let usable = |v: &&f64| v.is_finite() && (self.value_scale == Scale::Linear || **v > 0.0);
        let lo = self
            .values
            .iter()
            .filter(usable)
            .fold(f64::INFINITY, |a, &b| a.min(b));
        let hi = self
            .values
            .iter()
            .filter(usable)
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        if lo.is_finite() && hi.is_finite() {
            (lo, hi)
        } else {
            (0.0, 1.0)
        }
    }

    /// The colour of value `v` under [`HeatMap::color_range`].
    pub fn color_of(&self, v: f64, range: (f64, f64)) -> Rgb {
        if !v.is_finite() {
            return MISSING;
        }
        let t = match self.value_scale {
            Scale::Linear => {
                if range.1 > range.0 {
                    (v - range.0) / (range.1 - range.0)
                } else {
                    0.5
                }
            }
            Scale::Log10 => {
                if v <= 0.0 {
                    0.0
                } else {
                    let (a, b) = (range.0.max(f64::MIN_POSITIVE).log10(), range.1.log10());
                    if b > a {
                        (v.log10() - a) / (b - a)
                    } else {
                        0.5
                    }
                }
            }
        };
        viridis(t)
    }
}

/// What a writer produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Where the file was written.
    pub path: PathBuf,
    /// Its size in bytes.
    pub bytes: u64,
    /// Number of data marks drawn (points, line vertices, heat-map cells).
    pub marks: usize,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The figure's title (the report's caption).
    pub title: String,
    /// A short description of what it plots and on which axes (the
    /// report's alt text), distinct from the title.
    pub alt: String,
}

fn invalid(msg: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg.to_string())
}

fn write_file(
    path: &Path,
    bytes: &[u8],
    marks: usize,
    (width, height): (u32, u32),
    title: &str,
    alt: String,
) -> io::Result<Figure> {
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(path, bytes)?;
    Ok(Figure {
        path: path.to_path_buf(),
        bytes: bytes.len() as u64,
        marks,
        width,
        height,
        title: title.to_string(),
        alt,
    })
}
