use super::*;
use crate::harness::extremes::{extremes_grid, random_points};

fn tri(v: &[Vec3<f64>; 3]) -> Result<SphericalTriangle<f64>, WarpError> {
    SphericalTriangle::new(v[0].clone(), v[1].clone(), v[2].clone())
}

fn all_shapes() -> Vec<(String, [Vec3<f64>; 3])> {
    let mut s = ordinary_triangles();
    s.extend(hard_triangles());
    s
}

/// The extremes grid plus 16 random points.
fn points() -> Vec<(f64, f64)> {
    let mut p = extremes_grid();
    p.extend(random_points(16, 42));
    p
}

#[cfg(feature = "mpfr")]
mod accuracy {
    use super::*;
    use crate::harness::sensitivity::{InputFormat, accuracy_bound, sensitivities_in};
    use crate::real::{Mpfr256, convert};
    use crate::vector::Coords;

    /// Per-shape accuracy figures of one variant in one format.
    #[derive(Clone, Debug, Default)]
    pub(super) struct Figures {
        /// max error / (16·max(u_T, κ)) over the points.
        pub ratio: f64,
        /// max error (absolute, unit vectors).
        pub max_err: f64,
        /// κ at the point of maximal ratio.
        pub kappa: f64,
        pub worst: (f64, f64),
        pub nan: usize,
        pub outside: usize,
        /// max outside_by / u_T.
        pub max_outside_ulps: f64,
    }

    fn coords<T: Real>(t: &SphericalTriangle<T>) -> Vec<f64> {
        [t.a(), t.b(), t.c()]
            .iter()
            .flat_map(|v| [v.x.to_f64(), v.y.to_f64(), v.z.to_f64()])
            .collect()
    }

    fn build(p: &[Mpfr256]) -> Result<SphericalTriangle<Mpfr256>, WarpError> {
        let v = |i: usize| Vec3::new(p[i].clone(), p[i + 1].clone(), p[i + 2].clone());
        SphericalTriangle::new(v(0), v(3), v(6))
    }

    /// Measures both variants of `shape` in `T` against the 256-bit map of
    /// the shape as `T` sees it; `None` if `T` rejects the shape.
    pub(super) fn measure<T: Real>(
        shape: &[Vec3<f64>; 3],
        points: &[(f64, f64)],
    ) -> Option<[Figures; 2]> {
        let format = if T::precision() == 24 {
            InputFormat::F32
        } else {
            InputFormat::F64
        };
        let w: SphericalTriangle<T> = tri(shape).ok()?.at::<T>().ok()?;
        let reference = w.at::<Mpfr256>().ok()?;
        let params = coords(&w);
        let kappas = sensitivities_in::<Mpfr256, _, _>(build, &params, points, format)
            .expect("sensitivity");
        let ut = T::unit_roundoff().to_f64();
        let mut out = [Figures::default(), Figures::default()];
        for (k, variant) in [
            SphericalTriangleVariant::Robust,
            SphericalTriangleVariant::Literal,
        ]
        .into_iter()
        .enumerate()
        {
            let wv = w.clone().with_variant(variant);
            let f = &mut out[k];
            for (i, &(u, v)) in points.iter().enumerate() {
                let (u_t, v_t) = (T::from_f64(u), T::from_f64(v));
                let p = wv.map(&u_t, &v_t);
                if !p.is_finite() {
                    f.nan += 1;
                    continue;
                }
                let q = reference.map(&convert(&u_t), &convert(&v_t));
                let pr: Vec3<Mpfr256> = p.convert();
                let err = pr.sub(&q).max_abs().to_f64();
                let bound = accuracy_bound(kappas[i].kappa, format);
                if err / bound > f.ratio {
                    f.ratio = err / bound;
                    f.kappa = kappas[i].kappa;
                    f.worst = (u, v);
                }
                f.max_err = f.max_err.max(err);
                let out_ulps = reference.outside_by(&Coords::from_vec3(pr)).to_f64() / ut;
                if out_ulps > crate::harness::precision::OUTSIDE_TOLERANCE_ULPS {
                    f.outside += 1;
                }
                f.max_outside_ulps = f.max_outside_ulps.max(out_ulps);
            }
        }
        Some(out)
    }

    #[test]
    #[ignore = "report: prints the accuracy table of both variants (a few seconds)"]
    fn report_accuracy_table() {
        let pts = points();
        for (prec, name) in [(53, "f64"), (24, "f32")] {
            println!("\n== {name} ==");
            println!(
                "{:<16} {:>10} | {:>9} {:>9} {:>9} {:>4} {:>4} {:>6} | {:>9} {:>9} {:>4} {:>4}",
                "shape", "omega", "R err/bd", "R maxerr", "kappa", "NaN", "out", "outmx",
                "L err/bd", "L maxerr", "NaN", "out"
            );
            for (label, shape) in all_shapes() {
                let omega = tri(&shape).map(|t| *t.solid_angle()).unwrap_or(f64::NAN);
                let m = if prec == 53 {
                    measure::<f64>(&shape, &pts)
                } else {
                    measure::<f32>(&shape, &pts)
                };
                match m {
                    None => println!("{label:<16} {omega:>10.3e} | rejected in {name}"),
                    Some([r, l]) => println!(
                        "{label:<16} {omega:>10.3e} | {:>9.3e} {:>9.2e} {:>9.2e} {:>4} {:>4} {:>6.2} | {:>9.3e} {:>9.2e} {:>4} {:>4}   worst R {:?}",
                        r.ratio, r.max_err, r.kappa, r.nan, r.outside, r.max_outside_ulps,
                        l.ratio, l.max_err, l.nan, l.outside, r.worst
                    ),
                }
            }
        }
    }
}


#[test]
#[ignore = "report"]
fn report_roundtrip() {
    for (label, shape) in all_shapes() {
        let w = tri(&shape).unwrap();
        for variant in [SphericalTriangleVariant::Robust, SphericalTriangleVariant::Literal] {
            let w = w.clone().with_variant(variant);
            let (mut worst, mut at, mut worst_away, mut at_away, mut fails) = (0.0f64, (0.0, 0.0), 0.0f64, (0.0, 0.0), 0);
            for &(u, v) in &points() {
                let p = w.map(&u, &v);
                match w.inverse(&p) {
                    Some((u2, v2)) if u2.is_finite() && v2.is_finite() => {
                        let e = (u - u2).abs().max((v - v2).abs());
                        if e > worst { worst = e; at = (u, v); }
                        if v >= 1e-6 && e > worst_away { worst_away = e; at_away = (u, v); }
                    }
                    _ => fails += 1,
                }
            }
            println!("{label:<16} {variant:<8} worst {worst:.2e} at {at:?}  v>=1e-6: {worst_away:.2e} at {at_away:?} fails {fails}");
        }
    }
}

#[cfg(feature = "mpfr")]
#[test]
#[ignore = "debug"]
fn debug_inverse() {
    use crate::real::Mpfr256;
    let (_, shape) = all_shapes().into_iter().find(|(n, _)| n == "hemi 2pi-1e-6").unwrap();
    let w = tri(&shape).unwrap();
    let r = w.at::<Mpfr256>().unwrap();
    for (u, v) in [(0.5, 1.0), (0.5, 0.999999), (0.5, 0.5), (0.45, 1.0), (0.3, 1.0)] {
        let p = w.map(&u, &v);
        let inv = w.inverse(&p).unwrap();
        let pr: Vec3<Mpfr256> = p.convert();
        let invr = r.inverse(&pr).unwrap();
        let exact = r.map(&Mpfr256::from_f64(u), &Mpfr256::from_f64(v));
        let invx = r.inverse(&exact).unwrap();
        println!("({u},{v}): f64 inv {inv:?}  256-inv of f64 point ({:.17}, {:.17})  256 inv of exact ({:.17},{:.17}) |E|={:e}",
            invr.0.to_f64(), invr.1.to_f64(), invx.0.to_f64(), invx.1.to_f64(), p.add(&w.b).norm());
    }
}
