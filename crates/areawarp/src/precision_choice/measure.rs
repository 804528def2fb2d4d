//! Measured errors against 256 bits (feature `mpfr`): what the predictions
//! of [`advise`](super::advise) are checked against, and the audit of the
//! `f32` constructors, maps and inverses of issue 13.

use super::{Advisable, Evaluation, FACTOR, Mixed, U32};
use crate::error::WarpError;
use crate::harness::sensitivity::{InputFormat, sensitivities_in};
use crate::real::{Mpfr256, Real, convert};
use crate::vector::Vec3;
use crate::warp::Warp;

type M = Mpfr256;

/// One evaluation's measured worst error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// The evaluation.
    pub evaluation: Evaluation,
    /// `false` if its constructor rejected the shape.
    pub accepted: bool,
    /// The largest max-norm distance to the exact map (256 bits) of the
    /// same inputs over the points; `∞` if a point was NaN or infinite.
    pub worst_error: f64,
}

fn params_f32(params: &[f64]) -> Vec<f64> {
    params.iter().map(|&x| f64::from(x as f32)).collect()
}

fn to_m<S: Real>(p: &Vec3<S>) -> Vec3<M> {
    p.convert()
}

/// The worst error of `w`'s map in `S` (robust or literal) at `points`
/// against `exact`.
fn worst<S: Real, WS: Warp<S, Point = Vec3<S>>>(
    ws: &WS,
    exact: &impl Warp<M, Point = Vec3<M>>,
    points: &[(f64, f64)],
) -> f64 {
    let mut worst = 0.0f64;
    for &(u, v) in points {
        let (us, vs) = (S::from_f64(u), S::from_f64(v));
        let p = ws.map(&us, &vs);
        if !p.is_finite() {
            return f64::INFINITY;
        }
        let q = exact.map(&convert(&us), &convert(&vs));
        worst = worst.max(to_m(&p).sub(&q).max_abs().to_f64());
    }
    worst
}

/// The measured worst error of every [`Evaluation`] of `w` at `points`,
/// against the exact map at 256 bits of the inputs as each evaluation sees
/// them (`f32`-rounded parameters and `(u, v)` for the `f32` ones).
///
/// # Errors
/// [`WarpError`] if the exact shape cannot be built at 256 bits.
pub fn measure<W: Advisable>(w: &W, points: &[(f64, f64)]) -> Result<Vec<Measured>, WarpError> {
    let p64 = w.parameters();
    let p32 = params_f32(&p64);
    let exact64 = W::build::<M>(
        &p64.iter().map(|&x| M::from_f64(x)).collect::<Vec<_>>(),
        false,
        53,
    )?;
    // The shape rounded to f32 may be degenerate: then no f32 evaluation.
    let exact32 = W::build::<M>(
        &p32.iter().map(|&x| M::from_f64(x)).collect::<Vec<_>>(),
        false,
        24,
    );
    let f32s: Vec<f32> = p32.iter().map(|&x| x as f32).collect();
    let out = Evaluation::ALL
        .into_iter()
        .map(|evaluation| {
            let e = match evaluation {
                Evaluation::RobustF32 => exact32
                    .clone()
                    .and_then(|e| W::build(&f32s, false, 24).map(|w| worst(&w, &e, points))),
                Evaluation::LiteralF32 => exact32
                    .clone()
                    .and_then(|e| W::build(&f32s, true, 24).map(|w| worst(&w, &e, points))),
                Evaluation::MixedF32 => exact32.clone().and_then(|e| {
                    Mixed::<W>::from_f32_parameters(&p32).map(|w| worst(&w, &e, points))
                }),
                Evaluation::RobustF64 => {
                    W::build(&p64, false, 53).map(|w| worst(&w, &exact64, points))
                }
                Evaluation::LiteralF64 => {
                    W::build(&p64, true, 53).map(|w| worst(&w, &exact64, points))
                }
            };
            Measured {
                evaluation,
                accepted: e.is_ok(),
                worst_error: e.unwrap_or(f64::NAN),
            }
        })
        .collect();
    Ok(out)
}

/// The audit of one shape in `f32` (issue 13, items 1 and 2).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Audit {
    /// Whether `f64`, given the `f32`-rounded values (and told they are
    /// `f32` data), accepts the shape.
    pub f64_accepts: bool,
    /// Whether `f32` accepts it.
    pub f32_accepts: bool,
    /// The error `f32` gave, if it rejected the shape.
    pub f32_error: Option<WarpError>,
    /// Largest `error / (16·max(2⁻²⁴, κ₃₂))` of the robust `f32` map over
    /// the points, κ₃₂ at each point (one-`f32`-ulp perturbations of the
    /// parameters, `u` and `v`, evaluated in `f64`).
    pub map_ratio: f64,
    /// Largest error of the map (distance to the exact map).
    pub map_error: f64,
    /// Largest `error / max(10⁻⁶, 16·κ_inv)` of the robust `f32` inverse at
    /// the `f32` samples on the exact shape against the exact inverse (256
    /// bits) at the same direction, κ_inv the move of the exact inverse when one coordinate of
    /// the direction moves by one `f32` ulp of its largest coordinate (or,
    /// where that does not cover the error, when one parameter of the shape
    /// moves by one `f32` ulp).
    pub inverse_ratio: f64,
    /// Largest `(u, v)` error of the inverse.
    pub inverse_error: f64,
    /// Samples the `f32` inverse refused.
    pub inverse_refusals: usize,
    /// Samples whose `f32` rounding put them (just) off the exact shape:
    /// checked for refusal only (off the shape the exact inverse is not
    /// defined).
    pub off_exact_shape: usize,
    /// Samples not finite.
    pub non_finite: usize,
    /// Largest `outside_by` of a sample (by the `f32` shape itself), in
    /// units of `2⁻²⁴`.
    pub max_outside_ulps: f64,
}

/// Audits the robust `f32` evaluation of `w` at `points` (see [`Audit`]).
///
/// # Errors
/// [`WarpError`] if the exact shape cannot be built at 256 bits or κ
/// cannot be measured.
pub fn audit_f32<W: Advisable>(w: &W, points: &[(f64, f64)]) -> Result<Audit, WarpError> {
    let p32 = params_f32(&w.parameters());
    let f32s: Vec<f32> = p32.iter().map(|&x| x as f32).collect();
    let mut a = Audit {
        f64_accepts: W::build(&p32, false, 24).is_ok(),
        ..Audit::default()
    };
    let w32 = match W::build(&f32s, false, 24) {
        Ok(w) => w,
        Err(e) => {
            a.f32_error = Some(e);
            return Ok(a);
        }
    };
    a.f32_accepts = true;
    let exact = W::build::<M>(
        &p32.iter().map(|&x| M::from_f64(x)).collect::<Vec<_>>(),
        false,
        24,
    )?;
    let kappas = sensitivities_in::<f64, _, _>(
        |p: &[f64]| W::build(p, false, 24),
        &p32,
        points,
        InputFormat::F32,
    )?;
    let mut perturbed: Option<Vec<W::In<M>>> = None;
    for (&(u, v), s) in points.iter().zip(&kappas) {
        let (u32_, v32) = (u as f32, v as f32);
        let p = w32.map(&u32_, &v32);
        if !p.is_finite() {
            a.non_finite += 1;
            continue;
        }
        let (um, vm): (M, M) = (convert(&u32_), convert(&v32));
        let q = exact.map(&um, &vm);
        let err = to_m(&p).sub(&q).max_abs().to_f64();
        a.map_error = a.map_error.max(err);
        a.map_ratio = a.map_ratio.max(err / (FACTOR * U32.max(s.kappa)));
        a.max_outside_ulps = a.max_outside_ulps.max(f64::from(w32.outside_by(&p)) / U32);
        let Ok([ui, vi]) = w32.inverse(&p) else {
            a.inverse_refusals += 1;
            continue;
        };
        let pm = to_m(&p);
        let pn = pm.scale(&(M::one() / &pm.norm()));
        if exact.outside_by(&pn) > M::exp2i(-200) {
            // Off the exact shape the exact inverse is not defined (its
            // chart extrapolates); the f32 inverse projects onto the shape.
            a.off_exact_shape += 1;
            continue;
        }
        let Some((ue, ve)) = W::inverse_unchecked(&exact, &pm) else {
            continue;
        };
        let e = (M::from_f64(f64::from(ui)) - &ue)
            .abs()
            .max(&(M::from_f64(f64::from(vi)) - &ve).abs())
            .to_f64();
        let mut k = inverse_kappa::<W>(&exact, &p);
        if e > 1e-6f64.max(FACTOR * k) {
            // The move of the exact inverse at p when a parameter moves by
            // one f32 ulp (the f32 shape's own vertices are known to that):
            // built on demand, as only shapes smaller than a few f32 ulps
            // need it.
            let shapes = perturbed.get_or_insert_with(|| perturbed_shapes::<W>(&p32));
            for w in shapes.iter() {
                if let Some((a2, b2)) = W::inverse_unchecked(w, &pm) {
                    let m = (a2 - &ue).abs().max(&(b2 - &ve).abs()).to_f64();
                    k = k.max(m);
                }
            }
        }
        a.inverse_error = a.inverse_error.max(e);
        a.inverse_ratio = a.inverse_ratio.max(e / 1e-6f64.max(FACTOR * k));
    }
    Ok(a)
}

/// The exact shapes (256 bits) of the `f32` parameters `p32` with one
/// parameter moved by one `f32` ulp up or down.
fn perturbed_shapes<W: Advisable>(p32: &[f64]) -> Vec<W::In<M>> {
    let base: Vec<M> = p32.iter().map(|&x| M::from_f64(x)).collect();
    let mut out = Vec::new();
    for i in 0..p32.len() {
        let x = p32[i] as f32;
        for y in [x.next_up(), x.next_down()] {
            let mut p = base.clone();
            p[i] = M::from_f64(f64::from(y));
            if let Ok(w) = W::build(&p, false, 24) {
                out.push(w);
            }
        }
    }
    out
}

/// The move of the exact inverse (256 bits) when one coordinate of `p`
/// moves by one `f32` ulp of its largest coordinate.
fn inverse_kappa<W: Advisable>(exact: &W::In<M>, p: &Vec3<f32>) -> f64 {
    let c = [p.x, p.y, p.z];
    let widen = |c: [f32; 3]| -> Vec3<M> {
        Vec3::new(
            M::from_f64(f64::from(c[0])),
            M::from_f64(f64::from(c[1])),
            M::from_f64(f64::from(c[2])),
        )
    };
    let Some(base) = W::inverse_unchecked(exact, &widen(c)) else {
        return f64::INFINITY;
    };
    let m = c[0].abs().max(c[1].abs()).max(c[2].abs());
    let step = m.next_up() - m;
    let mut k = 0.0f64;
    for i in 0..3 {
        for x in [c[i] + step, c[i] - step] {
            let mut cc = c;
            cc[i] = x;
            if let Some((a, b)) = W::inverse_unchecked(exact, &widen(cc)) {
                let m = (a - &base.0).abs().max(&(b - &base.1).abs()).to_f64();
                k = k.max(m);
            }
        }
    }
    k
}

/// Predicted against measured worst errors of one evaluation over a set of
/// shapes (see [`PredictionTally`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictionRow {
    /// Shapes whose evaluation was accepted (and measured).
    pub cases: usize,
    /// Shapes where the measured error exceeds the prediction.
    pub under: usize,
    /// Shapes where the prediction is at most 100× the measured error.
    pub within_100: usize,
    /// The largest `predicted / measured` (1 when both are ∞).
    pub worst_ratio: f64,
    /// The smallest `predicted / measured` over the finite measurements:
    /// the margin of the bound (< 1 for an under-prediction); ∞ for none.
    pub least_ratio: f64,
}

impl Default for PredictionRow {
    fn default() -> Self {
        PredictionRow {
            cases: 0,
            under: 0,
            within_100: 0,
            worst_ratio: 0.0,
            least_ratio: f64::INFINITY,
        }
    }
}

impl PredictionRow {
    /// Counts one shape.
    pub fn add(&mut self, predicted: f64, measured: f64) {
        self.cases += 1;
        self.under += usize::from(!(predicted >= measured));
        self.within_100 += usize::from(predicted <= 100.0 * measured);
        let ratio = if predicted == measured {
            1.0
        } else {
            predicted / measured
        };
        self.worst_ratio = self.worst_ratio.max(ratio);
        if measured.is_finite() {
            self.least_ratio = self.least_ratio.min(ratio);
        }
    }

    /// The sum of two rows.
    pub fn merged(&self, other: &PredictionRow) -> PredictionRow {
        PredictionRow {
            cases: self.cases + other.cases,
            under: self.under + other.under,
            within_100: self.within_100 + other.within_100,
            worst_ratio: self.worst_ratio.max(other.worst_ratio),
            least_ratio: self.least_ratio.min(other.least_ratio),
        }
    }

    /// The fraction of cases within 100× (1 for no cases).
    pub fn fraction_within_100(&self) -> f64 {
        if self.cases == 0 {
            1.0
        } else {
            self.within_100 as f64 / self.cases as f64
        }
    }
}

/// Predicted against measured worst errors per [`Evaluation`], over a set
/// of shapes: what issue 13 asks of [`advise`](super::advise) (no
/// under-prediction, ≥ 90% within 100×).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PredictionTally {
    /// One row per evaluation.
    pub rows: std::collections::BTreeMap<Evaluation, PredictionRow>,
}

impl PredictionTally {
    /// Counts the accepted evaluations of one shape.
    pub fn add(&mut self, advice: &super::Advice, measured: &[Measured]) {
        for m in measured.iter().filter(|m| m.accepted) {
            self.rows
                .entry(m.evaluation)
                .or_default()
                .add(advice.predicted(m.evaluation), m.worst_error);
        }
    }

    /// All evaluations together.
    pub fn total(&self) -> PredictionRow {
        self.rows
            .values()
            .fold(PredictionRow::default(), |a, r| a.merged(r))
    }

    /// The tally of both sets of shapes.
    pub fn merged(&self, other: &PredictionTally) -> PredictionTally {
        let mut out = self.clone();
        for (e, r) in &other.rows {
            let row = out.rows.entry(*e).or_default();
            *row = row.merged(r);
        }
        out
    }

    /// A markdown table: one row per evaluation and the total, headed by
    /// `family`.
    pub fn table(&self, family: &str) -> String {
        let mut s = format!(
            "| {family} | cases | under-predicted | within 100× | predicted/measured: least | largest |\n|---|---|---|---|---|---|\n"
        );
        let line = |name: &str, r: &PredictionRow| {
            format!(
                "| {name} | {} | {} | {} ({:.1}%) | {:.3} | {:.3e} |\n",
                r.cases,
                r.under,
                r.within_100,
                100.0 * r.fraction_within_100(),
                r.least_ratio,
                r.worst_ratio
            )
        };
        for (e, r) in &self.rows {
            s += &line(e.label(), r);
        }
        s += &line("all", &self.total());
        s
    }
}
