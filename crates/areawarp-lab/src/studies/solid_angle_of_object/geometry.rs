//! The geometry of the study: triangle meshes, their exact solid angle, the
//! ray–triangle test and the angular bounding box.

use super::*;

// ---------------------------------------------------------------------------
// Small f64 vector helpers for the hot loop
// ---------------------------------------------------------------------------

pub(crate) type V3 = [f64; 3];

pub(crate) fn sub3(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn dot3(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross3(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn arr(v: &Vec3<f64>) -> V3 {
    [v.x, v.y, v.z]
}

// ---------------------------------------------------------------------------
// Meshes
// ---------------------------------------------------------------------------

/// How the exact solid angle of a mesh is computed from its faces'.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshKind {
    /// A closed, convex, outward-oriented mesh: Ω = ½ Σ|Ω_f| from outside,
    /// Σ|Ω_f| = 4π from inside.
    ConvexClosed,
    /// An open mesh that no ray from the viewpoint crosses twice (the
    /// caller's promise; e.g. a roof seen from above): Ω = Σ|Ω_f|.
    Open,
}

/// A triangle mesh: vertices (data, `f64`) and faces (vertex indices).
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMesh {
    pub(crate) vertices: Vec<Vec3<f64>>,
    pub(crate) faces: Vec<[usize; 3]>,
    pub(crate) kind: MeshKind,
}

pub(crate) fn check_faces(vertices: &[Vec3<f64>], faces: &[[usize; 3]]) -> Result<(), WarpError> {
    if vertices.iter().any(|v| !v.is_finite()) {
        return Err(WarpError::NonFinite {
            what: "mesh vertex",
        });
    }
    if faces.is_empty() {
        return Err(WarpError::Degenerate {
            what: "mesh without faces",
        });
    }
    for f in faces {
        if f.iter().any(|&i| i >= vertices.len()) {
            return Err(WarpError::InvalidParameter {
                name: "face",
                expected: "vertex indices below the number of vertices",
            });
        }
        let (a, b, c) = (&vertices[f[0]], &vertices[f[1]], &vertices[f[2]]);
        let n = b.sub(a).cross(&c.sub(a)).norm();
        let scale = b.sub(a).norm() * c.sub(a).norm();
        if n.is_nan() || n <= scale * 1e-12 {
            return Err(WarpError::Degenerate {
                what: "mesh face with collinear or coincident vertices",
            });
        }
    }
    Ok(())
}

impl TriangleMesh {
    /// A closed convex mesh with outward-oriented faces (counter-clockwise
    /// seen from outside).
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a non-finite vertex;
    /// [`WarpError::InvalidParameter`] for an index out of range;
    /// [`WarpError::Degenerate`] for a degenerate face, a mesh that is not
    /// closed and consistently oriented (every directed edge once, its
    /// reverse once), not convex, or oriented inward.
    ///
    /// # Example
    /// ```
    /// use areawarp_lab::studies::solid_angle_of_object::TriangleMesh;
    /// use areawarp::Vec3;
    /// let m = TriangleMesh::octahedron(Vec3::new(0.0, 0.0, 3.0), 1.0)?;
    /// assert_eq!(m.faces().len(), 8);
    /// // The same faces, one flipped: rejected.
    /// let mut faces = m.faces().to_vec();
    /// faces[0].swap(1, 2);
    /// assert!(TriangleMesh::convex_closed(m.vertices().to_vec(), faces).is_err());
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn convex_closed(
        vertices: Vec<Vec3<f64>>,
        faces: Vec<[usize; 3]>,
    ) -> Result<Self, WarpError> {
        check_faces(&vertices, &faces)?;
        let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
        for f in &faces {
            for k in 0..3 {
                *edges.entry((f[k], f[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(i, j), &count) in &edges {
            if count != 1 || edges.get(&(j, i)) != Some(&1) {
                return Err(WarpError::Degenerate {
                    what: "mesh is not closed and consistently oriented",
                });
            }
        }
        let n = vertices.len() as f64;
        let centroid = vertices
            .iter()
            .fold(Vec3::zero(), |s, v| s.add(v))
            .scale(&(1.0 / n));
        let size = vertices
            .iter()
            .map(|v| v.sub(&centroid).norm())
            .fold(0.0, f64::max);
        for f in &faces {
            let a = &vertices[f[0]];
            let normal = vertices[f[1]].sub(a).cross(&vertices[f[2]].sub(a));
            let unit = normal.scale(&(1.0 / normal.norm()));
            if unit.dot(&a.sub(&centroid)) <= 0.0 {
                return Err(WarpError::Degenerate {
                    what: "mesh face oriented inward",
                });
            }
            if vertices.iter().any(|v| unit.dot(&v.sub(a)) > size * 1e-12) {
                return Err(WarpError::Degenerate {
                    what: "mesh is not convex",
                });
            }
        }
        Ok(TriangleMesh {
            vertices,
            faces,
            kind: MeshKind::ConvexClosed,
        })
    }

    /// An open mesh. Its exact solid angle is Σ|Ω_f|, valid when no ray
    /// from the viewpoint crosses it twice (not checked).
    ///
    /// # Errors
    /// As [`TriangleMesh::convex_closed`] for vertices, indices and faces.
    pub fn open(vertices: Vec<Vec3<f64>>, faces: Vec<[usize; 3]>) -> Result<Self, WarpError> {
        check_faces(&vertices, &faces)?;
        Ok(TriangleMesh {
            vertices,
            faces,
            kind: MeshKind::Open,
        })
    }

    /// The tetrahedron with vertices `p` (faces oriented outward here).
    ///
    /// # Errors
    /// As [`TriangleMesh::convex_closed`] (e.g. four coplanar points).
    pub fn tetrahedron(p: [Vec3<f64>; 4]) -> Result<Self, WarpError> {
        let faces = orient_outward(&p, &[[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]);
        Self::convex_closed(p.to_vec(), faces)
    }

    /// The regular octahedron with vertices `center ± radius · e_k`.
    ///
    /// # Errors
    /// As [`TriangleMesh::convex_closed`] (e.g. `radius ≤ 0`).
    pub fn octahedron(center: Vec3<f64>, radius: f64) -> Result<Self, WarpError> {
        let r = radius;
        let v: Vec<Vec3<f64>> = [
            [r, 0.0, 0.0],
            [-r, 0.0, 0.0],
            [0.0, r, 0.0],
            [0.0, -r, 0.0],
            [0.0, 0.0, r],
            [0.0, 0.0, -r],
        ]
        .iter()
        .map(|d| center.add(&Vec3::new(d[0], d[1], d[2])))
        .collect();
        let mut faces = Vec::new();
        for x in [0, 1] {
            for y in [2, 3] {
                for z in [4, 5] {
                    faces.push([x, y, z]);
                }
            }
        }
        let faces = orient_outward(&v, &faces);
        Self::convex_closed(v, faces)
    }

    /// The four sloping faces of a square pyramid without its base (an open
    /// "roof"): base square of half-width `half_width` centred at `base`,
    /// in the plane `z = base.z`, apex `height` above it; faces oriented
    /// upward-outward.
    ///
    /// # Errors
    /// As [`TriangleMesh::open`] (e.g. `half_width` or `height` zero).
    pub fn pyramid_roof(base: Vec3<f64>, half_width: f64, height: f64) -> Result<Self, WarpError> {
        let h = half_width;
        let mut v: Vec<Vec3<f64>> = [[h, h], [-h, h], [-h, -h], [h, -h]]
            .iter()
            .map(|d| base.add(&Vec3::new(d[0], d[1], 0.0)))
            .collect();
        v.push(base.add(&Vec3::new(0.0, 0.0, height)));
        let faces = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        Self::open(v, faces)
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Vec3<f64>] {
        &self.vertices
    }
    /// The faces (vertex indices).
    pub fn faces(&self) -> &[[usize; 3]] {
        &self.faces
    }
    /// Closed convex or open.
    pub fn kind(&self) -> MeshKind {
        self.kind
    }
}

/// Orders each face of a convex vertex set so that its normal points away
/// from the centroid.
pub(crate) fn orient_outward(v: &[Vec3<f64>], faces: &[[usize; 3]]) -> Vec<[usize; 3]> {
    let c = v
        .iter()
        .fold(Vec3::zero(), |s, p| s.add(p))
        .scale(&(1.0 / v.len() as f64));
    faces
        .iter()
        .map(|f| {
            let n = v[f[1]].sub(&v[f[0]]).cross(&v[f[2]].sub(&v[f[0]]));
            if n.dot(&v[f[0]].sub(&c)) >= 0.0 {
                *f
            } else {
                [f[0], f[2], f[1]]
            }
        })
        .collect()
}

// ---------------------------------------------------------------------------
// Exact reference
// ---------------------------------------------------------------------------

/// The signed solid angle of the triangle with vertex vectors `a, b, c`
/// (relative to the viewpoint), Van Oosterom–Strackee:
/// `2 atan2(a·(b×c), |a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|)`, in
/// `(−2π, 2π]`; positive when `a, b, c` are counter-clockwise seen from the
/// viewpoint.
///
/// # Example
/// ```
/// use areawarp_lab::studies::solid_angle_of_object::signed_triangle_solid_angle;
/// use areawarp::Vec3;
/// // The octant: π/2.
/// let (x, y, z) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
/// let w = signed_triangle_solid_angle(&x, &y, &z);
/// assert!((w - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// assert!((signed_triangle_solid_angle(&x, &z, &y) + w).abs() < 1e-15);
/// ```
pub fn signed_triangle_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let num = a.dot(&b.cross(c));
    let den = la.clone() * &lb * &lc + &(a.dot(b) * &lc) + &(a.dot(c) * &lb) + &(b.dot(c) * &la);
    num.atan2(&den) * &T::from_i64(2)
}

/// The (unsigned) solid angle of the triangle with vertex vectors `a, b, c`
/// relative to the viewpoint: `|`[`signed_triangle_solid_angle`]`|`, in
/// `[0, 2π]`.
pub fn triangle_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    signed_triangle_solid_angle(a, b, c).abs()
}

/// The exact solid angle of `mesh` seen from `viewpoint`, in `T` (vertices
/// converted as data, differences taken in `T`): for a convex closed mesh
/// `½ Σ|Ω_f|` from outside and `Σ|Ω_f|` (= 4π) from inside — inside when
/// the winding number `Σ Ω_f^signed / 4π` is 1 —, for an open mesh `Σ|Ω_f|`.
///
/// # Errors
/// [`WarpError::NonFinite`] for a non-finite viewpoint;
/// [`WarpError::Degenerate`] if the viewpoint lies on a face (closer than
/// `2^-40` of the mesh size to its plane, inside the face).
///
/// # Example
/// ```
/// use areawarp_lab::studies::solid_angle_of_object::{TriangleMesh, exact_solid_angle};
/// use areawarp::Vec3;
/// let m = TriangleMesh::octahedron(Vec3::new(0.1, 0.2, -0.1), 1.0)?;
/// let inside: f64 = exact_solid_angle(&m, &Vec3::zero())?;
/// assert!((inside - 4.0 * std::f64::consts::PI).abs() < 1e-13);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn exact_solid_angle<T: Real>(
    mesh: &TriangleMesh,
    viewpoint: &Vec3<f64>,
) -> Result<T, WarpError> {
    if !viewpoint.is_finite() {
        return Err(WarpError::NonFinite { what: "viewpoint" });
    }
    check_viewpoint_off_mesh(mesh, viewpoint)?;
    let o: Vec3<T> = viewpoint.convert();
    let rel: Vec<Vec3<T>> = mesh
        .vertices
        .iter()
        .map(|v| v.convert::<T>().sub(&o))
        .collect();
    let mut sum_abs = T::zero();
    let mut sum_signed = T::zero();
    for f in &mesh.faces {
        let w = signed_triangle_solid_angle(&rel[f[0]], &rel[f[1]], &rel[f[2]]);
        sum_abs += &w.abs();
        sum_signed += &w;
    }
    Ok(match mesh.kind {
        MeshKind::Open => sum_abs,
        MeshKind::ConvexClosed => {
            // Winding number: 1 inside (outward faces are seen from behind:
            // positive), 0 outside.
            let two_pi = T::pi() * &T::from_i64(2);
            if sum_signed > two_pi {
                sum_abs
            } else {
                sum_abs / &T::from_i64(2)
            }
        }
    })
}

pub(crate) fn check_viewpoint_off_mesh(
    mesh: &TriangleMesh,
    o: &Vec3<f64>,
) -> Result<(), WarpError> {
    let size = mesh
        .vertices
        .iter()
        .map(|v| v.sub(o).max_abs())
        .fold(0.0, f64::max);
    for f in &mesh.faces {
        let (a, b, c) = (
            &mesh.vertices[f[0]],
            &mesh.vertices[f[1]],
            &mesh.vertices[f[2]],
        );
        let n = b.sub(a).cross(&c.sub(a));
        let n = n.scale(&(1.0 / n.norm()));
        if n.dot(&o.sub(a)).abs() <= size * 2f64.powi(-40) {
            // In the plane: inside the triangle?
            let s = [
                b.sub(a).cross(&o.sub(a)).dot(&n),
                c.sub(b).cross(&o.sub(b)).dot(&n),
                a.sub(c).cross(&o.sub(c)).dot(&n),
            ];
            if s.iter().all(|&x| x >= -size * size * 1e-12) {
                return Err(WarpError::Degenerate {
                    what: "viewpoint lies on the mesh",
                });
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Ray–triangle test
// ---------------------------------------------------------------------------

/// The barycentric slack of [`ray_hits_triangle`]: `2^-30 ≈ 9.3e-10`.
pub const EDGE_TOLERANCE: f64 = 1.0 / (1u64 << 30) as f64;

/// Möller–Trumbore ray–triangle intersection in `f64`: the ray parameter
/// `t > 0` of the hit of `origin + t · dir` with triangle `(a, b, c)`, or
/// `None`.
///
/// Edge policy: *inclusive with slack* — a hit when the barycentric
/// coordinates (as computed in `f64`) satisfy `β ≥ −ε, γ ≥ −ε,
/// β + γ ≤ 1 + ε` with `ε =` [`EDGE_TOLERANCE`]. A ray aimed exactly at a
/// shared edge or vertex computes slightly negative barycentrics for both
/// faces about half the time (rounding); the slack, far above that rounding
/// (`~10^-13` even for the study's millimetre-sized object), makes closed
/// meshes watertight, and the double hits it causes are harmless for the
/// hit/miss count of the solid-angle estimator. The price is a triangle
/// enlarged by `≈ 3ε` of its size, a relative bias `≲ 6ε ≈ 6·10^-9` of an
/// estimated solid angle, far below any Monte Carlo error here. Both sides
/// of the face count (no back-face culling); a ray parallel to the plane
/// (`det = 0`) misses; an origin on the face (`t = 0`) does not count.
///
/// # Example
/// ```
/// use areawarp_lab::studies::solid_angle_of_object::ray_hits_triangle;
/// use areawarp::Vec3;
/// let (a, b, c) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0));
/// let o = Vec3::zero();
/// assert_eq!(ray_hits_triangle(&o, &Vec3::new(0.2, 0.2, 1.0), &a, &b, &c), Some(1.0));
/// // Exactly through the edge bc: inclusive.
/// assert!(ray_hits_triangle(&o, &Vec3::new(0.5, 0.5, 1.0), &a, &b, &c).is_some());
/// assert!(ray_hits_triangle(&o, &Vec3::new(0.6, 0.6, 1.0), &a, &b, &c).is_none());
/// assert!(ray_hits_triangle(&o, &Vec3::new(0.2, 0.2, -1.0), &a, &b, &c).is_none());
/// ```
pub fn ray_hits_triangle(
    origin: &Vec3<f64>,
    dir: &Vec3<f64>,
    a: &Vec3<f64>,
    b: &Vec3<f64>,
    c: &Vec3<f64>,
) -> Option<f64> {
    let tri = RayTri::new(&sub3(&arr(a), &arr(origin)), &arr(b), &arr(c), &arr(origin));
    tri.hit(&arr(dir))
}

/// A triangle relative to the viewpoint: vertex `a − o` and edges.
#[derive(Clone, Debug)]
pub(crate) struct RayTri {
    pub(crate) a: V3,
    pub(crate) e1: V3,
    pub(crate) e2: V3,
}

impl RayTri {
    pub(crate) fn new(a_rel: &V3, b: &V3, c: &V3, o: &V3) -> Self {
        let b_rel = sub3(b, o);
        let c_rel = sub3(c, o);
        RayTri {
            a: *a_rel,
            e1: sub3(&b_rel, a_rel),
            e2: sub3(&c_rel, a_rel),
        }
    }

    /// Möller–Trumbore with the origin at 0.
    #[inline]
    pub(crate) fn hit(&self, d: &V3) -> Option<f64> {
        let p = cross3(d, &self.e2);
        let det = dot3(&self.e1, &p);
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let s = [-self.a[0], -self.a[1], -self.a[2]];
        let beta = dot3(&s, &p) * inv;
        if !(-EDGE_TOLERANCE..=1.0 + EDGE_TOLERANCE).contains(&beta) {
            return None;
        }
        let q = cross3(&s, &self.e1);
        let gamma = dot3(d, &q) * inv;
        if gamma < -EDGE_TOLERANCE || beta + gamma > 1.0 + EDGE_TOLERANCE {
            return None;
        }
        let t = dot3(&self.e2, &q) * inv;
        (t > 0.0).then_some(t)
    }
}

// ---------------------------------------------------------------------------
// Angular bounding box
// ---------------------------------------------------------------------------

/// A box `[u0, u1] × [v0, v0 + v_width]` (the `v` interval taken modulo 1)
/// in the `(u, v)` square of a [`Sphere`]: heights `z = 1 − 2u` and
/// azimuths `φ = 2πv` about the sphere's axis. Its solid angle is
/// `4π (u1 − u0) v_width` (Archimedes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngularBox {
    /// Lowest `u` (highest `z`).
    pub u0: f64,
    /// Highest `u`.
    pub u1: f64,
    /// Start of the azimuth interval, in turns, in `[0, 1)`.
    pub v0: f64,
    /// Length of the azimuth interval, in turns, in `(0, 1]`.
    pub v_width: f64,
}

impl AngularBox {
    /// The whole sphere.
    pub fn full() -> Self {
        AngularBox {
            u0: 0.0,
            u1: 1.0,
            v0: 0.0,
            v_width: 1.0,
        }
    }
    /// The fraction of the unit square (of the sphere) it covers.
    pub fn fraction(&self) -> f64 {
        (self.u1 - self.u0) * self.v_width
    }
    /// Its solid angle, `4π · fraction`.
    pub fn measure(&self) -> f64 {
        4.0 * std::f64::consts::PI * self.fraction()
    }
    /// The point `(u, v)` at relative coordinates `(s, t) ∈ [0, 1]²`.
    pub fn point(&self, s: f64, t: f64) -> (f64, f64) {
        let u = (self.u0 + (self.u1 - self.u0) * s).clamp(0.0, 1.0);
        let mut v = self.v0 + self.v_width * t;
        if v >= 1.0 {
            v -= 1.0;
        }
        (u, v.clamp(0.0, 1.0))
    }
    /// Whether `(u, v)` lies in the box.
    pub fn contains(&self, u: f64, v: f64) -> bool {
        u >= self.u0 && u <= self.u1 && (v - self.v0).rem_euclid(1.0) <= self.v_width
    }
}

/// The geometry of a scene prepared for sampling: triangles relative to the
/// viewpoint and unit vertex directions.
#[derive(Clone, Debug)]
pub(crate) struct Geometry {
    pub(crate) tris: Vec<RayTri>,
    pub(crate) dirs: Vec<Vec3<f64>>,
    pub(crate) faces: Vec<[usize; 3]>,
}

impl Geometry {
    pub(crate) fn new(mesh: &TriangleMesh, viewpoint: &Vec3<f64>) -> Result<Self, WarpError> {
        if !viewpoint.is_finite() {
            return Err(WarpError::NonFinite { what: "viewpoint" });
        }
        check_viewpoint_off_mesh(mesh, viewpoint)?;
        let o = arr(viewpoint);
        let tris = mesh
            .faces
            .iter()
            .map(|f| {
                let a = sub3(&arr(&mesh.vertices[f[0]]), &o);
                RayTri::new(
                    &a,
                    &arr(&mesh.vertices[f[1]]),
                    &arr(&mesh.vertices[f[2]]),
                    &o,
                )
            })
            .collect();
        let dirs = mesh
            .vertices
            .iter()
            .map(|v| {
                v.sub(viewpoint).normalized().ok_or(WarpError::Degenerate {
                    what: "viewpoint coincides with a vertex",
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Geometry {
            tris,
            dirs,
            faces: mesh.faces.clone(),
        })
    }

    #[inline]
    pub(crate) fn hit(&self, d: &V3) -> bool {
        self.tris.iter().any(|t| t.hit(d).is_some())
    }

    /// See [`angular_box`].
    pub(crate) fn angular_box(&self, sphere: &Sphere<f64>, pad: f64) -> AngularBox {
        let k = sphere.axis();
        // (u, v) of each vertex direction, and whether it is (nearly) a pole.
        let mut uv = Vec::with_capacity(self.dirs.len());
        for d in &self.dirs {
            match sphere.inverse(d) {
                Ok([u, v]) => uv.push((u, v)),
                Err(_) => return AngularBox::full(),
            }
        }
        let mut full_phi = false;
        let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut arcs: Vec<(f64, f64)> = Vec::new();
        for d in &self.dirs {
            let z = d.dot(&k);
            zmin = zmin.min(z);
            zmax = zmax.max(z);
            if d.sub(&k.scale(&z)).norm() < 1e-9 {
                full_phi = true; // a vertex at a pole
            }
        }
        for f in &self.faces {
            let (a, b, c) = (&self.dirs[f[0]], &self.dirs[f[1]], &self.dirs[f[2]]);
            // Poles inside the spherical triangle.
            let det = a.dot(&b.cross(c));
            if det != 0.0 {
                let s = det.signum();
                for (pole, is_north) in [(k, true), (k.neg(), false)] {
                    let inside = [(a, b), (b, c), (c, a)]
                        .iter()
                        .all(|(p, q)| p.cross(q).dot(&pole) * s >= -1e-12);
                    if inside {
                        full_phi = true;
                        if is_north {
                            zmax = 1.0;
                        } else {
                            zmin = -1.0;
                        }
                    }
                }
            }
            // Edges: interior z extremes and azimuth sweeps.
            for (i, j) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                let (p, q) = (&self.dirs[i], &self.dirs[j]);
                let n = p.cross(q);
                let nn = n.norm();
                if nn <= 1e-300 {
                    continue; // coincident directions: covered by vertices
                }
                let n = n.scale(&(1.0 / nn));
                let kn = k.dot(&n);
                // The highest and lowest points of the arc's great circle;
                // when on the arc, they extend the z range (a pole on the
                // arc gives z = ±1, hence a full azimuth range below).
                let m = k.sub(&n.scale(&kn));
                let mm = m.norm();
                if mm > 0.0 {
                    let m = m.scale(&(1.0 / mm));
                    for (dir, sign) in [(m, 1.0), (m.neg(), -1.0)] {
                        let on_arc = p.cross(&dir).dot(&n) >= 0.0 && dir.cross(q).dot(&n) >= 0.0;
                        if on_arc {
                            zmax = zmax.max(sign * mm);
                            zmin = zmin.min(sign * mm);
                        }
                    }
                }
                // An arc shorter than π not through a pole sweeps less than
                // half a turn of azimuth, monotonically: the shorter way
                // between its end azimuths. Near half a turn (an arc
                // grazing a pole) the way is ambiguous: give up on φ.
                let (vp, vq) = (uv[i].1, uv[j].1);
                let forward = (vq - vp).rem_euclid(1.0);
                if forward.min(1.0 - forward) > 0.5 - 1e-9 {
                    full_phi = true;
                } else if forward <= 0.5 {
                    arcs.push((vp, forward));
                } else {
                    arcs.push((vq, 1.0 - forward));
                }
            }
        }
        let u0 = ((1.0 - zmax.min(1.0)) / 2.0 - pad).max(0.0);
        let u1 = ((1.0 - zmin.max(-1.0)) / 2.0 + pad).min(1.0);
        let mut bx = AngularBox {
            u0,
            u1,
            v0: 0.0,
            v_width: 1.0,
        };
        if full_phi || u0 <= 0.0 || u1 >= 1.0 {
            return bx;
        }
        let Some((v0, width)) = covering_arc(&mut arcs) else {
            return bx;
        };
        // Angular padding → azimuth padding at the smallest sin θ of the box.
        let sin_min = (2.0 * (u0 * (1.0 - u0)).sqrt()).min(2.0 * (u1 * (1.0 - u1)).sqrt());
        let pad_v = pad / (2.0 * std::f64::consts::PI * sin_min);
        let width = width + 2.0 * pad_v;
        if width < 1.0 && pad_v.is_finite() {
            bx.v0 = (v0 - pad_v).rem_euclid(1.0);
            bx.v_width = width;
            if bx.v0 >= 1.0 {
                bx.v0 = 0.0;
            }
        }
        bx
    }
}

/// The shortest arc of the circle (turns) covering all `arcs` (start,
/// length): the complement of the largest gap. `None` if they cover it all.
pub(crate) fn covering_arc(arcs: &mut [(f64, f64)]) -> Option<(f64, f64)> {
    if arcs.is_empty() || arcs.iter().any(|a| a.1 >= 1.0 || !a.1.is_finite()) {
        return None;
    }
    arcs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first = arcs[0].0;
    let mut reach = first + arcs[0].1;
    let (mut gap_start, mut gap_len) = (0.0, 0.0);
    for &(s, w) in arcs.iter().skip(1) {
        if s > reach && s - reach > gap_len {
            gap_start = reach;
            gap_len = s - reach;
        }
        reach = reach.max(s + w);
    }
    let wrap = first + 1.0 - reach;
    if wrap > gap_len {
        gap_start = reach;
        gap_len = wrap;
    }
    if gap_len <= 0.0 {
        return None;
    }
    Some(((gap_start + gap_len).rem_euclid(1.0), 1.0 - gap_len))
}

/// The angular bounding box of `mesh` seen from `viewpoint` in the `(u, v)`
/// square of `sphere` (its axis and azimuth frame): the `z` range from the
/// vertices, the interior extremes of the edges' great arcs and the poles
/// contained in a face; the azimuth range as the shortest arc covering every
/// edge's sweep (an edge's great arc, shorter than π, sweeps its azimuths
/// monotonically and by less than half a turn unless it passes a pole: the
/// shorter way between its end azimuths); the full azimuth range when the
/// `z` range reaches a pole (a face or an edge contains it), a vertex lies
/// within `10^-9` of one, or an edge sweeps within `10^-9` of half a turn.
/// Padded by `pad` radians (in `u` by `pad`, in `v` by
/// `pad / (2π sin θ_min)`), so that it conservatively contains every
/// direction of the mesh — the estimator stays unbiased.
///
/// # Errors
/// [`WarpError::NonFinite`] / [`WarpError::Degenerate`] for a non-finite
/// viewpoint, one on the mesh or at a vertex.
///
/// # Example
/// ```
/// use areawarp_lab::studies::solid_angle_of_object::{TriangleMesh, angular_box};
/// use areawarp::shapes::Sphere;
/// use areawarp::Vec3;
/// let m = TriangleMesh::octahedron(Vec3::new(3.0, 0.0, 0.0), 0.5)?;
/// let b = angular_box(&m, &Vec3::zero(), &Sphere::new(), 1e-12)?;
/// // Seen along +x near the equator: a small box around v = 0.
/// assert!(b.fraction() < 0.02 && b.contains(0.5, 0.0));
/// # Ok::<(), areawarp::WarpError>(())
/// ```
pub fn angular_box(
    mesh: &TriangleMesh,
    viewpoint: &Vec3<f64>,
    sphere: &Sphere<f64>,
    pad: f64,
) -> Result<AngularBox, WarpError> {
    Ok(Geometry::new(mesh, viewpoint)?.angular_box(sphere, pad))
}
