//! The Pareto sets and the recommended defaults.

use super::*;

/// Marks, per warp, the rows not dominated in (median map time, max
/// error): no other row of the warp is at least as fast and at least as
/// accurate and strictly better in one. Rows with NaN/∞ outputs count as
/// infinitely inaccurate.
pub(crate) fn mark_pareto(rows: &mut [SpeedRow]) {
    let key = |r: &SpeedRow| {
        let e = if r.non_finite > 0 {
            f64::INFINITY
        } else {
            r.max_error
        };
        (r.map.median, e)
    };
    let keys: Vec<(f64, f64)> = rows.iter().map(key).collect();
    for i in 0..rows.len() {
        let (ti, ei) = keys[i];
        let dominated = (0..rows.len()).any(|j| {
            let (tj, ej) = keys[j];
            j != i && rows[j].warp == rows[i].warp && tj <= ti && ej <= ei && (tj < ti || ej < ei)
        });
        rows[i].pareto = !dominated && ei.is_finite();
    }
}

/// `a` is clearly faster than `b`: a median at least 10 % lower and
/// interquartile ranges that do not overlap.
pub(crate) fn clearly_faster(a: &Timing, b: &Timing) -> bool {
    a.median < 0.9 * b.median && a.q3 < b.q1
}

/// Per warp, among the `f64` rows without NaN/∞ whose max error is within a
/// factor 4 of the smallest such `f64` max error (*qualifying*): the
/// crate's default variant (the first of [`warp_variants`]) if it
/// qualifies and no qualifying alternative is [clearly
/// faster](clearly_faster); else the fastest (median) clearly faster
/// alternative; else, if the default does not qualify, the fastest
/// qualifying row. The reason cites the alternatives.
///
/// [`warp_variants`]: crate::studies::precision::warp_variants
pub(crate) fn recommend(rows: &[SpeedRow]) -> Vec<Recommendation> {
    pub(crate) fn fastest<'a>(v: &[&'a SpeedRow]) -> Option<&'a SpeedRow> {
        v.iter()
            .copied()
            .min_by(|a, b| a.map.median.total_cmp(&b.map.median))
    }
    let mut out = Vec::new();
    for (warp, variants) in crate::studies::precision::warp_variants() {
        let f64_rows: Vec<&SpeedRow> = rows
            .iter()
            .filter(|r| r.warp == warp && r.scalar == "f64")
            .collect();
        let clean: Vec<&SpeedRow> = f64_rows
            .iter()
            .copied()
            .filter(|r| r.non_finite == 0)
            .collect();
        let Some(best_error) = clean.iter().map(|r| r.max_error).min_by(f64::total_cmp) else {
            continue;
        };
        let tolerance = 4.0 * best_error.max(f64::MIN_POSITIVE);
        let qualifying: Vec<&SpeedRow> = clean
            .iter()
            .copied()
            .filter(|r| r.max_error <= tolerance)
            .collect();
        let default = qualifying
            .iter()
            .copied()
            .find(|r| r.variant == variants[0]);
        let (pick, why) = match default {
            Some(d) => {
                let faster: Vec<&SpeedRow> = qualifying
                    .iter()
                    .copied()
                    .filter(|r| clearly_faster(&r.map, &d.map))
                    .collect();
                match fastest(&faster) {
                    Some(f) => (f, "clearly faster than the default, as accurate"),
                    None => (
                        d,
                        "the default: as accurate as the best, no alternative clearly faster",
                    ),
                }
            }
            None => match fastest(&qualifying) {
                Some(f) => (f, "the default is not accurate enough"),
                None => continue,
            },
        };
        let mut reason = format!(
            "{why} — f64 {}: {} ns/sample ({} with construction), max error {} ({} u) over {} shapes",
            pick.variant,
            fmt_num(pick.map.median),
            fmt_num(pick.build_and_map.median),
            fmt_num(pick.max_error),
            fmt_num(pick.max_error_ulps),
            pick.shapes
        );
        for r in &f64_rows {
            if r.variant == pick.variant {
                continue;
            }
            let _ = write!(
                reason,
                "; {}: {} ns/sample ({:.2}×), max error {}",
                r.variant,
                fmt_num(r.map.median),
                r.map.median / pick.map.median,
                fmt_num(r.max_error)
            );
            if r.non_finite > 0 {
                let _ = write!(reason, ", {} NaN/∞", r.non_finite);
            } else if r.max_error > tolerance {
                let _ = write!(
                    reason,
                    " ({}× the best)",
                    fmt_num(r.max_error / best_error.max(f64::MIN_POSITIVE))
                );
            }
        }
        if let Some(f32_row) = rows
            .iter()
            .find(|r| r.warp == warp && r.scalar == "f32" && r.variant == pick.variant)
        {
            let _ = write!(
                reason,
                "; in f32: {} ns/sample ({:.2}×), max error {}{}",
                fmt_num(f32_row.map.median),
                f32_row.map.median / pick.map.median,
                fmt_num(f32_row.max_error),
                if f32_row.non_finite > 0 {
                    format!(", {} NaN/∞", f32_row.non_finite)
                } else {
                    String::new()
                }
            );
        }
        out.push(Recommendation {
            warp: warp.to_string(),
            variant: pick.variant.clone(),
            scalar: pick.scalar.clone(),
            ns_per_sample: pick.map.median,
            ns_with_construction: pick.build_and_map.median,
            max_error: pick.max_error,
            reason,
        });
    }
    out
}
