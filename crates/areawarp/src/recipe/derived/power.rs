//! The first s-panel \[0, b\] of a marginal density that vanishes like a
//! power at s = 0, f(s) = s^e·q(s) with q smooth and positive (a Phong lobe
//! of exponent k seen from the horizon: e = k, declared by the definition,
//! [`WarpDefinition::left_power`](crate::recipe::WarpDefinition::left_power)).
//!
//! q = f/s^e is interpolated instead of f (f itself is not smooth at 0 for a
//! non-integer e), and the CDF on the panel is held as
//! ∫₀ˢ f = s^m·H(s), m = e + 1, with H the polynomial solving
//! s·H' + m·H = q (the Euler operator; H(s) = ∫₀¹ r^(m−1) q(sr) dr, a
//! weighted mean of q over \[0, s\] divided by m). s^m·H(s) keeps the relative
//! accuracy of H at every s > 0, however small F(s) is: no cancellation, no
//! floor. See docs/recipe-quadrature.md §2.

use super::piecewise::stated_root;
use crate::real::Real;
use crate::recipe::chebyshev::{clenshaw, local};
use crate::recipe::invert::{Cdf1, Inverter, Newton};

/// Replaces the value at ξ = −1 (the last of `values`, ordered from ξ = 1 at
/// k = 0, at the Chebyshev points of the second kind cos(kπ/N)) by the value
/// there of the interpolant of degree N − 1 through the others: q(0), where
/// f/s^e is 0/0. With barycentric weights (−1)^k δ_k (δ = 1/2 at the ends)
/// the interpolant through all points but the last, evaluated at it, is
/// Σ_{k<N} w_k q_k / Σ_{k<N} w_k, and Σ_{k<N} w_k = −w_N.
pub(crate) fn fill_origin<T: Real>(values: &mut [T]) {
    let n = values.len();
    if n < 3 {
        return;
    }
    let big_n = n - 1;
    let mut sum = T::zero();
    for (k, v) in values.iter().enumerate().take(big_n) {
        let w = if k == 0 {
            v.clone() / &T::from_i64(2)
        } else {
            v.clone()
        };
        if k.is_multiple_of(2) {
            sum += &w;
        } else {
            sum -= &w;
        }
    }
    // w_N = (−1)^N / 2: q(−1) = −2 (−1)^N · sum.
    let value = sum * &T::from_i64(2);
    values[big_n] = if big_n.is_multiple_of(2) {
        -value
    } else {
        value
    };
}

/// The Chebyshev coefficients h of the polynomial H with (1 + ξ)·dH/dξ +
/// m·H = q on \[−1, 1\] (s·H' + m·H = q on \[0, b\], s = b(1 + ξ)/2), given
/// those of q. In the Chebyshev basis (1 + ξ)T_i' has the coefficient i + m
/// on T_i, 2i on every T_j with 1 ≤ j < i and i on T_0, so the system is
/// upper triangular: h_j = (q_j − 2·Σ_{i>j} i·h_i)/(m + j), halved sum for
/// j = 0.
pub(crate) fn euler_solve<T: Real>(q: &[T], m: &T) -> Vec<T> {
    let n = q.len();
    let mut h = vec![T::zero(); n];
    let mut sum = T::zero(); // Σ_{i>j} i·h_i
    for j in (0..n).rev() {
        let rhs = if j == 0 {
            q[0].clone() - &sum
        } else {
            q[j].clone() - &(sum.clone() * &T::from_i64(2))
        };
        h[j] = rhs / &(m.clone() + &T::from_i64(j as i64));
        sum += &(h[j].clone() * &T::from_i64(j as i64));
    }
    h
}

/// The mass b^m·H(b) of the power panel \[0, b\] of q (H(b) = Σ h_j).
pub(crate) fn power_mass<T: Real>(q: &[T], b: &T, e: &T) -> T {
    PowerPanel::new(q, b, e).mass
}

/// The power panel of a [`PiecewiseDensity`](super::PiecewiseDensity).
#[derive(Clone, Debug)]
pub(crate) struct PowerPanel<T> {
    /// Right end (the left end is 0).
    pub b: T,
    inv_width: T,
    /// The exponent e of f = s^e·q.
    e: T,
    /// m = e + 1.
    m: T,
    /// κ = 2^j with κ^e ≈ q(0): f = (κs)^e·(q/κ^e), so that (κs)^e leaves
    /// the normal range only where f does (s^e alone underflows first when
    /// q is large: s^100 at s = 7·10⁻⁴, where F = 10⁻³⁰⁰ for Phong k = 100).
    kappa: T,
    /// Coefficients of q/κ^e and of H/κ^e.
    q: Vec<T>,
    h: Vec<T>,
    /// ∫₀ᵇ f.
    pub mass: T,
}

impl<T: Real> PowerPanel<T> {
    /// From q's coefficients on \[0, b\].
    pub fn new(q: &[T], b: &T, e: &T) -> Self {
        let m = e.clone() + &T::one();
        let q0 = clenshaw(q, &-T::one()).abs();
        let j = (q0.ln() / &(e.clone() * &T::from_i64(2).ln())).to_f64();
        let j = if j.is_finite() {
            j.round().clamp(-256.0, 256.0) as i32
        } else {
            0
        };
        let kappa = T::exp2i(j);
        let inv = T::one() / &kappa.powf(e);
        let q: Vec<T> = q.iter().map(|c| c.clone() * &inv).collect();
        let h = euler_solve(&q, &m);
        let mut sum = T::zero();
        for c in &h {
            sum += c;
        }
        PowerPanel {
            mass: (kappa.clone() * b).powf(e) * b * &sum,
            b: b.clone(),
            inv_width: T::one() / b,
            e: e.clone(),
            m,
            kappa,
            q,
            h,
        }
    }

    fn xi(&self, s: &T) -> T {
        local(s, &T::zero(), &self.b, &self.inv_width)
    }

    /// f(s) = (κs)^e·q(s)/κ^e (0 at s = 0).
    pub fn density(&self, s: &T) -> T {
        if !(*s > T::zero()) {
            return T::zero();
        }
        (self.kappa.clone() * s).powf(&self.e) * &clenshaw(&self.q, &self.xi(s))
    }

    /// ∫₀ˢ f = (κs)^e·s·H(s)/κ^e (0 at s = 0).
    pub fn left(&self, s: &T) -> T {
        if !(*s > T::zero()) {
            return T::zero();
        }
        (self.kappa.clone() * s).powf(&self.e) * s * &clenshaw(&self.h, &self.xi(s))
    }

    /// s in \[0, b\] with ∫₀ˢ f = y·total (y ≤ 0 or NaN as
    /// [`invert_in_panel`](super::piecewise::invert_in_panel) treats them),
    /// with stated derivatives as there.
    pub fn invert(&self, y: &T, inv_total: &T, total: &T) -> T {
        let cdf = PowerCdf {
            panel: self,
            inv_total,
        };
        let newton = Newton::default();
        if y.is_nan() || !(*y > T::zero()) {
            return newton.invert(&cdf, y).x;
        }
        let target = y.detached() * total;
        // Start from b·(Y/mass)^(1/m) (within a factor (H(b)/H(s))^(1/m)),
        // then Newton on ln(s^m H(s)) − ln Y, whose slope q/(sH) makes it
        // nearly linear in ln s; the safeguarded Newton on F finishes.
        let inv_m = T::one() / &self.m;
        let mut s = (self.b.clone() * &(target.clone() / &self.mass).powf(&inv_m))
            .clamp(&T::zero(), &self.b);
        let ln_target = target.ln();
        for _ in 0..6 {
            if !(s > T::zero()) {
                break;
            }
            let xi = self.xi(&s);
            let hv = clenshaw(&self.h, &xi);
            let qv = clenshaw(&self.q, &xi);
            if !(hv > T::zero() && qv > T::zero()) {
                break;
            }
            let phi =
                self.e.clone() * &(self.kappa.clone() * &s).ln() + &s.ln() + &hv.ln() - &ln_target;
            let ratio = phi * &hv / &qv;
            let next = if ratio >= T::one() {
                s.clone() / &T::from_i64(2)
            } else {
                (s.clone() * &(T::one() - &ratio)).min(&self.b)
            };
            let done = (next.clone() - &s).abs() <= T::exp2i(-(T::precision() as i32 / 2)) * &s;
            s = next;
            if done {
                break;
            }
        }
        let value = newton.solve_in(&cdf, y, s, T::zero(), self.b.clone()).x;
        stated_root(&cdf, y, value)
    }
}

/// F on the power panel, normalized.
struct PowerCdf<'a, T> {
    panel: &'a PowerPanel<T>,
    inv_total: &'a T,
}

impl<T: Real> Cdf1<T> for PowerCdf<'_, T> {
    fn cdf(&self, s: &T) -> T {
        self.panel.left(s) * self.inv_total
    }
    fn pdf(&self, s: &T) -> T {
        self.panel.density(s) * self.inv_total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recipe::chebyshev::ChebyshevLevels;

    #[test]
    fn origin_fill_is_the_lower_degree_interpolant() {
        // q = 1 + ξ + ξ² at 9 points: degree 2 < 8, so the fill is exact.
        let levels = ChebyshevLevels::<f64>::new();
        let level = levels.level(9);
        let mut v: Vec<f64> = level.points.iter().map(|x| 1.0 + x + x * x).collect();
        let exact = v[8];
        v[8] = f64::NAN;
        fill_origin(&mut v);
        assert!((v[8] - exact).abs() < 1e-14, "{} {exact}", v[8]);
    }

    #[test]
    fn euler_solve_integrates_a_power() {
        // q(s) = 1 + s on [0, 1/2] (ξ: q = 5/4 + ξ/4), e = 1/2, m = 3/2:
        // ∫₀ˢ x^(1/2)(1 + x) dx = s^(3/2)(2/3 + 2s/5).
        let b = 0.5f64;
        let e = 0.5f64;
        let p = PowerPanel::new(&[1.25, 0.25], &b, &e);
        for s in [1e-200, 1e-30, 1e-3, 0.1, 0.5] {
            let exact = f64::powf(s, 1.5) * (2.0 / 3.0 + 0.4 * s);
            assert!((p.left(&s) / exact - 1.0).abs() < 4e-16, "{s}");
        }
        let total = 2.0;
        let inv_total = 0.5;
        for y in [1e-300, 1e-100, 1e-10, 0.05] {
            let s = p.invert(&y, &inv_total, &total);
            assert!((p.left(&s) * inv_total / y - 1.0).abs() < 1e-15, "{y} {s}");
        }
    }
}
