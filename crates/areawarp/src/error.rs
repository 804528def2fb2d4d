//! The crate's error type.

use core::fmt;

/// Why a warp could not be built, or an input could not be used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WarpError {
    /// An input number is NaN or infinite.
    NonFinite {
        /// Which input.
        what: &'static str,
    },
    /// The shape is degenerate (collinear or coincident vertices, zero area…).
    Degenerate {
        /// What is degenerate.
        what: &'static str,
    },
    /// The shape is valid, but a quantity its map needs (a solid angle, a
    /// density, a per-shape constant or a per-sample intermediate) is outside
    /// the range of the scalar type: e.g. a triangle of 1e-60 sr in `f32`.
    /// The same shape in a wider type is accepted.
    Unrepresentable {
        /// What does not fit.
        what: &'static str,
    },
    /// A parameter is outside its valid range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// A numerical construction (quadrature, tabulation) did not reach the
    /// accuracy it must certify.
    NotConverged {
        /// What did not converge.
        what: &'static str,
    },
    /// Two computations of the same quantity disagree (e.g. a closed form
    /// supplied by the user and the quadrature).
    Inconsistent {
        /// What disagrees.
        what: &'static str,
    },
}

impl fmt::Display for WarpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WarpError::NonFinite { what } => write!(f, "{what} is not finite"),
            WarpError::Degenerate { what } => write!(f, "degenerate shape: {what}"),
            WarpError::Unrepresentable { what } => {
                write!(f, "not representable in this scalar type: {what}")
            }
            WarpError::InvalidParameter { name, expected } => {
                write!(f, "invalid parameter {name}: expected {expected}")
            }
            WarpError::NotConverged { what } => write!(f, "did not converge: {what}"),
            WarpError::Inconsistent { what } => write!(f, "inconsistent: {what}"),
        }
    }
}

impl std::error::Error for WarpError {}
