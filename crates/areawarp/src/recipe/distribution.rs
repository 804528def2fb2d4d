//! Step 3: the marginal and conditional distributions.

use crate::real::Real;

/// Step 3: the marginal CDF F(s) = ∫₀ˢ∫₀¹ σ / m and the conditional CDF
/// G_s(t) = ∫₀ᵗ σ(s, ·) / ∫₀¹ σ(s, ·), with their densities, where
/// m = ∫∫ σ is the total measure.
///
/// Closed-form inverses, when known, are returned by
/// [`MarginalConditional::marginal_inverse`] and
/// [`MarginalConditional::conditional_inverse`] and used by the
/// [`ClosedForm`](super::ClosedForm) inverter.
pub trait MarginalConditional<T: Real> {
    /// m = ∫∫ σ: the total (weighted) measure of M.
    fn measure(&self) -> T;
    /// F(s).
    fn marginal_cdf(&self, s: &T) -> T;
    /// F'(s) = ∫₀¹ σ(s, t) dt / m.
    fn marginal_pdf(&self, s: &T) -> T;
    /// G_s(t).
    fn conditional_cdf(&self, s: &T, t: &T) -> T;
    /// ∂G_s/∂t.
    fn conditional_pdf(&self, s: &T, t: &T) -> T;
    /// F⁻¹(u) in closed form, if known.
    fn marginal_inverse(&self, _u: &T) -> Option<T> {
        None
    }
    /// G_s⁻¹(v) in closed form, if known.
    fn conditional_inverse(&self, _s: &T, _v: &T) -> Option<T> {
        None
    }
}
