use super::*;
use crate::shapes::{hard_rectangles, hard_triangles};

#[test]
fn ordinary_triangle_takes_f32_and_mixed_is_accurate() {
    let t = SphericalTriangle::<f64>::new(
        Vec3::new(1.0, 0.1, 0.0),
        Vec3::new(0.2, 1.0, 0.1),
        Vec3::new(0.0, 0.3, 1.0),
    )
    .unwrap();
    let a = advise(&t).unwrap();
    assert!(a.kappa_f32 > 1e-8 && a.kappa_f32 < 1e-6, "{a:?}");
    assert!(a.kappa_f64 > 1e-17 && a.kappa_f64 < 1e-15, "{a:?}");
    assert_eq!(a.choose(1e-5), Some(Evaluation::RobustF32));
    assert_eq!(a.choose(1e-7), Some(Evaluation::MixedF32));
    assert_eq!(a.choose(1e-9), Some(Evaluation::RobustF64));
    assert_eq!(a.choose(1e-20), None);
    // Literal: at the probes far worse than the robust maps.
    assert!(a.predicted(Evaluation::LiteralF64) > 1e3 * a.predicted(Evaluation::RobustF64));
    let m = Mixed::new(&t).unwrap();
    let t32 = t.at::<f32>().unwrap();
    for (u, v) in probes() {
        let (u, v) = (u as f32, v as f32);
        let p = m.map(&u, &v);
        let q = t32.map(&u, &v);
        assert!(p.sub(&q).max_abs() < 1e-6, "{p:?} {q:?}");
        assert!(m.inverse(&p).is_ok());
    }
}

#[test]
fn hard_shapes_have_finite_predictions_for_the_robust_maps() {
    for (name, [a, b, c]) in hard_triangles() {
        let adv = advise(&SphericalTriangle::<f64>::new(a, b, c).unwrap()).unwrap();
        for e in [
            Evaluation::RobustF32,
            Evaluation::MixedF32,
            Evaluation::RobustF64,
        ] {
            let p = adv.predicted(e);
            assert!(p.is_finite() && p > 0.0, "{name} {e}: {adv:?}");
        }
        assert!(adv.choose(1.0).is_some(), "{name}");
    }
    for (name, [s, ex, ey, o]) in hard_rectangles() {
        let adv = advise(&SphericalRectangle::<f64>::new(s, ex, ey, o).unwrap()).unwrap();
        assert!(
            adv.predicted(Evaluation::RobustF64).is_finite(),
            "{name}: {adv:?}"
        );
    }
}

/// Issue 13 on the whole ladder (triangles and rectangles, ordinary and
/// hard): f32 accepts what f64 accepts on the same values; the robust f32
/// map within 16·max(2⁻²⁴, κ₃₂), the inverse within max(1e-6, 16·κ_inv),
/// never refusing its own samples; the predictions of `advise` at least the
/// measured errors of every evaluation, within 100× for ≥ 90% of them.
#[cfg(feature = "mpfr")]
mod ladder {
    use super::*;
    use crate::harness::extremes::{extremes_grid, random_points};
    use crate::precision_choice::measure::{PredictionTally, audit_f32, measure};
    use crate::shapes::{ordinary_rectangles, ordinary_triangles};

    fn points() -> Vec<(f64, f64)> {
        let mut p = extremes_grid();
        p.extend(random_points(16, 42));
        p
    }

    fn check<W: Advisable>(name: &str, w: &W, tally: &mut PredictionTally) {
        let pts = points();
        let a = audit_f32(w, &pts).unwrap();
        println!("{name}: {a:?}");
        assert_eq!(a.f32_accepts, a.f64_accepts, "{name}: {a:?}");
        if a.f32_accepts {
            assert!(a.map_ratio <= 1.0, "{name}: {a:?}");
            assert!(a.inverse_ratio <= 1.0, "{name}: {a:?}");
            assert_eq!(a.inverse_refusals + a.non_finite, 0, "{name}: {a:?}");
        }
        let advice = advise(w).unwrap();
        let measured = measure(w, &pts).unwrap();
        for m in measured.iter().filter(|m| m.accepted) {
            let p = advice.predicted(m.evaluation);
            println!(
                "  {}: predicted {p:.3e} measured {:.3e}",
                m.evaluation, m.worst_error
            );
            // Upper bounds for every evaluation, the literal ones included.
            assert!(
                p >= m.worst_error,
                "{name} {}: {p:e} < {:e}",
                m.evaluation,
                m.worst_error
            );
        }
        tally.add(&advice, &measured);
    }

    /// Grazing observers above the interior (the map depends on the sign of
    /// `h`, which `f64` cannot resolve from world coordinates) and beside
    /// the rectangle, at scales 1 and 1e28, in a generic frame: whatever the
    /// evaluations' errors (up to "no digit"), the predictions bound them.
    #[test]
    fn grazing_rectangles_at_large_scales_are_bounded() {
        let a = Vec3::new(2.0, -1.0, 2.0).scale(&(1.0 / 3.0));
        let b = Vec3::new(2.0, 2.0, -1.0).scale(&(1.0 / 3.0));
        let n = Vec3::new(-1.0, 2.0, 2.0).scale(&(1.0 / 3.0));
        let corner = Vec3::new(0.37, -1.21, 0.73);
        let pts = points();
        let mut worst_f64 = 0.0f64;
        for k in [1.0, 1e28] {
            for (fx, fy) in [(0.3, 0.45), (-0.4, 0.3)] {
                for h in [1e-9, 1e-15, 1e-20, 1e-30] {
                    let s = corner.scale(&k);
                    let o = s
                        .add(&a.scale(&(fx * k)))
                        .add(&b.scale(&(fy * k)))
                        .add(&n.scale(&(h * k)));
                    let Ok(r) = SphericalRectangle::<f64>::new(s, a.scale(&k), b.scale(&k), o)
                    else {
                        continue;
                    };
                    let advice = advise(&r).unwrap();
                    for m in measure(&r, &pts).unwrap().iter().filter(|m| m.accepted) {
                        let p = advice.predicted(m.evaluation);
                        println!(
                            "k {k:e} foot ({fx}, {fy}) h {h:e} {}: predicted {p:.3e} measured {:.3e}",
                            m.evaluation, m.worst_error
                        );
                        assert!(p >= m.worst_error, "{k} {fx} {fy} {h} {}", m.evaluation);
                        if m.evaluation == Evaluation::RobustF64 {
                            worst_f64 = worst_f64.max(m.worst_error);
                        }
                    }
                }
            }
        }
        println!("worst f64 robust error: {worst_f64:e}");
    }

    /// Predicted ≥ measured everywhere; ≥ 90% within 100× per family and
    /// over both.
    #[test]
    fn ladder_f32_accepted_accurate_and_predicted() {
        let (mut tri, mut rect) = (PredictionTally::default(), PredictionTally::default());
        for (name, [a, b, c]) in ordinary_triangles().into_iter().chain(hard_triangles()) {
            let t = SphericalTriangle::<f64>::new(a, b, c).unwrap();
            check(&name, &t, &mut tri);
        }
        for (name, [s, ex, ey, o]) in ordinary_rectangles().into_iter().chain(hard_rectangles()) {
            let r = SphericalRectangle::<f64>::new(s, ex, ey, o).unwrap();
            check(&name, &r, &mut rect);
        }
        let both = tri.merged(&rect);
        println!(
            "{}\n{}\n{}",
            tri.table("ladder triangles"),
            rect.table("ladder rectangles"),
            both.table("ladder, both")
        );
        for (family, t) in [("triangles", &tri), ("rectangles", &rect), ("both", &both)] {
            let total = t.total();
            assert_eq!(total.under, 0, "{family}: {total:?}");
            assert!(total.fraction_within_100() >= 0.9, "{family}: {total:?}");
        }
    }
}
