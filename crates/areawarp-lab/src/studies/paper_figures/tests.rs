use super::*;
use crate::figures::{FigureKind, verify_figure};
use areawarp::shapes::Sphere;
use areawarp::shapes::polygon_measures::triangle_solid_angle;
use areawarp::warp::Warp;
use std::sync::OnceLock;

fn quick() -> &'static PaperFigures {
    static STUDY: OnceLock<PaperFigures> = OnceLock::new();
    STUDY.get_or_init(|| run(&PaperFiguresConfig::quick()).expect("the quick study runs"))
}

/// The quick and the report's (default) size: the properties the report's
/// text states hold at both.
fn both() -> [&'static PaperFigures; 2] {
    static STUDY: OnceLock<PaperFigures> = OnceLock::new();
    let default =
        STUDY.get_or_init(|| run(&PaperFiguresConfig::default()).expect("the default study runs"));
    [quick(), default]
}

#[test]
fn configurations_out_of_range_are_refused() {
    for bad in [
        PaperFiguresConfig {
            hammersley_points: 128,
            ..PaperFiguresConfig::quick()
        },
        PaperFiguresConfig {
            placement_samples: 901,
            ..PaperFiguresConfig::quick()
        },
        PaperFiguresConfig {
            sphere_strata: 2,
            ..PaperFiguresConfig::quick()
        },
        PaperFiguresConfig {
            cdf_points: 3,
            ..PaperFiguresConfig::quick()
        },
    ] {
        assert!(matches!(run(&bad), Err(WarpError::InvalidParameter { .. })));
    }
}

#[test]
fn the_triangle_pair_is_measure_preserving_but_not_stratified_like_the_rectangle() {
    for study in both() {
        let t = &study.triangle_pair;
        let k = t.grid;
        assert_eq!(t.pair_points.len(), k * k);
        // The first triangle's probability is its share of the solid angle.
        let [s, ex, ey, o] = t.geometry;
        let (p0, p1, p2, p3) = (s, s.add(&ex), s.add(&ex).add(&ey), s.add(&ey));
        let r = |p: &areawarp::vector::Vec3<f64>| p.sub(&o);
        let w1 = triangle_solid_angle(&r(&p0), &r(&p1), &r(&p2)).abs();
        let w2 = triangle_solid_angle(&r(&p0), &r(&p2), &r(&p3)).abs();
        assert!((t.first_probability - w1 / (w1 + w2)).abs() < 1e-12);
        // Every pair point lies on the rectangle (in its plane, inside).
        for p in &t.pair_points {
            let q = p.sub(&s);
            assert!(q.z.abs() < 1e-12);
            assert!(q.x > -1e-12 && q.x < 2.0 + 1e-12 && q.y > -1e-12 && q.y < 2.0 + 1e-12);
        }
        // One point per cell for the rectangle map; holes and doubles for the
        // pair, fewer than for independent points.
        assert_eq!(t.rectangle_cells, (1, 1));
        assert_eq!(t.chi2[1], 0.0);
        assert!(t.pair_empty_cells > 0 && t.pair_crowded_cells > 0);
        assert!(t.chi2[0] > 0.0 && t.chi2[0] < t.chi2[2]);
        assert_eq!(t.empty_cell_centres.len(), t.pair_empty_cells);
    }
}

#[test]
fn adaptive_partitions_meet_the_stopping_rule_and_sum_to_lamberts_measure() {
    for study in both() {
        let a = &study.adaptive;
        assert!(a.k_whole > PARTITION_THRESHOLDS[0]);
        let mut last = 0;
        for row in &a.partitions {
            assert!(row.max_k < row.threshold, "{row:?}");
            assert_eq!(row.capped, 0);
            assert!((row.sigma_perp_sum / a.projected_solid_angle - 1.0).abs() < 1e-12);
            assert!(row.pieces.len() > last, "smaller K, more pieces");
            last = row.pieces.len();
        }
        let [strat, coarse, fine] = &a.placements[..] else {
            panic!("three placements")
        };
        for p in &a.placements {
            assert_eq!(p.directions.len(), 900);
        }
        let dof = (a.measure_cells - 1) as f64;
        // P ∝ σ fits σ, not σ⊥; the adaptive sets fit σ⊥, not σ.
        assert!(crate::verdict::chi2_p_value(strat.chi2_projected, dof) < 1e-6);
        assert!(strat.chi2_solid_angle < dof);
        for p in [coarse, fine] {
            assert!(
                crate::verdict::chi2_p_value(p.chi2_projected, dof) > 1e-3,
                "{}",
                p.method
            );
            assert!(
                crate::verdict::chi2_p_value(p.chi2_solid_angle, dof) < 1e-6,
                "{}",
                p.method
            );
        }
        // K = 0.001 spaces its samples more evenly than K = 0.1.
        assert!(fine.nn_cv < coarse.nn_cv && fine.nn_mean > coarse.nn_mean);
    }
}

#[test]
fn the_marginal_cdf_is_monotone_from_0_to_1_and_the_cubic_inverts_it() {
    for study in both() {
        let m = &study.marginal;
        assert_eq!(m.decreasing_steps, 0);
        assert_eq!(m.curve.first().map(|p| p.1), Some(0.0));
        assert_eq!(m.curve.last().map(|p| p.1), Some(1.0));
        // A breakpoint per vertex meridian, plus the closing turn.
        assert_eq!(m.breakpoints.len(), m.vertices.len() + 1);
        assert!(m.breakpoints.windows(2).all(|w| w[1].1 > w[0].1));
        assert!(m.max_fluctuation() > 1e-4, "F is not piecewise linear");
        assert!(m.max_cubic_error() > 0.0 && m.max_cubic_error() < 1e-3);
        assert!(m.max_newton_error() < 1e-13);
        assert_eq!(m.lunes, m.vertices.len());
    }
}

#[test]
fn archimedes_samples_are_uniform_and_the_box_rejection_keeps_the_triangle() {
    for study in both() {
        let s = &study.sphere;
        assert!((s.cell_solid_angle_sum - 4.0 * std::f64::consts::PI).abs() < 1e-12);
        assert_eq!(s.cells, 80);
        let dof = (s.cells - 1) as f64;
        assert!(crate::verdict::chi2_p_value(s.chi2[0], dof) > 1e-3);
        assert!(s.chi2[1] < s.chi2[0] && s.resultant[1] < s.resultant[0]);
        for set in &s.drawn {
            assert!(set.iter().all(|d| (d.norm() - 1.0).abs() < 1e-14));
        }

        let t = &study.sphere_triangle;
        let sphere = Sphere::<f64>::new();
        // The box holds the triangle's vertices.
        for v in &t.vertices {
            let [u, w] = sphere.inverse(v).expect("a unit direction");
            assert!(t.bounding_box.contains(u, w), "{u} {w}");
        }
        // Kept points are inside the triangle (signs of the edge planes), the
        // rejected ones outside.
        let [a, b, c] = t.vertices;
        let det = |p: &areawarp::vector::Vec3<f64>,
                   q: &areawarp::vector::Vec3<f64>,
                   r: &areawarp::vector::Vec3<f64>| { p.dot(&q.cross(r)) };
        let sign = det(&a, &b, &c).signum();
        for (d, kept) in t.drawn.iter().flatten() {
            let depth = (sign * det(&a, &b, d))
                .min(sign * det(&b, &c, d))
                .min(sign * det(&c, &a, d));
            if depth.abs() > 1e-9 {
                assert_eq!(*kept, depth > 0.0);
            }
        }
        // The kept fraction is Ω/|B| within 4 binomial standard errors.
        let p = t.solid_angle / t.bounding_box.measure();
        let n = t.measure_points as f64;
        let se = (p * (1.0 - p) / n).sqrt();
        for k in t.kept {
            assert!(
                (k as f64 / n - p).abs() < 4.0 * se,
                "{k} of {n}, expected {p}"
            );
        }
        assert!(t.chi2[1] < t.chi2[0]);
    }
}

#[test]
fn every_figure_is_written_valid_titled_and_shown_in_its_section() {
    let study = quick();
    let dir = std::env::temp_dir().join(format!("areawarp-paper-figures-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let figs = study.write_figures(&dir).expect("figures written");
    let stems = PaperFigures::figure_stems();
    assert_eq!(figs.len(), 2 * stems.len());
    for f in &figs {
        let check = verify_figure(&f.path).expect("a valid figure");
        match check.kind {
            FigureKind::Svg => assert!(check.marks >= 2 && check.texts >= 4, "{check:?}"),
            FigureKind::Png => assert!(check.distinct_colors >= 2 && check.dark_pixels >= 200),
        }
        // The alt text describes the picture: not a file name.
        assert!(f.title.split_whitespace().count() > 12, "{}", f.title);
        assert!(!f.title.contains(".svg"));
    }
    let md = [
        study.ufk_markdown(),
        study.urena_markdown(),
        study.arvo_markdown(),
        study.shao_markdown(),
    ];
    for stem in &stems {
        let shown = md
            .iter()
            .filter(|m| m.contains(&format!("({stem}.svg)")))
            .count();
        assert_eq!(shown, 1, "{stem} is shown in exactly one section");
        assert!(md.iter().any(|m| m.contains(&format!("({stem}.png)"))));
    }
    assert!(md[0].contains("ufk2013_fig5") && md[1].contains("urena2000_fig3"));
    assert!(md[2].contains("arvo2001_fig1_9") && md[3].contains("shao_badler1996_fig4"));
    let csv = std::fs::read_to_string(study.write_csv(&dir).unwrap()).unwrap();
    assert!(csv.lines().count() > 30);
    assert!(csv.lines().skip(1).all(|l| l.split(',').count() >= 4));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_study_is_deterministic_for_a_seed() {
    let config = PaperFiguresConfig::quick();
    let a = run(&config).unwrap();
    let b = run(&config).unwrap();
    assert_eq!(a.urena_markdown(), b.urena_markdown());
    assert_eq!(a.shao_markdown(), b.shao_markdown());
    let other = run(&PaperFiguresConfig {
        seed: config.seed + 1,
        ..config
    })
    .unwrap();
    assert_ne!(a.shao_markdown(), other.shao_markdown());
}
