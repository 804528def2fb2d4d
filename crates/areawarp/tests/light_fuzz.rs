//! Fuzz of the light shapes' constructors and maps (issue 10, item 3; issue
//! 13, item 2): random and near-degenerate spherical triangles (random,
//! nearly coincident, nearly antipodal, nearly collinear vertices, seen from
//! points at scales 1e-30 … 1e30) and spherical rectangles (observers 1e-6 …
//! 1e-300 off the plane, elongated, scales 1e-30 … 1e30), built in `f32` and
//! `f64`, robust and literal; sphere lights (tiny cones, observers next to
//! the surface, scales 1e-30 … 1e30) in `f32` and `f64`.
//!
//! Every constructor either returns a typed error or a shape whose samples at
//! `u, v ∈ {0, smallest subnormal, 1e-7, ½, 1 − ulp, 1}` are finite, on the
//! shape by its own `outside_by` (within its `on_shape_tolerance`, the one
//! its `inverse` uses), accepted by its own `inverse`, with a finite positive
//! density, and whose light samples have a finite point at a finite positive
//! distance with a finite positive area density (zero allowed at the sphere's
//! rim) on the emitter: the triangle's plane (from points), the rectangle,
//! the sphere; and that agree with themselves (`light_consistency`): the
//! point along the direction at the distance, the density in area equal to
//! `pdf·|cos θ_e|/t²`. Counts of shapes tried / accepted / with a
//! sample off the shape are printed per variant and scalar, with the first
//! offending case and the case and `(u, v)` of the largest `outside_by`;
//! the robust variants must have none off the shape.
//!
//! Fast sizes by default; `cargo test --release -p areawarp --test light_fuzz
//! -- --ignored --nocapture` runs the large sizes.

use areawarp::shapes::{
    SphereLight, SphericalRectangle, SphericalRectangleVariant, SphericalTriangle,
    SphericalTriangleVariant,
};
use areawarp::warp::LightWarp;
use areawarp::{Real, Vec3, Warp, WarpError};
use proptest::test_runner::Config;
use std::cell::RefCell;
use std::collections::BTreeMap;

#[path = "support/light_cases.rs"]
mod light_cases;
use light_cases::*;

/// What happened to the shapes of one variant and scalar.
#[derive(Clone, Debug, Default)]
struct Tally {
    tried: usize,
    accepted: usize,
    /// Accepted shapes with a sample that is not finite, off the shape,
    /// refused by the inverse or of non-finite/zero density.
    off_shape: usize,
    /// Rejections by error kind.
    rejected: BTreeMap<String, usize>,
    /// Largest `outside_by` of a sample, in units of roundoff.
    max_outside_ulps: f64,
    /// The first offending case.
    first: Option<String>,
    /// The case and `(u, v)` of the largest `outside_by`.
    worst: Option<String>,
    /// `(tried, accepted, off the shape)` per kind of case.
    by_kind: BTreeMap<&'static str, (usize, usize, usize)>,
}

impl Tally {
    fn reject(&mut self, e: &WarpError) {
        let key = match e {
            WarpError::NonFinite { .. } => "non-finite".to_string(),
            WarpError::Degenerate { what } => format!("degenerate: {what}"),
            WarpError::Unrepresentable { what } => format!("unrepresentable: {what}"),
            WarpError::InvalidParameter { name, .. } => format!("invalid {name}"),
            WarpError::NotConverged { what } => format!("not converged: {what}"),
            WarpError::Inconsistent { what } => format!("inconsistent: {what}"),
        };
        *self.rejected.entry(key).or_default() += 1;
    }
}

type Tallies = BTreeMap<String, Tally>;

/// Samples the accepted shape `w` of `case` (of kind `kind`) and records
/// the result in `tally`: the largest `outside_by` and where, and the
/// shape as off the shape if a sample is bad (its description kept if it
/// is the first).
fn check_samples<T: Real, W: Warp<T, Point = Vec3<T>>>(
    w: &W,
    (case, kind): (&dyn std::fmt::Debug, &'static str),
    extra: impl Fn(&T, &T) -> Option<String>,
    tally: &mut Tally,
) {
    if let Some(why) = bad_sample(w, case, extra, tally) {
        tally.off_shape += 1;
        tally.by_kind.entry(kind).or_default().2 += 1;
        tally
            .first
            .get_or_insert_with(|| format!("{case:?}: {why}"));
    }
}

/// The first bad sample of the accepted shape `w` of `case`, described;
/// sets the tally's largest `outside_by` (and the case and `(u, v)` of it)
/// on the way.
fn bad_sample<T: Real, W: Warp<T, Point = Vec3<T>>>(
    w: &W,
    case: &dyn std::fmt::Debug,
    extra: impl Fn(&T, &T) -> Option<String>,
    tally: &mut Tally,
) -> Option<String> {
    let tol = w.on_shape_tolerance();
    let values = unit_values::<T>();
    let ut = T::unit_roundoff();
    for u in &values {
        for v in &values {
            let (p, pdf) = w.map_with_pdf(u, v);
            let why = if !p.is_finite() {
                Some("non-finite point")
            } else if !(pdf > T::zero()) || !pdf.is_finite() {
                Some("density not finite and positive")
            } else {
                let out = w.outside_by(&p);
                let ulps = (out.clone() / &ut).to_f64();
                if ulps > tally.max_outside_ulps {
                    tally.max_outside_ulps = ulps;
                    tally.worst = Some(format!("{case:?} at u = {u}, v = {v}: {ulps:.2} u"));
                }
                if out > tol {
                    Some("off the shape")
                } else if w.inverse(&p).is_err() {
                    Some("refused by its inverse")
                } else {
                    None
                }
            };
            if let Some(why) = why {
                return Some(format!("{why} at u = {u}, v = {v}: {p:?}"));
            }
            if let Some(why) = extra(u, v) {
                return Some(format!("{why} at u = {u}, v = {v}"));
            }
        }
    }
    None
}

fn run_triangle<T: Real>(case: &TriangleCase, variant: SphericalTriangleVariant, t: &mut Tally) {
    t.tried += 1;
    t.by_kind.entry(case.kind).or_default().0 += 1;
    let w = match case.build::<T>(variant) {
        Ok(w) => w,
        Err(e) => return t.reject(&e),
    };
    t.accepted += 1;
    t.by_kind.entry(case.kind).or_default().1 += 1;
    // The light sample: a finite point at a finite positive distance, a
    // finite positive area density; from points, the point on their plane.
    // The plane of the directions `p − o` as T holds them (an f32 rounding
    // of the differences moves a plane seen at a grazing angle by more
    // than the density check's tolerance).
    let plane = case
        .observer
        .as_ref()
        .map(|o| emitter_plane::<T>(&case.v, o));
    let points = case
        .observer
        .as_ref()
        .map(|o| [case.v[0], case.v[1], case.v[2], *o].map(|p| v3::<T>(&p)));
    let robust = variant == SphericalTriangleVariant::Robust;
    let extra = |u: &T, v: &T| {
        let s = w.sample_light([u.clone(), v.clone()]);
        if let (Some([a, b, c, o]), true) = (&points, robust)
            && SphericalTriangle::sample_light_once(a, b, c, o, u, v).as_ref() != Ok(&s)
        {
            return Some("sample_light_once differs from sample_light".to_string());
        }
        if !s.point.is_finite() || !s.distance.is_finite_above(&T::zero()) {
            return Some(format!("point {:?}, distance {}", s.point, s.distance));
        }
        if !s.pdf_area.is_finite_above(&T::zero()) {
            return Some(format!("area density {}", s.pdf_area));
        }
        let plane = plane.as_ref()?;
        let (off, scale) = plane.offset(&s.point);
        if off > tolerance::<T>().to_f64() * scale {
            return Some(format!("point {off:e} off the plane"));
        }
        light_consistency(&s, &plane.observer.convert(), &plane.normal, 0.0, 0.0)
    };
    check_samples(&w, (case, case.kind), extra, t);
}

fn run_rectangle<T: Real>(case: &RectangleCase, variant: SphericalRectangleVariant, t: &mut Tally) {
    t.tried += 1;
    t.by_kind.entry(case.kind).or_default().0 += 1;
    let w = match case.build::<T>(variant) {
        Ok(w) => w,
        Err(e) => return t.reject(&e),
    };
    t.accepted += 1;
    t.by_kind.entry(case.kind).or_default().1 += 1;
    let scale = w.corner().norm() + &w.edge_x().norm() + &w.edge_y().norm();
    let robust = variant == SphericalRectangleVariant::Robust;
    let [s0, ex, ey, o] = [&case.s, &case.ex, &case.ey, &case.o].map(|x| v3::<T>(x));
    // The plane's unit normal, from the edges as T holds them.
    let normal = {
        let n = ex.convert::<f64>().cross(&ey.convert());
        n.scale(&(1.0 / n.norm()))
    };
    let extra = |u: &T, v: &T| {
        let s = w.sample_light([u.clone(), v.clone()]);
        if robust && SphericalRectangle::sample_once(&s0, &ex, &ey, &o, u, v).as_ref() != Ok(&s) {
            return Some("sample_once differs from sample_light".to_string());
        }
        if !s.point.is_finite() {
            return Some("non-finite point".to_string());
        }
        if !(s.pdf_area > T::zero()) || !s.pdf_area.is_finite() {
            return Some(format!("area density {}", s.pdf_area));
        }
        if w.point_outside_by(&s.point) > tolerance::<T>() * &scale {
            return Some("point off the rectangle".to_string());
        }
        light_consistency(&s, &o, &normal, 0.0, scale.to_f64())
    };
    check_samples(&w, (case, case.kind), extra, t);
}

fn run_sphere<T: Real>(case: &SphereCase, t: &mut Tally) {
    t.tried += 1;
    t.by_kind.entry(case.kind).or_default().0 += 1;
    let (c, r, o) = (v3::<T>(&case.c), T::from_f64(case.r), v3::<T>(&case.o));
    let w = match SphereLight::new(c.clone(), r.clone(), o.clone()) {
        Ok(w) => w,
        Err(e) => return t.reject(&e),
    };
    t.accepted += 1;
    t.by_kind.entry(case.kind).or_default().1 += 1;
    // The hit point c + r·n carries the rounding of c's coordinates.
    let scale = c.norm().to_f64() + r.to_f64();
    let extra = |u: &T, v: &T| {
        let s = w.sample_light([u.clone(), v.clone()]);
        if SphereLight::sample_once(&c, &r, &o, u, v).as_ref() != Ok(&s) {
            return Some("sample_once differs from sample_light".to_string());
        }
        if !s.point.is_finite() || !s.distance.is_finite() || !(s.distance > T::zero()) {
            return Some(format!("point {:?}, distance {}", s.point, s.distance));
        }
        // Zero only at the rim (u = 1), where the ray is tangent.
        let rim = *u == T::one();
        if !s.pdf_area.is_finite() || !(s.pdf_area > T::zero() || rim) {
            return Some(format!("area density {}", s.pdf_area));
        }
        let p = s.point.sub(&c);
        let off = (p.norm().to_f64() - r.to_f64()).abs();
        if off > tolerance::<T>().to_f64() * scale {
            return Some(format!("point {off:e} off the sphere"));
        }
        // The normal from the point as T holds it: known to u·|point|/r.
        let n = s.point.convert::<f64>().sub(&c.convert());
        let n_error = T::unit_roundoff().to_f64() * s.point.norm().to_f64() / r.to_f64();
        light_consistency(&s, &o, &n.scale(&(1.0 / n.norm())), n_error, scale)
    };
    check_samples(&w, (case, case.kind), extra, t);
}

fn print(title: &str, tallies: &Tallies) {
    println!(
        "\n{title}: variant / scalar | tried | accepted | off the shape | max outside_by [u] | rejections"
    );
    for (k, t) in tallies {
        println!(
            "{k:<16} | {} | {} | {} | {:.2} | {:?}",
            t.tried, t.accepted, t.off_shape, t.max_outside_ulps, t.rejected
        );
        println!("    by kind (tried, accepted, off): {:?}", t.by_kind);
        if let Some(f) = &t.first {
            println!("    first: {f}");
        }
        if let Some(w) = &t.worst {
            println!("    largest outside_by: {w}");
        }
    }
}

/// The robust variants must have no sample off the shape.
fn assert_robust(tallies: &Tallies) {
    for (k, t) in tallies {
        if k.starts_with("robust") {
            assert_eq!(t.off_shape, 0, "{k}: {t:?}");
            assert!(t.accepted > 0, "{k}: {t:?}");
        }
    }
}

fn fuzz_triangles(cases: u32) -> Tallies {
    let tallies = RefCell::new(Tallies::new());
    let mut runner = runner(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&triangle_case(), |case| {
            let mut ts = tallies.borrow_mut();
            for (variant, name) in [
                (SphericalTriangleVariant::Robust, "robust"),
                (SphericalTriangleVariant::Literal, "literal"),
            ] {
                run_triangle::<f32>(&case, variant, ts.entry(format!("{name} f32")).or_default());
                run_triangle::<f64>(&case, variant, ts.entry(format!("{name} f64")).or_default());
            }
            Ok(())
        })
        .unwrap();
    tallies.into_inner()
}

fn fuzz_rectangles(cases: u32) -> Tallies {
    let tallies = RefCell::new(Tallies::new());
    let mut runner = runner(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let issue_cases = [1e-90, 1e-38, 1e-12, 1e-300].map(|h| RectangleCase {
        kind: "issue 10",
        s: [0.0, 0.0, 0.0],
        ex: [1.0, 0.0, 0.0],
        ey: [0.0, 1.0, 0.0],
        o: [3.0, 2.0, h],
    });
    let run = |case: &RectangleCase| {
        let mut ts = tallies.borrow_mut();
        for (variant, name) in [
            (SphericalRectangleVariant::Robust, "robust"),
            (SphericalRectangleVariant::Literal, "literal"),
        ] {
            run_rectangle::<f32>(case, variant, ts.entry(format!("{name} f32")).or_default());
            run_rectangle::<f64>(case, variant, ts.entry(format!("{name} f64")).or_default());
        }
    };
    for case in &issue_cases {
        run(case);
    }
    runner
        .run(&rectangle_case(), |case| {
            run(&case);
            Ok(())
        })
        .unwrap();
    tallies.into_inner()
}

fn fuzz_spheres(cases: u32) -> Tallies {
    let tallies = RefCell::new(Tallies::new());
    let mut runner = runner(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&sphere_case(), |case| {
            let mut ts = tallies.borrow_mut();
            run_sphere::<f32>(&case, ts.entry("robust f32".to_string()).or_default());
            run_sphere::<f64>(&case, ts.entry("robust f64".to_string()).or_default());
            Ok(())
        })
        .unwrap();
    tallies.into_inner()
}

#[test]
fn light_fuzz_triangles() {
    let t = fuzz_triangles(3000);
    print("spherical triangles", &t);
    assert_robust(&t);
}

#[test]
fn light_fuzz_rectangles() {
    let t = fuzz_rectangles(3000);
    print("spherical rectangles", &t);
    assert_robust(&t);
}

#[test]
fn light_fuzz_spheres() {
    let t = fuzz_spheres(3000);
    print("sphere lights", &t);
    assert_robust(&t);
}

#[test]
#[ignore = "large fuzz: 10⁵ shapes per kind"]
fn light_fuzz_large() {
    let t = fuzz_triangles(100_000);
    print("spherical triangles", &t);
    let r = fuzz_rectangles(100_000);
    print("spherical rectangles", &r);
    let s = fuzz_spheres(100_000);
    print("sphere lights", &s);
    assert_robust(&t);
    assert_robust(&r);
    assert_robust(&s);
}

/// The cases quoted in issue 10: a rectangle seen from just off its plane.
#[test]
fn grazing_rectangles_of_issue_10() {
    let build = |h: f64| {
        (
            SphericalRectangle::<f64>::new(
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(3.0, 2.0, h),
            ),
            SphericalRectangle::<f32>::new(
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(3.0, 2.0, h as f32),
            ),
        )
    };
    // f64 at h = 1e-90 and f32 at h = 1e-12: accepted, finite, on the shape.
    let (r64, _) = build(1e-90);
    let s = r64.unwrap().sample_light([0.5, 0.5]);
    assert!(s.point.is_finite() && s.direction.is_finite(), "{s:?}");
    assert!(
        s.point.z == 0.0 && s.point.x > 0.0 && s.point.x < 1.0,
        "{s:?}"
    );
    let (_, r32) = build(1e-12);
    let s = r32.unwrap().sample_light([0.5, 0.5]);
    assert!(s.point.is_finite() && s.pdf_area.is_finite(), "{s:?}");
    // f32 at h = 1e-38: h² underflows f32: a typed error, not an infinite pdf.
    let (_, r32) = build(1e-38);
    assert!(
        matches!(r32, Err(WarpError::Unrepresentable { .. })),
        "{r32:?}"
    );
}

/// A NaN `u` or `v` is not a point of the square: it gives a NaN sample,
/// never a made-up boundary point.
#[test]
fn nan_inputs_give_nan_samples() {
    let t = SphericalTriangle::<f32>::new(
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    )
    .unwrap();
    let r = SphericalRectangle::<f64>::new(
        Vec3::new(-0.5, -0.5, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    )
    .unwrap();
    for (u, v) in [(f64::NAN, 0.5), (0.5, f64::NAN), (f64::NAN, f64::NAN)] {
        let p = t.map(&(u as f32), &(v as f32));
        assert!(p.x.is_nan() && p.y.is_nan() && p.z.is_nan(), "{p:?}");
        let s = r.sample_light([u, v]);
        assert!(s.point.x.is_nan() && s.direction.x.is_nan(), "{s:?}");
    }
}

/// Issue 13 over random and near-degenerate shapes (with `--features
/// mpfr`): the `f32` constructor accepts what the `f64` constructor accepts
/// on the same (`f32`) values, except what `f32` cannot represent; every
/// accepted shape's robust `f32` map is within `16·max(2⁻²⁴, κ₃₂)` of the
/// exact map (256 bits), its inverse within `max(1e-6, 16·κ_inv)` and never
/// refusing its own samples; and [`advise`]'s predictions are at least the
/// measured errors of every evaluation, within 100× for ≥ 90% of them.
#[cfg(feature = "mpfr")]
mod issue_13 {
    use super::*;
    use areawarp::harness::extremes::{extremes_grid, random_points};
    use areawarp::precision_choice::measure::{
        Audit, Measured, PredictionTally, audit_f32, measure,
    };
    use areawarp::precision_choice::{Advice, Advisable, advise};

    #[derive(Debug, Default)]
    struct Counts {
        tried: usize,
        f64_accepts: usize,
        f32_accepts: usize,
        /// f64 accepts, f32 rejects: by reason.
        f32_only_rejects: BTreeMap<String, usize>,
        /// f32 accepts, f64 rejects (must stay 0).
        f32_accepts_more: usize,
        max_map_ratio: f64,
        max_inverse_ratio: f64,
        inverse_refusals: usize,
        /// Samples off the exact shape (inverse checked for refusal only).
        off_exact_shape: usize,
        samples: usize,
        max_outside_ulps: f64,
        /// Predicted against measured, per evaluation.
        tally: PredictionTally,
        worst_under: Option<String>,
    }

    fn points() -> Vec<(f64, f64)> {
        let mut p = extremes_grid();
        p.extend(random_points(16, 42));
        p
    }

    fn audit<W: Advisable>(w: &W, c: &mut Counts, label: &str) {
        let pts = points();
        let a: Audit = audit_f32(w, &pts).unwrap();
        c.tried += 1;
        c.f64_accepts += usize::from(a.f64_accepts);
        c.f32_accepts += usize::from(a.f32_accepts);
        if a.f64_accepts && !a.f32_accepts {
            let why = format!("{:?}", a.f32_error);
            *c.f32_only_rejects.entry(why).or_default() += 1;
        }
        c.f32_accepts_more += usize::from(a.f32_accepts && !a.f64_accepts);
        c.max_map_ratio = c.max_map_ratio.max(a.map_ratio);
        c.max_inverse_ratio = c.max_inverse_ratio.max(a.inverse_ratio);
        c.inverse_refusals += a.inverse_refusals + a.non_finite;
        c.off_exact_shape += a.off_exact_shape;
        c.samples += if a.f32_accepts { pts.len() } else { 0 };
        c.max_outside_ulps = c.max_outside_ulps.max(a.max_outside_ulps);
        if a.map_ratio > 1.0 || a.inverse_ratio > 1.0 || a.inverse_refusals > 0 {
            c.worst_under
                .get_or_insert_with(|| format!("{label}: {a:?}"));
        }
        let Ok(advice) = advise(w) else { return };
        let measured = measure(w, &pts).unwrap_or_else(|e| panic!("{label}: {e:?}"));
        for m in measured.iter().filter(|m| m.accepted) {
            let p = advice.predicted(m.evaluation);
            if !(p >= m.worst_error) {
                c.worst_under.get_or_insert_with(|| {
                    format!(
                        "{label} {}: predicted {p:e} < measured {:e}",
                        m.evaluation, m.worst_error
                    )
                });
            }
        }
        c.tally.add(&advice, &measured);
    }

    fn run(cases: u32) -> (Counts, Counts) {
        let tri = RefCell::new(Counts::default());
        let rect = RefCell::new(Counts::default());
        let config = Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        };
        runner(config.clone())
            .run(&triangle_case(), |case| {
                if let Ok(t) = case.build::<f64>(SphericalTriangleVariant::Robust) {
                    audit(&t, &mut tri.borrow_mut(), &format!("{case:?}"));
                }
                Ok(())
            })
            .unwrap();
        runner(config)
            .run(&rectangle_case(), |case| {
                if let Ok(r) = case.build::<f64>(SphericalRectangleVariant::Robust) {
                    audit(&r, &mut rect.borrow_mut(), &format!("{case:?}"));
                }
                Ok(())
            })
            .unwrap();
        (tri.into_inner(), rect.into_inner())
    }

    fn check(name: &str, c: &Counts) {
        println!("\n{name}: {c:#?}");
        assert_eq!(c.f32_accepts_more, 0, "{name}");
        assert!(c.max_map_ratio <= 1.0, "{name}: {c:?}");
        assert!(c.max_inverse_ratio <= 1.0, "{name}: {c:?}");
        assert_eq!(c.inverse_refusals, 0, "{name}: {c:?}");
        // Every prediction, the literal algorithms' included, is an upper
        // bound.
        println!("{}", c.tally.table(name));
        assert_eq!(c.tally.total().under, 0, "{name}: {c:?}");
    }

    /// ≥ 90% of the predictions within 100× of the measured error, per
    /// family and over both.
    fn check_tightness(t: &Counts, r: &Counts) {
        let both = t.tally.merged(&r.tally);
        println!("{}", both.table("random shapes, both families"));
        for (family, tally) in [
            ("triangles", &t.tally),
            ("rectangles", &r.tally),
            ("both", &both),
        ] {
            let total = tally.total();
            assert!(total.fraction_within_100() >= 0.9, "{family}: {total:?}");
        }
    }

    /// The predictions alone (no audit) over more shapes:
    /// `AREAWARP_CASES` (default 2500) triangles and rectangles;
    /// `AREAWARP_OUTLIERS=1` prints every case beyond 100× or predicted
    /// less than 1.25× its measured error.
    #[test]
    #[ignore = "large: advise and measure at 256 bits on 2500 + 2500 shapes (minutes)"]
    fn predictions_random_shapes() {
        let cases = std::env::var("AREAWARP_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(2500);
        let outliers = std::env::var("AREAWARP_OUTLIERS").is_ok();
        let pts = points();
        let config = Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        };
        let tally = |w: &dyn Fn() -> Option<(Advice, Vec<Measured>)>,
                     t: &mut PredictionTally,
                     label: &str| {
            let Some((advice, measured)) = w() else {
                return;
            };
            for m in measured.iter().filter(|m| m.accepted) {
                let p = advice.predicted(m.evaluation);
                if outliers && !(p >= 1.25 * m.worst_error && p <= 100.0 * m.worst_error) {
                    println!(
                        "OUT {} ratio {:.3e} predicted {p:.3e} measured {:.3e} κ32 {:.3e} κ64 {:.3e} κmix {:.3e}: {label}",
                        m.evaluation,
                        p / m.worst_error,
                        m.worst_error,
                        advice.kappa_f32,
                        advice.kappa_f64,
                        advice.kappa_mixed
                    );
                }
            }
            t.add(&advice, &measured);
        };
        let (tri, rect) = (
            RefCell::new(PredictionTally::default()),
            RefCell::new(PredictionTally::default()),
        );
        runner(config.clone())
            .run(&triangle_case(), |case| {
                if let Ok(t) = case.build::<f64>(SphericalTriangleVariant::Robust) {
                    let f = || Some((advise(&t).ok()?, measure(&t, &pts).ok()?));
                    tally(&f, &mut tri.borrow_mut(), &format!("{case:?}"));
                }
                Ok(())
            })
            .unwrap();
        runner(config)
            .run(&rectangle_case(), |case| {
                if let Ok(r) = case.build::<f64>(SphericalRectangleVariant::Robust) {
                    let f = || Some((advise(&r).ok()?, measure(&r, &pts).ok()?));
                    tally(&f, &mut rect.borrow_mut(), &format!("{case:?}"));
                }
                Ok(())
            })
            .unwrap();
        let (tri, rect) = (tri.into_inner(), rect.into_inner());
        let both = tri.merged(&rect);
        println!(
            "{}\n{}\n{}",
            tri.table("random triangles"),
            rect.table("random rectangles"),
            both.table("random shapes, both")
        );
        for (family, t) in [("triangles", &tri), ("rectangles", &rect), ("both", &both)] {
            let total = t.total();
            assert_eq!(total.under, 0, "{family}: {total:?}");
            assert!(total.fraction_within_100() >= 0.9, "{family}: {total:?}");
        }
    }

    #[test]
    fn f32_audit_random_shapes() {
        let (t, r) = run(60);
        check("spherical triangles (shapes f64 accepts)", &t);
        check("spherical rectangles (shapes f64 accepts)", &r);
        check_tightness(&t, &r);
    }

    #[test]
    #[ignore = "large: 5000 triangles and 5000 rectangles at 256 bits (minutes)"]
    fn f32_audit_random_shapes_large() {
        let (t, r) = run(5000);
        check("spherical triangles (shapes f64 accepts)", &t);
        check("spherical rectangles (shapes f64 accepts)", &r);
        check_tightness(&t, &r);
    }
}

/// Cases the random fuzz found.
#[test]
fn fuzz_regressions() {
    let r = SphericalRectangle::<f32>::new(
        Vec3::new(1474729.623491079, -1551252.5309053469, 1191406.4307607305).convert(),
        Vec3::new(
            -51512071.731312685,
            -34196071.473136105,
            -44089759.835586466,
        )
        .convert(),
        Vec3::new(326182.9673429833, 3249772.8962839525, -2901622.216159868).convert(),
        Vec3::new(412731.6123861427, -1244505.7424952113, -778541.2693697122).convert(),
    );
    if let Ok(r) = r {
        for u in unit_values::<f32>() {
            for v in unit_values::<f32>() {
                let s = r.sample_light([u, v]);
                assert!(
                    s.direction.is_finite() && s.point.is_finite(),
                    "{u} {v}: {s:?} {r:?}"
                );
            }
        }
    }
}

/// The projected polygon and the sphere: f32 accepts what f64 accepts on the
/// same values (issue 13, item 1). A band of 8 vertices just above the
/// equator bounds nearly 2π; the test of the 2π ambiguity used to run with
/// f32's roundoff.
#[test]
fn projected_polygon_and_sphere_f32_accept_what_f64_accepts() {
    use areawarp::shapes::{ProjectedPolygon, Sphere};
    let (mut tried, mut both, mut unrepresentable) = (0, 0, 0);
    for eps in [1e-2f32, 1e-3, 1e-4, 1e-5, 1e-6] {
        for n in [4, 8, 16] {
            let v: Vec<Vec3<f32>> = (0..n)
                .map(|i| {
                    let a = 2.0 * std::f32::consts::PI * i as f32 / n as f32 + 0.1;
                    Vec3::new(a.cos(), a.sin(), eps)
                })
                .collect();
            let v64: Vec<Vec3<f64>> = v.iter().map(|p| p.convert()).collect();
            let f64_ok = ProjectedPolygon::<f64>::new(&v64).is_ok();
            let f32_result = ProjectedPolygon::<f32>::new(&v);
            tried += 1;
            match f32_result {
                Ok(_) => {
                    assert!(f64_ok, "{eps} {n}: f32 accepts, f64 rejects");
                    both += 1;
                }
                Err(WarpError::Unrepresentable { .. }) => unrepresentable += 1,
                Err(e) => assert!(!f64_ok, "{eps} {n}: f32 rejects ({e}), f64 accepts"),
            }
        }
    }
    println!(
        "bands: {tried} tried, {both} accepted by both, {unrepresentable} unrepresentable in f32"
    );
    assert_eq!(tried, 15);
    // The sphere's only decisions (finite, non-zero axis) are exact.
    for axis in [Vec3::new(1e-40f32, 0.0, 0.0), Vec3::new(3e38, 3e38, 0.0)] {
        assert!(Sphere::with_axis(axis).is_ok());
        assert!(Sphere::<f64>::with_axis(axis.convert()).is_ok());
    }
}
