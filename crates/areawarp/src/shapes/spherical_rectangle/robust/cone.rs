//! The cone the rectangle spans from the observer: its faces and corner
//! directions, and the distance of a direction outside it (`outside_by`),
//! built on the first use of `outside_by`.

use super::super::geometry::length;
use super::Robust;
use crate::real::Real;

/// The faces of the cone spanned by the rectangle, for
/// [`Cone::outside_local`] (computed on the first use of `outside_by`).
#[derive(Clone, Debug)]
pub(in crate::shapes::spherical_rectangle) struct Cone<T> {
    /// Inward unit normals of the faces x₀, x₁, y₀, y₁ of the cone spanned
    /// by the rectangle (local vectors `(x, y, z)`, rectangle at `z = −h`).
    normals: [[T; 3]; 4],
    /// `n_x₀·n_y₀`, `n_x₀·n_y₁`, `n_x₁·n_y₀`, `n_x₁·n_y₁`.
    normal_dots: [T; 4],
    /// The unit corner directions.
    corners: [[T; 3]; 4],
}

impl<T: Real> Cone<T> {
    /// The faces and edges of the cone of the rectangle of `r`.
    pub fn new(r: &Robust<T>) -> Self {
        let zero = T::zero();
        let (x0, x1, y0, y1, h) = (
            &r.parts.x0,
            &r.parts.x1,
            &r.parts.y0,
            &r.parts.y1,
            &r.parts.h,
        );
        let unit = |v: [T; 3]| -> [T; 3] {
            let inv = T::one() / &length(&v);
            v.map(|c| c * &inv)
        };
        let normals = [
            unit([h.clone(), zero.clone(), x0.clone()]),
            unit([-h.clone(), zero.clone(), -x1.clone()]),
            unit([zero.clone(), h.clone(), y0.clone()]),
            unit([zero.clone(), -h.clone(), -y1.clone()]),
        ];
        let ndot = |p: &[T; 3], q: &[T; 3]| {
            p[0].clone() * &q[0] + &(p[1].clone() * &q[1]) + &(p[2].clone() * &q[2])
        };
        let normal_dots = [
            ndot(&normals[0], &normals[2]),
            ndot(&normals[0], &normals[3]),
            ndot(&normals[1], &normals[2]),
            ndot(&normals[1], &normals[3]),
        ];
        let corners = [
            unit([x0.clone(), y0.clone(), -h.clone()]),
            unit([x1.clone(), y0.clone(), -h.clone()]),
            unit([x1.clone(), y1.clone(), -h.clone()]),
            unit([x0.clone(), y1.clone(), -h.clone()]),
        ];
        Cone {
            normals,
            normal_dots,
            corners,
        }
    }

    /// How far the unit local direction `(a, b, c)` (`c = −w·ẑ`, positive
    /// towards the plane) lies outside the spherical rectangle: the
    /// Euclidean distance from `ŵ` to the cone K spanned by the rectangle
    /// (the sine of the angular distance below 90°, 1 beyond), 0 inside.
    ///
    /// The nearest point of K is the apex, or on one of the four edge rays
    /// (the corner directions kⱼ: `|ŵ − (ŵ·kⱼ) kⱼ|` when `ŵ·kⱼ > 0`), or in
    /// the relative interior of a face with inward normal nᵢ violated by ŵ
    /// (distance `−nᵢ·ŵ`, valid when the projection `ŵ − (nᵢ·ŵ) nᵢ` satisfies
    /// the two adjacent faces): the distance is the least of the valid
    /// candidates. Exact up to rounding for every direction, including those
    /// opposite to a small or grazing rectangle, where every bounding plane
    /// passes close by and no single half-space gives the distance.
    ///
    /// A face's candidate is taken when its projection satisfies the
    /// adjacent faces to within the rounding error of that test,
    /// `16u (Sᵢ + Sⱼ)` with `Sᵢ = Σₖ |nᵢₖ wₖ|` (the magnitude the dot
    /// product `gᵢ` is formed from): where the observer lies nearly in the
    /// rectangle's plane the four faces nearly coincide (the cone is flat,
    /// its normals within 10⁻¹⁴ of each other or of their opposites), the
    /// test `gⱼ − gᵢ(nᵢ·nⱼ)` is a difference of two nearly equal values,
    /// and its sign is rounding: taken exactly, no face qualified and a
    /// direction 10⁻⁷ from such a sliver was judged 0.07 away by its
    /// nearest corner (`f32`, the light fuzz at seed 132). Within that
    /// slack the face's distance `−gᵢ` is short of the exact one by at
    /// most about the slack (≤ 32u: `Sᵢ ≤ 1`). Derivation:
    /// `docs/spherical-rectangle.md`, item 9.
    pub fn outside_local(&self, a: &T, b: &T, c: &T) -> T {
        let zero = T::zero();
        let z = -c.clone();
        let w = [a.clone(), b.clone(), z];
        let dot =
            |n: &[T; 3]| n[0].clone() * &w[0] + &(n[1].clone() * &w[1]) + &(n[2].clone() * &w[2]);
        // Faces in the order x₀, x₁, y₀, y₁.
        let g: [T; 4] = core::array::from_fn(|i| dot(&self.normals[i]));
        if g.iter().all(|gi| *gi >= zero) {
            return zero;
        }
        // Sᵢ = Σₖ |nᵢₖ wₖ|, the scale of the rounding error of gᵢ: once per
        // face (each enters the tests of up to three faces).
        let scale: [T; 4] = core::array::from_fn(|i| {
            let n = &self.normals[i];
            (n[0].clone() * &w[0]).abs()
                + &(n[1].clone() * &w[1]).abs()
                + &(n[2].clone() * &w[2]).abs()
        });
        let slack_unit = T::from_i64(16) * &T::unit_roundoff();
        let mut best = T::one();
        for i in 0..4 {
            if g[i] >= zero {
                continue;
            }
            // The adjacent faces of an x-face are the y-faces and vice versa:
            // nⱼ·(ŵ − gᵢ nᵢ) = gⱼ − gᵢ (nᵢ·nⱼ).
            let adjacent = if i < 2 { [2, 3] } else { [0, 1] };
            let on_face = adjacent.iter().all(|&j| {
                let nij = &self.normal_dots[i.min(j) * 2 + (i.max(j) - 2)];
                let slack = slack_unit.clone() * &(scale[i].clone() + &scale[j]);
                g[j].clone() - &(g[i].clone() * nij) >= -slack
            });
            if on_face && -g[i].clone() < best {
                best = -g[i].clone();
            }
        }
        for k in &self.corners {
            let t = dot(k);
            if t > zero {
                let d = ((w[0].clone() - &(t.clone() * &k[0])).square()
                    + &(w[1].clone() - &(t.clone() * &k[1])).square()
                    + &(w[2].clone() - &(t * &k[2])).square())
                    .sqrt();
                if d < best {
                    best = d;
                }
            }
        }
        best
    }
}
