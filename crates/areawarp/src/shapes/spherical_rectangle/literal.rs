//! The [`Literal`](super::SphericalRectangleVariant::Literal) evaluation:
//! Ureña, Fajardo and King's reference algorithm (Appendix B, Listings 1–3)
//! transcribed statement by statement, in `T`.
//!
//! Kept faithful on purpose, including its weaknesses: Ω from Girard's sum
//! of the four internal angles (`acos` of dot products of edge normals),
//! `c_u` and `x_u` through `√(1 − c²)`, the `clamp`s "to avoid NaNs / Infs",
//! and the cut-off `h_v² < 1 − ε ⇒ y_v = y₁`. The listing leaves `ε`
//! undefined; `10⁻⁶` is used here, the value of the best-known production
//! transcription (Blender Cycles). `clamp` follows [`Real::clamp`] (a NaN
//! argument maps to the lower bound, as `fmin(fmax(x, lo), hi)` does).

use crate::real::Real;
use crate::vector::Vec3;

/// The constants of Listing 1 (`SphQuad`).
#[derive(Clone, Debug)]
pub(super) struct Literal<T> {
    o: Vec3<T>,
    x: Vec3<T>,
    y: Vec3<T>,
    z: Vec3<T>,
    z0: T,
    z0sq: T,
    x0: T,
    y0: T,
    y0sq: T,
    x1: T,
    y1: T,
    y1sq: T,
    b0: T,
    b1: T,
    b0sq: T,
    k: T,
    /// The solid angle S of the listing.
    s: T,
    /// `1 − ε`, `ε = 10⁻⁶`.
    one_m_eps: T,
}

/// `normalize(v) = v / sqrt(dot(v, v))`.
fn normalize<T: Real>(v: &Vec3<T>) -> Vec3<T> {
    v.scale(&(T::one() / &v.dot(v).sqrt()))
}

impl<T: Real> Literal<T> {
    /// Listing 2 (`SphQuadInit`).
    pub fn new(s: &Vec3<T>, ex: &Vec3<T>, ey: &Vec3<T>, o: &Vec3<T>) -> Self {
        let one = T::one();
        let exl = ex.dot(ex).sqrt();
        let eyl = ey.dot(ey).sqrt();
        // compute local reference system 'R'
        let x = ex.scale(&(one.clone() / &exl));
        let y = ey.scale(&(one.clone() / &eyl));
        let mut z = x.cross(&y);
        // compute rectangle coords in local reference system
        let d = s.sub(o);
        let mut z0 = d.dot(&z);
        // flip 'z' to make it point against 'Q'
        if z0 > T::zero() {
            z = z.neg();
            z0 = -z0;
        }
        let z0sq = z0.square();
        let x0 = d.dot(&x);
        let y0 = d.dot(&y);
        let x1 = x0.clone() + &exl;
        let y1 = y0.clone() + &eyl;
        let y0sq = y0.square();
        let y1sq = y1.square();
        // create vectors to four vertices
        let v00 = Vec3::new(x0.clone(), y0.clone(), z0.clone());
        let v01 = Vec3::new(x0.clone(), y1.clone(), z0.clone());
        let v10 = Vec3::new(x1.clone(), y0.clone(), z0.clone());
        let v11 = Vec3::new(x1.clone(), y1.clone(), z0.clone());
        // compute normals to edges
        let n0 = normalize(&v00.cross(&v10));
        let n1 = normalize(&v10.cross(&v11));
        let n2 = normalize(&v11.cross(&v01));
        let n3 = normalize(&v01.cross(&v00));
        // compute internal angles (gamma_i)
        let g0 = (-n0.dot(&n1)).acos();
        let g1 = (-n1.dot(&n2)).acos();
        let g2 = (-n2.dot(&n3)).acos();
        let g3 = (-n3.dot(&n0)).acos();
        // compute predefined constants
        let b0 = n0.z.clone();
        let b1 = n2.z.clone();
        let b0sq = b0.square();
        let k = T::pi() * &T::from_i64(2) - &g2 - &g3;
        // compute solid angle from internal angles
        let s_angle = g0 + &g1 - &k;
        Literal {
            o: o.clone(),
            x,
            y,
            z,
            z0,
            z0sq,
            x0,
            y0,
            y0sq,
            x1,
            y1,
            y1sq,
            b0,
            b1,
            b0sq,
            k,
            s: s_angle,
            one_m_eps: one - &T::from_ratio(1, 1_000_000),
        }
    }

    /// The solid angle `S` of Listing 2.
    pub fn solid_angle(&self) -> T {
        self.s.clone()
    }

    /// Listing 3 (`SphQuadSample`): the point on the rectangle.
    pub fn point(&self, u: &T, v: &T) -> Vec3<T> {
        let one = T::one();
        // 1. compute 'cu'
        let au = u.clone() * &self.s + &self.k;
        let fu = (au.cos() * &self.b0 - &self.b1) / &au.sin();
        let sign = if fu > T::zero() {
            one.clone()
        } else {
            -one.clone()
        };
        let cu = one.clone() / &(fu.square() + &self.b0sq).sqrt() * &sign;
        let cu = cu.clamp(&-one.clone(), &one); // avoid NaNs
        // 2. compute 'xu'
        let xu = -(cu.clone() * &self.z0) / &(one.clone() - &cu.square()).sqrt();
        let xu = xu.clamp(&self.x0, &self.x1); // avoid Infs
        // 3. compute 'yv'
        let d = (xu.square() + &self.z0sq).sqrt();
        let h0 = self.y0.clone() / &(d.square() + &self.y0sq).sqrt();
        let h1 = self.y1.clone() / &(d.square() + &self.y1sq).sqrt();
        let hv = h0.clone() + &(v.clone() * &(h1 - &h0));
        let hv2 = hv.square();
        let yv = if hv2 < self.one_m_eps {
            hv * &d / &(one - &hv2).sqrt()
        } else {
            self.y1.clone()
        };
        // 4. transform (xu,yv,z0) to world coords
        self.o
            .add(&self.x.scale(&xu))
            .add(&self.y.scale(&yv))
            .add(&self.z.scale(&self.z0))
    }

    /// The observer (for the direction `normalize(p − o)`).
    pub fn observer(&self) -> &Vec3<T> {
        &self.o
    }
}
