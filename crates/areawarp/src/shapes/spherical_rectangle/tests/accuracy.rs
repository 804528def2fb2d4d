//! The ladder against 256 bits, with the bound 16·max(u_T, κ).
use super::*;
use crate::harness::sensitivity::InputFormat;
use crate::real::{Mpfr256, convert};

type M = Mpfr256;

/// Errors of one point, in the units of κ: the direction absolutely
/// (unit vectors), the point per axis relative to that edge's length
/// (and off the plane relative to the shorter edge).
pub(super) struct Frame {
    xhat: Vec3<M>,
    yhat: Vec3<M>,
    zhat: Vec3<M>,
    inv_lx: M,
    inv_ly: M,
    inv_small: M,
}

impl Frame {
    pub(super) fn of(r: &SphericalRectangle<M>) -> Self {
        let g = &r.geometry;
        let (lx, ly) = (g.ex.norm(), g.ey.norm());
        Frame {
            xhat: g.xhat.clone(),
            yhat: g.yhat.clone(),
            zhat: g.zhat.clone(),
            inv_small: M::one() / &lx.min(&ly),
            inv_lx: M::one() / &lx,
            inv_ly: M::one() / &ly,
        }
    }
    /// `max` over the axes of `|Δp·axis| / length`.
    pub(super) fn point_error(&self, dp: &Vec3<M>) -> M {
        (dp.dot(&self.xhat).abs() * &self.inv_lx)
            .max(&(dp.dot(&self.yhat).abs() * &self.inv_ly))
            .max(&(dp.dot(&self.zhat).abs() * &self.inv_small))
    }
}

fn params(p: &[Vec3<f64>; 4]) -> [f64; 12] {
    let mut out = [0.0; 12];
    for (i, v) in p.iter().enumerate() {
        out[3 * i] = v.x;
        out[3 * i + 1] = v.y;
        out[3 * i + 2] = v.z;
    }
    out
}

fn from_params(q: &[f64; 12], bits: u32) -> Result<SphericalRectangle<M>, WarpError> {
    let v = |i: usize| {
        Vec3::new(
            M::from_f64(q[i]),
            M::from_f64(q[i + 1]),
            M::from_f64(q[i + 2]),
        )
    };
    SphericalRectangle::with_input_precision(v(0), v(3), v(6), v(9), V::Robust, bits)
}

fn bits(format: InputFormat) -> u32 {
    match format {
        InputFormat::F32 => 24,
        InputFormat::F64 => 53,
    }
}

/// κ of the direction and of the point (as [`Frame::point_error`]) at
/// each input point: the largest move of the exact (256-bit) map under a
/// one-ulp change of one of the 12 coordinates, of `u` or of `v`, in the
/// input format.
pub(super) fn kappas(
    shape: &[Vec3<f64>; 4],
    points: &[(f64, f64)],
    format: InputFormat,
) -> Result<Vec<(f64, f64)>, WarpError> {
    let b = bits(format);
    let base: [f64; 12] = params(shape).map(|x| format.round(x));
    let w = from_params(&base, b)?;
    let frame = Frame::of(&w);
    let inputs: Vec<(M, M)> = points
        .iter()
        .map(|&(u, v)| (M::from_f64(format.round(u)), M::from_f64(format.round(v))))
        .collect();
    let reference: Vec<(Vec3<M>, Vec3<M>)> =
        inputs.iter().map(|(u, v)| w.sample_point(u, v)).collect();
    let mut k = vec![(M::zero(), M::zero()); points.len()];
    let mut record = |i: usize, (p, d): (Vec3<M>, Vec3<M>)| {
        let kd = d.sub(&reference[i].1).max_abs();
        let kp = frame.point_error(&p.sub(&reference[i].0));
        if kd > k[i].0 {
            k[i].0 = kd;
        }
        if kp > k[i].1 {
            k[i].1 = kp;
        }
    };
    let mut q = base;
    for j in 0..12 {
        for x in [format.next_up(base[j]), format.next_down(base[j])] {
            q[j] = x;
            let built = from_params(&q, b);
            q[j] = base[j];
            let Ok(wp) = built else { continue };
            for (i, (u, v)) in inputs.iter().enumerate() {
                record(i, wp.sample_point(u, v));
            }
        }
    }
    for (i, &(u, v)) in points.iter().enumerate() {
        let (u, v) = (format.round(u), format.round(v));
        for x in [format.next_up(u), format.next_down(u)] {
            if (0.0..=1.0).contains(&x) {
                record(i, w.sample_point(&M::from_f64(x), &inputs[i].1));
            }
        }
        for x in [format.next_up(v), format.next_down(v)] {
            if (0.0..=1.0).contains(&x) {
                record(i, w.sample_point(&inputs[i].0, &M::from_f64(x)));
            }
        }
    }
    Ok(k.into_iter()
        .map(|(a, b)| (a.to_f64(), b.to_f64()))
        .collect())
}

/// One row of the accuracy table.
#[derive(Clone, Debug, Default)]
pub(super) struct Row {
    pub name: String,
    pub omega: f64,
    /// Shape rejected in this precision (e.g. the observer rounds into the plane).
    pub rejected: bool,
    /// max error of the direction / of the point, in units of u_T.
    pub dir_ulps: f64,
    pub point_ulps: f64,
    /// max of error / (16·max(u_T, κ)) for direction and point.
    pub dir_ratio: f64,
    pub point_ratio: f64,
    /// max κ over the points, in units of u_T.
    pub kappa_dir_ulps: f64,
    pub kappa_point_ulps: f64,
    pub non_finite: usize,
    /// Points off the rectangle by more than 4 u_T (|s| + |e_x| + |e_y|),
    /// directions off the spherical rectangle by more than 16·max(u_T, κ).
    pub outside: usize,
    /// max |(u, v) − inverse(map(u, v))| through the direction.
    pub roundtrip: f64,
    /// max |(u, v) − inverse_point(point(u, v))|.
    pub roundtrip_point: f64,
    /// max of the round-trip error over 16·max(u_T, κ_inv), κ_inv the
    /// move of the exact inverse under a one-ulp change of one
    /// coordinate of the direction (resp. point) rounded to T.
    pub roundtrip_ratio: f64,
    pub roundtrip_point_ratio: f64,
    /// max over points of the round-trip error over
    /// max(1e-12, 16·max(u_T, κ_inv)) at that point, through the
    /// direction and the point: ≤ 1 when every point meets issue 4's
    /// 1e-12 or, where the data cannot determine (u, v) that well, 16×
    /// its own floor.
    pub roundtrip_excess: f64,
    pub roundtrip_point_excess: f64,
    pub roundtrip_failures: usize,
}

/// Measures `variant` in `T` on `shape` against the robust map at 256
/// bits of the same shape as `T` sees it.
pub(super) fn measure<T: Real>(
    name: &str,
    shape: &[Vec3<f64>; 4],
    variant: V,
    points: &[(f64, f64)],
    kappa: &[(f64, f64)],
) -> Row {
    let mut row = Row {
        name: name.to_string(),
        ..Row::default()
    };
    let Ok(wt) = build::<T>(shape, variant) else {
        row.rejected = true;
        return row;
    };
    let wref = build::<T>(shape, V::Robust)
        .and_then(|w| w.at::<M>())
        .expect("the reference accepts what T accepts");
    row.omega = wref.solid_angle().to_f64();
    let frame = Frame::of(&wref);
    let ut = T::unit_roundoff().to_f64();
    let g = &wref.geometry;
    let point_scale = M::from_f64(4.0 * ut) * &(g.s.norm() + &g.ex.norm() + &g.ey.norm());
    for (&(u, v), &(kd, kp)) in points.iter().zip(kappa) {
        let (u_t, v_t) = (T::from_f64(u), T::from_f64(v));
        let (p, d) = wt.sample_point(&u_t, &v_t);
        if !(p.is_finite() && d.is_finite()) {
            row.non_finite += 1;
            continue;
        }
        let (um, vm): (M, M) = (convert(&u_t), convert(&v_t));
        let (pr, dr) = wref.sample_point(&um, &vm);
        let (pm, dm): (Vec3<M>, Vec3<M>) = (p.convert(), d.convert());
        let ed = dm.sub(&dr).max_abs().to_f64();
        let ep = frame.point_error(&pm.sub(&pr)).to_f64();
        let bd = 16.0 * ut.max(kd);
        let bp = 16.0 * ut.max(kp);
        row.dir_ulps = row.dir_ulps.max(ed / ut);
        row.point_ulps = row.point_ulps.max(ep / ut);
        row.dir_ratio = row.dir_ratio.max(ed / bd);
        row.point_ratio = row.point_ratio.max(ep / bp);
        row.kappa_dir_ulps = row.kappa_dir_ulps.max(kd / ut);
        row.kappa_point_ulps = row.kappa_point_ulps.max(kp / ut);
        let out_p = wref.point_outside_by(&pm) > point_scale;
        let out_d = wref.outside_by(&dm).to_f64() > bd;
        if out_p || out_d {
            row.outside += 1;
        }
        let format = if T::precision() <= 24 {
            InputFormat::F32
        } else {
            InputFormat::F64
        };
        let uv = (um.to_f64(), vm.to_f64());
        for (which, inv) in [(0, wt.inverse(&d)), (1, wt.inverse_point(&p))] {
            let Some([a, b]) = inv.ok().filter(|[a, b]| a.is_finite() && b.is_finite()) else {
                row.roundtrip_failures += 1;
                continue;
            };
            let e = (a - &u_t).abs().max(&(b - &v_t).abs()).to_f64();
            let q = if which == 0 { &d } else { &p };
            let k = inverse_kappa(&wref, which == 0, q, uv, format);
            let ratio = e / (16.0 * ut.max(k));
            let excess = e / (16.0 * ut.max(k)).max(1e-12);
            if which == 0 {
                row.roundtrip = row.roundtrip.max(e);
                row.roundtrip_ratio = row.roundtrip_ratio.max(ratio);
                row.roundtrip_excess = row.roundtrip_excess.max(excess);
            } else {
                row.roundtrip_point = row.roundtrip_point.max(e);
                row.roundtrip_point_ratio = row.roundtrip_point_ratio.max(ratio);
                row.roundtrip_point_excess = row.roundtrip_point_excess.max(excess);
            }
        }
    }
    row
}

/// κ of the exact inverse at `q` (a direction or a point in `T`): the
/// largest move of the exact `(u, v)` (256 bits) of `q` when one
/// coordinate of `q` moves by one ulp (in `format`) of `q`'s largest
/// coordinate: the size of the rounding error of every coordinate of a
/// computed unit vector, or of a point `s + ξ e_x + η e_y`.
fn inverse_kappa<T: Real>(
    wref: &SphericalRectangle<M>,
    direction: bool,
    q: &Vec3<T>,
    _uv: (f64, f64),
    format: InputFormat,
) -> f64 {
    let c = [q.x.to_f64(), q.y.to_f64(), q.z.to_f64()];
    let eval = |c: [f64; 3]| -> Option<(M, M)> {
        let v = Vec3::new(M::from_f64(c[0]), M::from_f64(c[1]), M::from_f64(c[2]));
        if direction {
            wref.direction_uv(&v)
        } else {
            Some(wref.point_uv(&v))
        }
    };
    let Some(base) = eval(c) else {
        return f64::INFINITY;
    };
    let m = c[0].abs().max(c[1].abs()).max(c[2].abs());
    let step = format.next_up(m) - m;
    let mut k = M::zero();
    for i in 0..3 {
        for x in [c[i] + step, c[i] - step] {
            let mut cc = c;
            cc[i] = x;
            if let Some((a, b)) = eval(cc) {
                let m = (a - &base.0).abs().max(&(b - &base.1).abs());
                if m > k {
                    k = m;
                }
            }
        }
    }
    k.to_f64()
}

pub(super) fn print_header() {
    println!(
        "{:<34} {:>10} {:>10} {:>10} {:>8} {:>8} {:>10} {:>10} {:>4} {:>4} {:>9} {:>7} {:>9} {:>7}",
        "shape",
        "Ω",
        "dir[u]",
        "pt[u]",
        "dir/bd",
        "pt/bd",
        "κdir[u]",
        "κpt[u]",
        "NaN",
        "out",
        "rt(dir)",
        "rt/lim",
        "rt(pt)",
        "rt/lim"
    );
}

pub(super) fn print_row(r: &Row) {
    if r.rejected {
        println!("{:<34} rejected in this precision", r.name);
        return;
    }
    println!(
        "{:<34} {:>10.3e} {:>10.3e} {:>10.3e} {:>8.3} {:>8.3} {:>10.3e} {:>10.3e} {:>4} {:>4} {:>9.2e} {:>7.3} {:>9.2e} {:>7.3}",
        r.name,
        r.omega,
        r.dir_ulps,
        r.point_ulps,
        r.dir_ratio,
        r.point_ratio,
        r.kappa_dir_ulps,
        r.kappa_point_ulps,
        r.non_finite,
        r.outside,
        r.roundtrip,
        r.roundtrip_excess,
        r.roundtrip_point,
        r.roundtrip_point_excess
    );
}

fn ladder_points(random: usize) -> Vec<(f64, f64)> {
    let mut pts = extremes_grid();
    pts.extend(random_points(random, 4));
    pts
}

fn run<T: Real>(format: InputFormat, random: usize) -> Vec<(Row, Row)> {
    let pts = ladder_points(random);
    let mut rows = Vec::new();
    for (name, shape) in all_shapes() {
        let kappa = match kappas(&shape, &pts, format) {
            Ok(k) => k,
            Err(_) => {
                let r = Row {
                    name: name.clone(),
                    rejected: true,
                    ..Row::default()
                };
                rows.push((r.clone(), r));
                continue;
            }
        };
        let robust = measure::<T>(&name, &shape, V::Robust, &pts, &kappa);
        let literal = measure::<T>(&name, &shape, V::Literal, &pts, &kappa);
        rows.push((robust, literal));
    }
    println!("{} — robust:", T::type_name());
    print_header();
    rows.iter().for_each(|(r, _)| print_row(r));
    println!("{} — literal:", T::type_name());
    print_header();
    rows.iter().for_each(|(_, l)| print_row(l));
    rows
}

/// The criteria of issue 4 for the robust map: error ≤ 16·max(u_T, κ)
/// for the direction and the point, no NaN, nothing outside, and an
/// inverse for every sample. In f64 also the round trip: through the
/// point within `max(1e-12, 16 κ_inv)` (κ_inv the sensitivity of the
/// exact inverse to a one-ulp change of the point), through the
/// direction within 16 times that (the direction carries the forward
/// error, up to 16 κ of the map, which the inverse amplifies like a
/// rounding error), and within 1e-12 on the ordinary shapes.
fn assert_robust(rows: &[(Row, Row)], f64_round_trip: bool) {
    let ordinary: Vec<String> = ordinary_rectangles().into_iter().map(|(n, _)| n).collect();
    for (r, _) in rows {
        if r.rejected {
            continue;
        }
        assert_eq!(r.non_finite, 0, "{r:?}");
        assert_eq!(r.outside, 0, "{r:?}");
        assert!(r.dir_ratio <= 1.0 && r.point_ratio <= 1.0, "{r:?}");
        assert_eq!(r.roundtrip_failures, 0, "{r:?}");
        if f64_round_trip {
            // Point by point: within 1e-12, or within 16 times the
            // floor the f64 data leave (the exact inverse's move under
            // one ulp of the direction or point).
            assert!(r.roundtrip_point_excess <= 1.0, "{r:?}");
            assert!(r.roundtrip_excess <= 1.0, "{r:?}");
            if ordinary.contains(&r.name) {
                assert!(r.roundtrip <= 1e-12 && r.roundtrip_point <= 1e-12, "{r:?}");
            }
        }
    }
}

#[test]
fn spherical_rectangle_robust_f64_within_sensitivity_bound() {
    let rows = run::<f64>(InputFormat::F64, 8);
    assert_robust(&rows, true);
    assert!(rows.iter().all(|(r, _)| !r.rejected));
}

#[test]
fn spherical_rectangle_robust_f32_within_sensitivity_bound() {
    let rows = run::<f32>(InputFormat::F32, 8);
    assert_robust(&rows, false);
}

/// The full tables (more random points), printed: `cargo test --release
/// spherical_rectangle_accuracy_tables -- --ignored --nocapture`.
#[test]
#[ignore]
fn spherical_rectangle_accuracy_tables() {
    let rows = run::<f64>(InputFormat::F64, 256);
    assert_robust(&rows, true);
    let rows = run::<f32>(InputFormat::F32, 256);
    assert_robust(&rows, false);
}
