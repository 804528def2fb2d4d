//! Sampling strategies for direct lighting from a receiver: every strategy
//! returns unit directions (world coordinates) from the receiver with
//! densities in *solid angle*, so that all of them can be combined by
//! [`Mis`](areawarp::estimate::Mis).

use super::polygon::PlanarPolygon;
use super::reflectance::Reflectance;
use super::{Frame, Receiver};
use areawarp::error::WarpError;
use areawarp::estimate::{Mixture, Sample, Strategy};
use areawarp::shapes::{
    MarginalInversion, PhongLobe, PlanarTriangle, ProjectedPolygon, SphericalRectangle,
    SphericalTriangle,
};
use areawarp::vector::Vec3;
use areawarp::warp::Warp;

/// `p` if it is a usable density (finite, `> 0`).
fn usable(p: f64) -> Option<f64> {
    (p > 0.0 && p.is_finite()).then_some(p)
}

/// A warp of directions about local `+z` (hemisphere, Phong lobe, …) used
/// in a given frame: `sample` rotates the warp's point to world
/// coordinates, `pdf` rotates back. Densities are the warp's (solid angle).
#[derive(Clone, Debug)]
pub struct FramedWarp<W> {
    warp: W,
    frame: Frame,
}

impl<W: Warp<f64, Point = Vec3<f64>>> FramedWarp<W> {
    /// The warp in `frame` (local `+z` = `frame.normal`).
    pub fn new(warp: W, frame: Frame) -> Self {
        FramedWarp { warp, frame }
    }

    /// The wrapped warp.
    pub fn warp(&self) -> &W {
        &self.warp
    }

    /// The frame.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }
}

impl<W: Warp<f64, Point = Vec3<f64>>> Strategy for FramedWarp<W> {
    type Point = Vec3<f64>;

    fn sample(&self, u: f64, v: f64) -> Option<Sample<Vec3<f64>>> {
        let local = self.warp.map(&u, &v);
        let pdf = usable(self.warp.pdf(&local))?;
        Some(Sample {
            point: self.frame.to_world(&local),
            pdf,
        })
    }

    fn pdf(&self, x: &Vec3<f64>) -> f64 {
        let p = self.warp.pdf(&self.frame.to_local(x));
        if p.is_nan() { 0.0 } else { p }
    }
}

/// Cosine-weighted directions about the receiver's normal
/// ([`PhongLobe`] with `k = 1`): density `cos⁺θ / π`.
///
/// # Errors
/// None in practice (the lobe `k = 1` is always valid); the `Result` is
/// that of [`PhongLobe::new`].
pub fn cosine_sampling(receiver: &Receiver) -> Result<FramedWarp<PhongLobe<f64>>, WarpError> {
    Ok(FramedWarp::new(
        PhongLobe::new(1.0)?,
        receiver.frame().clone(),
    ))
}

/// Directions about `axis` with density `(k + 1)/(2π) cos^k α` (`α` from
/// the axis, `α < π/2`).
///
/// # Errors
/// As [`Frame::from_normal`] and [`PhongLobe::new`].
pub fn lobe_sampling(
    axis: &Vec3<f64>,
    exponent: f64,
) -> Result<FramedWarp<PhongLobe<f64>>, WarpError> {
    Ok(FramedWarp::new(
        PhongLobe::new(exponent)?,
        Frame::from_normal(axis)?,
    ))
}

/// BRDF sampling at the receiver for the outgoing direction `outgoing`:
/// for a Lambertian BRDF the cosine lobe; for Phong the mixture of the
/// cosine lobe (probability ∝ `k_d`) and the lobe `cos^n α` about the
/// mirror direction (∝ `k_s`). Directions of the specular lobe may fall
/// below the surface, where the BRDF is 0.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for a BRDF that reflects nothing
/// (`k_d = k_s = 0`), and as [`lobe_sampling`].
pub fn brdf_sampling(
    reflectance: &Reflectance,
    receiver: &Receiver,
    outgoing: &Vec3<f64>,
) -> Result<Mixture<FramedWarp<PhongLobe<f64>>>, WarpError> {
    match *reflectance {
        Reflectance::Lambertian { .. } => Mixture::new(vec![cosine_sampling(receiver)?], &[1.0]),
        Reflectance::Phong {
            diffuse,
            specular,
            exponent,
        } => {
            let mirror = Reflectance::mirror(receiver.normal(), outgoing);
            Mixture::new(
                vec![
                    cosine_sampling(receiver)?,
                    lobe_sampling(&mirror, exponent)?,
                ],
                &[diffuse, specular],
            )
        }
    }
}

/// Uniform area sampling of a polygon (one triangle of its triangulation
/// chosen ∝ area by `u`, then the planar triangle map), returned as the
/// direction from `origin` with the density converted to solid angle:
/// `p_ω = p_A · r² / |cos θ_e|` (`θ_e` between the direction and the
/// polygon's normal). [`Strategy::pdf`] traces the ray to the polygon (0 if
/// it misses).
#[derive(Clone, Debug)]
pub struct AreaSampling {
    polygon: PlanarPolygon,
    /// `(v₀, v₁ − v₀, v₃ − v₀)` when the polygon is a parallelogram: then
    /// `y = v₀ + u e₁ + v e₃` (the usual area sampling of a rectangular
    /// light) instead of the triangulation.
    parallelogram: Option<(Vec3<f64>, Vec3<f64>, Vec3<f64>)>,
    triangles: Vec<PlanarTriangle<f64>>,
    cumulative: Vec<f64>,
    origin: Vec3<f64>,
    inv_area: f64,
}

impl AreaSampling {
    /// Area sampling of `polygon` seen from `origin`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a non-finite origin;
    /// [`WarpError::Degenerate`] if a triangle of the triangulation that
    /// carries area cannot be built as a [`PlanarTriangle`].
    pub fn new(polygon: &PlanarPolygon, origin: &Vec3<f64>) -> Result<Self, WarpError> {
        if !origin.is_finite() {
            return Err(WarpError::NonFinite { what: "origin" });
        }
        let mut triangles = Vec::new();
        let mut cumulative = Vec::new();
        let mut total = 0.0;
        for [a, b, c] in polygon.triangles() {
            match PlanarTriangle::new(*a, *b, *c) {
                Ok(t) => {
                    total += t.area();
                    cumulative.push(total);
                    triangles.push(t);
                }
                // A sliver carrying no measurable area: skip it.
                Err(_) if super::polygon::polygon_area(&[*a, *b, *c]) <= 1e-12 * polygon.area() => {
                }
                Err(e) => return Err(e),
            }
        }
        if triangles.is_empty() || total.is_nan() || total <= 0.0 {
            return Err(WarpError::Degenerate {
                what: "polygon without area",
            });
        }
        for c in &mut cumulative {
            *c /= total;
        }
        if let Some(last) = cumulative.last_mut() {
            *last = 1.0;
        }
        let v = polygon.vertices();
        let parallelogram = (v.len() == 4).then(|| {
            let (e1, e3) = (v[1].sub(&v[0]), v[3].sub(&v[0]));
            let off = v[2].sub(&v[1]).sub(&e3).norm();
            (off <= super::polygon::SHAPE_TOLERANCE * (e1.norm() + e3.norm()))
                .then(|| (v[0], e1, e3))
        });
        Ok(AreaSampling {
            polygon: polygon.clone(),
            parallelogram: parallelogram.flatten(),
            triangles,
            cumulative,
            origin: *origin,
            inv_area: 1.0 / total,
        })
    }

    /// A point uniformly distributed on the polygon (density `1/area` in
    /// the area measure), for `(u, v) ∈ [0, 1]²`: bilinear on a
    /// parallelogram, else a triangle of the triangulation chosen by `u`
    /// (∝ area) and the planar-triangle map.
    pub fn sample_point(&self, u: f64, v: f64) -> Vec3<f64> {
        let u = u.clamp(0.0, 1.0);
        if let Some((o, e1, e3)) = &self.parallelogram {
            let v = v.clamp(0.0, 1.0);
            return o.add(&e1.scale(&u)).add(&e3.scale(&v));
        }
        let i = self
            .cumulative
            .partition_point(|&c| c <= u)
            .min(self.triangles.len() - 1);
        let lo = if i == 0 { 0.0 } else { self.cumulative[i - 1] };
        let width = self.cumulative[i] - lo;
        let ui = if width > 0.0 {
            ((u - lo) / width).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.triangles[i].map(&ui, &v)
    }

    /// The density in the area measure, `1/area`.
    pub fn area_pdf(&self) -> f64 {
        self.inv_area
    }

    /// The polygon.
    pub fn polygon(&self) -> &PlanarPolygon {
        &self.polygon
    }
}

impl Strategy for AreaSampling {
    type Point = Vec3<f64>;

    fn sample(&self, u: f64, v: f64) -> Option<Sample<Vec3<f64>>> {
        let y = self.sample_point(u, v);
        let d = y.sub(&self.origin);
        let r2 = d.norm_squared();
        let w = d.normalized()?;
        let cos_e = self.polygon.normal().dot(&w).abs();
        let pdf = usable(self.inv_area * r2 / cos_e)?;
        Some(Sample { point: w, pdf })
    }

    fn pdf(&self, x: &Vec3<f64>) -> f64 {
        let Some(w) = x.normalized() else {
            return 0.0;
        };
        match self.polygon.intersect(&self.origin, &w) {
            Some(hit) => {
                let cos_e = self.polygon.normal().dot(&w).abs();
                usable(self.inv_area * hit.t * hit.t / cos_e).unwrap_or(0.0)
            }
            None => 0.0,
        }
    }
}

/// A warp of directions from `origin` whose density is in solid angle
/// (a spherical triangle or rectangle, the projected polygon, …),
/// restricted to the directions whose rays from `origin` hit `support`
/// (the planar polygon the warp samples): the density is 0 elsewhere,
/// which the constant-density warps do not do by themselves.
#[derive(Clone, Debug)]
pub struct SolidAngleSampling<W> {
    warp: W,
    support: PlanarPolygon,
    origin: Vec3<f64>,
}

impl<W: Warp<f64, Point = Vec3<f64>>> SolidAngleSampling<W> {
    /// `warp` (directions seen from `origin`), supported on the directions
    /// toward `support`.
    pub fn new(warp: W, support: &PlanarPolygon, origin: &Vec3<f64>) -> Self {
        SolidAngleSampling {
            warp,
            support: support.clone(),
            origin: *origin,
        }
    }

    /// The wrapped warp.
    pub fn warp(&self) -> &W {
        &self.warp
    }
}

impl<W: Warp<f64, Point = Vec3<f64>>> Strategy for SolidAngleSampling<W> {
    type Point = Vec3<f64>;

    fn sample(&self, u: f64, v: f64) -> Option<Sample<Vec3<f64>>> {
        let (w, pdf) = self.warp.map_with_pdf(&u, &v);
        let w = w.normalized()?;
        let pdf = usable(pdf)?;
        Some(Sample { point: w, pdf })
    }

    fn pdf(&self, x: &Vec3<f64>) -> f64 {
        if self.support.intersect(&self.origin, x).is_none() {
            return 0.0;
        }
        let p = self.warp.pdf(x);
        if p.is_nan() { 0.0 } else { p }
    }
}

/// Solid-angle sampling of a polygon by spherical triangles (Arvo 1995):
/// one [`SphericalTriangle`] per triangle of the polygon's triangulation
/// (two for a rectangle), chosen with probability ∝ its solid angle, so
/// that the mixture density is uniform, `1/Ω`, over the polygon's solid
/// angle.
///
/// # Errors
/// As [`SphericalTriangle::from_points`] (e.g. [`WarpError::Degenerate`]
/// for a receiver in the polygon's plane).
pub fn spherical_triangles(
    polygon: &PlanarPolygon,
    origin: &Vec3<f64>,
) -> Result<Mixture<SolidAngleSampling<SphericalTriangle<f64>>>, WarpError> {
    let mut parts = Vec::new();
    let mut weights = Vec::new();
    for [a, b, c] in polygon.triangles() {
        let t = SphericalTriangle::from_points(*a, *b, *c, *origin)?;
        weights.push(t.solid_angle());
        let support = PlanarPolygon::triangle(*a, *b, *c)?;
        parts.push(SolidAngleSampling::new(t, &support, origin));
    }
    Mixture::new(parts, &weights)
}

/// Solid-angle sampling of a rectangle as one spherical rectangle (Ureña,
/// Fajardo and King 2013): [`SphericalRectangle`] with corner `v₀` and
/// edges `v₁ − v₀`, `v₃ − v₀` of the polygon (as built by
/// [`PlanarPolygon::rectangle`]); density `1/Ω`.
///
/// # Errors
/// [`WarpError::InvalidParameter`] if the polygon is not a rectangle (four
/// vertices with `v₂ = v₁ + v₃ − v₀` within `10⁻⁹` relative, perpendicular
/// edges), and as [`SphericalRectangle::new`].
pub fn spherical_rectangle(
    polygon: &PlanarPolygon,
    origin: &Vec3<f64>,
) -> Result<SolidAngleSampling<SphericalRectangle<f64>>, WarpError> {
    let v = polygon.vertices();
    let not_rectangle = WarpError::InvalidParameter {
        name: "polygon",
        expected: "a rectangle (four vertices, v2 = v1 + v3 - v0)",
    };
    if v.len() != 4 {
        return Err(not_rectangle);
    }
    let ex = v[1].sub(&v[0]);
    let ey = v[3].sub(&v[0]);
    let size = ex.norm() + ey.norm();
    if v[2].sub(&v[1]).sub(&ey).norm() > super::polygon::SHAPE_TOLERANCE * size {
        return Err(not_rectangle);
    }
    let w = SphericalRectangle::new(v[0], ex, ey, *origin)?;
    Ok(SolidAngleSampling::new(w, polygon, origin))
}

/// Cosine-weighted sampling of the polygon's solid angle (Arvo 2001, §1.4):
/// [`ProjectedPolygon`] of the polygon seen from the receiver, clipped to
/// its horizon; density `cos⁺θ / Π` on the directions toward the polygon.
///
/// # Errors
/// As [`ProjectedPolygon::from_points`] (e.g. for a polygon entirely
/// below the receiver's horizon).
pub fn projected_polygon(
    polygon: &PlanarPolygon,
    receiver: &Receiver,
) -> Result<SolidAngleSampling<ProjectedPolygon<f64>>, WarpError> {
    projected_polygon_with(polygon, receiver, MarginalInversion::default())
}

/// [`projected_polygon`] with the marginal inverted by `inversion` (e.g.
/// Arvo's fitted cubic alone, [`MarginalInversion::Cubic`]).
///
/// # Errors
/// As [`projected_polygon`].
pub fn projected_polygon_with(
    polygon: &PlanarPolygon,
    receiver: &Receiver,
    inversion: MarginalInversion,
) -> Result<SolidAngleSampling<ProjectedPolygon<f64>>, WarpError> {
    let w = ProjectedPolygon::from_points_with(
        polygon.vertices(),
        receiver.position(),
        receiver.normal(),
        inversion,
    )?;
    Ok(SolidAngleSampling::new(w, polygon, receiver.position()))
}
