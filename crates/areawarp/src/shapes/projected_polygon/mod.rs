//! Cosine-weighted sampling of spherical polygons: the projected spherical
//! polygon map of Arvo 2001, §1.4, with a corrected conditional density.
//! Derivation, numerics and the measured speed–accuracy trade of the
//! marginal inversion: `docs/projected-polygon.md`.

mod build;
mod coincident;
mod geometry;
mod light;
mod lune;
mod narrow;
mod ranges;
#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;

use self::build::{Parts, clip, fit_lune, partition, prepare};
use self::coincident::coincidence_scale;
use self::geometry::{Frame, Source, arc_distance, source_solid_angle, unit_direction};
use self::lune::{ActiveLune, LuneCdf, Side, SideFit};
use self::narrow::{Stored, narrow_measure, narrow_parts, representable, unrepresentable};
use super::turns::{atan2_by_atan, clamp_unit};
use crate::error::WarpError;
use crate::real::Real;
use crate::recipe::{Cdf1, Inverter, Newton, Tolerance};
use crate::shapes::light_plane::LightPlane;
use crate::shapes::wide::{narrow3, widen3};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, on_shape_tolerance};
use std::sync::OnceLock;

/// How the marginal CDF of a lune is inverted (step 4 of the recipe; the
/// only step of the map that is not exact).
///
/// Each lune's inverse marginal F⁻¹ is approximated, at the first sample
/// that falls in the lune, by cubics through four points,
/// [`FittedCubic`](crate::recipe::FittedCubic) (Arvo's Vandermonde cubic,
/// eqs. 1.56–1.57): one per half of the lune (each half inverted from its
/// own end), fitted in the variable (F/F_h)^(1/m) that removes the y^(1/m)
/// singularity of F⁻¹ next to an extremal vertex. The settings differ in
/// what they do with the cubic per sample. Costs and accuracy are measured
/// in `docs/projected-polygon.md`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MarginalInversion {
    /// The cubic alone: no evaluation of F per sample (fastest), biased at
    /// the level of the cubic's error (backward error |u − F(φ̂)| up to a
    /// few 10⁻⁴ on the test polygons, relative bias of cosine-weighted
    /// integrals up to ~10⁻⁵).
    Cubic,
    /// The cubic, then `k` safeguarded Newton steps
    /// ([`FittedCubic::invert`](crate::recipe::FittedCubic::invert)); each
    /// step costs one evaluation of F and F' and roughly squares the error.
    CubicNewton(u32),
    /// Safeguarded Newton ([`Newton`]) from the cubic, to convergence
    /// (4 units of roundoff): unbiased to the working precision, and
    /// exactly area-preserving at 256 bits. The default.
    #[default]
    Newton,
}

/// Cosine-weighted directions in a spherical polygon (Arvo 2001, §1.4): the
/// density is proportional to `cos θ` (θ from the receiver's normal, local
/// `+z`), i.e. uniform in the polygon's projection onto the receiver's
/// plane (Nusselt's analogy). Convex or not, around the pole or not, partly
/// below the horizon (clipped).
///
/// # The map
/// With the polygon projected into the unit disk (a direction
/// `(x, y, z) ↦ (x, y)`), the projected solid angle is plane area, and the
/// map samples that planar region in polar coordinates `(φ, r)`:
///
/// 1. `u` picks the azimuth φ by the marginal `F(φ)` = projected area of
///    the polygon between the first meridian and φ. The polygon is cut by
///    the meridians through its vertices into *lunes*; inside a lune the
///    area swept by an edge is `½ n_z α(δ)` (Lambert; α from eq. 1.47), a
///    lune is chosen by binary search on the cumulative areas, and F is
///    inverted inside it by the [`MarginalInversion`] setting.
/// 2. `v` picks the height on that meridian from the conditional density,
///    which is *uniform in r² = 1 − z²* over the union of the polygon's
///    intervals on the meridian (density ∝ z in z — not ∝ z² as printed
///    in Arvo's eq. 1.58–1.60; see the docs).
///
/// `v = 0` is the innermost point (nearest the pole) and `v = 1` the
/// outermost. Cost per sample: O(log n) to find the lune plus O(k) for the k
/// edges crossing it (2 for convex polygons), times the evaluations of F
/// the inversion setting needs.
///
/// # Input and conventions
/// Vertices are directions seen from the origin (any positive length),
/// joined by minor great arcs, in either order; the polygon is the
/// *smaller* of the two regions the boundary bounds (solid angle < 2π).
/// The receiver's normal is `+z` for [`ProjectedPolygon::new`]; with
/// [`ProjectedPolygon::from_points`] the directions are `points − observer`
/// and the normal is given (returned directions are then in world
/// coordinates).
///
/// # Repeated vertices
/// A vertex whose direction coincides with its predecessor's (the same
/// input direction, decided exactly, or not resolved by unit vectors) is
/// dropped: a quad with a repeated corner is the triangle. The shape keeps
/// its input verbatim ([`WarpFamily::at`](crate::warp::WarpFamily::at),
/// [`LightWarp::sample_light`](crate::warp::LightWarp::sample_light)'s
/// plane); see `docs/projected-polygon.md`, "Repeated vertices".
///
/// # Checked in the constructor
/// Fewer than three (distinct) vertices, non-finite or zero directions,
/// antipodal consecutive vertices, a boundary folding back on itself, a
/// boundary that is a great circle (interior ambiguous), zero
/// projected solid angle after clipping (below the horizon), and — cheaply,
/// as a by-product of the lune partition — self-intersections: edges whose
/// order along a meridian changes inside a lune (by more than 2^(−p/2) in
/// r²) and inconsistent inner/outer alternation of the edges crossing a
/// lune. A self-intersection exactly on a vertex meridian may go unnoticed.
/// Given by points ([`ProjectedPolygon::from_points`]), also a light whose
/// plane's distances or densities in area the type cannot hold
/// ([`WarpError::Unrepresentable`]).
///
/// # Precision
/// For `f32` (a scalar narrower than its `Real::Wide`), every decision and
/// every constant of the partition is computed in `f64` (as for the
/// spherical triangle and rectangle) and rounded to `f32` at the first
/// sample (Π at construction; the clamping ranges are then made from the
/// rounded constants, `ranges.rs`): an `f32` polygon is
/// accepted when the `f64` constructor accepts the same values, unless two
/// consecutive unit vertices round together in `f32`, or (given by points)
/// `f32` cannot hold the light's plane ([`WarpError::Unrepresentable`]).
/// Each sample's height
/// on its meridian is held inside the range of its interval's region in the
/// lune, so that edges nearly along a meridian (whose height on a meridian
/// is ill-conditioned) cannot carry it off the polygon
/// (`docs/projected-polygon.md`, Numerics).
///
/// # Density
/// `pdf(p) = max(cos θ, 0) / Π` per steradian, `measure() = Π`, the
/// projected solid angle of the clipped polygon (π × the form factor).
/// [`Warp::pdf`] is 0 for a direction off the polygon (by
/// [`Warp::outside_by`]); [`Warp::pdf_unchecked`] skips that test for a
/// direction known to come from the map.
///
/// # Example
/// ```
/// use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
/// use areawarp::{Vec3, Warp};
///
/// // A square light in the plane z = 1, partly beside the receiver.
/// let light = [
///     Vec3::new(-0.5, 0.2, 1.0),
///     Vec3::new(0.5, 0.2, 1.0),
///     Vec3::new(0.5, 1.2, 1.0),
///     Vec3::new(-0.5, 1.2, 1.0),
/// ];
/// let w = ProjectedPolygon::<f64>::new(&light)?;
/// let p = w.map(&0.3, &0.7);
/// assert!((p.norm() - 1.0).abs() < 1e-15);
/// assert!(w.outside_by(&p) < 1e-15);
/// assert!((w.pdf(&p) - p.z / w.measure()).abs() < 1e-15);
/// let [u, v] = w.inverse(&p).unwrap();
/// assert!((u - 0.3).abs() < 1e-12 && (v - 0.7).abs() < 1e-12);
///
/// // The bare cubic: faster, slightly biased.
/// let fast = ProjectedPolygon::<f64>::new_with(&light, MarginalInversion::Cubic)?;
/// assert!(fast.map(&0.3, &0.7).sub(&p).norm() < 1e-3);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
#[derive(Clone, Debug)]
pub struct ProjectedPolygon<T: Real> {
    source: Source<T>,
    inversion: MarginalInversion,
    frame: Option<Frame<T>>,
    /// The clipped boundary, lunes, edges and intervals as the constructor
    /// made them: in `T`, or in `T::Wide` for a narrower type (`f32`).
    stored: Stored<T>,
    /// For a narrower type, the stored parts rounded to `T`, made at the
    /// first use ([`ProjectedPolygon::parts`]).
    narrowed: OnceLock<Parts<T>>,
    /// The lunes of positive area, by azimuth, with their fitted inverse
    /// marginals (the list made at the first sample,
    /// [`ProjectedPolygon::active`]; each fit at the first sample in its
    /// lune, [`ProjectedPolygon::fit`]).
    active: OnceLock<Vec<ActiveLune<T>>>,
    /// The plane of the corners for `sample_light`.
    plane: PlaneSlot<T>,
    measure: T,
    /// The solid angle before clipping: set by the constructor where its
    /// validation needed it, else computed on first use.
    solid_angle: OnceLock<T>,
    two_pi: T,
}

/// Where [`ProjectedPolygon`]'s light plane is: made by the constructor
/// from points (which refuses a plane `T` cannot hold), or, for vertex
/// directions, at the first `sample_light` (`None` where `T` cannot hold
/// it: the sample's point is then on the unit sphere).
#[derive(Clone, Debug)]
enum PlaneSlot<T> {
    Made(LightPlane<T>),
    Lazy(OnceLock<Option<LightPlane<T>>>),
}

impl<T: Real> ProjectedPolygon<T> {
    /// The polygon with vertex directions `vertices` (receiver normal `+z`),
    /// sampled with the default [`MarginalInversion::Newton`].
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a non-finite vertex,
    /// [`WarpError::Degenerate`] for the cases listed on the type,
    /// [`WarpError::Unrepresentable`] (`f32` only) for a polygon valid in
    /// `f64` two of whose consecutive unit vertices round together in `f32`.
    ///
    /// # Density
    /// `cos θ / Π` per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::ProjectedPolygon;
    /// use areawarp::{Vec3, Warp};
    /// // The octant x, y, z ≥ 0: a quarter of the unit disk when projected.
    /// let o = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0)];
    /// let w = ProjectedPolygon::<f64>::new(&o)?;
    /// assert!((w.measure() - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn new(vertices: &[Vec3<T>]) -> Result<Self, WarpError> {
        Self::new_with(vertices, MarginalInversion::default())
    }

    /// As [`ProjectedPolygon::new`], with the given marginal inversion.
    ///
    /// # Errors
    /// As [`ProjectedPolygon::new`].
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
    /// use areawarp::Vec3;
    /// let tri = [Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.0, 0.3, 1.0), Vec3::new(-0.1, -0.1, 1.0)];
    /// let w = ProjectedPolygon::<f32>::new_with(&tri, MarginalInversion::CubicNewton(2))?;
    /// assert_eq!(w.inversion(), MarginalInversion::CubicNewton(2));
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn new_with(vertices: &[Vec3<T>], inversion: MarginalInversion) -> Result<Self, WarpError> {
        Self::build(
            Source::Directions(vertices.to_vec()),
            vertices.iter().cloned(),
            None,
            inversion,
        )
    }

    /// The polygon with corners `points` (in space) as seen from `observer`
    /// on a receiver with normal `normal` (any positive length): the
    /// directions are `points − observer`, expressed in a frame with
    /// `normal` as `+z`. [`Warp::map`] returns world directions, and
    /// [`Warp::pdf`], [`Warp::inverse`] and [`Warp::outside_by`] take them.
    /// Uses the default [`MarginalInversion`].
    ///
    /// # Errors
    /// As [`ProjectedPolygon::new`], plus [`WarpError::NonFinite`] /
    /// [`WarpError::Degenerate`] for a non-finite observer or a zero or
    /// non-finite normal, and [`WarpError::Unrepresentable`] for a polygon
    /// whose plane's distances or densities in area `T` cannot hold (the
    /// light sample's point, distance and `pdf_area`: corners very far or
    /// very near at either end of `T`'s range, or a plane through the
    /// observer's neighbourhood), as
    /// [`SphericalTriangle::from_points`](crate::shapes::SphericalTriangle::from_points).
    ///
    /// # Density
    /// `max(n · ω, 0) / Π` per steradian, `n` the unit normal.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::ProjectedPolygon;
    /// use areawarp::{Vec3, Warp};
    /// // A triangle light above a receiver tilted towards +x.
    /// let light = [
    ///     Vec3::new(1.0, 0.0, 3.0),
    ///     Vec3::new(2.0, 1.0, 3.0),
    ///     Vec3::new(1.0, 1.0, 3.5),
    /// ];
    /// let w = ProjectedPolygon::<f64>::from_points(
    ///     &light,
    ///     &Vec3::new(0.0, 0.0, 1.0),
    ///     &Vec3::new(0.3, 0.0, 1.0),
    /// )?;
    /// let d = w.map(&0.5, &0.5);
    /// assert!(w.outside_by(&d) < 1e-14);
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn from_points(
        points: &[Vec3<T>],
        observer: &Vec3<T>,
        normal: &Vec3<T>,
    ) -> Result<Self, WarpError> {
        Self::from_points_with(points, observer, normal, MarginalInversion::default())
    }

    /// As [`ProjectedPolygon::from_points`], with the given marginal inversion.
    ///
    /// # Errors
    /// As [`ProjectedPolygon::from_points`].
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
    /// use areawarp::Vec3;
    /// let light = [Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.0, 2.0)];
    /// let o = Vec3::new(0.0, 0.0, 0.0);
    /// let n = Vec3::new(0.0, 0.0, 1.0);
    /// let w = ProjectedPolygon::<f64>::from_points_with(&light, &o, &n, MarginalInversion::Cubic)?;
    /// assert_eq!(w.inversion(), MarginalInversion::Cubic);
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn from_points_with(
        points: &[Vec3<T>],
        observer: &Vec3<T>,
        normal: &Vec3<T>,
        inversion: MarginalInversion,
    ) -> Result<Self, WarpError> {
        if !observer.is_finite() {
            return Err(WarpError::NonFinite { what: "observer" });
        }
        let n = match unit_direction(normal, "receiver normal") {
            Ok(n) => n,
            Err(WarpError::Degenerate { .. }) => {
                return Err(WarpError::Degenerate {
                    what: "the receiver normal is the zero vector",
                });
            }
            Err(e) => return Err(e),
        };
        if points.iter().any(|p| !p.is_finite()) {
            return Err(WarpError::NonFinite {
                what: "polygon vertex",
            });
        }
        let frame = Frame::about_unit(n);
        // The local directions as the validation reads them (no vector of
        // them is made).
        let local = points.iter().map(|p| frame.to_local(&p.sub(observer)));
        Self::build(
            Source::Points {
                points: points.to_vec(),
                observer: observer.clone(),
                normal: normal.clone(),
            },
            local,
            Some(frame.clone()),
            inversion,
        )
    }

    /// The plane of `corners` seen from `observer` for the densities in
    /// solid angle of a polygon of projected solid angle `measure`: from
    /// `1/Π` down to `2^-10` of it (below that, next to the receiver's
    /// horizon, densities in area may round to 0).
    fn light_plane(
        measure: &T,
        corners: &[Vec3<T>],
        observer: &Vec3<T>,
    ) -> Result<LightPlane<T>, WarpError> {
        let pdf_max = T::one() / measure;
        let pdf_min = pdf_max.clone() * &T::exp2i(-10);
        LightPlane::new(corners, observer, &pdf_max, &pdf_min)
    }

    /// The polygon of the local directions `local` (and, given by points,
    /// its light's plane).
    fn build(
        source: Source<T>,
        local: impl ExactSizeIterator<Item = Vec3<T>>,
        frame: Option<Frame<T>>,
        inversion: MarginalInversion,
    ) -> Result<Self, WarpError> {
        // Validation, orientation and solid angle in the wide type (f64 for
        // f32): f32 accepts what f64 accepts on the same vertices, unless
        // two consecutive unit vertices round together in f32. For a
        // narrower T the clipping, the partition and every constant are
        // computed in the wide type too and rounded (`narrow.rs`).
        // Repeated vertices are dropped (`coincident.rs`).
        let (vertices_w, solid_angle_w) = prepare(
            local.map(|v| widen3(&v)),
            &coincidence_scale::<T>(),
            |i, j| source.same_direction(i, j),
        )?;
        let (stored, measure) = if T::precision() < <T::Wide as Real>::precision() {
            if !representable::<T>(&vertices_w) {
                return Err(unrepresentable());
            }
            let (parts_w, _) = clip(&vertices_w, Vec3::clone).and_then(partition)?;
            // Π in T as the rounded lunes sum it; the rounding of the
            // lunes, edges and intervals waits for the first sample.
            let measure = narrow_measure::<T>(&parts_w.lunes).ok_or_else(unrepresentable)?;
            (Stored::Wide(parts_w), measure)
        } else {
            let (parts, measure) = clip(&vertices_w, narrow3::<T>).and_then(partition)?;
            (Stored::Own(parts), measure)
        };
        let solid_angle = OnceLock::new();
        if let Some(omega) = solid_angle_w {
            let _ = solid_angle.set(T::narrow(&omega));
        }
        // A polygon given by points: the emitter's plane now, not at the
        // first `sample_light`, so that a light whose plane (distances,
        // densities in area) `T` cannot hold is refused, as
        // `SphericalTriangle::from_points` refuses it, instead of placing
        // its samples off the emitter.
        let plane = match &source {
            Source::Points {
                points, observer, ..
            } => PlaneSlot::Made(Self::light_plane(&measure, points, observer)?),
            Source::Directions(_) => PlaneSlot::Lazy(OnceLock::new()),
        };
        Ok(ProjectedPolygon {
            source,
            inversion,
            frame,
            stored,
            narrowed: OnceLock::new(),
            active: OnceLock::new(),
            plane,
            measure,
            solid_angle,
            two_pi: T::pi() * &T::from_i64(2),
        })
    }

    /// The partition in `T` (for `f32`, rounded from `f64` on the first
    /// call: a polygon built only for its [`Warp::measure`] never rounds
    /// it).
    #[inline]
    fn parts(&self) -> &Parts<T> {
        match &self.stored {
            Stored::Own(parts) => parts,
            Stored::Wide(wide) => self.narrowed.get_or_init(|| narrow_parts(wide)),
        }
    }

    /// The marginal inversion setting.
    pub fn inversion(&self) -> MarginalInversion {
        self.inversion
    }

    /// The same polygon with another marginal inversion (no recomputation:
    /// the fitted cubics are shared by all settings).
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
    /// use areawarp::Vec3;
    /// let tri = [Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.0, 0.3, 1.0), Vec3::new(-0.1, -0.1, 1.0)];
    /// let w = ProjectedPolygon::<f64>::new(&tri)?.with_inversion(MarginalInversion::Cubic);
    /// assert_eq!(w.inversion(), MarginalInversion::Cubic);
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn with_inversion(mut self, inversion: MarginalInversion) -> Self {
        self.inversion = inversion;
        self
    }

    /// The projected solid angle Π of the clipped polygon (= [`Warp::measure`]).
    pub fn projected_solid_angle(&self) -> T {
        self.measure.clone()
    }

    /// The solid angle of the polygon, before clipping against the horizon
    /// (computed on the first call unless the constructor needed it).
    pub fn solid_angle(&self) -> T {
        self.solid_angle
            .get_or_init(|| source_solid_angle(&self.source, self.frame.as_ref()))
            .clone()
    }

    /// The number of lunes of positive projected area (the azimuth
    /// intervals between consecutive vertex meridians that the polygon
    /// covers).
    pub fn lune_count(&self) -> usize {
        self.active().len()
    }

    /// The largest number of edges crossing one lune (2 for a convex
    /// polygon off the pole, 1 around it): the per-sample cost factor.
    pub fn max_edges_per_lune(&self) -> usize {
        // The counts are the same in the wide partition: no rounding to `T`
        // for them.
        match &self.stored {
            Stored::Own(parts) => parts.lunes.iter().map(|l| l.n_edges).max(),
            Stored::Wide(wide) => wide.lunes.iter().map(|l| l.n_edges).max(),
        }
        .unwrap_or(0)
    }

    /// The active lune that `u` falls in (its index among the lunes and its
    /// fits, [`ProjectedPolygon::fit`]),
    /// the side to invert its marginal from, and the normalized position in
    /// that side's marginal: `y ∈ [0, 1/2]`-ish from the start, or the
    /// complementary position from the end, computed from `1 − u` (exact
    /// for `u ≥ 1/2`) so that the last lune keeps its relative accuracy.
    fn select<'a>(&'a self, parts: &'a Parts<T>, u: &T) -> (usize, &'a [SideFit<T>; 2], Side, T) {
        let u = clamp_unit(u);
        let half = T::from_ratio(1, 2);
        let (zero, one) = (T::zero(), T::one());
        let active = self.active();
        let na = active.len();
        let t = u.clone() * &self.measure;
        let t_rev = (one.clone() - &u) * &self.measure;
        let k = if u <= half {
            active[..na - 1].partition_point(|a| {
                let lune = &parts.lunes[a.lune];
                lune.cum_start.clone() + &lune.area <= t
            })
        } else {
            active[..na - 1].partition_point(|a| parts.lunes[a.lune].cum_after > t_rev)
        };
        let a = &active[k];
        let lune = &parts.lunes[a.lune];
        let fits = self.fit(parts, a);
        let y = ((t - &lune.cum_start) / &lune.area).clamp(&zero, &one);
        if y <= fits[0].fh {
            (a.lune, fits, Side::Start, y)
        } else {
            let y_end = ((t_rev - &lune.cum_after) / &lune.area).clamp(&zero, &one);
            (a.lune, fits, Side::End, y_end)
        }
    }

    /// The lunes of positive area, by azimuth: listed at the first sample
    /// (not by the constructor, which `measure` alone does not need).
    fn active(&self) -> &[ActiveLune<T>] {
        self.active
            .get_or_init(|| ActiveLune::of(&self.parts().lunes))
    }

    /// The fitted inverse marginal of the active lune `a`, from the start and
    /// the end, computed the first time a sample falls in the lune: most of
    /// the construction's cost otherwise, and a renderer that builds the
    /// sampler for a few samples pays only for the lunes it visits.
    fn fit<'a>(&'a self, parts: &Parts<T>, a: &'a ActiveLune<T>) -> &'a [SideFit<T>; 2] {
        a.fit
            .get_or_init(|| fit_lune(&parts.lunes[a.lune], &parts.edges, &parts.pairs))
    }

    fn lune_cdf(parts: &Parts<T>, l: usize, side: Side) -> LuneCdf<'_, T> {
        LuneCdf {
            lune: &parts.lunes[l],
            edges: &parts.edges,
            pairs: &parts.pairs,
            side,
        }
    }

    /// x = F⁻¹(y) from `side` of lune `l` (active), with the configured
    /// inversion, in the transformed half-marginal G of [`SideFit`]
    /// (`fits` its fits, from [`ProjectedPolygon::select`]).
    fn invert_marginal(
        &self,
        parts: &Parts<T>,
        l: usize,
        fits: &[SideFit<T>; 2],
        side: Side,
        y: &T,
    ) -> T {
        let fit = &fits[side as usize];
        let cdf = fit.half(Self::lune_cdf(parts, l, side));
        let target = cdf.target(y);
        let cubic = &fit.cubic;
        if target <= T::zero() && fit.m > 1 && self.inversion != MarginalInversion::Cubic {
            // At a vertex where the density vanishes dx/dy is infinite:
            // x = 0·x_h keeps the value 0 and, over dual numbers, carries
            // the infinite derivative of the target (y/F_h)^(1/m) instead
            // of the false zero of the solvers' end case.
            return target * &fit.xh;
        }
        match self.inversion {
            MarginalInversion::Cubic => {
                let (lo, hi) = cubic.bracket(&target);
                cubic.eval(&target).clamp(&lo, &hi)
            }
            MarginalInversion::CubicNewton(steps) => cubic.invert(&cdf, &target, steps).x,
            MarginalInversion::Newton => {
                let newton = Newton {
                    tolerance: Tolerance::Ulps(4),
                    max_iterations: 100,
                    start: None,
                };
                if target > T::zero() && target < T::one() {
                    // Started from the fitted cubic inside its bracket; an
                    // exact root gets the closing update in `solve_in`, so
                    // dual numbers carry dx/dy = 1/G'(x).
                    let (lo, hi) = cubic.bracket(&target);
                    newton
                        .solve_in(&cdf, &target, cubic.eval(&target), lo, hi)
                        .x
                } else {
                    newton.invert(&cdf, &target).x
                }
            }
        }
    }

    /// The azimuth φ̂ = F⁻¹(u) (radians) that [`Warp::map`] uses for `u`,
    /// computed with the configured inversion: the first half of the map,
    /// exposed to measure the inversion error (backward error
    /// `|u − F(φ̂)|` with [`ProjectedPolygon::marginal_cdf`], forward error
    /// against a converged inversion). The result lies in
    /// `[φ₀, φ₀ + 2π]`, φ₀ the azimuth of the first lune.
    pub fn azimuth(&self, u: &T) -> T {
        let parts = self.parts();
        let (l, fits, side, y) = self.select(parts, u);
        let lune = &parts.lunes[l];
        let x = self.invert_marginal(parts, l, fits, side, &y);
        match side {
            Side::Start => lune.start.clone() + &x,
            Side::End => lune.end_az.clone() - &x,
        }
    }

    /// The marginal CDF F(φ) ∈ [0, 1): the fraction of the projected solid
    /// angle between the first lune's meridian φ₀ and azimuth `phi`
    /// (radians, any turn: φ is reduced into `[φ₀, φ₀ + 2π)`, so that
    /// F(φ₀ + 2π) = F(φ₀) = 0), evaluated in closed form.
    pub fn marginal_cdf(&self, phi: &T) -> T {
        let parts = self.parts();
        let (l, p) = self.locate_azimuth(parts, phi);
        self.cdf_at(parts, l, &p)
    }

    /// F at the reduced azimuth `p` of lune `l`, evaluated from the nearer end.
    fn cdf_at(&self, parts: &Parts<T>, l: usize, p: &T) -> T {
        let lune = &parts.lunes[l];
        let (zero, one) = (T::zero(), T::one());
        if lune.active.is_none() {
            return (lune.cum_start.clone() / &self.measure).clamp(&zero, &one);
        }
        let x = (p.clone() - &lune.start).clamp(&zero, &lune.width);
        if x.clone() * &T::from_i64(2) <= lune.width {
            let f = Self::lune_cdf(parts, l, Side::Start).cdf(&x);
            ((lune.cum_start.clone() + &(f * &lune.area)) / &self.measure).clamp(&zero, &one)
        } else {
            let x = (lune.end_az.clone() - p).clamp(&zero, &lune.width);
            let f = Self::lune_cdf(parts, l, Side::End).cdf(&x);
            (one.clone() - &((lune.cum_after.clone() + &(f * &lune.area)) / &self.measure))
                .clamp(&zero, &one)
        }
    }

    /// The lune containing azimuth `phi` and `phi` reduced into
    /// `[φ₀, φ₀ + 2π)`.
    fn locate_azimuth(&self, parts: &Parts<T>, phi: &T) -> (usize, T) {
        let phi0 = &parts.lunes[0].start;
        let mut p = phi.clone();
        if !(p >= *phi0 && p < phi0.clone() + &self.two_pi) {
            let turns = ((p.clone() - phi0) / &self.two_pi).floor();
            p -= &(turns * &self.two_pi);
            if !(p >= *phi0) {
                p = phi0.clone();
            }
        }
        let l = parts
            .lunes
            .partition_point(|lune| lune.start <= p)
            .saturating_sub(1);
        (l, p)
    }

    /// The side nearer to the reduced azimuth `p` in lune `l`, and the side
    /// coordinate's `(cos x, sin x)`.
    fn side_coordinates(parts: &Parts<T>, l: usize, p: &T) -> (Side, T, T) {
        let lune = &parts.lunes[l];
        let x = p.clone() - &lune.start;
        let (side, x) = if x.clone() * &T::from_i64(2) <= lune.width {
            (Side::Start, x)
        } else {
            (Side::End, lune.end_az.clone() - p)
        };
        let (s, c) = lune.sin_cos_at(&x.clamp(&T::zero(), &lune.width));
        (side, c, s)
    }

    fn local(&self, p: &Vec3<T>) -> Vec3<T> {
        match &self.frame {
            Some(f) => f.to_local(p),
            None => p.clone(),
        }
    }

    /// Whether the unit local direction `d` lies in the clipped polygon, by
    /// the intervals of its lune. A lune the map does not sample (its area
    /// rounded to zero: a sliver narrower than rounding in azimuth, such as
    /// the sliver between a vertex just above the horizon and the crossing
    /// of its edge) is still part of the polygon and is judged by its
    /// intervals too; a lune without edges (a gap between parts of the
    /// polygon) has none and contains nothing.
    fn contains(&self, parts: &Parts<T>, d: &Vec3<T>) -> bool {
        if d.z < T::zero() {
            return false;
        }
        let (l, p) = self.locate_azimuth(parts, &atan2_by_atan(&d.y, &d.x));
        let lune = &parts.lunes[l];
        let (side, c, s) = Self::side_coordinates(parts, l, &p);
        let r2 = d.x.square() + &d.y.square();
        let z2 = d.z.square();
        lune.contains(&parts.edges, &parts.pairs, side, &c, &s, &r2, &z2)
    }
}

impl<T: Real> Warp<T> for ProjectedPolygon<T> {
    type Point = Vec3<T>;

    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let parts = self.parts();
        let (l, fits, side, y) = self.select(parts, u);
        let lune = &parts.lunes[l];
        let x = self.invert_marginal(parts, l, fits, side, &y);
        let (s, c) = x.sin_cos();
        let (cos_phi, sin_phi) = match side {
            // φ = a + x.
            Side::Start => {
                let (ca, sa) = &lune.cs_a;
                (
                    ca.clone() * &c - &(sa.clone() * &s),
                    sa.clone() * &c + &(ca.clone() * &s),
                )
            }
            // φ = b − x.
            Side::End => {
                let (cb, sb) = &lune.cs_b;
                (
                    cb.clone() * &c + &(sb.clone() * &s),
                    sb.clone() * &c - &(cb.clone() * &s),
                )
            }
        };
        let (r2, z2) = lune.sample(
            &parts.edges,
            &parts.pairs,
            &parts.arcs,
            side,
            &c,
            &s,
            &clamp_unit(v),
        );
        let r = r2.sqrt();
        let local = Vec3::new(r.clone() * &cos_phi, r * &sin_phi, z2.sqrt());
        match &self.frame {
            Some(f) => f.to_world(&local),
            None => local,
        }
    }

    /// `cos θ / Π` without the test that `p` lies on the polygon.
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        let l = self.local(p);
        let n = l.norm();
        if !(n > T::zero()) {
            return T::zero();
        }
        (l.z / &n).max(&T::zero()) / &self.measure
    }

    /// Π, the projected solid angle of the clipped polygon.
    fn measure(&self) -> T {
        self.measure.clone()
    }

    /// `(u, v) = (F(φ), G_φ(r²))`; `None` if `p` is not finite or lies
    /// farther than `2^(−p/2)` outside the polygon.
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let refuse = || InverseError::refuse(self, p);
        let d = self.local(p).normalized().ok_or_else(refuse)?;
        let parts = self.parts();
        let (mut l, mut p) = self.locate_azimuth(parts, &atan2_by_atan(&d.y, &d.x));
        if parts.lunes[l].active.is_none() {
            // On a meridian bounding the polygon, within rounding: snap to
            // the nearer end of the neighbouring active lunes.
            let m = parts.lunes.len();
            let next = (1..m)
                .map(|i| (l + i) % m)
                .find(|&j| parts.lunes[j].active.is_some())
                .ok_or_else(refuse)?;
            let prev = (1..m)
                .map(|i| (l + m - i) % m)
                .find(|&j| parts.lunes[j].active.is_some())
                .ok_or_else(refuse)?;
            let to_next = parts.lunes[l].end_az.clone() - &p;
            let to_prev = p.clone() - &parts.lunes[l].start;
            if to_next <= to_prev {
                l = next;
                p = parts.lunes[next].start.clone();
            } else {
                l = prev;
                p = parts.lunes[prev].end_az.clone();
            }
        }
        let u = self.cdf_at(parts, l, &p);
        let (side, c, s) = Self::side_coordinates(parts, l, &p);
        let r2 = d.x.square() + &d.y.square();
        let z2 = d.z.max(&T::zero()).square();
        let v = parts.lunes[l].conditional_cdf(&parts.edges, &parts.pairs, side, &c, &s, &r2, &z2);
        Ok([u, v])
    }

    /// `| |p| − 1 |` plus, for a direction outside the clipped polygon, the
    /// Euclidean distance from `p/|p|` to its boundary.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let l = self.local(p);
        let n = l.norm();
        let Some(d) = l.normalized() else {
            return T::one();
        };
        let radial = (n - &T::one()).abs();
        let parts = self.parts();
        if self.contains(parts, &d) {
            return radial;
        }
        let mut best = T::max_value();
        for arc in &parts.arcs {
            best = best.min(&arc_distance(&d, arc));
        }
        radial + &best
    }
}

crate::warp::distribution_for_floats!(ProjectedPolygon, Vec3);
