//! The mixed-precision construction of a narrow scalar type (`f32`): the
//! clipping, the lune partition and every per-edge and per-lune constant
//! (except the clamping ranges, made lazily from the rounded constants:
//! `ranges.rs`) are computed in the wide type (`f64`) from the unit
//! vertices and then rounded to `T` for the per-sample path, as the spherical triangle and
//! rectangle do. An `f32` polygon is thereby accepted when the `f64`
//! constructor accepts the same values and no two consecutive unit
//! vertices round together in `f32`; its constants are
//! correctly rounded (no cancellation in `f32`), and its samples are held
//! in their lune and interval by the ranges `ranges.rs` computes from the
//! rounded constants. The constructor keeps the wide partition
//! ([`Stored::Wide`]) and needs only Π in `T` ([`narrow_measure`]); the
//! rounded parts ([`narrow_parts`]) are made at the first sample, so that
//! a polygon built for its measure alone never rounds them.

use super::build::{Arc, Parts, accumulate};
use super::lune::{EdgeSide, Lune, LuneEdge, Pair};
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::wide::{narrow3, widen3};
use crate::vector::Vec3;
use std::sync::OnceLock;

/// The polygon is valid, but not once its unit vertices are rounded to `T`.
pub(super) fn unrepresentable() -> WarpError {
    WarpError::Unrepresentable {
        what: "two consecutive unit vertices of the polygon round together in the scalar type (or its projected solid angle rounds to zero)",
    }
}

/// Whether the oriented unit vertices `vertices_w` (from `build::prepare`,
/// in the wide type), rounded to `T`, are still distinct from their neighbours:
/// the polygon's edges exist in `T`. (Its orientation and every constant
/// come from the wide type, so nothing else of `T`'s rounding can undo it;
/// this is one cross product per edge, not a second validation.)
pub(super) fn representable<T: Real>(vertices_w: &[Vec3<T::Wide>]) -> bool {
    let rounded = |v: &Vec3<T::Wide>| widen3(&narrow3::<T>(v));
    let Some(last) = vertices_w.last() else {
        return true;
    };
    let mut prev = rounded(last);
    vertices_w.iter().all(|v| {
        let r = rounded(v);
        // A non-zero cross product ([`Vec3::is_zero`]: comparisons).
        let distinct = !prev.cross(&r).is_zero();
        prev = r;
        distinct
    })
}

fn n<T: Real>(x: &T::Wide) -> T {
    T::narrow(x)
}

fn n2<T: Real>((a, b): &(T::Wide, T::Wide)) -> (T, T) {
    (T::narrow(a), T::narrow(b))
}

/// The parts as the constructor made them: in the polygon's own type, or
/// (for a type narrower than its `Real::Wide`) in the wide type, rounded
/// to `T` at the first sample ([`narrow_parts`]).
#[derive(Clone, Debug)]
pub(super) enum Stored<T: Real> {
    /// In `T`.
    Own(Parts<T>),
    /// In `T::Wide`.
    Wide(Parts<T::Wide>),
}

/// The area of the wide lune `l` in `T`: zero for a lune the wide
/// partition does not sample, or whose doubled area rounds to zero.
fn narrow_area<T: Real>(l: &Lune<T::Wide>, two_area_start: &T) -> T {
    if l.active.is_some() && *two_area_start > T::zero() {
        n::<T>(&l.area)
    } else {
        T::zero()
    }
}

/// Π in `T`, as [`narrow_parts`] sums it (`accumulate`: the same
/// additions in the same order, hence the same bits), from the wide
/// lunes alone; `None` if it is not positive and finite (the projected
/// solid angle is not representable in `T`). The constructor needs only
/// this; the rounded parts wait for the first sample.
pub(super) fn narrow_measure<T: Real>(lunes: &[Lune<T::Wide>]) -> Option<T> {
    let mut measure = T::zero();
    for l in lunes {
        let area = narrow_area::<T>(l, &n::<T>(&l.two_area_start));
        if area > T::zero() {
            measure += &area;
        }
    }
    measure.is_finite_above(&T::zero()).then_some(measure)
}

/// The wide partition rounded to `T`. Lunes whose area rounds to zero are
/// not sampled.
pub(super) fn narrow_parts<T: Real>(w: &Parts<T::Wide>) -> Parts<T> {
    let arcs = w
        .arcs
        .iter()
        .map(|a| Arc {
            a: narrow3(&a.a),
            b: narrow3(&a.b),
            n: narrow3(&a.n),
        })
        .collect();
    let edges = w
        .edges
        .iter()
        .map(|e| LuneEdge {
            nz: n::<T>(&e.nz),
            abs_nz: n::<T>(&e.abs_nz),
            nz2: n::<T>(&e.nz2),
            side: [0, 1].map(|i| EdgeSide {
                g0: n::<T>(&e.side[i].g0),
                k0: n::<T>(&e.side[i].k0),
                gv: n::<T>(&e.side[i].gv),
            }),
            arc: e.arc,
            arc_end: e.arc_end,
        })
        .collect();
    let pairs = w
        .pairs
        .iter()
        .map(|p| Pair {
            inner: p.inner,
            outer: p.outer,
            d: [n2::<T>(&p.d[0]), n2::<T>(&p.d[1])],
            shared: p.shared,
            r0: [T::narrow(&p.r0[0]), T::narrow(&p.r0[1])],
            range: OnceLock::new(),
        })
        .collect();
    let mut lunes: Vec<Lune<T>> = w
        .lunes
        .iter()
        .map(|l| {
            let two_area_start = n::<T>(&l.two_area_start);
            Lune {
                start: n::<T>(&l.start),
                end_az: n::<T>(&l.end_az),
                width: n::<T>(&l.width),
                cs_a: n2::<T>(&l.cs_a),
                cs_b: n2::<T>(&l.cs_b),
                width_sc: n2::<T>(&l.width_sc),
                area: narrow_area::<T>(l, &two_area_start),
                two_area_start,
                two_area_end: OnceLock::new(),
                cum_start: T::zero(),
                cum_after: T::zero(),
                first: l.first,
                end: l.end,
                n_edges: l.n_edges,
                active: None,
            }
        })
        .collect();
    // The cumulative areas and the active lunes again, in T (Π is
    // [`narrow_measure`]'s).
    accumulate(&mut lunes);
    Parts {
        arcs,
        lunes,
        edges,
        pairs,
    }
}
