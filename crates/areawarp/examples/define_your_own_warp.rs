//! Define your own warp by its parametrization alone: uniform sampling of a
//! spherical cap, the cone of directions within an angle θ_max of +z.
//!
//! Only step 1 of Arvo's recipe is written — φ(s, t), its chart φ⁻¹, and how
//! to rebuild it at another precision. The framework derives the rest: σ by
//! dual numbers, the measure, F and G_s by adaptive quadrature to the
//! precision of the scalar, their inversion by safeguarded Newton — and the
//! harness proves the composed map area-preserving to 256-bit accuracy.
//! (For a weighted target, override `AreaDensity::weight`; see
//! `examples/cosine_weighted_cap.rs`.)
//!
//! ```text
//! cargo run --release -p areawarp --features mpfr --example define_your_own_warp
//! ```
//!
//! Walk-through: `docs/recipe.md`.

#[cfg(feature = "mpfr")]
use areawarp::harness::{
    extremes::extremes_grid,
    jacobian::{JacobianReport, check_jacobian},
    precision::{PrecisionReport, check_precision},
    roundtrip::{RoundTripReport, check_roundtrip},
};
use areawarp::real::{Embed, Real, convert};
use areawarp::recipe::{AreaDensity, DerivedWarp, Parametrization, WarpDefinition};
use areawarp::{Vec3, WarpError};

/// The spherical cap {p ∈ S², angle(p, +z) ≤ θ_max}, 0 < θ_max ≤ π.
#[derive(Clone, Debug)]
pub struct Cap<T> {
    theta_max: T,
}

impl<T: Real> Cap<T> {
    /// The cap of half-angle `theta_max` (radians) around +z.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a NaN or infinite angle,
    /// [`WarpError::InvalidParameter`] outside (0, π].
    pub fn new(theta_max: T) -> Result<Self, WarpError> {
        if !theta_max.is_finite() {
            return Err(WarpError::NonFinite { what: "theta_max" });
        }
        if theta_max <= T::zero() || theta_max > T::pi() {
            return Err(WarpError::InvalidParameter {
                name: "theta_max",
                expected: "0 < theta_max <= pi",
            });
        }
        Ok(Cap { theta_max })
    }
}

// Step 1: φ(s, t) = (sin θ cos 2πt, sin θ sin 2πt, cos θ), θ = s·θ_max. Generic
// over the evaluation scalar S (T, or dual numbers over T for the exact
// derivatives σ is made of); constants are built in S, never from f64 literals.
impl<T: Real> Parametrization<T> for Cap<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (sin_th, cos_th) = (S::embed(&self.theta_max) * s).sin_cos();
        let (sin_az, cos_az) = (S::pi() * &S::from_i64(2) * t).sin_cos();
        Vec3::new(sin_th.clone() * &cos_az, sin_th * &sin_az, cos_th)
    }

    /// φ⁻¹, for `Warp::inverse`: polar angle by atan2, azimuth in turns.
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let theta = p.x.hypot(&p.y).atan2(&p.z);
        let turns = p.y.atan2(&p.x) / &(T::pi() * &T::from_i64(2));
        let t = if turns < T::zero() {
            turns + &T::one()
        } else {
            turns
        };
        p.is_finite()
            .then(|| (theta / &self.theta_max, t.min(&T::one())))
    }
}

// The weight: uniform (w = 1, the default).
impl<T: Real> AreaDensity<T> for Cap<T> {}

// The same cap at any precision.
impl<T: Real> WarpDefinition<T> for Cap<T> {
    type At<S: Real> = Cap<S>;
    fn recast<S: Real>(&self) -> Result<Cap<S>, WarpError> {
        Cap::new(convert::<T, S>(&self.theta_max))
    }
    fn name(&self) -> String {
        format!("cap(theta_max={})", self.theta_max.to_f64())
    }
}

/// The derived warp: ψ(u, v) = φ(F⁻¹(u), G_s⁻¹(v)), all of it computed.
pub type CapWarp<T> = DerivedWarp<T, Cap<T>>;

/// The cap warp for `theta_max` (radians, data).
pub fn cap_warp(theta_max: f64) -> Result<CapWarp<f64>, WarpError> {
    DerivedWarp::new(Cap::new(theta_max)?)
}

/// Bounds the example (and its test) holds the warp to: the Jacobian
/// deviation at 256 bits (a correct map is near 1e-76)...
pub const JACOBIAN_BOUND: f64 = 1e-60;
/// ...the f64 map against 256 bits, in units of roundoff...
pub const PRECISION_ULPS: f64 = 16.0;
/// ...the round trip ψ⁻¹(ψ(u, v)) − (u, v) in f64 away from the pole u = 0
/// (every v maps there) and the seam v = 1 (≡ v = 0)...
pub const ROUNDTRIP_PARAM: f64 = 1e-14;
/// ...and the image error ψ(ψ⁻¹(p)) − p on the whole grid, units of roundoff.
pub const ROUNDTRIP_IMAGE_ULPS: f64 = 16.0;

#[cfg(feature = "mpfr")]
/// The harness reports for one cap.
#[derive(Debug)]
pub struct CapChecks {
    /// θ_max.
    pub theta_max: f64,
    /// Jacobian at 256 bits (dual numbers), whole grid.
    pub jacobian: JacobianReport,
    /// f64 against 256 bits, whole grid.
    pub precision: PrecisionReport,
    /// f64 round trip, whole grid (its image error is the one checked).
    pub roundtrip: RoundTripReport,
    /// f64 round trip off the pole and the seam (its parameter error is the
    /// one checked).
    pub roundtrip_interior: RoundTripReport,
}

#[cfg(feature = "mpfr")]
impl CapChecks {
    /// All checks within the example's bounds.
    pub fn passes(&self) -> bool {
        self.jacobian.passes(JACOBIAN_BOUND)
            && self.precision.passes(PRECISION_ULPS)
            && self.roundtrip.passes(1.0, ROUNDTRIP_IMAGE_ULPS)
            && self
                .roundtrip_interior
                .passes(ROUNDTRIP_PARAM, ROUNDTRIP_IMAGE_ULPS)
    }
}

#[cfg(feature = "mpfr")]
/// Runs the harness on the cap of half-angle `theta_max` over the extremes
/// grid (u, v ∈ {0, 2^-60, 1e-12, 1e-6, 1/2, 1 − 1e-6, 1 − 1e-12, 1}).
///
/// # Errors
/// An invalid angle, or a warp that cannot be rebuilt at 256 bits.
pub fn check_cap(theta_max: f64) -> Result<CapChecks, WarpError> {
    let w = cap_warp(theta_max)?;
    let grid = extremes_grid();
    let interior: Vec<(f64, f64)> = grid
        .iter()
        .copied()
        .filter(|&(u, v)| u > 0.0 && v < 1.0)
        .collect();
    Ok(CapChecks {
        theta_max,
        jacobian: check_jacobian(&w, &grid)?,
        precision: check_precision::<f64, _>(&w, &grid)?,
        roundtrip: check_roundtrip::<f64, _>(&w, &grid)?,
        roundtrip_interior: check_roundtrip::<f64, _>(&w, &interior)?,
    })
}

/// The half-angles the example checks: a narrow cone, 60°, a hemisphere,
/// two wide caps, and the whole sphere (θ_max = π, where the antipode is a
/// second pole: the derived inversion works from the far end there).
pub const THETAS: [f64; 6] = [
    0.05,
    std::f64::consts::FRAC_PI_3,
    std::f64::consts::FRAC_PI_2,
    2.5,
    3.0,
    std::f64::consts::PI,
];

#[cfg(feature = "mpfr")]
fn main() {
    use areawarp::Warp;
    // A few samples first: the warp is an ordinary `Warp<f64>`.
    let w = cap_warp(std::f64::consts::FRAC_PI_3).expect("valid angle");
    println!("cap of half-angle 60°: area {:.15} (= π)", w.measure());
    for (u, v) in [(0.0, 0.0), (0.25, 0.5), (0.5, 0.125), (1.0, 0.75)] {
        let p = w.map(&u, &v);
        println!(
            "  ψ({u}, {v}) = ({:+.6}, {:+.6}, {:+.6}), z ≥ cos 60° = 0.5",
            p.x, p.y, p.z
        );
    }

    let mut ok = true;
    for theta in THETAS {
        let c = match check_cap(theta) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("theta_max = {theta}: {e}");
                std::process::exit(2);
            }
        };
        println!("\ntheta_max = {theta}");
        println!(
            "  Jacobian (256-bit duals): max |J·pdf − 1| = {:.3e} over {} points ({} nudged off singular edges, {} non-finite)  [bound {JACOBIAN_BOUND:e}]",
            c.jacobian.max_rel_deviation,
            c.jacobian.points,
            c.jacobian.nudged,
            c.jacobian.non_finite
        );
        println!(
            "  f64 precision vs 256 bits: max {:.2} ulps, median {:.2} ulps, {} NaN/Inf, {} outside  [bound {PRECISION_ULPS}]",
            c.precision.max_ulps,
            c.precision.median_ulps,
            c.precision.non_finite,
            c.precision.outside
        );
        println!(
            "  f64 round trip: image error max {:.2} ulps, {} failures; parameter error off pole and seam max {:.3e} (median {:.3e})  [bounds {ROUNDTRIP_IMAGE_ULPS}, {ROUNDTRIP_PARAM:e}]",
            c.roundtrip.max_image_ulps,
            c.roundtrip.failures,
            c.roundtrip_interior.max_error,
            c.roundtrip_interior.median_error
        );
        let pass = c.passes();
        println!("  {}", if pass { "PASS" } else { "FAIL" });
        ok &= pass;
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
