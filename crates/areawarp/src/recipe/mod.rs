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

mod compose;
mod density;
mod distribution;
pub mod invert;
mod parametrization;

pub use compose::{Recipe, RecipeWarp};
pub use density::AreaDensity;
pub use distribution::MarginalConditional;
pub use invert::{
    Bisection, Cdf1, ClosedForm, Conditional, FittedCubic, Inversion, Inverter, Marginal, Newton,
    Start, Tolerance, VandermondeCubic,
};
pub use parametrization::Parametrization;
