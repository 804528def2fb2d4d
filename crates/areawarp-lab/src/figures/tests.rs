use super::draw::tick_label;
use super::*;
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("areawarp-figures-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    dir.join(name)
}

#[test]
fn png_round_trip_through_the_png_crate() {
    let (w, h) = (37u32, 23u32);
    let rgb: Vec<u8> = (0..h)
        .flat_map(|y| (0..w).flat_map(move |x| [(x * 7) as u8, (y * 11) as u8, (x ^ y) as u8]))
        .collect();
    let png = encode_png(w, h, &rgb).unwrap();
    assert_eq!(&png[..8], &[0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A]);
    let img = decode_png(&png).unwrap();
    assert_eq!((img.width, img.height), (w, h));
    assert_eq!(img.rgb, rgb);
    // A flipped bit inside IHDR fails its CRC; a truncated file fails.
    let mut bad = png.clone();
    bad[18] ^= 0x40;
    assert!(decode_png(&bad).is_err());
    assert!(decode_png(&png[..png.len() / 2]).is_err());
    assert!(encode_png(2, 2, &[0; 11]).is_err());
}

#[test]
fn svg_inspector_rejects_malformed_and_counts_coloured_marks() {
    assert!(inspect_svg("<svg><g></svg>").is_err());
    assert!(inspect_svg("<svg><g></g>").is_err());
    assert!(inspect_svg("<svg><text>a < b</text></svg>").is_err());
    assert!(inspect_svg("<svg><text>a & b</text></svg>").is_err());
    assert!(inspect_svg("<svg/><svg/>").is_err());
    assert!(inspect_svg("<g/>").is_err());
    assert!(inspect_svg("<svg><rect x=\"1/></svg>").is_err());
    let ok = inspect_svg(
        "<?xml version=\"1.0\"?><!-- c --><svg><rect fill=\"#FFFFFF\"/>\
         <circle fill=\"#1F77B4\"/><polyline stroke=\"#FF7F0E\" points=\"1,2 3,4 5,6\"/>\
         <polyline stroke=\"#000000\" points=\"1,2 3,4\"/><line stroke=\"#E1E1E1\"/><image data-marks=\"5\"/>\
         <text>a &amp; b</text></svg>",
    )
    .unwrap();
    assert_eq!((ok.elements, ok.marks, ok.texts), (8, 1 + 3 + 5, 1));
}

#[test]
fn line_plot_svg_and_png_carry_axes_text_bands_and_legend() {
    let n: Vec<f64> = (0..8).map(|k| 4f64.powi(k + 2)).collect();
    let plot = Plot::new("error <vs> n & more", Axis::log("n"), Axis::log("error"))
        .series(
            Series::new("a", n.iter().map(|&x| (x, x.powf(-0.5))).collect()).with_band(
                n.iter()
                    .map(|&x| (x, 0.8 * x.powf(-0.5), 1.25 * x.powf(-0.5)))
                    .collect(),
            ),
        )
        .series(
            Series::new("b", n.iter().map(|&x| (x, 0.1 * x.powf(-0.75))).collect())
                .marker(Marker::Square),
        )
        // A skipped point (0 on a log axis) breaks the line.
        .series(Series::new(
            "c",
            vec![(16.0, 1e-3), (64.0, 0.0), (256.0, 1e-4), (1024.0, 1e-5)],
        ))
        .series(Series::new("slope -1/2", vec![(16.0, 0.5), (65536.0, 0.5 / 64.0)]).reference())
        // Nothing drawable: not in the legend.
        .series(Series::new("nothing", vec![(0.0, 1.0)]));
    let f = write_line_plot_svg(&tmp("line.svg"), &plot).unwrap();
    assert_eq!(f.marks, 8 + 8 + 3 + 2);
    let text = std::fs::read_to_string(&f.path).unwrap();
    let s = inspect_svg(&text).unwrap();
    assert!(s.marks >= f.marks, "{} < {}", s.marks, f.marks);
    assert!(text.contains("&lt;vs&gt; n &amp; more"), "title escaped");
    assert!(text.contains("slope -1/2") && !text.contains("nothing"));
    assert!(text.contains("<polygon"), "the band");
    // Title, two axis labels, four legend entries, ticks.
    assert!(s.texts >= 1 + 2 + 4 + 6, "{}", s.texts);
    let png = write_line_plot_png(&tmp("line.png"), &plot).unwrap();
    let check = verify_figure(&png.path).unwrap();
    assert_eq!((check.width, check.height), (720, 480));
    assert!(check.distinct_colors > 20, "{check:?}");
    assert!(check.dark_pixels > 500, "axes and text: {check:?}");
}

#[test]
fn scatter_equal_aspect_and_clipping() {
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
    assert!(inspect_svg(&text).unwrap().marks >= 100);
    // Equal aspect: the x and y pixel extents of the data are in ratio 2:1.
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for line in text.lines().filter(|l| l.contains("<circle")) {
        let a = |k: &str| {
            let key = format!(" {k}=\"");
            let s = line.find(&key).unwrap() + key.len();
            line[s..s + line[s..].find('"').unwrap()]
                .parse::<f64>()
                .unwrap()
        };
        xs.push(a("cx"));
        ys.push(a("cy"));
    }
    xs.pop(); // the legend's marker
    ys.pop();
    let span = |v: &[f64]| {
        v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - v.iter().cloned().fold(f64::INFINITY, f64::min)
    };
    let ratio = span(&xs) / span(&ys);
    assert!((ratio - 2.0).abs() < 0.05, "{ratio}");
    // Points outside a fixed range are not drawn.
    let clipped = Plot::new(
        "half",
        Axis::linear("x").with_range(0.0, 2.0),
        Axis::linear("y"),
    )
    .series(Series::new("", pts.clone()));
    let f = write_scatter_svg(&tmp("scatter2.svg"), &clipped).unwrap();
    assert!(f.marks > 30 && f.marks < 70, "{}", f.marks);
    let png = write_scatter_png(&tmp("scatter.png"), &plot.clone().size(300, 240)).unwrap();
    let check = verify_figure(&png.path).unwrap();
    assert_eq!((check.width, check.height), (300, 240));
    assert!(check.dark_pixels > 100, "{check:?}");
    let img = decode_png(&std::fs::read(&png.path).unwrap()).unwrap();
    assert!(
        img.rgb
            .chunks_exact(3)
            .any(|p| Rgb(p[0], p[1], p[2]) == PALETTE[0])
    );
    assert!(write_scatter_png(&tmp("tiny.png"), &plot.size(10, 10)).is_err());
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
    assert!(s.marks >= cols * rows);
    assert_eq!(s.embedded_pngs.len(), 1);
    let img = &s.embedded_pngs[0];
    let k = 16;
    assert_eq!((img.width, img.height), (cols as u32 * k, rows as u32 * k));
    // The bottom-left cell is the minimum, the top-right the maximum.
    assert_eq!(img.pixel(0, rows as u32 * k - 1), Some(viridis(0.0)));
    assert_eq!(img.pixel(cols as u32 * k - 1, 0), Some(viridis(1.0)));
    assert_eq!(
        img.pixel(3 * k + 5, (rows as u32 - 1 - 4) * k + 7),
        Some(MISSING)
    );
    assert!(text.contains("\nerror\n") && text.contains("\nmap\n"));
    let png = write_heat_map_png(&tmp("heat.png"), &map, 8).unwrap();
    assert_eq!(png.marks, cols * rows);
    let check = verify_figure(&png.path).unwrap();
    assert!(
        check.distinct_colors > 20 && check.dark_pixels > 200,
        "{check:?}"
    );
    assert!(HeatMap::new("bad", 3, 3, vec![0.0; 8]).is_err());
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
fn tick_labels() {
    assert_eq!(tick_label(0.0), "0");
    assert_eq!(tick_label(0.2), "0.2");
    assert_eq!(tick_label(1000.0), "1000");
    assert_eq!(tick_label(1e-6), "10⁻⁶");
    assert_eq!(tick_label(2e7), "2·10⁷");
    assert_eq!(tick_label(0.001), "0.001");
}
