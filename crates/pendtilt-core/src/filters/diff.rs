//! Smoothing differentiators.
