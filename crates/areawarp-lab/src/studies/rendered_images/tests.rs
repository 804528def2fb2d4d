use super::*;
use crate::estimator::{Method, Sampler};
use crate::figures::verify_figure;

fn tiny() -> ImagesConfig {
    let mut c = ImagesConfig::quick();
    c.ground.grid.cols = 8;
    c.ground.grid.rows = 6;
    c.triptych.grid.cols = 6;
    c.triptych.grid.rows = 4;
    c
}

#[test]
fn pixel_centres_cover_the_rectangle_bottom_row_first() {
    let g = PixelGrid {
        x: (-1.0, 1.0),
        y: (0.0, 2.0),
        cols: 4,
        rows: 2,
    };
    let p = g.receiver(0, 0).unwrap();
    assert_eq!((p.position().x, p.position().y), (-0.75, 0.5));
    let q = g.receiver(3, 1).unwrap();
    assert_eq!((q.position().x, q.position().y), (0.75, 1.5));
    assert_eq!(q.position().z, 0.0);
    let empty = PixelGrid { cols: 0, ..g };
    assert!(reference_image(&standing_light(1.0, 0.5, 1.0).unwrap(), &empty).is_err());
}

#[test]
fn images_match_the_estimators_and_the_exact_reference() {
    let config = tiny();
    let images = run(&config).unwrap();
    let g = &images.ground;
    assert_eq!(g.plain.len(), Sampler::LIGHT.len());
    assert_eq!(g.plain_images[0].len(), config.ground.spp.len());
    let n = g.grid.len();
    // Every pixel estimated, reference positive everywhere in front of the light.
    assert!(g.reference.values.iter().all(|e| *e > 0.0 && e.is_finite()));
    for im in g.plain_images.iter().chain(&g.mis_images).flatten() {
        assert_eq!(im.values.len(), n);
        assert_eq!(im.failed, 0, "{}", im.label);
    }
    // The projected polygon alone is a zero-variance estimator: its image
    // is the reference up to rounding.
    let pp = g
        .plain
        .iter()
        .position(|m| *m == Method::plain(Sampler::ProjectedPolygon))
        .unwrap();
    for im in &g.plain_images[pp] {
        let (image, pixel) = im.rms_errors(&g.reference);
        assert!(image < 1e-12 && pixel < 1e-12, "{image} {pixel}");
    }
    // Area sampling is noisier than the spherical rectangle at 16 spp.
    let at = |s: Sampler| {
        let m = g.plain.iter().position(|m| m.sampler == s).unwrap();
        g.plain_images[m].last().unwrap().rms_errors(&g.reference).0
    };
    assert!(at(Sampler::Area) > at(Sampler::Rectangle));
    // The pixel (0, 0) of the rectangle at 1 spp is the study's estimator
    // on its own points: rerendering gives the same image (determinism).
    let again = run(&config).unwrap();
    assert_eq!(again.ground, images.ground);
    assert_eq!(again.triptych, images.triptych);
    // The triptych: reference, then K = ∞, stratified, K = 0.1, K = 0.001.
    let t = &images.triptych;
    assert_eq!(t.images.len(), 4);
    assert!(t.images[0].label.contains("K = ∞"));
    assert!(t.images[3].label.contains("K=0.001"));
    assert!(t.images.iter().all(|im| im.failed == 0 && im.spp == 36));
}

#[test]
fn figures_csv_and_markdown() {
    let images = run(&tiny()).unwrap();
    let dir = std::env::temp_dir().join(format!("areawarp-images-{}", std::process::id()));
    let figs = images.write_figures(&dir).unwrap();
    assert_eq!(figs.len(), 3);
    for f in &figs {
        let check = verify_figure(&f.path).unwrap();
        assert!(
            check.distinct_colors > 20 && check.dark_pixels > 200,
            "{check:?}"
        );
        assert!(f.title.len() > 200, "caption: {}", f.title);
    }
    // 1 reference + 5 methods × 3 spp × (image + error) cells of 8 × 6.
    assert_eq!(figs[0].marks, (1 + 5 * 3 * 2) * 48);
    assert_eq!(figs[2].marks, (1 + 4 * 2) * 24);
    let csv = std::fs::read_to_string(images.write_csv(&dir).unwrap()).unwrap();
    assert_eq!(csv.lines().count(), 1 + 2 * 5 * 3 + 4);
    let md = images.ground_markdown();
    assert!(md.contains(output::GROUND_FIGURE) && md.contains(output::GROUND_MIS_FIGURE));
    assert!(md.contains("| rectangle+MIS(balance) |"));
    let md = images.triptych_markdown();
    assert!(md.contains(output::TRIPTYCH_FIGURE) && md.contains("| adaptive K=0.001 |"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn error_bound_is_a_high_quantile_and_never_zero() {
    // |e| = 1 … 100 with both signs: the 99th percentile is 99.
    let e: Vec<f64> = (1..=100)
        .map(|k| if k % 2 == 0 { k as f64 } else { -(k as f64) })
        .collect();
    assert_eq!(output::error_bound(e.iter(), 1.0), 99.0);
    assert_eq!(output::error_bound([0.0, f64::NAN].iter(), 0.5), 0.5);
}
