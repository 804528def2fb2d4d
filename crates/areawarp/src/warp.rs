//! What every area-preserving map offers: [`Warp`] (sample / pdf / invert /
//! measure) and [`WarpFamily`] (the same shape rebuilt at another precision,
//! which is how the harness compares `f32`/`f64` against 256 bits and gets
//! exact derivatives from dual numbers).

use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Coords;

/// An area-preserving parametrization ψ: [0, 1]² → M of a shape M, possibly
/// weighted (Phong lobe, cosine).
///
/// # Density
/// With weight w on M (w ≡ 1 for uniform warps) and total weighted measure
/// `m = ∫_M w`, points `ψ(u, v)` of uniform `(u, v)` have density
/// `pdf(p) = w(p) / m` with respect to M's area (or solid-angle) measure, and
/// `|ψ_u × ψ_v| · pdf(ψ(u, v)) = 1` everywhere.
pub trait Warp<T: Real> {
    /// The points of M: [`Vec2`](crate::vector::Vec2) or [`Vec3`](crate::vector::Vec3).
    type Point: Coords<T>;
    /// ψ(u, v) for `u, v ∈ [0, 1]`; finite and on M (within rounding) for every
    /// such input, including the edges.
    fn map(&self, u: &T, v: &T) -> Self::Point;
    /// Density of the returned points at `p`, in M's area or solid-angle measure.
    fn pdf(&self, p: &Self::Point) -> T;
    /// `(ψ(u, v), pdf(ψ(u, v)))` in one call: what a sampler needs. The
    /// default evaluates [`Warp::pdf`] at the mapped point; warps whose
    /// `pdf` must first test that its argument lies on the shape (the
    /// spherical rectangle) override it with the density they know the
    /// mapped point has, so that a renderer does not pay for the test.
    fn map_with_pdf(&self, u: &T, v: &T) -> (Self::Point, T) {
        let p = self.map(u, v);
        let pdf = self.pdf(&p);
        (p, pdf)
    }
    /// Total (weighted) measure of M: area, solid angle, or ∫ w.
    fn measure(&self) -> T;
    /// ψ⁻¹(p): the `(u, v)` that maps to `p`, or `None` if `p` is not finite or
    /// not on M (beyond rounding).
    fn inverse(&self, p: &Self::Point) -> Option<(T, T)>;
    /// How far `p` lies outside M (0 on M), in the units of the coordinates.
    fn outside_by(&self, p: &Self::Point) -> T;
    /// A characteristic length of M, the scale of absolute errors (1 for unit shapes).
    fn extent(&self) -> T {
        T::one()
    }
}

/// A warp whose shape can be rebuilt at any other precision.
///
/// `w.at::<Mpfr256>()` is the same map at 256 bits; `w.at::<f32>()?.at::<Mpfr256>()`
/// is the shape exactly as `f32` sees it (parameters rounded to `f32`), the
/// right reference for an `f32` precision check; `w.at::<Dual2<Mpfr256>>()`
/// evaluates ψ with exact partial derivatives.
pub trait WarpFamily<T: Real>: Warp<T> + Clone {
    /// The same warp over scalar `S`.
    type At<S: Real>: WarpFamily<S>;
    /// Rebuilds the warp over `S` (parameters converted, constants recomputed).
    fn at<S: Real>(&self) -> Result<Self::At<S>, WarpError>;
    /// A short name for reports, e.g. `hemisphere`.
    fn name(&self) -> String;
}
