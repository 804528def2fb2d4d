//! Planar emitters with constant radiance or a rectangular radiance pattern.

use super::polygon::{PlanarPolygon, SHAPE_TOLERANCE, clip_half_space, polygon_area};
use areawarp::error::WarpError;
use areawarp::vector::Vec3;

/// A checkerboard of rectangular cells over the emitter's plane: radiance
/// `high` on the cells `(i, j)` with `i + j` even, `low` on the others.
///
/// This is our reading of Ureña (2000, §5), whose test scene has a source
/// triangle whose "radiance emitted … is not constant: it follows a
/// rectangular pattern", interacting with an array of rectangular
/// occluders; the report gives no more detail (its figures 8–9 are not in
/// our copy), so the pattern is defined here:
///
/// with unit axes `ŝ ⟂ t̂` in the emitter's plane, an origin `o` and cell
/// sizes `a, b > 0`, a point `p` lies in cell
/// `(i, j) = (⌊(p − o)·ŝ / a⌋, ⌊(p − o)·t̂ / b⌋)`, and
/// `L(p) = high` if `i + j` is even, `low` otherwise.
///
/// Its integral over a polygon `P` is `Σ_cells L_cell · area(P ∩ cell)`,
/// computed exactly (to rounding) by clipping ([`RectangularPattern::integral`]);
/// over a rectangle tiled by an even number of whole cells it is
/// `area · (high + low) / 2`. The pattern is discontinuous across cell
/// edges, which is what makes it hard for samplers that ignore it.
#[derive(Clone, Debug, PartialEq)]
pub struct RectangularPattern {
    origin: Vec3<f64>,
    s_axis: Vec3<f64>,
    t_axis: Vec3<f64>,
    cell_s: f64,
    cell_t: f64,
    high: f64,
    low: f64,
}

fn check_radiance(l: f64) -> Result<(), WarpError> {
    if !l.is_finite() {
        return Err(WarpError::NonFinite { what: "radiance" });
    }
    if l < 0.0 {
        return Err(WarpError::InvalidParameter {
            name: "radiance",
            expected: "a finite radiance >= 0",
        });
    }
    Ok(())
}

impl RectangularPattern {
    /// The checkerboard with origin `origin`, axes along `s_axis` and
    /// `t_axis` (normalized here; they must be perpendicular) and cells of
    /// size `cell_s × cell_t`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] / [`WarpError::InvalidParameter`] for
    /// non-finite data, zero or non-perpendicular axes (relative `10⁻⁹`),
    /// cell sizes that are not positive, or negative radiances.
    pub fn new(
        origin: Vec3<f64>,
        s_axis: Vec3<f64>,
        t_axis: Vec3<f64>,
        cell_s: f64,
        cell_t: f64,
        high: f64,
        low: f64,
    ) -> Result<Self, WarpError> {
        if !origin.is_finite() {
            return Err(WarpError::NonFinite {
                what: "pattern origin",
            });
        }
        let axes = WarpError::InvalidParameter {
            name: "pattern axes",
            expected: "two non-zero perpendicular axes",
        };
        let s = s_axis.normalized().ok_or(axes.clone())?;
        let t = t_axis.normalized().ok_or(axes.clone())?;
        if s.dot(&t).abs() > SHAPE_TOLERANCE {
            return Err(axes);
        }
        for c in [cell_s, cell_t] {
            if !(c > 0.0 && c.is_finite()) {
                return Err(WarpError::InvalidParameter {
                    name: "pattern cell size",
                    expected: "finite cell sizes > 0",
                });
            }
        }
        check_radiance(high)?;
        check_radiance(low)?;
        Ok(RectangularPattern {
            origin,
            s_axis: s,
            t_axis: t,
            cell_s,
            cell_t,
            high,
            low,
        })
    }

    /// The checkerboard of `cells_s × cells_t` cells over the bounding box
    /// of `polygon` in its own plane, with `ŝ` along the first edge
    /// (`v₁ − v₀`) and `t̂ = n × ŝ`. For a rectangle given as
    /// [`PlanarPolygon::rectangle`] the cells tile it exactly.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] for zero cell counts, and as
    /// [`RectangularPattern::new`].
    pub fn aligned(
        polygon: &PlanarPolygon,
        cells_s: usize,
        cells_t: usize,
        high: f64,
        low: f64,
    ) -> Result<Self, WarpError> {
        if cells_s == 0 || cells_t == 0 {
            return Err(WarpError::InvalidParameter {
                name: "cell counts",
                expected: "at least one cell along each axis",
            });
        }
        let v = polygon.vertices();
        let s = v[1].sub(&v[0]).normalized().ok_or(WarpError::Degenerate {
            what: "zero first edge",
        })?;
        let t = polygon.normal().cross(&s);
        let range = |axis: &Vec3<f64>| {
            v.iter()
                .map(|p| p.sub(&v[0]).dot(axis))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                })
        };
        let (s0, s1) = range(&s);
        let (t0, t1) = range(&t);
        let origin = v[0].add(&s.scale(&s0)).add(&t.scale(&t0));
        Self::new(
            origin,
            s,
            t,
            (s1 - s0) / cells_s as f64,
            (t1 - t0) / cells_t as f64,
            high,
            low,
        )
    }

    /// The cell `(i, j)` of the point `p` (projected onto the pattern's axes).
    pub fn cell_of(&self, p: &Vec3<f64>) -> (i64, i64) {
        let d = p.sub(&self.origin);
        (
            (d.dot(&self.s_axis) / self.cell_s).floor() as i64,
            (d.dot(&self.t_axis) / self.cell_t).floor() as i64,
        )
    }

    /// The radiance of cell `(i, j)`: `high` if `i + j` is even.
    pub fn cell_radiance(&self, i: i64, j: i64) -> f64 {
        if (i + j).rem_euclid(2) == 0 {
            self.high
        } else {
            self.low
        }
    }

    /// The radiance at `p`.
    pub fn radiance_at(&self, p: &Vec3<f64>) -> f64 {
        let (i, j) = self.cell_of(p);
        self.cell_radiance(i, j)
    }

    /// `max(high, low)`.
    pub fn max_radiance(&self) -> f64 {
        self.high.max(self.low)
    }

    /// The unit axes `(ŝ, t̂)`.
    pub fn axes(&self) -> (&Vec3<f64>, &Vec3<f64>) {
        (&self.s_axis, &self.t_axis)
    }

    /// The pieces `polygon ∩ cell` with their cell's radiance, for every cell
    /// that the polygon's bounding range touches (pieces may be empty).
    /// The polygon must lie in the pattern's plane (or parallel to it).
    pub fn pieces<'a>(
        &'a self,
        vertices: &'a [Vec3<f64>],
    ) -> impl Iterator<Item = (f64, Vec<Vec3<f64>>)> + 'a {
        let coord = |axis: &Vec3<f64>, cell: f64| {
            vertices.iter().fold((i64::MAX, i64::MIN), |(lo, hi), p| {
                let c = (p.sub(&self.origin).dot(axis) / cell).floor() as i64;
                (lo.min(c), hi.max(c))
            })
        };
        let (i0, i1) = coord(&self.s_axis, self.cell_s);
        let (j0, j1) = coord(&self.t_axis, self.cell_t);
        let so = self.s_axis.dot(&self.origin);
        let to = self.t_axis.dot(&self.origin);
        (i0..=i1).flat_map(move |i| {
            (j0..=j1).map(move |j| {
                let (s_lo, s_hi) = (
                    so + i as f64 * self.cell_s,
                    so + (i + 1) as f64 * self.cell_s,
                );
                let (t_lo, t_hi) = (
                    to + j as f64 * self.cell_t,
                    to + (j + 1) as f64 * self.cell_t,
                );
                let mut piece = clip_half_space(vertices, &self.s_axis, s_lo);
                piece = clip_half_space(&piece, &self.s_axis.neg(), -s_hi);
                piece = clip_half_space(&piece, &self.t_axis, t_lo);
                piece = clip_half_space(&piece, &self.t_axis.neg(), -t_hi);
                (self.cell_radiance(i, j), piece)
            })
        })
    }

    /// `∫_P L dA` over the polygon with the given vertices, exactly (to
    /// rounding) by clipping the polygon against each cell.
    pub fn integral(&self, vertices: &[Vec3<f64>]) -> f64 {
        self.pieces(vertices)
            .map(|(l, piece)| l * polygon_area(&piece))
            .sum()
    }
}

/// The radiance an emitter sends toward its front side.
#[derive(Clone, Debug, PartialEq)]
pub enum Radiance {
    /// The same radiance everywhere.
    Constant(f64),
    /// A checkerboard of two radiances ([`RectangularPattern`]).
    Pattern(RectangularPattern),
}

impl Radiance {
    /// The radiance at the point `p` of the emitter.
    pub fn at(&self, p: &Vec3<f64>) -> f64 {
        match self {
            Radiance::Constant(l) => *l,
            Radiance::Pattern(pattern) => pattern.radiance_at(p),
        }
    }

    /// The largest radiance.
    pub fn max(&self) -> f64 {
        match self {
            Radiance::Constant(l) => *l,
            Radiance::Pattern(pattern) => pattern.max_radiance(),
        }
    }
}

/// A planar polygonal light source: a [`PlanarPolygon`] with a
/// [`Radiance`], emitting on the side its normal points to, or on both
/// sides (Ureña et al. 2013 use a double-sided rectangle).
#[derive(Clone, Debug)]
pub struct Emitter {
    polygon: PlanarPolygon,
    radiance: Radiance,
    two_sided: bool,
}

impl Emitter {
    /// A one-sided emitter.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] / [`WarpError::InvalidParameter`] for a
    /// negative or non-finite constant radiance, or a pattern whose axes
    /// are not in the polygon's plane (relative `10⁻⁹`).
    pub fn new(polygon: PlanarPolygon, radiance: Radiance) -> Result<Self, WarpError> {
        match &radiance {
            Radiance::Constant(l) => check_radiance(*l)?,
            Radiance::Pattern(p) => {
                let n = polygon.normal();
                let (s, t) = p.axes();
                if n.dot(s).abs() > SHAPE_TOLERANCE || n.dot(t).abs() > SHAPE_TOLERANCE {
                    return Err(WarpError::InvalidParameter {
                        name: "pattern axes",
                        expected: "axes in the emitter's plane",
                    });
                }
            }
        }
        Ok(Emitter {
            polygon,
            radiance,
            two_sided: false,
        })
    }

    /// A one-sided emitter of constant radiance `l`.
    ///
    /// # Errors
    /// As [`Emitter::new`].
    pub fn constant(polygon: PlanarPolygon, l: f64) -> Result<Self, WarpError> {
        Self::new(polygon, Radiance::Constant(l))
    }

    /// The same emitter, emitting on both sides (`true`) or only toward its
    /// normal (`false`).
    pub fn with_two_sided(mut self, two_sided: bool) -> Self {
        self.two_sided = two_sided;
        self
    }

    /// The emitting polygon.
    pub fn polygon(&self) -> &PlanarPolygon {
        &self.polygon
    }

    /// The radiance.
    pub fn radiance(&self) -> &Radiance {
        &self.radiance
    }

    /// `true` if the emitter emits on both sides.
    pub fn is_two_sided(&self) -> bool {
        self.two_sided
    }

    /// `true` if the emitter sends light from its plane toward the point
    /// `x` (on its front side, or anywhere off the plane if two-sided).
    pub fn faces(&self, x: &Vec3<f64>) -> bool {
        let d = self.polygon.signed_distance(x);
        d > 0.0 || (self.two_sided && d < 0.0)
    }

    /// The radiance leaving the point `p` of the emitter in the direction
    /// `toward` (any length): 0 toward the back of a one-sided emitter.
    pub fn emitted(&self, p: &Vec3<f64>, toward: &Vec3<f64>) -> f64 {
        let c = self.polygon.normal().dot(toward);
        if c > 0.0 || (self.two_sided && c < 0.0) {
            self.radiance.at(p)
        } else {
            0.0
        }
    }

    /// `∫_P L dA` over the emitter (one side), exact to rounding.
    pub fn radiance_integral(&self) -> f64 {
        match &self.radiance {
            Radiance::Constant(l) => l * self.polygon.area(),
            Radiance::Pattern(p) => p.integral(self.polygon.vertices()),
        }
    }
}
