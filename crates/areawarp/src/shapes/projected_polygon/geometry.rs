//! Geometry the polygon's map needs beside the lunes: its input, the
//! receiver's frame and the distance from a direction to a boundary arc.

use super::build::Arc;
use crate::real::Real;
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

/// A right-handed orthonormal frame `(e1, e2, n)` with the receiver's
/// normal `n` as local `+z`.
#[derive(Clone, Debug)]
pub(super) struct Frame<T> {
    e1: Vec3<T>,
    e2: Vec3<T>,
    n: Vec3<T>,
}

impl<T: Real> Frame<T> {
    /// Completes the unit normal `n` to a frame (Duff et al. 2017,
    /// "Building an orthonormal basis, revisited").
    pub(super) fn from_normal(n: Vec3<T>) -> Self {
        let one = T::one();
        let sign = one.copysign(&n.z);
        let a = -(one.clone() / &(sign.clone() + &n.z));
        let b = n.x.clone() * &n.y * &a;
        let e1 = Vec3::new(
            one + &(sign.clone() * &n.x.square() * &a),
            sign.clone() * &b,
            -(sign.clone() * &n.x),
        );
        let e2 = Vec3::new(b, sign + &(n.y.square() * &a), -n.y.clone());
        Frame { e1, e2, n }
    }
    pub(super) fn to_local(&self, p: &Vec3<T>) -> Vec3<T> {
        Vec3::new(p.dot(&self.e1), p.dot(&self.e2), p.dot(&self.n))
    }
    pub(super) fn to_world(&self, l: &Vec3<T>) -> Vec3<T> {
        self.e1
            .scale(&l.x)
            .add(&self.e2.scale(&l.y))
            .add(&self.n.scale(&l.z))
    }
}

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
