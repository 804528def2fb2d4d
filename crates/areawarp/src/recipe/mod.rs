//! Arvo's five-step recipe, one module per step.
//!
//! | step | what | trait / type |
//! |---|---|---|
//! | 1 | parametrization φ(s,t): [0, 1]² → M | [`Parametrization`] |
//! | 2 | area density σ(s,t) = ‖φ_s × φ_t‖ · w(φ) | [`AreaDensity`] |
//! | 3 | marginal F(s), conditional G_s(t) | [`MarginalConditional`] |
//! | 4 | inversion of F and G_s | [`Cdf1`], [`Inverter`]: [`ClosedForm`], [`Newton`], [`Bisection`], [`VandermondeCubic`] |
//! | 5 | ψ(u,v) = φ(F⁻¹(u), G_s⁻¹(v)) | [`RecipeWarp`], a [`Warp`](crate::warp::Warp) |
//!
//! A user defines a warp by implementing steps 1–3 for a struct (plus
//! [`Recipe`] to rebuild it at another precision), picks inverters, and gets a
//! [`RecipeWarp`]. See `docs/recipe.md` and `examples/define_your_own_warp.rs`.
//!
//! Or the user writes step 1 alone — φ and, optionally, a weight: a
//! [`WarpDefinition`] — and [`DerivedWarp`] executes steps 2–4 (σ by dual
//! numbers, F and G_s by adaptive Chebyshev/Clenshaw–Curtis quadrature to the
//! type's precision, inversion by safeguarded Newton), at any precision;
//! [`TabulatedWarp`] replaces the inversions by piecewise polynomials of F⁻¹
//! and G⁻¹ built for a requested tolerance. Closed forms the user has still
//! override any step. See `docs/recipe-quadrature.md`.

pub(crate) mod chebyshev;
mod compose;
mod definition;
pub mod definitions;
mod density;
mod derived;
mod distribution;
pub mod invert;
mod parametrization;
pub mod tabulated;

pub use compose::{Recipe, RecipeWarp};
pub use definition::WarpDefinition;
pub use density::AreaDensity;
pub use derived::{DerivedRecipe, DerivedWarp, QuadratureReport};
pub use distribution::MarginalConditional;
pub use invert::{
    Bisection, Cdf1, ClosedForm, Conditional, FittedCubic, Inversion, Inverter, Marginal, Newton,
    Start, Tolerance, VandermondeCubic,
};
pub use parametrization::Parametrization;
pub use tabulated::{TabulatedWarp, TabulationReport};
