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
        }
    }
}

impl std::error::Error for WarpError {}
