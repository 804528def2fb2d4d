//! A warp nobody ships, derived: directions in a spherical cap (the cone
//! subtended by a spherical light) distributed by *projected* solid angle
//! about the surface normal +z — w(p) = cos θ = p·z — for a cap whose axis
//! is tilted by β from the normal. Renderers sample the cone uniformly and
//! weight by cos θ afterwards; this samples cos θ exactly, with a density
//! that is not uniform in the azimuth about the cap's axis, so the
//! conditional G_s is a genuine function of s and t.
//!
//! φ, its chart and the weight are all that is written (a screenful); the
//! measure must come out as the cap's projected solid angle
//! π sin²θ_max cos β, which the example checks, with the harness (dual
//! numbers, round trip; at 256 bits with `--256`) and a tabulated fast
//! variant.
//!
//! ```text
//! cargo run --release -p areawarp --features mpfr --example cosine_weighted_cap [-- --256]
//! ```

use areawarp::real::{Embed, Real, convert};
use areawarp::recipe::{AreaDensity, DerivedWarp, Parametrization, WarpDefinition};
use areawarp::{Vec3, WarpError};

/// The cap of half-angle θ_max about the axis a = (sin β, 0, cos β),
/// weighted by cos θ = p_z; it must lie above the horizon, β + θ_max < π/2.
#[derive(Clone, Debug)]
pub struct CosineCap<T> {
    theta_max: T,
    beta: T,
    /// The frame (e1, e2, a) of the cap's axis.
    e1: Vec3<T>,
    e2: Vec3<T>,
    axis: Vec3<T>,
}

impl<T: Real> CosineCap<T> {
    /// The cap of half-angle `theta_max` tilted by `beta` (radians).
    ///
    /// # Errors
    /// [`WarpError::NonFinite`]; [`WarpError::InvalidParameter`] unless
    /// θ_max > 0, β ≥ 0 and β + θ_max < π/2 (wholly above the horizon, where
    /// the weight cos θ is smooth and positive).
    pub fn new(theta_max: T, beta: T) -> Result<Self, WarpError> {
        if !theta_max.is_finite() || !beta.is_finite() {
            return Err(WarpError::NonFinite { what: "cap angles" });
        }
        let above = theta_max.clone() + &beta < T::pi() / &T::from_i64(2);
        if !(theta_max > T::zero() && beta >= T::zero() && above) {
            return Err(WarpError::InvalidParameter {
                name: "theta_max, beta",
                expected: "theta_max > 0, beta >= 0, beta + theta_max < pi/2",
            });
        }
        let (sb, cb) = beta.sin_cos();
        Ok(CosineCap {
            e1: Vec3::new(cb.clone(), T::zero(), -sb.clone()),
            e2: Vec3::new(T::zero(), T::one(), T::zero()),
            axis: Vec3::new(sb, T::zero(), cb),
            theta_max,
            beta,
        })
    }
}

// Step 1: polar coordinates about the cap's axis, θ = s·θ_max, azimuth 2πt.
impl<T: Real> Parametrization<T> for CosineCap<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (sin_th, cos_th) = (S::embed(&self.theta_max) * s).sin_cos();
        let (sin_az, cos_az) = (S::pi() * &S::from_i64(2) * t).sin_cos();
        let (x, y) = (sin_th.clone() * &cos_az, sin_th * &sin_az);
        let along = |e: &Vec3<T>| Vec3::new(S::embed(&e.x), S::embed(&e.y), S::embed(&e.z));
        let (e1, e2, a) = (along(&self.e1), along(&self.e2), along(&self.axis));
        e1.scale(&x).add(&e2.scale(&y)).add(&a.scale(&cos_th))
    }

    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let (x, y, z) = (p.dot(&self.e1), p.dot(&self.e2), p.dot(&self.axis));
        let theta = x.hypot(&y).atan2(&z);
        let turns = y.atan2(&x) / &(T::pi() * &T::from_i64(2));
        let t = if turns < T::zero() {
            turns + &T::one()
        } else {
            turns
        };
        p.is_finite()
            .then(|| (theta / &self.theta_max, t.min(&T::one())))
    }
}

// The weight: cos θ about the normal +z.
impl<T: Real> AreaDensity<T> for CosineCap<T> {
    fn weight(&self, p: &Vec3<T>) -> T {
        p.z.max(&T::zero())
    }
}

impl<T: Real> WarpDefinition<T> for CosineCap<T> {
    type At<S: Real> = CosineCap<S>;
    fn recast<S: Real>(&self) -> Result<CosineCap<S>, WarpError> {
        CosineCap::new(convert(&self.theta_max), convert(&self.beta))
    }
    fn name(&self) -> String {
        let (th, b) = (self.theta_max.to_f64(), self.beta.to_f64());
        format!("cosine-cap(theta_max={th}, beta={b})")
    }
}

/// The projected solid angle of the cap, π sin²θ_max cos β: what the
/// derived measure must equal.
pub fn projected_solid_angle(theta_max: f64, beta: f64) -> f64 {
    std::f64::consts::PI * theta_max.sin().powi(2) * beta.cos()
}

/// The derived warp.
pub fn cosine_cap_warp(
    theta_max: f64,
    beta: f64,
) -> Result<DerivedWarp<f64, CosineCap<f64>>, WarpError> {
    DerivedWarp::new(CosineCap::new(theta_max, beta)?)
}

/// The caps the example checks: (θ_max, β).
pub const CAPS: [(f64, f64); 4] = [(0.05, 1.2), (0.3, 0.6), (0.7, 0.8), (1.2, 0.3)];

/// What the example measures for one cap in `f64` (seconds).
#[derive(Debug)]
pub struct QuickChecks {
    /// |m / (π sin²θ_max cos β) − 1|.
    pub measure_error: f64,
    /// t-panels of the conditional (more than one: G_s is not uniform).
    pub t_panels: usize,
    /// max |J·pdf − 1| with f64 dual numbers.
    pub jacobian_f64: f64,
    /// Round trip: image error (ulps) and failures.
    pub roundtrip: (f64, usize),
    /// Cells of the table of G⁻¹ at 1e-9, and its measured error against
    /// the derived warp in f64.
    pub table: (usize, f64),
}

/// The f64 checks of one cap.
///
/// # Errors
/// An invalid cap.
pub fn quick_checks(theta_max: f64, beta: f64) -> Result<QuickChecks, WarpError> {
    use areawarp::harness::extremes::{extremes_grid, random_points};
    use areawarp::harness::{jacobian::check_jacobian_in, roundtrip::check_roundtrip};
    use areawarp::recipe::TabulatedWarp;
    use areawarp::recipe::tabulated::measure_error;
    let w = cosine_cap_warp(theta_max, beta)?;
    let grid = extremes_grid();
    let jac = check_jacobian_in::<f64, _>(&w, &grid)?;
    let rt = check_roundtrip::<f64, _>(&w, &grid)?;
    let table = TabulatedWarp::new(&w, 1e-9)?;
    let mut pts = grid.clone();
    pts.extend(random_points(200, 7));
    let m = measure_error(&table, &w, &pts);
    Ok(QuickChecks {
        measure_error: (areawarp::Warp::measure(&w) / projected_solid_angle(theta_max, beta) - 1.0)
            .abs(),
        t_panels: w.recipe().report().t_panels,
        jacobian_f64: jac.max_rel_deviation,
        roundtrip: (rt.max_image_ulps, rt.failures),
        table: (table.report().conditional_cells, m.inverse()),
    })
}

#[cfg(feature = "mpfr")]
fn main() {
    use areawarp::harness::{
        extremes::extremes_grid, jacobian::check_jacobian, precision::check_precision,
    };
    let full = std::env::args().any(|a| a == "--256");
    let mut ok = true;
    for (theta_max, beta) in CAPS {
        let c = quick_checks(theta_max, beta).expect("valid cap");
        println!("\ncap theta_max = {theta_max}, beta = {beta}: {c:?}");
        let pass = c.measure_error < 1e-13
            && c.jacobian_f64 < 1e-12
            && c.roundtrip.0 <= 16.0
            && c.roundtrip.1 == 0
            && c.table.1 <= 1e-9;
        ok &= pass;
        if full {
            // Every evaluation of σ at 256 bits costs ~0.1 ms, and the
            // conditional needs ~10⁵ of them: minutes per cap.
            let w = cosine_cap_warp(theta_max, beta).expect("valid cap");
            let grid = extremes_grid();
            let jac = check_jacobian(&w, &grid).expect("256 bits");
            let prec = check_precision::<f64, _>(&w, &grid).expect("256 bits");
            println!(
                "  256 bits: max |J*pdf - 1| = {:.2e} ({} nudged); f64 vs 256 bits: {:.2} ulps",
                jac.max_rel_deviation, jac.nudged, prec.max_ulps
            );
            ok &= jac.passes(1e-60) && prec.passes(16.0);
        }
        println!("  {}", if ok { "PASS" } else { "FAIL" });
    }
    if !full {
        println!(
            "\n(run with --256 for the Jacobian and the precision at 256 bits: minutes per cap)"
        );
    }
    if !ok {
        eprintln!("some check failed");
        std::process::exit(1);
    }
}

#[cfg(not(feature = "mpfr"))]
fn main() {
    eprintln!("this example checks the warp at 256 bits: build with the `mpfr` feature");
    std::process::exit(1);
}
