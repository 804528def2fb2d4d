//! The analytic warps.

/// `rand::distr::Distribution` directly on the `f32`/`f64` warps (so that
/// `warp.sample(&mut rng)` works): ψ(u, v) of two uniform `[0, 1)` numbers.
/// `crate::sampling::WarpSampler` wraps any warp the same way.
macro_rules! impl_distribution {
    ($warp:ident, $point:ident) => {
        impl_distribution!(@one $warp, $point, f32);
        impl_distribution!(@one $warp, $point, f64);
    };
    (@one $warp:ident, $point:ident, $t:ty) => {
        impl rand::distr::Distribution<$crate::vector::$point<$t>> for $warp<$t> {
            /// ψ(u, v) of two uniform `[0, 1)` numbers drawn from `rng`.
            fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> $crate::vector::$point<$t> {
                use rand::RngExt;
                let u: $t = rng.random();
                let v: $t = rng.random();
                $crate::warp::Warp::map(self, &u, &v)
            }
        }
    };
}
pub(crate) use impl_distribution;

mod beckmann;
mod bilinear;
mod concentric_disk;
mod disk;
mod ggx;
mod hemisphere;
mod local_frame;
mod phong;
mod planar_triangle;
pub mod polygon_measures;
mod projected_polygon;
mod sphere;
mod sphere_light;
mod spherical_lune;
mod spherical_rectangle;
mod spherical_triangle;
mod std_normal;
mod tent;
#[cfg(test)]
mod test_support;
mod turns;
mod uniform_cone;
mod von_mises_fisher;
pub use beckmann::{Beckmann, BeckmannRecipe};
pub use bilinear::{Bilinear, BilinearRecipe};
pub use concentric_disk::ConcentricDisk;
pub use disk::{PolarDisk, PolarDiskRecipe};
pub use ggx::{Ggx, GgxRecipe};
pub use hemisphere::{Hemisphere, HemisphereRecipe};
pub use phong::{PhongLobe, PhongRecipe};
pub use planar_triangle::{PlanarTriangle, PlanarTriangleRecipe, PlanarTriangleVariant};
pub use projected_polygon::{MarginalInversion, ProjectedPolygon};
pub use sphere::{Sphere, SphereRecipe};
pub use sphere_light::{SphereLight, SphereLightSample, sphere_light_ladder};
pub use spherical_lune::{SphericalLune, lune_catalogue};
pub use spherical_rectangle::{
    SphericalRectangle, SphericalRectangleRecipe, SphericalRectangleVariant, hard_rectangles,
    ordinary_rectangles,
};
pub use spherical_triangle::{
    SphericalTriangle, SphericalTriangleRecipe, SphericalTriangleVariant, hard_triangles,
    ordinary_triangles,
};
pub use std_normal::StdNormal;
pub use tent::Tent;
pub use uniform_cone::{UniformCone, UniformConeRecipe};
pub use von_mises_fisher::VonMisesFisher;
