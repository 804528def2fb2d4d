use super::*;
use crate::figures::verify_figure;
use areawarp::harness::sensitivity::check_precision_conditioned;

fn quick() -> &'static PrecisionStudy {
    use std::sync::OnceLock;
    static STUDY: OnceLock<PrecisionStudy> = OnceLock::new();
    STUDY.get_or_init(|| run(&PrecisionConfig::quick()).expect("quick precision study"))
}

#[test]
fn precision_tables_cover_every_warp_variant_and_type() {
    let s = quick();
    for (warp, variants) in warp_variants() {
        for variant in variants {
            for scalar in ["f32", "f64"] {
                let r = s
                    .summary_of(warp, variant, scalar)
                    .unwrap_or_else(|| panic!("{warp} {variant} {scalar} missing"));
                assert!(r.shapes > 0, "{r:?}");
                assert!(r.points >= 64 * r.shapes, "{r:?}");
                assert_eq!(r.reference_non_finite, 0, "{r:?}");
            }
        }
    }
    // Whole ladders: every hard shape is a cell, in both types.
    for (name, _) in hard_triangles() {
        assert!(
            s.cell("spherical-triangle", "literal", &name, "f32")
                .is_some()
        );
    }
    for (name, _) in hard_rectangles() {
        assert!(
            s.cell("spherical-rectangle", "robust", &name, "f64")
                .is_some()
        );
    }
    let md = s.to_markdown();
    for warp in WARPS {
        assert!(
            md.contains(&format!("| {warp} |")),
            "{warp} not in the table"
        );
    }
    assert_eq!(
        s.summary.len(),
        2 * warp_variants().iter().map(|v| v.1.len()).sum::<usize>()
    );
}

#[test]
fn precision_robust_solid_angle_maps_within_kappa_bound_f64() {
    // Mirrors the shapes' own tests: in f64 the robust maps are finite,
    // on the shape and within 16·max(u, κ) on every shape of the
    // ladders (the triangle's test counts "outside" with the 4-unit
    // tolerance, the rectangle's with the κ bound).
    let s = quick();
    for warp in ["spherical-triangle", "spherical-rectangle"] {
        let cells: Vec<&PrecisionCell> = s
            .cells
            .iter()
            .filter(|c| c.warp == warp && c.variant == "robust" && c.scalar == "f64")
            .collect();
        assert!(cells.len() >= 10, "{warp}");
        for c in cells {
            assert!(!c.rejected, "{c:?}");
            assert_eq!(c.non_finite + c.reference_non_finite, 0, "{c:?}");
            let ratio = c.max_kappa_ratio.unwrap_or(f64::INFINITY);
            assert!(ratio <= 1.0, "{c:?}");
            assert_eq!(c.outside_bound, 0, "{c:?}");
            if warp == "spherical-triangle" {
                assert_eq!(c.outside, 0, "{c:?}");
            }
            assert!(c.jacobian_max_dev < 1e-60, "{c:?}");
        }
    }
    // The literal maps are measurably worse somewhere on the ladders.
    let lit = s
        .summary_of("spherical-triangle", "literal", "f64")
        .unwrap();
    let rob = s.summary_of("spherical-triangle", "robust", "f64").unwrap();
    assert!(
        lit.non_finite > 0 || lit.max_ulps > 1e3 * rob.max_ulps.max(1.0),
        "{lit:?}"
    );
}

fn conditioned<T: Real>(
    w: &SphericalTriangle<f64>,
    points: &[(f64, f64)],
) -> areawarp::harness::sensitivity::ConditionedReport {
    let wt = w.at::<T>().unwrap();
    let params = coords(&[wt.a(), wt.b(), wt.c()]);
    check_precision_conditioned::<T, _, _, _>(
        w,
        |p: &[M]| SphericalTriangle::new(vec3_at(p, 0), vec3_at(p, 3), vec3_at(p, 6)),
        &params,
        points,
    )
    .unwrap()
}

#[test]
fn precision_cell_agrees_with_check_precision_conditioned() {
    // The study's own evaluation against the harness's, on robust
    // hard triangles in f64 and f32.
    let points = PrecisionConfig::quick().points();
    // Two hard triangles that f32 accepts (the 1e-10 and 1e-12 sr ones
    // round to degenerate triangles in f32).
    let accepted: Vec<(String, [Vec3<f64>; 3])> = hard_triangles()
        .into_iter()
        .filter(|(_, [a, b, c])| {
            SphericalTriangle::<f32>::new(a.convert(), b.convert(), c.convert()).is_ok()
        })
        .collect();
    assert!(accepted.len() >= 4, "{}", accepted.len());
    for k in [1, accepted.len() - 1] {
        let (name, [a, b, c]) = accepted[k].clone();
        let w = SphericalTriangle::new(a, b, c).unwrap();
        for (r, scalar) in [
            (conditioned::<f64>(&w, &points), "f64"),
            (conditioned::<f32>(&w, &points), "f32"),
        ] {
            let cell = quick()
                .cell("spherical-triangle", "robust", &name, scalar)
                .unwrap();
            let ratio = cell.max_kappa_ratio.unwrap();
            assert!(
                (ratio - r.max_ratio).abs() <= 1e-12 * r.max_ratio.max(1e-300),
                "{name} {scalar}: {ratio} vs {r:?}"
            );
            assert_eq!(cell.non_finite, r.non_finite);
            assert_eq!(cell.outside_bound, r.outside);
        }
    }
}

#[test]
fn precision_study_is_identical_for_one_and_two_threads() {
    let config = PrecisionConfig {
        max_shapes: Some(2),
        heat_map_nodes: 6,
        // The projected polygon's κ (Newton at 256 bits for every
        // perturbed vertex) would dominate the single-thread run.
        warps: Some(
            WARPS
                .iter()
                .filter(|&&w| w != "projected-polygon")
                .map(|w| w.to_string())
                .collect(),
        ),
        random_points: 2,
        ..PrecisionConfig::quick()
    };
    let run_with = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&config).unwrap())
    };
    let one = run_with(1);
    let two = run_with(2);
    assert_eq!(one, two);
    assert!(!one.cells.is_empty() && !one.f32_maps.is_empty());
}

#[test]
fn precision_figures_are_written_and_non_trivial() {
    let s = quick();
    let dir = std::env::temp_dir().join(format!("areawarp-precision-{}", std::process::id()));
    let figs = s.write_figures(&dir).unwrap();
    assert_eq!(figs.len(), s.f32_maps.len());
    // One per warp at least.
    for warp in WARPS {
        assert!(s.f32_maps.iter().any(|m| m.warp == warp), "{warp}");
    }
    for f in &figs {
        let check = verify_figure(&f.path).unwrap();
        assert!(check.marks >= 144, "{f:?}");
        assert!(check.distinct_colors > 1, "{f:?}: a constant map");
    }
    let csv = s.write_csv(&dir).unwrap();
    assert_eq!(csv.len(), 3);
    let cells = std::fs::read_to_string(&csv[0]).unwrap();
    assert_eq!(cells.lines().count(), s.cells.len() + 1);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn precision_config_is_validated() {
    let bad = PrecisionConfig {
        heat_map_nodes: 1,
        ..PrecisionConfig::quick()
    };
    assert!(run(&bad).is_err());
    let bad = PrecisionConfig {
        max_shapes: Some(0),
        ..PrecisionConfig::quick()
    };
    assert!(run(&bad).is_err());
    let bad = PrecisionConfig {
        warps: Some(vec!["torus".to_string()]),
        ..PrecisionConfig::quick()
    };
    assert!(run(&bad).is_err());
    assert_eq!(slug("cubic+1 Newton"), "cubic-1-newton");
    assert_eq!(median(&[3.0, f64::NAN, 1.0]), 2.0);
}
