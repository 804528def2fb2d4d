//! Arvo 2001, Fig. 1.9: the cumulative marginal distribution F(φ) of the
//! projected-polygon map — the fraction of the projected solid angle
//! between the first vertex meridian and azimuth φ — for the non-convex
//! comb of Arvo's Fig. 1.11 (the sample-distribution study's polygon),
//! evaluated by the map itself ([`ProjectedPolygon::marginal_cdf`]), with
//! Arvo's Vandermonde-cubic inverse ([`MarginalInversion::Cubic`]).

use super::{Row, describe, png_links};
use crate::figures::{self, Axis, Figure, Marker, PALETTE, Plot, Series};
use crate::studies::sample_figures::experiments::{comb, v3};
use crate::studies::sample_figures::output::dots;
use areawarp::error::WarpError;
use areawarp::shapes::{MarginalInversion, ProjectedPolygon};
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// The file stems written.
pub(crate) const STEMS: [&str; 2] = [
    "arvo2001_fig1_9_marginal_cdf",
    "arvo2001_fig1_9_fluctuation_and_inversion_error",
];

/// Points of the cubic's inverse drawn on the CDF.
const CUBIC_DOTS: usize = 48;

/// Fig. 1.9 and its numbers. Azimuths are relative to φ₀, the first
/// lune's meridian, in radians.
#[derive(Clone, Debug, PartialEq)]
pub struct MarginalCdf {
    /// The polygon's vertices in the plane `z = 1`.
    pub vertices: Vec<(f64, f64)>,
    /// φ₀, the azimuth where F = 0.
    pub phi0: f64,
    /// Lunes of positive area.
    pub lunes: usize,
    /// The curve `(φ − φ₀, F(φ))`.
    pub curve: Vec<(f64, f64)>,
    /// The vertex meridians `(θ_i − φ₀, F(θ_i))`, sorted.
    pub breakpoints: Vec<(f64, f64)>,
    /// `(φ̂ − φ₀, u)` with φ̂ from the cubic inverse, for `u` on a grid.
    pub cubic_points: Vec<(f64, f64)>,
    /// `(φ − φ₀, |F(φ) − chord|)`: F's deviation from the straight line
    /// between its values at the neighbouring vertex meridians.
    pub fluctuation: Vec<(f64, f64)>,
    /// `(φ̂ − φ₀, |u − F(φ̂)|)` for the cubic inverse.
    pub cubic_error: Vec<(f64, f64)>,
    /// `(φ̂ − φ₀, |u − F(φ̂)|)` for Newton's inverse (the default).
    pub newton_error: Vec<(f64, f64)>,
    /// Steps of the plotted curve where F decreases (0: monotone).
    pub decreasing_steps: usize,
}

impl MarginalCdf {
    /// The largest deviation of F from its chords.
    pub fn max_fluctuation(&self) -> f64 {
        self.fluctuation.iter().map(|p| p.1).fold(0.0, f64::max)
    }
    /// The largest backward error of the cubic inverse.
    pub fn max_cubic_error(&self) -> f64 {
        self.cubic_error.iter().map(|p| p.1).fold(0.0, f64::max)
    }
    /// The largest backward error of Newton's inverse.
    pub fn max_newton_error(&self) -> f64 {
        self.newton_error.iter().map(|p| p.1).fold(0.0, f64::max)
    }
}

pub(crate) fn run(c: &super::PaperFiguresConfig) -> Result<MarginalCdf, WarpError> {
    let vertices = comb();
    let dirs: Vec<_> = vertices.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
    let newton = ProjectedPolygon::<f64>::new(&dirs)?;
    let cubic = newton.clone().with_inversion(MarginalInversion::Cubic);
    let phi0 = newton.azimuth(&0.0);
    let f = |rel: f64| -> f64 {
        if rel >= TAU {
            1.0
        } else {
            newton.marginal_cdf(&(phi0 + rel))
        }
    };
    let m = c.cdf_points;
    let curve: Vec<(f64, f64)> = (0..=m)
        .map(|i| {
            let rel = TAU * i as f64 / m as f64;
            (rel, f(rel))
        })
        .collect();
    let decreasing_steps = curve.windows(2).filter(|w| w[1].1 < w[0].1).count();
    let mut thetas: Vec<f64> = vertices
        .iter()
        .map(|&(x, y)| (y.atan2(x) - phi0).rem_euclid(TAU))
        .collect();
    thetas.push(TAU);
    thetas.sort_by(f64::total_cmp);
    thetas.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let breakpoints: Vec<(f64, f64)> = thetas.iter().map(|&t| (t, f(t))).collect();
    let chord = |rel: f64| -> f64 {
        let i = breakpoints
            .partition_point(|b| b.0 <= rel)
            .clamp(1, breakpoints.len() - 1);
        let (a, b) = (breakpoints[i - 1], breakpoints[i]);
        if b.0 > a.0 {
            a.1 + (b.1 - a.1) * (rel - a.0) / (b.0 - a.0)
        } else {
            a.1
        }
    };
    let fluctuation = curve
        .iter()
        .map(|&(x, y)| (x, (y - chord(x)).abs()))
        .collect();
    let inverse_error = |w: &ProjectedPolygon<f64>, n: usize| -> Vec<(f64, f64)> {
        (0..n)
            .map(|j| {
                let u = (j as f64 + 0.5) / n as f64;
                let rel = w.azimuth(&u) - phi0;
                (rel, (u - f(rel)).abs())
            })
            .collect()
    };
    let cubic_points = (0..CUBIC_DOTS)
        .map(|j| {
            let u = (j as f64 + 0.5) / CUBIC_DOTS as f64;
            (cubic.azimuth(&u) - phi0, u)
        })
        .collect();
    Ok(MarginalCdf {
        lunes: newton.lune_count(),
        phi0,
        curve,
        breakpoints,
        cubic_points,
        fluctuation,
        cubic_error: inverse_error(&cubic, m),
        newton_error: inverse_error(&newton, m),
        decreasing_steps,
        vertices,
    })
}

impl MarginalCdf {
    pub(crate) fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        let deg = |v: &[(f64, f64)]| -> Vec<(f64, f64)> {
            v.iter().map(|&(x, y)| (x.to_degrees(), y)).collect()
        };
        let x = "azimuth φ − φ₀ (degrees; Arvo's θ)";
        let mut line = Series::new("F(φ), closed form (the map's marginal)", deg(&self.curve))
            .with_color(PALETTE[0]);
        line.markers = false;
        let plot = Plot::new(
            "Arvo 2001, Fig. 1.9: the marginal CDF of the projected comb",
            Axis::linear(x).with_range(0.0, 360.0),
            Axis::linear("F(φ): fraction of the projected solid angle").with_range(0.0, 1.0),
        )
        .size(760, 520)
        .series(line)
        .series(
            dots(
                "vertex meridians θ_i (breakpoints)",
                &deg(&self.breakpoints),
                PALETTE[3],
            )
            .marker(Marker::Square),
        )
        .series(
            dots(
                "(F̂⁻¹(u), u): Arvo's cubic inverse",
                &deg(&self.cubic_points),
                PALETTE[2],
            )
            .marker(Marker::Cross),
        )
        .point_radius(3.5);
        let alt = format!(
            "Arvo 2001, Fig. 1.9 re-made: the cumulative marginal F(φ) of cosine-weighted sampling of the \
             {}-vertex non-convex comb, computed by areawarp's projected-polygon map, rising monotonically \
             from 0 to 1 over one turn of azimuth with a kink at each of the {} vertex meridians (red squares); \
             green crosses: azimuths from Arvo's Vandermonde cubic inverse, on the curve",
            self.vertices.len(),
            self.breakpoints.len() - 1
        );
        let mut out = vec![
            figures::write_line_plot_svg(&dir.join(format!("{}.svg", STEMS[0])), &plot)?,
            figures::write_line_plot_png(&dir.join(format!("{}.png", STEMS[0])), &plot)?,
        ];
        out = describe(out, &alt);

        let pos = |v: &[(f64, f64)]| -> Vec<(f64, f64)> {
            v.iter()
                .filter(|p| p.1 > 0.0)
                .map(|&(x, y)| (x.to_degrees(), y))
                .collect()
        };
        let mut fl = Series::new(
            "|F − chord between vertex meridians|",
            pos(&self.fluctuation),
        )
        .with_color(PALETTE[0]);
        fl.markers = false;
        let mut cu = Series::new("cubic inverse: |u − F(F̂⁻¹(u))|", pos(&self.cubic_error))
            .with_color(PALETTE[2]);
        cu.markers = false;
        let mut nw = Series::new(
            "Newton inverse (default): |u − F(F̂⁻¹(u))|",
            pos(&self.newton_error),
        )
        .with_color(PALETTE[4]);
        nw.markers = false;
        let plot = Plot::new(
            "F's departure from its chords, and the inverses' backward error",
            Axis::linear(x).with_range(0.0, 360.0),
            Axis::log("fraction of the projected solid angle"),
        )
        .size(760, 520)
        .series(fl)
        .series(cu)
        .series(nw);
        let alt = format!(
            "The real size of Fig. 1.9's fluctuations: F departs from the straight chords between vertex \
             meridians by at most {:.1e} of the projected solid angle (blue), Arvo's cubic inverse misses \
             F by up to {:.1e} (green), Newton's inverse by {:.1e} (violet; zeros not drawn), on a log scale \
             against azimuth",
            self.max_fluctuation(),
            self.max_cubic_error(),
            self.max_newton_error()
        );
        let more = vec![
            figures::write_line_plot_svg(&dir.join(format!("{}.svg", STEMS[1])), &plot)?,
            figures::write_line_plot_png(&dir.join(format!("{}.png", STEMS[1])), &plot)?,
        ];
        out.extend(describe(more, &alt));
        Ok(out)
    }

    pub(crate) fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "### The marginal CDF of the projected-polygon map (Arvo 2001, Fig. 1.9)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** F(θ), the form factor of the part of the polygon between the first vertex meridian \
             and azimuth θ (normalized), \"strictly monotonically increasing, with at most n − 2 derivative \
             discontinuities\" at the vertex meridians θ_i, its \"fluctuations greatly exaggerated for purposes \
             of illustration\"; F is inverted per lune by a cubic through four of its values (eqs. 1.56–1.57), \
             and Newton's method is \"not warranted\". **Ours:** `ProjectedPolygon::marginal_cdf` — the map's \
             own closed-form F, the function its first step inverts — for the {}-vertex comb of the \
             cosine-weighted sample figure above (receiver normal +z, the pole inside), {} points over one \
             turn from φ₀ = {:.2}°, where F = 0. Green crosses: azimuths from `MarginalInversion::Cubic` (our \
             cubics are fitted per half-lune in a variable that removes the square-root singularity at \
             extremal vertices: a departure from Arvo's one cubic per lune). **Measured:** monotonicity, \
             F's true departure from its chords (what the paper's drawing exaggerates), and the backward \
             error |u − F(F̂⁻¹(u))| of the cubic and of the default Newton inverse.\n",
            self.vertices.len(),
            self.curve.len(),
            self.phi0.to_degrees()
        );
        s.push_str(&super::image_lines(&[
            ("the marginal CDF", "arvo2001_fig1_9_marginal_cdf"),
            (
                "fluctuations and inversion errors",
                "arvo2001_fig1_9_fluctuation_and_inversion_error",
            ),
        ]));
        let _ = writeln!(
            s,
            "| vertices | lunes | breakpoints in (0, 2π) | steps where F decreases | max \\|F − chord\\| | max backward error, cubic | max backward error, Newton |\n\
             |---:|---:|---:|---:|---:|---:|---:|\n\
             | {} | {} | {} | {} | {:.2e} | {:.2e} | {:.2e} |\n",
            self.vertices.len(),
            self.lunes,
            self.breakpoints.len().saturating_sub(2),
            self.decreasing_steps,
            self.max_fluctuation(),
            self.max_cubic_error(),
            self.max_newton_error()
        );
        let _ = writeln!(
            s,
            "Between its breakpoints F is within {:.1e} of a straight line: drawn to scale, the curve is a \
             polygonal line (hence the paper's exaggeration), and a cubic per half-lune already inverts it \
             to {:.0e}. PNG: {}.\n",
            self.max_fluctuation(),
            self.max_cubic_error(),
            png_links(&STEMS)
        );
        s
    }

    pub(crate) fn rows(&self) -> Vec<Row> {
        let f = "Arvo 2001 Fig. 1.9";
        vec![
            (
                f,
                "lunes of positive area".into(),
                self.lunes.to_string(),
                String::new(),
            ),
            (
                f,
                "steps where F decreases; reference: 0 (monotone)".into(),
                self.decreasing_steps.to_string(),
                "0".into(),
            ),
            (
                f,
                "max |F - chord between vertex meridians|".into(),
                format!("{:e}", self.max_fluctuation()),
                String::new(),
            ),
            (
                f,
                "max backward error |u - F(F^-1(u))|, cubic".into(),
                format!("{:e}", self.max_cubic_error()),
                String::new(),
            ),
            (
                f,
                "max backward error |u - F(F^-1(u))|, Newton".into(),
                format!("{:e}", self.max_newton_error()),
                String::new(),
            ),
        ]
    }
}
