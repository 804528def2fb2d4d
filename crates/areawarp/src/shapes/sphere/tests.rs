use super::*;
use proptest::prelude::*;
use rand::SeedableRng;
use rand::rngs::SmallRng;

fn edges() -> [f64; 8] {
    [
        0.0,
        2f64.powi(-60),
        1e-12,
        1e-6,
        0.5,
        1.0 - 1e-6,
        1.0 - 1e-12,
        1.0,
    ]
}

fn axes() -> [Vec3<f64>; 4] {
    [
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(1.0, 2.0, -3.0),
        Vec3::new(1e-30, -1e-30, 1e-31),
    ]
}

fn finite_on_shape<T: Real>() {
    let tol = T::unit_roundoff() * &T::from_i64(8);
    let mut warps = vec![Sphere::<T>::new()];
    for a in axes() {
        warps.push(Sphere::with_axis(a.convert()).unwrap());
    }
    for w in &warps {
        for &u in &edges() {
            for &v in &edges() {
                let p = w.map(&T::from_f64(u), &T::from_f64(v));
                assert!(p.is_finite(), "{u} {v}: {p:?}");
                assert!(w.outside_by(&p) <= tol, "{u} {v}: {p:?}");
                assert!(w.pdf(&p).is_finite());
            }
        }
    }
}

#[test]
fn sphere_finite_on_shape_f32() {
    finite_on_shape::<f32>();
}

#[test]
fn sphere_finite_on_shape_f64() {
    finite_on_shape::<f64>();
}

#[test]
fn sphere_frames_orthonormal_right_handed() {
    for a in axes().into_iter().chain([
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, -1.0, 1e-30),
        Vec3::new(f64::MAX, f64::MAX, -f64::MAX),
    ]) {
        let f = Frame::from_axis(&a).unwrap();
        let n = a.scale(&(1.0 / a.max_abs()));
        let n = n.scale(&(1.0 / n.norm()));
        assert!(f.axis.sub(&n).max_abs() <= 4.0 * f64::EPSILON);
        for (x, y) in [(&f.e1, &f.e2), (&f.e1, &f.axis), (&f.e2, &f.axis)] {
            assert!(x.dot(y).abs() <= 4.0 * f64::EPSILON);
        }
        for x in [&f.e1, &f.e2, &f.axis] {
            assert!((x.norm() - 1.0).abs() <= 4.0 * f64::EPSILON);
        }
        assert!(f.e1.cross(&f.e2).sub(&f.axis).max_abs() <= 4.0 * f64::EPSILON);
    }
}

#[test]
fn sphere_constructor_errors() {
    assert_eq!(
        Sphere::with_axis(Vec3::<f64>::zero()).unwrap_err(),
        WarpError::Degenerate {
            what: "sphere axis is the zero vector"
        }
    );
    assert!(matches!(
        Sphere::with_axis(Vec3::new(f64::NAN, 0.0, 1.0)),
        Err(WarpError::NonFinite { .. })
    ));
    assert!(matches!(
        Sphere::with_axis(Vec3::new(0.0, f32::INFINITY, 1.0)),
        Err(WarpError::NonFinite { .. })
    ));
    assert!(SphereRecipe::with_axis(Vec3::new(0.0, 0.0, -0.0f64)).is_err());
    assert!(Sphere::with_axis(Vec3::new(0.0, 0.0, 5e-324f64)).is_ok());
}

#[test]
fn sphere_poles_follow_axis() {
    for a in axes() {
        let w = Sphere::with_axis(a).unwrap();
        let n = w.axis();
        assert!(w.map(&0.0, &0.3).sub(&n).max_abs() <= 4.0 * f64::EPSILON);
        assert!(w.map(&1.0, &0.3).add(&n).max_abs() <= 4.0 * f64::EPSILON);
        // The equator is orthogonal to the axis.
        assert!(w.map(&0.5, &0.3).dot(&n).abs() <= 4.0 * f64::EPSILON);
    }
    // Tiny u: sin θ ≈ 2√u to full relative accuracy, at both poles.
    let s = Sphere::<f64>::new();
    let u = 2f64.powi(-60);
    assert!((s.map(&u, &0.0).x / (2.0 * u.sqrt()) - 1.0).abs() < 4.0 * f64::EPSILON);
    let w = 1e-12;
    let p = s.map(&(1.0 - w), &0.0);
    // 1 − (1 − 1e-12) is exact in f64, so the reference uses that value.
    let d = 1.0 - (1.0 - w);
    assert!((p.x / (2.0 * (d * (1.0 - d)).sqrt()) - 1.0).abs() < 4.0 * f64::EPSILON);
}

#[test]
fn sphere_roundtrip_f64() {
    for a in axes() {
        let w = Sphere::with_axis(a).unwrap();
        for &u in &edges() {
            if u == 0.0 || u == 1.0 {
                continue; // the poles: v undefined
            }
            for &v in &edges() {
                if v == 1.0 {
                    continue;
                }
                let [u2, v2] = w.inverse(&w.map(&u, &v)).unwrap();
                // Axes ±z have exact frames: u is recovered to relative
                // accuracy. In a rotated frame the point's own rounding
                // (≈ 2^-53 absolute) limits u to absolute accuracy, and v
                // to ≈ 2^-53/sin θ, so v is checked away from the poles.
                let exact = a.x == 0.0 && a.y == 0.0;
                let tol_u = if exact { 1e-12 * u } else { 1e-12 };
                assert!((u2 - u).abs() <= tol_u, "{a:?} {u} {v}: {u2}");
                if exact || (1e-6..=1.0 - 1e-6).contains(&u) {
                    // Azimuth is periodic: compare on the circle.
                    let dv = (v2 - v).abs();
                    assert!(dv.min(1.0 - dv) <= 1e-10, "{a:?} {u} {v}: {v2}");
                }
            }
        }
    }
}

/// Near the south pole ψ is steep in u (sin θ ≈ 2√(1 − u)); in a rotated
/// frame the inverse goes through 1 − u = ρ²/(2(1 − z)), accurate from
/// the point's x, y, and reproduces u exactly.
#[test]
fn sphere_roundtrip_exact_near_south_pole() {
    for a in axes() {
        let w = Sphere::with_axis(a).unwrap();
        for u in [1.0 - 1e-6, 1.0 - 1e-12, 1.0 - 2f64.powi(-40)] {
            for v in [0.0, 0.3, 0.8] {
                let [u2, _] = w.inverse(&w.map(&u, &v)).unwrap();
                assert_eq!(u2, u, "{a:?} v={v}");
            }
        }
    }
}

#[test]
fn sphere_inverse_rejects_off_shape() {
    let w = Sphere::<f64>::new();
    assert!(w.inverse(&Vec3::new(0.0, 0.0, 1.1)).is_err());
    assert!(w.inverse(&Vec3::new(0.0, f64::INFINITY, 1.0)).is_err());
    assert_eq!(w.inverse(&Vec3::new(0.0, 0.0, -1.0)), Ok([1.0, 0.0]));
}

#[test]
fn sphere_random_axis_is_uniform_enough() {
    let mut rng = SmallRng::seed_from_u64(42);
    let n = 4000;
    let mut mean = Vec3::<f64>::zero();
    let mut upper = 0;
    for _ in 0..n {
        let a = Sphere::<f64>::random_axis(&mut rng);
        assert!((a.norm() - 1.0).abs() < 1e-15);
        mean = mean.add(&a);
        if a.z > 0.0 {
            upper += 1;
        }
    }
    // Each mean coordinate has standard deviation 1/√(3n) ≈ 0.009.
    assert!(mean.scale(&(1.0 / n as f64)).max_abs() < 0.05);
    assert!((upper as f64 / n as f64 - 0.5).abs() < 0.05);
    let s = Sphere::<f32>::with_random_axis(&mut rng);
    assert!((s.axis().norm() - 1.0).abs() < 1e-6);
}

#[test]
fn sphere_family() {
    let w = Sphere::with_axis(Vec3::new(1.0f32, 2.0, 3.0)).unwrap();
    assert_eq!(w.name(), "sphere");
    let g = w.at::<f64>().unwrap();
    assert!(g.axis().sub(&w.axis().convert()).max_abs() < 1e-7);
    assert_eq!(
        Sphere::<f64>::new().at::<f32>().unwrap().axis(),
        Vec3::new(0.0, 0.0, 1.0)
    );
}

#[cfg(feature = "mpfr")]
mod mpfr {
    use super::*;
    use crate::real::{Dual2, Mpfr256};
    use crate::recipe::{ClosedForm, RecipeWarp};

    type M = Mpfr256;

    fn grid() -> Vec<M> {
        let one = M::one();
        vec![
            M::zero(),
            M::exp2i(-60),
            M::from_ratio(1, 2),
            one.clone() - &M::exp2i(-40),
            one,
        ]
    }

    #[test]
    fn sphere_recipe_matches_direct_at_256_bits() {
        let tol = M::exp2i(-230);
        let axes: [Option<Vec3<M>>; 2] = [
            None,
            Some(Vec3::new(M::from_i64(1), M::from_i64(2), M::from_i64(-3))),
        ];
        for axis in axes {
            let (spec, direct) = match axis {
                None => (SphereRecipe::<M>::new(), Sphere::<M>::new()),
                Some(a) => (
                    SphereRecipe::with_axis(a.clone()).unwrap(),
                    Sphere::with_axis(a).unwrap(),
                ),
            };
            let spec = RecipeWarp::new(spec, ClosedForm, ClosedForm);
            for u in grid() {
                for v in grid() {
                    let d = spec.map(&u, &v).sub(&direct.map(&u, &v)).max_abs();
                    assert!(d <= tol, "u={u} v={v}: {d}");
                }
            }
            assert!((spec.measure() - &direct.measure()).abs() <= tol);
        }
    }

    #[test]
    fn sphere_recipe_sigma_consistent_with_marginal() {
        let r = SphereRecipe::with_axis(Vec3::new(M::from_i64(2), M::from_i64(-1), M::from_i64(2)))
            .unwrap();
        let tol = M::exp2i(-240);
        let four_pi = M::pi() * &M::from_i64(4);
        let mut s_values: Vec<M> = [(1, 10), (1, 4), (1, 2), (3, 4), (9, 10)]
            .iter()
            .map(|&(n, d)| M::from_ratio(n, d))
            .collect();
        s_values.push(M::exp2i(-60));
        s_values.push(M::one() - &M::exp2i(-60));
        for s in s_values {
            let sig0 = r.sigma(&s, &M::zero());
            // Archimedes' local theorem, from the dual-number partials:
            // σ ≡ 4π, in particular independent of t …
            assert!(
                (sig0.clone() - &four_pi).abs() <= tol.clone() * &four_pi,
                "s={s}"
            );
            for t in [M::from_ratio(1, 3), M::from_ratio(7, 10)] {
                assert!((r.sigma(&s, &t) - &sig0).abs() <= tol.clone() * &sig0);
            }
            // … so ∫σ dt = σ = F'(s)·m.
            let fm = r.marginal_pdf(&s) * &r.measure();
            assert!((fm - &sig0).abs() <= tol.clone() * &sig0, "s={s}");
            let back = r.marginal_cdf(&r.marginal_inverse(&s).unwrap());
            assert_eq!(back, s);
        }
        // The spherical-coordinate route gives the same map: with
        // F(s) = sin²(πs/2), F⁻¹(u) = (2/π) arcsin √u, cos πs = 1 − 2u.
        let direct = Sphere::<M>::new();
        for u in [
            M::from_ratio(1, 10),
            M::from_ratio(1, 3),
            M::from_ratio(4, 5),
        ] {
            let s = u.sqrt().asin() * &M::from_i64(2) / &M::pi();
            let (sin_a, cos_a) = (M::pi() * &s).sin_cos();
            let p = direct.map(&u, &M::zero());
            assert!((p.x.clone() - &sin_a).abs() <= tol && (p.z.clone() - &cos_a).abs() <= tol);
        }
    }

    /// f64 against 256 bits at the extremes (default axis), coordinate by
    /// coordinate, relative to each coordinate (exact zeros stay zero).
    #[test]
    fn sphere_f64_accurate_at_extremes() {
        let w64 = Sphere::<f64>::new();
        let wm = w64.at::<M>().unwrap();
        for u in edges() {
            for v in edges() {
                let a = w64.map(&u, &v);
                let b = wm.map(&M::from_f64(u), &M::from_f64(v));
                for (x, y) in a.to_array().iter().zip(b.to_array()) {
                    let err = (M::from_f64(*x) - &y).abs();
                    let ulps = (err / &y.abs().max(&M::exp2i(-1000))).to_f64() / f64::EPSILON;
                    assert!(ulps <= 4.0, "u={u} v={v}: {x} vs {y}: {ulps} ulps");
                }
            }
        }
        // A rotated axis: absolute accuracy, a few units of roundoff.
        let w64 = Sphere::with_axis(Vec3::new(1.0, 2.0, -3.0)).unwrap();
        let wm = w64.at::<M>().unwrap();
        for u in edges() {
            for v in edges() {
                let a: Vec3<M> = w64.map(&u, &v).convert();
                let d = a.sub(&wm.map(&M::from_f64(u), &M::from_f64(v))).max_abs();
                assert!(d.to_f64() <= 4.0 * f64::EPSILON, "u={u} v={v}: {d}");
            }
        }
    }

    #[test]
    fn sphere_jacobian_constant_at_256_bits() {
        let inner =
            Sphere::with_axis(Vec3::new(M::from_i64(1), M::from_i64(1), M::from_i64(0))).unwrap();
        let w = inner.at::<Dual2<M>>().unwrap();
        for (u, v) in [
            (M::from_ratio(1, 3), M::from_ratio(1, 7)),
            (M::from_ratio(9, 10), M::from_ratio(5, 6)),
        ] {
            let p = w.map(&Dual2::seed_u(u.clone()), &Dual2::seed_v(v.clone()));
            let pu = Vec3::new(p.x.du.clone(), p.y.du.clone(), p.z.du.clone());
            let pv = Vec3::new(p.x.dv.clone(), p.y.dv.clone(), p.z.dv.clone());
            let j = pu.cross(&pv).norm() * &inner.pdf(&inner.map(&u, &v));
            assert!((j - &M::one()).abs() <= M::exp2i(-240));
        }
    }
}

proptest! {
    #[test]
    fn sphere_prop_on_shape_and_roundtrip(
        u in 0.0f64..=1.0,
        v in 0.0f64..=1.0,
        ax in -1.0f64..1.0,
        ay in -1.0f64..1.0,
        az in -1.0f64..1.0,
    ) {
        prop_assume!(ax.abs().max(ay.abs()).max(az.abs()) > 1e-3);
        let w = Sphere::with_axis(Vec3::new(ax, ay, az)).unwrap();
        let p = w.map(&u, &v);
        prop_assert!(p.is_finite());
        prop_assert!(w.outside_by(&p) <= 8.0 * f64::EPSILON);
        // Height along the axis is 1 − 2u.
        prop_assert!((p.dot(&w.axis()) - (1.0 - 2.0 * u)).abs() <= 8.0 * f64::EPSILON);
        let [u2, _v2] = w.inverse(&p).unwrap();
        prop_assert!((u2 - u).abs() <= 1e-12);
        let [u3, v3] = Sphere::<f64>::new().inverse(&Sphere::<f64>::new().map(&u, &v)).unwrap();
        prop_assert!((u3 - u).abs() <= 1e-12 * u);
        if u > 1e-6 && u < 1.0 - 1e-6 {
            let dv = (v3 - v).abs();
            prop_assert!(dv.min(1.0 - dv) <= 1e-10);
        }
        let pf = Sphere::with_axis(Vec3::new(ax as f32, ay as f32, az as f32)).unwrap().map(&(u as f32), &(v as f32));
        prop_assert!(pf.is_finite());
    }
}
