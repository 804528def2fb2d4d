//! Uniform sampling of the solid angle a sphere subtends from a point
//! outside it (pbrt's sphere-light sampling): directions uniform in the
//! cone of half-angle θ_max = arcsin(r/d), and the point where each hits
//! the sphere first. Derivation: `docs/sphere-light.md`.

use super::local_frame::{LocalFrame, off_unit_sphere, one_minus_z, unit_vector};
use super::turns::{clamp_unit, polar_turns, positive, turns_of};
use super::wide::{largest_abs, scale_exponent};
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;
use crate::warp::{InverseError, LightSample, LightWarp, Warp, WarpFamily, on_shape_tolerance};

/// How far a direction with `w = 1 − cos θ` and `sin θ` lies beyond the rim
/// of a cone with `h = 1 − cos θ_max`, `sin θ_max`, as an angle:
/// `θ − θ_max ≈ (cos θ_max − cos θ)/sin((θ + θ_max)/2)`, here with the
/// mean of the sines in the denominator (0 inside).
pub(crate) fn beyond_rim<T: Real>(w: &T, h: &T, sin_theta: &T, sin_max: &T) -> T {
    let excess = w.clone() - h;
    if !positive(&excess) {
        return T::zero();
    }
    let s = (sin_theta.clone() + sin_max) / &T::from_i64(2);
    if positive(&s) { excess / &s } else { excess }
}

/// Uniform directions (in solid angle) towards a sphere of centre `c` and
/// radius `r` seen from an observer `o` outside it, and their first hit
/// points on the sphere (pbrt-v4's `SphereLight`/`Sphere::Sample(ctx)`):
/// with `d = |c − o|`, `sin θ_max = r/d`, `h = 1 − cos θ_max`,
///
/// 1 − cos θ = u·h,   φ = 2πv,
///
/// about the axis `(c − o)/d`; ψ(u, v) is the direction, and
/// [`LightWarp::sample_light`] also returns the point `c + r·n` with
/// `n = (sin α cos φ, sin α sin φ, −cos α)` in the same frame, α the angle
/// at the centre between `n` and `−axis`.
///
/// Numerics, from an observer 10⁻⁶ above the surface to a sphere of
/// 10⁻⁸ sr far away, at any scale the type can hold the densities of:
/// - every length in units of the offset's power of two (exact: the same
///   directions and Ω at every scale; `docs/sphere-light.md`, scale and
///   cost);
/// - `cos θ_max = √((d − r)(d + r))/d` and `h = sin²θ_max/(1 + cos θ_max)`
///   (no `1 − cos θ_max`, which would lose every digit of a tiny cone);
/// - the direction works with `1 − cos θ = u·h` and
///   `sin θ = √(uh(2 − uh))`, never with a rounded `cos θ` (as
///   [`UniformCone`](super::UniformCone));
/// - the hit point uses `sin²θ_max − sin²θ = h(1 − u)(cos θ + cos θ_max)`
///   (a product, where pbrt's `1 − sin²θ/sin²θ_max` cancels at the rim),
///   `cos α = (sin²θ + cos θ·√(…))/sin θ_max` and
///   `sin α = sin θ·cos²θ_max/(sin θ_max(cos θ + √(…)))` (sums of positive
///   terms; pbrt's `sin α = √(1 − cos²α)` cancels at the nearest point).
///
/// # Density
/// `pdf = 1/Ω` per steradian in the cone (0 outside), `Ω = 2πh =
/// measure()`.
///
/// # Example
/// ```
/// use areawarp::shapes::SphereLight;
/// use areawarp::{Vec3, Warp};
///
/// let light = SphereLight::new(Vec3::new(0.0, 0.0, 2.0f64), 1.0, Vec3::new(0.0, 0.0, 0.0)).unwrap();
/// // sin θ_max = 1/2: Ω = 2π(1 − √3/2).
/// let omega = 2.0 * std::f64::consts::PI * (1.0 - 3f64.sqrt() / 2.0);
/// assert!((light.measure() - omega).abs() < 1e-15);
/// use areawarp::warp::LightWarp;
/// let s = light.sample_light([0.3, 0.7]);
/// assert!(((s.point.sub(&Vec3::new(0.0, 0.0, 2.0))).norm() - 1.0).abs() < 1e-15);
/// let along = s.point.scale(&(1.0 / s.point.norm()));
/// assert!(along.sub(&s.direction).norm() < 1e-15);
/// assert!(SphereLight::new(Vec3::new(0.0, 0.0, 0.5f64), 1.0, Vec3::new(0.0, 0.0, 0.0)).is_err());
/// ```
#[derive(Clone, Debug)]
pub struct SphereLight<T> {
    center: Vec3<T>,
    radius: T,
    observer: Vec3<T>,
    /// d = |c − o| in units of 2^e (see `new`); `down` = 2^−e, `up` = 2^e.
    distance: T,
    down: T,
    up: T,
    frame: LocalFrame<T>,
    sin_max: T,
    cos_max: T,
    h: T,
    omega: T,
    inv_omega: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> SphereLight<T> {
    /// The sphere of `center` and `radius` seen from `observer`.
    ///
    /// # Errors
    /// - [`WarpError::NonFinite`] for NaN/∞ coordinates or radius, or a
    ///   distance that overflows;
    /// - [`WarpError::InvalidParameter`] for a radius ≤ 0, and for an
    ///   observer inside or on the sphere (`|c − o| ≤ r`: there is no cone
    ///   of directions to sample; sample the whole sphere of directions
    ///   instead);
    /// - [`WarpError::Degenerate`] if the cone's solid angle underflows;
    /// - [`WarpError::Unrepresentable`] if the type cannot hold what the
    ///   map computes: a solid angle so small that `h·u` underflows, or a
    ///   density in area (largest at the nearest point, smallest positive
    ///   next to the rim) outside the normal range.
    ///
    /// # Density
    /// `1/Ω` per steradian; in area on the sphere `|n·ψ|/(Ω t²)`.
    pub fn new(center: Vec3<T>, radius: T, observer: Vec3<T>) -> Result<Self, WarpError> {
        Self::build(center, radius, observer)
    }

    /// [`SphereLight::new`], inlined into [`SphereLight::sample_once`]: the
    /// light is then never stored and read back.
    #[inline(always)]
    fn build(center: Vec3<T>, radius: T, observer: Vec3<T>) -> Result<Self, WarpError> {
        if !center.is_finite() {
            return Err(WarpError::NonFinite {
                what: "sphere centre",
            });
        }
        if !observer.is_finite() {
            return Err(WarpError::NonFinite { what: "observer" });
        }
        if !radius.is_finite() {
            return Err(WarpError::NonFinite {
                what: "sphere radius",
            });
        }
        if !positive(&radius) {
            return Err(WarpError::InvalidParameter {
                name: "radius",
                expected: "a finite radius > 0",
            });
        }
        let offset = center.sub(&observer);
        if !offset.is_finite() {
            return Err(WarpError::NonFinite {
                what: "centre − observer (overflow)",
            });
        }
        // Every length in units of 2^e, the power of two that brings the
        // offset's largest coordinate into [1, 2) (exact: the same values
        // at every scale, no overflow or underflow of d², (d − r)(d + r) or
        // the distances' squares); the world's lengths are the local ones
        // times 2^e.
        let e = scale_exponent::<T>(largest_abs(&offset).to_f64());
        let (down, up) = (T::exp2i(-e), T::exp2i(e));
        let off = offset.scale(&down);
        let r = radius.clone() * &down;
        let d = off.norm_squared().sqrt();
        if !(d > r) {
            return Err(WarpError::InvalidParameter {
                name: "observer",
                expected: "a point outside the sphere (|centre − observer| > radius)",
            });
        }
        if !(d.clone() * &up).is_finite() {
            return Err(WarpError::NonFinite {
                what: "distance to the centre (overflow)",
            });
        }
        let inv_d = T::one() / &d;
        let frame = LocalFrame::about_unit(off.scale(&inv_d));
        let sin_max = r.clone() * &inv_d;
        let near = d.clone() - &r;
        let cos_max = (near.clone() * &(d.clone() + &r)).sqrt() * &inv_d;
        let h = sin_max.square() / &(T::one() + &cos_max);
        let pi = T::pi();
        let omega = pi.clone() * &T::from_i64(2) * &h;
        let inv_omega = T::one() / &omega;
        if !(omega >= T::normal_floor()) || !inv_omega.is_finite() {
            return Err(WarpError::Degenerate {
                what: "the sphere's solid angle underflows",
            });
        }
        // h(1 − u) ≥ h·u (the root at the rim, for u < 1) must stay normal.
        if !(h >= T::normal_floor() / T::unit_roundoff()) {
            return Err(WarpError::Unrepresentable {
                what: "solid angle below the scalar type's range for the map (h·u underflows)",
            });
        }
        // The density in area is largest at the nearest point (t = d − r,
        // |n·ψ| = 1): 1/(Ω (d − r)²) in world units, at most max/16 (a
        // margin for the sample's own roundings of the same value).
        let range = || WarpError::Unrepresentable {
            what: "density in area measure outside the scalar type's range",
        };
        let p_max = inv_omega.clone() / &near.square() * &down * &down;
        if !p_max.is_finite_above(&T::zero()) || p_max > T::max_value() / T::from_i64(16) {
            return Err(range());
        }
        let light = SphereLight {
            center,
            radius,
            observer,
            distance: d,
            down,
            up,
            frame,
            sin_max,
            cos_max,
            h,
            omega,
            inv_omega,
            half_pi: pi.clone() / &T::from_i64(2),
            inv_two_pi: T::one() / &(pi * &T::from_i64(2)),
        };
        // It decreases towards the rim (0 at u = 1, where the ray is
        // tangent); its smallest positive value, at the largest u below 1,
        // must not underflow. That holds when 2^e ≤ 2^40 and
        // cos θ_max ≥ 2^-32 in a type whose range exceeds 2^±100
        // (`docs/sphere-light.md`, scale and cost); otherwise the sample
        // there is evaluated.
        let ordinary = e <= 40 && light.cos_max >= T::exp2i(-32) && T::max_value() >= T::exp2i(100);
        if !ordinary {
            let last = T::one() - &T::unit_roundoff();
            if !(light.sample_hit(&last, &T::zero()).pdf_area >= T::normal_floor()) {
                return Err(range());
            }
        }
        Ok(light)
    }

    /// One light sample of the sphere of `center` and `radius` seen from
    /// `observer`, without keeping a [`SphereLight`]: bit for bit
    /// `SphereLight::new(center, radius, observer)?.sample_light([u, v])`,
    /// what a renderer calls per shading point.
    ///
    /// # Errors
    /// As [`SphereLight::new`].
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::SphereLight;
    /// use areawarp::{LightWarp, Vec3};
    /// let (c, o) = (Vec3::new(0.0f32, 0.0, 2.0), Vec3::new(0.0, 0.0, 0.0));
    /// let once = SphereLight::sample_once(&c, &0.5, &o, &0.3, &0.7)?;
    /// let light = SphereLight::new(c, 0.5, o)?;
    /// assert_eq!(once, light.sample_light([0.3, 0.7]));
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    #[inline]
    pub fn sample_once(
        center: &Vec3<T>,
        radius: &T,
        observer: &Vec3<T>,
        u: &T,
        v: &T,
    ) -> Result<LightSample<T>, WarpError> {
        Ok(Self::build(center.clone(), radius.clone(), observer.clone())?.sample_hit(u, v))
    }

    /// The centre.
    pub fn center(&self) -> &Vec3<T> {
        &self.center
    }
    /// The radius.
    pub fn radius(&self) -> &T {
        &self.radius
    }
    /// The observer.
    pub fn observer(&self) -> &Vec3<T> {
        &self.observer
    }
    /// `1 − cos θ_max`, the cone's height: Ω = 2π·h.
    pub fn cone_height(&self) -> &T {
        &self.h
    }

    /// `(1 − cos θ, sin θ, cos θ, (cos φ, sin φ))` of ψ(u, v).
    fn angles(&self, u: &T, v: &T) -> (T, T, T, (T, T)) {
        let w = u.clone() * &self.h;
        let sin_theta = (w.clone() * &(T::from_i64(2) - &w)).sqrt();
        let cos_theta = T::one() - &w;
        (
            w,
            sin_theta,
            cos_theta,
            polar_turns(&T::one(), v, &self.half_pi),
        )
    }

    /// ψ(u, v) with the first hit point on the sphere, its distance and
    /// both densities (see [`LightWarp::sample_light`]).
    #[inline(always)]
    fn sample_hit(&self, u: &T, v: &T) -> LightSample<T> {
        let (u, v) = (clamp_unit(u), clamp_unit(v));
        let (_, sin_theta, cos_theta, (c, s)) = self.angles(&u, &v);
        let direction = self.frame.to_world(&Vec3::new(
            sin_theta.clone() * &c,
            sin_theta.clone() * &s,
            cos_theta.clone(),
        ));
        // √(sin²θ_max − sin²θ) = √(h(1 − u)(cos θ + cos θ_max)).
        let root =
            (self.h.clone() * &(T::one() - &u) * &(cos_theta.clone() + &self.cos_max)).sqrt();
        let cos_alpha = (sin_theta.square() + &(cos_theta.clone() * &root)) / &self.sin_max;
        let den = cos_theta + &root;
        let sin_alpha = sin_theta * &self.cos_max.square() / &(self.sin_max.clone() * &den);
        let n = self.frame.to_world(&Vec3::new(
            sin_alpha.clone() * &c,
            sin_alpha * &s,
            -cos_alpha,
        ));
        // The ray parameter t = d cos θ − √(r² − d² sin²θ), without its
        // cancellation at the rim: t = d cos²θ_max/(cos θ + √(…)). The
        // cosine at the emitter |n·ψ| = cos(α + θ) = √(…)/sin θ_max.
        // t and pdf_area = |n·ψ|/(Ω t²) with t in units of 2^e, then
        // scaled to the world: 2^e t and ((…)·2^−e)·2^−e (each finite and
        // normal for the densities `new` admits).
        let t = self.distance.clone() * &self.cos_max.square() / &den;
        let cos_emitter = root / &self.sin_max;
        let pdf_area =
            self.inv_omega.clone() * &cos_emitter / &t.square() * &self.down * &self.down;
        let distance = t * &self.up;
        LightSample {
            point: self.center.add(&n.scale(&self.radius)),
            direction,
            distance,
            pdf: self.inv_omega.clone(),
            pdf_area,
        }
    }

    /// `[u, v]` of a point `p` on the sphere's visible cap: the inverse of
    /// the direction `(p − o)/|p − o|`.
    ///
    /// # Errors
    /// [`InverseError`] if `p` is not finite, farther than `2^(−p/2)·r` from
    /// the sphere, or its direction is not in the cone.
    pub fn inverse_point(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        if !p.is_finite() {
            return Err(InverseError::NonFinite);
        }
        let off = (p.sub(&self.center).norm() - &self.radius).abs() / &self.radius;
        if off > on_shape_tolerance::<T>() {
            return Err(InverseError::OffShape {
                distance: (off * &self.radius).to_f64(),
            });
        }
        let dir = unit_vector(&p.sub(&self.observer)).ok_or(InverseError::OffShape {
            distance: self.radius.to_f64(),
        })?;
        self.inverse(&dir)
    }
}

impl<T: Real> Warp<T> for SphereLight<T> {
    type Point = Vec3<T>;

    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let (_, sin_theta, cos_theta, (c, s)) = self.angles(&clamp_unit(u), &clamp_unit(v));
        self.frame.to_world(&Vec3::new(
            sin_theta.clone() * &c,
            sin_theta * &s,
            cos_theta,
        ))
    }

    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        self.inv_omega.clone()
    }

    /// `max(2^(−p/2)·sin θ_max, 64u)`: relative to the cone's size, so that
    /// [`Warp::pdf`] and [`Warp::inverse`] refuse directions well outside a
    /// narrow cone (θ_max = 5.6·10⁻⁵ for 10⁻⁸ sr, below `f32`'s
    /// `2⁻¹² ≈ 2.4·10⁻⁴`), but never below the rounding of a unit
    /// direction's coordinates.
    fn on_shape_tolerance(&self) -> T {
        (on_shape_tolerance::<T>() * &self.sin_max.min(&T::one()))
            .max(&(T::unit_roundoff() * &T::from_i64(64)))
    }

    fn measure(&self) -> T {
        self.omega.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &self.on_shape_tolerance())?;
        let l = self.frame.to_local(p);
        let (w, _) = one_minus_z(&l);
        Ok([
            clamp_unit(&(w / &self.h)),
            turns_of(&l.y, &l.x, &self.inv_two_pi),
        ])
    }

    /// `| |p| − 1 |` plus the angle by which the direction lies beyond the
    /// cone's rim.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let radial = off_unit_sphere(p);
        if p.norm_squared() == T::zero() {
            return radial;
        }
        let l = self.frame.to_local(p);
        let (w, rho2) = one_minus_z(&l);
        radial + &beyond_rim(&w, &self.h, &rho2.sqrt(), &self.sin_max)
    }
}

impl<T: Real> WarpFamily<T> for SphereLight<T> {
    type At<S: Real> = SphereLight<S>;
    fn at<S: Real>(&self) -> Result<SphereLight<S>, WarpError> {
        SphereLight::new(
            self.center.convert(),
            crate::real::convert(&self.radius),
            self.observer.convert(),
        )
    }
    fn name(&self) -> String {
        "sphere-light".to_string()
    }
}

crate::warp::distribution_for_floats!(SphereLight, Vec3);

impl<T: Real> LightWarp<T> for SphereLight<T> {
    fn observer(&self) -> Vec3<T> {
        self.observer.clone()
    }
    /// The direction ψ(u, v), the first hit `c + r·n` on the sphere, the
    /// distance `d cos²θ_max/(cos θ + √(sin²θ_max − sin²θ))` (no
    /// cancellation at the rim) and both densities.
    #[inline]
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T> {
        let [u, v] = uv;
        self.sample_hit(&u, &v)
    }
}

/// The test shapes, from a sphere of 10⁻⁸ sr far away to an observer
/// 10⁻⁶ above the surface: `(name, [cx, cy, cz, r, ox, oy, oz])`.
pub fn sphere_light_ladder() -> Vec<(String, [f64; 7])> {
    let dir = [2.0 / 7.0, -3.0 / 7.0, 6.0 / 7.0];
    let o = [0.1, 0.2, -0.3];
    let at = |dist: f64| {
        [
            o[0] + dist * dir[0],
            o[1] + dist * dir[1],
            o[2] + dist * dir[2],
        ]
    };
    let c_far = at(1e4);
    let c_mid = [0.3, -1.2, 2.0];
    let near = |gap: f64| {
        let (c, r) = ([0.25, -0.5, 1.5], 0.75);
        let d = r + gap;
        [c[0] - d * dir[0], c[1] - d * dir[1], c[2] - d * dir[2]]
    };
    let n3 = near(0.75e-3);
    let n6 = near(1e-6);
    vec![
        (
            "medium".into(),
            [c_mid[0], c_mid[1], c_mid[2], 0.7, o[0], o[1], o[2]],
        ),
        (
            "far 1e-8 sr".into(),
            [c_far[0], c_far[1], c_far[2], 0.5642, o[0], o[1], o[2]],
        ),
        (
            "near 1e-3 r".into(),
            [0.25, -0.5, 1.5, 0.75, n3[0], n3[1], n3[2]],
        ),
        (
            "near 1e-6".into(),
            [0.25, -0.5, 1.5, 0.75, n6[0], n6[1], n6[2]],
        ),
        (
            "axis 1e-6".into(),
            [0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 1.0 - 1e-6],
        ),
    ]
}

#[cfg(test)]
mod tests;
