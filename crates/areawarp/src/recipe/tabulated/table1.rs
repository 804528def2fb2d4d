//! A monotone function [0, 1] → [0, 1] (the inverse marginal F⁻¹) as
//! polynomials of a fixed degree on adaptively bisected panels; the panels
//! of [0, 1/2] optionally in w = u^(1/m), where F⁻¹ ~ c·u^(1/m) at u = 0.

use super::poly::{Basis, horner, interpolate_distinct};
use crate::error::WarpError;
use crate::real::{Real, convert};
use crate::recipe::chebyshev::local;
use crate::recipe::invert::{Cdf1, Newton};

/// Panels of the table, with a uniform guide for the lookup.
#[derive(Clone, Debug)]
pub(crate) struct Table1<T> {
    degree: usize,
    /// Panel ends in u (len P + 1).
    breaks: Vec<T>,
    /// 1 / width per panel, in the panel's variable (u, or w on a power panel).
    inv_width: Vec<T>,
    /// The exact function at the breaks (len P + 1): the range of each
    /// panel, to which its polynomial is clamped.
    values: Vec<T>,
    /// Monomial coefficients in the local ξ, (d + 1) per panel.
    mono: Vec<T>,
    /// guide\[c\] = the panel containing c/G, for c = 0 … G.
    guide: Vec<usize>,
    /// The variable w = u^(1/m) of the panels of \[0, 1/2\], if F⁻¹ is
    /// fitted in it there.
    power: Option<Power<T>>,
}

/// The variable of the panels of \[0, 1/2\]: w = u^(1/m), in which
/// F⁻¹(u) = h(w) is smooth when F(s) ~ C·s^m at s = 0. They are bisected in
/// w (a bisection in u would leave the first panel's w-range \[0, b^(1/m)\]
/// nearly as wide for a large m: b = 2⁻¹⁷⁰ is w = 0.31 for m = 101).
#[derive(Clone, Debug)]
struct Power<T> {
    m: T,
    inv_m: T,
    /// The panel ends in w of the first `ends.len() − 1` panels.
    ends: Vec<T>,
}

/// A panel to fit: its ends in u and, for a panel fitted in w, in w.
type Pending<T> = (T, T, Option<(T, T)>);

/// What fitting a table reports.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FitStats {
    pub panels: usize,
    pub evaluations: usize,
    /// Largest error seen at the check points (the estimate the fit is
    /// accepted on).
    pub estimated_error: f64,
}

impl<T: Real> Table1<T> {
    /// Fits `f` (monotone, [0,1] → [0,1]) to absolute error `tol`/4 at the
    /// check points of every panel, bisecting down to width `min_width`.
    /// With `power` = m, the panels of [0, 1/2] are fitted in, and bisected
    /// in, w = u^(1/m) (see [`Power`]).
    pub fn fit(
        f: &mut dyn FnMut(&T) -> T,
        degree: usize,
        tol: &T,
        min_width: &T,
        power: Option<&T>,
    ) -> Result<(Self, FitStats), WarpError> {
        let basis = Basis::<T>::new(degree);
        let target = tol.clone() / &T::from_i64(4);
        let mut stats = FitStats::default();
        let mut breaks = vec![T::zero()];
        let mut values = vec![f(&T::zero())];
        let mut mono = Vec::new();
        let mut inv_width = Vec::new();
        let mut worst = T::zero();
        let two = T::from_i64(2);
        let half_u = T::from_ratio(1, 2);
        let inv_m = power.map(|m| T::one() / m);
        // (a, b, the ends in w of a panel of [0, 1/2] fitted in w).
        let mut stack: Vec<Pending<T>> = match &inv_m {
            Some(im) => vec![
                (half_u.clone(), T::one(), None),
                (
                    T::zero(),
                    half_u.clone(),
                    Some((T::zero(), half_u.powf(im))),
                ),
            ],
            None => vec![(T::zero(), T::one(), None)],
        };
        let mut w_ends = vec![T::zero()];
        while let Some((a, b, wr)) = stack.pop() {
            // The panel's variable x: u, or w = u^(1/m).
            let pw = wr.as_ref().and(power.zip(inv_m.as_ref()));
            let var = |u: &T| -> T {
                match pw {
                    Some((_, im)) => u.powf(im),
                    None => u.clone(),
                }
            };
            let (xa, xb) = match &wr {
                Some((wa, wb)) => (wa.clone(), wb.clone()),
                None => (a.clone(), b.clone()),
            };
            let half = (xb.clone() - &xa) / &two;
            let x_mid = (xa.clone() + &xb) / &two;
            let mid = match pw {
                Some((m, _)) => x_mid.powf(m),
                None => x_mid.clone(),
            };
            // The u of the local coordinate ξ (the ends exactly a and b).
            let at = |xi: &T| -> T {
                let x = if *xi >= T::zero() {
                    xb.clone() - &(half.clone() * &(T::one() - xi))
                } else {
                    xa.clone() + &(half.clone() * &(T::one() + xi))
                };
                match pw {
                    _ if *xi == T::one() => b.clone(),
                    _ if *xi == -T::one() => a.clone(),
                    Some((m, _)) => x.powf(m).clamp(&a, &b),
                    None => x,
                }
            };
            let nodes: Vec<T> = basis.second.iter().map(&at).collect();
            let vals: Vec<T> = nodes.iter().map(&mut *f).collect();
            stats.evaluations += vals.len();
            let iw = T::one() / &(xb.clone() - &xa);
            let xi: Vec<T> = nodes
                .iter()
                .map(|u| local(&var(u), &xa, &xb, &iw))
                .collect();
            let m = interpolate_distinct(&xi, &vals);
            let mut err = T::zero();
            for xi in &basis.checks_second {
                let u = at(xi);
                let exact = f(&u);
                stats.evaluations += 1;
                let approx = horner(&m, &local(&var(&u), &xa, &xb, &iw));
                err = err.max(&(approx - &exact).abs());
            }
            let splittable = xb.clone() - &xa > *min_width && mid > a && mid < b;
            if !(err <= target) && splittable {
                let (right, left) = match &wr {
                    Some(_) => (Some((x_mid.clone(), xb.clone())), Some((xa.clone(), x_mid))),
                    None => (None, None),
                };
                stack.push((mid.clone(), b.clone(), right));
                stack.push((a, mid, left));
                continue;
            }
            if !(err <= target) {
                return Err(WarpError::NotConverged {
                    what: "the tabulated inverse marginal at the narrowest panel",
                });
            }
            if pw.is_some() {
                w_ends.push(xb.clone());
            }
            worst = worst.max(&err);
            breaks.push(b.clone());
            values.push(vals[0].clone());
            mono.extend(m);
            inv_width.push(iw);
        }
        stats.panels = inv_width.len();
        stats.estimated_error = worst.to_f64();
        let mut table = Table1::assemble(degree, breaks, inv_width, values, mono);
        table.power = power.zip(inv_m).map(|(m, im)| Power {
            m: m.clone(),
            inv_m: im,
            ends: w_ends,
        });
        Ok((table, stats))
    }

    fn assemble(
        degree: usize,
        breaks: Vec<T>,
        inv_width: Vec<T>,
        values: Vec<T>,
        mono: Vec<T>,
    ) -> Self {
        let panels = inv_width.len();
        let g = (2 * panels).max(16);
        let mut guide = Vec::with_capacity(g + 1);
        let mut i = 0;
        for c in 0..=g {
            let u = T::from_ratio(c as i64, g as i64);
            while i + 1 < panels && breaks[i + 1] <= u {
                i += 1;
            }
            guide.push(i);
        }
        Table1 {
            degree,
            breaks,
            inv_width,
            values,
            mono,
            guide,
            power: None,
        }
    }

    /// Number of panels.
    pub fn panels(&self) -> usize {
        self.inv_width.len()
    }

    /// The panel containing `u` (clamped to [0, 1]).
    fn locate(&self, u: &T) -> usize {
        let g = self.guide.len() - 1;
        let c = (u.clone() * &T::from_i64(g as i64)).floor().to_f64();
        let c = if c.is_nan() || c < 0.0 {
            0
        } else {
            (c as usize).min(g - 1)
        };
        let (mut lo, mut hi) = (self.guide[c], self.guide[c + 1]);
        // Largest i in [lo, hi] with breaks[i] ≤ u.
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if self.breaks[mid] <= *u {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        lo
    }

    /// The tabulated function at `u`.
    pub fn eval(&self, u: &T) -> T {
        let u = u.clamp(&T::zero(), &T::one());
        let i = self.locate(&u);
        self.eval_in(i, &u)
    }

    fn eval_in(&self, i: usize, u: &T) -> T {
        self.poly_at(i, &self.var_of(i, u))
    }

    /// The power variable of panel `i`, if it has one.
    fn power_of(&self, i: usize) -> Option<&Power<T>> {
        self.power.as_ref().filter(|p| i + 1 < p.ends.len())
    }

    /// Panel `i`'s variable at `u`: u, or w = u^(1/m).
    fn var_of(&self, i: usize, u: &T) -> T {
        match self.power_of(i) {
            Some(p) => u.powf(&p.inv_m),
            None => u.clone(),
        }
    }

    /// Panel `i`'s ends in its variable.
    fn var_bounds(&self, i: usize) -> (T, T) {
        match self.power_of(i) {
            Some(p) => (p.ends[i].clone(), p.ends[i + 1].clone()),
            None => (self.breaks[i].clone(), self.breaks[i + 1].clone()),
        }
    }

    /// Panel `i`'s polynomial at `x` (in its variable), clamped to its range.
    fn poly_at(&self, i: usize, x: &T) -> T {
        let d1 = self.degree + 1;
        let (a, b) = self.var_bounds(i);
        let xi = local(x, &a, &b, &self.inv_width[i]);
        horner(&self.mono[i * d1..(i + 1) * d1], &xi).clamp(&self.values[i], &self.values[i + 1])
    }

    /// The u with eval(u) = s, by safeguarded Newton on the panel whose range
    /// contains s (in w on a power panel, then u = w^m).
    pub fn inverse(&self, s: &T) -> T {
        let panels = self.panels();
        if !(*s > self.values[0]) {
            return T::zero();
        }
        if !(*s < self.values[panels]) {
            return T::one();
        }
        // Largest i with values[i] ≤ s.
        let (mut lo, mut hi) = (0, panels - 1);
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if self.values[mid] <= *s {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        let piece = Piece { table: self, i: lo };
        let (a, b) = self.var_bounds(lo);
        let frac = ((s.clone() - &self.values[lo])
            / &(self.values[lo + 1].clone() - &self.values[lo]))
            .clamp(&T::zero(), &T::one());
        let x0 = a.clone() + &(frac * &(b.clone() - &a));
        let x = Newton::default().solve_in(&piece, s, x0, a, b).x;
        match self.power_of(lo) {
            Some(p) => x.powf(&p.m).clamp(&self.breaks[lo], &self.breaks[lo + 1]),
            None => x,
        }
    }

    /// The same table over `S` (every number converted).
    pub fn convert<S: Real>(&self) -> Table1<S> {
        let c = |v: &Vec<T>| v.iter().map(convert::<T, S>).collect::<Vec<S>>();
        Table1 {
            degree: self.degree,
            breaks: c(&self.breaks),
            inv_width: c(&self.inv_width),
            values: c(&self.values),
            mono: c(&self.mono),
            guide: self.guide.clone(),
            power: self.power.as_ref().map(|p| Power {
                m: convert(&p.m),
                inv_m: convert(&p.inv_m),
                ends: p.ends.iter().map(convert::<T, S>).collect(),
            }),
        }
    }
}

/// One panel's polynomial, in the panel's variable, as an increasing
/// function for [`Newton`].
struct Piece<'a, T> {
    table: &'a Table1<T>,
    i: usize,
}

impl<T: Real> Cdf1<T> for Piece<'_, T> {
    fn cdf(&self, x: &T) -> T {
        self.table.poly_at(self.i, x)
    }
    fn pdf(&self, x: &T) -> T {
        // d/dx of the polynomial: Horner on the derivative.
        let t = self.table;
        let d1 = t.degree + 1;
        let m = &t.mono[self.i * d1..(self.i + 1) * d1];
        let (a, b) = t.var_bounds(self.i);
        let xi = local(x, &a, &b, &t.inv_width[self.i]);
        let mut acc = T::zero();
        for (k, c) in m.iter().enumerate().skip(1).rev() {
            acc = acc * &xi + &(c.clone() * &T::from_i64(k as i64));
        }
        acc * &t.inv_width[self.i] * &T::from_i64(2)
    }
}
