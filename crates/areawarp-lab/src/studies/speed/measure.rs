//! Measuring one warp: its errors against 512 bits and its timings.

use super::*;

/// The max error of one variant on one shape in one scalar.
#[derive(Clone, Debug)]
pub(crate) struct ErrorCell {
    pub(crate) rejected: bool,
    pub(crate) max_error: f64,
    pub(crate) non_finite: usize,
}

/// Max error of each variant of `e` in `T` against the exact map at 512
/// bits: each exact variant is its own reference (the sphere's two axes are
/// two maps), the others (literal, truncated inversions) share the
/// reference of the first, exact variant, evaluated once per point.
pub(crate) fn shape_errors<T: Real>(
    e: &ShapeEntry,
    points: &[(f64, f64)],
) -> Result<Vec<ErrorCell>, WarpError> {
    pub(crate) type Reference = Option<(Vec<Option<Vec3<R>>>, R)>;
    let first: Reference = with_warp!(&e.variants[0].1, |w| reference_points::<T, _>(w, points))?;
    let mut out = Vec::new();
    for (j, (_, built)) in e.variants.iter().enumerate() {
        let own: Option<Reference> = if j > 0 && with_warp!(built, |w| w.is_exact()) {
            Some(with_warp!(built, |w| reference_points::<T, _>(w, points))?)
        } else {
            None
        };
        let Some((refs, extent)) = own.as_ref().unwrap_or(&first) else {
            out.push(ErrorCell {
                rejected: true,
                max_error: 0.0,
                non_finite: 0,
            });
            continue;
        };
        let cell = with_warp!(built, |w| variant_error::<T, _>(w, points, refs, extent))?;
        out.push(cell);
    }
    Ok(out)
}

/// `x` converted exactly to the reference scalar: the sum of its leading
/// `f64` parts (`x = Σ x_i`, each `x_i` the `f64` nearest to the remainder;
/// exact for scalars of up to 512 bits, unlike a decimal round trip, whose
/// rounding the cancellation in `1 − u` would amplify).
pub(crate) fn widen<T: Real>(x: &T) -> R {
    let mut acc = R::zero();
    let mut rest = x.clone();
    for _ in 0..12 {
        let part = rest.to_f64();
        if part == 0.0 || !part.is_finite() {
            break;
        }
        acc += R::from_f64(part);
        rest -= T::from_f64(part);
    }
    acc
}

pub(crate) fn widen3<T: Real>(p: &Vec3<T>) -> Vec3<R> {
    Vec3::new(widen(&p.x), widen(&p.y), widen(&p.z))
}

/// The exact map of the shape as `T` sees it at 512 bits, at the points
/// rounded to `T` (`None` where not finite), and its extent; `None` if
/// `T` rejects the shape.
#[allow(clippy::type_complexity)]
pub(crate) fn reference_points<T: Real, W: StudyWarp>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<Option<(Vec<Option<Vec3<R>>>, R)>, WarpError> {
    let Ok(wt) = w.exact().at::<T>() else {
        return Ok(None);
    };
    let wr = wt.at::<R>()?;
    let refs = points
        .iter()
        .map(|&(u, v)| {
            let (ut, vt) = (T::from_f64(u), T::from_f64(v));
            let q = wr.map(&widen(&ut), &widen(&vt)).to_vec3();
            q.is_finite().then_some(q)
        })
        .collect();
    Ok(Some((refs, wr.extent())))
}

pub(crate) fn variant_error<T: Real, W: StudyWarp>(
    w: &W,
    points: &[(f64, f64)],
    refs: &[Option<Vec3<R>>],
    extent: &R,
) -> Result<ErrorCell, WarpError> {
    let Ok(wt) = w.at::<T>() else {
        return Ok(ErrorCell {
            rejected: true,
            max_error: 0.0,
            non_finite: 0,
        });
    };
    let mut cell = ErrorCell {
        rejected: false,
        max_error: 0.0,
        non_finite: 0,
    };
    for (&(u, v), q) in points.iter().zip(refs) {
        let Some(q) = q else { continue };
        let p = wt.map(&T::from_f64(u), &T::from_f64(v)).to_vec3();
        if !p.is_finite() {
            cell.non_finite += 1;
            continue;
        }
        let p: Vec3<R> = widen3(&p);
        let err = (p.sub(q).max_abs() / extent).to_f64();
        cell.max_error = cell.max_error.max(err);
    }
    Ok(cell)
}

/// ns per sample of `w.map` over `inputs`, `reps` timed runs after one
/// untimed run.
pub(crate) fn time_map<T: Real, W: Warp<T>>(w: &W, inputs: &[(T, T)], reps: usize) -> Timing {
    let run = || {
        let start = Instant::now();
        for (u, v) in inputs {
            black_box(w.map(black_box(u), black_box(v)));
        }
        start.elapsed().as_secs_f64() * 1e9 / inputs.len() as f64
    };
    run();
    Timing::of((0..reps).map(|_| run()).collect(), inputs.len())
}

/// ns per sample of rebuilding the shape in `T` from its `f64` data
/// ([`WarpFamily::at`]) and mapping one sample, over `inputs`.
pub(crate) fn time_build<T: Real, W: WarpFamily<f64>>(
    w: &W,
    inputs: &[(T, T)],
    reps: usize,
) -> Result<Timing, WarpError> {
    let run = || -> Result<f64, WarpError> {
        let start = Instant::now();
        for (u, v) in inputs {
            // Opaque, so that the map cannot be specialised to the
            // constants of a shape built in the loop.
            let wt = black_box(black_box(w).at::<T>()?);
            black_box(wt.map(black_box(u), black_box(v)));
        }
        Ok(start.elapsed().as_secs_f64() * 1e9 / inputs.len() as f64)
    };
    run()?;
    let runs = (0..reps).map(|_| run()).collect::<Result<Vec<f64>, _>>()?;
    Ok(Timing::of(runs, inputs.len()))
}

pub(crate) fn timings<T: Real, W: StudyWarp>(
    w: &W,
    config: &SpeedConfig,
) -> Result<(Timing, Timing), WarpError> {
    let mpfr = T::precision() > 53;
    let (batch, build_batch, reps) = if mpfr {
        (
            config.mpfr_batch,
            config.mpfr_batch,
            config.mpfr_repetitions,
        )
    } else {
        (config.batch, config.build_batch, config.repetitions)
    };
    let inputs: Vec<(T, T)> = random_points(batch.max(build_batch), config.seed ^ 0x7157)
        .into_iter()
        .map(|(u, v)| (T::from_f64(u), T::from_f64(v)))
        .collect();
    let wt = w.at::<T>()?;
    let map = time_map(&wt, &inputs[..batch], reps);
    let build = time_build(w, &inputs[..build_batch], reps)?;
    Ok((map, build))
}
