//! The projected polygon as a light seen from a point ([`LightWarp`]) and
//! as a member of a family over scalar types ([`WarpFamily`]).

use super::ProjectedPolygon;
use super::geometry::Source;
use crate::error::WarpError;
use crate::real::Real;
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
    /// the plane of the polygon's corners (relative to the observer; the
    /// plane through their centroid with Newell's normal `n`, exact for a
    /// planar polygon): `t = (n·c̄)/(n·d)`, `|cos θ_e| = |n·d|/|n|`. The
    /// plane is computed here, not at construction, so that a sampler that
    /// never asks for points does not pay for it.
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T> {
        let [u, v] = uv;
        let (d, pdf) = self.map_with_pdf(&u, &v);
        let (corners, observer) = match &self.source {
            Source::Points {
                points, observer, ..
            } => (points, observer.clone()),
            Source::Directions(v) => (v, Vec3::zero()),
        };
        let k = corners.len();
        let rel = |i: usize| corners[i % k].sub(&observer);
        let mut n = Vec3::zero();
        let mut centroid = Vec3::zero();
        for i in 0..k {
            let (p, q) = (rel(i), rel(i + 1));
            n = n.add(&p.cross(&q));
            centroid = centroid.add(&p);
        }
        let centroid = centroid.scale(&(T::one() / &T::from_i64(k as i64)));
        let dn = d.dot(&n);
        let t = (centroid.dot(&n) / &dn).abs();
        let cos_e = dn.abs() / &n.norm();
        let pdf_area = pdf.clone() * &cos_e / &t.square();
        LightSample {
            point: observer.add(&d.scale(&t)),
            direction: d,
            distance: t,
            pdf,
            pdf_area,
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
