//! The conditional G_s(t) at any s: one partition of the t-axis, shared by
//! every s and fixed at construction, on which σw(s, ·) is interpolated at
//! sample time (no allocation: stack buffers of [`MAX_NODES`]).

use super::partition::{Settings, adaptive_partition, fit_panel};
use super::piecewise::{Masses, PanelView, invert_in_panel};
use crate::real::Real;
use crate::recipe::AreaDensity;
use crate::recipe::chebyshev::{
    ChebyshevLevels, MAX_NODES, TAIL_ULPS, integral_coefficients_into, local, tail,
};

/// How many panels' masses [`ConditionalGrid::inverse`] keeps from its
/// first pass (beyond that, the later panels are evaluated again).
const MASS_CACHE: usize = 64;

/// One t-panel: its ends, half-width, node count and nodes.
#[derive(Clone, Debug)]
struct TPanel<T> {
    a: T,
    b: T,
    half: T,
    inv_width: T,
    n: usize,
    /// The largest tail a probe's interpolant was accepted with here.
    tail: T,
    nodes: Vec<T>,
    /// The nodes' actual local coordinates, where they are off the
    /// Chebyshev points by more than a unit roundoff (else empty).
    xi: Vec<T>,
}

/// The t-panels of the conditional.
#[derive(Clone, Debug)]
pub(crate) struct ConditionalGrid<T> {
    panels: Vec<TPanel<T>>,
}

/// The outcome of evaluating Z(s) = ∫₀¹ σw(s, t) dt with the resolution of
/// every non-negligible t-panel checked.
pub(crate) struct CheckedNormalizer<T> {
    pub value: T,
    pub resolved: bool,
    /// Panels (index, node count, tail) that a probe at this s resolves
    /// with more nodes than the grid has: raised after the partition
    /// ([`ConditionalGrid::upgrade`]).
    pub upgrades: Vec<(usize, usize, T)>,
}

impl<T: Real> ConditionalGrid<T> {
    /// The grid for which σw(s, ·) is resolved at every probe s: the union
    /// of the adaptive partitions of each probe, each merged panel with the
    /// largest node count any probe needed there. Returns the grid, whether
    /// every probe was resolved, and the σ evaluations spent.
    pub fn build<D: AreaDensity<T>>(
        def: &D,
        probes: &[T],
        levels: &ChebyshevLevels<T>,
        settings: &Settings<T>,
    ) -> (Self, bool, usize) {
        type Piece<T> = (T, T, usize, T);
        let mut parts = Vec::with_capacity(probes.len());
        let mut evaluations = 0;
        let mut all_resolved = true;
        // One starting panel in t, seen at 17 points or more: the conditional
        // is often uniform, and a single panel keeps it exactly so.
        let settings = Settings {
            start_panels: 1,
            ..settings.clone()
        };
        for s in probes {
            let mut f = |t: &T| def.sigma(s, t);
            let p = adaptive_partition(&mut f, levels, &settings);
            evaluations += p.evaluations;
            all_resolved &= p.resolved;
            parts.push(
                p.fits
                    .into_iter()
                    .map(|f| (f.a, f.b, f.n, f.tail))
                    .collect::<Vec<Piece<T>>>(),
            );
        }
        // Union of the (dyadic, hence exactly comparable) breakpoints.
        let mut breaks: Vec<T> = vec![T::zero(), T::one()];
        for part in &parts {
            for (a, _, _, _) in part {
                breaks.push(a.clone());
            }
        }
        breaks.sort_by(|x, y| x.partial_cmp(y).expect("finite breakpoints"));
        breaks.dedup();
        let mut panels = Vec::with_capacity(breaks.len() - 1);
        for w in breaks.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let mut n = levels.levels[0].n;
            let mut worst = T::zero();
            for part in &parts {
                for (pa, pb, pn, pt) in part {
                    if *pa <= *a && *b <= *pb {
                        n = n.max(*pn);
                        if pt.is_finite() {
                            worst = worst.max(pt);
                        }
                    }
                }
            }
            panels.push(TPanel::new(a.clone(), b.clone(), n, worst, levels));
        }
        (ConditionalGrid { panels }, all_resolved, evaluations)
    }

    /// Number of t-panels.
    pub fn panels(&self) -> usize {
        self.panels.len()
    }

    /// The largest tail a t-panel was accepted with.
    pub fn worst_tail(&self) -> T {
        let mut w = T::zero();
        for p in &self.panels {
            w = w.max(&p.tail);
        }
        w
    }

    /// σ evaluations per Z(s).
    pub fn nodes_total(&self) -> usize {
        self.panels.iter().map(|p| p.n).sum()
    }

    /// The largest node count of a t-panel.
    pub fn max_nodes(&self) -> usize {
        self.panels.iter().map(|p| p.n).max().unwrap_or(0)
    }

    /// σw(s, ·) at panel j's nodes into `buf`; returns the panel's mass.
    fn values<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        j: usize,
        levels: &ChebyshevLevels<T>,
        buf: &mut [T],
    ) -> T {
        let p = &self.panels[j];
        for (slot, t) in buf.iter_mut().zip(&p.nodes) {
            *slot = def.sigma(s, t);
        }
        levels.level(p.n).integral(&buf[..p.n]) * &p.half
    }

    /// Z(s) = ∫₀¹ σw(s, t) dt, with the resolution of every non-negligible
    /// panel checked (construction only: it computes every panel's
    /// coefficients).
    pub fn normalizer_checked<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        levels: &ChebyshevLevels<T>,
    ) -> CheckedNormalizer<T> {
        let mut buf: Vec<T> = vec![T::zero(); MAX_NODES];
        let mut coeffs: Vec<T> = vec![T::zero(); MAX_NODES];
        let mut value = T::zero();
        let mut panel_scales = Vec::with_capacity(self.panels.len());
        let mut ok = true;
        for j in 0..self.panels.len() {
            let m = self.values(def, s, j, levels, &mut buf);
            value += &m;
            let p = &self.panels[j];
            let vals = &buf[..p.n];
            if !vals.iter().all(|v| v.is_finite()) {
                ok = false;
                continue;
            }
            let mut scale = T::zero();
            for v in vals {
                scale = scale.max(&v.abs());
            }
            p.coefficients(levels, vals, &mut coeffs);
            let width = p.b.clone() - &p.a;
            let allowed = (T::from_i64(TAIL_ULPS) * &T::unit_roundoff())
                .max(&(p.tail.clone() * &T::from_i64(4)));
            let t = tail(&coeffs[..p.n], &scale);
            panel_scales.push((t.clone() <= allowed, t, j, scale * &width));
        }
        let negligible = T::unit_roundoff().square() * &value.abs();
        let mut upgrades = Vec::new();
        for (res, _, j, weight) in panel_scales {
            if !res && weight > negligible {
                // What a probe at this s would have made of the panel: if
                // one panel of more nodes resolves it (a conditional that
                // is a constant plus rounding noise whose level varies with
                // s), the panel takes those nodes after the partition;
                // otherwise the t-panels are rebuilt with s as a probe.
                match self.refit(def, s, j, levels) {
                    Some((n, t)) => upgrades.push((j, n, t)),
                    None => ok = false,
                }
            }
        }
        let finite = value.is_finite();
        CheckedNormalizer {
            value,
            resolved: ok && finite,
            upgrades,
        }
    }

    /// Panel j at this s, fitted as a probe would fit it (from 17 points,
    /// up to the type's largest level, the noise-plateau rule included):
    /// its node count and tail if one panel suffices, else `None`.
    fn refit<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        j: usize,
        levels: &ChebyshevLevels<T>,
    ) -> Option<(usize, T)> {
        let p = &self.panels[j];
        let mut f = |x: &T| def.sigma(s, x);
        let mut evaluations = 0;
        let start = Settings::<T>::for_type().start_n;
        let fit = fit_panel(
            &mut f,
            &p.a,
            &p.b,
            levels,
            (start, usize::MAX),
            &mut evaluations,
        );
        fit.resolved.then_some((fit.n, fit.tail))
    }

    /// Raises panel j to `n` nodes (if it has fewer) and its accepted tail
    /// to `tail` (if larger).
    pub fn upgrade(&mut self, j: usize, n: usize, tail: &T, levels: &ChebyshevLevels<T>) {
        let p = &self.panels[j];
        if n > p.n || *tail > p.tail {
            let worst = p.tail.max(tail);
            let n = n.max(p.n);
            self.panels[j] = TPanel::new(p.a.clone(), p.b.clone(), n, worst, levels);
        }
    }

    /// Whether σw(s, ·), whose interpolant on the only t-panel has the
    /// Chebyshev coefficients `density`, is uniform in t up to rounding:
    /// every coefficient after the constant within [`TAIL_ULPS`] unit
    /// roundoffs of it (the level at which the partition accepts a fit as
    /// resolved). Then G_s(t) = t exactly, not t plus the noise that σ's
    /// rounding puts into the higher coefficients (which moved G⁻¹(½) of the
    /// derived Beckmann α = 0.1 by 6e-16 at u = 1 − 1e-11). See
    /// `docs/recipe-quadrature.md`, "A conditional uniform up to rounding".
    fn uniform_at(&self, density: &[T]) -> bool {
        if self.panels.len() != 1 || density.is_empty() {
            return false;
        }
        let bound = T::from_i64(TAIL_ULPS) * &T::unit_roundoff() * &density[0].abs();
        bound > T::zero() && density[1..].iter().all(|c| c.abs() <= bound)
    }

    /// Z(s) = ∫₀¹ σw(s, t) dt.
    pub fn normalizer<D: AreaDensity<T>>(&self, def: &D, s: &T, levels: &ChebyshevLevels<T>) -> T {
        let mut buf: [T; MAX_NODES] = core::array::from_fn(|_| T::zero());
        let mut total = T::zero();
        for j in 0..self.panels.len() {
            total += &self.values(def, s, j, levels, &mut buf);
        }
        total
    }

    /// The panel where the conditional CDF crosses `y` (the first for
    /// y ≤ 0, the last for y ≥ 1), with the masses before and after it;
    /// leaves that panel's values in `buf`. `total` is Z(s).
    ///
    /// `masses[j]`, where present, is panel j's mass as
    /// [`ConditionalGrid::total_with_values`] found it; those panels are
    /// not evaluated again.
    #[allow(clippy::too_many_arguments)]
    fn locate<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        y: &T,
        total: &T,
        levels: &ChebyshevLevels<T>,
        buf: &mut [T],
        masses: &[Option<T>],
    ) -> (usize, T, T, T) {
        let count = self.panels.len();
        let half = T::from_ratio(1, 2);
        let get = |j: usize, buf: &mut [T]| -> T {
            if let Some(Some(m)) = masses.get(j) {
                m.clone()
            } else if count == 1 {
                // The only panel's values are still in the buffer.
                levels
                    .level(self.panels[0].n)
                    .integral(&buf[..self.panels[0].n])
                    * &self.panels[0].half
            } else {
                self.values(def, s, j, levels, buf)
            }
        };
        if y.is_nan() || *y <= half {
            let target = y.clone() * total;
            let mut before = T::zero();
            for j in 0..count {
                let m = get(j, buf);
                if j + 1 == count || before.clone() + &m >= target || !(*y > T::zero()) {
                    let after = (total.clone() - &before - &m).max(&T::zero());
                    return (j, before, m, after);
                }
                before += &m;
            }
        } else {
            let target = (T::one() - y) * total;
            let mut after = T::zero();
            for j in (0..count).rev() {
                let m = get(j, buf);
                if j == 0 || after.clone() + &m >= target || !(*y < T::one()) {
                    let before = (total.clone() - &after - &m).max(&T::zero());
                    return (j, before, m, after);
                }
                after += &m;
            }
        }
        unreachable!("the loops return at their last panel")
    }

    /// Z(s), leaving the values of the last panel in `buf` and each panel's
    /// mass in `masses` (the first `masses.len()` panels), so that
    /// [`ConditionalGrid::locate`] does not evaluate σw on them again.
    fn total_with_values<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        levels: &ChebyshevLevels<T>,
        buf: &mut [T],
        masses: &mut [Option<T>],
    ) -> T {
        let mut total = T::zero();
        for j in 0..self.panels.len() {
            let m = self.values(def, s, j, levels, buf);
            total += &m;
            if let Some(slot) = masses.get_mut(j) {
                *slot = Some(m);
            }
        }
        total
    }

    /// G_s⁻¹(v). Where Z(s) is not positive (a pole of φ, where every t
    /// gives the same point) it returns v.
    pub fn inverse<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        v: &T,
        levels: &ChebyshevLevels<T>,
    ) -> T {
        let mut buf: [T; MAX_NODES] = core::array::from_fn(|_| T::zero());
        // The panels' masses from the pass that sums Z(s), kept on the stack
        // (`None` costs no allocation, even for MPFR) so that finding the
        // panel of v evaluates σw once per panel, not twice.
        let mut masses: [Option<T>; MASS_CACHE] = core::array::from_fn(|_| None);
        let total = self.total_with_values(def, s, levels, &mut buf, &mut masses);
        if !(total > T::zero()) || !total.is_finite() {
            return v.clamp(&T::zero(), &T::one());
        }
        let (j, before, own, after) = self.locate(def, s, v, &total, levels, &mut buf, &masses);
        let p = &self.panels[j];
        if self.panels.len() > 1 && masses.get(j).is_some_and(Option::is_some) {
            // locate took panel j's mass from the cache: its values, which
            // the inversion needs, are evaluated here, once.
            self.values(def, s, j, levels, &mut buf);
        }
        let mut density: [T; MAX_NODES] = core::array::from_fn(|_| T::zero());
        let mut left: [T; MAX_NODES + 1] = core::array::from_fn(|_| T::zero());
        let mut right: [T; MAX_NODES + 1] = core::array::from_fn(|_| T::zero());
        p.coefficients(levels, &buf, &mut density);
        if self.uniform_at(&density[..p.n]) && (T::zero()..=T::one()).contains(v) {
            return v.clone();
        }
        let poly_mass = integral_coefficients_into(
            &density[..p.n],
            &p.half,
            &mut left[..=p.n],
            &mut right[..=p.n],
        );
        // One panel: its polynomial's own mass as Z, so that G_s(1) = 1 and a
        // constant density gives G_s(t) = t exactly.
        let (total, own) = if self.panels.len() == 1 {
            (poly_mass.clone(), poly_mass)
        } else {
            (total, own)
        };
        let view = PanelView {
            a: &p.a,
            b: &p.b,
            inv_width: &p.inv_width,
            density_ends: [&buf[p.n - 1], &buf[0]],
            density: &density[..p.n],
            left: &left[..=p.n],
            right: &right[..=p.n],
        };
        let inv_total = T::one() / &total;
        let masses = Masses {
            before: &before,
            after: &after,
            own: &own,
            total: &total,
            inv_total: &inv_total,
        };
        invert_in_panel(view, &masses, v)
    }

    /// G_s⁻¹ at every v of `vs` (construction: one evaluation of σw(s, ·)
    /// for all of them; the same numbers as [`ConditionalGrid::inverse`]).
    pub fn inverse_many<D: AreaDensity<T>>(
        &self,
        def: &D,
        s: &T,
        vs: &[T],
        levels: &ChebyshevLevels<T>,
    ) -> Vec<T> {
        let count = self.panels.len();
        let mut buf: Vec<T> = vec![T::zero(); MAX_NODES];
        let mut values = Vec::with_capacity(count);
        let mut masses = Vec::with_capacity(count);
        let mut total = T::zero();
        for j in 0..count {
            let m = self.values(def, s, j, levels, &mut buf);
            total += &m;
            masses.push(m);
            values.push(buf[..self.panels[j].n].to_vec());
        }
        let mut polys = Vec::with_capacity(count);
        for (j, vals) in values.iter().enumerate() {
            let p = &self.panels[j];
            let mut density = vec![T::zero(); MAX_NODES];
            let mut left = vec![T::zero(); p.n + 1];
            let mut right = vec![T::zero(); p.n + 1];
            p.coefficients(levels, vals, &mut density);
            density.truncate(p.n);
            if self.uniform_at(&density) {
                return vs.iter().map(|v| v.clamp(&T::zero(), &T::one())).collect();
            }
            let poly_mass = integral_coefficients_into(&density, &p.half, &mut left, &mut right);
            polys.push((density, left, right, poly_mass));
        }
        if count == 1 {
            total = polys[0].3.clone();
            masses[0] = total.clone();
        }
        if !(total > T::zero()) || !total.is_finite() {
            return vs.iter().map(|v| v.clamp(&T::zero(), &T::one())).collect();
        }
        let inv_total = T::one() / &total;
        let half = T::from_ratio(1, 2);
        let mut before = Vec::with_capacity(count);
        let mut acc = T::zero();
        for m in &masses {
            before.push(acc.clone());
            acc += m;
        }
        let mut after = vec![T::zero(); count];
        let mut acc = T::zero();
        for j in (0..count).rev() {
            after[j] = acc.clone();
            acc += &masses[j];
        }
        vs.iter()
            .map(|v| {
                let j = if v.is_nan() || *v <= half {
                    let target = v.clone() * &total;
                    (0..count)
                        .find(|&j| {
                            j + 1 == count
                                || before[j].clone() + &masses[j] >= target
                                || !(*v > T::zero())
                        })
                        .unwrap_or(0)
                } else {
                    let target = (T::one() - v) * &total;
                    (0..count)
                        .rev()
                        .find(|&j| {
                            j == 0 || after[j].clone() + &masses[j] >= target || !(*v < T::one())
                        })
                        .unwrap_or(count - 1)
                };
                let p = &self.panels[j];
                let (density, left, right, _) = &polys[j];
                let (b, a) = if count == 1 {
                    (T::zero(), T::zero())
                } else {
                    (
                        (total.clone() - &after[j] - &masses[j]).max(&T::zero()),
                        (total.clone() - &before[j] - &masses[j]).max(&T::zero()),
                    )
                };
                // The per-sample walk accumulates `before` (left) or `after`
                // (right) itself and derives the other by difference.
                let (bj, aj) = if v.is_nan() || *v <= half {
                    (before[j].clone(), a)
                } else {
                    (b, after[j].clone())
                };
                let view = PanelView {
                    a: &p.a,
                    b: &p.b,
                    inv_width: &p.inv_width,
                    density_ends: [&values[j][p.n - 1], &values[j][0]],
                    density,
                    left,
                    right,
                };
                let masses = Masses {
                    before: &bj,
                    after: &aj,
                    own: &masses[j],
                    total: &total,
                    inv_total: &inv_total,
                };
                invert_in_panel(view, &masses, v)
            })
            .collect()
    }

    /// G_s(t) (0 where Z(s) is not positive... then t itself).
    pub fn cdf<D: AreaDensity<T>>(&self, def: &D, s: &T, t: &T, levels: &ChebyshevLevels<T>) -> T {
        let mut buf: [T; MAX_NODES] = core::array::from_fn(|_| T::zero());
        let total = self.normalizer(def, s, levels);
        let t = t.clamp(&T::zero(), &T::one());
        if !(total > T::zero()) || !total.is_finite() {
            return t;
        }
        let mut before = T::zero();
        let count = self.panels.len();
        for j in 0..count {
            let p = &self.panels[j];
            if t > p.b && j + 1 < count {
                before += &self.values(def, s, j, levels, &mut buf);
                continue;
            }
            self.values(def, s, j, levels, &mut buf);
            let mut density: [T; MAX_NODES] = core::array::from_fn(|_| T::zero());
            let mut left: [T; MAX_NODES + 1] = core::array::from_fn(|_| T::zero());
            let mut right: [T; MAX_NODES + 1] = core::array::from_fn(|_| T::zero());
            p.coefficients(levels, &buf, &mut density);
            if self.uniform_at(&density[..p.n]) {
                return t;
            }
            integral_coefficients_into(
                &density[..p.n],
                &p.half,
                &mut left[..=p.n],
                &mut right[..=p.n],
            );
            let view = PanelView {
                a: &p.a,
                b: &p.b,
                inv_width: &p.inv_width,
                density_ends: [&buf[p.n - 1], &buf[0]],
                density: &density[..p.n],
                left: &left[..=p.n],
                right: &right[..=p.n],
            };
            let from_left = (before + &view.left_at(&t)) / &total;
            if from_left <= T::from_ratio(1, 2) {
                return from_left;
            }
            // Near 1: the complement, accumulated from the right.
            let mut after = view.right_at(&t);
            for k in j + 1..count {
                after += &self.values(def, s, k, levels, &mut buf);
            }
            return T::one() - &(after / &total);
        }
        T::one()
    }
}

impl<T: Real> TPanel<T> {
    fn new(a: T, b: T, n: usize, tail: T, levels: &ChebyshevLevels<T>) -> Self {
        let half = (b.clone() - &a) / &T::from_i64(2);
        let inv_width = T::one() / &(b.clone() - &a);
        let level = levels.level(n);
        let nodes: Vec<T> = (0..n).map(|k| level.node(&a, &b, &half, k)).collect();
        let xi: Vec<T> = nodes.iter().map(|t| local(t, &a, &b, &inv_width)).collect();
        let xi = if level.nodes_exact(&xi) {
            Vec::new()
        } else {
            xi
        };
        TPanel {
            a,
            b,
            half,
            inv_width,
            n,
            tail,
            nodes,
            xi,
        }
    }

    /// The interpolant's coefficients from the values at the nodes.
    fn coefficients(&self, levels: &ChebyshevLevels<T>, values: &[T], out: &mut [T]) {
        let level = levels.level(self.n);
        if self.xi.is_empty() {
            level.coefficients_into(&values[..self.n], &mut out[..self.n]);
        } else {
            let mut work: [T; 2 * MAX_NODES] = core::array::from_fn(|_| T::zero());
            level.coefficients_at(&values[..self.n], &self.xi, &mut out[..self.n], &mut work);
        }
    }
}
