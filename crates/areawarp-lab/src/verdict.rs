//! Verdicts on the papers' claims, by one rule for every study.
//!
//! A claim with a number (a ratio, a saving, a factor) is **reproduced**
//! only if the paper's figure lies inside our 95% confidence interval
//! (`x ± 1.96·se`, `se` a jackknife standard error over independent runs)
//! or our value lies inside a tolerance *the paper itself states*; if our
//! interval lies wholly on the claimed side of "no effect" the verdict is
//! **direction holds** (with the interval); otherwise **not reproduced**.
//! A claim without a number ("less noisy", "several orders of magnitude")
//! is reproduced when the whole interval lies on the claimed side of the
//! threshold the words imply (1 for "less noisy", 100 for "orders of
//! magnitude"), direction holds when only the point does (or a threshold
//! in words is missed significantly in size only).
//!
//! Rows that are our own questions, not claims of a paper, carry a source
//! starting with [`OUR_QUESTION`] and are kept out of the summary's
//! verdict counts.

/// The two-sided 95% quantile of the normal distribution.
pub const Z95: f64 = 1.959_963_984_540_054;

/// How the source of a row that is our question (not a paper's claim)
/// starts.
pub const OUR_QUESTION: &str = "our question";

/// How the source of a row that checks a paper's claim outside the
/// paper's setup (e.g. with occluders it removed) starts.
pub const OUR_EXTENSION: &str = "our extension";

/// The outcome of checking a claim.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The paper's figure is inside our 95% interval (or ours inside the
    /// paper's stated tolerance); for claims without a number, our whole
    /// interval is on the claimed side.
    Reproduced,
    /// The effect has the claimed direction (significantly), but the
    /// paper's figure is outside our interval.
    Qualitative,
    /// The claim holds on the paper's measure (the whole image) but is
    /// significantly reversed on a part (e.g. near the light).
    Mixed,
    /// Not seen in our measurement (reversed, or not significant).
    NotReproduced,
    /// The configuration lacks what the claim needs.
    NotMeasured,
}

impl Verdict {
    /// `reproduced`, `direction holds`, `mixed`, `not reproduced`,
    /// `not measured`.
    pub fn name(&self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Qualitative => "direction holds",
            Verdict::Mixed => "mixed (holds overall, reversed in part)",
            Verdict::NotReproduced => "not reproduced",
            Verdict::NotMeasured => "not measured",
        }
    }
}

/// A claim of a paper checked against the measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Claim {
    /// Who claims it (paper and place), or [`OUR_QUESTION`]….
    pub source: String,
    /// The claim.
    pub statement: String,
    /// What we measured, with numbers.
    pub measured: String,
    /// The outcome.
    pub verdict: Verdict,
}

impl Claim {
    /// Whether the row is our question or extension rather than a
    /// paper's claim in the paper's setup.
    pub fn is_our_question(&self) -> bool {
        self.source.starts_with(OUR_QUESTION) || self.source.starts_with(OUR_EXTENSION)
    }

    /// The verdict's text; for our own questions the answer (`yes`,
    /// `yes, smaller`, `no`, `mixed`).
    pub fn verdict_text(&self) -> &'static str {
        if !self.is_our_question() || self.source.starts_with(OUR_EXTENSION) {
            return self.verdict.name();
        }
        match self.verdict {
            Verdict::Reproduced => "yes",
            Verdict::Qualitative => "yes, smaller",
            Verdict::Mixed => "mixed",
            Verdict::NotReproduced => "no",
            Verdict::NotMeasured => "not measured",
        }
    }
}

/// The 95% interval `x ± 1.96·se` (`x` alone for an unknown `se`).
pub fn interval(x: f64, se: f64) -> (f64, f64) {
    let h = if se.is_finite() { Z95 * se } else { 0.0 };
    (x - h, x + h)
}

/// `[lo, hi]` for a 95% interval.
pub fn interval_text(x: f64, se: f64) -> String {
    let (lo, hi) = interval(x, se);
    format!("[{}, {}]", sig3(lo), sig3(hi))
}

/// Three significant digits, plain or in e-notation.
pub fn sig3(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let e = x.abs().log10().floor();
    if (-3.0..4.0).contains(&e) {
        format!("{:.*}", (2.0 - e).max(0.0) as usize, x)
    } else {
        format!("{x:.2e}")
    }
}

/// The verdict on a claimed value: reproduced if `claimed` is inside our
/// interval or `x` inside the paper's own stated tolerance; direction
/// holds if our interval lies wholly beyond `null` on the side of
/// `claimed`; not reproduced otherwise.
pub fn judge_value(
    x: f64,
    se: f64,
    claimed: f64,
    stated_tolerance: Option<(f64, f64)>,
    null: f64,
) -> Verdict {
    if !x.is_finite() {
        return Verdict::NotReproduced;
    }
    let (lo, hi) = interval(x, se);
    if (lo <= claimed && claimed <= hi) || stated_tolerance.is_some_and(|(a, b)| a <= x && x <= b) {
        return Verdict::Reproduced;
    }
    let beyond = if claimed > null { lo > null } else { hi < null };
    if beyond {
        Verdict::Qualitative
    } else {
        Verdict::NotReproduced
    }
}

/// The verdict on a claim without a number that `x` exceeds `threshold`
/// (e.g. 1 for "less noisy", 100 for "orders of magnitude"): reproduced
/// if the whole interval is above it; direction holds if the interval is
/// above `null` (the effect exists, smaller than the words say); not
/// reproduced otherwise.
pub fn judge_exceeds(x: f64, se: f64, threshold: f64, null: f64) -> Verdict {
    if !x.is_finite() {
        return Verdict::NotReproduced;
    }
    let (lo, _) = interval(x, se);
    if lo > threshold {
        Verdict::Reproduced
    } else if lo > null {
        Verdict::Qualitative
    } else {
        Verdict::NotReproduced
    }
}

/// `ln Γ(x)` for `x > 0` (Lanczos, g = 7, 9 terms; relative error
/// below 1e-13 — for p-values, not for 256-bit work).
pub fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularized upper incomplete gamma function `Q(a, x)` (series for
/// `x < a + 1`, Lentz's continued fraction otherwise).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if !(a > 0.0) || x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    let lead = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut sum, mut term, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * lead.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        lead.exp() * h
    }
}

/// The p-value of a χ² statistic with `dof` degrees of freedom:
/// `P(X ≥ chi2)`.
pub fn chi2_p_value(chi2: f64, dof: f64) -> f64 {
    gamma_q(dof / 2.0, chi2 / 2.0)
}

/// The two-sided p-value of a standard normal score `z`.
pub fn normal_two_sided_p(z: f64) -> f64 {
    // erfc(|z|/√2) = Q(1/2, z²/2).
    gamma_q(0.5, z * z / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule() {
        // 1.19 ± 0.025 against a claimed 1.10: outside the interval.
        assert_eq!(
            judge_value(1.19, 0.025, 1.10, None, 1.0),
            Verdict::Qualitative
        );
        // 1.12 ± 0.02 against 1.10: inside.
        assert_eq!(
            judge_value(1.12, 0.02, 1.10, None, 1.0),
            Verdict::Reproduced
        );
        // 1.001 ± 0.035 against 1.18: no effect.
        assert_eq!(
            judge_value(1.001, 0.035, 1.18, None, 1.0),
            Verdict::NotReproduced
        );
        // A tolerance the paper states.
        assert_eq!(
            judge_value(1.3, 0.01, 1.1, Some((1.0, 1.5)), 1.0),
            Verdict::Reproduced
        );
        // Claimed below the null: the other side.
        assert_eq!(judge_value(0.5, 0.05, 0.8, None, 1.0), Verdict::Qualitative);
        assert_eq!(judge_exceeds(167.0, 17.0, 100.0, 1.0), Verdict::Reproduced);
        assert_eq!(judge_exceeds(31.0, 3.0, 100.0, 1.0), Verdict::Qualitative);
        assert_eq!(judge_exceeds(1.05, 0.05, 1.0, 1.0), Verdict::NotReproduced);
        assert_eq!(
            judge_exceeds(f64::NAN, 0.1, 1.0, 1.0),
            Verdict::NotReproduced
        );
        assert_eq!(interval_text(2.0, 0.5), "[1.02, 2.98]");
    }

    #[test]
    fn p_values() {
        // Known quantiles: χ²(15) = 25.0 at p ≈ 0.0498; χ²(1) = 3.841 at 0.05.
        assert!((chi2_p_value(24.996, 15.0) - 0.05).abs() < 1e-4);
        assert!((chi2_p_value(3.841_459, 1.0) - 0.05).abs() < 1e-6);
        assert!((chi2_p_value(0.0, 3.0) - 1.0).abs() < 1e-15);
        assert!((normal_two_sided_p(1.959_964) - 0.05).abs() < 1e-6);
        assert!((normal_two_sided_p(0.0) - 1.0).abs() < 1e-12);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    }
}
