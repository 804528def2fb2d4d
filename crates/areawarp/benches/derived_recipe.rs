//! What deriving a warp costs: the derived warps (φ and w only, steps 2–4 by
//! quadrature and Newton) beside the closed forms of the same maps, per
//! sample and per construction; and the tabulation dial (tables of F⁻¹ and
//! G⁻¹ for tolerances 1e-3 … 1e-12): ns/sample in f32 and f64 and the
//! construction time.
//!
//! ```text
//! cargo bench -p areawarp --bench derived_recipe
//! cargo bench -p areawarp --bench derived_recipe -- derived/   # item 1 only
//! cargo bench -p areawarp --bench derived_recipe -- dial/      # the dial only
//! ```
//!
//! Every group maps the same batch of 1024 points; the derived, closed-form
//! and tabulated maps of one shape are in one group, so their ratios come
//! from one run. The errors of the tables (measured at 256 bits) are printed
//! by `cargo test -p areawarp --features mpfr --release --test
//! tabulated_recipe -- --ignored --nocapture`.

use areawarp::recipe::definitions::{Cap, Disk, Ggx, Hemisphere, Phong, Sphere, VonMisesFisher};
use areawarp::recipe::{DerivedWarp, TabulatedWarp, WarpDefinition};
use areawarp::shapes;
use areawarp::{Coords, Real, Warp};
use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use std::hint::black_box;
use std::time::Duration;

const N: usize = 1024;

/// A fixed batch of points in [0, 1]² (a 64-bit LCG), corners included.
fn batch<T: Real>() -> Vec<(T, T)> {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut pts: Vec<(T, T)> = (0..N)
        .map(|_| (T::from_f64(next()), T::from_f64(next())))
        .collect();
    pts[0] = (T::zero(), T::zero());
    pts[1] = (T::one(), T::one());
    pts
}

/// Maps the batch, summing the coordinates so nothing is optimized away.
fn map_all<T: Real, W: Warp<T>>(w: &W, pts: &[(T, T)]) -> T {
    let mut acc = T::zero();
    for (u, v) in pts {
        let p = w.map(u, v).to_vec3();
        acc += &(p.x + &p.y + &p.z);
    }
    acc
}

fn derived_vs_closed<P, C>(c: &mut Criterion, name: &str, def: P, closed: C)
where
    P: WarpDefinition<f64>,
    C: Warp<f64>,
{
    let pts = batch::<f64>();
    let derived = DerivedWarp::new(def.clone()).expect("derivable");
    let mut g = c.benchmark_group(format!("derived/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("closed_form", |b| {
        b.iter(|| black_box(map_all(&closed, &pts)))
    });
    g.bench_function("derived", |b| b.iter(|| black_box(map_all(&derived, &pts))));
    g.throughput(Throughput::Elements(1));
    g.sampling_mode(SamplingMode::Flat);
    g.bench_function("construction", |b| {
        b.iter(|| black_box(DerivedWarp::new(black_box(def.clone())).expect("derivable")))
    });
    g.finish();
}

fn derived(c: &mut Criterion) {
    derived_vs_closed(
        c,
        "hemisphere",
        Hemisphere::new(),
        shapes::Hemisphere::new(),
    );
    for k in [1.0, 10.0, 1000.0] {
        derived_vs_closed(
            c,
            &format!("phong_k{k}"),
            Phong::new(k).expect("k"),
            shapes::PhongLobe::new(k).expect("k"),
        );
    }
    derived_vs_closed(c, "disk", Disk::new(), shapes::PolarDisk::new());
    derived_vs_closed(c, "sphere", Sphere::new(), shapes::Sphere::new());
    let cap = Cap::new(1.0).expect("angle");
    let closed_cap = DerivedWarp::new(cap.clone().with_closed_forms()).expect("closed");
    derived_vs_closed(c, "cap_1rad", cap, closed_cap);
    // The same cap against the closed-form uniform cone (cos θ_max given).
    derived_vs_closed(
        c,
        "cap_vs_uniform_cone_1rad",
        Cap::new(1.0).expect("angle"),
        shapes::UniformCone::new(1f64.cos()).expect("cone"),
    );
    derived_vs_closed(
        c,
        "ggx_alpha0.5",
        Ggx::new(0.5).expect("alpha"),
        shapes::Ggx::new(0.5).expect("alpha"),
    );
    derived_vs_closed(
        c,
        "vmf_kappa10",
        VonMisesFisher::new(10.0).expect("kappa"),
        shapes::VonMisesFisher::new(10.0).expect("kappa"),
    );
}

/// The tolerances of the dial.
const TOLERANCES: [f64; 4] = [1e-3, 1e-6, 1e-9, 1e-12];

fn dial_for<P: WarpDefinition<f64>>(c: &mut Criterion, name: &str, def: P) {
    let p64 = batch::<f64>();
    let p32 = batch::<f32>();
    let derived32 = DerivedWarp::new(def.recast::<f32>().expect("f32")).expect("derivable");
    let derived = DerivedWarp::new(def).expect("derivable");
    let mut g = c.benchmark_group(format!("dial/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("derived_f64", |b| {
        b.iter(|| black_box(map_all(&derived, &p64)))
    });
    for tol in TOLERANCES {
        let t64 = TabulatedWarp::new(&derived, tol).expect("tabulated");
        g.sampling_mode(SamplingMode::Auto);
        g.throughput(Throughput::Elements(N as u64));
        g.bench_with_input(BenchmarkId::new("f64", tol), &tol, |b, _| {
            b.iter(|| black_box(map_all(&t64, &p64)))
        });
        // f32 tables are built in f32 (from the f32 derived warp), where f32
        // can hold the tolerance (≥ 64 units of its roundoff).
        if let Ok(t32) = TabulatedWarp::new(&derived32, tol) {
            g.bench_with_input(BenchmarkId::new("f32", tol), &tol, |b, _| {
                b.iter(|| black_box(map_all(&t32, &p32)))
            });
        }
        g.throughput(Throughput::Elements(1));
        g.sampling_mode(SamplingMode::Flat);
        g.bench_with_input(BenchmarkId::new("construction", tol), &tol, |b, &tol| {
            b.iter(|| black_box(TabulatedWarp::new(&derived, tol).expect("tabulated")))
        });
    }
    g.finish();
}

fn dial(c: &mut Criterion) {
    dial_for(c, "cap_0.5rad", Cap::new(0.5).expect("angle"));
    dial_for(c, "ggx_alpha0.5", Ggx::new(0.5).expect("alpha"));
    dial_for(c, "vmf_kappa10", VonMisesFisher::new(10.0).expect("kappa"));
    // F⁻¹ ~ u^(1/11) at u = 0: the first panel in w = u^(1/m).
    dial_for(c, "phong_k10", Phong::new(10.0).expect("k"));
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(20)
}

criterion_group! {
    name = benches;
    config = config();
    targets = derived, dial
}
criterion_main!(benches);
