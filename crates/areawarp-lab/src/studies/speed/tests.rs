use super::*;
use crate::figures::verify_figure;
use crate::studies::precision::warp_variants;

fn quick() -> &'static SpeedStudy {
    use std::sync::OnceLock;
    static STUDY: OnceLock<SpeedStudy> = OnceLock::new();
    STUDY.get_or_init(|| run(&SpeedConfig::quick()).expect("quick speed study"))
}

#[test]
fn speed_table_covers_every_warp_variant_and_type() {
    let s = quick();
    let mut expected = 0;
    for (warp, variants) in warp_variants() {
        for variant in variants {
            for scalar in SCALARS {
                expected += 1;
                let r = s
                    .row(warp, variant, scalar)
                    .unwrap_or_else(|| panic!("{warp} {variant} {scalar} missing"));
                assert!(
                    r.map.median > 0.0 && r.map.min <= r.map.median && r.map.median <= r.map.max,
                    "{r:?}"
                );
                assert!(r.map.q1 <= r.map.q3, "{r:?}");
                assert!(r.build_and_map.median > 0.0, "{r:?}");
                assert!(r.shapes > 0 && r.max_error.is_finite(), "{r:?}");
                assert_eq!(r.map.runs, if scalar.starts_with("mpfr") { 2 } else { 3 });
            }
        }
    }
    assert_eq!(s.rows.len(), expected);
    // Every inversion setting of the polygon, in every type.
    for inv in [
        "cubic",
        "cubic+1 Newton",
        "cubic+2 Newton",
        "cubic+3 Newton",
        "Newton",
    ] {
        assert!(s.row("projected-polygon", inv, "mpfr:128").is_some());
    }
    let md = s.to_markdown();
    assert!(md.contains("| projected-polygon | cubic+2 Newton | mpfr:256 |"));
}

/// The errors (not the timings) are identical for 1 and 2 threads.
#[test]
fn speed_errors_are_identical_for_one_and_two_threads() {
    let config = SpeedConfig {
        max_shapes: Some(2),
        ..SpeedConfig::quick()
    };
    let errors = |threads: usize| -> Vec<(String, f64, f64, usize, usize)> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let study = pool.install(|| run(&config)).expect("runs");
        study
            .rows
            .iter()
            .map(|r| {
                (
                    format!("{} {} {} {}", r.warp, r.variant, r.scalar, r.worst_shape),
                    r.max_error,
                    r.timed_shape_error,
                    r.non_finite,
                    r.rejected,
                )
            })
            .collect()
    };
    assert_eq!(errors(1), errors(2));
}

#[test]
fn speed_errors_order_the_scalars() {
    // Structure, not timing: the exact variants' errors shrink with the
    // precision, and the bare cubic is no better in f64 than its bias.
    let s = quick();
    let exact = ["closed form", "+z axis", "tilted axis", "robust", "Newton"];
    for (warp, variants) in warp_variants() {
        for v in variants.into_iter().filter(|v| exact.contains(v)) {
            let e: Vec<f64> = SCALARS
                .iter()
                .map(|t| s.row(warp, v, t).unwrap().max_error)
                .collect();
            assert!(
                e[0] > e[1] && e[1] > e[2] && e[2] > e[3],
                "{warp} {v}: {e:?}"
            );
            assert!(
                e[0] < 1e-5 && e[1] < 1e-12 && e[3] < 1e-70,
                "{warp} {v}: {e:?}"
            );
        }
    }
    let cubic = s.row("projected-polygon", "cubic", "mpfr:256").unwrap();
    assert!(cubic.max_error > 1e-12, "{cubic:?}");
}

#[test]
fn speed_pareto_and_recommendations_cover_every_warp() {
    let s = quick();
    for warp in WARPS {
        let front = s.pareto(warp);
        assert!(!front.is_empty(), "{warp}");
        // Along the front, slower means more accurate.
        for w in front.windows(2) {
            assert!(
                w[0].map.median <= w[1].map.median && w[0].max_error >= w[1].max_error,
                "{w:?}"
            );
        }
    }
    let rec = s.recommendations();
    assert_eq!(rec.len(), WARPS.len());
    for r in rec {
        assert_eq!(r.scalar, "f64");
        let row = s.row(&r.warp, &r.variant, "f64").unwrap();
        assert_eq!(row.non_finite, 0);
        assert_eq!(r.max_error, row.max_error);
        assert!(r.reason.contains("ns/sample"));
        // The rule, checked structurally (whatever the timings).
        let clean: Vec<&SpeedRow> = s
            .rows
            .iter()
            .filter(|x| x.warp == r.warp && x.scalar == "f64" && x.non_finite == 0)
            .collect();
        let best = clean
            .iter()
            .map(|x| x.max_error)
            .fold(f64::INFINITY, f64::min);
        let ok = |x: &SpeedRow| x.max_error <= 4.0 * best.max(f64::MIN_POSITIVE);
        assert!(ok(row), "{r:?}");
        let default_variant = warp_variants()
            .into_iter()
            .find(|(w, _)| *w == r.warp)
            .unwrap()
            .1[0];
        let default = s.row(&r.warp, default_variant, "f64").unwrap();
        let faster: Vec<&&SpeedRow> = clean
            .iter()
            .filter(|x| ok(x) && clearly_faster(&x.map, &default.map))
            .collect();
        if r.variant == default_variant {
            assert!(faster.is_empty(), "{r:?}: {faster:?}");
        } else if ok(default) {
            assert!(clearly_faster(&row.map, &default.map), "{r:?}");
            assert!(
                faster.iter().all(|x| x.map.median >= row.map.median),
                "{r:?}"
            );
        }
    }
    // The literal solid-angle maps are disqualified on the quick
    // shapes already (NaN/∞ or far from the robust error), so they are
    // never recommended.
    for warp in ["spherical-triangle", "spherical-rectangle"] {
        let lit = s.row(warp, "literal", "f64").unwrap();
        let rob = s.row(warp, "robust", "f64").unwrap();
        assert!(
            lit.non_finite > 0 || lit.max_error > 4.0 * rob.max_error,
            "{lit:?}"
        );
        let r = rec.iter().find(|r| r.warp == warp).unwrap();
        assert_eq!(r.variant, "robust", "{r:?}");
    }
}

#[test]
fn speed_figures_and_csv_are_written() {
    let s = quick();
    let dir = std::env::temp_dir().join(format!("areawarp-speed-{}", std::process::id()));
    let figs = s.write_figures(&dir).unwrap();
    assert_eq!(figs.len(), 3);
    let hw = verify_figure(&figs[0].path).unwrap();
    let rows = |mpfr: bool| {
        s.rows
            .iter()
            .filter(|r| r.non_finite == 0 && r.scalar.starts_with("mpfr") == mpfr)
            .count()
    };
    assert!(hw.marks >= rows(false), "{hw:?}");
    let mpfr = verify_figure(&figs[1].path).unwrap();
    assert!(mpfr.marks >= rows(true), "{mpfr:?}");
    let poly = verify_figure(&figs[2].path).unwrap();
    assert!(poly.marks >= 20, "{poly:?}");
    let csv = s.write_csv(&dir).unwrap();
    let rows = std::fs::read_to_string(&csv[0]).unwrap();
    assert_eq!(rows.lines().count(), s.rows.len() + 1);
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        run(&SpeedConfig {
            batch: 0,
            ..SpeedConfig::quick()
        })
        .is_err()
    );
}

/// The default sizes of both studies, timed, with their Markdown
/// printed and files written to `target/studies-report`:
/// `cargo test --release --lib studies::speed::tests::default_sizes -- --ignored --nocapture`.
#[test]
#[ignore]
fn default_sizes() {
    use crate::studies::precision;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/studies-report");
    let t0 = Instant::now();
    let p = precision::run(&precision::PrecisionConfig::default()).unwrap();
    let tp = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let s = run(&SpeedConfig::default()).unwrap();
    let ts = t1.elapsed().as_secs_f64();
    println!("{}\n{}", p.to_markdown(), s.to_markdown());
    p.write_csv(&dir).unwrap();
    p.write_figures(&dir).unwrap();
    s.write_csv(&dir).unwrap();
    s.write_figures(&dir).unwrap();
    println!("precision: {tp:.1} s, speed: {ts:.1} s");
}

#[test]
fn widening_is_exact() {
    // 1 − 10⁻¹² as a 128-bit number: a decimal round trip (40 digits)
    // would move it by ~10⁻⁴⁰, i.e. 1 − u by 10⁻²⁸ relative.
    let u = 1.0 - 1e-12;
    assert_eq!(widen(&Mpfr128::from_f64(u)), R::from_f64(u));
    let third = Mpfr128::from_ratio(1, 3);
    let w = widen(&third);
    let e = (w.clone() * &R::from_i64(3) - &R::one()).abs();
    assert!(e > R::zero() && e <= R::exp2i(-127), "{e}");
    let back = w - &R::from_f64(third.to_f64());
    assert!(back.abs() <= R::exp2i(-54), "{back}");
    assert_eq!(widen(&0.1f32), R::from_f64(f64::from(0.1f32)));
    let third256 = Mpfr256::from_ratio(1, 3);
    let e = (widen(&third256) * &R::from_i64(3) - &R::one()).abs();
    assert!(e > R::zero() && e <= R::exp2i(-255), "{e}");
}

#[test]
fn timing_quantiles() {
    let t = Timing::of(vec![4.0, 1.0, 3.0, 2.0, 5.0], 10);
    assert_eq!(
        (t.min, t.q1, t.median, t.q3, t.max),
        (1.0, 2.0, 3.0, 4.0, 5.0)
    );
    let t = Timing::of(vec![2.0, 1.0], 1);
    assert_eq!(t.median, 1.5);
}
