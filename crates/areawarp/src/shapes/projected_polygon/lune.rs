//! One lune (azimuth interval) of the projected polygon: the edges crossing
//! it, its marginal CDF (a [`Cdf1`] for the framework's inverters) and the
//! conditional distribution on a meridian.
//!
//! Notation (see `docs/projected-polygon.md`): the lune is `φ ∈ [a, b]`,
//! `Δ = b − a`. Everything is evaluated from either end ([`Side`]): from
//! the start with `x = φ − a`, from the end with `x = b − φ`, and
//! `(c, s) = (cos x, sin x)`; evaluating from the nearer end keeps the
//! relative accuracy of the small quantities there. An edge lies on the
//! great circle with unit normal `n`; on the meridian at φ it sits at
//!
//! r² = n_z² / (n_z² + g²),  z² = g² / (n_z² + g²),  g(φ) = n_x cos φ + n_y sin φ,
//!
//! with `g = g₀ c + k₀ s` in side coordinates (`g₀ = g(a)`, `k₀ = g'(a)` from
//! the start; `g₀ = g(b)`, `k₀ = −g'(b)` from the end). `r` is the distance
//! from the pole in the projected (unit-disk) picture.

use super::build::Arc;
use super::ranges::{ArcEnd, EdgeRange};
use crate::real::Real;
use crate::recipe::Cdf1;
use crate::shapes::turns::atan2_by_atan;
use std::sync::OnceLock;

/// The end of a lune that coordinates are measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    /// x = φ − a.
    Start = 0,
    /// x = b − φ.
    End = 1,
}

/// An edge's great circle seen from one end of a lune.
#[derive(Clone, Debug)]
pub(super) struct EdgeSide<T> {
    /// g at the side's meridian.
    pub g0: T,
    /// dg/dx there.
    pub k0: T,
    /// g at the side's meridian as the map's intervals place the edge's
    /// points: `g0`, except where the edge's own end V lies on that
    /// meridian (at V's own azimuth) and the sum g₀ is ill-conditioned,
    /// where it is `−n_z z_V/r_V` (`build::vertex_g`).
    pub gv: T,
}

/// An edge crossing a lune.
#[derive(Clone, Debug)]
pub(super) struct LuneEdge<T> {
    /// n_z, signed: positive for an *outer* boundary (the region lies on the
    /// pole side of the edge), negative for an inner one.
    pub nz: T,
    /// |n_z|.
    pub abs_nz: T,
    /// n_z².
    pub nz2: T,
    /// Constants from the start and from the end.
    pub side: [EdgeSide<T>; 2],
    /// The edge's arc (index into the clipped boundary's arcs).
    pub arc: usize,
    /// Which of the arc's end points lies on the lune's first and last
    /// meridian (for its range in the lune, [`Pair::range`]).
    pub arc_end: [ArcEnd; 2],
}

impl<T: Real> LuneEdge<T> {
    /// The edge's constants for the lune `[a, b]` (given by the cosines and
    /// sines of its ends) from the great circle's unit normal `n`; `arc`
    /// and `arc_end` as the fields. [`EdgeSide::gv`] is `g₀` here; the
    /// constructor replaces it at the arc's own end point where `g₀` is
    /// ill-conditioned (`build::vertex_g`).
    pub fn new(n: [&T; 3], a: (&T, &T), b: (&T, &T), arc: usize, arc_end: [ArcEnd; 2]) -> Self {
        let [nx, ny, nz] = n;
        let nz2 = nz.square();
        let side = |(cos, sin): (&T, &T), sign: bool| {
            let g0 = nx.clone() * cos + &(ny.clone() * sin);
            let k = ny.clone() * cos - &(nx.clone() * sin);
            EdgeSide {
                gv: g0.clone(),
                g0,
                k0: if sign { k } else { -k },
            }
        };
        LuneEdge {
            nz: nz.clone(),
            abs_nz: nz.abs(),
            nz2: nz2.clone(),
            side: [side(a, true), side(b, false)],
            arc,
            arc_end,
        }
    }

    /// `(g, n_z² + g²)` at side coordinate `(c, s)`, from `g` at the
    /// side's meridian `at_side` and the side's dg/dx.
    #[inline]
    fn g_from(&self, at_side: &T, side: Side, c: &T, s: &T) -> (T, T) {
        let g = at_side.clone() * c + &(self.side[side as usize].k0.clone() * s);
        let den = self.nz2.clone() + &g.square();
        (g, den)
    }

    /// `(g, n_z² + g²)` at side coordinate `(c, s)`.
    #[inline]
    fn g(&self, side: Side, c: &T, s: &T) -> (T, T) {
        self.g_from(&self.side[side as usize].g0, side, c, s)
    }

    /// `(g, n_z² + g²)` at side coordinate `(c, s)` as the map's intervals
    /// place the edge's points (from [`EdgeSide::gv`]).
    #[inline]
    fn g_map(&self, side: Side, c: &T, s: &T) -> (T, T) {
        self.g_from(&self.side[side as usize].gv, side, c, s)
    }

    /// r² = n_z²/(n_z² + g²) of the edge's point at side coordinate
    /// `(c, s)` (the squared distance from the pole's axis).
    #[inline]
    pub fn r2(&self, side: Side, c: &T, s: &T) -> T {
        let (_, den) = self.g(side, c, s);
        self.nz2.clone() / &den
    }

    /// α(x): the arc of the edge's great circle between its points on the
    /// side's meridian and at side coordinate x (eq. 1.47):
    /// `α = atan2(|n_z| sin x, n_z² cos x + g₀ g(x))`.
    #[inline]
    fn alpha(&self, side: Side, g: &T, c: &T, s: &T) -> T {
        let e = &self.side[side as usize];
        let y = self.abs_nz.clone() * s;
        let x = self.nz2.clone() * c + &(e.g0.clone() * g);
        atan2_by_atan(&y, &x)
    }
}

/// One interval of the polygon on the meridians of a lune: between an inner
/// edge (or the pole) and an outer edge.
#[derive(Clone, Debug)]
pub(super) struct Pair<T> {
    /// Inner edge (index into the edges), `None` for the pole.
    pub inner: Option<usize>,
    /// Outer edge.
    pub outer: usize,
    /// `D = n_z,o g_i − n_z,i g_o = A c + B s` from each side (A exactly 0
    /// where the two edges meet at that side's meridian).
    pub d: [(T, T); 2],
    /// Whether the two edges meet at each side's meridian (an extremal
    /// vertex of the polygon: the interval closes there).
    pub shared: [bool; 2],
    /// r of the shared vertex at each side where `shared` (0 elsewhere):
    /// the polar triangle's fixed side in [`Lune::swept`], computed once at
    /// construction.
    pub r0: [T; 2],
    /// The range of the interval's region in the lune (samples are clamped
    /// into it), computed on first use ([`Pair::range`]).
    pub range: OnceLock<EdgeRange<T>>,
}

/// An azimuth interval `[start, start + width]` with no vertex inside.
#[derive(Clone, Debug)]
pub(super) struct Lune<T> {
    /// Azimuth `a` of the lune's first meridian, radians.
    pub start: T,
    /// Azimuth `b` of its last meridian (`start + width`, exactly as the
    /// next lune's start, or one turn more for the last lune).
    pub end_az: T,
    /// Width Δ, radians.
    pub width: T,
    /// (cos a, sin a).
    pub cs_a: (T, T),
    /// (cos b, sin b).
    pub cs_b: (T, T),
    /// (sin Δ, cos Δ), from (cos a, sin a) and (cos b, sin b) by the
    /// subtraction formulas ([`sin_cos_between`]): the side coordinate's
    /// sine and cosine at the far meridian, with which the lune's area is
    /// summed (from either side) and its marginals evaluated there
    /// ([`Lune::sin_cos_at`]), so that they reach 1 exactly.
    pub width_sc: (T, T),
    /// 2 × the projected area of the polygon inside the lune (0 if empty),
    /// as summed from the start.
    pub two_area_start: T,
    /// The same, summed from the end (the normalization of the marginal
    /// from the end, so that it reaches 1 exactly): computed on first use
    /// ([`Lune::two_area`]), as only samples and inverses in the lune's
    /// second half need it.
    pub two_area_end: OnceLock<T>,
    /// The projected area of the polygon inside the lune.
    pub area: T,
    /// Projected area of the polygon in the lunes before this one.
    pub cum_start: T,
    /// Projected area of the polygon in the lunes after this one.
    pub cum_after: T,
    /// The lune's intervals: `pairs[first..end]`, from the pole outwards.
    pub first: usize,
    /// One past the last interval.
    pub end: usize,
    /// Number of edges crossing the lune.
    pub n_edges: usize,
    /// Index among the lunes of positive area (those that are sampled).
    pub active: Option<usize>,
}

/// The two ends of one interval on a meridian, in r² and z², and its
/// length in r².
pub(super) struct Interval<T> {
    pub r_in: T,
    pub z_in: T,
    pub r_out: T,
    pub z_out: T,
    pub len: T,
}

/// α − sin α, accurate also for small α (series below 1/4).
fn alpha_minus_sin<T: Real>(a: &T) -> T {
    if a.abs() > T::from_ratio(1, 4) {
        return a.clone() - &a.sin();
    }
    let a2 = a.square();
    let mut term = a.clone() * &a2 / &T::from_i64(6);
    let mut sum = term.clone();
    let tol = T::unit_roundoff();
    for k in 1..400i64 {
        term = -(term * &a2) / &T::from_i64((2 * k + 2) * (2 * k + 3));
        sum += &term;
        if term.abs() <= tol.clone() * &sum.abs() {
            break;
        }
    }
    sum
}

/// `(sin(b − a), cos(b − a))` from `(cos a, sin a)` and `(cos b, sin b)`:
/// four products, no library call. Each result has an absolute error of
/// a few units of roundoff, as `sin_cos` of the rounded difference of the
/// two azimuths has (whose own rounding is about u·|a|); a lune thinner
/// than `16πu` is never formed (the partition merges such meridians).
pub(super) fn sin_cos_between<T: Real>((ca, sa): (&T, &T), (cb, sb): (&T, &T)) -> (T, T) {
    (
        sb.clone() * ca - &(cb.clone() * sa),
        cb.clone() * ca + &(sb.clone() * sa),
    )
}

impl<T: Real> Lune<T> {
    /// `(sin x, cos x)` of the side coordinate `x ∈ [0, Δ]`: at the far
    /// meridian (`x ≥ Δ`) the lune's own [`Lune::width_sc`], elsewhere
    /// `x.sin_cos()`.
    #[inline]
    pub fn sin_cos_at(&self, x: &T) -> (T, T) {
        if *x >= self.width {
            self.width_sc.clone()
        } else {
            x.sin_cos()
        }
    }

    /// 2 × the projected area inside the lune, as summed from `side` (the
    /// end's sum computed on first use; where rounding leaves it at zero
    /// while the start's is positive, a sliver lune, the start's is used).
    pub fn two_area(&self, edges: &[LuneEdge<T>], pairs: &[Pair<T>], side: Side) -> T {
        match side {
            Side::Start => self.two_area_start.clone(),
            Side::End => self
                .two_area_end
                .get_or_init(|| {
                    if self.n_edges == 0 {
                        return T::zero();
                    }
                    let (s, c) = self.width_sc.clone();
                    let a = self.swept(edges, pairs, Side::End, &c, &s).max(&T::zero());
                    if a > T::zero() {
                        a
                    } else {
                        self.two_area_start.clone()
                    }
                })
                .clone(),
        }
    }

    fn pairs<'a>(&self, pairs: &'a [Pair<T>]) -> &'a [Pair<T>] {
        &pairs[self.first..self.end]
    }

    /// The interval of `pair` on the meridian at side coordinate `(c, s)`.
    #[inline]
    pub fn interval(
        &self,
        edges: &[LuneEdge<T>],
        pair: &Pair<T>,
        side: Side,
        c: &T,
        s: &T,
    ) -> Interval<T> {
        // The edges' points as the map places them: at an edge's own end
        // vertex on the side's meridian exactly there ([`EdgeSide::gv`]).
        let o = &edges[pair.outer];
        let (g_o, den_o) = o.g_map(side, c, s);
        let r_out = o.nz2.clone() / &den_o;
        let z_out = g_o.square() / &den_o;
        match pair.inner {
            None => Interval {
                r_in: T::zero(),
                z_in: T::one(),
                len: r_out.clone(),
                r_out,
                z_out,
            },
            Some(i) => {
                let e = &edges[i];
                let (g_i, den_i) = e.g_map(side, c, s);
                let len = self.pair_len(o, e, pair, side, (&g_o, &den_o), (&g_i, &den_i), c, s);
                Interval {
                    r_in: e.nz2.clone() / &den_i,
                    z_in: g_i.square() / &den_i,
                    r_out,
                    z_out,
                    len,
                }
            }
        }
    }

    /// 2 × the projected area between the side's meridian and side
    /// coordinate x: Σ n_z α over the edges (Lambert, eq. 1.53). For an
    /// interval whose two edges meet at the side's meridian (an extremal
    /// vertex) the two terms cancel to O(x²); there (for sin x < 1/4) each sector
    /// `|n_z| α` is split into the polar triangle `r₀ r(x) sin x` and the
    /// elliptic segment `|n_z| (α − sin α)`, the triangles of the two edges
    /// are combined exactly (`r_o − r_i = L / (r_o + r_i)`), and the small
    /// area keeps its relative accuracy.
    pub fn swept(&self, edges: &[LuneEdge<T>], pairs: &[Pair<T>], side: Side, c: &T, s: &T) -> T {
        let mut sum = T::zero();
        let mut tri = T::zero();
        let si = side as usize;
        for p in self.pairs(pairs) {
            let o = &edges[p.outer];
            let (g_o, den_o) = o.g(side, c, s);
            let a_o = o.alpha(side, &g_o, c, s);
            let Some(i) = p.inner else {
                sum += &(a_o * &o.nz);
                continue;
            };
            let e = &edges[i];
            let (g_i, den_i) = e.g(side, c, s);
            let a_i = e.alpha(side, &g_i, c, s);
            // Far from the vertex (sin x ≥ 1/4) the cancellation costs a few
            // units of roundoff at most: the plain sum is accurate enough.
            if !p.shared[si] || *s >= T::from_ratio(1, 4) {
                sum += &(a_o * &o.nz + &(a_i * &e.nz));
                continue;
            }
            sum += &(alpha_minus_sin(&a_o) * &o.abs_nz - &(alpha_minus_sin(&a_i) * &e.abs_nz));
            let len = self.pair_len(o, e, p, side, (&g_o, &den_o), (&g_i, &den_i), c, s);
            let r_o = (o.nz2.clone() / &den_o).sqrt();
            let r_i = (e.nz2.clone() / &den_i).sqrt();
            let r_sum = r_o + &r_i;
            if r_sum > T::zero() {
                tri += &(p.r0[si].clone() * &(len / &r_sum));
            }
        }
        sum + &(tri * s)
    }

    /// r_o² − r_i² = D E / (den_o den_i), with D = n_o g_i − n_i g_o =
    /// A cos x + B sin x and E = n_o g_i + n_i g_o: no cancellation where
    /// D → 0 at a shared vertex (A = 0 exactly there).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn pair_len(
        &self,
        o: &LuneEdge<T>,
        e: &LuneEdge<T>,
        p: &Pair<T>,
        side: Side,
        (g_o, den_o): (&T, &T),
        (g_i, den_i): (&T, &T),
        c: &T,
        s: &T,
    ) -> T {
        let (a, b) = &p.d[side as usize];
        let d = a.clone() * c + &(b.clone() * s);
        let ee = o.nz.clone() * g_i + &(e.nz.clone() * g_o);
        (d * &ee / &(den_o.clone() * den_i)).max(&T::zero())
    }

    /// The total length, in r², of the polygon's intervals on the meridian:
    /// 2 × the derivative of the projected area with respect to φ.
    pub fn chord(&self, edges: &[LuneEdge<T>], pairs: &[Pair<T>], side: Side, c: &T, s: &T) -> T {
        let mut sum = T::zero();
        for p in self.pairs(pairs) {
            sum += &self.interval(edges, p, side, c, s).len;
        }
        sum
    }

    /// `(r², z²)` of the point at conditional probability `v` on the
    /// meridian at side coordinate `(c, s)`, clamped into its interval's
    /// range ([`Pair::range`], from the edges and the clipped boundary's
    /// `arcs`): uniform in r² (equivalently in
    /// z²) over the union of intervals, from the pole outwards. `v ≤ 1/2` is
    /// measured from the pole, `v > 1/2` from the outer end with `1 − v`
    /// (exact there), so that both ends keep their relative accuracy.
    #[allow(clippy::too_many_arguments)]
    pub fn sample(
        &self,
        edges: &[LuneEdge<T>],
        pairs: &[Pair<T>],
        arcs: &[Arc<T>],
        side: Side,
        c: &T,
        s: &T,
        v: &T,
    ) -> (T, T) {
        let list = self.pairs(pairs);
        let total = self.chord(edges, pairs, side, c, s);
        let ni = list.len();
        let zero = T::zero();
        let one = T::one();
        let mut out = (zero.clone(), one.clone());
        if *v <= T::from_ratio(1, 2) || v.is_nan() {
            let w = v.clone() * &total;
            let mut cum = T::zero();
            for (i, p) in list.iter().enumerate() {
                let iv = self.interval(edges, p, side, c, s);
                if w <= cum.clone() + &iv.len || i + 1 == ni {
                    let t = (w - &cum).clamp(&zero, &iv.len);
                    out = p.range(edges, arcs).clamp(iv.r_in + &t, iv.z_in - &t);
                    break;
                }
                cum += &iv.len;
            }
        } else {
            let w = (one.clone() - v) * &total;
            let mut cum = T::zero();
            for (i, p) in list.iter().enumerate().rev() {
                let iv = self.interval(edges, p, side, c, s);
                if w <= cum.clone() + &iv.len || i == 0 {
                    let t = (w - &cum).clamp(&zero, &iv.len);
                    out = p.range(edges, arcs).clamp(iv.r_out - &t, iv.z_out + &t);
                    break;
                }
                cum += &iv.len;
            }
        }
        (out.0.clamp(&zero, &one), out.1.clamp(&zero, &one))
    }

    /// The conditional CDF at the point `(r², z²)` of the meridian at side
    /// coordinate `(c, s)` (inverse of [`Lune::sample`]); points in a gap
    /// between intervals snap to the next interval's inner end.
    #[allow(clippy::too_many_arguments)]
    pub fn conditional_cdf(
        &self,
        edges: &[LuneEdge<T>],
        pairs: &[Pair<T>],
        side: Side,
        c: &T,
        s: &T,
        r2: &T,
        z2: &T,
    ) -> T {
        let list = self.pairs(pairs);
        let total = self.chord(edges, pairs, side, c, s);
        if !(total > T::zero()) {
            return T::zero();
        }
        let ni = list.len();
        let half = T::from_ratio(1, 2);
        let zero = T::zero();
        let mut cum = T::zero();
        let mut chosen = ni.saturating_sub(1);
        for (i, p) in list.iter().enumerate() {
            let iv = self.interval(edges, p, side, c, s);
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
        for p in &list[chosen + 1..] {
            after += &self.interval(edges, p, side, c, s).len;
        }
        let iv = self.interval(edges, &list[chosen], side, c, s);
        let t = if *r2 <= half {
            iv.r_out.clone() - r2
        } else {
            z2.clone() - &iv.z_out
        };
        let rest = after + &t.clamp(&zero, &iv.len);
        (T::one() - &(rest / &total)).clamp(&zero, &T::one())
    }

    /// Whether the point `(r², z²)` of the meridian at side coordinate
    /// `(c, s)` lies in one of the polygon's intervals (closed), compared in
    /// r² near the pole and in z² near the horizon (where r² is too coarse).
    #[allow(clippy::too_many_arguments)]
    pub fn contains(
        &self,
        edges: &[LuneEdge<T>],
        pairs: &[Pair<T>],
        side: Side,
        c: &T,
        s: &T,
        r2: &T,
        z2: &T,
    ) -> bool {
        let near_pole = *r2 <= T::from_ratio(1, 2);
        self.pairs(pairs).iter().any(|p| {
            let iv = self.interval(edges, p, side, c, s);
            if near_pole {
                *r2 >= iv.r_in && *r2 <= iv.r_out
            } else {
                *z2 <= iv.z_in && *z2 >= iv.z_out
            }
        })
    }
}

/// The marginal CDF of one lune measured from one side,
/// `F(x) = swept(x) / swept(Δ)` on `[0, Δ]`, with density
/// `F'(x) = L(x) / swept(Δ)` (`L` the chord in r²). From the end it is the
/// complementary CDF `1 − F_start(Δ − x)`.
pub(super) struct LuneCdf<'a, T> {
    /// The lune.
    pub lune: &'a Lune<T>,
    /// All lunes' edges.
    pub edges: &'a [LuneEdge<T>],
    /// All lunes' intervals.
    pub pairs: &'a [Pair<T>],
    /// Where x is measured from.
    pub side: Side,
}

impl<T: Real> Cdf1<T> for LuneCdf<'_, T> {
    fn cdf(&self, x: &T) -> T {
        let (s, c) = self.lune.sin_cos_at(x);
        self.lune.swept(self.edges, self.pairs, self.side, &c, &s)
            / &self.lune.two_area(self.edges, self.pairs, self.side)
    }
    fn pdf(&self, x: &T) -> T {
        let (s, c) = self.lune.sin_cos_at(x);
        self.lune.chord(self.edges, self.pairs, self.side, &c, &s)
            / &self.lune.two_area(self.edges, self.pairs, self.side)
    }
    fn domain(&self) -> (T, T) {
        (T::zero(), self.lune.width.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::alpha_minus_sin;

    #[test]
    fn alpha_minus_sin_small_and_large() {
        for a in [1e-8f64, 1e-3, 0.1, 0.2499, 0.25, 0.3, 1.0, 3.0] {
            let series = alpha_minus_sin(&a);
            // Reference: the series summed in f64 to many terms, or direct.
            let mut t = a * a * a / 6.0;
            let mut want = t;
            for k in 1..30 {
                t = -t * a * a / ((2 * k + 2) * (2 * k + 3)) as f64;
                want += t;
            }
            // Series below 1/4: relative accuracy; above: absolute u·α.
            let tol = if a < 0.25 { want.abs() } else { a };
            assert!(
                (series - want).abs() <= 4.0 * f64::EPSILON * tol,
                "{a}: {series} {want}"
            );
        }
        assert_eq!(alpha_minus_sin(&0.0f64), 0.0);
    }
}

/// The part of a lune's marginal that one side inverts: from the side's
/// meridian to the split point `x_h` (where F_start = ½), rescaled to
/// `[0, 1]` and raised to the power `1/m`, with `m` the order of the zero
/// of F at the side's meridian:
///
/// G(x) = (F(x) / F(x_h))^(1/m),  x ∈ [0, x_h].
///
/// `m = 1` at a generic end, `m = 2` at an extremal vertex (the polygon's
/// chord vanishes linearly, F ~ x²), `m = 3` where two edges meet
/// tangentially in projection (at a vertex on the horizon, F ~ x³). G is
/// then nearly linear, which is what the fitted cubic and Newton like: F⁻¹
/// itself has a `y^(1/m)` singularity there that no cubic in y follows.
pub(super) struct HalfCdf<'a, T> {
    /// The side's marginal.
    pub base: LuneCdf<'a, T>,
    /// F(x_h).
    pub fh: T,
    /// The order of the zero of F at x = 0.
    pub m: u8,
    /// The end x_h of the domain.
    pub end: T,
}

impl<T: Real> HalfCdf<'_, T> {
    /// `(y / F(x_h))^(1/m)`: the target in G of the full-marginal value `y`.
    pub fn target(&self, y: &T) -> T {
        let t = (y.clone() / &self.fh).clamp(&T::zero(), &T::one());
        root(&t, self.m)
    }
}

fn root<T: Real>(x: &T, m: u8) -> T {
    match m {
        1 => x.clone(),
        2 => x.sqrt(),
        _ => x.cbrt(),
    }
}

impl<T: Real> Cdf1<T> for HalfCdf<'_, T> {
    fn cdf(&self, x: &T) -> T {
        let f = (self.base.cdf(x) / &self.fh).max(&T::zero());
        root(&f, self.m)
    }
    fn pdf(&self, x: &T) -> T {
        let f = (self.base.cdf(x) / &self.fh).max(&T::zero());
        let d = self.base.pdf(x) / &self.fh;
        match self.m {
            1 => d,
            // d/dx f^(1/m) = f' / (m f^((m−1)/m)); 0/0 = NaN at f = 0 tells
            // the solvers not to take a Newton step there.
            2 => d / &(f.sqrt() * &T::from_i64(2)),
            _ => d / &(f.cbrt().square() * &T::from_i64(3)),
        }
    }
    fn domain(&self) -> (T, T) {
        (T::zero(), self.end.clone())
    }
}

/// The fitted inverse of one side of a lune.
#[derive(Clone, Debug)]
pub(super) struct SideFit<T> {
    /// The cubic fitted to G⁻¹.
    pub cubic: crate::recipe::FittedCubic<T>,
    /// The end x_h of the fitted part, in side coordinates.
    pub xh: T,
    /// F(x_h).
    pub fh: T,
    /// The order of the zero of F at the side's meridian.
    pub m: u8,
}

impl<T: Real> SideFit<T> {
    /// Fits the side's marginal `base` on `[0, xh]`.
    pub fn new(base: LuneCdf<'_, T>, xh: T) -> Self {
        let fh = base.cdf(&xh);
        let m = zero_order(&base, &xh);
        let half = HalfCdf {
            base,
            fh: fh.clone(),
            m,
            end: xh.clone(),
        };
        let cubic = crate::recipe::FittedCubic::fit(&half);
        SideFit { cubic, xh, fh, m }
    }

    /// The [`HalfCdf`] of this fit over `base`.
    pub fn half<'a>(&self, base: LuneCdf<'a, T>) -> HalfCdf<'a, T> {
        HalfCdf {
            base,
            fh: self.fh.clone(),
            m: self.m,
            end: self.xh.clone(),
        }
    }
}

/// The order m ∈ {1, 2, 3} of the zero of F at 0: 1 if the density is
/// positive there, else the rounded log₂ of F(h)/F(h/2) at h = x_h/1024.
fn zero_order<T: Real>(base: &LuneCdf<'_, T>, xh: &T) -> u8 {
    if base.pdf(&T::zero()) > T::zero() {
        return 1;
    }
    let h = xh.clone() * &T::exp2i(-10);
    let (f1, f2) = (base.cdf(&h), base.cdf(&(h / &T::from_i64(2))));
    if !(f1 > T::zero() && f2 > T::zero()) {
        return 2;
    }
    // log₂ ratio ≥ 2.5 ⇔ ratio ≥ 2^2.5 ≈ 5.657: compare the ratio squared
    // with 32 (no logarithm needed).
    if (f1 / &f2).square() >= T::from_i64(32) {
        3
    } else {
        2
    }
}

/// A lune of positive area (one that is sampled): its index among all the
/// lunes, and its fitted inverse marginal from its start and its end,
/// computed the first time a sample falls in it
/// ([`fit_lune`](super::build::fit_lune)).
#[derive(Clone, Debug)]
pub(super) struct ActiveLune<T> {
    /// Index into the lunes.
    pub lune: usize,
    /// The fits from the start and from the end, once computed.
    pub fit: OnceLock<[SideFit<T>; 2]>,
}

impl<T: Real> ActiveLune<T> {
    /// The lunes of positive area among `lunes`, by azimuth.
    pub fn of(lunes: &[Lune<T>]) -> Vec<Self> {
        lunes
            .iter()
            .enumerate()
            .filter(|(_, l)| l.active.is_some())
            .map(|(lune, _)| ActiveLune {
                lune,
                fit: OnceLock::new(),
            })
            .collect()
    }
}
