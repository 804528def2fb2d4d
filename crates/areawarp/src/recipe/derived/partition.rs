//! Adaptive panels: where to place Chebyshev interpolants so that a
//! non-negative density on [0, 1] is resolved to the type's precision, and
//! resolved *relative to itself* wherever it matters (see [`Settings`]).

use super::power::{fill_origin, power_mass};
use crate::real::Real;
use crate::recipe::chebyshev::{ChebyshevLevel, ChebyshevLevels, LEVELS, TAIL_ULPS, local, tail};

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
    /// The exponent e of a power panel \[0, b\] (the values and coefficients
    /// are those of q = f/s^e, see [`super::power`]), or `None`.
    pub power: Option<T>,
}

/// The fewest points at which a noise plateau is recognised ([`accept`]).
const PLATEAU_MIN_N: usize = 17;

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
            n >= PLATEAU_MIN_N
                && *tail <= noise_ceiling::<T>()
                && tail.clone() * &T::from_i64(8) >= *prev
        }
        None => false,
    }
}

impl<T: Real> PanelFit<T> {
    /// ∫_a^b of the interpolant (Clenshaw–Curtis; on a power panel
    /// b^m·H(b), [`power_mass`]).
    pub fn integral(&self, levels: &ChebyshevLevels<T>) -> T {
        if let Some(e) = &self.power {
            return power_mass(&self.coeffs, &self.b, e);
        }
        let half = (self.b.clone() - &self.a) / &T::from_i64(2);
        levels.level(self.n).integral(&self.values) * &half
    }

    /// The largest value of the density on the panel (up to the
    /// interpolant's error): `scale`, times b^e on a power panel.
    pub fn density_scale(&self) -> T {
        match &self.power {
            Some(e) => self.scale.clone() * &self.b.powf(e),
            None => self.scale.clone(),
        }
    }
}

/// The interpolant through `values` at the level's nodes on `[a, b]`:
/// coefficients (at the nodes' actual positions), scale, floor and tail.
fn interpolant<T: Real>(
    level: &ChebyshevLevel<T>,
    values: &[T],
    a: &T,
    b: &T,
) -> (Vec<T>, T, T, T, bool) {
    let n = level.n;
    let half = (b.clone() - a) / &T::from_i64(2);
    let inv_width = T::one() / &(b.clone() - a);
    let finite = values.iter().all(|v| v.is_finite());
    let mut scale = T::zero();
    let mut floor = T::max_value();
    for v in values {
        scale = scale.max(&v.abs());
        floor = floor.min(&v.abs());
    }
    let mut coeffs = vec![T::zero(); n];
    if finite {
        let xi: Vec<T> = (0..n)
            .map(|k| local(&level.node(a, b, &half, k), a, b, &inv_width))
            .collect();
        if level.nodes_exact(&xi) {
            level.coefficients_into(values, &mut coeffs);
        } else {
            let mut work = vec![T::zero(); 2 * n];
            level.coefficients_at(values, &xi, &mut coeffs, &mut work);
        }
    }
    let tail_now = if finite {
        tail(&coeffs, &scale)
    } else {
        T::max_value()
    };
    (coeffs, scale, floor, tail_now, finite)
}

/// Samples `f` on `[a, b]` at 5, 9, 17, … Chebyshev points (reusing the
/// values of the coarser level) until the interpolant is resolved or the
/// type's largest level is reached; starts at `start_n` points and stops
/// after `stop_n`. An accepted interpolant is then replaced by the coarsest
/// nested one (every other value, recursively) that is no worse, so that
/// looking at many points to find no structure does not make the panel
/// expensive to evaluate.
pub(crate) fn fit_panel<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    a: &T,
    b: &T,
    levels: &ChebyshevLevels<T>,
    range: (usize, usize),
    evaluations: &mut usize,
) -> PanelFit<T> {
    fit_panel_with(f, a, b, levels, range, evaluations, None)
}

/// The power panel \[0, b\] of a density f = s^e·q: [`fit_panel`] on
/// q = f/s^e, its value at s = 0 (0/0) filled from the others
/// ([`fill_origin`]). Where f or s^e is below `normal` (the smallest
/// normal number, below which their quotient is noise) q is NaN, which
/// stops the fit unresolved.
fn fit_power_panel<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    e: &T,
    b: &T,
    normal: &T,
    levels: &ChebyshevLevels<T>,
    range: (usize, usize),
    evaluations: &mut usize,
) -> PanelFit<T> {
    let mut q = |s: &T| {
        if *s > T::zero() {
            let (fs, se) = (f(s), s.powf(e));
            if fs < *normal || se < *normal {
                return T::from_i64(0) / &T::zero();
            }
            fs / &se
        } else {
            T::zero()
        }
    };
    fit_panel_with(&mut q, &T::zero(), b, levels, range, evaluations, Some(e))
}

fn fit_panel_with<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    a: &T,
    b: &T,
    levels: &ChebyshevLevels<T>,
    (start_n, stop_n): (usize, usize),
    evaluations: &mut usize,
    power: Option<&T>,
) -> PanelFit<T> {
    let half = (b.clone() - a) / &T::from_i64(2);
    let mut values: Vec<T> = Vec::new();
    let mut fit: Option<PanelFit<T>> = None;
    let mut previous: Option<T> = None;
    for level in &levels.levels {
        if level.n < start_n.min(stop_n) {
            continue;
        }
        if level.n > stop_n && fit.is_some() {
            break;
        }
        let n = level.n;
        let new_values: Vec<T> = (0..n)
            .map(|k| {
                if !values.is_empty() && k % 2 == 0 {
                    values[k / 2].clone()
                } else {
                    *evaluations += 1;
                    f(&level.node(a, b, &half, k))
                }
            })
            .collect();
        values = new_values;
        if power.is_some() {
            fill_origin(&mut values);
            // q not computable at this level's nodes (f or s^e below the
            // normal range, in f64 for a large e): the previous level, if
            // it has the 17 points a plateau is recognised from and a tail
            // below the noise ceiling, is accepted as at a noise plateau
            // (σw's own rounding: 100u for Phong k = 100).
            if !values.iter().all(|v| v.is_finite())
                && let Some(prev) = fit.as_mut()
                && prev.n >= PLATEAU_MIN_N
                && prev.tail <= noise_ceiling::<T>()
            {
                prev.resolved = true;
                break;
            }
        }
        let (coeffs, scale, floor, tail_now, finite) = interpolant(level, &values, a, b);
        let clean = tail_now <= T::from_i64(TAIL_ULPS) * &T::unit_roundoff();
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
            power: power.cloned(),
        });
        if ok {
            // The coarsest nested level that is no worse: still clean, or
            // for a fit accepted at a noise plateau, within twice its tail
            // and not below the 17 points a plateau is recognised from (the
            // interpolant of noisy values averages the noise in its
            // integral over its points: a constant plus noise of 30u
            // integrated from 5 points puts the conditional's inverse 10u
            // off, from 17 points a few u).
            let (allowed, floor_n) = if clean {
                (T::from_i64(TAIL_ULPS) * &T::unit_roundoff(), LEVELS[0])
            } else {
                let current = fit.as_ref().map_or_else(T::zero, |f| f.tail.clone());
                (current * &T::from_i64(2), PLATEAU_MIN_N)
            };
            while let Some(current) = fit.as_ref().filter(|f| f.n > floor_n) {
                let coarse: Vec<T> = current.values.iter().step_by(2).cloned().collect();
                let level = levels.level(coarse.len());
                let (c, sc, fl, t, _) = interpolant(level, &coarse, a, b);
                if t > allowed {
                    break;
                }
                fit = Some(PanelFit {
                    a: a.clone(),
                    b: b.clone(),
                    n: coarse.len(),
                    values: coarse,
                    coeffs: c,
                    scale: sc,
                    floor: fl,
                    tail: t,
                    resolved: true,
                    power: power.cloned(),
                });
            }
        }
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
    /// Panels to start from (a power of 2): more catch narrower peaks.
    pub start_panels: i64,
    /// The factor S of the unreachable right tail: the panels at the right
    /// end whose combined mass is bounded by u·∫f/S are not refined for
    /// relative accuracy ([`Partition::tail_start`]).
    pub tail_safety: i64,
    /// The exponent e of a density f = s^e·q (q smooth and positive) at
    /// s = 0, if known: the first panel is then a power panel (q
    /// interpolated, [`super::power`]) and the left tail is refined for
    /// relative accuracy at every mass ([`adaptive_partition`]).
    pub power: Option<T>,
}

impl<T: Real> Settings<T> {
    /// The defaults for `T`: min width 2^-(p/8 + 14), ratio 8, starting
    /// from 16 panels of 17 points.
    pub fn for_type() -> Self {
        Settings {
            min_width: T::exp2i(-((T::precision() / 8) as i32 + 14)),
            ratio: T::from_i64(8),
            start_n: 17,
            start_panels: 16,
            tail_safety: 16,
            power: None,
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
    /// over the non-negligible panels left of `tail_start`: the
    /// interpolants' accuracy where an inversion can land.
    pub worst_tail: T,
    /// Where the unreachable right tail starts (1 if there is none): the
    /// panels right of it hold a combined mass below u·∫f/S (bounded by
    /// 2·Σ|c_j|·width per panel, the interpolant's sup and as much again),
    /// so that no y < 1 of the type inverts into them (1 − y ≥ u), and they
    /// are resolved to the type's precision of their own largest value but
    /// not refined for relative accuracy.
    pub tail_start: T,
}

/// A bound on the panel's mass: 2·Σ|c_j|·width (Σ|c_j| bounds the
/// interpolant on the panel; the factor 2 covers the interpolation error of
/// a resolved panel many times over).
fn mass_bound<T: Real>(fit: &PanelFit<T>) -> T {
    let mut sum = T::zero();
    for c in &fit.coeffs {
        sum += &c.abs();
    }
    if let Some(e) = &fit.power {
        sum *= &fit.b.powf(e);
    }
    sum * &(fit.b.clone() - &fit.a) * &T::from_i64(2)
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
    // Pass 1 starts from 16 panels of 17 points (by default) (a single coarse panel could
    // see only zeros around a narrow peak, as for a von Mises–Fisher lobe of
    // κ = 10⁴); their integrals also give a coarse estimate of ∫f, against
    // which panels too small to matter are not refined for resolution (an
    // underestimate, from a peak between the points, only makes fewer
    // panels negligible).
    let count = settings.start_panels;
    let mut coarse_fits = Vec::with_capacity(count as usize);
    let mut coarse = T::zero();
    // The smallest density the left tail is refined for relatively: below
    // 2^p of the smallest normal number, f's own values lose their
    // precision (f64, f32; MPFR's exponent range puts it out of reach).
    let underflow = T::precision_floor();
    // The smallest normal number (about): q = f/s^e needs both normal.
    let normal = T::normal_floor();
    let mut power = settings.power.clone();
    let mut i = 0;
    while i < count {
        let range = (settings.start_n, usize::MAX);
        if i == 0
            && let Some(e) = power.take()
        {
            // The power panel [0, b], b the first of 1, 2, 4, 8 starting
            // widths at whose nodes q is computable (f and s^e above the
            // smallest normal number; a wider panel has its smallest nodes
            // further from 0); none: the plain panels.
            let mut width = 1;
            while width <= 8 && width <= count {
                let b = T::from_ratio(width, count);
                // From 9 points, so that a noise plateau of q (σw's own
                // rounding, 100u for k = 100) is recognised at 17 without
                // the 33 points whose smallest nodes underflow in f64.
                let from_9 = (LEVELS[1], usize::MAX);
                let p = fit_power_panel(f, &e, &b, &normal, levels, from_9, &mut evaluations);
                if p.values.iter().all(|v| v.is_finite() && *v > T::zero()) {
                    coarse += &p.integral(levels).abs();
                    coarse_fits.push(p);
                    power = Some(e);
                    i = width;
                    break;
                }
                width *= 2;
            }
            if power.is_some() {
                continue;
            }
        }
        let a = T::from_ratio(i, count);
        let b = T::from_ratio(i + 1, count);
        let fit = fit_panel(f, &a, &b, levels, range, &mut evaluations);
        coarse += &fit.integral(levels).abs();
        coarse_fits.push(fit);
        i += 1;
    }
    // With a power panel, F is relatively accurate on it at any mass, so
    // the panels between it and the bulk (the left tail, before the first
    // panel that is not negligible) are refined for relative accuracy too,
    // down to the underflow level: with the factor 8 where the mass is
    // above u² of the total, and with 2^(p/8) below it (relative error
    // about 32u·2^(p/8), 2^−42 in f64, at a fraction of the panels).
    let left_tail = power.is_some();
    let deep_ratio = T::exp2i((T::precision() / 8) as i32);
    let coarse_negligible = T::unit_roundoff().square() * &coarse;
    // Pass 1: resolution.
    let mut stack: Vec<PanelFit<T>> = coarse_fits.into_iter().rev().collect();
    let mut bulk_seen = false;
    while let Some(fit) = stack.pop() {
        let width = fit.b.clone() - &fit.a;
        let fscale = fit.density_scale();
        let small = fscale.clone() * &width <= coarse_negligible;
        let in_tail = left_tail && !bulk_seen && fscale >= underflow;
        let negligible = small && !in_tail;
        if fit.resolved || negligible || width <= settings.min_width {
            bulk_seen |= !small;
            fits.push(fit);
        } else {
            let (l, r) = split(f, &fit, levels, &mut evaluations);
            stack.push(r);
            stack.push(l);
        }
    }
    let mut total = T::zero();
    for fit in &fits {
        total += &fit.integral(levels).abs();
    }
    let negligible = T::unit_roundoff().square() * &total;
    // The unreachable right tail: the longest run of panels at the right
    // end whose mass bounds sum to at most u·total/S.
    let reachable_mass = T::unit_roundoff() * &total / &T::from_i64(settings.tail_safety);
    let mut tail_start = T::one();
    let mut suffix = T::zero();
    for fit in fits.iter().rev() {
        suffix += &mass_bound(fit);
        if !(suffix <= reachable_mass) {
            break;
        }
        tail_start = fit.a.clone();
    }
    let mut worst_tail = T::zero();
    // Pass 2: relative accuracy.
    let mut out = Vec::with_capacity(fits.len());
    for fit in fits.into_iter().rev() {
        stack.push(fit);
    }
    let mut bulk_seen = false;
    while let Some(fit) = stack.pop() {
        let width = fit.b.clone() - &fit.a;
        let splittable = width > settings.min_width;
        let fscale = fit.density_scale();
        let bulk = fscale.clone() * &width > negligible;
        let in_tail = left_tail && !bulk_seen && fscale >= underflow;
        let matters = bulk || in_tail;
        let ratio = if bulk { &settings.ratio } else { &deep_ratio };
        let steep = matters && fit.b <= tail_start && fit.scale > ratio.clone() * &fit.floor;
        if splittable && ((matters && !fit.resolved) || steep) {
            let (l, r) = split(f, &fit, levels, &mut evaluations);
            stack.push(r);
            stack.push(l);
        } else {
            bulk_seen |= bulk;
            if matters {
                all_resolved &= fit.resolved;
                if fit.b <= tail_start {
                    worst_tail = worst_tail.max(&fit.tail);
                }
            }
            out.push(fit);
        }
    }
    Partition {
        fits: out,
        resolved: all_resolved,
        evaluations,
        worst_tail,
        tail_start,
    }
}

/// Splits at the midpoint and fits both halves (starting at 5 points: a
/// half of a panel seen at 17 or more points hides no new structure).
fn split<T: Real>(
    f: &mut dyn FnMut(&T) -> T,
    fit: &PanelFit<T>,
    levels: &ChebyshevLevels<T>,
    evaluations: &mut usize,
) -> (PanelFit<T>, PanelFit<T>) {
    let mid = (fit.a.clone() + &fit.b) / &T::from_i64(2);
    let range = (LEVELS[0], usize::MAX);
    let normal = T::normal_floor();
    let l = match &fit.power {
        Some(e) => fit_power_panel(f, e, &mid, &normal, levels, range, evaluations),
        None => fit_panel(f, &fit.a, &mid, levels, range, evaluations),
    };
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
        // [0, 2^-20], [2^-20, 2^-19], …, [1/32, 1/16] (17 panels), then the
        // 15 starting panels [k/16, (k+1)/16]: 32 panels.
        assert_eq!(
            p.fits.len(),
            32,
            "{:?}",
            p.fits.iter().map(|f| f.a).collect::<Vec<_>>()
        );
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
