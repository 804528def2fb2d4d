//! Arithmetic operators and array conversions for [`Vec2`] and [`Vec3`].
//!
//! Every operator exists by value (`a + b`, `a * k`: for `f32`/`f64`, whose
//! vectors are `Copy`, this is what a renderer writes) and by reference
//! (`&a + &b`, `&a * &k`: for MPFR and dual numbers, which are not `Copy`,
//! so that nothing is cloned that need not be). Scalars multiply on the right
//! in generic code (`v * k`); `k * v` exists for `f32` and `f64`.

use super::{Vec2, Vec3};
use crate::real::Real;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Implements the component-wise operators for a vector type with the given
/// fields.
macro_rules! vector_ops {
    ($V:ident { $($f:ident),+ }) => {
        impl<T: Real> Add for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn add(self, o: $V<T>) -> $V<T> {
                $V { $($f: self.$f + o.$f),+ }
            }
        }
        impl<T: Real> Add<&$V<T>> for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn add(self, o: &$V<T>) -> $V<T> {
                $V { $($f: self.$f + &o.$f),+ }
            }
        }
        impl<T: Real> Add for &$V<T> {
            type Output = $V<T>;
            #[inline]
            fn add(self, o: &$V<T>) -> $V<T> {
                $V { $($f: self.$f.clone() + &o.$f),+ }
            }
        }
        impl<T: Real> Sub for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn sub(self, o: $V<T>) -> $V<T> {
                $V { $($f: self.$f - o.$f),+ }
            }
        }
        impl<T: Real> Sub<&$V<T>> for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn sub(self, o: &$V<T>) -> $V<T> {
                $V { $($f: self.$f - &o.$f),+ }
            }
        }
        impl<T: Real> Sub for &$V<T> {
            type Output = $V<T>;
            #[inline]
            fn sub(self, o: &$V<T>) -> $V<T> {
                $V { $($f: self.$f.clone() - &o.$f),+ }
            }
        }
        impl<T: Real> Neg for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn neg(self) -> $V<T> {
                $V { $($f: -self.$f),+ }
            }
        }
        impl<T: Real> Neg for &$V<T> {
            type Output = $V<T>;
            #[inline]
            fn neg(self) -> $V<T> {
                $V { $($f: -self.$f.clone()),+ }
            }
        }
        impl<T: Real> Mul<T> for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn mul(self, k: T) -> $V<T> {
                $V { $($f: self.$f * &k),+ }
            }
        }
        impl<T: Real> Mul<&T> for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn mul(self, k: &T) -> $V<T> {
                $V { $($f: self.$f * k),+ }
            }
        }
        impl<T: Real> Mul<&T> for &$V<T> {
            type Output = $V<T>;
            #[inline]
            fn mul(self, k: &T) -> $V<T> {
                $V { $($f: self.$f.clone() * k),+ }
            }
        }
        impl<T: Real> Div<T> for $V<T> {
            type Output = $V<T>;
            /// Divides every coordinate by `k` (no reciprocal: exact where the
            /// quotients are, and no overflow of `1/k` for subnormal `k`).
            #[inline]
            fn div(self, k: T) -> $V<T> {
                $V { $($f: self.$f / &k),+ }
            }
        }
        impl<T: Real> Div<&T> for $V<T> {
            type Output = $V<T>;
            #[inline]
            fn div(self, k: &T) -> $V<T> {
                $V { $($f: self.$f / k),+ }
            }
        }
        impl<T: Real> Div<&T> for &$V<T> {
            type Output = $V<T>;
            #[inline]
            fn div(self, k: &T) -> $V<T> {
                $V { $($f: self.$f.clone() / k),+ }
            }
        }
        impl<T: Real> AddAssign for $V<T> {
            #[inline]
            fn add_assign(&mut self, o: $V<T>) {
                $(self.$f += o.$f;)+
            }
        }
        impl<T: Real> AddAssign<&$V<T>> for $V<T> {
            #[inline]
            fn add_assign(&mut self, o: &$V<T>) {
                $(self.$f += &o.$f;)+
            }
        }
        impl<T: Real> SubAssign for $V<T> {
            #[inline]
            fn sub_assign(&mut self, o: $V<T>) {
                $(self.$f -= o.$f;)+
            }
        }
        impl<T: Real> SubAssign<&$V<T>> for $V<T> {
            #[inline]
            fn sub_assign(&mut self, o: &$V<T>) {
                $(self.$f -= &o.$f;)+
            }
        }
        impl<T: Real> MulAssign<T> for $V<T> {
            #[inline]
            fn mul_assign(&mut self, k: T) {
                $(self.$f *= &k;)+
            }
        }
        impl<T: Real> MulAssign<&T> for $V<T> {
            #[inline]
            fn mul_assign(&mut self, k: &T) {
                $(self.$f *= k;)+
            }
        }
        impl<T: Real> DivAssign<T> for $V<T> {
            #[inline]
            fn div_assign(&mut self, k: T) {
                $(self.$f /= &k;)+
            }
        }
        impl<T: Real> DivAssign<&T> for $V<T> {
            #[inline]
            fn div_assign(&mut self, k: &T) {
                $(self.$f /= k;)+
            }
        }
        impl Mul<$V<f32>> for f32 {
            type Output = $V<f32>;
            #[inline]
            fn mul(self, v: $V<f32>) -> $V<f32> {
                v * self
            }
        }
        impl Mul<$V<f64>> for f64 {
            type Output = $V<f64>;
            #[inline]
            fn mul(self, v: $V<f64>) -> $V<f64> {
                v * self
            }
        }
    };
}

vector_ops!(Vec2 { x, y });
vector_ops!(Vec3 { x, y, z });

impl<T> From<[T; 2]> for Vec2<T> {
    #[inline]
    fn from([x, y]: [T; 2]) -> Self {
        Vec2 { x, y }
    }
}

impl<T> From<Vec2<T>> for [T; 2] {
    #[inline]
    fn from(v: Vec2<T>) -> Self {
        [v.x, v.y]
    }
}

impl<T> From<[T; 3]> for Vec3<T> {
    #[inline]
    fn from([x, y, z]: [T; 3]) -> Self {
        Vec3 { x, y, z }
    }
}

impl<T> From<Vec3<T>> for [T; 3] {
    #[inline]
    fn from(v: Vec3<T>) -> Self {
        [v.x, v.y, v.z]
    }
}

impl<T> From<(T, T)> for Vec2<T> {
    #[inline]
    fn from((x, y): (T, T)) -> Self {
        Vec2 { x, y }
    }
}

impl<T> From<(T, T, T)> for Vec3<T> {
    #[inline]
    fn from((x, y, z): (T, T, T)) -> Self {
        Vec3 { x, y, z }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real::Dual2;

    #[test]
    fn by_value_operators_f32() {
        let a = Vec3::new(1.0f32, 2.0, 3.0);
        let b = Vec3::from([0.5f32, -1.0, 4.0]);
        // Copy: `a` and `b` stay usable after being moved into operators.
        assert_eq!(a + b, Vec3::new(1.5, 1.0, 7.0));
        assert_eq!(a - b, Vec3::new(0.5, 3.0, -1.0));
        assert_eq!(-a, Vec3::new(-1.0, -2.0, -3.0));
        assert_eq!(a * 2.0, Vec3::new(2.0, 4.0, 6.0));
        assert_eq!(2.0 * a, a * 2.0);
        assert_eq!(a / 2.0, Vec3::new(0.5, 1.0, 1.5));
        let mut c = a;
        c += b;
        c -= a;
        assert_eq!(c, b);
        c *= 4.0;
        c /= 2.0;
        assert_eq!(c, b * 2.0);
        assert_eq!(<[f32; 3]>::from(a), [1.0, 2.0, 3.0]);
        let arr: [f32; 3] = b.into();
        assert_eq!(Vec3::from(arr), b);
    }

    #[test]
    fn vec2_operators_f64() {
        let a = Vec2::new(1.0f64, -2.0);
        let b: Vec2<f64> = [3.0, 5.0].into();
        assert_eq!(a + b, Vec2::new(4.0, 3.0));
        assert_eq!(b - a, Vec2::new(2.0, 7.0));
        assert_eq!(-b, Vec2::new(-3.0, -5.0));
        assert_eq!(0.5 * b, Vec2::new(1.5, 2.5));
        assert_eq!(b / 2.0, Vec2::new(1.5, 2.5));
        let mut c = a;
        c += &b;
        c -= &b;
        c *= &3.0;
        c /= &3.0;
        assert_eq!(c, a);
        assert_eq!(<[f64; 2]>::from(a), [1.0, -2.0]);
        assert_eq!(Vec2::from((1.0, -2.0)), a);
    }

    /// Non-`Copy` scalars: the by-reference operators leave their operands
    /// intact and agree with the by-value ones and the named methods.
    #[test]
    fn by_reference_operators_dual() {
        let d = |x: f64| Dual2::constant(x);
        let a = Vec3::new(d(1.0), d(2.0), d(3.0));
        let b = Vec3::new(d(-4.0), d(0.5), d(2.0));
        let k = d(3.0);
        // The named methods, by path: with `core::ops` imported, method
        // syntax `a.add(&b)` would pick the (by-value) operator trait.
        assert_eq!(&a + &b, Vec3::add(&a, &b));
        assert_eq!(&a - &b, Vec3::sub(&a, &b));
        assert_eq!(&a * &k, a.scale(&k));
        assert_eq!(&(&a * &k) / &k, a);
        assert_eq!(-&a, Vec3::neg(&a));
        assert_eq!(a.clone() + &b, &a + &b);
        assert_eq!(a.clone() - &b, &a - &b);
        assert_eq!(a.clone() * &k, &a * &k);
        assert_eq!(a.clone() / &k, &a / &k);
        let mut c = a.clone();
        c += &b;
        c -= &a;
        assert_eq!(c, b);
        c *= &k;
        c /= k.clone();
        assert_eq!(c, b);
        c *= k.clone();
        assert_eq!(c, &b * &k);
        let arr: [Dual2<f64>; 3] = a.clone().into();
        assert_eq!(Vec3::from(arr), a);
    }

    #[test]
    fn is_zero_by_comparisons() {
        assert!(Vec3::new(0.0, -0.0, 0.0).is_zero());
        assert!(Vec3::<f64>::zero().is_zero());
        for v in [
            Vec3::new(0.0, 0.0, 5e-324),
            Vec3::new(-1e-300, 0.0, 0.0),
            Vec3::new(0.0, f64::NAN, 0.0),
            Vec3::new(f64::INFINITY, 0.0, 0.0),
        ] {
            assert!(!v.is_zero(), "{v:?}");
        }
        // Where `max_abs` passes over the NaN and reads 0.
        assert_eq!(Vec3::new(0.0, f64::NAN, 0.0).max_abs(), 0.0);
    }
}
