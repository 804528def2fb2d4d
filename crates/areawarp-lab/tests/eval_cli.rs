//! `areawarp eval` against an independent evaluation: the closed forms of the
//! papers written directly with MPFR (`rug`) at 256 bits in this file, not
//! through the crate's generic code.

use rug::Float;
use rug::float::Constant;
use rug::ops::Pow;
use std::io::Write;
use std::process::{Command, Stdio};

const PREC: u32 = 256;
const UV: [&str; 8] = [
    "0",
    "8.673617379884035e-19",
    "1e-12",
    "1e-6",
    "0.5",
    "0.999999",
    "0.999999999999",
    "1",
];

fn f(x: f64) -> Float {
    Float::with_val(PREC, x)
}

fn run_eval(args: &[&str], input: &str) -> (String, bool) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_areawarp"))
        .arg("eval")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("run areawarp");
    feed(&mut child, input.as_bytes());
    let out = child.wait_with_output().unwrap();
    (String::from_utf8(out.stdout).unwrap(), out.status.success())
}

/// Writes `input` to the child's standard input and closes it. A program
/// that refuses its arguments exits before reading, so a broken pipe is
/// expected there (the exit status says what happened); any other write
/// error fails the test.
fn feed(child: &mut std::process::Child, input: &[u8]) {
    let mut stdin = child.stdin.take().unwrap();
    match stdin.write_all(input) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => panic!("write to areawarp: {e}"),
        _ => {}
    }
}

/// The input value as the evaluator sees it in the given precision, exactly.
fn as_seen(s: &str, prec: &str) -> Float {
    if prec == "f32" {
        f(s.parse::<f32>().unwrap() as f64)
    } else {
        f(s.parse::<f64>().unwrap())
    }
}

fn two_pi() -> Float {
    Float::with_val(PREC, Constant::Pi) * 2u32
}

/// (√u cos 2πv, √u sin 2πv)
fn polar(r: Float, v: &Float) -> [Float; 2] {
    let a = two_pi() * v;
    [r.clone() * a.clone().cos(), r * a.sin()]
}

fn reference(map: &str, params: &[Float], u: &Float, v: &Float) -> Vec<Float> {
    let one = f(1.0);
    match map {
        "disk" => polar(u.clone().sqrt(), v).to_vec(),
        "concentric-disk" => {
            let a = u.clone() * 2u32 - 1u32;
            let b = v.clone() * 2u32 - 1u32;
            if a.is_zero() && b.is_zero() {
                return vec![f(0.0), f(0.0)];
            }
            let quarter_pi = Float::with_val(PREC, Constant::Pi) / 4u32;
            let (r, phi) = if a.clone().abs() > b.clone().abs() {
                (a.clone(), quarter_pi * (b / &a))
            } else {
                (
                    b.clone(),
                    Float::with_val(PREC, Constant::Pi) / 2u32 - quarter_pi * (a / &b),
                )
            };
            vec![r.clone() * phi.clone().cos(), r * phi.sin()]
        }
        "hemisphere" | "sphere" | "phong" => {
            let z = match map {
                "hemisphere" => one.clone() - u,
                "sphere" => one.clone() - u.clone() * 2u32,
                _ => {
                    let e = one.clone() / (params[0].clone() + 1u32);
                    if u.is_zero() {
                        f(0.0)
                    } else {
                        u.clone().pow(&e)
                    }
                }
            };
            let r = (one - z.clone().square()).sqrt();
            let [x, y] = polar(r, v);
            vec![x, y, z]
        }
        "planar-triangle" => {
            let s = u.clone().sqrt();
            (0..3)
                .map(|i| {
                    (f(1.0) - &s) * &params[i]
                        + s.clone() * (f(1.0) - v) * &params[3 + i]
                        + s.clone() * v * &params[6 + i]
                })
                .collect()
        }
        "uniform-cone" | "von-mises-fisher" | "ggx" | "beckmann" => {
            let z = match map {
                "uniform-cone" => one.clone() - u.clone() * (one.clone() - &params[0]),
                "von-mises-fisher" => {
                    // z = 1 + ln(1 + u(e^(−2κ) − 1))/κ, from the antipode's
                    // side (1 − u)(e^(2κ) − 1) for u > 1/2, where e^(−2κ)
                    // is below even 256 bits' resolution of 1.
                    let k = &params[0];
                    if *u <= 0.5 {
                        let e = (k.clone() * -2i32).exp_m1();
                        one.clone() + (u.clone() * e).ln_1p() / k
                    } else {
                        let e = (k.clone() * 2u32).exp_m1();
                        ((one.clone() - u) * e).ln_1p() / k - 1u32
                    }
                }
                "ggx" => {
                    let a2 = params[0].clone().square();
                    let q = one.clone() - u;
                    (q.clone() / (q + a2 * u)).sqrt()
                }
                _ => {
                    // tan²θ = −α² ln(1 − u); at u = 1, z = 0.
                    let t2 = -(params[0].clone().square()) * (one.clone() - u).ln();
                    one.clone() / (one.clone() + t2).sqrt()
                }
            };
            // max(0, ·): at u = 1, z = −1 up to the 256-bit rounding.
            let r = (one - z.clone().square()).max(&f(0.0)).sqrt();
            let [x, y] = polar(r, v);
            vec![x, y, z]
        }
        "bilinear" => {
            // Root of the linear CDF's quadratic (cancellation is harmless
            // at 256 bits); uniform when the endpoints are equal.
            let lin = |u: &Float, a: &Float, b: &Float| -> Float {
                if a == b {
                    return u.clone();
                }
                let root = (a.clone().square()
                    + u.clone() * (b.clone().square() - a.clone().square()))
                .sqrt();
                (root - a) / (b.clone() - a)
            };
            let w = params;
            let x = lin(u, &(w[0].clone() + &w[2]), &(w[1].clone() + &w[3]));
            let a = (one.clone() - &x) * &w[0] + x.clone() * &w[1];
            let b = (one.clone() - &x) * &w[2] + x.clone() * &w[3];
            vec![x, lin(v, &a, &b)]
        }
        "tent" => {
            let t = |u: &Float| -> Float {
                if *u < 0.5 {
                    (u.clone() * 2u32).sqrt() - 1u32
                } else {
                    one.clone() - ((one.clone() - u) * 2u32).sqrt()
                }
            };
            vec![t(u), t(v)]
        }
        "std-normal" => {
            let mut q = one.clone() - u;
            if q.is_zero() {
                q = Float::with_val(PREC, Float::i_exp(1, -120));
            }
            let r = (q.ln() * -2i32).sqrt();
            polar(r, v).to_vec()
        }
        "planar-triangle-fold" => {
            let (lb, lc) = if u >= v {
                (u.clone() - v.clone() / 2u32, v.clone() / 2u32)
            } else {
                (u.clone() / 2u32, v.clone() - u.clone() / 2u32)
            };
            let la = one.clone() - u.clone().max(v);
            (0..3)
                .map(|i| {
                    la.clone() * &params[i]
                        + lb.clone() * &params[3 + i]
                        + lc.clone() * &params[6 + i]
                })
                .collect()
        }
        _ => unreachable!(),
    }
}

fn check(map: &str, params: &[&str], extent: f64) {
    check_with(map, map, &[], params, extent);
}

/// As [`check`], with extra `args` and the reference formula `reference_of`.
fn check_with(map: &str, reference_of: &str, args: &[&str], params: &[&str], extent: f64) {
    for prec in ["f32", "f64"] {
        let unit = if prec == "f32" {
            f32::EPSILON as f64 / 2.0
        } else {
            f64::EPSILON / 2.0
        };
        let mut input = String::new();
        let mut cases = Vec::new();
        for u in UV {
            for v in UV {
                input += &format!("{map} {} {u} {v}\n", params.join(" "));
                cases.push((u, v));
            }
        }
        let mut all_args = vec!["--precision", prec];
        all_args.extend_from_slice(args);
        let (out, ok) = run_eval(&all_args, &input);
        assert!(ok, "{map} {prec}: eval failed:\n{out}");
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), cases.len());
        let ps: Vec<Float> = params.iter().map(|p| as_seen(p, prec)).collect();
        let mut worst = 0.0f64;
        for (line, (u, v)) in lines.iter().zip(&cases) {
            let mut words = line.split_whitespace();
            assert_eq!(words.next(), Some(map), "{line}");
            let got: Vec<f64> = words.map(|w| w.parse::<f64>().unwrap()).collect();
            assert!(
                got.iter().all(|x| x.is_finite()),
                "{map} {prec} u={u} v={v}: non-finite {line}"
            );
            let want = reference(reference_of, &ps, &as_seen(u, prec), &as_seen(v, prec));
            assert_eq!(got.len(), want.len(), "{line}");
            for (g, w) in got.iter().zip(&want) {
                let err = (f(*g) - w).abs().to_f64() / extent / unit;
                worst = worst.max(err);
                assert!(
                    err <= 16.0,
                    "{map} {prec} u={u} v={v}: {g} vs {w:.20} is {err:.1} units of roundoff"
                );
            }
        }
        println!("{map} {args:?} {params:?} {prec}: max error {worst:.2} units of roundoff");
    }
}

#[test]
fn disks_agree_with_independent_mpfr() {
    check("disk", &[], 1.0);
    check("concentric-disk", &[], 1.0);
}

#[test]
fn spherical_warps_agree_with_independent_mpfr() {
    check("hemisphere", &[], 1.0);
    check("sphere", &[], 1.0);
    for k in ["0", "1", "1000", "1e6"] {
        check("phong", &[k], 1.0);
    }
}

#[test]
fn planar_triangle_agrees_with_independent_mpfr() {
    check(
        "planar-triangle",
        &["0", "0", "0", "1", "0", "0", "0.25", "1", "0"],
        1.0,
    );
    check(
        "planar-triangle",
        &["1", "2", "3", "-2", "0.5", "1", "0.5", "-1", "2"],
        3.0,
    );
}

#[test]
fn bad_lines_get_an_error_line_and_a_failing_status() {
    let input = "# comment\n\nhemisphere 0.5 0.5\nphong -1 0.5 0.5\nnope 1 2\nhemisphere 2 0.5\ndisk x 0.5\n\
                 planar-triangle 0 0 0 1 1 1 2 2 2 0.5 0.5\nsphere 0.5\n";
    let (out, ok) = run_eval(&[], input);
    assert!(!ok);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 7, "{out}");
    assert!(lines[0].starts_with("hemisphere ") && !lines[0].contains("error"));
    for l in &lines[1..] {
        assert!(l.contains(" error: "), "{l}");
    }
}

/// Runs `areawarp eval` on raw bytes: (stdout, exit code).
fn run_eval_bytes(args: &[&str], input: &[u8]) -> (String, Option<i32>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_areawarp"))
        .arg("eval")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("run areawarp");
    feed(&mut child, input);
    let out = child.wait_with_output().unwrap();
    (String::from_utf8(out.stdout).unwrap(), out.status.code())
}

#[test]
fn a_line_of_invalid_utf8_is_one_bad_line() {
    // Line 2 has a stray 0xFF inside its numbers, line 4 is Latin-1 (é) in
    // a comment-less word, line 5 starts with an invalid byte; the lines
    // after each are still evaluated, CRLF endings are accepted.
    let mut input = Vec::new();
    input.extend_from_slice(b"hemisphere 0.25 0.5\n");
    input.extend_from_slice(b"sphere 0.5 \xFF0.5\n");
    input.extend_from_slice(b"disk 0.5 0\r\n");
    input.extend_from_slice(b"caf\xE9 1 2\n");
    input.extend_from_slice(b"\x80\n");
    input.extend_from_slice(b"concentric-disk 1 0.5");
    let (out, code) = run_eval_bytes(&["--precision", "f64"], &input);
    assert_eq!(code, Some(1), "a bad line fails the run at its end: {out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 6, "{out}");
    assert!(lines[0].starts_with("hemisphere ") && !lines[0].contains("error"));
    assert_eq!(
        lines[1],
        "sphere error: line 2 is not valid UTF-8 (byte 0xFF at column 12)"
    );
    assert!(lines[2].starts_with("disk ") && !lines[2].contains("error"));
    assert_eq!(
        lines[3],
        "caf\u{FFFD} error: line 4 is not valid UTF-8 (byte 0xE9 at column 4)"
    );
    assert_eq!(
        lines[4],
        "\u{FFFD} error: line 5 is not valid UTF-8 (byte 0x80 at column 1)"
    );
    assert!(lines[5].starts_with("concentric-disk ") && !lines[5].contains("error"));
    // Valid input alone still succeeds.
    let (_, code) = run_eval_bytes(&[], b"disk 0.5 0\r\nsphere 0 0\n");
    assert_eq!(code, Some(0));
}

#[test]
fn inverse_round_trips_through_the_cli() {
    let (out, ok) = run_eval(&["--precision", "f64"], "sphere 0.25 0.75\ndisk 0.3 0.6\n");
    assert!(ok);
    let mut inv = String::new();
    for line in out.lines() {
        inv += line;
        inv.push('\n');
    }
    let (back, ok) = run_eval(&["--inverse"], &inv);
    assert!(ok, "{back}");
    let expect = [(0.25, 0.75), (0.3, 0.6)];
    for (line, (u, v)) in back.lines().zip(expect) {
        let w: Vec<f64> = line
            .split_whitespace()
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        assert!(
            (w[0] - u).abs() < 1e-15 && (w[1] - v).abs() < 1e-15,
            "{line}"
        );
    }
}

#[test]
fn mpfr_output_round_trips_at_its_precision() {
    let (out, ok) = run_eval(&["--precision", "mpfr:256"], "disk 0.5 0.125\n");
    assert!(ok);
    let w: Vec<&str> = out.split_whitespace().collect();
    let x = Float::with_val(PREC, Float::parse(w[1]).unwrap());
    let want = reference("disk", &[], &f(0.5), &f(0.125));
    assert!((x - &want[0]).abs() < Float::with_val(PREC, Float::i_exp(1, -250)));
}

fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect()
}

#[test]
fn solid_angle_maps_through_the_cli() {
    let tri = "spherical-triangle 1 0 0 0 1 0 0 0 1";
    let rect = "spherical-rectangle -1 -1 1 2 0 0 0 3 0 0 0 0";
    let poly = "projected-polygon 4 1 0 0.2 0 1 0.5 -1 0 0.2 0 -1 0.5";
    for variant in ["robust", "literal"] {
        let input = format!("{tri} 0.3 0.7\n{tri} 0 0\n{tri} 1 1\n{rect} 0.3 0.7\n{rect} 1 0\n");
        let (out, ok) = run_eval(&["--variant", variant], &input);
        assert!(ok, "{variant}: {out}");
        let lines: Vec<&str> = out.lines().collect();
        for l in &lines[..3] {
            let p = numbers(l);
            assert!(
                ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs() < 1e-15,
                "{l}"
            );
            assert!(p.iter().all(|x| *x >= -1e-16), "{l}: outside the octant");
        }
        for l in &lines[3..] {
            let p = numbers(l);
            assert_eq!(p.len(), 6, "{l}");
            assert!(
                (p[2] - 1.0).abs() < 1e-15,
                "{l}: point off the rectangle's plane z = 1"
            );
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            for i in 0..3 {
                assert!(
                    (p[3 + i] - p[i] / r).abs() < 1e-15,
                    "{l}: direction does not point at the point"
                );
            }
        }
        // The forward output pipes straight into --inverse.
        let back_in: String = lines
            .iter()
            .zip([tri, tri, tri, rect, rect])
            .map(|(l, head)| {
                format!(
                    "{head} {}\n",
                    l.split_whitespace().skip(1).collect::<Vec<_>>().join(" ")
                )
            })
            .collect();
        let (back, ok) = run_eval(&["--variant", variant, "--inverse"], &back_in);
        assert!(ok, "{variant}: {back}");
        let uv: Vec<Vec<f64>> = back.lines().map(numbers).collect();
        assert!(
            (uv[0][0] - 0.3).abs() < 1e-12 && (uv[0][1] - 0.7).abs() < 1e-12,
            "{back}"
        );
        assert!(
            (uv[3][0] - 0.3).abs() < 1e-12 && (uv[3][1] - 0.7).abs() < 1e-12,
            "{back}"
        );
    }
    for newton in [None, Some("0"), Some("2")] {
        let mut args = vec![];
        if let Some(k) = newton {
            args = vec!["--newton", k];
        }
        let (out, ok) = run_eval(&args, &format!("{poly} 0.3 0.7\n{poly} 0 0\n{poly} 1 1\n"));
        assert!(ok, "{out}");
        for l in out.lines() {
            let p = numbers(l);
            assert!(
                ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs() < 1e-14,
                "{l}"
            );
            assert!(p[2] >= 0.0, "{l}");
        }
    }
    let (out, ok) = run_eval(
        &[],
        "spherical-triangle 1 0 0 2 0 0 0 0 1 0.5 0.5\nprojected-polygon 2 1 0 0 0 1 0 0.5 0.5\n",
    );
    assert!(!ok);
    assert!(out.lines().all(|l| l.contains(" error: ")), "{out}");
}

/// `--precision auto:TOL`: each light evaluated the cheapest way predicted
/// to meet the tolerance; the issue-10 rectangle 1e-90 above its plane is
/// served in f64 (f32 cannot hold its observer), in f32 at 1e-12 above it.
#[test]
fn eval_auto_precision() {
    let input = "spherical-triangle 1 0.1 0 0.2 1 0.1 0 0.3 1 0.3 0.7\n\
                 spherical-rectangle 0 0 0 1 0 0 0 1 0 3 2 1e-90 0.5 0.5\n\
                 hemisphere 0.25 0.5\n";
    let (out, ok) = run_eval(&["--precision", "auto:1e-5"], input);
    assert!(ok, "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].contains("# f32 robust"), "{out}");
    assert_eq!(lines[0].split_whitespace().nth(4), Some("#"), "{out}");
    assert!(lines[1].contains("# f64 robust"), "{out}");
    assert!(!lines[1].contains("NaN"), "{out}");
    assert!(lines[2].ends_with("# f64"), "{out}");
    let (out, ok) = run_eval(&["--precision", "auto:1e-12"], input);
    assert!(
        ok && out.lines().next().unwrap().contains("# f64 robust"),
        "{out}"
    );
    let (out, ok) = run_eval(
        &["--precision", "f32"],
        "spherical-rectangle 0 0 0 1 0 0 0 1 0 3 2 1e-12 0.5 0.5\n",
    );
    assert!(ok && !out.contains("NaN"), "{out}");
    let (out, ok) = run_eval(
        &["--precision", "f32"],
        "spherical-rectangle 0 0 0 1 0 0 0 1 0 3 2 1e-38 0.5 0.5\n",
    );
    assert!(!ok && out.contains("not representable"), "{out}");
    let (_, ok) = run_eval(&["--precision", "auto:0"], input);
    assert!(!ok);
}

#[test]
fn new_warps_agree_with_independent_mpfr() {
    for c in ["0.5", "0", "-1", "0.999999"] {
        check("uniform-cone", &[c], 1.0);
    }
    for k in ["0.00000001", "0.0001", "1", "400", "1000000"] {
        check("von-mises-fisher", &[k], 1.0);
    }
    for a in ["0.0001", "0.3", "1", "3"] {
        check("ggx", &[a], 1.0);
        check("beckmann", &[a], 1.0);
    }
    for w in [
        ["1", "1", "1", "1"],
        ["0.1", "2", "0.7", "3"],
        ["0", "1", "1", "0"],
    ] {
        check("bilinear", &w, 1.0);
    }
    check("tent", &[], 1.0);
    check("std-normal", &[], 16.0);
    check_with(
        "planar-triangle",
        "planar-triangle-fold",
        &["--variant", "fold"],
        &["1", "2", "3", "-2", "0.5", "1", "0.5", "-1", "2"],
        3.0,
    );
}

/// The maps without an independent formula here (frames built from the
/// parameters): properties of their output, and the inverse through the CLI.
#[test]
fn sphere_light_and_lune_through_the_cli() {
    let light = "sphere-light 0.3 -1.2 2 0.7 0.1 0.2 -0.3";
    let lune = "spherical-lune 0.3 0.8 -0.2 -0.6 0.1 0.7";
    let mut input = String::new();
    for u in UV {
        for v in UV {
            input += &format!("{light} {u} {v}\n{lune} {u} {v}\n");
        }
    }
    let (out, ok) = run_eval(&[], &input);
    assert!(ok, "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2 * UV.len() * UV.len());
    let (c, o) = ([0.3, -1.2, 2.0], [0.1, 0.2, -0.3]);
    let n = |x: [f64; 3]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    let (n1, n2) = ([0.3, 0.8, -0.2], [-0.6, 0.1, 0.7]);
    for pair in lines.chunks(2) {
        let p = numbers(pair[0]);
        assert_eq!(p.len(), 6, "{}", pair[0]);
        let off = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        assert!(
            (n(off) - 0.7).abs() < 1e-14,
            "{}: not on the sphere",
            pair[0]
        );
        let to_p = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
        let dist = n(to_p);
        for i in 0..3 {
            assert!((to_p[i] / dist - p[3 + i]).abs() < 1e-14, "{}", pair[0]);
        }
        let q = numbers(pair[1]);
        assert!((n([q[0], q[1], q[2]]) - 1.0).abs() < 1e-15, "{}", pair[1]);
        let d1 = q[0] * n1[0] + q[1] * n1[1] + q[2] * n1[2];
        let d2 = q[0] * n2[0] + q[1] * n2[1] + q[2] * n2[2];
        assert!(
            d1 >= -1e-15 && d2 >= -1e-15,
            "{}: outside the lune",
            pair[1]
        );
    }
    // Round trips: the light through its printed point and direction, the
    // lune through its direction.
    let (out, ok) = run_eval(&[], &format!("{light} 0.3 0.7\n{lune} 0.3 0.7\n"));
    assert!(ok, "{out}");
    let back_in: String = out
        .lines()
        .zip([light, lune])
        .map(|(l, head)| {
            format!(
                "{head} {}\n",
                l.split_whitespace().skip(1).collect::<Vec<_>>().join(" ")
            )
        })
        .collect();
    let (back, ok) = run_eval(&["--inverse"], &back_in);
    assert!(ok, "{back}");
    for l in back.lines() {
        let uv = numbers(l);
        assert!(
            (uv[0] - 0.3).abs() < 1e-12 && (uv[1] - 0.7).abs() < 1e-12,
            "{l}"
        );
    }
    // Inside the sphere, parallel normals: error lines and a failing status.
    let (out, ok) = run_eval(
        &[],
        "sphere-light 0 0 0 1 0 0 0.5 0.5 0.5\nspherical-lune 0 0 1 0 0 2 0.5 0.5\n",
    );
    assert!(!ok);
    assert!(out.lines().all(|l| l.contains(" error: ")), "{out}");
    assert!(out.contains("outside the sphere"), "{out}");
}

#[test]
fn new_warps_invert_through_the_cli() {
    let heads = [
        "uniform-cone 0.25",
        "von-mises-fisher 10",
        "ggx 0.1",
        "beckmann 0.1",
        "bilinear 0.1 2 0.7 3",
        "tent",
        "std-normal",
    ];
    let input: String = heads.iter().map(|h| format!("{h} 0.3 0.7\n")).collect();
    let (out, ok) = run_eval(&[], &input);
    assert!(ok, "{out}");
    let back_in: String = out
        .lines()
        .zip(heads)
        .map(|(l, head)| {
            format!(
                "{head} {}\n",
                l.split_whitespace()
                    .skip(heads_len(head))
                    .collect::<Vec<_>>()
                    .join(" ")
            )
        })
        .collect();
    let (back, ok) = run_eval(&["--inverse"], &back_in);
    assert!(ok, "{back}");
    for l in back.lines() {
        let uv = numbers(l);
        assert!(
            (uv[0] - 0.3).abs() < 1e-13 && (uv[1] - 0.7).abs() < 1e-13,
            "{l}"
        );
    }
    let tri = "planar-triangle 1 2 3 -2 0.5 1 0.5 -1 2";
    let (out, ok) = run_eval(&["--variant", "fold"], &format!("{tri} 0.3 0.7\n"));
    assert!(ok, "{out}");
    let pt = out.split_whitespace().skip(1).collect::<Vec<_>>().join(" ");
    let (back, ok) = run_eval(
        &["--variant", "fold", "--inverse"],
        &format!("{tri} {pt}\n"),
    );
    assert!(ok, "{back}");
    let uv = numbers(back.lines().next().unwrap());
    assert!(
        (uv[0] - 0.3).abs() < 1e-14 && (uv[1] - 0.7).abs() < 1e-14,
        "{back}"
    );
}

/// The output line starts with the map's name only (parameters are not echoed).
fn heads_len(_head: &str) -> usize {
    1
}

/// `--variant derived` and `--variant tabulated:TOL`: the warps derived from
/// φ and a weight by quadrature, and with tabulated inverses, answer the same
/// lines as the closed forms, within f64 roundoff (derived) and within the
/// tolerance times |∂φ| ≤ 2π (tabulated); `--inverse` inverts them.
#[test]
fn derived_and_tabulated_variants_through_the_cli() {
    let lines = "uniform-cone 0.5 0.3 0.7\nggx 0.5 0.3 0.7\nbeckmann 0.5 0.9 0.1\n\
                 von-mises-fisher 10 0.3 0.7\nphong 10 0.3 0.7\nhemisphere 0.3 0.7\n\
                 sphere 0.999999 0.25\n";
    let (closed, ok) = run_eval(&["--variant", "closed"], lines);
    assert!(ok, "{closed}");
    for (variant, bound) in [("derived", 1e-14), ("tabulated:1e-9", 8e-9)] {
        let (out, ok) = run_eval(&["--variant", variant], lines);
        assert!(ok, "{out}");
        assert_eq!(out.lines().count(), lines.lines().count(), "{out}");
        for (a, b) in out.lines().zip(closed.lines()) {
            assert_eq!(a.split(' ').next(), b.split(' ').next());
            let (x, y) = (numbers(a), numbers(b));
            assert_eq!(x.len(), 3, "{a}");
            let d = x
                .iter()
                .zip(&y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(d <= bound, "{variant}: {a} vs {b}: {d:e}");
        }
        // Round trip through the same variant.
        let back_in: String = out
            .lines()
            .zip(lines.lines())
            .map(|(o, l)| {
                let words: Vec<&str> = l.split_whitespace().collect();
                let params = &words[..words.len() - 2];
                let point: Vec<&str> = o.split_whitespace().skip(1).collect();
                format!("{} {}\n", params.join(" "), point.join(" "))
            })
            .collect();
        let (back, ok) = run_eval(&["--variant", variant, "--inverse"], &back_in);
        assert!(ok, "{back}");
        for (b, l) in back.lines().zip(lines.lines()) {
            let uv = numbers(b);
            let w: Vec<f64> = numbers(l);
            let (u, v) = (w[w.len() - 2], w[w.len() - 1]);
            assert!(
                (uv[0] - u).abs() < 1e-9 && (uv[1] - v).abs() < 1e-9,
                "{variant}: {b} for {l}"
            );
        }
    }
    // A map without a derived variant, and a tolerance f32 cannot hold, are
    // error lines; a tolerance that is not positive is refused.
    let (out, ok) = run_eval(&["--variant", "derived"], "disk 0.3 0.7\n");
    assert!(
        !ok && out.starts_with("disk error:") && out.contains("no derived variant for disk"),
        "{out}"
    );
    let (out, ok) = run_eval(
        &["--variant", "tabulated:1e-9", "--precision", "f32"],
        "ggx 0.5 0.3 0.7\n",
    );
    assert!(!ok && out.starts_with("ggx error:"), "{out}");
    let (out, ok) = run_eval(
        &["--variant", "tabulated:1e-4", "--precision", "f32"],
        "ggx 0.5 0.3 0.7\n",
    );
    assert!(ok && numbers(&out).len() == 3, "{out}");
    // (No input: the program exits before reading it.)
    let (_, ok) = run_eval(&["--variant", "tabulated:0"], "");
    assert!(!ok);
}
