//! The measurement engine: relative RMS error against spp per method, point set
//! and receiver subset, fitted rates, samples at equal error, failures.

use super::*;

// The measurement engine
// ---------------------------------------------------------------------------

/// Which receivers an error is taken over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Subset {
    /// All receivers.
    All,
    /// The receivers within [`MeasureSpec::near_light`] of the light.
    NearLight,
}

impl Subset {
    /// `all` or `near light`.
    pub fn name(&self) -> &'static str {
        match self {
            Subset::All => "all",
            Subset::NearLight => "near light",
        }
    }

    pub(crate) fn index(&self) -> usize {
        match self {
            Subset::All => 0,
            Subset::NearLight => 1,
        }
    }
}

/// What [`measure`] runs: a setup with a reference per receiver, the
/// estimators, point sets and sample counts, the number of independent runs
/// and the seed.
pub struct MeasureSpec<'a> {
    /// The scene and receivers.
    pub setup: &'a Setup,
    /// The reference value at each receiver (exact or converged; `> 0`).
    pub references: &'a [f64],
    /// The methods.
    pub estimators: &'a [&'a dyn ReceiverEstimator],
    /// The point sets.
    pub point_sets: &'a [PointSet],
    /// Samples per receiver, increasing.
    pub spp: &'a [usize],
    /// Independent runs per receiver.
    pub runs: usize,
    /// The seed of [`run_jobs`].
    pub seed: u64,
    /// Receivers at most this far from the light (Euclidean distance to the
    /// emitter polygon) form the [`Subset::NearLight`].
    pub near_light: f64,
}

/// A receiver of a [`Measurement`].
#[derive(Clone, Debug, PartialEq)]
pub struct ReceiverInfo {
    /// Its position.
    pub position: Vec3<f64>,
    /// The reference irradiance.
    pub reference: f64,
    /// Its distance to the light polygon.
    pub light_distance: f64,
    /// In [`Subset::NearLight`].
    pub near: bool,
}

/// A method that failed at a receiver: skipped there.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The method's name.
    pub method: String,
    /// The receiver's index.
    pub receiver: usize,
    /// Its position.
    pub position: Vec3<f64>,
    /// How many estimates (runs × point sets × spp levels) failed there.
    pub failed: usize,
    /// Out of how many.
    pub attempted: usize,
    /// The first error.
    pub error: String,
}

/// Sums over estimates: count, `Σ rel`, `Σ rel²`, `Σ (Ê − E)²`, `Σ E²`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Acc {
    pub(crate) n: u64,
    pub(crate) rel: f64,
    pub(crate) rel2: f64,
    pub(crate) err2: f64,
    pub(crate) ref2: f64,
}

impl Acc {
    pub(crate) fn push(&mut self, estimate: f64, reference: f64) {
        let e = estimate - reference;
        let r = e / reference;
        self.n += 1;
        self.rel += r;
        self.rel2 += r * r;
        self.err2 += e * e;
        self.ref2 += reference * reference;
    }
    pub(crate) fn add(&mut self, o: &Acc) {
        self.n += o.n;
        self.rel += o.rel;
        self.rel2 += o.rel2;
        self.err2 += o.err2;
        self.ref2 += o.ref2;
    }
    pub(crate) fn rms(&self) -> f64 {
        if self.n == 0 {
            f64::NAN
        } else {
            (self.rel2 / self.n as f64).sqrt()
        }
    }
    pub(crate) fn value(&self, metric: Metric) -> f64 {
        match metric {
            Metric::PerReceiver => self.rms(),
            Metric::Image if self.n == 0 => f64::NAN,
            Metric::Image => (self.err2 / self.ref2).sqrt(),
        }
    }
}

/// The error measure of a curve or ratio.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Metric {
    /// Per-receiver relative RMS, `√(mean of ((Ê − E)/E)²)` over
    /// receivers and runs: every receiver weighs the same, however dark.
    #[default]
    PerReceiver,
    /// Image-style relative RMS, `√(Σ (Ê − E)² / Σ E²)`: bright receivers
    /// weigh more, as in the papers' RMS over a rendered image.
    Image,
}

impl Metric {
    /// `per-receiver` or `image`.
    pub fn name(&self) -> &'static str {
        match self {
            Metric::PerReceiver => "per-receiver relative RMS",
            Metric::Image => "image relative RMS",
        }
    }
}

/// One point of an error curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// Samples per receiver (light samples; MIS adds as many cosine samples).
    pub spp: usize,
    /// Relative RMS error over receivers and runs.
    pub rms_relative_error: f64,
    /// `√(Σ (Ê − E)²) / √(Σ E²)`.
    pub image_relative_error: f64,
    /// Mean relative error (bias indicator).
    pub mean_relative_error: f64,
    /// Number of estimates.
    pub estimates: u64,
}

/// A least-squares fit `ε(n) = c n^(−α)` in log–log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerFit {
    /// The convergence rate `α`.
    pub alpha: f64,
    /// `ln c`.
    pub log_c: f64,
}

impl PowerFit {
    /// `c n^(−α)`.
    pub fn at(&self, n: f64) -> f64 {
        (self.log_c - self.alpha * n.ln()).exp()
    }

    /// The `n` with `c n^(−α) = error`.
    pub fn samples_for(&self, error: f64) -> f64 {
        ((self.log_c - error.ln()) / self.alpha).exp()
    }

    /// The fit through `(n_i, ε_i)` (finite, positive values only); `None`
    /// for fewer than two usable points.
    pub fn fit(points: &[(f64, f64)]) -> Option<PowerFit> {
        let pts: Vec<(f64, f64)> = points
            .iter()
            .filter(|(n, e)| *n > 0.0 && *e > 0.0 && e.is_finite())
            .map(|(n, e)| (n.ln(), e.ln()))
            .collect();
        if pts.len() < 2 {
            return None;
        }
        let k = pts.len() as f64;
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / k;
        let my = pts.iter().map(|p| p.1).sum::<f64>() / k;
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        if sxx <= 0.0 {
            return None;
        }
        let slope = sxy / sxx;
        Some(PowerFit {
            alpha: -slope,
            log_c: my - slope * mx,
        })
    }
}

/// The smallest fitted rate `α` from which a curve is extrapolated to find
/// the samples at equal error; flatter curves (plain area sampling near the
/// light, whose heavy-tailed errors do not settle) give no ratio.
pub const MIN_FIT_RATE: f64 = 0.1;

/// How many samples method `b` needs, relative to method `a` at the
/// largest spp, for the same error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleRatio {
    /// `n_b / n_max` with `ε_b(n_b) = ε_a(n_max)` (fitted curves); NaN if
    /// `b`'s fitted rate is below [`MIN_FIT_RATE`].
    pub ratio: f64,
    /// Jackknife standard error over runs (NaN for one run).
    pub std_error: f64,
    /// `n_max`.
    pub at_spp: usize,
}

impl SampleRatio {
    /// `1 − 1/ratio`: the fraction of `b`'s samples that `a` saves.
    pub fn saving(&self) -> f64 {
        1.0 - 1.0 / self.ratio
    }

    /// Standard error of [`SampleRatio::saving`] (delta method).
    pub fn saving_std_error(&self) -> f64 {
        self.std_error / (self.ratio * self.ratio)
    }
}

/// The result of [`measure`]: accumulated errors per method, point set,
/// spp level, and per receiver and per run.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// Method names, in the order given.
    pub methods: Vec<String>,
    /// The point sets.
    pub point_sets: Vec<PointSet>,
    /// The spp levels.
    pub spp: Vec<usize>,
    /// Runs per receiver.
    pub runs: usize,
    /// The receivers.
    pub receivers: Vec<ReceiverInfo>,
    /// Method–receiver pairs with failed estimates.
    pub failures: Vec<Failure>,
    /// Last-levels used by fits ([`Measurement::fit`]).
    pub fit_levels: usize,
    /// The error measure of [`Measurement::rms`], the fits and the ratios
    /// (switch with [`Measurement::with_metric`]).
    pub metric: Metric,
    /// `[subset][method][set][level][run]`.
    pub(crate) per_run: Vec<Acc>,
    /// `[method][set][level][receiver]`.
    pub(crate) per_receiver: Vec<Acc>,
}

impl Measurement {
    pub(crate) fn run_index(&self, s: Subset, m: usize, p: usize, l: usize, k: usize) -> usize {
        let (nm, np, nl, nk) = (
            self.methods.len(),
            self.point_sets.len(),
            self.spp.len(),
            self.runs,
        );
        (((s.index() * nm + m) * np + p) * nl + l) * nk + k
    }

    pub(crate) fn receiver_index(&self, m: usize, p: usize, l: usize, r: usize) -> usize {
        let (np, nl, nr) = (self.point_sets.len(), self.spp.len(), self.receivers.len());
        ((m * np + p) * nl + l) * nr + r
    }

    /// The index of a method by name.
    pub fn method_index(&self, name: &str) -> Option<usize> {
        self.methods.iter().position(|m| m == name)
    }

    /// The index of a point set.
    pub fn point_set_index(&self, p: PointSet) -> Option<usize> {
        self.point_sets.iter().position(|q| *q == p)
    }

    /// The sums over all runs except `exclude`, in run order.
    pub(crate) fn acc(
        &self,
        s: Subset,
        m: usize,
        p: usize,
        l: usize,
        exclude: Option<usize>,
    ) -> Acc {
        let mut a = Acc::default();
        for k in 0..self.runs {
            if Some(k) != exclude {
                a.add(&self.per_run[self.run_index(s, m, p, l, k)]);
            }
        }
        a
    }

    /// The same measurement read with another error measure.
    pub fn with_metric(&self, metric: Metric) -> Measurement {
        Measurement {
            metric,
            ..self.clone()
        }
    }

    /// The relative RMS error (in [`Measurement::metric`]) of method `m`
    /// with point set `p` at level `l`.
    pub fn rms(&self, s: Subset, m: usize, p: usize, l: usize) -> f64 {
        self.acc(s, m, p, l, None).value(self.metric)
    }

    /// The jackknife standard error over runs of [`Measurement::rms`].
    pub fn rms_std_error(&self, s: Subset, m: usize, p: usize, l: usize) -> f64 {
        let k = self.runs;
        if k < 2 {
            return f64::NAN;
        }
        let th: Vec<f64> = (0..k)
            .map(|i| self.acc(s, m, p, l, Some(i)).value(self.metric))
            .collect();
        let mean = th.iter().sum::<f64>() / k as f64;
        let ss: f64 = th.iter().map(|t| (t - mean) * (t - mean)).sum();
        ((k - 1) as f64 / k as f64 * ss).sqrt()
    }

    /// The fitted rate α of [`Measurement::fit`] with its jackknife
    /// standard error over runs.
    pub fn fit_alpha(&self, s: Subset, m: usize, p: usize) -> (f64, f64) {
        let alpha = self.fit(s, m, p).map_or(f64::NAN, |f| f.alpha);
        let k = self.runs;
        if k < 2 {
            return (alpha, f64::NAN);
        }
        let th: Vec<f64> = (0..k)
            .map(|i| {
                self.fit_excluding(s, m, p, Some(i))
                    .map_or(f64::NAN, |f| f.alpha)
            })
            .collect();
        let mean = th.iter().sum::<f64>() / k as f64;
        let ss: f64 = th.iter().map(|t| (t - mean) * (t - mean)).sum();
        (alpha, ((k - 1) as f64 / k as f64 * ss).sqrt())
    }

    /// The whole curve of method `m` with point set `p`.
    pub fn curve(&self, s: Subset, m: usize, p: usize) -> Vec<CurvePoint> {
        (0..self.spp.len())
            .map(|l| {
                let a = self.acc(s, m, p, l, None);
                CurvePoint {
                    spp: self.spp[l],
                    rms_relative_error: a.rms(),
                    image_relative_error: (a.err2 / a.ref2).sqrt(),
                    mean_relative_error: if a.n == 0 {
                        f64::NAN
                    } else {
                        a.rel / a.n as f64
                    },
                    estimates: a.n,
                }
            })
            .collect()
    }

    /// The relative RMS error at receiver `r` over its runs.
    pub fn receiver_rms(&self, m: usize, p: usize, l: usize, r: usize) -> f64 {
        self.per_receiver[self.receiver_index(m, p, l, r)].rms()
    }

    pub(crate) fn fit_excluding(
        &self,
        s: Subset,
        m: usize,
        p: usize,
        exclude: Option<usize>,
    ) -> Option<PowerFit> {
        let nl = self.spp.len();
        let first = nl.saturating_sub(self.fit_levels.max(2));
        let pts: Vec<(f64, f64)> = (first..nl)
            .map(|l| {
                (
                    self.spp[l] as f64,
                    self.acc(s, m, p, l, exclude).value(self.metric),
                )
            })
            .collect();
        PowerFit::fit(&pts)
    }

    /// The power-law fit to the last [`Measurement::fit_levels`] levels.
    pub fn fit(&self, s: Subset, m: usize, p: usize) -> Option<PowerFit> {
        self.fit_excluding(s, m, p, None)
    }

    pub(crate) fn ratio_excluding(
        &self,
        s: Subset,
        a: usize,
        b: usize,
        p: usize,
        ex: Option<usize>,
    ) -> f64 {
        let n_max = self.spp.last().copied().unwrap_or(1) as f64;
        match (
            self.fit_excluding(s, a, p, ex),
            self.fit_excluding(s, b, p, ex),
        ) {
            (Some(fa), Some(fb)) if fb.alpha > MIN_FIT_RATE => fb.samples_for(fa.at(n_max)) / n_max,
            _ => f64::NAN,
        }
    }

    /// How many times the samples of method `a` (at the largest spp) method
    /// `b` needs for the same error, with a jackknife standard error.
    pub fn sample_ratio(&self, s: Subset, a: usize, b: usize, p: usize) -> SampleRatio {
        let ratio = self.ratio_excluding(s, a, b, p, None);
        let k = self.runs;
        let std_error = if k < 2 {
            f64::NAN
        } else {
            let th: Vec<f64> = (0..k)
                .map(|i| self.ratio_excluding(s, a, b, p, Some(i)))
                .collect();
            let mean = th.iter().sum::<f64>() / k as f64;
            let ss: f64 = th.iter().map(|t| (t - mean) * (t - mean)).sum();
            ((k - 1) as f64 / k as f64 * ss).sqrt()
        };
        SampleRatio {
            ratio,
            std_error,
            at_spp: self.spp.last().copied().unwrap_or(0),
        }
    }

    /// The jackknife standard error over runs of the ratio of the RMS
    /// errors of methods `a` and `b` at level `l`, with the ratio.
    pub fn error_ratio(&self, s: Subset, a: usize, b: usize, p: usize, l: usize) -> (f64, f64) {
        let r = |ex| {
            self.acc(s, a, p, l, ex).value(self.metric)
                / self.acc(s, b, p, l, ex).value(self.metric)
        };
        let ratio = r(None);
        let k = self.runs;
        if k < 2 {
            return (ratio, f64::NAN);
        }
        let th: Vec<f64> = (0..k).map(|i| r(Some(i))).collect();
        let mean = th.iter().sum::<f64>() / k as f64;
        let ss: f64 = th.iter().map(|t| (t - mean) * (t - mean)).sum();
        (ratio, ((k - 1) as f64 / k as f64 * ss).sqrt())
    }

    /// A robust reading of a heavy-tailed curve: the median over runs of
    /// each run's error (every run covers all receivers of the subset: a
    /// median of means), with a distribution-free interval for that median
    /// from order statistics. Returns `(median, lo, hi, coverage)`:
    /// `[lo, hi] = [x₍ⱼ₎, x₍ₖ₊₁₋ⱼ₎]` with the largest `j` whose exact
    /// binomial coverage is ≥ 95% (`j = 1`, the whole range, with its lower
    /// coverage when there are too few runs). In the metric of
    /// [`Measurement::metric`].
    ///
    /// The median estimates the *typical* run's error, not the root mean
    /// square: for a right-skewed error it is lower, and the two differ
    /// exactly when rare large errors dominate the mean.
    pub fn rms_median_of_runs(
        &self,
        s: Subset,
        m: usize,
        p: usize,
        l: usize,
    ) -> (f64, f64, f64, f64) {
        let mut x: Vec<f64> = (0..self.runs)
            .map(|k| self.per_run[self.run_index(s, m, p, l, k)].value(self.metric))
            .filter(|v| v.is_finite())
            .collect();
        if x.is_empty() {
            return (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
        }
        x.sort_by(f64::total_cmp);
        median_and_interval(&x)
    }

    /// The number of receivers at which method `m` failed at least once.
    pub fn skipped_receivers(&self, method: &str) -> usize {
        self.failures.iter().filter(|f| f.method == method).count()
    }

    /// The mean relative squared error of method `m` (the mean of
    /// `((Ê − E)/E)²`) at level `l`.
    pub fn mean_squared_relative_error(&self, s: Subset, m: usize, p: usize, l: usize) -> f64 {
        let a = self.acc(s, m, p, l, None);
        a.rel2 / a.n as f64
    }
}

/// The median of the sorted, non-empty `x` and its distribution-free
/// interval by order statistics ([`order_statistic_interval`]):
/// `(median, low, high, coverage)`.
pub fn median_and_interval(x: &[f64]) -> (f64, f64, f64, f64) {
    let k = x.len();
    let median = if k % 2 == 1 {
        x[k / 2]
    } else {
        (x[k / 2 - 1] + x[k / 2]) / 2.0
    };
    let (j, coverage) = order_statistic_interval(k);
    (median, x[j - 1], x[k - j], coverage)
}

/// For `k` samples: the largest `j ≥ 1` with `P(x₍ⱼ₎ ≤ median ≤
/// x₍ₖ₊₁₋ⱼ₎) = 1 − 2 P(Bin(k, ½) ≤ j − 1) ≥ 0.95`, and that coverage (for
/// `j = 1` possibly below 0.95).
pub fn order_statistic_interval(k: usize) -> (usize, f64) {
    // P(Bin(k, 1/2) <= i), cumulated.
    let mut cdf = Vec::with_capacity(k + 1);
    let (mut term, mut acc) = (0.5f64.powi(k as i32), 0.0);
    for i in 0..=k {
        acc += term;
        cdf.push(acc);
        term *= (k - i) as f64 / (i + 1) as f64;
    }
    let coverage = |j: usize| 1.0 - 2.0 * cdf[j - 1];
    let mut j = 1;
    while 2 * (j + 1) <= k + 1 && coverage(j + 1) >= 0.95 {
        j += 1;
    }
    (j, coverage(j).max(0.0))
}

/// The Euclidean distance from `x` to the (closed) polygon.
pub(crate) fn distance_to_polygon(polygon: &PlanarPolygon, x: &Vec3<f64>) -> f64 {
    let seg = |a: &Vec3<f64>, b: &Vec3<f64>| {
        let ab = b.sub(a);
        let l2 = ab.norm_squared();
        let t = if l2 > 0.0 {
            (x.sub(a).dot(&ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        x.sub(&a.add(&ab.scale(&t))).norm()
    };
    let v = polygon.vertices();
    let mut best = f64::INFINITY;
    for i in 0..v.len() {
        best = best.min(seg(&v[i], &v[(i + 1) % v.len()]));
    }
    // Inside the polygon's outline (projected): the plane distance.
    let d = polygon.signed_distance(x);
    let foot = x.sub(&polygon.normal().scale(&d));
    let n = polygon.normal();
    let inside = polygon.triangles().any(|[a, b, c]| {
        let s0 = b.sub(a).cross(&foot.sub(a)).dot(n);
        let s1 = c.sub(b).cross(&foot.sub(b)).dot(n);
        let s2 = a.sub(c).cross(&foot.sub(c)).dot(n);
        (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0)
    });
    if inside { best.min(d.abs()) } else { best }
}

/// The estimates of one job (receiver × run): `[method][set][level]`, NaN
/// where an estimate failed, and the first error per method.
pub(crate) struct JobOut {
    pub(crate) values: Vec<f64>,
    pub(crate) errors: Vec<Option<String>>,
}

/// Runs every estimator at every receiver, `spec.runs` times, for every
/// point set and spp, and accumulates the relative errors against the
/// references. One [`run_jobs`] job per (receiver, run); deterministic for
/// any thread count.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for no receivers, a reference count
/// that differs from the receivers', a reference that is not finite and
/// `> 0`, no estimators, point sets or spp levels, a zero spp, or zero runs.
pub fn measure(spec: &MeasureSpec<'_>, fit_levels: usize) -> Result<Measurement, WarpError> {
    let receivers = &spec.setup.receivers;
    let bad = |name: &'static str, expected: &'static str| {
        Err(WarpError::InvalidParameter { name, expected })
    };
    if receivers.is_empty() || receivers.len() != spec.references.len() {
        return bad("references", "one reference per receiver, at least one");
    }
    if spec.references.iter().any(|e| !(e.is_finite() && *e > 0.0)) {
        return bad("references", "finite references > 0");
    }
    if spec.estimators.is_empty() || spec.point_sets.is_empty() || spec.spp.is_empty() {
        return bad("methods", "at least one estimator, point set and spp level");
    }
    if spec.spp.contains(&0) || spec.runs == 0 {
        return bad("spp", "spp levels >= 1 and at least one run");
    }
    let polygon = spec.setup.scene.emitter().polygon();
    let infos: Vec<ReceiverInfo> = receivers
        .iter()
        .zip(spec.references)
        .map(|(r, &e)| {
            let d = distance_to_polygon(polygon, r.position());
            ReceiverInfo {
                position: *r.position(),
                reference: e,
                light_distance: d,
                near: d <= spec.near_light,
            }
        })
        .collect();
    let (nm, np, nl, nr, nk) = (
        spec.estimators.len(),
        spec.point_sets.len(),
        spec.spp.len(),
        receivers.len(),
        spec.runs,
    );
    let max_n = spec.spp.iter().copied().max().unwrap_or(1);
    let scene = &spec.setup.scene;

    let job = |i: usize, rng: &mut Xoshiro256PlusPlus| -> JobOut {
        let receiver = &receivers[i / nk];
        let mut values = vec![f64::NAN; nm * np * nl];
        let mut errors: Vec<Option<String>> = vec![None; nm];
        let mut prepared: Vec<Option<Box<dyn PreparedEstimator + '_>>> = spec
            .estimators
            .iter()
            .zip(errors.iter_mut())
            .map(|(e, err)| match e.prepare(scene, receiver) {
                Ok(p) => Some(p),
                Err(x) => {
                    *err = Some(x.to_string());
                    None
                }
            })
            .collect();
        let mut light = Vec::with_capacity(max_n);
        let mut partner = Vec::with_capacity(max_n);
        for (p, set) in spec.point_sets.iter().enumerate() {
            for (l, &n) in spec.spp.iter().enumerate() {
                set.fill(n, rng, &mut light);
                set.fill(n, rng, &mut partner);
                let level_seed = rng.next_u64();
                for (m, est) in prepared.iter_mut().enumerate() {
                    let Some(est) = est else { continue };
                    let batch = Batch {
                        light: &light,
                        partner: &partner,
                        point_set: *set,
                        seed: job_seed(level_seed, m as u64),
                    };
                    match est.estimate(&batch) {
                        Ok(v) if v.is_finite() => values[(m * np + p) * nl + l] = v,
                        Ok(_) => {
                            errors[m].get_or_insert_with(|| "non-finite estimate".to_string());
                        }
                        Err(x) => {
                            errors[m].get_or_insert_with(|| x.to_string());
                        }
                    }
                }
            }
        }
        JobOut { values, errors }
    };
    let outs = run_jobs(nr * nk, spec.seed, job);

    let mut m = Measurement {
        methods: spec.estimators.iter().map(|e| e.name()).collect(),
        point_sets: spec.point_sets.to_vec(),
        spp: spec.spp.to_vec(),
        runs: nk,
        receivers: infos,
        failures: Vec::new(),
        fit_levels,
        metric: Metric::PerReceiver,
        per_run: vec![Acc::default(); 2 * nm * np * nl * nk],
        per_receiver: vec![Acc::default(); nm * np * nl * nr],
    };
    // failed[method][receiver] = (count, first error)
    let mut failed: Vec<(usize, Option<String>)> = vec![(0, None); nm * nr];
    for (i, out) in outs.iter().enumerate() {
        let (r, k) = (i / nk, i % nk);
        let reference = spec.references[r];
        let near = m.receivers[r].near;
        for mi in 0..nm {
            for p in 0..np {
                for l in 0..nl {
                    let v = out.values[(mi * np + p) * nl + l];
                    if !v.is_finite() {
                        failed[mi * nr + r].0 += 1;
                        continue;
                    }
                    let ri = m.receiver_index(mi, p, l, r);
                    m.per_receiver[ri].push(v, reference);
                    let ai = m.run_index(Subset::All, mi, p, l, k);
                    m.per_run[ai].push(v, reference);
                    if near {
                        let ni = m.run_index(Subset::NearLight, mi, p, l, k);
                        m.per_run[ni].push(v, reference);
                    }
                }
            }
            if let Some(e) = &out.errors[mi] {
                failed[mi * nr + r].1.get_or_insert_with(|| e.clone());
            }
        }
    }
    for mi in 0..nm {
        for r in 0..nr {
            let (count, err) = &failed[mi * nr + r];
            if *count > 0 {
                m.failures.push(Failure {
                    method: m.methods[mi].clone(),
                    receiver: r,
                    position: m.receivers[r].position,
                    failed: *count,
                    attempted: nk * np * nl,
                    error: err.clone().unwrap_or_else(|| "unknown".to_string()),
                });
            }
        }
    }
    Ok(m)
}
