//! The range of r² and z² of each interval's region in its lune, into
//! which samples are clamped (`docs/projected-polygon.md`, Numerics,
//! "Samples held in their interval's region"). Computed the first time a
//! sample falls in the interval ([`Pair::range`]), not by the constructor:
//! it is a quarter of a quad's construction otherwise, and a renderer that
//! builds the sampler for a few samples pays only for the intervals it
//! visits. In `f64` the values are those the constructor used to compute
//! (the same operations on the same stored constants); in `f32` they are
//! computed from the rounded constants and arcs (no longer rounded from
//! `f64`) and widened by 64 `f32` units.

use super::build::Arc;
use super::lune::{LuneEdge, Pair};
use crate::real::Real;
use crate::vector::Vec3;

/// Which end point of an edge's arc lies on one of its lune's bounding
/// meridians (its own end point, exact, is then that side's extreme).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ArcEnd {
    /// Neither: the edge crosses the meridian.
    Neither,
    /// The arc's start `a`.
    Start,
    /// The arc's end `b`.
    End,
}

/// The range of r² and of z² over a part of an edge, or over the region
/// of an interval ([`Pair`]) in its lune, `(least, largest)` each: from the
/// inner edge's least r² (0 at the pole) to the outer edge's largest
/// ([`EdgeRange::pair`]). Samples are clamped into their interval's range
/// (widened by rounding, [`EdgeRange::slackened`]), which keeps them within
/// the lune's azimuth width of the region where the edges' r² on a meridian
/// is ill-conditioned (edges nearly along a meridian).
#[derive(Clone, Debug)]
pub(super) struct EdgeRange<T> {
    /// (least r², largest r²).
    pub r2: (T, T),
    /// (least z², largest z²).
    pub z2: (T, T),
}

impl<T: Real> EdgeRange<T> {
    /// The range of the point `p` (unit).
    pub fn point(p: [&T; 3]) -> Self {
        let r2 = p[0].square() + &p[1].square();
        let z2 = p[2].square();
        EdgeRange {
            r2: (r2.clone(), r2),
            z2: (z2.clone(), z2),
        }
    }

    /// `(r², z²)` clamped into the range.
    #[inline]
    pub fn clamp(&self, r2: T, z2: T) -> (T, T) {
        (
            r2.max(&self.r2.0).min(&self.r2.1),
            z2.max(&self.z2.0).min(&self.z2.1),
        )
    }

    /// The range widened by 64 units of roundoff (relative) at both ends:
    /// the clamp then leaves every well-conditioned value, and its
    /// derivative over dual numbers, alone and acts only where the
    /// meridian's r² is off by more than rounding.
    pub fn slackened(&self) -> Self {
        let k = T::from_i64(64) * &T::unit_roundoff();
        let widen = |(lo, hi): &(T, T)| {
            (
                lo.clone() - &(lo.clone() * &k),
                hi.clone() + &(hi.clone() * &k),
            )
        };
        EdgeRange {
            r2: widen(&self.r2),
            z2: widen(&self.z2),
        }
    }

    /// The smallest range holding both.
    pub fn hull(&self, o: &Self) -> Self {
        EdgeRange {
            r2: (self.r2.0.min(&o.r2.0), self.r2.1.max(&o.r2.1)),
            z2: (self.z2.0.min(&o.z2.0), self.z2.1.max(&o.z2.1)),
        }
    }

    /// `self` clamped into `outer` (both ends).
    pub fn within(&self, outer: &Self) -> Self {
        let c = |x: &T, (lo, hi): &(T, T)| x.max(lo).min(hi);
        EdgeRange {
            r2: (c(&self.r2.0, &outer.r2), c(&self.r2.1, &outer.r2)),
            z2: (c(&self.z2.0, &outer.z2), c(&self.z2.1, &outer.z2)),
        }
    }

    /// The range of the region between the inner edge `inner` (`None`: the
    /// pole) and the outer edge `outer` across a lune: on every meridian
    /// the region runs from the inner edge outwards to the outer edge.
    pub fn pair(inner: Option<&Self>, outer: &Self) -> Self {
        let (r_lo, z_hi) = match inner {
            Some(i) => (i.r2.0.clone(), i.z2.1.clone()),
            None => (T::zero(), T::one()),
        };
        EdgeRange {
            r2: (r_lo, outer.r2.1.clone()),
            z2: (outer.z2.0.clone(), z_hi),
        }
    }
}

/// The range of r² and z² over the arc: its ends, and the top of its great
/// circle (r² = n_z², the point nearest the pole) if that lies on the arc.
fn arc_range<T: Real>(arc: &Arc<T>) -> EdgeRange<T> {
    let ends = EdgeRange::point([&arc.a.x, &arc.a.y, &arc.a.z])
        .hull(&EdgeRange::point([&arc.b.x, &arc.b.y, &arc.b.z]));
    let n = &arc.n;
    // The top, e_z − n_z n (unnormalized), lies on the minor arc a → b if it
    // is on the left of a and on the right of b along the great circle.
    let top = Vec3::new(
        -(n.z.clone() * &n.x),
        -(n.z.clone() * &n.y),
        n.x.square() + &n.y.square(),
    );
    if n.cross(&arc.a).dot(&top) >= T::zero() && arc.b.cross(n).dot(&top) >= T::zero() {
        let r2 = n.z.square();
        let z2 = T::one() - &r2;
        ends.hull(&EdgeRange {
            r2: (r2.clone(), r2),
            z2: (z2.clone(), z2),
        })
    } else {
        ends
    }
}

/// The range of the edge's part inside its lune: its points on the two
/// bounding meridians (the arc's own end point there, if it ends on that
/// meridian, else computed from the side's constants), the top of its
/// great circle (r² = n_z²) if that lies inside the lune, all held inside
/// the range of the whole arc ([`arc_range`]).
fn edge_range<T: Real>(e: &LuneEdge<T>, arcs: &[Arc<T>]) -> EdgeRange<T> {
    let arc = &arcs[e.arc];
    let at = |si: usize| -> EdgeRange<T> {
        let p = match e.arc_end[si] {
            ArcEnd::Start => &arc.a,
            ArcEnd::End => &arc.b,
            ArcEnd::Neither => {
                let g0 = &e.side[si].g0;
                let den = e.nz2.clone() + &g0.square();
                let r2 = e.nz2.clone() / &den;
                let z2 = g0.square() / &den;
                return EdgeRange {
                    r2: (r2.clone(), r2),
                    z2: (z2.clone(), z2),
                };
            }
        };
        EdgeRange::point([&p.x, &p.y, &p.z])
    };
    let mut r = at(0).hull(&at(1));
    // g' = k₀ at the start and −k₀ at the end: of opposite signs, |g|
    // peaks inside, where the great circle is highest (r² = n_z²).
    if e.side[0].k0.clone() * &e.side[1].k0 > T::zero() {
        let top = e.nz2.clone();
        let z_top = T::one() - &top;
        r = r.hull(&EdgeRange {
            r2: (top.clone(), top),
            z2: (z_top.clone(), z_top),
        });
    }
    r.within(&arc_range(arc))
}

impl<T: Real> Pair<T> {
    /// The range of the interval's region in its lune, widened by
    /// rounding ([`EdgeRange::slackened`]): computed on first use from the
    /// edges' constants and the clipped boundary's `arcs`.
    #[inline]
    pub fn range(&self, edges: &[LuneEdge<T>], arcs: &[Arc<T>]) -> &EdgeRange<T> {
        self.range.get_or_init(|| {
            let outer = edge_range(&edges[self.outer], arcs);
            let inner = self.inner.map(|i| edge_range(&edges[i], arcs));
            EdgeRange::pair(inner.as_ref(), &outer).slackened()
        })
    }
}
