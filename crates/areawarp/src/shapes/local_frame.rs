//! A right-handed orthonormal frame about a unit axis, generic over the
//! scalar (Duff et al. 2017): the local coordinates of the sphere light, the
//! rotated sphere, the projected polygon's receiver and `vector::Frame`.

use super::turns::positive;
use crate::real::Real;
use crate::vector::Vec3;

/// `(e1, e2, axis)` with `e1 × e2 = axis`.
#[derive(Clone, Debug)]
pub(crate) struct LocalFrame<T> {
    pub(crate) e1: Vec3<T>,
    pub(crate) e2: Vec3<T>,
    pub(crate) axis: Vec3<T>,
}

/// `v / |v|`, scaled by the largest coordinate first (no overflow for huge,
/// no underflow for subnormal inputs); `None` for zero or non-finite `v`.
pub(crate) fn unit_vector<T: Real>(v: &Vec3<T>) -> Option<Vec3<T>> {
    if !v.is_finite() {
        return None;
    }
    let m = v.max_abs();
    if !positive(&m) {
        return None;
    }
    let b = Vec3::new(v.x.clone() / &m, v.y.clone() / &m, v.z.clone() / &m);
    let n = b.norm();
    Some(Vec3::new(b.x / &n, b.y / &n, b.z / &n))
}

impl<T: Real> LocalFrame<T> {
    /// The frame about the unit vector `a` (`|a| = 1` up to a few roundings;
    /// not checked), completed by Duff et al. (2017), "Building an
    /// orthonormal basis, revisited": no cancellation, branch-free apart
    /// from the sign of `z`.
    #[inline]
    pub(crate) fn about_unit(a: Vec3<T>) -> Self {
        let one = T::one();
        let sign = one.copysign(&a.z);
        let s = -(one.clone() / &(sign.clone() + &a.z));
        let c = a.x.clone() * &a.y * &s;
        let e1 = Vec3::new(
            one + &(sign.clone() * &a.x.square() * &s),
            sign.clone() * &c,
            -(sign.clone() * &a.x),
        );
        let e2 = Vec3::new(c, sign + &(a.y.square() * &s), -a.y.clone());
        LocalFrame { e1, e2, axis: a }
    }

    /// `l.x·e1 + l.y·e2 + l.z·axis`.
    pub(crate) fn to_world(&self, l: &Vec3<T>) -> Vec3<T> {
        let col = |a: &T, b: &T, c: &T| l.x.clone() * a + &(l.y.clone() * b) + &(l.z.clone() * c);
        Vec3::new(
            col(&self.e1.x, &self.e2.x, &self.axis.x),
            col(&self.e1.y, &self.e2.y, &self.axis.y),
            col(&self.e1.z, &self.e2.z, &self.axis.z),
        )
    }

    /// The coordinates of `p` in the frame.
    pub(crate) fn to_local(&self, p: &Vec3<T>) -> Vec3<T> {
        Vec3::new(p.dot(&self.e1), p.dot(&self.e2), p.dot(&self.axis))
    }
}

/// `1 − z` and `ρ² = x² + y²` of the direction `l / |l|` given in local
/// coordinates: `1 − z = ρ²/(1 + z)` for `z > 0`, where the difference would
/// lose the relative accuracy of small values.
pub(crate) fn one_minus_z<T: Real>(l: &Vec3<T>) -> (T, T) {
    let n2 = l.norm_squared();
    let rho2 = (l.x.square() + &l.y.square()) / &n2;
    let z = l.z.clone() / &n2.sqrt();
    let w = if z > T::zero() {
        rho2.clone() / &(T::one() + &z)
    } else {
        T::one() - &z
    };
    (w, rho2)
}

/// `| |p| − 1 |`: how far `p` is off the unit sphere.
pub(crate) fn off_unit_sphere<T: Real>(p: &Vec3<T>) -> T {
    (p.norm() - &T::one()).abs()
}
