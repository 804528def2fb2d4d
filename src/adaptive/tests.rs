//! Tests of the adaptive sampler.
