//! Small interpolants for the tables: Chebyshev points of both kinds, the
//! monomial coefficients of the interpolant through the nodes' actual
//! (rounded) positions, and Horner's rule. Degrees are small (≤ 8), where
//! the monomial basis on [−1, 1] is well conditioned.

use crate::real::Real;

/// The points and cosines of one degree, computed in `T`.
#[derive(Clone, Debug)]
pub(crate) struct Basis<T> {
    /// The degree d (d + 1 points).
    pub degree: usize,
    /// Second-kind points cos(kπ/d), k = 0 … d (ends included, from 1 to −1).
    pub second: Vec<T>,
    /// First-kind points cos((2k + 1)π/(2(d + 1))), k = 0 … d (interior).
    pub first: Vec<T>,
    /// Check points between the second-kind points: cos((2k + 1)π/(2d)).
    pub checks_second: Vec<T>,
    /// Check points between the first-kind points and beyond them:
    /// cos(kπ/(d + 1)), k = 0 … d + 1 (the ends included).
    pub checks_first: Vec<T>,
}

/// cos(π·num/den), accurate near zero: sin(π(den − 2num)/(2den)).
fn cos_pi<T: Real>(num: i64, den: i64) -> T {
    (T::pi() * &T::from_ratio(den - 2 * num, 2 * den)).sin()
}

impl<T: Real> Basis<T> {
    /// The basis of degree `degree ≥ 1`.
    pub fn new(degree: usize) -> Self {
        let d = degree as i64;
        let second = (0..=d).map(|k| cos_pi(k, d)).collect();
        let first = (0..=d).map(|k| cos_pi(2 * k + 1, 2 * (d + 1))).collect();
        let checks_second = (0..d).map(|k| cos_pi(2 * k + 1, 2 * d)).collect();
        let checks_first = (0..=d + 1).map(|k| cos_pi(k, d + 1)).collect();
        Basis {
            degree,
            second,
            first,
            checks_second,
            checks_first,
        }
    }
}

/// The monomial coefficients of the polynomial of degree n − 1 through
/// `(xi[k], values[k])`: the Vandermonde system solved by Gaussian
/// elimination with partial pivoting (well conditioned for the few, nearly
/// Chebyshev, points used here). Interpolating at the *actual* local
/// coordinates of the rounded nodes matters where the function is steep
/// (F⁻¹ near a pole at u = 1, where a node off by half an ulp of u moves the
/// value by far more than the tolerance).
pub(crate) fn interpolate<T: Real>(xi: &[T], values: &[T]) -> Vec<T> {
    let n = xi.len();
    // Augmented matrix rows [ξ^0 … ξ^(n−1) | f].
    let mut a: Vec<Vec<T>> = xi
        .iter()
        .zip(values)
        .map(|(x, f)| {
            let mut row = Vec::with_capacity(n + 1);
            let mut p = T::one();
            for _ in 0..n {
                row.push(p.clone());
                p *= x;
            }
            row.push(f.clone());
            row
        })
        .collect();
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&i, &j| {
                a[i][col]
                    .abs()
                    .partial_cmp(&a[j][col].abs())
                    .unwrap_or(core::cmp::Ordering::Equal)
            })
            .unwrap_or(col);
        a.swap(col, pivot);
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for row in lower.iter_mut() {
            let factor = row[col].clone() / &pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= &(factor.clone() * p);
            }
        }
    }
    let mut m = vec![T::zero(); n];
    for r in (0..n).rev() {
        let mut acc = a[r][n].clone();
        for c in r + 1..n {
            acc -= &(a[r][c].clone() * &m[c]);
        }
        m[r] = acc / &a[r][r];
    }
    m
}

/// [`interpolate`] through the distinct points only (a panel a few floats
/// wide rounds several nodes to the same value), padded with zero
/// coefficients to `xi.len()`: the interpolant of lower degree then passes
/// through every float the panel holds.
pub(crate) fn interpolate_distinct<T: Real>(xi: &[T], values: &[T]) -> Vec<T> {
    let mut px: Vec<T> = Vec::with_capacity(xi.len());
    let mut pv: Vec<T> = Vec::with_capacity(xi.len());
    for (x, v) in xi.iter().zip(values) {
        if !px.iter().any(|p| p == x) {
            px.push(x.clone());
            pv.push(v.clone());
        }
    }
    let mut m = interpolate(&px, &pv);
    m.resize(xi.len(), T::zero());
    m
}

/// Σ m_i ξ^i by Horner's rule.
#[inline]
pub(crate) fn horner<T: Real>(m: &[T], xi: &T) -> T {
    let mut acc = T::zero();
    for c in m.iter().rev() {
        acc = acc * xi + c;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolants_at_both_kinds() {
        let b = Basis::<f64>::new(5);
        let f = |x: f64| (x + 0.3).exp();
        for points in [&b.first, &b.second] {
            let m = interpolate(points, &points.iter().map(|&x| f(x)).collect::<Vec<_>>());
            for &x in points.iter() {
                assert!((horner(&m, &x) - f(x)).abs() < 1e-14);
            }
            // Degree 5 on [−1, 1]: error ~ e/(2^5 6!) ≈ 1e-4.
            assert!((horner(&m, &0.77) - f(0.77)).abs() < 3e-4);
        }
        assert_eq!(b.checks_first.len(), 7);
        assert_eq!(b.checks_second.len(), 5);
    }
}
