//! Re-reading written figures: PNG through the `png` crate, SVG through a
//! small well-formedness check that also counts what was drawn.

use super::Rgb;
use std::io;
use std::path::Path;

/// Encodes 8-bit RGB pixels (row-major, top row first) as a PNG with the
/// `png` crate.
///
/// # Errors
/// [`io::ErrorKind::InvalidInput`] if `rgb.len() != 3 · width · height`;
/// encoder errors.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> io::Result<Vec<u8>> {
    if width == 0 || height == 0 || rgb.len() != 3 * width as usize * height as usize {
        return Err(super::invalid("PNG needs 3 · width · height bytes"));
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::High);
        let mut w = enc.write_header().map_err(io::Error::other)?;
        w.write_image_data(rgb).map_err(io::Error::other)?;
        w.finish().map_err(io::Error::other)?;
    }
    Ok(out)
}

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
    /// Number of dark pixels (every channel below 100): axes, ticks and
    /// text — a plot's bitmap without them has (nearly) none.
    pub fn dark_pixels(&self) -> usize {
        self.rgb
            .chunks_exact(3)
            .filter(|p| p[0] < 100 && p[1] < 100 && p[2] < 100)
            .count()
    }
}

/// Decodes a PNG (any colour type and depth the `png` crate reads,
/// expanded and converted to 8-bit RGB).
///
/// # Errors
/// The decoder's error, as text.
pub fn decode_png(bytes: &[u8]) -> Result<PngImage, String> {
    let mut dec = png::Decoder::new(io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = dec.read_info().map_err(|e| e.to_string())?;
    let size = reader
        .output_buffer_size()
        .ok_or("PNG too large to decode")?;
    let mut buf = vec![0u8; size];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    let (w, h) = (info.width as usize, info.height as usize);
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err("indexed PNG not expanded".into()),
    };
    let mut rgb = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        let row = &buf[y * info.line_size..y * info.line_size + w * channels];
        for p in row.chunks_exact(channels) {
            match channels {
                1 | 2 => rgb.extend_from_slice(&[p[0], p[0], p[0]]),
                _ => rgb.extend_from_slice(&p[..3]),
            }
        }
    }
    Ok(PngImage {
        width: info.width,
        height: info.height,
        rgb,
    })
}

/// What [`inspect_svg`] found in an SVG document.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SvgSummary {
    /// Number of elements.
    pub elements: usize,
    /// Data marks: circles and polygons (markers, bands) count 1, coloured
    /// (not grey) rectangles 1, polylines not drawn in black one per vertex,
    /// and an element with `data-marks="k"` counts k. Axes and ticks (black
    /// polylines), grid lines (`<line>`), text and the white background do
    /// not count.
    pub marks: usize,
    /// Number of `<text>` elements.
    pub texts: usize,
    /// Embedded PNG rasters (`data:image/png;base64,…`), all decoded.
    pub embedded_pngs: Vec<PngImage>,
}

fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// Whether an SVG colour is a colour (not a grey, not `none`).
fn coloured(value: Option<&str>) -> bool {
    let Some(v) = value else { return false };
    let v = v.trim().trim_start_matches('#');
    if v.len() != 6 || !v.chars().all(|c| c.is_ascii_hexdigit()) {
        return false;
    }
    let ch = |k: usize| u8::from_str_radix(&v[k..k + 2], 16).unwrap_or(0);
    !(ch(0) == ch(2) && ch(2) == ch(4))
}

/// Checks that `text` is a well-formed SVG document at the level the writers
/// need (one root `<svg>` element; every tag closed and properly nested;
/// attribute quotes balanced; no stray `<` or `&` in text; embedded PNGs
/// decode) and counts its elements, data marks and texts.
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
        let colour = coloured(attribute(body, "fill")) || coloured(attribute(body, "stroke"));
        let black = attribute(body, "stroke").is_some_and(|c| c.eq_ignore_ascii_case("#000000"));
        match name {
            "text" => summary.texts += 1,
            _ if attribute(body, "data-marks").is_some() => {
                summary.marks += attribute(body, "data-marks")
                    .and_then(|k| k.parse::<usize>().ok())
                    .ok_or("bad data-marks")?;
            }
            "circle" | "polygon" => summary.marks += 1,
            "rect" if colour => summary.marks += 1,
            "polyline" if !black => {
                summary.marks +=
                    attribute(body, "points").map_or(0, |p| p.split_whitespace().count());
            }
            _ => {}
        }
        if let Some(href) = attribute(body, "href")
            && let Some(b64) = href.strip_prefix("data:image/png;base64,")
        {
            use base64::Engine as _;
            let png = base64::engine::general_purpose::STANDARD
                .decode(b64)
                .map_err(|e| e.to_string())?;
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
    /// Data marks counted in an SVG ([`SvgSummary::marks`]); 0 for a PNG.
    pub marks: usize,
    /// `<text>` elements of an SVG; 0 for a PNG.
    pub texts: usize,
    /// Distinct colours of a PNG, or of the largest raster embedded in an SVG.
    pub distinct_colors: usize,
    /// Dark pixels of a PNG (axes, ticks, text: [`PngImage::dark_pixels`]).
    pub dark_pixels: usize,
    /// PNG width (0 for an SVG).
    pub width: u32,
    /// PNG height (0 for an SVG).
    pub height: u32,
}

/// Re-reads a figure (an SVG or PNG file) and checks it: an SVG must pass
/// [`inspect_svg`], a PNG must decode ([`decode_png`]). The test of
/// "written, labelled and non-trivial" is then e.g. `check.marks > 0 &&
/// check.texts > 0` (SVG) or `check.distinct_colors > 1 && check.dark_pixels
/// > 0` (PNG).
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
                texts: s.texts,
                distinct_colors: s
                    .embedded_pngs
                    .iter()
                    .map(PngImage::distinct_colors)
                    .max()
                    .unwrap_or(0),
                dark_pixels: 0,
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
                texts: 0,
                distinct_colors: img.distinct_colors(),
                dark_pixels: img.dark_pixels(),
                width: img.width,
                height: img.height,
            })
        }
        _ => Err(format!("{}: not .svg or .png", path.display())),
    }
}
