//! The per-sample formulas of the [`Robust`](super::SphericalTriangleVariant::Robust)
//! evaluation: the map from one [`Anchor`] (shared by the shape and the
//! one-shot path) and the inverse.

use super::build::{Anchor, norm2};
use super::{SphericalTriangle, clamp_keep_nan};
use crate::real::Real;
use crate::shapes::turns::clamp_unit;
use crate::shapes::wide::unit_vector;
use crate::vector::Vec3;

/// The anchor the map uses for `u` (A for `u ≤ 1/2`, C otherwise) and the
/// sub-triangle's half area measured from it; NaN `u` selects C and stays NaN.
#[inline]
pub(super) fn uses_anchor_a<T: Real>(u: &T) -> bool {
    *u <= T::from_ratio(1, 2)
}

/// ψ(u, v) from the anchor of `u` (see the type's docs), `b` the unit
/// vertex B, `b_norm2` = |B|² as stored, `half_omega` = Ω/2. `u`, `v` are
/// clamped to `[0, 1]`; a NaN `u` or `v` gives a NaN point.
///
/// Inlined into every caller: the prepared sample
/// ([`SphericalTriangle::map_robust`](super::SphericalTriangle::map_robust)),
/// where it is measured faster (per sample 37.9 → 36.5 ns in `f32`,
/// 46.7 → 45.5 ns in `f64`), and the one-shots. The `f64` one-shot
/// direction had called it out of line, faster with the map of that time
/// (ratio 2.55 against 2.96 inlined); since the map's offset along the
/// tangent at B is formed once, inlined is faster there too (2.400–2.409
/// against 2.493–2.497). Measurements: `docs/spherical-triangle.md` §5b,
/// `docs/spherical-triangle-one-shot.md`.
#[inline(always)]
pub(super) fn map_from<T: Real>(
    anchor: &Anchor<T>,
    b: &Vec3<T>,
    b_norm2: &T,
    half_omega: &T,
    u: &T,
    v: &T,
) -> Vec3<T> {
    let u = clamp_unit(u);
    let v = clamp_unit(v);
    let one = T::one();
    let two = T::from_i64(2);
    let half = T::from_ratio(1, 2);
    let h = if uses_anchor_a(&u) {
        u * half_omega
    } else {
        (one.clone() - &u) * half_omega
    };
    let (sh, ch) = h.sin_cos();
    // Step 1 (V = anchor vertex, c = ∠VB, α = angle at V, d, k as in the
    // type's docs): tan(b_s/2) = n/m with n = (1 + cos c) sin h / d and
    // m = cos h − (k/d) sin h = sin(α − h)/sin α (eq. T divided by d).
    // The angle β_s at B between the arcs B V and B C_s (eq. B):
    // (sin β_s, cos β_s) ∝ (nb, cb) = (sin h·m, 1 − sin h (k cos h + d sin h)/d)/sin²(c/2).
    let n = anchor.k1_d.clone() * &sh;
    let m = ch.clone() - &(anchor.k_d.clone() * &sh);
    let nb = sh.clone() * &m * &anchor.inv_s2;
    let cb = one.clone() - &(sh.clone() * &(anchor.k_d.clone() * &ch + &sh) * &anchor.inv_s2);
    // sin b_s = 2nm/(n² + m²), 1 − cos b_s = 2n²/(n² + m²):
    // C_s − V = sin b_s·[W|V] − (1 − cos b_s)·V, its numerator formed
    // while the division runs (the chain waits for one product after it).
    let two_n = n.clone() + &n;
    let inv_nm2 = one.clone() / &(n.square() + &m.square());
    let numerator = anchor
        .along
        .scale(&(two_n.clone() * &m))
        .sub(&anchor.vertex.scale(&(two_n * &n)));
    let nd2 = nb.square() + &cb.square();
    // Independent of the first: the two divisions overlap. `4/|(nb, cb)|²`:
    // the factor 2 of the roots below taken inside them (√(4x) = 2√x
    // exactly), off the sample's dependent chain.
    let inv4_nd2 = T::from_i64(4) / &nd2;
    let delta = numerator.scale(&inv_nm2);
    // D = C_s − B.
    let d_vec = delta.add(&anchor.v_minus_b);
    // 4 sin²(a_s/2) of the arc B C_s.
    let q = norm2(&d_vec);
    // W·|(nb, cb)|, the unit tangent at B towards C_s scaled (off the
    // dependent chain: the sample's offsets along it wait only for their
    // coefficient).
    let towards = anchor.t_b.scale(&cb).add(&anchor.n_b.scale(&nb));
    // Step 2: θ = ∠BP with sin²(θ/2) = v sin²(a_s/2),
    // cos²(θ/2) = cos²(a_s/2) + (1 − v) sin²(a_s/2).
    let p = if v <= half {
        // P = B + sin θ·W − (1 − cos θ)·B with W = (cb·t_b + nb·n_b)/|(nb, cb)|;
        // here cos²(θ/2) = 1 − sin²(θ/2) ≥ 1/2 (no cancellation, and
        // cos²(a_s/2) is not needed), and sin θ/|(nb, cb)| is one root.
        // sin²(θ/2) = (v/4)·q, with v/4 (exact for a normal v), 1 −
        // sin²(θ/2) and (v/4)·4/|(nb, cb)|² formed off the chain: after q,
        // one product each before the root's argument, then the root.
        let v4 = v.clone() / T::from_i64(4);
        let cos2 = one.clone() - &(q.clone() * &v4);
        let f = (q.clone() * &(v4.clone() * &inv4_nd2) * &cos2).sqrt();
        // B − (1 − cos θ)·B = (1 − 2 sin²(θ/2))·B, beside the root.
        let b_part = b.scale(&(one.clone() - &(q * &(v4 * &two))));
        b_part.add(&towards.scale(&f))
    } else {
        // From the other end: with C_s = cos a_s·B + sin a_s·W,
        // P = C_s + (cos θ − cos a_s)·B + (sin θ − sin a_s)·W, where
        // cos θ − cos a_s = 2 sin²(a_s/2)(1 − v) exactly and
        // sin θ − sin a_s = 2(sin(θ/2) cos(θ/2) − sin(a_s/2) cos(a_s/2)):
        // both vanish at v = 1 (P = C_s, so (0, 1) ↦ A and (1, 1) ↦ C),
        // and are small, with small absolute errors, near it.
        // cos²(a_s/2) = |C_s + B|²/4 keeps its accuracy when C_s ≈ −B.
        let s2 = q / T::from_i64(4);
        let c2 = norm2(&delta.add(&anchor.v_plus_b)) / T::from_i64(4);
        let cp2 = c2.clone() + &((one.clone() - &v) * &s2);
        // sin θ = 2 sin(θ/2) cos(θ/2) and sin a_s, over |(nb, cb)|.
        let sin_theta = (v.clone() * &s2 * &cp2 * &inv4_nd2).sqrt();
        let sin_a = (s2.clone() * &c2 * &inv4_nd2).sqrt();
        let w_coef = sin_theta - &sin_a;
        let b_coef = s2 * &(one - &v) * &two;
        let c_s = anchor.vertex.add(&delta);
        let offset = b.scale(&b_coef).add(&towards.scale(&w_coef));
        c_s.add(&offset)
    };
    // |P| = 1 + O(u): one Newton step towards |P| = |B| (|B| = 1 up to
    // the rounding of the stored vertex), P·(1 + (|B|² − |P|²)/2), brings
    // the norm to within about one unit of roundoff without a square root
    // and leaves P = B (v = 0) untouched.
    let x = norm2(&p);
    p.scale(&(T::one() + &((b_norm2.clone() - &x) / &two)))
}

impl<T: Real> SphericalTriangle<T> {
    /// Where the great circle through B and the unit direction `q` meets the
    /// arc AC: returns `(sin(θ/2), cos(θ/2), n̂₁, q − B)` with θ = ∠AC_s and
    /// `n̂₁ = (B × q)/|B × q|`; `None` if `q = ±B`. Where that circle
    /// holds the whole arc AC to rounding (a sliver: the chart's `(x, y)`
    /// below 16 units of roundoff), the end of the arc beyond q as seen
    /// from B.
    pub(super) fn chart_half_angle(&self, q: &Vec3<T>) -> Option<(T, T, Vec3<T>, Vec3<T>)> {
        let w = q.sub(&self.b);
        // n₁ = B × q, from the shorter of q ∓ B (no cancellation near ±B).
        let n1 = if q.dot(&self.b) >= T::zero() {
            self.b.cross(&w)
        } else {
            self.b.cross(&q.add(&self.b))
        };
        let n1 = unit_vector(&n1)?;
        // C_s = cos θ·A + sin θ·[C|A] with C_s·n₁ = 0:
        // (sin θ, cos θ) ∝ (−A·n₁, [C|A]·n₁), A·n₁ = (A − B)·n₁ exactly.
        let mut y = -self.a_minus_b.dot(&n1);
        let mut x = self.c_perp.dot(&n1);
        // Of the two antipodal intersections take the one on the side of the
        // arc's midpoint: x·cos(b/2) + y·sin(b/2) ≥ 0, scaled by 2cos(b/2).
        if x.clone() * &self.one_plus_cos_b + &(y.clone() * &self.sin_b) < T::zero() {
            x = -x;
            y = -y;
        }
        let r = x.hypot(&y);
        // n̂₁ is accurate to a few units of roundoff (w = q − B is exact
        // where q ≈ B), and so are x and y: below 16u, (x, y) is noise.
        if r <= T::from_i64(16) * &T::unit_roundoff() {
            // The great circle through B and q holds A and the arc AC to
            // working precision (a sliver narrower than rounding, q on it),
            // so where it meets the arc is not determined. The sliver lies
            // along one great circle, and q on the arc from B to one end V
            // of AC (A: θ = 0; C: θ = b), the one with the larger
            // (q − B)·(V − B): that end serves as q's chart, and v follows
            // (`docs/spherical-triangle.md` §6, "Slivers below rounding").
            let c_minus_b = self.c.sub(&self.b);
            let (s, c) = if w.dot(&c_minus_b) > w.dot(&self.a_minus_b) {
                // tan(b/2) = sin b/(1 + cos b).
                let m = self.sin_b.hypot(&self.one_plus_cos_b);
                (self.sin_b.clone() / &m, self.one_plus_cos_b.clone() / &m)
            } else {
                (T::zero(), T::one())
            };
            return Some((s, c, n1, w));
        }
        if !r.is_finite_above(&T::zero()) {
            return None;
        }
        // tan(θ/2) = y/(r + x) = (r − x)/y, whichever does not cancel.
        let (s, c) = if x >= T::zero() {
            (y, r + &x)
        } else {
            (r - &x, y)
        };
        let m = s.hypot(&c);
        Some((s / &m, c / &m, n1, w))
    }

    /// `(C_s − B, C_s + B)` for `C_s` at the half-angle `(sin(θ/2), cos(θ/2))`
    /// from A: `C_s − A = 2 sin(θ/2)(cos(θ/2)[C|A] − sin(θ/2)A)`.
    pub(super) fn chart_offsets(&self, s: &T, c: &T) -> (Vec3<T>, Vec3<T>) {
        let two_s = s.clone() * &T::from_i64(2);
        let delta = self
            .c_perp
            .scale(&(two_s.clone() * c))
            .sub(&self.a.scale(&(two_s * s)));
        (delta.add(&self.a_minus_b), delta.add(&self.a_plus_b))
    }

    /// ψ⁻¹ by the robust formulas (see [`Warp::inverse`](crate::warp::Warp::inverse)), without the
    /// on-shape test; `q` must be a unit vector.
    /// `q` (a unit vector) moved onto the triangle if rounding left it just
    /// outside: clipped against each edge plane it violates,
    /// `q − (n·q)·n` renormalized. Used by the inverse of a narrower type
    /// evaluated in the wide one: a sample of a thin triangle rounded to
    /// `f32` may lie off it by more than the triangle's width; the chart of
    /// such a point (where the great circle through B and q meets the arc
    /// AC) would land anywhere along the arc, the chart of its projection
    /// lands next to the sample.
    pub(super) fn onto_triangle(&self, q: &Vec3<T>) -> Vec3<T> {
        let mut q = q.clone();
        for _ in 0..2 {
            let mut moved = false;
            for n in self.normals() {
                let g = n.dot(&q);
                if g < T::zero() {
                    q = q.sub(&n.scale(&g));
                    moved = true;
                }
            }
            if !moved {
                break;
            }
            match unit_vector(&q) {
                Some(u) => q = u,
                None => break,
            }
        }
        q
    }

    pub(super) fn inverse_robust(&self, q: &Vec3<T>) -> Option<(T, T)> {
        let Some((s, c, n1, w)) = self.chart_half_angle(q) else {
            // q = B (v = 0, any u), or q = −B (not on the triangle).
            return if norm2(&q.sub(&self.b)) == T::zero() {
                Some((T::zero(), T::zero()))
            } else {
                None
            };
        };
        let (d_vec, e_vec) = self.chart_offsets(&s, &c);
        let two = T::from_i64(2);
        // Area of A B C_s measured from A (eq. T at A):
        // tan(A_s/2) = sin c sin α·sin(θ/2) / ((1 + cos c) cos(θ/2) + sin c cos α·sin(θ/2)).
        // It needs only θ, but its denominator cancels when A_s ≈ π with
        // A, B, C_s near one great circle (nearly hemispherical triangles).
        let num_a = self.d.clone() * &s;
        let (t1, t2) = (self.k1a.clone() * &c, self.ka.clone() * &s);
        let den_a = t1.clone() + &t2;
        let half_area = if t1.abs() + &t2.abs() <= num_a.hypot(&den_a) * &T::from_i64(8) {
            num_a.atan2(&den_a)
        } else {
            // Measured from B instead (eq. T at B): with W = n̂₁ × B the unit
            // tangent at B towards q, sin c·sin β_s = det(A, B, W) = A·n̂₁ and
            // sin c·cos β_s = A·W,
            // tan(A_s/2) = sin(a_s/2)·sin c sin β_s / ((1 + cos c) cos(a_s/2) + sin c cos β_s·sin(a_s/2)).
            // β_s comes from q directly, and cos(a_s/2) — ill-determined when
            // C_s ≈ −B — only enters to absolute accuracy.
            let sa = norm2(&d_vec).sqrt() / &two;
            let ca = norm2(&e_vec).sqrt() / &two;
            let tangent_b = n1.cross(&self.b);
            let sign = if self.positive { T::one() } else { -T::one() };
            let d_b = self.a_minus_b.dot(&n1) * &sign;
            let k_b = self.a_minus_b.dot(&tangent_b);
            (sa.clone() * &d_b).atan2(&(self.k1a.clone() * &ca + &(k_b * &sa)))
        };
        let u = half_area / &self.half_omega;
        // v = sin²(∠Bq/2) / sin²(a_s/2) = |q − B|² / |C_s − B|².
        let v = norm2(&w) / &norm2(&d_vec);
        Some((clamp_keep_nan(&u), clamp_keep_nan(&v)))
    }
}
