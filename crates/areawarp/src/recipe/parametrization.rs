//! Step 1: the parametrization φ.

use crate::real::{Dual2, Embed, Real};
use crate::vector::Vec3;

/// Step 1: a smooth map φ(s, t) from [0, 1]² onto the manifold M (bijective
/// almost everywhere). Planar shapes return `z = 0`.
///
/// `phi` is generic over the evaluation scalar `S`, into which the shape's
/// constants (stored as `T`) are embedded with [`Embed::embed`]; evaluating it
/// at dual numbers gives exact partial derivatives ([`Parametrization::partials`]).
pub trait Parametrization<T: Real> {
    /// φ(s, t).
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S>;

    /// `[φ, φ_s, φ_t]` at `(s, t)`, exact up to rounding in `T` (forward-mode
    /// dual numbers, no finite differences).
    fn partials(&self, s: &T, t: &T) -> [Vec3<T>; 3] {
        let p = self.phi(&Dual2::seed_u(s.clone()), &Dual2::seed_v(t.clone()));
        [
            Vec3::new(p.x.re, p.y.re, p.z.re),
            Vec3::new(p.x.du, p.y.du, p.z.du),
            Vec3::new(p.x.dv, p.y.dv, p.z.dv),
        ]
    }

    /// The coordinate chart φ⁻¹: `(s, t)` of a point on M, if known.
    fn chart(&self, _p: &Vec3<T>) -> Option<(T, T)> {
        None
    }
}
