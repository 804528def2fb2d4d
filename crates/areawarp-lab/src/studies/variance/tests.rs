use super::output::*;
use super::*;
use crate::figures::verify_figure;
use crate::scene::Quantity;
use crate::scene::strategies;
use areawarp::estimate::monte_carlo;
use areawarp::sampling::jittered_iter;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("areawarp-variance-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn quick_study() -> VarianceStudy {
    run(&VarianceConfig::quick()).expect("quick study runs")
}

#[test]
fn grid_columns_split_powers_of_two() {
    assert_eq!(grid_columns(1), 1);
    assert_eq!(grid_columns(2), 2);
    assert_eq!(grid_columns(8), 4);
    assert_eq!(grid_columns(16), 4);
    assert_eq!(grid_columns(1024), 32);
    assert_eq!(grid_columns(7), 7);
    assert_eq!(grid_columns(0), 0);
}

#[test]
fn power_fit_recovers_rate_and_sample_ratio() {
    let pts: Vec<(f64, f64)> = [64.0, 128.0, 256.0]
        .iter()
        .map(|&n: &f64| (n, 3.0 * n.powf(-0.75)))
        .collect();
    let f = PowerFit::fit(&pts).unwrap();
    assert!((f.alpha - 0.75).abs() < 1e-12);
    assert!((f.at(100.0) - 3.0 * 100f64.powf(-0.75)).abs() < 1e-12);
    assert!((f.samples_for(f.at(300.0)) - 300.0).abs() < 1e-9);
    assert!(PowerFit::fit(&[(1.0, 1.0)]).is_none());
    let r = SampleRatio {
        ratio: 1.0 / 0.85,
        std_error: 0.0,
        at_spp: 1024,
    };
    assert!((r.saving() - 0.15).abs() < 1e-12);
}

#[test]
fn distance_to_the_standing_light() {
    let s = setup::standing_rectangle(1.0, 0.5, 1.0, 0.1, 1.0, 2, 1).unwrap();
    let light = s.scene.emitter().polygon();
    // In front of the light: the plane distance.
    let d = distance_to_polygon(light, &Vec3::new(0.1, 0.3, 0.2));
    assert!((d - 0.3).abs() < 1e-15);
    // Beside it: the distance to the side edge x = 0.5.
    let d = distance_to_polygon(light, &Vec3::new(0.75, 0.0, 0.0));
    assert!((d - 0.25).abs() < 1e-15);
    let d = distance_to_polygon(light, &Vec3::new(1.5, 1.0, 0.25));
    assert!((d - 2f64.sqrt()).abs() < 1e-15);
}

#[test]
fn curves_decrease_with_spp() {
    let study = quick_study();
    let ms = &study.measurement;
    let last = ms.spp.len() - 1;
    assert!(ms.spp[last] >= 256);
    for (p, set) in ms.point_sets.iter().enumerate() {
        for (m, method) in study.config.methods.iter().enumerate() {
            if method.sampler == Sampler::ProjectedPolygon && method.mis.is_none() {
                continue; // zero variance: tested below
            }
            let e1 = ms.rms(Subset::All, m, p, 0);
            let en = ms.rms(Subset::All, m, p, last);
            // Plain area sampling is heavy-tailed near the light (its
            // relative variance grows like 1/d²): with few runs its RMS
            // is itself noisy, so only require that it falls.
            // Independent points converge like n^(−1/2) only, and
            // cosine sampling's hit-or-miss RMS at 1 spp is itself
            // noisy over few runs: require a halving over 1…256 spp.
            let factor = if *method == Method::plain(Sampler::Area) {
                1.0
            } else if *set == PointSet::Independent {
                0.5
            } else {
                0.1
            };
            assert!(
                e1.is_finite() && en.is_finite() && en < factor * e1,
                "{} ({}): {e1} at 1 spp, {en} at {} spp",
                ms.methods[m],
                set.name(),
                ms.spp[last]
            );
            // The solid-angle samplers are bounded estimators: every
            // factor 4 in spp must lower the error.
            if matches!(method.sampler, Sampler::Rectangle | Sampler::TrianglePair) {
                for l in 2..=last {
                    let (a, b) = (
                        ms.rms(Subset::All, m, p, l - 2),
                        ms.rms(Subset::All, m, p, l),
                    );
                    assert!(
                        b < a,
                        "{} ({}): {a} -> {b} at level {l}",
                        ms.methods[m],
                        set.name()
                    );
                }
                let fit = ms.fit(Subset::All, m, p).unwrap();
                // Stratified and low-discrepancy points beat plain
                // Monte Carlo's rate; independent points have it.
                let (min_alpha, max_alpha) = match (set, method.mis) {
                    (PointSet::Independent, _) => (0.35, 0.65),
                    (_, None) => (0.8, f64::INFINITY),
                    _ => (0.5, f64::INFINITY),
                };
                assert!(
                    fit.alpha > min_alpha && fit.alpha < max_alpha,
                    "{} ({}): α = {}",
                    ms.methods[m],
                    set.name(),
                    fit.alpha
                );
            }
        }
    }
}

#[test]
fn projected_polygon_has_zero_variance_and_failures_are_reported() {
    let study = quick_study();
    let ms = &study.measurement;
    let name = Method::plain(Sampler::ProjectedPolygon).name();
    let m = ms.method_index(&name).unwrap();
    let skipped = ms.skipped_receivers(&name);
    assert!(
        skipped < ms.receivers.len(),
        "the map works at most receivers"
    );
    for p in 0..ms.point_sets.len() {
        for (l, c) in ms.curve(Subset::All, m, p).iter().enumerate() {
            assert_eq!(
                c.estimates as usize,
                (ms.receivers.len() - skipped) * ms.runs,
                "level {l}"
            );
            assert!(c.rms_relative_error < 1e-12, "{c:?}");
        }
    }
    // Every skip is listed with its error, in the table and the CSV.
    let md = study.to_markdown();
    for f in &ms.failures {
        assert!(!f.error.is_empty());
        assert!(f.failed > 0 && f.failed <= f.attempted);
        assert!(md.contains(&format!("| {} | {} |", f.method, f.receiver)));
    }
    if ms.failures.is_empty() {
        assert!(md.contains("Every method was built"));
    }
}

#[test]
fn results_are_identical_for_one_and_two_threads() {
    let mut config = VarianceConfig::quick();
    config.max_log2_spp = 5;
    config.runs = 3;
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&config).unwrap())
    };
    let one = in_pool(1);
    let two = in_pool(2);
    assert_eq!(one.measurement, two.measurement);
    assert_eq!(curves_csv(&one.measurement), curves_csv(&two.measurement));
    assert_eq!(one.claims(), two.claims());
    // A different seed gives different errors.
    config.seed += 1;
    let other = run(&config).unwrap();
    assert_ne!(curves_csv(&one.measurement), curves_csv(&other.measurement));
}

#[test]
fn csv_and_figures_are_written_and_non_trivial() {
    let study = quick_study();
    let dir = temp_dir("out");
    let paths = study.write_csv(&dir).unwrap();
    assert_eq!(paths.len(), 7);
    let ms = &study.measurement;
    let curves = std::fs::read_to_string(dir.join("variance_curves.csv")).unwrap();
    assert_eq!(
        curves.lines().count(),
        1 + ms.methods.len() * ms.point_sets.len() * 2 * ms.spp.len()
    );
    assert!(curves.contains("rectangle+MIS(balance),jittered,all,256,"));
    let receivers = std::fs::read_to_string(dir.join("variance_receivers.csv")).unwrap();
    assert_eq!(
        receivers.lines().count(),
        1 + ms.receivers.len() * ms.methods.len() * ms.point_sets.len()
    );
    let claims = std::fs::read_to_string(dir.join("variance_claims.csv")).unwrap();
    assert!(claims.lines().count() > 8);
    let figs = study.write_figures(&dir).unwrap();
    // 3 sets × (all, near) + distance + heuristics + 3 occluded.
    assert_eq!(figs.len(), 11);
    for f in &figs {
        let check = verify_figure(&f.path).unwrap();
        assert!(f.marks >= 10, "{:?}", f.path);
        assert!(check.marks >= f.marks, "{:?}", f.path);
    }
    let text = std::fs::read_to_string(dir.join("variance_jittered.svg")).unwrap();
    assert!(text.contains("triangle pair") && text.contains("area+MIS(balance)"));
    // The zero-variance curve is named, not drawn.
    assert!(text.contains("not drawn, error &lt; 1e-12: projected polygon"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn claims_are_all_checked() {
    let study = quick_study();
    let claims = study.claims();
    assert!(claims.len() >= 10);
    let measured = claims
        .iter()
        .filter(|c| c.verdict != Verdict::NotMeasured)
        .count();
    // Only the cost claim (speed study) is out of scope.
    assert_eq!(measured, claims.len() - 1);
    for c in &claims {
        assert!(!c.measured.is_empty());
    }
    // Near a light whose foot is 0.01 away, area sampling is far worse.
    let near = claims
        .iter()
        .find(|c| c.statement.starts_with("near the light"))
        .unwrap();
    assert_ne!(near.verdict, Verdict::NotReproduced, "{}", near.measured);
    let md = study.to_markdown();
    assert!(md.contains("### Samples at equal error"));
    assert!(md.contains("| area+MIS(power(2)) |"));
}

#[test]
fn occluded_reference_matches_a_converged_estimate() {
    let base = setup::standing_rectangle(1.0, 0.5, 1.0, 0.1, 1.0, 2, 1).unwrap();
    let mut scene = base.scene.clone();
    for o in OccluderRow::standard().polygons().unwrap() {
        scene = scene.with_occluder(o);
    }
    let up = Vec3::new(0.0, 0.0, 1.0);
    let mut shadowed = 0;
    for (x, y) in [
        (-0.35, 0.3),
        (0.0, 1.0),
        (0.2, 0.2),
        (0.1, 0.05),
        (0.6, 0.4),
        (-0.1, 3.0),
    ] {
        let rx = Receiver::new(Vec3::new(x, y, 0.0), up).unwrap();
        let exact = occluded_irradiance(&scene, &rx).unwrap();
        let free = lambert::irradiance(scene.emitter(), &rx);
        assert!(exact <= free * (1.0 + 1e-12));
        if exact < 0.99 * free {
            shadowed += 1;
        }
        // Solid-angle sampling with visibility: bounded, converges fast.
        let rect =
            strategies::spherical_rectangle(scene.emitter().polygon(), rx.position()).unwrap();
        let mut rng = areawarp::estimate::job_rng(5, 0);
        let pts: Vec<(f64, f64)> = jittered_iter::<f64, _>(384, 384, &mut rng).collect();
        let e = monte_carlo(
            &rect,
            |d| scene.integrand(&rx, &Quantity::Irradiance, d),
            pts,
        );
        assert!(
            (e.value / exact - 1.0).abs() < 2e-4,
            "receiver ({x}, {y}): exact {exact}, estimate {}",
            e.value
        );
    }
    assert!(shadowed >= 3, "the occluders must cast shadows: {shadowed}");
    // A receiver level with the occluders' plane: not supported.
    let rx = Receiver::new(Vec3::new(0.0, 0.15, 0.0), up).unwrap();
    assert!(occluded_irradiance(&scene, &rx).is_none());
}

/// An estimator failing at receivers with `x < 0`, and otherwise area
/// sampling: exercises the hook and the failure accounting.
struct FailsLeft(Method);

impl ReceiverEstimator for FailsLeft {
    fn name(&self) -> String {
        "fails-left".to_string()
    }
    fn prepare<'s>(
        &'s self,
        scene: &'s Scene,
        receiver: &'s Receiver,
    ) -> Result<Box<dyn PreparedEstimator + 's>, WarpError> {
        if receiver.position().x < 0.0 {
            return Err(WarpError::Degenerate { what: "left side" });
        }
        self.0.prepare(scene, receiver)
    }
}

#[test]
fn the_hook_measures_other_setups_and_attaches_sections() {
    // The adaptive comparison's setup: patterned triangle, occluders,
    // converged references.
    let setup = setup::patterned_triangle(2, 2.0, 0.5, 2).unwrap();
    let references: Vec<f64> = setup
        .receivers
        .iter()
        .map(|r| {
            setup
                .scene
                .reference(r, &Quantity::Irradiance, 4096, 7)
                .unwrap()
                .value
        })
        .collect();
    let tri = Method::plain(Sampler::TrianglePair);
    let fails = FailsLeft(Method::plain(Sampler::Area));
    let estimators: [&dyn ReceiverEstimator; 2] = [&tri, &fails];
    let spp = [1, 4, 16, 64];
    let spec = MeasureSpec {
        setup: &setup,
        references: &references,
        estimators: &estimators,
        point_sets: &[PointSet::Jittered],
        spp: &spp,
        runs: 3,
        seed: 11,
        near_light: 0.0,
    };
    let m = measure(&spec, 3).unwrap();
    assert_eq!(m.methods, vec!["triangle pair", "fails-left"]);
    // Two of the four receivers have x < 0: listed, skipped.
    assert_eq!(m.skipped_receivers("fails-left"), 2);
    assert!(
        m.failures
            .iter()
            .all(|f| f.failed == f.attempted && f.error.contains("left side"))
    );
    let c = m.curve(Subset::All, 1, 0);
    assert!(c.iter().all(|p| p.estimates == 2 * 3));
    let c = m.curve(Subset::All, 0, 0);
    assert!(c[3].rms_relative_error < c[0].rms_relative_error);

    let mut study = run(&VarianceConfig {
        max_log2_spp: 3,
        runs: 2,
        ..VarianceConfig::quick()
    })
    .unwrap();
    study.attach(ExtraSection {
        title: "Adaptive vs stratified (Ureña 2000)".to_string(),
        markdown: "placeholder table".to_string(),
        slug: "adaptive".to_string(),
        measurement: Some(m),
        claims: vec![Claim {
            source: "Ureña 2000".to_string(),
            statement: "adaptive lowers noise".to_string(),
            measured: "n/a".to_string(),
            verdict: Verdict::NotMeasured,
        }],
        claims_image: Vec::new(),
    });
    assert!(
        study
            .to_markdown()
            .contains("### Adaptive vs stratified (Ureña 2000)")
    );
    assert!(study.claims().iter().any(|c| c.source == "Ureña 2000"));
    let dir = temp_dir("hook");
    let paths = study.write_csv(&dir).unwrap();
    assert!(
        paths
            .iter()
            .any(|p| p.ends_with("variance_adaptive_curves.csv"))
    );
    let figs = study.write_figures(&dir).unwrap();
    let f = figs
        .iter()
        .find(|f| f.path.ends_with("variance_adaptive.svg"))
        .unwrap();
    assert!(verify_figure(&f.path).unwrap().marks > 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn measure_rejects_bad_specs() {
    let setup = setup::standing_rectangle(1.0, 0.5, 1.0, 0.1, 1.0, 2, 1).unwrap();
    let rect = Method::plain(Sampler::Rectangle);
    let estimators: [&dyn ReceiverEstimator; 1] = [&rect];
    let good = [1.0, 1.0];
    let spec = |references: &'static [f64], spp: &'static [usize], runs| MeasureSpec {
        setup: &setup,
        references,
        estimators: &estimators,
        point_sets: &[PointSet::Sobol],
        spp,
        runs,
        seed: 0,
        near_light: 0.0,
    };
    assert!(measure(&spec(&[1.0], &[1], 1), 3).is_err());
    assert!(measure(&spec(&[1.0, -1.0], &[1], 1), 3).is_err());
    assert!(measure(&spec(&[1.0, 1.0], &[0], 1), 3).is_err());
    assert!(measure(&spec(&[1.0, 1.0], &[1], 0), 3).is_err());
    assert!(measure(&spec(&[1.0, 1.0], &[], 1), 3).is_err());
    let _ = good;
}

/// The quick configuration, printed.
#[test]
#[ignore]
fn quick_study_report() {
    let study = quick_study();
    println!("{}", study.to_markdown());
    let dir = std::env::temp_dir().join("areawarp-variance-quick");
    study.write_csv(&dir).unwrap();
    study.write_figures(&dir).unwrap();
    println!("written to {}", dir.display());
}

/// The report's configuration, printed (`cargo test --release --lib
/// studies::variance -- --ignored --nocapture`).
#[test]
#[ignore]
fn default_study_report() {
    let study = run(&VarianceConfig::default()).unwrap();
    println!("{}", study.to_markdown());
    let dir = temp_dir("default");
    study.write_csv(&dir).unwrap();
    study.write_figures(&dir).unwrap();
    println!("written to {}", dir.display());
}

#[test]
fn order_statistic_intervals_have_their_binomial_coverage() {
    // 16 runs: [x(4), x(13)] covers the median with 1 − 2·P(Bin(16, ½) ≤ 3).
    let (j, c) = order_statistic_interval(16);
    assert_eq!(j, 4);
    assert!((c - (1.0 - 2.0 * 697.0 / 65536.0)).abs() < 1e-12, "{c}");
    // 4 runs: only the whole range, 1 − 2/16.
    assert_eq!(order_statistic_interval(4), (1, 0.875));
    // Coverage at least 95% whenever it can be.
    for k in 6..64 {
        let (j, c) = order_statistic_interval(k);
        assert!(c >= 0.95 && 2 * j <= k + 1, "{k}: {j} {c}");
    }
}

#[test]
fn median_of_runs_lies_in_its_interval_and_the_section_shows_it() {
    let study = quick_study();
    let ms = &study.measurement;
    let i = ms
        .method_index(&Method::plain(Sampler::Area).name())
        .unwrap();
    for l in 0..ms.spp.len() {
        let (m, lo, hi, c) = ms.rms_median_of_runs(Subset::All, i, 0, l);
        assert!(lo <= m && m <= hi && m > 0.0, "{lo} {m} {hi}");
        assert!(c > 0.5 && c <= 1.0);
    }
    let md = study.robust_markdown();
    assert!(md.contains("median of runs") && md.contains("variance_area_robust.svg"));
    let dir = temp_dir("robust");
    std::fs::create_dir_all(&dir).unwrap();
    let fig = study.write_robust_figure(&dir).unwrap().expect("figure");
    verify_figure(&fig.path).expect("valid figure");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn glossy_receiver_mis_lowers_area_samplings_error() {
    let mut c = VarianceConfig::quick();
    c.max_log2_spp = 6;
    let g = run_glossy(&c, &GlossyConfig::quick()).expect("glossy runs");
    let gc = GlossyConfig::quick();
    // Every sampler alone and with MIS, and BRDF sampling alone.
    assert_eq!(g.methods.len(), 2 * gc.samplers.len() + 1);
    assert!(g.reference_rel_se > 0.0 && g.reference_rel_se < 0.05);
    let ratios = g.mis_ratios();
    assert_eq!(ratios.len(), gc.samplers.len());
    for (s, r, se) in &ratios {
        assert!(r.is_finite() && *r > 0.0 && se.is_finite(), "{s:?}");
    }
    // Near the light area sampling's f/p explodes; the BRDF sample, whose
    // density does not, caps it under the balance heuristic.
    let (_, area, area_se) = ratios
        .iter()
        .find(|x| x.0 == Sampler::Area)
        .copied()
        .unwrap();
    assert!(area + 1.96 * area_se < 1.0, "{area} ± {area_se}");
    let section = g.to_section();
    assert_eq!(section.slug, "glossy");
    assert!(section.markdown.contains("RMS(+MIS) / RMS(alone)"));
}
