//! `areawarp eval --variant closed|derived|tabulated:TOL`: the maps that
//! also have a recipe definition (φ and a weight, `areawarp::recipe::
//! definitions`) evaluated as their closed form (the default), as the warp
//! derived from the definition by quadrature and Newton
//! ([`DerivedWarp`]), or with tabulated inverses of F and G_s for a
//! tolerance on the parameters s and t of φ ([`TabulatedWarp`]). The line
//! format and the output are those of the closed form.

use super::eval::{apply, expect};
use areawarp::WarpError;
use areawarp::real::Real;
use areawarp::recipe::definitions::{
    Beckmann, Cap, Ggx, Hemisphere, Phong, Sphere, VonMisesFisher,
};
use areawarp::recipe::{DerivedWarp, TabulatedWarp, WarpDefinition};

/// Which version of a map is evaluated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum RecipeVariant {
    /// The closed form (the default).
    #[default]
    Closed,
    /// Derived from the definition by quadrature.
    Derived,
    /// Derived, with the inverses tabulated to this tolerance.
    Tabulated(f64),
}

impl RecipeVariant {
    /// `closed`, `derived` or `tabulated:TOL` (TOL a positive number).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "closed" => Some(RecipeVariant::Closed),
            "derived" => Some(RecipeVariant::Derived),
            _ => {
                let tol: f64 = s.strip_prefix("tabulated:")?.trim().parse().ok()?;
                (tol > 0.0 && tol.is_finite()).then_some(RecipeVariant::Tabulated(tol))
            }
        }
    }
}

/// The maps with derived and tabulated variants, and their parameters.
pub const WITH_VARIANTS: [&str; 7] = [
    "uniform-cone",
    "ggx",
    "beckmann",
    "von-mises-fisher",
    "hemisphere",
    "phong",
    "sphere",
];

/// `name` (one of [`WITH_VARIANTS`]) evaluated by `variant` (not
/// [`RecipeVariant::Closed`]) on the numbers `n` of its line.
pub fn eval_variant<T: Real>(
    name: &str,
    n: &[T],
    variant: RecipeVariant,
    inverse: bool,
) -> Result<String, String> {
    if !WITH_VARIANTS.contains(&name) {
        return Err(format!(
            "no derived variant for {name} (maps with derived and tabulated variants: {})",
            WITH_VARIANTS.join(", ")
        ));
    }
    let params = match name {
        "hemisphere" | "sphere" => 0,
        _ => 1,
    };
    expect(n, params, inverse, 3)?;
    let rest = &n[params..];
    match name {
        "uniform-cone" => {
            let c = &n[0];
            if !(*c >= -T::one() && *c < T::one()) {
                return Err("cos_theta_max must be in [-1, 1)".into());
            }
            run(Cap::new(c.acos()), rest, variant, inverse)
        }
        "ggx" => run(Ggx::new(n[0].clone()), rest, variant, inverse),
        "beckmann" => run(Beckmann::new(n[0].clone()), rest, variant, inverse),
        "von-mises-fisher" => run(VonMisesFisher::new(n[0].clone()), rest, variant, inverse),
        "phong" => run(Phong::new(n[0].clone()), rest, variant, inverse),
        "hemisphere" => run(Ok(Hemisphere::new()), rest, variant, inverse),
        "sphere" => run(Ok(Sphere::new()), rest, variant, inverse),
        _ => Err(format!("no derived variant for {name}")),
    }
}

/// The derived or tabulated warp of `def`, applied to the line's tail.
fn run<T: Real, D: WarpDefinition<T>>(
    def: Result<D, WarpError>,
    rest: &[T],
    variant: RecipeVariant,
    inverse: bool,
) -> Result<String, String> {
    let derived = DerivedWarp::new(def.map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    match variant {
        RecipeVariant::Tabulated(tol) => {
            let table = TabulatedWarp::new(&derived, tol).map_err(|e| e.to_string())?;
            apply(&table, rest, inverse)
        }
        _ => apply(&derived, rest, inverse),
    }
}
