//! A tiny, dependency-free figure writer for the studies' reports: SVG plots
//! (scatter plots with optional equal-aspect axes, line plots with linear or
//! log axes, several series with a legend, ticks and labels; heat maps of a
//! scalar over a rectangle with a colour bar) and PNG rasters (heat maps,
//! scatter rasters), plus the checks the tests use to prove a figure is
//! well-formed and non-trivial.
//!
//! The PNG encoder is minimal but real: 8-bit RGB, per-row filter `Sub` or
//! `Up`, DEFLATE with the fixed Huffman code and run-length matches
//! (distance 1), CRC-32 per chunk and Adler-32 over the zlib stream. The
//! decoder [`decode_png`] inflates stored, fixed and dynamic Huffman blocks
//! and undoes all five PNG filters, so it also reads PNGs written by other
//! tools (8-bit grey, RGB or RGBA, non-interlaced).
//!
//! Every writer returns a [`Figure`] (path, size in bytes, number of *marks*
//! drawn: points, line vertices, heat-map cells) so that a test can assert a
//! figure is non-trivial; [`verify_figure`] re-reads a written file and
//! checks it independently of the writer's own count.
//!
//! Marks in SVG output are the elements with `class="mark"`; an element
//! standing for several marks (a polyline without markers, a heat map's
//! embedded raster) carries `data-marks="k"`. [`inspect_svg`] counts them.
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
//! assert_eq!(check.marks, 8);
//! # Ok::<(), std::io::Error>(())
//! ```

use std::fmt::Write as _;
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
        }
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
/// [`write_scatter_svg`] or [`write_scatter_png`].
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
    fn color_of(&self, v: f64, range: (f64, f64)) -> Rgb {
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
}

fn invalid(msg: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg.to_string())
}

fn write_file(
    path: &Path,
    bytes: &[u8],
    marks: usize,
    width: u32,
    height: u32,
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
    })
}

// ---------------------------------------------------------------------------
// Axes, ticks, coordinate transforms
// ---------------------------------------------------------------------------

/// Escapes `& < > "` for SVG text and attributes.
fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// A resolved axis: data range in transformed units (log10 for log axes)
/// and the pixel interval it maps to.
#[derive(Clone, Copy, Debug)]
struct Mapped {
    scale: Scale,
    lo: f64,
    hi: f64,
    p0: f64,
    p1: f64,
}

impl Mapped {
    fn tr(scale: Scale, v: f64) -> Option<f64> {
        match scale {
            Scale::Linear => v.is_finite().then_some(v),
            Scale::Log10 => (v.is_finite() && v > 0.0).then(|| v.log10()),
        }
    }
    /// Pixel coordinate of data value `v`.
    fn px(&self, v: f64) -> Option<f64> {
        let t = Self::tr(self.scale, v)?;
        Some(self.p0 + (t - self.lo) / (self.hi - self.lo) * (self.p1 - self.p0))
    }
    fn contains(&self, v: f64) -> bool {
        Self::tr(self.scale, v).is_some_and(|t| {
            let eps = (self.hi - self.lo) * 1e-9;
            t >= self.lo - eps && t <= self.hi + eps
        })
    }
}

/// The transformed data range of an axis (fixed or fitted, padded, never empty).
fn axis_range(axis: &Axis, values: impl Iterator<Item = f64>, pad: bool) -> (f64, f64) {
    let (lo, hi) = match axis.range {
        Some((a, b)) => {
            let a = Mapped::tr(axis.scale, a);
            let b = Mapped::tr(axis.scale, b);
            match (a, b) {
                (Some(a), Some(b)) if b > a => return (a, b),
                _ => (f64::INFINITY, f64::NEG_INFINITY),
            }
        }
        None => values
            .filter_map(|v| Mapped::tr(axis.scale, v))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), t| {
                (l.min(t), h.max(t))
            }),
    };
    if !lo.is_finite() || !hi.is_finite() {
        return (0.0, 1.0);
    }
    if hi <= lo {
        let w = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
        return (lo - w, hi + w);
    }
    if pad {
        let w = (hi - lo) * 0.04;
        (lo - w, hi + w)
    } else {
        (lo, hi)
    }
}

/// Tick positions (transformed units) and labels (SVG markup) for a range.
fn ticks(scale: Scale, lo: f64, hi: f64) -> Vec<(f64, String)> {
    match scale {
        Scale::Linear => {
            let span = hi - lo;
            let raw = span / 5.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * mag)
                .find(|s| span / s <= 7.0)
                .unwrap_or(10.0 * mag);
            let mut out = Vec::new();
            let mut k = (lo / step).ceil();
            while k * step <= hi + step * 1e-9 && out.len() < 20 {
                let v = k * step;
                let v = if v.abs() < step * 1e-9 { 0.0 } else { v };
                out.push((v, format_linear(v, step)));
                k += 1.0;
            }
            out
        }
        Scale::Log10 => {
            let (a, b) = (lo.ceil() as i64, hi.floor() as i64);
            let mut out: Vec<(f64, String)> = (a..=b)
                .map(|e| {
                    (
                        e as f64,
                        if (-3..=4).contains(&e) {
                            format_decimal(10f64.powi(e as i32))
                        } else {
                            format!("10<tspan dy=\"-6\" font-size=\"9\">{e}</tspan>")
                        },
                    )
                })
                .collect();
            if b - a < 2 {
                // Less than two decades: add 2· and 5· ticks.
                for e in (lo.floor() as i64)..=(hi.ceil() as i64) {
                    for m in [2.0f64, 5.0] {
                        let t = e as f64 + m.log10();
                        if t >= lo && t <= hi {
                            out.push((t, format_decimal(m * 10f64.powi(e as i32))));
                        }
                    }
                }
                out.sort_by(|x, y| x.0.total_cmp(&y.0));
            }
            if b - a > 12 {
                // Too many decades: keep every k-th.
                let k = ((b - a) / 8).max(1);
                out.retain(|(t, _)| (*t as i64 - a) % k == 0);
            }
            out
        }
    }
}

fn format_linear(v: f64, step: f64) -> String {
    let digits = (-step.log10().floor()).max(0.0) as usize;
    if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-4) {
        format!("{v:.1e}")
    } else {
        format!("{v:.digits$}")
    }
}

fn format_decimal(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-4) {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The plot frame inside an image: left, right, top, bottom pixel bounds.
#[derive(Clone, Copy, Debug)]
struct Frame {
    left: f64,
    right: f64,
    top: f64,
    bottom: f64,
}

impl Frame {
    fn for_plot(width: u32, height: u32, extra_right: f64) -> Frame {
        Frame {
            left: 78.0,
            right: width as f64 - 20.0 - extra_right,
            top: 36.0,
            bottom: height as f64 - 52.0,
        }
    }
}

/// Resolves both axes of a plot; with `equal_aspect` (both linear) widens the
/// narrower range so that one data unit has the same length on both axes.
fn resolve_axes(plot: &Plot, frame: Frame, pad: bool) -> (Mapped, Mapped) {
    let all = || plot.series.iter().flat_map(|s| s.points.iter());
    let (mut xl, mut xh) = axis_range(&plot.x, all().map(|p| p.0), pad);
    let (mut yl, mut yh) = axis_range(&plot.y, all().map(|p| p.1), pad);
    let (w, h) = (frame.right - frame.left, frame.bottom - frame.top);
    if plot.equal_aspect && plot.x.scale == Scale::Linear && plot.y.scale == Scale::Linear {
        let per_px = ((xh - xl) / w).max((yh - yl) / h);
        let (cx, cy) = ((xl + xh) / 2.0, (yl + yh) / 2.0);
        xl = cx - per_px * w / 2.0;
        xh = cx + per_px * w / 2.0;
        yl = cy - per_px * h / 2.0;
        yh = cy + per_px * h / 2.0;
    }
    (
        Mapped {
            scale: plot.x.scale,
            lo: xl,
            hi: xh,
            p0: frame.left,
            p1: frame.right,
        },
        Mapped {
            scale: plot.y.scale,
            lo: yl,
            hi: yh,
            p0: frame.bottom,
            p1: frame.top,
        },
    )
}

fn svg_open(out: &mut String, width: u32, height: u32, title: &str) {
    let _ = writeln!(
        out,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
         version=\"1.1\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" \
         font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">"
    );
    let _ = writeln!(out, "<title>{}</title>", esc(title));
    let _ = writeln!(
        out,
        "<rect x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"white\"/>"
    );
    let _ = writeln!(
        out,
        "<text x=\"{:.1}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">{}</text>",
        width as f64 / 2.0,
        esc(title)
    );
}

/// Frame, grid lines, ticks and axis labels.
fn svg_axes(
    out: &mut String,
    frame: Frame,
    x: &Mapped,
    y: &Mapped,
    labels: (&str, &str),
    grid: bool,
) {
    let (xl, yl) = labels;
    let _ = writeln!(
        out,
        "<g class=\"axes\" stroke=\"#444\" fill=\"none\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></g>",
        frame.left,
        frame.top,
        frame.right - frame.left,
        frame.bottom - frame.top
    );
    let _ = writeln!(out, "<g class=\"ticks\">");
    for (t, label) in ticks(x.scale, x.lo, x.hi) {
        let px = x.p0 + (t - x.lo) / (x.hi - x.lo) * (x.p1 - x.p0);
        if grid {
            let _ = write!(
                out,
                "<line x1=\"{px:.1}\" y1=\"{:.1}\" x2=\"{px:.1}\" y2=\"{:.1}\" stroke=\"#ddd\"/>",
                frame.top, frame.bottom
            );
        }
        let _ = writeln!(
            out,
            "<line x1=\"{px:.1}\" y1=\"{:.1}\" x2=\"{px:.1}\" y2=\"{:.1}\" stroke=\"#444\"/>\
             <text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{label}</text>",
            frame.bottom,
            frame.bottom + 5.0,
            frame.bottom + 19.0
        );
    }
    for (t, label) in ticks(y.scale, y.lo, y.hi) {
        let py = y.p0 + (t - y.lo) / (y.hi - y.lo) * (y.p1 - y.p0);
        if grid {
            let _ = write!(
                out,
                "<line x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\" stroke=\"#ddd\"/>",
                frame.left, frame.right
            );
        }
        let _ = writeln!(
            out,
            "<line x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\" stroke=\"#444\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{label}</text>",
            frame.left - 5.0,
            frame.left,
            frame.left - 8.0,
            py + 4.0
        );
    }
    let _ = writeln!(out, "</g>");
    let _ = writeln!(
        out,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
        (frame.left + frame.right) / 2.0,
        frame.bottom + 40.0,
        esc(xl)
    );
    let (cx, cy) = (18.0, (frame.top + frame.bottom) / 2.0);
    let _ = writeln!(
        out,
        "<text x=\"{cx:.1}\" y=\"{cy:.1}\" text-anchor=\"middle\" transform=\"rotate(-90 {cx:.1} {cy:.1})\">{}</text>",
        esc(yl)
    );
}

fn series_color(s: &Series, i: usize) -> Rgb {
    s.color.unwrap_or(PALETTE[i % PALETTE.len()])
}

/// The legend in the top-left corner of the frame.
/// The legend, in the corner of the frame that covers the fewest of the
/// `occupied` pixel positions (data points and points along lines).
fn svg_legend(
    out: &mut String,
    frame: Frame,
    series: &[Series],
    lines: bool,
    occupied: &[(f64, f64)],
) {
    let entries: Vec<(usize, &Series)> = series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.is_empty())
        .collect();
    if entries.is_empty() {
        return;
    }
    let longest = entries
        .iter()
        .map(|(_, s)| s.label.chars().count())
        .max()
        .unwrap_or(0);
    let (w, h) = (
        40.0 + 6.6 * longest as f64,
        8.0 + 16.0 * entries.len() as f64,
    );
    let corners = [
        (frame.left + 8.0, frame.top + 8.0),
        (frame.right - 8.0 - w, frame.top + 8.0),
        (frame.left + 8.0, frame.bottom - 8.0 - h),
        (frame.right - 8.0 - w, frame.bottom - 8.0 - h),
    ];
    let covered = |&(x0, y0): &(f64, f64)| {
        occupied
            .iter()
            .filter(|(x, y)| {
                *x >= x0 - 4.0 && *x <= x0 + w + 4.0 && *y >= y0 - 4.0 && *y <= y0 + h + 4.0
            })
            .count()
    };
    let (x0, y0) = corners
        .iter()
        .min_by_key(|c| covered(c))
        .copied()
        .unwrap_or(corners[0]);
    let _ = writeln!(
        out,
        "<g class=\"legend\"><rect x=\"{x0:.1}\" y=\"{y0:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999\"/>"
    );
    for (k, (i, s)) in entries.iter().enumerate() {
        let c = series_color(s, *i).hex();
        let y = y0 + 14.0 + 16.0 * k as f64;
        if lines {
            let dash = if s.dashed {
                " stroke-dasharray=\"5,3\""
            } else {
                ""
            };
            let _ = write!(
                out,
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{c}\" stroke-width=\"2\"{dash}/>",
                x0 + 6.0,
                y - 4.0,
                x0 + 28.0,
                y - 4.0
            );
        } else {
            let _ = write!(
                out,
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3.5\" fill=\"{c}\"/>",
                x0 + 17.0,
                y - 4.0
            );
        }
        let _ = writeln!(
            out,
            "<text x=\"{:.1}\" y=\"{y:.1}\">{}</text>",
            x0 + 34.0,
            esc(&s.label)
        );
    }
    let _ = writeln!(out, "</g>");
}

fn check_size(width: u32, height: u32) -> io::Result<()> {
    if !(160..=8192).contains(&width) || !(120..=8192).contains(&height) {
        return Err(invalid("figure size must be within 160×120 … 8192×8192"));
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// SVG writers
// ---------------------------------------------------------------------------

/// Writes `plot` as an SVG line plot: one polyline per series (broken at
/// skipped points), markers at the points if the series asks for them,
/// ticks (decades, with 2 and 5 in between on short log ranges; 1-2-5 steps
/// on linear axes), axis labels and a legend.
///
/// `marks` counts the points drawn.
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an image size outside
/// 160×120 … 8192×8192.
pub fn write_line_plot_svg(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let frame = Frame::for_plot(plot.width, plot.height, 0.0);
    let (x, y) = resolve_axes(plot, frame, true);
    let mut out = String::new();
    svg_open(&mut out, plot.width, plot.height, &plot.title);
    svg_axes(
        &mut out,
        frame,
        &x,
        &y,
        (&plot.x.label, &plot.y.label),
        true,
    );
    let mut marks = 0;
    let mut occupied: Vec<(f64, f64)> = Vec::new();
    let _ = writeln!(
        out,
        "<clipPath id=\"plot-area\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>",
        frame.left,
        frame.top,
        frame.right - frame.left,
        frame.bottom - frame.top
    );
    let _ = writeln!(out, "<g clip-path=\"url(#plot-area)\">");
    for (i, s) in plot.series.iter().enumerate() {
        let c = series_color(s, i).hex();
        let dash = if s.dashed {
            " stroke-dasharray=\"5,3\""
        } else {
            ""
        };
        let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for &(px, py) in &s.points {
            match (x.px(px), y.px(py)) {
                (Some(a), Some(b)) if x.contains(px) && y.contains(py) => {
                    if let Some(run) = runs.last_mut() {
                        run.push((a, b));
                    }
                }
                _ => {
                    if runs.last().is_some_and(|r| !r.is_empty()) {
                        runs.push(Vec::new());
                    }
                }
            }
        }
        for run in runs.iter().filter(|r| !r.is_empty()) {
            occupied.extend(run.iter().copied());
            for pair in run.windows(2) {
                for k in 1..16 {
                    let t = k as f64 / 16.0;
                    occupied.push((
                        pair[0].0 + t * (pair[1].0 - pair[0].0),
                        pair[0].1 + t * (pair[1].1 - pair[0].1),
                    ));
                }
            }
            let pts: Vec<String> = run.iter().map(|(a, b)| format!("{a:.2},{b:.2}")).collect();
            let counted = if s.markers {
                String::new()
            } else {
                marks += run.len();
                format!(" class=\"mark\" data-marks=\"{}\"", run.len())
            };
            let _ = writeln!(
                out,
                "<polyline{counted} points=\"{}\" fill=\"none\" stroke=\"{c}\" stroke-width=\"2\"{dash}/>",
                pts.join(" ")
            );
            if s.markers {
                for (a, b) in run {
                    marks += 1;
                    let _ = writeln!(
                        out,
                        "<circle class=\"mark\" cx=\"{a:.2}\" cy=\"{b:.2}\" r=\"{:.1}\" fill=\"{c}\"/>",
                        plot.point_radius
                    );
                }
            }
        }
    }
    let _ = writeln!(out, "</g>");
    svg_legend(&mut out, frame, &plot.series, true, &occupied);
    out.push_str("</svg>\n");
    write_file(path, out.as_bytes(), marks, plot.width, plot.height)
}

/// Writes `plot` as an SVG scatter plot: one circle per point inside the
/// axes' range (equal units per pixel on both axes if
/// [`Plot::equal_aspect`] is set), with ticks, labels and a legend.
///
/// `marks` counts the circles drawn.
///
/// # Errors
/// As [`write_line_plot_svg`].
pub fn write_scatter_svg(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let frame = Frame::for_plot(plot.width, plot.height, 0.0);
    let (x, y) = resolve_axes(plot, frame, true);
    let mut out = String::new();
    svg_open(&mut out, plot.width, plot.height, &plot.title);
    svg_axes(
        &mut out,
        frame,
        &x,
        &y,
        (&plot.x.label, &plot.y.label),
        true,
    );
    let mut marks = 0;
    let mut occupied: Vec<(f64, f64)> = Vec::new();
    for (i, s) in plot.series.iter().enumerate() {
        let c = series_color(s, i).hex();
        let _ = writeln!(out, "<g fill=\"{c}\">");
        for &(px, py) in &s.points {
            if let (Some(a), Some(b)) = (x.px(px), y.px(py))
                && x.contains(px)
                && y.contains(py)
            {
                marks += 1;
                occupied.push((a, b));
                let _ = writeln!(
                    out,
                    "<circle class=\"mark\" cx=\"{a:.2}\" cy=\"{b:.2}\" r=\"{:.1}\"/>",
                    plot.point_radius
                );
            }
        }
        let _ = writeln!(out, "</g>");
    }
    svg_legend(&mut out, frame, &plot.series, false, &occupied);
    out.push_str("</svg>\n");
    write_file(path, out.as_bytes(), marks, plot.width, plot.height)
}

/// Writes a heat map as SVG: the cells as an embedded PNG raster (one pixel
/// per cell, scaled without smoothing), axes with ticks and labels, and a
/// colour bar with ticks (log or linear). Compact even for large grids.
///
/// `marks` counts the cells (finite or not).
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an inconsistent grid.
pub fn write_heat_map_svg(path: &Path, map: &HeatMap) -> io::Result<Figure> {
    if map.cols == 0 || map.rows == 0 || map.values.len() != map.cols * map.rows {
        return Err(invalid("heat map needs cols · rows = values.len() > 0"));
    }
    let (width, height) = (640u32, 560u32);
    let frame = Frame {
        left: 70.0,
        right: width as f64 - 120.0,
        top: 36.0,
        bottom: height as f64 - 56.0,
    };
    let plot = Plot::new(&map.title, map.x.clone(), map.y.clone());
    let (x, y) = resolve_axes(
        &Plot {
            series: Vec::new(),
            ..plot
        },
        frame,
        false,
    );
    let range = map.color_range();
    // k × k pixels per cell (at least 256 pixels a side, so that viewers
    // which smooth the scaled raster blur only the cell borders), top row first.
    let k = 256usize.div_ceil(map.cols.min(map.rows)).clamp(1, 16);
    let (w, h) = (map.cols * k, map.rows * k);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for j in (0..map.rows).rev() {
        let mut row = Vec::with_capacity(w * 3);
        for i in 0..map.cols {
            let c = map.color_of(map.values[j * map.cols + i], range);
            for _ in 0..k {
                row.extend_from_slice(&[c.0, c.1, c.2]);
            }
        }
        for _ in 0..k {
            rgb.extend_from_slice(&row);
        }
    }
    let png = encode_png(w as u32, h as u32, &rgb)?;
    let mut out = String::new();
    svg_open(&mut out, width, height, &map.title);
    let _ = writeln!(
        out,
        "<image class=\"mark\" data-marks=\"{}\" x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" \
         preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" image-rendering=\"optimizeSpeed\" \
         href=\"data:image/png;base64,{}\"/>",
        map.cols * map.rows,
        frame.left,
        frame.top,
        frame.right - frame.left,
        frame.bottom - frame.top,
        base64(&png)
    );
    svg_axes(&mut out, frame, &x, &y, (&map.x.label, &map.y.label), false);
    // Colour bar.
    let (bx, bw) = (frame.right + 24.0, 18.0);
    let steps = 64;
    let _ = writeln!(out, "<g class=\"colorbar\">");
    let bh = frame.bottom - frame.top;
    for k in 0..steps {
        let t = (k as f64 + 0.5) / steps as f64;
        let c = viridis(t).hex();
        let y0 = frame.bottom - bh * (k + 1) as f64 / steps as f64;
        let _ = writeln!(
            out,
            "<rect x=\"{bx:.1}\" y=\"{y0:.2}\" width=\"{bw:.1}\" height=\"{:.2}\" fill=\"{c}\" stroke=\"none\"/>",
            bh / steps as f64 + 0.3
        );
    }
    let _ = writeln!(
        out,
        "<rect x=\"{bx:.1}\" y=\"{:.1}\" width=\"{bw:.1}\" height=\"{bh:.1}\" fill=\"none\" stroke=\"#444\"/>",
        frame.top
    );
    let (lo, hi) = match map.value_scale {
        Scale::Linear => (range.0, range.1),
        Scale::Log10 => (
            range.0.max(f64::MIN_POSITIVE).log10(),
            range.1.max(f64::MIN_POSITIVE).log10(),
        ),
    };
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, lo + 0.5)
    };
    for (t, label) in ticks(map.value_scale, lo, hi) {
        let py = frame.bottom - (t - lo) / (hi - lo) * bh;
        let _ = writeln!(
            out,
            "<line x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\" stroke=\"#444\"/><text x=\"{:.1}\" y=\"{:.1}\">{label}</text>",
            bx + bw,
            bx + bw + 4.0,
            bx + bw + 7.0,
            py + 4.0
        );
    }
    let (cx, cy) = (width as f64 - 12.0, (frame.top + frame.bottom) / 2.0);
    let _ = writeln!(
        out,
        "<text x=\"{cx:.1}\" y=\"{cy:.1}\" text-anchor=\"middle\" transform=\"rotate(-90 {cx:.1} {cy:.1})\">{}</text>",
        esc(&map.value_label)
    );
    let _ = writeln!(out, "</g>");
    out.push_str("</svg>\n");
    write_file(path, out.as_bytes(), map.cols * map.rows, width, height)
}

// ---------------------------------------------------------------------------
// PNG writers
// ---------------------------------------------------------------------------

/// Writes a heat map as a PNG: each cell a `cell_px × cell_px` block (bottom
/// row at the bottom), and a vertical colour bar (low at the bottom) at the
/// right after an 8-pixel gap. No text: the value range belongs in the
/// caption (see [`HeatMap::color_range`]).
///
/// `marks` counts the cells.
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an inconsistent grid,
/// `cell_px = 0` or an image larger than 8192 pixels a side.
pub fn write_heat_map_png(path: &Path, map: &HeatMap, cell_px: u32) -> io::Result<Figure> {
    if map.cols == 0 || map.rows == 0 || map.values.len() != map.cols * map.rows || cell_px == 0 {
        return Err(invalid(
            "heat map needs cols · rows = values.len() > 0 and cell_px > 0",
        ));
    }
    let (cw, ch) = (map.cols * cell_px as usize, map.rows * cell_px as usize);
    let (gap, bar) = (8usize, 16usize);
    let (w, h) = (cw + gap + bar, ch);
    if w > 8192 || h > 8192 {
        return Err(invalid("heat map image larger than 8192 pixels"));
    }
    let range = map.color_range();
    let mut rgb = vec![255u8; w * h * 3];
    for py in 0..h {
        let j = map.rows - 1 - py / cell_px as usize;
        for px in 0..cw {
            let i = px / cell_px as usize;
            let c = map.color_of(map.values[j * map.cols + i], range);
            rgb[(py * w + px) * 3..(py * w + px) * 3 + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
        let c = viridis(1.0 - (py as f64 + 0.5) / h as f64);
        for px in cw + gap..w {
            rgb[(py * w + px) * 3..(py * w + px) * 3 + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    }
    let png = encode_png(w as u32, h as u32, &rgb)?;
    write_file(path, &png, map.cols * map.rows, w as u32, h as u32)
}

/// Rasterizes `plot` as a PNG scatter plot of `plot.width × plot.height`
/// pixels: white background, a grey frame around the axes' range, each
/// point a filled disc of [`Plot::point_radius`] pixels in its series'
/// colour. No text.
///
/// `marks` counts the points inside the range.
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an image size outside
/// 160×120 … 8192×8192.
pub fn write_scatter_png(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let (w, h) = (plot.width as usize, plot.height as usize);
    let m = 8.0;
    let frame = Frame {
        left: m,
        right: w as f64 - m,
        top: m,
        bottom: h as f64 - m,
    };
    let (x, y) = resolve_axes(plot, frame, true);
    let mut rgb = vec![255u8; w * h * 3];
    let mut put = |px: i64, py: i64, c: Rgb| {
        if px >= 0 && py >= 0 && (px as usize) < w && (py as usize) < h {
            let k = (py as usize * w + px as usize) * 3;
            rgb[k..k + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    };
    // The frame of the data range.
    let grey = Rgb(160, 160, 160);
    let (l, r, t, b) = (
        frame.left as i64,
        frame.right as i64,
        frame.top as i64,
        frame.bottom as i64,
    );
    for px in l..=r {
        put(px, t, grey);
        put(px, b, grey);
    }
    for py in t..=b {
        put(l, py, grey);
        put(r, py, grey);
    }
    let rad = plot.point_radius.max(0.5);
    let ir = rad.ceil() as i64;
    let mut marks = 0;
    for (i, s) in plot.series.iter().enumerate() {
        let c = series_color(s, i);
        for &(dx, dy) in &s.points {
            if let (Some(cx), Some(cy)) = (x.px(dx), y.px(dy))
                && x.contains(dx)
                && y.contains(dy)
            {
                marks += 1;
                let (ox, oy) = (cx.floor() as i64, cy.floor() as i64);
                for py in oy - ir..=oy + ir {
                    for px in ox - ir..=ox + ir {
                        let (ddx, ddy) = (px as f64 + 0.5 - cx, py as f64 + 0.5 - cy);
                        if ddx * ddx + ddy * ddy <= rad * rad + 0.25 {
                            put(px, py, c);
                        }
                    }
                }
            }
        }
    }
    let png = encode_png(plot.width, plot.height, &rgb)?;
    write_file(path, &png, marks, plot.width, plot.height)
}

// ---------------------------------------------------------------------------
// PNG encoding
// ---------------------------------------------------------------------------

/// CRC-32 (IEEE, reflected, polynomial `0xEDB88320`) as used by PNG chunks.
pub fn crc32(data: &[u8]) -> u32 {
    const fn table() -> [u32; 256] {
        let mut t = [0u32; 256];
        let mut n = 0;
        while n < 256 {
            let mut c = n as u32;
            let mut k = 0;
            while k < 8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
                k += 1;
            }
            t[n] = c;
            n += 1;
        }
        t
    }
    const TABLE: [u32; 256] = table();
    let mut c = 0xFFFF_FFFFu32;
    for &b in data {
        c = TABLE[((c ^ b as u32) & 0xFF) as usize] ^ (c >> 8);
    }
    c ^ 0xFFFF_FFFF
}

/// Adler-32 (the zlib stream checksum).
pub fn adler32(data: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for chunk in data.chunks(5552) {
        for &x in chunk {
            a += x as u32;
            b += a;
        }
        a %= 65521;
        b %= 65521;
    }
    (b << 16) | a
}

/// An LSB-first bit writer for DEFLATE.
struct BitWriter {
    out: Vec<u8>,
    acc: u64,
    n: u32,
}

impl BitWriter {
    fn put(&mut self, bits: u32, count: u32) {
        self.acc |= (bits as u64) << self.n;
        self.n += count;
        while self.n >= 8 {
            self.out.push(self.acc as u8);
            self.acc >>= 8;
            self.n -= 8;
        }
    }
    /// A Huffman code, sent most significant bit first.
    fn code(&mut self, code: u32, len: u32) {
        let mut rev = 0;
        for i in 0..len {
            rev |= ((code >> i) & 1) << (len - 1 - i);
        }
        self.put(rev, len);
    }
    fn finish(mut self) -> Vec<u8> {
        if self.n > 0 {
            self.out.push(self.acc as u8);
        }
        self.out
    }
}

const LENGTH_BASE: [u16; 29] = [
    3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131,
    163, 195, 227, 258,
];
const LENGTH_EXTRA: [u8; 29] = [
    0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
];
const DIST_BASE: [u16; 30] = [
    1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537,
    2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577,
];
const DIST_EXTRA: [u8; 30] = [
    0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13,
    13,
];

/// The fixed Huffman code of a literal/length symbol: (code, bits).
fn fixed_code(sym: u32) -> (u32, u32) {
    match sym {
        0..=143 => (0x30 + sym, 8),
        144..=255 => (0x190 + sym - 144, 9),
        256..=279 => (sym - 256, 7),
        _ => (0xC0 + sym - 280, 8),
    }
}

/// A zlib stream of `data`: one final DEFLATE block with the fixed Huffman
/// code, literals and run-length matches (distance 1, lengths 3–258).
pub fn zlib_compress(data: &[u8]) -> Vec<u8> {
    let mut w = BitWriter {
        out: vec![0x78, 0x01],
        acc: 0,
        n: 0,
    };
    w.put(1, 1); // BFINAL
    w.put(1, 2); // BTYPE = 01, fixed Huffman
    let mut i = 0;
    while i < data.len() {
        let mut run = 0;
        if i > 0 {
            while run < 258 && i + run < data.len() && data[i + run] == data[i - 1] {
                run += 1;
            }
        }
        if run >= 3 {
            let k = LENGTH_BASE
                .iter()
                .rposition(|&b| b as usize <= run)
                .unwrap_or(0);
            let (c, l) = fixed_code(257 + k as u32);
            w.code(c, l);
            if LENGTH_EXTRA[k] > 0 {
                w.put(
                    (run - LENGTH_BASE[k] as usize) as u32,
                    LENGTH_EXTRA[k] as u32,
                );
            }
            w.code(0, 5); // distance code 0 = distance 1
            i += run;
        } else {
            let (c, l) = fixed_code(data[i] as u32);
            w.code(c, l);
            i += 1;
        }
    }
    let (c, l) = fixed_code(256);
    w.code(c, l);
    let mut out = w.finish();
    out.extend_from_slice(&adler32(data).to_be_bytes());
    out
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// Encodes an 8-bit RGB image (`rgb` row-major, top row first,
/// `3 · width · height` bytes) as PNG. Each row is filtered with `Up` if it
/// repeats the row above, else with `Sub`.
///
/// # Errors
/// [`io::ErrorKind::InvalidInput`] if the buffer size does not match or a
/// side is 0.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> io::Result<Vec<u8>> {
    let (w, h) = (width as usize, height as usize);
    if w == 0 || h == 0 || rgb.len() != w * h * 3 {
        return Err(invalid("PNG buffer must hold 3 · width · height bytes"));
    }
    let stride = w * 3;
    let mut raw = Vec::with_capacity((stride + 1) * h);
    for y in 0..h {
        let row = &rgb[y * stride..(y + 1) * stride];
        if y > 0 && row == &rgb[(y - 1) * stride..y * stride] {
            raw.push(2); // Up: all zeros
            raw.extend(std::iter::repeat_n(0u8, stride));
        } else {
            raw.push(1); // Sub
            for x in 0..stride {
                let left = if x >= 3 { row[x - 3] } else { 0 };
                raw.push(row[x].wrapping_sub(left));
            }
        }
    }
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"IDAT", &zlib_compress(&raw));
    chunk(&mut out, b"IEND", &[]);
    Ok(out)
}

// ---------------------------------------------------------------------------
// PNG decoding (for checks)
// ---------------------------------------------------------------------------

/// A decoded PNG, converted to 8-bit RGB.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PngImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGB, top row first.
    pub rgb: Vec<u8>,
}

impl PngImage {
    /// Number of distinct colours.
    pub fn distinct_colors(&self) -> usize {
        let mut set = std::collections::HashSet::new();
        for p in self.rgb.chunks_exact(3) {
            set.insert((p[0], p[1], p[2]));
        }
        set.len()
    }
    /// The pixel at column `x`, row `y` (top row 0).
    pub fn pixel(&self, x: u32, y: u32) -> Option<Rgb> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let k = (y as usize * self.width as usize + x as usize) * 3;
        Some(Rgb(self.rgb[k], self.rgb[k + 1], self.rgb[k + 2]))
    }
}

struct BitReader<'a> {
    data: &'a [u8],
    pos: usize,
    bit: u32,
}

impl BitReader<'_> {
    fn bits(&mut self, n: u32) -> Result<u32, String> {
        let mut v = 0;
        for i in 0..n {
            let byte = *self.data.get(self.pos).ok_or("deflate stream truncated")?;
            v |= (((byte >> self.bit) & 1) as u32) << i;
            self.bit += 1;
            if self.bit == 8 {
                self.bit = 0;
                self.pos += 1;
            }
        }
        Ok(v)
    }
    fn align(&mut self) {
        if self.bit > 0 {
            self.bit = 0;
            self.pos += 1;
        }
    }
}

/// A canonical Huffman decoding table: counts per length, symbols by code.
struct Huffman {
    counts: [u16; 16],
    symbols: Vec<u16>,
}

impl Huffman {
    fn new(lengths: &[u8]) -> Result<Self, String> {
        let mut counts = [0u16; 16];
        for &l in lengths {
            counts[l as usize] += 1;
        }
        counts[0] = 0;
        let mut left: i32 = 1;
        for &c in &counts[1..] {
            left = left * 2 - c as i32;
            if left < 0 {
                return Err("over-subscribed Huffman code".into());
            }
        }
        let mut offs = [0u16; 16];
        for l in 1..15 {
            offs[l + 1] = offs[l] + counts[l];
        }
        let mut symbols = vec![0u16; lengths.len()];
        for (s, &l) in lengths.iter().enumerate() {
            if l != 0 {
                symbols[offs[l as usize] as usize] = s as u16;
                offs[l as usize] += 1;
            }
        }
        Ok(Huffman { counts, symbols })
    }
    fn decode(&self, r: &mut BitReader<'_>) -> Result<u16, String> {
        let (mut code, mut first, mut index) = (0i32, 0i32, 0i32);
        for len in 1..16 {
            code |= r.bits(1)? as i32;
            let count = self.counts[len] as i32;
            if code - count < first {
                return self
                    .symbols
                    .get((index + (code - first)) as usize)
                    .copied()
                    .ok_or_else(|| "bad Huffman code".to_string());
            }
            index += count;
            first = (first + count) << 1;
            code <<= 1;
        }
        Err("invalid Huffman code".into())
    }
}

/// Inflates a zlib stream (checks the header and the Adler-32).
///
/// # Errors
/// A description of the first inconsistency found.
pub fn zlib_decompress(data: &[u8]) -> Result<Vec<u8>, String> {
    if data.len() < 6 {
        return Err("zlib stream too short".into());
    }
    let (cmf, flg) = (data[0], data[1]);
    if cmf & 0x0F != 8 || !((cmf as u16) << 8 | flg as u16).is_multiple_of(31) || flg & 0x20 != 0 {
        return Err("bad zlib header".into());
    }
    let mut r = BitReader {
        data: &data[2..],
        pos: 0,
        bit: 0,
    };
    let mut out: Vec<u8> = Vec::new();
    loop {
        let last = r.bits(1)?;
        match r.bits(2)? {
            0 => {
                r.align();
                let p = r.pos;
                let d = r.data;
                if p + 4 > d.len() {
                    return Err("stored block truncated".into());
                }
                let len = u16::from_le_bytes([d[p], d[p + 1]]) as usize;
                let nlen = u16::from_le_bytes([d[p + 2], d[p + 3]]) as usize;
                if len != (!nlen & 0xFFFF) || p + 4 + len > d.len() {
                    return Err("bad stored block".into());
                }
                out.extend_from_slice(&d[p + 4..p + 4 + len]);
                r.pos = p + 4 + len;
            }
            kind @ (1 | 2) => {
                let (lit, dist) = if kind == 1 {
                    let mut l = [0u8; 288];
                    for (s, x) in l.iter_mut().enumerate() {
                        *x = match s {
                            0..=143 => 8,
                            144..=255 => 9,
                            256..=279 => 7,
                            _ => 8,
                        };
                    }
                    (Huffman::new(&l)?, Huffman::new(&[5u8; 30])?)
                } else {
                    dynamic_tables(&mut r)?
                };
                loop {
                    let sym = lit.decode(&mut r)? as usize;
                    if sym < 256 {
                        out.push(sym as u8);
                    } else if sym == 256 {
                        break;
                    } else {
                        let k = sym - 257;
                        if k >= 29 {
                            return Err("bad length symbol".into());
                        }
                        let len =
                            LENGTH_BASE[k] as usize + r.bits(LENGTH_EXTRA[k] as u32)? as usize;
                        let ds = dist.decode(&mut r)? as usize;
                        if ds >= 30 {
                            return Err("bad distance symbol".into());
                        }
                        let d = DIST_BASE[ds] as usize + r.bits(DIST_EXTRA[ds] as u32)? as usize;
                        if d > out.len() {
                            return Err("distance too far back".into());
                        }
                        for _ in 0..len {
                            out.push(out[out.len() - d]);
                        }
                    }
                }
            }
            _ => return Err("reserved block type".into()),
        }
        if last == 1 {
            break;
        }
    }
    r.align();
    let p = r.pos;
    let tail = r.data.get(p..p + 4).ok_or("missing Adler-32")?;
    let expected = u32::from_be_bytes([tail[0], tail[1], tail[2], tail[3]]);
    if expected != adler32(&out) {
        return Err("Adler-32 mismatch".into());
    }
    Ok(out)
}

fn dynamic_tables(r: &mut BitReader<'_>) -> Result<(Huffman, Huffman), String> {
    let hlit = r.bits(5)? as usize + 257;
    let hdist = r.bits(5)? as usize + 1;
    let hclen = r.bits(4)? as usize + 4;
    const ORDER: [usize; 19] = [
        16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15,
    ];
    let mut cl = [0u8; 19];
    for &o in ORDER.iter().take(hclen) {
        cl[o] = r.bits(3)? as u8;
    }
    let clh = Huffman::new(&cl)?;
    let mut lengths = Vec::with_capacity(hlit + hdist);
    while lengths.len() < hlit + hdist {
        let sym = clh.decode(r)?;
        match sym {
            0..=15 => lengths.push(sym as u8),
            16 => {
                let prev = *lengths.last().ok_or("repeat with no previous length")?;
                for _ in 0..3 + r.bits(2)? {
                    lengths.push(prev);
                }
            }
            17 => lengths.extend(std::iter::repeat_n(0, 3 + r.bits(3)? as usize)),
            _ => lengths.extend(std::iter::repeat_n(0, 11 + r.bits(7)? as usize)),
        }
    }
    if lengths.len() > hlit + hdist {
        return Err("code lengths overflow".into());
    }
    Ok((
        Huffman::new(&lengths[..hlit])?,
        Huffman::new(&lengths[hlit..])?,
    ))
}

/// Decodes a PNG: checks the signature, every chunk's CRC, the IHDR
/// (8-bit grey, RGB or RGBA; not interlaced), inflates the IDAT stream,
/// undoes the row filters and converts to RGB.
///
/// # Errors
/// A description of the first inconsistency found.
pub fn decode_png(bytes: &[u8]) -> Result<PngImage, String> {
    const SIG: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    if bytes.len() < 8 || bytes[..8] != SIG {
        return Err("not a PNG signature".into());
    }
    let mut pos = 8;
    let mut header: Option<(u32, u32, u8)> = None;
    let mut idat = Vec::new();
    let mut ended = false;
    while pos + 12 <= bytes.len() {
        let len = u32::from_be_bytes([bytes[pos], bytes[pos + 1], bytes[pos + 2], bytes[pos + 3]])
            as usize;
        let end = pos + 8 + len;
        if end + 4 > bytes.len() {
            return Err("chunk truncated".into());
        }
        let kind = &bytes[pos + 4..pos + 8];
        let data = &bytes[pos + 8..end];
        let crc = u32::from_be_bytes([bytes[end], bytes[end + 1], bytes[end + 2], bytes[end + 3]]);
        if crc != crc32(&bytes[pos + 4..end]) {
            return Err(format!("CRC mismatch in {}", String::from_utf8_lossy(kind)));
        }
        match kind {
            b"IHDR" => {
                if len != 13 {
                    return Err("bad IHDR length".into());
                }
                let w = u32::from_be_bytes([data[0], data[1], data[2], data[3]]);
                let h = u32::from_be_bytes([data[4], data[5], data[6], data[7]]);
                if data[8] != 8 || data[10] != 0 || data[11] != 0 || data[12] != 0 {
                    return Err("only 8-bit, non-interlaced PNGs are supported".into());
                }
                if w == 0 || h == 0 {
                    return Err("empty image".into());
                }
                header = Some((w, h, data[9]));
            }
            b"IDAT" => idat.extend_from_slice(data),
            b"IEND" => {
                ended = true;
                break;
            }
            _ => {}
        }
        pos = end + 4;
    }
    let (w, h, color) = header.ok_or("missing IHDR")?;
    if !ended {
        return Err("missing IEND".into());
    }
    let bpp = match color {
        0 => 1,
        2 => 3,
        6 => 4,
        _ => return Err(format!("unsupported colour type {color}")),
    };
    let raw = zlib_decompress(&idat)?;
    let stride = w as usize * bpp;
    if raw.len() != (stride + 1) * h as usize {
        return Err("image data size mismatch".into());
    }
    let mut pix = vec![0u8; stride * h as usize];
    for y in 0..h as usize {
        let filter = raw[y * (stride + 1)];
        let src = &raw[y * (stride + 1) + 1..(y + 1) * (stride + 1)];
        for x in 0..stride {
            let a = if x >= bpp {
                pix[y * stride + x - bpp] as i32
            } else {
                0
            };
            let b = if y > 0 {
                pix[(y - 1) * stride + x] as i32
            } else {
                0
            };
            let c = if x >= bpp && y > 0 {
                pix[(y - 1) * stride + x - bpp] as i32
            } else {
                0
            };
            let pred = match filter {
                0 => 0,
                1 => a,
                2 => b,
                3 => (a + b) / 2,
                4 => {
                    let p = a + b - c;
                    let (pa, pb, pc) = ((p - a).abs(), (p - b).abs(), (p - c).abs());
                    if pa <= pb && pa <= pc {
                        a
                    } else if pb <= pc {
                        b
                    } else {
                        c
                    }
                }
                _ => return Err(format!("bad filter type {filter}")),
            };
            pix[y * stride + x] = (src[x] as i32 + pred) as u8;
        }
    }
    let rgb = match bpp {
        3 => pix,
        1 => pix.iter().flat_map(|&g| [g, g, g]).collect(),
        _ => pix
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect(),
    };
    Ok(PngImage {
        width: w,
        height: h,
        rgb,
    })
}

// ---------------------------------------------------------------------------
// Base64 (for PNGs embedded in SVG)
// ---------------------------------------------------------------------------

const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Standard base64 with padding.
pub fn base64(data: &[u8]) -> String {
    let mut out = String::with_capacity(data.len().div_ceil(3) * 4);
    for c in data.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(B64[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Decodes standard base64 (padding optional, no whitespace).
///
/// # Errors
/// On a character outside the alphabet or a dangling sextet.
pub fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let (mut acc, mut n) = (0u32, 0u32);
    for ch in text.bytes().take_while(|&b| b != b'=') {
        let v = B64
            .iter()
            .position(|&b| b == ch)
            .ok_or_else(|| format!("bad base64 character {:?}", ch as char))?
            as u32;
        acc = acc << 6 | v;
        n += 6;
        if n >= 8 {
            n -= 8;
            out.push((acc >> n) as u8);
            acc &= (1 << n) - 1;
        }
    }
    if n >= 6 {
        return Err("dangling base64 sextet".into());
    }
    Ok(out)
}

// ---------------------------------------------------------------------------
// Checks
// ---------------------------------------------------------------------------

/// What [`inspect_svg`] found in an SVG document.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SvgSummary {
    /// Number of elements.
    pub elements: usize,
    /// Marks: elements with `class="mark"`, each counting `data-marks` (or 1).
    pub marks: usize,
    /// Number of `<text>` elements.
    pub texts: usize,
    /// Embedded PNG rasters (`data:image/png;base64,…`), all decoded and checked.
    pub embedded_pngs: Vec<PngImage>,
}

fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// Checks that `text` is a well-formed SVG document at the level the writers
/// need (one root `<svg>` element; every tag closed and properly nested;
/// attribute quotes balanced; no stray `<` or `&` in text; embedded PNGs
/// decode) and counts its elements and marks.
///
/// # Errors
/// A description of the first problem found.
pub fn inspect_svg(text: &str) -> Result<SvgSummary, String> {
    let mut stack: Vec<&str> = Vec::new();
    let mut summary = SvgSummary {
        elements: 0,
        marks: 0,
        texts: 0,
        embedded_pngs: Vec::new(),
    };
    let mut roots = 0;
    let mut rest = text;
    while let Some(lt) = rest.find('<') {
        let between = &rest[..lt];
        if stack.is_empty() && !between.trim().is_empty() {
            return Err("text outside the root element".into());
        }
        if let Some(amp) = between.find('&') {
            let ent = &between[amp..];
            if !["&amp;", "&lt;", "&gt;", "&quot;", "&apos;", "&#"]
                .iter()
                .any(|e| ent.starts_with(e))
            {
                return Err("unescaped & in text".into());
            }
        }
        rest = &rest[lt..];
        if let Some(r) = rest.strip_prefix("<!--") {
            let end = r.find("-->").ok_or("unterminated comment")?;
            rest = &r[end + 3..];
            continue;
        }
        if let Some(r) = rest.strip_prefix("<?") {
            let end = r.find("?>").ok_or("unterminated processing instruction")?;
            rest = &r[end + 2..];
            continue;
        }
        // Find the closing '>' outside quotes.
        let mut in_quote = false;
        let mut end = None;
        for (i, c) in rest.char_indices().skip(1) {
            match c {
                '"' => in_quote = !in_quote,
                '<' if !in_quote => return Err("'<' inside a tag".into()),
                '>' if !in_quote => {
                    end = Some(i);
                    break;
                }
                _ => {}
            }
        }
        let end = end.ok_or("unterminated tag")?;
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let name = name.trim();
            match stack.pop() {
                Some(open) if open == name => {}
                Some(open) => return Err(format!("</{name}> closes <{open}>")),
                None => return Err(format!("</{name}> without an open tag")),
            }
            continue;
        }
        let self_closing = tag.ends_with('/');
        let body = tag.trim_end_matches('/');
        let name = body.split_whitespace().next().ok_or("empty tag")?;
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == ':' || c == '-')
        {
            return Err(format!("bad tag name {name:?}"));
        }
        if stack.is_empty() {
            roots += 1;
            if name != "svg" || roots > 1 {
                return Err("the document must have one <svg> root".into());
            }
        }
        summary.elements += 1;
        if name == "text" {
            summary.texts += 1;
        }
        if attribute(body, "class") == Some("mark") {
            summary.marks += match attribute(body, "data-marks") {
                Some(k) => k.parse::<usize>().map_err(|_| "bad data-marks")?,
                None => 1,
            };
        }
        if let Some(href) = attribute(body, "href")
            && let Some(b64) = href.strip_prefix("data:image/png;base64,")
        {
            let png = base64_decode(b64)?;
            summary.embedded_pngs.push(decode_png(&png)?);
        }
        if !self_closing {
            stack.push(name);
        }
    }
    if !rest.trim().is_empty() {
        return Err("trailing text after the root element".into());
    }
    if let Some(open) = stack.pop() {
        return Err(format!("<{open}> is never closed"));
    }
    if roots != 1 {
        return Err("no <svg> root element".into());
    }
    Ok(summary)
}

/// The file type of a figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FigureKind {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics.
    Png,
}

/// What [`verify_figure`] found in a written figure.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FigureCheck {
    /// SVG or PNG (by extension).
    pub kind: FigureKind,
    /// File size.
    pub bytes: u64,
    /// Marks counted in an SVG ([`SvgSummary::marks`]); 0 for a PNG.
    pub marks: usize,
    /// Distinct colours of a PNG, or of the largest raster embedded in an SVG.
    pub distinct_colors: usize,
    /// PNG width (0 for an SVG).
    pub width: u32,
    /// PNG height (0 for an SVG).
    pub height: u32,
}

/// Re-reads a figure written by this module (or any 8-bit PNG / simple SVG)
/// and checks it: an SVG must pass [`inspect_svg`], a PNG must decode
/// ([`decode_png`]). The test of "written and non-trivial" is then e.g.
/// `check.marks > 0` (SVG) or `check.distinct_colors > 1` (PNG).
///
/// # Errors
/// I/O errors and format errors, as text.
pub fn verify_figure(path: &Path) -> Result<FigureCheck, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("svg") => {
            let text = std::str::from_utf8(&bytes).map_err(|_| "SVG is not UTF-8")?;
            let s = inspect_svg(text)?;
            Ok(FigureCheck {
                kind: FigureKind::Svg,
                bytes: bytes.len() as u64,
                marks: s.marks,
                distinct_colors: s
                    .embedded_pngs
                    .iter()
                    .map(PngImage::distinct_colors)
                    .max()
                    .unwrap_or(0),
                width: 0,
                height: 0,
            })
        }
        Some("png") => {
            let img = decode_png(&bytes)?;
            Ok(FigureCheck {
                kind: FigureKind::Png,
                bytes: bytes.len() as u64,
                marks: 0,
                distinct_colors: img.distinct_colors(),
                width: img.width,
                height: img.height,
            })
        }
        _ => Err(format!("{}: not .svg or .png", path.display())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("areawarp-figures-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        dir.join(name)
    }

    #[test]
    fn checksums_match_known_values() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b"IEND"), 0xAE42_6082);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
        assert_eq!(adler32(&[]), 1);
    }

    #[test]
    fn zlib_round_trip() {
        let mut data = Vec::new();
        for i in 0..70_000u32 {
            data.push(if i % 1000 < 600 {
                7
            } else {
                (i * 31 % 251) as u8
            });
        }
        let z = zlib_compress(&data);
        assert!(z.len() < data.len() / 2, "{}", z.len());
        assert_eq!(zlib_decompress(&z).unwrap(), data);
        assert_eq!(
            zlib_decompress(&zlib_compress(&[])).unwrap(),
            Vec::<u8>::new()
        );
        // A corrupted checksum is detected.
        let mut bad = z.clone();
        let n = bad.len();
        bad[n - 1] ^= 1;
        assert!(zlib_decompress(&bad).is_err());
        // A stored block (hand-made): "abc".
        let stored = [
            0x78, 0x01, 0x01, 3, 0, 0xFC, 0xFF, b'a', b'b', b'c', 0x02, 0x4D, 0x01, 0x27,
        ];
        assert_eq!(zlib_decompress(&stored).unwrap(), b"abc");
    }

    #[test]
    fn base64_round_trip() {
        for s in [&b""[..], b"f", b"fo", b"foo", b"foob", b"fooba", b"foobar"] {
            assert_eq!(base64_decode(&base64(s)).unwrap(), s);
        }
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert!(base64_decode("Zm9v!").is_err());
    }

    #[test]
    fn png_round_trip_and_corruption() {
        let (w, h) = (37u32, 23u32);
        let mut rgb = Vec::new();
        for y in 0..h {
            for x in 0..w {
                rgb.extend_from_slice(&[
                    (x * 7) as u8,
                    (y * 11) as u8,
                    if y % 5 == 0 { 9 } else { 200 },
                ]);
            }
        }
        // Repeat a row to exercise the Up filter.
        let stride = (w * 3) as usize;
        let row2 = rgb[2 * stride..3 * stride].to_vec();
        rgb[3 * stride..4 * stride].copy_from_slice(&row2);
        let png = encode_png(w, h, &rgb).unwrap();
        assert_eq!(&png[..8], &[0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A]);
        assert_eq!(&png[12..16], b"IHDR");
        let img = decode_png(&png).unwrap();
        assert_eq!((img.width, img.height), (w, h));
        assert_eq!(img.rgb, rgb);
        assert!(img.distinct_colors() > 100);
        // Flip a bit inside IHDR's data: the CRC check fails.
        let mut bad = png.clone();
        bad[18] ^= 0x40;
        assert!(decode_png(&bad).unwrap_err().contains("CRC"));
        assert!(decode_png(&png[..png.len() - 12]).is_err(), "IEND missing");
        assert!(encode_png(2, 2, &[0; 11]).is_err());
    }

    #[test]
    fn svg_inspector_rejects_malformed() {
        assert!(inspect_svg("<svg><g></svg>").is_err());
        assert!(inspect_svg("<svg><g></g>").is_err());
        assert!(inspect_svg("<svg><text>a < b</text></svg>").is_err());
        assert!(inspect_svg("<svg><text>a & b</text></svg>").is_err());
        assert!(inspect_svg("<svg/><svg/>").is_err());
        assert!(inspect_svg("<g/>").is_err());
        assert!(inspect_svg("<svg><rect x=\"1/></svg>").is_err());
        let ok = inspect_svg(
            "<?xml version=\"1.0\"?><!-- c --><svg><circle class=\"mark\"/>\
             <polyline class=\"mark\" data-marks=\"5\"/><text>a &amp; b</text></svg>",
        )
        .unwrap();
        assert_eq!((ok.elements, ok.marks, ok.texts), (4, 6, 1));
    }

    #[test]
    fn line_plot_svg_log_axes() {
        let n: Vec<f64> = (0..8).map(|k| 4f64.powi(k + 2)).collect();
        let plot = Plot::new("error <vs> n & more", Axis::log("n"), Axis::log("error"))
            .series(Series::new(
                "a",
                n.iter().map(|&x| (x, x.powf(-0.5))).collect(),
            ))
            .series(Series::new(
                "b",
                n.iter().map(|&x| (x, 0.1 * x.powf(-0.75))).collect(),
            ))
            // A skipped point (0 on a log axis) breaks the line.
            .series(Series::new(
                "c",
                vec![(16.0, 1e-3), (64.0, 0.0), (256.0, 1e-4), (1024.0, 1e-5)],
            ))
            .series(
                Series::new("slope -1/2", vec![(16.0, 0.5), (65536.0, 0.5 / 64.0)]).reference(),
            );
        let f = write_line_plot_svg(&tmp("line.svg"), &plot).unwrap();
        assert_eq!(f.marks, 8 + 8 + 3 + 2);
        let text = std::fs::read_to_string(&f.path).unwrap();
        let s = inspect_svg(&text).unwrap();
        assert_eq!(s.marks, f.marks);
        assert_eq!(text.matches("<circle class=\"mark\"").count(), 19);
        assert!(text.contains("&lt;vs&gt; n &amp; more"));
        // Decade ticks with exponents, and four legend entries.
        assert!(text.contains(">10<tspan"));
        assert!(s.texts >= 4 + 2 + 1 + 6);
        assert_eq!(verify_figure(&f.path).unwrap().marks, 21);
        assert_eq!(f.bytes, text.len() as u64);
    }

    #[test]
    fn scatter_svg_equal_aspect() {
        let pts: Vec<(f64, f64)> = (0..100)
            .map(|i| {
                let t = i as f64 * 0.0628;
                (t.cos(), 0.5 * t.sin())
            })
            .collect();
        let plot = Plot::new("ellipse", Axis::linear("x"), Axis::linear("y"))
            .series(Series::new("pts", pts.clone()))
            .equal_aspect();
        let f = write_scatter_svg(&tmp("scatter.svg"), &plot).unwrap();
        assert_eq!(f.marks, 100);
        let text = std::fs::read_to_string(&f.path).unwrap();
        assert_eq!(inspect_svg(&text).unwrap().marks, 100);
        // Equal aspect: the x and y pixel extents of the data are in ratio 2:1.
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for line in text.lines().filter(|l| l.contains("class=\"mark\"")) {
            xs.push(attribute(line, "cx").unwrap().parse::<f64>().unwrap());
            ys.push(attribute(line, "cy").unwrap().parse::<f64>().unwrap());
        }
        let span = |v: &[f64]| {
            v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                - v.iter().cloned().fold(f64::INFINITY, f64::min)
        };
        let ratio = span(&xs) / span(&ys);
        assert!((ratio - 2.0).abs() < 0.02, "{ratio}");
        // Points outside a fixed range are not drawn.
        let clipped = Plot::new(
            "half",
            Axis::linear("x").with_range(0.0, 2.0),
            Axis::linear("y"),
        )
        .series(Series::new("", pts));
        let f = write_scatter_svg(&tmp("scatter2.svg"), &clipped).unwrap();
        assert!(f.marks > 30 && f.marks < 70, "{}", f.marks);
    }

    #[test]
    fn heat_maps_svg_and_png() {
        let (cols, rows) = (32, 16);
        let values: Vec<f64> = (0..cols * rows)
            .map(|k| {
                let (i, j) = (k % cols, k / cols);
                if i == 3 && j == 4 {
                    f64::NAN
                } else {
                    10f64.powf((i + j) as f64 / 8.0)
                }
            })
            .collect();
        let map = HeatMap::new("map", cols, rows, values)
            .unwrap()
            .value_axis("error", Scale::Log10);
        let svg = write_heat_map_svg(&tmp("heat.svg"), &map).unwrap();
        assert_eq!(svg.marks, cols * rows);
        let text = std::fs::read_to_string(&svg.path).unwrap();
        let s = inspect_svg(&text).unwrap();
        assert_eq!(s.marks, cols * rows);
        assert_eq!(s.embedded_pngs.len(), 1);
        let img = &s.embedded_pngs[0];
        // 16 × 16 pixels per cell (at least 256 pixels a side).
        let k = 16;
        assert_eq!((img.width, img.height), (cols as u32 * k, rows as u32 * k));
        // The bottom-left cell is the minimum, the top-right the maximum.
        assert_eq!(img.pixel(0, rows as u32 * k - 1), Some(viridis(0.0)));
        assert_eq!(img.pixel(cols as u32 * k - 1, 0), Some(viridis(1.0)));
        assert_eq!(
            img.pixel(3 * k + 5, (rows as u32 - 1 - 4) * k + 7),
            Some(MISSING)
        );
        assert_eq!(
            img.pixel(3 * k - 1, (rows as u32 - 1 - 4) * k + 7),
            Some(map.color_of(map.values[4 * cols + 2], map.color_range()))
        );
        let png = write_heat_map_png(&tmp("heat.png"), &map, 4).unwrap();
        assert_eq!(png.marks, cols * rows);
        let check = verify_figure(&png.path).unwrap();
        assert_eq!(
            (check.width, check.height),
            (cols as u32 * 4 + 24, rows as u32 * 4)
        );
        assert!(check.distinct_colors > 20);
        assert!(HeatMap::new("bad", 3, 3, vec![0.0; 8]).is_err());
    }

    #[test]
    fn scatter_png_raster() {
        let pts: Vec<(f64, f64)> = (0..50).map(|i| (i as f64, (i * i % 17) as f64)).collect();
        let plot = Plot::new("", Axis::linear(""), Axis::linear(""))
            .series(Series::new("a", pts))
            .series(Series::new("b", vec![(10.0, 40.0)]))
            .size(200, 160);
        let f = write_scatter_png(&tmp("scatter.png"), &plot).unwrap();
        assert_eq!(f.marks, 51);
        let img = decode_png(&std::fs::read(&f.path).unwrap()).unwrap();
        assert_eq!((img.width, img.height), (200, 160));
        // White, frame grey, and both series colours.
        let colors: std::collections::HashSet<_> = img
            .rgb
            .chunks_exact(3)
            .map(|p| Rgb(p[0], p[1], p[2]))
            .collect();
        assert!(colors.contains(&PALETTE[0]) && colors.contains(&PALETTE[1]));
        assert!(colors.contains(&Rgb(255, 255, 255)));
        assert!(write_scatter_png(&tmp("tiny.png"), &plot.clone().size(10, 10)).is_err());
    }

    #[test]
    fn viridis_endpoints_and_monotone_lightness() {
        assert_eq!(viridis(0.0), Rgb(68, 1, 84));
        assert_eq!(viridis(1.0), Rgb(253, 231, 37));
        assert_eq!(viridis(f64::NAN), MISSING);
        let light = |c: Rgb| 0.2126 * c.0 as f64 + 0.7152 * c.1 as f64 + 0.0722 * c.2 as f64;
        let mut prev = -1.0;
        for k in 0..=100 {
            let l = light(viridis(k as f64 / 100.0));
            assert!(l > prev);
            prev = l;
        }
    }

    #[test]
    fn linear_ticks_are_nice() {
        let t = ticks(Scale::Linear, -0.03, 1.03);
        let v: Vec<f64> = t.iter().map(|x| x.0).collect();
        assert_eq!(v.len(), 6, "{v:?}");
        for (k, x) in v.iter().enumerate() {
            assert!((x - 0.2 * k as f64).abs() < 1e-12, "{v:?}");
        }
        assert_eq!(t[1].1, "0.2");
        let t = ticks(Scale::Log10, -0.2, 0.9); // 0.63 … 7.9
        let labels: Vec<&str> = t.iter().map(|x| x.1.as_str()).collect();
        assert!(labels.contains(&"2") && labels.contains(&"5"), "{labels:?}");
    }
}
