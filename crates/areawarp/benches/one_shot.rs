//! One-shot against per-sample cost of the light shapes (issue 10, item 4;
//! issue 13, item 4), in one run: the spherical triangle and rectangle,
//! robust, in `f32`, `f64` and the mixed mode (`f32` in and out, `f64`
//! arithmetic).
//!
//! For each shape and evaluation, over a batch of 256 shading points (the
//! observer moves from point to point, as in a renderer) and 256 `(u, v)`:
//! - `per-sample`: the shape built once, constants precomputed; one
//!   `(direction, pdf)` per `(u, v)`;
//! - `one-shot`: construct + one sample per shading point
//!   (`sample_once`, no shape kept);
//! - `one-shot-textbook` (`f32`, `f64`): the same one-shot as a renderer
//!   writes it, pbrt-v4 style, unvalidated, in `T`
//!   (`support/textbook_one_shot.rs`; `tests/textbook_one_shot.rs` checks
//!   it computes the same maps), over the same shading points and `(u, v)`,
//!   folding the same outputs (the rectangle's textbook computes the area
//!   pdf too); the parity reference for `one-shot`
//!   (`python3 scripts/criterion-ratios triangle/f one-shot-textbook`:
//!   every function of the group over it, so `one-shot` reads areawarp /
//!   textbook and `per-sample` the inverse of textbook / per-sample;
//!   `… rectangle/f one-shot-textbook`);
//! - `solid-angle`: the one-shot solid angle (the pdf is `1/Ω`) per shading
//!   point, no shape built;
//! - `solid-angle-textbook`: the same solid angle as renderers write it,
//!   unvalidated, in `T`: Van Oosterom–Strackee for the triangle (pbrt-v4's
//!   formula), Girard's sum of the four planes' angles for the rectangle
//!   (pbrt-v4's `SphericalQuadArea`, the paper's Appendix B); the parity
//!   reference for `solid-angle`
//!   (`python3 scripts/criterion-ratios triangle/f solid-angle-textbook`,
//!   `… rectangle/f solid-angle-textbook`);
//! - `build`: the full constructor per shading point, for reference;
//! - `light per-sample`, `light one-shot` (triangle): the light sample of
//!   the triangle of points (direction, point, distance, both densities),
//!   `sample_light` of the built shape and `sample_light_once` (its plane
//!   included); `light one-shot-textbook`: Arvo's map unvalidated in `T`
//!   with the ray's hit on the plane and the density in area
//!   (`textbook_triangle_light_sample`), the parity reference for
//!   `light one-shot`.
//!
//! The sphere light (`sphere/f32`, `sphere/f64`): `per-sample`, `one-shot`
//! (`SphereLight::sample_once`: the light sample with its point, distance
//! and both densities) and `build`, over shading points 1.25–3.5 radii from
//! the centre; no textbook reference.
//!
//! ```text
//! cargo bench -p areawarp --bench one_shot -- --warm-up-time 1 --measurement-time 3
//! ```
//!
//! Criterion reports the time per batch of 256 (ns/sample = batch / 256); the
//! ratios one-shot / per-sample are taken within one run.

use areawarp::precision_choice::Mixed;
use areawarp::shapes::{SphereLight, SphericalRectangle, SphericalTriangle};
use areawarp::{Real, Vec3, Warp};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

#[path = "support/one_shot_data.rs"]
mod data;
use data::{
    N, batch, fold, light_per_sample, rectangle_one_shot, rectangle_textbook_one_shot, rectangles,
    sphere_one_shot, spheres, triangle_light_one_shot, triangle_light_textbook_one_shot,
    triangle_one_shot, triangle_per_sample, triangle_textbook_one_shot, triangles,
};
#[path = "support/textbook_one_shot.rs"]
mod textbook;
use textbook::{textbook_rectangle_solid_angle, textbook_solid_angle};

fn widen(v: &Vec3<f32>) -> Vec3<f64> {
    Vec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

fn narrow(v: &Vec3<f64>) -> Vec3<f32> {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

fn triangle_in<T: Real>(c: &mut Criterion, name: &str) {
    let uv = batch::<T>();
    let shapes = triangles::<T>();
    let mut g = c.benchmark_group(format!("triangle/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    let [a, b, cc, o] = &shapes[0];
    let t = SphericalTriangle::from_points(a.clone(), b.clone(), cc.clone(), o.clone()).unwrap();
    g.bench_function("per-sample", |bch| {
        bch.iter(|| triangle_per_sample(&t, &uv))
    });
    g.bench_function("one-shot", |bch| {
        bch.iter(|| triangle_one_shot(&shapes, &uv))
    });
    g.bench_function("one-shot-textbook", |bch| {
        bch.iter(|| triangle_textbook_one_shot(&shapes, &uv))
    });
    g.bench_function("light per-sample", |bch| {
        bch.iter(|| light_per_sample(&t, &uv))
    });
    g.bench_function("light one-shot", |bch| {
        bch.iter(|| triangle_light_one_shot(&shapes, &uv))
    });
    g.bench_function("light one-shot-textbook", |bch| {
        bch.iter(|| triangle_light_textbook_one_shot(&shapes, &uv))
    });
    g.bench_function("solid-angle", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, [a, b, c, o]| {
                let o = black_box(o);
                let omega =
                    SphericalTriangle::solid_angle_of(&a.sub(o), &b.sub(o), &c.sub(o)).unwrap();
                acc + &omega
            })
        })
    });
    g.bench_function("solid-angle-textbook", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, [a, b, c, o]| {
                let o = black_box(o);
                acc + &textbook_solid_angle(&a.sub(o), &b.sub(o), &c.sub(o))
            })
        })
    });
    g.bench_function("build", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, [a, b, c, o]| {
                let t = SphericalTriangle::from_points(
                    black_box(a).clone(),
                    b.clone(),
                    c.clone(),
                    o.clone(),
                )
                .unwrap();
                acc + t.solid_angle()
            })
        })
    });
    g.finish();
}

fn triangle_mixed(c: &mut Criterion) {
    let uv = batch::<f32>();
    let shapes = triangles::<f32>();
    let mut g = c.benchmark_group("triangle/f32 mixed");
    g.throughput(Throughput::Elements(N as u64));
    let [a, b, cc, o] = &shapes[0];
    let t = SphericalTriangle::<f64>::from_points(widen(a), widen(b), widen(cc), widen(o)).unwrap();
    let m = Mixed::new(&t).unwrap();
    g.bench_function("per-sample", |bch| {
        bch.iter(|| {
            uv.iter().fold(0.0f32, |acc, (u, v)| {
                let (p, pdf) = m.map_with_pdf(black_box(u), black_box(v));
                fold(acc, &p, &pdf)
            })
        })
    });
    g.bench_function("one-shot", |bch| {
        bch.iter(|| {
            shapes
                .iter()
                .zip(&uv)
                .fold(0.0f32, |acc, ([a, b, c, o], (u, v))| {
                    let (p, pdf) = SphericalTriangle::<f64>::sample_once_from_points(
                        &widen(black_box(a)),
                        &widen(b),
                        &widen(c),
                        &widen(black_box(o)),
                        &f64::from(*u),
                        &f64::from(*v),
                    )
                    .unwrap();
                    fold(acc, &narrow(&p), &(pdf as f32))
                })
        })
    });
    g.finish();
}

fn rectangle_in<T: Real>(c: &mut Criterion, name: &str) {
    let uv = batch::<T>();
    let shapes = rectangles::<T>();
    let mut g = c.benchmark_group(format!("rectangle/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    let [s, ex, ey, o] = &shapes[0];
    let r = SphericalRectangle::new(s.clone(), ex.clone(), ey.clone(), o.clone()).unwrap();
    g.bench_function("per-sample", |bch| bch.iter(|| light_per_sample(&r, &uv)));
    g.bench_function("one-shot", |bch| {
        bch.iter(|| rectangle_one_shot(&shapes, &uv))
    });
    g.bench_function("one-shot-textbook", |bch| {
        bch.iter(|| rectangle_textbook_one_shot(&shapes, &uv))
    });
    g.bench_function("solid-angle", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, [s, ex, ey, o]| {
                acc + &SphericalRectangle::solid_angle_of(black_box(s), ex, ey, black_box(o))
                    .unwrap()
            })
        })
    });
    // The reference computes the same quantity (to its own accuracy).
    for [s, ex, ey, o] in &shapes {
        let ours = SphericalRectangle::solid_angle_of(s, ex, ey, o)
            .unwrap()
            .to_f64();
        let book = textbook_rectangle_solid_angle(s, ex, ey, o).to_f64();
        assert!((ours - book).abs() <= 1e-3 * ours, "{ours} {book}");
    }
    g.bench_function("solid-angle-textbook", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, [s, ex, ey, o]| {
                acc + &textbook_rectangle_solid_angle(black_box(s), ex, ey, black_box(o))
            })
        })
    });
    g.bench_function("build", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, [s, ex, ey, o]| {
                let r = SphericalRectangle::new(
                    black_box(s).clone(),
                    ex.clone(),
                    ey.clone(),
                    o.clone(),
                )
                .unwrap();
                acc + &r.solid_angle()
            })
        })
    });
    g.finish();
}

fn rectangle_mixed(c: &mut Criterion) {
    let uv = batch::<f32>();
    let shapes = rectangles::<f32>();
    let mut g = c.benchmark_group("rectangle/f32 mixed");
    g.throughput(Throughput::Elements(N as u64));
    let [s, ex, ey, o] = &shapes[0];
    let r = SphericalRectangle::<f64>::new(widen(s), widen(ex), widen(ey), widen(o)).unwrap();
    let m = Mixed::new(&r).unwrap();
    g.bench_function("per-sample", |bch| {
        bch.iter(|| {
            uv.iter().fold(0.0f32, |acc, (u, v)| {
                let (p, pdf) = m.map_with_pdf(black_box(u), black_box(v));
                fold(acc, &p, &pdf)
            })
        })
    });
    g.bench_function("one-shot", |bch| {
        bch.iter(|| {
            shapes
                .iter()
                .zip(&uv)
                .fold(0.0f32, |acc, ([s, ex, ey, o], (u, v))| {
                    let smp = SphericalRectangle::<f64>::sample_once(
                        &widen(black_box(s)),
                        &widen(ex),
                        &widen(ey),
                        &widen(black_box(o)),
                        &f64::from(*u),
                        &f64::from(*v),
                    )
                    .unwrap();
                    fold(acc, &narrow(&smp.direction), &(smp.pdf as f32))
                })
        })
    });
    g.finish();
}

fn sphere_in<T: Real>(c: &mut Criterion, name: &str) {
    let uv = batch::<T>();
    let shapes = spheres::<T>();
    let mut g = c.benchmark_group(format!("sphere/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    let (centre, radius, o) = &shapes[0];
    let light = SphereLight::new(centre.clone(), radius.clone(), o.clone()).unwrap();
    g.bench_function("per-sample", |bch| {
        bch.iter(|| light_per_sample(&light, &uv))
    });
    g.bench_function("one-shot", |bch| bch.iter(|| sphere_one_shot(&shapes, &uv)));
    g.bench_function("build", |bch| {
        bch.iter(|| {
            shapes.iter().fold(T::zero(), |acc, (centre, radius, o)| {
                let light =
                    SphereLight::new(black_box(centre).clone(), radius.clone(), o.clone()).unwrap();
                acc + &light.measure()
            })
        })
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    triangle_in::<f32>(c, "f32 robust");
    triangle_mixed(c);
    triangle_in::<f64>(c, "f64 robust");
    rectangle_in::<f32>(c, "f32 robust");
    rectangle_mixed(c);
    rectangle_in::<f64>(c, "f64 robust");
    sphere_in::<f32>(c, "f32");
    sphere_in::<f64>(c, "f64");
}

criterion_group!(one_shot, benches);
criterion_main!(one_shot);
