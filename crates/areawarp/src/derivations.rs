//! The derivations behind every warp, one page each: the five steps of
//! Arvo's recipe worked out for the shape, the numerical reformulations the
//! code uses instead of the papers' literal formulas, and the measured
//! accuracy. They are the files of the crate's `docs/` folder, included
//! here so that they are part of the rustdoc.
//!
//! | page | shape |
//! |---|---|
//! | [`recipe`] | Arvo's five-step recipe and which trait is which; warps derived from φ and w alone, and what they cost. |
//! | [`recipe_quadrature`] | Steps 2–4 executed: the adaptive quadrature, the inversion and the tabulated inverses, with their error control. |
//! | [`planar_triangle`] | The planar triangle. |
//! | [`disk`] | The polar and concentric disks. |
//! | [`hemisphere`] | The uniform hemisphere. |
//! | [`phong`] | The Phong lobe (cosine-power hemisphere). |
//! | [`sphere`] | The sphere by Archimedes' theorem (Shao and Badler 1996). |
//! | [`quarter_turns`] | The azimuth `2πv`: exact quarter-turn reduction and the `f32`/`f64` sine–cosine kernels of the reduced angle. |
//! | [`spherical_triangle`] | The spherical triangle (Arvo 1995), literal and robust. |
//! | [`spherical_triangle_one_shot`] | The spherical triangle's one-shot sample and solid angle: their cost, and the rounds of work on it. |
//! | [`spherical_rectangle`] | The spherical rectangle (Ureña, Fajardo and King 2013), literal and robust. |
//! | [`projected_polygon`] | The projected spherical polygon: cosine-weighted sampling (Arvo 2001). |
//! | [`projected_polygon_cost`] | The projected polygon's construction cost, and the rounds of work on it. |
//! | [`adaptive_triangle`] | Ureña's (2000) adaptive triangle sampler and its variance bound. |
//! | [`precision_choice`] | The light shapes in `f32` (decisions in the wide type) and the precision chosen per shape from its conditioning. |
//! | [`uniform_cone`] | The uniform cone (spherical cap). |
//! | [`sphere_light`] | A sphere seen from a point: directions in the subtended cone and their hit points. |
//! | [`spherical_lune`] | The spherical lune between two great circles. |
//! | [`von_mises_fisher`] | The von Mises–Fisher distribution, κ from 0 to 10⁶. |
//! | [`microfacet`] | The Beckmann and GGX microfacet normal distributions. |
//! | [`planar_densities`] | The bilinear, tent and standard normal densities on the plane. |

#[doc = include_str!("../docs/recipe.md")]
pub mod recipe {}

#[doc = include_str!("../docs/recipe-quadrature.md")]
pub mod recipe_quadrature {}

#[doc = include_str!("../docs/planar-triangle.md")]
pub mod planar_triangle {}

#[doc = include_str!("../docs/disk.md")]
pub mod disk {}

#[doc = include_str!("../docs/hemisphere.md")]
pub mod hemisphere {}

#[doc = include_str!("../docs/phong.md")]
pub mod phong {}

#[doc = include_str!("../docs/sphere.md")]
pub mod sphere {}

#[doc = include_str!("../docs/quarter-turns.md")]
pub mod quarter_turns {}

#[doc = include_str!("../docs/spherical-triangle.md")]
pub mod spherical_triangle {}

#[doc = include_str!("../docs/spherical-triangle-one-shot.md")]
pub mod spherical_triangle_one_shot {}

#[doc = include_str!("../docs/spherical-rectangle.md")]
pub mod spherical_rectangle {}

#[doc = include_str!("../docs/projected-polygon.md")]
pub mod projected_polygon {}

#[doc = include_str!("../docs/projected-polygon-cost.md")]
pub mod projected_polygon_cost {}

#[doc = include_str!("../docs/adaptive-triangle.md")]
pub mod adaptive_triangle {}

#[doc = include_str!("../docs/precision-choice.md")]
pub mod precision_choice {}
#[doc = include_str!("../docs/uniform-cone.md")]
pub mod uniform_cone {}

#[doc = include_str!("../docs/sphere-light.md")]
pub mod sphere_light {}

#[doc = include_str!("../docs/spherical-lune.md")]
pub mod spherical_lune {}

#[doc = include_str!("../docs/von-mises-fisher.md")]
pub mod von_mises_fisher {}

#[doc = include_str!("../docs/microfacet.md")]
pub mod microfacet {}

#[doc = include_str!("../docs/planar-densities.md")]
pub mod planar_densities {}
