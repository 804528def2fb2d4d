//! Fuzz of the projected polygon's constructors and map (issue 10, item 3):
//! random and near-degenerate spherical polygons — convex, 3 to 6 vertices,
//! from 1e-8 rad to 1.4 rad across, needles, nearly collinear and nearly
//! coincident vertices, polygons straddling or grazing the horizon, and
//! planar polygons in space seen from observers at scales 1e-30 … 1e30 —
//! built in `f32` and `f64` with each marginal inversion.
//!
//! Every constructor either returns a typed error or a shape whose samples at
//! `u, v ∈ {0, smallest subnormal, 1e-7, ½, 1 − ulp, 1}` (and 16 random
//! points) are finite, on the polygon by its own `outside_by` (within its
//! `on_shape_tolerance`), accepted by its own `inverse`, with a finite,
//! non-negative density. Counts of shapes tried / accepted / with a bad
//! sample are printed per inversion and scalar; none may have a bad sample.
//! An `f32` constructor may reject only what `f64` rejects on the same
//! (rounded) values, or call the polygon unrepresentable in `f32` (issue
//! 13): both counts are printed, the first must be 0.
//!
//! `cargo test --release -p areawarp --test polygon_fuzz -- --nocapture`
//! (the large size: `-- --ignored --nocapture`).

use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
use areawarp::{Real, Vec3, Warp, WarpError};
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::cell::RefCell;
use std::collections::BTreeMap;

#[path = "support/light_cases.rs"]
mod light_cases;
use light_cases::{power, runner, unit_values, v3};

/// A polygon case: vertex directions (receiver normal +z), or corners in
/// space seen from an observer on a receiver with a normal.
#[derive(Clone, Debug)]
struct PolygonCase {
    kind: &'static str,
    vertices: Vec<[f64; 3]>,
    /// `Some((observer, normal))`: the vertices are points in space.
    seen_from: Option<([f64; 3], [f64; 3])>,
}

/// A convex polygon of `n` vertices on a small circle of angular radius
/// `rho` about the direction of elevation `elev` and azimuth `az`, squashed
/// across by `squash` (1 = round).
fn ring(n: usize, rho: f64, elev: f64, az: f64, squash: f64, phase: f64) -> Vec<[f64; 3]> {
    let c = [elev.cos() * az.cos(), elev.cos() * az.sin(), elev.sin()];
    let e1 = [-az.sin(), az.cos(), 0.0];
    let e2 = [-elev.sin() * az.cos(), -elev.sin() * az.sin(), elev.cos()];
    (0..n)
        .map(|k| {
            let beta = phase + std::f64::consts::TAU * k as f64 / n as f64;
            let (a, b) = (rho * beta.cos(), rho * squash * beta.sin());
            let t = (a * a + b * b).sqrt();
            let (s, cs) = if t > 0.0 {
                (t.sin() / t, t.cos())
            } else {
                (1.0, 1.0)
            };
            [0, 1, 2].map(|i| cs * c[i] + s * (a * e1[i] + b * e2[i]))
        })
        .collect()
}

// 1.5707: an elevation just below π/2 (not meant as π/2).
#[allow(clippy::approx_constant)]
fn polygon_case() -> impl Strategy<Value = PolygonCase> {
    let shape = (
        3usize..=6,
        power(-8.0, 0.15),
        0.0f64..std::f64::consts::TAU,
        0.0f64..1.0,
    );
    prop_oneof![
        // Random convex polygons above the horizon.
        (shape.clone(), 0.05f64..1.5707).prop_map(|((n, rho, az, ph), elev)| PolygonCase {
            kind: "random",
            vertices: ring(n, rho.min(elev * 0.9), elev, az, 1.0, ph),
            seen_from: None,
        }),
        // Straddling or grazing the horizon (clipped by the receiver).
        (shape.clone(), -1.0f64..1.0).prop_map(|((n, rho, az, ph), t)| PolygonCase {
            kind: "horizon",
            vertices: ring(n, rho, t * rho, az, 1.0, ph),
            seen_from: None,
        }),
        // Needles: squashed across by 1e-1 … 1e-9.
        (shape.clone(), 0.1f64..1.5, power(-9.0, -1.0)).prop_map(|((n, rho, az, ph), elev, sq)| {
            PolygonCase {
                kind: "needle",
                vertices: ring(n.max(4), rho, elev, az, sq, ph),
                seen_from: None,
            }
        }),
        // A vertex nudged onto the arc of its neighbours (1e-12 … 1e-3 off).
        (shape.clone(), 0.1f64..1.5, power(-12.0, -3.0)).prop_map(
            |((n, rho, az, ph), elev, off)| {
                let mut v = ring(n.max(4), rho, elev, az, 1.0, ph);
                let (a, b) = (v[0], v[2]);
                let mid = [0, 1, 2].map(|i| a[i] + b[i]);
                let out = [0, 1, 2].map(|i| v[1][i] - mid[i] * 0.5);
                v[1] = [0, 1, 2].map(|i| mid[i] * 0.5 + off * out[i]);
                PolygonCase {
                    kind: "nearly collinear",
                    vertices: v,
                    seen_from: None,
                }
            }
        ),
        // Two vertices 1e-14 … 1e-4 (relative) apart.
        (shape.clone(), 0.1f64..1.5, power(-14.0, -4.0)).prop_map(
            |((n, rho, az, ph), elev, gap)| {
                let mut v = ring(n, rho, elev, az, 1.0, ph);
                let (a, b) = (v[0], v[1]);
                v[1] = [0, 1, 2].map(|i| a[i] + gap * (b[i] - a[i]));
                PolygonCase {
                    kind: "nearly coincident",
                    vertices: v,
                    seen_from: None,
                }
            }
        ),
        // A planar quad in space at scale 1e-30 … 1e30, seen from an observer
        // on a tilted receiver.
        (
            power(-30.0, 30.0),
            -1.0f64..1.0,
            -1.0f64..1.0,
            0.2f64..3.0,
            power(-6.0, 0.5),
            -0.8f64..0.8
        )
            .prop_map(|(scale, x, y, h, size, tilt)| {
                let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.6], [0.0, 1.0]];
                PolygonCase {
                    kind: "points",
                    vertices: corners
                        .iter()
                        .map(|c| {
                            [
                                (x + size * c[0]) * scale,
                                (y + size * c[1]) * scale,
                                h * scale,
                            ]
                        })
                        .collect(),
                    seen_from: Some(([0.0, 0.0, 0.0], [tilt, 0.3 * tilt, 1.0])),
                }
            }),
    ]
}

/// What happened to the shapes of one inversion and scalar.
#[derive(Clone, Debug, Default)]
struct Tally {
    tried: usize,
    accepted: usize,
    bad: usize,
    rejected: BTreeMap<String, usize>,
    /// Largest `outside_by` of a sample, in units of roundoff.
    max_outside_ulps: f64,
    first: Option<String>,
    /// `(tried, accepted, bad)` per kind of case.
    by_kind: BTreeMap<&'static str, (usize, usize, usize)>,
    /// Rejected by a narrow type for a reason other than "unrepresentable"
    /// although `f64` accepts the same values (issue 13: must be 0).
    narrow_only: usize,
    /// Rejected by a narrow type as unrepresentable although `f64` accepts
    /// the same values (allowed: the rounded vertices no longer bound a
    /// valid polygon).
    unrepresentable_only: usize,
}

fn why_rejected(e: &WarpError) -> String {
    match e {
        WarpError::NonFinite { .. } => "non-finite".to_string(),
        WarpError::Degenerate { what } => format!("degenerate: {what}"),
        WarpError::Unrepresentable { what } => format!("unrepresentable: {what}"),
        WarpError::InvalidParameter { name, .. } => format!("invalid {name}"),
        WarpError::NotConverged { what } => format!("not converged: {what}"),
        WarpError::Inconsistent { what } => format!("inconsistent: {what}"),
    }
}

/// The first bad sample of `w`, if any.
fn bad_sample<T: Real>(
    w: &ProjectedPolygon<T>,
    extra: &[(f64, f64)],
    t: &mut Tally,
) -> Option<String> {
    let values = unit_values::<T>();
    let mut grid: Vec<(T, T)> = Vec::new();
    for u in &values {
        for v in &values {
            grid.push((u.clone(), v.clone()));
        }
    }
    grid.extend(extra.iter().map(|&(u, v)| (T::from_f64(u), T::from_f64(v))));
    let tol = w.on_shape_tolerance();
    for (u, v) in grid {
        let (p, pdf) = w.map_with_pdf(&u, &v);
        let why = if !p.is_finite() {
            Some("non-finite direction".to_string())
        } else if !pdf.is_finite() || pdf < T::zero() {
            Some(format!("density {pdf:?}"))
        } else {
            let out = w.outside_by(&p);
            let ulps = (out.clone() / &T::unit_roundoff()).to_f64();
            t.max_outside_ulps = t.max_outside_ulps.max(ulps);
            if !(out <= tol) {
                Some(format!("off the polygon by {out:?} (tolerance {tol:?})"))
            } else if let Err(e) = w.inverse(&p) {
                Some(format!("refused by its inverse: {e:?}"))
            } else {
                None
            }
        };
        if let Some(why) = why {
            return Some(format!("{why} at u = {u:?}, v = {v:?}: {p:?}"));
        }
    }
    None
}

/// Whether `f64` accepts the case on the values `vertices` (and the
/// observer and normal) rounded to a narrow type.
fn wide_accepts<T: Real>(
    case: &PolygonCase,
    vertices: &[Vec3<T>],
    inversion: MarginalInversion,
) -> bool {
    let wide: Vec<Vec3<f64>> = vertices.iter().map(|v| v.convert()).collect();
    match &case.seen_from {
        None => ProjectedPolygon::new_with(&wide, inversion).is_ok(),
        Some((o, n)) => ProjectedPolygon::from_points_with(
            &wide,
            &v3::<T>(o).convert(),
            &v3::<T>(n).convert(),
            inversion,
        )
        .is_ok(),
    }
}

fn run<T: Real>(
    case: &PolygonCase,
    inversion: MarginalInversion,
    extra: &[(f64, f64)],
    t: &mut Tally,
) {
    t.tried += 1;
    t.by_kind.entry(case.kind).or_default().0 += 1;
    let vertices: Vec<Vec3<T>> = case.vertices.iter().map(v3).collect();
    let built = match &case.seen_from {
        None => ProjectedPolygon::new_with(&vertices, inversion),
        Some((o, n)) => ProjectedPolygon::from_points_with(&vertices, &v3(o), &v3(n), inversion),
    };
    let w = match built {
        Ok(w) => w,
        Err(e) => {
            *t.rejected.entry(why_rejected(&e)).or_default() += 1;
            if T::precision() < 53 && wide_accepts(case, &vertices, inversion) {
                match e {
                    WarpError::Unrepresentable { .. } => t.unrepresentable_only += 1,
                    _ => {
                        t.narrow_only += 1;
                        t.first.get_or_insert_with(|| {
                            format!("{case:?}: rejected ({e:?}) but f64 accepts the same values")
                        });
                    }
                }
            }
            return;
        }
    };
    t.accepted += 1;
    t.by_kind.entry(case.kind).or_default().1 += 1;
    if let Some(why) = bad_sample(&w, extra, t) {
        t.bad += 1;
        t.by_kind.entry(case.kind).or_default().2 += 1;
        t.first.get_or_insert_with(|| format!("{case:?}: {why}"));
    }
}

fn fuzz(cases: u32) -> BTreeMap<String, Tally> {
    let tallies = RefCell::new(BTreeMap::<String, Tally>::new());
    let mut runner = runner(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let extra: Vec<(f64, f64)> = areawarp::harness::extremes::random_points(16, 3);
    runner
        .run(&polygon_case(), |case| {
            let mut ts = tallies.borrow_mut();
            for (inversion, name) in [
                (MarginalInversion::Newton, "newton"),
                (MarginalInversion::Cubic, "cubic"),
                (MarginalInversion::CubicNewton(2), "cubic+2"),
            ] {
                run::<f32>(
                    &case,
                    inversion,
                    &extra,
                    ts.entry(format!("{name} f32")).or_default(),
                );
                run::<f64>(
                    &case,
                    inversion,
                    &extra,
                    ts.entry(format!("{name} f64")).or_default(),
                );
            }
            Ok(())
        })
        .unwrap();
    tallies.into_inner()
}

fn report_and_check(tallies: &BTreeMap<String, Tally>) {
    println!(
        "\nprojected polygons: inversion / scalar | tried | accepted | bad samples | max outside_by [u] | f64 accepts the same values: rejected as unrepresentable / otherwise | rejections"
    );
    for (k, t) in tallies {
        println!(
            "{k:<12} | {} | {} | {} | {:.2} | {} / {} | {:?}",
            t.tried,
            t.accepted,
            t.bad,
            t.max_outside_ulps,
            t.unrepresentable_only,
            t.narrow_only,
            t.rejected
        );
        println!("    by kind (tried, accepted, bad): {:?}", t.by_kind);
        if let Some(f) = &t.first {
            println!("    first: {f}");
        }
    }
    for (k, t) in tallies {
        assert_eq!(t.bad, 0, "{k}: {:?}", t.first);
        assert_eq!(t.narrow_only, 0, "{k}: {:?}", t.first);
        assert!(
            t.accepted * 2 > t.tried,
            "{k}: most shapes are valid: {t:?}"
        );
    }
}

#[test]
fn polygon_fuzz() {
    report_and_check(&fuzz(600));
}

#[test]
#[ignore = "large fuzz: 10⁴ polygons"]
fn polygon_fuzz_large() {
    report_and_check(&fuzz(10_000));
}
