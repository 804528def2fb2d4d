//! `areawarp eval`: one map evaluation per input line.
//!
//! Input lines are `MAP PARAMS… u v` (or `MAP PARAMS… POINT…` with
//! `--inverse`); `#` lines and blank lines are skipped. Every line is
//! answered on its own: a line that is not valid UTF-8 gets an error line
//! with its line number, and the lines after it are still evaluated.
//! Numbers are parsed directly in the chosen precision. Outputs are printed with enough digits
//! to read back to the same value in that precision.

use super::eval_recipe::RecipeVariant;
use areawarp::real::Real;
use areawarp::shapes::{
    Beckmann, Bilinear, ConcentricDisk, Ggx, Hemisphere, MarginalInversion, PhongLobe,
    PlanarTriangle, PlanarTriangleVariant, PolarDisk, ProjectedPolygon, Sphere, SphereLight,
    SphericalLune, SphericalRectangle, SphericalRectangleVariant, SphericalTriangle,
    SphericalTriangleVariant, StdNormal, Tent, UniformCone, VonMisesFisher,
};
use areawarp::warp::LightWarp;
use areawarp::{Coords, Vec3, Warp};
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::ExitCode;

/// Answers one line in a fixed precision (see [`eval_line`]).
type LineEvaluator = fn(&str, &Options) -> Option<Result<String, String>>;

/// The evaluator's switches.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// Lines end with a point; answer `u v`.
    pub inverse: bool,
    /// Use the papers' literal algorithms for the solid-angle maps.
    pub literal: bool,
    /// `planar-triangle`: Heitz's fold map instead of Arvo's √u map.
    pub fold: bool,
    /// Newton steps after the cubic for `projected-polygon` (`None`: to convergence).
    pub newton: Option<u32>,
    /// `--precision auto:TOL`: the largest error the caller accepts; the
    /// light shapes are evaluated the cheapest way predicted to meet it.
    pub tolerance: Option<f64>,
    /// `--variant closed|derived|tabulated:TOL` (see [`super::eval_recipe`]).
    pub recipe: RecipeVariant,
}

/// Entry point of `areawarp eval`.
pub fn main(precision: &str, mut opts: Options, file: Option<&Path>) -> ExitCode {
    let input: Box<dyn BufRead> = match file {
        Some(path) => match std::fs::File::open(path) {
            Ok(f) => Box::new(BufReader::new(f)),
            Err(e) => {
                eprintln!("error: cannot open {}: {e}", path.display());
                return ExitCode::from(2);
            }
        },
        None => Box::new(BufReader::new(std::io::stdin())),
    };
    let run: LineEvaluator = match precision {
        "f32" => eval_line::<f32>,
        "f64" => eval_line::<f64>,
        p if p.starts_with("auto:") => match p[5..].trim().parse::<f64>() {
            Ok(tol) if tol > 0.0 => {
                opts.tolerance = Some(tol);
                super::eval_auto::eval_line_auto
            }
            _ => {
                eprintln!("error: auto:TOL needs a positive tolerance, got {p}");
                return ExitCode::from(2);
            }
        },
        p if p.starts_with("mpfr:") => match mpfr_evaluator(&p[5..]) {
            Some(f) => f,
            None => {
                eprintln!(
                    "error: unsupported precision {p}: BITS must be one of 64, 113, 128, 192, 256, 512, 1024"
                );
                return ExitCode::from(2);
            }
        },
        p => {
            eprintln!("error: unknown precision {p}: expected f32, f64, mpfr:BITS or auto:TOL");
            return ExitCode::from(2);
        }
    };
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut failed = false;
    // Bytes, not `String` lines: a line that is not UTF-8 is one bad line
    // (answered with an error line), not the end of the input.
    let mut input = input;
    let mut buf = Vec::new();
    let mut line_number = 0usize;
    loop {
        buf.clear();
        match input.read_until(b'\n', &mut buf) {
            Ok(0) => break,
            Ok(_) => {}
            Err(e) => {
                eprintln!("error: reading input: {e}");
                return ExitCode::from(2);
            }
        }
        line_number += 1;
        let answer = match std::str::from_utf8(strip_line_end(&buf)) {
            Ok(line) => match run(line, &opts) {
                None => continue,
                Some(Ok(s)) => s,
                Some(Err(s)) => {
                    failed = true;
                    s
                }
            },
            Err(e) => {
                failed = true;
                not_utf8_line(&buf, line_number, &e)
            }
        };
        if writeln!(out, "{answer}").is_err() {
            return ExitCode::from(2);
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// The line without its `\n` or `\r\n` ending (as [`BufRead::lines`]).
fn strip_line_end(line: &[u8]) -> &[u8] {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    line.strip_suffix(b"\r").unwrap_or(line)
}

/// The error line for input line `line_number` (1-based), which is not
/// UTF-8: `MAP error: line N is not valid UTF-8 (byte 0xFF at column C)`,
/// MAP being the line's first word (invalid bytes shown as U+FFFD, `?` for
/// a line with no word).
fn not_utf8_line(bytes: &[u8], line_number: usize, e: &std::str::Utf8Error) -> String {
    let text = String::from_utf8_lossy(strip_line_end(bytes));
    let name = text.split_whitespace().next().unwrap_or("?");
    let at = e.valid_up_to();
    format!(
        "{name} error: line {line_number} is not valid UTF-8 (byte 0x{:02X} at column {})",
        bytes[at],
        at + 1
    )
}

fn mpfr_evaluator(bits: &str) -> Option<LineEvaluator> {
    use areawarp::real::Mpfr;
    Some(match bits.trim() {
        "64" => eval_line::<Mpfr<64>>,
        "113" => eval_line::<Mpfr<113>>,
        "128" => eval_line::<Mpfr<128>>,
        "192" => eval_line::<Mpfr<192>>,
        "256" => eval_line::<Mpfr<256>>,
        "512" => eval_line::<Mpfr<512>>,
        "1024" => eval_line::<Mpfr<1024>>,
        _ => return None,
    })
}

/// Answers one input line: `None` for blank and comment lines, `Ok(output)`
/// or `Err(error line)` otherwise.
pub fn eval_line<T: Real>(line: &str, opts: &Options) -> Option<Result<String, String>> {
    let line = line.trim();
    if line.is_empty() || line.starts_with('#') {
        return None;
    }
    let mut words = line.split_whitespace();
    let name = words.next()?;
    let numbers: Result<Vec<T>, String> = words
        .map(|w| T::parse_decimal(w).ok_or_else(|| format!("not a number: {w:?}")))
        .collect();
    Some(
        numbers
            .and_then(|n| dispatch::<T>(name, &n, opts))
            .map(|out| format!("{name} {out}"))
            .map_err(|e| format!("{name} error: {e}")),
    )
}

fn dispatch<T: Real>(name: &str, n: &[T], opts: &Options) -> Result<String, String> {
    let inverse = opts.inverse;
    if opts.recipe != RecipeVariant::Closed {
        return super::eval_recipe::eval_variant(name, n, opts.recipe, inverse);
    }
    let vec3 = |i: usize| Vec3::new(n[i].clone(), n[i + 1].clone(), n[i + 2].clone());
    match name {
        "spherical-triangle" => {
            expect(n, 9, inverse, 3)?;
            let variant = if opts.literal {
                SphericalTriangleVariant::Literal
            } else {
                SphericalTriangleVariant::Robust
            };
            let w = SphericalTriangle::new_with(vec3(0), vec3(3), vec3(6), variant)
                .map_err(|e| e.to_string())?;
            apply(&w, &n[9..], inverse)
        }
        "spherical-rectangle" => spherical_rectangle(n, opts),
        "projected-polygon" => projected_polygon(n, opts),
        "planar-triangle" => {
            expect(n, 9, inverse, 3)?;
            let variant = if opts.fold {
                PlanarTriangleVariant::Fold
            } else {
                PlanarTriangleVariant::SquareRoot
            };
            let w = PlanarTriangle::new_with(vec3(0), vec3(3), vec3(6), variant)
                .map_err(|e| e.to_string())?;
            apply(&w, &n[9..], inverse)
        }
        "uniform-cone" => {
            expect(n, 1, inverse, 3)?;
            let w = UniformCone::new(n[0].clone()).map_err(|e| e.to_string())?;
            apply(&w, &n[1..], inverse)
        }
        "sphere-light" => sphere_light(n, opts),
        "spherical-lune" => {
            expect(n, 6, inverse, 3)?;
            let w = SphericalLune::new(vec3(0), vec3(3)).map_err(|e| e.to_string())?;
            apply(&w, &n[6..], inverse)
        }
        "von-mises-fisher" => {
            expect(n, 1, inverse, 3)?;
            let w = VonMisesFisher::new(n[0].clone()).map_err(|e| e.to_string())?;
            apply(&w, &n[1..], inverse)
        }
        "beckmann" => {
            expect(n, 1, inverse, 3)?;
            let w = Beckmann::new(n[0].clone()).map_err(|e| e.to_string())?;
            apply(&w, &n[1..], inverse)
        }
        "ggx" => {
            expect(n, 1, inverse, 3)?;
            let w = Ggx::new(n[0].clone()).map_err(|e| e.to_string())?;
            apply(&w, &n[1..], inverse)
        }
        "bilinear" => {
            expect(n, 4, inverse, 2)?;
            let w = Bilinear::new([n[0].clone(), n[1].clone(), n[2].clone(), n[3].clone()])
                .map_err(|e| e.to_string())?;
            apply(&w, &n[4..], inverse)
        }
        "tent" => {
            expect(n, 0, inverse, 2)?;
            apply(&Tent::<T>::new(), n, inverse)
        }
        "std-normal" => {
            expect(n, 0, inverse, 2)?;
            apply(&StdNormal::<T>::new(), n, inverse)
        }
        "disk" => {
            expect(n, 0, inverse, 2)?;
            apply(&PolarDisk::<T>::new(), n, inverse)
        }
        "concentric-disk" => {
            expect(n, 0, inverse, 2)?;
            apply(&ConcentricDisk::<T>::new(), n, inverse)
        }
        "hemisphere" => {
            expect(n, 0, inverse, 3)?;
            apply(&Hemisphere::<T>::new(), n, inverse)
        }
        "phong" => {
            expect(n, 1, inverse, 3)?;
            let w = PhongLobe::new(n[0].clone()).map_err(|e| e.to_string())?;
            apply(&w, &n[1..], inverse)
        }
        "sphere" => {
            expect(n, 0, inverse, 3)?;
            apply(&Sphere::<T>::new(), n, inverse)
        }
        _ => Err(format!(
            "unknown map {name:?} (known: planar-triangle, disk, concentric-disk, hemisphere, phong, sphere, \
             spherical-triangle, spherical-rectangle, projected-polygon, uniform-cone, sphere-light, \
             spherical-lune, von-mises-fisher, beckmann, ggx, bilinear, tent, std-normal)"
        )),
    }
}

/// `spherical-rectangle s ex ey o u v` → `point direction`; with `--inverse`
/// the line ends with a direction from `o` (3 numbers) or with the point and
/// direction printed by the forward map (6 numbers; the point is used).
fn spherical_rectangle<T: Real>(n: &[T], opts: &Options) -> Result<String, String> {
    let vec3 = |i: usize| Vec3::new(n[i].clone(), n[i + 1].clone(), n[i + 2].clone());
    let tail = n.len().saturating_sub(12);
    let ok = if opts.inverse {
        tail == 3 || tail == 6
    } else {
        tail == 2
    };
    if n.len() < 12 || !ok {
        let what = if opts.inverse {
            "a direction (3) or a point and direction (6)"
        } else {
            "u v"
        };
        return Err(format!(
            "expected 12 parameters (s, ex, ey, o) then {what}, got {} numbers",
            n.len()
        ));
    }
    let variant = if opts.literal {
        SphericalRectangleVariant::Literal
    } else {
        SphericalRectangleVariant::Robust
    };
    let w = SphericalRectangle::new_with(vec3(0), vec3(3), vec3(6), vec3(9), variant)
        .map_err(|e| e.to_string())?;
    if opts.inverse {
        let [u, v] = if tail == 6 {
            w.inverse_point(&vec3(12))
        } else {
            w.inverse(&vec3(12))
        }
        .map_err(|e| e.to_string())?;
        return Ok(format!(
            "{} {}",
            u.to_roundtrip_string(),
            v.to_roundtrip_string()
        ));
    }
    let (u, v) = (&n[12], &n[13]);
    check_unit(u, v)?;
    let (p, d) = w.sample_point(u, v);
    Ok(join(&[p.x, p.y, p.z, d.x, d.y, d.z]))
}

/// `sphere-light cx cy cz r ox oy oz u v` → `point direction` (the first
/// hit on the sphere, then the unit direction from `o`); with `--inverse`
/// the line ends with a direction (3 numbers) or with the point and
/// direction printed by the forward map (6 numbers; the point is used).
fn sphere_light<T: Real>(n: &[T], opts: &Options) -> Result<String, String> {
    let vec3 = |i: usize| Vec3::new(n[i].clone(), n[i + 1].clone(), n[i + 2].clone());
    let tail = n.len().saturating_sub(7);
    let ok = if opts.inverse {
        tail == 3 || tail == 6
    } else {
        tail == 2
    };
    if n.len() < 7 || !ok {
        let what = if opts.inverse {
            "a direction (3) or a point and direction (6)"
        } else {
            "u v"
        };
        return Err(format!(
            "expected 7 parameters (c, r, o) then {what}, got {} numbers",
            n.len()
        ));
    }
    let w = SphereLight::new(vec3(0), n[3].clone(), vec3(4)).map_err(|e| e.to_string())?;
    if opts.inverse {
        let [u, v] = if tail == 6 {
            w.inverse_point(&vec3(7))
        } else {
            w.inverse(&vec3(7))
        }
        .map_err(|e| e.to_string())?;
        return Ok(format!(
            "{} {}",
            u.to_roundtrip_string(),
            v.to_roundtrip_string()
        ));
    }
    let (u, v) = (&n[7], &n[8]);
    check_unit(u, v)?;
    let s = w.sample_light([u.clone(), v.clone()]);
    let (p, d) = (s.point, s.direction);
    Ok(join(&[p.x, p.y, p.z, d.x, d.y, d.z]))
}

/// `projected-polygon N v1 … vN u v` → `x y z` (directions from the origin,
/// receiver normal +z).
fn projected_polygon<T: Real>(n: &[T], opts: &Options) -> Result<String, String> {
    let count = n.first().ok_or("expected the vertex count N")?;
    let k = count.to_f64();
    if !((3.0..=1e6).contains(&k) && k.fract() == 0.0) {
        return Err(format!(
            "N = {count} is not a vertex count (an integer ≥ 3)"
        ));
    }
    let k = k as usize;
    expect(n, 1 + 3 * k, opts.inverse, 3)?;
    let verts: Vec<Vec3<T>> = (0..k)
        .map(|i| {
            Vec3::new(
                n[1 + 3 * i].clone(),
                n[2 + 3 * i].clone(),
                n[3 + 3 * i].clone(),
            )
        })
        .collect();
    let inversion = match opts.newton {
        None => MarginalInversion::Newton,
        Some(0) => MarginalInversion::Cubic,
        Some(steps) => MarginalInversion::CubicNewton(steps),
    };
    let w = ProjectedPolygon::new_with(&verts, inversion).map_err(|e| e.to_string())?;
    apply(&w, &n[1 + 3 * k..], opts.inverse)
}

fn check_unit<T: Real>(u: &T, v: &T) -> Result<(), String> {
    for (name, x) in [("u", u), ("v", v)] {
        if !(*x >= T::zero() && *x <= T::one()) {
            return Err(format!("{name} = {x} is not in [0, 1]"));
        }
    }
    Ok(())
}

fn join<T: Real>(xs: &[T]) -> String {
    xs.iter()
        .map(|c| c.to_roundtrip_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Checks the number count: `params` shape parameters, then `u v` or a point of `dim` coordinates.
pub(super) fn expect<T>(n: &[T], params: usize, inverse: bool, dim: usize) -> Result<(), String> {
    let want = params + if inverse { dim } else { 2 };
    if n.len() == want {
        Ok(())
    } else {
        let tail = if inverse {
            format!("a point of {dim} coordinates")
        } else {
            "u v".to_string()
        };
        Err(format!(
            "expected {want} numbers ({params} parameters, then {tail}), got {}",
            n.len()
        ))
    }
}

pub(super) fn apply<T: Real, W: Warp<T>>(
    w: &W,
    rest: &[T],
    inverse: bool,
) -> Result<String, String> {
    if inverse {
        let mut c = rest.to_vec();
        c.resize(3, T::zero());
        let p = W::Point::from_vec3(Vec3::new(c[0].clone(), c[1].clone(), c[2].clone()));
        let [u, v] = w.inverse(&p).map_err(|e| e.to_string())?;
        Ok(format!(
            "{} {}",
            u.to_roundtrip_string(),
            v.to_roundtrip_string()
        ))
    } else {
        let (u, v) = (&rest[0], &rest[1]);
        check_unit(u, v)?;
        let p = w.map(u, v).to_vec3();
        Ok(join(&[p.x, p.y, p.z][..W::Point::DIM]))
    }
}
