//! Study 4 — the solid angle of an object by sampling the sphere
//! (Shao & Badler 1996, §3).
//!
//! # The estimator
//! Archimedes' local theorem makes the axial projection of the unit sphere
//! onto its circumscribed cylinder area-preserving, so a uniform point
//! `(z, φ)` of `[−1, 1] × [0, 2π)` — in the crate's parameters
//! `(u, v) = ((1 − z)/2, φ/2π)` of [`Sphere`] — is a uniform direction. The
//! solid angle Ω of an object seen from a point `o` is the measure of the set
//! of directions whose ray from `o` hits the object, so with `n` directions
//! `d_i` uniform in a region `B` of measure `|B|` that contains the object's
//! directions,
//!
//! Ω̂ = |B| · #{i : ray(o, d_i) hits the object} / n,    E[Ω̂] = Ω.
//!
//! Shao and Badler's remarks, all implemented here:
//! 1. the region is the object's *angular bounding box* in `(z, φ)`
//!    ([`AngularBox`], [`angular_box`]): `|B| = 4π · Δu · Δv` instead of
//!    `4π`, so only that part of the unit square is sampled and the variance
//!    of the hit indicator drops with the miss rate;
//! 2. *stratified* sampling is trivial in `(z, φ)`: a jittered `k × k` grid
//!    over the box ([`Sampling::Stratified`]); only strata cut by the
//!    silhouette contribute variance, so the error falls like `n^(−3/4)`
//!    instead of `n^(−1/2)`;
//! 3. the truncation error of the axial projection concentrates at the
//!    poles; the cure is a *random axis* ([`AxisMode::Random`]) — per sample
//!    for random sampling, and for stratified sampling a coarser stratified
//!    set of axes times a stratified cylinder grid per axis (`≈ n^(1/4)`
//!    axes × `≈ n^(3/4)` samples each).
//!
//! The object is a triangle mesh ([`TriangleMesh`]) and the ray test
//! Möller–Trumbore ([`ray_hits_triangle`]) with an *inclusive* edge policy.
//!
//! # The exact reference
//! The solid angle of one triangle seen from the origin, with vertex vectors
//! `a, b, c` (Van Oosterom & Strackee 1983):
//!
//! tan(Ω/2) = |a · (b × c)| / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|),
//!
//! evaluated as `2 atan2(|det|, den)` (correct also when the denominator is
//! negative, Ω > π), generic over [`Real`]: in `f64` and at 256 bits
//! ([`exact_solid_angle`]). A convex closed mesh covers each direction of its
//! silhouette twice from outside (Ω = ½ Σ|Ω_f|, equivalently the sum over
//! the faces facing the viewer) and every direction once from inside
//! (Ω = Σ|Ω_f| = 4π); an open mesh that no ray from the viewpoint crosses
//! twice (e.g. a roof seen from above) has Ω = Σ|Ω_f|.
//!
//! # `f32` truncation error
//! [`run`] also maps the end-to-end error of `Sphere<f32>` — data `(u, v)`
//! given in `f64`, rounded to `f32` and mapped in `f32` — against the 256-bit
//! map at the exact data, over a grid of cells of `[0, 1]²`, as a profile
//! towards each pole, and over world directions for a fixed and a random
//! axis. The `f32` inputs near `u = 1` are spaced by `2^-24`, so the height
//! `z = 1 − 2u` is quantized to `2^-23` and the direction near the south
//! pole by `≈ 2^-23/sin θ`: the error grows like `1/sin θ` there, while
//! floats are dense near `u = 0` and the north pole stays accurate. The
//! evaluation alone (inputs first rounded to `f32`, as in
//! [`areawarp::harness::precision`]) stays within a few units everywhere.
//!
//! # Example
//! ```
//! use areawarp_lab::studies::solid_angle_of_object::{SolidAngleConfig, run};
//!
//! let mut config = SolidAngleConfig::quick();
//! config.sample_counts = vec![16, 256];
//! config.repetitions = 4;
//! config.heat_map_cells = 8;
//! config.world_samples = 256;
//! config.profile_points = 2;
//! let study = run(&config)?;
//! assert!(study.rows.iter().all(|r| r.rms_relative_error.is_finite()));
//! assert!(study.to_markdown().contains("Solid angle of an object"));
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use crate::figures::{self, Axis, Figure, HeatMap, Plot, Scale, Series};
use areawarp::error::WarpError;
use areawarp::real::{Real, convert};
use areawarp::shapes::Sphere;
use areawarp::vector::Vec3;
use areawarp::warp::{Warp, WarpFamily};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};
type Reference = areawarp::real::Mpfr256;
mod geometry;
mod output;
mod run;
pub use self::geometry::*;
pub use self::run::*;
#[cfg(test)]
mod tests;
// ---------------------------------------------------------------------------
// Scenes and methods
// ---------------------------------------------------------------------------

/// An object and the point it is seen from.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// A short name (used in file names).
    pub name: String,
    /// One line for the report.
    pub description: String,
    /// The object.
    pub mesh: TriangleMesh,
    /// The point it is seen from.
    pub viewpoint: Vec3<f64>,
}

/// The study's default scenes, all seen from the origin:
/// - `tetrahedron`: an irregular tetrahedron (closed, convex) off to the
///   side, above the equator;
/// - `roof`: an open pyramid roof below the viewpoint, straddling the
///   south pole of the default axis;
/// - `speck`: an octahedron of radius `10^-3` one unit below the viewpoint
///   (slightly off-axis) — a 2 mm object seen from 1 m, inside the region
///   where `f32` heights near the south pole are quantized.
///
/// # Errors
/// Never in practice (the meshes are valid); propagated from the mesh constructors.
pub fn default_scenes() -> Result<Vec<Scene>, WarpError> {
    let v = Vec3::new;
    Ok(vec![
        Scene {
            name: "tetrahedron".into(),
            description: "irregular tetrahedron (closed, convex), off to the side".into(),
            mesh: TriangleMesh::tetrahedron([
                v(1.4, 0.3, 0.5),
                v(1.9, 1.1, 0.2),
                v(1.1, 1.2, 0.9),
                v(1.8, 0.6, 1.3),
            ])?,
            viewpoint: Vec3::zero(),
        },
        Scene {
            name: "roof".into(),
            description: "open pyramid roof (4 faces) below the viewpoint, around the south pole"
                .into(),
            mesh: TriangleMesh::pyramid_roof(v(0.15, -0.1, -1.5), 1.0, 0.6)?,
            viewpoint: Vec3::zero(),
        },
        Scene {
            name: "speck".into(),
            description: "octahedron of radius 1e-3 one unit straight below (2 mm seen from 1 m)"
                .into(),
            mesh: TriangleMesh::octahedron(v(3e-4, -2e-4, -1.0), 1e-3)?,
            viewpoint: Vec3::zero(),
        },
    ])
}

/// How the points of the cylinder are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// Independent uniform points.
    Random,
    /// A jittered `k × k` grid (`n = k²`): one uniform point per stratum.
    Stratified,
}

/// The cylinder axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisMode {
    /// The `+z` axis ([`Sphere::new`]).
    Fixed,
    /// Random axes ([`Sphere::with_random_axis`], [`Sphere::with_axis`]):
    /// one per sample for [`Sampling::Random`]; for [`Sampling::Stratified`]
    /// a jittered `a × a` set of axes mapped through the sphere, each with a
    /// jittered `c × c` cylinder grid in its own box (`n = 4^k`,
    /// `a = 2^⌊k/4⌋`, `c = 2^(k − ⌊k/4⌋)`: `a² ≈ n^(1/4)` axes). Splitting
    /// `n` samples over `m` independently stratified boxes costs a factor
    /// `≈ m^(1/4)` in error against one box (`(n/m)^(−3/4)/√m`), so the
    /// axis grid is kept coarse, as Shao and Badler suggest.
    Random,
}

/// The scalar of the sphere map (the ray test is always `f64`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// `Sphere<f32>`: `(u, v)` rounded to `f32`.
    F32,
    /// `Sphere<f64>`.
    F64,
}

/// One estimator variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Method {
    /// Random or stratified points.
    pub sampling: Sampling,
    /// Fixed or random axis.
    pub axis: AxisMode,
    /// `f32` or `f64` sphere map.
    pub precision: Precision,
    /// Sample only the object's angular bounding box (else the whole sphere).
    pub bounding_box: bool,
}

impl Method {
    /// A short name, e.g. `stratified/fixed/f64/box`.
    pub fn name(&self) -> String {
        format!(
            "{}/{}/{}/{}",
            match self.sampling {
                Sampling::Random => "random",
                Sampling::Stratified => "stratified",
            },
            match self.axis {
                AxisMode::Fixed => "fixed",
                AxisMode::Random => "random-axis",
            },
            match self.precision {
                Precision::F32 => "f32",
                Precision::F64 => "f64",
            },
            if self.bounding_box { "box" } else { "sphere" }
        )
    }

    /// The study's methods: random and stratified in the box (fixed axis,
    /// `f64`); stratified over the whole sphere; random and stratified with
    /// random axes (`f64`); stratified with fixed and random axes in `f32`.
    pub fn standard() -> Vec<Method> {
        let m = |sampling, axis, precision, bounding_box| Method {
            sampling,
            axis,
            precision,
            bounding_box,
        };
        use AxisMode::{Fixed, Random as Rand};
        use Precision::{F32, F64};
        vec![
            m(Sampling::Random, Fixed, F64, true),
            m(Sampling::Stratified, Fixed, F64, true),
            m(Sampling::Stratified, Fixed, F64, false),
            m(Sampling::Random, Rand, F64, true),
            m(Sampling::Stratified, Rand, F64, true),
            m(Sampling::Stratified, Fixed, F32, true),
            m(Sampling::Stratified, Rand, F32, true),
        ]
    }
}

// ---------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------

/// The study's size and seed.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidAngleConfig {
    /// Master seed; every job derives its own from it.
    pub seed: u64,
    /// Sample counts, each a power of 4 (`4, 16, 64, …`).
    pub sample_counts: Vec<usize>,
    /// Independent estimates per (scene, method, n), at least 2.
    pub repetitions: usize,
    /// The scenes.
    pub scenes: Vec<Scene>,
    /// The methods.
    pub methods: Vec<Method>,
    /// Cells per side of the `f32` error map over `[0, 1]²`.
    pub heat_map_cells: usize,
    /// Points per cell side of that map (`p × p` jittered points per cell).
    pub heat_map_points: usize,
    /// Samples of the world-direction error maps (fixed and random axis).
    pub world_samples: usize,
    /// Points per distance of the pole profile.
    pub profile_points: usize,
    /// The largest `n` run with a random axis *per sample*
    /// ([`Sampling::Random`] × [`AxisMode::Random`]), which rebuilds the
    /// bounding box for every sample (a few µs each); larger counts are
    /// skipped for that method.
    pub per_sample_axis_max_n: usize,
}

impl SolidAngleConfig {
    /// A quick run (a second or two in `--release` on 2 cores): `n` up to
    /// 4096, 12 repetitions, a 64 × 64 error map.
    ///
    /// The scenes are [`default_scenes`] (valid by construction; were one
    /// not, the list would be empty and [`run`] would reject it).
    pub fn quick() -> Self {
        SolidAngleConfig {
            seed: 0x5EED_5A0B,
            sample_counts: (1..=6).map(|k| 1usize << (2 * k)).collect(),
            repetitions: 12,
            scenes: default_scenes().unwrap_or_default(),
            methods: Method::standard(),
            heat_map_cells: 64,
            heat_map_points: 2,
            world_samples: 20_000,
            profile_points: 16,
            per_sample_axis_max_n: 4096,
        }
    }
}

impl Default for SolidAngleConfig {
    /// The report's size (≈ 11 s in `--release` on 2 cores): `n` from 4 to
    /// 65536, 32 repetitions, a 128 × 128 error map with 2 × 2 points per
    /// cell, 100 000 world samples per axis mode.
    fn default() -> Self {
        SolidAngleConfig {
            sample_counts: (1..=8).map(|k| 1usize << (2 * k)).collect(),
            repetitions: 32,
            heat_map_cells: 128,
            heat_map_points: 2,
            world_samples: 100_000,
            profile_points: 64,
            ..Self::quick()
        }
    }
}

impl SolidAngleConfig {
    fn validate(&self) -> Result<(), WarpError> {
        if self.sample_counts.is_empty()
            || self
                .sample_counts
                .iter()
                .any(|&n| n < 4 || !n.is_power_of_two() || n.trailing_zeros() % 2 != 0)
        {
            return Err(WarpError::InvalidParameter {
                name: "sample_counts",
                expected: "a non-empty list of powers of 4 (4, 16, 64, …)",
            });
        }
        if self.repetitions < 2 {
            return Err(WarpError::InvalidParameter {
                name: "repetitions",
                expected: "at least 2",
            });
        }
        if self.scenes.is_empty() || self.methods.is_empty() {
            return Err(WarpError::InvalidParameter {
                name: "scenes/methods",
                expected: "at least one scene and one method",
            });
        }
        if self.heat_map_cells == 0
            || self.heat_map_points == 0
            || self.world_samples == 0
            || self.profile_points == 0
        {
            return Err(WarpError::InvalidParameter {
                name: "heat_map_cells/heat_map_points/world_samples/profile_points",
                expected: "positive",
            });
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------

/// A scene's exact solid angle.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSummary {
    /// Scene name.
    pub name: String,
    /// Scene description.
    pub description: String,
    /// Number of faces.
    pub faces: usize,
    /// Closed convex or open.
    pub kind: MeshKind,
    /// Ω in `f64` (sr).
    pub exact_f64: f64,
    /// Ω at the reference precision (decimal, 256 bits with `mpfr`).
    pub exact_reference: String,
    /// `|Ω_f64 − Ω_ref| / Ω_ref`.
    pub f64_relative_error: f64,
    /// Fraction of the sphere covered by the box with the fixed axis.
    pub fixed_box_fraction: f64,
}

/// Error of one method on one scene at one sample count.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    /// Scene name.
    pub scene: String,
    /// [`Method::name`].
    pub method: String,
    /// Samples per estimate.
    pub n: usize,
    /// Number of estimates.
    pub repetitions: usize,
    /// Mean of the estimates (sr).
    pub mean: f64,
    /// RMS of `(Ω̂ − Ω)/Ω` over the estimates.
    pub rms_relative_error: f64,
    /// Standard error of `rms_relative_error` (delta method: the standard
    /// deviation of the squared relative errors / √R, over 2 × RMS).
    pub rms_std_error: f64,
    /// `(mean − Ω)/Ω`.
    pub relative_bias: f64,
    /// Standard error of `relative_bias` (sample standard deviation / √R / Ω).
    pub bias_std_error: f64,
    /// Mean fraction of the sphere covered by the sampled boxes.
    pub box_fraction: f64,
    /// The relative standard deviation plain random sampling of that box
    /// would have: `√(p(1 − p)/n) · |B| / Ω`, `p = Ω/|B|`.
    pub random_prediction: f64,
}

/// Least-squares slope of `log RMS error` against `log n`.
#[derive(Clone, Debug, PartialEq)]
pub struct SlopeRow {
    /// Scene name.
    pub scene: String,
    /// [`Method::name`].
    pub method: String,
    /// The slope (−1/2 for plain Monte Carlo, −3/4 for stratified with a
    /// smooth silhouette).
    pub slope: f64,
}

/// The `f32` error of the sphere map over a grid of `[0, 1]²`.
#[derive(Clone, Debug, PartialEq)]
pub struct F32ErrorMap {
    /// Cells along `u` (columns).
    pub cols: usize,
    /// Cells along `v` (rows).
    pub rows: usize,
    /// Points per cell.
    pub points_per_cell: usize,
    /// The reference scalar, e.g. `mpfr:256`.
    pub reference: String,
    /// Per cell (row-major, row = `v` index), the maximal end-to-end error
    /// (data `(u, v)` in `f64`, rounded to `f32` and mapped in `f32`, against
    /// the reference map at the data), in units of `2^-24`.
    pub end_to_end_ulps: Vec<f64>,
    /// Per cell, the maximal evaluation error (reference at the
    /// `f32`-rounded inputs), in units of `2^-24`.
    pub evaluation_ulps: Vec<f64>,
}

/// The `f32` error at distance `d` from each pole (`u ∈ [d, 2d)` and
/// `1 − u ∈ (d, 2d]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PoleProfileRow {
    /// `log2 d`.
    pub log2_distance: i32,
    /// Max end-to-end error near the north pole (`u ≈ d`), units of `2^-24`.
    pub north_end_to_end: f64,
    /// Max end-to-end error near the south pole (`u ≈ 1 − d`).
    pub south_end_to_end: f64,
    /// Max evaluation-only error near the north pole.
    pub north_evaluation: f64,
    /// Max evaluation-only error near the south pole.
    pub south_evaluation: f64,
}

/// Where the `f32` end-to-end error lands in world directions, for one
/// axis mode.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisSpread {
    /// `fixed` or `random`.
    pub axis: String,
    /// Number of samples.
    pub samples: usize,
    /// Share of the total squared error that falls in the polar caps
    /// `|z| > 0.99` of the *world* frame (1% of the sphere).
    pub cap_error_share: f64,
    /// Max error (units of `2^-24`) in the world's north cap `z > 0.99`.
    pub max_north_cap: f64,
    /// Max error in the world's south cap `z < −0.99`.
    pub max_south_cap: f64,
    /// Max error elsewhere.
    pub max_elsewhere: f64,
    /// RMS error over all samples.
    pub rms: f64,
    /// Cells of the world map along `u_w = (1 − z)/2` (columns).
    pub cols: usize,
    /// Cells along `v_w = φ/2π` (rows).
    pub rows: usize,
    /// Per-cell RMS error (row-major, row = `v_w` index); `None` for
    /// empty cells.
    pub cell_rms: Vec<Option<f64>>,
}

/// Everything [`run`] measured.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidAngleStudy {
    /// The configuration used.
    pub config: SolidAngleConfig,
    /// Exact references.
    pub scenes: Vec<SceneSummary>,
    /// Error rows, by scene, method, `n`.
    pub rows: Vec<ErrorRow>,
    /// Convergence slopes, by scene and method.
    pub slopes: Vec<SlopeRow>,
    /// The `f32` error map over `[0, 1]²`.
    pub f32_map: F32ErrorMap,
    /// The `f32` error towards each pole.
    pub pole_profile: Vec<PoleProfileRow>,
    /// World-direction error spread, fixed and random axis.
    pub axis_spread: Vec<AxisSpread>,
    /// A sample-distribution demo: the first scene, stratified fixed-axis
    /// box, 1024 points `(v, u, hit)`.
    pub demo_points: Vec<(f64, f64, bool)>,
    /// The demo's box.
    pub demo_box: AngularBox,
}
