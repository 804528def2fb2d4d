//! Uniform sampling of the solid angle of a planar rectangle seen from a
//! point: Ureña, Fajardo and King (2013), *An area-preserving parametrization
//! for spherical rectangles*. Derivation, numerical reformulations and
//! measured accuracy: `docs/spherical-rectangle.md`.
//!
//! Two evaluations of the same map share one type, selected by
//! [`SphericalRectangleVariant`]: [`Literal`](SphericalRectangleVariant::Literal),
//! the published algorithm transcribed as printed, and the default
//! [`Robust`](SphericalRectangleVariant::Robust), reformulated so that every
//! step is as accurate as the data allow.

mod geometry;
mod ladder;
mod literal;
mod recipe;
mod robust;
#[cfg(test)]
mod tests;

pub use ladder::{hard_rectangles, ordinary_rectangles};
pub use recipe::SphericalRectangleRecipe;

use super::turns::clamp_unit;
use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::turns::positive;
use crate::shapes::wide::widen3;
use crate::vector::Vec3;
use crate::warp::{InverseError, LightSample, LightWarp, Warp, WarpFamily, on_shape_tolerance};
use geometry::{Geometry, area_density_exact, area_density_in_range};
use literal::Literal;
use robust::{Cone, Omega, Robust};
use std::sync::OnceLock;

/// Which evaluation of the Ureña–Fajardo–King map a [`SphericalRectangle`]
/// uses. Both compute the same map M(u, v); they differ only in arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SphericalRectangleVariant {
    /// The reference algorithm of the paper (Appendix B) as published: Ω as
    /// Girard's sum of the four internal angles (`acos` of edge-normal dot
    /// products) minus 2π, `c_u = ±1/√(f² + b₀²)` from the angle
    /// `uS + k`, `x_u = −c_u z₀/√(1 − c_u²)`, `y_v = h_v d/√(1 − h_v²)`, with
    /// the paper's clamps and its cut-off `h_v² ≥ 1 − ε ⇒ y_v = y₁`
    /// (`ε = 10⁻⁶`). The baseline to compare against: it puts every sample
    /// on one edge when the observer grazes the plane (Σγ − 2π cancels to 0)
    /// and loses digits near the edges of the square and for small or
    /// distant rectangles.
    Literal,
    /// The same map evaluated without cancellation (the default): Ω and the
    /// sub-rectangle solid angles from `ω(x) = x(ℓ₀ + ℓ₁)/(r₀ℓ₁ + r₁ℓ₀)` and
    /// half-angle sines, `x_u` in closed form from sines of half angles
    /// anchored at the nearer end of `[x₀, x₁]`, `y_v` from differences of
    /// `h` written as products, `1 − h_v²` as a sum of positive terms.
    #[default]
    Robust,
}

impl SphericalRectangleVariant {
    /// `"literal"` or `"robust"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            SphericalRectangleVariant::Literal => "literal",
            SphericalRectangleVariant::Robust => "robust",
        }
    }
}

impl core::fmt::Display for SphericalRectangleVariant {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::str::FromStr for SphericalRectangleVariant {
    type Err = WarpError;
    /// Parses `literal` or `robust` (ASCII case-insensitive).
    fn from_str(s: &str) -> Result<Self, WarpError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "literal" => Ok(SphericalRectangleVariant::Literal),
            "robust" => Ok(SphericalRectangleVariant::Robust),
            _ => Err(WarpError::InvalidParameter {
                name: "variant",
                expected: "literal or robust",
            }),
        }
    }
}

/// `x` clamped to `[0, 1]`, NaN kept.
fn clamp01<T: Real>(x: &T) -> T {
    if x.is_nan() {
        x.clone()
    } else {
        x.clamp(&T::zero(), &T::one())
    }
}

/// Uniform directions (in solid angle) towards a planar rectangle, seen from
/// an observer: the map M(u, v) of Ureña, Fajardo and King (2013).
///
/// The rectangle has the corner `s` and the perpendicular edges `e_x`,
/// `e_y`; the observer is `o`. In the frame `x̂ = e_x/|e_x|`,
/// `ŷ = e_y/|e_y|` centred at `o`, the rectangle is `[x₀, x₁] × [y₀, y₁]` in
/// the plane at distance `h` from `o`. The map picks
///
/// 1. the column `x_u`: the sub-rectangle `[x₀, x_u] × [y₀, y₁]` subtends
///    `u·Ω`;
/// 2. the row `y_v` in that column: with `hⱼ = yⱼ/√(x_u² + h² + yⱼ²)` (the
///    cosine of the angle between ŷ and the direction to `(x_u, yⱼ)`), the
///    value `h_v = h₀ + v(h₁ − h₀)` belongs to `y_v`.
///
/// The point is `s + ξ e_x + η e_y` with `ξ = (x_u − x₀)/|e_x|`,
/// `η = (y_v − y₀)/|e_y|`, and the direction is the unit vector from `o`
/// to it. `u = 0` and `u = 1` give exactly the edges `ξ = 0` and `ξ = 1`,
/// likewise `v`.
///
/// # Variants
/// [`SphericalRectangleVariant::Robust`] (the default) evaluates the map
/// accurately for every rectangle and every `(u, v)`;
/// [`SphericalRectangleVariant::Literal`] runs the published algorithm, for
/// comparison. Both share the validation, the density `1/Ω` (the accurate
/// Ω) and the inverse.
///
/// # Input
/// The edges must be perpendicular to within 64 units of roundoff of the
/// precision the data are given in (`|cos ∠(e_x, e_y)| ≤ 64·2^-p`); `e_y`
/// is then replaced by its component perpendicular to `e_x`, so that the
/// shape is an exact rectangle at every precision. Rejected: non-finite
/// numbers, zero-length edges, non-perpendicular edges, an observer exactly
/// in the rectangle's plane, a rectangle of zero (underflowing) solid angle.
///
/// # Density
/// Uniform in solid angle: `pdf(ω) = 1/Ω` for directions on the spherical
/// rectangle (within `2^-p/2`), 0 elsewhere; `measure() = Ω`. In area
/// measure on the rectangle: [`SphericalRectangle::pdf_area`].
///
/// # Example
/// ```
/// use areawarp::shapes::SphericalRectangle;
/// use areawarp::{Vec3, Warp};
///
/// // A unit square one unit below the observer.
/// let r = SphericalRectangle::<f64>::new(
///     Vec3::new(-0.5, -0.5, 0.0),
///     Vec3::new(1.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
///     Vec3::new(0.0, 0.0, 1.0),
/// )
/// .unwrap();
/// // Ω = 4·asin(1/5) for this square.
/// assert!((r.solid_angle() - 4.0 * 0.2f64.asin()).abs() < 1e-15);
/// let (p, d) = r.sample_point(&0.5, &0.5);
/// assert!(p.norm() < 1e-15 && (d.z + 1.0).abs() < 1e-15); // the centre
/// let [u, v] = r.inverse(&d).unwrap();
/// assert!((u - 0.5).abs() < 1e-15 && (v - 0.5).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct SphericalRectangle<T: Real> {
    /// `e_y` as given (the geometry holds it squared up).
    ey_input: Vec3<T>,
    geometry: Geometry<T>,
    robust: Robust<T>,
    /// The cone's faces for `outside_by`, computed on first use.
    cone: OnceLock<Cone<T>>,
    literal: Option<Literal<T>>,
    variant: SphericalRectangleVariant,
    bits: u32,
    /// 1/Ω (Ω itself is `robust`'s).
    inv_omega: T,
}

impl<T: Real> SphericalRectangle<T> {
    /// The rectangle with corner `s` and edges `ex`, `ey` seen from `o`,
    /// [`Robust`](SphericalRectangleVariant::Robust) evaluation.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for non-finite input,
    /// [`WarpError::Degenerate`] for a zero-length edge, an observer in the
    /// plane of the rectangle or a zero solid angle,
    /// [`WarpError::InvalidParameter`] for edges that are not perpendicular
    /// (`|cos ∠(ex, ey)| > 64·2^-p`, `p` the precision of `T`),
    /// [`WarpError::Unrepresentable`] for a rectangle `T` cannot serve: an
    /// observer so close to the plane that `h²` underflows, a solid angle
    /// or its reciprocal out of range, or a density in area at the nearest
    /// or farthest point outside `[16·tiny, max/16]` (`tiny ≈` the smallest
    /// normal number; this includes every rectangle with a subnormal edge).
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::SphericalRectangle;
    /// use areawarp::{Vec3, WarpError};
    /// let in_plane = SphericalRectangle::<f64>::new(
    ///     Vec3::new(0.0, 0.0, 0.0),
    ///     Vec3::new(1.0, 0.0, 0.0),
    ///     Vec3::new(0.0, 1.0, 0.0),
    ///     Vec3::new(3.0, 2.0, 0.0),
    /// );
    /// assert!(matches!(in_plane, Err(WarpError::Degenerate { .. })));
    /// ```
    pub fn new(s: Vec3<T>, ex: Vec3<T>, ey: Vec3<T>, o: Vec3<T>) -> Result<Self, WarpError> {
        Self::new_with(s, ex, ey, o, SphericalRectangleVariant::default())
    }

    /// [`SphericalRectangle::new`] with the evaluation `variant`.
    ///
    /// # Errors
    /// As [`SphericalRectangle::new`].
    pub fn new_with(
        s: Vec3<T>,
        ex: Vec3<T>,
        ey: Vec3<T>,
        o: Vec3<T>,
        variant: SphericalRectangleVariant,
    ) -> Result<Self, WarpError> {
        Self::with_input_precision(s, ex, ey, o, variant, T::precision())
    }

    /// [`SphericalRectangle::new_with`] for data that were rounded to `bits`
    /// significand bits before being converted to `T` (e.g. `f32` or `f64`
    /// data evaluated at 256 bits): the perpendicularity tolerance is that of
    /// the coarser of `bits` and `T`'s precision. [`WarpFamily::at`] uses
    /// it to rebuild a shape at higher precision.
    ///
    /// # Errors
    /// As [`SphericalRectangle::new`].
    pub fn with_input_precision(
        s: Vec3<T>,
        ex: Vec3<T>,
        ey: Vec3<T>,
        o: Vec3<T>,
        variant: SphericalRectangleVariant,
        bits: u32,
    ) -> Result<Self, WarpError> {
        let bits = bits.min(T::precision());
        let geometry = wide_geometry(&s, &ex, &ey, &o, bits)?;
        let parts = Omega::new(&geometry);
        let inv_omega = check_range(&geometry, &parts.omega)?;
        let robust = Robust::from_omega(&geometry, parts, None);
        let out = SphericalRectangle {
            ey_input: ey,
            inv_omega,
            geometry,
            robust,
            cone: OnceLock::new(),
            literal: None,
            variant: SphericalRectangleVariant::Robust,
            bits,
        };
        Ok(out.with_variant(variant))
    }

    /// The same rectangle evaluated with `variant`.
    pub fn with_variant(mut self, variant: SphericalRectangleVariant) -> Self {
        self.variant = variant;
        self.literal = match variant {
            SphericalRectangleVariant::Literal => Some(Literal::new(
                &self.geometry.s,
                &self.geometry.ex,
                &self.ey_input,
                &self.geometry.o,
            )),
            SphericalRectangleVariant::Robust => None,
        };
        self
    }

    /// The evaluation variant.
    pub fn variant(&self) -> SphericalRectangleVariant {
        self.variant
    }

    /// The corner `s`.
    pub fn corner(&self) -> &Vec3<T> {
        &self.geometry.s
    }

    /// The edge `e_x`.
    pub fn edge_x(&self) -> &Vec3<T> {
        &self.geometry.ex
    }

    /// The edge `e_y`, made exactly perpendicular to `e_x` (its component
    /// perpendicular to `e_x`; equal to the input for perpendicular edges).
    pub fn edge_y(&self) -> &Vec3<T> {
        &self.geometry.ey
    }

    /// The observer `o`.
    pub fn observer(&self) -> &Vec3<T> {
        &self.geometry.o
    }

    /// The parameters as given: `[s, e_x, e_y, o]` (`e_y` not squared up).
    pub fn inputs(&self) -> [&Vec3<T>; 4] {
        [
            &self.geometry.s,
            &self.geometry.ex,
            &self.ey_input,
            &self.geometry.o,
        ]
    }

    /// The rectangle in its local frame (observer at the origin, edges
    /// along the axes, plane `z = −h`): `[x₀, y₀, h, ℓx, ℓy]` scaled by
    /// `2^(−e)` so that the largest is in `[1, 2)`, and `e`. The corner is
    /// `(x₀, y₀, −h)`, the edges `(ℓx, 0, 0)` and `(0, ℓy, 0)`: the numbers
    /// the robust map computes from, as rounded to `T`.
    pub fn local_coordinates(&self) -> ([T; 5], i32) {
        let g = &self.geometry;
        (
            [
                g.x0.clone(),
                g.y0.clone(),
                g.h.clone(),
                g.lx.clone(),
                g.ly.clone(),
            ],
            g.exp,
        )
    }

    /// The unit normal of the rectangle's plane on the observer's side.
    pub fn normal(&self) -> &Vec3<T> {
        &self.geometry.zhat
    }

    /// The distance from the observer to the rectangle's plane.
    pub fn distance_to_plane(&self) -> &T {
        &self.geometry.h_world
    }

    /// The solid angle Ω (steradians), accurate to a few units of roundoff
    /// for every accepted rectangle (see the type's docs); the density of
    /// both variants is `1/Ω`.
    pub fn solid_angle(&self) -> T {
        self.robust.omega().clone()
    }

    /// The solid angle `S = γ₀ + γ₁ + γ₂ + γ₃ − 2π` of the paper's Listing 2
    /// (Girard's formula with `acos` of edge-normal dot products), the value
    /// the published algorithm samples with. Loses all accuracy for small,
    /// distant or grazing rectangles; for comparison only.
    pub fn girard_solid_angle(&self) -> T {
        match &self.literal {
            Some(l) => l.solid_angle(),
            None => Literal::new(
                &self.geometry.s,
                &self.geometry.ex,
                &self.ey_input,
                &self.geometry.o,
            )
            .solid_angle(),
        }
    }

    /// `(point, direction)` = M(u, v) by the rectangle's variant: the point
    /// on the rectangle and the unit direction from the observer to it.
    /// `u`, `v` are clamped to `[0, 1]` (NaN stays NaN).
    pub fn sample_point(&self, u: &T, v: &T) -> (Vec3<T>, Vec3<T>) {
        let s = self.sample_full(u, v);
        (s.point, s.direction)
    }

    /// M(u, v) with the point, its distance and both densities
    /// ([`LightWarp::sample_light`] by reference).
    /// Inlined into the caller's loop (the robust map's constants stay in
    /// registers); the literal variant's sample is a call.
    #[inline]
    fn sample_full(&self, u: &T, v: &T) -> LightSample<T> {
        let (u, v) = (clamp_unit(u), clamp_unit(v));
        match &self.literal {
            None => self.sample_robust(&u, &v),
            Some(lit) => self.sample_literal(lit, &u, &v),
        }
    }

    /// [`SphericalRectangle::sample_full`] of the literal variant (`u`, `v`
    /// clamped).
    #[inline(never)]
    fn sample_literal(&self, lit: &Literal<T>, u: &T, v: &T) -> LightSample<T> {
        let point = lit.point(u, v);
        let offset = point.sub(lit.observer());
        let r2 = offset.norm_squared();
        let r = r2.sqrt();
        let direction = if r.is_finite_above(&T::zero()) {
            offset.scale(&(T::one() / &r))
        } else {
            self.geometry.zhat.neg()
        };
        let pdf_area = self.geometry.h_world.clone() * &self.inv_omega / &(r2 * &r);
        LightSample {
            point,
            direction,
            distance: r,
            pdf: self.inv_omega.clone(),
            pdf_area,
        }
    }

    fn sample_robust(&self, u: &T, v: &T) -> LightSample<T> {
        sample_with(&self.geometry, &self.robust, &self.inv_omega, u, v)
    }

    /// One sample of the rectangle with corner `s` and edges `ex`, `ey`
    /// seen from `o` without building a [`SphericalRectangle`]: M(u, v) with
    /// both densities by the robust map, bit for bit what
    /// `SphericalRectangle::new(s, ex, ey, o)?.sample_light([u, v])` returns, at the
    /// cost of the validation, Ω and the one anchor (`x₀` or `x₁`) the sample
    /// needs (not the cone's faces of `outside_by`). What a renderer calls
    /// per shading point.
    ///
    /// # Errors
    /// As [`SphericalRectangle::new`].
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::SphericalRectangle;
    /// use areawarp::{LightWarp, Vec3};
    /// let (s, ex, ey, o) = (
    ///     Vec3::new(-0.5f32, -0.5, 0.0),
    ///     Vec3::new(1.0, 0.0, 0.0),
    ///     Vec3::new(0.0, 1.0, 0.0),
    ///     Vec3::new(0.0, 0.0, 1.0),
    /// );
    /// let once = SphericalRectangle::sample_once(&s, &ex, &ey, &o, &0.3, &0.7)?;
    /// let r = SphericalRectangle::new(s, ex, ey, o)?;
    /// assert_eq!(once, r.sample_light([0.3, 0.7]));
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn sample_once(
        s: &Vec3<T>,
        ex: &Vec3<T>,
        ey: &Vec3<T>,
        o: &Vec3<T>,
        u: &T,
        v: &T,
    ) -> Result<LightSample<T>, WarpError> {
        let geometry = wide_geometry(s, ex, ey, o, T::precision())?;
        let which = usize::from(!(clamp_unit(u) <= T::from_ratio(1, 2)));
        let parts = Omega::new(&geometry);
        let inv_omega = check_range(&geometry, &parts.omega)?;
        let robust = Robust::from_omega(&geometry, parts, Some(which));
        Ok(sample_with(&geometry, &robust, &inv_omega, u, v))
    }

    /// The solid angle Ω of the rectangle with corner `s` and edges `ex`,
    /// `ey` seen from `o`, without building a [`SphericalRectangle`]: equal
    /// to its [`solid_angle`](SphericalRectangle::solid_angle) (the density
    /// of its samples is `1/Ω`).
    ///
    /// # Errors
    /// As [`SphericalRectangle::new`].
    pub fn solid_angle_of(
        s: &Vec3<T>,
        ex: &Vec3<T>,
        ey: &Vec3<T>,
        o: &Vec3<T>,
    ) -> Result<T, WarpError> {
        let geometry = wide_geometry(s, ex, ey, o, T::precision())?;
        // Ω and the range check alone: not the map's anchors.
        let omega = Omega::new(&geometry).omega;
        check_range(&geometry, &omega)?;
        Ok(omega)
    }

    /// The density in area on the rectangle at the point `p`:
    /// `cos θ_p / (Ω r²) = h / (Ω r³)` with `r = |p − o|` and `h` the
    /// distance from the observer to the plane; 0 if `p` is not on the
    /// rectangle (as in [`SphericalRectangle::inverse_point`]).
    pub fn pdf_area(&self, p: &Vec3<T>) -> T {
        if !self.on_rectangle(p) {
            return T::zero();
        }
        let r = p.sub(&self.geometry.o).norm();
        self.geometry.h_world.clone() * &self.inv_omega / &(r.square() * &r)
    }

    /// The distance from `p` to the rectangle (world units): the distance
    /// to the plane plus how far the projection lies outside each edge.
    /// Non-finite `p`: [`Real::max_value`].
    pub fn point_outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        let g = &self.geometry;
        let q = p.sub(&g.s);
        let zero = T::zero();
        let a = q.dot(&g.xhat);
        let b = q.dot(&g.yhat);
        let lx = g.ex.norm();
        let ly = g.ey.norm();
        let out_x = (-a.clone()).max(&(a - &lx)).max(&zero);
        let out_y = (-b.clone()).max(&(b - &ly)).max(&zero);
        q.dot(&g.zhat).abs() + &out_x + &out_y
    }

    /// `true` if `p` lies within `2^(−p/2) (|s| + |e_x| + |e_y|)` of the
    /// rectangle ([`SphericalRectangle::point_outside_by`]): the scale of the
    /// rounding errors of a computed point `s + ξ e_x + η e_y`.
    fn on_rectangle(&self, p: &Vec3<T>) -> bool {
        if !p.is_finite() {
            return false;
        }
        let g = &self.geometry;
        let scale = g.s.norm() + &g.ex.norm() + &g.ey.norm();
        self.point_outside_by(p) <= on_shape_tolerance::<T>() * &scale
    }

    /// `(u, v)` of a point `p` on the rectangle: `u = Ω([x₀, x_p])/Ω`,
    /// `v = (h_p − h₀)/(h₁ − h₀)`, both computed without cancellation (the
    /// same for both variants). `None` if `p` is not finite or farther than
    /// `2^(−p/2) (|s| + |e_x| + |e_y|)` from the rectangle
    /// ([`SphericalRectangle::point_outside_by`]).
    ///
    /// # Errors
    /// [`InverseError::NonFinite`] or [`InverseError::OffShape`] (with the
    /// distance to the rectangle) for a point that is not on it.
    pub fn inverse_point(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        if !p.is_finite() {
            return Err(InverseError::NonFinite);
        }
        if !self.on_rectangle(p) {
            return Err(InverseError::OffShape {
                distance: self.point_outside_by(p).to_f64(),
            });
        }
        let (u, v) = self.point_uv(p);
        Ok([u, v])
    }

    /// `(u, v)` of the point of the rectangle nearest to `p` (no check).
    ///
    /// The column and row `(x, y)` of `p` are measured from the observer
    /// (not from the corner `s`, which may lie far away on an elongated
    /// rectangle: their rounding errors are then relative to the distance
    /// the direction's accuracy depends on); the offsets from the edges,
    /// `x − x₀ = ξ|e_x|` and `x₁ − x = (1 − ξ)|e_x|` (likewise in y), from
    /// `ξ = (p − s)·e_x/|e_x|²`, accurate relative to the rectangle's size
    /// also when the observer is far away.
    fn point_uv(&self, p: &Vec3<T>) -> (T, T) {
        let g = &self.geometry;
        let one = T::one();
        let zero = T::zero();
        let q = p.sub(&g.s);
        let xi = (q.dot(&g.ex) / &g.ex.norm_squared()).clamp(&zero, &one);
        let eta = (q.dot(&g.ey) / &g.ey.norm_squared()).clamp(&zero, &one);
        let (x, y) = g.local_point(p);
        let [x, _, _, y, _, _] = self.robust.offsets(x, y);
        let (ax, bx) = (xi.clone() * &g.lx, (one.clone() - &xi) * &g.lx);
        let (ay, by) = (eta.clone() * &g.ly, (one - &eta) * &g.ly);
        let (u, v) = self.robust.uv_of(&x, &ax, &bx, &y, &ay, &by);
        (clamp01(&u), clamp01(&v))
    }

    /// `(u, v)` of the direction `d` without the on-shape test of
    /// [`Warp::inverse`] (the caller knows `d` is on the rectangle, e.g. to
    /// its own tolerance).
    pub(crate) fn inverse_unchecked(&self, d: &Vec3<T>) -> Option<(T, T)> {
        self.direction_uv(d)
    }

    /// `(u, v)` of the direction `d` (no check beyond finiteness).
    fn direction_uv(&self, d: &Vec3<T>) -> Option<(T, T)> {
        let (a, b, c) = self.geometry.local_direction(d)?;
        // A direction accepted within the tolerance may still point (just)
        // away from the plane: it is then at the horizon, on an edge.
        let c = c.max(&T::unit_roundoff().square());
        let [x, ax, bx, y, ay, by] = self.robust.hit(&a, &b, &c);
        let (u, v) = self.robust.uv_of(&x, &ax, &bx, &y, &ay, &by);
        Some((clamp01(&u), clamp01(&v)))
    }

    /// The cone's faces (computed on first use).
    fn cone(&self) -> &Cone<T> {
        self.cone.get_or_init(|| Cone::new(&self.robust))
    }

    /// `true` if the direction `d` lies on the spherical rectangle within
    /// `2^(−p/2)` ([`Warp::outside_by`]).
    pub fn contains(&self, d: &Vec3<T>) -> bool {
        self.outside_by(d) <= on_shape_tolerance::<T>()
    }
}

/// Validates the rectangle and builds its frame in [`Real::Wide`] (every
/// decision, the frame and the local coordinates in the wide type), rounded
/// to `T`.
#[inline(always)]
fn wide_geometry<T: Real>(
    s: &Vec3<T>,
    ex: &Vec3<T>,
    ey: &Vec3<T>,
    o: &Vec3<T>,
    bits: u32,
) -> Result<Geometry<T>, WarpError> {
    // Data of a narrower type than the wide one (`f32` in `f64`).
    let narrow_data = T::precision() < <T::Wide as Real>::precision();
    let wide = Geometry::new(
        widen3(s),
        widen3(ex),
        widen3(ey),
        widen3(o),
        bits,
        narrow_data,
    )?;
    Ok(wide.narrow::<T>())
}

/// The reasons `T` cannot serve a valid rectangle.
mod range {
    use crate::error::WarpError;
    pub const GRAZING: WarpError = WarpError::Unrepresentable {
        what: "observer so close to the rectangle's plane that h² underflows the scalar type",
    };
    pub const OMEGA: WarpError = WarpError::Unrepresentable {
        what: "solid angle (or its reciprocal) outside the scalar type's range",
    };
    pub const AREA_PDF: WarpError = WarpError::Unrepresentable {
        what: "density in area measure outside the scalar type's range",
    };
}

/// `1/Ω` once `T` is known to serve the rectangle (Ω given): `h²` (local, the
/// largest local length in `[1, 2)`) and Ω above `tiny/u` (`tiny ≈` the
/// smallest normal number, `4/max`), so that the map's products of small
/// terms stay normal; `1/Ω` finite; the area density `h/(Ω r³)` within
/// `[16·tiny, max/16]` at the nearest and farthest points of the rectangle.
#[inline(always)]
fn check_range<T: Real>(g: &Geometry<T>, omega: &T) -> Result<T, WarpError> {
    let tiny = T::normal_floor();
    let floor = tiny / &T::unit_roundoff();
    if !(g.h.square() >= floor) {
        return Err(range::GRAZING);
    }
    let inv_omega = T::one() / omega;
    if !(*omega >= floor) || !omega.is_finite() || !inv_omega.is_finite() {
        return Err(if positive(omega) {
            range::OMEGA
        } else {
            WarpError::Degenerate {
                what: "zero solid angle",
            }
        });
    }
    if ordinary_density_range(&g.h, omega, g.exp) {
        return Ok(inv_omega);
    }
    let w = |x: &T| x.widen();
    let local = [w(&g.x0), w(&g.y0), w(&g.lx), w(&g.ly), w(&g.h)];
    let omega_w = w(omega);
    if !area_density_in_range::<T>(&local, &omega_w, g.exp)
        && !area_density_exact::<T>(&local, &omega_w, g.exp)
    {
        return Err(range::AREA_PDF);
    }
    Ok(inv_omega)
}

/// A sufficient condition for [`area_density_in_range`] by three
/// comparisons in `T`: `|exp| ≤ 16`, `h ≥ 2^-16`, `Ω ≥ 2^-32` (every
/// rectangle neither tiny, huge, grazed nor far away), for a `T` whose range
/// exceeds `2^±104` (`f32` and wider). Derivation:
/// `docs/spherical-rectangle.md` (one-shot cost).
#[inline(always)]
fn ordinary_density_range<T: Real>(h: &T, omega: &T, exp: i32) -> bool {
    exp.abs() <= 16
        && *h >= T::exp2i(-16)
        && *omega >= T::exp2i(-32)
        && T::max_value() >= T::exp2i(104)
}

/// M(u, v) with both densities, by the robust map. Inlined into its caller:
/// on the one-shot path the map's constants then need not be stored in a
/// [`Robust`] and read back (what `sample_once` gains over constructing the
/// shape).
#[inline(always)]
fn sample_with<T: Real>(
    g: &Geometry<T>,
    robust: &Robust<T>,
    inv_omega: &T,
    u: &T,
    v: &T,
) -> LightSample<T> {
    let (u, v) = (clamp_unit(u), clamp_unit(v));
    let (xi, x) = robust.column_at(&u);
    let row = robust.row_at(&x, &v);
    let point = g.point(&clamp01(&xi), &clamp01(&row.eta));
    // The sample's local vector (x, y_v, −h) has the length r = D/√(1 − h_v²)
    // (r² = D² + y_v², y_v = D h_v/√(1 − h_v²)): its unit vector is
    // (x/r, h_v, −h/r) with 1/r = √(1 − h_v²)/D, both from the row's values
    // (no root of x² + y_v² + h², which would wait for y_v).
    let inv_r = row.c.clone() / &row.dd;
    let r = row.dd / &row.c;
    let cos = g.h.clone() * &inv_r;
    let direction = g.direction(&(x * &inv_r), &row.hv, &cos);
    // pdf_area = cos θ_p / (Ω r²) with cos θ_p = h/r and the world distance
    // r·2^exp, as ((cos θ_p/Ω)·t)·t, t = 2^−exp/r: no spurious overflow or
    // underflow for the densities `check_range` admits.
    let t = T::exp2i(-g.exp) * &inv_r;
    let pdf_area = cos * inv_omega * &t * &t;
    LightSample {
        point,
        direction,
        // The world is the local frame scaled by 2^exp (exactly).
        distance: r * &T::exp2i(g.exp),
        pdf: inv_omega.clone(),
        pdf_area,
    }
}

impl<T: Real> Warp<T> for SphericalRectangle<T> {
    type Point = Vec3<T>;

    /// The unit direction of M(u, v) ([`SphericalRectangle::sample_point`]).
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        self.sample_full(u, v).direction
    }

    /// The direction of M(u, v) and `1/Ω`, without [`Warp::pdf`]'s test
    /// that the direction lies on the rectangle (it does, by construction).
    fn map_with_pdf(&self, u: &T, v: &T) -> (Vec3<T>, T) {
        (self.sample_full(u, v).direction, self.inv_omega.clone())
    }

    /// `1/Ω`.
    fn pdf_unchecked(&self, _d: &Vec3<T>) -> T {
        self.inv_omega.clone()
    }

    /// Ω.
    fn measure(&self) -> T {
        self.robust.omega().clone()
    }

    /// `(u, v)` of the direction `d` (normalized first): the ray from the
    /// observer hits the plane at `(x, y)`, `u = Ω([x₀, x])/Ω`,
    /// `v = (h(y) − h₀)/(h₁ − h₀)`, computed without cancellation (the same
    /// for both variants). `None` if `d` is not finite or lies farther than
    /// `2^(−p/2)` from the spherical rectangle.
    fn inverse(&self, d: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, d, &on_shape_tolerance::<T>())?;
        let (u, v) = self
            .direction_uv(d)
            .ok_or_else(|| InverseError::refuse(self, d))?;
        Ok([u, v])
    }

    /// `| |d| − 1 |` plus the Euclidean distance from the normalized `d` to
    /// the cone of directions towards the rectangle: 0 on the spherical
    /// rectangle, the sine of the angular distance to it up to 90°, 1
    /// beyond. Non-finite or zero `d`: [`Real::max_value`].
    fn outside_by(&self, d: &Vec3<T>) -> T {
        let Some((a, b, c)) = self.geometry.local_direction(d) else {
            return T::max_value();
        };
        let radial = (d.norm() - &T::one()).abs();
        radial + &self.cone().outside_local(&a, &b, &c)
    }
}

impl<T: Real> LightWarp<T> for SphericalRectangle<T> {
    fn observer(&self) -> Vec3<T> {
        self.geometry.o.clone()
    }

    /// M(u, v): the direction, the point `s + ξ e_x + η e_y` on the
    /// rectangle, its distance `r` from the observer, `1/Ω` and the density
    /// in area `cos θ_p / (Ω r²) = h / (Ω r³)`.
    #[inline]
    fn sample_light(&self, uv: [T; 2]) -> LightSample<T> {
        let [u, v] = uv;
        self.sample_full(&u, &v)
    }
}

crate::warp::distribution_for_floats!(SphericalRectangle, Vec3);

impl<T: Real> WarpFamily<T> for SphericalRectangle<T> {
    type At<S: Real> = SphericalRectangle<S>;

    /// The rectangle with its input converted to `S` (exactly, from `f32`
    /// or `f64`), same variant, perpendicularity tolerance of the coarser
    /// precision ([`SphericalRectangle::with_input_precision`]).
    fn at<S: Real>(&self) -> Result<SphericalRectangle<S>, WarpError> {
        let g = &self.geometry;
        SphericalRectangle::with_input_precision(
            g.s.convert(),
            g.ex.convert(),
            self.ey_input.convert(),
            g.o.convert(),
            self.variant,
            self.bits,
        )
    }

    /// `spherical-rectangle` (both variants).
    fn name(&self) -> String {
        "spherical-rectangle".to_string()
    }
}
