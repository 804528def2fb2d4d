//! Exact references for unoccluded polygons: Lambert's formula for the
//! projected solid angle (irradiance, point-to-polygon form factor), by way
//! of [`areawarp::shapes::polygon_measures`].
//!
//! For a polygon seen from a receiver at `x` with unit normal `N`, clipped
//! to the receiver's upper half-space `{p : N·(p − x) ≥ 0}`, with vertex
//! directions `v_i` (relative to `x`), Lambert's formula is
//!
//! `Π = ½ |Σ_i θ_i (n̂_i · N)|`, `θ_i = ∠(v_i, v_{i+1})`,
//! `n̂_i = v_i × v_{i+1} / |v_i × v_{i+1}|`,
//!
//! the projected solid angle `∫_P cos θ dω`; the irradiance from a
//! constant radiance `L` is `E = L Π` and the point-to-polygon form factor
//! is `F = Π / π`. A patterned emitter is the sum over its cells of
//! `L_cell Π(polygon ∩ cell)`.

use super::Receiver;
use super::emitter::{Emitter, Radiance};
use super::polygon::{PlanarPolygon, clip_half_space};
use areawarp::shapes::polygon_measures;
use areawarp::vector::Vec3;

/// The vertices of `vertices ∩ {N·(p − x) ≥ 0}`, relative to `x`.
fn clipped_directions(vertices: &[Vec3<f64>], receiver: &Receiver) -> Vec<Vec3<f64>> {
    let x = receiver.position();
    let n = receiver.normal();
    clip_half_space(vertices, n, n.dot(x))
        .iter()
        .map(|p| p.sub(x))
        .collect()
}

/// The orientation factor that makes Lambert's signed sum positive for
/// pieces of `plane`'s polygon seen from `x`: `+1` when `x` is behind the
/// plane's normal, `−1` in front (see
/// [`polygon_measures`]' orientation convention).
fn orientation(plane: &PlanarPolygon, x: &Vec3<f64>) -> f64 {
    if plane.signed_distance(x) < 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// Lambert's projected solid angle of a piece (vertices in space) of the
/// polygon `plane`, clipped to the receiver's upper half-space, signed so
/// that pieces with the polygon's orientation count positively.
fn piece_projected_solid_angle(
    piece: &[Vec3<f64>],
    plane: &PlanarPolygon,
    receiver: &Receiver,
) -> f64 {
    if plane.signed_distance(receiver.position()) == 0.0 {
        return 0.0;
    }
    let d = clipped_directions(piece, receiver);
    if d.len() < 3 {
        return 0.0;
    }
    orientation(plane, receiver.position())
        * polygon_measures::projected_solid_angle(&d, receiver.normal())
}

/// The projected solid angle `Π = ∫ cos⁺θ dω` of the polygon seen from the
/// receiver (the part above its horizon), by Lambert's formula; 0 for a
/// receiver in the polygon's plane.
pub fn projected_solid_angle(polygon: &PlanarPolygon, receiver: &Receiver) -> f64 {
    piece_projected_solid_angle(polygon.vertices(), polygon, receiver).max(0.0)
}

/// The point-to-polygon form factor `F = Π / π` from a differential area at
/// the receiver to the (unoccluded) polygon.
pub fn form_factor(polygon: &PlanarPolygon, receiver: &Receiver) -> f64 {
    projected_solid_angle(polygon, receiver) / core::f64::consts::PI
}

/// The solid angle the polygon subtends at the receiver's position (whole
/// polygon, not clipped), by the Gauss–Bonnet formula of
/// [`polygon_measures::solid_angle`].
pub fn solid_angle(polygon: &PlanarPolygon, receiver: &Receiver) -> f64 {
    let x = receiver.position();
    let d: Vec<Vec3<f64>> = polygon.vertices().iter().map(|p| p.sub(x)).collect();
    polygon_measures::solid_angle(&d)
}

/// The irradiance `E = ∫ L cos⁺θ dω` at the receiver from the unoccluded
/// emitter: `L Π` for constant radiance, `Σ_cells L_cell Π(P ∩ cell)` for a
/// pattern; 0 if the receiver is behind a one-sided emitter or in its plane.
pub fn irradiance(emitter: &Emitter, receiver: &Receiver) -> f64 {
    let polygon = emitter.polygon();
    if !emitter.faces(receiver.position()) {
        return 0.0;
    }
    match emitter.radiance() {
        Radiance::Constant(l) => l * projected_solid_angle(polygon, receiver),
        Radiance::Pattern(pattern) => pattern
            .pieces(polygon.vertices())
            .filter(|(l, piece)| *l != 0.0 && piece.len() >= 3)
            .map(|(l, piece)| l * piece_projected_solid_angle(&piece, polygon, receiver))
            .sum::<f64>()
            .max(0.0),
    }
}
