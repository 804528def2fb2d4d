//! Measures of one spherical triangle (generic): solid angle, projected
//! solid angle and the largest cosine over it.

use super::*;
// ---------------------------------------------------------------------------
// Measures of one spherical triangle (generic).

/// The largest `z` (`cos θ` about the receiver's normal `+z`) on the minor
/// great arc from `a` to `b` (directions, normalized here).
///
/// On the great circle with normal `n = a × b` the highest point is
/// `p = (ẑ − n̂_z n̂)/√(1 − n̂_z²)`, of height `√(1 − n̂_z²) = |n_xy|/|n|`;
/// it is on the arc iff it lies between `a` and `b`, i.e.
/// `(a × p)·n ≥ 0` and `(p × b)·n ≥ 0`. Otherwise `z` is monotone along
/// the arc and the maximum is at an end (Ureña 2000, §4.3, Fig. 6). An
/// arc on the horizon (`n ∥ ẑ`) has `z = 0` throughout.
///
/// # Example
/// ```
/// use areawarp::adaptive::arc_max_cosine;
/// use areawarp::Vec3;
/// // A meridian arc over the pole: its maximum is the pole.
/// let a = Vec3::<f64>::new(1.0, 0.0, 1.0);
/// let b = Vec3::<f64>::new(-1.0, 0.0, 1.0);
/// assert!((arc_max_cosine(&a, &b) - 1.0).abs() < 1e-15);
/// // An arc peaking between its ends, at (1, 0, 1)/√2 by symmetry.
/// let m = arc_max_cosine(&Vec3::<f64>::new(1.0, -1.0, 1.0), &Vec3::new(1.0, 1.0, 1.0));
/// assert!((m - 0.5f64.sqrt()).abs() < 1e-15);
/// ```
pub fn arc_max_cosine<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    let (a, b) = (unit_or_nan(a), unit_or_nan(b));
    let mut m = a.z.clone().max(&b.z);
    let n = a.cross(&b);
    let s2 = n.x.square() + &n.y.square();
    if s2 > T::zero() {
        // p ∝ ẑ |n|² − n_z n (height s2 > 0), unnormalized.
        let p = Vec3::new(-(n.z.clone() * &n.x), -(n.z.clone() * &n.y), s2.clone());
        if a.cross(&p).dot(&n) >= T::zero() && p.cross(&b).dot(&n) >= T::zero() {
            let top = s2.sqrt() / &n.norm();
            m = m.max(&top);
        }
    }
    m
}

/// `m(E)`: the largest `z = cos θ` over the spherical triangle `a b c`
/// (directions, normalized here; minor arcs), Ureña (2000) §4.3.
///
/// `z` is the height function on the sphere; restricted to a spherical
/// triangle (a geodesically convex region smaller than a hemisphere) its
/// maximum is either the pole `ẑ`, if the triangle contains it (then
/// `m = 1`), or on the boundary — a local maximum of `z` inside a region
/// that does not contain the pole would be a critical point of `z` on the
/// sphere other than ±ẑ, and there is none. On the boundary it is the
/// largest of the three arc maxima ([`arc_max_cosine`]). The pole is in
/// the triangle iff it is on the inner side of all three edges, i.e. the
/// `z` components of the edge normals `v_i × v_{i+1}` all have the
/// orientation's sign (§4.3).
///
/// # Example
/// ```
/// use areawarp::adaptive::max_cosine;
/// use areawarp::Vec3;
/// // Around the pole: m = 1.
/// let r = 0.5f64;
/// let (a, b, c) = (
///     Vec3::new(r, 0.0, 1.0),
///     Vec3::new(-r / 2.0, r * 0.75f64.sqrt(), 1.0),
///     Vec3::new(-r / 2.0, -r * 0.75f64.sqrt(), 1.0),
/// );
/// assert_eq!(max_cosine(&a, &b, &c), 1.0);
/// // Off the pole, at the highest vertex.
/// let (a, b, c) = (Vec3::new(1.0, 0.0, 0.1), Vec3::new(0.0, 1.0, 0.1), Vec3::new(1.0, 1.0, 1.0));
/// assert!((max_cosine(&a, &b, &c) - 1.0 / 3f64.sqrt()).abs() < 1e-15);
/// ```
pub fn max_cosine<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    let (a, b, c) = (unit_or_nan(a), unit_or_nan(b), unit_or_nan(c));
    // Orientation from differences (accurate for small triangles).
    let det = a.dot(&b.sub(&a).cross(&c.sub(&a)));
    let zero = T::zero();
    let (nab, nbc, nca) = (a.cross(&b).z, b.cross(&c).z, c.cross(&a).z);
    let inside = if det > zero {
        nab >= zero && nbc >= zero && nca >= zero
    } else if det < zero {
        nab <= zero && nbc <= zero && nca <= zero
    } else {
        false
    };
    if inside {
        return T::one();
    }
    arc_max_cosine(&a, &b)
        .max(&arc_max_cosine(&b, &c))
        .max(&arc_max_cosine(&c, &a))
}

/// `v/|v|`, NaN coordinates for a zero or non-finite `v`.
pub(super) fn unit_or_nan<T: Real>(v: &Vec3<T>) -> Vec3<T> {
    v.normalized().unwrap_or_else(|| {
        let nan = T::zero() / T::zero();
        Vec3::new(nan.clone(), nan.clone(), nan)
    })
}

/// Lambert's formula for the projected solid angle (receiver normal `+z`)
/// of the spherical triangle with *unit* vertices `a`, `b`, `c`:
///
/// `σ⊥ = ½ |Σ_i θ_i n̂_i·ẑ|`, `θ_i = ∠(v_i, v_{i+1})`, `n̂_i = v_i × v_{i+1}/|v_i × v_{i+1}|`
///
/// (π × the point-to-polygon form factor; Ureña 2000 §4.2, whose `n_i`
/// must be normalized). Each edge normal is formed as `v_i × (v_{i+1} − v_i)`
/// (the same vector, without the cancellation of `v_i × v_{i+1}` for short
/// edges), so that each term has full relative accuracy; the sum of the
/// three `O(size)` terms to an `O(size²)` result still costs a relative
/// error of about `u/size` (`u` the unit roundoff). Edges of zero length
/// contribute 0.
pub(super) fn lambert<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    let zero = T::zero();
    let mut sum = zero.clone();
    for (x, y) in [(a, b), (b, c), (c, a)] {
        let n = x.cross(&y.sub(x));
        let s = n.norm();
        if s > zero {
            sum += &(s.atan2(&x.dot(y)) * &n.z / &s);
        }
    }
    (sum / &T::from_i64(2)).abs()
}

/// The solid angle of the triangle with unit vertices `a`, `b`, `c` by the
/// evaluation of [`SphericalTriangle::new`] (Van Oosterom–Strackee,
/// `Ω = 2 atan2(|det|, 1 + a·b + b·c + c·a)`, with `det(a, b, c)` from the
/// cross product of the two shortest chords at the vertex opposite the
/// longest, and `1 + a·b = |a + b|²/2`), and `true` if the triangle passes
/// that constructor's non-degeneracy test `|det| > 256 u ℓ₁ℓ₂` with a
/// 16-fold margin (so that [`SphericalTriangle::new`] accepts it too).
pub(super) fn robust_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> (T, bool) {
    let ab = b.sub(a);
    let bc = c.sub(b);
    let ca = a.sub(c);
    let (l_ab, l_bc, l_ca) = (ab.norm(), bc.norm(), ca.norm());
    let (det, l1, l2) = if l_bc >= l_ab && l_bc >= l_ca {
        (a.dot(&ab.cross(&ca.neg())), &l_ab, &l_ca)
    } else if l_ca >= l_ab {
        (b.dot(&bc.cross(&ab.neg())), &l_ab, &l_bc)
    } else {
        (c.dot(&ca.cross(&bc.neg())), &l_bc, &l_ca)
    };
    let two = T::from_i64(2);
    let a_plus_b = a.add(b);
    let den = a_plus_b.dot(&a_plus_b) / &two + &c.dot(&a_plus_b);
    let omega = det.abs().atan2(&den) * &two;
    let threshold = T::from_i64(4096) * &T::unit_roundoff() * l1 * l2;
    let ok = det.abs() > threshold
        && omega > T::zero()
        && (T::one() / &omega).is_finite()
        && l1.clone() > T::zero();
    (omega, ok)
}

/// σ, σ⊥, m and k of one spherical triangle above the receiver's horizon
/// (receiver normal `+z`), the quantities that drive the subdivision.
///
/// - `σ` ([`solid_angle`](Self::solid_angle)): the solid angle, by the
///   robust Van Oosterom–Strackee evaluation of [`SphericalTriangle`]
///   (not Girard's `Σβ − π` of the paper's §4.2, which cancels for small
///   triangles);
/// - `σ⊥` ([`projected_solid_angle`](Self::projected_solid_angle)):
///   Lambert's formula `½ |Σ θ_i n̂_i·ẑ|`, with edge normals formed from
///   differences (relative error about `u/size`);
/// - `m` ([`max_cosine`](Self::max_cosine)): [`max_cosine`];
/// - `k = m σ/σ⊥ − 1` ([`k`](Self::k), eq. 5): `≥ 0` since
///   `σ⊥ = ∫ cos dσ ≤ m σ` (to rounding); `+∞` when `σ⊥ = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMeasures<T> {
    /// σ, in steradians.
    pub solid_angle: T,
    /// σ⊥ = ∫ cos θ dω.
    pub projected_solid_angle: T,
    /// m = max cos θ over the triangle.
    pub max_cosine: T,
    /// k = m σ / σ⊥ − 1.
    pub k: T,
}

impl<T: Real> TriangleMeasures<T> {
    /// The measures of the triangle with vertex directions `a`, `b`, `c`.
    ///
    /// # Errors
    /// As [`SphericalTriangle::new`] (non-finite, zero, coincident or
    /// collinear vertices), and [`WarpError::InvalidParameter`] if a vertex
    /// is below the horizon (`z < 0`: clip first, as
    /// [`AdaptiveTriangle::new`] does).
    ///
    /// # Example
    /// ```
    /// use areawarp::adaptive::TriangleMeasures;
    /// use areawarp::Vec3;
    /// // The octant: σ = π/2, σ⊥ = π/4, m = 1 (the pole is a vertex), k = 1.
    /// let m = TriangleMeasures::<f64>::new(
    ///     Vec3::new(1.0, 0.0, 0.0),
    ///     Vec3::new(0.0, 1.0, 0.0),
    ///     Vec3::new(0.0, 0.0, 1.0),
    /// )?;
    /// assert!((m.k - 1.0).abs() < 1e-15);
    /// # Ok::<(), areawarp::WarpError>(())
    /// ```
    pub fn new(a: Vec3<T>, b: Vec3<T>, c: Vec3<T>) -> Result<Self, WarpError> {
        Self::of(&SphericalTriangle::new(a, b, c)?)
    }

    /// The measures of an existing [`SphericalTriangle`] (σ is its
    /// [`solid_angle`](SphericalTriangle::solid_angle)).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if a vertex is below the horizon.
    pub fn of(tri: &SphericalTriangle<T>) -> Result<Self, WarpError> {
        let zero = T::zero();
        let (a, b, c) = (tri.a(), tri.b(), tri.c());
        if a.z < zero || b.z < zero || c.z < zero {
            return Err(WarpError::InvalidParameter {
                name: "vertices",
                expected: "directions with z >= 0 (clip against the horizon first)",
            });
        }
        Ok(Self::with_solid_angle(a, b, c, tri.solid_angle().clone()))
    }

    /// The measures of the triangle with unit vertices `a b c` (z ≥ 0) and
    /// solid angle `sigma`.
    pub(super) fn with_solid_angle(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>, sigma: T) -> Self {
        let zero = T::zero();
        let sigma_perp = lambert(a, b, c);
        let m = max_cosine(a, b, c);
        let k = if sigma_perp > zero {
            m.clone() * &sigma / &sigma_perp - &T::one()
        } else {
            T::one() / T::zero()
        };
        TriangleMeasures {
            solid_angle: sigma,
            projected_solid_angle: sigma_perp,
            max_cosine: m,
            k,
        }
    }
}
