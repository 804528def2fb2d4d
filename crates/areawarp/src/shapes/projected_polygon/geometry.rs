//! Geometry the polygon's map needs beside the lunes: its input, the
//! receiver's frame, the distance from a direction to a boundary arc, the
//! unit vectors of vertices and normals, and the solid angle computed on
//! demand.

use super::build::Arc;
use super::coincident::{coincidence_scale, distinct};
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::polygon_measures::oriented_solid_angle_of_units;
use crate::shapes::wide::{largest_abs, widen3};
use crate::vector::Vec3;

/// Where the polygon came from, kept to rebuild it at another precision.
#[derive(Clone, Debug)]
pub(super) enum Source<T> {
    Directions(Vec<Vec3<T>>),
    Points {
        points: Vec<Vec3<T>>,
        observer: Vec3<T>,
        normal: Vec3<T>,
    },
}

impl<T> Source<T> {
    /// The corners as given: the points, or the vertex directions.
    pub(super) fn corners(&self) -> &[Vec3<T>] {
        match self {
            Source::Points { points, .. } => points,
            Source::Directions(v) => v,
        }
    }
}

/// The frame `(e1, e2, n)` with the receiver's unit normal `n` as local
/// `+z`: the axially symmetric warps' [`LocalFrame`] (Duff et al. 2017).
pub(super) use crate::shapes::local_frame::LocalFrame as Frame;

/// Euclidean distance from the unit vector `d` to the arc.
pub(super) fn arc_distance<T: Real>(d: &Vec3<T>, arc: &Arc<T>) -> T {
    let ends = d.sub(&arc.a).norm().min(&d.sub(&arc.b).norm());
    let w = d.sub(&arc.n.scale(&d.dot(&arc.n)));
    match w.normalized() {
        Some(q)
            if arc.a.cross(&q).dot(&arc.n) >= T::zero()
                && q.cross(&arc.b).dot(&arc.n) >= T::zero() =>
        {
            d.sub(&q).norm().min(&ends)
        }
        _ => ends,
    }
}

/// `v / |v|`, or `None` for a zero or non-finite vector: `v` is divided by
/// its largest coordinate first, after which `|v|` is a plain square root
/// (no overflow or underflow for huge or subnormal input, and none of the
/// two `hypot` calls of [`Vec3::normalized`]).
pub(super) fn scaled_unit<T: Real>(v: &Vec3<T>) -> Option<Vec3<T>> {
    // The largest magnitude by comparisons (`max_abs` takes NaN-aware
    // maxima); a NaN coordinate it passes over makes `n` NaN below.
    let m = largest_abs(v);
    if !m.is_finite_above(&T::zero()) {
        return None;
    }
    let w = Vec3::new(v.x.clone() / &m, v.y.clone() / &m, v.z.clone() / &m);
    let n = w.dot(&w).sqrt();
    // n ∈ [1, √3] for a finite v.
    if !n.is_finite_above(&T::zero()) {
        return None;
    }
    Some(Vec3::new(w.x / &n, w.y / &n, w.z / &n))
}

/// `v / |v|` with the errors a polygon vertex or a receiver normal gets:
/// `v` is scaled by the reciprocal of its largest coordinate (so that
/// directions that are positive multiples of each other usually coincide
/// after normalization, which the coincident-vertex test relies on), then
/// divided by its length, a plain square root after the scaling (by
/// quotients where the reciprocal overflows: a subnormal direction is a
/// direction too).
pub(super) fn unit_direction<T: Real>(
    v: &Vec3<T>,
    what: &'static str,
) -> Result<Vec3<T>, WarpError> {
    if !v.is_finite() {
        return Err(WarpError::NonFinite { what });
    }
    let zero = || WarpError::Degenerate {
        what: "a polygon vertex direction is the zero vector",
    };
    // Finite: the largest magnitude by comparisons (`max_abs` takes
    // NaN-aware maxima).
    let m = largest_abs(v);
    if !(m > T::zero()) {
        return Err(zero());
    }
    let inv = T::one() / &m;
    let w = if inv.is_finite() {
        v.scale(&inv)
    } else {
        // A subnormal largest coordinate (below 1/max): its reciprocal
        // overflows, the quotients do not.
        Vec3::new(v.x.clone() / &m, v.y.clone() / &m, v.z.clone() / &m)
    };
    let n = w.dot(&w).sqrt();
    if !n.is_finite_above(&T::zero()) {
        return Err(zero());
    }
    Ok(w.scale(&(T::one() / &n)))
}

/// The solid angle of the polygon that `prepare` accepted, from its unit
/// vertices (the smaller region, in `[0, 2π)`): the fan `prepare` skips
/// where the rough sum decides, computed when it is asked for.
fn solid_angle_of_units<T: Real>(v: &[Vec3<T>]) -> T {
    let omega = oriented_solid_angle_of_units(v);
    let four_pi = T::pi() * &T::from_i64(4);
    let other = four_pi - &omega;
    if omega > other { other } else { omega }
}

/// The solid angle of the polygon given by `source` (seen in the receiver's
/// `frame` for points), from the unit vertices in the wide type and in the
/// input order, as `prepare` computes them (repeated vertices dropped): the
/// same bits as the constructor's value where it needed one.
pub(super) fn source_solid_angle<T: Real>(source: &Source<T>, frame: Option<&Frame<T>>) -> T {
    let local: Vec<Vec3<T>> = match (source, frame) {
        (
            Source::Points {
                points, observer, ..
            },
            Some(f),
        ) => points
            .iter()
            .map(|p| f.to_local(&p.sub(observer)))
            .collect(),
        (Source::Points { points, .. }, None) | (Source::Directions(points), _) => points.clone(),
    };
    let units: Vec<Vec3<T::Wide>> = local
        .iter()
        .map(|p| unit_direction(&widen3(p), "polygon vertex").expect("accepted vertices"))
        .collect();
    let units = distinct(units, &coincidence_scale::<T>(), |i, j| {
        source.same_direction(i, j)
    })
    .expect("accepted vertices");
    T::narrow(&solid_angle_of_units(&units))
}
