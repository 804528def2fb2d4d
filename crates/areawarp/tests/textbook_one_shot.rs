//! The textbook one-shot samplers of the benchmarks
//! (`benches/support/textbook_one_shot.rs`, unvalidated, pbrt-v4 style)
//! compute the same maps as areawarp's one-shot paths: Arvo's map against
//! `SphericalTriangle::sample_once{,_from_points}` (and, with the point on
//! the plane and the density in area, `sample_light_once`) and Ureña's against
//! `SphericalRectangle::sample_once`, at the same `(u, v)`, on the
//! benchmarks' own shapes and on a few hundred random well-conditioned
//! triangles and rectangles, in `f64` (to 1e-9) and `f32` (to 1e-3).
//!
//! This is what makes the benchmark's comparison fair: the baseline is a
//! correct sampler of the same map, not a cheaper different one.

use areawarp::shapes::{SphericalRectangle, SphericalTriangle};
use areawarp::{LightSample, Real, Vec3};

#[path = "../benches/support/textbook_one_shot.rs"]
mod textbook;
use textbook::{
    textbook_rectangle_sample, textbook_triangle_light_sample, textbook_triangle_sample,
};

#[path = "../benches/support/one_shot_data.rs"]
#[allow(dead_code)]
mod data;
use data::{batch, lcg, rectangles, triangles};

/// The largest differences seen: direction (Euclidean), relative pdf,
/// relative area pdf, point (relative to the distance; for light samples
/// also the relative difference of the distances).
#[derive(Default, Debug)]
struct Worst {
    direction: f64,
    pdf: f64,
    pdf_area: f64,
    point: f64,
    samples: usize,
}

impl Worst {
    /// One light sample of ours against the textbook's: direction, point
    /// and distance (relative to ours), pdf and area pdf.
    fn add<T: Real>(&mut self, ours: &LightSample<T>, book: &LightSample<T>) {
        self.direction = self.direction.max(dist(&ours.direction, &book.direction));
        self.point = self
            .point
            .max(dist(&ours.point, &book.point) / ours.distance.to_f64())
            .max(rel(&book.distance, &ours.distance));
        self.pdf = self.pdf.max(rel(&book.pdf, &ours.pdf));
        self.pdf_area = self.pdf_area.max(rel(&book.pdf_area, &ours.pdf_area));
        self.samples += 1;
    }
}

fn dist<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> f64 {
    let d = a.sub(b);
    d.dot(&d).to_f64().sqrt()
}

fn rel<T: Real>(a: &T, b: &T) -> f64 {
    ((a.to_f64() - b.to_f64()) / b.to_f64()).abs()
}

fn triangle<T: Real>([a, b, c, o]: &[Vec3<T>; 4], uv: &[(T, T)], w: &mut Worst) {
    let (da, db, dc) = (a.sub(o), b.sub(o), c.sub(o));
    for (u, v) in uv {
        let (p, pdf) = SphericalTriangle::sample_once_from_points(a, b, c, o, u, v).unwrap();
        let (q, qdf) = textbook_triangle_sample(&da, &db, &dc, u, v);
        w.direction = w.direction.max(dist(&p, &q));
        w.pdf = w.pdf.max(rel(&qdf, &pdf));
        // The light sample: the same direction's point on the plane and
        // its density in area.
        let ours = SphericalTriangle::sample_light_once(a, b, c, o, u, v).unwrap();
        let book = textbook_triangle_light_sample(a, b, c, o, u, v);
        w.add(&ours, &book);
    }
}

fn rectangle<T: Real>([s, ex, ey, o]: &[Vec3<T>; 4], uv: &[(T, T)], w: &mut Worst) {
    for (u, v) in uv {
        let ours = SphericalRectangle::sample_once(s, ex, ey, o, u, v).unwrap();
        let book = textbook_rectangle_sample(s, ex, ey, o, u, v);
        w.add(&ours, &book);
    }
}

/// Random well-conditioned triangles, as points seen from an observer:
/// vertex directions at least 0.3 rad apart, none within 0.3 rad of the
/// plane of the other two, at distances 0.5–3.
fn random_triangles<T: Real>(n: usize) -> Vec<[Vec3<T>; 4]> {
    let mut next = lcg(0x5EED_7A1A);
    let mut dir = || loop {
        let d = [2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0];
        let n2: f64 = d.iter().map(|x| x * x).sum();
        if (0.01..=1.0).contains(&n2) {
            return d.map(|x| x / n2.sqrt());
        }
    };
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let mut out = Vec::new();
    let mut scale = lcg(0xD15_7A4C);
    while out.len() < n {
        let (a, b, c) = (dir(), dir(), dir());
        let apart = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|(p, q)| dot(p, q) < 0.3f64.cos());
        let off_plane = [(a, b, c), (b, c, a), (c, a, b)].iter().all(|(p, q, r)| {
            let n = cross(q, r);
            dot(p, &n).abs() / dot(&n, &n).sqrt() > 0.3f64.sin()
        });
        if !(apart && off_plane) {
            continue;
        }
        let o = [scale() - 0.5, scale() - 0.5, scale() - 0.5];
        let at =
            |d: [f64; 3], r: f64| Vec3::from_f64(o[0] + r * d[0], o[1] + r * d[1], o[2] + r * d[2]);
        out.push([
            at(a, 0.5 + 2.5 * scale()),
            at(b, 0.5 + 2.5 * scale()),
            at(c, 0.5 + 2.5 * scale()),
            Vec3::from_f64(o[0], o[1], o[2]),
        ]);
    }
    out
}

/// Random well-conditioned rectangles: edges of length 0.3–2 in a random
/// orientation, the observer 0.2–2 off the plane (either side), its foot
/// within 2 of the rectangle.
fn random_rectangles<T: Real>(n: usize) -> Vec<[Vec3<T>; 4]> {
    let mut next = lcg(0xAB5_0C1E);
    let mut out = Vec::new();
    while out.len() < n {
        // A random rotation from two random vectors (Gram–Schmidt).
        let a = [2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0];
        let b = [2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0];
        let na = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if na < 0.1 {
            continue;
        }
        let x = a.map(|t| t / na);
        let bx = b[0] * x[0] + b[1] * x[1] + b[2] * x[2];
        let p = [b[0] - bx * x[0], b[1] - bx * x[1], b[2] - bx * x[2]];
        let np = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        if np < 0.1 {
            continue;
        }
        let y = p.map(|t| t / np);
        let z = [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ];
        let (lx, ly) = (0.3 + 1.7 * next(), 0.3 + 1.7 * next());
        let h = (0.2 + 1.8 * next()) * if next() < 0.5 { -1.0 } else { 1.0 };
        let (fx, fy) = (4.0 * next() - 2.0, 4.0 * next() - 2.0);
        let c = [next() - 0.5, next() - 0.5, next() - 0.5];
        // Corner s at c; the observer at c + fx x + fy y + h z.
        let o = [0, 1, 2].map(|i| c[i] + fx * x[i] + fy * y[i] + h * z[i]);
        out.push([
            Vec3::from_f64(c[0], c[1], c[2]),
            Vec3::from_f64(lx * x[0], lx * x[1], lx * x[2]),
            Vec3::from_f64(ly * y[0], ly * y[1], ly * y[2]),
            Vec3::from_f64(o[0], o[1], o[2]),
        ]);
    }
    out
}

/// Every benchmark shape at every `(u, v)` of the batch, each random shape
/// at 32 of them; then every shape at the corners and midpoints of the
/// square (`edge`), where the textbook triangle loses half the digits at
/// `u = 0` (`√(1 − q²)` of `q = cos 0` rounded) and is held only to
/// `edge_tol`. Returns the worst differences (interior, edge) of the
/// triangle and the rectangle.
fn compare<T: Real>() -> [Worst; 4] {
    let uv = batch::<T>();
    let few = &uv[uv.len() - 32..];
    let edge: Vec<(T, T)> = (0..9)
        .map(|i| (T::from_ratio(i / 3, 2), T::from_ratio(i % 3, 2)))
        .collect();
    let mut w: [Worst; 4] = Default::default();
    let (tri, rect) = (triangles::<T>(), rectangles::<T>());
    let (rand_tri, rand_rect) = (random_triangles::<T>(400), random_rectangles::<T>(400));
    for (shapes, uv) in [(&tri, &uv[..]), (&rand_tri, few)] {
        for shape in shapes {
            triangle(shape, uv, &mut w[0]);
            triangle(shape, &edge, &mut w[1]);
        }
    }
    for (shapes, uv) in [(&rect, &uv[..]), (&rand_rect, few)] {
        for shape in shapes {
            rectangle(shape, uv, &mut w[2]);
            rectangle(shape, &edge, &mut w[3]);
        }
    }
    w
}

fn check<T: Real>(tol: f64, edge_tol: f64) {
    let w = compare::<T>();
    let names = ["triangle", "triangle edge", "rectangle", "rectangle edge"];
    for (what, w) in names.iter().zip(&w) {
        println!("{} {what:14} {w:?}", T::type_name());
    }
    // At the triangle's edges the point on the plane and the density in
    // area inherit the textbook direction's error (half the digits at
    // u = 0) amplified by the plane's slant: held to ten times the edge
    // tolerance (measured: 4.2e-7 in f64, 8.2e-3 in f32, where the
    // direction differs by 3.9e-8 and 1.0e-3).
    let light_tol = [tol, 10.0 * edge_tol, tol, tol];
    for (((what, w), tol), light_tol) in names
        .iter()
        .zip(&w)
        .zip([tol, edge_tol, tol, tol])
        .zip(light_tol)
    {
        let worst = w.direction.max(w.pdf);
        let worst_light = w.pdf_area.max(w.point);
        assert!(
            worst <= tol && worst_light <= light_tol,
            "{} {what}: {w:?}",
            T::type_name()
        );
    }
}

#[test]
fn textbook_equals_areawarp_f64() {
    check::<f64>(1e-9, 1e-7);
}

#[test]
fn textbook_equals_areawarp_f32() {
    check::<f32>(1e-3, 1e-2);
}

/// Which side of the `f32` differences is off: both `f32` one-shots against
/// areawarp's `f64` one-shot of the same (`f32`) data, on the benchmark's
/// triangles and rectangles at the batch's `(u, v)`. Printed for the record; areawarp's
/// `f32` must be the closer.
#[test]
fn f32_accuracy_against_f64() {
    let uv = batch::<f32>();
    let (mut ours, mut book) = (0.0f64, 0.0f64);
    let wide = |p: &Vec3<f32>| p.convert::<f64>();
    for [a, b, c, o] in &triangles::<f32>() {
        let (da, db, dc) = (a.sub(o), b.sub(o), c.sub(o));
        for (u, v) in &uv {
            let (p, _) = SphericalTriangle::sample_once_from_points(a, b, c, o, u, v).unwrap();
            let (q, _) = textbook_triangle_sample(&da, &db, &dc, u, v);
            let (r, _) = SphericalTriangle::sample_once(
                &wide(&da),
                &wide(&db),
                &wide(&dc),
                &f64::from(*u),
                &f64::from(*v),
            )
            .unwrap();
            ours = ours.max(dist(&wide(&p), &r));
            book = book.max(dist(&wide(&q), &r));
        }
    }
    println!("f32 triangle vs f64: areawarp {ours:.3e}  textbook {book:.3e}");
    assert!(ours < book, "{ours} {book}");
    // The rectangle: direction and relative pdf.
    let (mut ours, mut book) = ([0.0f64; 2], [0.0f64; 2]);
    for [s, ex, ey, o] in &rectangles::<f32>() {
        for (u, v) in &uv {
            let p = SphericalRectangle::sample_once(s, ex, ey, o, u, v).unwrap();
            let textbook = textbook_rectangle_sample(s, ex, ey, o, u, v);
            let (q, qdf) = (textbook.direction, textbook.pdf);
            let (u, v) = (f64::from(*u), f64::from(*v));
            let r =
                SphericalRectangle::sample_once(&wide(s), &wide(ex), &wide(ey), &wide(o), &u, &v)
                    .unwrap();
            let pdf = |x: f32| ((f64::from(x) - r.pdf) / r.pdf).abs();
            ours = [
                ours[0].max(dist(&wide(&p.direction), &r.direction)),
                ours[1].max(pdf(p.pdf)),
            ];
            book = [
                book[0].max(dist(&wide(&q), &r.direction)),
                book[1].max(pdf(qdf)),
            ];
        }
    }
    println!("f32 rectangle vs f64 (direction, pdf): areawarp {ours:?}  textbook {book:?}");
    assert!(ours[0] < book[0] && ours[1] < book[1], "{ours:?} {book:?}");
}
