use super::*;
use crate::figures::verify_figure;
use crate::scene::{Emitter, PlanarPolygon};
use crate::studies::variance::{self, VarianceConfig};
use areawarp::vector::Vec3;
use std::sync::OnceLock;

fn quick() -> &'static AdaptiveComparison {
    static QUICK: OnceLock<AdaptiveComparison> = OnceLock::new();
    QUICK.get_or_init(|| run_comparison(&AdaptiveComparisonConfig::quick()).unwrap())
}

/// The quick configuration with the occluders kept (our extension).
fn quick_occluded() -> &'static AdaptiveComparison {
    static QUICK: OnceLock<AdaptiveComparison> = OnceLock::new();
    QUICK.get_or_init(|| {
        run_comparison(&AdaptiveComparisonConfig {
            occluders: true,
            ..AdaptiveComparisonConfig::quick()
        })
        .unwrap()
    })
}

/// A smaller configuration for the determinism test.
fn tiny() -> AdaptiveComparisonConfig {
    AdaptiveComparisonConfig {
        receivers_per_side: 2,
        spp: vec![4, 16, 64],
        runs: 2,
        reference: ReferenceConfig {
            replicas: 2,
            side: 16,
        },
        // Timings differ from run to run: not part of the determinism.
        cost: None,
        ..AdaptiveComparisonConfig::quick()
    }
}

#[test]
fn results_are_identical_for_one_and_two_threads() {
    let config = tiny();
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run_comparison(&config).unwrap())
    };
    let one = in_pool(1);
    let two = in_pool(2);
    assert_eq!(one.measurement, two.measurement);
    assert_eq!(one.references, two.references);
    assert_eq!(one.claims(), two.claims());
    // Same seed, same thread count: the same again.
    let again = in_pool(2);
    assert_eq!(again.measurement, two.measurement);
    // Another seed: other errors, the same references' exact parts.
    let other = run_comparison(&AdaptiveComparisonConfig {
        seed: config.seed + 1,
        ..config.clone()
    })
    .unwrap();
    assert_ne!(other.measurement, one.measurement);
    for (a, b) in other.references.iter().zip(&one.references) {
        assert_eq!(a.unoccluded, b.unoccluded);
    }
}

#[test]
fn adaptive_estimator_is_unbiased_for_constant_radiance() {
    // A tilted triangle light, no occluders: Lambert is exact.
    let light = PlanarPolygon::triangle(
        Vec3::new(-1.0, 0.3, 0.1),
        Vec3::new(0.2, 0.1, 1.5),
        Vec3::new(1.2, 0.5, 0.3),
    )
    .unwrap();
    let scene = Scene::new(Emitter::constant(light, 2.0).unwrap().with_two_sided(true));
    let rx = Receiver::new(Vec3::new(0.1, 0.8, 0.0), Vec3::new(0.0, 0.0, 1.0)).unwrap();
    let exact = lambert::irradiance(scene.emitter(), &rx);
    assert!(exact > 0.0);
    let empty: [(f64, f64); 0] = [];
    for (k, allocation) in [
        (f64::INFINITY, Allocation::Systematic),
        (0.1, Allocation::Systematic),
        (0.1, Allocation::Multinomial),
        (0.001, Allocation::Systematic),
    ] {
        let est = AdaptiveEstimator::new(k).with_allocation(allocation);
        let mut p = est.prepare(&scene, &rx).unwrap();
        let mut stats = Stats::new();
        let n = 5;
        let pts = vec![(0.5, 0.5); n];
        for seed in 0..2000u64 {
            let batch = Batch {
                light: &pts,
                partner: &empty,
                point_set: PointSet::Jittered,
                seed,
            };
            stats.push(p.estimate(&batch).unwrap());
        }
        let z = (stats.mean() - exact) / stats.std_error();
        assert!(
            z.abs() < 4.0,
            "{}: mean {} vs exact {exact} (z = {z})",
            est.name(),
            stats.mean()
        );
        // The estimates vary (it draws its own points), less so for
        // small K; the same seed gives the same estimate.
        assert!(stats.std_error() > 0.0);
        let batch = Batch {
            light: &pts,
            partner: &empty,
            point_set: PointSet::Jittered,
            seed: 7,
        };
        assert_eq!(p.estimate(&batch).unwrap(), p.estimate(&batch).unwrap());
        if k == 0.001 {
            // Near the ideal density: relative std of one estimate
            // below √(K/n)-ish for a constant integrand.
            let rel = stats.variance().sqrt() / exact;
            assert!(rel < 0.02, "{rel}");
        }
    }
    // Names.
    assert_eq!(AdaptiveEstimator::new(0.1).name(), "adaptive K=0.1");
    assert_eq!(AdaptiveEstimator::new(f64::INFINITY).name(), "adaptive K=∞");
    assert_eq!(
        AdaptiveEstimator::new(0.001)
            .with_allocation(Allocation::Successive)
            .name(),
        "adaptive K=0.001 (successive)"
    );
}

#[test]
fn adaptive_estimator_rejects_non_triangles_and_bad_thresholds() {
    let light = PlanarPolygon::rectangle(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    )
    .unwrap();
    let scene = Scene::new(Emitter::constant(light, 1.0).unwrap().with_two_sided(true));
    let rx = Receiver::new(Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0)).unwrap();
    assert!(AdaptiveEstimator::new(0.1).prepare(&scene, &rx).is_err());
    let bad = AdaptiveComparisonConfig {
        thresholds: vec![0.0],
        ..tiny()
    };
    assert!(run_comparison(&bad).is_err());
    let bad = AdaptiveComparisonConfig {
        reference: ReferenceConfig {
            replicas: 1,
            side: 8,
        },
        ..tiny()
    };
    assert!(run_comparison(&bad).is_err());
}

#[test]
fn references_are_exact_where_unshadowed_and_accurate_elsewhere() {
    // Without occluders (the paper's Fig. 9) every reference is exact.
    assert!(
        quick()
            .references
            .iter()
            .all(|r| r.blocked == 0.0 && r.std_error == 0.0)
    );
    let q = quick_occluded();
    let shadowed = q.references.iter().filter(|r| r.blocked > 0.0).count();
    assert!(shadowed >= 2, "the occluders must shadow some receivers");
    for r in &q.references {
        assert!(r.value > 0.0 && r.value <= r.unoccluded);
        if r.blocked == 0.0 {
            assert_eq!(r.std_error, 0.0);
            assert_eq!(r.value, r.unoccluded);
        }
    }
    // Much more accurate than the errors they judge.
    assert!(
        q.max_reference_error() < 0.1 * q.min_rms_error(),
        "{} vs {}",
        q.max_reference_error(),
        q.min_rms_error()
    );
    // A converged estimate by jittered solid-angle sampling agrees.
    let setup = setup::patterned_triangle(5, 1.0, 0.1, 3).unwrap();
    let (i, r) = q
        .references
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.blocked.total_cmp(&b.1.blocked))
        .unwrap();
    let rx = &setup.receivers[i];
    let s = Method::plain(Sampler::TrianglePair)
        .sampler
        .strategy(&setup.scene, rx)
        .unwrap();
    let mut rng = job_rng(3, 0);
    let e = areawarp::estimate::monte_carlo(
        &*s,
        |d| setup.scene.integrand(rx, &Quantity::Irradiance, d),
        jittered_iter::<f64, _>(300, 300, &mut rng),
    );
    assert!(
        (e.value / r.value - 1.0).abs() < 2e-3,
        "{} vs {}",
        e.value,
        r.value
    );
}

#[test]
fn errors_decrease_with_spp() {
    let ms = &quick().measurement;
    let last = ms.spp.len() - 1;
    assert_eq!(ms.spp[last], 256);
    assert!(ms.failures.is_empty(), "{:?}", ms.failures);
    for m in 0..ms.methods.len() {
        let c = ms.curve(Subset::All, m, 0);
        assert!(
            c[last].rms_relative_error < 0.35 * c[0].rms_relative_error,
            "{}: {c:?}",
            ms.methods[m]
        );
        // Every factor 4 in spp (4 → 16 → 64 → 256) lowers the error.
        for (a, b) in [(0, 1), (1, 3), (3, 4)] {
            assert!(
                c[b].rms_relative_error < c[a].rms_relative_error,
                "{}: {c:?}",
                ms.methods[m]
            );
        }
        // No visible bias: the mean relative error is within 4.5
        // standard errors of 0 (rms/√count bounds its standard error).
        assert!(
            c.iter().all(|p| p.mean_relative_error.abs()
                < 4.5 * p.rms_relative_error / (p.estimates as f64).sqrt()),
            "{}: {c:?}",
            ms.methods[m]
        );
    }
    // Stratification beats independent points at 256 spp.
    let q = quick();
    assert!(q.rms_error(STRATIFIED_SOLID_ANGLE, 256) < q.rms_error("adaptive K=∞", 256));
    assert!(q.rms_error(STRATIFIED_COSINE, 256) < q.rms_error(RANDOM_COSINE, 256));
}

#[test]
fn markdown_has_the_tables_and_the_claims() {
    let q = quick();
    let section = q.section();
    assert_eq!(section.slug, "adaptive");
    let md = &section.markdown;
    assert!(md.contains("#### Relative RMS error vs spp"));
    assert!(md.contains("| method | 4 spp | 16 spp | 36 spp | 64 spp | 256 spp | α (fit) |"));
    for name in [
        STRATIFIED_SOLID_ANGLE,
        STRATIFIED_COSINE,
        RANDOM_COSINE,
        "adaptive K=∞",
        "adaptive K=0.1",
        "adaptive K=0.001",
    ] {
        assert!(md.contains(&format!("| {name} |")), "{name}");
    }
    assert!(md.contains("#### Error ratio adaptive / stratified solid angle"));
    // The claims are listed once, in the variance study's claims table.
    assert!(!md.contains("#### Claims"));
    assert!(md.contains("occluders removed as in the paper"));
    // The figure written by `VarianceStudy::write_figures`, shown
    // (the report's figures sit beside index.md).
    assert!(md.contains("![variance_adaptive.svg](variance_adaptive.svg)"));
    let claims = &section.claims;
    // Fig. 9 ×2, every-spp ×2, Fig. 7, the bound ×2, cost ×2.
    assert_eq!(claims.len(), 9);
    for c in claims {
        assert_ne!(c.verdict, Verdict::NotMeasured, "{}", c.statement);
        assert!(!c.measured.is_empty());
    }
    // The every-spp and K-comparison rows are our questions, not the paper's.
    assert_eq!(claims.iter().filter(|c| c.is_our_question()).count(), 3);
    assert_eq!(section.claims_image.len(), claims.len());
    // With the occluders, the paper's claims are marked as our extension.
    let ext = quick_occluded().section();
    assert_eq!(ext.slug, "adaptive_occluded");
    assert!(ext.claims.iter().all(|c| c.is_our_question()));
    // Stratification pays off (paper's Fig. 9, top vs middle): at
    // least the direction, at 36 spp.
    assert_ne!(
        claims[0].verdict,
        Verdict::NotReproduced,
        "{}",
        claims[0].measured
    );
    // Ureña's bound holds for both thresholds.
    for c in &claims[5..7] {
        assert_eq!(c.verdict, Verdict::Reproduced, "{}", c.measured);
    }
    // The partitions: K = 0.1 is coarse and counted everywhere,
    // K = 0.001 has more than PIECE_LIMIT pieces everywhere.
    assert_eq!(q.partitions.len(), 2);
    let (coarse, fine) = (&q.partitions[0], &q.partitions[1]);
    assert_eq!((coarse.k, coarse.over_limit), (0.1, 0));
    assert_eq!(coarse.counts.len(), 9);
    assert!(coarse.range().unwrap().0 >= 4);
    assert_eq!((fine.k, fine.over_limit), (0.001, 9));
    assert!(md.contains("more than 10000 pieces at 9 receivers"));
    // Without the random methods some claims cannot be judged.
    let mut config = tiny();
    config.thresholds = vec![0.1];
    let partial = run_comparison(&config).unwrap();
    assert!(
        partial
            .claims()
            .iter()
            .any(|c| c.verdict == Verdict::NotMeasured)
    );
}

#[test]
fn the_section_attaches_and_writes_csv_and_figure() {
    let mut study = variance::run(&VarianceConfig {
        max_log2_spp: 2,
        runs: 1,
        rows: 2,
        occluders: None,
        ..VarianceConfig::quick()
    })
    .unwrap();
    let section = quick().section();
    let claims = section.claims.clone();
    study.attach(section);
    assert!(
        study
            .to_markdown()
            .contains("### Adaptive vs stratified (Ureña 2000, Fig. 9: occluders removed)")
    );
    let all = study.claims();
    for c in &claims {
        assert!(all.contains(c));
    }
    let dir = std::env::temp_dir().join(format!(
        "areawarp-adaptive-comparison-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    let paths = study.write_csv(&dir).unwrap();
    let csv_path = dir.join("variance_adaptive_curves.csv");
    assert!(paths.contains(&csv_path));
    let csv = std::fs::read_to_string(&csv_path).unwrap();
    let ms = &quick().measurement;
    assert_eq!(csv.lines().count(), 1 + ms.methods.len() * 2 * ms.spp.len());
    assert!(csv.contains("adaptive K=0.001,jittered,all,256,"));
    let claims_csv = std::fs::read_to_string(dir.join("variance_claims.csv")).unwrap();
    assert!(claims_csv.contains("Ureña 2000, §5 / Fig. 9"));
    let figs = study.write_figures(&dir).unwrap();
    let fig = figs
        .iter()
        .find(|f| f.path.ends_with("variance_adaptive.svg"))
        .unwrap();
    let check = verify_figure(&fig.path).unwrap();
    // Six curves × five levels at least.
    assert!(fig.marks >= 6 * 5, "{}", fig.marks);
    assert!(check.marks >= fig.marks, "{check:?}");
    let svg = std::fs::read_to_string(&fig.path).unwrap();
    assert!(svg.contains("adaptive K=0.001") && svg.contains(STRATIFIED_SOLID_ANGLE));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn equal_time_table_figure_and_cost_claims() {
    let q = quick();
    let cost = q.cost.as_ref().expect("timed");
    let ms = &q.measurement;
    assert_eq!(cost.costs.len(), ms.methods.len());
    assert_eq!(cost.receivers, 9);
    let s = q.index(COST_BASELINE).unwrap();
    for (m, c) in cost.costs.iter().enumerate() {
        assert_eq!(c.method, ms.methods[m]);
        assert_eq!(c.skipped, 0);
        assert_eq!(c.per_estimate.len(), ms.spp.len());
        for (l, t) in c.per_estimate.iter().enumerate() {
            assert_eq!(t.runs, 3);
            assert!(t.min > 0.0 && t.min <= t.median, "{}: {t:?}", c.method);
            let cell = q.equal_time_cell(m, l).unwrap();
            assert!(cell.micros > 0.0 && cell.time_ratio > 0.0);
            let (e, se) = cell.efficiency;
            assert!(
                e > 0.0 && e.is_finite() && se >= 0.0,
                "{}: {e} ± {se}",
                c.method
            );
            if m == s {
                assert_eq!(cell.efficiency, (1.0, 0.0));
            }
        }
    }
    // An estimate of 1024 samples costs more than one of 4.
    let a = q.adaptive_index(0.001).unwrap();
    let last = ms.spp.len() - 1;
    assert!(cost.costs[a].micros(last) > cost.costs[a].micros(0));
    let (c, lo, hi) = q.break_even_ns(0.001, q.paper_level()).unwrap();
    assert!(c >= 0.0 && lo <= c && c <= hi, "{c} [{lo}, {hi}]");
    let md = q.to_markdown();
    for s in [
        "#### Equal time: cost per estimate and efficiency",
        "| method | CPU µs/estimate at 36 spp [median; IQR] | time ratio at 36 spp |",
        "| stratified solid angle |",
        "**When is adaptive sampling worth its cost?**",
        "(equal_time_adaptive.svg)",
    ] {
        assert!(md.contains(s), "lacks {s:?}");
    }
    let claims = q.cost_claims();
    assert_eq!(claims.len(), 2);
    for c in &claims {
        assert_eq!(c.source, "Ureña 2000, §5 (last paragraph)");
        assert_ne!(c.verdict, Verdict::NotMeasured);
    }
    // With the occluders: our extension, its own figure.
    let o = quick_occluded();
    assert!(o.cost_claims().iter().all(|c| c.is_our_question()));
    assert_eq!(o.cost_figure_name(), "equal_time_adaptive_occluded.svg");
    let dir = std::env::temp_dir().join(format!("areawarp-adaptive-cost-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fig = q.write_cost_figure(&dir).unwrap().expect("a figure");
    assert!(fig.path.ends_with("equal_time_adaptive.svg"));
    assert!(fig.marks >= 6 * 5, "{}", fig.marks);
    let check = verify_figure(&fig.path).unwrap();
    assert!(check.marks >= fig.marks && check.texts >= 4, "{check:?}");
    assert_ne!(fig.alt, fig.title);
    // Without a timing: no table, no claims, no figure.
    let mut config = tiny();
    config.cost = None;
    let none = run_comparison(&config).unwrap();
    assert!(none.cost_claims().is_empty() && none.cost_markdown().is_none());
    assert!(none.write_cost_figure(&dir).unwrap().is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The quick configuration, printed.
#[test]
#[ignore]
fn quick_comparison_report() {
    let q = quick();
    println!("{}", q.to_markdown());
    let ms = &q.measurement;
    for m in 0..ms.methods.len() {
        println!("{}: {:?}", ms.methods[m], ms.curve(Subset::All, m, 0));
    }
    for (r, info) in q.references.iter().zip(&ms.receivers) {
        println!("{:?} {:?}", info.position, r);
    }
}

/// The report's configuration, printed (`cargo test --release --lib
/// studies::adaptive_comparison -- --ignored --nocapture`).
#[test]
#[ignore]
fn default_comparison_report() {
    let start = Instant::now();
    let c = run_comparison(&AdaptiveComparisonConfig::default()).unwrap();
    println!("{}", c.to_markdown());
    println!(
        "default: {:.1} s (references {:.1} s)",
        start.elapsed().as_secs_f64(),
        c.reference_seconds
    );
    let start = Instant::now();
    let _ = run_comparison(&AdaptiveComparisonConfig::quick()).unwrap();
    println!("quick: {:.2} s", start.elapsed().as_secs_f64());
}
