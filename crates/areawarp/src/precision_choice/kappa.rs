//! κ of an evaluation: how far the exact map moves under the perturbations
//! the evaluation itself makes (its constructor's roundings, modelled by a
//! [`RoundingModel`], and the rounding of `ũ = min(u, 1 − u)`, `ṽ`).

use super::{Advisable, K, Step};
use crate::error::WarpError;
use crate::vector::Vec3;
use crate::warp::Warp;

/// Whose roundoff the perturbations of [`evaluation_kappa`] are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Format {
    /// `f32` data and arithmetic: one-`f32`-ulp steps.
    F32,
    /// `f64` data and arithmetic: `2^K`-ulp steps, divided by `2^K`.
    F64,
    /// `f32` data (the perpendicularity tolerance of `f32` input), `f64`
    /// arithmetic: `f64` steps.
    F64InputsF32,
}

impl Format {
    /// The precision of the arithmetic (24 or 53 bits).
    pub(super) fn bits(self) -> u32 {
        match self {
            Format::F32 => 24,
            Format::F64 | Format::F64InputsF32 => 53,
        }
    }
    /// The parameter `x` moved up or down by `ulps` ulps of the format.
    pub(super) fn neighbour(self, x: f64, up: bool, ulps: f64) -> f64 {
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
    pub(super) fn ulp(self, x: f64) -> f64 {
        match self {
            Format::F32 => {
                let y = x as f32;
                f64::from(y.next_up()) - f64::from(y)
            }
            Format::F64 | Format::F64InputsF32 => x.next_up() - x,
        }
    }
}

/// The parameter `x` moved by `n` steps (`n` ulps of the format, or `n`
/// times an absolute step) up or down.
fn moved(format: Format, step: &Step, x: f64, up: bool, n: f64) -> f64 {
    match step {
        Step::Ulp => format.neighbour(x, up, n),
        Step::Absolute(d) => {
            if up {
                x + n * d
            } else {
                x - n * d
            }
        }
        Step::Fixed => x,
    }
}

/// κ of the evaluation at the probes: the largest move of the robust map
/// (evaluated in `f64`) under one rounding, in `format`, of one number of
/// the evaluation's [`RoundingModel`], or of `ũ = min(u, 1 − u)` or
/// `ṽ = min(v, 1 − v)`.
///
/// In `f64` a number is moved by `n = 2^K` steps (fewer if that would take
/// it across zero, or more than half-way to it) and the move divided by
/// `n`: the linearization, free of the map's own rounding noise; and by
/// one step: far above the linearization (> 4×), the map is not linear at
/// the scale of one step (an observer one ulp above the plane) and the
/// one-step move is κ.
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
pub(super) fn evaluation_kappa<W: Advisable>(
    params: &[f64],
    probes: &[(f64, f64)],
    format: Format,
) -> Result<f64, WarpError> {
    // Steps of 2^16 f64 ulps exceed a perpendicularity tolerance of 64
    // ulps: the perturbed rectangles are built with 2^(−(53 − 16)) slack.
    let bits = if format == Format::F64 {
        53 - K as u32
    } else {
        24
    };
    let model = W::rounding_model(params, format.bits(), bits)?;
    let params = &model.params[..];
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
    // A move: max norm in the shape's own frame, or the Euclidean norm in a
    // local frame (which bounds the max norm after any rotation).
    let distance = |p: &Vec3<f64>, q: &Vec3<f64>| {
        let d = p.sub(q);
        if model.local_frame {
            d.dot(&d).sqrt()
        } else {
            d.max_abs()
        }
    };
    let mut kappa = 0.0f64;
    let mut perturbed = params.to_vec();
    let (mut linear, mut one_step) = (0.0f64, 0.0f64);
    for (i, step) in model.steps.iter().enumerate() {
        if *step == Step::Fixed {
            continue;
        }
        let x = params[i];
        // The linearization's number of steps: 2^K, fewer for an absolute
        // step that would take x more than half-way to zero.
        let many = if format == Format::F32 {
            None
        } else {
            let mut n = 2f64.powi(K);
            if let Step::Absolute(d) = step {
                while n > 1.0 && n * d > x.abs() / 2.0 {
                    n /= 2.0;
                }
            }
            Some(n)
        };
        for ulps in many.into_iter().chain([1.0]) {
            for up in [true, false] {
                perturbed[i] = moved(format, step, x, up, ulps);
                let mut built = W::build(&perturbed, false, bits);
                // One step from a shape the constructor rejects (an
                // observer one ulp off the plane): the move to the shape
                // two or four steps away, on the far side, counts as a
                // one-step move; if those are rejected too, no digit can be
                // promised.
                let mut far = ulps;
                while built.is_err() && ulps == 1.0 && far < 4.0 {
                    far *= 2.0;
                    perturbed[i] = moved(format, step, x, up, far);
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
                        let m = distance(&p, &reference[k]);
                        if ulps == 1.0 && many.is_some() {
                            one_step = one_step.max(m);
                        } else {
                            linear = linear.max(m / ulps);
                        }
                    }
                }
            }
        }
    }
    kappa = kappa.max(if one_step > 4.0 * linear {
        one_step
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
                let slope = distance(&p, &reference[k]) / dh;
                kappa = kappa.max(slope * format.ulp(tilde));
            }
        }
    }
    Ok(kappa)
}
