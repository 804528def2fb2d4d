//! The plane of a planar emitter's corners as given (relative to the
//! observer): where [`LightWarp::sample_light`](crate::warp::LightWarp::sample_light)
//! of the spherical triangle and the projected polygon places the sampled
//! direction, with its distance and its density in area.
//!
//! With the plane's unit normal `n̂` and its distance `t₀ = |c̄·n̂|` from the
//! observer (`c̄` the corners' centroid), the ray along a unit direction `d`
//! meets it at `t = t₀/|d·n̂|`, where the density in area is
//! `pdf·|d·n̂|/t² = pdf·K·|d·n̂|³` with `K = 1/t₀²`. Over a convex emitter
//! `|d·n̂|` lies between `c_min = t₀/max|V|` (its minimum is at the corner
//! farthest from the observer) and 1. Everything is computed in
//! [`Real::Wide`] from the corners scaled by a power of two (exact): the
//! normal is the fan sum `Σ (Vᵢ − V₀) × (Vᵢ₊₁ − V₀)` of short differences, no
//! cross product overflows or underflows. Derivation:
//! `docs/spherical-triangle.md` (the light sample).

use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::wide::{larger, largest_abs, narrow3, scale_exponent, unit_vector, widen3};
use crate::vector::Vec3;
use crate::warp::LightSample;

/// The plane's constants in `T`.
#[derive(Clone, Debug)]
pub(crate) struct LightPlane<T> {
    /// `n̂`.
    n: Vec3<T>,
    /// `t₀` in world units: the scaled `t₀` times `2^e` (exact; the
    /// constructor checks it is normal), so that a sample's distance is one
    /// quotient `t₀/|d·n̂|`.
    t0: T,
    /// `q = 1/t₀` (world units): `K = q²`, applied as `((pdf·q)·q)`, whose
    /// intermediate lies between `pdf` and `pdf·K` (no spurious underflow
    /// where `K` alone would leave `T`'s range).
    q: T,
    /// `c_min`: rounded directions are held to it.
    c_min: T,
}

fn unrepresentable() -> WarpError {
    WarpError::Unrepresentable {
        what: "density in area measure (or distance) of the emitter's plane outside the scalar type's range",
    }
}

impl<T: Real> LightPlane<T> {
    /// The plane of `corners` seen from `observer` (their differences,
    /// formed in `T`, as the shapes give them; at least three corners;
    /// `WarpError::Degenerate` if their normal vanishes) for densities in
    /// solid angle between `pdf_min` and `pdf_max`: `Unrepresentable`
    /// unless `T` holds the distances `t₀` (normal) and `max|V|` (finite),
    /// `1/t₀` (normal) and the densities in area, `pdf_max·K` to a
    /// sixteenth of `T`'s largest value and `pdf_min·K·c_min³` sixteen
    /// times above its smallest normal number (margins for the sample's
    /// roundings of the same values).
    #[inline(always)]
    pub fn new(
        corners: &[Vec3<T>],
        observer: &Vec3<T>,
        pdf_max: &T,
        pdf_min: &T,
    ) -> Result<Self, WarpError> {
        type W<T> = <T as Real>::Wide;
        let rel = |p: &Vec3<T>| p.sub(observer);
        let m = corners
            .iter()
            .fold(T::zero(), |m, p| larger(m, largest_abs(&rel(p))));
        let e = scale_exponent::<T>(m.to_f64());
        let down = W::<T>::exp2i(-e);
        // Each corner scaled and widened once, as it is used.
        let at = |p: &Vec3<T>| widen3(&rel(p)).scale(&down);
        let v0 = at(&corners[0]);
        let mut sum = Vec3::zero();
        let mut centroid = v0.clone();
        let mut far = v0.dot(&v0);
        let mut prev: Option<Vec3<W<T>>> = None;
        for p in &corners[1..] {
            let v = at(p);
            let q = v.dot(&v);
            if q > far {
                far = q;
            }
            let edge = v.sub(&v0);
            if let Some(prev) = &prev {
                sum = sum.add(&prev.cross(&edge));
            }
            centroid = centroid.add(&v);
            prev = Some(edge);
        }
        let n = unit_vector(&sum).ok_or(WarpError::Degenerate {
            what: "the emitter's corners are collinear (no plane)",
        })?;
        let t0 = centroid.dot(&n).abs() / &W::<T>::from_i64(corners.len() as i64);
        let far = far.sqrt();
        let c_min = t0.clone() / &far;
        // K = 1/(t₀ 2^e)² = q², q = 2^−e/t₀, applied as the sample applies
        // it, ((pdf·q)·q): K alone may leave even the wide type's range.
        let q = down / &t0;
        let density = |pdf: &T, c: &W<T>| pdf.widen() * &q * &q * c * c * c;
        let p_max = density(pdf_max, &W::<T>::one());
        let p_min = density(pdf_min, &c_min);
        let up = T::exp2i(e);
        let plane = LightPlane {
            n: narrow3::<T>(&n),
            t0: T::narrow(&t0) * &up,
            q: T::narrow(&q),
            c_min: T::narrow(&c_min),
        };
        let sixteen = T::from_i64(16);
        let in_range = p_max <= (T::max_value() / &sixteen).widen()
            && T::narrow(&p_min) >= T::normal_floor() * &sixteen
            && plane.t0 >= T::normal_floor()
            && (T::narrow(&far) * &up).is_finite()
            && plane.q.is_finite_above(&T::normal_floor())
            && plane.c_min.is_finite_above(&T::zero());
        if in_range {
            Ok(plane)
        } else {
            Err(unrepresentable())
        }
    }

    /// The light sample of the unit direction `d` (from the map) with
    /// density `pdf` seen from `observer`.
    #[inline]
    pub fn sample(&self, d: Vec3<T>, pdf: T, observer: &Vec3<T>) -> LightSample<T> {
        let c = d.dot(&self.n).abs();
        // A rounded direction just outside the emitter is held to its
        // edge's value (a NaN stays NaN).
        let c = if c < self.c_min {
            self.c_min.clone()
        } else {
            c
        };
        let t = self.t0.clone() / &c;
        LightSample {
            point: observer.add(&d.scale(&t)),
            direction: d,
            distance: t,
            pdf_area: pdf.clone() * &self.q * &self.q * &c * &c * &c,
            pdf,
        }
    }

    /// The light sample of `d` with density `pdf` on the unit sphere around
    /// `observer` (distance 1, density in area equal to `pdf`): for an
    /// emitter given by directions whose plane `T` cannot hold.
    pub fn on_unit_sphere(d: Vec3<T>, pdf: T, observer: &Vec3<T>) -> LightSample<T> {
        LightSample {
            point: observer.add(&d),
            direction: d,
            distance: T::one(),
            pdf_area: pdf.clone(),
            pdf,
        }
    }
}
