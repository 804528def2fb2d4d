//! Lambertian and (modified) Phong reflectance.

use areawarp::error::WarpError;
use areawarp::vector::Vec3;
use core::f64::consts::PI;

/// A BRDF `f_r(ω_i, ω_o)` at a receiver (directions point away from the
/// surface: `ω_i` toward the light, `ω_o` toward the viewer).
///
/// - Lambertian: `f_r = ρ / π`.
/// - Phong, in the energy-conserving modified form (Lafortune and Willems
///   1994): `f_r = k_d / π + k_s (n + 2)/(2π) · cos^n α`, with `α` the angle
///   between `ω_i` and the mirror direction `r = 2 (N·ω_o) N − ω_o` of the
///   outgoing direction (`cos α` clamped at 0), `k_d + k_s ≤ 1`.
///
/// Both are 0 when `ω_i` or `ω_o` is below the surface. The reflected
/// radiance is `L_o = ∫ L_i f_r cos⁺θ_i dω_i`; for a Lambertian receiver it
/// is `(ρ/π) E`, which Lambert's formula gives exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reflectance {
    /// Diffuse reflection with albedo `ρ ∈ [0, 1]`.
    Lambertian {
        /// The albedo ρ.
        albedo: f64,
    },
    /// Modified Phong: diffuse `k_d`, specular `k_s` (`k_d, k_s ≥ 0`,
    /// `k_d + k_s ≤ 1`) and exponent `n ≥ 0`.
    Phong {
        /// The diffuse coefficient `k_d`.
        diffuse: f64,
        /// The specular coefficient `k_s`.
        specular: f64,
        /// The exponent `n`.
        exponent: f64,
    },
}

fn unit_interval(x: f64, name: &'static str) -> Result<(), WarpError> {
    if !x.is_finite() {
        return Err(WarpError::NonFinite { what: name });
    }
    if !(0.0..=1.0).contains(&x) {
        return Err(WarpError::InvalidParameter {
            name,
            expected: "a number in [0, 1]",
        });
    }
    Ok(())
}

impl Reflectance {
    /// A Lambertian BRDF.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] / [`WarpError::NonFinite`] unless
    /// `0 ≤ albedo ≤ 1`.
    pub fn lambertian(albedo: f64) -> Result<Self, WarpError> {
        unit_interval(albedo, "albedo")?;
        Ok(Reflectance::Lambertian { albedo })
    }

    /// A modified Phong BRDF.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] / [`WarpError::NonFinite`] unless
    /// `k_d, k_s ∈ [0, 1]`, `k_d + k_s ≤ 1` and `n ≥ 0` is finite.
    pub fn phong(diffuse: f64, specular: f64, exponent: f64) -> Result<Self, WarpError> {
        unit_interval(diffuse, "diffuse coefficient")?;
        unit_interval(specular, "specular coefficient")?;
        if diffuse + specular > 1.0 {
            return Err(WarpError::InvalidParameter {
                name: "diffuse + specular",
                expected: "k_d + k_s <= 1 (energy conservation)",
            });
        }
        if !exponent.is_finite() {
            return Err(WarpError::NonFinite {
                what: "Phong exponent",
            });
        }
        if exponent < 0.0 {
            return Err(WarpError::InvalidParameter {
                name: "Phong exponent",
                expected: "an exponent >= 0",
            });
        }
        Ok(Reflectance::Phong {
            diffuse,
            specular,
            exponent,
        })
    }

    /// The mirror direction `r = 2 (N·ω_o) N − ω_o` (unit `normal` and
    /// `outgoing`).
    pub fn mirror(normal: &Vec3<f64>, outgoing: &Vec3<f64>) -> Vec3<f64> {
        normal.scale(&(2.0 * normal.dot(outgoing))).sub(outgoing)
    }

    /// `f_r(ω_i, ω_o)` at a surface with unit `normal`, for unit
    /// `incoming` (toward the light) and `outgoing` (toward the viewer).
    pub fn brdf(&self, normal: &Vec3<f64>, incoming: &Vec3<f64>, outgoing: &Vec3<f64>) -> f64 {
        if normal.dot(incoming) <= 0.0 || normal.dot(outgoing) <= 0.0 {
            return 0.0;
        }
        match *self {
            Reflectance::Lambertian { albedo } => albedo / PI,
            Reflectance::Phong {
                diffuse,
                specular,
                exponent,
            } => {
                let cos_alpha = Self::mirror(normal, outgoing).dot(incoming).max(0.0);
                diffuse / PI + specular * (exponent + 2.0) / (2.0 * PI) * cos_alpha.powf(exponent)
            }
        }
    }
}
