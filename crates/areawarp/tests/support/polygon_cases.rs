//! The random and near-degenerate spherical polygons of the projected
//! polygon fuzz (shared by `polygon_fuzz.rs` and `polygon_rejections.rs`):
//! convex rings of 3 to 6 vertices from 1e-8 rad to 1.4 rad across, needles,
//! nearly collinear and nearly coincident vertices, polygons straddling or
//! grazing the horizon, and planar quads in space seen from observers at
//! scales 1e-30 … 1e30.
#![allow(dead_code)] // each test crate uses a part

use super::light_cases::power;
use proptest::prelude::*;

/// A polygon case: vertex directions (receiver normal +z), or corners in
/// space seen from an observer on a receiver with a normal.
#[derive(Clone, Debug)]
pub struct PolygonCase {
    pub kind: &'static str,
    pub vertices: Vec<[f64; 3]>,
    /// `Some((observer, normal))`: the vertices are points in space.
    pub seen_from: Option<([f64; 3], [f64; 3])>,
}

/// A convex polygon of `n` vertices on a small circle of angular radius
/// `rho` about the direction of elevation `elev` and azimuth `az`, squashed
/// across by `squash` (1 = round).
pub fn ring(n: usize, rho: f64, elev: f64, az: f64, squash: f64, phase: f64) -> Vec<[f64; 3]> {
    let c = [elev.cos() * az.cos(), elev.cos() * az.sin(), elev.sin()];
    let e1 = [-az.sin(), az.cos(), 0.0];
    let e2 = [-elev.sin() * az.cos(), -elev.sin() * az.sin(), elev.cos()];
    (0..n)
        .map(|k| {
            let beta = phase + std::f64::consts::TAU * k as f64 / n as f64;
            let (a, b) = (rho * beta.cos(), rho * squash * beta.sin());
            let t = (a * a + b * b).sqrt();
            let (s, cs) = if t > 0.0 {
                (t.sin() / t, t.cos())
            } else {
                (1.0, 1.0)
            };
            [0, 1, 2].map(|i| cs * c[i] + s * (a * e1[i] + b * e2[i]))
        })
        .collect()
}

// 1.5707: an elevation just below π/2 (not meant as π/2).
#[allow(clippy::approx_constant)]
pub fn polygon_case() -> impl Strategy<Value = PolygonCase> {
    let shape = (
        3usize..=6,
        power(-8.0, 0.15),
        0.0f64..std::f64::consts::TAU,
        0.0f64..1.0,
    );
    prop_oneof![
        // Random convex polygons above the horizon.
        (shape.clone(), 0.05f64..1.5707).prop_map(|((n, rho, az, ph), elev)| PolygonCase {
            kind: "random",
            vertices: ring(n, rho.min(elev * 0.9), elev, az, 1.0, ph),
            seen_from: None,
        }),
        // Straddling or grazing the horizon (clipped by the receiver).
        (shape.clone(), -1.0f64..1.0).prop_map(|((n, rho, az, ph), t)| PolygonCase {
            kind: "horizon",
            vertices: ring(n, rho, t * rho, az, 1.0, ph),
            seen_from: None,
        }),
        // Needles: squashed across by 1e-1 … 1e-9.
        (shape.clone(), 0.1f64..1.5, power(-9.0, -1.0)).prop_map(|((n, rho, az, ph), elev, sq)| {
            PolygonCase {
                kind: "needle",
                vertices: ring(n.max(4), rho, elev, az, sq, ph),
                seen_from: None,
            }
        }),
        // A vertex nudged onto the arc of its neighbours (1e-12 … 1e-3 off).
        (shape.clone(), 0.1f64..1.5, power(-12.0, -3.0)).prop_map(
            |((n, rho, az, ph), elev, off)| {
                let mut v = ring(n.max(4), rho, elev, az, 1.0, ph);
                let (a, b) = (v[0], v[2]);
                let mid = [0, 1, 2].map(|i| a[i] + b[i]);
                let out = [0, 1, 2].map(|i| v[1][i] - mid[i] * 0.5);
                v[1] = [0, 1, 2].map(|i| mid[i] * 0.5 + off * out[i]);
                PolygonCase {
                    kind: "nearly collinear",
                    vertices: v,
                    seen_from: None,
                }
            }
        ),
        // Two vertices 1e-14 … 1e-4 (relative) apart.
        (shape.clone(), 0.1f64..1.5, power(-14.0, -4.0)).prop_map(
            |((n, rho, az, ph), elev, gap)| {
                let mut v = ring(n, rho, elev, az, 1.0, ph);
                let (a, b) = (v[0], v[1]);
                v[1] = [0, 1, 2].map(|i| a[i] + gap * (b[i] - a[i]));
                PolygonCase {
                    kind: "nearly coincident",
                    vertices: v,
                    seen_from: None,
                }
            }
        ),
        // A planar quad in space at scale 1e-30 … 1e30, seen from an observer
        // on a tilted receiver.
        (
            power(-30.0, 30.0),
            -1.0f64..1.0,
            -1.0f64..1.0,
            0.2f64..3.0,
            power(-6.0, 0.5),
            -0.8f64..0.8
        )
            .prop_map(|(scale, x, y, h, size, tilt)| {
                let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.6], [0.0, 1.0]];
                PolygonCase {
                    kind: "points",
                    vertices: corners
                        .iter()
                        .map(|c| {
                            [
                                (x + size * c[0]) * scale,
                                (y + size * c[1]) * scale,
                                h * scale,
                            ]
                        })
                        .collect(),
                    seen_from: Some(([0.0, 0.0, 0.0], [tilt, 0.3 * tilt, 1.0])),
                }
            }),
    ]
}
