//! Drawing with plotters: one function per kind of figure, generic over the
//! back end, so the SVG and PNG of a figure are the same drawing.

use super::{Axis, Figure, Marker, PALETTE, Plot, Rgb, Scale, Series, invalid, write_file};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;
use std::io;
use std::path::Path;
use std::sync::Once;

/// The font family every figure uses: DejaVu Sans, registered once for the
/// bitmap back end (the SVG back end writes the family name only).
pub(super) const FONT: &str = "sans-serif";

static REGISTER_FONT: Once = Once::new();

pub(super) fn register_font() {
    REGISTER_FONT.call_once(|| {
        // DejaVu Sans is a valid TrueType font: registration cannot fail.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

pub(super) fn err<E: std::fmt::Display>(e: E) -> io::Error {
    io::Error::other(e.to_string())
}

pub(super) fn color(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

pub(super) fn check_size(width: u32, height: u32) -> io::Result<()> {
    if !(160..=8192).contains(&width) || !(120..=8192).contains(&height) {
        return Err(invalid("figure size must be within 160×120 … 8192×8192"));
    }
    Ok(())
}

/// A series' colour: its own, or the palette's `i`-th.
pub(super) fn series_color(s: &Series, i: usize) -> Rgb {
    s.color.unwrap_or(PALETTE[i % PALETTE.len()])
}

/// Whether `v` can be drawn on an axis of scale `scale`.
fn drawable(scale: Scale, v: f64) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

/// The data range of an axis (fixed, or fitted to `values` and padded by 4%
/// — a factor on a log axis), never empty.
fn axis_range(axis: &Axis, values: impl Iterator<Item = f64>, pad: bool) -> (f64, f64) {
    if let Some((a, b)) = axis.range
        && drawable(axis.scale, a)
        && drawable(axis.scale, b)
        && b > a
    {
        return (a, b);
    }
    let (lo, hi) = values
        .filter(|&v| drawable(axis.scale, v))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    let log = axis.scale == Scale::Log10;
    if !lo.is_finite() || !hi.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if hi <= lo {
        return if log {
            (lo / 2.0, hi * 2.0)
        } else {
            let w = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
            (lo - w, hi + w)
        };
    }
    match (pad, log) {
        (false, _) => (lo, hi),
        (true, false) => {
            let w = (hi - lo) * 0.04;
            (lo - w, hi + w)
        }
        (true, true) => {
            let f = (hi / lo).powf(0.04);
            (lo / f, hi * f)
        }
    }
}

/// A tick label: plain decimals between 10⁻³ and 10⁵, otherwise `m·10ᵉ`
/// with a superscript exponent (`10ᵉ` alone for powers of ten).
pub(super) fn tick_label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let e = v.abs().log10().floor();
    if (-3.0..4.0).contains(&e) {
        let s = format!("{:.*}", (3.0 - e).max(0.0) as usize + 1, v);
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        return s;
    }
    let m = v / 10f64.powf(e);
    let sup: String = format!("{}", e as i64)
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect();
    if (m - 1.0).abs() < 1e-9 {
        format!("10{sup}")
    } else if (m + 1.0).abs() < 1e-9 {
        format!("−10{sup}")
    } else {
        let ms = format!("{m:.1}");
        format!("{}·10{sup}", ms.trim_end_matches('0').trim_end_matches('.'))
    }
}

/// The title's font size: 16 pixels, smaller for a title too long for
/// the width (DejaVu Sans averages about 0.55 em per character).
pub(super) fn title_size(title: &str, width: u32) -> u32 {
    let chars = title.chars().count().max(1) as f64;
    ((width as f64 - 20.0) / (0.58 * chars)).clamp(9.0, 16.0) as u32
}

/// The layout of a plot: pixels of margin and label areas.
pub(super) const MARGIN: u32 = 10;
pub(super) const X_LABEL_AREA: u32 = 44;
pub(super) const Y_LABEL_AREA: u32 = 72;

/// The width of the legend panel for these labels (0 without labels).
fn legend_width(labels: &[&str], width: u32) -> u32 {
    let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as u32;
    if longest == 0 {
        return 0;
    }
    (longest * 7 + 52).min(width * 2 / 5)
}

/// The points of a series that can be drawn, split into runs at the skipped
/// ones (which break a line).
fn runs(
    s: &Series,
    xs: Scale,
    ys: Scale,
    clip: Option<((f64, f64), (f64, f64))>,
) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for &(x, y) in &s.points {
        let inside = clip.is_none_or(|((x0, x1), (y0, y1))| {
            let (ex, ey) = ((x1 - x0).abs() * 1e-9, (y1 - y0).abs() * 1e-9);
            x >= x0 - ex && x <= x1 + ex && y >= y0 - ey && y <= y1 + ey
        });
        if drawable(xs, x) && drawable(ys, y) && inside {
            out.last_mut().expect("non-empty").push((x, y));
        } else if !out.last().expect("non-empty").is_empty() {
            out.push(Vec::new());
        }
    }
    out.retain(|r| !r.is_empty());
    out
}

/// Draws a marker of shape `m` at pixel offset `(0, 0)` from `p`.
fn draw_marker<DB: DrawingBackend, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    m: Marker,
    pts: &[(f64, f64)],
    r: i32,
    c: RGBColor,
) -> io::Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let style = c.filled();
    match m {
        Marker::Circle => chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, r, style)))
            .map(|_| ()),
        Marker::Square => chart
            .draw_series(
                pts.iter()
                    .map(|&p| EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], style)),
            )
            .map(|_| ()),
        Marker::Triangle => chart
            .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, r + 1, style)))
            .map(|_| ()),
        Marker::Cross => chart
            .draw_series(pts.iter().map(|&p| Cross::new(p, r, c.stroke_width(2))))
            .map(|_| ()),
    }
    .map_err(err)
}

/// The dash pattern (dash, gap) of the `k`-th dashed series: long dashes,
/// dots, medium dashes, …, so two reference lines never look alike.
fn dash_pattern(k: usize) -> (u32, u32) {
    [(10, 5), (2, 4), (6, 3), (14, 3), (3, 8)][k % 5]
}

/// What kind of plot to draw from a [`Plot`].
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Line,
    Scatter,
}

/// Draws `plot` on `root`; returns the number of data points drawn.
fn draw_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &Plot,
    kind: Kind,
) -> io::Result<usize> {
    register_font();
    root.fill(&WHITE).map_err(err)?;
    let labelled: Vec<&Series> = plot
        .series
        .iter()
        .filter(|s| {
            !s.label.is_empty()
                && s.points
                    .iter()
                    .any(|&(x, y)| drawable(plot.x.scale, x) && drawable(plot.y.scale, y))
        })
        .collect();
    let labels: Vec<&str> = labelled.iter().map(|s| s.label.as_str()).collect();
    let lw = legend_width(&labels, plot.width);
    let titled = if plot.title.is_empty() {
        root.clone()
    } else {
        root.titled(&plot.title, (FONT, title_size(&plot.title, plot.width)))
            .map_err(err)?
    };
    let (main, legend) = titled.split_horizontally(titled.dim_in_pixel().0 - lw);
    let pad = true;
    let band_x = plot.series.iter().flat_map(|s| s.band.iter().map(|b| b.0));
    let band_y = plot
        .series
        .iter()
        .flat_map(|s| s.band.iter().flat_map(|b| [b.1, b.2]));
    let mut xr = axis_range(
        &plot.x,
        plot.series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.0))
            .chain(band_x),
        pad,
    );
    let mut yr = axis_range(
        &plot.y,
        plot.series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .chain(band_y),
        pad,
    );
    if plot.equal_aspect && plot.x.scale == Scale::Linear && plot.y.scale == Scale::Linear {
        let (w, h) = main.dim_in_pixel();
        let pw = w.saturating_sub(2 * MARGIN + Y_LABEL_AREA).max(1) as f64;
        let ph = h.saturating_sub(2 * MARGIN + X_LABEL_AREA).max(1) as f64;
        let (ux, uy) = ((xr.1 - xr.0) / pw, (yr.1 - yr.0) / ph);
        if ux > uy {
            let c = 0.5 * (yr.0 + yr.1);
            yr = (c - 0.5 * ux * ph, c + 0.5 * ux * ph);
        } else {
            let c = 0.5 * (xr.0 + xr.1);
            xr = (c - 0.5 * uy * pw, c + 0.5 * uy * pw);
        }
    }
    let lin = |r: (f64, f64)| r.0..r.1;
    let marks = match (plot.x.scale, plot.y.scale) {
        (Scale::Linear, Scale::Linear) => draw_in(&main, plot, kind, lin(xr), lin(yr), (xr, yr)),
        (Scale::Log10, Scale::Linear) => {
            draw_in(&main, plot, kind, lin(xr).log_scale(), lin(yr), (xr, yr))
        }
        (Scale::Linear, Scale::Log10) => {
            draw_in(&main, plot, kind, lin(xr), lin(yr).log_scale(), (xr, yr))
        }
        (Scale::Log10, Scale::Log10) => draw_in(
            &main,
            plot,
            kind,
            lin(xr).log_scale(),
            lin(yr).log_scale(),
            (xr, yr),
        ),
    }?;
    if lw > 0 {
        draw_legend(&legend, plot, kind)?;
    }
    root.present().map_err(err)?;
    Ok(marks)
}

fn draw_in<DB, XS, YS>(
    area: &DrawingArea<DB, Shift>,
    plot: &Plot,
    kind: Kind,
    xs: XS,
    ys: YS,
    clip: ((f64, f64), (f64, f64)),
) -> io::Result<usize>
where
    DB: DrawingBackend,
    XS: AsRangedCoord<Value = f64>,
    YS: AsRangedCoord<Value = f64>,
    XS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    YS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(xs, ys)
        .map_err(err)?;
    // Rounding noise near 0 on a linear axis prints as 0; on a log axis
    // small ticks are real values (10⁻¹² is not 0).
    let snap = |span: f64, log: bool| {
        move |v: &f64| {
            tick_label(if !log && v.abs() < span * 1e-9 {
                0.0
            } else {
                *v
            })
        }
    };
    let (fx, fy) = (
        snap((clip.0.1 - clip.0.0).abs(), plot.x.scale == Scale::Log10),
        snap((clip.1.1 - clip.1.0).abs(), plot.y.scale == Scale::Log10),
    );
    chart
        .configure_mesh()
        .x_desc(plot.x.label.as_str())
        .y_desc(plot.y.label.as_str())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(RGBColor(245, 245, 245))
        .x_labels(8)
        .y_labels(8)
        .draw()
        .map_err(err)?;
    let (xsc, ysc) = (plot.x.scale, plot.y.scale);
    let r = plot.point_radius.max(0.5).round() as i32;
    let mut marks = 0;
    let mut dashed = 0;
    // Bands first, behind every line.
    for (i, s) in plot.series.iter().enumerate() {
        let c = color(series_color(s, i));
        let band: Vec<(f64, f64, f64)> = s
            .band
            .iter()
            .copied()
            .filter(|&(x, lo, hi)| {
                drawable(xsc, x) && drawable(ysc, hi) && lo.is_finite() && hi >= lo
            })
            .map(|(x, lo, hi)| {
                let lo = if drawable(ysc, lo) {
                    lo.max(clip.1.0)
                } else {
                    clip.1.0
                };
                (x, lo, hi.min(clip.1.1))
            })
            .collect();
        if band.len() >= 2 {
            let poly: Vec<(f64, f64)> = band
                .iter()
                .map(|b| (b.0, b.2))
                .chain(band.iter().rev().map(|b| (b.0, b.1)))
                .collect();
            chart
                .draw_series(std::iter::once(Polygon::new(poly, c.mix(0.18).filled())))
                .map_err(err)?;
        }
    }
    for (i, s) in plot.series.iter().enumerate() {
        let c = color(series_color(s, i));
        let clip_to = (kind == Kind::Scatter).then_some(clip);
        for run in runs(s, xsc, ysc, clip_to) {
            marks += run.len();
            if kind == Kind::Line && run.len() >= 2 {
                if s.dashed {
                    let (d, g) = dash_pattern(dashed);
                    chart
                        .draw_series(DashedLineSeries::new(run.clone(), d, g, c.stroke_width(2)))
                        .map_err(err)?;
                } else {
                    chart
                        .draw_series(LineSeries::new(run.clone(), c.stroke_width(2)))
                        .map_err(err)?;
                }
            }
            if kind == Kind::Scatter || s.markers {
                let rr = if kind == Kind::Line { r.max(3) } else { r };
                draw_marker(&mut chart, s.marker, &run, rr, c)?;
            }
        }
        if s.dashed {
            dashed += 1;
        }
    }
    Ok(marks)
}

/// The legend, in its own panel right of the plot: one entry per labelled
/// series that has something drawn, with its line style and marker.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &Plot,
    kind: Kind,
) -> io::Result<()> {
    let mut y = (MARGIN + 8) as i32;
    let mut dashed = 0;
    let style = TextStyle::from((FONT, 12).into_font()).color(&BLACK);
    for (i, s) in plot.series.iter().enumerate() {
        let has = s
            .points
            .iter()
            .any(|&(x, yv)| drawable(plot.x.scale, x) && drawable(plot.y.scale, yv));
        let pattern = dash_pattern(dashed);
        if s.dashed {
            dashed += 1;
        }
        if s.label.is_empty() || !has {
            continue;
        }
        let c = color(series_color(s, i));
        let (x0, x1) = (4, 30);
        if kind == Kind::Line {
            if s.dashed {
                let (d, g) = (pattern.0 as i32, pattern.1 as i32);
                let mut x = x0;
                while x < x1 {
                    let e = (x + d).min(x1);
                    area.draw(&PathElement::new(vec![(x, y), (e, y)], c.stroke_width(2)))
                        .map_err(err)?;
                    x = e + g;
                }
            } else {
                area.draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(2)))
                    .map_err(err)?;
            }
        }
        if kind == Kind::Scatter || s.markers {
            let p = ((x0 + x1) / 2, y);
            let st = c.filled();
            match s.marker {
                Marker::Circle => area.draw(&Circle::new(p, 4, st)),
                Marker::Square => area.draw(&Rectangle::new(
                    [(p.0 - 4, p.1 - 4), (p.0 + 4, p.1 + 4)],
                    st,
                )),
                Marker::Triangle => area.draw(&TriangleMarker::new(p, 5, st)),
                Marker::Cross => area.draw(&Cross::new(p, 4, c.stroke_width(2))),
            }
            .map_err(err)?;
        }
        area.draw_text(
            &s.label,
            &style.pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Left,
                plotters::style::text_anchor::VPos::Center,
            )),
            (x1 + 6, y),
        )
        .map_err(err)?;
        y += 18;
    }
    Ok(())
}

/// Renders with the SVG back end into a string.
pub(super) fn render_svg(
    width: u32,
    height: u32,
    f: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> io::Result<usize>,
) -> io::Result<(String, usize)> {
    let mut text = String::new();
    let marks = {
        let root = SVGBackend::with_string(&mut text, (width, height)).into_drawing_area();
        let m = f(&root)?;
        root.present().map_err(err)?;
        m
    };
    Ok((text, marks))
}

/// Renders with the bitmap back end and encodes the PNG.
pub(super) fn render_png(
    width: u32,
    height: u32,
    f: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> io::Result<usize>,
) -> io::Result<(Vec<u8>, usize)> {
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    let marks = {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        let m = f(&root)?;
        root.present().map_err(err)?;
        m
    };
    Ok((super::encode_png(width, height, &rgb)?, marks))
}

/// Writes `plot` as an SVG line plot: one line per series (broken at
/// skipped points: non-finite, or non-positive on a log axis), markers at
/// the points if the series asks for them, its confidence band if it has
/// one, dashed reference lines (each in its own dash pattern), axes with
/// ticks and labels, and a legend beside the plot.
///
/// `marks` counts the points drawn.
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an image size outside
/// 160×120 … 8192×8192.
pub fn write_line_plot_svg(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let (text, marks) = render_svg(plot.width, plot.height, |root| {
        draw_plot(root, plot, Kind::Line)
    })?;
    write_file(
        path,
        text.as_bytes(),
        marks,
        (plot.width, plot.height),
        &plot.title,
        plot.alt_text("Line chart"),
    )
}

/// [`write_line_plot_svg`]'s drawing as a PNG (same axes, text and legend).
///
/// # Errors
/// As [`write_line_plot_svg`].
pub fn write_line_plot_png(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let (png, marks) = render_png(plot.width, plot.height, |root| {
        draw_plot(root, plot, Kind::Line)
    })?;
    write_file(
        path,
        &png,
        marks,
        (plot.width, plot.height),
        &plot.title,
        plot.alt_text("Line chart"),
    )
}

/// Writes `plot` as an SVG scatter plot: a marker per point inside the
/// axes' ranges (points outside a fixed range are not drawn), axes, and a
/// legend beside the plot; equal units on both axes if the plot asks.
///
/// `marks` counts the points drawn.
///
/// # Errors
/// As [`write_line_plot_svg`].
pub fn write_scatter_svg(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let (text, marks) = render_svg(plot.width, plot.height, |root| {
        draw_plot(root, plot, Kind::Scatter)
    })?;
    write_file(
        path,
        text.as_bytes(),
        marks,
        (plot.width, plot.height),
        &plot.title,
        plot.alt_text("Scatter plot"),
    )
}

/// [`write_scatter_svg`]'s drawing as a PNG of `plot.width × plot.height`
/// pixels, with the same axes, ticks, labels and legend.
///
/// # Errors
/// As [`write_line_plot_svg`].
pub fn write_scatter_png(path: &Path, plot: &Plot) -> io::Result<Figure> {
    check_size(plot.width, plot.height)?;
    let (png, marks) = render_png(plot.width, plot.height, |root| {
        draw_plot(root, plot, Kind::Scatter)
    })?;
    write_file(
        path,
        &png,
        marks,
        (plot.width, plot.height),
        &plot.title,
        plot.alt_text("Scatter plot"),
    )
}
