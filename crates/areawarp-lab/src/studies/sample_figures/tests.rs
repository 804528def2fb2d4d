use super::output::*;
use super::*;
use crate::figures::{FigureKind, verify_figure};

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "areawarp-sample-figures-{tag}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn figures_are_written_and_non_trivial() {
    let study = run(&SampleFiguresConfig::quick()).unwrap();
    let dir = temp_dir("quick");
    let figs = study.write_figures(&dir).unwrap();
    assert_eq!(figs.len(), 14);
    let n = study.config.strata * study.config.strata;
    let h = study.config.hammersley_points;
    let samples = [n, n, n, n, h, h, h];
    for (k, stem) in SampleFigures::figure_stems().iter().enumerate() {
        let svg = &figs[2 * k];
        let png = &figs[2 * k + 1];
        assert_eq!(svg.path, dir.join(format!("{stem}.svg")));
        assert_eq!(png.path, dir.join(format!("{stem}.png")));
        let check = verify_figure(&svg.path).unwrap();
        assert_eq!(check.kind, FigureKind::Svg);
        assert!(check.marks >= svg.marks, "{stem}: {check:?}");
        assert!(check.texts >= 4, "{stem}: title, axis labels, ticks");
        // Every sample is drawn as a marker, plus the outline's vertices.
        let text = std::fs::read_to_string(&svg.path).unwrap();
        let circles = text.matches("<circle").count();
        assert!(circles >= samples[k], "{stem}: {circles} circles");
        assert!(check.marks > circles + 100, "{stem}: {}", check.marks);
        let check = verify_figure(&png.path).unwrap();
        assert_eq!(check.kind, FigureKind::Png);
        assert_eq!((check.width, check.height), (png.width, png.height));
        assert!(png.width >= 480 && png.height >= 380);
        assert!(check.dark_pixels > 100, "{stem}: axes and text");
        // White, the frame, the outline and the samples (at least).
        assert!(
            check.distinct_colors >= 4,
            "{stem}: {}",
            check.distinct_colors
        );
        let img = figures::decode_png(&std::fs::read(&png.path).unwrap()).unwrap();
        let blue = img
            .rgb
            .chunks_exact(3)
            .filter(|p| Rgb(p[0], p[1], p[2]) == SAMPLES)
            .count();
        assert!(blue >= samples[k], "{stem}: {blue} sample pixels");
    }
    let csv = study.write_csv(&dir).unwrap();
    let text = std::fs::read_to_string(&csv[0]).unwrap();
    assert_eq!(text.lines().count(), 1 + study.rows().len());
    // Four fields per line (commas inside quoted fields do not count).
    for line in text.lines() {
        let mut quoted = false;
        let mut commas = 0;
        for c in line.chars() {
            match c {
                '"' => quoted = !quoted,
                ',' if !quoted => commas += 1,
                _ => {}
            }
        }
        assert_eq!((commas, quoted), (3, false), "{line}");
    }
    assert!(text.contains("\"chi2 over 4 sub-triangles, 256 uniform random;"));
    let md = study.to_markdown();
    for stem in SampleFigures::figure_stems() {
        assert!(md.contains(&format!("({stem}.svg)")), "{stem}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn jittered_triangle_samples_are_more_even_than_random() {
    for seed in [1u64, 2, 3] {
        let config = SampleFiguresConfig {
            seed,
            ..SampleFiguresConfig::default()
        };
        let t = run_triangle(&config).unwrap();
        let cells = t.cell_solid_angles.len();
        assert_eq!(cells, 16);
        assert_eq!((t.random.len(), t.jittered.len()), (256, 256));
        // The sub-triangles tile the triangle.
        let total: f64 = t.cell_solid_angles.iter().sum();
        assert!((total - t.solid_angle).abs() < 1e-12 * t.solid_angle);
        assert!((0.9..1.2).contains(&t.solid_angle), "{}", t.solid_angle);
        assert_eq!(t.measure_samples, 4096);
        assert_eq!(t.random_counts.iter().sum::<usize>(), 4096);
        assert_eq!(t.jittered_counts.iter().sum::<usize>(), 4096);
        assert!(t.max_outside_by < 1e-14);
        // Random: χ² of 15 degrees of freedom (99.9% below 37.7).
        assert!(t.random_chi2 < 37.7, "{seed}: {}", t.random_chi2);
        // Jittered: far below the random expectation (15), and below
        // the 1% quantile of χ²(15), 5.23.
        assert!(t.jittered_chi2 < 3.0, "{seed}: {}", t.jittered_chi2);
        assert!(t.jittered_chi2 < t.random_chi2 / 3.0);
    }
}

#[test]
fn projected_polygon_samples_are_inside_and_cosine_weighted() {
    let config = SampleFiguresConfig::default();
    let p = run_polygon(&config).unwrap();
    let n = p.random.len();
    assert_eq!((n, p.jittered.len(), p.measure_samples), (256, 256, 4096));
    assert_eq!(p.random_inside, n);
    assert_eq!(p.jittered_inside, n);
    assert_eq!(p.measure_inside, 2 * 4096);
    assert_eq!(p.random_counts.iter().sum::<usize>(), 4096);
    assert_eq!(p.jittered_counts.iter().sum::<usize>(), 4096);
    assert!(p.max_outside_by < 1e-12, "{}", p.max_outside_by);
    // The cells' projected solid angles add up to Lambert's Π of the
    // whole comb, which is the map's measure.
    let sum: f64 = p.cell_fractions.iter().sum();
    assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    let sum: f64 = p.cell_fractions_uniform.iter().sum();
    assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    assert!((plane_measures(&p.vertices).1 - p.projected_solid_angle).abs() < 1e-12);
    let cells = p.cell_fractions.len();
    assert!(cells >= 20, "{cells}");
    let dof = (cells - 1) as f64;
    // Random: within the bulk of χ²(dof); jittered: far more even.
    assert!(
        p.random_chi2 < dof + 6.0 * (2.0 * dof).sqrt(),
        "{}",
        p.random_chi2
    );
    assert!(p.jittered_chi2 < dof / 2.0, "{} {dof}", p.jittered_chi2);
    // The same counts are far from uniform-in-solid-angle.
    assert!(
        p.jittered_chi2_uniform > dof + 6.0 * (2.0 * dof).sqrt(),
        "{} {dof}",
        p.jittered_chi2_uniform
    );
}

#[test]
fn rectangle_samples_follow_the_solid_angle() {
    let config = SampleFiguresConfig::default();
    let r = run_rectangle(&config).unwrap();
    let n = r.points.len();
    assert_eq!((n, r.grid), (256, 16));
    assert!((r.solid_angle - r.solid_angle_triangles).abs() < 1e-13);
    // One solid-angle sample per equal-solid-angle cell; area sampling
    // leaves cells empty and crowds others.
    assert_eq!(r.solid_angle_cells, (1, 1));
    assert_eq!(r.solid_angle_empty_cells, 0);
    assert_eq!(r.area_cells.0, 0);
    assert!(r.area_cells.1 >= 4, "{:?}", r.area_cells);
    assert!(r.area_empty_cells > 50, "{}", r.area_empty_cells);
    // The near and far quarters: counts within the net's bound (the
    // number of grid cells a boundary curve can cross, 2k) of the exact
    // solid-angle fractions — and in fact within a few points.
    let near = r.near_fraction_exact * n as f64;
    let far = r.far_fraction_exact * n as f64;
    assert!(near > 100.0 && far < 20.0, "{near} {far}");
    let bound = 2.0 * r.grid as f64;
    assert!((r.near_count as f64 - near).abs() <= bound);
    assert!((r.far_count as f64 - far).abs() <= bound);
    assert!(
        (r.near_count as f64 - near).abs() <= 3.0,
        "{} {near}",
        r.near_count
    );
    assert!(
        (r.far_count as f64 - far).abs() <= 3.0,
        "{} {far}",
        r.far_count
    );
    // Area sampling puts exactly a quarter there, far off.
    assert_eq!((r.area_near_count, r.area_far_count), (n / 4, n / 4));
    // ... beyond the bound the solid-angle samples meet.
    assert!(near - r.area_near_count as f64 > bound);
    assert!(r.area_far_count as f64 - far > bound);
    // Points are on the rectangle, and each direction points at its point.
    for (p, d) in r.points.iter().zip(&r.directions) {
        let q = p.sub(&r.observer);
        assert!(q.cross(d).norm() < 1e-12 * q.norm());
        assert!(p.z.abs() < 1e-12);
    }
}

#[test]
fn deterministic_for_a_fixed_seed() {
    let config = SampleFiguresConfig::quick();
    let a = run(&config).unwrap();
    let b = run(&config).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.to_markdown(), b.to_markdown());
    let other = run(&SampleFiguresConfig {
        seed: config.seed + 1,
        ..config.clone()
    })
    .unwrap();
    assert_ne!(a.triangle.random, other.triangle.random);
    assert_ne!(a.polygon.jittered, other.polygon.jittered);
    // Hammersley points do not depend on the seed.
    assert_eq!(a.rectangle, other.rectangle);
}

#[test]
fn invalid_configurations_are_rejected() {
    let ok = SampleFiguresConfig::quick();
    for bad in [
        SampleFiguresConfig {
            strata: 1,
            ..ok.clone()
        },
        SampleFiguresConfig {
            hammersley_points: 128,
            ..ok.clone()
        },
        SampleFiguresConfig {
            hammersley_points: 2,
            ..ok.clone()
        },
        SampleFiguresConfig {
            triangle_levels: 0,
            ..ok.clone()
        },
        SampleFiguresConfig {
            polygon_cell: f64::NAN,
            ..ok.clone()
        },
    ] {
        assert!(matches!(run(&bad), Err(WarpError::InvalidParameter { .. })));
    }
}

#[test]
fn helpers() {
    // Equal-area projection: radius 2 sin(θ/2), seen from the centre.
    let p = EqualArea::about(&v3(0.0, 0.0, 1.0), &v3(1.0, 0.0, 0.0));
    let (x, y) = p.project(&v3(1.0, 0.0, 0.0));
    assert!((x - 2f64.sqrt()).abs() < 1e-15 && y.abs() < 1e-15);
    let (x, y) = p.project(&v3(0.0, 1.0, 1.0));
    assert!(x.abs() < 1e-15 && (y + 2.0 * (std::f64::consts::PI / 8.0).sin()).abs() < 1e-15);
    // Clipping the comb to its bounding box changes nothing; to a box
    // across a gap between two teeth it keeps both pieces.
    let comb = comb();
    let (o, pi) = plane_measures(&comb);
    let (o2, pi2) = plane_measures(&clip_to_box(&comb, -2.0, 2.0, -2.0, 2.0));
    assert!((o - o2).abs() < 1e-15 && (pi - pi2).abs() < 1e-15);
    let piece = clip_to_box(&comb, -1.2, 1.2, -1.4, -1.0);
    let (_, p_two) = plane_measures(&piece);
    let (_, p_a) = plane_measures(&clip_to_box(&comb, -1.2, 0.0, -1.4, -1.0));
    let (_, p_b) = plane_measures(&clip_to_box(&comb, 0.0, 1.2, -1.4, -1.0));
    assert!((p_two - p_a - p_b).abs() < 1e-15);
    assert!(inside_polygon(&comb, (0.0, -1.0)) && !inside_polygon(&comb, (0.8, -1.0)));
    assert_eq!(densify(&[(0.0, 0.0), (1.0, 0.0)], 0.25).len(), 5);
}
