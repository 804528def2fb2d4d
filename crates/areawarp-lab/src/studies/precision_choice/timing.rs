//! What the evaluations cost: per sample (the light built once) and
//! one-shot (construct + one sample per shading point), for the spherical
//! triangle and rectangle, `f32` robust, `f32` mixed and `f64` robust. The
//! evaluations are interleaved within every timing run, and the medians of
//! the runs reported, so that a shared machine's drift affects all alike.

use areawarp::precision_choice::{Evaluation, Mixed};
use areawarp::real::Real;
use areawarp::shapes::{SphericalRectangle, SphericalTriangle};
use areawarp::{Vec3, Warp};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::hint::black_box;
use std::time::Instant;

/// One light and evaluation's costs (ns).
#[derive(Clone, Debug, PartialEq)]
pub struct CostRow {
    /// `spherical-triangle` or `spherical-rectangle`.
    pub light: &'static str,
    /// The evaluation.
    pub evaluation: Evaluation,
    /// ns per sample, the light built once.
    pub per_sample: f64,
    /// ns per construct + one sample.
    pub one_shot: f64,
    /// ns per one-shot solid angle (no light built); `None` for the mixed
    /// mode (it is the `f64` one).
    pub solid_angle: Option<f64>,
}

fn widen(v: &Vec3<f32>) -> Vec3<f64> {
    Vec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

/// Triangle lights and shading points below them (as `[p0, p1, p2, o]`),
/// and rectangles (`[s, ex, ey, o]`), in f32 (the f64 runs widen them).
/// Per shading point: the light's four vectors (points and observer, or
/// corner, edges and observer).
type Lights = Vec<[Vec3<f32>; 4]>;

fn lights(n: usize) -> (Lights, Lights) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(0xC057);
    let mut r = || rng.random::<f64>();
    let v = |x: f64, y: f64, z: f64| Vec3::new(x as f32, y as f32, z as f32);
    let tris = (0..n)
        .map(|_| {
            [
                v(1.0, 0.1, 0.0),
                v(0.2, 1.0, 0.1),
                v(0.0, 0.3, 1.0),
                v(r() - 0.5, r() - 0.5, -1.0 - r()),
            ]
        })
        .collect();
    let rects = (0..n)
        .map(|_| {
            [
                v(-0.5, -0.4, 1.0),
                v(1.0, 0.0, 0.0),
                v(0.0, 0.8, 0.0),
                v(2.0 * r() - 1.0, 2.0 * r() - 1.0, -r()),
            ]
        })
        .collect();
    (tris, rects)
}

/// ns per call of `f` over `n` calls.
fn time(n: usize, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    f();
    start.elapsed().as_secs_f64() * 1e9 / n as f64
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn sum3<T: Real>(acc: &mut T, p: &Vec3<T>, pdf: &T) {
    *acc += p.x.clone() + &p.y + &p.z + pdf;
}

/// The costs of the six (light, evaluation) pairs, medians over
/// `repetitions` interleaved runs of `batch` samples each.
pub fn time_costs(batch: usize, repetitions: usize) -> Vec<CostRow> {
    let (tris, rects) = lights(batch);
    let uv: Vec<(f32, f32)> = {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        (0..batch)
            .map(|_| (rng.random::<f32>(), rng.random::<f32>()))
            .collect()
    };
    let uv64: Vec<(f64, f64)> = uv
        .iter()
        .map(|&(u, v)| (f64::from(u), f64::from(v)))
        .collect();
    let t0 = &tris[0];
    let tri32 = SphericalTriangle::from_points(t0[0], t0[1], t0[2], t0[3]).expect("valid triangle");
    let tri64 = SphericalTriangle::<f64>::from_points(
        widen(&t0[0]),
        widen(&t0[1]),
        widen(&t0[2]),
        widen(&t0[3]),
    )
    .expect("valid triangle");
    let tri_mixed = Mixed::new(&tri64).expect("valid triangle");
    let r0 = &rects[0];
    let rect32 = SphericalRectangle::new(r0[0], r0[1], r0[2], r0[3]).expect("valid rectangle");
    let rect64 =
        SphericalRectangle::<f64>::new(widen(&r0[0]), widen(&r0[1]), widen(&r0[2]), widen(&r0[3]))
            .expect("valid rectangle");
    let rect_mixed = Mixed::new(&rect64).expect("valid rectangle");
    let tris64: Vec<[Vec3<f64>; 4]> = tris.iter().map(|t| t.each_ref().map(widen)).collect();
    let rects64: Vec<[Vec3<f64>; 4]> = rects.iter().map(|t| t.each_ref().map(widen)).collect();

    // 16 timings per run: 6 per-sample, 6 one-shot, 4 solid angles.
    let mut runs: Vec<[f64; 16]> = Vec::new();
    for rep in 0..=repetitions {
        let mut t = [0.0; 16];
        let (mut a32, mut a64) = (0.0f32, 0.0f64);
        t[0] = time(batch, || {
            for (u, v) in &uv {
                let (p, pdf) = tri32.map_with_pdf(black_box(u), v);
                sum3(&mut a32, &p, &pdf);
            }
        });
        t[1] = time(batch, || {
            for (u, v) in &uv {
                let (p, pdf) = tri_mixed.map_with_pdf(black_box(u), v);
                sum3(&mut a32, &p, &pdf);
            }
        });
        t[2] = time(batch, || {
            for (u, v) in &uv64 {
                let (p, pdf) = tri64.map_with_pdf(black_box(u), v);
                sum3(&mut a64, &p, &pdf);
            }
        });
        t[3] = time(batch, || {
            for (u, v) in &uv {
                let (p, pdf) = rect32.map_with_pdf(black_box(u), v);
                sum3(&mut a32, &p, &pdf);
            }
        });
        t[4] = time(batch, || {
            for (u, v) in &uv {
                let (p, pdf) = rect_mixed.map_with_pdf(black_box(u), v);
                sum3(&mut a32, &p, &pdf);
            }
        });
        t[5] = time(batch, || {
            for (u, v) in &uv64 {
                let (p, pdf) = rect64.map_with_pdf(black_box(u), v);
                sum3(&mut a64, &p, &pdf);
            }
        });
        t[6] = time(batch, || {
            for ([a, b, c, o], (u, v)) in tris.iter().zip(&uv) {
                if let Ok((p, pdf)) =
                    SphericalTriangle::sample_once_from_points(black_box(a), b, c, o, u, v)
                {
                    sum3(&mut a32, &p, &pdf);
                }
            }
        });
        t[7] = time(batch, || {
            for ([a, b, c, o], (u, v)) in tris.iter().zip(&uv) {
                if let Ok((p, pdf)) = SphericalTriangle::<f64>::sample_once_from_points(
                    &widen(black_box(a)),
                    &widen(b),
                    &widen(c),
                    &widen(o),
                    &f64::from(*u),
                    &f64::from(*v),
                ) {
                    let p = Vec3::new(p.x as f32, p.y as f32, p.z as f32);
                    sum3(&mut a32, &p, &(pdf as f32));
                }
            }
        });
        t[8] = time(batch, || {
            for ([a, b, c, o], (u, v)) in tris64.iter().zip(&uv64) {
                if let Ok((p, pdf)) =
                    SphericalTriangle::sample_once_from_points(black_box(a), b, c, o, u, v)
                {
                    sum3(&mut a64, &p, &pdf);
                }
            }
        });
        t[9] = time(batch, || {
            for ([s, ex, ey, o], (u, v)) in rects.iter().zip(&uv) {
                if let Ok(smp) = SphericalRectangle::sample_once(black_box(s), ex, ey, o, u, v) {
                    sum3(&mut a32, &smp.direction, &smp.pdf);
                }
            }
        });
        t[10] = time(batch, || {
            for ([s, ex, ey, o], (u, v)) in rects.iter().zip(&uv) {
                if let Ok(smp) = SphericalRectangle::<f64>::sample_once(
                    &widen(black_box(s)),
                    &widen(ex),
                    &widen(ey),
                    &widen(o),
                    &f64::from(*u),
                    &f64::from(*v),
                ) {
                    let d = &smp.direction;
                    let p = Vec3::new(d.x as f32, d.y as f32, d.z as f32);
                    sum3(&mut a32, &p, &(smp.pdf as f32));
                }
            }
        });
        t[11] = time(batch, || {
            for ([s, ex, ey, o], (u, v)) in rects64.iter().zip(&uv64) {
                if let Ok(smp) = SphericalRectangle::sample_once(black_box(s), ex, ey, o, u, v) {
                    sum3(&mut a64, &smp.direction, &smp.pdf);
                }
            }
        });
        t[12] = time(batch, || {
            for [a, b, c, o] in &tris {
                let o = black_box(o);
                if let Ok(w) = SphericalTriangle::solid_angle_of(&a.sub(o), &b.sub(o), &c.sub(o)) {
                    a32 += w;
                }
            }
        });
        t[13] = time(batch, || {
            for [a, b, c, o] in &tris64 {
                let o = black_box(o);
                if let Ok(w) = SphericalTriangle::solid_angle_of(&a.sub(o), &b.sub(o), &c.sub(o)) {
                    a64 += w;
                }
            }
        });
        t[14] = time(batch, || {
            for [s, ex, ey, o] in &rects {
                if let Ok(w) = SphericalRectangle::solid_angle_of(black_box(s), ex, ey, o) {
                    a32 += w;
                }
            }
        });
        t[15] = time(batch, || {
            for [s, ex, ey, o] in &rects64 {
                if let Ok(w) = SphericalRectangle::solid_angle_of(black_box(s), ex, ey, o) {
                    a64 += w;
                }
            }
        });
        black_box((a32, a64));
        if rep > 0 {
            runs.push(t);
        }
    }
    let m = |i: usize| median(runs.iter().map(|t| t[i]).collect());
    let evals = [
        Evaluation::RobustF32,
        Evaluation::MixedF32,
        Evaluation::RobustF64,
    ];
    let mut out = Vec::new();
    for (light, offset, sa) in [
        ("spherical-triangle", 0, [Some(12), None, Some(13)]),
        ("spherical-rectangle", 3, [Some(14), None, Some(15)]),
    ] {
        for (k, &evaluation) in evals.iter().enumerate() {
            out.push(CostRow {
                light,
                evaluation,
                per_sample: m(offset + k),
                one_shot: m(6 + offset + k),
                solid_angle: sa[k].map(m),
            });
        }
    }
    out
}
