use super::*;
use crate::harness::extremes::EXTREMES;
use crate::shapes::test_support::{AxisBins, chi2_passes, roundtrip_passes};

fn build<T: Real>(p: &[T]) -> Result<SphereLight<T>, WarpError> {
    SphereLight::new(
        Vec3::new(p[0].clone(), p[1].clone(), p[2].clone()),
        p[3].clone(),
        Vec3::new(p[4].clone(), p[5].clone(), p[6].clone()),
    )
}

fn ladder() -> Vec<(String, [f64; 7], SphereLight<f64>)> {
    sphere_light_ladder()
        .into_iter()
        .map(|(n, p)| {
            let w = build(&p).unwrap();
            (n, p, w)
        })
        .collect()
}

#[test]
fn sphere_light_constructor_errors() {
    let o = Vec3::new(0.0, 0.0, 0.0);
    let c = Vec3::new(0.0, 0.0, 2.0);
    assert!(matches!(
        SphereLight::new(c, 2.0, o),
        Err(WarpError::InvalidParameter {
            name: "observer",
            ..
        })
    ));
    assert!(matches!(
        SphereLight::new(c, 3.0, o),
        Err(WarpError::InvalidParameter {
            name: "observer",
            ..
        })
    ));
    assert!(matches!(
        SphereLight::new(c, 0.0, o),
        Err(WarpError::InvalidParameter { name: "radius", .. })
    ));
    assert!(matches!(
        SphereLight::new(c, f64::NAN, o),
        Err(WarpError::NonFinite { .. })
    ));
    assert!(matches!(
        SphereLight::new(Vec3::new(f64::INFINITY, 0.0, 0.0), 1.0, o),
        Err(WarpError::NonFinite { .. })
    ));
    // The ladder's solid angles: 1e-8 sr far away, ~2π next to the surface.
    let l = ladder();
    assert!(
        (l[1].2.measure() / 1e-8 - 1.0).abs() < 1e-3,
        "{}",
        l[1].2.measure()
    );
    let near = l[3].2.measure();
    assert!(near > 2.0 * std::f64::consts::PI * (1.0 - 2e-3) && near < 2.0 * std::f64::consts::PI);
}

#[test]
fn sphere_light_hit_points_are_first_hits_on_the_sphere() {
    for (name, _, w) in ladder() {
        let w32 = w.at::<f32>().unwrap();
        for &u in &EXTREMES {
            for &v in &EXTREMES {
                let s = w.sample_hit(&u, &v);
                assert!(
                    s.point.is_finite() && s.direction.is_finite(),
                    "{name} {u} {v}"
                );
                let n = s.point.sub(w.center());
                let r = *w.radius();
                let scale = w.center().max_abs() + r;
                assert!(
                    (n.norm() - r).abs() <= 8.0 * f64::EPSILON * scale,
                    "{name} {u} {v}"
                );
                // Front-facing: the normal points back towards the observer.
                assert!(
                    n.dot(&s.direction) <= 8.0 * f64::EPSILON * scale,
                    "{name} {u} {v}"
                );
                // The point lies along the direction from the observer.
                let to_p = s.point.sub(w.observer());
                let across = to_p.sub(&s.direction.scale(&to_p.dot(&s.direction))).norm();
                assert!(
                    across <= 16.0 * f64::EPSILON * scale,
                    "{name} {u} {v}: {across:e}"
                );
                assert_eq!(s.direction, w.map(&u, &v));
                // The distance is |p − o|, the area density pdf·|cos θ_e|/t².
                assert!(
                    (s.distance - to_p.norm()).abs() <= 16.0 * f64::EPSILON * scale,
                    "{name} {u} {v}"
                );
                let cos_e = n.dot(&s.direction).abs() / r;
                let want = s.pdf * cos_e / (s.distance * s.distance);
                assert!(
                    (s.pdf_area - want).abs()
                        <= 1e-6 * want.max(1e-300) + 1e-9 * s.pdf / (s.distance * s.distance),
                    "{name} {u} {v}: {} {want}",
                    s.pdf_area
                );
                assert!(w.outside_by(&s.direction) <= 4.0 * f64::EPSILON);
                let t = w32.sample_hit(&(u as f32), &(v as f32));
                assert!(
                    t.point.is_finite() && t.direction.is_finite(),
                    "{name} f32 {u} {v}"
                );
            }
        }
        // The rim (u = 1) is tangent: n ⟂ direction.
        let s = w.sample_hit(&1.0, &0.3);
        let n = s.point.sub(w.center()).scale(&(1.0 / w.radius()));
        assert!(n.dot(&s.direction).abs() < 1e-9, "{name}");
        // Round trip through the point.
        let [u2, v2] = w.inverse_point(&w.sample_hit(&0.3, &0.7).point).unwrap();
        assert!(
            (u2 - 0.3).abs() < 1e-6 && (v2 - 0.7).abs() < 1e-6,
            "{name}: {u2} {v2}"
        );
    }
}

/// Scaling the centre, radius and observer by 2^k (exact) scales the
/// sample's point and distance by exactly 2^k and its area density by
/// 2^-2k, directions and the solid-angle density unchanged (the constructor
/// works in units of the offset's power of two), in `f32` and `f64`, until
/// the density in area leaves the type's range: then `new` says so. The
/// old constructor (lengths in world units) accepted an `f64` sphere at
/// 1e-200 with Ω = π/2 instead of 0.84 and an `f32` one at 1e-25 likewise,
/// and rejected one at 1e200 as "solid angle underflows" (its solid angle
/// is 0.84 sr; what leaves the range is its density in area).
#[test]
fn sphere_light_is_scale_free() {
    fn check<T: Real>(ks: &[i32]) -> usize {
        let mut accepted = 0;
        for (name, p) in sphere_light_ladder() {
            let at = |k: i32| {
                let s = T::exp2i(k);
                let q: Vec<T> = p.iter().map(|x| T::from_f64(*x) * &s).collect();
                build(&q)
            };
            let base = at(0).unwrap();
            for &k in ks {
                let w = match at(k) {
                    Ok(w) => w,
                    Err(e) => {
                        assert!(
                            matches!(e, WarpError::Unrepresentable { .. }),
                            "{name} 2^{k}: {e}"
                        );
                        continue;
                    }
                };
                accepted += 1;
                assert_eq!(w.measure(), base.measure(), "{name} 2^{k}");
                let (up, down) = (T::exp2i(k), T::exp2i(-k));
                for &u in &EXTREMES {
                    for &v in &EXTREMES {
                        let uv = [T::from_f64(u), T::from_f64(v)];
                        let (a, b) = (base.sample_light(uv.clone()), w.sample_light(uv));
                        assert_eq!(b.direction, a.direction, "{name} 2^{k} {u} {v}");
                        assert_eq!(b.pdf, a.pdf);
                        assert_eq!(b.point, a.point.scale(&up), "{name} 2^{k} {u} {v}");
                        assert_eq!(b.distance, a.distance * &up);
                        assert_eq!(
                            b.pdf_area,
                            a.pdf_area * &down * &down,
                            "{name} 2^{k} {u} {v}"
                        );
                        let rim = T::from_f64(u) == T::one();
                        assert!(
                            b.pdf_area.is_finite() && (b.pdf_area > T::zero() || rim),
                            "{name} 2^{k} {u} {v}: {:?}",
                            b.pdf_area
                        );
                    }
                }
            }
        }
        accepted
    }
    // Every ladder shape at ±2^20 (5 shapes × 2), some beyond.
    assert!(check::<f32>(&[-100, -60, -20, 20, 60, 100]) >= 10);
    assert!(check::<f64>(&[-1000, -600, -200, 200, 600, 1000]) >= 10);
    // Lengths of 1e-200 in f64 and 1e-25 in f32: the density in area
    // (≈ 1e400 and 1e50 per unit area) is not representable.
    let (c, o) = (Vec3::new(0.0, 0.0, 2e-200), Vec3::new(0.0, 0.0, 0.0));
    assert!(matches!(
        SphereLight::new(c, 1e-200, o),
        Err(WarpError::Unrepresentable { .. })
    ));
    let (c, o) = (Vec3::new(0.0f32, 0.0, 2e-25), Vec3::new(0.0, 0.0, 0.0));
    assert!(matches!(
        SphereLight::new(c, 1e-25, o),
        Err(WarpError::Unrepresentable { .. })
    ));
    // 1e140 in f64 is served, with the same Ω as at scale 1 (at 1e150 the
    // density next to the rim, ≈ 1e-308, would leave the normal range).
    let w = SphereLight::new(Vec3::new(0.0, 0.0, 2e140), 1e140, Vec3::new(0.0, 0.0, 0.0)).unwrap();
    let one = SphereLight::new(Vec3::new(0.0, 0.0, 2.0), 1.0, Vec3::new(0.0, 0.0, 0.0)).unwrap();
    assert_eq!(w.measure(), one.measure());
}

#[test]
fn sphere_light_roundtrip_and_chi2() {
    for (name, _, w) in ladder() {
        roundtrip_passes::<f64, _>(&format!("sphere-light {name}"), &w, 16.0);
        roundtrip_passes::<f32, _>(&format!("sphere-light {name}"), &w, 16.0);
        let f = &w.frame;
        let edges = AxisBins::quantile_edges(|_| 1.0, 10, *w.cone_height());
        let bins = AxisBins::new(
            [f.e1, f.e2, f.axis],
            edges,
            2.0 * std::f64::consts::PI,
            12,
            |_| 1.0 / w.measure(),
        );
        chi2_passes(&format!("sphere-light {name}"), &w, &bins, 200_000);
    }
}

#[cfg(feature = "mpfr")]
mod mpfr {
    use super::*;
    use crate::harness::extremes::{extremes_grid, random_points};
    use crate::harness::sensitivity::check_precision_conditioned;
    use crate::real::Mpfr256;
    use crate::shapes::test_support::harness_passes;

    type M = Mpfr256;

    #[test]
    fn sphere_light_harness_at_extremes() {
        for (name, _, w) in ladder() {
            // Absolute direction errors; the ill-conditioned shapes (a
            // one-ulp move of the observer 1e-6 above the surface turns the
            // cone) are held to their κ bound in the next test.
            let bound = if name.starts_with("near") || name.starts_with("axis") {
                f64::INFINITY
            } else {
                4.0
            };
            harness_passes(&format!("sphere-light {name}"), &w, bound);
        }
    }

    /// The direction within 16·max(u_T, κ) of the 256-bit map, κ the map's
    /// own sensitivity to one-ulp changes of c, r, o, u, v (f32 and f64).
    #[test]
    fn sphere_light_within_kappa_bound_from_far_to_grazing() {
        let mut pts = extremes_grid();
        pts.extend(random_points(200, 11));
        for (name, params, w) in ladder() {
            let r32 =
                check_precision_conditioned::<f32, _, _, _>(&w, |p: &[M]| build(p), &params, &pts)
                    .unwrap();
            let r64 =
                check_precision_conditioned::<f64, _, _, _>(&w, |p: &[M]| build(p), &params, &pts)
                    .unwrap();
            for r in [&r32, &r64] {
                println!(
                    "conditioned sphere-light {name} {}: max error/bound {:.3} (error {:.2e}, κ {:.2e} at {:?}), max κ {:.2e}, non-finite {}",
                    r.scalar,
                    r.max_ratio,
                    r.worst_error,
                    r.worst_kappa,
                    r.worst,
                    r.max_kappa,
                    r.non_finite
                );
                assert!(r.passes(), "{name}: {r:?}");
            }
        }
    }

    /// The first hit point as a warp of its own (the point on the sphere,
    /// area density `pdf_area`), so that the κ harness can hold it to the
    /// bound of its own conditioning.
    #[derive(Clone, Debug)]
    struct HitPoint<T>(SphereLight<T>);

    impl<T: Real> Warp<T> for HitPoint<T> {
        type Point = Vec3<T>;
        fn map(&self, u: &T, v: &T) -> Vec3<T> {
            self.0.sample_hit(u, v).point
        }
        fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
            match self.0.inverse_point(p) {
                Ok([u, v]) => self.0.sample_hit(&u, &v).pdf_area,
                Err(_) => T::zero(),
            }
        }
        fn measure(&self) -> T {
            T::one()
        }
        fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
            self.0.inverse_point(p)
        }
        fn outside_by(&self, p: &Vec3<T>) -> T {
            (p.sub(self.0.center()).norm() - self.0.radius()).abs()
        }
        fn extent(&self) -> T {
            self.0.center().max_abs() + self.0.radius()
        }
    }

    impl<T: Real> WarpFamily<T> for HitPoint<T> {
        type At<S: Real> = HitPoint<S>;
        fn at<S: Real>(&self) -> Result<HitPoint<S>, WarpError> {
            Ok(HitPoint(self.0.at()?))
        }
        fn name(&self) -> String {
            "sphere-light-hit".to_string()
        }
    }

    /// The hit point within 16·max(u_T, κ) of the 256-bit hit point of the
    /// same shape, κ its own sensitivity to one-ulp changes of c, r, o, u, v:
    /// next to the surface the rounding of `d − r` moves the hit point by
    /// hundreds of ulps of `|c| + r`, and κ says so.
    #[test]
    fn sphere_light_hit_point_within_kappa_bound() {
        let mut pts = extremes_grid();
        pts.extend(random_points(200, 17));
        for (name, params, w) in ladder() {
            let hit = HitPoint(w);
            let build_hit = |p: &[M]| build(p).map(HitPoint);
            let r32 = check_precision_conditioned::<f32, _, _, _>(&hit, build_hit, &params, &pts)
                .unwrap();
            let r64 = check_precision_conditioned::<f64, _, _, _>(&hit, build_hit, &params, &pts)
                .unwrap();
            for r in [&r32, &r64] {
                println!(
                    "conditioned sphere-light hit point {name} {}: max error/bound {:.3} (error {:.2e}, κ {:.2e} at {:?}), max κ {:.2e}, non-finite {}, outside {}",
                    r.scalar,
                    r.max_ratio,
                    r.worst_error,
                    r.worst_kappa,
                    r.worst,
                    r.max_kappa,
                    r.non_finite,
                    r.outside
                );
                assert!(r.passes(), "{name}: {r:?}");
            }
        }
    }

    /// The hit point against the 256-bit hit point of the same shape, in
    /// units of roundoff of `|c| + r` (the scale of its coordinates).
    #[test]
    fn sphere_light_hit_point_accuracy() {
        let mut pts = extremes_grid();
        pts.extend(random_points(200, 13));
        for (name, _, w) in ladder() {
            let w32 = w.at::<f32>().unwrap();
            let m64 = w.at::<M>().unwrap();
            let m32 = w32.at::<M>().unwrap();
            let (mut e32, mut e64) = (0.0f64, 0.0f64);
            for &(u, v) in &pts {
                let scale = w.center().max_abs() + w.radius();
                let a = w.sample_hit(&u, &v).point.convert::<M>();
                let b = m64.sample_hit(&M::from_f64(u), &M::from_f64(v)).point;
                e64 = e64.max(a.sub(&b).max_abs().to_f64() / scale / (f64::EPSILON / 2.0));
                let (uf, vf) = (u as f32, v as f32);
                let a = w32.sample_hit(&uf, &vf).point.convert::<M>();
                let b = m32
                    .sample_hit(&M::from_f64(uf as f64), &M::from_f64(vf as f64))
                    .point;
                e32 = e32.max(a.sub(&b).max_abs().to_f64() / scale / (f32::EPSILON as f64 / 2.0));
            }
            println!(
                "hit point sphere-light {name}: max error f32 {e32:.2}, f64 {e64:.2} units of roundoff of |c| + r"
            );
            assert!(e32.is_finite() && e64.is_finite());
        }
    }
}
