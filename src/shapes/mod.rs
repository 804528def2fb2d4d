//! The analytic warps.
