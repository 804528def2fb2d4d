//! Precision chosen per shape (issue 13): for every shape of the light
//! ladders (ordinary and hard spherical triangles and rectangles), the worst
//! error of each evaluation — `f32` robust, `f32` mixed (`f32` in and out,
//! `f64` arithmetic), `f64` robust, and the published (literal) algorithms
//! in `f32` and `f64` — measured against the exact map at 256 bits, beside
//! the error [`advise`] predicts from the shape's conditioning, and the
//! evaluation [`Advice::choose`] picks for a few tolerances; then what each
//! evaluation costs per sample and one-shot (construct + one sample).
//!
//! The measured error is the max-norm distance of the returned direction to
//! the exact map of the same inputs (the shape and `(u, v)` rounded to the
//! evaluation's input type) over the extremes grid and 16 random points.
//!
//! # Example
//! ```no_run
//! use areawarp_lab::studies::precision_choice::{run, ChoiceConfig};
//! let study = run(&ChoiceConfig::quick())?;
//! println!("{}", study.to_markdown());
//! # Ok::<(), areawarp::WarpError>(())
//! ```

mod timing;

pub use timing::{CostRow, time_costs};

use areawarp::error::WarpError;
use areawarp::harness::extremes::{extremes_grid, random_points};
use areawarp::precision_choice::measure::{PredictionTally, measure};
use areawarp::precision_choice::{Advice, Advisable, Evaluation, advise};
use areawarp::shapes::{
    SphericalRectangle, SphericalTriangle, hard_rectangles, hard_triangles, ordinary_rectangles,
    ordinary_triangles,
};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// The study's size.
#[derive(Clone, Debug, PartialEq)]
pub struct ChoiceConfig {
    /// Random `(u, v)` points added to the extremes grid.
    pub random_points: usize,
    /// The tolerances the choice is shown for.
    pub tolerances: Vec<f64>,
    /// Samples (and shading points) per timing batch.
    pub batch: usize,
    /// Timing runs (the median is reported).
    pub repetitions: usize,
}

impl ChoiceConfig {
    /// The tests' size.
    pub fn quick() -> Self {
        ChoiceConfig {
            random_points: 4,
            tolerances: vec![1e-5, 1e-7, 1e-12],
            batch: 256,
            repetitions: 3,
        }
    }
}

impl Default for ChoiceConfig {
    fn default() -> Self {
        ChoiceConfig {
            random_points: 16,
            tolerances: vec![1e-5, 1e-7, 1e-12],
            batch: 4096,
            repetitions: 15,
        }
    }
}

/// One shape: its conditioning, and per evaluation the predicted and the
/// measured worst error.
#[derive(Clone, Debug)]
pub struct ShapeRow {
    /// `spherical-triangle` or `spherical-rectangle`.
    pub warp: &'static str,
    /// The shape's label in its ladder.
    pub shape: String,
    /// `true` for a shape of a hard ladder.
    pub hard: bool,
    /// The advice (κ's and predictions).
    pub advice: Advice,
    /// `(evaluation, measured worst error)`; `None` when the evaluation's
    /// constructor rejects the shape.
    pub measured: Vec<(Evaluation, Option<f64>)>,
    /// The evaluation chosen for each tolerance of the configuration.
    pub chosen: Vec<Option<Evaluation>>,
}

impl ShapeRow {
    /// The measured worst error of `e` (`None`: rejected).
    pub fn measured(&self, e: Evaluation) -> Option<f64> {
        self.measured
            .iter()
            .find(|(m, _)| *m == e)
            .and_then(|(_, x)| *x)
    }
}

/// The study's result.
#[derive(Clone, Debug)]
pub struct ChoiceStudy {
    /// The configuration.
    pub config: ChoiceConfig,
    /// One row per ladder shape.
    pub rows: Vec<ShapeRow>,
    /// Costs per sample and one-shot.
    pub costs: Vec<CostRow>,
}

fn row<W: Advisable>(
    warp: &'static str,
    shape: String,
    hard: bool,
    w: &W,
    points: &[(f64, f64)],
    tolerances: &[f64],
) -> Result<ShapeRow, WarpError> {
    let advice = advise(w)?;
    let measured = measure(w, points)?
        .into_iter()
        .map(|m| (m.evaluation, m.accepted.then_some(m.worst_error)))
        .collect();
    let chosen = tolerances.iter().map(|&t| advice.choose(t)).collect();
    Ok(ShapeRow {
        warp,
        shape,
        hard,
        advice,
        measured,
        chosen,
    })
}

/// Runs the study.
///
/// # Errors
/// [`WarpError`] if a ladder shape cannot be built or measured.
pub fn run(config: &ChoiceConfig) -> Result<ChoiceStudy, WarpError> {
    let mut points = extremes_grid();
    points.extend(random_points(config.random_points, 42));
    let tol = &config.tolerances;
    let mut rows = Vec::new();
    let triangles = ordinary_triangles()
        .into_iter()
        .map(|t| (t, false))
        .chain(hard_triangles().into_iter().map(|t| (t, true)));
    for ((name, [a, b, c]), hard) in triangles {
        let t = SphericalTriangle::<f64>::new(a, b, c)?;
        rows.push(row("spherical-triangle", name, hard, &t, &points, tol)?);
    }
    let rectangles = ordinary_rectangles()
        .into_iter()
        .map(|r| (r, false))
        .chain(hard_rectangles().into_iter().map(|r| (r, true)));
    for ((name, [s, ex, ey, o]), hard) in rectangles {
        let r = SphericalRectangle::<f64>::new(s, ex, ey, o)?;
        rows.push(row("spherical-rectangle", name, hard, &r, &points, tol)?);
    }
    let costs = time_costs(config.batch, config.repetitions);
    Ok(ChoiceStudy {
        config: config.clone(),
        rows,
        costs,
    })
}

/// The statistics of predicted against measured over the rows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PredictionStats {
    /// (shape, evaluation) cases with a measurement.
    pub cases: usize,
    /// Cases with measured > predicted.
    pub under: usize,
    /// Cases with predicted ≤ 100 × measured.
    pub within_100: usize,
}

impl ChoiceStudy {
    /// Predicted against measured over all rows, for the evaluations `keep`
    /// selects.
    pub fn stats(&self, keep: impl Fn(Evaluation) -> bool) -> PredictionStats {
        let mut s = PredictionStats::default();
        for r in &self.rows {
            for &(e, m) in &r.measured {
                let Some(m) = m else { continue };
                if !keep(e) {
                    continue;
                }
                let p = r.advice.predicted(e);
                s.cases += 1;
                s.under += usize::from(p < m);
                s.within_100 += usize::from(p <= 100.0 * m);
            }
        }
        s
    }

    /// Predicted against measured per evaluation, for the rows of `warp`
    /// (`None`: every row).
    pub fn tally(&self, warp: Option<&str>) -> PredictionTally {
        let mut t = PredictionTally::default();
        for r in self
            .rows
            .iter()
            .filter(|r| warp.is_none_or(|w| w == r.warp))
        {
            for &(e, m) in &r.measured {
                if let Some(m) = m {
                    t.rows.entry(e).or_default().add(r.advice.predicted(e), m);
                }
            }
        }
        t
    }

    /// The report section.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "## Precision chosen per shape\n");
        let _ = writeln!(
            s,
            "For every shape of the light ladders, the worst error of each evaluation (max-norm distance of the \
             direction to the exact map of the same inputs at 256 bits, over the extremes grid and {} random \
             points) beside the error `advise` predicts from the shape's conditioning (κ of the evaluation: \
             one-ulp moves of the parameters and of min(u, 1−u), min(v, 1−v); predicted `16·max(u, κ)`, the \
             mixed mode `2⁻²⁴ + 16·max(2⁻⁵³, κ₆₄)`; the literal algorithms: 4× their error at 545 probes plus \
             the robust bound, ∞ where they return NaN at a probe). *f32 mixed*: f32 inputs and outputs, the \
             robust map evaluated in f64. `rej.` = the evaluation's constructor rejects the shape. Cells: \
             predicted / measured.\n",
            self.config.random_points
        );
        let _ = writeln!(
            s,
            "| warp | shape | κ₃₂ | κ₆₄ | f32 robust | f32 mixed | f64 robust | f32 literal | f64 literal | chosen for {} |",
            self.config
                .tolerances
                .iter()
                .map(|t| format!("{t:.0e}"))
                .collect::<Vec<_>>()
                .join(" / ")
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
        for r in &self.rows {
            let cell = |e: Evaluation| match r.measured(e) {
                None => "rej.".to_string(),
                Some(m) => format!("{} / {}", num(r.advice.predicted(e)), num(m)),
            };
            let chosen: Vec<String> = r
                .chosen
                .iter()
                .map(|c| c.map_or("none".to_string(), |e| e.label().to_string()))
                .collect();
            let _ = writeln!(
                s,
                "| {} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.warp,
                r.shape,
                if r.hard { "" } else { " (ordinary)" },
                num(r.advice.kappa_f32),
                num(r.advice.kappa_f64),
                cell(Evaluation::RobustF32),
                cell(Evaluation::MixedF32),
                cell(Evaluation::RobustF64),
                cell(Evaluation::LiteralF32),
                cell(Evaluation::LiteralF64),
                chosen.join(" / ")
            );
        }
        let _ = writeln!(
            s,
            "\nPredicted against measured, per family and evaluation (*least*: the bound's smallest margin; \
             *largest*: its largest overestimate; ∞ where a literal algorithm returns NaN at a probe but not \
             at the points measured). The rectangle's κ moves the numbers its evaluation rounds — the local \
             coordinates x₀, y₀, h (by one ulp of the arithmetic, or of |s − o| in f64, whichever is larger) \
             and the edge lengths — rather than the world coordinates of s and o; the literal rectangle's \
             prediction adds the error of its cut-off `h_v² ≥ 1 − ε ⇒ y_v = y₁` (bounded from the geometry).\n"
        );
        for (name, warp) in [
            ("triangles", Some("spherical-triangle")),
            ("rectangles", Some("spherical-rectangle")),
            ("both", None),
        ] {
            let _ = writeln!(s, "{}", self.tally(warp).table(name));
        }
        let _ = writeln!(
            s,
            "### What each evaluation costs (ns per sample, median of {} runs of {}, this machine)\n",
            self.config.repetitions, self.config.batch
        );
        let _ = writeln!(
            s,
            "*per sample*: the light built once; *one-shot*: construct + one sample per shading point (the \
             observer moves), no light kept; *solid angle*: the one-shot Ω (pdf = 1/Ω) without building the \
             light. Ratios are taken within this run.\n"
        );
        let _ = writeln!(
            s,
            "| light | evaluation | per sample | one-shot | one-shot / per sample | solid angle | per sample / f32 robust |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for c in &self.costs {
            let base = self
                .costs
                .iter()
                .find(|b| b.light == c.light && b.evaluation == Evaluation::RobustF32)
                .map_or(f64::NAN, |b| b.per_sample);
            let _ = writeln!(
                s,
                "| {} | {} | {:.1} | {:.1} | {:.2} | {} | {:.2} |",
                c.light,
                c.evaluation,
                c.per_sample,
                c.one_shot,
                c.one_shot / c.per_sample,
                c.solid_angle.map_or("—".to_string(), |x| format!("{x:.1}")),
                c.per_sample / base
            );
        }
        s
    }

    /// Writes `precision_choice.csv` and `precision_choice_cost.csv`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        let mut t =
            String::from("warp,shape,hard,kappa_f32,kappa_f64,evaluation,predicted,measured\n");
        for r in &self.rows {
            for &(e, m) in &r.measured {
                let _ = writeln!(
                    t,
                    "{},\"{}\",{},{:e},{:e},{},{:e},{}",
                    r.warp,
                    r.shape,
                    r.hard,
                    r.advice.kappa_f32,
                    r.advice.kappa_f64,
                    e.label(),
                    r.advice.predicted(e),
                    m.map_or("rejected".to_string(), |m| format!("{m:e}"))
                );
            }
        }
        let mut c = String::from("light,evaluation,ns_per_sample,ns_one_shot,ns_solid_angle\n");
        for x in &self.costs {
            let _ = writeln!(
                c,
                "{},{},{},{},{}",
                x.light,
                x.evaluation.label(),
                x.per_sample,
                x.one_shot,
                x.solid_angle.map_or(String::new(), |v| v.to_string())
            );
        }
        let a = dir.join("precision_choice.csv");
        let b = dir.join("precision_choice_cost.csv");
        std::fs::write(&a, t)?;
        std::fs::write(&b, c)?;
        Ok(vec![a, b])
    }
}

fn num(x: f64) -> String {
    if x.is_infinite() {
        "∞".to_string()
    } else if x == 0.0 {
        "0".to_string()
    } else {
        format!("{x:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn precision_choice_quick_covers_the_ladders() {
        let s = run(&ChoiceConfig::quick()).unwrap();
        assert_eq!(
            s.rows.len(),
            hard_triangles().len()
                + ordinary_triangles().len()
                + hard_rectangles().len()
                + ordinary_rectangles().len()
        );
        for warp in [
            Some("spherical-triangle"),
            Some("spherical-rectangle"),
            None,
        ] {
            let total = s.tally(warp).total();
            assert_eq!(total.under, 0, "{warp:?}: {total:?}");
            assert!(total.fraction_within_100() >= 0.9, "{warp:?}: {total:?}");
        }
        assert_eq!(s.costs.len(), 6);
        let md = s.to_markdown();
        assert!(md.contains("Precision chosen per shape") && md.contains("sliver@A"));
        let dir = std::env::temp_dir().join("areawarp-precision-choice-test");
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(s.write_csv(&dir).unwrap().len(), 2);
    }

    /// The report's section at the default size, printed:
    /// `cargo test --release -p areawarp-lab --lib precision_choice_section -- --ignored --nocapture`.
    #[test]
    #[ignore = "the report section at the default size (timings: one run)"]
    fn precision_choice_section() {
        let s = run(&ChoiceConfig::default()).unwrap();
        println!("{}", s.to_markdown());
    }
}
