//! Test-only reference: a polygonal light given as a planar polygon in
//! space, and the exact projected-solid-angle integrals over the part of
//! its spherical projection above the horizon, computed independently of
//! the sampler.
//!
//! Independence: the region is defined by ray casting (a direction is
//! inside when its ray hits the planar polygon, by an even–odd test in the
//! plane), the polygon's intervals on a meridian come from intersecting the
//! meridian's half-plane with the planar edges (segment–plane, not great
//! circles), the inside/outside status of each piece is decided by ray
//! casting at its midpoint, and the horizon is applied by clipping the
//! intervals, not the polygon. No lune constants, no orientation, no
//! Lambert formula. Integrals over the projected region in the unit disk
//! are Gauss–Legendre in φ (composite, split at every vertex and horizon
//! azimuth, where the integrand is not smooth) times closed-form radial
//! integrals.

use crate::vector::Vec3;
use std::f64::consts::PI;

/// A planar polygon in space (coplanar corners, plane not through the origin).
#[derive(Clone, Debug)]
pub struct PlanarLight {
    /// The corners, in order.
    pub points: Vec<Vec3<f64>>,
    normal: Vec3<f64>,
    offset: f64,
    e1: Vec3<f64>,
    e2: Vec3<f64>,
    flat: Vec<(f64, f64)>,
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// Integrals over the projected region: ∫ f dx dy for f = 1, x, y, x², xy, y².
#[derive(Clone, Copy, Debug, Default)]
pub struct Moments {
    pub area: f64,
    pub x: f64,
    pub y: f64,
    pub xx: f64,
    pub xy: f64,
    pub yy: f64,
}

impl PlanarLight {
    pub fn new(points: &[[f64; 3]]) -> Self {
        let points: Vec<Vec3<f64>> = points.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        // Newell's normal.
        let n = points.len();
        let mut nn = Vec3::new(0.0, 0.0, 0.0);
        for i in 0..n {
            let (a, b) = (&points[i], &points[(i + 1) % n]);
            nn = nn.add(&a.cross(b));
        }
        let normal = nn.normalized().expect("planar light normal");
        let offset = normal.dot(&points[0]);
        assert!(offset.abs() > 1e-9, "plane through the origin");
        let seed = if normal.x.abs() < 0.9 {
            Vec3::new(1.0, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 1.0, 0.0)
        };
        let e1 = seed.cross(&normal).normalized().unwrap();
        let e2 = normal.cross(&e1);
        let flat = points.iter().map(|p| (p.dot(&e1), p.dot(&e2))).collect();
        for p in &points {
            assert!((normal.dot(p) - offset).abs() < 1e-12, "non-planar light");
        }
        PlanarLight {
            points,
            normal,
            offset,
            e1,
            e2,
            flat,
        }
    }

    /// Whether the ray along `d` hits the polygon (even–odd rule).
    pub fn inside(&self, d: &Vec3<f64>) -> bool {
        let den = self.normal.dot(d);
        if den == 0.0 {
            return false;
        }
        let t = self.offset / den;
        if !(t > 0.0) || !t.is_finite() {
            return false;
        }
        let x = d.scale(&t);
        let (px, py) = (x.dot(&self.e1), x.dot(&self.e2));
        let n = self.flat.len();
        let mut inside = false;
        for i in 0..n {
            let (ax, ay) = self.flat[i];
            let (bx, by) = self.flat[(i + 1) % n];
            if (ay > py) != (by > py) {
                let xc = ax + (py - ay) * (bx - ax) / (by - ay);
                if px < xc {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// The polygon's intervals `(r²_in, r²_out)` on the half-meridian at
    /// azimuth `phi`, above the horizon, from the pole outwards.
    pub fn intervals(&self, phi: f64) -> Vec<(f64, f64)> {
        let (s, c) = phi.sin_cos();
        let m = Vec3::new(c, s, 0.0);
        let t = Vec3::new(-s, c, 0.0);
        let mut thetas = vec![0.0, PI];
        let n = self.points.len();
        for i in 0..n {
            let (a, b) = (&self.points[i], &self.points[(i + 1) % n]);
            let (da, db) = (t.dot(a), t.dot(b));
            if (da > 0.0 && db > 0.0) || (da < 0.0 && db < 0.0) || da == db {
                continue;
            }
            let lambda = da / (da - db);
            let x = a.add(&b.sub(a).scale(&lambda));
            let h = x.dot(&m);
            if h < 0.0 {
                continue;
            }
            thetas.push(h.atan2(x.z));
        }
        thetas.sort_by(f64::total_cmp);
        let mut out: Vec<(f64, f64)> = Vec::new();
        for w in thetas.windows(2) {
            let (ta, tb) = (w[0], w[1].min(PI / 2.0));
            if !(tb > ta) {
                continue;
            }
            let tm = 0.5 * (ta + tb);
            let d = m.scale(&tm.sin()).add(&Vec3::new(0.0, 0.0, tm.cos()));
            if self.inside(&d) {
                let (ra, rb) = (ta.sin().powi(2), tb.sin().powi(2));
                match out.last_mut() {
                    Some(last) if last.1 == ra => last.1 = rb,
                    _ => out.push((ra, rb)),
                }
            }
        }
        out
    }

    /// Azimuths where the intervals are not smooth functions of φ: the
    /// vertices and the edges' horizon crossings, sorted in [0, 2π], with
    /// both ends.
    fn breakpoints(&self) -> Vec<f64> {
        let az = |p: &Vec3<f64>| {
            let a = p.y.atan2(p.x);
            if a < 0.0 { a + 2.0 * PI } else { a }
        };
        let mut b = vec![0.0, 2.0 * PI];
        let n = self.points.len();
        for i in 0..n {
            let (a, q) = (&self.points[i], &self.points[(i + 1) % n]);
            b.push(az(a));
            if (a.z > 0.0) != (q.z > 0.0) && a.z != q.z {
                let l = a.z / (a.z - q.z);
                b.push(az(&a.add(&q.sub(a).scale(&l))));
            }
        }
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    }

    /// Composite Gauss–Legendre over φ ∈ [0, 2π] (split at the
    /// breakpoints, `panels` panels of `order` nodes each), calling
    /// `f(φ, weight, intervals)` at each node.
    pub fn integrate_phi(
        &self,
        extra: &[f64],
        panels: usize,
        order: usize,
        mut f: impl FnMut(f64, f64, &[(f64, f64)]),
    ) {
        let gl = gauss_legendre(order);
        let mut b = self.breakpoints();
        b.extend_from_slice(extra);
        b.sort_by(f64::total_cmp);
        b.dedup();
        for w in b.windows(2) {
            let h = (w[1] - w[0]) / panels as f64;
            for p in 0..panels {
                let (lo, hi) = (w[0] + p as f64 * h, w[0] + (p + 1) as f64 * h);
                for &(x, wt) in &gl {
                    let phi = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
                    f(phi, 0.5 * (hi - lo) * wt, &self.intervals(phi));
                }
            }
        }
    }

    /// The moments of the projected region.
    pub fn moments(&self) -> Moments {
        let mut m = Moments::default();
        self.integrate_phi(&[], 6, 24, |phi, w, iv| {
            let (s, c) = phi.sin_cos();
            for &(a, b) in iv {
                let r2 = 0.5 * (b - a);
                let r3 = (b * b.sqrt() - a * a.sqrt()) / 3.0;
                let r4 = (b * b - a * a) / 4.0;
                m.area += w * r2;
                m.x += w * c * r3;
                m.y += w * s * r3;
                m.xx += w * c * c * r4;
                m.xy += w * c * s * r4;
                m.yy += w * s * s * r4;
            }
        });
        m
    }

    /// Probabilities of the cells of a grid of `nphi` equal azimuth sectors
    /// × `ns` equal bins in r² (cell index `i·ns + j`).
    pub fn cell_probabilities(&self, nphi: usize, ns: usize) -> Vec<f64> {
        let mut p = vec![0.0; nphi * ns];
        let mut total = 0.0;
        // Sector edges are breakpoints; the r² bin edges cut the integrand
        // at kinks inside a sector, hence the many panels.
        let edges: Vec<f64> = (1..nphi)
            .map(|i| 2.0 * PI * i as f64 / nphi as f64)
            .collect();
        self.integrate_phi(&edges, 16, 8, |phi, w, iv| {
            let sector = ((phi / (2.0 * PI) * nphi as f64) as usize).min(nphi - 1);
            for &(a, b) in iv {
                total += w * 0.5 * (b - a);
                for j in 0..ns {
                    let (lo, hi) = (j as f64 / ns as f64, (j + 1) as f64 / ns as f64);
                    let overlap = (b.min(hi) - a.max(lo)).max(0.0);
                    p[sector * ns + j] += w * 0.5 * overlap;
                }
            }
        });
        for x in &mut p {
            *x /= total;
        }
        p
    }
}
