//! `areawarp eval --precision auto:TOL`: the light shapes evaluated the
//! cheapest way predicted to meet the tolerance
//! ([`areawarp::precision_choice`]).
//!
//! `spherical-triangle A B C u v` and `spherical-rectangle s ex ey o u v`
//! (parameters parsed as `f64`; the `f32` evaluations round them to `f32`)
//! print the direction (and the rectangle's point first, as in the fixed
//! precisions) in the chosen output type, then a comment with the choice and
//! every evaluation's predicted worst error:
//!
//! ```text
//! spherical-triangle 0.57735026 0.57735026 0.57735026 # f32 robust (predicted 1.5e-6 ≤ 1e-5; f32 mixed 6.0e-8, f64 robust 2.8e-15)
//! ```
//!
//! Every other line is evaluated in `f64`, with `# f64`.

use super::eval::{Options, eval_line};
use areawarp::precision_choice::{Advice, Advisable, Evaluation, Mixed, advise};
use areawarp::real::Real;
use areawarp::shapes::{SphericalRectangle, SphericalTriangle};
use areawarp::{Vec3, Warp};

/// Answers one line with automatic precision (see the module docs).
pub fn eval_line_auto(line: &str, opts: &Options) -> Option<Result<String, String>> {
    let trimmed = line.trim();
    if trimmed.is_empty() || trimmed.starts_with('#') {
        return None;
    }
    let tol = opts.tolerance.unwrap_or(f64::EPSILON);
    let mut words = trimmed.split_whitespace();
    let name = words.next()?;
    if opts.inverse || opts.literal || !matches!(name, "spherical-triangle" | "spherical-rectangle")
    {
        return eval_line::<f64>(line, opts).map(|r| r.map(|s| format!("{s} # f64")));
    }
    let numbers: Result<Vec<f64>, String> = words
        .map(|w| w.parse::<f64>().map_err(|_| format!("not a number: {w:?}")))
        .collect();
    let result = numbers.and_then(|n| {
        let (params, uv) = match (name, n.len()) {
            ("spherical-triangle", 11) => (&n[..9], (n[9], n[10])),
            ("spherical-rectangle", 14) => (&n[..12], (n[12], n[13])),
            _ => {
                return Err(format!(
                    "expected the shape's parameters then u v, got {} numbers",
                    n.len()
                ));
            }
        };
        if !(0.0..=1.0).contains(&uv.0) || !(0.0..=1.0).contains(&uv.1) {
            return Err(format!("(u, v) = ({}, {}) is not in [0, 1]²", uv.0, uv.1));
        }
        if name == "spherical-triangle" {
            let t = <SphericalTriangle<f64> as Advisable>::build(params, false, 53)
                .map_err(|e| e.to_string())?;
            evaluate(&t, params, uv, tol, false)
        } else {
            let r = <SphericalRectangle<f64> as Advisable>::build(params, false, 53)
                .map_err(|e| e.to_string())?;
            evaluate(&r, params, uv, tol, true)
        }
    });
    Some(
        result
            .map(|out| format!("{name} {out}"))
            .map_err(|e| format!("{name} error: {e}")),
    )
}

fn join<T: Real>(xs: &[T]) -> String {
    xs.iter()
        .map(Real::to_roundtrip_string)
        .collect::<Vec<_>>()
        .join(" ")
}

/// The rectangle's point and direction, or the triangle's direction, in `S`.
fn output<W: Advisable, S: Real>(w: &W::In<S>, u: &S, v: &S, point: bool) -> String
where
    W::In<S>: RectanglePoint<S>,
{
    let d = w.map(u, v);
    match (point, w.point(u, v)) {
        (true, Some(p)) => join(&[p.x, p.y, p.z, d.x, d.y, d.z]),
        _ => join(&[d.x, d.y, d.z]),
    }
}

/// The point on the light, for shapes that have one.
pub trait RectanglePoint<S: Real> {
    /// The point of the sample on the emitter (`None`: direction only).
    fn point(&self, u: &S, v: &S) -> Option<Vec3<S>>;
}

impl<S: Real> RectanglePoint<S> for SphericalTriangle<S> {
    fn point(&self, _: &S, _: &S) -> Option<Vec3<S>> {
        None
    }
}

impl<S: Real> RectanglePoint<S> for SphericalRectangle<S> {
    fn point(&self, u: &S, v: &S) -> Option<Vec3<S>> {
        Some(areawarp::LightWarp::sample_light(self, [u.clone(), v.clone()]).point)
    }
}

fn summary(advice: &Advice, chosen: Evaluation, tol: f64) -> String {
    let others: Vec<String> = Evaluation::ALL
        .into_iter()
        .filter(|&e| e.is_robust() && e != chosen)
        .map(|e| format!("{e} {:.1e}", advice.predicted(e)))
        .collect();
    format!(
        "# {chosen} (predicted {:.1e} ≤ {tol:e}; {})",
        advice.predicted(chosen),
        others.join(", ")
    )
}

fn evaluate<W>(
    w: &W,
    params: &[f64],
    uv: (f64, f64),
    tol: f64,
    point: bool,
) -> Result<String, String>
where
    W: Advisable,
    W::In<f32>: RectanglePoint<f32>,
    W::In<f64>: RectanglePoint<f64>,
{
    let advice = advise(w).map_err(|e| e.to_string())?;
    let Some(chosen) = advice.choose(tol) else {
        return Err(format!(
            "no evaluation is predicted to meet {tol:e} (f64 robust: {:.1e})",
            advice.predicted(Evaluation::RobustF64)
        ));
    };
    let p32: Vec<f32> = params.iter().map(|&x| x as f32).collect();
    let (u32_, v32) = (uv.0 as f32, uv.1 as f32);
    let out = match chosen {
        Evaluation::RobustF32 => {
            let w32 = W::build(&p32, false, 24).map_err(|e| e.to_string())?;
            output::<W, f32>(&w32, &u32_, &v32, point)
        }
        Evaluation::MixedF32 => {
            let p: Vec<f64> = p32.iter().map(|&x| f64::from(x)).collect();
            let inner = W::build(&p, false, 24).map_err(|e| e.to_string())?;
            let m = Mixed::<W>::from_f32_parameters(&p).map_err(|e| e.to_string())?;
            let d = m.map(&u32_, &v32);
            match inner.point(&f64::from(u32_), &f64::from(v32)) {
                Some(q) if point => join(&[q.x as f32, q.y as f32, q.z as f32, d.x, d.y, d.z]),
                _ => join(&[d.x, d.y, d.z]),
            }
        }
        _ => {
            let w64 = W::build(params, false, 53).map_err(|e| e.to_string())?;
            output::<W, f64>(&w64, &uv.0, &uv.1, point)
        }
    };
    Ok(format!("{out} {}", summary(&advice, chosen, tol)))
}
