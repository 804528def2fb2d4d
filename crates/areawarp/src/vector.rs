//! The crate's one vector type family: small vectors over any [`Real`],
//! [`Vec2`] for planar points and [`Vec3`] for points in space.
//!
//! Own types rather than nalgebra's: every operation here works with
//! non-`Copy` scalars (MPFR, dual numbers) through references, and the set of
//! operations a warp needs is small. For `f32`/`f64` they behave like a
//! renderer's vectors: `Copy`, with operators by value (`a + b`, `a * k`,
//! `-a`, `a += b`; by reference `&a + &b`, `&a * &k` for every [`Real`]),
//! `From`/`Into` arrays `[T; 2]`/`[T; 3]` (and tuples), and, behind the
//! optional features `mint`, `glam` and `nalgebra`, `From`/`Into` the
//! vector and point types of those crates.
//!
//! ```
//! use areawarp::Vec3;
//! let a = Vec3::from([1.0f32, 2.0, 3.0]);
//! let b = Vec3::new(0.5f32, 0.5, 0.5);
//! let c = (a - b) * 2.0 + -b;
//! let arr: [f32; 3] = c.into();
//! assert_eq!(arr, [0.5, 2.5, 4.5]);
//! assert_eq!(a.dot(&b), 3.0); // a and b are Copy: still usable
//! ```

mod interop;
mod ops;

use crate::real::Real;

/// A point or vector in the plane (`Copy` when `T` is).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec2<T> {
    /// First coordinate.
    pub x: T,
    /// Second coordinate.
    pub y: T,
}

/// A point or vector in space (`Copy` when `T` is).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3<T> {
    /// First coordinate.
    pub x: T,
    /// Second coordinate.
    pub y: T,
    /// Third coordinate.
    pub z: T,
}

impl<T: Real> Vec2<T> {
    /// A vector from its coordinates.
    pub fn new(x: T, y: T) -> Self {
        Vec2 { x, y }
    }
    /// `self + o`.
    pub fn add(&self, o: &Self) -> Self {
        Vec2::new(self.x.clone() + &o.x, self.y.clone() + &o.y)
    }
    /// `self − o`.
    pub fn sub(&self, o: &Self) -> Self {
        Vec2::new(self.x.clone() - &o.x, self.y.clone() - &o.y)
    }
    /// `k · self`.
    pub fn scale(&self, k: &T) -> Self {
        Vec2::new(self.x.clone() * k, self.y.clone() * k)
    }
    /// Dot product.
    pub fn dot(&self, o: &Self) -> T {
        self.x.clone() * &o.x + &(self.y.clone() * &o.y)
    }
    /// The 2-D cross product (determinant `[self o]`).
    pub fn cross(&self, o: &Self) -> T {
        self.x.clone() * &o.y - &(self.y.clone() * &o.x)
    }
    /// Euclidean length.
    pub fn norm(&self) -> T {
        self.x.hypot(&self.y)
    }
    /// Embeds into space with `z = 0`.
    pub fn to_vec3(&self) -> Vec3<T> {
        Vec3::new(self.x.clone(), self.y.clone(), T::zero())
    }
}

impl<T: Real> Vec3<T> {
    /// A vector from its coordinates.
    pub fn new(x: T, y: T, z: T) -> Self {
        Vec3 { x, y, z }
    }
    /// The zero vector.
    pub fn zero() -> Self {
        Vec3::new(T::zero(), T::zero(), T::zero())
    }
    /// A vector from `f64` data (see [`Real::from_f64`]).
    pub fn from_f64(x: f64, y: f64, z: f64) -> Self {
        Vec3::new(T::from_f64(x), T::from_f64(y), T::from_f64(z))
    }
    /// The coordinates as an array.
    pub fn to_array(&self) -> [T; 3] {
        [self.x.clone(), self.y.clone(), self.z.clone()]
    }
    /// `self + o`.
    pub fn add(&self, o: &Self) -> Self {
        Vec3::new(
            self.x.clone() + &o.x,
            self.y.clone() + &o.y,
            self.z.clone() + &o.z,
        )
    }
    /// `self − o`.
    pub fn sub(&self, o: &Self) -> Self {
        Vec3::new(
            self.x.clone() - &o.x,
            self.y.clone() - &o.y,
            self.z.clone() - &o.z,
        )
    }
    /// `k · self`.
    pub fn scale(&self, k: &T) -> Self {
        Vec3::new(self.x.clone() * k, self.y.clone() * k, self.z.clone() * k)
    }
    /// `−self`.
    pub fn neg(&self) -> Self {
        Vec3::new(-self.x.clone(), -self.y.clone(), -self.z.clone())
    }
    /// Dot product.
    pub fn dot(&self, o: &Self) -> T {
        self.x.clone() * &o.x + &(self.y.clone() * &o.y) + &(self.z.clone() * &o.z)
    }
    /// Cross product.
    pub fn cross(&self, o: &Self) -> Self {
        Vec3::new(
            self.y.clone() * &o.z - &(self.z.clone() * &o.y),
            self.z.clone() * &o.x - &(self.x.clone() * &o.z),
            self.x.clone() * &o.y - &(self.y.clone() * &o.x),
        )
    }
    /// Squared length.
    pub fn norm_squared(&self) -> T {
        self.dot(self)
    }
    /// Euclidean length, without undue overflow or underflow.
    pub fn norm(&self) -> T {
        self.x.hypot(&self.y).hypot(&self.z)
    }
    /// Largest absolute coordinate.
    pub fn max_abs(&self) -> T {
        self.x.abs().max(&self.y.abs()).max(&self.z.abs())
    }
    /// `self / |self|`, or `None` for the zero vector or non-finite input.
    pub fn normalized(&self) -> Option<Self> {
        // Divide (rather than multiply by 1/n, which overflows for subnormal
        // vectors); `norm` itself neither overflows nor underflows.
        let n = self.norm();
        if n.is_finite_above(&T::zero()) {
            Some(Vec3::new(
                self.x.clone() / &n,
                self.y.clone() / &n,
                self.z.clone() / &n,
            ))
        } else {
            None
        }
    }
    /// `true` if every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
    /// `true` if every coordinate is zero (of either sign; `false` with a
    /// NaN): three comparisons, where `max_abs() == 0` takes NaN-aware
    /// maxima.
    pub fn is_zero(&self) -> bool {
        let zero = T::zero();
        self.x == zero && self.y == zero && self.z == zero
    }
    /// Linear interpolation `(1 − t)·self + t·o`.
    pub fn lerp(&self, o: &Self, t: &T) -> Self {
        self.scale(&(T::one() - t)).add(&o.scale(t))
    }
    /// Converts every coordinate to another scalar type (see [`crate::real::convert`]).
    pub fn convert<S: Real>(&self) -> Vec3<S> {
        Vec3::new(
            crate::real::convert(&self.x),
            crate::real::convert(&self.y),
            crate::real::convert(&self.z),
        )
    }
}

/// The points a warp can return: [`Vec2`] (planar shapes) or [`Vec3`].
///
/// The harness works on the 3-D embedding (`z = 0` for planar points), where
/// the area element is `|ψ_u × ψ_v|` in both cases.
pub trait Coords<T: Real>: Clone + core::fmt::Debug {
    /// Number of coordinates printed or parsed (2 or 3).
    const DIM: usize;
    /// The point in space (`z = 0` for planar points).
    fn to_vec3(&self) -> Vec3<T>;
    /// The point from its first `DIM` coordinates in space.
    fn from_vec3(v: Vec3<T>) -> Self;
}

impl<T: Real> Coords<T> for Vec2<T> {
    const DIM: usize = 2;
    fn to_vec3(&self) -> Vec3<T> {
        Vec2::to_vec3(self)
    }
    fn from_vec3(v: Vec3<T>) -> Self {
        Vec2::new(v.x, v.y)
    }
}

impl<T: Real> Coords<T> for Vec3<T> {
    const DIM: usize = 3;
    fn to_vec3(&self) -> Vec3<T> {
        self.clone()
    }
    fn from_vec3(v: Vec3<T>) -> Self {
        v
    }
}

/// A right-handed orthonormal frame `(tangent, bitangent, normal)`:
/// `tangent × bitangent = normal`.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// First in-plane axis (local `x`).
    pub tangent: Vec3<f64>,
    /// Second in-plane axis (local `y`).
    pub bitangent: Vec3<f64>,
    /// The normal (local `z`).
    pub normal: Vec3<f64>,
}

impl Frame {
    /// Completes the direction `normal` (normalized here) to a frame
    /// (Duff et al. 2017, "Building an orthonormal basis, revisited"),
    /// continuous except across `normal.z = 0` with `normal.z` changing sign.
    ///
    /// # Errors
    /// [`crate::error::WarpError::Degenerate`] for a zero or non-finite normal.
    pub fn from_normal(normal: &Vec3<f64>) -> Result<Self, crate::error::WarpError> {
        let n = normal.normalized().filter(Vec3::is_finite).ok_or(
            crate::error::WarpError::Degenerate {
                what: "zero or non-finite normal",
            },
        )?;
        let f = crate::shapes::local_frame::LocalFrame::about_unit(n);
        Ok(Frame {
            tangent: f.e1,
            bitangent: f.e2,
            normal: f.axis,
        })
    }

    /// World → local coordinates.
    pub fn to_local(&self, w: &Vec3<f64>) -> Vec3<f64> {
        Vec3::new(
            w.dot(&self.tangent),
            w.dot(&self.bitangent),
            w.dot(&self.normal),
        )
    }

    /// Local → world coordinates.
    pub fn to_world(&self, l: &Vec3<f64>) -> Vec3<f64> {
        self.tangent
            .scale(&l.x)
            .add(&self.bitangent.scale(&l.y))
            .add(&self.normal.scale(&l.z))
    }
}
