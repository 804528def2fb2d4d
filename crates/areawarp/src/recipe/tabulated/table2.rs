//! The inverse conditional G⁻¹(s, v) as tensor-product polynomials on
//! cells: s-panels (bisected adaptively) × v-panels (bisected adaptively,
//! per s-panel).
//!
//! In s the interpolation points are of the first kind (interior: σw may
//! vanish identically at a pole s = 0 or 1, where G_s is undefined); in v of
//! the second kind (ends included: G⁻¹(s, 0) = 0 and G⁻¹(s, 1) = 1 are
//! reproduced, and the table is continuous across v-panels).

use super::poly::{Basis, horner, interpolate_distinct};
use super::table1::FitStats;
use crate::error::WarpError;
use crate::real::{Real, convert};
use crate::recipe::chebyshev::local;
use crate::recipe::invert::{Cdf1, Newton};

/// One s-panel: its v-panels and their tensor coefficients.
#[derive(Clone, Debug)]
struct SPanel<T> {
    /// v-panel ends (len Q + 1).
    breaks: Vec<T>,
    inv_width: Vec<T>,
    /// (d + 1)² monomial coefficients per v-panel: `mono[q][i·(d+1) + j]`
    /// multiplies ξ^i η^j (ξ local in s, η local in v).
    mono: Vec<T>,
}

/// The table.
#[derive(Clone, Debug)]
pub(crate) struct Table2<T> {
    degree: usize,
    /// s-panel ends (len P + 1).
    s_breaks: Vec<T>,
    s_inv_width: Vec<T>,
    panels: Vec<SPanel<T>>,
    /// The table is G⁻¹(s, v) = v to the rounding level (a conditional
    /// uniform in t: every azimuthally symmetric lobe): evaluated as v.
    identity: bool,
}

/// The s-values of a panel's nodes and checks, and the v-values of a cell's.
fn mapped<T: Real>(points: &[T], a: &T, b: &T) -> Vec<T> {
    let half = (b.clone() - a) / &T::from_i64(2);
    points
        .iter()
        .map(|xi| {
            if *xi >= T::zero() {
                b.clone() - &(half.clone() * &(T::one() - xi))
            } else {
                a.clone() + &(half.clone() * &(T::one() + xi))
            }
        })
        .collect()
}

/// Σ_i ξ^i Σ_j m_ij η^j.
fn eval_tensor<T: Real>(m: &[T], d1: usize, xi: &T, eta: &T) -> T {
    let mut acc = T::zero();
    for i in (0..d1).rev() {
        acc = acc * xi + &horner(&m[i * d1..(i + 1) * d1], eta);
    }
    acc
}

/// How a cell fares.
enum CellFit<T> {
    Accepted(Vec<T>, T),
    SplitV,
    SplitS,
}

impl<T: Real> Table2<T> {
    /// Fits `g(s, v)` (for each s monotone in v, [0,1] → [0,1]; `g(s, vs)`
    /// returns it at every v of `vs`) to absolute error `tol`/4 at the check
    /// points of every cell.
    pub fn fit(
        g: &mut dyn FnMut(&T, &[T]) -> Vec<T>,
        degree: usize,
        tol: &T,
        min_width: &T,
    ) -> Result<(Self, FitStats), WarpError> {
        let basis = Basis::<T>::new(degree);
        let target = tol.clone() / &T::from_i64(4);
        let d1 = degree + 1;
        let two = T::from_i64(2);
        let mut stats = FitStats::default();
        let mut worst = T::zero();
        let mut s_breaks = vec![T::zero()];
        let mut s_inv_width = Vec::new();
        let mut panels = Vec::new();
        let mut s_stack = vec![(T::zero(), T::one())];
        'spanels: while let Some((a, b)) = s_stack.pop() {
            let s_nodes = mapped(&basis.first, &a, &b);
            let s_checks = mapped(&basis.checks_first, &a, &b);
            let s_iw = T::one() / &(b.clone() - &a);
            let mut panel = SPanel {
                breaks: vec![T::zero()],
                inv_width: Vec::new(),
                mono: Vec::new(),
            };
            let mut v_stack = vec![(T::zero(), T::one())];
            let mut panel_worst = T::zero();
            while let Some((c, e)) = v_stack.pop() {
                let v_nodes = mapped(&basis.second, &c, &e);
                let v_checks = mapped(&basis.checks_second, &c, &e);
                let v_iw = T::one() / &(e.clone() - &c);
                let fit = Self::fit_cell(
                    g,
                    &basis,
                    (&a, &b, &s_iw, &s_nodes, &s_checks),
                    (&c, &e, &v_iw, &v_nodes, &v_checks),
                    &target,
                    &mut stats,
                );
                let v_mid = (c.clone() + &e) / &two;
                let s_mid = (a.clone() + &b) / &two;
                let v_splittable = e.clone() - &c > *min_width && v_mid > c && v_mid < e;
                let s_splittable = b.clone() - &a > *min_width && s_mid > a && s_mid < b;
                match fit {
                    CellFit::Accepted(m, err) => {
                        panel_worst = panel_worst.max(&err);
                        panel.breaks.push(e.clone());
                        panel.inv_width.push(v_iw);
                        panel.mono.extend(m);
                    }
                    CellFit::SplitV if v_splittable => {
                        let mid = (c.clone() + &e) / &two;
                        v_stack.push((mid.clone(), e));
                        v_stack.push((c, mid));
                    }
                    CellFit::SplitS | CellFit::SplitV if s_splittable => {
                        let mid = (a.clone() + &b) / &two;
                        s_stack.push((mid.clone(), b));
                        s_stack.push((a, mid));
                        continue 'spanels;
                    }
                    _ => {
                        return Err(WarpError::NotConverged {
                            what: "the tabulated inverse conditional at the narrowest cell",
                        });
                    }
                }
            }
            worst = worst.max(&panel_worst);
            s_breaks.push(b);
            s_inv_width.push(s_iw);
            panels.push(panel);
        }
        stats.panels = panels.iter().map(|p| p.inv_width.len()).sum();
        stats.estimated_error = worst.to_f64();
        // One cell whose polynomial is (1 + η)/2 = v: the identity.
        let identity = panels.len() == 1 && panels[0].inv_width.len() == 1 && {
            let m = &panels[0].mono;
            let bound = T::from_i64(4) * &T::unit_roundoff();
            let half = T::from_ratio(1, 2);
            m.iter().enumerate().all(|(k, c)| {
                let expected = if k == 0 || k == 1 {
                    half.clone()
                } else {
                    T::zero()
                };
                (c.clone() - &expected).abs() <= bound
            })
        };
        let _ = d1;
        Ok((
            Table2 {
                degree,
                s_breaks,
                s_inv_width,
                panels,
                identity,
            },
            stats,
        ))
    }

    /// Fits one cell and judges it: the v-direction at (s-nodes × v-checks),
    /// the s-direction at (s-checks × v-nodes).
    fn fit_cell(
        g: &mut dyn FnMut(&T, &[T]) -> Vec<T>,
        basis: &Basis<T>,
        (a, b, s_iw, s_nodes, s_checks): (&T, &T, &T, &[T], &[T]),
        (c, e, v_iw, v_nodes, v_checks): (&T, &T, &T, &[T], &[T]),
        target: &T,
        stats: &mut FitStats,
    ) -> CellFit<T> {
        let d1 = basis.degree + 1;
        // Values at the node grid: rows over s, columns over v.
        let mut rows: Vec<Vec<T>> = Vec::with_capacity(d1);
        for s in s_nodes {
            rows.push(g(s, v_nodes));
        }
        stats.evaluations += d1 * d1;
        // Interpolate at the nodes' actual local coordinates: in v per row,
        // then in s per power of η.
        let xi: Vec<T> = s_nodes.iter().map(|s| local(s, a, b, s_iw)).collect();
        let eta: Vec<T> = v_nodes.iter().map(|v| local(v, c, e, v_iw)).collect();
        let in_eta: Vec<Vec<T>> = rows.iter().map(|r| interpolate_distinct(&eta, r)).collect();
        let mut mono = vec![T::zero(); d1 * d1];
        for j in 0..d1 {
            let column: Vec<T> = in_eta.iter().map(|r| r[j].clone()).collect();
            for (i, mij) in interpolate_distinct(&xi, &column).into_iter().enumerate() {
                mono[i * d1 + j] = mij;
            }
        }
        let approx =
            |s: &T, v: &T| eval_tensor(&mono, d1, &local(s, a, b, s_iw), &local(v, c, e, v_iw));
        let mut err_v = T::zero();
        for s in s_nodes {
            for (v, exact) in v_checks.iter().zip(g(s, v_checks)) {
                err_v = err_v.max(&(approx(s, v) - &exact).abs());
            }
        }
        stats.evaluations += d1 * v_checks.len();
        if !(err_v <= *target) {
            return CellFit::SplitV;
        }
        let mut err_s = T::zero();
        // Not at s = 0 or 1 themselves: there σw may vanish identically (a
        // pole, every t the same point) and G_s is undefined.
        let all_v: Vec<T> = v_nodes.iter().chain(v_checks).cloned().collect();
        for s in s_checks
            .iter()
            .filter(|s| **s > T::zero() && **s < T::one())
        {
            for (v, exact) in all_v.iter().zip(g(s, &all_v)) {
                err_s = err_s.max(&(approx(s, v) - &exact).abs());
            }
        }
        stats.evaluations += s_checks.len() * (v_nodes.len() + v_checks.len());
        if !(err_s <= *target) {
            return CellFit::SplitS;
        }
        CellFit::Accepted(mono, err_v.max(&err_s))
    }

    fn s_panel(&self, s: &T) -> usize {
        let (mut lo, mut hi) = (0, self.panels.len() - 1);
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if self.s_breaks[mid] <= *s {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        lo
    }

    fn cell_eval(&self, p: usize, q: usize, xi: &T, v: &T) -> T {
        let d1 = self.degree + 1;
        let panel = &self.panels[p];
        let eta = local(
            v,
            &panel.breaks[q],
            &panel.breaks[q + 1],
            &panel.inv_width[q],
        );
        eval_tensor(&panel.mono[q * d1 * d1..(q + 1) * d1 * d1], d1, xi, &eta)
    }

    /// G⁻¹(s, v) from the table, clamped to [0, 1].
    pub fn eval(&self, s: &T, v: &T) -> T {
        let v = v.clamp(&T::zero(), &T::one());
        if self.identity {
            return v;
        }
        let s = s.clamp(&T::zero(), &T::one());
        let p = self.s_panel(&s);
        let panel = &self.panels[p];
        let xi = local(
            &s,
            &self.s_breaks[p],
            &self.s_breaks[p + 1],
            &self.s_inv_width[p],
        );
        // Largest q with breaks[q] ≤ v.
        let (mut lo, mut hi) = (0, panel.inv_width.len() - 1);
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if panel.breaks[mid] <= v {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        self.cell_eval(p, lo, &xi, &v).clamp(&T::zero(), &T::one())
    }

    /// The v with eval(s, v) = t: the cell whose t-range at s contains t,
    /// then safeguarded Newton.
    pub fn inverse(&self, s: &T, t: &T) -> T {
        if self.identity {
            return t.clamp(&T::zero(), &T::one());
        }
        let s = s.clamp(&T::zero(), &T::one());
        let p = self.s_panel(&s);
        let panel = &self.panels[p];
        let xi = local(
            &s,
            &self.s_breaks[p],
            &self.s_breaks[p + 1],
            &self.s_inv_width[p],
        );
        let cells = panel.inv_width.len();
        // Largest q whose lower edge maps to ≤ t.
        let (mut lo, mut hi) = (0, cells - 1);
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if self.cell_eval(p, mid, &xi, &panel.breaks[mid]) <= *t {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        let piece = Cell {
            table: self,
            p,
            q: lo,
            xi,
        };
        let (c, e) = (panel.breaks[lo].clone(), panel.breaks[lo + 1].clone());
        let (tc, te) = (piece.cdf(&c), piece.cdf(&e));
        if !(*t > tc) {
            return c;
        }
        if !(*t < te) {
            return e;
        }
        let frac = ((t.clone() - &tc) / &(te - &tc)).clamp(&T::zero(), &T::one());
        let x0 = c.clone() + &(frac * &(e.clone() - &c));
        // Within u·(e − c) of c the local coordinate rounds to −1 (or
        // nearly): the cell is flat there to the rounding of its value, and
        // a root that close to c (a t within that rounding of the cell's
        // value at c, as the chart gives at v = 0) is beyond Newton's
        // relative tolerance: it bisected towards it until its iteration
        // cap and stopped ~2^-114 away at 256 bits. c is a preimage to
        // within u·(e − c).
        if !(*t > piece.cdf(&(c.clone() + &((e.clone() - &c) * &T::unit_roundoff())))) {
            return c;
        }
        Newton::default().solve_in(&piece, t, x0, c, e).x
    }

    /// The same table over `S`.
    pub fn convert<S: Real>(&self) -> Table2<S> {
        let c = |v: &Vec<T>| v.iter().map(convert::<T, S>).collect::<Vec<S>>();
        Table2 {
            degree: self.degree,
            s_breaks: c(&self.s_breaks),
            s_inv_width: c(&self.s_inv_width),
            panels: self
                .panels
                .iter()
                .map(|p| SPanel {
                    breaks: c(&p.breaks),
                    inv_width: c(&p.inv_width),
                    mono: c(&p.mono),
                })
                .collect(),
            identity: self.identity,
        }
    }
}

/// One cell at fixed s as an increasing function of v, for [`Newton`].
struct Cell<'a, T> {
    table: &'a Table2<T>,
    p: usize,
    q: usize,
    xi: T,
}

impl<T: Real> Cdf1<T> for Cell<'_, T> {
    fn cdf(&self, v: &T) -> T {
        self.table.cell_eval(self.p, self.q, &self.xi, v)
    }
    fn pdf(&self, v: &T) -> T {
        let t = self.table;
        let d1 = t.degree + 1;
        let panel = &t.panels[self.p];
        let m = &panel.mono[self.q * d1 * d1..(self.q + 1) * d1 * d1];
        let eta = local(
            v,
            &panel.breaks[self.q],
            &panel.breaks[self.q + 1],
            &panel.inv_width[self.q],
        );
        // ∂/∂η of Σ ξ^i Σ j m_ij η^(j−1).
        let mut acc = T::zero();
        for i in (0..d1).rev() {
            let row = &m[i * d1..(i + 1) * d1];
            let mut r = T::zero();
            for (j, c) in row.iter().enumerate().skip(1).rev() {
                r = r * &eta + &(c.clone() * &T::from_i64(j as i64));
            }
            acc = acc * &self.xi + &r;
        }
        acc * &panel.inv_width[self.q] * &T::from_i64(2)
    }
}
