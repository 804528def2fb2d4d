//! Chebyshev interpolation on an interval, generic over the scalar: the
//! quadrature engine of the derived warps ([`super::DerivedWarp`]).
//!
//! A function f on a panel `[a, b]` is sampled at the n Chebyshev points of
//! the second kind ξ_k = cos(kπ/N), N = n − 1 (mapped to `[a, b]`), and
//! replaced by its interpolant p(ξ) = Σ c_j T_j(ξ). Its integral from `a` to
//! any x is the integral of p, again a Chebyshev series (Clenshaw–Curtis
//! quadrature, indefinite form): evaluating F(x) costs one Clenshaw sum, not
//! new evaluations of f. The points are nested (n = 5, 9, 17, …: the points
//! of level n are among those of level 2n − 1), so doubling reuses every
//! value, and the interpolant is accepted when its trailing coefficients have
//! decayed to the rounding level of the type ([`tail`]).
//!
//! Every node, weight and cosine is computed in the scalar type itself
//! (`T::pi()`, `sin`), never taken from an `f64` table, so the same code is
//! 24-, 53- or 256-bit accurate.

use crate::real::Real;

/// The node counts tried on a panel, coarsest first.
pub(crate) const LEVELS: [usize; 6] = [5, 9, 17, 33, 65, 129];

/// The largest node count any panel may use (stack buffers are this long).
pub(crate) const MAX_NODES: usize = 129;

/// The largest node count used for a type of `p` significand bits: 33 for
/// `f32`, 65 for `f64`, 129 beyond. A panel that is not resolved with it
/// is split.
pub(crate) fn max_nodes(p: u32) -> usize {
    if p <= 24 {
        33
    } else if p <= 53 {
        65
    } else {
        129
    }
}

/// Trailing coefficients must be below this many units of roundoff times
/// the panel's largest value for the interpolant to count as resolved.
pub(crate) const TAIL_ULPS: i64 = 32;

/// The cosines, Clenshaw–Curtis weights and points of one node count n,
/// computed in `T`.
#[derive(Clone, Debug)]
pub(crate) struct ChebyshevLevel<T> {
    /// Number of points n.
    pub n: usize,
    /// cos(jπ/N) for j = 0 … 2N − 1 (N = n − 1): the DCT's cosines.
    cos: Vec<T>,
    /// The points ξ_k = cos(kπ/N), k = 0 … N (from 1 down to −1).
    pub points: Vec<T>,
    /// 1 − ξ_k = 2 sin²(kπ/(2N)), without cancellation near ξ = 1.
    one_minus: Vec<T>,
    /// 1 + ξ_k = 2 sin²((N − k)π/(2N)), without cancellation near ξ = −1.
    one_plus: Vec<T>,
    /// Weights w_k with ∫₋₁¹ p = Σ w_k f(ξ_k) (Clenshaw–Curtis).
    pub weights: Vec<T>,
}

impl<T: Real> ChebyshevLevel<T> {
    /// The level with `n ≥ 2` points.
    pub fn new(n: usize) -> Self {
        let big_n = (n - 1) as i64;
        // cos(jπ/N) = sin(π(N − 2j)/(2N)): symmetric, exact zero in the middle.
        let cos: Vec<T> = (0..2 * big_n)
            .map(|j| (T::pi() * &T::from_ratio(big_n - 2 * j, 2 * big_n)).sin())
            .collect();
        let points: Vec<T> = cos[..n].to_vec();
        let two_sin2 = |k: i64| -> T {
            (T::pi() * &T::from_ratio(k, 2 * big_n)).sin().square() * &T::from_i64(2)
        };
        let one_minus: Vec<T> = (0..n as i64).map(two_sin2).collect();
        let one_plus: Vec<T> = (0..n as i64).map(|k| two_sin2(big_n - k)).collect();
        // ∫₋₁¹ T_j = 2/(1 − j²) for even j, 0 for odd j.
        let mut weights = Vec::with_capacity(n);
        let two_over_n = T::from_ratio(2, big_n);
        for k in 0..n {
            let mut acc = T::zero();
            let mut j = 0;
            while j < n {
                let mut term =
                    T::from_ratio(2, 1 - (j as i64) * (j as i64)) * &cos[(j * k) % (2 * (n - 1))];
                if j == 0 || j == n - 1 {
                    term /= &T::from_i64(2);
                }
                acc += &term;
                j += 2;
            }
            let mut w = acc * &two_over_n;
            if k == 0 || k == n - 1 {
                w /= &T::from_i64(2);
            }
            weights.push(w);
        }
        ChebyshevLevel {
            n,
            cos,
            points,
            one_minus,
            one_plus,
            weights,
        }
    }

    /// The k-th point mapped to `[a, b]` (`half` = (b − a)/2), measured from
    /// the nearer end so that points next to an end keep their relative
    /// distance to it: `b` for k = 0, `a` for k = N.
    pub fn node(&self, a: &T, b: &T, half: &T, k: usize) -> T {
        if k == 0 {
            b.clone()
        } else if k == self.n - 1 {
            a.clone()
        } else if 2 * k < self.n {
            b.clone() - &(half.clone() * &self.one_minus[k])
        } else {
            a.clone() + &(half.clone() * &self.one_plus[k])
        }
    }

    /// Chebyshev coefficients c_0 … c_{n−1} of the interpolant through
    /// `values[k] = f(ξ_k)` (a DCT-I, O(n²)), written into `out`.
    pub fn coefficients_into(&self, values: &[T], out: &mut [T]) {
        let n = self.n;
        // A constant is represented exactly (c_0 = value, the rest 0), so
        // that a conditional uniform in t inverts to t = v exactly.
        if values[1..n].iter().all(|v| *v == values[0]) {
            out[0] = values[0].clone();
            for c in out.iter_mut().take(n).skip(1) {
                *c = T::zero();
            }
            return;
        }
        let period = 2 * (n - 1);
        let two_over_n = T::from_ratio(2, (n - 1) as i64);
        let half = T::from_ratio(1, 2);
        for (j, c) in out.iter_mut().enumerate().take(n) {
            let mut acc = (values[0].clone()
                + &(values[n - 1].clone() * &self.cos[(j * (n - 1)) % period]))
                * &half;
            for (k, v) in values.iter().enumerate().take(n - 1).skip(1) {
                acc += &(v.clone() * &self.cos[(j * k) % period]);
            }
            let mut cj = acc * &two_over_n;
            if j == 0 || j == n - 1 {
                cj *= &half;
            }
            *c = cj;
        }
    }

    /// The coefficients of the polynomial through `values[k]` at the
    /// *actual* local coordinates `xi[k]` of the (rounded) nodes: the DCT,
    /// then up to four steps of iterative refinement with the residuals at
    /// `xi` (each step divides the error by about the nodes' displacement
    /// times n²). Where a panel is narrow compared with its distance from 0
    /// the rounded nodes sit measurably off the Chebyshev points; without
    /// this the interpolant would carry a systematic error of about
    /// u·|x|·|f'| (large near a zero of f at x = 1). `work` needs 2n slots.
    pub fn coefficients_at(&self, values: &[T], xi: &[T], out: &mut [T], work: &mut [T]) {
        let n = self.n;
        self.coefficients_into(values, out);
        let mut scale = T::zero();
        for v in &values[..n] {
            scale = scale.max(&v.abs());
        }
        let bound = T::unit_roundoff() * &scale;
        let (residual, correction) = work.split_at_mut(n);
        for _ in 0..4 {
            let mut worst = T::zero();
            for k in 0..n {
                residual[k] = values[k].clone() - &clenshaw(&out[..n], &xi[k]);
                worst = worst.max(&residual[k].abs());
            }
            if !(worst > bound) {
                break;
            }
            self.coefficients_into(residual, correction);
            for (c, d) in out.iter_mut().zip(correction.iter()).take(n) {
                *c += d;
            }
        }
    }

    /// Whether the rounded nodes of `[a, b]` have local coordinates `xi`
    /// within a unit roundoff of the Chebyshev points (then the DCT alone
    /// interpolates them).
    pub fn nodes_exact(&self, xi: &[T]) -> bool {
        let u = T::unit_roundoff();
        self.points
            .iter()
            .zip(xi)
            .all(|(p, x)| (p.clone() - x).abs() <= u)
    }

    /// ∫₋₁¹ of the interpolant through `values`.
    pub fn integral(&self, values: &[T]) -> T {
        let mut acc = T::zero();
        for (w, v) in self.weights.iter().zip(values) {
            acc += &(w.clone() * v);
        }
        acc
    }
}

/// All levels up to `max_n` points.
#[derive(Clone, Debug)]
pub(crate) struct ChebyshevLevels<T> {
    /// The levels, coarsest first.
    pub levels: Vec<ChebyshevLevel<T>>,
}

impl<T: Real> ChebyshevLevels<T> {
    /// Levels of [`LEVELS`] up to [`max_nodes`] for `T`.
    pub fn new() -> Self {
        let max_n = max_nodes(T::precision());
        ChebyshevLevels {
            levels: LEVELS
                .iter()
                .filter(|&&n| n <= max_n)
                .map(|&n| ChebyshevLevel::new(n))
                .collect(),
        }
    }

    /// The level with `n` points.
    pub fn level(&self, n: usize) -> &ChebyshevLevel<T> {
        self.levels
            .iter()
            .find(|l| l.n == n)
            .expect("a node count of LEVELS")
    }
}

/// The local coordinate ξ = ((x − a) − (b − x)) / (b − a) of `x` on
/// `[a, b]`; `inv_width` = 1/(b − a). For the dyadic panels of the
/// partitions both differences are exact (Sterbenz), so ξ is accurate to a
/// unit roundoff even on a panel much narrower than |x|.
pub(crate) fn local<T: Real>(x: &T, a: &T, b: &T, inv_width: &T) -> T {
    ((x.clone() - a) - &(b.clone() - x)) * inv_width
}

/// Σ c_j T_j(ξ) by Clenshaw's recurrence (ξ any scalar, dual numbers included).
pub(crate) fn clenshaw<T: Real>(c: &[T], xi: &T) -> T {
    let mut b1 = T::zero();
    let mut b2 = T::zero();
    let two_xi = xi.clone() * &T::from_i64(2);
    for cj in c.iter().skip(1).rev() {
        let b0 = two_xi.clone() * &b1 - &b2 + cj;
        b2 = b1;
        b1 = b0;
    }
    match c.first() {
        Some(c0) => xi.clone() * &b1 - &b2 + c0,
        None => T::zero(),
    }
}

/// The coefficients of ∫₋₁^ξ p (`left`, n + 1 of them, zero at ξ = −1) and
/// of ∫_ξ¹ p (`right`, zero at ξ = 1), each multiplied by `scale` (the
/// panel's half-width, turning ξ-integrals into x-integrals), from the
/// coefficients `c` of p. Returns the whole integral ∫₋₁¹ p · scale.
pub(crate) fn integral_coefficients_into<T: Real>(
    c: &[T],
    scale: &T,
    left: &mut [T],
    right: &mut [T],
) -> T {
    let n = c.len();
    let at = |j: usize| -> T { if j < n { c[j].clone() } else { T::zero() } };
    // ∫T_0 = T_1, ∫T_1 = T_2/4, ∫T_j = T_{j+1}/(2(j+1)) − T_{j−1}/(2(j−1)).
    let mut sum_alt = T::zero(); // Σ_{k≥1} b_k (−1)^k = value at ξ = −1 without b_0
    let mut sum_all = T::zero(); // Σ_{k≥1} b_k = value at ξ = 1 without b_0
    for k in 1..=n {
        let bk = if k == 1 {
            at(0) - &(at(2) / &T::from_i64(2))
        } else {
            (at(k - 1) - &at(k + 1)) / &T::from_i64(2 * k as i64)
        };
        let bk = bk * scale;
        if k % 2 == 1 {
            sum_alt -= &bk;
        } else {
            sum_alt += &bk;
        }
        sum_all += &bk;
        right[k] = -bk.clone();
        left[k] = bk;
    }
    // left(−1) = 0: b_0 = −Σ b_k (−1)^k; right(1) = 0: r_0 = Σ b_k.
    left[0] = -sum_alt.clone();
    right[0] = sum_all.clone();
    sum_all - &sum_alt
}

/// The size of the interpolant's tail relative to `scale` (the largest
/// |value|): max |c_j| over the last max(3, n/4) coefficients / scale (0
/// for a zero function).
pub(crate) fn tail<T: Real>(c: &[T], scale: &T) -> T {
    let n = c.len();
    let count = (n / 4).max(3).min(n);
    let mut worst = T::zero();
    for cj in &c[n - count..] {
        worst = worst.max(&cj.abs());
    }
    if *scale > T::zero() {
        worst / scale
    } else {
        worst
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn resolved<T: Real>(c: &[T], scale: &T) -> bool {
        tail(c, scale) <= T::from_i64(TAIL_ULPS) * &T::unit_roundoff()
    }

    fn values<T: Real>(level: &ChebyshevLevel<T>, f: impl Fn(&T) -> T) -> Vec<T> {
        level.points.iter().map(f).collect()
    }

    #[test]
    fn interpolant_reproduces_the_function() {
        let lvl = ChebyshevLevel::<f64>::new(33);
        let f = |x: &f64| (2.0 * x).exp() * x.sin();
        let v = values(&lvl, f);
        let mut c = vec![0.0; 33];
        lvl.coefficients_into(&v, &mut c);
        assert!(resolved(&c, &7.4));
        for x in [-1.0, -0.77, 0.0, 0.3, 0.999, 1.0] {
            assert!((clenshaw(&c, &x) - f(&x)).abs() < 1e-14, "{x}");
        }
    }

    #[test]
    fn integrals_left_and_right() {
        let lvl = ChebyshevLevel::<f64>::new(17);
        let v = values(&lvl, |x| x.cos());
        let mut c = vec![0.0; 17];
        lvl.coefficients_into(&v, &mut c);
        let (mut l, mut r) = (vec![0.0; 18], vec![0.0; 18]);
        let total = integral_coefficients_into(&c, &1.0, &mut l, &mut r);
        let exact = 2.0 * 1f64.sin();
        assert!((total - exact).abs() < 1e-15);
        assert!((lvl.integral(&v) - exact).abs() < 1e-15);
        for x in [-1.0, -0.5, 0.2, 1.0] {
            let left = x.sin() + 1f64.sin();
            assert!((clenshaw(&l, &x) - left).abs() < 1e-15, "{x}");
            assert!((clenshaw(&r, &x) - (exact - left)).abs() < 1e-15, "{x}");
        }
        assert!(clenshaw(&l, &-1.0).abs() < 1e-15);
    }

    #[test]
    fn unresolved_function_is_detected() {
        let lvl = ChebyshevLevel::<f64>::new(9);
        let v = values(&lvl, |x| (20.0 * x).sin());
        let mut c = vec![0.0; 9];
        lvl.coefficients_into(&v, &mut c);
        assert!(!resolved(&c, &1.0));
    }

    #[cfg(feature = "mpfr")]
    #[test]
    fn weights_are_exact_at_256_bits() {
        use crate::real::Mpfr256 as M;
        let lvl = ChebyshevLevel::<M>::new(65);
        // ∫₋₁¹ eˣ = e − 1/e, resolved to 256 bits with 65 points.
        let v = values(&lvl, |x| x.exp());
        let exact = M::one().exp() - &(-M::one()).exp();
        let err = (lvl.integral(&v) - &exact).abs();
        assert!(err < M::exp2i(-250), "{err}");
        let mut c = vec![M::zero(); 65];
        lvl.coefficients_into(&v, &mut c);
        assert!(resolved(&c, &M::from_i64(3)));
    }
}
