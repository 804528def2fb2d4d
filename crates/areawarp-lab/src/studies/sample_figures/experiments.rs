//! The three experiments: uniform vs jittered samples on a spherical triangle,
//! cosine-weighted samples in a non-convex polygon, Hammersley points on a
//! spherical rectangle; with the geometry they need.

use super::*;

// ---------------------------------------------------------------------------
// Geometry helpers (f64 data)
// ---------------------------------------------------------------------------

pub(crate) fn v3(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}

pub(crate) fn unit(v: &Vec3<f64>) -> Vec3<f64> {
    v.normalized().unwrap_or(*v)
}

pub(crate) fn det(a: &Vec3<f64>, b: &Vec3<f64>, c: &Vec3<f64>) -> f64 {
    a.dot(&b.cross(c))
}

/// The Lambert azimuthal equal-area projection about `c`, seen from the
/// centre of the sphere looking along `c`, with `e1` to the right.
#[derive(Clone, Debug)]
pub(crate) struct EqualArea {
    pub(crate) c: Vec3<f64>,
    pub(crate) e1: Vec3<f64>,
    pub(crate) e2: Vec3<f64>,
}

impl EqualArea {
    /// About the unit direction `c`, with the component of `right` normal
    /// to `c` pointing right.
    pub(crate) fn about(c: &Vec3<f64>, right: &Vec3<f64>) -> Self {
        let c = unit(c);
        let e1 = right
            .sub(&c.scale(&right.dot(&c)))
            .normalized()
            .or_else(|| {
                let h = if c.x.abs() < 0.9 {
                    v3(1.0, 0.0, 0.0)
                } else {
                    v3(0.0, 1.0, 0.0)
                };
                h.sub(&c.scale(&h.dot(&c))).normalized()
            })
            .unwrap_or_else(|| v3(1.0, 0.0, 0.0));
        // Screen up = e1 × c: (e1, e2) is right-handed seen from the centre.
        let e2 = e1.cross(&c);
        EqualArea { c, e1, e2 }
    }

    pub(crate) fn project(&self, d: &Vec3<f64>) -> (f64, f64) {
        let d = unit(d);
        let (x, y) = (d.dot(&self.e1), d.dot(&self.e2));
        let h = x.hypot(y);
        if h == 0.0 {
            return (0.0, 0.0);
        }
        let rho = d.sub(&self.c).norm();
        (rho * x / h, rho * y / h)
    }
}

/// `n + 1` points along the minor great arc from `a` to `b` (normalized
/// linear interpolation: the chord's central projection is the arc).
pub(crate) fn great_arc(a: &Vec3<f64>, b: &Vec3<f64>, n: usize) -> Vec<Vec3<f64>> {
    (0..=n)
        .map(|i| unit(&a.lerp(b, &(i as f64 / n as f64))))
        .collect()
}

/// The closed outline of a polygon with vertex directions `v`, `n` points
/// per edge.
pub(crate) fn outline(v: &[Vec3<f64>], n: usize) -> Vec<Vec3<f64>> {
    let mut out = Vec::with_capacity(v.len() * n + 1);
    for i in 0..v.len() {
        let arc = great_arc(&v[i], &v[(i + 1) % v.len()], n);
        out.extend(arc.into_iter().take(n));
    }
    if let Some(first) = out.first().cloned() {
        out.push(first);
    }
    out
}

/// The fewest and most of `counts`.
pub(crate) fn min_max(counts: &[usize]) -> (usize, usize) {
    (
        counts.iter().copied().min().unwrap_or(0),
        counts.iter().copied().max().unwrap_or(0),
    )
}

/// `"a-b"`: the smallest and largest expected count `N Ω_i / Σ Ω`, 1 decimal.
pub(crate) fn expected_range(omegas: &[f64], n: usize) -> String {
    let total: f64 = omegas.iter().sum();
    let e = |o: f64| n as f64 * o / total;
    let lo = omegas.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = omegas.iter().copied().fold(0.0, f64::max);
    format!("{:.1}-{:.1}", e(lo), e(hi))
}

/// Σ (n_i − N p_i)² / (N p_i) over the cells with p_i > 0.
pub(crate) fn chi_square(counts: &[usize], fractions: &[f64]) -> f64 {
    let n: usize = counts.iter().sum();
    counts
        .iter()
        .zip(fractions)
        .filter(|(_, p)| **p > 0.0)
        .map(|(&c, &p)| {
            let e = n as f64 * p;
            (c as f64 - e).powi(2) / e
        })
        .sum()
}

// ---------------------------------------------------------------------------
// Figure 1: spherical triangle
// ---------------------------------------------------------------------------

/// The four sample sets of a direction map: drawn uniform random (`k²`),
/// drawn `k × k` jittered, measured uniform random (`m²`) and measured
/// `m × m` jittered, each from its own seed.
pub(crate) struct SampleSets {
    pub(crate) random: Vec<Vec3<f64>>,
    pub(crate) jittered: Vec<Vec3<f64>>,
    pub(crate) measure_random: Vec<Vec3<f64>>,
    pub(crate) measure_jittered: Vec<Vec3<f64>>,
}

impl SampleSets {
    pub(crate) fn draw<W: Warp<f64, Point = Vec3<f64>>>(
        w: &W,
        k: usize,
        m: usize,
        seed: u64,
    ) -> Self {
        let random = |n: usize, s: u64| -> Vec<Vec3<f64>> {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(s);
            (0..n)
                .map(|_| {
                    let (u, v) = (rng.random::<f64>(), rng.random::<f64>());
                    w.map(&u, &v)
                })
                .collect()
        };
        let strat = |n: usize, s: u64| -> Vec<Vec3<f64>> {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(s);
            jittered::<f64, _>(n, n, &mut rng)
                .iter()
                .map(|(u, v)| w.map(u, v))
                .collect()
        };
        SampleSets {
            random: random(k * k, seed ^ 0x11),
            jittered: strat(k, seed ^ 0x12),
            measure_random: random(m * m, seed ^ 0x13),
            measure_jittered: strat(m, seed ^ 0x14),
        }
    }

    pub(crate) fn all(&self) -> impl Iterator<Item = &Vec3<f64>> {
        self.random
            .iter()
            .chain(&self.jittered)
            .chain(&self.measure_random)
            .chain(&self.measure_jittered)
    }
}

/// The triangle: vertices in the plane z = 1 (normalized), Ω ≈ 1 sr.
pub(crate) fn triangle_vertices() -> [Vec3<f64>; 3] {
    [
        unit(&v3(-0.95, -0.62, 1.0)),
        unit(&v3(0.98, -0.42, 1.0)),
        unit(&v3(-0.05, 0.98, 1.0)),
    ]
}

/// `4^levels` sub-triangles by midpoint subdivision.
pub(crate) fn subdivide(t: [Vec3<f64>; 3], levels: u32) -> Vec<[Vec3<f64>; 3]> {
    let mut cells = vec![t];
    for _ in 0..levels {
        let mut next = Vec::with_capacity(cells.len() * 4);
        for [a, b, c] in cells {
            let ab = unit(&a.add(&b));
            let bc = unit(&b.add(&c));
            let ca = unit(&c.add(&a));
            next.push([a, ab, ca]);
            next.push([ab, b, bc]);
            next.push([ca, bc, c]);
            next.push([ab, bc, ca]);
        }
        cells = next;
    }
    cells
}

/// The cell containing `d`: the one where `d` is deepest inside (largest
/// smallest edge-plane distance, signed by the orientation), so that points
/// on shared edges are counted once.
pub(crate) fn triangle_cell(cells: &[[Vec3<f64>; 3]], d: &Vec3<f64>) -> usize {
    let mut best = (f64::NEG_INFINITY, 0);
    for (i, [a, b, c]) in cells.iter().enumerate() {
        let s = det(a, b, c).signum();
        let depth = (s * det(a, b, d))
            .min(s * det(b, c, d))
            .min(s * det(c, a, d));
        if depth > best.0 {
            best = (depth, i);
        }
    }
    best.1
}

pub(crate) fn run_triangle(c: &SampleFiguresConfig) -> Result<TriangleSamples, WarpError> {
    let [a, b, cc] = triangle_vertices();
    let tri = SphericalTriangle::<f64>::new(a, b, cc)?;
    let sets = SampleSets::draw(&tri, c.strata, c.measure_strata, c.seed ^ 0x7100);
    let cells = subdivide([a, b, cc], c.triangle_levels);
    let omegas: Vec<f64> = cells
        .iter()
        .map(|[p, q, r]| triangle_solid_angle(p, q, r).abs())
        .collect();
    let total: f64 = omegas.iter().sum();
    let fractions: Vec<f64> = omegas.iter().map(|o| o / total).collect();
    let count = |d: &[Vec3<f64>]| {
        let mut k = vec![0usize; cells.len()];
        for p in d {
            k[triangle_cell(&cells, p)] += 1;
        }
        k
    };
    let random_counts = count(&sets.measure_random);
    let jittered_counts = count(&sets.measure_jittered);
    let max_outside_by = sets.all().map(|p| tri.outside_by(p)).fold(0.0, f64::max);
    Ok(TriangleSamples {
        centre: unit(&a.add(&b).add(&cc)),
        vertices: [a, b, cc],
        solid_angle: tri.solid_angle(),
        random_chi2: chi_square(&random_counts, &fractions),
        jittered_chi2: chi_square(&jittered_counts, &fractions),
        cell_solid_angles: omegas,
        random_counts,
        jittered_counts,
        measure_samples: sets.measure_random.len(),
        random: sets.random,
        jittered: sets.jittered,
        max_outside_by,
    })
}

// ---------------------------------------------------------------------------
// Figure 2: projected (cosine-weighted) non-convex polygon
// ---------------------------------------------------------------------------

/// A comb with three teeth pointing to −y, in the plane z = 1, reaching
/// down to 22° above the horizon (the middle tooth covers the pole).
pub(crate) fn comb() -> Vec<(f64, f64)> {
    vec![
        (-1.9, -1.5),
        (-1.1, -1.5),
        (-1.1, 0.1),
        (-0.4, 0.1),
        (-0.4, -1.5),
        (0.4, -1.5),
        (0.4, 0.1),
        (1.1, 0.1),
        (1.1, -1.5),
        (1.9, -1.5),
        (1.9, 1.7),
        (-1.9, 1.7),
    ]
}

/// Even–odd point-in-polygon test in the plane.
pub(crate) fn inside_polygon(poly: &[(f64, f64)], p: (f64, f64)) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.1 > p.1) != (b.1 > p.1) {
            let x = a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
            if p.0 < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Sutherland–Hodgman clip of `poly` to the box `[x0, x1] × [y0, y1]` (a
/// non-convex polygon may come out with zero-width bridges, which cancel in
/// the signed measures below).
pub(crate) fn clip_to_box(
    poly: &[(f64, f64)],
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
) -> Vec<(f64, f64)> {
    pub(crate) type Inside = fn(&(f64, f64), f64) -> bool;
    pub(crate) type Cut = fn(&(f64, f64), &(f64, f64), f64) -> (f64, f64);
    let cut_x: Cut = |a, b, x| (x, a.1 + (x - a.0) / (b.0 - a.0) * (b.1 - a.1));
    let cut_y: Cut = |a, b, y| (a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0), y);
    let planes: [(Inside, Cut, f64); 4] = [
        (|p, x| p.0 >= x, cut_x, x0),
        (|p, x| p.0 <= x, cut_x, x1),
        (|p, y| p.1 >= y, cut_y, y0),
        (|p, y| p.1 <= y, cut_y, y1),
    ];
    let mut out = poly.to_vec();
    for (inside, cut, k) in planes {
        let input = std::mem::take(&mut out);
        for i in 0..input.len() {
            let (cur, prev) = (&input[i], &input[(i + input.len() - 1) % input.len()]);
            match (inside(cur, k), inside(prev, k)) {
                (true, true) => out.push(*cur),
                (true, false) => {
                    out.push(cut(prev, cur, k));
                    out.push(*cur);
                }
                (false, true) => out.push(cut(prev, cur, k)),
                (false, false) => {}
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// `(|Ω|, |Π|)` of a polygon in the plane z = 1 (signed triangle fan from
/// its first vertex and Lambert's formula; both additive, so zero-width
/// bridges cancel).
pub(crate) fn plane_measures(poly: &[(f64, f64)]) -> (f64, f64) {
    if poly.len() < 3 {
        return (0.0, 0.0);
    }
    let d: Vec<Vec3<f64>> = poly.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
    let omega: f64 = (1..d.len() - 1)
        .map(|i| triangle_solid_angle(&d[0], &d[i], &d[i + 1]))
        .sum();
    let pi = projected_solid_angle(&d, &v3(0.0, 0.0, 1.0));
    (omega.abs(), pi.abs())
}

pub(crate) fn run_polygon(c: &SampleFiguresConfig) -> Result<PolygonSamples, WarpError> {
    let poly = comb();
    let dirs: Vec<Vec3<f64>> = poly.iter().map(|&(x, y)| v3(x, y, 1.0)).collect();
    let warp = ProjectedPolygon::<f64>::new(&dirs)?;
    let sets = SampleSets::draw(&warp, c.strata, c.measure_strata, c.seed ^ 0x9000);
    let n = sets.measure_random.len();
    let plane = |d: &Vec3<f64>| (d.x / d.z, d.y / d.z);
    let inside = |s: &[Vec3<f64>]| {
        s.iter()
            .filter(|d| d.z > 0.0 && inside_polygon(&poly, plane(d)))
            .count()
    };
    // Cells of side `cell` from the polygon's lower-left corner.
    let (x0, y0) = poly.iter().fold((f64::INFINITY, f64::INFINITY), |a, p| {
        (a.0.min(p.0), a.1.min(p.1))
    });
    let (x1, y1) = poly
        .iter()
        .fold((f64::NEG_INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.max(p.0), a.1.max(p.1))
        });
    let cell = c.polygon_cell;
    let cols = (((x1 - x0) / cell).ceil() as usize).max(1);
    let rows = (((y1 - y0) / cell).ceil() as usize).max(1);
    let (omega_total, pi_total) = plane_measures(&poly);
    let mut measures = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            let (a, b) = (x0 + i as f64 * cell, y0 + j as f64 * cell);
            measures.push(plane_measures(&clip_to_box(
                &poly,
                a,
                a + cell,
                b,
                b + cell,
            )));
        }
    }
    // Pool the cells expecting fewer than 5 cosine-weighted samples.
    let pooled = measures.len();
    let slot: Vec<usize> = {
        let mut next = 0;
        measures
            .iter()
            .map(|&(_, p)| {
                if n as f64 * p / pi_total >= 5.0 {
                    next += 1;
                    next - 1
                } else {
                    pooled
                }
            })
            .collect()
    };
    let kept = slot.iter().filter(|&&s| s != pooled).count();
    let has_pool = kept < measures.len();
    let slots = kept + usize::from(has_pool);
    let slot_of = |k: usize| if slot[k] == pooled { kept } else { slot[k] };
    let mut cos_frac = vec![0.0; slots];
    let mut uni_frac = vec![0.0; slots];
    for (k, &(o, p)) in measures.iter().enumerate() {
        cos_frac[slot_of(k)] += p / pi_total;
        uni_frac[slot_of(k)] += o / omega_total;
    }
    let count = |s: &[Vec3<f64>]| {
        let mut counts = vec![0usize; slots];
        for d in s {
            let (x, y) = plane(d);
            let i = (((x - x0) / cell).floor().max(0.0) as usize).min(cols - 1);
            let j = (((y - y0) / cell).floor().max(0.0) as usize).min(rows - 1);
            counts[slot_of(j * cols + i)] += 1;
        }
        counts
    };
    let random_counts = count(&sets.measure_random);
    let jittered_counts = count(&sets.measure_jittered);
    let max_outside_by = sets.all().map(|p| warp.outside_by(p)).fold(0.0, f64::max);
    Ok(PolygonSamples {
        projected_solid_angle: warp.projected_solid_angle(),
        solid_angle: warp.solid_angle(),
        random_inside: inside(&sets.random),
        jittered_inside: inside(&sets.jittered),
        measure_samples: n,
        measure_inside: inside(&sets.measure_random) + inside(&sets.measure_jittered),
        max_outside_by,
        cell,
        random_chi2: chi_square(&random_counts, &cos_frac),
        jittered_chi2: chi_square(&jittered_counts, &cos_frac),
        jittered_chi2_uniform: chi_square(&jittered_counts, &uni_frac),
        cell_fractions: cos_frac,
        cell_fractions_uniform: uni_frac,
        random_counts,
        jittered_counts,
        random: sets.random,
        jittered: sets.jittered,
        vertices: poly,
    })
}

// ---------------------------------------------------------------------------
// Figure 3: spherical rectangle
// ---------------------------------------------------------------------------

/// The rectangle: 2 × 2 on the ground `z = 0`, seen from 0.5 above a point
/// 0.25 before its near edge.
pub(crate) fn rectangle_geometry() -> [Vec3<f64>; 4] {
    [
        v3(-1.0, 0.0, 0.0),
        v3(2.0, 0.0, 0.0),
        v3(0.0, 2.0, 0.0),
        v3(0.0, -0.25, 0.5),
    ]
}

/// Ω of the part `η ∈ [a, b]` of the rectangle (fractions of `e_y`) as two
/// triangles.
pub(crate) fn strip_solid_angle(g: &[Vec3<f64>; 4], a: f64, b: f64) -> f64 {
    let [s, ex, ey, o] = g;
    let p = |xi: f64, eta: f64| s.add(&ex.scale(&xi)).add(&ey.scale(&eta)).sub(o);
    let (p0, p1, p2, p3) = (p(0.0, a), p(1.0, a), p(1.0, b), p(0.0, b));
    triangle_solid_angle(&p0, &p1, &p2).abs() + triangle_solid_angle(&p0, &p2, &p3).abs()
}

pub(crate) fn run_rectangle(c: &SampleFiguresConfig) -> Result<RectangleSamples, WarpError> {
    let g = rectangle_geometry();
    let [s, ex, ey, o] = g;
    let rect = SphericalRectangle::<f64>::new(s, ex, ey, o)?;
    let n = c.hammersley_points;
    let k = 1usize << (n.trailing_zeros() / 2);
    let half = 0.5 / n as f64;
    let uv: Vec<(f64, f64)> = hammersley::<f64>(n)
        .into_iter()
        .map(|(u, v)| (u + half, v + half))
        .collect();
    let mut directions = Vec::with_capacity(n);
    let mut points = Vec::with_capacity(n);
    for (u, v) in &uv {
        let (p, d) = rect.sample_point(u, v);
        points.push(p);
        directions.push(d);
    }
    let area_points: Vec<Vec3<f64>> = uv
        .iter()
        .map(|(u, v)| s.add(&ex.scale(u)).add(&ey.scale(v)))
        .collect();
    // The grid of equal-solid-angle cells: images of u = i/k and v = j/k.
    let steps = 48;
    let mut grid_lines = Vec::with_capacity(2 * k + 2);
    for fixed_u in [true, false] {
        for i in 0..=k {
            let a = i as f64 / k as f64;
            grid_lines.push(
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
    let cells = |pts: &[Vec3<f64>]| -> Vec<usize> {
        let mut counts = vec![0usize; k * k];
        for p in pts {
            if let Ok([u, v]) = rect.inverse(&unit(&p.sub(&o))) {
                let i = ((u * k as f64) as usize).min(k - 1);
                let j = ((v * k as f64) as usize).min(k - 1);
                counts[j * k + i] += 1;
            }
        }
        counts
    };
    let range = |v: &[usize]| {
        (
            v.iter().copied().min().unwrap_or(0),
            v.iter().copied().max().unwrap_or(0),
        )
    };
    let sa_cells = cells(&points);
    let area_cells = cells(&area_points);
    let near_depth = 0.25;
    let omega_tri = strip_solid_angle(&g, 0.0, 1.0);
    let yhat = unit(&ey);
    let eta = |p: &Vec3<f64>| p.sub(&s).dot(&yhat) / ey.norm();
    Ok(RectangleSamples {
        solid_angle: rect.solid_angle(),
        solid_angle_triangles: omega_tri,
        grid: k,
        solid_angle_cells: range(&sa_cells),
        area_cells: range(&area_cells),
        solid_angle_empty_cells: sa_cells.iter().filter(|&&x| x == 0).count(),
        area_empty_cells: area_cells.iter().filter(|&&x| x == 0).count(),
        near_depth,
        near_fraction_exact: strip_solid_angle(&g, 0.0, near_depth) / omega_tri,
        near_count: points.iter().filter(|p| eta(p) < near_depth).count(),
        area_near_count: area_points.iter().filter(|p| eta(p) < near_depth).count(),
        far_fraction_exact: strip_solid_angle(&g, 1.0 - near_depth, 1.0) / omega_tri,
        far_count: points.iter().filter(|p| eta(p) > 1.0 - near_depth).count(),
        area_far_count: area_points
            .iter()
            .filter(|p| eta(p) > 1.0 - near_depth)
            .count(),
        corner: s,
        edge_x: ex,
        edge_y: ey,
        observer: o,
        uv,
        directions,
        points,
        area_points,
        grid_lines,
    })
}
