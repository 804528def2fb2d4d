//! Study 4 — the solid angle of an object by sampling the sphere
//! (Shao & Badler 1996, §3).
//!
//! # The estimator
//! Archimedes' local theorem makes the axial projection of the unit sphere
//! onto its circumscribed cylinder area-preserving, so a uniform point
//! `(z, φ)` of `[−1, 1] × [0, 2π)` — in the crate's parameters
//! `(u, v) = ((1 − z)/2, φ/2π)` of [`Sphere`] — is a uniform direction. The
//! solid angle Ω of an object seen from a point `o` is the measure of the set
//! of directions whose ray from `o` hits the object, so with `n` directions
//! `d_i` uniform in a region `B` of measure `|B|` that contains the object's
//! directions,
//!
//! Ω̂ = |B| · #{i : ray(o, d_i) hits the object} / n,    E[Ω̂] = Ω.
//!
//! Shao and Badler's remarks, all implemented here:
//! 1. the region is the object's *angular bounding box* in `(z, φ)`
//!    ([`AngularBox`], [`angular_box`]): `|B| = 4π · Δu · Δv` instead of
//!    `4π`, so only that part of the unit square is sampled and the variance
//!    of the hit indicator drops with the miss rate;
//! 2. *stratified* sampling is trivial in `(z, φ)`: a jittered `k × k` grid
//!    over the box ([`Sampling::Stratified`]); only strata cut by the
//!    silhouette contribute variance, so the error falls like `n^(−3/4)`
//!    instead of `n^(−1/2)`;
//! 3. the truncation error of the axial projection concentrates at the
//!    poles; the cure is a *random axis* ([`AxisMode::Random`]) — per sample
//!    for random sampling, and for stratified sampling a coarser stratified
//!    set of axes times a stratified cylinder grid per axis (`≈ n^(1/4)`
//!    axes × `≈ n^(3/4)` samples each).
//!
//! The object is a triangle mesh ([`TriangleMesh`]) and the ray test
//! Möller–Trumbore ([`ray_hits_triangle`]) with an *inclusive* edge policy.
//!
//! # The exact reference
//! The solid angle of one triangle seen from the origin, with vertex vectors
//! `a, b, c` (Van Oosterom & Strackee 1983):
//!
//! tan(Ω/2) = |a · (b × c)| / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|),
//!
//! evaluated as `2 atan2(|det|, den)` (correct also when the denominator is
//! negative, Ω > π), generic over [`Real`]: in `f64` and at 256 bits
//! ([`exact_solid_angle`]). A convex closed mesh covers each direction of its
//! silhouette twice from outside (Ω = ½ Σ|Ω_f|, equivalently the sum over
//! the faces facing the viewer) and every direction once from inside
//! (Ω = Σ|Ω_f| = 4π); an open mesh that no ray from the viewpoint crosses
//! twice (e.g. a roof seen from above) has Ω = Σ|Ω_f|.
//!
//! # `f32` truncation error
//! [`run`] also maps the end-to-end error of `Sphere<f32>` — data `(u, v)`
//! given in `f64`, rounded to `f32` and mapped in `f32` — against the 256-bit
//! map at the exact data, over a grid of cells of `[0, 1]²`, as a profile
//! towards each pole, and over world directions for a fixed and a random
//! axis. The `f32` inputs near `u = 1` are spaced by `2^-24`, so the height
//! `z = 1 − 2u` is quantized to `2^-23` and the direction near the south
//! pole by `≈ 2^-23/sin θ`: the error grows like `1/sin θ` there, while
//! floats are dense near `u = 0` and the north pole stays accurate. The
//! evaluation alone (inputs first rounded to `f32`, as in
//! [`areawarp::harness::precision`]) stays within a few units everywhere.
//!
//! # Example
//! ```
//! use areawarp_lab::studies::solid_angle_of_object::{SolidAngleConfig, run};
//!
//! let mut config = SolidAngleConfig::quick();
//! config.sample_counts = vec![16, 256];
//! config.repetitions = 4;
//! config.heat_map_cells = 8;
//! config.world_samples = 256;
//! config.profile_points = 2;
//! let study = run(&config)?;
//! assert!(study.rows.iter().all(|r| r.rms_relative_error.is_finite()));
//! assert!(study.to_markdown().contains("Solid angle of an object"));
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use crate::figures::{self, Axis, Figure, HeatMap, Plot, Scale, Series};
use areawarp::error::WarpError;
use areawarp::real::{Real, convert};
use areawarp::shapes::Sphere;
use areawarp::vector::Vec3;
use areawarp::warp::{Warp, WarpFamily};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

type Reference = areawarp::real::Mpfr256;

// ---------------------------------------------------------------------------
// Small f64 vector helpers for the hot loop
// ---------------------------------------------------------------------------

type V3 = [f64; 3];

fn sub3(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot3(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross3(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn arr(v: &Vec3<f64>) -> V3 {
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
    vertices: Vec<Vec3<f64>>,
    faces: Vec<[usize; 3]>,
    kind: MeshKind,
}

fn check_faces(vertices: &[Vec3<f64>], faces: &[[usize; 3]]) -> Result<(), WarpError> {
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
fn orient_outward(v: &[Vec3<f64>], faces: &[[usize; 3]]) -> Vec<[usize; 3]> {
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

fn check_viewpoint_off_mesh(mesh: &TriangleMesh, o: &Vec3<f64>) -> Result<(), WarpError> {
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
struct RayTri {
    a: V3,
    e1: V3,
    e2: V3,
}

impl RayTri {
    fn new(a_rel: &V3, b: &V3, c: &V3, o: &V3) -> Self {
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
    fn hit(&self, d: &V3) -> Option<f64> {
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
struct Geometry {
    tris: Vec<RayTri>,
    dirs: Vec<Vec3<f64>>,
    faces: Vec<[usize; 3]>,
}

impl Geometry {
    fn new(mesh: &TriangleMesh, viewpoint: &Vec3<f64>) -> Result<Self, WarpError> {
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
    fn hit(&self, d: &V3) -> bool {
        self.tris.iter().any(|t| t.hit(d).is_some())
    }

    /// See [`angular_box`].
    fn angular_box(&self, sphere: &Sphere<f64>, pad: f64) -> AngularBox {
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
fn covering_arc(arcs: &mut [(f64, f64)]) -> Option<(f64, f64)> {
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

// ---------------------------------------------------------------------------
// Scenes and methods
// ---------------------------------------------------------------------------

/// An object and the point it is seen from.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// A short name (used in file names).
    pub name: String,
    /// One line for the report.
    pub description: String,
    /// The object.
    pub mesh: TriangleMesh,
    /// The point it is seen from.
    pub viewpoint: Vec3<f64>,
}

/// The study's default scenes, all seen from the origin:
/// - `tetrahedron`: an irregular tetrahedron (closed, convex) off to the
///   side, above the equator;
/// - `roof`: an open pyramid roof below the viewpoint, straddling the
///   south pole of the default axis;
/// - `speck`: an octahedron of radius `10^-3` one unit below the viewpoint
///   (slightly off-axis) — a 2 mm object seen from 1 m, inside the region
///   where `f32` heights near the south pole are quantized.
///
/// # Errors
/// Never in practice (the meshes are valid); propagated from the mesh constructors.
pub fn default_scenes() -> Result<Vec<Scene>, WarpError> {
    let v = Vec3::new;
    Ok(vec![
        Scene {
            name: "tetrahedron".into(),
            description: "irregular tetrahedron (closed, convex), off to the side".into(),
            mesh: TriangleMesh::tetrahedron([
                v(1.4, 0.3, 0.5),
                v(1.9, 1.1, 0.2),
                v(1.1, 1.2, 0.9),
                v(1.8, 0.6, 1.3),
            ])?,
            viewpoint: Vec3::zero(),
        },
        Scene {
            name: "roof".into(),
            description: "open pyramid roof (4 faces) below the viewpoint, around the south pole"
                .into(),
            mesh: TriangleMesh::pyramid_roof(v(0.15, -0.1, -1.5), 1.0, 0.6)?,
            viewpoint: Vec3::zero(),
        },
        Scene {
            name: "speck".into(),
            description: "octahedron of radius 1e-3 one unit straight below (2 mm seen from 1 m)"
                .into(),
            mesh: TriangleMesh::octahedron(v(3e-4, -2e-4, -1.0), 1e-3)?,
            viewpoint: Vec3::zero(),
        },
    ])
}

/// How the points of the cylinder are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// Independent uniform points.
    Random,
    /// A jittered `k × k` grid (`n = k²`): one uniform point per stratum.
    Stratified,
}

/// The cylinder axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisMode {
    /// The `+z` axis ([`Sphere::new`]).
    Fixed,
    /// Random axes ([`Sphere::with_random_axis`], [`Sphere::with_axis`]):
    /// one per sample for [`Sampling::Random`]; for [`Sampling::Stratified`]
    /// a jittered `a × a` set of axes mapped through the sphere, each with a
    /// jittered `c × c` cylinder grid in its own box (`n = 4^k`,
    /// `a = 2^⌊k/4⌋`, `c = 2^(k − ⌊k/4⌋)`: `a² ≈ n^(1/4)` axes). Splitting
    /// `n` samples over `m` independently stratified boxes costs a factor
    /// `≈ m^(1/4)` in error against one box (`(n/m)^(−3/4)/√m`), so the
    /// axis grid is kept coarse, as Shao and Badler suggest.
    Random,
}

/// The scalar of the sphere map (the ray test is always `f64`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// `Sphere<f32>`: `(u, v)` rounded to `f32`.
    F32,
    /// `Sphere<f64>`.
    F64,
}

/// One estimator variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Method {
    /// Random or stratified points.
    pub sampling: Sampling,
    /// Fixed or random axis.
    pub axis: AxisMode,
    /// `f32` or `f64` sphere map.
    pub precision: Precision,
    /// Sample only the object's angular bounding box (else the whole sphere).
    pub bounding_box: bool,
}

impl Method {
    /// A short name, e.g. `stratified/fixed/f64/box`.
    pub fn name(&self) -> String {
        format!(
            "{}/{}/{}/{}",
            match self.sampling {
                Sampling::Random => "random",
                Sampling::Stratified => "stratified",
            },
            match self.axis {
                AxisMode::Fixed => "fixed",
                AxisMode::Random => "random-axis",
            },
            match self.precision {
                Precision::F32 => "f32",
                Precision::F64 => "f64",
            },
            if self.bounding_box { "box" } else { "sphere" }
        )
    }

    /// The study's methods: random and stratified in the box (fixed axis,
    /// `f64`); stratified over the whole sphere; random and stratified with
    /// random axes (`f64`); stratified with fixed and random axes in `f32`.
    pub fn standard() -> Vec<Method> {
        let m = |sampling, axis, precision, bounding_box| Method {
            sampling,
            axis,
            precision,
            bounding_box,
        };
        use AxisMode::{Fixed, Random as Rand};
        use Precision::{F32, F64};
        vec![
            m(Sampling::Random, Fixed, F64, true),
            m(Sampling::Stratified, Fixed, F64, true),
            m(Sampling::Stratified, Fixed, F64, false),
            m(Sampling::Random, Rand, F64, true),
            m(Sampling::Stratified, Rand, F64, true),
            m(Sampling::Stratified, Fixed, F32, true),
            m(Sampling::Stratified, Rand, F32, true),
        ]
    }
}

// ---------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------

/// The study's size and seed.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidAngleConfig {
    /// Master seed; every job derives its own from it.
    pub seed: u64,
    /// Sample counts, each a power of 4 (`4, 16, 64, …`).
    pub sample_counts: Vec<usize>,
    /// Independent estimates per (scene, method, n), at least 2.
    pub repetitions: usize,
    /// The scenes.
    pub scenes: Vec<Scene>,
    /// The methods.
    pub methods: Vec<Method>,
    /// Cells per side of the `f32` error map over `[0, 1]²`.
    pub heat_map_cells: usize,
    /// Points per cell side of that map (`p × p` jittered points per cell).
    pub heat_map_points: usize,
    /// Samples of the world-direction error maps (fixed and random axis).
    pub world_samples: usize,
    /// Points per distance of the pole profile.
    pub profile_points: usize,
    /// The largest `n` run with a random axis *per sample*
    /// ([`Sampling::Random`] × [`AxisMode::Random`]), which rebuilds the
    /// bounding box for every sample (a few µs each); larger counts are
    /// skipped for that method.
    pub per_sample_axis_max_n: usize,
}

impl SolidAngleConfig {
    /// A quick run (a second or two in `--release` on 2 cores): `n` up to
    /// 4096, 12 repetitions, a 64 × 64 error map.
    ///
    /// The scenes are [`default_scenes`] (valid by construction; were one
    /// not, the list would be empty and [`run`] would reject it).
    pub fn quick() -> Self {
        SolidAngleConfig {
            seed: 0x5EED_5A0B,
            sample_counts: (1..=6).map(|k| 1usize << (2 * k)).collect(),
            repetitions: 12,
            scenes: default_scenes().unwrap_or_default(),
            methods: Method::standard(),
            heat_map_cells: 64,
            heat_map_points: 2,
            world_samples: 20_000,
            profile_points: 16,
            per_sample_axis_max_n: 4096,
        }
    }
}

impl Default for SolidAngleConfig {
    /// The report's size (≈ 11 s in `--release` on 2 cores): `n` from 4 to
    /// 65536, 32 repetitions, a 128 × 128 error map with 2 × 2 points per
    /// cell, 100 000 world samples per axis mode.
    fn default() -> Self {
        SolidAngleConfig {
            sample_counts: (1..=8).map(|k| 1usize << (2 * k)).collect(),
            repetitions: 32,
            heat_map_cells: 128,
            heat_map_points: 2,
            world_samples: 100_000,
            profile_points: 64,
            ..Self::quick()
        }
    }
}

impl SolidAngleConfig {
    fn validate(&self) -> Result<(), WarpError> {
        if self.sample_counts.is_empty()
            || self
                .sample_counts
                .iter()
                .any(|&n| n < 4 || !n.is_power_of_two() || n.trailing_zeros() % 2 != 0)
        {
            return Err(WarpError::InvalidParameter {
                name: "sample_counts",
                expected: "a non-empty list of powers of 4 (4, 16, 64, …)",
            });
        }
        if self.repetitions < 2 {
            return Err(WarpError::InvalidParameter {
                name: "repetitions",
                expected: "at least 2",
            });
        }
        if self.scenes.is_empty() || self.methods.is_empty() {
            return Err(WarpError::InvalidParameter {
                name: "scenes/methods",
                expected: "at least one scene and one method",
            });
        }
        if self.heat_map_cells == 0
            || self.heat_map_points == 0
            || self.world_samples == 0
            || self.profile_points == 0
        {
            return Err(WarpError::InvalidParameter {
                name: "heat_map_cells/heat_map_points/world_samples/profile_points",
                expected: "positive",
            });
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------

/// A scene's exact solid angle.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSummary {
    /// Scene name.
    pub name: String,
    /// Scene description.
    pub description: String,
    /// Number of faces.
    pub faces: usize,
    /// Closed convex or open.
    pub kind: MeshKind,
    /// Ω in `f64` (sr).
    pub exact_f64: f64,
    /// Ω at the reference precision (decimal, 256 bits with `mpfr`).
    pub exact_reference: String,
    /// `|Ω_f64 − Ω_ref| / Ω_ref`.
    pub f64_relative_error: f64,
    /// Fraction of the sphere covered by the box with the fixed axis.
    pub fixed_box_fraction: f64,
}

/// Error of one method on one scene at one sample count.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    /// Scene name.
    pub scene: String,
    /// [`Method::name`].
    pub method: String,
    /// Samples per estimate.
    pub n: usize,
    /// Number of estimates.
    pub repetitions: usize,
    /// Mean of the estimates (sr).
    pub mean: f64,
    /// RMS of `(Ω̂ − Ω)/Ω` over the estimates.
    pub rms_relative_error: f64,
    /// `(mean − Ω)/Ω`.
    pub relative_bias: f64,
    /// Standard error of `relative_bias` (sample standard deviation / √R / Ω).
    pub bias_std_error: f64,
    /// Mean fraction of the sphere covered by the sampled boxes.
    pub box_fraction: f64,
    /// The relative standard deviation plain random sampling of that box
    /// would have: `√(p(1 − p)/n) · |B| / Ω`, `p = Ω/|B|`.
    pub random_prediction: f64,
}

/// Least-squares slope of `log RMS error` against `log n`.
#[derive(Clone, Debug, PartialEq)]
pub struct SlopeRow {
    /// Scene name.
    pub scene: String,
    /// [`Method::name`].
    pub method: String,
    /// The slope (−1/2 for plain Monte Carlo, −3/4 for stratified with a
    /// smooth silhouette).
    pub slope: f64,
}

/// The `f32` error of the sphere map over a grid of `[0, 1]²`.
#[derive(Clone, Debug, PartialEq)]
pub struct F32ErrorMap {
    /// Cells along `u` (columns).
    pub cols: usize,
    /// Cells along `v` (rows).
    pub rows: usize,
    /// Points per cell.
    pub points_per_cell: usize,
    /// The reference scalar, e.g. `mpfr:256`.
    pub reference: String,
    /// Per cell (row-major, row = `v` index), the maximal end-to-end error
    /// (data `(u, v)` in `f64`, rounded to `f32` and mapped in `f32`, against
    /// the reference map at the data), in units of `2^-24`.
    pub end_to_end_ulps: Vec<f64>,
    /// Per cell, the maximal evaluation error (reference at the
    /// `f32`-rounded inputs), in units of `2^-24`.
    pub evaluation_ulps: Vec<f64>,
}

/// The `f32` error at distance `d` from each pole (`u ∈ [d, 2d)` and
/// `1 − u ∈ (d, 2d]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PoleProfileRow {
    /// `log2 d`.
    pub log2_distance: i32,
    /// Max end-to-end error near the north pole (`u ≈ d`), units of `2^-24`.
    pub north_end_to_end: f64,
    /// Max end-to-end error near the south pole (`u ≈ 1 − d`).
    pub south_end_to_end: f64,
    /// Max evaluation-only error near the north pole.
    pub north_evaluation: f64,
    /// Max evaluation-only error near the south pole.
    pub south_evaluation: f64,
}

/// Where the `f32` end-to-end error lands in world directions, for one
/// axis mode.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisSpread {
    /// `fixed` or `random`.
    pub axis: String,
    /// Number of samples.
    pub samples: usize,
    /// Share of the total squared error that falls in the polar caps
    /// `|z| > 0.99` of the *world* frame (1% of the sphere).
    pub cap_error_share: f64,
    /// Max error (units of `2^-24`) in the world's north cap `z > 0.99`.
    pub max_north_cap: f64,
    /// Max error in the world's south cap `z < −0.99`.
    pub max_south_cap: f64,
    /// Max error elsewhere.
    pub max_elsewhere: f64,
    /// RMS error over all samples.
    pub rms: f64,
    /// Cells of the world map along `u_w = (1 − z)/2` (columns).
    pub cols: usize,
    /// Cells along `v_w = φ/2π` (rows).
    pub rows: usize,
    /// Per-cell RMS error (row-major, row = `v_w` index); `None` for
    /// empty cells.
    pub cell_rms: Vec<Option<f64>>,
}

/// Everything [`run`] measured.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidAngleStudy {
    /// The configuration used.
    pub config: SolidAngleConfig,
    /// Exact references.
    pub scenes: Vec<SceneSummary>,
    /// Error rows, by scene, method, `n`.
    pub rows: Vec<ErrorRow>,
    /// Convergence slopes, by scene and method.
    pub slopes: Vec<SlopeRow>,
    /// The `f32` error map over `[0, 1]²`.
    pub f32_map: F32ErrorMap,
    /// The `f32` error towards each pole.
    pub pole_profile: Vec<PoleProfileRow>,
    /// World-direction error spread, fixed and random axis.
    pub axis_spread: Vec<AxisSpread>,
    /// A sample-distribution demo: the first scene, stratified fixed-axis
    /// box, 1024 points `(v, u, hit)`.
    pub demo_points: Vec<(f64, f64, bool)>,
    /// The demo's box.
    pub demo_box: AngularBox,
}

// ---------------------------------------------------------------------------
// Running
// ---------------------------------------------------------------------------

fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A job's seed from the master seed and the job's coordinates.
fn job_seed(seed: u64, parts: &[u64]) -> u64 {
    parts
        .iter()
        .fold(splitmix(seed), |h, &p| splitmix(h ^ splitmix(p)))
}

/// The box padding for a map in `T`: 64 units of roundoff (radians).
fn pad_for<T: Real>() -> f64 {
    64.0 * T::unit_roundoff().to_f64()
}

/// Counts hits of the `pts` relative box points through `sphere` (in `T`).
fn count_hits<T: Real>(
    geom: &Geometry,
    sphere: &Sphere<T>,
    bx: &AngularBox,
    pts: impl Iterator<Item = (f64, f64)>,
) -> u64 {
    let mut hits = 0;
    for (s, t) in pts {
        let (u, v) = bx.point(s, t);
        let p = sphere.map(&T::from_f64(u), &T::from_f64(v));
        if geom.hit(&[p.x.to_f64(), p.y.to_f64(), p.z.to_f64()]) {
            hits += 1;
        }
    }
    hits
}

fn jitter<'r>(k: usize, rng: &'r mut Xoshiro256PlusPlus) -> impl Iterator<Item = (f64, f64)> + 'r {
    (0..k * k).map(move |idx| {
        let (i, j) = (idx % k, idx / k);
        let a: f64 = rng.random();
        let b: f64 = rng.random();
        ((i as f64 + a) / k as f64, (j as f64 + b) / k as f64)
    })
}

fn uniform(n: usize, rng: &mut Xoshiro256PlusPlus) -> impl Iterator<Item = (f64, f64)> + '_ {
    (0..n).map(move |_| (rng.random::<f64>(), rng.random::<f64>()))
}

/// One estimate: `(Ω̂, mean box fraction)`.
fn estimate<T: Real>(
    geom: &Geometry,
    m: &Method,
    n: usize,
    seed: u64,
) -> Result<(f64, f64), WarpError> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let pad = pad_for::<T>();
    let boxed = |sphere: &Sphere<T>| -> Result<AngularBox, WarpError> {
        Ok(if m.bounding_box {
            geom.angular_box(&sphere.at::<f64>()?, pad)
        } else {
            AngularBox::full()
        })
    };
    let log4 = (n.trailing_zeros() / 2) as usize;
    match (m.axis, m.sampling) {
        (AxisMode::Fixed, sampling) => {
            let sphere = Sphere::<T>::new();
            let bx = boxed(&sphere)?;
            let hits = match sampling {
                Sampling::Random => count_hits(geom, &sphere, &bx, uniform(n, &mut rng)),
                Sampling::Stratified => count_hits(geom, &sphere, &bx, jitter(1 << log4, &mut rng)),
            };
            Ok((bx.measure() * hits as f64 / n as f64, bx.fraction()))
        }
        (AxisMode::Random, Sampling::Random) => {
            let (mut sum, mut frac) = (0.0, 0.0);
            for _ in 0..n {
                let sphere = Sphere::<T>::with_random_axis(&mut rng);
                let bx = boxed(&sphere)?;
                let st = (rng.random::<f64>(), rng.random::<f64>());
                let hits = count_hits(geom, &sphere, &bx, std::iter::once(st));
                sum += bx.measure() * hits as f64;
                frac += bx.fraction();
            }
            Ok((sum / n as f64, frac / n as f64))
        }
        (AxisMode::Random, Sampling::Stratified) => {
            let (ka, kc) = (1usize << (log4 / 4), 1usize << (log4 - log4 / 4));
            let north = Sphere::<f64>::new();
            let axes: Vec<(f64, f64)> = jitter(ka, &mut rng).collect();
            let (mut sum, mut frac) = (0.0, 0.0);
            for (a, b) in axes {
                let axis: Vec3<T> = north.map(&a, &b).convert();
                let sphere = Sphere::<T>::with_axis(axis)?;
                let bx = boxed(&sphere)?;
                let hits = count_hits(geom, &sphere, &bx, jitter(kc, &mut rng));
                sum += bx.measure() * hits as f64 / (kc * kc) as f64;
                frac += bx.fraction();
            }
            Ok((sum / (ka * ka) as f64, frac / (ka * ka) as f64))
        }
    }
}

fn estimate_with(
    geom: &Geometry,
    m: &Method,
    n: usize,
    seed: u64,
) -> Result<(f64, f64), WarpError> {
    match m.precision {
        Precision::F32 => estimate::<f32>(geom, m, n, seed),
        Precision::F64 => estimate::<f64>(geom, m, n, seed),
    }
}

/// End-to-end and evaluation-only errors of `Sphere<f32>` (from `s32`) at
/// data `(u, v)`, against `sr` (the same frame in `R`), in units of `2^-24`;
/// also the reference point.
fn f32_errors<R: Real>(s32: &Sphere<f32>, sr: &Sphere<R>, u: f64, v: f64) -> (f64, f64, Vec3<R>) {
    let unit = R::exp2i(-24);
    let (u32_, v32) = (u as f32, v as f32);
    let p = s32.map(&u32_, &v32);
    let exact = sr.map(&R::from_f64(u), &R::from_f64(v));
    let rounded = sr.map(&convert::<f32, R>(&u32_), &convert::<f32, R>(&v32));
    if !p.is_finite() {
        return (f64::INFINITY, f64::INFINITY, exact);
    }
    let p: Vec3<R> = p.convert();
    let e2e = (p.sub(&exact).max_abs() / &unit).to_f64();
    let eval = (p.sub(&rounded).max_abs() / &unit).to_f64();
    (e2e, eval, exact)
}

fn f32_map(config: &SolidAngleConfig) -> Result<F32ErrorMap, WarpError> {
    let (cells, pp) = (config.heat_map_cells, config.heat_map_points);
    let s32 = Sphere::<f32>::new();
    let sr = s32.at::<Reference>()?;
    let rows: Vec<(Vec<f64>, Vec<f64>)> = (0..cells)
        .into_par_iter()
        .map(|j| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(config.seed, &[1, j as u64]));
            let mut e2e = vec![0.0f64; cells];
            let mut eval = vec![0.0f64; cells];
            for i in 0..cells {
                for a in 0..pp {
                    for b in 0..pp {
                        let u = (i as f64 + (a as f64 + rng.random::<f64>()) / pp as f64)
                            / cells as f64;
                        let v = (j as f64 + (b as f64 + rng.random::<f64>()) / pp as f64)
                            / cells as f64;
                        let (x, y, _) = f32_errors(&s32, &sr, u, v);
                        e2e[i] = e2e[i].max(x);
                        eval[i] = eval[i].max(y);
                    }
                }
            }
            (e2e, eval)
        })
        .collect();
    let mut map = F32ErrorMap {
        cols: cells,
        rows: cells,
        points_per_cell: pp * pp,
        reference: Reference::type_name(),
        end_to_end_ulps: Vec::with_capacity(cells * cells),
        evaluation_ulps: Vec::with_capacity(cells * cells),
    };
    for (e, v) in rows {
        map.end_to_end_ulps.extend(e);
        map.evaluation_ulps.extend(v);
    }
    Ok(map)
}

fn pole_profile(config: &SolidAngleConfig) -> Result<Vec<PoleProfileRow>, WarpError> {
    let s32 = Sphere::<f32>::new();
    let sr = s32.at::<Reference>()?;
    let ks: Vec<i32> = (1..=40).collect();
    Ok(ks
        .par_iter()
        .map(|&k| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(config.seed, &[2, k as u64]));
            let d = 2f64.powi(-k);
            let mut row = PoleProfileRow {
                log2_distance: -k,
                north_end_to_end: 0.0,
                south_end_to_end: 0.0,
                north_evaluation: 0.0,
                south_evaluation: 0.0,
            };
            for _ in 0..config.profile_points {
                let r: f64 = rng.random();
                let v: f64 = rng.random();
                let (a, b, _) = f32_errors(&s32, &sr, d * (1.0 + r), v);
                row.north_end_to_end = row.north_end_to_end.max(a);
                row.north_evaluation = row.north_evaluation.max(b);
                let (a, b, _) = f32_errors(&s32, &sr, 1.0 - d * (1.0 + r), v);
                row.south_end_to_end = row.south_end_to_end.max(a);
                row.south_evaluation = row.south_evaluation.max(b);
            }
            row
        })
        .collect())
}

/// Per-job accumulator of the world maps.
#[derive(Clone)]
struct WorldAcc {
    sum_sq: Vec<f64>,
    count: Vec<u64>,
    max_north: f64,
    max_south: f64,
    max_else: f64,
    cap_sq: f64,
    total_sq: f64,
}

fn axis_spread(
    config: &SolidAngleConfig,
    random: bool,
    cols: usize,
    rows: usize,
) -> Result<AxisSpread, WarpError> {
    let jobs = 64usize;
    let per_job = config.world_samples.div_ceil(jobs);
    let world = Sphere::<f64>::new();
    let accs: Vec<WorldAcc> = (0..jobs)
        .into_par_iter()
        .map(|job| -> Result<WorldAcc, WarpError> {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(
                config.seed,
                &[3, random as u64, job as u64],
            ));
            let mut acc = WorldAcc {
                sum_sq: vec![0.0; cols * rows],
                count: vec![0; cols * rows],
                max_north: 0.0,
                max_south: 0.0,
                max_else: 0.0,
                cap_sq: 0.0,
                total_sq: 0.0,
            };
            let fixed = Sphere::<f32>::new();
            let fixed_ref = fixed.at::<Reference>()?;
            let start = job * per_job;
            let end = ((job + 1) * per_job).min(config.world_samples);
            for _ in start..end {
                let (u, v): (f64, f64) = (rng.random(), rng.random());
                let (e2e, exact) = if random {
                    let s = Sphere::<f32>::with_random_axis(&mut rng);
                    let r = s.at::<Reference>()?;
                    let (e, _, p) = f32_errors(&s, &r, u, v);
                    (e, p)
                } else {
                    let (e, _, p) = f32_errors(&fixed, &fixed_ref, u, v);
                    (e, p)
                };
                let p = Vec3::new(exact.x.to_f64(), exact.y.to_f64(), exact.z.to_f64());
                let p = p.normalized().unwrap_or(Vec3::new(0.0, 0.0, 1.0));
                let [uw, vw] = world.inverse(&p).unwrap_or([0.0, 0.0]);
                let ci = ((uw * cols as f64) as usize).min(cols - 1);
                let cj = ((vw * rows as f64) as usize).min(rows - 1);
                let sq = e2e * e2e;
                acc.sum_sq[cj * cols + ci] += sq;
                acc.count[cj * cols + ci] += 1;
                acc.total_sq += sq;
                if p.z > 0.99 {
                    acc.max_north = acc.max_north.max(e2e);
                    acc.cap_sq += sq;
                } else if p.z < -0.99 {
                    acc.max_south = acc.max_south.max(e2e);
                    acc.cap_sq += sq;
                } else {
                    acc.max_else = acc.max_else.max(e2e);
                }
            }
            Ok(acc)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut total = WorldAcc {
        sum_sq: vec![0.0; cols * rows],
        count: vec![0; cols * rows],
        max_north: 0.0,
        max_south: 0.0,
        max_else: 0.0,
        cap_sq: 0.0,
        total_sq: 0.0,
    };
    for a in &accs {
        for k in 0..cols * rows {
            total.sum_sq[k] += a.sum_sq[k];
            total.count[k] += a.count[k];
        }
        total.max_north = total.max_north.max(a.max_north);
        total.max_south = total.max_south.max(a.max_south);
        total.max_else = total.max_else.max(a.max_else);
        total.cap_sq += a.cap_sq;
        total.total_sq += a.total_sq;
    }
    Ok(AxisSpread {
        axis: if random { "random" } else { "fixed" }.to_string(),
        samples: config.world_samples,
        cap_error_share: if total.total_sq > 0.0 {
            total.cap_sq / total.total_sq
        } else {
            0.0
        },
        max_north_cap: total.max_north,
        max_south_cap: total.max_south,
        max_elsewhere: total.max_else,
        rms: (total.total_sq / config.world_samples as f64).sqrt(),
        cols,
        rows,
        cell_rms: total
            .sum_sq
            .iter()
            .zip(&total.count)
            .map(|(s, &c)| (c > 0).then(|| (s / c as f64).sqrt()))
            .collect(),
    })
}

fn slope(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let k = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / k,
        pts.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

/// `|a − b| / |b|`, evaluated in `R`.
fn relative_difference<R: Real>(a: f64, b: &R) -> f64 {
    ((R::from_f64(a) - b) / b).abs().to_f64()
}

/// Runs the study on rayon's current thread pool. The result depends only
/// on `config` (not on the number of threads).
///
/// # Errors
/// [`WarpError::InvalidParameter`] for an invalid configuration (sample
/// counts not powers of 4, fewer than 2 repetitions, empty lists); mesh and
/// viewpoint errors of the scenes.
pub fn run(config: &SolidAngleConfig) -> Result<SolidAngleStudy, WarpError> {
    config.validate()?;
    let geoms: Vec<Geometry> = config
        .scenes
        .iter()
        .map(|s| Geometry::new(&s.mesh, &s.viewpoint))
        .collect::<Result<_, _>>()?;
    let mut scenes = Vec::new();
    let mut exact = Vec::new();
    for (s, g) in config.scenes.iter().zip(&geoms) {
        let e64: f64 = exact_solid_angle(&s.mesh, &s.viewpoint)?;
        let er: Reference = exact_solid_angle(&s.mesh, &s.viewpoint)?;
        let rel = relative_difference(e64, &er);
        scenes.push(SceneSummary {
            name: s.name.clone(),
            description: s.description.clone(),
            faces: s.mesh.faces.len(),
            kind: s.mesh.kind,
            exact_f64: e64,
            exact_reference: er.to_roundtrip_string(),
            f64_relative_error: rel,
            fixed_box_fraction: g.angular_box(&Sphere::new(), pad_for::<f64>()).fraction(),
        });
        exact.push(er.to_f64());
    }

    // The estimation jobs, in a fixed order; results collected in that order.
    let mut jobs = Vec::new();
    let skipped = |m: &Method, n: usize| {
        m.sampling == Sampling::Random
            && m.axis == AxisMode::Random
            && n > config.per_sample_axis_max_n
    };
    for si in 0..config.scenes.len() {
        for mi in 0..config.methods.len() {
            for (ni, &n) in config.sample_counts.iter().enumerate() {
                if skipped(&config.methods[mi], n) {
                    continue;
                }
                for r in 0..config.repetitions {
                    jobs.push((si, mi, ni, n, r));
                }
            }
        }
    }
    let results: Vec<(f64, f64)> = jobs
        .par_iter()
        .map(|&(si, mi, ni, n, r)| {
            let seed = job_seed(config.seed, &[0, si as u64, mi as u64, ni as u64, r as u64]);
            estimate_with(&geoms[si], &config.methods[mi], n, seed)
        })
        .collect::<Result<_, _>>()?;

    let mut rows = Vec::new();
    let mut slopes = Vec::new();
    let reps = config.repetitions;
    // Jobs are grouped by (scene, method, n) with the repetitions innermost.
    let mut chunks = results.chunks(reps);
    for (si, s) in config.scenes.iter().enumerate() {
        for m in &config.methods {
            let mut curve = Vec::new();
            for &n in &config.sample_counts {
                if skipped(m, n) {
                    continue;
                }
                let Some(chunk) = chunks.next() else {
                    break;
                };
                let omega = exact[si];
                let mean = chunk.iter().map(|r| r.0).sum::<f64>() / reps as f64;
                let mse = chunk.iter().map(|r| (r.0 - omega).powi(2)).sum::<f64>() / reps as f64;
                let var =
                    chunk.iter().map(|r| (r.0 - mean).powi(2)).sum::<f64>() / (reps - 1) as f64;
                let frac = chunk.iter().map(|r| r.1).sum::<f64>() / reps as f64;
                let area = 4.0 * std::f64::consts::PI * frac;
                let p = (omega / area).min(1.0);
                let row = ErrorRow {
                    scene: s.name.clone(),
                    method: m.name(),
                    n,
                    repetitions: reps,
                    mean,
                    rms_relative_error: mse.sqrt() / omega,
                    relative_bias: (mean - omega) / omega,
                    bias_std_error: (var / reps as f64).sqrt() / omega,
                    box_fraction: frac,
                    random_prediction: (p * (1.0 - p) / n as f64).sqrt() * area / omega,
                };
                curve.push((n as f64, row.rms_relative_error));
                rows.push(row);
            }
            slopes.push(SlopeRow {
                scene: s.name.clone(),
                method: m.name(),
                slope: slope(&curve),
            });
        }
    }

    // Sample-distribution demo on the first scene.
    let demo_geom = &geoms[0];
    let demo_box = demo_geom.angular_box(&Sphere::new(), pad_for::<f64>());
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(config.seed, &[4]));
    let sphere = Sphere::<f64>::new();
    let demo_points = jitter(32, &mut rng)
        .map(|(s, t)| {
            let (u, v) = demo_box.point(s, t);
            let p = sphere.map(&u, &v);
            (v, u, demo_geom.hit(&arr(&p)))
        })
        .collect();

    Ok(SolidAngleStudy {
        config: config.clone(),
        scenes,
        rows,
        slopes,
        f32_map: f32_map(config)?,
        pole_profile: pole_profile(config)?,
        axis_spread: vec![
            axis_spread(config, false, 64, 32)?,
            axis_spread(config, true, 64, 32)?,
        ],
        demo_points,
        demo_box,
    })
}

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// A decimal string cut to `digits` significant characters, keeping its
/// exponent.
fn short_decimal(s: &str, digits: usize) -> String {
    match s.find(['e', 'E']) {
        Some(i) => format!("{}{}", &s[..i.min(digits + 2)], &s[i..]),
        None => s[..s.len().min(digits + 2)].to_string(),
    }
}

fn fmt_e(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.2e}")
    }
}

fn csv_write(path: &Path, header: &str, lines: &[String]) -> io::Result<PathBuf> {
    let mut s = String::from(header);
    s.push('\n');
    for l in lines {
        s.push_str(l);
        s.push('\n');
    }
    std::fs::write(path, s)?;
    Ok(path.to_path_buf())
}

impl SolidAngleStudy {
    fn row(&self, scene: &str, method: &Method, n: usize) -> Option<&ErrorRow> {
        let name = method.name();
        self.rows
            .iter()
            .find(|r| r.scene == scene && r.method == name && r.n == n)
    }

    /// The file names [`SolidAngleStudy::write_figures`] writes, in order.
    pub fn figure_files(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "solid_angle_samples.svg",
            "solid_angle_f32_error_uv.svg",
            "solid_angle_f32_error_uv.png",
            "solid_angle_f32_evaluation_uv.svg",
            "solid_angle_f32_pole_profile.svg",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for a in &self.axis_spread {
            v.push(format!("solid_angle_f32_world_{}.svg", a.axis));
        }
        for sc in &self.scenes {
            v.push(format!("solid_angle_error_vs_n_{}.svg", sc.name));
        }
        v
    }

    /// `rms(a) / rms(b)` on `scene` at the largest `n` where both were
    /// measured, with that `n`.
    pub fn error_ratio(&self, scene: &str, a: &Method, b: &Method) -> Option<(f64, usize)> {
        self.config.sample_counts.iter().rev().find_map(|&n| {
            Some((
                self.rms_error(scene, a, n)? / self.rms_error(scene, b, n)?,
                n,
            ))
        })
    }

    /// The RMS relative error of `method` on `scene` at `n`, if measured.
    pub fn rms_error(&self, scene: &str, method: &Method, n: usize) -> Option<f64> {
        self.row(scene, method, n).map(|r| r.rms_relative_error)
    }

    /// The report section (Markdown): scenes with exact references, the
    /// error-vs-samples tables, slopes, headline ratios, the `f32` error
    /// profile and spread, and links to the figures (relative to the
    /// directory given to [`SolidAngleStudy::write_figures`]).
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let c = &self.config;
        let nmax = c.sample_counts.iter().copied().max().unwrap_or(0);
        let _ = writeln!(s, "## Solid angle of an object (Shao–Badler §3)\n");
        let _ = writeln!(
            s,
            "Ω̂ = |B| · (hits / n): directions uniform in the object's angular bounding box B in \
             cylinder coordinates (z, φ) — Archimedes' axial projection makes them uniform on the \
             sphere —, a Möller–Trumbore ray test per direction (inclusive edges), against the exact \
             Ω from Van Oosterom–Strackee per face ({}). {} estimates per cell, seed {:#x}.\n",
            self.f32_map.reference, c.repetitions, c.seed
        );
        let _ = writeln!(
            s,
            "| scene | faces | kind | Ω exact (sr) | f64 vs reference | box share of sphere (fixed axis) |\n|---|---|---|---|---|---|"
        );
        for sc in &self.scenes {
            let _ = writeln!(
                s,
                "| {} — {} | {} | {:?} | {} | {} | {} |",
                sc.name,
                sc.description,
                sc.faces,
                sc.kind,
                short_decimal(&sc.exact_reference, 20),
                fmt_e(sc.f64_relative_error),
                fmt_e(sc.fixed_box_fraction)
            );
        }
        for sc in &self.scenes {
            let _ = writeln!(
                s,
                "\n### RMS relative error — {}\n\n![error vs n](solid_angle_error_vs_n_{}.svg)\n",
                sc.name, sc.name
            );
            let _ = write!(s, "| n |");
            for m in &c.methods {
                let _ = write!(s, " {} |", m.name());
            }
            let _ = write!(s, "\n|---|");
            for _ in &c.methods {
                let _ = write!(s, "---|");
            }
            s.push('\n');
            for &n in &c.sample_counts {
                let _ = write!(s, "| {n} |");
                for m in &c.methods {
                    let v = self.rms_error(&sc.name, m, n).unwrap_or(f64::NAN);
                    let _ = write!(s, " {} |", fmt_e(v));
                }
                s.push('\n');
            }
            let _ = write!(s, "| slope |");
            for m in &c.methods {
                let sl = self
                    .slopes
                    .iter()
                    .find(|r| r.scene == sc.name && r.method == m.name())
                    .map_or(f64::NAN, |r| r.slope);
                let _ = write!(s, " {sl:.2} |");
            }
            s.push('\n');
            let _ = write!(s, "| bias at n = {nmax} (± s.e.) |");
            for m in &c.methods {
                match self.row(&sc.name, m, nmax) {
                    Some(r) => {
                        let _ = write!(
                            s,
                            " {} ± {} |",
                            fmt_e(r.relative_bias),
                            fmt_e(r.bias_std_error)
                        );
                    }
                    None => s.push_str(" – |"),
                }
            }
            s.push('\n');
        }
        // Headlines.
        let _ = writeln!(
            s,
            "\n### Findings (RMS error ratios at the largest n measured for both)\n"
        );
        let std = Method::standard();
        let (rand_box, strat_box, strat_sphere, rand_axis, strat_axes, f32_fixed, f32_axes) =
            (std[0], std[1], std[2], std[3], std[4], std[5], std[6]);
        let ratio = |scene: &str, a: &Method, b: &Method| match self.error_ratio(scene, a, b) {
            Some((r, n)) if r < 0.01 => format!("{} (n = {n})", fmt_e(r)),
            Some((r, n)) => format!("{r:.3} (n = {n})"),
            None => "–".to_string(),
        };
        for sc in &self.scenes {
            let _ = writeln!(
                s,
                "- **{}**: stratified / random {}; stratified box / whole sphere {}; random axis \
                 / fixed axis: random sampling (axis per sample) {}, stratified (≈ n^(1/4) axes) {}.",
                sc.name,
                ratio(&sc.name, &strat_box, &rand_box),
                ratio(&sc.name, &strat_box, &strat_sphere),
                ratio(&sc.name, &rand_axis, &rand_box),
                ratio(&sc.name, &strat_axes, &strat_box),
            );
            if let (Some(a), Some(r)) = (
                self.row(&sc.name, &f32_fixed, nmax),
                self.row(&sc.name, &f32_axes, nmax),
            ) {
                let _ = writeln!(
                    s,
                    "  `f32` map at n = {nmax}: fixed axis bias {} ± {} (RMS {}), random axes \
                     bias {} ± {} (RMS {}).",
                    fmt_e(a.relative_bias),
                    fmt_e(a.bias_std_error),
                    fmt_e(a.rms_relative_error),
                    fmt_e(r.relative_bias),
                    fmt_e(r.bias_std_error),
                    fmt_e(r.rms_relative_error)
                );
            }
        }
        // f32 error.
        let m = &self.f32_map;
        let max_e2e = m.end_to_end_ulps.iter().copied().fold(0.0, f64::max);
        let max_eval = m.evaluation_ulps.iter().copied().fold(0.0, f64::max);
        let col_max = |i: usize| {
            (0..m.rows)
                .map(|j| m.end_to_end_ulps[j * m.cols + i])
                .fold(0.0, f64::max)
        };
        let mid = (m.cols / 4..3 * m.cols / 4)
            .map(col_max)
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "\n### Where the `f32` truncation error of the sphere map lives\n\n\
             ![f32 error over (u, v)](solid_angle_f32_error_uv.svg)\n\n\
             End-to-end error of `Sphere<f32>` (data (u, v) in f64, rounded to f32) against the \
             {} map at the data, max over {} points per cell of a {}×{} grid, in units of 2^-24: \
             max {:.1} overall; first column (u → 0, north pole) {:.1}; middle half \
             (|z| < 1/2) {:.1}; last column (u → 1, south pole) {:.1}. The evaluation alone \
             (inputs first rounded to f32) stays within {:.1} units everywhere \
             ([map](solid_angle_f32_evaluation_uv.svg)): the error is the quantization of u \
             near 1, amplified by dθ/dz = 1/sin θ.\n",
            m.reference,
            m.points_per_cell,
            m.cols,
            m.rows,
            max_e2e,
            col_max(0),
            mid,
            col_max(m.cols - 1),
            max_eval
        );
        let _ = writeln!(
            s,
            "![f32 error towards the poles](solid_angle_f32_pole_profile.svg)\n\n\
             | distance d from the pole | north, end-to-end | south, end-to-end | north, evaluation | south, evaluation |\n|---|---|---|---|---|"
        );
        for r in self
            .pole_profile
            .iter()
            .filter(|r| r.log2_distance % 4 == 0)
        {
            let _ = writeln!(
                s,
                "| 2^{} | {:.2} | {:.2} | {:.2} | {:.2} |",
                r.log2_distance,
                r.north_end_to_end,
                r.south_end_to_end,
                r.north_evaluation,
                r.south_evaluation
            );
        }
        let _ = writeln!(
            s,
            "\nWorld directions (caps |z| > 0.99 hold 1% of the sphere): \
             ![fixed axis](solid_angle_f32_world_fixed.svg) ![random axis](solid_angle_f32_world_random.svg)\n\n\
             | axis | samples | share of squared error in the caps | max, north cap | max, south cap | max elsewhere | RMS |\n|---|---|---|---|---|---|---|"
        );
        for a in &self.axis_spread {
            let _ = writeln!(
                s,
                "| {} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.2} |",
                a.axis,
                a.samples,
                a.cap_error_share,
                a.max_north_cap,
                a.max_south_cap,
                a.max_elsewhere,
                a.rms
            );
        }
        let _ = writeln!(s, "\n![samples over the object](solid_angle_samples.svg)\n");
        s
    }

    /// Writes the tables as CSV files into `dir` (created if needed):
    /// `solid_angle_scenes.csv`, `solid_angle_errors.csv`,
    /// `solid_angle_slopes.csv`, `solid_angle_f32_pole_profile.csv`,
    /// `solid_angle_f32_uv.csv`, `solid_angle_f32_axis_spread.csv`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        out.push(csv_write(
            &dir.join("solid_angle_scenes.csv"),
            "scene,faces,kind,exact_f64,exact_reference,f64_relative_error,fixed_box_fraction",
            &self
                .scenes
                .iter()
                .map(|s| {
                    format!(
                        "{},{},{:?},{:e},{},{:e},{:e}",
                        s.name,
                        s.faces,
                        s.kind,
                        s.exact_f64,
                        s.exact_reference,
                        s.f64_relative_error,
                        s.fixed_box_fraction
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_errors.csv"),
            "scene,method,n,repetitions,mean,rms_relative_error,relative_bias,bias_std_error,box_fraction,random_prediction",
            &self
                .rows
                .iter()
                .map(|r| {
                    format!(
                        "{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
                        r.scene,
                        r.method,
                        r.n,
                        r.repetitions,
                        r.mean,
                        r.rms_relative_error,
                        r.relative_bias,
                        r.bias_std_error,
                        r.box_fraction,
                        r.random_prediction
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_slopes.csv"),
            "scene,method,slope",
            &self
                .slopes
                .iter()
                .map(|r| format!("{},{},{:e}", r.scene, r.method, r.slope))
                .collect::<Vec<_>>(),
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_f32_pole_profile.csv"),
            "log2_distance,north_end_to_end,south_end_to_end,north_evaluation,south_evaluation",
            &self
                .pole_profile
                .iter()
                .map(|r| {
                    format!(
                        "{},{:e},{:e},{:e},{:e}",
                        r.log2_distance,
                        r.north_end_to_end,
                        r.south_end_to_end,
                        r.north_evaluation,
                        r.south_evaluation
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        let m = &self.f32_map;
        let mut lines = Vec::with_capacity(m.cols * m.rows);
        for j in 0..m.rows {
            for i in 0..m.cols {
                lines.push(format!(
                    "{},{},{:.4e},{:.4e}",
                    (i as f64 + 0.5) / m.cols as f64,
                    (j as f64 + 0.5) / m.rows as f64,
                    m.end_to_end_ulps[j * m.cols + i],
                    m.evaluation_ulps[j * m.cols + i]
                ));
            }
        }
        out.push(csv_write(
            &dir.join("solid_angle_f32_uv.csv"),
            "u_center,v_center,end_to_end_ulps,evaluation_ulps",
            &lines,
        )?);
        out.push(csv_write(
            &dir.join("solid_angle_f32_axis_spread.csv"),
            "axis,samples,cap_error_share,max_north_cap,max_south_cap,max_elsewhere,rms",
            &self
                .axis_spread
                .iter()
                .map(|a| {
                    format!(
                        "{},{},{:e},{:e},{:e},{:e},{:e}",
                        a.axis,
                        a.samples,
                        a.cap_error_share,
                        a.max_north_cap,
                        a.max_south_cap,
                        a.max_elsewhere,
                        a.rms
                    )
                })
                .collect::<Vec<_>>(),
        )?);
        Ok(out)
    }

    /// Writes the figures into `dir` (created if needed): per scene a
    /// log-log plot of RMS relative error against `n` for every method with
    /// `n^(−1/2)` and `n^(−3/4)` reference slopes
    /// (`solid_angle_error_vs_n_<scene>.svg`); the `f32` error heat maps
    /// over `(u, v)` (end-to-end as SVG and PNG, evaluation-only as SVG);
    /// the pole profile; the world-direction maps for the fixed and the
    /// random axis (same colour range); and the sample-distribution demo.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        // Samples over the object.
        let hits: Vec<(f64, f64)> = self
            .demo_points
            .iter()
            .filter(|p| p.2)
            .map(|p| (p.0, 1.0 - 2.0 * p.1))
            .collect();
        let misses: Vec<(f64, f64)> = self
            .demo_points
            .iter()
            .filter(|p| !p.2)
            .map(|p| (p.0, 1.0 - 2.0 * p.1))
            .collect();
        let name = self.scenes.first().map_or("", |s| s.name.as_str());
        out.push(figures::write_scatter_svg(
            &dir.join("solid_angle_samples.svg"),
            &Plot::new(
                &format!(
                    "{} stratified directions in the (z, φ) box of the {name} ({:.2}% of the sphere)",
                    self.demo_points.len(),
                    100.0 * self.demo_box.fraction()
                ),
                Axis::linear("φ / 2π (turns)"),
                Axis::linear("z"),
            )
            .series(Series::new("hit", hits))
            .series(Series::new("miss", misses))
            .point_radius(2.0),
        )?);
        // f32 maps over (u, v).
        let m = &self.f32_map;
        let uv_axes = |map: HeatMap| {
            map.axes(
                Axis::linear("u   (0: north pole, 1: south pole)").with_range(0.0, 1.0),
                Axis::linear("v = φ / 2π").with_range(0.0, 1.0),
            )
        };
        let e2e = uv_axes(HeatMap::new(
            &format!(
                "f32 sphere map, end-to-end error vs {} (units of 2^-24)",
                m.reference
            ),
            m.cols,
            m.rows,
            m.end_to_end_ulps.clone(),
        )?)
        .value_axis("max error / 2^-24 per cell", Scale::Log10);
        out.push(figures::write_heat_map_svg(
            &dir.join("solid_angle_f32_error_uv.svg"),
            &e2e,
        )?);
        out.push(figures::write_heat_map_png(
            &dir.join("solid_angle_f32_error_uv.png"),
            &e2e,
            (256 / m.cols.max(1)).max(1) as u32,
        )?);
        let mut eval = uv_axes(HeatMap::new(
            "f32 sphere map, evaluation error only (inputs rounded to f32 first)",
            m.cols,
            m.rows,
            m.evaluation_ulps.clone(),
        )?)
        .value_axis("max error / 2^-24 per cell", Scale::Log10);
        eval.value_range = Some((
            e2e.color_range().0.min(eval.color_range().0),
            e2e.color_range().1,
        ));
        out.push(figures::write_heat_map_svg(
            &dir.join("solid_angle_f32_evaluation_uv.svg"),
            &eval,
        )?);
        // Pole profile.
        let series = |f: fn(&PoleProfileRow) -> f64| -> Vec<(f64, f64)> {
            self.pole_profile
                .iter()
                .map(|r| (2f64.powi(r.log2_distance), f(r)))
                .collect()
        };
        out.push(figures::write_line_plot_svg(
            &dir.join("solid_angle_f32_pole_profile.svg"),
            &Plot::new(
                "f32 sphere map: error at distance d (in u) from each pole",
                Axis::log("d  (u = d at the north pole, u = 1 − d at the south pole)"),
                Axis::log("max error / 2^-24"),
            )
            .series(Series::new(
                "south, end-to-end",
                series(|r| r.south_end_to_end),
            ))
            .series(Series::new(
                "north, end-to-end",
                series(|r| r.north_end_to_end),
            ))
            .series(Series::new(
                "south, evaluation only",
                series(|r| r.south_evaluation),
            ))
            .series(Series::new(
                "north, evaluation only",
                series(|r| r.north_evaluation),
            )),
        )?);
        // World maps, one colour range.
        let range = self
            .axis_spread
            .iter()
            .flat_map(|a| a.cell_rms.iter().flatten().copied())
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        for a in &self.axis_spread {
            let mut map = HeatMap::new(
                &format!(
                    "f32 end-to-end error over world directions, {} axis (RMS per cell)",
                    a.axis
                ),
                a.cols,
                a.rows,
                a.cell_rms.iter().map(|c| c.unwrap_or(f64::NAN)).collect(),
            )?
            .axes(
                Axis::linear("u_world = (1 − z)/2").with_range(0.0, 1.0),
                Axis::linear("φ_world / 2π").with_range(0.0, 1.0),
            )
            .value_axis("RMS error / 2^-24", Scale::Log10);
            if range.0.is_finite() && range.1 > range.0 {
                map.value_range = Some(range);
            }
            out.push(figures::write_heat_map_svg(
                &dir.join(format!("solid_angle_f32_world_{}.svg", a.axis)),
                &map,
            )?);
        }
        // Error vs n per scene.
        for sc in &self.scenes {
            let mut plot = Plot::new(
                &format!("solid angle of the {}: RMS relative error", sc.name),
                Axis::log("samples n"),
                Axis::log("RMS relative error"),
            );
            for m in &self.config.methods {
                let pts: Vec<(f64, f64)> = self
                    .rows
                    .iter()
                    .filter(|r| r.scene == sc.name && r.method == m.name())
                    .map(|r| (r.n as f64, r.rms_relative_error))
                    .collect();
                plot = plot.series(Series::new(&m.name(), pts));
            }
            let nmin = self.config.sample_counts.iter().copied().min().unwrap_or(4) as f64;
            let nmax = self.config.sample_counts.iter().copied().max().unwrap_or(4) as f64;
            let anchor = |m: &Method| {
                self.rms_error(&sc.name, m, nmin as usize)
                    .filter(|v| *v > 0.0)
            };
            let std = Method::standard();
            if let Some(a) = anchor(&std[0]) {
                plot = plot.series(
                    Series::new(
                        "n^-1/2",
                        vec![(nmin, a), (nmax, a * (nmax / nmin).powf(-0.5))],
                    )
                    .reference()
                    .with_color(figures::Rgb(90, 90, 90)),
                );
            }
            if let Some(a) = anchor(&std[1]) {
                plot = plot.series(
                    Series::new(
                        "n^-3/4",
                        vec![(nmin, a), (nmax, a * (nmax / nmin).powf(-0.75))],
                    )
                    .reference()
                    .with_color(figures::Rgb(160, 160, 160)),
                );
            }
            out.push(figures::write_line_plot_svg(
                &dir.join(format!("solid_angle_error_vs_n_{}.svg", sc.name)),
                &plot,
            )?);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
        Vec3::new(x, y, z)
    }

    fn scene(name: &str) -> Scene {
        default_scenes()
            .unwrap()
            .into_iter()
            .find(|s| s.name == name)
            .unwrap()
    }

    fn tiny_config() -> SolidAngleConfig {
        SolidAngleConfig {
            sample_counts: vec![16, 64, 256],
            repetitions: 4,
            heat_map_cells: 16,
            heat_map_points: 1,
            world_samples: 2_000,
            profile_points: 2,
            ..SolidAngleConfig::quick()
        }
    }

    #[test]
    fn mesh_validation() {
        let o = TriangleMesh::octahedron(v(0.0, 0.0, 5.0), 1.0).unwrap();
        assert_eq!(o.kind(), MeshKind::ConvexClosed);
        // Open (a face removed), non-convex (a vertex pushed in), inward.
        let mut faces = o.faces().to_vec();
        faces.pop();
        assert!(TriangleMesh::convex_closed(o.vertices().to_vec(), faces).is_err());
        let mut verts = o.vertices().to_vec();
        verts[0] = v(-0.2, 0.0, 5.0); // a dent: inside the others' hull
        assert!(TriangleMesh::convex_closed(verts, o.faces().to_vec()).is_err());
        let flipped: Vec<[usize; 3]> = o.faces().iter().map(|f| [f[0], f[2], f[1]]).collect();
        assert!(TriangleMesh::convex_closed(o.vertices().to_vec(), flipped).is_err());
        assert!(TriangleMesh::octahedron(v(0.0, 0.0, 0.0), 0.0).is_err());
        assert!(TriangleMesh::open(vec![v(0.0, 0.0, 0.0); 3], vec![[0, 1, 2]]).is_err());
        assert!(TriangleMesh::open(vec![v(f64::NAN, 0.0, 0.0); 3], vec![[0, 1, 2]]).is_err());
        assert!(
            TriangleMesh::open(
                vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)],
                vec![[0, 1, 3]]
            )
            .is_err()
        );
        // A viewpoint on a face is rejected.
        let tri = TriangleMesh::open(
            vec![v(0.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(0.0, 1.0, 1.0)],
            vec![[0, 1, 2]],
        )
        .unwrap();
        assert!(exact_solid_angle::<f64>(&tri, &v(0.2, 0.2, 1.0)).is_err());
        assert!(exact_solid_angle::<f64>(&tri, &v(2.0, 2.0, 1.0)).is_ok());
    }

    #[test]
    fn config_validation() {
        let bad = |f: fn(&mut SolidAngleConfig)| {
            let mut c = tiny_config();
            f(&mut c);
            run(&c).is_err()
        };
        assert!(bad(|c| c.sample_counts = vec![8]));
        assert!(bad(|c| c.sample_counts = vec![2]));
        assert!(bad(|c| c.sample_counts.clear()));
        assert!(bad(|c| c.repetitions = 1));
        assert!(bad(|c| c.methods.clear()));
        assert!(bad(|c| c.heat_map_cells = 0));
    }

    #[test]
    fn ray_triangle_edge_policy() {
        let (a, b, c) = (v(0.0, 0.0, 2.0), v(2.0, 0.0, 2.0), v(0.0, 2.0, 2.0));
        let o = Vec3::zero();
        let hit = |d: Vec3<f64>| ray_hits_triangle(&o, &d, &a, &b, &c);
        assert_eq!(hit(v(0.5, 0.5, 2.0)), Some(1.0));
        // Vertices and edges (exactly representable barycentrics): inclusive.
        for d in [a, b, c, v(1.0, 0.0, 2.0), v(0.0, 1.0, 2.0)] {
            assert!(hit(d).is_some(), "{d:?}");
        }
        assert!(hit(v(1.0, 1.0, 2.0)).is_some(), "hypotenuse");
        assert!(hit(v(1.0, 1.0 + 1e-12, 2.0)).is_some(), "within the slack");
        assert!(hit(v(1.0, 1.0 + 1e-8, 2.0)).is_none());
        assert!(hit(v(-1e-8, 0.5, 2.0)).is_none());
        // Behind the origin, parallel to the plane, from the plane itself.
        assert!(hit(v(0.5, 0.5, -2.0)).is_none());
        assert!(hit(v(1.0, 0.0, 0.0)).is_none());
        assert!(ray_hits_triangle(&v(0.5, 0.5, 2.0), &v(0.0, 0.0, 1.0), &a, &b, &c).is_none());
        // Both sides count.
        assert!(ray_hits_triangle(&v(0.5, 0.5, 4.0), &v(0.0, 0.0, -1.0), &a, &b, &c).is_some());
        // A closed mesh is watertight along a shared edge: rays aimed at
        // points of the edges of the octahedron all hit.
        let m = TriangleMesh::octahedron(v(0.3, -0.2, 3.0), 1.0).unwrap();
        let g = Geometry::new(&m, &Vec3::zero()).unwrap();
        let vs = m.vertices();
        for f in m.faces() {
            for k in 0..3 {
                for t in [0.0, 0.25, 0.5, 1.0 / 3.0] {
                    let p = vs[f[k]].lerp(&vs[f[(k + 1) % 3]], &t);
                    assert!(g.hit(&arr(&p)), "{p:?}");
                }
            }
        }
    }

    #[test]
    fn exact_reference_inside_closed_mesh_is_four_pi() {
        let m = TriangleMesh::octahedron(v(0.2, -0.3, 0.1), 1.0).unwrap();
        let t = TriangleMesh::tetrahedron([
            v(1.0, 0.1, -0.3),
            v(-0.6, 0.9, -0.2),
            v(-0.4, -0.8, -0.4),
            v(0.1, 0.0, 1.2),
        ])
        .unwrap();
        for mesh in [&m, &t] {
            let w: f64 = exact_solid_angle(mesh, &Vec3::zero()).unwrap();
            assert!((w - 4.0 * PI).abs() < 1e-13, "{w}");
            {
                use areawarp::real::Mpfr256 as M;
                let w: M = exact_solid_angle(mesh, &Vec3::zero()).unwrap();
                let four_pi = M::pi() * &M::from_i64(4);
                assert!((w - &four_pi).abs() < M::exp2i(-240));
            }
            // Every direction hits.
            let g = Geometry::new(mesh, &Vec3::zero()).unwrap();
            let sphere = Sphere::<f64>::new();
            let bx = g.angular_box(&sphere, pad_for::<f64>());
            assert_eq!(bx, AngularBox::full());
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
            for (s, t) in jitter(32, &mut rng) {
                assert!(g.hit(&arr(&sphere.map(&s, &t))));
            }
        }
    }

    #[test]
    fn exact_reference_outside_convex_is_half_sum_and_front_faces() {
        let sc = scene("tetrahedron");
        let w: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
        // Sum over the faces facing the viewpoint (outward normal towards it).
        let vs = sc.mesh.vertices();
        let mut front = 0.0;
        let mut all = 0.0;
        for f in sc.mesh.faces() {
            let (a, b, c) = (vs[f[0]], vs[f[1]], vs[f[2]]);
            let n = b.sub(&a).cross(&c.sub(&a));
            let om = triangle_solid_angle(&a, &b, &c);
            all += om;
            if n.dot(&sc.viewpoint.sub(&a)) > 0.0 {
                front += om;
                // Front-facing outward faces have negative signed angle.
                assert!(signed_triangle_solid_angle(&a, &b, &c) < 0.0);
            }
        }
        assert!((w - front).abs() < 1e-14 && (w - all / 2.0).abs() < 1e-14);
        assert!(w > 0.05 && w < 1.0, "{w}");
    }

    /// Van Oosterom–Strackee against Girard's theorem (Ω = α + β + γ − π,
    /// with the angles between the great-circle planes) at 256 bits.
    #[test]
    fn vos_matches_girard_at_256_bits() {
        use areawarp::real::Mpfr256 as M;
        let m = |x: i64, y: i64, z: i64| Vec3::new(M::from_i64(x), M::from_i64(y), M::from_i64(z));
        let tris = [
            (m(1, 0, 0), m(0, 1, 0), m(0, 0, 1)),
            (m(3, 1, 7), m(-2, 5, 6), m(1, -4, 9)),
            (m(10, 1, 1), m(1, 10, 1), m(1, 1, -10)),
            (m(10, 0, -1), m(-5, 9, -1), m(-5, -9, -1)), // Ω > π: den < 0
            (m(1000, 1, 2), m(1000, 3, 1), m(1000, 2, 4)), // tiny
        ];
        for (a, b, c) in tris {
            let vos = triangle_solid_angle(&a, &b, &c);
            let angle = |p: &Vec3<M>, q: &Vec3<M>, r: &Vec3<M>| {
                // Angle at vertex p between the arcs p→q and p→r.
                let n1 = p.cross(q);
                let n2 = p.cross(r);
                n1.cross(&n2).norm().atan2(&n1.dot(&n2))
            };
            let girard = angle(&a, &b, &c) + &angle(&b, &c, &a) + &angle(&c, &a, &b) - &M::pi();
            assert!(
                (vos.clone() - &girard).abs() <= M::exp2i(-240) * &girard.max(&M::one()),
                "{vos} vs {girard}"
            );
            // And f64 agrees to a few ulps (relative).
            let to64 = |p: &Vec3<M>| Vec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64());
            let w64 = triangle_solid_angle(&to64(&a), &to64(&b), &to64(&c));
            assert!(
                ((w64 - vos.to_f64()) / vos.to_f64()).abs() < 1e-13,
                "{w64} {vos}"
            );
        }
    }

    #[test]
    fn covering_arc_cases() {
        let close = |a: Option<(f64, f64)>, b: (f64, f64)| {
            let a = a.unwrap();
            assert!(
                (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
                "{a:?} {b:?}"
            );
        };
        close(covering_arc(&mut [(0.1, 0.1), (0.15, 0.1)]), (0.1, 0.15));
        // Wrapping around 0.
        close(covering_arc(&mut [(0.9, 0.15), (0.02, 0.05)]), (0.9, 0.17));
        // Two clusters: the larger gap is excluded.
        close(covering_arc(&mut [(0.1, 0.05), (0.5, 0.05)]), (0.1, 0.45));
        assert!(covering_arc(&mut [(0.0, 0.5), (0.5, 0.5)]).is_none());
        assert!(covering_arc(&mut []).is_none());
    }

    /// Every direction that hits lies in the box, for every default scene,
    /// the fixed axis and random axes (a deterministic check that the box
    /// is conservative), and the boxes are not trivially the whole sphere.
    #[test]
    fn angular_box_contains_every_hit_direction() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let extra = |name: &str, mesh: TriangleMesh| Scene {
            name: name.into(),
            description: String::new(),
            mesh,
            viewpoint: Vec3::zero(),
        };
        let tri = |a, b, c| TriangleMesh::open(vec![a, b, c], vec![[0, 1, 2]]).unwrap();
        let mut scenes = default_scenes().unwrap();
        scenes.extend([
            // Edges on meridian planes (y = 0, constant azimuth).
            extra(
                "axis-aligned octahedron",
                TriangleMesh::octahedron(v(3.0, 0.0, 0.0), 0.5).unwrap(),
            ),
            // An edge through the south pole.
            extra(
                "edge through pole",
                tri(v(1.0, 0.0, -1.0), v(-1.0, 0.0, -1.0), v(0.0, 1.0, -1.0)),
            ),
            // Near the north pole, not containing it, edges passing close.
            extra(
                "near pole",
                tri(v(0.01, 0.001, 1.0), v(-0.01, 0.002, 1.0), v(0.0, 0.02, 1.0)),
            ),
        ]);
        for sc in scenes {
            let g = Geometry::new(&sc.mesh, &sc.viewpoint).unwrap();
            let mut spheres = vec![Sphere::<f64>::new()];
            for _ in 0..6 {
                spheres.push(Sphere::with_random_axis(&mut rng));
            }
            // Axes pointing at a vertex and through the object.
            spheres.push(Sphere::with_axis(g.dirs[0]).unwrap());
            spheres.push(Sphere::with_axis(g.dirs[0].neg()).unwrap());
            for sphere in &spheres {
                let bx = g.angular_box(sphere, pad_for::<f64>());
                assert!(bx.fraction() < 0.6, "{}: {bx:?}", sc.name);
                // Hitting directions: aim at random points of random faces.
                for _ in 0..2000 {
                    let f = g.faces[rng.random_range(0..g.faces.len())];
                    let (mut a, mut b): (f64, f64) = (rng.random(), rng.random());
                    if a + b > 1.0 {
                        (a, b) = (1.0 - a, 1.0 - b);
                    }
                    let vs = sc.mesh.vertices();
                    let p = vs[f[0]]
                        .add(&vs[f[1]].sub(&vs[f[0]]).scale(&a))
                        .add(&vs[f[2]].sub(&vs[f[0]]).scale(&b));
                    let d = p.sub(&sc.viewpoint).normalized().unwrap();
                    let [u, vv] = sphere.inverse(&d).unwrap();
                    assert!(bx.contains(u, vv), "{}: {u} {vv} {bx:?}", sc.name);
                }
            }
        }
    }

    fn estimates(sc: &Scene, m: Method, n: usize, seeds: u64) -> Vec<f64> {
        let g = Geometry::new(&sc.mesh, &sc.viewpoint).unwrap();
        (0..seeds)
            .map(|s| estimate_with(&g, &m, n, 1000 + s).unwrap().0)
            .collect()
    }

    fn method(
        sampling: Sampling,
        axis: AxisMode,
        precision: Precision,
        bounding_box: bool,
    ) -> Method {
        Method {
            sampling,
            axis,
            precision,
            bounding_box,
        }
    }

    #[test]
    fn stratified_converges_and_beats_random() {
        let sc = scene("tetrahedron");
        let omega: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
        let g = Geometry::new(&sc.mesh, &sc.viewpoint).unwrap();
        let area = g.angular_box(&Sphere::new(), pad_for::<f64>()).measure();
        let p = omega / area;
        let n = 4096;
        let sigma_random = area * (p * (1.0 - p) / n as f64).sqrt();
        let strat = estimates(
            &sc,
            method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, true),
            n,
            12,
        );
        let rand = estimates(
            &sc,
            method(Sampling::Random, AxisMode::Fixed, Precision::F64, true),
            n,
            12,
        );
        for e in &strat {
            assert!(
                (e - omega).abs() <= 3.0 * sigma_random,
                "{e} vs {omega} (σ {sigma_random})"
            );
        }
        let rms = |v: &[f64]| {
            (v.iter().map(|e| (e - omega).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
        };
        let (rs, rr) = (rms(&strat), rms(&rand));
        // Plain random sampling matches its predicted standard deviation.
        assert!(
            rr > 0.4 * sigma_random && rr < 2.0 * sigma_random,
            "{rr} vs {sigma_random}"
        );
        assert!(rs < rr / 3.0, "stratified {rs} vs random {rr}");
    }

    /// The box and the whole sphere estimate the same Ω (both unbiased),
    /// also with random axes, in f64 and f32 (away from the pole).
    #[test]
    fn bounding_box_same_expectation_as_full_sphere() {
        let sc = scene("tetrahedron");
        let omega: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
        let stats = |v: &[f64]| {
            let k = v.len() as f64;
            let mean = v.iter().sum::<f64>() / k;
            let se = (v.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0) / k).sqrt();
            (mean, se)
        };
        let use_ = [
            method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, true),
            method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, false),
            method(Sampling::Random, AxisMode::Fixed, Precision::F64, false),
            method(Sampling::Stratified, AxisMode::Random, Precision::F64, true),
            method(Sampling::Random, AxisMode::Random, Precision::F64, true),
            method(Sampling::Stratified, AxisMode::Random, Precision::F32, true),
        ];
        let (box_mean, box_se) = stats(&estimates(&sc, use_[0], 1024, 24));
        for m in use_ {
            let (mean, se) = stats(&estimates(&sc, m, 1024, 24));
            assert!(
                (mean - omega).abs() <= 4.0 * se + 1e-12,
                "{}: {mean} ± {se} vs {omega}",
                m.name()
            );
            let joint = (se * se + box_se * box_se).sqrt();
            assert!(
                (mean - box_mean).abs() <= 4.0 * joint,
                "{}: {mean} vs box {box_mean}",
                m.name()
            );
        }
    }

    /// Shao–Badler's remark 3 in numbers: seen straight down the fixed
    /// axis, a millimetre-sized object lies where `f32` heights are
    /// quantized (`u` spaced by `2^-24` near 1: a handful of levels across
    /// the object), and the `f32` estimate is biased by percents; with random
    /// axes the object is almost surely far from the poles and the `f32`
    /// estimate is unbiased. The `f64` map is unbiased either way.
    #[test]
    fn f32_fixed_axis_biased_at_south_pole_random_axes_not() {
        let sc = scene("speck");
        let omega: f64 = exact_solid_angle(&sc.mesh, &sc.viewpoint).unwrap();
        let bias = |m: Method| {
            let v: Vec<f64> = estimates(&sc, m, 65536, 6)
                .iter()
                .map(|e| e / omega - 1.0)
                .collect();
            let k = v.len() as f64;
            let mean = v.iter().sum::<f64>() / k;
            let se = (v.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0) / k).sqrt();
            (mean, se)
        };
        let (b, se) = bias(method(
            Sampling::Stratified,
            AxisMode::Fixed,
            Precision::F32,
            true,
        ));
        assert!(b < -0.01 && b < -5.0 * se, "f32 fixed axis: {b} ± {se}");
        for m in [
            method(Sampling::Stratified, AxisMode::Random, Precision::F32, true),
            method(Sampling::Stratified, AxisMode::Fixed, Precision::F64, true),
        ] {
            let (b, se) = bias(m);
            assert!(b.abs() < 4.0 * se + 1e-3, "{}: {b} ± {se}", m.name());
        }
    }

    #[test]
    fn f32_error_concentrates_at_south_pole() {
        let mut c = tiny_config();
        c.profile_points = 8;
        let profile = pole_profile(&c).unwrap();
        let at = |k: i32| profile.iter().find(|r| r.log2_distance == -k).unwrap();
        // 1 − u ≈ 2^-20: u is rounded to 2^-25 absolute, z to 2^-24,
        // the angle by 2^-24 / sin θ ≈ 2^-24 · 2^9 → hundreds of units.
        assert!(at(20).south_end_to_end > 100.0, "{:?}", at(20));
        assert!(at(4).south_end_to_end < 16.0, "{:?}", at(4));
        for r in &profile {
            assert!(r.north_end_to_end < 4.0, "{r:?}");
            assert!(
                r.north_evaluation < 4.0 && r.south_evaluation < 4.0,
                "{r:?}"
            );
        }
        c.heat_map_cells = 64;
        c.heat_map_points = 2;
        let m = f32_map(&c).unwrap();
        let col = |i: usize| {
            (0..m.rows)
                .map(|j| m.end_to_end_ulps[j * m.cols + i])
                .fold(0.0, f64::max)
        };
        let middle = (m.cols / 4..3 * m.cols / 4).map(col).fold(0.0, f64::max);
        assert!(
            col(m.cols - 1) > 4.0 * middle,
            "{} {middle}",
            col(m.cols - 1)
        );
        assert!(middle < 4.0, "{middle}");
        assert!(col(0) < 4.0);
    }

    #[test]
    fn run_identical_with_one_and_two_threads() {
        let c = tiny_config();
        let go = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(&c).unwrap())
        };
        let (a, b) = (go(1), go(2));
        assert_eq!(a.scenes, b.scenes);
        assert_eq!(a.rows, b.rows);
        assert_eq!(a.f32_map, b.f32_map);
        assert_eq!(a.pole_profile, b.pole_profile);
        assert_eq!(a.axis_spread, b.axis_spread);
        assert_eq!(a.demo_points, b.demo_points);
        assert_eq!(a, b);
        assert_eq!(a.rows.len(), 3 * 7 * 3);
        // And a different seed changes the estimates.
        let mut c2 = c.clone();
        c2.seed += 1;
        assert_ne!(run(&c2).unwrap().rows, a.rows);
    }

    #[test]
    fn figures_and_csv_written_and_non_trivial() {
        let study = run(&tiny_config()).unwrap();
        let dir = std::env::temp_dir().join(format!("areawarp-solid-angle-{}", std::process::id()));
        let figs = study.write_figures(&dir).unwrap();
        assert_eq!(figs.len(), 7 + study.scenes.len());
        let names: Vec<String> = figs
            .iter()
            .map(|f| f.path.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, study.figure_files());
        for f in &figs {
            let check = figures::verify_figure(&f.path).unwrap();
            assert!(f.marks > 0 && f.bytes > 500, "{f:?}");
            match check.kind {
                figures::FigureKind::Svg => assert_eq!(check.marks, f.marks, "{f:?}"),
                figures::FigureKind::Png => assert!(check.distinct_colors > 4, "{check:?}"),
            }
        }
        // The error plots hold every method's points.
        let e = figs
            .iter()
            .find(|f| f.path.ends_with("solid_angle_error_vs_n_tetrahedron.svg"))
            .unwrap();
        assert!(e.marks >= 7 * 3);
        let csv = study.write_csv(&dir).unwrap();
        assert_eq!(csv.len(), 6);
        let errors = std::fs::read_to_string(dir.join("solid_angle_errors.csv")).unwrap();
        assert_eq!(errors.lines().count(), 1 + study.rows.len());
        let md = study.to_markdown();
        for needle in [
            "| n |",
            "slope",
            "solid_angle_f32_error_uv.svg",
            "tetrahedron",
            "south cap",
        ] {
            assert!(md.contains(needle), "{needle}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The report-size run (for `areawarp report`); prints the Markdown.
    #[test]
    #[ignore]
    fn default_size_run() {
        let t = std::time::Instant::now();
        let study = run(&SolidAngleConfig::default()).unwrap();
        println!("{}", study.to_markdown());
        println!("elapsed {:?}", t.elapsed());
        let dir = std::path::PathBuf::from("target/solid_angle_report");
        study.write_figures(&dir).unwrap();
        study.write_csv(&dir).unwrap();
    }
}
