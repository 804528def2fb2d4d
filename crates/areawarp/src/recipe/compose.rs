//! Step 5: composing the recipe into an area-preserving map.

use super::{AreaDensity, Conditional, Inverter, Marginal, MarginalConditional};
use crate::error::WarpError;
use crate::real::Real;
use crate::vector::Vec3;
use crate::warp::InverseError;
use crate::warp::{Warp, WarpFamily};

/// Steps 1–3 of a warp, rebuildable at any precision.
///
/// Implement [`Parametrization`](super::Parametrization),
/// [`AreaDensity`] and [`MarginalConditional`] for a struct generic over the
/// scalar, then this trait to convert its parameters, and
/// [`RecipeWarp::new`] composes the map.
pub trait Recipe<T: Real>: AreaDensity<T> + MarginalConditional<T> + Clone {
    /// The same recipe over scalar `S`.
    type At<S: Real>: Recipe<S>;
    /// Rebuilds the recipe over `S` (convert parameters with [`crate::real::convert`]).
    fn recast<S: Real>(&self) -> Result<Self::At<S>, WarpError>;
    /// A short name for reports.
    fn name(&self) -> String;
    /// How far `p` lies outside M. The default measures the distance from `p`
    /// to φ(chart(p)) with the chart clamped to [0, 1]²; shapes without a
    /// chart report 0.
    fn outside_by(&self, p: &Vec3<T>) -> T {
        match self.chart(p) {
            Some((s, t)) => {
                let (s, t) = (
                    s.clamp(&T::zero(), &T::one()),
                    t.clamp(&T::zero(), &T::one()),
                );
                self.phi(&s, &t).sub(p).norm()
            }
            None => T::zero(),
        }
    }
    /// A characteristic length of M (see [`Warp::extent`]).
    fn extent(&self) -> T {
        T::one()
    }
}

/// Step 5: ψ(u, v) = φ(F⁻¹(u), G_s⁻¹(v)) from a [`Recipe`] and two inverters.
///
/// This is the framework's composed map: the specification an optimized
/// direct implementation is tested against.
///
/// # Example
/// See `examples/define_your_own_warp.rs`.
#[derive(Clone, Debug)]
pub struct RecipeWarp<R, IM, IC> {
    /// Steps 1–3.
    pub recipe: R,
    /// Inverter for the marginal F.
    pub marginal: IM,
    /// Inverter for the conditional G_s.
    pub conditional: IC,
}

impl<R, IM, IC> RecipeWarp<R, IM, IC> {
    /// Composes a recipe with its inverters.
    pub fn new(recipe: R, marginal: IM, conditional: IC) -> Self {
        RecipeWarp {
            recipe,
            marginal,
            conditional,
        }
    }

    /// `(s, t) = (F⁻¹(u), G_s⁻¹(v))`: the warping function of step 4.
    pub fn warp_coordinates<T: Real>(&self, u: &T, v: &T) -> (T, T)
    where
        R: MarginalConditional<T>,
        IM: Inverter,
        IC: Inverter,
    {
        let s = self.marginal.invert(&Marginal(&self.recipe), u).x;
        let cond = Conditional {
            dist: &self.recipe,
            s,
        };
        let t = self.conditional.invert(&cond, v).x;
        (cond.s, t)
    }
}

impl<T: Real, R: Recipe<T>, IM: Inverter, IC: Inverter> Warp<T> for RecipeWarp<R, IM, IC> {
    type Point = Vec3<T>;
    fn map(&self, u: &T, v: &T) -> Vec3<T> {
        let (s, t) = self.warp_coordinates(u, v);
        self.recipe.phi(&s, &t)
    }
    fn pdf_unchecked(&self, p: &Vec3<T>) -> T {
        self.recipe.weight(p) / &self.recipe.measure()
    }
    fn measure(&self) -> T {
        self.recipe.measure()
    }
    fn inverse(&self, p: &Vec3<T>) -> Result<[T; 2], InverseError> {
        let (s, t) = self
            .recipe
            .chart(p)
            .ok_or_else(|| InverseError::refuse(self, p))?;
        Ok([
            self.recipe.marginal_cdf(&s),
            self.recipe.conditional_cdf(&s, &t),
        ])
    }
    fn outside_by(&self, p: &Vec3<T>) -> T {
        self.recipe.outside_by(p)
    }
    fn extent(&self) -> T {
        self.recipe.extent()
    }
}

impl<T: Real, R: Recipe<T>, IM: Inverter + Clone, IC: Inverter + Clone> WarpFamily<T>
    for RecipeWarp<R, IM, IC>
{
    type At<S: Real> = RecipeWarp<R::At<S>, IM, IC>;
    fn at<S: Real>(&self) -> Result<Self::At<S>, WarpError> {
        Ok(RecipeWarp::new(
            self.recipe.recast()?,
            self.marginal.clone(),
            self.conditional.clone(),
        ))
    }
    fn name(&self) -> String {
        format!("recipe:{}", self.recipe.name())
    }
}
