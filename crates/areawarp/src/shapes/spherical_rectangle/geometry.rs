//! The rectangle as the observer sees it: validation of the input, the
//! orthonormal frame `(x̂, ŷ, ẑ)` along the edges, and the local coordinates
//! `[x₀, x₁] × [y₀, y₁]` of the rectangle in the plane `z = −h` (observer at
//! the origin), scaled by a power of two to be O(1).

use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::turns::positive;
use crate::shapes::wide::{
    check_finite, larger, narrow3, plain_root_is_safe, scale_exponent, unit_vector, widen3,
};
use crate::vector::Vec3;

/// How far from perpendicular the edges may be, in units of roundoff of the
/// precision the data were given in: `|cos ∠(e_x, e_y)| ≤ 64 · 2^-p`.
pub(super) const PERPENDICULAR_ULPS: i64 = 64;

/// The validated rectangle, its frame and its local coordinates.
#[derive(Clone, Debug)]
pub(super) struct Geometry<T: Real> {
    /// The corner `s`.
    pub s: Vec3<T>,
    /// The edge `e_x` as given.
    pub ex: Vec3<T>,
    /// The edge `e_y` made exactly perpendicular to `e_x`:
    /// `e_y − (e_y·x̂) x̂` (equal to `e_y` for perpendicular input).
    pub ey: Vec3<T>,
    /// The observer `o`.
    pub o: Vec3<T>,
    /// `e_x / |e_x|`.
    pub xhat: Vec3<T>,
    /// The unit vector along the squared-up `e_y`.
    pub yhat: Vec3<T>,
    /// The unit normal of the plane on the observer's side: the rectangle
    /// lies at local `z = −h < 0`.
    pub zhat: Vec3<T>,
    /// Distance from the observer to the plane, in world units.
    pub h_world: T,
    /// `x₀ = (s − o)·x̂`, scaled.
    pub x0: T,
    /// `|e_x|`, scaled.
    pub lx: T,
    /// `y₀ = (s − o)·ŷ`, scaled.
    pub y0: T,
    /// `|e_y|` (squared up), scaled.
    pub ly: T,
    /// `1/ℓx` and `1/ℓy` (scaled): the frame's reciprocals times `2^exp`
    /// (exact), so that the map's constants need no division of their own.
    pub inv_lx: T,
    pub inv_ly: T,
    /// `h = −(s − o)·ẑ > 0`, scaled.
    pub h: T,
    /// The scale of the local lengths: local = world · 2^(−exp).
    pub exp: i32,
    /// The frame and the corner's local coordinates in `T::Wide`, for the
    /// inverses: an `f32` direction or point is measured in the frame of
    /// the exact `f32` shape (a rounded frame would tilt the plane by
    /// `2^-24`, more than a grazing observer's elevation).
    pub wide: WideFrame<T::Wide>,
}

/// The frame `(x̂, ŷ, ẑ)` and the corner's scaled local coordinates
/// `(x₀, y₀)` in the wide type.
#[derive(Clone, Debug)]
pub(super) struct WideFrame<W> {
    pub xhat: Vec3<W>,
    pub yhat: Vec3<W>,
    pub zhat: Vec3<W>,
    pub x0: W,
    pub y0: W,
}

/// `√(Σ xᵢ²)` by one square root when the sum of squares is neither tiny
/// nor huge, else by scaling with the largest magnitude first (no spurious
/// overflow or underflow). Cheaper than two `hypot` calls.
#[inline(always)]
pub(super) fn length<T: Real>(v: &[T]) -> T {
    let sum = v.iter().fold(T::zero(), |acc, x| acc + &x.square());
    if plain_root_is_safe(&sum) {
        return sum.sqrt();
    }
    let m = v.iter().fold(T::zero(), |acc, x| acc.max(&x.abs()));
    if !m.is_finite_above(&T::zero()) {
        return m;
    }
    let scaled = v
        .iter()
        .fold(T::zero(), |acc, x| acc + &(x.clone() / &m).square());
    scaled.sqrt() * &m
}

/// `|v|` by [`length`].
#[inline(always)]
pub(super) fn norm<T: Real>(v: &Vec3<T>) -> T {
    length(&[v.x.clone(), v.y.clone(), v.z.clone()])
}

fn non_finite(what: &'static str) -> WarpError {
    WarpError::NonFinite { what }
}

fn degenerate(what: &'static str) -> WarpError {
    WarpError::Degenerate { what }
}

/// The frame along the edges: `|e_x|`, `x̂`, the squared-up `e_y`, its
/// length, `ŷ` and `x̂ × ŷ`, and the reciprocals of the lengths.
struct Frame<T> {
    lx_world: T,
    inv_lx: T,
    inv_ly: T,
    xhat: Vec3<T>,
    ey_perp: Vec3<T>,
    ly_world: T,
    yhat: Vec3<T>,
    zplus: Vec3<T>,
}

/// `[d·ẑ₊, d·x̂, d·ŷ]` from the inputs' products, where [`Frame::direct`]
/// formed them (`None`: taken from the unit vectors). Returned beside the
/// frame rather than in it: as a field of [`Frame`] the one-shot solid
/// angle was 4–6 % slower (the compiler's layout, not examined further).
type Offsets<T> = Option<[T; 3]>;

/// An edge shorter than `1/max` (subnormal): its reciprocal overflows, and
/// no such rectangle has a density in area that the type can hold
/// (`docs/spherical-rectangle.md`, "Subnormal edges"): refused for that
/// reason, where the overflowed frame used to fail the perpendicularity
/// test.
fn subnormal_edge() -> WarpError {
    super::range::AREA_PDF
}

fn not_perpendicular() -> WarpError {
    WarpError::InvalidParameter {
        name: "ey",
        expected: "an edge perpendicular to ex (|cos| ≤ 64 units of roundoff)",
    }
}

impl<T: Real> Frame<T> {
    /// The frame of the finite edges `ex`, `ey` (`|cos ∠| ≤ tol`) when
    /// `|e_x|²`, `|e_y|²` and `|e_y⊥|²` are neither tiny nor huge (`None`
    /// otherwise: [`Frame::scaled`]). The projection `e_y⊥ = e_y −
    /// (e_x·e_y/|e_x|²) e_x` and the perpendicularity test
    /// `|e_x·e_y| ≤ tol |e_x| |e_y|` come from `e_x·e_y` directly, so that
    /// the second edge's root does not wait for the first's root and
    /// division (the constructor's longest chain of dependent operations);
    /// the test is taken in squares, `(e_x·e_y)²/|e_x|² ≤ tol² |e_y|²`, with
    /// the projection's own quotient (no root of `|e_y|²`; the left side is
    /// at most `|e_y|²`, so neither side overflows). `ℓy² = |e_y⊥|²` is
    /// `|e_y|² − k e_x·e_y` (equal in exact arithmetic, without
    /// cancellation: `k e_x·e_y ≤ tol²|e_y|²`), which does not wait for
    /// `e_y⊥`.
    ///
    /// With `products` (data that are values of a narrower type than `T`),
    /// `ℓy` is `|e_x × e_y|/ℓx` with `|e_x × e_y|² = |e_x|²|e_y|² −
    /// (e_x·e_y)²`, whose root does not wait for the division `k`, and the
    /// frame also returns the observer's offsets `[d·ẑ₊, d·x̂, d·ŷ]` (`d =
    /// s − o`, `ẑ₊ = x̂ × ŷ`) formed from the inputs' products, `d·(e_x ×
    /// e_y)/(ℓx ℓy)`, `(d·e_x)/ℓx` and `(d·e_y − k d·e_x)/ℓy`: none of them
    /// waits for the unit vectors, so the local coordinates are ready
    /// sooner (`docs/spherical-rectangle.md`, "The frame from the inputs'
    /// products"). They round differently from the unit vectors' dot
    /// products that the inverses take (`2^-53|d|` apart), which is far
    /// below data given in `f32`; for data in `T`'s own precision the
    /// offsets are the unit vectors' (`None`): there the difference
    /// showed in the round trip of an elongated or nearly grazed
    /// rectangle.
    #[inline(always)]
    fn direct(
        ex: &Vec3<T>,
        ey: &Vec3<T>,
        d: &Vec3<T>,
        tol: &T,
        products: bool,
    ) -> Option<Result<(Self, Offsets<T>), WarpError>> {
        let lx2 = ex.dot(ex);
        let ey2 = ey.dot(ey);
        if !plain_root_is_safe(&lx2) || !plain_root_is_safe(&ey2) {
            return None;
        }
        let ee = ex.dot(ey);
        let k = ee.clone() / &lx2;
        let kee = k.clone() * &ee;
        // tol²|e_y|² ≥ tol² u⁴ is normal.
        if kee > tol.square() * &ey2 {
            return Some(Err(not_perpendicular()));
        }
        let lx_world = lx2.sqrt();
        let ey_perp = ey.sub(&ex.scale(&k));
        let inv_lx = T::one() / &lx_world;
        let (inv_ly, ly_world) = if products {
            // |e_x × e_y|² = |e_x|²|e_y|² − (e_x·e_y)² (Lagrange), and
            // ℓy = |e_y⊥| = |e_x × e_y|/ℓx: no division waits for k.
            let n2 = lx2.clone() * &ey2 - &ee.square();
            if !plain_root_is_safe(&n2) {
                return None;
            }
            let root_n2 = n2.sqrt();
            (lx_world.clone() / &root_n2, root_n2 * &inv_lx)
        } else {
            // |e_y⊥|² = |e_y|² − (e_x·e_y)²/|e_x|².
            let ly2 = ey2 - &kee;
            if !plain_root_is_safe(&ly2) {
                return None;
            }
            let ly_world = ly2.sqrt();
            (T::one() / &ly_world, ly_world)
        };
        let xhat = ex.scale(&inv_lx);
        let yhat = ey_perp.scale(&inv_ly);
        // `h` as `d·(e_x × e_y)·(1/ℓx)·(1/ℓy)`, from the reciprocals at
        // hand: with `1/|e_x × e_y|` formed once instead (and `1/ℓy =
        // ℓx/|e_x × e_y|` as its product) the same accuracy figures, but the
        // `f32` one-shot solid angle measured 5 % slower (1.10 → 1.16 of
        // the textbook formula, 2026-11-30).
        let offsets = products.then(|| {
            let dx = d.dot(ex);
            [
                d.dot(&ex.cross(ey)) * &inv_lx * &inv_ly,
                dx.clone() * &inv_lx,
                (d.dot(ey) - &(k.clone() * &dx)) * &inv_ly,
            ]
        });
        Some(Ok((
            Frame {
                zplus: xhat.cross(&yhat),
                xhat,
                yhat,
                inv_lx,
                inv_ly,
                lx_world,
                ey_perp,
                ly_world,
            },
            offsets,
        )))
    }

    /// The frame of the finite edges `ex`, `ey` of any magnitude (lengths
    /// by [`norm`]), or why there is none.
    fn scaled(ex: &Vec3<T>, ey: &Vec3<T>, tol: &T) -> Result<Self, WarpError> {
        let one = T::one();
        let lx_world = norm(ex);
        if !positive(&lx_world) {
            return Err(degenerate("zero-length edge ex"));
        }
        if !lx_world.is_finite() {
            return Err(non_finite("length of edge ex"));
        }
        let ey_len = norm(ey);
        if !positive(&ey_len) {
            return Err(degenerate("zero-length edge ey"));
        }
        if !ey_len.is_finite() {
            return Err(non_finite("length of edge ey"));
        }
        let inv_lx = one.clone() / &lx_world;
        if !inv_lx.is_finite() {
            return Err(subnormal_edge());
        }
        let xhat = ex.scale(&inv_lx);
        let along = xhat.dot(ey);
        let cosine = along.clone() / &ey_len;
        if cosine.is_nan() || cosine.abs() > *tol {
            return Err(not_perpendicular());
        }
        let ey_perp = ey.sub(&xhat.scale(&along));
        let ly_world = norm(&ey_perp);
        let inv_ly = one / &ly_world;
        if !inv_ly.is_finite() {
            return Err(subnormal_edge());
        }
        let yhat = ey_perp.scale(&inv_ly);
        let zplus = xhat.cross(&yhat);
        Ok(Frame {
            lx_world,
            inv_lx,
            inv_ly,
            xhat,
            ey_perp,
            ly_world,
            yhat,
            zplus,
        })
    }
}

impl<T: Real> Geometry<T> {
    /// Validates the input and builds the frame; `bits` is the precision the
    /// data were given in (it sets the perpendicularity tolerance);
    /// `narrow_data` says that the data are values of a narrower type than
    /// `T` (an `f32` rectangle computed in `f64`), whose offsets may come
    /// from the inputs' products ([`Frame::direct`]).
    #[inline(always)]
    pub fn new(
        s: Vec3<T>,
        ex: Vec3<T>,
        ey: Vec3<T>,
        o: Vec3<T>,
        bits: u32,
        narrow_data: bool,
    ) -> Result<Self, WarpError> {
        check_finite([
            (&s, "corner s"),
            (&ex, "edge ex"),
            (&ey, "edge ey"),
            (&o, "observer o"),
        ])?;
        let tol = T::from_i64(PERPENDICULAR_ULPS) * &T::exp2i(-(bits.min(T::precision()) as i32));
        let d = s.sub(&o);
        let (
            Frame {
                lx_world,
                inv_lx,
                inv_ly,
                xhat,
                ey_perp,
                ly_world,
                yhat,
                zplus,
            },
            offsets,
        ) = match Frame::direct(&ex, &ey, &d, &tol, narrow_data) {
            Some(frame) => frame?,
            None => (Frame::scaled(&ex, &ey, &tol)?, None),
        };
        let [zc, x0w, y0w] = offsets.unwrap_or_else(|| [d.dot(&zplus), d.dot(&xhat), d.dot(&yhat)]);
        if zc.is_nan() {
            return Err(non_finite("observer offset"));
        }
        if zc == T::zero() {
            return Err(degenerate("observer on the rectangle's plane"));
        }
        let (zhat, h_world) = if zc > T::zero() {
            (zplus.neg(), zc)
        } else {
            (zplus, -zc)
        };
        // Scale the local lengths by a power of two (exactly) so that the
        // largest is in [1, 2): squares and products of four lengths then
        // neither overflow nor underflow in f32.
        // By comparisons ([`larger`]): a NaN here (from an overflowed
        // s − o) makes Ω NaN and the shape rejected whatever the scale.
        let m = [
            y0w.abs(),
            lx_world.clone(),
            ly_world.clone(),
            h_world.clone(),
        ]
        .into_iter()
        .fold(x0w.abs(), larger)
        .to_f64();
        // 0 for a zero or non-finite m (no scaling).
        let e = scale_exponent::<T>(m);
        let scale = T::exp2i(-e);
        let x0 = x0w * &scale;
        let y0 = y0w * &scale;
        Ok(Geometry {
            exp: e,
            wide: WideFrame {
                xhat: widen3(&xhat),
                yhat: widen3(&yhat),
                zhat: widen3(&zhat),
                x0: x0.widen(),
                y0: y0.widen(),
            },
            x0,
            lx: lx_world * &scale,
            y0,
            ly: ly_world * &scale,
            inv_lx: inv_lx * &T::exp2i(e),
            inv_ly: inv_ly * &T::exp2i(e),
            h: h_world.clone() * &scale,
            s,
            ex,
            ey: ey_perp,
            o,
            xhat,
            yhat,
            zhat,
            h_world,
        })
    }

    /// The geometry rounded to `T` (`self` computed in `T::Wide`).
    #[inline(always)]
    pub fn narrow<N: Real<Wide = T>>(&self) -> Geometry<N> {
        Geometry {
            s: narrow3(&self.s),
            ex: narrow3(&self.ex),
            ey: narrow3(&self.ey),
            o: narrow3(&self.o),
            xhat: narrow3(&self.xhat),
            yhat: narrow3(&self.yhat),
            zhat: narrow3(&self.zhat),
            h_world: N::narrow(&self.h_world),
            x0: N::narrow(&self.x0),
            lx: N::narrow(&self.lx),
            y0: N::narrow(&self.y0),
            ly: N::narrow(&self.ly),
            inv_lx: N::narrow(&self.inv_lx),
            inv_ly: N::narrow(&self.inv_ly),
            h: N::narrow(&self.h),
            exp: self.exp,
            wide: WideFrame {
                xhat: self.xhat.clone(),
                yhat: self.yhat.clone(),
                zhat: self.zhat.clone(),
                x0: self.x0.clone(),
                y0: self.y0.clone(),
            },
        }
    }

    /// The local coordinates `(x, y)` (scaled, observer at the origin) of
    /// the world point `p`, computed in `T::Wide` in the wide frame, either
    /// from the observer, `(p − o)·x̂`, or from the corner,
    /// `x₀ + (p − s)·x̂`, whichever has the smaller rounding error
    /// (`|p − o|` against `|s − o|_plane + |p − s|`): from the observer on an
    /// elongated rectangle whose corner is far away, from the corner when
    /// the observer is far from the rectangle.
    pub fn local_point(&self, p: &Vec3<T>) -> (T, T) {
        let f = &self.wide;
        let pw = widen3(p);
        let from_o = pw.sub(&widen3(&self.o));
        let from_s = pw.sub(&widen3(&self.s));
        let scale = <T::Wide as Real>::exp2i(-self.exp);
        let corner = f.x0.abs().max(&f.y0.abs()) / &scale;
        let (x, y) = if from_o.max_abs() <= corner + &from_s.max_abs() {
            (from_o.dot(&f.xhat) * &scale, from_o.dot(&f.yhat) * &scale)
        } else {
            (
                f.x0.clone() + &(from_s.dot(&f.xhat) * &scale),
                f.y0.clone() + &(from_s.dot(&f.yhat) * &scale),
            )
        };
        (T::narrow(&x), T::narrow(&y))
    }

    /// The world point `s + ξ e_x + η e_y`.
    pub fn point(&self, xi: &T, eta: &T) -> Vec3<T> {
        self.s.add(&self.ex.scale(xi)).add(&self.ey.scale(eta))
    }

    /// The world direction `a x̂ + b ŷ − c ẑ` of the local unit vector
    /// `(a, b, −c)`.
    pub fn direction(&self, a: &T, b: &T, c: &T) -> Vec3<T> {
        Vec3::new(
            a.clone() * &self.xhat.x + &(b.clone() * &self.yhat.x) - &(c.clone() * &self.zhat.x),
            a.clone() * &self.xhat.y + &(b.clone() * &self.yhat.y) - &(c.clone() * &self.zhat.y),
            a.clone() * &self.xhat.z + &(b.clone() * &self.yhat.z) - &(c.clone() * &self.zhat.z),
        )
    }

    /// The direction `w` in local components `(w·x̂, w·ŷ, −w·ẑ)` after
    /// normalization; `None` for a zero or non-finite vector.
    pub fn local_direction(&self, w: &Vec3<T>) -> Option<(T, T, T)> {
        if !w.is_finite() {
            return None;
        }
        // In the wide frame: for a grazing observer the elevation −w·ẑ is
        // far below 2^-p and must not be swamped by the frame's rounding.
        let f = &self.wide;
        let w = unit_vector(&widen3(w))?;
        Some((
            T::narrow(&w.dot(&f.xhat)),
            T::narrow(&w.dot(&f.yhat)),
            T::narrow(&-w.dot(&f.zhat)),
        ))
    }
}

/// `(far_x, far_y)`, the farthest local coordinates of the rectangle
/// `local = [x₀, y₀, ℓx, ℓy, h]`, and `(near_x, near_y)`, the nearest.
#[inline(always)]
pub(super) fn far_near<W: Real>(local: &[W; 5]) -> ((W, W), (W, W)) {
    let [x0, y0, lx, ly, _] = local;
    let (x1, y1) = (x0.clone() + lx, y0.clone() + ly);
    let zero = W::zero();
    (
        (x0.abs().max(&x1.abs()), y0.abs().max(&y1.abs())),
        (zero.clamp(x0, &x1), zero.clamp(y0, &y1)),
    )
}

/// Whether the area densities `h/(Ω r³)` at the nearest and the farthest
/// point of the rectangle `local = [x₀, y₀, ℓx, ℓy, h]` (local lengths,
/// world = local · 2^exp), computed in the wide type, lie within
/// `[16·tiny, max/16]` once rounded to `T` (`tiny` = [`Real::normal_floor`]):
/// normal numbers with margins that cover the sample's own roundings of
/// the same value, as the triangle's plane asks (`shapes/light_plane.rs`).
pub(super) fn area_density_exact<T: Real>(local: &[T::Wide; 5], omega: &T::Wide, exp: i32) -> bool {
    let h = &local[4];
    let ((far_x, far_y), (near_x, near_y)) = far_near(local);
    let scale = <T::Wide as Real>::exp2i(-2 * exp);
    let density = |x: &T::Wide, y: &T::Wide| {
        let r = (x.square() + &y.square() + &h.square()).sqrt();
        T::narrow(&(h.clone() / &(omega.clone() * &r * &r * &r) * &scale))
    };
    let (p_max, p_min) = (density(&near_x, &near_y), density(&far_x, &far_y));
    let sixteen = T::from_i64(16);
    p_max <= T::max_value() / &sixteen && p_min >= T::normal_floor() * &sixteen
}

/// A sufficient condition for [`area_density_exact`], by products alone
/// (no square root, no division): `true` only if the exact test passes.
/// Derivation: `docs/spherical-rectangle.md` (one-shot cost).
#[inline(always)]
pub(super) fn area_density_in_range<T: Real>(
    local: &[T::Wide; 5],
    omega: &T::Wide,
    exp: i32,
) -> bool {
    type W<T> = <T as Real>::Wide;
    let h = &local[4];
    let two = W::<T>::from_i64(2);
    if exp.abs() > 100 || !(*h <= two) {
        return false;
    }
    let ((far_x, far_y), _) = far_near(local);
    let scale = W::<T>::exp2i(-2 * exp);
    let max = T::max_value().widen();
    let tiny = W::<T>::from_i64(4) / &max;
    // The same floor in the wide type, for its intermediate results.
    let tiny_w = W::<T>::normal_floor();
    let h2 = h.square();
    // Ω r³ ≥ Ω h³ stays normal, and h/(Ω r³) ≤ 2/(Ω h³) finite.
    let no_underflow = omega.clone() * &h2 * h >= W::<T>::from_i64(64) * &tiny_w;
    // r_near ≥ h: p_max ≤ s/(Ω h²) < max/32 (the exact test asks max/16).
    let p_max_ok = omega.clone() * &h2 * &(max / &W::<T>::from_i64(32)) > scale;
    // r_far ≤ R = far_x + far_y + h: p_min ≥ h s/(Ω R³), and h/(Ω R³) normal.
    let r = far_x + &far_y + h;
    let omega_r3 = omega.clone() * &(r.square() * &r);
    // p_min ≥ 32·tiny (the exact test asks 16·tiny).
    let p_min_ok = h.clone() * &scale >= omega_r3.clone() * &W::<T>::from_i64(32) * &tiny
        && *h >= omega_r3 * &W::<T>::from_i64(64) * &tiny_w;
    no_underflow && p_max_ok && p_min_ok
}
