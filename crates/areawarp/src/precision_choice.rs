//! Precision chosen per shape: predict, from a light shape's measured
//! conditioning, the worst error of each way to evaluate it, and pick the
//! cheapest that meets a tolerance.
//!
//! A renderer that samples lights in `f32` to go faster should not have to
//! guess which lights need `f64`. For a spherical triangle or rectangle,
//! [`advise`] measures the shape's condition κ — how far the exact map moves
//! when one input (a vertex coordinate, `u`, `v`) moves by one unit in the
//! last place of `f32` or of `f64` — at a set of probe points, and predicts
//! the worst error (max-norm distance of the returned direction to the exact
//! map of the same inputs) of every [`Evaluation`]:
//!
//! | evaluation | predicted worst error |
//! |---|---|
//! | [`Evaluation::RobustF32`] | `16·max(2⁻²⁴, κ₃₂)` |
//! | [`Evaluation::MixedF32`] (f32 in and out, f64 arithmetic: [`Mixed`]) | `2⁻²⁴ + 16·max(2⁻⁵³, κ₆₄')` (κ₆₄' of the shape rounded to f32, plus the final rounding) |
//! | [`Evaluation::RobustF64`] | `16·max(2⁻⁵³, κ₆₄)` |
//! | (any robust one, when the above is `≥ 1/4`) | 2: no digit left (the largest distance of two unit vectors) |
//! | [`Evaluation::LiteralF32`], [`Evaluation::LiteralF64`] | `4·e + 16·max(u, κ) + c`, `e` the literal map's error observed at the probes against the robust `f64` map, `c` the error of a cut-off of the published algorithm bounded from the geometry ([`Advisable::literal_cutoff_error`]: the rectangle's `h_v² ≥ 1 − ε ⇒ y_v = y₁`); `∞` if it is NaN at a probe |
//!
//! The robust maps are as accurate as their inputs allow — within
//! `16·max(u, κ)` of the exact map, measured against 256 bits on the hard
//! ladders and on random shapes — so their prediction is an upper bound by
//! construction, and not a loose one: they stay within 0.04–0.25 of it. The
//! papers' literal algorithms have no such bound (their cancellations are
//! not the shape's), so theirs is measured at the probes, plus what their
//! cut-offs can cost where no probe lands, and kept for comparison;
//! [`Advice::choose`] never picks them.
//!
//! κ₃₂ is measured by one-`f32`-ulp perturbations evaluated with the robust
//! `f64` map (the definition of κ, evaluated `2²⁹` times more precisely
//! than the effect it measures); κ₆₄ by perturbations of `2¹⁶` `f64` ulps,
//! divided by `2¹⁶` (a linearization whose rounding noise is `2⁻¹⁶` of the
//! map's own error). What is perturbed is what the evaluation rounds
//! ([`Advisable::rounding_model`]): the triangle's vertex coordinates; the
//! rectangle's local coordinates `x₀, y₀, h` and edge lengths (by one ulp of
//! the arithmetic, or by the rounding of the `f64` dot products that compute
//! them from `s − o`, whichever is larger), not the world coordinates of
//! its corner and observer — those overstate the rounding of a rectangle
//! whose corner is far from the origin, and put a grazing observer exactly
//! on the plane (rejected) although `h` crossing zero moves the map only if
//! the observer's foot is on the rectangle. The probes are the extremes grid (`u, v ∈ {0, 2⁻⁶⁰,
//! 10⁻¹², 10⁻⁶, ½, 1 − 10⁻⁶, 1 − 10⁻¹², 1}`, where the maps' conditioning is
//! worst) and 16 random points. Cost: about 60 constructions and 5 000 map
//! evaluations in `f64`, ≈ 0.3 ms: a per-light decision at scene load, not
//! per sample.
//!
//! # Example
//! ```
//! use areawarp::precision_choice::{advise, Evaluation};
//! use areawarp::shapes::{hard_triangles, SphericalTriangle};
//! use areawarp::Vec3;
//!
//! // An ordinary triangle: f32 is enough for a tolerance of 1e-5.
//! let t = SphericalTriangle::<f64>::new(
//!     Vec3::new(1.0, 0.1, 0.0),
//!     Vec3::new(0.2, 1.0, 0.1),
//!     Vec3::new(0.0, 0.3, 1.0),
//! )?;
//! let advice = advise(&t)?;
//! assert_eq!(advice.choose(1e-5), Some(Evaluation::RobustF32));
//! // A nearly hemispherical triangle (2π − 1e-6 sr): f32 arithmetic is
//! // not predicted to hold 1e-6; f32 output with f64 arithmetic is.
//! let (_, [a, b, c]) = hard_triangles().into_iter().find(|(n, _)| n == "hemi 2pi-1e-6").unwrap();
//! let hemi = advise(&SphericalTriangle::<f64>::new(a, b, c)?)?;
//! assert!(hemi.predicted(Evaluation::RobustF32) > 1e-6);
//! assert_eq!(hemi.choose(1e-6), Some(Evaluation::MixedF32));
//! # Ok::<(), areawarp::WarpError>(())
//! ```

mod kappa;
#[cfg(feature = "mpfr")]
pub mod measure;
mod mixed;

pub use mixed::Mixed;

use crate::error::WarpError;
use crate::harness::extremes::{extremes_grid, random_points};
use crate::real::Real;
use crate::shapes::{
    SphericalRectangle, SphericalRectangleVariant, SphericalTriangle, SphericalTriangleVariant,
};
use crate::vector::Vec3;
use crate::warp::{Warp, WarpFamily};
use kappa::Format;

/// A way to evaluate a light shape: a variant in a scalar type, or the
/// mixed mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Evaluation {
    /// The robust map in `f32` (constants rounded from `f64`).
    RobustF32,
    /// `f32` inputs and outputs, the robust map evaluated in `f64`
    /// ([`Mixed`]).
    MixedF32,
    /// The robust map in `f64`.
    RobustF64,
    /// The published algorithm in `f32`.
    LiteralF32,
    /// The published algorithm in `f64`.
    LiteralF64,
}

impl Evaluation {
    /// Every evaluation, the robust ones from the cheapest per sample to the
    /// dearest (the order [`Advice::choose`] tries them in), then the literal
    /// ones.
    pub const ALL: [Evaluation; 5] = [
        Evaluation::RobustF32,
        Evaluation::MixedF32,
        Evaluation::RobustF64,
        Evaluation::LiteralF32,
        Evaluation::LiteralF64,
    ];

    /// `f32 robust`, `f32 mixed`, `f64 robust`, `f32 literal`, `f64 literal`.
    pub fn label(&self) -> &'static str {
        match self {
            Evaluation::RobustF32 => "f32 robust",
            Evaluation::MixedF32 => "f32 mixed",
            Evaluation::RobustF64 => "f64 robust",
            Evaluation::LiteralF32 => "f32 literal",
            Evaluation::LiteralF64 => "f64 literal",
        }
    }

    /// `true` for the robust evaluations (including the mixed mode).
    pub fn is_robust(&self) -> bool {
        matches!(
            self,
            Evaluation::RobustF32 | Evaluation::MixedF32 | Evaluation::RobustF64
        )
    }

    /// `true` if the output is `f32`.
    pub fn outputs_f32(&self) -> bool {
        matches!(
            self,
            Evaluation::RobustF32 | Evaluation::MixedF32 | Evaluation::LiteralF32
        )
    }
}

impl core::fmt::Display for Evaluation {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.label())
    }
}

/// One evaluation's predicted worst error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prediction {
    /// The evaluation.
    pub evaluation: Evaluation,
    /// Its predicted worst error over `[0, 1]²`: max-norm distance of the
    /// returned direction to the exact map of the same inputs (the shape
    /// rounded to the input type); `∞` when it may return NaN.
    pub worst_error: f64,
}

/// The outcome of [`advise`]: the shape's conditioning and the predicted
/// worst error of every [`Evaluation`].
#[derive(Clone, Debug, PartialEq)]
pub struct Advice {
    /// κ for `f32` inputs: the largest move of the exact map under a
    /// one-`f32`-ulp change of one input, over the probes.
    pub kappa_f32: f64,
    /// κ for `f64` inputs.
    pub kappa_f64: f64,
    /// κ for `f64` perturbations of the shape rounded to `f32` (the mixed
    /// mode's arithmetic).
    pub kappa_mixed: f64,
    /// The predictions, in [`Evaluation::ALL`] order.
    pub predictions: Vec<Prediction>,
}

impl Advice {
    /// The predicted worst error of `e`.
    pub fn predicted(&self, e: Evaluation) -> f64 {
        self.predictions
            .iter()
            .find(|p| p.evaluation == e)
            .map_or(f64::INFINITY, |p| p.worst_error)
    }

    /// The cheapest robust evaluation whose predicted worst error is at most
    /// `tolerance` (in the order of [`Evaluation::ALL`]: `f32`, mixed,
    /// `f64`); `None` if not even `f64` meets it.
    pub fn choose(&self, tolerance: f64) -> Option<Evaluation> {
        Evaluation::ALL
            .into_iter()
            .filter(Evaluation::is_robust)
            .find(|&e| self.predicted(e) <= tolerance)
    }

    /// [`Advice::choose`] among the evaluations with `f32` output.
    pub fn choose_f32_output(&self, tolerance: f64) -> Option<Evaluation> {
        self.choose(tolerance).filter(Evaluation::outputs_f32)
    }
}

/// A light shape [`advise`] can judge: rebuilt from its `f64` parameters in
/// any scalar type and variant.
pub trait Advisable: WarpFamily<f64, Point = Vec3<f64>> + Sized {
    /// The same shape in scalar `S`.
    type In<S: Real>: Warp<S, Point = Vec3<S>> + Clone;
    /// The shape's parameters as given (vertex directions, or corner,
    /// edges and observer).
    fn parameters(&self) -> Vec<f64>;
    /// The shape of parameters `p` in `S`, robust or literal; `input_bits`
    /// is the precision the parameters were given in (the rectangle's
    /// perpendicularity tolerance).
    fn build<S: Real>(p: &[S], literal: bool, input_bits: u32) -> Result<Self::In<S>, WarpError>;
    /// ψ⁻¹ without the on-shape test.
    fn inverse_unchecked<S: Real>(w: &Self::In<S>, p: &Vec3<S>) -> Option<(S, S)>;
    /// The largest error the literal algorithm makes by design (not by
    /// rounding) on the shape of parameters `p` in `arithmetic_bits` (24 or
    /// 53): a cut-off that replaces a computed value near a singularity by
    /// a limit; 2 if it can jump across the shape. 0 by default.
    fn literal_cutoff_error(p: &[f64], arithmetic_bits: u32) -> f64 {
        let _ = (p, arithmetic_bits);
        0.0
    }
    /// The numbers an evaluation in `arithmetic_bits` (24 or 53) rounds
    /// when it builds the shape of parameters `p` (given with `input_bits`
    /// of precision), and by how much: what κ of the evaluation perturbs.
    /// By default the parameters themselves, each by one ulp.
    ///
    /// # Errors
    /// [`WarpError`] if the shape of `p` cannot be built in `f64`.
    fn rounding_model(
        p: &[f64],
        arithmetic_bits: u32,
        input_bits: u32,
    ) -> Result<RoundingModel, WarpError> {
        let _ = (arithmetic_bits, input_bits);
        Ok(RoundingModel {
            params: p.to_vec(),
            steps: vec![Step::Ulp; p.len()],
            local_frame: false,
        })
    }
}

/// How one number of a [`RoundingModel`] is perturbed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    /// By one ulp of the evaluation's arithmetic.
    Ulp,
    /// By this absolute amount (the rounding error of a computed quantity,
    /// e.g. a coordinate of a difference rounded with the difference's
    /// magnitude).
    Absolute(f64),
    /// Not perturbed (exact: a zero coordinate of a canonical frame).
    Fixed,
}

/// The parameters (of [`Advisable::build`]) whose roundings model what an
/// evaluation's constructor rounds, and the size of each rounding.
#[derive(Clone, Debug, PartialEq)]
pub struct RoundingModel {
    /// Parameters of the same shape, possibly moved to a canonical frame.
    pub params: Vec<f64>,
    /// One step per parameter.
    pub steps: Vec<Step>,
    /// `true` if `params` place the shape in a local frame (rotated and
    /// translated): moves are then measured in the Euclidean norm, which
    /// bounds the max norm in any frame.
    pub local_frame: bool,
}

fn v3<S: Real>(p: &[S], i: usize) -> Vec3<S> {
    Vec3::new(p[i].clone(), p[i + 1].clone(), p[i + 2].clone())
}

fn flat(vs: &[&Vec3<f64>]) -> Vec<f64> {
    vs.iter().flat_map(|v| [v.x, v.y, v.z]).collect()
}

impl Advisable for SphericalTriangle<f64> {
    type In<S: Real> = SphericalTriangle<S>;
    /// The three vertex directions as given (9 numbers).
    fn parameters(&self) -> Vec<f64> {
        let [a, b, c] = self.vertex_inputs();
        flat(&[a, b, c])
    }
    fn build<S: Real>(p: &[S], literal: bool, _: u32) -> Result<SphericalTriangle<S>, WarpError> {
        let variant = if literal {
            SphericalTriangleVariant::Literal
        } else {
            SphericalTriangleVariant::Robust
        };
        SphericalTriangle::new_with(v3(p, 0), v3(p, 3), v3(p, 6), variant)
    }
    fn inverse_unchecked<S: Real>(w: &SphericalTriangle<S>, p: &Vec3<S>) -> Option<(S, S)> {
        w.inverse_unchecked(p)
    }
}

impl Advisable for SphericalRectangle<f64> {
    type In<S: Real> = SphericalRectangle<S>;
    /// Corner, edges (as given) and observer (12 numbers).
    fn parameters(&self) -> Vec<f64> {
        let [s, ex, ey, o] = self.inputs();
        flat(&[s, ex, ey, o])
    }
    fn build<S: Real>(
        p: &[S],
        literal: bool,
        input_bits: u32,
    ) -> Result<SphericalRectangle<S>, WarpError> {
        let variant = if literal {
            SphericalRectangleVariant::Literal
        } else {
            SphericalRectangleVariant::Robust
        };
        SphericalRectangle::with_input_precision(
            v3(p, 0),
            v3(p, 3),
            v3(p, 6),
            v3(p, 9),
            variant,
            input_bits,
        )
    }
    fn inverse_unchecked<S: Real>(w: &SphericalRectangle<S>, p: &Vec3<S>) -> Option<(S, S)> {
        w.inverse_unchecked(p)
    }
    /// The published algorithm replaces the row `y_v` by `y₁` wherever
    /// `h_v² ≥ 1 − ε` (`ε = 10⁻⁶`, "to avoid NaNs"): every direction within
    /// `φ_c = asin √ε` of `±ŷ` in its column's plane goes to the top edge.
    /// The bound is derived in `docs/precision-choice.md`.
    fn literal_cutoff_error(p: &[f64], arithmetic_bits: u32) -> f64 {
        let Ok(r) = Self::build(p, false, arithmetic_bits.min(53)) else {
            return 0.0;
        };
        let ([x0, y0, h, lx, ly], _) = r.local_coordinates();
        let u = 2f64.powi(-(arithmetic_bits as i32));
        literal_cutoff_error(x0, x0 + lx, y0, y0 + ly, h, 1e-6 + 16.0 * u)
    }
    /// The rectangle in its local frame, the numbers its robust map
    /// computes from: corner `(x₀, y₀, −h)`, edges `(ℓx, 0, 0)`, `(0, ℓy,
    /// 0)`, observer at the origin (scaled by a power of two). The
    /// constructor computes them in `f64` from `d = s − o` (each coordinate
    /// rounded relative to itself, exact for nearby s and o) by dot products
    /// with the frame (for an `f32` shape, with the edges, divided by their
    /// lengths: errors of the same size): `x₀`, `y₀`, `h` carry absolute errors of about one
    /// `f64` ulp of `|d|`; an `f32` shape rounds them, and the lengths, to
    /// `f32` (one `f32` ulp of each). Perturbing the world coordinates of `s`
    /// and `o` instead would count the rounding of `|s|` (a corner 50× as
    /// far from the origin as from the observer: 50× too much) and, for a
    /// grazing observer, an `f64` ulp of `o` that puts it exactly on the
    /// plane (rejected), although `h` crossing zero does not move the map
    /// unless the observer's foot is on the rectangle.
    fn rounding_model(
        p: &[f64],
        arithmetic_bits: u32,
        input_bits: u32,
    ) -> Result<RoundingModel, WarpError> {
        let r = Self::build(p, false, input_bits)?;
        let ([x0, y0, h, lx, ly], e) = r.local_coordinates();
        let ulp = |x: f64| {
            if arithmetic_bits == 24 {
                let y = (x.abs() as f32).max(f32::MIN_POSITIVE);
                f64::from(y.next_up()) - f64::from(y)
            } else {
                x.abs().next_up() - x.abs()
            }
        };
        // The f64 constructor computes a local coordinate as d·ê (d = s − o
        // rounded coordinate-wise, ê a unit vector of the rounded frame):
        // its rounding scales with 2⁻⁵³·Σ|dᵢ|·(|êᵢ| + the rounding of
        // êᵢ). The step is one ulp of |d|, or twice that sum where it is
        // smaller (a frame aligned with the axes, where only the coordinate
        // itself is rounded).
        let [s, ex, ey, o] = [0, 3, 6, 9].map(|i| v3(p, i));
        let xhat = ex.scale(&(1.0 / ex.norm()));
        let ey_perp = ey.sub(&xhat.scale(&ey.dot(&xhat)));
        let yhat = ey_perp.scale(&(1.0 / ey_perp.norm()));
        let zhat = xhat.cross(&yhat);
        let d = s.sub(&o);
        let [da, xa, ya, za] = [&d, &xhat, &yhat, &zhat].map(|v| [v.x.abs(), v.y.abs(), v.z.abs()]);
        // ẑ = x̂ × ŷ: each component a difference of two products.
        let z_round = [
            xa[1] * ya[2] + xa[2] * ya[1],
            xa[2] * ya[0] + xa[0] * ya[2],
            xa[0] * ya[1] + xa[1] * ya[0],
        ];
        let scale = 2f64.powi(-e);
        let f64_error = |w: [f64; 3]| U64 * scale * (0..3).map(|i| da[i] * w[i]).sum::<f64>();
        let ex_err = f64_error(xa.map(|x| 2.0 * x));
        let ey_err = f64_error(ya.map(|y| 2.0 * y));
        let h_err = f64_error([0, 1, 2].map(|i| 2.0 * (za[i] + z_round[i])));
        let ulp_d = {
            let d = (x0 * x0 + y0 * y0 + h * h).sqrt();
            d.next_up() - d
        };
        let offset = |x: f64, err: f64| Step::Absolute(ulp(x).max(err.min(ulp_d)));
        let length = |x: f64| Step::Absolute(ulp(x));
        Ok(RoundingModel {
            params: vec![x0, y0, -h, lx, 0.0, 0.0, 0.0, ly, 0.0, 0.0, 0.0, 0.0],
            steps: vec![
                offset(x0, ex_err),
                offset(y0, ey_err),
                offset(h, h_err),
                length(lx),
                Step::Fixed,
                Step::Fixed,
                Step::Fixed,
                length(ly),
                Step::Fixed,
                Step::Fixed,
                Step::Fixed,
                Step::Fixed,
            ],
            local_frame: true,
        })
    }
}

/// The largest error of the rectangle's published cut-off `h_v² ≥ 1 − ε ⇒
/// y_v = y₁` on the rectangle `[x₀, x₁] × [y₀, y₁]` at `z = −h`: in the
/// plane of the column at distance `d = √(x² + h²)` a row `y` is seen at the
/// angle `θ(y) = atan2(d, y)` from `ŷ`, and the cut-off moves every row with
/// `|y| ≥ d cot φ_c` (`tan φ_c = √(ε/(1 − ε))`) to `y₁`: an error
/// `θ(y) − θ(y₁)` (≥ the chord, ≥ the max norm). Rows near `+ŷ`: largest at
/// `y = max(y₀, d cot φ_c)`, over the columns at `d* = y₀ tan φ_c` (below,
/// `atan(d/y₀) − atan(d/y₁)` grows with `d`; above, `φ_c − atan(d/y₁)`
/// falls) clamped to `[d_min, d_max]`. Rows near `−ŷ` (possible only if
/// `−y₀ ≥ d_min cot φ_c`) jump to `y₁`: across the rectangle (2, no digit)
/// if `y₁ ≥ 0`, else by `θ(y₀) − θ(y₁)`, largest at `d = min(−y₀ tan φ_c,
/// d_max)`. `ε` includes the rounding of `h_v²`.
fn literal_cutoff_error(x0: f64, x1: f64, y0: f64, y1: f64, h: f64, eps: f64) -> f64 {
    let t = (eps / (1.0 - eps)).sqrt();
    let d_min = 0f64.clamp(x0, x1).hypot(h);
    let d_max = x0.abs().max(x1.abs()).hypot(h);
    let theta = |y: f64, d: f64| d.atan2(y);
    let mut err = 0.0f64;
    if y1 > 0.0 {
        let d = if y0 > 0.0 {
            (y0 * t).clamp(d_min, d_max)
        } else {
            d_min
        };
        let lo = y0.max(d / t);
        if lo <= y1 {
            err = err.max(theta(lo, d) - theta(y1, d));
        }
    }
    if y0 < 0.0 && -y0 >= d_min / t {
        if y1 >= 0.0 {
            return 2.0;
        }
        let d = (-y0 * t).min(d_max);
        err = err.max(theta(y0, d) - theta(y1, d));
    }
    // Rounding of the angles: a relative 2⁻⁴⁰.
    err * (1.0 + 1e-12)
}

/// The probes of [`advise`]: the extremes grid and 16 random points.
pub fn probes() -> Vec<(f64, f64)> {
    let mut p = extremes_grid();
    p.extend(random_points(16, 0x5eed));
    p
}

/// The literal maps' probes: the extremes grid, the 17 × 17 grid and 256
/// random points (their NaN and their worst errors sit wherever their
/// cancellations strike, not where the conditioning points).
fn literal_probes() -> Vec<(f64, f64)> {
    let mut p = extremes_grid();
    p.extend(crate::harness::extremes::uniform_grid(17));
    p.extend(random_points(256, 0x11e7));
    p
}

/// The factor of the accuracy criterion `error ≤ 16·max(u, κ)`.
const FACTOR: f64 = 16.0;
/// The `f64` perturbations of κ₆₄ are `2^K` ulps.
const K: i32 = 16;
/// `2⁻²⁴` and `2⁻⁵³`.
const U32: f64 = 5.960464477539063e-8;
const U64: f64 = 1.1102230246251565e-16;

/// Predicts the worst error of every [`Evaluation`] of the light `w` (see
/// the [module documentation](self)).
///
/// A shape whose `f32`-rounded parameters `f32` rejects (e.g. an observer
/// 1e-90 above the plane, which rounds to 0) gets `∞` for the `f32` and
/// mixed evaluations.
///
/// # Errors
/// [`WarpError`] if the shape cannot be rebuilt in `f64` from its
/// parameters, or if the map is not finite at a probe.
pub fn advise<W: Advisable>(w: &W) -> Result<Advice, WarpError> {
    let params = w.parameters();
    let probes = probes();
    let rounded: Vec<f64> = params.iter().map(|&x| f64::from(x as f32)).collect();
    let kappa_f64 = kappa::evaluation_kappa::<W>(&params, &probes, Format::F64)?;
    // A shape that f32 cannot hold (rounded to f32, it is degenerate or out
    // of range): no f32 evaluation, predicted error ∞.
    let kappa_f32 =
        kappa::evaluation_kappa::<W>(&rounded, &probes, Format::F32).unwrap_or(f64::INFINITY);
    let kappa_mixed = kappa::evaluation_kappa::<W>(&rounded, &probes, Format::F64InputsF32)
        .unwrap_or(f64::INFINITY);
    let dense = literal_probes();
    let literal_f32 = literal_error::<W, f32>(&params, &dense);
    let literal_f64 = literal_error::<W, f64>(&params, &dense);
    let cutoff_f32 = W::literal_cutoff_error(&rounded, 24);
    let cutoff_f64 = W::literal_cutoff_error(&params, 53);
    let predictions = Evaluation::ALL
        .into_iter()
        .map(|evaluation| Prediction {
            evaluation,
            worst_error: match evaluation {
                Evaluation::RobustF32 => no_digits(FACTOR * U32.max(kappa_f32)),
                Evaluation::MixedF32 => no_digits(U32 + FACTOR * U64.max(kappa_mixed)),
                Evaluation::RobustF64 => no_digits(FACTOR * U64.max(kappa_f64)),
                Evaluation::LiteralF32 => {
                    4.0 * literal_f32 + FACTOR * U32.max(kappa_f32) + cutoff_f32
                }
                Evaluation::LiteralF64 => {
                    4.0 * literal_f64 + FACTOR * U64.max(kappa_f64) + cutoff_f64
                }
            },
        })
        .collect();
    Ok(Advice {
        kappa_f32,
        kappa_f64,
        kappa_mixed,
        predictions,
    })
}

/// A bound of 1/4 or more on the distance between two unit vectors says
/// that no digit is left: the bound is then 2, the largest distance (max
/// norm) two unit vectors can have. (κ measured by one-ulp moves saturates
/// where the map is that ill-conditioned, and no longer bounds the error.)
fn no_digits(bound: f64) -> f64 {
    if bound >= 0.25 { 2.0 } else { bound }
}

/// The literal map's largest error at the probes, in `S` on the parameters
/// rounded to `S`, against the robust `f64` map of the same rounded
/// parameters; `∞` if it is not finite at a probe (or `S` rejects the
/// shape).
fn literal_error<W: Advisable, S: Real>(params: &[f64], probes: &[(f64, f64)]) -> f64 {
    let ps: Vec<S> = params.iter().map(|&x| S::from_f64(x)).collect();
    let pr: Vec<f64> = ps.iter().map(Real::to_f64).collect();
    let bits = S::precision();
    let (Ok(lit), Ok(exact)) = (W::build(&ps, true, bits), W::build(&pr, false, bits)) else {
        return f64::INFINITY;
    };
    let mut worst = 0.0f64;
    for &(u, v) in probes {
        let (us, vs) = (S::from_f64(u), S::from_f64(v));
        let p = lit.map(&us, &vs);
        if !p.is_finite() {
            return f64::INFINITY;
        }
        let q = exact.map(&us.to_f64(), &vs.to_f64());
        let p: Vec3<f64> = Vec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64());
        worst = worst.max(p.sub(&q).max_abs());
    }
    worst
}

#[cfg(test)]
mod tests;
