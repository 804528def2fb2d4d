//! The catalogue: warps, variants, shapes (the extremes suite and the hard
//! ladders), built once per study.

use super::*;

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

pub(crate) fn flatten(vs: &[Vec3<f64>]) -> Vec<f64> {
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
pub(crate) fn format_of<T: Real>() -> Result<InputFormat, WarpError> {
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

pub(crate) fn kappa_values<W, F>(
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

pub(crate) fn vec3_at<R: Real>(p: &[R], i: usize) -> Vec3<R> {
    Vec3::new(p[i].clone(), p[i + 1].clone(), p[i + 2].clone())
}

pub(crate) fn coords<T: Real>(vs: &[&Vec3<T>]) -> Vec<f64> {
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
