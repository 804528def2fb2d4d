use super::*;
use crate::shapes::Hemisphere;
use crate::vector::Vec2;
use crate::warp::InverseError;
use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;

fn rng(seed: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(seed)
}

/// `true` if `points` (binary fractions given as `f64`) form a
/// (0, m, 2)-net: `2^m` points in `[0, 1)²`, one in each elementary
/// interval of area `2^-m`.
fn is_net(points: &[(f64, f64)], m: u32) -> bool {
    if points.len() != 1 << m {
        return false;
    }
    for a in 0..=m {
        let b = m - a;
        let mut seen = vec![false; 1 << m];
        for &(u, v) in points {
            if !((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v)) {
                return false;
            }
            // Scaling by powers of two and flooring is exact.
            let i = (u * f64::from(1u32 << a)).floor() as usize;
            let j = (v * f64::from(1u32 << b)).floor() as usize;
            let cell = (i << b) | j;
            if seen[cell] {
                return false;
            }
            seen[cell] = true;
        }
    }
    true
}

#[test]
fn jittered_has_one_point_per_cell_in_f32() {
    // f32 coordinates times small n are exact in f64: a strict check.
    let (nx, ny) = (7, 5);
    let pts: Vec<(f32, f32)> = jittered(nx, ny, &mut rng(1));
    assert_eq!(pts.len(), nx * ny);
    let mut count = vec![0; nx * ny];
    for (k, &(u, v)) in pts.iter().enumerate() {
        let i = (f64::from(u) * nx as f64).floor() as usize;
        let j = (f64::from(v) * ny as f64).floor() as usize;
        assert_eq!((i, j), (k % nx, k / nx), "point {k}: ({u}, {v})");
        // Strictly inside the stratum.
        assert!(f64::from(u) * nx as f64 > i as f64);
        count[j * nx + i] += 1;
    }
    assert!(count.iter().all(|&c| c == 1));
}

#[test]
fn jittered_has_one_point_per_cell_in_f64_and_is_random() {
    let n = 64;
    let pts: Vec<(f64, f64)> = jittered(n, n, &mut rng(2));
    let mut count = vec![0; n * n];
    for &(u, v) in &pts {
        // n a power of two: the scaling is exact.
        let i = (u * n as f64).floor() as usize;
        let j = (v * n as f64).floor() as usize;
        count[j * n + i] += 1;
    }
    assert!(count.iter().all(|&c| c == 1));
    // The offsets within the cells are uniform: their mean is 1/2 within
    // a few standard errors (1/√(12 · 4096) ≈ 0.0045).
    let mean = pts
        .iter()
        .map(|&(u, _)| u * n as f64 - (u * n as f64).floor())
        .sum::<f64>()
        / pts.len() as f64;
    assert!((mean - 0.5).abs() < 0.02, "{mean}");
    // Not the cell centres, and different seeds differ.
    assert!(pts.iter().any(|&(u, _)| (u * n as f64).fract() != 0.5));
    let other: Vec<(f64, f64)> = jittered(n, n, &mut rng(3));
    assert_ne!(pts, other);
    // Edge cases.
    assert!(jittered::<f64, _>(0, 5, &mut rng(1)).is_empty());
    let one: Vec<(f64, f64)> = jittered(1, 1, &mut rng(1));
    assert_eq!(one.len(), 1);
    assert!((0.0..1.0).contains(&one[0].0));
    assert_eq!(jittered_iter::<f32, _>(3, 4, &mut rng(1)).len(), 12);
}

#[cfg(feature = "mpfr")]
#[test]
fn jittered_in_mpfr_is_strictly_inside_its_cells() {
    use crate::real::Mpfr256;
    let n = 3;
    let pts: Vec<(Mpfr256, Mpfr256)> = jittered(n, n, &mut rng(4));
    for (k, (u, _)) in pts.iter().enumerate() {
        let i = (k % n) as i64;
        let scaled = u.clone() * &Mpfr256::from_i64(n as i64);
        assert!(scaled > Mpfr256::from_i64(i) && scaled < Mpfr256::from_i64(i + 1));
    }
}

#[test]
fn hammersley_known_points_and_net_property() {
    let h: Vec<(f64, f64)> = hammersley(8);
    let expected = [
        (0.0, 0.0),
        (0.125, 0.5),
        (0.25, 0.25),
        (0.375, 0.75),
        (0.5, 0.125),
        (0.625, 0.625),
        (0.75, 0.375),
        (0.875, 0.875),
    ];
    assert_eq!(h, expected);
    for m in 0..=10 {
        assert!(is_net(&hammersley::<f64>(1 << m), m), "m = {m}");
    }
    // f32 agrees (all values dyadic).
    let h32: Vec<(f32, f32)> = hammersley(8);
    assert!(
        h32.iter()
            .zip(&h)
            .all(|(a, b)| f64::from(a.0) == b.0 && f64::from(a.1) == b.1)
    );
    assert!(hammersley::<f64>(0).is_empty());
    // (n − 1)/n stays below 1 even when it would round to 1.
    let (u, _) = hammersley_point::<f32>((1 << 30) - 1, 1 << 30);
    assert!(u < 1.0);
}

#[test]
fn van_der_corput_values() {
    assert_eq!(van_der_corput::<f64>(0), 0.0);
    assert_eq!(van_der_corput::<f64>(1), 0.5);
    assert_eq!(van_der_corput::<f64>(6), 0.375);
    assert_eq!(van_der_corput::<f64>(11), 0.8125);
    // Largest index: all bits set, truncated to 53 bits, below 1.
    assert_eq!(van_der_corput::<f64>(u64::MAX), 1.0 - 2f64.powi(-53));
    assert_eq!(van_der_corput::<f32>(u64::MAX), 1.0 - 2f32.powi(-24));
}

#[test]
fn sobol_known_points() {
    let s: Vec<(f64, f64)> = sobol_2d(8);
    let expected = [
        (0.0, 0.0),
        (0.5, 0.5),
        (0.25, 0.75),
        (0.75, 0.25),
        (0.125, 0.625),
        (0.625, 0.125),
        (0.375, 0.375),
        (0.875, 0.875),
    ];
    assert_eq!(s, expected);
    // The direction numbers m_k = 1, 3, 5, 15, 17, 51 (v_k = m_k / 2^k).
    let m: Vec<u64> = (0..6).map(|k| SOBOL_DIM2[k] >> (63 - k)).collect();
    assert_eq!(m, [1, 3, 5, 15, 17, 51]);
    // u is exactly van der Corput; random access matches iteration.
    let seq = Sobol2::<f64>::new();
    for i in 0..100u64 {
        assert_eq!(seq.point(i).0, van_der_corput::<f64>(i));
    }
    let tail: Vec<(f64, f64)> = Sobol2::new().starting_at(5).take(3).collect();
    assert_eq!(tail, expected[5..8]);
}

#[test]
fn sobol_blocks_are_nets() {
    // Every block of 2^m consecutive points starting at a multiple of
    // 2^m is a (0, m, 2)-net: one point per elementary interval.
    for m in 0..=9 {
        for block in [0u64, 1, 5] {
            let start = block << m;
            let seq = Sobol2::<f64>::new();
            let pts: Vec<(f64, f64)> = (start..start + (1 << m)).map(|i| seq.point(i)).collect();
            assert!(is_net(&pts, m), "m = {m}, block {block}");
        }
    }
    // A block not aligned to 2^m is not a net in general: points 1 … 16
    // leave [0, 1) × [0, 1/16) empty (point 0 was its only one).
    let seq = Sobol2::<f64>::new();
    let pts: Vec<(f64, f64)> = (1..17).map(|i| seq.point(i)).collect();
    assert!(!is_net(&pts, 4));
    assert!(!pts.iter().any(|p| p.1 < 1.0 / 16.0));
    // Nor are 16 uniform random points.
    assert!(!is_net(&crate::harness::extremes::random_points(16, 1), 4));
}

#[test]
fn scrambled_sobol_keeps_the_net_property() {
    let a = Sobol2::<f64>::scrambled(1);
    let b = Sobol2::<f64>::scrambled(2);
    for m in [0, 4, 8, 10] {
        let pa: Vec<(f64, f64)> = (0..1u64 << m).map(|i| a.point(i)).collect();
        let pb: Vec<(f64, f64)> = (0..1u64 << m).map(|i| b.point(i)).collect();
        assert!(is_net(&pa, m), "seed 1, m = {m}");
        assert!(is_net(&pb, m), "seed 2, m = {m}");
    }
    // Randomized: the first point is no longer (0, 0), seeds differ,
    // and the same seed reproduces.
    assert_ne!(a.point(0), (0.0, 0.0));
    assert_ne!(a.point(0), b.point(0));
    assert_eq!(a.point(7), Sobol2::<f64>::scrambled(1).point(7));
    // Over many seeds, the first point is uniform: mean 1/2 (se ≈ 0.009).
    let n = 1000;
    let mean = (0..n)
        .map(|s| Sobol2::<f64>::scrambled(s).point(0).1)
        .sum::<f64>()
        / n as f64;
    assert!((mean - 0.5).abs() < 0.045, "{mean}");
    let f: (f32, f32) = Sobol2::<f32>::scrambled(9).point(3);
    assert!((0.0..1.0).contains(&f.0) && (0.0..1.0).contains(&f.1));
}

#[test]
fn halton_values() {
    let h: Vec<(f64, f64)> = halton(5);
    assert_eq!(h[0], (0.0, 0.0));
    assert_eq!(h[1], (0.5, 1.0 / 3.0));
    assert_eq!(h[2], (0.25, 2.0 / 3.0));
    assert_eq!(h[3], (0.75, 1.0 / 9.0));
    assert_eq!(h[4], (0.125, 4.0 / 9.0));
    // 3^39 − 1 has 39 digits 2: φ₃ = 1 − 3^-39, which rounds to 1 in f64.
    let x = radical_inverse_3::<f64>(3u64.pow(39) - 1);
    assert!(x < 1.0 && x > 1.0 - 1e-15);
    // Equal thirds in the first 3^5 points.
    let pts: Vec<(f64, f64)> = halton(243);
    for t in 0..3 {
        // φ₃ = k/243 rounded: a tiny guard keeps k = 81, 162 in the upper third.
        let c = pts
            .iter()
            .filter(|p| (p.1 * 3.0 + 1e-9).floor() as usize == t)
            .count();
        assert_eq!(c, 81);
    }
}

/// The identity map of the square, to observe what the sampler feeds.
#[derive(Clone, Debug)]
struct Identity;
impl<T: Real> Warp<T> for Identity {
    type Point = Vec2<T>;
    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        Vec2::new(u.clone(), v.clone())
    }
    fn pdf_unchecked(&self, _p: &Vec2<T>) -> T {
        T::one()
    }
    fn measure(&self) -> T {
        T::one()
    }
    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        Ok([p.x.clone(), p.y.clone()])
    }
    fn outside_by(&self, _p: &Vec2<T>) -> T {
        T::zero()
    }
}

#[test]
fn sampler_draws_full_resolution_inputs_in_the_half_open_square() {
    let s32 = WarpSampler::<_, f32>::new(Identity);
    let mut r = rng(5);
    let mut fine = false;
    for _ in 0..10_000 {
        let p = s32.sample(&mut r);
        assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
        // Multiples of 2^-24.
        assert_eq!((p.x * 2f32.powi(24)).fract(), 0.0);
        fine |= (p.x * 2f32.powi(23)).fract() != 0.0;
    }
    assert!(fine, "the 24th bit is never used");
    let s64 = WarpSampler::<_, f64>::new(Identity);
    let mut fine = false;
    for _ in 0..10_000 {
        let p = s64.sample(&mut r);
        assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
        assert_eq!((p.x * 2f64.powi(53)).fract(), 0.0);
        fine |= (p.x * 2f64.powi(52)).fract() != 0.0;
    }
    assert!(fine, "the 53rd bit is never used");
}

#[test]
fn sampler_mean_over_the_hemisphere() {
    // Uniform on the hemisphere: E[z] = 1/2, E[x] = E[y] = 0, with
    // standard deviations 1/√12 and 1/√3; 5 standard errors at n = 10^5.
    let n = 100_000;
    let tol_z = 5.0 / (12.0 * n as f64).sqrt();
    let tol_xy = 5.0 / (3.0 * n as f64).sqrt();
    let s = WarpSampler::new(Hemisphere::<f64>::new());
    let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
    for p in s.sample_iter(rng(6)).take(n) {
        assert!(p.z >= 0.0);
        x += p.x;
        y += p.y;
        z += p.z;
    }
    let n_f = n as f64;
    assert!((z / n_f - 0.5).abs() < tol_z, "{}", z / n_f);
    assert!((x / n_f).abs() < tol_xy && (y / n_f).abs() < tol_xy);

    let s = WarpSampler::new(Hemisphere::<f32>::new());
    let mean: f64 = (&s)
        .sample_iter(rng(7))
        .take(n)
        .map(|p| f64::from(p.z))
        .sum::<f64>()
        / n_f;
    assert!((mean - 0.5).abs() < tol_z, "{mean}");
    assert_eq!(s.warp().measure(), 2.0 * core::f32::consts::PI);
}
