//! Derived warps (φ and w only; σ, F, G_s and their inverses computed):
//! exactly area-preserving at 256 bits, and as accurate in `f64` as the
//! closed forms of the same maps (issue 12, "What it must show", item 1).
//!
//! ```text
//! cargo test -p areawarp --features mpfr --release --test derived_recipe -- --include-ignored --nocapture
//! ```
//!
//! The speed of the derived warps beside the closed forms is measured by
//! `cargo bench -p areawarp --bench derived_recipe -- derived/`.
#![cfg(feature = "mpfr")]

use areawarp::harness::extremes::{extremes_grid, random_points};
use areawarp::harness::jacobian::check_jacobian;
use areawarp::harness::roundtrip::check_roundtrip;
use areawarp::real::{Embed, Mpfr256, Real};
use areawarp::recipe::definitions::{
    Beckmann, Cap, Disk, Ggx, Hemisphere, Phong, Sphere, VonMisesFisher,
};
use areawarp::recipe::{
    AreaDensity, DerivedRecipe, DerivedWarp, Newton, Parametrization, RecipeWarp, WarpDefinition,
};
use areawarp::{Coords, Vec3, Warp, WarpError, WarpFamily, shapes};

/// The bound on |J·pdf − 1| at 256 bits.
const JACOBIAN_BOUND: f64 = 1e-60;
/// The bound on the derived f64 map against the closed form, in units of
/// roundoff.
const ULPS_BOUND: f64 = 16.0;

/// Distances over the extremes grid, in units of f64 roundoff (2⁻⁵³, the
/// shapes have extent 1), of max ‖·‖_∞: the derived f64 map against the
/// closed form at 256 bits, the closed form's own f64 map against it, and
/// the derived f64 map against the closed-form f64 map.
struct Distances {
    derived_vs_256: f64,
    closed_vs_256: f64,
    derived_vs_closed: f64,
}

fn against_closed<D, C>(derived: &D, closed: &C) -> Distances
where
    D: Warp<f64>,
    C: WarpFamily<f64>,
{
    let reference = closed.at::<Mpfr256>().expect("256 bits");
    let unit = f64::EPSILON / 2.0;
    let mut d = Distances {
        derived_vs_256: 0.0,
        closed_vs_256: 0.0,
        derived_vs_closed: 0.0,
    };
    for (u, v) in extremes_grid() {
        let p = derived.map(&u, &v).to_vec3();
        let q = reference
            .map(&Mpfr256::from_f64(u), &Mpfr256::from_f64(v))
            .to_vec3();
        let r = closed.map(&u, &v).to_vec3();
        let (pm, rm): (Vec3<Mpfr256>, Vec3<Mpfr256>) = (p.convert(), r.convert());
        d.derived_vs_256 = d.derived_vs_256.max(pm.sub(&q).max_abs().to_f64() / unit);
        d.closed_vs_256 = d.closed_vs_256.max(rm.sub(&q).max_abs().to_f64() / unit);
        d.derived_vs_closed = d.derived_vs_closed.max(p.sub(&r).max_abs() / unit);
    }
    d
}

/// One derived warp checked: Jacobian at 256 bits (if `jacobian`) and f64
/// against the closed form; prints a table row.
fn check<P, C>(name: &str, def: P, closed: C, jacobian: bool)
where
    P: WarpDefinition<f64>,
    C: WarpFamily<f64>,
{
    let derived = DerivedWarp::new(def).expect("derivable");
    let r = derived.recipe().report();
    let d = against_closed(&derived, &closed);
    let start = std::time::Instant::now();
    let jac = jacobian.then(|| check_jacobian(&derived, &extremes_grid()).expect("256 bits"));
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "| {name} | {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {seconds:.1} s |",
        r.s_panels,
        r.t_panels,
        r.evaluations,
        jac.as_ref().map_or("—".to_string(), |j| format!(
            "{:.1e} ({} nudged)",
            j.max_rel_deviation, j.nudged
        )),
        d.derived_vs_256,
        d.closed_vs_256,
        d.derived_vs_closed,
    );
    assert!(
        d.derived_vs_256 <= ULPS_BOUND,
        "{name}: {} ulps against the closed form at 256 bits",
        d.derived_vs_256
    );
    assert!(
        d.derived_vs_closed <= ULPS_BOUND,
        "{name}: {} ulps against the closed form in f64",
        d.derived_vs_closed
    );
    if let Some(j) = jac {
        assert!(j.passes(JACOBIAN_BOUND), "{name}: {j:?}");
    }
}

fn header() {
    println!(
        "| warp | s-panels | t-panels | σ evaluations | max \\|J·pdf − 1\\| at 256 bits (extremes grid) | derived f64 vs closed form at 256 bits (u) | closed form f64 vs 256 bits (u) | derived f64 vs closed form f64 (u) | Jacobian check (256-bit derivation + 64 points), wall |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
}

#[test]
fn derived_warps_are_exact_and_match_the_closed_forms() {
    header();
    check(
        "hemisphere",
        Hemisphere::new(),
        shapes::Hemisphere::new(),
        true,
    );
    check("disk", Disk::new(), shapes::PolarDisk::new(), true);
    check("sphere", Sphere::new(), shapes::Sphere::new(), true);
    let cap = Cap::new(1.0).unwrap();
    let closed = DerivedWarp::new(cap.clone().with_closed_forms()).unwrap();
    check("cap θ_max = 1", cap, closed, true);
    // k = 0: the uniform lobe, whose weight 0^0 = 1 at the horizon; k = 1/2
    // and 3/2: σw ~ s^k not smooth at s = 0 (a power panel, σw/s^k
    // interpolated); k = 30, 100: F relatively accurate far below u².
    for k in [0.0, 0.5, 1.0, 1.5, 10.0, 30.0, 100.0, 1000.0] {
        let name = format!("Phong k = {k}");
        check(
            &name,
            Phong::new(k).unwrap(),
            shapes::PhongLobe::new(k).unwrap(),
            false,
        );
    }
    check(
        "GGX α = 0.5",
        Ggx::new(0.5).unwrap(),
        shapes::Ggx::new(0.5).unwrap(),
        false,
    );
    for a in [0.5, 0.2, 0.1, 0.01] {
        check(
            &format!("Beckmann α = {a}"),
            Beckmann::new(a).unwrap(),
            shapes::Beckmann::new(a).unwrap(),
            false,
        );
    }
    for k in [10.0, 100.0, 1e4] {
        check(
            &format!("vMF κ = {k:e}"),
            VonMisesFisher::new(k).unwrap(),
            shapes::VonMisesFisher::new(k).unwrap(),
            false,
        );
    }
}

/// The cap of half-angle acos(`c`) derived, against the uniform cone of
/// cos θ_max = `c` (θ_max rounded to f64 from acos(c) at 256 bits, so the
/// two caps differ by half an ulp of θ_max).
fn cap_and_cone(c: f64) -> (Cap<f64>, shapes::UniformCone<f64>) {
    let theta = Mpfr256::from_f64(c).acos().to_f64();
    (
        Cap::new(theta).unwrap(),
        shapes::UniformCone::new(c).unwrap(),
    )
}

#[test]
#[ignore = "256-bit Jacobians of every derived warp with a closed form (several minutes in release)"]
fn derived_warps_jacobians_at_256_bits() {
    header();
    check(
        "hemisphere",
        Hemisphere::new(),
        shapes::Hemisphere::new(),
        true,
    );
    check("disk", Disk::new(), shapes::PolarDisk::new(), true);
    check("sphere", Sphere::new(), shapes::Sphere::new(), true);
    for k in [1.0, 10.0, 1000.0] {
        let name = format!("Phong k = {k}");
        check(
            &name,
            Phong::new(k).unwrap(),
            shapes::PhongLobe::new(k).unwrap(),
            true,
        );
    }
    // Caps θ_max = 0.045 … π against the uniform cone (the cap's own
    // closed forms, asin(√u sin(θ_max/2)), lose up to 1e6 u near θ_max = π).
    for c in [0.999, 0.5, 0.0, -0.8, -0.99, -1.0] {
        let (cap, cone) = cap_and_cone(c);
        check(&format!("cap, cone cos θ_max = {c}"), cap, cone, true);
    }
    for a in [1.0, 0.5, 0.1, 0.01] {
        check(
            &format!("GGX α = {a}"),
            Ggx::new(a).unwrap(),
            shapes::Ggx::new(a).unwrap(),
            true,
        );
    }
}

#[test]
#[ignore = "256-bit Jacobians of the derived Beckmann distributions"]
fn derived_beckmann_jacobians_at_256_bits() {
    header();
    for a in [1.0, 0.5, 0.2, 0.1, 0.01] {
        check(
            &format!("Beckmann α = {a}"),
            Beckmann::new(a).unwrap(),
            shapes::Beckmann::new(a).unwrap(),
            true,
        );
    }
}

#[test]
#[ignore = "256-bit Jacobians of the Phong lobes served by the power panel at s = 0"]
fn derived_phong_power_jacobians_at_256_bits() {
    header();
    for k in [0.5, 1.5, 30.0, 100.0] {
        check(
            &format!("Phong k = {k}"),
            Phong::new(k).unwrap(),
            shapes::PhongLobe::new(k).unwrap(),
            true,
        );
    }
}

#[test]
#[ignore = "256-bit Jacobians of the derived von Mises–Fisher distributions"]
fn derived_vmf_jacobians_at_256_bits() {
    header();
    for k in [1e-8, 1.0, 10.0, 100.0, 1e4] {
        check(
            &format!("vMF κ = {k:e}"),
            VonMisesFisher::new(k).unwrap(),
            shapes::VonMisesFisher::new(k).unwrap(),
            true,
        );
    }
}

#[test]
fn closed_forms_override_the_derived_steps() {
    // The cap with its closed forms: the marginal and conditional inverses
    // are the formulas (no quadrature used per sample), the measure is
    // 4π sin²(θ_max/2), and the map agrees with the derived one.
    let cap = Cap::new(0.7).unwrap();
    let closed = DerivedWarp::new(cap.clone().with_closed_forms()).unwrap();
    let derived = DerivedWarp::new(cap).unwrap();
    let area = 4.0 * std::f64::consts::PI * (0.35f64).sin().powi(2);
    assert_eq!(
        closed.measure(),
        Cap::new(0.7)
            .unwrap()
            .with_closed_forms()
            .measure_closed()
            .unwrap()
    );
    assert!((derived.measure() / area - 1.0).abs() < 1e-15);
    for (u, v) in random_points(100, 5) {
        let (s, t) = closed.warp_coordinates(&u, &v);
        assert_eq!(t, v);
        let expected = 2.0 / 0.7 * (u.sqrt() * 0.35f64.sin()).asin();
        assert!((s - expected).abs() < 1e-15);
        assert!(derived.map(&u, &v).sub(&closed.map(&u, &v)).max_abs() < 1e-14);
    }
}

/// A definition whose closed-form measure is wrong by a factor 1 + 1e-9.
#[derive(Clone, Debug)]
struct WrongMeasure(Hemisphere<f64>);

impl Parametrization<f64> for WrongMeasure {
    fn phi<S: Embed<f64>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.0.phi(s, t)
    }
}
impl AreaDensity<f64> for WrongMeasure {}
impl WarpDefinition<f64> for WrongMeasure {
    type At<S: Real> = Hemisphere<S>;
    fn recast<S: Real>(&self) -> Result<Hemisphere<S>, WarpError> {
        Ok(Hemisphere::new())
    }
    fn name(&self) -> String {
        "wrong".into()
    }
    fn measure_closed(&self) -> Option<f64> {
        Some(2.0 * std::f64::consts::PI * (1.0 + 1e-9))
    }
}

/// A definition whose weight jumps across a curve: not resolvable by
/// polynomials, which the quadrature must say.
#[derive(Clone, Debug)]
struct Jump(Hemisphere<f64>);

impl Parametrization<f64> for Jump {
    fn phi<S: Embed<f64>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.0.phi(s, t)
    }
}
impl AreaDensity<f64> for Jump {
    fn weight(&self, p: &Vec3<f64>) -> f64 {
        if p.z > 0.3 { 2.0 } else { 1.0 }
    }
}
impl WarpDefinition<f64> for Jump {
    type At<S: Real> = Hemisphere<S>;
    fn recast<S: Real>(&self) -> Result<Hemisphere<S>, WarpError> {
        Ok(Hemisphere::new())
    }
    fn name(&self) -> String {
        "jump".into()
    }
}

#[test]
fn inconsistent_closed_forms_and_unresolvable_densities_are_refused() {
    assert!(matches!(
        DerivedWarp::new(WrongMeasure(Hemisphere::new())),
        Err(WarpError::Inconsistent { .. })
    ));
    assert!(matches!(
        DerivedWarp::new(Jump(Hemisphere::new())),
        Err(WarpError::NotConverged { .. })
    ));
}

#[test]
fn derived_warp_inverts_composes_and_runs_in_f32() {
    let w = DerivedWarp::new(Phong::new(10.0).unwrap()).unwrap();
    let grid = extremes_grid();
    let rt = check_roundtrip::<f64, _>(&w, &grid).unwrap();
    assert_eq!(rt.failures, 0, "{rt:?}");
    assert!(rt.max_image_ulps <= 16.0, "{rt:?}");
    // Off the shape: no inverse, zero density.
    let below = Vec3::new(0.0, 0.6, -0.8);
    assert!(w.inverse(&below).is_err());
    assert_eq!(w.pdf(&below), 0.0);
    // The derived recipe composes with the generic inverters.
    let recipe = DerivedRecipe::new(Phong::new(10.0).unwrap()).unwrap();
    let composed = RecipeWarp::new(recipe, Newton::default(), Newton::default());
    for (u, v) in random_points(20, 9) {
        let d = composed.map(&u, &v).sub(&w.map(&u, &v)).max_abs();
        assert!(d < 1e-13, "({u}, {v}): {d}");
    }
    // The same definition in f32.
    let w32 = DerivedWarp::new(Phong::<f32>::new(10.0).unwrap()).unwrap();
    for &(u, v) in &grid {
        let p = w32.map(&(u as f32), &(v as f32));
        assert!(p.is_finite() && (p.norm() - 1.0).abs() < 1e-6, "{p:?}");
        assert!(p.z >= 0.0);
    }
    let r = w32.recipe().report();
    assert!(
        r.s_tail < 1e-5 && (r.measure - 2.0 * std::f64::consts::PI / 11.0).abs() < 1e-6,
        "{r:?}"
    );
}

#[test]
fn derived_measures_are_exact_at_256_bits() {
    // m = 2π/(k + 1) for Phong, π for the disk, 4π for the sphere: the
    // quadrature at 256 bits agrees to about 2⁻²⁵⁰.
    use areawarp::recipe::MarginalConditional;
    let pi = Mpfr256::pi();
    let k = Mpfr256::from_i64(10);
    let cases: [(Mpfr256, Mpfr256); 3] = [
        (
            DerivedRecipe::new(Phong::new(k.clone()).unwrap())
                .unwrap()
                .measure(),
            pi.clone() * &Mpfr256::from_i64(2) / &(k + &Mpfr256::one()),
        ),
        (
            DerivedRecipe::new(Disk::<Mpfr256>::new())
                .unwrap()
                .measure(),
            pi.clone(),
        ),
        (
            DerivedRecipe::new(Sphere::<Mpfr256>::new())
                .unwrap()
                .measure(),
            pi * &Mpfr256::from_i64(4),
        ),
    ];
    for (m, exact) in cases {
        let rel = ((m - &exact) / &exact).abs();
        assert!(rel < Mpfr256::exp2i(-245), "{rel}");
    }
}
