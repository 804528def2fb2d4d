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
//! sampling ([`estimate`]), Ureña's adaptive triangle sampling ([`adaptive`]),
//! a minimal scene model for the experiments ([`scene`]) and, with the
//! `studies` feature, the studies behind `areawarp report`.
//!
//! ## Features
//! - `mpfr` (default): MPFR scalars ([`real::Mpfr`]) via `rug` (builds GMP/MPFR from C).
//! - `studies` (default through `cli`): the studies and figure writers (adds `rayon`).
//! - `cli` (default): the `areawarp` program (`eval`, `report`); implies `mpfr` and `studies`.
//!
//! A renderer depends on `areawarp` with `default-features = false`: pure Rust.
#![deny(missing_docs)]

pub mod adaptive;
pub mod error;
pub mod estimate;
#[cfg(feature = "studies")]
pub mod figures;
pub mod harness;
pub mod real;
pub mod recipe;
pub mod sampling;
pub mod scene;
pub mod shapes;
#[cfg(feature = "studies")]
pub mod studies;
pub mod vector;
pub mod warp;

pub use error::WarpError;
pub use real::Real;
pub use vector::{Coords, Vec2, Vec3};
pub use warp::{Warp, WarpFamily};
