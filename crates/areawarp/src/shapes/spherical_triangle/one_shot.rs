//! The one-shot paths: a sample, a light sample or the solid angle of a
//! triangle used once (a renderer's shading point), computing only what
//! that one result needs (the validation, Ω, the anchor of the sample's
//! half and, for a light sample, the plane), bit for bit what the built
//! shape returns.

use super::build::{self, OneEndBounds, Validated};
use super::{SphericalTriangle, robust};
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::light_plane::LightPlane;
use crate::shapes::turns::clamp_unit;
use crate::shapes::wide::narrow3;
use crate::vector::Vec3;
use crate::warp::{LightSample, LightWarp, Warp};

impl<T: Real> SphericalTriangle<T> {
    /// One sample of the triangle with vertex directions `a`, `b`, `c`
    /// without building a [`SphericalTriangle`]: `(ψ(u, v), 1/Ω)` by the
    /// robust map, bit for bit what
    /// `SphericalTriangle::new(a, b, c)?.map_with_pdf(u, v)` returns, at the
    /// cost of the validation, Ω and the one anchor (A or C) the sample
    /// needs. What a renderer calls per shading point.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`].
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::SphericalTriangle;
    /// use areawarp::{Vec3, Warp};
    /// let (a, b, c) = (Vec3::new(1.0f32, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    /// let (p, pdf) = SphericalTriangle::sample_once(&a, &b, &c, &0.3, &0.7)?;
    /// let t = SphericalTriangle::new(a, b, c)?;
    /// assert_eq!((p, pdf), t.map_with_pdf(&0.3, &0.7));
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn sample_once(
        a: &Vec3<T>,
        b: &Vec3<T>,
        c: &Vec3<T>,
        u: &T,
        v: &T,
    ) -> Result<(Vec3<T>, T), WarpError> {
        let tri = build::validated_of(a, b, c)?;
        match Self::sample_core(&tri, u, v) {
            Some(sample) => Ok(sample),
            // The constructor decides (see `sample_core`).
            None => cold(|| Ok(Self::new(a.clone(), b.clone(), c.clone())?.map_with_pdf(u, v))),
        }
    }

    /// [`SphericalTriangle::sample_once`] for the triangle the points `p0`,
    /// `p1`, `p2` subtend from `observer` (as
    /// [`SphericalTriangle::from_points`]).
    ///
    /// # Errors
    /// As [`SphericalTriangle::from_points`], except that the range of the
    /// plane's distances and area densities (which this does not return)
    /// is not checked.
    pub fn sample_once_from_points(
        p0: &Vec3<T>,
        p1: &Vec3<T>,
        p2: &Vec3<T>,
        observer: &Vec3<T>,
        u: &T,
        v: &T,
    ) -> Result<(Vec3<T>, T), WarpError> {
        let hot = Self::from_points_validated::<false>(p0, p1, p2, observer);
        match hot.ok().and_then(|(_, tri)| Self::sample_core(&tri, u, v)) {
            Some(sample) => Ok(sample),
            // The constructor decides (see `sample_core`), without the
            // plane's checks, as above.
            None => cold(|| {
                let t = Self::from_points_with(p0, p1, p2, observer, false)?;
                Ok(t.map_with_pdf(u, v))
            }),
        }
    }

    /// One light sample of the triangle with corners `p0`, `p1`, `p2` seen
    /// from `observer` without building a [`SphericalTriangle`]: the
    /// direction, the point on the triangle, its distance and both
    /// densities, bit for bit what
    /// `SphericalTriangle::from_points(p0, p1, p2, observer)?.sample_light([u, v])`
    /// returns (pbrt-v4's `SampleSphericalTriangle` with the point and
    /// area density of a triangle light), at the cost of the validation,
    /// Ω, the one anchor the sample needs and the plane of the points (its
    /// unit normal, distance and range checks:
    /// `docs/spherical-triangle.md` §5b). What a renderer calls per shading
    /// point when it needs the point (shadow ray) or the area density (MIS
    /// with area sampling); [`SphericalTriangle::sample_once_from_points`]
    /// skips the plane.
    ///
    /// # Errors
    /// As [`SphericalTriangle::from_points`].
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::SphericalTriangle;
    /// use areawarp::{LightWarp, Vec3};
    /// let (p0, p1, p2) = (
    ///     Vec3::new(-1.0f32, -1.0, 2.0),
    ///     Vec3::new(1.0, -1.0, 2.0),
    ///     Vec3::new(0.0, 1.0, 2.0),
    /// );
    /// let o = Vec3::new(0.0, 0.0, 0.0);
    /// let once = SphericalTriangle::sample_light_once(&p0, &p1, &p2, &o, &0.3, &0.7)?;
    /// assert!((once.point.z - 2.0).abs() < 1e-6 && once.pdf_area > 0.0);
    /// let t = SphericalTriangle::from_points(p0, p1, p2, o)?;
    /// assert_eq!(once, t.sample_light([0.3, 0.7]));
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn sample_light_once(
        p0: &Vec3<T>,
        p1: &Vec3<T>,
        p2: &Vec3<T>,
        observer: &Vec3<T>,
        u: &T,
        v: &T,
    ) -> Result<LightSample<T>, WarpError> {
        let hot = Self::from_points_validated::<false>(p0, p1, p2, observer)
            .ok()
            .and_then(|(input, tri)| Some((input, Self::sample_core(&tri, u, v)?)));
        let Some((input, (d, pdf))) = hot else {
            // The constructor decides (see `sample_core`).
            return cold(|| {
                let t = Self::from_points_with(p0, p1, p2, observer, true)?;
                Ok(t.sample_light([u.clone(), v.clone()]))
            });
        };
        // The plane `from_points` builds (after every other check there,
        // so the same error comes first), of the same rounded directions.
        let plane = LightPlane::new(&input, &Vec3::zero(), &pdf, &pdf)?;
        Ok(plane.sample(d, pdf, observer))
    }

    /// The sample of the validated triangle `tri` at `(u, v)` and its
    /// density. Only the anchor of `u`'s half is formed
    /// ([`Validated::anchor_alone`]: one tangent on the arc AC, where the
    /// built shape's constructor forms both ends').
    ///
    /// `None` where a range check fails or the triangle is at the bottom
    /// of `T`'s range ([`OneEndBounds`]): there only the constructor's
    /// checks of both ends decide as it does, and the caller builds the
    /// shape (a cold path that takes the caller's inputs, so that the
    /// validated triangle need not be kept in memory here). Inside the
    /// bounds, the checks of one end pass exactly when the constructor's
    /// pass, with the same values.
    #[inline(always)]
    fn sample_core(tri: &Validated<T::Wide>, u: &T, v: &T) -> Option<(Vec3<T>, T)> {
        let from_a = robust::uses_anchor_a(&clamp_unit(u));
        let anchor = tri.anchor_alone(from_a, &OneEndBounds::of::<T>())?;
        // Inside the bounds, `d` and the anchor's constants are in `T`'s
        // range: of the constructor's range tests (`Scalars::of`,
        // `Anchor::narrow`) only Ω's are needed. The anchor's, redundant
        // here, are kept for `f32`, whose one-shot is measured faster with
        // them (101–102 against 105 ns with today's map), and dropped for
        // wider types (`f64` one-shot / per-sample 2.400–2.409 against
        // 2.432–2.459 with the map before its last change; rounds in
        // `docs/spherical-triangle-one-shot.md`).
        let (_, inv_omega) = build::omega_in::<T>(&tri.omega).ok()?;
        let anchor = if T::precision() <= f32::MANTISSA_DIGITS {
            anchor.narrow::<T>()?
        } else {
            anchor.narrow_in_bounds::<T>()
        };
        let b = narrow3::<T>(&tri.b);
        let b_norm2 = build::norm2(&b);
        let half_omega = &T::narrow(&tri.half_omega);
        let d = robust::map_from(&anchor, &b, &b_norm2, half_omega, u, v);
        Some((d, inv_omega))
    }

    /// The solid angle Ω of the triangle with vertex directions `a`, `b`,
    /// `c` (Van Oosterom–Strackee, computed in [`Real::Wide`]) without
    /// building a [`SphericalTriangle`]: equal to its
    /// [`solid_angle`](SphericalTriangle::solid_angle). The density of its
    /// samples is `1/Ω`.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`], except that the range of the map's
    /// per-sample constants is not checked.
    pub fn solid_angle_of(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> Result<T, WarpError> {
        build::solid_angle_of(a, b, c)
    }
}

/// `f()`, out of line and marked cold: the one-shot's path where the
/// constructor decides (`SphericalTriangle::sample_core`), kept out of the
/// hot path's code.
#[cold]
#[inline(never)]
fn cold<R>(f: impl FnOnce() -> R) -> R {
    f()
}
