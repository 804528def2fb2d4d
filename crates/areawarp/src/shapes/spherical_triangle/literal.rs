//! The [`Literal`](super::SphericalTriangleVariant::Literal) evaluation:
//! Arvo's 1995 `SampleTriangle`, transcribed as published.
//!
//! The paper does not say how the internal angles are computed; we use the
//! textbook dihedral form α = acos(n̂_AB · n̂_AC) with n̂_XY = (X × Y)/|X × Y|,
//! the `acos` argument clamped to [−1, 1] (the only clamp: the published
//! pseudo-code has none, so `√(1 − q²)` and `√(1 − z²)` are NaN when rounding
//! pushes |q| or |z| above 1). `[x|y]` is `normalize(x − (x·y)y)` as in eq. 6.

use crate::real::Real;
use crate::vector::Vec3;

/// `[x|y] = normalize(x − (x·y)y)`, computed as written (NaN for x ∥ y).
fn perp<T: Real>(x: &Vec3<T>, y: &Vec3<T>) -> Vec3<T> {
    let w = x.sub(&y.scale(&x.dot(y)));
    let n = w.dot(&w).sqrt();
    Vec3::new(w.x / &n, w.y / &n, w.z / &n)
}

/// `(x × y)/|x × y|`, as written.
fn plane_normal<T: Real>(x: &Vec3<T>, y: &Vec3<T>) -> Vec3<T> {
    let n = x.cross(y);
    let len = n.dot(&n).sqrt();
    Vec3::new(n.x / &len, n.y / &len, n.z / &len)
}

/// The internal angle at `v` of the spherical triangle `v x y`: the dihedral
/// angle between the planes (v, x) and (v, y).
fn dihedral<T: Real>(v: &Vec3<T>, x: &Vec3<T>, y: &Vec3<T>) -> T {
    let cos = plane_normal(v, x).dot(&plane_normal(v, y));
    cos.clamp(&-T::one(), &T::one()).acos()
}

/// Girard's formula α + β + γ − π with dihedral angles.
pub(super) fn girard<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    dihedral(a, b, c) + &dihedral(b, c, a) + &dihedral(c, a, b) - &T::pi()
}

/// The per-triangle constants of the published algorithm.
#[derive(Clone, Debug)]
pub(super) struct Literal<T> {
    /// α, the internal angle at A.
    alpha: T,
    cos_alpha: T,
    sin_alpha: T,
    /// cos c = A·B.
    cos_c: T,
    /// [C|A].
    c_perp: Vec3<T>,
    /// Girard's area 𝒜 = α + β + γ − π.
    pub(super) area: T,
}

impl<T: Real> Literal<T> {
    /// "cos α, sin α, cos c and [C|A] need only be computed once per triangle."
    pub(super) fn new(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> Self {
        let alpha = dihedral(a, b, c);
        let (sin_alpha, cos_alpha) = alpha.sin_cos();
        Literal {
            cos_alpha,
            sin_alpha,
            cos_c: a.dot(b),
            c_perp: perp(c, a),
            area: girard(a, b, c),
            alpha,
        }
    }

    /// `SampleTriangle(ξ₁, ξ₂)` (Arvo 1995), line by line.
    pub(super) fn map(&self, a: &Vec3<T>, b: &Vec3<T>, xi1: &T, xi2: &T) -> Vec3<T> {
        let one = T::one();
        // Use one random variable to select the new area.
        let area_hat = xi1.clone() * &self.area;
        // Save the sine and cosine of the angle φ.
        let phi = area_hat - &self.alpha;
        let s = phi.sin();
        let t = phi.cos();
        // Compute the pair (u, v) that determines β̂.
        let u = t.clone() - &self.cos_alpha;
        let v = s.clone() + &(self.sin_alpha.clone() * &self.cos_c);
        // Let q be the cosine of the new edge length b̂.
        let q = ((v.clone() * &t - &(u.clone() * &s)) * &self.cos_alpha - &v)
            / &((v * &s + &(u * &t)) * &self.sin_alpha);
        // Compute the third vertex of the sub-triangle.
        let c_hat = a
            .scale(&q)
            .add(&self.c_perp.scale(&(one.clone() - &q.square()).sqrt()));
        // Use the other random variable to select cos θ.
        let z = one.clone() - &(xi2.clone() * &(one.clone() - &c_hat.dot(b)));
        // Construct the corresponding point on the sphere.
        b.scale(&z)
            .add(&perp(&c_hat, b).scale(&(one - &z.square()).sqrt()))
    }
}
