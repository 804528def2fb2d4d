//! Occluders with an exact reference: the row of squares standing in for the
//! paper's spheres, and the occluded irradiance by clipping.

use super::*;

// Occluders with an exact reference
// ---------------------------------------------------------------------------

/// A row of opaque squares standing in for the paper's three spheres: in
/// the plane `y = distance` (parallel to the standing light), side `side`,
/// bottom edge at height `bottom`, centred at `x ∈ centers`. They cast
/// penumbrae on the receivers farther than `distance` from the light, so
/// that — as in the paper's renders — the integrand has visibility
/// discontinuities inside the light's solid angle.
#[derive(Clone, Debug, PartialEq)]
pub struct OccluderRow {
    /// Distance of the squares' plane from the light's plane.
    pub distance: f64,
    /// Side of each square.
    pub side: f64,
    /// Height of the squares' bottom edge above the ground.
    pub bottom: f64,
    /// The squares' centres along `x` (disjoint squares).
    pub centers: Vec<f64>,
}

impl OccluderRow {
    /// Three squares of side 0.15 at `y = 0.15`, `z ∈ [0.02, 0.17]`,
    /// `x = −0.35, 0, 0.35`.
    pub fn standard() -> Self {
        OccluderRow {
            distance: 0.15,
            side: 0.15,
            bottom: 0.02,
            centers: vec![-0.35, 0.0, 0.35],
        }
    }

    /// The squares as polygons.
    ///
    /// # Errors
    /// As [`PlanarPolygon::rectangle`] (e.g. a zero side).
    pub fn polygons(&self) -> Result<Vec<PlanarPolygon>, WarpError> {
        self.centers
            .iter()
            .map(|&cx| {
                PlanarPolygon::rectangle(
                    Vec3::new(cx - self.side / 2.0, self.distance, self.bottom),
                    Vec3::new(0.0, 0.0, self.side),
                    Vec3::new(self.side, 0.0, 0.0),
                )
            })
            .collect()
    }
}

/// The convex polygon `subject ∩ clip` (both convex, in the same plane with
/// unit normal `normal`), consecutive duplicates removed.
pub(crate) fn clip_convex(
    subject: &[Vec3<f64>],
    clip: &[Vec3<f64>],
    normal: &Vec3<f64>,
) -> Vec<Vec3<f64>> {
    let k = clip.len() as f64;
    let centroid = clip
        .iter()
        .fold(Vec3::zero(), |a, v| a.add(v))
        .scale(&(1.0 / k));
    let mut out = subject.to_vec();
    for i in 0..clip.len() {
        let (a, b) = (&clip[i], &clip[(i + 1) % clip.len()]);
        let mut inward = normal.cross(&b.sub(a));
        if inward.dot(&centroid.sub(a)) < 0.0 {
            inward = inward.neg();
        }
        out = crate::scene::clip_half_space(&out, &inward, inward.dot(a));
        if out.is_empty() {
            return out;
        }
    }
    let mut dedup: Vec<Vec3<f64>> = Vec::with_capacity(out.len());
    for v in out {
        if dedup.last() != Some(&v) {
            dedup.push(v);
        }
    }
    while dedup.len() > 1 && dedup.first() == dedup.last() {
        dedup.pop();
    }
    dedup
}

/// Lambert's projected solid angle of a convex piece of the light's plane
/// seen from the receiver (0 for a degenerate piece).
pub(crate) fn piece_projected_solid_angle(piece: &[Vec3<f64>], receiver: &Receiver) -> f64 {
    if piece.len() < 3 || crate::scene::polygon_area(piece) <= 0.0 {
        return 0.0;
    }
    match PlanarPolygon::new(piece) {
        Ok(p) => lambert::projected_solid_angle(&p, receiver),
        // A sliver of no measurable area.
        Err(_) => 0.0,
    }
}

/// The exact irradiance at `receiver` from a constant-radiance convex light
/// partly hidden by convex occluders, by Lambert's formula: each occluder
/// lying strictly between the receiver and the light's plane is projected
/// from the receiver onto that plane, and
/// `E = L (Π(light) − Σ_i Π(light ∩ shadow_i))`.
///
/// `None` when this does not apply: non-constant radiance, an occluder
/// straddling the receiver's distance to the light's plane, or overlapping
/// shadows (inclusion–exclusion is not attempted).
pub fn occluded_irradiance(scene: &Scene, receiver: &Receiver) -> Option<f64> {
    let l = match scene.emitter().radiance() {
        crate::scene::Radiance::Constant(l) => *l,
        crate::scene::Radiance::Pattern(_) => return None,
    };
    if !scene.emitter().faces(receiver.position()) {
        return Some(0.0);
    }
    let light = scene.emitter().polygon();
    let x = receiver.position();
    let sx = light.signed_distance(x);
    let mut shadows: Vec<Vec<Vec3<f64>>> = Vec::new();
    for occ in scene.occluders() {
        let sv: Vec<f64> = occ
            .vertices()
            .iter()
            .map(|v| light.signed_distance(v))
            .collect();
        let between = sv.iter().all(|&d| d * sx > 0.0 && d.abs() < sx.abs());
        let beyond = sv.iter().all(|&d| d * sx <= 0.0 || d.abs() > sx.abs());
        if beyond {
            continue;
        }
        if !between {
            return None;
        }
        let shadow: Vec<Vec3<f64>> = occ
            .vertices()
            .iter()
            .zip(&sv)
            .map(|(v, &d)| x.add(&v.sub(x).scale(&(sx / (sx - d)))))
            .collect();
        shadows.push(shadow);
    }
    let n = light.normal();
    for i in 0..shadows.len() {
        for j in i + 1..shadows.len() {
            let both = clip_convex(&shadows[i], &shadows[j], n);
            if crate::scene::polygon_area(&both) > 0.0 {
                return None;
            }
        }
    }
    let mut pi = lambert::projected_solid_angle(light, receiver);
    for shadow in &shadows {
        pi -= piece_projected_solid_angle(&clip_convex(light.vertices(), shadow, n), receiver);
    }
    Some(l * pi.max(0.0))
}
