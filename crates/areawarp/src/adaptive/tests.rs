//! Tests of the adaptive sampler (issue 5, item 4, at sizes for the default
//! suite; the full study is `#[ignore]`d).

use super::*;
use crate::estimate::{Stats, job_rng, run_jobs_sequential};
use crate::shapes::ProjectedPolygon;
use crate::shapes::polygon_measures;
use crate::warp::Warp;
use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;

fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}

fn up() -> Vec3<f64> {
    v(0.0, 0.0, 1.0)
}

/// A random triangle above the horizon: a centre direction with
/// `z ∈ [zmin, 1]` and three vertices at angular distance up to `size`.
fn random_triangle(rng: &mut Xoshiro256PlusPlus, zmin: f64, size: f64) -> [Vec3<f64>; 3] {
    loop {
        let z: f64 = zmin + (1.0 - zmin) * rng.random::<f64>();
        let phi: f64 = 2.0 * core::f64::consts::PI * rng.random::<f64>();
        let r = (1.0 - z * z).sqrt();
        let c = v(r * phi.cos(), r * phi.sin(), z);
        let mut out = Vec::new();
        for _ in 0..3 {
            let d = v(
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5,
            );
            let p = c.add(&d.scale(&(2.0 * size)));
            match p.normalized() {
                Some(p) if p.z >= 0.0 => out.push(p),
                _ => break,
            }
        }
        if out.len() == 3 && SphericalTriangle::new(out[0], out[1], out[2]).is_ok() {
            return [out[0], out[1], out[2]];
        }
    }
}

/// The largest z over a dense sampling of the triangle: its edges (2000
/// points each), an interior grid through Arvo's map, and the pole if the
/// triangle contains it.
fn brute_force_max_z(t: &[Vec3<f64>; 3]) -> f64 {
    let mut m = f64::NEG_INFINITY;
    for i in 0..3 {
        let (a, b) = (&t[i], &t[(i + 1) % 3]);
        for j in 0..=2000 {
            let s = j as f64 / 2000.0;
            if let Some(p) = a.scale(&(1.0 - s)).add(&b.scale(&s)).normalized() {
                m = m.max(p.z);
            }
        }
    }
    let tri = SphericalTriangle::new(t[0], t[1], t[2]).unwrap();
    for i in 0..=60 {
        for j in 0..=60 {
            m = m.max(tri.map(&(i as f64 / 60.0), &(j as f64 / 60.0)).z);
        }
    }
    if tri.contains(&up()) {
        m = 1.0;
    }
    m
}

#[test]
fn adaptive_max_cosine_matches_brute_force() {
    // Constructed cases: pole inside, maximum inside an arc, at a vertex.
    let pole = [v(0.3, 0.0, 1.0), v(-0.2, 0.3, 1.0), v(-0.2, -0.3, 1.0)];
    assert_eq!(max_cosine(&pole[0], &pole[1], &pole[2]), 1.0);
    let (a, b) = (v(1.0, -1.0, 1.0), v(1.0, 1.0, 1.0));
    let arc = arc_max_cosine(&a, &b);
    // The arc peaks at (1, 0, 1)/√2 (symmetry).
    assert!((arc - 0.5f64.sqrt()).abs() < 1e-15, "{arc}");
    let tri = [a, b, v(1.0, 0.0, 0.2)];
    assert!((max_cosine(&tri[0], &tri[1], &tri[2]) - 0.5f64.sqrt()).abs() < 1e-15);
    // A vertex maximum.
    let vert = [v(1.0, 0.0, 0.1), v(0.0, 1.0, 0.1), v(1.0, 1.0, 1.0)];
    assert!((max_cosine(&vert[0], &vert[1], &vert[2]) - 1.0 / 3f64.sqrt()).abs() < 1e-15);
    // Both orientations agree.
    assert_eq!(
        max_cosine(&pole[0], &pole[2], &pole[1]),
        max_cosine(&pole[0], &pole[1], &pole[2])
    );
    // Random triangles of all sizes and heights.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let mut inside = 0;
    let mut on_arc = 0;
    for i in 0..300 {
        let size = [0.02, 0.2, 0.6][i % 3];
        let zmin = [0.0, 0.5, 0.9][(i / 3) % 3];
        let t = random_triangle(&mut rng, zmin, size);
        let m = max_cosine(&t[0], &t[1], &t[2]);
        let m2 = max_cosine(&t[0], &t[2], &t[1]);
        assert_eq!(m, m2);
        let bf = brute_force_max_z(&t);
        assert!(bf <= m + 1e-13, "{i}: sampled {bf} above m = {m}");
        assert!(m - bf < 2e-6, "{i}: m = {m} not attained (sampled {bf})");
        let vmax = t.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
        if m == 1.0 {
            inside += 1;
        } else if m > vmax + 1e-9 {
            on_arc += 1;
        }
    }
    // The random set exercises all three cases.
    assert!(inside > 3 && on_arc > 3, "pole {inside}, arc {on_arc}");
}

#[test]
fn adaptive_measures_against_references() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(12);
    for i in 0..200 {
        let size = [0.01, 0.1, 0.5][i % 3];
        let t = random_triangle(&mut rng, 0.0, size);
        let m = TriangleMeasures::new(t[0], t[1], t[2]).unwrap();
        // σ against the Gauss–Bonnet fan of `polygon_measures` (which
        // loses a few digits on slivers) and, with MPFR, against 256 bits.
        let sigma = polygon_measures::solid_angle(&t);
        assert!(
            (m.solid_angle / sigma - 1.0).abs() < 1e-8,
            "{i}: {} vs {sigma}, {t:?}",
            m.solid_angle
        );
        #[cfg(feature = "mpfr")]
        {
            use crate::real::Mpfr256;
            let h =
                TriangleMeasures::<Mpfr256>::new(t[0].convert(), t[1].convert(), t[2].convert())
                    .unwrap();
            let rel = |x: f64, y: &Mpfr256| (x / y.to_f64() - 1.0).abs();
            assert!(rel(m.solid_angle, &h.solid_angle) < 1e-12, "{i}");
            // Lambert's sum of three O(size) terms to an O(size²) result:
            // relative error ~ u/size (1e-12 for this set's 5e-3 rad slivers,
            // times the amplification of the unit vertices' own rounding:
            // 1.5e-11 measured at the worst case with one-division
            // normalization).
            assert!(
                rel(m.projected_solid_angle, &h.projected_solid_angle) < 3e-11,
                "{i}: {:e} {t:?} {}",
                rel(m.projected_solid_angle, &h.projected_solid_angle),
                m.projected_solid_angle
            );
            assert!(rel(m.max_cosine, &h.max_cosine) < 1e-15, "{i}");
        }
        // The subdivision's own evaluation: σ as SphericalTriangle's, σ⊥
        // as polygon_measures' Lambert.
        let tri = SphericalTriangle::new(t[0], t[1], t[2]).unwrap();
        let (a, b, c) = (tri.a(), tri.b(), tri.c());
        let (omega, ok) = robust_solid_angle(a, b, c);
        assert!(ok);
        assert!((omega / tri.solid_angle() - 1.0).abs() < 1e-15, "{i}");
        let lp = polygon_measures::projected_solid_angle(&t, &up()).abs();
        assert!((lambert(a, b, c) / lp - 1.0).abs() < 1e-9, "{i}");
        let pp = ProjectedPolygon::new(&t).unwrap();
        assert!(
            (m.projected_solid_angle / pp.projected_solid_angle() - 1.0).abs() < 1e-9,
            "{i}"
        );
        assert!(m.k >= -1e-12, "{i}: k = {}", m.k);
        assert!(m.projected_solid_angle <= m.max_cosine * m.solid_angle * (1.0 + 1e-12));
    }
    // The octant: σ = π/2, σ⊥ = π/4, m = 1, k = 1.
    let o = TriangleMeasures::new(v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), up()).unwrap();
    assert!((o.solid_angle - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert!((o.projected_solid_angle - core::f64::consts::FRAC_PI_4).abs() < 1e-15);
    assert_eq!(o.max_cosine, 1.0);
    assert!((o.k - 1.0).abs() < 1e-15);
    // Below the horizon: rejected.
    assert!(matches!(
        TriangleMeasures::new(v(1.0, 0.0, -0.1), v(0.0, 1.0, 0.1), up()),
        Err(WarpError::InvalidParameter { .. })
    ));
    // Generic: the same numbers at 256 bits.
    #[cfg(feature = "mpfr")]
    {
        use crate::real::Mpfr256;
        let t = [v(0.5, 0.1, 0.8), v(0.2, 0.6, 0.7), v(0.1, 0.1, 1.0)];
        let m = TriangleMeasures::new(t[0], t[1], t[2]).unwrap();
        let h = TriangleMeasures::<Mpfr256>::new(t[0].convert(), t[1].convert(), t[2].convert())
            .unwrap();
        assert!((h.k.to_f64() - m.k).abs() < 1e-13);
        assert!((h.projected_solid_angle.to_f64() / m.projected_solid_angle - 1.0).abs() < 1e-14);
    }
}

/// All pieces: probabilities sum to 1, measures add up to the triangle's,
/// the non-capped ones have k < K, P ≈ σ⊥/σ⊥(E).
#[test]
fn adaptive_partition_covers_the_triangle() {
    let tris = [
        [v(1.0, -0.5, 0.3), v(1.0, 0.6, 0.4), v(0.2, 0.0, 1.0)],
        [v(0.6, 0.0, 1.0), v(-0.3, 0.5, 1.0), v(-0.3, -0.55, 1.05)],
        [v(1.0, -0.6, -0.3), v(0.8, 0.7, 0.2), v(0.3, 0.0, 0.9)],
    ];
    // Near the horizon pieces must shrink with their height (k ≈ size/z):
    // the crossing triangle's partition grows like 2^depth/K², so it is
    // checked at K = 0.3 and depth 8 only.
    for (ti, t) in tris.iter().enumerate() {
        let (ks, depth): (&[f64], u32) = if ti < 2 {
            (&[0.3, 0.1, 0.01], 12)
        } else {
            (&[0.3], 8)
        };
        for &k in ks {
            let a = AdaptiveTriangle::new(t[0], t[1], t[2], k)
                .unwrap()
                .with_max_depth(depth)
                .unwrap();
            let pieces = a.pieces(1 << 20).unwrap();
            assert_eq!(a.piece_count(1 << 20), Some(pieces.len()));
            let p: f64 = pieces.iter().map(|p| p.probability).sum();
            assert!((p - 1.0).abs() < 1e-12, "{ti} {k}: ΣP = {p}");
            let s: f64 = pieces.iter().map(|p| p.measures.solid_angle).sum();
            assert!((s / a.solid_angle() - 1.0).abs() < 1e-11, "{ti} {k}");
            let sp: f64 = pieces
                .iter()
                .map(|p| p.measures.projected_solid_angle)
                .sum();
            assert!((sp / a.projected_solid_angle() - 1.0).abs() < 1e-11);
            for q in &pieces {
                assert_eq!(q.capped, !(q.measures.k < k));
                assert!(q.depth <= depth);
                if q.capped {
                    assert_eq!(q.depth, depth);
                }
                // P = σ⊥(piece)/σ⊥(E) to rounding (Lambert's sum loses
                // relative accuracy for the tiny σ⊥ of pieces on the horizon).
                let sp = a.projected_solid_angle();
                let diff = q.probability * sp - q.measures.projected_solid_angle;
                assert!(diff.abs() < 1e-13 * sp, "{ti} {k}: {diff}");
                if q.probability > 1e-4 {
                    assert!((diff / q.measures.projected_solid_angle).abs() < 1e-11);
                }
            }
            // Only the crossing triangle (pieces on the horizon) has capped pieces,
            // and their excess is tiny.
            let excess = a.capped_excess(1 << 20).unwrap();
            if ti < 2 {
                assert_eq!(excess, 0.0);
            } else {
                assert!(excess > 0.0 && excess < 1e-3, "{excess}");
            }
            // Smaller K, finer partition.
            if k < 0.3 {
                let coarse = a.clone().with_threshold(k * 3.0).unwrap();
                let nc = coarse.piece_count(1 << 20).unwrap();
                assert!(nc <= pieces.len(), "{ti} {k}: {nc} {}", pieces.len());
            }
        }
    }
}

#[test]
fn adaptive_distribute_samples_follows_section_4_1() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(13);
    // Exact floors: no residual, the same counts for every rule that
    // floors, whatever the random stream.
    for rule in [Allocation::Successive, Allocation::Systematic] {
        for _ in 0..50 {
            assert_eq!(
                distribute_samples(&[0.5, 0.25, 0.125, 0.125], 8, rule, &mut rng).unwrap(),
                vec![4, 2, 1, 1]
            );
            assert_eq!(
                distribute_samples(&[0.5, 0.25, 0.125, 0.125], 16, rule, &mut rng).unwrap(),
                vec![8, 4, 2, 2]
            );
            // Unnormalized input is normalized.
            assert_eq!(
                distribute_samples(&[2.0, 1.0, 1.0, 0.0], 4, rule, &mut rng).unwrap(),
                vec![2, 1, 1, 0]
            );
        }
    }
    // p n = (3.6, 2.7, 1.8, 0.9): floors (3, 2, 1, 0), 3 residual samples,
    // each region floor or floor + 1; frequencies of the extra sample are
    // the fractional parts for the systematic rule (and the paper's claim),
    // the successive-sampling inclusion probabilities for the paper's rule.
    let p = [0.4, 0.3, 0.2, 0.1];
    let n = 9;
    for rule in [
        Allocation::Successive,
        Allocation::Systematic,
        Allocation::Multinomial,
    ] {
        let trials = 200_000;
        let mut sum = [0.0f64; 4];
        for _ in 0..trials {
            let c = distribute_samples(&p, n, rule, &mut rng).unwrap();
            assert_eq!(c.iter().sum::<usize>(), n);
            if rule != Allocation::Multinomial {
                for (ci, fl) in c.iter().zip([3usize, 2, 1, 0]) {
                    assert!(*ci == fl || *ci == fl + 1, "{rule}: {c:?}");
                }
            }
            for i in 0..4 {
                sum[i] += c[i] as f64;
            }
        }
        let e = expected_counts(&p, n, rule).unwrap();
        for i in 0..4 {
            let mean = sum[i] / trials as f64;
            // Standard error ≤ √(0.25/trials) for floor+Bernoulli, √(n p(1−p)/trials) for multinomial.
            let se = if rule == Allocation::Multinomial {
                (n as f64 * p[i] * (1.0 - p[i]) / trials as f64).sqrt()
            } else {
                (0.25 / trials as f64).sqrt()
            };
            assert!(
                (mean - e[i]).abs() < 5.0 * se,
                "{rule} {i}: {mean} vs {}",
                e[i]
            );
        }
    }
    let succ = expected_counts(&p, n, Allocation::Successive).unwrap();
    let sys = expected_counts(&p, n, Allocation::Systematic).unwrap();
    for i in 0..4 {
        assert!((sys[i] - p[i] * n as f64).abs() < 1e-12);
    }
    // The paper's rule: E[n_i] ≠ p_i n once r ≥ 2 (here r = 3).
    let dev: f64 = (0..4).map(|i| (succ[i] - sys[i]).abs()).fold(0.0, f64::max);
    assert!(dev > 0.01, "{succ:?}");
    // r = 1 (fractional parts sum to 1): the paper's rule is exact.
    let p1 = [0.35, 0.35, 0.15, 0.15];
    let e1 = expected_counts(&p1, 3, Allocation::Successive).unwrap();
    for i in 0..4 {
        assert!((e1[i] - 3.0 * p1[i]).abs() < 1e-12, "{e1:?}");
    }
    // The documented r = 2 example.
    let e2 = expected_counts(&[0.45, 0.45, 0.05, 0.05], 2, Allocation::Successive).unwrap();
    let pi1 = 0.45 + 0.45 * 0.9 / 1.1 + 2.0 * 0.05 * 0.9 / 1.9;
    assert!((e2[0] - pi1).abs() < 1e-12 && (e2[1] - pi1).abs() < 1e-12);
    assert!((e2.iter().sum::<f64>() - 2.0).abs() < 1e-12);
    // Invalid input.
    assert!(distribute_samples(&[], 3, Allocation::Systematic, &mut rng).is_err());
    assert!(distribute_samples(&[0.0, 0.0], 3, Allocation::Systematic, &mut rng).is_err());
    assert!(distribute_samples(&[1.0, -0.1], 3, Allocation::Systematic, &mut rng).is_err());
    assert!(distribute_samples(&[f64::NAN, 1.0], 3, Allocation::Systematic, &mut rng).is_err());
}

/// A triangle and K for which the partition is exactly the first split:
/// the counts per sub-triangle are then exactly DistributeSamples'.
#[test]
fn adaptive_counts_per_piece_follow_section_4_1() {
    let t = [v(1.0, -0.3, 0.5), v(1.0, 0.35, 0.6), v(0.7, 0.0, 1.0)];
    let root = TriangleMeasures::new(t[0], t[1], t[2]).unwrap();
    let k = root.k * 0.999;
    let a = AdaptiveTriangle::new(t[0], t[1], t[2], k).unwrap();
    let pieces = a.pieces(16).unwrap();
    assert_eq!(pieces.len(), 4, "one split");
    assert!(pieces.iter().all(|p| p.depth == 1 && !p.capped));
    let p: Vec<f64> = pieces.iter().map(|q| q.probability).collect();
    for rule in [Allocation::Successive, Allocation::Systematic] {
        let a = a.clone().with_allocation(rule);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(14);
        for n in [1usize, 2, 3, 5, 8, 13, 40, 100, 1000] {
            for _ in 0..40 {
                let set = a.generate(n, &mut rng);
                assert_eq!(set.len(), n);
                let mut counts = [0usize; 4];
                for l in &set.leaves {
                    assert_eq!(l.depth, 1);
                    counts[(l.code % 4) as usize] += l.count;
                }
                for i in 0..4 {
                    let fl = (p[i] * n as f64).floor() as usize;
                    assert!(
                        counts[i] == fl || counts[i] == fl + 1,
                        "{rule} n = {n}: {counts:?}, p = {p:?}"
                    );
                }
                // The per-sample leaf index is consistent with the visits.
                for (s, &l) in set.leaf.iter().enumerate() {
                    assert!(set.leaves[l as usize].count > 0, "{s}");
                }
            }
        }
    }
    // Frequencies: E[n_i] = p_i n for the systematic rule (n = 3: floors
    // and 1–3 residual samples).
    let a = a.with_allocation(Allocation::Systematic);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(15);
    let trials = 40_000;
    let mut sum = [0.0f64; 4];
    for _ in 0..trials {
        let set = a.generate(3, &mut rng);
        for l in &set.leaves {
            sum[(l.code % 4) as usize] += l.count as f64;
        }
    }
    for i in 0..4 {
        let mean = sum[i] / trials as f64;
        let se = (0.25 / trials as f64).sqrt();
        assert!(
            (mean - 3.0 * p[i]).abs() < 5.0 * se,
            "{i}: {mean} vs {}",
            3.0 * p[i]
        );
    }
}

/// Every weight is at most σ⊥(E)(1 + K) (the pointwise form of the
/// bound), the density matches [`AdaptiveTriangle::pdf`], the directions
/// lie in the triangle above the horizon.
#[test]
fn adaptive_weights_and_densities() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(16);
    let mut tris: Vec<[Vec3<f64>; 3]> = (0..12)
        .map(|i| random_triangle(&mut rng, 0.0, [0.05, 0.3, 0.6][i % 3]))
        .collect();
    tris.push([v(1.0, -0.6, -0.3), v(0.8, 0.7, 0.2), v(0.3, 0.0, 0.9)]);
    for (ti, t) in tris.iter().enumerate() {
        for k in [0.3, 0.1, 0.01, 0.001] {
            let a = AdaptiveTriangle::new(t[0], t[1], t[2], k).unwrap();
            let sp = a.projected_solid_angle();
            let set = a.generate(64, &mut rng);
            let whole = SphericalTriangle::new(t[0], t[1], t[2]).unwrap();
            for i in 0..set.len() {
                let d = &set.directions[i];
                assert!((d.norm() - 1.0).abs() < 1e-14);
                assert!(d.z >= -1e-15);
                assert!(whole.outside_by(d) < 1e-12, "{ti}");
                let leaf = &set.leaves[set.leaf[i] as usize];
                let w = set.weights[i];
                if !leaf.capped {
                    assert!(leaf.k < k);
                    assert!(
                        w <= sp * (1.0 + leaf.k) * (1.0 + 1e-12),
                        "{ti} {k}: w/σ⊥ = {}",
                        w / sp
                    );
                }
                assert!((w - set.cosines[i] / set.pdfs[i]).abs() <= 1e-12 * w.max(1e-300));
                let p = a.pdf(d);
                assert!(
                    (p / set.pdfs[i] - 1.0).abs() < 1e-12,
                    "{ti} {k}: {p} {}",
                    set.pdfs[i]
                );
            }
        }
    }
    // The density integrates to 1: E_uniform[pdf]·σ over the whole triangle.
    let t = [v(1.0, -0.5, 0.3), v(1.0, 0.6, 0.4), v(0.2, 0.0, 1.0)];
    let a = AdaptiveTriangle::new(t[0], t[1], t[2], 0.05).unwrap();
    let whole = SphericalTriangle::new(t[0], t[1], t[2]).unwrap();
    let mut s = Stats::new();
    for (u, w) in crate::sampling::jittered::<f64, _>(100, 100, &mut rng) {
        s.push(a.pdf(&whole.map(&u, &w)) * whole.solid_angle());
    }
    assert!((s.mean() - 1.0).abs() < 1e-3, "{}", s.mean());
    // Outside and below: 0.
    assert_eq!(a.pdf(&v(0.0, 0.0, -1.0)), 0.0);
    assert_eq!(a.pdf(&v(-1.0, 0.0, 0.1)), 0.0);
}

#[test]
fn adaptive_rejects_bad_input() {
    let (a, b, c) = (v(1.0, 0.0, 0.5), v(0.0, 1.0, 0.5), up());
    for k in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            AdaptiveTriangle::new(a, b, c, k),
            Err(WarpError::InvalidParameter { .. })
        ));
    }
    assert!(AdaptiveTriangle::new(a, b, c, f64::INFINITY).is_ok());
    assert!(matches!(
        AdaptiveTriangle::new(v(f64::NAN, 0.0, 1.0), b, c, 0.1),
        Err(WarpError::NonFinite { .. })
    ));
    assert!(matches!(
        AdaptiveTriangle::new(a, a, c, 0.1),
        Err(WarpError::Degenerate { .. })
    ));
    // Entirely below the horizon, or touching it only along an edge.
    assert!(matches!(
        AdaptiveTriangle::new(v(1.0, 0.0, -0.5), v(0.0, 1.0, -0.5), v(0.0, 0.0, -1.0), 0.1),
        Err(WarpError::Degenerate { .. })
    ));
    assert!(matches!(
        AdaptiveTriangle::new(v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, -1.0), 0.1),
        Err(WarpError::Degenerate { .. })
    ));
    let t = AdaptiveTriangle::new(a, b, c, 0.1).unwrap();
    assert!(t.clone().with_max_depth(0).is_err());
    assert!(t.clone().with_max_depth(31).is_err());
    assert!(t.clone().with_threshold(0.0).is_err());
    assert!(t.pieces(0).is_err());
    assert_eq!(t.piece_count(0), None);
    // n = 0: an empty set.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
    assert!(t.generate(0, &mut rng).is_empty());
}

/// A triangle crossing the horizon is clipped (two starting triangles),
/// σ⊥ is Lambert's of the clipped polygon, and the constant-radiance
/// estimate is unbiased.
#[test]
fn adaptive_clipped_triangle() {
    let t = [v(1.0, -0.6, -0.3), v(0.8, 0.7, 0.2), v(0.3, 0.0, 0.9)];
    let a = AdaptiveTriangle::new(t[0], t[1], t[2], 0.01).unwrap();
    assert_eq!(a.roots().len(), 2);
    for (r, _) in a.roots() {
        assert!(r.iter().all(|p| p.z >= 0.0));
    }
    let pp = ProjectedPolygon::new(&t).unwrap();
    assert!((a.projected_solid_angle() / pp.projected_solid_angle() - 1.0).abs() < 1e-12);
    let exact = pp.projected_solid_angle();
    let est: Stats = run_jobs_sequential(400, 17, |_, rng| a.generate(32, rng).estimate(|_| 1.0))
        .into_iter()
        .collect();
    let z = (est.mean() - exact) / est.std_error();
    assert!(z.abs() < 4.5, "z = {z}");
    // The variance of a constant-radiance estimate is below K σ⊥²/n.
    assert!(
        est.variance() * 32.0 <= 0.01 * exact * exact,
        "{}",
        est.variance()
    );
}

/// Same seed, same samples; thread count does not matter (run_jobs).
#[test]
fn adaptive_is_deterministic() {
    let t = [v(1.0, -0.5, 0.3), v(1.0, 0.6, 0.4), v(0.2, 0.0, 1.0)];
    let a = AdaptiveTriangle::new(t[0], t[1], t[2], 0.01).unwrap();
    let s1 = a.generate(50, &mut job_rng(3, 0));
    let s2 = a
        .clone()
        .with_cache_depth(0)
        .generate(50, &mut job_rng(3, 0));
    assert_eq!(s1, s2);
    let mut buf = SampleSet::default();
    a.generate_into(50, &mut job_rng(3, 0), &mut buf);
    assert_eq!(buf, s1);
}
