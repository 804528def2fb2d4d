//! Steps 2–4 executed: a warp from its [`WarpDefinition`] (φ and w) alone.
//!
//! At construction ([`DerivedRecipe::new`]):
//! 1. **The t-panels.** σw(s, ·) is sampled at probe values of s and the
//!    t-axis is split until every probe is resolved by Chebyshev interpolants
//!    (the union of the probes' partitions, [`ConditionalGrid`]).
//! 2. **The marginal density** f(s) = ∫₀¹ σw(s, t) dt (Clenshaw–Curtis on
//!    the t-panels, each panel's resolution re-checked at every s used; a
//!    failure adds that s to the probes and restarts) is interpolated on
//!    adaptive s-panels ([`adaptive_partition`]) until resolved to the
//!    type's precision and, where its values matter, relatively accurate.
//! 3. **The measure** m = ∫₀¹ f and the cumulative masses of the panels from
//!    both ends.
//!
//! Per sample ([`DerivedWarp`]): s = F⁻¹(u) by safeguarded Newton on the
//! panel's polynomial (from the far end for u > 1/2); σw(s, ·) at the
//! t-panels' nodes gives Z(s) and, on the panel where G_s crosses v, the
//! interpolant whose integral is inverted by Newton in the same way.
//!
//! See `docs/recipe.md` (what is computed, what it costs) and
//! `docs/recipe-quadrature.md` (error control).

mod conditional;
mod partition;
mod piecewise;
mod power;

use conditional::ConditionalGrid;
use partition::{Settings, adaptive_partition};
pub(crate) use piecewise::PiecewiseDensity;

use super::chebyshev::{ChebyshevLevel, ChebyshevLevels};
use super::invert::{Cdf1, Inverter, Newton};
use super::{AreaDensity, MarginalConditional, Parametrization, Recipe, WarpDefinition};
use crate::error::WarpError;
use crate::real::{Embed, Real};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// What the construction of a derived warp computed.
#[derive(Clone, Debug, PartialEq)]
pub struct QuadratureReport {
    /// s-panels of the marginal density.
    pub s_panels: usize,
    /// Largest node count of an s-panel.
    pub s_max_nodes: usize,
    /// t-panels of the conditional (shared by every s).
    pub t_panels: usize,
    /// Largest node count of a t-panel.
    pub t_max_nodes: usize,
    /// Evaluations of σw spent.
    pub evaluations: usize,
    /// Rounds of the t-panel construction (1 when the first probes sufficed).
    pub rounds: usize,
    /// The measure m from the quadrature (as `f64`).
    pub measure: f64,
    /// The accuracy of the marginal's interpolants: their largest trailing
    /// Chebyshev coefficient relative to the panel's largest value, over the
    /// panels that matter (≤ 32 units of roundoff when σw is evaluated to
    /// the rounding level; larger, up to 2^(−p/2), at a noise plateau of an
    /// ill-conditioned weight).
    pub s_tail: f64,
    /// The same for the t-panels, over the probes.
    pub t_tail: f64,
}

/// Steps 1–3 of a warp from its definition: φ and w from the user, σ from
/// dual numbers, the marginal and conditional CDFs by quadrature.
///
/// It implements [`Recipe`], so it composes with any inverter in a
/// [`RecipeWarp`](super::RecipeWarp); [`DerivedWarp`] is the faster
/// composition (the conditional's quadrature shared between the CDF and
/// its density within one sample).
#[derive(Clone, Debug)]
pub struct DerivedRecipe<T, P> {
    def: P,
    levels: ChebyshevLevels<T>,
    marginal: PiecewiseDensity<T>,
    grid: ConditionalGrid<T>,
    measure: T,
    closed: ClosedForms,
    report: QuadratureReport,
}

/// Which closed forms the definition supplies.
#[derive(Clone, Copy, Debug, Default)]
struct ClosedForms {
    marginal: bool,
    marginal_inverse: bool,
    conditional: bool,
    conditional_inverse: bool,
}

/// How many times the t-panels may be rebuilt with more probes.
const MAX_ROUNDS: usize = 4;

impl<T: Real, P: WarpDefinition<T>> DerivedRecipe<T, P> {
    /// Runs steps 2–3 for `def`.
    ///
    /// # Errors
    /// [`WarpError::NotConverged`] if σw is not resolved to the type's
    /// precision by the finest panels (a discontinuity or a singularity of
    /// the density inside [0, 1]²) or the measure is not positive and finite;
    /// [`WarpError::Inconsistent`] if a closed-form measure or marginal
    /// disagrees with the quadrature by more than 2¹⁰ units of roundoff.
    pub fn new(def: P) -> Result<Self, WarpError> {
        let levels = ChebyshevLevels::<T>::new();
        let settings = Settings::<T>::for_type();
        let marginal_settings = Settings {
            power: def.left_power().filter(|e| *e > T::zero()),
            ..settings.clone()
        };
        let mut probes: Vec<T> = ChebyshevLevel::<T>::new(17)
            .points
            .iter()
            .map(|x| (x.clone() + &T::one()) / &T::from_i64(2))
            .collect();
        probes.push(T::exp2i(-10));
        probes.push(T::one() - &T::exp2i(-10));
        let mut evaluations = 0;
        let mut rounds = 0;
        let (grid, partition) = loop {
            rounds += 1;
            let (mut grid, probes_resolved, evals) =
                ConditionalGrid::build(&def, &probes, &levels, &settings);
            evaluations += evals;
            if !probes_resolved {
                return Err(WarpError::NotConverged {
                    what: "the conditional density sigma*w(s, .) at a probe s",
                });
            }
            let mut failures: Vec<T> = Vec::new();
            let mut upgrades: Vec<(T, usize, usize, T)> = Vec::new();
            let mut f = |s: &T| {
                let z = grid.normalizer_checked(&def, s, &levels);
                if !z.resolved {
                    failures.push(s.clone());
                }
                for (j, n, t) in z.upgrades {
                    upgrades.push((s.clone(), j, n, t));
                }
                z.value
            };
            // A power panel at s = 0 if the definition declares the
            // exponent; the plain partition if it cannot be resolved.
            let mut partition = adaptive_partition(&mut f, &levels, &marginal_settings);
            if !partition.resolved && marginal_settings.power.is_some() {
                evaluations += partition.evaluations * grid.nodes_total();
                partition = adaptive_partition(&mut f, &levels, &settings);
            }
            evaluations += partition.evaluations * grid.nodes_total();
            // The conditional matters only where an s = F⁻¹(y) can land:
            // not inside the unreachable right tail of the marginal.
            failures.retain(|s| *s <= partition.tail_start);
            if failures.is_empty() {
                for (s, j, n, t) in &upgrades {
                    if *s <= partition.tail_start {
                        grid.upgrade(*j, *n, t, &levels);
                    }
                }
                break (grid, partition);
            }
            if rounds >= MAX_ROUNDS {
                return Err(WarpError::NotConverged {
                    what: "the conditional density sigma*w(s, .) between the probes",
                });
            }
            failures.truncate(8);
            probes.extend(failures);
        };
        if !partition.resolved {
            return Err(WarpError::NotConverged {
                what: "the marginal density (integral of sigma*w over t)",
            });
        }
        let marginal = PiecewiseDensity::from_fits(&partition.fits, &levels);
        let quad = marginal.total().clone();
        if !(quad > T::zero()) || !quad.is_finite() {
            return Err(WarpError::NotConverged {
                what: "the measure (not positive and finite)",
            });
        }
        let agree = |a: &T, b: &T, scale: &T| -> bool {
            (a.clone() - b).abs() <= T::exp2i(10) * &T::unit_roundoff() * scale
        };
        let measure = match def.measure_closed() {
            Some(m) => {
                if !agree(&m, &quad, &quad) {
                    return Err(WarpError::Inconsistent {
                        what: "the closed-form measure and the quadrature",
                    });
                }
                m
            }
            None => quad.clone(),
        };
        let half = T::from_ratio(1, 2);
        let closed = ClosedForms {
            marginal: def.marginal_closed(&half).is_some(),
            marginal_inverse: def.marginal_inverse_closed(&half).is_some(),
            conditional: def.conditional_closed(&half, &half).is_some(),
            conditional_inverse: def.conditional_inverse_closed(&half, &half).is_some(),
        };
        if closed.marginal {
            for k in 1..8 {
                let s = T::from_ratio(k, 8);
                let [f, _] = def.marginal_closed(&s).expect("closed marginal");
                if !agree(&f, &marginal.cdf(&s), &T::one()) {
                    return Err(WarpError::Inconsistent {
                        what: "the closed-form marginal CDF and the quadrature",
                    });
                }
            }
        }
        let report = QuadratureReport {
            s_panels: marginal.panels(),
            s_max_nodes: partition.fits.iter().map(|f| f.n).max().unwrap_or(0),
            t_panels: grid.panels(),
            t_max_nodes: grid.max_nodes(),
            evaluations,
            rounds,
            measure: quad.to_f64(),
            s_tail: partition.worst_tail.to_f64(),
            t_tail: grid.worst_tail().to_f64(),
        };
        Ok(DerivedRecipe {
            def,
            levels,
            marginal,
            grid,
            measure,
            closed,
            report,
        })
    }

    /// The definition.
    pub fn definition(&self) -> &P {
        &self.def
    }

    /// What the construction computed.
    pub fn report(&self) -> &QuadratureReport {
        &self.report
    }

    /// The s-panel ends of the marginal.
    pub fn s_panel_ends(&self) -> &[T] {
        self.marginal.ends()
    }

    /// F⁻¹(u): the closed form if the definition has one, else Newton on the
    /// closed F, else the quadrature's piecewise inversion.
    pub fn marginal_inverse_of(&self, u: &T) -> T {
        if self.closed.marginal_inverse
            && let Some(s) = self.def.marginal_inverse_closed(u)
        {
            return s;
        }
        if self.closed.marginal {
            return Newton::default().invert(&ClosedMarginal(&self.def), u).x;
        }
        self.marginal.inverse(u)
    }

    /// G_s⁻¹(v), likewise.
    pub fn conditional_inverse_of(&self, s: &T, v: &T) -> T {
        if self.closed.conditional_inverse
            && let Some(t) = self.def.conditional_inverse_closed(s, v)
        {
            return t;
        }
        if self.closed.conditional {
            let cdf = ClosedConditional { def: &self.def, s };
            return Newton::default().invert(&cdf, v).x;
        }
        self.grid.inverse(&self.def, s, v, &self.levels)
    }

    /// G_s⁻¹ at every v of `vs`, sharing one quadrature of σw(s, ·).
    pub fn conditional_inverse_many(&self, s: &T, vs: &[T]) -> Vec<T> {
        if self.closed.conditional_inverse || self.closed.conditional {
            return vs
                .iter()
                .map(|v| self.conditional_inverse_of(s, v))
                .collect();
        }
        self.grid.inverse_many(&self.def, s, vs, &self.levels)
    }

    /// F(s).
    pub fn marginal_cdf_of(&self, s: &T) -> T {
        if self.closed.marginal
            && let Some([f, _]) = self.def.marginal_closed(s)
        {
            return f;
        }
        self.marginal.cdf(s)
    }

    /// G_s(t).
    pub fn conditional_cdf_of(&self, s: &T, t: &T) -> T {
        if self.closed.conditional
            && let Some([g, _]) = self.def.conditional_closed(s, t)
        {
            return g;
        }
        self.grid.cdf(&self.def, s, t, &self.levels)
    }

    /// Z(s) = ∫₀¹ σw(s, t) dt by the t-quadrature.
    pub fn normalizer(&self, s: &T) -> T {
        self.grid.normalizer(&self.def, s, &self.levels)
    }
}

/// The user's closed marginal as a [`Cdf1`].
struct ClosedMarginal<'a, P>(&'a P);

impl<T: Real, P: WarpDefinition<T>> Cdf1<T> for ClosedMarginal<'_, P> {
    fn cdf(&self, x: &T) -> T {
        self.0.marginal_closed(x).expect("closed marginal")[0].clone()
    }
    fn pdf(&self, x: &T) -> T {
        self.0.marginal_closed(x).expect("closed marginal")[1].clone()
    }
}

/// The user's closed conditional at fixed s as a [`Cdf1`].
struct ClosedConditional<'a, P, T> {
    def: &'a P,
    s: &'a T,
}

impl<T: Real, P: WarpDefinition<T>> Cdf1<T> for ClosedConditional<'_, P, T> {
    fn cdf(&self, x: &T) -> T {
        self.def
            .conditional_closed(self.s, x)
            .expect("closed conditional")[0]
            .clone()
    }
    fn pdf(&self, x: &T) -> T {
        self.def
            .conditional_closed(self.s, x)
            .expect("closed conditional")[1]
            .clone()
    }
}

impl<T: Real, P: WarpDefinition<T>> Parametrization<T> for DerivedRecipe<T, P> {
    fn phi<S: Embed<T>>(&self, s: &S, t: &S) -> Vec3<S> {
        self.def.phi(s, t)
    }
    fn partials(&self, s: &T, t: &T) -> [Vec3<T>; 3] {
        self.def.partials(s, t)
    }
    fn chart(&self, p: &Vec3<T>) -> Option<(T, T)> {
        self.def.chart(p)
    }
}

impl<T: Real, P: WarpDefinition<T>> AreaDensity<T> for DerivedRecipe<T, P> {
    fn weight(&self, p: &Vec3<T>) -> T {
        self.def.weight(p)
    }
    fn sigma(&self, s: &T, t: &T) -> T {
        self.def.sigma(s, t)
    }
}

impl<T: Real, P: WarpDefinition<T>> MarginalConditional<T> for DerivedRecipe<T, P> {
    fn measure(&self) -> T {
        self.measure.clone()
    }
    fn marginal_cdf(&self, s: &T) -> T {
        self.marginal_cdf_of(s)
    }
    fn marginal_pdf(&self, s: &T) -> T {
        if self.closed.marginal
            && let Some([_, d]) = self.def.marginal_closed(s)
        {
            return d;
        }
        self.marginal.pdf(s)
    }
    fn conditional_cdf(&self, s: &T, t: &T) -> T {
        self.conditional_cdf_of(s, t)
    }
    fn conditional_pdf(&self, s: &T, t: &T) -> T {
        if self.closed.conditional
            && let Some([_, d]) = self.def.conditional_closed(s, t)
        {
            return d;
        }
        let z = self.normalizer(s);
        if z > T::zero() {
            self.def.sigma(s, t) / &z
        } else {
            T::one()
        }
    }
    fn marginal_inverse(&self, u: &T) -> Option<T> {
        self.closed
            .marginal_inverse
            .then(|| self.def.marginal_inverse_closed(u))
            .flatten()
    }
    fn conditional_inverse(&self, s: &T, v: &T) -> Option<T> {
        self.closed
            .conditional_inverse
            .then(|| self.def.conditional_inverse_closed(s, v))
            .flatten()
    }
}

impl<T: Real, P: WarpDefinition<T>> Recipe<T> for DerivedRecipe<T, P> {
    type At<S: Real> = DerivedRecipe<S, P::At<S>>;
    fn recast<S: Real>(&self) -> Result<Self::At<S>, WarpError> {
        DerivedRecipe::new(self.def.recast::<S>()?)
    }
    fn name(&self) -> String {
        format!("derived:{}", self.def.name())
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.def.outside_by(p)
    }
    fn extent(&self) -> T {
        self.def.extent()
    }
}

/// The warp derived from a [`WarpDefinition`]: ψ(u, v) = φ(F⁻¹(u),
/// G_s⁻¹(v)) with F and G_s computed by quadrature ([`DerivedRecipe`]) and
/// inverted by safeguarded Newton, at any precision.
///
/// # Density
/// pdf(p) = w(p)/m, m the measure (closed form if the definition has one,
/// else the quadrature's).
///
/// # Example
/// ```
/// use areawarp::recipe::DerivedWarp;
/// use areawarp::recipe::definitions::Hemisphere;
/// use areawarp::Warp;
///
/// let w = DerivedWarp::new(Hemisphere::<f64>::new())?;
/// assert!((w.measure() - 2.0 * std::f64::consts::PI).abs() < 1e-14);
/// let p = w.map(&0.25, &0.5);
/// assert!((p.z - 0.75).abs() < 1e-15); // z = 1 − u, as the closed form
/// # Ok::<(), areawarp::WarpError>(())
/// ```
#[derive(Clone, Debug)]
pub struct DerivedWarp<T, P> {
    recipe: DerivedRecipe<T, P>,
}

impl<T: Real, P: WarpDefinition<T>> DerivedWarp<T, P> {
    /// Derives the warp of `def` (see [`DerivedRecipe::new`]).
    ///
    /// # Errors
    /// As [`DerivedRecipe::new`].
    pub fn new(def: P) -> Result<Self, WarpError> {
        Ok(DerivedWarp {
            recipe: DerivedRecipe::new(def)?,
        })
    }

    /// The recipe (steps 1–3) behind the warp.
    pub fn recipe(&self) -> &DerivedRecipe<T, P> {
        &self.recipe
    }

    /// `(s, t) = (F⁻¹(u), G_s⁻¹(v))`.
    pub fn warp_coordinates(&self, u: &T, v: &T) -> (T, T) {
        let s = self.recipe.marginal_inverse_of(u);
        let t = self.recipe.conditional_inverse_of(&s, v);
        (s, t)
    }

    /// `(F(s), G_s(t))` of the chart coordinates of `p`, if `p` is finite,
    /// on the shape and has a chart.
    pub fn inverse_pair(&self, p: &Vec3<T>) -> Option<[T; 2]> {
        if !p.is_finite() || self.recipe.def.outside_by(p) > on_shape_tolerance::<T>() {
            return None;
        }
        let (s, t) = self.recipe.def.chart(p)?;
        let (s, t) = (
            s.clamp(&T::zero(), &T::one()),
            t.clamp(&T::zero(), &T::one()),
        );
        Some([
            self.recipe.marginal_cdf_of(&s),
            self.recipe.conditional_cdf_of(&s, &t),
        ])
    }
}

impl<T: Real, P: WarpDefinition<T>> Warp<T> for DerivedWarp<T, P> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let (s, t) = self.warp_coordinates(u, v);
        self.recipe.def.phi(&s, &t)
    }
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        self.recipe.def.weight(p) / &self.recipe.measure
    }
    fn measure(&self) -> T {
        self.recipe.measure.clone()
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &self.on_shape_tolerance())?;
        self.inverse_pair(p)
            .ok_or_else(|| InverseError::refuse(self, p))
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.recipe.def.outside_by(p)
    }
    fn extent(&self) -> T {
        self.recipe.def.extent()
    }
}

impl<T: Real, P: WarpDefinition<T>> WarpFamily<T> for DerivedWarp<T, P> {
    type At<S: Real> = DerivedWarp<S, P::At<S>>;
    fn at<S: Real>(&self) -> Result<Self::At<S>, WarpError> {
        DerivedWarp::new(self.recipe.def.recast::<S>()?)
    }
    fn name(&self) -> String {
        format!("derived:{}", self.recipe.def.name())
    }
}
