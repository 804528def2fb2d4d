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

mod build;
mod ladder;
mod literal;
mod one_shot;
mod recipe;
mod robust;
#[cfg(test)]
mod tests;

pub use ladder::{hard_triangles, ordinary_triangles};
pub use recipe::SphericalTriangleRecipe;

use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::light_plane::LightPlane;
use crate::shapes::turns::clamp_unit;
use crate::shapes::wide::{check_finite, narrow3, unit_vector, widen3};
use crate::vector::Vec3;
use crate::warp::{InverseError, LightSample, LightWarp, Warp, WarpFamily, on_shape_tolerance};
use build::{Anchor, Core, Scalars, Validated};
use literal::Literal;
use std::sync::{Arc, OnceLock};

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

/// `x` clamped to `[0, 1]`, NaN kept (for values that report failure).
fn clamp_keep_nan<T: Real>(x: &T) -> T {
    clamp_unit(x)
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
/// `|det(A, B, C)| ≤ 256·u·ℓ₁ℓ₂` (u the unit roundoff of [`Real::Wide`],
/// ℓ₁ ≤ ℓ₂ the two shortest chords |A − B|, |B − C|, |C − A|). Since
/// `det(A, B, C) = ℓ₁ℓ₂·sin θ·dist(O, plane ABC)` with θ the largest angle of
/// the planar triangle ABC, the criterion is scale-free: it rejects vertices
/// collinear on the sphere's chord triangle (θ → 0 or π) and vertices on
/// one great circle (plane through the origin), in both cases only when the
/// orientation of the triangle is lost in the rounding of the determinant.
/// It also rejects two vertices X, Y that are nearly antipodal,
/// `|X + Y| ≤ 64·2^(−p/2)` (`≈ 5.8e-7` in `f64`): the great arc between them
/// is then determined (by `X × Y`, of length `≈ |X + Y|`) only to
/// `u/|X + Y|`, worse than the on-shape tolerance `2^(−p/2)` of the inverse.
/// Tiny triangles (1e-12 sr in `f64`), slivers and nearly hemispherical
/// triangles (2π − 1e-7 sr) are accepted.
///
/// # Precision
/// Every decision and every constant of the constructor is computed in
/// [`Real::Wide`] (`f64` for `f32`) from the vertices as given, and the
/// constants are rounded to `T`: an `f32` triangle is accepted exactly when
/// the `f64` constructor accepts the same values, except when `f32` cannot
/// hold its solid angle, density or a constant
/// ([`WarpError::Unrepresentable`]). The per-sample path runs in `T`.
///
/// # Inputs outside the unit square
/// `u`, `v` outside `[0, 1]` are clamped to it; a NaN `u` or `v` gives a
/// NaN point (it is not a point of `[0, 1]²`, and the map does not make a
/// boundary point up for it). For `(u, v) ∈ [0, 1]²` the point is finite and
/// on the triangle.
///
/// # Cost
/// The constructor computes the validation, Ω and the robust map's constants
/// (two anchors of three vectors and three scalars each); the literal
/// variant's constants only for that variant, and the edge-plane normals of
/// [`Warp::outside_by`] and [`Warp::inverse`] on their first use. Sampling
/// one direction of a triangle used once (a renderer's shading point):
/// [`SphericalTriangle::sample_once`], which builds only the anchor the
/// sample needs ([`SphericalTriangle::sample_light_once`] for a light
/// sample of points: with the point, distance and density in area); its
/// solid angle alone: [`SphericalTriangle::solid_angle_of`].
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
/// assert!(t.map(&f64::NAN, &0.5).x.is_nan());
/// ```
#[derive(Clone, Debug)]
pub struct SphericalTriangle<T: Real> {
    variant: SphericalTriangleVariant,
    /// The vertex directions as given (what [`WarpFamily::at`] rebuilds
    /// from): the planar triangle behind the directions, relative to the
    /// observer, for [`LightWarp::sample_light`].
    input: [Vec3<T>; 3],
    /// The observer given to [`SphericalTriangle::from_points`] (the origin
    /// for [`SphericalTriangle::new`]).
    observer: Vec3<T>,
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
    /// [C|A], 1 + cos c, sin c · cos α, A − B and A + B (inverse, recipe).
    c_perp: Vec3<T>,
    k1a: T,
    ka: T,
    a_minus_b: Vec3<T>,
    a_plus_b: Vec3<T>,
    /// The map's constants measured from A (u ≤ 1/2) and from C (u > 1/2).
    anchors: [Anchor<T>; 2],
    /// sin b and 1 + cos b (arc AC), for the inverse.
    sin_b: T,
    one_plus_cos_b: T,
    /// Inward unit normals of the edge planes AB, BC, CA, computed on the
    /// first call of `outside_by`/`inverse`.
    normals: OnceLock<[Vec3<T>; 3]>,
    /// The plane of the vertices as given, for `sample_light` (`None` for
    /// vertex directions whose plane `T` cannot hold).
    plane: Option<LightPlane<T>>,
    /// `true` if det(A, B, C) > 0 (counter-clockwise seen from outside).
    positive: bool,
    /// The published algorithm's constants (literal variant only).
    literal: Option<Literal<T>>,
    /// The same triangle in [`Real::Wide`], for the inverse of a narrower
    /// `T` (built on its first use).
    wide: OnceLock<Arc<dyn WideInverse<T>>>,
}

/// The inverse of a triangle evaluated in the wide type (type-erased, so
/// that `SphericalTriangle<T>` does not contain `SphericalTriangle<T::Wide>`).
trait WideInverse<T>: Send + Sync + core::fmt::Debug {
    fn inverse(&self, p: &Vec3<T>) -> Option<(T, T)>;
}

/// A triangle in `T::Wide` answering for `T`.
#[derive(Debug)]
struct WideTriangle<T: Real>(SphericalTriangle<T::Wide>);

impl<T: Real> WideInverse<T> for WideTriangle<T> {
    fn inverse(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let q = unit_vector(&widen3(p))?;
        let (u, v) = self.0.inverse_robust(&self.0.onto_triangle(&q))?;
        Some((T::narrow(&u), T::narrow(&v)))
    }
}

/// The directions `p_i − observer` rounded to `T`, and the wide triangle
/// validated.
type PointsValidated<T> = ([Vec3<T>; 3], Validated<<T as Real>::Wide>);

/// The reason a triangle is rejected.
fn out_of_range() -> WarpError {
    build::reject::OUT_OF_RANGE
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
    ///   triangle, two nearly antipodal vertices (see the type's docs), or a
    ///   solid angle that underflows [`Real::Wide`].
    /// - [`WarpError::Unrepresentable`] if the solid angle, its reciprocal or
    ///   a constant of the map is outside `T`'s range (the same triangle is
    ///   accepted in [`Real::Wide`]).
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
        let core = build::core_of(&a, &b, &c)?;
        Self::from_core(&core, [a, b, c], variant, false)
    }

    /// The triangle from its validated wide core; `light`: the input are
    /// points of an emitter, whose plane `T` must hold (else the plane is
    /// optional, see [`SphericalTriangle::sample_light`](LightWarp::sample_light)).
    fn from_core(
        core: &Core<T::Wide>,
        input: [Vec3<T>; 3],
        variant: SphericalTriangleVariant,
        light: bool,
    ) -> Result<Self, WarpError> {
        let two = <T::Wide as Real>::from_i64(2);
        let Scalars {
            omega,
            inv_omega,
            half_omega,
            d,
        } = Scalars::of(core)?;
        let anchors = [
            core.anchor(true)?.narrow::<T>().ok_or_else(out_of_range)?,
            core.anchor(false)?.narrow::<T>().ok_or_else(out_of_range)?,
        ];
        let a = narrow3::<T>(&core.v.a);
        let b = narrow3::<T>(&core.v.b);
        let c = narrow3::<T>(&core.v.c);
        let literal = match variant {
            SphericalTriangleVariant::Literal => Some(Literal::new(&a, &b, &c)),
            SphericalTriangleVariant::Robust => None,
        };
        let plane = match LightPlane::new(&input, &Vec3::zero(), &inv_omega, &inv_omega) {
            Ok(p) => Some(p),
            Err(e) if light => return Err(e),
            Err(_) => None,
        };
        Ok(SphericalTriangle {
            variant,
            input,
            observer: Vec3::zero(),
            b_norm2: build::norm2(&b),
            half_omega,
            omega,
            inv_omega,
            d,
            k1a: T::narrow(&core.v.k1a),
            ka: T::narrow(&core.ka),
            a_minus_b: narrow3::<T>(&core.v.ab.neg()),
            // A + B as the validation formed it.
            a_plus_b: narrow3::<T>(&core.v.at_b[0].1),
            c_perp: narrow3::<T>(&core.c_perp),
            anchors,
            // 1 + cos b = |A + C|²/2, from the validation's |A + C|².
            one_plus_cos_b: T::narrow(&(core.v.p_ca.clone() / &two)),
            sin_b: T::narrow(&core.sin_b),
            normals: OnceLock::new(),
            plane,
            wide: OnceLock::new(),
            positive: core.ccw,
            literal,
            a,
            b,
            c,
        })
    }

    /// The spherical triangle subtended by the points `p0`, `p1`, `p2` as
    /// seen from `observer`: vertex directions `p_i − observer`, computed in
    /// [`Real::Wide`] (exactly, for `f32` points of similar magnitude); the
    /// directions rounded to `T` are what [`WarpFamily::at`] rebuilds from.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`]; a point at the observer gives
    /// [`WarpError::Degenerate`] (zero vertex direction), a difference that
    /// overflows [`WarpError::NonFinite`], and a triangle whose plane's
    /// distances or densities in area `T` cannot hold (the light sample's
    /// point, distance and `pdf_area`: points very far or very near at
    /// either end of `T`'s range, or a plane through the observer's
    /// neighbourhood) [`WarpError::Unrepresentable`].
    pub fn from_points(
        p0: Vec3<T>,
        p1: Vec3<T>,
        p2: Vec3<T>,
        observer: Vec3<T>,
    ) -> Result<Self, WarpError> {
        Self::from_points_with(&p0, &p1, &p2, &observer, true)
    }

    /// [`SphericalTriangle::from_points`]; `light`: the plane of the points
    /// must be one `T` holds (else, as for `new`, the plane is optional:
    /// what the one-shot direction, which returns no point, is held to).
    fn from_points_with(
        p0: &Vec3<T>,
        p1: &Vec3<T>,
        p2: &Vec3<T>,
        observer: &Vec3<T>,
        light: bool,
    ) -> Result<Self, WarpError> {
        let (d, tri) = Self::from_points_validated::<true>(p0, p1, p2, observer)?;
        let core = Core::from_validated(tri)?;
        let mut t = Self::from_core(&core, d, SphericalTriangleVariant::Robust, light)?;
        t.observer = observer.clone();
        Ok(t)
    }

    /// The barycentric coordinates `[b_A, b_B, b_C]` (non-negative, summing
    /// to 1) of the point where the ray from the observer along `direction`
    /// meets the plane of the triangle's vertices, the vectors given to the
    /// constructor: `b_A ∝ d·(B × C)`, `b_B ∝ d·(C × A)`, `b_C ∝ d·(A × B)`
    /// (signed volumes), clamped to the triangle.
    pub fn barycentrics(&self, direction: &Vec3<T>) -> [T; 3] {
        let [va, vb, vc] = &self.input;
        let zero = T::zero();
        let sign = if self.positive { T::one() } else { -T::one() };
        let w = [
            (direction.dot(&vb.cross(vc)) * &sign).max(&zero),
            (direction.dot(&vc.cross(va)) * &sign).max(&zero),
            (direction.dot(&va.cross(vb)) * &sign).max(&zero),
        ];
        let sum = w[0].clone() + &w[1] + &w[2];
        if !sum.is_finite_above(&zero) {
            let third = T::from_ratio(1, 3);
            return [third.clone(), third.clone(), third];
        }
        w.map(|x| x / &sum)
    }

    /// The directions `p_i − observer` rounded to `T`, and the triangle of
    /// the wide directions validated. `CHECKED`: a point that is not finite,
    /// or a difference that overflows, is refused as such
    /// ([`WarpError::NonFinite`]); unchecked (the one-shots' hot path, whose
    /// every error goes to the constructor to be named), it fails the
    /// validation instead (a direction with an infinite coordinate has no
    /// unit vector; a NaN makes the determinant NaN).
    #[inline(always)]
    fn from_points_validated<const CHECKED: bool>(
        p0: &Vec3<T>,
        p1: &Vec3<T>,
        p2: &Vec3<T>,
        observer: &Vec3<T>,
    ) -> Result<PointsValidated<T>, WarpError> {
        if CHECKED {
            check_finite([
                (p0, "point 0"),
                (p1, "point 1"),
                (p2, "point 2"),
                (observer, "observer"),
            ])?;
        }
        let o = widen3(observer);
        let d = [widen3(p0).sub(&o), widen3(p1).sub(&o), widen3(p2).sub(&o)];
        // A difference of two finite `T` values overflows only when the
        // wide type is `T` itself (its range not at least twice `T`'s).
        if CHECKED
            && <T::Wide as Real>::max_value()
                <= T::max_value().widen() * &<T::Wide as Real>::from_i64(2)
        {
            check_finite([
                (&d[0], "vertex A"),
                (&d[1], "vertex B"),
                (&d[2], "vertex C"),
            ])?;
        }
        let tri = Validated::new(&d[0], &d[1], &d[2])?;
        Ok((d.map(|v| narrow3::<T>(&v)), tri))
    }

    /// The same triangle evaluated with `variant`.
    pub fn with_variant(mut self, variant: SphericalTriangleVariant) -> Self {
        self.variant = variant;
        if variant == SphericalTriangleVariant::Literal && self.literal.is_none() {
            self.literal = Some(Literal::new(&self.a, &self.b, &self.c));
        }
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

    /// The vertex directions as given to the constructor (`p_i − observer`
    /// for [`SphericalTriangle::from_points`]), not normalized: the
    /// parameters [`WarpFamily::at`] rebuilds the triangle from.
    pub fn vertex_inputs(&self) -> &[Vec3<T>; 3] {
        &self.input
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
        match &self.literal {
            Some(l) => l.area.clone(),
            None => literal::girard(&self.a, &self.b, &self.c),
        }
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
    /// `[0, 1]`; a NaN `u` or `v` gives a NaN point.
    pub fn map_robust(&self, u: &T, v: &T) -> Vec3<T> {
        let anchor = &self.anchors[usize::from(!robust::uses_anchor_a(&clamp_unit(u)))];
        robust::map_from(anchor, &self.b, &self.b_norm2, &self.half_omega, u, v)
    }

    /// ψ(u, v) by the [`Literal`](SphericalTriangleVariant::Literal)
    /// evaluation (Arvo 1995 as published), whatever the triangle's variant
    /// (its constants are computed here for a robust triangle). May return
    /// NaN coordinates (see the variant's docs).
    pub fn map_literal(&self, u: &T, v: &T) -> Vec3<T> {
        match &self.literal {
            Some(l) => l.map(&self.a, &self.b, u, v),
            None => Literal::new(&self.a, &self.b, &self.c).map(&self.a, &self.b, u, v),
        }
    }

    /// The inward unit normals of the edge planes AB, BC, CA, from the wide
    /// core (computed on first use).
    fn normals(&self) -> &[Vec3<T>; 3] {
        self.normals.get_or_init(|| {
            let [a, b, c] = &self.input;
            build::core_of(a, b, c)
                .and_then(|core| core.normals())
                .map(|n| n.map(|v| narrow3::<T>(&v)))
                .unwrap_or_else(|_| {
                    // Unreachable for a validated triangle (the same
                    // computation succeeded in the constructor); the normals
                    // of the stored vertices in `T` as a fallback.
                    let sign = if self.positive { T::one() } else { -T::one() };
                    let inward = |v: &Vec3<T>, w: &Vec3<T>| {
                        unit_vector(&v.cross(&w.sub(v)).scale(&sign)).unwrap_or(Vec3::zero())
                    };
                    [
                        inward(&self.a, &self.b),
                        inward(&self.b, &self.c),
                        inward(&self.c, &self.a),
                    ]
                })
        })
    }

    /// `true` if `p` lies on the triangle within the inverse's tolerance
    /// `2^(−p/2)` (p the precision: ≈ 1.1e-8 in `f64`).
    pub fn contains(&self, p: &Vec3<T>) -> bool {
        self.outside_by(p) <= on_shape_tolerance::<T>()
    }
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
    /// u = 0); for `f32` evaluated in [`Real::Wide`]. Refuses `p` if it is
    /// not finite or lies farther than `2^(−p/2)` from the triangle
    /// ([`SphericalTriangle::contains`]); `p = B` gives `(0, 0)`.
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        let (u, v) = self
            .inverse_unchecked(p)
            .ok_or_else(|| InverseError::refuse(self, p))?;
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
        self.outside_by_impl(p)
    }
}

impl<T: Real> SphericalTriangle<T> {
    /// ψ⁻¹(p) by the triangle's variant without the on-shape test (the
    /// caller knows `p` is on the triangle, e.g. to its own tolerance).
    ///
    /// For a `T` narrower than [`Real::Wide`] (`f32`) the inverse is
    /// evaluated in the wide type: the unit vertices rounded to `f32` are
    /// themselves off by `2⁻²⁴`, which moves where the great circle through
    /// B and `p` meets the arc AC by `2⁻²⁴` over the triangle's angle — all
    /// of it for a needle a few `f32` ulps wide.
    pub(crate) fn inverse_unchecked(&self, p: &Vec3<T>) -> Option<(T, T)> {
        // Both variants invert with the robust formulas: Arvo (1995) gives
        // no inverse, and the map is the same function in both.
        if T::precision() < <T::Wide as Real>::precision() {
            let wide = self.wide.get_or_init(|| {
                let [a, b, c] = self.input.each_ref().map(widen3);
                let w = SphericalTriangle::<T::Wide>::new(a, b, c)
                    .expect("a triangle valid in T is valid in its wide type");
                Arc::new(WideTriangle::<T>(w))
            });
            return wide.inverse(p);
        }
        let q = unit_vector(p)?;
        self.inverse_robust(&q)
    }

    /// [`Warp::outside_by`].
    fn outside_by_impl(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let Some(q) = unit_vector(p) else {
            return T::max_value();
        };
        let radial = (p.norm() - &T::one()).abs();
        let [n_ab, n_bc, n_ca] = self.normals();
        let v_ab = -n_ab.dot(&q.sub(&self.a));
        let v_bc = -n_bc.dot(&q.sub(&self.b));
        let v_ca = -n_ca.dot(&q.sub(&self.c));
        radial.max(&v_ab).max(&v_bc).max(&v_ca).max(&T::zero())
    }
}

impl<T: Real> WarpFamily<T> for SphericalTriangle<T> {
    type At<S: Real> = SphericalTriangle<S>;

    /// The triangle with its vertex directions as given
    /// ([`SphericalTriangle::vertex_inputs`]) converted to `S`, same
    /// variant: from an `f32` triangle, `at::<Mpfr256>()` is the exact map
    /// of the `f32` inputs.
    fn at<S: Real>(&self) -> Result<SphericalTriangle<S>, WarpError> {
        let [a, b, c] = &self.input;
        SphericalTriangle::new_with(a.convert(), b.convert(), c.convert(), self.variant)
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
        self.observer.clone()
    }

    /// The direction ψ(u, v) and the point where it meets the plane of the
    /// triangle whose vertices the constructor was given (relative to the
    /// observer): with its unit normal `n̂` and distance `t₀ = |c̄·n̂|` (`c̄`
    /// the vertices' centroid), the ray `t·d` meets it at `t = t₀/|d·n̂|`,
    /// where the density in area is
    /// `pdf·|d·n̂|/t² = (pdf/t₀²)·|d·n̂|³` (constants computed by the
    /// constructor). [`SphericalTriangle::from_points`] refuses a triangle
    /// whose plane's distances or area densities `T` cannot hold; for vertex
    /// directions given to [`SphericalTriangle::new`] that are so long or
    /// short (or whose plane passes so close to the observer), the point is
    /// the direction itself: on the unit sphere, distance 1, area density
    /// equal to the density in solid angle.
    #[inline]
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T> {
        let [u, v] = uv;
        let d = self.map(&u, &v);
        let pdf = self.inv_omega.clone();
        match &self.plane {
            Some(plane) => plane.sample(d, pdf, &self.observer),
            None => LightPlane::on_unit_sphere(d, pdf, &self.observer),
        }
    }
}
