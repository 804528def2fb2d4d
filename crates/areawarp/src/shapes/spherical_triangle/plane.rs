//! The plane of the triangle's vertices as given (relative to the observer):
//! where [`LightWarp::sample_light`](crate::warp::LightWarp::sample_light)
//! places the sampled direction, its distance and its density in area.
//!
//! With the unit normal `n̂` of the plane through `A, B, C` and the distance
//! `t₀ = |A·n̂|` from the observer to it, the ray along a unit direction `d`
//! meets the plane at `t = t₀/|d·n̂|`, where the density in area is
//! `pdf·|d·n̂|/t² = K·|d·n̂|³` with `K = pdf/t₀²`. The plane is computed in
//! [`Real::Wide`] from the vertices scaled by a power of two (exact), so
//! that no cross product overflows or underflows; the constructor refuses a
//! triangle whose area densities or distances `T` cannot hold. Derivation:
//! `docs/spherical-triangle.md` (the light sample).

use super::build::reject;
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::wide::{narrow3, scale_exponent, unit_vector, widen3};
use crate::vector::Vec3;
use crate::warp::LightSample;

/// The plane's constants in `T`.
#[derive(Clone, Debug)]
pub(super) struct Plane<T> {
    /// `n̂`.
    n: Vec3<T>,
    /// `t₀` in units of `2^e`, and `2^e`.
    t0: T,
    up: T,
    /// `K = pdf/t₀²` (world units).
    k: T,
    /// The smallest `|d·n̂|` over the triangle, `t₀/max|V|` (at the vertex
    /// farthest from the observer): rounded directions are held to it.
    c_min: T,
}

fn unrepresentable() -> WarpError {
    WarpError::Unrepresentable {
        what: "density in area measure (or distance) of the triangle's plane outside the scalar type's range",
    }
}

impl<T: Real> Plane<T> {
    /// The plane of `input` (the vertex vectors as given to the
    /// constructor), `pdf` = 1/Ω: `Unrepresentable` unless `T` holds the
    /// distance to the plane and the area densities over the triangle,
    /// `K` (the largest bound) to a sixteenth of its largest value and
    /// `K·c_min³` (the smallest, at the farthest vertex) sixteen times
    /// above its smallest normal number (margins for the sample's
    /// roundings of the same values).
    pub fn new(input: &[Vec3<T>; 3], pdf: &T) -> Result<Self, WarpError> {
        let zero = <T::Wide as Real>::zero();
        let larger = |a: T::Wide, b: &T| {
            let b = b.widen().abs();
            if b > a { b } else { a }
        };
        let m = input.iter().fold(zero.clone(), |m, v| {
            larger(larger(larger(m, &v.x), &v.y), &v.z)
        });
        let e = scale_exponent::<T>(m.to_f64());
        let down = <T::Wide as Real>::exp2i(-e);
        let [a, b, c] = input.each_ref().map(|v| widen3(v).scale(&down));
        let n = unit_vector(&b.sub(&a).cross(&c.sub(&a))).ok_or(reject::ON_CIRCLE)?;
        let t0 = a.dot(&n).abs();
        let far = {
            let (qa, qb, qc) = (a.dot(&a), b.dot(&b), c.dot(&c));
            let q = if qb > qa { qb } else { qa };
            if qc > q { qc } else { q }
        }
        .sqrt();
        let c_min = t0.clone() / &far;
        // K = pdf/(t₀ 2^e)² as (pdf·q)·q, q = 2^−e/t₀.
        let q = down / &t0;
        let k = pdf.widen() * &q * &q;
        let p_min = k.clone() * &c_min * &c_min * &c_min;
        let plane = Plane {
            n: narrow3::<T>(&n),
            t0: T::narrow(&t0),
            up: T::exp2i(e),
            k: T::narrow(&k),
            c_min: T::narrow(&c_min),
        };
        let sixteen = T::from_i64(16);
        let in_range = plane.k <= T::max_value() / &sixteen
            && T::narrow(&p_min) >= T::normal_floor() * &sixteen
            && (plane.t0.clone() * &plane.up) >= T::normal_floor()
            && (T::narrow(&far) * &plane.up).is_finite()
            && positive_finite(&plane.c_min);
        if in_range {
            Ok(plane)
        } else {
            Err(unrepresentable())
        }
    }

    /// The light sample of the unit direction `d` (from the map) with
    /// density `pdf` seen from `observer`.
    #[inline]
    pub fn sample(&self, d: Vec3<T>, pdf: &T, observer: &Vec3<T>) -> LightSample<T> {
        let c = d.dot(&self.n).abs();
        // A rounded direction just outside the triangle is held to its
        // edge's value (a NaN stays NaN).
        let c = if c < self.c_min {
            self.c_min.clone()
        } else {
            c
        };
        let t = self.t0.clone() / &c * &self.up;
        LightSample {
            point: observer.add(&d.scale(&t)),
            direction: d,
            distance: t,
            pdf: pdf.clone(),
            pdf_area: self.k.clone() * &c * &c * &c,
        }
    }
}

/// `0 < x < ∞`.
fn positive_finite<T: Real>(x: &T) -> bool {
    x.is_finite_above(&T::zero())
}
