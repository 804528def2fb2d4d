//! The rotation by a reduced angle `(π/2)·x`, `|x| ≤ 1/2`, for `f32`
//! without a call to `sincosf` ([`Real::rotate_quarter_turns`]).
//!
//! The warps measure azimuths in turns and reduce them exactly by quarter
//! turns (`shapes::turns`), so the argument that reaches the sine and
//! cosine is already in `[−1/2, 1/2]` quarter turns, i.e. `[−π/4, π/4]`. A
//! library `sincosf` would first round `(π/2)·x` to `f32` (half a unit of
//! the angle's roundoff) and then redo a range reduction the argument does
//! not need. Here `sin((π/2)·x)/x` and `cos((π/2)·x)` are minimax
//! polynomials in `y = x²` (relative error below `2^-37` and `2^-34`),
//! evaluated in `f64` from the exact `f64` value of `x`, and the rotated
//! point `(a·c − b·s, a·s + b·c)` is formed in `f64` too: each coordinate is
//! rounded to `f32` once, so it is within about half a unit of roundoff of
//! the exact value (the exhaustive test below measures the kernels over
//! every `f32` input). Derivation of the coefficients (Remez exchange on
//! the relative error): `docs/quarter-turns.md`.
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
    let y = x * x;
    // Estrin's scheme in y² (shorter dependency chains than Horner).
    let y2 = y * y;
    let s = (SIN[0] + SIN[1] * y) + y2 * ((SIN[2] + SIN[3] * y) + y2 * SIN[4]);
    let c = (COS[0] + COS[1] * y) + y2 * ((COS[2] + COS[3] * y) + y2 * COS[4]);
    (s * x, c)
}

/// `(a, b)` rotated by `(π/2)·x`, `|x| ≤ 1/2`, each coordinate rounded to
/// `f32` once from `f64`.
#[inline(always)]
pub(crate) fn rotate_f32(x: f32, a: f32, b: f32) -> (f32, f32) {
    let (s, c) = sin_cos_quarter_turns_f32(x as f64);
    let (a, b) = (a as f64, b as f64);
    ((a * c - b * s) as f32, (a * s + b * c) as f32)
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
}
