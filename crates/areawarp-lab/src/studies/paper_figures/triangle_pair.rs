//! Ureña, Fajardo & King 2013, Fig. 5: the triangle-pair panel. The
//! rectangle split along its diagonal into two spherical triangles, one
//! chosen ∝ its solid angle by `u` (rescaled) and sampled by Arvo's map:
//! measure-preserving like the spherical-rectangle map, but its strata are
//! wedges fanning out from a corner of each triangle, cut by the diagonal,
//! so the same Hammersley net no longer puts one point in each compact
//! equal-solid-angle cell.

use super::{Row, describe, png_links};
use crate::figures::{Figure, PALETTE};
use crate::scene::PlanarPolygon;
use crate::scene::strategies::spherical_triangles;
use crate::studies::sample_figures::experiments::{rectangle_geometry, unit};
use crate::studies::sample_figures::output::{Drawing, GRID, Layer, OUTLINE, SAMPLES, SQUARE};
use areawarp::error::WarpError;
use areawarp::estimate::Strategy;
use areawarp::sampling::hammersley;
use areawarp::shapes::SphericalRectangle;
use areawarp::vector::Vec3;
use areawarp::warp::Warp;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// The file stems written.
pub(crate) const STEMS: [&str; 2] = [
    "ufk2013_fig5_triangle_pair",
    "ufk2013_fig5_triangle_pair_on_rectangle_grid",
];

/// The triangle-pair panel and its counts.
#[derive(Clone, Debug, PartialEq)]
pub struct TrianglePairPanel {
    /// The corner `s`, edges `e_x`, `e_y` and the observer (those of the
    /// sample-distribution study's Fig. 5).
    pub geometry: [Vec3<f64>; 4],
    /// The probability of the first triangle (`s, s+e_x, s+e_x+e_y`):
    /// its share of the solid angle.
    pub first_probability: f64,
    /// Cells per side `k` of the equal-solid-angle grids (`k² = N`).
    pub grid: usize,
    /// The Hammersley `(u, v)`, moved to the centres of their `1/N` cells.
    pub uv: Vec<(f64, f64)>,
    /// The points through the triangle pair, on the rectangle.
    pub pair_points: Vec<Vec3<f64>>,
    /// The pair's grid lines (images of `u = i/k` and of `v = j/k`, split
    /// where `u` crosses from one triangle to the other), on the rectangle.
    pub pair_grid: Vec<Vec<Vec3<f64>>>,
    /// The spherical-rectangle map's grid lines, on the rectangle.
    pub rectangle_grid: Vec<Vec<Vec3<f64>>>,
    /// The centres (images of the cell centres) of the spherical-rectangle
    /// map's cells that no pair point falls in.
    pub empty_cell_centres: Vec<Vec3<f64>>,
    /// Fewest and most pair points per cell of the rectangle map's grid.
    pub pair_cells: (usize, usize),
    /// Cells of that grid without a pair point.
    pub pair_empty_cells: usize,
    /// Cells of that grid with two or more pair points.
    pub pair_crowded_cells: usize,
    /// Fewest and most of the rectangle map's own points per cell (1, 1).
    pub rectangle_cells: (usize, usize),
    /// The same counts for `N` independent uniform `(u, v)` through the
    /// rectangle map (min, max, empty), for calibration.
    pub random_cells: (usize, usize, usize),
    /// Σ (n_i − 1)² over the `k²` cells: pair, rectangle map, independent.
    pub chi2: [f64; 3],
    /// The same on the coarser `k/2 × k/2` grid (4 points expected per
    /// cell): pair, rectangle map, independent.
    pub chi2_coarse: [f64; 3],
}

/// `k²` counts of the points (directions from `o`) in the cells of the
/// rectangle map's `k × k` grid.
fn counts(
    rect: &SphericalRectangle<f64>,
    o: &Vec3<f64>,
    pts: &[Vec3<f64>],
    k: usize,
) -> Vec<usize> {
    let mut c = vec![0usize; k * k];
    for p in pts {
        if let Ok([u, v]) = rect.inverse(&unit(&p.sub(o))) {
            let i = ((u * k as f64) as usize).min(k - 1);
            let j = ((v * k as f64) as usize).min(k - 1);
            c[j * k + i] += 1;
        }
    }
    c
}

/// Σ (n_i − e)² / e with `e` the mean count.
fn chi2(c: &[usize]) -> f64 {
    let e = c.iter().sum::<usize>() as f64 / c.len() as f64;
    c.iter().map(|&n| (n as f64 - e).powi(2) / e).sum()
}

/// The `k/2 × k/2` counts from the `k × k` ones.
fn coarse(c: &[usize], k: usize) -> Vec<usize> {
    let h = k / 2;
    let mut out = vec![0usize; h * h];
    for j in 0..k {
        for i in 0..k {
            out[(j / 2) * h + i / 2] += c[j * k + i];
        }
    }
    out
}

pub(crate) fn run(c: &super::PaperFiguresConfig) -> Result<TrianglePairPanel, WarpError> {
    let g = rectangle_geometry();
    let [s, ex, ey, o] = g;
    let polygon = PlanarPolygon::rectangle(s, ex, ey)?;
    let pair = spherical_triangles(&polygon, &o)?;
    let rect = SphericalRectangle::<f64>::new(s, ex, ey, o)?;
    let n = c.hammersley_points;
    let k = 1usize << (n.trailing_zeros() / 2);
    let half = 0.5 / n as f64;
    let uv: Vec<(f64, f64)> = hammersley::<f64>(n)
        .into_iter()
        .map(|(u, v)| (u + half, v + half))
        .collect();
    let normal = *polygon.normal();
    // The point where the ray from o along d meets the light's plane.
    let on_plane = |d: &Vec3<f64>| -> Vec3<f64> {
        let t = s.sub(&o).dot(&normal) / d.dot(&normal);
        o.add(&d.scale(&t))
    };
    let through_pair =
        |u: f64, v: f64| -> Option<Vec3<f64>> { pair.sample(u, v).map(|smp| on_plane(&smp.point)) };
    let pair_points: Vec<Vec3<f64>> = uv.iter().filter_map(|&(u, v)| through_pair(u, v)).collect();
    let rect_points: Vec<Vec3<f64>> = uv.iter().map(|(u, v)| rect.sample_point(u, v).0).collect();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(c.seed ^ 0x5041_4952);
    let random_points: Vec<Vec3<f64>> = (0..n)
        .map(|_| {
            let (u, v) = (rng.random::<f64>(), rng.random::<f64>());
            rect.sample_point(&u, &v).0
        })
        .collect();
    let first_probability = pair.probabilities()[0];

    // Grid lines of the pair: u = i/k (v running), v = j/k (u running,
    // split at the triangle boundary u = c₁, where the map jumps).
    let steps = 48;
    let mut pair_grid = Vec::new();
    for i in 0..=k {
        let a = i as f64 / k as f64;
        let line: Vec<Vec3<f64>> = (0..=steps)
            .filter_map(|t| through_pair(a, t as f64 / steps as f64))
            .collect();
        pair_grid.push(line);
    }
    let fine = 4 * steps;
    for j in 0..=k {
        let b = j as f64 / k as f64;
        let mut first = Vec::new();
        let mut second = Vec::new();
        for t in 0..=fine {
            let a = t as f64 / fine as f64;
            // Each piece up to and including its own end of [0, c₁], [c₁, 1].
            let ends = [(0.0, first_probability), (first_probability, 1.0)];
            for (side, (lo, hi)) in ends.iter().enumerate() {
                let x = lo + (hi - lo) * a;
                let x = if side == 0 {
                    x.min(first_probability * (1.0 - 1e-12))
                } else {
                    x
                };
                if let Some(p) = through_pair(x, b) {
                    if side == 0 {
                        first.push(p);
                    } else {
                        second.push(p);
                    }
                }
            }
        }
        pair_grid.push(first);
        pair_grid.push(second);
    }
    let mut rectangle_grid = Vec::new();
    for fixed_u in [true, false] {
        for i in 0..=k {
            let a = i as f64 / k as f64;
            rectangle_grid.push(
                (0..=steps)
                    .map(|t| {
                        let b = t as f64 / steps as f64;
                        let (u, v) = if fixed_u { (a, b) } else { (b, a) };
                        rect.sample_point(&u, &v).0
                    })
                    .collect(),
            );
        }
    }
    let pc = counts(&rect, &o, &pair_points, k);
    let rc = counts(&rect, &o, &rect_points, k);
    let xc = counts(&rect, &o, &random_points, k);
    let empty_cell_centres = pc
        .iter()
        .enumerate()
        .filter(|(_, n)| **n == 0)
        .map(|(idx, _)| {
            let (i, j) = (idx % k, idx / k);
            let (u, v) = ((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64);
            rect.sample_point(&u, &v).0
        })
        .collect();
    let mm = |c: &[usize]| {
        (
            c.iter().copied().min().unwrap_or(0),
            c.iter().copied().max().unwrap_or(0),
        )
    };
    Ok(TrianglePairPanel {
        geometry: g,
        first_probability,
        grid: k,
        pair_cells: mm(&pc),
        pair_empty_cells: pc.iter().filter(|&&x| x == 0).count(),
        pair_crowded_cells: pc.iter().filter(|&&x| x >= 2).count(),
        rectangle_cells: mm(&rc),
        random_cells: (mm(&xc).0, mm(&xc).1, xc.iter().filter(|&&x| x == 0).count()),
        chi2: [chi2(&pc), chi2(&rc), chi2(&xc)],
        chi2_coarse: [
            chi2(&coarse(&pc, k)),
            chi2(&coarse(&rc, k)),
            chi2(&coarse(&xc, k)),
        ],
        uv,
        pair_points,
        pair_grid,
        rectangle_grid,
        empty_cell_centres,
    })
}

impl TrianglePairPanel {
    /// Rectangle coordinates `(x, y)` along `e_x`, `e_y` from the corner.
    fn flat(&self, p: &Vec3<f64>) -> (f64, f64) {
        let [s, ex, ey, _] = &self.geometry;
        let q = p.sub(s);
        (q.dot(&unit(ex)), q.dot(&unit(ey)))
    }

    pub(crate) fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        let [s, ex, ey, o] = &self.geometry;
        let n = self.pair_points.len();
        let k = self.grid;
        let diagonal = vec![self.flat(s), self.flat(&s.add(ex).add(ey))];
        let outline: Vec<(f64, f64)> = [*s, s.add(ex), s.add(ex).add(ey), s.add(ey), *s]
            .iter()
            .map(|p| self.flat(p))
            .collect();
        let grid = |lines: &[Vec<Vec3<f64>>]| -> Vec<Layer> {
            lines
                .iter()
                .filter(|l| l.len() >= 2)
                .map(|l| {
                    (
                        String::new(),
                        l.iter().map(|p| self.flat(p)).collect(),
                        GRID,
                    )
                })
                .collect()
        };
        let pts: Vec<(f64, f64)> = self.pair_points.iter().map(|p| self.flat(p)).collect();
        let foot = self.flat(&Vec3::new(o.x, o.y, s.z));
        let mut out = Vec::new();

        let mut lines = grid(&self.pair_grid);
        lines.push(("rectangle".into(), outline.clone(), OUTLINE));
        lines.push(("diagonal (shared edge)".into(), diagonal.clone(), OUTLINE));
        let d = Drawing {
            title: format!(
                "{n} Hammersley points through the triangle pair, pulled back to the rectangle"
            ),
            x: format!(
                "x along e_x    (red: the pair's {k} × {k} cells of equal solid angle; orange: the observer's foot)"
            ),
            y: "y along e_y (away from the observer)".into(),
            size: SQUARE,
            lines,
            dots: vec![
                (String::new(), pts.clone(), SAMPLES),
                (String::new(), vec![foot], PALETTE[1]),
            ],
        };
        out.extend(describe(
            d.write(dir, STEMS[0])?,
            &format!(
                "Ureña, Fajardo & King 2013, Fig. 5, triangle-pair panel re-made: {n} Hammersley points sent through \
                 the pair of spherical triangles (diagonal drawn black) and pulled back to the 2 × 2 rectangle on the \
                 ground; the red curves are the pair's own {k} × {k} grid of equal solid angle, thin wedges fanning \
                 out from a corner of each triangle and broken at the diagonal"
            ),
        ));

        let mut lines = grid(&self.rectangle_grid);
        lines.push(("rectangle".into(), outline, OUTLINE));
        lines.push((String::new(), diagonal, OUTLINE));
        let holes: Vec<(f64, f64)> = self
            .empty_cell_centres
            .iter()
            .map(|p| self.flat(p))
            .collect();
        let d = Drawing {
            title: format!(
                "the same {n} pair points over the spherical-rectangle map's grid: {} empty cells",
                self.pair_empty_cells
            ),
            x: format!(
                "x along e_x    (red: the rectangle map's {k} × {k} cells of equal solid angle; orange: empty cells)"
            ),
            y: "y along e_y (away from the observer)".into(),
            size: SQUARE,
            lines,
            dots: vec![
                (String::new(), pts, SAMPLES),
                (String::new(), holes, PALETTE[1]),
            ],
        };
        out.extend(describe(
            d.write(dir, STEMS[1])?,
            &format!(
                "The triangle pair's {n} points over the spherical-rectangle map's {k} × {k} grid of equal solid \
                 angle on the rectangle: the rectangle map puts exactly one point in every cell, the pair leaves \
                 {} cells empty (orange dots) and puts two or more points in {}",
                self.pair_empty_cells, self.pair_crowded_cells
            ),
        ));
        Ok(out)
    }

    pub(crate) fn to_markdown(&self) -> String {
        let mut s = String::new();
        let n = self.pair_points.len();
        let k = self.grid;
        let h = k / 2;
        let _ = writeln!(
            s,
            "### Why the triangle pair loses stratification (Ureña, Fajardo & King 2013, Fig. 5, triangle-pair panel)\n"
        );
        let _ = writeln!(
            s,
            "**The paper:** 256 Hammersley points through each mapping, projected back onto the rectangle, with \
             the red grid of equal-solid-angle cells; the triangle pair (Arvo's map on the two halves of the \
             rectangle, one chosen ∝ its solid angle) \"does not preserve sample stratification as well\", which \
             the paper gives as the reason for its slower convergence. **Ours:** the same rectangle and points as \
             the spherical-rectangle and area panels above, sent \
             through `strategies::spherical_triangles` — the triangle-pair sampler of the variance study: the \
             first triangle gets u < {c1:.3} (its share of Ω), and u is rescaled. The pair is measure-preserving \
             too: each of its own cells (red, first figure) holds one point. But those cells are wedges fanning out from a \
             corner of each triangle and cut by the diagonal, and its strata no longer match the compact cells of \
             the spherical-rectangle map. **Measured:** points per cell of the spherical-rectangle map's \
             {k} × {k} grid (1 expected) and of its {h} × {h} coarsening (4 expected); Σ(n_i − e)²/e is 0 for \
             a perfectly stratified set and about the number of cells for independent points.\n",
            c1 = self.first_probability,
        );
        s.push_str(&super::image_lines(&[
            ("triangle pair", "ufk2013_fig5_triangle_pair"),
            (
                "triangle pair over the rectangle grid",
                "ufk2013_fig5_triangle_pair_on_rectangle_grid",
            ),
        ]));
        let [cp, cr, cx] = self.chi2;
        let [qp, qr, qx] = self.chi2_coarse;
        let _ = writeln!(
            s,
            "| {n} points | per cell, {k}×{k} grid (min–max) | empty cells | cells with ≥ 2 | Σ(n−e)²/e, {k}×{k} ({kk} cells) | Σ(n−e)²/e, {h}×{h} ({hh} cells) |\n\
             |---|---:|---:|---:|---:|---:|\n\
             | spherical rectangle map, Hammersley | {}–{} | 0 | 0 | {cr:.1} | {qr:.1} |\n\
             | triangle pair, Hammersley | {}–{} | {} | {} | {cp:.1} | {qp:.1} |\n\
             | spherical rectangle map, independent (u, v) | {}–{} | {} | — | {cx:.1} | {qx:.1} |\n",
            self.rectangle_cells.0,
            self.rectangle_cells.1,
            self.pair_cells.0,
            self.pair_cells.1,
            self.pair_empty_cells,
            self.pair_crowded_cells,
            self.random_cells.0,
            self.random_cells.1,
            self.random_cells.2,
            kk = k * k,
            hh = h * h,
        );
        let _ = writeln!(
            s,
            "The pair's points are better spread than independent ones but no longer one per compact cell: \
             this is the loss of stratification the paper blames for the pair's slower convergence, which the \
             variance tables above measure. PNG: {}. Data: `paper_figures.csv`.\n",
            png_links(&STEMS)
        );
        s
    }

    pub(crate) fn rows(&self) -> Vec<Row> {
        let f = "UFK13 Fig. 5 triangle pair";
        let k = self.grid;
        let r = |a: (usize, usize)| format!("{}-{}", a.0, a.1);
        vec![
            (
                f,
                "probability of the first triangle (solid-angle share)".into(),
                format!("{:.6}", self.first_probability),
                String::new(),
            ),
            (
                f,
                format!(
                    "pair points per cell of the rectangle map's {k}x{k} grid (min-max); reference: rectangle map"
                ),
                r(self.pair_cells),
                r(self.rectangle_cells),
            ),
            (
                f,
                "cells without a pair point; reference: independent points".into(),
                self.pair_empty_cells.to_string(),
                self.random_cells.2.to_string(),
            ),
            (
                f,
                "cells with two or more pair points".into(),
                self.pair_crowded_cells.to_string(),
                String::new(),
            ),
            (
                f,
                format!(
                    "sum (n-e)^2/e over {} cells, pair; reference: independent points",
                    k * k
                ),
                format!("{:.2}", self.chi2[0]),
                format!("{:.2}", self.chi2[2]),
            ),
            (
                f,
                format!(
                    "sum (n-e)^2/e over {} cells, pair; reference: independent points",
                    k * k / 4
                ),
                format!("{:.2}", self.chi2_coarse[0]),
                format!("{:.2}", self.chi2_coarse[2]),
            ),
        ]
    }
}
