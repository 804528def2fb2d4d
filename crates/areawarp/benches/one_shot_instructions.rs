//! The batches of `one_shot_min.rs` run without a clock, one at a time, for
//! an instruction counter: how many instructions a prepared sample, a
//! one-shot sample and the textbook one-shot execute (the robust spherical
//! triangle and rectangle, `f32` and `f64`). Wall time on a shared machine
//! moves by tens of percent; an instruction count does not, and it shows
//! what a one-shot at 2.5× the prepared sample's time would have to leave
//! out (`docs/spherical-triangle-one-shot.md`, "What the one-shot executes").
//!
//! ```text
//! cargo bench -p areawarp --bench one_shot_instructions --no-run
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!     target/release/deps/one_shot_instructions-<hash> BATCH [REPS]
//! ```
//!
//! `BATCH` is one of the names listed when it is missing (`none` runs the
//! loop with an empty batch: its count is the harness's own, to subtract);
//! each repetition runs the batch over the 256 shading points and `(u, v)`
//! of `one_shot_min.rs`. Instructions per sample:
//! `(count(BATCH) − count(none)) / (256·REPS)`.

use areawarp::Real;
use areawarp::shapes::{SphericalRectangle, SphericalTriangle};
use std::hint::black_box;

#[path = "support/one_shot_data.rs"]
#[allow(dead_code)]
mod data;
use data::{
    batch, light_per_sample, rectangle_one_shot, rectangle_textbook_one_shot, rectangles,
    triangle_one_shot, triangle_per_sample, triangle_textbook_one_shot, triangles,
};
#[path = "support/textbook_one_shot.rs"]
mod textbook;

/// The batches of one scalar type, by name suffix (`32`, `64`).
fn batches<T: Real>(bits: &str) -> Vec<(String, Box<dyn Fn() -> f64>)> {
    let (tris, rects, uv) = (triangles::<T>(), rectangles::<T>(), batch::<T>());
    let [a, b, c, o] = tris[0].clone();
    let tri = SphericalTriangle::from_points(a, b, c, o).unwrap();
    let [s, ex, ey, o] = rects[0].clone();
    let rect = SphericalRectangle::new(s, ex, ey, o).unwrap();
    let (tris, rects, uv) = (&*tris.leak(), &*rects.leak(), &*uv.leak());
    let (tri, rect) = (&*Box::leak(Box::new(tri)), &*Box::leak(Box::new(rect)));
    let named = |name: &str, f: Box<dyn Fn() -> f64>| (format!("{name}{bits}"), f);
    vec![
        named(
            "triangle-per-sample",
            Box::new(|| triangle_per_sample(black_box(tri), uv).to_f64()),
        ),
        named(
            "triangle-one-shot",
            Box::new(|| triangle_one_shot(black_box(tris), uv).to_f64()),
        ),
        named(
            "triangle-textbook",
            Box::new(|| triangle_textbook_one_shot(black_box(tris), uv).to_f64()),
        ),
        named(
            "rectangle-per-sample",
            Box::new(|| light_per_sample(black_box(rect), uv).to_f64()),
        ),
        named(
            "rectangle-one-shot",
            Box::new(|| rectangle_one_shot(black_box(rects), uv).to_f64()),
        ),
        named(
            "rectangle-textbook",
            Box::new(|| rectangle_textbook_one_shot(black_box(rects), uv).to_f64()),
        ),
    ]
}

fn main() {
    // `cargo bench` passes `--bench`: the first other argument names the
    // batch, a number sets the repetitions.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let which = args.iter().find(|a| a.parse::<usize>().is_err());
    let reps = args.iter().find_map(|a| a.parse().ok()).unwrap_or(200);
    let mut all = batches::<f32>("32");
    all.extend(batches::<f64>("64"));
    all.push(("none".to_string(), Box::new(|| 0.0)));
    let Some(f) = which.and_then(|w| all.iter().find(|(n, _)| n == w)) else {
        let names: Vec<&str> = all.iter().map(|(n, _)| n.as_str()).collect();
        println!("batches: {}", names.join(" "));
        return;
    };
    let mut acc = 0.0;
    for _ in 0..reps {
        acc += (f.1)();
    }
    black_box(acc);
}
