//! What a user writes to get a derived warp: step 1 (φ) and, optionally, a
//! weight and any closed forms they already have.

use super::AreaDensity;
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;

/// A warp defined by its parametrization φ(s, t) on [0, 1]² (step 1, trait
/// [`Parametrization`](super::Parametrization)) and a weight w(p) (trait
/// [`AreaDensity`], default 1): everything else — σ, the measure, the
/// marginal and conditional CDFs, their inverses — is computed by
/// [`DerivedWarp`](super::DerivedWarp).
///
/// Closed forms, where the user has them, override the computed steps: the
/// area density by overriding [`AreaDensity::sigma`], the others by the
/// `*_closed` methods below (each `None` by default). The derived warp
/// cross-checks a closed measure and a closed marginal against its
/// quadrature at construction and refuses a disagreement.
///
/// # Example
/// `examples/define_your_own_warp.rs` (a spherical cap in a screenful) and
/// [`definitions`](super::definitions) (hemisphere, Phong, disk, sphere, cap,
/// GGX, Beckmann, von Mises–Fisher).
pub trait WarpDefinition<T: Real>: AreaDensity<T> + Clone {
    /// The same definition over scalar `S`.
    type At<S: Real>: WarpDefinition<S>;
    /// Rebuilds the definition over `S` (convert parameters with
    /// [`crate::real::convert`], recompute constants in `S`).
    fn recast<S: Real>(&self) -> Result<Self::At<S>, WarpError>;
    /// A short name for reports.
    fn name(&self) -> String;
    /// How far `p` lies outside M. The default measures the distance from
    /// `p` to φ(chart(p)) with the chart clamped to [0, 1]²; definitions
    /// without a chart report 0.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        match self.chart(p) {
            Some((s, t)) => {
                let (s, t) = (
                    s.clamp(&T::zero(), &T::one()),
                    t.clamp(&T::zero(), &T::one()),
                );
                self.phi(&s, &t).sub(p).norm()
            }
            None => T::zero(),
        }
    }
    /// A characteristic length of M (see [`Warp::extent`](crate::warp::Warp::extent)).
    fn extent(&self) -> T {
        T::one()
    }
    /// The exponent e > 0 with which σw vanishes at s = 0, if known:
    /// σw(s, t) = s^e·g(s, t), g smooth and positive at s = 0 (a Phong lobe
    /// of exponent k, in elevation from the horizon: e = k). It must be
    /// exact (not estimated): the derived marginal then interpolates
    /// f(s)/s^e on its first panel and holds F relatively accurate at every
    /// s, however small F(s) (docs/recipe-quadrature.md §2), and the tables
    /// fit F⁻¹ in u^(1/(e+1)) near u = 0. The default `None` leaves the
    /// density as it is.
    fn left_power(&self) -> Option<T> {
        None
    }
    /// m = ∫∫σ in closed form, if known.
    fn measure_closed(&self) -> Option<T> {
        None
    }
    /// `[F(s), F'(s)]` in closed form, if known.
    fn marginal_closed(&self, _s: &T) -> Option<[T; 2]> {
        None
    }
    /// F⁻¹(u) in closed form, if known.
    fn marginal_inverse_closed(&self, _u: &T) -> Option<T> {
        None
    }
    /// `[G_s(t), ∂G_s/∂t]` in closed form, if known.
    fn conditional_closed(&self, _s: &T, _t: &T) -> Option<[T; 2]> {
        None
    }
    /// G_s⁻¹(v) in closed form, if known.
    fn conditional_inverse_closed(&self, _s: &T, _v: &T) -> Option<T> {
        None
    }
}
