//! The subcommands of the `areawarp` program.

pub mod eval;
pub mod eval_auto;
pub mod eval_recipe;
mod overview;
pub mod placement;
pub mod report;
pub mod summary;
