//! The checking harness.
