//! Warps defined by φ and w alone ([`WarpDefinition`]), for
//! [`DerivedWarp`](super::DerivedWarp) and
//! [`TabulatedWarp`](super::TabulatedWarp): the shapes the crate also ships
//! in closed form (hemisphere, Phong lobe, disk, sphere), the spherical cap
//! (with its closed forms as an option), and three densities renderers need,
//! GGX, Beckmann and von Mises–Fisher, without a line of CDF algebra.
//!
//! Spherical definitions use the polar angle θ = θ_range·s (or the elevation,
//! for Phong) and the azimuth 2πt, evaluated without cancellation near the
//! ends of [0, 1] (the reduced azimuth of the closed forms; sin θ near θ = π
//! as sin(π(1 − s))).

use super::{AreaDensity, Parametrization, WarpDefinition};
use crate::error::WarpError;
use crate::real::{Embed, Real, convert};
use crate::shapes::turns::{polar_turns, turns_of};
use crate::vector::Vec3;

/// (sin θ cos 2πt, sin θ sin 2πt, cos θ).
fn spherical<S: Real>(sin_theta: S, cos_theta: S, t: &S, half_pi: &S) -> Vec3<S> {
    let (x, y) = polar_turns(&sin_theta, t, half_pi);
    Vec3::new(x, y, cos_theta)
}

/// (sin πx, cos πx) for x ∈ [0, 1], through π(1 − x) above 1/2.
fn sin_cos_pi<S: Real>(x: &S, pi: &S) -> (S, S) {
    if *x > S::from_ratio(1, 2) {
        let (s, c) = ((S::one() - x) * pi).sin_cos();
        (s, -c)
    } else {
        (x.clone() * pi).sin_cos()
    }
}

/// The polar angle of `p` about +z, and its azimuth in turns.
fn polar_chart<T: Real>(p: &Vec3<T>, inv_two_pi: &T) -> Option<(T, T)> {
    if !p.is_finite() {
        return None;
    }
    Some((
        p.x.hypot(&p.y).atan2(&p.z),
        turns_of(&p.y, &p.x, inv_two_pi),
    ))
}

/// Constants shared by the spherical definitions.
#[derive(Clone, Debug)]
struct Angles<T> {
    pi: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> Angles<T> {
    fn new() -> Self {
        let pi = T::pi();
        Angles {
            half_pi: pi.clone() / &T::from_i64(2),
            inv_two_pi: T::one() / &(pi.clone() * &T::from_i64(2)),
            pi,
        }
    }
}

/// Validates a parameter: finite and within `[lo, hi]` (`lo` excluded if
/// `open_lo`).
fn check<T: Real>(
    x: &T,
    name: &'static str,
    lo: &T,
    hi: &T,
    open_lo: bool,
    expected: &'static str,
) -> Result<(), WarpError> {
    if !x.is_finite() {
        return Err(WarpError::NonFinite { what: name });
    }
    if *x < *lo || (open_lo && *x == *lo) || *x > *hi {
        return Err(WarpError::InvalidParameter { name, expected });
    }
    Ok(())
}

macro_rules! spherical_definition {
    ($name:ident, $label:expr, [$($field:ident),*], |$self_:ident, $p:ident| $weight:expr, |$sr:ident| $recast:expr $(, $($extra:tt)*)?) => {
        impl<T: Real> AreaDensity<T> for $name<T> {
            fn weight(&$self_, $p: &Vec3<T>) -> T {
                $weight
            }
        }
        impl<T: Real> WarpDefinition<T> for $name<T> {
            type At<S: Real> = $name<S>;
            fn recast<S: Real>(&$sr) -> Result<$name<S>, WarpError> {
                $recast
            }
            fn name(&self) -> String {
                let s = String::from($label);
                $( let s = format!("{s} {}={}", stringify!($field), self.$field.to_f64()); )*
                s
            }
            $($($extra)*)?
        }
    };
}

/// The unit upper hemisphere, uniform: φ(s, t) = (sin θ cos 2πt,
/// sin θ sin 2πt, cos θ), θ = πs/2 (s = 0 the pole, s = 1 the equator), as
/// [`shapes::Hemisphere`](crate::shapes::Hemisphere).
#[derive(Clone, Debug)]
pub struct Hemisphere<T> {
    angles: Angles<T>,
}

impl<T: Real> Hemisphere<T> {
    /// The hemisphere about +z.
    pub fn new() -> Self {
        Hemisphere {
            angles: Angles::new(),
        }
    }
}

impl<T: Real> Default for Hemisphere<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Parametrization<T> for Hemisphere<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        // θ = πs/2: (sin θ, cos θ) = (sin πs/2, sin π(1 − s)/2).
        let hp = S::embed(&self.angles.half_pi);
        let sin_theta = (s.clone() * &hp).sin();
        let cos_theta = ((S::one() - s) * &hp).sin();
        spherical(sin_theta, cos_theta, t, &hp)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let (theta, t) = polar_chart(p, &self.angles.inv_two_pi)?;
        Some((theta / &self.angles.half_pi, t))
    }
}

spherical_definition!(
    Hemisphere,
    "hemisphere",
    [],
    |self, _p| T::one(),
    |self| Ok(Hemisphere::new())
);

/// A Phong lobe, w = cos^k θ on the upper hemisphere, with φ in elevation
/// (s = 0 the horizon, s = 1 the pole) as
/// [`shapes::PhongLobe`](crate::shapes::PhongLobe): z = sin(πs/2).
#[derive(Clone, Debug)]
pub struct Phong<T> {
    k: T,
    angles: Angles<T>,
}

impl<T: Real> Phong<T> {
    /// The lobe of exponent `k ≥ 0`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`], [`WarpError::InvalidParameter`] for k < 0.
    pub fn new(k: T) -> Result<Self, WarpError> {
        check(&k, "k", &T::zero(), &T::max_value(), false, "k >= 0")?;
        Ok(Phong {
            k,
            angles: Angles::new(),
        })
    }
}

impl<T: Real> Parametrization<T> for Phong<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let hp = S::embed(&self.angles.half_pi);
        let z = (s.clone() * &hp).sin();
        let rho = ((S::one() - s) * &hp).sin();
        spherical(rho, z, t, &hp)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let (theta, t) = polar_chart(p, &self.angles.inv_two_pi)?;
        Some((T::one() - &(theta / &self.angles.half_pi), t))
    }
}

// The weight of a point of the unit sphere: p.z itself, not p.z/|p|, so that
// it does not pick up the rounding of |p| (which varies with t).
spherical_definition!(
    Phong,
    "phong",
    [k],
    |self, p| {
        // The closed hemisphere: at the horizon z = 0 the weight is 0^k,
        // 1 for k = 0 (no jump at s = 0 for the uniform lobe).
        if !(p.z >= T::zero()) {
            T::zero()
        } else {
            p.z.powf(&self.k)
        }
    },
    |self| Phong::new(convert(&self.k)),
    // σ = (π/2)·2π·cos(πs/2), w = sin^k(πs/2): σw = s^k·g(s) with g
    // positive at s = 0 (0^k at the horizon, 1 for k = 0: no zero).
    fn left_power(&self) -> Option<T> {
        (self.k > T::zero()).then(|| self.k.clone())
    }
);

/// The unit disk in the plane z = 0, uniform: φ(s, t) = s (cos 2πt,
/// sin 2πt, 0), as [`shapes::PolarDisk`](crate::shapes::PolarDisk).
#[derive(Clone, Debug)]
pub struct Disk<T> {
    angles: Angles<T>,
}

impl<T: Real> Disk<T> {
    /// The unit disk.
    pub fn new() -> Self {
        Disk {
            angles: Angles::new(),
        }
    }
}

impl<T: Real> Default for Disk<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Parametrization<T> for Disk<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (x, y) = polar_turns(s, t, &S::embed(&self.angles.half_pi));
        Vec3::new(x, y, S::zero())
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        Some((
            p.x.hypot(&p.y),
            turns_of(&p.y, &p.x, &self.angles.inv_two_pi),
        ))
    }
}

spherical_definition!(
    Disk,
    "disk",
    [],
    |self, _p| T::one(),
    |self| Ok(Disk::new())
);

/// The unit sphere, uniform, in polar angle θ = πs (s = 0 the north pole,
/// s = 1 the south pole): the same map as
/// [`shapes::Sphere`](crate::shapes::Sphere), derived from a φ whose σ is not
/// constant.
#[derive(Clone, Debug)]
pub struct Sphere<T> {
    angles: Angles<T>,
}

impl<T: Real> Sphere<T> {
    /// The unit sphere.
    pub fn new() -> Self {
        Sphere {
            angles: Angles::new(),
        }
    }
}

impl<T: Real> Default for Sphere<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Parametrization<T> for Sphere<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (st, ct) = sin_cos_pi(s, &S::embed(&self.angles.pi));
        spherical(st, ct, t, &S::embed(&self.angles.half_pi))
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let (theta, t) = polar_chart(p, &self.angles.inv_two_pi)?;
        Some((theta / &self.angles.pi, t))
    }
}

spherical_definition!(Sphere, "sphere", [], |self, _p| T::one(), |self| Ok(
    Sphere::new()
));

/// The spherical cap {angle(p, +z) ≤ θ_max}, uniform: θ = θ_max·s.
///
/// [`Cap::with_closed_forms`] adds the closed forms (m = 4π sin²(θ_max/2),
/// F(s) = sin²(sθ_max/2)/sin²(θ_max/2), F⁻¹(u) = (2/θ_max)
/// asin(√u sin(θ_max/2)), G_s⁻¹(v) = v), which then override steps 3–4.
#[derive(Clone, Debug)]
pub struct Cap<T> {
    theta_max: T,
    half_theta: T,
    sin_half: T,
    angles: Angles<T>,
    closed: bool,
}

impl<T: Real> Cap<T> {
    /// The cap of half-angle `theta_max ∈ (0, π]` about +z.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`], [`WarpError::InvalidParameter`] outside (0, π].
    pub fn new(theta_max: T) -> Result<Self, WarpError> {
        check(
            &theta_max,
            "theta_max",
            &T::zero(),
            &T::pi(),
            true,
            "0 < theta_max <= pi",
        )?;
        let half_theta = theta_max.clone() / &T::from_i64(2);
        Ok(Cap {
            sin_half: half_theta.sin(),
            half_theta,
            theta_max,
            angles: Angles::new(),
            closed: false,
        })
    }

    /// The same cap with its closed forms.
    pub fn with_closed_forms(mut self) -> Self {
        self.closed = true;
        self
    }
}

impl<T: Real> Parametrization<T> for Cap<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let (st, ct) = (S::embed(&self.theta_max) * s).sin_cos();
        spherical(st, ct, t, &S::embed(&self.angles.half_pi))
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let (theta, t) = polar_chart(p, &self.angles.inv_two_pi)?;
        Some((theta / &self.theta_max, t))
    }
}

impl<T: Real> AreaDensity<T> for Cap<T> {}

impl<T: Real> WarpDefinition<T> for Cap<T> {
    type At<S: Real> = Cap<S>;
    fn recast<S: Real>(&self) -> Result<Cap<S>, WarpError> {
        let c = Cap::new(convert(&self.theta_max))?;
        Ok(if self.closed {
            c.with_closed_forms()
        } else {
            c
        })
    }
    fn name(&self) -> String {
        format!(
            "cap{} theta_max={}",
            if self.closed { "(closed)" } else { "" },
            self.theta_max.to_f64()
        )
    }
    fn measure_closed(&self) -> Option<T> {
        self.closed
            .then(|| self.sin_half.square() * &self.angles.pi * &T::from_i64(4))
    }
    fn marginal_closed(&self, s: &T) -> Option<[T; 2]> {
        self.closed.then(|| {
            let inv = T::one() / &self.sin_half.square();
            let f = (self.half_theta.clone() * s).sin().square() * &inv;
            let d = (self.theta_max.clone() * s).sin() * &self.half_theta * &inv;
            [f, d]
        })
    }
    fn marginal_inverse_closed(&self, u: &T) -> Option<T> {
        self.closed.then(|| {
            let u = u.clamp(&T::zero(), &T::one());
            let x = (u.sqrt() * &self.sin_half).min(&T::one());
            (x.asin() / &self.half_theta).clamp(&T::zero(), &T::one())
        })
    }
    fn conditional_closed(&self, _s: &T, t: &T) -> Option<[T; 2]> {
        self.closed.then(|| [t.clone(), T::one()])
    }
    fn conditional_inverse_closed(&self, _s: &T, v: &T) -> Option<T> {
        self.closed.then(|| v.clamp(&T::zero(), &T::one()))
    }
}

/// The GGX (Trowbridge–Reitz) distribution of microfacet normals m on the
/// upper hemisphere, sampled proportionally to D(m)·cos θ_m:
/// w(m) = α² cos θ / (π (α² cos² θ + sin² θ)²), whose integral is 1.
/// φ as [`Hemisphere`].
#[derive(Clone, Debug)]
pub struct Ggx<T> {
    alpha: T,
    alpha2: T,
    hemisphere: Hemisphere<T>,
}

impl<T: Real> Ggx<T> {
    /// The distribution of roughness `alpha ∈ (0, 1]`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`], [`WarpError::InvalidParameter`] outside (0, 1].
    pub fn new(alpha: T) -> Result<Self, WarpError> {
        check(
            &alpha,
            "alpha",
            &T::zero(),
            &T::one(),
            true,
            "0 < alpha <= 1",
        )?;
        Ok(Ggx {
            alpha2: alpha.square(),
            alpha,
            hemisphere: Hemisphere::new(),
        })
    }
}

impl<T: Real> Parametrization<T> for Ggx<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.hemisphere.phi(s, t)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.hemisphere.chart(p)
    }
}

spherical_definition!(
    Ggx,
    "ggx",
    [alpha],
    |self, p| {
        let n2 = p.norm_squared();
        if !(p.z > T::zero()) || !(n2 > T::zero()) {
            T::zero()
        } else {
            // With cos θ = z/|p|, sin² θ = (x² + y²)/|p|².
            let rho2 = p.x.square() + &p.y.square();
            let q = self.alpha2.clone() * &p.z.square() + &rho2;
            self.alpha2.clone() * &p.z * &n2.sqrt() * &n2
                / &(q.square() * &self.hemisphere.angles.pi)
        }
    },
    |self| Ggx::new(convert(&self.alpha))
);

/// The Beckmann distribution of microfacet normals m on the upper
/// hemisphere, sampled proportionally to D(m)·cos θ_m:
/// w(m) = exp(−tan² θ/α²) / (π α² cos³ θ), whose integral is 1, cut to 0
/// where exp(−tan² θ/α²) < 2^(−2p−16) (p the precision of `T`). φ as
/// [`Hemisphere`].
#[derive(Clone, Debug)]
pub struct Beckmann<T> {
    alpha: T,
    alpha2: T,
    /// (2p + 16) ln 2: where the weight is cut to 0.
    cut: T,
    hemisphere: Hemisphere<T>,
}

impl<T: Real> Beckmann<T> {
    /// The distribution of roughness `alpha ∈ (0, 1]`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`], [`WarpError::InvalidParameter`] outside (0, 1].
    pub fn new(alpha: T) -> Result<Self, WarpError> {
        check(
            &alpha,
            "alpha",
            &T::zero(),
            &T::one(),
            true,
            "0 < alpha <= 1",
        )?;
        Ok(Beckmann {
            cut: T::from_i64(2).ln() * &T::from_i64(2 * T::precision() as i64 + 16),
            alpha2: alpha.square(),
            alpha,
            hemisphere: Hemisphere::new(),
        })
    }
}

impl<T: Real> Parametrization<T> for Beckmann<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.hemisphere.phi(s, t)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.hemisphere.chart(p)
    }
}

spherical_definition!(
    Beckmann,
    "beckmann",
    [alpha],
    |self, p| {
        let z2 = p.z.square();
        if !(p.z > T::zero()) {
            return T::zero();
        }
        // tan² θ = ρ²/z², 1/cos³ θ = (|p|/z)³.
        let rho2 = p.x.square() + &p.y.square();
        let x = rho2.clone() / &(z2.clone() * &self.alpha2);
        // Cut where e^(−x) < 2^(−2p−16): the mass beyond is below u², and
        // without the cut (MPFR's exponents do not underflow) the
        // quadrature would chase a tail that decays faster than any power
        // towards the horizon.
        if !(x <= self.cut) {
            return T::zero();
        }
        let e = (-x).exp();
        let sec2 = (rho2 + &z2) / &z2;
        e * &sec2 * &sec2.sqrt() / &(self.alpha2.clone() * &self.hemisphere.angles.pi)
    },
    |self| Beckmann::new(convert(&self.alpha))
);

/// The von Mises–Fisher distribution on the unit sphere about +z,
/// w(p) = exp(κ (z − 1)) (peak 1), with z − 1 = −(x² + y²)/(1 + z) on the
/// upper half (no cancellation near the mode). φ as [`Sphere`].
#[derive(Clone, Debug)]
pub struct VonMisesFisher<T> {
    kappa: T,
    sphere: Sphere<T>,
}

impl<T: Real> VonMisesFisher<T> {
    /// The distribution of concentration `kappa > 0`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`], [`WarpError::InvalidParameter`] for κ ≤ 0.
    pub fn new(kappa: T) -> Result<Self, WarpError> {
        check(
            &kappa,
            "kappa",
            &T::zero(),
            &T::max_value(),
            true,
            "kappa > 0",
        )?;
        Ok(VonMisesFisher {
            kappa,
            sphere: Sphere::new(),
        })
    }
}

impl<T: Real> Parametrization<T> for VonMisesFisher<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.sphere.phi(s, t)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.sphere.chart(p)
    }
}

spherical_definition!(
    VonMisesFisher,
    "vmf",
    [kappa],
    |self, p| {
        let n = p.norm();
        if !(n > T::zero()) {
            return T::zero();
        }
        let z = p.z.clone() / &n;
        let z_minus_1 = if z > T::zero() {
            -((p.x.square() + &p.y.square()) / &n.square()) / &(T::one() + &z)
        } else {
            z - &T::one()
        };
        (self.kappa.clone() * &z_minus_1).exp()
    },
    |self| VonMisesFisher::new(convert(&self.kappa))
);
