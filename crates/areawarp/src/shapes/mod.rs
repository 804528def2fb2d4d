//! The analytic warps.
mod beckmann;
mod bilinear;
mod concentric_disk;
mod disk;
mod ggx;
mod hemisphere;
mod light_plane;
pub(crate) mod local_frame;
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
pub(crate) mod turns;
mod uniform_cone;
mod von_mises_fisher;
mod wide;
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
pub use sphere_light::{SphereLight, sphere_light_ladder};
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
