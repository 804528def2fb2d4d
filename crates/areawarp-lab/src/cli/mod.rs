//! The subcommands of the `areawarp` program.

pub mod eval;
pub mod report;
pub mod summary;
