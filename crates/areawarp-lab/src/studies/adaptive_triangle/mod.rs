//! The measurements of `docs/adaptive-triangle.md` (issue 5, item 4): the
//! second moment `U` of the adaptive estimator against the ideal `U₀`, its
//! bias, and its sample distribution, over several triangles, integrands
//! and thresholds K.

use crate::jobs::run_jobs;
use crate::scene::{
    Emitter, PlanarPolygon, Radiance, Receiver, RectangularPattern, Scene, lambert,
};
use areawarp::adaptive::{AdaptiveTriangle, Allocation, PartitionSummary};
use areawarp::error::WarpError;
use areawarp::estimate::{Stats, job_seed};
use areawarp::sampling::jittered;
use areawarp::shapes::ProjectedPolygon;
use areawarp::vector::Vec3;
use areawarp::warp::Warp;
use std::fmt::Write as _;

mod study;
pub use self::study::*;
#[cfg(test)]
mod tests;
/// Cells per side of the checkerboard of [`StudyIntegrand::Pattern`].
const PATTERN_CELLS: usize = 5;
/// Its two radiances.
const PATTERN_HIGH: f64 = 1.0;
const PATTERN_LOW: f64 = 0.1;
/// The direction `d` of [`StudyIntegrand::Smooth`], world frame.
const SMOOTH_AXIS: [f64; 3] = [0.5, -0.4, 0.3];
/// Gauss–Legendre nodes per axis for the smooth references.
const QUADRATURE_NODES: usize = 48;

/// The function `f` integrated against `cos θ` in a study case (the
/// paper's `f`, e.g. the incident radiance `L_i`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StudyIntegrand {
    /// `f = 1` on the triangle: `I = σ⊥` (Lambert) and `U₀ = σ⊥²` exactly.
    Constant,
    /// A checkerboard ([`RectangularPattern::aligned`], 5 × 5 cells over
    /// the planar triangle, radiances 1 and 0.1): `I` and
    /// `U₀ = σ⊥ ∫ f² dσ⊥` exact by Lambert's formula per cell.
    Pattern,
    /// `f(ω) = (1 + ω·d)²`, `d = (0.5, −0.4, 0.3)` (world frame): smooth,
    /// from 0.09 to 2.9; `I` and `U₀` by Gauss–Legendre quadrature over
    /// Arvo's map (48 × 48 nodes per triangle, `v = s²`), converged to
    /// rounding.
    Smooth,
    /// The checkerboard seen through three opaque bars halfway between
    /// the receiver and the triangle; `I` and `U₀` from jittered
    /// cosine-weighted samples ([`ProjectedPolygon`]), with their standard
    /// errors.
    PatternOccluded,
    /// A given [`Scene`]'s incident radiance ([`StudyCase::from_scene`]),
    /// referenced like [`StudyIntegrand::PatternOccluded`].
    Scene,
}

impl StudyIntegrand {
    /// A short label.
    pub fn as_str(&self) -> &'static str {
        match self {
            StudyIntegrand::Constant => "constant",
            StudyIntegrand::Pattern => "pattern",
            StudyIntegrand::Smooth => "smooth",
            StudyIntegrand::PatternOccluded => "pattern+occluders",
            StudyIntegrand::Scene => "scene",
        }
    }
}

/// A triangle seen from a receiver, with the function to integrate.
#[derive(Clone, Debug)]
pub struct StudyCase {
    /// The case's name (the triangle's).
    pub name: String,
    /// The integrand.
    pub integrand: StudyIntegrand,
    /// The triangle's corners in space.
    pub points: [Vec3<f64>; 3],
    /// The receiver.
    pub receiver: Receiver,
    scene: Scene,
}

impl StudyCase {
    /// The planar triangle `points` seen from `receiver`, with the given
    /// integrand (not [`StudyIntegrand::Scene`]). The emitter is two-sided.
    ///
    /// # Errors
    /// As [`PlanarPolygon::triangle`] and [`RectangularPattern::aligned`];
    /// [`WarpError::InvalidParameter`] for [`StudyIntegrand::Scene`].
    pub fn new(
        name: &str,
        points: [Vec3<f64>; 3],
        receiver: Receiver,
        integrand: StudyIntegrand,
    ) -> Result<Self, WarpError> {
        let light = PlanarPolygon::new(&points)?;
        let radiance = match integrand {
            StudyIntegrand::Constant | StudyIntegrand::Smooth => Radiance::Constant(1.0),
            StudyIntegrand::Pattern | StudyIntegrand::PatternOccluded => {
                Radiance::Pattern(RectangularPattern::aligned(
                    &light,
                    PATTERN_CELLS,
                    PATTERN_CELLS,
                    PATTERN_HIGH,
                    PATTERN_LOW,
                )?)
            }
            StudyIntegrand::Scene => {
                return Err(WarpError::InvalidParameter {
                    name: "integrand",
                    expected: "Constant, Pattern, Smooth or PatternOccluded (use from_scene)",
                });
            }
        };
        let mut scene = Scene::new(Emitter::new(light, radiance)?.with_two_sided(true));
        if integrand == StudyIntegrand::PatternOccluded {
            // Three bars in the plane of the triangle scaled by 1/2 about
            // the receiver: bands s ∈ [s₀, s₀ + 0.12] of the triangle's
            // affine coordinates x + ½((a − x) + s(b − a) + t(c − a)).
            let x = receiver.position();
            let [a, b, c] = &points;
            let at = |s: f64, t: f64| {
                x.add(
                    &a.sub(x)
                        .add(&b.sub(a).scale(&s))
                        .add(&c.sub(a).scale(&t))
                        .scale(&0.5),
                )
            };
            for s0 in [0.15, 0.45, 0.75] {
                let s1 = s0 + 0.12;
                scene = scene.with_occluder(PlanarPolygon::new(&[
                    at(s0, -0.1),
                    at(s1, -0.1),
                    at(s1, 1.1),
                    at(s0, 1.1),
                ])?);
            }
        }
        Ok(StudyCase {
            name: name.to_string(),
            integrand,
            points,
            receiver,
            scene,
        })
    }

    /// A case from a scene whose emitter is a triangle (e.g.
    /// [`setup::patterned_triangle`](crate::scene::setup::patterned_triangle)):
    /// `f` is the scene's incident radiance (pattern and occluders
    /// included).
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] if the emitter is not a triangle.
    pub fn from_scene(name: &str, scene: &Scene, receiver: Receiver) -> Result<Self, WarpError> {
        let v = scene.emitter().polygon().vertices();
        if v.len() != 3 {
            return Err(WarpError::InvalidParameter {
                name: "scene",
                expected: "a triangular emitter",
            });
        }
        Ok(StudyCase {
            name: name.to_string(),
            integrand: StudyIntegrand::Scene,
            points: [v[0], v[1], v[2]],
            receiver,
            scene: scene.clone(),
        })
    }

    /// The function `f(ω)` for a unit world direction ω: the incident
    /// radiance (0 off the triangle or behind an occluder), times
    /// `(1 + ω·d)²` for [`StudyIntegrand::Smooth`].
    pub fn f(&self, direction: &Vec3<f64>) -> f64 {
        let l = self
            .scene
            .incident_radiance(self.receiver.position(), direction);
        if self.integrand == StudyIntegrand::Smooth && l != 0.0 {
            let d = Vec3::new(SMOOTH_AXIS[0], SMOOTH_AXIS[1], SMOOTH_AXIS[2]);
            let s = 1.0 + direction.dot(&d);
            l * s * s
        } else {
            l
        }
    }

    /// The adaptive sampler of this case's triangle.
    ///
    /// # Errors
    /// As [`AdaptiveTriangle::from_points`].
    pub fn sampler(&self, k_threshold: f64) -> Result<AdaptiveTriangle, WarpError> {
        let [a, b, c] = &self.points;
        AdaptiveTriangle::from_points(
            [a, b, c],
            self.receiver.position(),
            self.receiver.normal(),
            k_threshold,
        )
    }

    /// The cosine-weighted sampler of this case's triangle (the ideal
    /// density `cos θ/σ⊥`).
    ///
    /// # Errors
    /// As [`ProjectedPolygon::from_points`].
    pub fn cosine_sampler(&self) -> Result<ProjectedPolygon<f64>, WarpError> {
        ProjectedPolygon::from_points(
            &self.points,
            self.receiver.position(),
            self.receiver.normal(),
        )
    }

    /// `I = ∫ f cos dω` and `U₀ = σ⊥ ∫ f² cos dω`, exact or converged
    /// (see [`StudyIntegrand`]), each with its standard error (0 for the
    /// exact ones), and the `U₀` of `reference_samples` jittered
    /// cosine-weighted samples as an independent check.
    ///
    /// # Errors
    /// As [`StudyCase::sampler`] and [`StudyCase::cosine_sampler`].
    pub fn reference(&self, reference_samples: usize, seed: u64) -> Result<Reference, WarpError> {
        let t = self.sampler(1.0)?;
        let sp = t.projected_solid_angle();
        let cos = self.cosine_estimate(reference_samples, seed)?;
        let (value, value_se, u0, u0_se, method) = match self.integrand {
            StudyIntegrand::Constant => (sp, 0.0, sp * sp, 0.0, "Lambert"),
            StudyIntegrand::Pattern => {
                let light = self.scene.emitter().polygon().clone();
                let squared = RectangularPattern::aligned(
                    &light,
                    PATTERN_CELLS,
                    PATTERN_CELLS,
                    PATTERN_HIGH * PATTERN_HIGH,
                    PATTERN_LOW * PATTERN_LOW,
                )?;
                let e2 = Emitter::new(light, Radiance::Pattern(squared))?.with_two_sided(true);
                let i = lambert::irradiance(self.scene.emitter(), &self.receiver);
                let i2 = lambert::irradiance(&e2, &self.receiver);
                (i, 0.0, sp * i2, 0.0, "Lambert per cell")
            }
            StudyIntegrand::Smooth => {
                let i = self.quadrature(&t, |f| f);
                let i2 = self.quadrature(&t, |f| f * f);
                (i, 0.0, sp * i2, 0.0, "Gauss-Legendre")
            }
            StudyIntegrand::PatternOccluded | StudyIntegrand::Scene => (
                cos.value,
                cos.value_se,
                cos.u0,
                cos.u0_se,
                "cosine-weighted, jittered",
            ),
        };
        Ok(Reference {
            value,
            value_se,
            u0,
            u0_se,
            method,
            projected_solid_angle: sp,
            solid_angle: t.solid_angle(),
            u0_cosine: cos.u0,
            u0_cosine_se: cos.u0_se,
        })
    }

    /// `∫ h(f(ω)) cos θ dω` by tensor Gauss–Legendre quadrature of
    /// `σ_T ∫∫ h(f(ψ(u, s²))) cos θ 2s du ds` over each starting triangle T
    /// of the sampler (the substitution `v = s²` removes the `√v` of
    /// Arvo's map at its vertex B).
    fn quadrature<H: Fn(f64) -> f64>(&self, t: &AdaptiveTriangle, h: H) -> f64 {
        let nodes = gauss_legendre(QUADRATURE_NODES);
        let mut total = 0.0;
        for (tri, _) in t.root_triangles() {
            let mut sum = 0.0;
            for (u, wu) in &nodes {
                for (s, ws) in &nodes {
                    let d = tri.map(u, &(s * s));
                    let cos = d.z.max(0.0);
                    let world = match t.frame() {
                        Some(f) => f.to_world(&d),
                        None => d,
                    };
                    let v = self.f(&world);
                    if v != 0.0 {
                        sum += wu * ws * 2.0 * s * h(v) * cos;
                    }
                }
            }
            total += sum * tri.solid_angle();
        }
        total
    }

    /// `I` and `U₀` from `samples` jittered cosine-weighted samples in 8
    /// independent batches (standard errors from the batch spread).
    fn cosine_estimate(&self, samples: usize, seed: u64) -> Result<CosineEstimate, WarpError> {
        let w = self.cosine_sampler()?;
        let sp = w.projected_solid_angle();
        let batches = 8;
        let side = ((samples / batches) as f64).sqrt().floor().max(2.0) as usize;
        let results = run_jobs(batches, seed, |_, rng| {
            let pts = jittered::<f64, _>(side, side, rng);
            let (mut s1, mut s2) = (0.0, 0.0);
            for (u, v) in &pts {
                let d = w.map(u, v);
                let f = self.f(&d);
                s1 += f;
                s2 += f * f;
            }
            let n = pts.len() as f64;
            (sp * s1 / n, sp * sp * s2 / n)
        });
        let value: Stats = results.iter().map(|r| r.0).collect();
        let u0: Stats = results.iter().map(|r| r.1).collect();
        Ok(CosineEstimate {
            value: value.mean(),
            value_se: value.std_error(),
            u0: u0.mean(),
            u0_se: u0.std_error(),
        })
    }
}

/// `I` and `U₀` from cosine-weighted samples.
struct CosineEstimate {
    value: f64,
    value_se: f64,
    u0: f64,
    u0_se: f64,
}

/// The Gauss–Legendre nodes and weights of order `n` on `[0, 1]`
/// (Newton on `P_n` from Chebyshev-like starts).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    let nf = n as f64;
    for i in 0..n {
        let mut x = (core::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            dp = nf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push(((1.0 - x) / 2.0, w / 2.0));
    }
    out
}

/// The reference values of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// `I = ∫ f cos dω`.
    pub value: f64,
    /// Its standard error (0 if exact).
    pub value_se: f64,
    /// `U₀ = σ⊥ ∫ f² cos dω`.
    pub u0: f64,
    /// Its standard error (0 if exact).
    pub u0_se: f64,
    /// How `I` and `U₀` were obtained.
    pub method: &'static str,
    /// σ⊥ of the (clipped) triangle.
    pub projected_solid_angle: f64,
    /// σ of the (clipped) triangle.
    pub solid_angle: f64,
    /// `U₀ = σ⊥² E[f²]` measured with jittered cosine-weighted samples
    /// ([`ProjectedPolygon`]), the independent check.
    pub u0_cosine: f64,
    /// Its standard error.
    pub u0_cosine_se: f64,
}
