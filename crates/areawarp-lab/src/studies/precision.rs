//! Study 1, *precision*: every warp × variant × {`f32`, `f64`} against the
//! exact map at 256 bits, on the extremes suite (the extremes grid plus
//! random points), over every shape of the warp's test set — for the
//! solid-angle maps, their ordinary shapes and the whole hard ladders
//! ([`hard_triangles`], [`hard_rectangles`]).
//!
//! For each warp, variant, shape and scalar `T` the study measures, at each
//! input point `(u, v)` rounded to `T`:
//!
//! - the **error** `‖ψ_T(u, v) − ψ_exact(u, v)‖_∞ / extent` in units of
//!   `T`'s unit roundoff `u_T` (`2⁻²⁴`, `2⁻⁵³`), where `ψ_exact` is the
//!   *exact* map of the shape as `T` sees it (parameters rounded to `T`),
//!   evaluated at 256 bits: the robust variant for the spherical triangle
//!   and rectangle, Newton to convergence for the projected polygon. For a
//!   literal variant or a truncated inversion this error includes what the
//!   variant gets wrong at any precision (the literal rectangle's cut-off,
//!   the cubic's bias); the column *own* isolates the rounding error by
//!   comparing with the variant's own map at 256 bits;
//! - the **NaN/∞** outputs, and the points **outside** the shape by more
//!   than [`OUTSIDE_TOLERANCE_ULPS`]` · u_T · extent`;
//! - the **κ-conditioned ratio** error / (16 · max(u_T, κ)), κ the move of
//!   the exact map under a one-ulp change of one input (the shape's
//!   parameters, `u`, `v`; [`sensitivities_in`]): at most 1 means the map is
//!   as accurate as its inputs allow (the criterion of
//!   [`check_precision_conditioned`](areawarp::harness::sensitivity::check_precision_conditioned));
//! - the **Jacobian deviation** `max |J · pdf − 1|` of the variant's map at
//!   256 bits with exact partials ([`check_jacobian`]) — independent of `T`;
//!   a literal variant or a truncated inversion that is not area-preserving
//!   shows here at any precision.
//!
//! Plus *where the `f32` error lives*: per warp, the `f32` error (in units of
//! `2⁻²⁴`) over a fine grid of nodes `(i/(n−1), j/(n−1))` of `[0, 1]²`,
//! written as heat maps ([`PrecisionStudy::write_figures`]).
//!
//! The study is deterministic: the cells are independent jobs run by
//! [`run_jobs`] and collected in job order, so the result is the same for
//! any number of threads.
//!
//! # Example
//! ```no_run
//! use areawarp_lab::studies::precision::{run, PrecisionConfig};
//! let study = run(&PrecisionConfig::quick())?;
//! println!("{}", study.to_markdown());
//! # Ok::<(), areawarp::WarpError>(())
//! ```

use crate::figures::{Axis, Figure, HeatMap, Scale, write_heat_map_svg};
use crate::jobs::run_jobs;
use areawarp::error::WarpError;
use areawarp::harness::extremes::{extremes_grid, random_points};
use areawarp::harness::jacobian::check_jacobian;
use areawarp::harness::precision::OUTSIDE_TOLERANCE_ULPS;
use areawarp::harness::sensitivity::{InputFormat, accuracy_bound, sensitivities_in};
use areawarp::real::{Mpfr256, Real, convert};
use areawarp::shapes::{
    Beckmann, Bilinear, ConcentricDisk, Ggx, Hemisphere, MarginalInversion, PhongLobe,
    PlanarTriangle, PlanarTriangleVariant, PolarDisk, ProjectedPolygon, Sphere, SphereLight,
    SphericalLune, SphericalRectangle, SphericalRectangleVariant, SphericalTriangle,
    SphericalTriangleVariant, StdNormal, Tent, UniformCone, VonMisesFisher, hard_rectangles,
    hard_triangles, lune_catalogue, ordinary_rectangles, ordinary_triangles, sphere_light_ladder,
};
use areawarp::vector::{Coords, Vec3};
use areawarp::warp::{Warp, WarpFamily};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// The 256-bit reference scalar.
type M = Mpfr256;

// ---------------------------------------------------------------------------
// The catalogue: warps, variants, shapes
// ---------------------------------------------------------------------------

/// A warp built in `f64`, one variant per enum case's value.
// A few dozen values, built once per study: boxing would buy nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub(crate) enum Built {
    PlanarTriangle(PlanarTriangle<f64>),
    PolarDisk(PolarDisk<f64>),
    ConcentricDisk(ConcentricDisk<f64>),
    Hemisphere(Hemisphere<f64>),
    Phong(PhongLobe<f64>),
    Sphere(Sphere<f64>),
    SphericalTriangle(SphericalTriangle<f64>),
    SphericalRectangle(SphericalRectangle<f64>),
    ProjectedPolygon(ProjectedPolygon<f64>),
    UniformCone(UniformCone<f64>),
    SphereLight(SphereLight<f64>),
    SphericalLune(SphericalLune<f64>),
    VonMisesFisher(VonMisesFisher<f64>),
    Beckmann(Beckmann<f64>),
    Ggx(Ggx<f64>),
    Bilinear(Bilinear<f64>),
    Tent(Tent<f64>),
    StdNormal(StdNormal<f64>),
}

/// Runs `$body` with `$w` bound to the concrete warp inside a [`Built`]
/// (the body is instantiated once per warp type).
macro_rules! with_warp {
    ($built:expr, |$w:ident| $body:expr) => {
        match $built {
            Built::PlanarTriangle($w) => $body,
            Built::PolarDisk($w) => $body,
            Built::ConcentricDisk($w) => $body,
            Built::Hemisphere($w) => $body,
            Built::Phong($w) => $body,
            Built::Sphere($w) => $body,
            Built::SphericalTriangle($w) => $body,
            Built::SphericalRectangle($w) => $body,
            Built::ProjectedPolygon($w) => $body,
            Built::UniformCone($w) => $body,
            Built::SphereLight($w) => $body,
            Built::SphericalLune($w) => $body,
            Built::VonMisesFisher($w) => $body,
            Built::Beckmann($w) => $body,
            Built::Ggx($w) => $body,
            Built::Bilinear($w) => $body,
            Built::Tent($w) => $body,
            Built::StdNormal($w) => $body,
        }
    };
}
pub(crate) use with_warp;

/// One shape of one warp, in all the warp's variants (the first is the
/// exact one, the reference of the others).
#[derive(Clone, Debug)]
pub(crate) struct ShapeEntry {
    /// The warp's label (one of [`WARPS`]).
    pub warp: &'static str,
    /// The shape's label.
    pub shape: String,
    /// `true` for a shape of a hard ladder.
    pub hard: bool,
    /// The shape's parameters as given (`f64` data), for κ.
    pub raw: Vec<f64>,
    /// `(variant label, warp)`; the first is the exact variant.
    pub variants: Vec<(&'static str, Built)>,
}

/// The warps of the studies, in report order.
pub const WARPS: [&str; 18] = [
    "planar-triangle",
    "polar-disk",
    "concentric-disk",
    "hemisphere",
    "phong",
    "sphere",
    "spherical-triangle",
    "spherical-rectangle",
    "projected-polygon",
    "uniform-cone",
    "sphere-light",
    "spherical-lune",
    "von-mises-fisher",
    "beckmann",
    "ggx",
    "bilinear",
    "tent",
    "std-normal",
];

/// The variant labels of the projected polygon's marginal inversion
/// settings, and the settings.
pub const POLYGON_SETTINGS: [(&str, MarginalInversion); 5] = [
    ("Newton", MarginalInversion::Newton),
    ("cubic", MarginalInversion::Cubic),
    ("cubic+1 Newton", MarginalInversion::CubicNewton(1)),
    ("cubic+2 Newton", MarginalInversion::CubicNewton(2)),
    ("cubic+3 Newton", MarginalInversion::CubicNewton(3)),
];

/// Every warp with its variant labels (the exact variant first): the rows
/// the studies' tables cover, per scalar type.
///
/// - `closed form`: the shape's only evaluation;
/// - sphere: `+z axis` (Archimedes) and `tilted axis`
///   ([`Sphere::with_axis`], the Shao–Badler random-axis option at a fixed
///   generic axis);
/// - spherical triangle and rectangle: `robust` (default) and `literal`
///   (the published algorithm);
/// - projected polygon: the [`MarginalInversion`] settings
///   ([`POLYGON_SETTINGS`]).
pub fn warp_variants() -> Vec<(&'static str, Vec<&'static str>)> {
    WARPS
        .iter()
        .map(|&w| {
            let v: Vec<&'static str> = match w {
                "sphere" => vec!["+z axis", "tilted axis"],
                "planar-triangle" => vec!["closed form", "fold"],
                "spherical-triangle" | "spherical-rectangle" => vec!["robust", "literal"],
                "projected-polygon" => POLYGON_SETTINGS.iter().map(|s| s.0).collect(),
                _ => vec!["closed form"],
            };
            (w, v)
        })
        .collect()
}

/// The test polygons of the projected-polygon map (vertices as points seen
/// from the origin, receiver normal `+z`): a convex quadrilateral, a
/// non-convex comb, a pentagon around the pole, a rectangle crossing the
/// horizon (clipped) and a triangle with a vertex at the pole.
pub fn test_polygons() -> Vec<(String, Vec<Vec3<f64>>)> {
    let v = |p: &[[f64; 3]]| -> Vec<Vec3<f64>> {
        p.iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect()
    };
    let pentagon: Vec<[f64; 3]> = (0..5)
        .map(|i| {
            let a = 2.0 * std::f64::consts::PI * f64::from(i) / 5.0 + 0.3;
            [0.1 + 0.7 * a.cos(), -0.05 + 0.7 * a.sin(), 1.0]
        })
        .collect();
    vec![
        (
            "convex".to_string(),
            v(&[
                [-0.3, 0.2, 1.0],
                [0.6, 0.1, 1.0],
                [0.7, 0.9, 1.0],
                [-0.2, 0.8, 1.0],
            ]),
        ),
        (
            "comb".to_string(),
            v(&[
                [0.3, -0.3, 1.0],
                [0.4, -0.3, 1.0],
                [0.4, 0.3, 1.0],
                [0.6, 0.3, 1.0],
                [0.6, -0.3, 1.0],
                [0.7, -0.3, 1.0],
                [0.7, 0.3, 1.0],
                [0.9, 0.3, 1.0],
                [0.9, -0.3, 1.0],
                [1.0, -0.3, 1.0],
                [1.0, 0.4, 1.0],
                [0.3, 0.4, 1.0],
            ]),
        ),
        ("around-pole".to_string(), v(&pentagon)),
        (
            "horizon".to_string(),
            v(&[
                [1.0, -0.5, 0.6],
                [1.0, 0.5, 0.6],
                [1.0, 0.5, -0.4],
                [1.0, -0.5, -0.4],
            ]),
        ),
        (
            "pole-vertex".to_string(),
            v(&[[0.0, 0.0, 1.0], [0.8, 0.1, 1.0], [0.3, 0.7, 1.0]]),
        ),
    ]
}

fn flatten(vs: &[Vec3<f64>]) -> Vec<f64> {
    vs.iter().flat_map(|v| [v.x, v.y, v.z]).collect()
}

/// The full catalogue of shapes, each warp's first shape being the one the
/// speed study times and the heat maps show. `max_shapes` limits the
/// number of shapes per warp (ordinary shapes first), `max_polygons` that
/// of the projected polygon.
pub(crate) fn catalogue(
    max_shapes: Option<usize>,
    max_polygons: Option<usize>,
) -> Result<Vec<ShapeEntry>, WarpError> {
    let mut out = Vec::new();
    let limit = max_shapes.unwrap_or(usize::MAX);
    let mut push = |e: ShapeEntry, count: &mut usize| {
        if *count < limit {
            out.push(e);
        }
        *count = count.saturating_add(1);
    };
    let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);

    let mut n = 0;
    for (name, [a, b, c]) in [
        (
            "3-D",
            [v(1.0, 2.0, 3.0), v(-2.0, 0.5, 1.0), v(0.5, -1.0, 2.0)],
        ),
        (
            "unit",
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.25, 1.0, 0.0)],
        ),
        (
            "sliver",
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.5, 1e-6, 0.0)],
        ),
    ] {
        let w = PlanarTriangle::new(a, b, c)?;
        let fold = w.clone().with_variant(PlanarTriangleVariant::Fold);
        push(
            ShapeEntry {
                warp: "planar-triangle",
                shape: name.to_string(),
                hard: false,
                raw: flatten(&[a, b, c]),
                variants: vec![
                    ("closed form", Built::PlanarTriangle(w)),
                    ("fold", Built::PlanarTriangle(fold)),
                ],
            },
            &mut n,
        );
    }
    let simple: [(&'static str, Built); 3] = [
        ("polar-disk", Built::PolarDisk(PolarDisk::new())),
        (
            "concentric-disk",
            Built::ConcentricDisk(ConcentricDisk::new()),
        ),
        ("hemisphere", Built::Hemisphere(Hemisphere::new())),
    ];
    for (warp, b) in simple {
        let mut n = 0;
        push(
            ShapeEntry {
                warp,
                shape: "unit".to_string(),
                hard: false,
                raw: Vec::new(),
                variants: vec![("closed form", b)],
            },
            &mut n,
        );
    }
    let mut n = 0;
    for k in [20.0, 0.0, 1.0, 1e6] {
        push(
            ShapeEntry {
                warp: "phong",
                shape: format!("k={k}"),
                hard: false,
                raw: vec![k],
                variants: vec![("closed form", Built::Phong(PhongLobe::new(k)?))],
            },
            &mut n,
        );
    }
    let mut n = 0;
    push(
        ShapeEntry {
            warp: "sphere",
            shape: "unit".to_string(),
            hard: false,
            raw: Vec::new(),
            variants: vec![
                ("+z axis", Built::Sphere(Sphere::new())),
                (
                    "tilted axis",
                    Built::Sphere(Sphere::with_axis(v(0.36, -0.48, 0.8))?),
                ),
            ],
        },
        &mut n,
    );

    let mut n = 0;
    let mut triangles = ordinary_triangles();
    // "generic" first: the shape the speed study times.
    triangles.sort_by_key(|(name, _)| name != "generic");
    let triangles = triangles
        .into_iter()
        .map(|t| (t, false))
        .chain(hard_triangles().into_iter().map(|t| (t, true)));
    for ((name, [a, b, c]), hard) in triangles {
        let robust = SphericalTriangle::new(a, b, c)?;
        let literal = robust
            .clone()
            .with_variant(SphericalTriangleVariant::Literal);
        push(
            ShapeEntry {
                warp: "spherical-triangle",
                shape: name,
                hard,
                raw: flatten(&[a, b, c]),
                variants: vec![
                    ("robust", Built::SphericalTriangle(robust)),
                    ("literal", Built::SphericalTriangle(literal)),
                ],
            },
            &mut n,
        );
    }

    let mut n = 0;
    let mut rectangles = ordinary_rectangles();
    rectangles.sort_by_key(|(name, _)| name != "oblique");
    let rectangles = rectangles
        .into_iter()
        .map(|r| (r, false))
        .chain(hard_rectangles().into_iter().map(|r| (r, true)));
    for ((name, [s, ex, ey, o]), hard) in rectangles {
        let robust = SphericalRectangle::new(s, ex, ey, o)?;
        let literal = robust
            .clone()
            .with_variant(SphericalRectangleVariant::Literal);
        push(
            ShapeEntry {
                warp: "spherical-rectangle",
                shape: name,
                hard,
                raw: flatten(&[s, ex, ey, o]),
                variants: vec![
                    ("robust", Built::SphericalRectangle(robust)),
                    ("literal", Built::SphericalRectangle(literal)),
                ],
            },
            &mut n,
        );
    }

    // Counting from the polygon limit's complement makes `push` stop at
    // min(max_shapes, max_polygons).
    let mut n = limit.saturating_sub(max_polygons.unwrap_or(usize::MAX));
    for (name, verts) in test_polygons() {
        let exact = ProjectedPolygon::new(&verts)?;
        let variants = POLYGON_SETTINGS
            .iter()
            .map(|&(label, inv)| {
                (
                    label,
                    Built::ProjectedPolygon(exact.clone().with_inversion(inv)),
                )
            })
            .collect();
        push(
            ShapeEntry {
                warp: "projected-polygon",
                shape: name,
                hard: false,
                raw: flatten(&verts),
                variants,
            },
            &mut n,
        );
    }
    new_warps(&mut push)?;
    Ok(out)
}

/// The shapes of the warps of issue 12 (uniform cone … standard normal).
fn new_warps(push: &mut impl FnMut(ShapeEntry, &mut usize)) -> Result<(), WarpError> {
    let one = |warp: &'static str, shape: String, hard: bool, raw: Vec<f64>, b: Built| ShapeEntry {
        warp,
        shape,
        hard,
        raw,
        variants: vec![("closed form", b)],
    };
    let mut n = 0;
    for (name, c) in [("60°", 0.5), ("tiny", 0.999_999)] {
        let w = Built::UniformCone(UniformCone::new(c)?);
        push(one("uniform-cone", name.into(), false, vec![c], w), &mut n);
    }
    let mut n = 0;
    for (name, p) in sphere_light_ladder() {
        let w = SphereLight::new(v3(&p, 0), p[3], v3(&p, 4))?;
        let hard = name.starts_with("near") || name.starts_with("axis");
        push(
            one(
                "sphere-light",
                name,
                hard,
                p.to_vec(),
                Built::SphereLight(w),
            ),
            &mut n,
        );
    }
    let mut n = 0;
    for (name, p) in lune_catalogue() {
        let w = Built::SphericalLune(SphericalLune::new(v3(&p, 0), v3(&p, 3))?);
        push(one("spherical-lune", name, false, p.to_vec(), w), &mut n);
    }
    let mut n = 0;
    for k in [10.0, 1e-8, 1e6] {
        let w = Built::VonMisesFisher(VonMisesFisher::new(k)?);
        push(
            one("von-mises-fisher", format!("κ={k}"), false, vec![k], w),
            &mut n,
        );
    }
    for warp in ["beckmann", "ggx"] {
        let mut n = 0;
        for a in [0.3, 1e-4] {
            let w = if warp == "ggx" {
                Built::Ggx(Ggx::new(a)?)
            } else {
                Built::Beckmann(Beckmann::new(a)?)
            };
            push(one(warp, format!("α={a}"), false, vec![a], w), &mut n);
        }
    }
    let mut n = 0;
    for w4 in [[0.1, 2.0, 0.7, 3.0], [0.0, 1.0, 1.0, 0.0]] {
        let w = Built::Bilinear(Bilinear::new(w4)?);
        push(
            one("bilinear", format!("{w4:?}"), false, w4.to_vec(), w),
            &mut n,
        );
    }
    let mut n = 0;
    push(
        one(
            "tent",
            "unit".into(),
            false,
            vec![],
            Built::Tent(Tent::new()),
        ),
        &mut n,
    );
    let mut n = 0;
    let w = Built::StdNormal(StdNormal::new());
    push(one("std-normal", "unit".into(), false, vec![], w), &mut n);
    Ok(())
}

fn v3(p: &[f64], i: usize) -> Vec3<f64> {
    Vec3::new(p[i], p[i + 1], p[i + 2])
}

/// The input format of `T` (`f32` or `f64`).
fn format_of<T: Real>() -> Result<InputFormat, WarpError> {
    InputFormat::for_precision(T::precision()).ok_or(WarpError::InvalidParameter {
        name: "T",
        expected: "f32 or f64",
    })
}

/// What the studies need from a warp beyond [`WarpFamily`].
pub(crate) trait StudyWarp: WarpFamily<f64> + Sync {
    /// The same shape evaluated exactly (robust variant, Newton inversion).
    fn exact(&self) -> Self;
    /// `true` if `self` is its own exact variant.
    fn is_exact(&self) -> bool;
    /// κ of the exact map at each of `points`, for `T`'s input format:
    /// one-ulp perturbations of `u`, `v` and of the shape's parameters as
    /// `T` stores them (`raw`: the shape's data as given).
    fn kappas<T: Real>(&self, raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
        let _ = raw;
        let format = format_of::<T>()?;
        let wr = self.exact().at::<T>()?.at::<M>()?;
        kappa_values(|_: &[M]| Ok(wr.clone()), &[], points, format)
    }
}

fn kappa_values<W, F>(
    build: F,
    params: &[f64],
    points: &[(f64, f64)],
    format: InputFormat,
) -> Result<Vec<f64>, WarpError>
where
    W: Warp<M>,
    F: Fn(&[M]) -> Result<W, WarpError>,
{
    Ok(sensitivities_in::<M, W, F>(build, params, points, format)?
        .into_iter()
        .map(|s| s.kappa)
        .collect())
}

fn vec3_at<R: Real>(p: &[R], i: usize) -> Vec3<R> {
    Vec3::new(p[i].clone(), p[i + 1].clone(), p[i + 2].clone())
}

fn coords<T: Real>(vs: &[&Vec3<T>]) -> Vec<f64> {
    vs.iter()
        .flat_map(|v| [v.x.to_f64(), v.y.to_f64(), v.z.to_f64()])
        .collect()
}

impl StudyWarp for PlanarTriangle<f64> {
    fn exact(&self) -> Self {
        self.clone()
    }
    fn is_exact(&self) -> bool {
        true
    }
    fn kappas<T: Real>(&self, _raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
        let wt = self.at::<T>()?;
        let params = coords(&[wt.a(), wt.b(), wt.c()]);
        let variant = self.variant();
        kappa_values(
            |p: &[M]| {
                PlanarTriangle::new_with(vec3_at(p, 0), vec3_at(p, 3), vec3_at(p, 6), variant)
            },
            &params,
            points,
            format_of::<T>()?,
        )
    }
}

macro_rules! exact_without_parameters {
    ($($t:ty),*) => {$(
        impl StudyWarp for $t {
            fn exact(&self) -> Self {
                self.clone()
            }
            fn is_exact(&self) -> bool {
                true
            }
        }
    )*};
}
exact_without_parameters!(
    PolarDisk<f64>,
    ConcentricDisk<f64>,
    Hemisphere<f64>,
    Sphere<f64>,
    Tent<f64>,
    StdNormal<f64>
);

/// Warps built from their parameters `raw` (as given, in `f64`) by `$build`.
macro_rules! exact_from_raw {
    ($($t:ty => $build:expr),* $(,)?) => {$(
        impl StudyWarp for $t {
            fn exact(&self) -> Self {
                self.clone()
            }
            fn is_exact(&self) -> bool {
                true
            }
            fn kappas<T: Real>(&self, raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
                kappa_values($build, raw, points, format_of::<T>()?)
            }
        }
    )*};
}
exact_from_raw!(
    UniformCone<f64> => |p: &[M]| UniformCone::new(p[0].clone()),
    VonMisesFisher<f64> => |p: &[M]| VonMisesFisher::new(p[0].clone()),
    Beckmann<f64> => |p: &[M]| Beckmann::new(p[0].clone()),
    Ggx<f64> => |p: &[M]| Ggx::new(p[0].clone()),
    Bilinear<f64> => |p: &[M]| Bilinear::new([p[0].clone(), p[1].clone(), p[2].clone(), p[3].clone()]),
    SphereLight<f64> => |p: &[M]| SphereLight::new(vec3_at(p, 0), p[3].clone(), vec3_at(p, 4)),
    SphericalLune<f64> => |p: &[M]| SphericalLune::new(vec3_at(p, 0), vec3_at(p, 3)),
);

impl StudyWarp for PhongLobe<f64> {
    fn exact(&self) -> Self {
        self.clone()
    }
    fn is_exact(&self) -> bool {
        true
    }
    fn kappas<T: Real>(&self, _raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
        let k = self.at::<T>()?.exponent().to_f64();
        kappa_values(
            |p: &[M]| PhongLobe::new(p[0].clone()),
            &[k],
            points,
            format_of::<T>()?,
        )
    }
}

impl StudyWarp for SphericalTriangle<f64> {
    fn exact(&self) -> Self {
        self.clone().with_variant(SphericalTriangleVariant::Robust)
    }
    fn is_exact(&self) -> bool {
        self.variant() == SphericalTriangleVariant::Robust
    }
    /// The parameters are the unit vertices as `T` stores them (the
    /// shape's tests do the same).
    fn kappas<T: Real>(&self, _raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
        let wt = self.at::<T>()?;
        let params = coords(&[wt.a(), wt.b(), wt.c()]);
        kappa_values(
            |p: &[M]| SphericalTriangle::new(vec3_at(p, 0), vec3_at(p, 3), vec3_at(p, 6)),
            &params,
            points,
            format_of::<T>()?,
        )
    }
}

impl StudyWarp for SphericalRectangle<f64> {
    fn exact(&self) -> Self {
        self.clone().with_variant(SphericalRectangleVariant::Robust)
    }
    fn is_exact(&self) -> bool {
        self.variant() == SphericalRectangleVariant::Robust
    }
    /// The parameters are the 12 coordinates of `s, e_x, e_y, o` as given,
    /// rebuilt at 256 bits with the input precision's perpendicularity
    /// tolerance (as the shape's tests do).
    fn kappas<T: Real>(&self, raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
        let bits = T::precision();
        kappa_values(
            |p: &[M]| {
                SphericalRectangle::with_input_precision(
                    vec3_at(p, 0),
                    vec3_at(p, 3),
                    vec3_at(p, 6),
                    vec3_at(p, 9),
                    SphericalRectangleVariant::Robust,
                    bits,
                )
            },
            raw,
            points,
            format_of::<T>()?,
        )
    }
}

impl StudyWarp for ProjectedPolygon<f64> {
    fn exact(&self) -> Self {
        self.clone().with_inversion(MarginalInversion::Newton)
    }
    fn is_exact(&self) -> bool {
        self.inversion() == MarginalInversion::Newton
    }
    /// The parameters are the vertex coordinates (directions from the
    /// receiver, normal `+z`).
    fn kappas<T: Real>(&self, raw: &[f64], points: &[(f64, f64)]) -> Result<Vec<f64>, WarpError> {
        kappa_values(
            |p: &[M]| {
                let verts: Vec<Vec3<M>> = (0..p.len() / 3).map(|i| vec3_at(p, 3 * i)).collect();
                ProjectedPolygon::new(&verts)
            },
            raw,
            points,
            format_of::<T>()?,
        )
    }
}

// ---------------------------------------------------------------------------
// Measuring one warp in one scalar
// ---------------------------------------------------------------------------

/// The outcome at one input point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PointOutcome {
    /// Both finite: error against the exact map and against the variant's
    /// own map at 256 bits (units of `u_T · extent`), and the distance
    /// outside the shape (same units).
    Finite {
        ulps: f64,
        own_ulps: f64,
        outside_ulps: f64,
    },
    /// The map in `T` returned NaN or ∞.
    NonFinite,
    /// The 256-bit reference was not finite.
    ReferenceNonFinite,
}

/// Evaluates `w` in `T` at `points` against the exact map of the shape as
/// `T` sees it at 256 bits. `Err` if `T` rejects the shape.
pub(crate) fn point_errors<T: Real, W: StudyWarp>(
    w: &W,
    points: &[(f64, f64)],
) -> Result<Vec<PointOutcome>, WarpError> {
    let wt = w.at::<T>()?;
    let wr = w.exact().at::<T>()?.at::<M>()?;
    let own = if w.is_exact() {
        None
    } else {
        Some(wt.at::<M>()?)
    };
    let unit = M::exp2i(-(T::precision() as i32)) * &wr.extent();
    let mut out = Vec::with_capacity(points.len());
    for &(u, v) in points {
        let (ut, vt) = (T::from_f64(u), T::from_f64(v));
        let (um, vm): (M, M) = (convert(&ut), convert(&vt));
        let q = wr.map(&um, &vm).to_vec3();
        if !q.is_finite() {
            out.push(PointOutcome::ReferenceNonFinite);
            continue;
        }
        let p = wt.map(&ut, &vt).to_vec3();
        if !p.is_finite() {
            out.push(PointOutcome::NonFinite);
            continue;
        }
        let pm: Vec3<M> = p.convert();
        let ulps = (pm.sub(&q).max_abs() / &unit).to_f64();
        let own_ulps = match &own {
            None => ulps,
            Some(o) => {
                let r = o.map(&um, &vm).to_vec3();
                if r.is_finite() {
                    (pm.sub(&r).max_abs() / &unit).to_f64()
                } else {
                    f64::NAN
                }
            }
        };
        let outside = wr.outside_by(&Coords::from_vec3(pm)) / &unit;
        out.push(PointOutcome::Finite {
            ulps,
            own_ulps,
            outside_ulps: outside.to_f64(),
        });
    }
    Ok(out)
}

/// The median of the finite values (sorted copy); 0 for none.
pub(crate) fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}

// ---------------------------------------------------------------------------
// Configuration and results
// ---------------------------------------------------------------------------

/// The precision study's size.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionConfig {
    /// Seed of the random points.
    pub seed: u64,
    /// Random points added to the extremes grid (64 points) for every shape.
    pub random_points: usize,
    /// At most this many shapes per warp (ordinary shapes first); `None`:
    /// all, i.e. the whole hard ladders.
    pub max_shapes: Option<usize>,
    /// At most this many test polygons of the projected polygon (the most
    /// expensive shapes: κ rebuilds the polygon for every perturbed vertex
    /// coordinate); `None`: all of [`test_polygons`].
    pub max_polygons: Option<usize>,
    /// Nodes per side of the `f32` error maps (`n × n` nodes
    /// `(i/(n−1), j/(n−1))`), at least 2.
    pub heat_map_nodes: usize,
    /// Only these warps (labels of [`WARPS`]); `None`: all.
    pub warps: Option<Vec<String>>,
}

impl PrecisionConfig {
    /// The tests' size (a few seconds of CPU in the test profile): every
    /// shape of every ladder but only the first test polygon, on the
    /// extremes grid plus 4 random points, 12 × 12 error maps.
    pub fn quick() -> Self {
        PrecisionConfig {
            seed: 0x0005_EED5,
            random_points: 4,
            max_shapes: None,
            max_polygons: Some(1),
            heat_map_nodes: 12,
            warps: None,
        }
    }
}

impl Default for PrecisionConfig {
    /// The report's size: every shape on the extremes grid plus 64 random
    /// points, 64 × 64 error maps.
    fn default() -> Self {
        PrecisionConfig {
            random_points: 64,
            max_polygons: None,
            heat_map_nodes: 64,
            ..Self::quick()
        }
    }
}

impl PrecisionConfig {
    fn validate(&self) -> Result<(), WarpError> {
        if self.heat_map_nodes < 2 {
            return Err(WarpError::InvalidParameter {
                name: "heat_map_nodes",
                expected: "at least 2",
            });
        }
        if let Some(only) = &self.warps
            && (only.is_empty() || only.iter().any(|w| !WARPS.contains(&w.as_str())))
        {
            return Err(WarpError::InvalidParameter {
                name: "warps",
                expected: "labels of studies::precision::WARPS",
            });
        }
        if self.max_shapes == Some(0) || self.max_polygons == Some(0) {
            return Err(WarpError::InvalidParameter {
                name: "max_shapes/max_polygons",
                expected: "at least 1 (or None)",
            });
        }
        Ok(())
    }

    /// The input points of every shape: the extremes grid, then
    /// [`PrecisionConfig::random_points`] random points.
    pub fn points(&self) -> Vec<(f64, f64)> {
        let mut p = extremes_grid();
        p.extend(random_points(self.random_points, self.seed));
        p
    }
}

/// One warp × variant × shape × scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionCell {
    /// The warp (one of [`WARPS`]).
    pub warp: String,
    /// The variant (see [`warp_variants`]).
    pub variant: String,
    /// The shape.
    pub shape: String,
    /// `true` for a shape of a hard ladder.
    pub hard: bool,
    /// `f32` or `f64`.
    pub scalar: String,
    /// `true` if the constructor in this scalar rejects the shape (e.g. it
    /// rounds to a degenerate one); the other fields are then 0.
    pub rejected: bool,
    /// Number of points.
    pub points: usize,
    /// Max error against the exact map, units of `u_T · extent`, over the
    /// finite points.
    pub max_ulps: f64,
    /// Median of the same.
    pub median_ulps: f64,
    /// The input with the max error.
    pub worst: Option<(f64, f64)>,
    /// Max error against the variant's own map at 256 bits (the rounding
    /// error alone; equal to `max_ulps` for an exact variant).
    pub own_max_ulps: f64,
    /// Points where the map in this scalar returned NaN or ∞.
    pub non_finite: usize,
    /// Points where the 256-bit reference was not finite (a bug).
    pub reference_non_finite: usize,
    /// Points outside the shape by more than
    /// [`OUTSIDE_TOLERANCE_ULPS`]` · u_T · extent`.
    pub outside: usize,
    /// Max distance outside the shape, units of `u_T · extent`.
    pub max_outside_ulps: f64,
    /// Max over the points of error / (16 · max(u_T, κ)); `None` if κ
    /// could not be computed (see [`PrecisionCell::kappa_error`]).
    pub max_kappa_ratio: Option<f64>,
    /// The input with the largest ratio.
    pub worst_kappa_ratio: Option<(f64, f64)>,
    /// Max κ over the points, units of `u_T`.
    pub max_kappa_ulps: Option<f64>,
    /// Points outside the shape by more than their bound 16 · max(u_T, κ).
    pub outside_bound: usize,
    /// Why κ is missing, if it is.
    pub kappa_error: Option<String>,
    /// `max |J · pdf − 1|` of the variant's map at 256 bits (the same for
    /// both scalars).
    pub jacobian_max_dev: f64,
    /// Points where `J · pdf` was not finite even after the harness's nudge.
    pub jacobian_non_finite: usize,
}

/// One warp × variant × scalar, over all the warp's shapes.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionSummary {
    /// The warp.
    pub warp: String,
    /// The variant.
    pub variant: String,
    /// `f32` or `f64`.
    pub scalar: String,
    /// Shapes measured (accepted by the scalar).
    pub shapes: usize,
    /// Shapes the scalar's constructor rejects.
    pub rejected: usize,
    /// Points evaluated (over the accepted shapes).
    pub points: usize,
    /// Max error against the exact map, units of `u_T · extent`.
    pub max_ulps: f64,
    /// The shape and input of the max error.
    pub worst: Option<(String, (f64, f64))>,
    /// The median error over all points of all shapes.
    pub median_ulps: f64,
    /// Max error against the variant's own 256-bit map.
    pub own_max_ulps: f64,
    /// NaN/∞ outputs.
    pub non_finite: usize,
    /// Reference NaN/∞ (bugs).
    pub reference_non_finite: usize,
    /// Points outside by more than 4 `u_T · extent`.
    pub outside: usize,
    /// Points outside by more than their κ bound.
    pub outside_bound: usize,
    /// Max κ-conditioned ratio over the shapes with κ.
    pub max_kappa_ratio: Option<f64>,
    /// The shape of that ratio.
    pub worst_kappa_shape: Option<String>,
    /// Shapes whose κ could not be computed.
    pub kappa_failures: usize,
    /// Max 256-bit Jacobian deviation over the shapes.
    pub jacobian_max_dev: f64,
    /// Non-finite `J · pdf` points over the shapes.
    pub jacobian_non_finite: usize,
}

/// The `f32` error of one warp over a grid of `[0, 1]²`.
#[derive(Clone, Debug, PartialEq)]
pub struct F32ErrorMap {
    /// The warp.
    pub warp: String,
    /// The variant.
    pub variant: String,
    /// The shape.
    pub shape: String,
    /// Nodes per side `n`.
    pub nodes: usize,
    /// Error at node `(u_i, v_j) = (i/(n−1), j/(n−1))` in units of
    /// `2⁻²⁴ · extent`, at index `j · n + i`; NaN where the `f32` map is not
    /// finite.
    pub values: Vec<f64>,
    /// Max over the finite nodes.
    pub max_ulps: f64,
    /// The node of the max.
    pub worst: (f64, f64),
    /// Median over the finite nodes.
    pub median_ulps: f64,
    /// Fraction of the finite nodes with an error above 4 units.
    pub above_4: f64,
    /// Nodes where the `f32` map is not finite.
    pub non_finite: usize,
}

/// The results of the precision study.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionStudy {
    /// The configuration it ran with.
    pub config: PrecisionConfig,
    /// Points per shape.
    pub points_per_shape: usize,
    /// Every warp × variant × shape × scalar, in catalogue order (shape,
    /// then scalar `f32`, `f64`, then variant).
    pub cells: Vec<PrecisionCell>,
    /// Every warp × variant × scalar.
    pub summary: Vec<PrecisionSummary>,
    /// Where the `f32` error lives, per warp (exact variant) and for the
    /// literal variants.
    pub f32_maps: Vec<F32ErrorMap>,
}

/// The warps, variants and shapes whose `f32` error is mapped: each warp's
/// exact variant on its first shape, the literal variants of the
/// solid-angle maps and the bare cubic of the projected polygon.
fn heat_map_cases(shapes: &[ShapeEntry]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for warp in WARPS {
        let Some(k) = shapes.iter().position(|s| s.warp == warp) else {
            continue;
        };
        for (j, (label, _)) in shapes[k].variants.iter().enumerate() {
            if j == 0 || *label == "literal" || *label == "cubic" || *label == "tilted axis" {
                out.push((k, j));
            }
        }
    }
    out
}

enum JobOut {
    Jacobian(Vec<(f64, usize)>),
    Cells(Vec<(PrecisionCell, Vec<f64>)>),
    Map(F32ErrorMap),
}

/// Runs the study on rayon's current thread pool (sequentially without the
/// `studies` feature's rayon); the result does not depend on the number of
/// threads.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for an invalid configuration; the
/// errors of building a catalogue shape in `f64` or at 256 bits (none for
/// the shipped shapes).
pub fn run(config: &PrecisionConfig) -> Result<PrecisionStudy, WarpError> {
    config.validate()?;
    let mut shapes = catalogue(config.max_shapes, config.max_polygons)?;
    if let Some(only) = &config.warps {
        shapes.retain(|e| only.iter().any(|w| w == e.warp));
    }
    let points = config.points();
    let maps = heat_map_cases(&shapes);
    let n = config.heat_map_nodes;
    let grid: Vec<(f64, f64)> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64)))
        .collect();
    // The heat maps first (the longest jobs), then per shape its
    // Jacobians, its f32 cells and its f64 cells.
    let jobs = maps.len() + 3 * shapes.len();
    let results = run_jobs(jobs, config.seed, |i, _rng| -> Result<JobOut, WarpError> {
        if i < maps.len() {
            let (k, j) = maps[i];
            let e = &shapes[k];
            let (label, built) = &e.variants[j];
            let outcomes = with_warp!(built, |w| point_errors::<f32, _>(w, &grid))?;
            return Ok(JobOut::Map(error_map(e, label, n, &grid, &outcomes)));
        }
        let i = i - maps.len();
        let e = &shapes[i / 3];
        match i % 3 {
            0 => jacobians(e, &points).map(JobOut::Jacobian),
            1 => scalar_cells::<f32>(e, &points).map(JobOut::Cells),
            _ => scalar_cells::<f64>(e, &points).map(JobOut::Cells),
        }
    });
    let mut cells = Vec::new();
    let mut f32_maps = Vec::new();
    let mut jac = Vec::new();
    for r in results {
        match r? {
            JobOut::Jacobian(j) => jac = j,
            JobOut::Cells(c) => {
                // The variants of one scalar, in order: the Jacobian of
                // variant j belongs to cell j.
                for (j, (mut cell, errs)) in c.into_iter().enumerate() {
                    if let Some(&(dev, bad)) = jac.get(j) {
                        cell.jacobian_max_dev = dev;
                        cell.jacobian_non_finite = bad;
                    }
                    cells.push((cell, errs));
                }
            }
            JobOut::Map(m) => f32_maps.push(m),
        }
    }
    let summary = summarize(&cells);
    Ok(PrecisionStudy {
        config: config.clone(),
        points_per_shape: points.len(),
        cells: cells.into_iter().map(|(c, _)| c).collect(),
        summary,
        f32_maps,
    })
}

fn error_map(
    e: &ShapeEntry,
    variant: &str,
    n: usize,
    grid: &[(f64, f64)],
    outcomes: &[PointOutcome],
) -> F32ErrorMap {
    let mut values = Vec::with_capacity(outcomes.len());
    let mut non_finite = 0;
    let mut max = 0.0;
    let mut worst = (0.0, 0.0);
    for (o, &uv) in outcomes.iter().zip(grid) {
        match o {
            PointOutcome::Finite { ulps, .. } => {
                values.push(*ulps);
                if *ulps > max {
                    max = *ulps;
                    worst = uv;
                }
            }
            _ => {
                non_finite += 1;
                values.push(f64::NAN);
            }
        }
    }
    let finite = values.iter().filter(|x| x.is_finite()).count();
    let above = values.iter().filter(|&&x| x > 4.0).count();
    F32ErrorMap {
        warp: e.warp.to_string(),
        variant: variant.to_string(),
        shape: e.shape.clone(),
        nodes: n,
        median_ulps: median(&values),
        max_ulps: max,
        worst,
        above_4: if finite > 0 {
            above as f64 / finite as f64
        } else {
            0.0
        },
        non_finite,
        values,
    }
}

/// The 256-bit Jacobian deviation and non-finite count of each variant of
/// `e` (independent of the scalar under test).
fn jacobians(e: &ShapeEntry, points: &[(f64, f64)]) -> Result<Vec<(f64, usize)>, WarpError> {
    let mut jac = Vec::new();
    for (_, built) in &e.variants {
        let r = with_warp!(built, |w| check_jacobian(w, points))?;
        jac.push((r.max_rel_deviation, r.non_finite));
    }
    Ok(jac)
}

/// The cells of every variant of `e` in `T` (κ computed once), each with
/// its finite per-point errors (for the pooled medians); the Jacobian
/// fields are filled in by [`run`].
fn scalar_cells<T: Real>(
    e: &ShapeEntry,
    points: &[(f64, f64)],
) -> Result<Vec<(PrecisionCell, Vec<f64>)>, WarpError> {
    let format = format_of::<T>()?;
    let ut = format.unit_roundoff();
    let exact = &e.variants[0].1;
    let accepted = with_warp!(exact, |w| w.at::<T>().is_ok());
    let kappas: Result<Vec<f64>, WarpError> = if accepted {
        with_warp!(exact, |w| w.kappas::<T>(&e.raw, points))
    } else {
        Err(WarpError::Degenerate {
            what: "shape rejected in this scalar",
        })
    };
    let mut out = Vec::new();
    for (label, built) in &e.variants {
        let mut cell = PrecisionCell {
            warp: e.warp.to_string(),
            variant: label.to_string(),
            shape: e.shape.clone(),
            hard: e.hard,
            scalar: T::type_name(),
            rejected: false,
            points: points.len(),
            max_ulps: 0.0,
            median_ulps: 0.0,
            worst: None,
            own_max_ulps: 0.0,
            non_finite: 0,
            reference_non_finite: 0,
            outside: 0,
            max_outside_ulps: 0.0,
            max_kappa_ratio: None,
            worst_kappa_ratio: None,
            max_kappa_ulps: None,
            outside_bound: 0,
            kappa_error: None,
            jacobian_max_dev: 0.0,
            jacobian_non_finite: 0,
        };
        let outcomes = if accepted {
            with_warp!(built, |w| point_errors::<T, _>(w, points))
        } else {
            Err(WarpError::Degenerate { what: "rejected" })
        };
        let Ok(outcomes) = outcomes else {
            cell.rejected = true;
            out.push((cell, Vec::new()));
            continue;
        };
        let kappa = kappas.as_ref().ok();
        if let Err(err) = &kappas {
            cell.kappa_error = Some(err.to_string());
        } else {
            cell.max_kappa_ratio = Some(0.0);
            cell.max_kappa_ulps = Some(0.0);
        }
        let mut finite = Vec::with_capacity(points.len());
        for (i, (o, &uv)) in outcomes.iter().zip(points).enumerate() {
            match *o {
                PointOutcome::NonFinite => cell.non_finite += 1,
                PointOutcome::ReferenceNonFinite => cell.reference_non_finite += 1,
                PointOutcome::Finite {
                    ulps,
                    own_ulps,
                    outside_ulps,
                } => {
                    finite.push(ulps);
                    if cell.worst.is_none() || ulps > cell.max_ulps {
                        cell.max_ulps = ulps;
                        cell.worst = Some(uv);
                    }
                    if own_ulps > cell.own_max_ulps || own_ulps.is_nan() {
                        cell.own_max_ulps = own_ulps;
                    }
                    if outside_ulps > OUTSIDE_TOLERANCE_ULPS {
                        cell.outside += 1;
                    }
                    cell.max_outside_ulps = cell.max_outside_ulps.max(outside_ulps);
                    if let Some(k) = kappa {
                        let bound = accuracy_bound(k[i], format);
                        let ratio = ulps * ut / bound;
                        if ratio > cell.max_kappa_ratio.unwrap_or(0.0)
                            || cell.worst_kappa_ratio.is_none()
                        {
                            cell.max_kappa_ratio = Some(ratio);
                            cell.worst_kappa_ratio = Some(uv);
                        }
                        let ku = k[i] / ut;
                        if ku > cell.max_kappa_ulps.unwrap_or(0.0) {
                            cell.max_kappa_ulps = Some(ku);
                        }
                        if outside_ulps * ut > bound {
                            cell.outside_bound += 1;
                        }
                    }
                }
            }
        }
        cell.median_ulps = median(&finite);
        out.push((cell, finite));
    }
    Ok(out)
}

fn summarize(cells: &[(PrecisionCell, Vec<f64>)]) -> Vec<PrecisionSummary> {
    let mut out = Vec::new();
    for (warp, variants) in warp_variants() {
        for variant in variants {
            for scalar in ["f32", "f64"] {
                let mine: Vec<&(PrecisionCell, Vec<f64>)> = cells
                    .iter()
                    .filter(|(c, _)| c.warp == warp && c.variant == variant && c.scalar == scalar)
                    .collect();
                if mine.is_empty() {
                    continue;
                }
                let mut s = PrecisionSummary {
                    warp: warp.to_string(),
                    variant: variant.to_string(),
                    scalar: scalar.to_string(),
                    shapes: 0,
                    rejected: 0,
                    points: 0,
                    max_ulps: 0.0,
                    worst: None,
                    median_ulps: 0.0,
                    own_max_ulps: 0.0,
                    non_finite: 0,
                    reference_non_finite: 0,
                    outside: 0,
                    outside_bound: 0,
                    max_kappa_ratio: None,
                    worst_kappa_shape: None,
                    kappa_failures: 0,
                    jacobian_max_dev: 0.0,
                    jacobian_non_finite: 0,
                };
                let mut pooled = Vec::new();
                for (c, errs) in mine {
                    s.jacobian_max_dev = s.jacobian_max_dev.max(c.jacobian_max_dev);
                    s.jacobian_non_finite += c.jacobian_non_finite;
                    if c.rejected {
                        s.rejected += 1;
                        continue;
                    }
                    s.shapes += 1;
                    s.points += c.points;
                    pooled.extend_from_slice(errs);
                    if let Some(uv) = c.worst
                        && (s.worst.is_none() || c.max_ulps > s.max_ulps)
                    {
                        s.max_ulps = c.max_ulps;
                        s.worst = Some((c.shape.clone(), uv));
                    }
                    if c.own_max_ulps > s.own_max_ulps || c.own_max_ulps.is_nan() {
                        s.own_max_ulps = c.own_max_ulps;
                    }
                    s.non_finite += c.non_finite;
                    s.reference_non_finite += c.reference_non_finite;
                    s.outside += c.outside;
                    s.outside_bound += c.outside_bound;
                    match c.max_kappa_ratio {
                        Some(r) => {
                            if s.max_kappa_ratio.is_none_or(|m| r > m) {
                                s.max_kappa_ratio = Some(r);
                                s.worst_kappa_shape = Some(c.shape.clone());
                            }
                        }
                        None => s.kappa_failures += 1,
                    }
                }
                s.median_ulps = median(&pooled);
                out.push(s);
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// `x` in a short scientific or fixed notation for tables.
pub(crate) fn fmt_num(x: f64) -> String {
    if x.is_nan() {
        "NaN".to_string()
    } else if x == 0.0 {
        "0".to_string()
    } else if x.abs() >= 1e4 || x.abs() < 1e-2 {
        format!("{x:.1e}")
    } else if x.abs() >= 100.0 {
        format!("{x:.0}")
    } else {
        format!("{x:.2}")
    }
}

fn fmt_opt(x: Option<f64>) -> String {
    x.map_or("–".to_string(), fmt_num)
}

fn fmt_uv(uv: (f64, f64)) -> String {
    let f = |x: f64| {
        if x == 0.0 || x == 1.0 || x == 0.5 {
            format!("{x}")
        } else if x < 1e-3 {
            format!("{x:.0e}")
        } else if x > 1.0 - 1e-3 {
            format!("1−{:.0e}", 1.0 - x)
        } else {
            format!("{x:.3}")
        }
    };
    format!("({}, {})", f(uv.0), f(uv.1))
}

/// A file-name-safe version of `s`.
pub(crate) fn slug(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('-') {
            out.push('-');
        }
    }
    out.trim_matches('-').to_string()
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn opt_csv(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| format!("{v:e}"))
}

fn uv_csv(uv: Option<(f64, f64)>) -> (String, String) {
    uv.map_or((String::new(), String::new()), |(u, v)| {
        (format!("{u:e}"), format!("{v:e}"))
    })
}

impl PrecisionStudy {
    /// The summary row of `warp`, `variant`, `scalar`.
    pub fn summary_of(&self, warp: &str, variant: &str, scalar: &str) -> Option<&PrecisionSummary> {
        self.summary
            .iter()
            .find(|s| s.warp == warp && s.variant == variant && s.scalar == scalar)
    }

    /// The cell of `warp`, `variant`, `shape`, `scalar`.
    pub fn cell(
        &self,
        warp: &str,
        variant: &str,
        shape: &str,
        scalar: &str,
    ) -> Option<&PrecisionCell> {
        self.cells.iter().find(|c| {
            c.warp == warp && c.variant == variant && c.shape == shape && c.scalar == scalar
        })
    }

    /// The figure file name of an `f32` error map.
    pub fn map_file_name(m: &F32ErrorMap) -> String {
        format!(
            "precision_f32_map_{}_{}.svg",
            slug(&m.warp),
            slug(&m.variant)
        )
    }

    /// The study as a Markdown section: the summary over all shapes, the
    /// solid-angle maps' ladders shape by shape, the projected polygon's
    /// inversion settings per polygon, and the `f32` error maps.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "## Precision: every warp × variant × type against 256 bits\n"
        );
        let _ = writeln!(
            s,
            "Each shape is evaluated on the extremes grid (u, v ∈ {{0, 2⁻⁶⁰, 1e-12, 1e-6, ½, 1−1e-6, 1−1e-12, 1}}²) \
             plus {} random points ({} points per shape), for every shape of the warp's test set — for the \
             spherical triangle and rectangle their ordinary shapes and the whole hard ladders. *Error* is the \
             max-norm distance to the **exact** map (robust variant, Newton-converged inversion) of the shape as \
             the type sees it, at the same rounded inputs, evaluated at 256 bits, over the shape's extent, in \
             units of the type's roundoff (2⁻²⁴, 2⁻⁵³); *own* compares with the variant's own map at 256 bits \
             instead (rounding alone; NaN where that map itself is NaN). *κ-ratio* is max error / (16·max(u, κ)), κ the move of the exact map \
             under a one-ulp change of one input (parameters, u, v): ≤ 1 means as accurate as the inputs allow. \
             *Jacobian* is max |J·pdf − 1| of the variant's map at 256 bits with exact partials (same for both \
             types). *NaN* counts NaN/∞ outputs, *out* points off the shape by more than 4 units (by more than \
             the κ bound in parentheses).\n",
            self.config.random_points, self.points_per_shape
        );
        let _ = writeln!(
            s,
            "| warp | variant | type | shapes (rejected) | max error [u] | at shape (u, v) | median [u] | own max [u] | NaN | out (κ) | κ-ratio | Jacobian dev. |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &self.summary {
            let at = r.worst.as_ref().map_or("–".to_string(), |(sh, uv)| {
                format!("{sh} {}", fmt_uv(*uv))
            });
            let kappa = match (r.max_kappa_ratio, r.kappa_failures) {
                (Some(k), 0) => fmt_num(k),
                (Some(k), f) => format!("{} ({f} without κ)", fmt_num(k)),
                (None, _) => "–".to_string(),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} ({}) | {} | {:.1e}{} |",
                r.warp,
                r.variant,
                r.scalar,
                r.shapes,
                r.rejected,
                fmt_num(r.max_ulps),
                at,
                fmt_num(r.median_ulps),
                fmt_num(r.own_max_ulps),
                r.non_finite,
                r.outside,
                r.outside_bound,
                kappa,
                r.jacobian_max_dev,
                if r.jacobian_non_finite > 0 {
                    format!(" ({} non-finite)", r.jacobian_non_finite)
                } else {
                    String::new()
                }
            );
        }
        for warp in ["spherical-triangle", "spherical-rectangle"] {
            let shapes: Vec<&PrecisionCell> = self
                .cells
                .iter()
                .filter(|c| c.warp == warp && c.variant == "robust" && c.scalar == "f64")
                .collect();
            if shapes.is_empty() {
                continue;
            }
            let _ = writeln!(
                s,
                "\n### {warp}: shape by shape (max error [u] / κ-ratio / NaN; `rej.` = rejected by the type)\n"
            );
            let _ = writeln!(
                s,
                "| shape | f64 robust | f64 literal | f32 robust | f32 literal | Jacobian literal |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|");
            for c in shapes {
                let cell = |variant: &str, scalar: &str| -> String {
                    match self.cell(warp, variant, &c.shape, scalar) {
                        None => "–".to_string(),
                        Some(x) if x.rejected => "rej.".to_string(),
                        Some(x) => format!(
                            "{} / {} / {}",
                            fmt_num(x.max_ulps),
                            fmt_opt(x.max_kappa_ratio),
                            x.non_finite
                        ),
                    }
                };
                let jl = self
                    .cell(warp, "literal", &c.shape, "f64")
                    .map_or("–".to_string(), |x| format!("{:.1e}", x.jacobian_max_dev));
                let _ = writeln!(
                    s,
                    "| {}{} | {} | {} | {} | {} | {} |",
                    c.shape,
                    if c.hard { "" } else { " (ordinary)" },
                    cell("robust", "f64"),
                    cell("literal", "f64"),
                    cell("robust", "f32"),
                    cell("literal", "f32"),
                    jl
                );
            }
        }
        let polys: Vec<&PrecisionCell> = self
            .cells
            .iter()
            .filter(|c| c.warp == "projected-polygon" && c.variant == "Newton" && c.scalar == "f64")
            .collect();
        if !polys.is_empty() {
            let _ = writeln!(
                s,
                "\n### projected-polygon: inversion settings per polygon (f64 max error against the exact map [u]; 256-bit Jacobian deviation)\n"
            );
            let mut head = "| polygon |".to_string();
            let mut rule = "|---|".to_string();
            for (label, _) in POLYGON_SETTINGS {
                let _ = write!(head, " {label} |");
                rule.push_str("---|");
            }
            let _ = writeln!(s, "{head}\n{rule}");
            for c in polys {
                let mut row = format!("| {} |", c.shape);
                for (label, _) in POLYGON_SETTINGS {
                    let x = self.cell("projected-polygon", label, &c.shape, "f64");
                    let _ = write!(
                        row,
                        " {} |",
                        x.map_or("–".to_string(), |x| format!(
                            "{} ({:.0e})",
                            fmt_num(x.max_ulps),
                            x.jacobian_max_dev
                        ))
                    );
                }
                let _ = writeln!(s, "{row}");
            }
        }
        if !self.f32_maps.is_empty() {
            let n = self.config.heat_map_nodes;
            let _ = writeln!(
                s,
                "\n### Where the f32 error lives over [0, 1]²\n\n\
                 The f32 error (units of 2⁻²⁴ · extent, against the exact map at 256 bits) at the {n} × {n} nodes \
                 (i/{m}, j/{m}); log colour scale, grey = NaN/∞.\n",
                m = n - 1
            );
            let _ = writeln!(
                s,
                "| warp | variant | shape | max [u] | at (u, v) | median [u] | nodes > 4 u | NaN | figure |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
            for m in &self.f32_maps {
                let f = Self::map_file_name(m);
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {} | {:.1}% | {} | [{f}]({f}) |",
                    m.warp,
                    m.variant,
                    m.shape,
                    fmt_num(m.max_ulps),
                    fmt_uv(m.worst),
                    fmt_num(m.median_ulps),
                    100.0 * m.above_4,
                    m.non_finite
                );
            }
            s.push('\n');
            for m in &self.f32_maps {
                let f = Self::map_file_name(m);
                let _ = writeln!(s, "![{} {} f32 error]({f})", m.warp, m.variant);
            }
        }
        s
    }

    /// Writes `precision_cells.csv` (every warp × variant × shape × type),
    /// `precision_summary.csv` (every warp × variant × type) and
    /// `precision_f32_maps.csv` (the error maps' statistics) into `dir`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_csv(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        let mut t = String::from(
            "warp,variant,shape,hard,type,rejected,points,max_ulps,median_ulps,worst_u,worst_v,own_max_ulps,\
             non_finite,reference_non_finite,outside,max_outside_ulps,max_kappa_ratio,worst_kappa_u,worst_kappa_v,\
             max_kappa_ulps,outside_kappa_bound,kappa_error,jacobian_max_dev,jacobian_non_finite\n",
        );
        for c in &self.cells {
            let (wu, wv) = uv_csv(c.worst);
            let (ku, kv) = uv_csv(c.worst_kappa_ratio);
            let _ = writeln!(
                t,
                "{},{},{},{},{},{},{},{:e},{:e},{wu},{wv},{:e},{},{},{},{:e},{},{ku},{kv},{},{},{},{:e},{}",
                csv_field(&c.warp),
                csv_field(&c.variant),
                csv_field(&c.shape),
                c.hard,
                c.scalar,
                c.rejected,
                c.points,
                c.max_ulps,
                c.median_ulps,
                c.own_max_ulps,
                c.non_finite,
                c.reference_non_finite,
                c.outside,
                c.max_outside_ulps,
                opt_csv(c.max_kappa_ratio),
                opt_csv(c.max_kappa_ulps),
                c.outside_bound,
                csv_field(c.kappa_error.as_deref().unwrap_or("")),
                c.jacobian_max_dev,
                c.jacobian_non_finite
            );
        }
        let p = dir.join("precision_cells.csv");
        std::fs::write(&p, t)?;
        out.push(p);

        let mut t = String::from(
            "warp,variant,type,shapes,rejected,points,max_ulps,worst_shape,worst_u,worst_v,median_ulps,own_max_ulps,\
             non_finite,reference_non_finite,outside,outside_kappa_bound,max_kappa_ratio,worst_kappa_shape,\
             kappa_failures,jacobian_max_dev,jacobian_non_finite\n",
        );
        for r in &self.summary {
            let (shape, (wu, wv)) = match &r.worst {
                Some((sh, uv)) => (sh.clone(), uv_csv(Some(*uv))),
                None => (String::new(), uv_csv(None)),
            };
            let _ = writeln!(
                t,
                "{},{},{},{},{},{},{:e},{},{wu},{wv},{:e},{:e},{},{},{},{},{},{},{},{:e},{}",
                csv_field(&r.warp),
                csv_field(&r.variant),
                r.scalar,
                r.shapes,
                r.rejected,
                r.points,
                r.max_ulps,
                csv_field(&shape),
                r.median_ulps,
                r.own_max_ulps,
                r.non_finite,
                r.reference_non_finite,
                r.outside,
                r.outside_bound,
                opt_csv(r.max_kappa_ratio),
                csv_field(r.worst_kappa_shape.as_deref().unwrap_or("")),
                r.kappa_failures,
                r.jacobian_max_dev,
                r.jacobian_non_finite
            );
        }
        let p = dir.join("precision_summary.csv");
        std::fs::write(&p, t)?;
        out.push(p);

        let mut t = String::from(
            "warp,variant,shape,nodes,max_ulps,worst_u,worst_v,median_ulps,fraction_above_4,non_finite,figure\n",
        );
        for m in &self.f32_maps {
            let _ = writeln!(
                t,
                "{},{},{},{},{:e},{:e},{:e},{:e},{},{},{}",
                csv_field(&m.warp),
                csv_field(&m.variant),
                csv_field(&m.shape),
                m.nodes,
                m.max_ulps,
                m.worst.0,
                m.worst.1,
                m.median_ulps,
                m.above_4,
                m.non_finite,
                Self::map_file_name(m)
            );
        }
        let p = dir.join("precision_f32_maps.csv");
        std::fs::write(&p, t)?;
        out.push(p);
        Ok(out)
    }

    /// Writes one SVG heat map per `f32` error map
    /// ([`PrecisionStudy::map_file_name`]): log colour scale from
    /// `1/16` unit (or the smallest error above it) to the map's max.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_figures(&self, dir: &Path) -> io::Result<Vec<Figure>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        for m in &self.f32_maps {
            let n = m.nodes;
            let half = 0.5 / (n - 1) as f64;
            let floor = 1.0 / 16.0;
            let values: Vec<f64> = m
                .values
                .iter()
                .map(|&x| if x.is_finite() { x.max(floor) } else { x })
                .collect();
            let hi = m.max_ulps.max(2.0 * floor);
            let mut map = HeatMap::new(
                &format!("{} ({}, {}): f32 error", m.warp, m.variant, m.shape),
                n,
                n,
                values,
            )?
            .axes(
                Axis::linear("u").with_range(-half, 1.0 + half),
                Axis::linear("v").with_range(-half, 1.0 + half),
            )
            .value_axis("error [units of 2^-24 · extent]", Scale::Log10);
            map.value_range = Some((floor, hi));
            out.push(write_heat_map_svg(&dir.join(Self::map_file_name(m)), &map)?);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::verify_figure;
    use areawarp::harness::sensitivity::check_precision_conditioned;

    fn quick() -> &'static PrecisionStudy {
        use std::sync::OnceLock;
        static STUDY: OnceLock<PrecisionStudy> = OnceLock::new();
        STUDY.get_or_init(|| run(&PrecisionConfig::quick()).expect("quick precision study"))
    }

    #[test]
    fn precision_tables_cover_every_warp_variant_and_type() {
        let s = quick();
        for (warp, variants) in warp_variants() {
            for variant in variants {
                for scalar in ["f32", "f64"] {
                    let r = s
                        .summary_of(warp, variant, scalar)
                        .unwrap_or_else(|| panic!("{warp} {variant} {scalar} missing"));
                    assert!(r.shapes > 0, "{r:?}");
                    assert!(r.points >= 64 * r.shapes, "{r:?}");
                    assert_eq!(r.reference_non_finite, 0, "{r:?}");
                }
            }
        }
        // Whole ladders: every hard shape is a cell, in both types.
        for (name, _) in hard_triangles() {
            assert!(
                s.cell("spherical-triangle", "literal", &name, "f32")
                    .is_some()
            );
        }
        for (name, _) in hard_rectangles() {
            assert!(
                s.cell("spherical-rectangle", "robust", &name, "f64")
                    .is_some()
            );
        }
        let md = s.to_markdown();
        for warp in WARPS {
            assert!(
                md.contains(&format!("| {warp} |")),
                "{warp} not in the table"
            );
        }
        assert_eq!(
            s.summary.len(),
            2 * warp_variants().iter().map(|v| v.1.len()).sum::<usize>()
        );
    }

    #[test]
    fn precision_robust_solid_angle_maps_within_kappa_bound_f64() {
        // Mirrors the shapes' own tests: in f64 the robust maps are finite,
        // on the shape and within 16·max(u, κ) on every shape of the
        // ladders (the triangle's test counts "outside" with the 4-unit
        // tolerance, the rectangle's with the κ bound).
        let s = quick();
        for warp in ["spherical-triangle", "spherical-rectangle"] {
            let cells: Vec<&PrecisionCell> = s
                .cells
                .iter()
                .filter(|c| c.warp == warp && c.variant == "robust" && c.scalar == "f64")
                .collect();
            assert!(cells.len() >= 10, "{warp}");
            for c in cells {
                assert!(!c.rejected, "{c:?}");
                assert_eq!(c.non_finite + c.reference_non_finite, 0, "{c:?}");
                let ratio = c.max_kappa_ratio.unwrap_or(f64::INFINITY);
                assert!(ratio <= 1.0, "{c:?}");
                assert_eq!(c.outside_bound, 0, "{c:?}");
                if warp == "spherical-triangle" {
                    assert_eq!(c.outside, 0, "{c:?}");
                }
                assert!(c.jacobian_max_dev < 1e-60, "{c:?}");
            }
        }
        // The literal maps are measurably worse somewhere on the ladders.
        let lit = s
            .summary_of("spherical-triangle", "literal", "f64")
            .unwrap();
        let rob = s.summary_of("spherical-triangle", "robust", "f64").unwrap();
        assert!(
            lit.non_finite > 0 || lit.max_ulps > 1e3 * rob.max_ulps.max(1.0),
            "{lit:?}"
        );
    }

    fn conditioned<T: Real>(
        w: &SphericalTriangle<f64>,
        points: &[(f64, f64)],
    ) -> areawarp::harness::sensitivity::ConditionedReport {
        let wt = w.at::<T>().unwrap();
        let params = coords(&[wt.a(), wt.b(), wt.c()]);
        check_precision_conditioned::<T, _, _, _>(
            w,
            |p: &[M]| SphericalTriangle::new(vec3_at(p, 0), vec3_at(p, 3), vec3_at(p, 6)),
            &params,
            points,
        )
        .unwrap()
    }

    #[test]
    fn precision_cell_agrees_with_check_precision_conditioned() {
        // The study's own evaluation against the harness's, on robust
        // hard triangles in f64 and f32.
        let points = PrecisionConfig::quick().points();
        // Two hard triangles that f32 accepts (the 1e-10 and 1e-12 sr ones
        // round to degenerate triangles in f32).
        let accepted: Vec<(String, [Vec3<f64>; 3])> = hard_triangles()
            .into_iter()
            .filter(|(_, [a, b, c])| {
                SphericalTriangle::<f32>::new(a.convert(), b.convert(), c.convert()).is_ok()
            })
            .collect();
        assert!(accepted.len() >= 4, "{}", accepted.len());
        for k in [1, accepted.len() - 1] {
            let (name, [a, b, c]) = accepted[k].clone();
            let w = SphericalTriangle::new(a, b, c).unwrap();
            for (r, scalar) in [
                (conditioned::<f64>(&w, &points), "f64"),
                (conditioned::<f32>(&w, &points), "f32"),
            ] {
                let cell = quick()
                    .cell("spherical-triangle", "robust", &name, scalar)
                    .unwrap();
                let ratio = cell.max_kappa_ratio.unwrap();
                assert!(
                    (ratio - r.max_ratio).abs() <= 1e-12 * r.max_ratio.max(1e-300),
                    "{name} {scalar}: {ratio} vs {r:?}"
                );
                assert_eq!(cell.non_finite, r.non_finite);
                assert_eq!(cell.outside_bound, r.outside);
            }
        }
    }

    #[test]
    fn precision_study_is_identical_for_one_and_two_threads() {
        let config = PrecisionConfig {
            max_shapes: Some(2),
            heat_map_nodes: 6,
            // The projected polygon's κ (Newton at 256 bits for every
            // perturbed vertex) would dominate the single-thread run.
            warps: Some(
                WARPS
                    .iter()
                    .filter(|&&w| w != "projected-polygon")
                    .map(|w| w.to_string())
                    .collect(),
            ),
            random_points: 2,
            ..PrecisionConfig::quick()
        };
        let run_with = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(&config).unwrap())
        };
        let one = run_with(1);
        let two = run_with(2);
        assert_eq!(one, two);
        assert!(!one.cells.is_empty() && !one.f32_maps.is_empty());
    }

    #[test]
    fn precision_figures_are_written_and_non_trivial() {
        let s = quick();
        let dir = std::env::temp_dir().join(format!("areawarp-precision-{}", std::process::id()));
        let figs = s.write_figures(&dir).unwrap();
        assert_eq!(figs.len(), s.f32_maps.len());
        // One per warp at least.
        for warp in WARPS {
            assert!(s.f32_maps.iter().any(|m| m.warp == warp), "{warp}");
        }
        for f in &figs {
            let check = verify_figure(&f.path).unwrap();
            assert_eq!(check.marks, 144, "{f:?}");
            assert!(check.distinct_colors > 1, "{f:?}: a constant map");
        }
        let csv = s.write_csv(&dir).unwrap();
        assert_eq!(csv.len(), 3);
        let cells = std::fs::read_to_string(&csv[0]).unwrap();
        assert_eq!(cells.lines().count(), s.cells.len() + 1);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn precision_config_is_validated() {
        let bad = PrecisionConfig {
            heat_map_nodes: 1,
            ..PrecisionConfig::quick()
        };
        assert!(run(&bad).is_err());
        let bad = PrecisionConfig {
            max_shapes: Some(0),
            ..PrecisionConfig::quick()
        };
        assert!(run(&bad).is_err());
        let bad = PrecisionConfig {
            warps: Some(vec!["torus".to_string()]),
            ..PrecisionConfig::quick()
        };
        assert!(run(&bad).is_err());
        assert_eq!(slug("cubic+1 Newton"), "cubic-1-newton");
        assert_eq!(median(&[3.0, f64::NAN, 1.0]), 2.0);
    }
}
