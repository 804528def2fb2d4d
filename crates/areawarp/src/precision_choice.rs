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
//! | [`Evaluation::LiteralF32`], [`Evaluation::LiteralF64`] | `4·e + 16·max(u, κ)`, `e` the literal map's error observed at the probes against the robust `f64` map; `∞` if it is NaN at a probe |
//!
//! The robust maps are as accurate as their inputs allow — within
//! `16·max(u, κ)` of the exact map, measured against 256 bits on the hard
//! ladders and on random shapes — so their prediction is an upper bound by
//! construction, and not a loose one: they stay within 0.04–0.25 of it. The
//! papers' literal algorithms have no such bound (their cancellations are
//! not the shape's), so theirs is measured at the probes and kept for
//! comparison; [`Advice::choose`] never picks them.
//!
//! κ₃₂ is measured by one-`f32`-ulp perturbations evaluated with the robust
//! `f64` map (the definition of κ, evaluated `2²⁹` times more precisely
//! than the effect it measures); κ₆₄ by perturbations of `2¹⁶` `f64` ulps,
//! divided by `2¹⁶` (a linearization whose rounding noise is `2⁻¹⁶` of the
//! map's own error). The probes are the extremes grid (`u, v ∈ {0, 2⁻⁶⁰,
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
    let kappa_f64 = evaluation_kappa::<W>(&params, &probes, Format::F64)?;
    // A shape that f32 cannot hold (rounded to f32, it is degenerate or out
    // of range): no f32 evaluation, predicted error ∞.
    let kappa_f32 = evaluation_kappa::<W>(&rounded, &probes, Format::F32).unwrap_or(f64::INFINITY);
    let kappa_mixed =
        evaluation_kappa::<W>(&rounded, &probes, Format::F64InputsF32).unwrap_or(f64::INFINITY);
    let dense = literal_probes();
    let literal_f32 = literal_error::<W, f32>(&params, &dense);
    let literal_f64 = literal_error::<W, f64>(&params, &dense);
    let predictions = Evaluation::ALL
        .into_iter()
        .map(|evaluation| Prediction {
            evaluation,
            worst_error: match evaluation {
                Evaluation::RobustF32 => no_digits(FACTOR * U32.max(kappa_f32)),
                Evaluation::MixedF32 => no_digits(U32 + FACTOR * U64.max(kappa_mixed)),
                Evaluation::RobustF64 => no_digits(FACTOR * U64.max(kappa_f64)),
                Evaluation::LiteralF32 => 4.0 * literal_f32 + FACTOR * U32.max(kappa_f32),
                Evaluation::LiteralF64 => 4.0 * literal_f64 + FACTOR * U64.max(kappa_f64),
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

/// Whose roundoff the perturbations of [`evaluation_kappa`] are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    /// `f32` data and arithmetic: one-`f32`-ulp steps.
    F32,
    /// `f64` data and arithmetic: `2^K`-ulp steps, divided by `2^K`.
    F64,
    /// `f32` data (the perpendicularity tolerance of `f32` input), `f64`
    /// arithmetic: `f64` steps.
    F64InputsF32,
}

impl Format {
    /// The input precision the shapes are built with.
    fn input_bits(self) -> u32 {
        match self {
            Format::F32 | Format::F64InputsF32 => 24,
            Format::F64 => 53,
        }
    }
    /// The parameter `x` moved up or down by `ulps` ulps of the format.
    fn neighbour(self, x: f64, up: bool, ulps: f64) -> f64 {
        match self {
            Format::F32 => {
                let mut y = x as f32;
                for _ in 0..(ulps as u32).max(1) {
                    y = if up { y.next_up() } else { y.next_down() };
                }
                f64::from(y)
            }
            Format::F64 | Format::F64InputsF32 => {
                let ulp = if up {
                    x.next_up() - x
                } else {
                    x - x.next_down()
                };
                if up { x + ulp * ulps } else { x - ulp * ulps }
            }
        }
    }
    /// One ulp of `x ≥ 0` in this format's arithmetic (upwards).
    fn ulp(self, x: f64) -> f64 {
        match self {
            Format::F32 => {
                let y = x as f32;
                f64::from(y.next_up()) - f64::from(y)
            }
            Format::F64 | Format::F64InputsF32 => x.next_up() - x,
        }
    }
}

/// κ of the evaluation at the probes: the largest move of the robust map
/// (evaluated in `f64`) under a one-ulp change, in `format`, of one
/// parameter, or of `ũ = min(u, 1 − u)` or `ṽ = min(v, 1 − v)`.
///
/// Unlike the harness's κ
/// ([`sensitivities_in`](crate::harness::sensitivity::sensitivities_in)),
/// which moves `u` by one
/// ulp of `u`, the sample coordinates are perturbed relative to the nearer
/// end of `[0, 1]`: the robust maps compute from `1 − u` for `u > 1/2`
/// (exactly, by Sterbenz's lemma), so near `u = 1` their rounding errors
/// are those of `1 − u`, not of `u`. Near the degenerate corners of a
/// nearly hemispherical triangle the map moves by O(1) under one ulp of
/// `u` ≈ 1, which the evaluation never does. `ũ`'s part is the derivative
/// (a one-sided difference of step `max(ũ/4096, 256 ulp(u))` towards the
/// interior) times one ulp of `ũ`.
fn evaluation_kappa<W: Advisable>(
    params: &[f64],
    probes: &[(f64, f64)],
    format: Format,
) -> Result<f64, WarpError> {
    let scale = if format == Format::F32 {
        1.0
    } else {
        2f64.powi(K)
    };
    // Steps of 2^16 f64 ulps exceed a perpendicularity tolerance of 64
    // ulps: the perturbed rectangles are built with 2^(−(53 − 16)) slack.
    let bits = if format == Format::F32 {
        24
    } else {
        format.input_bits().min(53 - K as u32)
    };
    let base = W::build(params, false, bits)?;
    let inputs: Vec<(f64, f64)> = probes
        .iter()
        .map(|&(u, v)| match format {
            Format::F32 | Format::F64InputsF32 => (f64::from(u as f32), f64::from(v as f32)),
            Format::F64 => (u, v),
        })
        .collect();
    let reference: Vec<Vec3<f64>> = inputs.iter().map(|(u, v)| base.map(u, v)).collect();
    if reference.iter().any(|p| !p.is_finite()) {
        return Err(WarpError::NonFinite {
            what: "map at a probe",
        });
    }
    let mut kappa = 0.0f64;
    // Parameters: one rebuilt shape per perturbation. In f64, steps of
    // 2^K ulps divided by 2^K (the linearization, free of the map's own
    // rounding noise), and of one ulp: far above the linearization (> 4×),
    // the map is not linear at the scale of one ulp (an observer one ulp
    // above the plane) and the one-ulp move is κ.
    let mut perturbed = params.to_vec();
    let (mut linear, mut one_ulp) = (0.0f64, 0.0f64);
    let steps: &[f64] = if format == Format::F32 {
        &[1.0]
    } else {
        &[2f64.powi(K), 1.0]
    };
    for i in 0..params.len() {
        let x = params[i];
        for &ulps in steps {
            for up in [true, false] {
                perturbed[i] = format.neighbour(x, up, ulps);
                let mut built = W::build(&perturbed, false, bits);
                // One ulp from a shape the constructor rejects (an observer
                // one ulp off the plane): the move to the shape two or four
                // ulps away, on the far side, counts as a one-ulp move; if
                // those are rejected too, no digit can be promised.
                let mut far = ulps;
                while built.is_err() && ulps == 1.0 && far < 4.0 {
                    far *= 2.0;
                    perturbed[i] = format.neighbour(x, up, far);
                    built = W::build(&perturbed, false, bits);
                }
                perturbed[i] = x;
                let Ok(w) = built else {
                    if ulps == 1.0 {
                        return Ok(f64::INFINITY);
                    }
                    continue;
                };
                for (k, (u, v)) in inputs.iter().enumerate() {
                    let p = w.map(u, v);
                    if p.is_finite() {
                        let m = p.sub(&reference[k]).max_abs();
                        if ulps == 1.0 && scale > 1.0 {
                            one_ulp = one_ulp.max(m);
                        } else {
                            linear = linear.max(m / scale);
                        }
                    }
                }
            }
        }
    }
    kappa = kappa.max(if one_ulp > 4.0 * linear {
        one_ulp
    } else {
        linear
    });
    // ũ and ṽ: derivative towards the interior times one ulp of ũ.
    for (k, &(u, v)) in inputs.iter().enumerate() {
        for along_u in [true, false] {
            let x = if along_u { u } else { v };
            let tilde = x.min(1.0 - x);
            if tilde <= 0.0 {
                continue;
            }
            let h = (tilde / 4096.0).max(256.0 * (x.next_up() - x));
            let moved = if x <= 0.5 { x + h } else { x - h };
            let dh = (moved - x).abs();
            let p = if along_u {
                base.map(&moved, &v)
            } else {
                base.map(&u, &moved)
            };
            if p.is_finite() && dh > 0.0 {
                let slope = p.sub(&reference[k]).max_abs() / dh;
                kappa = kappa.max(slope * format.ulp(tilde));
            }
        }
    }
    Ok(kappa)
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
