//! The report's first section, the warps overview: every warp's Jacobian
//! at 256 bits, its precision in `f32`/`f64` against 256 bits, its round
//! trip and its speed per sample, in one table and a CSV.

use super::report::Size;
use areawarp::harness::extremes::{extremes_grid, random_points};
use areawarp::harness::{jacobian, precision, roundtrip};
use areawarp::real::{Mpfr256, Real};
use areawarp::shapes::{
    ConcentricDisk, Hemisphere, PhongLobe, PlanarTriangle, PolarDisk, ProjectedPolygon, Sphere,
    SphericalRectangle, SphericalRectangleVariant, SphericalTriangle, SphericalTriangleVariant,
};
use areawarp::{Vec3, Warp, WarpError, WarpFamily};
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

/// One warp's measured row.
struct Row {
    name: String,
    jacobian_max_dev: f64,
    f64_max_ulps: f64,
    f64_median_ulps: f64,
    f64_bad: usize,
    f32_max_ulps: f64,
    f32_median_ulps: f64,
    f32_bad: usize,
    roundtrip_f64: f64,
    ns_f32: f64,
    ns_f64: f64,
    ns_mpfr: f64,
}

/// The first section: every warp's precision, Jacobian and speed at a glance.
pub(super) fn overview(
    out: &Path,
    size: Size,
) -> Result<(String, bool), Box<dyn std::error::Error>> {
    let mut points = extremes_grid();
    let (random, reps) = match size {
        Size::Quick => (200, 3),
        Size::Default => (2000, 7),
        Size::Large => (8000, 15),
    };
    points.extend(random_points(random, 1));
    let v = |x: f64, y: f64, z: f64| Vec3::<f64>::from_f64(x, y, z);
    let mut rows = vec![
        study(
            &PlanarTriangle::new(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.25, 1.0, 0.0))?,
            "planar-triangle (unit)",
            &points,
            reps,
        )?,
        study(
            &PlanarTriangle::new(v(1.0, 2.0, 3.0), v(-2.0, 0.5, 1.0), v(0.5, -1.0, 2.0))?,
            "planar-triangle (3-D)",
            &points,
            reps,
        )?,
        study(&PolarDisk::<f64>::new(), "disk (polar)", &points, reps)?,
        study(
            &ConcentricDisk::<f64>::new(),
            "concentric-disk",
            &points,
            reps,
        )?,
        study(&Hemisphere::<f64>::new(), "hemisphere", &points, reps)?,
    ];
    for k in [0.0, 1.0, 1000.0, 1e6] {
        rows.push(study(
            &PhongLobe::new(k)?,
            &format!("phong k={k}"),
            &points,
            reps,
        )?);
    }
    rows.push(study(
        &Sphere::<f64>::new(),
        "sphere (Archimedes)",
        &points,
        reps,
    )?);
    let (a, b, c) = (v(1.0, 0.1, 0.2), v(0.2, 1.0, 0.1), v(0.1, 0.3, 1.0));
    for (variant, label) in [
        (SphericalTriangleVariant::Robust, "robust"),
        (SphericalTriangleVariant::Literal, "literal"),
    ] {
        let w = SphericalTriangle::new_with(a, b, c, variant)?;
        rows.push(study(
            &w,
            &format!("spherical-triangle ({label})"),
            &points,
            reps,
        )?);
    }
    let (s0, ex, ey, o) = (
        v(-1.0, -0.5, 1.0),
        v(2.0, 0.0, 0.0),
        v(0.0, 1.5, 0.0),
        v(0.2, 0.1, 0.0),
    );
    for (variant, label) in [
        (SphericalRectangleVariant::Robust, "robust"),
        (SphericalRectangleVariant::Literal, "literal"),
    ] {
        let w = SphericalRectangle::new_with(s0, ex, ey, o, variant)?;
        rows.push(study(
            &w,
            &format!("spherical-rectangle ({label})"),
            &points,
            reps,
        )?);
    }
    let square = [
        v(1.0, 0.0, 0.3),
        v(0.0, 1.0, 0.6),
        v(-1.0, 0.0, 0.3),
        v(0.0, -1.0, 0.6),
    ];
    rows.push(study(
        &ProjectedPolygon::new(&square)?,
        "projected-polygon (Newton)",
        &points,
        reps,
    )?);

    let md = render(&rows, points.len());
    std::fs::write(out.join("warps.csv"), render_csv(&rows))?;
    println!("{md}");
    // The papers' literal algorithms are baselines, expected to fail at the extremes.
    let ok = rows
        .iter()
        .filter(|r| !r.name.contains("literal"))
        .all(|r| r.jacobian_max_dev <= 1e-60 && r.f64_bad == 0 && r.f32_bad == 0);
    Ok((md, ok))
}

fn study<W: WarpFamily<f64>>(
    w: &W,
    name: &str,
    points: &[(f64, f64)],
    reps: usize,
) -> Result<Row, WarpError> {
    let jac = jacobian::check_jacobian(w, &extremes_grid())?;
    let p64 = precision::check_precision::<f64, W>(w, points)?;
    let p32 = precision::check_precision::<f32, W>(w, points)?;
    let rt = roundtrip::check_roundtrip::<f64, W>(w, &interior(points))?;
    Ok(Row {
        name: name.to_string(),
        jacobian_max_dev: jac.max_rel_deviation,
        f64_max_ulps: p64.max_ulps,
        f64_median_ulps: p64.median_ulps,
        f64_bad: p64.non_finite + p64.outside,
        f32_max_ulps: p32.max_ulps,
        f32_median_ulps: p32.median_ulps,
        f32_bad: p32.non_finite + p32.outside,
        roundtrip_f64: rt.max_error,
        ns_f32: time_map(&w.at::<f32>()?, 20_000, reps),
        ns_f64: time_map(&w.at::<f64>()?, 20_000, reps),
        ns_mpfr: time_map(&w.at::<Mpfr256>()?, 500, reps),
    })
}

/// Points away from the edges u, v ∈ {0, 1}, where inverses are singular for some warps.
fn interior(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|&(u, v)| u > 1e-9 && u < 1.0 - 1e-9 && v > 1e-9 && v < 1.0 - 1e-9)
        .collect()
}

/// Median over `reps` runs of the time per sample of `n` map evaluations.
fn time_map<T: Real, W: Warp<T>>(w: &W, n: usize, reps: usize) -> f64 {
    let inputs: Vec<(T, T)> = random_points(n, 7)
        .into_iter()
        .map(|(u, v)| (T::from_f64(u), T::from_f64(v)))
        .collect();
    let mut times: Vec<f64> = (0..reps)
        .map(|_| {
            let start = Instant::now();
            for (u, v) in &inputs {
                black_box(w.map(black_box(u), black_box(v)));
            }
            start.elapsed().as_secs_f64() * 1e9 / n as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn render(rows: &[Row], npoints: usize) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## Warps at a glance\n");
    let _ = writeln!(
        s,
        "Every warp checked over the extremes grid (u, v ∈ {{0, 2⁻⁶⁰, 1e-12, 1e-6, ½, 1−1e-6, 1−1e-12, 1}}²) \
         plus random points ({npoints} points in all). Errors are max-norm distances to the 256-bit map at the \
         same inputs, divided by the shape's extent, in units of the type's unit roundoff (2⁻²⁴ for f32, \
         2⁻⁵³ for f64). The Jacobian column is max |ψ_u × ψ_v| · pdf(ψ) − 1 over the extremes grid, \
         computed at 256 bits with dual numbers. \"bad\" counts NaN/Inf outputs and points off the shape.\n"
    );
    let _ = writeln!(s, "### Precision and Jacobian\n");
    let _ = writeln!(
        s,
        "| warp | Jacobian dev. (256 bits) | f64 max ulps | f64 median | f64 bad | f32 max ulps | f32 median | f32 bad | f64 round trip |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {:.1e} | {:.2} | {:.2} | {} | {:.2} | {:.2} | {} | {:.1e} |",
            r.name,
            r.jacobian_max_dev,
            r.f64_max_ulps,
            r.f64_median_ulps,
            r.f64_bad,
            r.f32_max_ulps,
            r.f32_median_ulps,
            r.f32_bad,
            r.roundtrip_f64
        );
    }
    let _ = writeln!(
        s,
        "\n### Speed (ns per sample, median of repeated runs, this machine)\n"
    );
    let _ = writeln!(s, "| warp | f32 | f64 | mpfr:256 | mpfr / f64 |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.1} | {:.0} | {:.0}× |",
            r.name,
            r.ns_f32,
            r.ns_f64,
            r.ns_mpfr,
            r.ns_mpfr / r.ns_f64
        );
    }
    let _ = writeln!(
        s,
        "\nTimings come from one run on a shared machine: compare ratios within this table, not across runs."
    );
    s
}

fn render_csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "warp,jacobian_dev,f64_max_ulps,f64_median_ulps,f64_bad,f32_max_ulps,f32_median_ulps,f32_bad,roundtrip_f64,ns_f32,ns_f64,ns_mpfr256\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{:e},{},{},{},{},{},{},{:e},{},{},{}",
            r.name,
            r.jacobian_max_dev,
            r.f64_max_ulps,
            r.f64_median_ulps,
            r.f64_bad,
            r.f32_max_ulps,
            r.f32_median_ulps,
            r.f32_bad,
            r.roundtrip_f64,
            r.ns_f32,
            r.ns_f64,
            r.ns_mpfr
        );
    }
    s
}
