use super::*;
use std::f64::consts::PI;

fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}

fn scene(name: &str) -> Scene {
    default_scenes()
        .unwrap()
        .into_iter()
        .find(|s| s.name == name)
        .unwrap()
}

fn tiny_config() -> SolidAngleConfig {
    SolidAngleConfig {
        sample_counts: vec![16, 64, 256],
        repetitions: 4,
        heat_map_cells: 16,
        heat_map_points: 1,
        world_samples: 2_000,
        profile_points: 2,
        ..SolidAngleConfig::quick()
    }
}

#[test]
fn mesh_validation() {
    let o = TriangleMesh::octahedron(v(0.0, 0.0, 5.0), 1.0).unwrap();
    assert_eq!(o.kind(), MeshKind::ConvexClosed);
    // Open (a face removed), non-convex (a vertex pushed in), inward.
    let mut faces = o.faces().to_vec();
    faces.pop();
    assert!(TriangleMesh::convex_closed(o.vertices().to_vec(), faces).is_err());
    let mut verts = o.vertices().to_vec();
    verts[0] = v(-0.2, 0.0, 5.0); // a dent: inside the others' hull
    assert!(TriangleMesh::convex_closed(verts, o.faces().to_vec()).is_err());
    let flipped: Vec<[usize; 3]> = o.faces().iter().map(|f| [f[0], f[2], f[1]]).collect();
    assert!(TriangleMesh::convex_closed(o.vertices().to_vec(), flipped).is_err());
    assert!(TriangleMesh::octahedron(v(0.0, 0.0, 0.0), 0.0).is_err());
    assert!(TriangleMesh::open(vec![v(0.0, 0.0, 0.0); 3], vec![[0, 1, 2]]).is_err());
    assert!(TriangleMesh::open(vec![v(f64::NAN, 0.0, 0.0); 3], vec![[0, 1, 2]]).is_err());
    assert!(
        TriangleMesh::open(
            vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)],
            vec![[0, 1, 3]]
        )
        .is_err()
    );
    // A viewpoint on a face is rejected.
    let tri = TriangleMesh::open(
        vec![v(0.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(0.0, 1.0, 1.0)],
        vec![[0, 1, 2]],
    )
    .unwrap();
    assert!(exact_solid_angle::<f64>(&tri, &v(0.2, 0.2, 1.0)).is_err());
    assert!(exact_solid_angle::<f64>(&tri, &v(2.0, 2.0, 1.0)).is_ok());
}

#[test]
fn config_validation() {
    let bad = |f: fn(&mut SolidAngleConfig)| {
        let mut c = tiny_config();
        f(&mut c);
        run(&c).is_err()
    };
    assert!(bad(|c| c.sample_counts = vec![8]));
    assert!(bad(|c| c.sample_counts = vec![2]));
    assert!(bad(|c| c.sample_counts.clear()));
    assert!(bad(|c| c.repetitions = 1));
    assert!(bad(|c| c.methods.clear()));
    assert!(bad(|c| c.heat_map_cells = 0));
}

#[test]
fn ray_triangle_edge_policy() {
    let (a, b, c) = (v(0.0, 0.0, 2.0), v(2.0, 0.0, 2.0), v(0.0, 2.0, 2.0));
    let o = Vec3::zero();
    let hit = |d: Vec3<f64>| ray_hits_triangle(&o, &d, &a, &b, &c);
    assert_eq!(hit(v(0.5, 0.5, 2.0)), Some(1.0));
    // Vertices and edges (exactly representable barycentrics): inclusive.
    for d in [a, b, c, v(1.0, 0.0, 2.0), v(0.0, 1.0, 2.0)] {
        assert!(hit(d).is_some(), "{d:?}");
    }
    assert!(hit(v(1.0, 1.0, 2.0)).is_some(), "hypotenuse");
    assert!(hit(v(1.0, 1.0 + 1e-12, 2.0)).is_some(), "within the slack");
    assert!(hit(v(1.0, 1.0 + 1e-8, 2.0)).is_none());
    assert!(hit(v(-1e-8, 0.5, 2.0)).is_none());
    // Behind the origin, parallel to the plane, from the plane itself.
    assert!(hit(v(0.5, 0.5, -2.0)).is_none());
    assert!(hit(v(1.0, 0.0, 0.0)).is_none());
    assert!(ray_hits_triangle(&v(0.5, 0.5, 2.0), &v(0.0, 0.0, 1.0), &a, &b, &c).is_none());
    // Both sides count.
    assert!(ray_hits_triangle(&v(0.5, 0.5, 4.0), &v(0.0, 0.0, -1.0), &a, &b, &c).is_some());
    // A closed mesh is watertight along a shared edge: rays aimed at
    // points of the edges of the octahedron all hit.
    let m = TriangleMesh::octahedron(v(0.3, -0.2, 3.0), 1.0).unwrap();
    let g = Geometry::new(&m, &Vec3::zero()).unwrap();
    let vs = m.vertices();
    for f in m.faces() {
        for k in 0..3 {
            for t in [0.0, 0.25, 0.5, 1.0 / 3.0] {
                let p = vs[f[k]].lerp(&vs[f[(k + 1) % 3]], &t);
                assert!(g.hit(&arr(&p)), "{p:?}");
            }
        }
    }
}

#[test]
fn exact_reference_inside_closed_mesh_is_four_pi() {
    let m = TriangleMesh::octahedron(v(0.2, -0.3, 0.1), 1.0).unwrap();
    let t = TriangleMesh::tetrahedron([
        v(1.0, 0.1, -0.3),
        v(-0.6, 0.9, -0.2),
        v(-0.4, -0.8, -0.4),
        v(0.1, 0.0, 1.2),
    ])
    .unwrap();
    for mesh in [&m, &t] {
        let w: f64 = exact_solid_angle(mesh, &Vec3::zero()).unwrap();
        assert!((w - 4.0 * PI).abs() < 1e-13, "{w}");
        {
            use areawarp::real::Mpfr256 as M;
            let w: M = exact_solid_angle(mesh, &Vec3::zero()).unwrap();
            let four_pi = M::pi() * &M::from_i64(4);
            assert!((w - &four_pi).abs() < M::exp2i(-240));
        }
        // Every direction hits.
        let g = Geometry::new(mesh, &Vec3::zero()).unwrap();
        let sphere = Sphere::<f64>::new();
        let bx = g.angular_box(&sphere, pad_for::<f64>());
        assert_eq!(bx, AngularBox::full());
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        for (s, t) in jitter(32, &mut rng) {
            assert!(g.hit(&arr(&sphere.map(&s, &t))));
        }
    }
}

#[test]
fn exact_reference_outside_convex_is_half_sum_and_front_faces() {
    let sc = scene("tetrahedron");
    let w: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
    // Sum over the faces facing the viewpoint (outward normal towards it).
    let vs = sc.mesh.vertices();
    let mut front = 0.0;
    let mut all = 0.0;
    for f in sc.mesh.faces() {
        let (a, b, c) = (vs[f[0]], vs[f[1]], vs[f[2]]);
        let n = b.sub(&a).cross(&c.sub(&a));
        let om = triangle_solid_angle(&a, &b, &c);
        all += om;
        if n.dot(&sc.viewpoint.sub(&a)) > 0.0 {
            front += om;
            // Front-facing outward faces have negative signed angle.
            assert!(signed_triangle_solid_angle(&a, &b, &c) < 0.0);
        }
    }
    assert!((w - front).abs() < 1e-14 && (w - all / 2.0).abs() < 1e-14);
    assert!(w > 0.05 && w < 1.0, "{w}");
}

/// Van Oosterom–Strackee against Girard's theorem (Ω = α + β + γ − π,
/// with the angles between the great-circle planes) at 256 bits.
#[test]
fn vos_matches_girard_at_256_bits() {
    use areawarp::real::Mpfr256 as M;
    let m = |x: i64, y: i64, z: i64| Vec3::new(M::from_i64(x), M::from_i64(y), M::from_i64(z));
    let tris = [
        (m(1, 0, 0), m(0, 1, 0), m(0, 0, 1)),
        (m(3, 1, 7), m(-2, 5, 6), m(1, -4, 9)),
        (m(10, 1, 1), m(1, 10, 1), m(1, 1, -10)),
        (m(10, 0, -1), m(-5, 9, -1), m(-5, -9, -1)), // Ω > π: den < 0
        (m(1000, 1, 2), m(1000, 3, 1), m(1000, 2, 4)), // tiny
    ];
    for (a, b, c) in tris {
        let vos = triangle_solid_angle(&a, &b, &c);
        let angle = |p: &Vec3<M>, q: &Vec3<M>, r: &Vec3<M>| {
            // Angle at vertex p between the arcs p→q and p→r.
            let n1 = p.cross(q);
            let n2 = p.cross(r);
            n1.cross(&n2).norm().atan2(&n1.dot(&n2))
        };
        let girard = angle(&a, &b, &c) + &angle(&b, &c, &a) + &angle(&c, &a, &b) - &M::pi();
        assert!(
            (vos.clone() - &girard).abs() <= M::exp2i(-240) * &girard.max(&M::one()),
            "{vos} vs {girard}"
        );
        // And f64 agrees to a few ulps (relative).
        let to64 = |p: &Vec3<M>| Vec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64());
        let w64 = triangle_solid_angle(&to64(&a), &to64(&b), &to64(&c));
        assert!(
            ((w64 - vos.to_f64()) / vos.to_f64()).abs() < 1e-13,
            "{w64} {vos}"
        );
    }
}

#[test]
fn covering_arc_cases() {
    let close = |a: Option<(f64, f64)>, b: (f64, f64)| {
        let a = a.unwrap();
        assert!(
            (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
            "{a:?} {b:?}"
        );
    };
    close(covering_arc(&mut [(0.1, 0.1), (0.15, 0.1)]), (0.1, 0.15));
    // Wrapping around 0.
    close(covering_arc(&mut [(0.9, 0.15), (0.02, 0.05)]), (0.9, 0.17));
    // Two clusters: the larger gap is excluded.
    close(covering_arc(&mut [(0.1, 0.05), (0.5, 0.05)]), (0.1, 0.45));
    assert!(covering_arc(&mut [(0.0, 0.5), (0.5, 0.5)]).is_none());
    assert!(covering_arc(&mut []).is_none());
}

/// Every direction that hits lies in the box, for every default scene,
/// the fixed axis and random axes (a deterministic check that the box
/// is conservative), and the boxes are not trivially the whole sphere.
#[test]
fn angular_box_contains_every_hit_direction() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let extra = |name: &str, mesh: TriangleMesh| Scene {
        name: name.into(),
        description: String::new(),
        mesh,
        viewpoint: Vec3::zero(),
    };
    let tri = |a, b, c| TriangleMesh::open(vec![a, b, c], vec![[0, 1, 2]]).unwrap();
    let mut scenes = default_scenes().unwrap();
    scenes.extend([
        // Edges on meridian planes (y = 0, constant azimuth).
        extra(
            "axis-aligned octahedron",
            TriangleMesh::octahedron(v(3.0, 0.0, 0.0), 0.5).unwrap(),
        ),
        // An edge through the south pole.
        extra(
            "edge through pole",
            tri(v(1.0, 0.0, -1.0), v(-1.0, 0.0, -1.0), v(0.0, 1.0, -1.0)),
        ),
        // Near the north pole, not containing it, edges passing close.
        extra(
            "near pole",
            tri(v(0.01, 0.001, 1.0), v(-0.01, 0.002, 1.0), v(0.0, 0.02, 1.0)),
        ),
    ]);
    for sc in scenes {
        let g = Geometry::new(&sc.mesh, &sc.viewpoint).unwrap();
        let mut spheres = vec![Sphere::<f64>::new()];
        for _ in 0..6 {
            spheres.push(Sphere::with_random_axis(&mut rng));
        }
        // Axes pointing at a vertex and through the object.
        spheres.push(Sphere::with_axis(g.dirs[0]).unwrap());
        spheres.push(Sphere::with_axis(g.dirs[0].neg()).unwrap());
        for sphere in &spheres {
            let bx = g.angular_box(sphere, pad_for::<f64>());
            assert!(bx.fraction() < 0.6, "{}: {bx:?}", sc.name);
            // Hitting directions: aim at random points of random faces.
            for _ in 0..2000 {
                let f = g.faces[rng.random_range(0..g.faces.len())];
                let (mut a, mut b): (f64, f64) = (rng.random(), rng.random());
                if a + b > 1.0 {
                    (a, b) = (1.0 - a, 1.0 - b);
                }
                let vs = sc.mesh.vertices();
                let p = vs[f[0]]
                    .add(&vs[f[1]].sub(&vs[f[0]]).scale(&a))
                    .add(&vs[f[2]].sub(&vs[f[0]]).scale(&b));
                let d = p.sub(&sc.viewpoint).normalized().unwrap();
                let [u, vv] = sphere.inverse(&d).unwrap();
                assert!(bx.contains(u, vv), "{}: {u} {vv} {bx:?}", sc.name);
            }
        }
    }
}

fn estimates(sc: &Scene, m: Method, n: usize, seeds: u64) -> Vec<f64> {
    let g = Geometry::new(&sc.mesh, &sc.viewpoint).unwrap();
    (0..seeds)
        .map(|s| estimate_with(&g, &m, n, 1000 + s).unwrap().0)
        .collect()
}

fn method(sampling: Sampling, axis: AxisMode, precision: Precision, bounding_box: bool) -> Method {
    Method {
        sampling,
        axis,
        precision,
        bounding_box,
    }
}

#[test]
fn stratified_converges_and_beats_random() {
    let sc = scene("tetrahedron");
    let omega: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
    let g = Geometry::new(&sc.mesh, &sc.viewpoint).unwrap();
    let area = g.angular_box(&Sphere::new(), pad_for::<f64>()).measure();
    let p = omega / area;
    let n = 4096;
    let sigma_random = area * (p * (1.0 - p) / n as f64).sqrt();
    let strat = estimates(
        &sc,
        method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, true),
        n,
        12,
    );
    let rand = estimates(
        &sc,
        method(Sampling::Random, AxisMode::Fixed, Precision::F64, true),
        n,
        12,
    );
    for e in &strat {
        assert!(
            (e - omega).abs() <= 3.0 * sigma_random,
            "{e} vs {omega} (σ {sigma_random})"
        );
    }
    let rms =
        |v: &[f64]| (v.iter().map(|e| (e - omega).powi(2)).sum::<f64>() / v.len() as f64).sqrt();
    let (rs, rr) = (rms(&strat), rms(&rand));
    // Plain random sampling matches its predicted standard deviation.
    assert!(
        rr > 0.4 * sigma_random && rr < 2.0 * sigma_random,
        "{rr} vs {sigma_random}"
    );
    assert!(rs < rr / 3.0, "stratified {rs} vs random {rr}");
}

/// The box and the whole sphere estimate the same Ω (both unbiased),
/// also with random axes, in f64 and f32 (away from the pole).
#[test]
fn bounding_box_same_expectation_as_full_sphere() {
    let sc = scene("tetrahedron");
    let omega: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
    let stats = |v: &[f64]| {
        let k = v.len() as f64;
        let mean = v.iter().sum::<f64>() / k;
        let se = (v.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0) / k).sqrt();
        (mean, se)
    };
    let use_ = [
        method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, true),
        method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, false),
        method(Sampling::Random, AxisMode::Fixed, Precision::F64, false),
        method(Sampling::Stratified, AxisMode::Random, Precision::F64, true),
        method(Sampling::Random, AxisMode::Random, Precision::F64, true),
        method(Sampling::Stratified, AxisMode::Random, Precision::F32, true),
    ];
    let (box_mean, box_se) = stats(&estimates(&sc, use_[0], 1024, 24));
    for m in use_ {
        let (mean, se) = stats(&estimates(&sc, m, 1024, 24));
        assert!(
            (mean - omega).abs() <= 4.0 * se + 1e-12,
            "{}: {mean} ± {se} vs {omega}",
            m.name()
        );
        let joint = (se * se + box_se * box_se).sqrt();
        assert!(
            (mean - box_mean).abs() <= 4.0 * joint,
            "{}: {mean} vs box {box_mean}",
            m.name()
        );
    }
}

/// Shao–Badler's remark 3 in numbers: seen straight down the fixed
/// axis, a millimetre-sized object lies where `f32` heights are
/// quantized (`u` spaced by `2^-24` near 1: a handful of levels across
/// the object), and the `f32` estimate is biased by percents; with random
/// axes the object is almost surely far from the poles and the `f32`
/// estimate is unbiased. The `f64` map is unbiased either way.
#[test]
fn f32_fixed_axis_biased_at_south_pole_random_axes_not() {
    let sc = scene("speck");
    let omega: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
    let bias = |m: Method| {
        let v: Vec<f64> = estimates(&sc, m, 65536, 6)
            .iter()
            .map(|e| e / omega - 1.0)
            .collect();
        let k = v.len() as f64;
        let mean = v.iter().sum::<f64>() / k;
        let se = (v.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0) / k).sqrt();
        (mean, se)
    };
    let (b, se) = bias(method(
        Sampling::Stratified,
        AxisMode::Fixed,
        Precision::F32,
        true,
    ));
    assert!(b < -0.01 && b < -5.0 * se, "f32 fixed axis: {b} ± {se}");
    for m in [
        method(Sampling::Stratified, AxisMode::Random, Precision::F32, true),
        method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, true),
    ] {
        let (b, se) = bias(m);
        assert!(b.abs() < 4.0 * se + 1e-3, "{}: {b} ± {se}", m.name());
    }
}

#[test]
fn f32_error_concentrates_at_south_pole() {
    let mut c = tiny_config();
    c.profile_points = 8;
    let profile = pole_profile(&c).unwrap();
    let at = |k: i32| profile.iter().find(|r| r.log2_distance == -k).unwrap();
    // 1 − u ≈ 2^-20: u is rounded to 2^-25 absolute, z to 2^-24,
    // the angle by 2^-24 / sin θ ≈ 2^-24 · 2^9 → hundreds of units.
    assert!(at(20).south_end_to_end > 100.0, "{:?}", at(20));
    assert!(at(4).south_end_to_end < 16.0, "{:?}", at(4));
    for r in &profile {
        assert!(r.north_end_to_end < 4.0, "{r:?}");
        assert!(
            r.north_evaluation < 4.0 && r.south_evaluation < 4.0,
            "{r:?}"
        );
    }
    c.heat_map_cells = 64;
    c.heat_map_points = 2;
    let m = f32_map(&c).unwrap();
    let col = |i: usize| {
        (0..m.rows)
            .map(|j| m.end_to_end_ulps[j * m.cols + i])
            .fold(0.0, f64::max)
    };
    let middle = (m.cols / 4..3 * m.cols / 4).map(col).fold(0.0, f64::max);
    assert!(
        col(m.cols - 1) > 4.0 * middle,
        "{} {middle}",
        col(m.cols - 1)
    );
    assert!(middle < 4.0, "{middle}");
    assert!(col(0) < 4.0);
}

#[test]
fn run_identical_with_one_and_two_threads() {
    let c = tiny_config();
    let go = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&c).unwrap())
    };
    let (a, b) = (go(1), go(2));
    assert_eq!(a.scenes, b.scenes);
    assert_eq!(a.rows, b.rows);
    assert_eq!(a.f32_map, b.f32_map);
    assert_eq!(a.pole_profile, b.pole_profile);
    assert_eq!(a.axis_spread, b.axis_spread);
    assert_eq!(a.demo_points, b.demo_points);
    assert_eq!(a, b);
    assert_eq!(a.rows.len(), 3 * 7 * 3);
    // And a different seed changes the estimates.
    let mut c2 = c.clone();
    c2.seed += 1;
    assert_ne!(run(&c2).unwrap().rows, a.rows);
}

#[test]
fn figures_and_csv_written_and_non_trivial() {
    let study = run(&tiny_config()).unwrap();
    let dir = std::env::temp_dir().join(format!("areawarp-solid-angle-{}", std::process::id()));
    let figs = study.write_figures(&dir).unwrap();
    assert_eq!(figs.len(), 7 + study.scenes.len());
    let names: Vec<String> = figs
        .iter()
        .map(|f| f.path.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, study.figure_files());
    for f in &figs {
        let check = figures::verify_figure(&f.path).unwrap();
        assert!(f.marks > 0 && f.bytes > 500, "{f:?}");
        match check.kind {
            figures::FigureKind::Svg => assert!(check.marks >= f.marks, "{f:?}"),
            figures::FigureKind::Png => assert!(check.distinct_colors > 4, "{check:?}"),
        }
    }
    // The error plots hold every method's points.
    let e = figs
        .iter()
        .find(|f| f.path.ends_with("solid_angle_error_vs_n_tetrahedron.svg"))
        .unwrap();
    assert!(e.marks >= 7 * 3);
    let csv = study.write_csv(&dir).unwrap();
    assert_eq!(csv.len(), 6);
    let errors = std::fs::read_to_string(dir.join("solid_angle_errors.csv")).unwrap();
    assert_eq!(errors.lines().count(), 1 + study.rows.len());
    let md = study.to_markdown();
    for needle in [
        "| n |",
        "slope",
        "solid_angle_f32_error_uv.svg",
        "tetrahedron",
        "south cap",
    ] {
        assert!(md.contains(needle), "{needle}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The report-size run (for `areawarp report`); prints the Markdown.
#[test]
#[ignore]
fn default_size_run() {
    let t = std::time::Instant::now();
    let study = run(&SolidAngleConfig::default()).unwrap();
    println!("{}", study.to_markdown());
    println!("elapsed {:?}", t.elapsed());
    let dir = std::path::PathBuf::from("target/solid_angle_report");
    study.write_figures(&dir).unwrap();
    study.write_csv(&dir).unwrap();
}

#[test]
fn error_ratios_carry_delta_method_intervals() {
    let study = run(&tiny_config()).expect("runs");
    let std = Method::standard();
    let (rand_box, strat_box) = (std[0], std[1]);
    for sc in &study.scenes {
        let (r, se, n) = study
            .error_ratio_interval(&sc.name, &strat_box, &rand_box)
            .expect("both measured");
        let (plain, n2) = study.error_ratio(&sc.name, &strat_box, &rand_box).unwrap();
        assert_eq!((r, n), (plain, n2));
        assert!(se > 0.0 && se.is_finite(), "{}: se {se}", sc.name);
        // The delta method: se(r)/r from the two rows' relative errors.
        let (a, b) = (
            study.row(&sc.name, &strat_box, n).unwrap(),
            study.row(&sc.name, &rand_box, n).unwrap(),
        );
        let rel = ((a.rms_std_error / a.rms_relative_error).powi(2)
            + (b.rms_std_error / b.rms_relative_error).powi(2))
        .sqrt();
        assert!((se / r - rel).abs() <= 1e-12 * rel);
        // The standard error of an RMS is below the RMS itself for 4
        // estimates only if the squared errors are not all in one.
        assert!(a.rms_std_error >= 0.0 && b.rms_std_error > 0.0);
    }
    let md = study.to_markdown();
    assert!(md.contains("[95%: "), "findings carry intervals");
}
