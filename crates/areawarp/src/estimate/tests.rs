use super::*;
use crate::shapes::{Hemisphere, PhongLobe};
use crate::vector::Vec3;
use rand::RngExt;
use rand::rngs::Xoshiro256PlusPlus;

/// A 1-D strategy on [0, 1] with the linear density `p(x) = 1 + a(1 − 2x)`,
/// `|a| < 1` (only `u` is used).
struct Linear {
    a: f64,
}

impl Linear {
    fn density(&self, x: f64) -> f64 {
        if (0.0..=1.0).contains(&x) {
            1.0 + self.a * (1.0 - 2.0 * x)
        } else {
            0.0
        }
    }
}

impl Strategy for Linear {
    type Point = f64;
    fn sample(&self, u: f64, _v: f64) -> Option<Sample<f64>> {
        // F(x) = x + a(x − x²) = u, solved without cancellation.
        let b = 1.0 + self.a;
        let x = 2.0 * u / (b + (b * b - 4.0 * self.a * u).max(0.0).sqrt());
        let x = x.clamp(0.0, 1.0);
        Some(Sample {
            point: x,
            pdf: self.density(x),
        })
    }
    fn pdf(&self, x: &f64) -> f64 {
        self.density(*x)
    }
}

/// The test integrand `x⁴ + (1 − x)⁴` on [0, 1], integral 2/5: peaks at
/// both ends, each favoured by one of the two linear strategies.
fn peaks(x: &f64) -> f64 {
    x.powi(4) + (1.0 - x).powi(4)
}
const PEAKS: f64 = 0.4;

fn uniform_points(n: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<(f64, f64)> {
    (0..n).map(|_| (rng.random(), rng.random())).collect()
}

const HEURISTICS: [Heuristic; 5] = [
    Heuristic::Balance,
    Heuristic::Power(2.0),
    Heuristic::Power(0.5),
    Heuristic::Power(8.0),
    Heuristic::Maximum,
];

/// Exact variance of one MIS estimate with counts `n` (midpoint rule,
/// 10⁵ cells): `Σ_i (1/N_i) [∫ w_i² f² / p_i − (∫ w_i f)²]`.
fn exact_variance(strategies: &[&Linear], n: &[usize], h: Heuristic) -> f64 {
    let m = 100_000;
    let k = strategies.len();
    let mut second = vec![0.0; k];
    let mut first = vec![0.0; k];
    let mut q = vec![0.0; k];
    for c in 0..m {
        let x = (c as f64 + 0.5) / m as f64;
        let fx = peaks(&x);
        for j in 0..k {
            q[j] = n[j] as f64 * strategies[j].density(x);
        }
        for i in 0..k {
            if n[i] == 0 {
                continue;
            }
            let w = h.weight(i, &q);
            second[i] += w * w * fx * fx / strategies[i].density(x) / m as f64;
            first[i] += w * fx / m as f64;
        }
    }
    (0..k)
        .filter(|&i| n[i] > 0)
        .map(|i| (second[i] - first[i] * first[i]) / n[i] as f64)
        .sum()
}

#[test]
fn estimate_weights_are_nonnegative_and_sum_to_one() {
    let mut rng = job_rng(1, 0);
    let specials = [
        0.0,
        1e-300,
        5e-324,
        1.0,
        3.5,
        1e300,
        f64::MAX,
        f64::INFINITY,
        f64::NAN,
        -2.0,
    ];
    let mut worst = 0.0_f64;
    for trial in 0..20_000 {
        let k = 1 + trial % 5;
        let q: Vec<f64> = (0..k)
            .map(|_| {
                if rng.random::<f64>() < 0.3 {
                    specials[rng.random_range(0..specials.len())]
                } else {
                    // Densities over 40 orders of magnitude.
                    10f64.powf(rng.random_range(-20.0..20.0))
                }
            })
            .collect();
        for h in HEURISTICS {
            let mut w = vec![0.0; k];
            h.weights(&q, &mut w);
            assert!(
                w.iter().all(|&x| x >= 0.0 && x.is_finite()),
                "{h:?} {q:?} {w:?}"
            );
            let s: f64 = w.iter().sum();
            worst = worst.max((s - 1.0).abs());
            assert!((s - 1.0).abs() <= 8.0 * f64::EPSILON, "{h:?} {q:?} {w:?}");
        }
    }
    eprintln!("largest |Σw − 1| = {worst:e}");
}

#[test]
fn estimate_heuristic_values() {
    let q = [1.0, 3.0, 0.0];
    let w = |h: Heuristic, i| h.weight(i, &q);
    assert_eq!(w(Heuristic::Balance, 0), 0.25);
    assert_eq!(w(Heuristic::Balance, 1), 0.75);
    assert_eq!(w(Heuristic::Balance, 2), 0.0);
    assert!((w(Heuristic::Power(2.0), 0) - 0.1).abs() < 1e-15);
    assert!((w(Heuristic::Power(1.0), 1) - 0.75).abs() < 1e-15);
    assert_eq!(w(Heuristic::Maximum, 1), 1.0);
    assert_eq!(w(Heuristic::Maximum, 0), 0.0);
    // Ties share, no density anywhere gives 1/k, out of range gives 0.
    assert_eq!(Heuristic::Maximum.weight(0, &[2.0, 2.0]), 0.5);
    assert_eq!(Heuristic::Balance.weight(2, &[0.0, 0.0, 0.0, 0.0]), 0.25);
    assert_eq!(Heuristic::Balance.weight(5, &[1.0]), 0.0);
    // Huge β approaches the maximum heuristic.
    assert!(Heuristic::Power(200.0).weight(1, &q) > 1.0 - 1e-12);
    assert!(Heuristic::Power(0.0).validate().is_err());
    assert!(Heuristic::Power(f64::NAN).validate().is_err());
    assert!(Heuristic::Power(2.0).validate().is_ok());
    assert_eq!(Heuristic::Power(2.0).name(), "power(2)");
}

#[test]
fn estimate_mis_weights_at_points_sum_to_one() {
    let (p1, p2) = (Linear { a: 0.9 }, Linear { a: -0.9 });
    let s: [&dyn Strategy<Point = f64>; 2] = [&p1, &p2];
    for h in HEURISTICS {
        let mis = Mis::new(&s, &[3, 1], h).unwrap();
        let mut w = [0.0; 2];
        for c in 0..=1000 {
            let x = c as f64 / 1000.0;
            mis.weights_at(&x, &mut w);
            assert!(w[0] >= 0.0 && w[1] >= 0.0);
            assert!(
                (w[0] + w[1] - 1.0).abs() <= 4.0 * f64::EPSILON,
                "{h:?} {x} {w:?}"
            );
        }
    }
}

#[test]
fn estimate_mis_is_unbiased_for_every_heuristic() {
    let (p1, p2) = (Linear { a: 0.9 }, Linear { a: -0.9 });
    let s: [&dyn Strategy<Point = f64>; 2] = [&p1, &p2];
    // Unequal counts exercise the N_i in the weights and normalization.
    let counts = [30_000, 10_000];
    for (t, h) in HEURISTICS.into_iter().enumerate() {
        let mis = Mis::new(&s, &counts, h).unwrap();
        let mut rng = job_rng(7, t as u64);
        let e = mis
            .estimate(peaks, |i| uniform_points(counts[i], &mut rng))
            .unwrap();
        let z = (e.value - PEAKS) / e.std_error();
        let exact = exact_variance(&[&p1, &p2], &counts, h);
        eprintln!(
            "{:>10}: value {:.6} z = {z:+.2}, variance {:.3e} (exact {:.3e})",
            h.name(),
            e.value,
            e.variance,
            exact
        );
        assert!(z.abs() < 4.0, "{h:?}: z = {z}");
        assert!((e.variance / exact - 1.0).abs() < 0.1, "{h:?}");
    }
    // Single strategies, for comparison.
    for (t, p) in [&p1, &p2].into_iter().enumerate() {
        let mut rng = job_rng(8, t as u64);
        let e = monte_carlo(p, peaks, uniform_points(40_000, &mut rng));
        let z = e.z_score(PEAKS);
        eprintln!("single {t}: value {:.6} z = {z:+.2}", e.value);
        assert!(z.abs() < 4.0);
    }
}

/// The two linear strategies favour opposite ends of `x⁴ + (1 − x)⁴`: each
/// alone has per-sample variance 0.432, the balance heuristic with one
/// sample of each 0.0327 per pair (vs 0.216 for two samples of one).
#[test]
fn estimate_balance_heuristic_beats_each_single_strategy() {
    let (p1, p2) = (Linear { a: 0.9 }, Linear { a: -0.9 });
    let s: [&dyn Strategy<Point = f64>; 2] = [&p1, &p2];
    let n = 20_000;
    let mut rng = job_rng(3, 0);
    let mut measured = Vec::new();
    for h in HEURISTICS {
        let mis = Mis::new(&s, &[n, n], h).unwrap();
        let e = mis
            .estimate(peaks, |_| uniform_points(n, &mut rng))
            .unwrap();
        measured.push((h, e.variance * n as f64));
    }
    // The same total of 2n samples from one strategy.
    let single: Vec<f64> = [&p1, &p2]
        .into_iter()
        .map(|p| {
            let e = monte_carlo(p, peaks, uniform_points(2 * n, &mut rng));
            e.variance * n as f64
        })
        .collect();
    for (h, v) in &measured {
        let exact = exact_variance(&[&p1, &p2], &[1, 1], *h);
        eprintln!(
            "{:>10}: variance per pair {v:.4} (exact {exact:.4})",
            h.name()
        );
        assert!((v / exact - 1.0).abs() < 0.1);
    }
    let exact_single = exact_variance(&[&p1, &p2], &[2, 0], Heuristic::Balance);
    eprintln!("single strategies: {single:?} (exact {exact_single:.4})");
    for v in &single {
        assert!((v / exact_single - 1.0).abs() < 0.1);
    }
    let balance = measured[0].1;
    assert!(balance < 0.25 * single[0] && balance < 0.25 * single[1]);
    // Here the balance heuristic also beats the other heuristics.
    assert!(measured[1..].iter().all(|(_, v)| balance < *v));
}

#[test]
fn estimate_cosine_sampling_of_cosine_has_zero_variance() {
    let cosine = WarpStrategy::new(PhongLobe::<f64>::new(1.0).unwrap());
    let mut rng = job_rng(5, 0);
    let e = monte_carlo(&cosine, |d: &Vec3<f64>| d.z, uniform_points(1000, &mut rng));
    assert!((e.value - std::f64::consts::PI).abs() < 1e-12);
    assert!(e.variance < 1e-20);
    let uniform = WarpStrategy::new(Hemisphere::<f64>::new());
    let e = monte_carlo(
        &uniform,
        |d: &Vec3<f64>| d.z,
        uniform_points(100_000, &mut rng),
    );
    assert!(e.z_score(std::f64::consts::PI).abs() < 4.0);
    // Hemisphere MIS with a restricted-support strategy: the lobe k = 20.
    let lobe = WarpStrategy::new(PhongLobe::<f64>::new(20.0).unwrap());
    let s: [&dyn Strategy<Point = Vec3<f64>>; 2] = [&uniform, &lobe];
    let f = |d: &Vec3<f64>| d.z.max(0.0).powi(30) + 0.1;
    // ∫ (cos³⁰θ + 0.1) dω = 2π/31 + 0.2π.
    let exact = 2.0 * std::f64::consts::PI / 31.0 + 0.2 * std::f64::consts::PI;
    for h in HEURISTICS {
        let mis = Mis::new(&s, &[5000, 5000], h).unwrap();
        let e = mis.estimate(f, |_| uniform_points(5000, &mut rng)).unwrap();
        assert!(((e.value - exact) / e.std_error()).abs() < 4.0, "{h:?}");
    }
}

#[test]
fn estimate_mixture_density_and_support() {
    // Two halves of [0, 1], uniform on each: the mixture is uniform.
    struct Half(f64);
    impl Strategy for Half {
        type Point = f64;
        fn sample(&self, u: f64, _v: f64) -> Option<Sample<f64>> {
            Some(Sample {
                point: self.0 + 0.5 * u,
                pdf: 2.0,
            })
        }
        fn pdf(&self, x: &f64) -> f64 {
            if (self.0..=self.0 + 0.5).contains(x) {
                2.0
            } else {
                0.0
            }
        }
    }
    let m = Mixture::new(vec![Half(0.0), Half(0.5)], &[1.0, 3.0]).unwrap();
    assert_eq!(m.probabilities(), &[0.25, 0.75]);
    let s = m.sample(0.1, 0.0).unwrap();
    assert!((s.point - 0.2).abs() < 1e-15 && (s.pdf - 0.5).abs() < 1e-15);
    let s = m.sample(0.25 + 0.75 * 0.5, 0.0).unwrap();
    assert!((s.point - 0.75).abs() < 1e-15 && (s.pdf - 1.5).abs() < 1e-15);
    assert!((m.pdf(&0.9) - 1.5).abs() < 1e-15);
    assert!(m.sample(1.0, 0.0).unwrap().point <= 1.0);
    let mut rng = job_rng(9, 0);
    let e = monte_carlo(&m, |x: &f64| x * x, uniform_points(50_000, &mut rng));
    assert!(e.z_score(1.0 / 3.0).abs() < 4.0);
    assert!(Mixture::new(vec![Half(0.0)], &[0.0]).is_err());
    assert!(Mixture::new(vec![Half(0.0)], &[1.0, 2.0]).is_err());
    assert!(Mixture::new(vec![Half(0.0)], &[f64::NAN]).is_err());
    // A zero-probability part is never chosen.
    let m = Mixture::new(vec![Half(0.0), Half(0.5)], &[0.0, 1.0]).unwrap();
    assert!(m.sample(0.0, 0.0).unwrap().point >= 0.5);
}

#[test]
fn estimate_mis_rejects_bad_input() {
    let p1 = Linear { a: 0.5 };
    let s: [&dyn Strategy<Point = f64>; 1] = [&p1];
    assert!(Mis::new(&s, &[1, 2], Heuristic::Balance).is_err());
    assert!(Mis::new(&s, &[0], Heuristic::Balance).is_err());
    assert!(Mis::new(&s, &[1], Heuristic::Power(-1.0)).is_err());
    let mis = Mis::new(&s, &[10], Heuristic::Balance).unwrap();
    assert!(mis.estimate(peaks, |_| vec![(0.5, 0.5); 3]).is_err());
    assert_eq!(mis.len(), 1);
}

#[test]
fn estimate_stats_merge_matches_push() {
    let xs: Vec<f64> = (0..1000).map(|i| ((i * 37) % 101) as f64 / 7.0).collect();
    let all: Stats = xs.iter().cloned().collect();
    let mut merged = Stats::new();
    for chunk in xs.chunks(77) {
        merged.merge(&chunk.iter().cloned().collect());
    }
    assert_eq!(merged.count(), 1000);
    assert!((merged.mean() - all.mean()).abs() < 1e-12);
    assert!((merged.variance() / all.variance() - 1.0).abs() < 1e-12);
    let direct_mean = xs.iter().sum::<f64>() / 1000.0;
    let direct_var = xs.iter().map(|x| (x - direct_mean).powi(2)).sum::<f64>() / 999.0;
    assert!((all.variance() / direct_var - 1.0).abs() < 1e-12);
    assert!(Stats::new().variance().is_nan());
}

#[test]
fn estimate_job_seeds_are_distinct_and_stable() {
    let seeds: std::collections::HashSet<u64> = (0..10_000).map(|i| job_seed(42, i)).collect();
    assert_eq!(seeds.len(), 10_000);
    assert_ne!(job_seed(1, 0), job_seed(2, 0));
    let a: Vec<u64> = run_jobs_sequential(4, 9, |_, r| rand::Rng::next_u64(r));
    let b: Vec<u64> = (0..4)
        .map(|i| rand::Rng::next_u64(&mut job_rng(9, i)))
        .collect();
    assert_eq!(a, b);
}

#[test]
fn estimate_warp_strategy_with_support() {
    use crate::shapes::SphericalTriangle;
    // The octant: constant density 1/Ω = 2/π on it, 0 elsewhere once
    // restricted to the triangle.
    let octant = SphericalTriangle::<f64>::new(
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    )
    .unwrap();
    let free = WarpStrategy::new(octant.clone());
    let inside = |p: &Vec3<f64>| p.x >= 0.0 && p.y >= 0.0 && p.z >= 0.0;
    let restricted = WarpStrategy::with_support(octant, inside);
    let away = Vec3::new(-1.0, 0.0, 0.0);
    let on = Vec3::new(1.0, 1.0, 1.0).normalized().unwrap();
    // Every warp's pdf is 0 off its shape (the `Warp` contract), so the
    // support test only restricts further.
    assert_eq!(free.pdf(&away), 0.0);
    assert!((free.pdf(&on) - 2.0 / std::f64::consts::PI).abs() < 1e-15);
    assert_eq!(restricted.pdf(&away), 0.0);
    assert!((restricted.pdf(&on) - 2.0 / std::f64::consts::PI).abs() < 1e-15);
    let s = restricted.sample(0.3, 0.6).unwrap();
    assert!(inside(&s.point) && (s.pdf - restricted.pdf(&s.point)).abs() < 1e-15);
    // MIS of the octant with uniform hemisphere sampling: ∫_hemisphere z dω = π.
    let hemi = WarpStrategy::new(Hemisphere::<f64>::new());
    let st: [&dyn Strategy<Point = Vec3<f64>>; 2] = [&restricted, &hemi];
    let mis = Mis::new(&st, &[4000, 4000], Heuristic::Power(2.0)).unwrap();
    let mut rng = job_rng(13, 0);
    let e = mis
        .estimate(
            |d: &Vec3<f64>| d.z.max(0.0),
            |_| uniform_points(4000, &mut rng),
        )
        .unwrap();
    assert!(((e.value - std::f64::consts::PI) / e.std_error()).abs() < 4.0);
}
