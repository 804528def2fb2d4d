//! The papers' experiment scenes, rebuilt from their descriptions.

use super::{
    Emitter, PlanarPolygon, Radiance, Receiver, RectangularPattern, Scene, receivers_on_grid,
};
use areawarp::error::WarpError;
use areawarp::vector::Vec3;

/// A scene with the receivers at which it is measured.
#[derive(Clone, Debug)]
pub struct Setup {
    /// The emitter and occluders.
    pub scene: Scene,
    /// The receivers, in a fixed order.
    pub receivers: Vec<Receiver>,
}

/// The experiment of Ureña, Fajardo and King (2013, Fig. 4 and 7): a
/// double-sided rectangular light of constant radiance `radiance` standing
/// perpendicular on a ground plane, seen from receivers on the ground.
///
/// Geometry: ground `z = 0` with normal `+z`; the light in the plane
/// `y = 0`, `x ∈ [−width/2, width/2]`, `z ∈ [0, height]`, its normal `+y`
/// (double-sided, so it lights both half-planes `y > 0` and `y < 0`).
/// Receivers on the ground at `y > 0`: `lateral` columns at
/// `x = −width … width` (cell centres; `lateral = 1` gives the line `x = 0`)
/// times `rows` distances `y_k = near · (far/near)^(k/(rows−1))`, spaced
/// geometrically so that they are dense near the foot of the light, where
/// area sampling breaks down (the `1/r²` of its estimator).
///
/// The paper renders three spheres on the ground as well; they only
/// occlude part of the light and are left out (the scene model has planar
/// occluders only).
///
/// # Errors
/// [`WarpError::InvalidParameter`] for non-positive sizes or distances,
/// zero counts, or `near > far`.
pub fn standing_rectangle(
    width: f64,
    height: f64,
    radiance: f64,
    near: f64,
    far: f64,
    rows: usize,
    lateral: usize,
) -> Result<Setup, WarpError> {
    if !(width > 0.0 && height > 0.0 && width.is_finite() && height.is_finite()) {
        return Err(WarpError::InvalidParameter {
            name: "light size",
            expected: "finite width and height > 0",
        });
    }
    let light = PlanarPolygon::rectangle(
        Vec3::new(-width / 2.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, height),
        Vec3::new(width, 0.0, 0.0),
    )?;
    let emitter = Emitter::constant(light, radiance)?.with_two_sided(true);
    let up = Vec3::new(0.0, 0.0, 1.0);
    let lines = super::receivers_on_line(
        &Vec3::zero(),
        &Vec3::new(0.0, 1.0, 0.0),
        &up,
        near,
        far,
        rows,
    )?;
    if lateral == 0 {
        return Err(WarpError::InvalidParameter {
            name: "lateral",
            expected: "at least one receiver column",
        });
    }
    let mut receivers = Vec::with_capacity(rows * lateral);
    for r in &lines {
        for i in 0..lateral {
            let x = if lateral == 1 {
                0.0
            } else {
                -width + 2.0 * width * (i as f64 + 0.5) / lateral as f64
            };
            receivers.push(Receiver::new(
                r.position().add(&Vec3::new(x, 0.0, 0.0)),
                up,
            )?);
        }
    }
    Ok(Setup {
        scene: Scene::new(emitter),
        receivers,
    })
}

/// The test scene of Ureña (2000, §5, Fig. 8–9), as described there: "the
/// source is a vertical triangle, and the receiver is the horizontal planar
/// rectangle. An array of rectangles partially occludes the light from
/// source to receiver. Radiance emitted from the source … follows a
/// rectangular pattern". The report gives no dimensions; ours:
///
/// - source: the triangle `(−1, 0, 0.2)`, `(0, 0, 1.6)`, `(1, 0, 0.2)` in
///   the plane `y = 0`, facing `+y`, one-sided, with a
///   [`RectangularPattern::aligned`] checkerboard of `cells × cells` cells
///   over its bounding box, radiances `high` and `low`;
/// - occluders: a 3 × 2 array of horizontal squares of side 0.25 at height
///   `z = 0.6`, centred at `x ∈ {−0.5, 0, 0.5}`, `y ∈ {0.3, 0.7}`;
/// - receivers: a `count × count` grid (cell centres) on the horizontal
///   rectangle `x ∈ [−1.5, 1.5]`, `y ∈ [0.05, 2.05]`, `z = 0`, normal `+z`.
///
/// # Errors
/// As [`RectangularPattern::aligned`] and [`receivers_on_grid`].
pub fn patterned_triangle(
    cells: usize,
    high: f64,
    low: f64,
    count: usize,
) -> Result<Setup, WarpError> {
    let light = PlanarPolygon::triangle(
        Vec3::new(-1.0, 0.0, 0.2),
        Vec3::new(0.0, 0.0, 1.6),
        Vec3::new(1.0, 0.0, 0.2),
    )?;
    let pattern = RectangularPattern::aligned(&light, cells, cells, high, low)?;
    let mut scene = Scene::new(Emitter::new(light, Radiance::Pattern(pattern))?);
    let side = 0.25;
    for cy in [0.3, 0.7] {
        for cx in [-0.5, 0.0, 0.5] {
            scene = scene.with_occluder(PlanarPolygon::rectangle(
                Vec3::new(cx - side / 2.0, cy - side / 2.0, 0.6),
                Vec3::new(side, 0.0, 0.0),
                Vec3::new(0.0, side, 0.0),
            )?);
        }
    }
    let receivers = receivers_on_grid(
        &Vec3::new(-1.5, 0.05, 0.0),
        &Vec3::new(3.0, 0.0, 0.0),
        &Vec3::new(0.0, 2.0, 0.0),
        &Vec3::new(0.0, 0.0, 1.0),
        count,
        count,
    )?;
    Ok(Setup { scene, receivers })
}
