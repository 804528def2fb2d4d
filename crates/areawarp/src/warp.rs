//! What every area-preserving map offers: [`Warp`] (sample / pdf / invert /
//! measure) and [`WarpFamily`] (the same shape rebuilt at another precision,
//! which is how the harness compares `f32`/`f64` against 256 bits and gets
//! exact derivatives from dual numbers).

use crate::error::WarpError;
use crate::real::Real;
use crate::vector::{Coords, Vec3};

/// One sample of a warp: the point ψ(u, v) and its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample<T, P> {
    /// The point on the shape (a point of the plane, of space, or a unit
    /// direction).
    pub point: P,
    /// Its density with respect to the shape's measure (area, solid angle),
    /// finite and `> 0`.
    pub pdf: T,
}

/// Why [`Warp::inverse`] refused a point.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum InverseError {
    /// A coordinate of the point is NaN or infinite.
    NonFinite,
    /// The point lies off the shape beyond the rounding tolerance of the
    /// scalar type: by `distance` (in the units of
    /// [`Warp::outside_by`], rounded to `f64`).
    OffShape {
        /// How far outside the shape the point lies.
        distance: f64,
    },
}

impl core::fmt::Display for InverseError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            InverseError::NonFinite => write!(f, "the point is not finite"),
            InverseError::OffShape { distance } => {
                write!(f, "the point lies off the shape by {distance:e}")
            }
        }
    }
}

impl std::error::Error for InverseError {}

impl InverseError {
    /// `Ok(())` if `p` is finite and within `tolerance` of `w`'s shape
    /// ([`Warp::outside_by`]); otherwise the reason. The shared first step of
    /// every [`Warp::inverse`].
    pub fn check<T: Real, W: Warp<T> + ?Sized>(
        w: &W,
        p: &W::Point,
        tolerance: &T,
    ) -> Result<(), InverseError> {
        if !p.to_vec3().is_finite() {
            return Err(InverseError::NonFinite);
        }
        let d = w.outside_by(p);
        if d > *tolerance || d.is_nan() {
            return Err(InverseError::OffShape {
                distance: d.to_f64(),
            });
        }
        Ok(())
    }

    /// The refusal of a point `p` that passed [`InverseError::check`] but
    /// for which the map still has no preimage (e.g. a direction that rounds
    /// to zero): [`InverseError::OffShape`] with its distance, or
    /// [`InverseError::NonFinite`].
    pub fn refuse<T: Real, W: Warp<T> + ?Sized>(w: &W, p: &W::Point) -> InverseError {
        if !p.to_vec3().is_finite() {
            return InverseError::NonFinite;
        }
        InverseError::OffShape {
            distance: w.outside_by(p).to_f64(),
        }
    }
}

/// How far off a shape of extent 1 a point may lie for `pdf` and `inverse`
/// to count it as on the shape: `2^(−p/2)` for a `p`-bit type (`≈ 2.4e-4`
/// in `f32`, `≈ 1.1e-8` in `f64`); [`Warp::on_shape_tolerance`] scales it
/// by the shape's extent. The one definition for the shapes and the
/// recipe's warps.
///
/// Generous on purpose: directions normalized elsewhere, or pushed through
/// a few rotations, are "on the sphere" for every practical purpose, and the
/// inverses re-normalize before they compute anything.
pub(crate) fn on_shape_tolerance<T: Real>() -> T {
    T::exp2i(-((T::precision() / 2) as i32))
}

/// An area-preserving parametrization ψ: \[0, 1\]² → M of a shape M,
/// possibly weighted (Phong lobe, cosine).
///
/// # Density
/// With weight w on M (w ≡ 1 for uniform warps) and total weighted measure
/// `m = ∫_M w`, points `ψ(u, v)` of uniform `(u, v)` have density
/// `pdf(p) = w(p) / m` with respect to M's area (or solid-angle) measure, and
/// `|ψ_u × ψ_v| · pdf(ψ(u, v)) = 1` everywhere.
///
/// # The contract
/// Every warp of the crate keeps it, and `tests/contract.rs` checks it for
/// every warp and variant in `f32`, `f64` and at 256 bits:
/// - **map** — [`Warp::map`] / [`Warp::sample_uv`]: for every `u, v ∈ [0, 1]`
///   (edges included) a finite point on M within rounding
///   ([`Warp::outside_by`] of the order of the unit roundoff times
///   [`Warp::extent`]); inputs outside `[0, 1]` are clamped. A constructor
///   that accepted a shape never produces a map that breaks this: shapes the
///   map cannot serve are rejected with a [`WarpError`].
/// - **pdf** — [`Warp::pdf`] is the density at a point of M and exactly 0
///   off M (beyond rounding) and at non-finite points. [`Warp::sample_uv`]
///   returns the density the sampled point has without testing that the
///   point is on M (the fast path a sampler wants); [`Warp::pdf_unchecked`]
///   is the same for a point the caller knows came from the map.
/// - **inverse** — [`Warp::inverse`] returns `(u, v)` with
///   `ψ(u, v) = p` within the map's conditioning, or says why it refused
///   ([`InverseError`]); it never refuses a point that the map produced.
/// - **measure** — [`Warp::measure`] is the total (weighted) measure of M,
///   `1/pdf` for uniform warps.
/// - every `f32`/`f64` warp of the crate also implements
///   [`rand::distr::Distribution`] over its points, drawing `(u, v)`
///   uniformly and mapping them (the same `(u, v)` as
///   [`crate::sampling::WarpSampler`]).
///
/// `map` takes its arguments by reference (the generic core, for MPFR and
/// dual numbers, which are not `Copy`); [`Warp::sample_uv`] takes them by
/// value, which is what `f32`/`f64` callers want.
///
/// Name clash: while [`rand::distr::Distribution`] is in scope (it is in
/// `rand::prelude`), `w.map(&u, &v)` on an `f32`/`f64` warp resolves to
/// `Distribution::map` (which takes `self` by value) and does not compile;
/// write `Warp::map(&w, &u, &v)` or use `w.sample_uv([u, v])`.
pub trait Warp<T: Real> {
    /// The points of M: [`Vec2`](crate::vector::Vec2) or [`Vec3`].
    type Point: Coords<T>;
    /// ψ(u, v) for `u, v ∈ [0, 1]`; finite and on M (within rounding) for every
    /// such input, including the edges.
    fn map(&self, u: &T, v: &T) -> Self::Point;
    /// Density of the returned points at `p`, in M's area or solid-angle
    /// measure; 0 off M (farther than [`Warp::on_shape_tolerance`]) and at
    /// non-finite `p`. The default tests [`Warp::outside_by`] and then
    /// evaluates [`Warp::pdf_unchecked`].
    fn pdf(&self, p: &Self::Point) -> T {
        if !p.to_vec3().is_finite() || !(self.outside_by(p) <= self.on_shape_tolerance()) {
            return T::zero();
        }
        self.pdf_unchecked(p)
    }
    /// The density at a point `p` that the caller knows came from
    /// [`Warp::map`]: the value [`Warp::pdf`] has there, without the test
    /// that `p` lies on M. Off M the result is unspecified (but finite).
    fn pdf_unchecked(&self, p: &Self::Point) -> T;
    /// How far off M a point may lie ([`Warp::outside_by`]) for
    /// [`Warp::pdf`] to count it as on M: `2^(−p/2)` times
    /// [`Warp::extent`] for a `p`-bit scalar, far above the rounding errors
    /// of any computed point of the map and far below any real distance.
    fn on_shape_tolerance(&self) -> T {
        on_shape_tolerance::<T>() * &self.extent()
    }
    /// `(ψ(u, v), pdf(ψ(u, v)))` in one call: what a sampler needs. The
    /// default evaluates [`Warp::pdf_unchecked`] at the mapped point.
    #[inline]
    fn map_with_pdf(&self, u: &T, v: &T) -> (Self::Point, T) {
        let p = self.map(u, v);
        let pdf = self.pdf_unchecked(&p);
        (p, pdf)
    }
    /// [`Warp::map_with_pdf`] by value: the sample at `uv = [u, v]`.
    ///
    /// (Named `sample_uv` rather than `sample` so that it never clashes with
    /// [`rand::distr::Distribution::sample`], which the `f32`/`f64` warps
    /// implement too.)
    #[inline]
    fn sample_uv(&self, uv: [T; 2]) -> Sample<T, Self::Point> {
        let [u, v] = uv;
        let (point, pdf) = self.map_with_pdf(&u, &v);
        Sample { point, pdf }
    }
    /// Total (weighted) measure of M: area, solid angle, or ∫ w.
    fn measure(&self) -> T;
    /// ψ⁻¹(p): the `[u, v]` that maps to `p`.
    ///
    /// # Errors
    /// [`InverseError`] if `p` is not finite or not on M (beyond rounding);
    /// never for a point that [`Warp::map`] returned.
    fn inverse(&self, p: &Self::Point) -> Result<[T; 2], InverseError>;
    /// How far `p` lies outside M (0 on M), in the units of the coordinates.
    fn outside_by(&self, p: &Self::Point) -> T;
    /// A characteristic length of M, the scale of absolute errors (1 for unit shapes).
    fn extent(&self) -> T {
        T::one()
    }
}

/// A sample of an emitter seen from an observer: what a renderer's light
/// sampling routine returns (compare pbrt-v4's `SampleSphericalTriangle` /
/// `ShapeSample`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample<T> {
    /// The unit direction from the observer towards the point.
    pub direction: Vec3<T>,
    /// The point on the emitter (world coordinates).
    pub point: Vec3<T>,
    /// `|point − observer|`: the length of the shadow ray.
    pub distance: T,
    /// Density in solid angle at the observer (the warp's [`Warp::pdf`]).
    pub pdf: T,
    /// Density in area on the emitter: `pdf · |cos θ_e| / distance²`, with
    /// `θ_e` the angle between the direction and the emitter's normal.
    pub pdf_area: T,
}

/// A warp onto the directions towards an emitter seen from an observer
/// (spherical triangle, spherical rectangle, projected polygon, sphere
/// light): it also places the sampled direction on the emitter.
///
/// A light given in space (a rectangle, a sphere, a triangle or polygon
/// `from_points`) is refused by its constructor when the scalar type cannot
/// hold its distances or densities in area
/// ([`WarpError::Unrepresentable`]), so
/// that every point it returns lies on the emitter, with
/// `pdf_area = pdf·|cos θ_e|/distance²`. A shape given by vertex
/// directions (`new`) has no emitter of its own: the plane of its vectors
/// as given stands for one, and where the type cannot hold that plane the
/// point is the direction itself (distance 1, `pdf_area = pdf`).
///
/// A renderer that draws one sample per light and shading point need not
/// build the shape: the one-shot light samples
/// [`SphericalTriangle::sample_light_once`](crate::shapes::SphericalTriangle::sample_light_once),
/// [`SphericalRectangle::sample_once`](crate::shapes::SphericalRectangle::sample_once) and
/// [`SphereLight::sample_once`](crate::shapes::SphereLight::sample_once)
/// return the same [`LightSample`], bit for bit, computing only what that
/// sample needs.
pub trait LightWarp<T: Real>: Warp<T, Point = Vec3<T>> {
    /// The observer (the shading point), world coordinates.
    fn observer(&self) -> Vec3<T>;
    /// The sample at `uv` with the point on the emitter, its distance and
    /// both densities.
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T>;
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

/// `ψ(u, v)` of two uniform `[0, 1)` numbers drawn from `rng` (`u` first):
/// the [`rand::distr::Distribution`] of every `f32`/`f64` warp.
pub(crate) fn draw<T, W, R>(w: &W, rng: &mut R) -> W::Point
where
    T: Real,
    W: Warp<T> + ?Sized,
    R: rand::Rng + ?Sized,
    rand::distr::StandardUniform: rand::distr::Distribution<T>,
{
    use rand::RngExt;
    let u: T = rng.random();
    let v: T = rng.random();
    w.map(&u, &v)
}

/// Implements [`rand::distr::Distribution`] over its points for the `f32`
/// and `f64` versions of a warp type `$shape<T>` ([`draw`]).
macro_rules! distribution_for_floats {
    ($shape:ident, $point:ident) => {
        impl rand::distr::Distribution<$point<f32>> for $shape<f32> {
            /// ψ(u, v) of two uniform `[0, 1)` numbers from `rng`.
            fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> $point<f32> {
                $crate::warp::draw(self, rng)
            }
        }
        impl rand::distr::Distribution<$point<f64>> for $shape<f64> {
            /// ψ(u, v) of two uniform `[0, 1)` numbers from `rng`.
            fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> $point<f64> {
                $crate::warp::draw(self, rng)
            }
        }
    };
}
pub(crate) use distribution_for_floats;
