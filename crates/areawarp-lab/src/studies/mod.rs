//! The studies behind `areawarp report`: each a folder (its experiment,
//! its tables, its figures, its tests) with a small API —
//! a configuration with quick and default sizes, a `run` returning plain
//! data, and writers for Markdown, CSV and figures ([`crate::figures`]).
//!
//! All studies are deterministic for a fixed seed whatever the number of
//! threads: work is split into jobs with their own seeds, run on rayon's
//! current thread pool, and reduced in job order.
//!
//! | study | question |
//! |---|---|
//! | [`precision`] (feature `mpfr`) | every warp × variant × {f32, f64} against the exact map at 256 bits on the extremes suite and the hard ladders: error in units of roundoff, NaN/∞, off-shape points, κ-conditioned ratio, 256-bit Jacobian; where the f32 error lives over [0, 1]² |
//! | [`precision_choice`] | per light-ladder shape: the worst error of f32 robust, f32 mixed (f64 arithmetic), f64 robust and the literal algorithms against 256 bits, beside the error predicted from the shape's conditioning and the evaluation chosen per tolerance; their cost per sample and one-shot |
//! | [`speed`] (feature `mpfr`) | ns/sample (with and without per-shape construction) against max error for every warp × variant × {f32, f64, mpfr:128, mpfr:256} and every inversion setting; Pareto sets and plots; recommended defaults |
//! | [`paper_figures`] | the papers' remaining figures re-made from our maps: the triangle-pair panel of Ureña–Fajardo–King 2013 Fig. 5, Ureña 2000 Figs. 3 and 7 (adaptive partitions, sample placements), Arvo 2001 Fig. 1.9 (the marginal CDF), Shao–Badler 1996 Figs. 3 and 4 (samples on a sphere and a spherical triangle), each with a measured number |
//! | [`sample_figures`] | the papers' sample-distribution figures re-made from our maps: uniform vs jittered samples on a spherical triangle (Arvo 1995), cosine-weighted samples in a non-convex polygon (Arvo 2001), Hammersley points on a spherical rectangle and pulled back to the rectangle (Ureña et al. 2013), each with a measured uniformity check |
//! | [`solid_angle_of_object`] | Shao–Badler §3: the solid angle of an object by stratified sampling of the sphere in cylinder coordinates, restricted to the object's (z, φ) bounding box; error vs samples; the random-axis variant; where the `f32` truncation error of the sphere map concentrates |
//! | [`adaptive_comparison`] | Ureña 2000 §5: stratified solid-angle and cosine-weighted sampling against adaptive sampling with K = ∞, 0.1, 0.001 at equal sample counts on a patterned triangle light with occluders; with the CPU time of one whole estimate of every method (cold, per-receiver work included) and its efficiency at equal time; attached to the variance study |
//! | [`light_cost`] (feature `mpfr`) | Ureña et al. 2013's cost claim: ns per sample of area, spherical-rectangle, triangle-pair, projected-polygon and cosine sampling of the standing light, alone and inside the estimator with 0, 3 and many occluders; construction per receiver; ratios to area sampling |
//! | [`equal_time`] | the variance study's methods at equal time, without and with occluders: error against CPU µs per receiver of the whole estimator (timed here: thread CPU time, interleaved rounds, minimum over rounds) and efficiency 1/(MSE·time); the bias of cubic-only projected-polygon inversion |
//! | [`rendered_images`] | false-colour irradiance images of the ground: Ureña, Fajardo & King 2013 Fig. 4/6 (reference, every light sampler with and without MIS at 1/4/16 spp, signed errors) and Ureña 2000 Fig. 9 (36 spp: unstratified, stratified, adaptive K = 0.1 and 0.001) with the studies' estimators |
//! | [`variance`] | Ureña, Fajardo & King 2013, Fig. 4/7: relative RMS error vs spp of area, triangle-pair, spherical-rectangle and projected-polygon sampling of a standing rectangular light, with and without MIS; samples at equal error |

pub mod adaptive_comparison;
pub mod adaptive_triangle;
pub mod equal_time;

pub mod light_cost;
pub mod paper_figures;

pub mod precision;
pub mod precision_choice;
pub mod rendered_images;
pub mod sample_figures;
pub mod solid_angle_of_object;

pub mod speed;
pub mod variance;
// New studies: add `pub mod <name>;` here and one line in
// `cli::report::EXTRA_STUDIES` (e.g. `precision_choice`: f32 vs mixed vs
// f64 per shape).
