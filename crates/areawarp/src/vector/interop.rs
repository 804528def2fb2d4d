//! Conversions to and from the vector types renderers already use, each
//! behind its optional feature (none is part of the default build):
//!
//! | feature | types (both directions) |
//! |---|---|
//! | `mint` | `mint::Vector2<T>`, `mint::Point2<T>` ↔ [`Vec2<T>`]; `mint::Vector3<T>`, `mint::Point3<T>` ↔ [`Vec3<T>`] |
//! | `glam` | `glam::Vec2` ↔ `Vec2<f32>`, `glam::DVec2` ↔ `Vec2<f64>`, `glam::Vec3` and `glam::Vec3A` ↔ `Vec3<f32>`, `glam::DVec3` ↔ `Vec3<f64>` |
//! | `nalgebra` | `nalgebra::Vector2<T>`, `nalgebra::Point2<T>` ↔ [`Vec2<T>`]; `nalgebra::Vector3<T>`, `nalgebra::Point3<T>` ↔ [`Vec3<T>`] |
//!
//! All are plain `From` impls, so `.into()` works in both directions:
//! `let p: glam::Vec3 = warp.map(&u, &v).into();`.

#[allow(unused_imports)]
use super::{Vec2, Vec3};

#[cfg(feature = "mint")]
mod mint_impls {
    use super::{Vec2, Vec3};

    /// `From` both ways between a mint type and ours, field by field.
    macro_rules! mint_pair {
        ($M:ident, $V:ident { $($f:ident),+ }) => {
            impl<T> From<mint::$M<T>> for $V<T> {
                #[inline]
                fn from(m: mint::$M<T>) -> Self {
                    $V { $($f: m.$f),+ }
                }
            }
            impl<T> From<$V<T>> for mint::$M<T> {
                #[inline]
                fn from(v: $V<T>) -> Self {
                    mint::$M { $($f: v.$f),+ }
                }
            }
        };
    }
    mint_pair!(Vector2, Vec2 { x, y });
    mint_pair!(Point2, Vec2 { x, y });
    mint_pair!(Vector3, Vec3 { x, y, z });
    mint_pair!(Point3, Vec3 { x, y, z });
}

#[cfg(feature = "glam")]
mod glam_impls {
    use super::{Vec2, Vec3};

    /// `From` both ways between a glam type and ours over the scalar `$T`.
    macro_rules! glam_pair {
        ($G:ident, $V:ident<$T:ty> { $($f:ident),+ }) => {
            impl From<glam::$G> for $V<$T> {
                #[inline]
                fn from(g: glam::$G) -> Self {
                    $V { $($f: g.$f),+ }
                }
            }
            impl From<$V<$T>> for glam::$G {
                #[inline]
                fn from(v: $V<$T>) -> Self {
                    glam::$G::new($(v.$f),+)
                }
            }
        };
    }
    glam_pair!(Vec2, Vec2<f32> { x, y });
    glam_pair!(DVec2, Vec2<f64> { x, y });
    glam_pair!(Vec3, Vec3<f32> { x, y, z });
    glam_pair!(Vec3A, Vec3<f32> { x, y, z });
    glam_pair!(DVec3, Vec3<f64> { x, y, z });
}

#[cfg(feature = "nalgebra")]
mod nalgebra_impls {
    use super::{Vec2, Vec3};
    use nalgebra::Scalar;

    impl<T: Scalar> From<nalgebra::Vector2<T>> for Vec2<T> {
        #[inline]
        fn from(n: nalgebra::Vector2<T>) -> Self {
            let [x, y]: [T; 2] = n.into();
            Vec2 { x, y }
        }
    }
    impl<T: Scalar> From<Vec2<T>> for nalgebra::Vector2<T> {
        #[inline]
        fn from(v: Vec2<T>) -> Self {
            nalgebra::Vector2::new(v.x, v.y)
        }
    }
    impl<T: Scalar> From<nalgebra::Point2<T>> for Vec2<T> {
        #[inline]
        fn from(p: nalgebra::Point2<T>) -> Self {
            p.coords.into()
        }
    }
    impl<T: Scalar> From<Vec2<T>> for nalgebra::Point2<T> {
        #[inline]
        fn from(v: Vec2<T>) -> Self {
            nalgebra::Point2::new(v.x, v.y)
        }
    }
    impl<T: Scalar> From<nalgebra::Vector3<T>> for Vec3<T> {
        #[inline]
        fn from(n: nalgebra::Vector3<T>) -> Self {
            let [x, y, z]: [T; 3] = n.into();
            Vec3 { x, y, z }
        }
    }
    impl<T: Scalar> From<Vec3<T>> for nalgebra::Vector3<T> {
        #[inline]
        fn from(v: Vec3<T>) -> Self {
            nalgebra::Vector3::new(v.x, v.y, v.z)
        }
    }
    impl<T: Scalar> From<nalgebra::Point3<T>> for Vec3<T> {
        #[inline]
        fn from(p: nalgebra::Point3<T>) -> Self {
            p.coords.into()
        }
    }
    impl<T: Scalar> From<Vec3<T>> for nalgebra::Point3<T> {
        #[inline]
        fn from(v: Vec3<T>) -> Self {
            nalgebra::Point3::new(v.x, v.y, v.z)
        }
    }
}
