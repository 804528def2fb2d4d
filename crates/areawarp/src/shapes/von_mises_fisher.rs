//! The von Mises–Fisher distribution on the unit sphere about `+z`,
//! density ∝ e^(κ(z − 1)), for every concentration κ from 0 to 10⁶ and
//! beyond. Derivation: `docs/von-mises-fisher.md`.

use super::local_frame::one_minus_z;
use super::turns::{clamp_unit, polar_turns, turns_of};
use crate::error::WarpError;
use crate::real::{Real, convert};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// `ln(1 + x)/x`, 1 at `x = 0` (the limit).
fn log1p_ratio<T: Real>(x: &T) -> T {
    if *x == T::zero() {
        T::one()
    } else {
        x.ln_1p() / x
    }
}

/// `−expm1(−y)/y` for `y ≥ 0`, 1 at `y = 0`.
fn one_minus_exp_ratio<T: Real>(y: &T) -> T {
    if *y == T::zero() {
        T::one()
    } else {
        -(-y.clone()).exp_m1() / y
    }
}

/// `expm1(y)/y`, 1 at `y = 0`.
fn expm1_ratio<T: Real>(y: &T) -> T {
    if *y == T::zero() {
        T::one()
    } else {
        y.exp_m1() / y
    }
}

/// `ln(1 + e^a)` without overflow.
fn softplus<T: Real>(a: &T) -> T {
    if *a > T::zero() {
        a.clone() + &(-a.clone()).exp().ln_1p()
    } else {
        a.exp().ln_1p()
    }
}

/// Directions on the unit sphere with the von Mises–Fisher density of
/// concentration κ ≥ 0 about `+z`,
///
/// pdf(p) = κ e^(κ(z − 1)) / (2π (1 − e^(−2κ)))   per steradian,
///
/// (Mitsuba's `square_to_von_mises_fisher`; κ = 0 is the uniform sphere).
/// With `w = 1 − z` ∈ [0, 2]:
///
/// ψ(u, v) = (sin θ cos 2πv, sin θ sin 2πv, 1 − w),  w = −ln(1 + u·expm1(−2κ))/κ,
///
/// `sin θ = √(w(2 − w))`. `u = 0` is the mean direction `+z`, `u = 1` the
/// antipode.
///
/// Numerics (accurate for every κ from 0 through 10⁻⁸ to 10⁶): the map
/// never forms `z` first. In the front hemisphere (`u` below the
/// median-of-hemispheres `u₀ = 1/(1 + e^(−κ))`) it computes `w` itself,
/// as `2u·r₁·ln(1 + x)/x` with `x = u·expm1(−2κ)` and
/// `r₁ = −expm1(−2κ)/(2κ)` (no division by a tiny κ, no cancellation), or,
/// where `1 + x < 1/2`, as `−ln((1 − u) + u e^(−2κ))/κ` with `1 − u` exact.
/// In the back hemisphere it computes `w' = 1 + z = 2 − w` directly from the
/// mirrored CDF, `ln(1 + (1 − u)·expm1(2κ))/κ`, in log space once
/// `expm1(2κ)` overflows. `sin θ = √(w(2 − w))` then keeps its relative
/// accuracy at both poles, for κ = 10⁻⁸ (where `1 − e^(−2κ)` would
/// cancel) and for κ = 10⁶ (where `e^(2κ)` overflows and all samples lie
/// within 10⁻³ rad of the pole).
///
/// # Density
/// As above; [`Warp::measure`] is the weighted measure
/// `∫ e^(κ(z−1)) dω = 2π(1 − e^(−2κ))/κ` (4π at κ = 0), so that
/// `pdf = e^(κ(z−1))/measure`.
///
/// # Example
/// ```
/// use areawarp::shapes::VonMisesFisher;
/// use areawarp::Warp;
///
/// let sharp = VonMisesFisher::new(1e6f64).unwrap();
/// let p = sharp.map(&0.5, &0.0);
/// // 1 − z = ln 2/κ; sin θ ≈ √(2 ln 2/κ), although z rounds to 1 − 7e-7.
/// assert!((p.x / (2.0 * 2f64.ln() / 1e6).sqrt() - 1.0).abs() < 1e-6);
/// let [u, _] = sharp.inverse(&p).unwrap();
/// assert!((u - 0.5).abs() < 1e-12);
/// let flat = VonMisesFisher::new(0.0f64).unwrap(); // uniform sphere
/// assert!((flat.pdf(&p) * 4.0 * std::f64::consts::PI - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct VonMisesFisher<T> {
    kappa: T,
    /// expm1(−2κ) ∈ [−1, 0].
    e: T,
    /// e^(−2κ).
    big_e: T,
    /// −expm1(−2κ)/(2κ), 1 at κ = 0.
    r1: T,
    /// expm1(2κ) (may be +∞).
    em: T,
    /// expm1(2κ)/(2κ), 1 at κ = 0.
    r2: T,
    /// ln expm1(2κ) = 2κ + ln(1 − e^(−2κ)), used when `em` overflows.
    ln_em: T,
    /// 1/(1 + e^(−κ)): the u of the equator.
    u_equator: T,
    norm: T,
    measure: T,
    half_pi: T,
    inv_two_pi: T,
}

impl<T: Real> VonMisesFisher<T> {
    /// The distribution of concentration `kappa ≥ 0` about `+z`.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`] for NaN/∞, [`WarpError::InvalidParameter`]
    /// for κ < 0.
    ///
    /// # Density
    /// κ e^(κ(z − 1)) / (2π(1 − e^(−2κ))) per steradian.
    ///
    /// # Example
    /// ```
    /// use areawarp::shapes::VonMisesFisher;
    /// assert!(VonMisesFisher::new(-1.0f64).is_err());
    /// assert!(VonMisesFisher::new(1e-8f32).is_ok());
    /// ```
    pub fn new(kappa: T) -> Result<Self, WarpError> {
        if !kappa.is_finite() {
            return Err(WarpError::NonFinite { what: "kappa" });
        }
        if kappa < T::zero() {
            return Err(WarpError::InvalidParameter {
                name: "kappa",
                expected: "a finite concentration >= 0",
            });
        }
        let two_k = kappa.clone() * &T::from_i64(2);
        let e = (-two_k.clone()).exp_m1();
        let em = two_k.exp_m1();
        let r1 = one_minus_exp_ratio(&two_k);
        let r2 = expm1_ratio(&two_k);
        let ln_em = two_k.clone() + &(-(-two_k.clone()).exp()).ln_1p();
        let pi = T::pi();
        let measure = pi.clone() * &T::from_i64(4) * &r1;
        Ok(VonMisesFisher {
            big_e: (-two_k).exp(),
            u_equator: T::one() / &(T::one() + &(-kappa.clone()).exp()),
            norm: T::one() / &measure,
            measure,
            half_pi: pi.clone() / &T::from_i64(2),
            inv_two_pi: T::one() / &(pi * &T::from_i64(2)),
            kappa,
            e,
            r1,
            em,
            r2,
            ln_em,
        })
    }

    /// The concentration κ.
    pub fn kappa(&self) -> &T {
        &self.kappa
    }

    /// `(1 − z, 1 + z)` of ψ(u, ·), each to full relative accuracy.
    fn heights(&self, u: &T) -> (T, T) {
        let one = T::one();
        let two = T::from_i64(2);
        if *u < self.u_equator {
            let x = u.clone() * &self.e;
            let w = if x >= -T::from_ratio(1, 2) {
                u.clone() * &two * &self.r1 * &log1p_ratio(&x)
            } else {
                // 1 + x < 1/2: here u > 1/2, so 1 − u is exact.
                -((one.clone() - u) + &(u.clone() * &self.big_e)).ln() / &self.kappa
            };
            let w_back = two - &w;
            (w, w_back)
        } else {
            // u ≥ 1/2: 1 − u is exact.
            let y = one - u;
            let w_back = if self.em.is_finite() {
                let x = y.clone() * &self.em;
                if x <= T::from_ratio(1, 2) {
                    y * &two * &self.r2 * &log1p_ratio(&x)
                } else {
                    x.ln_1p() / &self.kappa
                }
            } else {
                softplus(&(y.ln() + &self.ln_em)) / &self.kappa
            };
            let w = two - &w_back;
            (w, w_back)
        }
    }
}

impl<T: Real> Warp<T> for VonMisesFisher<T> {
    type Point = Vec3<T>;

    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let (w, w_back) = self.heights(&clamp_unit(u));
        let sin_theta = (w.clone() * &w_back).sqrt();
        let z = if w <= T::one() {
            T::one() - &w
        } else {
            w_back - &T::one()
        };
        let (x, y) = polar_turns(&sin_theta, &clamp_unit(v), &self.half_pi);
        Vec3::new(x, y, z)
    }

    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() || p.norm_squared() == T::zero() {
            return T::zero();
        }
        let (w, _) = one_minus_z(p);
        (-(self.kappa.clone() * &w)).exp() * &self.norm
    }

    fn measure(&self) -> T {
        self.measure.clone()
    }

    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &on_shape_tolerance::<T>())?;
        Ok(self.inverse_uv(p))
    }

    fn outside_by(&self, p: &Vec3<T>) -> T {
        if !p.is_finite() {
            return T::max_value();
        }
        (p.norm() - &T::one()).abs()
    }
}

impl<T: Real> VonMisesFisher<T> {
    /// `[u, v]` of a direction (normalized first; on the sphere, checked
    /// by the caller).
    fn inverse_uv(&self, p: &Vec3<T>) -> [T; 2] {
        let (w, rho2) = one_minus_z(p);
        let two = T::from_i64(2);
        let u = if w <= T::one() {
            // u = (1 − e^(−κw))/(1 − e^(−2κ)).
            let u = w.clone() * &one_minus_exp_ratio(&(self.kappa.clone() * &w))
                / &(self.r1.clone() * &two);
            if u > T::from_ratio(1, 2) {
                // Where ψ is steep in u (concentrated lobes, u → 1), round u
                // once from 1 − u = e^(−κw)(1 − e^(−κ(2 − w)))/(1 − e^(−2κ)).
                let w_back = two.clone() - &w;
                let tail = (-(self.kappa.clone() * &w)).exp()
                    * &(-(-(self.kappa.clone() * &w_back)).exp_m1())
                    / &(-self.e.clone());
                T::one() - &tail
            } else {
                u
            }
        } else {
            // 1 + z = ρ²/(1 − z): accurate near the antipode.
            let w_back = rho2 / &w;
            let kw = self.kappa.clone() * &w_back;
            // 1 − u = (e^(κw') − 1)/(e^(2κ) − 1).
            let tail = if self.em.is_finite() {
                w_back * &expm1_ratio(&kw) / &(self.r2.clone() * &two)
            } else {
                (kw.clone() - &self.ln_em).exp() * &(-(-kw).exp_m1())
            };
            T::one() - &tail
        };
        [clamp_unit(&u), turns_of(&p.y, &p.x, &self.inv_two_pi)]
    }
}

impl<T: Real> WarpFamily<T> for VonMisesFisher<T> {
    type At<S: Real> = VonMisesFisher<S>;
    fn at<S: Real>(&self) -> Result<VonMisesFisher<S>, WarpError> {
        VonMisesFisher::new(convert(&self.kappa))
    }
    fn name(&self) -> String {
        "von-mises-fisher".to_string()
    }
}

crate::warp::distribution_for_floats!(VonMisesFisher, Vec3);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::extremes::EXTREMES;
    use crate::shapes::test_support::{AxisBins, chi2_passes, roundtrip_passes};

    /// κ from 10⁻⁸ to 10⁶, and 0.
    pub(crate) const KAPPAS: [f64; 9] = [0.0, 1e-8, 1e-4, 0.1, 1.0, 10.0, 400.0, 1e4, 1e6];

    #[test]
    fn vmf_constructor_errors() {
        assert!(matches!(
            VonMisesFisher::new(f64::INFINITY),
            Err(WarpError::NonFinite { .. })
        ));
        assert!(matches!(
            VonMisesFisher::new(-1e-300f64),
            Err(WarpError::InvalidParameter { .. })
        ));
    }

    #[test]
    fn vmf_finite_at_edges_and_pdf_matches_formula() {
        for k in KAPPAS {
            let w = VonMisesFisher::new(k).unwrap();
            let w32 = VonMisesFisher::new(k as f32).unwrap();
            for &u in &EXTREMES {
                for &v in &EXTREMES {
                    let p = w.map(&u, &v);
                    assert!(
                        p.is_finite() && w.outside_by(&p) <= 4.0 * f64::EPSILON,
                        "{k} {u} {v} {p:?}"
                    );
                    let q = w32.map(&(u as f32), &(v as f32));
                    assert!(
                        q.is_finite() && w32.outside_by(&q) <= 4.0 * f32::EPSILON,
                        "{k} {u} {v} {q:?}"
                    );
                    let d = w.pdf(&p);
                    assert!(d.is_finite() && d >= 0.0);
                }
            }
            assert_eq!(w.map(&0.0, &0.0), Vec3::new(0.0, 0.0, 1.0));
            assert_eq!(w.map(&1.0, &0.0).z, -1.0);
            // pdf at the pole: κ/(2π(1 − e^(−2κ))).
            let pole = w.pdf(&Vec3::new(0.0, 0.0, 1.0));
            let want = if k == 0.0 {
                1.0 / (4.0 * std::f64::consts::PI)
            } else {
                k / (2.0 * std::f64::consts::PI * -(-2.0 * k).exp_m1())
            };
            assert!((pole / want - 1.0).abs() < 1e-14, "{k}: {pole} {want}");
        }
    }

    #[test]
    fn vmf_roundtrip_and_chi2() {
        for k in KAPPAS {
            let w = VonMisesFisher::new(k).unwrap();
            // Near the antipode ψ is steep (sin θ ∝ √(1 − u)): one ulp of the
            // recovered u moves the image by up to ~20 units there.
            roundtrip_passes::<f64, _>(&format!("von-mises-fisher {k}"), &w, 32.0);
            roundtrip_passes::<f32, _>(&format!("von-mises-fisher {k}"), &w, 32.0);
            let axis = Vec3::new(0.0, 0.0, 1.0);
            let pdf_w = |x: f64| w.pdf(&Vec3::new((x * (2.0 - x)).max(0.0).sqrt(), 0.0, 1.0 - x));
            let edges = AxisBins::quantile_edges(pdf_w, 10, 2.0);
            let bins = AxisBins::new(
                [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), axis],
                edges,
                2.0 * std::f64::consts::PI,
                12,
                |x| w.pdf(&Vec3::new((x * (2.0 - x)).max(0.0).sqrt(), 0.0, 1.0 - x)),
            );
            chi2_passes(&format!("von-mises-fisher {k}"), &w, &bins, 200_000);
        }
    }

    #[cfg(feature = "mpfr")]
    mod mpfr {
        use super::*;
        use crate::shapes::test_support::harness_passes;

        /// Within 16·max(u_T, κ_map) of the 256-bit map (κ_map: the map's
        /// sensitivity to one-ulp changes of κ, u, v) for κ from 10⁻⁸ to
        /// 10⁶, in f32 and f64, on the extremes grid and random points.
        #[test]
        fn vmf_within_kappa_bound_at_every_concentration() {
            use crate::harness::extremes::{extremes_grid, random_points};
            use crate::harness::sensitivity::check_precision_conditioned;
            use crate::real::Mpfr256;
            let mut pts = extremes_grid();
            pts.extend(random_points(200, 17));
            for k in KAPPAS {
                let w = VonMisesFisher::new(k).unwrap();
                let build = |p: &[Mpfr256]| VonMisesFisher::new(p[0].clone());
                let r32 =
                    check_precision_conditioned::<f32, _, _, _>(&w, build, &[k], &pts).unwrap();
                let r64 =
                    check_precision_conditioned::<f64, _, _, _>(&w, build, &[k], &pts).unwrap();
                for r in [&r32, &r64] {
                    println!(
                        "conditioned von-mises-fisher {k} {}: max error/bound {:.3} (error {:.2e}, κ_map {:.2e} at {:?}), max κ_map {:.2e}, non-finite {}",
                        r.scalar,
                        r.max_ratio,
                        r.worst_error,
                        r.worst_kappa,
                        r.worst,
                        r.max_kappa,
                        r.non_finite
                    );
                    assert!(r.passes(), "κ = {k}: {r:?}");
                }
            }
        }

        #[test]
        fn vmf_harness_at_extremes() {
            for k in KAPPAS {
                harness_passes(
                    &format!("von-mises-fisher {k}"),
                    &VonMisesFisher::new(k).unwrap(),
                    16.0,
                );
            }
        }
    }
}
