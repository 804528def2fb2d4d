//! Uniform sampling of the unit sphere by Archimedes' axial projection
//! (Shao & Badler 1996): `z = 1 − 2u`, `φ = 2πv`, optionally about a
//! rotated (e.g. random) axis. Derivation: `docs/sphere.md`.

use super::local_frame::{LocalFrame, unit_vector};
use super::turns::{clamp_unit, polar_turns, positive, turns_of};
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};
use rand::{Rng, RngExt};

/// A right-handed orthonormal frame `(e1, e2, axis)` around a unit axis.
#[derive(Clone, Debug)]
struct Frame<T> {
    e1: Vec3<T>,
    e2: Vec3<T>,
    axis: Vec3<T>,
}

impl<T: Real> Frame<T> {
    /// Validates and normalizes `axis`, then completes it to a frame
    /// ([`LocalFrame::about_unit`]: Duff et al. 2017).
    fn from_axis(axis: &Vec3<T>) -> Result<Self, WarpError> {
        if !axis.is_finite() {
            return Err(WarpError::NonFinite {
                what: "sphere axis",
            });
        }
        // Scaled by the largest coordinate first: no overflow for huge and
        // no underflow for subnormal inputs.
        let a = unit_vector(axis).ok_or(WarpError::Degenerate {
            what: "sphere axis is the zero vector",
        })?;
        let LocalFrame { e1, e2, axis } = LocalFrame::about_unit(a);
        Ok(Frame { e1, e2, axis })
    }

    /// `l.x·e1 + l.y·e2 + l.z·axis`, in any scalar the frame embeds into.
    fn to_world<S: Embed<T>>(&self, l: &Vec3<S>) -> Vec3<S> {
        let col = |i: usize| {
            let (a, b, c) = match i {
                0 => (&self.e1.x, &self.e2.x, &self.axis.x),
                1 => (&self.e1.y, &self.e2.y, &self.axis.y),
                _ => (&self.e1.z, &self.e2.z, &self.axis.z),
            };
            l.x.clone() * &S::embed(a)
                + &(l.y.clone() * &S::embed(b))
                + &(l.z.clone() * &S::embed(c))
        };
        Vec3::new(col(0), col(1), col(2))
    }

    /// The coordinates of `p` in the frame.
    fn to_local(&self, p: &Vec3<T>) -> Vec3<T> {
        Vec3::new(p.dot(&self.e1), p.dot(&self.e2), p.dot(&self.axis))
    }

    fn convert<S: Real>(&self) -> Result<Frame<S>, WarpError> {
        Frame::from_axis(&self.axis.convert())
    }
}

/// `(u, v)` of a unit-sphere point in the frame's local coordinates.
fn local_inverse<T: Real>(l: &Vec3<T>, inv_two_pi: &T) -> (T, T) {
    let n = l.norm();
    let (x, y, z) = (l.x.clone() / &n, l.y.clone() / &n, l.z.clone() / &n);
    let one = T::one();
    let two = T::from_i64(2);
    // u = (1 − z)/2. In the north 1 − z = ρ²/(1 + z) keeps the relative
    // accuracy of tiny u; in the south 1 − u = (1 + z)/2 = ρ²/(2(1 − z)) is
    // computed from ρ² = x² + y², which a rotated point carries to relative
    // accuracy (its z does not), and u is rounded once from it.
    let rho2 = x.square() + &y.square();
    let u = if z > T::zero() {
        rho2 / &((one + &z) * &two)
    } else {
        one.clone() - &(rho2 / &((one - &z) * &two))
    };
    (clamp_unit(&u), turns_of(&y, &x, inv_two_pi))
}

/// Uniform points on the unit sphere by Archimedes' axial projection
/// (Shao & Badler 1996): a uniform point `(z, φ) = (1 − 2u, 2πv)` on the
/// circumscribed cylinder `[−1, 1] × [0, 2π)` is projected back onto the
/// sphere along the ray from the axis,
///
/// ψ(u, v) = (sin θ cos 2πv, sin θ sin 2πv, 1 − 2u),  sin θ = 2√(u (1 − u)),
///
/// in the frame of the cylinder axis (`+z` by default, see
/// [`Sphere::with_axis`]). `u = 0` is the north pole (the axis), `u = 1` the
/// south pole.
///
/// Numerics: `sin θ = √(1 − z²)` is computed as `2√(u(1 − u))`, which does
/// not cancel at either pole; the azimuth is reduced by quarter turns; the
/// inverse takes `u = (x² + y²)/(2(1 + z))` in the northern hemisphere. One
/// asymmetry remains and is intrinsic to the input: floating-point `u` are
/// dense near 0, so samples come arbitrarily close to the north pole, but
/// spaced by `2^-p` just below 1 (`p` = 53 in `f64`), so `1 − u ≥ 2^-p` and
/// `sin θ = 2√(u(1 − u)) ≳ 2^(1−p/2)`: no sample falls strictly inside the
/// south polar cap of angular radius `≈ 2^(1−p/2)` (≈ 2.1e-8 in `f64`,
/// ≈ 4.9e-4 in `f32`). This is the pole-concentrated truncation error Shao
/// and Badler point out (§3, remark 3); their cure is a random axis, see
/// [`Sphere::with_random_axis`].
///
/// # Density
/// Uniform in solid angle: `pdf(p) = 1/(4π)`, `measure() = 4π`.
///
/// # Example
/// ```
/// use areawarp::shapes::Sphere;
/// use areawarp::Warp;
///
/// let s = Sphere::<f64>::new();
/// let p = s.map(&0.75, &0.25);
/// assert!((p.z + 0.5).abs() < 1e-15); // z = 1 − 2u
/// assert!((p.norm() - 1.0).abs() < 1e-15);
/// assert!((s.pdf(&p) * s.measure() - 1.0).abs() < 1e-15);
/// let [u, v] = s.inverse(&p).unwrap();
/// assert!((u - 0.75).abs() < 1e-15 && (v - 0.25).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct Sphere<T> {
    frame: Option<Frame<T>>,
    half_pi: T,
    inv_two_pi: T,
    four_pi: T,
    inv_four_pi: T,
}

impl<T: Real> Sphere<T> {
    fn build(frame: Option<Frame<T>>) -> Self {
        let pi = T::pi();
        let four_pi = pi.clone() * &T::from_i64(4);
        Sphere {
            frame,
            half_pi: pi.clone() / &T::from_i64(2),
            inv_two_pi: T::one() / &(pi * &T::from_i64(2)),
            inv_four_pi: T::one() / &four_pi,
            four_pi,
        }
    }

    /// The sphere warp with the cylinder axis `+z`.
    ///
    /// # Density
    /// `1/(4π)` per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Sphere;
    /// use areawarp::Warp;
    /// let s = Sphere::<f32>::new();
    /// assert_eq!(s.map(&0.0, &0.4).z, 1.0);
    /// assert_eq!(s.map(&0.5, &0.4).z, 0.0);
    /// assert_eq!(s.map(&1.0, &0.4).z, -1.0);
    /// ```
    pub fn new() -> Self {
        Self::build(None)
    }

    /// The sphere warp with the cylinder axis along `axis` (normalized
    /// here): `ψ(0, v) = axis/|axis|`, and the azimuth is measured in a
    /// right-handed orthonormal frame `(e1, e2, axis)` completed from it.
    ///
    /// Shao and Badler (§3, remark 3) note that the truncation errors of the
    /// axial projection are not uniform over the sphere but concentrate
    /// around the two poles of the axis, and suggest a random axis per
    /// sample to spread them; for stratified sampling, stratify the axis
    /// (e.g. with a second, coarser stratified set through
    /// [`Sphere::random_axis`]'s map) and the cylinder separately.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] if a coordinate is NaN or infinite,
    /// [`WarpError::Degenerate`] for the zero vector.
    ///
    /// # Density
    /// `1/(4π)` per steradian, whatever the axis.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Sphere;
    /// use areawarp::{Vec3, Warp, WarpError};
    /// let s = Sphere::with_axis(Vec3::new(3.0f64, 0.0, 4.0)).unwrap();
    /// let north = s.map(&0.0, &0.0);
    /// assert!((north.x - 0.6).abs() < 1e-15 && (north.z - 0.8).abs() < 1e-15);
    /// assert!(matches!(Sphere::with_axis(Vec3::<f64>::zero()), Err(WarpError::Degenerate { .. })));
    /// ```
    pub fn with_axis(axis: Vec3<T>) -> Result<Self, WarpError> {
        Ok(Self::build(Some(Frame::from_axis(&axis)?)))
    }

    /// A uniformly distributed random unit vector, drawn with two `f64`
    /// uniforms from `rng` and mapped through the `+z` sphere warp; meant
    /// for [`Sphere::with_axis`] (see [`Sphere::with_random_axis`]).
    ///
    /// The uniforms have 53-bit resolution whatever `T` is.
    ///
    /// # Density
    /// Uniform on the unit sphere: `1/(4π)` per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Sphere;
    /// use rand::{SeedableRng, rngs::SmallRng};
    /// let mut rng = SmallRng::seed_from_u64(7);
    /// let a = Sphere::<f64>::random_axis(&mut rng);
    /// assert!((a.norm() - 1.0).abs() < 1e-15);
    /// ```
    pub fn random_axis<R: Rng + ?Sized>(rng: &mut R) -> Vec3<T> {
        let u: f64 = rng.random();
        let v: f64 = rng.random();
        Sphere::<T>::new().map(&T::from_f64(u), &T::from_f64(v))
    }

    /// The sphere warp about a uniformly random axis ([`Sphere::random_axis`]):
    /// Shao and Badler's remedy for the pole-concentrated truncation error of
    /// a fixed axis (§3, remark 3). Building one is cheap (a frame from one
    /// vector), so it can be done per sample or per batch of samples.
    ///
    /// # Density
    /// `1/(4π)` per steradian for every axis, so also for a random one.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Sphere;
    /// use areawarp::Warp;
    /// use rand::{SeedableRng, rngs::SmallRng};
    /// let mut rng = SmallRng::seed_from_u64(1);
    /// let s = Sphere::<f64>::with_random_axis(&mut rng);
    /// assert!((s.map(&0.0, &0.0).sub(&s.axis())).norm() < 1e-15);
    /// ```
    pub fn with_random_axis<R: Rng + ?Sized>(rng: &mut R) -> Self {
        match Frame::from_axis(&Self::random_axis(rng)) {
            Ok(frame) => Self::build(Some(frame)),
            // Unreachable (the axis is a unit vector); stay total anyway.
            Err(_) => Self::new(),
        }
    }

    /// The unit cylinder axis: `+z`, or the normalized axis given to
    /// [`Sphere::with_axis`].
    ///
    /// # Density
    /// The density does not depend on the axis.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::Sphere;
    /// use areawarp::Vec3;
    /// assert_eq!(Sphere::<f64>::new().axis(), Vec3::new(0.0, 0.0, 1.0));
    /// let a = Sphere::with_axis(Vec3::new(0.0, -2.0f64, 0.0)).unwrap().axis();
    /// assert_eq!(a, Vec3::new(0.0, -1.0, 0.0));
    /// ```
    pub fn axis(&self) -> Vec3<T> {
        match &self.frame {
            Some(f) => f.axis.clone(),
            None => Vec3::new(T::zero(), T::zero(), T::one()),
        }
    }
}

impl<T: Real> Default for Sphere<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Warp<T> for Sphere<T> {
    type Point = Vec3<T>;

    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let u = clamp_unit(u);
        let two = T::from_i64(2);
        let two_u = u * &two;
        let z = T::one() - &two_u;
        // 2√(u(1 − u)) as √(2u(2 − 2u)): the same bits (scalings by 2 and
        // 4 commute with rounding and with the square root; for a
        // subnormal u the product is exact), sharing 2u with z and without
        // a product after the root.
        let sin_theta = (two_u.clone() * &(two - &two_u)).sqrt();
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        let local = Vec3::new(x, y, z);
        match &self.frame {
            Some(f) => f.to_world(&local),
            None => local,
        }
    }

    #[inline]
    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        self.inv_four_pi.clone()
    }

    fn measure(&self) -> T {
        self.four_pi.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let (u, v) = match &self.frame {
            Some(f) => local_inverse(&f.to_local(p), &self.inv_two_pi),
            None => local_inverse(p, &self.inv_two_pi),
        };
        Ok([u, v])
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        (p.norm() - &T::one()).abs()
    }
}

crate::warp::distribution_for_floats!(Sphere, Vec3);

impl<T: Real> WarpFamily<T> for Sphere<T> {
    type At<S: Real> = Sphere<S>;
    fn at<S: Real>(&self) -> Result<Sphere<S>, WarpError> {
        Ok(match &self.frame {
            Some(f) => Sphere::build(Some(f.convert()?)),
            None => Sphere::new(),
        })
    }
    fn name(&self) -> String {
        "sphere".to_string()
    }
}

/// The recipe specification of [`Sphere`] (Shao & Badler 1996), steps 1–4,
/// with step 1 the inverse axial projection of the circumscribed cylinder:
///
/// 1. φ(s, t) = 2√(s(1 − s)) (cos 2πt · e1 + sin 2πt · e2) + (1 − 2s) · a, in
///    the frame `(e1, e2, a)` of the cylinder axis `a` (`s` the height
///    fraction `(1 − z)/2`, `t` the azimuth in turns);
/// 2. σ(s, t) = ‖φ_s × φ_t‖ = 4π: Archimedes' local theorem (the axial
///    projection preserves area), here *derived by dual numbers* and
///    checked by the unit tests rather than assumed;
/// 3. m = 4π, F(s) = s, G_s(t) = t;
/// 4. F⁻¹(u) = u, G_s⁻¹(v) = v.
///
/// The same map follows from spherical coordinates φ(s, t) = (sin πs cos 2πt,
/// sin πs sin 2πt, cos πs), σ = 2π² sin πs, F(s) = sin²(πs/2),
/// F⁻¹(u) = (2/π) arcsin √u (see `docs/sphere.md`); the cylinder coordinate is
/// used here because it is exact at *both* poles: a polar-angle `s` near 1
/// is a float whose `1 − s` (the distance to the south pole) has only
/// absolute accuracy, which would limit the recipe's Jacobian there to
/// ≈ 2^-256/θ at 256 bits, while here `1 − s = 1 − u` is exact.
///
/// # Density
/// Weight 1 (uniform): density `1/(4π)` per steradian, total measure 4π.
///
/// # Example
/// ```
/// use areawarp::recipe::{AreaDensity, ClosedForm, RecipeWarp};
/// use areawarp::shapes::{Sphere, SphereRecipe};
/// use areawarp::Warp;
///
/// let recipe = SphereRecipe::<f64>::new();
/// // Archimedes: the area density is the constant 4π.
/// let four_pi = 4.0 * std::f64::consts::PI;
/// assert!((recipe.sigma(&0.1, &0.7) - four_pi).abs() < 1e-13);
/// let spec = RecipeWarp::new(recipe, ClosedForm, ClosedForm);
/// let p = spec.map(&0.3, &0.6);
/// let q = Sphere::<f64>::new().map(&0.3, &0.6);
/// assert!(p.sub(&q).norm() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct SphereRecipe<T> {
    frame: Option<Frame<T>>,
    two_pi: T,
    inv_two_pi: T,
    four_pi: T,
}

impl<T: Real> SphereRecipe<T> {
    fn build(frame: Option<Frame<T>>) -> Self {
        let two_pi = T::pi() * &T::from_i64(2);
        SphereRecipe {
            frame,
            inv_two_pi: T::one() / &two_pi,
            four_pi: two_pi.clone() * &T::from_i64(2),
            two_pi,
        }
    }

    /// The recipe about the `+z` axis.
    ///
    /// # Density
    /// σ(s, t) = 4π (Archimedes), total measure 4π.
    ///
    /// # Example
    /// ```
    /// use areawarp::recipe::MarginalConditional;
    /// use areawarp::shapes::SphereRecipe;
    /// let r = SphereRecipe::<f64>::new();
    /// assert_eq!(r.marginal_cdf(&0.25), 0.25);
    /// ```
    pub fn new() -> Self {
        Self::build(None)
    }

    /// The recipe about `axis` (normalized; same frame as [`Sphere::with_axis`]).
    ///
    /// # Errors
    /// As [`Sphere::with_axis`].
    ///
    /// # Density
    /// σ(s, t) = 4π, total measure 4π, whatever the axis.
    ///
    /// # Example
    /// ```
    /// use areawarp::recipe::Parametrization;
    /// use areawarp::shapes::SphereRecipe;
    /// use areawarp::Vec3;
    /// let r = SphereRecipe::with_axis(Vec3::new(1.0f64, 0.0, 0.0)).unwrap();
    /// let north = r.phi(&0.0, &0.0);
    /// assert!((north.x - 1.0).abs() < 1e-15);
    /// assert!(SphereRecipe::with_axis(Vec3::new(f64::NAN, 0.0, 1.0)).is_err());
    /// ```
    pub fn with_axis(axis: Vec3<T>) -> Result<Self, WarpError> {
        Ok(Self::build(Some(Frame::from_axis(&axis)?)))
    }
}

impl<T: Real> Default for SphereRecipe<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Parametrization<T> for SphereRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let one = S::one();
        let two = S::from_i64(2);
        let z = one.clone() - &(s.clone() * &two);
        let radius = (s.clone() * &(one - s)).sqrt() * &two;
        let (sin_b, cos_b) = (S::embed(&self.two_pi) * t).sin_cos();
        let local = Vec3::new(radius.clone() * &cos_b, radius * &sin_b, z);
        match &self.frame {
            Some(f) => f.to_world(&local),
            None => local,
        }
    }

    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() || !positive(&p.norm()) {
            return None;
        }
        Some(match &self.frame {
            Some(f) => local_inverse(&f.to_local(p), &self.inv_two_pi),
            None => local_inverse(p, &self.inv_two_pi),
        })
    }
}

impl<T: Real> AreaDensity<T> for SphereRecipe<T> {}

impl<T: Real> MarginalConditional<T> for SphereRecipe<T> {
    fn measure(&self) -> T {
        self.four_pi.clone()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        clamp_unit(s)
    }
    fn marginal_pdf(&self, _s: &T) -> T {
        T::one()
    }
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        Some(u.clone())
    }
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for SphereRecipe<T> {
    type At<S: Real> = SphereRecipe<S>;
    fn recast<S: Real>(&self) -> Result<SphereRecipe<S>, WarpError> {
        Ok(match &self.frame {
            Some(f) => SphereRecipe::build(Some(f.convert()?)),
            None => SphereRecipe::new(),
        })
    }
    fn name(&self) -> String {
        "sphere".to_string()
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        (p.norm() - &T::one()).abs()
    }
}

#[cfg(test)]
mod tests;
