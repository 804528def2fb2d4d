//! The recipe specification of the spherical triangle (Arvo 2001, §1.3.5).

use super::SphericalTriangle;
use super::build::norm2;
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::shapes::wide::unit_vector;
use crate::vector::Vec3;
use crate::warp::{Warp, WarpFamily};

/// Embeds a vector of `T` constants into the evaluation scalar `S`.
fn embed3<T: Real, S: Embed<T>>(v: &Vec3<T>) -> Vec3<S> {
    Vec3::new(S::embed(&v.x), S::embed(&v.y), S::embed(&v.z))
}

/// Arvo's recipe for the spherical triangle (steps 1–3), the specification
/// the direct map [`SphericalTriangle`] is tested against at 256 bits.
///
/// 1. φ(s, t) = slerp(B, slerp(A, C, s), t) (eq. 1.29), both slerps by arc
///    length: `C_s = cos(s·b)·A + sin(s·b)·[C|A]` (b = ∠AC), then P at the
///    fraction t of the arc from B to C_s (length a_s).
/// 2. σ(s, t) = b · sin c sin α · a_s sin(t·a_s) / sin² a_s.
/// 3. Ω = 2·atan2(|det(A, B, C)|, 1 + A·B + B·C + C·A);
///    F(s) = area(A B C_s)/Ω with
///    `tan(area/2) = sin c sin α · sin(θ/2) / ((1 + cos c) cos(θ/2) + sin c cos α · sin(θ/2))`,
///    θ = s·b; F'(s) = b · sin c sin α / ((1 + cos a_s)·Ω);
///    G_s(t) = (1 − cos(t·a_s))/(1 − cos a_s) = sin²(t·a_s/2)/sin²(a_s/2).
/// 4. F⁻¹(u): θ/2 = atan2((1 + cos c)·sin h, sin c sin α·cos h − sin c cos α·sin h),
///    h = u·Ω/2 (eq. T of `docs/spherical-triangle.md`);
///    G_s⁻¹(v) = 2·asin(√v·sin(a_s/2))/a_s.
///
/// The closed forms are evaluated as written (one formula over the whole
/// square, no branch on u): composed with
/// [`RecipeWarp`](crate::recipe::RecipeWarp) and
/// [`ClosedForm`](crate::recipe::ClosedForm) inverters at 256 bits it is the
/// reference for the direct map.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::SphericalTriangle;
/// use areawarp::{Vec3, Warp};
///
/// let t = SphericalTriangle::<f64>::new(
///     Vec3::new(1.0, 0.1, 0.0),
///     Vec3::new(0.2, 1.0, 0.1),
///     Vec3::new(0.0, 0.3, 1.0),
/// )
/// .unwrap();
/// let spec = RecipeWarp::new(t.recipe(), ClosedForm, ClosedForm);
/// let d = spec.map(&0.3, &0.6).sub(&t.map(&0.3, &0.6)).norm();
/// assert!(d < 1e-14);
/// ```
#[derive(Clone, Debug)]
pub struct SphericalTriangleRecipe<T: Real> {
    tri: SphericalTriangle<T>,
    /// b = ∠AC.
    b_arc: T,
}

impl<T: Real> SphericalTriangleRecipe<T> {
    /// The recipe of `tri`.
    pub fn new(tri: SphericalTriangle<T>) -> Self {
        let b_arc = norm2(&tri.c.sub(&tri.a))
            .sqrt()
            .atan2(&norm2(&tri.c.add(&tri.a)).sqrt())
            * &T::from_i64(2);
        SphericalTriangleRecipe { tri, b_arc }
    }

    /// The triangle.
    pub fn triangle(&self) -> &SphericalTriangle<T> {
        &self.tri
    }

    /// `C_s = cos(s·b)·A + sin(s·b)·[C|A]`.
    fn sub_vertex(&self, s: &T) -> Vec3<T> {
        let (st, ct) = (s.clone() * &self.b_arc).sin_cos();
        self.tri.a.scale(&ct).add(&self.tri.c_perp.scale(&st))
    }

    /// `(sin(a_s/2), a_s)`: half the chord |C_s − B| and the arc length BC_s.
    fn arc(&self, s: &T) -> (T, T) {
        let cs = self.sub_vertex(s);
        let half_chord = norm2(&cs.sub(&self.tri.b)).sqrt() / &T::from_i64(2);
        let half_sum = norm2(&cs.add(&self.tri.b)).sqrt() / &T::from_i64(2);
        let a_s = half_chord.atan2(&half_sum) * &T::from_i64(2);
        (half_chord, a_s)
    }
}

impl<T: Real> Parametrization<T> for SphericalTriangleRecipe<T> {
    /// slerp(B, slerp(A, C, s), t), the tangent `[C_s|B]` computed as
    /// `(D + |D|²/2·B)/|…|` with `D = C_s − B` (no cancellation near B).
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let a: Vec3<S> = embed3(&self.tri.a);
        let b: Vec3<S> = embed3(&self.tri.b);
        let c_perp: Vec3<S> = embed3(&self.tri.c_perp);
        let two = S::from_i64(2);
        let (st, ct) = (s.clone() * &S::embed(&self.b_arc)).sin_cos();
        let cs = a.scale(&ct).add(&c_perp.scale(&st));
        let d = cs.sub(&b);
        let e = cs.add(&b);
        let d2 = d.dot(&d);
        let a_s = d2.sqrt().atan2(&e.dot(&e).sqrt()) * &two;
        let w = d.add(&b.scale(&(d2 / &two)));
        let w = w.scale(&(S::one() / &w.dot(&w).sqrt()));
        let (sp, cp) = (t.clone() * &a_s).sin_cos();
        b.scale(&cp).add(&w.scale(&sp))
    }

    /// `(s, t) = (∠AC_s / b, ∠BP / a_s)` with `C_s` where the great circle
    /// through B and `p` meets the arc AC; `None` if `p` is not finite or is
    /// ±B.
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        if !p.is_finite() {
            return None;
        }
        let q = unit_vector(p)?;
        let (sh, ch, _, w) = self.tri.chart_half_angle(&q)?;
        let two = T::from_i64(2);
        let s = sh.atan2(&ch) * &two / &self.b_arc;
        let cs = self.sub_vertex(&s);
        let a_s = norm2(&cs.sub(&self.tri.b))
            .sqrt()
            .atan2(&norm2(&cs.add(&self.tri.b)).sqrt())
            * &two;
        let theta_p = norm2(&w).sqrt().atan2(&norm2(&q.add(&self.tri.b)).sqrt()) * &two;
        Some((s, theta_p / &a_s))
    }
}

impl<T: Real> AreaDensity<T> for SphericalTriangleRecipe<T> {
    /// σ(s, t) = b · d · a_s sin(t·a_s) / sin² a_s, d = sin c sin α.
    fn sigma(&self, s: &T, t: &T) -> T {
        let (_, a_s) = self.arc(s);
        self.b_arc.clone() * &self.tri.d * &a_s * &(t.clone() * &a_s).sin() / &a_s.sin().square()
    }
}

impl<T: Real> MarginalConditional<T> for SphericalTriangleRecipe<T> {
    fn measure(&self) -> T {
        self.tri.omega.clone()
    }
    /// F(s) = 2·atan2(d·sin(θ/2), (1 + cos c)·cos(θ/2) + k·sin(θ/2)) / Ω, θ = s·b.
    fn marginal_cdf(&self, s: &T) -> T {
        let (sh, ch) = (s.clone() * &self.b_arc / &T::from_i64(2)).sin_cos();
        let num = self.tri.d.clone() * &sh;
        let den = self.tri.k1a.clone() * &ch + &(self.tri.ka.clone() * &sh);
        num.atan2(&den) / &self.tri.half_omega
    }
    /// F'(s) = b·d / ((1 + cos a_s)·Ω), 1 + cos a_s = |C_s + B|²/2.
    fn marginal_pdf(&self, s: &T) -> T {
        let cs = self.sub_vertex(s);
        let one_plus_cos = norm2(&cs.add(&self.tri.b)) / &T::from_i64(2);
        self.b_arc.clone() * &self.tri.d / &(one_plus_cos * &self.tri.omega)
    }
    /// G_s(t) = sin²(t·a_s/2) / sin²(a_s/2).
    fn conditional_cdf(&self, s: &T, t: &T) -> T {
        let (half_chord, a_s) = self.arc(s);
        ((t.clone() * &a_s / &T::from_i64(2)).sin() / &half_chord).square()
    }
    /// ∂G_s/∂t = a_s sin(t·a_s) / (2 sin²(a_s/2)).
    fn conditional_pdf(&self, s: &T, t: &T) -> T {
        let (half_chord, a_s) = self.arc(s);
        a_s.clone() * &(t.clone() * &a_s).sin() / &(half_chord.square() * &T::from_i64(2))
    }
    /// θ/2 = atan2((1 + cos c)·sin h, d·cos h − k·sin h), h = u·Ω/2; s = θ/b.
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        let u = u.clamp(&T::zero(), &T::one());
        let (sh, ch) = (u * &self.tri.half_omega).sin_cos();
        let num = self.tri.k1a.clone() * &sh;
        let den = self.tri.d.clone() * &ch - &(self.tri.ka.clone() * &sh);
        Some(num.atan2(&den) * &T::from_i64(2) / &self.b_arc)
    }
    /// t = 2·asin(√v·sin(a_s/2)) / a_s.
    fn conditional_inverse(&self, s: &T, v: &T) -> Option<T> {
        let v = v.clamp(&T::zero(), &T::one());
        let (half_chord, a_s) = self.arc(s);
        Some((v.sqrt() * &half_chord).asin() * &T::from_i64(2) / &a_s)
    }
}

impl<T: Real> Recipe<T> for SphericalTriangleRecipe<T> {
    type At<S: Real> = SphericalTriangleRecipe<S>;
    fn recast<S: Real>(&self) -> Result<SphericalTriangleRecipe<S>, WarpError> {
        self.tri.at::<S>().map(SphericalTriangleRecipe::new)
    }
    fn name(&self) -> String {
        "spherical-triangle".to_string()
    }
    /// As [`SphericalTriangle`]'s `outside_by`.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.tri.outside_by(p)
    }
}
