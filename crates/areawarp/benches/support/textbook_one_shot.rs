//! One-shot light samples written the way a renderer writes them: the
//! baseline for areawarp's `sample_once` (issue 10, item 4, "pay only for
//! what you use"). Our own code, written from the papers' formulas in the
//! style of pbrt-v4's `SampleSphericalTriangle` / `SampleSphericalRectangle`
//! (not copied): no validation of the input, no reformulation against
//! cancellation, every step in `T`, plain `a·b − c·d` (no `mul_add`: on
//! baseline x86-64 without FMA it calls libm's software `fma`).
//!
//! Also the textbook solid angles the one-shot `solid_angle_of` is timed
//! against: Van Oosterom–Strackee for the triangle, Girard for the
//! rectangle.
//!
//! UNVALIDATED: degenerate input (zero edges, collinear vertices, an
//! observer in the light's plane) gives NaN or nonsense, and accuracy is
//! that of the published algorithms (digits lost near the edges of the unit
//! square and for small, thin or distant lights). Use only as a timing
//! baseline; `tests/textbook_one_shot.rs` checks that it computes the same
//! maps as areawarp (Arvo's, Ureña's) on well-conditioned shapes.

#![allow(dead_code)]

use areawarp::{LightSample, Real, Vec3};

/// `v / |v|` by one square root and one division (what renderers write; no
/// guard against overflow, underflow or the zero vector).
#[inline(always)]
fn unit<T: Real>(v: &Vec3<T>) -> Vec3<T> {
    v.scale(&(T::one() / &v.dot(v).sqrt()))
}

/// The angle between the unit vectors `x` and `y` in `[0, π]`, accurate
/// for nearly parallel and nearly antiparallel vectors: `2 asin(|y − x|/2)`,
/// or `π − 2 asin(|x + y|/2)` when `x·y < 0` (the form pbrt-v4's
/// `AngleBetween` uses).
#[inline(always)]
fn angle_between<T: Real>(x: &Vec3<T>, y: &Vec3<T>) -> T {
    let two = T::from_i64(2);
    if x.dot(y) < T::zero() {
        let s = x.add(y);
        T::pi() - &(two.clone() * &(s.dot(&s).sqrt() / &two).asin())
    } else {
        let d = y.sub(x);
        two.clone() * &(d.dot(&d).sqrt() / &two).asin()
    }
}

/// `√max(x, 0)`: the square root of a quantity that is ≥ 0 in exact
/// arithmetic (pbrt's `SafeSqrt`).
#[inline(always)]
fn safe_sqrt<T: Real>(x: &T) -> T {
    x.max(&T::zero()).sqrt()
}

/// The interior angle `acos(−n_i·n_j)` at the edge shared by two
/// consecutive planes with outward unit normals `n_i`, `n_j` (Girard's
/// theorem sums these), the cosine clamped into `[−1, 1]`.
#[inline(always)]
fn interior_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    (-a.dot(b)).clamp(&-T::one(), &T::one()).acos()
}

/// The unit part of `c` perpendicular to the unit vector `a`,
/// `[c|a] = (c − (c·a) a)/|c − (c·a) a|` (Arvo's notation; a Gram–Schmidt
/// step).
#[inline(always)]
fn perp<T: Real>(c: &Vec3<T>, a: &Vec3<T>) -> Vec3<T> {
    unit(&c.sub(&a.scale(&c.dot(a))))
}

/// Arvo's (1995) uniform sample of the spherical triangle with vertex
/// directions `a`, `b`, `c` (from the observer, any length): the unit
/// direction `P = ψ(u, v)` and its density `1/Ω` per steradian.
/// Unvalidated textbook code (see the module doc).
///
/// Same parametrization as areawarp's `SphericalTriangle`: `C'` on the arc
/// AC cuts off the sub-triangle A B C' of area `u·Ω`; `P` lies on the arc
/// from B to C' with `1 − P·B = v (1 − C'·B)`.
///
/// Steps (Arvo 1995, Fig. 2, re-derived): the unit normals of the planes
/// through the edges, the triangle's angles α, β, γ between them, the area
/// `Ω = α + β + γ − π` (Girard); `Â = uΩ`; with `s = sin(Â − α)`,
/// `t = cos(Â − α)`, `p = t − cos α`, `q₀ = s + sin α cos c` (`cos c = a·b`)
/// the cosine of the arc AC' is
/// `q = ((q₀ t − p s) cos α − q₀) / ((q₀ s + p t) sin α)` (spherical law of
/// cosines for the angle at C' of A B C', solved for the side b̂);
/// `C' = q a + √(1 − q²) [c|a]`; `cos θ = 1 − v (1 − C'·b)`;
/// `P = cos θ b + sin θ [C'|b]`.
#[inline(always)]
pub fn textbook_triangle_sample<T: Real>(
    a: &Vec3<T>,
    b: &Vec3<T>,
    c: &Vec3<T>,
    u: &T,
    v: &T,
) -> (Vec3<T>, T) {
    let (a, b, c) = (unit(a), unit(b), unit(c));
    let n_ab = unit(&a.cross(&b));
    let n_bc = unit(&b.cross(&c));
    let n_ca = unit(&c.cross(&a));
    // The angle at a vertex between the planes of the two edges through it
    // (the normals, both taken pointing into the triangle).
    let alpha = angle_between(&n_ab, &n_ca.neg());
    let beta = angle_between(&n_bc, &n_ab.neg());
    let gamma = angle_between(&n_ca, &n_bc.neg());
    let area = alpha.clone() + &beta + &gamma - &T::pi();
    let area_u = u.clone() * &area;
    let (s, t) = (area_u - &alpha).sin_cos();
    let (sin_alpha, cos_alpha) = alpha.sin_cos();
    let p = t.clone() - &cos_alpha;
    let q0 = s.clone() + &(sin_alpha.clone() * &a.dot(&b));
    let q = ((q0.clone() * &t - &(p.clone() * &s)) * &cos_alpha - &q0)
        / &((q0 * &s + &(p * &t)) * &sin_alpha);
    let q = q.clamp(&-T::one(), &T::one());
    let c_s = a
        .scale(&q)
        .add(&perp(&c, &a).scale(&safe_sqrt(&(T::one() - &q.square()))));
    let cos_theta = T::one() - &(v.clone() * &(T::one() - &c_s.dot(&b)));
    let sin_theta = safe_sqrt(&(T::one() - &cos_theta.square()));
    let p = b.scale(&cos_theta).add(&perp(&c_s, &b).scale(&sin_theta));
    (p, T::one() / &area)
}

/// [`textbook_triangle_sample`] as a triangle light's sample, the way a
/// renderer completes it: the triangle of points `p0`, `p1`, `p2` seen from
/// `o`, the direction `d` from Arvo's map, the point where the ray meets
/// the triangle's plane (normal `n = (p1 − p0) × (p2 − p0)`, unnormalized:
/// `t = ((p0 − o)·n)/(d·n)`), and the density in area
/// `pdf·|d·n|/(|n| t²)`, returned as areawarp's `LightSample`.
/// Unvalidated textbook code (see the module doc).
#[inline(always)]
pub fn textbook_triangle_light_sample<T: Real>(
    p0: &Vec3<T>,
    p1: &Vec3<T>,
    p2: &Vec3<T>,
    o: &Vec3<T>,
    u: &T,
    v: &T,
) -> LightSample<T> {
    let a = p0.sub(o);
    let (d, pdf) = textbook_triangle_sample(&a, &p1.sub(o), &p2.sub(o), u, v);
    let n = p1.sub(p0).cross(&p2.sub(p0));
    let dn = d.dot(&n);
    let t = a.dot(&n) / &dn;
    let point = o.add(&d.scale(&t));
    let pdf_area = pdf.clone() * &dn.abs() / &(n.dot(&n).sqrt() * &t.square());
    LightSample {
        direction: d,
        point,
        distance: t,
        pdf,
        pdf_area,
    }
}

/// Ureña, Fajardo and King's (2013) uniform sample of the solid angle of
/// the rectangle with corner `s` and perpendicular edges `ex`, `ey`, seen
/// from `o`, as areawarp's `LightSample`: the unit direction from `o`, the
/// point on the rectangle, its distance `r`, the density `1/Ω` per
/// steradian and the density per unit area `pdf · |cos θ_e| / r²` (a
/// renderer computes it for MIS with area lights).
/// Unvalidated textbook code (see the module doc).
///
/// Same parametrization as areawarp's `SphericalRectangle`: in the frame
/// `x = ex/|ex|`, `y = ey/|ey|`, `z = x × y` (turned so that the rectangle
/// lies at `z₀ < 0`) centred at `o`, the rectangle is `[x₀, x₁] × [y₀, y₁]`;
/// the column `x_u` cuts off `[x₀, x_u] × [y₀, y₁]` of solid angle `uΩ`,
/// the row `y_v` interpolates `h = y/√(x_u² + z₀² + y²)` linearly in `v`.
///
/// Steps (the paper's Appendix B, re-derived): the unit normals `n₀…n₃` of
/// the planes through `o` and the edges (y = y₀, x = x₁, y = y₁, x = x₀),
/// the interior angles `γᵢ = acos(−nᵢ·nᵢ₊₁)`, `Ω = Σγ − 2π`; with
/// `b₀ = n₀·z`, `b₁ = n₂·z`, `k = 2π − γ₂ − γ₃`: `φ = uΩ + k`,
/// `f = (cos φ b₀ − b₁)/sin φ`, `c_u = sign(f)/√(f² + b₀²)`,
/// `x_u = −c_u z₀/√(1 − c_u²)`; `d = √(x_u² + z₀²)`,
/// `h_v = h₀ + v (h₁ − h₀)`, `y_v = h_v d/√(1 − h_v²)` (`y₁` when
/// `h_v² ≥ 1 − ε`, the paper's cut-off, here `ε` = 8 units of roundoff of
/// `T` instead of `10⁻⁶`).
#[inline(always)]
pub fn textbook_rectangle_sample<T: Real>(
    s: &Vec3<T>,
    ex: &Vec3<T>,
    ey: &Vec3<T>,
    o: &Vec3<T>,
    u: &T,
    v: &T,
) -> LightSample<T> {
    let (len_x, len_y) = (ex.dot(ex).sqrt(), ey.dot(ey).sqrt());
    let x = ex.scale(&(T::one() / &len_x));
    let y = ey.scale(&(T::one() / &len_y));
    let mut z = x.cross(&y);
    let d = s.sub(o);
    let (x0, y0, mut z0) = (d.dot(&x), d.dot(&y), d.dot(&z));
    if z0 > T::zero() {
        z0 = -z0;
        z = z.neg();
    }
    let x1 = x0.clone() + &len_x;
    let y1 = y0.clone() + &len_y;
    // Corners in the local frame, counterclockwise seen from o.
    let corner = |cx: &T, cy: &T| Vec3::new(cx.clone(), cy.clone(), z0.clone());
    let (v00, v10) = (corner(&x0, &y0), corner(&x1, &y0));
    let (v11, v01) = (corner(&x1, &y1), corner(&x0, &y1));
    let n0 = unit(&v00.cross(&v10));
    let n1 = unit(&v10.cross(&v11));
    let n2 = unit(&v11.cross(&v01));
    let n3 = unit(&v01.cross(&v00));
    let g0 = interior_angle(&n0, &n1);
    let g1 = interior_angle(&n1, &n2);
    let g2 = interior_angle(&n2, &n3);
    let g3 = interior_angle(&n3, &n0);
    let two_pi = T::pi() * &T::from_i64(2);
    let (b0, b1) = (n0.z.clone(), n2.z.clone());
    let k = two_pi - &g2 - &g3;
    let omega = g0 + &g1 - &k;
    // The column x_u.
    let au = u.clone() * &omega + &k;
    let (sin_au, cos_au) = au.sin_cos();
    let fu = (cos_au * &b0 - &b1) / &sin_au;
    let cu = (T::one().copysign(&fu) / &(fu.square() + &b0.square()).sqrt())
        .clamp(&-T::one(), &T::one());
    let xu = (-(cu.clone() * &z0) / &(T::one() - &cu.square()).sqrt()).clamp(&x0, &x1);
    // The row y_v.
    let dd2 = xu.square() + &z0.square();
    let dd = dd2.sqrt();
    let h0 = y0.clone() / &(dd2.clone() + &y0.square()).sqrt();
    let h1 = y1.clone() / &(dd2 + &y1.square()).sqrt();
    let hv = h0.clone() + &(v.clone() * &(h1 - &h0));
    let hv2 = hv.square();
    let eps = T::unit_roundoff() * &T::from_i64(8);
    let yv = if hv2 < T::one() - &eps {
        hv * &dd / &(T::one() - &hv2).sqrt()
    } else {
        y1
    };
    // Back to world coordinates.
    let local = x.scale(&xu).add(&y.scale(&yv)).add(&z.scale(&z0));
    let r2 = local.dot(&local);
    let r = r2.sqrt();
    let direction = local.scale(&(T::one() / &r));
    let point = o.add(&local);
    let pdf = T::one() / &omega;
    // cos θ_e = |z₀|/r: pdf_area = pdf |z₀| / r³.
    let pdf_area = pdf.clone() * &(-z0) / &(r2 * &r);
    LightSample {
        direction,
        point,
        distance: r,
        pdf,
        pdf_area,
    }
}

/// The solid angle as a renderer writes it without validation (pbrt-v4's
/// `SphericalTriangleArea` after normalizing the directions; our own code):
/// Van Oosterom–Strackee in `T`, `|2 atan2(a·(b × c), 1 + a·b + a·c + b·c)|`.
#[inline]
pub fn textbook_solid_angle<T: Real>(a: &Vec3<T>, b: &Vec3<T>, c: &Vec3<T>) -> T {
    let (a, b, c) = (unit(a), unit(b), unit(c));
    let den = T::one() + &a.dot(&b) + &a.dot(&c) + &b.dot(&c);
    (a.dot(&b.cross(&c)).atan2(&den) * &T::from_i64(2)).abs()
}

/// The solid angle of a rectangle as a renderer writes it without
/// validation (Girard's theorem, as pbrt-v4's `SphericalQuadArea` and the
/// paper's Appendix B; our own code): the unit normals of the four planes
/// through the observer and an edge, the interior angles `acos(−n_i·n_j)`
/// of consecutive planes, `|Σγ − 2π|`.
#[inline]
pub fn textbook_rectangle_solid_angle<T: Real>(
    s: &Vec3<T>,
    ex: &Vec3<T>,
    ey: &Vec3<T>,
    o: &Vec3<T>,
) -> T {
    let p0 = s.sub(o);
    let p1 = p0.add(ex);
    let p2 = p1.add(ey);
    let p3 = p0.add(ey);
    let n = [
        unit(&p0.cross(&p1)),
        unit(&p1.cross(&p2)),
        unit(&p2.cross(&p3)),
        unit(&p3.cross(&p0)),
    ];
    let sum = interior_angle(&n[3], &n[0])
        + &interior_angle(&n[0], &n[1])
        + &interior_angle(&n[1], &n[2])
        + &interior_angle(&n[2], &n[3]);
    (sum - &(T::pi() * &T::from_i64(2))).abs()
}
