//! The [`Robust`](super::SphericalRectangleVariant::Robust) evaluation of the
//! Ureña–Fajardo–King map: every quantity is a product or a sum of positive
//! terms of accurately computed factors (derivation: `docs/spherical-rectangle.md`).
//!
//! Notation (all lengths in the scaled local frame of [`Geometry`]): the
//! rectangle is `[x₀, x₁] × [y₀, y₁]` in the plane `z = −h`; `ℓⱼ = √(yⱼ² + h²)`
//! is the distance to the line `y = yⱼ`, `rⱼ(x) = √(x² + ℓⱼ²)`, and
//!
//! - `ω(x) = x (ℓ₀ + ℓ₁) / (r₀(x) ℓ₁ + r₁(x) ℓ₀) ∈ (−1, 1)`,
//! - `Φ(x) = 2 atan(tan(Δ/2) ω(x))`, the solid angle of the strip between the
//!   columns 0 and x (signed), `Δ` the angle the column's height subtends in
//!   the limit x → ±∞, `S_d = sin(Δ/2)`, `C_d = cos(Δ/2)`;
//! - `P = Δ − Φ`, `M = Δ + Φ` (the solid angles from the column to ±∞).
//!
//! The sub-rectangle `[x₀, x]` has solid angle `Φ(x) − Φ(x₀)`; the map needs
//! `x` with `Φ(x) = Φ(x₀) + uΩ`, which is the closed form
//! `x = 2ℓ₀ℓ₁ C_d S_d sin(Φ/2) cos(Φ/2) / √(sin(P/2) sin(M/2) (ℓ₀ sin(M/2) + ℓ₁ sin(P/2)) (ℓ₀ sin(P/2) + ℓ₁ sin(M/2)))`
//! evaluated from the sines and cosines of the half angles, each obtained from
//! a precomputed anchor (the nearer end of `[x₀, x₁]`) and `sin_cos(τ/2)` by
//! the addition theorems.

mod cone;

use super::geometry::{Geometry, length};
use crate::real::Real;
use crate::shapes::turns::{atan2_nonneg, positive};
use crate::shapes::wide::floor_log2;
pub(super) use cone::Cone;

/// ω at one column `x` and the roots it is formed from.
#[derive(Clone, Debug)]
pub(super) struct Column<T> {
    /// `ω(x)`.
    pub w: T,
    /// `N(x) = r₀(x) ℓ₁ + r₁(x) ℓ₀`.
    pub n: T,
    /// `r₀(x)`.
    pub r0: T,
    /// `r₁(x)`.
    pub r1: T,
}

/// The row of a sample ([`Robust::row_at`]).
#[derive(Clone, Debug)]
pub(super) struct Row<T> {
    /// `η = (y_v − y₀)/(y₁ − y₀)`.
    pub eta: T,
    /// `h_v = y_v/√(D² + y_v²)`: the sample's unit direction's component
    /// along ŷ.
    pub hv: T,
    /// `D = √(x² + h²)`, the distance to the column's foot line.
    pub dd: T,
    /// `√(1 − h_v²) = D/r` (computed as a sum of positive terms), `r` the
    /// distance to the sample.
    pub c: T,
}

/// The constants of one end of `[x₀, x₁]`, mirrored (`x → −x`) for the end
/// `x₁` so that the code walks inwards with increasing `x̃` from both ends.
#[derive(Clone, Debug)]
struct Anchor<T> {
    /// `ω̃ₑ` (`ω₀`, or `−ω₁` at the end `x₁`).
    w: T,
    /// `|ωₑ|`.
    abs_w: T,
    /// `1 − |ωₑ|`.
    one_m_abs_w: T,
    /// `x̃ₑ` (`x₀`, or `−x₁`).
    x: T,
    /// `sin(Φ̃ₑ/2)`, `cos(Φ̃ₑ/2)`.
    s_phi: T,
    c_phi: T,
    /// `sin(P̃ₑ/2)`, `cos(P̃ₑ/2)` with `P̃ = Δ − Φ̃`.
    s_p: T,
    c_p: T,
    /// `sin(M̃ₑ/2)`, `cos(M̃ₑ/2)` with `M̃ = Δ + Φ̃`.
    s_m: T,
    c_m: T,
    /// `√S(ωₑ) = 2ℓ₀ℓ₁(ℓ₀ + ℓ₁)/N(xₑ)`.
    sqrt_s: T,
    /// `N(xₑ)/(ℓ₀ + ℓ₁)`.
    n_over_sigma: T,
    /// `C_d / cos(Φₑ/2) = √(C_d² + S_d² ωₑ²)`.
    n: T,
    /// `ωₑ = 0` (the end passes through the foot of the observer).
    w_zero: bool,
    /// `ω̃ₑ < 0`.
    w_negative: bool,
}

/// The per-shape constants of the robust map and of the (shared) inverse.
#[derive(Clone, Debug)]
pub(super) struct Robust<T> {
    /// The quantities up to Ω (lengths, end columns, `S_d`, `C_d`, Ω).
    parts: Omega<T>,
    inv_lx: T,
    inv_ly: T,
    y_sum: T,
    y_same_sign: bool,
    /// `σ·S_d` with the power of two `σ = 2^k` that brings `S_d` into
    /// `[1, 2)` (see [`Robust::column_at`]).
    sd_scaled: T,
    /// `σ` and `1/σ²`.
    sd_scale: T,
    inv_scale2: T,
    /// `2ℓ₀ℓ₁ C_d S_d · σ`.
    k_x: T,
    anchors: [Anchor<T>; 2],
}

/// The lengths a column needs.
struct Lengths<'a, T> {
    l0: &'a T,
    l1: &'a T,
    l0sq: &'a T,
    l1sq: &'a T,
    sigma: &'a T,
}

#[inline(always)]
fn column<T: Real>(x: &T, k: &Lengths<'_, T>) -> Column<T> {
    let x2 = x.square();
    let r0 = (x2.clone() + k.l0sq).sqrt();
    let r1 = (x2 + k.l1sq).sqrt();
    let n = r0.clone() * k.l1 + &(r1.clone() * k.l0);
    let w = x.clone() * k.sigma / &n;
    Column { w, n, r0, r1 }
}

/// `(1 − ω(x), 1 + ω(x))` at the column `col` of `x`, without cancellation
/// (only the anchors need them: computed for the anchor's column alone),
/// given `t = ℓ₀ℓ₁/N(x)`.
#[inline(always)]
fn complements<T: Real>(col: &Column<T>, x: &T, t: &T, k: &Lengths<'_, T>) -> (T, T) {
    let one = T::one();
    let (r0, r1, w) = (&col.r0, &col.r1, &col.w);
    // N − |x|σ = ℓ₁(r₀ − |x|) + ℓ₀(r₁ − |x|), rⱼ − |x| = ℓⱼ²/(rⱼ + |x|):
    // 1 ∓ ω = t (ℓ₀(r₁ + |x|) + ℓ₁(r₀ + |x|)) / ((r₀ + |x|)(r₁ + |x|)), one
    // division (every product of two lengths ≥ h², normal).
    let c = |a: T| {
        let (p0, p1) = (r0.clone() + &a, r1.clone() + &a);
        t.clone() * &((k.l0.clone() * &p1 + &(k.l1.clone() * &p0)) / &(p0 * &p1))
    };
    if *x > T::zero() {
        (c(x.clone()), one + w)
    } else if *x < T::zero() {
        (one - w, c(-x.clone()))
    } else {
        (one.clone(), one)
    }
}

/// The quantities up to the solid angle Ω: the lengths, the end columns,
/// `S_d`, `C_d` and Ω itself. What the range check and the one-shot solid
/// angle need; [`Robust::from_omega`] completes them to the map's constants.
#[derive(Clone, Debug)]
pub(super) struct Omega<T> {
    x0: T,
    x1: T,
    y0: T,
    y1: T,
    ly: T,
    h: T,
    h2: T,
    l0: T,
    l1: T,
    l0sq: T,
    l1sq: T,
    sigma: T,
    col0: Column<T>,
    col1: Column<T>,
    sd: T,
    cd: T,
    sdcd: T,
    sd2: T,
    cd2: T,
    /// Ω and Ω/2 (the arctangent; Ω is it doubled, exactly).
    pub omega: T,
    half_omega: T,
}

impl<T: Real> Omega<T> {
    /// The lengths a column needs.
    fn lengths(&self) -> Lengths<'_, T> {
        Lengths {
            l0: &self.l0,
            l1: &self.l1,
            l0sq: &self.l0sq,
            l1sq: &self.l1sq,
            sigma: &self.sigma,
        }
    }

    /// Ω of the rectangle of `g` and what it is computed from.
    #[inline(always)]
    pub fn new(g: &Geometry<T>) -> Self {
        let one = T::one();
        let half = T::from_ratio(1, 2);
        let (x0, lx, y0, ly, h) = (
            g.x0.clone(),
            g.lx.clone(),
            g.y0.clone(),
            g.ly.clone(),
            g.h.clone(),
        );
        let x1 = x0.clone() + &lx;
        let y1 = y0.clone() + &ly;
        let h2 = h.square();
        let l0sq = y0.square() + &h2;
        let l1sq = y1.square() + &h2;
        // ℓⱼ² ≥ h² stays normal for every shape the range check accepts
        // (h² ≥ tiny/u) and below 20 (local lengths below 2): one root each,
        // no scaling needed.
        let l0 = l0sq.sqrt();
        let l1 = l1sq.sqrt();
        let sigma = l0.clone() + &l1;
        let lengths = Lengths {
            l0: &l0,
            l1: &l1,
            l0sq: &l0sq,
            l1sq: &l1sq,
            sigma: &sigma,
        };
        let col0 = column(&x0, &lengths);
        let col1 = column(&x1, &lengths);

        // S_d = sin(Δ/2), C_d = cos(Δ/2) with Δ/2 = ψ₁ − ψ₀, ψⱼ = θⱼ/2,
        // tan θⱼ = yⱼ/h: cos ψⱼ = √((ℓⱼ + h)/(2ℓⱼ)), sin ψⱼ = yⱼ/√(2ℓⱼ(ℓⱼ + h)),
        // and the subtraction formulas with their numerators written as sums
        // of non-negative terms.
        let zero = T::zero();
        let (e0, e1) = (l0.clone() + &h, l1.clone() + &h);
        let opposite = y0 < zero && y1 > zero;
        let num_s = if opposite {
            y1.clone() * &e0 - &(y0.clone() * &e1)
        } else {
            // y₁(ℓ₀ + h) − y₀(ℓ₁ + h) = h L [1 + h (y₁ + y₀)/(y₁ℓ₀ + y₀ℓ₁)].
            h.clone()
                * &ly
                * &(one.clone()
                    + &(h.clone() * &(y1.clone() + &y0)
                        / &(y1.clone() * &l0 + &(y0.clone() * &l1))))
        };
        let num_c = if opposite {
            // (ℓ₀ + h)(ℓ₁ + h) − |y₀|y₁ with ℓⱼ + h − |yⱼ| = h + h²/(ℓⱼ + |yⱼ|).
            let d0 = h.clone() + &(h2.clone() / &(l0.clone() + &y0.abs()));
            let d1 = h.clone() + &(h2.clone() / &(l1.clone() + &y1.abs()));
            y0.abs() * &d1 + &(y1.abs() * &d0) + &(d0 * &d1)
        } else {
            e0.clone() * &e1 + &(y0.clone() * &y1)
        };
        // One division for both: 1/(2√(ℓ₀ℓ₁(ℓ₀ + h)(ℓ₁ + h))).
        let inv_den = half / &(l0.clone() * &l1 * &e0 * &e1).sqrt();
        let sd = num_s * &inv_den;
        let cd = num_c * &inv_den;
        let sdcd = sd.clone() * &cd;
        let sd2 = sd.square();
        let cd2 = cd.square();
        let dw = omega_diff(&lengths, &x0, &col0, &x1, &col1, &lx);
        let half_omega = half_solid_angle_between(&sdcd, &sd2, &cd2, &col0, &col1, &dw);
        let omega = half_omega.clone() * &T::from_i64(2);
        Omega {
            x0,
            x1,
            y0,
            y1,
            ly,
            h,
            h2,
            l0,
            l1,
            l0sq,
            l1sq,
            sigma,
            col0,
            col1,
            sd,
            cd,
            sdcd,
            sd2,
            cd2,
            omega,
            half_omega,
        }
    }
}

/// `ω(x_b) − ω(x_a)` for `x_a ≤ x_b`, `len = x_b − x_a` (given exactly).
#[inline(always)]
fn omega_diff<T: Real>(
    k: &Lengths<'_, T>,
    xa: &T,
    ca: &Column<T>,
    xb: &T,
    cb: &Column<T>,
    len: &T,
) -> T {
    if *len == T::zero() {
        return T::zero();
    }
    let zero = T::zero();
    if (*xa > zero && *xb > zero) || (*xa < zero && *xb < zero) {
        // x_b rⱼ(x_a) − x_a rⱼ(x_b) = ℓⱼ² (x_b − x_a)(x_b + x_a) / (x_b rⱼ(x_a) + x_a rⱼ(x_b)).
        let t = k.l1.clone() * k.l0sq / &(xb.clone() * &ca.r0 + &(xa.clone() * &cb.r0))
            + &(k.l0.clone() * k.l1sq / &(xb.clone() * &ca.r1 + &(xa.clone() * &cb.r1)));
        k.sigma.clone() * len * &(xb.clone() + xa) * &t / &(ca.n.clone() * &cb.n)
    } else {
        cb.w.clone() - &ca.w
    }
}

/// Half of `Φ(x_b) − Φ(x_a) = 2 atan2(S_d C_d (ω_b − ω_a), C_d² + S_d² ω_a ω_b)`:
/// the arctangent itself, which doubled (exactly) is the solid angle
/// between the columns. The map's `Ω/2` is this value, not `(2·…)·½`.
#[inline(always)]
fn half_solid_angle_between<T: Real>(
    sdcd: &T,
    sd2: &T,
    cd2: &T,
    ca: &Column<T>,
    cb: &Column<T>,
    dw: &T,
) -> T {
    let y = sdcd.clone() * dw;
    let x = cd2.clone() + &(sd2.clone() * &ca.w * &cb.w);
    // y ≥ 0: by atan(y/x) for x > 0 (half angle below π/2), about half
    // of atan2's cost (see `atan2_nonneg`).
    atan2_nonneg(&y, &x)
}

impl<T: Real> Robust<T> {
    /// The constants of the rectangle whose quantities up to Ω are `o`;
    /// with `only_anchor = Some(i)` only the anchor `i` (0: `x₀`, for
    /// `u ≤ 1/2`; 1: `x₁`) is computed (it stands in both places): what one
    /// sample needs.
    #[inline(always)]
    pub fn from_omega(g: &Geometry<T>, o: Omega<T>, only_anchor: Option<usize>) -> Self {
        let two = T::from_i64(2);
        let lengths = o.lengths();
        let sd = &o.sd;
        // σ = 2^k, k = −⌊log₂ S_d⌋: the anchors' sines of half angles that
        // are O(S_d), and the sample's sin(τ/2), are stored times σ, so that
        // the products of four of them in `column_at` do not underflow when
        // the observer grazes the plane (S_d → 0); the scaling is exact.
        let k = if positive(sd) {
            (-floor_log2(sd.to_f64())).clamp(0, 1000)
        } else {
            0
        };
        let sd_scale = T::exp2i(k);
        let inv_scale2 = T::exp2i(-2 * k);
        let sd_scaled = sd.clone() * &sd_scale;
        let at_x0 = || anchor(&o.col0, &o.x0, false, sd, &o.cd, &sd_scale, &lengths);
        let at_x1 = || anchor(&o.col1, &o.x1, true, sd, &o.cd, &sd_scale, &lengths);
        let anchors = match only_anchor {
            Some(i) => {
                let a = if i == 0 { at_x0() } else { at_x1() };
                [a.clone(), a]
            }
            None => [at_x0(), at_x1()],
        };
        Robust {
            // 1/ℓx, 1/ℓy from the frame (no division here).
            inv_lx: g.inv_lx.clone(),
            inv_ly: g.inv_ly.clone(),
            y_sum: o.y1.clone() + &o.y0,
            y_same_sign: (o.y0 >= T::zero()) || (o.y1 <= T::zero()),
            k_x: two * &o.l0 * &o.l1 * &o.sdcd * &sd_scale,
            anchors,
            sd_scale,
            inv_scale2,
            sd_scaled,
            parts: o,
        }
    }

    /// `Φ(x_b) − Φ(x_a)`: twice [`half_solid_angle_between`] with this
    /// rectangle's `S_d`, `C_d`.
    fn between(&self, ca: &Column<T>, cb: &Column<T>, dw: &T) -> T {
        let o = &self.parts;
        half_solid_angle_between(&o.sdcd, &o.sd2, &o.cd2, ca, cb, dw) * &T::from_i64(2)
    }

    /// Ω, from the quantities the constants were completed from.
    pub fn omega(&self) -> &T {
        &self.parts.omega
    }

    /// The column of the sample: `(ξ, x)` with `ξ = (x_u − x₀)/(x₁ − x₀)` and
    /// `x_u` (scaled local), for `u ∈ [0, 1]`.
    /// Inlined into its caller (the one-shot path: the shape's constants
    /// need not be stored first).
    #[inline(always)]
    pub fn column_at(&self, u: &T) -> (T, T) {
        let half = T::from_ratio(1, 2);
        let (a, uu, mirrored) = if *u <= half {
            (&self.anchors[0], u.clone(), false)
        } else {
            (&self.anchors[1], T::one() - u, true)
        };
        let (st, ct) = (uu * &self.parts.half_omega).sin_cos();
        // Every sine of a half angle below is σ times its value (exact).
        let st = st * &self.sd_scale;
        // Half angles at the sample by the addition theorems (τ/2 ≥ 0 moves
        // Φ̃ and M̃ up and P̃ down).
        let su = a.s_phi.clone() * &ct + &(a.c_phi.clone() * &st);
        // cos(Φ/2) is O(1): the product of two scaled sines is divided by σ².
        let gu = a.c_phi.clone() * &ct - &(a.s_phi.clone() * &st * &self.inv_scale2);
        let sp = a.s_p.clone() * &ct - &(a.c_p.clone() * &st);
        let sm = a.s_m.clone() * &ct + &(a.c_m.clone() * &st);
        let (l0, l1) = (&self.parts.l0, &self.parts.l1);
        // √q for q = sp·sm·(ℓ₀sm + ℓ₁sp)(ℓ₀sp + ℓ₁sm), as the product of two
        // roots of products of two factors: near an anchor with the observer
        // above the interior (C_d → 0) every factor is O(C_d), and a product
        // of four would underflow long before the shape's quantities do.
        let sa = l0.clone() * &sm + &(l1.clone() * &sp);
        let sb = l0.clone() * &sp + &(l1.clone() * &sm);
        let rq = (sp.clone() * &sm).sqrt() * &(sa * &sb).sqrt();
        let xt = self.k_x.clone() * &su * &gu / &rq;
        let dx = if a.w_negative && su > T::zero() {
            // The column crossed the foot: both terms positive.
            xt.clone() - &a.x
        } else {
            // Same sign: x(ω) − x(ωₑ) = (Nₑ/σ) δω (ω + ωₑ) F / ((ω√Sₑ + ωₑ√S) √S),
            // everything multiplied through by g = cos(Φ̃/2) S_d.
            let g = gu * &self.sd_scaled;
            let wh = su * &self.parts.cd;
            let dh = st * &a.n;
            let (one_m_abs, aw) = if wh >= T::zero() {
                (sp, wh.clone())
            } else {
                (sm, -wh.clone())
            };
            let m_minus = one_m_abs + &(aw.clone() * &a.one_m_abs_w);
            let m_plus = g.clone() + &(aw * &a.abs_w);
            let fg2 = (l0.clone() * &m_plus + &(l1.clone() * &m_minus))
                * &(l0.clone() * &m_minus + &(l1.clone() * &m_plus));
            // F²g²/√q is O(1): divided first, so that no product of more
            // than two small factors is formed.
            let fg2_rq = fg2 / &rq;
            if a.w_zero {
                a.n_over_sigma.clone() * &dh * &fg2_rq / &(g * &a.sqrt_s)
            } else {
                let ratio = (wh.clone() + &(a.w.clone() * &g))
                    / &(wh * &g * &a.sqrt_s + &(a.w.clone() * &rq));
                a.n_over_sigma.clone() * &dh * &ratio * &fg2_rq
            }
        };
        if mirrored {
            (T::one() - &(dx * &self.inv_lx), -xt)
        } else {
            (dx * &self.inv_lx, xt)
        }
    }

    /// The row of the sample in column `x`, for `v ∈ [0, 1]`: `η` with
    /// `η = (y_v − y₀)/(y₁ − y₀)`, and the sample's `h_v`, `D = √(x² + h²)`
    /// and `√(1 − h_v²)`, from which its direction and distance follow
    /// without `y_v` itself ([`Row`]).
    #[inline(always)]
    pub fn row_at(&self, x: &T, v: &T) -> Row<T> {
        let one = T::one();
        let x2 = x.square();
        let d2 = x2.clone() + &self.parts.h2;
        let dd = d2.sqrt();
        let r0 = (x2.clone() + &self.parts.l0sq).sqrt();
        let r1 = (x2 + &self.parts.l1sq).sqrt();
        let ir0 = one.clone() / &r0;
        let ir1 = one.clone() / &r1;
        let s0 = self.parts.y0.clone() * &ir0;
        let s1 = self.parts.y1.clone() * &ir1;
        // h₁ − h₀ (hⱼ = yⱼ/rⱼ, the paper's h).
        let dh = if self.y_same_sign {
            d2.clone() * &self.parts.ly * &self.y_sum
                / &((self.parts.y1.clone() * &r0 + &(self.parts.y0.clone() * &r1)) * &r0 * &r1)
        } else {
            s1.clone() - &s0
        };
        let vm = one.clone() - v;
        // 1 − h_v² for h_v = (1 − v)h₀ + v h₁: a sum of three non-negative terms.
        let c2 = d2.clone() * &(vm.clone() * &ir0.square() + &(v.clone() * &ir1.square()))
            + &(v.clone() * &vm * &dh.square());
        let c = c2.sqrt();
        let (se, re, ye, dsv, mirrored) = if *v <= T::from_ratio(1, 2) {
            (s0, r0, self.parts.y0.clone(), v.clone() * &dh, false)
        } else {
            (-s1, r1, -self.parts.y1.clone(), vm * &dh, true)
        };
        let s = se.clone() + &dsv;
        let dy = if se < T::zero() && s > T::zero() {
            // y_v (mirrored: −y_v) = D h_v/√(1 − h_v²).
            dd.clone() * &s / &c - &ye
        } else if se == T::zero() {
            re.square() * &dsv / &(dd.clone() * &c)
        } else {
            re.square() * &dsv * &(s.clone() + &se) / &((s.clone() * &dd + &(se * &re * &c)) * &c)
        };
        let (eta, hv) = if mirrored {
            (one - &(dy * &self.inv_ly), -s)
        } else {
            (dy * &self.inv_ly, s)
        };
        Row { eta, hv, dd, c }
    }

    /// `(u, v)` of the local point `(x, y)` with the offsets
    /// `ax = x − x₀`, `bx = x₁ − x`, `ay = y − y₀`, `by = y₁ − y`, all ≥ 0.
    #[allow(clippy::too_many_arguments)]
    pub fn uv_of(&self, x: &T, ax: &T, bx: &T, y: &T, ay: &T, by: &T) -> (T, T) {
        let one = T::one();
        let o = &self.parts;
        let k = o.lengths();
        let col = column(x, &k);
        let u = if ax <= bx {
            let dw = omega_diff(&k, &o.x0, &o.col0, x, &col, ax);
            self.between(&o.col0, &col, &dw) / &o.omega
        } else {
            let dw = omega_diff(&k, x, &col, &o.x1, &o.col1, bx);
            one.clone() - &(self.between(&col, &o.col1, &dw) / &o.omega)
        };
        let d2 = x.square() + &o.h2;
        let ry = (d2.clone() + &y.square()).sqrt();
        let total = row_diff(&o.y0, &col.r0, &o.y1, &col.r1, &o.ly, &d2);
        let v = if ay <= by {
            row_diff(&o.y0, &col.r0, y, &ry, ay, &d2) / &total
        } else {
            one - &(row_diff(y, &ry, &o.y1, &col.r1, by, &d2) / &total)
        };
        (u, v)
    }

    /// The local hit point of the unit local direction `(a, b, c)`
    /// (`c = −w·ẑ > 0`) on the plane: `(x, y)` and the clamped offsets
    /// `(x − x₀, x₁ − x, y − y₀, y₁ − y)`.
    pub fn hit(&self, a: &T, b: &T, c: &T) -> [T; 6] {
        let k = self.parts.h.clone() / c;
        let x = a.clone() * &k;
        let y = b.clone() * &k;
        self.offsets(x, y)
    }

    /// `[x, x − x₀, x₁ − x, y, y − y₀, y₁ − y]` with `x, y` clamped to the
    /// rectangle.
    pub fn offsets(&self, x: T, y: T) -> [T; 6] {
        let zero = T::zero();
        let x = x.clamp(&self.parts.x0, &self.parts.x1);
        let y = y.clamp(&self.parts.y0, &self.parts.y1);
        let ax = (x.clone() - &self.parts.x0).max(&zero);
        let bx = (self.parts.x1.clone() - &x).max(&zero);
        let ay = (y.clone() - &self.parts.y0).max(&zero);
        let by = (self.parts.y1.clone() - &y).max(&zero);
        [x, ax, bx, y, ay, by]
    }
}

/// `y_b/r_b − y_a/r_a` for `y_a ≤ y_b` in the column `D² = d2`, with
/// `len = y_b − y_a` given: a product when `y_a`, `y_b` have the same sign.
fn row_diff<T: Real>(ya: &T, ra: &T, yb: &T, rb: &T, len: &T, d2: &T) -> T {
    let zero = T::zero();
    if *len == zero {
        return zero;
    }
    if (*ya >= zero && *yb >= zero) || (*ya <= zero && *yb <= zero) {
        d2.clone() * len * &(yb.clone() + ya) / &((yb.clone() * ra + &(ya.clone() * rb)) * ra * rb)
    } else {
        yb.clone() / rb - &(ya.clone() / ra)
    }
}

#[inline(always)]
fn anchor<T: Real>(
    col: &Column<T>,
    x: &T,
    mirror: bool,
    sd: &T,
    cd: &T,
    scale: &T,
    k: &Lengths<'_, T>,
) -> Anchor<T> {
    let two = T::from_i64(2);
    let w = col.w.clone();
    let sdw = sd.clone() * &w;
    let n = length(&[cd.clone(), sdw.clone()]);
    let inv_n = T::one() / &n;
    let s_phi = sdw.clone() * &inv_n * scale;
    let c_phi = cd.clone() * &inv_n;
    let sdcd_n = sd.clone() * cd * &inv_n;
    // ℓ₀ℓ₁/N(xₑ), shared by the complements and √S(ωₑ).
    let t = k.l0.clone() * k.l1 / &col.n;
    let (one_m_w, one_p_w) = complements(col, x, &t, k);
    let s_p = one_m_w.clone() * &sdcd_n * scale;
    let s_m = one_p_w.clone() * &sdcd_n * scale;
    let cd2 = cd.square();
    let sd2w = sd.clone() * &sdw;
    let c_p = (cd2.clone() + &sd2w) * &inv_n;
    let c_m = (cd2 - &sd2w) * &inv_n;
    let one_m_abs_w = if w >= T::zero() { one_m_w } else { one_p_w };
    let sqrt_s = two * &t * k.sigma;
    let n_over_sigma = col.n.clone() / k.sigma;
    let w_zero = w == T::zero();
    let abs_w = w.abs();
    if mirror {
        Anchor {
            w_negative: w > T::zero(),
            w: -w,
            abs_w,
            one_m_abs_w,
            x: -x.clone(),
            s_phi: -s_phi,
            c_phi,
            s_p: s_m,
            c_p: c_m,
            s_m: s_p,
            c_m: c_p,
            sqrt_s,
            n_over_sigma,
            n,
            w_zero,
        }
    } else {
        Anchor {
            w_negative: w < T::zero(),
            w,
            abs_w,
            one_m_abs_w,
            x: x.clone(),
            s_phi,
            c_phi,
            s_p,
            c_p,
            s_m,
            c_m,
            sqrt_s,
            n_over_sigma,
            n,
            w_zero,
        }
    }
}
