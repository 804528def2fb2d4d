//! Adaptive panels: where to place Chebyshev interpolants so that a
//! non-negative density on [0, 1] is resolved to the type's precision, and
//! resolved *relative to itself* wherever it matters (see [`Settings`]).

use crate::real::Real;
use crate::recipe::chebyshev::{ChebyshevLevels, LEVELS, TAIL_ULPS, local, tail};

/// A density sampled on one panel `[a, b]` at the Chebyshev points of its
/// level, with the interpolant's coefficients.
#[derive(Clone, Debug)]
pub(crate) struct PanelFit<T> {
    /// Left end.
    pub a: T,
    /// Right end.
    pub b: T,
    /// Number of points.
    pub n: usize,
    /// Values at the points, ordered from `b` (k = 0) to `a` (k = n − 1).
    pub values: Vec<T>,
    /// Chebyshev coefficients of the interpolant.
    pub coeffs: Vec<T>,
    /// max |value|.
    pub scale: T,
    /// min |value|.
    pub floor: T,
    /// The trailing coefficients relative to `scale` ([`tail`]): the
    /// interpolant's accuracy.
    pub tail: T,
    /// Whether the interpolant is accepted: every value finite and the tail
    /// at the rounding level ([`TAIL_ULPS`] units of roundoff) or, for a
    /// function whose own evaluation is noisier than that (a weight like
    /// cos^1000 θ, whose condition number is 1000), at a noise plateau below
    /// 2^(−p/2) that doubling the points no longer lowers.
    pub resolved: bool,
}

/// The largest tail accepted as a noise plateau: 2^(−p/2).
pub(crate) fn noise_ceiling<T: Real>() -> T {
    T::exp2i(-((T::precision() / 2) as i32))
}

/// Whether an interpolant with relative tail `tail` (and `previous` at the
/// level before, if any, at `n` points) is accepted.
pub(crate) fn accept<T: Real>(tail: &T, previous: Option<&T>, n: usize) -> bool {
    if *tail <= T::from_i64(TAIL_ULPS) * &T::unit_roundoff() {
        return true;
    }
    match previous {
        Some(prev) => {
            n >= 17 && *tail <= noise_ceiling::<T>() && tail.clone() * &T::from_i64(8) >= *prev
        }
        None => false,
    }
}

impl<T: Real> PanelFit<T> {
    /// ∫_a^b of the interpolant (Clenshaw–Curtis).
    pub fn integral(&self, levels: &ChebyshevLevels<T>) -> T {
        let half = (self.b.clone() - &self.a) / &T::from_i64(2);
        levels.level(self.n).integral(&self.values) * &half
    }
}

/// Samples `f` on `[a, b]` at 5, 9, 17, … Chebyshev points (reusing the
/// values of the coarser level) until the interpolant is resolved or the
/// type's largest level is reached; starts at `start_n` points.
pub(crate) fn fit_panel<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    a: &T,
    b: &T,
    levels: &ChebyshevLevels<T>,
    (start_n, stop_n): (usize, usize),
    evaluations: &mut usize,
) -> PanelFit<T> {
    let half = (b.clone() - a) / &T::from_i64(2);
    let inv_width = T::one() / &(b.clone() - a);
    let mut values: Vec<T> = Vec::new();
    let mut fit = None;
    let mut previous: Option<T> = None;
    for level in &levels.levels {
        if level.n < start_n.min(stop_n) {
            continue;
        }
        if level.n > stop_n && fit.is_some() {
            break;
        }
        let n = level.n;
        let new_values: Vec<T> = if values.is_empty() {
            (0..n)
                .map(|k| {
                    *evaluations += 1;
                    f(&level.node(a, b, &half, k))
                })
                .collect()
        } else {
            (0..n)
                .map(|k| {
                    if k % 2 == 0 {
                        values[k / 2].clone()
                    } else {
                        *evaluations += 1;
                        f(&level.node(a, b, &half, k))
                    }
                })
                .collect()
        };
        values = new_values;
        let finite = values.iter().all(|v| v.is_finite());
        let mut scale = T::zero();
        let mut floor = T::max_value();
        for v in &values {
            scale = scale.max(&v.abs());
            floor = floor.min(&v.abs());
        }
        let mut coeffs = vec![T::zero(); n];
        if finite {
            let xi: Vec<T> = (0..n)
                .map(|k| local(&level.node(a, b, &half, k), a, b, &inv_width))
                .collect();
            if level.nodes_exact(&xi) {
                level.coefficients_into(&values, &mut coeffs);
            } else {
                let mut work = vec![T::zero(); 2 * n];
                level.coefficients_at(&values, &xi, &mut coeffs, &mut work);
            }
        }
        let tail_now = if finite { tail(&coeffs, &scale) } else { T::max_value() };
        let ok = finite && accept(&tail_now, previous.as_ref(), n);
        previous = Some(tail_now.clone());
        fit = Some(PanelFit {
            a: a.clone(),
            b: b.clone(),
            n,
            values: values.clone(),
            coeffs,
            scale,
            floor,
            tail: tail_now,
            resolved: ok,
        });
        if ok || !finite {
            break;
        }
    }
    fit.expect("at least one level")
}

/// How panels are split.
#[derive(Clone, Debug)]
pub(crate) struct Settings<T> {
    /// Panels narrower than this are not split (the type's floor 2^-(p/8+14)).
    pub min_width: T,
    /// Largest max/min ratio of the density over a non-negligible panel: a
    /// panel where the density varies more is split, so that the
    /// interpolant's error (relative to the panel's largest value) is
    /// within this factor of the density everywhere on it. This refines
    /// geometrically towards zeros of the density (poles) and along steep
    /// tails, which keeps the CDF and its complement relatively accurate.
    pub ratio: T,
    /// Node count to start at.
    pub start_n: usize,
}

impl<T: Real> Settings<T> {
    /// The defaults for `T`: min width 2^-(p/8 + 14), ratio 8, 5 points.
    pub fn for_type() -> Self {
        Settings {
            min_width: T::exp2i(-((T::precision() / 8) as i32 + 14)),
            ratio: T::from_i64(8),
            start_n: LEVELS[0],
        }
    }
}

/// An adaptive partition of [0, 1] for a density `f ≥ 0`.
pub(crate) struct Partition<T> {
    /// The panels, left to right.
    pub fits: Vec<PanelFit<T>>,
    /// Whether every panel is resolved.
    pub resolved: bool,
    /// Evaluations of `f` spent.
    pub evaluations: usize,
    /// The largest accepted tail (relative to its panel's largest value)
    /// over the non-negligible panels: the interpolants' accuracy.
    pub worst_tail: T,
}

/// Builds the partition: first by resolution alone (bisecting unresolved
/// panels down to `min_width`, except panels negligible against a coarse
/// estimate of the total), which estimates the total ∫f; then panels that
/// are not negligible (max f · width > u² · total) and whose density varies
/// by more than `ratio` are bisected further.
pub(crate) fn adaptive_partition<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    levels: &ChebyshevLevels<T>,
    settings: &Settings<T>,
) -> Partition<T> {
    let mut evaluations = 0;
    let mut fits = Vec::new();
    let mut all_resolved = true;
    // A coarse estimate of ∫f (16 panels of 17 points): an underestimate
    // (a peak between the points) only makes fewer panels negligible.
    let sixteenth = T::from_ratio(1, 16);
    let mut coarse = T::zero();
    for i in 0..16 {
        let a = T::from_ratio(i, 16);
        let b = a.clone() + &sixteenth;
        let fit = fit_panel(f, &a, &b, levels, (17, 17), &mut evaluations);
        coarse += &fit.integral(levels).abs();
    }
    let coarse_negligible = T::unit_roundoff().square() * &coarse;
    let first = fit_panel(
        f,
        &T::zero(),
        &T::one(),
        levels,
        (settings.start_n, usize::MAX),
        &mut evaluations,
    );
    // Pass 1: resolution.
    let mut stack = vec![first];
    while let Some(fit) = stack.pop() {
        let width = fit.b.clone() - &fit.a;
        let negligible = fit.scale.clone() * &width <= coarse_negligible;
        if fit.resolved || negligible || width <= settings.min_width {
            fits.push(fit);
        } else {
            let (l, r) = split(f, &fit, levels, settings, &mut evaluations);
            stack.push(r);
            stack.push(l);
        }
    }
    let mut total = T::zero();
    for fit in &fits {
        total += &fit.integral(levels).abs();
    }
    let negligible = T::unit_roundoff().square() * &total;
    let mut worst_tail = T::zero();
    // Pass 2: relative accuracy.
    let mut out = Vec::with_capacity(fits.len());
    for fit in fits.into_iter().rev() {
        stack.push(fit);
    }
    while let Some(fit) = stack.pop() {
        let width = fit.b.clone() - &fit.a;
        let splittable = width > settings.min_width;
        let matters = fit.scale.clone() * &width > negligible;
        let steep = matters && fit.scale > settings.ratio.clone() * &fit.floor;
        if splittable && ((matters && !fit.resolved) || steep) {
            let (l, r) = split(f, &fit, levels, settings, &mut evaluations);
            stack.push(r);
            stack.push(l);
        } else {
            if matters {
                all_resolved &= fit.resolved;
                worst_tail = worst_tail.max(&fit.tail);
            }
            out.push(fit);
        }
    }
    Partition {
        fits: out,
        resolved: all_resolved,
        evaluations,
        worst_tail,
    }
}

fn split<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    fit: &PanelFit<T>,
    levels: &ChebyshevLevels<T>,
    settings: &Settings<T>,
    evaluations: &mut usize,
) -> (PanelFit<T>, PanelFit<T>) {
    let mid = (fit.a.clone() + &fit.b) / &T::from_i64(2);
    let range = (settings.start_n, usize::MAX);
    let l = fit_panel(f, &fit.a, &mid, levels, range, evaluations);
    let r = fit_panel(f, &mid, &fit.b, levels, range, evaluations);
    (l, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pole_is_refined_geometrically() {
        let levels = ChebyshevLevels::<f64>::new();
        let settings = Settings::for_type();
        let mut f = |s: &f64| s * (1.0 + s);
        let p = adaptive_partition(&mut f, &levels, &settings);
        assert!(p.resolved);
        // [0, 2^-20], [2^-20, 2^-19], …, [1/2, 1]: 21 panels.
        assert_eq!(p.fits.len(), 21, "{:?}", p.fits.iter().map(|f| f.a).collect::<Vec<_>>());
        assert_eq!(p.fits[0].b, 2f64.powi(-20));
        let total: f64 = p.fits.iter().map(|f| f.integral(&levels)).sum();
        assert!((total - (0.5 + 1.0 / 3.0)).abs() < 1e-15);
    }

    #[test]
    fn narrow_peak_is_resolved() {
        let levels = ChebyshevLevels::<f64>::new();
        let settings = Settings::for_type();
        let mut f = |s: &f64| (-((s - 0.3) * 100.0).powi(2)).exp();
        let p = adaptive_partition(&mut f, &levels, &settings);
        assert!(p.resolved);
        let total: f64 = p.fits.iter().map(|f| f.integral(&levels)).sum();
        let exact = std::f64::consts::PI.sqrt() / 100.0;
        assert!((total - exact).abs() < 1e-16, "{total} {exact}");
    }

    #[test]
    fn a_jump_is_not_resolved() {
        let levels = ChebyshevLevels::<f64>::new();
        let settings = Settings::for_type();
        let mut f = |s: &f64| if *s < 1.0 / 3.0 { 1.0 } else { 2.0 };
        let p = adaptive_partition(&mut f, &levels, &settings);
        assert!(!p.resolved);
    }
}
