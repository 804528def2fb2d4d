//! Planar polygons: validation, triangulation, the ray–polygon hit test and
//! half-space clipping.

use super::Frame;
use areawarp::error::WarpError;
use areawarp::vector::Vec3;

/// Relative tolerance of the coplanarity and perpendicularity checks on
/// input data (vertices computed by rotations or from decimal input are
/// planar only to rounding).
pub(crate) const SHAPE_TOLERANCE: f64 = 1e-9;

/// `(b − a) × (c − a)`.
fn tri_cross(a: &Vec3<f64>, b: &Vec3<f64>, c: &Vec3<f64>) -> Vec3<f64> {
    b.sub(a).cross(&c.sub(a))
}

/// 2-D orientation `(b − a) × (c − a)` (positive: counter-clockwise).
fn orient(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// `true` if the closed segments `ab` and `cd` intersect (2-D).
fn segments_intersect(a: (f64, f64), b: (f64, f64), c: (f64, f64), d: (f64, f64)) -> bool {
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: (f64, f64), q: (f64, f64), r: (f64, f64)| {
        r.0 >= p.0.min(q.0) && r.0 <= p.0.max(q.0) && r.1 >= p.1.min(q.1) && r.1 <= p.1.max(q.1)
    };
    (d1 == 0.0 && on(c, d, a))
        || (d2 == 0.0 && on(c, d, b))
        || (d3 == 0.0 && on(a, b, c))
        || (d4 == 0.0 && on(a, b, d))
}

/// Where a ray meets a polygon: `point = origin + t · direction`.
#[derive(Clone, Debug, PartialEq)]
pub struct Hit {
    /// The ray parameter (the distance, for a unit direction), `> 0`.
    pub t: f64,
    /// The hit point.
    pub point: Vec3<f64>,
}

/// A simple planar polygon in space (convex or not), given by its vertices
/// in order.
///
/// The unit normal follows the vertex order by the right-hand rule
/// (counter-clockwise seen from the side the normal points to), computed by
/// Newell's method. The polygon is triangulated once, by ear clipping, for
/// the hit test and for area sampling.
///
/// # The hit test
/// [`PlanarPolygon::intersect`] tests the ray against each triangle of the
/// triangulation by the signs of the three determinants
/// `det(a − o, b − o, d)` over the triangle's edges `ab` (the side of each
/// edge's line the ray passes on; Plücker coordinates), and takes the
/// distance from the polygon's plane. Ties are inclusive: a ray through an
/// edge or a vertex (a determinant exactly 0) *hits*, both for the polygon's
/// outer boundary and for the internal diagonals of the triangulation. The
/// determinant of an edge shared by two triangles (or by two polygons with
/// bitwise-equal vertices) is computed as the exact negation on the two
/// sides, so no ray slips between adjacent triangles or abutting occluders.
/// A ray in the polygon's plane (`n · d = 0`) misses. These decisions are
/// exact for the computed determinants; the boundary has measure zero, so
/// the integrals do not depend on them.
#[derive(Clone, Debug)]
pub struct PlanarPolygon {
    vertices: Vec<Vec3<f64>>,
    normal: Vec3<f64>,
    offset: f64,
    area: f64,
    triangles: Vec<[usize; 3]>,
    frame: Frame,
}

impl PlanarPolygon {
    /// The polygon with the given vertices, in order (at least three).
    ///
    /// # Errors
    /// - [`WarpError::NonFinite`] for a NaN or infinite coordinate.
    /// - [`WarpError::Degenerate`] for fewer than three vertices, coincident
    ///   consecutive vertices, zero area, a self-intersecting boundary, or a
    ///   polygon that cannot be triangulated (all vertices collinear).
    /// - [`WarpError::InvalidParameter`] for vertices that are not coplanar
    ///   (distance to the mean plane above `10⁻⁹` times the polygon's size).
    pub fn new(vertices: &[Vec3<f64>]) -> Result<Self, WarpError> {
        let n = vertices.len();
        if n < 3 {
            return Err(WarpError::Degenerate {
                what: "polygon with fewer than three vertices",
            });
        }
        if vertices.iter().any(|v| !v.is_finite()) {
            return Err(WarpError::NonFinite {
                what: "polygon vertex",
            });
        }
        for i in 0..n {
            if vertices[i] == vertices[(i + 1) % n] {
                return Err(WarpError::Degenerate {
                    what: "coincident consecutive polygon vertices",
                });
            }
        }
        let v0 = &vertices[0];
        // Newell's normal, relative to v0: |N| = 2 · area.
        let mut newell = Vec3::zero();
        for i in 1..n - 1 {
            newell = newell.add(&tri_cross(v0, &vertices[i], &vertices[i + 1]));
        }
        let extent = vertices
            .iter()
            .map(|v| v.sub(v0).norm())
            .fold(0.0, f64::max);
        let normal = match newell.normalized() {
            Some(nn) if newell.norm() > 1e-24 * extent * extent => nn,
            _ => {
                return Err(WarpError::Degenerate {
                    what: "polygon of zero area",
                });
            }
        };
        if !normal.is_finite() {
            return Err(WarpError::NonFinite {
                what: "polygon normal",
            });
        }
        let off_plane = vertices
            .iter()
            .map(|v| normal.dot(&v.sub(v0)).abs())
            .fold(0.0, f64::max);
        if off_plane > SHAPE_TOLERANCE * extent {
            return Err(WarpError::InvalidParameter {
                name: "vertices",
                expected: "coplanar polygon vertices",
            });
        }
        let frame = Frame::from_normal(&normal)?;
        let flat: Vec<(f64, f64)> = vertices
            .iter()
            .map(|v| {
                let d = v.sub(v0);
                (d.dot(&frame.tangent), d.dot(&frame.bitangent))
            })
            .collect();
        // Simplicity: non-adjacent edges must not meet; adjacent edges must
        // not fold back onto each other.
        for i in 0..n {
            let (a, b) = (flat[i], flat[(i + 1) % n]);
            for j in i + 1..n {
                let (c, d) = (flat[j], flat[(j + 1) % n]);
                let adjacent = j == i + 1 || (i == 0 && j == n - 1);
                if adjacent {
                    // Shared vertex: b == c (j = i + 1) or a == d (wrap).
                    let (p, q, r) = if j == i + 1 { (a, b, d) } else { (b, a, c) };
                    let dot = (p.0 - q.0) * (r.0 - q.0) + (p.1 - q.1) * (r.1 - q.1);
                    if orient(p, q, r) == 0.0 && dot > 0.0 {
                        return Err(WarpError::Degenerate {
                            what: "polygon boundary folds back on itself",
                        });
                    }
                } else if segments_intersect(a, b, c, d) {
                    return Err(WarpError::Degenerate {
                        what: "self-intersecting polygon",
                    });
                }
            }
        }
        let triangles = ear_clip(&flat).ok_or(WarpError::Degenerate {
            what: "polygon that cannot be triangulated",
        })?;
        Ok(PlanarPolygon {
            offset: normal.dot(v0),
            vertices: vertices.to_vec(),
            normal,
            area: newell.norm() / 2.0,
            triangles,
            frame,
        })
    }

    /// The triangle `a, b, c`.
    ///
    /// # Errors
    /// As [`PlanarPolygon::new`].
    pub fn triangle(a: Vec3<f64>, b: Vec3<f64>, c: Vec3<f64>) -> Result<Self, WarpError> {
        Self::new(&[a, b, c])
    }

    /// The rectangle (parallelogram with perpendicular edges) with vertices
    /// `corner`, `corner + edge_a`, `corner + edge_a + edge_b`,
    /// `corner + edge_b`; its normal is along `edge_a × edge_b`.
    ///
    /// # Errors
    /// As [`PlanarPolygon::new`], and [`WarpError::InvalidParameter`] if the
    /// edges are not perpendicular (relative `10⁻⁹`).
    pub fn rectangle(
        corner: Vec3<f64>,
        edge_a: Vec3<f64>,
        edge_b: Vec3<f64>,
    ) -> Result<Self, WarpError> {
        let scale = edge_a.norm() * edge_b.norm();
        if edge_a.dot(&edge_b).abs() > SHAPE_TOLERANCE * scale {
            return Err(WarpError::InvalidParameter {
                name: "edges",
                expected: "perpendicular rectangle edges",
            });
        }
        let p1 = corner.add(&edge_a);
        let p2 = p1.add(&edge_b);
        let p3 = corner.add(&edge_b);
        Self::new(&[corner, p1, p2, p3])
    }

    /// The vertices, in order.
    pub fn vertices(&self) -> &[Vec3<f64>] {
        &self.vertices
    }

    /// The unit normal (right-hand rule over the vertex order).
    pub fn normal(&self) -> &Vec3<f64> {
        &self.normal
    }

    /// The area.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// An orthonormal frame `(tangent, bitangent, normal)` of the plane; the
    /// vertices run counter-clockwise in `(tangent, bitangent)` coordinates.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The triangulation, as vertex index triples (counter-clockwise about
    /// the normal): `n − 2` triangles for `n` vertices (fewer where
    /// vertices lie on straight runs of the boundary).
    pub fn triangle_indices(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// The triangles of the triangulation as vertex triples.
    pub fn triangles(&self) -> impl Iterator<Item = [&Vec3<f64>; 3]> + '_ {
        self.triangles.iter().map(|t| {
            [
                &self.vertices[t[0]],
                &self.vertices[t[1]],
                &self.vertices[t[2]],
            ]
        })
    }

    /// Signed distance of `p` from the plane, positive on the normal's side.
    pub fn signed_distance(&self, p: &Vec3<f64>) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// Where the ray `origin + t · direction`, `t > 0`, meets the polygon
    /// (closed: edges and vertices count; see the type's docs), or `None`.
    /// `direction` need not be normalized (`t` is in its units).
    pub fn intersect(&self, origin: &Vec3<f64>, direction: &Vec3<f64>) -> Option<Hit> {
        let denom = self.normal.dot(direction);
        if denom == 0.0 || !denom.is_finite() {
            return None;
        }
        let t = -self.signed_distance(origin) / denom;
        if !(t > 0.0 && t.is_finite()) {
            return None;
        }
        let hit = self.triangles.iter().any(|tri| {
            let a = self.vertices[tri[0]].sub(origin);
            let b = self.vertices[tri[1]].sub(origin);
            let c = self.vertices[tri[2]].sub(origin);
            let s0 = a.cross(&b).dot(direction);
            let s1 = b.cross(&c).dot(direction);
            let s2 = c.cross(&a).dot(direction);
            (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0)
        });
        hit.then(|| Hit {
            t,
            point: origin.add(&direction.scale(&t)),
        })
    }

    /// `true` if the ray `origin + t · direction` meets the polygon at some
    /// `0 < t < t_max` (strictly).
    pub fn blocks(&self, origin: &Vec3<f64>, direction: &Vec3<f64>, t_max: f64) -> bool {
        self.intersect(origin, direction)
            .is_some_and(|h| h.t < t_max)
    }
}

/// The part of the closed polygon `vertices` in the closed half-space
/// `{p : normal · p ≥ offset}` (Sutherland–Hodgman). The result may contain
/// repeated vertices and, for non-convex input, edges running back and
/// forth along the clipping plane; boundary integrals (Lambert's formula,
/// Newell's area) are unaffected by both. Fewer than three vertices means
/// nothing is left.
pub fn clip_half_space(vertices: &[Vec3<f64>], normal: &Vec3<f64>, offset: f64) -> Vec<Vec3<f64>> {
    let n = vertices.len();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let (a, b) = (&vertices[i], &vertices[(i + 1) % n]);
        let (da, db) = (normal.dot(a) - offset, normal.dot(b) - offset);
        if da >= 0.0 {
            out.push(*a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            // The crossing point, interpolated from the end inside.
            let t = da / (da - db);
            out.push(a.lerp(b, &t));
        }
    }
    if out.len() < 3 { Vec::new() } else { out }
}

/// The area of a closed polygon by Newell's formula (any planar polygon,
/// degenerate edges allowed).
pub fn polygon_area(vertices: &[Vec3<f64>]) -> f64 {
    if vertices.len() < 3 {
        return 0.0;
    }
    let v0 = &vertices[0];
    let mut s = Vec3::zero();
    for i in 1..vertices.len() - 1 {
        s = s.add(&tri_cross(v0, &vertices[i], &vertices[i + 1]));
    }
    s.norm() / 2.0
}

/// Ear clipping of a simple counter-clockwise polygon in the plane; `None`
/// if no ear can be found (degenerate input).
fn ear_clip(p: &[(f64, f64)]) -> Option<Vec<[usize; 3]>> {
    let mut idx: Vec<usize> = (0..p.len()).collect();
    let mut out = Vec::with_capacity(p.len().saturating_sub(2));
    while idx.len() > 3 {
        let m = idx.len();
        let mut clipped = false;
        for k in 0..m {
            let (i0, i1, i2) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
            let (a, b, c) = (p[i0], p[i1], p[i2]);
            if orient(a, b, c) <= 0.0 {
                continue;
            }
            let blocked = idx.iter().any(|&j| {
                if j == i0 || j == i1 || j == i2 {
                    return false;
                }
                let q = p[j];
                if q == a || q == b || q == c {
                    return false;
                }
                orient(a, b, q) >= 0.0 && orient(b, c, q) >= 0.0 && orient(c, a, q) >= 0.0
            });
            if !blocked {
                out.push([i0, i1, i2]);
                idx.remove(k);
                clipped = true;
                break;
            }
        }
        if !clipped {
            // Drop a vertex where the boundary runs straight on (zero-area
            // corner), if any; otherwise give up.
            let k = (0..m).find(|&k| {
                let (a, b, c) = (p[idx[(k + m - 1) % m]], p[idx[k]], p[idx[(k + 1) % m]]);
                orient(a, b, c) == 0.0
            })?;
            idx.remove(k);
        }
    }
    let (a, b, c) = (p[idx[0]], p[idx[1]], p[idx[2]]);
    if orient(a, b, c) > 0.0 {
        out.push([idx[0], idx[1], idx[2]]);
    }
    if out.is_empty() { None } else { Some(out) }
}
