//! Uniform sampling of the solid angle of a spherical triangle: Arvo (1995),
//! *Stratified sampling of spherical triangles*; Arvo (2001), §1.3.5.
//! Derivation, numerical reformulations and measured accuracy:
//! `docs/spherical-triangle.md`.
//!
//! Two evaluations of the same map share one type, selected by
//! [`SphericalTriangleVariant`]: [`Literal`](SphericalTriangleVariant::Literal),
//! Arvo's published algorithm transcribed as printed, and the default
//! [`Robust`](SphericalTriangleVariant::Robust), reformulated so that every
//! step is as accurate as the data allow.

mod ladder;
mod literal;
mod recipe;
#[cfg(test)]
mod tests;

pub use ladder::{hard_triangles, ordinary_triangles};
pub use recipe::SphericalTriangleRecipe;

use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;
use crate::warp::InverseError;
use crate::warp::{LightSample, LightWarp, Warp, WarpFamily};
use literal::Literal;

/// Which evaluation of Arvo's spherical-triangle map a [`SphericalTriangle`]
/// uses. Both compute the same map ψ(u, v); they differ only in arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SphericalTriangleVariant {
    /// Arvo's 1995 algorithm as published: Girard's area α + β + γ − π from
    /// dihedral angles, `cos b̂` from the cosine laws, `Ĉ = q·A + √(1 − q²)·[C|A]`,
    /// `z = 1 − v(1 − Ĉ·B)`, `P = z·B + √(1 − z²)·[Ĉ|B]`. No clamps beyond
    /// the `acos` argument of the angle computation. The baseline to compare
    /// against: it loses digits near the edges of the square, on small, thin
    /// and nearly hemispherical triangles, and may return NaN there.
    Literal,
    /// The same map evaluated without cancellation (the default): solid angle
    /// by Van Oosterom–Strackee with a stable determinant, the sub-triangle's
    /// vertex from a half-angle tangent formula anchored at the nearer end of
    /// the arc, the point on the arc from chord lengths (see the type's docs).
    #[default]
    Robust,
}

impl SphericalTriangleVariant {
    /// `"literal"` or `"robust"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            SphericalTriangleVariant::Literal => "literal",
            SphericalTriangleVariant::Robust => "robust",
        }
    }
}

impl core::fmt::Display for SphericalTriangleVariant {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::str::FromStr for SphericalTriangleVariant {
    type Err = WarpError;
    /// Parses `literal` or `robust` (ASCII case-insensitive).
    fn from_str(s: &str) -> Result<Self, WarpError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "literal" => Ok(SphericalTriangleVariant::Literal),
            "robust" => Ok(SphericalTriangleVariant::Robust),
            _ => Err(WarpError::InvalidParameter {
                name: "variant",
                expected: "literal or robust",
            }),
        }
    }
}

/// `x` clamped to `[0, 1]`, NaN mapped to 0.
fn clamp01<T: Real>(x: &T) -> T {
    x.clamp(&T::zero(), &T::one())
}

/// `x` clamped to `[0, 1]`, NaN kept (for values that report failure).
fn clamp_keep_nan<T: Real>(x: &T) -> T {
    if x.is_nan() { x.clone() } else { clamp01(x) }
}

/// `x > 0`: `false` for zero, negative values and NaN.
fn positive<T: Real>(x: &T) -> bool {
    *x > T::zero()
}

/// `|v|²`.
fn norm2<T: Real>(v: &Vec3<T>) -> T {
    v.dot(v)
}

/// `v / |v|` computed as `w / |w|` with `w = v / max|v_i|`: free of overflow
/// and underflow for any finite non-zero `v`; `None` for the zero vector.
fn unit<T: Real>(v: &Vec3<T>) -> Option<Vec3<T>> {
    let m = v.max_abs();
    if !positive(&m) || !m.is_finite() {
        return None;
    }
    let w = Vec3::new(v.x.clone() / &m, v.y.clone() / &m, v.z.clone() / &m);
    let n = norm2(&w).sqrt();
    Some(Vec3::new(w.x / &n, w.y / &n, w.z / &n))
}

/// The unit tangent `[y|x]` at the unit vector `x` pointing along the great
/// arc towards `y`, and `|y − (x·y)x| = sin∠(x, y)`.
///
/// `y − (x·y)x` cancels when `y ≈ ±x`; it is computed as
/// `(y − x) + (|y − x|²/2)·x` when `x·y ≥ 0` and as
/// `(y + x) − (|y + x|²/2)·x` otherwise (identities for unit vectors, since
/// `1 − x·y = |y − x|²/2` and `1 + x·y = |y + x|²/2`): the differences are
/// exact or nearly so, and the result has full relative accuracy.
fn tangent<T: Real>(x: &Vec3<T>, y: &Vec3<T>) -> Option<(Vec3<T>, T)> {
    let two = T::from_i64(2);
    let t = if x.dot(y) >= T::zero() {
        let e = y.sub(x);
        e.add(&x.scale(&(norm2(&e) / &two)))
    } else {
        let e = y.add(x);
        e.sub(&x.scale(&(norm2(&e) / &two)))
    };
    let len = norm2(&t).sqrt();
    if !positive(&len) || !len.is_finite() {
        return None;
    }
    Some((t.scale(&(T::one() / &len)), len))
}

/// The constants of the robust map measured from one end V of the arc AC
/// (V = A for u ≤ 1/2, V = C for u > 1/2, W the other end), all divided by
/// `d = sin c sin α = |det(A, B, C)| / sin b` (the same for both ends) so
/// that they stay O(1) for tiny triangles.
#[derive(Clone, Debug)]
struct Anchor<T> {
    /// V.
    vertex: Vec3<T>,
    /// `[W|V]`: the unit tangent at V along the arc towards W.
    along: Vec3<T>,
    /// `(1 + cos∠VB)/d`.
    k1_d: T,
    /// `sin∠VB · cos(angle at V)/d`.
    k_d: T,
    /// `1/sin²(∠VB/2) = 4/|V − B|²`.
    inv_s2: T,
    /// V − B and V + B.
    v_minus_b: Vec3<T>,
    v_plus_b: Vec3<T>,
    /// `[V|B]`: the unit tangent at B towards V.
    t_b: Vec3<T>,
    /// The unit tangent at B perpendicular to `t_b`, towards W.
    n_b: Vec3<T>,
}

impl<T: Real> Anchor<T> {
    /// The constants for the end `vertex` of the arc, the other end being
    /// `other`; `sign` is the sign of det(A, B, C) as ±1 for V = A (its
    /// opposite for V = C), `d` the common |det|/sin b.
    fn new(
        vertex: &Vec3<T>,
        other: &Vec3<T>,
        b: &Vec3<T>,
        d: &T,
        sign: &T,
    ) -> Result<Self, WarpError> {
        let degenerate = WarpError::Degenerate {
            what: "coincident or antipodal vertices",
        };
        let two = T::from_i64(2);
        let (along, _) = tangent(vertex, other).ok_or(degenerate.clone())?;
        let (t_b, _) = tangent(b, vertex).ok_or(degenerate.clone())?;
        let v_minus_b = vertex.sub(b);
        let v_plus_b = vertex.add(b);
        let s2 = norm2(&v_minus_b) / T::from_i64(4);
        // sin∠VB·cos(angle at V) = B·[W|V] = (B − V)·[W|V].
        let k = v_minus_b.neg().dot(&along);
        let k1 = norm2(&v_plus_b) / &two;
        // n_b·[W|B] > 0: for V = A, (t_A × B)·t_C ∝ det(A, B, C).
        let n_b = unit(&t_b.cross(b).scale(sign)).ok_or(degenerate)?;
        Ok(Anchor {
            vertex: vertex.clone(),
            along,
            k1_d: k1 / d,
            k_d: k / d,
            inv_s2: T::one() / &s2,
            v_minus_b,
            v_plus_b,
            t_b,
            n_b,
        })
    }
}

/// Uniform directions in a spherical triangle: Arvo's area-preserving map
/// (Arvo 1995; Arvo 2001, §1.3.5).
///
/// The vertices A, B, C are unit directions (the constructor normalizes),
/// the triangle is the region bounded by the three minor great arcs, of
/// solid angle Ω < 2π. For `(u, v) ∈ [0, 1]²`:
///
/// 1. `C_s` is the point of the arc AC such that the sub-triangle A B C_s
///    has solid angle u·Ω;
/// 2. `P` is the point of the arc from B to C_s with
///    `(1 − cos∠BP) / (1 − cos∠BC_s) = v`.
///
/// `u = 0` is the arc BA, `u = 1` the arc BC, `v = 0` the vertex B and
/// `v = 1` the arc AC. The density is `pdf = 1/Ω` per steradian.
///
/// # Robust evaluation (default)
/// With `c = ∠AB`, α the angle at A and `h = u·Ω/2`, the arc length
/// `b_s = ∠AC_s` satisfies (`docs/spherical-triangle.md`, eq. T)
///
/// `tan(b_s/2) = (1 + cos c)·sin h / (sin c · sin(α − h))`,
///
/// and `C_s = A + sin b_s·[C|A] − (1 − cos b_s)·A` with
/// `sin b_s = 2r/(1 + r²)`, `1 − cos b_s = r·sin b_s`, `r = tan(b_s/2)`:
/// no `√(1 − q²)` of a cosine near 1. For `u > 1/2` the same formula is
/// applied from C with the complementary area `(1 − u)·Ω`, so that `C_s` is
/// always a small, accurate offset from the nearer vertex and `u = 1` gives
/// exactly `C_s = C`. The constants `1 + cos c = |A + B|²/2`,
/// `sin c·sin α = |det(A, B, C)| / sin b` and `sin c·cos α = (B − A)·[C|A]`
/// are computed once from chords and a stable triple product, and
/// Ω = 2·atan2(|det|, 1 + A·B + B·C + C·A) (Van Oosterom–Strackee) from the
/// *same* determinant, so that Ω and the map stay consistent.
///
/// The direction W of the arc B C_s at B comes from the sub-triangle's angle
/// β_s at B (eq. B: `(sin β_s, cos β_s) ∝ (sin h sin(α − h),
/// sin α sin²(c/2) − sin h cos(α − h))`), not from the chord `C_s − B`, whose
/// direction is ill-determined when C_s is nearly antipodal to B (nearly
/// hemispherical triangles), and the point uses half-angle sines from chord
/// lengths, `sin²(a_s/2) = |C_s − B|²/4`, `cos²(a_s/2) = |C_s + B|²/4`,
/// `sin²(θ/2) = v·sin²(a_s/2)` (θ = ∠BP):
///
/// - `v ≤ 1/2`: `P = B + sin θ·W − (1 − cos θ)·B` (exactly B at v = 0);
/// - `v > 1/2`: `P = C_s + 2 sin²(a_s/2)(1 − v)·B + (sin θ − sin a_s)·W`
///   (exactly C_s at v = 1, so the corners (0, 1), (1, 1) are A and C).
///
/// A final Newton step scales |P| to |B| (no square root). Cost per sample:
/// one `sin_cos`, one or two square roots, two divisions, no allocation.
///
/// # Non-degeneracy
/// [`SphericalTriangle::new`] rejects vertices that are not finite or zero,
/// coincident directions, and triangles with
/// `|det(A, B, C)| ≤ 256·u·ℓ₁ℓ₂` (u = [`Real::unit_roundoff`], ℓ₁ ≤ ℓ₂ the two
/// shortest chords |A − B|, |B − C|, |C − A|). Since
/// `det(A, B, C) = ℓ₁ℓ₂·sin θ·dist(O, plane ABC)` with θ the largest angle of
/// the planar triangle ABC, the criterion is scale-free: it rejects vertices
/// collinear on the sphere's chord triangle (θ → 0 or π) and vertices on
/// one great circle (plane through the origin), in both cases only when the
/// orientation of the triangle is lost in the rounding of the determinant.
/// Tiny triangles (1e-12 sr in `f64`), slivers and nearly hemispherical
/// triangles (2π − 1e-7 sr) are accepted.
///
/// # Example
/// ```
/// use areawarp::shapes::SphericalTriangle;
/// use areawarp::{Vec3, Warp};
///
/// // The octant: Ω = π/2.
/// let t = SphericalTriangle::<f64>::new(
///     Vec3::new(1.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
///     Vec3::new(0.0, 0.0, 1.0),
/// )
/// .unwrap();
/// assert!((t.solid_angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// let p = t.map(&0.3, &0.7);
/// assert!((p.norm() - 1.0).abs() < 1e-15 && p.x >= 0.0 && p.y >= 0.0 && p.z >= 0.0);
/// let [u, v] = t.inverse(&p).unwrap();
/// assert!((u - 0.3).abs() < 1e-14 && (v - 0.7).abs() < 1e-14);
/// assert_eq!(t.map(&0.5, &0.0), Vec3::new(0.0, 1.0, 0.0)); // v = 0 is B
/// ```
#[derive(Clone, Debug)]
pub struct SphericalTriangle<T> {
    variant: SphericalTriangleVariant,
    /// Unit vertices.
    a: Vec3<T>,
    b: Vec3<T>,
    c: Vec3<T>,
    /// |B|² (1 up to rounding).
    b_norm2: T,
    /// Solid angle Ω (Van Oosterom–Strackee), Ω/2 and 1/Ω.
    omega: T,
    half_omega: T,
    inv_omega: T,
    /// sin c · sin α = sin a · sin γ = |det(A, B, C)| / sin b.
    d: T,
    /// [C|A], 1 + cos c, sin c · cos α and A − B (inverse, recipe).
    c_perp: Vec3<T>,
    k1a: T,
    ka: T,
    a_minus_b: Vec3<T>,
    /// The map's constants measured from A (u ≤ 1/2) and from C (u > 1/2).
    from_a: Anchor<T>,
    from_c: Anchor<T>,
    /// sin b and 1 + cos b (arc AC), for the inverse.
    sin_b: T,
    one_plus_cos_b: T,
    /// Inward unit normals of the edge planes AB, BC, CA.
    n_ab: Vec3<T>,
    n_bc: Vec3<T>,
    n_ca: Vec3<T>,
    /// `true` if det(A, B, C) > 0 (counter-clockwise seen from outside).
    positive: bool,
    /// The published algorithm's constants.
    literal: Literal<T>,
    /// The planar triangle behind the directions, for
    /// [`LightWarp::sample_light`].
    emitter: Emitter<T>,
}

/// The planar triangle a [`SphericalTriangle`] is the image of: its vertices
/// relative to the observer (the vectors given to the constructor, not
/// normalized) and the observer.
#[derive(Clone, Debug)]
struct Emitter<T> {
    observer: Vec3<T>,
    vertices: [Vec3<T>; 3],
}

impl<T: Real> SphericalTriangle<T> {
    /// The spherical triangle with vertex directions `a`, `b`, `c`
    /// (normalized here), evaluated with the default
    /// [`Robust`](SphericalTriangleVariant::Robust) variant.
    ///
    /// # Errors
    /// - [`WarpError::NonFinite`] if a coordinate is NaN or infinite.
    /// - [`WarpError::Degenerate`] for a zero vertex vector, coincident
    ///   directions, vertices on one great circle or collinear on their chord
    ///   triangle (see the type's docs), or a solid angle whose reciprocal
    ///   overflows.
    pub fn new(a: Vec3<T>, b: Vec3<T>, c: Vec3<T>) -> Result<Self, WarpError> {
        Self::new_with(a, b, c, SphericalTriangleVariant::Robust)
    }

    /// As [`SphericalTriangle::new`], with the given evaluation variant.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`] (the variant does not affect validation).
    pub fn new_with(
        a: Vec3<T>,
        b: Vec3<T>,
        c: Vec3<T>,
        variant: SphericalTriangleVariant,
    ) -> Result<Self, WarpError> {
        for (v, what) in [(&a, "vertex A"), (&b, "vertex B"), (&c, "vertex C")] {
            if !v.is_finite() {
                return Err(WarpError::NonFinite { what });
            }
        }
        let zero_vertex = WarpError::Degenerate {
            what: "zero vertex direction",
        };
        let emitter = Emitter {
            observer: Vec3::zero(),
            vertices: [a.clone(), b.clone(), c.clone()],
        };
        let a = unit(&a).ok_or(zero_vertex.clone())?;
        let b = unit(&b).ok_or(zero_vertex.clone())?;
        let c = unit(&c).ok_or(zero_vertex)?;
        let zero = T::zero();
        let one = T::one();
        let two = T::from_i64(2);

        let ab = b.sub(&a);
        let bc = c.sub(&b);
        let ca = a.sub(&c);
        let (l_ab, l_bc, l_ca) = (norm2(&ab).sqrt(), norm2(&bc).sqrt(), norm2(&ca).sqrt());
        if l_ab == zero || l_bc == zero || l_ca == zero {
            return Err(WarpError::Degenerate {
                what: "coincident vertices",
            });
        }
        // det(A, B, C) = V·(e₁ × e₂) from the vertex V opposite the longest
        // chord (e₁, e₂ the two shortest chords): the cross product of short
        // difference vectors keeps relative accuracy for small triangles.
        let (det, l1, l2) = if l_bc >= l_ab && l_bc >= l_ca {
            (a.dot(&ab.cross(&ca.neg())), &l_ab, &l_ca)
        } else if l_ca >= l_ab {
            (b.dot(&bc.cross(&ab.neg())), &l_ab, &l_bc)
        } else {
            (c.dot(&ca.cross(&bc.neg())), &l_bc, &l_ca)
        };
        let threshold = T::from_i64(256) * &T::unit_roundoff() * l1 * l2;
        if det.is_nan() || det.abs() <= threshold {
            return Err(WarpError::Degenerate {
                what: "vertices on one great circle (or collinear)",
            });
        }
        let ccw = det > zero;
        let abs_det = det.abs();

        let on_arc = WarpError::Degenerate {
            what: "coincident or antipodal vertices",
        };
        let (c_perp, sin_b) = tangent(&a, &c).ok_or(on_arc)?;
        let d = abs_det.clone() / &sin_b;
        let a_plus_b = a.add(&b);
        let a_plus_c = a.add(&c);
        let k1a = norm2(&a_plus_b) / &two;
        let ka = ab.dot(&c_perp);
        // 1 + A·B + B·C + C·A = (1 + A·B) + C·(A + B).
        let den = k1a.clone() + &c.dot(&a_plus_b);
        let omega = abs_det.atan2(&den) * &two;
        let inv_omega = one.clone() / &omega;
        if !positive(&omega) || !inv_omega.is_finite() || !positive(&d) || !d.is_finite() {
            return Err(WarpError::Degenerate {
                what: "solid angle underflows",
            });
        }
        let sign = if ccw { one.clone() } else { -one.clone() };
        let inward = |v: &Vec3<T>, e: &Vec3<T>| unit(&v.cross(e).scale(&sign));
        let normals_degenerate = WarpError::Degenerate {
            what: "edge plane undefined",
        };
        let n_ab = inward(&a, &ab).ok_or(normals_degenerate.clone())?;
        let n_bc = inward(&b, &bc).ok_or(normals_degenerate.clone())?;
        let n_ca = inward(&c, &ca).ok_or(normals_degenerate)?;
        let from_a = Anchor::new(&a, &c, &b, &d, &sign)?;
        let from_c = Anchor::new(&c, &a, &b, &d, &-sign.clone())?;
        let literal = Literal::new(&a, &b, &c);
        Ok(SphericalTriangle {
            variant,
            b_norm2: norm2(&b),
            half_omega: omega.clone() / &two,
            omega,
            inv_omega,
            d,
            k1a,
            ka,
            a_minus_b: ab.neg(),
            c_perp,
            from_a,
            from_c,
            one_plus_cos_b: norm2(&a_plus_c) / &two,
            sin_b,
            n_ab,
            n_bc,
            n_ca,
            positive: ccw,
            literal,
            emitter,
            a,
            b,
            c,
        })
    }

    /// The spherical triangle subtended by the points `p0`, `p1`, `p2` as
    /// seen from `observer`: vertex directions `p_i − observer`.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`]; a point at the observer gives
    /// [`WarpError::Degenerate`] (zero vertex direction), a difference that
    /// overflows [`WarpError::NonFinite`].
    pub fn from_points(
        p0: Vec3<T>,
        p1: Vec3<T>,
        p2: Vec3<T>,
        observer: Vec3<T>,
    ) -> Result<Self, WarpError> {
        for (v, what) in [
            (&p0, "point 0"),
            (&p1, "point 1"),
            (&p2, "point 2"),
            (&observer, "observer"),
        ] {
            if !v.is_finite() {
                return Err(WarpError::NonFinite { what });
            }
        }
        let mut t = Self::new(p0.sub(&observer), p1.sub(&observer), p2.sub(&observer))?;
        t.emitter.observer = observer;
        Ok(t)
    }

    /// The barycentric coordinates `[b_A, b_B, b_C]` (non-negative, summing
    /// to 1) of the point where the ray from the observer along `direction`
    /// meets the plane of the triangle's vertices, the vectors given to the
    /// constructor: `b_A ∝ d·(B × C)`, `b_B ∝ d·(C × A)`, `b_C ∝ d·(A × B)`
    /// (signed volumes), clamped to the triangle.
    pub fn barycentrics(&self, direction: &Vec3<T>) -> [T; 3] {
        let [va, vb, vc] = &self.emitter.vertices;
        let zero = T::zero();
        let sign = if self.positive { T::one() } else { -T::one() };
        let w = [
            (direction.dot(&vb.cross(vc)) * &sign).max(&zero),
            (direction.dot(&vc.cross(va)) * &sign).max(&zero),
            (direction.dot(&va.cross(vb)) * &sign).max(&zero),
        ];
        let sum = w[0].clone() + &w[1] + &w[2];
        if !(sum > zero) || !sum.is_finite() {
            let third = T::from_ratio(1, 3);
            return [third.clone(), third.clone(), third];
        }
        w.map(|x| x / &sum)
    }

    /// The same triangle evaluated with `variant`.
    pub fn with_variant(mut self, variant: SphericalTriangleVariant) -> Self {
        self.variant = variant;
        self
    }

    /// The evaluation variant.
    pub fn variant(&self) -> SphericalTriangleVariant {
        self.variant
    }

    /// Unit vertex A (the image of u = 0, v = 1).
    pub fn a(&self) -> &Vec3<T> {
        &self.a
    }
    /// Unit vertex B (the image of v = 0).
    pub fn b(&self) -> &Vec3<T> {
        &self.b
    }
    /// Unit vertex C (the image of u = 1, v = 1).
    pub fn c(&self) -> &Vec3<T> {
        &self.c
    }

    /// The solid angle Ω (steradians), by Van Oosterom–Strackee:
    /// `Ω = 2·atan2(|det(A, B, C)|, 1 + A·B + B·C + C·A)`, accurate to a few
    /// units of roundoff relative for every accepted triangle. The density of
    /// both variants is `1/Ω`.
    pub fn solid_angle(&self) -> T {
        self.omega.clone()
    }

    /// Girard's solid angle α + β + γ − π with the angles computed as in the
    /// [`Literal`](SphericalTriangleVariant::Literal) variant (dihedral
    /// angles by `acos` of normalized edge-plane normals): the value the
    /// published algorithm samples with. Loses all accuracy for small
    /// triangles; for comparison only.
    pub fn girard_solid_angle(&self) -> T {
        self.literal.area.clone()
    }

    /// `true` if `det(A, B, C) > 0` (the vertices run counter-clockwise seen
    /// from outside the sphere).
    pub fn is_counter_clockwise(&self) -> bool {
        self.positive
    }

    /// The recipe specification of this triangle (steps 1–3).
    pub fn recipe(&self) -> SphericalTriangleRecipe<T> {
        SphericalTriangleRecipe::new(self.clone())
    }

    /// ψ(u, v) by the [`Robust`](SphericalTriangleVariant::Robust)
    /// evaluation, whatever the triangle's variant. `u`, `v` are clamped to
    /// `[0, 1]` (NaN counts as 0).
    pub fn map_robust(&self, u: &T, v: &T) -> Vec3<T> {
        let u = clamp01(u);
        let v = clamp01(v);
        let one = T::one();
        let two = T::from_i64(2);
        let half = T::from_ratio(1, 2);
        let (anchor, h) = if u <= half {
            (&self.from_a, u * &self.half_omega)
        } else {
            (&self.from_c, (one.clone() - &u) * &self.half_omega)
        };
        let (sh, ch) = h.sin_cos();
        // Step 1 (V = anchor vertex, c = ∠VB, α = angle at V, d, k as in the
        // type's docs): tan(b_s/2) = n/m with n = (1 + cos c) sin h / d and
        // m = cos h − (k/d) sin h = sin(α − h)/sin α (eq. T divided by d).
        // The angle β_s at B between the arcs B V and B C_s (eq. B):
        // (sin β_s, cos β_s) ∝ (nb, cb) = (sin h·m, 1 − sin h (k cos h + d sin h)/d)/sin²(c/2).
        let n = anchor.k1_d.clone() * &sh;
        let m = ch.clone() - &(anchor.k_d.clone() * &sh);
        let nb = sh.clone() * &m * &anchor.inv_s2;
        let cb = one.clone() - &(sh.clone() * &(anchor.k_d.clone() * &ch + &sh) * &anchor.inv_s2);
        // g = 2n/(n² + m²) = sin b_s / m.
        let g = (n.clone() + &n) / &(n.square() + &m.square());
        let nd2 = nb.square() + &cb.square();
        // Independent of g: the two divisions overlap.
        let inv_nd2 = one.clone() / &nd2;
        // C_s − V = sin b_s·[W|V] − (1 − cos b_s)·V; D = C_s − B.
        let delta = anchor
            .along
            .scale(&(g.clone() * &m))
            .sub(&anchor.vertex.scale(&(g * &n)));
        let d_vec = delta.add(&anchor.v_minus_b);
        // sin²(a_s/2) of the arc B C_s.
        let s2 = norm2(&d_vec) / T::from_i64(4);
        // Step 2: θ = ∠BP with sin²(θ/2) = v sin²(a_s/2),
        // cos²(θ/2) = cos²(a_s/2) + (1 − v) sin²(a_s/2).
        let p = if v <= half {
            // P = B + sin θ·W − (1 − cos θ)·B with W = (cb·t_b + nb·n_b)/|(nb, cb)|;
            // here cos²(θ/2) = 1 − sin²(θ/2) ≥ 1/2 (no cancellation, and
            // cos²(a_s/2) is not needed), and sin θ/|(nb, cb)| is one root.
            let sp2 = v * &s2;
            let f = (sp2.clone() * &(one.clone() - &sp2) * &inv_nd2).sqrt() * &two;
            let offset = anchor
                .t_b
                .scale(&(f.clone() * &cb))
                .add(&anchor.n_b.scale(&(f * &nb)))
                .sub(&self.b.scale(&(sp2 * &two)));
            self.b.add(&offset)
        } else {
            // From the other end: with C_s = cos a_s·B + sin a_s·W,
            // P = C_s + (cos θ − cos a_s)·B + (sin θ − sin a_s)·W, where
            // cos θ − cos a_s = 2 sin²(a_s/2)(1 − v) exactly and
            // sin θ − sin a_s = 2(sin(θ/2) cos(θ/2) − sin(a_s/2) cos(a_s/2)):
            // both vanish at v = 1 (P = C_s, so (0, 1) ↦ A and (1, 1) ↦ C),
            // and are small, with small absolute errors, near it.
            // cos²(a_s/2) = |C_s + B|²/4 keeps its accuracy when C_s ≈ −B.
            let c2 = norm2(&delta.add(&anchor.v_plus_b)) / T::from_i64(4);
            let cp2 = c2.clone() + &((one.clone() - &v) * &s2);
            // sin(θ/2) cos(θ/2) and sin(a_s/2) cos(a_s/2), over |(nb, cb)|.
            let half_sin_theta = (v.clone() * &s2 * &cp2 * &inv_nd2).sqrt();
            let half_sin_a = (s2.clone() * &c2 * &inv_nd2).sqrt();
            let w_coef = (half_sin_theta - &half_sin_a) * &two;
            let b_coef = s2 * &(one - &v) * &two;
            let c_s = anchor.vertex.add(&delta);
            let offset = self
                .b
                .scale(&b_coef)
                .add(&anchor.t_b.scale(&(w_coef.clone() * &cb)))
                .add(&anchor.n_b.scale(&(w_coef * &nb)));
            c_s.add(&offset)
        };
        // |P| = 1 + O(u): one Newton step towards |P| = |B| (|B| = 1 up to
        // the rounding of the stored vertex), P·(1 + (|B|² − |P|²)/2), brings
        // the norm to within about one unit of roundoff without a square root
        // and leaves P = B (v = 0) untouched.
        let x = norm2(&p);
        p.scale(&(T::one() + &((self.b_norm2.clone() - &x) / &two)))
    }

    /// ψ(u, v) by the [`Literal`](SphericalTriangleVariant::Literal)
    /// evaluation (Arvo 1995 as published), whatever the triangle's variant.
    /// May return NaN coordinates (see the variant's docs).
    pub fn map_literal(&self, u: &T, v: &T) -> Vec3<T> {
        self.literal.map(&self.a, &self.b, u, v)
    }

    /// Where the great circle through B and the unit direction `q` meets the
    /// arc AC: returns `(sin(θ/2), cos(θ/2), n̂₁, q − B)` with θ = ∠AC_s and
    /// `n̂₁ = (B × q)/|B × q|`; `None` if `q = ±B`.
    fn chart_half_angle(&self, q: &Vec3<T>) -> Option<(T, T, Vec3<T>, Vec3<T>)> {
        let w = q.sub(&self.b);
        // n₁ = B × q, from the shorter of q ∓ B (no cancellation near ±B).
        let n1 = if q.dot(&self.b) >= T::zero() {
            self.b.cross(&w)
        } else {
            self.b.cross(&q.add(&self.b))
        };
        let n1 = unit(&n1)?;
        // C_s = cos θ·A + sin θ·[C|A] with C_s·n₁ = 0:
        // (sin θ, cos θ) ∝ (−A·n₁, [C|A]·n₁), A·n₁ = (A − B)·n₁ exactly.
        let mut y = -self.a_minus_b.dot(&n1);
        let mut x = self.c_perp.dot(&n1);
        // Of the two antipodal intersections take the one on the side of the
        // arc's midpoint: x·cos(b/2) + y·sin(b/2) ≥ 0, scaled by 2cos(b/2).
        if x.clone() * &self.one_plus_cos_b + &(y.clone() * &self.sin_b) < T::zero() {
            x = -x;
            y = -y;
        }
        let r = x.hypot(&y);
        if !positive(&r) || !r.is_finite() {
            return None;
        }
        // tan(θ/2) = y/(r + x) = (r − x)/y, whichever does not cancel.
        let (s, c) = if x >= T::zero() {
            (y, r + &x)
        } else {
            (r - &x, y)
        };
        let m = s.hypot(&c);
        Some((s / &m, c / &m, n1, w))
    }

    /// `(C_s − B, C_s + B)` for `C_s` at the half-angle `(sin(θ/2), cos(θ/2))`
    /// from A: `C_s − A = 2 sin(θ/2)(cos(θ/2)[C|A] − sin(θ/2)A)`.
    fn chart_offsets(&self, s: &T, c: &T) -> (Vec3<T>, Vec3<T>) {
        let two_s = s.clone() * &T::from_i64(2);
        let delta = self
            .c_perp
            .scale(&(two_s.clone() * c))
            .sub(&self.a.scale(&(two_s * s)));
        (
            delta.add(&self.from_a.v_minus_b),
            delta.add(&self.from_a.v_plus_b),
        )
    }

    /// ψ⁻¹ by the robust formulas (see [`Warp::inverse`]), without the
    /// on-shape test; `q` must be a unit vector.
    fn inverse_robust(&self, q: &Vec3<T>) -> Option<(T, T)> {
        let Some((s, c, n1, w)) = self.chart_half_angle(q) else {
            // q = B (v = 0, any u), or q = −B (not on the triangle).
            return if norm2(&q.sub(&self.b)) == T::zero() {
                Some((T::zero(), T::zero()))
            } else {
                None
            };
        };
        let (d_vec, e_vec) = self.chart_offsets(&s, &c);
        let two = T::from_i64(2);
        // Area of A B C_s measured from A (eq. T at A):
        // tan(A_s/2) = sin c sin α·sin(θ/2) / ((1 + cos c) cos(θ/2) + sin c cos α·sin(θ/2)).
        // It needs only θ, but its denominator cancels when A_s ≈ π with
        // A, B, C_s near one great circle (nearly hemispherical triangles).
        let num_a = self.d.clone() * &s;
        let (t1, t2) = (self.k1a.clone() * &c, self.ka.clone() * &s);
        let den_a = t1.clone() + &t2;
        let half_area = if t1.abs() + &t2.abs() <= num_a.hypot(&den_a) * &T::from_i64(8) {
            num_a.atan2(&den_a)
        } else {
            // Measured from B instead (eq. T at B): with W = n̂₁ × B the unit
            // tangent at B towards q, sin c·sin β_s = det(A, B, W) = A·n̂₁ and
            // sin c·cos β_s = A·W,
            // tan(A_s/2) = sin(a_s/2)·sin c sin β_s / ((1 + cos c) cos(a_s/2) + sin c cos β_s·sin(a_s/2)).
            // β_s comes from q directly, and cos(a_s/2) — ill-determined when
            // C_s ≈ −B — only enters to absolute accuracy.
            let sa = norm2(&d_vec).sqrt() / &two;
            let ca = norm2(&e_vec).sqrt() / &two;
            let tangent_b = n1.cross(&self.b);
            let sign = if self.positive { T::one() } else { -T::one() };
            let d_b = self.a_minus_b.dot(&n1) * &sign;
            let k_b = self.a_minus_b.dot(&tangent_b);
            (sa.clone() * &d_b).atan2(&(self.k1a.clone() * &ca + &(k_b * &sa)))
        };
        let u = half_area / &self.half_omega;
        // v = sin²(∠Bq/2) / sin²(a_s/2) = |q − B|² / |C_s − B|².
        let v = norm2(&w) / &norm2(&d_vec);
        Some((clamp_keep_nan(&u), clamp_keep_nan(&v)))
    }

    /// `true` if `p` lies on the triangle within the inverse's tolerance
    /// `2^(−p/2)` (p the precision: ≈ 1.1e-8 in `f64`).
    pub fn contains(&self, p: &Vec3<T>) -> bool {
        self.outside_by(p) <= on_shape_tolerance::<T>()
    }
}

/// How far off a shape a point may lie for `inverse` to accept it:
/// `2^(−p/2)` for a `p`-bit type.
fn on_shape_tolerance<T: Real>() -> T {
    T::exp2i(-((T::precision() / 2) as i32))
}

impl<T: Real> Warp<T> for SphericalTriangle<T> {
    type Point = Vec3<T>;

    /// ψ(u, v) by the triangle's variant ([`SphericalTriangle::map_robust`]
    /// or [`SphericalTriangle::map_literal`]).
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        match self.variant {
            SphericalTriangleVariant::Robust => self.map_robust(u, v),
            SphericalTriangleVariant::Literal => self.map_literal(u, v),
        }
    }

    /// `1/Ω` (Van Oosterom–Strackee Ω, for both variants), whatever `p`: the
    /// density is constant on the triangle; use
    /// [`SphericalTriangle::contains`] to test membership.
    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        self.inv_omega.clone()
    }

    /// Ω.
    fn measure(&self) -> T {
        self.omega.clone()
    }

    /// `(u, v)` of the direction `p` (normalized first): `C_s` is where the
    /// great circle through B and p meets the arc AC, `u = area(A B C_s)/Ω`
    /// and `v = |p − B|²/|C_s − B|²` (= (1 − cos∠Bp)/(1 − cos∠BC_s) by
    /// half-angle sines), the area with the same half-angle formula as the
    /// robust map, for both variants (Arvo 1995 gives no inverse; the
    /// literal Girard-formula inverse returned NaN at the edges v = 0 and
    /// u = 0). Refuses `p` if it is not finite or lies farther than
    /// `2^(−p/2)` from the triangle ([`SphericalTriangle::contains`]);
    /// `p = B` gives `(0, 0)`.
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let refuse = || InverseError::refuse(self, p);
        let q = unit(p).ok_or_else(refuse)?;
        // Both variants invert with the robust formulas: Arvo (1995) gives
        // no inverse, and the map is the same function in both.
        let (u, v) = self.inverse_robust(&q).ok_or_else(refuse)?;
        Ok([u, v])
    }

    /// A lower bound of the Euclidean distance from `p` to the triangle (as a
    /// set of unit vectors), within a factor √2 of it near the triangle:
    /// `max(| |p| − 1 |, max_i −n_i·(p̂ − V_i))` with `n_i` the inward unit
    /// normals of the three edge planes, `V_i` a vertex of edge i and
    /// `p̂ = p/|p|`; 0 on the triangle. The triangle is the intersection of
    /// the three hemispheres `n_i·p ≥ 0`, so a direction outside it violates
    /// at least one of them (the antipodal region violates all three).
    /// Non-finite or zero `p`: [`Real::max_value`].
    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let Some(q) = unit(p) else {
            return T::max_value();
        };
        let radial = (p.norm() - &T::one()).abs();
        let v_ab = -self.n_ab.dot(&q.sub(&self.a));
        let v_bc = -self.n_bc.dot(&q.sub(&self.b));
        let v_ca = -self.n_ca.dot(&q.sub(&self.c));
        radial.max(&v_ab).max(&v_bc).max(&v_ca).max(&T::zero())
    }
}

impl<T: Real> WarpFamily<T> for SphericalTriangle<T> {
    type At<S: Real> = SphericalTriangle<S>;

    /// The triangle with its unit vertices converted to `S` (and normalized
    /// again there), same variant.
    fn at<S: Real>(&self) -> Result<SphericalTriangle<S>, WarpError> {
        SphericalTriangle::new_with(
            self.a.convert(),
            self.b.convert(),
            self.c.convert(),
            self.variant,
        )
    }

    /// `spherical-triangle` (both variants).
    fn name(&self) -> String {
        "spherical-triangle".to_string()
    }
}

crate::warp::distribution_for_floats!(SphericalTriangle, Vec3);

impl<T: Real> LightWarp<T> for SphericalTriangle<T> {
    /// The observer given to [`SphericalTriangle::from_points`] (the origin
    /// for [`SphericalTriangle::new`]).
    fn observer(&self) -> Vec3<T> {
        self.emitter.observer.clone()
    }

    /// The direction ψ(u, v) and the point where it meets the planar
    /// triangle whose vertices the constructor was given (relative to the
    /// observer): with `n = (B − A) × (C − A)`, the ray `t·d` meets the plane
    /// at `t = det(A, B, C) / (d·n)`, and `|cos θ_e| = |d·n| / |n|`.
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T> {
        let [u, v] = uv;
        let d = self.map(&u, &v);
        let [va, vb, vc] = &self.emitter.vertices;
        let n = vb.sub(va).cross(&vc.sub(va));
        let dn = d.dot(&n);
        let t = (va.dot(&n) / &dn).abs();
        let cos_e = dn.abs() / &n.norm();
        let pdf = self.inv_omega.clone();
        let pdf_area = pdf.clone() * &cos_e / &t.square();
        LightSample {
            point: self.emitter.observer.add(&d.scale(&t)),
            direction: d,
            distance: t,
            pdf,
            pdf_area,
        }
    }
}
