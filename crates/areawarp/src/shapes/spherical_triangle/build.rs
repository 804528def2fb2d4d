//! The triangle as the constructor sees it: validation and every constant
//! of the robust map, computed in the wide scalar `W = T::Wide` (`f64` for
//! `f32`) and rounded to `T` afterwards.
//!
//! Every decision (degenerate? nearly antipodal?) is taken in `W`, so an
//! `f32` triangle is accepted exactly when the `f64` constructor accepts the
//! same values; what `T` cannot hold (a solid angle or constant outside its
//! range) is rejected after rounding, with [`WarpError::Unrepresentable`].

use crate::error::WarpError;
use crate::real::Real;
use crate::shapes::turns::atan2_nonneg;
use crate::shapes::turns::positive;
use crate::shapes::wide::{check_finite, narrow3, unit_vector, widen3};
use crate::vector::Vec3;

/// `|v|²`.
#[inline]
pub(super) fn norm2<T: Real>(v: &Vec3<T>) -> T {
    v.dot(v)
}

/// The unit tangent `[y|x]` at the unit vector `x` pointing along the great
/// arc towards `y`, `|y − (x·y)x| = sin∠(x, y)` and its reciprocal (the
/// one division the normalization needs, shared with the caller), from the
/// chords at hand:
/// `minus = y − x`, `plus = y + x` and their squared lengths.
///
/// `y − (x·y)x` cancels when `y ≈ ±x`; it is computed as
/// `(y − x) + (|y − x|²/2)·x` when `|y − x| ≤ |y + x|` (`x·y ≥ 0`) and as
/// `(y + x) − (|y + x|²/2)·x` otherwise (identities for unit vectors, since
/// `1 − x·y = |y − x|²/2` and `1 + x·y = |y + x|²/2`): the differences are
/// exact or nearly so, and the result has full relative accuracy. The
/// chords are what the constructor has computed anyway (no dot product and
/// no chord is formed twice).
#[inline(always)]
pub(super) fn tangent<T: Real>(
    x: &Vec3<T>,
    (minus, q_minus): (&Vec3<T>, &T),
    (plus, q_plus): (&Vec3<T>, &T),
) -> Option<(Vec3<T>, T, T)> {
    let two = T::from_i64(2);
    let t = if q_minus <= q_plus {
        minus.add(&x.scale(&(q_minus.clone() / &two)))
    } else {
        plus.sub(&x.scale(&(q_plus.clone() / &two)))
    };
    let len = norm2(&t).sqrt();
    if !len.is_finite_above(&T::zero()) {
        return None;
    }
    let inv = T::one() / &len;
    Some((Vec3::new(t.x * &inv, t.y * &inv, t.z * &inv), len, inv))
}

/// The typed errors of the constructor.
pub(super) mod reject {
    use crate::error::WarpError;
    pub const ZERO_VERTEX: WarpError = WarpError::Degenerate {
        what: "zero vertex direction",
    };
    pub const COINCIDENT: WarpError = WarpError::Degenerate {
        what: "coincident vertices",
    };
    pub const ON_CIRCLE: WarpError = WarpError::Degenerate {
        what: "vertices on one great circle (or collinear)",
    };
    pub const ANTIPODAL: WarpError = WarpError::Degenerate {
        what: "nearly antipodal vertices: the great arc between them is not determined",
    };
    pub const UNDERFLOW: WarpError = WarpError::Degenerate {
        what: "solid angle underflows",
    };
    pub const OUT_OF_RANGE: WarpError = WarpError::Unrepresentable {
        what: "a constant of the spherical triangle's map (solid angle, density or a sub-triangle term) is outside the scalar type's range",
    };
}

/// How close to antipodal two vertices may be: `|X + Y| = 2 cos(∠XY/2)`
/// must exceed `64 · 2^(−p/2)` (`p` the wide type's precision; `≈ 5.8e-7`
/// in `f64`). Closer, the plane of the arc XY (normal `X × Y`, of length
/// `≈ |X + Y|`) is known only to `u/|X + Y|`, more than the on-shape
/// tolerance `2^(−p/2)` of [`Warp::inverse`](crate::warp::Warp::inverse): the map's samples and
/// the membership test would follow two different arcs.
fn antipodal_limit<W: Real>() -> W {
    W::from_i64(64) * &W::exp2i(-((W::precision() / 2) as i32))
}

/// The validated triangle in `W`: unit vertices, chords, orientation, the
/// arc AC and the constants shared by the map, the inverse and the recipe.
#[derive(Clone, Debug)]
pub(super) struct Core<W> {
    /// The unit vertices, chords and Ω of the validation.
    pub v: Validated<W>,
    /// det(A, B, C) > 0.
    pub ccw: bool,
    /// ±1: the sign of det(A, B, C).
    pub sign: W,
    /// [C|A] and sin b.
    pub c_perp: Vec3<W>,
    pub sin_b: W,
    /// `d = sin c sin α = |det| / sin b`, formed as `|det|·(1/sin b)` with
    /// the tangent's reciprocal (two roundings), and `1/d = sin b / |det|`
    /// (one rounding), of the anchor at A (the anchor at C forms its own
    /// from its tangent, [`Core::anchor`]).
    pub d: W,
    pub inv_d: W,
    /// `sin c cos α = (B − A)·[C|A]`.
    pub ka: W,
}

/// The triangle validated, with its solid angle: what
/// [`SphericalTriangle::solid_angle_of`](super::SphericalTriangle::solid_angle_of)
/// needs, and the first half of [`Core::from_validated`].
#[derive(Clone, Debug)]
pub(super) struct Validated<W> {
    pub a: Vec3<W>,
    pub b: Vec3<W>,
    pub c: Vec3<W>,
    pub ab: Vec3<W>,
    pub bc: Vec3<W>,
    pub ca: Vec3<W>,
    pub s_ca: Vec3<W>,
    pub q_ca: W,
    pub p_ca: W,
    /// `(|A − B|², A + B, |A + B|²)` and `(|C − B|², C + B, |C + B|²)`.
    pub at_b: [(W, Vec3<W>, W); 2],
    pub k1a: W,
    /// det(A, B, C) (its sign the orientation, its magnitude d's numerator).
    pub det: W,
    /// Ω (Van Oosterom–Strackee) and Ω/2, the arctangent itself (`2·(Ω/2)`
    /// and `(2·(Ω/2))/2` are exact: the map's `h = u·Ω/2` does not wait on
    /// two multiplications by 2 and ½ that cancel).
    pub omega: W,
    pub half_omega: W,
}

impl<W: Real> Validated<W> {
    /// Validates the (finite) vertex directions `a`, `b`, `c` and computes
    /// the solid angle.
    #[inline(always)]
    pub fn new(a: &Vec3<W>, b: &Vec3<W>, c: &Vec3<W>) -> Result<Self, WarpError> {
        let a = unit_vector(a).ok_or(reject::ZERO_VERTEX)?;
        let b = unit_vector(b).ok_or(reject::ZERO_VERTEX)?;
        let c = unit_vector(c).ok_or(reject::ZERO_VERTEX)?;
        let two = W::from_i64(2);
        let ab = b.sub(&a);
        let bc = c.sub(&b);
        let ca = a.sub(&c);
        let (q_ab, q_bc, q_ca) = (norm2(&ab), norm2(&bc), norm2(&ca));
        if q_ab == W::zero() || q_bc == W::zero() || q_ca == W::zero() {
            return Err(reject::COINCIDENT);
        }
        // det(A, B, C) = V·(e₁ × e₂) from the vertex V opposite the longest
        // chord (e₁, e₂ the two shortest chords): the cross product of short
        // difference vectors keeps relative accuracy for small triangles.
        // The criterion |det| ≤ 256·u·ℓ₁ℓ₂ compares squares: det² ≤ (256u)²ℓ₁²ℓ₂².
        // ℓ₁²ℓ₂², the product of the two shortest chords (for the criterion
        // below), is the smallest of the three pairwise products (rounding
        // is monotonic, so also after rounding): no selection, no branch.
        // (By comparisons: the chords are finite, `min`'s NaN handling
        // would cost a dozen instructions.)
        let smaller = |a: W, b: W| if b < a { b } else { a };
        let q12 = smaller(
            smaller(q_ab.clone() * &q_bc, q_bc.clone() * &q_ca),
            q_ca.clone() * &q_ab,
        );
        // The pair (X, Y) with the smallest |X + Y| (nearest to antipodal)
        // and the third vertex Z: det(A, B, C) is unchanged when one column
        // is added to another, so det = (X + Y)·(…) with the short, exactly
        // computed sum X + Y, accurate to u|X + Y| where the chords' form
        // cancels (an arc near π); and 1 + A·B + B·C + C·A =
        // |X + Y|²/2 + Z·(X + Y), two small accurate terms.
        let (s_ab, s_bc, s_ca) = (a.add(&b), b.add(&c), c.add(&a));
        let (p_ab, p_bc, p_ca) = (norm2(&s_ab), norm2(&s_bc), norm2(&s_ca));
        let k1a = p_ab.clone() / &two;
        let (sum, q_sum, third, pair) = if p_ca <= p_ab && p_ca <= p_bc {
            (s_ca.clone(), p_ca.clone(), &b, 0)
        } else if p_ab <= p_bc {
            (s_ab.clone(), p_ab.clone(), &c, 1)
        } else {
            (s_bc.clone(), p_bc.clone(), &a, 2)
        };
        let det = if q_sum < q12 {
            // (C + A)·(B × C) and (A + B)·(B × C) are det; for B + C the
            // sum takes C's column.
            match pair {
                0 | 1 => sum.dot(&b.cross(&c)),
                _ => a.dot(&b.cross(&sum)),
            }
        } else if q_bc >= q_ab && q_bc >= q_ca {
            a.dot(&ab.cross(&ca.neg()))
        } else if q_ca >= q_ab {
            b.dot(&bc.cross(&ab.neg()))
        } else {
            c.dot(&ca.cross(&bc.neg()))
        };
        let k = W::from_i64(256) * &W::unit_roundoff();
        // k² is a power of two: k²·(ℓ₁²ℓ₂²) rounds as (k²ℓ₁²)·ℓ₂² did.
        if det.is_nan() || det.square() <= k.square() * &q12 {
            return Err(reject::ON_CIRCLE);
        }
        // Nearly antipodal pairs.
        let limit = antipodal_limit::<W>().square();
        if q_sum <= limit {
            return Err(reject::ANTIPODAL);
        }
        let den = q_sum / &two + &third.dot(&sum);
        // Ω = 2 atan2(|det|, den), by atan(|det|/den) where that is exact
        // enough (see `atan2_nonneg`).
        let half_omega = atan2_nonneg(&det.abs(), &den);
        let omega = half_omega.clone() * &two;
        if !positive(&omega) {
            return Err(reject::UNDERFLOW);
        }
        Ok(Validated {
            a,
            b,
            c,
            ab,
            bc,
            ca,
            s_ca,
            q_ca,
            p_ca,
            at_b: [(q_ab, s_ab, p_ab), (q_bc, s_bc, p_bc)],
            k1a,
            det,
            omega,
            half_omega,
        })
    }
}

/// Where one end's anchor decides for both: `1/d ≤ max/16` and
/// `|A − B|², |C − B|² ≥ 64/max` (`max` the largest value of the target
/// type, in `W`). Inside, every constant of both anchors (`(1 + cos)/d`,
/// `k/d`, `4/|V − B|²`, `V − B`) and `d` itself are far inside the target
/// type's range, whichever end's rounding of `sin b` they take, so the
/// constructor's range checks cannot refuse the triangle for the end a
/// one-shot sample does not form; outside (tiny or extremely thin
/// triangles at the bottom of the type's range), the one-shot runs the
/// constructor's checks.
pub(super) struct OneEndBounds<W> {
    pub max_inv_d: W,
    pub min_chord2: W,
}

impl<W: Real> OneEndBounds<W> {
    /// The bounds for the target type `T` (`T::Wide = W`).
    #[inline(always)]
    pub fn of<T: Real<Wide = W>>() -> Self {
        let max = T::max_value().widen();
        OneEndBounds {
            min_chord2: W::from_i64(64) / &max,
            max_inv_d: max / W::from_i64(16),
        }
    }
}

impl<W: Real> Validated<W> {
    /// The unit tangent at V = A (`from_a`) or C along the arc AC towards
    /// the other end, `sin b` and `1/sin b` ([`tangent`] of the chords
    /// `±(A − C)` and `A + C`).
    #[inline(always)]
    pub fn tangent_at(&self, from_a: bool) -> Option<(Vec3<W>, W, W)> {
        let (x, minus) = if from_a {
            (&self.a, self.ca.neg())
        } else {
            (&self.c, self.ca.clone())
        };
        tangent(x, (&minus, &self.q_ca), (&self.s_ca, &self.p_ca))
    }

    /// The anchor at V = A (`from_a`) or C alone: the tangent at V and
    /// nothing of the other end (what one sample needs). The same values as
    /// [`Core::from_validated`] and [`Core::anchor`] compute for that end.
    /// `Some` only when the triangle is inside `bounds` ([`OneEndBounds`]):
    /// there `d = |det|/sin b` and every constant of the anchor are inside
    /// `T`'s range (the constructor's tests of them pass, and the sample
    /// need not repeat them: [`Anchor::narrow_in_bounds`]). `None` outside
    /// (or where the anchor cannot be formed): there only the constructor's
    /// tests of both ends decide.
    #[inline(always)]
    pub fn anchor_alone(&self, from_a: bool, bounds: &OneEndBounds<W>) -> Option<Anchor<W>> {
        if from_a {
            self.anchor_alone_at::<true>(bounds)
        } else {
            self.anchor_alone_at::<false>(bounds)
        }
    }

    /// [`Validated::anchor_alone`] compiled for one end: selecting the
    /// end's inputs without a branch was slower (the one-shot sample
    /// 113 → 125 ns in `f32`; `docs/spherical-triangle-one-shot.md`).
    #[inline(always)]
    fn anchor_alone_at<const FROM_A: bool>(&self, bounds: &OneEndBounds<W>) -> Option<Anchor<W>> {
        let (along, inv_d) = self.own_end(FROM_A).ok()?;
        // By comparisons: a NaN fails them.
        let inside = inv_d <= bounds.max_inv_d
            && self.at_b[0].0 >= bounds.min_chord2
            && self.at_b[1].0 >= bounds.min_chord2;
        let anchor = self.anchor_with(FROM_A, &along, &inv_d).ok()?;
        inside.then_some(anchor)
    }

    /// V's own tangent on the arc AC (V = A for `from_a`, else C) and
    /// `1/d = sin b/|det|` with that tangent's `sin b`: what the one-shot's
    /// anchor, and the built shape's at C, are made from.
    #[inline(always)]
    fn own_end(&self, from_a: bool) -> Result<(Vec3<W>, W), WarpError> {
        let (along, sin_b, _) = self.tangent_at(from_a).ok_or(reject::ANTIPODAL)?;
        Ok((along, sin_b / &self.det.abs()))
    }

    /// The anchor at V = A (`from_a`) or C given the tangent `along` there
    /// and `inv_d`.
    #[inline(always)]
    fn anchor_with(
        &self,
        from_a: bool,
        along: &Vec3<W>,
        inv_d: &W,
    ) -> Result<Anchor<W>, WarpError> {
        // ±1: the sign of det(A, B, C) for V = A, its opposite for V = C.
        let positive = (self.det > W::zero()) == from_a;
        let sign = if positive { W::one() } else { -W::one() };
        // V − B: A − B = −(B − A) exactly, or C − B.
        let (vertex, minus, at_b) = if from_a {
            (&self.a, self.ab.neg(), &self.at_b[0])
        } else {
            (&self.c, self.bc.clone(), &self.at_b[1])
        };
        Anchor::new(vertex, along, &self.b, (&minus, at_b), inv_d, &sign)
    }
}

impl<W: Real> Core<W> {
    /// The shared constants of the validated triangle `v`.
    #[inline(always)]
    pub fn from_validated(v: Validated<W>) -> Result<Self, WarpError> {
        let ccw = v.det > W::zero();
        let abs_det = v.det.abs();
        let (c_perp, sin_b, inv_sin_b) = v.tangent_at(true).ok_or(reject::ANTIPODAL)?;
        // d by the normalization's reciprocal; 1/d by its own division,
        // which runs beside the tangent's (no division waits on another).
        let d = abs_det.clone() * &inv_sin_b;
        let inv_d = sin_b.clone() / &abs_det;
        let ka = v.ab.dot(&c_perp);
        if !d.is_finite_above(&W::zero()) {
            return Err(reject::UNDERFLOW);
        }
        let sign = if ccw { W::one() } else { -W::one() };
        Ok(Core {
            v,
            ccw,
            sign,
            c_perp,
            sin_b,
            d,
            inv_d,
            ka,
        })
    }

    /// The anchor of the map at A (`from_a = true`) or C. The anchor at A
    /// takes the tangent [C|A] and `1/d` the core holds; the anchor at C its
    /// own tangent [A|C] and `1/d = sin b/|det|` with that tangent's
    /// `sin b` (equal to A's up to rounding): bit for bit what
    /// [`Validated::anchor_alone`] computes for the same end.
    #[inline(always)]
    pub fn anchor(&self, from_a: bool) -> Result<Anchor<W>, WarpError> {
        if from_a {
            self.v.anchor_with(true, &self.c_perp, &self.inv_d)
        } else {
            let (along, inv_d) = self.v.own_end(false)?;
            self.v.anchor_with(false, &along, &inv_d)
        }
    }

    /// The inward unit normals of the edge planes AB, BC, CA.
    pub fn normals(&self) -> Result<[Vec3<W>; 3], WarpError> {
        let inward = |v: &Vec3<W>, e: &Vec3<W>| {
            unit_vector(&v.cross(e).scale(&self.sign)).ok_or(reject::ON_CIRCLE)
        };
        Ok([
            inward(&self.v.a, &self.v.ab)?,
            inward(&self.v.b, &self.v.bc)?,
            inward(&self.v.c, &self.v.ca)?,
        ])
    }
}

/// The constants of the robust map measured from one end V of the arc AC
/// (V = A for u ≤ 1/2, V = C for u > 1/2, W the other end), all divided by
/// `d = sin c sin α = |det(A, B, C)| / sin b` (the same for both ends in
/// exact arithmetic; each end takes `sin b` from its own tangent on the arc
/// AC, so that one sample forms one tangent there) so that they stay O(1)
/// for tiny triangles.
#[derive(Clone, Debug)]
pub(super) struct Anchor<T> {
    /// V.
    pub vertex: Vec3<T>,
    /// `[W|V]`: the unit tangent at V along the arc towards W.
    pub along: Vec3<T>,
    /// `(1 + cos∠VB)/d`.
    pub k1_d: T,
    /// `sin∠VB · cos(angle at V)/d`.
    pub k_d: T,
    /// `1/sin²(∠VB/2) = 4/|V − B|²`.
    pub inv_s2: T,
    /// V − B and V + B.
    pub v_minus_b: Vec3<T>,
    pub v_plus_b: Vec3<T>,
    /// `[V|B]`: the unit tangent at B towards V.
    pub t_b: Vec3<T>,
    /// The unit tangent at B perpendicular to `t_b`, towards W.
    pub n_b: Vec3<T>,
}

impl<W: Real> Anchor<W> {
    /// The constants for the end `vertex` of the arc, `along` the unit
    /// tangent there towards the other end; `sign` is the sign of
    /// det(A, B, C) as ±1 for V = A (its opposite for V = C), `inv_d` the
    /// reciprocal of the common `d = |det|/sin b`; `v_minus_b` is `V − B`
    /// and `(|V − B|², V + B, |V + B|²)` the chords the validation formed.
    #[inline(always)]
    fn new(
        vertex: &Vec3<W>,
        along: &Vec3<W>,
        b: &Vec3<W>,
        (v_minus_b, (q_minus, v_plus_b, q_plus)): (&Vec3<W>, &(W, Vec3<W>, W)),
        inv_d: &W,
        sign: &W,
    ) -> Result<Self, WarpError> {
        let two = W::from_i64(2);
        let (t_b, _, _) =
            tangent(b, (v_minus_b, q_minus), (v_plus_b, q_plus)).ok_or(reject::ANTIPODAL)?;
        let s2 = q_minus.clone() / W::from_i64(4);
        // sin∠VB·cos(angle at V) = B·[W|V] = (B − V)·[W|V].
        let k = v_minus_b.neg().dot(along);
        let k1 = q_plus.clone() / &two;
        // n_b·[W|B] > 0: for V = A, (t_A × B)·t_C ∝ det(A, B, C). t_b ⊥ B,
        // both unit: the cross product is a unit vector up to rounding.
        let n_b = t_b.cross(b).scale(sign);
        Ok(Anchor {
            vertex: vertex.clone(),
            along: along.clone(),
            k1_d: k1 * inv_d,
            k_d: k * inv_d,
            inv_s2: W::one() / &s2,
            v_minus_b: v_minus_b.clone(),
            v_plus_b: v_plus_b.clone(),
            t_b,
            n_b,
        })
    }

    /// The anchor rounded to `T`; `None` if a constant leaves `T`'s range.
    #[inline(always)]
    pub fn narrow<T: Real<Wide = W>>(&self) -> Option<Anchor<T>> {
        let out = self.narrow_in_bounds::<T>();
        // V − B (finite) rounded to zero ([`Vec3::is_zero`]: comparisons).
        let finite = out.k1_d.is_finite_above(&T::zero())
            && out.k_d.is_finite()
            && out.inv_s2.is_finite()
            && !out.v_minus_b.is_zero();
        finite.then_some(out)
    }

    /// The anchor rounded to `T` without [`Anchor::narrow`]'s range tests,
    /// for an anchor of a triangle inside [`OneEndBounds`], where they
    /// pass: `k1_d = (|V + B|²/2)/d` is at most `2/d ≤ max/8` and at least
    /// half the antipodal limit (`1/d ≥ 1`), `|k_d| ≤ 2/d`,
    /// `inv_s2 = 4/|V − B|² ≤ max/16`, and `|V − B|² ≥ 64/max` keeps a
    /// coordinate of `V − B` above `2^-63` in `f32` (far above its smallest
    /// subnormal).
    #[inline(always)]
    pub fn narrow_in_bounds<T: Real<Wide = W>>(&self) -> Anchor<T> {
        Anchor {
            vertex: narrow3::<T>(&self.vertex),
            along: narrow3::<T>(&self.along),
            k1_d: T::narrow(&self.k1_d),
            k_d: T::narrow(&self.k_d),
            inv_s2: T::narrow(&self.inv_s2),
            v_minus_b: narrow3::<T>(&self.v_minus_b),
            v_plus_b: narrow3::<T>(&self.v_plus_b),
            t_b: narrow3::<T>(&self.t_b),
            n_b: narrow3::<T>(&self.n_b),
        }
    }
}

/// The scalars of the map rounded to `T` (Ω, 1/Ω, Ω/2, d), for the
/// constructor; `Unrepresentable` if `T` cannot hold them. (The one-shot
/// sample, inside [`OneEndBounds`], needs only Ω's test: [`omega_in`].)
pub(super) struct Scalars<T> {
    pub omega: T,
    pub inv_omega: T,
    pub half_omega: T,
    pub d: T,
}

impl<T: Real> Scalars<T> {
    #[inline(always)]
    pub fn of(core: &Core<T::Wide>) -> Result<Self, WarpError> {
        let (omega, inv_omega) = omega_in::<T>(&core.v.omega)?;
        let d = T::narrow(&core.d);
        if !positive(&d) {
            return Err(reject::OUT_OF_RANGE);
        }
        Ok(Scalars {
            omega,
            inv_omega,
            half_omega: T::narrow(&core.v.half_omega),
            d,
        })
    }
}

/// The solid angle Ω (`wide`, computed in `T::Wide`) and density 1/Ω
/// rounded to `T`, or the reason `T` cannot hold them.
#[inline(always)]
pub(super) fn omega_in<T: Real>(wide: &T::Wide) -> Result<(T, T), WarpError> {
    let omega = T::narrow(wide);
    let inv_omega = T::narrow(&(<T::Wide as Real>::one() / wide));
    if !positive(&omega) || !inv_omega.is_finite_above(&T::zero()) {
        return Err(reject::OUT_OF_RANGE);
    }
    Ok((omega, inv_omega))
}

/// Ω (`wide`, computed in `T::Wide`) rounded to `T`, with the decision of
/// [`omega_in`] but without forming 1/Ω where two comparisons settle it:
/// `8/max ≤ Ω ≤ 16` (`max` the largest value of `T`; every Ω is at most
/// 2π) rounds to a positive, finite value of `T`, and
/// `1/Ω ≤ (max/8)(1 + u)` to a finite one, so [`omega_in`] would accept it
/// with these bits. What the one-shot solid angle needs (its density is
/// the caller's division).
#[inline(always)]
pub(super) fn omega_alone_in<T: Real>(wide: &T::Wide) -> Result<T, WarpError> {
    let ordinary = <T::Wide as Real>::from_i64(8) / &T::max_value().widen();
    if *wide >= ordinary && *wide <= <T::Wide as Real>::from_i64(16) {
        return Ok(T::narrow(wide));
    }
    Ok(omega_in::<T>(wide)?.0)
}

/// The validated core of the triangle with the vertex directions `a`, `b`,
/// `c` given in `T` ([`validated_of`]).
#[inline(always)]
pub(super) fn core_of<T: Real>(
    a: &Vec3<T>,
    b: &Vec3<T>,
    c: &Vec3<T>,
) -> Result<Core<T::Wide>, WarpError> {
    Core::from_validated(validated_of(a, b, c)?)
}

/// The triangle with the vertex directions `a`, `b`, `c` given in `T`,
/// checked finite, widened and validated in `T::Wide`, with its solid
/// angle.
#[inline(always)]
pub(super) fn validated_of<T: Real>(
    a: &Vec3<T>,
    b: &Vec3<T>,
    c: &Vec3<T>,
) -> Result<Validated<T::Wide>, WarpError> {
    check_finite([(a, "vertex A"), (b, "vertex B"), (c, "vertex C")])?;
    Validated::new(&widen3(a), &widen3(b), &widen3(c))
}

/// The solid angle Ω of the triangle with the vertex directions `a`, `b`,
/// `c` given in `T`, validated as [`core_of`] validates (the constants
/// that only the map needs are not computed: once validation has passed,
/// they cannot fail), rounded to `T`.
#[inline(always)]
pub(super) fn solid_angle_of<T: Real>(
    a: &Vec3<T>,
    b: &Vec3<T>,
    c: &Vec3<T>,
) -> Result<T, WarpError> {
    omega_alone_in::<T>(&validated_of(a, b, c)?.omega)
}
