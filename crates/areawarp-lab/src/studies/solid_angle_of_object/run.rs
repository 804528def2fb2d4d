//! Running the study: the estimators, the f32 error maps, the pole profile and
//! the random-axis spread.

use super::*;

// ---------------------------------------------------------------------------
// Running
// ---------------------------------------------------------------------------

pub(crate) fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A job's seed from the master seed and the job's coordinates.
pub(crate) fn job_seed(seed: u64, parts: &[u64]) -> u64 {
    parts
        .iter()
        .fold(splitmix(seed), |h, &p| splitmix(h ^ splitmix(p)))
}

/// The box padding for a map in `T`: 64 units of roundoff (radians).
pub(crate) fn pad_for<T: Real>() -> f64 {
    64.0 * T::unit_roundoff().to_f64()
}

/// Counts hits of the `pts` relative box points through `sphere` (in `T`).
pub(crate) fn count_hits<T: Real>(
    geom: &Geometry,
    sphere: &Sphere<T>,
    bx: &AngularBox,
    pts: impl Iterator<Item = (f64, f64)>,
) -> u64 {
    let mut hits = 0;
    for (s, t) in pts {
        let (u, v) = bx.point(s, t);
        let p = sphere.map(&T::from_f64(u), &T::from_f64(v));
        if geom.hit(&[p.x.to_f64(), p.y.to_f64(), p.z.to_f64()]) {
            hits += 1;
        }
    }
    hits
}

pub(crate) fn jitter<'r>(
    k: usize,
    rng: &'r mut Xoshiro256PlusPlus,
) -> impl Iterator<Item = (f64, f64)> + 'r {
    (0..k * k).map(move |idx| {
        let (i, j) = (idx % k, idx / k);
        let a: f64 = rng.random();
        let b: f64 = rng.random();
        ((i as f64 + a) / k as f64, (j as f64 + b) / k as f64)
    })
}

pub(crate) fn uniform(
    n: usize,
    rng: &mut Xoshiro256PlusPlus,
) -> impl Iterator<Item = (f64, f64)> + '_ {
    (0..n).map(move |_| (rng.random::<f64>(), rng.random::<f64>()))
}

/// One estimate: `(Ω̂, mean box fraction)`.
pub(crate) fn estimate<T: Real>(
    geom: &Geometry,
    m: &Method,
    n: usize,
    seed: u64,
) -> Result<(f64, f64), WarpError> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let pad = pad_for::<T>();
    let boxed = |sphere: &Sphere<T>| -> Result<AngularBox, WarpError> {
        Ok(if m.bounding_box {
            geom.angular_box(&sphere.at::<f64>()?, pad)
        } else {
            AngularBox::full()
        })
    };
    let log4 = (n.trailing_zeros() / 2) as usize;
    match (m.axis, m.sampling) {
        (AxisMode::Fixed, sampling) => {
            let sphere = Sphere::<T>::new();
            let bx = boxed(&sphere)?;
            let hits = match sampling {
                Sampling::Random => count_hits(geom, &sphere, &bx, uniform(n, &mut rng)),
                Sampling::Stratified => count_hits(geom, &sphere, &bx, jitter(1 << log4, &mut rng)),
            };
            Ok((bx.measure() * hits as f64 / n as f64, bx.fraction()))
        }
        (AxisMode::Random, Sampling::Random) => {
            let (mut sum, mut frac) = (0.0, 0.0);
            for _ in 0..n {
                let sphere = Sphere::<T>::with_random_axis(&mut rng);
                let bx = boxed(&sphere)?;
                let st = (rng.random::<f64>(), rng.random::<f64>());
                let hits = count_hits(geom, &sphere, &bx, std::iter::once(st));
                sum += bx.measure() * hits as f64;
                frac += bx.fraction();
            }
            Ok((sum / n as f64, frac / n as f64))
        }
        (AxisMode::Random, Sampling::Stratified) => {
            let (ka, kc) = (1usize << (log4 / 4), 1usize << (log4 - log4 / 4));
            let north = Sphere::<f64>::new();
            let axes: Vec<(f64, f64)> = jitter(ka, &mut rng).collect();
            let (mut sum, mut frac) = (0.0, 0.0);
            for (a, b) in axes {
                let axis: Vec3<T> = north.map(&a, &b).convert();
                let sphere = Sphere::<T>::with_axis(axis)?;
                let bx = boxed(&sphere)?;
                let hits = count_hits(geom, &sphere, &bx, jitter(kc, &mut rng));
                sum += bx.measure() * hits as f64 / (kc * kc) as f64;
                frac += bx.fraction();
            }
            Ok((sum / (ka * ka) as f64, frac / (ka * ka) as f64))
        }
    }
}

pub(crate) fn estimate_with(
    geom: &Geometry,
    m: &Method,
    n: usize,
    seed: u64,
) -> Result<(f64, f64), WarpError> {
    match m.precision {
        Precision::F32 => estimate::<f32>(geom, m, n, seed),
        Precision::F64 => estimate::<f64>(geom, m, n, seed),
    }
}

/// End-to-end and evaluation-only errors of `Sphere<f32>` (from `s32`) at
/// data `(u, v)`, against `sr` (the same frame in `R`), in units of `2^-24`;
/// also the reference point.
pub(crate) fn f32_errors<R: Real>(
    s32: &Sphere<f32>,
    sr: &Sphere<R>,
    u: f64,
    v: f64,
) -> (f64, f64, Vec3<R>) {
    let unit = R::exp2i(-24);
    let (u32_, v32) = (u as f32, v as f32);
    let p = s32.map(&u32_, &v32);
    let exact = sr.map(&R::from_f64(u), &R::from_f64(v));
    let rounded = sr.map(&convert::<f32, R>(&u32_), &convert::<f32, R>(&v32));
    if !p.is_finite() {
        return (f64::INFINITY, f64::INFINITY, exact);
    }
    let p: Vec3<R> = p.convert();
    let e2e = (p.sub(&exact).max_abs() / &unit).to_f64();
    let eval = (p.sub(&rounded).max_abs() / &unit).to_f64();
    (e2e, eval, exact)
}

pub(crate) fn f32_map(config: &SolidAngleConfig) -> Result<F32ErrorMap, WarpError> {
    let (cells, pp) = (config.heat_map_cells, config.heat_map_points);
    let s32 = Sphere::<f32>::new();
    let sr = s32.at::<Reference>()?;
    let rows: Vec<(Vec<f64>, Vec<f64>)> = (0..cells)
        .into_par_iter()
        .map(|j| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(config.seed, &[1, j as u64]));
            let mut e2e = vec![0.0f64; cells];
            let mut eval = vec![0.0f64; cells];
            for i in 0..cells {
                for a in 0..pp {
                    for b in 0..pp {
                        let u = (i as f64 + (a as f64 + rng.random::<f64>()) / pp as f64)
                            / cells as f64;
                        let v = (j as f64 + (b as f64 + rng.random::<f64>()) / pp as f64)
                            / cells as f64;
                        let (x, y, _) = f32_errors(&s32, &sr, u, v);
                        e2e[i] = e2e[i].max(x);
                        eval[i] = eval[i].max(y);
                    }
                }
            }
            (e2e, eval)
        })
        .collect();
    let mut map = F32ErrorMap {
        cols: cells,
        rows: cells,
        points_per_cell: pp * pp,
        reference: Reference::type_name(),
        end_to_end_ulps: Vec::with_capacity(cells * cells),
        evaluation_ulps: Vec::with_capacity(cells * cells),
    };
    for (e, v) in rows {
        map.end_to_end_ulps.extend(e);
        map.evaluation_ulps.extend(v);
    }
    Ok(map)
}

pub(crate) fn pole_profile(config: &SolidAngleConfig) -> Result<Vec<PoleProfileRow>, WarpError> {
    let s32 = Sphere::<f32>::new();
    let sr = s32.at::<Reference>()?;
    let ks: Vec<i32> = (1..=40).collect();
    Ok(ks
        .par_iter()
        .map(|&k| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(config.seed, &[2, k as u64]));
            let d = 2f64.powi(-k);
            let mut row = PoleProfileRow {
                log2_distance: -k,
                north_end_to_end: 0.0,
                south_end_to_end: 0.0,
                north_evaluation: 0.0,
                south_evaluation: 0.0,
            };
            for _ in 0..config.profile_points {
                let r: f64 = rng.random();
                let v: f64 = rng.random();
                let (a, b, _) = f32_errors(&s32, &sr, d * (1.0 + r), v);
                row.north_end_to_end = row.north_end_to_end.max(a);
                row.north_evaluation = row.north_evaluation.max(b);
                let (a, b, _) = f32_errors(&s32, &sr, 1.0 - d * (1.0 + r), v);
                row.south_end_to_end = row.south_end_to_end.max(a);
                row.south_evaluation = row.south_evaluation.max(b);
            }
            row
        })
        .collect())
}

/// Per-job accumulator of the world maps.
#[derive(Clone)]
pub(crate) struct WorldAcc {
    pub(crate) sum_sq: Vec<f64>,
    pub(crate) count: Vec<u64>,
    pub(crate) max_north: f64,
    pub(crate) max_south: f64,
    pub(crate) max_else: f64,
    pub(crate) cap_sq: f64,
    pub(crate) total_sq: f64,
}

pub(crate) fn axis_spread(
    config: &SolidAngleConfig,
    random: bool,
    cols: usize,
    rows: usize,
) -> Result<AxisSpread, WarpError> {
    let jobs = 64usize;
    let per_job = config.world_samples.div_ceil(jobs);
    let world = Sphere::<f64>::new();
    let accs: Vec<WorldAcc> = (0..jobs)
        .into_par_iter()
        .map(|job| -> Result<WorldAcc, WarpError> {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(
                config.seed,
                &[3, random as u64, job as u64],
            ));
            let mut acc = WorldAcc {
                sum_sq: vec![0.0; cols * rows],
                count: vec![0; cols * rows],
                max_north: 0.0,
                max_south: 0.0,
                max_else: 0.0,
                cap_sq: 0.0,
                total_sq: 0.0,
            };
            let fixed = Sphere::<f32>::new();
            let fixed_ref = fixed.at::<Reference>()?;
            let start = job * per_job;
            let end = ((job + 1) * per_job).min(config.world_samples);
            for _ in start..end {
                let (u, v): (f64, f64) = (rng.random(), rng.random());
                let (e2e, exact) = if random {
                    let s = Sphere::<f32>::with_random_axis(&mut rng);
                    let r = s.at::<Reference>()?;
                    let (e, _, p) = f32_errors(&s, &r, u, v);
                    (e, p)
                } else {
                    let (e, _, p) = f32_errors(&fixed, &fixed_ref, u, v);
                    (e, p)
                };
                let p = Vec3::new(exact.x.to_f64(), exact.y.to_f64(), exact.z.to_f64());
                let p = p.normalized().unwrap_or(Vec3::new(0.0, 0.0, 1.0));
                let [uw, vw] = world.inverse(&p).unwrap_or([0.0, 0.0]);
                let ci = ((uw * cols as f64) as usize).min(cols - 1);
                let cj = ((vw * rows as f64) as usize).min(rows - 1);
                let sq = e2e * e2e;
                acc.sum_sq[cj * cols + ci] += sq;
                acc.count[cj * cols + ci] += 1;
                acc.total_sq += sq;
                if p.z > 0.99 {
                    acc.max_north = acc.max_north.max(e2e);
                    acc.cap_sq += sq;
                } else if p.z < -0.99 {
                    acc.max_south = acc.max_south.max(e2e);
                    acc.cap_sq += sq;
                } else {
                    acc.max_else = acc.max_else.max(e2e);
                }
            }
            Ok(acc)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut total = WorldAcc {
        sum_sq: vec![0.0; cols * rows],
        count: vec![0; cols * rows],
        max_north: 0.0,
        max_south: 0.0,
        max_else: 0.0,
        cap_sq: 0.0,
        total_sq: 0.0,
    };
    for a in &accs {
        for k in 0..cols * rows {
            total.sum_sq[k] += a.sum_sq[k];
            total.count[k] += a.count[k];
        }
        total.max_north = total.max_north.max(a.max_north);
        total.max_south = total.max_south.max(a.max_south);
        total.max_else = total.max_else.max(a.max_else);
        total.cap_sq += a.cap_sq;
        total.total_sq += a.total_sq;
    }
    Ok(AxisSpread {
        axis: if random { "random" } else { "fixed" }.to_string(),
        samples: config.world_samples,
        cap_error_share: if total.total_sq > 0.0 {
            total.cap_sq / total.total_sq
        } else {
            0.0
        },
        max_north_cap: total.max_north,
        max_south_cap: total.max_south,
        max_elsewhere: total.max_else,
        rms: (total.total_sq / config.world_samples as f64).sqrt(),
        cols,
        rows,
        cell_rms: total
            .sum_sq
            .iter()
            .zip(&total.count)
            .map(|(s, &c)| (c > 0).then(|| (s / c as f64).sqrt()))
            .collect(),
    })
}

pub(crate) fn slope(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let k = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / k,
        pts.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

/// `|a − b| / |b|`, evaluated in `R`.
pub(crate) fn relative_difference<R: Real>(a: f64, b: &R) -> f64 {
    ((R::from_f64(a) - b) / b).abs().to_f64()
}

/// Runs the study on rayon's current thread pool. The result depends only
/// on `config` (not on the number of threads).
///
/// # Errors
/// [`WarpError::InvalidParameter`] for an invalid configuration (sample
/// counts not powers of 4, fewer than 2 repetitions, empty lists); mesh and
/// viewpoint errors of the scenes.
pub fn run(config: &SolidAngleConfig) -> Result<SolidAngleStudy, WarpError> {
    config.validate()?;
    let geoms: Vec<Geometry> = config
        .scenes
        .iter()
        .map(|s| Geometry::new(&s.mesh, &s.viewpoint))
        .collect::<Result<_, _>>()?;
    let mut scenes = Vec::new();
    let mut exact = Vec::new();
    for (s, g) in config.scenes.iter().zip(&geoms) {
        let e64: f64 = exact_solid_angle(&s.mesh, &s.viewpoint)?;
        let er: Reference = exact_solid_angle(&s.mesh, &s.viewpoint)?;
        let rel = relative_difference(e64, &er);
        scenes.push(SceneSummary {
            name: s.name.clone(),
            description: s.description.clone(),
            faces: s.mesh.faces.len(),
            kind: s.mesh.kind,
            exact_f64: e64,
            exact_reference: er.to_roundtrip_string(),
            f64_relative_error: rel,
            fixed_box_fraction: g.angular_box(&Sphere::new(), pad_for::<f64>()).fraction(),
        });
        exact.push(er.to_f64());
    }

    // The estimation jobs, in a fixed order; results collected in that order.
    let mut jobs = Vec::new();
    let skipped = |m: &Method, n: usize| {
        m.sampling == Sampling::Random
            && m.axis == AxisMode::Random
            && n > config.per_sample_axis_max_n
    };
    for si in 0..config.scenes.len() {
        for mi in 0..config.methods.len() {
            for (ni, &n) in config.sample_counts.iter().enumerate() {
                if skipped(&config.methods[mi], n) {
                    continue;
                }
                for r in 0..config.repetitions {
                    jobs.push((si, mi, ni, n, r));
                }
            }
        }
    }
    let results: Vec<(f64, f64)> = jobs
        .par_iter()
        .map(|&(si, mi, ni, n, r)| {
            let seed = job_seed(config.seed, &[0, si as u64, mi as u64, ni as u64, r as u64]);
            estimate_with(&geoms[si], &config.methods[mi], n, seed)
        })
        .collect::<Result<_, _>>()?;

    let mut rows = Vec::new();
    let mut slopes = Vec::new();
    let reps = config.repetitions;
    // Jobs are grouped by (scene, method, n) with the repetitions innermost.
    let mut chunks = results.chunks(reps);
    for (si, s) in config.scenes.iter().enumerate() {
        for m in &config.methods {
            let mut curve = Vec::new();
            for &n in &config.sample_counts {
                if skipped(m, n) {
                    continue;
                }
                let Some(chunk) = chunks.next() else {
                    break;
                };
                let omega = exact[si];
                let mean = chunk.iter().map(|r| r.0).sum::<f64>() / reps as f64;
                let mse = chunk.iter().map(|r| (r.0 - omega).powi(2)).sum::<f64>() / reps as f64;
                let var =
                    chunk.iter().map(|r| (r.0 - mean).powi(2)).sum::<f64>() / (reps - 1) as f64;
                let frac = chunk.iter().map(|r| r.1).sum::<f64>() / reps as f64;
                // se of the mean squared error, then of its square root.
                let sq_var = chunk
                    .iter()
                    .map(|r| ((r.0 - omega).powi(2) - mse).powi(2))
                    .sum::<f64>()
                    / (reps - 1) as f64;
                let rms_std_error = if mse > 0.0 {
                    (sq_var / reps as f64).sqrt() / (2.0 * mse.sqrt()) / omega
                } else {
                    0.0
                };
                let area = 4.0 * std::f64::consts::PI * frac;
                let p = (omega / area).min(1.0);
                let row = ErrorRow {
                    scene: s.name.clone(),
                    method: m.name(),
                    n,
                    repetitions: reps,
                    mean,
                    rms_relative_error: mse.sqrt() / omega,
                    rms_std_error,
                    relative_bias: (mean - omega) / omega,
                    bias_std_error: (var / reps as f64).sqrt() / omega,
                    box_fraction: frac,
                    random_prediction: (p * (1.0 - p) / n as f64).sqrt() * area / omega,
                };
                curve.push((n as f64, row.rms_relative_error));
                rows.push(row);
            }
            slopes.push(SlopeRow {
                scene: s.name.clone(),
                method: m.name(),
                slope: slope(&curve),
            });
        }
    }

    // Sample-distribution demo on the first scene.
    let demo_geom = &geoms[0];
    let demo_box = demo_geom.angular_box(&Sphere::new(), pad_for::<f64>());
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(job_seed(config.seed, &[4]));
    let sphere = Sphere::<f64>::new();
    let demo_points = jitter(32, &mut rng)
        .map(|(s, t)| {
            let (u, v) = demo_box.point(s, t);
            let p = sphere.map(&u, &v);
            (v, u, demo_geom.hit(&arr(&p)))
        })
        .collect();

    Ok(SolidAngleStudy {
        config: config.clone(),
        scenes,
        rows,
        slopes,
        f32_map: f32_map(config)?,
        pole_profile: pole_profile(config)?,
        axis_spread: vec![
            axis_spread(config, false, 64, 32)?,
            axis_spread(config, true, 64, 32)?,
        ],
        demo_points,
        demo_box,
    })
}
