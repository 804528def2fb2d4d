//! # areawarp
//!
//! Area-preserving parametrizations ("warps") of 2-manifolds: maps ψ from the
//! unit square onto a shape whose Jacobian is constant, so that uniform,
//! stratified or quasi-Monte Carlo points on [0, 1]² become uniform (or
//! weighted) samples on the shape.
//!
//! The crate follows Arvo's five-step recipe ([`recipe`]), generic over the
//! scalar type ([`real::Real`]: `f32`, `f64`, MPFR, dual numbers), and ships
//! the warps ([`shapes`]: planar triangle, disks, hemisphere, Phong lobe,
//! sphere, spherical triangle and rectangle, projected spherical polygon) and
//! a checking harness ([`harness`]) that proves, at 256 bits, that a map's
//! Jacobian really is constant and measures how many digits `f32`/`f64` lose.
//! Around them: point sets ([`sampling`]), estimators and multiple importance
//! sampling ([`estimate`]) and Ureña's adaptive triangle sampling
//! ([`adaptive`]). The studies behind the report, the scene model they use
//! and the `areawarp` program live in the separate `areawarp-lab` crate.
//!
//! ## Features
//! The default build is pure Rust with `rand` as its only dependency.
//! - `mpfr` (opt-in): MPFR scalars (`real::Mpfr`) via `rug`, which builds
//!   GMP/MPFR from C sources; it enables the harness's 256-bit checks.
//! - `mint`, `glam`, `nalgebra` (opt-in): `From`/`Into` between [`Vec2`]/[`Vec3`]
//!   and those crates' vector and point types (see [`vector`]).
#![deny(missing_docs)]

pub mod adaptive;
pub mod derivations;
pub mod error;
pub mod estimate;
pub mod harness;
pub mod precision_choice;
pub mod real;
pub mod recipe;
pub mod sampling;
pub mod shapes;
pub mod vector;
pub mod warp;

pub use error::WarpError;
pub use real::Real;
pub use vector::{Coords, Vec2, Vec3};
pub use warp::{InverseError, LightSample, LightWarp, Sample, Warp, WarpFamily};
