//! Fast inverses with a measured error: F⁻¹ and G⁻¹ of a
//! [`DerivedWarp`] replaced by piecewise polynomials
//! built at construction for a requested tolerance.
//!
//! * F⁻¹(u): polynomials of degree d (default 5) in u, interpolating at the
//!   Chebyshev points of the second kind (ends included, so the table is
//!   continuous and exact at u = 0 and 1) on panels bisected until the error
//!   at the points between the nodes is below tolerance/4. Near an end where
//!   F⁻¹ behaves like √u (a pole of φ) this refines geometrically; where it
//!   behaves like u^(1/m) with m > 17/8 (σw ~ s^(m−1), a Phong lobe seen
//!   from the horizon), the panels of [0, 1/2] are fitted and bisected in
//!   w = u^(1/m) instead (see `left_exponent` and
//!   docs/recipe-quadrature.md §5). A single
//!   panel of degree 3 is the Vandermonde cubic of
//!   [`VandermondeCubic`](super::VandermondeCubic).
//! * G⁻¹(s, v): G_s depends on s, so the table is two-dimensional:
//!   tensor-product polynomials of degree d in s and in v on cells,
//!   s-panels bisected when the error between the s-nodes exceeds
//!   tolerance/4, and within each s-panel its own v-panels bisected when the
//!   error between the v-nodes does. A per-s-panel v-partition follows
//!   conditionals whose shape changes with s (a tilted lobe) without
//!   refining every s-panel alike; a conditional uniform in t costs one cell.
//!
//! The tolerance is on s = F⁻¹(u) and on t = G_s⁻¹(v) (absolute, in the
//! parameters of φ); the error *claimed* is what the construction saw at its
//! check points, the error *certified* is measured against the derived warp
//! at 256 bits (feature `mpfr`) on a dense set of points by
//! [`measure_error`]. Closed-form inverses of the definition, if any, are used instead
//! of a table.

mod poly;
mod table1;
mod table2;

use table1::Table1;
use table2::Table2;

use super::invert::{Bisection, Cdf1, Inverter};
use super::{DerivedRecipe, DerivedWarp, WarpDefinition};
use crate::error::WarpError;
use crate::real::{Real, convert};
use crate::vector::Vec3;
use crate::warp::{InverseError, Warp, WarpFamily, on_shape_tolerance};

/// What the construction of a table computed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TabulationReport {
    /// The requested tolerance.
    pub tolerance: f64,
    /// The polynomial degree.
    pub degree: usize,
    /// Panels of F⁻¹ (0 with a closed form).
    pub marginal_panels: usize,
    /// Cells of G⁻¹ (0 with a closed form).
    pub conditional_cells: usize,
    /// Exact inversions spent on fitting and checking.
    pub evaluations: usize,
    /// The largest error the construction saw at its check points (at most
    /// tolerance/4 by construction; not a certificate, see [`measure_error`]).
    pub estimated_error: f64,
}

/// The default polynomial degree of the tables.
pub const DEFAULT_DEGREE: usize = 5;

/// A warp whose inverse CDFs are tables: ψ(u, v) = φ(F̃⁻¹(u), G̃⁻¹(F̃⁻¹(u), v)).
///
/// # Density
/// pdf(p) = w(p)/m, the target density; the tabulated map's own density
/// differs from it by the derivative error of the tables (of the order of
/// the tolerance times the degree squared over the panel width).
///
/// # Example
/// ```
/// use areawarp::recipe::definitions::Cap;
/// use areawarp::recipe::{DerivedWarp, TabulatedWarp};
/// use areawarp::Warp;
///
/// let derived = DerivedWarp::new(Cap::<f64>::new(0.5)?)?;
/// let fast = TabulatedWarp::new(&derived, 1e-9)?;
/// let (p, q) = (fast.map(&0.3, &0.7), derived.map(&0.3, &0.7));
/// assert!(p.sub(&q).norm() < 1e-8);
/// # Ok::<(), areawarp::WarpError>(())
/// ```
#[derive(Clone, Debug)]
pub struct TabulatedWarp<T, P> {
    def: P,
    measure: T,
    marginal: Option<Table1<T>>,
    conditional: Option<Table2<T>>,
    report: TabulationReport,
}

impl<T: Real, P: WarpDefinition<T>> TabulatedWarp<T, P> {
    /// Tables of degree [`DEFAULT_DEGREE`] for `tolerance`.
    ///
    /// # Errors
    /// As [`TabulatedWarp::with_degree`].
    pub fn new(derived: &DerivedWarp<T, P>, tolerance: f64) -> Result<Self, WarpError> {
        Self::with_degree(derived, tolerance, DEFAULT_DEGREE)
    }

    /// Tables of degree `degree` (1 … 8) for `tolerance` (absolute, on s and
    /// t), built from the derived warp's exact inversions.
    ///
    /// # Errors
    /// [`WarpError::InvalidParameter`] for a tolerance that is not finite,
    /// not positive or below 64 units of roundoff of `T`, or a degree
    /// outside 1 … 8; [`WarpError::NotConverged`] if a panel holding no
    /// more floats still misses the tolerance.
    pub fn with_degree(
        derived: &DerivedWarp<T, P>,
        tolerance: f64,
        degree: usize,
    ) -> Result<Self, WarpError> {
        let tol = T::from_f64(tolerance);
        if !tolerance.is_finite() || !(tol >= T::from_i64(64) * &T::unit_roundoff()) {
            return Err(WarpError::InvalidParameter {
                name: "tolerance",
                expected: "finite, at least 64 units of roundoff of the scalar type",
            });
        }
        if !(1..=8).contains(&degree) {
            return Err(WarpError::InvalidParameter {
                name: "degree",
                expected: "1 to 8",
            });
        }
        let recipe = derived.recipe();
        let def = recipe.definition().clone();
        let half = T::from_ratio(1, 2);
        let min_width = T::exp2i(-(2 * T::precision() as i32 + 64));
        let mut report = TabulationReport {
            tolerance,
            degree,
            ..TabulationReport::default()
        };
        let marginal = if def.marginal_inverse_closed(&half).is_some() {
            None
        } else {
            let power = left_exponent(recipe);
            let mut f = |u: &T| recipe.marginal_inverse_of(u);
            let (table, stats) = Table1::fit(&mut f, degree, &tol, &min_width, power.as_ref())?;
            report.marginal_panels = stats.panels;
            report.evaluations += stats.evaluations;
            report.estimated_error = stats.estimated_error;
            Some(table)
        };
        let conditional = if def.conditional_inverse_closed(&half, &half).is_some() {
            None
        } else {
            let mut g = |s: &T, vs: &[T]| recipe.conditional_inverse_many(s, vs);
            let (table, stats) = Table2::fit(&mut g, degree, &tol, &min_width)?;
            report.conditional_cells = stats.panels;
            report.evaluations += stats.evaluations;
            report.estimated_error = report.estimated_error.max(stats.estimated_error);
            Some(table)
        };
        Ok(TabulatedWarp {
            measure: derived.measure(),
            def,
            marginal,
            conditional,
            report,
        })
    }

    /// What the construction computed.
    pub fn report(&self) -> &TabulationReport {
        &self.report
    }

    /// The definition.
    pub fn definition(&self) -> &P {
        &self.def
    }

    /// F̃⁻¹(u).
    pub fn marginal_inverse(&self, u: &T) -> T {
        match &self.marginal {
            Some(t) => t.eval(u),
            None => self
                .def
                .marginal_inverse_closed(u)
                .expect("closed marginal inverse"),
        }
    }

    /// G̃_s⁻¹(v).
    pub fn conditional_inverse(&self, s: &T, v: &T) -> T {
        match &self.conditional {
            Some(t) => t.eval(s, v),
            None => self
                .def
                .conditional_inverse_closed(s, v)
                .expect("closed conditional inverse"),
        }
    }

    /// `(s, t)` of the tabulated map.
    pub fn warp_coordinates(&self, u: &T, v: &T) -> (T, T) {
        let s = self.marginal_inverse(u);
        let t = self.conditional_inverse(&s, v);
        (s, t)
    }

    /// `(u, v)` with warp_coordinates(u, v) = chart(p), if p is finite, on
    /// the shape and has a chart.
    pub fn inverse_pair(&self, p: &Vec3<T>) -> Option<[T; 2]> {
        if !p.is_finite() || self.def.outside_by(p) > on_shape_tolerance::<T>() {
            return None;
        }
        let (s, t) = self.def.chart(p)?;
        let (s, t) = (
            s.clamp(&T::zero(), &T::one()),
            t.clamp(&T::zero(), &T::one()),
        );
        let u = match &self.marginal {
            Some(table) => table.inverse(&s),
            None => match self.def.marginal_closed(&s) {
                Some([f, _]) => f,
                None => Bisection::default().invert(&ClosedInverse(&self.def), &s).x,
            },
        };
        let v = match &self.conditional {
            Some(table) => table.inverse(&s, &t),
            None => match self.def.conditional_closed(&s, &t) {
                Some([g, _]) => g,
                None => t,
            },
        };
        Some([u, v])
    }
}

/// The exponent m of F(s) ~ C·s^m at s = 0 (F⁻¹(u) ~ (u/C)^(1/m)), if F
/// follows a power law there with m > 17/8: then no polynomial in u meets a
/// tolerance near u = 0 on panels of any representable width (Phong of
/// exponent k seen from the horizon: m = k + 1, F⁻¹ ~ u^(1/11) for k = 10),
/// and the panels of [0, 1/2] are fitted, and bisected, in w = u^(1/m)
/// instead, where F⁻¹ is smooth. m = 2 (a pole of φ, F⁻¹ ~ √u) is left to the geometric
/// refinement, which meets every tolerance the type allows.
///
/// Estimated from the density F' ∝ Z(s) = ∫σw dt (the t-quadrature,
/// relatively accurate at any s, unlike F near 0): local exponents
/// m(s) = 1 + log₂(Z(s)/Z(s/2)) at s = 2⁻ʲ, j = 3 … min(p/2, 40) while
/// Z(s/2) stays a normal number, the last two extrapolated (m(s) = m +
/// O(s²) for an analytic Z·s^(1−m)). An error δ in m leaves F⁻¹ ~
/// w^(1+δ) in w, which the fit does not see for the δ ~ s⁴ this leaves. A
/// density that is not a power law at 0 (the last two local exponents
/// differ by more than 1/64 of m) keeps the plain fit.
///
/// A definition that declares its exponent e ([`WarpDefinition::left_power`])
/// gives m = e + 1 exactly.
fn left_exponent<T: Real, P: WarpDefinition<T>>(recipe: &DerivedRecipe<T, P>) -> Option<T> {
    if let Some(e) = recipe.definition().left_power() {
        let m = e + &T::one();
        return (m > T::from_ratio(17, 8)).then_some(m);
    }
    let two = T::from_i64(2);
    let ln2 = two.ln();
    let floor = T::precision_floor();
    let last = (T::precision() as i32 / 2).min(40);
    let mut z = recipe.normalizer(&T::exp2i(-3));
    // The last two local exponents.
    let (mut m1, mut m2): (Option<T>, Option<T>) = (None, None);
    for j in 3..last {
        let z_half = recipe.normalizer(&T::exp2i(-(j + 1)));
        if !(z_half >= floor && z > z_half) {
            break;
        }
        m1 = m2.take();
        m2 = Some(T::one() + &((z.clone() / &z_half).ln() / &ln2));
        z = z_half;
    }
    let (m1, m2) = (m1?, m2?);
    let m = (m2.clone() * &T::from_i64(4) - &m1) / &T::from_i64(3);
    let power_law = (m1 - &m2).abs() * &T::from_i64(64) <= m;
    (power_law && m.is_finite() && m > T::from_ratio(17, 8)).then_some(m)
}

/// A closed marginal inverse u ↦ s as an increasing function, so that
/// bisection can invert it.
struct ClosedInverse<'a, P>(&'a P);

impl<T: Real, P: WarpDefinition<T>> Cdf1<T> for ClosedInverse<'_, P> {
    fn cdf(&self, u: &T) -> T {
        self.0.marginal_inverse_closed(u).expect("closed inverse")
    }
    fn pdf(&self, _u: &T) -> T {
        T::zero()
    }
}

impl<T: Real, P: WarpDefinition<T>> Warp<T> for TabulatedWarp<T, P> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let (s, t) = self.warp_coordinates(u, v);
        self.def.phi(&s, &t)
    }
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        self.def.weight(p) / &self.measure
    }
    fn measure(&self) -> T {
        self.measure.clone()
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        InverseError::check(self, p, &self.on_shape_tolerance())?;
        self.inverse_pair(p)
            .ok_or_else(|| InverseError::refuse(self, p))
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.def.outside_by(p)
    }
    fn extent(&self) -> T {
        self.def.extent()
    }
}

impl<T: Real, P: WarpDefinition<T>> WarpFamily<T> for TabulatedWarp<T, P> {
    type At<S: Real> = TabulatedWarp<S, P::At<S>>;
    /// The same tables over `S` (their numbers converted, not refitted): the
    /// map a renderer evaluating them in `S` gets. Converted to a scalar
    /// coarser than the one they were fitted in, the tables can miss the
    /// tolerance where F⁻¹ is steep (next to a pole at u = 1, panels finer
    /// than the coarser scalar's floats): build them in that scalar instead
    /// (`TabulatedWarp::new` on a `DerivedWarp<f32, _>`).
    fn at<S: Real>(&self) -> Result<Self::At<S>, WarpError> {
        Ok(TabulatedWarp {
            def: self.def.recast::<S>()?,
            measure: convert(&self.measure),
            marginal: self.marginal.as_ref().map(|t| t.convert()),
            conditional: self.conditional.as_ref().map(|t| t.convert()),
            report: self.report,
        })
    }
    fn name(&self) -> String {
        format!("tabulated({:e}):{}", self.report.tolerance, self.def.name())
    }
}

/// The error of a table, measured against the derived warp at 256 bits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeasuredError {
    /// max |F̃⁻¹(u) − F⁻¹(u)|.
    pub marginal: f64,
    /// max |G̃⁻¹(s̃, v) − G⁻¹_s̃(v)| at the s̃ the table produced.
    pub conditional: f64,
    /// max ‖ψ̃(u, v) − ψ(u, v)‖_∞ / extent (the points themselves).
    pub point: f64,
    /// Points measured.
    pub points: usize,
    /// Points where the table produced a non-finite value.
    pub non_finite: usize,
}

impl MeasuredError {
    /// max(marginal, conditional): the error the tolerance bounds.
    pub fn inverse(&self) -> f64 {
        self.marginal.max(self.conditional)
    }
}

/// Measures the table `table` (in its own scalar `T`, inputs rounded to
/// `T`) against `exact`, the same definition derived in a reference scalar
/// `M` (256-bit MPFR for the certificate), on `points`: the errors of F̃⁻¹,
/// of G̃⁻¹ and of the mapped points.
pub fn measure_error<T: Real, M: Real, P: WarpDefinition<T>>(
    table: &TabulatedWarp<T, P>,
    exact: &DerivedWarp<M, P::At<M>>,
    points: &[(f64, f64)],
) -> MeasuredError {
    let mut out = MeasuredError {
        points: points.len(),
        ..MeasuredError::default()
    };
    let extent: M = exact.extent();
    for &(u, v) in points {
        let (ut, vt) = (T::from_f64(u), T::from_f64(v));
        let (s, t) = table.warp_coordinates(&ut, &vt);
        let p = table.def.phi(&s, &t);
        if !(s.is_finite() && t.is_finite() && p.is_finite()) {
            out.non_finite += 1;
            continue;
        }
        let (um, vm): (M, M) = (convert(&ut), convert(&vt));
        let sm: M = convert(&s);
        let tm: M = convert(&t);
        let s_exact = exact.recipe().marginal_inverse_of(&um);
        let t_exact = exact.recipe().conditional_inverse_of(&sm, &vm);
        let q = exact.map(&um, &vm);
        let pm: Vec3<M> = p.convert();
        out.marginal = out.marginal.max((sm - &s_exact).abs().to_f64());
        out.conditional = out.conditional.max((tm - &t_exact).abs().to_f64());
        out.point = out.point.max((pm.sub(&q).max_abs() / &extent).to_f64());
    }
    out
}
