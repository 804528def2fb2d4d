//! A minimal scene model for the variance studies — only what the
//! experiments of Ureña (2000) and Ureña, Fajardo and King (2013) need, no
//! renderer: receivers (a point and a normal), one planar polygonal
//! [`Emitter`] (triangle, rectangle, any simple polygon) with constant
//! radiance or a [`RectangularPattern`], optional planar occluders with an
//! exact ray–polygon test, and Lambertian / Phong [`Reflectance`].
//!
//! Everything is in `f64` and in world coordinates; directions are unit
//! vectors pointing *away* from the receiver.
//!
//! # Integrands and references
//! All integrals are over incident directions ω at a receiver with normal
//! `N`, in solid angle ([`Quantity`], [`Scene::integrand`]):
//!
//! | quantity | integrand | exact reference (no occluders) |
//! |---|---|---|
//! | irradiance `E` | `L_i(ω) cos⁺θ` | Lambert: `L Π`, or `Σ_cells L_c Π_c` ([`lambert::irradiance`]) |
//! | form factor `F` | `V(ω) cos⁺θ / π` | `Π / π` ([`lambert::form_factor`]) |
//! | reflected radiance `L_o` | `L_i(ω) f_r(ω, ω_o) cos⁺θ` | `(ρ/π) E` for Lambertian; none for Phong |
//!
//! with `Π` the projected solid angle of the polygon clipped to the
//! receiver's horizon, `L_i(ω)` the emitter's radiance where the ray hits
//! it (0 toward its back side if one-sided, 0 if an occluder is hit
//! first), `V(ω)` the same test without radiance. Where no exact value
//! exists, [`Scene::reference`] computes a converged estimate.
//!
//! # Strategies
//! [`strategies`] provides the samplers, all as directions with densities
//! in solid angle so that [`Mis`] can combine any of them: uniform area
//! sampling of the emitter (`p_ω = r² / (A cos θ_e)`), cosine and BRDF
//! lobes, spherical triangles (∝ solid angle), the projected polygon.
//!
//! # Example
//! ```
//! use areawarp::estimate::{Heuristic, Mis, Strategy};
//! use areawarp::sampling::hammersley;
//! use areawarp_lab::scene::{Emitter, PlanarPolygon, Quantity, Receiver, Scene, lambert, strategies};
//! use areawarp::Vec3;
//!
//! // A unit square light facing down from height 1, a receiver below it.
//! let light = PlanarPolygon::rectangle(
//!     Vec3::new(-0.5, -0.5, 1.0),
//!     Vec3::new(0.0, 1.0, 0.0),
//!     Vec3::new(1.0, 0.0, 0.0),
//! )?;
//! let scene = Scene::new(Emitter::constant(light, 1.0)?);
//! let rx = Receiver::new(Vec3::new(0.2, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0))?;
//! let exact = scene.exact(&rx, &Quantity::Irradiance).unwrap();
//! assert!((exact - lambert::irradiance(scene.emitter(), &rx)).abs() < 1e-15);
//!
//! let area = strategies::AreaSampling::new(scene.emitter().polygon(), rx.position())?;
//! let cosine = strategies::cosine_sampling(&rx)?;
//! let s: [&dyn Strategy<Point = Vec3<f64>>; 2] = [&area, &cosine];
//! let mis = Mis::new(&s, &[256, 256], Heuristic::Balance)?;
//! let e = mis.estimate(|d| scene.integrand(&rx, &Quantity::Irradiance, d), |_| hammersley::<f64>(256))?;
//! assert!((e.value / exact - 1.0).abs() < 0.02);
//! # Ok::<(), areawarp::WarpError>(())
//! ```

pub mod bilinear;
mod emitter;
pub mod lambert;
mod polygon;
mod reflectance;
pub mod setup;
pub mod strategies;

pub use emitter::{Emitter, Radiance, RectangularPattern};
pub use polygon::{Hit, PlanarPolygon, clip_half_space, polygon_area};
pub use reflectance::Reflectance;

use areawarp::error::WarpError;
use areawarp::estimate::{Estimate, Heuristic, Mis, Strategy, job_rng};
use areawarp::sampling::jittered;
pub use areawarp::vector::Frame;
use areawarp::vector::Vec3;
use core::f64::consts::PI;

/// A receiving point with its unit surface normal.
#[derive(Clone, Debug, PartialEq)]
pub struct Receiver {
    position: Vec3<f64>,
    frame: Frame,
}

impl Receiver {
    /// The receiver at `position` with normal `normal` (normalized here).
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for a non-finite position, and as
    /// [`Frame::from_normal`].
    pub fn new(position: Vec3<f64>, normal: Vec3<f64>) -> Result<Self, WarpError> {
        if !position.is_finite() {
            return Err(WarpError::NonFinite {
                what: "receiver position",
            });
        }
        Ok(Receiver {
            position,
            frame: Frame::from_normal(&normal)?,
        })
    }

    /// The position.
    pub fn position(&self) -> &Vec3<f64> {
        &self.position
    }

    /// The unit normal.
    pub fn normal(&self) -> &Vec3<f64> {
        &self.frame.normal
    }

    /// A frame with the normal as local `+z`.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }
}

/// `count` receivers on the ray `start + d · direction̂`, with distances
/// `d_k = near · (far/near)^(k/(count−1))` spaced geometrically — dense
/// near `start` (e.g. the foot of a light) — all with the same `normal`.
///
/// # Errors
/// [`WarpError::InvalidParameter`] unless `0 < near ≤ far` are finite and
/// `count ≥ 1`; as [`Receiver::new`].
pub fn receivers_on_line(
    start: &Vec3<f64>,
    direction: &Vec3<f64>,
    normal: &Vec3<f64>,
    near: f64,
    far: f64,
    count: usize,
) -> Result<Vec<Receiver>, WarpError> {
    if !(near > 0.0 && near <= far && far.is_finite()) || count == 0 {
        return Err(WarpError::InvalidParameter {
            name: "receiver distances",
            expected: "0 < near <= far (finite) and count >= 1",
        });
    }
    let dir = direction.normalized().ok_or(WarpError::Degenerate {
        what: "zero direction",
    })?;
    (0..count)
        .map(|k| {
            let f = if count == 1 {
                0.0
            } else {
                k as f64 / (count - 1) as f64
            };
            let d = near * (far / near).powf(f);
            Receiver::new(start.add(&dir.scale(&d)), *normal)
        })
        .collect()
}

/// `count_a × count_b` receivers at the cell centres of the parallelogram
/// `origin + s · axis_a + t · axis_b`, `s, t ∈ [0, 1]`:
/// `s = (i + ½)/count_a`, `t = (j + ½)/count_b`, `i` fastest.
///
/// # Errors
/// [`WarpError::InvalidParameter`] for a zero count; as [`Receiver::new`].
pub fn receivers_on_grid(
    origin: &Vec3<f64>,
    axis_a: &Vec3<f64>,
    axis_b: &Vec3<f64>,
    normal: &Vec3<f64>,
    count_a: usize,
    count_b: usize,
) -> Result<Vec<Receiver>, WarpError> {
    if count_a == 0 || count_b == 0 {
        return Err(WarpError::InvalidParameter {
            name: "receiver counts",
            expected: "at least one receiver along each axis",
        });
    }
    let mut out = Vec::with_capacity(count_a * count_b);
    for j in 0..count_b {
        for i in 0..count_a {
            let s = (i as f64 + 0.5) / count_a as f64;
            let t = (j as f64 + 0.5) / count_b as f64;
            let p = origin.add(&axis_a.scale(&s)).add(&axis_b.scale(&t));
            out.push(Receiver::new(p, *normal)?);
        }
    }
    Ok(out)
}

/// What is integrated at a receiver (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum Quantity {
    /// Irradiance `E = ∫ L_i cos⁺θ dω`.
    Irradiance,
    /// The point-to-polygon form factor `F = (1/π) ∫ V cos⁺θ dω` to the
    /// emitter's polygon (geometric: radiance and sidedness ignored).
    FormFactor,
    /// Reflected radiance `L_o = ∫ L_i f_r(ω, ω_o) cos⁺θ dω` toward the unit
    /// direction `outgoing`.
    Radiance {
        /// The BRDF.
        reflectance: Reflectance,
        /// The outgoing direction ω_o (unit, away from the surface).
        outgoing: Vec3<f64>,
    },
}

/// One emitter and optional occluders.
#[derive(Clone, Debug)]
pub struct Scene {
    emitter: Emitter,
    occluders: Vec<PlanarPolygon>,
}

impl Scene {
    /// A scene with one emitter and no occluders.
    pub fn new(emitter: Emitter) -> Self {
        Scene {
            emitter,
            occluders: Vec::new(),
        }
    }

    /// The scene with one more occluder (opaque, both sides).
    pub fn with_occluder(mut self, occluder: PlanarPolygon) -> Self {
        self.occluders.push(occluder);
        self
    }

    /// The emitter.
    pub fn emitter(&self) -> &Emitter {
        &self.emitter
    }

    /// The occluders.
    pub fn occluders(&self) -> &[PlanarPolygon] {
        &self.occluders
    }

    /// `true` if an occluder meets the ray `origin + t · direction` at some
    /// `0 < t < t_max` (strictly; hits on an occluder's boundary count, see
    /// [`PlanarPolygon`]).
    pub fn occluded(&self, origin: &Vec3<f64>, direction: &Vec3<f64>, t_max: f64) -> bool {
        self.occluders
            .iter()
            .any(|o| o.blocks(origin, direction, t_max))
    }

    /// `true` if the segment between `from` and `to` (exclusive) meets no
    /// occluder.
    pub fn visible(&self, from: &Vec3<f64>, to: &Vec3<f64>) -> bool {
        !self.occluded(from, &to.sub(from), 1.0)
    }

    /// Where the ray from `origin` along `direction` meets the emitter, if it
    /// does before any occluder.
    pub fn emitter_hit(&self, origin: &Vec3<f64>, direction: &Vec3<f64>) -> Option<Hit> {
        let hit = self.emitter.polygon().intersect(origin, direction)?;
        (!self.occluded(origin, direction, hit.t)).then_some(hit)
    }

    /// The radiance arriving at `origin` from `direction`: the emitter's
    /// radiance toward `origin` where the ray hits it unoccluded, else 0.
    pub fn incident_radiance(&self, origin: &Vec3<f64>, direction: &Vec3<f64>) -> f64 {
        match self.emitter_hit(origin, direction) {
            Some(hit) => self.emitter.emitted(&hit.point, &direction.neg()),
            None => 0.0,
        }
    }

    /// The integrand of `quantity` at the receiver for the unit direction
    /// `direction` (solid-angle measure; see the module docs).
    pub fn integrand(
        &self,
        receiver: &Receiver,
        quantity: &Quantity,
        direction: &Vec3<f64>,
    ) -> f64 {
        let cos = receiver.normal().dot(direction);
        if cos.is_nan() || cos <= 0.0 {
            return 0.0;
        }
        let x = receiver.position();
        match quantity {
            Quantity::Irradiance => self.incident_radiance(x, direction) * cos,
            Quantity::FormFactor => {
                if self.emitter_hit(x, direction).is_some() {
                    cos / PI
                } else {
                    0.0
                }
            }
            Quantity::Radiance {
                reflectance,
                outgoing,
            } => {
                let l = self.incident_radiance(x, direction);
                if l == 0.0 {
                    0.0
                } else {
                    l * reflectance.brdf(receiver.normal(), direction, outgoing) * cos
                }
            }
        }
    }

    /// The exact value of `quantity` by Lambert's formula, when there is
    /// one: no occluders, and a Lambertian BRDF for reflected radiance
    /// (`(ρ/π) E`, 0 if `ω_o` is below the surface). `None` otherwise.
    pub fn exact(&self, receiver: &Receiver, quantity: &Quantity) -> Option<f64> {
        if !self.occluders.is_empty() {
            return None;
        }
        match quantity {
            Quantity::Irradiance => Some(lambert::irradiance(&self.emitter, receiver)),
            Quantity::FormFactor => Some(lambert::form_factor(self.emitter.polygon(), receiver)),
            Quantity::Radiance {
                reflectance: Reflectance::Lambertian { albedo },
                outgoing,
            } => Some(if receiver.normal().dot(outgoing) > 0.0 {
                albedo / PI * lambert::irradiance(&self.emitter, receiver)
            } else {
                0.0
            }),
            Quantity::Radiance { .. } => None,
        }
    }

    /// A converged reference for `quantity` at the receiver: the balance
    /// heuristic over area sampling of the emitter, cosine sampling and,
    /// for a Phong BRDF, BRDF sampling, with `samples` jittered points per
    /// strategy (rounded down to a square grid) drawn from
    /// [`job_rng`]`(seed, 0)`. Its [`Estimate::variance`] is the
    /// independent-sample estimate, an upper bound for jittered points.
    ///
    /// # Errors
    /// As the strategies' constructors; [`WarpError::InvalidParameter`] for
    /// fewer than 4 samples.
    pub fn reference(
        &self,
        receiver: &Receiver,
        quantity: &Quantity,
        samples: usize,
        seed: u64,
    ) -> Result<Estimate, WarpError> {
        let side = (samples as f64).sqrt().floor() as usize;
        if side < 2 {
            return Err(WarpError::InvalidParameter {
                name: "samples",
                expected: "at least 4 samples per strategy",
            });
        }
        let n = side * side;
        let area = strategies::AreaSampling::new(self.emitter.polygon(), receiver.position())?;
        let cosine = strategies::cosine_sampling(receiver)?;
        let brdf = match quantity {
            Quantity::Radiance {
                reflectance: r @ Reflectance::Phong { .. },
                outgoing,
            } => Some(strategies::brdf_sampling(r, receiver, outgoing)?),
            _ => None,
        };
        let mut list: Vec<&dyn Strategy<Point = Vec3<f64>>> = vec![&area, &cosine];
        if let Some(b) = &brdf {
            list.push(b);
        }
        let counts = vec![n; list.len()];
        let mis = Mis::new(&list, &counts, Heuristic::Balance)?;
        let mut rng = job_rng(seed, 0);
        let e = mis.estimate(
            |d| self.integrand(receiver, quantity, d),
            |_| jittered::<f64, _>(side, side, &mut rng),
        )?;
        Ok(e.as_estimate())
    }
}

#[cfg(test)]
mod tests;
