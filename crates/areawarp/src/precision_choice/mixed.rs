//! The mixed mode: `f32` in and out, `f64` arithmetic.

use super::Advisable;
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp};

/// A light shape with `f32` inputs and outputs whose map is evaluated in
/// `f64`: the shape is the `f32` one (its parameters rounded to `f32`),
/// `u`, `v` are `f32`, the direction is the robust `f64` map rounded to
/// `f32`. Its error against the exact map of the `f32` inputs is the
/// final rounding (`≤ 2⁻²⁴`) plus the `f64` map's `16·max(2⁻⁵³, κ₆₄)`: what
/// the few shapes whose `f32` conditioning is too poor for `f32`
/// arithmetic need ([`advise`](super::advise) says which).
///
/// `inverse` and `outside_by` take `f32` directions with `f32`'s on-shape
/// tolerance `2⁻¹²`.
///
/// # Example
/// ```
/// use areawarp::precision_choice::Mixed;
/// use areawarp::shapes::SphericalTriangle;
/// use areawarp::{Vec3, Warp};
/// let t = SphericalTriangle::<f64>::new(
///     Vec3::new(1.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
///     Vec3::new(0.0, 0.0, 1.0),
/// )?;
/// let m = Mixed::new(&t)?;
/// let p: Vec3<f32> = m.map(&0.25, &0.5);
/// let [u, v] = m.inverse(&p).unwrap();
/// assert!((u - 0.25).abs() < 1e-6 && (v - 0.5).abs() < 1e-6);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Mixed<W: Advisable> {
    /// The `f64` shape of the `f32`-rounded parameters.
    inner: W::In<f64>,
    /// `1/Ω` and Ω rounded to `f32`.
    pdf: f32,
    measure: f32,
}

impl<W: Advisable> Mixed<W> {
    /// The mixed-mode evaluation of `w` (robust variant), its parameters
    /// rounded to `f32` first.
    ///
    /// # Errors
    /// [`WarpError`] if the shape's `f32` parameters are rejected, or
    /// [`WarpError::Unrepresentable`] if its density is not an `f32`.
    pub fn new(w: &W) -> Result<Self, WarpError> {
        let p: Vec<f64> = w
            .parameters()
            .iter()
            .map(|&x| f64::from(x as f32))
            .collect();
        Self::from_f32_parameters(&p)
    }

    /// The mixed-mode evaluation of the shape with the `f32` parameters `p`
    /// (as `f64` values).
    ///
    /// # Errors
    /// As [`Mixed::new`].
    pub fn from_f32_parameters(p: &[f64]) -> Result<Self, WarpError> {
        let inner = W::build(p, false, 24)?;
        let measure = inner.measure() as f32;
        let pdf = (1.0 / inner.measure()) as f32;
        if !(pdf > 0.0 && pdf.is_finite() && measure > 0.0) {
            return Err(WarpError::Unrepresentable {
                what: "solid angle or density outside the range of f32",
            });
        }
        Ok(Mixed {
            inner,
            pdf,
            measure,
        })
    }

    /// The `f64` shape the map is evaluated with.
    pub fn inner(&self) -> &W::In<f64> {
        &self.inner
    }
}

fn narrow(p: &Vec3<f64>) -> Vec3<f32> {
    Vec3::new(p.x as f32, p.y as f32, p.z as f32)
}

fn widen(p: &Vec3<f32>) -> Vec3<f64> {
    Vec3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z))
}

impl<W: Advisable> Warp<f32> for Mixed<W> {
    type Point = Vec3<f32>;

    /// The robust `f64` map at `(u, v)`, rounded to `f32`.
    fn map(&self, u: &f32, v: &f32) -> Vec3<f32> {
        narrow(&self.inner.map(&f64::from(*u), &f64::from(*v)))
    }

    /// `1/Ω` (the density is constant on the shape).
    fn pdf_unchecked(&self, _p: &Vec3<f32>) -> f32 {
        self.pdf
    }

    /// `f32`'s on-shape tolerance `2⁻¹²`.
    fn on_shape_tolerance(&self) -> f32 {
        f32::exp2i(-12)
    }

    /// The map and `1/Ω`.
    fn map_with_pdf(&self, u: &f32, v: &f32) -> (Vec3<f32>, f32) {
        (self.map(u, v), self.pdf)
    }

    /// Ω.
    fn measure(&self) -> f32 {
        self.measure
    }

    /// ψ⁻¹ in `f64` of the `f32` direction `p`, rounded to `f32`.
    ///
    /// # Errors
    /// [`InverseError`] if `p` is not finite or lies farther than `2⁻¹²`
    /// from the shape.
    fn inverse(&self, p: &Vec3<f32>) -> Result<[f32; 2], InverseError> {
        InverseError::check(self, p, &f32::exp2i(-12))?;
        let (u, v) = W::inverse_unchecked(&self.inner, &widen(p))
            .ok_or_else(|| InverseError::refuse(self, p))?;
        Ok([u as f32, v as f32])
    }

    /// The `f64` shape's `outside_by` of `p`, rounded to `f32`.
    fn outside_by(&self, p: &Vec3<f32>) -> f32 {
        self.inner.outside_by(&widen(p)) as f32
    }
}
