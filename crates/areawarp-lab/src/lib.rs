//! # areawarp-lab
//!
//! The program around the `areawarp` library: the `areawarp` command
//! (`eval`, `report`), the studies behind the report, the minimal scene
//! model they run in, the figure writers, parallel job runs and progress
//! bars. A renderer never needs this crate; it depends on `areawarp` alone.
//!
//! | module | what it holds |
//! |---|---|
//! | [`cli`] | the `eval` and `report` subcommands |
//! | [`studies`] | one folder per study of the report (its experiment, tables, figures) |
//! | [`estimator`] | the estimator pieces the variance experiments share: strategies, MIS methods, point sets, the measurement engine |
//! | [`verdict`] | the rule that judges a paper's claim against a measurement, with intervals and p-values |
//! | [`scene`] | receivers, emitters, occluders and light-sampling strategies for the variance experiments |
//! | [`figures`] | SVG/PNG line plots, scatter plots, heat maps and grids of false-colour images drawn with plotters, and their checker |
//! | [`jobs`] | [`jobs::run_jobs`]: reproducible parallel estimator jobs on rayon |
//! | [`progress`] | progress bars (indicatif) for long parallel steps |
//! | [`timing`] | per-thread CPU time for timings on a shared machine |
#![deny(missing_docs)]

pub mod cli;
pub mod estimator;
pub mod figures;
pub mod jobs;
pub mod progress;
pub mod scene;
pub mod studies;
pub mod timing;
pub mod verdict;
