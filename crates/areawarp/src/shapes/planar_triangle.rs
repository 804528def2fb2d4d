//! Uniform sampling of a planar triangle in space: Arvo (2001), §1.3.1,
//! eq. (1.20). Derivation and numerical choices: `docs/planar-triangle.md`.

mod fold;

pub use fold::PlanarTriangleVariant;

use super::turns::clamp01;
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::vector::Vec3;
use crate::warp::InverseError;
use crate::warp::{Warp, WarpFamily};

/// Euclidean length computed as `m·sqrt(Σ (x_i/m)²)` with `m` the largest
/// absolute coordinate: free of overflow and underflow, and, unlike
/// `hypot`-based norms, with finite (zero) derivatives for constant dual
/// numbers whose coordinates are partly zero.
fn scaled_norm<T: Real>(v: &Vec3<T>) -> T {
    let m = v.max_abs();
    if !m.is_finite() || m == T::zero() {
        // Zero vector, or non-finite input (propagated as is).
        return m;
    }
    let x = v.x.clone() / &m;
    let y = v.y.clone() / &m;
    let z = v.z.clone() / &m;
    (x.square() + &y.square() + &z.square()).sqrt() * &m
}

/// Embeds a vector of `T` constants into the evaluation scalar `S`.
fn embed3<T: Real, S: Embed<T>>(v: &Vec3<T>) -> Vec3<S> {
    Vec3::new(S::embed(&v.x), S::embed(&v.y), S::embed(&v.z))
}

/// Distance from `p` to the segment `p0 + τ·dir`, `τ ∈ [0, len]` (`dir` a unit vector).
fn segment_distance<T: Real>(p: &Vec3<T>, p0: &Vec3<T>, dir: &Vec3<T>, len: &T) -> T {
    let d = p.sub(p0);
    let tau = d.dot(dir).clamp(&T::zero(), len);
    scaled_norm(&d.sub(&dir.scale(&tau)))
}

/// `v + (w1·e1 − w2·e2)`: the small terms are combined first, so that the
/// only rounding at the scale of the coordinates is the final addition.
#[inline]
fn anchored<T: Real>(v: &Vec3<T>, w1: &T, e1: &Vec3<T>, w2: &T, e2: &Vec3<T>) -> Vec3<T> {
    v.add(&e1.scale(w1).sub(&e2.scale(w2)))
}

/// The uniform area-preserving map of a triangle `ABC` in space (Arvo 2001,
/// eq. 1.20):
///
/// ψ(u, v) = (1 − √u)·A + √u(1 − v)·B + √u·v·C.
///
/// `u` sweeps from the vertex `A` (u = 0) to the opposite edge `BC` (u = 1);
/// `v` runs along the segments parallel to `BC`, from the side `AB` (v = 0)
/// to the side `AC` (v = 1).
///
/// # Density
/// Uniform in area: `pdf(p) = 1 / area` for every `p` on the triangle, and
/// `|ψ_u × ψ_v| = area` on the whole open square (`measure() = area`).
///
/// # Evaluation
/// With `s = √u`, `t = v` and the edge vectors precomputed, a point with
/// u < 1 is `A + s·((1 − t)(B − A) + t·(C − A))`: the two products with
/// the edges are formed while the square root runs, and two operations
/// follow it. On the side u = 1 the point is anchored at B (v ≤ ½) or C,
/// `V_k + (λ_i·(V_i − V_k) + λ_j·(V_j − V_k))` with the barycentric weights
/// λ_A = 1 − s, λ_B = s(1 − t), λ_C = s·t. A factor that is zero in exact
/// arithmetic is exactly zero in floating point (s at u = 0, 1 − t or t at
/// v ∈ {0, 1}, λ_A at u = 1), so the three vertices are reproduced exactly
/// and every side of the square maps onto the corresponding edge (a
/// two-point interpolation); the absolute error is at most ½ ulp of the
/// result plus a few units of roundoff times the longest edge (measured:
/// ≤ 3.6 u·extent). The branch depends on `u = 1` only, which random
/// samples never mispredict. See `docs/planar-triangle.md`.
///
/// # Non-degeneracy
/// [`PlanarTriangle::new`] rejects triangles whose largest interior angle θ
/// has `sin θ ≤ 256·u` (u = [`Real::unit_roundoff`]): this is
/// `2·area ≤ 256·u·ℓ₁ℓ₂` with ℓ₁, ℓ₂ the two shortest edges, a criterion
/// independent of scale, position and orientation. The computed sine carries
/// an absolute error below about 8u, so every accepted triangle has its
/// normal, area and density determined to better than 1/32 relative; below
/// the threshold the data do not fix the triangle's orientation at this
/// precision.
///
/// # Example
/// ```
/// use areawarp::shapes::PlanarTriangle;
/// use areawarp::{Vec3, Warp};
///
/// let tri = PlanarTriangle::<f64>::new(
///     Vec3::new(0.0, 0.0, 0.0),
///     Vec3::new(2.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
/// )
/// .unwrap();
/// assert_eq!(tri.measure(), 1.0);
/// let p = tri.map(&0.25, &0.5); // √u = 1/2: halfway to BC, middle of the segment
/// assert!((p.x - 0.5).abs() < 1e-15 && (p.y - 0.25).abs() < 1e-15);
/// let [u, v] = tri.inverse(&p).unwrap();
/// assert!((u - 0.25).abs() < 1e-15 && (v - 0.5).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct PlanarTriangle<T> {
    a: Vec3<T>,
    b: Vec3<T>,
    c: Vec3<T>,
    /// B − A.
    e_ab: Vec3<T>,
    /// C − B.
    e_bc: Vec3<T>,
    /// A − C.
    e_ca: Vec3<T>,
    /// Unit edge directions and edge lengths (segment distances).
    d_ab: Vec3<T>,
    d_bc: Vec3<T>,
    d_ca: Vec3<T>,
    l_ab: T,
    l_bc: T,
    l_ca: T,
    /// Unit normal, oriented as (B − A) × (C − A).
    normal: Vec3<T>,
    /// normal / (2·area): barycentric coordinates are `(edge × (p − V))·m`.
    m: Vec3<T>,
    area: T,
    inv_area: T,
    extent: T,
    /// Largest `outside_by` that [`Warp::inverse`] accepts.
    inverse_tolerance: T,
    /// Which map of the triangle (Arvo's √u map or Heitz's fold map).
    variant: PlanarTriangleVariant,
}

impl<T: Real> PlanarTriangle<T> {
    /// The triangle with vertices `a`, `b`, `c`.
    ///
    /// # Errors
    /// - [`WarpError::NonFinite`] if a coordinate is NaN or infinite, or an
    ///   edge vector, the area or a vertex norm overflows.
    /// - [`WarpError::Degenerate`] for coincident vertices, collinear vertices
    ///   (largest interior angle with `sin θ ≤ 256·u`, see the type's docs),
    ///   or an area so small that its reciprocal overflows.
    pub fn new(a: Vec3<T>, b: Vec3<T>, c: Vec3<T>) -> Result<Self, WarpError> {
        for (v, what) in [(&a, "vertex A"), (&b, "vertex B"), (&c, "vertex C")] {
            if !v.is_finite() {
                return Err(WarpError::NonFinite { what });
            }
        }
        let e_ab = b.sub(&a);
        let e_bc = c.sub(&b);
        let e_ca = a.sub(&c);
        if !(e_ab.is_finite() && e_bc.is_finite() && e_ca.is_finite()) {
            return Err(WarpError::NonFinite {
                what: "triangle edge (overflow)",
            });
        }
        let l_ab = scaled_norm(&e_ab);
        let l_bc = scaled_norm(&e_bc);
        let l_ca = scaled_norm(&e_ca);
        if !(l_ab.is_finite() && l_bc.is_finite() && l_ca.is_finite()) {
            return Err(WarpError::NonFinite {
                what: "triangle edge length (overflow)",
            });
        }
        let zero = T::zero();
        if l_ab == zero || l_bc == zero || l_ca == zero {
            return Err(WarpError::Degenerate {
                what: "coincident vertices",
            });
        }
        let d_ab = e_ab.scale(&(T::one() / &l_ab));
        let d_bc = e_bc.scale(&(T::one() / &l_bc));
        let d_ca = e_ca.scale(&(T::one() / &l_ca));
        // The normal from the two shortest edges, i.e. at the vertex opposite
        // the longest edge, where the angle's sine is largest. All three
        // orientations equal (B − A) × (C − A):
        // e_ca × e_ab (at A) = e_ab × e_bc (at B) = e_bc × e_ca (at C).
        let (cross, l1, l2) = if l_bc >= l_ab && l_bc >= l_ca {
            (d_ca.cross(&d_ab), &l_ca, &l_ab)
        } else if l_ca >= l_ab {
            (d_ab.cross(&d_bc), &l_ab, &l_bc)
        } else {
            (d_bc.cross(&d_ca), &l_bc, &l_ca)
        };
        let sine = scaled_norm(&cross);
        if sine.is_nan() || sine <= T::from_i64(256) * T::unit_roundoff() {
            return Err(WarpError::Degenerate {
                what: "collinear vertices",
            });
        }
        let normal = cross.scale(&(T::one() / &sine));
        let two_area = l1.clone() * l2 * &sine;
        if !two_area.is_finite() {
            return Err(WarpError::NonFinite {
                what: "triangle area (overflow)",
            });
        }
        let area = two_area.clone() / T::from_i64(2);
        let inv_area = T::one() / &area;
        let m = normal.scale(&(T::one() / &two_area));
        if area <= T::zero() || !inv_area.is_finite() || !m.is_finite() {
            return Err(WarpError::Degenerate {
                what: "triangle area underflows",
            });
        }
        let extent = scaled_norm(&a).max(&scaled_norm(&b)).max(&scaled_norm(&c));
        if !extent.is_finite() {
            return Err(WarpError::NonFinite {
                what: "vertex norm (overflow)",
            });
        }
        let inverse_tolerance = T::exp2i(10) * T::unit_roundoff() * &extent;
        Ok(PlanarTriangle {
            a,
            b,
            c,
            e_ab,
            e_bc,
            e_ca,
            d_ab,
            d_bc,
            d_ca,
            l_ab,
            l_bc,
            l_ca,
            normal,
            m,
            area,
            inv_area,
            extent,
            inverse_tolerance,
            variant: PlanarTriangleVariant::SquareRoot,
        })
    }

    /// The triangle `abc` with the map `variant` (see
    /// [`PlanarTriangleVariant`]).
    ///
    /// # Errors
    /// As [`PlanarTriangle::new`].
    pub fn new_with(
        a: Vec3<T>,
        b: Vec3<T>,
        c: Vec3<T>,
        variant: PlanarTriangleVariant,
    ) -> Result<Self, WarpError> {
        Ok(PlanarTriangle::new(a, b, c)?.with_variant(variant))
    }

    /// The same triangle with another map.
    pub fn with_variant(mut self, variant: PlanarTriangleVariant) -> Self {
        self.variant = variant;
        self
    }

    /// The map in use.
    pub fn variant(&self) -> PlanarTriangleVariant {
        self.variant
    }

    /// Vertex A (the image of u = 0).
    pub fn a(&self) -> &Vec3<T> {
        &self.a
    }
    /// Vertex B (the image of (u, v) = (1, 0)).
    pub fn b(&self) -> &Vec3<T> {
        &self.b
    }
    /// Vertex C (the image of (u, v) = (1, 1)).
    pub fn c(&self) -> &Vec3<T> {
        &self.c
    }
    /// The area, ½‖(B − A) × (C − A)‖.
    pub fn area(&self) -> &T {
        &self.area
    }
    /// The unit normal, oriented as (B − A) × (C − A).
    pub fn normal(&self) -> &Vec3<T> {
        &self.normal
    }

    /// Barycentric coordinates `(λ_A, λ_B, λ_C)` of the orthogonal projection
    /// of `p` onto the triangle's plane (signed: negative outside an edge).
    ///
    /// Each coordinate is a signed area ratio `((edge × (p − V)) · n) / (2·area)`
    /// with V an endpoint of the opposite edge; λ_B and λ_C are both taken
    /// from A, so that they are accurate relative to their size near A.
    pub fn barycentric(&self, p: &Vec3<T>) -> (T, T, T) {
        let da = p.sub(&self.a);
        let db = p.sub(&self.b);
        let la = self.e_bc.cross(&db).dot(&self.m);
        let lb = self.e_ca.cross(&da).dot(&self.m);
        let lc = self.e_ab.cross(&da).dot(&self.m);
        (la, lb, lc)
    }

    /// The coordinate chart φ⁻¹ of the barycentric parametrization
    /// φ(s, t) = (1 − s)A + s(1 − t)B + stC: `(s, t) ∈ [0, 1]²` of the
    /// projection of `p`, clamped onto the triangle.
    ///
    /// `s = λ_B + λ_C` (= 1 − λ_A, but accurate near A) and `t = λ_C / s`,
    /// after clamping λ_B, λ_C to be non-negative; `t = 0` at `s = 0`.
    /// `None` if `p` or the result is not finite.
    pub fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        let (_, lb, lc) = self.barycentric(p);
        let lb = lb.max(&T::zero());
        let lc = lc.max(&T::zero());
        let sum = lb + &lc;
        if !sum.is_finite() {
            return None;
        }
        let t = if sum > T::zero() {
            (lc / &sum).min(&T::one())
        } else {
            T::zero()
        };
        Some((sum.min(&T::one()), t))
    }

    /// The recipe specification of this triangle (steps 1–3).
    pub fn recipe(&self) -> PlanarTriangleRecipe<T> {
        PlanarTriangleRecipe {
            triangle: self.clone(),
        }
    }
}

impl<T: Real> Warp<T> for PlanarTriangle<T> {
    type Point = Vec3<T>;

    /// ψ(u, v) of eq. (1.20), evaluated as the type's docs describe. `u`
    /// and `v` are clamped to `[0, 1]` (NaN counts as 0).
    #[inline]
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        if self.variant == PlanarTriangleVariant::Fold {
            return fold::map(self, u, v);
        }
        // NaN u counts as 0; u ≥ 1 goes to the side u = 1 below.
        let u = u.max(&T::zero());
        let t = clamp01(v);
        if u < T::one() {
            // A + s·((1 − t)(B − A) + t (C − A)); the products with the
            // edges do not wait for the square root.
            let w = self.e_ab.scale(&(T::one() - &t)).sub(&self.e_ca.scale(&t));
            return self.a.add(&w.scale(&u.sqrt()));
        }
        // The side u = 1 (the edge BC), anchored at B or C: then B, C and
        // the edge BC are exact. The weights are formed from s = √u as in
        // the interior (the same polynomial: exact derivatives for duals).
        let s = u.min(&T::one()).sqrt();
        let la = T::one() - &s;
        let lb = s.clone() * &(T::one() - &t);
        let lc = s * &t;
        if t <= T::from_ratio(1, 2) {
            // B + λ_C (C − B) + λ_A (A − B)
            anchored(&self.b, &lc, &self.e_bc, &la, &self.e_ab)
        } else {
            // C + λ_A (A − C) + λ_B (B − C)
            anchored(&self.c, &la, &self.e_ca, &lb, &self.e_bc)
        }
    }

    /// `1 / area`, whatever `p` (the density is constant; `p` is not checked).
    #[inline]
    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        self.inv_area.clone()
    }

    /// The area.
    fn measure(&self) -> T {
        self.area.clone()
    }

    /// `(u, v) = (s², t)` from [`PlanarTriangle::chart`]; `None` if `p` is not
    /// finite or lies farther than `1024·u·extent` from the triangle.
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &self.inverse_tolerance)?;
        if self.variant == PlanarTriangleVariant::Fold {
            return Ok(fold::inverse(self, p));
        }
        let (s, t) = self.chart(p).ok_or_else(|| InverseError::refuse(self, p))?;
        Ok([s.square(), t])
    }

    /// Euclidean distance from `p` to the (closed) triangle: the distance off
    /// the plane when the projection of `p` falls inside, otherwise the
    /// distance to the nearest edge. The distance to the nearest edge is
    /// always an upper bound and is used as such, which keeps the result
    /// meaningful for thin triangles whose normal is known only roughly.
    /// Non-finite `p`: [`Real::max_value`].
    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let edges = segment_distance(p, &self.a, &self.d_ab, &self.l_ab)
            .min(&segment_distance(p, &self.b, &self.d_bc, &self.l_bc))
            .min(&segment_distance(p, &self.c, &self.d_ca, &self.l_ca));
        let (la, lb, lc) = self.barycentric(p);
        let zero = T::zero();
        if la >= zero && lb >= zero && lc >= zero {
            let off_plane = self.normal.dot(&p.sub(&self.a)).abs();
            edges.min(&off_plane)
        } else {
            edges
        }
    }

    /// The largest vertex norm max(‖A‖, ‖B‖, ‖C‖): the scale of the absolute
    /// rounding errors of coordinates (a small triangle far from the origin
    /// cannot be evaluated more accurately than its position allows).
    fn extent(&self) -> T {
        self.extent.clone()
    }
}

crate::warp::distribution_for_floats!(PlanarTriangle, Vec3);

impl<T: Real> WarpFamily<T> for PlanarTriangle<T> {
    type At<S: Real> = PlanarTriangle<S>;

    /// The triangle with its vertices converted to `S` (which may fail, e.g.
    /// if `S` cannot represent them or sees them as collinear).
    fn at<S: Real>(&self) -> Result<PlanarTriangle<S>, WarpError> {
        PlanarTriangle::new_with(
            self.a.convert(),
            self.b.convert(),
            self.c.convert(),
            self.variant,
        )
    }

    /// `planar-triangle` (both variants).
    fn name(&self) -> String {
        "planar-triangle".to_string()
    }
}

/// Arvo's recipe for the planar triangle (steps 1–3), the specification the
/// direct map [`PlanarTriangle`] is tested against.
///
/// 1. φ(s, t) = (1 − s)A + s(1 − t)B + stC (barycentric; bijective except at s = 0).
/// 2. σ(s, t) = ‖φ_s × φ_t‖ = 2·area·s.
/// 3. F(s) = s², G_s(t) = t; inverses f(u) = √u, g(u, v) = v.
///
/// # Density
/// Uniform: weight 1, measure = area, so the composed map has density
/// `1 / area` in the triangle's area measure.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{PlanarTriangle, PlanarTriangleRecipe};
/// use areawarp::{Vec3, Warp};
///
/// let (a, b, c) = (
///     Vec3::<f64>::new(0.0, 0.0, 1.0),
///     Vec3::new(1.0, 0.0, 1.0),
///     Vec3::new(0.0, 1.0, 1.0),
/// );
/// let direct = PlanarTriangle::new(a.clone(), b.clone(), c.clone()).unwrap();
/// let composed = RecipeWarp::new(PlanarTriangleRecipe::new(a, b, c).unwrap(), ClosedForm, ClosedForm);
/// let (p, q) = (direct.map(&0.3, &0.6), composed.map(&0.3, &0.6));
/// assert!(p.sub(&q).norm() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct PlanarTriangleRecipe<T> {
    triangle: PlanarTriangle<T>,
}

impl<T: Real> PlanarTriangleRecipe<T> {
    /// The recipe of the triangle `abc`; validated as [`PlanarTriangle::new`].
    ///
    /// # Errors
    /// As [`PlanarTriangle::new`].
    pub fn new(a: Vec3<T>, b: Vec3<T>, c: Vec3<T>) -> Result<Self, WarpError> {
        PlanarTriangle::new(a, b, c).map(|triangle| PlanarTriangleRecipe { triangle })
    }

    /// The validated triangle behind this recipe.
    pub fn triangle(&self) -> &PlanarTriangle<T> {
        &self.triangle
    }
}

impl<T: Real> Parametrization<T> for PlanarTriangleRecipe<T> {
    /// φ(s, t) = (1 − s)A + s(1 − t)B + stC.
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let a: Vec3<S> = embed3(&self.triangle.a);
        let b: Vec3<S> = embed3(&self.triangle.b);
        let c: Vec3<S> = embed3(&self.triangle.c);
        let wa = S::one() - s;
        let wb = s.clone() * &(S::one() - t);
        let wc = s.clone() * t;
        a.scale(&wa).add(&b.scale(&wb)).add(&c.scale(&wc))
    }

    /// See [`PlanarTriangle::chart`].
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.triangle.chart(p)
    }
}

impl<T: Real> AreaDensity<T> for PlanarTriangleRecipe<T> {
    /// σ(s, t) = 2·area·s (closed form of ‖φ_s × φ_t‖).
    fn sigma(&self, s: &T, _t: &T) -> T {
        self.triangle.area.clone() * T::from_i64(2) * s
    }
}

impl<T: Real> MarginalConditional<T> for PlanarTriangleRecipe<T> {
    fn measure(&self) -> T {
        self.triangle.area.clone()
    }
    /// F(s) = s².
    fn marginal_cdf(&self, s: &T) -> T {
        s.square()
    }
    /// F'(s) = 2s.
    fn marginal_pdf(&self, s: &T) -> T {
        s.clone() * T::from_i64(2)
    }
    /// G_s(t) = t.
    fn conditional_cdf(&self, _s: &T, t: &T) -> T {
        t.clone()
    }
    /// ∂G_s/∂t = 1.
    fn conditional_pdf(&self, _s: &T, _t: &T) -> T {
        T::one()
    }
    /// f(u) = √u (u clamped at 0).
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        Some(u.max(&T::zero()).sqrt())
    }
    /// g(s, v) = v.
    fn conditional_inverse(&self, _s: &T, v: &T) -> Option<T> {
        Some(v.clone())
    }
}

impl<T: Real> Recipe<T> for PlanarTriangleRecipe<T> {
    type At<S: Real> = PlanarTriangleRecipe<S>;
    fn recast<S: Real>(&self) -> Result<PlanarTriangleRecipe<S>, WarpError> {
        self.triangle
            .at::<S>()
            .map(|triangle| PlanarTriangleRecipe { triangle })
    }
    fn name(&self) -> String {
        "planar-triangle".to_string()
    }
    /// As [`PlanarTriangle`]'s `outside_by`.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.triangle.outside_by(p)
    }
    /// As [`PlanarTriangle`]'s `extent`.
    fn extent(&self) -> T {
        self.triangle.extent.clone()
    }
}

#[cfg(test)]
mod tests;
