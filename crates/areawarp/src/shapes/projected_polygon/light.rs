//! The projected polygon as a light seen from a point ([`LightWarp`]) and
//! as a member of a family over scalar types ([`WarpFamily`]).

use super::geometry::Source;
use super::{PlaneSlot, ProjectedPolygon};
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::light_plane::LightPlane;
use crate::vector::Vec3;
use crate::warp::{LightSample, LightWarp, Warp, WarpFamily};

impl<T: Real> LightWarp<T> for ProjectedPolygon<T> {
    /// The observer given to [`ProjectedPolygon::from_points`] (the origin
    /// for [`ProjectedPolygon::new`]).
    fn observer(&self) -> Vec3<T> {
        match &self.source {
            Source::Points { observer, .. } => observer.clone(),
            Source::Directions(_) => Vec3::zero(),
        }
    }

    /// The cosine-weighted direction ψ(u, v) and the point where it meets
    /// the plane of the polygon's corners (relative to the observer): the
    /// plane through their centroid with the normal of their fan of
    /// triangles (exact for a planar polygon), `t = t₀/|d·n̂|`,
    /// `|cos θ_e| = |d·n̂|` (`shapes/light_plane.rs`).
    /// [`ProjectedPolygon::from_points`] makes the plane and refuses a
    /// polygon whose plane `T` cannot hold (corners far beyond or below its
    /// range, or a plane through the observer's neighbourhood), as
    /// [`SphericalTriangle::from_points`](crate::shapes::SphericalTriangle::from_points)
    /// does: every point is on the emitter. For vertex directions
    /// ([`ProjectedPolygon::new`]) the plane is made at the first call, so
    /// that a sampler of directions never pays for it, and where `T` cannot
    /// hold it the point is the direction itself, on the unit sphere
    /// (distance 1, density in area equal to the density in solid angle).
    /// Densities in area are normal from directions `2^-10` (in cosine)
    /// above the receiver's horizon; nearer it they may round to 0.
    #[inline]
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T> {
        let [u, v] = uv;
        let (d, pdf) = self.map_with_pdf(&u, &v);
        let observer = self.observer();
        let plane = match &self.plane {
            PlaneSlot::Made(plane) => Some(plane),
            // Vertex directions: the plane made here, once.
            PlaneSlot::Lazy(cell) => cell
                .get_or_init(|| {
                    Self::light_plane(&self.measure, self.source.corners(), &observer).ok()
                })
                .as_ref(),
        };
        match plane {
            Some(plane) => plane.sample(d, pdf, &observer),
            None => LightPlane::on_unit_sphere(d, pdf, &observer),
        }
    }
}

impl<T: Real> WarpFamily<T> for ProjectedPolygon<T> {
    type At<S: Real> = ProjectedPolygon<S>;

    /// Rebuilds the polygon from its input converted to `S`, with the same
    /// [`MarginalInversion`](super::MarginalInversion).
    fn at<S: Real>(&self) -> Result<ProjectedPolygon<S>, WarpError> {
        let conv = |v: &[Vec3<T>]| -> Vec<Vec3<S>> { v.iter().map(|p| p.convert()).collect() };
        match &self.source {
            Source::Directions(v) => ProjectedPolygon::new_with(&conv(v), self.inversion),
            Source::Points {
                points,
                observer,
                normal,
            } => ProjectedPolygon::from_points_with(
                &conv(points),
                &observer.convert(),
                &normal.convert(),
                self.inversion,
            ),
        }
    }

    fn name(&self) -> String {
        "projected-polygon".to_string()
    }
}
