//! The rotation by a reduced angle `(π/2)·x`, `|x| ≤ 1/2`, for `f32` and
//! `f64` without a call to the library's sine and cosine
//! ([`Real::rotate_quarter_turns`]).
//!
//! The warps measure azimuths in turns and reduce them exactly by quarter
//! turns (`shapes::turns`), so the argument that reaches the sine and
//! cosine is already in `[−1/2, 1/2]` quarter turns, i.e. `[−π/4, π/4]`. A
//! library `sin_cos` would first round `(π/2)·x` (half a unit of the
//! angle's roundoff) and then redo a range reduction the argument does not
//! need. Here `sin((π/2)·x)/x` and `cos((π/2)·x)` are minimax polynomials
//! in `y = x²` of the exact `x`:
//!
//! - `f32`: evaluated in `f64` (relative error below `2^-37` and `2^-34`),
//!   and the rotated point `(a·c − b·s, a·s + b·c)` is formed in `f64` too:
//!   each coordinate is rounded to `f32` once, within `0.5 + 2^-10` units
//!   of the exact value over every `f32` input (exhaustive test below);
//! - `f64`: the leading terms `x·π/2` and `1 + C₁x²` kept exact by splits
//!   (see [`sin_cos_quarter_turns_f64`]): 0.81 and 0.88 units against 256
//!   bits, where `(x·π/2).sin_cos()` measures 1.81 and 1.03 (test below).
//!
//! Derivation and the coefficients' fit (Remez exchange on the relative
//! error): `docs/quarter-turns.md`.
//!
//! [`Real::rotate_quarter_turns`]: super::Real::rotate_quarter_turns

/// `sin((π/2)·x)/x` as a polynomial in `y = x²` on `y ∈ [0, 1/4]`, relative
/// error below `4.6·10⁻¹²` (≈ `2^-37.7`).
const SIN: [f64; 5] = [
    1.57079632678775,
    -0.6459640961024178,
    0.07969258184288427,
    -0.0046812606275760385,
    0.00015819507434731414,
];

/// `cos((π/2)·x)` as a polynomial in `y = x²` on `y ∈ [0, 1/4]`, relative
/// error below `5.7·10⁻¹¹` (≈ `2^-34`).
const COS: [f64; 5] = [
    0.9999999999439374,
    -1.2337005395647531,
    0.2536691825959931,
    -0.020859936027821775,
    0.0009033629762163813,
];

/// `(sin((π/2)·x), cos((π/2)·x))` in `f64` for `|x| ≤ 1/2`, to the
/// polynomials' accuracy (about `2^-34` relative, far below `f32`'s
/// roundoff). NaN gives NaN.
#[inline(always)]
pub(crate) fn sin_cos_quarter_turns_f32(x: f64) -> (f64, f64) {
    sin_cos_poly(x, &SIN, &COS)
}

/// `(x·S(x²), C(x²))` for the five-term polynomials `sin`, `cos` in `x²`,
/// by Estrin's scheme in `y²` (shorter dependency chains than Horner):
/// the `f32` kernels, in quarter turns ([`SIN`], [`COS`]) or in turns
/// ([`SIN_W`], [`COS_W`]), with the same operations in the same order.
#[inline(always)]
fn sin_cos_poly(x: f64, sin: &[f64; 5], cos: &[f64; 5]) -> (f64, f64) {
    let y = x * x;
    let y2 = y * y;
    let s = (sin[0] + sin[1] * y) + y2 * ((sin[2] + sin[3] * y) + y2 * sin[4]);
    let c = (cos[0] + cos[1] * y) + y2 * ((cos[2] + cos[3] * y) + y2 * cos[4]);
    (s * x, c)
}

/// `(a, b)` rotated by the angle of sine `s` and cosine `c` in `f64`, each
/// coordinate rounded to `f32` once.
#[inline(always)]
fn rotate_rounded(s: f64, c: f64, a: f64, b: f64) -> (f32, f32) {
    ((a * c - b * s) as f32, (a * s + b * c) as f32)
}

/// `(a, b)` rotated by `(π/2)·x`, `|x| ≤ 1/2`, each coordinate rounded to
/// `f32` once from `f64`.
#[inline(always)]
pub(crate) fn rotate_f32(x: f32, a: f32, b: f32) -> (f32, f32) {
    let (s, c) = sin_cos_quarter_turns_f32(x as f64);
    rotate_rounded(s, c, a as f64, b as f64)
}

/// [`SIN`] for the argument `w = x/4` (turns instead of quarter turns):
/// `sin(2πw)/w` as a polynomial in `w²`, the coefficients multiplied by
/// `4·16^k` (exact: powers of two).
const SIN_W: [f64; 5] = [
    SIN[0] * 4.0,
    SIN[1] * 64.0,
    SIN[2] * 1024.0,
    SIN[3] * 16384.0,
    SIN[4] * 262144.0,
];
/// [`COS`] for `w = x/4`: `cos(2πw)` as a polynomial in `w²`, the
/// coefficients multiplied by `16^k` (exact).
const COS_W: [f64; 5] = [
    COS[0],
    COS[1] * 16.0,
    COS[2] * 256.0,
    COS[3] * 4096.0,
    COS[4] * 65536.0,
];

/// `(r cos 2πv, r sin 2πv)` for `v ∈ [0, 1]` ([`Real::polar_turns`]),
/// the values of the generic route bit for bit (except the sign of a
/// zero: a zero coordinate is `+0` here, where the rotation of the generic
/// route can give `−0` at `r = 0` or for a negative `r`), with fewer
/// operations.
///
/// The generic route splits `4v` into the integer `q` nearest it and
/// `x = 4v − q`; here `v + 1.5·2^21` rounds `v` to a multiple `q/4` of ¼
/// (the spacing of `f32` in `[2^21, 2^22)`; the same rounding, ties to
/// even included, as `4v + 1.5·2^23`, scaled by ¼), so that
/// `w = v − q/4 = x/4` is exact without the product `4v`, and the
/// quadrant `q mod 4` is in the same low bits. The kernels of
/// [`sin_cos_quarter_turns_f32`] are evaluated in `w` with coefficients
/// scaled by powers of two ([`SIN_W`], [`COS_W`]): every intermediate is
/// the generic one times a power of two (no underflow: `w² ≥ 2^-300`
/// unless `w = 0`), so the sine and cosine are the same `f64` values.
/// The generic route rotates `(r cos(qπ/2), r sin(qπ/2))`, one of whose
/// coordinates is `±0`, by `(c, s)`: each coordinate is `±r·c` or `±r·s`
/// exactly before its rounding to `f32`. Here `r·c` and `r·s` are formed
/// in `f64` and rounded once each (rounding commutes with negation), and
/// the quarter turns are swaps and negations selected by the bits of `q`
/// with masks, without a branch (no table, no products by 0 and ±1;
/// `+ 0.0` turns `−0` into `+0`, as the rotation's sums do for `r > 0`).
/// NaN `v` gives NaN coordinates.
///
/// [`Real::polar_turns`]: super::Real::polar_turns
#[inline(always)]
pub(crate) fn polar_turns_f32(v: f32, r: f32) -> (f32, f32) {
    // 1.5·2^21.
    let rounder = (3u32 << 20) as f32;
    let shifted = v + rounder;
    let q = shifted.to_bits() & 3;
    let w = (v - (shifted - rounder)) as f64;
    let (s, c) = sin_cos_poly(w, &SIN_W, &COS_W);
    let r = r as f64;
    let (rc, rs) = ((r * c) as f32, (r * s) as f32);
    // i^q·(rc + i·rs): an odd q swaps and negates the first coordinate
    // (one quarter turn), q ≥ 2 negates both (a half turn). On the bits,
    // without a branch: q is as random as v, and a branch on it was
    // mispredicted half the time. A negation is a flip of the sign bit.
    const SIGN: u32 = 1 << 31;
    let odd = 0u32.wrapping_sub(q & 1);
    let (c_bits, s_bits) = (rc.to_bits(), rs.to_bits());
    let x = (c_bits & !odd) | ((s_bits ^ SIGN) & odd);
    let y = (s_bits & !odd) | (c_bits & odd);
    let half = (q & 2) << 30;
    (
        f32::from_bits(x ^ half) + 0.0,
        f32::from_bits(y ^ half) + 0.0,
    )
}

/// π/2 rounded to 24 bits (`f32`'s π/2): `xh·SIN64_HI` is exact for a
/// 26-bit `xh`.
const SIN64_HI: f64 = 1.5707963705062866;
/// π/2 − `SIN64_HI`, rounded (the rest, `≈ −2.7·10⁻²⁴`, is below `2^-77`).
const SIN64_LO: f64 = -4.3711390001862426e-08;
/// `(sin((π/2)·x)/x − π/2)/y` as a polynomial in `y = x²`; relative error
/// of `sin` below `3.4·10⁻¹⁸` (≈ `2^-58`).
const SIN64: [f64; 6] = [
    -0.6459640975062443,
    0.07969262624603957,
    -0.004681754132282415,
    0.00016044115029163048,
    -3.5986417543868745e-06,
    5.633721005314096e-08,
];
/// `(cos((π/2)·x) − 1)/y` as a polynomial in `y = x²`; relative error of
/// `cos` below `3.6·10⁻²⁰`.
const COS64: [f64; 7] = [
    -1.2337005501361697,
    0.2536695079010466,
    -0.020863480763308004,
    0.0009192602741467693,
    -2.5202036558199326e-05,
    4.710603581027675e-07,
    -6.320557308810856e-09,
];

/// `(sin((π/2)·x), cos((π/2)·x))` in `f64` for `|x| ≤ 1/2`, within about
/// one unit of roundoff (measured against 256 bits by the tests below:
/// better than the library route `(x·π/2).sin_cos()`, which first rounds
/// the angle).
///
/// With a Veltkamp split `x = xh + xl` (26-bit `xh`) and π/2 split into a
/// 24-bit `H` and the rest `L`: `sin = xh·H + ((xh·L + xl·π/2) + x·y·P(y))`
/// with `xh·H` exact, so that the leading term is not rounded before the
/// small corrections are added (one rounding of the sum); and
/// `cos = 1 + C₁x² + y²·R(y)` with `x² = xh² + xl·(xh + x)` (`xh²` exact),
/// `1 + C₁xh²` rounded with its exact error (Fast2Sum, `|C₁xh²| < 1`), and
/// that error added to the small tail.
#[inline(always)]
pub(crate) fn sin_cos_quarter_turns_f64(x: f64) -> (f64, f64) {
    let y = x * x;
    let y2 = y * y;
    let y4 = y2 * y2;
    // 2^27 + 1: Veltkamp's splitter for 53-bit significands.
    let t = x * 134_217_729.0;
    let xh = t - (t - x);
    let xl = x - xh;
    let ps =
        (SIN64[0] + SIN64[1] * y) + y2 * (SIN64[2] + SIN64[3] * y) + y4 * (SIN64[4] + SIN64[5] * y);
    let half_pi = SIN64_HI + SIN64_LO;
    let sin = xh * SIN64_HI + ((xh * SIN64_LO + xl * half_pi) + x * (y * ps));
    let lead = COS64[0] * (xh * xh);
    let w = 1.0 + lead;
    let lead_err = (1.0 - w) + lead;
    let r =
        (COS64[1] + COS64[2] * y) + y2 * (COS64[3] + COS64[4] * y) + y4 * (COS64[5] + COS64[6] * y);
    let cos = w + (lead_err + (COS64[0] * (xl * (xh + x)) + y2 * r));
    (sin, cos)
}

/// `(a, b)` rotated by `(π/2)·x`, `|x| ≤ 1/2`, in `f64` with the kernel
/// above.
#[inline(always)]
pub(crate) fn rotate_f64(x: f64, a: f64, b: f64) -> (f64, f64) {
    let (s, c) = sin_cos_quarter_turns_f64(x);
    (a * c - b * s, a * s + b * c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The error of `got` (an `f32`) against `want`, in units in the last
    /// place of `want` rounded to `f32` (its binade's spacing).
    fn ulps(got: f32, want: f64) -> f64 {
        if want == 0.0 {
            return if got == 0.0 { 0.0 } else { f64::INFINITY };
        }
        let w = want as f32;
        let ulp = (f32::from_bits(w.abs().to_bits() + 1) - w.abs()) as f64;
        (got as f64 - want).abs() / ulp
    }

    /// The worst errors (sine, cosine) of [`rotate_f32`] applied to `(1, 0)`
    /// over every `step`-th `f32` in `[0, 1/2]` (the kernels are odd and
    /// even), in units in the last place, against the `f64` reference
    /// `sin(π/2·x)`, whose own error (`≈ 2^-52` relative, mostly the
    /// rounding of the argument) is negligible at this scale.
    fn sweep(step: usize) -> (f64, f64) {
        let (mut worst_s, mut worst_c) = (0.0f64, 0.0f64);
        let hp = core::f64::consts::FRAC_PI_2;
        let top = 0.5f32.to_bits();
        for bits in (0..=top).step_by(step).chain([top]) {
            let x = f32::from_bits(bits);
            let (c, s) = rotate_f32(x, 1.0, 0.0);
            let angle = hp * x as f64;
            worst_s = worst_s.max(ulps(s, angle.sin()));
            worst_c = worst_c.max(ulps(c, angle.cos()));
        }
        (worst_s, worst_c)
    }

    /// A sample of the `f32` inputs: within `0.5 + 2^-8` units, i.e.
    /// correctly rounded but for a few near-halfway cases.
    #[test]
    fn quarter_turn_kernels_f32() {
        let (s, c) = sweep(997);
        assert!(s <= 0.5 + 1.0 / 256.0 && c <= 0.5 + 1.0 / 256.0, "{s} {c}");
    }

    /// Every `f32` input (about 10⁹; a minute in release):
    /// `cargo test --release -p areawarp --lib quarter_turn_kernels_all -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn quarter_turn_kernels_all_f32() {
        let (s, c) = sweep(1);
        println!("all f32 in [0, 1/2]: sin {s} ulps, cos {c} ulps");
        assert!(s <= 0.5 + 1.0 / 256.0 && c <= 0.5 + 1.0 / 256.0, "{s} {c}");
    }

    /// The generic route of `Real::polar_turns` for `f32`: `4v` split by
    /// `split_quarter_turns`, `r` times the quadrant's cosine and sine in
    /// `f32`, rotated by [`rotate_f32`].
    fn polar_generic(v: f32, r: f32) -> (f32, f32) {
        use crate::real::Real;
        const COS_Q: [f32; 4] = [1.0, 0.0, -1.0, 0.0];
        const SIN_Q: [f32; 4] = [0.0, 1.0, 0.0, -1.0];
        let four_v = v * 4.0;
        let (q, quadrant) = four_v.split_quarter_turns();
        rotate_f32(four_v - q, r * COS_Q[quadrant], r * SIN_Q[quadrant])
    }

    /// Every `step`-th `f32` in `[0, 1]` (and 1): [`polar_turns_f32`]
    /// returns the generic route's bits (radii 1 and 0.7).
    fn polar_matches_generic(step: usize) {
        for bits in (0..=1f32.to_bits()).step_by(step).chain([1f32.to_bits()]) {
            let v = f32::from_bits(bits);
            for r in [1.0f32, 0.7] {
                let (x, y) = polar_turns_f32(v, r);
                let (gx, gy) = polar_generic(v, r);
                assert!(
                    x.to_bits() == gx.to_bits() && y.to_bits() == gy.to_bits(),
                    "v = {v:e}, r = {r}: ({x:e}, {y:e}) vs ({gx:e}, {gy:e})"
                );
            }
            // At r = 0 both are zeros; here always +0.
            let (x, y) = polar_turns_f32(v, 0.0);
            let (gx, gy) = polar_generic(v, 0.0);
            assert!(
                x == gx && y == gy && x.to_bits() == 0 && y.to_bits() == 0,
                "v = {v:e}, r = 0: ({x:e}, {y:e}) vs ({gx:e}, {gy:e})"
            );
        }
        assert!(polar_turns_f32(f32::NAN, 1.0).0.is_nan());
    }

    #[test]
    fn polar_turns_f32_is_the_generic_route() {
        polar_matches_generic(4099);
    }

    /// Every `f32` in `[0, 1]` (about 10⁹; a minute in release):
    /// `cargo test --release -p areawarp --lib polar_turns_f32_all -- --ignored`.
    #[test]
    #[ignore]
    fn polar_turns_f32_all_is_the_generic_route() {
        polar_matches_generic(1);
    }

    /// The `f64` kernel against 256 bits on 200 000 random reduced
    /// arguments and the edges, next to the library route
    /// `(x·π/2).sin_cos()` it replaces (printed with `--nocapture`).
    #[cfg(feature = "mpfr")]
    #[test]
    fn quarter_turn_kernel_f64_vs_mpfr() {
        use crate::real::{Mpfr256, Real};
        type M = Mpfr256;
        let hp = M::pi() / M::from_i64(2);
        let ulps = |got: f64, want: &M| {
            let w = want.to_f64();
            if w == 0.0 {
                return if got == 0.0 { 0.0 } else { f64::INFINITY };
            }
            let e = (M::from_f64(got) - want).abs().to_f64();
            // The spacing of want's binade.
            e / (f64::from_bits(w.abs().to_bits() + 1) - w.abs())
        };
        let mut state: u64 = 12345;
        let mut xs = vec![0.0, 0.5, -0.5, 0.25, 1e-300, 2f64.powi(-30)];
        for _ in 0..200_000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            xs.push((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
        }
        let (mut poly, mut libm) = ([0.0f64; 2], [0.0f64; 2]);
        for x in xs {
            let (s_ref, c_ref) = (M::from_f64(x) * &hp).sin_cos();
            let (s, c) = sin_cos_quarter_turns_f64(x);
            poly[0] = poly[0].max(ulps(s, &s_ref));
            poly[1] = poly[1].max(ulps(c, &c_ref));
            let (s, c) = (x * core::f64::consts::FRAC_PI_2).sin_cos();
            libm[0] = libm[0].max(ulps(s, &s_ref));
            libm[1] = libm[1].max(ulps(c, &c_ref));
        }
        println!(
            "f64 quarter-turn kernel: sin {} ulps, cos {} ulps",
            poly[0], poly[1]
        );
        println!(
            "library (x·π/2).sin_cos(): sin {} ulps, cos {} ulps",
            libm[0], libm[1]
        );
        assert!(
            poly[0] <= libm[0].max(1.0) && poly[1] <= libm[1].max(1.0),
            "{poly:?} {libm:?}"
        );
    }
}
