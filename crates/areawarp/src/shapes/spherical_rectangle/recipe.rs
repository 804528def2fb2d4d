//! The recipe specification of the spherical rectangle (steps 1–4 of
//! Arvo's recipe), written independently of the robust map: the corner
//! formula for the solid angle and the paper's closed-form inverses.

use super::geometry::Geometry;
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::recipe::{AreaDensity, MarginalConditional, Parametrization, Recipe};
use crate::shapes::turns::positive;
use crate::vector::Vec3;

/// The recipe specification of
/// [`SphericalRectangle`](super::SphericalRectangle) (Ureña, Fajardo, King
/// 2013), steps 1–4, in the local frame of the rectangle
/// (`[x₀, x₁] × [y₀, y₁]` at distance `h`, `Lx = x₁ − x₀`, `Ly = y₁ − y₀`):
///
/// 1. φ(s, t) = the unit direction from the observer to the point
///    `(x₀ + s Lx, y₀ + t Ly)` of the rectangle;
/// 2. σ(s, t) = ‖φ_s × φ_t‖ = `h Lx Ly / r³` (the solid angle subtended per
///    unit of `s t`; derived by dual numbers);
/// 3. m = Ω = `Σ ± G(xᵢ, yⱼ)` over the corners with
///    `G(x, y) = atan(x y / (h √(x² + y² + h²)))` (the two terms of each
///    column combined into one arctangent);
///    F(s) = `Ω([x₀, x_s] × [y₀, y₁]) / Ω` by the same corner formula;
///    G_s(t) = `(h(y_t) − h₀)/(h₁ − h₀)` with `h(y) = y/√(x_s² + h² + y²)`
///    (the integral of σ along the column, up to normalization);
/// 4. F⁻¹ in the closed form of the paper (Appendix A):
///    `Φ_u = Φ(x₀) + uΩ` with `Φ(x) = asin(a c₁) − asin(a c₀)`,
///    `a = x/√(x² + h²)`, `cⱼ = yⱼ/√(yⱼ² + h²)`; then
///    `a_u = sin Φ_u / √(c₀² + c₁² − 2c₀c₁ cos Φ_u)` and
///    `x_u = h a_u/√(1 − a_u²)`; G_s⁻¹: `y = d h_v/√(1 − h_v²)`,
///    `d = √(x_s² + h²)`.
///
/// These are the textbook forms, with their cancellations: the paper's F⁻¹
/// goes through `√(1 − a_u²)` with `a_u → 1` when the observer grazes the
/// plane, and loses up to twice the digits of `h/x` there (at 256 bits:
/// fine for ordinary rectangles, 10⁻⁵⁹ for the 10⁻⁹ grazing ones). The tests
/// therefore hold [`SphericalRectangle`](super::SphericalRectangle) to
/// [`RecipeWarp`](crate::recipe::RecipeWarp) with this recipe and a
/// [`Newton`](crate::recipe::Newton) inverter for F (accurate wherever F
/// is), and check the closed form against Newton separately.
///
/// # Density
/// Uniform in solid angle: weight 1, total measure Ω.
///
/// # Example
/// ```
/// use areawarp::recipe::{ClosedForm, RecipeWarp};
/// use areawarp::shapes::{SphericalRectangle, SphericalRectangleRecipe};
/// use areawarp::{Vec3, Warp};
///
/// let args = || (
///     Vec3::new(0.2, -0.4, -1.0),
///     Vec3::new(1.5, 0.0, 0.0),
///     Vec3::new(0.0, 0.8, 0.0),
///     Vec3::new(0.0, 0.0, 0.0),
/// );
/// let (s, ex, ey, o) = args();
/// let spec = RecipeWarp::new(SphericalRectangleRecipe::new(s, ex, ey, o).unwrap(), ClosedForm, ClosedForm);
/// let (s, ex, ey, o) = args();
/// let direct = SphericalRectangle::new(s, ex, ey, o).unwrap();
/// let d = spec.map(&0.3, &0.7).sub(&direct.map(&0.3, &0.7)).norm();
/// assert!(d < 1e-14, "{d}");
/// ```
#[derive(Clone, Debug)]
pub struct SphericalRectangleRecipe<T: Real> {
    pub(super) geometry: Geometry<T>,
    ey_input: Vec3<T>,
    bits: u32,
    x1: T,
    y1: T,
    omega: T,
}

impl<T: Real> SphericalRectangleRecipe<T> {
    /// The recipe of the rectangle with corner `s`, edges `ex`, `ey`, seen
    /// from `o`.
    ///
    /// # Errors
    /// As [`SphericalRectangle::new`](super::SphericalRectangle::new).
    pub fn new(s: Vec3<T>, ex: Vec3<T>, ey: Vec3<T>, o: Vec3<T>) -> Result<Self, WarpError> {
        Self::with_input_precision(s, ex, ey, o, T::precision())
    }

    /// [`SphericalRectangleRecipe::new`] for data given with `bits`
    /// significand bits (see
    /// [`SphericalRectangle::with_input_precision`](super::SphericalRectangle::with_input_precision)).
    ///
    /// # Errors
    /// As [`SphericalRectangle::new`](super::SphericalRectangle::new).
    pub fn with_input_precision(
        s: Vec3<T>,
        ex: Vec3<T>,
        ey: Vec3<T>,
        o: Vec3<T>,
        bits: u32,
    ) -> Result<Self, WarpError> {
        let bits = bits.min(T::precision());
        let geometry = Geometry::new(s, ex, ey.clone(), o, bits, false)?;
        let x1 = geometry.x0.clone() + &geometry.lx;
        let y1 = geometry.y0.clone() + &geometry.ly;
        let mut r = SphericalRectangleRecipe {
            geometry,
            ey_input: ey,
            bits,
            x1,
            y1,
            omega: T::zero(),
        };
        r.omega = r.strip(&r.geometry.x0, &r.x1);
        if !r.omega.is_finite_above(&T::zero()) {
            return Err(WarpError::Degenerate {
                what: "zero solid angle",
            });
        }
        Ok(r)
    }

    /// `Φ(x) = G(x, y₁) − G(x, y₀)`, the solid angle of `[0, x] × [y₀, y₁]`
    /// (signed), with `G(x, y) = atan(x y / (h R))`, `R = √(x² + y² + h²)`
    /// (the solid angle of `[0, x] × [0, y]`), as one arctangent:
    /// `tan(G₁ − G₀) = x h (y₁R₀ − y₀R₁) / (h² R₀R₁ + x² y₀y₁)`, where
    /// `y₁R₀ − y₀R₁ = (y₁ − y₀)(y₁ + y₀)(x² + h²)/(y₁R₀ + y₀R₁)` when `y₀`,
    /// `y₁` have the same sign (so that `Φ` keeps its relative accuracy when
    /// the observer grazes the plane).
    fn phi_of(&self, x: &T) -> T {
        let g = &self.geometry;
        let (y0, y1, h) = (&g.y0, &self.y1, &g.h);
        let d2 = x.square() + &h.square();
        let r0 = (d2.clone() + &y0.square()).sqrt();
        let r1 = (d2.clone() + &y1.square()).sqrt();
        let zero = T::zero();
        let diff = if (*y0 >= zero && *y1 >= zero) || (*y0 <= zero && *y1 <= zero) {
            g.ly.clone() * &(y1.clone() + y0) * &d2 / &(y1.clone() * &r0 + &(y0.clone() * &r1))
        } else {
            y1.clone() * &r0 - &(y0.clone() * &r1)
        };
        let num = x.clone() * h * &diff;
        let den = h.square() * &r0 * &r1 + &(x.square() * y0 * y1);
        num.atan2(&den)
    }

    /// The solid angle of `[xa, xb] × [y₀, y₁]`.
    fn strip(&self, xa: &T, xb: &T) -> T {
        self.phi_of(xb) - &self.phi_of(xa)
    }

    /// The column `x = x₀ + s Lx`, `d² = x² + h²` and `hⱼ = yⱼ/√(d² + yⱼ²)`.
    fn column(&self, s: &T) -> (T, T, T, T) {
        let g = &self.geometry;
        let x = g.x0.clone() + &(s.clone() * &g.lx);
        let d2 = x.square() + &g.h.square();
        let h0 = g.y0.clone() / &(d2.clone() + &g.y0.square()).sqrt();
        let h1 = self.y1.clone() / &(d2.clone() + &self.y1.square()).sqrt();
        (x, d2, h0, h1)
    }
}

impl<T: Real> Parametrization<T> for SphericalRectangleRecipe<T> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        let g = &self.geometry;
        let x = S::embed(&g.x0) + &(s.clone() * &S::embed(&g.lx));
        let y = S::embed(&g.y0) + &(t.clone() * &S::embed(&g.ly));
        let h = S::embed(&g.h);
        let comp = |a: &T, b: &T, c: &T| -> S {
            x.clone() * &S::embed(a) + &(y.clone() * &S::embed(b)) - &(h.clone() * &S::embed(c))
        };
        let v = Vec3::new(
            comp(&g.xhat.x, &g.yhat.x, &g.zhat.x),
            comp(&g.xhat.y, &g.yhat.y, &g.zhat.y),
            comp(&g.xhat.z, &g.yhat.z, &g.zhat.z),
        );
        let n = v.norm_squared().sqrt();
        v.scale(&(S::one() / &n))
    }

    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        let g = &self.geometry;
        let (a, b, c) = g.local_direction(p)?;
        if !positive(&c) {
            return None;
        }
        let k = g.h.clone() / &c;
        let x = a * &k;
        let y = b * &k;
        Some(((x - &g.x0) / &g.lx, (y - &g.y0) / &g.ly))
    }
}

impl<T: Real> AreaDensity<T> for SphericalRectangleRecipe<T> {}

impl<T: Real> MarginalConditional<T> for SphericalRectangleRecipe<T> {
    fn measure(&self) -> T {
        self.omega.clone()
    }

    fn marginal_cdf(&self, s: &T) -> T {
        let (x, ..) = self.column(s);
        self.strip(&self.geometry.x0, &x) / &self.omega
    }

    fn marginal_pdf(&self, s: &T) -> T {
        // ∫ h dy / (d² + y²)^{3/2} = h (h₁ − h₀) / d².
        let g = &self.geometry;
        let (_, d2, h0, h1) = self.column(s);
        g.lx.clone() * &g.h * &(h1 - &h0) / &d2 / &self.omega
    }

    fn conditional_cdf(&self, s: &T, t: &T) -> T {
        let g = &self.geometry;
        let (_, d2, h0, h1) = self.column(s);
        let y = g.y0.clone() + &(t.clone() * &g.ly);
        let hy = y.clone() / &(d2 + &y.square()).sqrt();
        (hy - &h0) / &(h1 - &h0)
    }

    fn conditional_pdf(&self, s: &T, t: &T) -> T {
        let g = &self.geometry;
        let (_, d2, h0, h1) = self.column(s);
        let y = g.y0.clone() + &(t.clone() * &g.ly);
        let r2 = d2.clone() + &y.square();
        let r = r2.sqrt();
        g.ly.clone() * &d2 / &(r2 * &r) / &(h1 - &h0)
    }

    fn marginal_inverse(&self, u: &T) -> Option<T> {
        let g = &self.geometry;
        let h = &g.h;
        let c0 = g.y0.clone() / &g.y0.hypot(h);
        let c1 = self.y1.clone() / &self.y1.hypot(h);
        let phi_u = self.phi_of(&g.x0) + &(u.clone() * &self.omega);
        let sin_phi = phi_u.sin();
        // c₀² + c₁² − 2c₀c₁ cos Φ (Appendix A), as (c₁ − c₀)² + 4c₀c₁ sin²(Φ/2).
        let half = (phi_u * &T::from_ratio(1, 2)).sin();
        let den =
            ((c1.clone() - &c0).square() + &(T::from_i64(4) * &c0 * &c1 * &half.square())).sqrt();
        let a = sin_phi / &den;
        let x = h.clone() * &a / &(T::one() - &a.square()).sqrt();
        Some((x - &g.x0) / &g.lx)
    }

    fn conditional_inverse(&self, s: &T, v: &T) -> Option<T> {
        let g = &self.geometry;
        let (_, d2, h0, h1) = self.column(s);
        let hv = h0.clone() + &(v.clone() * &(h1 - &h0));
        let y = d2.sqrt() * &hv / &(T::one() - &hv.square()).sqrt();
        Some((y - &g.y0) / &g.ly)
    }
}

impl<T: Real> Recipe<T> for SphericalRectangleRecipe<T> {
    type At<S: Real> = SphericalRectangleRecipe<S>;

    fn recast<S: Real>(&self) -> Result<SphericalRectangleRecipe<S>, WarpError> {
        let g = &self.geometry;
        SphericalRectangleRecipe::with_input_precision(
            g.s.convert(),
            g.ex.convert(),
            self.ey_input.convert(),
            g.o.convert(),
            self.bits,
        )
    }

    fn name(&self) -> String {
        "spherical-rectangle".to_string()
    }
}
