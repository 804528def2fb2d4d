//! Uniform sampling of a spherical lune, the intersection of the two
//! hemispheres `{n₁·p ≥ 0}` and `{n₂·p ≥ 0}`: Archimedes' `z = 1 − 2u`
//! along the lune's edge line and the azimuth `Δ·v` across it.
//! Derivation: `docs/spherical-lune.md`.

use super::local_frame::{off_unit_sphere, unit_vector};
use super::turns::{clamp_unit, positive};
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// Uniform directions (in solid angle) in the spherical lune
/// `L = {|p| = 1, n₁·p ≥ 0, n₂·p ≥ 0}` bounded by the great circles with
/// normals `n₁`, `n₂` (Mitsuba's `square_to_uniform_spherical_lune`, defined
/// here from the two normals directly).
///
/// The circles meet at `±a`, `a = n₁ × n₂/|n₁ × n₂|`; the lune's dihedral
/// angle is `Δ = π − ∠(n₁, n₂) = atan2(|n₁ × n₂|, −n₁·n₂)` and its solid
/// angle `2Δ`. In the right-handed frame `(e₁, n₁, −a)` with
/// `e₁ = a × n₁` (the edge on the first circle),
///
/// ψ(u, v) = (sin θ cos Δv, sin θ sin Δv, 1 − 2u),  sin θ = 2√(u(1 − u)),
///
/// so `v = 0` is the edge on circle 1 and `v = 1` the edge on circle 2
/// (`n₂·ψ = sin θ sin(∠(n₁,n₂) + Δv) = 0`), `u = 0` and `u = 1` the
/// vertices `−a` and `a`. With `n₁ = (0, 1, 0)`, `n₂ = (−sin Δ, −cos Δ, 0)`
/// … the lune is the wedge `0 ≤ φ ≤ Δ` about the `z` axis.
///
/// Numerics: `sin θ = 2√(u(1 − u))` (no cancellation at either vertex);
/// the frame is built once, `e₁` as a cross product of unit vectors.
///
/// # Density
/// `1/(2Δ)` per steradian on the lune (0 outside), `measure() = 2Δ`.
///
/// # Example
/// ```
/// use areawarp::shapes::SphericalLune;
/// use areawarp::{Vec3, Warp};
///
/// // The quarter of the sphere with y ≥ 0 and x ≥ 0.
/// let lune = SphericalLune::new(Vec3::new(0.0, 1.0, 0.0f64), Vec3::new(1.0, 0.0, 0.0)).unwrap();
/// assert!((lune.measure() - std::f64::consts::PI).abs() < 1e-15);
/// let p = lune.map(&0.3, &0.4);
/// assert!(p.x >= 0.0 && p.y >= 0.0 && (p.norm() - 1.0).abs() < 1e-15);
/// let [u, v] = lune.inverse(&p).unwrap();
/// assert!((u - 0.3).abs() < 1e-15 && (v - 0.4).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct SphericalLune<T> {
    n1: Vec3<T>,
    n2: Vec3<T>,
    e1: Vec3<T>,
    /// −a: the local `z` axis.
    axis: Vec3<T>,
    delta: T,
    measure: T,
    inv_measure: T,
}

impl<T: Real> SphericalLune<T> {
    /// The lune `{n₁·p ≥ 0, n₂·p ≥ 0}` (normals of any non-zero length).
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for NaN/∞ normals; [`WarpError::Degenerate`]
    /// for a zero normal, or normals parallel or antiparallel within
    /// `|n̂₁ × n̂₂| ≤ 256·u` (a hemisphere or a great circle: no lune).
    ///
    /// # Density
    /// `1/(2Δ)` per steradian.
    pub fn new(n1: Vec3<T>, n2: Vec3<T>) -> Result<Self, WarpError> {
        for (n, what) in [(&n1, "lune normal n1"), (&n2, "lune normal n2")] {
            if !n.is_finite() {
                return Err(WarpError::NonFinite { what });
            }
        }
        let a1 = unit_vector(&n1).ok_or(WarpError::Degenerate {
            what: "lune normal n1 is zero",
        })?;
        let a2 = unit_vector(&n2).ok_or(WarpError::Degenerate {
            what: "lune normal n2 is zero",
        })?;
        let cross = a1.cross(&a2);
        let s = cross.norm();
        if !(s > T::from_i64(256) * T::unit_roundoff()) {
            return Err(WarpError::Degenerate {
                what: "lune normals are parallel or antiparallel",
            });
        }
        let a = cross.scale(&(T::one() / &s));
        let e1 = unit_vector(&a.cross(&a1)).ok_or(WarpError::Degenerate { what: "lune frame" })?;
        let c = a1.dot(&a2);
        let delta = s.atan2(&-c);
        let measure = delta.clone() * &T::from_i64(2);
        if !positive(&measure) {
            return Err(WarpError::Degenerate {
                what: "lune of zero angle",
            });
        }
        Ok(SphericalLune {
            inv_measure: T::one() / &measure,
            measure,
            delta,
            axis: a.neg(),
            e1,
            n1: a1,
            n2: a2,
        })
    }

    /// The unit normals `n̂₁`, `n̂₂`.
    pub fn normals(&self) -> (&Vec3<T>, &Vec3<T>) {
        (&self.n1, &self.n2)
    }

    /// The dihedral angle Δ.
    pub fn angle(&self) -> &T {
        &self.delta
    }

    fn to_world(&self, x: &T, y: &T, z: &T) -> Vec3<T> {
        self.e1
            .scale(x)
            .add(&self.n1.scale(y))
            .add(&self.axis.scale(z))
    }
}

impl<T: Real> Warp<T> for SphericalLune<T> {
    type Point = Vec3<T>;

    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let u = clamp_unit(u);
        let one = T::one();
        let z = one.clone() - &(u.clone() * &T::from_i64(2));
        let sin_theta = (u.clone() * &(one - &u)).sqrt() * &T::from_i64(2);
        let (s, c) = (self.delta.clone() * &clamp_unit(v)).sin_cos();
        self.to_world(&(sin_theta.clone() * &c), &(sin_theta * &s), &z)
    }

    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        self.inv_measure.clone()
    }

    fn measure(&self) -> T {
        self.measure.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let q = unit_vector(p).ok_or_else(|| InverseError::refuse(self, p))?;
        let (x, y, z) = (q.dot(&self.e1), q.dot(&self.n1), q.dot(&self.axis));
        let one = T::one();
        let two = T::from_i64(2);
        let rho2 = x.square() + &y.square();
        // As the sphere: u = ρ²/(2(1 + z)) in the north, 1 − ρ²/(2(1 − z)).
        let u = if z > T::zero() {
            rho2 / &((one.clone() + &z) * &two)
        } else {
            one.clone() - &(rho2 / &((one - &z) * &two))
        };
        let mut angle = y.atan2(&x);
        if angle < T::zero() {
            // Just outside one of the two edges: snap to the nearer one.
            let wrapped = angle.clone() + &(T::pi() * &two);
            angle = if wrapped.clone() - &self.delta < -angle {
                self.delta.clone()
            } else {
                T::zero()
            };
        }
        let v = (angle / &self.delta).min(&T::one());
        Ok([clamp_unit(&u), v])
    }

    /// `| |p| − 1 |` plus `max(0, −p̂·n₁, −p̂·n₂)` (the sine of the angle
    /// beyond the nearer bounding circle).
    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let radial = off_unit_sphere(p);
        let Some(q) = unit_vector(p) else {
            return radial;
        };
        let beyond = (-q.dot(&self.n1)).max(&-q.dot(&self.n2)).max(&T::zero());
        radial + &beyond
    }
}

impl<T: Real> WarpFamily<T> for SphericalLune<T> {
    type At<S: Real> = SphericalLune<S>;
    fn at<S: Real>(&self) -> Result<SphericalLune<S>, WarpError> {
        SphericalLune::new(self.n1.convert(), self.n2.convert())
    }
    fn name(&self) -> String {
        "spherical-lune".to_string()
    }
}

crate::warp::distribution_for_floats!(SphericalLune, Vec3);

/// Test lunes `(name, [n1, n2])`: a quarter sphere, a thin lune
/// (Δ ≈ 0.01), a nearly full hemisphere (Δ ≈ π − 0.01) and a generic one.
pub fn lune_catalogue() -> Vec<(String, [f64; 6])> {
    let (s, c) = 0.01f64.sin_cos();
    vec![
        ("generic".into(), [0.3, 0.8, -0.2, -0.6, 0.1, 0.7]),
        ("quarter".into(), [0.0, 1.0, 0.0, 1.0, 0.0, 0.0]),
        ("thin".into(), [0.0, 1.0, 0.0, -s, -c, 0.0]),
        ("wide".into(), [0.0, 1.0, 0.0, s, c, 0.0]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{AxisBins, chi2_passes, roundtrip_passes};

    fn lunes() -> Vec<(String, SphericalLune<f64>)> {
        lune_catalogue()
            .into_iter()
            .map(|(n, p)| {
                let l =
                    SphericalLune::new(Vec3::new(p[0], p[1], p[2]), Vec3::new(p[3], p[4], p[5]));
                (n, l.unwrap())
            })
            .collect()
    }

    #[test]
    fn lune_errors_angles_and_edges() {
        let y = Vec3::new(0.0, 1.0, 0.0f64);
        assert!(matches!(
            SphericalLune::new(y, y),
            Err(WarpError::Degenerate { .. })
        ));
        assert!(matches!(
            SphericalLune::new(y, y.neg()),
            Err(WarpError::Degenerate { .. })
        ));
        assert!(matches!(
            SphericalLune::new(y, Vec3::zero()),
            Err(WarpError::Degenerate { .. })
        ));
        assert!(matches!(
            SphericalLune::new(y, Vec3::new(f64::NAN, 0.0, 0.0)),
            Err(WarpError::NonFinite { .. })
        ));
        let l = lunes();
        assert!((l[2].1.angle() - 0.01).abs() < 1e-15);
        assert!((l[3].1.angle() - (std::f64::consts::PI - 0.01)).abs() < 1e-14);
        for (name, w) in &l {
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = w.map(&u, &v);
                    assert!(
                        p.is_finite() && w.outside_by(&p) <= 4.0 * f64::EPSILON,
                        "{name} {u} {v}"
                    );
                }
            }
            let (n1, n2) = w.normals();
            // v = 0 on circle 1, v = 1 on circle 2.
            assert!(w.map(&0.3, &0.0).dot(n1).abs() < 1e-15, "{name}");
            assert!(w.map(&0.3, &1.0).dot(n2).abs() < 1e-15, "{name}");
        }
    }

    #[test]
    fn lune_roundtrip_and_chi2() {
        for (name, w) in lunes() {
            roundtrip_passes::<f64, _>(&format!("spherical-lune {name}"), &w, 8.0);
            roundtrip_passes::<f32, _>(&format!("spherical-lune {name}"), &w, 8.0);
            let e2 = w.axis.cross(&w.e1);
            let bins = AxisBins::new(
                [w.e1, e2, w.axis],
                (0..=10).map(|i| 0.2 * i as f64).collect(),
                w.delta,
                8,
                |_| 1.0 / w.measure(),
            );
            chi2_passes(&format!("spherical-lune {name}"), &w, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn lune_harness_at_extremes() {
        for (name, w) in lunes() {
            crate::shapes::test_support::harness_passes(&format!("spherical-lune {name}"), &w, 4.0);
        }
    }
}
