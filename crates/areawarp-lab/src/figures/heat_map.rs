//! Heat maps: the cells (a bitmap, or one embedded raster in an SVG), the
//! axes and a colour bar, drawn with plotters.

use super::draw::{
    FONT, MARGIN, X_LABEL_AREA, Y_LABEL_AREA, color, err, register_font, render_png, render_svg,
    tick_label, title_size,
};
use super::{Figure, HeatMap, Scale, invalid, viridis, write_file};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::io;
use std::path::Path;

/// The width of a heat map's colour-bar panel.
const BAR_PANEL: u32 = 130;

/// Draws `map` on `root`: the cells (drawn here on a bitmap, or left to the
/// caller — `cells = false` — who embeds them as one raster in an SVG), the
/// axes and a colour bar. Returns the plotting area's pixel rectangle.
fn draw_heat_map<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    map: &HeatMap,
    cells: bool,
) -> io::Result<(std::ops::Range<i32>, std::ops::Range<i32>)> {
    register_font();
    root.fill(&WHITE).map_err(err)?;
    let titled = if map.title.is_empty() {
        root.clone()
    } else {
        root.titled(
            &map.title,
            (FONT, title_size(&map.title, root.dim_in_pixel().0)),
        )
        .map_err(err)?
    };
    let (main, bar) = titled.split_horizontally(titled.dim_in_pixel().0 - BAR_PANEL);
    let (x0, x1) = map.x.range.unwrap_or((0.0, 1.0));
    let (y0, y1) = map.y.range.unwrap_or((0.0, 1.0));
    let mut chart = ChartBuilder::on(&main)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA - 12)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    let fmt = |v: &f64| tick_label(*v);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(map.x.label.as_str())
        .y_desc(map.y.label.as_str())
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .draw()
        .map_err(err)?;
    let range = map.color_range();
    if cells {
        let (dx, dy) = ((x1 - x0) / map.cols as f64, (y1 - y0) / map.rows as f64);
        chart
            .draw_series((0..map.rows).flat_map(|j| {
                (0..map.cols).map(move |i| {
                    let c = map.color_of(map.values[j * map.cols + i], range);
                    let (a, b) = (x0 + i as f64 * dx, y0 + j as f64 * dy);
                    Rectangle::new([(a, b), (a + dx, b + dy)], color(c).filled())
                })
            }))
            .map_err(err)?;
    }
    let pixels = chart.plotting_area().get_pixel_range();
    // The colour bar: the value axis on the right of a viridis strip.
    let (lo, hi) = if range.1 > range.0 {
        range
    } else {
        (range.0 - 0.5, range.0 + 0.5)
    };
    let steps = 96;
    let label = map.value_label.as_str();
    let bar_area = bar.margin(MARGIN, MARGIN + X_LABEL_AREA, 4, 0);
    let strip = |t: f64| color(viridis(t));
    match map.value_scale {
        Scale::Log10 if lo > 0.0 => {
            let mut c = ChartBuilder::on(&bar_area)
                .right_y_label_area_size(BAR_PANEL - 62)
                .build_cartesian_2d(0.0..1.0, (lo..hi).log_scale())
                .map_err(err)?;
            c.configure_mesh()
                .disable_mesh()
                .disable_x_axis()
                .y_label_formatter(&fmt)
                .label_style((FONT, 11))
                .axis_desc_style((FONT, 12))
                .draw()
                .map_err(err)?;
            let r = (hi / lo).ln();
            c.draw_series((0..steps).map(|k| {
                let (a, b) = (k as f64 / steps as f64, (k + 1) as f64 / steps as f64);
                Rectangle::new(
                    [(0.0, lo * (a * r).exp()), (1.0, lo * (b * r).exp())],
                    strip((a + b) / 2.0).filled(),
                )
            }))
            .map_err(err)?;
        }
        _ => {
            let mut c = ChartBuilder::on(&bar_area)
                .right_y_label_area_size(BAR_PANEL - 62)
                .build_cartesian_2d(0.0..1.0, lo..hi)
                .map_err(err)?;
            c.configure_mesh()
                .disable_mesh()
                .disable_x_axis()
                .y_label_formatter(&fmt)
                .label_style((FONT, 11))
                .axis_desc_style((FONT, 12))
                .draw()
                .map_err(err)?;
            c.draw_series((0..steps).map(|k| {
                let (a, b) = (k as f64 / steps as f64, (k + 1) as f64 / steps as f64);
                Rectangle::new(
                    [(0.0, lo + a * (hi - lo)), (1.0, lo + b * (hi - lo))],
                    strip((a + b) / 2.0).filled(),
                )
            }))
            .map_err(err)?;
        }
    }
    if !label.is_empty() {
        let (w, h) = bar.dim_in_pixel();
        let style = TextStyle::from((FONT, 12).into_font())
            .transform(FontTransform::Rotate270)
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ));
        bar.draw_text(
            label,
            &style,
            (w as i32 - 10, (h as i32 - X_LABEL_AREA as i32) / 2),
        )
        .map_err(err)?;
    }
    Ok(pixels)
}

/// The size of a heat map's image for cells of `cell_px` pixels.
fn heat_map_size(map: &HeatMap, cell_px: u32) -> io::Result<(u32, u32)> {
    if map.cols == 0 || map.rows == 0 || map.values.len() != map.cols * map.rows || cell_px == 0 {
        return Err(invalid(
            "heat map needs cols · rows = values.len() > 0 and cell_px > 0",
        ));
    }
    let title = if map.title.is_empty() { 0 } else { 30 };
    let w = map.cols as u64 * cell_px as u64 + (2 * MARGIN + Y_LABEL_AREA - 12 + BAR_PANEL) as u64;
    let h = map.rows as u64 * cell_px as u64 + (2 * MARGIN + X_LABEL_AREA + title) as u64;
    if w > 8192 || h > 8192 {
        return Err(invalid("heat map image larger than 8192 pixels"));
    }
    Ok((w.max(160) as u32, h.max(120) as u32))
}

/// The cells of `map` as an RGB raster, `k × k` pixels per cell, top row
/// first.
fn heat_map_raster(map: &HeatMap, k: usize) -> (u32, u32, Vec<u8>) {
    let range = map.color_range();
    let (w, h) = (map.cols * k, map.rows * k);
    let mut rgb = vec![0u8; w * h * 3];
    for py in 0..h {
        let j = map.rows - 1 - py / k;
        for px in 0..w {
            let c = map.color_of(map.values[j * map.cols + px / k], range);
            rgb[(py * w + px) * 3..(py * w + px) * 3 + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    }
    (w as u32, h as u32, rgb)
}

/// Writes `map` as SVG: axes, title and colour bar drawn by plotters, the
/// cells one embedded PNG raster (`data-marks` = number of cells) scaled
/// without smoothing onto the plotting area (at least 256 pixels a side, an
/// integer number of pixels per cell).
///
/// `marks` counts the cells.
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an inconsistent grid.
pub fn write_heat_map_svg(path: &Path, map: &HeatMap) -> io::Result<Figure> {
    let (w, h) = heat_map_size(map, 1)?;
    let (w, h) = (w.max(640), h.max(420));
    let mut area = None;
    let (mut text, _) = render_svg(w, h, |root| {
        area = Some(draw_heat_map(root, map, false)?);
        Ok(0)
    })?;
    let (xs, ys) = area.expect("drawn");
    let k = 256usize
        .div_ceil(map.cols.min(map.rows))
        .clamp(1, 4096 / map.cols.max(map.rows).max(1))
        .max(1);
    let (rw, rh, rgb) = heat_map_raster(map, k);
    let png = super::encode_png(rw, rh, &rgb)?;
    use base64::Engine as _;
    let b64 = base64::engine::general_purpose::STANDARD.encode(&png);
    let image = format!(
        "<image x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" preserveAspectRatio=\"none\" \
         style=\"image-rendering:pixelated\" data-marks=\"{}\" href=\"data:image/png;base64,{b64}\"/>\n",
        xs.start,
        ys.start,
        xs.end - xs.start,
        ys.end - ys.start,
        map.cols * map.rows
    );
    let end = text
        .rfind("</svg>")
        .ok_or_else(|| invalid("plotters wrote no </svg>"))?;
    text.insert_str(end, &image);
    write_file(
        path,
        text.as_bytes(),
        map.cols * map.rows,
        (w, h),
        &map.title,
        map.alt_text(),
    )
}

/// Writes `map` as a PNG with `cell_px × cell_px` pixels per cell, with
/// axes, ticks, labels, title and colour bar.
///
/// `marks` counts the cells.
///
/// # Errors
/// I/O errors; [`io::ErrorKind::InvalidInput`] for an inconsistent grid,
/// `cell_px = 0` or an image larger than 8192 pixels a side.
pub fn write_heat_map_png(path: &Path, map: &HeatMap, cell_px: u32) -> io::Result<Figure> {
    let (w, h) = heat_map_size(map, cell_px)?;
    let (png, _) = render_png(w, h, |root| {
        draw_heat_map(root, map, true)?;
        Ok(0)
    })?;
    write_file(
        path,
        &png,
        map.cols * map.rows,
        (w, h),
        &map.title,
        map.alt_text(),
    )
}
