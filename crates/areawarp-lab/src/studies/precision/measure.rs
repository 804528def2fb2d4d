//! Measuring one warp in one scalar type against 256 bits: errors,
//! κ-conditioned ratios, Jacobians, f32 error maps.

use super::*;

// ---------------------------------------------------------------------------
// Measuring one warp in one scalar
// ---------------------------------------------------------------------------

/// The outcome at one input point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PointOutcome {
    /// Both finite: error against the exact map and against the variant's
    /// own map at 256 bits (units of `u_T · extent`), and the distance
    /// outside the shape (same units).
    Finite {
        ulps: f64,
        own_ulps: f64,
        outside_ulps: f64,
    },
    /// The map in `T` returned NaN or ∞.
    NonFinite,
    /// The 256-bit reference was not finite.
    ReferenceNonFinite,
}

/// Evaluates `w` in `T` at `points` against the exact map of the shape as
/// `T` sees it at 256 bits. `Err` if `T` rejects the shape.
pub(crate) fn point_errors<T: Real, W: StudyWarp>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<Vec<PointOutcome>, WarpError> {
    let wt = w.at::<T>()?;
    let wr = w.exact().at::<T>()?.at::<M>()?;
    let own = if w.is_exact() {
        None
    } else {
        Some(wt.at::<M>()?)
    };
    let unit = M::exp2i(-(T::precision() as i32)) * &wr.extent();
    let mut out = Vec::with_capacity(points.len());
    for &(u, v) in points {
        let (ut, vt) = (T::from_f64(u), T::from_f64(v));
        let (um, vm): (M, M) = (convert(&ut), convert(&vt));
        let q = wr.map(&um, &vm).to_vec3();
        if !q.is_finite() {
            out.push(PointOutcome::ReferenceNonFinite);
            continue;
        }
        let p = wt.map(&ut, &vt).to_vec3();
        if !p.is_finite() {
            out.push(PointOutcome::NonFinite);
            continue;
        }
        let pm: Vec3<M> = p.convert();
        let ulps = (pm.sub(&q).max_abs() / &unit).to_f64();
        let own_ulps = match &own {
            None => ulps,
            Some(o) => {
                let r = o.map(&um, &vm).to_vec3();
                if r.is_finite() {
                    (pm.sub(&r).max_abs() / &unit).to_f64()
                } else {
                    f64::NAN
                }
            }
        };
        let outside = wr.outside_by(&Coords::from_vec3(pm)) / &unit;
        out.push(PointOutcome::Finite {
            ulps,
            own_ulps,
            outside_ulps: outside.to_f64(),
        });
    }
    Ok(out)
}

/// The median of the finite values (sorted copy); 0 for none.
pub(crate) fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}

pub(crate) fn error_map(
    e: &ShapeEntry,
    variant: &str,
    n: usize,
    grid: &[(f64, f64)],
    outcomes: &[PointOutcome],
) -> F32ErrorMap {
    let mut values = Vec::with_capacity(outcomes.len());
    let mut non_finite = 0;
    let mut max = 0.0;
    let mut worst = (0.0, 0.0);
    for (o, &uv) in outcomes.iter().zip(grid) {
        match o {
            PointOutcome::Finite { ulps, .. } => {
                values.push(*ulps);
                if *ulps > max {
                    max = *ulps;
                    worst = uv;
                }
            }
            _ => {
                non_finite += 1;
                values.push(f64::NAN);
            }
        }
    }
    let finite = values.iter().filter(|x| x.is_finite()).count();
    let above = values.iter().filter(|&&x| x > 4.0).count();
    F32ErrorMap {
        warp: e.warp.to_string(),
        variant: variant.to_string(),
        shape: e.shape.clone(),
        nodes: n,
        median_ulps: median(&values),
        max_ulps: max,
        worst,
        above_4: if finite > 0 {
            above as f64 / finite as f64
        } else {
            0.0
        },
        non_finite,
        values,
    }
}

/// The 256-bit Jacobian deviation and non-finite count of each variant of
/// `e` (independent of the scalar under test).
pub(crate) fn jacobians(
    e: &ShapeEntry,
    points: &[(f64, f64)],
) -> Result<Vec<(f64, usize)>, WarpError> {
    let mut jac = Vec::new();
    for (_, built) in &e.variants {
        let r = with_warp!(built, |w| check_jacobian(w, points))?;
        jac.push((r.max_rel_deviation, r.non_finite));
    }
    Ok(jac)
}

/// The cells of every variant of `e` in `T` (κ computed once), each with
/// its finite per-point errors (for the pooled medians); the Jacobian
/// fields are filled in by [`run`].
pub(crate) fn scalar_cells<T: Real>(
    e: &ShapeEntry,
    points: &[(f64, f64)],
) -> Result<Vec<(PrecisionCell, Vec<f64>)>, WarpError> {
    let format = format_of::<T>()?;
    let ut = format.unit_roundoff();
    let exact = &e.variants[0].1;
    let accepted = with_warp!(exact, |w| w.at::<T>().is_ok());
    let kappas: Result<Vec<f64>, WarpError> = if accepted {
        with_warp!(exact, |w| w.kappas::<T>(&e.raw, points))
    } else {
        Err(WarpError::Degenerate {
            what: "shape rejected in this scalar",
        })
    };
    let mut out = Vec::new();
    for (label, built) in &e.variants {
        let mut cell = PrecisionCell {
            warp: e.warp.to_string(),
            variant: label.to_string(),
            shape: e.shape.clone(),
            hard: e.hard,
            scalar: T::type_name(),
            rejected: false,
            points: points.len(),
            max_ulps: 0.0,
            median_ulps: 0.0,
            worst: None,
            own_max_ulps: 0.0,
            non_finite: 0,
            reference_non_finite: 0,
            outside: 0,
            max_outside_ulps: 0.0,
            max_kappa_ratio: None,
            worst_kappa_ratio: None,
            max_kappa_ulps: None,
            outside_bound: 0,
            kappa_error: None,
            jacobian_max_dev: 0.0,
            jacobian_non_finite: 0,
        };
        let outcomes = if accepted {
            with_warp!(built, |w| point_errors::<T, _>(w, points))
        } else {
            Err(WarpError::Degenerate { what: "rejected" })
        };
        let Ok(outcomes) = outcomes else {
            cell.rejected = true;
            out.push((cell, Vec::new()));
            continue;
        };
        let kappa = kappas.as_ref().ok();
        if let Err(err) = &kappas {
            cell.kappa_error = Some(err.to_string());
        } else {
            cell.max_kappa_ratio = Some(0.0);
            cell.max_kappa_ulps = Some(0.0);
        }
        let mut finite = Vec::with_capacity(points.len());
        for (i, (o, &uv)) in outcomes.iter().zip(points).enumerate() {
            match *o {
                PointOutcome::NonFinite => cell.non_finite += 1,
                PointOutcome::ReferenceNonFinite => cell.reference_non_finite += 1,
                PointOutcome::Finite {
                    ulps,
                    own_ulps,
                    outside_ulps,
                } => {
                    finite.push(ulps);
                    if cell.worst.is_none() || ulps > cell.max_ulps {
                        cell.max_ulps = ulps;
                        cell.worst = Some(uv);
                    }
                    if own_ulps > cell.own_max_ulps || own_ulps.is_nan() {
                        cell.own_max_ulps = own_ulps;
                    }
                    if outside_ulps > OUTSIDE_TOLERANCE_ULPS {
                        cell.outside += 1;
                    }
                    cell.max_outside_ulps = cell.max_outside_ulps.max(outside_ulps);
                    if let Some(k) = kappa {
                        let bound = accuracy_bound(k[i], format);
                        let ratio = ulps * ut / bound;
                        if ratio > cell.max_kappa_ratio.unwrap_or(0.0)
                            || cell.worst_kappa_ratio.is_none()
                        {
                            cell.max_kappa_ratio = Some(ratio);
                            cell.worst_kappa_ratio = Some(uv);
                        }
                        let ku = k[i] / ut;
                        if ku > cell.max_kappa_ulps.unwrap_or(0.0) {
                            cell.max_kappa_ulps = Some(ku);
                        }
                        if outside_ulps * ut > bound {
                            cell.outside_bound += 1;
                        }
                    }
                }
            }
        }
        cell.median_ulps = median(&finite);
        out.push((cell, finite));
    }
    Ok(out)
}

pub(crate) fn summarize(cells: &[(PrecisionCell, Vec<f64>)]) -> Vec<PrecisionSummary> {
    let mut out = Vec::new();
    for (warp, variants) in warp_variants() {
        for variant in variants {
            for scalar in ["f32", "f64"] {
                let mine: Vec<&(PrecisionCell, Vec<f64>)> = cells
                    .iter()
                    .filter(|(c, _)| c.warp == warp && c.variant == variant && c.scalar == scalar)
                    .collect();
                if mine.is_empty() {
                    continue;
                }
                let mut s = PrecisionSummary {
                    warp: warp.to_string(),
                    variant: variant.to_string(),
                    scalar: scalar.to_string(),
                    shapes: 0,
                    rejected: 0,
                    points: 0,
                    max_ulps: 0.0,
                    worst: None,
                    median_ulps: 0.0,
                    own_max_ulps: 0.0,
                    non_finite: 0,
                    reference_non_finite: 0,
                    outside: 0,
                    outside_bound: 0,
                    max_kappa_ratio: None,
                    worst_kappa_shape: None,
                    kappa_failures: 0,
                    jacobian_max_dev: 0.0,
                    jacobian_non_finite: 0,
                };
                let mut pooled = Vec::new();
                for (c, errs) in mine {
                    s.jacobian_max_dev = s.jacobian_max_dev.max(c.jacobian_max_dev);
                    s.jacobian_non_finite += c.jacobian_non_finite;
                    if c.rejected {
                        s.rejected += 1;
                        continue;
                    }
                    s.shapes += 1;
                    s.points += c.points;
                    pooled.extend_from_slice(errs);
                    if let Some(uv) = c.worst
                        && (s.worst.is_none() || c.max_ulps > s.max_ulps)
                    {
                        s.max_ulps = c.max_ulps;
                        s.worst = Some((c.shape.clone(), uv));
                    }
                    if c.own_max_ulps > s.own_max_ulps || c.own_max_ulps.is_nan() {
                        s.own_max_ulps = c.own_max_ulps;
                    }
                    s.non_finite += c.non_finite;
                    s.reference_non_finite += c.reference_non_finite;
                    s.outside += c.outside;
                    s.outside_bound += c.outside_bound;
                    match c.max_kappa_ratio {
                        Some(r) => {
                            if s.max_kappa_ratio.is_none_or(|m| r > m) {
                                s.max_kappa_ratio = Some(r);
                                s.worst_kappa_shape = Some(c.shape.clone());
                            }
                        }
                        None => s.kappa_failures += 1,
                    }
                }
                s.median_ulps = median(&pooled);
                out.push(s);
            }
        }
    }
    out
}
