//! A density on [0, 1] held as Chebyshev interpolants on panels, with its
//! CDF, complementary CDF and their inversion by the safeguarded [`Newton`].

use super::partition::PanelFit;
use super::power::PowerPanel;
use crate::real::Real;
use crate::recipe::chebyshev::{ChebyshevLevels, clenshaw, integral_coefficients_into, local};
use crate::recipe::invert::{Cdf1, Inverter, Newton};

/// One panel's polynomials, borrowed: the density p and its integrals from
/// the left end (`left`, ∫_a^x p) and to the right end (`right`, ∫_x^b p),
/// as Chebyshev series in ξ = (2x − a − b)/(b − a).
#[derive(Debug)]
pub(crate) struct PanelView<'a, T> {
    pub a: &'a T,
    pub b: &'a T,
    /// 1 / (b − a).
    pub inv_width: &'a T,
    /// The density's node values at a and b (the interpolant reproduces
    /// them only to rounding; a zero of the density at a pole must stay 0).
    pub density_ends: [&'a T; 2],
    pub density: &'a [T],
    pub left: &'a [T],
    pub right: &'a [T],
}

impl<T> Clone for PanelView<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for PanelView<'_, T> {}

impl<T: Real> PanelView<'_, T> {
    /// ξ of a point s of the panel.
    pub fn xi(&self, s: &T) -> T {
        local(s, self.a, self.b, self.inv_width)
    }
    /// ξ of the point s = 1 − x. For a panel inside [1/2, 1] it is computed
    /// from x without forming 1 − x (exact differences, so x keeps its
    /// relative precision near s = 1); elsewhere through s = 1 − x, which is
    /// accurate to a unit roundoff of s.
    fn xi_of_complement(&self, x: &T) -> T {
        let one = T::one();
        if *self.a >= T::from_ratio(1, 2) {
            let from_a = (one.clone() - self.a) - x; // s − a
            let to_b = x.clone() - &(one - self.b); // b − s
            (from_a - &to_b) * self.inv_width
        } else {
            self.xi(&(one - x))
        }
    }
    /// Σ c_j T_j(ξ), with the value pinned to `exact` where ξ = ∓1 (a panel
    /// end): the series' value there is replaced by the exact one while its
    /// derivative (over dual numbers) is kept, as exact + (series(ξ) −
    /// series(∓1)), whose value part is exactly `exact` (both evaluations
    /// round identically).
    fn series(c: &[T], xi: &T, pins: [Option<&T>; 2]) -> T {
        let value = clenshaw(c, xi);
        for (end, exact) in [(-1, pins[0]), (1, pins[1])] {
            let end = T::from_i64(end);
            if let Some(exact) = exact
                && *xi == end
            {
                return exact.clone() + &(value - &clenshaw(c, &end));
            }
        }
        value
    }
    /// p at ξ.
    pub fn density_xi(&self, xi: &T) -> T {
        Self::series(
            self.density,
            xi,
            [Some(self.density_ends[0]), Some(self.density_ends[1])],
        )
    }
    /// ∫_a^s p at ξ(s).
    pub fn left_xi(&self, xi: &T) -> T {
        Self::series(self.left, xi, [Some(&T::zero()), None])
    }
    /// ∫_s^b p at ξ(s).
    pub fn right_xi(&self, xi: &T) -> T {
        Self::series(self.right, xi, [None, Some(&T::zero())])
    }
    /// p(s).
    pub fn density_at(&self, s: &T) -> T {
        self.density_xi(&self.xi(s))
    }
    /// ∫_a^s p.
    pub fn left_at(&self, s: &T) -> T {
        self.left_xi(&self.xi(s))
    }
    /// ∫_s^b p.
    pub fn right_at(&self, s: &T) -> T {
        self.right_xi(&self.xi(s))
    }
}

/// The CDF on one panel, from the left: (mass before a + ∫_a^s p) / total.
struct LeftCdf<'a, T> {
    view: PanelView<'a, T>,
    before: &'a T,
    inv_total: &'a T,
}

impl<T: Real> Cdf1<T> for LeftCdf<'_, T> {
    fn cdf(&self, s: &T) -> T {
        (self.before.clone() + &self.view.left_at(s)) * self.inv_total
    }
    fn pdf(&self, s: &T) -> T {
        self.view.density_at(s) * self.inv_total
    }
}

/// The complementary CDF in the reflected variable x = 1 − s:
/// (mass after b + ∫_s^b p) / total, increasing in x; for panels inside
/// [1/2, 1], evaluated from x itself.
struct RightCdf<'a, T> {
    view: PanelView<'a, T>,
    after: &'a T,
    inv_total: &'a T,
}

impl<T: Real> Cdf1<T> for RightCdf<'_, T> {
    fn cdf(&self, x: &T) -> T {
        let xi = self.view.xi_of_complement(x);
        (self.after.clone() + &self.view.right_xi(&xi)) * self.inv_total
    }
    fn pdf(&self, x: &T) -> T {
        let xi = self.view.xi_of_complement(x);
        self.view.density_xi(&xi) * self.inv_total
    }
}

/// The masses around the panel the inversion runs in.
pub(crate) struct Masses<'a, T> {
    /// Mass left of the panel.
    pub before: &'a T,
    /// Mass right of the panel.
    pub after: &'a T,
    /// The panel's own mass.
    pub own: &'a T,
    /// Total mass and its reciprocal.
    pub total: &'a T,
    /// 1 / total.
    pub inv_total: &'a T,
}

/// s with F(s) = y on the panel `view` (which must be the panel where the
/// CDF crosses y: the first panel for y ≤ 0, the last for y ≥ 1), by
/// safeguarded Newton inside the panel.
///
/// For y > 1/2 it solves 1 − F(s) = 1 − y (exact) in x = 1 − s, with the
/// complement accumulated from the right (and, on a panel inside [1/2, 1],
/// evaluated from x itself), so that in a thin tail of the density and near
/// a zero of it at s = 1 (a pole) s is as accurate as near s = 0.
///
/// # Derivatives
/// The returned s is the Newton root s_r with its derivative stated, not
/// inherited from the iterations: s_r + (y − y_r − (F(s_r) − F(s_r)_r)) /
/// F'(s_r)_r, where `_r` is the value with zero derivative
/// ([`Real::detached`]): over dual numbers ds = (dy − ∂F/∂(parameters))/F'(s_r)
/// exactly at the point returned, even where the iteration could only
/// approach the root to the granularity of s (near s = 1 at 256 bits).
pub(crate) fn invert_in_panel<T: Real>(view: PanelView<'_, T>, masses: &Masses<'_, T>, y: &T) -> T {
    let newton = Newton::default();
    let half = T::from_ratio(1, 2);
    let width = view.b.clone() - view.a;
    let left = LeftCdf {
        view,
        before: masses.before,
        inv_total: masses.inv_total,
    };
    let value = if y.is_nan() || !(*y > T::zero()) {
        return newton.invert(&left, y).x;
    } else if *y > half {
        let yc = T::one() - y;
        let right = RightCdf {
            view,
            after: masses.after,
            inv_total: masses.inv_total,
        };
        if !(yc > T::zero()) {
            return T::one() - &newton.invert(&right, &yc).x;
        }
        let frac =
            ((yc.clone() * masses.total - masses.after) / masses.own).clamp(&T::zero(), &T::one());
        let lo = T::one() - view.b;
        let hi = T::one() - view.a;
        let x0 = lo.clone() + &(frac * &width);
        T::one() - &newton.solve_in(&right, &yc, x0, lo, hi).x
    } else {
        let frac =
            ((y.clone() * masses.total - masses.before) / masses.own).clamp(&T::zero(), &T::one());
        let x0 = view.a.clone() + &(frac * &width);
        newton
            .solve_in(&left, y, x0, view.a.clone(), view.b.clone())
            .x
    };
    stated_root(&left, y, value)
}

/// The root `value` of `cdf(s) = y` with its derivative stated (see
/// [`invert_in_panel`], "Derivatives"): s_r + (y − y_r − (F(s_r) −
/// F(s_r)_r)) / F'(s_r)_r; `value` itself where F'(s_r) is 0 or not finite.
pub(crate) fn stated_root<T: Real, C: Cdf1<T>>(cdf: &C, y: &T, value: T) -> T {
    let s = value.detached();
    let d = cdf.pdf(&s);
    if !(d > T::zero()) || !d.is_finite() {
        return value;
    }
    let f = cdf.cdf(&s);
    let moved = (y.clone() - &y.detached()) - &(f.clone() - &f.detached());
    s + &(moved / &d.detached())
}

/// A piecewise-Chebyshev density on [0, 1] with cumulative masses from both
/// ends.
#[derive(Clone, Debug)]
pub(crate) struct PiecewiseDensity<T> {
    /// Panel ends: panel i is [ends\[i\], ends\[i + 1\]].
    ends: Vec<T>,
    /// 1 / width per panel.
    inv_width: Vec<T>,
    /// The density's node values at each panel's ends.
    density_ends: Vec<[T; 2]>,
    /// Per panel: density coefficients, left and right integral coefficients.
    density: Vec<Vec<T>>,
    left: Vec<Vec<T>>,
    right: Vec<Vec<T>>,
    /// Per panel: its mass, the mass before it, the mass after it.
    mass: Vec<T>,
    before: Vec<T>,
    after: Vec<T>,
    /// Total mass and its reciprocal.
    total: T,
    inv_total: T,
    /// Panel 0 as a power panel (its entries in `density`, `left`, `right`
    /// then unused), if the partition made one.
    power: Option<PowerPanel<T>>,
}

impl<T: Real> PiecewiseDensity<T> {
    /// From the fits of an adaptive partition (left to right, covering [0, 1]).
    pub fn from_fits(fits: &[PanelFit<T>], _levels: &ChebyshevLevels<T>) -> Self {
        let mut ends = Vec::with_capacity(fits.len() + 1);
        let mut inv_width = Vec::with_capacity(fits.len());
        let mut density_ends = Vec::with_capacity(fits.len());
        let (mut density, mut left, mut right, mut mass) = (vec![], vec![], vec![], vec![]);
        let mut power = None;
        for fit in fits {
            if let Some(e) = &fit.power {
                let p = PowerPanel::new(&fit.coeffs, &fit.b, e);
                ends.push(fit.a.clone());
                inv_width.push(T::one() / &fit.b);
                density_ends.push([T::zero(), fit.values[0].clone() * &fit.b.powf(e)]);
                density.push(Vec::new());
                left.push(Vec::new());
                right.push(Vec::new());
                mass.push(p.mass.clone().max(&T::zero()));
                power = Some(p);
                continue;
            }
            ends.push(fit.a.clone());
            inv_width.push(T::one() / &(fit.b.clone() - &fit.a));
            density_ends.push([fit.values[fit.n - 1].clone(), fit.values[0].clone()]);
            let half = (fit.b.clone() - &fit.a) / &T::from_i64(2);
            let mut l = vec![T::zero(); fit.n + 1];
            let mut r = vec![T::zero(); fit.n + 1];
            let m = integral_coefficients_into(&fit.coeffs, &half, &mut l, &mut r);
            density.push(fit.coeffs.clone());
            left.push(l);
            right.push(r);
            mass.push(m.max(&T::zero()));
        }
        ends.push(fits.last().map_or(T::one(), |f| f.b.clone()));
        let count = mass.len();
        let mut before = Vec::with_capacity(count);
        let mut acc = T::zero();
        for m in &mass {
            before.push(acc.clone());
            acc += m;
        }
        let total = acc;
        let mut after = vec![T::zero(); count];
        let mut acc = T::zero();
        for i in (0..count).rev() {
            after[i] = acc.clone();
            acc += &mass[i];
        }
        let inv_total = T::one() / &total;
        PiecewiseDensity {
            ends,
            inv_width,
            density_ends,
            density,
            left,
            right,
            mass,
            before,
            after,
            total,
            inv_total,
            power,
        }
    }

    /// The power panel, if `i` is it.
    fn power_at(&self, i: usize) -> Option<&PowerPanel<T>> {
        self.power.as_ref().filter(|_| i == 0)
    }

    /// ∫₀¹ of the density.
    pub fn total(&self) -> &T {
        &self.total
    }

    /// Number of panels.
    pub fn panels(&self) -> usize {
        self.mass.len()
    }

    /// The panel ends.
    pub fn ends(&self) -> &[T] {
        &self.ends
    }

    fn view(&self, i: usize) -> PanelView<'_, T> {
        PanelView {
            a: &self.ends[i],
            b: &self.ends[i + 1],
            inv_width: &self.inv_width[i],
            density_ends: [&self.density_ends[i][0], &self.density_ends[i][1]],
            density: &self.density[i],
            left: &self.left[i],
            right: &self.right[i],
        }
    }

    /// The panel containing x (clamped to [0, 1]).
    fn locate(&self, x: &T) -> usize {
        let count = self.mass.len();
        // Largest i with ends[i] ≤ x.
        let (mut lo, mut hi) = (0, count - 1);
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if self.ends[mid] <= *x {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        lo
    }

    /// The density, normalized: F'(x).
    pub fn pdf(&self, x: &T) -> T {
        let i = self.locate(x);
        if let Some(p) = self.power_at(i) {
            return p.density(x) * &self.inv_total;
        }
        self.view(i).density_at(x) * &self.inv_total
    }

    /// F(x), from whichever end is nearer in mass.
    pub fn cdf(&self, x: &T) -> T {
        if !(*x > T::zero()) {
            return T::zero();
        }
        if *x >= T::one() {
            return T::one();
        }
        let i = self.locate(x);
        if let Some(p) = self.power_at(i) {
            let left = p.left(x);
            let from_left = left.clone() * &self.inv_total;
            if from_left <= T::from_ratio(1, 2) {
                return from_left;
            }
            let right = self.after[0].clone() + &(p.mass.clone() - &left);
            return T::one() - &(right * &self.inv_total);
        }
        let v = self.view(i);
        let from_left = (self.before[i].clone() + &v.left_at(x)) * &self.inv_total;
        if from_left <= T::from_ratio(1, 2) {
            from_left
        } else {
            T::one() - &((self.after[i].clone() + &v.right_at(x)) * &self.inv_total)
        }
    }

    /// F⁻¹(y) (see [`invert_in_panel`]).
    pub fn inverse(&self, y: &T) -> T {
        let count = self.mass.len();
        let half = T::from_ratio(1, 2);
        let i = if y.is_nan() || !(*y > T::zero()) {
            0
        } else if *y <= half {
            // Largest i with before[i] ≤ y·total.
            let target = y.clone() * &self.total;
            let (mut lo, mut hi) = (0, count - 1);
            while lo < hi {
                let mid = (lo + hi).div_ceil(2);
                if self.before[mid] <= target {
                    lo = mid;
                } else {
                    hi = mid - 1;
                }
            }
            lo
        } else if !(*y < T::one()) {
            count - 1
        } else {
            // Smallest i with after[i] ≤ (1 − y)·total.
            let target = (T::one() - y) * &self.total;
            let (mut lo, mut hi) = (0, count - 1);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if self.after[mid] <= target {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            lo
        };
        if let Some(p) = self.power_at(i) {
            return p.invert(y, &self.inv_total, &self.total);
        }
        let masses = Masses {
            before: &self.before[i],
            after: &self.after[i],
            own: &self.mass[i],
            total: &self.total,
            inv_total: &self.inv_total,
        };
        invert_in_panel(self.view(i), &masses, y)
    }
}
