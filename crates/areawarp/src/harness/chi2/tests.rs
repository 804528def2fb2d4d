//! Tests of the χ² goodness-of-fit machinery.

use super::*;
use crate::harness::test_warps::{TestDisk, TestLobe, TestSphere, TestTriangle};

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

#[test]
#[allow(clippy::excessive_precision)]
fn incomplete_gamma_matches_reference_values() {
    // Reference values: mpmath gammainc(a, x, inf, regularized=True), 30 digits.
    let table = [
        (0.5, 0.1, 0.654_720_846_018_577_02),
        (0.5, 2.0, 0.045_500_263_896_358_414),
        (1.0, 3.0, 0.049_787_068_367_863_943),
        (2.5, 1.0, 0.849_145_036_084_609_64),
        (5.0, 20.0, 1.694_474_393_006_738_4e-5),
        (10.0, 3.0, 0.998_897_511_869_884_52),
        (50.0, 40.0, 0.929_664_933_340_605_05),
        (50.0, 70.0, 0.005_140_502_458_505_893_9),
        (0.5, 30.0, 9.485_737_571_073_848_4e-15),
        (100.0, 100.0, 0.486_701_201_720_851_34),
        (1000.0, 1100.0, 0.001_059_323_253_929_977_3),
        (3.0, 0.001, 0.999_999_999_833_458_28),
        (4999.5, 5100.0, 0.078_292_895_215_381_575),
        (10000.0, 10000.0, 0.498_670_191_660_044_8),
    ];
    for (a, x, q) in table {
        let got = regularized_gamma_q(a, x);
        assert!(close(got, q, 1e-10), "Q({a}, {x}) = {got}, expected {q}");
    }
    // The 5 % critical value of χ² with one degree of freedom.
    assert!(close(
        regularized_gamma_q(0.5, 3.841_458_820_694_124 / 2.0),
        0.05,
        1e-12
    ));
    assert_eq!(regularized_gamma_q(2.0, 0.0), 1.0);
    assert!(regularized_gamma_q(0.0, 1.0).is_nan());
    assert!(regularized_gamma_q(1.0, -1.0).is_nan());
}

#[test]
#[allow(clippy::excessive_precision)]
fn ln_gamma_matches_reference_values() {
    let table = [
        (0.5, 0.572_364_942_924_700_09),
        (1.5, -0.120_782_237_635_245_22),
        (10.0, 12.801_827_480_081_47),
        (100.5, 361.435_540_467_777_62),
        (1e5, 1_051_287.708_973_656_9),
    ];
    for (x, l) in table {
        assert!(close(ln_gamma(x), l, 1e-13), "lnΓ({x}) = {}", ln_gamma(x));
    }
    assert!(ln_gamma(1.0).abs() < 1e-14 && ln_gamma(2.0).abs() < 1e-14);
}

#[test]
fn exact_counts_pass_and_skewed_counts_fail() {
    let expected = vec![100.0; 50];
    let observed = vec![100u64; 50];
    let ok = chi_square_test(&observed, &expected, MIN_EXPECTED, 0.01, 1);
    assert!(ok.passed && ok.statistic == 0.0 && ok.dof == 49, "{ok:?}");
    assert_eq!(ok.p_value, 1.0);
    let mut skewed = observed.clone();
    skewed[0] += 100;
    skewed[1] -= 100;
    let bad = chi_square_test(&skewed, &expected, MIN_EXPECTED, 0.01, 1);
    assert!((bad.statistic - 200.0).abs() < 1e-12);
    assert!(
        !bad.passed && bad.failure == Some(ChiSquareFailure::Rejected),
        "{bad:?}"
    );
}

#[test]
fn small_cells_are_pooled() {
    let expected = [1.0, 50.0, 2.0, 50.0, 3.0, 50.0];
    let observed = [2, 49, 1, 50, 4, 51];
    let o = chi_square_test(&observed, &expected, MIN_EXPECTED, 0.01, 1);
    assert_eq!(
        (o.pooled_cells, o.pooled_expected, o.pool_dropped),
        (3, 6.0, false)
    );
    assert_eq!(o.dof, 3);
    assert!((o.statistic - (1.0 / 50.0 + 0.0 + 1.0 / 50.0 + 1.0 / 6.0)).abs() < 1e-12);
    // Everything below the minimum: the pool is dropped, nothing is left.
    let tiny = chi_square_test(&[1, 1, 1], &[1.0, 1.0, 1.0], MIN_EXPECTED, 0.01, 1);
    assert!(tiny.pool_dropped && tiny.failure == Some(ChiSquareFailure::TooFewCells));
}

#[test]
fn sidak_correction_and_invalid_input() {
    let o = chi_square_test(&[10, 10], &[10.0, 10.0], MIN_EXPECTED, 0.01, 10);
    assert!(
        close(o.significance, 1.0 - 0.99f64.powf(0.1), 1e-12),
        "{o:?}"
    );
    let z = chi_square_test(&[1, 10, 9], &[0.0, 10.0, 10.0], MIN_EXPECTED, 0.01, 1);
    assert_eq!(
        (z.zero_expected_hits, z.failure),
        (1, Some(ChiSquareFailure::ZeroExpectedHit))
    );
    let m = chi_square_test(&[1, 2], &[1.0], MIN_EXPECTED, 0.01, 1);
    assert_eq!(m.failure, Some(ChiSquareFailure::LengthMismatch));
    let n = chi_square_test(&[1, 2], &[f64::NAN, 1.0], MIN_EXPECTED, 0.01, 1);
    assert_eq!(n.failure, Some(ChiSquareFailure::InvalidExpected));
}

#[test]
fn binnings_have_consistent_cells() {
    let tri = TriangleBins::new(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        4,
    )
    .unwrap();
    // Every cell index is hit exactly once by the centroids of the 16 cells.
    let mut seen = vec![0; 16];
    for i in 0..4 {
        for j in 0..4 - i {
            let up = Vec3::new(
                (i as f64 + 1.0 / 3.0) / 4.0,
                (j as f64 + 1.0 / 3.0) / 4.0,
                0.0,
            );
            seen[tri.bin(&up).unwrap()] += 1;
            if i + j < 3 {
                let down = Vec3::new(
                    (i as f64 + 2.0 / 3.0) / 4.0,
                    (j as f64 + 2.0 / 3.0) / 4.0,
                    0.0,
                );
                seen[tri.bin(&down).unwrap()] += 1;
            }
        }
    }
    assert!(seen.iter().all(|&s| s == 1), "{seen:?}");
    assert!(tri.bin(&Vec3::new(0.6, 0.6, 0.0)).is_none());
    assert!(tri.bin(&Vec3::new(0.2, 0.2, 1e-3)).is_none());
    assert!(tri.bin(&Vec3::new(1.0, 0.0, 0.0)).is_some());

    let disk = DiskBins::unit(4, 8).unwrap();
    assert_eq!(disk.n_bins(), 32);
    assert_eq!(disk.bin(&Vec3::new(0.0, 0.0, 0.0)), Some(0));
    assert_eq!(disk.bin(&Vec3::new(1.0, -1e-18, 0.0)), Some(3 * 8 + 7));
    assert!(disk.bin(&Vec3::new(0.8, 0.8, 0.0)).is_none());

    let hemi = ZPhiBins::hemisphere(2, 4).unwrap();
    assert_eq!(hemi.bin(&Vec3::new(0.0, 0.0, 1.0)), Some(4));
    assert!(hemi.bin(&Vec3::new(0.0, 0.6, -0.8)).is_none());
    assert!(hemi.bin(&Vec3::new(0.0, 0.0, 1.1)).is_none());
    let phong = ZPhiBins::phong(1.0, 2, 1).unwrap();
    // cdf z² = 1/2 at z = 1/√2.
    let z = 0.70;
    assert_eq!(
        phong.bin(&Vec3::new((1.0f64 - z * z).sqrt(), 0.0, z)),
        Some(0)
    );
    let z = 0.72;
    assert_eq!(
        phong.bin(&Vec3::new((1.0f64 - z * z).sqrt(), 0.0, z)),
        Some(1)
    );

    assert!(ZPhiBins::phong(-1.0, 2, 2).is_err());
    assert!(ZPhiBins::sphere(0, 2).is_err());
    assert!(DiskBins::unit(2, 0).is_err());
    assert!(
        TriangleBins::new(
            Vec3::zero(),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(2.0, 2.0, 2.0),
            3
        )
        .is_err()
    );
}

#[test]
fn correct_warps_pass() {
    let disk = run_chi_square(
        &TestDisk::<f64>::correct(),
        &DiskBins::unit(10, 20).unwrap(),
        100_000,
        1,
        0.01,
        1,
    );
    assert!(disk.passed, "{disk:?}");
    assert_eq!(disk.observed_total, 100_000);
    let sphere = TestSphere::<f64>::new(false);
    for bins in [
        ZPhiBins::sphere(10, 20).unwrap(),
        ZPhiBins::sphere(10, 20)
            .unwrap()
            .with_axis(Vec3::new(1.0, 2.0, 3.0))
            .unwrap(),
    ] {
        let o = run_chi_square(&sphere, &bins, 100_000, 2, 0.01, 1);
        assert!(o.passed, "{o:?}");
    }
    let hemi = run_chi_square(
        &TestLobe::new(0.0),
        &ZPhiBins::hemisphere(10, 20).unwrap(),
        100_000,
        3,
        0.01,
        1,
    );
    assert!(hemi.passed, "{hemi:?}");
    let lobe = run_chi_square(
        &TestLobe::new(20.0),
        &ZPhiBins::phong(20.0, 10, 20).unwrap(),
        100_000,
        4,
        0.01,
        1,
    );
    assert!(lobe.passed, "{lobe:?}");
    let (a, b, c) = (
        Vec3::new(0.5, -1.0, 2.0),
        Vec3::new(3.0, 0.0, 1.0),
        Vec3::new(-1.0, 2.0, 0.5),
    );
    let tri = run_chi_square(
        &TestTriangle::new(a, b, c),
        &TriangleBins::new(c, a, b, 14).unwrap(),
        100_000,
        5,
        0.01,
        1,
    );
    assert!(tri.passed, "{tri:?}");
}

#[test]
fn wrong_warps_fail() {
    let disk = run_chi_square(
        &TestDisk::<f64>::wrong(),
        &DiskBins::unit(10, 20).unwrap(),
        100_000,
        1,
        0.01,
        1,
    );
    assert!(
        !disk.passed && disk.failure == Some(ChiSquareFailure::Rejected),
        "{disk:?}"
    );
    assert!(disk.p_value < 1e-100, "{disk:?}");
    let sphere = run_chi_square(
        &TestSphere::<f64>::new(true),
        &ZPhiBins::sphere(10, 20).unwrap(),
        100_000,
        2,
        0.01,
        1,
    );
    assert!(!sphere.passed, "{sphere:?}");
    // A cosine lobe tested as if it were a k = 2 lobe.
    let lobe = run_chi_square(
        &TestLobe::new(1.0),
        &ZPhiBins::phong(2.0, 10, 20).unwrap(),
        100_000,
        3,
        0.01,
        1,
    );
    assert!(!lobe.passed, "{lobe:?}");
    // Samples outside the binned shape (a disk of radius 0.9).
    let small = DiskBins::new(Vec2::new(0.0, 0.0), 0.9, 10, 20).unwrap();
    let out = run_chi_square(&TestDisk::<f64>::correct(), &small, 10_000, 4, 0.01, 1);
    assert!(!out.passed && out.outside > 1000, "{out:?}");
    assert_eq!(out.failure, Some(ChiSquareFailure::Outside));
}
