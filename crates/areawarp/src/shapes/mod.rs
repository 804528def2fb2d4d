//! The analytic warps.
mod concentric_disk;
mod disk;
mod hemisphere;
mod phong;
mod planar_triangle;
pub mod polygon_measures;
mod projected_polygon;
mod sphere;
mod spherical_rectangle;
mod spherical_triangle;
mod turns;
mod wide;
pub use concentric_disk::ConcentricDisk;
pub use disk::{PolarDisk, PolarDiskRecipe};
pub use hemisphere::{Hemisphere, HemisphereRecipe};
pub use phong::{PhongLobe, PhongRecipe};
pub use planar_triangle::{PlanarTriangle, PlanarTriangleRecipe};
pub use projected_polygon::{MarginalInversion, ProjectedPolygon};
pub use sphere::{Sphere, SphereRecipe};
pub use spherical_rectangle::{
    SphericalRectangle, SphericalRectangleRecipe, SphericalRectangleVariant, hard_rectangles,
    ordinary_rectangles,
};
pub use spherical_triangle::{
    SphericalTriangle, SphericalTriangleRecipe, SphericalTriangleVariant, hard_triangles,
    ordinary_triangles,
};
