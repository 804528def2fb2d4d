//! `Real::exp2i` for `f32` and `f64` over every exponent from far below the
//! subnormal range to far above the largest finite power, with the exponent
//! hidden from the optimizer (the out-of-range cases run out of line at
//! run time, not constant-folded): exact powers of two where representable,
//! zero below (`2^(emin − p)` is a tie, rounded to even: zero), infinity above.

use areawarp::Real;
use std::hint::black_box;

/// `2^e` as the exact `f64` from its bits (normal or subnormal), 0 or ∞.
fn reference_f64(e: i32) -> f64 {
    if e > 1023 {
        f64::INFINITY
    } else if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else if e >= -1074 {
        f64::from_bits(1u64 << (e + 1074))
    } else {
        0.0
    }
}

fn reference_f32(e: i32) -> f32 {
    if e > 127 {
        f32::INFINITY
    } else if e >= -126 {
        f32::from_bits(((e + 127) as u32) << 23)
    } else if e >= -149 {
        f32::from_bits(1u32 << (e + 149))
    } else {
        0.0
    }
}

#[test]
fn exp2i_is_exact_over_the_whole_range() {
    for e in -2200..=2200 {
        let x = black_box(e);
        assert_eq!(f64::exp2i(x), reference_f64(e), "f64 2^{e}");
        assert_eq!(f32::exp2i(x), reference_f32(e), "f32 2^{e}");
    }
}
