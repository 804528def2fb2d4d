use super::*;
use crate::studies::variance::{VarianceConfig, run as run_variance};

fn small_variance() -> VarianceStudy {
    let mut c = VarianceConfig::quick();
    c.max_log2_spp = 5;
    c.runs = 3;
    c.point_sets = vec![PointSet::Jittered];
    run_variance(&c).expect("variance runs")
}

#[test]
fn equal_time_times_every_method_on_both_scenes() {
    let var = small_variance();
    let mut cfg = EqualTimeConfig::quick();
    cfg.batch = 16;
    cfg.rounds = 3;
    let eq = run(&var, &cfg).expect("runs");
    let occ = eq.occluded.as_ref().expect("occluded table");
    for t in [&eq.free, occ] {
        assert_eq!(t.baseline, "rectangle");
        assert_eq!(t.rows[0].method, "rectangle");
        assert_eq!(t.rows[0].efficiency, 1.0);
        for r in &t.rows {
            let c = &r.cost.per_sample;
            assert_eq!(c.runs, 3);
            assert_eq!(r.cost.rounds.len(), 3);
            assert!(c.min > 0.0 && c.min <= c.median && c.median <= c.max);
            assert!(r.micros > 0.0 && r.time_ratio > 0.0);
            assert!(r.efficiency > 0.0, "{}: {}", r.method, r.efficiency);
        }
    }
    // Cubic-only and Newton projected polygons in the occluded table.
    let names: Vec<&str> = occ.rows.iter().map(|r| r.method.as_str()).collect();
    assert!(names.contains(&"projected polygon"));
    assert!(names.contains(&"projected polygon (cubic only)"));
    // The free projected polygon is exact: infinite efficiency.
    let pp = eq
        .free
        .rows
        .iter()
        .find(|r| r.method == "projected polygon");
    assert!(pp.is_some_and(|r| r.efficiency.is_infinite()));
    let md = eq.to_markdown();
    for s in [
        "#### Equal time, no occluders",
        "#### Equal time, 3 occluders",
        "CLOCK_THREAD_CPUTIME_ID",
        "#### Cubic-only inversion",
        "equal_time_occluded.svg",
    ] {
        assert!(md.contains(s), "lacks {s:?}");
    }
}

#[test]
fn cubic_only_bias_is_zero_without_occluders_and_measured_with_them() {
    let var = small_variance();
    let c = &var.config;
    let set = setup::standing_rectangle(
        c.width, c.height, c.radiance, c.near, c.far, c.rows, c.lateral,
    )
    .unwrap();
    // Without occluders f/p = LΠ for both maps: no bias at all.
    let refs: Vec<f64> = set
        .receivers
        .iter()
        .map(|r| crate::scene::lambert::irradiance(set.scene.emitter(), r))
        .collect();
    let b = inversion::run(&set.scene, &set.receivers, &refs, &BiasConfig::quick()).unwrap();
    assert_eq!(b.receivers + b.skipped, set.receivers.len());
    for x in [b.newton, b.cubic, b.difference] {
        assert!(x.bias.abs() < 1e-12, "{x:?}");
    }
    // With occluders: finite, with a positive standard error.
    let eq = run(&var, &EqualTimeConfig::quick()).unwrap();
    let b = eq.bias.expect("bias test ran");
    assert!(b.receivers > 0);
    for x in [b.newton, b.cubic, b.difference] {
        assert!(x.bias.is_finite() && x.std_error > 0.0, "{x:?}");
        assert!((0.0..=1.0).contains(&x.p()));
    }
    assert!(inversion::run(&set.scene, &set.receivers, &refs[1..], &BiasConfig::quick()).is_err());
}

/// The report's size of this study and the sections it added to the
/// variance study (glossy MIS, area sampling's robust curve), printed:
/// `cargo test --release -p areawarp-lab --lib equal_time::tests::default_size -- --ignored --nocapture`.
#[test]
#[ignore = "the report's size (a minute or more)"]
fn default_size() {
    let var = run_variance(&VarianceConfig::default()).expect("variance runs");
    let eq = run(&var, &EqualTimeConfig::default()).expect("equal time runs");
    println!("{}", eq.to_markdown());
    let g = crate::studies::variance::run_glossy(
        &var.config,
        &crate::studies::variance::GlossyConfig::default(),
    )
    .expect("glossy runs");
    println!("{}", g.to_section().markdown);
    println!("{}", var.robust_markdown());
}
