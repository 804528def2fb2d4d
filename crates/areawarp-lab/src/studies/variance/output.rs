//! The study's CSV files and figures.

use super::*;

impl VarianceStudy {
    /// Writes the CSV files into `dir` (created if needed):
    /// `variance_curves.csv` (every curve point, both subsets),
    /// `variance_receivers.csv` (per receiver and method, the error at the
    /// largest spp), `variance_ratios.csv`, `variance_claims.csv`,
    /// `variance_failures.csv`, with occluders `variance_occluded_curves.csv`
    /// and `variance_occluded_failures.csv`, and `variance_<slug>_curves.csv` per
    /// attached section with a measurement. Returns the paths.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut paths = Vec::new();
        let mut write = |name: &str, text: String| -> io::Result<()> {
            let path = dir.join(name);
            std::fs::write(&path, text)?;
            paths.push(path);
            Ok(())
        };
        write("variance_curves.csv", curves_csv(&self.measurement))?;

        let ms = &self.measurement;
        let mut t = String::from(
            "receiver,x,y,z,light_distance,near_light,reference,method,point_set,spp,rms_relative_error\n",
        );
        if let Some(l) = ms.spp.len().checked_sub(1) {
            for (r, info) in ms.receivers.iter().enumerate() {
                for (m, name) in ms.methods.iter().enumerate() {
                    for (p, set) in ms.point_sets.iter().enumerate() {
                        let _ = writeln!(
                            t,
                            "{r},{},{},{},{:e},{},{:e},{},{},{},{:e}",
                            info.position.x,
                            info.position.y,
                            info.position.z,
                            info.light_distance,
                            info.near,
                            info.reference,
                            csv_field(name),
                            set.name(),
                            ms.spp[l],
                            ms.receiver_rms(m, p, l, r)
                        );
                    }
                }
            }
        }
        write("variance_receivers.csv", t)?;

        let mut t = String::from("comparison,a,b,point_set,subset,spp,ratio,std_error\n");
        for (a, b, what) in ratio_pairs() {
            for set in &ms.point_sets {
                for subset in [Subset::All, Subset::NearLight] {
                    if let Some(r) = self.sample_ratio(a, b, *set, subset) {
                        let _ = writeln!(
                            t,
                            "{},{},{},{},{},{},{:e},{:e}",
                            csv_field(what),
                            csv_field(&a.name()),
                            csv_field(&b.name()),
                            set.name(),
                            subset.name(),
                            r.at_spp,
                            r.ratio,
                            r.std_error
                        );
                    }
                }
            }
        }
        write("variance_ratios.csv", t)?;

        let mut t = String::from("source,claim,measured,verdict\n");
        for c in self.claims() {
            let _ = writeln!(
                t,
                "{},{},{},{}",
                csv_field(&c.source),
                csv_field(&c.statement),
                csv_field(&c.measured),
                csv_field(c.verdict.name())
            );
        }
        write("variance_claims.csv", t)?;

        let t = failures_csv(ms);
        write("variance_failures.csv", t)?;

        if let Some(o) = &self.occluded {
            write("variance_occluded_curves.csv", curves_csv(&o.measurement))?;
            write(
                "variance_occluded_failures.csv",
                failures_csv(&o.measurement),
            )?;
        }
        for e in &self.extra {
            if let Some(m) = &e.measurement {
                write(&format!("variance_{}_curves.csv", e.slug), curves_csv(m))?;
            }
        }
        Ok(paths)
    }

    /// Writes the figures into `dir` (created if needed): per point set the
    /// relative-RMS-error-vs-spp curves over all receivers
    /// (`variance_<set>.svg`) and near the light (`variance_<set>_near.svg`),
    /// the error at the largest spp of each receiver against its distance
    /// to the light, for the samplers alone and area sampling with MIS
    /// (`variance_distance.svg`, a scatter plot), the MIS heuristics
    /// (`variance_heuristics.svg`), with occluders the curves per point set
    /// (`variance_occluded_<set>.svg`), and one figure per attached section
    /// with a measurement. Curves whose error never exceeds `10⁻¹²` (the
    /// zero-variance projected polygon) are named in the legend instead of
    /// drawn.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let ms = &self.measurement;
        let c = &self.config;
        let mut figs = Vec::new();
        let main: Vec<usize> = (0..ms.methods.len())
            .filter(|&m| {
                !matches!(
                    c.methods.get(m).and_then(|x| x.mis),
                    Some(Heuristic::Power(_) | Heuristic::Maximum)
                )
            })
            .collect();
        let style = |m: usize| -> (Option<figures::Rgb>, bool) {
            match c.methods.get(m) {
                Some(method) => {
                    let i = match method.sampler {
                        Sampler::Area => 0,
                        Sampler::TrianglePair => 1,
                        Sampler::Rectangle => 2,
                        Sampler::ProjectedPolygon => 3,
                        Sampler::ProjectedPolygonCubic => 8,
                        Sampler::Cosine => 4,
                        Sampler::BilinearRectangle => 9,
                    };
                    let color = match method.mis {
                        None | Some(Heuristic::Balance) => PALETTE[i],
                        Some(Heuristic::Power(_)) => PALETTE[5 + i % 5],
                        Some(Heuristic::Maximum) => PALETTE[(7 + i) % 10],
                    };
                    (Some(color), method.mis.is_some())
                }
                None => (None, false),
            }
        };
        for (p, set) in ms.point_sets.iter().enumerate() {
            for subset in [Subset::All, Subset::NearLight] {
                if subset == Subset::NearLight && !ms.receivers.iter().any(|r| r.near) {
                    continue;
                }
                let (plot, _) =
                    curves_plot(ms, &main, p, subset, &style, &self.title(*set, subset));
                let name = match subset {
                    Subset::All => format!("variance_{}.svg", set.name()),
                    Subset::NearLight => format!("variance_{}_near.svg", set.name()),
                };
                figs.push(figures::write_line_plot_svg(&dir.join(name), &plot)?);
            }
        }
        if let (Some(p), Some(l)) = (self.primary_set(), ms.spp.len().checked_sub(1)) {
            let mut order: Vec<usize> = (0..ms.receivers.len()).collect();
            order.sort_by(|&a, &b| {
                ms.receivers[a]
                    .light_distance
                    .total_cmp(&ms.receivers[b].light_distance)
            });
            let mut plot = Plot::new(
                &format!(
                    "Relative RMS error at {} spp ({} points) vs distance to the light",
                    ms.spp[l],
                    ms.point_sets[p].name()
                ),
                Axis::log("distance from the receiver to the light"),
                Axis::log("relative RMS error over runs"),
            );
            // The samplers alone, and area sampling with MIS (in its own colour).
            let area_mis = Method::mis(Sampler::Area, Heuristic::Balance);
            for &m in &main {
                let Some(method) = c.methods.get(m) else {
                    continue;
                };
                if method.mis.is_some() && *method != area_mis {
                    continue;
                }
                let pts: Vec<(f64, f64)> = order
                    .iter()
                    .map(|&r| (ms.receivers[r].light_distance, ms.receiver_rms(m, p, l, r)))
                    .collect();
                if pts.iter().all(|(_, e)| e.is_nan() || *e <= 1e-12) {
                    continue;
                }
                let color = if *method == area_mis {
                    Some(PALETTE[5])
                } else {
                    style(m).0
                };
                let mut s = Series::new(&ms.methods[m], pts);
                s.color = color;
                plot = plot.series(s);
            }
            figs.push(figures::write_scatter_svg(
                &dir.join("variance_distance.svg"),
                &plot.size(820, 560).point_radius(2.0),
            )?);
        }
        if !c.heuristic_samplers.is_empty()
            && let Some(p) = self.primary_set()
        {
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
            if !ids.is_empty() {
                // Colour by heuristic, dashed for all but the first sampler.
                let first = c.heuristic_samplers.first().copied();
                let heuristic_style = |m: usize| -> (Option<figures::Rgb>, bool) {
                    match c.methods.get(m) {
                        Some(method) => {
                            let color = match method.mis {
                                Some(Heuristic::Power(_)) => PALETTE[1],
                                Some(Heuristic::Maximum) => PALETTE[2],
                                _ => PALETTE[0],
                            };
                            (Some(color), Some(method.sampler) != first)
                        }
                        None => (None, false),
                    }
                };
                let (plot, _) = curves_plot(
                    ms,
                    &ids,
                    p,
                    Subset::All,
                    &heuristic_style,
                    &format!(
                        "MIS heuristics: relative RMS error vs spp ({} points)",
                        ms.point_sets[p].name()
                    ),
                );
                figs.push(figures::write_line_plot_svg(
                    &dir.join("variance_heuristics.svg"),
                    &plot,
                )?);
            }
        }
        if let Some(o) = &self.occluded {
            let om = &o.measurement;
            let ids: Vec<usize> = (0..om.methods.len()).collect();
            let occ_style = |m: usize| -> (Option<figures::Rgb>, bool) {
                let method = self.config.occluded_methods.get(m);
                let i = match method.map(|x| x.sampler) {
                    Some(Sampler::Area) => 0,
                    Some(Sampler::TrianglePair) => 1,
                    Some(Sampler::Rectangle) => 2,
                    Some(Sampler::ProjectedPolygon) => 3,
                    Some(Sampler::ProjectedPolygonCubic) => 8,
                    Some(Sampler::BilinearRectangle) => 9,
                    _ => 4,
                };
                (Some(PALETTE[i]), method.is_some_and(|x| x.mis.is_some()))
            };
            for (p, set) in om.point_sets.iter().enumerate() {
                let (plot, _) = curves_plot(
                    om,
                    &ids,
                    p,
                    Subset::All,
                    &occ_style,
                    &format!(
                        "With occluders: relative RMS error vs spp ({} points)",
                        set.name()
                    ),
                );
                figs.push(figures::write_line_plot_svg(
                    &dir.join(format!("variance_occluded_{}.svg", set.name())),
                    &plot,
                )?);
            }
        }
        for e in &self.extra {
            if let Some(m) = &e.measurement
                && !m.point_sets.is_empty()
            {
                let ids: Vec<usize> = (0..m.methods.len()).collect();
                let (plot, _) = curves_plot(m, &ids, 0, Subset::All, &|_| (None, false), &e.title);
                figs.push(figures::write_line_plot_svg(
                    &dir.join(format!("variance_{}.svg", e.slug)),
                    &plot,
                )?);
            }
        }
        Ok(figs)
    }

    /// A data-driven paragraph explaining the main differences (fitted
    /// rates, what MIS does to each sampler, the maximum heuristic).
    pub(crate) fn reading(&self) -> String {
        let ms = &self.measurement;
        let Some(p) = self.primary_set() else {
            return String::new();
        };
        let last = self.last_level();
        let alpha = |m: Method| {
            self.method(m)
                .and_then(|i| ms.fit(Subset::All, i, p))
                .map_or(f64::NAN, |f| f.alpha)
        };
        let rms = |m: Method| {
            self.method(m)
                .map_or(f64::NAN, |i| ms.rms(Subset::All, i, p, last))
        };
        let bal = |s| Method::mis(s, Heuristic::Balance);
        let n_max = ms.spp.last().copied().unwrap_or(0);
        let mut out = String::new();
        let (ar, at) = (
            alpha(Method::plain(Sampler::Rectangle)),
            alpha(Method::plain(Sampler::TrianglePair)),
        );
        if ar.is_finite() && at.is_finite() {
            let _ = write!(
                out,
                "Reading the numbers ({} points). Fitted rates near {n_max} spp: rectangle spp^−{ar:.2}, \
                 triangle pair spp^−{at:.2}.",
                ms.point_sets[p].name()
            );
            if at < ar {
                let _ = write!(
                    out,
                    " The pair chooses its triangle by `u`, which cuts the strata straddling the split into \
                     pieces on different triangles; the rectangle keeps every stratum whole, so on a smooth \
                     integrand its advantage grows with spp, and the sample ratio at equal error depends on \
                     where it is taken."
                );
            }
            // Independent points isolate the density from the stratification.
            if let (Some(q), Some(ia), Some(ib)) = (
                ms.point_set_index(PointSet::Independent),
                self.method(Method::plain(Sampler::Rectangle)),
                self.method(Method::plain(Sampler::TrianglePair)),
            ) {
                let r = ms.sample_ratio(Subset::All, ia, ib, q);
                let _ = write!(
                    out,
                    " With independent points the pair needs {:.3} ± {:.3} × the rectangle's samples: \
                     both densities are uniform in solid angle, so without strata their estimators are \
                     the same, and every difference between them comes from how each map carries a \
                     stratified or low-discrepancy point set.",
                    r.ratio, r.std_error
                );
            }
            if let Some(o) = &self.occluded {
                let om = &o.measurement;
                let a = |m: Method| {
                    om.method_index(&m.name())
                        .and_then(|i| om.fit(Subset::All, i, 0))
                        .map_or(f64::NAN, |f| f.alpha)
                };
                let _ = write!(
                    out,
                    " With the occluders (visibility discontinuities inside the light, as in the paper's \
                     scene): rectangle spp^−{:.2}, triangle pair spp^−{:.2}.",
                    a(Method::plain(Sampler::Rectangle)),
                    a(Method::plain(Sampler::TrianglePair))
                );
            }
            out.push_str("\n\n");
        }
        let ratios: Vec<(Sampler, f64)> = Sampler::LIGHT
            .iter()
            .filter(|&&s| s != Sampler::ProjectedPolygon)
            .filter_map(|&s| {
                let (a, b) = (rms(Method::plain(s)), rms(bal(s)));
                (a.is_finite() && b.is_finite()).then_some((s, a / b))
            })
            .collect();
        if !ratios.is_empty() {
            let list = |pred: &dyn Fn(f64) -> bool| {
                ratios
                    .iter()
                    .filter(|(_, r)| pred(*r))
                    .map(|(s, r)| format!("{} {}", s.name(), num(*r)))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let (gain, loss) = (list(&|r| r > 1.0), list(&|r| r <= 1.0));
            let _ = write!(
                out,
                "MIS with cosine sampling (balance heuristic, n + n samples), error without / with MIS at \
                 {n_max} spp — lower with MIS: {}; higher with MIS: {}.",
                if gain.is_empty() { "none" } else { &gain },
                if loss.is_empty() { "none" } else { &loss },
            );
            if !loss.is_empty() {
                let _ = write!(
                    out,
                    " Where MIS loses, the weighted estimator inherits the cosine samples' hit-or-miss \
                     discontinuity at the light's outline and caps the rate."
                );
            }
            let max = Method::mis(Sampler::Rectangle, Heuristic::Maximum);
            if let (Some(a), Some(b)) = (
                self.method(max),
                self.method(Method::plain(Sampler::Rectangle)),
            ) && (0..ms.spp.len())
                .all(|l| ms.rms(Subset::All, a, p, l) == ms.rms(Subset::All, b, p, l))
            {
                let _ = write!(
                    out,
                    " The maximum heuristic with the spherical rectangle never keeps a cosine sample here \
                     (n/Ω > n cos θ/π whenever Ω < π): its errors equal the rectangle's alone."
                );
            }
            out.push_str("\n\n");
        }
        out
    }

    pub(crate) fn title(&self, set: PointSet, subset: Subset) -> String {
        format!(
            "Relative RMS error vs spp ({} points, {} receivers)",
            set.name(),
            subset.name()
        )
    }
}

/// A log–log plot of the curves of `methods` with point set `p`, plus
/// dashed reference slopes `n^(−1/2)` and `n^(−1)`; methods with no error
/// above `10⁻¹²` get a legend entry without points instead. Returns the plot and the
/// number of curves drawn.
pub(crate) fn curves_plot(
    ms: &Measurement,
    methods: &[usize],
    p: usize,
    subset: Subset,
    style: &dyn Fn(usize) -> (Option<figures::Rgb>, bool),
    title: &str,
) -> (Plot, usize) {
    let mut exact = Vec::new();
    let mut series = Vec::new();
    let mut top: f64 = 0.0;
    for &m in methods {
        // MIS casts a cosine ray per light sample: plot it at its rays.
        let rays = if ms.methods[m].contains("MIS") {
            2.0
        } else {
            1.0
        };
        let levels = 0..ms.spp.len();
        let pts: Vec<(f64, f64)> = levels
            .clone()
            .map(|l| (rays * ms.spp[l] as f64, ms.rms(subset, m, p, l)))
            .collect();
        let band: Vec<(f64, f64, f64)> = levels
            .map(|l| {
                let (e, se) = (ms.rms(subset, m, p, l), ms.rms_std_error(subset, m, p, l));
                let (lo, hi) = crate::verdict::interval(e, se);
                (rays * ms.spp[l] as f64, lo, hi)
            })
            .collect();
        if pts.iter().all(|(_, e)| e.is_nan() || *e <= 1e-12) {
            exact.push(ms.methods[m].clone());
            continue;
        }
        top = top.max(
            pts.iter()
                .map(|p| p.1)
                .filter(|e| e.is_finite())
                .fold(0.0, f64::max),
        );
        let (color, dashed) = style(m);
        let mut s = Series::new(&ms.methods[m], pts).with_band(band);
        s.color = color;
        s.dashed = dashed;
        series.push(s);
    }
    let drawn = series.len();
    let title = if exact.is_empty() {
        title.to_string()
    } else {
        format!("{title} (not drawn, error < 1e-12: {})", exact.join(", "))
    };
    let mut plot = Plot::new(
        &title,
        Axis::log("rays per receiver (spp; MIS: n light + n cosine)"),
        Axis::log(&format!("{} (band: 95% interval)", ms.metric.name())),
    )
    .size(820, 560);
    for s in series {
        plot = plot.series(s);
    }
    if let (Some(&n0), Some(&n1)) = (ms.spp.first(), ms.spp.last())
        && top > 0.0
        && n1 > n0
    {
        for (label, a) in [("reference ∝ n^-1/2", 0.5), ("reference ∝ n^-1", 1.0)] {
            let pts = vec![
                (n0 as f64, top),
                (n1 as f64, top * (n1 as f64 / n0 as f64).powf(-a)),
            ];
            plot = plot.series(Series::new(label, pts).reference().with_color(PALETTE[7]));
        }
    }
    (plot, drawn)
}

/// The failures of a measurement as CSV.
pub(crate) fn failures_csv(ms: &Measurement) -> String {
    let mut t = String::from("method,receiver,x,y,z,failed,attempted,error\n");
    for f in &ms.failures {
        let _ = writeln!(
            t,
            "{},{},{},{},{},{},{},{}",
            csv_field(&f.method),
            f.receiver,
            f.position.x,
            f.position.y,
            f.position.z,
            f.failed,
            f.attempted,
            csv_field(&f.error)
        );
    }
    t
}

/// All curve points of a measurement as CSV.
pub(crate) fn curves_csv(ms: &Measurement) -> String {
    let mut t = String::from(
        "method,point_set,subset,spp,rms_relative_error,image_relative_error,mean_relative_error,estimates,skipped_receivers\n",
    );
    for (m, name) in ms.methods.iter().enumerate() {
        for (p, set) in ms.point_sets.iter().enumerate() {
            for subset in [Subset::All, Subset::NearLight] {
                for c in ms.curve(subset, m, p) {
                    let _ = writeln!(
                        t,
                        "{},{},{},{},{:e},{:e},{:e},{},{}",
                        csv_field(name),
                        set.name(),
                        subset.name(),
                        c.spp,
                        c.rms_relative_error,
                        c.image_relative_error,
                        c.mean_relative_error,
                        c.estimates,
                        ms.skipped_receivers(name)
                    );
                }
            }
        }
    }
    t
}
