//! One lune (azimuth interval) of the projected polygon: the edges crossing
//! it, its marginal CDF (a [`Cdf1`] for the framework's inverters) and the
//! conditional distribution on a meridian.
//!
//! Notation (see `docs/projected-polygon.md`): the lune is
//! `φ ∈ [a, a + Δ]`, the local coordinate is `δ = φ − a`, and `(c, s) =
//! (cos δ, sin δ)`. An edge lies on the great circle with unit normal
//! `n = (n_x, n_y, n_z)`; on the meridian at azimuth φ it sits at
//!
//! r² = n_z² / (n_z² + g²),  z² = g² / (n_z² + g²),  g(φ) = n_x cos φ + n_y sin φ,
//!
//! with `g = g_a c − k_a s`, `g_a = g(a)`, `k_a = g'(a) = −n_x sin a + n_y cos a`.
//! `r` is the distance from the pole in the projected (unit-disk) picture.

use crate::real::Real;
use crate::recipe::Cdf1;

/// An edge crossing a lune: its great circle in the lune's coordinates.
#[derive(Clone, Debug)]
pub(super) struct LuneEdge<T> {
    /// n_z, signed: positive for an *outer* boundary (the region lies on the
    /// pole side of the edge), negative for an inner one.
    pub nz: T,
    /// |n_z|.
    pub abs_nz: T,
    /// n_z².
    pub nz2: T,
    /// g(a) = n_x cos a + n_y sin a.
    pub g_a: T,
    /// g'(a) = −n_x sin a + n_y cos a.
    pub k_a: T,
}

impl<T: Real> LuneEdge<T> {
    /// The edge's constants for a lune starting at azimuth `a` (given as
    /// `cos a`, `sin a`) from the great circle's unit normal `n`.
    pub fn new(nx: &T, ny: &T, nz: &T, cos_a: &T, sin_a: &T) -> Self {
        LuneEdge {
            nz: nz.clone(),
            abs_nz: nz.abs(),
            nz2: nz.square(),
            g_a: nx.clone() * cos_a + &(ny.clone() * sin_a),
            k_a: ny.clone() * cos_a - &(nx.clone() * sin_a),
        }
    }

    /// `(r², z²)` of the edge's point on the meridian at `δ`.
    #[inline]
    pub fn crossing(&self, c: &T, s: &T) -> (T, T) {
        let g = self.g_a.clone() * c - &(self.k_a.clone() * s);
        let g2 = g.square();
        let den = self.nz2.clone() + &g2;
        (self.nz2.clone() / &den, g2 / &den)
    }

    /// n_z · α(δ), with α(δ) the arc of the edge's great circle between its
    /// points on the meridians at `a` and `a + δ`:
    ///
    /// α(δ) = atan2(|n_z| sin δ, n_z² cos δ + g_a g(δ))   (eq. 1.47).
    ///
    /// Half of it is the signed projected area swept (Lambert, eq. 1.53).
    #[inline]
    pub fn swept(&self, c: &T, s: &T) -> T {
        let g = self.g_a.clone() * c - &(self.k_a.clone() * s);
        let y = self.abs_nz.clone() * s;
        let x = self.nz2.clone() * c + &(self.g_a.clone() * &g);
        y.atan2(&x) * &self.nz
    }
}

/// An azimuth interval `[start, start + width]` with no vertex inside.
#[derive(Clone, Debug)]
pub(super) struct Lune<T> {
    /// Azimuth `a` of the lune's first meridian, radians.
    pub start: T,
    /// Width Δ, radians.
    pub width: T,
    /// cos a.
    pub cos_a: T,
    /// sin a.
    pub sin_a: T,
    /// 2 × the projected area of the polygon inside the lune (0 if empty).
    pub two_area: T,
    /// The projected area of the polygon inside the lune.
    pub area: T,
    /// Projected area of the polygon in the lunes before this one.
    pub cum_start: T,
    /// The lune's edges: `edges[first..end]`, sorted by distance from the pole.
    pub first: usize,
    /// One past the last edge.
    pub end: usize,
    /// Whether the pole side of the innermost edge belongs to the polygon.
    pub pole_inside: bool,
    /// Index among the lunes of positive area (those that are sampled).
    pub active: Option<usize>,
}

impl<T: Real> Lune<T> {
    /// Number of interval boundaries on a meridian (the pole counts as one
    /// when inside).
    fn n_bounds(&self) -> usize {
        self.end - self.first + usize::from(self.pole_inside)
    }

    /// `(r², z²)` of boundary `j` (0 = the pole when it is inside).
    #[inline]
    fn bound(&self, edges: &[LuneEdge<T>], j: usize, c: &T, s: &T) -> (T, T) {
        if self.pole_inside {
            if j == 0 {
                (T::zero(), T::one())
            } else {
                edges[self.first + j - 1].crossing(c, s)
            }
        } else {
            edges[self.first + j].crossing(c, s)
        }
    }

    /// The intervals `(inner, outer)` of the polygon on the meridian at δ,
    /// from the pole outwards.
    #[inline]
    fn interval(&self, edges: &[LuneEdge<T>], i: usize, c: &T, s: &T) -> Interval<T> {
        let (r_in, z_in) = self.bound(edges, 2 * i, c, s);
        let (r_out, z_out) = self.bound(edges, 2 * i + 1, c, s);
        Interval::new(r_in, z_in, r_out, z_out)
    }

    fn n_intervals(&self) -> usize {
        self.n_bounds() / 2
    }

    /// Σ n_z α over the lune's edges at δ: 2 × the projected area between
    /// the meridians at `a` and `a + δ`.
    pub fn swept(&self, edges: &[LuneEdge<T>], c: &T, s: &T) -> T {
        let mut sum = T::zero();
        for e in &edges[self.first..self.end] {
            sum += &e.swept(c, s);
        }
        sum
    }

    /// The total length, in r², of the polygon's intervals on the meridian:
    /// 2 × the derivative of the projected area with respect to φ.
    pub fn chord(&self, edges: &[LuneEdge<T>], c: &T, s: &T) -> T {
        let mut sum = T::zero();
        for i in 0..self.n_intervals() {
            sum += &self.interval(edges, i, c, s).len;
        }
        sum
    }

    /// `(r², z²)` of the point at conditional probability `v` on the
    /// meridian at δ: uniform in r² (equivalently in z²) over the union of
    /// intervals. `v ≤ 1/2` is measured from the pole, `v > 1/2` from the
    /// outer end with `1 − v` (exact there), so that both ends keep their
    /// relative accuracy.
    pub fn sample(&self, edges: &[LuneEdge<T>], c: &T, s: &T, v: &T) -> (T, T) {
        let total = self.chord(edges, c, s);
        let ni = self.n_intervals();
        let zero = T::zero();
        let one = T::one();
        let (r2, z2) = if *v <= T::from_ratio(1, 2) || v.is_nan() {
            let w = v.clone() * &total;
            let mut cum = T::zero();
            let mut out = (zero.clone(), one.clone());
            for i in 0..ni {
                let iv = self.interval(edges, i, c, s);
                if w <= cum.clone() + &iv.len || i + 1 == ni {
                    let t = (w - &cum).clamp(&zero, &iv.len);
                    out = (iv.r_in + &t, iv.z_in - &t);
                    break;
                }
                cum += &iv.len;
            }
            out
        } else {
            let w = (one.clone() - v) * &total;
            let mut cum = T::zero();
            let mut out = (one.clone(), zero.clone());
            for i in (0..ni).rev() {
                let iv = self.interval(edges, i, c, s);
                if w <= cum.clone() + &iv.len || i == 0 {
                    let t = (w - &cum).clamp(&zero, &iv.len);
                    out = (iv.r_out - &t, iv.z_out + &t);
                    break;
                }
                cum += &iv.len;
            }
            out
        };
        (r2.clamp(&zero, &one), z2.clamp(&zero, &one))
    }

    /// The conditional CDF at the point `(r², z²)` of the meridian at δ
    /// (inverse of [`Lune::sample`]); points in a gap between intervals
    /// snap to the next interval's inner end.
    pub fn conditional_cdf(&self, edges: &[LuneEdge<T>], c: &T, s: &T, r2: &T, z2: &T) -> T {
        let total = self.chord(edges, c, s);
        if !(total > T::zero()) {
            return T::zero();
        }
        let ni = self.n_intervals();
        let half = T::from_ratio(1, 2);
        let zero = T::zero();
        let mut cum = T::zero();
        let mut chosen = ni.saturating_sub(1);
        for i in 0..ni {
            let iv = self.interval(edges, i, c, s);
            if *r2 <= iv.r_out || i + 1 == ni {
                chosen = i;
                // Offset from the inner end, from whichever coordinate is
                // accurate: r² near the pole, z² near the horizon.
                let t = if *r2 <= half {
                    r2.clone() - &iv.r_in
                } else {
                    iv.z_in.clone() - z2
                };
                let pos = cum.clone() + &t.clamp(&zero, &iv.len);
                if pos <= total.clone() * &half {
                    return (pos / &total).clamp(&zero, &T::one());
                }
                break;
            }
            cum += &iv.len;
        }
        // In the outer half: measure 1 − v from the outer end.
        let mut after = T::zero();
        for i in (chosen + 1..ni).rev() {
            after += &self.interval(edges, i, c, s).len;
        }
        let iv = self.interval(edges, chosen, c, s);
        let t = if *r2 <= half {
            iv.r_out.clone() - r2
        } else {
            z2.clone() - &iv.z_out
        };
        let rest = after + &t.clamp(&zero, &iv.len);
        (T::one() - &(rest / &total)).clamp(&zero, &T::one())
    }

    /// Whether the point `(r², ·)` of the meridian at δ lies in one of the
    /// polygon's intervals (closed).
    pub fn contains(&self, edges: &[LuneEdge<T>], c: &T, s: &T, r2: &T) -> bool {
        (0..self.n_intervals()).any(|i| {
            let iv = self.interval(edges, i, c, s);
            *r2 >= iv.r_in && *r2 <= iv.r_out
        })
    }
}

/// One interval `[r_in², r_out²]` of a meridian, with the matching z².
struct Interval<T> {
    r_in: T,
    z_in: T,
    r_out: T,
    z_out: T,
    /// r_out² − r_in² = z_in² − z_out² (≥ 0), from whichever pair is accurate.
    len: T,
}

impl<T: Real> Interval<T> {
    #[inline]
    fn new(r_in: T, z_in: T, r_out: T, z_out: T) -> Self {
        let len = if r_out <= T::from_ratio(1, 2) {
            r_out.clone() - &r_in
        } else {
            z_in.clone() - &z_out
        };
        let len = len.max(&T::zero());
        Interval {
            r_in,
            z_in,
            r_out,
            z_out,
            len,
        }
    }
}

/// The marginal CDF of one lune, `F(δ) = Σ n_z α(δ) / Σ n_z α(Δ)` on
/// `[0, Δ]`, with density `F'(δ) = L(δ) / Σ n_z α(Δ)` (`L` the chord in r²).
pub(super) struct LuneCdf<'a, T> {
    /// The lune.
    pub lune: &'a Lune<T>,
    /// All lunes' edges.
    pub edges: &'a [LuneEdge<T>],
}

impl<T: Real> Cdf1<T> for LuneCdf<'_, T> {
    fn cdf(&self, x: &T) -> T {
        let (s, c) = x.sin_cos();
        self.lune.swept(self.edges, &c, &s) / &self.lune.two_area
    }
    fn pdf(&self, x: &T) -> T {
        let (s, c) = x.sin_cos();
        self.lune.chord(self.edges, &c, &s) / &self.lune.two_area
    }
    fn domain(&self) -> (T, T) {
        (T::zero(), self.lune.width.clone())
    }
}
