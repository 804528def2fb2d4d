//! Step 2: the area density σ.

use super::Parametrization;
use crate::real::Real;
use crate::vector::Vec3;

/// Step 2: σ(s, t) = ‖φ_s × φ_t‖ · w(φ(s, t)), so that ∫_A σ is the (weighted)
/// area of φ(A). In the plane ‖φ_s × φ_t‖ = |det Dφ|.
///
/// The default implementation derives σ from step 1 by dual numbers; the
/// weight w defaults to 1 (uniform sampling). Override [`AreaDensity::weight`]
/// for non-uniform targets (cosine, Phong lobes).
pub trait AreaDensity<T: Real>: Parametrization<T> {
    /// The target weight w at a point of M (1 for uniform sampling).
    fn weight(&self, _p: &Vec3<T>) -> T {
        T::one()
    }
    /// σ(s, t).
    fn sigma(&self, s: &T, t: &T) -> T {
        let [p, ps, pt] = self.partials(s, t);
        ps.cross(&pt).norm() * &self.weight(&p)
    }
}
