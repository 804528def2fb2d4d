//! Small warps for the harness's own unit tests: correct ones, and
//! deliberately wrong ones that the checks must reject.

use crate::error::WarpError;
use crate::real::{Real, convert};
use crate::vector::{Vec2, Vec3};
use crate::warp::InverseError;
use crate::warp::{Warp, WarpFamily};

fn two_pi<T: Real>() -> T {
    T::pi() * &T::from_i64(2)
}

/// `v / 2π` wrapped into `[0, 1)`.
fn turn<T: Real>(y: &T, x: &T) -> T {
    let t = y.atan2(x) / &two_pi::<T>();
    if t < T::zero() { t + &T::one() } else { t }
}

/// Solves `d ≈ s e1 + t e2` in the least-squares sense (Gram system).
fn coordinates<T: Real>(d: &Vec3<T>, e1: &Vec3<T>, e2: &Vec3<T>) -> (T, T) {
    let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (p, q) = (d.dot(e1), d.dot(e2));
    let det = a.clone() * &c - &(b.clone() * &b);
    (
        (c * &p - &(b.clone() * &q)) / &det,
        (a * &q - &(b * &p)) / &det,
    )
}

/// The parallelogram `o + u e1 + v e2`: an affine map, constant Jacobian.
#[derive(Clone, Debug)]
pub struct Parallelogram<T> {
    o: Vec3<T>,
    e1: Vec3<T>,
    e2: Vec3<T>,
    area: T,
}

impl<T: Real> Parallelogram<T> {
    pub fn new(o: Vec3<T>, e1: Vec3<T>, e2: Vec3<T>) -> Result<Self, WarpError> {
        let area = e1.cross(&e2).norm();
        if area.is_nan() || area <= T::zero() {
            return Err(WarpError::Degenerate { what: "edges" });
        }
        Ok(Parallelogram { o, e1, e2, area })
    }
}

impl<T: Real> Warp<T> for Parallelogram<T> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        self.o.add(&self.e1.scale(u)).add(&self.e2.scale(v))
    }
    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        T::one() / &self.area
    }
    fn measure(&self) -> T {
        self.area.clone()
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        if !p.is_finite() {
            return Err(InverseError::NonFinite);
        }
        let (s, t) = coordinates(&p.sub(&self.o), &self.e1, &self.e2);
        Ok([s, t])
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        let (s, t) = coordinates(&p.sub(&self.o), &self.e1, &self.e2);
        let (zero, one) = (T::zero(), T::one());
        let q = self.map(&s.clamp(&zero, &one), &t.clamp(&zero, &one));
        q.sub(p).norm()
    }
    fn extent(&self) -> T {
        self.e1.norm().max(&self.e2.norm())
    }
}

impl<T: Real> WarpFamily<T> for Parallelogram<T> {
    type At<S: Real> = Parallelogram<S>;
    fn at<S: Real>(&self) -> Result<Parallelogram<S>, WarpError> {
        Parallelogram::new(self.o.convert(), self.e1.convert(), self.e2.convert())
    }
    fn name(&self) -> String {
        "test-parallelogram".into()
    }
}

/// The polar unit disk: `r = √u` (correct) or `r = u` (wrong: not
/// area-preserving, samples crowd the centre), `θ = 2πv`; pdf claims `1/π`.
#[derive(Clone, Debug)]
pub struct TestDisk<T> {
    wrong: bool,
    _t: core::marker::PhantomData<T>,
}

impl<T: Real> TestDisk<T> {
    pub fn correct() -> Self {
        TestDisk {
            wrong: false,
            _t: core::marker::PhantomData,
        }
    }
    pub fn wrong() -> Self {
        TestDisk {
            wrong: true,
            _t: core::marker::PhantomData,
        }
    }
}

impl<T: Real> Warp<T> for TestDisk<T> {
    type Point = Vec2<T>;
    fn map(&self, u: &T, v: &T) -> Vec2<T> {
        let r = if self.wrong { u.clone() } else { u.sqrt() };
        let (s, c) = (two_pi::<T>() * v).sin_cos();
        Vec2::new(r.clone() * &c, r * &s)
    }
    fn pdf_unchecked(&self, _p: &Vec2<T>) -> T {
        T::one() / &T::pi()
    }
    fn measure(&self) -> T {
        T::pi()
    }
    fn inverse(&self, p: &Vec2<T>) -> Result<[T; 2], InverseError> {
        let r = p.norm();
        if !r.is_finite() {
            return Err(InverseError::NonFinite);
        }
        let u = if self.wrong { r } else { r.square() };
        Ok([u, turn(&p.y, &p.x)])
    }
    fn outside_by(&self, p: &Vec2<T>) -> T {
        (p.norm() - &T::one()).max(&T::zero())
    }
}

impl<T: Real> WarpFamily<T> for TestDisk<T> {
    type At<S: Real> = TestDisk<S>;
    fn at<S: Real>(&self) -> Result<TestDisk<S>, WarpError> {
        Ok(if self.wrong {
            TestDisk::wrong()
        } else {
            TestDisk::correct()
        })
    }
    fn name(&self) -> String {
        if self.wrong {
            "test-disk-wrong".into()
        } else {
            "test-disk".into()
        }
    }
}

/// The unit sphere, `z = 1 − 2u` (correct) or `z = 1 − 2u²` (wrong), `φ = 2πv`.
#[derive(Clone, Debug)]
pub struct TestSphere<T> {
    wrong: bool,
    _t: core::marker::PhantomData<T>,
}

impl<T: Real> TestSphere<T> {
    pub fn new(wrong: bool) -> Self {
        TestSphere {
            wrong,
            _t: core::marker::PhantomData,
        }
    }
}

impl<T: Real> Warp<T> for TestSphere<T> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let a = if self.wrong { u.square() } else { u.clone() };
        // z = 1 − 2a, sin θ = 2 √(a (1 − a)).
        let z = T::one() - &(a.clone() * &T::from_i64(2));
        let s = (a.clone() * &(T::one() - &a)).sqrt() * &T::from_i64(2);
        let (sp, cp) = (two_pi::<T>() * v).sin_cos();
        Vec3::new(s.clone() * &cp, s * &sp, z)
    }
    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        T::one() / &(T::pi() * &T::from_i64(4))
    }
    fn measure(&self) -> T {
        T::pi() * &T::from_i64(4)
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        if !p.is_finite() {
            return Err(InverseError::NonFinite);
        }
        let a = (T::one() - &p.z) / &T::from_i64(2);
        let u = if self.wrong { a.sqrt() } else { a };
        Ok([u, turn(&p.y, &p.x)])
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        (p.norm() - &T::one()).abs()
    }
}

impl<T: Real> WarpFamily<T> for TestSphere<T> {
    type At<S: Real> = TestSphere<S>;
    fn at<S: Real>(&self) -> Result<TestSphere<S>, WarpError> {
        Ok(TestSphere::new(self.wrong))
    }
    fn name(&self) -> String {
        "test-sphere".into()
    }
}

/// The Phong lobe `cos^k θ` about +z: `z = u^(1/(k+1))`, `φ = 2πv`.
#[derive(Clone, Debug)]
pub struct TestLobe<T> {
    k: T,
}

impl<T: Real> TestLobe<T> {
    pub fn new(k: T) -> Self {
        TestLobe { k }
    }
}

impl<T: Real> Warp<T> for TestLobe<T> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let z = u.powf(&(T::one() / &(self.k.clone() + &T::one())));
        let s = (T::one() - &z.square()).max(&T::zero()).sqrt();
        let (sp, cp) = (two_pi::<T>() * v).sin_cos();
        Vec3::new(s.clone() * &cp, s * &sp, z)
    }
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        let kp1 = self.k.clone() + &T::one();
        p.z.max(&T::zero()).powf(&self.k) * &kp1 / &two_pi::<T>()
    }
    fn measure(&self) -> T {
        two_pi::<T>() / &(self.k.clone() + &T::one())
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        if !p.is_finite() {
            return Err(InverseError::NonFinite);
        }
        let u = p.z.max(&T::zero()).powf(&(self.k.clone() + &T::one()));
        Ok([u, turn(&p.y, &p.x)])
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        (p.norm() - &T::one()).abs() + &(-p.z.clone()).max(&T::zero())
    }
}

impl<T: Real> WarpFamily<T> for TestLobe<T> {
    type At<S: Real> = TestLobe<S>;
    fn at<S: Real>(&self) -> Result<TestLobe<S>, WarpError> {
        Ok(TestLobe::new(convert(&self.k)))
    }
    fn name(&self) -> String {
        format!("test-lobe({})", self.k)
    }
}

/// The triangle `a (1 − √u) + b √u (1 − v) + c √u v`.
#[derive(Clone, Debug)]
pub struct TestTriangle<T> {
    a: Vec3<T>,
    b: Vec3<T>,
    c: Vec3<T>,
    area: T,
}

impl<T: Real> TestTriangle<T> {
    pub fn new(a: Vec3<T>, b: Vec3<T>, c: Vec3<T>) -> Self {
        let area = b.sub(&a).cross(&c.sub(&a)).norm() / &T::from_i64(2);
        TestTriangle { a, b, c, area }
    }
}

impl<T: Real> Warp<T> for TestTriangle<T> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let su = u.sqrt();
        self.a
            .scale(&(T::one() - &su))
            .add(&self.b.scale(&(su.clone() * &(T::one() - v))))
            .add(&self.c.scale(&(su * v)))
    }
    fn pdf_unchecked(&self, _p: &Vec3<T>) -> T {
        T::one() / &self.area
    }
    fn measure(&self) -> T {
        self.area.clone()
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        let (beta, gamma) =
            coordinates(&p.sub(&self.a), &self.b.sub(&self.a), &self.c.sub(&self.a));
        let su = beta + &gamma;
        let v = if su > T::zero() {
            gamma / &su
        } else {
            T::zero()
        };
        Ok([su.square(), v])
    }
    fn outside_by(&self, _p: &Vec3<T>) -> T {
        T::zero()
    }
}

impl<T: Real> WarpFamily<T> for TestTriangle<T> {
    type At<S: Real> = TestTriangle<S>;
    fn at<S: Real>(&self) -> Result<TestTriangle<S>, WarpError> {
        Ok(TestTriangle::new(
            self.a.convert(),
            self.b.convert(),
            self.c.convert(),
        ))
    }
    fn name(&self) -> String {
        "test-triangle".into()
    }
}
