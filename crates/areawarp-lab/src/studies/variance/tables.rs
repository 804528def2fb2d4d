//! The study's Markdown: tables of errors, rates, ratios, claims and failures.

use super::*;

/// Writes a Markdown table of relative RMS errors of `methods` (indices)
/// with point set `p` over `subset`, at the levels `levels`.
pub(crate) fn error_table(
    out: &mut String,
    ms: &Measurement,
    methods: &[usize],
    p: usize,
    subset: Subset,
    levels: &[usize],
) {
    let _ = write!(out, "| method |");
    for &l in levels {
        let _ = write!(out, " {} spp |", ms.spp[l]);
    }
    let nl = ms.spp.len();
    let first = nl.saturating_sub(ms.fit_levels.max(2));
    let _ = writeln!(
        out,
        " α (fit over {}…{} spp, ± 95%) | skipped receivers |",
        ms.spp.get(first).copied().unwrap_or(0),
        ms.spp.last().copied().unwrap_or(0)
    );
    let _ = write!(out, "|---|");
    for _ in levels {
        let _ = write!(out, "---:|");
    }
    let _ = writeln!(out, "---:|---:|");
    for &m in methods {
        let _ = write!(out, "| {} |", ms.methods[m]);
        for &l in levels {
            let (e, se) = (ms.rms(subset, m, p, l), ms.rms_std_error(subset, m, p, l));
            if se.is_finite() && e > 0.0 {
                let _ = write!(
                    out,
                    " {} ±{:.0}% |",
                    sci(e),
                    100.0 * crate::verdict::Z95 * se / e
                );
            } else {
                let _ = write!(out, " {} |", sci(e));
            }
        }
        let (a, se) = ms.fit_alpha(subset, m, p);
        let alpha = if !a.is_finite() {
            "–".to_string()
        } else if se.is_finite() {
            format!("{a:.2} ± {:.2}", crate::verdict::Z95 * se)
        } else {
            format!("{a:.2}")
        };
        let _ = writeln!(out, " {alpha} | {} |", ms.skipped_receivers(&ms.methods[m]));
    }
}

/// The levels shown in tables: even powers of two and the last.
pub(crate) fn table_levels(ms: &Measurement) -> Vec<usize> {
    let nl = ms.spp.len();
    let mut v: Vec<usize> = (0..nl)
        .filter(|&l| ms.spp[l].is_power_of_two() && ms.spp[l].trailing_zeros().is_multiple_of(2))
        .collect();
    if nl > 0 && v.last() != Some(&(nl - 1)) {
        v.push(nl - 1);
    }
    v
}

/// The method pairs compared at equal error: (a, b, what).
pub(crate) fn ratio_pairs() -> Vec<(Method, Method, &'static str)> {
    let bal = |s| Method::mis(s, Heuristic::Balance);
    vec![
        (
            Method::plain(Sampler::Rectangle),
            Method::plain(Sampler::TrianglePair),
            "triangle pair vs rectangle (paper: 1/0.85 ≈ 1.18)",
        ),
        (
            bal(Sampler::Rectangle),
            bal(Sampler::TrianglePair),
            "triangle pair vs rectangle, MIS (paper: 1/0.91 ≈ 1.10)",
        ),
        (
            bal(Sampler::Rectangle),
            bal(Sampler::Area),
            "area vs rectangle, MIS (paper: ≈ 2)",
        ),
        (
            Method::plain(Sampler::Rectangle),
            Method::plain(Sampler::Area),
            "area vs rectangle (paper: orders of magnitude)",
        ),
    ]
}

impl VarianceStudy {
    /// The Markdown of the attached section `slug` ("### title" and its
    /// body), for a report that shows it elsewhere (see
    /// [`VarianceStudy::detach`]).
    pub fn extra_markdown(&self, slug: &str) -> Option<String> {
        self.extra
            .iter()
            .find(|e| e.slug == slug)
            .map(|e| format!("### {}\n\n{}\n", e.title, e.markdown))
    }

    /// Leaves the attached section `slug` out of
    /// [`VarianceStudy::to_markdown`] (its claims stay in the claims table).
    pub fn detach(&mut self, slug: &str) {
        self.detached.push(slug.to_string());
    }

    /// The study as a Markdown section: setup, error tables per point set
    /// (all receivers and near the light), samples at equal error, the MIS
    /// heuristics, the claims, failures, and attached sections.
    pub fn to_markdown(&self) -> String {
        let ms = &self.measurement;
        let c = &self.config;
        let mut out = String::new();
        let near_count = ms.receivers.iter().filter(|r| r.near).count();
        let _ = writeln!(
            out,
            "## Variance: the standing rectangular light (Ureña, Fajardo & King 2013, Fig. 4 and 7)\n"
        );
        let _ = writeln!(
            out,
            "A double-sided {w} × {h} light of radiance {l} stands on the ground plane; {nr} receivers on the ground \
             ({rows} rows at distances {near}…{far} from the light's plane, geometrically spaced, × {lat} across), \
             {near_count} of them within {nl} of the light (\"near light\"). Irradiance at each receiver against \
             Lambert's exact formula; relative RMS error over receivers and {runs} independent runs, spp = {s0}…{s1}, \
             points {sets}. MIS methods take *n* light samples plus *n* cosine samples (2*n* rays at *n* spp). \
             All methods see the same points at a given receiver, run and spp. Columns of the error tables: *n spp* — the \
             per-receiver relative RMS error √(mean over receivers and runs of ((Ê − E)/E)²) at n samples per receiver, \
             ± the half-width of its 95% interval relative to it (jackknife over runs); *α* — the fitted exponent of \
             ε ∝ spp^−α over the last {fl} levels (the range is in the header), ± 95%; *skipped receivers* — receivers \
             where the method could not be built. Seed {seed:#x}; run time {t:.1} s.\n",
            w = c.width,
            h = c.height,
            l = c.radiance,
            nr = ms.receivers.len(),
            rows = c.rows,
            near = c.near,
            far = c.far,
            lat = c.lateral,
            nl = c.near_light,
            runs = ms.runs,
            s0 = ms.spp.first().copied().unwrap_or(0),
            s1 = ms.spp.last().copied().unwrap_or(0),
            sets = ms
                .point_sets
                .iter()
                .map(|p| p.name())
                .collect::<Vec<_>>()
                .join(" and "),
            fl = ms.fit_levels,
            seed = c.seed,
            t = self.elapsed_seconds,
        );
        let levels = table_levels(ms);
        let main: Vec<usize> = (0..ms.methods.len())
            .filter(|&m| {
                !matches!(
                    c.methods.get(m).and_then(|x| x.mis),
                    Some(Heuristic::Power(_) | Heuristic::Maximum)
                )
            })
            .collect();
        for (p, set) in ms.point_sets.iter().enumerate() {
            let _ = writeln!(
                out,
                "### Relative RMS error, {} points, all receivers\n",
                set.name()
            );
            error_table(&mut out, ms, &main, p, Subset::All, &levels);
            out.push('\n');
        }
        if near_count > 0 {
            for (p, set) in ms.point_sets.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "### Relative RMS error, {} points, the {near_count} receivers within {} of the light\n",
                    set.name(),
                    c.near_light
                );
                error_table(&mut out, ms, &main, p, Subset::NearLight, &levels);
                out.push('\n');
            }
        }

        let _ = writeln!(
            out,
            "### Samples at equal error\n\nHow many times the samples of *a* at {} spp method *b* needs for the same \
             relative RMS error (fitted power laws over the last levels; ± one jackknife standard error over runs; \
             \"not a power law\": the standard error exceeds the ratio, so no sample count is meaningful).\n",
            ms.spp.last().copied().unwrap_or(0)
        );
        let _ = write!(out, "| comparison (b vs a) |");
        for set in &ms.point_sets {
            let _ = write!(out, " {} |", set.name());
        }
        let _ = writeln!(out);
        let _ = write!(out, "|---|");
        for _ in &ms.point_sets {
            let _ = write!(out, "---:|");
        }
        let _ = writeln!(out);
        for (a, b, what) in ratio_pairs() {
            if self.method(a).is_none() || self.method(b).is_none() {
                continue;
            }
            let _ = write!(out, "| {what} |");
            for set in &ms.point_sets {
                match self.sample_ratio(a, b, *set, Subset::All) {
                    // A jackknife error above the ratio itself: b's curve
                    // is not a power law over the fitted levels (area
                    // sampling near the light), so no sample count is
                    // meaningful; the claims use error ratios instead.
                    Some(r) if r.ratio.is_finite() && r.std_error > r.ratio => {
                        let _ = write!(
                            out,
                            " not a power law ({} ± {}) |",
                            num(r.ratio),
                            num(r.std_error)
                        );
                    }
                    Some(r) if r.ratio.is_finite() => {
                        let _ = write!(out, " {} ± {} |", num(r.ratio), num(r.std_error));
                    }
                    _ => {
                        let _ = write!(out, " – |");
                    }
                }
            }
            let _ = writeln!(out);
        }
        out.push('\n');

        if !c.heuristic_samplers.is_empty() {
            let _ = writeln!(
                out,
                "### MIS heuristics (light + cosine sampling, n + n samples), relative RMS error, all receivers\n"
            );
            for (p, set) in ms.point_sets.iter().enumerate() {
                let ids: Vec<usize> = c
                    .heuristic_samplers
                    .iter()
                    .flat_map(|&s| {
                        [
                            Heuristic::Balance,
                            Heuristic::Power(2.0),
                            Heuristic::Maximum,
                        ]
                        .map(|h| Method::mis(s, h))
                    })
                    .filter_map(|m| self.method(m))
                    .collect();
                let _ = writeln!(out, "{} points:\n", set.name());
                error_table(&mut out, ms, &ids, p, Subset::All, &levels);
                out.push('\n');
            }
        }

        if let Some(o) = &self.occluded {
            let om = &o.measurement;
            let row = &o.occluders;
            let _ = writeln!(
                out,
                "### With occluders (the paper's spheres, as {} floating squares)\n\n\
                 The paper's scene has three spheres on the ground; the renders' pixels see their shadows, so \
                 the integrand is discontinuous inside the light's solid angle. Here {} opaque squares of side {} \
                 stand in the plane {} away from the light, bottom edge at height {}, centred at x = {:?}; \
                 {} of the {} receivers are partly in shadow ({} left out: no exact reference there). \
                 The exact reference subtracts the projected solid angle of each shadow's part of the light \
                 (Lambert's formula on the light clipped by the occluder's central projection).\n",
                row.centers.len(),
                row.centers.len(),
                row.side,
                row.distance,
                row.bottom,
                row.centers,
                o.shadowed,
                om.receivers.len(),
                o.dropped
            );
            let ids: Vec<usize> = (0..om.methods.len()).collect();
            let levels = table_levels(om);
            for (p, set) in om.point_sets.iter().enumerate() {
                let _ = writeln!(out, "{} points, all receivers:\n", set.name());
                error_table(&mut out, om, &ids, p, Subset::All, &levels);
                out.push('\n');
            }
            let _ = writeln!(
                out,
                "| comparison (b vs a), with occluders | {} |\n|---|{}",
                om.point_sets
                    .iter()
                    .map(|p| p.name())
                    .collect::<Vec<_>>()
                    .join(" | "),
                "---:|".repeat(om.point_sets.len())
            );
            for (a, b, what) in ratio_pairs() {
                let (Some(ia), Some(ib)) = (om.method_index(&a.name()), om.method_index(&b.name()))
                else {
                    continue;
                };
                let cells: Vec<String> = (0..om.point_sets.len())
                    .map(|p| {
                        let r = om.sample_ratio(Subset::All, ia, ib, p);
                        if r.ratio.is_finite() {
                            format!("{} ± {}", num(r.ratio), num(r.std_error))
                        } else {
                            "–".to_string()
                        }
                    })
                    .collect();
                let _ = writeln!(out, "| {what} | {} |", cells.join(" | "));
            }
            out.push('\n');
            if !om.failures.is_empty() {
                let _ = writeln!(
                    out,
                    "{} (method, receiver) pairs failed with occluders and were skipped (see `variance_occluded_failures.csv`).\n",
                    om.failures.len()
                );
            }
        }

        let _ = writeln!(
            out,
            "### The papers' claims, judged under both error measures\n"
        );
        let _ = writeln!(
            out,
            "Verdict rule ([`verdict`](crate::verdict)): *reproduced* only if the paper's figure lies inside our 95% \
             interval (± 1.96 jackknife standard errors over runs) or our value inside a tolerance the paper states; \
             *direction holds* if our whole interval shows the claimed effect but not its size; otherwise *not \
             reproduced*. Claims without a number are reproduced when the whole interval lies beyond the threshold \
             the words imply (stated in the row). Each claim is judged on the per-receiver relative RMS (every \
             receiver weighs the same) and on the image relative RMS √(Σ(Ê−E)²/ΣE²) (bright receivers weigh more, as \
             in the papers' image RMS); *measured* quotes the per-receiver numbers, and the image numbers where the \
             verdicts differ. Rows whose source starts with *our question* or *our extension* are not claims of a \
             paper in its setup.\n"
        );
        let _ = writeln!(
            out,
            "| # | source | claim | measured | verdict (per-receiver) | verdict (image) |\n|---|---|---|---|---|---|"
        );
        for (k, (a, b)) in self.claims_both_metrics().into_iter().enumerate() {
            let flip = a.verdict != b.verdict;
            let measured = if flip {
                format!("{} — *image metric:* {}", a.measured, b.measured)
            } else {
                a.measured.clone()
            };
            let _ = writeln!(
                out,
                "| C{} | {} | {} | {} | **{}** | {}{} |",
                k + 1,
                a.source,
                a.statement,
                measured,
                a.verdict_text(),
                b.verdict_text(),
                if flip { " (flips)" } else { "" }
            );
        }
        out.push('\n');
        out.push_str(&departures_table());
        out.push_str(&self.reading());

        let _ = writeln!(out, "### Failures\n");
        if ms.failures.is_empty() {
            let _ = writeln!(
                out,
                "Every method was built and gave a finite estimate at every receiver.\n"
            );
        } else {
            let _ = writeln!(
                out,
                "Skipped (method, receiver) pairs — excluded from that method's errors:\n\n\
                 | method | receiver | position | failed estimates | error |\n|---|---:|---|---:|---|"
            );
            for f in &ms.failures {
                let _ = writeln!(
                    out,
                    "| {} | {} | ({}, {}, {}) | {} / {} | {} |",
                    f.method,
                    f.receiver,
                    f.position.x,
                    f.position.y,
                    f.position.z,
                    f.failed,
                    f.attempted,
                    f.error
                );
            }
            out.push('\n');
        }

        for e in self
            .extra
            .iter()
            .filter(|e| !self.detached.contains(&e.slug))
        {
            let _ = writeln!(out, "### {}\n\n{}\n", e.title, e.markdown);
        }
        if self.extra.is_empty() {
            let _ = writeln!(
                out,
                "*The adaptive comparison of Ureña (2000) attaches here (`VarianceStudy::attach`).*\n"
            );
        }
        out
    }
}

/// The departures from the papers' setups, one row each.
pub(crate) fn departures_table() -> String {
    let rows = [
        (
            "Ureña, Fajardo & King 2013, §6",
            "error over the pixels of a 1-megapixel render seen by a camera",
            "error at 96 receivers on the ground (24 distances × 4 across) with exact references",
            "the weights of near and far regions differ; we give two metrics (per-receiver and image-style)",
        ),
        (
            "Ureña, Fajardo & King 2013, §6",
            "three diffuse spheres in the scene (occluders)",
            "unoccluded, and with a row of 3 floating squares (exact references by clipping)",
            "squares have exact references; spheres would need estimated ones",
        ),
        (
            "Ureña, Fajardo & King 2013, §6",
            "1…1024 spp, sampler unstated",
            "1…1024 spp, jittered (primary), Sobol and independent points",
            "the triangle pair's loss depends on the point set: we show all three",
        ),
        (
            "Ureña, Fajardo & King 2013, §6",
            "production renderer's cost per sample",
            "our minimal estimator, alone and with 3 and 32 occluders",
            "the cost ratio is larger where the estimator does less other work",
        ),
        (
            "Ureña 2000, §5 / Fig. 9",
            "irradiance images \"with the occluders removed\", 36 spp per pixel",
            "7 × 7 receivers, occluders removed (the paper's run) and kept (our extension), 4…1024 spp",
            "the phrase may also mean the occluders were only hidden from the top view: the occluded run covers that reading",
        ),
        (
            "Ureña 2000, §4.1",
            "successive sampling of the residuals (biased for r ≥ 2, see `areawarp::adaptive`)",
            "the systematic allocation rule (unbiased), random within each piece",
            "the bias of §4.1 as written is measured in the adaptive triangle section",
        ),
        (
            "Ureña 2000, §5",
            "a rectangular radiance pattern of unstated size",
            "a 5 × 5 checkerboard of radiances 1 and 0.1 over the triangle's bounding box",
            "",
        ),
        (
            "Arvo 2001, ch. 2 (Veach)",
            "the balance heuristic's bound for independent samples",
            "judged with independent points; jittered points shown as our question",
            "",
        ),
    ];
    let mut s = String::from(
        "#### Departures from the papers' setups\n\n| paper | paper's setup | ours | consequence |\n|---|---|---|---|\n",
    );
    for (p, a, b, c) in rows {
        let _ = writeln!(s, "| {p} | {a} | {b} | {c} |");
    }
    s.push('\n');
    s
}
