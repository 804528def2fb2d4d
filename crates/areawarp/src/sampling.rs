//! Point sets on the unit square, for the maps to carry onto their shapes,
//! and a [`rand`] adapter that turns any `f32`/`f64` warp into a
//! [`Distribution`].
//!
//! An area-preserving map ψ keeps the quality of the points it is fed:
//! stratified points stay stratified (each stratum of the square becomes a
//! region of equal measure on the shape), and low-discrepancy points keep
//! their low discrepancy. The point sets here:
//!
//! | set | function | property |
//! |---|---|---|
//! | jittered (stratified) | [`jittered`], [`jittered_iter`] | exactly one point in each of the `nx × ny` cells, uniform within its cell |
//! | Hammersley | [`hammersley`], [`hammersley_point`] | `(i/n, φ₂(i))`; for `n = 2^m` a (0, m, 2)-net in base 2 |
//! | Sobol (first two dimensions) | [`Sobol2`], [`sobol_2d`] | a (0, 2)-sequence in base 2, optionally Owen-scrambled |
//! | Halton (bases 2, 3) | [`halton`] | an open sequence, extensible one point at a time |
//!
//! A *(0, m, 2)-net in base 2* is a set of `2^m` points with exactly one
//! point in every elementary interval
//! `[a 2^-k, (a + 1) 2^-k) × [b 2^-(m-k), (b + 1) 2^-(m-k))` of area `2^-m`;
//! in a *(0, 2)-sequence* every block of `2^m` consecutive points starting at
//! a multiple of `2^m` is such a net.
//!
//! All sets are generic over the scalar `T: Real` and lie in `[0, 1)²` in
//! `T`: the coordinates are dyadic numbers `k · 2^-q` with `q = min(p, 63)`
//! bits (`p` the precision of `T`), built exactly with [`Real::exp2i`] and
//! [`Real::from_i64`], or correctly rounded ratios kept below 1.
//!
//! [`WarpSampler`] implements [`rand::distr::Distribution`] for any warp over
//! `f32` or `f64`, drawing `u, v` uniform in `[0, 1)` with 24 (`f32`) or 53
//! (`f64`) random bits ([`rand::distr::StandardUniform`]).
//!
//! # Example
//! ```
//! use areawarp::sampling::{Sobol2, WarpSampler, jittered};
//! use areawarp::shapes::Hemisphere;
//! use areawarp::Warp;
//! use rand::distr::Distribution;
//! use rand::SeedableRng;
//!
//! let hemisphere = Hemisphere::<f64>::new();
//!
//! // Quasi-Monte Carlo: the first 1024 Sobol points carried onto the
//! // hemisphere (`sample_uv`: `Distribution::map` shadows `Warp::map` while
//! // both traits are in scope).
//! let mean_z: f64 = Sobol2::<f64>::new()
//!     .take(1024)
//!     .map(|(u, v)| hemisphere.sample_uv([u, v]).point.z)
//!     .sum::<f64>()
//!     / 1024.0;
//! assert!((mean_z - 0.5).abs() < 1e-3);
//!
//! // Stratified: one sample in each of 16 × 16 cells.
//! let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(7);
//! let cells: Vec<(f64, f64)> = jittered(16, 16, &mut rng);
//! assert_eq!(cells.len(), 256);
//!
//! // Monte Carlo through `rand`: the warp as a distribution of directions.
//! let sampler = WarpSampler::new(hemisphere);
//! let p = sampler.sample(&mut rng);
//! assert!(p.z >= 0.0);
//! ```

use crate::real::Real;
use crate::warp::Warp;
use core::marker::PhantomData;
use rand::Rng;
use rand::distr::{Distribution, StandardUniform};

/// The number `q = min(p, 63)` of fraction bits of the dyadic coordinates in `T`.
fn fraction_bits<T: Real>() -> u32 {
    T::precision().min(63)
}

/// `k · 2^-q`, exact in `T` for `k < 2^min(p, q)`, `q ≤ 63`.
fn dyadic<T: Real>(k: u64, q: u32) -> T {
    T::from_i64(k as i64) * &T::exp2i(-(q as i32))
}

/// The binary fraction `0.b₆₃ b₆₂ … b₀` of `x`, truncated to `T`'s
/// [`fraction_bits`] (so it stays below 1).
fn unit_from_bits<T: Real>(x: u64) -> T {
    let q = fraction_bits::<T>();
    dyadic(x >> (64 - q), q)
}

/// `x` if `x < 1`, else the largest number of `T` below 1, `1 − 2^-p`.
fn below_one<T: Real>(x: T) -> T {
    if x < T::one() {
        x
    } else {
        T::one() - &T::unit_roundoff()
    }
}

/// `⌈log₂ n⌉` for `n ≥ 1`.
fn ceil_log2(n: usize) -> u32 {
    if n <= 1 { 0 } else { (n - 1).ilog2() + 1 }
}

// ---------------------------------------------------------------------------
// Jittered (stratified) points.

/// One axis of a jittered grid: `n` strata and the fraction bits of the
/// offset within a stratum.
#[derive(Clone, Copy, Debug)]
struct Strata {
    n: usize,
    q: u32,
}

impl Strata {
    fn new<T: Real>(n: usize) -> Self {
        let q = fraction_bits::<T>().saturating_sub(ceil_log2(n)).max(1);
        Strata { n, q }
    }

    /// `(i + ξ)/n` with `ξ = (2k + 1) 2^-q`, `k` uniform on `q − 1` bits.
    fn point<T: Real, R: Rng + ?Sized>(&self, i: usize, rng: &mut R) -> T {
        let k = if self.q > 1 {
            rng.next_u64() >> (65 - self.q)
        } else {
            0
        };
        let xi = dyadic::<T>(2 * k + 1, self.q);
        (T::from_i64(i as i64) + &xi) / &T::from_i64(self.n as i64)
    }
}

/// Jittered (stratified) points: the iterator behind [`jittered`].
///
/// Cells are visited with `u` fastest: cell `(i, j)` (column `i < nx`, row
/// `j < ny`) is the `(j · nx + i)`-th item.
#[derive(Debug)]
pub struct Jittered<'r, T, R: ?Sized> {
    x: Strata,
    y: Strata,
    next: usize,
    len: usize,
    rng: &'r mut R,
    _t: PhantomData<fn() -> T>,
}

impl<T: Real, R: Rng + ?Sized> Iterator for Jittered<'_, T, R> {
    type Item = (T, T);

    fn next(&mut self) -> Option<(T, T)> {
        if self.next >= self.len {
            return None;
        }
        let (i, j) = (self.next % self.x.n, self.next / self.x.n);
        self.next += 1;
        let u = self.x.point(i, self.rng);
        let v = self.y.point(j, self.rng);
        Some((u, v))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.len - self.next;
        (left, Some(left))
    }
}

impl<T: Real, R: Rng + ?Sized> ExactSizeIterator for Jittered<'_, T, R> {}

/// Jittered (stratified) points, lazily: one uniform point in each cell
/// `[i/nx, (i+1)/nx) × [j/ny, (j+1)/ny)` of an `nx × ny` grid, `u` fastest.
///
/// Within its cell a coordinate is `(i + ξ)/n` with `ξ = (2k + 1) 2^-q`, `k`
/// uniform on `q − 1` random bits and `q = min(p, 63) − ⌈log₂ n⌉`: the
/// midpoints of `2^(q−1)` equal sub-intervals, a resolution of about `2^-p`
/// overall. The construction is exact up to the final division, whose
/// rounding cannot leave the cell: each coordinate lies *strictly* inside
/// its stratum, in `T` (for `n ≤ 2^(p−2)`; for absurdly fine grids the offset
/// degenerates to the cell centre).
///
/// `nx = 0` or `ny = 0` gives no points.
pub fn jittered_iter<T: Real, R: Rng + ?Sized>(
    nx: usize,
    ny: usize,
    rng: &mut R,
) -> Jittered<'_, T, R> {
    Jittered {
        x: Strata::new::<T>(nx),
        y: Strata::new::<T>(ny),
        next: 0,
        len: nx.saturating_mul(ny),
        rng,
        _t: PhantomData,
    }
}

/// The `nx · ny` jittered points of [`jittered_iter`], collected.
///
/// # Example
/// ```
/// use areawarp::sampling::jittered;
/// use rand::SeedableRng;
/// let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(1);
/// let pts: Vec<(f32, f32)> = jittered(4, 2, &mut rng);
/// // Cell (i, j) = (1, 1) is the 6th point.
/// let (u, v) = pts[5];
/// assert!((0.25..0.5).contains(&u) && (0.5..1.0).contains(&v));
/// ```
pub fn jittered<T: Real, R: Rng + ?Sized>(nx: usize, ny: usize, rng: &mut R) -> Vec<(T, T)> {
    jittered_iter(nx, ny, rng).collect()
}

// ---------------------------------------------------------------------------
// Radical inverses, Hammersley, Halton.

/// The van der Corput radical inverse in base 2, `φ₂(i) = Σ b_k 2^-(k+1)`
/// for `i = Σ b_k 2^k` (the bits of `i` mirrored about the binary point),
/// truncated to `min(p, 63)` bits: exact for `i < 2^min(p, 63)`, and `< 1`.
pub fn van_der_corput<T: Real>(i: u64) -> T {
    unit_from_bits(i.reverse_bits())
}

/// The radical inverse in base 3, `φ₃(i) = Σ d_k 3^-(k+1)` for
/// `i = Σ d_k 3^k`, correctly rounded for `i < 3^39` (digits beyond the 39th
/// change the value by less than `3^-39 ≈ 2^-61.8` and are ignored) and
/// kept below 1.
pub fn radical_inverse_3<T: Real>(i: u64) -> T {
    let mut rest = i;
    let mut num: i64 = 0;
    let mut den: i64 = 1;
    for _ in 0..39 {
        if rest == 0 {
            break;
        }
        num = num * 3 + (rest % 3) as i64;
        den *= 3;
        rest /= 3;
    }
    below_one(T::from_ratio(num, den))
}

/// The `i`-th point `(i/n, φ₂(i))` of the `n`-point Hammersley set
/// (`i < n`), in `[0, 1)²`.
pub fn hammersley_point<T: Real>(i: u64, n: u64) -> (T, T) {
    let u = if n == 0 {
        T::zero()
    } else {
        below_one(T::from_ratio(i as i64, n as i64))
    };
    (u, van_der_corput(i))
}

/// The `n`-point Hammersley set `(i/n, φ₂(i))`, `i = 0 … n−1`.
///
/// For `n = 2^m` it is a (0, m, 2)-net in base 2 (one point in each
/// elementary interval of area `2^-m`). Unlike a sequence, it cannot be
/// extended: every point depends on `n`.
///
/// # Example
/// ```
/// use areawarp::sampling::hammersley;
/// let h: Vec<(f64, f64)> = hammersley(4);
/// assert_eq!(h, vec![(0.0, 0.0), (0.25, 0.5), (0.5, 0.25), (0.75, 0.75)]);
/// ```
pub fn hammersley<T: Real>(n: usize) -> Vec<(T, T)> {
    (0..n as u64)
        .map(|i| hammersley_point(i, n as u64))
        .collect()
}

/// The first `n` points `(φ₂(i), φ₃(i))` of the Halton sequence in bases 2
/// and 3 (starting with `(0, 0)` at `i = 0`).
pub fn halton<T: Real>(n: usize) -> Vec<(T, T)> {
    (0..n as u64)
        .map(|i| (van_der_corput(i), radical_inverse_3(i)))
        .collect()
}

// ---------------------------------------------------------------------------
// Sobol.

/// Direction numbers of the second Sobol dimension, as 64-bit binary
/// fractions: primitive polynomial `x + 1`, `m₁ = 1`, hence
/// `v₁ = 1/2` and `v_k = v_{k−1} ⊕ (v_{k−1} ≫ 1)` (the generator matrix is
/// Pascal's triangle mod 2).
const SOBOL_DIM2: [u64; 64] = {
    let mut v = [0u64; 64];
    v[0] = 1 << 63;
    let mut k = 1;
    while k < 64 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    v
};

/// The two Sobol coordinates of index `i` as 64-bit binary fractions.
fn sobol_bits(i: u64) -> (u64, u64) {
    let mut y = 0u64;
    let mut rest = i;
    let mut k = 0;
    while rest != 0 {
        if rest & 1 == 1 {
            y ^= SOBOL_DIM2[k];
        }
        rest >>= 1;
        k += 1;
    }
    (i.reverse_bits(), y)
}

/// SplitMix64's finalizer: derives well-mixed per-dimension seeds.
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A hash-based nested uniform (Owen) scramble of a binary fraction.
///
/// On the bit-reversed value, every step (adding the seed, multiplying by an
/// odd number, `r ⊕= r · even`) changes bit `k` only as a function of bits
/// `0 … k`, and is a bijection. Reversed back, each digit of the fraction is
/// therefore flipped by a function of the digits before it (a nested
/// permutation of the elementary intervals), which preserves every
/// (0, m, 2)-net property while randomizing the points (after Laine and
/// Karras 2011 and Burley 2020).
fn owen_scramble(x: u64, seed: u64) -> u64 {
    let mut r = x.reverse_bits();
    r ^= r.wrapping_mul(0x3d20_adea_0b3f_5a8e);
    r = r.wrapping_add(seed);
    r = r.wrapping_mul((seed >> 32) | 1);
    r ^= r.wrapping_mul(0x0552_6c56_a7b4_c6f2);
    r ^= r.wrapping_mul(0x53a2_2864_9e37_79b8);
    r.reverse_bits()
}

/// The first two dimensions of the Sobol sequence: `u` is the van der Corput
/// sequence `φ₂(i)`, `v` uses the second dimension's direction numbers
/// (polynomial `x + 1`). Optionally Owen-scrambled.
///
/// Points are indexed directly (point `i` applies the generator matrices
/// to the bits of `i`), not in Gray-code order: both orders give the same
/// point set for every block `[k 2^m, (k+1) 2^m)`, and the direct order
/// makes `u` exactly the van der Corput sequence. Every such block is a
/// (0, m, 2)-net: one point in each elementary interval of area `2^-m`.
///
/// An iterator over `(u, v)` in `[0, 1)²` (endless: use `take`), with
/// random access through [`Sobol2::point`]; coordinates are truncated to
/// `min(p, 63)` bits (exact in `f64` for the unscrambled sequence).
///
/// # Example
/// ```
/// use areawarp::sampling::Sobol2;
/// let first: Vec<(f64, f64)> = Sobol2::new().take(4).collect();
/// assert_eq!(first, vec![(0.0, 0.0), (0.5, 0.5), (0.25, 0.75), (0.75, 0.25)]);
/// let scrambled = Sobol2::<f32>::scrambled(42);
/// let (u, v) = scrambled.point(3);
/// assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
/// ```
#[derive(Clone, Debug)]
pub struct Sobol2<T> {
    index: u64,
    seeds: Option<(u64, u64)>,
    _t: PhantomData<fn() -> T>,
}

impl<T: Real> Sobol2<T> {
    /// The unscrambled sequence, starting at `(0, 0)`.
    pub fn new() -> Self {
        Sobol2 {
            index: 0,
            seeds: None,
            _t: PhantomData,
        }
    }

    /// The sequence with an independent hash-based Owen scramble of each
    /// coordinate, determined by `seed` (different seeds give independent-
    /// looking randomizations; each keeps the net properties, and each
    /// point is uniform on the square over random seeds).
    pub fn scrambled(seed: u64) -> Self {
        let s1 = mix64(seed);
        let s2 = mix64(s1 ^ 0x6a09_e667_f3bc_c909);
        Sobol2 {
            index: 0,
            seeds: Some((s1, s2)),
            _t: PhantomData,
        }
    }

    /// The point of index `i` (independent of the iterator's position).
    pub fn point(&self, i: u64) -> (T, T) {
        let (mut x, mut y) = sobol_bits(i);
        if let Some((s1, s2)) = self.seeds {
            x = owen_scramble(x, s1);
            y = owen_scramble(y, s2);
        }
        (unit_from_bits(x), unit_from_bits(y))
    }

    /// The iterator started at index `i` (e.g. to continue a progressive
    /// render where it stopped).
    pub fn starting_at(mut self, i: u64) -> Self {
        self.index = i;
        self
    }
}

impl<T: Real> Default for Sobol2<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Iterator for Sobol2<T> {
    type Item = (T, T);

    fn next(&mut self) -> Option<(T, T)> {
        let p = self.point(self.index);
        self.index = self.index.wrapping_add(1);
        Some(p)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (usize::MAX, None)
    }
}

/// The first `n` points of the unscrambled [`Sobol2`] sequence.
pub fn sobol_2d<T: Real>(n: usize) -> Vec<(T, T)> {
    Sobol2::new().take(n).collect()
}

// ---------------------------------------------------------------------------
// rand adapter.

/// A warp as a [`rand::distr::Distribution`] of its points: each sample
/// draws `u` then `v` uniform in `[0, 1)` from the generator
/// ([`StandardUniform`]: 24 random bits for `f32`, 53 for `f64`) and returns
/// `warp.map(u, v)`.
///
/// `T` is the warp's scalar (`f32` or `f64`), normally inferred from the
/// warp.
///
/// # Example
/// ```
/// use areawarp::sampling::WarpSampler;
/// use areawarp::shapes::Sphere;
/// use rand::distr::Distribution;
/// use rand::SeedableRng;
///
/// let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(3);
/// let sphere = WarpSampler::new(Sphere::<f32>::new());
/// let directions: Vec<_> = sphere.sample_iter(&mut rng).take(8).collect();
/// assert!(directions.iter().all(|d| (d.norm() - 1.0).abs() < 1e-6));
/// ```
#[derive(Clone, Debug)]
pub struct WarpSampler<W, T = f64> {
    warp: W,
    _t: PhantomData<fn() -> T>,
}

impl<T: Real, W: Warp<T>> WarpSampler<W, T> {
    /// Wraps `warp`.
    pub fn new(warp: W) -> Self {
        WarpSampler {
            warp,
            _t: PhantomData,
        }
    }

    /// The wrapped warp (for its pdf, measure or inverse).
    pub fn warp(&self) -> &W {
        &self.warp
    }

    /// Unwraps the warp.
    pub fn into_inner(self) -> W {
        self.warp
    }
}

impl<T: Real, W: Warp<T>> Distribution<W::Point> for WarpSampler<W, T>
where
    StandardUniform: Distribution<T>,
{
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> W::Point {
        let u: T = StandardUniform.sample(rng);
        let v: T = StandardUniform.sample(rng);
        self.warp.map(&u, &v)
    }
}

#[cfg(test)]
mod tests;
