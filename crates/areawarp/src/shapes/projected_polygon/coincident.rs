//! Repeated vertices: a vertex whose direction coincides with its
//! predecessor's is dropped (a degenerate quad that is a triangle, as
//! renderers pass them), as long as three distinct directions remain.
//!
//! Two consecutive vertices *coincide* when their input directions are
//! exactly the same (cross product exactly zero and dot product positive,
//! decided on the input values), or when their unit vectors do not resolve
//! them (the cross product of the unit vectors rounds to zero, dot product
//! positive). [`distinct`] computes the cross product of consecutive unit
//! vertices (one per edge); only where it is within rounding of zero
//! (`close`, 64 units of roundoff of the input type) is any further work
//! done ([`drop_coincident`], out of line). Derivation and
//! the fuzz counts: `docs/projected-polygon.md`, "Repeated vertices".

use super::build::{degenerate, next};
use super::geometry::Source;
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::wide::{largest_abs, widen3};
use crate::vector::Vec3;

/// The size of the cross product of two consecutive unit vertices (in the
/// wide type) below which their input directions are tested for exact
/// coincidence: 64 units of roundoff of the input type `T`, well above the
/// rounding of a unit vertex computed from it (a few units, also for
/// points minus an observer rotated into the receiver's frame), so that
/// exactly coinciding inputs always get the test.
pub(super) fn coincidence_scale<T: Real>() -> T::Wide {
    (T::from_i64(64) * &T::unit_roundoff()).widen()
}

/// The index and magnitude of the first coordinate of largest magnitude.
fn largest<W: Real>(a: &Vec3<W>) -> (usize, W) {
    let (x, y, z) = (a.x.abs(), a.y.abs(), a.z.abs());
    if x >= y && x >= z {
        (0, x)
    } else if y >= z {
        (1, y)
    } else {
        (2, z)
    }
}

/// Whether the finite vectors `a` and `b` point in the same direction,
/// decided on their values: each is divided by the magnitude of its
/// largest coordinate (the first one on a tie). For exactly proportional
/// `b = c a`, `c > 0`, that coordinate is the same one and the correctly
/// rounded quotients `b_i / |b_k| = a_i / |a_k|` are the same numbers, so
/// exactly coinciding directions are always recognized (no product is
/// formed: nothing to overflow, underflow or round differently). The
/// converse admits directions whose quotients round together, i.e. closer
/// than the coordinates resolve, which the caller drops as well.
fn same_ray<W: Real>(a: &Vec3<W>, b: &Vec3<W>) -> bool {
    let ((ka, ma), (kb, mb)) = (largest(a), largest(b));
    ka == kb
        && ma > W::zero()
        && mb > W::zero()
        && a.x.clone() / &ma == b.x.clone() / &mb
        && a.y.clone() / &ma == b.y.clone() / &mb
        && a.z.clone() / &ma == b.z.clone() / &mb
}

impl<T: Real> Source<T> {
    /// Whether input vertices `i` and `j` have the same direction, decided
    /// on the input values in the wide type ([`same_ray`]): the vertices
    /// themselves, or `p − o` for points seen from an observer (exact for
    /// `f32` input; for `f64`, on the rounded differences, which are equal
    /// for a repeated corner).
    pub(super) fn same_direction(&self, i: usize, j: usize) -> bool {
        match self {
            Source::Directions(v) => same_ray(&widen3(&v[i]), &widen3(&v[j])),
            Source::Points {
                points, observer, ..
            } => {
                let o = widen3(observer);
                same_ray(&widen3(&points[i]).sub(&o), &widen3(&points[j]).sub(&o))
            }
        }
    }
}

/// The unit vertices `v` without the vertices that coincide with their
/// predecessor (see the module): the first vertex of each run of
/// coinciding ones is kept (cyclically: a last vertex coinciding with the
/// first is dropped). Errors: antipodal consecutive vertices, or fewer than
/// three distinct directions left. `same(i, j)` decides on the inputs `i`,
/// `j`; `close` is [`coincidence_scale`]. Costs one cross product per edge
/// unless a pair is within `close` ([`drop_coincident`]).
pub(super) fn distinct<W: Real>(
    v: Vec<Vec3<W>>,
    close: &W,
    same: impl Fn(usize, usize) -> bool,
) -> Result<Vec<Vec3<W>>, WarpError> {
    let n = v.len();
    // Unit vectors: finite cross products, their largest magnitude by
    // comparisons.
    if (0..n).any(|i| largest_abs(&v[i].cross(&v[next(i, n)])) <= *close) {
        drop_coincident(v, close, same)
    } else {
        Ok(v)
    }
}

/// Whether consecutive unit vertices `a` (input `i`) and `b` (input `j`)
/// coincide; an error if they are antipodal (their edge is undefined).
fn coincide<W: Real>(
    (i, a): (usize, &Vec3<W>),
    (j, b): (usize, &Vec3<W>),
    close: &W,
    same: &impl Fn(usize, usize) -> bool,
) -> Result<bool, WarpError> {
    let c = a.cross(b).max_abs();
    if !(c <= *close) {
        return Ok(false);
    }
    if a.dot(b) > W::zero() {
        Ok(c == W::zero() || same(i, j))
    } else if c == W::zero() {
        Err(degenerate(
            "antipodal consecutive vertices (the edge is undefined)",
        ))
    } else {
        Ok(false)
    }
}

/// [`distinct`] where some pair is within `close`: one pass comparing each
/// vertex with the last one kept.
#[cold]
#[inline(never)]
fn drop_coincident<W: Real>(
    v: Vec<Vec3<W>>,
    close: &W,
    same: impl Fn(usize, usize) -> bool,
) -> Result<Vec<Vec3<W>>, WarpError> {
    let mut kept: Vec<(usize, Vec3<W>)> = Vec::with_capacity(v.len());
    for (j, b) in v.into_iter().enumerate() {
        if let Some((i, a)) = kept.last()
            && coincide((*i, a), (j, &b), close, &same)?
        {
            continue;
        }
        kept.push((j, b));
    }
    while kept.len() > 1 {
        let (last, first) = (&kept[kept.len() - 1], &kept[0]);
        if !coincide((last.0, &last.1), (first.0, &first.1), close, &same)? {
            break;
        }
        kept.pop();
    }
    if kept.len() < 3 {
        return Err(degenerate(
            "coincident consecutive vertices: fewer than 3 distinct vertex directions",
        ));
    }
    Ok(kept.into_iter().map(|(_, p)| p).collect())
}
