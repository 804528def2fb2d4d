//! Are the polygons that the projected polygon's constructor rejects as
//! self-intersecting really self-intersecting? (Issue 10, item 3:
//! "rejecting a valid input is a failure".)
//!
//! The polygons of the fuzz (`support/polygon_cases.rs`) are built in
//! `f32` and `f64`; each one rejected as self-intersecting is judged in
//! 1024-bit arithmetic on the input values (rounded to the scalar type):
//! every pair of edges (minor arcs) is tested for a crossing, a touch or
//! an overlap on or above the receiver's horizon (the map clips the polygon
//! to `z ≥ 0`, so a crossing below it does not matter), with determinants
//! that are exact for direction input. A rejection of a polygon with no
//! such meeting is a false rejection; none is allowed.
//! Counts per kind of case are printed.
//!
//! `cargo test --release -p areawarp --features mpfr --test polygon_rejections -- --nocapture`
//! (the fuzz's large size: `-- --ignored --nocapture`).
#![cfg(feature = "mpfr")]

use areawarp::real::Mpfr;
use areawarp::shapes::ProjectedPolygon;
use areawarp::{Real, Vec3, WarpError};
use proptest::test_runner::Config;
use std::cell::RefCell;
use std::collections::BTreeMap;

#[path = "support/light_cases.rs"]
mod light_cases;
use light_cases::{runner, v3};

#[path = "support/polygon_cases.rs"]
mod polygon_cases;
use polygon_cases::{PolygonCase, polygon_case};

/// Wide enough that the determinants of the tests below (products of up
/// to seven input coordinates) are exact for the inputs of the fuzz.
type M = Mpfr<1024>;

/// The case's vertex directions in the receiver's frame (normal `+z`),
/// from its values rounded to `T` (the polygon that `T`'s constructor is
/// given), unnormalized: every test below is a sign of a determinant,
/// invariant under positive scaling, so for direction input it is exact.
fn directions<T: Real>(case: &PolygonCase) -> Vec<Vec3<M>> {
    let raw: Vec<Vec3<M>> = case.vertices.iter().map(|p| v3::<T>(p).convert()).collect();
    match &case.seen_from {
        None => raw,
        Some((o, n)) => {
            let o: Vec3<M> = v3::<T>(o).convert();
            let n: Vec3<M> = v3::<T>(n).convert();
            let n = n.scale(&(M::one() / &n.norm()));
            // Any right-handed orthonormal frame with n as +z: the judgement
            // does not depend on the azimuth of e1.
            let helper = if n.x.abs() < M::from_ratio(1, 2) {
                Vec3::new(M::one(), M::zero(), M::zero())
            } else {
                Vec3::new(M::zero(), M::one(), M::zero())
            };
            let e1 = helper.cross(&n);
            let e1 = e1.scale(&(M::one() / &e1.norm()));
            let e2 = n.cross(&e1);
            raw.iter()
                .map(|p| {
                    let d = p.sub(&o);
                    Vec3::new(d.dot(&e1), d.dot(&e2), d.dot(&n))
                })
                .collect()
        }
    }
}

/// Whether `p` lies on the closed minor arc `a → b` (`n = a × b`), given
/// that it lies on its great circle.
fn on_arc(a: &Vec3<M>, b: &Vec3<M>, n: &Vec3<M>, p: &Vec3<M>) -> bool {
    a.cross(p).dot(n) >= M::zero() && p.cross(b).dot(n) >= M::zero()
}

/// Whether two edges of the polygon `v` (minor arcs) meet, other than at
/// the vertex two consecutive edges share, at a point with `z ≥ 0`: a
/// crossing, a touch, or an overlap along a common great circle (including
/// an edge folding back over its predecessor).
fn meets_above_horizon(v: &[Vec3<M>]) -> bool {
    let k = v.len();
    let zero = M::zero();
    for i in 0..k {
        for j in i + 1..k {
            let adjacent = j == i + 1 || (i == 0 && j == k - 1);
            let (a, b) = (&v[i], &v[(i + 1) % k]);
            let (c, d) = (&v[j], &v[(j + 1) % k]);
            let n1 = a.cross(b);
            let n2 = c.cross(d);
            let p = n1.cross(&n2);
            if p.x == zero && p.y == zero && p.z == zero {
                // One great circle: do the arcs overlap (beyond a shared
                // vertex)? Any end of one inside the other, strictly for a
                // shared vertex.
                let ends = [
                    (c, a, b, &n1),
                    (d, a, b, &n1),
                    (a, c, d, &n2),
                    (b, c, d, &n2),
                ];
                if ends.iter().any(|(p, s, e, n)| {
                    let shared = adjacent && (*p == a || *p == b) && (*p == c || *p == d);
                    let strict_in = s.cross(p).dot(n) > zero && p.cross(e).dot(n) > zero;
                    (if shared {
                        strict_in
                    } else {
                        on_arc(s, e, n, p)
                    }) && p.z >= zero
                }) {
                    return true;
                }
                continue;
            }
            if adjacent {
                continue;
            }
            if n1.dot(c) * &n1.dot(d) > zero || n2.dot(a) * &n2.dot(b) > zero {
                continue;
            }
            for q in [p.clone(), p.neg()] {
                if on_arc(a, b, &n1, &q) && on_arc(c, d, &n2, &q) && q.z >= zero {
                    return true;
                }
            }
        }
    }
    false
}

fn self_intersection(e: &WarpError) -> bool {
    matches!(e, WarpError::Degenerate { what } if what.contains("self-intersecting"))
}

fn build<T: Real>(case: &PolygonCase) -> Result<ProjectedPolygon<T>, WarpError> {
    let vertices: Vec<Vec3<T>> = case.vertices.iter().map(v3).collect();
    match &case.seen_from {
        None => ProjectedPolygon::new(&vertices),
        Some((o, n)) => ProjectedPolygon::from_points(&vertices, &v3(o), &v3(n)),
    }
}

/// Per kind: (tried, rejected as self-intersecting, of which really
/// self-intersecting above the horizon).
type Counts = BTreeMap<&'static str, (usize, usize, usize)>;

#[derive(Default)]
struct Tallies {
    counts: BTreeMap<&'static str, Counts>,
    false_rejections: Vec<String>,
}

fn judge<T: Real>(case: &PolygonCase, name: &'static str, t: &mut Tallies) {
    let entry = t
        .counts
        .entry(name)
        .or_default()
        .entry(case.kind)
        .or_default();
    entry.0 += 1;
    let Err(e) = build::<T>(case) else {
        return;
    };
    if !self_intersection(&e) {
        return;
    }
    entry.1 += 1;
    if meets_above_horizon(&directions::<T>(case)) {
        entry.2 += 1;
    } else {
        if t.false_rejections.len() < 20 {
            t.false_rejections.push(format!("{name}: {case:?}: {e:?}"));
        }
    }
}

fn check(cases: u32) {
    let tallies = RefCell::new(Tallies::default());
    let mut runner = runner(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&polygon_case(), |case| {
            let mut t = tallies.borrow_mut();
            judge::<f32>(&case, "f32", &mut t);
            judge::<f64>(&case, "f64", &mut t);
            Ok(())
        })
        .unwrap();
    let t = tallies.into_inner();
    println!(
        "\nprojected polygons rejected as self-intersecting, per scalar and kind: (tried, rejected, edges really meet above the horizon (exact))"
    );
    let mut false_rejections = 0;
    for (name, counts) in &t.counts {
        println!("{name}: {counts:?}");
        false_rejections += counts.values().map(|c| c.1 - c.2).sum::<usize>();
    }
    for f in &t.false_rejections {
        println!("false rejection: {f}");
    }
    assert_eq!(false_rejections, 0, "{:?}", t.false_rejections.first());
}

#[test]
fn polygon_rejections() {
    check(600);
}

#[test]
#[ignore = "the fuzz's large size: 10⁴ polygons"]
fn polygon_rejections_large() {
    check(10_000);
}

/// The judge itself: a bow tie and a boundary folding back along one great
/// circle meet themselves; a convex quad does not, nor a bow tie whose
/// crossing is below the horizon.
#[test]
fn judge_sanity() {
    let case = |v: &[[f64; 3]]| PolygonCase {
        kind: "sanity",
        vertices: v.to_vec(),
        seen_from: None,
    };
    let meets = |v: &[[f64; 3]]| meets_above_horizon(&directions::<f64>(&case(v)));
    let quad = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    assert!(!meets(&quad));
    let bow_tie = [
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    assert!(meets(&bow_tie));
    let below = bow_tie.map(|p| [p[0], p[1], -1.0]);
    assert!(!meets(&below));
    let folded = [
        [0.1, 0.0, 1.0],
        [0.3, 0.0, 1.0],
        [0.2, 0.0, 1.0],
        [0.4, 0.0, 1.0],
    ];
    assert!(meets(&folded));
    let fold_back = [
        [0.1, 0.0, 1.0],
        [0.3, 0.0, 1.0],
        [0.2, 0.0, 1.0],
        [0.2, 0.5, 1.0],
    ];
    assert!(meets(&fold_back));
}
